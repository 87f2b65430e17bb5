//! The Model section: the terms of the mass-spring-damper model and its extensions (Rayleigh
//! damping, limits, stiffening, asymmetry, viscoelasticity, bulk pressure, elasticity law,
//! self-collision).

use eframe::egui;
use softgrip_core::scene::{BulkPressure, Elasticity, ModelParams};

use crate::widgets::{linear, log_scale, log_slider, optional_slider, radios, slider, sliders};

/// The section; true if the user changed `m`.
pub(super) fn ui(ui: &mut egui::Ui, m: &mut ModelParams) -> bool {
    let mut changed = false;
    egui::CollapsingHeader::new("Model")
        .default_open(true)
        .show(ui, |ui| {
            changed |= springs_and_damping(ui, m);
            changed |= extensions(ui, m);
            changed |= choices(ui, m);
        });
    changed
}

/// The thesis's terms: the volume-preservation scale alpha, the springs' limits, the damping
/// (ratio and Rayleigh) and the limits' iterations; true if the user changed one.
fn springs_and_damping(ui: &mut egui::Ui, m: &mut ModelParams) -> bool {
    let mut changed = false;
    changed |= log_slider(ui, &mut m.alpha, 0.0..=1e8, "alpha");
    changed |= optional_slider(ui, &mut m.tau_s, 0.0..=1.0, "tau_s", 0.16);
    changed |= optional_slider(ui, &mut m.tau_c, 0.0..=0.9, "tau_c", 0.155);
    changed |= slider(ui, &mut m.damping_ratio, 0.0..=5.0, "damping ratio");
    // Rayleigh damping a M + b K (`forces::viscosity`).
    changed |= sliders(
        ui,
        [
            log_scale(&mut m.rayleigh_mass, 0.0..=1e3, "Rayleigh a (1/s)"),
            log_scale(&mut m.rayleigh_stiffness, 0.0..=0.1, "Rayleigh b (s)"),
        ],
    );
    changed |= slider(
        ui,
        &mut m.constraint_iterations,
        0..=100,
        "constraint iterations",
    );
    changed
}

/// The extensions' terms: bulk modulus, limit stiffness, stiffening (and the elements' Yeoh
/// law), compression / tension asymmetry and viscoelasticity; true if the user changed one.
fn extensions(ui: &mut egui::Ui, m: &mut ModelParams) -> bool {
    let mut changed = false;
    changed |= sliders(
        ui,
        [
            log_scale(&mut m.bulk_modulus, 0.0..=1e8, "bulk modulus (Pa)"),
            log_scale(&mut m.limit_stiffness, 0.0..=1e5, "limit stiffness (x)"),
            log_scale(&mut m.stiffening, 0.0..=1e5, "stiffening"),
        ],
    );
    if m.elasticity == Elasticity::NeoHookean {
        // The elements' two-term Yeoh law (`forces::fem`).
        changed |= sliders(
            ui,
            [
                log_scale(
                    &mut m.stiffening_cubic,
                    0.0..=1e5,
                    "stiffening, cubic (elements)",
                ),
                linear(&mut m.softening, 0.0..=0.99, "early softening (elements)"),
            ],
        );
    }
    changed |= sliders(
        ui,
        [
            log_scale(
                &mut m.compression_ratio,
                0.05..=20.0,
                "compression / tension stiffness",
            ),
            linear(
                &mut m.prony_g,
                0.0..=0.95,
                "viscoelastic g (relaxing share)",
            ),
            log_scale(&mut m.prony_tau, 1e-3..=1e3, "viscoelastic tau (s)"),
        ],
    );
    changed
}

/// Bulk pressure per element or per node, the elasticity law and self-collision; true if the
/// user changed one.
fn choices(ui: &mut egui::Ui, m: &mut ModelParams) -> bool {
    let mut changed = false;
    changed |= radios(
        ui,
        Some("bulk pressure"),
        &mut m.bulk_pressure,
        &[
            (BulkPressure::Element, "per element"),
            (BulkPressure::Nodal, "per node"),
        ],
    );
    changed |= radios(
        ui,
        Some("elasticity"),
        &mut m.elasticity,
        &[
            (Elasticity::Springs, "springs"),
            (Elasticity::NeoHookean, "neo-Hookean FEM"),
        ],
    );
    changed |= ui
        .checkbox(&mut m.self_collision, "self-collision")
        .changed();
    changed
}
