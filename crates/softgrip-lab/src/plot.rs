//! PNG plots for the command-line reports (`softgrip compare`, `fit`, `sweep`,
//! `diagnose`): line and point charts, heat maps and bar charts.
//!
//! Drawing goes through `plotters` into an RGB buffer, text through its
//! `ab_glyph` renderer with DejaVu Sans embedded in the binary
//! (`assets/fonts/`, licence in `LICENSE-DejaVu.txt`), and the `png` crate
//! encodes the result. Nothing here reads system fonts, clocks or hash order,
//! so the same input gives the same bytes; the core builds without the GUI.
//!
//! Layout is computed here, not by plotters' chart builder: [`chart_layout`],
//! [`heat_map_layout`] and [`bars_layout`] return the exact data-to-pixel
//! mapping the drawing uses, so tests and callers can check where a point lands.

use std::path::{Path, PathBuf};

use ab_glyph::{Font, FontRef, ScaleFont};
use std::sync::OnceLock;

use plotters::backend::{BitMapBackend, RGBPixel};
use plotters::coord::Shift;
use plotters::drawing::{DrawingArea, IntoDrawingArea};
use plotters::element::{Circle, PathElement, Polygon, Rectangle, Text};
use plotters::style::{
    Color, FontFamily, FontStyle, FontTransform, IntoFont, RGBColor, TextStyle, register_font,
};

/// DejaVu Sans, embedded so plots look the same on every machine.
const FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
/// The name the font is registered under in plotters' font table.
const FAMILY: &str = "softgrip-dejavu-sans";

/// The size used by `Default`: 800 x 500 px reads well in a Markdown report.
pub const DEFAULT_SIZE: (u32, u32) = (800, 500);
/// Smallest accepted image, in px: below it the labels leave no plot area.
pub const MIN_SIZE: (u32, u32) = (200, 150);
/// Largest accepted image, in px, per side (keeps the buffer under 300 MB).
pub const MAX_SIDE: u32 = 10_000;

// Text sizes in px (plotters' ab_glyph size: ascender to descender). Keep
// them even: plotters truncates size/2 plus each glyph's top to whole pixels,
// which with an odd size lifts some glyphs (a "." drawn as a raised dot).
const TITLE_PX: f64 = 18.0;
const LABEL_PX: f64 = 14.0;
const TICK_PX: f64 = 12.0;
// DejaVu Sans: cap height and descender as fractions of that size.
const CAP: f64 = 0.63;
const DESCENT: f64 = 0.21;
const PAD: i32 = 8;
const TICK_LEN: i32 = 5;

const WHITE: RGBColor = RGBColor(255, 255, 255);
const INK: RGBColor = RGBColor(30, 30, 30);
const AXIS: RGBColor = RGBColor(90, 90, 90);
const GRID: RGBColor = RGBColor(228, 228, 228);
/// Heat-map cells without a value.
const NO_VALUE: RGBColor = RGBColor(170, 170, 170);

/// Why a plot could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No series point (or heat-map value, or bar) is finite.
    #[error("plot \"{title}\": nothing finite to plot")]
    NothingToPlot {
        /// The plot's title, to tell which plot of a report failed.
        title: String,
    },
    /// A logarithmic axis was given a value that is zero or negative.
    #[error(
        "plot \"{title}\": the {axis} axis is logarithmic but the data has {value}, which is not positive"
    )]
    LogAxis {
        /// The plot's title.
        title: String,
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// The first offending value.
        value: f64,
    },
    /// The image size is outside [`MIN_SIZE`] .. [`MAX_SIDE`], or leaves no
    /// room for the plot area once the labels are placed.
    #[error(
        "plot size {width}x{height} px is too small or too large (at least {}x{}, at most {MAX_SIDE} per side, with room for the labels)",
        MIN_SIZE.0,
        MIN_SIZE.1
    )]
    Size {
        /// Requested width in px.
        width: u32,
        /// Requested height in px.
        height: u32,
    },
    /// The input's parts do not fit together (lengths, ordering of centres).
    #[error("plot \"{title}\": {detail}")]
    Shape {
        /// The plot's title.
        title: String,
        /// What does not fit.
        detail: String,
    },
    /// The embedded font could not be loaded (a corrupt build).
    #[error("the embedded plot font could not be loaded: {0}")]
    Font(String),
    /// plotters failed while drawing.
    #[error("drawing the plot failed: {0}")]
    Draw(String),
    /// The PNG encoder failed.
    #[error("encoding the plot as PNG failed: {0}")]
    Encode(String),
    /// Writing the PNG file failed.
    #[error("could not write plot {}: {source}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line through the points in order, 2 px wide.
    Line,
    /// A dot at each point and no line (measurements).
    Points,
    /// A solid line with a dot at each point.
    LineAndPoints,
    /// A dashed line (a reference or model curve beside the data).
    Dashed,
}

