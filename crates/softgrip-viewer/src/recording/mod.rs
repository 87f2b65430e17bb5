//! The Recording panel: a lab recording opened over the run, replayed on a background thread
//! (`replayed`), its samples scrubbed in the 3-D view (`samples`, `overlay`) with the recorded
//! and simulated markers and the residuals between them, a fit run from here (`fit`) and a
//! diagnosis ([`diagnosis`]). The jobs and how they stop are in `crate::jobs`.
//!
//! The panel's order: Open, the error or status, the replay's progress, the samples, "Replay with
//! the panel's parameters", Fit..., Diagnose....

pub mod diagnosis;
mod fit;
mod overlay;
mod replayed;
mod samples;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use eframe::egui;

use crate::jobs::{Job, job_error};
use crate::widgets::ERROR_RED;
use diagnosis::{DiagnosisSection, SectionAction};
use fit::FitSection;
use softgrip_core::scene::Scene;
use softgrip_lab::params;
use softgrip_lab::recording::Recording;

pub use fit::{FIT_PARAMS, Fitted, fitted_value};
pub use overlay::{Overlay, OverlayKey};
pub use replayed::Replayed;

/// What the panel asks of the rest of the viewer.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Open this recording (the file dialog's choice).
    Open(PathBuf),
    /// Set these parameters in the live run (the fit's values).
    Apply(Vec<(&'static str, f64)>),
    /// Replay the recording on the scene the panels show (the sliders'
    /// values).
    ReplayEdited,
}

/// The panel's state: the recording, its replay and its fit.
pub struct RecordingPanel {
    /// Bumped by every recording opened; results of older jobs are
    /// dropped.
    generation: u64,
    recording: Option<Arc<Recording>>,
    /// The last error (a file that would not open, a replay or a fit
    /// that failed); the run is not touched.
    pub error: Option<String>,
    status: Option<String>,
    replay_job: Option<Job<Replayed>>,
    replayed: Option<Arc<Replayed>>,
    /// Draw the recording in the 3-D view instead of the live run.
    pub show: bool,
    sample: usize,
    /// Residuals drawn this many times longer (1: true positions).
    pub exaggerate: f64,
    fit: FitSection,
    /// The Diagnose section.
    pub diagnosis: DiagnosisSection,
}

impl Default for RecordingPanel {
    fn default() -> RecordingPanel {
        RecordingPanel {
            generation: 0,
            recording: None,
            error: None,
            status: None,
            replay_job: None,
            replayed: None,
            show: true,
            sample: 0,
            exaggerate: 1.0,
            fit: FitSection::default(),
            diagnosis: Default::default(),
        }
    }
}

/// A recording's header is TOML with a `samples` key, which a scene file
/// never has: how the scene box's Open tells the two apart.
pub fn is_recording_file(path: &Path) -> bool {
    softgrip_core::files::read_at_most(path, softgrip_lab::recording::MAX_HEADER_BYTES)
        .ok()
        .and_then(|bytes| String::from_utf8(bytes).ok())
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("samples") && t.contains_key("mode"))
}

impl RecordingPanel {
    /// The recording open, with the scene of its latest replay.
    pub fn recording(&self) -> Option<&Arc<Recording>> {
        self.recording.as_ref()
    }

    /// The finished replay, if any.
    pub fn replayed(&self) -> Option<&Arc<Replayed>> {
        self.replayed.as_ref()
    }

    /// The finished fit, if any.
    pub fn fitted(&self) -> Option<&Arc<Fitted>> {
        self.fit.fitted()
    }

    /// The sample shown (from 0).
    pub fn sample(&self) -> usize {
        self.sample
    }

    /// Shows sample `k` (from 0; clamped to the samples there are).
    pub fn set_sample(&mut self, k: usize) {
        let n = self
            .replayed
            .as_ref()
            .map_or(1, |r| r.recording.samples.len());
        self.sample = k.min(n.saturating_sub(1));
    }

    /// Whether a replay is running on its thread.
    pub fn replaying(&self) -> bool {
        self.replay_job.is_some()
    }

    /// Whether a fit is running on its thread.
    pub fn fitting(&self) -> bool {
        self.fit.fitting()
    }

    /// A replay or a fit is running (the UI redraws for its progress).
    pub fn busy(&self) -> bool {
        self.replaying() || self.fitting() || self.diagnosis.running()
    }

    /// Chooses whether `FIT_PARAMS[k]` is fitted.
    pub fn choose_fit_param(&mut self, k: usize, on: bool) {
        self.fit.choose(k, on);
    }

    /// Takes a loaded recording: drops whatever the previous one had
    /// running or shown, and starts replaying this one.
    pub fn open(&mut self, recording: Recording) {
        self.generation += 1;
        self.error = None;
        self.status = Some(format!(
            "opened {} ({} samples, {} markers)",
            recording.source.display(),
            recording.samples.len(),
            recording.markers.len()
        ));
        self.replay_job = None;
        self.replayed = None;
        self.fit.clear();
        self.diagnosis.clear();
        self.sample = 0;
        let recording = Arc::new(recording);
        self.recording = Some(Arc::clone(&recording));
        self.start_replay(recording);
    }

