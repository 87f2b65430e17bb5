//! Volume-preservation forces. Thesis eq. 10-12 (Alg. 2, after Mollemans et al.): each element
//! pushes its particles away from its barycentre when it has lost volume and pulls them in when
//! it has gained some, `f_i = alpha (V0 - V) (u_i - mean(u))`. The element volumetric stiffness
//! (`[model] bulk_modulus`, softgrip, off by default): the gradient of the energy
//! `K V0 / 2 (V / V0 - 1)^2`, with the volume change measured per element or, with
//! `bulk_pressure = "nodal"`, per node (average nodal pressure, Bonet and Burton 1998). Each
//! comes with a positive semi-definite Jacobian for the implicit step.
//!
//! The departures from the printed text (ARCHITECTURE.md) and the Jacobians:
//! `docs/design/volume-forces.md`.

use glam::{DMat3, DVec3};

use crate::mesh::{TET_EDGES, signed_volume, volume_gradients};
use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Adds eq. 11's correction forces and the `bulk_modulus` forces of a spring model, with their
/// Jacobians: the nodal term once ([`nodal`]), then every element. A neo-Hookean model's
/// elements are `forces::fem`'s (the step's stage list, `step::assemble`, picks which).
///
/// Both element Jacobians are `c G_a G_b^T` (`c = alpha / g` for eq. 11, `K / V0`
/// for the bulk term), so they share one set of blocks, and their product
/// with the velocities is `c G_a (sum_b G_b . v_b)`.
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    nodal(model, state, force, system);
    accumulate_elements(model, state, force, system, 0..model.tets.len());
}

/// [`accumulate`]'s element pass for the elements in `elements` only (the
/// two threads each take a share; [`nodal`] runs once, before). Spring models only.
pub fn accumulate_elements(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let (alpha, bulk) = (model.alpha, model.bulk_modulus);
    let element_bulk = if model.nodal_bulk.is_some() {
        0.0
    } else {
        bulk
    };
    if alpha == 0.0 && element_bulk == 0.0 {
        return;
    }
    let dt2 = system.dt() * system.dt();
    let (x, v) = (&state.positions, &state.velocities);
    accumulate_range(model, x, v, element_bulk, dt2, force, system, elements);
}

thread_local! {
    /// [`nodal`]'s per-node and per-edge sums: one set per thread.
    static NODAL_SCRATCH: std::cell::RefCell<NodalScratch> = std::cell::RefCell::new(NodalScratch::default());
}

#[derive(Default)]
struct NodalScratch {
    /// Per node: `V_i`, then `p_i`; `g_i . v`, then `K_i / V0_i (g_i . v)`.
    volume: Vec<f64>,
    rate: Vec<f64>,
    /// Per node `(g_a)_a`; per spring `(g_i)_j` and `(g_j)_i` (i < j).
    own: Vec<DVec3>,
    i_at_j: Vec<DVec3>,
    j_at_i: Vec<DVec3>,
}

