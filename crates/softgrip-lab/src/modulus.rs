//! Young's modulus from a compression recording (thesis Sec. VII-B, eq.
//! 49-50): the stress `F / A` and strain `dl / l0` of each load level, and a
//! line fitted through the initial linear part of the curve.
//!
//! The initial linear part is found automatically: starting from the
//! unloaded state (0, 0) and the first two levels, levels are added while
//! the curve stays straight, that is while the newest segment's slope is
//! within [`LINEAR_TOLERANCE`] of the line fitted so far. The fit is a
//! least-squares line with an intercept (a seating toe shifts the curve
//! without changing its slope); E is its slope.

use crate::recording::{MarkerRef, Mode, Recording};
use softgrip_core::scene::{FingerShape, Shape};

/// How far (relative) a segment's slope may leave the fitted line before
/// the curve is no longer taken as linear.
pub const LINEAR_TOLERANCE: f64 = 0.10;

/// Young's modulus fitted to a compression recording, and what it rests on.
#[derive(Debug, Clone, PartialEq)]
pub struct ModulusFit {
    /// Pa: the slope of the line through the initial linear part.
    pub young_modulus: f64,
    /// Pa: the intercept of that line (the toe).
    pub intercept: f64,
    /// Coefficient of determination of the fit.
    pub r_squared: f64,
    /// The strain range fitted, and how many points it holds.
    pub strain_range: (f64, f64),
    /// Points in the fit.
    pub points: usize,
    /// The smallest and largest E over the candidate ranges from 2 points
    /// up to the chosen one: how much the answer depends on the range.
    pub e_range: (f64, f64),
    /// All (strain, stress) points, the unloaded state first.
    pub curve: Vec<(f64, f64)>,
    /// m^2 and m: the area and the initial length used.
    pub area: f64,
    /// The object's initial height along the compression, m.
    pub length: f64,
}

/// Why no modulus could be measured from a recording.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModulusError {
    /// The recording is a time series.
    #[error("{0}: modulus needs a quasi-static recording (loads with plate positions)")]
    NotQuasiStatic(String),
    /// No finger marker observes z (the plate's travel).
    #[error(
        "{0}: no finger marker with an observed z: modulus reads the plate's travel from the `finger` marker"
    )]
    NoTravel(String),
    /// The object is a mesh: its area and height are unknown.
    #[error(
        "{0}: the object is a mesh; modulus needs a cuboid or a cylinder to know the area and height"
    )]
    UnknownGeometry(String),
    /// Fewer than 2 load levels compress the object.
    #[error("{0}: fewer than 2 load levels with positive strain; nothing to fit")]
    TooFew(String),
    /// The recording is no flat-plate compression, and why (recording, reason).
    #[error("{0}: not a flat-plate compression: {1}")]
    NotCompression(String, String),
}

/// Why `r` is not what modulus measures (a plate pressed down onto the object's top with
/// rising positive loads), or `None`. Stress `F / A` and strain `dl / l0` mean nothing for an
/// indentation or a pull: E = 9.3 kPa came out of a sphere indentation of 57.6 kPa silicone.
fn not_a_compression(r: &Recording, area: f64) -> Option<String> {
    let Some(finger) = r.scene.fingers.first() else {
        return Some("the scene has no finger (the plate)".into());
    };
    let other = "fit E to it with `softgrip fit RECORDING --params young_modulus`, which simulates the finger as it is";
    match finger.shape {
        FingerShape::Plate { half_size } => {
            let plate = 4.0 * half_size[0] * half_size[1];
            if plate < 0.99 * area {
                return Some(format!(
                    "the plate ({:.1} x {:.1} mm) is smaller than the object's top ({:.0} mm^2), so the stress is not F / A; {other}",
                    2e3 * half_size[0],
                    2e3 * half_size[1],
                    1e6 * area
                ));
            }
        }
        FingerShape::Sphere { radius } => {
            return Some(format!(
                "finger 1 is a sphere of radius {:.1} mm (an indentation); {other}",
                1e3 * radius
            ));
        }
        FingerShape::Box { .. } => {
            return Some(format!("finger 1 is a box, not a plate; {other}"));
        }
    }
    if !(finger.force.z < 0.0 && finger.force.x == 0.0 && finger.force.y == 0.0) {
        return Some(format!(
            "the plate's force = {:?} is not straight down (-z), the direction its travel is read in",
            finger.force.to_array()
        ));
    }
    if let Some((i, s)) = r.samples.iter().enumerate().find(|(_, s)| s.load < 0.0) {
        return Some(format!(
            "sample {} has load {} N: a compression's loads are positive (N along the plate's force)",
            i + 1,
            s.load
        ));
    }
    if let Some(i) = (1..r.samples.len()).find(|&i| r.samples[i].load < r.samples[i - 1].load) {
        return Some(format!(
            "the load falls at sample {} ({} N after {} N): modulus reads a loading curve; give the loading part only",
            i + 1,
            r.samples[i].load,
            r.samples[i - 1].load
        ));
    }
    None
}