/// One named set of (x, y) points in data units.
///
/// Non-finite points are skipped; a line breaks where one was.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; empty keeps the series out of the legend.
    pub label: String,
    /// The points, drawn in this order.
    pub points: Vec<(f64, f64)>,
    /// How the points are drawn.
    pub mark: Mark,
    /// sRGB colour, e.g. from [`palette`].
    pub color: [u8; 3],
}

/// An arrow from one data point to another, `(from, to, color)`.
pub type Arrow = ((f64, f64), (f64, f64), [u8; 3]);

/// An x-y chart of one or more series.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Drawn centred above the plot; empty leaves the band out.
    pub title: String,
    /// x axis label, with its unit, e.g. "time (s)".
    pub x_label: String,
    /// y axis label, with its unit.
    pub y_label: String,
    /// The series, drawn in order (later ones on top).
    pub series: Vec<Series>,
    /// Logarithmic x axis; every x must then be positive.
    pub x_log: bool,
    /// Logarithmic y axis; every y must then be positive.
    pub y_log: bool,
    /// Same scale on both axes (marker paths in metres drawn to shape).
    pub equal_aspect: bool,
    /// Arrows from (x0,y0) to (x1,y1), e.g. residuals; drawn in `color`.
    pub arrows: Vec<Arrow>,
    /// Image width and height in px.
    pub size: (u32, u32),
}

impl Default for Chart {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            series: Vec::new(),
            x_log: false,
            y_log: false,
            equal_aspect: false,
            arrows: Vec::new(),
            size: DEFAULT_SIZE,
        }
    }
}

/// A grid of values drawn as coloured cells (e.g. a parameter sweep), with a
/// colour bar.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatMap {
    /// Drawn centred above the plot.
    pub title: String,
    /// x axis label, with its unit.
    pub x_label: String,
    /// y axis label, with its unit.
    pub y_label: String,
    /// Colour bar label: what the colour means, with its unit.
    pub value_label: String,
    /// Cell centres along x and y (ascending); `values[j * x.len() + i]` is the cell `(x[i], y[j])`; NaN = no value (drawn grey).
    pub x: Vec<f64>,
    /// Cell centres along y (ascending).
    pub y: Vec<f64>,
    /// Row-major values, `x.len() * y.len()` of them.
    pub values: Vec<f64>,
    /// Logarithmic x axis (cells then span geometric midpoints).
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// A point to mark (e.g. the best), drawn as a white-edged cross.
    pub mark: Option<(f64, f64)>,
    /// Image width and height in px.
    pub size: (u32, u32),
}

impl Default for HeatMap {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            value_label: String::new(),
            x: Vec::new(),
            y: Vec::new(),
            values: Vec::new(),
            x_log: false,
            y_log: false,
            mark: None,
            size: DEFAULT_SIZE,
        }
    }
}

/// A bar chart: one bar per label, from zero to its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Bars {
    /// Drawn centred above the plot.
    pub title: String,
    /// y axis label, with its unit.
    pub y_label: String,
    /// One label per bar, written under it.
    pub labels: Vec<String>,
    /// Bar heights in data units; a non-finite value leaves its slot empty.
    pub values: Vec<f64>,
    /// Bar colours; missing entries take [`palette`] colours.
    pub colors: Vec<[u8; 3]>,
    /// Image width and height in px.
    pub size: (u32, u32),
}

impl Default for Bars {
    fn default() -> Self {
        Self {
            title: String::new(),
            y_label: String::new(),
            labels: Vec::new(),
            values: Vec::new(),
            colors: Vec::new(),
            size: DEFAULT_SIZE,
        }
    }
}

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
fn axis_t(v: f64, log: bool) -> f64 {
    if log {
        if v > 0.0 { v.log10() } else { f64::NAN }
    } else {
        v
    }
}

