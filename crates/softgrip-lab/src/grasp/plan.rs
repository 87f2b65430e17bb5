//! A grasp window's settings: the scene's `[grasp]` and what the command line asked, with the
//! defaults where neither says, each with where it came from.

use glam::DVec3;

use super::window::{Damage, LiftProfile, Measure, WindowOptions};
use crate::error::LabError;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::model::{AxisDrive, Model};
use softgrip_core::scene::{Grasp, Scene};

/// The scene's own lift acceleration (m/s^2): the lifting fingers' largest speed over their
/// ramp time; `None` where no finger lifts or a lift starts at full speed (`ramp_time = 0`).
pub fn scene_lift_acceleration(model: &Model) -> Option<f64> {
    let up = -model.gravity.normalize_or_zero();
    model
        .fingers
        .iter()
        .filter_map(|f| {
            let v = DVec3::from_array(f.drive.map(|d| match d {
                AxisDrive::Velocity(v) => v,
                _ => 0.0,
            }));
            (v.dot(up) > 0.0 && f.ramp_time > 0.0).then(|| v.length() / f.ramp_time)
        })
        .reduce(f64::max)
}

/// What the command line asks beyond the scene's `[grasp]`: each given value wins.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Asked {
    /// The lift's upward acceleration, m/s^2.
    pub acceleration: Option<f64>,
    /// The lift's sideways acceleration, m/s^2.
    pub shake: Option<f64>,
    /// Held: the contacts slide by less than this, m.
    pub slip_tolerance: Option<f64>,
    /// Seconds held in each dynamic confirmation, s.
    pub hold: Option<f64>,
    /// The damage measure.
    pub damage: Option<Measure>,
    /// The damage limit, in the measure's unit (Pa; none for a strain).
    pub limit: Option<f64>,
}

/// The contacts' mean slide allowed when neither the scene nor the command line gives one (m).
pub const DEFAULT_SLIP_TOLERANCE: f64 = 5e-4;
/// Seconds held in a dynamic confirmation by default.
pub const DEFAULT_HOLD: f64 = 1.0;
/// Each bound to within this share of itself by default.
pub const DEFAULT_TOLERANCE: f64 = 0.01;

/// A window's settings, each with where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// How the window is searched: the lift, the damage limit, the tolerance, the statics.
    pub options: WindowOptions,
    /// Seconds held in the dynamic confirmations.
    pub hold: f64,
    /// Where the lift's acceleration and the limit came from, for the report.
    pub acceleration_from: String,
    /// Where the damage limit came from.
    pub limit_from: String,
}

/// The window's settings from the scene's `[grasp]` and what was `asked` (which wins): the lift's
/// acceleration defaults to the scene's own lift ramp, the damage measure to the material's first
/// of pressure, strain and stress; a limit must come from somewhere, and the error says where to
/// give it.
pub fn plan(scene: &Scene, asked: Asked) -> Result<Plan, LabError> {
    let g = &scene.grasp;
    let model = Model::from_scene(scene).map_err(LabError::from)?;
    let (acceleration, acceleration_from) = acceleration_of(&asked, g, &model);
    let measure = measure_of(&asked, g)?;
    let (limit, limit_from) = limit_of(&asked, g, measure)?;
    if !(limit.is_finite() && limit > 0.0) {
        return Err(LabError::Input(format!(
            "grasp window: --limit {limit}: must be > 0, in the damage measure's unit"
        )));
    }
    let profile = LiftProfile {
        acceleration,
        shake: asked.shake.or(g.shake).unwrap_or(0.0),
        slip_tolerance: asked
            .slip_tolerance
            .or(g.slip_tolerance)
            .unwrap_or(DEFAULT_SLIP_TOLERANCE),
    };
    Ok(Plan {
        options: WindowOptions {
            profile,
            damage: Damage { measure, limit },
            tolerance: DEFAULT_TOLERANCE,
            statics: window_statics(),
        },
        hold: asked.hold.or(g.hold).unwrap_or(DEFAULT_HOLD),
        acceleration_from,
        limit_from,
    })
}

/// The lift's acceleration (m/s^2) and where it came from: asked, `[grasp]`, the scene's lift,
/// or none.
fn acceleration_of(asked: &Asked, g: &Grasp, model: &Model) -> (f64, String) {
    match (asked.acceleration, g.acceleration) {
        (Some(a), _) => (a, "--acceleration".to_string()),
        (None, Some(a)) => (a, "[grasp] acceleration".to_string()),
        (None, None) => match scene_lift_acceleration(model) {
            Some(a) => (a, "the scene's lift (speed / ramp_time)".to_string()),
            None => (
                0.0,
                "none given (a lift slow enough to add nothing)".to_string(),
            ),
        },
    }
}

/// The damage measure: asked, `[grasp]`, or the material's first of pressure, strain and stress.
fn measure_of(asked: &Asked, g: &Grasp) -> Result<Measure, LabError> {
    let measure = asked.damage.or(g.damage).or_else(|| {
        g.material.and_then(|m| {
            [Measure::Pressure, Measure::Strain, Measure::Stress]
                .into_iter()
                .find(|&d| m.limit(d).is_some())
        })
    });
    let Some(measure) = measure else {
        return Err(LabError::Input(format!(
            "grasp window: no damage measure: give [grasp] damage = \"strain\", \"stress\" or \"pressure\" and its limit, or [grasp] material = one of {} (or --damage and --limit)",
            material_names().join(", ")
        )));
    };
    Ok(measure)
}

/// The damage limit (in `measure`'s unit) and where it came from: asked, `[grasp]`, or the
/// material's table.
fn limit_of(asked: &Asked, g: &Grasp, measure: Measure) -> Result<(f64, String), LabError> {
    Ok(match (asked.limit, g.limit, g.material) {
        (Some(l), _, _) => (l, "--limit".to_string()),
        (None, Some(l), _) => (l, "[grasp] limit".to_string()),
        (None, None, Some(m)) => match m.limit(measure) {
            Some(l) => (l, format!("material {:?} ({})", m.name, m.source)),
            None => {
                return Err(LabError::Input(format!(
                    "grasp window: material {:?} has no {} limit in the table: give [grasp] limit (or --limit), or a damage it has",
                    m.name,
                    measure.describe()
                )));
            }
        },
        (None, None, None) => {
            return Err(LabError::Input(format!(
                "grasp window: no limit for the {}: give [grasp] limit (in {}), or [grasp] material = one of {} (or --limit)",
                measure.describe(),
                if measure.unit().is_empty() {
                    "strain, e.g. 0.5"
                } else {
                    "Pa"
                },
                material_names().join(", ")
            )));
        }
    })
}

/// The names of the materials with damage limits in the table.
fn material_names() -> Vec<&'static str> {
    softgrip_core::scene::DAMAGE_MATERIALS
        .iter()
        .map(|m| m.name)
        .collect()
}

/// The static solver's settings for a window: more iterations than a replay's, since a grip
/// near its least squeeze converges slowly (the friction cones nearly full): on the shipped
/// cube 400 iterations put the least squeeze 1.6 % above the force balance, 3000 0.4 %.
pub fn window_statics() -> StaticOptions {
    StaticOptions {
        max_iterations: 2000,
        ..StaticOptions::default()
    }
}
