//! Gmsh `.msh`: format 2.2 and 4.1, ASCII and binary (little-endian,
//! data size 8), following the Gmsh reference manual's "MSH file format".
//! Sections other than `$MeshFormat`, `$Nodes` and `$Elements` are skipped.

use glam::DVec3;

use super::builder::{Builder, Imported};
use super::cursor::Cursor;
use super::error::ImportError;
use super::text::num;
use crate::mesh::TetMesh;

/// Nodes of a Gmsh element type (the manual's table), and what to call
/// skipped ones.
fn element_nodes(kind: i64) -> Option<(usize, &'static str)> {
    Some(match kind {
        1 => (2, "lines"),
        2 => (3, "triangles"),
        3 => (4, "quadrangles"),
        4 => (4, "tetrahedra"),
        5 => (8, "hexahedra"),
        6 => (6, "prisms"),
        7 => (5, "pyramids"),
        8 => (3, "second-order lines"),
        9 => (6, "second-order triangles"),
        10 => (9, "second-order quadrangles"),
        11 => (10, "second-order tetrahedra"),
        12 => (27, "second-order hexahedra"),
        13 => (18, "second-order prisms"),
        14 => (14, "second-order pyramids"),
        15 => (1, "points"),
        16 => (8, "serendipity quadrangles"),
        17 => (20, "serendipity hexahedra"),
        18 => (15, "serendipity prisms"),
        19 => (13, "serendipity pyramids"),
        20 => (9, "third-order triangles"),
        21 => (10, "third-order triangles"),
        22 => (12, "fourth-order triangles"),
        23 => (15, "fourth-order triangles"),
        24 => (15, "fifth-order triangles"),
        25 => (21, "fifth-order triangles"),
        26 => (4, "third-order lines"),
        27 => (5, "fourth-order lines"),
        28 => (6, "fifth-order lines"),
        29 => (20, "third-order tetrahedra"),
        30 => (35, "fourth-order tetrahedra"),
        31 => (56, "fifth-order tetrahedra"),
        92 => (64, "third-order hexahedra"),
        93 => (125, "fourth-order hexahedra"),
        _ => return None,
    })
}

