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
    pub plan: Plan,
    pub gripper: Gripper,
    pub window: Window,
    pub confirmations: Vec<Confirmation>,
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
#[derive(Debug, Clone, serde::Serialize)]
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
#[derive(Debug, Clone, serde::Serialize)]
pub struct Binding {
    pub measure: &'static str,
    pub limit: f64,
    pub value_at_least_squeeze: f64,
    #[serde(rename = "where")]
    pub at: PeakFigures,
}

/// One squeeze tried.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SampleFigures {
    pub squeeze: f64,
    pub held: bool,
    /// `None` where it fell.
    pub slip_m: Option<f64>,
    pub margin: f64,
    pub peak: PeakFigures,
}

/// One dynamic lift.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ConfirmationFigures {
    pub squeeze: f64,
    pub held: bool,
    pub off_table: bool,
    pub hold_slip_m: f64,
    pub hold_s: f64,
    pub peak: PeakFigures,
}

/// A bound's derivative in a fitted parameter (N per the parameter's unit).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Derivative {
    pub parameter: String,
    pub d_least: f64,
    pub d_most: Option<f64>,
}

/// What `softgrip grasp window --json` writes and Python returns (docs/cli.md): squeezes in N.
#[derive(Debug, Clone, serde::Serialize)]
pub struct WindowFigures {
    pub least_squeeze: f64,
    pub most_squeeze: Option<f64>,
    pub window: bool,
    pub least_dropped_at: f64,
    pub most_reached_at: Option<f64>,
    pub most_not_reached_up_to: Option<f64>,
    pub force_balance_squeeze: f64,
    pub load_n: f64,
    pub acceleration_m_s2: f64,
    pub acceleration_from: String,
    pub shake_m_s2: f64,
    pub slip_tolerance_m: f64,
    pub measure: &'static str,
    pub unit: &'static str,
    pub limit: f64,
    pub limit_from: String,
    pub tolerance: f64,
    pub binding: Option<Binding>,
    pub least_squeeze_se: Option<f64>,
    pub most_squeeze_se: Option<f64>,
    pub confidence: Option<f64>,
    pub ends_overlap: Option<bool>,
    pub derivatives: Option<Vec<Derivative>>,
    pub method: &'static str,
    pub samples: Vec<SampleFigures>,
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
            measure: o.damage.measure.name(),
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
        measure: o.damage.measure.name(),
        unit: o.damage.measure.unit(),
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
        method: "statics: squeeze, then the load m (g - a) with friction by its return mapping; least squeeze bisected, most by regula falsi (Illinois)",
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
