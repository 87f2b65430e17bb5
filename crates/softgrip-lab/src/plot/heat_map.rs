//! Heat maps: a grid of values as coloured cells, with a colour bar.

use plotters::element::Rectangle;
use plotters::style::{Color, RGBColor};

use super::axes::{
    frame, label_on_row, titles, x_tick_label, x_tick_mark, y_tick_label, y_tick_mark,
};
use super::canvas::{Area, draw_err, fill_rect, polyline, render};
use super::error::PlotError;
use super::layout::{
    Layout, axis_inv, axis_t, bottom_room, check_area, check_size, round_px, top_margin,
    y_label_room,
};
use super::style::{AXIS, CAP, DESCENT, INK, LABEL_PX, NO_VALUE, PAD, TICK_LEN, TICK_PX, WHITE};
use super::text::{Align, ensure_font, max_width, text_up, text_width};
use super::ticks::{
    Tick, degenerate, format_log_value, format_number, linear_ticks, log_wants_sci, wants_sci,
};
use super::types::HeatMap;
use plotters::backend::DrawingBackend;

/// Cell edges for ascending centres: midpoints between neighbours (geometric
/// on a log axis), the outer edges half a spacing beyond the end centres.
fn cell_edges(c: &[f64], log: bool) -> Vec<f64> {
    let t: Vec<f64> = c.iter().map(|&v| axis_t(v, log)).collect();
    let n = t.len();
    let mut e = Vec::with_capacity(n + 1);
    if n == 1 {
        let d = if log {
            0.5
        } else if t[0] != 0.0 {
            t[0].abs() * 0.1
        } else {
            0.5
        };
        e.push(t[0] - d);
        e.push(t[0] + d);
    } else {
        e.push(t[0] - (t[1] - t[0]) / 2.0);
        for k in 0..n - 1 {
            e.push((t[k] + t[k + 1]) / 2.0);
        }
        e.push(t[n - 1] + (t[n - 1] - t[n - 2]) / 2.0);
    }
    e.into_iter().map(|v| axis_inv(v, log)).collect()
}

/// Checks a heat map's shape and axes; returns the finite value range.
fn heat_map_checks(h: &HeatMap) -> Result<(f64, f64), PlotError> {
    check_size(h.size)?;
    let shape = |detail: String| PlotError::Shape {
        title: h.title.clone(),
        detail,
    };
    for (name, c, log) in [("x", &h.x, h.x_log), ("y", &h.y, h.y_log)] {
        if c.iter().any(|v| !v.is_finite()) {
            return Err(shape(format!("the {name} cell centres must be finite")));
        }
        if c.windows(2).any(|w| w[1] <= w[0]) {
            return Err(shape(format!("the {name} cell centres must be ascending")));
        }
        if log && let Some(&value) = c.iter().find(|v| **v <= 0.0) {
            return Err(PlotError::LogAxis {
                title: h.title.clone(),
                axis: name,
                value,
            });
        }
    }
    if h.values.len() != h.x.len() * h.y.len() {
        return Err(shape(format!(
            "{} values for {} x {} cells",
            h.values.len(),
            h.x.len(),
            h.y.len()
        )));
    }
    let finite = h.values.iter().copied().filter(|v| v.is_finite());
    let range = finite.fold(None, |r: Option<(f64, f64)>, v| {
        Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
    });
    let Some((lo, hi)) = range else {
        return Err(PlotError::NothingToPlot {
            title: h.title.clone(),
        });
    };
    if degenerate(lo, hi) {
        let d = if lo != 0.0 { lo.abs() * 0.1 } else { 1.0 };
        return Ok((lo - d, hi + d));
    }
    Ok((lo, hi))
}