/// The inverse of [`axis_t`].
fn axis_inv(t: f64, log: bool) -> f64 {
    if log { 10f64.powf(t) } else { t }
}

/// Nearest pixel index, saturating far outside the image.
fn round_px(v: f64) -> i32 {
    v.round().clamp(-1e6, 1e6) as i32
}

/// A distinguishable colour for series `k`: Tableau 10 (matplotlib's default
/// cycle), readable on white; repeats after ten.
pub fn palette(k: usize) -> [u8; 3] {
    const TABLEAU_10: [[u8; 3]; 10] = [
        [31, 119, 180],
        [255, 127, 14],
        [44, 160, 44],
        [214, 39, 40],
        [148, 103, 189],
        [140, 86, 75],
        [227, 119, 194],
        [127, 127, 127],
        [188, 189, 34],
        [23, 190, 207],
    ];
    TABLEAU_10[k % TABLEAU_10.len()]
}

/// Writes PNG bytes (from [`chart_png`] and the others) to `path`; the error
/// names the path. Parent directories must exist.
pub fn write_png(path: &Path, png: &[u8]) -> Result<(), PlotError> {
    std::fs::write(path, png).map_err(|source| PlotError::Write {
        path: path.to_path_buf(),
        source,
    })
}

// ---------------------------------------------------------------------------
// Font, canvas and PNG encoding.

/// Registers the embedded font with plotters once per process.
fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok =
        *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font("DejaVuSans.ttf did not parse".into()))
    }
}

/// The embedded font parsed for metrics (advances, kerning, bearings).
fn metrics_font() -> Result<&'static FontRef<'static>, PlotError> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
        .ok_or_else(|| PlotError::Font("DejaVuSans.ttf did not parse".into()))
}

/// Where each visible glyph of `s` starts, in px from the text's origin
/// (the left edge of its bitmap), and the text's total advance in px.
///
/// plotters' ab_glyph renderer drops each glyph's side bearing and rounds
/// the pen down, which spaces letters unevenly ("l ab"); so text is drawn one
/// glyph at a time at these offsets, and plotters only rasterises each glyph.
fn glyph_offsets(s: &str, size: f64) -> Result<(Vec<(char, i32)>, i32), PlotError> {
    let font = metrics_font()?;
    let scaled = font.as_scaled(size as f32);
    let mut pen = 0.0f32;
    let mut prev = None;
    let mut out = Vec::new();
    for c in s.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        prev = Some(id);
        // The same glyph plotters outlines: scale `size`, positioned at the origin.
        if let Some(outline) = scaled.outline_glyph(scaled.scaled_glyph(c)) {
            let min_x = outline.px_bounds().min.x;
            out.push((c, round_px(f64::from(pen + min_x))));
        }
        pen += scaled.h_advance(id);
    }
    Ok((out, round_px(f64::from(pen))))
}

/// Width in px of `s` drawn at `size`.
fn text_width(s: &str, size: f64) -> Result<i32, PlotError> {
    glyph_offsets(s, size).map(|(_, w)| w)
}

/// The widest of `labels` at `size`, in px.
fn max_width<'a>(labels: impl IntoIterator<Item = &'a str>, size: f64) -> Result<i32, PlotError> {
    let mut w = 0;
    for s in labels {
        w = w.max(text_width(s, size)?);
    }
    Ok(w)
}

type Area<'a> = DrawingArea<BitMapBackend<'a, RGBPixel>, Shift>;

fn draw_err(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
}

fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

fn check_size(size: (u32, u32)) -> Result<(), PlotError> {
    let (width, height) = size;
    if width < MIN_SIZE.0 || height < MIN_SIZE.1 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(PlotError::Size { width, height });
    }
    Ok(())
}

/// Fails with [`PlotError::Size`] when the labels leave less than 40 x 30 px to plot in.
fn check_area(l: &Layout, size: (u32, u32)) -> Result<(), PlotError> {
    if l.right - l.left < 40 || l.bottom - l.top < 30 {
        return Err(PlotError::Size {
            width: size.0,
            height: size.1,
        });
    }
    Ok(())
}

/// Draws on a white RGB canvas of `size` and encodes it as PNG.
fn render(
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), PlotError>,
) -> Result<Vec<u8>, PlotError> {
    let (w, h) = size;
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    {
        let backend = BitMapBackend::<RGBPixel>::with_buffer_and_format(&mut buf, (w, h))
            .map_err(draw_err)?;
        let area = backend.into_drawing_area();
        area.fill(&WHITE).map_err(draw_err)?;
        draw(&area)?;
        area.present().map_err(draw_err)?;
    }
    encode_png(&buf, w, h)
}

