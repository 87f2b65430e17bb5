//! The report of `softgrip fit`.

use std::fmt::Write as _;
use std::path::Path;

use crate::fit::{Fit, FitMany};
use crate::plot::{Chart, Mark, Series, palette};
use crate::recording::Recording;

use super::figures::{plotted_markers, replay_plots, residual_chart};
use super::out::{Out, ReportError, Written};
use super::tables::{errors_table, fmt_value, header, marker_table, volume_line};

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
    let shared = Shared {
        params: &fit.params,
        start: &fit.start,
        fitted: &fit.fitted,
        at_bound: &fit.at_bound,
        uncertainty: &fit.uncertainty,
        sensitivity: &fit.sensitivity,
        trials: &fit.trials,
        largest_strain: fit.replay.largest_strain,
    };
    md += &parameters(&shared);
    md += "## Plots\n\n";
    md += &convergence(&mut out, &shared)?;
    md += &fitted_sections(&mut out, recording, &fit.start_replay, &fit.replay)?;
    out.finish("fit.md", &md)
}

/// A name for a recording in a report: its file's stem, or its directory's for
/// `.../gravity_a/recording.toml`.
pub fn recording_name(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if stem == "recording" || stem.is_empty() {
        path.canonicalize()
            .ok()
            .and_then(|p| {
                p.parent()?
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
            })
            .unwrap_or(stem)
    } else {
        stem
    }
}

/// The report of `softgrip fit` over several recordings in `dir`: `fit.md` with the shared
/// parameters, each recording's NRMSE before and after and the search; each recording's own
/// figures (residuals before and after, paths, motion, residuals, per-marker table) in a
/// directory of its own, `NN-NAME/recording.md`, linked from `fit.md`.
pub fn fit_many(
    dir: &Path,
    recordings: &[Recording],
    fit: &FitMany,
) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let mut md = format!("# Fit over {} recordings\n\n", recordings.len());
    let _ = writeln!(
        md,
        "One set of parameter values, each recording simulated on its own scene with them. The objective is the mean of the recordings' NRMSE (each recording's RMSE over its own object's extent, so none outweighs the others by its number of samples). {} points of {} simulations each ({} converged). Mean NRMSE {:.5} at the start, {:.5} fitted.\n",
        fit.trials.len(),
        recordings.len(),
        if fit.converged {
            "the search"
        } else {
            "the search stopped at its budget, not"
        },
        fit.before,
        fit.after
    );
    md += "| recording | mode | samples | NRMSE at the start | NRMSE fitted | RMSE fitted (mm) | figures |\n|---|---|---|---|---|---|---|\n";
    let mut images = Vec::new();
    let mut sections = Vec::new();
    for (i, (recording, part)) in recordings.iter().zip(&fit.recordings).enumerate() {
        let (name, written) = recording_part(&mut md, dir, i, recording, part)?;
        sections.push((name, written.images.clone()));
        images.extend(written.images);
    }
    md.push('\n');
    let largest_strain = fit.recordings.iter().fold([0.0f64; 2], |m, r| {
        [
            m[0].max(r.replay.largest_strain[0]),
            m[1].max(r.replay.largest_strain[1]),
        ]
    });
    let shared = Shared {
        params: &fit.params,
        start: &fit.start,
        fitted: &fit.fitted,
        at_bound: &fit.at_bound,
        uncertainty: &fit.uncertainty,
        sensitivity: &fit.sensitivity,
        trials: &fit.trials,
        largest_strain,
    };
    md += &parameters(&shared);
    md += "The standard errors come from the recordings' residuals stacked into one vector (one noise level for all); the NRMSE at -10 % and +10 % is the mean over the recordings.\n\n";
    md += "## Plots\n\n";
    md += &convergence(&mut out, &shared)?;
    md += &figure_links(&sections);
    let mut written = out.finish("fit.md", &md)?;
    written.images.extend(images);
    Ok(written)
}

/// Recording `i`'s row of the table in `md`, and its own report in `NN-NAME/recording.md`:
/// the directory's name and what was written there.
fn recording_part(
    md: &mut String,
    dir: &Path,
    i: usize,
    recording: &Recording,
    part: &crate::fit::RecordingFit,
) -> Result<(String, Written), ReportError> {
    let name = format!("{:02}-{}", i + 1, recording_name(&recording.source));
    let _ = writeln!(
        md,
        "| `{}` | {} | {} | {:.5} | {:.5} | {:.3} | [{name}]({name}/recording.md) |",
        recording.source.display(),
        recording.mode.name(),
        recording.samples.len(),
        part.before.nrmse,
        part.after.nrmse,
        1e3 * part.after.rmse_m
    );
    let mut sub = Out::new(&dir.join(&name))?;
    let mut smd = header(recording, "Fit over several recordings, this one");
    let _ = writeln!(
        smd,
        "Fitted together with the other recordings of [the fit](../fit.md). NRMSE {:.5} at the start, {:.5} fitted.\n",
        part.before.nrmse, part.after.nrmse
    );
    smd += &errors_table(&[("start", &part.before), ("fitted", &part.after)]);
    smd += &fitted_sections(&mut sub, recording, &part.start_replay, &part.replay)?;
    let written = sub.finish("recording.md", &smd)?;
    Ok((name, written))
}

/// The section linking each recording's report and figures (`sections`: directory, images).
fn figure_links(sections: &[(String, Vec<std::path::PathBuf>)]) -> String {
    let mut md = String::new();
    md += "## Each recording's figures\n\n";
    for (name, files) in sections {
        let list: Vec<String> = files
            .iter()
            .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
            .map(|n| format!("[{n}]({name}/{n})"))
            .collect();
        let _ = writeln!(md, "- [{name}]({name}/recording.md): {}", list.join(", "));
    }
    md.push('\n');
    md
}

