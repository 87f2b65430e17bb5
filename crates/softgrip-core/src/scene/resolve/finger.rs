//! `[[finger]]` and its `[[finger.part]]`s: the rigid shapes, how the finger is driven (force or
//! velocity, along which axes, from when), its contact material and friction, its guide.

use super::resolver::{At, Resolver};
use crate::scene::error::SceneError;
use crate::scene::raw::{RawFinger, RawPart};
use crate::scene::{Control, Finger, FingerPart, FingerShape};

/// A finger's contact material and friction (see [`Finger`]'s fields of the same names).
struct ContactMaterial {
    young_modulus: f64,
    poisson_ratio: f64,
    restitution: f64,
    friction: f64,
    stick_velocity: f64,
    stick_stiffness: f64,
    stick_damping: f64,
}

/// When and how far a finger moves, and its guide (see [`Finger`]'s fields of the same names).
struct Motion {
    travel: Option<f64>,
    start_time: f64,
    ramp_time: f64,
    guide_friction: f64,
    guide_speed: f64,
}

impl Resolver<'_> {
    pub(super) fn fingers(&mut self, raw: &[RawFinger]) -> Result<Vec<Finger>, SceneError> {
        // `[[finger.part]]` tables are numbered in file order, across fingers.
        let mut parts_seen = 0;
        let mut fingers = Vec::new();
        for (i, f) in raw.iter().enumerate() {
            fingers.push(self.finger(i, f, &mut parts_seen)?);
        }
        Ok(fingers)
    }

    /// A finger's (or a part's) `shape` with its `radius` or `size`.
    fn finger_shape<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        shape: Option<String>,
        radius: Option<f64>,
        size: Option<Vec<f64>>,
    ) -> Result<FingerShape, SceneError> {
        let extents = |this: &mut Self, n: usize, default: &[f64]| {
            let size = this.default(at("size"), size.clone(), default.to_vec());
            if size.len() != n || !size.iter().all(|c| c.is_finite() && *c > 0.0) {
                let what = if n == 2 { "[x, y]" } else { "[x, y, z]" };
                return Err(this.err(
                    at("size"),
                    format!("{size:?}"),
                    &format!("must be {what}, every extent > 0 m"),
                ));
            }
            Ok(size)
        };
        Ok(
            match self
                .default(at("shape"), shape, "sphere".to_string())
                .as_str()
            {
                "sphere" => {
                    let radius =
                        self.number(at("radius"), radius, 0.015, |x| x > 0.0, "must be > 0 m")?;
                    FingerShape::Sphere { radius }
                }
                "plate" => {
                    let size = extents(self, 2, &[0.08, 0.08])?;
                    FingerShape::Plate {
                        half_size: [0.5 * size[0], 0.5 * size[1]],
                    }
                }
                "box" => {
                    let size = extents(self, 3, &[0.02, 0.02, 0.02])?;
                    FingerShape::Box {
                        half_size: [0.5 * size[0], 0.5 * size[1], 0.5 * size[2]],
                    }
                }
                other => {
                    return Err(self.err(
                        at("shape"),
                        format!("{other:?}"),
                        "must be \"sphere\", \"plate\" or \"box\"",
                    ));
                }
            },
        )
    }

    /// A finger's parts, numbered from `parts_seen` on.
    fn parts(
        &mut self,
        raw: &[RawPart],
        parts_seen: &mut usize,
    ) -> Result<Vec<FingerPart>, SceneError> {
        let mut parts = Vec::new();
        for raw in raw {
            let index = *parts_seen;
            *parts_seen += 1;
            let at = |key| At {
                table: "finger.part",
                index: Some(index),
                key,
            };
            let shape = self.finger_shape(at, raw.shape.clone(), raw.radius, raw.size.clone())?;
            let offset = self.vec3(at("offset"), raw.offset, [0.0; 3])?;
            parts.push(FingerPart { shape, offset });
        }
        Ok(parts)
    }

    /// The `i`-th `[[finger]]`, stage by stage in file order (the order of the defaults
    /// recorded and of the errors reported); its parts are numbered from `parts_seen` on.
    fn finger(
        &mut self,
        i: usize,
        f: &RawFinger,
        parts_seen: &mut usize,
    ) -> Result<Finger, SceneError> {
        let at = |key| At {
            table: "finger",
            index: Some(i),
            key,
        };
        let shape = self.finger_shape(at, f.shape.clone(), f.radius, f.size.clone())?;
        let parts = self.parts(f.part.as_deref().unwrap_or_default(), parts_seen)?;
        let position = self.vec3(at("position"), f.position, [0.0, 0.0, 0.035])?;
        let free_axes = self.finger_free_axes(at, f.free_axes.clone())?;
        let control = self.finger_control(at, f.control.clone())?;
        let force = self.vec3(at("force"), f.force, [0.0; 3])?;
        let velocity = self.vec3(at("velocity"), f.velocity, [0.0; 3])?;
        let mass = self.number(
            at("mass"),
            f.mass,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 kg (0 = a light guide)",
        )?;
        let contact = self.finger_contact(at, f)?;
        let motion = self.finger_motion(at, f)?;
        let contact_stiffness_scale = self.number(
            at("contact_stiffness_scale"),
            f.contact_stiffness_scale,
            1.0,
            |x| x > 0.0 && x <= 1e6,
            "must be in (0, 1e6] (1 = thesis eq. 27)",
        )?;
        Ok(Finger {
            shape,
            parts,
            position,
            free_axes,
            control,
            force,
            velocity,
            mass,
            young_modulus: contact.young_modulus,
            poisson_ratio: contact.poisson_ratio,
            restitution: contact.restitution,
            friction: contact.friction,
            stick_velocity: contact.stick_velocity,
            stick_stiffness: contact.stick_stiffness,
            stick_damping: contact.stick_damping,
            travel: motion.travel,
            start_time: motion.start_time,
            ramp_time: motion.ramp_time,
            guide_friction: motion.guide_friction,
            guide_speed: motion.guide_speed,
            contact_stiffness_scale,
        })
    }

    /// `free_axes`: the letters of the axes along which the finger moves, each once.
    fn finger_free_axes<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        free_axes: Option<String>,
    ) -> Result<[bool; 3], SceneError> {
        let axes_text = self.default(at("free_axes"), free_axes, "z".to_string());
        let mut free_axes = [false; 3];
        for c in axes_text.chars() {
            let k = match c {
                'x' => 0,
                'y' => 1,
                'z' => 2,
                _ => return Err(self.err(at("free_axes"), format!("{axes_text:?}"),
                    "must be letters from \"xyz\", each once (e.g. \"z\" or \"xz\"); \"\" holds the finger still")),
            };
            if free_axes[k] {
                return Err(self.err(
                    at("free_axes"),
                    format!("{axes_text:?}"),
                    "names an axis twice",
                ));
            }
            free_axes[k] = true;
        }
        Ok(free_axes)
    }

    /// `control`: how the finger is driven, by force or by velocity.
    fn finger_control<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        control: Option<String>,
    ) -> Result<Control, SceneError> {
        let control = match self
            .default(at("control"), control, "force".to_string())
            .as_str()
        {
            "force" => Control::Force,
            "velocity" => Control::Velocity,
            other => {
                return Err(self.err(
                    at("control"),
                    format!("{other:?}"),
                    "must be \"force\" or \"velocity\"",
                ));
            }
        };
        Ok(control)
    }

    /// The finger's contact material and friction, from `young_modulus` to `stick_damping`.
    fn finger_contact<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        f: &RawFinger,
    ) -> Result<ContactMaterial, SceneError> {
        let young_modulus = self.number(
            at("young_modulus"),
            f.young_modulus,
            2e9,
            |x| (1.0..=1e13).contains(&x),
            "must be a modulus from 1 Pa to 1e13 Pa (a steel finger is 2e11)",
        )?;
        let poisson_ratio = self.number(
            at("poisson_ratio"),
            f.poisson_ratio,
            0.3,
            |x| x > -1.0 && x < 0.5,
            "must be in (-1, 0.5)",
        )?;
        let restitution = self.number(
            at("restitution"),
            f.restitution,
            0.5,
            |x| (0.0..=1.0).contains(&x),
            "must be in [0, 1]",
        )?;
        let friction = self.number(
            at("friction"),
            f.friction,
            0.5,
            |x| x >= 0.0,
            "must be >= 0",
        )?;
        let stick_velocity = self.number(
            at("stick_velocity"),
            f.stick_velocity,
            1e-3,
            |x| (1e-9..=10.0).contains(&x),
            "must be a speed from 1e-9 to 10 m/s (the slip speed under which a contact sticks; 1e-3 by default)",
        )?;
        let stick_stiffness = self.number(
            at("stick_stiffness"),
            f.stick_stiffness,
            500.0,
            |x| x >= 0.0,
            "must be >= 0 N/m",
        )?;
        let stick_damping = self.number(
            at("stick_damping"),
            f.stick_damping,
            5.0,
            |x| x >= 0.0,
            "must be >= 0 N s/m",
        )?;
        Ok(ContactMaterial {
            young_modulus,
            poisson_ratio,
            restitution,
            friction,
            stick_velocity,
            stick_stiffness,
            stick_damping,
        })
    }

    /// When and how far the finger moves, and its guide: from `travel` to `guide_speed`.
    fn finger_motion<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        f: &RawFinger,
    ) -> Result<Motion, SceneError> {
        let travel = self.optional(at("travel"), f.travel, |x| x >= 0.0, "must be >= 0 m")?;
        let start_time = self.number(
            at("start_time"),
            f.start_time,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let ramp_time = self.number(
            at("ramp_time"),
            f.ramp_time,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let guide_friction = self.number(
            at("guide_friction"),
            f.guide_friction,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 N (the Coulomb friction force in the finger's guide)",
        )?;
        let guide_speed = self.number(
            at("guide_speed"),
            f.guide_speed,
            0.05,
            |x| x > 0.0,
            "must be > 0 m/s",
        )?;
        Ok(Motion {
            travel,
            start_time,
            ramp_time,
            guide_friction,
            guide_speed,
        })
    }
}
