//! VTK XML unstructured grid (`.vtu`, ASCII) of one state: the tetrahedra
//! with point data (displacement, velocity, contact force, fixed) and cell
//! data (volume ratio V / V0, max spring strain).

use std::fmt::Write as _;

use crate::mesh::signed_volume;
use crate::model::Model;
use crate::state::State;

/// The contact force on each particle (N): each contact's normal and
/// tangential force shared by its barycentric weights, as the step applied
/// them (thesis eq. 37-39).
pub fn contact_forces(model: &Model, state: &State) -> Vec<glam::DVec3> {
    let mut out = vec![glam::DVec3::ZERO; model.particle_count()];
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

pub fn to_vtu(model: &Model, state: &State) -> String {
    let n = model.particle_count();
    let t = model.tets.len();
    let mut s = String::with_capacity(64 * (n + t));
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(s, "  <UnstructuredGrid>");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{t}\">"
    );
    s.push_str("      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in &state.positions {
        let _ = writeln!(s, "          {:e} {:e} {:e}", p.x, p.y, p.z);
    }
    s.push_str("        </DataArray>\n      </Points>\n");
    s.push_str("      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for tet in &model.tets {
        let _ = writeln!(s, "          {} {} {} {}", tet[0], tet[1], tet[2], tet[3]);
    }
    s.push_str("        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 0..t {
        let _ = writeln!(s, "          {}", 4 * (i + 1));
    }
    s.push_str("        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..t {
        s.push_str("          10\n");
    }
    s.push_str("        </DataArray>\n      </Cells>\n");
    s.push_str("      <PointData Vectors=\"displacement\">\n");
    s.push_str("        <DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (p, r) in state.positions.iter().zip(&model.rest_positions) {
        let d = *p - *r;
        let _ = writeln!(s, "          {:e} {:e} {:e}", d.x, d.y, d.z);
    }
    s.push_str("        </DataArray>\n");
    s.push_str("        <DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for v in &state.velocities {
        let _ = writeln!(s, "          {:e} {:e} {:e}", v.x, v.y, v.z);
    }
    s.push_str("        </DataArray>\n");
    s.push_str("        <DataArray type=\"Float64\" Name=\"contact_force\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for f in contact_forces(model, state) {
        let _ = writeln!(s, "          {:e} {:e} {:e}", f.x, f.y, f.z);
    }
    s.push_str("        </DataArray>\n");
    s.push_str("        <DataArray type=\"UInt8\" Name=\"fixed\" format=\"ascii\">\n");
    for f in &model.fixed {
        let _ = writeln!(s, "          {}", *f as u8);
    }
    s.push_str("        </DataArray>\n      </PointData>\n");
    s.push_str("      <CellData>\n        <DataArray type=\"Float64\" Name=\"volume_ratio\" format=\"ascii\">\n");
    for (tet, v0) in model.tets.iter().zip(&model.rest_volume) {
        let p = tet.map(|i| state.positions[i as usize]);
        let _ = writeln!(
            s,
            "          {:e}",
            signed_volume(p[0], p[1], p[2], p[3]) / v0
        );
    }
    s.push_str("        </DataArray>\n        <DataArray type=\"Float64\" Name=\"max_spring_strain\" format=\"ascii\">\n");
    for e in crate::fields::element_max_spring_strain(model, state) {
        let _ = writeln!(s, "          {e:e}");
    }
    s.push_str("        </DataArray>\n      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    s
}
