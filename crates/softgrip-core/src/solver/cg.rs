//! Preconditioned conjugate gradient (thesis Alg. 6) on a linear operator.
//!
//! Vectors are `[DVec3]` (one block per particle or finger). Reductions run in
//! index order, so results are bit-identical from run to run.

use glam::DVec3;

/// `y = A x` and `z = P^-1 r` for a symmetric positive definite `A`.
pub trait LinearOperator {
    /// `y = A x` (`y` overwritten; both of the system's length).
    fn apply(&self, x: &[DVec3], y: &mut [DVec3]);
    /// `z = P^-1 r` (`z` overwritten; both of the system's length).
    fn precondition(&self, r: &[DVec3], z: &mut [DVec3]);

    /// `z = P^-1 r` and `r . z` (summed in index order), in one pass where
    /// the operator can.
    fn precondition_dot(&self, r: &[DVec3], z: &mut [DVec3]) -> f64 {
        self.precondition(r, z);
        dot(r, z)
    }
}

/// When CG stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgParams {
    /// Stop when |r| <= tolerance * max(|b|, reference).
    pub tolerance: f64,
    /// The size of right-hand side the tolerance is relative to when `b`
    /// itself is smaller (0: relative to |b| alone).
    pub reference: f64,
    /// Iterations at most before [`CgError::NoConvergence`].
    pub max_iterations: usize,
}

/// How a CG solve went.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CgReport {
    /// Iterations made (0 when the start already met the tolerance).
    pub iterations: usize,
    /// |b - A x| / max(|b|, reference) at exit (0 when b = 0): the
    /// quantity the tolerance bounds.
    pub relative_residual: f64,
}

/// Why CG stopped without an answer.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum CgError {
    /// A search direction `d` with `d . A d <= 0`.
    #[error(
        "the system matrix is not positive definite (d.Ad = {curvature:e} at CG iteration {iteration})"
    )]
    NotPositiveDefinite {
        /// The iteration it happened at.
        iteration: usize,
        /// `d . A d`, in the system's units.
        curvature: f64,
    },
    /// [`CgParams::max_iterations`] reached above the tolerance.
    #[error("CG did not converge in {iterations} iterations (relative residual {residual:e})")]
    NoConvergence {
        /// Iterations made.
        iterations: usize,
        /// The recursive residual over max(|b|, reference) at the end.
        residual: f64,
    },
    /// A NaN or infinity appeared.
    #[error("CG produced a non-finite value at iteration {iteration}")]
    NonFinite {
        /// The iteration it happened at.
        iteration: usize,
    },
}

/// Scratch vectors for CG, allocated once.
#[derive(Debug, Default, Clone)]
pub struct CgScratch {
    r: Vec<DVec3>,
    z: Vec<DVec3>,
    d: Vec<DVec3>,
    q: Vec<DVec3>,
}

/// `a . b`, summed in index order.
fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    let mut sum = 0.0;
    for (x, y) in a.iter().zip(b) {
        sum += x.dot(*y);
    }
    sum
}

