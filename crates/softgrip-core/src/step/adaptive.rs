//! Error-controlled time steps: a time series replayed with the steps its accuracy needs, not
//! the scene's `dt` throughout. A slow creep held for 30 s is 15,000 steps at 2 ms and some
//! hundred controlled ones.
//!
//! Step doubling (Hairer, Norsett and Wanner, Solving ODEs I, II.4): from each state one step of
//! `h` and two of `h / 2`; their difference estimates the local error of the step of `h` (implicit
//! Euler's is `O(h^2)`, so the two half steps' is about half of it). The two half steps are kept
//! when the largest difference of a particle or finger is within the tolerance; the step is
//! doubled after one well within it (an eighth), halved and tried again after one beyond it.
//! Steps are the scene's `dt` times a power of two, cut short to land on the requested time; at
//! `dt` itself no estimate is made (the fixed-step replay). Everything a step does (contacts,
//! friction anchors, Prony arms, the divergence checks) it does at its own `h`.

use std::sync::Arc;

use glam::DVec3;

use super::Simulation;
use crate::error::SimError;
use crate::model::Model;

/// How the steps are controlled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveOptions {
    /// The largest local error kept, m (the difference of a particle or finger between one step
    /// and two half steps).
    pub tolerance: f64,
    /// The longest step, as `dt` times `2^max_level`.
    pub max_level: u32,
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        AdaptiveOptions {
            tolerance: DEFAULT_TOLERANCE,
            max_level: 10,
        }
    }
}

/// The default local error per step, m: a tenth of the 0.1 mm a lab camera's markers are noisy
/// by. On a 4 mm continuum cuboid creeping for 30 s under 9.73 N (g 0.5, tau 3 s, dt 2 ms) the
/// markers' RMS distance from the fixed-step replay is 8 um at 1e-5 (2.3 s against 30.5 s), 3.4
/// at 3e-6 (4.3 s), 1.1 at 1e-6 (6.9 s), and 0.8 at 1e-7: there the fixed step's own error
/// shows (`docs/results/benchmarks.md`).
pub const DEFAULT_TOLERANCE: f64 = 1e-5;

/// What a controlled run did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AdaptiveReport {
    /// Steps kept (each of them two half steps, or one at `dt`).
    pub steps: usize,
    /// Steps computed in all, rejected and estimating ones included.
    pub solves: usize,
    /// Steps rejected by the error estimate and taken again shorter.
    pub rejected: usize,
}

/// A run's step control: the models at each step length and the level reached.
#[derive(Debug)]
pub struct Adaptive {
    options: AdaptiveOptions,
    base: Arc<Model>,
    /// Models at step lengths other than `dt`, by the length's bits.
    models: Vec<(u64, Arc<Model>)>,
    /// The next step's level: `dt 2^level`.
    level: u32,
    /// What the run did so far.
    pub report: AdaptiveReport,
}

impl Adaptive {
    /// Control for `sim`'s model (its `dt` the shortest step).
    pub fn new(sim: &Simulation, options: AdaptiveOptions) -> Adaptive {
        Adaptive {
            options,
            base: Arc::clone(&sim.model),
            models: Vec::new(),
            level: 0,
            report: AdaptiveReport::default(),
        }
    }

    /// Back to the shortest step: after a change of load, whose transient the control would
    /// otherwise meet with a long step first.
    pub fn restart(&mut self) {
        self.level = 0;
    }

    fn model(&mut self, h: f64) -> Arc<Model> {
        if h == self.base.dt {
            return Arc::clone(&self.base);
        }
        let key = h.to_bits();
        if let Some((_, m)) = self.models.iter().find(|(k, _)| *k == key) {
            return Arc::clone(m);
        }
        let mut m = (*self.base).clone();
        m.dt = h;
        let m = Arc::new(m);
        // A few lengths are in use at a time: the level's, its half, a last step cut short.
        if self.models.len() >= 8 {
            self.models.remove(0);
        }
        self.models.push((key, Arc::clone(&m)));
        m
    }
}

impl Simulation {
    /// Steps until `time` (s) with error-controlled steps ([`Adaptive`]); the model is the base
    /// one again at the end.
    pub fn run_until_adaptive(&mut self, time: f64, a: &mut Adaptive) -> Result<(), SimError> {
        let result = self.run_adaptive(time, a);
        self.model = Arc::clone(&a.base);
        result
    }

    fn run_adaptive(&mut self, time: f64, a: &mut Adaptive) -> Result<(), SimError> {
        let cancel = crate::cancel::current();
        let dt = a.base.dt;
        while self.state.time + 0.5 * dt < time {
            crate::cancel::check(cancel.as_ref())?;
            let remaining = time - self.state.time;
            let h = (dt * f64::from(1u32 << a.level)).min(remaining);
            if a.level == 0 || h <= dt * (1.0 + 1e-9) {
                self.model = a.model(h);
                self.step()?;
                a.report.steps += 1;
                a.report.solves += 1;
                if a.level == 0 && a.options.max_level > 0 {
                    // The next step estimates its error at twice dt.
                    a.level = 1;
                }
                continue;
            }
            let start = self.state.clone();
            self.model = a.model(h);
            let whole = self.step().map(|()| points(&self.state));
            let big = match whole {
                Ok(p) => p,
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(_) => {
                    // Too long to take at all: shorter.
                    self.state = start;
                    a.level -= 1;
                    a.report.rejected += 1;
                    a.report.solves += 1;
                    continue;
                }
            };
            self.state = start.clone();
            self.model = a.model(0.5 * h);
            let halves = self.step().and_then(|()| self.step());
            a.report.solves += 3;
            let error = match halves {
                Ok(()) => largest_distance(&big, &points(&self.state)),
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(e) if a.level == 1 => {
                    // The half steps are dt: the fixed-step run would have failed too.
                    return Err(e);
                }
                Err(_) => f64::INFINITY,
            };
            if error <= a.options.tolerance {
                a.report.steps += 1;
                if error <= a.options.tolerance / 8.0 && a.level < a.options.max_level {
                    a.level += 1;
                }
            } else {
                self.state = start;
                a.level -= 1;
                a.report.rejected += 1;
            }
        }
        Ok(())
    }
}

fn points(state: &crate::state::State) -> Vec<DVec3> {
    let fingers = state.fingers.iter().map(|f| f.position);
    state.positions.iter().copied().chain(fingers).collect()
}

fn largest_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}
