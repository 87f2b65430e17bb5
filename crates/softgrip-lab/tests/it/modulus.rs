//! Issue 5: Young's modulus from compression recordings (thesis eq.
//! 49-50): exact on synthetic curves, and on the Ecoflex recordings
//! consistent with the moduli the database publishes.

use std::path::Path;

use softgrip_lab::modulus::{LINEAR_TOLERANCE, fit_curve, from_recording};
use softgrip_lab::recording::Recording;

#[test]
fn a_straight_curve_gives_its_slope_and_a_toe_does_not_change_it() {
    // 80 kPa, straight from the origin.
    let e = 80e3;
    let mut curve = vec![(0.0, 0.0)];
    curve.extend((1..=10).map(|k| {
        let s = 0.01 * k as f64;
        (s, e * s)
    }));
    let fit = fit_curve(&curve).expect("fit");
    assert!((fit.slope - e).abs() < 1e-6 * e);
    assert!(fit.intercept.abs() < 1e-6);
    assert!((fit.r_squared - 1.0).abs() < 1e-12);
    assert_eq!(fit.points, 11, "all of a straight curve is linear");
    let (lo, hi) = fit.slope_range;
    assert!((lo - e).abs() < 1e-6 * e && (hi - e).abs() < 1e-6 * e);
}

#[test]
fn the_linear_range_ends_where_the_curve_stiffens() {
    // Linear to 10 % strain, then stiffening quadratically.
    let e = 100e3;
    let stress = |s: f64| {
        if s <= 0.1 {
            e * s
        } else {
            e * s + 3.0 * e * (s - 0.1) * (s - 0.1) / 0.01
        }
    };
    let mut curve = vec![(0.0, 0.0)];
    curve.extend((1..=30).map(|k| {
        let s = 0.01 * k as f64;
        (s, stress(s))
    }));
    let fit = fit_curve(&curve).expect("fit");
    let (slope, points) = (fit.slope, fit.points);
    assert!((slope - e).abs() < 1e-6 * e, "{slope}");
    let last = curve[points - 1].0;
    // The first segment past 10 % that is 10 % steeper than the line ends it.
    let next = (curve[points].1 - curve[points - 1].1) / (curve[points].0 - curve[points - 1].0);
    assert!(next > (1.0 + LINEAR_TOLERANCE) * e);
    assert!((0.1..0.13).contains(&last), "stops at {last}");
}

/// The database's moduli (Dawood et al.; assets/recordings/README.md) and
/// the spread of the 0-5 % linear fits over its 10 tests per material.
#[test]
fn the_ecoflex_recordings_give_the_database_moduli() {
    for (case, published, spread) in [
        ("EF30_0T_A1", 103.46e3, 3.9e3),
        ("EF10_0T_A1", 56.27e3, 2.5e3),
    ] {
        let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("assets/recordings/ecoflex_compression")
            .join(case)
            .join("recording.toml");
        let r = Recording::load(&path).expect("recording");
        let fit = from_recording(&r).expect("fit");
        let e = fit.young_modulus;
        assert!(
            (e - published).abs() < 2.0 * spread,
            "{case}: E = {:.1} kPa, published {:.1} +/- {:.1} kPa",
            e / 1e3,
            published / 1e3,
            spread / 1e3
        );
        // Small strain: the fitted range stays within 5 % strain.
        assert!(fit.strain_range.1 <= 0.05, "{:?}", fit.strain_range);
        assert!(fit.r_squared > 0.99);
    }
}

/// What `docs/results/diagnosis-history.md` reads in the Ecoflex diagnoses: against
/// an incompressible neo-Hookean solid of the database's small-strain
/// modulus in uniaxial stress (nominal stress `mu (l - 1 / l^2)`, `mu = E /
/// 3`), each recording's nominal stress falls below it through the middle
/// levels and rises far above it at the last: it softens, then stiffens,
/// which no one-term stiffening (it only grows with strain) follows.
/// `cargo test -p softgrip-lab modulus::the_ecoflex_curves -- --nocapture` prints the ratios.
#[test]
fn the_ecoflex_curves_soften_then_stiffen_against_neo_hookean() {
    // The cylinders: D 50 mm, H 30 mm; the plate's z is 30 mm less the
    // compression. The published small-strain moduli (README, Recordings).
    for (name, modulus) in [("EF30_0T_A1", 103.46e3), ("EF10_0T_A1", 56.27e3)] {
        let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(format!(
            "assets/recordings/ecoflex_compression/{name}/diagnosis/recording.toml"
        ));
        let r = Recording::load(&path).expect("recording");
        let area = std::f64::consts::PI * 0.025 * 0.025;
        let mu = modulus / 3.0;
        let ratios: Vec<(f64, f64)> = r
            .samples
            .iter()
            .map(|s| {
                let z = s.observations[0].position[2].expect("the plate's z");
                let l = z / 0.03;
                (1.0 - l, (s.load / area) / (mu * (1.0 / (l * l) - l)))
            })
            .collect();
        eprintln!(
            "{name}: strain and stress over neo-Hookean {:?}",
            ratios
                .iter()
                .map(|(e, q)| format!("{:.0} % {q:.2}", 100.0 * e))
                .collect::<Vec<_>>()
        );
        let (at, lowest) = ratios
            .iter()
            .enumerate()
            .map(|(i, (_, q))| (i, *q))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("levels");
        let last = ratios.last().expect("levels").1;
        assert!(
            at > 0 && at + 1 < ratios.len() && lowest < 0.9,
            "{name}: the lowest ratio {lowest:.2} is at level {at}, not below 0.9 in the middle"
        );
        assert!(
            last > 1.2,
            "{name}: the last level's ratio is {last:.2}, not above 1.2"
        );
    }
}
