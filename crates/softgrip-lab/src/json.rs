//! The figures of `compare`, `fit` and `sweep` as JSON: what the CLI's `--json` writes and the
//! Python package returns, one builder each so that both say the same (`docs/formats.md`).
//! Each output is a typed struct ([`CompareFigures`], ...; the commands' own in [`commands`])
//! turned into a `serde_json::Value` by [`to_value`], so its keys come out sorted, as they
//! always have; their schemas are [`crate::schema`]'s.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use crate::compare::Errors;
use crate::discretisation::Discretisation;
use crate::fit::{Fit, FitMany, FitParam};
use crate::params::Axis;
use crate::recording::Recording;
use crate::replay::Replay;
use crate::sweep::SweepPoint;

pub mod commands;
mod figures;

pub use figures::{
    CompareFigures, ErrorFigures, FitFigures, FitManyFigures, FitManyRecording, FitRingingFigures,
    NrmseFigures, SceneParams, SweepFigures,
};

/// `figures` as a JSON value, its objects' keys sorted (serde_json's `Value`): the form every
/// output is written in, so that the CLI's file and Python's string are the same.
pub fn to_value(figures: &impl Serialize) -> Value {
    // Numbers, strings, lists and maps with string keys: nothing here fails to serialize.
    serde_json::to_value(figures).unwrap_or(Value::Null)
}

/// The error figures: NRMSE and RMSE, object markers and all.
pub fn error_figures(e: &Errors) -> ErrorFigures {
    ErrorFigures {
        nrmse: e.nrmse,
        rmse_m: e.rmse_m,
        nrmse_all: e.nrmse_all,
        rmse_all_m: e.rmse_all_m,
        observations: e.count,
    }
}

/// [`error_figures`] as JSON.
pub fn errors(e: &Errors) -> Value {
    to_value(&error_figures(e))
}

/// [`errors`] against the recording at `path`: what `compare`, `sweep` and `fit` start from.
pub fn errors_for(path: &Path, e: &Errors) -> Value {
    let mut value = errors(e);
    value["recording"] = path.display().to_string().into();
    value
}

/// The ringing of a fit: the recording's most-moving marker axis, and the replays' at the
/// start and at the fit on it; `None` for a quasi-static recording.
pub fn fit_ringing(
    recording: &Recording,
    start: &Replay,
    fitted: &Replay,
) -> Option<FitRingingFigures> {
    use crate::ringing;
    // Both are `None` together: only the recording decides whether there is a ringing.
    let at_start = ringing::compare(recording, &start.residuals)?.figures(recording);
    let at_fit = ringing::compare(recording, &fitted.residuals)?.figures(recording);
    Some(FitRingingFigures {
        marker: at_start.marker,
        axis: at_start.axis,
        recorded: at_start.recorded,
        start: at_start.simulated,
        fitted: at_fit.simulated,
    })
}

/// `compare`: the replay of the recording at `path` on its own scene.
pub fn compare_figures(
    path: &Path,
    recording: &Recording,
    run: &Replay,
    discretisation: Option<&Discretisation>,
) -> CompareFigures {
    let o = &recording.scene.object;
    let m = &recording.scene.model;
    let e = &run.errors;
    CompareFigures {
        nrmse: e.nrmse,
        rmse_m: e.rmse_m,
        nrmse_all: e.nrmse_all,
        rmse_all_m: e.rmse_all_m,
        observations: e.count,
        recording: path.display().to_string(),
        params: SceneParams {
            young_modulus: o.young_modulus,
            alpha: m.alpha,
            tau_s: m.tau_s,
            tau_c: m.tau_c,
        },
        discretisation: discretisation.map(Discretisation::figures),
        ringing: crate::ringing::compare(recording, &run.residuals).map(|c| c.figures(recording)),
    }
}

/// [`compare_figures`] as JSON.
pub fn compare(
    path: &Path,
    recording: &Recording,
    run: &Replay,
    discretisation: Option<&Discretisation>,
) -> Value {
    to_value(&compare_figures(path, recording, run, discretisation))
}

/// The parameters by name (`None` where not finite, written as `null`).
pub fn by_name(params: &[FitParam], values: &[f64]) -> BTreeMap<String, Option<f64>> {
    params
        .iter()
        .zip(values)
        .map(|(p, v)| (p.param.name.to_string(), v.is_finite().then_some(*v)))
        .collect()
}

