//! Hunt-Crossley normal force (thesis eq. 26-29).

/// Normal force magnitude and its derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalForce {
    /// The normal force's magnitude, N (never pulling).
    pub force: f64,
    /// dF / d(penetration).
    pub stiffness: f64,
    /// dF / d(penetration rate).
    pub damping: f64,
}

/// `F = K d^n (1 + 3 (1 - e) / 2 * d' / v0)`, never pulling (F >= 0).
///
/// `approach_speed` is eq. 26's normal speed at first contact, already
/// floored by the caller (see `HUNT_CROSSLEY_MIN_APPROACH_SPEED`).
pub fn hunt_crossley_normal_force(
    stiffness: f64,
    exponent: f64,
    restitution: f64,
    penetration: f64,
    penetration_rate: f64,
    approach_speed: f64,
) -> NormalForce {
    if penetration <= 0.0 {
        return NormalForce {
            force: 0.0,
            stiffness: 0.0,
            damping: 0.0,
        };
    }
    let elastic = stiffness * penetration.powf(exponent);
    let lambda = 1.5 * (1.0 - restitution) / approach_speed;
    let force = elastic * (1.0 + lambda * penetration_rate);
    if force <= 0.0 {
        // Separating faster than the damping allows: the contact lets go.
        return NormalForce {
            force: 0.0,
            stiffness: 0.0,
            damping: 0.0,
        };
    }
    NormalForce {
        force,
        stiffness: exponent
            * stiffness
            * penetration.powf(exponent - 1.0)
            * (1.0 + lambda * penetration_rate).max(0.0),
        damping: elastic * lambda,
    }
}

/// Elastic energy of the contact, `K d^(n+1) / (n+1)` (J).
pub fn elastic_energy(stiffness: f64, exponent: f64, penetration: f64) -> f64 {
    if penetration <= 0.0 {
        0.0
    } else {
        stiffness * penetration.powf(exponent + 1.0) / (exponent + 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn static_force_is_hertz() {
        let f = hunt_crossley_normal_force(1000.0, 1.5, 0.5, 1e-3, 0.0, 0.1);
        assert!((f.force - 1000.0 * 1e-3f64.powf(1.5)).abs() < 1e-15);
        // dF/dd = 1.5 K d^0.5
        assert!((f.stiffness - 1.5 * 1000.0 * 1e-3f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn damping_follows_restitution() {
        // e = 1: no damping.
        let f = hunt_crossley_normal_force(1000.0, 1.5, 1.0, 1e-3, 0.05, 0.1);
        assert_eq!(f.damping, 0.0);
        let g = hunt_crossley_normal_force(1000.0, 1.5, 0.0, 1e-3, 0.05, 0.1);
        // 1 + 1.5 * 0.05 / 0.1 = 1.75 times the elastic force while approaching.
        assert!((g.force / (1000.0 * 1e-3f64.powf(1.5)) - 1.75).abs() < 1e-12);
    }

    #[test]
    fn never_pulls() {
        let f = hunt_crossley_normal_force(1000.0, 1.5, 0.0, 1e-3, -1.0, 0.1);
        assert_eq!(f.force, 0.0);
    }
}
