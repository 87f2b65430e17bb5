//! x-y charts: series as lines, dots or dashes, arrows, and a legend.

use plotters::element::{Polygon, Rectangle};
use plotters::style::{Color, RGBColor};

use super::axes::{axes, frame, label_on_row, titles};
use super::canvas::{Area, dot, draw_err, polyline, render, rgb};
use super::error::PlotError;
use super::layout::{
    Layout, bottom_room, check_size, equalize, round_px, settle_edges, top_margin, y_label_room,
};
use super::style::{PAD, TICK_LEN, TICK_PX, WHITE};
use super::text::{Align, ensure_font, max_width, text_width};
use super::ticks::{Tick, axis_ticks, padded_range};
use super::types::{Chart, Mark, Series};
use plotters::backend::DrawingBackend;

/// A chart's layout with its ticks.
struct ChartFrame {
    layout: Layout,
    x_ticks: Vec<Tick>,
    y_ticks: Vec<Tick>,
}

/// The plotting area of a chart: its pixel rectangle and the data-to-pixel
/// mapping [`chart_png`] draws with.
pub fn chart_layout(c: &Chart) -> Result<Layout, PlotError> {
    chart_frame(c).map(|f| f.layout)
}

/// Checks one coordinate for a log axis; `Ok(false)` skips a non-finite one.
fn usable(v: f64, log: bool, axis: &'static str, title: &str) -> Result<bool, PlotError> {
    if !v.is_finite() {
        return Ok(false);
    }
    if log && v <= 0.0 {
        return Err(PlotError::LogAxis {
            title: title.to_string(),
            axis,
            value: v,
        });
    }
    Ok(true)
}

