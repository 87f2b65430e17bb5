//! The Recording panel's Diagnose section: `softgrip diagnose` on a
//! background thread (`softgrip-diagnose`) with its progress, then the
//! verdict, where the baseline misses, the candidates ranked as bars, the
//! evidence, and a toggle that replays the recording on the baseline or on
//! the model with the effects found, so the 3-D view overlays either on
//! the recording.

use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use eframe::egui;

use super::fit::fitted_value;
use crate::jobs::{Job, job_error, progress_with_stop};
use crate::widgets::ERROR_RED;
use softgrip_core::scene::Scene;
use softgrip_lab::diagnose::{self, DiagnoseOptions, Diagnosis};
use softgrip_lab::recording::Recording;

const ACCEPTED: egui::Color32 = egui::Color32::from_rgb(40, 150, 70);
const REJECTED: egui::Color32 = egui::Color32::from_rgb(120, 130, 150);

/// Which fitted model the overlay shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shown {
    /// The recording's own scene (before any diagnosis).
    #[default]
    Nominal,
    /// The model fitted without any effect (the diagnosis's baseline fit).
    Baseline,
    /// The model with the effects found, fitted (the diagnosis's final fit).
    Extended,
}

/// The section's state.
pub struct DiagnosisSection {
    job: Option<Job<Diagnosis>>,
    /// What the running job is fitting.
    stage: Arc<Mutex<String>>,
    /// The running job's stages so far, each with the seconds since the job started when it
    /// began: every one but the last has finished.
    stages: Arc<Mutex<Vec<(String, f64)>>>,
    result: Option<Arc<Diagnosis>>,
    /// Which fitted model the overlay shows.
    pub shown: Shown,
    /// The last job's error (a diagnosis that failed or could not start), shown in red.
    pub error: Option<String>,
    /// Open the section on the next frame (a diagnosis started or came).
    reveal: bool,
    /// The scene's E was measured (a compression test's initial slope) ...
    pub e_measured: bool,
    /// ... to within this factor either way: every fit keeps E there
    /// (`DiagnoseOptions::bounds`, the CLI's `--bound`).
    pub e_within: f64,
}

impl Default for DiagnosisSection {
    fn default() -> Self {
        DiagnosisSection {
            job: None,
            stage: Arc::default(),
            stages: Arc::default(),
            result: None,
            shown: Shown::default(),
            error: None,
            reveal: false,
            e_measured: false,
            // Generous for a compression test's initial slope.
            e_within: 2.0,
        }
    }
}

impl DiagnosisSection {
    /// Whether a diagnosis is running on its thread.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// The finished diagnosis, if any.
    pub fn result(&self) -> Option<&Arc<Diagnosis>> {
        self.result.as_ref()
    }

    /// Drops a running job's result and the last diagnosis (a new
    /// recording was opened).
    pub fn clear(&mut self) {
        self.job = None;
        self.result = None;
        self.shown = Shown::Nominal;
        self.error = None;
    }

    /// Takes a diagnosis made elsewhere (the CLI's, or a test's).
    pub fn set_result(&mut self, d: Diagnosis) {
        self.result = Some(Arc::new(d));
        self.error = None;
        self.shown = Shown::Nominal;
        self.reveal = true;
    }

    /// Whether the section should be forced open this frame (once).
    pub fn take_reveal(&mut self) -> bool {
        std::mem::take(&mut self.reveal)
    }

    /// The options a diagnosis of `recording` started now runs with: the
    /// defaults, and E's range when it is marked measured.
    pub fn options(&self, recording: &Recording) -> DiagnoseOptions {
        let mut options = DiagnoseOptions::default();
        if self.e_measured {
            let e = recording.scene.object.young_modulus;
            let f = self.e_within.max(1.0 + 1e-9);
            options.bounds.push(("young_modulus".into(), e / f, e * f));
        }
        options
    }

