//! Fitting scene parameters to a recording: NRMSE minimised by a bounded
//! search, then what the data say about the answer.
//!
//! Each parameter is searched in 0..1 of its bounds (log for those spanning
//! decades): a Halton design first, then Nelder-Mead with restarts
//! ([`crate::optimize`]); a spring limit left acting nowhere is tried again
//! just below the largest strain. At the fit, the residuals' Jacobian gives
//! standard errors and correlations ([`Uncertainty`]), and NRMSE at +/-10 %
//! of each value tells whether the data identify it ([`Identifiability`]).
//! Batches of simulations run in parallel; results do not depend on the
//! number of workers. [`fit_many`] fits one parameter vector to several
//! recordings at once (each on its own scene), minimising the mean of their
//! NRMSE; [`fit`] is it for one. The method in full: `docs/design/fitting.md`.

mod evidence;
mod setup;

pub use setup::*;

pub(crate) use evidence::covariance;
use evidence::evidence;
use std::collections::HashMap;
use std::sync::Mutex;

use crate::compare::Errors;
use crate::error::LabError;
use crate::params;
use crate::recording::Recording;
use crate::replay::Replay;
use crate::sweep::parallel_map;
use softgrip_core::scene::Scene;

// The optimisers, where `diagnose`, the CLI and the tests have always found them.
pub use crate::optimize::{
    Minimum, ResidualBatch, at_bound, halton, levenberg_marquardt, minimize, nelder_mead,
};

/// Progress of a fit: simulations done and the best NRMSE so far (of a fit over several
/// recordings: points done, each the recordings' simulations, and the best mean NRMSE).
pub type Progress<'a> = &'a (dyn Fn(usize, f64) + Sync);

/// One recording's part in a fit over several ([`fit_many`]).
#[derive(Debug, Clone)]
pub struct RecordingFit {
    /// Its errors at the start.
    pub before: Errors,
    /// Its errors at the fit.
    pub after: Errors,
    /// Its replays at the start and at the fit.
    pub start_replay: Replay,
    /// Its replay at the fit.
    pub replay: Replay,
}

/// One parameter vector fitted to several recordings at once, and its evidence.
#[derive(Debug, Clone)]
pub struct FitMany {
    /// The parameters fitted.
    pub params: Vec<FitParam>,
    /// Their values at the start (the first recording's scene), in their units.
    pub start: Vec<f64>,
    /// The fitted values, in their units.
    pub fitted: Vec<f64>,
    /// The objective, the mean of the recordings' NRMSE, at the start and at the fit.
    pub before: f64,
    /// The mean NRMSE at the fit.
    pub after: f64,
    /// One per recording, in the order given.
    pub recordings: Vec<RecordingFit>,
    /// Every point of the search, in order, with its mean NRMSE (each point is one
    /// simulation per recording).
    pub trials: Vec<Trial>,
    /// The search converged or stopped improving (not stopped by its budget).
    pub converged: bool,
    /// Fitted values at (within 0.1 % of) a bound.
    pub at_bound: Vec<bool>,
    /// From the recordings' residuals stacked into one vector.
    pub uncertainty: Uncertainty,
    /// The mean NRMSE at +/-10 %; significance on the stacked residuals.
    pub sensitivity: Vec<Sensitivity>,
}

/// Fits `params` of the recording's scene to the recording, starting
/// from the scene's values (clamped into the bounds; the middle of the
/// bounds for a spring limit that is off). [`fit_many`] of one recording.
pub fn fit(
    recording: &Recording,
    params: &[FitParam],
    options: FitOptions,
    progress: Progress,
) -> Result<Fit, LabError> {
    let many = fit_many(std::slice::from_ref(recording), params, options, progress)?;
    let FitMany {
        params,
        start,
        fitted,
        recordings,
        trials,
        converged,
        at_bound,
        uncertainty,
        sensitivity,
        ..
    } = many;
    let Some(one) = recordings.into_iter().next() else {
        return Err(LabError::input("the fit has no recording"));
    };
    Ok(Fit {
        params,
        start,
        before: one.before,
        fitted,
        after: one.after,
        start_replay: one.start_replay,
        replay: one.replay,
        trials,
        converged,
        at_bound,
        uncertainty,
        sensitivity,
    })
}

