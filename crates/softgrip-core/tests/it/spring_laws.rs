//! Spring laws beyond the thesis's linear spring (`[model] stiffening`,
//! `compression_ratio`, `prony_g`, `prony_tau`): each reduces to the thesis
//! when off, and each is checked against its analytic behaviour.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::forces::springs;
use softgrip_core::model::{Model, SpringLaw};
use softgrip_core::solver::System;

use crate::support::{rest_within, shipped_scene};

/// The general spring pass under the thesis's law gives the linear pass's
/// forces and blocks to the last bit, on states along a thesis run (the
/// dispatcher takes the linear pass then, so `stiffening = 0` is the thesis
/// result bit for bit).
#[test]
fn the_general_spring_law_at_zero_is_the_thesis_spring_bit_for_bit() {
    let mut scene = Scene::thesis();
    scene.object.edge_length = 0.006;
    let mut sim = Simulation::new(&scene).expect("thesis");
    assert!(sim.model.spring_law.is_linear());
    for steps in [0, 50, 250] {
        sim.run_until(steps as f64 * sim.model.dt).expect("run");
        let n = sim.model.particle_count() + sim.model.fingers.len();
        let pass = |general: bool| {
            let mut force = vec![DVec3::ZERO; n];
            let mut system = System::default();
            system.begin(&sim.model, sim.model.dt);
            if general {
                springs::accumulate_general(&sim.model, &sim.state, &mut force, &mut system);
            } else {
                springs::accumulate(&sim.model, &sim.state, &mut force, &mut system);
            }
            (force, system.diag, system.off, system.kv)
        };
        assert!(pass(false) == pass(true), "after {steps} steps");
    }
    // The scene keys at their defaults change nothing.
    let mut explicit = scene.clone();
    explicit.model.stiffening = 0.0;
    explicit.model.prony_g = 0.0;
    explicit.model.prony_tau = 7.0;
    explicit.model.compression_ratio = 1.0;
    let run = |s: &Scene| {
        let mut sim = Simulation::new(s).expect("sim");
        sim.run_until(0.1).expect("run");
        sim.state.positions
    };
    assert_eq!(run(&scene), run(&explicit));
}

fn light_guide(stiffening: f64) -> Simulation {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = 0.006;
    scene.model.stiffening = stiffening;
    // No spring limits: they stiffen the linear model where it reaches them.
    scene.model.tau_s = None;
    scene.model.tau_c = None;
    Simulation::new(&scene).expect("sim")
}

fn depths(sim: &mut Simulation, loads: &[f64]) -> Vec<f64> {
    let tol = rest_within(1e-5, 10.0);
    loads
        .iter()
        .map(|&load| {
            sim.set_load(0, load);
            sim.settle(tol, |_| {}).expect("rest");
            sim.indentation(0)
        })
        .collect()
}

/// Stiffening leaves the small-load response as it was and makes the
/// force-depth curve steeper at large depth.
#[test]
fn stiffening_makes_the_force_depth_curve_steeper_at_large_depth() {
    let loads = [0.25, 0.5, 8.0, 9.73];
    let linear = depths(&mut light_guide(0.0), &loads);
    let stiff = depths(&mut light_guide(300.0), &loads);
    eprintln!("depths (m): linear {linear:?}, stiffening 300: {stiff:?}");
    let slope = |d: &[f64], a: usize| (loads[a + 1] - loads[a]) / (d[a + 1] - d[a]);
    // How much steeper the curve is at large depth than at small depth.
    let steepening = |d: &[f64]| slope(d, 2) / slope(d, 0);
    let (lin, stf) = (steepening(&linear), steepening(&stiff));
    eprintln!("slope at large over slope at small depth: linear {lin:.3}, stiffening {stf:.3}");
    assert!(
        stf > 1.2 * lin,
        "stiffening steepens the curve at large depth: {stf:.3} against {lin:.3}"
    );
    assert!(
        stiff[3] < 0.9 * linear[3],
        "and indents less: {stiff:?} vs {linear:?}"
    );
    assert!(
        (stiff[0] - linear[0]).abs() < 0.05 * linear[0],
        "while the smallest load indents about as far"
    );
}

