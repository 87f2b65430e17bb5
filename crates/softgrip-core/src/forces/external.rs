//! Gravity (thesis eq. 5), `[[load]]` forces, and the forces that drive the
//! fingers.

use glam::{DMat3, DVec3};

use crate::model::{AxisDrive, Model};
use crate::solver::System;
use crate::state::State;

pub use crate::model::GUIDE_REST_SPEED;

/// Adds gravity and the constant loads, and each finger's drive: its applied force, its guide's
/// damping and Coulomb friction, with their Jacobians.
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let n = model.particle_count();
    for (f, c) in force.iter_mut().zip(&model.constant_force) {
        *f += *c;
    }
    let vel = |dof: usize| super::velocity_of(state, dof);
    for (k, (finger, fs)) in model.fingers.iter().zip(&state.fingers).enumerate() {
        force[n + k] += finger.driving_force(fs.applied_force);
        let axes = DVec3::from_array(
            finger
                .drive
                .map(|d| if d == AxisDrive::Force { 1.0 } else { 0.0 }),
        );
        // A mass-less finger moves against the guide's damping on its force axes.
        let guide = finger.guide_damping(fs.applied_force);
        if guide > 0.0 {
            let c = DMat3::from_diagonal(axes * guide);
            force[n + k] -= c * fs.velocity;
            system.add_diag(n + k, DMat3::ZERO, c, &vel);
        }
        // Coulomb friction in the guide: `F_g` against the velocity, as a
        // damper `F_g / |v|` at the step's start velocity (implicit, so it
        // stops the finger and never reverses it; held still it is a damper
        // of `F_g / GUIDE_REST_SPEED`, which holds it while the forces on it
        // are smaller than `F_g`).
        if finger.guide_friction > 0.0 && fs.held.is_none() {
            let v = fs.velocity * axes;
            let d = finger.guide_friction / v.length().max(model.guide_rest_speed);
            force[n + k] -= d * v;
            system.add_diag(n + k, DMat3::ZERO, DMat3::from_diagonal(axes * d), &vel);
        }
    }
}

/// Potential energy of the constant forces and the applied finger forces (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    let object: f64 = model
        .constant_force
        .iter()
        .zip(&state.positions)
        .map(|(f, x)| -f.dot(*x))
        .sum();
    let fingers: f64 = model
        .fingers
        .iter()
        .zip(&state.fingers)
        .map(|(f, s)| -f.driving_force(s.applied_force).dot(s.position))
        .sum();
    object + fingers
}