/// Labels for cell centres; resolution 1/10 of the closest spacing (3
/// significant digits on a log axis).
fn centre_labels(c: &[f64], log: bool) -> Vec<String> {
    if log {
        let sci = log_wants_sci(c);
        return c.iter().map(|&v| format_log_value(v, sci)).collect();
    }
    let gap = c
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let largest = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let res = if gap.is_finite() {
        gap / 10.0
    } else {
        largest / 100.0
    };
    c.iter()
        .map(|&v| format_number(v, res, wants_sci(largest)))
        .collect()
}

/// Heat-map layout plus what it needs to draw.
struct HeatFrame {
    layout: Layout,
    x_labels: Vec<String>,
    y_labels: Vec<String>,
    values: (f64, f64),
    value_ticks: Vec<Tick>,
    cbar_left: i32,
}

const CBAR_W: i32 = 16;
const CBAR_GAP: i32 = 14;

/// The plotting area of a heat map: the cells span it edge to edge, and the
/// mapping is the one [`heat_map_png`] draws with.
pub fn heat_map_layout(h: &HeatMap) -> Result<Layout, PlotError> {
    heat_frame(h).map(|f| f.layout)
}

fn heat_frame(h: &HeatMap) -> Result<HeatFrame, PlotError> {
    let values = heat_map_checks(h)?;
    ensure_font()?;
    let (w, ht) = (h.size.0 as i32, h.size.1 as i32);
    let x_labels = centre_labels(&h.x, h.x_log);
    let y_labels = centre_labels(&h.y, h.y_log);
    let top = top_margin(&h.title);
    let bottom = ht - bottom_room(&h.x_label);
    let y_w = max_width(y_labels.iter().map(|s| s.as_str()), TICK_PX)?;
    let left = y_label_room(&h.y_label) + y_w + TICK_LEN + 6;
    let value_ticks = linear_ticks(values, bottom - top, 50, false)?;
    let v_w = max_width(value_ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
    let value_room = if h.value_label.is_empty() {
        0
    } else {
        round_px(LABEL_PX * (CAP + DESCENT)) + 8
    };
    let cbar_left = w - PAD - value_room - v_w - TICK_LEN - 4 - CBAR_W;
    let right = cbar_left - CBAR_GAP;
    let xe = cell_edges(&h.x, h.x_log);
    let ye = cell_edges(&h.y, h.y_log);
    let (Some(&x0), Some(&x1), Some(&y0), Some(&y1)) =
        (xe.first(), xe.last(), ye.first(), ye.last())
    else {
        return Err(PlotError::NothingToPlot {
            title: h.title.clone(),
        });
    };
    let layout = Layout {
        left,
        top,
        right,
        bottom,
        x_range: (x0, x1),
        y_range: (y0, y1),
        x_log: h.x_log,
        y_log: h.y_log,
    };
    check_area(&layout, h.size)?;
    Ok(HeatFrame {
        layout,
        x_labels,
        y_labels,
        values,
        value_ticks,
        cbar_left,
    })
}

/// The 8-bit colour of colour-map position `t` (0..1, viridis).
fn heat_color(t: f64) -> RGBColor {
    let c = softgrip_core::fields::colormap(t, false);
    let b = |v: f32| (f64::from(v) * 255.0).round().clamp(0.0, 255.0) as u8;
    RGBColor(b(c[0]), b(c[1]), b(c[2]))
}

/// Draws `h` as a PNG: coloured cells, a colour bar with `value_label`, tick
/// labels at cell centres (thinned so they do not overlap) and the mark.
pub fn heat_map_png(h: &HeatMap) -> Result<Vec<u8>, PlotError> {
    let f = heat_frame(h)?;
    let l = f.layout;
    let xe = cell_edges(&h.x, h.x_log);
    let ye = cell_edges(&h.y, h.y_log);
    let (lo, hi) = f.values;
    render(h.size, |area| {
        for (j, ys) in ye.windows(2).enumerate() {
            for (i, xs) in xe.windows(2).enumerate() {
                let v = h.values.get(j * h.x.len() + i).copied().unwrap_or(f64::NAN);
                let color = if v.is_finite() {
                    heat_color((v - lo) / (hi - lo))
                } else {
                    NO_VALUE
                };
                if let (Some(a), Some(b)) = (l.pixel(xs[0], ys[1]), l.pixel(xs[1], ys[0])) {
                    fill_rect(area, a, b, color)?;
                }
            }
        }
        frame(area, &l)?;
        // Tick labels at cell centres, skipping any that would overlap the previous one.
        let mut last_right = i32::MIN;
        for (x, label) in h.x.iter().zip(&f.x_labels) {
            let Some((px, _)) = l.pixel(*x, l.y_range.0) else {
                continue;
            };
            x_tick_mark(area, &l, px)?;
            let lw = text_width(label, TICK_PX)?;
            if px - lw / 2 >= last_right + 8 {
                x_tick_label(area, &l, px, label)?;
                last_right = px + lw / 2;
            }
        }
        let mut last_top = i32::MAX;
        let row = round_px(TICK_PX) + 4;
        for (y, label) in h.y.iter().zip(&f.y_labels) {
            let Some((_, py)) = l.pixel(l.x_range.0, *y) else {
                continue;
            };
            y_tick_mark(area, &l, py)?;
            if py + row / 2 <= last_top {
                y_tick_label(area, &l, py, label)?;
                last_top = py - row / 2;
            }
        }
        if let Some((mx, my)) = h.mark
            && let Some(p) = l.pixel(mx, my)
            && (l.left..=l.right).contains(&p.0)
            && (l.top..=l.bottom).contains(&p.1)
        {
            let arm = 7;
            for (color, width) in [(WHITE, 5), (INK, 2)] {
                polyline(
                    area,
                    vec![(p.0 - arm, p.1 - arm), (p.0 + arm, p.1 + arm)],
                    color,
                    width,
                )?;
                polyline(
                    area,
                    vec![(p.0 - arm, p.1 + arm), (p.0 + arm, p.1 - arm)],
                    color,
                    width,
                )?;
            }
        }
        color_bar(area, &f, h)?;
        titles(area, &l, h.size, [&h.title, &h.x_label, &h.y_label])
    })
}

/// The colour bar right of the cells: colour ramp, value ticks and label.
fn color_bar<DB: DrawingBackend>(
    area: &Area<DB>,
    f: &HeatFrame,
    h: &HeatMap,
) -> Result<(), PlotError> {
    let l = &f.layout;
    let (x0, x1) = (f.cbar_left, f.cbar_left + CBAR_W);
    let span = f64::from((l.bottom - l.top).max(1));
    for py in l.top..=l.bottom {
        let t = f64::from(l.bottom - py) / span;
        fill_rect(area, (x0, py), (x1, py + 1), heat_color(t))?;
    }
    area.draw(&Rectangle::new(
        [(x0, l.top), (x1, l.bottom)],
        AXIS.stroke_width(1),
    ))
    .map_err(draw_err)?;
    let (lo, hi) = f.values;
    for t in &f.value_ticks {
        let py = round_px(f64::from(l.bottom) - (t.value - lo) / (hi - lo) * span);
        polyline(area, vec![(x1, py), (x1 + TICK_LEN, py)], AXIS, 1)?;
        label_on_row(area, &t.label, x1 + TICK_LEN + 3, py, Align::Left)?;
    }
    let baseline_x = h.size.0 as i32 - PAD - round_px(LABEL_PX * DESCENT);
    text_up(
        area,
        &h.value_label,
        LABEL_PX,
        INK,
        baseline_x,
        (l.top + l.bottom) / 2,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_surround_centres() {
        assert_eq!(
            cell_edges(&[1.0, 2.0, 3.0], false),
            vec![0.5, 1.5, 2.5, 3.5]
        );
        let e = cell_edges(&[1.0, 100.0], true);
        assert!((e[1] - 10.0).abs() < 1e-9 && (e[0] - 0.1).abs() < 1e-12);
    }
}
