//! One fit of the diagnosis (the baseline's, a candidate's, a pair's): a model's parameters
//! fitted to the recording by the noise-weighted residual sum of squares over every marker,
//! from a small space-filling design and Levenberg-Marquardt from its best points, reusing
//! every replay it has run. One algorithm, kept whole.

use std::cell::{Cell, RefCell};
use std::collections::HashMap;

use super::checkpoint::{Checkpoint, Saved, Simulations};
use super::noise::{Noise, weighted_residuals, weighted_rss};
use super::options::DiagnoseOptions;
use super::statistics::{PROMISING, bic};
use crate::compare::Errors;
use crate::error::LabError;
use crate::fit::{FitOptions, FitParam};
use crate::optimize::levenberg_marquardt_with;
use crate::params;
use crate::recording::Recording;
use crate::replay::{MarkerSensitivities, Replay, ReplayOptions, SampleState, replay_observing};
use crate::sensitivity::replay_with_sensitivities;
use crate::sweep::parallel_map;
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::Scene;

/// Finite-difference step of the fits' Jacobian, in the unit box of each
/// parameter (2 % of E over its log range): large enough to stand above
/// the rest tolerance of a quasi-static replay.
pub const JACOBIAN_STEP: f64 = 0.01;

/// Every point a fit ran (its unit-box coordinates' bits), with its weighted residuals and
/// replay, or `None` where the replay failed.
type Evaluated = HashMap<Vec<u64>, Option<(Vec<f64>, Replay)>>;

/// A point's replay starts Newton from an evaluated point's states only within this distance
/// in the unit box (Levenberg-Marquardt's steps, the Jacobian's own point): from farther (the
/// design's points) it took longer than the usual path from rest.
pub const WARM_DISTANCE: f64 = 0.05;

/// Local searches at most per fit: from its best point and, where its
/// `Search` says, from the next best (see `fit_model`).
pub const LOCAL_SEARCHES: usize = 2;

/// Where a fit searches from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Search {
    /// Levenberg-Marquardt from the best of the start and the given
    /// starts (a refit whose start is already near its optimum).
    Local,
    /// Also a small space-filling design, and the search from its best
    /// point.
    Design,
    /// The design, and searches from its best and next best points (the
    /// baseline: every verdict is measured against it, so a local minimum
    /// there would show as an effect everywhere).
    Twice,
    /// The design, and a second search from the next best point when the
    /// first explains a share (PROMISING) of the current fit's residual
    /// (a candidate).
    Contender,
}

/// One fitted model.
#[derive(Debug, Clone)]
pub struct ModelFit {
    /// The scene with the fitted values set.
    pub scene: Scene,
    /// The fitted parameters, by name.
    pub params: Vec<(String, f64)>,
    /// RMSE and NRMSE of its replay against the recording.
    pub errors: Errors,
    /// Noise-weighted residual sum of squares (dimensionless).
    pub rss: f64,
    /// Residual components counted in `rss`: the coordinates recorded.
    pub n: usize,
    /// Parameters counted by BIC: the model's in all.
    pub k: usize,
    /// BIC of the fit, from `rss`, `n` and `k` (`statistics::bic`).
    pub bic: f64,
    /// Its replay at the fitted values: residuals, errors, the samples' states.
    pub replay: Replay,
    /// Simulations the fit ran (for one from a checkpoint, those of the run that saved it).
    pub evaluations: usize,
    /// The fit's wall time; for one taken from a checkpoint, the time it took the run that
    /// saved it.
    pub seconds: f64,
}

/// One fit of the diagnosis: the model, what is fitted and how.
pub(super) struct FitTask<'a> {
    pub(super) scene: &'a Scene,
    pub(super) params: &'a [FitParam],
    /// Parameters counted by BIC: the model's in all (the modulus is
    /// refitted, not added, by a candidate).
    pub(super) k_total: usize,
    pub(super) search: Search,
    /// Simulations at most.
    pub(super) budget: usize,
    /// Points (values) to start from beside the scene's own.
    pub(super) starts: &'a [Vec<f64>],
    /// A point (values) the fit ends no worse than, but does not search
    /// from: a candidate's effect switched off (`Candidate::off`).
    pub(super) floor: Option<&'a [f64]>,
    /// A fit already run: a point that is its model takes its replay.
    pub(super) known: Option<&'a ModelFit>,
}

