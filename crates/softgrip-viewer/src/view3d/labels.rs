//! What the 3-D view paints over its picture: the colour map's legend, the recording's caption
//! and colour key, the hint at the bottom (what a drag does, or why it does nothing), and a
//! spinner while the solver re-meshes.

use eframe::egui;

use super::input::Drag;
use crate::render::{self, Legend};
use softgrip_core::live::{Frame, RunState};

/// What the 3-D view shows while a recording is shown, and its colours'
/// key, at the view's top left.
pub(super) fn draw_recording_caption(ui: &egui::Ui, view: egui::Rect, caption: &str) {
    let painter = ui.painter();
    let color = |c: [f32; 4]| egui::Rgba::from_rgb(c[0], c[1], c[2]);
    let top = view.left_top() + egui::vec2(10.0, 10.0);
    painter.text(
        top,
        egui::Align2::LEFT_TOP,
        caption,
        egui::FontId::proportional(14.0),
        egui::Color32::from_gray(30),
    );
    let mut at = top + egui::vec2(6.0, 28.0);
    for (c, text) in [
        (render::markers::RECORDED, "recorded"),
        (render::markers::SIMULATED, "simulated"),
        (render::markers::RESIDUAL, "residual"),
    ] {
        painter.circle_filled(at, 5.0, color(c));
        let label = painter.text(
            at + egui::vec2(10.0, 0.0),
            egui::Align2::LEFT_CENTER,
            text,
            egui::FontId::proportional(13.0),
            egui::Color32::from_gray(40),
        );
        at.x = label.right() + 18.0;
    }
}

/// The colour map's bar at the right of the 3-D view, with its range and
/// the field's name and unit.
pub(super) fn draw_legend(ui: &egui::Ui, view: egui::Rect, legend: &Legend) {
    const STEPS: usize = 48;
    let painter = ui.painter();
    let height = (view.height() * 0.5).clamp(80.0, 320.0);
    let bar = egui::Rect::from_min_size(
        egui::pos2(view.right() - 90.0, view.top() + 40.0),
        egui::vec2(16.0, height),
    );
    for k in 0..STEPS {
        // Top is the maximum.
        let t = 1.0 - (k as f64 + 0.5) / STEPS as f64;
        let [r, g, b, _] = legend.color(legend.min + t * (legend.max - legend.min));
        let y0 = bar.top() + bar.height() * k as f32 / STEPS as f32;
        let y1 = bar.top() + bar.height() * (k + 1) as f32 / STEPS as f32;
        painter.rect_filled(
            egui::Rect::from_x_y_ranges(bar.x_range(), y0..=y1 + 0.5),
            0.0,
            egui::Rgba::from_rgb(r, g, b),
        );
    }
    painter.rect_stroke(
        bar,
        0.0,
        egui::Stroke::new(1.0, egui::Color32::from_gray(60)),
        egui::StrokeKind::Outside,
    );
    let field = legend.field;
    let k = field.display_scale();
    let text = |y: f32, value: f64| {
        painter.text(
            egui::pos2(bar.right() + 4.0, y),
            egui::Align2::LEFT_CENTER,
            format!("{:.3}", value * k),
            egui::FontId::monospace(11.0),
            egui::Color32::from_gray(40),
        );
    };
    text(bar.top(), legend.max);
    text(bar.center().y, 0.5 * (legend.min + legend.max));
    text(bar.bottom(), legend.min);
    painter.text(
        egui::pos2(bar.right() + 4.0, bar.top() - 18.0),
        egui::Align2::RIGHT_BOTTOM,
        format!("{} ({})", field.label(), field.unit()),
        egui::FontId::proportional(12.0),
        egui::Color32::from_gray(40),
    );
}

/// The hint at the view's bottom left, wrapped to the view's width: what a
/// drag does, or why it does nothing now.
pub(super) fn draw_hint(ui: &egui::Ui, rect: egui::Rect, f: &Frame, recording: bool, drag: Drag) {
    let hint = if recording {
        "showing the recording (untick \"show recording\" for the live run) | drag: orbit | right-drag: pan | scroll: zoom".to_string()
    } else if f.run == RunState::Paused && drag != Drag::None {
        "paused: press Play to see the drag act".to_string()
    } else if let Drag::Finger { index, .. } = drag
        && let Some(locked) = f
            .scene
            .fingers
            .get(index)
            .and_then(|s| locked_axes_hint(index, s.free_axes))
    {
        locked
    } else {
        "drag: finger moves, object is pulled, elsewhere orbits | right-drag: pan | scroll: zoom"
            .to_string()
    };
    // Wrapped to the view's width: a narrow view keeps the whole hint.
    let galley = ui.painter().layout(
        hint,
        egui::FontId::proportional(12.0),
        egui::Color32::from_gray(90),
        (rect.width() - 16.0).max(40.0),
    );
    let at = rect.left_bottom() + egui::vec2(8.0, -8.0 - galley.size().y);
    ui.painter()
        .galley(at, galley, egui::Color32::from_gray(90));
}

/// While the solver re-meshes, the old model stays drawn under a spinner,
/// with the new edge length and how long it has taken so far (`since`).
pub(super) fn draw_meshing(
    ui: &mut egui::Ui,
    rect: egui::Rect,
    f: &Frame,
    since: std::time::Instant,
) {
    let spinner = egui::Rect::from_center_size(rect.center(), egui::vec2(40.0, 40.0));
    ui.put(spinner, egui::Spinner::new().size(40.0));
    ui.painter().text(
        rect.center() + egui::vec2(0.0, 36.0),
        egui::Align2::CENTER_TOP,
        format!(
            "re-meshing at {:.2} mm edge length... {:.1} s",
            1e3 * f.scene.object.edge_length,
            since.elapsed().as_secs_f64()
        ),
        egui::FontId::proportional(18.0),
        egui::Color32::DARK_GRAY,
    );
}

/// While a finger with a locked axis is dragged: which way it can move and
/// where to free the others (a scene's `free_axes`; the thesis's finger
/// moves along z only, so a sideways drag alone does nothing).
fn locked_axes_hint(index: usize, free: [bool; 3]) -> Option<String> {
    if free.iter().all(|f| *f) {
        return None;
    }
    let names = |want: bool| {
        ["x", "y", "z"]
            .into_iter()
            .zip(free)
            .filter(|(_, f)| *f == want)
            .map(|(n, _)| n)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let finger = index + 1;
    Some(if free.iter().any(|f| *f) {
        format!(
            "finger {finger} moves along {} only: tick \"along {}\" under Fingers",
            names(true),
            names(false).replace(", ", "\" or \"along ")
        )
    } else {
        format!("finger {finger} has every axis locked: tick its \"along\" boxes under Fingers")
    })
}
