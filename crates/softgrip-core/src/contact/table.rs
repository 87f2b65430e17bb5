//! The table (`[support] kind = "table"`): the plane z = 0 under the object, unilateral, with
//! Coulomb friction (`[support] friction`) that sticks and slips. A softgrip addition; the
//! thesis pins the bottom face.
//!
//! Each boundary particle is its own contact: a critically damped penalty spring along the
//! normal that never pulls; a tangential stick spring to an anchor until it would pull harder
//! than `mu F_n`; then the kinetic force `mu F_n` against the sliding, until the sliding
//! reverses or slows below [`SLIP_REST_SPEED`]. Modes are chosen at the start of a step; the
//! forces and Jacobians enter the implicit step like any other. The details:
//! `docs/design/table-contact.md`.

use glam::{DMat3, DVec3};

use crate::model::Model;
use crate::solver::System;
use crate::state::{State, TableContact, TableMode};

/// A slipping contact slower than this (m/s) sticks again.
pub const SLIP_REST_SPEED: f64 = 1e-6;

const TANGENT: DVec3 = DVec3::new(1.0, 1.0, 0.0);

/// Adds the table's forces and Jacobians, choosing each contact's mode.
pub fn accumulate(model: &Model, state: &mut State, force: &mut [DVec3], system: &mut System) {
    let Some(table) = &model.table else {
        state.table.clear();
        return;
    };
    if state.table.len() != table.particles.len() {
        // A model rebuilt with a table under a running state.
        state.table = vec![TableContact::default(); table.particles.len()];
    }
    let k = table.stiffness;
    let mu = table.friction;
    let dt = model.dt;
    let velocities = &state.velocities;
    let vel = |dof: usize| {
        if dof < velocities.len() {
            velocities[dof]
        } else {
            state.fingers[dof - velocities.len()].velocity
        }
    };
    let tangent = DMat3::from_diagonal(TANGENT);
    for (c, &p) in state.table.iter_mut().zip(&table.particles) {
        let p = p as usize;
        let x = state.positions[p];
        let v = velocities[p];
        if leaves_contact(model, c, x, v) {
            continue;
        }
        let penetration = -x.z;
        let c_n = table.damping(model.mass[p]);
        let push = k * penetration - c_n * v.z;
        force[p].z += push;
        // The friction limit takes the penalty spring's force alone: the
        // dashpot's share is the transient of a particle landing or
        // rising, and counted in, its jitter made the friction jitter.
        let normal = k * penetration.max(0.0);
        c.normal_force = normal;
        c.penetration = penetration.max(0.0);
        system.add_diag(
            p,
            DMat3::from_diagonal(DVec3::Z * k),
            DMat3::from_diagonal(DVec3::Z * c_n),
            &vel,
        );
        if mu <= 0.0 {
            c.mode = TableMode::Slip;
            c.tangential_force = DVec3::ZERO;
            continue;
        }
        let limit = mu * normal;
        let xt = x * TANGENT;
        let vt = v * TANGENT;
        if model.quasi_static {
            let exact = model.full_tangent.then_some(mu * k);
            return_mapping(c, k, limit, exact, xt, vt, c_n, p, force, system, &vel);
            continue;
        }
        let speed = vt.length();
        choose_mode(c, xt, vt, speed, k, limit, dt);
        let last_speed = c.last_speed;
        c.last_speed = if c.mode == TableMode::Slip {
            speed
        } else {
            0.0
        };
        match c.mode {
            TableMode::Stick => {
                let f = -k * (xt - c.anchor) - c_n * vt;
                c.tangential_force = f;
                force[p] += f;
                system.add_diag(p, tangent * k, tangent * c_n, &vel);
            }
            TableMode::Slip => {
                let (f, damping) = slip(c, limit, speed, last_speed, dt, model.mass[p]);
                force[p] += f;
                system.add_diag(p, DMat3::ZERO, damping, &vel);
            }
            TableMode::Free => unreachable!("set above"),
        }
    }
}

