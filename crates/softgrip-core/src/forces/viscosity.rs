//! The material's viscous terms: the neo-Hookean elements' Prony arms ([`accumulate_arms`],
//! viscoelastic creep) and Rayleigh damping.
//!
//! Rayleigh damping, `D = a M + b K` (`[model] rayleigh_mass` a, `rayleigh_stiffness` b,
//! softgrip): material damping that lets a mode of angular frequency w ring at the ratio
//! `zeta = a / (2 w) + b w / 2`, where the springs' dampers (`damping_ratio`) damp each spring's
//! own mode near critically and a beam hardly rings at all.
//!
//! - **Mass-proportional** ([`accumulate_mass`]): each particle's `-a m_i v_i`, Jacobian
//!   `Dp = a m_i I`. It damps every motion, rigid translation and rotation too (a drag against
//!   the ground frame): that is Rayleigh's a. The fingers are not damped.
//! - **Stiffness-proportional**, rotation invariant, zero for rigid motion:
//!   - springs ([`accumulate_dashpots`]): a dashpot of `b k` (k the spring's stiffness, its
//!     rest tangent) along each spring, as the springs' own dampers are: force
//!     `b k (u . (v_j - v_i)) u` on i, Jacobian `b k u u^T`. At rest it is `b` times the
//!     springs' stiffness matrix (not the volume terms', alpha and the bulk term);
//!   - neo-Hookean elements ([`accumulate_elements`]): a Kelvin-Voigt viscosity on the Green
//!     strain rate `E' = sym(F^T F')`, `F' = sum_b v_b b_b^T`: dissipation potential
//!     `R = V0 eta / 2 E':E'`, force `f_a = -dR/dv_a = -V0 eta F E' b_a`, Jacobian
//!     `Dp_ab = V0 eta / 2 [(b_a . b_b) F F^T + (F b_b)(F b_a)^T]` (the Hessian of R, which is
//!     quadratic in the velocities: symmetric positive semi-definite), with `eta = 2 mu b`. At
//!     `F = I` that is `b V0 mu [(b_a . b_b) I + b_b b_a^T]`, exactly b times the shear part of
//!     the linear elastic stiffness; the volumetric part (Lamé's lambda) is not damped.
//!
//! `Dp` enters the system as `dt Dp`. The stiffness-proportional forces also depend on the
//! positions, through u or F; that Jacobian is not symmetric and stays out of the matrix, as
//! for the springs' dampers, but its product with the velocities, `-(df/dx) v`, goes into
//! `Kp v` (the right-hand side's `dt^2 (df/dx) v` of eq. 43): a rotating object's velocity
//! change (its centripetal acceleration) shortens and turns the dashpots, and without that
//! term `dt Dp` alone resists it, so the step damps a rigid rotation (measured once without
//! the term, at dt = 1e-3 s and b = 1e-3 s: a free block spun at 10 rad/s lost 0.278 of its
//! kinetic energy in a revolution against 0.204 undamped; with it the forces' zero holds to
//! first order in dt, and `tests/it/rayleigh.rs` prints 0.3398 against 0.3379 at 20 rad/s).
//! The term is second order in the velocities and zero at rest.
//!
//! The forces vanish at rest, so no equilibrium depends on a or b; they have no energy: what
//! they take is dissipated.

use glam::{DMat3, DVec3};

use crate::mesh::TET_EDGES;
use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// Every Rayleigh term over the whole object (for callers that do not split the work).
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    accumulate_mass(model, state, force, system);
    accumulate_dashpots(model, state, force, system, 0..model.springs.len());
    accumulate_elements(model, state, force, system, 0..model.tets.len());
}

