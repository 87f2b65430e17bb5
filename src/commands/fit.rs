//! `softgrip fit`: scene parameters fitted to a recording, or one set of
//! them to several recordings at once, with each one's uncertainty and
//! sensitivity (`softgrip_lab::fit`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, WorkersArgs};
use super::figures::{describe, print_ringing, write_json, wrote};
use super::progress::simulations_bar;

/// Fit scene parameters to a recording: NRMSE minimised by a bounded
/// Nelder-Mead search after a space-filling design, with each
/// parameter's noise-implied uncertainty and +/-10 % sensitivity
/// (unidentifiable parameters are flagged). Several recordings share one
/// set of parameters, each simulated on its own scene (e.g. the same
/// beam with different tip masses); their mean NRMSE is minimised.
#[derive(clap::Args)]
pub struct Args {
    /// The recordings' .toml headers: one, or several fitted together.
    #[arg(required = true)]
    recordings: Vec<PathBuf>,
    /// Parameters to fit: name or name=LOW:HIGH (add :log or :lin),
    /// comma-separated or repeated, e.g. --params young_modulus,alpha
    /// --params tau_c=0.05:0.3. Default bounds: 1/10 to 10 times the
    /// scene's modulus, 1/100 to 100 times its alpha, 0.02 to 0.5 for
    /// tau_s and tau_c.
    #[arg(long, required = true, num_args = 1..)]
    params: Vec<String>,
    /// Simulations at most in the search.
    #[arg(long, default_value_t = 400)]
    max_evaluations: usize,
    #[command(flatten)]
    workers: WorkersArgs,
    /// Also write the figures as JSON (nrmse before and after, fitted params,
    /// ringing of a time series, ...; with several recordings, each one's).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the fitted scene here (TOML). With several recordings, a
    /// directory: one fitted scene per recording, NN-NAME.toml.
    #[arg(long)]
    scene_out: Option<PathBuf>,
    #[command(flatten)]
    report: ReportArgs,
}

