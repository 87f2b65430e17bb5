//! What a fit is asked (its parameters, bounds and options) and gives (the fit, its uncertainty
//! and each parameter's sensitivity), and the one replay every fit runs.

use crate::compare::Errors;
use crate::error::LabError;
use crate::optimize::{BoundedScale, Tolerances};
use crate::params::{self, Param};
use crate::recording::Recording;
use crate::replay::{Replay, ReplayOptions, replay};
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::Scene;

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
    pub(super) fn design_points(&self, params: usize) -> usize {
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
pub(super) fn check_cancel() -> Result<(), LabError> {
    softgrip_core::cancel::check_scope(|| LabError::Cancelled)
}

/// A run's error as the fit's: cancelled, or the start's.
pub(super) fn start_error(e: LabError) -> LabError {
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
pub(super) fn run(recording: &Recording, scene: &Scene) -> Result<Replay, LabError> {
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    replay(recording, scene, options, |_| {}).map_err(LabError::from)
}
