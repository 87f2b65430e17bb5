//! The grasp window: the least squeeze that lifts the object and holds it through a lift, and
//! the most before a damage measure reaches its limit anywhere in it
//! (`docs/design/grasp-window.md`).
//!
//! Each squeeze is two static solves along the physical path (friction makes the answer path
//! dependent): the fingers squeeze with no body force, then the object takes its weight and the
//! lift's inertial force, `m (g - a)` (d'Alembert, in the fingers' frame), with each finger
//! contact's stick projected onto its friction cone. Held: that second solve has an equilibrium
//! and the contacts slid by less than the slip tolerance.

use std::sync::Arc;

use glam::DVec3;

use crate::error::LabError;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::error::SimError;
use softgrip_core::fields;
use softgrip_core::model::{AxisDrive, Model};
pub use softgrip_core::scene::DamageMeasure as Measure;
use softgrip_core::scene::{Scene, SupportKind};
use softgrip_core::step::Simulation;

/// The lift a grasp must survive, as accelerations of the fingers (m/s^2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftProfile {
    /// Upward, against gravity.
    pub acceleration: f64,
    /// Sideways: across gravity and across the squeeze.
    pub shake: f64,
    /// Held: the contacts slid along the fingers by less than this as the object took its load
    /// (m, their normal-force-weighted mean).
    pub slip_tolerance: f64,
}

/// The scene's gripper and object, ready to squeeze: the model with no support and no gravity
/// (the object hangs between the fingers), the lift's velocity-driven axes locked.
#[derive(Debug, Clone)]
pub struct Gripper {
    model: Arc<Model>,
    /// Each finger's applied force per newton of squeeze.
    per_newton: Vec<DVec3>,
    /// The scene's squeeze (N): its largest finger force along the force-driven axes.
    scene_squeeze: f64,
    /// The body force per kilogram while held: `g - a` (N/kg).
    body: DVec3,
    /// The lift the grip must survive.
    pub profile: LiftProfile,
}

/// One squeeze, held or not.
#[derive(Debug, Clone)]
pub struct Grip {
    /// The squeeze (N): the largest finger's force.
    pub squeeze: f64,
    /// The state squeezed, before the load.
    pub squeezed: Simulation,
    /// The state holding the load, where it has an equilibrium; why not, where not.
    pub held: Result<Simulation, String>,
    /// The contacts' slip as the object took its load (m), normal-force-weighted mean.
    pub slip: f64,
}

impl Grip {
    /// The grip reached an equilibrium holding the load and slid less than the profile's slip tolerance.
    pub fn holds(&self, profile: &LiftProfile) -> bool {
        self.held.is_ok() && self.slip <= profile.slip_tolerance
    }
}

impl Gripper {
    /// The gripper of `scene`, or why the scene cannot be gripped (no gravity, no squeezing finger, forces that do not balance, no friction).
    pub fn new(scene: &Scene, profile: LiftProfile) -> Result<Gripper, LabError> {
        let gravity = scene.simulation.gravity;
        if gravity.length() == 0.0 {
            return Err(LabError::input(
                "grasp window: the scene has no gravity: give [simulation] gravity (the object's weight is what the grip must carry)",
            ));
        }
        let mut free = scene.clone();
        free.support.kind = SupportKind::None;
        free.simulation.gravity = DVec3::ZERO;
        let mut model = Model::from_scene(&free).map_err(LabError::from)?;
        for f in &mut model.fingers {
            for d in &mut f.drive {
                if matches!(d, AxisDrive::Velocity(_)) {
                    *d = AxisDrive::Locked;
                }
            }
        }
        let largest = model
            .fingers
            .iter()
            .map(|f| f.driving_force(f.force).length())
            .fold(0.0, f64::max);
        if largest <= 0.0 {
            return Err(LabError::input(
                "grasp window: no finger squeezes: give at least two [[finger]]s a force-driven axis (free_axes with control = \"force\", or a force along an axis that is not velocity-driven) and a force",
            ));
        }
        let per_newton: Vec<DVec3> = model
            .fingers
            .iter()
            .map(|f| f.driving_force(f.force) / largest)
            .collect();
        let net: DVec3 = per_newton.iter().sum();
        if net.length() > 1e-6 {
            return Err(LabError::Input(format!(
                "grasp window: the fingers' forces do not balance (their sum is {:.3} times the largest, along ({:.2}, {:.2}, {:.2})): the squeeze would push the object away; set opposing fingers' force to equal and opposite vectors",
                net.length(),
                net.normalize().x,
                net.normalize().y,
                net.normalize().z
            )));
        }
        if model
            .fingers
            .iter()
            .zip(&per_newton)
            .all(|(f, p)| f.friction <= 0.0 || *p == DVec3::ZERO)
        {
            return Err(LabError::input(
                "grasp window: the squeezing fingers have no friction, so no squeeze lifts the object: give their [[finger]] friction (a Coulomb coefficient, e.g. 0.5)",
            ));
        }
        let up = -gravity.normalize();
        let squeeze_axis = model
            .fingers
            .iter()
            .map(|f| f.driving_force(f.force))
            .max_by(|a, b| a.length().total_cmp(&b.length()))
            .unwrap_or(DVec3::X)
            .normalize_or_zero();
        let mut side = up.cross(squeeze_axis).normalize_or_zero();
        if side == DVec3::ZERO {
            side = up.any_orthonormal_vector();
        }
        let body = gravity - up * profile.acceleration - side * profile.shake;
        Ok(Gripper {
            model: Arc::new(model),
            per_newton,
            scene_squeeze: largest,
            body,
            profile,
        })
    }

