//! Regions of other stiffness found from the data: the object's bounding box cut into a grid of
//! [`CELLS`] cells an axis, the markers' sensitivity to each cell's modulus taken from the
//! screen's one replay (the same factor), and every box of whole cells scored by the screen's
//! score test with the object's modulus projected out. The best box is fitted as a candidate
//! beside the four halves (a half is one of the boxes when the grid splits an axis evenly).
//!
//! Choosing the best of many boxes is a scan: under "no region" each box's signed score is a
//! standard normal, correlated with its neighbours' as their sensitivity columns are. The
//! scan's p-value and the bar its Vuong test must clear are taken from the distribution of the
//! largest of them, drawn by Monte Carlo in the span of the cells' columns ([`DRAWS`] draws,
//! seeded: deterministic). Many overlapping boxes then count as the few independent tests they
//! are, not as their number.

use glam::DVec3;
use softgrip_core::mesh::TetMesh;
use softgrip_core::scene::AaBox;

use super::statistics::{VUONG_Z, upper_tail};

/// Cells along each axis of the object's bounding box: 4 resolves a quarter of a side (a layer
/// of a quarter of the height, a half as two cells).
pub const CELLS: usize = 4;

/// Monte Carlo draws of the scan's largest score.
pub const DRAWS: usize = 4000;

/// The seed of those draws: the same every run.
const SCAN_SEED: u64 = 0x005e_ed0f_5ca9;

/// The grid of cells over the object's bounding box, and which cells hold an element's centroid
/// (a cell without one cannot take another modulus).
#[derive(Debug, Clone)]
pub struct Grid {
    lo: DVec3,
    hi: DVec3,
    n: [usize; 3],
    occupied: Vec<bool>,
}

impl Grid {
    /// The grid over `mesh`'s bounds: [`CELLS`] an axis, one along an axis the mesh is flat in.
    pub fn of(mesh: &TetMesh) -> Grid {
        let (lo, hi) = mesh.bounds();
        let extent = hi - lo;
        let largest = extent.max_element().max(f64::MIN_POSITIVE);
        let n = [0, 1, 2].map(|a| if extent[a] > 1e-6 * largest { CELLS } else { 1 });
        let centroids = mesh
            .tets
            .iter()
            .map(|tet| tet.iter().map(|&p| mesh.nodes[p as usize]).sum::<DVec3>() * 0.25);
        Grid::with_cells(lo, hi, n, centroids)
    }

    /// The grid of `n` cells an axis over `lo..hi`, occupied where one of `points` falls.
    pub fn with_cells(
        lo: DVec3,
        hi: DVec3,
        n: [usize; 3],
        points: impl IntoIterator<Item = DVec3>,
    ) -> Grid {
        let n = n.map(|k| k.max(1));
        let mut grid = Grid {
            lo,
            hi,
            n,
            occupied: vec![false; n[0] * n[1] * n[2]],
        };
        for p in points {
            let i = grid.cell_of(p);
            let at = grid.index(i);
            grid.occupied[at] = true;
        }
        grid
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        (k * self.n[1] + j) * self.n[0] + i
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        [0, 1, 2].map(|a| {
            let t = (p[a] - self.lo[a]) / (self.hi[a] - self.lo[a]).max(f64::MIN_POSITIVE);
            ((t * self.n[a] as f64).floor().max(0.0) as usize).min(self.n[a] - 1)
        })
    }

    /// The cells holding an element, in index order.
    pub fn cells(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for k in 0..self.n[2] {
            for j in 0..self.n[1] {
                for i in 0..self.n[0] {
                    if self.occupied[self.index([i, j, k])] {
                        out.push([i, j, k]);
                    }
                }
            }
        }
        out
    }

