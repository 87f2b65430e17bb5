//! The 3-D view: what is drawn (`geometry`), from where (`camera`), and the
//! wgpu renderer (`gpu`), shared by the viewer and `softgrip screenshot`.
//! Behind the `gui` feature; the simulation core does not depend on it.

pub mod camera;
pub mod geometry;
pub mod gpu;
pub mod pick;

pub use camera::{Camera, View};
pub use geometry::{Drawing, Mesh, Style, Vertex};
pub use gpu::{Offscreen, RenderError};

use glam::DVec3;

use crate::model::Model;
use crate::state::State;

/// A camera on `view` that frames the object and its fingers.
pub fn frame_camera(model: &Model, state: &State, view: View) -> Camera {
    let (mut lo, mut hi) = crate::mesh::bounds_of(&state.positions);
    for (f, fs) in model.fingers.iter().zip(&state.fingers) {
        let reach = DVec3::splat(f.shape.reach().max(0.002));
        lo = lo.min(fs.position - reach);
        hi = hi.max(fs.position + reach);
    }
    Camera::framing(lo.as_vec3(), hi.as_vec3(), view)
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
    renderer.render(&drawing, &frame_camera(model, state, view))
}
