//! Quasi-static mode: apply a load, then step until the object and the
//! fingers are at rest. The next load starts from the state reached (a warm
//! start), as the thesis's lab added weights one after another.
//!
//! "At rest" means: for `consecutive_steps` steps in a row, no particle and no
//! finger moves faster than `speed` (m/s). At rest, a mass-less finger's
//! remaining force imbalance is `guide_damping * speed` (for the thesis load,
//! 9.73 N / 0.05 m/s * 1e-5 m/s = 2 mN, 0.02 %).

use glam::DVec3;

use crate::error::SimError;
use crate::step::Simulation;

/// When a dynamically settled load counts as at rest, and how long it may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestTolerance {
    /// The top particle speed below which a step counts as at rest, m/s.
    pub speed: f64,
    /// Steps in a row at rest that end the settle.
    pub consecutive_steps: u32,
    /// Simulated seconds allowed per load before giving up.
    pub max_seconds: f64,
    /// Simulated seconds after which a load that is not calming down is
    /// given up on before `max_seconds` (None: never; fits use it, see
    /// [`RestTolerance::for_fits`]). Not calming down: in the last whole
    /// simulated second the top speed was above [`HOPELESS_SPEED_RATIO`]
    /// times `speed` and above [`HOPELESS_DECAY`] times the top speed of
    /// the second before (seconds in which a velocity-driven finger still
    /// moves along its travel do not count).
    pub give_up_after: Option<f64>,
}

/// See [`RestTolerance::give_up_after`].
pub const HOPELESS_SPEED_RATIO: f64 = 100.0;
/// See [`RestTolerance::give_up_after`]. From 100 times the rest speed, a
/// decay this slow (e^-0.22 a second) takes more than 20 s to reach it,
/// more than the whole budget.
pub const HOPELESS_DECAY: f64 = 0.8;

impl Default for RestTolerance {
    fn default() -> Self {
        RestTolerance {
            speed: 1e-5,
            consecutive_steps: 20,
            max_seconds: 20.0,
            give_up_after: None,
        }
    }
}

impl RestTolerance {
    /// For the replays of a fit, whose probes may land where the model
    /// does not settle: the default, but a load that is not calming down
    /// after 5 simulated seconds is given up on (the probe's cost is then
    /// infinite, as after 20 s). In a diagnosis of the suite's
    /// heterogeneous-stiffness-strong recording (timed with a throwaway
    /// trace, docs/results/benchmarks-history.md) the slowest of the loads that came to rest
    /// took 2.7 s; the 5 that did not were
    /// still moving at 2e-2 to 7e-2 m/s after 20 s (an oscillation that
    /// does not decay) and cost 10,000 steps each, 40 % of that
    /// diagnosis's time. A load that calms down fast enough to come to
    /// rest within the 20 s is not given up on (see [`HOPELESS_DECAY`]),
    /// and a load that comes to rest does so exactly as without the rule
    /// (`tests/rest.rs`).
    pub fn for_fits() -> Self {
        RestTolerance {
            give_up_after: Some(5.0),
            ..RestTolerance::default()
        }
    }
}

/// How a load came to rest by time steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestReport {
    /// Steps taken.
    pub steps: u64,
    /// Simulated time taken, s.
    pub seconds: f64,
    /// The top particle speed at the end, m/s.
    pub max_speed: f64,
}

impl Simulation {
    /// Sets the applied force of finger `k` to `magnitude` N along its scene
    /// `force` direction (the recording's `load`).
    pub fn set_load(&mut self, k: usize, magnitude: f64) {
        let dir = self.model.fingers[k].load_direction;
        self.state.fingers[k].applied_force = dir * magnitude;
    }

    /// The first force-controlled finger, whose force the recordings' `load` sets.
    pub fn load_finger(&self) -> Option<usize> {
        self.model
            .fingers
            .iter()
            .position(|f| f.is_force_controlled())
    }

    /// Whether a velocity-driven finger still moves along its travel (input, not unrest;
    /// a static solve cannot hold it).
    pub fn has_moving_input(&self) -> bool {
        self.model
            .fingers
            .iter()
            .zip(&self.state.fingers)
            .any(|(f, s)| {
                f.drive
                    .iter()
                    .any(|d| matches!(d, crate::model::AxisDrive::Velocity(v) if *v != 0.0))
                    && f.travel.is_none_or(|t| s.travelled < t)
            })
    }

