//! VTK XML unstructured grids (`.vtu`) of one state: the object's tetrahedra
//! with point data (displacement, velocity, contact force, fixed) and cell
//! data (volume ratio V / V0, max spring strain), and each finger's surface.
//! Data arrays are inline binary, zlib-compressed in VTK's blocks, unless
//! ASCII is asked for (see [`Encoding`] for which arrays are Float32).

use std::fmt::Write as _;

use glam::DVec3;

use super::finger::finger_surface;
use crate::mesh::io::base64;
use crate::mesh::signed_volume;
use crate::model::Model;
use crate::state::State;

/// How a `.vtu`'s data arrays are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// Base64 of zlib-compressed blocks (VTK's `vtkZLibDataCompressor`,
    /// UInt64 headers). Positions, displacement and contact forces are
    /// Float64, exact; velocity and the cell data are Float32 (7 digits):
    /// Float64's noisy low bits barely compress, and these three arrays in
    /// full made a compressed frame two thirds larger.
    #[default]
    Binary,
    /// Numbers as text, every array in full (Float64, shortest exact
    /// decimal): the format before binary, for tools that read lines.
    Ascii,
}

impl Encoding {
    /// Whether the arrays [`Encoding::Binary`] shortens are written in Float32.
    fn single(self) -> bool {
        self == Encoding::Binary
    }
}

/// VTK's default block (vtkXMLWriter): 32 KiB of data per zlib stream, so
/// a reader can inflate an array block by block.
const BLOCK_SIZE: usize = 1 << 15;
/// zlib's default level: 9 saved under 1 % on a frame, at several times the time.
const ZLIB_LEVEL: u8 = 6;

/// The contact force on each particle (N): each contact's normal and
/// tangential force shared by its barycentric weights, as the step applied
/// them (thesis eq. 37-39).
pub fn contact_forces(model: &Model, state: &State) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; model.particle_count()];
    for c in &state.contacts {
        let Some(tri) = model.facets.get(c.facet as usize) else {
            continue;
        };
        let total = c.normal * c.normal_force + c.tangential_force;
        for a in 0..3 {
            out[tri[a] as usize] += c.weights[a] * total;
        }
    }
    out
}

/// The object in `state` as a `.vtu`.
pub fn to_vtu(model: &Model, state: &State, encoding: Encoding) -> String {
    to_vtu_with(model, state, encoding, &[])
}

/// [`to_vtu`], with more per-element arrays `(name, values)` (the grasp window's marked peak).
pub fn to_vtu_with(
    model: &Model,
    state: &State,
    encoding: Encoding,
    more_cells: &[(&str, &[f64])],
) -> String {
    let (n, t) = (model.particle_count(), model.tets.len());
    let single = encoding.single();
    let mut doc = Document::new(encoding, n, t);
    doc.points(&state.positions, false);
    doc.cells(&model.tets, 10);
    doc.open("PointData Vectors=\"displacement\"");
    let displacement: Vec<DVec3> = state
        .positions
        .iter()
        .zip(&model.rest_positions)
        .map(|(p, r)| *p - *r)
        .collect();
    doc.vectors("displacement", &displacement, false);
    doc.vectors("velocity", &state.velocities, single);
    doc.vectors("contact_force", &contact_forces(model, state), false);
    let fixed: Vec<u8> = model.fixed.iter().map(|f| u8::from(*f)).collect();
    doc.array("fixed", 1, 1, &fixed);
    doc.reals(
        "contact_pressure",
        1,
        &crate::fields::contact_pressure(model, state),
        single,
    );
    doc.close("PointData");
    doc.open("CellData");
    let ratio: Vec<f64> = model
        .tets
        .iter()
        .zip(&model.rest_volume)
        .map(|(tet, v0)| {
            let p = tet.map(|i| state.positions[i as usize]);
            signed_volume(p[0], p[1], p[2], p[3]) / v0
        })
        .collect();
    doc.reals("volume_ratio", 1, &ratio, single);
    let strain = crate::fields::element_max_spring_strain(model, state);
    doc.reals("max_spring_strain", 1, &strain, single);
    let green = crate::fields::element_green_strain(model, state);
    doc.reals("green_strain", 1, &green, single);
    let von_mises = crate::fields::element_von_mises(model, state);
    doc.reals("von_mises", 1, &von_mises, single);
    for (name, values) in more_cells {
        doc.reals(name, 1, values, single);
    }
    doc.close("CellData");
    doc.finish()
}

