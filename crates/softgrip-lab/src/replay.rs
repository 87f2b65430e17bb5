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

use glam::DVec3;

use crate::compare::{Attachment, Errors, Residual, attach, errors, marker_position};
use crate::recording::{MarkerRef, Mode, Recording, Start};
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::error::SimError;
use softgrip_core::mesh::TetMesh;
use softgrip_core::model::AxisDrive;
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::Scene;
use softgrip_core::step::Simulation;
use softgrip_core::step::adaptive::{Adaptive, AdaptiveOptions};

/// A marker's reference farther than this fraction of the object's
/// largest extent from its surface is an error: the recording and the
/// scene do not describe the same object (units, frame or size). Marker
/// centres a few millimetres off a 100 mm beam still attach.
pub const OFF_SURFACE: f64 = 0.1;

/// What simulating a recording gives.
#[derive(Debug, Clone)]
pub struct Replay {
    /// Where each recorded marker attaches to the object's surface.
    pub attachments: Vec<Attachment>,
    /// Simulated against recorded marker positions, sample by sample.
    pub residuals: Vec<Residual>,
    /// The errors over the residuals.
    pub errors: Errors,
    /// Volume error |V - V0| / V0 at each sample (thesis eq. 47-48).
    pub volume_errors: Vec<f64>,
    /// The largest spring stretch and compression (strain, positive) at
    /// any sample: a limit tau_s or tau_c above them never acted.
    pub largest_strain: [f64; 2],
    /// With [`ReplayOptions::keep_states`]: the particle and finger
    /// positions at each sample (for showing a sample in the viewer).
    pub states: Vec<SampleState>,
}

/// The object and the fingers where a sample was taken.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleState {
    /// Particle positions, m.
    pub positions: Vec<DVec3>,
    /// Finger centres, m.
    pub fingers: Vec<DVec3>,
}

/// How a quasi-static load (and a time series' starting equilibrium) is reached. With
/// `Static`, where the solver finds no answer other than a load the model cannot carry, the
/// dynamics go on from the last equilibrium.
pub use softgrip_core::scene::Settle;

/// Options of a replay.
#[derive(Debug, Clone, Copy)]
pub struct ReplayOptions {
    /// `None`: as the scene's `[simulation] settle` says.
    pub settle: Option<Settle>,
    /// For [`Settle::Dynamic`], and for a static solve that a moving finger hands to it.
    pub rest: RestTolerance,
    /// The static solver's settings, for [`Settle::Static`].
    pub statics: StaticOptions,
    /// Threads for the simulation (see `Simulation::set_threads`; 0 =
    /// up to 2, as the machine has cores free: see
    /// `Simulation::set_threads`).
    pub threads: usize,
    /// Keep each sample's positions in [`Replay::states`].
    pub keep_states: bool,
    /// Keep them only where a later replay of a nearby point may start from them (a
    /// path-independent model: [`replay_observing`]'s `warm`); elsewhere they would be dead
    /// weight (a fit of the 23k-tetrahedron cylinder keeps ~80 replays).
    pub warm_seeds: bool,
    /// A time series stepped with error-controlled steps (`softgrip_core::step::adaptive`)
    /// instead of the scene's `dt` throughout: `None` for fixed steps.
    pub adaptive: Option<AdaptiveOptions>,
}

impl Default for ReplayOptions {
    /// As the scene says, time series with error-controlled steps.
    fn default() -> Self {
        ReplayOptions {
            settle: None,
            rest: RestTolerance::default(),
            statics: StaticOptions::default(),
            threads: 0,
            keep_states: false,
            warm_seeds: false,
            adaptive: Some(AdaptiveOptions::default()),
        }
    }
}

/// Simulates `recording` on `scene` (its own scene, or one with other
/// parameters for fitting); `progress` gets the number of samples done.
pub fn replay(
    recording: &Recording,
    scene: &Scene,
    options: ReplayOptions,
    progress: impl FnMut(usize),
) -> Result<Replay, SimError> {
    replay_observing(recording, scene, options, None, None, progress).map(|(r, _)| r)
}

/// The derivative of each residual's simulated position (in [`Replay::residuals`]' order) by
/// each parameter: `[residual][parameter]`, m per unit of the parameter.
pub type MarkerSensitivities = Vec<Vec<DVec3>>;