/// Tetrahedra of any order: their first four nodes are the corners.
fn is_tetrahedron(kind: i64) -> bool {
    matches!(kind, 4 | 11 | 29 | 30 | 31)
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Version {
    V22,
    V41,
}

struct Header {
    version: Version,
    binary: bool,
}

/// The tetrahedra of a `.msh` file (other elements skipped).
pub fn read(bytes: &[u8], name: &str) -> Result<Imported, ImportError> {
    let mut c = Cursor::new(bytes, name);
    let mut header: Option<Header> = None;
    let mut b = Builder::default();
    let (mut seen_nodes, mut seen_elements) = (false, false);
    let mut higher_order = false;
    while !c.at_end() {
        let line = c.line();
        let token = c.expect_token("a section")?;
        let Some(section) = token.strip_prefix('$') else {
            return Err(c.error(format!(
                "expected a section such as $Nodes, found {token:?}{}",
                if line == 1 {
                    " (is this a Gmsh .msh file?)"
                } else {
                    ""
                }
            )));
        };
        match section {
            "MeshFormat" => header = Some(read_format(&mut c)?),
            "Nodes" | "Elements" => {
                let Some(h) = header.as_ref() else {
                    return Err(c.error(format!(
                        "${section} before $MeshFormat (is this a Gmsh .msh file?)"
                    )));
                };
                if section == "Nodes" {
                    if seen_nodes {
                        return Err(c.error("a second $Nodes section"));
                    }
                    seen_nodes = true;
                    nodes_section(&mut c, &mut b, h)?;
                } else {
                    if seen_elements {
                        return Err(c.error("a second $Elements section"));
                    }
                    seen_elements = true;
                    higher_order = elements_section(&mut c, &mut b, h)?;
                }
            }
            s if s.starts_with("End") => {
                return Err(c.error(format!("${s} without its opening section")));
            }
            other => {
                c.rest_of_line();
                c.skip_past_line(&format!("$End{other}"))?;
            }
        }
    }
    if header.is_none() {
        return Err(ImportError::at(
            name,
            None,
            "no $MeshFormat section: not a Gmsh .msh file (or an empty one)",
        ));
    }
    if !seen_nodes || !seen_elements {
        return Err(ImportError::at(
            name,
            None,
            format!(
                "no {} section (truncated?)",
                if seen_nodes { "$Elements" } else { "$Nodes" }
            ),
        ));
    }
    if higher_order {
        b.notes.push(
            "higher-order tetrahedra: only their corner nodes are used (the mesh is linear)".into(),
        );
    }
    b.finish().map_err(|m| ImportError::at(name, None, m))
}

/// A `$Nodes` section's body in the header's version and encoding, and its `$EndNodes`.
fn nodes_section(c: &mut Cursor, b: &mut Builder, h: &Header) -> Result<(), ImportError> {
    match (h.version, h.binary) {
        (Version::V22, false) => nodes_22(c, b)?,
        (Version::V22, true) => nodes_22_binary(c, b)?,
        (Version::V41, binary) => nodes_41(c, b, binary)?,
    }
    c.expect_keyword("$EndNodes")
}

/// An `$Elements` section's body in the header's version and encoding, and its
/// `$EndElements`: whether higher-order tetrahedra were among them.
fn elements_section(c: &mut Cursor, b: &mut Builder, h: &Header) -> Result<bool, ImportError> {
    let higher_order = match (h.version, h.binary) {
        (Version::V22, false) => elements_22(c, b)?,
        (Version::V22, true) => elements_22_binary(c, b)?,
        (Version::V41, binary) => elements_41(c, b, binary)?,
    };
    c.expect_keyword("$EndElements")?;
    Ok(higher_order)
}

fn read_format(c: &mut Cursor) -> Result<Header, ImportError> {
    let version = c.expect_token("the format version")?;
    let version = match version {
        "2.2" | "2.1" | "2" => Version::V22,
        "4.1" => Version::V41,
        "4" | "4.0" => {
            return Err(c.error(
                "Gmsh format 4.0 is not supported; save as 4.1 or 2.2 (Gmsh: File > Export, or -format msh41)",
            ));
        }
        v => {
            return Err(c.error(format!(
                "Gmsh format {v:?} is not supported; softgrip reads 2.2 and 4.1"
            )));
        }
    };
    let file_type = c.usize("the file type (0 ASCII, 1 binary)")?;
    let data_size = c.usize("the data size")?;
    let binary = match file_type {
        0 => false,
        1 => true,
        t => return Err(c.error(format!("file type {t}: must be 0 (ASCII) or 1 (binary)"))),
    };
    if binary {
        if data_size != 8 {
            return Err(c.error(format!(
                "binary data size {data_size}: softgrip reads 8-byte (64-bit) files only"
            )));
        }
        c.end_of_header_line();
        let one = c.bin_i32("the endianness check")?;
        if one != 1 {
            return Err(c.binary_error(
                "the endianness check is not 1: a big-endian file, which softgrip does not read",
            ));
        }
    }
    c.expect_keyword("$EndMeshFormat")?;
    Ok(Header { version, binary })
}

fn point(c: &mut Cursor) -> Result<DVec3, ImportError> {
    Ok(DVec3::new(
        c.f64("an x coordinate")?,
        c.f64("a y coordinate")?,
        c.f64("a z coordinate")?,
    ))
}

fn bin_point(c: &mut Cursor) -> Result<DVec3, ImportError> {
    Ok(DVec3::new(
        c.bin_f64("an x coordinate")?,
        c.bin_f64("a y coordinate")?,
        c.bin_f64("a z coordinate")?,
    ))
}

fn add_node(c: &Cursor, b: &mut Builder, tag: i64, p: DVec3) -> Result<(), ImportError> {
    b.node(tag, p).map_err(|m| c.error(m))
}

fn nodes_22(c: &mut Cursor, b: &mut Builder) -> Result<(), ImportError> {
    let n = c.usize("the number of nodes")?;
    let n = c.check_count(n, 8, "nodes")?;
    for _ in 0..n {
        let tag = c.i64("a node number")?;
        let p = point(c)?;
        add_node(c, b, tag, p)?;
    }
    Ok(())
}

fn nodes_22_binary(c: &mut Cursor, b: &mut Builder) -> Result<(), ImportError> {
    let n = c.usize("the number of nodes")?;
    c.end_of_header_line();
    let n = c.check_count(n, 28, "nodes")?;
    for _ in 0..n {
        let tag = i64::from(c.bin_i32("a node number")?);
        let p = bin_point(c)?;
        add_node(c, b, tag, p)?;
    }
    Ok(())
}

/// Adds one element; true if it was a higher-order tetrahedron.
fn element(c: &Cursor, b: &mut Builder, kind: i64, nodes: &[i64]) -> Result<bool, ImportError> {
    if is_tetrahedron(kind) {
        if nodes.len() < 4 {
            return Err(c.error("a tetrahedron with fewer than 4 nodes"));
        }
        b.tets.push([nodes[0], nodes[1], nodes[2], nodes[3]]);
        return Ok(kind != 4);
    }
    let name =
        element_nodes(kind).map_or_else(|| format!("elements of type {kind}"), |(_, n)| n.into());
    b.skip(&name);
    Ok(false)
}

fn elements_22(c: &mut Cursor, b: &mut Builder) -> Result<bool, ImportError> {
    let n = c.usize("the number of elements")?;
    let n = c.check_count(n, 8, "elements")?;
    let mut higher = false;
    let mut nodes = Vec::new();
    for _ in 0..n {
        let _tag = c.i64("an element number")?;
        let kind = c.i64("an element type")?;
        let Some((count, _)) = element_nodes(kind) else {
            return Err(c.error(format!(
                "element type {kind} is not a Gmsh element type softgrip knows"
            )));
        };
        let tags = c.usize("the number of element tags")?;
        let tags = c.check_count(tags, 2, "element tags")?;
        for _ in 0..tags {
            c.i64("an element tag")?;
        }
        nodes.clear();
        for _ in 0..count {
            nodes.push(c.i64("an element's node")?);
        }
        higher |= element(c, b, kind, &nodes)?;
    }
    Ok(higher)
}

fn elements_22_binary(c: &mut Cursor, b: &mut Builder) -> Result<bool, ImportError> {
    let total = c.usize("the number of elements")?;
    c.end_of_header_line();
    let total = c.check_count(total, 8, "elements")?;
    let mut done = 0usize;
    let mut higher = false;
    let mut nodes = Vec::new();
    while done < total {
        let kind = i64::from(c.bin_i32("an element type")?);
        let Some((count, _)) = element_nodes(kind) else {
            return Err(c.binary_error(format!(
                "element type {kind} is not a Gmsh element type softgrip knows"
            )));
        };
        let in_block = c.bin_i32("an element count")?;
        let tags = c.bin_i32("a tag count")?;
        if in_block <= 0 || tags < 0 || done + in_block as usize > total {
            return Err(c.binary_error(format!(
                "an element block of {in_block} elements with {tags} tags does not fit the {total} elements announced"
            )));
        }
        let per = 4 * (1 + tags as usize + count);
        c.check_count(in_block as usize, per, "elements")?;
        for _ in 0..in_block {
            c.bin_i32("an element number")?;
            for _ in 0..tags {
                c.bin_i32("an element tag")?;
            }
            nodes.clear();
            for _ in 0..count {
                nodes.push(i64::from(c.bin_i32("an element's node")?));
            }
            higher |= element(c, b, kind, &nodes)?;
        }
        done += in_block as usize;
    }
    Ok(higher)
}

/// A size_t of a binary 4.1 file as a count or tag.
fn bin_size(c: &mut Cursor, what: &str) -> Result<usize, ImportError> {
    let v = c.bin_u64(what)?;
    usize::try_from(v)
        .ok()
        .filter(|v| *v <= i64::MAX as usize)
        .ok_or_else(|| c.binary_error(format!("{what} is {v}: too large")))
}

/// The header of a 4.1 `$Nodes` or `$Elements` section: the number of
/// entity blocks and of items (the tag range after them is skipped).
fn section_header_41(
    c: &mut Cursor,
    binary: bool,
    item: &str,
) -> Result<(usize, usize), ImportError> {
    let what = [
        format!("the number of {item} blocks"),
        format!("the number of {item}s"),
        format!("the smallest {item} tag"),
        format!("the largest {item} tag"),
    ];
    let mut v = [0usize; 4];
    if binary {
        c.end_of_header_line();
    }
    for (slot, what) in v.iter_mut().zip(&what) {
        *slot = if binary {
            bin_size(c, what)?
        } else {
            c.usize(what)?
        };
    }
    Ok((v[0], v[1]))
}

fn nodes_41(c: &mut Cursor, b: &mut Builder, binary: bool) -> Result<(), ImportError> {
    let (blocks, total) = section_header_41(c, binary, "node")?;
    let blocks = c.check_count(blocks, 4, "node blocks")?;
    let total = c.check_count(total, 8, "nodes")?;
    let mut read = 0usize;
    let mut tags = Vec::new();
    for _ in 0..blocks {
        let (dim, parametric, count) = if binary {
            let dim = c.bin_i32("an entity dimension")?;
            c.bin_i32("an entity tag")?;
            let parametric = c.bin_i32("the parametric flag")?;
            (dim, parametric, bin_size(c, "a block's node count")?)
        } else {
            let dim = c.i64("an entity dimension")? as i32;
            c.i64("an entity tag")?;
            let parametric = c.i64("the parametric flag")? as i32;
            (dim, parametric, c.usize("a block's node count")?)
        };
        if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
            return Err(c.error(format!(
                "a node block of dimension {dim}, parametric {parametric}: expected 0-3 and 0 or 1"
            )));
        }
        let extra = if parametric == 1 { dim as usize } else { 0 };
        if read + count > total {
            return Err(c.error(format!(
                "the node blocks hold more than the {total} nodes announced"
            )));
        }
        let count = c.check_count(count, 8, "nodes in a block")?;
        tags.clear();
        for _ in 0..count {
            tags.push(if binary {
                bin_size(c, "a node tag")? as i64
            } else {
                c.i64("a node tag")?
            });
        }
        for &tag in &tags {
            let p = if binary { bin_point(c)? } else { point(c)? };
            for _ in 0..extra {
                if binary {
                    c.bin_f64("a parametric coordinate")?;
                } else {
                    c.f64("a parametric coordinate")?;
                }
            }
            add_node(c, b, tag, p)?;
        }
        read += count;
    }
    if read != total {
        return Err(c.error(format!(
            "the node blocks hold {read} nodes, the section announced {total}"
        )));
    }
    Ok(())
}