/// Finger `k` in `state` as a `.vtu` of triangles (its shape at its
/// position), each point carrying the finger's displacement from its start,
/// velocity and the contact force the object exerts on it (N), in Float64.
/// The points are Float32: the triangles only draw the shape (a sphere's
/// are ~1 % of its radius inside it), and its exact centre is in `fingers.csv`.
pub fn finger_to_vtu(model: &Model, state: &State, k: usize, encoding: Encoding) -> String {
    let (position, velocity, force) = state
        .fingers
        .get(k)
        .map_or((DVec3::ZERO, DVec3::ZERO, DVec3::ZERO), |f| {
            (f.position, f.velocity, f.contact_force)
        });
    let start = model
        .fingers
        .get(k)
        .map_or(position, |f| f.initial_position);
    let surface = finger_surface(model, k, position);
    let n = surface.vertices.len();
    let mut doc = Document::new(encoding, n, surface.triangles.len());
    doc.points(&surface.vertices, true);
    doc.cells(&surface.triangles, 5);
    doc.open("PointData Vectors=\"contact_force\"");
    doc.vectors("displacement", &vec![position - start; n], false);
    doc.vectors("velocity", &vec![velocity; n], false);
    doc.vectors("contact_force", &vec![force; n], false);
    doc.close("PointData");
    doc.finish()
}

/// A value type both encodings write.
trait Scalar: Copy {
    /// VTK's name for it.
    const VTK: &'static str;
    fn push_le(self, out: &mut Vec<u8>);
    fn push_text(self, out: &mut String);
}

