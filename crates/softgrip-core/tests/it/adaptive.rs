//! Error-controlled time steps (`softgrip_core::step::adaptive`): a hanging viscoelastic block
//! creeps as a standard linear solid by far fewer steps, within the control's tolerance of the
//! fixed-step run, and lands on the times asked for.

use softgrip_core::Simulation;
use softgrip_core::step::adaptive::{Adaptive, AdaptiveOptions};

/// A 20 x 20 x 60 mm continuum block hung from its top, creeping under its weight (g, tau).
fn block(g: f64, tau: f64) -> Simulation {
    hung(g, tau, 40.0)
}

/// The block hung from its top, damped by `rayleigh_mass` (1/s).
fn hung(g: f64, tau: f64, rayleigh_mass: f64) -> Simulation {
    let more = format!(
        "density = 1070.0\nyoung_modulus = 57.6e3\npoisson_ratio = 0.499\n[model]\nelasticity = \"neo-hookean\"\nrayleigh_mass = {rayleigh_mass:?}\nprony_g = {g}\nprony_tau = {tau}\n[support]\nkind = \"none\"\n[[fixed]]\nmin = [-1.0, -1.0, {}]\nmax = [1.0, 1.0, 1.0]\n",
        0.06 - 1e-6
    );
    crate::support::simulation(
        &crate::support::cuboid_scene("dt = 1e-3", [0.02, 0.02, 0.06], 0.005, &more),
        "creeping block",
    )
}

/// The largest distance between the two runs' particles (m).
fn farthest(a: &Simulation, b: &Simulation) -> f64 {
    a.state
        .positions
        .iter()
        .zip(&b.state.positions)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

/// The bottom face's mean sag (m).
fn sag(sim: &Simulation) -> f64 {
    let bottom: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| sim.model.rest_positions[i].z < 1e-9)
        .collect();
    -bottom
        .iter()
        .map(|&i| sim.state.positions[i].z - sim.model.rest_positions[i].z)
        .sum::<f64>()
        / bottom.len() as f64
}

#[test]
fn controlled_steps_follow_the_fixed_step_creep_within_their_tolerance_in_fewer_solves() {
    let (g, tau) = (0.5, 0.3);
    let times: Vec<f64> = (1..=12).map(|k| 0.25 * f64::from(k)).collect();
    let mut fixed = block(g, tau);
    let mut controlled = block(g, tau);
    let tolerance = 2e-6;
    let mut control = Adaptive::new(
        &controlled,
        AdaptiveOptions {
            tolerance,
            ..AdaptiveOptions::default()
        },
    );
    let mut largest = 0.0f64;
    for &t in &times {
        fixed.run_until(t).expect("fixed steps");
        controlled
            .run_until_adaptive(t, &mut control)
            .expect("controlled steps");
        // Landed on the time asked for.
        assert!(
            (controlled.state.time - t).abs() < 1e-9,
            "{} at {t}",
            controlled.state.time
        );
        let d = farthest(&fixed, &controlled);
        largest = largest.max(d);
    }
    let report = control.report;
    eprintln!(
        "{report:?} against {} fixed steps; largest difference {:.2} um, sag {:.4} / {:.4} mm",
        fixed.state.step,
        largest * 1e6,
        sag(&fixed) * 1e3,
        sag(&controlled) * 1e3
    );
    // The global error of a dissipative run stays of the order of the local tolerance; the
    // fixed step's own error (O(dt) per unit time) is of that order too.
    assert!(
        largest < 10.0 * tolerance,
        "the controlled run is {largest:e} m off"
    );
    assert!(
        report.solves * 3 < fixed.state.step as usize,
        "{} solves against {} fixed steps",
        report.solves,
        fixed.state.step
    );
    // And it creeps: a standard linear solid's sag at 3 s is most of 1 / (1 - g) times the
    // instant one (the time constant tau / (1 - g) = 0.6 s: e^-5 left).
    let mut elastic = block(0.0, tau);
    elastic
        .equilibrium(softgrip_core::equilibrium::StaticOptions::default())
        .expect("equilibrium");
    assert!(sag(&controlled) > 1.8 * sag(&elastic));
}

/// Where no step of twice `dt` is within the tolerance (the undamped block's first 0.25 s, still
/// moving, and a tolerance none of its steps meets), the controlled run takes the fixed-step
/// run's steps, and its rejected tries at twice `dt` come ever more rarely: under 1.2 solves per
/// step kept, where a try after every step spent 4.
#[test]
fn where_twice_dt_is_never_within_the_tolerance_the_control_is_the_fixed_step_run_at_its_cost() {
    let mut fixed = hung(0.0, 1.0, 0.0);
    let mut controlled = hung(0.0, 1.0, 0.0);
    let mut control = Adaptive::new(
        &controlled,
        AdaptiveOptions {
            tolerance: 1e-15,
            ..AdaptiveOptions::default()
        },
    );
    fixed.run_until(0.25).expect("fixed steps");
    controlled
        .run_until_adaptive(0.25, &mut control)
        .expect("controlled steps");
    let report = control.report;
    assert_eq!(report.steps, fixed.state.step as usize, "{report:?}");
    assert!(report.rejected > 0, "twice dt was tried: {report:?}");
    let d = farthest(&fixed, &controlled);
    // The same steps: a rejected try changes only the next solve's starting guess (CG starts
    // from the last step's velocity change), so the runs differ by the solver's rounding, far
    // under the 7e-10 m the smallest kept step of twice dt would move a particle by here.
    assert!(d < 1e-11, "{d:e} m from the fixed-step run");
    assert!(
        (report.solves as f64) < 1.2 * report.steps as f64,
        "{} solves for {} steps",
        report.solves,
        report.steps
    );
}

/// A try rewound keeps what its solve took: the nearly incompressible block's nodal-pressure
/// factorization stays in use through the control's tries, its CG iterations within twice the
/// fixed-step run's (sampled every 10 ms for 0.2 s, as a recording is), where a count from
/// before the try had the preconditioner judge the factorization by block Jacobi's and turn it
/// off: ten times as many.
#[test]
fn a_rewound_try_leaves_the_factored_preconditioner_in_use() {
    let mut fixed = hung(0.0, 1.0, 0.0);
    let mut controlled = hung(0.0, 1.0, 0.0);
    let mut control = Adaptive::new(&controlled, AdaptiveOptions::default());
    let (mut by_fixed, mut by_controlled) = (0, 0);
    for k in 1..=20 {
        let t = f64::from(k) * 1e-2;
        fixed.run_until(t).expect("fixed steps");
        controlled
            .run_until_adaptive(t, &mut control)
            .expect("controlled steps");
        by_fixed += fixed.state.stats.cg_iterations;
        by_controlled += controlled.state.stats.cg_iterations;
    }
    assert!(control.report.rejected > 0, "{:?}", control.report);
    assert!(
        by_controlled <= 2 * by_fixed,
        "{by_controlled} CG iterations at the samples against {by_fixed} at fixed steps"
    );
}
