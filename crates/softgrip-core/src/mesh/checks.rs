//! The checks every loaded mesh goes through before a model is built on
//! it: inside-out tetrahedra reordered (an error when flat), duplicate
//! nodes merged, unused nodes dropped, disconnected parts counted. Each
//! change is reported as a warning; what cannot be fixed is an error.

use std::collections::HashMap;

use glam::DVec3;

use super::{MeshError, TetMesh, bounds_of, signed_volume};

/// What [`repair`] changed or noticed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Inside-out tetrahedra whose nodes were reordered.
    pub reordered: usize,
    /// Duplicate nodes merged into another on the same point.
    pub merged: usize,
    /// Nodes of no tetrahedron, dropped (the merged ones not counted).
    pub unused: usize,
    /// Connected parts (sharing nodes); 1 for a sound object.
    pub parts: usize,
    /// One sentence per change made or problem noticed, for the user.
    pub warnings: Vec<String>,
}

/// Two nodes closer than this fraction of the mesh's extent are one.
pub const DUPLICATE_TOLERANCE: f64 = 1e-9;

/// A tetrahedron with less volume than this fraction of the mean is flat.
pub const DEGENERATE_FRACTION: f64 = 1e-12;

/// A tetrahedron of shape quality (`TetMesh::tet_quality`) below this is flat: an error (a
/// dihedral angle of about 0.01 degrees).
pub const FLAT_QUALITY: f64 = 1e-4;

/// ... and below this a sliver: a warning (a dihedral angle of about 1 degree; Gmsh's and
/// TetGen's meshes stay above 0.05).
pub const SLIVER_QUALITY: f64 = 0.01;

/// Makes `mesh` fit for a model, or says why it cannot be.
pub fn repair(mesh: &mut TetMesh) -> Result<Report, MeshError> {
    if mesh.tets.is_empty() {
        return Err(MeshError::Empty);
    }
    super::check_nodes(&mesh.nodes)?;
    check_indices(mesh)?;
    let mut report = Report {
        merged: merge_duplicates(mesh),
        ..Report::default()
    };

    // Unused nodes go (and the merged ones with them).
    let unused = drop_unused(mesh);
    report.unused = unused.saturating_sub(report.merged);

    // Orientation: a negative volume is a node order; a flat one is an error.
    report.reordered = orient(mesh)?;

    if let Some(w) = slivers(mesh)? {
        report.warnings.push(w);
    }
    if let Some((count, node)) = non_manifold_nodes(mesh) {
        let p = mesh.nodes[node];
        return Err(MeshError::NonManifold {
            count,
            node,
            x: p.x,
            y: p.y,
            z: p.z,
        });
    }

    report.parts = parts(mesh);
    report.warn_changes();
    Ok(report)
}

impl Report {
    /// A warning for each kind of change made (reordered, merged, dropped)
    /// and for a mesh in several parts.
    fn warn_changes(&mut self) {
        if self.reordered > 0 {
            self.warnings.push(format!(
                "{} tetrahedra were inside out (negative volume): their nodes were reordered",
                self.reordered
            ));
        }
        if self.merged > 0 {
            self.warnings.push(format!(
                "{} duplicate nodes (on the same point as another) were merged",
                self.merged
            ));
        }
        if self.unused > 0 {
            self.warnings.push(format!(
                "{} nodes belong to no tetrahedron and were dropped",
                self.unused
            ));
        }
        if self.parts > 1 {
            self.warnings.push(format!(
                "the mesh has {} disconnected parts: each moves on its own (is that intended?)",
                self.parts
            ));
        }
    }
}

/// Every tetrahedron's node index within the mesh's nodes.
fn check_indices(mesh: &TetMesh) -> Result<(), MeshError> {
    for (t, tet) in mesh.tets.iter().enumerate() {
        for &n in tet {
            if n as usize >= mesh.nodes.len() {
                return Err(MeshError::IndexOutOfRange {
                    tet: t,
                    node: n,
                    nodes: mesh.nodes.len(),
                });
            }
        }
    }
    Ok(())
}

