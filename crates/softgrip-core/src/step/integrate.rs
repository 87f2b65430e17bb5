//! Implicit Euler (thesis eq. 41-43) solved by preconditioned CG (Alg. 6).
//!
//! `(M - dt df/dv - dt^2 df/dx) dv = dt (f_n + dt df/dx v_n)` gives the
//! velocity change `dv` itself, so `v_{n+1} = v_n + dv` and
//! `x_{n+1} = x_n + dt v_{n+1}`. (Alg. 5 prints `v += dv * dt`, which would
//! apply the change a second time scaled by dt; we follow the equations and a
//! test checks the oscillation period and the decay factor against them.)

use glam::DVec3;

use super::parallel::{Parallel, SystemOperator};
use crate::model::{AxisDrive, Model};
use crate::solver::System;
use crate::solver::cg::{CgError, CgParams, CgReport, CgScratch, conjugate_gradient};
use crate::solver::direct::{DirectError, DirectSolver};
use crate::state::State;

/// Sets the mask of fixed components: pinned particles, locked and
/// velocity-driven finger axes, and the free axes of a held finger.
pub fn set_mask(model: &Model, state: &State, system: &mut System) {
    let n = model.particle_count();
    for (m, &fixed) in system.mask.iter_mut().zip(&model.fixed) {
        if fixed {
            *m = DVec3::ZERO;
        }
    }
    for (k, f) in model.fingers.iter().enumerate() {
        let held = state.fingers.get(k).is_some_and(|fs| fs.held.is_some());
        system.mask[n + k] = DVec3::from_array(f.drive.map(|d| {
            if d == AxisDrive::Force && !held {
                1.0
            } else {
                0.0
            }
        }));
    }
}

/// A held finger closes the gap to where it is held in this time (s) ...
pub const HOLD_TIME: f64 = 0.03;
/// ... at no more than this speed (m/s), so that a quick drag pushes into
/// the object over many steps rather than in one.
pub const HOLD_SPEED: f64 = 0.3;

/// Solves eq. 43 for `dv` (warm-started from `dv`) and updates the state.
/// `system` is assembled and [`System::finish`]ed; `parallel` shares its
/// products with the helper thread.
pub fn implicit_euler_update(
    model: &Model,
    state: &mut State,
    force: &[DVec3],
    system: &System,
    parallel: &Parallel,
    rhs: &mut Vec<DVec3>,
    dv: &mut Vec<DVec3>,
    cg: &mut CgScratch,
) -> Result<CgReport, CgError> {
    let total = right_hand_side(model, force, system, rhs);
    if dv.len() != total {
        dv.clear();
        dv.resize(total, DVec3::ZERO);
    }
    for (d, m) in dv.iter_mut().zip(&system.mask) {
        *d *= *m;
    }
    let op = SystemOperator { system, parallel };
    let params = CgParams {
        tolerance: model.cg_tolerance,
        reference: model.cg_reference * model.dt * load_norm(model, state),
        max_iterations: model.cg_max_iterations,
    };
    let report = conjugate_gradient(&op, rhs, dv, params, cg)?;
    apply_velocity_change(model, state, dv);
    Ok(report)
}

/// [`implicit_euler_update`] with eq. 43 solved by a sparse factorisation of `system`
/// (`crate::solver::direct`): exact to rounding. A matrix that is not positive definite is
/// [`CgError::NotPositiveDefinite`], as CG would report it.
pub fn implicit_euler_direct(
    model: &Model,
    state: &mut State,
    force: &[DVec3],
    system: &System,
    direct: &mut DirectSolver,
    rhs: &mut Vec<DVec3>,
    dv: &mut Vec<DVec3>,
) -> Result<CgReport, CgError> {
    let total = right_hand_side(model, force, system, rhs);
    dv.clear();
    dv.resize(total, DVec3::ZERO);
    direct.factorise(model, system).map_err(|e| match e {
        DirectError::NotPositiveDefinite => CgError::NotPositiveDefinite {
            iteration: 0,
            curvature: f64::NAN,
        },
        DirectError::Factorisation(_) => CgError::NonFinite { iteration: 0 },
    })?;
    let iterations = direct.solve_system(system, rhs, dv).unwrap_or(usize::MAX);
    if dv.iter().any(|d| !d.is_finite()) {
        return Err(CgError::NonFinite { iteration: 0 });
    }
    apply_velocity_change(model, state, dv);
    Ok(CgReport {
        iterations,
        relative_residual: 0.0,
    })
}

/// `v += dv`, `x += dt v` for particles and fingers, and the fingers' travel.
fn apply_velocity_change(model: &Model, state: &mut State, dv: &[DVec3]) {
    let n = model.particle_count();
    let dt = model.dt;
    for i in 0..n {
        state.velocities[i] += dv[i];
        state.positions[i] += dt * state.velocities[i];
    }
    for (k, fs) in state.fingers.iter_mut().enumerate() {
        fs.velocity += dv[n + k];
        let step = dt * fs.velocity;
        fs.position += step;
        let held = fs.held.is_some();
        let driven = DVec3::from_array(model.fingers[k].drive.map(|d| {
            if matches!(d, AxisDrive::Velocity(_)) && !held {
                1.0
            } else {
                0.0
            }
        }));
        fs.travelled += (step * driven).length();
    }
}

/// The 2-norm of the loads (gravity, `[[load]]`, the fingers' applied forces
/// and weights), N: the scale of the forces the object carries.
fn load_norm(model: &Model, state: &State) -> f64 {
    let object: f64 = model
        .constant_force
        .iter()
        .map(|f| f.length_squared())
        .sum();
    let fingers: f64 = model
        .fingers
        .iter()
        .zip(&state.fingers)
        .map(|(f, s)| (s.applied_force + f.weight).length_squared())
        .sum();
    (object + fingers).sqrt()
}

/// Sets finger velocities on locked and velocity-driven axes before a step;
/// a held finger moves towards where it is held along its free axes.
pub fn drive_fingers(model: &Model, state: &mut State) {
    // The velocity over the coming step: at its middle, so a ramp's
    // distance is exact.
    let time = state.time + 0.5 * model.dt;
    for (f, fs) in model.fingers.iter().zip(&mut state.fingers) {
        if let Some(target) = fs.held {
            let free = DVec3::from_array(
                f.drive
                    .map(|d| if d == AxisDrive::Locked { 0.0 } else { 1.0 }),
            );
            let v = (target - fs.position) * free / HOLD_TIME;
            let speed = v.length();
            fs.velocity = if speed > HOLD_SPEED {
                v * (HOLD_SPEED / speed)
            } else {
                v
            };
            continue;
        }
        let stopped = f.travel.is_some_and(|t| fs.travelled >= t);
        for axis in 0..3 {
            match f.drive[axis] {
                AxisDrive::Locked => fs.velocity[axis] = 0.0,
                AxisDrive::Velocity(v) => {
                    fs.velocity[axis] = if stopped {
                        0.0
                    } else {
                        v * f.velocity_share(time)
                    }
                }
                AxisDrive::Force => {}
            }
        }
    }
}

/// Eq. 43's right-hand side `dt (f - dt Kp v)` on the free components into `rhs`; returns the
/// number of unknowns (particles, then fingers).
fn right_hand_side(model: &Model, force: &[DVec3], system: &System, rhs: &mut Vec<DVec3>) -> usize {
    let total = model.particle_count() + model.fingers.len();
    let dt = model.dt;
    rhs.clear();
    rhs.extend((0..total).map(|i| (force[i] - dt * system.kv[i]) * dt * system.mask[i]));
    total
}
