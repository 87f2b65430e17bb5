//! Acceptance 6: after the projection of Alg. 3 no spring is outside
//! [(1 - tau_c) l0, (1 + tau_s) l0] by more than the documented tolerance,
//! 1e-3 of its rest length: on Fig. 6, Fig. 5 and under the thesis's finger
//! with the default limit springs; with the projection alone (the thesis's
//! Alg. 3, `limit_stiffness = 0`) on Fig. 5 only with `constraint_tolerance`,
//! as ten sweeps are not enough there (ACCURACY.md).

use softgrip::{Scene, Simulation};

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
/// limits by more than the tolerance.
fn assert_within_limits_for_500_steps(scene: &Scene) {
    let mut sim = Simulation::new(scene).expect("sim");
    for _ in 0..500 {
        sim.step().expect("step");
        assert!(
            sim.state.stats.limit_violation <= TOLERANCE,
            "violation {} at t = {}",
            sim.state.stats.limit_violation,
            sim.state.time
        );
    }
}

#[test]
fn hung_object_springs_stay_within_tau_s() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/hang_two_corners.toml"
    );
    let scene = Scene::load(std::path::Path::new(path)).expect("scene");
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
    // spring is beyond it at any step.
    assert_within_limits_for_500_steps(&scene);

    // The projection alone (Alg. 3) pulls them back too, but its Jacobi
    // iterations converge slowly on this chain of corner springs: the
    // remaining violation falls as the iterations rise (figures in ACCURACY.md).
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
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/fixed_top_pull_bottom.toml"
    );
    let scene = Scene::load(std::path::Path::new(path)).expect("scene");
    assert_within_limits_for_500_steps(&scene);
}

/// Under the thesis's finger, tau_c limits the indentation, as the thesis's
/// fit of tau_c relies on (its Fig. 19-20: the depth grows with tau_c), and
/// at rest no spring is beyond its limits.
#[test]
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
