//! A continuum alternative to the springs (`[model] elasticity =
//! "neo-hookean"`, softgrip): linear tetrahedra with the stable neo-Hookean
//! energy of Smith, de Goes and Kim (2018), without its log term,
//!
//! `Psi(F) = mu / 2 (|F|^2 - 3) + lambda / 2 (J - a)^2`, `a = 1 + mu / lambda`,
//!
//! per unit rest volume, `F` the element's deformation gradient and `J =
//! det F`. It is at rest at `F = I`, stays finite and pushes back through
//! inversion (`J <= 0`), and linearises to Hooke's law with Lamé constants
//! `(mu, lambda - mu)`: so `mu` is the shear modulus `E / (2 (1 + nu))` and
//! `lambda` the Lamé constant plus `mu`.
//!
//! Forces: `f_a = -V0 P b_a` with `P = mu F + lambda (J - a) cof F` and `b_a`
//! the gradient of the linear shape function of node a (`F = sum x_a
//! b_a^T`), that is `f_a = -V0 mu F b_a - lambda (J - a) G_a` with `G_a =
//! dV/dx_a`. Jacobian: `V0 mu (b_a . b_b) I + lambda / V0 G_a G_b^T`, the
//! Gauss-Newton part of the energy's Hessian (the term `lambda (J - a) d2J`,
//! indefinite, is left out, as for the bulk term), positive semi-definite,
//! so conjugate gradients apply. The forces are exact; only the implicit
//! step's linearisation is approximate.
//!
//! The model shares everything else with the springs: masses, contact,
//! supports, the implicit integrator, and the springs' dampers (each edge's
//! `zeta 2 sqrt(k mu)` damps it, as for the springs). The lattice's own
//! corrections (eq. 11's alpha, the bulk term, the spring limits) do not
//! apply to it and are off.

use glam::{DMat3, DVec3};

use crate::mesh::TET_EDGES;
use crate::model::Model;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

use super::volume::volume_gradients;

/// The constant data of the neo-Hookean elements.
#[derive(Debug, Clone, PartialEq)]
pub struct FemModel {
    /// Shape-function gradients `b_a` of each element's four nodes (1/m).
    pub gradients: Vec<[DVec3; 4]>,
    /// Each element's `mu` and `lambda` (Pa), see the module docs.
    pub mu: Vec<f64>,
    pub lambda: Vec<f64>,
}

impl FemModel {
    /// From the rest positions of the elements and each element's Young's
    /// modulus, with one Poisson ratio.
    pub fn new(
        nodes: &[DVec3],
        tets: &[[u32; 4]],
        young_modulus: &[f64],
        poisson_ratio: f64,
    ) -> FemModel {
        let gradients = tets
            .iter()
            .map(|t| {
                let x = t.map(|i| nodes[i as usize]);
                let dm = DMat3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]);
                // F = Ds Dm^-1: node a (1..3) enters through row a of Dm^-1.
                let inv = dm.inverse().transpose();
                let (b1, b2, b3) = (inv.x_axis, inv.y_axis, inv.z_axis);
                [-(b1 + b2 + b3), b1, b2, b3]
            })
            .collect();
        let nu = poisson_ratio;
        let mu: Vec<f64> = young_modulus
            .iter()
            .map(|e| e / (2.0 * (1.0 + nu)))
            .collect();
        let lambda = young_modulus
            .iter()
            .zip(&mu)
            .map(|(e, m)| e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)) + m)
            .collect();
        FemModel {
            gradients,
            mu,
            lambda,
        }
    }
}

/// The deformation gradient of element `e` at positions `p`.
#[inline]
pub fn deformation_gradient(b: &[DVec3; 4], p: [DVec3; 4]) -> DMat3 {
    outer(p[0], b[0]) + outer(p[1], b[1]) + outer(p[2], b[2]) + outer(p[3], b[3])
}

/// First Piola-Kirchhoff stress of the energy at `F` (Pa).
pub fn stress(mu: f64, lambda: f64, f: DMat3) -> DMat3 {
    let j = f.determinant();
    let alpha = 1.0 + mu / lambda;
    // cof F = J F^-T, written with cross products so it exists at J = 0.
    let (c0, c1, c2) = (f.x_axis, f.y_axis, f.z_axis);
    let cof = DMat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    f * mu + cof * (lambda * (j - alpha))
}

