//! Narrow phase, sphere finger against a facet (thesis eq. 18-25): the contact
//! point is the point of the facet closest to the finger centre. When it lies
//! inside the facet this is the foot of the normal through the centre (eq.
//! 21-24, "contact on facet") and the force acts along the facet normal;
//! otherwise it lies on an edge (eq. 25, clamped to the edge's ends) and the
//! force acts along the line from the centre to that point.

use glam::DVec3;

use super::geometry::Geometry;
use crate::geometry::closest_point_on_triangle;

/// Contact of a sphere (centre, radius) with facet `p` (wound outward).
pub fn detect(centre: DVec3, radius: f64, p: [DVec3; 3]) -> Option<Geometry> {
    let (point, weights, interior) = closest_point_on_triangle(centre, p[0], p[1], p[2]);
    let outward = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    if outward == DVec3::ZERO {
        return None;
    }
    if interior {
        // Facet contact: signed distance of the centre above the facet plane.
        let height = (centre - point).dot(outward);
        if height < -0.5 * radius {
            // The centre is far behind this facet: it belongs to another side.
            return None;
        }
        let penetration = radius - height;
        (penetration > 0.0).then_some(Geometry {
            point,
            weights,
            normal: -outward,
            penetration,
            part: 0,
        })
    } else {
        // Edge contact.
        let offset = point - centre;
        let distance = offset.length();
        let penetration = radius - distance;
        if penetration <= 0.0 || distance <= 0.0 {
            return None;
        }
        let normal = offset / distance;
        // Only facets that face the finger: a back facet's edge is someone else's.
        if normal.dot(outward) > 0.5 {
            return None;
        }
        Some(Geometry {
            point,
            weights,
            normal,
            penetration,
            part: 0,
        })
    }
}

/// Gradients of the barycentric coordinates of the contact point's feature:
/// the triangle's for a face contact, the edge's (along it) for an edge
/// contact, none for a vertex contact.
pub fn barycentric_gradients(p: [DVec3; 3], weights: [f64; 3]) -> [DVec3; 3] {
    let zero_count = weights.iter().filter(|w| **w == 0.0).count();
    match zero_count {
        0 => {
            let normal2a = (p[1] - p[0]).cross(p[2] - p[0]);
            let twice_area = normal2a.length();
            if twice_area <= 0.0 {
                return [DVec3::ZERO; 3];
            }
            let n = normal2a / twice_area;
            std::array::from_fn(|a| n.cross(p[(a + 2) % 3] - p[(a + 1) % 3]) / twice_area)
        }
        1 => {
            // Edge between the two vertices with non-zero weight.
            let mut g = [DVec3::ZERO; 3];
            let idx: Vec<usize> = (0..3).filter(|&a| weights[a] != 0.0).collect();
            let (a, b) = (idx[0], idx[1]);
            let e = p[b] - p[a];
            let l2 = e.length_squared();
            if l2 > 0.0 {
                g[b] = e / l2;
                g[a] = -e / l2;
            }
            g
        }
        _ => [DVec3::ZERO; 3],
    }
}