fn elements_41(c: &mut Cursor, b: &mut Builder, binary: bool) -> Result<bool, ImportError> {
    let (blocks, total) = section_header_41(c, binary, "element")?;
    let blocks = c.check_count(blocks, 4, "element blocks")?;
    let total = c.check_count(total, 4, "elements")?;
    let mut read = 0usize;
    let mut higher = false;
    let mut nodes = Vec::new();
    for _ in 0..blocks {
        let (kind, count) = if binary {
            c.bin_i32("an entity dimension")?;
            c.bin_i32("an entity tag")?;
            let kind = i64::from(c.bin_i32("an element type")?);
            (kind, bin_size(c, "a block's element count")?)
        } else {
            c.i64("an entity dimension")?;
            c.i64("an entity tag")?;
            let kind = c.i64("an element type")?;
            (kind, c.usize("a block's element count")?)
        };
        let Some((per, _)) = element_nodes(kind) else {
            return Err(c.error(format!(
                "element type {kind} is not a Gmsh element type softgrip knows"
            )));
        };
        if read + count > total {
            return Err(c.error(format!(
                "the element blocks hold more than the {total} elements announced"
            )));
        }
        let count = c.check_count(count, 2 * (per + 1), "elements in a block")?;
        for _ in 0..count {
            nodes.clear();
            if binary {
                bin_size(c, "an element tag")?;
                for _ in 0..per {
                    nodes.push(bin_size(c, "an element's node")? as i64);
                }
            } else {
                c.i64("an element tag")?;
                for _ in 0..per {
                    nodes.push(c.i64("an element's node")?);
                }
            }
            higher |= element(c, b, kind, &nodes)?;
        }
        read += count;
    }
    if read != total {
        return Err(c.error(format!(
            "the element blocks hold {read} elements, the section announced {total}"
        )));
    }
    Ok(higher)
}

