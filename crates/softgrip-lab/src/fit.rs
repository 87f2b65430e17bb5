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

use std::collections::HashMap;
use std::sync::Mutex;

use crate::compare::{Errors, components};
use crate::error::LabError;
use crate::optimize::{BoundedScale, Tolerances, invert};
use crate::params::{self, Param};
use crate::recording::Recording;
use crate::replay::{Replay, ReplayOptions, replay};
use crate::sweep::parallel_map;
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::Scene;

// The optimisers, where `diagnose`, the CLI and the tests have always found them.
pub use crate::optimize::{
    Minimum, ResidualBatch, at_bound, halton, levenberg_marquardt, minimize, nelder_mead,
};

/// A parameter to fit and its bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitParam {
    /// The parameter.
    pub param: &'static Param,
    /// Lower bound, in the parameter's unit.
    pub lower: f64,
    /// Upper bound, in the parameter's unit.
    pub upper: f64,
    /// Searched on a log scale.
    pub log: bool,
}

impl FitParam {
    /// The bounds and scale the search maps 0..1 onto.
    pub fn scale(&self) -> BoundedScale {
        BoundedScale {
            lower: self.lower,
            upper: self.upper,
            log: self.log,
        }
    }

    /// The value at `u` in 0..1 of the bounds.
    pub fn value(&self, u: f64) -> f64 {
        self.scale().value(u)
    }

    /// Where `v` lies in the bounds, 0..1 (clamped).
    pub fn unit(&self, v: f64) -> f64 {
        self.scale().unit(v)
    }
}

/// The bounds used when the command line gives none: around the scene's
/// value for moduli and alpha, the physically sensible range otherwise.
pub fn default_bounds(param: &Param, scene: &Scene) -> Result<(f64, f64), LabError> {
    let value = params::get(scene, param.name)?;
    let around = |factor: f64| match value {
        Some(v) if v > 0.0 => Ok((v / factor, v * factor)),
        _ => Err(LabError::Input(format!(
            "{}: the scene's value is 0 or unset, so give bounds: {}=LOW:HIGH",
            param.name, param.name
        ))),
    };
    match param.name {
        "young_modulus" | "bulk_modulus" | "limit_stiffness" | "region_young_modulus" => {
            around(10.0)
        }
        "alpha" => around(100.0),
        "density" => around(2.0),
        "tau_s" | "tau_c" => Ok((0.02, 0.5)),
        "poisson_ratio" => Ok((0.3, 0.499)),
        "damping_ratio" => Ok((0.1, 3.0)),
        // zeta = a / (2 w) + b w / 2: a few percent to near critical for modes of 1 to 100 Hz.
        "rayleigh_mass" => Ok((0.1, 100.0)),
        "rayleigh_stiffness" => Ok((1e-5, 1e-2)),
        "friction" | "table_friction" => Ok((0.0, 2.0)),
        "stiffening" => Ok((0.0, 1000.0)),
        "compression_ratio" => Ok((0.2, 5.0)),
        "gent_limit" => Ok((0.5, 100.0)),
        "gent_stiffening" => Ok((0.0, 2.0)),
        "prony_g" => Ok((0.0, 0.9)),
        "prony_tau" => Ok((0.01, 100.0)),
        "guide_friction" => Ok((0.0, 5.0)),
        "restitution" => Ok((0.0, 1.0)),
        "contact_stiffness_scale" => Ok((0.1, 10.0)),
        other => Err(LabError::Input(format!(
            "{other} has no default bounds; give them: {other}=LOW:HIGH"
        ))),
    }
}

