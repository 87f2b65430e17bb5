//! The whole grasp window as the command line, Python and the viewer run it: the settings from
//! the scene and what was asked, a fitted material set in, the statics, the dynamic
//! confirmations and the fit's uncertainty.

use std::path::Path;

use super::uncertainty::{self, BoundErrors};
use super::window::{self, Asked, Confirmation, Gripper, Most, Peak, Plan, Sample, Window};
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
        to_json(
            &self.window,
            &self.plan,
            &self.confirmations,
            self.errors.as_ref(),
        )
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
    let plan = window::plan(&scene, asked)?;
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

/// The window's figures as JSON: what `softgrip grasp window --json` writes and Python returns.
pub fn to_json(
    window: &Window,
    plan: &Plan,
    confirmations: &[Confirmation],
    errors: Option<&BoundErrors>,
) -> serde_json::Value {
    use serde_json::json;
    let o = &window.options;
    let peak = |p: &Peak| json!({"value": p.value, "index": p.index, "at_m": p.at.to_array()});
    let binding = (!window.exists()).then(|| {
        window.at_least().map(|s| {
            json!({
                "measure": o.damage.measure.name(),
                "limit": o.damage.limit,
                "value_at_least_squeeze": s.peak.value,
                "where": peak(&s.peak),
            })
        })
    });
    json!({
        "least_squeeze": window.least_squeeze(),
        "most_squeeze": window.most_squeeze(),
        "window": window.exists(),
        "least_dropped_at": window.least.dropped,
        "most_reached_at": match window.most {
            Most::Found { above, .. } => Some(above),
            Most::NotReached(_) => None,
        },
        "most_not_reached_up_to": match window.most {
            Most::NotReached(f) => Some(f),
            Most::Found { .. } => None,
        },
        "force_balance_squeeze": window.force_balance,
        "load_n": window.load,
        "acceleration_m_s2": o.profile.acceleration,
        "acceleration_from": plan.acceleration_from,
        "shake_m_s2": o.profile.shake,
        "slip_tolerance_m": o.profile.slip_tolerance,
        "measure": o.damage.measure.name(),
        "unit": o.damage.measure.unit(),
        "limit": o.damage.limit,
        "limit_from": plan.limit_from,
        "tolerance": o.tolerance,
        "binding": binding.flatten(),
        "least_squeeze_se": errors.map(|e| e.least),
        "most_squeeze_se": errors.and_then(|e| e.most),
        "confidence": errors.map(|_| 0.95),
        "ends_overlap": errors.map(|e| e.overlaps(window)),
        "derivatives": errors.map(|e| e.derivatives.iter().map(|(n, l, m)| json!({
            "parameter": n, "d_least": l, "d_most": m
        })).collect::<Vec<_>>()),
        "method": "statics: squeeze, then the load m (g - a) with friction by its return mapping; least squeeze bisected, most by regula falsi (Illinois)",
        "samples": window.samples.iter().map(|s| json!({
            "squeeze": s.squeeze,
            "held": s.held,
            "slip_m": if s.slip.is_finite() { Some(s.slip) } else { None },
            "margin": s.margin,
            "peak": peak(&s.peak),
        })).collect::<Vec<_>>(),
        "confirmations": confirmations.iter().map(|c| json!({
            "squeeze": c.squeeze,
            "held": c.run.held,
            "off_table": c.run.off_table,
            "hold_slip_m": c.run.hold_slip,
            "hold_s": plan.hold,
            "peak": peak(&c.peak),
        })).collect::<Vec<_>>(),
    })
}
