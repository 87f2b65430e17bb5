//! The frame, ticks, title and axis labels around a plot area.

use plotters::element::Rectangle;
use plotters::style::Color;

use super::canvas::{Area, draw_err, polyline};
use super::error::PlotError;
use super::layout::{Layout, round_px, x_tick_baseline};
use super::style::{AXIS, CAP, DESCENT, GRID, INK, LABEL_PX, PAD, TICK_LEN, TICK_PX, TITLE_PX};
use super::text::{Align, text, text_up};
use super::ticks::Tick;
use plotters::backend::DrawingBackend;

pub(super) fn frame<DB: DrawingBackend>(area: &Area<DB>, l: &Layout) -> Result<(), PlotError> {
    area.draw(&Rectangle::new(
        [(l.left, l.top), (l.right, l.bottom)],
        AXIS.stroke_width(1),
    ))
    .map_err(draw_err)
}

fn title<DB: DrawingBackend>(area: &Area<DB>, s: &str, width: u32) -> Result<(), PlotError> {
    let baseline = PAD + round_px(TITLE_PX * 0.95);
    text(
        area,
        s,
        TITLE_PX,
        INK,
        width as i32 / 2,
        baseline,
        Align::Center,
    )
}

/// Draws the rotated y label in the left margin, centred on the plot area.
fn y_label<DB: DrawingBackend>(area: &Area<DB>, s: &str, l: &Layout) -> Result<(), PlotError> {
    let baseline_x = PAD + round_px(LABEL_PX * CAP);
    text_up(area, s, LABEL_PX, INK, baseline_x, (l.top + l.bottom) / 2)
}

/// Draws the x label under the tick labels, centred on the plot area.
fn x_label<DB: DrawingBackend>(
    area: &Area<DB>,
    s: &str,
    l: &Layout,
    height: u32,
) -> Result<(), PlotError> {
    let baseline = height as i32 - PAD - round_px(LABEL_PX * DESCENT);
    text(
        area,
        s,
        LABEL_PX,
        INK,
        (l.left + l.right) / 2,
        baseline,
        Align::Center,
    )
}

/// The title, x label and y label of a plot (an empty one draws nothing).
pub(super) fn titles<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    size: (u32, u32),
    [title_text, x_text, y_text]: [&str; 3],
) -> Result<(), PlotError> {
    title(area, title_text, size.0)?;
    x_label(area, x_text, l, size.1)?;
    y_label(area, y_text, l)
}

/// A tick mark under the plot area at column `px`.
pub(super) fn x_tick_mark<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    px: i32,
) -> Result<(), PlotError> {
    polyline(
        area,
        vec![(px, l.bottom), (px, l.bottom + TICK_LEN)],
        AXIS,
        1,
    )
}

/// A tick mark left of the plot area at row `py`.
pub(super) fn y_tick_mark<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    py: i32,
) -> Result<(), PlotError> {
    polyline(area, vec![(l.left - TICK_LEN, py), (l.left, py)], AXIS, 1)
}

/// A tick label centred on column `px`, under the plot area.
pub(super) fn x_tick_label<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    px: i32,
    label: &str,
) -> Result<(), PlotError> {
    text(
        area,
        label,
        TICK_PX,
        INK,
        px,
        x_tick_baseline(l),
        Align::Center,
    )
}

/// A tick label right-aligned left of the plot area, centred on row `py`.
pub(super) fn y_tick_label<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    py: i32,
    label: &str,
) -> Result<(), PlotError> {
    label_on_row(area, label, l.left - TICK_LEN - 3, py, Align::Right)
}

/// Tick-sized text centred on row `row`, aligned on column `x`.
pub(super) fn label_on_row<DB: DrawingBackend>(
    area: &Area<DB>,
    label: &str,
    x: i32,
    row: i32,
    align: Align,
) -> Result<(), PlotError> {
    let baseline = row + round_px(TICK_PX * CAP / 2.0);
    text(area, label, TICK_PX, INK, x, baseline, align)
}

/// Grid lines, tick marks and tick labels of an x-y plot area.
pub(super) fn axes<DB: DrawingBackend>(
    area: &Area<DB>,
    l: &Layout,
    x_ticks: &[Tick],
    y_ticks: &[Tick],
    grid: bool,
) -> Result<(), PlotError> {
    for t in x_ticks {
        let Some((px, _)) = l.map(t.value, l.y_range.0) else {
            continue;
        };
        let px = round_px(px);
        if grid {
            polyline(area, vec![(px, l.top), (px, l.bottom)], GRID, 1)?;
        }
        x_tick_mark(area, l, px)?;
        x_tick_label(area, l, px, &t.label)?;
    }
    for t in y_ticks {
        let Some((_, py)) = l.map(l.x_range.0, t.value) else {
            continue;
        };
        let py = round_px(py);
        if grid {
            polyline(area, vec![(l.left, py), (l.right, py)], GRID, 1)?;
        }
        y_tick_mark(area, l, py)?;
        y_tick_label(area, l, py, &t.label)?;
    }
    Ok(())
}
