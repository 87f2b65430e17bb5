//! Narrow phase, plate finger against a facet. The plate is a rigid square of
//! half-extents `(hx, hy)` whose face, normal -z, is at the finger's z. A facet
//! that faces up and whose centroid is under the plate and above its face is
//! in contact at its centroid (weights 1/3 each, the thesis's H at that point),
//! pushed along -z.

use glam::DVec3;

use super::geometry::Geometry;

/// The contact of a plate centred at `centre` (half sizes `half_size` in x and y, m; facets
/// deeper than `max_depth` behind it are not touched) with facet `p`, if any.
pub fn detect(
    centre: DVec3,
    half_size: [f64; 2],
    max_depth: f64,
    p: [DVec3; 3],
) -> Option<Geometry> {
    let outward = (p[1] - p[0]).cross(p[2] - p[0]);
    if outward.z <= 0.0 {
        return None;
    }
    let centroid = (p[0] + p[1] + p[2]) / 3.0;
    if (centroid.x - centre.x).abs() > half_size[0] || (centroid.y - centre.y).abs() > half_size[1]
    {
        return None;
    }
    let penetration = centroid.z - centre.z;
    (penetration > 0.0 && penetration < max_depth).then_some(Geometry {
        point: centroid,
        weights: [1.0 / 3.0; 3],
        normal: DVec3::NEG_Z,
        penetration,
        part: 0,
    })
}
