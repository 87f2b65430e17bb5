//! The Recording panel: a lab recording opened over the run, replayed on
//! a background thread (`softgrip-replay`, never the solver's), its
//! samples scrubbed in the 3-D view with the recorded and simulated
//! markers and the residuals between them, and a fit run from here
//! (`softgrip-fit`) with its progress.
//!
//! The UI never waits for a job: each frame it reads the job's progress
//! (atomics) and polls its result (a channel of one). Every recording
//! opened bumps a generation counter and each result carries the
//! generation it was started in, so a replay or a fit of a recording
//! that has since been replaced is ignored. A job's Stop button cancels
//! it through its `softgrip_core::cancel` token: its simulations stop at their
//! next step, and the job shows "stopping" until its thread has ended
//! (with the error "cancelled", shown as "stopped"). A job dropped
//! (another recording opened, the viewer closed) is cancelled the same
//! way, instead of keeping both cores busy for minutes.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, sync_channel};
use std::time::Instant;

use eframe::egui;
use glam::DVec3;

use crate::render::markers::MarkerPair;
use softgrip_core::cancel::Cancel;
use softgrip_core::model::Model;
use softgrip_core::scene::Scene;
use softgrip_core::state::State;
use softgrip_lab::compare::{marker_position, scored};
use softgrip_lab::fit::{Fit, FitOptions, FitParam, default_bounds, fit};
use softgrip_lab::params;
use softgrip_lab::recording::{Mode, Recording};
use softgrip_lab::replay::{Replay, ReplayOptions, replay};

/// The parameters the Fit section offers: the thesis's four.
pub const FIT_PARAMS: [&str; 4] = ["young_modulus", "alpha", "tau_s", "tau_c"];

const ERROR_RED: egui::Color32 = egui::Color32::from_rgb(200, 40, 40);

/// What a job's thread reports while it runs.
#[derive(Debug, Default)]
pub(super) struct Progress {
    /// Samples replayed, or simulations of a fit, or fits of a diagnosis.
    pub(super) done: AtomicUsize,
    /// A fit's best NRMSE so far (`f64` bits; NaN before the first).
    pub(super) best: AtomicU64,
    /// What `done` counts up to when the job learns it as it goes (a
    /// diagnosis's fits); 0: `Job::total`.
    pub(super) planned: AtomicUsize,
}

/// A job on a background thread: its progress and, once, its result.
pub(super) struct Job<T> {
    generation: u64,
    pub(super) progress: Arc<Progress>,
    /// What `done` counts up to (a fit's budget: it may stop earlier).
    pub(super) total: usize,
    result: Receiver<(u64, Result<T, String>)>,
    pub(super) started: Instant,
    /// Set by [`Job::stop`] and when the job is dropped: its simulations
    /// stop at their next step.
    cancel: Cancel,
}

impl<T> Drop for Job<T> {
    fn drop(&mut self) {
        self.cancel.cancel();
    }
}

impl<T: Send + 'static> Job<T> {
    /// Runs `work` on a thread named `name`; its result is tagged with
    /// `generation`.
    pub(super) fn spawn(
        name: &str,
        generation: u64,
        total: usize,
        work: impl FnOnce(&Progress) -> Result<T, String> + Send + 'static,
    ) -> Result<Job<T>, String> {
        let progress = Arc::new(Progress {
            done: AtomicUsize::new(0),
            best: AtomicU64::new(f64::NAN.to_bits()),
            planned: AtomicUsize::new(0),
        });
        let shared = Arc::clone(&progress);
        let cancel = Cancel::new();
        let token = cancel.clone();
        // One slot: the thread sends once and never waits.
        let (sender, result) = sync_channel(1);
        std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                let r = softgrip_core::cancel::scope(Some(token), || work(&shared));
                let _ = sender.send((generation, r));
            })
            .map_err(|e| format!("could not start the {name} thread: {e}"))?;
        Ok(Job {
            generation,
            progress,
            total,
            result,
            started: Instant::now(),
            cancel,
        })
    }

    /// The result, once the thread has sent it; `Err` if the thread
    /// ended without one (it panicked).
    pub(super) fn poll(&self) -> Option<(u64, Result<T, String>)> {
        match self.result.try_recv() {
            Ok(r) => Some(r),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some((
                self.generation,
                Err("the background thread stopped without a result".into()),
            )),
        }
    }

    /// Asks the job to stop; its result ("cancelled") comes by `poll`.
    pub(super) fn stop(&self) {
        self.cancel.cancel();
    }

    pub(super) fn stopping(&self) -> bool {
        self.cancel.is_cancelled()
    }

    pub(super) fn done(&self) -> usize {
        self.progress.done.load(Ordering::Relaxed)
    }

    fn best(&self) -> f64 {
        f64::from_bits(self.progress.best.load(Ordering::Relaxed))
    }
}

