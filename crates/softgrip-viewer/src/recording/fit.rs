//! The Fit section of the Recording panel: the parameters to fit, a fit of the open recording on
//! a background thread (`softgrip-fit`) with its progress, the fitted values with their standard
//! errors and verdicts, and Apply, which the panel hands on to the live run.

use std::sync::Arc;
use std::sync::atomic::Ordering;

use eframe::egui;

use crate::jobs::{Job, job_error, progress_with_stop};
use softgrip_lab::LabError;
use softgrip_lab::fit::{Fit, FitOptions, FitParam, default_bounds, fit};
use softgrip_lab::params;
use softgrip_lab::recording::Recording;

/// The parameters the Fit section offers: the thesis's four.
pub const FIT_PARAMS: [&str; 4] = ["young_modulus", "alpha", "tau_s", "tau_c"];

/// A fit that finished, and the recording it fitted.
pub struct Fitted {
    /// The recording fitted.
    pub recording: Arc<Recording>,
    /// The fit: the fitted values, their standard errors and verdicts.
    pub fit: Fit,
}

/// The section's state: the parameters chosen, the running fit and the
/// last one finished.
pub(super) struct FitSection {
    choice: [bool; 4],
    job: Option<Job<Fitted>>,
    fitted: Option<Arc<Fitted>>,
}

impl Default for FitSection {
    fn default() -> FitSection {
        FitSection {
            choice: [true, false, false, false],
            job: None,
            fitted: None,
        }
    }
}

impl FitSection {
    pub(super) fn fitting(&self) -> bool {
        self.job.is_some()
    }

    pub(super) fn fitted(&self) -> Option<&Arc<Fitted>> {
        self.fitted.as_ref()
    }

    /// Chooses whether `FIT_PARAMS[k]` is fitted.
    pub(super) fn choose(&mut self, k: usize, on: bool) {
        if let Some(c) = self.choice.get_mut(k) {
            *c = on;
        }
    }

    /// Drops the running fit and the last one (a new recording was
    /// opened); the parameters chosen stay.
    pub(super) fn clear(&mut self) {
        self.job = None;
        self.fitted = None;
    }

    /// Starts fitting the chosen parameters to `recording`; what goes
    /// wrong goes to `error`.
    fn start(
        &mut self,
        recording: Option<&Arc<Recording>>,
        generation: u64,
        error: &mut Option<String>,
    ) {
        let Some(recording) = recording.cloned() else {
            return;
        };
        let chosen: Result<Vec<FitParam>, LabError> = FIT_PARAMS
            .iter()
            .zip(self.choice)
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
                *error = Some("choose at least one parameter to fit".into());
                return;
            }
            Ok(p) => p,
            Err(e) => {
                *error = Some(format!("cannot fit: {e}"));
                return;
            }
        };
        *error = None;
        self.fitted = None;
        let options = FitOptions::default();
        let total = options.max_evaluations + 4 * params.len();
        let job = Job::spawn("softgrip-fit", generation, total, move |progress| {
            let report = |n: usize, best: f64| {
                progress.done.store(n, Ordering::Relaxed);
                progress.best.store(best.to_bits(), Ordering::Relaxed);
            };
            let fit = fit(&recording, &params, options, &report)?;
            Ok(Fitted { recording, fit })
        });
        match job {
            Ok(job) => self.job = Some(job),
            Err(e) => *error = Some(e),
        }
    }

    /// Takes the finished fit (if it is of `generation`); its failure goes
    /// to `error`.
    pub(super) fn poll(&mut self, generation: u64, error: &mut Option<String>) {
        if let Some((g, result)) = self.job.as_ref().and_then(Job::poll) {
            self.job = None;
            if g == generation {
                match result {
                    Ok(fitted) => self.fitted = Some(Arc::new(fitted)),
                    Err(e) => *error = Some(job_error("the fit", &e)),
                }
            }
        }
    }

    /// The fit: parameters, Run, progress, results and Apply; the values
    /// to apply when Apply was pressed.
    pub(super) fn ui(
        &mut self,
        ui: &mut egui::Ui,
        recording: Option<&Arc<Recording>>,
        generation: u64,
        error: &mut Option<String>,
    ) -> Option<Vec<(&'static str, f64)>> {
        let mut apply = None;
        egui::CollapsingHeader::new("Fit...").show(ui, |ui| {
            let scene = recording.map(|r| r.scene.clone());
            for (k, name) in FIT_PARAMS.iter().enumerate() {
                let bounds = scene
                    .as_ref()
                    .map(|s| params::find(name).and_then(|p| default_bounds(p, s).map(|b| (p, b))));
                let hint = match &bounds {
                    Some(Ok((p, (lo, hi)))) => {
                        format!("fitted in [{lo:.3e}, {hi:.3e}] {}", p.unit)
                    }
                    Some(Err(e)) => e.to_string(),
                    None => String::new(),
                };
                ui.checkbox(&mut self.choice[k], *name).on_hover_text(hint);
            }
            let running = self.job.is_some();
            if ui
                .add_enabled(!running, egui::Button::new("Run fit"))
                .on_hover_text("minimise NRMSE over the chosen parameters (background thread)")
                .clicked()
            {
                self.start(recording, generation, error);
            }
            if let Some(job) = &self.job {
                progress(ui, job);
            }
            if let Some(fitted) = self.fitted.clone() {
                apply = results(ui, &fitted.fit);
            }
        });
        apply
    }
}

/// The running fit's progress bar, with its Stop button, and the best
/// NRMSE so far.
fn progress(ui: &mut egui::Ui, job: &Job<Fitted>) {
    let done = job.done();
    let bar =
        egui::ProgressBar::new((done as f32 / job.total.max(1) as f32).min(1.0)).text(format!(
            "fitting: {done} simulations, {:.0} s",
            job.started.elapsed().as_secs_f64()
        ));
    let best = job.best();
    progress_with_stop(ui, job, bar);
    if best.is_finite() {
        ui.label(format!("best NRMSE so far {best:.4}"));
    }
}

/// The fitted values with their standard errors and verdicts, the NRMSE
/// before and after, and Apply; the values to apply when it was pressed.
fn results(ui: &mut egui::Ui, f: &Fit) -> Option<Vec<(&'static str, f64)>> {
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
    ui.button("Apply fitted values")
        .on_hover_text("set them in the live run and replay the recording with them")
        .clicked()
        .then(|| {
            f.params
                .iter()
                .zip(&f.fitted)
                .map(|(p, v)| (p.param.name, *v))
                .collect()
        })
}

/// Four significant digits, the way the fit's values are shown.
pub fn fitted_value(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4e}")
    } else {
        "inf".into()
    }
}