    /// The object's mass (kg).
    pub fn mass(&self) -> f64 {
        self.model.total_mass()
    }

    /// The load the grip carries (N): `m |g - a|`.
    pub fn load(&self) -> f64 {
        self.mass() * self.body.length()
    }

    /// The rigid force balance's least squeeze (N): the load over the fingers' friction
    /// coefficients times their share of the squeeze.
    pub fn force_balance(&self) -> f64 {
        let capacity: f64 = self
            .model
            .fingers
            .iter()
            .zip(&self.per_newton)
            .map(|(f, p)| f.friction * p.length())
            .sum();
        self.load() / capacity.max(f64::MIN_POSITIVE)
    }

    /// Squeezes with `squeeze` N, then loads the object with its weight and the lift's
    /// inertial force.
    pub fn grip(&self, squeeze: f64, options: StaticOptions) -> Result<Grip, LabError> {
        self.grip_as(squeeze, options, true)
    }

    /// [`Gripper::grip`]; with `load` false the squeeze alone (the grip "not held").
    fn grip_as(&self, squeeze: f64, options: StaticOptions, load: bool) -> Result<Grip, LabError> {
        let mut sim = Simulation::from_model((*self.model).clone());
        sim.set_threads(1);
        for (f, p) in sim.state.fingers.iter_mut().zip(&self.per_newton) {
            f.applied_force = *p * squeeze;
        }
        // Where Newton stalls (sphere fingers' contacts switching between sticking and sliding
        // under a weightless squeeze), time steps settle the squeeze, as replays do.
        let applied: Vec<DVec3> = sim.state.fingers.iter().map(|f| f.applied_force).collect();
        let rest = softgrip_core::quasi_static::RestTolerance::for_fits();
        match sim.settle_to_equilibrium(&applied, options, rest, |_| {}) {
            Ok(_) => {}
            Err(SimError::NoEquilibrium { why, .. }) => {
                return Err(LabError::Input(format!(
                    "grasp window: the squeeze alone, {squeeze:.4} N, has no rest ({why}): the fingers do not hold the object still before it is loaded"
                )));
            }
            Err(e) => return Err(e.into()),
        }
        if !load {
            return Ok(Grip {
                squeeze,
                squeezed: sim,
                held: Err("not loaded".into()),
                slip: f64::INFINITY,
            });
        }
        let squeezed = sim.clone();
        let mut loaded = (*sim.model).clone();
        for (c, m) in loaded.constant_force.iter_mut().zip(&loaded.mass) {
            *c += *m * self.body;
        }
        sim.model = Arc::new(loaded);
        let (held, slip) = match sim.equilibrium(options) {
            Ok(_) => {
                let slip = contact_slip(&sim);
                (Ok(sim), slip)
            }
            Err(e @ SimError::NoEquilibrium { .. }) => (Err(e.to_string()), f64::INFINITY),
            Err(e) => return Err(e.into()),
        };
        Ok(Grip {
            squeeze,
            squeezed,
            held,
            slip,
        })
    }
}