/// Solves `A x = b` starting from the given `x` (a warm start).
pub fn conjugate_gradient(
    a: &impl LinearOperator,
    b: &[DVec3],
    x: &mut [DVec3],
    params: CgParams,
    s: &mut CgScratch,
) -> Result<CgReport, CgError> {
    let n = b.len();
    for v in [&mut s.r, &mut s.z, &mut s.d, &mut s.q] {
        v.clear();
        v.resize(n, DVec3::ZERO);
    }
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.fill(DVec3::ZERO);
        return Ok(CgReport {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    a.apply(x, &mut s.q);
    for i in 0..n {
        s.r[i] = b[i] - s.q[i];
    }
    // A warm start that is further off than zero is dropped: at true rest
    // the last step's solution is noise (ARCHITECTURE.md, "Implicit system").
    if dot(&s.r, &s.r) > b_norm * b_norm {
        x.fill(DVec3::ZERO);
        s.r.copy_from_slice(b);
    }
    a.precondition(&s.r, &mut s.z);
    s.d.copy_from_slice(&s.z);
    let mut rz = dot(&s.r, &s.z);
    let scale = b_norm.max(params.reference);
    let target = params.tolerance * scale;
    let mut r_norm = dot(&s.r, &s.r).sqrt();
    let mut it = 0;
    while r_norm > target {
        if it >= params.max_iterations {
            return Err(CgError::NoConvergence {
                iterations: it,
                residual: r_norm / scale,
            });
        }
        a.apply(&s.d, &mut s.q);
        let curvature = dot(&s.d, &s.q);
        if !curvature.is_finite() {
            return Err(CgError::NonFinite { iteration: it });
        }
        if curvature <= 0.0 {
            return Err(CgError::NotPositiveDefinite {
                iteration: it,
                curvature,
            });
        }
        let alpha = rz / curvature;
        // Fused passes; each sum still runs in index order (bit-identical).
        let mut rr = 0.0;
        for i in 0..n {
            x[i] += alpha * s.d[i];
            s.r[i] -= alpha * s.q[i];
            rr += s.r[i].dot(s.r[i]);
        }
        let rz_new = a.precondition_dot(&s.r, &mut s.z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            s.d[i] = s.z[i] + beta * s.d[i];
        }
        r_norm = rr.sqrt();
        it += 1;
        if !r_norm.is_finite() {
            return Err(CgError::NonFinite { iteration: it });
        }
    }
    Ok(CgReport {
        iterations: it,
        relative_residual: r_norm / scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1-D Laplacian (tridiagonal 2, -1) acting on each component.
    struct Laplacian;
    impl LinearOperator for Laplacian {
        fn apply(&self, x: &[DVec3], y: &mut [DVec3]) {
            let n = x.len();
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { DVec3::ZERO };
                let right = if i + 1 < n { x[i + 1] } else { DVec3::ZERO };
                y[i] = 2.0 * x[i] - left - right;
            }
        }
        fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
            for (z, r) in z.iter_mut().zip(r) {
                *z = *r / 2.0;
            }
        }
    }

    #[test]
    fn solves_a_laplacian_to_tolerance() {
        let n = 50;
        let b: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(1.0, i as f64, -(i as f64).sin()))
            .collect();
        let mut x = vec![DVec3::ZERO; n];
        let params = CgParams {
            tolerance: 1e-12,
            reference: 0.0,
            max_iterations: 500,
        };
        let report = conjugate_gradient(&Laplacian, &b, &mut x, params, &mut CgScratch::default())
            .expect("converges");
        // CG on an n x n SPD system converges in at most n steps in exact arithmetic.
        assert!(report.iterations <= n + 5, "{report:?}");
        let mut ax = vec![DVec3::ZERO; n];
        Laplacian.apply(&x, &mut ax);
        let err: f64 = ax
            .iter()
            .zip(&b)
            .map(|(a, b)| (*a - *b).length_squared())
            .sum::<f64>()
            .sqrt();
        let bn: f64 = b.iter().map(|v| v.length_squared()).sum::<f64>().sqrt();
        assert!(err <= 1e-11 * bn, "residual {err}");
    }

    /// A well-conditioned tridiagonal (4, -1): CG stops on the tolerance
    /// after a few iterations, long before the dimension ends it.
    struct Shifted;
    impl LinearOperator for Shifted {
        fn apply(&self, x: &[DVec3], y: &mut [DVec3]) {
            let n = x.len();
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { DVec3::ZERO };
                let right = if i + 1 < n { x[i + 1] } else { DVec3::ZERO };
                y[i] = 4.0 * x[i] - left - right;
            }
        }
        fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
            for (z, r) in z.iter_mut().zip(r) {
                *z = *r / 4.0;
            }
        }
    }

    fn laplacian_problem() -> (Vec<DVec3>, CgParams) {
        let b = (0..1000)
            .map(|i| DVec3::new(1.0, (i % 50) as f64, -(i as f64).sin()))
            .collect();
        let params = CgParams {
            tolerance: 1e-6,
            reference: 0.0,
            max_iterations: 5000,
        };
        (b, params)
    }

    #[test]
    fn a_warm_start_worse_than_zero_is_dropped() {
        let (b, params) = laplacian_problem();
        let solve = |scale: f64| {
            let mut x: Vec<DVec3> = (0..b.len())
                .map(|i| scale * DVec3::new((1.7 * i as f64).sin(), (0.3 * i as f64).cos(), 1.0))
                .collect();
            conjugate_gradient(&Shifted, &b, &mut x, params, &mut CgScratch::default())
                .expect("converges")
        };
        let from_zero = solve(0.0);
        // A start far off (|b - A x0| >> |b|) costs exactly what zero does.
        let from_garbage = solve(1e3);
        assert!(from_zero.iterations < 30, "{from_zero:?}");
        assert_eq!(from_garbage.iterations, from_zero.iterations);
        assert!(from_garbage.relative_residual <= 1e-6);
    }

    #[test]
    fn a_right_hand_side_below_the_reference_needs_no_iteration() {
        let (b, mut params) = laplacian_problem();
        let tiny: Vec<DVec3> = b.iter().map(|v| *v * 1e-12).collect();
        params.reference = 1.0;
        params.tolerance = 1e-5;
        let mut x = vec![DVec3::ZERO; b.len()];
        let report =
            conjugate_gradient(&Laplacian, &tiny, &mut x, params, &mut CgScratch::default())
                .expect("converges");
        assert_eq!(report.iterations, 0);
        // Relative to |b| alone the same solve iterates.
        params.reference = 0.0;
        let report =
            conjugate_gradient(&Laplacian, &tiny, &mut x, params, &mut CgScratch::default())
                .expect("converges");
        assert!(report.iterations > 0);
    }

    #[test]
    fn reports_indefinite_matrix() {
        struct Negative;
        impl LinearOperator for Negative {
            fn apply(&self, x: &[DVec3], y: &mut [DVec3]) {
                for (y, x) in y.iter_mut().zip(x) {
                    *y = -*x;
                }
            }
            fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
                z.copy_from_slice(r);
            }
        }
        let b = vec![DVec3::ONE; 3];
        let mut x = vec![DVec3::ZERO; 3];
        let e = conjugate_gradient(
            &Negative,
            &b,
            &mut x,
            CgParams {
                tolerance: 1e-10,
                reference: 0.0,
                max_iterations: 10,
            },
            &mut CgScratch::default(),
        );
        assert!(matches!(e, Err(CgError::NotPositiveDefinite { .. })));
    }
}
