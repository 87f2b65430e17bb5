//! The discretisation check of `softgrip diagnose` (`softgrip_lab::discretisation`):
//! its measure on moves known by construction, what it checks for which
//! recording, and that the mesh's move shrinks as the mesh is refined.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use softgrip_core::quasi_static::RestTolerance;
use softgrip_lab::compare::Residual;
use softgrip_lab::diagnose::Noise;
use softgrip_lab::discretisation::{self, FINER, Outcome};
use softgrip_lab::recording::{MarkerRef, Recording};
use softgrip_lab::replay::{ReplayOptions, replay};

use crate::support;

fn temp(name: &str) -> PathBuf {
    support::temp_dir(&format!("discretisation-{name}"))
}

/// A recording of the light-guide cuboid at `edge` (m): three markers seen
/// in x and z and the finger, at `loads` (quasi-static) or, with `times`,
/// as a time series.
fn recording(dir: &Path, edge: f64, loads: &[f64], times: Option<&[f64]>) -> Recording {
    let markers = [
        ("top", DVec3::new(0.005, 0.0, 0.02)),
        ("corner", DVec3::new(-0.015, 0.0, 0.02)),
        ("side", DVec3::new(0.025, 0.0, 0.01)),
    ];
    let mode = if times.is_some() {
        "time-series"
    } else {
        "quasi-static"
    };
    let mut rows = String::new();
    for (k, l) in loads.iter().enumerate() {
        let t = times.map_or(String::new(), |t| format!("{:?}", t[k]));
        for (name, p) in &markers {
            let _ = writeln!(rows, "{t},{l},{name},{:?},,{:?}", p.x, p.z);
        }
        let _ = writeln!(rows, "{t},{l},finger,0,,0.035");
    }
    let scene = support::light_guide_scene(edge);
    support::write_recording(dir, &scene, mode, &markers, &rows)
}

fn noise(object_m: f64, finger_m: f64) -> Noise {
    Noise {
        object_m,
        finger_m,
        object_count: 10,
        finger_count: 10,
    }
}

fn residual(sample: usize, marker: MarkerRef, simulated: DVec3) -> Residual {
    Residual {
        sample,
        marker,
        simulated,
        recorded: [Some(0.0), None, Some(0.0)],
    }
}

