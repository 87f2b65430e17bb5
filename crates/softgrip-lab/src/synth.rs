//! Recordings made by softgrip itself: a scene simulated as a recording
//! would be, its markers sampled, Gaussian noise added, and the result
//! written in the spec's recording format. Fitting a synthetic recording
//! back to the parameters it was made with is how the fitting and the
//! diagnosis are tested (the truth is known).
//!
//! The noise comes from a seeded generator (SplitMix64 and Box-Muller):
//! the same seed gives the same files.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::recording::{Mode, Recording, RecordingError, Start};
use crate::replay::{ReplayOptions, replay};
use softgrip_core::error::SimError;
use softgrip_core::scene::Scene;

/// What to record and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Synthesis {
    /// How the samples are taken.
    pub mode: Mode,
    /// Time-series only.
    pub start: Start,
    /// One per sample: the time (time-series; `None` in quasi-static
    /// mode) and the load (N).
    pub samples: Vec<(Option<f64>, f64)>,
    /// Object markers: names and reference positions on the undeformed
    /// surface (m).
    pub markers: Vec<(String, DVec3)>,
    /// Also record the first finger's centre (the reserved `finger`).
    pub finger: bool,
    /// The observed axes (x, y, z); the others are left empty.
    pub axes: [bool; 3],
    /// Standard deviation of the Gaussian noise on each observed
    /// coordinate (m).
    pub noise: f64,
    /// Seed of the noise.
    pub seed: u64,
    /// The recording's `description`.
    pub description: String,
    /// Physics softgrip has no model of, laid on the simulated positions before the noise (the
    /// proof's out-of-catalogue cases); `None`: the simulation as it is.
    pub distortion: Option<Distortion>,
}

/// A mismatch no model of softgrip's makes, laid on a quasi-static recording's positions.
/// "Unloading" is every sample after the one at the largest load.
#[derive(Debug, Clone, PartialEq)]
pub enum Distortion {
    /// A permanent set: on unloading, every marker (the finger too) keeps `share` of the way
    /// it moved from where it is to where it was at the largest load.
    PermanentSet {
        /// Share of the way kept, 0 to 1.
        share: f64,
    },
    /// Adhesion: on unloading, the finger and the markers within `reach` (m, horizontally) of
    /// it keep `share` of that way: the surface sticks to the finger.
    Adhesion {
        /// Share of the way kept, 0 to 1.
        share: f64,
        /// Horizontal distance from the finger within which markers stick, m.
        reach: f64,
    },
    /// A marker slipping on the skin: marker `marker` moves by `rate` m per N of load along x.
    MarkerSlip {
        /// The marker's name.
        marker: String,
        /// Its slide along x per newton of load, m/N.
        rate: f64,
    },
}

impl Distortion {
    /// The positions `simulated` (one per residual of `placeholder`'s samples, `loads` by
    /// sample) with the distortion laid on.
    fn apply(
        &self,
        placeholder: &Recording,
        residuals: &[crate::compare::Residual],
        loads: &[f64],
    ) -> Vec<DVec3> {
        let peak = (0..loads.len())
            .max_by(|&a, &b| loads[a].total_cmp(&loads[b]))
            .unwrap_or(0);
        let at_peak = |r: &crate::compare::Residual| {
            residuals
                .iter()
                .find(|q| q.sample == peak && q.marker == r.marker)
                .map_or(r.simulated, |q| q.simulated)
        };
        let finger_at_peak = residuals
            .iter()
            .find(|q| q.sample == peak && placeholder.marker_name(q.marker) == "finger")
            .map(|q| q.simulated);
        residuals
            .iter()
            .map(|r| {
                let unloading = r.sample > peak;
                let name = placeholder.marker_name(r.marker);
                let keep = |share: f64| r.simulated + share * (at_peak(r) - r.simulated);
                match self {
                    Distortion::PermanentSet { share } if unloading => keep(*share),
                    Distortion::Adhesion { share, reach } if unloading => {
                        let near = name == "finger"
                            || finger_at_peak.is_some_and(|f| {
                                let d = at_peak(r) - f;
                                (d.x * d.x + d.y * d.y).sqrt() <= *reach
                            });
                        if near { keep(*share) } else { r.simulated }
                    }
                    Distortion::MarkerSlip { marker, rate } if *marker == name => {
                        r.simulated + DVec3::X * rate * loads[r.sample]
                    }
                    _ => r.simulated,
                }
            })
            .collect()
    }
}

