//! The replayed recording's samples: whether the 3-D view shows them, the sample slider, the
//! exaggeration of the residuals, the errors and the plot of the RMS residual per sample.

use eframe::egui;

use super::replayed::Replayed;
use crate::plot_grid;

/// The sample slider, the errors and the residual plot; `sample` counts
/// from 0.
pub(super) fn ui(
    ui: &mut egui::Ui,
    replayed: &Replayed,
    show: &mut bool,
    sample: &mut usize,
    exaggerate: &mut f64,
) {
    let n = replayed.recording.samples.len();
    ui.checkbox(show, "show recording")
        .on_hover_text("the 3-D view shows the replayed sample instead of the live run");
    let mut k = *sample + 1;
    ui.add_enabled(
        n > 1,
        egui::Slider::new(&mut k, 1..=n.max(1)).text("sample"),
    );
    *sample = k.clamp(1, n.max(1)) - 1;
    ui.label(format!(
        "sample {}/{n}: {}",
        *sample + 1,
        replayed.sample_label(*sample)
    ));
    ui.add(
        egui::Slider::new(exaggerate, 1.0..=100.0)
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
    let rms = replayed.sample_rms.get(*sample).copied().unwrap_or(0.0);
    ui.label(format!("this sample: RMS residual {:.3} mm", 1e3 * rms));
    ui.label(egui::RichText::new("RMS residual per sample (mm)").small());
    let points: Vec<[f64; 2]> = replayed
        .sample_rms
        .iter()
        .enumerate()
        .map(|(i, r)| [(i + 1) as f64, 1e3 * r])
        .collect();
    let current = (*sample + 1) as f64;
    plot_grid::with_grids(egui_plot::Plot::new("residual per sample"))
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
