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
///
/// Limit springs (`[model] limit_stiffness`, a softgrip extension): a spring
/// within [`LIMIT_MARGIN`] of its tau_s / tau_c limit gets a second spring,
/// `limit_stiffness` times stiffer, whose rest length is that point. The
/// limits are then met inside the implicit step, where a finger pressing the
/// object feels them (the thesis's fitted tau_c limits the indentation), and
/// the projection of Alg. 3 after the step has little or nothing left to do.
/// Starting the limit spring just before the limit keeps its equilibrium
/// inside the limit, so the projection and the limit spring do not pull
/// against each other (ARCHITECTURE.md, choice 5).
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let x = &state.positions;
    let v = &state.velocities;
    let dt = system.dt();
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
        let mut kp = uu * s.stiffness + (DMat3::IDENTITY - uu) * (s.stiffness * transverse);
        if let Some((start, k_lim)) = limit_spring(model, s, l) {
            let f = k_lim * (l - start) * u;
            force[i] += f;
            force[j] -= f;
            let t = (1.0 - start / l).max(0.0);
            kp += uu * k_lim + (DMat3::IDENTITY - uu) * (k_lim * t);
        }
        // Blocks (i, i) and (j, j) get +W, block (i, j) = (spring.i, spring.j)
        // gets -W, with W = dt^2 Kp + dt Dp; `Kp v` is Kp (v_i - v_j) at i.
        let w = kp * (dt * dt) + uu * (s.damping * dt);
        system.diag[i] += w;
        system.diag[j] += w;
        system.off[slot] -= w;
        let kv = kp * (v[i] - v[j]);
        system.kv[i] += kv;
        system.kv[j] -= kv;
    }
}

/// Where a limit spring starts, as a fraction of the rest length before the
/// tau_s / tau_c limit. At 0.2 % the limit springs let the springs of the
/// 1.6 mm thesis mesh settle 1.6e-3 beyond tau_c (the force per spring over
/// the limit stiffness is 3.6e-3 of l0 there); at 0.5 % they settle inside
/// on every mesh of ACCURACY.md's convergence table.
pub const LIMIT_MARGIN: f64 = 0.005;

/// The rest length and stiffness of the limit spring acting on spring `s` at
/// length `l`, if any.
#[inline]
fn limit_spring(model: &Model, s: &crate::model::Spring, l: f64) -> Option<(f64, f64)> {
    if model.limit_stiffness == 0.0 {
        return None;
    }
    let k = model.limit_stiffness * s.stiffness;
    if let Some(t) = model.tau_s {
        let start = (1.0 + t - LIMIT_MARGIN) * s.rest_length;
        if l > start {
            return Some((start, k));
        }
    }
    if let Some(t) = model.tau_c {
        let start = (1.0 - t + LIMIT_MARGIN) * s.rest_length;
        if l < start {
            return Some((start, k));
        }
    }
    None
}

/// Elastic energy stored in the springs and their limit springs (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    model
        .springs
        .iter()
        .map(|s| {
            let l = state.positions[s.i as usize].distance(state.positions[s.j as usize]);
            let limit = limit_spring(model, s, l)
                .map(|(start, k)| 0.5 * k * (l - start).powi(2))
                .unwrap_or(0.0);
            0.5 * s.stiffness * (l - s.rest_length).powi(2) + limit
        })
        .sum()
}