/// The little-endian bytes and the text of each value type.
macro_rules! scalar {
    ($t:ty, $vtk:literal, $text:literal) => {
        impl Scalar for $t {
            const VTK: &'static str = $vtk;
            fn push_le(self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
            fn push_text(self, out: &mut String) {
                let _ = write!(out, $text, self);
            }
        }
    };
}

scalar!(f64, "Float64", "{:e}");
scalar!(f32, "Float32", "{:e}");
scalar!(i64, "Int64", "{}");
scalar!(u8, "UInt8", "{}");

/// One `.vtu` being written: the XML up to the open `<Piece>` and the
/// arrays added since.
struct Document {
    s: String,
    encoding: Encoding,
    /// The array being encoded, reused.
    bytes: Vec<u8>,
}

impl Document {
    fn new(encoding: Encoding, points: usize, cells: usize) -> Document {
        // About what each point and cell takes: text runs to ~5 times binary.
        let per_item = match encoding {
            Encoding::Ascii => 64,
            Encoding::Binary => 16,
        };
        let mut s = String::with_capacity(per_item * (points + cells));
        s.push_str("<?xml version=\"1.0\"?>\n");
        s.push_str(match encoding {
            Encoding::Ascii => {
                "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
            }
            Encoding::Binary => {
                "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
            }
        });
        let _ = write!(
            s,
            "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">\n"
        );
        Document {
            s,
            encoding,
            bytes: Vec::new(),
        }
    }

    fn open(&mut self, tag: &str) {
        let _ = writeln!(self.s, "      <{tag}>");
    }

    fn close(&mut self, name: &str) {
        let _ = writeln!(self.s, "      </{name}>");
    }

    /// The `<Points>` (Float32 if `single`).
    fn points(&mut self, points: &[DVec3], single: bool) {
        self.open("Points");
        self.vectors("Points", points, single);
        self.close("Points");
    }

    /// Cells of one VTK type, each `N` points.
    fn cells<const N: usize>(&mut self, cells: &[[u32; N]], vtk_type: u8) {
        self.open("Cells");
        let connectivity: Vec<i64> = cells.iter().flatten().map(|&i| i64::from(i)).collect();
        self.array("connectivity", 1, N, &connectivity);
        let offsets: Vec<i64> = (1..=cells.len()).map(|k| (N * k) as i64).collect();
        self.array("offsets", 1, 1, &offsets);
        self.array("types", 1, 1, &vec![vtk_type; cells.len()]);
        self.close("Cells");
    }

    fn vectors(&mut self, name: &str, values: &[DVec3], single: bool) {
        let flat: Vec<f64> = values.iter().flat_map(|v| v.to_array()).collect();
        self.reals(name, 3, &flat, single);
    }

    /// Float64 values, or Float32 if `single`.
    fn reals(&mut self, name: &str, components: usize, values: &[f64], single: bool) {
        if single {
            let values: Vec<f32> = values.iter().map(|&v| v as f32).collect();
            self.array(name, components, components, &values);
        } else {
            self.array(name, components, components, values);
        }
    }

    /// A `<DataArray>`; ASCII puts `per_line` values on a line.
    fn array<T: Scalar>(&mut self, name: &str, components: usize, per_line: usize, values: &[T]) {
        let _ = write!(
            self.s,
            "        <DataArray type=\"{}\" Name=\"{name}\"",
            T::VTK
        );
        if components > 1 {
            let _ = write!(self.s, " NumberOfComponents=\"{components}\"");
        }
        match self.encoding {
            Encoding::Ascii => {
                self.s.push_str(" format=\"ascii\">\n");
                for line in values.chunks(per_line.max(1)) {
                    self.s.push_str("         ");
                    for v in line {
                        self.s.push(' ');
                        v.push_text(&mut self.s);
                    }
                    self.s.push('\n');
                }
            }
            Encoding::Binary => {
                self.s.push_str(" format=\"binary\">\n          ");
                self.bytes.clear();
                for v in values {
                    v.push_le(&mut self.bytes);
                }
                compressed_base64(&self.bytes, &mut self.s);
                self.s.push('\n');
            }
        }
        self.s.push_str("        </DataArray>\n");
    }

    fn finish(mut self) -> String {
        self.s
            .push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
        self.s
    }
}

/// `raw` as VTK's inline compressed binary: the UInt64 header
/// `[blocks, block size, last block's size (0: full), compressed sizes...]`
/// in base64, then the zlib blocks joined, in base64 of their own.
fn compressed_base64(raw: &[u8], out: &mut String) {
    let blocks: Vec<Vec<u8>> = raw
        .chunks(BLOCK_SIZE)
        .map(|block| miniz_oxide::deflate::compress_to_vec_zlib(block, ZLIB_LEVEL))
        .collect();
    let mut header = Vec::with_capacity(8 * (3 + blocks.len()));
    let sizes = [blocks.len(), BLOCK_SIZE, raw.len() % BLOCK_SIZE]
        .into_iter()
        .chain(blocks.iter().map(Vec::len));
    for v in sizes {
        header.extend_from_slice(&(v as u64).to_le_bytes());
    }
    base64::encode(&header, out);
    base64::encode(&blocks.concat(), out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::io::{Format, read_bytes_as, read_vtu_array};

    /// Arrays of several blocks, of a whole number of blocks and empty ones
    /// read back through the mesh reader's decoder, bit for bit.
    #[test]
    fn compressed_arrays_read_back_exactly() {
        for count in [0usize, 1, 4096, 2 * 4096, 10_000] {
            let values: Vec<f64> = (0..count)
                .map(|i| (i as f64 * 0.7).sin() * 1e-3 + f64::EPSILON * i as f64)
                .collect();
            let mut doc = Document::new(Encoding::Binary, 1, 1);
            doc.points(&[DVec3::new(0.1, -0.2, 1.0 / 3.0)], false);
            doc.cells(&[[0u32]], 1);
            doc.open("PointData");
            doc.array("data", 1, 1, &values);
            doc.close("PointData");
            let text = doc.finish();
            let back = read_vtu_array(text.as_bytes(), "t.vtu", "data").expect("reads");
            assert_eq!(back.len(), count);
            for (a, b) in values.iter().zip(&back) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
            let p = read_vtu_array(text.as_bytes(), "t.vtu", "Points").expect("points");
            assert_eq!(p, vec![0.1, -0.2, 1.0 / 3.0]);
        }
    }

    #[test]
    fn both_encodings_read_back_as_the_state() {
        let mut scene = crate::Scene::thesis();
        scene.object.edge_length = 0.008;
        let mut sim = crate::Simulation::new(&scene).expect("sim");
        sim.run_until(0.05).expect("run");
        let (model, state) = (&sim.model, &sim.state);
        for encoding in [Encoding::Binary, Encoding::Ascii] {
            let text = to_vtu(model, state, encoding);
            let mesh = read_bytes_as(text.as_bytes(), Format::Vtu, "f.vtu")
                .expect("reads")
                .mesh;
            assert_eq!(mesh.tets, model.tets);
            assert_eq!(mesh.nodes.len(), state.positions.len());
            for (a, b) in mesh.nodes.iter().zip(&state.positions) {
                assert_eq!(
                    a.to_array().map(f64::to_bits),
                    b.to_array().map(f64::to_bits)
                );
            }
            // Velocity: exact in ASCII, rounded once to Float32 in binary.
            let v = read_vtu_array(text.as_bytes(), "f.vtu", "velocity").expect("velocity");
            let round = |x: f64| {
                if encoding.single() {
                    f64::from(x as f32)
                } else {
                    x
                }
            };
            let flat: Vec<u64> = state
                .velocities
                .iter()
                .flat_map(|v| v.to_array().map(|x| round(x).to_bits()))
                .collect();
            assert_eq!(v.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), flat);
            let c = read_vtu_array(text.as_bytes(), "f.vtu", "contact_force").expect("force");
            let exact: Vec<f64> = contact_forces(model, state)
                .iter()
                .flat_map(|v| v.to_array())
                .collect();
            assert_eq!(c, exact);
            let finger = finger_to_vtu(model, state, 0, encoding);
            let force = read_vtu_array(finger.as_bytes(), "g.vtu", "contact_force").expect("f");
            assert_eq!(&force[..3], &state.fingers[0].contact_force.to_array());
        }
    }
}
