//! Background jobs of the Recording panel (a replay, a fit, a diagnosis), each on a thread of
//! its own. The UI never waits for one: each frame it reads the job's progress (atomics) and
//! polls its result (a channel of one). Each result carries the generation it was started in
//! (the panel bumps it for every recording opened), so a result of a replaced recording is
//! ignored. Stop cancels a job through its `softgrip_core::cancel` token: its simulations stop at
//! their next step, and the job shows "stopping" until its thread has ended (with
//! `LabError::Cancelled`, shown as "stopped"). A job dropped (another recording opened, the viewer closed)
//! is cancelled the same way, instead of keeping the cores busy for minutes.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, sync_channel};
use std::time::Instant;

use eframe::egui;
use softgrip_core::cancel::Cancel;
use softgrip_lab::LabError;

/// What a job's thread reports while it runs.
#[derive(Debug, Default)]
pub(crate) struct Progress {
    /// Samples replayed, or simulations of a fit, or fits of a diagnosis.
    pub(crate) done: AtomicUsize,
    /// A fit's best NRMSE so far (`f64` bits; NaN before the first).
    pub(crate) best: AtomicU64,
    /// What `done` counts up to when the job learns it as it goes (a
    /// diagnosis's fits); 0: `Job::total`.
    pub(crate) planned: AtomicUsize,
}

/// A job on a background thread: its progress and, once, its result.
pub(crate) struct Job<T> {
    generation: u64,
    pub(crate) progress: Arc<Progress>,
    /// What `done` counts up to (a fit's budget: it may stop earlier).
    pub(crate) total: usize,
    result: Receiver<(u64, Result<T, LabError>)>,
    pub(crate) started: Instant,
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
    pub(crate) fn spawn(
        name: &str,
        generation: u64,
        total: usize,
        work: impl FnOnce(&Progress) -> Result<T, LabError> + Send + 'static,
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

    /// The result, once the thread has sent it; `JobError::NoResult` if
    /// the thread ended without one (it panicked).
    pub(crate) fn poll(&self) -> Option<(u64, Result<T, JobError>)> {
        match self.result.try_recv() {
            Ok((generation, r)) => Some((generation, r.map_err(JobError::Failed))),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some((self.generation, Err(JobError::NoResult))),
        }
    }

    /// Asks the job to stop; its result (`LabError::Cancelled`) comes by `poll`.
    pub(crate) fn stop(&self) {
        self.cancel.cancel();
    }

    pub(crate) fn stopping(&self) -> bool {
        self.cancel.is_cancelled()
    }

    pub(crate) fn done(&self) -> usize {
        self.progress.done.load(Ordering::Relaxed)
    }

    pub(crate) fn best(&self) -> f64 {
        f64::from_bits(self.progress.best.load(Ordering::Relaxed))
    }
}

/// A job's progress bar with a Stop button beside it, which stops the
/// job (the bar then says so until its thread has ended).
pub(crate) fn progress_with_stop<T: Send + 'static>(
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

/// Why a job gave no result.
#[derive(Debug)]
pub(crate) enum JobError {
    /// The work's own error.
    Failed(LabError),
    /// The thread ended without a result (it panicked).
    NoResult,
}

/// A job's error in words: "stopped" for a cancelled one, else `failed`
/// and the error.
pub(crate) fn job_error(failed: &str, e: &JobError) -> String {
    match e {
        JobError::Failed(LabError::Cancelled) => format!("{failed}: stopped"),
        JobError::Failed(e) => format!("{failed}: {e}"),
        JobError::NoResult => {
            format!("{failed}: the background thread stopped without a result")
        }
    }
}
