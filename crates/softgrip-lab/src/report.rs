//! Reports of `softgrip compare`, `fit` and `sweep`: a Markdown file with
//! its figures as PNG plots beside it, in a directory of their own.
//!
//! The plots show what a reader would otherwise dig out of tables:
//! - `paths.png`: each object marker's path in the plane of the two axes
//!   it moves most along, recorded (dots) against simulated (line), with
//!   residual lines from simulated to recorded when there are few samples;
//! - `motion.png`: the most-moving coordinate against load or time;
//! - `residuals.png`: each marker's residual distance per sample, and
//!   their root mean square;
//! - fits add `convergence.png` (best NRMSE against simulations) and the
//!   residuals before and after; sweeps add the NRMSE curve or heat map.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::compare::{Errors, Residual};
use crate::fit::Fit;
use crate::params::Axis;
use crate::plot::{self, Chart, HeatMap, Mark, PlotError, Series, palette};
use crate::recording::{MarkerRef, Mode, Recording};
use crate::replay::Replay;
use crate::sweep::SweepPoint;

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("cannot write the report in {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("report plot: {0}")]
    Plot(#[from] PlotError),
}

/// The files a report wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    pub markdown: PathBuf,
    pub images: Vec<PathBuf>,
}

/// Marker paths drawn with at most this many markers (the palette's ten).
const MAX_MARKERS: usize = 10;
/// Residual lines only when there are at most this many samples.
const MAX_ARROW_SAMPLES: usize = 25;
const AXES: [&str; 3] = ["x", "y", "z"];

struct Out {
    dir: PathBuf,
    images: Vec<PathBuf>,
}

