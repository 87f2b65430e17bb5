//! VTK legacy `.vtk` unstructured grids ("VTK File Formats", legacy
//! section): versions up to 4.2 (`CELLS n size` with counts inline) and
//! 5.1 (`OFFSETS` and `CONNECTIVITY` arrays), ASCII or BINARY (big-endian).
//! Tetrahedra are cell type 10 (and 24, quadratic: corners used).

use glam::DVec3;

use super::builder::{Builder, Imported};
use super::cursor::Cursor;
use super::error::ImportError;
use super::text::num;
use crate::mesh::TetMesh;

/// What to call a skipped VTK cell type.
fn cell_name(kind: i64) -> String {
    match kind {
        1 => "vertices".into(),
        3 => "lines".into(),
        5 => "triangles".into(),
        7 => "polygons".into(),
        9 => "quads".into(),
        12 => "hexahedra".into(),
        13 => "wedges".into(),
        14 => "pyramids".into(),
        22 => "quadratic triangles".into(),
        k => format!("cells of type {k}"),
    }
}

/// A data type of the legacy format.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    F32,
    F64,
    I32,
    I64,
}

fn kind_of(c: &Cursor, name: &str) -> Result<Kind, ImportError> {
    Ok(match name.to_ascii_lowercase().as_str() {
        "float" => Kind::F32,
        "double" => Kind::F64,
        "int" | "unsigned_int" | "vtktypeint32" => Kind::I32,
        "long" | "unsigned_long" | "vtktypeint64" | "vtkidtype" => Kind::I64,
        other => {
            return Err(c.error(format!(
                "data type {other:?} is not one softgrip reads here (float, double, int, vtktypeint64)"
            )));
        }
    })
}

struct Reader<'a> {
    c: Cursor<'a>,
    binary: bool,
}

