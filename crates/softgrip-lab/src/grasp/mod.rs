//! Grasp and lift: fingers squeeze an object on a table, lift it and hold
//! it. Did friction hold it, how far did it slip, and what is the least
//! friction that holds it (the boundary), against the force balance
//! `mu* = weight / sum of squeeze forces`.
//!
//! The scene says how: force-driven axes squeeze, velocity-driven axes
//! lift after `start_time`, over `ramp_time`, for `travel` (the shipped
//! `assets/scenes/grasp_lift.toml`). A run lasts until every lifting finger
//! has used its travel, then `hold` seconds more.

pub mod compute;
pub mod plan;
pub mod uncertainty;
pub mod window;

use glam::DVec3;

use crate::error::LabError;
use crate::params;
use softgrip_core::error::SimError;
use softgrip_core::model::{AxisDrive, Model};
use softgrip_core::scene::Scene;
use softgrip_core::state::TableMode;
use softgrip_core::step::Simulation;

/// How a grasp is judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraspOptions {
    /// Seconds held after the lift.
    pub hold: f64,
    /// Held means: the object rose with the fingers, left the table, and
    /// slipped down the fingers by less than this over the hold (m).
    pub slip_bound: f64,
}

impl Default for GraspOptions {
    fn default() -> Self {
        GraspOptions {
            hold: 2.0,
            slip_bound: 1e-4,
        }
    }
}

/// One grasp-and-lift run.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspRun {
    /// When the lift ended (s).
    pub lift_end: f64,
    /// How far the fingers and the object's centre of mass rose by then (m).
    pub finger_rise: f64,
    /// How far the object's centre of mass rose by the lift's end, m.
    pub object_rise: f64,
    /// How far the object slid down the fingers during the hold (m): the
    /// fingers' rise minus the object's, from the lift's end to the hold's.
    pub hold_slip: f64,
    /// No particle touches the table at the end.
    pub off_table: bool,
    /// Held: off the table, the object rose by more than half the fingers' rise, and it slid by less than the slip bound over the hold.
    pub held: bool,
    /// (time, object centre-of-mass z, mean lifting-finger z) every 10 ms.
    pub trace: Vec<[f64; 3]>,
}

fn centre_of_mass(sim: &Simulation) -> DVec3 {
    sim.state.centre_of_mass(&sim.model)
}

/// A finger's driven velocity (m/s): its velocity-driven axes'.
fn driven_velocity(f: &softgrip_core::model::FingerModel) -> DVec3 {
    DVec3::from_array(f.drive.map(|d| match d {
        AxisDrive::Velocity(v) => v,
        _ => 0.0,
    }))
}

/// The fingers that lift: driven with a velocity against gravity.
fn lifters(model: &Model) -> Vec<usize> {
    let up = -model.gravity.normalize_or_zero();
    (0..model.fingers.len())
        .filter(|&k| driven_velocity(&model.fingers[k]).dot(up) > 0.0)
        .collect()
}

/// When the lift ends (s): every lifting finger has moved its `travel`.
pub fn lift_end(model: &Model) -> Result<f64, LabError> {
    let lifting = lifters(model);
    if lifting.is_empty() {
        return Err(LabError::input(
            "no finger lifts: give one a velocity-driven axis moving it up, against gravity (and a travel)",
        ));
    }
    let mut end: f64 = 0.0;
    for k in lifting {
        let f = &model.fingers[k];
        let speed = driven_velocity(f).length();
        let Some(travel) = f.travel else {
            return Err(LabError::Input(format!(
                "finger {} lifts but has no travel: give [[finger]] travel = the lift height (m)",
                k + 1
            )));
        };
        end = end.max(f.start_time + 0.5 * f.ramp_time + travel / speed);
    }
    Ok(end)
}

/// The friction the force balance asks for: the object's weight over the
/// sum of the squeeze forces (the force-driven parts of the fingers'
/// forces across gravity). `None` without gravity or squeeze.
pub fn force_balance_friction(model: &Model) -> Option<f64> {
    let g = model.gravity;
    let down = g.normalize_or_zero();
    let weight = model.total_mass() * g.length();
    let squeeze: f64 = model
        .fingers
        .iter()
        .map(|f| {
            let driven = f.driving_force(f.force);
            (driven - down * driven.dot(down)).length()
        })
        .sum();
    (weight > 0.0 && squeeze > 0.0).then(|| weight / squeeze)
}

/// Runs the scene's grasp and lift and judges it. `progress` gets the
/// fraction done.
pub fn lift(
    scene: &Scene,
    options: GraspOptions,
    progress: impl FnMut(f64),
) -> Result<GraspRun, SimError> {
    lift_observed(scene, options, progress, |_| {})
}