/// Every recording's scene takes every parameter at both its bounds: the error names the
/// recording whose scene cannot (a finger parameter where one has no finger, ...).
pub fn check_params(recordings: &[Recording], params: &[FitParam]) -> Result<(), LabError> {
    for r in recordings {
        for p in params {
            for v in [p.lower, p.upper] {
                params::set(&r.scene, p.param.name, v).map_err(|e| {
                    LabError::Input(format!(
                        "{}: its scene ({}) cannot take {} = {v}: {e}",
                        r.source.display(),
                        r.scene_path.display(),
                        p.param.name
                    ))
                })?;
            }
        }
    }
    Ok(())
}

/// `f` of each recording: in parallel when there are several.
fn each<R: Send>(
    recordings: &[Recording],
    workers: usize,
    f: impl Fn(&Recording) -> R + Sync,
) -> Vec<R> {
    match recordings {
        [one] => vec![f(one)],
        _ => parallel_map(recordings, workers, f, &|_| {}),
    }
}

/// Fits one set of values of `params` to every recording at once, each simulated on its own
/// scene (the recordings may differ in their scenes: a load, a tip mass, the mode) with the
/// parameters set to the same values. The objective is the mean of the recordings' NRMSE: each
/// recording's error is normalised by its own object's extent and counted as the root mean
/// square over its own observations, so a recording with more samples or markers, or a larger
/// motion, does not outweigh the others (a stacked sum of squares would let the longest
/// recording decide). The simulations of one point run in parallel on the worker pool, with
/// the points of a batch.
///
/// The search and the evidence are [`fit`]'s: it starts from the first recording's scene
/// values; the uncertainty comes from the recordings' residual vectors stacked into one (one
/// noise level s for all, `s^2 (J^T J)^-1` of the stacked Jacobian), the sensitivity from the
/// mean NRMSE at +/-10 % with significance on the stacked sum of squares. With one recording
/// this is [`fit`] exactly.
pub fn fit_many(
    recordings: &[Recording],
    params: &[FitParam],
    options: FitOptions,
    progress: Progress,
) -> Result<FitMany, LabError> {
    let first_recording = check_request(recordings, params, options)?;
    let start = start_values(&first_recording.scene, params);
    let runs = Runs {
        recordings,
        params,
        workers: options.workers,
    };
    let first = runs.at(&start).map_err(start_error)?;
    let before = mean_nrmse(&first);
    let u0: Vec<f64> = params.iter().zip(&start).map(|(p, v)| p.unit(*v)).collect();
    let mut search = Search {
        runs: &runs,
        progress,
        cache: HashMap::new(),
        trials: vec![Trial {
            values: start.clone(),
            nrmse: Ok(before),
        }],
        best_so_far: Mutex::new(before),
    };
    search.cache.insert(key(&u0), before);
    let mut best = search.design_then_minimize(u0, before, options);
    let mut fitted_replays = runs.at(&runs.values(&best.u)).map_err(start_error)?;
    search.retry_spring_limits(&mut best, &mut fitted_replays, options)?;
    let fitted = runs.values(&best.u);
    let at_bound = best.u.iter().map(|u| at_bound(*u)).collect();
    let after = mean_nrmse(&fitted_replays);
    check_cancel()?;
    let (uncertainty, sensitivity) =
        evidence(recordings, params, &fitted, &fitted_replays, options);
    check_cancel()?;
    let recordings = first
        .into_iter()
        .zip(fitted_replays)
        .map(|(start_replay, replay)| RecordingFit {
            before: start_replay.errors,
            after: replay.errors,
            start_replay,
            replay,
        })
        .collect();
    Ok(FitMany {
        params: params.to_vec(),
        start,
        fitted,
        before,
        after,
        recordings,
        trials: search.trials,
        converged: best.converged,
        at_bound,
        uncertainty,
        sensitivity,
    })
}

/// The first recording, once every recording's scene takes the parameters and the budget
/// covers the fewest simulations a fit takes.
fn check_request<'r>(
    recordings: &'r [Recording],
    params: &[FitParam],
    options: FitOptions,
) -> Result<&'r Recording, LabError> {
    let Some(first_recording) = recordings.first() else {
        return Err(LabError::input("a fit needs at least one recording"));
    };
    check_params(recordings, params)?;
    let least = options.least_evaluations(params.len());
    if options.max_evaluations < least {
        return Err(LabError::input(format!(
            "--max-evaluations {}: a fit of {} parameter(s) takes at least {least} simulations (the start, a space-filling design of {}, and the fitted point); give {least} or more (default 400)",
            options.max_evaluations,
            params.len(),
            options.design_points(params.len())
        )));
    }
    Ok(first_recording)
}

