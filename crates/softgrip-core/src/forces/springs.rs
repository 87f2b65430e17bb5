//! Spring and damper forces (thesis eq. 3-4, Alg. 1) and their Jacobians.

use glam::{DMat3, DVec3};

use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Spring `s`'s end points, its length and its unit axis from i to j in `x`; `None` when its
/// ends coincide (no direction: the spring exerts nothing).
pub(crate) fn axis(x: &[DVec3], s: &crate::model::Spring) -> Option<(usize, usize, f64, DVec3)> {
    let (i, j) = (s.i as usize, s.j as usize);
    let delta = x[j] - x[i];
    let l = delta.length();
    (l > 0.0).then(|| (i, j, l, delta / l))
}

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
///
/// Spring models only: with neo-Hookean elements the springs' stage runs
/// [`accumulate_dampers`] instead (`step::assemble`).
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    if !model.spring_law.is_linear() {
        return accumulate_general(model, state, force, system);
    }
    let x = &state.positions;
    let v = &state.velocities;
    for (slot, s) in model.springs.iter().enumerate() {
        let Some((i, j, l, u)) = axis(x, s) else {
            continue;
        };
        let elastic = s.stiffness * (l - s.rest_length); // eq. 3
        let damping = s.damping * u.dot(v[j] - v[i]); // eq. 4
        let f = (elastic + damping) * u;
        force[i] += f;
        force[j] -= f;

        let uu = outer(u, u);
        let transverse = clamp_transverse(model, 1.0 - s.rest_length / l);
        let kp = uu * s.stiffness + (DMat3::IDENTITY - uu) * (s.stiffness * transverse);
        limit_and_blocks(model, s, slot, l, u, kp, v, force, system);
    }
}

/// The elastic force of spring `s` along its length (N, positive in
/// tension) and its derivative by the length (N/m), under `model`'s
/// spring law, for the Maxwell arm's dashpot extension `q` (m):
///
/// - stiffness `k` in tension, `compression_ratio k` in compression;
/// - strain stiffening `F_e = k dl (1 + beta e^2)`, `e = dl / l0`: a cubic
///   with one parameter, the linear spring at beta = 0, stiffer at large
///   strain in both directions (energy `k l0^2 (e^2 / 2 + beta e^4 / 4)`);
/// - one Prony term (a standard linear solid): `(1 - g) F_e` in parallel
///   with a Maxwell arm, a spring `g k` in series with a dashpot
///   `g k tau`. Implicit Euler over the step, `q_{n+1} = (q_n + a dl_{n+1})
///   / (1 + a)` with `a = dt / tau`, makes the arm a spring of stiffness
///   `g k / (1 + a)` from `q_n`: `g k / (1 + a) (dl - q_n)`. A held
///   deformation relaxes to `1 - g` of its force with time constant tau; a
///   constant load creeps with `tau / (1 - g)`.
#[inline]
pub fn spring_law(model: &Model, s: &crate::model::Spring, l: f64, q: f64) -> SpringForce {
    let law = &model.spring_law;
    let dl = l - s.rest_length;
    let k = if dl < 0.0 {
        s.stiffness * law.compression_ratio
    } else {
        s.stiffness
    };
    let e = dl / s.rest_length;
    // Secant and tangent stiffness of the elastic part.
    let secant = k * (1.0 + law.stiffening * e * e);
    let tangent = k * (1.0 + 3.0 * law.stiffening * e * e);
    let g = law.prony_g;
    let arm = g * k / (1.0 + model.dt / law.prony_tau);
    SpringForce {
        // At beta = 0, g = 0 and ratio 1 every factor is exactly 1 or 0, so
        // this is the linear path's `k (l - l0)` and `k (1 - l0 / l)` to the
        // last bit.
        force: (1.0 - g) * (secant * dl) + arm * (dl - q),
        tangent: (1.0 - g) * tangent + arm,
        transverse: (1.0 - g) * (secant * (1.0 - s.rest_length / l)) + arm * (dl - q) / l,
    }
}

/// A spring's elastic force along it (N, positive in tension), its
/// derivative by the length (N/m) and its force over its length (N/m,
/// the transverse stiffness before clamping).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringForce {
    /// Elastic force along the spring, N (positive in tension).
    pub force: f64,
    /// Its derivative by the length, N/m.
    pub tangent: f64,
    /// Force over length, N/m: the transverse stiffness before clamping.
    pub transverse: f64,
}

/// [`accumulate`] under a spring law other than the thesis's (stiffening,
/// asymmetric, viscoelastic): the transverse stiffness is the force over
/// the length, `F / l (I - u u^T)`, clamped at zero. Under the thesis's law
/// it gives the same bits as [`accumulate`] (tested), which takes a
/// shorter path.
pub fn accumulate_general(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let x = &state.positions;
    let v = &state.velocities;
    for (slot, s) in model.springs.iter().enumerate() {
        let Some((i, j, l, u)) = axis(x, s) else {
            continue;
        };
        let q = state.maxwell.get(slot).copied().unwrap_or(0.0);
        let law = spring_law(model, s, l, q);
        let damping = s.damping * u.dot(v[j] - v[i]);
        let f = (law.force + damping) * u;
        force[i] += f;
        force[j] -= f;

        let uu = outer(u, u);
        let kp_linear = uu * law.tangent;
        let kp = kp_linear + (DMat3::IDENTITY - uu) * clamp_transverse(model, law.transverse);
        limit_and_blocks(model, s, slot, l, u, kp, v, force, system);
    }
}

