//! The diagnosis's parts, on residuals whose truth is known: the noise
//! estimate, the significance test, the criterion, where a mismatch is,
//! and which candidates apply to which recordings.

use glam::DVec3;
use softgrip_lab::compare::Residual;
use softgrip_lab::diagnose::{self, Noise};
use softgrip_lab::recording::{MarkerRef, Mode};
use softgrip_lab::synth::Gaussian;

use crate::support;

/// Residuals of `markers` object markers over `samples` samples, x and z
/// observed: a smooth mismatch `trend(marker, sample)` (m) plus Gaussian
/// noise of `sigma`.
fn residuals(
    markers: usize,
    samples: usize,
    sigma: f64,
    trend: impl Fn(usize, usize) -> f64,
) -> Vec<Residual> {
    let mut g = Gaussian::new(3);
    let mut out = Vec::new();
    for s in 0..samples {
        for m in 0..markers {
            let sim = DVec3::new(0.01 * m as f64, 0.0, 0.02);
            let t = trend(m, s);
            out.push(Residual {
                sample: s,
                marker: MarkerRef::Object(m),
                simulated: sim,
                recorded: [
                    Some(sim.x - t + sigma * g.sample()),
                    None,
                    Some(sim.z - t + sigma * g.sample()),
                ],
            });
        }
    }
    out
}

/// Second differences see through a smooth mismatch ten times the noise
/// (1 mm, growing with the square of the load) and give the noise.
#[test]
fn the_noise_estimate_sees_through_a_smooth_mismatch() {
    let sigma = 1e-4;
    for (what, trend) in [
        (
            "none",
            Box::new(|_: usize, _: usize| 0.0) as Box<dyn Fn(usize, usize) -> f64>,
        ),
        (
            "growing with load",
            Box::new(|m: usize, s: usize| {
                1e-3 * (m as f64 + 1.0) / 9.0 * (s as f64 / 30.0).powi(2)
            }),
        ),
    ] {
        let r = residuals(9, 30, sigma, trend);
        let noise = diagnose::estimate_noise(&r);
        assert!(
            (noise.object_m - sigma).abs() < 0.1 * sigma,
            "{what}: estimated {:e} m, true {sigma:e} m",
            noise.object_m
        );
        assert_eq!(noise.object_count, 9 * 2 * 28);
        // No finger markers: the fingers take the objects' level.
        assert_eq!(noise.finger_m, noise.object_m);
    }
}

#[test]
fn chi_square_significance_and_the_criterion() {
    assert!(!diagnose::significant(100.0, 100));
    assert!(!diagnose::significant(140.0, 100), "within 3 sd (42.4)");
    assert!(diagnose::significant(143.0, 100));
    // BIC: a parameter costs ln n; halving the residual with one more
    // parameter on 144 coordinates is worth 144 ln 2 - ln 144.
    let gain = diagnose::bic(50.0, 144, 5) - diagnose::bic(100.0, 144, 4);
    assert!((gain - (-144.0 * 2f64.ln() + 144f64.ln())).abs() < 1e-9);
}

/// A marker pulled off by a millimetre that grows with the load is named,
/// along its axis, and nothing else is.
#[test]
fn a_mismatch_is_located_at_its_marker_and_axis() {
    let sigma = 1e-4;
    let rec = support::thesis_7_loads();
    let markers = rec.markers.len();
    let samples = rec.samples.len();
    let mut r = residuals(markers, samples, sigma, |_, _| 0.0);
    let mut g = Gaussian::new(11);
    for x in &mut r {
        if x.marker == MarkerRef::Object(2) {
            // Simulated 1 mm x load fraction too far along x, only.
            let load = rec.samples[x.sample].load / 9.73;
            x.recorded[0] = Some(x.simulated.x - 1e-3 * load + sigma * g.sample());
        }
    }
    let noise = Noise {
        object_m: sigma,
        finger_m: sigma,
        object_count: 0,
        finger_count: 0,
    };
    let replay = softgrip_lab::replay::Replay {
        attachments: Vec::new(),
        errors: softgrip_lab::compare::errors(&r, 0.05),
        residuals: r,
        volume_errors: Vec::new(),
        largest_strain: [0.0; 2],
        states: Vec::new(),
    };
    let loc = diagnose::locate(&rec, &replay, &noise);
    assert!(loc.significant);
    assert_eq!(loc.markers.len(), 1, "{:?}", loc.markers);
    assert_eq!(loc.markers[0].0, rec.markers[2].name);
    assert_eq!(loc.axes, vec!["x".to_string()]);
    assert_eq!(loc.when, "grows with load");
    // Pure noise: nothing located.
    let quiet = softgrip_lab::replay::Replay {
        residuals: residuals(markers, samples, sigma, |_, _| 0.0),
        ..replay
    };
    let loc = diagnose::locate(&rec, &quiet, &noise);
    assert!(!loc.significant, "chi2 {} on {}", loc.chi2, loc.dof);
    assert!(loc.markers.is_empty());
}

