//! The RGB canvas plotters draws on, its PNG encoding, and the drawing
//! primitives every plot uses.

use std::path::Path;

use plotters::backend::{BitMapBackend, DrawingBackend, RGBPixel, SVGBackend};
use plotters::coord::Shift;
use plotters::drawing::{DrawingArea, IntoDrawingArea};
use plotters::element::{Circle, PathElement, Rectangle};
use plotters::style::{Color, RGBColor};

use super::error::PlotError;
use super::style::WHITE;

/// Writes PNG bytes (from [`chart_png`](super::chart_png) and the others) to `path`; the error
/// names the path. Parent directories must exist.
pub fn write_png(path: &Path, png: &[u8]) -> Result<(), PlotError> {
    std::fs::write(path, png).map_err(|source| PlotError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// What every plot draws on: a bitmap for PNG, an SVG document for SVG.
pub(super) type Area<DB> = DrawingArea<DB, Shift>;

pub(super) fn draw_err(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
}

pub(super) fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// Draws on a white SVG canvas of `size`: the same plot as [`render`]'s PNG, as vectors.
pub(super) fn render_svg(
    size: (u32, u32),
    draw: impl FnOnce(&Area<SVGBackend<'_>>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        area.fill(&WHITE).map_err(draw_err)?;
        draw(&area)?;
        area.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Draws on a white RGB canvas of `size` and encodes it as PNG.
pub(super) fn render(
    size: (u32, u32),
    draw: impl FnOnce(&Area<BitMapBackend<'_, RGBPixel>>) -> Result<(), PlotError>,
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

pub(super) fn polyline<DB: DrawingBackend>(
    area: &Area<DB>,
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

pub(super) fn dot<DB: DrawingBackend>(
    area: &Area<DB>,
    p: (i32, i32),
    r: i32,
    color: RGBColor,
) -> Result<(), PlotError> {
    area.draw(&Circle::new(p, r, color.filled()))
        .map_err(draw_err)
}

/// Filled rectangle covering columns `x0..x1` and rows `y0..y1` (end exclusive).
pub(super) fn fill_rect<DB: DrawingBackend>(
    area: &Area<DB>,
    (x0, y0): (i32, i32),
    (x1, y1): (i32, i32),
    color: RGBColor,
) -> Result<(), PlotError> {
    area.draw(&Rectangle::new([(x0, y0), (x1, y1)], color.filled()))
        .map_err(draw_err)
}
