//! `softgrip sweep`: scene parameters over a grid against a recording, in
//! parallel; the NRMSE of each point and the best.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, WorkersArgs};
use super::figures::{errors_json_for, write_json, wrote};
use super::progress::progress_bar;

/// Sweep scene parameters over a grid against a recording (thesis Fig.
/// 19-23), in parallel, and report the NRMSE of each point and the best.
#[derive(clap::Args)]
pub struct Args {
    recording: PathBuf,
    /// name=start:end:count (add :log for log spacing) or name=v1,v2,...;
    /// once for a curve, twice for a grid. Names: young_modulus, alpha,
    /// tau_s, tau_c, damping_ratio, friction, ... (an unknown name lists
    /// them all).
    #[arg(long = "param", required = true)]
    params: Vec<String>,
    /// Write every point as CSV (the report has it too).
    #[arg(long)]
    csv: Option<PathBuf>,
    #[command(flatten)]
    workers: WorkersArgs,
    /// Also write the figures as JSON (best point's nrmse, rmse_m, params).
    #[arg(long)]
    json: Option<PathBuf>,
    #[command(flatten)]
    report: ReportArgs,
}

pub fn run(args: Args) -> Result<()> {
    use softgrip_lab::sweep;
    let (path, params) = (args.recording.as_path(), &args.params);
    let (csv, workers) = (args.csv.as_deref(), args.workers.workers);
    let (json, report) = (args.json.as_deref(), &args.report);
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
                p.result
                    .as_ref()
                    .err()
                    .map_or(String::new(), ToString::to_string)
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
        let mut value = errors_json_for(path, e);
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
