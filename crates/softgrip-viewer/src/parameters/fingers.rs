//! The Fingers section: per finger its control (force or velocity), the axes it moves along, its
//! load, shape, friction, mass and contact terms, with Remove; and Add finger.

use eframe::egui;
use softgrip_core::live::Frame;
use softgrip_core::scene::{Control, Finger, FingerShape, Scene};

use crate::widgets::{linear, log_scale, radios, slider, sliders};

/// The section; true if the user changed `s` (its fingers). `frame`
/// places a finger added.
pub(super) fn ui(ui: &mut egui::Ui, s: &mut Scene, frame: Option<&Frame>) -> bool {
    let mut changed = false;
    egui::CollapsingHeader::new("Fingers")
        .default_open(true)
        .show(ui, |ui| {
            let mut remove = None;
            for (k, f) in s.fingers.iter_mut().enumerate() {
                ui.push_id(k, |ui| {
                    ui.horizontal(|ui| {
                        ui.label(format!("finger {}", k + 1));
                        if ui.small_button("remove").clicked() {
                            remove = Some(k);
                        }
                    });
                    changed |= finger(ui, f);
                });
                ui.separator();
            }
            if let Some(k) = remove {
                s.fingers.remove(k);
                changed = true;
            }
            if ui.button("Add finger").clicked() {
                s.fingers.push(new_finger(s, frame));
                changed = true;
            }
        });
    changed
}

/// One finger's widgets below its title; true if the user changed `f`.
fn finger(ui: &mut egui::Ui, f: &mut Finger) -> bool {
    let mut changed = radios(
        ui,
        None,
        &mut f.control,
        &[(Control::Force, "force"), (Control::Velocity, "velocity")],
    );
    ui.horizontal(|ui| {
        ui.label("moves along");
        for (a, name) in ["x", "y", "z"].into_iter().enumerate() {
            changed |= ui
                .checkbox(&mut f.free_axes[a], format!("along {name}"))
                .changed();
        }
    });
    changed |= sliders(
        ui,
        [
            linear(&mut f.force.z, -50.0..=50.0, "force z (N)"),
            linear(&mut f.velocity.z, -0.05..=0.05, "velocity z (m/s)"),
        ],
    );
    if let FingerShape::Sphere { radius } = &mut f.shape {
        changed |= slider(ui, radius, 0.001..=0.05, "radius (m)");
    }
    changed |= sliders(
        ui,
        [
            linear(&mut f.friction, 0.0..=2.0, "friction"),
            linear(&mut f.guide_friction, 0.0..=10.0, "guide friction (N)"),
            linear(&mut f.restitution, 0.0..=1.0, "restitution"),
            linear(&mut f.mass, 0.0..=5.0, "mass (kg)"),
            linear(&mut f.poisson_ratio, 0.0..=0.499, "nu"),
            log_scale(&mut f.stick_velocity, 1e-5..=1e-1, "stick velocity (m/s)"),
            log_scale(&mut f.stick_stiffness, 1.0..=1e5, "stick stiffness (N/m)"),
            log_scale(&mut f.stick_damping, 0.01..=1e3, "stick damping (N s/m)"),
            log_scale(&mut f.young_modulus, 1e4..=1e11, "E (Pa)"),
            log_scale(&mut f.contact_stiffness_scale, 0.1..=100.0, "contact scale"),
        ],
    );
    changed
}

/// A new force-controlled 5 mm sphere finger just above the object's top,
/// a quarter of the object's width off its centre (away from a finger
/// already at the centre), carrying 1 N.
fn new_finger(scene: &Scene, frame: Option<&Frame>) -> Finger {
    let mut finger = Scene::thesis().fingers[0].clone();
    let radius = 0.005;
    finger.shape = FingerShape::Sphere { radius };
    finger.mass = 0.0;
    finger.force = glam::DVec3::new(0.0, 0.0, -1.0);
    finger.contact_stiffness_scale = 1.0;
    let positions = frame
        .filter(|f| !f.state.positions.is_empty())
        .map(|f| f.state.positions.clone())
        .or_else(|| {
            softgrip_core::model::Model::mesh_of(scene)
                .ok()
                .map(|m| m.nodes)
        });
    let (lo, hi) = positions
        .map(|p| softgrip_core::mesh::bounds_of(&p))
        .unwrap_or((glam::DVec3::splat(-0.01), glam::DVec3::splat(0.01)));
    let centre = 0.5 * (lo + hi);
    finger.position = glam::DVec3::new(
        centre.x + 0.25 * (hi.x - lo.x),
        centre.y,
        hi.z + radius + 0.0005,
    );
    finger
}
