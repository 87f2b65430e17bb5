//! The scene's parameter sections of the left panel, in their order: the object's material, the
//! model's terms, the support and the fingers. Each edits the scene the panels show and says
//! whether the user changed it; the panels then send the scene to the solver.

mod fingers;
mod material;
mod model;
mod support;

use eframe::egui;
use softgrip_core::live::Frame;
use softgrip_core::scene::Scene;

/// The parameter sections; true if the user changed `scene`. `frame`
/// places a finger added.
pub(crate) fn ui(ui: &mut egui::Ui, scene: &mut Scene, frame: Option<&Frame>) -> bool {
    let mut changed = material::ui(ui, scene);
    changed |= model::ui(ui, &mut scene.model);
    changed |= support::ui(ui, &mut scene.support);
    changed |= fingers::ui(ui, scene, frame);
    changed
}
