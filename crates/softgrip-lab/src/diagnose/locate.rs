//! Where and when the residual stands out of the noise: each marker, axis and region of the
//! object against a chi-square test at three of its standard deviations, and how the residual
//! depends on the sample (grows with load, only on unloading, late at constant load).

use std::collections::HashMap;

use glam::DVec3;

use super::noise::{Noise, marker_key, weighted_rss};
use super::statistics::{significant, spearman};
use crate::compare::Residual;
use crate::recording::{MarkerRef, Mode, Recording};
use crate::replay::Replay;

/// Where and when the residual stands out of the noise.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Location {
    /// Markers whose residual is significant, worst first, with their RMS
    /// residual over the noise.
    pub markers: Vec<(String, f64)>,
    /// Axes ("x", "y", "z") whose residual is significant.
    pub axes: Vec<String>,
    /// Regions of the object whose markers' residual is significant, with
    /// RMS over noise, worst first.
    pub regions: Vec<(String, f64)>,
    /// How it depends on the sample.
    pub when: String,
    /// In words.
    pub description: String,
    /// The whole residual's chi-square and degrees of freedom.
    pub chi2: f64,
    /// Degrees of freedom of `chi2`: the coordinates recorded.
    pub dof: usize,
    /// Whether `chi2` is beyond three standard deviations of its distribution
    /// (`statistics::significant`).
    pub significant: bool,
}

impl Location {
    /// The RMS residual over the noise, `sqrt(chi2 / dof)`.
    pub(super) fn over_noise(&self) -> f64 {
        (self.chi2 / self.dof.max(1) as f64).sqrt()
    }
}

/// Locates the residual of `replay` against `noise`.
pub fn locate(recording: &Recording, replay: &Replay, noise: &Noise) -> Location {
    let residuals = &replay.residuals;
    let (chi2, n) = weighted_rss(residuals, noise);
    let mut loc = Location {
        chi2,
        dof: n,
        significant: significant(chi2, n),
        ..Location::default()
    };
    // Per marker.
    let mut per_marker: HashMap<MarkerRef, (f64, usize)> = HashMap::new();
    let mut per_axis = [(0.0, 0usize); 3];
    for r in residuals {
        let s = noise.sigma(r.marker);
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                let e = ((r.simulated[a] - x) / s).powi(2);
                let m = per_marker.entry(r.marker).or_default();
                m.0 += e;
                m.1 += 1;
                per_axis[a].0 += e;
                per_axis[a].1 += 1;
            }
        }
    }
    let mut markers: Vec<(MarkerRef, f64, usize)> = per_marker
        .into_iter()
        .map(|(m, (c, k))| (m, c, k))
        .collect();
    markers.sort_by_key(|(m, _, _)| marker_key(*m));
    let mut named: Vec<(String, f64)> = markers
        .iter()
        .filter(|(_, c, k)| significant(*c, *k))
        .map(|(m, c, k)| (recording.marker_name(*m), (c / *k as f64).sqrt()))
        .collect();
    named.sort_by(|a, b| b.1.total_cmp(&a.1));
    loc.markers = named;
    loc.axes = ["x", "y", "z"]
        .iter()
        .zip(per_axis)
        .filter(|(_, (c, k))| *k > 0 && significant(*c, *k))
        .map(|(a, _)| a.to_string())
        .collect();
    // Per region, over object markers.
    let (lo, hi) = softgrip_core::mesh::bounds_of(
        &recording
            .markers
            .iter()
            .map(|m| m.reference)
            .collect::<Vec<_>>(),
    );
    let (lo, hi) = object_bounds(recording).unwrap_or((lo, hi));
    let finger = recording.scene.fingers.first().map(|f| f.position);
    let mut per_region: HashMap<&'static str, (f64, usize)> = HashMap::new();
    for (m, c, k) in &markers {
        if let MarkerRef::Object(i) = m {
            for name in regions_of(recording.markers[*i].reference, lo, hi, finger) {
                let e = per_region.entry(name).or_default();
                e.0 += c;
                e.1 += k;
            }
        }
    }
    let mut regions: Vec<(String, f64)> = per_region
        .into_iter()
        .filter(|(_, (c, k))| significant(*c, *k))
        .map(|(name, (c, k))| (name.to_string(), (c / k as f64).sqrt()))
        .collect();
    regions.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    loc.regions = regions;
    loc.when = when(recording, residuals, noise);
    loc.description = description(&loc);
    loc
}

