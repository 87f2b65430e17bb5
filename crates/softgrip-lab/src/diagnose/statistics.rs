//! The tests the diagnosis decides by, and their thresholds: a chi-square test of the residual
//! against the noise, the Bayesian information criterion of a least-squares fit, Vuong's test
//! for two models fitted to the same data, and Spearman's rank correlation. Why these:
//! `docs/design/diagnosis.md`.

use super::noise::Noise;
use crate::compare::Residual;

/// Candidates that removed less than this share of the residual in the
/// first round are not tried again in later rounds.
pub const PROMISING: f64 = 0.05;

/// BIC must fall by more than this for an effect to be accepted.
pub const BIC_THRESHOLD: f64 = 10.0;

/// ... and the weighted residual sum of squares by at least this share ...
pub const MIN_EXPLAINED: f64 = 0.1;

/// ... and Vuong's statistic against the best other effect must reach this.
pub const VUONG_Z: f64 = 2.0;

/// Standard normal upper tail `P(Z > z)` for `z >= 0` (Abramowitz and Stegun 26.2.17, error
/// below 7.5e-8).
pub(super) fn upper_tail(z: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.231_641_9 * z);
    let poly = t
        * (0.319_381_530
            + t * (-0.356_563_782
                + t * (1.781_477_937 + t * (-1.821_255_978 + t * 1.330_274_429))));
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt() * poly
}