/// The volume term averaged per node (average nodal pressure, Bonet and
/// Burton 1998; `[model] bulk_pressure = "nodal"`): the energy
/// `sum_i V0_i K_i / 2 (V_i / V0_i - 1)^2`, `V_i` a quarter of the volume of each
/// element around node i, `K_i` the bulk term's modulus (springs) or
/// lambda (neo-Hookean elements), averaged over the node's elements. Its forces
/// and `Kp v` go into `force` and `system.kv`; its Gauss-Newton Jacobian
/// `sum_i K_i / V0_i g_i g_i^T` couples nodes two edges apart, so it goes into
/// `system.nodal`, applied matrix-free, with its exact diagonal blocks for
/// the preconditioner. Computed once per assembly, on one thread.
pub fn nodal(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let Some(nodal) = &model.nodal_bulk else {
        return;
    };
    let dt2 = system.dt() * system.dt();
    let (x, v) = (&state.positions, &state.velocities);
    let n = nodal.rest_volume.len();
    NODAL_SCRATCH.with_borrow_mut(|s| {
        for buffer in [&mut s.volume, &mut s.rate] {
            buffer.clear();
            buffer.resize(n, 0.0);
        }
        s.own.clear();
        s.own.resize(n, DVec3::ZERO);
        for buffer in [&mut s.i_at_j, &mut s.j_at_i] {
            buffer.clear();
            buffer.resize(model.springs.len(), DVec3::ZERO);
        }
        let op = &mut system.nodal;
        op.quarter_gradients.reserve(model.tets.len());
        for (e, tet) in model.tets.iter().enumerate() {
            let idx = tet.map(|i| i as usize);
            let p = idx.map(|i| x[i]);
            let g = volume_gradients(p);
            let volume = g[3].dot(p[3] - p[0]);
            let q = g.map(|g| g * 0.25);
            let rate = (0..4).map(|a| q[a].dot(v[idx[a]])).sum::<f64>();
            for (a, &i) in idx.iter().enumerate() {
                s.volume[i] += 0.25 * volume;
                s.rate[i] += rate;
                s.own[i] += q[a];
            }
            for (m, [a, b]) in TET_EDGES.into_iter().enumerate() {
                let slot = model.tet_springs[e][m] as usize;
                let (i, j) = if idx[a] < idx[b] { (a, b) } else { (b, a) };
                s.i_at_j[slot] += q[j];
                s.j_at_i[slot] += q[i];
            }
            op.quarter_gradients.push(q);
        }
        op.weight.reserve(n);
        for i in 0..n {
            let (v0, k) = (nodal.rest_volume[i], nodal.modulus[i]);
            let w = if v0 > 0.0 { k / v0 } else { 0.0 };
            s.volume[i] = if v0 > 0.0 {
                k * (s.volume[i] / v0 - 1.0)
            } else {
                0.0
            };
            s.rate[i] *= w;
            op.weight.push(w * dt2);
        }
        for (e, (tet, q)) in model.tets.iter().zip(&op.quarter_gradients).enumerate() {
            let idx = tet.map(|i| i as usize);
            let pressure: f64 = idx.iter().map(|&i| s.volume[i]).sum();
            let rate: f64 = idx.iter().map(|&i| s.rate[i]).sum();
            for (a, &i) in idx.iter().enumerate() {
                force[i] -= q[a] * pressure;
                system.kv[i] += q[a] * rate;
            }
            if model.full_tangent {
                // Newton's tangent: the pressures' geometric term, `sum_i p_i d2V_i`, each element
                // `sum_(i in e) p_i / 4 d2V_e` (the Gauss-Newton part is the operator's).
                let p = idx.map(|i| x[i]);
                let weight = 0.25 * pressure;
                for (m, [a, b]) in TET_EDGES.into_iter().enumerate() {
                    let (i, j) = if idx[a] < idx[b] { (a, b) } else { (b, a) };
                    let h = crate::forces::fem::volume_hessian(p, i, j) * weight;
                    system.off[model.tet_springs[e][m] as usize] += h * dt2;
                    system.kv[idx[i]] += h * v[idx[j]];
                    system.kv[idx[j]] += h.transpose() * v[idx[i]];
                }
            }
        }
        let op = &mut system.nodal;
        op.diag.clear();
        op.diag.resize(system.diag.len(), DMat3::ZERO);
        for i in 0..n {
            op.diag[i] += outer(s.own[i], s.own[i] * op.weight[i]);
        }
        for (slot, spring) in model.springs.iter().enumerate() {
            let (i, j) = (spring.i as usize, spring.j as usize);
            let (gi, gj) = (s.i_at_j[slot], s.j_at_i[slot]);
            op.diag[j] += outer(gi, gi * op.weight[i]);
            op.diag[i] += outer(gj, gj * op.weight[j]);
        }
    });
}