/// Drops the nodes no tetrahedron uses (renumbering the rest in order):
/// how many there were.
fn drop_unused(mesh: &mut TetMesh) -> usize {
    let mut used = vec![false; mesh.nodes.len()];
    for tet in &mesh.tets {
        for &n in tet {
            used[n as usize] = true;
        }
    }
    let unused = used.iter().filter(|u| !**u).count();
    if unused > 0 {
        let mut new_index = vec![u32::MAX; mesh.nodes.len()];
        let mut nodes = Vec::with_capacity(mesh.nodes.len() - unused);
        for (i, p) in mesh.nodes.iter().enumerate() {
            if used[i] {
                new_index[i] = nodes.len() as u32;
                nodes.push(*p);
            }
        }
        mesh.nodes = nodes;
        for tet in &mut mesh.tets {
            for n in tet.iter_mut() {
                *n = new_index[*n as usize];
            }
        }
    }
    unused
}

/// Reorders inside-out tetrahedra (negative volume: two nodes swapped):
/// how many; a flat one (repeated node, or volume within
/// [`DEGENERATE_FRACTION`] of the mean) is an error.
fn orient(mesh: &mut TetMesh) -> Result<usize, MeshError> {
    let mut reordered = 0;
    let mean = mesh
        .tets
        .iter()
        .map(|t| {
            let p = t.map(|i| mesh.nodes[i as usize]);
            signed_volume(p[0], p[1], p[2], p[3]).abs()
        })
        .sum::<f64>()
        / mesh.tets.len() as f64;
    for (t, tet) in mesh.tets.iter_mut().enumerate() {
        let p = tet.map(|i| mesh.nodes[i as usize]);
        let v = signed_volume(p[0], p[1], p[2], p[3]);
        let distinct = {
            let mut s = *tet;
            s.sort_unstable();
            s.windows(2).all(|w| w[0] != w[1])
        };
        if !distinct || v.abs() <= DEGENERATE_FRACTION * mean {
            let c = (p[0] + p[1] + p[2] + p[3]) / 4.0;
            return Err(MeshError::Inverted {
                tet: t,
                volume: v,
                x: c.x,
                y: c.y,
                z: c.z,
            });
        }
        if v < 0.0 {
            tet.swap(2, 3);
            reordered += 1;
        }
    }
    Ok(reordered)
}

/// Nodes on the same point (to [`DUPLICATE_TOLERANCE`] of the extent) made one: how many were
/// merged into another.
fn merge_duplicates(mesh: &mut TetMesh) -> usize {
    let mut merged = 0;
    let (lo, hi) = bounds_of(&mesh.nodes);
    let cell = ((hi - lo).max_element() * DUPLICATE_TOLERANCE).max(f64::MIN_POSITIVE);
    let mut first: HashMap<[i64; 3], u32> = HashMap::with_capacity(mesh.nodes.len());
    let mut remap: Vec<u32> = (0..mesh.nodes.len() as u32).collect();
    for (i, p) in mesh.nodes.iter().enumerate() {
        let key = ((*p - lo) / cell).round().as_i64vec3().to_array();
        match first.get(&key) {
            Some(&j) => {
                remap[i] = j;
                merged += 1;
            }
            None => {
                first.insert(key, i as u32);
            }
        }
    }
    for tet in &mut mesh.tets {
        for n in tet.iter_mut() {
            *n = remap[*n as usize];
        }
    }
    merged
}

/// Flat tetrahedra (an error naming the worst) and slivers (a warning naming the worst).
fn slivers(mesh: &TetMesh) -> Result<Option<String>, MeshError> {
    let mut slivers = 0;
    let mut worst: Option<(usize, f64)> = None;
    for t in 0..mesh.tets.len() {
        let q = mesh.tet_quality(t);
        if q < SLIVER_QUALITY {
            slivers += 1;
            if worst.is_none_or(|(_, w)| q < w) {
                worst = Some((t, q));
            }
        }
    }
    if let Some((t, q)) = worst {
        let c = mesh.tet_positions(t).iter().sum::<DVec3>() / 4.0;
        if q < FLAT_QUALITY {
            return Err(MeshError::Flat {
                tet: t,
                quality: q,
                x: c.x,
                y: c.y,
                z: c.z,
            });
        }
        return Ok(Some(format!(
            "{slivers} sliver tetrahedra (shape quality below {SLIVER_QUALITY}; the worst, tetrahedron {t}, {q:.1e} near ({:.4}, {:.4}, {:.4})): they make the step stiff and the contact rough; remesh (Gmsh: Mesh > Optimize 3D)",
            c.x, c.y, c.z
        )));
    }
    Ok(None)
}