/// A job's progress bar with a Stop button beside it, which stops the
/// job (the bar then says so until its thread has ended).
pub(super) fn progress_with_stop<T: Send + 'static>(
    ui: &mut egui::Ui,
    job: &Job<T>,
    bar: egui::ProgressBar,
) {
    ui.horizontal(|ui| {
        let stopping = job.stopping();
        if ui
            .add_enabled(!stopping, egui::Button::new("Stop"))
            .on_hover_text("cancel this job: its simulations stop at their next step")
            .clicked()
        {
            job.stop();
        }
        if stopping {
            ui.add(bar.text("stopping ..."));
        } else {
            ui.add(bar);
        }
    });
}

/// A job's error in words: "stopped" for a cancelled one, else `failed`
/// and the error.
pub(super) fn job_error(failed: &str, e: &str) -> String {
    if e == softgrip_core::cancel::CANCELLED {
        format!("{failed}: stopped")
    } else {
        format!("{failed}: {e}")
    }
}

/// A finished replay with what the overlay needs.
pub struct Replayed {
    /// The recording, with the scene it was replayed on.
    pub recording: Arc<Recording>,
    pub model: Arc<Model>,
    /// With each sample's state (`keep_states`).
    pub replay: Replay,
    /// RMS residual per sample over the markers NRMSE counts (m).
    pub sample_rms: Vec<f64>,
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

/// What the 3-D view draws instead of the live frame while the recording
/// is shown.
pub struct Overlay {
    pub model: Arc<Model>,
    pub state: State,
    pub markers: Vec<MarkerPair>,
    /// Residuals drawn this many times longer.
    pub exaggerate: f64,
    /// What is shown, for the view's caption.
    pub caption: String,
    /// Changes whenever what is drawn changes.
    pub key: OverlayKey,
}

/// The replay (its address), the sample and the exaggeration (`f64`
/// bits) an overlay shows.
pub type OverlayKey = (usize, usize, u64);

/// A fit that finished, and the recording it fitted.
pub struct Fitted {
    pub recording: Arc<Recording>,
    pub fit: Fit,
}

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
    fit_choice: [bool; 4],
    fit_job: Option<Job<Fitted>>,
    fitted: Option<Arc<Fitted>>,
    /// The Diagnose section.
    pub diagnosis: super::diagnosis::DiagnosisSection,
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
            fit_choice: [true, false, false, false],
            fit_job: None,
            fitted: None,
            diagnosis: Default::default(),
        }
    }
}

