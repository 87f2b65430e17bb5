//! `softgrip compare`: replay a lab recording and measure the error as the
//! thesis does, with `--discretisation` how much of it the mesh and the
//! step could make.

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, SettleArgs, SettleMode};
use super::figures::{describe, print_ringing, write_json, wrote};
use super::progress::progress_bar;

/// Simulate a lab recording and measure the error as the thesis does
/// (NRMSE, eq. 45-46): per marker, per axis, overall; for a time series
/// also how the object rings (frequency, decay rate, damping ratio of
/// the most-moving marker axis), recorded and simulated.
#[derive(clap::Args)]
pub struct Args {
    /// The recording's .toml header.
    recording: PathBuf,
    /// Also write the figures as JSON (nrmse, rmse_m, nrmse_all, params;
    /// ringing for a time series).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Also replay on a mesh 0.8 times as fine and, for a time series,
    /// at half the step, and say how far the markers move against the
    /// noise (estimated from the residual, as `diagnose` does): how
    /// much of the error the model's own discretisation can make.
    #[arg(long)]
    discretisation: bool,
    #[command(flatten)]
    settle: SettleArgs,
    /// With --settle dynamic: simulated seconds each load may take to come to rest.
    #[arg(long, default_value_t = 20.0, value_parser = super::args::positive)]
    max_seconds: f64,
    #[command(flatten)]
    report: ReportArgs,
}

pub fn run(args: Args) -> Result<()> {
    let (path, json) = (args.recording.as_path(), args.json.as_deref());
    let (discretisation, report) = (args.discretisation, &args.report);
    let recording = Recording::load(path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--json", json)
        .dir("--report", report.dir("compare", path).as_deref())
        .check()?;
    describe(path, &recording);
    let bar = progress_bar(recording.samples.len() as u64, "samples");
    let run = softgrip_lab::replay::replay(
        &recording,
        &recording.scene,
        softgrip_lab::replay::ReplayOptions {
            settle: args.settle.settle.map(SettleMode::replay),
            rest: softgrip_core::quasi_static::RestTolerance {
                max_seconds: args.max_seconds,
                ..Default::default()
            },
            ..Default::default()
        },
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
    print_ringing(&recording, &[("simulated", &run)]);
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
        let value = softgrip_lab::json::compare(path, &recording, &run, discretisation.as_ref());
        write_json(json, &value)?;
    }
    Ok(())
}
