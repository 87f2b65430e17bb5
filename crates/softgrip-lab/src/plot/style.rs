//! Sizes, text sizes, spacing and colours shared by every plot.

use plotters::style::RGBColor;

/// The size used by `Default`: 800 x 500 px reads well in a Markdown report.
pub const DEFAULT_SIZE: (u32, u32) = (800, 500);
/// Smallest accepted image, in px: below it the labels leave no plot area.
pub const MIN_SIZE: (u32, u32) = (200, 150);
/// Largest accepted image, in px, per side (keeps the buffer under 300 MB).
pub const MAX_SIDE: u32 = 10_000;

// Text sizes in px (plotters' ab_glyph size: ascender to descender). Keep
// them even: plotters truncates size/2 plus each glyph's top to whole pixels,
// which with an odd size lifts some glyphs (a "." drawn as a raised dot).
pub(super) const TITLE_PX: f64 = 18.0;
pub(super) const LABEL_PX: f64 = 14.0;
pub(super) const TICK_PX: f64 = 12.0;
// DejaVu Sans: cap height and descender as fractions of that size.
pub(super) const CAP: f64 = 0.63;
pub(super) const DESCENT: f64 = 0.21;
pub(super) const PAD: i32 = 8;
pub(super) const TICK_LEN: i32 = 5;

pub(super) const WHITE: RGBColor = RGBColor(255, 255, 255);
pub(super) const INK: RGBColor = RGBColor(30, 30, 30);
pub(super) const AXIS: RGBColor = RGBColor(90, 90, 90);
pub(super) const GRID: RGBColor = RGBColor(228, 228, 228);
/// Heat-map cells without a value.
pub(super) const NO_VALUE: RGBColor = RGBColor(170, 170, 170);

/// A distinguishable colour for series `k`: Tableau 10 (matplotlib's default
/// cycle), readable on white; repeats after ten.
pub fn palette(k: usize) -> [u8; 3] {
    // Tableau 10, then its lighter partners (Tableau 20's): twenty markers, twenty colours.
    const TABLEAU_20: [[u8; 3]; 20] = [
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
        [174, 199, 232],
        [255, 187, 120],
        [152, 223, 138],
        [255, 152, 150],
        [197, 176, 213],
        [196, 156, 148],
        [247, 182, 210],
        [199, 199, 199],
        [219, 219, 141],
        [158, 218, 229],
    ];
    TABLEAU_20[k % TABLEAU_20.len()]
}
