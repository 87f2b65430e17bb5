//! The report of `softgrip grasp window`: the window, the curves it was found on, the dynamic
//! confirmations and the object at the upper bound (`.vtu`, coloured by the damage measure,
//! its most loaded element marked).

use std::fmt::Write as _;
use std::path::Path;

use softgrip_core::output::vtu::{Encoding, to_vtu_with};
use softgrip_core::step::Simulation;

use crate::grasp::plan::Plan;
use crate::grasp::uncertainty::{self, BoundErrors};
use crate::grasp::window::{Confirmation, Measure, Most, Window};
use crate::plot::{Chart, Mark, Series, palette};

use super::out::{Out, ReportError, Written, write_file};

/// A measure's value in its display unit (kPa for stresses, a plain number for strain).
pub fn shown(measure: Measure, v: f64) -> String {
    if measure.unit().is_empty() {
        format!("{v:.4}")
    } else {
        format!("{:.2} kPa", v / 1e3)
    }
}

/// The window's chart: the slip margin and the damage measure over its limit against squeeze,
/// the window shaded.
pub fn window_chart(window: &Window) -> Chart {
    let o = &window.options;
    let x_max = window.samples.last().map_or(1.0, |s| s.squeeze);
    let mut x_bands = Vec::new();
    if window.exists() {
        let top = window.most_squeeze().unwrap_or(x_max);
        x_bands.push((window.least_squeeze(), top, [214, 239, 214]));
    }
    let line = |label: &str, y: f64| Series {
        label: label.into(),
        points: vec![(0.0, y), (x_max, y)],
        mark: Mark::Dashed,
        color: [90, 90, 90],
    };
    let y_top = window
        .samples
        .iter()
        .map(|s| s.peak.value / o.damage.limit)
        .fold(1.0, f64::max);
    let bound = |label: &str, x: f64, color| Series {
        label: label.into(),
        points: vec![(x, -0.05), (x, y_top)],
        mark: Mark::Dashed,
        color,
    };
    Chart {
        title: "The grasp window: held above the least squeeze, undamaged below the most".into(),
        x_label: "squeeze per finger (N)".into(),
        y_label: "slip margin; damage / limit".into(),
        series: vec![
            Series {
                label: "slip margin 1 - load / (sum mu N)".into(),
                points: window
                    .samples
                    .iter()
                    .map(|s| (s.squeeze, s.margin.max(-1.0)))
                    .collect(),
                mark: Mark::LineAndPoints,
                color: palette(0),
            },
            Series {
                label: format!("peak {} / limit", o.damage.measure.describe()),
                points: window
                    .samples
                    .iter()
                    .map(|s| (s.squeeze, s.peak.value / o.damage.limit))
                    .collect(),
                mark: Mark::LineAndPoints,
                color: palette(1),
            },
            line("", 0.0),
            line("", 1.0),
            bound("least squeeze", window.least_squeeze(), palette(0)),
            bound(
                "most before damage",
                window.most_squeeze().unwrap_or(f64::NAN),
                palette(1),
            ),
        ],
        x_bands,
        ..Chart::default()
    }
}

/// Writes `window.md`, `window.png` (and `.svg`) and, given the state held at the upper bound,
/// `upper_bound.vtu` (cell data `damage` and `peak`, 1 at the most loaded element) into `dir`.
pub fn grasp_window(
    dir: &Path,
    scene_name: &str,
    window: &Window,
    plan: &Plan,
    confirmations: &[Confirmation],
    errors: Option<&BoundErrors>,
    at_most: Option<&Simulation>,
) -> Result<Written, ReportError> {
    let mut out = Out::new(dir)?;
    let o = &window.options;
    let m = o.damage.measure;
    let mut md = format!("# Grasp window: {scene_name}\n\n");
    let most = match window.most {
        Most::Found { below, above } => format!(
            "{below:.4} N ({} reaches its limit at {above:.4} N)",
            m.describe()
        ),
        Most::NotReached(f) => format!("not reached up to {f:.4} N"),
    };
    let _ = writeln!(
        md,
        "| | |\n|---|---|\n| least squeeze that holds | {:.4} N (dropped at {:.4} N); rigid force balance {:.4} N |\n| most before damage | {most} |\n| window | {} |\n| load carried | {:.4} N: the mass times the length of g - a, a = {:.3} m/s^2 up ({}), shake {:.3} m/s^2 |\n| damage limit | {} {} ({}) |\n| slip tolerance | {:.3} mm (the contacts' mean slide as the object takes its load) |\n",
        window.least.held,
        window.least.dropped,
        window.force_balance,
        if window.exists() {
            format!(
                "{:.4} .. {} N",
                window.least.held,
                window
                    .most_squeeze()
                    .map_or("(no limit reached)".into(), |f| format!("{f:.4}"))
            )
        } else {
            "none: the object cannot be held undamaged".into()
        },
        window.load,
        o.profile.acceleration,
        plan.acceleration_from,
        o.profile.shake,
        m.describe(),
        shown(m, o.damage.limit),
        plan.limit_from,
        o.profile.slip_tolerance * 1e3,
    );
    if let Some(s) = window.at_least().filter(|_| !window.exists()) {
        let _ = writeln!(
            md,
            "No window: at the least squeeze that holds the {} is already {} (limit {}), at ({:.1}, {:.1}, {:.1}) mm.\n",
            m.describe(),
            shown(m, s.peak.value),
            shown(m, o.damage.limit),
            s.peak.at.x * 1e3,
            s.peak.at.y * 1e3,
            s.peak.at.z * 1e3
        );
    }
    if let Some(e) = errors {
        md += &uncertainty_table(window, e);
    }
    md += &out.chart(
        "window.png",
        &window_chart(window),
        "slip margin and damage against squeeze",
    )?;
    md += &confirmations_table(m, confirmations);
    md += &squeezes_table(window);
    if let Some(sim) = at_most {
        md += &upper_bound_vtu(dir, m, sim)?;
    }
    out.finish("window.md", &md)
}

