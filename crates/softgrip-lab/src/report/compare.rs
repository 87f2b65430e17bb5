//! The report of `softgrip compare`.

use std::fmt::Write as _;
use std::path::Path;

use crate::recording::Recording;
use crate::replay::Replay;

use super::figures::replay_plots;
use super::out::{Out, ReportError, Written, write_file};
use super::tables::{errors_table, header, marker_table, volume_line};

/// The report of `softgrip compare` in `dir` (`compare.md` and plots).
pub fn compare(dir: &Path, recording: &Recording, replay: &Replay) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = header(recording, "Compare");
    md += "NRMSE as the thesis (eq. 45-46) and the spec define it: the RMS, over the object markers and samples, of the distance between simulated and recorded position over the observed axes, divided by the object's largest extent.\n\n";
    md += &errors_table(&[("scene as given", &replay.errors)]);
    md += &volume_line(replay);
    md += "## Per marker\n\n";
    md += &marker_table(recording, replay);
    md += "Every residual (per marker, axis and sample) is in `residuals.csv`.\n\n";
    write_residuals(&dir.join("residuals.csv"), recording, replay)?;
    md += "## Plots\n\n";
    md += &replay_plots(&mut out, recording, replay, "scene as given")?;
    out.finish("compare.md", &md)
}

/// The full residual table: one row per marker per sample, the recorded
/// and simulated position and their difference per axis (m; empty where
/// the axis was not observed).
fn write_residuals(path: &Path, recording: &Recording, replay: &Replay) -> Result<(), ReportError> {
    let mut csv = String::from(
        "sample,time,load,marker,recorded_x,recorded_y,recorded_z,simulated_x,simulated_y,simulated_z,residual_x,residual_y,residual_z,distance\n",
    );
    for r in &replay.residuals {
        let s = &recording.samples[r.sample];
        let _ = write!(
            csv,
            "{},{},{:?},{}",
            r.sample,
            s.time.map_or(String::new(), |t| format!("{t:?}")),
            s.load,
            recording.marker_name(r.marker)
        );
        for a in 0..3 {
            let _ = write!(
                csv,
                ",{}",
                r.recorded[a].map_or(String::new(), |x| format!("{x:?}"))
            );
        }
        for a in 0..3 {
            let _ = write!(csv, ",{:?}", r.simulated[a]);
        }
        for a in 0..3 {
            let _ = write!(
                csv,
                ",{}",
                r.recorded[a].map_or(String::new(), |x| format!("{:?}", r.simulated[a] - x))
            );
        }
        let _ = writeln!(csv, ",{:?}", r.distance());
    }
    write_file(path, &csv)
}
