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

use glam::DVec3;

use crate::mesh::{TET_EDGES, signed_volume, volume_gradients};
use crate::model::{Model, NodalBulk};
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Adds eq. 11's correction forces and the `bulk_modulus` forces of every
/// element, with their Jacobians, in one pass over the elements.
///
/// Both Jacobians are `c G_a G_b^T` (`c = alpha / g` for eq. 11, `K / V0`
/// for the bulk term), so they share one set of blocks, and their product
/// with the velocities is `c G_a (sum_b G_b . v_b)`.
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    accumulate_elements(model, state, force, system, 0..model.tets.len());
}

/// [`accumulate`] for the elements in `elements` only.
pub fn accumulate_elements(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    if let Some(fem) = &model.fem {
        return crate::forces::fem::accumulate_elements(model, fem, state, force, system, elements);
    }
    let (alpha, bulk) = (model.alpha, model.bulk_modulus);
    if alpha == 0.0 && bulk == 0.0 {
        return;
    }
    let dt2 = system.dt() * system.dt();
    let (x, v) = (&state.positions, &state.velocities);
    NODAL_PRESSURE.with_borrow_mut(|nodal_pressure| {
        if let Some(nodal) = &model.nodal_bulk {
            nodal_pressures(model, nodal, x, nodal_pressure);
        }
        let nodal_pressure = model.nodal_bulk.as_ref().map(|_| &nodal_pressure[..]);
        accumulate_range(model, x, v, nodal_pressure, dt2, force, system, elements);
    });
}

thread_local! {
    /// Each node's pressure for [`accumulate_elements`]: one buffer per
    /// thread (the main and the helper each assemble a share of the
    /// elements, and each needs every node's pressure).
    static NODAL_PRESSURE: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Each node's volume change over its rest volume, times its modulus: `p_i =
/// K_i (V_i / V0_i - 1)`, `V_i` a quarter of each element's volume around i.
/// Returns the object's volume (m^3), summed on the way.
fn nodal_pressures(model: &Model, nodal: &NodalBulk, x: &[DVec3], out: &mut Vec<f64>) -> f64 {
    out.clear();
    out.resize(nodal.rest_volume.len(), 0.0);
    let mut volume = 0.0;
    for tet in &model.tets {
        let [a, b, c, d] = tet.map(|i| i as usize);
        let v = signed_volume(x[a], x[b], x[c], x[d]);
        volume += v;
        for i in [a, b, c, d] {
            out[i] += 0.25 * v;
        }
    }
    for ((p, v0), k) in out.iter_mut().zip(&nodal.rest_volume).zip(&nodal.modulus) {
        *p = if *v0 > 0.0 { k * (*p / v0 - 1.0) } else { 0.0 };
    }
    volume
}

#[allow(clippy::too_many_arguments)]
fn accumulate_range(
    model: &Model,
    x: &[DVec3],
    v: &[DVec3],
    nodal_pressure: Option<&[f64]>,
    dt2: f64,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let (alpha, bulk) = (model.alpha, model.bulk_modulus);
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
            let s = match nodal_pressure {
                // The mean of the four nodes' pressures.
                Some(p) => 0.25 * (p[idx[0]] + p[idx[1]] + p[idx[2]] + p[idx[3]]),
                None => bulk_per_volume * (volume - v0), // K (V / V0 - 1)
            };
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
        // The energy from the pressures: K V0 / 2 (V / V0 - 1)^2 = V0 p^2 / (2 K).
        return NODAL_PRESSURE.with_borrow_mut(|p| {
            let volume = nodal_pressures(model, nodal, x, p);
            let energy = p
                .iter()
                .zip(&nodal.rest_volume)
                .zip(&nodal.modulus)
                .filter(|(_, k)| **k > 0.0)
                .map(|((p, v0), k)| 0.5 * v0 * p * p / k)
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
