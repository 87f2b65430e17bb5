//! Issue 5: simulating a recording. A recording written from softgrip's
//! own run of a scene replays to zero error; shifted by a known offset on
//! its observed axes, to exactly that offset over the object's extent.

use std::fmt::Write as _;
use std::path::PathBuf;

use glam::DVec3;
use softgrip_lab::compare::{Residual, marker_position};
use softgrip_lab::recording::{MarkerRef, Recording};
use softgrip_lab::replay::{ReplayOptions, replay};

use crate::support::{self, write_recording as write};

fn temp(name: &str) -> PathBuf {
    support::temp_dir(&format!("replay-{name}"))
}

fn light_guide_scene() -> String {
    support::light_guide_scene(0.006)
}

/// The samples' rows of a replay of `recording` at `loads`: the finger's z
/// as simulated, each object marker's coordinates as `object` writes its
/// simulated position ("x,y,z", empty for an axis not seen).
fn rows_of(
    residuals: &[Residual],
    recording: &Recording,
    loads: &[f64],
    object: impl Fn(DVec3) -> String,
) -> String {
    let mut rows = String::new();
    for r in residuals {
        let name = recording.marker_name(r.marker);
        let l = loads[r.sample];
        let p = r.simulated;
        match r.marker {
            MarkerRef::Finger(_) => {
                let _ = writeln!(rows, ",{l},{name},,,{:?}", p.z);
            }
            MarkerRef::Object(_) => {
                let _ = writeln!(rows, ",{l},{name},{}", object(p));
            }
        }
    }
    rows
}