/// Fits the task's parameters of its scene to `recording` minimising the
/// noise-weighted residual sum of squares over every marker (fingers
/// included). `LabError::Cancelled` once the diagnosis's cancel token is set.
pub(super) fn fit_model(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    task: FitTask<'_>,
) -> Result<ModelFit, LabError> {
    let Some(checkpoint) = &options.checkpoint else {
        let fit = fit_task(recording, noise, options, task, None);
        check_cancel()?;
        return fit;
    };
    let key = checkpoint_key(checkpoint, recording, options, &task);
    if let Some(fit) = saved_fit(checkpoint, key, recording, noise, &task) {
        check_cancel()?;
        return Ok(fit);
    }
    // A time series' simulations are logged as they end (the checkpoint's module says why
    // not a quasi-static one's), under the fit's key and the noise that weights them.
    let log = (recording.mode == crate::recording::Mode::TimeSeries)
        .then(|| (checkpoint, checkpoint.key(&(key, noise))));
    let fit = fit_task(recording, noise, options, task, log);
    check_cancel()?;
    if let Ok(f) = &fit {
        checkpoint.save(
            key,
            Saved {
                evaluations: f.evaluations,
                seconds: f.seconds,
                values: f.params.iter().map(|(_, v)| *v).collect(),
            },
        );
    }
    fit
}

/// The checkpoint's key of a fit: a hash of what the fit depends on.
fn checkpoint_key(
    checkpoint: &Checkpoint,
    recording: &Recording,
    options: &DiagnoseOptions,
    task: &FitTask<'_>,
) -> u64 {
    // What the fit depends on: the recording, the options (not the file, nor the simulations
    // at once) and its task. Not the noise or the model it extends beyond that model's values:
    // both follow from the recording and options, and a resumed run replays its saved fits
    // from rest, so their bits differ within the rest tolerance from the run that saved them.
    let options = DiagnoseOptions {
        checkpoint: None,
        workers: 0,
        ..options.clone()
    };
    let known = task.known.map(|k| &k.params);
    checkpoint.key(&(
        recording,
        &options,
        task.scene,
        task.params,
        task.k_total,
        task.search,
        task.budget,
        task.starts,
        task.floor,
        known,
    ))
}

/// The fit the checkpoint saved under `key`, replayed from rest at its values; `None` where
/// there is none, it lies outside the search's bounds, or its replay fails.
fn saved_fit(
    checkpoint: &Checkpoint,
    key: u64,
    recording: &Recording,
    noise: &Noise,
    task: &FitTask<'_>,
) -> Option<ModelFit> {
    let (scene, params, k_total) = (task.scene, task.params, task.k_total);
    let saved = checkpoint
        .get(key)
        .filter(|s| s.values.len() == params.len());
    // A saved fit is trusted only within its search's bounds (a file edited by hand, or damaged
    // past its checksum, is fitted again).
    let within = |s: &Saved| {
        params
            .iter()
            .zip(&s.values)
            .all(|(p, v)| v.is_finite() && (p.lower..=p.upper).contains(v))
    };
    if saved.as_ref().is_some_and(|s| !within(s)) {
        checkpoint.refused();
    }
    let saved = saved.filter(within)?;
    // Replayed from rest at its values; a replay that fails so (it ran from a neighbour's
    // equilibrium before) is fitted again.
    let at = |values: &[f64]| -> Result<ModelFit, LabError> {
        let mut s = scene.clone();
        for (p, v) in params.iter().zip(values) {
            s = params::set(&s, p.param.name, *v)?;
        }
        let (replay, _) =
            replay_observing(recording, &s, fit_replay_options(), None, None, |_| {})?;
        model_fit(
            scene,
            params,
            values,
            replay,
            noise,
            k_total,
            saved.evaluations,
        )
        .map(|fit| ModelFit {
            seconds: saved.seconds,
            ..fit
        })
    };
    let fit = at(&saved.values).ok()?;
    checkpoint.taken(&saved);
    Some(fit)
}

