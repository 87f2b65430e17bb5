//! A bounded parameter mapped to 0..1 of its bounds, linearly or on a log
//! scale (for values whose plausible range spans decades).

/// The bounds of one coordinate and how the unit box maps onto them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundedScale {
    /// Lower bound, in the coordinate's own unit (above 0 on a log scale).
    pub lower: f64,
    /// Upper bound, in the coordinate's own unit.
    pub upper: f64,
    /// Mapped on a log scale.
    pub log: bool,
}

impl BoundedScale {
    /// The value at `u` in 0..1 of the bounds.
    pub fn value(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        if self.log {
            (self.lower.ln() + u * (self.upper.ln() - self.lower.ln())).exp()
        } else {
            self.lower + u * (self.upper - self.lower)
        }
    }

    /// Where `v` lies in the bounds, 0..1 (clamped).
    pub fn unit(&self, v: f64) -> f64 {
        let u = if self.log {
            (v.ln() - self.lower.ln()) / (self.upper.ln() - self.lower.ln())
        } else {
            (v - self.lower) / (self.upper - self.lower)
        };
        if u.is_finite() {
            u.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// Is a point at `u` (0..1 of a coordinate's bounds, [`BoundedScale::unit`])
/// at one of its bounds, within 0.1 % of the range?
pub fn at_bound(u: f64) -> bool {
    !(1e-3..=1.0 - 1e-3).contains(&u)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_scale_maps_the_middle_to_the_geometric_mean() {
        let s = BoundedScale {
            lower: 1e5,
            upper: 1e8,
            log: true,
        };
        assert!((s.value(0.5) - 10f64.powf(6.5)).abs() < 1.0);
        assert!((s.unit(1e6) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(s.unit(1e9), 1.0);
        let lin = BoundedScale { log: false, ..s };
        assert_eq!(lin.value(0.0), 1e5);
        assert_eq!(lin.value(2.0), 1e8);
        assert!(at_bound(0.0) && at_bound(1.0) && !at_bound(0.5));
    }
}