    /// The box of cells `first..=last` on each axis, grown by a thousandth of the object at its
    /// outer faces (so that no element on the surface falls outside by rounding).
    pub fn cell_box(&self, first: [usize; 3], last: [usize; 3]) -> AaBox {
        let pad = 1e-3 * (self.hi - self.lo).max_element();
        let at = |a: usize, i: usize| {
            self.lo[a] + (self.hi[a] - self.lo[a]) * i as f64 / self.n[a] as f64
        };
        let min = DVec3::from_array(
            [0, 1, 2].map(|a| at(a, first[a]) - if first[a] == 0 { pad } else { 0.0 }),
        );
        let max = DVec3::from_array(
            [0, 1, 2]
                .map(|a| at(a, last[a] + 1) + if last[a] + 1 == self.n[a] { pad } else { 0.0 }),
        );
        AaBox { min, max }
    }

    /// The box's name as a lab would say it: a half by the catalogue's own name, a layer
    /// (whole across two axes) by its face, otherwise a bar or a block by its faces, with its
    /// bounds in mm.
    pub fn describe(&self, first: [usize; 3], last: [usize; 3]) -> String {
        let faces = [("left", "right"), ("front", "back"), ("bottom", "top")];
        let whole: Vec<bool> = (0..3)
            .map(|a| first[a] == 0 && last[a] + 1 == self.n[a])
            .collect();
        let side = |a: usize| -> Option<&'static str> {
            match (first[a] == 0, last[a] + 1 == self.n[a]) {
                (true, false) => Some(faces[a].0),
                (false, true) => Some(faces[a].1),
                _ => None,
            }
        };
        let partial: Vec<usize> = (0..3).filter(|&a| !whole[a]).collect();
        let shape = match partial.as_slice() {
            [a] if 2 * (last[*a] + 1 - first[*a]) == self.n[*a] && side(*a).is_some() => {
                format!("{} half", side(*a).unwrap_or_default())
            }
            [a] => format!("{} layer", side(*a).unwrap_or("middle")),
            [_, _] => {
                let at: Vec<&str> = partial.iter().filter_map(|&a| side(a)).collect();
                let along = ["x", "y", "z"][(0..3).find(|&a| whole[a]).unwrap_or(0)];
                if at.is_empty() {
                    format!("inner bar along {along}")
                } else {
                    format!("{} bar along {along}", at.join("-"))
                }
            }
            _ => {
                let at: Vec<&str> = partial.iter().filter_map(|&a| side(a)).collect();
                if at.is_empty() {
                    "inner block".to_string()
                } else {
                    format!("{} block", at.join("-"))
                }
            }
        };
        let b = self.cell_box(first, last);
        let mm = |a: usize| {
            let (lo, hi) = (
                b.min[a].max(self.lo[a]) * 1e3,
                b.max[a].min(self.hi[a]) * 1e3,
            );
            format!("{} {lo:.1} to {hi:.1}", ["x", "y", "z"][a])
        };
        let bounds: Vec<String> = partial.iter().map(|&a| mm(a)).collect();
        if bounds.is_empty() {
            shape
        } else {
            format!("{shape}, {} mm", bounds.join(", "))
        }
    }

    /// The shapes the scan tries, simplest first: every layer (whole across two axes: the
    /// halves among them), every quarter (a half across two axes, whole along the third),
    /// every octant, and the inner block (the middle cells of every axis). A lab's part
    /// differs by a skin or a cured bottom, a two-material half, a moulding edge, an insert;
    /// 48 shapes on a 4-cell grid, pre-registered rather than every one of the 999 boxes, so
    /// that the scan's bar stays low enough to name a half a few times stiffer.
    pub fn family(&self) -> Vec<([usize; 3], [usize; 3])> {
        let n = self.n;
        let split: Vec<usize> = (0..3).filter(|&a| n[a] > 1).collect();
        let whole = |first: &mut [usize; 3], last: &mut [usize; 3], a: usize| {
            first[a] = 0;
            last[a] = n[a] - 1;
        };
        let mut out = Vec::new();
        // Layers: any range of cells along one axis.
        for &a in &split {
            for f in 0..n[a] {
                for l in f..n[a] {
                    if f == 0 && l + 1 == n[a] {
                        continue;
                    }
                    let (mut first, mut last) = ([0; 3], [0; 3]);
                    (0..3).for_each(|x| whole(&mut first, &mut last, x));
                    (first[a], last[a]) = (f, l);
                    out.push((first, last));
                }
            }
        }
        let halves = |a: usize| [(0, n[a] / 2 - 1), (n[a] / 2, n[a] - 1)];
        // Quarters: halves across two axes.
        for (i, &a) in split.iter().enumerate() {
            for &b in &split[i + 1..] {
                for ha in halves(a) {
                    for hb in halves(b) {
                        let (mut first, mut last) = ([0; 3], [0; 3]);
                        (0..3).for_each(|x| whole(&mut first, &mut last, x));
                        ((first[a], last[a]), (first[b], last[b])) = (ha, hb);
                        out.push((first, last));
                    }
                }
            }
        }
        if split.len() == 3 {
            for hx in halves(0) {
                for hy in halves(1) {
                    for hz in halves(2) {
                        out.push(([hx.0, hy.0, hz.0], [hx.1, hy.1, hz.1]));
                    }
                }
            }
        }
        if split.len() >= 2 {
            let (mut first, mut last) = ([0; 3], [0; 3]);
            (0..3).for_each(|x| whole(&mut first, &mut last, x));
            for &a in &split {
                (first[a], last[a]) = (1, n[a] - 2);
            }
            out.push((first, last));
        }
        out.retain(|(f, l)| (0..3).all(|a| f[a] <= l[a]));
        out
    }

    /// Whether the box holds the cell.
    fn holds(first: [usize; 3], last: [usize; 3], cell: [usize; 3]) -> bool {
        (0..3).all(|x| first[x] <= cell[x] && cell[x] <= last[x])
    }
}

