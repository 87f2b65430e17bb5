//! Text in the embedded font: metrics, and glyph-by-glyph drawing.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::element::Text;
use plotters::style::{
    Color, FontFamily, FontStyle, FontTransform, IntoFont, RGBColor, TextStyle, register_font,
};

use super::canvas::{Area, draw_err};
use super::error::PlotError;
use super::layout::round_px;
use plotters::backend::DrawingBackend;

/// DejaVu Sans, embedded so plots look the same on every machine.
const FONT_BYTES: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");
/// The name the font is registered under in plotters' font table.
pub(super) const FAMILY: &str = "softgrip-dejavu-sans";

/// Registers the embedded font with plotters once per process.
pub(super) fn ensure_font() -> Result<(), PlotError> {
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
pub(super) fn text_width(s: &str, size: f64) -> Result<i32, PlotError> {
    glyph_offsets(s, size).map(|(_, w)| w)
}

/// The widest of `labels` at `size`, in px.
pub(super) fn max_width<'a>(
    labels: impl IntoIterator<Item = &'a str>,
    size: f64,
) -> Result<i32, PlotError> {
    let mut w = 0;
    for s in labels {
        w = w.max(text_width(s, size)?);
    }
    Ok(w)
}

#[derive(Clone, Copy)]
pub(super) enum Align {
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
pub(super) fn text<DB: DrawingBackend>(
    area: &Area<DB>,
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
pub(super) fn text_up<DB: DrawingBackend>(
    area: &Area<DB>,
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

/// `s` cut with an ellipsis to at most `max_px` wide.
pub(super) fn fit_text(s: &str, size: f64, max_px: i32) -> Result<String, PlotError> {
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