/// The mass-proportional term: `-a m_i v_i` on each particle, `a m_i I` into its diagonal
/// block. Nothing when a is 0.
pub fn accumulate_mass(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let a = model.rayleigh_mass;
    if a == 0.0 {
        return;
    }
    let dt = system.dt();
    let (v, diag) = (&state.velocities, &mut system.diag);
    for (((f, d), &m), v) in force
        .iter_mut()
        .zip(diag.iter_mut())
        .zip(&model.mass)
        .zip(v)
    {
        let c = a * m;
        *f -= *v * c;
        *d += DMat3::from_diagonal(DVec3::splat(c * dt));
    }
}

/// The springs' stiffness-proportional dashpots, `b k` along each spring in `springs` (slots
/// of `model.springs`). Nothing when b is 0 or the elasticity is the elements'.
pub fn accumulate_dashpots(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    springs: std::ops::Range<usize>,
) {
    let b = model.rayleigh_stiffness;
    if b == 0.0 || model.fem.is_some() {
        return;
    }
    let (x, v) = (&state.positions, &state.velocities);
    let dt = system.dt();
    for slot in springs {
        let s = &model.springs[slot];
        let Some((i, j, l, u)) = super::springs::axis(x, s) else {
            continue;
        };
        let c = b * s.stiffness;
        let dv = v[j] - v[i];
        let rate = u.dot(dv);
        let f = (c * rate) * u;
        force[i] += f;
        force[j] -= f;
        // Blocks (i, i) and (j, j) get +W, block (i, j) = (spring.i, spring.j) -W, W = dt Dp.
        let w = outer(u, u) * (c * dt);
        system.diag[i] += w;
        system.diag[j] += w;
        system.off[slot] -= w;
        // The force's change as the spring turns with the velocities, (df_i/dx) v: see
        // the module docs.
        let turning = (u * (dv.length_squared() - rate * rate) + (dv - u * rate) * rate) * (c / l);
        system.kv[i] -= turning;
        system.kv[j] += turning;
    }
}

/// The elements' viscous terms for the elements in `elements`: their Maxwell arms
/// ([`accumulate_arms`]) and their Kelvin-Voigt viscosity (nothing when b is 0 or the elasticity
/// is the springs').
pub fn accumulate_elements(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    accumulate_arms(model, state, force, system, elements.clone());
    accumulate_element_damping(model, state, force, system, elements);
}

/// The neo-Hookean elements' Kelvin-Voigt viscosity for the elements in `elements` (nothing
/// when b is 0 or the elasticity is the springs').
pub fn accumulate_element_damping(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let b = model.rayleigh_stiffness;
    let Some(fem) = &model.fem else { return };
    if b == 0.0 {
        return;
    }
    let (x, v) = (&state.positions, &state.velocities);
    let dt = system.dt();
    for e in elements {
        let idx = model.tets[e].map(|i| i as usize);
        let g = &fem.gradients[e];
        let f = super::fem::deformation_gradient(g, idx.map(|i| x[i]));
        let f_rate = super::fem::deformation_gradient(g, idx.map(|i| v[i]));
        let e_rate = symmetric_part(f.transpose() * f_rate);
        // V0 eta, eta = 2 mu b.
        let c = model.rest_volume[e] * 2.0 * fem.mu[e] * b;
        let fe = f * e_rate;
        let fb = g.map(|ga| f * ga);
        let ff = f * f.transpose();
        let half = 0.5 * c * dt;
        // The force's change as the element moves with the velocities, (df_a/dx) v =
        // -V0 eta [F' E' + F F'^T F'] b_a (F' = dF along v): see the module docs.
        let turning = f_rate * e_rate + f * (f_rate.transpose() * f_rate);
        for a in 0..4 {
            force[idx[a]] -= fe * g[a] * c;
            system.diag[idx[a]] += (ff * g[a].dot(g[a]) + outer(fb[a], fb[a])) * half;
            system.kv[idx[a]] += turning * g[a] * c;
        }
        let slots = model.tet_springs[e];
        for (m, [p, q]) in TET_EDGES.into_iter().enumerate() {
            // Block (spring.i, spring.j), spring.i < spring.j: Dp_ik has (F b_k)(F b_i)^T.
            let (i, k) = if idx[p] < idx[q] { (p, q) } else { (q, p) };
            system.off[slots[m] as usize] += (ff * g[i].dot(g[k]) + outer(fb[k], fb[i])) * half;
        }
    }
}