/// The search's start: the scene's values clamped into the bounds, the middle of the bounds
/// where the scene has none (a spring limit that is off).
fn start_values(scene: &Scene, params: &[FitParam]) -> Vec<f64> {
    params
        .iter()
        .map(|p| {
            let v = params::get(scene, p.param.name).ok().flatten();
            v.map_or_else(|| p.value(0.5), |v| p.value(p.unit(v)))
        })
        .collect()
}

/// The mean of the replays' NRMSE: the objective of a fit over several recordings.
fn mean_nrmse(replays: &[Replay]) -> f64 {
    replays.iter().map(|r| r.errors.nrmse).sum::<f64>() / replays.len() as f64
}

/// The largest spring stretch and compression of the runs, over the recordings.
fn largest_strain(replays: &[Replay]) -> [f64; 2] {
    replays.iter().fold([0.0f64; 2], |m, r| {
        [m[0].max(r.largest_strain[0]), m[1].max(r.largest_strain[1])]
    })
}

/// The cache key of a point in unit coordinates: its exact bits.
fn key(u: &[f64]) -> Vec<u64> {
    u.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
}

/// The fit's simulations: the recordings, each on its own scene with the parameters set.
struct Runs<'a> {
    /// The recordings fitted, in the order given.
    recordings: &'a [Recording],
    /// The parameters fitted.
    params: &'a [FitParam],
    /// Simulations at once (0: one per core).
    workers: usize,
}

impl Runs<'_> {
    /// One recording's replay at `values`; of several, the error names the recording.
    fn one(&self, recording: &Recording, values: &[f64]) -> Result<Replay, LabError> {
        let several = self.recordings.len() > 1;
        run(
            recording,
            &scene_with(&recording.scene, self.params, values)?,
        )
        .map_err(|e| {
            if several && !matches!(e, LabError::Cancelled) {
                LabError::Input(format!("{}: {e}", recording.source.display()))
            } else {
                e
            }
        })
    }

    /// Every recording's replay at `values`, in the recordings' order.
    fn at(&self, values: &[f64]) -> Result<Vec<Replay>, LabError> {
        each(self.recordings, self.workers, |r| self.one(r, values))
            .into_iter()
            .collect()
    }

    /// The parameter values at `u` in 0..1 of their bounds.
    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.params
            .iter()
            .zip(u)
            .map(|(p, x)| p.value(*x))
            .collect()
    }
}

/// Where the search stands.
struct Best {
    /// The best point, in 0..1 of the bounds.
    u: Vec<f64>,
    /// Its mean NRMSE.
    f: f64,
    /// The local search that found it converged (not stopped by its budget).
    converged: bool,
    /// Simulations spent so far (points; each is one per recording).
    spent: usize,
}

/// The search's memory: every point tried, in order, and its mean NRMSE.
struct Search<'a> {
    /// The simulations it runs.
    runs: &'a Runs<'a>,
    /// Told the points done and the best mean NRMSE.
    progress: Progress<'a>,
    /// Mean NRMSE by point (`key`); infinite where a run failed.
    cache: HashMap<Vec<u64>, f64>,
    /// Every point simulated, in order.
    trials: Vec<Trial>,
    /// The best mean NRMSE so far, for progress.
    best_so_far: Mutex<f64>,
}