/// The finger contacts' normal-force-weighted mean slide in the last static solve (m).
fn contact_slip(sim: &Simulation) -> f64 {
    let (mut sum, mut weight) = (0.0, 0.0);
    for c in &sim.state.contacts {
        if let Some(m) = sim.state.contact_memory.get(&(c.finger, c.facet)) {
            weight += c.normal_force;
            sum += c.normal_force * m.dragged.length();
        }
    }
    if weight > 0.0 { sum / weight } else { 0.0 }
}

/// The friction the fingers' contacts can give (N): `sum mu_k N_k` over their normal forces.
fn friction_capacity(sim: &Simulation) -> f64 {
    sim.model
        .fingers
        .iter()
        .zip(&sim.state.fingers)
        .map(|(f, s)| f.friction * s.normal_force)
        .sum()
}

/// The damage measure's values over the object: per element for strain and stress, per surface
/// node for pressure.
pub fn values(measure: Measure, sim: &Simulation) -> Vec<f64> {
    match measure {
        Measure::Strain => fields::element_green_strain(&sim.model, &sim.state),
        Measure::Stress => fields::element_von_mises(&sim.model, &sim.state),
        Measure::Pressure => fields::contact_pressure(&sim.model, &sim.state),
    }
}

/// The damage measure's largest value over the object and where (an element's centroid, or the
/// node).
pub fn peak(measure: Measure, sim: &Simulation) -> Peak {
    let values = values(measure, sim);
    let (index, value) =
        values
            .iter()
            .copied()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (i, v)| {
                if v > best.1 || v.is_nan() {
                    (i, v)
                } else {
                    best
                }
            });
    let at = if measure == Measure::Pressure {
        sim.state
            .positions
            .get(index)
            .copied()
            .unwrap_or(DVec3::ZERO)
    } else {
        sim.model.tets.get(index).map_or(DVec3::ZERO, |t| {
            t.iter()
                .map(|&i| sim.state.positions[i as usize])
                .sum::<DVec3>()
                / 4.0
        })
    };
    Peak { value, index, at }
}

/// A damage measure's largest value and where: the element (or, for pressure, the surface
/// node) and its position now (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// The measure's largest value, in its unit (Pa; none for a strain).
    pub value: f64,
    /// The element (strain, stress) or surface node (pressure) where it is.
    pub index: usize,
    /// Where that element's centroid or node is now, m.
    pub at: DVec3,
}

/// The damage limit: a measure and the value it must stay below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damage {
    /// Which measure of damage.
    pub measure: Measure,
    /// The value the measure must stay below, in its unit (Pa; none for a strain).
    pub limit: f64,
}

/// How the window is searched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowOptions {
    /// The lift the grip must survive.
    pub profile: LiftProfile,
    /// The damage limit.
    pub damage: Damage,
    /// Each bound is found to within this share of itself.
    pub tolerance: f64,
    /// The static solver's settings for each squeeze.
    pub statics: StaticOptions,
}

/// One squeeze tried: whether it held, its slip margin and its damage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// The squeeze, N (the largest finger's force).
    pub squeeze: f64,
    /// The squeeze held the load ([`Grip::holds`]).
    pub held: bool,
    /// The contacts' slide as the object took its load (m); infinite where it fell.
    pub slip: f64,
    /// `1 - load / (sum mu N)`: the share of the fingers' friction left unused when holding
    /// (0 at the force balance's least squeeze, negative below it).
    pub margin: f64,
    /// The damage measure's peak, holding the load where held, else squeezed.
    pub peak: Peak,
}

/// The least squeeze that holds, bracketed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Least {
    /// The largest squeeze tried that did not hold (0 if none) ...
    pub dropped: f64,
    /// ... and the least that held: the bound.
    pub held: f64,
}

/// The largest squeeze before the damage limit, bracketed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Most {
    /// Below the limit at `below`, at or above it at `above` (the bound: `below`).
    Found {
        /// The largest squeeze tried below the limit, N: the bound.
        below: f64,
        /// The least squeeze tried at or above the limit, N.
        above: f64,
    },
    /// Below the limit at every squeeze tried, up to this one.
    NotReached(f64),
}

/// The window, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    /// The least squeeze that holds, bracketed.
    pub least: Least,
    /// The most squeeze before the damage limit, bracketed, or how far the search went without reaching it.
    pub most: Most,
    /// Every squeeze tried, in order of squeeze.
    pub samples: Vec<Sample>,
    /// The rigid force balance's least squeeze (N).
    pub force_balance: f64,
    /// The load the grip carries (N).
    pub load: f64,
    /// How the window was searched.
    pub options: WindowOptions,
}