/// The neo-Hookean elements' Prony term (`[model] prony_g` g, `prony_tau` tau): a standard
/// linear solid as the springs' ([`super::springs::spring_law`]), the elements' own shear modulus
/// lowered to `(1 - g) mu` (at the model's build) and in parallel a Maxwell arm on the Green
/// strain, energy `V0 mu_g |E - E_v|^2` with `mu_g = g mu` (so `2 mu_g` per unit strain, a
/// Saint Venant-Kirchhoff arm without lambda), its viscous strain `E_v` relaxing towards E with
/// time constant tau. Implicit Euler over the step, `E_v' = (E_v + a E) / (1 + a)`, `a = dt /
/// tau`, makes the arm a spring of modulus `mu_g / (1 + a)` from the step's start `E_v`. A held
/// shear relaxes to `1 - g` of its stress with time constant tau; a constant load creeps with
/// `tau / (1 - g)` in the incompressible limit. The volumetric response does not relax.
/// Jacobian: the arm's Gauss-Newton part, `V0 c [(b_a . b_b) F F^T + (F b_b)(F b_a)^T]` with
/// `c = mu_g / (1 + a)` (positive semi-definite); its stress term `(b_a^T S b_b) I` is left out,
/// as small as the arm's stress.
pub fn accumulate_arms(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let Some(fem) = &model.fem else { return };
    let g_share = model.spring_law.prony_g;
    if g_share == 0.0 || state.maxwell.len() != 6 * model.tets.len() {
        return;
    }
    let dt = system.dt();
    let dt2 = dt * dt;
    let (x, v) = (&state.positions, &state.velocities);
    let relax = 1.0 + model.dt / model.spring_law.prony_tau;
    for e in elements {
        let idx = model.tets[e].map(|i| i as usize);
        let g = &fem.gradients[e];
        let f = super::fem::deformation_gradient(g, idx.map(|i| x[i]));
        let strain = green_strain(f);
        let viscous = unpack(&state.maxwell[6 * e..6 * e + 6]);
        // The arm's modulus `mu_g / (1 + a)`, mu_g = g mu = g / (1 - g) times the elements'
        // lowered shear modulus; V0 times it.
        let c = model.rest_volume[e] * fem.mu[e] * g_share / (1.0 - g_share) / relax;
        let stress = (strain - viscous) * (2.0 * c); // V0 S
        let fb = g.map(|ga| f * ga);
        let ff = f * f.transpose();
        for a in 0..4 {
            force[idx[a]] -= f * (stress * g[a]);
        }
        let block = |a: usize, b: usize| (ff * g[a].dot(g[b]) + outer(fb[b], fb[a])) * c;
        for a in 0..4 {
            system.diag[idx[a]] += block(a, a) * dt2;
            let mut kv = DVec3::ZERO;
            for bb in 0..4 {
                kv += block(a, bb) * v[idx[bb]];
            }
            system.kv[idx[a]] += kv;
        }
        let slots = model.tet_springs[e];
        for (m, [p, q]) in TET_EDGES.into_iter().enumerate() {
            let (i, k) = if idx[p] < idx[q] { (p, q) } else { (q, p) };
            system.off[slots[m] as usize] += block(i, k) * dt2;
        }
    }
}

