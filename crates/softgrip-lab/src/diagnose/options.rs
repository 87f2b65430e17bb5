//! How a diagnosis runs: its options, the ranges the user gives parameters (`--bound`), and
//! its progress.

use super::checkpoint::Checkpoint;
use crate::error::LabError;
use crate::fit::FitParam;
use crate::params;
use softgrip_core::scene::{BulkPressure, Elasticity, Scene};

/// How a diagnosis runs.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagnoseOptions {
    /// Baseline parameters not to fit (kept at the scene's values).
    pub lock: Vec<String>,
    /// Ranges the user knows parameters to lie in, `(name, low, high)`:
    /// every fit that moves the parameter (the baseline's, each
    /// candidate's, the pair's) searches only there. E measured as the
    /// thesis did (the initial slope of a compression test, its section
    /// V.B) is a small-strain modulus: a fit that needs several times it is
    /// absorbing physics the model lacks.
    pub bounds: Vec<(String, f64, f64)>,
    /// Simulations at most for the baseline fit ...
    pub max_evaluations: usize,
    /// ... and per parameter for each candidate's (a design of 2 points
    /// per parameter, then the local searches; the candidates start from
    /// the current fit's values).
    pub candidate_evaluations_per_param: usize,
    /// Simulations at once (0: one per core).
    pub workers: usize,
    /// At most this many effects are added.
    pub max_effects: usize,
    /// Levenberg-Marquardt's Jacobian from the equilibria's sensitivities (one replay, however
    /// many parameters) where the fitted parameters have them; finite differences elsewhere.
    pub sensitivities: bool,
    /// Each round's candidates screened by the score test first (`screen`): one replay with
    /// sensitivities, and only those it cannot rule out fitted. False: every candidate fitted.
    pub screen: bool,
    /// The region scan's shapes (`regions`, `shapes`: 48 layers, quarters, octants and the
    /// inner block scanned from the screen's replay, the best placed by short fits) may name a
    /// region of other stiffness, not only the four halves, on a screened quasi-static
    /// recording. Without it a region the halves name is still placed by the scan. Off by
    /// default while a stiff top layer and strain stiffening read alike (measured:
    /// docs/results/diagnosis-history.md).
    pub region_scan: bool,
    /// The baseline's model, in place of the scene's (`None`: the scene's own): the thesis's
    /// lattice or the continuum (`BaselineModel`). By default the continuum: its form error
    /// against a converged FE code is a few per cent at 4 mm, the lattice's 35-50 %
    /// (`docs/results/accuracy.md`), and a form error the noise test sees is read as physics.
    pub model: Option<BaselineModel>,
    /// Fits saved here as they end and taken from here when a run of the same diagnosis
    /// (recording, options, build) saved them: a diagnosis stopped midway resumes.
    pub checkpoint: Option<Checkpoint>,
}

/// The models a diagnosis can start from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaselineModel {
    /// The thesis's spring lattice (without a bulk term it may carry no load: the diagnosis then
    /// gives it the one E and nu imply, as a finding, `nominal::carries_the_loads`).
    Lattice,
    /// Neo-Hookean tetrahedra with nodal pressures (locking-free; `docs/design/neo-hookean.md`).
    Continuum,
}

impl BaselineModel {
    /// Both, as `--model` names them.
    pub const ALL: [BaselineModel; 2] = [BaselineModel::Lattice, BaselineModel::Continuum];

    /// Its `--model` name.
    pub fn name(self) -> &'static str {
        match self {
            BaselineModel::Lattice => "lattice",
            BaselineModel::Continuum => "continuum",
        }
    }

    /// The model `--model NAME` names.
    pub fn from_name(name: &str) -> Option<BaselineModel> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// `scene` with this model: the other model's own keys reset (the spring limits and the
    /// springs' stiffening law for the continuum; the elements' stiffening terms for the lattice).
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        let m = &mut s.model;
        let now = m.elasticity;
        match self {
            BaselineModel::Continuum => {
                m.elasticity = Elasticity::NeoHookean;
                m.bulk_pressure = BulkPressure::Nodal;
                m.compression_ratio = 1.0;
                if now != Elasticity::NeoHookean {
                    m.tau_s = None;
                    m.tau_c = None;
                    m.stiffening = 0.0;
                }
            }
            BaselineModel::Lattice => {
                m.elasticity = Elasticity::Springs;
                m.bulk_pressure = BulkPressure::Element;
                if now != Elasticity::Springs {
                    m.stiffening = 0.0;
                    m.stiffening_cubic = 0.0;
                    m.softening = 0.0;
                }
            }
        }
        s
    }
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            lock: Vec::new(),
            bounds: Vec::new(),
            max_evaluations: 80,
            candidate_evaluations_per_param: 20,
            workers: 0,
            max_effects: 2,
            sensitivities: false,
            screen: true,
            region_scan: false,
            model: Some(BaselineModel::Continuum),
            checkpoint: None,
        }
    }
}

/// Progress: (fits done, fits planned, what is being fitted).
pub type Progress<'a> = &'a (dyn Fn(usize, usize, &str) + Sync);

/// How a progress message that is not a stage of its own begins: a candidate's fit that ended
/// inside the stage that fits several at once ("fitted: strain-stiffening (9.9 s)").
pub const FITTED: &str = "fitted: ";

/// A diagnosis's progress in fits: how many are done of how many are
/// planned, told to its [`Progress`] as each fit starts; and the wall time of each stage, kept
/// for the report.
pub(super) struct FitCount<'a> {
    pub(super) done: usize,
    pub(super) planned: usize,
    progress: Progress<'a>,
    /// Each stage ended, with its seconds; and the one running, since when.
    pub(super) stages: Vec<(String, f64)>,
    running: Option<(String, std::time::Instant)>,
}

