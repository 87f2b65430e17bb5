//! Issue 5: fitting. `--params` parse with their bounds and scales, and bad
//! ones are errors naming the parameter; a synthetic recording is fitted
//! back (slow). The optimisers' own tests are beside them in `optimize`.

use softgrip_lab::fit::parse_params;

#[test]
fn params_parse_with_bounds_and_scales_and_bad_ones_are_errors() {
    let scene = softgrip_core::Scene::thesis();
    let p = parse_params(
        &[
            "young_modulus,tau_c=0.05:0.3".into(),
            "alpha=1e5:1e8:lin".into(),
        ],
        &scene,
    )
    .unwrap();
    assert_eq!(p.len(), 3);
    assert_eq!(p[0].param.name, "young_modulus");
    assert!(p[0].log);
    assert!((p[0].lower - 5.76e3).abs() < 1e-6 && (p[0].upper - 5.76e5).abs() < 1e-3);
    assert_eq!((p[1].lower, p[1].upper, p[1].log), (0.05, 0.3, true));
    assert!(!p[2].log);
    // Log mapping: the middle of 1e5..1e8 is about 3.16e6.
    let a = parse_params(&["alpha=1e5:1e8".into()], &scene).unwrap()[0];
    assert!((a.value(0.5) - 10f64.powf(6.5)).abs() < 1.0);
    assert!((a.unit(1e6) - 1.0 / 3.0).abs() < 1e-12);
    for (bad, says) in [
        (vec!["tau_x"], "unknown parameter \"tau_x\""),
        (vec!["tau_c=0.3:0.1"], "LOW must be below HIGH"),
        (vec!["alpha=0:1e6"], "a log scale needs positive bounds"),
        (vec!["tau_c=0.1:0.2:cubic"], "the scale is log or lin"),
        (vec!["tau_c=0.1"], "bounds are LOW:HIGH"),
        (
            vec!["young_modulus=-5:1e5:lin"],
            "young_modulus = -5: not allowed",
        ),
        (vec!["tau_c", "tau_c=0.1:0.2"], "given twice"),
        (vec!["dt"], "dt has no default bounds; give them"),
        (vec![""], "no parameter to fit"),
    ] {
        let entries: Vec<String> = bad.iter().map(|s| s.to_string()).collect();
        let e = parse_params(&entries, &scene).expect_err(says).to_string();
        assert!(e.contains(says), "{bad:?}: {e}");
    }
}

