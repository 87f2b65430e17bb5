//! The Material section: the object's Young's modulus, Poisson's ratio, density and edge length
//! (which re-meshes), and the time step.

use eframe::egui;
use softgrip_core::scene::Scene;

use crate::widgets::{linear, log_scale, log_slider, sliders};

/// The section; true if the user changed `s`.
pub(super) fn ui(ui: &mut egui::Ui, s: &mut Scene) -> bool {
    let mut changed = false;
    egui::CollapsingHeader::new("Material")
        .default_open(true)
        .show(ui, |ui| {
            let o = &mut s.object;
            changed |= sliders(
                ui,
                [
                    log_scale(&mut o.young_modulus, 1e3..=1e8, "E (Pa)"),
                    linear(&mut o.poisson_ratio, 0.0..=0.499, "nu"),
                    linear(&mut o.density, 100.0..=3000.0, "density (kg/m3)"),
                ],
            );
            // Re-meshing is costly: sent when the slider is let go.
            let edge = ui.add(
                egui::Slider::new(&mut o.edge_length, 0.001..=0.02)
                    .logarithmic(true)
                    .text("edge length (m), re-meshes"),
            );
            changed |= edge.drag_stopped() || (edge.changed() && !edge.dragged());
            changed |= log_slider(ui, &mut s.simulation.dt, 1e-5..=1e-2, "dt (s)");
        });
    changed
}
