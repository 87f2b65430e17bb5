//! One set of parameters fitted to several recordings at once (`fit::fit_many`): two small
//! cantilevers made by softgrip itself, the same material with and without a tip mass, fitted
//! back together; the objective is the mean of the recordings' own NRMSE; a parameter one
//! recording's scene cannot take names that recording.

use glam::DVec3;
use softgrip_lab::fit::{FitOptions, fit, fit_many, parse_params, scene_with};
use softgrip_lab::params;
use softgrip_lab::recording::{Mode, Recording, Start};
use softgrip_lab::replay::{ReplayOptions, replay};
use softgrip_lab::synth::{Synthesis, synthesize};

use crate::support::{light_guide_scene, temp_dir, write_recording};

/// A 100 x 30 x 30 mm cantilever clamped at x = -50 mm, 10 mm elements, with `tip_mass` kg
/// hung on its tip's top edge (none at 0).
fn beam_scene(young_modulus: f64, tip_mass: f64) -> String {
    let mut text = format!(
        r#"[simulation]
dt = 1e-3
duration = 0.1
gravity = [0.0, 0.0, -9.81]

[object]
shape = "cuboid"
size = [0.1, 0.03, 0.03]
edge_length = 0.01
density = 1070.0
young_modulus = {young_modulus:?}
poisson_ratio = 0.45

[support]
kind = "none"

[[fixed]]
min = [-0.0505, -0.016, -0.001]
max = [-0.0495, 0.016, 0.031]
"#
    );
    if tip_mass > 0.0 {
        text += &format!(
            "\n[[load]]\nmin = [0.0495, -0.016, 0.0295]\nmax = [0.0505, 0.016, 0.0305]\nmass = {tip_mass:?}\n"
        );
    }
    text
}

/// The beam's sag at rest as a quasi-static recording of one sample: four markers, all axes,
/// 20 um Gaussian noise.
fn beam_recording(
    dir: &std::path::Path,
    young_modulus: f64,
    tip_mass: f64,
    seed: u64,
) -> Recording {
    let scene =
        softgrip_core::Scene::from_toml_str(&beam_scene(young_modulus, tip_mass), "beam").unwrap();
    let spec = Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: vec![(None, 0.0)],
        markers: vec![
            ("tip1".into(), DVec3::new(0.05, 0.0, 0.03)),
            ("tip2".into(), DVec3::new(0.05, -0.015, 0.015)),
            ("tip3".into(), DVec3::new(0.05, 0.015, 0.015)),
            ("mid".into(), DVec3::new(0.0, 0.0, 0.03)),
        ],
        finger: false,
        axes: [true; 3],
        noise: 2e-5,
        seed,
        description: format!("synthetic cantilever, tip mass {tip_mass} kg"),
        distortion: None,
    };
    synthesize(&scene, &spec, dir).unwrap()
}

const TRUE_E: f64 = 200e3;

/// Both beams made with E = 200 kPa, then given a wrong E (350 kPa) to start from.
fn two_beams(name: &str) -> (std::path::PathBuf, Vec<Recording>) {
    let dir = temp_dir(name);
    let mut recordings = vec![
        beam_recording(&dir.join("gravity"), TRUE_E, 0.0, 1),
        beam_recording(&dir.join("loaded"), TRUE_E, 0.05, 2),
    ];
    for r in &mut recordings {
        r.scene = params::set(&r.scene, "young_modulus", 350e3).unwrap();
    }
    (dir, recordings)
}

