//! The `softgrip` command as a user runs it: each subcommand on a short
//! scene, its output and exit status.

use std::path::Path;
use std::process::Output;

use crate::support::{
    arg, mesh_fixture, read_json, recording, scene, scratch_dir, scratch_path, softgrip, stderr,
    stdout, write_file,
};

#[test]
fn run_prints_the_results_a_user_needs() {
    let o = softgrip(&["run", "--duration", "0.05"]);
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    for needle in [
        "built-in thesis scene",
        "indentation depth",
        "contact force",
        "volume error",
        "CG iterations per step",
    ] {
        assert!(out.contains(needle), "missing {needle:?} in\n{out}");
    }
}

#[test]
fn scene_prints_a_file_that_check_accepts() {
    let o = softgrip(&["scene"]);
    assert!(o.status.success());
    let dir = scratch_dir("softgrip-cli");
    let path = write_file(&dir, "thesis.toml", &stdout(&o));
    let o = softgrip(&["check", arg(&path)]);
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    assert!(out.contains("mesh: 1014 nodes, 4320 tetrahedra"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn ramp_reaches_each_load() {
    let o = softgrip(&[
        "ramp",
        &scene("thesis_cuboid_light_guide.toml"),
        "--loads",
        "0.5,1",
        "--max-seconds",
        "2",
    ]);
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    // One table row per load, each with its contact force.
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("| 0.5 ") || l.starts_with("| 1 "))
        .collect();
    assert_eq!(rows.len(), 2, "{out}");
    let force = |row: &str| -> f64 {
        row.split('|')
            .nth(3)
            .and_then(|c| c.trim().parse().ok())
            .expect("contact force column")
    };
    assert!((force(rows[0]) - 0.5).abs() < 0.005, "{out}");
    assert!((force(rows[1]) - 1.0).abs() < 0.01, "{out}");
}

#[test]
fn bench_prints_a_row_per_size() {
    let o = softgrip(&["bench", "--edges", "8,6", "--seconds", "0.01"]);
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    assert!(out.contains("machine:"), "{out}");
    assert!(out.lines().any(|l| l.starts_with("| 8.0 |")), "{out}");
    assert!(out.lines().any(|l| l.starts_with("| 6.0 |")), "{out}");
}

#[test]
fn a_bad_scene_is_a_clear_error_and_a_failing_exit() {
    let dir = scratch_dir("softgrip-cli-bad");
    let path = write_file(
        &dir,
        "bad.toml",
        "[object]\nshape = \"cuboid\"\nsize = [0.05, 0.05, 0.02]\nyoung_modulus = -1.0\n",
    );
    let o = softgrip(&["run", arg(&path)]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("young_modulus") && err.contains("bad.toml"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mesh_info_convert_and_make() {
    let o = softgrip(&["mesh", "info", &mesh_fixture("cube_binary.msh")]);
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    for needle in [
        "tetrahedra: 384",
        "nodes: 143",
        "boundary facets: 264",
        "volume: 8.000000e-6 m^3",
        "skipped cells that are not tetrahedra: 48 lines, 8 points, 264 triangles",
        "smallest dihedral angle",
        "worst aspect ratio",
        "connected parts: 1",
    ] {
        assert!(out.contains(needle), "missing {needle:?} in\n{out}");
    }

    let dir = scratch_dir("softgrip-cli-mesh");
    let vtk = dir.join("cube.vtk");
    let o = softgrip(&["mesh", "convert", &mesh_fixture("cube.msh"), arg(&vtk)]);
    assert!(o.status.success(), "{o:?}");
    let back = softgrip_core::mesh::io::read(&vtk).expect("converted file reads");
    assert_eq!(back.mesh.tets.len(), 384);

    let msh22 = dir.join("pinch.msh");
    let pinch = scene("pinch.toml");
    let o = softgrip(&["mesh", "make", &pinch, arg(&msh22), "--format", "msh22"]);
    assert!(o.status.success(), "{o:?}");
    let made = softgrip_core::mesh::io::read(&msh22).expect("made file reads");
    assert_eq!(made.mesh.tets.len(), 4320);
    assert!((made.mesh.volume() - 0.05 * 0.05 * 0.02).abs() < 1e-15);

    // A bad file: an error naming it, no panic.
    let bad = write_file(&dir, "bad.msh", "$MeshFormat\n9.9 0 8\n");
    let o = softgrip(&["mesh", "info", arg(&bad)]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("bad.msh:2") && err.contains("9.9"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

/// A recording whose scene is bad, or missing: the error names the file,
/// the line and what to do, once (the recording's error quotes the
/// scene's, and printing the chain as well said everything twice).
#[test]
fn a_recordings_bad_scene_is_said_once() {
    let dir = scratch_dir("softgrip-cli-badrec");
    let shipped = recording("synthetic/thesis_7_loads");
    for f in ["recording.toml", "samples.csv"] {
        std::fs::copy(format!("{shipped}/{f}"), dir.join(f)).expect("copy");
    }
    let scene = std::fs::read_to_string(format!("{shipped}/scene.toml")).expect("scene");
    let bad: String = scene
        .lines()
        .map(|l| {
            if l.starts_with("tau_c") {
                "tau_c = 5"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(bad.contains("tau_c = 5"), "the shipped scene sets tau_c");
    std::fs::write(dir.join("scene.toml"), bad).expect("write");
    let header = dir.join("recording.toml");
    let o = softgrip(&["compare", arg(&header), "--no-report"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("scene.toml:") && err.contains("tau_c = 5"),
        "{err}"
    );
    assert_eq!(err.matches("tau_c = 5").count(), 1, "{err}");
    // A missing file: the system's reason once.
    let missing = dir.join("missing.toml");
    let o = softgrip(&["compare", arg(&missing), "--no-report"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("missing.toml"), "{err}");
    assert_eq!(err.matches("No such file").count(), 1, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `softgrip COMMAND RECORDING OPTIONS... --json JSON --report REPORT`.
fn lab_command(command: &str, rec: &str, options: &[&str], json: &Path, report: &Path) -> Output {
    let outputs = ["--json", arg(json), "--report", arg(report)];
    softgrip(&[&[command, rec], options, &outputs].concat())
}

#[test]
fn modulus_is_the_datasets_small_strain_modulus_and_compare_writes_its_figures() {
    let dir = scratch_dir("softgrip-cli-rec");
    let (json, report) = (dir.join("e.json"), dir.join("modulus"));
    let rec = recording("ecoflex_compression/EF30_0T_A1/recording.toml");
    let o = lab_command("modulus", &rec, &[], &json, &report);
    assert!(o.status.success(), "{o:?}");
    let md = std::fs::read_to_string(dir.join("modulus/modulus.md")).unwrap();
    assert!(md.contains("| Young's modulus E (slope) | "), "{md}");
    assert!(
        std::fs::read(dir.join("modulus/stress_strain.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
    assert!(
        stdout(&o).contains("Young's modulus E = "),
        "{}",
        stdout(&o)
    );
    let v = read_json(&json);
    let e = v["young_modulus"].as_f64().expect("young_modulus in Pa");
    // The independent value: the dataset's own small-strain modulus of Ecoflex 00-30, 103.46 +/-
    // 2.32 kPa over its samples (assets/recordings/README.md); within two of its spreads.
    assert!((e - 103.46e3).abs() < 2.0 * 2.32e3, "{e}");
    // The report prints the same figure, to 0.1 kPa.
    let row = format!("| Young's modulus E (slope) | {:.1} kPa |", e / 1e3);
    assert!(md.contains(&row), "{row} in {md}");

    let (json, report) = (dir.join("c.json"), dir.join("report"));
    let rec = recording("beam_ds10/gravity_a/recording.toml");
    let o = lab_command("compare", &rec, &[], &json, &report);
    assert!(o.status.success(), "{o:?}");
    // The full residual table: a row per marker per sample (3 x 159).
    let table = std::fs::read_to_string(report.join("residuals.csv")).unwrap();
    assert_eq!(table.lines().count(), 1 + 477);
    assert!(table.starts_with("sample,time,load,marker,recorded_x"));
    // The report: Markdown with the figures and its plots beside it.
    let md = std::fs::read_to_string(report.join("compare.md")).unwrap();
    assert!(md.contains("| scene as given | 0.0"), "{md}");
    assert!(md.contains("| tip1 |"), "{md}");
    for png in ["paths.png", "motion.png", "residuals.png"] {
        assert!(md.contains(&format!("]({png})")), "{md}");
        let bytes = std::fs::read(report.join(png)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{png}");
    }
    let out = stdout(&o);
    assert!(out.contains("NRMSE") && out.contains("tip1"), "{out}");
    let v = read_json(&json);
    let nrmse = v["nrmse"].as_f64().expect("nrmse");
    let rmse = v["rmse_m"].as_f64().expect("rmse_m");
    // NRMSE is RMSE over the beam's 100 mm extent.
    assert!((nrmse - rmse / 0.1).abs() < 1e-12);
    assert_eq!(v["params"]["young_modulus"].as_f64(), Some(215856.0));
    // The beam's ringing, recorded and simulated, on its most-moving marker axis (a tip's z).
    assert!(out.contains("ringing of tip"), "{out}");
    assert_eq!(v["ringing"]["axis"].as_str(), Some("z"), "{v}");
    let f = v["ringing"]["recorded"]["frequency_hz"]
        .as_f64()
        .expect("f");
    assert!((7.6..7.9).contains(&f), "{f}");
    let zeta = v["ringing"]["recorded"]["damping_ratio"]
        .as_f64()
        .expect("zeta");
    assert!((0.03..0.1).contains(&zeta), "{zeta}");
    assert!(
        v["ringing"]["simulated"]["frequency_hz"].as_f64().is_some(),
        "{v}"
    );

    let _ = std::fs::remove_dir_all(dir);
}

/// `fit` on a small recording softgrip made itself: the JSON carries the
/// fitted parameters with their standard errors, the report its tables
/// and plots; `sweep` writes its curve and CSV.
#[test]
#[ignore = "slow: the command run end to end"]
fn fit_and_sweep_write_their_figures_and_reports() {
    use softgrip_lab::recording::{Mode, Start};
    use softgrip_lab::synth::{Synthesis, synthesize};
    let dir = scratch_path("softgrip-cli-fit");
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/thesis_cuboid_light_guide.toml"
    ))
    .unwrap()
    .replace("edge_length = 0.004", "edge_length = 0.008");
    let scene = softgrip_core::Scene::from_toml_str(&text, "s").unwrap();
    let spec = Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: vec![(None, 2.0), (None, 5.0)],
        markers: vec![
            ("top".into(), glam::DVec3::new(0.01, 0.0, 0.02)),
            ("side".into(), glam::DVec3::new(0.025, 0.0, 0.01)),
        ],
        finger: true,
        axes: [true, false, true],
        noise: 5e-5,
        seed: 1,
        description: "cli fit".into(),
        distortion: None,
    };
    synthesize(&scene, &spec, &dir.join("rec")).unwrap();
    let rec = dir.join("rec/recording.toml");
    let (json, report) = (dir.join("fit.json"), dir.join("fit"));
    let search = [
        "--params",
        "young_modulus=2e4:2e5",
        "--max-evaluations",
        "40",
    ];
    let o = lab_command("fit", arg(&rec), &search, &json, &report);
    assert!(o.status.success(), "{o:?}");
    let v = read_json(&json);
    let e = v["params"]["young_modulus"].as_f64().expect("fitted E");
    let se = v["standard_errors"]["young_modulus"]
        .as_f64()
        .expect("its error");
    assert!((e - 57.6e3).abs() < 3.0 * se + 1e3, "{e} +/- {se}");
    assert!(v["nrmse"].as_f64().unwrap() <= v["before"]["nrmse"].as_f64().unwrap());
    let md = std::fs::read_to_string(dir.join("fit/fit.md")).unwrap();
    assert!(md.contains("| young_modulus (Pa) |"), "{md}");
    assert!(dir.join("fit/convergence.png").exists());
    let (grid, report) = ("young_modulus=4e4:8e4:3", dir.join("sweep"));
    let o = softgrip(&[
        "sweep",
        arg(&rec),
        "--param",
        grid,
        "--report",
        arg(&report),
    ]);
    assert!(o.status.success(), "{o:?}");
    assert!(
        stdout(&o).contains("best: young_modulus = 60000"),
        "{}",
        stdout(&o)
    );
    let csv = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(dir.join("sweep/sweep.png").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// `fit A B`: two small cantilevers softgrip made itself, the same material with and without a
/// tip mass, fitted together: the JSON lists each recording's NRMSE before and after and the
/// shared E; the report links each recording's figures; `--scene-out` is a directory with one
/// fitted scene per recording, and a file there is refused before the fit.
#[test]
fn fit_of_several_recordings_shares_the_parameters() {
    use softgrip_lab::recording::{Mode, Start};
    use softgrip_lab::synth::{Synthesis, synthesize};
    let dir = scratch_path("softgrip-cli-fit-many");
    let beam = |tip_mass: f64| {
        let mut text = "[simulation]\ndt = 1e-3\nduration = 0.1\ngravity = [0.0, 0.0, -9.81]\n\n[object]\nshape = \"cuboid\"\nsize = [0.1, 0.03, 0.03]\nedge_length = 0.01\ndensity = 1070.0\nyoung_modulus = 200000.0\npoisson_ratio = 0.45\n\n[support]\nkind = \"none\"\n\n[[fixed]]\nmin = [-0.0505, -0.016, -0.001]\nmax = [-0.0495, 0.016, 0.031]\n".to_string();
        if tip_mass > 0.0 {
            text += &format!(
                "\n[[load]]\nmin = [0.0495, -0.016, 0.0295]\nmax = [0.0505, 0.016, 0.0305]\nmass = {tip_mass:?}\n"
            );
        }
        softgrip_core::Scene::from_toml_str(&text, "beam").unwrap()
    };
    let spec = |seed: u64| Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: vec![(None, 0.0)],
        markers: vec![
            ("tip1".into(), glam::DVec3::new(0.05, 0.0, 0.03)),
            ("tip2".into(), glam::DVec3::new(0.05, -0.015, 0.015)),
            ("mid".into(), glam::DVec3::new(0.0, 0.0, 0.03)),
        ],
        finger: false,
        axes: [true; 3],
        noise: 2e-5,
        seed,
        description: "cli fit of several".into(),
        distortion: None,
    };
    let mut recs = Vec::new();
    for (name, mass, seed) in [("gravity", 0.0, 1), ("loaded", 0.05, 2)] {
        let mut scene = beam(mass);
        scene.object.young_modulus = 350e3;
        let r = synthesize(&beam(mass), &spec(seed), &dir.join(name)).unwrap();
        // Start from a wrong E.
        std::fs::write(&r.scene_path, scene.to_toml()).unwrap();
        recs.push(dir.join(name).join("recording.toml"));
    }
    let (json, report, scenes) = (dir.join("fit.json"), dir.join("report"), dir.join("scenes"));
    std::fs::write(&scenes, "a file").unwrap();
    let search = [
        "--params",
        "young_modulus=5e4:1e6",
        "--scene-out",
        arg(&scenes),
    ];
    let o = softgrip(&[&["fit", arg(&recs[0]), arg(&recs[1])], &search[..]].concat());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("names a directory"), "{}", stderr(&o));
    std::fs::remove_file(&scenes).unwrap();
    let o = lab_command(
        "fit",
        arg(&recs[0]),
        &[&[arg(&recs[1])], &search[..]].concat(),
        &json,
        &report,
    );
    assert!(o.status.success(), "{o:?}");
    let out = stdout(&o);
    assert!(
        out.contains("mean NRMSE") && out.contains("loaded/recording.toml"),
        "{out}"
    );
    let v = read_json(&json);
    let each = v["recordings"].as_array().expect("recordings");
    assert_eq!(each.len(), 2);
    for r in each {
        let (after, before) = (
            r["nrmse"].as_f64().unwrap(),
            r["before"]["nrmse"].as_f64().unwrap(),
        );
        assert!(after < 0.2 * before, "{r}");
    }
    let mean = (each[0]["nrmse"].as_f64().unwrap() + each[1]["nrmse"].as_f64().unwrap()) / 2.0;
    assert!((v["nrmse"].as_f64().unwrap() - mean).abs() < 1e-12, "{v}");
    let e = v["params"]["young_modulus"].as_f64().expect("E");
    let se = v["standard_errors"]["young_modulus"]
        .as_f64()
        .expect("its error");
    assert!((e - 200e3).abs() <= 3.0 * se, "{e} +/- {se}");
    let md = std::fs::read_to_string(report.join("fit.md")).unwrap();
    assert!(md.contains("(01-gravity/recording.md)"), "{md}");
    assert!(report.join("02-loaded/recording.md").exists());
    for name in ["01-gravity.toml", "02-loaded.toml"] {
        let text = std::fs::read_to_string(scenes.join(name)).unwrap();
        let fitted = softgrip_core::Scene::from_toml_str(&text, name).unwrap();
        assert!((fitted.object.young_modulus - e).abs() < 1e-6 * e, "{name}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn sweep_refuses_a_bad_grid_clearly() {
    let rec = recording("beam_ds10/gravity_a/recording.toml");
    let o = softgrip(&["sweep", &rec, "--param", "tau_q=0:1:3"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("unknown parameter \"tau_q\"; known: young_modulus"),
        "{err}"
    );
    let o = softgrip(&[
        "sweep",
        &rec,
        "--param",
        "tau_c=0:1:2",
        "--param",
        "alpha=1:2:2",
        "--param",
        "tau_s=0:1:2",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("a curve (one) or a grid (two)"));
}

/// `--report` names a directory: a file name is refused before any work,
/// with the directory to use instead, and nothing is made.
#[test]
fn a_report_named_like_a_file_is_refused_at_once() {
    let rec = recording("beam_ds10/gravity_a/recording.toml");
    let dir = scratch_path("softgrip-cli-report");
    let md = dir.join("diagnosis.md");
    let o = softgrip(&["diagnose", &rec, "--report", arg(&md)]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("--report takes a directory"), "{err}");
    assert!(err.contains("not a .md file"), "{err}");
    assert!(
        err.contains(&dir.join("diagnosis").display().to_string()),
        "{err}"
    );
    assert!(!md.exists(), "nothing is made");
}

/// A `--bound` that cannot be a range is refused before any work, naming
/// the option and the form to write.
#[test]
fn a_bad_bound_is_refused_at_once() {
    let rec = recording("beam_ds10/gravity_a/recording.toml");
    for (bound, says) in [
        ("young_modulus=9e4:3e4", "the low one first"),
        ("young_modulus=-1:3e4", "give a positive low value"),
        ("young_modulus:3e4", "write NAME=LOW:HIGH"),
        ("stiffness=1:2", "unknown parameter \"stiffness\""),
        (
            "young_modulus=1e12:2e12",
            "lies outside the range the baseline searches",
        ),
    ] {
        let o = softgrip(&["diagnose", &rec, "--no-report", "--bound", bound]);
        assert!(!o.status.success(), "{bound}");
        let err = stderr(&o);
        assert!(err.contains("--bound"), "{bound}: {err}");
        assert!(err.contains(says), "{bound}: {err}");
    }
}

/// `softgrip prove` refuses a bad option before making any recording.
#[test]
fn prove_refuses_a_bad_option_at_once() {
    let out = scratch_path("softgrip-prove-bad");
    let report = out.join("D.md");
    for (flag, value, says) in [
        ("--truth-edge-length", "4", "between 0.002 and 0.01"),
        ("--truth-edge-length", "0", "between 0.002 and 0.01"),
        ("--e-measured-within", "0.5", "give a factor above 1"),
    ] {
        let o = softgrip(&[
            "prove",
            "--out",
            arg(&out),
            "--report",
            arg(&report),
            flag,
            value,
        ]);
        assert!(!o.status.success(), "{flag} {value}");
        let err = stderr(&o);
        assert!(
            err.contains(flag) && err.contains(says),
            "{flag} {value}: {err}"
        );
        assert!(
            !out.exists(),
            "{flag} {value}: nothing made before the refusal"
        );
    }
}

/// A scene on an .stl surface: without TetGen, one clear error (said
/// once, not repeated by the error chain); the tetrahedralization itself
/// is tested with the feature (tests/surface_meshes.rs).
#[cfg(not(feature = "tetgen"))]
#[test]
fn a_surface_scene_without_tetgen_says_what_to_do_once() {
    let dir = scratch_dir("softgrip-cli-stl");
    std::fs::copy(mesh_fixture("sphere_surface.stl"), dir.join("ball.stl")).unwrap();
    std::fs::write(
        dir.join("scene.toml"),
        "[object]\nshape = \"mesh\"\npath = \"ball.stl\"\n[support]\nkind = \"fixed-bottom\"\n",
    )
    .unwrap();
    let (scene, out) = (dir.join("scene.toml"), dir.join("out.msh"));
    let o = softgrip(&["mesh", "make", arg(&scene), arg(&out)]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert_eq!(err.matches("built without TetGen").count(), 1, "{err}");
    assert!(
        err.contains("ball.stl") && err.contains("--features tetgen"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
#[ignore = "slow: the command run end to end"]
fn synth_writes_a_recording_that_compares_to_its_noise() {
    let dir = scratch_path("softgrip-cli-synth");
    let scene = scene("thesis_cuboid_light_guide.toml");
    let o = softgrip(&[
        "synth",
        &scene,
        "--loads",
        "2",
        "--axes",
        "xq",
        "--out",
        arg(&dir),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--axes \"xq\": use the letters x, y and z"));
    let o = softgrip(&[
        "synth",
        &scene,
        "--loads",
        "2,4",
        "--axes",
        "xz",
        "--noise",
        "0",
        "--out",
        arg(&dir),
    ]);
    assert!(o.status.success(), "{o:?}");
    assert!(
        stdout(&o).contains("(2 samples, 14 markers)"),
        "{}",
        stdout(&o)
    );
    let csv = std::fs::read_to_string(dir.join("samples.csv")).unwrap();
    // x and z observed, y left empty.
    assert!(
        csv.lines().nth(1).unwrap().split(',').nth(4) == Some(""),
        "{csv}"
    );
    // Without noise it is the scene's own simulation: NRMSE 0.
    let (rec, json) = (dir.join("recording.toml"), dir.join("c.json"));
    let o = softgrip(&["compare", arg(&rec), "--no-report", "--json", arg(&json)]);
    assert!(o.status.success(), "{o:?}");
    let v = read_json(&json);
    assert!(v["nrmse"].as_f64().unwrap() < 1e-12, "{v}");
    assert!(v.get("discretisation").is_none(), "only when asked: {v}");
    // Asked, the mesh's move: a quasi-static recording's step is not checked.
    let o = softgrip(&[
        "compare",
        arg(&rec),
        "--no-report",
        "--discretisation",
        "--json",
        arg(&json),
    ]);
    assert!(o.status.success(), "{o:?}");
    let text = stdout(&o);
    assert!(
        text.contains("discretisation: a finer mesh (3.2 mm instead of 4 mm) moves the markers by"),
        "{text}"
    );
    let v = read_json(&json);
    // With its discretisation the JSON is still its type's (docs/schema/compare.json).
    softgrip_lab::schema::round_trip("compare", &v).unwrap();
    let d = &v["discretisation"];
    assert!(d["mesh"]["rms_m"].as_f64().is_some_and(|m| m > 0.0), "{v}");
    assert!(d["time_step"]["skipped"].is_string(), "{v}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn grasp_says_whether_friction_held_the_object() {
    let dir = scratch_dir("softgrip-cli-grasp");
    let json = dir.join("grasp.json");
    let o = softgrip(&["grasp", &scene("grasp_lift.toml"), "--json", arg(&json)]);
    let text = stdout(&o);
    assert!(o.status.success(), "{text}");
    assert!(text.contains("HELD"), "{text}");
    assert!(
        text.contains("force balance: weight / squeeze = 0.14"),
        "{text}"
    );
    let v = read_json(&json);
    assert_eq!(v["held"], true);
    assert!((v["finger_rise_m"].as_f64().expect("rise") - 0.02).abs() < 1e-4);
    // Fingers' friction 0.05, a third of the force balance's 0.14: dropped, and the exit code
    // says so (4), not success.
    let text = std::fs::read_to_string(scene("grasp_lift.toml")).expect("the scene");
    let slippery = text.replace(
        "travel = 0.02                   # for 2 cm, then held\nfriction = 0.5",
        "travel = 0.02\nfriction = 0.05",
    );
    let slippery = slippery.replace(
        "travel = 0.02\nfriction = 0.5",
        "travel = 0.02\nfriction = 0.05",
    );
    assert_eq!(
        slippery.matches("friction = 0.05").count(),
        2,
        "both fingers changed"
    );
    let path = write_file(&dir, "slippery.toml", &slippery);
    let o = softgrip(&["grasp", arg(&path)]);
    let text = stdout(&o);
    assert!(text.contains("DROPPED"), "{text}{}", stderr(&o));
    assert_eq!(o.status.code(), Some(4), "{text}");
    // A scene where nothing lifts is an error saying what to add.
    let o = softgrip(&["grasp", &scene("pinch.toml")]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("no finger lifts") || err.contains("travel"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `grasp window`: the two bounds in the JSON under the names the docs give, the report's files,
/// and the exit code of a scene with no window (5).
#[test]
fn grasp_window_writes_both_bounds_and_exits_5_without_a_window() {
    let dir = scratch_dir("softgrip-cli-grasp-window");
    let json = dir.join("window.json");
    let report = dir.join("report");
    let o = softgrip(&[
        "grasp",
        "window",
        &scene("grasp_lift.toml"),
        "--damage",
        "pressure",
        "--limit",
        "5000",
        "--no-confirm",
        "--json",
        arg(&json),
        "--report",
        arg(&report),
    ]);
    let text = stdout(&o);
    assert!(o.status.success(), "{text}{}", stderr(&o));
    let v = read_json(&json);
    // The JSON is its type's (docs/schema/grasp_window.json).
    softgrip_lab::schema::round_trip("grasp_window", &v).unwrap();
    let least = v["least_squeeze"].as_f64().expect("least_squeeze");
    let most = v["most_squeeze"].as_f64().expect("most_squeeze");
    assert!(least > 0.28 && least < most, "{least} .. {most}");
    assert_eq!(v["window"], true);
    assert!(v["samples"].as_array().is_some_and(|s| s.len() > 5));
    for f in ["window.md", "window.png", "window.svg", "upper_bound.vtu"] {
        assert!(report.join(f).is_file(), "{f}");
    }
    let o = softgrip(&[
        "grasp",
        "window",
        &scene("grasp_lift.toml"),
        "--damage",
        "pressure",
        "--limit",
        "300",
        "--no-confirm",
    ]);
    assert_eq!(o.status.code(), Some(5), "{}", stdout(&o));
    assert!(stdout(&o).contains("NO WINDOW"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The subcommands `softgrip --help` lists, without `help`.
fn subcommands() -> Vec<String> {
    let help = stdout(&softgrip(&["--help"]));
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect()
}

/// The help texts and the docs say the same: docs/cli.md's table lists every command there is
/// and no other; each `--help` runs; and the facts the help states hold (what `run --out`
/// writes, the formats `mesh convert` takes, the number of `prove`'s controls).
#[test]
fn help_texts_agree_with_the_docs_and_the_program() {
    let commands = subcommands();
    assert!(commands.len() >= 15, "{commands:?}");
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/cli.md"))
        .expect("docs/cli.md");
    // The table's first column: `name ...`, or several names `a`, `b`.
    let documented: Vec<String> = docs
        .lines()
        .skip_while(|l| !l.starts_with("| command |"))
        .take_while(|l| l.starts_with('|'))
        .filter(|l| l.starts_with("| `"))
        .flat_map(|l| {
            let cell = l.split('|').nth(1).unwrap_or("");
            cell.split('`')
                .skip(1)
                .step_by(2)
                .filter_map(|c| c.split_whitespace().next().map(str::to_string))
                .collect::<Vec<_>>()
        })
        .collect();
    for c in &commands {
        assert!(
            documented.contains(c),
            "`softgrip {c}` is not in docs/cli.md's table: {documented:?}"
        );
        let o = softgrip(&[c, "--help"]);
        assert!(o.status.success(), "{c} --help: {}", stderr(&o));
    }
    for d in &documented {
        assert!(
            commands.contains(d),
            "docs/cli.md lists `{d}`, which `softgrip --help` does not have"
        );
    }

    // Every kind of file `run --out` writes is named in `run --help`.
    let dir = scratch_dir("softgrip-cli-help-out");
    let o = softgrip(&["run", "--duration", "0.02", "--out", arg(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = stdout(&softgrip(&["run", "--help"]));
    let mut kinds: Vec<String> = std::fs::read_dir(&dir)
        .expect("the output")
        .map(|e| {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            // frame_00012.vtu -> frame_*.vtu, finger1_00012.vtu -> finger*_*.vtu
            let mut kind = String::new();
            for c in name.chars() {
                if !c.is_ascii_digit() {
                    kind.push(c);
                } else if !kind.ends_with('*') {
                    kind.push('*');
                }
            }
            kind
        })
        .collect();
    kinds.sort();
    kinds.dedup();
    for k in &kinds {
        assert!(
            help.contains(k.as_str()),
            "`run --help` does not name {k}: {help}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);

    // `mesh convert --help` names every format `mesh convert` writes.
    let help = stdout(&softgrip(&["mesh", "convert", "--help"]));
    for ext in [".msh", ".node", ".ele", ".vtk", ".vtu"] {
        assert!(
            help.contains(ext),
            "`mesh convert --help` does not name {ext}: {help}"
        );
    }

    // `prove --help` counts the suite's controls right.
    let controls = softgrip_lab::prove::seeded(softgrip_lab::prove::DEVELOPMENT_SEED, "")
        .iter()
        .filter(|(_, c)| c.name.starts_with("control"))
        .count();
    let words = [
        "none", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    ];
    let help = stdout(&softgrip(&["prove", "--help"]));
    assert!(
        help.contains(&format!("{} controls", words[controls])),
        "{controls} controls in the suite: {help}"
    );
}

/// `--json` on run, check and mesh info, and `ramp --csv` and `--json`: the figures a script
/// reads, in SI units. Each load's contact force rises by the load's own rise (the finger's
/// weight is the same under every load).
#[test]
fn run_ramp_check_and_mesh_info_write_json_and_csv() {
    let dir = scratch_dir("softgrip-cli-json");
    let run = dir.join("run.json");
    let o = softgrip(&["run", "--duration", "0.05", "--json", arg(&run)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v = read_json(&run);
    assert!((v["time_s"].as_f64().expect("time") - 0.05).abs() < 1e-9);
    assert_eq!(v["fingers"].as_array().expect("fingers").len(), 1);
    assert!(v["warnings"].as_array().expect("warnings").is_empty());

    let (csv, json) = (dir.join("ramp.csv"), dir.join("ramp.json"));
    let guide = scene("thesis_cuboid_light_guide.toml");
    let o = softgrip(&[
        "ramp",
        &guide,
        "--loads",
        "1,3",
        "--csv",
        arg(&csv),
        "--json",
        arg(&json),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_json(&json)["loads"].as_array().expect("rows").clone();
    assert_eq!(rows.len(), 2);
    let force = |i: usize| rows[i]["contact_force_n"].as_f64().expect("force");
    assert!((force(1) - force(0) - 2.0).abs() < 1e-3, "{rows:?}");
    let text = std::fs::read_to_string(&csv).expect("csv");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    let cell: f64 = lines[2]
        .split(',')
        .nth(2)
        .expect("cell")
        .parse()
        .expect("number");
    assert!((cell - force(1)).abs() <= 1e-9 * force(1).abs(), "{text}");

    let check = dir.join("check.json");
    let o = softgrip(&["check", "--json", arg(&check)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The built-in 50 x 50 x 20 mm cuboid at 4 mm: 12 x 12 x 5 cells of six tetrahedra.
    assert_eq!(read_json(&check)["mesh"]["tetrahedra"], 4320);

    let info = dir.join("info.json");
    let o = softgrip(&[
        "mesh",
        "info",
        &mesh_fixture("cube.msh"),
        "--json",
        arg(&info),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v = read_json(&info);
    assert!(v["tetrahedra"].as_u64().expect("count") > 0);
    assert!(v["volume_m3"].as_f64().expect("volume") > 0.0);
    // A surface's figures too (its enclosed volume, as the tetrahedra's for a tet mesh).
    let surface = dir.join("surface.json");
    let o = softgrip(&[
        "mesh",
        "info",
        &mesh_fixture("sphere_surface.stl"),
        "--json",
        arg(&surface),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(read_json(&surface)["volume_m3"].as_f64().expect("volume") > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