/// Gmsh 4.1 ASCII: one volume entity holding every node and tetrahedron.
pub fn write_41(mesh: &TetMesh) -> String {
    use std::fmt::Write as _;
    let n = mesh.nodes.len();
    let t = mesh.tets.len();
    let mut s = String::with_capacity(48 * n + 40 * t + 256);
    s.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    let _ = writeln!(s, "$Nodes\n1 {n} 1 {n}\n3 1 0 {n}");
    for i in 1..=n {
        let _ = writeln!(s, "{i}");
    }
    for p in &mesh.nodes {
        let _ = writeln!(s, "{} {} {}", num(p.x), num(p.y), num(p.z));
    }
    s.push_str("$EndNodes\n");
    let _ = writeln!(s, "$Elements\n1 {t} 1 {t}\n3 1 4 {t}");
    for (k, tet) in mesh.tets.iter().enumerate() {
        let _ = writeln!(
            s,
            "{} {} {} {} {}",
            k + 1,
            tet[0] + 1,
            tet[1] + 1,
            tet[2] + 1,
            tet[3] + 1
        );
    }
    s.push_str("$EndElements\n");
    s
}

/// Gmsh 2.2 ASCII.
pub fn write_22(mesh: &TetMesh) -> String {
    use std::fmt::Write as _;
    let n = mesh.nodes.len();
    let t = mesh.tets.len();
    let mut s = String::with_capacity(48 * n + 40 * t + 256);
    s.push_str("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    let _ = writeln!(s, "$Nodes\n{n}");
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(s, "{} {} {} {}", i + 1, num(p.x), num(p.y), num(p.z));
    }
    let _ = writeln!(s, "$EndNodes\n$Elements\n{t}");
    for (k, tet) in mesh.tets.iter().enumerate() {
        let _ = writeln!(
            s,
            "{} 4 2 0 1 {} {} {} {}",
            k + 1,
            tet[0] + 1,
            tet[1] + 1,
            tet[2] + 1,
            tet[3] + 1
        );
    }
    s.push_str("$EndElements\n");
    s
}
