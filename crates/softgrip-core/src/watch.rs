//! Physical sanity checks a run makes as it goes: the answers that look like results but are
//! not. A finger that passed through the object (tunnelling: a 1e6 N load on a stiff cube at a
//! large `dt` ended 76 mm below its base with no contact), a force-driven finger that never
//! carried its load, a spring limit violated past its band, energy gained with no work done.
//! Each is found once, with the time and its cause in words; `softgrip run` prints them as
//! warnings (errors with `--strict`). Cheap: one pass over the particles a step.

use glam::DVec3;

use crate::model::{AxisDrive, Model};
use crate::state::State;

/// What went wrong physically.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// A finger came out beyond the object's far side with no contact.
    Tunnelled,
    /// A force-driven finger ended unbalanced and still moving.
    LoadNotCarried,
    /// A spring ended longer or shorter than its limit by more than [`LIMIT_BAND`].
    LimitViolated,
    /// The energy rose while nothing did work on the object.
    EnergyGained,
}

impl Kind {
    /// The name in JSON and tests.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Tunnelled => "tunnelled",
            Kind::LoadNotCarried => "load-not-carried",
            Kind::LimitViolated => "limit-violated",
            Kind::EnergyGained => "energy-gained",
        }
    }
}

/// One finding: its kind, the finger (if one), when it was first seen, and what it means.
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// What was found.
    pub kind: Kind,
    /// The finger concerned, 0-based; `None` for the object as a whole.
    pub finger: Option<usize>,
    /// Simulated time it was first seen, s.
    pub time: f64,
    /// What it means, in words for the user.
    pub message: String,
    /// The cause may be the time step: the caller may check whether this smaller `dt` helps
    /// before it advises one (`softgrip run` does).
    pub try_dt: Option<f64>,
}

/// Relative spring-limit violation left after the projection that is still "at the limit":
/// the projection stops at `constraint_tolerance` (1e-3 by default); 5 % is a spring the
/// projection gave up on.
pub const LIMIT_BAND: f64 = 0.05;

/// A force-driven finger whose contact balances less than this share of its load at the end,
/// still moving, did not carry it.
const UNBALANCED: f64 = 0.1;

/// Energy rise (J) over the lowest since work input stopped, as a share of the largest energy
/// magnitude seen, that counts as gained ...
const ENERGY_RISE: f64 = 0.05;
/// ... when it lasts this many steps: a blow-up grows; a stiff contact's first steps can
/// overshoot by 9 % and settle.
const ENERGY_STEPS: usize = 10;

/// Watches a run step by step.
#[derive(Debug, Clone, Default)]
pub struct Watch {
    findings: Vec<Finding>,
    /// The lowest energy since work input last stopped (J), and when.
    lowest: Option<(f64, f64)>,
    /// The largest energy magnitude seen (J).
    scale: f64,
    worst_limit: (f64, f64),
    /// Steps in a row the energy has stood above the lowest by more than the share.
    above: usize,
}

impl Watch {
    /// A watch that has found nothing yet.
    pub fn new() -> Watch {
        Watch::default()
    }

    /// What was found so far, in the order found.
    pub fn findings(&self) -> &[Finding] {
        &self.findings
    }

    fn found(&self, kind: Kind, finger: Option<usize>) -> bool {
        self.findings
            .iter()
            .any(|f| f.kind == kind && f.finger == finger)
    }

    /// After each step.
    pub fn step(&mut self, model: &Model, state: &State) {
        self.tunnelling(model, state);
        self.energy(model, state);
        let v = state.stats.limit_violation;
        if v > self.worst_limit.0 {
            self.worst_limit = (v, state.time);
        }
    }

    /// At the end of the run: the findings that only the end can tell, then all of them.
    pub fn finish(&mut self, model: &Model, state: &State) -> &[Finding] {
        self.loads(model, state);
        let (v, t) = self.worst_limit;
        if v > LIMIT_BAND && !self.found(Kind::LimitViolated, None) {
            self.findings.push(Finding {
                kind: Kind::LimitViolated,
                finger: None,
                time: t,
                message: format!(
                    "a spring stayed {:.0} % of its rest length past its limit (tau_s / tau_c) at t = {t:.4} s after the projection: the limits did not hold, so the result is not capped by them (the lattice was pulled or crushed past what the projection restores)",
                    100.0 * v
                ),
                try_dt: None,
            });
        }
        &self.findings
    }

