//! How the lab commands hand out their figures: the recording they read,
//! the report written, the JSON file.

use std::path::Path;

use anyhow::{Context, Result};
use softgrip_lab::compare::Errors;
use softgrip_lab::recording::Recording;
use softgrip_lab::report::Written;

/// The recording's header line: description, mode, samples and markers.
pub fn describe(path: &Path, recording: &Recording) {
    println!(
        "{}: {} ({}), {} samples, {} object markers",
        path.display(),
        if recording.description.is_empty() {
            "no description"
        } else {
            &recording.description
        },
        recording.mode.name(),
        recording.samples.len(),
        recording.markers.len()
    );
}

/// The line that says where the report went.
pub fn wrote(w: &Written) {
    println!(
        "report: {} ({} plots)",
        w.markdown.display(),
        w.images.len()
    );
}

/// Writes `value` as pretty JSON and says so.
pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<()> {
    std::fs::write(path, serde_json::to_string_pretty(value)?)
        .with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// Writes `value` as pretty JSON ended by a newline, silently (`diagnose`
/// and `grasp`).
pub fn write_json_line(path: &Path, value: &serde_json::Value) -> Result<()> {
    std::fs::write(path, serde_json::to_string_pretty(value)? + "\n")
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

/// The error figures against the recording at `path`, the JSON the
/// compare, sweep and fit commands start from.
pub fn errors_json_for(path: &Path, e: &Errors) -> serde_json::Value {
    let mut value = errors_json(e);
    value["recording"] = path.display().to_string().into();
    value
}

pub fn errors_json(e: &Errors) -> serde_json::Value {
    serde_json::json!({
        "nrmse": e.nrmse,
        "rmse_m": e.rmse_m,
        "nrmse_all": e.nrmse_all,
        "rmse_all_m": e.rmse_all_m,
        "observations": e.count,
    })
}