fn chart_frame(c: &Chart) -> Result<ChartFrame, PlotError> {
    check_size(c.size)?;
    ensure_font()?;
    let mut x_span: Option<(f64, f64)> = None;
    let mut y_span: Option<(f64, f64)> = None;
    let arrow_ends = c.arrows.iter().flat_map(|(p, q, _)| [*p, *q]);
    let series_points = c.series.iter().flat_map(|s| s.points.iter().copied());
    for (x, y) in series_points.chain(arrow_ends) {
        // Check both before skipping, so a log error is never hidden by a NaN partner.
        let ux = usable(x, c.x_log, "x", &c.title)?;
        let uy = usable(y, c.y_log, "y", &c.title)?;
        if ux && uy {
            x_span = Some(x_span.map_or((x, x), |(a, b)| (a.min(x), b.max(x))));
            y_span = Some(y_span.map_or((y, y), |(a, b)| (a.min(y), b.max(y))));
        }
    }
    let (Some(xs), Some(ys)) = (x_span, y_span) else {
        return Err(PlotError::NothingToPlot {
            title: c.title.clone(),
        });
    };
    let base_x = padded_range(xs.0, xs.1, c.x_log);
    let base_y = padded_range(ys.0, ys.1, c.y_log);
    let (w, h) = (c.size.0 as i32, c.size.1 as i32);
    let top = top_margin(&c.title);
    let bottom = h - bottom_room(&c.x_label);
    let label_room = y_label_room(&c.y_label);
    let edges = (label_room + 40, w - 20);
    let (layout, (x_ticks, y_ticks)) = settle_edges(&c.title, c.size, edges, 4, |left, right| {
        let (xr, yr) = if c.equal_aspect {
            equalize(base_x, base_y, right - left, bottom - top, c.x_log, c.y_log)
        } else {
            (base_x, base_y)
        };
        let x_ticks = axis_ticks(xr, c.x_log, right - left, true)?;
        let y_ticks = axis_ticks(yr, c.y_log, bottom - top, false)?;
        let y_w = max_width(y_ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
        let last_w = match x_ticks.last() {
            Some(t) => text_width(&t.label, TICK_PX)?,
            None => 0,
        };
        let new_left = label_room + y_w + TICK_LEN + 6;
        let new_right = w - (last_w / 2 + PAD).max(20);
        let layout = Layout {
            left,
            top,
            right,
            bottom,
            x_range: xr,
            y_range: yr,
            x_log: c.x_log,
            y_log: c.y_log,
        };
        Ok((layout, (x_ticks, y_ticks), (new_left, new_right)))
    })?;
    Ok(ChartFrame {
        layout,
        x_ticks,
        y_ticks,
    })
}

/// Splits a series into runs of placeable points, in pixels (sub-pixel).
fn pixel_runs(l: &Layout, points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut run = Vec::new();
    for &(x, y) in points {
        match l.map(x, y) {
            Some(p) => run.push(p),
            None => {
                if !run.is_empty() {
                    runs.push(std::mem::take(&mut run));
                }
            }
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

fn to_px(p: (f64, f64)) -> (i32, i32) {
    (round_px(p.0), round_px(p.1))
}

const LINE_W: u32 = 2;
const DOT_R: i32 = 3;
const DASH_ON: f64 = 8.0;
const DASH_OFF: f64 = 5.0;

/// A dashed polyline: 8 px dashes, 5 px gaps, the pattern running on across vertices.
fn dashed<DB: DrawingBackend>(
    area: &Area<DB>,
    run: &[(f64, f64)],
    color: RGBColor,
) -> Result<(), PlotError> {
    let mut on = true;
    let mut left = DASH_ON;
    let mut current: Vec<(i32, i32)> = Vec::new();
    for pair in run.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let mut s = 0.0;
        if on && current.is_empty() {
            current.push(to_px(a));
        }
        while len - s > left {
            s += left;
            let p = (a.0 + (b.0 - a.0) * s / len, a.1 + (b.1 - a.1) * s / len);
            if on {
                current.push(to_px(p));
                polyline(area, std::mem::take(&mut current), color, LINE_W)?;
                left = DASH_OFF;
            } else {
                current.push(to_px(p));
                left = DASH_ON;
            }
            on = !on;
        }
        left -= len - s;
        if on {
            current.push(to_px(b));
        }
    }
    if on {
        polyline(area, current, color, LINE_W)?;
    }
    Ok(())
}

/// Draws a run of pixel points with a series' mark.
fn draw_run<DB: DrawingBackend>(
    area: &Area<DB>,
    run: &[(f64, f64)],
    mark: Mark,
    color: RGBColor,
) -> Result<(), PlotError> {
    let line = matches!(mark, Mark::Line | Mark::LineAndPoints);
    let dots = matches!(mark, Mark::Points | Mark::LineAndPoints);
    if run.len() == 1 && !dots {
        // A lone point between gaps would vanish as a line: show it as a dot.
        return dot(area, to_px(run[0]), DOT_R - 1, color);
    }
    if line {
        polyline(area, run.iter().map(|&p| to_px(p)).collect(), color, LINE_W)?;
    }
    if mark == Mark::Dashed {
        dashed(area, run, color)?;
    }
    if dots {
        for &p in run {
            dot(area, to_px(p), DOT_R, color)?;
        }
    }
    Ok(())
}

/// An arrow from `a` to `b` in pixels: a 1 px shaft and a filled head.
fn arrow<DB: DrawingBackend>(
    area: &Area<DB>,
    a: (f64, f64),
    b: (f64, f64),
    color: RGBColor,
) -> Result<(), PlotError> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt();
    if len < 0.5 {
        return dot(area, to_px(b), 2, color);
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = 9.0f64.min(len * 0.6);
    let half = head * 0.4;
    let base = (b.0 - ux * head, b.1 - uy * head);
    polyline(area, vec![to_px(a), to_px(base)], color, 1)?;
    let pts = vec![
        to_px(b),
        to_px((base.0 - uy * half, base.1 + ux * half)),
        to_px((base.0 + uy * half, base.1 - ux * half)),
    ];
    area.draw(&Polygon::new(pts, color.filled()))
        .map_err(draw_err)
}

/// Samples of everything drawn in the plot area, in pixels, to place the
/// legend where it covers the least.
fn coverage_samples(c: &Chart, l: &Layout) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for s in &c.series {
        for run in pixel_runs(l, &s.points) {
            out.extend(run.iter().copied());
            if s.mark != Mark::Points {
                for pair in run.windows(2) {
                    let (a, b) = (pair[0], pair[1]);
                    let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                    let n = (len / 4.0).ceil().min(2000.0) as usize;
                    for k in 1..n {
                        let f = k as f64 / n as f64;
                        out.push((a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f));
                    }
                }
            }
        }
    }
    for &(p, q, _) in &c.arrows {
        if let (Some(a), Some(b)) = (l.map(p.0, p.1), l.map(q.0, q.1)) {
            for k in 0..=8 {
                let f = f64::from(k) / 8.0;
                out.push((a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f));
            }
        }
    }
    out
}

/// The legend: one row per labelled series, in the corner of the plot area
/// that covers the fewest drawn points.
fn legend<DB: DrawingBackend>(area: &Area<DB>, c: &Chart, l: &Layout) -> Result<(), PlotError> {
    let entries: Vec<&Series> = c.series.iter().filter(|s| !s.label.is_empty()).collect();
    if entries.is_empty() {
        return Ok(());
    }
    const SAMPLE: i32 = 24;
    const ROW: i32 = 18;
    // Over 7 entries, in columns of at most 7 rows: a tall legend covered the data.
    const ROWS: usize = 7;
    let columns = entries.len().div_ceil(ROWS);
    let rows = entries.len().div_ceil(columns) as i32;
    let text_w = max_width(entries.iter().map(|s| s.label.as_str()), TICK_PX)?;
    let column_w = 6 + SAMPLE + 6 + text_w + 8;
    let (bw, bh) = (column_w * columns as i32, 6 + ROW * rows);
    let inset = 8;
    let corners = [
        (l.right - inset - bw, l.top + inset),
        (l.left + inset, l.top + inset),
        (l.right - inset - bw, l.bottom - inset - bh),
        (l.left + inset, l.bottom - inset - bh),
    ];
    let samples = coverage_samples(c, l);
    let covered = |(x0, y0): (i32, i32)| {
        let (x0, y0) = (f64::from(x0 - 3), f64::from(y0 - 3));
        let (x1, y1) = (x0 + f64::from(bw + 6), y0 + f64::from(bh + 6));
        samples
            .iter()
            .filter(|p| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1)
            .count()
    };
    let mut best = corners[0];
    let mut best_count = covered(best);
    for &corner in &corners[1..] {
        let n = covered(corner);
        if n < best_count {
            best = corner;
            best_count = n;
        }
    }
    let (x0, y0) = best;
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + bw, y0 + bh)],
        WHITE.mix(0.88).filled(),
    ))
    .map_err(draw_err)?;
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + bw, y0 + bh)],
        RGBColor(200, 200, 200).stroke_width(1),
    ))
    .map_err(draw_err)?;
    for (k, s) in entries.iter().enumerate() {
        let (column, row) = (k as i32 / rows, k as i32 % rows);
        let cy = y0 + 3 + ROW * row + ROW / 2;
        let color = rgb(s.color);
        let left = x0 + column * column_w;
        let (sx0, sx1) = (left + 6, left + 6 + SAMPLE);
        let sample = [
            (f64::from(sx0), f64::from(cy)),
            (f64::from(sx1), f64::from(cy)),
        ];
        match s.mark {
            Mark::Points => dot(area, ((sx0 + sx1) / 2, cy), DOT_R, color)?,
            Mark::LineAndPoints => {
                draw_run(area, &sample, Mark::Line, color)?;
                dot(area, ((sx0 + sx1) / 2, cy), DOT_R, color)?;
            }
            mark => draw_run(area, &sample, mark, color)?,
        }
        label_on_row(area, &s.label, sx1 + 6, cy, Align::Left)?;
    }
    Ok(())
}

