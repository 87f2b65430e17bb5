//! Closed surfaces to tetrahedra with TetGen (H. Si), through the tritet
//! crate, which builds TetGen from its C++ source. Behind the `tetgen`
//! feature: TetGen is AGPL-3.0.

use super::TetMesh;
use super::surface::Surface;

/// TetGen's radius-edge ratio bound (its `-q`): 1.5 keeps slivers out at a
/// moderate cost in elements (TetGen's default is 2).
pub const QUALITY: f64 = 1.5;

/// The volume of a regular tetrahedron of edge `h`: TetGen's `-a` bound for
/// a target edge length.
pub fn max_volume(edge_length: f64) -> f64 {
    edge_length.powi(3) / (6.0 * std::f64::consts::SQRT_2)
}

/// Tetrahedralizes a checked, outward-facing closed surface with elements
/// no larger than a regular tetrahedron of edge `edge_length`.
#[cfg(feature = "tetgen")]
pub fn tetrahedralize(s: &Surface, edge_length: f64) -> Result<TetMesh, String> {
    use glam::DVec3;
    let facets = vec![3usize; s.triangles.len()];
    let mut t = tritet::Tetgen::new(s.vertices.len(), Some(facets), None, None)
        .map_err(|e| format!("TetGen: {e}"))?;
    for (i, p) in s.vertices.iter().enumerate() {
        t.set_point(i, 0, p.x, p.y, p.z)
            .map_err(|e| format!("TetGen: {e}"))?;
    }
    for (k, tri) in s.triangles.iter().enumerate() {
        for (m, &v) in tri.iter().enumerate() {
            t.set_facet_point(k, m, v as usize)
                .map_err(|e| format!("TetGen: {e}"))?;
        }
    }
    t.generate_mesh(false, false, Some(max_volume(edge_length)), Some(QUALITY))
        .map_err(|e| format!("TetGen failed: {e}"))?;
    let (np, nc) = (t.out_npoint(), t.out_ncell());
    if nc == 0 || np < 4 || t.out_cell_npoint() < 4 {
        return Err(
            "TetGen produced no tetrahedra (a self-intersecting or degenerate surface?)".into(),
        );
    }
    let nodes = (0..np)
        .map(|i| DVec3::new(t.out_point(i, 0), t.out_point(i, 1), t.out_point(i, 2)))
        .collect();
    let tets = (0..nc)
        .map(|c| std::array::from_fn(|m| t.out_cell_point(c, m) as u32))
        .collect();
    Ok(TetMesh { nodes, tets })
}

/// Without the `tetgen` feature: the error that says how to get it.
#[cfg(not(feature = "tetgen"))]
pub fn tetrahedralize(_s: &Surface, _edge_length: f64) -> Result<TetMesh, String> {
    Err("this softgrip was built without TetGen, which tetrahedralizes .stl and .obj surfaces: rebuild with `--features tetgen` (TetGen is AGPL-3.0; see README, \"Licences\"), or mesh the surface with Gmsh and open the .msh".into())
}