/// A compressed spring's transverse stiffness is negative; the implicit step clamps it at zero
/// (its matrix must stay positive definite), the static solver keeps it
/// ([`Model::exact_tangent`]) and shifts the matrix instead.
#[inline]
fn clamp_transverse(model: &Model, t: f64) -> f64 {
    if model.exact_tangent { t } else { t.max(0.0) }
}

/// The springs' dampers alone (eq. 4): the damping of the neo-Hookean
/// model, whose elastic forces are the elements' (`forces::fem`).
pub fn accumulate_dampers(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let x = &state.positions;
    let v = &state.velocities;
    let dt = system.dt();
    for (slot, s) in model.springs.iter().enumerate() {
        let Some((i, j, _, u)) = axis(x, s) else {
            continue;
        };
        let f = (s.damping * u.dot(v[j] - v[i])) * u;
        force[i] += f;
        force[j] -= f;
        let w = outer(u, u) * (s.damping * dt);
        system.diag[i] += w;
        system.diag[j] += w;
        system.off[slot] -= w;
    }
}

/// After a step: each viscoelastic spring's dashpot moves towards its
/// present extension, `q = (q + a dl) / (1 + a)`, `a = dt / tau` (the
/// implicit Euler step [`spring_law`] assumed).
pub fn relax(model: &Model, state: &mut State) {
    if !model.spring_law.is_viscoelastic() {
        return;
    }
    if model.fem.is_some() {
        return; // the elements' arms: `viscosity::relax_elements`
    }
    if state.maxwell.len() != model.springs.len() {
        state.maxwell = vec![0.0; model.springs.len()];
    }
    let a = model.dt / model.spring_law.prony_tau;
    let x = &state.positions;
    for (q, s) in state.maxwell.iter_mut().zip(&model.springs) {
        let dl = x[s.i as usize].distance(x[s.j as usize]) - s.rest_length;
        *q = (*q + a * dl) / (1.0 + a);
    }
}

/// The end of a spring's pass, shared by the thesis's and the general
/// law: its limit spring, if it is near a limit, then its blocks. Blocks
/// (i, i) and (j, j) get +W, block (i, j) = (spring.i, spring.j) gets -W,
/// with W = dt^2 Kp + dt Dp; `Kp v` is Kp (v_i - v_j) at i.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn limit_and_blocks(
    model: &Model,
    s: &crate::model::Spring,
    slot: usize,
    l: f64,
    u: DVec3,
    mut kp: DMat3,
    v: &[DVec3],
    force: &mut [DVec3],
    system: &mut System,
) {
    let (i, j) = (s.i as usize, s.j as usize);
    let uu = outer(u, u);
    if let Some((start, k_lim)) = limit_spring(model, s, l) {
        let f = k_lim * (l - start) * u;
        force[i] += f;
        force[j] -= f;
        let t = clamp_transverse(model, 1.0 - start / l);
        kp += uu * k_lim + (DMat3::IDENTITY - uu) * (k_lim * t);
    }
    let dt = system.dt();
    let w = kp * (dt * dt) + uu * (s.damping * dt);
    system.diag[i] += w;
    system.diag[j] += w;
    system.off[slot] -= w;
    let kv = kp * (v[i] - v[j]);
    system.kv[i] += kv;
    system.kv[j] -= kv;
}

/// Where a limit spring starts, as a fraction of the rest length before the
/// tau_s / tau_c limit. At 0.2 % the limit springs let the springs of the
/// 1.6 mm thesis mesh settle 1.6e-3 beyond tau_c (the force per spring over
/// the limit stiffness is 3.6e-3 of l0 there); at 0.5 % they settle inside
/// on every mesh of the mesh convergence table of docs/results/accuracy.md.
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

/// Elastic energy stored in the springs (their Maxwell arms included) and
/// their limit springs, or in the elements (their arms: [`super::viscosity::arm_energy`]) (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    if let Some(fem) = &model.fem {
        return super::fem::energy(model, fem, state);
    }
    let law = &model.spring_law;
    let linear = law.is_linear();
    model
        .springs
        .iter()
        .enumerate()
        .map(|(slot, s)| {
            let l = state.positions[s.i as usize].distance(state.positions[s.j as usize]);
            let limit = limit_spring(model, s, l)
                .map(|(start, k)| 0.5 * k * (l - start).powi(2))
                .unwrap_or(0.0);
            let dl = l - s.rest_length;
            if linear {
                return 0.5 * s.stiffness * dl.powi(2) + limit;
            }
            let k = if dl < 0.0 {
                s.stiffness * law.compression_ratio
            } else {
                s.stiffness
            };
            let e = dl / s.rest_length;
            let elastic =
                k * s.rest_length.powi(2) * (0.5 * e * e + 0.25 * law.stiffening * e.powi(4));
            let q = state.maxwell.get(slot).copied().unwrap_or(0.0);
            let g = law.prony_g;
            (1.0 - g) * elastic + 0.5 * g * k * (dl - q).powi(2) + limit
        })
        .sum()
}
