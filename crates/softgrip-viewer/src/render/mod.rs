//! The 3-D view: what is drawn (`geometry`), from where (`camera`), and the
//! wgpu renderer (`gpu`), shared by the viewer and `softgrip screenshot`.
//! Behind the `gui` feature; the simulation core does not depend on it.

pub mod camera;
pub mod geometry;
pub mod gpu;
pub mod markers;
pub mod pick;

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
    Ok(image)
}

/// The colour map's bar down the right edge of `image`: its maximum at
/// the top, its minimum at the bottom, framed in dark grey. (The numbers
/// are the caller's to print; the viewer draws them beside its bar.)
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
}

/// The byte the renderer writes for a colour channel (the target is
/// `Rgba8Unorm`: the value as it is).
fn to_srgb_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u8
}
