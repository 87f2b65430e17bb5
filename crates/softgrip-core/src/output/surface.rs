//! The deformed boundary surface of a state as a triangle mesh: binary
//! STL or Wavefront OBJ, for CAD and rendering tools.

use std::fmt::Write as _;

use crate::model::Model;
use crate::state::State;

/// Which surface format `softgrip run --surface` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceFormat {
    /// Binary STL ([`to_stl`]).
    Stl,
    /// Wavefront OBJ ([`to_obj`]).
    Obj,
}

impl SurfaceFormat {
    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            SurfaceFormat::Stl => "stl",
            SurfaceFormat::Obj => "obj",
        }
    }

    /// The deformed boundary surface of `state` in this format.
    pub fn write(self, model: &Model, state: &State) -> Vec<u8> {
        match self {
            SurfaceFormat::Stl => to_stl(model, state),
            SurfaceFormat::Obj => to_obj(model, state).into_bytes(),
        }
    }
}

/// Binary STL: the boundary facets at their current positions, wound
/// outward, with their unit normals (single precision, as STL has it).
pub fn to_stl(model: &Model, state: &State) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * model.facets.len());
    let mut header = [0u8; 80];
    let text = b"softgrip deformed surface (binary STL, metres)";
    header[..text.len()].copy_from_slice(text);
    out.extend_from_slice(&header);
    out.extend_from_slice(&(model.facets.len() as u32).to_le_bytes());
    for tri in &model.facets {
        let p = tri.map(|i| state.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for v in [n, p[0], p[1], p[2]] {
            for c in v.to_array() {
                out.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// OBJ: the boundary particles as vertices (full precision) and the
/// facets as faces; particles inside the object are left out.
pub fn to_obj(model: &Model, state: &State) -> String {
    let mut index = vec![0u32; model.particle_count()];
    let mut s = String::from("# softgrip deformed surface (metres)\n");
    let mut next = 1u32;
    for tri in &model.facets {
        for &i in tri {
            if index[i as usize] == 0 {
                index[i as usize] = next;
                next += 1;
                let p = state.positions[i as usize];
                let _ = writeln!(s, "v {:?} {:?} {:?}", p.x, p.y, p.z);
            }
        }
    }
    for tri in &model.facets {
        let [a, b, c] = tri.map(|i| index[i as usize]);
        let _ = writeln!(s, "f {a} {b} {c}");
    }
    s
}