impl Out {
    fn new(dir: &Path) -> Result<Out, ReportError> {
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Write {
            path: dir.to_path_buf(),
            source,
        })?;
        Ok(Out {
            dir: dir.to_path_buf(),
            images: Vec::new(),
        })
    }

    /// Writes a plot and returns the Markdown that shows it.
    fn image(&mut self, name: &str, png: &[u8], alt: &str) -> Result<String, ReportError> {
        let path = self.dir.join(name);
        plot::write_png(&path, png)?;
        self.images.push(path);
        Ok(format!("![{alt}]({name})\n\n"))
    }

    fn finish(self, name: &str, text: &str) -> Result<Written, ReportError> {
        let markdown = self.dir.join(name);
        std::fs::write(&markdown, text).map_err(|source| ReportError::Write {
            path: markdown.clone(),
            source,
        })?;
        Ok(Written {
            markdown,
            images: self.images,
        })
    }
}

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
fn plotted_markers(residuals: &[Residual]) -> Vec<MarkerRef> {
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
fn moving_axes(residuals: &[Residual]) -> Vec<usize> {
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
fn replay_plots(
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
        let mut chart = Chart {
            title: format!("{title}: marker paths, recorded (dots) and simulated (lines)"),
            x_label: format!("{} (mm)", AXES[a]),
            y_label: format!("{} (mm)", AXES[b]),
            equal_aspect: true,
            ..Chart::default()
        };
        for (k, m) in markers.iter().enumerate() {
            let rs: Vec<&Residual> = residuals.iter().filter(|r| r.marker == *m).collect();
            let color = palette(k);
            chart.series.push(Series {
                label: recording.marker_name(*m),
                points: rs
                    .iter()
                    .map(|r| (1e3 * r.simulated[a], 1e3 * r.simulated[b]))
                    .collect(),
                mark: Mark::Line,
                color,
            });
            let recorded: Vec<(f64, f64)> = rs
                .iter()
                .filter_map(|r| Some((1e3 * r.recorded[a]?, 1e3 * r.recorded[b]?)))
                .collect();
            if few {
                for r in &rs {
                    if let (Some(x), Some(y)) = (r.recorded[a], r.recorded[b]) {
                        chart.arrows.push((
                            (1e3 * r.simulated[a], 1e3 * r.simulated[b]),
                            (1e3 * x, 1e3 * y),
                            [120, 120, 120],
                        ));
                    }
                }
            }
            chart.series.push(Series {
                label: String::new(),
                points: recorded,
                mark: Mark::Points,
                color,
            });
        }
        md += &out.image("paths.png", &plot::chart_png(&chart)?, "marker paths")?;
    }
    if let Some(&a) = axes.first() {
        let mut chart = Chart {
            title: format!(
                "{title}: {} of each marker, recorded (dots) and simulated (lines)",
                AXES[a]
            ),
            x_label: sample_label(recording).into(),
            y_label: format!("{} (mm)", AXES[a]),
            ..Chart::default()
        };
        for (k, m) in markers.iter().enumerate() {
            let rs: Vec<&Residual> = residuals.iter().filter(|r| r.marker == *m).collect();
            let color = palette(k);
            chart.series.push(Series {
                label: recording.marker_name(*m),
                points: rs
                    .iter()
                    .map(|r| (sample_x(recording, r.sample), 1e3 * r.simulated[a]))
                    .collect(),
                mark: Mark::Line,
                color,
            });
            chart.series.push(Series {
                label: String::new(),
                points: rs
                    .iter()
                    .filter_map(|r| Some((sample_x(recording, r.sample), 1e3 * r.recorded[a]?)))
                    .collect(),
                mark: Mark::Points,
                color,
            });
        }
        md += &out.image("motion.png", &plot::chart_png(&chart)?, "motion")?;
    }
    md += &out.image(
        "residuals.png",
        &plot::chart_png(&residual_chart(recording, &[(title, replay)], &markers))?,
        "residuals",
    )?;
    Ok(md)
}

/// Each marker's residual distance per sample (thin lines) and the RMS
/// over the scored markers per sample (thick), for one or more replays
/// (e.g. before and after a fit).
fn residual_chart(recording: &Recording, runs: &[(&str, &Replay)], markers: &[MarkerRef]) -> Chart {
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

fn errors_table(rows: &[(&str, &Errors)]) -> String {
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
fn marker_table(recording: &Recording, replay: &Replay) -> String {
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

fn header(recording: &Recording, what: &str) -> String {
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

fn volume_line(replay: &Replay) -> String {
    let largest = replay.volume_errors.iter().copied().fold(0.0, f64::max);
    format!(
        "Volume error |V - V0| / V0 (thesis eq. 47-48): largest over the samples {:.3} %, at the last sample {:.3} %.\n\n",
        100.0 * largest,
        100.0 * replay.volume_errors.last().copied().unwrap_or(0.0)
    )
}

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
    std::fs::write(path, csv).map_err(|source| ReportError::Write {
        path: path.to_path_buf(),
        source,
    })
}

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
    md += &out.image(
        "stress_strain.png",
        &plot::chart_png(&chart)?,
        "stress against strain",
    )?;
    out.finish("modulus.md", &md)
}

fn fmt_value(v: f64) -> String {
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

/// The report of `softgrip fit` in `dir` (`fit.md` and plots).
pub fn fit(dir: &Path, recording: &Recording, fit: &Fit) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = header(recording, "Fit");
    let _ = writeln!(
        md,
        "{} simulations ({} converged). NRMSE {:.5} at the start, {:.5} fitted.\n",
        fit.trials.len(),
        if fit.converged {
            "the search"
        } else {
            "the search stopped at its budget, not"
        },
        fit.before.nrmse,
        fit.after.nrmse
    );
    md += &errors_table(&[("start", &fit.before), ("fitted", &fit.after)]);
    let u = &fit.uncertainty;
    let _ = writeln!(
        md,
        "## Parameters\n\nUncertainty: the noise the fitted residuals imply is s = {:.4} mm per observed coordinate ({} coordinates, {} parameters); the standard errors are s^2 (J^T J)^-1 of the residuals' Jacobian J at the fit, and the 95 % interval is +/- 1.96 standard errors. These errors assume independent residuals, which holds for measurement noise; where the model misses systematically (residuals that follow each other from sample to sample, s well above the tracking noise), they are too small, and the spread of fits over repeated recordings is the better measure. Sensitivity: the NRMSE with the parameter 10 % lower and higher; a change is significant when it raises the sum of squared residuals by more than 3.84 s^2 (chi-square, 1 degree of freedom, 95 %).\n",
        1e3 * u.sigma_m,
        u.residuals,
        fit.params.len()
    );
    md += "| parameter | bounds | start | fitted | standard error | 95 % interval | NRMSE at -10 % | NRMSE at +10 % | verdict |\n|---|---|---|---|---|---|---|---|---|\n";
    for (i, p) in fit.params.iter().enumerate() {
        let se = u.standard_errors[i];
        let v = fit.fitted[i];
        let interval = if se.is_finite() {
            format!(
                "{} .. {}",
                fmt_value(v - 1.96 * se),
                fmt_value(v + 1.96 * se)
            )
        } else {
            "none (no effect on the residuals)".into()
        };
        let s = &fit.sensitivity[i];
        let nrmse = |x: Option<f64>| x.map_or("not allowed".into(), |f| format!("{f:.5}"));
        let _ = writeln!(
            md,
            "| {}{} | {} .. {}{} | {} | {} | {} | {} | {} | {} | {}{} |",
            p.param.name,
            if p.param.unit.is_empty() {
                String::new()
            } else {
                format!(" ({})", p.param.unit)
            },
            fmt_value(p.lower),
            fmt_value(p.upper),
            if p.log { " (log)" } else { "" },
            fmt_value(fit.start[i]),
            fmt_value(v),
            fmt_value(se),
            interval,
            nrmse(s.minus),
            nrmse(s.plus),
            s.verdict.label(),
            if fit.at_bound[i] { ", AT A BOUND" } else { "" }
        );
    }
    md.push('\n');
    let [stretch, compression] = fit.replay.largest_strain;
    for (i, p) in fit.params.iter().enumerate() {
        let (largest, what) = match p.param.name {
            "tau_s" => (stretch, "stretch"),
            "tau_c" => (compression, "compression"),
            _ => continue,
        };
        if fit.fitted[i] > largest {
            let _ = writeln!(
                md,
                "{} = {} is above the largest spring {what} of the fitted run ({largest:.4}): the limit never acts, and any value above {largest:.4} fits as well.\n",
                p.param.name,
                fmt_value(fit.fitted[i])
            );
        } else {
            let _ = writeln!(
                md,
                "{}: the largest spring {what} of the fitted run is {largest:.4}, so the limit acts.\n",
                p.param.name
            );
        }
    }
    let correlated: Vec<String> = (0..fit.params.len())
        .flat_map(|i| (i + 1..fit.params.len()).map(move |j| (i, j)))
        .filter(|&(i, j)| u.correlations[i][j].abs() > 0.9)
        .map(|(i, j)| {
            format!(
                "{} and {} ({:+.2})",
                fit.params[i].param.name, fit.params[j].param.name, u.correlations[i][j]
            )
        })
        .collect();
    if !correlated.is_empty() {
        let _ = writeln!(
            md,
            "Strongly correlated estimates (|r| > 0.9): {}. The recording constrains a combination of these better than each alone.\n",
            correlated.join(", ")
        );
    }
    md += "## Plots\n\n";
    let mut best = f64::INFINITY;
    let trace: Vec<(f64, f64)> = fit
        .trials
        .iter()
        .enumerate()
        .map(|(k, t)| {
            if let Ok(f) = t.nrmse {
                best = best.min(f);
            }
            ((k + 1) as f64, best)
        })
        .filter(|(_, f)| f.is_finite())
        .collect();
    let tried: Vec<(f64, f64)> = fit
        .trials
        .iter()
        .enumerate()
        .filter_map(|(k, t)| t.nrmse.as_ref().ok().map(|f| ((k + 1) as f64, *f)))
        .collect();
    let chart = Chart {
        title: "Search: NRMSE of each simulation and the best so far".into(),
        x_label: "simulation".into(),
        y_label: "NRMSE".into(),
        y_log: tried.iter().all(|(_, f)| *f > 0.0) && trace.iter().all(|(_, f)| *f > 0.0),
        series: vec![
            Series {
                label: "tried".into(),
                points: tried,
                mark: Mark::Points,
                color: [150, 150, 150],
            },
            Series {
                label: "best so far".into(),
                points: trace,
                mark: Mark::Line,
                color: palette(0),
            },
        ],
        ..Chart::default()
    };
    md += &out.image("convergence.png", &plot::chart_png(&chart)?, "convergence")?;
    let markers = plotted_markers(&fit.replay.residuals);
    let mut chart = residual_chart(
        recording,
        &[("at the start", &fit.start_replay), ("fitted", &fit.replay)],
        &markers,
    );
    chart.title = "RMS residual per sample, at the start and fitted".into();
    md += &out.image(
        "residuals_before_after.png",
        &plot::chart_png(&chart)?,
        "residuals before and after",
    )?;
    md += &replay_plots(&mut out, recording, &fit.replay, "fitted")?;
    md += "## Per marker, fitted\n\n";
    md += &marker_table(recording, &fit.replay);
    md += &volume_line(&fit.replay);
    out.finish("fit.md", &md)
}

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
    std::fs::write(&csv, crate::sweep::to_csv(axes, points)).map_err(|source| {
        ReportError::Write {
            path: csv.clone(),
            source,
        }
    })?;
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
        md += &errors_table(&[("best", e)]);
    }
    let nrmse = |p: &SweepPoint| p.result.as_ref().map_or(f64::NAN, |e| e.nrmse);
    // A log axis for log-spaced values (`:log`), a linear one otherwise.
    let log_axis = |a: &Axis| {
        a.values.len() > 2
            && a.values.iter().all(|v| *v > 0.0)
            && a.values.windows(3).all(|w| {
                let (r0, r1) = (w[1] / w[0], w[2] / w[1]);
                (r0 - r1).abs() < 1e-6 * r0 && (r0 - 1.0).abs() > 1e-9
            })
    };
    let best = crate::sweep::best(points).map(|b| b.values.clone());
    match axes {
        [a] => {
            let chart = Chart {
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
            };
            md += &out.image("sweep.png", &plot::chart_png(&chart)?, "sweep curve")?;
        }
        [a, b] => {
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
            let map = HeatMap {
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
            };
            md += &out.image("sweep.png", &plot::heat_map_png(&map)?, "sweep heat map")?;
        }
        _ => {}
    }
    out.finish("sweep.md", &md)
}

fn axis_label(a: &Axis) -> String {
    if a.param.unit.is_empty() {
        a.param.name.into()
    } else {
        format!("{} ({})", a.param.name, a.param.unit)
    }
}

/// The report of `softgrip diagnose`: the verdict and its evidence, where
/// the baseline misses, the candidates ranked (`ranking.png`), each
/// marker's residual before and after as arrows (`arrows.png`), and the
/// RMS residual per sample before and after (`residuals.png`).
pub fn diagnosis(
    dir: &Path,
    recording: &Recording,
    d: &crate::diagnose::Diagnosis,
) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = header(recording, "Diagnosis");
    let effects = if d.effects.is_empty() {
        d.verdict()
    } else {
        d.effects.join(" + ")
    };
    let _ = writeln!(md, "## Verdict: {effects}\n\n{}\n", d.evidence);
    md += &errors_table(&[
        ("baseline", &d.baseline.errors),
        ("with the effects", &d.final_fit.errors),
    ]);
    let params = |p: &[(String, f64)]| {
        p.iter()
            .map(|(k, v)| format!("{k} = {}", fmt_value(*v)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        md,
        "\n- baseline fit: {}\n- with the effects: {}\n- noise, estimated from the data (second differences of the residual along the samples, per marker and axis): {}\n",
        params(&d.baseline.params),
        params(&d.fitted_params()),
        d.noise.describe()
    );
    let (beyond_before, beyond_after) = d.nrmse_all_beyond_noise();
    let _ = writeln!(
        md,
        "- NRMSE over all markers beyond the noise (the part of the residual the noise does not account for: the model's own error): {beyond_before:.4} for the baseline, {beyond_after:.4} with the effects{}",
        if beyond_before > 0.0 {
            format!(" ({:.2} of it left)", beyond_after / beyond_before)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        md,
        "- the model's own discretisation, at the final fit: {}\n",
        d.discretisation.describe()
    );
    if !d.pinned.is_empty() {
        let _ = writeln!(
            md,
            "- at the edge of its search range after the baseline fit: {} (each: either the data do not pin it down, or the fit bends it to stand in for something the model lacks; a measured range, `--bound`, settles it)",
            d.pinned.join(", ")
        );
    }
    for (name, low, high) in &d.bounds {
        let _ = writeln!(
            md,
            "- searched within the range given (`--bound`): {name} {} to {}",
            fmt_value(*low),
            fmt_value(*high)
        );
    }
    if !d.bounds.is_empty() || !d.pinned.is_empty() {
        md.push('\n');
    }
    let l = &d.location;
    let _ = writeln!(
        md,
        "## Where the baseline misses\n\n{} (chi-square {:.0} on {} coordinates{}).\n",
        l.description,
        l.chi2,
        l.dof,
        if l.significant {
            ", beyond three of its standard deviations"
        } else {
            ", within the noise"
        }
    );
    if !l.markers.is_empty() {
        md += "| marker | RMS residual / noise |\n|---|---|\n";
        for (m, r) in &l.markers {
            let _ = writeln!(md, "| {m} | {r:.1} |");
        }
        md.push('\n');
    }
    // The candidates, first round, ranked.
    let mut first: Vec<&crate::diagnose::Hypothesis> =
        d.hypotheses.iter().filter(|h| h.round == 0).collect();
    first.sort_by(|a, b| a.score.total_cmp(&b.score));
    if !first.is_empty() {
        let name =
            |h: &crate::diagnose::Hypothesis| crate::diagnose::effect_label(h.effect, &h.variant);
        let bars = plot::Bars {
            title: "Candidates: BIC gain over the baseline (higher is better; accepted in green)"
                .into(),
            y_label: "-(BIC change)".into(),
            labels: first.iter().map(|h| name(h)).collect(),
            values: first.iter().map(|h| (-h.score).max(-50.0)).collect(),
            colors: first
                .iter()
                .map(|h| {
                    if d.named(h) {
                        [40, 160, 60]
                    } else {
                        [150, 150, 150]
                    }
                })
                .collect(),
            ..plot::Bars::default()
        };
        md += "## Candidates\n\n";
        md += &out.image("ranking.png", &plot::bars_png(&bars)?, "candidates ranked")?;
        md += "| round | candidate | BIC change | residual removed | Vuong z against the best other effect | NRMSE, fingers included | fitted |\n|---|---|---|---|---|---|---|\n";
        let mut all: Vec<&crate::diagnose::Hypothesis> = d.hypotheses.iter().collect();
        all.sort_by(|a, b| {
            (a.round, a.score)
                .partial_cmp(&(b.round, b.score))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for h in all {
            match &h.fit {
                Ok(f) => {
                    let _ = writeln!(
                        md,
                        "| {} | {} | {:+.1} | {:.0} % | {} | {:.5} | {} |",
                        h.round + 1,
                        name(h),
                        h.score,
                        100.0 * h.explained,
                        h.z_text(),
                        f.errors.nrmse_all,
                        params(&f.params)
                    );
                }
                Err(e) => {
                    let _ = writeln!(md, "| {} | {} | failed | | | | {e} |", h.round + 1, name(h));
                }
            }
        }
        md.push('\n');
    }
    // Residual arrows, before and after, magnified.
    let residuals_before = &d.baseline.replay.residuals;
    let residuals_after = &d.final_fit.replay.residuals;
    let axes = moving_axes(residuals_before);
    if axes.len() >= 2 {
        let (a, b) = (axes[0].min(axes[1]), axes[0].max(axes[1]));
        let gain = 10.0;
        let mut chart = Chart {
            title: format!(
                "Residuals x{gain}: recorded (dots), baseline (red) and with the effects (blue) to them"
            ),
            x_label: format!("{} (mm)", AXES[a]),
            y_label: format!("{} (mm)", AXES[b]),
            equal_aspect: true,
            ..Chart::default()
        };
        let mut recorded = Vec::new();
        for (rs, color) in [
            (residuals_before, [200, 40, 40]),
            (residuals_after, [40, 80, 200]),
        ] {
            for r in rs {
                if let (Some(x), Some(y)) = (r.recorded[a], r.recorded[b]) {
                    let (sx, sy) = (r.simulated[a], r.simulated[b]);
                    chart.arrows.push((
                        (1e3 * (x + gain * (sx - x)), 1e3 * (y + gain * (sy - y))),
                        (1e3 * x, 1e3 * y),
                        color,
                    ));
                    recorded.push((1e3 * x, 1e3 * y));
                }
            }
        }
        chart.series.push(Series {
            label: "recorded".into(),
            points: recorded,
            mark: Mark::Points,
            color: [20, 20, 20],
        });
        md += "## Residuals before and after\n\n";
        md += &out.image("arrows.png", &plot::chart_png(&chart)?, "residual arrows")?;
    }
    let chart = residual_chart(
        recording,
        &[
            ("baseline", &d.baseline.replay),
            ("with the effects", &d.final_fit.replay),
        ],
        &[],
    );
    md += &out.image(
        "residuals.png",
        &plot::chart_png(&chart)?,
        "residuals per sample",
    )?;
    out.finish("diagnosis.md", &md)
}
