//! Tetrahedral meshes: the geometry the model is built from.
//!
//! Convention: a tetrahedron `[a, b, c, d]` is positively oriented when
//! `(b - a) · ((c - a) × (d - a)) > 0`. Every mesh handed to the model is
//! checked for it ([`TetMesh::validate`]).

pub mod budget;
mod builtin;
pub mod checks;
pub mod io;
pub mod surface;
pub mod tetrahedralize;

use std::collections::HashMap;

use glam::DVec3;

/// A tetrahedral mesh: node positions (m) and tetrahedra as node indices.
#[derive(Debug, Clone, PartialEq)]
pub struct TetMesh {
    /// Node positions, m (a file's own units until [`TetMesh::place`] scales them) (length: nodes).
    pub nodes: Vec<DVec3>,
    /// Tetrahedra as four indices into `nodes`, positively oriented once checked (length: tets).
    pub tets: Vec<[u32; 4]>,
}

/// Summary figures of a mesh, as printed by the CLI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshStats {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of tetrahedra.
    pub tets: usize,
    /// Number of faces on the boundary (those of one tetrahedron only).
    pub boundary_facets: usize,
    /// Total signed volume, m^3.
    pub volume: f64,
    /// Worst shape quality `6 sqrt(2) V / l_rms^3` (1 for a regular tetrahedron).
    pub worst_quality: f64,
    /// Shortest tetrahedron edge, m.
    pub min_edge: f64,
    /// Longest tetrahedron edge, m.
    pub max_edge: f64,
}

/// Why a mesh cannot carry a model (each names where, with tetrahedra and nodes counted from 0).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No tetrahedra at all.
    #[error("the mesh has no tetrahedra")]
    Empty,
    /// A tetrahedron names a node past the last.
    #[error("tetrahedron {tet} refers to node {node}, but the mesh has only {nodes} nodes")]
    IndexOutOfRange {
        /// The tetrahedron's index.
        tet: usize,
        /// The node index it names.
        node: u32,
        /// Number of nodes in the mesh.
        nodes: usize,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate {position:?}")]
    NonFinite {
        /// The node's index.
        node: usize,
        /// Its coordinates, in the mesh's units.
        position: [f64; 3],
    },
    /// A node coordinate is past [`MAX_COORDINATE`]: a damaged number.
    #[error(
        "node {node} (counting from 0 in the file's order) is at ({:e}, {:e}, {:e}): beyond {MAX_COORDINATE:e} in the file's units, a typo or a damaged number; fix that node's coordinates", position[0], position[1], position[2]
    )]
    FarAway {
        /// The node's index.
        node: usize,
        /// Its coordinates, in the file's units.
        position: [f64; 3],
    },
    /// A tetrahedron flat (a repeated node, next to no volume) or, in [`TetMesh::validate`],
    /// inside out.
    #[error(
        "tetrahedron {tet} is inverted or degenerate (signed volume {volume:.3e} near ({x:.4}, {y:.4}, {z:.4}), in the mesh's own units): reorder its nodes or fix the mesh"
    )]
    Inverted {
        /// The tetrahedron's index.
        tet: usize,
        /// Its signed volume, in the mesh's units cubed (m^3 once placed).
        volume: f64,
        /// Its centroid's x, in the mesh's units.
        x: f64,
        /// Its centroid's y, in the mesh's units.
        y: f64,
        /// Its centroid's z, in the mesh's units.
        z: f64,
    },
    /// The worst tetrahedron's shape quality is under [`checks::FLAT_QUALITY`].
    #[error(
        "tetrahedron {tet} is flat (shape quality {quality:.1e}, 1 for a regular one; near ({x:.4}, {y:.4}, {z:.4})): no step can integrate a sliver so thin; remesh (Gmsh: Mesh > Optimize 3D) or remove it"
    )]
    Flat {
        /// The tetrahedron's index.
        tet: usize,
        /// Its shape quality ([`TetMesh::tet_quality`], 1 for a regular one).
        quality: f64,
        /// Its centroid's x, in the mesh's units.
        x: f64,
        /// Its centroid's y, in the mesh's units.
        y: f64,
        /// Its centroid's z, in the mesh's units.
        z: f64,
    },
    /// Tetrahedra meet only at a node or an edge there (the mesh hinges).
    #[error(
        "the mesh is not a manifold: {count} node(s) where tetrahedra meet only at a point or an edge, e.g. node {node} at ({x:.4}, {y:.4}, {z:.4}); parts joined so hinge there: join them by shared faces or separate them"
    )]
    NonManifold {
        /// Number of such nodes.
        count: usize,
        /// The first such node's index.
        node: usize,
        /// That node's x, in the mesh's units.
        x: f64,
        /// That node's y, in the mesh's units.
        y: f64,
        /// That node's z, in the mesh's units.
        z: f64,
    },
}