/// Why a synthetic recording could not be made.
#[derive(Debug, thiserror::Error)]
pub enum SynthError {
    /// A file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why not.
        source: std::io::Error,
    },
    /// The recording written cannot be read back.
    #[error("the synthetic recording: {0}")]
    Recording(#[from] RecordingError),
    /// The simulation failed.
    #[error("simulating the synthetic recording: {0}")]
    Sim(#[from] SimError),
}

/// A seeded source of standard normal numbers (SplitMix64, Box-Muller).
#[derive(Debug, Clone)]
pub struct Gaussian {
    state: u64,
    spare: Option<f64>,
}

impl Gaussian {
    /// A source seeded with `seed`: the same seed, the same numbers.
    pub fn new(seed: u64) -> Gaussian {
        Gaussian {
            state: seed,
            spare: None,
        }
    }

    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // 53 random bits in (0, 1].
        ((z >> 11) as f64 + 1.0) / (1u64 << 53) as f64
    }

    /// The next standard normal number.
    pub fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        let a = std::f64::consts::TAU * v;
        self.spare = Some(r * a.sin());
        r * a.cos()
    }
}

fn write(path: &Path, text: &str) -> Result<(), SynthError> {
    std::fs::write(path, text).map_err(|source| SynthError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Simulates `spec` on `scene` and writes `scene.toml`, `recording.toml`
/// and `samples.csv` into `dir` (created if needed); returns the
/// recording as read back.
pub fn synthesize(scene: &Scene, spec: &Synthesis, dir: &Path) -> Result<Recording, SynthError> {
    let placeholder = prepare(scene, spec, dir)?;
    let run = replay(&placeholder, scene, truth_options(), |_| {})?;
    write_samples(&placeholder, spec, &run.residuals, dir)
}

/// As [`synthesize`] into `dir`, and the same samples without noise into `clean_dir`, from one
/// simulation: (the recording, its noise-free twin).
pub fn synthesize_with_clean(
    scene: &Scene,
    spec: &Synthesis,
    dir: &Path,
    clean_dir: &Path,
) -> Result<(Recording, Recording), SynthError> {
    let clean_spec = Synthesis {
        noise: 0.0,
        ..spec.clone()
    };
    let placeholder = prepare(scene, spec, dir)?;
    prepare(scene, &clean_spec, clean_dir)?;
    let run = replay(&placeholder, scene, truth_options(), |_| {})?;
    Ok((
        write_samples(&placeholder, spec, &run.residuals, dir)?,
        write_samples(&placeholder, &clean_spec, &run.residuals, clean_dir)?,
    ))
}

fn row_start(time: Option<f64>, load: f64) -> String {
    match time {
        Some(t) => format!("{t:?},{load:?}"),
        None => format!(",{load:?}"),
    }
}

/// Writes the scene, the recording's header and placeholder samples into `dir`, and reads the
/// recording back for replaying.
fn prepare(scene: &Scene, spec: &Synthesis, dir: &Path) -> Result<Recording, SynthError> {
    std::fs::create_dir_all(dir).map_err(|source| SynthError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let file = dir.join("scene.toml");
    write(&file, &scene.to_toml_for(&file))?;
    let mut header = String::from("# Made by softgrip (synth): simulated, with Gaussian noise.\n");
    let _ = writeln!(
        header,
        "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = {:?}",
        match spec.mode {
            Mode::QuasiStatic => "quasi-static",
            Mode::TimeSeries => "time-series",
        }
    );
    if spec.mode == Mode::TimeSeries {
        let start = match spec.start {
            Start::Rest => "rest",
            Start::Equilibrium => "equilibrium",
        };
        let _ = writeln!(header, "start = {start:?}");
    }
    let _ = writeln!(header, "description = {:?}\n\n[markers]", spec.description);
    for (name, p) in &spec.markers {
        let _ = writeln!(header, "{name} = [{:?}, {:?}, {:?}]", p.x, p.y, p.z);
    }
    let _ = writeln!(
        header,
        "\n[extra]\nnoise_m = {:?}\nseed = {}",
        spec.noise, spec.seed
    );
    write(&dir.join("recording.toml"), &header)?;
    let names: Vec<&str> = spec
        .markers
        .iter()
        .map(|(n, _)| n.as_str())
        .chain(spec.finger.then_some("finger"))
        .collect();
    // Placeholder positions, so that the recording reads and replays.
    let mut rows = String::from("time,load,marker,x,y,z\n");
    for &(time, load) in &spec.samples {
        for name in &names {
            let _ = writeln!(rows, "{},{name},0,0,0", row_start(time, load));
        }
    }
    write(&dir.join("samples.csv"), &rows)?;
    Ok(Recording::load(&dir.join("recording.toml"))?)
}

/// Writes the simulated positions `residuals` of `placeholder`'s samples, with `spec`'s noise,
/// as `dir`'s samples, and reads the recording back.
fn write_samples(
    placeholder: &Recording,
    spec: &Synthesis,
    residuals: &[crate::compare::Residual],
    dir: &Path,
) -> Result<Recording, SynthError> {
    let mut noise = Gaussian::new(spec.seed);
    let loads: Vec<f64> = spec.samples.iter().map(|s| s.1).collect();
    let positions: Vec<DVec3> = match &spec.distortion {
        Some(d) => d.apply(placeholder, residuals, &loads),
        None => residuals.iter().map(|r| r.simulated).collect(),
    };
    let mut rows = String::from("time,load,marker,x,y,z\n");
    for (r, p) in residuals.iter().zip(&positions) {
        let (time, load) = spec.samples[r.sample];
        let name = placeholder.marker_name(r.marker);
        let _ = write!(rows, "{},{name}", row_start(time, load));
        for a in 0..3 {
            if spec.axes[a] {
                let _ = write!(rows, ",{:?}", p[a] + spec.noise * noise.sample());
            } else {
                rows.push(',');
            }
        }
        rows.push('\n');
    }
    write(&dir.join("samples.csv"), &rows)?;
    Ok(Recording::load(&dir.join("recording.toml"))?)
}

/// `n` x `m` marker positions spread over the top face (z = height) of a
/// cuboid scene's object, inset by `inset` (m) from its edges, named
/// `t0_0`, `t0_1`, ...; and `k` along the front face's (y = -w/2)
/// mid-height line, named `f0`, `f1`, ...
pub fn cuboid_markers(size: DVec3, n: usize, inset: f64, k: usize) -> Vec<(String, DVec3)> {
    let mut out = Vec::new();
    let along = |count: usize, half: f64, i: usize| {
        if count <= 1 {
            0.0
        } else {
            -half + inset + (2.0 * (half - inset)) * i as f64 / (count - 1) as f64
        }
    };
    for i in 0..n {
        for j in 0..n {
            let p = DVec3::new(along(n, size.x / 2.0, i), along(n, size.y / 2.0, j), size.z);
            out.push((format!("t{i}_{j}"), p));
        }
    }
    for i in 0..k {
        let p = DVec3::new(along(k, size.x / 2.0, i), -size.y / 2.0, size.z / 2.0);
        out.push((format!("f{i}"), p));
    }
    out
}

/// A truth is simulated as its scene says: a time series at the scene's `dt` throughout, not by
/// the error-controlled steps replays take.
fn truth_options() -> ReplayOptions {
    ReplayOptions {
        adaptive: None,
        ..ReplayOptions::default()
    }
}
