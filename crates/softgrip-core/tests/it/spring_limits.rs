//! Acceptance 6: after the projection of Alg. 3 no spring is outside
//! [(1 - tau_c) l0, (1 + tau_s) l0] by more than the documented tolerance
//! (docs/results/accuracy.md, "Spring limits"):
//! - with the default limit springs, by more than `PROJECTION_BAND` (1e-2 of
//!   its rest length) at any step, and by more than 1e-3 once at rest: the
//!   limit springs hold the limit, the projection caps fast transients;
//! - with `constraint_tolerance = 1e-3`, by more than 1e-3 at every step;
//! - with the projection alone (the thesis's Alg. 3, `limit_stiffness = 0`)
//!   on Fig. 5 only with `constraint_tolerance`, as ten sweeps are not
//!   enough there.

use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::step::constraints::{PROJECTION_BAND, max_violation};

use crate::support::shipped_scene;

const TOLERANCE: f64 = 1e-3;

fn max_stretch(sim: &Simulation) -> f64 {
    sim.model
        .springs
        .iter()
        .map(|s| {
            sim.state.positions[s.i as usize].distance(sim.state.positions[s.j as usize])
                / s.rest_length
        })
        .fold(0.0, f64::max)
}

/// Steps `scene` 500 times; after each projection no spring is beyond its
/// limits by more than `bound`. Returns the worst violation and the one at
/// the end.
fn assert_within_limits_for_500_steps(scene: &Scene, bound: f64) -> (f64, f64) {
    let mut sim = Simulation::new(scene).expect("sim");
    let mut worst: f64 = 0.0;
    for _ in 0..500 {
        sim.step().expect("step");
        let violation = sim.state.stats.limit_violation;
        worst = worst.max(violation);
        assert!(
            violation <= bound,
            "violation {violation} at t = {}",
            sim.state.time
        );
        // The reported figure is the true one, not relative to the band.
        assert_eq!(violation, max_violation(&sim.model, &sim.state.positions));
    }
    (worst, sim.state.stats.limit_violation)
}

/// The default (limit springs) within the band at every step and within
/// the tolerance at the end; with `constraint_tolerance` within the
/// tolerance at every step.
fn assert_within_limits(scene: &Scene) {
    // The band's edge itself, plus rounding.
    let band = PROJECTION_BAND * (1.0 + 1e-9);
    let (worst, end) = assert_within_limits_for_500_steps(scene, band);
    assert!(end <= TOLERANCE, "violation {end} at the end");
    let mut strict = scene.clone();
    strict.model.constraint_tolerance = Some(TOLERANCE);
    let (strict_worst, _) = assert_within_limits_for_500_steps(&strict, TOLERANCE);
    println!(
        "worst violation over 500 steps {worst:.2e}, at the end {end:.2e}; with constraint_tolerance {strict_worst:.2e}"
    );
}

