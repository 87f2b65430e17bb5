//! Picking and dragging with the mouse: the ray under a pixel, what it
//! hits first (a finger or a boundary facet of the object), and where a
//! dragged point goes in the plane facing the camera. Plain geometry, no
//! GPU: the viewer uses it, and `tests/picking.rs` checks it.

use glam::DVec3;

use super::camera::Camera;
use softgrip_core::model::{AxisDrive, Model};
use softgrip_core::scene::FingerShape;
use softgrip_core::state::State;

/// A half-line from the eye through a pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Where it starts: the pixel on the near plane, world m.
    pub origin: DVec3,
    /// Unit length.
    pub direction: DVec3,
}

/// What the mouse grabbed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Picked {
    /// A finger, hit at `point`.
    Finger {
        /// The finger's index in `Model::fingers`.
        index: usize,
        /// Where the ray hit it, world m.
        point: DVec3,
    },
    /// A boundary facet of the object at the material point with these
    /// barycentric weights.
    Object {
        /// The facet's index in `Model::facets`.
        facet: u32,
        /// Barycentric weights of the hit over the facet's three particles (sum 1).
        weights: [f64; 3],
        /// Where the ray hit it, world m.
        point: DVec3,
    },
}

impl Picked {
    /// Where the ray hit what it grabbed, world m.
    pub fn point(&self) -> DVec3 {
        match *self {
            Picked::Finger { point, .. } | Picked::Object { point, .. } => point,
        }
    }
}

impl Camera {
    /// The ray through pixel `(x, y)` (x right, y down) of a `width` x
    /// `height` image.
    pub fn ray(&self, x: f32, y: f32, width: u32, height: u32) -> Ray {
        let inverse = self.view_projection(width as f32 / height as f32).inverse();
        let ndc_x = 2.0 * x / width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / height as f32;
        let near = inverse.project_point3(glam::Vec3::new(ndc_x, ndc_y, 0.0));
        let far = inverse.project_point3(glam::Vec3::new(ndc_x, ndc_y, 1.0));
        let origin = near.as_dvec3();
        Ray {
            origin,
            direction: (far.as_dvec3() - origin).normalize_or_zero(),
        }
    }

    /// Unit vector from the eye towards the target.
    pub fn forward(&self) -> DVec3 {
        (self.target - self.eye()).as_dvec3().normalize_or_zero()
    }
}

/// The nearest finger or boundary facet along `ray` (fingers drawn with
/// `plate_thickness`, as `geometry::build` draws them).
pub fn pick(model: &Model, state: &State, ray: &Ray, plate_thickness: f64) -> Option<Picked> {
    let mut best: Option<(f64, Picked)> = None;
    let mut consider = |t: f64, picked: Picked| {
        if best.is_none_or(|(b, _)| t < b) {
            best = Some((t, picked));
        }
    };
    for (index, (f, fs)) in model.fingers.iter().zip(&state.fingers).enumerate() {
        let hit = |part: &softgrip_core::model::PartModel| {
            let at = fs.position + part.offset;
            match part.shape {
                FingerShape::Sphere { radius } => hit_sphere(ray, at, radius),
                FingerShape::Plate { half_size } => {
                    let h = DVec3::new(half_size[0], half_size[1], 0.0);
                    hit_box(ray, at - h, at + h + DVec3::Z * plate_thickness)
                }
                FingerShape::Box { half_size } => {
                    let h = DVec3::from_array(half_size);
                    hit_box(ray, at - h, at + h)
                }
            }
        };
        let t = f.parts.iter().filter_map(hit).reduce(f64::min);
        if let Some(t) = t {
            consider(
                t,
                Picked::Finger {
                    index,
                    point: ray.origin + t * ray.direction,
                },
            );
        }
    }
    for (j, tri) in model.facets.iter().enumerate() {
        let p = tri.map(|i| state.positions[i as usize]);
        if let Some((t, weights)) = hit_triangle(ray, p) {
            consider(
                t,
                Picked::Object {
                    facet: j as u32,
                    weights,
                    point: ray.origin + t * ray.direction,
                },
            );
        }
    }
    best.map(|(_, p)| p)
}

/// Where the ray meets the plane through `point` with normal `normal`.
pub fn on_plane(ray: &Ray, point: DVec3, normal: DVec3) -> Option<DVec3> {
    let denom = ray.direction.dot(normal);
    if denom.abs() < 1e-9 {
        return None;
    }
    let t = (point - ray.origin).dot(normal) / denom;
    (t > 0.0).then(|| ray.origin + t * ray.direction)
}

/// Where a finger grabbed at `grabbed` (its centre then `centre`) is held
/// when the mouse ray is `ray`: moved with the mouse in the plane facing
/// the camera (normal `facing`), along its free axes only.
pub fn finger_target(
    model: &Model,
    finger: usize,
    centre: DVec3,
    grabbed: DVec3,
    facing: DVec3,
    ray: &Ray,
) -> Option<DVec3> {
    let f = model.fingers.get(finger)?;
    let now = on_plane(ray, grabbed, facing)?;
    let moved = centre + (now - grabbed);
    Some(DVec3::from_array(std::array::from_fn(|a| {
        if f.drive[a] == AxisDrive::Locked {
            centre[a]
        } else {
            moved[a]
        }
    })))
}

fn hit_sphere(ray: &Ray, centre: DVec3, radius: f64) -> Option<f64> {
    let oc = ray.origin - centre;
    let b = oc.dot(ray.direction);
    let c = oc.length_squared() - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    [-b - s, -b + s].into_iter().find(|t| *t > 0.0)
}

fn hit_box(ray: &Ray, lo: DVec3, hi: DVec3) -> Option<f64> {
    let mut t0 = 0.0f64;
    let mut t1 = f64::INFINITY;
    for a in 0..3 {
        let d = ray.direction[a];
        if d.abs() < 1e-15 {
            if ray.origin[a] < lo[a] || ray.origin[a] > hi[a] {
                return None;
            }
            continue;
        }
        let (mut ta, mut tb) = ((lo[a] - ray.origin[a]) / d, (hi[a] - ray.origin[a]) / d);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        t0 = t0.max(ta);
        t1 = t1.min(tb);
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}

/// Moller-Trumbore: distance along the ray and barycentric weights.
fn hit_triangle(ray: &Ray, p: [DVec3; 3]) -> Option<(f64, [f64; 3])> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let h = ray.direction.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-18 {
        return None;
    }
    let s = ray.origin - p[0];
    let u = s.dot(h) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.direction.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) / det;
    (t > 0.0).then_some((t, [1.0 - u - v, u, v]))
}
