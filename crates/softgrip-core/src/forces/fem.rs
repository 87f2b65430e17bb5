//! A continuum alternative to the springs (`[model] elasticity = "neo-hookean"`, softgrip):
//! linear tetrahedra with the stable neo-Hookean energy of Smith, de Goes and Kim (2018),
//! without its log term, `Psi(F) = mu / 2 (|F|^2 - 3) + lambda / 2 (J - a)^2` with
//! `a = 1 + mu / lambda`, per unit rest volume; plus the strain stiffening of `[model]
//! stiffening`, `stiffening_cubic` and `softening` (Yeoh's C20 and C30 forms). The forces are
//! exact; the Jacobian is the Gauss-Newton part of the energy's Hessian (positive
//! semi-definite, so conjugate gradients apply). Everything else (masses, contact, supports,
//! the integrator, the springs' dampers) is shared with the springs; eq. 11's alpha, the bulk
//! term and the spring limits are off.
//!
//! The derivation: `docs/design/neo-hookean.md`.

use glam::{DMat3, DVec3};

use crate::mesh::{TET_EDGES, volume_gradients};
use crate::model::Model;
use crate::model::fem::{FemModel, STABILISATION, Yeoh};
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::State;

/// The deformation gradient of element `e` at positions `p`.
#[inline]
pub fn deformation_gradient(b: &[DVec3; 4], p: [DVec3; 4]) -> DMat3 {
    outer(p[0], b[0]) + outer(p[1], b[1]) + outer(p[2], b[2]) + outer(p[3], b[3])
}

/// `I1 = |F|^2`.
#[inline]
fn first_invariant(f: DMat3) -> f64 {
    f.x_axis.length_squared() + f.y_axis.length_squared() + f.z_axis.length_squared()
}

/// `cof F = J F^-T`, written with cross products so it exists at J = 0.
#[inline]
fn cofactor(f: DMat3) -> DMat3 {
    let (c0, c1, c2) = (f.x_axis, f.y_axis, f.z_axis);
    DMat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1))
}

/// What the stiffening terms act on: `s = max(J^(-2/3) I1 - 3, 0)`, the
/// isochoric invariant, so that a change of volume alone never softens or
/// stiffens; with `J^(-2/3)` and `J^(-2/3) I1`. `(0, 1, 3)` for `J <= 0`.
#[inline]
fn stretch_invariant(f: DMat3) -> (f64, f64, f64) {
    let j = f.determinant();
    if j <= 0.0 {
        return (0.0, 1.0, 3.0);
    }
    let scale = j.powf(-2.0 / 3.0);
    let i1 = scale * first_invariant(f);
    ((i1 - 3.0).max(0.0), scale, i1)
}

/// `d2V / dx_i dx_j` of a tetrahedron's signed volume (`mesh::signed_volume`)
/// for `i != j`: `-[x_d - x_a]_x / 6` with `(a, i, j, d)` an even permutation
/// of the nodes; a skew matrix, and zero for `i == j`.
pub fn volume_hessian(p: [DVec3; 4], i: usize, j: usize) -> DMat3 {
    let mut rest = (0..4).filter(|&n| n != i && n != j);
    let (k, l) = (rest.next().unwrap_or(0), rest.next().unwrap_or(0));
    // The parity of (k, i, j, l) by counting inversions.
    let order = [k, i, j, l];
    let inversions = (0..4)
        .flat_map(|m| (m + 1..4).map(move |n| (m, n)))
        .filter(|&(m, n)| order[m] > order[n])
        .count();
    let (a, d) = if inversions % 2 == 0 { (k, l) } else { (l, k) };
    let w = (p[d] - p[a]) * (1.0 / 6.0);
    // -[w]_x
    DMat3::from_cols(
        DVec3::new(0.0, -w.z, w.y),
        DVec3::new(w.z, 0.0, -w.x),
        DVec3::new(-w.y, w.x, 0.0),
    )
}

