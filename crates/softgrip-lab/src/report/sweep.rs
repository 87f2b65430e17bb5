//! The report of `softgrip sweep`.

use std::fmt::Write as _;
use std::path::Path;

use crate::params::Axis;
use crate::plot::{self, Chart, HeatMap, Mark, Series, palette};
use crate::recording::Recording;
use crate::sweep::SweepPoint;

use super::out::{Out, ReportError, Written, write_file};
use super::tables::{errors_table, fmt_value, header};

/// The report of `softgrip sweep` in `dir` (`sweep.md`, `sweep.csv` and
/// the curve or heat map).
pub fn sweep(
    dir: &Path,
    recording: &Recording,
    axes: &[Axis],
    points: &[SweepPoint],
    seconds: f64,
) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = header(recording, "Sweep");
    let csv = dir.join("sweep.csv");
    write_file(&csv, &crate::sweep::to_csv(axes, points))?;
    summary(&mut md, axes, points, seconds);
    let best = crate::sweep::best(points).map(|b| b.values.clone());
    match axes {
        [a] => {
            let chart = curve(a, points, best);
            md += &out.chart("sweep.png", &chart, "sweep curve")?;
        }
        [a, b] => {
            let map = heat_map(a, b, points, best);
            md += &out.image("sweep.png", &plot::heat_map_png(&map)?, "sweep heat map")?;
        }
        _ => {}
    }
    out.finish("sweep.md", &md)
}

/// The points run and failed, the time taken, and the best point with its errors.
fn summary(md: &mut String, axes: &[Axis], points: &[SweepPoint], seconds: f64) {
    let failed = points.iter().filter(|p| p.result.is_err()).count();
    let _ = writeln!(
        md,
        "{} points ({}), {:.0} s; {} did not run. Every point is in `sweep.csv`.\n",
        points.len(),
        axes.iter()
            .map(|a| format!("{} x {}", a.values.len(), a.param.name))
            .collect::<Vec<_>>()
            .join(" by "),
        seconds,
        failed
    );
    if let Some(b) = crate::sweep::best(points)
        && let Ok(e) = &b.result
    {
        let at = axes
            .iter()
            .zip(&b.values)
            .map(|(a, v)| format!("{} = {}", a.param.name, fmt_value(*v)))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(md, "Best point: {at}.\n");
        *md += &errors_table(&[("best", e)]);
    }
}

/// A point's NRMSE; NaN where it did not run.
fn nrmse(p: &SweepPoint) -> f64 {
    p.result.as_ref().map_or(f64::NAN, |e| e.nrmse)
}

/// A log axis for log-spaced values (`:log`), a linear one otherwise.
fn log_axis(a: &Axis) -> bool {
    a.values.len() > 2
        && a.values.iter().all(|v| *v > 0.0)
        && a.values.windows(3).all(|w| {
            let (r0, r1) = (w[1] / w[0], w[2] / w[1]);
            (r0 - r1).abs() < 1e-6 * r0 && (r0 - 1.0).abs() > 1e-9
        })
}

/// NRMSE against the one axis swept, the best point marked.
fn curve(a: &Axis, points: &[SweepPoint], best: Option<Vec<f64>>) -> Chart {
    Chart {
        title: format!("NRMSE against {}", a.param.name),
        x_label: axis_label(a),
        y_label: "NRMSE".into(),
        x_log: log_axis(a),
        series: vec![
            Series {
                label: "NRMSE".into(),
                points: points.iter().map(|p| (p.values[0], nrmse(p))).collect(),
                mark: Mark::LineAndPoints,
                color: palette(0),
            },
            Series {
                label: "best".into(),
                points: best
                    .iter()
                    .filter_map(|b| {
                        let p = points.iter().find(|p| &p.values == b)?;
                        Some((b[0], nrmse(p)))
                    })
                    .collect(),
                mark: Mark::Points,
                color: palette(3),
            },
        ],
        ..Chart::default()
    }
}

/// NRMSE over the two axes swept (`a` along x, `b` along y), the best point marked.
fn heat_map(a: &Axis, b: &Axis, points: &[SweepPoint], best: Option<Vec<f64>>) -> HeatMap {
    // Grid order: the last axis fastest; the heat map's rows are y.
    let mut xs: Vec<(usize, f64)> = a.values.iter().copied().enumerate().collect();
    let mut ys: Vec<(usize, f64)> = b.values.iter().copied().enumerate().collect();
    xs.sort_by(|p, q| p.1.total_cmp(&q.1));
    ys.sort_by(|p, q| p.1.total_cmp(&q.1));
    let mut values = Vec::with_capacity(xs.len() * ys.len());
    for (j, _) in &ys {
        for (i, _) in &xs {
            values.push(points.get(i * b.values.len() + j).map_or(f64::NAN, nrmse));
        }
    }
    HeatMap {
        title: format!("NRMSE over {} and {}", a.param.name, b.param.name),
        x_label: axis_label(a),
        y_label: axis_label(b),
        value_label: "NRMSE".into(),
        x: xs.iter().map(|p| p.1).collect(),
        y: ys.iter().map(|p| p.1).collect(),
        values,
        x_log: log_axis(a),
        y_log: log_axis(b),
        mark: best.map(|v| (v[0], v[1])),
        ..HeatMap::default()
    }
}

/// An axis's label: the parameter's name, with its unit where it has one.
fn axis_label(a: &Axis) -> String {
    if a.param.unit.is_empty() {
        a.param.name.into()
    } else {
        format!("{} ({})", a.param.name, a.param.unit)
    }
}