impl Search<'_> {
    /// The mean NRMSE at each point (unit coordinates), simulating those not yet tried.
    fn evaluate(&mut self, points: &[Vec<f64>]) -> Vec<f64> {
        let todo: Vec<Vec<f64>> = points
            .iter()
            .filter(|u| !self.cache.contains_key(&key(u)))
            .cloned()
            .collect();
        let results = self.simulate(&todo);
        self.record(&todo, results);
        points
            .iter()
            .map(|u| self.cache.get(&key(u)).copied().unwrap_or(f64::INFINITY))
            .collect()
    }

    /// Each point's NRMSE on each recording, point by point (recordings in order), in parallel.
    fn simulate(&self, todo: &[Vec<f64>]) -> Vec<Result<f64, LabError>> {
        let k = self.runs.recordings.len();
        let done_before = self.trials.len();
        // One job per point and recording; a point's mean once its last recording is in.
        let jobs: Vec<(usize, usize)> = (0..todo.len())
            .flat_map(|i| (0..k).map(move |j| (i, j)))
            .collect();
        let partial = Mutex::new(vec![(0usize, 0.0f64); todo.len()]);
        let best_so_far = &self.best_so_far;
        parallel_map(
            &jobs,
            self.runs.workers,
            |&(i, j)| {
                let values = self.runs.values(&todo[i]);
                let r = self
                    .runs
                    .one(&self.runs.recordings[j], &values)
                    .map(|r| r.errors.nrmse);
                if let (Ok(f), Ok(mut part)) = (&r, partial.lock()) {
                    part[i].0 += 1;
                    part[i].1 += f;
                    if part[i].0 == k
                        && let Ok(mut b) = best_so_far.lock()
                    {
                        *b = b.min(part[i].1 / k as f64);
                    }
                }
                r
            },
            &|n| {
                let best = best_so_far.lock().map_or(f64::NAN, |b| *b);
                (self.progress)(done_before + n / k, best);
            },
        )
    }

    /// Files each point's mean NRMSE (infinite if a recording's run failed) and its trial.
    fn record(&mut self, todo: &[Vec<f64>], results: Vec<Result<f64, LabError>>) {
        let k = self.runs.recordings.len();
        let mut results = results.into_iter();
        for u in todo {
            let values = self.runs.values(u);
            // All k taken before the first error is looked for (a collect into a `Result`
            // would stop there and leave the point's other results for the next).
            let mine: Vec<Result<f64, LabError>> = results.by_ref().take(k).collect();
            let r = mine
                .into_iter()
                .collect::<Result<Vec<f64>, LabError>>()
                .map(|f| f.iter().sum::<f64>() / k as f64);
            let f = r.as_ref().map_or(f64::INFINITY, |f| *f);
            self.cache.insert(key(u), f);
            self.trials.push(Trial { values, nrmse: r });
        }
    }

    /// The space-filling design from `u0` (NRMSE `f0`), then Nelder-Mead from its best point.
    fn design_then_minimize(&mut self, u0: Vec<f64>, f0: f64, options: FitOptions) -> Best {
        let n = self.runs.params.len();
        // A space-filling design first: NRMSE is flat wherever a spring limit
        // acts on no spring, and a local search that starts on such a plateau
        // never leaves it.
        let (mut best_u, mut best_f) = (u0, f0);
        let design: Vec<Vec<f64>> = (1..=options.design_points(n))
            .map(|k| halton(k, n))
            .collect();
        for (u, f) in design.iter().zip(self.evaluate(&design)) {
            if f < best_f {
                (best_u, best_f) = (u.clone(), f);
            }
        }
        let mut spent = 1 + design.len();
        let first_search = minimize(
            &mut |points: &[Vec<f64>]| self.evaluate(points),
            &best_u,
            best_f,
            options.max_evaluations.saturating_sub(spent),
            options,
        );
        spent += first_search.evaluations;
        Best {
            u: first_search.x,
            f: first_search.f,
            converged: first_search.converged,
            spent,
        }
    }

    /// A spring limit above every strain of the fitted run acts nowhere, and
    /// NRMSE is flat in it: the search may have settled there with the
    /// modulus making up for it. Try again with such limits just below the
    /// largest strain (so that they act), and keep what fits better.
    fn retry_spring_limits(
        &mut self,
        best: &mut Best,
        fitted_replays: &mut Vec<Replay>,
        options: FitOptions,
    ) -> Result<(), LabError> {
        for _ in 0..2 {
            let strain = largest_strain(fitted_replays);
            let (retry, changed) = limits_below(self.runs.params, &best.u, strain);
            if !changed || best.spent >= options.max_evaluations {
                break;
            }
            let f = self.evaluate(std::slice::from_ref(&retry))[0];
            best.spent += 1;
            let r = minimize(
                &mut |points: &[Vec<f64>]| self.evaluate(points),
                &retry,
                f,
                options.max_evaluations.saturating_sub(best.spent),
                options,
            );
            best.spent += r.evaluations;
            if r.f >= best.f {
                break;
            }
            (best.u, best.f, best.converged) = (r.x, r.f, r.converged);
            *fitted_replays = self
                .runs
                .at(&self.runs.values(&best.u))
                .map_err(start_error)?;
        }
        Ok(())
    }
}

/// `best_u` with each spring limit above the largest strain moved to 0.8 of it, and whether
/// any moved.
fn limits_below(params: &[FitParam], best_u: &[f64], strain: [f64; 2]) -> (Vec<f64>, bool) {
    let mut retry = best_u.to_vec();
    let mut changed = false;
    for (i, p) in params.iter().enumerate() {
        let largest = match p.param.name {
            "tau_s" => strain[0],
            "tau_c" => strain[1],
            _ => continue,
        };
        if p.value(best_u[i]) > largest && largest > 0.0 {
            retry[i] = p.unit(0.8 * largest);
            changed |= retry[i] != best_u[i];
        }
    }
    (retry, changed)
}