/// First Piola-Kirchhoff stress of the energy at `F` (Pa), with the
/// stiffening terms `yeoh` (`Yeoh::default()`: the plain energy):
/// `mu F + lambda (J - a) cof F + Psi_s'(s) dI1bar/dF`,
/// `dI1bar/dF = 2 J^(-2/3) F - 2 I1bar / (3 J) cof F`.
pub fn stress(mu: f64, lambda: f64, yeoh: Yeoh, f: DMat3) -> DMat3 {
    let j = f.determinant();
    let alpha = 1.0 + mu / lambda;
    let cof = cofactor(f);
    let plain = f * mu + cof * (lambda * (j - alpha));
    let (s, scale, i1) = stretch_invariant(f);
    if s <= 0.0 {
        return plain;
    }
    // Psi_s' = mu / 2 (phi - 1).
    let extra = mu * (yeoh.factor(s) - 1.0);
    plain + f * (extra * scale) - cof * (extra * i1 / (3.0 * j))
}

/// The energy per unit rest volume at `F` (Pa), zero at rest.
pub fn energy_density(mu: f64, lambda: f64, yeoh: Yeoh, f: DMat3) -> f64 {
    let alpha = 1.0 + mu / lambda;
    let j = f.determinant();
    let i1 = first_invariant(f);
    let s = if yeoh.is_plain() {
        0.0
    } else {
        stretch_invariant(f).0
    };
    0.5 * mu * (i1 - 3.0)
        + yeoh.energy(mu, s)
        + 0.5 * lambda * ((j - alpha).powi(2) - (1.0 - alpha).powi(2))
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
    let yeoh = fem.yeoh;
    // With nodal pressures most of the stiff `lambda / 2 (J - 1)^2` is a
    // node's (`forces::volume::nodal`); the element keeps `-mu (J - 1)`, the
    // rest of `lambda / 2 (J - a)^2`, and a share `STABILISATION mu` of lambda.
    let nodal = model.nodal_bulk.is_some();
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
        // With nodal pressures an element keeps `STABILISATION mu` of lambda.
        let own = if nodal { STABILISATION * mu } else { lambda };
        let mut volumetric = own * (j - 1.0) + lambda * (1.0 - alpha);
        // The stiffening (see `stress`): a shear factor, a pressure, and the
        // Jacobian's weight along `e_a = dI1bar/dx_a / 2` (0 where it is off).
        let (mut mu_s, mut stiff) = (mu, 0.0);
        let mut e_grad = [DVec3::ZERO; 4];
        if !yeoh.is_plain() {
            let (s, scale, i1) = stretch_invariant(f);
            if s > 0.0 {
                let extra = mu * (yeoh.factor(s) - 1.0);
                mu_s = mu + extra * scale;
                volumetric -= extra * i1 / (3.0 * j);
                stiff = yeoh.slope_weight(v0, mu, s);
                let volume = j * v0;
                for a in 0..4 {
                    e_grad[a] = f * b[a] * scale - g[a] * (i1 / (3.0 * volume));
                }
            }
        }
        let fb = b.map(|ba| f * ba);
        for a in 0..4 {
            force[idx[a]] -= fb[a] * (v0 * mu_s) + g[a] * volumetric;
        }
        let blocks = if model.full_tangent {
            // Newton's tangent: the energy's whole Hessian, indefinite where the element is
            // stressed enough (see `exact_blocks`).
            let yeoh_terms = (stiff != 0.0 || mu_s != mu).then(|| {
                let (s, scale, i1) = stretch_invariant(f);
                let raw_i1 = i1 / scale;
                ExactYeoh {
                    c1: 0.5 * mu * (yeoh.factor(s) - 1.0),
                    slope: yeoh.slope_weight_signed(v0, mu, s),
                    j,
                    raw_i1,
                }
            });
            exact_blocks(
                b, &fb, &g, p, v0, mu_s, own, volumetric, &e_grad, yeoh_terms,
            )
        } else {
            gauss_newton_blocks(b, &g, p, v0, mu, mu_s, own, stiff, &e_grad)
        };
        scatter(model, e, &idx, &blocks, dt2, v, system);
    }
}