/// Vuong's threshold for an effect chosen as the best of several forms or places (the four
/// halves a region may fill), which count as `tests` independent tests ([`effective_tests`]):
/// [`VUONG_Z`]'s one-sided level divided among them (Bonferroni), so that the best of four
/// unrelated halves is no likelier to be named by chance than a lone candidate. 2.0 for one,
/// 2.28 for two, 2.53 for four.
pub fn vuong_threshold(tests: f64) -> f64 {
    if tests <= 1.0 {
        return VUONG_Z;
    }
    let level = upper_tail(VUONG_Z) / tests;
    let (mut lo, mut hi) = (VUONG_Z, 10.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if upper_tail(mid) > level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// How many independent tests the Vuong tests of one effect's variants count as, from their
/// per-observation statistics `d` (each `rival^2 - variant^2`): Galwey's effective number
/// (Genet. Epidemiol. 33, 2009), `(sum sqrt(lambda))^2 / sum lambda` over the non-negative
/// eigenvalues of the statistics' correlation matrix. Unrelated variants count as many tests,
/// identical ones as one, and it moves smoothly between (two with correlation r: 1 + sqrt(1 -
/// r^2)): two forms of stiffening that bend the same markers alike are nearly one test, and
/// Bonferroni over both asks more than chance calls for.
pub fn effective_tests(d: &[Vec<f64>]) -> f64 {
    let k = d.len();
    if k <= 1 {
        return k as f64;
    }
    let centred: Vec<(Vec<f64>, f64)> = d
        .iter()
        .map(|v| {
            let n = v.len().max(1) as f64;
            let m = v.iter().sum::<f64>() / n;
            let c: Vec<f64> = v.iter().map(|x| x - m).collect();
            let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
            (c, norm)
        })
        .collect();
    let mut r = vec![vec![0.0; k]; k];
    for i in 0..k {
        r[i][i] = 1.0;
        for j in 0..i {
            let ((a, na), (b, nb)) = (&centred[i], &centred[j]);
            // Statistics of another length or without spread do not pair up: unrelated.
            let c = if a.len() == b.len() && *na > 0.0 && *nb > 0.0 {
                a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>() / (na * nb)
            } else {
                0.0
            };
            r[i][j] = c;
            r[j][i] = c;
        }
    }
    let l: Vec<f64> = crate::optimize::symmetric_eigenvalues(&r)
        .into_iter()
        .map(|l| l.max(0.0))
        .collect();
    let roots: f64 = l.iter().map(|x| x.sqrt()).sum();
    // The trace is k; rounding aside.
    roots * roots / l.iter().sum::<f64>().max(f64::MIN_POSITIVE)
}

/// A mismatch no candidate explains is "unexplained" when the baseline's
/// RMS residual is more than this many times the noise; below, the
/// verdict is "none": a residual within a few noise levels that no
/// physics explains is the model's own form error (a lattice against a
/// continuum, one mesh against another), not missing physics.
pub const UNEXPLAINED_RATIO: f64 = 3.0;

/// BIC of a least-squares fit with the noise level free.
pub fn bic(rss: f64, n: usize, k: usize) -> f64 {
    let n = n.max(1) as f64;
    n * (rss.max(1e-300) / n).ln() + k as f64 * n.ln()
}

/// Is a chi-square of `chi2` on `dof` degrees of freedom beyond three of
/// its standard deviations?
pub fn significant(chi2: f64, dof: usize) -> bool {
    let d = dof.max(1) as f64;
    chi2 > d + 3.0 * (2.0 * d).sqrt()
}

/// Vuong's statistic for two non-nested least-squares models fitted to the
/// same data, from their residuals (same order, weighted alike):
/// `sqrt(n) mean(d) / sd(d)` with `d_i = b_i^2 - a_i^2`, asymptotically
/// standard normal when neither model is closer to the truth; positive
/// when `a` fits closer. None when the residuals do not pair up.
pub fn vuong(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.len() < 3 {
        return None;
    }
    let d: Vec<f64> = a.iter().zip(b).map(|(a, b)| b * b - a * a).collect();
    Some(mean_over_error(&d))
}

/// Vuong's statistic with the squared-residual differences summed per
/// sample first: `sqrt(m) mean(D) / sd(D)` over the m samples. Positive
/// when `a` fits closer; None with fewer than 3 samples or residuals that
/// do not pair up.
pub fn vuong_by_sample(a: &[Residual], b: &[Residual], noise: &Noise) -> Option<f64> {
    if a.len() != b.len() {
        return None;
    }
    let mut per: std::collections::BTreeMap<usize, f64> = std::collections::BTreeMap::new();
    for (ra, rb) in a.iter().zip(b) {
        if ra.sample != rb.sample || ra.marker != rb.marker {
            return None;
        }
        let s = noise.sigma(ra.marker);
        let mut d = 0.0;
        for k in 0..3 {
            if let Some(x) = ra.recorded[k] {
                let ea = (ra.simulated[k] - x) / s;
                let eb = (rb.simulated[k] - x) / s;
                d += eb * eb - ea * ea;
            }
        }
        *per.entry(ra.sample).or_insert(0.0) += d;
    }
    let d: Vec<f64> = per.into_values().collect();
    (d.len() >= 3).then(|| mean_over_error(&d))
}

/// `sqrt(n) mean(d) / sd(d)`: infinite with the sign of the mean when
/// every `d` is alike, 0 when they are all 0.
fn mean_over_error(d: &[f64]) -> f64 {
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    if var <= 0.0 {
        return if mean == 0.0 {
            0.0
        } else {
            mean.signum() * f64::INFINITY
        };
    }
    n.sqrt() * mean / var.sqrt()
}

/// Spearman's rank correlation (0 for fewer than 3 points or no spread).
pub(super) fn spearman(a: &[f64], b: &[f64]) -> f64 {
    if a.len() < 3 {
        return 0.0;
    }
    let rank = |v: &[f64]| {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        let mut r = vec![0.0; v.len()];
        for (k, &i) in idx.iter().enumerate() {
            r[i] = k as f64;
        }
        r
    };
    let (ra, rb) = (rank(a), rank(b));
    let n = ra.len() as f64;
    let ma = ra.iter().sum::<f64>() / n;
    let mb = rb.iter().sum::<f64>() / n;
    let cov: f64 = ra.iter().zip(&rb).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = ra.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = rb.iter().map(|y| (y - mb).powi(2)).sum();
    if va <= 0.0 || vb <= 0.0 {
        0.0
    } else {
        cov / (va * vb).sqrt()
    }
}

#[cfg(test)]
mod threshold_tests {
    use super::*;

    /// The tail against tabulated values (P(Z > 1.96) = 0.025, P(Z > 2.576) = 0.005), and the
    /// threshold's level divided among the tests.
    #[test]
    fn the_threshold_divides_the_level_among_the_tests() {
        assert!((upper_tail(1.959_964) - 0.025).abs() < 1e-6);
        assert!((upper_tail(2.575_829) - 0.005).abs() < 1e-6);
        assert_eq!(vuong_threshold(1.0), VUONG_Z);
        assert_eq!(vuong_threshold(0.0), VUONG_Z);
        for k in [1.3, 2.0, 4.0, 8.0] {
            let z = vuong_threshold(k);
            assert!(
                (upper_tail(z) * k - upper_tail(VUONG_Z)).abs() < 1e-9,
                "{k}: {z}"
            );
        }
        assert!((vuong_threshold(2.0) - 2.28).abs() < 0.01);
        assert!((vuong_threshold(4.0) - 2.53).abs() < 0.01);
    }

    /// Galwey's count: k unrelated statistics are k tests, k copies one, two with correlation r
    /// count 1 + sqrt(1 - r^2) (eigenvalues 1 + r and 1 - r); a sign flip changes nothing.
    #[test]
    fn the_effective_tests_run_from_one_for_copies_to_k_for_unrelated() {
        // +-1 by one bit of the index each: centred and uncorrelated.
        let walsh = |i: usize| -> Vec<f64> {
            (0..64usize)
                .map(|n| if (n >> (3 + i)) & 1 == 0 { 1.0 } else { -1.0 })
                .collect()
        };
        let unrelated: Vec<Vec<f64>> = (0..3).map(walsh).collect();
        assert!((effective_tests(&unrelated) - 3.0).abs() < 1e-9);
        let a: Vec<f64> = (0..50).map(|n| ((n * 37) % 11) as f64).collect();
        let b: Vec<f64> = (0..50).map(|n| ((n * 17) % 13) as f64).collect();
        assert!((effective_tests(&[a.clone(), a.clone(), a.clone()]) - 1.0).abs() < 1e-9);
        let neg: Vec<f64> = a.iter().map(|x| -2.0 * x + 5.0).collect();
        assert!((effective_tests(&[a.clone(), neg]) - 1.0).abs() < 1e-9);
        let r = {
            let m = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
            let (ma, mb) = (m(&a), m(&b));
            let cov: f64 = a.iter().zip(&b).map(|(x, y)| (x - ma) * (y - mb)).sum();
            let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
            let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
            cov / (va * vb).sqrt()
        };
        assert!(r.abs() > 0.01, "a test of a real correlation: {r}");
        let two = effective_tests(&[a.clone(), b]);
        assert!(
            (two - (1.0 + (1.0 - r * r).sqrt())).abs() < 1e-9,
            "{two} {r}"
        );
        // No spread or another length: unrelated, never a failure.
        assert!((effective_tests(&[a.clone(), vec![3.0; 50]]) - 2.0).abs() < 1e-9);
        assert!((effective_tests(&[a.clone(), vec![1.0, 2.0]]) - 2.0).abs() < 1e-9);
        assert_eq!(effective_tests(&[a]), 1.0);
        assert_eq!(effective_tests(&[]), 0.0);
    }
}
