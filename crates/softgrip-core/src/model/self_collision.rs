//! Self-collision's constant data (`[model] self_collision`): the boundary particles, the
//! contact thickness and stiffness, and the particle-facet pairs that touch at rest and so never
//! collide. Its forces are `crate::contact::self_collision`'s.

use glam::DVec3;

use crate::geometry::{FacetGrid, closest_point_on_triangle};

/// The penalty stiffness per contact in units of `E h` (as the table's).
pub const SELF_STIFFNESS_FACTOR: f64 = 100.0;
/// The contact thickness as a fraction of the mean edge length.
pub const SELF_THICKNESS: f64 = 0.25;

/// Self-collision's constant data: the contact's thickness and stiffness, the boundary
/// particles, and the particle-facet pairs that never collide.
#[derive(Debug, Clone, PartialEq)]
pub struct SelfCollisionModel {
    /// Contact thickness d, m: [`SELF_THICKNESS`] times the edge length.
    pub thickness: f64,
    /// Penalty stiffness k per contact, N/m: [`SELF_STIFFNESS_FACTOR`] `E h`.
    pub stiffness: f64,
    /// Boundary particles, ascending.
    pub particles: Vec<u32>,
    /// (particle, facet) pairs that never collide, sorted.
    pub excluded: Vec<(u32, u32)>,
}

impl SelfCollisionModel {
    /// From the rest positions (m), the boundary facets, the edge length h (m) and Young's
    /// modulus E (Pa): the pairs closer than the thickness at rest are excluded.
    pub fn new(
        nodes: &[DVec3],
        facets: &[[u32; 3]],
        edge_length: f64,
        young_modulus: f64,
    ) -> SelfCollisionModel {
        let thickness = SELF_THICKNESS * edge_length;
        let mut particles: Vec<u32> = facets.iter().flatten().copied().collect();
        particles.sort_unstable();
        particles.dedup();
        let mut grid = FacetGrid::default();
        grid.rebuild(2.0 * edge_length, facets, nodes);
        let mut candidates = Vec::new();
        let mut excluded = Vec::new();
        for &p in &particles {
            let x = nodes[p as usize];
            let pad = DVec3::splat(thickness);
            grid.query(x - pad, x + pad, &mut candidates);
            for &f in &candidates {
                let tri = facets[f as usize];
                let near = tri.contains(&p) || {
                    let t = tri.map(|i| nodes[i as usize]);
                    let (c, _, _) = closest_point_on_triangle(x, t[0], t[1], t[2]);
                    x.distance(c) < thickness
                };
                if near {
                    excluded.push((p, f));
                }
            }
        }
        excluded.sort_unstable();
        SelfCollisionModel {
            thickness,
            stiffness: SELF_STIFFNESS_FACTOR * young_modulus * edge_length,
            particles,
            excluded,
        }
    }
}
