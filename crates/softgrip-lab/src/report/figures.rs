//! The plots every report of a replay shows: marker paths, motion and
//! residuals per sample.

use crate::compare::Residual;
use crate::plot::{Chart, Mark, Series, palette};
use crate::recording::{MarkerRef, Mode, Recording};
use crate::replay::Replay;

use super::out::{Out, ReportError};

/// Marker paths drawn with at most this many markers (the palette's twenty).
const MAX_MARKERS: usize = 20;
/// Residual lines only when there are at most this many samples.
const MAX_ARROW_SAMPLES: usize = 25;
/// Axis names by index.
pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

/// The x of sample `i` in plots: its load (quasi-static) or time.
fn sample_x(recording: &Recording, i: usize) -> f64 {
    let s = &recording.samples[i];
    match recording.mode {
        Mode::QuasiStatic => s.load,
        Mode::TimeSeries => s.time.unwrap_or(f64::NAN),
    }
}

fn sample_label(recording: &Recording) -> &'static str {
    match recording.mode {
        Mode::QuasiStatic => "load (N)",
        Mode::TimeSeries => "time (s)",
    }
}

/// The markers plotted: the object markers (the fingers when there are
/// none), at most [`MAX_MARKERS`].
pub(super) fn plotted_markers(residuals: &[Residual]) -> Vec<MarkerRef> {
    let mut all: Vec<MarkerRef> = crate::compare::scored(residuals)
        .map(|r| r.marker)
        .collect();
    all.sort();
    all.dedup();
    all.truncate(MAX_MARKERS);
    all
}

/// The observed axes ordered by how far the recorded markers move along
/// them (largest first).
pub(super) fn moving_axes(residuals: &[Residual]) -> Vec<usize> {
    let mut spans: Vec<(usize, f64)> = (0..3)
        .filter_map(|a| {
            let mut per_marker: std::collections::BTreeMap<MarkerRef, (f64, f64)> =
                std::collections::BTreeMap::new();
            for r in crate::compare::scored(residuals) {
                if let Some(v) = r.recorded[a] {
                    let e = per_marker.entry(r.marker).or_insert((v, v));
                    e.0 = e.0.min(v);
                    e.1 = e.1.max(v);
                }
            }
            (!per_marker.is_empty())
                .then(|| (a, per_marker.values().map(|(lo, hi)| hi - lo).sum::<f64>()))
        })
        .collect();
    spans.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    spans.into_iter().map(|(a, _)| a).collect()
}

/// `paths.png`, `motion.png` and `residuals.png` of one replay; returns
/// their Markdown.
pub(super) fn replay_plots(
    out: &mut Out,
    recording: &Recording,
    replay: &Replay,
    title: &str,
) -> Result<String, ReportError> {
    let mut md = String::new();
    let residuals = &replay.residuals;
    let markers = plotted_markers(residuals);
    let axes = moving_axes(residuals);
    let few = recording.samples.len() <= MAX_ARROW_SAMPLES;
    if axes.len() >= 2 {
        let (a, b) = (axes[0].min(axes[1]), axes[0].max(axes[1]));
        let chart = paths_chart(recording, residuals, &markers, [a, b], few, title);
        md += &out.chart("paths.png", &chart, "marker paths")?;
    }
    if let Some(&a) = axes.first() {
        let chart = Chart {
            title: format!(
                "{title}: {} of each marker, recorded (dots) and simulated (lines)",
                AXES[a]
            ),
            x_label: sample_label(recording).into(),
            y_label: format!("{} (mm)", AXES[a]),
            series: marker_series(
                recording,
                residuals,
                &markers,
                |r| (sample_x(recording, r.sample), 1e3 * r.simulated[a]),
                |r| Some((sample_x(recording, r.sample), 1e3 * r.recorded[a]?)),
            ),
            ..Chart::default()
        };
        md += &out.chart("motion.png", &chart, "motion")?;
    }
    md += &out.chart(
        "residuals.png",
        &residual_chart(recording, &[(title, replay)], &markers),
        "residuals",
    )?;
    Ok(md)
}

