//! Every command's `--json` read back through its type (`softgrip_lab::schema::round_trip`): a
//! key the type does not know, one it lacks or a value of the wrong kind fails, and so does a
//! file that does not come back the same. The schemas in `docs/schema/` are those types'
//! (`softgrip-lab`'s test `schema`). The diagnosis's JSON is read back in its own end-to-end
//! test (`softgrip-lab`'s `diagnose_run`), the grasp window's and compare's with
//! `--discretisation` in `cli.rs`.

use std::path::Path;

use super::support::{arg, read_json, recording, scene, scratch_dir, softgrip, stderr};

/// The JSON at `path`, which the output `name` is, read through its type.
fn fits(name: &str, path: &Path) {
    let value = read_json(path);
    if let Err(e) = softgrip_lab::schema::round_trip(name, &value) {
        panic!("{}: {e}", path.display());
    }
}

/// `softgrip ARGS...`, which must succeed.
fn ok(args: &[&str]) {
    let o = softgrip(args);
    assert!(
        o.status.success(),
        "softgrip {}: {}",
        args.join(" "),
        stderr(&o)
    );
}

/// The cheap commands' JSON: modulus, mesh info of a mesh and of a surface, check (one with a
/// warning), grasp, compare, a sweep, its shards and their merge, run and ramp.
#[test]
fn every_commands_json_fits_its_type() {
    let dir = scratch_dir("softgrip-json-schema");
    let out = |name: &str| dir.join(format!("{name}.json"));
    let ecoflex = recording("ecoflex_compression/EF30_0T_A1/recording.toml");
    ok(&[
        "modulus",
        &ecoflex,
        "--no-report",
        "--json",
        arg(&out("modulus")),
    ]);
    fits("modulus", &out("modulus"));

    let meshes = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/crates/softgrip-core/tests/data/meshes"
    );
    for (name, file) in [("tets", "cube.msh"), ("surface", "sphere_surface.stl")] {
        let path = format!("{meshes}/{file}");
        ok(&["mesh", "info", &path, "--json", arg(&out(name))]);
        fits("mesh", &out(name));
    }

    for (name, file) in [
        ("check", "pinch.toml"),
        ("warned", "thesis_cuboid_no_bulk.toml"),
    ] {
        ok(&["check", &scene(file), "--json", arg(&out(name))]);
        fits("check", &out(name));
    }
    let warnings = read_json(&out("warned"))["warnings"].clone();
    assert_eq!(warnings.as_array().map(Vec::len), Some(1), "{warnings}");

    ok(&[
        "grasp",
        &scene("grasp_lift.toml"),
        "--json",
        arg(&out("grasp")),
    ]);
    fits("grasp", &out("grasp"));

    let thesis = recording("synthetic/thesis_7_loads/recording.toml");
    ok(&[
        "compare",
        &thesis,
        "--no-report",
        "--json",
        arg(&out("compare")),
    ]);
    fits("compare", &out("compare"));

    let grid = "young_modulus=5e4:7e4:2";
    let sweep = ["sweep", &thesis, "--param", grid, "--workers", "1"];
    ok(&[&sweep[..], &["--no-report", "--json", arg(&out("sweep"))]].concat());
    fits("sweep", &out("sweep"));
    for i in 0..2 {
        let (shard, part) = (format!("{i}/2"), out(&format!("part{i}")));
        ok(&[&sweep[..], &["--shard", &shard, "--part", arg(&part)]].concat());
        fits("sweep_part", &part);
    }
    let parts = [out("part0"), out("part1")];
    ok(&[
        "merge",
        arg(&parts[0]),
        arg(&parts[1]),
        "--json",
        arg(&out("merge")),
    ]);
    fits("merge", &out("merge"));

    ok(&["run", "--duration", "0.05", "--json", arg(&out("run"))]);
    fits("run", &out("run"));
    let guide = scene("thesis_cuboid_light_guide.toml");
    ok(&[
        "ramp",
        &guide,
        "--loads",
        "1,3",
        "--json",
        arg(&out("ramp")),
    ]);
    fits("ramp", &out("ramp"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fit's JSON, of one recording and of several: two small cantilevers softgrip makes itself,
/// one ringing under gravity (a time series: the JSON has its ringing), one at rest under a tip
/// mass.
#[test]
fn a_fits_json_fits_its_type() {
    use softgrip_lab::recording::{Mode, Start};
    use softgrip_lab::synth::{Synthesis, synthesize};
    let dir = scratch_dir("softgrip-json-schema-fit");
    let beam = |tip_mass: f64| {
        let mut text = "[simulation]\ndt = 1e-3\nduration = 0.1\ngravity = [0.0, 0.0, -9.81]\n\n[object]\nshape = \"cuboid\"\nsize = [0.1, 0.03, 0.03]\nedge_length = 0.01\ndensity = 1070.0\nyoung_modulus = 200000.0\npoisson_ratio = 0.45\n\n[support]\nkind = \"none\"\n\n[[fixed]]\nmin = [-0.0505, -0.016, -0.001]\nmax = [-0.0495, 0.016, 0.031]\n".to_string();
        if tip_mass > 0.0 {
            text += &format!(
                "\n[[load]]\nmin = [0.0495, -0.016, 0.0295]\nmax = [0.0505, 0.016, 0.0305]\nmass = {tip_mass:?}\n"
            );
        }
        softgrip_core::Scene::from_toml_str(&text, "beam").expect("the beam")
    };
    let spec = |mode: Mode, samples: Vec<(Option<f64>, f64)>| Synthesis {
        mode,
        start: Start::Rest,
        samples,
        markers: vec![("tip".into(), glam::DVec3::new(0.05, 0.0, 0.03))],
        finger: false,
        axes: [true; 3],
        noise: 2e-5,
        seed: 1,
        description: "json schema".into(),
        distortion: None,
    };
    let ringing: Vec<_> = (1..=20).map(|i| (Some(0.005 * i as f64), 0.0)).collect();
    let rec = |name: &str| dir.join(name).join("recording.toml");
    synthesize(
        &beam(0.0),
        &spec(Mode::TimeSeries, ringing),
        &dir.join("ringing"),
    )
    .expect("a time series");
    synthesize(
        &beam(0.05),
        &spec(Mode::QuasiStatic, vec![(None, 0.0)]),
        &dir.join("loaded"),
    )
    .expect("a quasi-static recording");
    let (one, many) = (dir.join("fit.json"), dir.join("fit_many.json"));
    let fit = [
        "fit",
        "--params",
        "young_modulus=1e5:4e5",
        "--max-evaluations",
        "10",
    ];
    let (ringing, loaded) = (rec("ringing"), rec("loaded"));
    ok(&[
        &fit[..],
        &[arg(&ringing), "--no-report", "--json", arg(&one)],
    ]
    .concat());
    fits("fit", &one);
    assert!(
        read_json(&one)["ringing"].is_object(),
        "a time series rings"
    );
    let both = [arg(&ringing), arg(&loaded)];
    ok(&[&fit[..], &both[..], &["--no-report", "--json", arg(&many)]].concat());
    fits("fit_many", &many);
    let _ = std::fs::remove_dir_all(&dir);
}