/// The fit of both recovers E within its stated uncertainty; each recording's NRMSE falls; the
/// objective at the fit is the mean of the two NRMSE `compare` gives at the same point.
#[test]
fn two_recordings_sharing_e_are_fitted_back_together() {
    let (dir, recordings) = two_beams("fit-many");
    let p = parse_params(&["young_modulus=5e4:1e6".into()], &recordings[0].scene).unwrap();
    let f = fit_many(&recordings, &p, FitOptions::default(), &|_, _| {}).unwrap();
    let (e, se) = (f.fitted[0], f.uncertainty.standard_errors[0]);
    println!(
        "fitted E = {e:.1} Pa +/- {se:.1} (true {TRUE_E}); mean NRMSE {:.3e} -> {:.3e}; per recording {:?}; noise {:.2} um; {} points",
        f.before,
        f.after,
        f.recordings
            .iter()
            .map(|r| (r.before.nrmse, r.after.nrmse))
            .collect::<Vec<_>>(),
        1e6 * f.uncertainty.sigma_m,
        f.trials.len()
    );
    assert!(f.converged);
    assert!(se.is_finite() && se > 0.0 && se < 0.02 * TRUE_E, "se {se}");
    assert!((e - TRUE_E).abs() <= 2.0 * se, "{e} +/- {se}");
    // The stacked residuals: 2 recordings x 4 markers x 3 axes.
    assert_eq!(f.uncertainty.residuals, 24);
    // The noise the residuals imply is the noise added (20 um), within what 23 degrees of
    // freedom allow.
    assert!(
        (f.uncertainty.sigma_m / 2e-5 - 1.0).abs() < 0.4,
        "{}",
        f.uncertainty.sigma_m
    );
    for r in &f.recordings {
        assert!(
            r.after.nrmse < 0.2 * r.before.nrmse,
            "{:?}",
            (r.before, r.after)
        );
    }
    // The objective is the mean of what `compare` says at the fitted point.
    let compared: Vec<f64> = recordings
        .iter()
        .map(|r| {
            let scene = scene_with(&r.scene, &p, &f.fitted).unwrap();
            replay(r, &scene, ReplayOptions::default(), |_| {})
                .unwrap()
                .errors
                .nrmse
        })
        .collect();
    let mean = (compared[0] + compared[1]) / 2.0;
    assert!(
        (f.after - mean).abs() <= 1e-9 * mean,
        "{} vs {mean}",
        f.after
    );
    for (r, c) in f.recordings.iter().zip(&compared) {
        assert!((r.after.nrmse - c).abs() <= 1e-9 * c);
    }
    let best = f
        .trials
        .iter()
        .filter_map(|t| t.nrmse.as_ref().ok())
        .fold(f64::INFINITY, |a, b| a.min(*b));
    assert_eq!(best, f.after, "the trials' objective is the mean NRMSE");
    // The report lists each recording's figures.
    let w = softgrip_lab::report::fit_many(&dir.join("report"), &recordings, &f).unwrap();
    let md = std::fs::read_to_string(&w.markdown).unwrap();
    assert!(md.contains("01-gravity/recording.md"), "{md}");
    assert!(md.contains("02-loaded/recording.md"), "{md}");
    assert!(md.contains("| young_modulus (Pa) |"), "{md}");
    assert!(
        dir.join("report/02-loaded/residuals_before_after.png")
            .exists()
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Of one recording, `fit_many` is `fit`: the same points, values and figures.
#[test]
fn one_recording_fit_many_is_fit() {
    let (dir, recordings) = two_beams("fit-many-one");
    let p = parse_params(&["young_modulus=5e4:1e6".into()], &recordings[1].scene).unwrap();
    let options = FitOptions {
        max_evaluations: 14,
        ..FitOptions::default()
    };
    let single = fit(&recordings[1], &p, options, &|_, _| {}).unwrap();
    let many = fit_many(&recordings[1..], &p, options, &|_, _| {}).unwrap();
    assert_eq!(single.fitted, many.fitted);
    assert_eq!(single.trials, many.trials);
    assert_eq!(single.after, many.recordings[0].after);
    assert_eq!(single.after.nrmse, many.after);
    assert_eq!(single.before.nrmse, many.before);
    assert_eq!(single.uncertainty, many.uncertainty);
    assert_eq!(single.sensitivity, many.sensitivity);
    let _ = std::fs::remove_dir_all(dir);
}

/// A parameter one recording's scene cannot take is refused before any simulation, naming that
/// recording; no recording at all is an error too.
#[test]
fn a_parameter_one_scene_cannot_take_names_the_recording() {
    let dir = temp_dir("fit-many-refused");
    let guide = write_recording(
        &dir.join("guide"),
        &light_guide_scene(0.008),
        "quasi-static",
        &[],
        ",1.0,finger,0,0,0.03\n",
    );
    std::fs::create_dir_all(dir.join("beam")).unwrap();
    let beam = write_recording(
        &dir.join("beam"),
        &beam_scene(TRUE_E, 0.0),
        "quasi-static",
        &[("tip1", DVec3::new(0.05, 0.0, 0.03))],
        ",0.0,tip1,0.05,0,0.03\n",
    );
    let p = parse_params(&["friction=0.1:1".into()], &guide.scene).unwrap();
    let e = fit_many(&[guide, beam], &p, FitOptions::default(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("beam/recording.toml"), "{e}");
    assert!(e.contains("friction is a finger parameter"), "{e}");
    assert!(!e.contains("guide/recording.toml"), "{e}");
    let e = fit_many(&[], &p, FitOptions::default(), &|_, _| {}).unwrap_err();
    assert!(e.to_string().contains("at least one recording"), "{e}");
    let _ = std::fs::remove_dir_all(dir);
}
