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
fn upper_tail(z: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.231_641_9 * z);
    let poly = t
        * (0.319_381_530
            + t * (-0.356_563_782
                + t * (1.781_477_937 + t * (-1.821_255_978 + t * 1.330_274_429))));
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt() * poly
}

/// Vuong's threshold for an effect chosen as the best of `variants` forms or places (the four
/// halves a region may fill): [`VUONG_Z`]'s one-sided level divided among them (Bonferroni), so
/// that the best of four halves is no likelier to be named by chance than a lone candidate. 2.0
/// for one, 2.26 for two, 2.53 for four.
pub fn vuong_threshold(variants: usize) -> f64 {
    let level = upper_tail(VUONG_Z) / variants.max(1) as f64;
    let (mut lo, mut hi) = (VUONG_Z, 10.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if upper_tail(mid) > level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    if variants <= 1 { VUONG_Z } else { hi }
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
    /// threshold's level divided among the variants.
    #[test]
    fn the_threshold_divides_the_level_among_the_variants() {
        assert!((upper_tail(1.959_964) - 0.025).abs() < 1e-6);
        assert!((upper_tail(2.575_829) - 0.005).abs() < 1e-6);
        assert_eq!(vuong_threshold(1), VUONG_Z);
        for k in [2, 4, 8] {
            let z = vuong_threshold(k);
            assert!(
                (upper_tail(z) * k as f64 - upper_tail(VUONG_Z)).abs() < 1e-9,
                "{k}: {z}"
            );
        }
        assert!((vuong_threshold(4) - 2.53).abs() < 0.01);
    }
}
