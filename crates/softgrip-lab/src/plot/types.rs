//! What a plot shows: charts of series, heat maps and bar charts.

use super::style::DEFAULT_SIZE;

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
    /// sRGB colour, e.g. from [`palette`](super::palette).
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
    /// Spans of x shaded over the plot's height, `(x0, x1, color)`, drawn under the series (a
    /// window, a range).
    pub x_bands: Vec<(f64, f64, [u8; 3])>,
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
            x_bands: Vec::new(),
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
    /// Bar colours; missing entries take [`palette`](super::palette) colours.
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
