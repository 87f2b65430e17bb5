//! What the mouse does in the 3-D view. A primary-button drag is decided where it starts: on a
//! finger it holds the finger where the mouse is (along its free axes), on the object it pulls
//! it with the mouse spring, elsewhere (or with Alt held, or on a recording shown) it orbits.
//! The middle button orbits, the right one pans, the wheel zooms.

use eframe::egui;
use glam::{DVec3, Vec3};

use crate::render::pick::{self, Ray};
use crate::render::{self, Camera};
use softgrip_core::live::Command;
use softgrip_core::model::Model;
use softgrip_core::state::{Pull, State};

/// What a primary-button drag in the 3-D view does, decided where it
/// starts: on a finger it moves the finger, on the object it pulls it with
/// the mouse spring, elsewhere (or with Alt held) it orbits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Drag {
    None,
    Orbit,
    Finger {
        index: usize,
        /// Where the finger was grabbed and its centre then.
        grabbed: DVec3,
        centre: DVec3,
        /// The drag plane's normal: the camera's forward at the grab.
        facing: DVec3,
        last: Option<DVec3>,
    },
    Object {
        facet: u32,
        weights: [f64; 3],
        grabbed: DVec3,
        facing: DVec3,
        last: Option<DVec3>,
    },
}

/// The view's place on the screen and its size in pixels: how a pointer
/// position becomes a ray.
pub(super) struct Pixels {
    pub(super) rect: egui::Rect,
    /// Pixels per egui point.
    pub(super) ppp: f32,
    pub(super) width: u32,
    pub(super) height: u32,
}

impl Pixels {
    /// `rect` (egui points) in pixels at the screen's scale, each side at least 16.
    pub(super) fn of(ui: &egui::Ui, rect: egui::Rect) -> Pixels {
        let ppp = ui.ctx().pixels_per_point();
        let (w, h) = (
            (rect.width() * ppp).round().max(16.0) as u32,
            (rect.height() * ppp).round().max(16.0) as u32,
        );
        Pixels {
            rect,
            ppp,
            width: w,
            height: h,
        }
    }

    fn ray(&self, camera: &Camera, pos: egui::Pos2) -> Ray {
        camera.ray(
            (pos.x - self.rect.min.x) * self.ppp,
            (pos.y - self.rect.min.y) * self.ppp,
            self.width,
            self.height,
        )
    }
}

/// The drawn model and state a drag acts on; `pickable` is false while a
/// recording is shown (a drag then only orbits).
pub(super) struct Drawn<'a> {
    pub(super) model: &'a Model,
    pub(super) state: &'a State,
    pub(super) pickable: bool,
}

/// Moves `camera` and `drag` by this frame's pointer; the finger held or
/// the object pulled goes to `send`.
pub(super) fn handle(
    ui: &egui::Ui,
    response: &egui::Response,
    pixels: &Pixels,
    camera: &mut Camera,
    drag: &mut Drag,
    drawn: Drawn<'_>,
    send: &dyn Fn(Command),
) {
    let Drawn {
        model,
        state,
        pickable,
    } = drawn;
    let alt = ui.input(|i| i.modifiers.alt);
    if response.drag_started_by(egui::PointerButton::Primary)
        && let Some(pos) = response.interact_pointer_pos()
    {
        let ray = pixels.ray(camera, pos);
        *drag = grab(model, state, &ray, camera.forward(), !alt && pickable);
    }
    let orbit = (response.dragged_by(egui::PointerButton::Primary) && *drag == Drag::Orbit)
        || response.dragged_by(egui::PointerButton::Middle);
    if orbit {
        let d = response.drag_delta();
        camera.yaw -= d.x * 0.008;
        camera.pitch = (camera.pitch + d.y * 0.008).clamp(-1.55, 1.55);
    }
    if response.dragged_by(egui::PointerButton::Primary)
        && let Some(pos) = response.interact_pointer_pos()
    {
        let ray = pixels.ray(camera, pos);
        follow(drag, model, &ray, send);
    }
    if response.drag_stopped() || (!response.dragged() && *drag != Drag::None) {
        match *drag {
            Drag::Finger { index, .. } => send(Command::Hold {
                finger: index,
                at: None,
            }),
            Drag::Object { .. } => send(Command::Pull(None)),
            Drag::None | Drag::Orbit => {}
        }
        *drag = Drag::None;
    }
    if response.dragged_by(egui::PointerButton::Secondary) {
        let d = response.drag_delta();
        let eye = camera.eye();
        let forward = (camera.target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Z).normalize_or_zero();
        let up = right.cross(forward);
        let per_pixel = camera.distance * 0.0015;
        camera.target += (-d.x * right + d.y * up) * per_pixel;
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        camera.distance *= (-scroll * 0.002).exp();
    }
}

/// The drag that starts where `ray` points: a finger or the object when
/// `pickable` and one is hit, else orbit.
fn grab(model: &Model, state: &State, ray: &Ray, facing: DVec3, pickable: bool) -> Drag {
    let thickness = render::geometry::plate_thickness(model);
    match pickable
        .then(|| pick::pick(model, state, ray, thickness))
        .flatten()
    {
        Some(pick::Picked::Finger { index, point }) => Drag::Finger {
            index,
            grabbed: point,
            centre: state.fingers[index].position,
            facing,
            last: None,
        },
        Some(pick::Picked::Object {
            facet,
            weights,
            point,
        }) => Drag::Object {
            facet,
            weights,
            grabbed: point,
            facing,
            last: None,
        },
        None => Drag::Orbit,
    }
}

/// A drag under way: the finger held, or the object pulled, where `ray`
/// now points (sent only when it moved).
fn follow(drag: &mut Drag, model: &Model, ray: &Ray, send: &dyn Fn(Command)) {
    match drag {
        Drag::Finger {
            index,
            grabbed,
            centre,
            facing,
            last,
        } => {
            let target = pick::finger_target(model, *index, *centre, *grabbed, *facing, ray);
            if target.is_some() && target != *last {
                *last = target;
                send(Command::Hold {
                    finger: *index,
                    at: target,
                });
            }
        }
        Drag::Object {
            facet,
            weights,
            grabbed,
            facing,
            last,
        } => {
            let target = pick::on_plane(ray, *grabbed, *facing);
            if let Some(target) = target
                && Some(target) != *last
            {
                *last = Some(target);
                send(Command::Pull(Some(Pull {
                    facet: *facet,
                    weights: *weights,
                    target,
                    stiffness: Pull::default_stiffness(model),
                })));
            }
        }
        Drag::None | Drag::Orbit => {}
    }
}