    fn tunnelling(&mut self, model: &Model, state: &State) {
        if state.positions.is_empty() {
            return;
        }
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &state.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        for (k, (f, fs)) in model.fingers.iter().zip(&state.fingers).enumerate() {
            let Some(d) = pushing(f, fs) else { continue };
            if fs.normal_force > 0.0 || self.found(Kind::Tunnelled, Some(k)) {
                continue;
            }
            // Over the object: inside its box across the push (the push along one axis).
            let Some(axis) = (0..3).find(|&a| d[a].abs() > 0.99) else {
                continue;
            };
            let c = fs.position;
            let across = (0..3)
                .filter(|&a| a != axis)
                .all(|a| c[a] > lo[a] && c[a] < hi[a]);
            let far = if d[axis] > 0.0 { hi[axis] } else { -lo[axis] };
            let back = c[axis] * d[axis].signum() - f.shape.reach_along(-d);
            if across && back > far + model.edge_length {
                let (cause, try_dt) = tunnelling_cause(model, f, fs);
                self.findings.push(Finding {
                    kind: Kind::Tunnelled,
                    finger: Some(k),
                    time: state.time,
                    message: format!(
                        "finger {} passed through the object: at t = {:.4} s it is {:.1} mm beyond the object's far side with no contact; its results (depth, contact force) are not physical. {cause}",
                        k + 1,
                        state.time,
                        1e3 * (back - far),
                    ),
                    try_dt,
                });
            }
        }
    }

    fn energy(&mut self, model: &Model, state: &State) {
        let e = state.stats.energy;
        if !e.is_finite() {
            return;
        }
        self.scale = self.scale.max(e.abs()).max(state.stats.kinetic_energy);
        // The spring-limit projection moves particles without a force: not work, not a blow-up.
        if work_input(model, state) || state.stats.projection_sweeps > 0 {
            self.lowest = None;
            self.above = 0;
            return;
        }
        let (low, since) = match self.lowest {
            Some((low, since)) if low <= e => (low, since),
            _ => (e, state.time),
        };
        self.lowest = Some((low, since));
        if e - low > ENERGY_RISE * self.scale.max(1e-12) {
            self.above += 1;
        } else {
            self.above = 0;
        }
        if self.above >= ENERGY_STEPS && !self.found(Kind::EnergyGained, None) {
            self.findings.push(Finding {
                kind: Kind::EnergyGained,
                finger: None,
                time: state.time,
                message: format!(
                    "the energy rose by {:.3e} J from t = {since:.4} s to {:.4} s and stayed up while nothing did work on the object (no finger moving under velocity control, loads constant, no spring limit projected): the integration is not stable at dt = {} s",
                    e - low,
                    state.time,
                    model.dt
                ),
                try_dt: None,
            });
        }
    }

    fn loads(&mut self, model: &Model, state: &State) {
        for (k, (f, fs)) in model.fingers.iter().zip(&state.fingers).enumerate() {
            if !f.is_force_controlled() || fs.held.is_some() {
                continue;
            }
            let load = f.driving_force(fs.applied_force);
            if load.length() == 0.0 {
                continue;
            }
            let d = load.normalize();
            // -0 and rounding dust read as "pushes back 0 N".
            let carried = -fs.contact_force.dot(d) + 0.0;
            let moving = fs.velocity.dot(d);
            // A mass-less finger free of contact moves at its guide speed; one with mass that
            // still moves at a thousandth of a metre a second has not come to rest either.
            let still_moving = if f.mass == 0.0 {
                moving > 0.5 * f.guide_speed
            } else {
                moving > 1e-3
            };
            let short = load.length() - carried - f.guide_friction;
            if short > UNBALANCED * load.length() && still_moving {
                self.findings.push(Finding {
                    kind: Kind::LoadNotCarried,
                    finger: Some(k),
                    time: state.time,
                    message: format!(
                        "finger {} did not carry its load of {:.4e} N: at the end (t = {:.4} s) the object pushes back {:.4e} N and the finger still moves at {:.3e} m/s into it{}",
                        k + 1,
                        load.length(),
                        state.time,
                        carried,
                        moving,
                        if f.mass == 0.0 {
                            format!(" (its guide speed is {} m/s)", f.guide_speed)
                        } else {
                            String::new()
                        }
                    ),
                    try_dt: None,
                });
            }
        }
    }
}

/// Why a finger went through, in words, and a smaller `dt` worth checking where the step may be
/// the cause. A sphere's Hertz contact carries `F = K d^1.5` a facet: a load that needs `d`
/// past the radius sinks the sphere between the surface nodes at any `dt`.
fn tunnelling_cause(
    model: &Model,
    f: &crate::model::FingerModel,
    fs: &crate::state::FingerState,
) -> (String, Option<f64>) {
    let load = f.driving_force(fs.applied_force).length();
    if let crate::scene::FingerShape::Sphere { radius } = f.shape {
        let k = f.hertz_stiffness * f.contact_stiffness_scale;
        let depth = (load / k).powf(2.0 / 3.0);
        if load > 0.0 && depth > radius {
            return (
                format!(
                    "Its load of {load:.4e} N needs the Hertz contact (K = {k:.3e} N/m^1.5) to sink about {:.1} mm, more than the sphere's radius ({:.1} mm): lower the load, or stiffen the contact (the finger's young_modulus, contact_stiffness_scale)",
                    1e3 * depth,
                    1e3 * radius
                ),
                None,
            );
        }
    }
    let step = fs.velocity.length() * model.dt;
    (
        format!(
            "It moved {:.2} mm in its last step (dt = {} s, {:.3e} m/s) against edges of {:.1} mm.",
            1e3 * step,
            model.dt,
            fs.velocity.length(),
            1e3 * model.edge_length
        ),
        Some(model.dt / 10.0),
    )
}

