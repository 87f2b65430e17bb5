//! `softgrip sweep`: scene parameters over a grid against a recording, in
//! parallel; the NRMSE of each point and the best.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, WorkersArgs};
use super::figures::{write_json, wrote};
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
    /// Run only shard I of N (0 <= I < N: every N-th grid point from the I-th) and write its
    /// points to --part; `softgrip merge` of every shard's file gives this sweep's CSV and JSON.
    /// On Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT.
    #[arg(long, requires = "part", conflicts_with_all = ["csv", "json"])]
    shard: Option<String>,
    /// The shard's file (JSON), with --shard.
    #[arg(long, requires = "shard")]
    part: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<()> {
    use softgrip_lab::sweep;
    if let (Some(shard), Some(part)) = (&args.shard, &args.part) {
        return run_shard(&args, shard, part);
    }
    let (path, params) = (args.recording.as_path(), &args.params);
    let (csv, workers) = (args.csv.as_deref(), args.workers.workers);
    let (json, report) = (args.json.as_deref(), &args.report);
    let axes = softgrip_lab::shard::parse_axes(params)?;
    let recording = Recording::load(path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--csv", csv)
        .file("--json", json)
        .dir("--report", report.dir("sweep", path).as_deref())
        .check()?;
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
        .map(|(a, v)| format!("{} = {}", a.param.name, super::args::number(*v)))
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
        let value = softgrip_lab::json::sweep(path, &axes, &points)
            .ok_or_else(|| anyhow::anyhow!("no point of the sweep ran"))?;
        write_json(json, &value)?;
    }
    Ok(())
}

/// One shard of the sweep, written to its file.
fn run_shard(args: &Args, shard: &str, part: &std::path::Path) -> Result<()> {
    use softgrip_lab::shard;
    let shard = shard::Shard::parse(shard)?;
    let path = args.recording.as_path();
    let axes = shard::parse_axes(&args.params)?;
    let recording = Recording::load(path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--part", Some(part))
        .check()?;
    let total = softgrip_lab::sweep::grid(&axes).len();
    let mine = shard.indices(total).len();
    println!(
        "{}: shard {} of {}: {mine} of {total} points",
        path.display(),
        shard.index,
        shard.count
    );
    let bar = progress_bar(mine as u64, "grid points");
    let value = shard::run_part(
        path,
        &recording,
        &args.params,
        shard,
        args.workers.workers,
        &|n| bar.set_position(n as u64),
    )?;
    bar.finish_and_clear();
    write_json(part, &value)
}