/// The markers' paths in the plane of axes `a` and `b` (`title: ...`): recorded dots, simulated
/// lines, with an arrow from each simulated to its recorded position where `few` samples.
fn paths_chart(
    recording: &Recording,
    residuals: &[Residual],
    markers: &[MarkerRef],
    [a, b]: [usize; 2],
    few: bool,
    title: &str,
) -> Chart {
    let mut chart = Chart {
        title: format!("{title}: marker displacements, recorded (dots) and simulated (lines)"),
        x_label: format!("{} displacement (mm)", AXES[a]),
        y_label: format!("{} displacement (mm)", AXES[b]),
        equal_aspect: true,
        ..Chart::default()
    };
    // From each marker's undeformed position: sub-millimetre paths on a 50 mm object
    // would be dots at their absolute positions.
    let at = |r: &Residual| reference(recording, r.marker);
    chart.series = marker_series(
        recording,
        residuals,
        markers,
        |r| {
            (
                1e3 * (r.simulated[a] - at(r)[a]),
                1e3 * (r.simulated[b] - at(r)[b]),
            )
        },
        |r| {
            Some((
                1e3 * (r.recorded[a]? - at(r)[a]),
                1e3 * (r.recorded[b]? - at(r)[b]),
            ))
        },
    );
    if few {
        for m in markers {
            for r in residuals.iter().filter(|r| r.marker == *m) {
                if let (Some(x), Some(y)) = (r.recorded[a], r.recorded[b]) {
                    let o = at(r);
                    chart.arrows.push((
                        (1e3 * (r.simulated[a] - o[a]), 1e3 * (r.simulated[b] - o[b])),
                        (1e3 * (x - o[a]), 1e3 * (y - o[b])),
                        [120, 120, 120],
                    ));
                }
            }
        }
    }
    chart
}

/// Where a marker is on the undeformed scene: its reference, or a finger's starting centre.
fn reference(recording: &Recording, m: MarkerRef) -> glam::DVec3 {
    match m {
        MarkerRef::Object(k) => recording.markers[k].reference,
        MarkerRef::Finger(k) => recording
            .scene
            .fingers
            .get(k)
            .map_or(glam::DVec3::ZERO, |f| f.position),
    }
}

/// Per marker, in its palette colour: where `simulated` puts its residuals
/// as a labelled line, then where `recorded` puts those observed as dots.
fn marker_series(
    recording: &Recording,
    residuals: &[Residual],
    markers: &[MarkerRef],
    simulated: impl Fn(&Residual) -> (f64, f64),
    recorded: impl Fn(&Residual) -> Option<(f64, f64)>,
) -> Vec<Series> {
    let mut series = Vec::with_capacity(2 * markers.len());
    for (k, m) in markers.iter().enumerate() {
        let rs: Vec<&Residual> = residuals.iter().filter(|r| r.marker == *m).collect();
        let color = palette(k);
        series.push(Series {
            label: recording.marker_name(*m),
            points: rs.iter().map(|r| simulated(r)).collect(),
            mark: Mark::Line,
            color,
        });
        series.push(Series {
            label: String::new(),
            points: rs.iter().filter_map(|r| recorded(r)).collect(),
            mark: Mark::Points,
            color,
        });
    }
    series
}

/// Each marker's residual distance per sample (thin lines) and the RMS
/// over the scored markers per sample (thick), for one or more replays
/// (e.g. before and after a fit).
pub(super) fn residual_chart(
    recording: &Recording,
    runs: &[(&str, &Replay)],
    markers: &[MarkerRef],
) -> Chart {
    let mut chart = Chart {
        title: "Residual distance per sample (simulated to recorded, observed axes)".into(),
        x_label: sample_label(recording).into(),
        y_label: "residual (mm)".into(),
        ..Chart::default()
    };
    let single = runs.len() == 1;
    for (j, (name, replay)) in runs.iter().enumerate() {
        if single {
            for (k, m) in markers.iter().enumerate() {
                chart.series.push(Series {
                    label: recording.marker_name(*m),
                    points: replay
                        .residuals
                        .iter()
                        .filter(|r| r.marker == *m)
                        .map(|r| (sample_x(recording, r.sample), 1e3 * r.distance()))
                        .collect(),
                    mark: Mark::Line,
                    color: palette(k),
                });
            }
        }
        let rms = per_sample_rms(recording, &replay.residuals);
        chart.series.push(Series {
            label: format!("RMS {name}"),
            points: rms,
            mark: if single || j > 0 {
                Mark::LineAndPoints
            } else {
                Mark::Dashed
            },
            color: if single { [20, 20, 20] } else { palette(j) },
        });
    }
    chart
}

/// (x, RMS residual in mm) of each sample over the scored markers.
fn per_sample_rms(recording: &Recording, residuals: &[Residual]) -> Vec<(f64, f64)> {
    let mut sums = vec![(0.0, 0usize); recording.samples.len()];
    for r in crate::compare::scored(residuals) {
        if let Some(s) = sums.get_mut(r.sample) {
            s.0 += r.distance().powi(2);
            s.1 += 1;
        }
    }
    sums.iter()
        .enumerate()
        .filter(|(_, (_, n))| *n > 0)
        .map(|(i, (s, n))| (sample_x(recording, i), 1e3 * (s / *n as f64).sqrt()))
        .collect()
}