/// The root of `i` in a union-find forest, halving the path on the way.
fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

/// Nodes around which the tetrahedra do not form one piece through their shared faces (two
/// tetrahedra meeting only at a node or an edge): how many, and the first.
pub fn non_manifold_nodes(mesh: &TetMesh) -> Option<(usize, usize)> {
    // A union-find over (tetrahedron, corner) incidences: two tetrahedra sharing a face join
    // their corners at its three nodes.
    let n = 4 * mesh.tets.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut faces: HashMap<[u32; 3], (u32, [u8; 3])> = HashMap::with_capacity(2 * n);
    for (t, tet) in mesh.tets.iter().enumerate() {
        for skip in 0..4u8 {
            let mut corners: Vec<u8> = (0..4u8).filter(|&c| c != skip).collect();
            corners.sort_by_key(|&c| tet[c as usize]);
            let key = [0, 1, 2].map(|k| tet[corners[k] as usize]);
            let mine = [corners[0], corners[1], corners[2]];
            match faces.remove(&key) {
                Some((other, theirs)) => {
                    for k in 0..3 {
                        let a = root(&mut parent, 4 * t as u32 + mine[k] as u32);
                        let b = root(&mut parent, 4 * other + theirs[k] as u32);
                        parent[a as usize] = b;
                    }
                }
                None => {
                    faces.insert(key, (t as u32, mine));
                }
            }
        }
    }
    let mut first_root = vec![u32::MAX; mesh.nodes.len()];
    let mut bad = vec![false; mesh.nodes.len()];
    for (t, tet) in mesh.tets.iter().enumerate() {
        for (c, &node) in tet.iter().enumerate() {
            let r = root(&mut parent, 4 * t as u32 + c as u32);
            match first_root[node as usize] {
                u32::MAX => first_root[node as usize] = r,
                f if f != r => bad[node as usize] = true,
                _ => {}
            }
        }
    }
    let count = bad.iter().filter(|b| **b).count();
    bad.iter().position(|b| *b).map(|first| (count, first))
}

/// Connected parts of the node graph of the tetrahedra (union-find).
pub fn parts(mesh: &TetMesh) -> usize {
    let mut parent: Vec<u32> = (0..mesh.nodes.len() as u32).collect();
    for tet in &mesh.tets {
        let a = root(&mut parent, tet[0]);
        for &n in &tet[1..] {
            let b = root(&mut parent, n);
            if a != b {
                parent[b as usize] = a;
            }
        }
    }
    let mut used = vec![false; mesh.nodes.len()];
    for tet in &mesh.tets {
        for &n in tet {
            used[n as usize] = true;
        }
    }
    (0..mesh.nodes.len() as u32)
        .filter(|&i| used[i as usize] && root(&mut parent, i) == i)
        .count()
}