/// Two replays that differ by moves set by hand: the RMS over the observed
/// coordinates (y is not observed and its move must not count), the same
/// over the noise per class, and the marker that moves most.
#[test]
fn the_measure_is_the_rms_move_of_the_observed_coordinates() {
    let dir = temp("measure");
    let rec = recording(&dir, 0.008, &[1.0, 2.0], None);
    let index = |name: &str| {
        rec.markers
            .iter()
            .position(|m| m.name == name)
            .map(MarkerRef::Object)
            .expect("marker")
    };
    let (top, corner, finger) = (index("top"), index("corner"), MarkerRef::Finger(0));
    let mut a = Vec::new();
    let mut b = Vec::new();
    for s in 0..2 {
        for m in [top, corner, finger] {
            let p = DVec3::new(0.001 * s as f64, 0.002, 0.003);
            a.push(residual(s, m, p));
            // top: 0.3 mm in x, 1 mm in the unobserved y; corner: 0.1 mm
            // in z; finger: 0.2 mm in z.
            let d = if m == top {
                DVec3::new(3e-4, 1e-3, 0.0)
            } else if m == corner {
                DVec3::new(0.0, 0.0, 1e-4)
            } else {
                DVec3::new(0.0, 0.0, 2e-4)
            };
            b.push(residual(s, m, p + d));
        }
    }
    let (sigma_object, sigma_finger) = (1e-4, 4e-4);
    let (rms, over, worst) =
        discretisation::moves(&rec, &a, &b, &noise(sigma_object, sigma_finger)).expect("same");
    // Per sample: 6 observed coordinates, squares 9e-8, 0, 0, 1e-8, 0, 4e-8.
    let expected = ((9e-8 + 1e-8 + 4e-8) / 6.0f64).sqrt();
    assert!((rms - expected).abs() < 1e-12, "{rms} against {expected}");
    let expected_over = ((9.0 + 1.0 + 0.25) / 6.0f64).sqrt();
    assert!(
        (over - expected_over).abs() < 1e-9,
        "{over} against {expected_over}"
    );
    assert_eq!(worst.0, "top");
    // top's RMS distance over its observed axes, x and z: 0.3 mm (its 1 mm
    // in y is not seen).
    assert!((worst.1 - 3e-4).abs() < 1e-12, "{worst:?}");
    // Noise-free object markers beside a noisy finger: the move over the
    // noise counts only the finger's coordinates (its 0.2 mm in z over
    // 0.4 mm, on 2 of its 2 observed coordinates per sample), not the
    // object's over the 1 um floor.
    let floor = softgrip_lab::diagnose::NOISE_FLOOR_M;
    let (_, over_mixed, _) =
        discretisation::moves(&rec, &a, &b, &noise(floor, sigma_finger)).expect("same");
    let expected_mixed = (0.25 / 2.0f64).sqrt();
    assert!(
        (over_mixed - expected_mixed).abs() < 1e-9,
        "{over_mixed} against {expected_mixed}"
    );
    // No move, nothing measured; other observations, no comparison.
    let (rms0, over0, _) = discretisation::moves(&rec, &a, &a, &noise(1e-4, 1e-4)).expect("same");
    assert_eq!((rms0, over0), (0.0, 0.0));
    assert!(discretisation::moves(&rec, &a, &b[1..], &noise(1e-4, 1e-4)).is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

fn fits() -> ReplayOptions {
    ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    }
}

/// A quasi-static recording: no time-step check (rest states do not depend
/// on the step), and the mesh's move is the distance between the replay
/// on the scene's mesh and on one FINER times it, on every observed
/// coordinate; it shrinks as the mesh is refined (the lattice converges).
#[test]
fn a_quasi_static_recording_checks_the_mesh_which_converges() {
    let dir = temp("qs");
    let loads = [3.0, 9.0];
    let mut moves = Vec::new();
    for edge in [0.008, 0.005] {
        let rec = recording(&dir.join(format!("{edge}")), edge, &loads, None);
        let coarse = replay(&rec, &rec.scene, fits(), |_| {}).expect("replay");
        let d = discretisation::check(&rec, &rec.scene, &coarse, &noise(1e-4, 1e-4), fits().rest);
        match &d.time_step {
            Outcome::Skipped(why) => assert!(why.contains("quasi-static"), "{why}"),
            Outcome::Measured(c) => panic!("a quasi-static recording checked the step: {c:?}"),
        }
        let mesh = d.mesh.measured().expect("the mesh is checked").clone();
        assert_eq!(mesh.coarse, edge);
        assert!((mesh.fine - edge * FINER).abs() < 1e-15);
        // The same measure by hand, from a replay on the finer mesh.
        let mut finer = rec.scene.clone();
        finer.object.edge_length = edge * FINER;
        let fine = replay(&rec, &finer, fits(), |_| {}).expect("finer replay");
        let mut sum = 0.0;
        let mut n = 0;
        for (a, b) in coarse.residuals.iter().zip(&fine.residuals) {
            for axis in [0, 2] {
                sum += (a.simulated[axis] - b.simulated[axis]).powi(2);
                n += 1;
            }
        }
        let by_hand = (sum / n as f64).sqrt();
        assert!(
            (mesh.rms_m - by_hand).abs() <= 1e-9 * by_hand.max(1e-9),
            "{} against {by_hand}",
            mesh.rms_m
        );
        assert!(mesh.rms_m > 0.0, "two meshes give two answers");
        assert!((mesh.over_noise - mesh.rms_m / 1e-4).abs() < 1e-9);
        moves.push(mesh.rms_m);
    }
    assert!(
        moves[1] < moves[0],
        "the move from refining shrinks with the edge: {moves:?} (m) at 8 and 5 mm"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A time series checks the step too, and a mesh file is not refined
/// (nor a quasi-static recording's step: nothing is replayed).
#[test]
fn a_time_series_checks_the_step_and_a_mesh_file_is_not_refined() {
    let dir = temp("ts");
    let mut rec = recording(
        &dir,
        0.008,
        &[3.0, 3.0, 6.0, 6.0],
        Some(&[0.05, 0.1, 0.15, 0.2]),
    );
    let coarse = replay(&rec, &rec.scene, fits(), |_| {}).expect("replay");
    // A noise-free recording (its noise estimate at the floor) gives the
    // moves in mm and no ratio to a noise it does not have.
    let floor = softgrip_lab::diagnose::NOISE_FLOOR_M;
    let bare = discretisation::check(&rec, &rec.scene, &coarse, &noise(floor, floor), fits().rest);
    let step = bare.time_step.measured().expect("the step is checked");
    assert!(!step.noise_measured && step.over_noise == 0.0, "{step:?}");
    assert!(step.rms_m > 0.0, "half the step moves the markers");
    assert!(
        bare.describe().contains("shows no noise") && !bare.describe().contains("times the noise"),
        "{}",
        bare.describe()
    );
    assert!(bare.to_json()["time_step"]["over_noise"].is_null());
    assert!(bare.caution().is_none(), "{:?}", bare.caution());
    let d = discretisation::check(&rec, &rec.scene, &coarse, &noise(1e-4, 1e-4), fits().rest);
    let step = d.time_step.measured().expect("the step is checked");
    assert!(step.noise_measured);
    assert!(d.to_json()["time_step"]["over_noise"].is_number());
    assert_eq!(step.fine, step.coarse / 2.0);
    assert!(step.rms_m.is_finite() && step.over_noise.is_finite());
    assert!(d.mesh.measured().is_some());
    assert!(d.describe().contains("half the time step"));
    let json = d.to_json();
    assert!(json["time_step"]["rms_m"].is_number(), "{json}");
    // Quasi-static as well, so that nothing is replayed.
    rec.mode = softgrip_lab::recording::Mode::QuasiStatic;
    rec.scene.object.shape = softgrip_core::scene::Shape::Mesh {
        path: PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../softgrip-core/tests/data/meshes/cube.msh"
        )),
        scale: 1.0,
        position: DVec3::ZERO,
    };
    let d = discretisation::check(&rec, &rec.scene, &coarse, &noise(1e-4, 1e-4), fits().rest);
    match &d.mesh {
        Outcome::Skipped(why) => assert!(why.contains("mesh file"), "{why}"),
        Outcome::Measured(c) => panic!("a mesh file was refined: {c:?}"),
    }
    assert!(d.to_json()["mesh"]["skipped"].is_string());
    assert_eq!(d.over_noise(), 0.0);
    assert!(
        d.caution().is_none(),
        "nothing measured, nothing to caution"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
