//! The whole grasp window as the command line, Python and the viewer run it: the settings from
//! the scene and what was asked, a fitted material set in, the statics, the dynamic
//! confirmations and the fit's uncertainty.

use std::path::Path;

use super::plan::{self, Asked, Plan};
use super::uncertainty::{self, BoundErrors};
use super::window::{Confirmation, Gripper, Most, Peak, Sample, Window};
use crate::error::LabError;
use softgrip_core::scene::Scene;

/// Both bounds lifted dynamically ([`Gripper::confirm`]), each on a thread of its own.
pub fn confirm_bounds(
    gripper: &Gripper,
    scene: &Scene,
    found: &Window,
    plan: &Plan,
    progress: &(impl Fn(Stage<'_>) + Sync),
) -> Result<Vec<Confirmation>, LabError> {
    let mut bounds = vec![found.least_squeeze()];
    bounds.extend(found.most_squeeze().filter(|&f| f > 0.0));
    let cancel = softgrip_core::cancel::current();
    std::thread::scope(|scope| {
        let lifts: Vec<_> = bounds
            .iter()
            .map(|&f| {
                let cancel = cancel.clone();
                scope.spawn(move || {
                    softgrip_core::cancel::scope(cancel, || {
                        gripper.confirm(scene, f, plan.options.damage.measure, plan.hold, |x| {
                            progress(Stage::Lift(f, x))
                        })
                    })
                })
            })
            .collect();
        lifts
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|_| {
                    Err(LabError::input("grasp window: a dynamic lift stopped"))
                })
            })
            .collect()
    })
}

/// What [`compute`] found.
#[derive(Debug, Clone)]
pub struct Computed {
    /// The scene the window is of (with the fit's values, where given).
    pub scene: Scene,
    /// The window's settings, each with where it came from.
    pub plan: Plan,
    /// The scene's gripper and object, ready to squeeze.
    pub gripper: Gripper,
    /// The window found by the statics.
    pub window: Window,
    /// The dynamic lifts at the bounds (empty without `confirm`).
    pub confirmations: Vec<Confirmation>,
    /// Each bound's standard error from the fit's, where a fit was given.
    pub errors: Option<BoundErrors>,
}

/// What [`compute`] is doing, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stage<'a> {
    /// A squeeze of the statics was solved.
    Squeeze(&'a Sample),
    /// A dynamic lift at this squeeze, this share done.
    Lift(f64, f64),
    /// The fit's uncertainty: evaluations done of the total.
    Uncertainty(usize, usize),
}

impl Computed {
    /// The figures as `--json` writes them.
    pub fn to_json(&self) -> serde_json::Value {
        let f = figures(
            &self.window,
            &self.plan,
            &self.confirmations,
            self.errors.as_ref(),
        );
        // Plain numbers, strings and lists: nothing here fails to serialize.
        serde_json::to_value(f).unwrap_or(serde_json::Value::Null)
    }
}

/// The window of `scene` with `asked` over its `[grasp]`, the fitted material of `fit` (a `fit
/// --json` file) set in and its uncertainty carried to both bounds, each bound confirmed by a
/// dynamic lift when `confirm`.
pub fn compute(
    scene: &Scene,
    asked: Asked,
    fit: Option<&Path>,
    confirm: bool,
    progress: impl Fn(Stage<'_>) + Sync,
) -> Result<Computed, LabError> {
    let fitted = fit.map(uncertainty::read_fit).transpose()?;
    let scene = match &fitted {
        Some(f) => uncertainty::with_fit(scene, f)?,
        None => scene.clone(),
    };
    let plan = plan::plan(&scene, asked)?;
    let gripper = Gripper::new(&scene, plan.options.profile)?;
    let found = gripper.window(plan.options, |s| progress(Stage::Squeeze(s)))?;
    let confirmations = if confirm {
        confirm_bounds(&gripper, &scene, &found, &plan, &progress)?
    } else {
        Vec::new()
    };
    let errors = match &fitted {
        Some(f) => Some(uncertainty::propagate(
            &scene,
            f,
            &plan,
            &found,
            |done, total| progress(Stage::Uncertainty(done, total)),
        )?),
        None => None,
    };
    Ok(Computed {
        scene,
        plan,
        gripper,
        window: found,
        confirmations,
        errors,
    })
}

/// Where a damage measure peaks, in the JSON.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PeakFigures {
    /// The measure's value (its unit: `unit`).
    pub value: f64,
    /// The element (strain, stress) or surface node (pressure).
    pub index: usize,
    /// Where it is now (m).
    pub at_m: [f64; 3],
}

