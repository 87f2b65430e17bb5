//! The Markdown pieces reports share: the header, the error and marker
//! tables, the volume line and compact numbers.

use std::fmt::Write as _;

use crate::compare::Errors;
use crate::recording::{MarkerRef, Mode, Recording};
use crate::replay::Replay;

pub(super) fn errors_table(rows: &[(&str, &Errors)]) -> String {
    let mut md = String::from(
        "| | NRMSE | RMSE (mm) | NRMSE, fingers included | RMSE, fingers included (mm) | observations |\n|---|---|---|---|---|---|\n",
    );
    for (name, e) in rows {
        let _ = writeln!(
            md,
            "| {name} | {:.5} | {:.3} | {:.5} | {:.3} | {} |",
            e.nrmse,
            1e3 * e.rmse_m,
            e.nrmse_all,
            1e3 * e.rmse_all_m,
            e.count
        );
    }
    md.push('\n');
    md
}

/// Per marker: its reference's distance from the surface and the RMS
/// residual per observed axis and overall.
pub(super) fn marker_table(recording: &Recording, replay: &Replay) -> String {
    let mut md = String::from(
        "| marker | reference from surface (mm) | RMS x (mm) | RMS y (mm) | RMS z (mm) | RMS distance (mm) |\n|---|---|---|---|---|---|\n",
    );
    for e in crate::compare::per_marker(&replay.residuals) {
        let m = e.marker;
        let axis = |a: usize| e.axes[a].map_or("-".to_string(), |x| format!("{:.3}", 1e3 * x));
        let total = e.distance;
        let distance = match m {
            MarkerRef::Object(k) => replay
                .attachments
                .get(k)
                .map_or("-".into(), |a| format!("{:.2}", 1e3 * a.distance)),
            MarkerRef::Finger(_) => "(finger centre)".into(),
        };
        let _ = writeln!(
            md,
            "| {} | {distance} | {} | {} | {} | {:.3} |",
            recording.marker_name(m),
            axis(0),
            axis(1),
            axis(2),
            1e3 * total
        );
    }
    md.push('\n');
    md
}

pub(super) fn header(recording: &Recording, what: &str) -> String {
    let mut md = format!("# {what}: {}\n\n", recording.source.display());
    if !recording.description.is_empty() {
        let _ = writeln!(md, "{}\n", recording.description);
    }
    let observations: usize = recording.samples.iter().map(|s| s.observations.len()).sum();
    let _ = writeln!(
        md,
        "- scene: `{}`\n- mode: {}, {} samples, {} object markers, {} observations\n",
        recording.scene_path.display(),
        match recording.mode {
            Mode::QuasiStatic => "quasi-static",
            Mode::TimeSeries => "time-series",
        },
        recording.samples.len(),
        recording.markers.len(),
        observations
    );
    md
}

pub(super) fn volume_line(replay: &Replay) -> String {
    let largest = replay.volume_errors.iter().copied().fold(0.0, f64::max);
    format!(
        "Volume error |V - V0| / V0 (thesis eq. 47-48): largest over the samples {:.3} %, at the last sample {:.3} %.\n\n",
        100.0 * largest,
        100.0 * replay.volume_errors.last().copied().unwrap_or(0.0)
    )
}

pub(super) fn fmt_value(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if !v.is_finite() {
        "inf".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-2 {
        format!("{v:.4e}")
    } else {
        format!("{v:.5}")
    }
}
