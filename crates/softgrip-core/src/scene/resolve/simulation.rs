//! `[simulation]`: the time step, the duration, gravity and the linear solver's limits.

use super::resolver::{At, Resolver};
use crate::scene::defaults::DEFAULT_CG_TOLERANCE;
use crate::scene::error::SceneError;
use crate::scene::raw::RawSimulation;
use crate::scene::{Settle, Simulation};

impl Resolver<'_> {
    pub(super) fn simulation(&mut self, s: RawSimulation) -> Result<Simulation, SceneError> {
        let at = |key| At {
            table: "simulation",
            index: None,
            key,
        };
        let dt = self.number(
            at("dt"),
            s.dt,
            1e-3,
            |x| x > 0.0 && x <= 0.1,
            "must be > 0 and <= 0.1 s (the thesis uses 1e-3 s)",
        )?;
        let duration = self.number(
            at("duration"),
            s.duration,
            2.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let gravity = self.vec3(at("gravity"), s.gravity, [0.0, 0.0, -9.81])?;
        if gravity.length() > MAX_GRAVITY {
            return Err(self.err(
                at("gravity"),
                format!("{:?}", gravity.to_array()),
                "must be at most 1e4 m/s^2 (1000 g) in size; on Earth, gravity = [0.0, 0.0, -9.81]",
            ));
        }
        let cg_tolerance = self.number(
            at("cg_tolerance"),
            s.cg_tolerance,
            DEFAULT_CG_TOLERANCE,
            |x| x > 0.0 && x < 1.0,
            "must be in (0, 1); a relative residual, e.g. 1e-5",
        )?;
        let cg_max = self.default(at("cg_max_iterations"), s.cg_max_iterations, 2000);
        if !(1..=1_000_000).contains(&cg_max) {
            return Err(self.err(at("cg_max_iterations"), cg_max, "must be in 1..=1000000"));
        }
        let settle_at = at("settle");
        let settle = match self
            .default(settle_at, s.settle, "static".to_string())
            .as_str()
        {
            "static" => Settle::Static,
            "dynamic" => Settle::Dynamic,
            other => {
                return Err(self.err(
                    settle_at,
                    format!("{other:?}"),
                    "must be \"static\" (Newton's method) or \"dynamic\" (time steps until at rest)",
                ));
            }
        };

        Ok(Simulation {
            dt,
            duration,
            gravity,
            cg_tolerance,
            cg_max_iterations: cg_max as usize,
            settle,
        })
    }
}

/// The largest gravity a scene may have (m/s^2): a thousand g, past any lab's (a centrifuge's
/// included); a larger one is a typo, and only diverges.
const MAX_GRAVITY: f64 = 1e4;
