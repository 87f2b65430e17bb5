//! Built-in shapes meshed without external tools: a cuboid (mirrored Kuhn
//! subdivision of a regular grid) and a cylinder (concentric rings extruded in
//! layers, each prism split into three tetrahedra).

use glam::DVec3;

use super::{TetMesh, signed_volume};

/// The six tetrahedra of the Kuhn (Freudenthal) subdivision of the unit cube,
/// as corner indices `bit0 = x, bit1 = y, bit2 = z`: every path 0 -> 7 along
/// cube edges.
const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// Cells along an axis of length `len` for a target edge `h`; `even` keeps the
/// count even so the mirrored subdivision is symmetric about the centre.
fn cell_count(len: f64, h: f64, even: bool) -> usize {
    super::budget::cells(len, h, even) as usize
}

/// Pushes `tet` wound positively.
fn push_oriented(mesh: &mut TetMesh, mut tet: [u32; 4]) {
    let p = tet.map(|i| mesh.nodes[i as usize]);
    if signed_volume(p[0], p[1], p[2], p[3]) < 0.0 {
        tet.swap(2, 3);
    }
    mesh.tets.push(tet);
}

impl TetMesh {
    /// A cuboid of extents `size`, centred at x = y = 0 with its bottom face at
    /// z = 0, cut into cubes of about `edge_length` (an even count along x and y,
    /// so the mesh is mirror-symmetric about x = 0 and y = 0) and each cube into
    /// six tetrahedra. Neighbouring cubes are mirror images, so the mesh has no
    /// preferred diagonal direction.
    pub fn cuboid(size: DVec3, edge_length: f64) -> TetMesh {
        let n = [
            cell_count(size.x, edge_length, true),
            cell_count(size.y, edge_length, true),
            cell_count(size.z, edge_length, false),
        ];
        let origin = DVec3::new(-0.5 * size.x, -0.5 * size.y, 0.0);
        let step = size / DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
        let node_id = |i: usize, j: usize, k: usize| (i + (n[0] + 1) * (j + (n[1] + 1) * k)) as u32;
        let mut mesh = TetMesh {
            nodes: Vec::new(),
            tets: Vec::with_capacity(6 * n[0] * n[1] * n[2]),
        };
        for k in 0..=n[2] {
            for j in 0..=n[1] {
                for i in 0..=n[0] {
                    // Exact end coordinates so faces lie exactly on the bounds.
                    let c = |idx: usize, count: usize, lo: f64, len: f64, st: f64| {
                        if idx == count {
                            lo + len
                        } else {
                            lo + idx as f64 * st
                        }
                    };
                    mesh.nodes.push(DVec3::new(
                        c(i, n[0], origin.x, size.x, step.x),
                        c(j, n[1], origin.y, size.y, step.y),
                        c(k, n[2], 0.0, size.z, step.z),
                    ));
                }
            }
        }
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let flip = [i % 2, j % 2, k % 2];
                    let corner = |local: usize| {
                        let a = (local & 1) ^ flip[0];
                        let b = ((local >> 1) & 1) ^ flip[1];
                        let c = ((local >> 2) & 1) ^ flip[2];
                        node_id(i + a, j + b, k + c)
                    };
                    for tet in KUHN {
                        push_oriented(&mut mesh, tet.map(corner));
                    }
                }
            }
        }
        mesh
    }

    /// A cylinder of `radius` and `height`, axis along z, centred at x = y = 0,
    /// bottom at z = 0. The disc is meshed as concentric rings (ring k has 6k
    /// nodes), zipped into triangles, and extruded in layers; each prism is cut
    /// into three tetrahedra by a rule that depends only on the global node
    /// order, so neighbouring prisms agree on their shared quad diagonals.
    pub fn cylinder(radius: f64, height: f64, edge_length: f64) -> TetMesh {
        let rings = cell_count(radius, edge_length, false);
        let layers = cell_count(height, edge_length, false);
        // Disc nodes.
        let mut disc: Vec<(f64, f64)> = vec![(0.0, 0.0)];
        let mut ring_start = vec![0usize];
        for k in 1..=rings {
            ring_start.push(disc.len());
            let r = radius * k as f64 / rings as f64;
            let count = 6 * k;
            for m in 0..count {
                let th = std::f64::consts::TAU * m as f64 / count as f64;
                disc.push((r * th.cos(), r * th.sin()));
            }
        }
        // Disc triangles, by zipping ring k-1 and ring k in angle order.
        let mut tris: Vec<[usize; 3]> = Vec::new();
        for k in 1..=rings {
            let (na, nb) = (if k == 1 { 1 } else { 6 * (k - 1) }, 6 * k);
            let (sa, sb) = (ring_start[k - 1], ring_start[k]);
            let angle = |m: usize, n: usize| std::f64::consts::TAU * m as f64 / n as f64;
            if na == 1 {
                for m in 0..nb {
                    tris.push([sa, sb + m, sb + (m + 1) % nb]);
                }
                continue;
            }
            let (mut i, mut j) = (0usize, 0usize);
            while i < na || j < nb {
                let advance_a = if i >= na {
                    false
                } else if j >= nb {
                    true
                } else {
                    angle(i + 1, na) < angle(j + 1, nb) - 1e-12
                };
                if advance_a {
                    tris.push([sa + i % na, sa + (i + 1) % na, sb + j % nb]);
                    i += 1;
                } else {
                    tris.push([sa + i % na, sb + (j + 1) % nb, sb + j % nb]);
                    j += 1;
                }
            }
        }
        let n2 = disc.len();
        let mut mesh = TetMesh {
            nodes: Vec::with_capacity(n2 * (layers + 1)),
            tets: Vec::new(),
        };
        for l in 0..=layers {
            let z = if l == layers {
                height
            } else {
                height * l as f64 / layers as f64
            };
            mesh.nodes
                .extend(disc.iter().map(|&(x, y)| DVec3::new(x, y, z)));
        }
        for l in 0..layers {
            for tri in &tris {
                let mut t = *tri;
                t.sort_unstable();
                let [a, b, c] = t;
                let bot = |v: usize| (l * n2 + v) as u32;
                let top = |v: usize| ((l + 1) * n2 + v) as u32;
                push_oriented(&mut mesh, [bot(a), bot(b), bot(c), top(c)]);
                push_oriented(&mut mesh, [bot(a), bot(b), top(b), top(c)]);
                push_oriented(&mut mesh, [bot(a), top(a), top(b), top(c)]);
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuboid_is_valid_and_fills_its_box() {
        let size = DVec3::new(0.05, 0.05, 0.02);
        let m = TetMesh::cuboid(size, 0.004);
        m.validate().expect("valid mesh");
        let v = m.volume();
        assert!((v - size.x * size.y * size.z).abs() < 1e-12 * v.abs().max(1e-12) * 1e3);
        // 12 x 12 x 5 cells of 6 tets.
        assert_eq!(m.tets.len(), 12 * 12 * 5 * 6);
        let (lo, hi) = m.bounds();
        assert_eq!(lo, DVec3::new(-0.025, -0.025, 0.0));
        assert_eq!(hi, DVec3::new(0.025, 0.025, 0.02));
    }

    #[test]
    fn cuboid_boundary_is_closed_and_outward() {
        let m = TetMesh::cuboid(DVec3::new(0.03, 0.02, 0.01), 0.005);
        let facets = m.boundary_facets();
        // Surface area from the facets matches the box.
        let area: f64 = facets
            .iter()
            .map(|f| {
                let p = f.map(|i| m.nodes[i as usize]);
                0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
            })
            .sum();
        let expected = 2.0 * (0.03 * 0.02 + 0.03 * 0.01 + 0.02 * 0.01);
        assert!((area - expected).abs() < 1e-12, "{area} vs {expected}");
        // Divergence theorem: (1/3) sum of x . n dA equals the volume only when all normals point out.
        let flux: f64 = facets
            .iter()
            .map(|f| {
                let p = f.map(|i| m.nodes[i as usize]);
                let n2a = (p[1] - p[0]).cross(p[2] - p[0]);
                ((p[0] + p[1] + p[2]) / 3.0).dot(n2a) / 6.0
            })
            .sum();
        assert!(
            (flux - m.volume()).abs() < 1e-12,
            "{flux} vs {}",
            m.volume()
        );
    }

    #[test]
    fn cuboid_is_mirror_symmetric_about_x0() {
        let m = TetMesh::cuboid(DVec3::new(0.05, 0.05, 0.02), 0.004);
        let mut edges: Vec<(i64, i64, i64, i64, i64, i64)> = Vec::new();
        let key = |p: DVec3| {
            (
                (p.x * 1e6).round() as i64,
                (p.y * 1e6).round() as i64,
                (p.z * 1e6).round() as i64,
            )
        };
        for [i, j] in m.edges() {
            let (a, b) = (key(m.nodes[i as usize]), key(m.nodes[j as usize]));
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            edges.push((a.0, a.1, a.2, b.0, b.1, b.2));
        }
        let mut mirrored: Vec<_> = edges
            .iter()
            .map(|&(ax, ay, az, bx, by, bz)| {
                let (a, b) = ((-ax, ay, az), (-bx, by, bz));
                let (a, b) = if a < b { (a, b) } else { (b, a) };
                (a.0, a.1, a.2, b.0, b.1, b.2)
            })
            .collect();
        edges.sort_unstable();
        mirrored.sort_unstable();
        assert_eq!(edges, mirrored);
    }

    #[test]
    fn cylinder_is_valid_and_close_to_its_volume() {
        let (r, h) = (0.04, 0.0533);
        let m = TetMesh::cylinder(r, h, 0.004);
        m.validate().expect("valid mesh");
        let exact = std::f64::consts::PI * r * r * h;
        // The polygonal rings lose area ~ (1 - sin(2 pi / n) n / (2 pi)) on the outer ring.
        let rel = (m.volume() - exact).abs() / exact;
        assert!(rel < 0.01, "relative volume error {rel}");
        // Closed surface: flux check.
        let flux: f64 = m
            .boundary_facets()
            .iter()
            .map(|f| {
                let p = f.map(|i| m.nodes[i as usize]);
                ((p[0] + p[1] + p[2]) / 3.0).dot((p[1] - p[0]).cross(p[2] - p[0])) / 6.0
            })
            .sum();
        assert!((flux - m.volume()).abs() < 1e-12 * 1e3);
        assert!(m.stats().worst_quality > 0.2, "{}", m.stats());
    }

    #[test]
    fn validate_rejects_inverted_and_out_of_range() {
        let mut m = TetMesh::cuboid(DVec3::splat(0.01), 0.005);
        m.tets[3].swap(0, 1);
        assert!(matches!(
            m.validate(),
            Err(super::super::MeshError::Inverted { tet: 3, .. })
        ));
        let mut m = TetMesh::cuboid(DVec3::splat(0.01), 0.005);
        m.tets[0][2] = 10_000;
        assert!(matches!(
            m.validate(),
            Err(super::super::MeshError::IndexOutOfRange { .. })
        ));
    }
}