/// [`lift`], with `observe` shown the simulation every 10 ms (the trace's samples).
pub fn lift_observed(
    scene: &Scene,
    options: GraspOptions,
    mut progress: impl FnMut(f64),
    mut observe: impl FnMut(&Simulation),
) -> Result<GraspRun, SimError> {
    let mut sim = Simulation::new(scene)?;
    sim.set_threads(1);
    let lift_end = lift_end(&sim.model).map_err(|what| SimError::NotSupported {
        what: format!("grasp: {what}"),
    })?;
    let lifting = lifters(&sim.model);
    let finger_z = |sim: &Simulation| {
        lifting
            .iter()
            .map(|&k| sim.state.fingers[k].position.z)
            .sum::<f64>()
            / lifting.len() as f64
    };
    let end = lift_end + options.hold;
    let (object0, finger0) = (centre_of_mass(&sim).z, finger_z(&sim));
    let mut trace = vec![[0.0, object0, finger0]];
    let mut at_lift_end = None;
    let sample = (0.01 / sim.model.dt).round().max(1.0) as u64;
    while sim.state.time + 0.5 * sim.model.dt < end {
        sim.step()?;
        if sim.state.step % sample == 0 {
            trace.push([sim.state.time, centre_of_mass(&sim).z, finger_z(&sim)]);
            progress(sim.state.time / end);
            observe(&sim);
        }
        if at_lift_end.is_none() && sim.state.time + 0.5 * sim.model.dt >= lift_end {
            at_lift_end = Some((centre_of_mass(&sim).z, finger_z(&sim)));
        }
    }
    let (object_lifted, finger_lifted) = at_lift_end.unwrap_or((object0, finger0));
    let (object1, finger1) = (centre_of_mass(&sim).z, finger_z(&sim));
    let finger_rise = finger_lifted - finger0;
    let object_rise = object_lifted - object0;
    let hold_slip = (finger1 - finger_lifted) - (object1 - object_lifted);
    let off_table = sim.state.table.iter().all(|c| c.mode == TableMode::Free);
    let held = off_table
        && object1 - object0 > 0.5 * (finger1 - finger0)
        && hold_slip.abs() < options.slip_bound;
    Ok(GraspRun {
        lift_end,
        finger_rise,
        object_rise,
        hold_slip,
        off_table,
        held,
        trace,
    })
}

/// The least finger friction (every finger's `friction`) that holds the
/// object, bisected in `[low, high]` to within `tolerance`.
#[derive(Debug, Clone, PartialEq)]
pub struct Boundary {
    /// The largest friction tried that dropped it and the least that held.
    pub dropped: f64,
    /// The least friction tried that held (friction coefficient).
    pub held: f64,
    /// Every friction tried and whether it held, in order.
    pub tries: Vec<(f64, bool)>,
}

impl Boundary {
    /// The boundary's estimate: the middle of `dropped` and `held`.
    pub fn estimate(&self) -> f64 {
        0.5 * (self.dropped + self.held)
    }
}

/// The least finger friction that holds the object in `(low, high)` (friction coefficients), by bisection to within `tolerance`; `progress` hears tries done of the total expected.
pub fn boundary_friction(
    scene: &Scene,
    options: GraspOptions,
    (low, high): (f64, f64),
    tolerance: f64,
    mut progress: impl FnMut(usize, usize),
) -> Result<Boundary, SimError> {
    let total = 2 + ((high - low) / tolerance).log2().ceil().max(0.0) as usize;
    let mut tries = Vec::new();
    let mut held_at = |mu: f64, tries: &mut Vec<(f64, bool)>| -> Result<bool, SimError> {
        let s = params::set(scene, "friction", mu).map_err(|what| SimError::NotSupported {
            what: format!("grasp: {what}"),
        })?;
        let held = lift(&s, options, |_| {})?.held;
        tries.push((mu, held));
        progress(tries.len(), total);
        Ok(held)
    };
    if held_at(low, &mut tries)? {
        return Err(SimError::NotSupported {
            what: format!(
                "grasp: the object is held even at friction {low}: friction is not what holds it (the fingers' shape or squeeze carry it), so there is no least friction to find"
            ),
        });
    }
    if !held_at(high, &mut tries)? {
        return Err(SimError::NotSupported {
            what: format!(
                "grasp: the object is dropped even at friction {high}: squeeze harder or raise the bound"
            ),
        });
    }
    let (mut dropped, mut held) = (low, high);
    while held - dropped > tolerance {
        let mid = 0.5 * (dropped + held);
        if held_at(mid, &mut tries)? {
            held = mid;
        } else {
            dropped = mid;
        }
    }
    Ok(Boundary {
        dropped,
        held,
        tries,
    })
}