impl Window {
    /// The least squeeze that holds (N).
    pub fn least_squeeze(&self) -> f64 {
        self.least.held
    }

    /// The most before damage (N), `None` where the limit was not reached.
    pub fn most_squeeze(&self) -> Option<f64> {
        match self.most {
            Most::Found { below, .. } => Some(below),
            Most::NotReached(_) => None,
        }
    }

    /// Whether a squeeze both holds and stays below the limit.
    pub fn exists(&self) -> bool {
        self.most_squeeze()
            .is_none_or(|most| most >= self.least.held)
    }

    /// The sample at the least squeeze that holds.
    pub fn at_least(&self) -> Option<&Sample> {
        self.samples.iter().find(|s| s.squeeze == self.least.held)
    }
}

/// Squeezes this many times the force balance's estimate at most before saying the limit is
/// not reached (or, for the least squeeze, that nothing holds).
const SEARCH_RANGE: f64 = 64.0;

impl Gripper {
    /// One squeeze, judged and measured.
    pub fn sample(&self, squeeze: f64, options: &WindowOptions) -> Result<Sample, LabError> {
        self.sample_as(squeeze, options, true)
    }

    /// [`Gripper::sample`]; with `load` false the squeeze alone, judged not held: below the
    /// force balance's least squeeze, where the fingers' friction cannot carry the load, the
    /// search for the most squeeze needs only the squeeze's damage (a failing load solve takes
    /// the longest).
    fn sample_as(
        &self,
        squeeze: f64,
        options: &WindowOptions,
        load: bool,
    ) -> Result<Sample, LabError> {
        let grip = self.grip_as(squeeze, options.statics, load)?;
        let held = grip.holds(&options.profile);
        let state = grip.held.as_ref().unwrap_or(&grip.squeezed);
        let capacity = friction_capacity(state);
        Ok(Sample {
            squeeze,
            held,
            slip: grip.slip,
            margin: 1.0 - self.load() / capacity.max(f64::MIN_POSITIVE),
            peak: peak(options.damage.measure, state),
        })
    }

    /// The window: the least squeeze by bisection from the force balance's bracket, and beside
    /// it on a second thread the most by the Illinois variant of regula falsi on `peak - limit`
    /// from the force balance up (below the least squeeze a sample's peak is the squeeze's
    /// alone). `progress` hears each squeeze tried.
    pub fn window(
        &self,
        options: WindowOptions,
        progress: impl FnMut(&Sample) + Send,
    ) -> Result<Window, LabError> {
        let progress = std::sync::Mutex::new(progress);
        let balance = self.force_balance();
        let tried = |f: f64, samples: &mut Vec<Sample>| -> Result<Sample, LabError> {
            // Below the force balance (by more than the bracket's tolerance) nothing holds.
            let s = self.sample_as(f, &options, f >= balance * (1.0 - options.tolerance))?;
            if let Ok(mut p) = progress.lock() {
                p(&s);
            }
            samples.push(s);
            Ok(s)
        };
        let cancel = softgrip_core::cancel::current();
        let (least, most) = std::thread::scope(|scope| {
            let most = scope.spawn(|| {
                softgrip_core::cancel::scope(cancel.clone(), || {
                    let mut samples = Vec::new();
                    let most = self.most(balance, &options, &mut |f| tried(f, &mut samples));
                    (most, samples)
                })
            });
            let mut samples = Vec::new();
            let least = self.least(balance, &options, &mut |f| tried(f, &mut samples));
            let (most, more) = most.join().unwrap_or_else(|_| {
                (
                    Err(LabError::input(
                        "grasp window: the search for the most squeeze stopped",
                    )),
                    Vec::new(),
                )
            });
            samples.extend(more);
            (least.map(|l| (l, samples)), most)
        });
        let (least, mut samples) = least?;
        let most = most?;
        samples.sort_by(|a, b| a.squeeze.total_cmp(&b.squeeze));
        samples.dedup_by(|a, b| a.squeeze == b.squeeze);
        Ok(Window {
            least,
            most,
            samples,
            force_balance: balance,
            load: self.load(),
            options,
        })
    }

