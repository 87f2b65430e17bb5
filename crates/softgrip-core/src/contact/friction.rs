//! Stick-slip tangential force (thesis eq. 30-36).

use glam::DVec3;

/// Tangential force on the object and the coefficients of its Jacobian.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialForce {
    /// The tangential force on the object, N.
    pub force: DVec3,
    /// Stick weight S (eq. 31).
    pub stick: f64,
    /// `-df/dx ~ stiffness P`, `-df/dv ~ damping P` (P the tangent projector).
    pub stiffness: f64,
    /// Its damping coefficient along the plane, N s/m.
    pub damping: f64,
}

/// A finger's stick-slip friction law (eq. 30-36).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickSlipParams {
    /// Coulomb friction coefficient mu.
    pub friction: f64,
    /// The slip speed of eq. 31's stick-slip transition, m/s.
    pub stick_velocity: f64,
    /// The stick spring's stiffness, N/m.
    pub stick_stiffness: f64,
    /// The stick spring's damping, N s/m.
    pub stick_damping: f64,
}

/// `drift`: the tangential displacement of the stuck material point from its
/// anchor (already limited to the friction cone by the caller, see
/// [`limit_drift`]); `tangential_velocity`: eq. 33's v_t; `slip_speed`: how
/// fast the anchor is being dragged (m/s), which sets eq. 31's transition.
///
/// Eq. 31 evaluates S on v_t. Taken at the start of an implicit step that
/// makes a contact flip between stick and slip every step (a particle under a
/// resting finger jitters at ~1e-3 m/s and never comes to rest: S is
/// explicit, and its steep dependence on v is missing from the Jacobian). We
/// evaluate S on the slip speed instead: the speed at which the contact
/// slides over the object, as opposed to the stick spring's own elastic
/// give. A contact inside its friction cone does not slide, so S = 1 and the
/// stick spring holds (static friction); a contact sliding much faster than
/// `stick_velocity` gets S = 0 and eq. 34's Coulomb force, as in the thesis.
pub fn stick_slip_force(
    p: &StickSlipParams,
    normal_force: f64,
    drift: DVec3,
    tangential_velocity: DVec3,
    slip_speed: f64,
) -> TangentialForce {
    let speed = tangential_velocity.length();
    let stick = (-(slip_speed * slip_speed) / (p.stick_velocity * p.stick_velocity)).exp(); // eq. 31
    let slip = if speed > 0.0 {
        -p.friction * normal_force * tangential_velocity / speed // eq. 34
    } else {
        DVec3::ZERO
    };
    let d = drift.length();
    let stick_force = if d > 0.0 {
        let direction = drift / d;
        let d_rate = direction.dot(tangential_velocity);
        -(p.stick_stiffness * d + p.stick_damping * d_rate) * direction // eq. 35-36
    } else {
        DVec3::ZERO
    };
    TangentialForce {
        force: stick * stick_force + (1.0 - stick) * slip, // eq. 30
        stick,
        stiffness: stick * p.stick_stiffness,
        damping: stick * p.stick_damping
            + (1.0 - stick) * p.friction * normal_force / speed.max(p.stick_velocity),
    }
}

/// Limits the stick drift to the friction cone: when the stick spring would
/// pull harder than `mu F_n`, the contact slips and its anchor is dragged
/// along (the "reset the stick anchor when slipping"). Returns the limited
/// drift and how far the anchor moved.
pub fn limit_drift(p: &StickSlipParams, normal_force: f64, drift: DVec3) -> (DVec3, DVec3) {
    let d = drift.length();
    if p.stick_stiffness <= 0.0 {
        return (DVec3::ZERO, drift);
    }
    let limit = p.friction * normal_force / p.stick_stiffness;
    if d <= limit {
        (drift, DVec3::ZERO)
    } else {
        let kept = drift * (limit / d);
        (kept, drift - kept)
    }
}

/// [`limit_drift`] for a contact held sliding: the drift put on the cone's edge, inside the
/// cone too.
pub fn slide_drift(p: &StickSlipParams, normal_force: f64, drift: DVec3) -> (DVec3, DVec3) {
    let d = drift.length();
    if p.stick_stiffness <= 0.0 || d == 0.0 {
        return limit_drift(p, normal_force, drift);
    }
    let kept = drift * (p.friction * normal_force / p.stick_stiffness / d);
    (kept, drift - kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: StickSlipParams = StickSlipParams {
        friction: 0.5,
        stick_velocity: 1e-3,
        stick_stiffness: 500.0,
        stick_damping: 5.0,
    };

    #[test]
    fn fast_sliding_is_coulomb() {
        let t = stick_slip_force(&P, 2.0, DVec3::ZERO, DVec3::new(0.1, 0.0, 0.0), 0.1);
        // S = exp(-(0.1/1e-3)^2) = 0: pure Coulomb, mu F_n against the motion.
        assert!((t.force - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn at_rest_the_stick_spring_holds() {
        let t = stick_slip_force(&P, 2.0, DVec3::new(0.0, 1e-3, 0.0), DVec3::ZERO, 0.0);
        assert_eq!(t.stick, 1.0);
        assert!((t.force - DVec3::new(0.0, -0.5, 0.0)).length() < 1e-12);
    }

    #[test]
    fn a_stuck_contact_keeps_its_stick_spring_while_it_gives() {
        // The stick spring stretching at 5 mm/s is not sliding: S stays 1.
        let t = stick_slip_force(
            &P,
            2.0,
            DVec3::new(1e-3, 0.0, 0.0),
            DVec3::new(5e-3, 0.0, 0.0),
            0.0,
        );
        assert_eq!(t.stick, 1.0);
        // -k d - c d' = -500 * 1e-3 - 5 * 5e-3
        assert!((t.force.x + 0.525).abs() < 1e-12, "{t:?}");
        // Sliding at the stick velocity blends by exp(-1).
        let t = stick_slip_force(&P, 2.0, DVec3::ZERO, DVec3::new(1e-3, 0.0, 0.0), 1e-3);
        assert!((t.stick - (-1.0f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn drift_is_limited_to_the_cone() {
        let (kept, moved) = limit_drift(&P, 2.0, DVec3::new(0.01, 0.0, 0.0));
        // mu F / k = 0.5 * 2 / 500 = 2 mm
        assert!((kept.x - 0.002).abs() < 1e-15);
        assert!((moved.x - 0.008).abs() < 1e-15);
    }
}