/// Whether particle contact `c` (at `x`, moving at `v`) is off the table for this step: then it
/// is reset, keeping in a static solve the anchor where it would stick if it landed.
fn leaves_contact(model: &Model, c: &mut TableContact, x: DVec3, v: DVec3) -> bool {
    // In contact when below the table, or about to be by the end of
    // the step: a particle that would land lands on the plane instead
    // of bouncing off the penalty a step later. One below it stays in
    // contact while it rises back (the dashpot stops it on the plane;
    // released, it left at the penetration over dt and fell back, a
    // two-step bounce for ever).
    // A static solve counts a particle on the plane (z = 0, the object's rest on the
    // table) as touching: its tangent then holds the object up from the first iteration.
    let off = if model.quasi_static {
        x.z > 0.0
    } else {
        x.z >= 0.0
    };
    if off && x.z + model.dt * v.z >= 0.0 {
        // A static solve keeps where a particle off the table would stick if it landed
        // ([`begin_increment`]).
        let anchor = if model.quasi_static {
            c.anchor
        } else {
            DVec3::ZERO
        };
        *c = TableContact {
            anchor,
            ..TableContact::default()
        };
        return true;
    }
    false
}

/// A time step's friction mode for a contact at tangential position `xt` moving at `vt`
/// (`speed` its length): free contacts land sticking or sliding, a stuck one slips when its
/// stick spring (stiffness `k`) would pull harder than `limit` by the step's end, a slipping
/// one sticks again when it reverses or comes to rest.
fn choose_mode(
    c: &mut TableContact,
    xt: DVec3,
    vt: DVec3,
    speed: f64,
    k: f64,
    limit: f64,
    dt: f64,
) {
    match c.mode {
        TableMode::Free => {
            // Landing while sliding slides on (a stick spring would stop
            // the particle in one step, whatever mu F_n allows).
            if speed > SLIP_REST_SPEED {
                c.mode = TableMode::Slip;
                c.direction = vt / speed;
            } else {
                c.mode = TableMode::Stick;
                c.anchor = xt;
            }
        }
        TableMode::Stick => {
            // Slips when the spring would pull harder than mu F_n by
            // the end of the step at the present velocity.
            let drift = xt + dt * vt - c.anchor;
            let d = drift.length();
            if k * d > limit {
                c.mode = TableMode::Slip;
                c.direction = drift / d;
            }
        }
        TableMode::Slip => {
            let stopping = speed < SLIP_REST_SPEED && speed < c.last_speed;
            if stopping || vt.dot(c.direction) <= 0.0 {
                // Stick again, carrying on with the same force.
                c.mode = TableMode::Stick;
                c.anchor = xt - c.direction * (limit / k);
            } else {
                c.direction = vt / speed;
            }
        }
    }
}

/// A slipping contact's force (to add to the particle's) and damping block (for the system):
/// the kinetic friction `limit` against the velocity, `speed` now and `last_speed` a step ago,
/// on a particle of `mass` (kg).
fn slip(
    c: &mut TableContact,
    limit: f64,
    speed: f64,
    last_speed: f64,
    dt: f64,
    mass: f64,
) -> (DVec3, DMat3) {
    // mu F_n against the velocity. Its Jacobian is a damper
    // `d = mu F_n / |v_t|` across the velocity (the direction
    // turns with it) and, along it, `d` times the share of the
    // speed friction alone would take in a step (at most 1): a
    // particle friction could stop in a step is slowed by a
    // damper, never reversed. The damper takes `d dv` off the
    // force in the step, so the force adds `d dv` for the speed
    // gained in the last step: mu F_n exactly while the speed
    // grows steadily (a block accelerating slowly down a slope
    // had 1 % too much friction without it, and 30 % too little
    // acceleration; with no damper along the velocity, landing
    // particles with a large F_n were thrown back and the block
    // diverged).
    let s = speed.max(SLIP_REST_SPEED);
    let d = limit / s;
    let share = (limit * dt / (mass * s)).min(1.0);
    let gained = if last_speed > 0.0 {
        (speed - last_speed).clamp(0.0, speed)
    } else {
        0.0
    };
    let t = c.direction;
    let along = crate::solver::system::outer(t, t);
    let f = -limit * t;
    c.tangential_force = f;
    let tangent = DMat3::from_diagonal(TANGENT);
    (
        f + t * (d * share * gained),
        (tangent - along) * d + along * (d * share),
    )
}

