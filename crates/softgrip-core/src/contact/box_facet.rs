//! Narrow phase, box finger against a facet. The box is rigid and
//! axis-aligned, centred on the finger, with half-extents `h`. As for the
//! plate, a facet is in contact at its centroid (weights 1/3 each) when the
//! centroid is inside the box; it is pushed out through the face it looks at
//! most squarely (its outward normal most against the face's), along that
//! face's outward normal, by its depth behind that face.
//!
//! Not the face it is least deep behind, as for a point in a box: a soft
//! side pressed by the box wraps around its edges, and side facets whose
//! centroids crossed into the box just under its top face were pushed up
//! through it. The box's edges then carried a squeezed cube like hooks,
//! whatever the friction (`tests/grasp.rs` lifted it at mu = 0.02, where
//! the force balance needs 0.14).

use glam::DVec3;

use super::geometry::Geometry;

/// The contact of a box centred at `centre` with half sizes `h` (m) with facet `p`, if any.
pub fn detect(centre: DVec3, h: [f64; 3], p: [DVec3; 3]) -> Option<Geometry> {
    let outward = (p[1] - p[0]).cross(p[2] - p[0]);
    let centroid = (p[0] + p[1] + p[2]) / 3.0;
    let local = centroid - centre;
    if (0..3).any(|a| local[a].abs() >= h[a]) {
        return None;
    }
    let mut best: Option<(f64, usize, f64)> = None;
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let facing = -sign * outward[axis];
            if facing > 0.0 && best.is_none_or(|(f, _, _)| facing > f) {
                best = Some((facing, axis, sign));
            }
        }
    }
    let best = best.map(|(_, axis, sign)| {
        let mut n = DVec3::ZERO;
        n[axis] = sign;
        (h[axis] - sign * local[axis], n)
    });
    best.map(|(penetration, normal)| Geometry {
        point: centroid,
        weights: [1.0 / 3.0; 3],
        normal,
        penetration,
        part: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An upward-facing facet 1 mm inside the bottom of a box is pushed down
    /// through the bottom face; one facing down is pushed up through the
    /// top face, however deep; a side facet through the side, even next to
    /// the top face.
    #[test]
    fn a_facet_is_pushed_out_through_the_face_it_looks_at() {
        let centre = DVec3::new(0.0, 0.0, 0.05);
        let h = [0.01, 0.02, 0.01];
        let z = 0.041;
        let up = [
            DVec3::new(-0.001, -0.001, z),
            DVec3::new(0.002, -0.001, z),
            DVec3::new(-0.001, 0.002, z),
        ];
        let g = detect(centre, h, up).expect("inside");
        assert_eq!(g.normal, DVec3::NEG_Z);
        assert!((g.penetration - 0.001).abs() < 1e-12);
        let down = [up[0], up[2], up[1]];
        let g = detect(centre, h, down).expect("inside");
        assert_eq!(g.normal, DVec3::Z, "a downward facet looks at the top face");
        assert!((g.penetration - 0.019).abs() < 1e-12);
        // A side facet (normal -x) near the +x face is pushed along +x.
        let side = [
            DVec3::new(0.009, 0.0, 0.049),
            DVec3::new(0.009, 0.001, 0.051),
            DVec3::new(0.009, -0.001, 0.051),
        ];
        let n = (side[1] - side[0]).cross(side[2] - side[0]);
        let side = if n.x < 0.0 {
            side
        } else {
            [side[0], side[2], side[1]]
        };
        let g = detect(centre, h, side).expect("inside");
        assert_eq!(g.normal, DVec3::X);
        assert!((g.penetration - 0.001).abs() < 1e-12);
        let near_top = side.map(|p| p + DVec3::Z * 0.0095);
        let g = detect(centre, h, near_top).expect("inside");
        assert_eq!(
            g.normal,
            DVec3::X,
            "not up through the top face 0.5 mm away"
        );
        // Outside: nothing.
        let out = up.map(|p| p + DVec3::Z * 0.03);
        assert!(detect(centre, h, out).is_none());
    }
}