/// How every fit replays: to the fits' rest tolerance, each replay keeping its samples' states
/// where they can serve (the next points start Newton from the nearest one's).
fn fit_replay_options() -> ReplayOptions {
    ReplayOptions {
        rest: RestTolerance::for_fits(),
        warm_seeds: true,
        ..ReplayOptions::default()
    }
}

/// The fitted model of `scene` with `params` at `values`, from its replay.
fn model_fit(
    scene: &Scene,
    params: &[FitParam],
    values: &[f64],
    replay: Replay,
    noise: &Noise,
    k_total: usize,
    evaluations: usize,
) -> Result<ModelFit, LabError> {
    let (rss, n) = weighted_rss(&replay.residuals, noise);
    let mut fitted_scene = scene.clone();
    for (p, v) in params.iter().zip(values) {
        fitted_scene = params::set(&fitted_scene, p.param.name, *v)?;
    }
    Ok(ModelFit {
        scene: fitted_scene,
        params: params
            .iter()
            .zip(values)
            .map(|(p, v)| (p.param.name.to_string(), *v))
            .collect(),
        errors: replay.errors,
        rss,
        n,
        k: k_total,
        bic: bic(rss, n, k_total),
        replay,
        evaluations,
        seconds: 0.0,
    })
}

/// [`fit_searching`], timed: the fit with its wall time.
fn fit_task(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    task: FitTask<'_>,
    log: Option<(&Checkpoint, u64)>,
) -> Result<ModelFit, LabError> {
    let started = std::time::Instant::now();
    let mut fit = fit_searching(recording, noise, options, task, log)?;
    fit.seconds = started.elapsed().as_secs_f64();
    Ok(fit)
}

/// The fit itself: the start and the other starts, a small design (as `search` says), then
/// Levenberg-Marquardt from the best points; the fitted model at the best point found. With
/// `log`, each simulation is logged in the checkpoint under the key given, and those logged
/// before are taken from it.
fn fit_searching(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    task: FitTask<'_>,
    log: Option<(&Checkpoint, u64)>,
) -> Result<ModelFit, LabError> {
    let FitTask {
        scene,
        params,
        k_total,
        search,
        budget,
        starts,
        floor,
        known,
    } = task;
    let space = FitSpace::new(recording, noise, options, scene, params, starts, floor);
    let cache = FitCache::new(space, options.workers, log);
    // A point that is the model a fit already ran (a candidate whose
    // effect starts switched off, or the floor, on the current fit) has
    // that fit's replay.
    if let Some(k) = known {
        cache.seed_known(k);
    }
    let best_u = search_best(&cache, search, budget, known)?;
    cache.into_model_fit(&best_u, k_total)
}

/// What a fit replays and where: the model, its fitted parameters, and the points of the unit
/// box whose values it knows exactly (its start, the other starts, the floor).
struct FitSpace<'a> {
    /// The recording every point is replayed against.
    recording: &'a Recording,
    /// The model at its own values.
    scene: &'a Scene,
    /// The fitted parameters.
    params: &'a [FitParam],
    /// The noise the residuals are weighted by.
    noise: &'a Noise,
    /// How every point replays ([`fit_replay_options`]).
    replay_options: ReplayOptions,
    /// The fitted parameters' names.
    names: Vec<&'a str>,
    /// Whether each replay solves its equilibria's sensitivities (the Jacobian from them).
    analytic: bool,
    /// The scene's own value of each parameter, where it has one.
    own: Vec<Option<f64>>,
    /// The start in the unit box: the scene's own values (0.5 where it has none).
    start: Vec<f64>,
    /// The floor in the unit box.
    floor_u: Option<Vec<f64>>,
    /// The other starts, then the floor: each in the unit box, with its values.
    others: Vec<(Vec<f64>, &'a [f64])>,
}

