//! What the narrow phases find: where a finger touches a facet.

use glam::DVec3;

/// Where a finger touches a facet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// The contact point on the facet, m.
    pub point: DVec3,
    /// Barycentric weights of `point` on the facet.
    pub weights: [f64; 3],
    /// Unit normal from the finger into the object.
    pub normal: DVec3,
    /// How deep the finger is behind the facet, m.
    pub penetration: f64,
    /// Which of the finger's parts touches (`FingerModel::parts`).
    pub part: usize,
}