/// At an equilibrium (the simulation, and the mesh it was built on): `dx/dp` of the particles
/// then the fingers, one vector per parameter, or `None` where it cannot be had.
pub type AtEquilibrium<'a> = dyn FnMut(&Simulation, &TetMesh) -> Option<Vec<Vec<DVec3>>> + 'a;

/// [`replay`], and for a quasi-static recording the markers' sensitivities from
/// `at_equilibrium` at each load's equilibrium (`crate::sensitivity::replay_with_sensitivities`
/// gives it). `None` where one load's cannot be had (a time series, a load that came to rest
/// dynamically, a solve that failed): the caller falls back to finite differences.
///
/// `warm`: each sample's state at another parameter point of the same scene (a fit's evaluated
/// point, [`ReplayOptions::keep_states`]): a quasi-static load starts Newton from there where
/// the model's equilibria do not depend on the path (`Model::path_independent`), and takes the
/// usual path where that fails.
pub fn replay_observing(
    recording: &Recording,
    scene: &Scene,
    options: ReplayOptions,
    warm: Option<&[SampleState]>,
    at_equilibrium: Option<&mut AtEquilibrium>,
    mut progress: impl FnMut(usize),
) -> Result<(Replay, Option<MarkerSensitivities>), SimError> {
    let mesh = softgrip_core::model::Model::mesh_of(scene)?;
    let mut sim = Simulation::on_mesh(scene, mesh.clone())?;
    sim.set_threads(options.threads);
    let options = ReplayOptions {
        settle: Some(options.settle.unwrap_or(scene.simulation.settle)),
        ..options
    };
    let references: Vec<_> = recording.markers.iter().map(|m| m.reference).collect();
    let attachments = attach(&sim.model, &references);
    check_markers(recording, &sim, &attachments)?;
    let loaded = sim.load_finger();
    check_loads(recording, scene, &sim, loaded)?;
    let keep_states = options.keep_states || (options.warm_seeds && sim.model.path_independent());
    let mut run = Replaying {
        recording,
        sim,
        options,
        loaded,
        attachments,
        residuals: Vec::new(),
        volume_errors: Vec::with_capacity(recording.samples.len()),
        largest_strain: [0.0f64; 2],
        states: Vec::new(),
        keep_states,
    };
    let sensitivities = match recording.mode {
        Mode::QuasiStatic => run.quasi_static(&mesh, warm, at_equilibrium, &mut progress)?,
        Mode::TimeSeries => {
            run.time_series(&mut progress)?;
            None
        }
    };
    Ok((run.finish(), sensitivities))
}

/// Every marker's reference lies on the scene's object: within [`OFF_SURFACE`] of its extent.
fn check_markers(
    recording: &Recording,
    sim: &Simulation,
    attachments: &[Attachment],
) -> Result<(), SimError> {
    let limit = OFF_SURFACE * sim.model.extent;
    if let Some((m, a)) = recording
        .markers
        .iter()
        .zip(attachments)
        .find(|(_, a)| a.distance > limit)
    {
        return Err(SimError::MarkerOffSurface {
            file: recording.source.display().to_string(),
            marker: m.name.clone(),
            reference: m.reference.to_array(),
            distance_mm: 1e3 * a.distance,
            limit_mm: 1e3 * limit,
        });
    }
    Ok(())
}

/// A recording with loads has a force-controlled finger with a direction (`loaded`), and no
/// negative load.
fn check_loads(
    recording: &Recording,
    scene: &Scene,
    sim: &Simulation,
    loaded: Option<usize>,
) -> Result<(), SimError> {
    let load = recording
        .samples
        .iter()
        .map(|s| s.load.abs())
        .fold(0.0, f64::max);
    if load > 0.0 {
        let why = match loaded {
            None => Some("the scene has no force-controlled finger".to_string()),
            Some(k) if sim.model.fingers[k].load_direction == DVec3::ZERO => Some(format!(
                "finger #{} has force = [0, 0, 0], which gives no direction",
                k + 1
            )),
            Some(_) => None,
        };
        if let Some(why) = why {
            return Err(SimError::NoLoadDirection {
                file: scene
                    .source
                    .as_ref()
                    .map_or("the scene".into(), |p| p.display().to_string()),
                load,
                why,
            });
        }
    }
    if let (Some(k), Some((i, s))) = (
        loaded,
        recording
            .samples
            .iter()
            .enumerate()
            .find(|(_, s)| s.load < 0.0),
    ) {
        return Err(SimError::NegativeLoad {
            file: recording.samples_path.display().to_string(),
            sample: i + 1,
            load: s.load,
            finger: k + 1,
            direction: sim.model.fingers[k].load_direction.to_array(),
        });
    }
    Ok(())
}

