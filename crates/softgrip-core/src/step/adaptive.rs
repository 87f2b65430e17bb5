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
//! `dt` itself no estimate is made (the fixed-step replay). A step of `2 dt` pays only as the way
//! to longer ones: its two half steps are `dt`'s, for three solves where the fixed step takes
//! two. So from `dt`, twice it is tried after one step, and each time it is rejected, or kept
//! without room to go longer, the control goes back to `dt` for twice as many steps as before
//! (at most [`MAX_HOLD`]), until a step goes longer. Without that hold, a beam released under
//! its weight (whose steps of `2 dt` are kept now and then, never with room to spare) replayed
//! 4.5 times slower than at fixed steps. Everything a step does (contacts,
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

/// The most steps at `dt` taken before the next try at twice it, after tries that failed in a row.
pub const MAX_HOLD: u32 = 64;

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
    /// Steps at `dt` still to take before the next try at twice it.
    hold: u32,
    /// `hold` after the next try at twice `dt` that fails (rejected, or kept with no room to go
    /// longer): doubled by each one in a row, 1 again once a step goes longer.
    backoff: u32,
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
            hold: 0,
            backoff: 1,
            report: AdaptiveReport::default(),
        }
    }

    /// Back to the shortest step: after a change of load, whose transient the control would
    /// otherwise meet with a long step first.
    pub fn restart(&mut self) {
        self.level = 0;
        self.hold = 0;
        self.backoff = 1;
    }

    /// A step of the current level rejected: one level shorter, held back at `dt`.
    fn reject(&mut self) {
        self.level -= 1;
        self.report.rejected += 1;
        if self.level == 0 {
            self.hold_back();
        }
    }

    /// Down at `dt`: held there for `backoff` steps, and the next hold twice as long.
    fn hold_back(&mut self) {
        self.hold = self.backoff;
        self.backoff = (2 * self.backoff).min(MAX_HOLD);
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
            // A step cut short by rounding alone (the samples on the dt grid, the time a sum of
            // steps) is a whole one: another length is another model.
            let h = (dt * f64::from(1u32 << a.level)).min(remaining);
            let h = if h > dt * (1.0 - 1e-6) && h < dt {
                dt
            } else {
                h
            };
            if a.level == 0 || h <= dt * (1.0 + 1e-9) {
                self.model = a.model(h);
                self.step()?;
                a.report.steps += 1;
                a.report.solves += 1;
                a.hold = a.hold.saturating_sub(1);
                if a.level == 0 && a.hold == 0 && a.options.max_level > 0 {
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
                    self.rewind(start);
                    a.reject();
                    a.report.solves += 1;
                    continue;
                }
            };
            self.rewind(start.clone());
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
                    a.backoff = 1;
                } else if a.level == 1 {
                    // Kept, but no way up: the half steps are dt's, for three solves where the
                    // fixed step takes two.
                    a.level = 0;
                    a.hold_back();
                } else {
                    a.backoff = 1;
                }
            } else {
                self.rewind(start);
                a.reject();
            }
        }
        Ok(())
    }

    /// Back to `start` for another try, keeping what the last solve took: the linear solver's
    /// choice of preconditioner reads it at the next step, and a count from before the try
    /// (block Jacobi's, say) judged the nodal pressure's factorization by it and turned it off
    /// for good (a beam's replay then ran on block Jacobi, 1.9 times slower).
    fn rewind(&mut self, start: crate::state::State) {
        let iterations = self.state.stats.cg_iterations;
        self.state = start;
        self.state.stats.cg_iterations = iterations;
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