    /// The least squeeze that holds, found again near `guess` (a bound of a nearby model): a
    /// bracket by steps of 5 %, then bisection to the options' tolerance.
    pub fn least_near(&self, guess: f64, options: &WindowOptions) -> Result<f64, LabError> {
        let holds = |f: f64| -> Result<bool, LabError> { Ok(self.sample(f, options)?.held) };
        let (mut dropped, mut held) = (guess, guess);
        if holds(guess)? {
            while {
                dropped = held / 1.05;
                holds(dropped)?
            } {
                held = dropped;
            }
        } else {
            while {
                held = dropped * 1.05;
                !holds(held)?
            } {
                dropped = held;
                if held > SEARCH_RANGE * guess {
                    return Err(LabError::Input(format!(
                        "grasp window: not held near {guess:.4} N with the parameter changed: the window is too sensitive to it for a difference"
                    )));
                }
            }
        }
        while held - dropped > options.tolerance * held {
            let mid = 0.5 * (dropped + held);
            if holds(mid)? {
                held = mid;
            } else {
                dropped = mid;
            }
        }
        Ok(held)
    }

    /// The most before damage found again near `guess`: a bracket by steps of 5 %, then regula
    /// falsi to the options' tolerance.
    pub fn most_near(&self, guess: f64, options: &WindowOptions) -> Result<f64, LabError> {
        let excess = |f: f64| -> Result<(f64, f64), LabError> {
            let v = self.sample(f, options)?.peak.value;
            Ok((
                f,
                if v.is_nan() {
                    f64::INFINITY
                } else {
                    v - options.damage.limit
                },
            ))
        };
        let first = excess(guess)?;
        let (below, above) = if first.1 < 0.0 {
            let mut below = first;
            loop {
                if below.0 > SEARCH_RANGE * guess {
                    return Err(LabError::Input(format!(
                        "grasp window: the limit is not reached near {guess:.4} N with the parameter changed: the window is too sensitive to it for a difference"
                    )));
                }
                let next = excess(below.0 * 1.05)?;
                if next.1 >= 0.0 {
                    break (below, next);
                }
                below = next;
            }
        } else {
            let mut above = first;
            loop {
                if above.0 < guess / SEARCH_RANGE {
                    return Ok(0.0);
                }
                let next = excess(above.0 / 1.05)?;
                if next.1 < 0.0 {
                    break (next, above);
                }
                above = next;
            }
        };
        match self.regula_falsi(below, above, options, &mut |f| self.sample(f, options))? {
            Most::Found { below, .. } => Ok(below),
            Most::NotReached(f) => Ok(f),
        }
    }

    fn least(
        &self,
        balance: f64,
        options: &WindowOptions,
        try_at: &mut dyn FnMut(f64) -> Result<Sample, LabError>,
    ) -> Result<Least, LabError> {
        let (mut dropped, mut held) = (0.0, f64::NAN);
        let mut f = balance;
        while held.is_nan() {
            if try_at(f)?.held {
                held = f;
            } else {
                dropped = f;
                f *= 2.0;
                if f > SEARCH_RANGE * balance {
                    return Err(LabError::Input(format!(
                        "grasp window: the object is not held even at a squeeze of {:.4} N ({SEARCH_RANGE} times the force balance's {balance:.4} N): the fingers' friction cannot carry it; give the fingers more friction or a shape that cradles it",
                        dropped
                    )));
                }
            }
        }
        if dropped == 0.0 {
            // Held at the force balance: look below it.
            let mut f = 0.5 * held;
            while f > balance / SEARCH_RANGE {
                if try_at(f)?.held {
                    held = f;
                    f *= 0.5;
                } else {
                    dropped = f;
                    break;
                }
            }
        }
        while held - dropped > options.tolerance * held {
            let mid = 0.5 * (dropped + held);
            if try_at(mid)?.held {
                held = mid;
            } else {
                dropped = mid;
            }
        }
        Ok(Least { dropped, held })
    }