/// A contact in a static solve: the stick spring to an anchor held over the whole load increment,
/// its force projected onto the Coulomb disc `|f| <= mu F_n` (the return mapping of
/// elastoplasticity, as FE codes treat friction: Wriggers, Computational Contact Mechanics, ch. 5),
/// with the projection's consistent tangent. The answer depends on the increment's end, not on
/// the path Newton takes to it; [`commit`] moves the anchors of the contacts that slid.
#[allow(clippy::too_many_arguments)]
fn return_mapping(
    c: &mut TableContact,
    k: f64,
    limit: f64,
    exact: Option<f64>,
    xt: DVec3,
    vt: DVec3,
    c_n: f64,
    p: usize,
    force: &mut [DVec3],
    system: &mut System,
    vel: &dyn Fn(usize) -> DVec3,
) {
    // Landed in this increment: tied where it was when the increment began
    // ([`begin_increment`]), so that the answer does not depend on where Newton's iterates
    // first crossed the plane.
    c.last_speed = 0.0;
    let tangent = DMat3::from_diagonal(TANGENT);
    let d = xt - c.anchor;
    let trial = k * d.length();
    // The dashpot acts on the pseudo velocity, zero at the answer: it only damps the iteration.
    let damper = -c_n * vt;
    if trial <= limit && !(c.sliding && trial > 0.0) {
        c.mode = TableMode::Stick;
        c.tangential_force = -k * d;
        force[p] += c.tangential_force + damper;
        system.add_diag(p, tangent * k, tangent * c_n, &vel);
    } else {
        let n = d / d.length();
        c.mode = TableMode::Slip;
        c.direction = n;
        c.tangential_force = -limit * n;
        force[p] += c.tangential_force + damper;
        // d(limit n)/dx = (limit / |d|) (I_t - n n^T): the disc's edge turns with the slip.
        let along = crate::solver::system::outer(n, n);
        let kp = (tangent - along) * (limit / d.length());
        if let Some(mu_k) = exact {
            // Newton's exact tangent also has the limit following the penetration:
            // `-df_t/dz = -mu k n`, a column with no row to match: the system's non-symmetric
            // remainder (its symmetric part would make the block indefinite on a long slide).
            let column = crate::solver::system::outer(n * -mu_k, DVec3::Z);
            let none = crate::solver::system::Asym::NONE;
            let mut blocks = [[DMat3::ZERO; 4]; 4];
            blocks[0][0] = column;
            system.add_asym([p as u32, none, none, none], blocks);
        }
        system.add_diag(p, kp, tangent * c_n, &vel);
    }
}

/// Before a static solve: a particle off the table is tied, if it lands in this load increment,
/// below where it is now (its anchor), whatever path Newton's iterates take to the plane.
pub fn begin_increment(model: &Model, state: &mut State) {
    let Some(table) = &model.table else {
        return;
    };
    if state.table.len() != table.particles.len() {
        state.table = vec![TableContact::default(); table.particles.len()];
    }
    for (c, &p) in state.table.iter_mut().zip(&table.particles) {
        if c.mode == TableMode::Free {
            c.anchor = state.positions[p as usize] * TANGENT;
        }
    }
}

/// After a static solve: each contact that slid in the increment has its anchor dragged to where
/// the Coulomb limit holds it, so that the next increment starts from the friction this one ended
/// with (and a time step from here sticks with the same force).
pub fn commit(model: &Model, state: &mut State) {
    let Some(table) = &model.table else {
        return;
    };
    let k = table.stiffness;
    for (c, &p) in state.table.iter_mut().zip(&table.particles) {
        let x = state.positions[p as usize];
        c.dragged = DVec3::ZERO;
        if c.mode == TableMode::Free || x.z >= 0.0 {
            continue;
        }
        let limit = table.friction * k * (-x.z);
        let d = x * TANGENT - c.anchor;
        if k * d.length() > limit {
            let anchor = x * TANGENT - d / d.length() * (limit / k);
            c.dragged = anchor - c.anchor;
            c.anchor = anchor;
        }
    }
}

/// Elastic energy in the table's penalty and stick springs (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    let Some(table) = &model.table else {
        return 0.0;
    };
    state
        .table
        .iter()
        .zip(&table.particles)
        .map(|(c, &p)| {
            let x = state.positions[p as usize];
            let normal = 0.5 * table.stiffness * (-x.z).max(0.0).powi(2);
            let stick = if c.mode == TableMode::Stick {
                0.5 * table.stiffness * (x * TANGENT - c.anchor).length_squared()
            } else {
                0.0
            };
            normal + stick
        })
        .sum()
}

/// The total force the table exerts on the object in the last step (N).
pub fn total_force(state: &State) -> DVec3 {
    state
        .table
        .iter()
        .map(|c| c.tangential_force + DVec3::Z * c.normal_force)
        .sum()
}