    /// Starts diagnosing `recording` (on its own scene).
    pub fn start(&mut self, recording: Arc<Recording>, generation: u64) {
        self.error = None;
        self.result = None;
        let stage = Arc::clone(&self.stage);
        let stages = Arc::clone(&self.stages);
        if let Ok(mut s) = stages.lock() {
            s.clear();
        }
        let options = self.options(&recording);
        // Two baseline fits and each candidate once or twice; the count is
        // corrected as the diagnosis reports it.
        let total = 2 + 8 * options.max_effects;
        let job = Job::spawn("softgrip-diagnose", generation, total, move |progress| {
            let started = std::time::Instant::now();
            let report = |done: usize, planned: usize, what: &str| {
                progress.done.store(done, Ordering::Relaxed);
                progress.planned.store(planned, Ordering::Relaxed);
                if let Ok(mut s) = stage.lock() {
                    *s = what.to_string();
                }
                if let Ok(mut s) = stages.lock() {
                    s.push((what.to_string(), started.elapsed().as_secs_f64()));
                }
            };
            diagnose::diagnose(&recording, &options, &report)
        });
        match job {
            Ok(job) => self.job = Some(job),
            Err(e) => self.error = Some(e),
        }
        self.reveal = true;
    }

    /// Takes the finished job's result (if it is of `generation`).
    pub fn poll(&mut self, generation: u64) {
        if let Some((g, result)) = self.job.as_ref().and_then(Job::poll) {
            self.job = None;
            if g == generation {
                match result {
                    Ok(d) => self.set_result(d),
                    Err(e) => self.error = Some(job_error("the diagnosis", &e)),
                }
            }
        }
    }

    /// The section; the scene to replay on when the toggle changed.
    pub fn ui(&mut self, ui: &mut egui::Ui, can_start: bool) -> SectionAction {
        let mut action = SectionAction::None;
        let running = self.job.is_some();
        self.e_bound_ui(ui, running);
        if ui
            .add_enabled(can_start && !running, egui::Button::new("Run diagnosis"))
            .on_hover_text(
                "fit the model (E, alpha, tau_s, tau_c), locate what it still misses against the noise, try the catalogue of missing physics and name what explains it (minutes, on a background thread)",
            )
            .clicked()
        {
            action = SectionAction::Start;
        }
        self.progress_ui(ui);
        if let Some(e) = &self.error {
            ui.colored_label(ERROR_RED, e);
        }
        let Some(d) = self.result.clone() else {
            return action;
        };
        verdict_ui(ui, &d);
        ranking(ui, &d);
        details_ui(ui, &d);
        if let Some(toggled) = self.overlay_ui(ui, &d) {
            action = toggled;
        }
        action
    }

    /// The "E measured, within a factor of" row, disabled while a diagnosis runs.
    fn e_bound_ui(&mut self, ui: &mut egui::Ui, running: bool) {
        ui.add_enabled_ui(!running, |ui| {
            ui.horizontal(|ui| {
                ui.checkbox(&mut self.e_measured, "E measured, within a factor of")
                    .on_hover_text(
                        "the scene's Young's modulus was measured (the initial slope of a compression test): every fit keeps E within this factor of it, so a fit cannot absorb missing physics (strain-stiffening, creep) into an implausible E",
                    );
                ui.add_enabled(
                    self.e_measured,
                    egui::DragValue::new(&mut self.e_within)
                        .range(1.05..=10.0)
                        .speed(0.01)
                        .fixed_decimals(2),
                );
            });
        });
    }

    /// The running diagnosis's progress bar with its Stop button, and its stages so far.
    fn progress_ui(&self, ui: &mut egui::Ui) {
        let Some(job) = &self.job else {
            return;
        };
        let done = job.done();
        let planned = match job.progress.planned.load(Ordering::Relaxed) {
            0 => job.total,
            n => n,
        };
        let stage = self.stage.lock().map(|s| s.clone()).unwrap_or_default();
        let bar =
            egui::ProgressBar::new((done as f32 / planned.max(1) as f32).min(1.0)).text(format!(
                "diagnosing: {done} / {planned} fits ({stage}), {:.0} s",
                job.started.elapsed().as_secs_f64()
            ));
        progress_with_stop(ui, job, bar);
        let stages = self.stages.lock().map(|s| s.clone()).unwrap_or_default();
        for line in stage_lines(&stages, job.started.elapsed().as_secs_f64()) {
            ui.small(line);
        }
    }