/// The location in words: who, where, along which axes, and when.
fn description(loc: &Location) -> String {
    // The first `n` names of a list, worst first.
    let first = |named: &[(String, f64)], n: usize| {
        named
            .iter()
            .take(n)
            .map(|(name, _)| name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if !loc.significant {
        "the residual is at the noise level".into()
    } else {
        let who = if loc.markers.is_empty() {
            "spread thinly over every marker".to_string()
        } else {
            format!("markers {}", first(&loc.markers, 4))
        };
        let regions = if loc.regions.is_empty() {
            String::new()
        } else {
            format!(" ({})", first(&loc.regions, 2))
        };
        let axes = if loc.axes.is_empty() {
            String::new()
        } else {
            format!(", along {}", loc.axes.join(" and "))
        };
        format!("{who}{regions}{axes}; {}", loc.when)
    }
}

/// The named regions a marker at `p` belongs to, on an object with bounds
/// `lo..hi`, pressed by a finger starting at `finger`.
fn regions_of(p: DVec3, lo: DVec3, hi: DVec3, finger: Option<DVec3>) -> Vec<&'static str> {
    let size = hi - lo;
    let centre = 0.5 * (lo + hi);
    let mut out = Vec::new();
    if let Some(f) = finger {
        let near = (p.truncate() - f.truncate()).length() < 0.25 * size.truncate().max_element()
            && p.z > hi.z - 0.25 * size.z;
        if near {
            out.push("contact zone");
        }
    }
    if p.z < lo.z + 0.25 * size.z {
        out.push("base");
    }
    if p.z > hi.z - 0.25 * size.z {
        out.push("top");
    }
    let side =
        (p.x - lo.x).min(hi.x - p.x) < 0.1 * size.x || (p.y - lo.y).min(hi.y - p.y) < 0.1 * size.y;
    if side {
        out.push("sides");
    }
    if p.x < centre.x - 0.05 * size.x {
        out.push("left half");
    } else if p.x > centre.x + 0.05 * size.x {
        out.push("right half");
    }
    out
}

/// The object's undeformed bounds, from its scene.
fn object_bounds(recording: &Recording) -> Option<(DVec3, DVec3)> {
    let mesh = softgrip_core::model::Model::mesh_of(&recording.scene).ok()?;
    Some(mesh.bounds())
}

/// How the residual depends on the samples, in words.
fn when(recording: &Recording, residuals: &[Residual], noise: &Noise) -> String {
    let samples = &recording.samples;
    if samples.len() < 3 {
        return "too few samples to say when".into();
    }
    // Mean squared residual per sample (over noise).
    let mut per_sample = vec![(0.0, 0usize); samples.len()];
    for r in residuals {
        let s = noise.sigma(r.marker);
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                per_sample[r.sample].0 += ((r.simulated[a] - x) / s).powi(2);
                per_sample[r.sample].1 += 1;
            }
        }
    }
    let level: Vec<f64> = per_sample
        .iter()
        .map(|(c, k)| if *k > 0 { c / *k as f64 } else { 0.0 })
        .collect();
    let mean = |idx: &[usize]| {
        if idx.is_empty() {
            0.0
        } else {
            idx.iter().map(|&i| level[i]).sum::<f64>() / idx.len() as f64
        }
    };
    match recording.mode {
        Mode::QuasiStatic => {
            let unloading: Vec<usize> = (1..samples.len())
                .filter(|&i| samples[i].load < samples[i - 1].load)
                .collect();
            let loading: Vec<usize> = (0..samples.len())
                .filter(|i| !unloading.contains(i))
                .collect();
            if !unloading.is_empty() && mean(&unloading) > 3.0 * mean(&loading).max(1.0) {
                return "mostly on unloading".into();
            }
            // Rank correlation of the residual with the load on the way up.
            let loads: Vec<f64> = loading.iter().map(|&i| samples[i].load).collect();
            let levels: Vec<f64> = loading.iter().map(|&i| level[i]).collect();
            if spearman(&loads, &levels) > 0.7 {
                "grows with load".into()
            } else {
                "at every load".into()
            }
        }
        Mode::TimeSeries => {
            // Within each constant-load stretch: the later half against
            // the earlier half.
            let mut early = Vec::new();
            let mut late = Vec::new();
            let mut start = 0;
            for i in 1..=samples.len() {
                if i == samples.len() || samples[i].load != samples[start].load {
                    let len = i - start;
                    for (j, k) in (start..i).enumerate() {
                        if 2 * j < len {
                            early.push(k);
                        } else {
                            late.push(k);
                        }
                    }
                    start = i;
                }
            }
            if mean(&late) > 2.0 * mean(&early).max(1.0) {
                "grows late in time at constant load".into()
            } else if mean(&early) > 2.0 * mean(&late).max(1.0) {
                "right after load changes".into()
            } else {
                "throughout".into()
            }
        }
    }
}
