//! Issue 5: parameter sweeps. Grids parse as written, a bad value is an
//! error naming the parameter, and a sweep over a recording softgrip made
//! itself finds the parameter it was made with, whatever the number of
//! workers.

use std::fmt::Write as _;

use softgrip_lab::params::{self, parse_axis};
use softgrip_lab::recording::Recording;
use softgrip_lab::replay::{ReplayOptions, replay};
use softgrip_lab::sweep::{best, grid, sweep, to_csv};

#[test]
fn axes_parse_linear_log_and_lists() {
    let a = parse_axis("tau_c=0.01:0.25:25").unwrap();
    assert_eq!(a.param.name, "tau_c");
    assert_eq!(a.values.len(), 25);
    assert_eq!(a.values[0], 0.01);
    assert!((a.values[24] - 0.25).abs() < 1e-15);
    assert!((a.values[1] - 0.02).abs() < 1e-15);
    let l = parse_axis("alpha=1e5:1e7:3:log").unwrap();
    for (v, e) in l.values.iter().zip([1e5, 1e6, 1e7]) {
        assert!((v - e).abs() < 1e-9 * e, "{v}");
    }
    assert_eq!(parse_axis("tau_s=0.1,0.2").unwrap().values, [0.1, 0.2]);
    for (bad, says) in [
        (
            "tau_x=0:1:3",
            "unknown parameter \"tau_x\"; known: young_modulus",
        ),
        ("tau_c=0:1", "a range has start:end:count"),
        ("tau_c=0:1:0", "from 1 to 10000"),
        ("alpha=0:1e6:3:log", "positive ends"),
        ("tau_c", "no '='"),
        ("tau_c=a,b", "\"a\" is not a number"),
    ] {
        let e = parse_axis(bad).expect_err(bad).to_string();
        assert!(e.contains(says), "{bad}: {e}");
    }
}

#[test]
fn a_bad_value_names_the_parameter_and_the_rule() {
    let scene = softgrip_core::Scene::thesis();
    let e = params::set(&scene, "young_modulus", -5.0)
        .expect_err("negative")
        .to_string();
    assert!(e.starts_with("young_modulus = -5: not allowed: "), "{e}");
    let ok = params::set(&scene, "tau_c", 0.2).expect("fine");
    assert_eq!(params::get(&ok, "tau_c").unwrap(), Some(0.2));
    assert_eq!(ok.model.tau_s, scene.model.tau_s, "nothing else changed");
    let f = params::set(&scene, "friction", 0.9).expect("fine");
    assert!(f.fingers.iter().all(|x| x.friction == 0.9));
}

#[test]
fn grids_vary_the_last_axis_fastest() {
    let axes = [
        parse_axis("tau_s=1,2").unwrap(),
        parse_axis("tau_c=3,4,5").unwrap(),
    ];
    let g = grid(&axes);
    assert_eq!(
        g,
        vec![
            vec![1.0, 3.0],
            vec![1.0, 4.0],
            vec![1.0, 5.0],
            vec![2.0, 3.0],
            vec![2.0, 4.0],
            vec![2.0, 5.0]
        ]
    );
}

/// A quasi-static recording of the light-guide thesis scene (6 mm mesh) at
/// tau_c = 0.155, made by softgrip itself.
fn synthetic() -> Recording {
    let dir = std::env::temp_dir().join(format!("softgrip-sweep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/assets/scenes/thesis_cuboid_light_guide.toml"
    ))
    .unwrap()
    .replace("edge_length = 0.004", "edge_length = 0.006");
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    std::fs::write(
        dir.join("recording.toml"),
        "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"quasi-static\"\n[markers]\ntop = [0.01, 0.0, 0.02]\nside = [0.025, 0.0, 0.01]\n",
    )
    .unwrap();
    let loads = [4.0, 9.73];
    let mut rows = String::from("time,load,marker,x,y,z\n");
    for l in loads {
        for m in ["top", "side"] {
            let _ = writeln!(rows, ",{l},{m},0,0,0");
        }
    }
    std::fs::write(dir.join("samples.csv"), &rows).unwrap();
    let placeholder = Recording::load(&dir.join("recording.toml")).unwrap();
    let run = replay(
        &placeholder,
        &placeholder.scene,
        ReplayOptions::default(),
        |_| {},
    )
    .unwrap();
    let mut rows = String::from("time,load,marker,x,y,z\n");
    for r in &run.residuals {
        let p = r.simulated;
        let _ = writeln!(
            rows,
            ",{},{},{:?},,{:?}",
            loads[r.sample],
            placeholder.marker_name(r.marker),
            p.x,
            p.z
        );
    }
    std::fs::write(dir.join("samples.csv"), &rows).unwrap();
    Recording::load(&dir.join("recording.toml")).unwrap()
}

#[test]
fn a_sweep_finds_the_parameter_a_recording_was_made_with() {
    let rec = synthetic();
    assert_eq!(rec.scene.model.tau_c, Some(0.155));
    let axes = [parse_axis("tau_c=0.10,0.155,0.25").unwrap()];
    let serial = sweep(&rec, &axes, 1, &|_| {});
    let parallel = sweep(&rec, &axes, 3, &|_| {});
    assert_eq!(serial, parallel, "the same whatever the number of workers");
    let b = best(&serial).expect("a best point");
    assert_eq!(b.values, [0.155]);
    assert_eq!(b.result.as_ref().unwrap().nrmse, 0.0);
    for p in &serial {
        if p.values != [0.155] {
            assert!(p.result.as_ref().unwrap().nrmse > 1e-4, "{p:?}");
        }
    }
    let csv = to_csv(&axes, &serial);
    assert!(csv.starts_with("tau_c,nrmse,rmse_m,nrmse_all,rmse_all_m,error\n"));
    assert_eq!(csv.lines().count(), 4);
    // A point that cannot run is reported, not fatal.
    let bad = [parse_axis("young_modulus=-1,57600").unwrap()];
    let points = sweep(&rec, &bad, 2, &|_| {});
    assert!(
        points[0]
            .result
            .as_ref()
            .unwrap_err()
            .to_string()
            .contains("young_modulus = -1")
    );
    assert!(points[1].result.is_ok());
}