/// A recording's header is TOML with a `samples` key, which a scene file
/// never has: how the scene box's Open tells the two apart.
pub fn is_recording_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
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
        self.fitted.as_ref()
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

    pub fn replaying(&self) -> bool {
        self.replay_job.is_some()
    }

    pub fn fitting(&self) -> bool {
        self.fit_job.is_some()
    }

    /// A replay or a fit is running (the UI redraws for its progress).
    pub fn busy(&self) -> bool {
        self.replaying() || self.fitting() || self.diagnosis.running()
    }

    /// Chooses whether `FIT_PARAMS[k]` is fitted.
    pub fn choose_fit_param(&mut self, k: usize, on: bool) {
        if let Some(c) = self.fit_choice.get_mut(k) {
            *c = on;
        }
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
        self.fit_job = None;
        self.fitted = None;
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

    fn start_replay(&mut self, recording: Arc<Recording>) {
        let total = recording.samples.len();
        let job = Job::spawn("softgrip-replay", self.generation, total, move |progress| {
            let scene = &recording.scene;
            let model = Arc::new(Model::from_scene(scene).map_err(|e| e.to_string())?);
            let options = ReplayOptions {
                keep_states: true,
                ..Default::default()
            };
            let replay = replay(&recording, scene, options, |n| {
                progress.done.store(n, Ordering::Relaxed);
            })
            .map_err(|e| e.to_string())?;
            Ok(Replayed::new(recording, model, replay))
        });
        match job {
            Ok(job) => self.replay_job = Some(job),
            Err(e) => self.error = Some(e),
        }
    }

    fn start_fit(&mut self) {
        let Some(recording) = self.recording.clone() else {
            return;
        };
        let chosen: Result<Vec<FitParam>, String> = FIT_PARAMS
            .iter()
            .zip(self.fit_choice)
            .filter(|(_, on)| *on)
            .map(|(name, _)| {
                let param = params::find(name)?;
                let (lower, upper) = default_bounds(param, &recording.scene)?;
                Ok(FitParam {
                    param,
                    lower,
                    upper,
                    log: param.log,
                })
            })
            .collect();
        let params = match chosen {
            Ok(p) if p.is_empty() => {
                self.error = Some("choose at least one parameter to fit".into());
                return;
            }
            Ok(p) => p,
            Err(e) => {
                self.error = Some(format!("cannot fit: {e}"));
                return;
            }
        };
        self.error = None;
        self.fitted = None;
        let options = FitOptions::default();
        let total = options.max_evaluations + 4 * params.len();
        let job = Job::spawn("softgrip-fit", self.generation, total, move |progress| {
            let report = |n: usize, best: f64| {
                progress.done.store(n, Ordering::Relaxed);
                progress.best.store(best.to_bits(), Ordering::Relaxed);
            };
            let fit = fit(&recording, &params, options, &report).map_err(|e| e.to_string())?;
            Ok(Fitted { recording, fit })
        });
        match job {
            Ok(job) => self.fit_job = Some(job),
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
        if let Some((generation, result)) = self.fit_job.as_ref().and_then(Job::poll) {
            self.fit_job = None;
            if generation == self.generation {
                match result {
                    Ok(fitted) => self.fitted = Some(Arc::new(fitted)),
                    Err(e) => self.error = Some(job_error("the fit", &e)),
                }
            }
        }
    }

    /// What the 3-D view draws while the recording is shown.
    pub fn overlay(&self) -> Option<Overlay> {
        if !self.show {
            return None;
        }
        let replayed = self.replayed.as_ref()?;
        let state = replayed.state(self.sample)?;
        let markers = replayed.markers(self.sample, &state);
        let n = replayed.recording.samples.len();
        Some(Overlay {
            model: Arc::clone(&replayed.model),
            state,
            markers,
            exaggerate: self.exaggerate,
            caption: format!(
                "recording, sample {}/{n}: {}{}",
                self.sample + 1,
                replayed.sample_label(self.sample),
                if self.exaggerate == 1.0 {
                    String::new()
                } else {
                    format!(", residuals drawn x{:.0}", self.exaggerate)
                }
            ),
            key: (
                Arc::as_ptr(replayed) as usize,
                self.sample,
                self.exaggerate.to_bits(),
            ),
        })
    }

    /// The panel; what it asks of the viewer, if anything.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<Action> {
        let mut action = None;
        egui::CollapsingHeader::new("Recording")
            .default_open(true)
            .show(ui, |ui| {
                if ui
                    .button("Open recording...")
                    .on_hover_text(
                        "a lab recording (.toml header with its samples CSV); its scene replaces the run's",
                    )
                    .clicked()
                {
                    match rfd::FileDialog::new()
                        .add_filter("softgrip recording", &["toml"])
                        .pick_file()
                    {
                        Some(path) => action = Some(Action::Open(path)),
                        None => {
                            self.status = Some(
                                "no file chosen (or no file dialog here): type the recording's path in the scene file box and press Open, or start with `softgrip view --recording REC`"
                                    .into(),
                            );
                        }
                    }
                }
                if let Some(e) = &self.error {
                    ui.colored_label(ERROR_RED, e);
                } else if let Some(s) = &self.status {
                    ui.label(s);
                }
                if let Some(job) = &self.replay_job {
                    let done = job.done();
                    let bar = egui::ProgressBar::new(done as f32 / job.total.max(1) as f32).text(
                        format!(
                            "replaying: {done} / {} samples, {:.0} s",
                            job.total,
                            job.started.elapsed().as_secs_f64()
                        ),
                    );
                    progress_with_stop(ui, job, bar);
                }
                if self.replayed.is_some() {
                    self.samples(ui);
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
                    if let Some(a) = self.fit_section(ui) {
                        action = Some(a);
                    }
                    self.diagnosis_section(ui);
                }
            });
        action
    }

    /// The sample slider, the errors and the residual plot.
    fn samples(&mut self, ui: &mut egui::Ui) {
        let Some(replayed) = self.replayed.clone() else {
            return;
        };
        let n = replayed.recording.samples.len();
        ui.checkbox(&mut self.show, "show recording")
            .on_hover_text("the 3-D view shows the replayed sample instead of the live run");
        let mut k = self.sample + 1;
        ui.add_enabled(
            n > 1,
            egui::Slider::new(&mut k, 1..=n.max(1)).text("sample"),
        );
        self.sample = k.clamp(1, n.max(1)) - 1;
        ui.label(format!(
            "sample {}/{n}: {}",
            self.sample + 1,
            replayed.sample_label(self.sample)
        ));
        ui.add(
            egui::Slider::new(&mut self.exaggerate, 1.0..=100.0)
                .logarithmic(true)
                .text("residuals drawn x"),
        )
        .on_hover_text(
            "draw the recorded markers at simulated + x (recorded - simulated): residuals of a good fit are too short to see",
        );
        let e = &replayed.replay.errors;
        ui.label(format!(
            "NRMSE {:.4} (RMSE {:.3} mm over {} observations)",
            e.nrmse,
            1e3 * e.rmse_m,
            e.count
        ));
        let rms = replayed.sample_rms.get(self.sample).copied().unwrap_or(0.0);
        ui.label(format!("this sample: RMS residual {:.3} mm", 1e3 * rms));
        ui.label(egui::RichText::new("RMS residual per sample (mm)").small());
        let points: Vec<[f64; 2]> = replayed
            .sample_rms
            .iter()
            .enumerate()
            .map(|(i, r)| [(i + 1) as f64, 1e3 * r])
            .collect();
        let current = (self.sample + 1) as f64;
        super::grid::with_grids(egui_plot::Plot::new("residual per sample"))
            .height(110.0)
            .x_axis_label("sample")
            .allow_scroll(false)
            .show(ui, |plot| {
                plot.line(egui_plot::Line::new("RMS residual (mm)", points.clone()));
                plot.points(egui_plot::Points::new("samples", points).radius(2.5));
                plot.vline(
                    egui_plot::VLine::new("this sample", current)
                        .stroke(egui::Stroke::new(1.5, egui::Color32::from_gray(70))),
                );
            });
    }

    /// The fit: parameters, Run, progress, results and Apply.
    fn fit_section(&mut self, ui: &mut egui::Ui) -> Option<Action> {
        let mut action = None;
        egui::CollapsingHeader::new("Fit...").show(ui, |ui| {
            let scene = self.recording.as_ref().map(|r| r.scene.clone());
            for (k, name) in FIT_PARAMS.iter().enumerate() {
                let bounds = scene
                    .as_ref()
                    .ok_or_else(String::new)
                    .and_then(|s| Ok((params::find(name)?, s)))
                    .and_then(|(p, s)| default_bounds(p, s).map(|b| (p, b)));
                let hint = match &bounds {
                    Ok((p, (lo, hi))) => format!("fitted in [{lo:.3e}, {hi:.3e}] {}", p.unit),
                    Err(e) => e.clone(),
                };
                ui.checkbox(&mut self.fit_choice[k], *name)
                    .on_hover_text(hint);
            }
            let running = self.fit_job.is_some();
            if ui
                .add_enabled(!running, egui::Button::new("Run fit"))
                .on_hover_text("minimise NRMSE over the chosen parameters (background thread)")
                .clicked()
            {
                self.start_fit();
            }
            if let Some(job) = &self.fit_job {
                let done = job.done();
                let bar = egui::ProgressBar::new((done as f32 / job.total.max(1) as f32).min(1.0))
                    .text(format!(
                        "fitting: {done} simulations, {:.0} s",
                        job.started.elapsed().as_secs_f64()
                    ));
                let best = job.best();
                progress_with_stop(ui, job, bar);
                if best.is_finite() {
                    ui.label(format!("best NRMSE so far {best:.4}"));
                }
            }
            if let Some(fitted) = self.fitted.clone() {
                let f = &fitted.fit;
                egui::Grid::new("fit results")
                    .num_columns(3)
                    .striped(true)
                    .show(ui, |ui| {
                        for (i, p) in f.params.iter().enumerate() {
                            let se = f
                                .uncertainty
                                .standard_errors
                                .get(i)
                                .copied()
                                .unwrap_or(f64::INFINITY);
                            ui.label(p.param.name);
                            ui.monospace(format!(
                                "{} +/- {} {}",
                                fitted_value(f.fitted[i]),
                                fitted_value(se),
                                p.param.unit
                            ));
                            let mut verdict = f
                                .sensitivity
                                .get(i)
                                .map_or("", |s| s.verdict.label())
                                .to_string();
                            if f.at_bound.get(i).copied().unwrap_or(false) {
                                verdict.push_str(", at a bound");
                            }
                            ui.label(verdict);
                            ui.end_row();
                        }
                    });
                ui.label(format!(
                    "fit NRMSE {:.4} -> {:.4}{}",
                    f.before.nrmse,
                    f.after.nrmse,
                    if f.converged {
                        ""
                    } else {
                        " (stopped by its budget)"
                    }
                ));
                if ui
                    .button("Apply fitted values")
                    .on_hover_text("set them in the live run and replay the recording with them")
                    .clicked()
                {
                    action = Some(Action::Apply(
                        f.params
                            .iter()
                            .zip(&f.fitted)
                            .map(|(p, v)| (p.param.name, *v))
                            .collect(),
                    ));
                }
            }
        });
        action
    }

    /// The Diagnose section, and what it asks for.
    fn diagnosis_section(&mut self, ui: &mut egui::Ui) {
        use super::diagnosis::SectionAction;
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
}

/// Four significant digits, the way the fit's values are shown.
pub fn fitted_value(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4e}")
    } else {
        "inf".into()
    }
}
