//! Small pieces the panels share: the colour of errors, the parameter sections' sliders (linear,
//! over a log scale, or with an off switch for a limit that may be absent) and radio buttons.

use eframe::egui;

/// An error's colour (a file that would not open, a job that failed).
pub(crate) const ERROR_RED: egui::Color32 = egui::Color32::from_rgb(200, 40, 40);

/// A slider; true if the user changed `value`.
pub(crate) fn slider<N: egui::emath::Numeric>(
    ui: &mut egui::Ui,
    value: &mut N,
    range: std::ops::RangeInclusive<N>,
    text: &str,
) -> bool {
    ui.add(egui::Slider::new(value, range).text(text)).changed()
}

/// A row of a radio button per choice, after `label` if any; true if the
/// user changed `value`.
pub(crate) fn radios<T: PartialEq + Copy>(
    ui: &mut egui::Ui,
    label: Option<&str>,
    value: &mut T,
    choices: &[(T, &str)],
) -> bool {
    ui.horizontal(|ui| {
        if let Some(label) = label {
            ui.label(label);
        }
        let mut changed = false;
        for &(choice, name) in choices {
            changed |= ui.radio_value(value, choice, name).changed();
        }
        changed
    })
    .inner
}

/// A row of [`sliders`]: the value, its range and label, and whether
/// the scale is logarithmic.
pub(crate) struct Row<'a> {
    value: &'a mut f64,
    range: Range,
    text: &'a str,
    log: bool,
}

/// A slider's range.
type Range = std::ops::RangeInclusive<f64>;

/// A row of [`sliders`] on a linear scale.
pub(crate) fn linear<'a>(value: &'a mut f64, range: Range, text: &'a str) -> Row<'a> {
    Row {
        value,
        range,
        text,
        log: false,
    }
}

/// A row of [`sliders`] on a log scale.
pub(crate) fn log_scale<'a>(value: &'a mut f64, range: Range, text: &'a str) -> Row<'a> {
    Row {
        log: true,
        ..linear(value, range, text)
    }
}

/// A slider per row, top to bottom; true if the user changed any value.
pub(crate) fn sliders<const N: usize>(ui: &mut egui::Ui, rows: [Row<'_>; N]) -> bool {
    let mut changed = false;
    for row in rows {
        changed |= if row.log {
            log_slider(ui, row.value, row.range, row.text)
        } else {
            slider(ui, row.value, row.range, row.text)
        };
    }
    changed
}

/// A slider over a log scale; true if the user changed `value`.
pub(crate) fn log_slider(
    ui: &mut egui::Ui,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
) -> bool {
    ui.add(egui::Slider::new(value, range).logarithmic(true).text(text))
        .changed()
}

/// A limit that may be off (`None`: the key omitted).
pub(crate) fn optional_slider(
    ui: &mut egui::Ui,
    value: &mut Option<f64>,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
    default: f64,
) -> bool {
    let mut on = value.is_some();
    let mut changed = false;
    ui.horizontal(|ui| {
        changed |= ui
            .checkbox(&mut on, "on")
            .on_hover_text(format!("{text}: off means no limit"))
            .changed();
        let mut v = value.unwrap_or(default);
        ui.add_enabled_ui(on, |ui| {
            changed |= ui
                .add(egui::Slider::new(&mut v, range).text(text))
                .changed();
        });
        *value = on.then_some(v);
    });
    changed
}