/// Which candidates apply: creep needs time, the table a support, load
/// loss a pressing finger.
#[test]
fn the_catalogue_offers_what_applies() {
    let rec = support::thesis_7_loads();
    assert_eq!(rec.mode, Mode::QuasiStatic);
    let names = |c: &[diagnose::Candidate]| {
        let mut v: Vec<&str> = c.iter().map(|c| c.effect).collect();
        v.dedup();
        v
    };
    let all = diagnose::catalogue(&rec, &rec.scene);
    assert_eq!(
        names(&all),
        vec![
            "table-friction",
            "strain-stiffening",
            "finger-friction",
            "heterogeneous-stiffness",
            "load-loss"
        ]
    );
    assert_eq!(
        all.iter()
            .filter(|c| c.effect == "heterogeneous-stiffness")
            .count(),
        4,
        "one per half"
    );
    let mut timed = rec.clone();
    timed.mode = Mode::TimeSeries;
    let timed_names = names(&diagnose::catalogue(&timed, &rec.scene));
    assert!(timed_names.contains(&"viscoelastic-creep"));
    // Damping changes nothing at rest: offered for time series only, with
    // the scene's ratio inside its range.
    assert!(timed_names.contains(&"damping"));
    assert!(!names(&all).contains(&"damping"));
    let damping = diagnose::catalogue(&timed, &rec.scene)
        .into_iter()
        .find(|c| c.effect == "damping")
        .expect("damping offered");
    let ratio = &damping.params[1];
    assert_eq!(ratio.param.name, "damping_ratio");
    let d = rec.scene.model.damping_ratio;
    assert!(ratio.lower < d && d < ratio.upper && ratio.log);
    // Creep starts with a relaxing share (at g = 0 its time constant moves
    // nothing and the fit cannot leave), and with the long-term modulus
    // E (1 - g) the baseline fitted, so the start changes only how fast.
    let creep = diagnose::catalogue(&timed, &rec.scene)
        .into_iter()
        .find(|c| c.effect == "viscoelastic-creep")
        .expect("creep offered");
    let (g, e) = (creep.scene.model.prony_g, creep.scene.object.young_modulus);
    assert!(g > 0.0 && g < 0.9, "g starts at {g}");
    let relaxed = e * (1.0 - g);
    assert!(
        (relaxed - rec.scene.object.young_modulus).abs() < 1e-9 * relaxed,
        "long-term modulus {relaxed} against the baseline's {}",
        rec.scene.object.young_modulus
    );
    // Its off point is no creep at all: the model it is added to.
    let off_values = creep.off.as_ref().expect("creep has an off point");
    let mut off = creep.scene.clone();
    for (p, v) in creep.params.iter().zip(off_values) {
        off = softgrip_lab::params::set(&off, p.param.name, *v).expect("in range");
    }
    assert!(diagnose::same_model(&off, &rec.scene));
    assert!(!diagnose::same_model(&creep.scene, &rec.scene));
    // The two-term stiffening (soften, then stiffen) is for elements: the
    // lattice has no such law, and every value in its range is a valid
    // scene.
    let two_term = |scene: &softgrip_core::Scene| {
        diagnose::catalogue(&rec, scene)
            .into_iter()
            .find(|c| c.effect == "strain-stiffening" && c.variant == "two-term")
    };
    assert!(two_term(&rec.scene).is_none());
    let mut elements = rec.scene.clone();
    elements.model.elasticity = softgrip_core::scene::Elasticity::NeoHookean;
    let c = two_term(&elements).expect("offered for elements");
    let names_of: Vec<&str> = c.params.iter().map(|p| p.param.name).collect();
    assert_eq!(
        names_of,
        vec!["young_modulus", "stiffening_cubic", "softening"]
    );
    for p in &c.params[1..] {
        for v in [p.lower, p.upper] {
            softgrip_lab::params::set(&c.scene, p.param.name, v).expect("in range");
        }
    }
    let mut free = rec.scene.clone();
    free.support.kind = softgrip_core::scene::SupportKind::None;
    assert!(!names(&diagnose::catalogue(&rec, &free)).contains(&"table-friction"));
    // Locking a baseline parameter leaves it out; an unknown one is an error.
    let base = diagnose::baseline_params(&rec.scene, &["alpha".into()]).expect("params");
    assert!(base.iter().all(|p| p.param.name != "alpha"));
    assert!(diagnose::baseline_params(&rec.scene, &["alfa".into()]).is_err());
}