/// 8-bit RGB PNG, default compression, no timestamps or other metadata.
fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, PlotError> {
    let enc_err = |e: png::EncodingError| PlotError::Encode(e.to_string());
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(enc_err)?;
    writer.write_image_data(rgb).map_err(enc_err)?;
    writer.finish().map_err(enc_err)?;
    Ok(out)
}

#[derive(Clone, Copy)]
enum Align {
    Left,
    Center,
    Right,
}

fn text_style(size: f64, color: RGBColor) -> TextStyle<'static> {
    TextStyle {
        color: color.to_backend_color(),
        ..TextStyle::from((FontFamily::Name(FAMILY), size).into_font())
    }
}

/// Horizontal text with its baseline on row `baseline`, aligned on column `x`.
fn text(
    area: &Area<'_>,
    s: &str,
    size: f64,
    color: RGBColor,
    x: i32,
    baseline: i32,
    align: Align,
) -> Result<(), PlotError> {
    let (glyphs, w) = glyph_offsets(s, size)?;
    let x0 = match align {
        Align::Left => x,
        Align::Center => x - w / 2,
        Align::Right => x - w,
    };
    // plotters' ab_glyph renderer puts the baseline size/2 below the anchor.
    let y0 = baseline - round_px(size / 2.0);
    let style = text_style(size, color);
    for (c, dx) in glyphs {
        area.draw(&Text::new(c.to_string(), (x0 + dx, y0), style.clone()))
            .map_err(draw_err)?;
    }
    Ok(())
}

/// Text reading upwards (rotated a quarter turn anticlockwise), its baseline
/// on column `baseline_x` (letter tops point left), centred on row `center_y`.
fn text_up(
    area: &Area<'_>,
    s: &str,
    size: f64,
    color: RGBColor,
    baseline_x: i32,
    center_y: i32,
) -> Result<(), PlotError> {
    let (glyphs, w) = glyph_offsets(s, size)?;
    let style = text_style(size, color).transform(FontTransform::Rotate270);
    let (x0, y0) = (baseline_x - round_px(size / 2.0), center_y + w / 2);
    for (c, dx) in glyphs {
        area.draw(&Text::new(c.to_string(), (x0, y0 - dx), style.clone()))
            .map_err(draw_err)?;
    }
    Ok(())
}

fn polyline(
    area: &Area<'_>,
    pts: Vec<(i32, i32)>,
    color: RGBColor,
    width: u32,
) -> Result<(), PlotError> {
    if pts.len() < 2 {
        return Ok(());
    }
    area.draw(&PathElement::new(pts, color.stroke_width(width)))
        .map_err(draw_err)
}

fn dot(area: &Area<'_>, p: (i32, i32), r: i32, color: RGBColor) -> Result<(), PlotError> {
    area.draw(&Circle::new(p, r, color.filled()))
        .map_err(draw_err)
}

/// Filled rectangle covering columns `x0..x1` and rows `y0..y1` (end exclusive).
fn fill_rect(
    area: &Area<'_>,
    (x0, y0): (i32, i32),
    (x1, y1): (i32, i32),
    color: RGBColor,
) -> Result<(), PlotError> {
    area.draw(&Rectangle::new([(x0, y0), (x1, y1)], color.filled()))
        .map_err(draw_err)
}

fn frame(area: &Area<'_>, l: &Layout) -> Result<(), PlotError> {
    area.draw(&Rectangle::new(
        [(l.left, l.top), (l.right, l.bottom)],
        AXIS.stroke_width(1),
    ))
    .map_err(draw_err)
}