impl<'a> FitSpace<'a> {
    /// The space of a fit of `params` of `scene`, from `starts` and no worse than `floor`.
    fn new(
        recording: &'a Recording,
        noise: &'a Noise,
        options: &DiagnoseOptions,
        scene: &'a Scene,
        params: &'a [FitParam],
        starts: &'a [Vec<f64>],
        floor: Option<&'a [f64]>,
    ) -> Self {
        // On the default thread count: one simulation per core while a batch
        // has several, both cores for the last one left (`Simulation::set_threads`).
        let replay_options = fit_replay_options();
        // Levenberg-Marquardt's Jacobian from the equilibria's sensitivities where every fitted
        // parameter has one (a quasi-static recording): each replay solves them at its
        // equilibria, so a point the search keeps has its Jacobian with no further replay.
        let names: Vec<&str> = params.iter().map(|p| p.param.name).collect();
        let analytic = options.sensitivities
            && recording.mode == crate::recording::Mode::QuasiStatic
            && names
                .iter()
                .all(|n| crate::sensitivity::WITH_SENSITIVITY.contains(n));
        let own: Vec<Option<f64>> = params
            .iter()
            .map(|p| params::get(scene, p.param.name).ok().flatten())
            .collect();
        let start: Vec<f64> = params
            .iter()
            .zip(&own)
            .map(|(p, v)| v.map_or(0.5, |v| p.unit(v)))
            .collect();
        // The other starts and the floor, in the unit scale, with their values.
        let unit =
            |v: &[f64]| -> Vec<f64> { params.iter().zip(v).map(|(p, x)| p.unit(*x)).collect() };
        let floor_u: Option<Vec<f64>> = floor.map(unit);
        let others: Vec<(Vec<f64>, &[f64])> = starts
            .iter()
            .map(|v| v.as_slice())
            .chain(floor)
            .map(|v| (unit(v), v))
            .collect();
        FitSpace {
            recording,
            scene,
            params,
            noise,
            replay_options,
            names,
            analytic,
            own,
            start,
            floor_u,
            others,
        }
    }

    /// The replay of the model at `values` (with its sensitivities where the fit is
    /// `analytic`), Newton starting from `warm`'s states where given.
    fn run(
        &self,
        values: &[f64],
        warm: Option<&[SampleState]>,
    ) -> Result<(Replay, Option<MarkerSensitivities>), LabError> {
        let mut s = self.scene.clone();
        for (p, v) in self.params.iter().zip(values) {
            s = params::set(&s, p.param.name, *v)?;
        }
        if self.analytic {
            return replay_with_sensitivities(
                self.recording,
                &s,
                self.replay_options,
                warm,
                &self.names,
                |_| {},
            )
            .map_err(LabError::from);
        }
        replay_observing(self.recording, &s, self.replay_options, warm, None, |_| {})
            .map(|(r, _)| (r, None))
            .map_err(LabError::from)
    }

    /// The values at unit-box point `u`.
    fn value_at(&self, u: &[f64]) -> Vec<f64> {
        // The start is the scene's own values exactly (not their round trip
        // through the unit scale), so it is the scene as given; so are the
        // other starts' and the floor's values.
        if let Some((_, v)) = self.others.iter().find(|(o, _)| o == u) {
            return v.to_vec();
        }
        self.params
            .iter()
            .zip(u)
            .zip(u.iter().zip(&self.start).zip(&self.own))
            .map(|((p, x), ((a, b), v))| match v {
                Some(v) if a.to_bits() == b.to_bits() => *v,
                _ => p.value(*x),
            })
            .collect()
    }