/// The Yeoh terms of an element's exact Hessian: `c1 = dPsi/dI`, the slope weight
/// `V0 2 mu phi'` (signed), `J`, and the raw `I1 = |F|^2`.
#[derive(Debug, Clone, Copy)]
struct ExactYeoh {
    c1: f64,
    slope: f64,
    j: f64,
    raw_i1: f64,
}

/// An element's 4 x 4 blocks, `[a][b]` = `-df_a/dx_b`.
type Blocks = [[DMat3; 4]; 4];

/// The Gauss-Newton blocks the time steps use (positive semi-definite, so CG applies): the
/// shear `V0 mu (b_a . b_b) I` with the stiffened shear factor, the volumetric `c G_a G_b^T`,
/// the stiffening's `e_a e_b^T`, and the rest stress's `-mu d2V` (without it the shear block
/// resists a rigid rotation, which implicit Euler then damps).
#[allow(clippy::too_many_arguments)]
fn gauss_newton_blocks(
    b: &[DVec3; 4],
    g: &[DVec3; 4],
    p: [DVec3; 4],
    v0: f64,
    mu: f64,
    mu_s: f64,
    own: f64,
    stiff: f64,
    e_grad: &[DVec3; 4],
) -> Blocks {
    // A softened element's shear factor is positive for any J > 0 (phi >= 1 - q^2 > 0); the
    // Jacobian clamps it where J is tiny.
    let mu_k = mu_s.max(0.0);
    // The weight of `-d2V`: mu at rest, less where softening has lowered the shear factor, so
    // the blocks stay semi-definite.
    let rest_stress = mu_k.min(mu);
    let c = own / v0;
    let mut k = [[DMat3::ZERO; 4]; 4];
    for a in 0..4 {
        for bb in 0..4 {
            let mut block = DMat3::from_diagonal(DVec3::splat(v0 * mu_k * b[a].dot(b[bb])))
                + outer(g[a], g[bb] * c);
            if stiff > 0.0 {
                block += outer(e_grad[a], e_grad[bb] * stiff);
            }
            if a != bb {
                block -= volume_hessian(p, a, bb) * rest_stress;
            }
            k[a][bb] = block;
        }
    }
    k
}

/// The energy's exact Hessian (`docs/design/neo-hookean.md`, "Newton's tangent"): with
/// `Psi = mu / 2 (I1 - 3) + Psi_s(I) + psi(J)`, `I = J^(-2/3) I1`,
/// `-df_a/dx_b = V0 mu_s (b_a . b_b) I + psi'' / V0 G_a G_b^T + p d2V_ab`
/// `+ V0 Psi_s'' dI_a dI_b^T + c1 [-(4/3) J^(-5/3) (G_a (F b_b)^T + (F b_a) G_b^T)`
/// `+ (10/9) I1 J^(-8/3) / V0 G_a G_b^T]`, where `p` (`volumetric`) is every term's
/// `dPsi/dJ` and `mu_s` carries the stiffening's `2 c1 J^(-2/3)`.
#[allow(clippy::too_many_arguments)]
fn exact_blocks(
    b: &[DVec3; 4],
    fb: &[DVec3; 4],
    g: &[DVec3; 4],
    p: [DVec3; 4],
    v0: f64,
    mu_s: f64,
    own: f64,
    volumetric: f64,
    e_grad: &[DVec3; 4],
    yeoh: Option<ExactYeoh>,
) -> Blocks {
    let c = own / v0;
    let mut k = [[DMat3::ZERO; 4]; 4];
    for a in 0..4 {
        for bb in 0..4 {
            let mut block = DMat3::from_diagonal(DVec3::splat(v0 * mu_s * b[a].dot(b[bb])))
                + outer(g[a], g[bb] * c);
            if a != bb {
                block += volume_hessian(p, a, bb) * volumetric;
            }
            if let Some(y) = yeoh {
                // e = dI / 2, so V0 Psi_s'' dI dI^T = slope e e^T.
                block += outer(e_grad[a], e_grad[bb] * y.slope);
                let j53 = y.j.powf(-5.0 / 3.0);
                let j83 = y.j.powf(-8.0 / 3.0);
                block += (outer(g[a], fb[bb]) + outer(fb[a], g[bb])) * (-4.0 / 3.0 * y.c1 * j53)
                    + outer(g[a], g[bb]) * (10.0 / 9.0 * y.c1 * y.raw_i1 * j83 / v0);
            }
            k[a][bb] = block;
        }
    }
    k
}