/// Where the load turns (loading, then unloading) the residual turns too;
/// differences taken across the turn would call that noise. Split at the
/// turn, the estimate is the noise again.
#[test]
fn the_noise_estimate_is_not_fooled_by_a_load_reversal() {
    let sigma = 1e-4;
    // As `softgrip prove` loads: up over 6 samples, down over 2, the
    // mismatch growing to 1 mm at the turn and falling back with the load.
    let loads = [1.5, 3.0, 4.5, 6.0, 7.5, 9.0, 4.5, 1.5];
    let vee = |m: usize, s: usize| 1e-3 * (m as f64 + 1.0) / 9.0 * loads[s] / 9.0;
    let r = residuals(9, 8, sigma, vee);
    let across = diagnose::estimate_noise(&r).object_m;
    // The load turns at sample 5: the runs are 0..=5 and 6..=7, leaving
    // 72 second differences, whose estimate spreads by about 10 %.
    let split = diagnose::estimate_noise_split(&r, &[6]).object_m;
    assert!(
        across > 1.2 * sigma,
        "across the turn the estimate is inflated: {across:e}"
    );
    assert!(
        (split - sigma).abs() < 0.2 * sigma,
        "split at the turn: {split:e} m, true {sigma:e} m"
    );
}

/// Vuong's statistic: two models equally far from the truth score near 0,
/// one closer scores beyond 2 (standard normal under the null), and it is
/// antisymmetric.
#[test]
fn vuong_tells_the_closer_of_two_models() {
    let mut g = Gaussian::new(3);
    let n = 400;
    let noise: Vec<f64> = (0..n).map(|_| g.sample()).collect();
    // a: the truth's residual (noise only); b: noise plus a smooth bias of
    // half a noise level; c: another draw of the same size as a.
    let a = noise.clone();
    let b: Vec<f64> = noise
        .iter()
        .enumerate()
        .map(|(i, e)| e + 0.5 * (i as f64 / n as f64 * 6.0).sin())
        .collect();
    let z = diagnose::vuong(&a, &b).expect("paired");
    assert!(z > 2.0, "the truth against a biased model: z = {z}");
    let back = diagnose::vuong(&b, &a).expect("paired");
    assert!((z + back).abs() < 1e-12, "antisymmetric: {z} and {back}");
    // Two models off by independent noise of the same level: no winner.
    let c: Vec<f64> = (0..n).map(|_| g.sample()).collect();
    let tie = diagnose::vuong(&a, &c).expect("paired");
    assert!(tie.abs() < 2.0, "equally close: z = {tie}");
    assert_eq!(diagnose::vuong(&a, &a[1..]), None, "unpaired");
}

/// Summed per sample first, Vuong's statistic does not count an
/// improvement confined to one sample as systematic, which the statistic
/// over every coordinate does; a bias in every sample it still sees.
#[test]
fn vuong_by_sample_counts_each_sample_once() {
    let sigma = 1e-4;
    let truth = residuals(9, 8, sigma, |_, _| 0.0);
    let noise = Noise {
        object_m: sigma,
        finger_m: sigma,
        object_count: 0,
        finger_count: 0,
    };
    let shifted = |by: &dyn Fn(usize) -> f64| -> Vec<Residual> {
        truth
            .iter()
            .map(|r| Residual {
                simulated: r.simulated + DVec3::new(by(r.sample), 0.0, by(r.sample)),
                ..*r
            })
            .collect()
    };
    // Off by three noise levels in one sample of eight.
    let one = shifted(&|s| if s == 3 { 3.0 * sigma } else { 0.0 });
    let w = |r: &[Residual]| diagnose::weighted_residuals(r, &noise);
    let plain = diagnose::vuong(&w(&truth), &w(&one)).expect("paired");
    let by = diagnose::vuong_by_sample(&truth, &one, &noise).expect("paired");
    assert!(
        plain > 2.0,
        "over every coordinate it looks significant: {plain}"
    );
    assert!(by.abs() < 2.0, "one sample is one observation: {by}");
    // Off by one noise level in every sample.
    let every = shifted(&|_| sigma);
    let by = diagnose::vuong_by_sample(&truth, &every, &noise).expect("paired");
    assert!(by > 2.0, "a bias in every sample: {by}");
    let back = diagnose::vuong_by_sample(&every, &truth, &noise).expect("paired");
    assert!((by + back).abs() < 1e-12, "antisymmetric: {by} and {back}");
    assert_eq!(
        diagnose::vuong_by_sample(&truth, &every[1..], &noise),
        None,
        "unpaired"
    );
}