    /// The scene at unit-box point `u`; `None` where a value cannot be set.
    fn scene_at(&self, u: &[f64]) -> Option<Scene> {
        let mut s = self.scene.clone();
        for (p, v) in self.params.iter().zip(self.value_at(u)) {
            s = params::set(&s, p.param.name, v).ok()?;
        }
        Some(s)
    }

    /// The Jacobian's columns at `u` (one per parameter, in the unit box, noise-weighted) from
    /// `replay`'s marker sensitivities `d` (per parameter value).
    fn jacobian_columns(
        &self,
        u: &[f64],
        replay: &Replay,
        d: &MarkerSensitivities,
    ) -> Vec<Vec<f64>> {
        // dp/du of each parameter's scale, by a central difference of the map itself.
        let dp_du: Vec<f64> = self
            .params
            .iter()
            .zip(u)
            .map(|(p, &x)| {
                let e = 1e-6;
                (p.value((x + e).min(1.0)) - p.value((x - e).max(0.0)))
                    / ((x + e).min(1.0) - (x - e).max(0.0))
            })
            .collect();
        (0..self.params.len())
            .map(|j| {
                let mut c = Vec::new();
                for (r, dr) in replay.residuals.iter().zip(d) {
                    let sigma = self.noise.sigma(r.marker);
                    for a in 0..3 {
                        if r.recorded[a].is_some() {
                            c.push(dr[j][a] * dp_du[j] / sigma);
                        }
                    }
                }
                c
            })
            .collect()
    }
}

/// A cache key: a unit-box point's coordinates' bits.
fn key(u: &[f64]) -> Vec<u64> {
    u.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
}

/// The cost of a point's weighted residuals: their sum of squares, infinite where it failed.
fn cost(r: &Option<Vec<f64>>) -> f64 {
    r.as_ref()
        .map_or(f64::INFINITY, |r| r.iter().map(|v| v * v).sum::<f64>())
}

/// Every point a fit has run, with its replay (the fit's best point is one of them, so its
/// replay is not run again), and how many replays it took.
struct FitCache<'a> {
    /// What the fit replays and where.
    space: FitSpace<'a>,
    /// Simulations at once (0: one per core).
    workers: usize,
    /// Every point run, with its weighted residuals and replay.
    evaluated: RefCell<Evaluated>,
    /// Each evaluated point's sensitivities, where its replay solved them.
    solved: RefCell<HashMap<Vec<u64>, MarkerSensitivities>>,
    /// Replays run by [`FitCache::evaluate`].
    evaluations: Cell<usize>,
    /// Replays run by [`FitCache::jacobian`] for points whose replay came from elsewhere.
    extra: Cell<usize>,
    /// Where each simulation is logged, and under which key.
    log: Option<(&'a Checkpoint, u64)>,
    /// Simulations logged by an earlier run of this fit, not yet asked for.
    logged: RefCell<Simulations>,
    /// Those asked for: their weighted residuals, with no replay.
    from_log: RefCell<Simulations>,
}