/// The smallest dihedral angle (degrees) and the worst aspect ratio
/// (longest edge over the smallest height) of the mesh.
pub fn shape_figures(mesh: &TetMesh) -> (f64, f64) {
    let mut min_angle = f64::INFINITY;
    let mut worst_aspect: f64 = 0.0;
    for t in &mesh.tets {
        let p = t.map(|i| mesh.nodes[i as usize]);
        let v = signed_volume(p[0], p[1], p[2], p[3]).abs();
        // Face normals (outward-ish; angles from their dot products).
        let faces: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];
        let normals: Vec<(DVec3, f64)> = faces
            .iter()
            .enumerate()
            .map(|(k, f)| {
                let n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
                // Point away from the opposite vertex.
                let n = if n.dot(p[k] - p[f[0]]) > 0.0 { -n } else { n };
                (n.normalize_or_zero(), 0.5 * n.length())
            })
            .collect();
        for a in 0..4 {
            for b in a + 1..4 {
                let cos = -normals[a].0.dot(normals[b].0);
                let angle = cos.clamp(-1.0, 1.0).acos().to_degrees();
                min_angle = min_angle.min(angle);
            }
        }
        let longest = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
            .iter()
            .map(|[a, b]| p[*a].distance(p[*b]))
            .fold(0.0f64, f64::max);
        let largest_face = normals.iter().map(|n| n.1).fold(0.0f64, f64::max);
        let height = if largest_face > 0.0 {
            3.0 * v / largest_face
        } else {
            0.0
        };
        let aspect = if height > 0.0 {
            longest / height
        } else {
            f64::INFINITY
        };
        worst_aspect = worst_aspect.max(aspect);
    }
    (min_angle, worst_aspect)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::mesh::TetMesh;
    use crate::mesh::checks;

    #[test]
    fn shape_figures_of_a_regular_tetrahedron() {
        let s = 1.0 / 2f64.sqrt();
        let m = TetMesh {
            nodes: vec![
                DVec3::new(1.0, 0.0, -s),
                DVec3::new(-1.0, 0.0, -s),
                DVec3::new(0.0, 1.0, s),
                DVec3::new(0.0, -1.0, s),
            ],
            tets: vec![[0, 1, 2, 3]],
        };
        let (angle, aspect) = checks::shape_figures(&m);
        // Dihedral angle acos(1/3); edge 2 over height 2 sqrt(2/3).
        assert!(
            (angle - (1.0f64 / 3.0).acos().to_degrees()).abs() < 1e-9,
            "{angle}"
        );
        assert!(
            (aspect - 2.0 / (2.0 * (2.0f64 / 3.0).sqrt())).abs() < 1e-9,
            "{aspect}"
        );
    }

    /// Two unit tetrahedra, of `second`'s nodes.
    fn two(second: [DVec3; 4]) -> TetMesh {
        let mut nodes = vec![
            DVec3::ZERO,
            DVec3::X * 0.01,
            DVec3::Y * 0.01,
            DVec3::Z * 0.01,
        ];
        nodes.extend(second);
        TetMesh {
            nodes,
            tets: vec![[0, 1, 2, 3], [4, 5, 6, 7]],
        }
    }

    #[test]
    fn tetrahedra_meeting_only_at_a_node_are_not_a_manifold() {
        // The second's first node on the first's apex: merged into one node by the checks.
        let apex = DVec3::Z * 0.01;
        let mut mesh = two([
            apex,
            apex + DVec3::X * 0.01,
            apex + DVec3::Y * 0.01,
            apex + DVec3::Z * 0.01,
        ]);
        let e = checks::repair(&mut mesh)
            .expect_err("a hinge at a node")
            .to_string();
        assert!(e.contains("not a manifold") && e.contains("1 node"), "{e}");
        // Sharing a face instead, they are one piece.
        let mut mesh = TetMesh {
            nodes: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE],
            tets: vec![[0, 1, 2, 3], [1, 2, 3, 4]],
        };
        assert!(checks::repair(&mut mesh).is_ok());
    }

    #[test]
    fn a_flat_tetrahedron_is_an_error_and_a_thin_one_a_warning_each_named() {
        let far = DVec3::new(0.05, 0.0, 0.0);
        // 1e-12 m thick: flat.
        let mut flat = two([
            far,
            far + DVec3::X * 0.01,
            far + DVec3::Y * 0.01,
            far + DVec3::new(0.005, 0.005, 1e-12),
        ]);
        let e = checks::repair(&mut flat).expect_err("flat").to_string();
        assert!(e.contains("tetrahedron 1 is flat"), "{e}");
        // 0.05 mm thick over 10 mm: quality about 0.005, a sliver.
        let mut thin = two([
            far,
            far + DVec3::X * 0.01,
            far + DVec3::Y * 0.01,
            far + DVec3::new(0.004, 0.004, 5e-5),
        ]);
        let r = checks::repair(&mut thin).expect("a sliver is kept");
        assert!(
            r.warnings
                .iter()
                .any(|w| w.contains("1 sliver") && w.contains("tetrahedron 1")),
            "{:?}",
            r.warnings
        );
    }
}