/// One spring, one particle hanging from a pinned one: its stretch under a
/// weight and its compression under the same weight upside down follow
/// `F / k` and `F / (ratio k)`.
fn hanging(law: SpringLaw, gravity: f64) -> Simulation {
    let k: f64 = 100.0;
    let m: f64 = 1e-3;
    // Lightly damped: the dashpot in parallel would slow the creep.
    let damping = 0.1 * 2.0 * (k * m).sqrt();
    let mut model = Model::from_particles(
        vec![DVec3::ZERO, DVec3::new(0.0, 0.0, -0.01)],
        vec![m, m],
        vec![true, false],
        &[(0, 1, k, damping)],
        DVec3::new(0.0, 0.0, gravity),
        1e-3,
    );
    model.spring_law = law;
    Simulation::from_model(model)
}

fn stretch(sim: &Simulation) -> f64 {
    sim.state.positions[0].distance(sim.state.positions[1]) - 0.01
}

#[test]
fn compression_and_tension_stiffness_differ_by_the_ratio() {
    let law = SpringLaw {
        compression_ratio: 2.5,
        ..SpringLaw::default()
    };
    let force = 1e-3 * 9.81;
    let mut down = hanging(law, -9.81);
    down.run_until(1.0).expect("run");
    let mut up = hanging(law, 9.81);
    up.run_until(1.0).expect("run");
    assert!(((stretch(&down) - force / 100.0) / (force / 100.0)).abs() < 1e-6);
    assert!(((stretch(&up) + force / 250.0) / (force / 250.0)).abs() < 1e-6);
}

/// Creep: under a constant load a standard linear solid stretches from
/// `F / k` towards `F / ((1 - g) k)` with the retardation time
/// `tau / (1 - g)`.
#[test]
fn a_viscoelastic_spring_creeps_with_the_standard_linear_solid_time_constant() {
    let (g, tau) = (0.5, 0.4);
    let law = SpringLaw {
        prony_g: g,
        prony_tau: tau,
        ..SpringLaw::default()
    };
    let mut sim = hanging(law, -9.81);
    let force = 1e-3 * 9.81;
    let (x0, x_inf) = (force / 100.0, force / ((1.0 - g) * 100.0));
    let retardation = tau / (1.0 - g);
    for t in [0.4, 0.8, 1.6, 2.4] {
        sim.run_until(t).expect("run");
        let x = stretch(&sim);
        let measured = -t / ((x_inf - x) / (x_inf - x0)).ln();
        eprintln!("t {t}: stretch {x:e} m, time constant {measured:.4} s");
        assert!(
            (measured - retardation).abs() < 0.05 * retardation,
            "t = {t} s: creep time constant {measured:.4} s, the SLS gives {retardation:.4} s"
        );
    }
    // Elastic at g = 0: the stretch is F / k at once and stays.
    let mut elastic = hanging(
        SpringLaw {
            prony_tau: tau,
            ..SpringLaw::default()
        },
        -9.81,
    );
    elastic.run_until(2.4).expect("run");
    assert!(((stretch(&elastic) - x0) / x0).abs() < 1e-6);
}