/// Least-squares line `y = a + b x`: (b, a, r^2).
fn line(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x, sy + y));
    let (mx, my) = (sx / n, sy / n);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in points {
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (y - my);
        syy += (y - my) * (y - my);
    }
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let a = my - b * mx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    (b, a, r2)
}

/// A line through the initial linear part of a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineFit {
    /// Slope of the line (the curve's y unit per x unit; Pa for stress against strain).
    pub slope: f64,
    /// Intercept of the line (the curve's y unit).
    pub intercept: f64,
    /// Coefficient of determination of the fit.
    pub r_squared: f64,
    /// Points of the curve in the fit (from its start).
    pub points: usize,
    /// The smallest and largest slope over the candidate ranges.
    pub slope_range: (f64, f64),
}

/// Fits E to a stress-strain curve that starts at (0, 0) (see the module
/// docs); `curve` sorted by strain.
pub fn fit_curve(curve: &[(f64, f64)]) -> Option<LineFit> {
    if curve.len() < 3 {
        return None;
    }
    let mut k = 3;
    let mut es = vec![line(&curve[..2]).0];
    while k < curve.len() {
        let (b, _, _) = line(&curve[..k]);
        es.push(b);
        let (x0, y0) = curve[k - 1];
        let (x1, y1) = curve[k];
        let segment = (y1 - y0) / (x1 - x0);
        if !segment.is_finite() || (segment - b).abs() > LINEAR_TOLERANCE * b.abs() {
            break;
        }
        k += 1;
    }
    let (b, a, r2) = line(&curve[..k]);
    es.push(b);
    let lo = es.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = es.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Some(LineFit {
        slope: b,
        intercept: a,
        r_squared: r2,
        points: k,
        slope_range: (lo, hi),
    })
}

/// E from a quasi-static compression recording whose `finger` marker is the
/// plate: strain from its travel below its scene position over the
/// object's height, stress from the load over the object's cross-section.
pub fn from_recording(r: &Recording) -> Result<ModulusFit, ModulusError> {
    let name = r.source.display().to_string();
    if r.mode != Mode::QuasiStatic {
        return Err(ModulusError::NotQuasiStatic(name));
    }
    let (area, length) = match r.scene.object.shape {
        Shape::Cylinder { radius, height } => (std::f64::consts::PI * radius * radius, height),
        Shape::Cuboid { size } => (size.x * size.y, size.z),
        Shape::Mesh { .. } => return Err(ModulusError::UnknownGeometry(name)),
    };
    if let Some(why) = not_a_compression(r, area) {
        return Err(ModulusError::NotCompression(name, why));
    }
    let z0 = r
        .scene
        .fingers
        .first()
        .map(|f| f.position.z)
        .ok_or_else(|| ModulusError::NoTravel(name.clone()))?;
    let mut curve = vec![(0.0, 0.0)];
    let mut observed = false;
    for s in &r.samples {
        let z = s
            .observations
            .iter()
            .find(|o| o.marker == MarkerRef::Finger(0))
            .and_then(|o| o.position[2]);
        if let Some(z) = z {
            observed = true;
            let strain = (z0 - z) / length;
            if strain > 0.0 {
                curve.push((strain, s.load / area));
            }
        }
    }
    if !observed {
        return Err(ModulusError::NoTravel(name));
    }
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    let fit = fit_curve(&curve).ok_or_else(|| ModulusError::TooFew(name.clone()))?;
    Ok(ModulusFit {
        young_modulus: fit.slope,
        intercept: fit.intercept,
        r_squared: fit.r_squared,
        strain_range: (curve[0].0, curve[fit.points - 1].0),
        points: fit.points,
        e_range: fit.slope_range,
        curve,
        area,
        length,
    })
}