/// What a fit of one recording and one of several share: the parameters and the search.
struct Shared<'a> {
    params: &'a [crate::fit::FitParam],
    start: &'a [f64],
    fitted: &'a [f64],
    at_bound: &'a [bool],
    uncertainty: &'a crate::fit::Uncertainty,
    sensitivity: &'a [crate::fit::Sensitivity],
    trials: &'a [crate::fit::Trial],
    /// Over the fitted runs.
    largest_strain: [f64; 2],
}

/// One recording's residuals at the start and fitted, its replay plots and its marker table.
fn fitted_sections(
    out: &mut Out,
    recording: &Recording,
    start: &crate::replay::Replay,
    fitted: &crate::replay::Replay,
) -> Result<String, ReportError> {
    let markers = plotted_markers(&fitted.residuals);
    let mut chart = residual_chart(
        recording,
        &[("at the start", start), ("fitted", fitted)],
        &markers,
    );
    chart.title = "RMS residual per sample, at the start and fitted".into();
    let mut md = out.chart(
        "residuals_before_after.png",
        &chart,
        "residuals before and after",
    )?;
    md += &replay_plots(out, recording, fitted, "fitted")?;
    md += "## Per marker, fitted\n\n";
    md += &marker_table(recording, fitted);
    md += &volume_line(fitted);
    Ok(md)
}

/// The parameters' section: the uncertainty, the table, the spring limits, the correlations.
fn parameters(sh: &Shared) -> String {
    let mut md = String::new();
    let u = sh.uncertainty;
    let _ = writeln!(
        md,
        "## Parameters\n\nUncertainty: the noise the fitted residuals imply is s = {:.4} mm per observed coordinate ({} coordinates, {} parameters); the standard errors are s^2 (J^T J)^-1 of the residuals' Jacobian J at the fit, and the 95 % interval is +/- 1.96 standard errors. These errors assume independent residuals, which holds for measurement noise; where the model misses systematically (residuals that follow each other from sample to sample, s well above the tracking noise), they are too small, and the spread of fits over repeated recordings is the better measure. Sensitivity: the NRMSE with the parameter 10 % lower and higher; a change is significant when it raises the sum of squared residuals by more than 3.84 s^2 (chi-square, 1 degree of freedom, 95 %).\n",
        1e3 * u.sigma_m,
        u.residuals,
        sh.params.len()
    );
    md += &parameter_table(sh);
    md += &spring_limits(sh);
    md += &correlations(sh);
    md
}

/// The table of the parameters: bounds, start, fit, standard error, sensitivity, verdict.
fn parameter_table(sh: &Shared) -> String {
    let u = sh.uncertainty;
    let mut md = String::new();
    md += "| parameter | bounds | start | fitted | standard error | 95 % interval | NRMSE at -10 % | NRMSE at +10 % | verdict |\n|---|---|---|---|---|---|---|---|---|\n";
    for (i, p) in sh.params.iter().enumerate() {
        let se = u.standard_errors[i];
        let v = sh.fitted[i];
        let interval = if se.is_finite() {
            format!(
                "{} .. {}",
                fmt_value(v - 1.96 * se),
                fmt_value(v + 1.96 * se)
            )
        } else {
            "none (no effect on the residuals)".into()
        };
        let s = &sh.sensitivity[i];
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
            fmt_value(sh.start[i]),
            fmt_value(v),
            fmt_value(se),
            interval,
            nrmse(s.minus),
            nrmse(s.plus),
            s.verdict.label(),
            if sh.at_bound[i] { ", AT A BOUND" } else { "" }
        );
    }
    md.push('\n');
    md
}

/// Whether each fitted spring limit acts: above the largest strain of the fitted run, it never
/// does.
fn spring_limits(sh: &Shared) -> String {
    let mut md = String::new();
    let [stretch, compression] = sh.largest_strain;
    for (i, p) in sh.params.iter().enumerate() {
        let (largest, what) = match p.param.name {
            "tau_s" => (stretch, "stretch"),
            "tau_c" => (compression, "compression"),
            _ => continue,
        };
        if sh.fitted[i] > largest {
            let _ = writeln!(
                md,
                "{} = {} is above the largest spring {what} of the fitted run ({largest:.4}): the limit never acts, and any value above {largest:.4} fits as well.\n",
                p.param.name,
                fmt_value(sh.fitted[i])
            );
        } else {
            let _ = writeln!(
                md,
                "{}: the largest spring {what} of the fitted run is {largest:.4}, so the limit acts.\n",
                p.param.name
            );
        }
    }
    md
}

/// The pairs of estimates correlated beyond |r| = 0.9, if any.
fn correlations(sh: &Shared) -> String {
    let u = sh.uncertainty;
    let mut md = String::new();
    let correlated: Vec<String> = (0..sh.params.len())
        .flat_map(|i| (i + 1..sh.params.len()).map(move |j| (i, j)))
        .filter(|&(i, j)| u.correlations[i][j].abs() > 0.9)
        .map(|(i, j)| {
            format!(
                "{} and {} ({:+.2})",
                sh.params[i].param.name, sh.params[j].param.name, u.correlations[i][j]
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
    md
}

/// The search's convergence chart.
fn convergence(out: &mut Out, sh: &Shared) -> Result<String, ReportError> {
    let mut best = f64::INFINITY;
    let trace: Vec<(f64, f64)> = sh
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
    let tried: Vec<(f64, f64)> = sh
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
    out.chart("convergence.png", &chart, "convergence")
}