impl<'a> FitCount<'a> {
    pub(super) fn new(planned: usize, progress: Progress<'a>) -> Self {
        FitCount {
            done: 0,
            planned,
            progress,
            stages: Vec::new(),
            running: None,
        }
    }

    /// A fit that ran beside others (a candidate's among a round's, within the running stage)
    /// ended after `seconds` of its own: counted as done and told to the progress.
    pub(super) fn finished(&mut self, what: &str, seconds: f64) {
        self.done += 1;
        (self.progress)(
            self.done,
            self.planned,
            &format!("{FITTED}{what} ({seconds:.1} s)"),
        );
    }

    /// Tells the progress what is fitted next (the stage before it ends).
    pub(super) fn starting(&mut self, what: &str) {
        if let Some((name, since)) = self.running.take() {
            self.stages.push((name, since.elapsed().as_secs_f64()));
        }
        if what != "done" {
            self.running = Some((what.to_string(), std::time::Instant::now()));
        }
        (self.progress)(self.done, self.planned, what);
    }
}

/// Parses `NAME=LOW:HIGH` (a `--bound`).
pub fn parse_bound(text: &str) -> Result<(String, f64, f64), LabError> {
    let bad = || {
        LabError::Input(format!(
            "--bound {text:?}: write NAME=LOW:HIGH, e.g. young_modulus=30e3:120e3"
        ))
    };
    let (name, range) = text.split_once('=').ok_or_else(bad)?;
    let (low, high) = range.split_once(':').ok_or_else(bad)?;
    let number = |v: &str| v.trim().parse::<f64>().map_err(|_| bad());
    let bound = (name.trim().to_string(), number(low)?, number(high)?);
    check_bounds(std::slice::from_ref(&bound))?;
    Ok(bound)
}

/// Checks the user's ranges (`DiagnoseOptions::bounds`): a known
/// parameter, low below high, both positive where the parameter is
/// searched on a log scale.
pub fn check_bounds(bounds: &[(String, f64, f64)]) -> Result<(), LabError> {
    for (name, low, high) in bounds {
        let p = params::find(name).map_err(|e| LabError::Input(format!("--bound {name}: {e}")))?;
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(LabError::Input(format!(
                "--bound {name}={low}:{high}: give two finite values, the low one first \
                 ({name}=LOW:HIGH{})",
                if p.unit.is_empty() || p.unit == "1" {
                    String::new()
                } else {
                    format!(", in {}", p.unit)
                }
            )));
        }
        if p.log && *low <= 0.0 {
            return Err(LabError::Input(format!(
                "--bound {name}={low}:{high}: {name} is positive; give a positive low value"
            )));
        }
    }
    Ok(())
}

/// `params` with each range the user gave intersected with the fit's own;
/// a parameter whose own range misses the user's is searched at the
/// user's range's nearer end.
pub(super) fn within_bounds(
    mut params: Vec<FitParam>,
    bounds: &[(String, f64, f64)],
) -> Vec<FitParam> {
    for p in &mut params {
        for (name, low, high) in bounds {
            if p.param.name == name {
                let lower = p.lower.max(*low).min(*high);
                let upper = p.upper.min(*high).max(*low);
                p.lower = lower;
                p.upper = upper.max(lower);
            }
        }
    }
    params
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A range the user gives narrows a fit's own and never widens it; one
    /// outside the fit's own leaves the search at its nearer end.
    #[test]
    fn a_given_range_narrows_the_fits_own() {
        let e = |lower: f64, upper: f64| FitParam {
            param: params::find("young_modulus").expect("known"),
            lower,
            upper,
            log: true,
        };
        let friction = FitParam {
            param: params::find("table_friction").expect("known"),
            lower: 0.0,
            upper: 2.0,
            log: false,
        };
        let given = vec![("young_modulus".to_string(), 3e4, 1.2e5)];
        let out = within_bounds(vec![e(6e3, 6e5), friction], &given);
        assert_eq!((out[0].lower, out[0].upper), (3e4, 1.2e5));
        assert_eq!(
            (out[1].lower, out[1].upper),
            (0.0, 2.0),
            "other names untouched"
        );
        let out = within_bounds(vec![e(5e4, 8e4)], &given);
        assert_eq!((out[0].lower, out[0].upper), (5e4, 8e4), "not widened");
        let out = within_bounds(vec![e(2e5, 6e5)], &given);
        assert_eq!(
            (out[0].lower, out[0].upper),
            (1.2e5, 1.2e5),
            "the nearer end"
        );
    }

    #[test]
    fn a_bound_parses_and_bad_ones_say_what_to_write() {
        assert_eq!(
            parse_bound(" young_modulus = 3e4 : 1.2e5 "),
            Ok(("young_modulus".to_string(), 3e4, 1.2e5))
        );
        assert_eq!(
            parse_bound("table_friction=0:0.5"),
            Ok(("table_friction".to_string(), 0.0, 0.5))
        );
        for (text, says) in [
            ("young_modulus=1.2e5:3e4", "the low one first"),
            ("young_modulus=3e4:3e4", "the low one first"),
            ("young_modulus=0:3e4", "positive"),
            ("young_modulus=a:3e4", "NAME=LOW:HIGH"),
            ("young_modulus", "NAME=LOW:HIGH"),
            ("modulus=1:2", "unknown parameter"),
        ] {
            let e = parse_bound(text).expect_err(text).to_string();
            assert!(e.contains(says) && e.contains("--bound"), "{text}: {e}");
        }
    }
}
