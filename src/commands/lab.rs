//! The lab-recording commands: compare, sweep, fit and modulus. Each
//! prints its figures, writes a report (Markdown and PNG plots) unless
//! told not to, and with `--json` writes its figures as JSON.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use softgrip_lab::compare::Errors;
use softgrip_lab::recording::Recording;
use softgrip_lab::report::Written;

use super::progress_bar;

#[derive(clap::Args, Debug, Clone)]
pub struct ReportArgs {
    /// Write the report (Markdown and PNG plots) in this directory
    /// [default: report-COMMAND-RECORDING in the current directory].
    #[arg(long, value_parser = report_dir)]
    report: Option<PathBuf>,
    /// Write no report.
    #[arg(long, conflicts_with = "report")]
    no_report: bool,
}

/// `--report` names a directory: a file name (`report.md`) is refused at
/// once, before the work, rather than made into a directory after it.
fn report_dir(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    let ext = p
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some(e @ ("md" | "html" | "txt" | "png" | "svg" | "json" | "csv" | "pdf")) => Err(format!(
            "--report takes a directory (the report is written there as Markdown with its PNG plots), not a .{e} file: try --report {}",
            p.with_extension("").display()
        )),
        _ => Ok(p),
    }
}

impl ReportArgs {
    pub(crate) fn dir(&self, command: &str, recording: &Path) -> Option<PathBuf> {
        if self.no_report {
            return None;
        }
        if let Some(d) = &self.report {
            return Some(d.clone());
        }
        // `.../gravity_a/recording.toml` is named by its directory.
        let stem = recording
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name = if stem == "recording" || stem.is_empty() {
            recording
                .canonicalize()
                .ok()
                .and_then(|p| {
                    p.parent()?
                        .file_name()
                        .map(|n| n.to_string_lossy().into_owned())
                })
                .unwrap_or(stem)
        } else {
            stem
        };
        Some(PathBuf::from(format!("report-{command}-{name}")))
    }
}