impl<'a> FitCache<'a> {
    /// An empty cache over `space`, running `workers` simulations at once.
    fn new(space: FitSpace<'a>, workers: usize, log: Option<(&'a Checkpoint, u64)>) -> Self {
        let logged = log.map(|(c, k)| c.simulations(k)).unwrap_or_default();
        FitCache {
            space,
            workers,
            evaluated: RefCell::default(),
            solved: RefCell::default(),
            evaluations: Cell::new(0),
            extra: Cell::new(0),
            log,
            logged: RefCell::new(logged),
            from_log: RefCell::default(),
        }
    }

    /// Takes `u` from the simulations an earlier run logged, if it is there (once: counted as
    /// a simulation of this fit).
    fn take_logged(&self, u: &[f64]) -> bool {
        let Some(logged) = self.logged.borrow_mut().remove(&key(u)) else {
            return false;
        };
        self.from_log.borrow_mut().insert(key(u), logged);
        self.evaluations.set(self.evaluations.get() + 1);
        if let Some((c, _)) = self.log {
            c.simulation_taken();
        }
        true
    }

    /// The weighted residuals at `u` where it has run or was taken from the log: `Some(None)`
    /// where its replay failed, `None` where it has neither.
    fn residuals(&self, u: &[f64]) -> Option<Option<Vec<f64>>> {
        let k = key(u);
        if let Some(f) = self.evaluated.borrow().get(&k) {
            return Some(f.as_ref().map(|f| f.0.clone()));
        }
        self.from_log.borrow().get(&k).cloned()
    }

    /// Whether `u` has its residuals or its failure, as [`FitCache::residuals`] finds them,
    /// without copying them.
    fn knows(&self, u: &[f64]) -> bool {
        let k = key(u);
        self.evaluated.borrow().contains_key(&k) || self.from_log.borrow().contains_key(&k)
    }

    /// Takes `known`'s replay for each start (the scene's own, the others, the floor) that is
    /// its model.
    fn seed_known(&self, known: &ModelFit) {
        let space = &self.space;
        for u in std::iter::once(&space.start).chain(space.others.iter().map(|(u, _)| u)) {
            if space
                .scene_at(u)
                .is_some_and(|s| same_model(&known.scene, &s))
            {
                let r = weighted_residuals(&known.replay.residuals, space.noise);
                self.evaluated
                    .borrow_mut()
                    .insert(key(u), Some((r, known.replay.clone())));
            }
        }
    }

    /// The states of the evaluated point nearest `u` in the unit box (ties to the smaller key,
    /// so the choice does not depend on the map's order), if within `WARM_DISTANCE`.
    fn nearest(&self, u: &[f64]) -> Option<Vec<SampleState>> {
        self.evaluated
            .borrow()
            .iter()
            .filter_map(|(k, f)| {
                let r = &f.as_ref()?.1;
                let d: f64 = k
                    .iter()
                    .zip(u)
                    .map(|(a, b)| (f64::from_bits(*a) - b).powi(2))
                    .sum();
                (r.states.len() == self.space.recording.samples.len() && d <= WARM_DISTANCE.powi(2))
                    .then_some((d, k, r))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then_with(|| a.1.cmp(b.1)))
            .map(|(_, _, r)| r.states.clone())
    }

    /// The weighted residuals at each of `points` (`None`: its replay failed), replaying at
    /// once those not run before.
    fn evaluate(&self, points: &[Vec<f64>]) -> Vec<Option<Vec<f64>>> {
        let space = &self.space;
        let mut todo: Vec<Vec<f64>> = Vec::new();
        for u in points {
            if !self.knows(u) && !todo.contains(u) && !self.take_logged(u) {
                todo.push(u.clone());
            }
        }
        // Chosen among the points evaluated before this batch: the same whatever order
        // the batch's runs end in.
        let warm: Vec<Option<Vec<SampleState>>> = todo.iter().map(|u| self.nearest(u)).collect();
        let results = parallel_map(
            &todo.iter().zip(&warm).collect::<Vec<_>>(),
            self.workers,
            |(u, warm)| space.run(&space.value_at(u), warm.as_deref()),
            &|_| {},
        );
        for (u, f) in todo.iter().zip(results) {
            let cancelled = matches!(f, Err(LabError::Cancelled));
            let f = f.ok().map(|(r, d)| {
                if let Some(d) = d {
                    self.solved.borrow_mut().insert(key(u), d);
                }
                (weighted_residuals(&r.residuals, space.noise), r)
            });
            // A replay stopped by a cancel is not logged: it did not fail, the next run runs it.
            if let (Some((c, k)), false) = (self.log, cancelled) {
                c.log_simulation(k, &key(u), f.as_ref().map(|f| f.0.as_slice()));
            }
            self.evaluated.borrow_mut().insert(key(u), f);
        }
        self.evaluations.set(self.evaluations.get() + todo.len());
        points.iter().map(|u| self.residuals(u).flatten()).collect()
    }

    /// The Jacobian at `u` from its replay's sensitivities, where the fit is `analytic`
    /// (`None`: finite differences instead).
    fn jacobian(&self, u: &[f64]) -> Option<Vec<Vec<f64>>> {
        let space = &self.space;
        if !space.analytic {
            return None;
        }
        if !self.solved.borrow().contains_key(&key(u)) {
            // A point whose replay came from elsewhere (a model already fitted): solved now,
            // Newton starting at its answers.
            let warm = self.nearest(u);
            let (replay, d) = space.run(&space.value_at(u), warm.as_deref()).ok()?;
            self.solved.borrow_mut().insert(key(u), d?);
            self.extra.set(self.extra.get() + 1);
            let r = weighted_residuals(&replay.residuals, space.noise);
            self.evaluated
                .borrow_mut()
                .insert(key(u), Some((r, replay)));
        }
        let cached = self.evaluated.borrow();
        let (_, replay) = cached.get(&key(u))?.as_ref()?;
        let sensitivities = self.solved.borrow();
        let d = sensitivities.get(&key(u))?;
        Some(space.jacobian_columns(u, replay, d))
    }

    /// The fitted model at unit-box point `best_u`, its replay taken from the cache (run again
    /// where it is not there).
    fn into_model_fit(self, best_u: &[f64], k_total: usize) -> Result<ModelFit, LabError> {
        let space = &self.space;
        let mut evaluations = self.evaluations.get();
        evaluations += self.extra.get();
        let values = space.value_at(best_u);
        let replay = match self.evaluated.borrow_mut().remove(&key(best_u)).flatten() {
            Some((_, r)) => r,
            None => {
                evaluations += 1;
                space.run(&values, None)?.0
            }
        };
        model_fit(
            space.scene,
            space.params,
            &values,
            replay,
            space.noise,
            k_total,
            evaluations,
        )
    }
}

