//! `softgrip modulus`: Young's modulus from a compression recording's
//! stress-strain curve (`softgrip_lab::modulus`).

use std::path::PathBuf;

use anyhow::Result;

use super::args::ReportArgs;
use super::figures::{write_json, wrote};

/// Young's modulus from a compression recording (thesis eq. 49-50): a
/// line through the initial linear part of the stress-strain curve.
#[derive(clap::Args)]
pub struct Args {
    recording: PathBuf,
    /// Also write the figures as JSON (young_modulus in Pa, ...).
    #[arg(long)]
    json: Option<PathBuf>,
    #[command(flatten)]
    report: ReportArgs,
}

pub fn run(args: Args) -> Result<()> {
    let (path, json, report) = (args.recording.as_path(), args.json.as_deref(), &args.report);
    let recording = softgrip_lab::recording::Recording::load(path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--json", json)
        .dir("--report", report.dir("modulus", path).as_deref())
        .check()?;
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
        let figures = softgrip_lab::json::commands::ModulusFigures {
            recording: path.display().to_string(),
            young_modulus: fit.young_modulus,
            young_modulus_range: [fit.e_range.0, fit.e_range.1],
            r_squared: fit.r_squared,
            strain_range: [fit.strain_range.0, fit.strain_range.1],
            points: fit.points,
            intercept_pa: fit.intercept,
        };
        write_json(json, &serde_json::to_value(&figures)?)?;
    }
    Ok(())
}
