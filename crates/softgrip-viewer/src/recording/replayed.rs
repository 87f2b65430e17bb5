//! A replay of the open recording on a background thread (`softgrip-replay`, never the
//! solver's), and what it leaves for the overlay: each sample's state, the compared markers and
//! the RMS residual per sample.

use std::sync::Arc;
use std::sync::atomic::Ordering;

use eframe::egui;
use glam::DVec3;

use crate::jobs::{Job, progress_with_stop};
use crate::render::markers::MarkerPair;
use softgrip_core::model::Model;
use softgrip_core::state::State;
use softgrip_lab::compare::{marker_position, scored};
use softgrip_lab::recording::{Mode, Recording};
use softgrip_lab::replay::{Replay, ReplayOptions, replay};

/// A finished replay with what the overlay needs.
pub struct Replayed {
    /// The recording, with the scene it was replayed on.
    pub recording: Arc<Recording>,
    /// The model built from that scene, which the replay ran.
    pub model: Arc<Model>,
    /// With each sample's state (`keep_states`).
    pub replay: Replay,
    /// RMS residual per sample over the markers NRMSE counts (m).
    pub sample_rms: Vec<f64>,
}

/// Starts replaying `recording` on its own scene; the result is tagged
/// with `generation`.
pub(super) fn spawn(recording: Arc<Recording>, generation: u64) -> Result<Job<Replayed>, String> {
    let total = recording.samples.len();
    Job::spawn("softgrip-replay", generation, total, move |progress| {
        let scene = &recording.scene;
        let model = Arc::new(Model::from_scene(scene)?);
        let options = ReplayOptions {
            keep_states: true,
            ..Default::default()
        };
        let replay = replay(&recording, scene, options, |n| {
            progress.done.store(n, Ordering::Relaxed);
        })?;
        Ok(Replayed::new(recording, model, replay))
    })
}

/// The running replay's progress bar, with its Stop button.
pub(super) fn progress(ui: &mut egui::Ui, job: &Job<Replayed>) {
    let done = job.done();
    let bar = egui::ProgressBar::new(done as f32 / job.total.max(1) as f32).text(format!(
        "replaying: {done} / {} samples, {:.0} s",
        job.total,
        job.started.elapsed().as_secs_f64()
    ));
    progress_with_stop(ui, job, bar);
}

impl Replayed {
    fn new(recording: Arc<Recording>, model: Arc<Model>, replay: Replay) -> Replayed {
        let mut sums = vec![(0.0, 0usize); recording.samples.len()];
        for r in scored(&replay.residuals) {
            if let Some(s) = sums.get_mut(r.sample) {
                s.0 += r.distance().powi(2);
                s.1 += 1;
            }
        }
        let sample_rms = sums
            .iter()
            .map(|&(sum, n)| if n == 0 { 0.0 } else { (sum / n as f64).sqrt() })
            .collect();
        Replayed {
            recording,
            model,
            replay,
            sample_rms,
        }
    }

    /// The object and fingers as replayed at `sample`.
    pub fn state(&self, sample: usize) -> Option<State> {
        let s = self.replay.states.get(sample)?;
        let mut state = State::initial(&self.model);
        if s.positions.len() != state.positions.len() {
            return None;
        }
        state.positions.clone_from(&s.positions);
        for (f, &p) in state.fingers.iter_mut().zip(&s.fingers) {
            f.position = p;
        }
        Some(state)
    }

    /// The compared markers of `sample` in `state` (that sample's state):
    /// simulated where the marker's material point is, recorded over the
    /// observed axes.
    pub fn markers(&self, sample: usize, state: &State) -> Vec<MarkerPair> {
        self.replay
            .residuals
            .iter()
            .filter(|r| r.sample == sample)
            .map(|r| {
                let simulated =
                    marker_position(&self.model, state, &self.replay.attachments, r.marker)
                        .unwrap_or(r.simulated);
                let recorded = DVec3::from_array(std::array::from_fn(|a| {
                    r.recorded[a].unwrap_or(simulated[a])
                }));
                MarkerPair {
                    simulated,
                    recorded,
                }
            })
            .collect()
    }

    /// "load 2.000 N" (quasi-static) or "t = 0.150 s" (time series).
    pub fn sample_label(&self, sample: usize) -> String {
        let Some(s) = self.recording.samples.get(sample) else {
            return String::new();
        };
        match (self.recording.mode, s.time) {
            (Mode::TimeSeries, Some(t)) => format!("t = {t:.3} s (load {:.3} N)", s.load),
            _ => format!("load {:.3} N", s.load),
        }
    }
}
