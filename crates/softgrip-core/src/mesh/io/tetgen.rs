//! TetGen's `.node`, `.ele` and `.face` files (TetGen manual, "File
//! formats"): `#` comments, numbering from 0 or 1 as the files choose,
//! attributes and boundary markers read and ignored.

use glam::DVec3;

use super::builder::{Builder, Imported};
use super::cursor::Cursor;
use super::error::ImportError;
use super::text::num;
use crate::mesh::TetMesh;

/// The text with `#` comments blanked (line numbers kept).
fn uncommented(bytes: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let mut comment = false;
    for b in &mut out {
        if *b == b'\n' {
            comment = false;
        } else if *b == b'#' || comment {
            comment = true;
            *b = b' ';
        }
    }
    out
}

/// The mesh of a `.node` and `.ele` pair, checked against the optional
/// `.face` file (whose faces only raise a warning when their count differs).
pub fn read(
    node: (&[u8], &str),
    ele: (&[u8], &str),
    face: Option<(&[u8], String)>,
) -> Result<Imported, ImportError> {
    let mut b = Builder::default();
    read_node(&mut b, node)?;
    read_ele(&mut b, ele)?;
    let known: std::collections::HashSet<i64> = b.index.keys().copied().collect();
    let mut imported = b.finish().map_err(|m| ImportError::at(ele.1, None, m))?;

    if let Some((bytes, name)) = face {
        check_face(&mut imported, &known, bytes, &name)?;
    }
    Ok(imported)
}

/// The points of a `.node` file (`bytes`, file `name`), added to `b`.
fn read_node(b: &mut Builder, (bytes, name): (&[u8], &str)) -> Result<(), ImportError> {
    let text = uncommented(bytes);
    let mut c = Cursor::new(&text, name);
    if c.at_end() {
        return Err(c.error("the .node file is empty"));
    }
    let n = c.usize("the number of points")?;
    let dim = c.usize("the dimension")?;
    if dim != 3 {
        return Err(c.error(format!("dimension {dim}: softgrip reads 3-D meshes only")));
    }
    let attributes = c.usize("the number of attributes")?;
    let markers = c.usize("the boundary-marker flag")?;
    if markers > 1 {
        return Err(c.error(format!("boundary-marker flag {markers}: must be 0 or 1")));
    }
    let n = c.check_count(n, 8, "points")?;
    for _ in 0..n {
        let tag = c.i64("a point number")?;
        let p = DVec3::new(
            c.f64("an x coordinate")?,
            c.f64("a y coordinate")?,
            c.f64("a z coordinate")?,
        );
        for _ in 0..attributes + markers {
            c.f64("a point attribute or marker")?;
        }
        b.node(tag, p).map_err(|m| c.error(m))?;
    }
    if !c.at_end() {
        return Err(c.error(format!(
            "more data after the {n} points announced (a wrong count?)"
        )));
    }
    Ok(())
}

/// The tetrahedra of an `.ele` file (`bytes`, file `name`), added to `b`
/// (10-node ones by their corners, with a note).
fn read_ele(b: &mut Builder, (bytes, name): (&[u8], &str)) -> Result<(), ImportError> {
    let text = uncommented(bytes);
    let mut c = Cursor::new(&text, name);
    if c.at_end() {
        return Err(c.error("the .ele file is empty"));
    }
    let t = c.usize("the number of tetrahedra")?;
    let per = c.usize("the nodes per tetrahedron")?;
    if per != 4 && per != 10 {
        return Err(c.error(format!("{per} nodes per tetrahedron: must be 4 or 10")));
    }
    let region = c.usize("the region-attribute flag")?;
    let t = c.check_count(t, 10, "tetrahedra")?;
    for _ in 0..t {
        c.i64("a tetrahedron number")?;
        let mut tet = [0i64; 4];
        for slot in &mut tet {
            *slot = c.i64("a tetrahedron's node")?;
        }
        for _ in 4..per {
            c.i64("a tetrahedron's mid-edge node")?;
        }
        for _ in 0..region {
            c.f64("a region attribute")?;
        }
        b.tets.push(tet);
    }
    if !c.at_end() {
        return Err(c.error(format!(
            "more data after the {t} tetrahedra announced (a wrong count?)"
        )));
    }
    if per == 10 {
        b.notes
            .push("second-order tetrahedra: only their corner nodes are used".into());
    }
    Ok(())
}

/// Reads a `.face` file: every face's points must be among `known` (the
/// `.node` file's numbers); a face count other than the mesh's boundary is a
/// warning on `imported`.
fn check_face(
    imported: &mut Imported,
    known: &std::collections::HashSet<i64>,
    bytes: &[u8],
    name: &str,
) -> Result<(), ImportError> {
    let text = uncommented(bytes);
    let mut c = Cursor::new(&text, name);
    let f = c.usize("the number of faces")?;
    let markers = c.usize("the boundary-marker flag")?;
    let f = c.check_count(f, 8, "faces")?;
    for _ in 0..f {
        c.i64("a face number")?;
        for _ in 0..3 {
            let v = c.i64("a face's node")?;
            if !known.contains(&v) {
                return Err(c.error(format!(
                    "a face refers to point {v}, which the .node file does not define"
                )));
            }
        }
        for _ in 0..markers {
            c.i64("a face marker")?;
        }
    }
    let boundary = imported.mesh.boundary_facets().len();
    if f != boundary {
        imported.warnings.push(format!(
            "the .face file lists {f} faces; the tetrahedra have {boundary} boundary faces (softgrip uses the latter)"
        ));
    }
    Ok(())
}

/// `.node`, `.ele` and `.face` text, numbered from 1.
pub fn write(mesh: &TetMesh) -> (String, String, String) {
    use std::fmt::Write as _;
    let mut node = String::new();
    let _ = writeln!(node, "# written by softgrip\n{} 3 0 0", mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(node, "{} {} {} {}", i + 1, num(p.x), num(p.y), num(p.z));
    }
    let mut ele = String::new();
    let _ = writeln!(ele, "# written by softgrip\n{} 4 0", mesh.tets.len());
    for (k, t) in mesh.tets.iter().enumerate() {
        let _ = writeln!(
            ele,
            "{} {} {} {} {}",
            k + 1,
            t[0] + 1,
            t[1] + 1,
            t[2] + 1,
            t[3] + 1
        );
    }
    let facets = mesh.boundary_facets();
    let mut face = String::new();
    let _ = writeln!(
        face,
        "# written by softgrip: the boundary, wound outward\n{} 0",
        facets.len()
    );
    for (k, f) in facets.iter().enumerate() {
        let _ = writeln!(face, "{} {} {} {}", k + 1, f[0] + 1, f[1] + 1, f[2] + 1);
    }
    (node, ele, face)
}
