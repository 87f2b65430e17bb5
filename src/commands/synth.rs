//! `softgrip synth`: a recording made by softgrip's own simulation with
//! Gaussian noise, where the truth of a fit or a sweep is known.

use std::path::PathBuf;

use anyhow::Result;

use super::load::load_scene;

/// Make a recording from a scene (softgrip's own simulation, with
/// Gaussian noise): for testing fits and sweeps where the truth is known.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (.toml); omit for the built-in thesis scene.
    scene: Option<PathBuf>,
    /// Loads in N, one quasi-static sample each (along the first
    /// force-controlled finger's `force` direction); with --times, the load of each sample
    /// time, or one load held throughout.
    #[arg(long, value_delimiter = ',', required = true, value_parser = super::args::finite)]
    loads: Vec<f64>,
    /// A time series instead: sample times in s, rising (the first load stepped on at
    /// t = 0 from rest), e.g. a creep test held 30 s sampled at 2 Hz: --loads 9.73 --times
    /// 0.5,1,...,30.
    #[arg(long, value_delimiter = ',', value_parser = super::args::finite)]
    times: Vec<f64>,
    /// Object markers NAME=X,Y,Z on the undeformed surface (m);
    /// default for a cuboid: 9 on the top face and 5 along the front.
    #[arg(long = "marker")]
    markers: Vec<String>,
    /// Observed axes, e.g. xz for a side camera.
    #[arg(long, default_value = "xyz")]
    axes: String,
    /// Standard deviation of the noise on each coordinate (m).
    #[arg(long, default_value_t = 1e-4, value_parser = super::args::non_negative)]
    noise: f64,
    #[arg(long, value_parser = super::args::seed, default_value_t = 1)]
    seed: u64,
    /// Directory for scene.toml, recording.toml and samples.csv.
    #[arg(long)]
    out: PathBuf,
}

/// `softgrip synth`: the recording `args` describe, made by simulating the scene and adding
/// Gaussian noise, written to `--out`.
pub fn run(args: Args) -> Result<()> {
    use softgrip_lab::recording::Start;
    use softgrip_lab::synth::{Synthesis, synthesize};
    let scene = &load_scene(args.scene.as_deref())?;
    super::outputs::Outputs::new()
        .scene(scene)
        .dir("--out", Some(&args.out))
        .file("--out", Some(&args.out.join("scene.toml")))
        .file("--out", Some(&args.out.join("samples.csv")))
        .file("--out", Some(&args.out.join("recording.toml")))
        .check()?;
    let (loads, markers, axes) = (&args.loads, &args.markers, &args.axes);
    let (noise, seed, out) = (args.noise, args.seed, args.out.as_path());
    anyhow::ensure!(
        noise.is_finite() && noise >= 0.0,
        "--noise {noise}: must be a standard deviation in metres, 0 or more"
    );
    let observed = observed_axes(axes)?;
    let markers = marker_positions(scene, markers)?;
    let (mode, samples) = samples(loads, &args.times)?;
    let spec = Synthesis {
        mode,
        start: Start::Rest,
        samples,
        markers,
        finger: !scene.fingers.is_empty(),
        axes: observed,
        noise,
        seed,
        description: format!(
            "made by softgrip synth: loads {loads:?} N, axes {axes}, noise {noise} m, seed {seed}"
        ),
        distortion: None,
    };
    let rec = synthesize(scene, &spec, out)?;
    println!(
        "wrote {} ({} samples, {} markers)",
        rec.source.display(),
        rec.samples.len(),
        rec.markers.len()
    );
    Ok(())
}

/// `--axes` (letters x, y, z) as the observed flags of x, y and z; at least one.
fn observed_axes(axes: &str) -> Result<[bool; 3]> {
    let mut observed = [false; 3];
    for c in axes.chars() {
        match c {
            'x' => observed[0] = true,
            'y' => observed[1] = true,
            'z' => observed[2] = true,
            _ => anyhow::bail!("--axes {axes:?}: use the letters x, y and z, e.g. xz"),
        }
    }
    anyhow::ensure!(observed.iter().any(|a| *a), "--axes: at least one axis");
    Ok(observed)
}

/// The markers' names and undeformed positions (m): those of `--marker`, or without any a
/// cuboid's default set.
fn marker_positions(
    scene: &softgrip_core::Scene,
    markers: &[String],
) -> Result<Vec<(String, glam::DVec3)>> {
    use softgrip_core::scene::Shape;
    use softgrip_lab::synth::cuboid_markers;
    if markers.is_empty() {
        return match scene.object.shape {
            Shape::Cuboid { size } => Ok(cuboid_markers(size, 3, 0.1 * size.x.min(size.y), 5)),
            _ => anyhow::bail!(
                "the object is not a cuboid: give its markers with --marker NAME=X,Y,Z (m, on the undeformed surface)"
            ),
        };
    }
    markers.iter().map(|m| parse_marker(m)).collect()
}

/// One `--marker NAME=X,Y,Z` (m): its name (letters, digits, _ and -, not a finger's) and
/// position.
fn parse_marker(m: &str) -> Result<(String, glam::DVec3)> {
    let bad = || anyhow::anyhow!("--marker {m:?}: write NAME=X,Y,Z in metres");
    let (name, xyz) = m.split_once('=').ok_or_else(bad)?;
    let v: Vec<f64> = xyz
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    anyhow::ensure!(v.len() == 3 && v.iter().all(|x| x.is_finite()), bad());
    let name = name.trim();
    // The name is a key of the recording's [markers] table and a CSV cell.
    anyhow::ensure!(
        !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'),
        "--marker {m:?}: a marker name is letters, digits, _ and - (it is a key of the recording's [markers]), e.g. top_1=0,0,0.02"
    );
    anyhow::ensure!(
        softgrip_lab::recording::finger_marker(name).is_none(),
        "--marker {m:?}: {name} names a finger's centre, which the recording has already; choose another name"
    );
    Ok((name.to_string(), glam::DVec3::new(v[0], v[1], v[2])))
}

/// A recording's samples: each one's time (s; `None` quasi-static) and load (N).
type Samples = Vec<(Option<f64>, f64)>;

/// The recording's mode and samples (time, load in N): one quasi-static sample per load, or
/// with `--times` a time series, one load held or one per time.
fn samples(loads: &[f64], times: &[f64]) -> Result<(softgrip_lab::recording::Mode, Samples)> {
    use softgrip_lab::recording::Mode;
    if times.is_empty() {
        return Ok((
            Mode::QuasiStatic,
            loads.iter().map(|l| (None, *l)).collect::<Vec<_>>(),
        ));
    }
    anyhow::ensure!(
        times[0] > 0.0 && times.windows(2).all(|w| w[1] > w[0]),
        "--times {times:?}: sample times rise from above 0 s (the load is stepped on at 0)"
    );
    anyhow::ensure!(
        loads.len() == 1 || loads.len() == times.len(),
        "--times gives {} samples and --loads {} loads: give one load (held) or one per time",
        times.len(),
        loads.len()
    );
    let load = |i: usize| if loads.len() == 1 { loads[0] } else { loads[i] };
    Ok((
        Mode::TimeSeries,
        times
            .iter()
            .enumerate()
            .map(|(i, t)| (Some(*t), load(i)))
            .collect(),
    ))
}