/// Adds the elastic forces and Jacobian blocks of the elements in
/// `elements`.
pub fn accumulate_elements(
    model: &Model,
    fem: &FemModel,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    elements: std::ops::Range<usize>,
) {
    let dt2 = system.dt() * system.dt();
    let (x, v) = (&state.positions, &state.velocities);
    for e in elements {
        let tet = model.tets[e];
        let idx = tet.map(|i| i as usize);
        let p = idx.map(|i| x[i]);
        let b = &fem.gradients[e];
        let (mu, lambda) = (fem.mu[e], fem.lambda[e]);
        let v0 = model.rest_volume[e];
        let f = deformation_gradient(b, p);
        let g = volume_gradients(p);
        let j = g[3].dot(p[3] - p[0]) / v0; // V / V0 = det F
        let alpha = 1.0 + mu / lambda;
        let volumetric = lambda * (j - alpha);
        for a in 0..4 {
            force[idx[a]] -= (f * b[a]) * (v0 * mu) + g[a] * volumetric;
        }
        // Blocks weighted by dt^2 as they enter A.
        let c = lambda / v0;
        let rate =
            g[0].dot(v[idx[0]]) + g[1].dot(v[idx[1]]) + g[2].dot(v[idx[2]]) + g[3].dot(v[idx[3]]);
        for a in 0..4 {
            let shear = v0 * mu * b[a].dot(b[a]);
            system.diag[idx[a]] +=
                DMat3::from_diagonal(DVec3::splat(shear * dt2)) + outer(g[a], g[a] * (c * dt2));
            // Kp v: the shear part sum_b V0 mu (b_a . b_b) v_b, the volumetric c G_a (G . v).
            let mut kv = g[a] * (c * rate);
            for (bb, &ib) in b.iter().zip(&idx) {
                kv += v[ib] * (v0 * mu * b[a].dot(*bb));
            }
            system.kv[idx[a]] += kv;
        }
        let slots = model.tet_springs[e];
        for (m, [a, bb]) in TET_EDGES.into_iter().enumerate() {
            // Block (spring.i, spring.j), spring.i < spring.j.
            let (i, k) = if idx[a] < idx[bb] { (a, bb) } else { (bb, a) };
            let shear = v0 * mu * b[i].dot(b[k]) * dt2;
            system.off[slots[m] as usize] +=
                DMat3::from_diagonal(DVec3::splat(shear)) + outer(g[i], g[k] * (c * dt2));
        }
    }
}

/// The elastic energy of the elements (J), zero at rest.
pub fn energy(model: &Model, fem: &FemModel, state: &State) -> f64 {
    let x = &state.positions;
    let mut total = 0.0;
    for (e, tet) in model.tets.iter().enumerate() {
        let p = tet.map(|i| x[i as usize]);
        let f = deformation_gradient(&fem.gradients[e], p);
        let (mu, lambda) = (fem.mu[e], fem.lambda[e]);
        let alpha = 1.0 + mu / lambda;
        let j = f.determinant();
        let norm2 =
            f.x_axis.length_squared() + f.y_axis.length_squared() + f.z_axis.length_squared();
        let psi =
            0.5 * mu * (norm2 - 3.0) + 0.5 * lambda * ((j - alpha).powi(2) - (1.0 - alpha).powi(2));
        total += model.rest_volume[e] * psi;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The forces are the energy's gradient (central differences), and the
    /// stress vanishes at rest.
    #[test]
    fn forces_are_the_gradient_of_the_energy() {
        let nodes = vec![
            DVec3::ZERO,
            DVec3::new(0.01, 0.0, 0.0),
            DVec3::new(0.0, 0.012, 0.0),
            DVec3::new(0.002, 0.001, 0.009),
        ];
        let tets = vec![[0u32, 1, 2, 3]];
        let fem = FemModel::new(&nodes, &tets, &[60e3], 0.45);
        assert!(stress(fem.mu[0], fem.lambda[0], DMat3::IDENTITY).abs_diff_eq(DMat3::ZERO, 1e-9));
        let deformed = vec![
            DVec3::new(0.0001, -0.0002, 0.0),
            DVec3::new(0.0093, 0.0004, 0.0002),
            DVec3::new(0.0003, 0.0127, -0.0005),
            DVec3::new(0.0025, 0.0006, 0.0081),
        ];
        let energy_at = |pos: &[DVec3]| {
            let b = &fem.gradients[0];
            let f = deformation_gradient(b, [pos[0], pos[1], pos[2], pos[3]]);
            let (mu, lambda) = (fem.mu[0], fem.lambda[0]);
            let alpha = 1.0 + mu / lambda;
            let norm2 =
                f.x_axis.length_squared() + f.y_axis.length_squared() + f.z_axis.length_squared();
            let v0 = 0.01 * 0.012 * 0.009 / 6.0;
            v0 * (0.5 * mu * (norm2 - 3.0) + 0.5 * lambda * (f.determinant() - alpha).powi(2))
        };
        // f_a = -V0 P b_a
        let v0 = 0.01 * 0.012 * 0.009 / 6.0;
        let f = deformation_gradient(
            &fem.gradients[0],
            [deformed[0], deformed[1], deformed[2], deformed[3]],
        );
        let p = stress(fem.mu[0], fem.lambda[0], f);
        for a in 0..4 {
            let analytic = -(p * fem.gradients[0][a]) * v0;
            for k in 0..3 {
                let h = 1e-9;
                let mut plus = deformed.clone();
                plus[a][k] += h;
                let mut minus = deformed.clone();
                minus[a][k] -= h;
                let numeric = -(energy_at(&plus) - energy_at(&minus)) / (2.0 * h);
                assert!(
                    (numeric - analytic[k]).abs() < 1e-6 * analytic.length().max(1e-9),
                    "node {a} axis {k}: {numeric} against {}",
                    analytic[k]
                );
            }
        }
    }
}
