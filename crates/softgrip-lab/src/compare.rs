//! Comparing a simulation with a recording: markers attached to the
//! material point of the nearest boundary facet (spec: "A marker follows
//! the material point of the surface nearest its reference position"),
//! and the error measures of the thesis (eq. 45-46) as the spec defines
//! them.

use glam::DVec3;

use crate::recording::MarkerRef;
use softgrip_core::geometry::closest_point_on_triangle;
use softgrip_core::model::Model;
use softgrip_core::state::State;

/// Where a marker sits on the object: a boundary facet and the barycentric
/// weights of the point nearest its reference position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attachment {
    /// Index of the boundary facet in the model's `facets`.
    pub facet: u32,
    /// Barycentric weights of the point on that facet's three nodes.
    pub weights: [f64; 3],
    /// How far the reference position was from the undeformed surface (m).
    pub distance: f64,
}

/// Attaches each reference position to the nearest point of the
/// undeformed boundary (ties: the lowest facet index, so it is
/// deterministic).
pub fn attach(model: &Model, references: &[DVec3]) -> Vec<Attachment> {
    references
        .iter()
        .map(|r| {
            let mut best = Attachment {
                facet: 0,
                weights: [1.0 / 3.0; 3],
                distance: f64::INFINITY,
            };
            for (j, tri) in model.facets.iter().enumerate() {
                let [a, b, c] = tri.map(|i| model.rest_positions[i as usize]);
                let (point, weights, _) = closest_point_on_triangle(*r, a, b, c);
                let d = point.distance(*r);
                if d < best.distance {
                    best = Attachment {
                        facet: j as u32,
                        weights,
                        distance: d,
                    };
                }
            }
            best
        })
        .collect()
}

/// The attached material point in `state`.
pub fn position(model: &Model, state: &State, a: &Attachment) -> DVec3 {
    let tri = model.facets[a.facet as usize];
    (0..3)
        .map(|k| a.weights[k] * state.positions[tri[k] as usize])
        .sum()
}

/// A marker's simulated position: an object marker's material point, or
/// a finger's centre.
pub fn marker_position(
    model: &Model,
    state: &State,
    attachments: &[Attachment],
    marker: MarkerRef,
) -> Option<DVec3> {
    match marker {
        MarkerRef::Object(k) => attachments.get(k).map(|a| position(model, state, a)),
        MarkerRef::Finger(k) => state.fingers.get(k).map(|f| f.position),
    }
}

/// One compared observation: simulated against recorded over the observed
/// axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residual {
    /// Index of the sample, from 0.
    pub sample: usize,
    /// The marker.
    pub marker: MarkerRef,
    /// Its simulated position, m.
    pub simulated: DVec3,
    /// Its recorded position per axis x, y, z, m; `None` where not observed.
    pub recorded: [Option<f64>; 3],
}

impl Residual {
    /// Simulated minus recorded, 0 on unobserved axes (m).
    pub fn difference(&self) -> DVec3 {
        DVec3::from_array(std::array::from_fn(|a| {
            self.recorded[a].map_or(0.0, |r| self.simulated[a] - r)
        }))
    }

    /// Euclidean distance over the observed axes (m).
    pub fn distance(&self) -> f64 {
        self.difference().length()
    }
}

/// The spec's measures of a set of residuals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// Root mean square of the distances over the object markers (the
    /// finger markers when there are no object markers), m.
    pub rmse_m: f64,
    /// `rmse_m` over the object's largest extent.
    pub nrmse: f64,
    /// The same over all markers, fingers included.
    pub rmse_all_m: f64,
    /// `rmse_all_m` over the object's largest extent.
    pub nrmse_all: f64,
    /// Observations counted in `rmse_m`.
    pub count: usize,
}

fn rms(values: impl Iterator<Item = f64>) -> (f64, usize) {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), d| (s + d * d, n + 1));
    if n == 0 {
        (0.0, 0)
    } else {
        ((sum / n as f64).sqrt(), n)
    }
}

/// RMSE and NRMSE (thesis eq. 45-46 as the spec defines them): over all
/// object markers and samples, fingers excluded unless there are no
/// object markers; `extent` is the object's largest extent (m).
pub fn errors(residuals: &[Residual], extent: f64) -> Errors {
    let (rmse, count) = rms(scored(residuals).map(Residual::distance));
    let (rmse_all, _) = rms(residuals.iter().map(Residual::distance));
    Errors {
        rmse_m: rmse,
        nrmse: rmse / extent,
        rmse_all_m: rmse_all,
        nrmse_all: rmse_all / extent,
        count,
    }
}

/// The residuals NRMSE counts: the object markers', or the fingers' when
/// there are no object markers.
pub fn scored(residuals: &[Residual]) -> impl Iterator<Item = &Residual> {
    let object = residuals
        .iter()
        .any(|r| matches!(r.marker, MarkerRef::Object(_)));
    residuals
        .iter()
        .filter(move |r| !object || matches!(r.marker, MarkerRef::Object(_)))
}

/// The scored residuals as one vector of simulated-minus-recorded
/// components over the observed axes (m), in residual order: what a
/// least-squares view of NRMSE works with (NRMSE^2 = |r|^2 / (count
/// extent^2)).
pub fn components(residuals: &[Residual]) -> Vec<f64> {
    let mut out = Vec::new();
    for r in scored(residuals) {
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                out.push(r.simulated[a] - x);
            }
        }
    }
    out
}

/// One marker's root-mean-square residual per axis (`None` where the axis
/// was never observed) and of the distance, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarkerError {
    /// The marker.
    pub marker: MarkerRef,
    /// RMS residual per axis x, y, z, m.
    pub axes: [Option<f64>; 3],
    /// RMS distance over the observed axes, m.
    pub distance: f64,
}

/// [`MarkerError`] of every marker in `residuals`, in marker order.
pub fn per_marker(residuals: &[Residual]) -> Vec<MarkerError> {
    let mut markers: Vec<MarkerRef> = residuals.iter().map(|r| r.marker).collect();
    markers.sort();
    markers.dedup();
    markers
        .into_iter()
        .map(|m| {
            let rs: Vec<&Residual> = residuals.iter().filter(|r| r.marker == m).collect();
            let axes = std::array::from_fn(|a| {
                let (s, n) = rms(rs
                    .iter()
                    .filter_map(|r| r.recorded[a].map(|x| r.simulated[a] - x)));
                (n > 0).then_some(s)
            });
            MarkerError {
                marker: m,
                axes,
                distance: rms(rs.iter().map(|r| r.distance())).0,
            }
        })
        .collect()
}