#[allow(clippy::too_many_arguments)]
fn accumulate_range(
    model: &Model,
    x: &[DVec3],
    v: &[DVec3],
    bulk: f64,
    dt2: f64,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let alpha = model.alpha;
    for e in elements {
        let tet = model.tets[e];
        let v0 = model.rest_volume[e];
        let idx = [
            tet[0] as usize,
            tet[1] as usize,
            tet[2] as usize,
            tet[3] as usize,
        ];
        let p = [x[idx[0]], x[idx[1]], x[idx[2]], x[idx[3]]];
        let g = volume_gradients(p);
        let volume = g[3].dot(p[3] - p[0]); // = signed_volume(p)
        let mut c = 0.0;
        if alpha != 0.0 {
            let barycentre = (p[0] + p[1] + p[2] + p[3]) * 0.25; // eq. 12 (four vertices)
            let r = [
                p[0] - barycentre,
                p[1] - barycentre,
                p[2] - barycentre,
                p[3] - barycentre,
            ];
            // Eight independent square roots, so they pipeline.
            let len = [r[0].length(), r[1].length(), r[2].length(), r[3].length()];
            let g_mean = 0.25 * (g[0].length() + g[1].length() + g[2].length() + g[3].length());
            let u = [
                unit(r[0], len[0]),
                unit(r[1], len[1]),
                unit(r[2], len[2]),
                unit(r[3], len[3]),
            ];
            let mean_u = (u[0] + u[1] + u[2] + u[3]) * 0.25;
            let scale = alpha * (v0 - volume); // eq. 11, restoring sign
            for k in 0..4 {
                force[idx[k]] += scale * (u[k] - mean_u);
            }
            if g_mean > 0.0 {
                c += alpha / g_mean;
            }
        }
        if bulk != 0.0 {
            let bulk = match model.element_stiffness_scale.get(e) {
                Some(scale) => bulk * scale,
                None => bulk,
            };
            let bulk_per_volume = bulk / v0;
            let s = bulk_per_volume * (volume - v0); // K (V / V0 - 1)
            for k in 0..4 {
                force[idx[k]] -= s * g[k];
            }
            c += bulk_per_volume;
        }
        if c == 0.0 {
            continue;
        }
        // Blocks weighted by dt^2 as they enter A; their product with the
        // velocities is rank one.
        let cw = c * dt2;
        let rate =
            g[0].dot(v[idx[0]]) + g[1].dot(v[idx[1]]) + g[2].dot(v[idx[2]]) + g[3].dot(v[idx[3]]);
        let gw = [g[0] * cw, g[1] * cw, g[2] * cw, g[3] * cw];
        for k in 0..4 {
            system.diag[idx[k]] += outer(g[k], gw[k]);
            system.kv[idx[k]] += (c * rate) * g[k];
        }
        let slots = model.tet_springs[e];
        for (m, [a, b]) in TET_EDGES.into_iter().enumerate() {
            // Block (spring.i, spring.j) = c G_i G_j^T, and spring.i < spring.j.
            let (i, j) = if idx[a] < idx[b] { (a, b) } else { (b, a) };
            system.off[slots[m] as usize] += outer(g[i], gw[j]);
        }
    }
}

/// `r / len`, or zero for a zero vector.
#[inline]
fn unit(r: DVec3, len: f64) -> DVec3 {
    if len > 0.0 {
        r * (1.0 / len)
    } else {
        DVec3::ZERO
    }
}

/// The object's volume (m^3) and the elastic energy of the volumetric
/// stiffness (J), in one pass over the elements.
pub fn volume_and_bulk_energy(model: &Model, state: &State) -> (f64, f64) {
    let x = &state.positions;
    if let Some(nodal) = &model.nodal_bulk {
        // K V0 / 2 (V / V0 - 1)^2 per node; the shares in the nodal pass's
        // buffer, so that the step's diagnostics allocate nothing.
        return NODAL_SCRATCH.with_borrow_mut(|s| {
            let share = &mut s.volume;
            share.clear();
            share.resize(nodal.rest_volume.len(), 0.0);
            let mut volume = 0.0;
            for tet in &model.tets {
                let [a, b, c, d] = tet.map(|i| i as usize);
                let v = signed_volume(x[a], x[b], x[c], x[d]);
                volume += v;
                for i in [a, b, c, d] {
                    share[i] += 0.25 * v;
                }
            }
            let energy = share
                .iter()
                .zip(&nodal.rest_volume)
                .zip(&nodal.modulus)
                .filter(|((_, v0), _)| **v0 > 0.0)
                .map(|((v, v0), k)| 0.5 * k * v0 * (v / v0 - 1.0).powi(2))
                .sum();
            (volume, energy)
        });
    }
    // A plain loop: the iterator form compiled to code seven times slower.
    let (mut volume, mut squares) = (0.0, 0.0);
    let scale = &model.element_stiffness_scale;
    for (e, (tet, &v0)) in model.tets.iter().zip(&model.rest_volume).enumerate() {
        let [a, b, c, d] = *tet;
        let v = signed_volume(x[a as usize], x[b as usize], x[c as usize], x[d as usize]);
        volume += v;
        let square = (v - v0) * (v - v0) / v0;
        squares += match scale.get(e) {
            Some(s) => square * s,
            None => square,
        };
    }
    (volume, 0.5 * model.bulk_modulus * squares)
}
