//! The report of `softgrip fit`.

use std::fmt::Write as _;
use std::path::Path;

use crate::fit::Fit;
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
    md += &out.chart("convergence.png", &chart, "convergence")?;
    let markers = plotted_markers(&fit.replay.residuals);
    let mut chart = residual_chart(
        recording,
        &[("at the start", &fit.start_replay), ("fitted", &fit.replay)],
        &markers,
    );
    chart.title = "RMS residual per sample, at the start and fitted".into();
    md += &out.chart(
        "residuals_before_after.png",
        &chart,
        "residuals before and after",
    )?;
    md += &replay_plots(&mut out, recording, &fit.replay, "fitted")?;
    md += "## Per marker, fitted\n\n";
    md += &marker_table(recording, &fit.replay);
    md += &volume_line(&fit.replay);
    out.finish("fit.md", &md)
}
