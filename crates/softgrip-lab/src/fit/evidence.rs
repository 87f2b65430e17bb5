//! The fit's evidence: the uncertainty (`s^2 (J^T J)^-1` of the stacked residuals' Jacobian) and
//! each parameter's sensitivity (the NRMSE 10 % either side, and whether the rise is significant).

use super::setup::{
    FitOptions, FitParam, Identifiability, Sensitivity, Uncertainty, run, scene_with,
};
use crate::compare::components;
use crate::error::LabError;
use crate::optimize::invert;
use crate::recording::Recording;
use crate::replay::Replay;
use crate::sweep::parallel_map;

/// NRMSE at -10 % and +10 % of a value, and whether each rise of the error is significant.
type Probe = (Option<f64>, Option<f64>, bool, bool);

/// The uncertainty and the sensitivity at the fit, from the recordings' residuals stacked.
pub(super) fn evidence(
    recordings: &[Recording],
    params: &[FitParam],
    fitted: &[f64],
    at_fit: &[Replay],
    options: FitOptions,
) -> (Uncertainty, Vec<Sensitivity>) {
    let p = params.len();
    let k = recordings.len();
    let r0 = stacked(&at_fit.iter().collect::<Vec<_>>());
    let m = r0.len();
    let ssr: f64 = r0.iter().map(|x| x * x).sum();
    let dof = m.saturating_sub(p).max(1) as f64;
    // A floor far below any measurement keeps a perfect fit well defined.
    let sigma2 = (ssr / dof).max(1e-24);
    let (steps, points) = probe_points(params, fitted);
    let runs = run_points(recordings, params, &points, options.workers);
    // A point's replays, one per recording, or `None` if one failed.
    let point = |i: usize| -> Option<Vec<&Replay>> {
        runs[k * i..k * (i + 1)]
            .iter()
            .map(|r| r.as_ref().ok())
            .collect()
    };
    let mut jacobian: Vec<Option<Vec<f64>>> = Vec::with_capacity(p);
    let mut sensitivity: Vec<Probe> = Vec::with_capacity(p);
    // The rise of the sum of squared residuals against chi-square's 95 %.
    let significant = |e: Option<&Vec<&Replay>>| {
        e.is_some_and(|rs| {
            let total: f64 = rs
                .iter()
                .map(|r| r.errors.count as f64 * r.errors.rmse_m.powi(2))
                .sum();
            total - ssr > 3.84 * sigma2
        })
    };
    let mean = |rs: &Vec<&Replay>| rs.iter().map(|r| r.errors.nrmse).sum::<f64>() / k as f64;
    for i in 0..p {
        let column = match (point(4 * i), point(4 * i + 1)) {
            (Some(a), Some(b)) => central_difference(&a, &b, m, steps[i]),
            _ => None,
        };
        jacobian.push(column);
        let (minus, plus) = (point(4 * i + 2), point(4 * i + 3));
        sensitivity.push((
            minus.as_ref().map(mean),
            plus.as_ref().map(mean),
            significant(minus.as_ref()),
            significant(plus.as_ref()),
        ));
    }
    let (standard_errors, correlations) = covariance(&jacobian, m, sigma2);
    let sensitivity = verdicts(sensitivity, &standard_errors, fitted);
    (
        Uncertainty {
            residuals: m,
            sigma_m: sigma2.sqrt(),
            standard_errors,
            correlations,
        },
        sensitivity,
    )
}

/// The replays' residual coordinates stacked into one vector, recording after recording (m).
fn stacked(replays: &[&Replay]) -> Vec<f64> {
    replays
        .iter()
        .flat_map(|r| components(&r.residuals))
        .collect()
}

/// The central-difference steps, and the points around the fit: per parameter, -step, +step,
/// -10 % and +10 %.
fn probe_points(params: &[FitParam], fitted: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let p = params.len();
    // Central-difference steps, then the +/-10 % points.
    let steps: Vec<f64> = params
        .iter()
        .zip(fitted)
        .map(|(q, v)| {
            if *v != 0.0 {
                0.01 * v.abs()
            } else {
                0.01 * (q.upper - q.lower)
            }
        })
        .collect();
    let mut points: Vec<Vec<f64>> = Vec::with_capacity(4 * p);
    for i in 0..p {
        for delta in [-steps[i], steps[i], -0.1 * fitted[i], 0.1 * fitted[i]] {
            let mut v = fitted.to_vec();
            v[i] += delta;
            points.push(v);
        }
    }
    (steps, points)
}

/// Each point's replay on each recording, point by point (recordings in order), in parallel.
fn run_points(
    recordings: &[Recording],
    params: &[FitParam],
    points: &[Vec<f64>],
    workers: usize,
) -> Vec<Result<Replay, LabError>> {
    let k = recordings.len();
    // One job per point and recording.
    let jobs: Vec<(usize, usize)> = (0..points.len())
        .flat_map(|i| (0..k).map(move |j| (i, j)))
        .collect();
    parallel_map(
        &jobs,
        workers,
        |&(i, j)| {
            let recording = &recordings[j];
            scene_with(&recording.scene, params, &points[i]).and_then(|s| run(recording, &s))
        },
        &|_| {},
    )
}