/// One shape the scan keeps: a box of whole cells and which way its modulus moves at first
/// order (+1 stiffer, -1 softer).
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// The box, as a region's bounds.
    pub region: AaBox,
    /// Its name ([`Grid::describe`]).
    pub variant: String,
    /// +1 where the residual asks for a stiffer region, -1 for a softer one.
    pub sign: f64,
    /// Its score statistic.
    pub statistic: f64,
}

/// The scan's best box.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionScan {
    /// The family's shapes by their score, best first, each distinct from those before it
    /// (a mirror image the markers cannot tell apart is left out).
    pub shapes: Vec<Shape>,
    /// The best shape's score statistic (chi-square with one degree of freedom for a lone
    /// box).
    pub statistic: f64,
    /// The chance that the best of all boxes scores as high where no region differs.
    pub p_value: f64,
    /// How many independent tests the scan counts as: the `m` whose Bonferroni bar
    /// (`vuong_threshold(m)`) is the largest score's upper quantile at Vuong's level.
    pub tests: f64,
    /// The share of the residual its first-order step would remove.
    pub predicted_share: f64,
    /// Shapes scored.
    pub boxes: usize,
    /// One of the four halves is significant on its own (set by the screen, which tests them
    /// as before the scan): the region is fitted then too.
    pub halves_significant: bool,
}