/// A replay under way: the simulation and what it has gathered, sample by sample.
struct Replaying<'a> {
    /// The recording replayed.
    recording: &'a Recording,
    /// The scene's simulation.
    sim: Simulation,
    /// The replay's options, `settle` resolved.
    options: ReplayOptions,
    /// The force-controlled finger the samples' loads go to, if any.
    loaded: Option<usize>,
    /// Where each recorded marker sits on the object.
    attachments: Vec<Attachment>,
    /// Simulated against recorded marker positions, sample by sample.
    residuals: Vec<Residual>,
    /// Volume error |V - V0| / V0 at each sample.
    volume_errors: Vec<f64>,
    /// The largest spring stretch and compression so far (strain, positive).
    largest_strain: [f64; 2],
    /// Each sample's particle and finger positions, where kept.
    states: Vec<SampleState>,
    /// Keep each sample's positions in `states`.
    keep_states: bool,
}

impl Replaying<'_> {
    /// Sets the loaded finger's load, N (nothing without one).
    fn set_load(&mut self, load: f64) {
        if let Some(k) = self.loaded {
            self.sim.set_load(k, load);
        }
    }

    /// The force applied to each finger now, N.
    fn applied_forces(&self) -> Vec<DVec3> {
        self.sim
            .state
            .fingers
            .iter()
            .map(|f| f.applied_force)
            .collect()
    }

    /// Sample `i`'s residuals: each observed marker's simulated and recorded position.
    fn record(&mut self, i: usize) {
        let sim = &self.sim;
        for o in &self.recording.samples[i].observations {
            if let Some(p) = marker_position(&sim.model, &sim.state, &self.attachments, o.marker) {
                self.residuals.push(Residual {
                    sample: i,
                    marker: o.marker,
                    simulated: p,
                    recorded: o.position,
                });
            }
        }
    }

    /// The springs' strains into the largest so far, and the state kept where asked.
    fn strains(&mut self) {
        let sim = &self.sim;
        for e in softgrip_core::fields::spring_strain(&sim.model, &sim.state) {
            self.largest_strain[0] = self.largest_strain[0].max(e);
            self.largest_strain[1] = self.largest_strain[1].max(-e);
        }
        if self.keep_states {
            self.states.push(SampleState {
                positions: sim.state.positions.clone(),
                fingers: sim.state.fingers.iter().map(|f| f.position).collect(),
            });
        }
    }

    /// Each sample's load brought to rest in turn, and the markers' sensitivities where
    /// `at_equilibrium` gives them at every load.
    fn quasi_static(
        &mut self,
        mesh: &TetMesh,
        warm: Option<&[SampleState]>,
        mut at_equilibrium: Option<&mut AtEquilibrium>,
        progress: &mut impl FnMut(usize),
    ) -> Result<Option<MarkerSensitivities>, SimError> {
        let recording = self.recording;
        let options = self.options;
        let mut sensitivities: Option<MarkerSensitivities> =
            at_equilibrium.is_some().then(Vec::new);
        for (i, sample) in recording.samples.iter().enumerate() {
            let from = self.applied_forces();
            self.set_load(sample.load);
            let sim = &mut self.sim;
            let guess = warm.and_then(|w| w.get(i));
            let near = match (guess, options.settle) {
                (Some(g), Some(Settle::Static)) if !sim.has_moving_input() => sim
                    .equilibrium_near(&g.positions, &g.fingers, options.statics)?
                    .is_some(),
                _ => false,
            };
            if !near {
                // Where the load is the recording's: which sample asked for it.
                settle(sim, &from, options).map_err(|e| asked_by(e, recording, i, sample.load))?;
            }
            self.record(i);
            if let (Some(columns), Some(f)) = (sensitivities.as_mut(), at_equilibrium.as_mut()) {
                match f(&self.sim, mesh) {
                    Some(d) => columns.extend(marker_sensitivities(
                        &self.sim,
                        &self.attachments,
                        &recording.samples[i].observations,
                        &d,
                    )),
                    None => sensitivities = None,
                }
            }
            self.volume_errors.push(self.sim.state.stats.volume_error);
            self.strains();
            progress(i + 1);
        }
        Ok(sensitivities)
    }

    /// The time series: from rest or equilibrium, stepped to each sample's time, where its
    /// load then takes over.
    fn time_series(&mut self, progress: &mut impl FnMut(usize)) -> Result<(), SimError> {
        let recording = self.recording;
        let options = self.options;
        let first = recording.samples.first().map_or(0.0, |s| s.load);
        self.set_load(first);
        if recording.start == Start::Equilibrium {
            settle_still(&mut self.sim, options)?;
            self.sim.state.time = 0.0;
            self.sim.state.step = 0;
        }
        let mut control = options.adaptive.map(|a| Adaptive::new(&self.sim, a));
        for (i, sample) in recording.samples.iter().enumerate() {
            let t = sample.time.unwrap_or(0.0);
            match control.as_mut() {
                Some(c) => self.sim.run_until_adaptive(t, c)?,
                None => self.sim.run_until(t)?,
            }
            self.record(i);
            self.volume_errors.push(self.sim.state.stats.volume_error);
            self.strains();
            let before = self.applied_forces();
            self.set_load(sample.load);
            let changed = self
                .sim
                .state
                .fingers
                .iter()
                .zip(&before)
                .any(|(f, b)| f.applied_force != *b);
            if let (true, Some(c)) = (changed, control.as_mut()) {
                c.restart();
            }
            progress(i + 1);
        }
        Ok(())
    }

    /// The replay: what was gathered, with its errors.
    fn finish(self) -> Replay {
        let errors = errors(&self.residuals, self.sim.model.extent);
        Replay {
            attachments: self.attachments,
            residuals: self.residuals,
            errors,
            volume_errors: self.volume_errors,
            largest_strain: self.largest_strain,
            states: self.states,
        }
    }
}