/// A point to search from: in the unit box, its weighted residuals, its cost.
type Start = (Vec<f64>, Vec<f64>, f64);

/// The best point of the fit in the unit box: the start, the design, the local searches from
/// its best points, the floor where they all end worse.
fn search_best(
    cache: &FitCache<'_>,
    search: Search,
    budget: usize,
    known: Option<&ModelFit>,
) -> Result<Vec<f64>, LabError> {
    let space = &cache.space;
    let r0 = cache.evaluate(std::slice::from_ref(&space.start)).remove(0);
    let f0 = cost(&r0);
    if !f0.is_finite() {
        return Err(space
            .run(&space.value_at(&space.start), None)
            .err()
            .unwrap_or(LabError::StartFailed));
    }
    let (points, floor_f, spent) = design_step(cache, search, r0, f0);
    let (best_u, best_f) = local_searches(cache, points, search, budget, known, spent, f0);
    Ok(match &space.floor_u {
        Some(u) if floor_f < best_f => u.clone(),
        _ => best_u,
    })
}

/// The design step: the start (`r0`, cost `f0`), the other starts and, unless
/// `Search::Local`, a small space-filling design, run. The points to search from (best first),
/// the floor's cost and the runs spent.
fn design_step(
    cache: &FitCache<'_>,
    search: Search,
    r0: Option<Vec<f64>>,
    f0: f64,
) -> (Vec<Start>, f64, usize) {
    let space = &cache.space;
    let n = space.params.len();
    // A small space-filling design (2 points per parameter) against
    // local minima, then Levenberg-Marquardt (below: from the best
    // point, and where `search` says from the next best too).
    // Other starts the caller knows of (values, not unit), first, and
    // the floor. The floor is not a place to search from: where the
    // effect is off its own parameters do nothing (creep's time at
    // g 0), and a search from there stays near it.
    // The fit ends at the floor when the search ends worse.
    let mut design: Vec<Vec<f64>> = space.others.iter().map(|(u, _)| u.clone()).collect();
    if search != Search::Local {
        design.extend((1..=2 * n).map(|k| crate::fit::halton(k, n)));
    }
    let mut floor_f = f64::INFINITY;
    let mut points: Vec<Start> = Vec::new();
    if let Some(r) = r0 {
        points.push((space.start.clone(), r, f0));
    }
    for (u, r) in design.iter().zip(cache.evaluate(&design)) {
        let f = cost(&r);
        if space.floor_u.as_ref() == Some(u) {
            floor_f = f;
        } else if let Some(r) = r.filter(|_| f.is_finite()) {
            points.push((u.clone(), r, f));
        }
    }
    points.sort_by(|a, b| a.2.total_cmp(&b.2));
    let spent = 1 + design.len() - usize::from(space.floor_u.is_some());
    (points, floor_f, spent)
}

