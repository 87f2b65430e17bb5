//! The 3-D view: what is drawn (`geometry`), from where (`camera`), and the
//! wgpu renderer (`gpu`), shared by the viewer and `softgrip screenshot`.
//! Behind the `gui` feature; the simulation core does not depend on it.

pub mod camera;
pub mod geometry;
pub mod gpu;
pub mod markers;
pub mod pick;
pub mod text;

pub use camera::{Camera, View};
pub use geometry::{Cut, Drawing, Legend, Mesh, Style, Vertex};
pub use gpu::{Offscreen, RenderError};

use glam::DVec3;

use softgrip_core::model::Model;
use softgrip_core::state::State;

/// A camera on `view` that frames the object and its fingers.
pub fn frame_camera(model: &Model, state: &State, view: View) -> Camera {
    frame_camera_aspect(model, state, view, 1.0)
}

/// As [`frame_camera`], for an image of this width / height.
pub fn frame_camera_aspect(model: &Model, state: &State, view: View, aspect: f32) -> Camera {
    let (mut lo, mut hi) = softgrip_core::mesh::bounds_of(&state.positions);
    for (f, fs) in model.fingers.iter().zip(&state.fingers) {
        let reach = DVec3::splat(f.shape.reach().max(0.002));
        lo = lo.min(fs.position - reach);
        hi = hi.max(fs.position + reach);
    }
    Camera::framing_aspect(lo.as_vec3(), hi.as_vec3(), view, aspect)
}

/// Renders `state` of `model` headless into a `width` x `height` image.
pub fn screenshot(
    model: &Model,
    state: &State,
    view: View,
    width: u32,
    height: u32,
    style: &Style,
) -> Result<image::RgbaImage, RenderError> {
    let renderer = Offscreen::new(width, height)?;
    let drawing = geometry::build(model, state, style);
    let mut image = renderer.render(&drawing, &frame_camera(model, state, view))?;
    if let Some(legend) = &drawing.legend {
        draw_legend_bar(&mut image, legend);
    }
    draw_key(&mut image, state, style);
    Ok(image)
}

/// The colour map's bar down the right edge of `image`: its maximum at the top, its minimum at
/// the bottom, framed in dark grey, with five ticks and their values to its left and the field
/// and its unit above it.
pub fn draw_legend_bar(image: &mut image::RgbaImage, legend: &Legend) {
    let (w, h) = image.dimensions();
    let bar_w = (w / 40).max(6);
    let top = h / 5;
    let bottom = h - h / 5;
    let right = w.saturating_sub(bar_w);
    let left = right.saturating_sub(bar_w);
    for y in top.saturating_sub(1)..=bottom.min(h - 1) {
        for x in left.saturating_sub(1)..=right.min(w - 1) {
            let frame = y < top || y == bottom || x < left || x == right;
            let t = f64::from(bottom - y) / f64::from((bottom - top).max(1));
            let c = if frame {
                [60, 60, 64, 255]
            } else {
                let v = legend.min + t * (legend.max - legend.min);
                let [r, g, b, _] = legend.color(v);
                [to_srgb_byte(r), to_srgb_byte(g), to_srgb_byte(b), 255]
            };
            image.put_pixel(x, y, image::Rgba(c));
        }
    }
    let px = (h as f32 / 36.0).clamp(10.0, 20.0);
    let ink = [30, 30, 34];
    let k = legend.field.display_scale();
    for i in 0..=4 {
        let t = f64::from(i) / 4.0;
        let y = bottom as f32 - t as f32 * (bottom - top) as f32;
        let label = format!("{:.3}", (legend.min + t * (legend.max - legend.min)) * k);
        let x = left as f32 - 6.0 - text::width(&label, px);
        text::draw(image, x, y + 0.35 * px, px, &label, ink);
        for dx in 1..=4 {
            if let Some(x) = left.checked_sub(dx) {
                image.put_pixel(x, (y as u32).min(h - 1), image::Rgba([60, 60, 64, 255]));
            }
        }
    }
    let title = format!("{} ({})", legend.field.label(), legend.field.unit());
    let x = (right as f32 - text::width(&title, px)).max(2.0);
    text::draw(image, x, top as f32 - 0.8 * px, px, &title, ink);
}

/// A key in the lower left of `image` for the arrows and points drawn for `state`: what the
/// colours mean (the purple arrow is the force on a finger).
pub fn draw_key(image: &mut image::RgbaImage, state: &State, style: &Style) {
    let forces = state.fingers.iter().any(|f| f.contact_force != DVec3::ZERO);
    let contacts = !state.contacts.is_empty();
    let mut entries: Vec<([f32; 4], &str)> = Vec::new();
    if style.arrows && forces {
        entries.push((style.finger_force, "force on the finger"));
        if contacts {
            entries.push((style.normal_force, "contact force, normal"));
            entries.push((style.tangential_force, "contact force, tangential"));
        }
    }
    if style.contacts && state.contacts.iter().any(|c| c.stick >= 0.5) {
        entries.push((style.stick, "contact sticking"));
    }
    if style.contacts && state.contacts.iter().any(|c| c.stick < 0.5) {
        entries.push((style.slip, "contact slipping"));
    }
    if entries.is_empty() {
        return;
    }
    let (_, h) = image.dimensions();
    let px = (h as f32 / 40.0).clamp(9.0, 18.0);
    let line = 1.4 * px;
    let x0 = 0.6 * px;
    let mut y = h as f32 - 0.6 * px - line * (entries.len() as f32 - 1.0);
    for (color, label) in entries {
        let c = [
            to_srgb_byte(color[0]),
            to_srgb_byte(color[1]),
            to_srgb_byte(color[2]),
            255,
        ];
        let side = (0.8 * px) as u32;
        let (sx, sy) = (x0 as u32, (y - 0.8 * px).max(0.0) as u32);
        for yy in sy..(sy + side).min(h) {
            for xx in sx..(sx + side).min(image.width()) {
                image.put_pixel(xx, yy, image::Rgba(c));
            }
        }
        text::draw(image, x0 + 1.3 * px, y, px, label, [30, 30, 34]);
        y += line;
    }
}

/// The byte the renderer writes for a colour channel (the target is
/// `Rgba8Unorm`: the value as it is).
fn to_srgb_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u8
}
