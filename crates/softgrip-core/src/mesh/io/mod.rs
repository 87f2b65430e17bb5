//! Tetrahedral mesh files in and out: Gmsh `.msh` (2.2 and 4.1, ASCII and
//! binary), TetGen `.node`/`.ele` (with an optional `.face`), VTK legacy
//! `.vtk`. Readers never panic and never trust a count: a malformed file is
//! an [`ImportError`] naming the file, the line (or byte) and what is wrong.
//! Cells other than tetrahedra are skipped with a warning that counts them.

pub(crate) mod base64;
mod builder;
pub(crate) mod cursor;
pub(crate) mod error;
mod gmsh;
mod tetgen;
mod text;
mod vtk;
mod vtu;
mod xml;

use std::path::{Path, PathBuf};

use super::TetMesh;
pub use builder::Imported;
pub use error::ImportError;
use text::num;

/// The mesh formats softgrip reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Gmsh 4.1 ASCII (`.msh`; reading also takes 2.2 and binary).
    Msh,
    /// Gmsh 2.2 ASCII (`.msh`).
    Msh22,
    /// TetGen `.node` + `.ele` (+ `.face`): give either file name.
    Tetgen,
    /// VTK legacy ASCII unstructured grid (`.vtk`; reading also takes
    /// binary and version 5.1).
    Vtk,
    /// VTK XML unstructured grid (`.vtu`, ASCII; reading also takes
    /// inline binary, appended and zlib-compressed data).
    Vtu,
}

impl Format {
    /// The format a file name implies.
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "msh" => Format::Msh,
            "node" | "ele" | "face" => Format::Tetgen,
            "vtk" => Format::Vtk,
            "vtu" => Format::Vtu,
            _ => return None,
        })
    }
}

/// Surface files: tetrahedralized (see [`read_surface`]).
pub const SURFACE_EXTENSIONS: &[&str] = &["stl", "obj"];

/// Reads and checks a closed surface (`.stl`, `.obj`).
pub fn read_surface(path: &Path) -> Result<super::surface::Surface, ImportError> {
    let name = path.display().to_string();
    let obj = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    let surface = super::surface::read(&read_bytes(path)?, &name, obj)?;
    super::surface::check(&surface, &name)?;
    Ok(surface)
}

/// Whether `path` names a surface file.
pub fn is_surface(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| SURFACE_EXTENSIONS.iter().any(|s| e.eq_ignore_ascii_case(s)))
}

/// Extensions [`read`] takes.
pub const READ_EXTENSIONS: &[&str] = &["msh", "node", "ele", "vtk", "vtu"];

/// The largest mesh file read (bytes): a 2-million-tetrahedron ASCII mesh is about 200 MB.
pub const MAX_MESH_BYTES: u64 = 512_000_000;

fn read_bytes(path: &Path) -> Result<Vec<u8>, ImportError> {
    crate::files::read_at_most(path, MAX_MESH_BYTES).map_err(|e| {
        ImportError::at(
            &path.display().to_string(),
            None,
            match e {
                crate::files::ReadError::Io(e) => format!("cannot read the file: {e}"),
                e => format!(
                    "{e} (a mesh file is read whole, at most {} MB)",
                    MAX_MESH_BYTES / 1_000_000
                ),
            },
        )
    })
}

/// Reads a tetrahedral mesh file, the format told by its extension.
pub fn read(path: &Path) -> Result<Imported, ImportError> {
    let name = path.display().to_string();
    let Some(format) = Format::of(path) else {
        return Err(ImportError::at(
            &name,
            None,
            format!(
                "unknown mesh format (extension {:?}); softgrip reads .msh (Gmsh 2.2 or 4.1, ASCII or binary), .node/.ele (TetGen), .vtk (VTK legacy) and .vtu (VTK XML)",
                path.extension().and_then(|e| e.to_str()).unwrap_or("")
            ),
        ));
    };
    match format {
        Format::Msh | Format::Msh22 => gmsh::read(&read_bytes(path)?, &name),
        Format::Vtk => vtk::read(&read_bytes(path)?, &name),
        Format::Vtu => vtu::read(&read_bytes(path)?, &name),
        Format::Tetgen => {
            let node = path.with_extension("node");
            let ele = path.with_extension("ele");
            let face = path.with_extension("face");
            let face_bytes = if face.exists() {
                Some(read_bytes(&face)?)
            } else {
                None
            };
            tetgen::read(
                (&read_bytes(&node)?, &node.display().to_string()),
                (&read_bytes(&ele)?, &ele.display().to_string()),
                face_bytes
                    .as_deref()
                    .map(|b| (b, face.display().to_string())),
            )
        }
    }
}

