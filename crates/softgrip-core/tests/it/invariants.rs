//! Acceptance 2 and 8: momentum of a free object, energy decay with damping,
//! and bit-identical reruns.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;

use crate::support::{WEIGHTLESS_EXACT, free_block as free_block_text, simulation};

fn free_block(alpha: f64, limits: bool, rigid: bool) -> Simulation {
    let limits = if limits {
        "tau_s = 0.16\ntau_c = 0.155"
    } else {
        ""
    };
    let text = free_block_text(WEIGHTLESS_EXACT, &format!("alpha = {alpha}\n{limits}"));
    let mut sim = simulation(&text, "free block");
    // A pure strain rate (internal motion), plus a drift and a spin when `rigid`.
    for (v, x) in sim
        .state
        .velocities
        .iter_mut()
        .zip(&sim.model.rest_positions)
    {
        let strain_rate = DVec3::new(3.0 * x.x, -3.0 * x.y, 0.0);
        let rigid_motion = DVec3::new(0.01, -0.02, 0.005) + DVec3::new(0.0, 0.0, 2.0).cross(*x);
        *v = strain_rate + if rigid { rigid_motion } else { DVec3::ZERO };
    }
    sim
}

#[test]
fn free_object_conserves_linear_momentum() {
    let mut sim = free_block(6e6, true, true);
    let p0 = sim.state.momentum(&sim.model);
    for _ in 0..300 {
        sim.step().expect("step");
    }
    let p = sim.state.momentum(&sim.model);
    let rel = (p - p0).length() / p0.length();
    assert!(rel < 1e-9, "momentum drift {rel:e}: {p0:?} -> {p:?}");
}

#[test]
fn damped_free_object_never_gains_energy() {
    // Springs and dampers only (the volume force of eq. 11 has no potential).
    let mut sim = free_block(0.0, false, false);
    sim.step().expect("step");
    let first = sim.state.stats.energy;
    let mut last = first;
    for i in 0..400 {
        sim.step().expect("step");
        let e = sim.state.stats.energy;
        assert!(
            e <= last + 1e-12 * first,
            "energy rose at step {i}: {last:e} -> {e:e}"
        );
        last = e;
    }
    // The dampers took a real share of the energy of the shear motion.
    assert!(last < 0.5 * first, "energy {first:e} -> {last:e}");
}

#[test]
fn same_scene_twice_is_bit_identical() {
    let run = || {
        let mut scene = Scene::thesis();
        scene.object.edge_length = 0.005;
        let mut sim = Simulation::new(&scene).expect("sim");
        for _ in 0..150 {
            sim.step().expect("step");
        }
        sim.state
    };
    let (a, b) = (run(), run());
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.velocities, b.velocities);
    assert_eq!(a.fingers, b.fingers);
    assert_eq!(a.contacts, b.contacts);
}
