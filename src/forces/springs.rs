//! Spring and damper forces (thesis eq. 3-4, Alg. 1) and their Jacobians.

use glam::{DMat3, DVec3};

use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Adds every spring's elastic and damping force and its Jacobian blocks.
///
/// The stiffness Jacobian of a spring is
/// `k [u u^T + (1 - l0 / l) (I - u u^T)]`; its transverse term is negative for
/// a compressed spring (`l < l0`), which would make the system indefinite, so
/// it is clamped at zero there (the usual remedy; the force itself is exact).
/// The damping Jacobian is `d u u^T`; the dependence of the damping force on
/// positions (through `u`) is left out of the Jacobian.
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let x = &state.positions;
    let v = &state.velocities;
    let vel = |dof: usize| super::velocity_of(state, dof);
    for (slot, s) in model.springs.iter().enumerate() {
        let (i, j) = (s.i as usize, s.j as usize);
        let delta = x[j] - x[i];
        let l = delta.length();
        if l <= 0.0 {
            continue;
        }
        let u = delta / l;
        let elastic = s.stiffness * (l - s.rest_length); // eq. 3
        let damping = s.damping * u.dot(v[j] - v[i]); // eq. 4
        let f = (elastic + damping) * u;
        force[i] += f;
        force[j] -= f;

        let uu = outer(u, u);
        let transverse = (1.0 - s.rest_length / l).max(0.0);
        let kp = uu * s.stiffness + (DMat3::IDENTITY - uu) * (s.stiffness * transverse);
        let dp = uu * s.damping;
        system.add_diag(i, kp, dp, &vel);
        system.add_diag(j, kp, dp, &vel);
        system.add_off(&model.springs, slot as u32, i, j, -kp, -dp, &vel);
    }
}

/// Elastic energy stored in the springs (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    model
        .springs
        .iter()
        .map(|s| {
            let l = state.positions[s.i as usize].distance(state.positions[s.j as usize]);
            0.5 * s.stiffness * (l - s.rest_length).powi(2)
        })
        .sum()
}
