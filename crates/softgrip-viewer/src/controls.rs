//! The run controls at the top of the left panel: Play or Pause, Step, Reset, and the speed
//! (a multiple of real time, or as fast as the solver goes).

use eframe::egui;
use softgrip_core::live::Command;

/// The speed chosen.
pub(crate) struct RunControls {
    /// Simulated seconds per second of wall time.
    speed: f64,
    /// As fast as the solver goes (`speed` then waits).
    max_speed: bool,
}

impl Default for RunControls {
    fn default() -> RunControls {
        RunControls {
            speed: 1.0,
            max_speed: false,
        }
    }
}

impl RunControls {
    /// The buttons and the speed; `running` chooses Pause over Play, and
    /// what the user asks goes to `send`.
    pub(crate) fn ui(&mut self, ui: &mut egui::Ui, running: bool, send: &dyn Fn(Command)) {
        ui.horizontal(|ui| {
            if running {
                if ui.button("Pause").clicked() {
                    send(Command::Pause);
                }
            } else if ui.button("Play").clicked() {
                send(Command::Play);
            }
            if ui.button("Step").clicked() {
                send(Command::Step(1));
            }
            if ui.button("Reset").clicked() {
                send(Command::Reset);
            }
        });
        let mut speed_changed = ui
            .checkbox(&mut self.max_speed, "as fast as it goes")
            .changed();
        ui.add_enabled_ui(!self.max_speed, |ui| {
            speed_changed |= ui
                .add(
                    egui::Slider::new(&mut self.speed, 0.01..=10.0)
                        .logarithmic(true)
                        .text("x real time"),
                )
                .changed();
        });
        if speed_changed {
            send(Command::SetSpeed((!self.max_speed).then_some(self.speed)));
        }
    }
}