pub fn run(args: Args) -> Result<()> {
    if args.recordings.len() > 1 {
        return run_many(args);
    }
    use softgrip_lab::fit;
    let Some(path) = args.recordings.first() else {
        anyhow::bail!("give a recording to fit");
    };
    let (path, params) = (path.as_path(), &args.params);
    let (max_evaluations, workers) = (args.max_evaluations, args.workers.workers);
    let (json, scene_out) = (args.json.as_deref(), args.scene_out.as_deref());
    let report = &args.report;
    let recording = Recording::load(path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--json", json)
        .file("--scene-out", scene_out)
        .dir("--report", report.dir("fit", path).as_deref())
        .check()?;
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
    let bar = simulations_bar((max_evaluations + 4 * params.len()) as u64);
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
    print_params(
        &result.params,
        &result.fitted,
        &result.uncertainty.standard_errors,
        &result.sensitivity,
        &result.at_bound,
    );
    print_ringing(
        &recording,
        &[
            ("at the start", &result.start_replay),
            ("fitted", &result.replay),
        ],
    );
    if let Some(out) = scene_out {
        let scene = fit::scene_with(&recording.scene, &result.params, &result.fitted)
            .map_err(anyhow::Error::msg)?;
        std::fs::write(out, scene.to_toml_for(out))
            .with_context(|| format!("writing {}", out.display()))?;
        println!("wrote the fitted scene to {}", out.display());
    }
    if let Some(dir) = report.dir("fit", path) {
        wrote(&softgrip_lab::report::fit(&dir, &recording, &result)?);
    }
    if let Some(json) = json {
        let value = softgrip_lab::json::fit(path, &recording, &result);
        write_json(json, &value)?;
    }
    Ok(())
}

/// The parameters by name as a JSON object (`null` where not finite).
/// One row per fitted parameter: value, standard error, the +/-10 % check and its verdict.
fn print_params(
    params: &[softgrip_lab::fit::FitParam],
    fitted: &[f64],
    standard_errors: &[f64],
    sensitivity: &[softgrip_lab::fit::Sensitivity],
    at_bound: &[bool],
) {
    for (i, p) in params.iter().enumerate() {
        let s = &sensitivity[i];
        let n = |x: Option<f64>| x.map_or("n/a".to_string(), |f| format!("{f:.5}"));
        println!(
            "  {:<20} {:<12.5e} {:<14.3e} {:<11} {:<11} {}{}",
            p.param.name,
            fitted[i],
            standard_errors[i],
            n(s.minus),
            n(s.plus),
            s.verdict.label(),
            if at_bound[i] { " (at a bound)" } else { "" }
        );
    }
}

/// One set of parameters fitted to several recordings at once.
fn run_many(args: Args) -> Result<()> {
    use softgrip_lab::fit;
    let paths = &args.recordings;
    let recordings: Vec<Recording> = paths
        .iter()
        .map(|p| Recording::load(p).with_context(|| format!("reading {}", p.display())))
        .collect::<Result<_>>()?;
    let mut outputs = super::outputs::Outputs::new()
        .file("--json", args.json.as_deref())
        .dir("--report", args.report.dir_many("fit", paths).as_deref());
    for r in &recordings {
        outputs = outputs.recording(r);
    }
    if args.scene_out.as_deref().is_some_and(|d| !d.is_file()) {
        outputs = outputs.dir("--scene-out", args.scene_out.as_deref());
    }
    outputs.check()?;
    for (path, recording) in paths.iter().zip(&recordings) {
        describe(path, recording);
    }
    if let Some(dir) = args.scene_out.as_deref().filter(|d| d.is_file()) {
        anyhow::bail!(
            "--scene-out {}: with several recordings this names a directory (one fitted scene per recording, NN-NAME.toml), and it is a file",
            dir.display()
        );
    }
    // Bounds from the first recording's scene; every scene must take them.
    let params =
        fit::parse_params(&args.params, &recordings[0].scene).map_err(anyhow::Error::msg)?;
    fit::check_params(&recordings, &params).map_err(anyhow::Error::msg)?;
    for p in &params {
        println!(
            "  fit {} in {:e} .. {:e}{}, shared by the {} recordings",
            p.param.name,
            p.lower,
            p.upper,
            if p.log { " (log scale)" } else { "" },
            recordings.len()
        );
    }
    let options = fit::FitOptions {
        max_evaluations: args.max_evaluations,
        workers: args.workers.workers,
        ..fit::FitOptions::default()
    };
    let bar = simulations_bar((args.max_evaluations + 4 * params.len()) as u64);
    let started = Instant::now();
    let result = fit::fit_many(&recordings, &params, options, &|n, best| {
        bar.set_position(n as u64);
        bar.set_message(format!("best mean NRMSE {best:.5}"));
    })?;
    bar.finish_and_clear();
    print_many(paths, &recordings, &result, started.elapsed().as_secs_f64());
    if let Some(dir) = args.scene_out.as_deref() {
        write_scenes(dir, &recordings, &result)?;
    }
    if let Some(dir) = args.report.dir_many("fit", paths) {
        wrote(&softgrip_lab::report::fit_many(&dir, &recordings, &result)?);
    }
    if let Some(json) = args.json.as_deref() {
        let paths: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
        let value = softgrip_lab::json::fit_many(&paths, &recordings, &result);
        write_json(json, &value)?;
    }
    Ok(())
}

/// What a fit of several recordings found, on the console.
fn print_many(
    paths: &[std::path::PathBuf],
    recordings: &[Recording],
    result: &softgrip_lab::fit::FitMany,
    seconds: f64,
) {
    println!(
        "{} points of {} simulations each in {:.0} s ({}); mean NRMSE {:.5} at the start, {:.5} fitted",
        result.trials.len(),
        recordings.len(),
        seconds,
        if result.converged {
            "converged"
        } else {
            "stopped at --max-evaluations, not converged"
        },
        result.before,
        result.after,
    );
    println!(
        "  recording                                  NRMSE start  NRMSE fitted  RMSE fitted (mm)"
    );
    for (path, part) in paths.iter().zip(&result.recordings) {
        println!(
            "  {:<42} {:<12.5} {:<13.5} {:.3}",
            path.display(),
            part.before.nrmse,
            part.after.nrmse,
            1e3 * part.after.rmse_m
        );
    }
    println!(
        "noise implied by the fitted residuals (all recordings): {:.4} mm per coordinate",
        1e3 * result.uncertainty.sigma_m
    );
    println!(
        "  parameter            fitted       +/- (1 s.e.)   NRMSE -10%  NRMSE +10%  verdict (NRMSE: the mean)"
    );
    print_params(
        &result.params,
        &result.fitted,
        &result.uncertainty.standard_errors,
        &result.sensitivity,
        &result.at_bound,
    );
    for ((path, recording), part) in paths.iter().zip(recordings).zip(&result.recordings) {
        let replays = [
            ("at the start", &part.start_replay),
            ("fitted", &part.replay),
        ];
        if softgrip_lab::ringing::dominant(recording).is_some() {
            print!("{}: ", path.display());
            print_ringing(recording, &replays);
        }
    }
}

/// One fitted scene per recording in `dir`, `NN-NAME.toml`.
fn write_scenes(
    dir: &std::path::Path,
    recordings: &[Recording],
    result: &softgrip_lab::fit::FitMany,
) -> Result<()> {
    use softgrip_lab::fit;
    let names: Vec<String> = recordings
        .iter()
        .enumerate()
        .map(|(i, r)| {
            format!(
                "{:02}-{}",
                i + 1,
                softgrip_lab::report::recording_name(&r.source)
            )
        })
        .collect();
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (recording, name) in recordings.iter().zip(&names) {
        let scene = fit::scene_with(&recording.scene, &result.params, &result.fitted)
            .map_err(anyhow::Error::msg)?;
        let out = dir.join(format!("{name}.toml"));
        std::fs::write(&out, scene.to_toml_for(&out))
            .with_context(|| format!("writing {}", out.display()))?;
    }
    println!(
        "wrote the fitted scenes to {} ({})",
        dir.display(),
        names
            .iter()
            .map(|n| format!("{n}.toml"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
