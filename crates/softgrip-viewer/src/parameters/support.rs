//! The Support section: what holds the object (a fixed bottom, a table with its friction, or
//! nothing).

use eframe::egui;
use softgrip_core::scene::{Support, SupportKind};

use crate::widgets::{radios, slider};

/// The section (closed at first); true if the user changed `support`.
pub(super) fn ui(ui: &mut egui::Ui, support: &mut Support) -> bool {
    let mut changed = false;
    egui::CollapsingHeader::new("Support")
        .default_open(false)
        .show(ui, |ui| {
            changed |= radios(
                ui,
                None,
                &mut support.kind,
                &[
                    (SupportKind::FixedBottom, "fixed bottom"),
                    (SupportKind::Table, "table"),
                    (SupportKind::None, "none"),
                ],
            );
            ui.add_enabled_ui(support.kind == SupportKind::Table, |ui| {
                changed |= slider(ui, &mut support.friction, 0.0..=2.0, "table friction");
            });
        });
    changed
}