/// The bounds with their standard errors from the fitted material, and each parameter's share.
fn uncertainty_table(window: &Window, e: &BoundErrors) -> String {
    let range = uncertainty::range_text;
    let mut md = String::from(
        "## With the fitted material's uncertainty

| bound | value, standard error, 95 % range |
|---|---|
",
    );
    let _ = writeln!(
        md,
        "| least squeeze | {} |",
        range(window.least_squeeze(), e.least)
    );
    if let (Some(m), Some(se)) = (window.most_squeeze(), e.most) {
        let _ = writeln!(md, "| most before damage | {} |", range(m, se));
    }
    let _ = writeln!(
        md,
        "\n{}\n\nFrom the fit's standard errors, taken as independent: each bound's derivative by a central difference at the parameter +/- its standard error (bounds found to {:.1} %):\n\n| parameter | d least / dp | d most / dp |\n|---|---|---|",
        if e.overlaps(window) {
            "**The two ends overlap within their 95 % ranges: the window may be empty.**"
        } else {
            "The two ends' 95 % ranges do not overlap."
        },
        100.0 * e.tolerance
    );
    for (name, l, m) in &e.derivatives {
        let _ = writeln!(
            md,
            "| `{name}` | {l:.4e} | {} |",
            m.map_or("-".to_string(), |m| format!("{m:.4e}"))
        );
    }
    md + "\n"
}

/// The dynamic lifts' table (empty without any).
fn confirmations_table(m: Measure, confirmations: &[Confirmation]) -> String {
    let mut md = String::new();
    if confirmations.is_empty() {
        return md;
    }
    md += "## Confirmed by dynamic lifts\n\n| squeeze (N) | held | slid over the hold (mm) | peak over the lift |\n|---|---|---|---|\n";
    for c in confirmations {
        let _ = writeln!(
            md,
            "| {:.4} | {} | {:.4} | {} |",
            c.squeeze,
            if c.run.held { "yes" } else { "no" },
            c.run.hold_slip * 1e3,
            shown(m, c.peak.value)
        );
    }
    md += "\n";
    md
}

/// Every squeeze tried.
fn squeezes_table(window: &Window) -> String {
    let m = window.options.damage.measure;
    let mut md = String::new();
    md += "## Squeezes tried\n\n| squeeze (N) | held | slip (mm) | slip margin | peak | where (mm) |\n|---|---|---|---|---|---|\n";
    for s in &window.samples {
        let _ = writeln!(
            md,
            "| {:.4} | {} | {} | {:.3} | {} | ({:.1}, {:.1}, {:.1}) |",
            s.squeeze,
            if s.held { "yes" } else { "no" },
            if s.slip.is_finite() {
                format!("{:.4}", s.slip * 1e3)
            } else {
                "fell".into()
            },
            s.margin,
            shown(m, s.peak.value),
            s.peak.at.x * 1e3,
            s.peak.at.y * 1e3,
            s.peak.at.z * 1e3
        );
    }
    md
}

/// `upper_bound.vtu` in `dir`: the object held at the upper bound with cell data `damage` and
/// `peak`; the Markdown that says so.
fn upper_bound_vtu(dir: &Path, m: Measure, sim: &Simulation) -> Result<String, ReportError> {
    let mut md = String::new();
    let values = crate::grasp::window::values(m, sim);
    let peak = crate::grasp::window::peak(m, sim);
    let cells: Vec<f64> = if m == Measure::Pressure {
        // Per node: each element takes its nodes' largest.
        sim.model
            .tets
            .iter()
            .map(|t| t.iter().map(|&i| values[i as usize]).fold(0.0, f64::max))
            .collect()
    } else {
        values
    };
    let marked: Vec<f64> = if m == Measure::Pressure {
        sim.model
            .tets
            .iter()
            .map(|t| f64::from(u8::from(t.contains(&(peak.index as u32)))))
            .collect()
    } else {
        (0..sim.model.tets.len())
            .map(|e| f64::from(u8::from(e == peak.index)))
            .collect()
    };
    let text = to_vtu_with(
        &sim.model,
        &sim.state,
        Encoding::Binary,
        &[("damage", &cells), ("peak", &marked)],
    );
    write_file(&dir.join("upper_bound.vtu"), &text)?;
    let _ = writeln!(
        md,
        "\n`upper_bound.vtu`: the object held at the upper bound, cell data `damage` ({}) and `peak` (1 at the most loaded element{}).",
        m.describe(),
        if m == Measure::Pressure {
            "s, those of the node where the pressure peaks"
        } else {
            ""
        }
    );
    Ok(md)
}
