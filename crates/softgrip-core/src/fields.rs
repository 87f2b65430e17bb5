//! Scalar fields of a state, per particle and per element: what the viewer
//! colours the object by and what the exporters write. GUI-free.

use glam::DVec3;

use crate::model::Model;
use crate::state::State;

/// A field the object can be coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Field {
    /// Distance from the rest position (m).
    Displacement,
    /// Strain `(l - l0) / l0` of the spring at each particle with the
    /// largest magnitude, signed (stretch > 0, compression < 0).
    SpringStrain,
    /// Element volume change `V / V0 - 1`, averaged (volume-weighted) over
    /// the elements at each particle.
    VolumeChange,
    /// Contact normal force per unit area at each boundary particle (Pa):
    /// each contact's force shared by its barycentric weights, divided by
    /// the particle's share (a third) of the area of its boundary facets.
    ContactPressure,
    /// The material's Young's modulus (Pa), volume-weighted over the
    /// elements at each particle: shows `[[region]]`s.
    YoungModulus,
    /// The largest principal Green strain of the elements at each particle, the largest of
    /// them ([`element_green_strain`]): where a tear would start.
    GreenStrain,
    /// The von Mises stress (Pa) of the elements at each particle, the largest of them
    /// ([`element_von_mises`]).
    VonMises,
}

impl Field {
    /// Every field, in the order the viewer lists them.
    pub const ALL: [Field; 7] = [
        Field::Displacement,
        Field::SpringStrain,
        Field::VolumeChange,
        Field::ContactPressure,
        Field::YoungModulus,
        Field::GreenStrain,
        Field::VonMises,
    ];

    /// The field's name, for legends and menus.
    pub fn label(self) -> &'static str {
        match self {
            Field::Displacement => "displacement",
            Field::SpringStrain => "spring strain",
            Field::VolumeChange => "element volume change",
            Field::ContactPressure => "contact pressure",
            Field::YoungModulus => "Young's modulus",
            Field::GreenStrain => "largest principal Green strain",
            Field::VonMises => "von Mises stress",
        }
    }

    /// The unit of [`Field::display_scale`]d values.
    pub fn unit(self) -> &'static str {
        match self {
            Field::Displacement => "mm",
            Field::SpringStrain | Field::VolumeChange | Field::GreenStrain => "%",
            Field::ContactPressure | Field::YoungModulus | Field::VonMises => "kPa",
        }
    }

    /// Multiplies SI values into [`Field::unit`].
    pub fn display_scale(self) -> f64 {
        match self {
            Field::Displacement => 1e3,
            Field::SpringStrain | Field::VolumeChange | Field::GreenStrain => 1e2,
            Field::ContactPressure | Field::YoungModulus | Field::VonMises => 1e-3,
        }
    }

    /// Whether the field has a sign (a diverging colour map centred on 0).
    pub fn signed(self) -> bool {
        matches!(
            self,
            Field::SpringStrain | Field::VolumeChange | Field::GreenStrain
        )
    }

    /// The field at every particle (SI units).
    pub fn particle_values(self, model: &Model, state: &State) -> Vec<f64> {
        match self {
            Field::Displacement => displacement(model, state),
            Field::SpringStrain => particle_spring_strain(model, state),
            Field::VolumeChange => particle_volume_change(model, state),
            Field::ContactPressure => contact_pressure(model, state),
            Field::YoungModulus => particle_young_modulus(model),
            Field::GreenStrain => particle_largest(model, &element_green_strain(model, state)),
            Field::VonMises => particle_largest(model, &element_von_mises(model, state)),
        }
    }
}

/// Each particle's distance from its rest position, m (length: particles).
pub fn displacement(model: &Model, state: &State) -> Vec<f64> {
    state
        .positions
        .iter()
        .zip(&model.rest_positions)
        .map(|(x, x0)| (*x - *x0).length())
        .collect()
}

/// `(l - l0) / l0` of every spring.
pub fn spring_strain(model: &Model, state: &State) -> Vec<f64> {
    model
        .springs
        .iter()
        .map(|s| {
            let l = (state.positions[s.j as usize] - state.positions[s.i as usize]).length();
            (l - s.rest_length) / s.rest_length
        })
        .collect()
}

/// Per particle, the strain of largest magnitude among its springs.
pub fn particle_spring_strain(model: &Model, state: &State) -> Vec<f64> {
    let mut out = vec![0.0f64; model.particle_count()];
    for (s, e) in model.springs.iter().zip(spring_strain(model, state)) {
        for i in [s.i as usize, s.j as usize] {
            if e.abs() > out[i].abs() {
                out[i] = e;
            }
        }
    }
    out
}

/// `V / V0 - 1` of every element.
pub fn element_volume_change(model: &Model, state: &State) -> Vec<f64> {
    model
        .tets
        .iter()
        .zip(&model.rest_volume)
        .map(|(t, v0)| {
            let p = t.map(|i| state.positions[i as usize]);
            crate::mesh::signed_volume(p[0], p[1], p[2], p[3]) / v0 - 1.0
        })
        .collect()
}

