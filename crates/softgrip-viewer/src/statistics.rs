//! The right panel's figures: the run's state, the UI's frame time, the solver's speed and its
//! convergence, energy and contacts, and each finger's forces and depth.

use eframe::egui;
use softgrip_core::live::Frame;

/// The table; `frame_time` is the UI's (s, smoothed).
pub(crate) fn ui(ui: &mut egui::Ui, frame: Option<&Frame>, frame_time: f64) {
    let Some(f) = frame else {
        ui.label("starting...");
        return;
    };
    let st = &f.state.stats;
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        let mut row = |name: &str, value: String| {
            ui.label(name);
            ui.monospace(value);
            ui.end_row();
        };
        row("state", format!("{:?}", f.run));
        row("UI frame", format!("{:.1} ms", 1e3 * frame_time));
        row("time", format!("{:.3} s", f.state.time));
        row("steps/s", format!("{:.0}", f.steps_per_second));
        row("x real time", format!("{:.2}", f.realtime_factor));
        row("CG iterations", format!("{}", st.cg_iterations));
        row("CG residual", format!("{:.1e}", st.cg_residual));
        row("volume error", format!("{:.2e}", st.volume_error));
        row("energy", format!("{:.4e} J", st.energy));
        row("limit violation", format!("{:.1e}", st.limit_violation));
        row("contacts", format!("{}", st.contacts));
        for (k, fs) in f.state.fingers.iter().enumerate() {
            let depth = f
                .history
                .get(k)
                .and_then(|h| h.last())
                .map_or(0.0, |s| s.depth);
            row(
                &format!("finger {}", k + 1),
                format!(
                    "Fn {:.3} N, Ft {:.3} N, depth {:.3} mm",
                    fs.normal_force,
                    fs.tangential_force.length(),
                    depth * 1e3
                ),
            );
        }
    });
}
