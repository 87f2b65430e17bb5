//! The default CG tolerance is tight enough: over the thesis scene's first
//! 20 steps (the finger dropping in, the fastest part of the run) the state
//! solved at it stays within 1e-4 of an edge of a solve at 1e-10, and a
//! loose tolerance fails the same check.
//!
//! The check runs without friction: stick-slip (the friction cone) and the
//! spring-limit projection are threshold decisions that amplify any rounding,
//! so with them a 1e-8 solve already differs from a 1e-10 one by ~2e-6 m RMS
//! after a few steps (docs/results/accuracy.md, "CG tolerance").

use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::scene::DEFAULT_CG_TOLERANCE;

use crate::support::rms_distance;

/// RMS particle distance and finger distance (m) from a 1e-10 solve, the
/// finger frictionless.
fn difference_from_tight(tolerance: f64, until: f64) -> (f64, f64) {
    difference(tolerance, until, 0.0)
}

fn difference(tolerance: f64, until: f64, friction: f64) -> (f64, f64) {
    let run = |tol: f64| {
        let mut scene = Scene::thesis();
        scene.simulation.cg_tolerance = tol;
        scene.fingers[0].friction = friction;
        let mut sim = Simulation::new(&scene).expect("sim");
        sim.run_until(until).expect("run");
        sim
    };
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| run(tolerance));
        let b = s.spawn(|| run(1e-10));
        (a.join().expect("run"), b.join().expect("run"))
    });
    let particles = rms_distance(&a, &b);
    let finger = a.state.fingers[0]
        .position
        .distance(b.state.fingers[0].position);
    (particles, finger)
}

#[test]
fn default_tolerance_matches_a_tight_solve() {
    let edge = Scene::thesis().object.edge_length;
    let (particles, finger) = difference_from_tight(DEFAULT_CG_TOLERANCE, 0.02);
    println!(
        "cg_tolerance {DEFAULT_CG_TOLERANCE:e} vs 1e-10 at 0.02 s: particles {particles:.2e} m RMS, finger {finger:.2e} m"
    );
    assert!(particles < 1e-4 * edge, "{particles}");
    assert!(finger < 1e-4 * edge, "{finger}");
}

#[test]
fn a_loose_tolerance_is_caught() {
    // The check above can fail: at 1e-3 the solve is visibly off.
    let edge = Scene::thesis().object.edge_length;
    let (particles, finger) = difference_from_tight(1e-3, 0.02);
    println!(
        "cg_tolerance 1e-3 vs 1e-10 at 0.02 s: particles {particles:.2e} m RMS, finger {finger:.2e} m"
    );
    assert!(
        particles > 1e-4 * edge || finger > 1e-4 * edge,
        "{particles} {finger}"
    );
}

/// The table in docs/results/accuracy.md: the error against a 1e-10 solve grows with the
/// tolerance, so the check above measures the solver and not noise.
#[test]
fn error_grows_with_the_tolerance() {
    let tolerances = [1e-8, 1e-6, DEFAULT_CG_TOLERANCE, 1e-4, 1e-3];
    let diffs: Vec<(f64, f64)> = tolerances
        .iter()
        .map(|&t| difference_from_tight(t, 0.02))
        .collect();
    for (t, (p, f)) in tolerances.iter().zip(&diffs) {
        println!("cg_tolerance {t:e}: particles {p:.2e} m RMS, finger {f:.2e} m");
    }
    for pair in diffs.windows(2) {
        assert!(pair[1].0 > pair[0].0, "{diffs:?}");
    }
}