/// Each parameter's identifiability verdict by name.
fn identifiability(
    params: &[FitParam],
    sensitivity: &[crate::fit::Sensitivity],
) -> BTreeMap<String, String> {
    params
        .iter()
        .zip(sensitivity)
        .map(|(p, s)| (p.param.name.to_string(), s.verdict.label().to_string()))
        .collect()
}

/// `fit` of one recording.
pub fn fit_figures(path: &Path, recording: &Recording, result: &Fit) -> FitFigures {
    let by_name = |values: &[f64]| by_name(&result.params, values);
    let e = &result.after;
    FitFigures {
        nrmse: e.nrmse,
        rmse_m: e.rmse_m,
        nrmse_all: e.nrmse_all,
        rmse_all_m: e.rmse_all_m,
        observations: e.count,
        recording: path.display().to_string(),
        params: by_name(&result.fitted),
        start: by_name(&result.start),
        standard_errors: by_name(&result.uncertainty.standard_errors),
        identifiability: identifiability(&result.params, &result.sensitivity),
        before: error_figures(&result.before),
        noise_m: result.uncertainty.sigma_m,
        simulations: result.trials.len(),
        converged: result.converged,
        ringing: fit_ringing(recording, &result.start_replay, &result.replay),
    }
}

/// [`fit_figures`] as JSON.
pub fn fit(path: &Path, recording: &Recording, result: &Fit) -> Value {
    to_value(&fit_figures(path, recording, result))
}

/// `fit` of several recordings sharing one set of parameters.
pub fn fit_many_figures(
    paths: &[&Path],
    recordings: &[Recording],
    result: &FitMany,
) -> FitManyFigures {
    let each = paths
        .iter()
        .zip(recordings)
        .zip(&result.recordings)
        .map(|((path, recording), part)| {
            let e = &part.after;
            FitManyRecording {
                nrmse: e.nrmse,
                rmse_m: e.rmse_m,
                nrmse_all: e.nrmse_all,
                rmse_all_m: e.rmse_all_m,
                observations: e.count,
                recording: path.display().to_string(),
                before: error_figures(&part.before),
                mode: recording.mode.name().to_string(),
                ringing: fit_ringing(recording, &part.start_replay, &part.replay),
            }
        })
        .collect();
    FitManyFigures {
        recordings: each,
        nrmse: result.after,
        before: NrmseFigures {
            nrmse: result.before,
        },
        objective: "mean of the recordings' NRMSE".to_string(),
        params: by_name(&result.params, &result.fitted),
        start: by_name(&result.params, &result.start),
        standard_errors: by_name(&result.params, &result.uncertainty.standard_errors),
        identifiability: identifiability(&result.params, &result.sensitivity),
        noise_m: result.uncertainty.sigma_m,
        points: result.trials.len(),
        simulations: result.trials.len() * recordings.len(),
        converged: result.converged,
    }
}

/// [`fit_many_figures`] as JSON.
pub fn fit_many(paths: &[&Path], recordings: &[Recording], result: &FitMany) -> Value {
    to_value(&fit_many_figures(paths, recordings, result))
}

/// `sweep`: the best point's figures and parameters, how many points ran and failed; `None`
/// when no point ran.
pub fn sweep_figures(path: &Path, axes: &[Axis], points: &[SweepPoint]) -> Option<SweepFigures> {
    let best = crate::sweep::best(points)?;
    let e = best.result.as_ref().ok()?;
    Some(SweepFigures {
        nrmse: e.nrmse,
        rmse_m: e.rmse_m,
        nrmse_all: e.nrmse_all,
        rmse_all_m: e.rmse_all_m,
        observations: e.count,
        recording: path.display().to_string(),
        params: axes
            .iter()
            .zip(&best.values)
            .map(|(a, v)| (a.param.name.to_string(), *v))
            .collect(),
        points: points.len(),
        failed: points.iter().filter(|p| p.result.is_err()).count(),
    })
}

/// [`sweep_figures`] as JSON.
pub fn sweep(path: &Path, axes: &[Axis], points: &[SweepPoint]) -> Option<Value> {
    sweep_figures(path, axes, points).map(|f| to_value(&f))
}
