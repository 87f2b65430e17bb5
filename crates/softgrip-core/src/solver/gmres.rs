//! Flexible GMRES (Saad, SIAM J. Sci. Comput. 1993) for a non-symmetric operator given only
//! by its products, right-preconditioned by a solve that may change from call to call (an
//! inner CG stopped at a tolerance). Restarted every [`GmresParams::restart`] iterations, and
//! stopped when a restart cycle does not halve the residual (the products' noise reached:
//! [`GmresError::NoConvergence`] with the iterate left in `x`).
//!
//! Used for the exact static tangent of the sensitivities (`crate::sensitivity`), whose
//! products are differences of forces and whose preconditioner is CG on the assembled tangent.

use glam::DVec3;

/// When GMRES stops and how often it restarts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GmresParams {
    /// Stop when |b - A x| <= tolerance |b|.
    pub tolerance: f64,
    /// Iterations (products) at most, over all restarts.
    pub max_iterations: usize,
    /// Krylov vectors kept before a restart.
    pub restart: usize,
}

/// How a GMRES solve went.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GmresReport {
    /// Iterations made (operator products, over all restarts).
    pub iterations: usize,
    /// |b - A x| / |b| at exit, from a product with the answer.
    pub relative_residual: f64,
}

/// Why GMRES stopped without an answer, or the operator's or preconditioner's own error.
#[derive(Debug, Clone, PartialEq)]
pub enum GmresError<E> {
    /// The iterations ran out or a restart cycle did not halve the residual.
    NoConvergence {
        /// Iterations made.
        iterations: usize,
        /// `|b - A x| / |b|` at the last restart.
        residual: f64,
    },
    /// The operator's or the preconditioner's error.
    Operator(E),
}

fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x.dot(*y)).sum()
}

/// Solves `A x = b` from the start in `x`: `apply(v, out)` sets `out = A v`,
/// `precondition(r, z)` sets `z` to about `A^-1 r` (any start in `z`). Without convergence `x`
/// holds the last restart's iterate.
pub fn flexible_gmres<E>(
    mut apply: impl FnMut(&[DVec3], &mut Vec<DVec3>) -> Result<(), E>,
    mut precondition: impl FnMut(&[DVec3], &mut Vec<DVec3>) -> Result<(), E>,
    b: &[DVec3],
    x: &mut [DVec3],
    params: GmresParams,
) -> Result<GmresReport, GmresError<E>> {
    let n = b.len();
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.fill(DVec3::ZERO);
        return Ok(GmresReport::default());
    }
    let m = params.restart.max(1);
    let mut ax = vec![DVec3::ZERO; n];
    let mut iterations = 0;
    let mut last = f64::INFINITY;
    loop {
        apply(x, &mut ax).map_err(GmresError::Operator)?;
        let r: Vec<DVec3> = b.iter().zip(&ax).map(|(b, a)| *b - *a).collect();
        let beta = dot(&r, &r).sqrt();
        let relative = beta / b_norm;
        if relative <= params.tolerance {
            return Ok(GmresReport {
                iterations,
                relative_residual: relative,
            });
        }
        // A restart that did not halve the residual has met the products' own noise.
        if iterations >= params.max_iterations || relative > 0.5 * last {
            return Err(GmresError::NoConvergence {
                iterations,
                residual: relative,
            });
        }
        last = relative;
        let mut cycle = Cycle::new(&r, beta);
        let mut w = Vec::new();
        for j in 0..m {
            let mut zj = Vec::new();
            precondition(&cycle.v[j], &mut zj).map_err(GmresError::Operator)?;
            apply(&zj, &mut w).map_err(GmresError::Operator)?;
            cycle.z.push(zj);
            iterations += 1;
            cycle.extend(&mut w, j, n);
            if cycle.g[j + 1].abs() <= params.tolerance * b_norm
                || iterations >= params.max_iterations
            {
                break;
            }
        }
        cycle.correct(x);
    }
}

/// One restart cycle: Arnoldi with modified Gram-Schmidt; Givens rotations keep the
/// least-squares residual `|g[j + 1]|` at hand.
struct Cycle {
    /// The orthonormal Krylov basis (length: iterations + 1; each of the system's length).
    v: Vec<Vec<DVec3>>,
    /// The preconditioned directions, `z[j]` about `A^-1 v[j]` (length: iterations).
    z: Vec<Vec<DVec3>>,
    /// The Hessenberg columns, rotated to upper triangular (column `j`: length `j + 2`).
    h: Vec<Vec<f64>>,
    /// The Givens rotations' cosines (length: iterations).
    cs: Vec<f64>,
    /// The Givens rotations' sines (length: iterations).
    sn: Vec<f64>,
    /// The rotated right-hand side `beta e1` (length: iterations + 1).
    g: Vec<f64>,
}

