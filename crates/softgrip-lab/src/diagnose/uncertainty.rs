//! The final model's parameters with their standard errors: `s^2 (J^T J)^-1`, `J` the
//! noise-weighted residuals' derivatives by central differences (two replays a parameter) and
//! `s^2` the weighted residual's variance per degree of freedom (1 where the model leaves
//! noise alone). A linearisation: where a parameter hardly moves the markers the error is large
//! or infinite, which is the point of reporting it.

use super::model_fit::ModelFit;
use super::noise::{Noise, weighted_residuals};
use crate::params;
use crate::recording::Recording;
use crate::replay::{ReplayOptions, replay};
use crate::sweep::parallel_map;
use softgrip_core::quasi_static::RestTolerance;

/// A parameter's relative step: the differences' truncation error against the replays' own
/// (the static solver's tolerance) made about equal.
const STEP: f64 = 0.02;

/// The standard error of each of `fit`'s parameters (their order; infinite where the residuals
/// do not depend on it, NaN where a replay failed), and their correlations (NaN where not had).
pub(super) fn standard_errors(
    recording: &Recording,
    noise: &Noise,
    fit: &ModelFit,
    workers: usize,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    let p = fit.params.len();
    // A parameter at 0 (friction off) steps by an absolute amount on its own scale.
    let steps: Vec<f64> = fit
        .params
        .iter()
        .map(|(name, v)| {
            let typical = params::find(name)
                .ok()
                .and_then(|q| crate::fit::default_bounds(q, &fit.scene).ok())
                .map_or(1.0, |(lo, hi)| (hi - lo).abs().max(f64::MIN_POSITIVE));
            if *v != 0.0 {
                STEP * v.abs()
            } else {
                STEP * 0.1 * typical
            }
        })
        .collect();
    let points: Vec<(usize, f64)> = (0..p)
        .flat_map(|i| [(i, -steps[i]), (i, steps[i])])
        .collect();
    let residuals = parallel_map(
        &points,
        workers,
        |&(i, dv)| {
            let (name, v) = &fit.params[i];
            // A parameter cannot go below 0 (friction, a share): a one-sided step there.
            let value = (v + dv).max(0.0);
            let scene = params::set(&fit.scene, name, value).ok()?;
            let r = replay(recording, &scene, options, |_| {}).ok()?;
            Some((value, weighted_residuals(&r.residuals, noise)))
        },
        &|_| {},
    );
    let centre = weighted_residuals(&fit.replay.residuals, noise);
    let m = centre.len();
    let columns: Vec<Option<Vec<f64>>> = (0..p)
        .map(|i| {
            let (lo, hi) = (residuals[2 * i].as_ref()?, residuals[2 * i + 1].as_ref()?);
            let dv = hi.0 - lo.0;
            (dv > 0.0 && lo.1.len() == m && hi.1.len() == m)
                .then(|| lo.1.iter().zip(&hi.1).map(|(a, b)| (b - a) / dv).collect())
        })
        .collect();
    let dof = m.saturating_sub(p).max(1) as f64;
    let s2 = centre.iter().map(|r| r * r).sum::<f64>() / dof;
    let (errors, correlations) = crate::fit::covariance(&columns, m, s2);
    let errors = errors
        .into_iter()
        .zip(&columns)
        .map(|(e, c)| if c.is_none() { f64::NAN } else { e })
        .collect();
    (errors, correlations)
}
