//! Constant finger data: shape, drive per axis, contact constants.

use glam::DVec3;

use crate::scene::{Finger, FingerShape};

/// Hunt-Crossley divides by the normal speed at first contact (thesis eq. 26),
/// which is ~0 when a finger is lowered gently: that speed is floored here
/// (m/s). The floor bounds the contact damping coefficient
/// `1.5 (1 - e) K delta^n / v0`; at rest the damping does no work, so the
/// static answer does not depend on it.
pub const HUNT_CROSSLEY_MIN_APPROACH_SPEED: f64 = 0.01;

/// How one axis of a finger moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxisDrive {
    /// Not free: the finger never moves along this axis.
    Locked,
    /// Pushed by the applied force (and weight) and the contact reaction.
    Force,
    /// Moves at this speed (m/s) until its travel is used up.
    Velocity(f64),
}

/// One rigid shape of a finger, at `offset` from its position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartModel {
    /// The part's shape (sphere, plate or box; sizes in m).
    pub shape: FingerShape,
    /// The part's centre relative to the finger's position, m.
    pub offset: DVec3,
    /// Sphere: Hertz sphere-plane stiffness K (eq. 27), N/m^1.5.
    pub hertz_stiffness: f64,
}

/// A finger's constant data (`[[finger]]`): its shapes, its drive per axis and its contact
/// constants.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerModel {
    /// The shape at the finger's position (`parts[0]`).
    pub shape: FingerShape,
    /// Every shape of the finger: its own first, then `[[finger.part]]`s.
    pub parts: Vec<PartModel>,
    /// The finger's position at the start, m.
    pub initial_position: DVec3,
    /// The finger's mass, kg (0: a mass-less finger, see `guide_speed`).
    pub mass: f64,
    /// How the finger moves along x, y and z.
    pub drive: [AxisDrive; 3],
    /// Velocity control: distance after which the finger holds still (m).
    pub travel: Option<f64>,
    /// Velocity-driven axes hold still until this time (s) ...
    pub start_time: f64,
    /// ... then reach their velocity linearly over this time (s).
    pub ramp_time: f64,
    /// Coulomb friction in the guide (N), on the force-driven axes.
    pub guide_friction: f64,
    /// The scene's `force` (N); the state's `applied_force` starts from it.
    pub force: DVec3,
    /// The finger's weight `m g` (N).
    pub weight: DVec3,
    /// Unit direction of the scene's `force` (the recording's load direction).
    pub load_direction: DVec3,
    /// Mass-less finger: speed along its force axes when free (m/s), see
    /// [`FingerModel::guide_damping`].
    pub guide_speed: f64,
    /// Effective modulus `1 / (sigma_f + sigma_o)` (thesis eq. 27-28), Pa.
    pub effective_modulus: f64,
    /// Sphere: Hertz sphere-plane stiffness K (eq. 27), N/m^1.5.
    pub hertz_stiffness: f64,
    /// `contact_stiffness_scale`: multiplies every contact stiffness law
    /// (applied in `contact::stiffness_and_exponent`).
    pub contact_stiffness_scale: f64,
    /// Hunt-Crossley coefficient of restitution e (thesis eq. 26), 0 to 1.
    pub restitution: f64,
    /// Coulomb coefficient between object and finger (thesis eq. 34).
    pub friction: f64,
    /// Speed of the stick-slip transition (thesis eq. 31), m/s.
    pub stick_velocity: f64,
    /// Stiffness of the stick spring (thesis eq. 35), N/m.
    pub stick_stiffness: f64,
    /// Damping of the stick spring (thesis eq. 36), N s/m.
    pub stick_damping: f64,
}

impl FingerModel {
    /// From the scene's finger, with the object's Young's modulus (Pa) and Poisson ratio for
    /// the contact's effective modulus, and gravity (m/s^2) for its weight.
    pub fn new(
        f: &Finger,
        object_modulus: f64,
        object_poisson: f64,
        gravity: DVec3,
    ) -> FingerModel {
        let drive = std::array::from_fn(|axis| {
            if !f.free_axes[axis] {
                AxisDrive::Locked
            } else if f.axis_is_velocity_driven(axis) {
                AxisDrive::Velocity(f.velocity[axis])
            } else {
                AxisDrive::Force
            }
        });
        let sigma_f = (1.0 - f.poisson_ratio * f.poisson_ratio) / f.young_modulus;
        let sigma_o = (1.0 - object_poisson * object_poisson) / object_modulus;
        let effective_modulus = 1.0 / (sigma_f + sigma_o);
        let hertz = |shape: FingerShape| match shape {
            FingerShape::Sphere { radius } => 4.0 / 3.0 * effective_modulus * radius.sqrt(),
            FingerShape::Plate { .. } | FingerShape::Box { .. } => 0.0,
        };
        let hertz_stiffness = hertz(f.shape);
        let parts = std::iter::once((f.shape, DVec3::ZERO))
            .chain(f.parts.iter().map(|p| (p.shape, p.offset)))
            .map(|(shape, offset)| PartModel {
                shape,
                offset,
                hertz_stiffness: hertz(shape),
            })
            .collect();
        FingerModel {
            shape: f.shape,
            parts,
            initial_position: f.position,
            mass: f.mass,
            drive,
            travel: f.travel,
            start_time: f.start_time,
            ramp_time: f.ramp_time,
            guide_friction: f.guide_friction,
            force: f.force,
            weight: f.mass * gravity,
            load_direction: f.force.normalize_or_zero(),
            guide_speed: f.guide_speed,
            effective_modulus,
            hertz_stiffness,
            contact_stiffness_scale: f.contact_stiffness_scale,
            restitution: f.restitution,
            friction: f.friction,
            stick_velocity: f.stick_velocity,
            stick_stiffness: f.stick_stiffness,
            stick_damping: f.stick_damping,
        }
    }

    /// The applied force plus weight along the force-driven axes (N).
    pub fn driving_force(&self, applied_force: DVec3) -> DVec3 {
        let total = applied_force + self.weight;
        DVec3::from_array(std::array::from_fn(|a| match self.drive[a] {
            AxisDrive::Force => total[a],
            _ => 0.0,
        }))
    }

    /// Damping to the guide (N s/m) on the force axes of a mass-less finger.
    ///
    /// A finger with `mass = 0` (a load applied through a light guide) has no
    /// inertia, so its equation is first order: `c v = F_applied + F_contact`,
    /// carried in the implicit system like any damper. With
    /// `c = |F_applied| / guide_speed` it approaches at `guide_speed` when
    /// free and stops where the contact balances the load; at rest the
    /// balance is exact. A finger with mass has no guide damping.
    pub fn guide_damping(&self, applied_force: DVec3) -> f64 {
        if self.mass == 0.0 {
            applied_force.length().max(1e-3) / self.guide_speed
        } else {
            0.0
        }
    }

    /// The share of its velocity a velocity-driven axis has at `time`:
    /// 0 before `start_time`, rising linearly to 1 over `ramp_time`.
    pub fn velocity_share(&self, time: f64) -> f64 {
        if time < self.start_time {
            0.0
        } else if self.ramp_time > 0.0 {
            ((time - self.start_time) / self.ramp_time).min(1.0)
        } else {
            1.0
        }
    }

    /// Whether any axis is force-driven.
    pub fn is_force_controlled(&self) -> bool {
        self.drive.contains(&AxisDrive::Force)
    }
}