impl Reader<'_> {
    fn real(&mut self, kind: Kind, what: &str) -> Result<f64, ImportError> {
        let v = if !self.binary {
            return self.c.f64(what);
        } else {
            match kind {
                Kind::F32 => self.c.be_f32(what)?,
                Kind::F64 => self.c.be_f64(what)?,
                Kind::I32 => self.c.be_i32(what)? as f64,
                Kind::I64 => self.c.be_i64(what)? as f64,
            }
        };
        if !v.is_finite() {
            return Err(self
                .c
                .binary_error(format!("{what} is {v}: coordinates must be finite")));
        }
        Ok(v)
    }

    fn int(&mut self, kind: Kind, what: &str) -> Result<i64, ImportError> {
        if !self.binary {
            return self.c.i64(what);
        }
        match kind {
            Kind::I32 => self.c.be_i32(what),
            Kind::I64 => self.c.be_i64(what),
            Kind::F32 | Kind::F64 => Err(self
                .c
                .binary_error(format!("{what}: integers expected, not reals"))),
        }
    }

    fn size(kind: Kind) -> usize {
        match kind {
            Kind::F32 | Kind::I32 => 4,
            Kind::F64 | Kind::I64 => 8,
        }
    }

    /// After a keyword line announcing binary data.
    fn begin_data(&mut self) {
        if self.binary {
            self.c.end_of_header_line();
        }
    }

    /// The `POINTS` section (after its keyword), each point added to `b`.
    fn points(&mut self, b: &mut Builder) -> Result<(), ImportError> {
        let n = self.c.usize("the number of points")?;
        let data_type = self.c.expect_token("the data type")?;
        let kind = kind_of(&self.c, data_type)?;
        self.begin_data();
        let n = self.c.check_count(
            n,
            if self.binary {
                3 * Reader::size(kind)
            } else {
                6
            },
            "points",
        )?;
        for i in 0..n {
            let p = DVec3::new(
                self.real(kind, "an x coordinate")?,
                self.real(kind, "a y coordinate")?,
                self.real(kind, "a z coordinate")?,
            );
            b.node(i as i64, p).map_err(|m| self.c.error(m))?;
        }
        Ok(())
    }

    /// A 4.2 `CELLS n size` section (after its keyword): each cell's node
    /// count inline before its nodes.
    fn cells_inline(&mut self) -> Result<Vec<Vec<i64>>, ImportError> {
        let binary = self.binary;
        let n = self.c.usize("the number of cells")?;
        let size = self.c.usize("the size of the cell list")?;
        self.begin_data();
        let n = self.c.check_count(n, if binary { 4 } else { 2 }, "cells")?;
        self.c
            .check_count(size, if binary { 4 } else { 2 }, "cell list entries")?;
        let mut list = Vec::with_capacity(n);
        let mut used = 0usize;
        for _ in 0..n {
            let count = self.int(Kind::I32, "a cell's node count")?;
            if count < 0 || used + 1 + count as usize > size {
                return Err(self.c.error(format!(
                    "a cell of {count} nodes overruns the cell list of {size} entries"
                )));
            }
            let count =
                self.c
                    .check_count(count as usize, if binary { 4 } else { 2 }, "cell nodes")?;
            let mut cell = Vec::with_capacity(count);
            for _ in 0..count {
                cell.push(self.int(Kind::I32, "a cell's node")?);
            }
            used += 1 + count;
            list.push(cell);
        }
        if used != size {
            return Err(self.c.error(format!(
                "the cells use {used} entries, the header announced {size}"
            )));
        }
        Ok(list)
    }

    /// `len` integers after an array's `KEYWORD type` line (5.1's `OFFSETS`
    /// and `CONNECTIVITY`), `what` naming the array and `one` an entry.
    fn int_array(
        &mut self,
        keyword: &str,
        len: usize,
        what: &str,
        one: &str,
    ) -> Result<Vec<i64>, ImportError> {
        self.c.expect_keyword(keyword)?;
        let data_type = self.c.expect_token("the data type")?;
        let kind = kind_of(&self.c, data_type)?;
        self.begin_data();
        let len =
            self.c
                .check_count(len, if self.binary { Reader::size(kind) } else { 2 }, what)?;
        let mut out = Vec::with_capacity(len);
        for _ in 0..len {
            out.push(self.int(kind, one)?);
        }
        Ok(out)
    }

    /// A 5.1 `CELLS offsets connectivity` section (after its keyword): the
    /// `OFFSETS` and `CONNECTIVITY` arrays, cut into cells.
    fn cells_with_offsets(&mut self) -> Result<Vec<Vec<i64>>, ImportError> {
        let offsets = self.c.usize("the number of offsets")?;
        let connectivity = self.c.usize("the connectivity size")?;
        let off = self.int_array("OFFSETS", offsets, "offsets", "an offset")?;
        let offsets = off.len();
        let conn = self.int_array(
            "CONNECTIVITY",
            connectivity,
            "connectivity entries",
            "a cell's node",
        )?;
        let mut list = Vec::with_capacity(offsets.saturating_sub(1));
        for w in off.windows(2) {
            let (a, z) = (w[0], w[1]);
            if a < 0 || z < a || z as usize > conn.len() {
                return Err(self.c.error(format!(
                    "offsets {a}..{z} do not fit the {} connectivity entries",
                    conn.len()
                )));
            }
            list.push(conn[a as usize..z as usize].to_vec());
        }
        Ok(list)
    }

    /// The `CELL_TYPES` section (after its keyword).
    fn cell_types(&mut self) -> Result<Vec<i64>, ImportError> {
        let n = self.c.usize("the number of cell types")?;
        self.begin_data();
        let n = self
            .c
            .check_count(n, if self.binary { 4 } else { 2 }, "cell types")?;
        let mut list = Vec::with_capacity(n);
        for _ in 0..n {
            list.push(self.int(Kind::I32, "a cell type")?);
        }
        Ok(list)
    }

    /// Skips a `METADATA` section: until the blank line that ends it.
    fn skip_metadata(&mut self) {
        self.c.rest_of_line();
        loop {
            if self.c.remaining() == 0 {
                break;
            }
            if self.c.rest_of_line().trim().is_empty() {
                break;
            }
        }
    }
}

/// The four header lines: the version line (returns whether it is 5 or
/// later), the title, ASCII or BINARY (returns whether binary) and
/// `DATASET UNSTRUCTURED_GRID`.
fn header(c: &mut Cursor, name: &str) -> Result<(bool, bool), ImportError> {
    let first = c.rest_of_line();
    let version = first
        .trim()
        .strip_prefix("# vtk DataFile Version")
        .map(str::trim)
        .ok_or_else(|| {
            ImportError::at(
                name,
                Some(1),
                "not a VTK legacy file: the first line must be \"# vtk DataFile Version x.y\"",
            )
        })?;
    let modern = version
        .split('.')
        .next()
        .and_then(|m| m.parse::<u32>().ok())
        .is_some_and(|m| m >= 5);
    c.rest_of_line(); // title
    let format = c.expect_token("ASCII or BINARY")?.to_ascii_uppercase();
    let binary = match format.as_str() {
        "ASCII" => false,
        "BINARY" => true,
        f => return Err(c.error(format!("{f:?}: the third line must be ASCII or BINARY"))),
    };
    c.expect_keyword("DATASET")?;
    let dataset = c.expect_token("the dataset type")?;
    if !dataset.eq_ignore_ascii_case("UNSTRUCTURED_GRID") {
        return Err(c.error(format!(
            "DATASET {dataset}: softgrip reads UNSTRUCTURED_GRID (tetrahedra) only"
        )));
    }
    Ok((modern, binary))
}