#[test]
fn a_quasi_static_recording_of_softgrip_itself_replays_to_zero_and_an_offset_to_itself() {
    let markers = [
        ("top", DVec3::new(0.01, 0.0, 0.02)),
        ("side", DVec3::new(0.025, 0.0, 0.01)),
    ];
    // Loading then unloading: 2, 6, 9.73, then 6 again (a separate sample).
    let loads = [2.0, 6.0, 9.73, 6.0];
    let mut rows = String::new();
    for l in loads {
        for (name, _) in &markers {
            let _ = writeln!(rows, ",{l},{name},0,0,0");
        }
        let _ = writeln!(rows, ",{l},finger,,,0");
    }
    let dir = temp("qs");
    let placeholder = write(&dir, &light_guide_scene(), "quasi-static", &markers, &rows);
    assert_eq!(placeholder.samples.len(), 4);
    let first = replay(
        &placeholder,
        &placeholder.scene,
        ReplayOptions::default(),
        |_| {},
    )
    .expect("replay");
    // The same run, written as the recording.
    let rows = rows_of(&first.residuals, &placeholder, &loads, |p| {
        format!("{:?},{:?},{:?}", p.x, p.y, p.z)
    });
    let exact = write(&dir, &light_guide_scene(), "quasi-static", &markers, &rows);
    let again = replay(&exact, &exact.scene, ReplayOptions::default(), |_| {}).expect("replay");
    assert_eq!(again.errors.rmse_m, 0.0, "deterministic: the same run");
    assert_eq!(again.errors.nrmse_all, 0.0);
    // The finger went down as the load rose and came back up on unloading.
    let depth = |s: usize| {
        again
            .residuals
            .iter()
            .find(|r| r.sample == s && r.marker == MarkerRef::Finger(0))
            .map(|r| r.simulated.z)
            .unwrap()
    };
    assert!(depth(0) > depth(1) && depth(1) > depth(2) && depth(3) > depth(2));

    // Shift every object observation by (1, 0, -2) mm on x and z only
    // (y unobserved): NRMSE = sqrt(5) mm / 50 mm.
    let rows = rows_of(&first.residuals, &placeholder, &loads, |p| {
        format!("{:?},,{:?}", p.x + 0.001, p.z - 0.002)
    });
    let shifted = write(&dir, &light_guide_scene(), "quasi-static", &markers, &rows);
    let e = replay(&shifted, &shifted.scene, ReplayOptions::default(), |_| {})
        .expect("replay")
        .errors;
    let expected = (0.001f64.powi(2) + 0.002f64.powi(2)).sqrt();
    assert!(
        (e.rmse_m - expected).abs() < 1e-12,
        "{} vs {expected}",
        e.rmse_m
    );
    assert!((e.nrmse - expected / 0.05).abs() < 1e-10);
    assert_eq!(e.count, 8);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_time_series_samples_at_its_times_and_holds_each_load_until_the_next() {
    // The gravity beam, 0.2 s at 10 ms: replayed against itself.
    let scene = std::fs::read_to_string(support::asset(
        "assets/recordings/beam_ds10/gravity_a/scene.toml",
    ))
    .unwrap()
    .replace("edge_length = 0.005", "edge_length = 0.01");
    let markers = [("tip", DVec3::new(0.05, 0.0, 0.03))];
    let mut rows = String::new();
    for k in 0..=20 {
        let _ = writeln!(rows, "{:.2},0,tip,0,0,0", k as f64 * 0.01);
    }
    let dir = temp("ts");
    let rec = write(&dir, &scene, "time-series", &markers, &rows);
    // Fixed steps, as a plain run takes them (error-controlled ones have their own test in the
    // core's `adaptive`).
    let fixed = ReplayOptions {
        adaptive: None,
        ..ReplayOptions::default()
    };
    let run = replay(&rec, &rec.scene, fixed, |_| {}).expect("replay");
    assert_eq!(run.residuals.len(), 21);
    // Against a plain run sampled at the same times.
    let mut sim = softgrip_core::Simulation::new(&rec.scene).unwrap();
    for (k, r) in run.residuals.iter().enumerate() {
        sim.run_until(k as f64 * 0.01).unwrap();
        let p = marker_position(
            &sim.model,
            &sim.state,
            &run.attachments,
            MarkerRef::Object(0),
        )
        .unwrap();
        assert_eq!(p, r.simulated, "sample {k}");
    }
    // The tip falls under gravity after release.
    assert!(run.residuals[20].simulated.z < run.residuals[0].simulated.z - 1e-3);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_marker_far_from_the_surface_is_an_error_naming_it() {
    // 12 mm above the top face of a 50 mm block: more than a tenth of it.
    let markers = [
        ("top", DVec3::new(0.01, 0.0, 0.02)),
        ("high", DVec3::new(0.0, 0.0, 0.032)),
    ];
    let rec = write(
        &temp("far"),
        &light_guide_scene(),
        "quasi-static",
        &markers,
        ",1,top,0,0,0\n,1,high,0,0,0\n",
    );
    let e = replay(&rec, &rec.scene, ReplayOptions::default(), |_| {})
        .expect_err("off the surface")
        .to_string();
    assert!(
        e.contains("recording.toml: marker high at [0.0, 0.0, 0.032]"),
        "{e}"
    );
    assert!(
        e.contains("is 12.0 mm from the object's surface (more than 5.0 mm"),
        "{e}"
    );
    assert!(e.contains("millimetres written as metres?"), "{e}");
}

#[test]
fn loads_without_a_direction_are_an_error_not_ignored() {
    // The large-finger scene's finger is force-controlled with force =
    // [0, 0, 0] (its weight is its mass): a recording's loads could not act.
    let scene = std::fs::read_to_string(support::asset(
        "assets/scenes/thesis_cuboid_large_finger.toml",
    ))
    .unwrap()
    .replace("edge_length = 0.004", "edge_length = 0.008");
    let markers = [("top", DVec3::new(0.01, 0.0, 0.02))];
    let rec = write(
        &temp("direction"),
        &scene,
        "quasi-static",
        &markers,
        ",4,top,0,0,0\n",
    );
    let e = replay(&rec, &rec.scene, ReplayOptions::default(), |_| {})
        .expect_err("no direction")
        .to_string();
    assert!(
        e.contains("scene.toml: the recording's loads (up to 4 N)"),
        "{e}"
    );
    assert!(e.contains("finger #1 has force = [0, 0, 0]"), "{e}");
    // Zero loads need no direction: the weight alone presses.
    let rec = write(
        &temp("direction0"),
        &scene,
        "quasi-static",
        &markers,
        ",0,top,0,0,0\n",
    );
    assert!(replay(&rec, &rec.scene, ReplayOptions::default(), |_| {}).is_ok());
}