/// The Levenberg-Marquardt driver: searches from the best of `points` and, where `search` says,
/// the next best, on the budget left after `spent` runs. The best point found and its cost,
/// no worse than the start's `f0`.
fn local_searches(
    cache: &FitCache<'_>,
    points: Vec<Start>,
    search: Search,
    budget: usize,
    known: Option<&ModelFit>,
    spent: usize,
    f0: f64,
) -> (Vec<f64>, f64) {
    let fit_options = FitOptions {
        max_evaluations: budget,
        workers: cache.workers,
        x_tolerance: 2e-3,
        // A thousandth of the cost is 0.1-0.3 in BIC on these recordings,
        // against a threshold of 10: finer is runs spent on nothing.
        f_tolerance: 1e-3,
        ..FitOptions::default()
    };
    let (mut best_u, mut best_f) = (cache.space.start.clone(), f0);
    // Levenberg-Marquardt from the best point; for a candidate that
    // explains something (PROMISING) from there, also from the next
    // best point of the design (on the budget left). A candidate's
    // cost can have two valleys, and which one the search from the
    // best point ends in can turn on its start's last bits; a second
    // start from another valley makes the verdict independent of them.
    // A verdict must not turn on that. A candidate that explains
    // nothing from its best point is not searched again: that is where
    // most of the runs would go.
    let mut used = spent;
    for (i, (u, r, f)) in points.into_iter().enumerate() {
        let again = match search {
            Search::Twice => true,
            Search::Contender => known.is_some_and(|k| 1.0 - best_f / k.rss >= PROMISING),
            Search::Local | Search::Design => false,
        };
        if i >= LOCAL_SEARCHES || (i > 0 && !again) {
            break;
        }
        if f < best_f {
            (best_u, best_f) = (u.clone(), f);
        }
        let m = levenberg_marquardt_with(
            &mut |p: &[Vec<f64>]| cache.evaluate(p),
            &mut |x: &[f64]| cache.jacobian(x),
            &u,
            r,
            budget.saturating_sub(used),
            fit_options,
            JACOBIAN_STEP,
        );
        used += m.evaluations;
        if m.f < best_f {
            (best_u, best_f) = (m.x, m.f);
        }
    }
    (best_u, best_f)
}

/// Whether two scenes are the same model: equal (which values were
/// defaults aside), once their regions are
/// left out where every one of them has the object's own material (a
/// heterogeneous-stiffness candidate at its start). Such regions change no
/// element (see
/// `tests/it/diagnose.rs::a_region_of_the_objects_material_changes_nothing`);
/// one that overrides another region would, so then both must be equal.
pub fn same_model(a: &Scene, b: &Scene) -> bool {
    let plain = |s: &Scene| {
        let mut s = s.clone();
        let (e, rho) = (s.object.young_modulus, s.object.density);
        if s.regions
            .iter()
            .all(|r| r.young_modulus == e && r.density == rho)
        {
            s.regions.clear();
        }
        // Which values were defaults is no part of the model.
        s.defaults_applied.clear();
        s
    };
    a == b || plain(a) == plain(b)
}

/// `LabError::Cancelled` once the diagnosis's token is set (`softgrip_core::cancel`):
/// its simulations then fail at once, which must not read as candidates
/// that explain nothing.
pub(super) fn check_cancel() -> Result<(), LabError> {
    softgrip_core::cancel::check_scope(|| LabError::Cancelled)
}
