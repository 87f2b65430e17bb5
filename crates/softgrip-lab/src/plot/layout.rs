//! Where the plot area lies in the image: the data-to-pixel mapping, the
//! margins around it, and the checks on its size.

use super::error::PlotError;
use super::style::{CAP, DESCENT, LABEL_PX, MAX_SIDE, MIN_SIZE, PAD, TICK_LEN, TICK_PX, TITLE_PX};

/// Where the plot area lies in the image and how data maps onto it.
///
/// Pixel coordinates start at the top-left corner, y grows downwards. The
/// drawing uses [`Layout::map`] itself, so a data point lands exactly at the
/// pixel [`Layout::pixel`] returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// Pixel column of the plot area's left edge (where `x_range.0` maps).
    pub left: i32,
    /// Pixel row of the plot area's top edge (where `y_range.1` maps).
    pub top: i32,
    /// Pixel column of the right edge (where `x_range.1` maps).
    pub right: i32,
    /// Pixel row of the bottom edge (where `y_range.0` maps).
    pub bottom: i32,
    /// Data range shown along x, in data units (not logarithms).
    pub x_range: (f64, f64),
    /// Data range shown along y, in data units.
    pub y_range: (f64, f64),
    /// x is mapped through log10.
    pub x_log: bool,
    /// y is mapped through log10.
    pub y_log: bool,
}

impl Layout {
    /// The pixel position of data point (x, y), sub-pixel; `None` if it
    /// cannot be placed (non-finite, or not positive on a log axis). Points
    /// outside the ranges map outside the plot area.
    pub fn map(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let u = unit(x, self.x_range, self.x_log)?;
        let v = unit(y, self.y_range, self.y_log)?;
        let px = f64::from(self.left) + u * f64::from(self.right - self.left);
        let py = f64::from(self.bottom) - v * f64::from(self.bottom - self.top);
        Some((px, py))
    }

    /// The pixel that data point (x, y) is drawn at (the nearest to [`Layout::map`]).
    pub fn pixel(&self, x: f64, y: f64) -> Option<(i32, i32)> {
        self.map(x, y).map(|(px, py)| (round_px(px), round_px(py)))
    }
}

/// Position of `v` along `range` as a fraction 0..1 (log10 if `log`).
fn unit(v: f64, range: (f64, f64), log: bool) -> Option<f64> {
    let (a, b, v) = (axis_t(range.0, log), axis_t(range.1, log), axis_t(v, log));
    let u = (v - a) / (b - a);
    u.is_finite().then_some(u)
}

/// The plotted coordinate of a data value: itself, or its log10.
pub(super) fn axis_t(v: f64, log: bool) -> f64 {
    if log {
        if v > 0.0 { v.log10() } else { f64::NAN }
    } else {
        v
    }
}

/// The inverse of [`axis_t`].
pub(super) fn axis_inv(t: f64, log: bool) -> f64 {
    if log { 10f64.powf(t) } else { t }
}

/// Nearest pixel index, saturating far outside the image.
pub(super) fn round_px(v: f64) -> i32 {
    v.round().clamp(-1e6, 1e6) as i32
}

pub(super) fn check_size(size: (u32, u32)) -> Result<(), PlotError> {
    let (width, height) = size;
    if width < MIN_SIZE.0 || height < MIN_SIZE.1 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(PlotError::Size { width, height });
    }
    Ok(())
}

/// Fails with [`PlotError::Size`] when the labels leave less than 40 x 30 px to plot in.
pub(super) fn check_area(l: &Layout, size: (u32, u32)) -> Result<(), PlotError> {
    if l.right - l.left < 40 || l.bottom - l.top < 30 {
        return Err(PlotError::Size {
            width: size.0,
            height: size.1,
        });
    }
    Ok(())
}

/// Rows above the plot area: a band for the title, or a small margin.
pub(super) fn top_margin(title: &str) -> i32 {
    if title.is_empty() {
        PAD + round_px(TICK_PX / 2.0)
    } else {
        PAD + round_px(TITLE_PX * 1.2) + 14
    }
}

/// Columns left of the y tick labels: room for the rotated y label.
pub(super) fn y_label_room(label: &str) -> i32 {
    if label.is_empty() {
        PAD
    } else {
        PAD + round_px(LABEL_PX * (CAP + DESCENT)) + 8
    }
}

/// Rows below the plot area: tick labels and the x label.
pub(super) fn bottom_room(x_label: &str) -> i32 {
    let ticks = TICK_LEN + 4 + round_px(TICK_PX * (CAP + DESCENT));
    let label = if x_label.is_empty() {
        0
    } else {
        6 + round_px(LABEL_PX * (CAP + DESCENT))
    };
    ticks + label + PAD
}

/// The baseline row of x tick labels.
pub(super) fn x_tick_baseline(l: &Layout) -> i32 {
    l.bottom + TICK_LEN + 3 + round_px(TICK_PX * CAP)
}

/// Widens the narrower of two ranges (in plotted space) so one unit spans
/// the same number of pixels on both axes.
pub(super) fn equalize(
    x: (f64, f64),
    y: (f64, f64),
    w_px: i32,
    h_px: i32,
    x_log: bool,
    y_log: bool,
) -> ((f64, f64), (f64, f64)) {
    let (xa, xb) = (axis_t(x.0, x_log), axis_t(x.1, x_log));
    let (ya, yb) = (axis_t(y.0, y_log), axis_t(y.1, y_log));
    let (w, h) = (f64::from(w_px.max(1)), f64::from(h_px.max(1)));
    let scale = ((xb - xa) / w).max((yb - ya) / h);
    let (xc, yc) = ((xa + xb) / 2.0, (ya + yb) / 2.0);
    let (hx, hy) = (scale * w / 2.0, scale * h / 2.0);
    (
        (axis_inv(xc - hx, x_log), axis_inv(xc + hx, x_log)),
        (axis_inv(yc - hy, y_log), axis_inv(yc + hy, y_log)),
    )
}

/// Lays a plot out until its side edges settle: they make room for the tick
/// labels, whose widths depend on the ticks, which depend on the edges.
/// `lay_out(left, right)` returns the layout, what else it worked out, and
/// the edges it asks for; the last of `passes` passes stands. Fails with
/// [`PlotError::Size`] when the labels leave no room to plot in.
pub(super) fn settle_edges<T>(
    title: &str,
    size: (u32, u32),
    (mut left, mut right): (i32, i32),
    passes: usize,
    mut lay_out: impl FnMut(i32, i32) -> Result<(Layout, T, (i32, i32)), PlotError>,
) -> Result<(Layout, T), PlotError> {
    let mut frame = None;
    for pass in 0..passes {
        let (layout, more, (new_left, new_right)) = lay_out(left, right)?;
        frame = Some((layout, more));
        if (new_left == left && new_right == right) || pass + 1 == passes {
            break;
        }
        left = new_left;
        right = new_right;
    }
    let Some(frame) = frame else {
        return Err(PlotError::NothingToPlot {
            title: title.to_string(),
        });
    };
    check_area(&frame.0, size)?;
    Ok(frame)
}