    /// Steps until at rest (see [`RestTolerance`]); `progress` gets the step count.
    pub fn settle(
        &mut self,
        tol: RestTolerance,
        mut progress: impl FnMut(u64),
    ) -> Result<RestReport, SimError> {
        let start_time = self.state.time;
        let start_step = self.state.step;
        let mut calm = 0;
        // Top speeds of the second before the last whole one, of the last
        // whole one, and of the current one.
        let (mut before, mut last, mut current) = (f64::INFINITY, f64::INFINITY, 0.0f64);
        let mut second = 0u64;
        let cancel = crate::cancel::current();
        loop {
            crate::cancel::check(cancel.as_ref())?;
            self.step()?;
            let finger_speed = self
                .state
                .fingers
                .iter()
                .map(|f| f.velocity.length())
                .fold(0.0, f64::max);
            let speed = self.state.stats.max_speed.max(finger_speed);
            // Velocity-driven fingers that still move are not "at rest" input.
            let moving_input = self.has_moving_input();
            calm = if speed < tol.speed && !moving_input {
                calm + 1
            } else {
                0
            };
            progress(self.state.step - start_step);
            if calm >= tol.consecutive_steps {
                return Ok(RestReport {
                    steps: self.state.step - start_step,
                    seconds: self.state.time - start_time,
                    max_speed: speed,
                });
            }
            let elapsed = self.state.time - start_time;
            current = current.max(speed);
            if elapsed >= (second + 1) as f64 {
                (before, last, current) = (last, current, 0.0);
                second += 1;
            }
            if moving_input {
                // A finger driven along its travel is input, not unrest:
                // count from when it stops.
                (before, last) = (f64::INFINITY, f64::INFINITY);
            }
            let hopeless = tol.give_up_after.is_some_and(|t| {
                elapsed > t
                    && last > HOPELESS_SPEED_RATIO * tol.speed
                    && last > HOPELESS_DECAY * before
            });
            if elapsed > tol.max_seconds || hopeless {
                // The time the last seconds' decay needs to reach the rest speed, where it
                // decays: advice with a budget that works, else none.
                let rate = (before / last).ln();
                let needed = (last / tol.speed).ln() / rate;
                let advice = if !(before.is_finite() && last.is_finite()) {
                    // Under two whole seconds watched: no decay to read yet.
                    format!(
                        "it was watched for {elapsed:.2} s only: allow each load more simulated time (`softgrip ramp` and `compare`: --max-seconds {}), or raise [model] damping_ratio",
                        (4.0 * elapsed).max(2.0).ceil()
                    )
                } else if rate.is_finite() && rate > 0.01 && needed.is_finite() {
                    let s = (elapsed + 1.5 * needed.max(1.0)).ceil();
                    format!(
                        "the motion decays, by {:.0} % a second: allow each load more simulated time (`softgrip ramp` and `compare`: --max-seconds {s}), or raise [model] damping_ratio",
                        100.0 * (1.0 - (-rate).exp())
                    )
                } else {
                    "the motion is not dying out (no decay over the last second): more time will not help; raise [model] damping_ratio, or check that the object is held (supports, table friction) and the load is one it can carry".to_string()
                };
                return Err(SimError::NoRest {
                    seconds: if hopeless { elapsed } else { tol.max_seconds },
                    advice,
                    steps: self.state.step - start_step,
                    max_speed: speed,
                    tolerance: tol.speed,
                });
            }
        }
    }

    /// The direction finger `k` presses in: its force, else its velocity,
    /// else its weight; -z when it has none of them.
    pub fn press_direction(&self, k: usize) -> DVec3 {
        let f = &self.model.fingers[k];
        let velocity = DVec3::from_array(f.drive.map(|d| match d {
            crate::model::AxisDrive::Velocity(v) => v,
            _ => 0.0,
        }));
        [self.state.fingers[k].applied_force, velocity, f.weight]
            .into_iter()
            .map(|v| v.normalize_or_zero())
            .find(|v| *v != DVec3::ZERO)
            .unwrap_or(DVec3::NEG_Z)
    }

    /// How far finger `k`'s leading point is past the undeformed object's
    /// surface along its press direction (m), the surface under the finger (the object's nodes
    /// within its reach of its line of action); 0 when it is not, or when the object is not in
    /// its path (a finger beside the block is not "25 mm deep").
    pub fn indentation(&self, k: usize) -> f64 {
        let d = self.press_direction(k);
        let at = self.state.fingers[k].position;
        let reach = self.model.fingers[k].shape.lateral_reach();
        let surface = self
            .model
            .rest_positions
            .iter()
            .filter(|p| (**p - at).reject_from_normalized(d).length() <= reach)
            .map(|p| p.dot(d))
            .fold(f64::INFINITY, f64::min);
        if !surface.is_finite() {
            return 0.0;
        }
        let reach = self.model.fingers[k].shape.reach_along(d);
        ((self.state.fingers[k].position.dot(d) + reach) - surface).max(0.0)
    }

    /// Sum of the forces the pinned particles need to stay put, and the
    /// table's force of the last step: the support reaction (N). At rest it
    /// balances gravity, loads and finger forces.
    pub fn support_reaction(&self) -> DVec3 {
        self.reaction(|_| true) + crate::contact::table::total_force(&self.state)
    }

    /// Sum of the forces the pinned particles `pick` selects (by index) need to stay put (N):
    /// what a bonded plate holding them carries.
    pub fn reaction(&self, pick: impl Fn(usize) -> bool) -> DVec3 {
        // The step's own stages (`step::assemble`) at the present state, on a copy.
        let force = self.assembled_force();
        let (model, n) = (&self.model, self.model.particle_count());
        -(0..n)
            .filter(|&i| model.fixed[i] && pick(i))
            .map(|i| force[i])
            .sum::<DVec3>()
    }
}