/// Parses `--params` entries: `name`, `name=LOW:HIGH`, with `:log` or
/// `:lin` to choose the scale (default: the parameter's natural one);
/// entries may be comma-separated.
pub fn parse_params(entries: &[String], scene: &Scene) -> Result<Vec<FitParam>, LabError> {
    let mut out: Vec<FitParam> = Vec::new();
    for text in entries.iter().flat_map(|e| e.split(',')) {
        let text = text.trim();
        if text.is_empty() {
            continue;
        }
        let bad = |why: &str| {
            LabError::Input(format!(
                "--params {text:?}: {why}; write name or name=LOW:HIGH (add :log or :lin)"
            ))
        };
        let (name, spec) = match text.split_once('=') {
            Some((n, s)) => (n.trim(), Some(s)),
            None => (text, None),
        };
        let param = params::find(name)?;
        if out.iter().any(|p| p.param.name == param.name) {
            return Err(bad("given twice"));
        }
        let (lower, upper, log) = match spec {
            None => {
                let (lo, hi) = default_bounds(param, scene)?;
                (lo, hi, param.log)
            }
            Some(spec) => {
                let parts: Vec<&str> = spec.split(':').map(str::trim).collect();
                let log = match parts.get(2) {
                    None => param.log,
                    Some(&"log") => true,
                    Some(&"lin") => false,
                    Some(_) => return Err(bad("the scale is log or lin")),
                };
                if parts.len() < 2 || parts.len() > 3 {
                    return Err(bad("bounds are LOW:HIGH"));
                }
                let number = |t: &str| {
                    t.parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| bad(&format!("{t:?} is not a number")))
                };
                (number(parts[0])?, number(parts[1])?, log)
            }
        };
        if lower >= upper {
            return Err(bad("LOW must be below HIGH"));
        }
        if log && lower <= 0.0 {
            return Err(bad("a log scale needs positive bounds (or add :lin)"));
        }
        for v in [lower, upper] {
            params::set(scene, param.name, v)
                .map_err(|e| LabError::Input(format!("--params {text:?}: {e}")))?;
        }
        out.push(FitParam {
            param,
            lower,
            upper,
            log,
        });
    }
    if out.is_empty() {
        return Err(LabError::input(
            "--params: no parameter to fit; e.g. --params young_modulus,alpha",
        ));
    }
    Ok(out)
}

/// How the search runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Simulations at most in the search (the uncertainty and sensitivity
    /// runs come on top: 4 per parameter).
    pub max_evaluations: usize,
    /// Converged when the simplex is this small in every unit coordinate...
    pub x_tolerance: f64,
    /// ... and its NRMSE values differ by less than this fraction of the
    /// best; also, the search stops when the best has not improved by
    /// this fraction in `stall` simulations (a plateau).
    pub f_tolerance: f64,
    /// Simulations without progress before the search stops, per
    /// parameter plus one.
    pub stall: usize,
    /// Simulations at once (0: one per core).
    pub workers: usize,
    /// Points of the space-filling design tried before the local search,
    /// per parameter.
    pub design_per_param: usize,
}

impl FitOptions {
    fn design_points(&self, params: usize) -> usize {
        self.design_per_param * params
    }

    /// The fewest simulations a fit of `params` parameters takes: the start, the design and
    /// the fitted point. A smaller `max_evaluations` is refused, not silently exceeded.
    pub fn least_evaluations(&self, params: usize) -> usize {
        2 + self.design_points(params)
    }
}

impl Default for FitOptions {
    fn default() -> FitOptions {
        FitOptions {
            max_evaluations: 400,
            x_tolerance: 1e-3,
            f_tolerance: 1e-5,
            stall: 20,
            workers: 0,
            design_per_param: 8,
        }
    }
}

impl From<FitOptions> for Tolerances {
    fn from(o: FitOptions) -> Tolerances {
        Tolerances {
            x_tolerance: o.x_tolerance,
            f_tolerance: o.f_tolerance,
            stall: o.stall,
        }
    }
}

/// What the data say about one fitted parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Identifiability {
    /// Both +/-10 % changes raise the error significantly.
    Identified,
    /// Neither does, but the standard error is under half the value: the
    /// 95 % interval is wider than +/-10 %.
    Weak,
    /// Only one side does (the data give a bound, not a value).
    OneSided,
    /// Neither does: the recording cannot tell this parameter.
    Unidentifiable,
}