/// The energy the elements' Maxwell arms hold, `sum V0 mu_g |E - E_v|^2` (J). Part of the
/// object's energy: without it an arm giving back what it stored reads as the energy rising
/// with no input, and the divergence watch stopped a swinging viscoelastic beam.
pub fn arm_energy(model: &Model, state: &State) -> f64 {
    let Some(fem) = &model.fem else { return 0.0 };
    let g_share = model.spring_law.prony_g;
    if g_share == 0.0 || state.maxwell.len() != 6 * model.tets.len() {
        return 0.0;
    }
    let x = &state.positions;
    model
        .tets
        .iter()
        .enumerate()
        .map(|(e, tet)| {
            let f = super::fem::deformation_gradient(&fem.gradients[e], tet.map(|i| x[i as usize]));
            let d = green_strain(f) - unpack(&state.maxwell[6 * e..6 * e + 6]);
            let mu_g = fem.mu[e] * g_share / (1.0 - g_share);
            model.rest_volume[e] * mu_g * d.to_cols_array().iter().map(|v| v * v).sum::<f64>()
        })
        .sum()
}

/// After a step: each element's viscous strain moves towards its present Green strain,
/// `E_v = (E_v + a E) / (1 + a)`, `a = dt / tau` (the step [`accumulate_arms`] assumed).
pub fn relax_elements(model: &Model, state: &mut State) {
    let Some(fem) = &model.fem else { return };
    if !model.spring_law.is_viscoelastic() {
        return;
    }
    if state.maxwell.len() != 6 * model.tets.len() {
        state.maxwell = vec![0.0; 6 * model.tets.len()];
    }
    let a = model.dt / model.spring_law.prony_tau;
    let x = &state.positions;
    for (e, tet) in model.tets.iter().enumerate() {
        let f = super::fem::deformation_gradient(&fem.gradients[e], tet.map(|i| x[i as usize]));
        let strain = green_strain(f);
        let slot = &mut state.maxwell[6 * e..6 * e + 6];
        let viscous = (unpack(slot) + strain * a) * (1.0 / (1.0 + a));
        slot.copy_from_slice(&pack(viscous));
    }
}

/// The Green strain `(F^T F - I) / 2`.
#[inline]
fn green_strain(f: DMat3) -> DMat3 {
    (f.transpose() * f - DMat3::IDENTITY) * 0.5
}

/// A symmetric matrix from its six entries xx, yy, zz, xy, xz, yz.
#[inline]
fn unpack(s: &[f64]) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(s[0], s[3], s[4]),
        DVec3::new(s[3], s[1], s[5]),
        DVec3::new(s[4], s[5], s[2]),
    )
}

/// The six entries of a symmetric matrix (its upper triangle).
#[inline]
fn pack(m: DMat3) -> [f64; 6] {
    [
        m.x_axis.x, m.y_axis.y, m.z_axis.z, m.y_axis.x, m.z_axis.x, m.z_axis.y,
    ]
}

