//! Volume-preservation correction forces (thesis eq. 10-12, Alg. 2), after
//! Mollemans et al.
//!
//! Each element pushes its four particles away from its barycentre when it has
//! lost volume and pulls them in when it has gained some:
//! `f_i = alpha (V0 - V) (u_i - mean(u))`, `u_i` the unit vector from the
//! barycentre to particle i. Two departures from the printed text, both
//! documented in ARCHITECTURE.md: the sign is written so the force restores
//! the volume whatever the orientation convention (eq. 11's `V - V0` restores
//! only with Alg. 2's negatively signed determinant), and the element's mean
//! direction is removed so the four forces sum to zero (the unit vectors of a
//! distorted element do not, which would let a free object push itself along).
//!
//! Jacobian: `-df_i/dx_k ~ alpha u_i (dV/dx_k)^T`, symmetrised as
//! `alpha / g G_i G_k^T` with `G_i = dV/dx_i` and `g` the mean |G_i| (exact in
//! direction for a regular element, positive semi-definite, translation
//! invariant). It lets the implicit step carry these forces stably.

use glam::DVec3;

use crate::mesh::{TET_EDGES, signed_volume};
use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Gradient of the signed volume with respect to each of the four nodes.
#[inline]
pub fn volume_gradients(p: [DVec3; 4]) -> [DVec3; 4] {
    let [a, b, c, d] = p;
    let gb = (c - a).cross(d - a) / 6.0;
    let gc = (d - a).cross(b - a) / 6.0;
    let gd = (b - a).cross(c - a) / 6.0;
    [-(gb + gc + gd), gb, gc, gd]
}

pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    if model.alpha == 0.0 {
        return;
    }
    let vel = |dof: usize| super::velocity_of(state, dof);
    for (t, tet) in model.tets.iter().enumerate() {
        let p = tet.map(|i| state.positions[i as usize]);
        let volume = signed_volume(p[0], p[1], p[2], p[3]);
        let barycentre = (p[0] + p[1] + p[2] + p[3]) * 0.25; // eq. 12 (four vertices)
        let u = p.map(|q| (q - barycentre).normalize_or_zero());
        let mean_u = (u[0] + u[1] + u[2] + u[3]) * 0.25;
        let scale = model.alpha * (model.rest_volume[t] - volume); // eq. 11, restoring sign
        for k in 0..4 {
            force[tet[k] as usize] += scale * (u[k] - mean_u);
        }

        let g = volume_gradients(p);
        let g_mean = 0.25 * g.iter().map(|v| v.length()).sum::<f64>();
        if g_mean <= 0.0 {
            continue;
        }
        let c = model.alpha / g_mean;
        let zero = glam::DMat3::ZERO;
        for k in 0..4 {
            system.add_diag(tet[k] as usize, outer(g[k], g[k]) * c, zero, &vel);
        }
        for (e, [a, b]) in TET_EDGES.iter().enumerate() {
            let kp = outer(g[*a], g[*b]) * c;
            system.add_off(
                &model.springs,
                model.tet_springs[t][e],
                tet[*a] as usize,
                tet[*b] as usize,
                kp,
                zero,
                &vel,
            );
        }
    }
}