/// Relaxation: a spring held stretched loses `g` of its force with time
/// constant tau.
#[test]
fn a_held_viscoelastic_spring_relaxes() {
    let (g, tau) = (0.3, 0.25);
    let law = SpringLaw {
        prony_g: g,
        prony_tau: tau,
        ..SpringLaw::default()
    };
    let mut model = Model::from_particles(
        vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 0.01)],
        vec![1e-3, 1e-3],
        vec![true, true],
        &[(0, 1, 100.0, 0.0)],
        DVec3::ZERO,
        1e-3,
    );
    model.spring_law = law;
    let mut sim = Simulation::from_model(model);
    // Held 10 % stretched from t = 0.
    sim.state.positions[1].z = 0.011;
    let spring = sim.model.springs[0];
    let force = |sim: &Simulation| {
        let q = sim.state.maxwell[0];
        springs::spring_law(&sim.model, &spring, 0.011, q).force
    };
    let f0 = 100.0 * 0.001;
    let first = force(&sim);
    // The first step's force is the instantaneous one less what the
    // dashpot gives in that step (implicit Euler).
    assert!((first - f0).abs() < 0.01 * f0, "instantaneous {first}");
    for t in [tau, 2.0 * tau, 4.0 * tau] {
        sim.run_until(t).expect("run");
        let expected = f0 * ((1.0 - g) + g * (-t / tau).exp());
        let got = force(&sim);
        assert!(
            (got - expected).abs() < 0.01 * f0,
            "t = {t} s: force {got:.5} N, the SLS gives {expected:.5} N"
        );
    }
}

/// The neo-Hookean elements' Prony term: a block hanging from its top face (nu 0.499, nearly
/// incompressible, so shear carries the sag) creeps under its own weight as a standard linear
/// solid does: from the instant sag (the elastic block's, solved statically) to `1 / (1 - g)`
/// of it, a share `1 - 1/e` of the creep done at `tau / (1 - g)`.
#[test]
fn a_viscoelastic_continuum_creeps_as_a_standard_linear_solid() {
    let (g, tau): (f64, f64) = (0.5, 0.1);
    let scene = |prony: bool| {
        let more = format!(
            "density = 1070.0\nyoung_modulus = 57.6e3\npoisson_ratio = 0.499\n[model]\nelasticity = \"neo-hookean\"\nrayleigh_mass = 40.0\n{}[support]\nkind = \"none\"\n[[fixed]]\nmin = [-1.0, -1.0, {}]\nmax = [1.0, 1.0, 1.0]\n",
            if prony {
                format!("prony_g = {g}\nprony_tau = {tau}\n")
            } else {
                String::new()
            },
            0.06 - 1e-6
        );
        crate::support::cuboid_scene("dt = 1e-3", [0.02, 0.02, 0.06], 0.005, &more)
    };
    let sag = |sim: &Simulation| {
        let bottom: Vec<usize> = (0..sim.model.particle_count())
            .filter(|&i| sim.model.rest_positions[i].z < 1e-9)
            .collect();
        -bottom
            .iter()
            .map(|&i| sim.state.positions[i].z - sim.model.rest_positions[i].z)
            .sum::<f64>()
            / bottom.len() as f64
    };
    let mut elastic = crate::support::simulation(&scene(false), "elastic");
    elastic
        .equilibrium(softgrip_core::equilibrium::StaticOptions::default())
        .expect("equilibrium");
    let instant = sag(&elastic);
    let mut sim = crate::support::simulation(&scene(true), "viscoelastic");
    let creep_time = tau / (1.0 - g);
    let mut at_creep_time = 0.0;
    for step in 1..=2000 {
        sim.step().expect("a step");
        if step == (creep_time / 1e-3).round() as usize {
            at_creep_time = sag(&sim);
        }
    }
    let last = sag(&sim);
    let expected_last = instant / (1.0 - g);
    let share = (at_creep_time - instant) / (expected_last - instant);
    eprintln!(
        "instant {:.4} mm, at tau/(1-g) {:.4} mm ({share:.3} of the creep; SLS 0.632), after 2 s {:.4} mm ({:.3} x the instant; SLS {:.3})",
        instant * 1e3,
        at_creep_time * 1e3,
        last * 1e3,
        last / instant,
        1.0 / (1.0 - g)
    );
    assert!((last / expected_last - 1.0).abs() < 0.03);
    assert!((share - (1.0 - (-1.0f64).exp())).abs() < 0.06);
}