/// Per element, the strain of largest magnitude among its six springs.
pub fn element_max_spring_strain(model: &Model, state: &State) -> Vec<f64> {
    let strain = spring_strain(model, state);
    model
        .tet_springs
        .iter()
        .map(|springs| {
            springs
                .iter()
                .map(|&s| strain[s as usize])
                .fold(0.0f64, |a, e| if e.abs() > a.abs() { e } else { a })
        })
        .collect()
}

/// Per particle, the largest of its elements' `values` (0 for a particle of no element).
pub fn particle_largest(model: &Model, values: &[f64]) -> Vec<f64> {
    let mut out = vec![f64::NEG_INFINITY; model.particle_count()];
    for (t, v) in model.tets.iter().zip(values) {
        for &i in t {
            let o = &mut out[i as usize];
            if *v > *o || v.is_nan() {
                *o = *v;
            }
        }
    }
    for o in &mut out {
        if *o == f64::NEG_INFINITY {
            *o = 0.0;
        }
    }
    out
}

/// Per particle, the rest-volume-weighted mean of its elements' volume change.
pub fn particle_volume_change(model: &Model, state: &State) -> Vec<f64> {
    let n = model.particle_count();
    let mut sum = vec![0.0f64; n];
    let mut weight = vec![0.0f64; n];
    for ((t, v0), dv) in model
        .tets
        .iter()
        .zip(&model.rest_volume)
        .zip(element_volume_change(model, state))
    {
        for &i in t {
            sum[i as usize] += v0 * dv;
            weight[i as usize] += v0;
        }
    }
    sum.iter()
        .zip(&weight)
        .map(|(s, w)| if *w > 0.0 { s / w } else { 0.0 })
        .collect()
}

/// Young's modulus at each particle (Pa): its elements', volume-weighted.
pub fn particle_young_modulus(model: &Model) -> Vec<f64> {
    let n = model.particle_count();
    let mut sum = vec![0.0f64; n];
    let mut weight = vec![0.0f64; n];
    for (e, (t, v0)) in model.tets.iter().zip(&model.rest_volume).enumerate() {
        let scale = model.element_stiffness_scale.get(e).copied().unwrap_or(1.0);
        for &i in t {
            sum[i as usize] += v0 * scale * model.young_modulus;
            weight[i as usize] += v0;
        }
    }
    sum.iter()
        .zip(&weight)
        .map(|(s, w)| if *w > 0.0 { s / w } else { model.young_modulus })
        .collect()
}

/// Each boundary particle's share of the boundary area (m^2): a third of
/// its facets' areas, in the current state.
pub fn boundary_area(model: &Model, state: &State) -> Vec<f64> {
    let mut area = vec![0.0f64; model.particle_count()];
    for tri in &model.facets {
        let p = tri.map(|i| state.positions[i as usize]);
        let a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        for &i in tri {
            area[i as usize] += a / 3.0;
        }
    }
    area
}

/// Contact normal pressure at each particle (Pa); see
/// [`Field::ContactPressure`]. Pressure times [`boundary_area`] summed over
/// the particles is the total normal contact force.
pub fn contact_pressure(model: &Model, state: &State) -> Vec<f64> {
    let mut force = vec![0.0f64; model.particle_count()];
    for c in &state.contacts {
        let Some(tri) = model.facets.get(c.facet as usize) else {
            continue;
        };
        for a in 0..3 {
            force[tri[a] as usize] += c.weights[a] * c.normal_force;
        }
    }
    let area = boundary_area(model, state);
    force
        .iter()
        .zip(&area)
        .map(|(f, a)| if *a > 0.0 { f / a } else { 0.0 })
        .collect()
}

/// Each element's deformation gradient `F` in `state` (from its rest shape).
fn deformation_gradients(model: &Model, state: &State) -> Vec<glam::DMat3> {
    let rest = |t: &[u32; 4]| t.map(|i| model.rest_positions[i as usize]);
    model
        .tets
        .iter()
        .enumerate()
        .map(|(e, t)| {
            let b = match &model.fem {
                Some(fem) => fem.gradients[e],
                None => crate::model::fem::shape_gradients(rest(t)),
            };
            crate::forces::fem::deformation_gradient(&b, t.map(|i| state.positions[i as usize]))
        })
        .collect()
}

/// Each element's largest principal Green strain, the largest eigenvalue of
/// `E = (F^T F - I) / 2`: positive where the material is stretched in some direction (a
/// tear starts there), about `-0.5 (1 - lambda^2)` where it is only compressed.
pub fn element_green_strain(model: &Model, state: &State) -> Vec<f64> {
    deformation_gradients(model, state)
        .into_iter()
        .map(|f| {
            let c = f.transpose() * f;
            let green = faer::Mat::<f64>::from_fn(3, 3, |i, j| {
                0.5 * (c.col(j)[i] - if i == j { 1.0 } else { 0.0 })
            });
            green
                .self_adjoint_eigenvalues(faer::Side::Lower)
                .ok()
                .and_then(|l| l.last().copied())
                .unwrap_or(f64::NAN)
        })
        .collect()
}

