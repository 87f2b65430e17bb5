//! The contact stage's broad phase: a uniform grid over the boundary facets' bounding boxes, so
//! that only facets near a finger reach the narrow phase. Rebuilt every step
//! into buffers that keep their capacity.

use glam::{DVec3, IVec3};

/// A uniform grid of cubes binning the boundary facets by their bounding boxes.
#[derive(Debug, Default, Clone)]
pub struct FacetGrid {
    cell: f64,
    /// (cell key, facet), sorted by key.
    entries: Vec<(u64, u32)>,
    stamp: Vec<u32>,
    generation: u32,
}

fn key(c: IVec3) -> u64 {
    // 21 bits per axis, offset so negative cells map to positive numbers.
    let m = |v: i32| ((v + (1 << 20)) as u64) & 0x1F_FFFF;
    m(c.x) | (m(c.y) << 21) | (m(c.z) << 42)
}

impl FacetGrid {
    fn cell_of(&self, p: DVec3) -> IVec3 {
        (p / self.cell).floor().as_ivec3()
    }

    /// Bins every facet by its bounding box; `cell` about twice the facet size.
    pub fn rebuild(&mut self, cell: f64, facets: &[[u32; 3]], positions: &[DVec3]) {
        self.cell = cell;
        self.entries.clear();
        for (f, tri) in facets.iter().enumerate() {
            let p = tri.map(|i| positions[i as usize]);
            let lo = self.cell_of(p[0].min(p[1]).min(p[2]));
            let hi = self.cell_of(p[0].max(p[1]).max(p[2]));
            // A facet stretched over many cells (a wild state) is binned by its
            // corners' range anyway; clamp the loop so it stays cheap.
            let span = (hi - lo).min(IVec3::splat(16));
            for z in 0..=span.z {
                for y in 0..=span.y {
                    for x in 0..=span.x {
                        self.entries.push((key(lo + IVec3::new(x, y, z)), f as u32));
                    }
                }
            }
        }
        self.entries.sort_unstable();
        if self.stamp.len() != facets.len() {
            self.stamp = vec![0; facets.len()];
            self.generation = 0;
        }
    }

    /// Facets whose cells overlap the box `[lo, hi]`, sorted, each once.
    pub fn query(&mut self, lo: DVec3, hi: DVec3, out: &mut Vec<u32>) {
        out.clear();
        if self.cell <= 0.0 {
            return;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.fill(0);
            self.generation = 1;
        }
        let (a, b) = (self.cell_of(lo), self.cell_of(hi));
        let b = b.min(a + IVec3::splat(256));
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                for x in a.x..=b.x {
                    let k = key(IVec3::new(x, y, z));
                    let start = self.entries.partition_point(|e| e.0 < k);
                    for &(ek, f) in &self.entries[start..] {
                        if ek != k {
                            break;
                        }
                        if self.stamp[f as usize] != self.generation {
                            self.stamp[f as usize] = self.generation;
                            out.push(f);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_facets_near_a_box() {
        // A row of unit triangles along x.
        let mut positions = Vec::new();
        let mut facets = Vec::new();
        for i in 0..20 {
            let x = i as f64;
            let b = positions.len() as u32;
            positions.extend([
                DVec3::new(x, 0.0, 0.0),
                DVec3::new(x + 0.9, 0.0, 0.0),
                DVec3::new(x, 0.9, 0.0),
            ]);
            facets.push([b, b + 1, b + 2]);
        }
        let mut grid = FacetGrid::default();
        grid.rebuild(2.0, &facets, &positions);
        let mut out = Vec::new();
        grid.query(
            DVec3::new(7.5, -0.5, -0.5),
            DVec3::new(9.5, 0.5, 0.5),
            &mut out,
        );
        // Everything in cells 3..=4 along x (x in [6, 10)) is reported; 7, 8, 9 must be.
        for f in [7, 8, 9] {
            assert!(out.contains(&f), "{out:?}");
        }
        assert!(out.iter().all(|&f| (5..=10).contains(&f)), "{out:?}");
    }
}
