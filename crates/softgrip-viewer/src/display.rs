//! The Display section: how the 3-D view draws (arrows, finger opacity, contacts, the field
//! coloured, surface and springs, a cut-away) and the preset camera views.

use eframe::egui;

use crate::render::{Cut, Style, View};

/// The section (closed at first); a preset view pressed goes to
/// `view_request`.
pub(crate) fn ui(ui: &mut egui::Ui, st: &mut Style, view_request: &mut Option<View>) {
    egui::CollapsingHeader::new("Display").show(ui, |ui| {
        ui.add(
            egui::Slider::new(&mut st.force_scale, 1e-4..=1e-2)
                .logarithmic(true)
                .text("arrow m per N"),
        );
        ui.add(egui::Slider::new(&mut st.finger_opacity, 0.1..=1.0).text("finger opacity"));
        ui.checkbox(&mut st.contacts, "contact points");
        ui.checkbox(&mut st.arrows, "force arrows");
        egui::ComboBox::from_label("colour by")
            .selected_text(st.color_by.map_or("nothing", |f| f.label()))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut st.color_by, None, "nothing");
                for field in softgrip_core::fields::Field::ALL {
                    ui.selectable_value(&mut st.color_by, Some(field), field.label());
                }
            });
        ui.horizontal(|ui| {
            ui.checkbox(&mut st.surface, "surface");
            ui.checkbox(&mut st.wireframe, "springs (wireframe)");
        });
        cut_away(ui, &mut st.cut);
        ui.horizontal(|ui| {
            if ui
                .button("reset view")
                .on_hover_text("back to the opening view, framing the object")
                .clicked()
            {
                *view_request = Some(View::Iso);
            }
            for (name, view) in [
                ("front", View::Front),
                ("side", View::Side),
                ("top", View::Top),
                ("iso", View::Iso),
            ] {
                if ui.button(name).clicked() {
                    *view_request = Some(view);
                }
            }
        });
    });
}

/// The cut-away: on or off, its axis, side and place.
fn cut_away(ui: &mut egui::Ui, cut_style: &mut Option<Cut>) {
    let mut cut = cut_style.is_some();
    let mut c = cut_style.unwrap_or(Cut {
        axis: 1,
        fraction: 0.5,
        flip: false,
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut cut, "cut-away along");
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            ui.radio_value(&mut c.axis, axis, *name);
        }
        ui.checkbox(&mut c.flip, "flip");
    });
    ui.add_enabled(
        cut,
        egui::Slider::new(&mut c.fraction, 0.0..=1.0).text("cut at (fraction)"),
    );
    *cut_style = cut.then_some(c);
}