impl Cycle {
    /// A cycle from the residual `r` of norm `beta` (> 0).
    fn new(r: &[DVec3], beta: f64) -> Cycle {
        Cycle {
            v: vec![r.iter().map(|r| *r / beta).collect()],
            z: Vec::new(),
            h: Vec::new(),
            cs: Vec::new(),
            sn: Vec::new(),
            g: vec![beta],
        }
    }

    /// Step `j` with `w = A z[j]`: `w` orthogonalised against the basis (it is overwritten),
    /// the next basis vector (of length `n`) kept and the Hessenberg column rotated in.
    fn extend(&mut self, w: &mut [DVec3], j: usize, n: usize) {
        let (v, cs, sn, g) = (&mut self.v, &mut self.cs, &mut self.sn, &mut self.g);
        let mut column = vec![0.0; j + 2];
        for (i, vi) in v.iter().enumerate() {
            column[i] = dot(w, vi);
            for (w, vi) in w.iter_mut().zip(vi) {
                *w -= column[i] * *vi;
            }
        }
        column[j + 1] = dot(w, w).sqrt();
        let next: Vec<DVec3> = if column[j + 1] > 0.0 {
            w.iter().map(|w| *w / column[j + 1]).collect()
        } else {
            vec![DVec3::ZERO; n]
        };
        for i in 0..j {
            let (a, b) = (column[i], column[i + 1]);
            column[i] = cs[i] * a + sn[i] * b;
            column[i + 1] = -sn[i] * a + cs[i] * b;
        }
        let (a, b) = (column[j], column[j + 1]);
        let r = a.hypot(b);
        let (c, s) = if r > 0.0 { (a / r, b / r) } else { (1.0, 0.0) };
        cs.push(c);
        sn.push(s);
        column[j] = r;
        column[j + 1] = 0.0;
        g.push(-s * g[j]);
        g[j] *= c;
        self.h.push(column);
        v.push(next);
    }

    /// `x += Z y` with `H y = g` (upper triangular).
    fn correct(&self, x: &mut [DVec3]) {
        let (h, g) = (&self.h, &self.g);
        let k = h.len();
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let sum: f64 = (i + 1..k).map(|l| h[l][i] * y[l]).sum();
            y[i] = if h[i][i] != 0.0 {
                (g[i] - sum) / h[i][i]
            } else {
                0.0
            };
        }
        for (zi, yi) in self.z.iter().zip(&y) {
            for (x, z) in x.iter_mut().zip(zi) {
                *x += *yi * *z;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric tridiagonal (3, -1 left, -1.5 right) on each component.
    fn apply(x: &[DVec3], y: &mut Vec<DVec3>) -> Result<(), ()> {
        let n = x.len();
        y.clear();
        y.extend((0..n).map(|i| {
            let left = if i > 0 { x[i - 1] } else { DVec3::ZERO };
            let right = if i + 1 < n { x[i + 1] } else { DVec3::ZERO };
            3.0 * x[i] - left - 1.5 * right
        }));
        Ok(())
    }

    #[test]
    fn solves_a_non_symmetric_system() {
        let n = 40;
        let b: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(1.0, i as f64, (i as f64).cos()))
            .collect();
        let mut x = vec![DVec3::ZERO; n];
        let jacobi = |r: &[DVec3], z: &mut Vec<DVec3>| -> Result<(), ()> {
            z.clear();
            z.extend(r.iter().map(|r| *r / 3.0));
            Ok(())
        };
        let params = GmresParams {
            tolerance: 1e-12,
            max_iterations: 200,
            restart: 10,
        };
        let report = flexible_gmres(apply, jacobi, &b, &mut x, params).expect("converges");
        let mut ax = Vec::new();
        apply(&x, &mut ax).expect("product");
        let err = ax
            .iter()
            .zip(&b)
            .map(|(a, b)| (*a - *b).length_squared())
            .sum::<f64>()
            .sqrt();
        let bn = dot(&b, &b).sqrt();
        assert!(err <= 1e-11 * bn, "{report:?} {err}");
    }
}