impl From<&Peak> for PeakFigures {
    fn from(p: &Peak) -> Self {
        PeakFigures {
            value: p.value,
            index: p.index,
            at_m: p.at.to_array(),
        }
    }
}

/// The measure that binds where there is no window.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Binding {
    /// The damage measure's name: `strain`, `stress` or `pressure`.
    pub measure: String,
    /// The measure's limit, in its unit (Pa; none for a strain).
    pub limit: f64,
    /// The measure's peak at the least squeeze that holds, in its unit.
    pub value_at_least_squeeze: f64,
    /// Where that peak is.
    #[serde(rename = "where")]
    pub at: PeakFigures,
}

/// One squeeze tried.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SampleFigures {
    /// The squeeze, N (the largest finger's force).
    pub squeeze: f64,
    /// The squeeze held the load.
    pub held: bool,
    /// `None` where it fell.
    pub slip_m: Option<f64>,
    /// Share of the fingers' friction left unused when holding, `1 - load / (sum mu N)`.
    pub margin: f64,
    /// The damage measure's peak, holding the load where held, else squeezed.
    pub peak: PeakFigures,
}

/// One dynamic lift.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConfirmationFigures {
    /// The squeeze lifted with, N.
    pub squeeze: f64,
    /// The lift held the object ([`super::GraspRun::held`]).
    pub held: bool,
    /// No particle touched the table at the end.
    pub off_table: bool,
    /// How far the object slid down the fingers during the hold, m.
    pub hold_slip_m: f64,
    /// Seconds held after the lift, s.
    pub hold_s: f64,
    /// The damage measure's largest value over the run and where.
    pub peak: PeakFigures,
}

/// A bound's derivative in a fitted parameter (N per the parameter's unit).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Derivative {
    /// The fitted parameter's name.
    pub parameter: String,
    /// d(least squeeze)/dp, N per the parameter's unit.
    pub d_least: f64,
    /// d(most squeeze)/dp, N per the parameter's unit; `None` where the limit was not reached.
    pub d_most: Option<f64>,
}

/// What `softgrip grasp window --json` writes and Python returns (docs/cli.md): squeezes in N.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WindowFigures {
    /// The least squeeze that holds, N.
    pub least_squeeze: f64,
    /// The most squeeze before the damage limit, N; `None` where the limit was not reached.
    pub most_squeeze: Option<f64>,
    /// A squeeze both holds and stays below the limit.
    pub window: bool,
    /// The largest squeeze tried that did not hold, N (0 if none).
    pub least_dropped_at: f64,
    /// The least squeeze tried at or above the limit, N (with `most_squeeze`).
    pub most_reached_at: Option<f64>,
    /// The largest squeeze tried, all below the limit, N (without `most_squeeze`).
    pub most_not_reached_up_to: Option<f64>,
    /// The rigid force balance's least squeeze, `m |g - a| / sum mu`, N.
    pub force_balance_squeeze: f64,
    /// The load the grip carries, `m |g - a|`, N.
    pub load_n: f64,
    /// The lift's upward acceleration, m/s^2.
    pub acceleration_m_s2: f64,
    /// Where the acceleration came from.
    pub acceleration_from: String,
    /// The lift's sideways acceleration, m/s^2.
    pub shake_m_s2: f64,
    /// Held: the contacts slid by less than this, m.
    pub slip_tolerance_m: f64,
    /// The damage measure's name: `strain`, `stress` or `pressure`.
    pub measure: String,
    /// The measure's unit: `Pa`, or empty for a strain.
    pub unit: String,
    /// The damage limit, in the measure's unit.
    pub limit: f64,
    /// Where the limit came from.
    pub limit_from: String,
    /// Each bound found to within this share of itself (fraction).
    pub tolerance: f64,
    /// The measure that binds, where there is no window.
    pub binding: Option<Binding>,
    /// The least squeeze's standard error from the fit, N.
    pub least_squeeze_se: Option<f64>,
    /// The most squeeze's standard error from the fit, N.
    pub most_squeeze_se: Option<f64>,
    /// The confidence of the reported ranges (0.95), with a fit.
    pub confidence: Option<f64>,
    /// The two ends' 95 % ranges overlap, with a fit.
    pub ends_overlap: Option<bool>,
    /// Each bound's derivative in each fitted parameter, with a fit.
    pub derivatives: Option<Vec<Derivative>>,
    /// How the window was found, in words.
    pub method: String,
    /// Every squeeze tried, in order of squeeze.
    pub samples: Vec<SampleFigures>,
    /// The dynamic lifts at the bounds.
    pub confirmations: Vec<ConfirmationFigures>,
}

