//! Self-collision of the object's surface (`[model] self_collision = true`, softgrip; the
//! thesis's last recommendation): boundary particles against boundary facets.
//!
//! A particle closer than the contact thickness `d` (a quarter of the mean edge length) to a
//! facet, on its outer side or less than `d` behind it, is pushed out along the facet's normal
//! by a critically damped penalty spring `k (d - s)`; the reaction goes to the facet's
//! particles by barycentric weights (as a finger's, eq. 37-39). Pairs already within `d` at
//! rest never collide. Broad phase: the facet grid of the finger contact. More:
//! `docs/design/self-collision.md`.

use glam::DVec3;

use crate::geometry::{FacetGrid, closest_point_on_triangle};
use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::{SelfContact, State};

/// Reused buffers.
#[derive(Debug, Default, Clone)]
pub struct SelfScratch {
    grid: FacetGrid,
    candidates: Vec<u32>,
    /// (particle, facet, closest point, weights, facet normal, height).
    found: Vec<(u32, u32, DVec3, [f64; 3], DVec3, f64)>,
}

/// Adds the self-collision forces and Jacobians; records the contacts.
pub fn accumulate(
    model: &Model,
    state: &mut State,
    force: &mut [DVec3],
    system: &mut System,
    scratch: &mut SelfScratch,
) {
    let mut records = std::mem::take(&mut state.self_contacts);
    records.clear();
    let Some(sc) = &model.self_collision else {
        state.self_contacts = records;
        return;
    };
    let x = &state.positions;
    let v = &state.velocities;
    scratch
        .grid
        .rebuild(2.0 * model.edge_length, &model.facets, x);
    let (d, k) = (sc.thickness, sc.stiffness);
    let vel = |dof: usize| crate::forces::velocity_of(state, dof);
    scratch.found.clear();
    for &p in &sc.particles {
        let pi = p as usize;
        let xp = x[pi];
        let pad = DVec3::splat(d);
        scratch
            .grid
            .query(xp - pad, xp + pad, &mut scratch.candidates);
        for &f in &scratch.candidates {
            if sc.excluded.binary_search(&(p, f)).is_ok() {
                continue;
            }
            let tri = model.facets[f as usize];
            let t = tri.map(|i| x[i as usize]);
            let (c, w, _) = closest_point_on_triangle(xp, t[0], t[1], t[2]);
            if xp.distance(c) >= d {
                continue;
            }
            let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
            let s = (xp - c).dot(normal);
            if s <= -d || s >= d {
                continue;
            }
            scratch.found.push((p, f, c, w, normal, s));
        }
    }
    for &(p, f, c, w, n, s) in &scratch.found {
        let pi = p as usize;
        let tri = model.facets[f as usize];
        let idx = tri.map(|i| i as usize);
        // Relative normal speed of the particle over the facet's point.
        let v_facet: DVec3 = (0..3).map(|a| w[a] * v[idx[a]]).sum();
        let rate = (v[pi] - v_facet).dot(n);
        let m = model.mass[pi].min((0..3).map(|a| model.mass[idx[a]]).sum());
        let c_n = 2.0 * (k * m).sqrt();
        let push = k * (d - s) - c_n * rate;
        force[pi] += push * n;
        for a in 0..3 {
            force[idx[a]] -= (w[a] * push) * n;
        }
        // J = [1, -w0, -w1, -w2] (x) n.
        let nn = outer(n, n);
        let (kq, dq) = (nn * k, nn * c_n);
        system.add_diag(pi, kq, dq, &vel);
        for a in 0..3 {
            if w[a] == 0.0 {
                continue;
            }
            system.add_diag(idx[a], kq * (w[a] * w[a]), dq * (w[a] * w[a]), &vel);
            system.add_coupling(pi, idx[a], kq * -w[a], dq * -w[a], &vel);
            let b = (a + 1) % 3;
            let ww = w[a] * w[b];
            if ww != 0.0 {
                system.add_off(
                    &model.springs,
                    model.facet_springs[f as usize][a],
                    idx[a],
                    idx[b],
                    kq * ww,
                    dq * ww,
                    &vel,
                );
            }
        }
        records.push(SelfContact {
            particle: p,
            facet: f,
            point: c,
            normal: n,
            force: push,
            depth: d - s,
        });
    }
    state.self_contacts = records;
}

/// Energy in the self-collision penalty springs (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    let Some(sc) = &model.self_collision else {
        return 0.0;
    };
    state
        .self_contacts
        .iter()
        .map(|c| 0.5 * sc.stiffness * c.depth * c.depth)
        .sum()
}
