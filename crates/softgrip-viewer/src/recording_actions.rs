//! What the Recording panel asks of the live run: a recording opened replaces the run's scene
//! with its own, a replay on the scene the panels show, fitted values applied to the run; and
//! the run's pause while a fit or a diagnosis takes the cores.

use std::path::PathBuf;

use softgrip_core::live::{Command, RunState};

use crate::Panels;
use crate::recording;

impl Panels {
    /// Opens a lab recording: its scene replaces the run's (as opening
    /// the scene file would) and its replay starts on a background
    /// thread. A recording that does not load shows its error in the
    /// Recording panel and leaves the run and any recording open as they
    /// were.
    pub fn open_recording(&mut self, path: PathBuf) {
        match softgrip_lab::recording::Recording::load(&path) {
            Ok(recording) => {
                self.file_error = None;
                self.edited = recording.scene.clone();
                self.send(Command::SetScene(Box::new(recording.scene.clone())));
                self.recording.open(recording);
            }
            Err(e) => self.recording.failed(&path, e),
        }
    }

    /// A fit or a diagnosis wants the cores the live run (and its drawing)
    /// would take: the run waits while one goes on (a diagnosis from the
    /// viewer took two and a half times the CLI's beside a running scene on
    /// a 2-core machine) and plays again when it ends, unless the user
    /// played it meanwhile (they may: the note says how).
    pub(crate) fn pause_for_long_jobs(&mut self) {
        let long =
            self.recording.fitting() || self.recording.diagnosis.running() || self.grasp.busy();
        let run = self.frame.as_ref().map(|f| f.run);
        if long && !self.paused_for_job && run == Some(RunState::Running) {
            self.send(Command::Pause);
            self.paused_for_job = true;
        } else if !long && self.paused_for_job {
            self.paused_for_job = false;
            if run == Some(RunState::Paused) {
                self.send(Command::Play);
            }
        }
    }

    /// Does what the Recording panel asks.
    pub(crate) fn recording_action(&mut self, action: recording::Action) {
        match action {
            recording::Action::Open(path) => self.open_recording(path),
            recording::Action::ReplayEdited => self.recording.replay_on(self.edited.clone()),
            recording::Action::Apply(values) => {
                // As the sliders do: the edited scene, checked by the
                // scene file's rules, sent to the solver.
                let mut scene = self.edited.clone();
                for (name, v) in &values {
                    match softgrip_lab::params::set(&scene, name, *v) {
                        Ok(s) => scene = s,
                        Err(e) => {
                            self.recording.error =
                                Some(format!("cannot apply the fitted {name}: {e}"));
                            return;
                        }
                    }
                }
                self.edited = scene.clone();
                self.send(Command::SetScene(Box::new(scene)));
                self.recording.replay_fitted(&values);
            }
        }
    }
}