/// The window's figures: what `softgrip grasp window --json` writes and Python returns.
pub fn figures(
    window: &Window,
    plan: &Plan,
    confirmations: &[Confirmation],
    errors: Option<&BoundErrors>,
) -> WindowFigures {
    let o = &window.options;
    let binding = window
        .at_least()
        .filter(|_| !window.exists())
        .map(|s| Binding {
            measure: o.damage.measure.name().into(),
            limit: o.damage.limit,
            value_at_least_squeeze: s.peak.value,
            at: (&s.peak).into(),
        });
    let (most_reached_at, most_not_reached_up_to) = match window.most {
        Most::Found { above, .. } => (Some(above), None),
        Most::NotReached(f) => (None, Some(f)),
    };
    WindowFigures {
        least_squeeze: window.least_squeeze(),
        most_squeeze: window.most_squeeze(),
        window: window.exists(),
        least_dropped_at: window.least.dropped,
        most_reached_at,
        most_not_reached_up_to,
        force_balance_squeeze: window.force_balance,
        load_n: window.load,
        acceleration_m_s2: o.profile.acceleration,
        acceleration_from: plan.acceleration_from.clone(),
        shake_m_s2: o.profile.shake,
        slip_tolerance_m: o.profile.slip_tolerance,
        measure: o.damage.measure.name().into(),
        unit: o.damage.measure.unit().into(),
        limit: o.damage.limit,
        limit_from: plan.limit_from.clone(),
        tolerance: o.tolerance,
        binding,
        least_squeeze_se: errors.map(|e| e.least),
        most_squeeze_se: errors.and_then(|e| e.most),
        confidence: errors.map(|_| 0.95),
        ends_overlap: errors.map(|e| e.overlaps(window)),
        derivatives: errors.map(|e| {
            e.derivatives
                .iter()
                .map(|(n, l, m)| Derivative {
                    parameter: n.clone(),
                    d_least: *l,
                    d_most: *m,
                })
                .collect()
        }),
        method: "statics: squeeze, then the load m (g - a) with friction by its return mapping; least squeeze bisected, most by regula falsi (Illinois)".into(),
        samples: window
            .samples
            .iter()
            .map(|s| SampleFigures {
                squeeze: s.squeeze,
                held: s.held,
                slip_m: s.slip.is_finite().then_some(s.slip),
                margin: s.margin,
                peak: (&s.peak).into(),
            })
            .collect(),
        confirmations: confirmations
            .iter()
            .map(|c| ConfirmationFigures {
                squeeze: c.squeeze,
                held: c.run.held,
                off_table: c.run.off_table,
                hold_slip_m: c.run.hold_slip,
                hold_s: plan.hold,
                peak: (&c.peak).into(),
            })
            .collect(),
    }
}