/// `(A + A^T) / 2`.
#[inline]
fn symmetric_part(a: DMat3) -> DMat3 {
    (a + a.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::fem::FemModel;

    /// One neo-Hookean element: the viscous force is minus the gradient of the dissipation
    /// potential `R = V0 eta / 2 E':E'` by the velocities, its Jacobian that gradient's
    /// derivative (central differences; R is quadratic, so they are exact to rounding), the
    /// force is zero for a rigid rotation of a deformed element, and at F = I the Jacobian is
    /// b times the shear part of the linear elastic stiffness.
    /// One spring's dashpot: `b k` times the stretching rate along it, its velocity
    /// Jacobian `b k u u^T`, its `-(df/dx) v` by differences along the motion; nothing for a
    /// rigid rotation.
    #[test]
    fn a_dashpot_follows_its_spring() {
        let x = vec![DVec3::ZERO, DVec3::new(0.01, 0.004, -0.002)];
        let mut model = Model::from_particles(
            x.clone(),
            vec![1e-3; 2],
            vec![false; 2],
            &[(0, 1, 50.0, 0.0)],
            DVec3::ZERO,
            1.0,
        );
        model.rayleigh_stiffness = 3e-3;
        let c = 3e-3 * 50.0;
        let run = |x: &[DVec3], v: &[DVec3]| {
            let mut state = State::initial(&model);
            state.positions = x.to_vec();
            state.velocities = v.to_vec();
            let mut system = System::default();
            system.begin_partial(&model, 1.0);
            let mut force = vec![DVec3::ZERO; 2];
            accumulate(&model, &state, &mut force, &mut system);
            (force, system)
        };
        let v = vec![DVec3::new(0.1, -0.3, 0.2), DVec3::new(-0.2, 0.1, 0.4)];
        let (force, system) = run(&x, &v);
        let u = (x[1] - x[0]).normalize();
        let expected = u * (c * u.dot(v[1] - v[0]));
        assert!(force[0].abs_diff_eq(expected, 1e-15) && force[1] == -force[0]);
        let w = outer(u, u) * c;
        assert!(system.diag[0].abs_diff_eq(w, 1e-15) && system.off[0].abs_diff_eq(-w, 1e-15));
        let h = 1e-7;
        let along = |t: f64| -> Vec<DVec3> { x.iter().zip(&v).map(|(x, v)| *x + *v * t).collect() };
        let (fp, _) = run(&along(h), &v);
        let (fm, _) = run(&along(-h), &v);
        for a in 0..2 {
            let numeric = -(fp[a] - fm[a]) / (2.0 * h);
            assert!(
                numeric.abs_diff_eq(system.kv[a], 1e-6 * system.kv[a].length()),
                "{numeric} against {}",
                system.kv[a]
            );
        }
        let spin = DVec3::new(1.0, 2.0, -0.5);
        let rigid: Vec<DVec3> = x.iter().map(|p| spin.cross(*p) + DVec3::Y).collect();
        let (force, _) = run(&x, &rigid);
        assert!(force[0].length() < 1e-15, "{force:?}");
    }

    fn largest(m: DMat3) -> f64 {
        m.to_cols_array().iter().fold(0.0, |a, x| a.max(x.abs()))
    }

    /// One neo-Hookean element (E 60 kPa, nu 0.45) and its six edges, and a deformed state of it.
    fn one_element() -> (Model, Vec<DVec3>) {
        let rest = vec![
            DVec3::ZERO,
            DVec3::new(0.01, 0.0, 0.0),
            DVec3::new(0.0, 0.012, 0.0),
            DVec3::new(0.002, 0.001, 0.009),
        ];
        let tets = vec![[0u32, 1, 2, 3]];
        let edges: Vec<(u32, u32, f64, f64)> = TET_EDGES
            .iter()
            .map(|&[a, b]| (a as u32, b as u32, 0.0, 0.0))
            .collect();
        let mut model = Model::from_particles(
            rest.clone(),
            vec![1e-3; 4],
            vec![false; 4],
            &edges,
            DVec3::ZERO,
            1e-3,
        );
        let slots = TET_EDGES.map(|[a, b]| {
            (model.springs.iter())
                .position(|s| (s.i, s.j) == (a as u32, b as u32))
                .expect("every edge has a spring") as u32
        });
        model.fem = Some(FemModel::new(&rest, &tets, &[60e3], 0.45));
        model.tets = tets;
        model.rest_volume = vec![0.01 * 0.012 * 0.009 / 6.0];
        model.tet_springs = vec![slots];
        let deformed = vec![
            DVec3::new(0.0001, -0.0002, 0.0),
            DVec3::new(0.0112, 0.0004, 0.0002),
            DVec3::new(0.0003, 0.0117, -0.0005),
            DVec3::new(0.0025, 0.0006, 0.0093),
        ];
        (model, deformed)
    }

    /// Block (a, b) of the one element's system matrix.
    fn block_of(model: &Model, system: &System, a: usize, b: usize) -> DMat3 {
        if a == b {
            return system.diag[a];
        }
        let edge = TET_EDGES
            .iter()
            .position(|e| *e == [a.min(b), a.max(b)])
            .expect("an edge");
        let off = system.off[model.tet_springs[0][edge] as usize];
        if a < b { off } else { off.transpose() }
    }

    #[test]
    fn element_viscosity_is_the_gradient_of_its_dissipation_and_spares_rigid_motion() {
        let (mut model, deformed) = one_element();
        let fem = model.fem.as_ref().expect("an element");
        let (mu, grads, v0) = (fem.mu[0], fem.gradients[0], model.rest_volume[0]);
        let b = 2e-3;
        model.rayleigh_stiffness = b;
        let eta = 2.0 * mu * b;
        let velocities = vec![
            DVec3::new(0.1, -0.2, 0.05),
            DVec3::new(-0.3, 0.1, 0.2),
            DVec3::new(0.02, 0.15, -0.1),
            DVec3::new(0.2, -0.05, 0.3),
        ];
        let potential = |v: &[DVec3]| {
            let f = super::super::fem::deformation_gradient(
                &grads,
                [deformed[0], deformed[1], deformed[2], deformed[3]],
            );
            let fr = super::super::fem::deformation_gradient(&grads, [v[0], v[1], v[2], v[3]]);
            let er = symmetric_part(f.transpose() * fr);
            let sq: f64 = er.to_cols_array().iter().map(|x| x * x).sum();
            0.5 * v0 * eta * sq
        };
        let assemble = |x: &[DVec3], v: &[DVec3]| {
            let mut state = State::initial(&model);
            state.positions = x.to_vec();
            state.velocities = v.to_vec();
            let mut system = System::default();
            system.begin_partial(&model, 1.0);
            let mut force = vec![DVec3::ZERO; 4];
            accumulate(&model, &state, &mut force, &mut system);
            (force, system)
        };
        let (force, system) = assemble(&deformed, &velocities);
        // Block (a, b) of Dp from the system (dt = 1, no mass).
        let block = |a: usize, bb: usize| block_of(&model, &system, a, bb);
        let h = 1e-6;
        for a in 0..4 {
            for k in 0..3 {
                let (mut plus, mut minus) = (velocities.clone(), velocities.clone());
                plus[a][k] += h;
                minus[a][k] -= h;
                let numeric = -(potential(&plus) - potential(&minus)) / (2.0 * h);
                assert!(
                    (numeric - force[a][k]).abs() < 1e-7 * force[a].length(),
                    "node {a} axis {k}: {numeric} against {}",
                    force[a][k]
                );
                // Column (b, k) of Dp: -(f(v + h e) - f(v - h e)) / 2h.
                let (fp, _) = assemble(&deformed, &plus);
                let (fm, _) = assemble(&deformed, &minus);
                for bb in 0..4 {
                    let numeric = -(fp[bb] - fm[bb]) / (2.0 * h);
                    let analytic = block(bb, a).col(k);
                    assert!(
                        numeric.abs_diff_eq(analytic, 1e-7 * largest(block(bb, bb))),
                        "Dp ({bb}, {a}) column {k}: {numeric} against {analytic}"
                    );
                }
            }
        }
        // Kp v = -(df/dx) v, along the positions moved with the velocities.
        let moved = |t: f64| -> Vec<DVec3> {
            (deformed.iter().zip(&velocities))
                .map(|(x, v)| *x + *v * t)
                .collect()
        };
        let h = 1e-7;
        let (fp, _) = assemble(&moved(h), &velocities);
        let (fm, _) = assemble(&moved(-h), &velocities);
        for a in 0..4 {
            let numeric = -(fp[a] - fm[a]) / (2.0 * h);
            assert!(
                numeric.abs_diff_eq(system.kv[a], 1e-6 * system.kv[a].length()),
                "Kp v at {a}: {numeric} against {}",
                system.kv[a]
            );
        }
        // A rigid rotation of the deformed element: no force.
        let w = DVec3::new(0.3, -1.2, 0.7);
        let spin: Vec<DVec3> = deformed.iter().map(|p| w.cross(*p) + DVec3::X).collect();
        let (force, _) = assemble(&deformed, &spin);
        let scale = eta * v0 * w.length() * grads[0].length();
        assert!(
            force.iter().all(|f| f.length() < 1e-12 * scale),
            "{force:?}"
        );
        // At rest: b times the shear part of the linear stiffness.
        let (_, system) = assemble(&model.rest_positions, &velocities);
        let c = v0 * mu * b;
        for a in 0..4 {
            let expected =
                (DMat3::IDENTITY * grads[a].dot(grads[a]) + outer(grads[a], grads[a])) * c;
            assert!(system.diag[a].abs_diff_eq(expected, 1e-12 * largest(expected)));
        }
    }

    /// One element's Maxwell arm: its force is minus the gradient of its energy
    /// `V0 c |E - E_v|^2` (central differences), and where the arm is unstressed (E = E_v) its
    /// blocks are the force's exact derivative.
    #[test]
    fn an_element_arm_is_the_gradient_of_its_energy() {
        let (mut model, deformed) = one_element();
        let fem = model.fem.as_ref().expect("an element");
        let (grads, v0) = (fem.gradients[0], model.rest_volume[0]);
        let c = v0 * fem.mu[0] * 0.4 / 0.6 / (1.0 + 1e-3 / 0.05);
        model.spring_law.prony_g = 0.4;
        model.spring_law.prony_tau = 0.05;
        let strain = |x: &[DVec3]| {
            green_strain(super::super::fem::deformation_gradient(
                &grads,
                [x[0], x[1], x[2], x[3]],
            ))
        };
        let viscous = [0.01, -0.02, 0.005, 0.004, -0.003, 0.002];
        let energy = |x: &[DVec3]| {
            let d = strain(x) - unpack(&viscous);
            c * d.to_cols_array().iter().map(|v| v * v).sum::<f64>()
        };
        let assemble = |x: &[DVec3], maxwell: &[f64]| {
            let mut state = State::initial(&model);
            state.positions = x.to_vec();
            state.maxwell = maxwell.to_vec();
            let mut system = System::default();
            system.begin_partial(&model, 1.0);
            let mut force = vec![DVec3::ZERO; 4];
            accumulate_arms(&model, &state, &mut force, &mut system, 0..1);
            (force, system)
        };
        let (force, _) = assemble(&deformed, &viscous);
        // The energy the arm stores is the step's times 1 + dt / tau (the step's arm is softer).
        let mut state = State::initial(&model);
        state.positions = deformed.clone();
        state.maxwell = viscous.to_vec();
        let stored = arm_energy(&model, &state) / (1.0 + model.dt / 0.05);
        assert!(
            (stored - energy(&deformed)).abs() < 1e-12 * stored,
            "{stored:e} against {:e}",
            energy(&deformed)
        );
        let h = 1e-8;
        for a in 0..4 {
            for k in 0..3 {
                let shifted = |t: f64| {
                    let mut x = deformed.clone();
                    x[a][k] += t;
                    energy(&x)
                };
                let numeric = -(shifted(h) - shifted(-h)) / (2.0 * h);
                assert!(
                    (numeric - force[a][k]).abs() < 1e-6 * force[a].length(),
                    "node {a}, axis {k}: {numeric} against {}",
                    force[a][k]
                );
            }
        }
        // Unstressed: E_v = E.
        let held = pack(strain(&deformed));
        let (force, system) = assemble(&deformed, &held);
        assert!(force.iter().all(|f| f.length() < 1e-12), "{force:?}");
        let block = |a: usize, b: usize| block_of(&model, &system, a, b);
        for b in 0..4 {
            for k in 0..3 {
                let along = |t: f64| {
                    let mut x = deformed.clone();
                    x[b][k] += t;
                    assemble(&x, &held).0
                };
                let (fp, fm) = (along(h), along(-h));
                for a in 0..4 {
                    // K_ab e_k = -df_a / dx_bk.
                    let numeric = -(fp[a] - fm[a]) / (2.0 * h);
                    let exact = block(a, b).col(k);
                    assert!(
                        numeric.abs_diff_eq(exact, 1e-6 * largest(block(a, a))),
                        "block ({a}, {b}), column {k}: {numeric} against {exact}"
                    );
                }
            }
        }
    }
}