/// The scan of `grid`'s shapes ([`Grid::family`]): `columns` the residual's derivative in each occupied cell's
/// modulus (in [`Grid::cells`]'s order, the object's modulus projected out), `r` the weighted
/// residual and `s2` its variance per degree of freedom. `None` when the columns span nothing.
pub fn scan(grid: &Grid, columns: &[Vec<f64>], r: &[f64], s2: f64) -> Option<RegionScan> {
    let cells = grid.cells();
    if cells.len() != columns.len() || cells.is_empty() || s2 <= 0.0 {
        return None;
    }
    let basis = orthonormal_basis(columns);
    if basis.is_empty() {
        return None;
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // Each cell's column and the residual in the basis: a box's column is the sum of its cells'.
    let coeffs: Vec<Vec<f64>> = columns
        .iter()
        .map(|c| basis.iter().map(|q| dot(q, c)).collect())
        .collect();
    let rho: Vec<f64> = basis.iter().map(|q| dot(q, r)).collect();
    let boxes = grid.family();
    let mut units: Vec<Vec<f64>> = Vec::with_capacity(boxes.len());
    let mut kept: Vec<usize> = Vec::with_capacity(boxes.len());
    for (b, (first, last)) in boxes.iter().enumerate() {
        let mut a = vec![0.0; basis.len()];
        for (c, cell) in cells.iter().enumerate() {
            if Grid::holds(*first, *last, *cell) {
                a.iter_mut().zip(&coeffs[c]).for_each(|(s, v)| *s += v);
            }
        }
        let norm = dot(&a, &a).sqrt();
        if norm > 1e-9 * coeffs.iter().map(|c| dot(c, c).sqrt()).fold(0.0, f64::max) {
            units.push(a.iter().map(|v| v / norm).collect());
            kept.push(b);
        }
    }
    let scores: Vec<f64> = units.iter().map(|u| dot(u, &rho)).collect();
    let mut order: Vec<usize> = (0..units.len()).collect();
    order.sort_by(|&a, &b| scores[b].abs().total_cmp(&scores[a].abs()));
    let z = scores[*order.first()?];
    let statistic = z * z / s2;
    let maxima = largest_scores(&units, basis.len());
    let exceed = maxima.iter().filter(|m| **m * **m >= statistic).count();
    let p_value = (exceed + 1) as f64 / (maxima.len() + 1) as f64;
    // Vuong's bar for the scan: the largest |score|'s quantile at the two-sided level of one
    // test's one-sided bar (a box's modulus may go either way).
    let level = 2.0 * upper_tail(VUONG_Z);
    let mut sorted = maxima.clone();
    sorted.sort_by(f64::total_cmp);
    let at = ((1.0 - level) * sorted.len() as f64).ceil() as usize;
    let bar = sorted[at.min(sorted.len() - 1)].max(VUONG_Z);
    let tests = upper_tail(VUONG_Z) / upper_tail(bar);
    let rss = dot(r, r);
    let mut shapes: Vec<Shape> = Vec::new();
    let mut chosen: Vec<usize> = Vec::new();
    for &i in &order {
        if chosen
            .iter()
            .any(|&j| dot(&units[i], &units[j]).abs() > SAME_SHAPE)
        {
            continue;
        }
        chosen.push(i);
        let (first, last) = boxes[kept[i]];
        shapes.push(Shape {
            region: grid.cell_box(first, last),
            variant: grid.describe(first, last),
            // The residual (simulation minus record) falls as the modulus moves against its
            // gradient: a positive score asks for a softer region.
            sign: if scores[i] > 0.0 { -1.0 } else { 1.0 },
            statistic: scores[i] * scores[i] / s2,
        });
    }
    Some(RegionScan {
        shapes,
        statistic,
        p_value,
        tests,
        predicted_share: statistic * s2 / rss.max(f64::MIN_POSITIVE),
        boxes: units.len(),
        halves_significant: false,
    })
}

/// Two shapes whose unit sensitivity columns agree this closely are one to the markers (a
/// mirror image across the markers' plane).
const SAME_SHAPE: f64 = 0.999;

/// An orthonormal basis of the columns' span (modified Gram-Schmidt, twice; a column whose
/// remainder is below 1e-9 of the largest column is dependent and dropped).
fn orthonormal_basis(columns: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let largest = columns.iter().map(|c| dot(c, c).sqrt()).fold(0.0, f64::max);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for c in columns {
        let mut v = c.clone();
        for _ in 0..2 {
            for q in &basis {
                let k = dot(q, &v);
                v.iter_mut().zip(q).for_each(|(x, y)| *x -= k * y);
            }
        }
        let norm = dot(&v, &v).sqrt();
        if norm > 1e-9 * largest && norm > 0.0 {
            basis.push(v.into_iter().map(|x| x / norm).collect());
        }
    }
    basis
}

/// [`DRAWS`] draws of the largest `|u . xi|` over the unit vectors `units`, `xi` standard normal
/// in `dim` dimensions (the scores of every box at once where no region differs).
fn largest_scores(units: &[Vec<f64>], dim: usize) -> Vec<f64> {
    let mut normal = crate::synth::Gaussian::new(SCAN_SEED);
    (0..DRAWS)
        .map(|_| {
            let xi: Vec<f64> = (0..dim).map(|_| normal.sample()).collect();
            units
                .iter()
                .map(|u| u.iter().zip(&xi).map(|(a, b)| a * b).sum::<f64>().abs())
                .fold(0.0, f64::max)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of `n` unit cells an axis, every one occupied.
    fn grid(n: [usize; 3]) -> Grid {
        let mut centres = Vec::new();
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    centres.push(DVec3::new(i as f64, j as f64, k as f64) + 0.5);
                }
            }
        }
        let hi = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
        Grid::with_cells(DVec3::ZERO, hi, n, centres)
    }

    /// Orthogonal unit columns, one per cell, in `rows` observations.
    fn orthogonal(cells: usize, rows: usize) -> Vec<Vec<f64>> {
        (0..cells)
            .map(|c| (0..rows).map(|i| if i == c { 1.0 } else { 0.0 }).collect())
            .collect()
    }

    #[test]
    fn the_scan_finds_the_box_whose_column_the_residual_follows() {
        let g = grid([4, 4, 4]);
        let cells = g.cells();
        assert_eq!(cells.len(), 64);
        // The residual is the bottom layer's column (the 16 cells with k = 0) times 3.
        let columns = orthogonal(64, 100);
        let r: Vec<f64> = (0..100)
            .map(|i| if i < 64 && cells[i][2] == 0 { 3.0 } else { 0.0 })
            .collect();
        let s = scan(&g, &columns, &r, 1.0).expect("a scan");
        let best = &s.shapes[0];
        assert_eq!(best.variant, "bottom layer, z 0.0 to 1000.0 mm", "{s:?}");
        assert_eq!(best.region.max.z, 1.0);
        // The residual grows with the layer's modulus: it asks for a softer layer.
        assert_eq!(best.sign, -1.0);
        // |r|^2 = 16 * 9, all of it along the box's column.
        assert!((s.statistic - 144.0).abs() < 1e-9, "{s:?}");
        assert!((s.predicted_share - 1.0).abs() < 1e-12);
        assert!(s.p_value < 1e-3, "{s:?}");
        // 27 layers, 12 quarters, 8 octants, the inner block.
        assert_eq!(s.boxes, 48);
    }

    #[test]
    fn two_unrelated_boxes_count_as_two_tests_and_one_box_twice_as_one() {
        // Two cells: the boxes are each cell alone. Orthogonal columns: the largest of two
        // independent |Z|, whose bar at level q is Bonferroni's for two, to within the draws.
        let g = grid([2, 1, 1]);
        let r = vec![0.0; 10];
        let two = scan(&g, &orthogonal(2, 10), &r, 1.0).expect("a scan");
        assert!((two.tests - 2.0).abs() < 0.3, "{two:?}");
        // The same column twice: one test.
        let same = vec![orthogonal(1, 10)[0].clone(); 2];
        let one = scan(&g, &same, &r, 1.0).expect("a scan");
        assert!((one.tests - 1.0).abs() < 0.15, "{one:?}");
        // ... and one shape to the markers.
        assert_eq!((two.shapes.len(), one.shapes.len()), (2, 1));
        // With no residual the scan finds nothing: every draw scores at least as high.
        assert!(two.p_value > 0.99);
    }

    #[test]
    fn boxes_are_named_by_the_faces_they_touch() {
        let g = grid([4, 4, 4]);
        assert!(
            g.describe([0, 0, 0], [1, 3, 3])
                .starts_with("left half, x 0.0 to 2000.0")
        );
        assert!(g.describe([0, 0, 3], [3, 3, 3]).starts_with("top layer"));
        assert!(g.describe([0, 0, 1], [3, 3, 2]).starts_with("middle layer"));
        assert!(
            g.describe([3, 0, 0], [3, 3, 0])
                .starts_with("right-bottom bar along y")
        );
        assert!(g.describe([1, 1, 1], [2, 2, 2]).starts_with("inner block"));
    }
}
