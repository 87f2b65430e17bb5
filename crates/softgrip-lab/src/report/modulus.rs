//! The report of `softgrip modulus`.

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::{Chart, Mark, Series, palette};
use crate::recording::Recording;

use super::out::{Out, ReportError, Written};
use super::tables::header;

/// The report of `softgrip modulus` in `dir` (`modulus.md` and the
/// stress-strain plot with the fitted line).
pub fn modulus(
    dir: &Path,
    recording: &Recording,
    fit: &crate::modulus::ModulusFit,
) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = header(recording, "Modulus");
    let _ = writeln!(
        md,
        "Stress F / A and strain dl / l0 of each load level (thesis eq. 49-50), with A = {:.4e} m^2 and l0 = {:.4} m from the scene. The initial linear part is found automatically: levels are added from the unloaded state while the next segment's slope stays within {:.0} % of the line fitted so far.\n",
        fit.area,
        fit.length,
        100.0 * crate::modulus::LINEAR_TOLERANCE
    );
    let _ = writeln!(
        md,
        "| | value |\n|---|---|\n| Young's modulus E (slope) | {:.1} kPa |\n| strain range fitted | {:.4} .. {:.4} ({} points with the unloaded state) |\n| R^2 | {:.5} |\n| intercept (seating toe) | {:.3} kPa |\n| E over the candidate ranges (2 points up to the chosen) | {:.1} .. {:.1} kPa |\n| the scene's E | {:.1} kPa |\n",
        fit.young_modulus / 1e3,
        fit.strain_range.0,
        fit.strain_range.1,
        fit.points,
        fit.r_squared,
        fit.intercept / 1e3,
        fit.e_range.0 / 1e3,
        fit.e_range.1 / 1e3,
        recording.scene.object.young_modulus / 1e3
    );
    let end = fit.curve.last().map_or(0.0, |p| p.0);
    let line_end = (2.0 * fit.strain_range.1).min(end).max(fit.strain_range.1);
    let chart = Chart {
        title: "Stress against strain, and the line through the initial linear part".into(),
        x_label: "strain".into(),
        y_label: "stress (kPa)".into(),
        series: vec![
            Series {
                label: "measured".into(),
                points: fit.curve.iter().map(|(e, s)| (*e, s / 1e3)).collect(),
                mark: Mark::LineAndPoints,
                color: palette(0),
            },
            Series {
                label: "points fitted".into(),
                points: fit.curve[..fit.points.min(fit.curve.len())]
                    .iter()
                    .map(|(e, s)| (*e, s / 1e3))
                    .collect(),
                mark: Mark::Points,
                color: palette(3),
            },
            Series {
                label: format!("E = {:.1} kPa", fit.young_modulus / 1e3),
                points: [0.0, line_end]
                    .iter()
                    .map(|e| (*e, (fit.intercept + fit.young_modulus * e) / 1e3))
                    .collect(),
                mark: Mark::Dashed,
                color: [20, 20, 20],
            },
        ],
        ..Chart::default()
    };
    md += &out.chart("stress_strain.png", &chart, "stress against strain")?;
    out.finish("modulus.md", &md)
}