fn wrote(w: &Written) {
    println!(
        "report: {} ({} plots)",
        w.markdown.display(),
        w.images.len()
    );
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<()> {
    std::fs::write(path, serde_json::to_string_pretty(value)?)
        .with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn errors_json(e: &Errors) -> serde_json::Value {
    serde_json::json!({
        "nrmse": e.nrmse,
        "rmse_m": e.rmse_m,
        "nrmse_all": e.nrmse_all,
        "rmse_all_m": e.rmse_all_m,
        "observations": e.count,
    })
}

fn describe(path: &Path, recording: &Recording) {
    println!(
        "{}: {} ({:?}), {} samples, {} object markers",
        path.display(),
        if recording.description.is_empty() {
            "no description"
        } else {
            &recording.description
        },
        recording.mode,
        recording.samples.len(),
        recording.markers.len()
    );
}

pub fn compare(
    path: &Path,
    json: Option<&Path>,
    discretisation: bool,
    report: &ReportArgs,
) -> Result<()> {
    let recording = Recording::load(path)?;
    describe(path, &recording);
    let bar = progress_bar(recording.samples.len() as u64, "samples");
    let run = softgrip_lab::replay::replay(
        &recording,
        &recording.scene,
        softgrip_lab::replay::ReplayOptions::default(),
        |n| bar.set_position(n as u64),
    )?;
    bar.finish_and_clear();
    for (m, a) in recording.markers.iter().zip(&run.attachments) {
        println!(
            "  marker {}: reference {:.2} mm from the surface",
            m.name,
            1e3 * a.distance
        );
    }
    let e = run.errors;
    println!(
        "NRMSE {:.4} (RMSE {:.3} mm over {} observations{}); with fingers NRMSE {:.4} (RMSE {:.3} mm)",
        e.nrmse,
        1e3 * e.rmse_m,
        e.count,
        if recording.markers.is_empty() {
            ", finger markers: the recording has no object markers"
        } else {
            ", object markers"
        },
        e.nrmse_all,
        1e3 * e.rmse_all_m
    );
    println!("  marker      rmse x (mm)  rmse y (mm)  rmse z (mm)  rmse (mm)");
    for m in softgrip_lab::compare::per_marker(&run.residuals) {
        let axis = |a: usize| m.axes[a].map_or("-".to_string(), |e| format!("{:.3}", 1e3 * e));
        println!(
            "  {:<10}  {:>11}  {:>11}  {:>11}  {:>9.3}",
            recording.marker_name(m.marker),
            axis(0),
            axis(1),
            axis(2),
            1e3 * m.distance
        );
    }
    if let Some(v) = run.volume_errors.last() {
        println!("volume error at the last sample: {v:.3e}");
    }
    let discretisation = discretisation.then(|| {
        let noise = softgrip_lab::diagnose::estimate_noise(&run.residuals);
        println!("noise (estimated from the residual): {}", noise.describe());
        let spinner = progress_bar(1, "the scene refined");
        let d = softgrip_lab::discretisation::check(
            &recording,
            &recording.scene,
            &run,
            &noise,
            softgrip_lab::replay::ReplayOptions::default().rest,
        );
        spinner.finish_and_clear();
        println!("discretisation: {}", d.describe());
        d
    });
    if let Some(dir) = report.dir("compare", path) {
        wrote(&softgrip_lab::report::compare(&dir, &recording, &run)?);
    }
    if let Some(json) = json {
        let o = &recording.scene.object;
        let m = &recording.scene.model;
        let mut value = errors_json(&e);
        value["recording"] = path.display().to_string().into();
        value["params"] = serde_json::json!({
            "young_modulus": o.young_modulus,
            "alpha": m.alpha,
            "tau_s": m.tau_s,
            "tau_c": m.tau_c,
        });
        if let Some(d) = &discretisation {
            value["discretisation"] = d.to_json();
        }
        write_json(json, &value)?;
    }
    Ok(())
}

pub fn sweep(
    path: &Path,
    params: &[String],
    csv: Option<&Path>,
    workers: usize,
    json: Option<&Path>,
    report: &ReportArgs,
) -> Result<()> {
    use softgrip_lab::sweep;
    anyhow::ensure!(
        params.len() <= 2,
        "{} --param given: a sweep is a curve (one) or a grid (two)",
        params.len()
    );
    let axes = params
        .iter()
        .map(|p| softgrip_lab::params::parse_axis(p).map_err(anyhow::Error::msg))
        .collect::<Result<Vec<_>>>()?;
    let recording = Recording::load(path)?;
    let total = sweep::grid(&axes).len();
    println!(
        "{}: {} points of {}",
        path.display(),
        total,
        axes.iter()
            .map(|a| format!("{} ({} values)", a.param.name, a.values.len()))
            .collect::<Vec<_>>()
            .join(" x ")
    );
    let bar = progress_bar(total as u64, "grid points");
    let started = Instant::now();
    let points = sweep::sweep(&recording, &axes, workers, &|n| bar.set_position(n as u64));
    let seconds = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    println!("{total} points in {seconds:.1} s");
    let failed = points.iter().filter(|p| p.result.is_err()).count();
    if failed > 0 {
        println!("{failed} of {total} points did not run (see the CSV's error column), e.g.:");
        if let Some(p) = points.iter().find(|p| p.result.is_err()) {
            println!(
                "  {:?}: {}",
                p.values,
                p.result.as_ref().err().map_or("", String::as_str)
            );
        }
    }
    let best = sweep::best(&points).ok_or_else(|| anyhow::anyhow!("no point of the sweep ran"))?;
    let e = best.result.as_ref().map_err(|e| anyhow::anyhow!("{e}"))?;
    let at = axes
        .iter()
        .zip(&best.values)
        .map(|(a, v)| format!("{} = {v:.6}", a.param.name))
        .collect::<Vec<_>>()
        .join(", ");
    println!(
        "best: {at}: NRMSE {:.5} (RMSE {:.3} mm)",
        e.nrmse,
        1e3 * e.rmse_m
    );
    if let Some(csv) = csv {
        std::fs::write(csv, sweep::to_csv(&axes, &points))
            .with_context(|| format!("writing {}", csv.display()))?;
        println!("wrote {}", csv.display());
    }
    if let Some(dir) = report.dir("sweep", path) {
        wrote(&softgrip_lab::report::sweep(
            &dir, &recording, &axes, &points, seconds,
        )?);
    }
    if let Some(json) = json {
        let mut value = errors_json(e);
        value["recording"] = path.display().to_string().into();
        value["params"] = axes
            .iter()
            .zip(&best.values)
            .map(|(a, v)| (a.param.name.to_string(), serde_json::Value::from(*v)))
            .collect::<serde_json::Map<_, _>>()
            .into();
        value["points"] = total.into();
        value["failed"] = failed.into();
        value["seconds"] = seconds.into();
        write_json(json, &value)?;
    }
    Ok(())
}

pub fn fit(
    path: &Path,
    params: &[String],
    max_evaluations: usize,
    workers: usize,
    json: Option<&Path>,
    scene_out: Option<&Path>,
    report: &ReportArgs,
) -> Result<()> {
    use softgrip_lab::fit;
    let recording = Recording::load(path)?;
    let params = fit::parse_params(params, &recording.scene).map_err(anyhow::Error::msg)?;
    describe(path, &recording);
    for p in &params {
        println!(
            "  fit {} in {:e} .. {:e}{}",
            p.param.name,
            p.lower,
            p.upper,
            if p.log { " (log scale)" } else { "" }
        );
    }
    let options = fit::FitOptions {
        max_evaluations,
        workers,
        ..fit::FitOptions::default()
    };
    let bar = ProgressBar::new((max_evaluations + 4 * params.len()) as u64);
    if let Ok(style) = ProgressStyle::with_template(
        "{bar:40} {pos} simulations (at most {len})  {msg}  [{elapsed}]",
    ) {
        bar.set_style(style);
    }
    let started = Instant::now();
    let result = fit::fit(&recording, &params, options, &|n, best| {
        bar.set_position(n as u64);
        bar.set_message(format!("best NRMSE {best:.5}"));
    })?;
    bar.finish_and_clear();
    println!(
        "{} simulations in {:.0} s ({}); NRMSE {:.5} at the start, {:.5} fitted (RMSE {:.3} mm)",
        result.trials.len(),
        started.elapsed().as_secs_f64(),
        if result.converged {
            "converged"
        } else {
            "stopped at --max-evaluations, not converged"
        },
        result.before.nrmse,
        result.after.nrmse,
        1e3 * result.after.rmse_m
    );
    println!(
        "noise implied by the fitted residuals: {:.4} mm per coordinate",
        1e3 * result.uncertainty.sigma_m
    );
    println!("  parameter            fitted       +/- (1 s.e.)   NRMSE -10%  NRMSE +10%  verdict");
    for (i, p) in result.params.iter().enumerate() {
        let s = &result.sensitivity[i];
        let n = |x: Option<f64>| x.map_or("n/a".to_string(), |f| format!("{f:.5}"));
        println!(
            "  {:<20} {:<12.5e} {:<14.3e} {:<11} {:<11} {}{}",
            p.param.name,
            result.fitted[i],
            result.uncertainty.standard_errors[i],
            n(s.minus),
            n(s.plus),
            s.verdict.label(),
            if result.at_bound[i] {
                " (at a bound)"
            } else {
                ""
            }
        );
    }
    if let Some(out) = scene_out {
        let scene = fit::scene_with(&recording.scene, &result.params, &result.fitted)
            .map_err(anyhow::Error::msg)?;
        std::fs::write(out, scene.to_toml())
            .with_context(|| format!("writing {}", out.display()))?;
        println!("wrote the fitted scene to {}", out.display());
    }
    if let Some(dir) = report.dir("fit", path) {
        wrote(&softgrip_lab::report::fit(&dir, &recording, &result)?);
    }
    if let Some(json) = json {
        let by_name = |values: &[f64]| -> serde_json::Value {
            result
                .params
                .iter()
                .zip(values)
                .map(|(p, v)| {
                    let v = if v.is_finite() {
                        serde_json::Value::from(*v)
                    } else {
                        serde_json::Value::Null
                    };
                    (p.param.name.to_string(), v)
                })
                .collect::<serde_json::Map<_, _>>()
                .into()
        };
        let mut value = errors_json(&result.after);
        value["recording"] = path.display().to_string().into();
        value["params"] = by_name(&result.fitted);
        value["start"] = by_name(&result.start);
        value["standard_errors"] = by_name(&result.uncertainty.standard_errors);
        value["identifiability"] = result
            .params
            .iter()
            .zip(&result.sensitivity)
            .map(|(p, s)| (p.param.name.to_string(), s.verdict.label().into()))
            .collect::<serde_json::Map<_, _>>()
            .into();
        value["before"] = errors_json(&result.before);
        value["noise_m"] = result.uncertainty.sigma_m.into();
        value["simulations"] = result.trials.len().into();
        value["converged"] = result.converged.into();
        write_json(json, &value)?;
    }
    Ok(())
}

pub fn modulus(path: &Path, json: Option<&Path>, report: &ReportArgs) -> Result<()> {
    let recording = softgrip_lab::recording::Recording::load(path)?;
    let fit = softgrip_lab::modulus::from_recording(&recording)?;
    println!(
        "{}: {} levels; area {:.4e} m^2, initial length {:.4} m",
        path.display(),
        fit.curve.len() - 1,
        fit.area,
        fit.length
    );
    println!(
        "Young's modulus E = {:.1} kPa: the slope of a line through strain {:.4} .. {:.4} ({} points with the unloaded state, R^2 = {:.5}, intercept {:.3} kPa)",
        fit.young_modulus / 1e3,
        fit.strain_range.0,
        fit.strain_range.1,
        fit.points,
        fit.r_squared,
        fit.intercept / 1e3
    );
    println!(
        "over the candidate ranges (2 points up to these) E runs {:.1} .. {:.1} kPa; the scene says {:.1} kPa",
        fit.e_range.0 / 1e3,
        fit.e_range.1 / 1e3,
        recording.scene.object.young_modulus / 1e3
    );
    if let Some(dir) = report.dir("modulus", path) {
        wrote(&softgrip_lab::report::modulus(&dir, &recording, &fit)?);
    }
    if let Some(json) = json {
        let value = serde_json::json!({
            "recording": path.display().to_string(),
            "young_modulus": fit.young_modulus,
            "young_modulus_range": [fit.e_range.0, fit.e_range.1],
            "r_squared": fit.r_squared,
            "strain_range": [fit.strain_range.0, fit.strain_range.1],
            "points": fit.points,
            "intercept_pa": fit.intercept,
        });
        std::fs::write(json, serde_json::to_string_pretty(&value)?)
            .with_context(|| format!("writing {}", json.display()))?;
        println!("wrote {}", json.display());
    }
    Ok(())
}

pub fn synth(
    scene: &softgrip_core::Scene,
    loads: &[f64],
    markers: &[String],
    axes: &str,
    noise: f64,
    seed: u64,
    out: &Path,
) -> Result<()> {
    use softgrip_core::scene::Shape;
    use softgrip_lab::recording::{Mode, Start};
    use softgrip_lab::synth::{Synthesis, cuboid_markers, synthesize};
    anyhow::ensure!(
        noise.is_finite() && noise >= 0.0,
        "--noise {noise}: must be a standard deviation in metres, 0 or more"
    );
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
    let markers = if markers.is_empty() {
        match scene.object.shape {
            Shape::Cuboid { size } => cuboid_markers(size, 3, 0.1 * size.x.min(size.y), 5),
            _ => anyhow::bail!(
                "the object is not a cuboid: give its markers with --marker NAME=X,Y,Z (m, on the undeformed surface)"
            ),
        }
    } else {
        markers
            .iter()
            .map(|m| {
                let bad = || anyhow::anyhow!("--marker {m:?}: write NAME=X,Y,Z in metres");
                let (name, xyz) = m.split_once('=').ok_or_else(bad)?;
                let v: Vec<f64> = xyz
                    .split(',')
                    .map(|t| t.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| bad())?;
                anyhow::ensure!(v.len() == 3 && v.iter().all(|x| x.is_finite()), bad());
                Ok((name.trim().to_string(), glam::DVec3::new(v[0], v[1], v[2])))
            })
            .collect::<Result<Vec<_>>>()?
    };
    let spec = Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: loads.iter().map(|l| (None, *l)).collect(),
        markers,
        finger: !scene.fingers.is_empty(),
        axes: observed,
        noise,
        seed,
        description: format!(
            "made by softgrip synth: loads {loads:?} N, axes {axes}, noise {noise} m, seed {seed}"
        ),
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