/// A quasi-static load's `NoEquilibrium` with the sample that asked for the load (`i`, from 0)
/// named in its `why`; other errors as they are.
fn asked_by(e: SimError, recording: &Recording, i: usize, sample_load: f64) -> SimError {
    match e {
        SimError::NoEquilibrium {
            load,
            why,
            inverted,
            near,
            advice,
            stalled,
        } => SimError::NoEquilibrium {
            load,
            why: format!(
                "sample {} of {} asks for {} N; {why}",
                i + 1,
                recording.samples_path.display(),
                sample_load
            ),
            inverted,
            near,
            advice,
            stalled,
        },
        e => e,
    }
}

/// Each observed marker's `dx/dp` (in the order `record` keeps them): an object marker's is
/// its facet's weights applied to the particles' (positions are linear in them).
fn marker_sensitivities(
    sim: &Simulation,
    attachments: &[Attachment],
    observations: &[crate::recording::Observation],
    d: &[Vec<DVec3>],
) -> Vec<Vec<DVec3>> {
    let n = sim.model.particle_count();
    observations
        .iter()
        .filter_map(|o| {
            let of = |dx_dp: &Vec<DVec3>| -> Option<DVec3> {
                match o.marker {
                    MarkerRef::Object(k) => attachments.get(k).map(|a| {
                        let tri = sim.model.facets[a.facet as usize];
                        (0..3).map(|j| a.weights[j] * dx_dp[tri[j] as usize]).sum()
                    }),
                    MarkerRef::Finger(k) => dx_dp.get(n + k).copied(),
                }
            };
            d.iter().map(of).collect::<Option<Vec<DVec3>>>()
        })
        .collect()
}

/// Brings the present load to rest as `options` say: statically unless a finger still moves
/// along its travel (input a static solve cannot hold) or dynamics are asked for.
fn settle(sim: &mut Simulation, from: &[DVec3], options: ReplayOptions) -> Result<(), SimError> {
    match options.settle {
        Some(Settle::Static) if !sim.has_moving_input() => sim
            .settle_to_equilibrium(from, options.statics, options.rest, |_| {})
            .map(|_| ()),
        _ => sim.settle(options.rest, |_| {}).map(|_| ()),
    }
}

/// Settles with every velocity-driven finger axis held still.
fn settle_still(sim: &mut Simulation, options: ReplayOptions) -> Result<(), SimError> {
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
    // From the undeformed state, where no finger load acted.
    let from = vec![DVec3::ZERO; sim.state.fingers.len()];
    let settled = settle(sim, &from, options);
    sim.model = moving;
    for f in &mut sim.state.fingers {
        f.travelled = 0.0;
    }
    settled
}
