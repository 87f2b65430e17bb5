//! `run --out`: the ParaView files, fingers.csv and steps.csv are written and
//! consistent; the compressed `.vtu` files read back as written; a run that
//! fails keeps what it computed.

use std::path::Path;

use softgrip_core::Simulation;
use softgrip_core::mesh::io::{Format, read_bytes_as, read_vtu_array};
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
    // Each frame: the object as part 0, the finger as part 1, at one time.
    assert_eq!(sim.state.fingers.len(), 1);
    assert_eq!(text.matches("<DataSet").count(), 8);
    assert_eq!(text.matches("part=\"0\" file=\"frame_").count(), 4);
    assert_eq!(text.matches("part=\"1\" file=\"finger1_").count(), 4);
    // 30 steps of 1 ms: written 0.03, not the sum's 0.030000000000000013.
    let last_time = "timestep=\"0.03\"";
    assert!((sim.state.time - 0.03).abs() < 1e-12);
    assert_eq!(text.matches(last_time).count(), 2, "{text}");
    let vtu = std::fs::read_to_string(dir.join("frame_00003.vtu")).expect("vtu");
    assert!(vtu.contains("compressor=\"vtkZLibDataCompressor\""));
    assert!(!vtu.contains("format=\"ascii\""));
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
    // The last frame reads back as the state, bit for bit.
    let bytes = vtu.as_bytes();
    let mesh = read_bytes_as(bytes, Format::Vtu, "frame_00003.vtu")
        .expect("the mesh reader reads it")
        .mesh;
    assert_eq!(mesh.tets, sim.model.tets);
    assert_eq!(bits(&mesh.nodes), bits(&sim.state.positions));
    let field = |name: &str| -> Vec<u64> {
        read_vtu_array(bytes, "frame_00003.vtu", name)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    // Velocity and the cell diagnostics are Float32 in binary: rounded once.
    let single =
        |v: &[f64]| -> Vec<u64> { v.iter().map(|&x| f64::from(x as f32).to_bits()).collect() };
    let velocity: Vec<f64> = sim
        .state
        .velocities
        .iter()
        .flat_map(|v| v.to_array())
        .collect();
    assert_eq!(field("velocity"), single(&velocity));
    let contact = softgrip_core::output::vtu::contact_forces(&sim.model, &sim.state);
    assert_eq!(field("contact_force"), bits(&contact));
    let displacement: Vec<glam::DVec3> = sim
        .state
        .positions
        .iter()
        .zip(&sim.model.rest_positions)
        .map(|(p, r)| *p - *r)
        .collect();
    assert_eq!(field("displacement"), bits(&displacement));
    let strain = softgrip_core::fields::element_max_spring_strain(&sim.model, &sim.state);
    assert_eq!(field("max_spring_strain"), single(&strain));
    assert_eq!(field("volume_ratio").len(), sim.model.tets.len());
    let fixed = read_vtu_array(bytes, "frame_00003.vtu", "fixed").expect("fixed");
    let expected: Vec<f64> = sim
        .model
        .fixed
        .iter()
        .map(|&f| f64::from(u8::from(f)))
        .collect();
    assert_eq!(fixed, expected);

    // The finger: its shape around its centre, its contact force at every point.
    let finger = std::fs::read(dir.join("finger1_00003.vtu")).expect("finger vtu");
    let f = &sim.state.fingers[0];
    let points = read_vtu_array(&finger, "finger1", "Points").expect("points");
    let softgrip_core::scene::FingerShape::Sphere { radius } = sim.model.fingers[0].shape else {
        panic!("the thesis finger is a sphere");
    };
    assert!(points.len() > 3 * 100);
    // Float32 points: on the sphere to single precision.
    for p in points.chunks(3) {
        let r = (glam::DVec3::from_slice(p) - f.position).length();
        assert!((r - radius).abs() < 1e-7, "{r} vs {radius}");
    }
    let force = read_vtu_array(&finger, "finger1", "contact_force").expect("force");
    assert_eq!(force.len(), points.len());
    for c in force.chunks(3) {
        assert_eq!(c, f.contact_force.to_array());
    }
    assert!(f.contact_force.length() > 0.0);

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
    // Fingers are numbered from 1, as on screen and in the fingerK files.
    assert_eq!(last[1], 1.0);
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
    let vtu = softgrip_core::output::vtu::to_vtu(
        model,
        state,
        softgrip_core::output::vtu::Encoding::Binary,
    );
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

fn bits(v: &[glam::DVec3]) -> Vec<u64> {
    v.iter()
        .flat_map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// Bytes of the files in `dir` whose names start with `prefix`.
fn bytes_of(dir: &Path, prefix: &str) -> u64 {
    std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry"))
        .filter(|e| e.file_name().to_string_lossy().starts_with(prefix))
        .map(|e| e.metadata().expect("metadata").len())
        .sum()
}

/// `run --out` writes compressed binary; `--ascii` the same arrays as
/// text, the object's all Float64, several times larger.
#[test]
fn run_writes_compressed_binary_and_ascii_on_request() {
    let dir = scratch_dir("softgrip-out-ascii");
    let (binary, ascii) = (dir.join("binary"), dir.join("ascii"));
    for (out, extra) in [(&binary, None), (&ascii, Some("--ascii"))] {
        let mut args = vec!["run", "--duration", "0.04", "--out", arg(out)];
        args.extend(extra);
        let o = softgrip(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let frames = |out: &Path| std::fs::read_dir(out).expect("dir").count();
    assert_eq!(frames(&binary), frames(&ascii));
    for name in ["frame_00002.vtu", "finger1_00002.vtu"] {
        let b = std::fs::read(binary.join(name)).expect("binary");
        let a = std::fs::read(ascii.join(name)).expect("ascii");
        assert!(String::from_utf8_lossy(&a).contains("format=\"ascii\""));
        assert!(String::from_utf8_lossy(&b).contains("format=\"binary\""));
        // Exact in both; velocity is Float32 in binary. A finger's points
        // are Float32 in both, read back as the decimal of a Float32 from ASCII.
        let finger = name.starts_with("finger");
        for field in ["Points", "displacement", "contact_force"] {
            let single = finger && field == "Points";
            let read = |bytes: &[u8]| -> Vec<u64> {
                read_vtu_array(bytes, name, field)
                    .unwrap_or_else(|e| panic!("{name} {field}: {e}"))
                    .iter()
                    .map(|&v| if single { f64::from(v as f32) } else { v }.to_bits())
                    .collect()
            };
            assert_eq!(read(&b), read(&a), "{name} {field}");
        }
    }
    let (b, a) = (bytes_of(&binary, "frame_"), bytes_of(&ascii, "frame_"));
    assert!(5 * b < a, "binary {b} bytes, ASCII {a}");
    std::fs::remove_dir_all(&dir).ok();
}