    /// The overlay toggle (baseline or with the effects); the replay to show when it changed.
    fn overlay_ui(&mut self, ui: &mut egui::Ui, d: &Diagnosis) -> Option<SectionAction> {
        let mut action = None;
        ui.horizontal(|ui| {
            ui.label("overlay:");
            let before = self.shown;
            ui.selectable_value(&mut self.shown, Shown::Baseline, "baseline")
                .on_hover_text("replay on the model fitted without any effect");
            ui.add_enabled_ui(!d.effects.is_empty(), |ui| {
                ui.selectable_value(&mut self.shown, Shown::Extended, "with the effects")
                    .on_hover_text("replay on the model with the effects found, fitted");
            });
            if self.shown != before {
                action = Some(match self.shown {
                    Shown::Baseline => SectionAction::Replay(Box::new(d.baseline.scene.clone())),
                    Shown::Extended => SectionAction::Replay(Box::new(d.final_fit.scene.clone())),
                    Shown::Nominal => SectionAction::None,
                });
            }
        });
        action
    }
}

/// The diagnosis's verdict, what the model leaves, where and when, the NRMSE before and after
/// (all of it and beyond the noise) and, with effects found, the fitted parameters.
fn verdict_ui(ui: &mut egui::Ui, d: &Diagnosis) {
    let verdict = match d.effects.as_slice() {
        [] if d.remainder.fails() => format!(
            "unexplained, at {}: physics softgrip has no model of",
            d.mismatch_markers().join(", ")
        ),
        [] if d.unexplained => "mismatch beyond the noise that no candidate explains".into(),
        [] => "nothing missing: the model fits to the noise".into(),
        effects => format!("missing: {}", effects.join(" + ")),
    };
    ui.label(egui::RichText::new(verdict).strong());
    if let Some(left) = d.remainder.describe() {
        ui.label(format!("left by the model: {left}"));
    }
    if d.location.significant {
        ui.label(format!("where: {}", d.location.description));
        ui.label(format!("when: {}", d.location.when));
    }
    let (beyond_before, beyond_after) = d.nrmse_all_beyond_noise();
    ui.label(format!(
        "NRMSE over all markers {:.4} -> {:.4}",
        d.baseline.errors.nrmse_all, d.final_fit.errors.nrmse_all
    ))
    .on_hover_text("the recording's noise included: it cannot fall below the noise");
    ui.label(format!(
        "beyond the noise {beyond_before:.4} -> {beyond_after:.4}"
    ))
    .on_hover_text(
        "the part of the residual the noise does not account for: the model's own error",
    );
    if !d.effects.is_empty() {
        let fitted: Vec<String> = d
            .fitted_params()
            .iter()
            .map(|(n, v)| format!("{n} {}", fitted_value(*v)))
            .collect();
        ui.label(egui::RichText::new(fitted.join(", ")).small());
    }
}

/// Below the ranking: the evidence, the discretisation check, the candidates ruled out by the
/// score test and how long the diagnosis took.
fn details_ui(ui: &mut egui::Ui, d: &Diagnosis) {
    ui.label(egui::RichText::new(&d.evidence).small());
    ui.label(
        egui::RichText::new(format!("discretisation: {}", d.discretisation.describe()))
            .small(),
    )
    .on_hover_text(
        "the final model replayed on a mesh 0.8 times as fine and, for a time series, at half the step: a mismatch this size may be the model's own",
    );
    let ruled_out: Vec<String> = d
        .screens
        .iter()
        .filter(|(_, s)| !s.kept)
        .map(|(_, s)| diagnose::effect_label(s.effect, &s.variant))
        .collect();
    if !ruled_out.is_empty() {
        ui.label(
            egui::RichText::new(format!(
                "not fitted (the score test found nothing for them): {}",
                ruled_out.join(", ")
            ))
            .small(),
        )
        .on_hover_text(
            "each candidate's first-order effect at the current fit, from one replay with sensitivities: those not significant at 5 % cannot come near the evidence that names an effect",
        );
    }
    let total: f64 = d.stages.iter().map(|(_, s)| s).sum();
    if total > 0.0 {
        let longest = d
            .stages
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(n, s)| format!(", longest {n} {s:.1} s"))
            .unwrap_or_default();
        ui.label(egui::RichText::new(format!("took {total:.1} s{longest}")).small());
    }
}

