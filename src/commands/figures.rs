//! How the lab commands hand out their figures: the recording they read,
//! the report written, the JSON file.

use std::path::Path;

use anyhow::{Context, Result};
use softgrip_lab::recording::Recording;
use softgrip_lab::replay::Replay;
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

/// The recording's ringing (its most-moving marker axis) against each replay's on that axis,
/// printed as a table; `None` (and nothing printed) for a quasi-static recording.
pub fn print_ringing(recording: &Recording, replays: &[(&str, &Replay)]) -> Option<()> {
    use softgrip_lab::ringing::{self, NoRinging, Ringing};
    let d = ringing::dominant(recording)?;
    println!(
        "ringing of {} {} (the most-moving marker axis; c + A exp(-s t) cos(w t + phi) fitted):",
        recording.marker_name(d.marker),
        ringing::axis_name(d.axis)
    );
    println!("                  f (Hz)    s (1/s)   zeta     A (mm)    fit rms (mm)");
    let row = |label: &str, r: &Result<Ringing, NoRinging>| match r {
        Ok(r) => println!(
            "  {label:<15} {:<9.3} {:<9.3} {:<8.4} {:<9.3} {:.3}",
            r.frequency_hz,
            r.decay_rate,
            r.damping_ratio,
            1e3 * r.amplitude,
            1e3 * r.residual_rms
        ),
        Err(e) => println!("  {label:<15} none: {e}"),
    };
    row("recorded", &d.ringing);
    for (label, replay) in replays {
        if let Some(c) = ringing::compare(recording, &replay.residuals) {
            row(label, &c.simulated);
        }
    }
    Some(())
}