    fn most(
        &self,
        start: f64,
        options: &WindowOptions,
        try_at: &mut dyn FnMut(f64) -> Result<Sample, LabError>,
    ) -> Result<Most, LabError> {
        let limit = options.damage.limit;
        let excess = |s: &Sample| {
            if s.peak.value.is_nan() {
                f64::INFINITY
            } else {
                s.peak.value - limit
            }
        };
        // From `start`, doubling until the limit is passed.
        let mut below = (start, excess(&try_at(start)?));
        if below.1 >= 0.0 {
            // Damaged already: bracket the limit below.
            let mut f = 0.5 * start;
            let mut above = below;
            while f > start / SEARCH_RANGE {
                let e = excess(&try_at(f)?);
                if e < 0.0 {
                    return self.regula_falsi((f, e), above, options, try_at);
                }
                above = (f, e);
                f *= 0.5;
            }
            return Ok(Most::Found {
                below: 0.0,
                above: above.0,
            });
        }
        let mut f = 2.0 * start;
        loop {
            let e = excess(&try_at(f)?);
            if e >= 0.0 {
                return self.regula_falsi(below, (f, e), options, try_at);
            }
            below = (f, e);
            if f >= SEARCH_RANGE * start {
                return Ok(Most::NotReached(f));
            }
            f *= 2.0;
        }
    }

    /// The Illinois method on a bracket `below` (excess < 0) to `above` (>= 0): regula falsi,
    /// with the value kept at an end that stays twice in a row halved; each try kept inside the
    /// middle 90 % of the bracket, and a bisection where the end above has no finite value (an
    /// element inside out).
    fn regula_falsi(
        &self,
        mut below: (f64, f64),
        mut above: (f64, f64),
        options: &WindowOptions,
        try_at: &mut dyn FnMut(f64) -> Result<Sample, LabError>,
    ) -> Result<Most, LabError> {
        let mut last_above = None;
        while above.0 - below.0 > options.tolerance * below.0.max(f64::MIN_POSITIVE) {
            let width = above.0 - below.0;
            let f = if above.1.is_finite() {
                (below.0 - below.1 * width / (above.1 - below.1))
                    .clamp(below.0 + 0.05 * width, above.0 - 0.05 * width)
            } else {
                below.0 + 0.5 * width
            };
            let s = try_at(f)?;
            let e = if s.peak.value.is_nan() {
                f64::INFINITY
            } else {
                s.peak.value - options.damage.limit
            };
            let is_above = e >= 0.0;
            if is_above {
                above = (f, e);
                if last_above == Some(true) {
                    below.1 *= 0.5;
                }
            } else {
                below = (f, e);
                if last_above == Some(false) {
                    above.1 *= 0.5;
                }
            }
            last_above = Some(is_above);
        }
        Ok(Most::Found {
            below: below.0,
            above: above.0,
        })
    }
}

/// A bound confirmed by one dynamic lift of the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Confirmation {
    /// The squeeze lifted with, N.
    pub squeeze: f64,
    /// The dynamic lift and its hold.
    pub run: super::GraspRun,
    /// The damage measure's largest value over the run (sampled every 10 ms) and where.
    pub peak: Peak,
}

impl Gripper {
    /// The scene with every finger's force scaled to `squeeze` and its lift ramped to the
    /// profile's acceleration (the lifting fingers' `ramp_time = speed / acceleration`).
    pub fn scene_at(&self, scene: &Scene, squeeze: f64) -> Scene {
        let mut s = scene.clone();
        let up = -scene.simulation.gravity.normalize_or_zero();
        for f in &mut s.fingers {
            f.force *= squeeze / self.scene_squeeze;
            let lifts = f.velocity.dot(up) > 0.0;
            if lifts && self.profile.acceleration > 0.0 {
                f.ramp_time = f.velocity.length() / self.profile.acceleration;
            }
        }
        s
    }

    /// Lifts the scene dynamically at `squeeze` ([`super::lift`]) and holds it `hold` s: held or
    /// not, and the damage measure's peak over the run.
    pub fn confirm(
        &self,
        scene: &Scene,
        squeeze: f64,
        measure: Measure,
        hold: f64,
        progress: impl FnMut(f64),
    ) -> Result<Confirmation, LabError> {
        let lifted = self.scene_at(scene, squeeze);
        let options = super::GraspOptions {
            hold,
            slip_bound: self.profile.slip_tolerance,
        };
        let mut highest: Option<Peak> = None;
        let run = super::lift_observed(&lifted, options, progress, |sim| {
            let p = peak(measure, sim);
            if highest.is_none_or(|h| p.value > h.value || p.value.is_nan()) {
                highest = Some(p);
            }
        })?;
        Ok(Confirmation {
            squeeze,
            run,
            peak: highest.unwrap_or(Peak {
                value: f64::NAN,
                index: 0,
                at: DVec3::ZERO,
            }),
        })
    }
}