/// What the section asks of the panel.
#[derive(Debug, Clone)]
pub enum SectionAction {
    /// Nothing.
    None,
    /// Start a diagnosis (the "Run diagnosis" button was clicked).
    Start,
    /// Replay the recording on this scene (the overlay's toggle).
    Replay(Box<Scene>),
}

/// The candidates of the first round as bars of the residual share each
/// removed, accepted ones green, with their BIC change.
fn ranking(ui: &mut egui::Ui, d: &Diagnosis) {
    let mut rows: Vec<&diagnose::Hypothesis> = d.hypotheses.iter().collect();
    if rows.is_empty() {
        return;
    }
    rows.sort_by(|a, b| {
        (a.round, a.score)
            .partial_cmp(&(b.round, b.score))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    ui.label(egui::RichText::new("candidates: share of the residual removed (BIC change)").small());
    let width = ui.available_width().clamp(120.0, 400.0);
    let row_height = 16.0;
    let (rect, _) = ui.allocate_exact_size(
        egui::vec2(width, row_height * rows.len() as f32),
        egui::Sense::hover(),
    );
    let painter = ui.painter_at(rect);
    let text = ui.visuals().text_color();
    let label_width = 0.58 * width;
    for (i, h) in rows.iter().enumerate() {
        let top = rect.top() + i as f32 * row_height;
        // A later round's candidate was fitted beside the effects found.
        let name = format!(
            "{}{}",
            if h.round > 0 { "+ " } else { "" },
            diagnose::effect_label(h.effect, &h.variant)
        );
        painter.text(
            egui::pos2(rect.left(), top + 0.5 * row_height),
            egui::Align2::LEFT_CENTER,
            name,
            egui::FontId::proportional(10.5),
            text,
        );
        let share = h.explained.clamp(0.0, 1.0) as f32;
        let accepted = d.named(h);
        let bar = egui::Rect::from_min_size(
            egui::pos2(rect.left() + label_width, top + 3.0),
            egui::vec2(
                (width - label_width - 48.0).max(10.0) * share,
                row_height - 6.0,
            ),
        );
        painter.rect_filled(bar, 1.0, if accepted { ACCEPTED } else { REJECTED });
        painter.text(
            egui::pos2(rect.right(), top + 0.5 * row_height),
            egui::Align2::RIGHT_CENTER,
            format!("{:.0} % ({:+.0})", 100.0 * share, h.score),
            egui::FontId::proportional(10.0),
            text,
        );
    }
}

/// The stages as they finish, each with its seconds (`stages`: each progress message with the
/// seconds since the start when it came; `now` the seconds so far); a candidate's fit that ends
/// inside a stage fitting several at once is listed under it.
fn stage_lines(stages: &[(String, f64)], now: f64) -> Vec<String> {
    let inside = |what: &str| what.starts_with(diagnose::FITTED);
    stages
        .iter()
        .enumerate()
        .map(|(k, (what, at))| {
            if inside(what) {
                return format!("    {what}");
            }
            let end = stages[k + 1..]
                .iter()
                .find(|(w, _)| !inside(w))
                .map(|(_, t)| *t);
            match end {
                Some(end) => format!("done: {what}, {:.1} s", end - at),
                None => format!("running: {what}, {:.0} s so far", now - at),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_candidate_fitted_inside_a_stage_is_listed_under_it_and_does_not_end_it() {
        let stages = vec![
            ("baseline".to_string(), 0.0),
            ("7 candidates, 2 at once".to_string(), 2.0),
            (
                format!("{}strain-stiffening (9.4 s)", diagnose::FITTED),
                11.5,
            ),
            ("done".to_string(), 26.0),
        ];
        let lines = stage_lines(&stages, 30.0);
        assert_eq!(lines[0], "done: baseline, 2.0 s");
        // The batch lasts until the next stage, not until its first candidate's end.
        assert_eq!(lines[1], "done: 7 candidates, 2 at once, 24.0 s");
        assert_eq!(lines[2], "    fitted: strain-stiffening (9.4 s)");
        assert_eq!(lines[3], "running: done, 4 s so far");
    }
}