impl Identifiability {
    /// As the report writes it.
    pub fn label(self) -> &'static str {
        match self {
            Identifiability::Identified => "identified",
            Identifiability::Weak => "weakly identified (95 % interval wider than +/-10 %)",
            Identifiability::OneSided => "bounded on one side only",
            Identifiability::Unidentifiable => "UNIDENTIFIABLE",
        }
    }
}

/// NRMSE at -10 % and +10 % of a fitted value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity {
    /// `None`: the value is not allowed or the run failed.
    pub minus: Option<f64>,
    /// NRMSE at +10 %; `None`: the value is not allowed or the run failed.
    pub plus: Option<f64>,
    /// What the data say about the parameter.
    pub verdict: Identifiability,
}

/// The noise-implied uncertainty of the fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// Scalar residuals (observed coordinates) in the fit.
    pub residuals: usize,
    /// The noise the residuals imply, sqrt(SSR / (m - p)) (m).
    pub sigma_m: f64,
    /// One per parameter, in its units; infinite when the residuals do
    /// not depend on it (or only together with another).
    pub standard_errors: Vec<f64>,
    /// Correlation of the estimates (p x p; NaN where undefined).
    pub correlations: Vec<Vec<f64>>,
}

/// One simulation of the search.
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    /// The parameters' values tried, in their units (one per fitted parameter).
    pub values: Vec<f64>,
    /// NRMSE, or why the run failed.
    pub nrmse: Result<f64, LabError>,
}

/// A fit and its evidence.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The parameters fitted.
    pub params: Vec<FitParam>,
    /// Their values at the start, in their units.
    pub start: Vec<f64>,
    /// The errors at the start.
    pub before: Errors,
    /// The fitted values, in their units.
    pub fitted: Vec<f64>,
    /// The errors at the fit.
    pub after: Errors,
    /// The replays at the start and at the fit.
    pub start_replay: Replay,
    /// The replay at the fit.
    pub replay: Replay,
    /// Every simulation of the search, in order.
    pub trials: Vec<Trial>,
    /// The search converged or stopped improving (not stopped by its
    /// budget).
    pub converged: bool,
    /// Fitted values at (within 0.1 % of) a bound.
    pub at_bound: Vec<bool>,
    /// The noise-implied standard errors and correlations at the fit.
    pub uncertainty: Uncertainty,
    /// NRMSE at +/-10 % of each fitted value, and its verdict.
    pub sensitivity: Vec<Sensitivity>,
}

/// Why a fit did not run: [`LabError::FitStart`] or [`LabError::Cancelled`].
pub type FitError = LabError;

/// `LabError::Cancelled` once the fit's cancel token is set (its
/// simulations then fail at once, which must not read as bad points).
fn check_cancel() -> Result<(), LabError> {
    softgrip_core::cancel::check_scope(|| LabError::Cancelled)
}

/// A run's error as the fit's: cancelled, or the start's.
fn start_error(e: LabError) -> LabError {
    check_cancel()
        .err()
        .unwrap_or(LabError::FitStart(Box::new(e)))
}

/// `scene` with `params` set to `values`.
pub fn scene_with(scene: &Scene, params: &[FitParam], values: &[f64]) -> Result<Scene, LabError> {
    let mut s = scene.clone();
    for (p, v) in params.iter().zip(values) {
        s = params::set(&s, p.param.name, *v)?;
    }
    Ok(s)
}

/// A fit's replay, on the default thread count: one simulation per core
/// while a batch has several, both cores for the last one left
/// (`Simulation::set_threads`).
fn run(recording: &Recording, scene: &Scene) -> Result<Replay, LabError> {
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    replay(recording, scene, options, |_| {}).map_err(LabError::from)
}

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

/// NRMSE at -10 % and +10 % of a value, and whether each rise of the error is significant.
type Probe = (Option<f64>, Option<f64>, bool, bool);

/// The uncertainty and the sensitivity at the fit, from the recordings' residuals stacked.
fn evidence(
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
