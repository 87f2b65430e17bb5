//! The report of `softgrip diagnose`.

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::{self, Chart, Mark, Series};
use crate::recording::Recording;

use super::figures::{AXES, moving_axes, residual_chart};
use super::out::{Out, ReportError, Written};
use super::tables::{errors_table, fmt_value, header};

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
    verdict(&mut md, d);
    fit_notes(&mut md, d);
    misses(&mut md, d);
    candidates(&mut md, &mut out, d)?;
    if !d.screens.is_empty() {
        md += &screen_table(&d.screens);
    }
    if !d.stages.is_empty() {
        md += "## Time\n\n| stage | seconds |\n|---|---|\n";
        for (stage, seconds) in &d.stages {
            let _ = writeln!(md, "| {stage} | {seconds:.1} |");
        }
        md.push('\n');
    }
    arrows(&mut md, &mut out, d)?;
    let chart = residual_chart(
        recording,
        &[
            ("baseline", &d.baseline.replay),
            ("with the effects", &d.final_fit.replay),
        ],
        &[],
    );
    md += &out.chart("residuals.png", &chart, "residuals per sample")?;
    out.finish("diagnosis.md", &md)
}

/// Fitted parameters as `name = value, ...`.
fn param_list(p: &[(String, f64)]) -> String {
    p.iter()
        .map(|(k, v)| format!("{k} = {}", fmt_value(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The verdict, its evidence and region, and the errors before and after.
fn verdict(md: &mut String, d: &crate::diagnose::Diagnosis) {
    let effects = if d.effects.is_empty() {
        d.verdict()
    } else {
        d.effects.join(" + ")
    };
    let model = if d.model_finding.is_some() {
        " (of the model and samples the finding at the start of the evidence names)"
    } else {
        ""
    };
    let _ = writeln!(md, "## Verdict: {effects}{model}\n\n{}\n", d.evidence);
    if let Some(r) = d.region() {
        let _ = writeln!(md, "{}.\n", r.describe());
    }
    *md += &errors_table(&[
        ("baseline", &d.baseline.errors),
        ("with the effects", &d.final_fit.errors),
    ]);
}

/// The fitted parameters, the noise, the error beyond it, the discretisation, and the
/// parameters at or held to a bound.
fn fit_notes(md: &mut String, d: &crate::diagnose::Diagnosis) {
    let _ = writeln!(
        md,
        "\n- baseline fit: {}\n- with the effects: {}\n- noise, estimated from the data (second differences of the residual along the samples, per marker and axis): {}\n",
        param_list(&d.baseline.params),
        param_list(&d.fitted_params()),
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
}

/// Where the baseline misses: the location's test and its markers.
fn misses(md: &mut String, d: &crate::diagnose::Diagnosis) {
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
        *md += "| marker | RMS residual / noise |\n|---|---|\n";
        for (m, r) in &l.markers {
            let _ = writeln!(md, "| {m} | {r:.1} |");
        }
        md.push('\n');
    }
}

/// The candidates: the first round ranked (`ranking.png`), then every round's in a table.
fn candidates(
    md: &mut String,
    out: &mut Out,
    d: &crate::diagnose::Diagnosis,
) -> Result<(), ReportError> {
    // The candidates, first round, ranked.
    let mut first: Vec<&crate::diagnose::Hypothesis> =
        d.hypotheses.iter().filter(|h| h.round == 0).collect();
    first.sort_by(|a, b| a.score.total_cmp(&b.score));
    if first.is_empty() {
        return Ok(());
    }
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
    *md += "## Candidates\n\n";
    *md += &out.image("ranking.png", &plot::bars_png(&bars)?, "candidates ranked")?;
    *md += "| round | candidate | BIC change | residual removed | Vuong z against the best other effect | NRMSE, fingers included | fitted |\n|---|---|---|---|---|---|---|\n";
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
                    param_list(&f.params)
                );
            }
            Err(e) => {
                let _ = writeln!(md, "| {} | {} | failed | | | | {e} |", h.round + 1, name(h));
            }
        }
    }
    md.push('\n');
    Ok(())
}

/// Residual arrows, before and after, magnified (`arrows.png`), where two axes move.
fn arrows(
    md: &mut String,
    out: &mut Out,
    d: &crate::diagnose::Diagnosis,
) -> Result<(), ReportError> {
    let residuals_before = &d.baseline.replay.residuals;
    let residuals_after = &d.final_fit.replay.residuals;
    let axes = moving_axes(residuals_before);
    if axes.len() < 2 {
        return Ok(());
    }
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
    *md += "## Residuals before and after\n\n";
    *md += &out.chart("arrows.png", &chart, "residual arrows")?;
    Ok(())
}

/// The score tests that decided which candidates were fitted.
fn screen_table(screens: &[(usize, crate::diagnose::Screen)]) -> String {
    let mut md = format!(
        "## The score test\n\nEach round's candidates were first tested at the current fit by the \
         score test (one replay with the equilibria's sensitivities); those whose test is not \
         significant at {} were not fitted: to first order they remove at most the predicted \
         share of the residual, a quarter of what naming an effect asks. A table in place of a \
         bonded base (not nested in it at any friction) and the finger's friction (without a \
         derivative where every contact sticks) are tried at frictions {:?} and their own (T: \
         the likelihood ratio against the model after a Gauss-Newton step from the best). \
         A candidate whose test could not be had is fitted.\n\n\
         | round | candidate | tested at | T | degrees of freedom | p | predicted share | fitted |\n\
         |---|---|---|---|---|---|---|---|\n",
        crate::diagnose::SCREEN_LEVEL,
        crate::diagnose::FRICTION_GRID
    );
    for (round, s) in screens {
        let name = crate::diagnose::effect_label(s.effect, &s.variant);
        if s.dof == 0 {
            let _ = writeln!(md, "| {} | {name} | not tested | | | | | yes |", round + 1);
            continue;
        }
        let at: Vec<String> = s
            .tested
            .iter()
            .map(|(n, v)| format!("{n} {v:.4e}"))
            .collect();
        let _ = writeln!(
            md,
            "| {} | {name} | {} | {:.2} | {} | {:.3} | {:.1} % | {} |",
            round + 1,
            at.join(", "),
            s.statistic,
            s.dof,
            s.p_value,
            100.0 * s.predicted_share,
            match (s.kept, s.in_scan) {
                (true, _) => "yes",
                (false, true) => "in the region scan",
                (false, false) => "no",
            }
        );
    }
    md.push('\n');
    md
}