fn title(area: &Area<'_>, s: &str, width: u32) -> Result<(), PlotError> {
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

/// Rows above the plot area: a band for the title, or a small margin.
fn top_margin(title: &str) -> i32 {
    if title.is_empty() {
        PAD + round_px(TICK_PX / 2.0)
    } else {
        PAD + round_px(TITLE_PX * 1.2) + 14
    }
}

/// Columns left of the y tick labels: room for the rotated y label.
fn y_label_room(label: &str) -> i32 {
    if label.is_empty() {
        PAD
    } else {
        PAD + round_px(LABEL_PX * (CAP + DESCENT)) + 8
    }
}

/// Rows below the plot area: tick labels and the x label.
fn bottom_room(x_label: &str) -> i32 {
    let ticks = TICK_LEN + 4 + round_px(TICK_PX * (CAP + DESCENT));
    let label = if x_label.is_empty() {
        0
    } else {
        6 + round_px(LABEL_PX * (CAP + DESCENT))
    };
    ticks + label + PAD
}

/// Draws the rotated y label in the left margin, centred on the plot area.
fn y_label(area: &Area<'_>, s: &str, l: &Layout) -> Result<(), PlotError> {
    let baseline_x = PAD + round_px(LABEL_PX * CAP);
    text_up(area, s, LABEL_PX, INK, baseline_x, (l.top + l.bottom) / 2)
}

/// Draws the x label under the tick labels, centred on the plot area.
fn x_label(area: &Area<'_>, s: &str, l: &Layout, height: u32) -> Result<(), PlotError> {
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

/// The baseline row of x tick labels.
fn x_tick_baseline(l: &Layout) -> i32 {
    l.bottom + TICK_LEN + 3 + round_px(TICK_PX * CAP)
}

// ---------------------------------------------------------------------------
// Ranges, ticks and number formatting.

/// A tick: its value in data units and its label.
#[derive(Debug, Clone)]
struct Tick {
    value: f64,
    label: String,
}

/// The range to show for data spanning `lo..=hi`: 5 % margin on each side in
/// plotted (log) space, or a fixed widening when the data has no spread.
fn padded_range(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    let (a, b) = (axis_t(lo, log), axis_t(hi, log));
    let (a, b) = if degenerate(a, b) {
        let d = if log {
            0.5
        } else if a != 0.0 {
            a.abs() * 0.1
        } else {
            1.0
        };
        (a - d, b + d)
    } else {
        let m = 0.05 * (b - a);
        (a - m, b + m)
    };
    (axis_inv(a, log), axis_inv(b, log))
}

/// True when `a..b` is too narrow to divide into ticks.
fn degenerate(a: f64, b: f64) -> bool {
    let spread = b - a;
    let divisible = spread.is_finite() && spread > 1e-9 * a.abs().max(b.abs());
    !divisible
}

/// The 1, 2 or 5 times a power of ten at or above `raw`.
pub fn nice_step(raw: f64) -> f64 {
    let e = raw.log10().floor();
    let p = 10f64.powf(e);
    let f = raw / p;
    let m = if f <= 1.0 + 1e-9 {
        1.0
    } else if f <= 2.0 + 1e-9 {
        2.0
    } else if f <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    m * p
}

/// The 1-2-5 step below `step`: 1 -> 0.5, 2 -> 1, 5 -> 2 (times a power of ten).
fn finer_step(step: f64) -> f64 {
    let p = 10f64.powf(step.log10().floor());
    let m = (step / p).round();
    if m <= 1.0 {
        0.5 * p
    } else if m <= 2.0 {
        p
    } else if m <= 5.0 {
        2.0 * p
    } else {
        5.0 * p
    }
}

/// `v` formatted compactly: scientific ("2.5e5", "1e-4") when `sci`, else
/// fixed; digits down to `resolution` (the smallest difference worth showing).
fn format_number(v: f64, resolution: f64, sci: bool) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let res = resolution.abs();
    if v == 0.0 || (res > 0.0 && v.abs() < res * 1e-6) {
        return "0".into();
    }
    let last_digit = if res > 0.0 && res.is_finite() {
        res.log10().floor() as i32
    } else {
        v.abs().log10().floor() as i32 - 3
    };
    let s = if sci {
        let mut e = v.abs().log10().floor() as i32;
        let decimals = (e - last_digit).clamp(0, 6) as usize;
        let mut m = format!("{:.*}", decimals, v / 10f64.powi(e));
        if m.trim_start_matches('-').starts_with("10") {
            e += 1;
            m = format!("{:.*}", decimals, v / 10f64.powi(e));
        }
        format!("{}e{e}", trim_zeros(&m))
    } else {
        let decimals = (-last_digit).clamp(0, 9) as usize;
        // Whole numbers keep only the digits that resolve: 31622.8 -> "31600".
        let v = if last_digit > 0 {
            let p = 10f64.powi(last_digit);
            (v / p).round() * p
        } else {
            v
        };
        trim_zeros(&format!("{v:.decimals$}"))
    };
    if s == "-0" { "0".into() } else { s }
}

/// "2.500" -> "2.5", "3.0" -> "3"; integers unchanged.
fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Scientific notation when the largest magnitude is at least 1e5 or below 1e-3.
fn wants_sci(largest: f64) -> bool {
    largest >= 1e5 || (largest > 0.0 && largest < 1e-3)
}

/// Scientific labels on a log axis whose values reach 1e4 or go below 0.01,
/// so a whole axis reads "1e3, 1e4, 1e5" rather than "1000, 10000, 1e5".
fn log_wants_sci(values: &[f64]) -> bool {
    values.iter().any(|v| v.abs() >= 1e4 || v.abs() < 1e-2)
}

/// A compact label for one value on a log axis (3 significant digits).
fn format_log_value(v: f64, sci: bool) -> String {
    format_number(v, v.abs() / 100.0, sci)
}

/// Evenly spaced ticks inside `range`, about `len_px / spacing_px` of them,
/// spaced wider on a horizontal axis until the labels stand 12 px apart.
fn linear_ticks(
    range: (f64, f64),
    len_px: i32,
    spacing_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let (lo, hi) = range;
    let target = f64::from((len_px / spacing_px).clamp(2, 12));
    let mut step = nice_step((hi - lo) / target);
    // At least three ticks when the axis is long enough to hold them.
    let count = |step: f64| (hi / step + 1e-9).floor() - (lo / step - 1e-9).ceil() + 1.0;
    while count(step) < 3.0 && len_px >= 3 * spacing_px / 2 {
        let finer = finer_step(step);
        if finer.is_nan() || finer <= 0.0 || count(finer) > 12.0 {
            break;
        }
        step = finer;
    }
    let mut ticks = Vec::new();
    for _ in 0..8 {
        ticks.clear();
        let k0 = (lo / step - 1e-9).ceil();
        let k1 = (hi / step + 1e-9).floor();
        if !(k0.is_finite() && k1.is_finite()) || k1 - k0 > 100.0 {
            break;
        }
        let mut values = Vec::new();
        let mut k = k0;
        while k <= k1 {
            values.push(k * step);
            k += 1.0;
        }
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let sci = wants_sci(largest);
        for v in values {
            ticks.push(Tick {
                value: v,
                label: format_number(v, step, sci),
            });
        }
        if !horizontal {
            break;
        }
        let widest = max_width(ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
        let step_px = f64::from(len_px) * step / (hi - lo);
        if f64::from(widest + 12) <= step_px {
            break;
        }
        step = nice_step(step * 1.5);
    }
    Ok(ticks)
}

/// Ticks on a log axis: powers of ten (thinned to fit), or 1-2-5 steps when
/// the range spans less than two decades, or linear ticks within one.
fn log_ticks(
    range: (f64, f64),
    len_px: i32,
    spacing_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let (a, b) = (range.0.log10(), range.1.log10());
    let max_count = (len_px / spacing_px).clamp(2, 12) as i64;
    let (e0, e1) = ((a - 1e-9).ceil() as i64, (b + 1e-9).floor() as i64);
    let mut values: Vec<f64> = Vec::new();
    if e1 - e0 >= 1 {
        let every = ((e1 - e0 + 1) + max_count - 1) / max_count;
        let mut e = e0;
        while e <= e1 {
            values.push(10f64.powi(e as i32));
            e += every.max(1);
        }
    } else {
        let mut e = a.floor() as i64;
        while e <= b.floor() as i64 {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(e as i32);
                if v >= range.0 * (1.0 - 1e-9) && v <= range.1 * (1.0 + 1e-9) {
                    values.push(v);
                }
            }
            e += 1;
        }
    }
    if values.len() < 2 {
        return linear_ticks(range, len_px, spacing_px, horizontal);
    }
    let sci = log_wants_sci(&values);
    Ok(values
        .into_iter()
        .map(|v| Tick {
            value: v,
            label: format_log_value(v, sci),
        })
        .collect())
}

fn axis_ticks(
    range: (f64, f64),
    log: bool,
    len_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let spacing = if horizontal { 90 } else { 50 };
    if log {
        log_ticks(range, len_px, spacing, horizontal)
    } else {
        linear_ticks(range, len_px, spacing, horizontal)
    }
}

/// Widens the narrower of two ranges (in plotted space) so one unit spans
/// the same number of pixels on both axes.
fn equalize(
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

/// Grid lines, tick marks and tick labels of an x-y plot area.
fn axes(
    area: &Area<'_>,
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
        polyline(
            area,
            vec![(px, l.bottom), (px, l.bottom + TICK_LEN)],
            AXIS,
            1,
        )?;
        text(
            area,
            &t.label,
            TICK_PX,
            INK,
            px,
            x_tick_baseline(l),
            Align::Center,
        )?;
    }
    for t in y_ticks {
        let Some((_, py)) = l.map(l.x_range.0, t.value) else {
            continue;
        };
        let py = round_px(py);
        if grid {
            polyline(area, vec![(l.left, py), (l.right, py)], GRID, 1)?;
        }
        polyline(area, vec![(l.left - TICK_LEN, py), (l.left, py)], AXIS, 1)?;
        let baseline = py + round_px(TICK_PX * CAP / 2.0);
        text(
            area,
            &t.label,
            TICK_PX,
            INK,
            l.left - TICK_LEN - 3,
            baseline,
            Align::Right,
        )?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Charts.

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
    let (mut left, mut right) = (label_room + 40, w - 20);
    let mut frame = None;
    for pass in 0..4 {
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
        frame = Some(ChartFrame {
            layout,
            x_ticks,
            y_ticks,
        });
        if (new_left == left && new_right == right) || pass == 3 {
            break;
        }
        left = new_left;
        right = new_right;
    }
    let Some(frame) = frame else {
        return Err(PlotError::NothingToPlot {
            title: c.title.clone(),
        });
    };
    check_area(&frame.layout, c.size)?;
    Ok(frame)
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
fn dashed(area: &Area<'_>, run: &[(f64, f64)], color: RGBColor) -> Result<(), PlotError> {
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
fn draw_run(
    area: &Area<'_>,
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
fn arrow(area: &Area<'_>, a: (f64, f64), b: (f64, f64), color: RGBColor) -> Result<(), PlotError> {
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
fn legend(area: &Area<'_>, c: &Chart, l: &Layout) -> Result<(), PlotError> {
    let entries: Vec<&Series> = c.series.iter().filter(|s| !s.label.is_empty()).collect();
    if entries.is_empty() {
        return Ok(());
    }
    const SAMPLE: i32 = 24;
    const ROW: i32 = 18;
    let text_w = max_width(entries.iter().map(|s| s.label.as_str()), TICK_PX)?;
    let (bw, bh) = (6 + SAMPLE + 6 + text_w + 8, 6 + ROW * entries.len() as i32);
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
        let cy = y0 + 3 + ROW * k as i32 + ROW / 2;
        let color = rgb(s.color);
        let (sx0, sx1) = (x0 + 6, x0 + 6 + SAMPLE);
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
        let baseline = cy + round_px(TICK_PX * CAP / 2.0);
        text(area, &s.label, TICK_PX, INK, sx1 + 6, baseline, Align::Left)?;
    }
    Ok(())
}

/// Draws `c` as a PNG: series, arrows, grid, ticks, labels and a legend.
pub fn chart_png(c: &Chart) -> Result<Vec<u8>, PlotError> {
    let f = chart_frame(c)?;
    let l = f.layout;
    render(c.size, |area| {
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
        title(area, &c.title, c.size.0)?;
        x_label(area, &c.x_label, &l, c.size.1)?;
        y_label(area, &c.y_label, &l)
    })
}

// ---------------------------------------------------------------------------
// Heat maps.

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
            polyline(
                area,
                vec![(px, l.bottom), (px, l.bottom + TICK_LEN)],
                AXIS,
                1,
            )?;
            let lw = text_width(label, TICK_PX)?;
            if px - lw / 2 >= last_right + 8 {
                text(
                    area,
                    label,
                    TICK_PX,
                    INK,
                    px,
                    x_tick_baseline(&l),
                    Align::Center,
                )?;
                last_right = px + lw / 2;
            }
        }
        let mut last_top = i32::MAX;
        let row = round_px(TICK_PX) + 4;
        for (y, label) in h.y.iter().zip(&f.y_labels) {
            let Some((_, py)) = l.pixel(l.x_range.0, *y) else {
                continue;
            };
            polyline(area, vec![(l.left - TICK_LEN, py), (l.left, py)], AXIS, 1)?;
            if py + row / 2 <= last_top {
                let baseline = py + round_px(TICK_PX * CAP / 2.0);
                text(
                    area,
                    label,
                    TICK_PX,
                    INK,
                    l.left - TICK_LEN - 3,
                    baseline,
                    Align::Right,
                )?;
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
        title(area, &h.title, h.size.0)?;
        x_label(area, &h.x_label, &l, h.size.1)?;
        y_label(area, &h.y_label, &l)
    })
}

/// The colour bar right of the cells: colour ramp, value ticks and label.
fn color_bar(area: &Area<'_>, f: &HeatFrame, h: &HeatMap) -> Result<(), PlotError> {
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
        let baseline = py + round_px(TICK_PX * CAP / 2.0);
        text(
            area,
            &t.label,
            TICK_PX,
            INK,
            x1 + TICK_LEN + 3,
            baseline,
            Align::Left,
        )?;
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

// ---------------------------------------------------------------------------
// Bar charts.

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

/// `s` cut with an ellipsis to at most `max_px` wide.
fn fit_text(s: &str, size: f64, max_px: i32) -> Result<String, PlotError> {
    if text_width(s, size)? <= max_px {
        return Ok(s.to_string());
    }
    let chars: Vec<char> = s.chars().collect();
    for n in (0..chars.len()).rev() {
        let cut: String = chars[..n].iter().collect::<String>() + "…";
        if text_width(&cut, size)? <= max_px {
            return Ok(cut);
        }
    }
    Ok(String::new())
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
    let mut left = label_room + 40;
    let mut result = None;
    for pass in 0..3 {
        let y_ticks = linear_ticks((lo, hi), bottom - top, 50, false)?;
        let y_w = max_width(y_ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
        let new_left = label_room + y_w + TICK_LEN + 6;
        let layout = Layout {
            left,
            top,
            right: w - 20,
            bottom,
            x_range: (-0.5, f64::from(n) - 0.5),
            y_range: (lo, hi),
            x_log: false,
            y_log: false,
        };
        result = Some(BarFrame {
            layout,
            y_ticks,
            labels: labels.clone(),
            rotated,
        });
        if new_left == left || pass == 2 {
            break;
        }
        left = new_left;
    }
    let Some(frame) = result else {
        return Err(PlotError::NothingToPlot {
            title: b.title.clone(),
        });
    };
    check_area(&frame.layout, b.size)?;
    Ok(frame)
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
                text(
                    area,
                    label,
                    TICK_PX,
                    INK,
                    cx,
                    x_tick_baseline(&l),
                    Align::Center,
                )?;
            }
        }
        if let Some((_, zero)) = l.pixel(0.0, 0.0) {
            polyline(area, vec![(l.left, zero), (l.right, zero)], AXIS, 1)?;
        }
        frame(area, &l)?;
        title(area, &b.title, b.size.0)?;
        y_label(area, &b.y_label, &l)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact() {
        assert_eq!(format_number(1e5, 1e5, true), "1e5");
        assert_eq!(format_number(2.5e5, 5e4, true), "2.5e5");
        assert_eq!(format_number(0.3000000000000004, 0.1, false), "0.3");
        assert_eq!(format_number(-0.0, 0.1, false), "0");
        assert_eq!(format_number(0.25, 0.025, false), "0.25");
        assert_eq!(format_number(0.2, 0.2, false), "0.2");
        assert_eq!(format_number(31622.8, 100.0, false), "31600");
        assert_eq!(format_number(-1.5, 0.5, false), "-1.5");
        assert_eq!(format_number(3e-4, 1e-4, true), "3e-4");
        assert_eq!(format_number(99999.0, 10.0, true), "1e5");
        assert_eq!(format_number(99990.0, 10.0, true), "9.999e4");
        assert_eq!(format_log_value(1000.0, false), "1000");
        assert_eq!(format_log_value(31622.8, false), "31600");
        assert_eq!(format_log_value(31622.8, true), "3.16e4");
        assert_eq!(format_log_value(1e6, true), "1e6");
        assert_eq!(format_log_value(0.01, false), "0.01");
    }

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.13), 0.2);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(finer_step(1.0), 0.5);
        assert_eq!(finer_step(20.0), 10.0);
        assert_eq!(finer_step(0.05), 0.02);
    }

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
