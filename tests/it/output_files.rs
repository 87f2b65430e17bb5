//! `run --out`: the ParaView files, fingers.csv and steps.csv are written and
//! consistent; a run that fails keeps what it computed.

use softgrip_core::Simulation;
use softgrip_core::output::TrajectoryWriter;

use crate::support::{arg, scratch_dir, scratch_path, softgrip, stderr, write_file};

#[test]
fn trajectory_files_are_complete() {
    let mut scene = softgrip_core::Scene::thesis();
    scene.object.edge_length = 0.005;
    let mut sim = Simulation::new(&scene).expect("sim");
    let dir = scratch_path("softgrip-out");
    let mut w = TrajectoryWriter::new(&dir).expect("writer");
    w.frame(&sim.model, &sim.state).expect("frame");
    for _ in 0..3 {
        for _ in 0..10 {
            sim.step().expect("step");
            w.step(&sim.state);
        }
        w.frame(&sim.model, &sim.state).expect("frame");
    }
    let pvd = w.finish().expect("finish");
    let text = std::fs::read_to_string(&pvd).expect("pvd");
    assert_eq!(text.matches("<DataSet").count(), 4);
    let vtu = std::fs::read_to_string(dir.join("frame_00003.vtu")).expect("vtu");
    let header = format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        sim.model.particle_count(),
        sim.model.tets.len()
    );
    assert!(vtu.contains(&header));
    for field in [
        "displacement",
        "velocity",
        "fixed",
        "volume_ratio",
        "connectivity",
        "offsets",
        "types",
    ] {
        assert!(
            vtu.contains(&format!("Name=\"{field}\"")),
            "missing {field}"
        );
    }
    let csv = std::fs::read_to_string(dir.join("fingers.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time,finger,x,y,z,fx,fy,fz"));
    let last: Vec<f64> = lines
        .last()
        .expect("rows")
        .split(',')
        .map(|v| v.parse().expect("number"))
        .collect();
    assert_eq!(last.len(), 8);
    assert!((last[4] - sim.state.fingers[0].position.z).abs() < 1e-12);

    // steps.csv: a row per step, the last one the state's own record.
    let steps = std::fs::read_to_string(dir.join("steps.csv")).expect("steps.csv");
    let mut lines = steps.lines();
    assert_eq!(lines.next(), Some(softgrip_core::output::STEPS_HEADER));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 30);
    let last = rows.last().expect("rows");
    assert_eq!(last[1], 30.0);
    assert_eq!(last[2], sim.state.stats.cg_iterations as f64);
    assert_eq!(last[6], sim.state.stats.volume_error);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_failing_run_keeps_its_frames() {
    // The CLI on a scene that fails at its first step: the error is reported,
    // and the files computed so far are written.
    let dir = scratch_dir("softgrip-fail");
    let scene = write_file(
        &dir,
        "stiff.toml",
        "[simulation]\ncg_tolerance = 1e-12\ncg_max_iterations = 2\n[object]\nshape = \"cuboid\"\nsize = [0.05, 0.05, 0.02]\nedge_length = 0.005\nyoung_modulus = 5e9\n[[load]]\nmin = [-1.0, -1.0, 0.019]\nmax = [1.0, 1.0, 1.0]\nforce = [0.0, 0.0, -100.0]\n",
    );
    let out = dir.join("out");
    let status = softgrip(&["run", arg(&scene), "--out", arg(&out)]);
    assert!(!status.status.success());
    let stderr = stderr(&status);
    // A scene's own too-low limit on CG is said as such, not blamed on dt.
    assert!(
        stderr.contains("the linear solver stopped at t ="),
        "{stderr}"
    );
    assert!(stderr.contains("before the failure"), "{stderr}");
    let pvd = std::fs::read_to_string(out.join("trajectory.pvd")).expect("pvd kept");
    assert!(pvd.matches("<DataSet").count() >= 2, "{pvd}");
    assert!(out.join("steps.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// The deformed surface files close the object's deformed volume (the
/// divergence theorem over their triangles equals the tetrahedra's sum),
/// and the `.vtu` carries the contact force, which sums to the contacts'.
#[test]
fn surface_exports_enclose_the_deformed_volume() {
    use softgrip_core::output::surface::{to_obj, to_stl};
    let mut sim = Simulation::new(&softgrip_core::Scene::thesis()).expect("sim");
    sim.run_until(0.2).expect("run");
    let (model, state) = (&sim.model, &sim.state);
    let volume: f64 = model
        .tets
        .iter()
        .map(|t| {
            let p = t.map(|i| state.positions[i as usize]);
            softgrip_core::mesh::signed_volume(p[0], p[1], p[2], p[3])
        })
        .sum();
    let enclosed = |tris: &[[glam::DVec3; 3]]| -> f64 {
        tris.iter().map(|p| p[0].dot(p[1].cross(p[2])) / 6.0).sum()
    };

    let stl = to_stl(model, state);
    let count = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
    assert_eq!(count, model.facets.len());
    assert_eq!(stl.len(), 84 + 50 * count);
    let f = |at: usize| f32::from_le_bytes(stl[at..at + 4].try_into().unwrap()) as f64;
    let tris: Vec<[glam::DVec3; 3]> = (0..count)
        .map(|k| {
            let base = 84 + 50 * k + 12;
            std::array::from_fn(|v| {
                let b = base + 12 * v;
                glam::DVec3::new(f(b), f(b + 4), f(b + 8))
            })
        })
        .collect();
    let v_stl = enclosed(&tris);
    // Single precision: 1e-6 relative.
    assert!(
        (v_stl - volume).abs() < 1e-6 * volume,
        "STL {v_stl:e} vs {volume:e}"
    );

    let obj = to_obj(model, state);
    let vertices: Vec<glam::DVec3> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            glam::DVec3::new(c[0], c[1], c[2])
        })
        .collect();
    let tris: Vec<[glam::DVec3; 3]> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("f "))
        .map(|l| {
            let i: Vec<usize> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [vertices[i[0] - 1], vertices[i[1] - 1], vertices[i[2] - 1]]
        })
        .collect();
    assert_eq!(tris.len(), model.facets.len());
    let v_obj = enclosed(&tris);
    assert!(
        (v_obj - volume).abs() < 1e-12 * volume,
        "OBJ {v_obj:e} vs {volume:e}"
    );

    // The .vtu's contact force sums to what the contacts carry.
    let per_particle = softgrip_core::output::vtu::contact_forces(model, state);
    let total: glam::DVec3 = per_particle.iter().copied().sum();
    let contacts: glam::DVec3 = state
        .contacts
        .iter()
        .map(|c| c.normal * c.normal_force + c.tangential_force)
        .sum();
    assert!(contacts.length() > 1.0);
    assert!((total - contacts).length() < 1e-12 * contacts.length());
    let vtu = softgrip_core::output::vtu::to_vtu(model, state);
    for name in [
        "contact_force",
        "max_spring_strain",
        "displacement",
        "velocity",
        "fixed",
        "volume_ratio",
    ] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "{name}");
    }
}