/// A recording without a finger has no finger noise of its own: the level
/// it borrowed from the object is not reported as measured.
#[test]
fn noise_not_measured_is_not_reported_as_measured() {
    let both = diagnose::Noise {
        object_m: 0.084e-3,
        finger_m: 0.098e-3,
        object_count: 40,
        finger_count: 12,
    };
    assert_eq!(
        both.describe(),
        "0.084 mm on object markers, 0.098 mm on fingers"
    );
    let no_finger = diagnose::Noise {
        finger_m: 0.084e-3,
        finger_count: 0,
        ..both
    };
    assert_eq!(
        no_finger.describe(),
        "0.084 mm on object markers, none measured on fingers"
    );
    // A noise-free recording's estimate sits at the floor: no noise, and
    // nothing to weigh a move against.
    let floor = diagnose::NOISE_FLOOR_M;
    let bare = diagnose::Noise {
        object_m: floor,
        finger_m: floor,
        ..both
    };
    assert_eq!(
        bare.describe(),
        "none (noise-free data) on object markers, none (noise-free data) on fingers"
    );
    assert!(!bare.measured() && both.measured() && no_finger.measured());
}

/// A heterogeneous-stiffness candidate starts with its region at the
/// object's own material, which must be the current model exactly: the
/// diagnosis reuses the current model's replay for that start
/// (`diagnose::same_model`). Stepped side by side, the two stay
/// bit-identical; a region of another material, or a neutral one that
/// overrides another region, is not the same model.
#[test]
fn a_region_of_the_objects_material_changes_nothing() {
    use softgrip_core::step::Simulation;
    let rec = support::thesis_7_loads();
    let halves: Vec<diagnose::Candidate> = diagnose::catalogue(&rec, &rec.scene)
        .into_iter()
        .filter(|c| c.effect == "heterogeneous-stiffness")
        .collect();
    assert_eq!(halves.len(), 4);
    for c in &halves {
        assert!(
            diagnose::same_model(&c.scene, &rec.scene),
            "{} at its start",
            c.variant
        );
    }
    let top = &halves[3].scene;
    let mut plain = Simulation::new(&rec.scene).expect("scene");
    let mut with_region = Simulation::new(top).expect("scene with a region");
    for sim in [&mut plain, &mut with_region] {
        let k = sim.load_finger().expect("a force-controlled finger");
        sim.set_load(k, 9.73);
    }
    for _ in 0..150 {
        plain.step().expect("step");
        with_region.step().expect("step");
    }
    assert!(
        !plain.state.contacts.is_empty(),
        "the finger presses within 150 steps"
    );
    assert_eq!(plain.state.positions, with_region.state.positions);
    assert_eq!(
        plain.state.fingers[0].position,
        with_region.state.fingers[0].position
    );
    // Another material is another model ...
    let mut soft = top.clone();
    soft.regions[0].young_modulus *= 0.5;
    assert!(!diagnose::same_model(&soft, &rec.scene));
    // ... and so is a neutral region over a soft one (the last wins).
    let mut over = soft.clone();
    over.regions.push(top.regions[0].clone());
    assert!(!diagnose::same_model(&over, &soft));
    assert!(!diagnose::same_model(&over, &rec.scene));
}

/// The residual beyond the noise: with the noise estimated from the data
/// (second differences, which a constant offset does not reach), a
/// mismatch of b on x and on z comes out as sqrt(2) b, however large the
/// noise beside it; noise alone comes out near 0, and exactly 0 when the
/// noise given is larger than the residual.
#[test]
fn the_residual_beyond_the_noise_is_the_mismatch_without_the_noise() {
    let sigma = 1e-4;
    let offset = 1e-4;
    let with = residuals(8, 400, sigma, |_, _| offset);
    let noise = diagnose::estimate_noise(&with);
    assert!((noise.object_m / sigma - 1.0).abs() < 0.05, "{noise:?}");
    let beyond = diagnose::rms_beyond_noise(&with, &noise);
    let expected = 2f64.sqrt() * offset;
    // 3200 residuals: the mean square's scatter and the noise estimate's
    // each move the result by about 3 %.
    assert!(
        (beyond / expected - 1.0).abs() < 0.1,
        "{beyond} m beyond the noise, expected {expected}"
    );
    let total = (with
        .iter()
        .map(|r| r.difference().length_squared())
        .sum::<f64>()
        / with.len() as f64)
        .sqrt();
    // The total holds the noise too: sqrt(2 (sigma^2 + b^2)).
    let with_noise = (2.0 * (sigma * sigma + offset * offset)).sqrt();
    assert!(
        (total / with_noise - 1.0).abs() < 0.05,
        "{total} against {with_noise}"
    );

    let alone = residuals(8, 400, sigma, |_, _| 0.0);
    let noise = diagnose::estimate_noise(&alone);
    assert!(diagnose::rms_beyond_noise(&alone, &noise) < 0.3 * expected);
    let louder = Noise {
        object_m: 2.0 * sigma,
        ..noise
    };
    assert_eq!(diagnose::rms_beyond_noise(&alone, &louder), 0.0);
}
