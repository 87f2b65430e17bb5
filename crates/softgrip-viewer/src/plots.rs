//! The right panel's plots: each finger's depth and normal force over time, from the solver's
//! history, with a grid whose values egui_plot prints (`crate::plot_grid`).

use eframe::egui;
use softgrip_core::live::{FingerSample, Frame};

use crate::plot_grid;

/// Finger depth and contact force over time, from the solver's history.
pub(crate) fn ui(ui: &mut egui::Ui, frame: Option<&Frame>) {
    let Some(f) = frame else {
        return;
    };
    let series = |pick: fn(&FingerSample) -> f64| {
        f.history
            .iter()
            .map(|samples| {
                samples
                    .iter()
                    .map(|s| [s.time, pick(s)])
                    .collect::<Vec<[f64; 2]>>()
            })
            .collect::<Vec<_>>()
    };
    for (title, unit, lines) in [
        ("depth", "mm", series(|s| s.depth * 1e3)),
        ("normal force", "N", series(|s| s.normal_force)),
    ] {
        ui.label(format!("{title} ({unit})"));
        // Zero and some room above the largest value: a steady line
        // would otherwise sit on the frame with no value beside it.
        let top = lines
            .iter()
            .flatten()
            .map(|p| p[1])
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        plot_grid::with_grids(egui_plot::Plot::new(title))
            .height(140.0)
            .include_y(0.0)
            .include_y(top * 1.2)
            .x_axis_label("time (s)")
            .show(ui, |plot| {
                for (k, points) in lines.into_iter().enumerate() {
                    plot.line(egui_plot::Line::new(format!("finger {}", k + 1), points));
                }
            });
    }
}
