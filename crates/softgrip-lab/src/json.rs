//! The figures of `compare`, `fit` and `sweep` as JSON: what the CLI's `--json` writes and the
//! Python package returns, one builder each so that both say the same (`docs/formats.md`).

use std::path::Path;

use serde_json::{Map, Value, json};

use crate::compare::Errors;
use crate::discretisation::Discretisation;
use crate::fit::{Fit, FitMany, FitParam};
use crate::params::Axis;
use crate::recording::Recording;
use crate::replay::Replay;
use crate::sweep::SweepPoint;

/// The error figures: NRMSE and RMSE, object markers and all.
pub fn errors(e: &Errors) -> Value {
    json!({
        "nrmse": e.nrmse,
        "rmse_m": e.rmse_m,
        "nrmse_all": e.nrmse_all,
        "rmse_all_m": e.rmse_all_m,
        "observations": e.count,
    })
}

/// [`errors`] against the recording at `path`: what `compare`, `sweep` and `fit` start from.
pub fn errors_for(path: &Path, e: &Errors) -> Value {
    let mut value = errors(e);
    value["recording"] = path.display().to_string().into();
    value
}

/// The ringing: the marker axis, the recording's and each replay's (under its label); `None`
/// for a quasi-static recording.
pub fn ringing(recording: &Recording, replays: &[(&str, &Replay)]) -> Option<Value> {
    use crate::ringing;
    let first = replays.first()?;
    let mut value = ringing::compare(recording, &first.1.residuals)?.to_json(recording);
    value.as_object_mut()?.remove("simulated");
    for (label, replay) in replays {
        if let Some(c) = ringing::compare(recording, &replay.residuals) {
            value[*label] = c.to_json(recording)["simulated"].clone();
        }
    }
    Some(value)
}

/// `compare`: the replay of the recording at `path` on its own scene.
pub fn compare(
    path: &Path,
    recording: &Recording,
    run: &Replay,
    discretisation: Option<&Discretisation>,
) -> Value {
    let o = &recording.scene.object;
    let m = &recording.scene.model;
    let mut value = errors_for(path, &run.errors);
    value["params"] = json!({
        "young_modulus": o.young_modulus,
        "alpha": m.alpha,
        "tau_s": m.tau_s,
        "tau_c": m.tau_c,
    });
    if let Some(d) = discretisation {
        value["discretisation"] = d.to_json();
    }
    if let Some(r) = ringing(recording, &[("simulated", run)]) {
        value["ringing"] = r;
    }
    value
}

/// The parameters by name (`null` where not finite).
pub fn by_name(params: &[FitParam], values: &[f64]) -> Value {
    params
        .iter()
        .zip(values)
        .map(|(p, v)| {
            let v = if v.is_finite() {
                Value::from(*v)
            } else {
                Value::Null
            };
            (p.param.name.to_string(), v)
        })
        .collect::<Map<_, _>>()
        .into()
}

fn identifiability(params: &[FitParam], sensitivity: &[crate::fit::Sensitivity]) -> Value {
    params
        .iter()
        .zip(sensitivity)
        .map(|(p, s)| (p.param.name.to_string(), s.verdict.label().into()))
        .collect::<Map<_, _>>()
        .into()
}

/// `fit` of one recording.
pub fn fit(path: &Path, recording: &Recording, result: &Fit) -> Value {
    let by_name = |values: &[f64]| by_name(&result.params, values);
    let mut value = errors_for(path, &result.after);
    value["params"] = by_name(&result.fitted);
    value["start"] = by_name(&result.start);
    value["standard_errors"] = by_name(&result.uncertainty.standard_errors);
    value["identifiability"] = identifiability(&result.params, &result.sensitivity);
    value["before"] = errors(&result.before);
    value["noise_m"] = result.uncertainty.sigma_m.into();
    value["simulations"] = result.trials.len().into();
    value["converged"] = result.converged.into();
    let replays = [("start", &result.start_replay), ("fitted", &result.replay)];
    if let Some(r) = ringing(recording, &replays) {
        value["ringing"] = r;
    }
    value
}

/// `fit` of several recordings sharing one set of parameters.
pub fn fit_many(paths: &[&Path], recordings: &[Recording], result: &FitMany) -> Value {
    let each: Vec<Value> = paths
        .iter()
        .zip(recordings)
        .zip(&result.recordings)
        .map(|((path, recording), part)| {
            let mut v = errors_for(path, &part.after);
            v["before"] = errors(&part.before);
            v["mode"] = recording.mode.name().into();
            let replays = [("start", &part.start_replay), ("fitted", &part.replay)];
            if let Some(r) = ringing(recording, &replays) {
                v["ringing"] = r;
            }
            v
        })
        .collect();
    json!({
        "recordings": each,
        "nrmse": result.after,
        "before": { "nrmse": result.before },
        "objective": "mean of the recordings' NRMSE",
        "params": by_name(&result.params, &result.fitted),
        "start": by_name(&result.params, &result.start),
        "standard_errors": by_name(&result.params, &result.uncertainty.standard_errors),
        "identifiability": identifiability(&result.params, &result.sensitivity),
        "noise_m": result.uncertainty.sigma_m,
        "points": result.trials.len(),
        "simulations": result.trials.len() * recordings.len(),
        "converged": result.converged,
    })
}

/// `sweep`: the best point's figures and parameters, how many points ran and failed; `None`
/// when no point ran.
pub fn sweep(path: &Path, axes: &[Axis], points: &[SweepPoint]) -> Option<Value> {
    let best = crate::sweep::best(points)?;
    let e = best.result.as_ref().ok()?;
    let mut value = errors_for(path, e);
    value["params"] = axes
        .iter()
        .zip(&best.values)
        .map(|(a, v)| (a.param.name.to_string(), Value::from(*v)))
        .collect::<Map<_, _>>()
        .into();
    value["points"] = points.len().into();
    value["failed"] = points.iter().filter(|p| p.result.is_err()).count().into();
    Some(value)
}
