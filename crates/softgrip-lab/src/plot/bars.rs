//! Bar charts: one bar per label, from zero to its value.

use super::axes::{axes, frame, titles, x_tick_label};
use super::canvas::{fill_rect, polyline, render, rgb};
use super::error::PlotError;
use super::layout::{
    Layout, bottom_room, check_size, round_px, settle_edges, top_margin, y_label_room,
};
use super::style::{AXIS, CAP, INK, PAD, TICK_LEN, TICK_PX, palette};
use super::text::{Align, ensure_font, fit_text, max_width, text, text_up, text_width};
use super::ticks::{Tick, degenerate, format_number, linear_ticks, wants_sci};
use super::types::Bars;

/// Bar chart layout plus what it needs to draw.
struct BarFrame {
    layout: Layout,
    y_ticks: Vec<Tick>,
    labels: Vec<String>,
    rotated: bool,
}

/// The plotting area of a bar chart: bar `k` is centred on x = k (the x
/// range is -0.5 .. n - 0.5) and rises from y = 0; [`bars_png`] draws with
/// this mapping.
pub fn bars_layout(b: &Bars) -> Result<Layout, PlotError> {
    bar_frame(b).map(|f| f.layout)
}

fn bar_frame(b: &Bars) -> Result<BarFrame, PlotError> {
    check_size(b.size)?;
    if b.labels.len() != b.values.len() {
        return Err(PlotError::Shape {
            title: b.title.clone(),
            detail: format!("{} labels for {} bars", b.labels.len(), b.values.len()),
        });
    }
    let finite: Vec<f64> = b.values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return Err(PlotError::NothingToPlot {
            title: b.title.clone(),
        });
    }
    ensure_font()?;
    let lo = finite.iter().fold(0.0f64, |m, &v| m.min(v));
    let hi = finite.iter().fold(0.0f64, |m, &v| m.max(v));
    let (lo, hi) = if degenerate(lo, hi) {
        (0.0, 1.0)
    } else {
        // Room above (below) the bars for their value labels.
        let m = 0.12 * (hi - lo);
        (
            if lo < 0.0 { lo - m } else { lo },
            if hi > 0.0 { hi + m } else { hi },
        )
    };
    let (w, h) = (b.size.0 as i32, b.size.1 as i32);
    let n = b.values.len() as i32;
    let top = top_margin(&b.title);
    let label_room = y_label_room(&b.y_label);
    // Labels lie flat if they fit their slot, else read upwards, cut to a third of the height.
    let mut labels = b.labels.clone();
    let widest = max_width(labels.iter().map(|s| s.as_str()), TICK_PX)?;
    let rough_slot = (w - label_room - 60) / n.max(1);
    let rotated = widest + 6 > rough_slot;
    let bottom = if rotated {
        let max_px = h / 3;
        for s in &mut labels {
            *s = fit_text(s, TICK_PX, max_px)?;
        }
        let widest = max_width(labels.iter().map(|s| s.as_str()), TICK_PX)?;
        h - PAD - widest - TICK_LEN - 4
    } else {
        h - bottom_room("")
    };
    let edges = (label_room + 40, w - 20);
    let (layout, y_ticks) = settle_edges(&b.title, b.size, edges, 3, |left, right| {
        let y_ticks = linear_ticks((lo, hi), bottom - top, 50, false)?;
        let y_w = max_width(y_ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
        let new_left = label_room + y_w + TICK_LEN + 6;
        let layout = Layout {
            left,
            top,
            right,
            bottom,
            x_range: (-0.5, f64::from(n) - 0.5),
            y_range: (lo, hi),
            x_log: false,
            y_log: false,
        };
        Ok((layout, y_ticks, (new_left, right)))
    })?;
    Ok(BarFrame {
        layout,
        y_ticks,
        labels,
        rotated,
    })
}

/// Draws `b` as a PNG: bars from zero with their values written at their
/// ends, labels under them (rotated when long), and a y grid.
pub fn bars_png(b: &Bars) -> Result<Vec<u8>, PlotError> {
    let f = bar_frame(b)?;
    let l = f.layout;
    let finite_max = b
        .values
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let sci = wants_sci(finite_max);
    render(b.size, |area| {
        axes(area, &l, &[], &f.y_ticks, true)?;
        let slot = f64::from(l.right - l.left) / b.values.len().max(1) as f64;
        let half = (0.35 * slot).min(40.0) / slot;
        for (k, &v) in b.values.iter().enumerate() {
            let x = k as f64;
            let Some((cx, _)) = l.pixel(x, 0.0) else {
                continue;
            };
            if v.is_finite() {
                let color = rgb(b.colors.get(k).copied().unwrap_or_else(|| palette(k)));
                if let (Some(p), Some(q)) =
                    (l.pixel(x - half, v.max(0.0)), l.pixel(x + half, v.min(0.0)))
                {
                    fill_rect(area, p, (q.0, q.1.max(p.1 + 1)), color)?;
                }
                let label = format_number(v, finite_max / 1000.0, sci);
                if let Some((_, py)) = l.pixel(x, v) {
                    let baseline = if v >= 0.0 {
                        py - 4
                    } else {
                        py + 4 + round_px(TICK_PX * CAP)
                    };
                    text(area, &label, TICK_PX, INK, cx, baseline, Align::Center)?;
                }
            }
            let label = f.labels.get(k).map(String::as_str).unwrap_or("");
            if f.rotated {
                let w = text_width(label, TICK_PX)?;
                let baseline_x = cx + round_px(TICK_PX * CAP / 2.0);
                text_up(
                    area,
                    label,
                    TICK_PX,
                    INK,
                    baseline_x,
                    l.bottom + TICK_LEN + 4 + w / 2,
                )?;
            } else {
                x_tick_label(area, &l, cx, label)?;
            }
        }
        if let Some((_, zero)) = l.pixel(0.0, 0.0) {
            polyline(area, vec![(l.left, zero), (l.right, zero)], AXIS, 1)?;
        }
        frame(area, &l)?;
        titles(area, &l, b.size, [&b.title, "", &b.y_label])
    })
}
