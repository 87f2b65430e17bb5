//! Acceptance 2 and 8: momentum of a free object, energy decay with damping,
//! and bit-identical reruns.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;

use crate::support::{WEIGHTLESS_EXACT, cuboid_scene, free_block as free_block_text, simulation};

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

/// A viscoelastic cantilever swinging under its weight: its energy, the Maxwell arms' share
/// included, never rises, and the divergence watch lets it swing (it stopped such a beam while
/// the arms' energy was left out: an arm giving back what it stored read as energy from nowhere).
#[test]
fn a_swinging_viscoelastic_cantilever_never_gains_energy() {
    // About 17 Hz (a 60-step period), the relaxation 1 s: the arms store and give back.
    let text = cuboid_scene(
        "dt = 1e-3\ngravity = [0.0, 0.0, -9.81]",
        [0.06, 0.01, 0.01],
        0.005,
        "young_modulus = 1e5\ndensity = 1000.0\npoisson_ratio = 0.45\n\
         [model]\nelasticity = \"neo-hookean\"\nprony_g = 0.5\nprony_tau = 1.0\n\
         [support]\nkind = \"none\"\n\
         [[fixed]]\nmin = [-0.0305, -0.006, -0.001]\nmax = [-0.0295, 0.006, 0.011]\n",
    );
    let mut sim = simulation(&text, "viscoelastic cantilever");
    sim.step().expect("step");
    let first = sim.state.stats.energy;
    let mut last = first;
    // Kinetic energy's peak over the first and the last 150 steps.
    let mut peaks = [0.0f64; 2];
    for i in 0..600 {
        sim.step()
            .expect("a swinging viscoelastic beam is no divergence");
        let e = sim.state.stats.energy;
        assert!(
            e <= last + 1e-9 * first.abs(),
            "energy rose at step {i}: {last:e} -> {e:e}"
        );
        last = e;
        let slot = match i {
            0..150 => 0,
            450.. => 1,
            _ => continue,
        };
        peaks[slot] = peaks[slot].max(sim.state.stats.kinetic_energy);
    }
    // Still swinging at the end: the arms store and give back, not only damp.
    assert!(
        peaks[1] > 0.1 * peaks[0],
        "kinetic energy's peaks {peaks:?}"
    );
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
