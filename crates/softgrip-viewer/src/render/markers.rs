//! The recording overlay: each recorded marker (magenta), the simulated
//! marker it is compared with (dark blue) and the residual from one to
//! the other (a thin black arrow, and a line for residuals thinner than
//! a pixel), drawn over a replayed sample in the viewer.

use glam::{DVec3, Vec3};

use super::geometry::{Drawing, Mesh, bounds_size};
use softgrip_core::model::Model;

/// Recorded markers: magenta, which nothing else in the view uses.
pub const RECORDED: [f32; 4] = [0.92, 0.08, 0.88, 1.0];
/// Simulated markers: dark blue, distinct from the object and the fingers.
pub const SIMULATED: [f32; 4] = [0.08, 0.12, 0.45, 1.0];
/// The residual from simulated to recorded: near black, which shows on
/// the object's colours and on every colour map.
pub const RESIDUAL: [f32; 4] = [0.06, 0.06, 0.06, 1.0];

/// Radii as fractions of the object's extent: the recorded sphere larger,
/// so that a simulated marker on top of it (a residual of zero) still
/// shows the recorded colour round it.
const RECORDED_RADIUS: f32 = 0.02;
const SIMULATED_RADIUS: f32 = 0.013;
const RESIDUAL_RADIUS: f32 = 0.004;
/// Opacity of a marker where the object hides it (a recorded marker
/// inside the surface, markers on the far side).
const XRAY_ALPHA: f32 = 0.35;

/// One compared marker of a sample (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarkerPair {
    /// The simulated position (m).
    pub simulated: DVec3,
    /// The recorded position over the observed axes, the simulated
    /// coordinate on an unobserved one (so that the residual is what
    /// NRMSE counts).
    pub recorded: DVec3,
}

impl MarkerPair {
    /// Where the recorded marker is drawn when residuals are drawn
    /// `exaggerate` times longer than they are (1: where it was recorded).
    pub fn drawn_recorded(&self, exaggerate: f64) -> DVec3 {
        self.simulated + exaggerate * (self.recorded - self.simulated)
    }
}

/// Adds the markers and their residuals to `drawing` (opaque spheres and
/// arrows, the same faint in the x-ray layer, and lines); `exaggerate`
/// lengthens the residuals, which are a fraction of a millimetre on a
/// good fit, too short to see.
pub fn add_markers(drawing: &mut Drawing, model: &Model, pairs: &[MarkerPair], exaggerate: f64) {
    let scale = bounds_size(model).max(1e-3);
    let recorded_radius = RECORDED_RADIUS * scale;
    let mut solid = Mesh::default();
    for pair in pairs {
        let from = pair.simulated.as_vec3();
        let to = pair.drawn_recorded(exaggerate).as_vec3();
        solid.add_sphere(to, recorded_radius, RECORDED);
        solid.add_sphere(from, SIMULATED_RADIUS * scale, SIMULATED);
        let residual = to - from;
        let length = residual.length();
        if length > recorded_radius {
            // The arrow's tip on the recorded sphere's surface, so its
            // head shows.
            let shortened = residual * ((length - recorded_radius) / length);
            solid.add_arrow(from, shortened, RESIDUAL_RADIUS * scale, RESIDUAL);
        }
        if length > 0.0 {
            for p in [from, to] {
                drawing.lines.vertices.push(super::Vertex {
                    position: p.to_array(),
                    normal: Vec3::ZERO.to_array(),
                    color: RESIDUAL,
                });
                let at = drawing.lines.vertices.len() as u32 - 1;
                drawing.lines.indices.push(at);
            }
        }
    }
    append(&mut drawing.xray, &solid, Some(XRAY_ALPHA));
    append(&mut drawing.opaque, &solid, None);
}

/// Appends `src` to `dst`, with every vertex's alpha set to `alpha` if
/// given.
fn append(dst: &mut Mesh, src: &Mesh, alpha: Option<f32>) {
    let base = dst.vertices.len() as u32;
    dst.vertices.extend(src.vertices.iter().map(|v| {
        let mut v = *v;
        if let Some(a) = alpha {
            v.color[3] = a;
        }
        v
    }));
    dst.indices.extend(src.indices.iter().map(|i| base + i));
}