/// The tetrahedra of a legacy `.vtk` unstructured grid (other cells skipped).
pub fn read(bytes: &[u8], name: &str) -> Result<Imported, ImportError> {
    let mut c = Cursor::new(bytes, name);
    let (modern, binary) = header(&mut c, name)?;
    let mut r = Reader { c, binary };
    let mut b = Builder::default();
    let mut cells: Option<Vec<Vec<i64>>> = None;
    let mut types: Option<Vec<i64>> = None;
    let mut points = false;
    loop {
        let complete = points && cells.is_some() && types.is_some();
        if complete || r.c.at_end() {
            break;
        }
        let keyword = r.c.expect_token("a keyword")?.to_ascii_uppercase();
        match keyword.as_str() {
            "POINTS" => {
                r.points(&mut b)?;
                points = true;
            }
            "CELLS" if !modern => cells = Some(r.cells_inline()?),
            "CELLS" => cells = Some(r.cells_with_offsets()?),
            "CELL_TYPES" => types = Some(r.cell_types()?),
            "METADATA" => r.skip_metadata(),
            "POINT_DATA" | "CELL_DATA" | "FIELD" => break,
            other => {
                return Err(r.c.error(format!(
                    "unexpected {other:?} (expected POINTS, CELLS or CELL_TYPES)"
                )));
            }
        }
    }
    let (Some(cells), Some(types)) = (cells, types) else {
        return Err(ImportError::at(
            name,
            None,
            "no CELLS and CELL_TYPES: the file has no cells (truncated?)",
        ));
    };
    add_cells(&mut b, &cells, &types, name)?;
    b.finish().map_err(|m| ImportError::at(name, None, m))
}

/// Adds the tetrahedra among `cells` (types 10 and 24) to `b`, counting the
/// others as skipped.
fn add_cells(
    b: &mut Builder,
    cells: &[Vec<i64>],
    types: &[i64],
    name: &str,
) -> Result<(), ImportError> {
    if cells.len() != types.len() {
        return Err(ImportError::at(
            name,
            None,
            format!("{} cells but {} cell types", cells.len(), types.len()),
        ));
    }
    for (cell, kind) in cells.iter().zip(types) {
        match kind {
            10 | 24 if cell.len() >= 4 => {
                b.tets.push([cell[0], cell[1], cell[2], cell[3]]);
                if *kind == 24 && !b.notes.iter().any(|n| n.starts_with("quadratic")) {
                    b.notes
                        .push("quadratic tetrahedra: only their corner nodes are used".into());
                }
            }
            10 | 24 => {
                return Err(ImportError::at(
                    name,
                    None,
                    format!("a tetrahedron with {} nodes", cell.len()),
                ));
            }
            k => b.skip(&cell_name(*k)),
        }
    }
    Ok(())
}

/// VTK legacy 4.2 ASCII.
pub fn write(mesh: &TetMesh) -> String {
    use std::fmt::Write as _;
    let n = mesh.nodes.len();
    let t = mesh.tets.len();
    let mut s = String::with_capacity(48 * n + 32 * t + 256);
    let _ = writeln!(
        s,
        "# vtk DataFile Version 4.2\nsoftgrip tetrahedral mesh\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {n} double"
    );
    for p in &mesh.nodes {
        let _ = writeln!(s, "{} {} {}", num(p.x), num(p.y), num(p.z));
    }
    let _ = writeln!(s, "CELLS {t} {}", 5 * t);
    for tet in &mesh.tets {
        let _ = writeln!(s, "4 {} {} {} {}", tet[0], tet[1], tet[2], tet[3]);
    }
    let _ = writeln!(s, "CELL_TYPES {t}");
    for _ in 0..t {
        s.push_str("10\n");
    }
    s
}