/// Issue 5, acceptance 1: a recording softgrip made itself from known
/// parameters, with 0.1 mm Gaussian noise, is fitted back from a wrong
/// start: E, alpha, tau_s and tau_c each within three of the standard
/// errors the noise implies, and those errors are stated and finite.
///
/// The experiment is chosen so that all four act (`docs/results/accuracy.md` and the
/// fit report explain): the thesis model without the bulk term (which
/// would mask alpha), loads up to 3 N (above about 4 N that lattice has
/// more than one equilibrium and NRMSE jumps), a stretch limit low enough
/// to be reached, no finger friction; 16 markers on the top face and 5 on
/// the front, all three axes, 7 loads.
#[test]
#[ignore = "slow: a whole fit with its uncertainty"]
fn a_synthetic_recording_is_fitted_back_within_the_noise_implied_uncertainty() {
    use glam::DVec3;
    use softgrip_lab::fit::{FitOptions, Identifiability, fit};
    use softgrip_lab::params;
    use softgrip_lab::recording::{Mode, Start};
    use softgrip_lab::synth::{Synthesis, cuboid_markers, synthesize};

    let text = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/assets/scenes/thesis_cuboid_light_guide.toml"
    ))
    .unwrap()
    .replace("edge_length = 0.004", "edge_length = 0.008");
    let mut scene = softgrip_core::Scene::from_toml_str(&text, "synthetic").unwrap();
    let truth = [
        ("young_modulus", 57.6e3),
        ("alpha", 6e6),
        ("tau_s", 0.03),
        ("tau_c", 0.15),
    ];
    for (name, v) in truth
        .iter()
        .copied()
        .chain([("bulk_modulus", 0.0), ("friction", 0.0)])
    {
        scene = params::set(&scene, name, v).unwrap();
    }
    let spec = Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: (1..=7).map(|k| (None, 3.0 * k as f64 / 7.0)).collect(),
        markers: cuboid_markers(DVec3::new(0.05, 0.05, 0.02), 4, 0.004, 5),
        finger: true,
        axes: [true; 3],
        noise: 1e-4,
        seed: 7,
        description: "synthetic: thesis cuboid, known parameters, 0.1 mm noise".into(),
        distortion: None,
    };
    let dir = std::env::temp_dir().join(format!("softgrip-fit-synth-{}", std::process::id()));
    let mut rec = synthesize(&scene, &spec, &dir).unwrap();
    // At the truth the residuals are the noise alone.
    let at_truth =
        softgrip_lab::replay::replay(&rec, &rec.scene, Default::default(), |_| {}).unwrap();
    let noise_rmse = (3.0f64).sqrt() * 1e-4;
    assert!(
        (at_truth.errors.rmse_m / noise_rmse - 1.0).abs() < 0.1,
        "{:?}",
        at_truth.errors
    );
    // Start far off.
    for (name, v) in [
        ("young_modulus", 80e3),
        ("alpha", 2e6),
        ("tau_s", 0.15),
        ("tau_c", 0.25),
    ] {
        rec.scene = params::set(&rec.scene, name, v).unwrap();
    }
    let p = parse_params(
        &[
            "young_modulus=1e4:3e5".into(),
            "alpha=1e4:1e9".into(),
            "tau_s=0.01:0.3".into(),
            "tau_c=0.05:0.4".into(),
        ],
        &rec.scene,
    )
    .unwrap();
    let f = fit(&rec, &p, FitOptions::default(), &|_, _| {}).unwrap();
    assert!(f.after.nrmse < f.before.nrmse);
    // The global basin: as good as the truth itself (it fits some noise).
    assert!(
        f.after.nrmse <= at_truth.errors.nrmse * 1.0005,
        "{} vs {}",
        f.after.nrmse,
        at_truth.errors.nrmse
    );
    // The noise the residuals imply is the noise that was added.
    assert!(
        (f.uncertainty.sigma_m / 1e-4 - 1.0).abs() < 0.1,
        "{}",
        f.uncertainty.sigma_m
    );
    for (i, (name, v)) in truth.iter().enumerate() {
        assert_eq!(p[i].param.name, *name);
        let se = f.uncertainty.standard_errors[i];
        assert!(se.is_finite() && se < 0.5 * v, "{name}: se {se}");
        assert!(
            (f.fitted[i] - v).abs() <= 3.0 * se,
            "{name}: fitted {} true {v} se {se}",
            f.fitted[i]
        );
        assert_ne!(
            f.sensitivity[i].verdict,
            Identifiability::Unidentifiable,
            "{name}"
        );
    }
    // The report states the uncertainty.
    let report = softgrip_lab::report::fit(&dir.join("report"), &rec, &f).unwrap();
    let md = std::fs::read_to_string(&report.markdown).unwrap();
    assert!(md.contains("standard error"), "{md}");
    assert!(
        md.contains("the noise the fitted residuals imply is s = 0.10"),
        "{md}"
    );
    for image in &report.images {
        assert!(std::fs::metadata(image).unwrap().len() > 1000, "{image:?}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_noise_is_standard_normal_and_seeded() {
    use softgrip_lab::synth::Gaussian;
    let mut g = Gaussian::new(42);
    let x: Vec<f64> = (0..200_000).map(|_| g.sample()).collect();
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let within_1sd = x.iter().filter(|v| v.abs() < 1.0).count() as f64 / n;
    assert!(mean.abs() < 0.01, "{mean}");
    assert!((var - 1.0).abs() < 0.01, "{var}");
    // 68.27 % within one standard deviation.
    assert!((within_1sd - 0.6827).abs() < 0.005, "{within_1sd}");
    let mut again = Gaussian::new(42);
    assert!(x.iter().take(100).all(|v| *v == again.sample()));
    let mut other = Gaussian::new(43);
    assert_ne!(x[0], other.sample());
}