/// The unit direction a finger pushes in: its load's (force control) or its commanded
/// velocity's, or `None` for a finger that pushes nowhere.
fn pushing(f: &crate::model::FingerModel, fs: &crate::state::FingerState) -> Option<DVec3> {
    let load = f.driving_force(fs.applied_force);
    if load.length() > 0.0 {
        return Some(load.normalize());
    }
    let v = DVec3::from_array(f.drive.map(|d| match d {
        AxisDrive::Velocity(v) => v,
        _ => 0.0,
    }));
    (v.length() > 0.0).then(|| v.normalize())
}

/// Whether something does work on the object at this step: a finger moving under velocity
/// control (or ramping), or one held by the viewer.
fn work_input(model: &Model, state: &State) -> bool {
    state.pull.is_some()
        || model.fingers.iter().zip(&state.fingers).any(|(f, fs)| {
            fs.held.is_some()
                || f.drive
                    .iter()
                    .any(|d| matches!(d, AxisDrive::Velocity(v) if *v != 0.0))
                    && f.travel.is_none_or(|t| fs.travelled < t)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// The built-in scene's model, its finger unloaded (no work input, nothing pushing).
    fn quiet() -> (Model, State) {
        let mut scene = Scene::thesis();
        for f in &mut scene.fingers {
            f.force = DVec3::ZERO;
            f.velocity = DVec3::ZERO;
        }
        let model = Model::from_scene(&scene).expect("model");
        let state = State::initial(&model);
        (model, state)
    }

    fn run(energies: &[f64], sweeps: impl Fn(usize) -> usize) -> Vec<Kind> {
        let (model, mut state) = quiet();
        let mut watch = Watch::new();
        for (i, &e) in energies.iter().enumerate() {
            state.time = i as f64 * model.dt;
            state.stats.energy = e;
            state.stats.projection_sweeps = sweeps(i);
            watch.step(&model, &state);
        }
        watch
            .finish(&model, &state)
            .iter()
            .map(|f| f.kind)
            .collect()
    }

    #[test]
    fn energy_that_rises_and_stays_up_is_gained_a_blip_is_not() {
        let mut rising = vec![1.0, 0.9];
        rising.extend((0..12).map(|i| 1.0 + 0.1 * i as f64));
        assert_eq!(run(&rising, |_| 0), vec![Kind::EnergyGained]);
        // Up 9 % for three steps, then down: a stiff contact's first steps.
        let blip = [
            1.0, 0.9, 0.99, 0.99, 0.99, 0.8, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7,
        ];
        assert!(run(&blip, |_| 0).is_empty());
        // Falling energy (damping) is what a stable run does.
        let falling: Vec<f64> = (0..30).map(|i| 1.0 / (1.0 + i as f64)).collect();
        assert!(run(&falling, |_| 0).is_empty());
        // The spring-limit projection moves particles without work: not counted.
        assert!(run(&rising, |_| 1).is_empty());
    }

    #[test]
    fn a_spring_past_its_limit_band_is_found_within_it_not() {
        let (model, mut state) = quiet();
        for (v, expected) in [(0.02, false), (0.2, true)] {
            let mut watch = Watch::new();
            state.stats.limit_violation = v;
            watch.step(&model, &state);
            let found = watch
                .finish(&model, &state)
                .iter()
                .any(|f| f.kind == Kind::LimitViolated);
            assert_eq!(found, expected, "violation {v}");
        }
    }

    #[test]
    fn a_finger_beyond_the_far_side_without_contact_tunnelled() {
        let (model, mut state) = quiet();
        let mut scene_finger = model.fingers[0].clone();
        scene_finger.force = DVec3::new(0.0, 0.0, -10.0);
        let mut model = model;
        model.fingers[0] = scene_finger;
        state.fingers[0].applied_force = DVec3::new(0.0, 0.0, -10.0);
        // Above the object: nothing.
        let mut watch = Watch::new();
        watch.step(&model, &state);
        assert!(watch.findings().is_empty());
        // Below its base (z = 0) by more than an edge, over it, no contact: through.
        state.fingers[0].position = DVec3::new(0.0, 0.0, -0.03);
        watch.step(&model, &state);
        assert_eq!(watch.findings().len(), 1);
        assert_eq!(watch.findings()[0].kind, Kind::Tunnelled);
        // Beside it, not over it: a finger may pass there.
        let mut watch = Watch::new();
        state.fingers[0].position = DVec3::new(0.1, 0.0, -0.03);
        watch.step(&model, &state);
        assert!(watch.findings().is_empty());
    }
}