#[test]
#[ignore = "slow: a long settle"]
fn hung_object_springs_stay_within_tau_s() {
    let scene = shipped_scene("hang_two_corners.toml");
    let tau_s = scene.model.tau_s.expect("tau_s set");

    // Without the limit the corner springs stretch well past it ...
    let mut free = scene.clone();
    free.model.tau_s = None;
    let mut sim = Simulation::new(&free).expect("sim");
    sim.run_until(0.5).expect("run");
    let unlimited = max_stretch(&sim);
    assert!(
        unlimited > 1.0 + 1.5 * tau_s,
        "the scene must exercise the limit: max stretch {unlimited}"
    );

    // ... with it (the default: limit springs, then the projection), no
    // spring is beyond it by more than the band at any step, nor by more
    // than the tolerance at the end; with the tolerance, at any step.
    assert_within_limits(&scene);

    // The projection alone (Alg. 3) pulls them back too, but its Jacobi
    // iterations converge slowly on this chain of corner springs: the
    // remaining violation falls as the iterations rise (figures in docs/results/accuracy.md).
    let mut scene = scene.clone();
    scene.model.limit_stiffness = 0.0;
    let worst = |iterations: usize| {
        let mut s = scene.clone();
        s.model.constraint_iterations = iterations;
        let mut sim = Simulation::new(&s).expect("sim");
        let mut worst: f64 = 0.0;
        for _ in 0..500 {
            sim.step().expect("step");
            worst = worst.max(sim.state.stats.limit_violation);
        }
        worst
    };
    let (ten, twenty, forty) = (worst(10), worst(20), worst(40));
    println!(
        "worst violation over 500 steps: {ten:.2e} (10 iterations), {twenty:.2e} (20), {forty:.2e} (40); unlimited stretch {unlimited:.3}"
    );
    assert!(
        ten < 0.5 * (unlimited - 1.0 - tau_s),
        "10 iterations: {ten}"
    );
    assert!(
        forty < 0.5 * ten,
        "10 iterations {ten}, 40 iterations {forty}"
    );

    // With the tolerance the projection keeps sweeping until it holds.
    let mut s = scene.clone();
    s.model.constraint_tolerance = Some(TOLERANCE);
    let mut sim = Simulation::new(&s).expect("sim");
    let (mut most_sweeps, mut total_sweeps) = (0, 0);
    for _ in 0..500 {
        sim.step().expect("step");
        let st = &sim.state.stats;
        assert!(
            st.limit_violation <= TOLERANCE,
            "violation {} after {} sweeps at t = {}",
            st.limit_violation,
            st.projection_sweeps,
            sim.state.time
        );
        most_sweeps = most_sweeps.max(st.projection_sweeps);
        total_sweeps += st.projection_sweeps;
    }
    println!(
        "constraint_tolerance = 1e-3: at most {most_sweeps} sweeps in a step, {:.1} on average",
        total_sweeps as f64 / 500.0
    );
    // The tolerance costs sweeps beyond the thesis's ten only where needed.
    assert!(most_sweeps > 10, "{most_sweeps}");
}

#[test]
fn pulled_object_springs_stay_within_tau_c_and_tau_s() {
    let scene = shipped_scene("fixed_top_pull_bottom.toml");
    assert_within_limits(&scene);
}

/// Under the thesis's finger, tau_c limits the indentation, as the thesis's
/// fit of tau_c relies on (its Fig. 19-20: the depth grows with tau_c), and
/// at rest no spring is beyond its limits.
#[test]
#[ignore = "slow: a long settle"]
fn tau_c_limits_the_indentation_under_a_finger() {
    let run = |tau_c: f64| {
        let mut scene = Scene::thesis();
        scene.model.tau_c = Some(tau_c);
        let mut sim = Simulation::new(&scene).expect("sim");
        sim.run_until(1.0).expect("run");
        (sim.indentation(0), sim.state.stats.limit_violation)
    };
    let results: Vec<(f64, f64)> = std::thread::scope(|s| {
        let runs: Vec<_> = [0.10, 0.155, 0.25]
            .into_iter()
            .map(|t| s.spawn(move || run(t)))
            .collect();
        runs.into_iter().map(|h| h.join().expect("run")).collect()
    });
    println!("tau_c 0.10, 0.155, 0.25: (indentation m, violation) {results:?}");
    assert!(
        results[0].0 < results[1].0 && results[1].0 < results[2].0,
        "{results:?}"
    );
    for (_, violation) in &results {
        assert!(*violation <= TOLERANCE, "{results:?}");
    }
}

/// The limit springs hold the limit inside the implicit step and the
/// projection only caps what gets past them, so the two do not pull against
/// each other: the built-in scene comes truly to rest, with no spring beyond
/// its limits. (The band is what lets the 1.6 mm mesh come to rest; that
/// run is too long for the test suite: docs/results/accuracy.md, "Spring limits".)
#[test]
fn limit_springs_and_projection_let_the_built_in_scene_come_to_rest() {
    let mut sim = Simulation::new(&Scene::thesis()).expect("sim");
    sim.run_until(1.4).expect("run");
    let mut fastest: f64 = 0.0;
    for _ in 0..100 {
        sim.step().expect("step");
        fastest = fastest.max(sim.state.stats.max_speed);
    }
    let violation = sim.state.stats.limit_violation;
    println!("top speed over 1.4-1.5 s {fastest:.2e} m/s, violation {violation:.2e}");
    // Before (limit springs 0.2 % before the limit, projection to the
    // limit itself) the particles under the finger jittered at ~1e-6 m/s.
    assert!(fastest < 1e-7, "{fastest}");
    assert!(violation <= TOLERANCE, "{violation}");
}
