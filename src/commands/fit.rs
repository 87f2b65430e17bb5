//! `softgrip fit`: scene parameters fitted to a recording, with each one's
//! uncertainty and sensitivity (`softgrip_lab::fit`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, WorkersArgs};
use super::figures::{describe, errors_json, errors_json_for, write_json, wrote};
use super::progress::simulations_bar;

/// Fit scene parameters to a recording: NRMSE minimised by a bounded
/// Nelder-Mead search after a space-filling design, with each
/// parameter's noise-implied uncertainty and +/-10 % sensitivity
/// (unidentifiable parameters are flagged).
#[derive(clap::Args)]
pub struct Args {
    recording: PathBuf,
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
    /// Also write the figures as JSON (nrmse before and after, fitted params, ...).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the fitted scene here (TOML).
    #[arg(long)]
    scene_out: Option<PathBuf>,
    #[command(flatten)]
    report: ReportArgs,
}

pub fn run(args: Args) -> Result<()> {
    use softgrip_lab::fit;
    let (path, params) = (args.recording.as_path(), &args.params);
    let (max_evaluations, workers) = (args.max_evaluations, args.workers.workers);
    let (json, scene_out) = (args.json.as_deref(), args.scene_out.as_deref());
    let report = &args.report;
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
        let mut value = errors_json_for(path, &result.after);
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