/// Reads mesh text or bytes in a given format (TetGen: the `.node` and
/// `.ele` contents joined by `tetgen::read`; here only single-file
/// formats). For fuzzing and tests.
pub fn read_bytes_as(bytes: &[u8], format: Format, name: &str) -> Result<Imported, ImportError> {
    match format {
        Format::Msh | Format::Msh22 => gmsh::read(bytes, name),
        Format::Vtk => vtk::read(bytes, name),
        Format::Vtu => vtu::read(bytes, name),
        Format::Tetgen => {
            // One buffer holding both files, separated by a line "---ele---".
            let text = String::from_utf8_lossy(bytes);
            let (node, ele) = text.split_once("---ele---").ok_or_else(|| {
                ImportError::at(
                    name,
                    None,
                    "expected .node and .ele text separated by ---ele---",
                )
            })?;
            tetgen::read(
                (node.as_bytes(), &format!("{name}.node")),
                (ele.as_bytes(), &format!("{name}.ele")),
                None,
            )
        }
    }
}

/// The values of the `.vtu` data array named `array` (the first such in
/// its first piece; `"Points"` for the coordinates softgrip writes), as
/// numbers: for checking what `run --out` wrote, field by field.
pub fn read_vtu_array(bytes: &[u8], name: &str, array: &str) -> Result<Vec<f64>, ImportError> {
    vtu::read_array(bytes, name, array)
}

/// Writes `mesh` in `format` (TetGen: `path` with `.node`, `.ele` and
/// `.face`). Returns the files written.
pub fn write(mesh: &TetMesh, path: &Path, format: Format) -> std::io::Result<Vec<PathBuf>> {
    match format {
        Format::Msh => {
            std::fs::write(path, gmsh::write_41(mesh))?;
            Ok(vec![path.to_path_buf()])
        }
        Format::Msh22 => {
            std::fs::write(path, gmsh::write_22(mesh))?;
            Ok(vec![path.to_path_buf()])
        }
        Format::Vtk => {
            std::fs::write(path, vtk::write(mesh))?;
            Ok(vec![path.to_path_buf()])
        }
        Format::Vtu => {
            std::fs::write(path, vtu_text(mesh))?;
            Ok(vec![path.to_path_buf()])
        }
        Format::Tetgen => {
            let (node, ele, face) = tetgen::write(mesh);
            let paths = [
                path.with_extension("node"),
                path.with_extension("ele"),
                path.with_extension("face"),
            ];
            std::fs::write(&paths[0], node)?;
            std::fs::write(&paths[1], ele)?;
            std::fs::write(&paths[2], face)?;
            Ok(paths.to_vec())
        }
    }
}

/// A mesh alone as an ASCII `.vtu`.
fn vtu_text(mesh: &TetMesh) -> String {
    use std::fmt::Write as _;
    let (n, t) = (mesh.nodes.len(), mesh.tets.len());
    let mut s = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{t}\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"
    );
    for p in &mesh.nodes {
        let _ = writeln!(s, "{} {} {}", num(p.x), num(p.y), num(p.z));
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for q in &mesh.tets {
        let _ = writeln!(s, "{} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for k in 1..=t {
        let _ = writeln!(s, "{}", 4 * k);
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..t {
        s.push_str("10\n");
    }
    s.push_str("</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
}