/// A Jacobian column from the stacked residuals at -step (`a`) and +step (`b`), m/unit;
/// `None` when either has not `m` coordinates.
fn central_difference(a: &[&Replay], b: &[&Replay], m: usize, step: f64) -> Option<Vec<f64>> {
    let (ra, rb) = (stacked(a), stacked(b));
    (ra.len() == m && rb.len() == m).then(|| {
        ra.iter()
            .zip(&rb)
            .map(|(x, y)| (y - x) / (2.0 * step))
            .collect()
    })
}

/// Each parameter's sensitivity with its verdict, from its probe and standard error.
fn verdicts(probes: Vec<Probe>, standard_errors: &[f64], fitted: &[f64]) -> Vec<Sensitivity> {
    probes
        .into_iter()
        .enumerate()
        .map(|(i, (minus, plus, low, high))| {
            let relative = standard_errors[i] / fitted[i].abs();
            let verdict = match (low, high) {
                (true, true) => Identifiability::Identified,
                _ if relative < 0.5 => Identifiability::Weak,
                (false, false) => Identifiability::Unidentifiable,
                _ => Identifiability::OneSided,
            };
            Sensitivity {
                minus,
                plus,
                verdict,
            }
        })
        .collect()
}

/// Standard errors and correlations from Jacobian columns (`None`: not
/// available) and the noise variance: `sigma2 (J^T J)^-1`, leaving out the
/// columns that are missing or zero (infinite error).
pub(crate) fn covariance(
    columns: &[Option<Vec<f64>>],
    m: usize,
    sigma2: f64,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let p = columns.len();
    let norms: Vec<f64> = columns
        .iter()
        .map(|c| {
            c.as_ref()
                .map_or(0.0, |c| c.iter().map(|x| x * x).sum::<f64>().sqrt())
        })
        .collect();
    let largest = norms.iter().copied().fold(0.0, f64::max);
    let kept: Vec<usize> = (0..p)
        .filter(|&i| norms[i] > 1e-12 * largest && norms[i] > 0.0)
        .collect();
    let mut se = vec![f64::INFINITY; p];
    let mut corr = vec![vec![f64::NAN; p]; p];
    let k = kept.len();
    if k == 0 {
        return (se, corr);
    }
    // Normal matrix of the unit-scaled columns (better conditioned).
    let mut a = vec![vec![0.0; k]; k];
    for (x, &i) in kept.iter().enumerate() {
        for (y, &j) in kept.iter().enumerate() {
            let (ci, cj) = match (&columns[i], &columns[j]) {
                (Some(ci), Some(cj)) => (ci, cj),
                _ => return (se, corr),
            };
            a[x][y] = (0..m).map(|r| ci[r] * cj[r]).sum::<f64>() / (norms[i] * norms[j]);
        }
    }
    let Some(inv) = invert(a) else {
        return (se, corr);
    };
    for (x, &i) in kept.iter().enumerate() {
        se[i] = (sigma2 * inv[x][x]).sqrt() / norms[i];
        for (y, &j) in kept.iter().enumerate() {
            corr[i][j] = inv[x][y] / (inv[x][x] * inv[y][y]).sqrt();
        }
    }
    (se, corr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covariance_of_orthogonal_columns_is_sigma_over_their_norms() {
        // r = J theta + noise with J's columns orthogonal: the standard
        // errors are sigma / |J_i| and the estimates are uncorrelated.
        let columns = vec![
            Some(vec![1.0, 1.0, 0.0, 0.0]),
            Some(vec![0.0, 0.0, 2.0, -2.0]),
            None,
        ];
        let (se, corr) = covariance(&columns, 4, 0.25);
        assert!((se[0] - 0.5 / 2f64.sqrt()).abs() < 1e-12, "{se:?}");
        assert!((se[1] - 0.5 / 8f64.sqrt()).abs() < 1e-12, "{se:?}");
        assert!(se[2].is_infinite());
        assert!(corr[0][1].abs() < 1e-12 && (corr[0][0] - 1.0).abs() < 1e-12);
        // Two equal columns cannot be told apart: no finite error.
        let same = vec![Some(vec![1.0, 2.0]), Some(vec![1.0, 2.0])];
        let (se, _) = covariance(&same, 2, 1.0);
        assert!(se.iter().all(|s| s.is_infinite()), "{se:?}");
        // Correlated but separable: the textbook 2x2 inverse.
        let cols = vec![Some(vec![1.0, 0.0, 1.0]), Some(vec![1.0, 1.0, 0.0])];
        let (se, corr) = covariance(&cols, 3, 1.0);
        // J^T J = [[2, 1], [1, 2]], inverse [[2, -1], [-1, 2]] / 3.
        assert!((se[0] - (2.0f64 / 3.0).sqrt()).abs() < 1e-12, "{se:?}");
        assert!((corr[0][1] + 0.5).abs() < 1e-12, "{corr:?}");
    }
}