/// Draws `c` as a PNG: series, arrows, grid, ticks, labels and a legend.
pub fn chart_png(c: &Chart) -> Result<Vec<u8>, PlotError> {
    let f = chart_frame(c)?;
    render(c.size, |area| draw_chart(area, c, &f))
}

/// [`chart_png`]'s plot as SVG (vectors: it scales for print and slides).
pub fn chart_svg(c: &Chart) -> Result<String, PlotError> {
    let f = chart_frame(c)?;
    let svg = super::canvas::render_svg(c.size, |area| draw_chart(area, c, &f))?;
    // The embedded font's registered name means nothing to an SVG viewer: name the font and
    // its usual stand-ins.
    Ok(svg.replace(
        &format!("font-family=\"{}\"", super::text::FAMILY),
        "font-family=\"DejaVu Sans, Verdana, sans-serif\"",
    ))
}

fn draw_chart<DB: DrawingBackend>(
    area: &Area<DB>,
    c: &Chart,
    f: &ChartFrame,
) -> Result<(), PlotError> {
    let l = f.layout;
    for &(x0, x1, color) in &c.x_bands {
        let (lo, hi) = (l.y_range.0, l.y_range.1);
        let (x0, x1) = (x0.max(l.x_range.0), x1.min(l.x_range.1));
        if x0 >= x1 {
            continue;
        }
        if let (Some(a), Some(b)) = (l.pixel(x0, lo), l.pixel(x1, hi)) {
            area.draw(&Rectangle::new(
                [(a.0.max(l.left), b.1), (b.0.min(l.right), a.1)],
                rgb(color).filled(),
            ))
            .map_err(draw_err)?;
        }
    }
    axes(area, &l, &f.x_ticks, &f.y_ticks, true)?;
    for s in &c.series {
        for run in pixel_runs(&l, &s.points) {
            draw_run(area, &run, s.mark, rgb(s.color))?;
        }
    }
    for &(p, q, color) in &c.arrows {
        if let (Some(a), Some(b)) = (l.map(p.0, p.1), l.map(q.0, q.1)) {
            arrow(area, a, b, rgb(color))?;
        }
    }
    frame(area, &l)?;
    legend(area, c, &l)?;
    titles(area, &l, c.size, [&c.title, &c.x_label, &c.y_label])
}