/// The six edges of a tetrahedron as local node pairs.
pub const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The four faces of a positively oriented tetrahedron, each wound so that its
/// normal `(b - a) × (c - a)` points out of the tetrahedron.
pub const TET_FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

/// Signed volume of the tetrahedron `a, b, c, d`.
#[inline]
pub fn signed_volume(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).dot((c - a).cross(d - a)) / 6.0
}

/// Gradient of the signed volume with respect to each of the four nodes.
#[inline]
pub fn volume_gradients(p: [DVec3; 4]) -> [DVec3; 4] {
    let [a, b, c, d] = p;
    const SIXTH: f64 = 1.0 / 6.0;
    let gb = (c - a).cross(d - a) * SIXTH;
    let gc = (d - a).cross(b - a) * SIXTH;
    let gd = (b - a).cross(c - a) * SIXTH;
    [-(gb + gc + gd), gb, gc, gd]
}

/// Axis-aligned bounds `(min, max)` of a set of points.
pub fn bounds_of(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

impl TetMesh {
    /// The four node positions of tetrahedron `t`, m.
    pub fn tet_positions(&self, t: usize) -> [DVec3; 4] {
        self.tets[t].map(|i| self.nodes[i as usize])
    }

    /// Signed volume of tetrahedron `t`, m^3 (positive when positively oriented).
    pub fn tet_volume(&self, t: usize) -> f64 {
        let [a, b, c, d] = self.tet_positions(t);
        signed_volume(a, b, c, d)
    }

    /// Total signed volume of the tetrahedra, m^3.
    pub fn volume(&self) -> f64 {
        (0..self.tets.len()).map(|t| self.tet_volume(t)).sum()
    }

    /// Scales the nodes by `scale`, then moves them so that the centre of
    /// the bottom face of their bounding box is at `position`.
    pub fn place(&mut self, scale: f64, position: DVec3) {
        for p in &mut self.nodes {
            *p *= scale;
        }
        let (lo, hi) = self.bounds();
        let bottom = DVec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
        let shift = position - bottom;
        for p in &mut self.nodes {
            *p += shift;
        }
    }

    /// Axis-aligned bounds `(min, max)` of the nodes.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        bounds_of(&self.nodes)
    }

    /// Checks indices, coordinates and orientation. A tetrahedron whose volume
    /// is below `1e-12` of the mean is degenerate.
    pub fn validate(&self) -> Result<(), MeshError> {
        if self.tets.is_empty() {
            return Err(MeshError::Empty);
        }
        check_nodes(&self.nodes)?;
        for (t, tet) in self.tets.iter().enumerate() {
            for &n in tet {
                if n as usize >= self.nodes.len() {
                    return Err(MeshError::IndexOutOfRange {
                        tet: t,
                        node: n,
                        nodes: self.nodes.len(),
                    });
                }
            }
        }
        let mean = self.volume().abs() / self.tets.len() as f64;
        for t in 0..self.tets.len() {
            let v = self.tet_volume(t);
            if v <= 1e-12 * mean {
                let [a, b, c, d] = self.tet_positions(t);
                let ctr = (a + b + c + d) / 4.0;
                return Err(MeshError::Inverted {
                    tet: t,
                    volume: v,
                    x: ctr.x,
                    y: ctr.y,
                    z: ctr.z,
                });
            }
        }
        Ok(())
    }

    /// The faces that belong to exactly one tetrahedron, wound outward, in a
    /// deterministic order (sorted by their node triple).
    pub fn boundary_facets(&self) -> Vec<[u32; 3]> {
        let mut seen: HashMap<[u32; 3], (u32, [u32; 3])> =
            HashMap::with_capacity(self.tets.len() * 2);
        for tet in &self.tets {
            for face in TET_FACES {
                let oriented = face.map(|k| tet[k]);
                let mut key = oriented;
                key.sort_unstable();
                seen.entry(key)
                    .and_modify(|e| e.0 += 1)
                    .or_insert((1, oriented));
            }
        }
        let mut out: Vec<([u32; 3], [u32; 3])> = seen
            .into_iter()
            .filter(|(_, (n, _))| *n == 1)
            .map(|(k, (_, f))| (k, f))
            .collect();
        out.sort_unstable_by_key(|(k, _)| *k);
        out.into_iter().map(|(_, f)| f).collect()
    }

    /// Unique edges `[i, j]` with `i < j`, sorted.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut edges: Vec<[u32; 2]> = self
            .tets
            .iter()
            .flat_map(|t| {
                TET_EDGES.map(|[a, b]| {
                    let (i, j) = (t[a], t[b]);
                    if i < j { [i, j] } else { [j, i] }
                })
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
    }

    /// Shape quality of tetrahedron `t`: `6 sqrt(2) V / l_rms^3`, 1 for a regular one, 0 for a
    /// flat one.
    pub fn tet_quality(&self, t: usize) -> f64 {
        let p = self.tet_positions(t);
        let sum_sq: f64 = TET_EDGES
            .iter()
            .map(|[a, b]| p[*a].distance_squared(p[*b]))
            .sum();
        let l_rms = (sum_sq / 6.0).sqrt();
        6.0 * std::f64::consts::SQRT_2 * self.tet_volume(t).abs() / l_rms.powi(3)
    }

    /// The counts, volume, edge range and worst quality ([`MeshStats`]).
    pub fn stats(&self) -> MeshStats {
        let mut worst_quality = f64::INFINITY;
        let (mut min_edge, mut max_edge) = (f64::INFINITY, 0.0f64);
        for t in 0..self.tets.len() {
            let p = self.tet_positions(t);
            let mut sum_sq = 0.0;
            for [a, b] in TET_EDGES {
                let l = p[a].distance(p[b]);
                sum_sq += l * l;
                min_edge = min_edge.min(l);
                max_edge = max_edge.max(l);
            }
            let l_rms = (sum_sq / 6.0).sqrt();
            let q = 6.0 * std::f64::consts::SQRT_2 * self.tet_volume(t) / l_rms.powi(3);
            worst_quality = worst_quality.min(q);
        }
        MeshStats {
            nodes: self.nodes.len(),
            tets: self.tets.len(),
            boundary_facets: self.boundary_facets().len(),
            volume: self.volume(),
            worst_quality,
            min_edge,
            max_edge,
        }
    }
}

impl std::fmt::Display for MeshStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} nodes, {} tetrahedra, {} boundary facets, volume {:.4e} m^3, edges {:.2}-{:.2} mm, worst quality {:.3}",
            self.nodes,
            self.tets,
            self.boundary_facets,
            self.volume,
            self.min_edge * 1e3,
            self.max_edge * 1e3,
            self.worst_quality
        )
    }
}

/// Coordinates past this (in any unit: a kilometre in micrometres) are a damaged number: a
/// node at 1e300 once read as "tetrahedron 0 degenerate near (0, 0, 0)".
pub const MAX_COORDINATE: f64 = 1e9;

/// Every node finite and within [`MAX_COORDINATE`], checked before any volume is computed.
pub(crate) fn check_nodes(nodes: &[DVec3]) -> Result<(), MeshError> {
    for (i, p) in nodes.iter().enumerate() {
        if !p.is_finite() {
            return Err(MeshError::NonFinite {
                node: i,
                position: p.to_array(),
            });
        }
        if p.abs().max_element() > MAX_COORDINATE {
            return Err(MeshError::FarAway {
                node: i,
                position: p.to_array(),
            });
        }
    }
    Ok(())
}