    /// A recording that did not load: its error, and nothing else changes.
    pub fn failed(&mut self, path: &Path, error: impl std::fmt::Display) {
        self.error = Some(format!(
            "could not open the recording {}: {error}",
            path.display()
        ));
    }

    /// Replays the open recording on `scene` (its own, the sliders', or
    /// with fitted values).
    pub fn replay_on(&mut self, scene: Scene) {
        let Some(recording) = &self.recording else {
            return;
        };
        let mut recording = (**recording).clone();
        recording.scene = scene;
        let recording = Arc::new(recording);
        self.recording = Some(Arc::clone(&recording));
        self.start_replay(recording);
    }

    /// Replays with the fit's values set in the recording's scene.
    pub fn replay_fitted(&mut self, values: &[(&'static str, f64)]) {
        let Some(recording) = &self.recording else {
            return;
        };
        let mut scene = recording.scene.clone();
        for (name, v) in values {
            match params::set(&scene, name, *v) {
                Ok(s) => scene = s,
                Err(e) => {
                    self.error = Some(format!("cannot apply the fitted {name}: {e}"));
                    return;
                }
            }
        }
        self.replay_on(scene);
    }

    fn start_replay(&mut self, recording: Arc<Recording>) {
        match replayed::spawn(recording, self.generation) {
            Ok(job) => self.replay_job = Some(job),
            Err(e) => self.error = Some(e),
        }
    }

    /// Takes the results of finished jobs; once per UI frame.
    pub fn poll(&mut self) {
        if let Some((generation, result)) = self.replay_job.as_ref().and_then(Job::poll) {
            self.replay_job = None;
            if generation == self.generation {
                match result {
                    Ok(replayed) => {
                        let n = replayed.recording.samples.len();
                        self.sample = self.sample.min(n.saturating_sub(1));
                        self.replayed = Some(Arc::new(replayed));
                    }
                    Err(e) => self.error = Some(job_error("replaying the recording", &e)),
                }
            }
        }
        self.diagnosis.poll(self.generation);
        self.fit.poll(self.generation, &mut self.error);
    }

    /// What the 3-D view draws while the recording is shown.
    pub fn overlay(&self) -> Option<Overlay> {
        if !self.show {
            return None;
        }
        Overlay::of(self.replayed.as_ref()?, self.sample, self.exaggerate)
    }

    /// The panel; what it asks of the viewer, if anything.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<Action> {
        let mut action = None;
        egui::CollapsingHeader::new("Recording")
            .default_open(true)
            .show(ui, |ui| {
                if let Some(path) = self.open_button(ui) {
                    action = Some(Action::Open(path));
                }
                if let Some(e) = &self.error {
                    ui.colored_label(ERROR_RED, e);
                } else if let Some(s) = &self.status {
                    ui.label(s);
                }
                if let Some(job) = &self.replay_job {
                    replayed::progress(ui, job);
                }
                if let Some(replayed) = self.replayed.clone() {
                    samples::ui(
                        ui,
                        &replayed,
                        &mut self.show,
                        &mut self.sample,
                        &mut self.exaggerate,
                    );
                    if ui
                        .add_enabled(
                            self.replay_job.is_none(),
                            egui::Button::new("Replay with the panel's parameters"),
                        )
                        .on_hover_text(
                            "replay the recording on the scene as the sliders have made it",
                        )
                        .clicked()
                    {
                        action = Some(Action::ReplayEdited);
                    }
                    let recording = self.recording.as_ref();
                    if let Some(values) =
                        self.fit.ui(ui, recording, self.generation, &mut self.error)
                    {
                        action = Some(Action::Apply(values));
                    }
                    self.diagnosis_section(ui);
                }
            });
        action
    }

    /// "Open recording..."; the file chosen, if any.
    fn open_button(&mut self, ui: &mut egui::Ui) -> Option<PathBuf> {
        if !ui
            .button("Open recording...")
            .on_hover_text(
                "a lab recording (.toml header with its samples CSV); its scene replaces the run's",
            )
            .clicked()
        {
            return None;
        }
        let chosen = rfd::FileDialog::new()
            .add_filter("softgrip recording", &["toml"])
            .pick_file();
        if chosen.is_none() {
            self.status = Some(
                "no file chosen (or no file dialog here): type the recording's path in the scene file box and press Open, or start with `softgrip view --recording REC`"
                    .into(),
            );
        }
        chosen
    }

    /// The Diagnose section, and what it asks for.
    fn diagnosis_section(&mut self, ui: &mut egui::Ui) {
        let reveal = self.diagnosis.take_reveal();
        let asked = egui::CollapsingHeader::new("Diagnose...")
            .open(reveal.then_some(true))
            .show(ui, |ui| {
                self.diagnosis
                    .ui(ui, self.recording.is_some() && self.replay_job.is_none())
            })
            .body_returned;
        match asked {
            Some(SectionAction::Start) => {
                if let Some(recording) = self.recording.clone() {
                    self.diagnosis.start(recording, self.generation);
                }
            }
            Some(SectionAction::Replay(scene)) => self.replay_on(*scene),
            Some(SectionAction::None) | None => {}
        }
    }
}
