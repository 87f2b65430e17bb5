//! The linearisation behind the sensitivities (`softgrip_core::step::linear`,
//! `softgrip_core::sensitivity`): it changes nothing in the simulation, the step's results
//! stay the same bit for bit, and for springs alone the assembled static tangent is exact.
//! The sensitivities themselves are checked against whole solves in the lab's tests.

use glam::DVec3;
use softgrip_core::Simulation;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::error::SimError;
use softgrip_core::sensitivity::SensitivityOptions;

use crate::support::{cuboid_scene, shipped_scene, simulation};

/// The thesis cuboid under the light-guide finger at 8 mm edges, with its contact friction.
fn pressed() -> Simulation {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = 0.008;
    let mut sim = Simulation::new(&scene).expect("sim");
    sim.set_load(0, 2.0);
    sim
}

#[test]
fn the_linearisation_changes_nothing_and_steps_stay_the_same_bit_for_bit() {
    let mut a = pressed();
    for _ in 0..30 {
        a.step().expect("step");
    }
    let mut b = a.clone();
    let before = b.state.clone();
    let force = b.free_force();
    let y = b.solve_tangent(&force, 20_000).expect("tangent");
    assert!(y.iter().any(|v| *v != DVec3::ZERO));
    // Away from an equilibrium the sensitivities refuse, and change nothing either.
    let e = b.sensitivity(&[], SensitivityOptions::default());
    assert!(matches!(e, Err(SimError::NoSensitivity { .. })), "{e:?}");
    assert_eq!(b.state, before);
    for _ in 0..30 {
        a.step().expect("step");
        b.step().expect("step");
    }
    assert_eq!(a.state, b.state);
}

#[test]
fn the_free_force_vanishes_at_an_equilibrium() {
    let mut sim = pressed();
    let mut model = (*sim.model).clone();
    model.cg_tolerance = 1e-12;
    sim.model = std::sync::Arc::new(model);
    let options = StaticOptions {
        tolerance: 1e-10,
        move_tolerance: 1e-12,
        ..StaticOptions::default()
    };
    let report = sim.equilibrium(options).expect("equilibrium");
    let force = sim.free_force();
    let norm = force.iter().map(|f| f.length_squared()).sum::<f64>().sqrt();
    eprintln!("{report:?}: free force {norm:.3e} N");
    assert!(norm <= 1e-10 * report.load_scale, "{norm:e}");
    // The static solver's residual is this force's norm (no guide friction here).
    assert!(
        (norm - report.residual).abs() <= 1e-9 * norm,
        "{norm:e} {report:?}"
    );
}

#[test]
fn for_springs_alone_the_assembled_static_tangent_is_exact() {
    // A block on its fixed bottom, sagging under its weight: no volume terms and no contact,
    // so every force is a spring's, whose exact tangent (compressed springs' negative
    // transverse terms kept) the step assembles.
    let more = "young_modulus = 20e3\n[model]\nalpha = 0.0\n[support]\nkind = \"fixed-bottom\"\n";
    let text = cuboid_scene("cg_tolerance = 1e-12", [0.03, 0.02, 0.04], 0.005, more);
    let mut sim = simulation(&text, "sagging block");
    let options = StaticOptions {
        tolerance: 1e-10,
        ..StaticOptions::default()
    };
    sim.equilibrium(options).expect("equilibrium");
    // Any load on the free particles: here a twist about the vertical axis.
    let g: Vec<DVec3> = sim
        .state
        .positions
        .iter()
        .zip(&sim.model.fixed)
        .map(|(x, &fixed)| {
            if fixed {
                DVec3::ZERO
            } else {
                DVec3::new(-x.y, x.x, 0.0)
            }
        })
        .collect();
    let y = sim.solve_tangent(&g, 20_000).expect("tangent");
    // -df/dx y by a central difference of the force.
    let h = 1e-5 * sim.model.edge_length / y.iter().map(|v| v.length()).fold(0.0, f64::max);
    let force_at = |scale: f64| {
        let mut s = sim.clone();
        for (x, d) in s.state.positions.iter_mut().zip(&y) {
            *x += scale * *d;
        }
        s.free_force()
    };
    let (ahead, behind) = (force_at(h), force_at(-h));
    let error = (0..g.len())
        .map(|i| ((behind[i] - ahead[i]) / (2.0 * h) - g[i]).length())
        .fold(0.0, f64::max);
    let scale = g.iter().map(|v| v.length()).fold(0.0, f64::max);
    eprintln!("largest error of -df/dx y against g: {:.3e}", error / scale);
    assert!(error <= 1e-6 * scale, "{error:e} against {scale:e}");
}