/// Each element's von Mises stress (Pa), `sqrt(3/2 s:s)` of the deviator `s` of the Cauchy
/// stress `sigma = P F^T / J`: the elements' own law (their neo-Hookean energy with its
/// stiffening) for a continuum, and for the springs the neo-Hookean continuum of the element's
/// Young's modulus and [`Model::poisson_ratio`] that they stand for. A pressure changes nothing.
pub fn element_von_mises(model: &Model, state: &State) -> Vec<f64> {
    let gradients = deformation_gradients(model, state);
    let nu = model.poisson_ratio;
    gradients
        .into_iter()
        .enumerate()
        .map(|(e, f)| {
            let p = match &model.fem {
                Some(fem) => crate::forces::fem::stress(fem.mu[e], fem.lambda[e], fem.yeoh, f),
                None => {
                    let young = model.young_modulus
                        * model.element_stiffness_scale.get(e).copied().unwrap_or(1.0);
                    let mu = young / (2.0 * (1.0 + nu));
                    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)) + mu;
                    crate::forces::fem::stress(mu, lambda, Default::default(), f)
                }
            };
            let j = f.determinant();
            if j <= 0.0 {
                return f64::NAN;
            }
            let sigma = p * f.transpose() * (1.0 / j);
            let mean = (sigma.x_axis.x + sigma.y_axis.y + sigma.z_axis.z) / 3.0;
            let mut s2 = 0.0;
            for i in 0..3 {
                for k in 0..3 {
                    let d = sigma.col(k)[i] - if i == k { mean } else { 0.0 };
                    s2 += d * d;
                }
            }
            (1.5 * s2).sqrt()
        })
        .collect()
}

/// A colour (linear RGB, 0..1) for `t` in 0..1: a perceptually ordered
/// sequential map (dark blue, teal, green, yellow: viridis's stops) for
/// unsigned fields, a diverging blue-white-red map (Moreland's cool-warm)
/// centred on t = 0.5 for signed ones.
pub fn colormap(t: f64, signed: bool) -> [f32; 3] {
    const VIRIDIS: [[f64; 3]; 5] = [
        [0.267, 0.005, 0.329],
        [0.230, 0.322, 0.546],
        [0.128, 0.567, 0.551],
        [0.369, 0.789, 0.383],
        [0.993, 0.906, 0.144],
    ];
    const COOL_WARM: [[f64; 3]; 3] = [
        [0.230, 0.299, 0.754],
        [0.865, 0.865, 0.865],
        [0.706, 0.016, 0.150],
    ];
    let stops: &[[f64; 3]] = if signed { &COOL_WARM } else { &VIRIDIS };
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (stops.len() - 1) as f64;
    let k = (x.floor() as usize).min(stops.len() - 2);
    let f = x - k as f64;
    let c = DVec3::from_array(stops[k]).lerp(DVec3::from_array(stops[k + 1]), f);
    c.as_vec3().to_array()
}

/// The colour-map range for `values`: `[0, max]` for an unsigned field,
/// `[-m, m]` with `m` the largest magnitude for a signed one; never empty.
pub fn range(values: &[f64], signed: bool) -> (f64, f64) {
    let largest = values
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let m = if largest > 0.0 { largest } else { 1e-12 };
    if signed { (-m, m) } else { (0.0, m) }
}

#[cfg(test)]
mod tests {
    use super::colormap;
    use crate::fields;

    #[test]
    fn colour_maps_run_from_their_ends_and_centre_signed_fields_on_grey() {
        // Sequential: brightness rises from end to end.
        let luminance = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut last = -1.0;
        for k in 0..=20 {
            let l = luminance(colormap(k as f64 / 20.0, false));
            assert!(l > last, "luminance falls at {k}");
            last = l;
        }
        // Diverging: blue below, red above, neutral at the centre.
        let mid = colormap(0.5, true);
        assert!((mid[0] - mid[1]).abs() < 1e-6 && (mid[1] - mid[2]).abs() < 1e-6);
        let low = colormap(0.0, true);
        let high = colormap(1.0, true);
        assert!(low[2] > low[0] && high[0] > high[2]);
        // Out of range and NaN clamp instead of failing.
        assert_eq!(colormap(-3.0, false), colormap(0.0, false));
        assert_eq!(colormap(7.0, true), colormap(1.0, true));
        assert_eq!(colormap(f64::NAN, false), colormap(0.0, false));
        // Ranges: signed ones symmetric, never empty.
        assert_eq!(fields::range(&[-0.2, 0.1], true), (-0.2, 0.2));
        assert_eq!(fields::range(&[0.0, 3.0, 1.0], false), (0.0, 3.0));
        let (lo, hi) = fields::range(&[0.0, 0.0], false);
        assert!(hi > lo);
    }
}
