//! The small dense symmetric algebra the optimisers, the fit's covariance and the diagnosis's
//! test count need, by faer (the project's linear-algebra crate): Cholesky with a relative pivot
//! test, and self-adjoint eigenvalues.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, Side};

/// A pivot of the Cholesky factor (the diagonal of `L`, squared) below this share of the
/// matrix's largest diagonal entry counts as singular: a parameter with no effect, or two
/// with the same one, to working accuracy.
pub const RELATIVE_PIVOT: f64 = 1e-10;

/// The inverse of a symmetric positive definite matrix (rows of equal length) by Cholesky;
/// `None` when it is not positive definite, has a pivot below `RELATIVE_PIVOT` (1e-10) of its largest
/// diagonal entry, or is not finite.
pub fn invert(a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let m = Mat::from_fn(n, n, |i, j| a[i][j]);
    let largest = (0..n).map(|i| a[i][i]).fold(0.0, f64::max);
    if !(largest.is_finite() && largest > 0.0) {
        return None;
    }
    let llt = m.llt(Side::Lower).ok()?;
    let l = llt.L();
    if (0..n).any(|i| l[(i, i)] * l[(i, i)] < RELATIVE_PIVOT * largest) {
        return None;
    }
    let inverse = llt.inverse();
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| inverse[(i, j)]).collect())
        .collect();
    rows.iter().flatten().all(|x| x.is_finite()).then_some(rows)
}

/// The eigenvalues of a symmetric matrix (rows of equal length), in nondecreasing order; empty
/// when the decomposition fails (a matrix that is not finite).
pub fn symmetric_eigenvalues(a: &[Vec<f64>]) -> Vec<f64> {
    let n = a.len();
    Mat::from_fn(n, n, |i, j| a[i][j])
        .self_adjoint_eigenvalues(Side::Lower)
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inverse of a known matrix, and its product with the matrix the identity.
    #[test]
    fn inverts_a_known_matrix() {
        // [[4, 2], [2, 3]]^-1 = [[3, -2], [-2, 4]] / 8.
        let inv = invert(vec![vec![4.0, 2.0], vec![2.0, 3.0]]).expect("definite");
        let want = [[0.375, -0.25], [-0.25, 0.5]];
        for i in 0..2 {
            for j in 0..2 {
                assert!((inv[i][j] - want[i][j]).abs() < 1e-15, "{inv:?}");
            }
        }
    }

    /// Singular, indefinite and near-singular (relative to the largest diagonal) are refused;
    /// a badly scaled but well-conditioned one is not (the test is relative, not absolute).
    #[test]
    fn refuses_singular_and_indefinite_matrices_by_a_relative_pivot() {
        assert!(invert(vec![vec![1.0, 1.0], vec![1.0, 1.0]]).is_none());
        assert!(invert(vec![vec![1.0, 2.0], vec![2.0, 1.0]]).is_none());
        assert!(invert(vec![vec![1.0, 0.0], vec![0.0, 1e-12]]).is_none());
        assert!(invert(vec![vec![1e-20, 0.0], vec![0.0, 2e-20]]).is_some());
        assert!(invert(vec![vec![f64::NAN]]).is_none());
    }

    /// The eigenvalues of a matrix with known ones.
    #[test]
    fn finds_known_eigenvalues() {
        // [[2,1,0],[1,2,1],[0,1,2]]: 2 - sqrt 2, 2, 2 + sqrt 2.
        let l = symmetric_eigenvalues(&[
            vec![2.0, 1.0, 0.0],
            vec![1.0, 2.0, 1.0],
            vec![0.0, 1.0, 2.0],
        ]);
        let r2 = 2f64.sqrt();
        assert_eq!(l.len(), 3);
        for (got, want) in l.iter().zip([2.0 - r2, 2.0, 2.0 + r2]) {
            assert!((got - want).abs() < 1e-12, "{l:?}");
        }
    }
}