/// Adds an element's blocks to the system, weighted by `dt2` as they enter A, and their
/// product with the velocities to `Kp v`.
fn scatter(
    model: &Model,
    e: usize,
    idx: &[usize; 4],
    k: &Blocks,
    dt2: f64,
    v: &[DVec3],
    system: &mut System,
) {
    for a in 0..4 {
        system.diag[idx[a]] += k[a][a] * dt2;
        let mut kv = DVec3::ZERO;
        for bb in 0..4 {
            kv += k[a][bb] * v[idx[bb]];
        }
        system.kv[idx[a]] += kv;
    }
    let slots = model.tet_springs[e];
    for (m, [a, bb]) in TET_EDGES.into_iter().enumerate() {
        // Block (spring.i, spring.j), spring.i < spring.j.
        let (i, k2) = if idx[a] < idx[bb] { (a, bb) } else { (bb, a) };
        system.off[slots[m] as usize] += k[i][k2] * dt2;
    }
}

/// The elastic energy of the elements (J), zero at rest; with nodal
/// pressures without their `lambda / 2 (J - 1)^2`, which
/// `forces::volume::volume_and_bulk_energy` counts per node.
pub fn energy(model: &Model, fem: &FemModel, state: &State) -> f64 {
    let x = &state.positions;
    let mut total = 0.0;
    for (e, tet) in model.tets.iter().enumerate() {
        let p = tet.map(|i| x[i as usize]);
        let f = deformation_gradient(&fem.gradients[e], p);
        let (mu, lambda) = (fem.mu[e], fem.lambda[e]);
        let mut density = energy_density(mu, lambda, fem.yeoh, f);
        if model.nodal_bulk.is_some() {
            density -= 0.5 * (lambda - STABILISATION * mu) * (f.determinant() - 1.0).powi(2);
        }
        total += model.rest_volume[e] * density;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::fem::GENT_CAP;

    /// The forces are the energy's gradient (central differences), with
    /// and without stiffening, and the stress vanishes at rest.
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
        let (mu, lambda) = (fem.mu[0], fem.lambda[0]);
        let v0 = 0.01 * 0.012 * 0.009 / 6.0;
        let f_at = |pos: &[DVec3]| {
            deformation_gradient(&fem.gradients[0], [pos[0], pos[1], pos[2], pos[3]])
        };
        let i1 = |f: DMat3| {
            f.x_axis.length_squared() + f.y_axis.length_squared() + f.z_axis.length_squared()
        };
        // One element squeezed, one stretched.
        let squeezed = vec![
            DVec3::new(0.0001, -0.0002, 0.0),
            DVec3::new(0.0093, 0.0004, 0.0002),
            DVec3::new(0.0003, 0.0127, -0.0005),
            DVec3::new(0.0025, 0.0006, 0.0081),
        ];
        let stretched = vec![
            DVec3::new(0.0001, -0.0002, 0.0),
            DVec3::new(0.0112, 0.0004, 0.0002),
            DVec3::new(0.0003, 0.0117, -0.0005),
            DVec3::new(0.0025, 0.0006, 0.0093),
        ];
        // The stiffening acts on both (`J^(-2/3) I1 > 3` but for a change of
        // volume alone).
        let isochoric = |f: DMat3| f.determinant().powf(-2.0 / 3.0) * i1(f);
        assert!(isochoric(f_at(&squeezed)) > 3.001 && isochoric(f_at(&stretched)) > 3.001);
        for deformed in [squeezed, stretched] {
            assert!(f_at(&deformed).determinant() > 0.0);
            // Plain, stiffening alone, and soften-then-stiffen (beta -
            // 2 q sqrt(gamma) < 0).
            for (beta, gamma, q) in [(0.0, 0.0, 0.0), (50.0, 0.0, 0.0), (2.0, 400.0, 0.7)] {
                let yeoh = Yeoh::new(beta, gamma, q);
                assert!(stress(mu, lambda, yeoh, DMat3::IDENTITY).abs_diff_eq(DMat3::ZERO, 1e-9));
                // The energy written out here, not through `energy_density`:
                // `mu (beta s^2 / 12 + gamma s^3 / 54)`, beta with the
                // softening's share.
                let b = beta - 2.0 * q * gamma.sqrt();
                let energy_at = |pos: &[DVec3]| {
                    let f = f_at(pos);
                    let alpha = 1.0 + mu / lambda;
                    let s = (f.determinant().powf(-2.0 / 3.0) * i1(f) - 3.0).max(0.0);
                    v0 * (0.5 * mu * (i1(f) - 3.0)
                        + mu * b / 12.0 * s * s
                        + mu * gamma / 54.0 * s * s * s
                        + 0.5 * lambda * (f.determinant() - alpha).powi(2))
                };
                let p = stress(mu, lambda, yeoh, f_at(&deformed));
                let case = format!("beta {beta} gamma {gamma} q {q}");
                assert_forces_are_the_energys_gradient(&fem, v0, p, &deformed, &energy_at, &case);
            }
        }
    }

    /// The forces of stress `p` on the element at `deformed`, `f_a = -V0 P b_a`, against central
    /// differences of `energy_at`, to 1e-6 of their size.
    fn assert_forces_are_the_energys_gradient(
        fem: &FemModel,
        v0: f64,
        p: DMat3,
        deformed: &[DVec3],
        energy_at: &dyn Fn(&[DVec3]) -> f64,
        case: &str,
    ) {
        for a in 0..4 {
            let analytic = -(p * fem.gradients[0][a]) * v0;
            for k in 0..3 {
                let h = 1e-9;
                let mut plus = deformed.to_vec();
                plus[a][k] += h;
                let mut minus = deformed.to_vec();
                minus[a][k] -= h;
                let numeric = -(energy_at(&plus) - energy_at(&minus)) / (2.0 * h);
                assert!(
                    (numeric - analytic[k]).abs() < 1e-6 * analytic.length().max(1e-9),
                    "{case}, node {a} axis {k}: {numeric} against {}",
                    analytic[k]
                );
            }
        }
    }

    /// Gent's locking (Gent 1996): under an isochoric uniaxial stretch `l` (`F = diag(l,
    /// l^-1/2, l^-1/2)`, `J = 1`) the energy's derivative along the path is Gent's nominal
    /// stress `mu J_m / (J_m - s) (l - l^-2)`, `s = l^2 + 2 / l - 3`, written out here; and the
    /// forces are the gradient of Gent's energy, written out here too, below its cap and past
    /// it (where it goes on along its tangent).
    #[test]
    fn gent_follows_its_analytic_uniaxial_stress_and_its_forces_its_energy() {
        let (mu, lambda, jm) = (20e3, 1e6, 2.0);
        let gent = Yeoh::default().with_gent_limit(jm);
        let along = |l: f64| DMat3::from_diagonal(DVec3::new(l, l.powf(-0.5), l.powf(-0.5)));
        for l in [1.05, 1.2, 1.4, 0.8, 0.7] {
            let s: f64 = l * l + 2.0 / l - 3.0;
            assert!(s < GENT_CAP * jm, "below the cap: {s}");
            let h = 1e-6;
            let numeric = (energy_density(mu, lambda, gent, along(l + h))
                - energy_density(mu, lambda, gent, along(l - h)))
                / (2.0 * h);
            let analytic = mu * jm / (jm - s) * (l - 1.0 / (l * l));
            assert!(
                (numeric - analytic).abs() < 1e-6 * analytic.abs(),
                "stretch {l}: {numeric} against Gent's {analytic}"
            );
        }
        // The forces, at a stretch below the cap and one past it.
        let nodes = vec![
            DVec3::ZERO,
            DVec3::new(0.01, 0.0, 0.0),
            DVec3::new(0.0, 0.012, 0.0),
            DVec3::new(0.002, 0.001, 0.009),
        ];
        let fem = FemModel::new(&nodes, &[[0u32, 1, 2, 3]], &[60e3], 0.45);
        let (mu, lambda) = (fem.mu[0], fem.lambda[0]);
        let f_at = |pos: &[DVec3]| {
            deformation_gradient(&fem.gradients[0], [pos[0], pos[1], pos[2], pos[3]])
        };
        let gent_energy = |k: f64, s: f64| {
            let cap = GENT_CAP / k;
            let curve = |s: f64| -(1.0 - k * s).ln() / k - s;
            if s <= cap {
                curve(s)
            } else {
                let (g, dg) = (k * cap / (1.0 - k * cap), k / (1.0 - k * cap).powi(2));
                curve(cap) + g * (s - cap) + 0.5 * dg * (s - cap) * (s - cap)
            }
        };
        for (limit, stretch) in [(5.0, 1.3), (0.3, 1.4)] {
            let gent = Yeoh::default().with_gent_limit(limit);
            let deformed: Vec<DVec3> = nodes
                .iter()
                .map(|p| DVec3::new(p.x * stretch, p.y / stretch.sqrt(), p.z / stretch.sqrt()))
                .collect();
            let v0 = 0.01 * 0.012 * 0.009 / 6.0;
            let energy_at = |pos: &[DVec3]| {
                let f = f_at(pos);
                let i1 = f.x_axis.length_squared()
                    + f.y_axis.length_squared()
                    + f.z_axis.length_squared();
                let alpha = 1.0 + mu / lambda;
                let s = (f.determinant().powf(-2.0 / 3.0) * i1 - 3.0).max(0.0);
                v0 * (0.5 * mu * (i1 - 3.0)
                    + 0.5 * mu * gent_energy(1.0 / limit, s)
                    + 0.5 * lambda * (f.determinant() - alpha).powi(2))
            };
            let p = stress(mu, lambda, gent, f_at(&deformed));
            let case = format!("J_m {limit}");
            assert_forces_are_the_energys_gradient(&fem, v0, p, &deformed, &energy_at, &case);
        }
    }

    /// `volume_hessian` is the volume gradient's derivative (central
    /// differences), and with the shear block it leaves a rigid rotation
    /// of an element at rest unresisted.
    #[test]
    fn the_volume_hessian_is_the_gradients_derivative() {
        let p = [
            DVec3::new(0.0001, -0.0002, 0.0),
            DVec3::new(0.0112, 0.0004, 0.0002),
            DVec3::new(0.0003, 0.0117, -0.0005),
            DVec3::new(0.0025, 0.0006, 0.0093),
        ];
        for i in 0..4 {
            for j in 0..4 {
                if i == j {
                    continue;
                }
                let h = 1e-7;
                for k in 0..3 {
                    let (mut plus, mut minus) = (p, p);
                    plus[j][k] += h;
                    minus[j][k] -= h;
                    let column =
                        (volume_gradients(plus)[i] - volume_gradients(minus)[i]) / (2.0 * h);
                    let analytic = volume_hessian(p, i, j).col(k);
                    assert!(
                        (column - analytic).length() < 1e-9 * (1.0 + analytic.length()),
                        "({i}, {j}) column {k}: {column} against {analytic}"
                    );
                }
            }
        }
        // At rest: mu (b_a . b_b) I - mu d2V / V0 on a rotation's velocities.
        let fem = FemModel::new(&p, &[[0, 1, 2, 3]], &[60e3], 0.45);
        let (b, mu) = (fem.gradients[0], fem.mu[0]);
        let omega = DVec3::new(0.3, -1.0, 0.7);
        let v = p.map(|x| omega.cross(x));
        let v0 = crate::mesh::signed_volume(p[0], p[1], p[2], p[3]);
        for a in 0..4 {
            let mut kv = DVec3::ZERO;
            for bb in 0..4 {
                kv += v[bb] * (v0 * mu * b[a].dot(b[bb]));
                if bb != a {
                    kv -= volume_hessian(p, a, bb) * v[bb] * mu;
                }
            }
            assert!(kv.length() < 1e-9 * mu * v0 * 1e4, "node {a}: {kv}");
        }
    }

    /// Under a small isochoric uniaxial strain e the stiffening adds the
    /// share `beta e^2 / 2` to the energy, as it does to a spring's
    /// (`k l0^2 (e^2 / 2 + beta e^4 / 4)`); under a volume change alone
    /// (`J^(-2/3) I1 = 3`) it adds nothing.
    #[test]
    fn stiffening_adds_the_springs_share_and_nothing_under_compression_alone() {
        let (mu, lambda) = (20e3, 200e3);
        let beta = 100.0;
        let (plain, stiff) = (Yeoh::default(), Yeoh::new(beta, 0.0, 0.0));
        for e in [0.005f64, 0.01, -0.01] {
            let l = 1.0 + e;
            let f = DMat3::from_diagonal(DVec3::new(l, l.powf(-0.5), l.powf(-0.5)));
            let share =
                energy_density(mu, lambda, stiff, f) / energy_density(mu, lambda, plain, f) - 1.0;
            let expected = beta * e * e / 2.0;
            // The next order: `I1 - 3 = 3 e^2 (1 - 2 e / 3 + ...)`, so the
            // share is off by about 2 |e| / 3 of itself.
            assert!(
                (share - expected).abs() < e.abs() * expected,
                "e {e}: share {share}, beta e^2 / 2 = {expected}"
            );
        }
        let f = DMat3::from_diagonal(DVec3::splat(0.97));
        let soft = Yeoh::new(0.0, 30.0, 0.9);
        for y in [stiff, soft] {
            assert_eq!(stress(mu, lambda, y, f), stress(mu, lambda, plain, f));
            assert_eq!(
                energy_density(mu, lambda, y, f),
                energy_density(mu, lambda, plain, f)
            );
        }
    }

    /// The two-term solid's shear modulus dips to `1 - q^2` of mu at its
    /// lowest (beta 0: `phi = (t - q)^2 + 1 - q^2` in `t = sqrt(gamma) s /
    /// 3`, lowest at `t = q`), never below, for q up to 0.99 and any
    /// gamma; and then rises past 1.
    #[test]
    fn softening_dips_the_shear_modulus_to_one_minus_q_squared_and_never_below() {
        for gamma in [0.5, 3.0, 30.0, 1e4] {
            for q in [0.0, 0.3, 0.9, 0.99] {
                let y = Yeoh::new(0.0, gamma, q);
                // s over t in [0, 4] in steps of 1e-4 (off the lowest
                // point by 5e-5 at most: 2.5e-9 in phi).
                let lowest = (0..=40_000)
                    .map(|i| y.factor(3.0 * (i as f64 * 1e-4) / gamma.sqrt()))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    (lowest - (1.0 - q * q)).abs() < 1e-8 && lowest > 0.0,
                    "gamma {gamma}, q {q}: lowest {lowest}, 1 - q^2 = {}",
                    1.0 - q * q
                );
                // Past the dip, at t = 2 q + 1: back above 1.
                assert!(y.factor(3.0 * (2.0 * q + 1.0) / gamma.sqrt()) > 1.0);
            }
        }
    }
}
