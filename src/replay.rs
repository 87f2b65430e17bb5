//! Simulating a recording: the scene run as the recording says, sampled
//! where the recording has samples, and compared with it.
//!
//! - Quasi-static: each sample's load on the first force-controlled finger
//!   (along its scene `force` direction), then steps until at rest; the
//!   next load starts from there (warm start), so loading then unloading
//!   follows the path.
//! - Time-series: from rest (the undeformed scene at t = 0) or from
//!   equilibrium (settled under the first sample's load with
//!   velocity-driven finger axes held still, then t = 0). A sample's load
//!   holds from its time until the next sample's; positions are taken at
//!   each sample's time, before its own load change acts.

use std::sync::Arc;

use crate::compare::{Attachment, Errors, Residual, attach, errors, marker_position};
use crate::error::SimError;
use crate::model::AxisDrive;
use crate::quasi_static::RestTolerance;
use crate::recording::{Mode, Recording, Start};
use crate::scene::Scene;
use crate::step::Simulation;

/// What simulating a recording gives.
#[derive(Debug, Clone)]
pub struct Replay {
    pub attachments: Vec<Attachment>,
    pub residuals: Vec<Residual>,
    pub errors: Errors,
    /// Volume error |V - V0| / V0 at each sample (thesis eq. 47-48).
    pub volume_errors: Vec<f64>,
}

/// Options of a replay.
#[derive(Debug, Clone, Copy, Default)]
pub struct ReplayOptions {
    pub rest: RestTolerance,
    /// Threads for the simulation (see `Simulation::set_threads`; 0 =
    /// as many as the machine has, up to 2). Sweeps run one per core.
    pub threads: usize,
}

/// Simulates `recording` on `scene` (its own scene, or one with other
/// parameters for fitting); `progress` gets the number of samples done.
pub fn replay(
    recording: &Recording,
    scene: &Scene,
    options: ReplayOptions,
    mut progress: impl FnMut(usize),
) -> Result<Replay, SimError> {
    let mut sim = Simulation::new(scene)?;
    sim.set_threads(options.threads);
    let references: Vec<_> = recording.markers.iter().map(|m| m.reference).collect();
    let attachments = attach(&sim.model, &references);
    let loaded = sim.load_finger();
    let set_load = |sim: &mut Simulation, load: f64| {
        if let Some(k) = loaded {
            sim.set_load(k, load);
        }
    };
    let mut residuals = Vec::new();
    let mut volume_errors = Vec::with_capacity(recording.samples.len());
    let record = |sim: &Simulation, i: usize, residuals: &mut Vec<Residual>| {
        for o in &recording.samples[i].observations {
            if let Some(p) = marker_position(&sim.model, &sim.state, &attachments, o.marker) {
                residuals.push(Residual {
                    sample: i,
                    marker: o.marker,
                    simulated: p,
                    recorded: o.position,
                });
            }
        }
    };
    match recording.mode {
        Mode::QuasiStatic => {
            for (i, sample) in recording.samples.iter().enumerate() {
                set_load(&mut sim, sample.load);
                sim.settle(options.rest, |_| {})?;
                record(&sim, i, &mut residuals);
                volume_errors.push(sim.state.stats.volume_error);
                progress(i + 1);
            }
        }
        Mode::TimeSeries => {
            let first = recording.samples.first().map_or(0.0, |s| s.load);
            set_load(&mut sim, first);
            if recording.start == Start::Equilibrium {
                settle_still(&mut sim, options.rest)?;
                sim.state.time = 0.0;
                sim.state.step = 0;
            }
            for (i, sample) in recording.samples.iter().enumerate() {
                let t = sample.time.unwrap_or(0.0);
                sim.run_until(t)?;
                record(&sim, i, &mut residuals);
                volume_errors.push(sim.state.stats.volume_error);
                set_load(&mut sim, sample.load);
                progress(i + 1);
            }
        }
    }
    let errors = errors(&residuals, sim.model.extent);
    Ok(Replay {
        attachments,
        residuals,
        errors,
        volume_errors,
    })
}

/// Settles with every velocity-driven finger axis held still.
fn settle_still(sim: &mut Simulation, rest: RestTolerance) -> Result<(), SimError> {
    let moving = Arc::clone(&sim.model);
    let mut still = (*moving).clone();
    for f in &mut still.fingers {
        for d in &mut f.drive {
            if let AxisDrive::Velocity(_) = d {
                *d = AxisDrive::Velocity(0.0);
            }
        }
    }
    sim.model = Arc::new(still);
    let settled = sim.settle(rest, |_| {});
    sim.model = moving;
    for f in &mut sim.state.fingers {
        f.travelled = 0.0;
    }
    settled.map(|_| ())
}
