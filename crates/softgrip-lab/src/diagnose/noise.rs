//! The noise level, from the data: per marker and axis, the second differences of a residual
//! along the samples (`sigma^2 = mean(d2^2) / 6`), within each run of samples whose load moves
//! one way. A mismatch that varies smoothly with load or time cancels out of second
//! differences; white measurement noise does not. Object markers and fingers get their own
//! sigma. Also the residuals weighed by it, which the diagnosis and the discretisation check
//! (`crate::discretisation`) share. Why this estimator: `docs/design/diagnosis.md`.

use std::collections::HashMap;

use crate::compare::Residual;
use crate::recording::{MarkerRef, Recording};

/// The noise level, estimated from the data (m, one standard deviation per
/// coordinate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// The object markers' noise, m.
    pub object_m: f64,
    /// The finger markers' noise, m.
    pub finger_m: f64,
    /// How many second differences the object's estimate rests on.
    pub object_count: usize,
    /// How many second differences the fingers' estimate rests on.
    pub finger_count: usize,
}

/// The least noise level [`estimate_noise`] gives (m): a recording whose
/// residual has no second differences (a noise-free one, replayed by the
/// model that made it) sits here, and a move "over the noise" means nothing.
pub const NOISE_FLOOR_M: f64 = 1e-6;

impl Noise {
    /// False when both levels are at [`NOISE_FLOOR_M`]: the data showed no
    /// noise to measure moves against.
    pub fn measured(&self) -> bool {
        self.object_m > NOISE_FLOOR_M || self.finger_m > NOISE_FLOOR_M
    }

    /// Whether the class of `marker` (object markers, fingers) showed
    /// noise: above [`NOISE_FLOOR_M`].
    pub fn measured_on(&self, marker: MarkerRef) -> bool {
        self.sigma(marker) > NOISE_FLOOR_M
    }

    /// "0.084 mm on object markers, 0.098 mm on fingers"; a class with no
    /// differences of its own (no finger in the recording) took the
    /// other's level and is said to be not measured.
    pub fn describe(&self) -> String {
        let level = |m: f64, count: usize| {
            if count < 3 {
                "none measured".to_string()
            } else if m <= NOISE_FLOOR_M {
                "none (noise-free data)".to_string()
            } else {
                format!("{:.3} mm", m * 1e3)
            }
        };
        format!(
            "{} on object markers, {} on fingers",
            level(self.object_m, self.object_count),
            level(self.finger_m, self.finger_count)
        )
    }

    /// The level of `marker`'s class: object markers or fingers.
    pub(super) fn sigma(&self, marker: MarkerRef) -> f64 {
        match marker {
            MarkerRef::Object(_) => self.object_m,
            MarkerRef::Finger(_) => self.finger_m,
        }
    }
}

/// Per marker and axis, (sample, residual component) in sample order.
fn series_indexed(residuals: &[Residual]) -> HashMap<(MarkerRef, usize), Vec<(usize, f64)>> {
    let mut out: HashMap<(MarkerRef, usize), Vec<(usize, f64)>> = HashMap::new();
    for r in residuals {
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                out.entry((r.marker, a))
                    .or_default()
                    .push((r.sample, r.simulated[a] - x));
            }
        }
    }
    for v in out.values_mut() {
        v.sort_by_key(|(s, _)| *s);
    }
    out
}

/// The noise from second differences of the residual along the samples
/// (see the module docs). A class with too few differences (fewer than 3)
/// takes the other's level, or a floor of 1 um.
pub fn estimate_noise(residuals: &[Residual]) -> Noise {
    estimate_noise_split(residuals, &[])
}

/// As [`estimate_noise`], the second differences taken only within runs of
/// samples between the `breaks` (sample indices where the load turns).
pub fn estimate_noise_split(residuals: &[Residual], breaks: &[usize]) -> Noise {
    let mut sums = [(0.0, 0usize); 2];
    let run_of = |s: usize| breaks.iter().filter(|&&b| b <= s).count();
    let mut keys: Vec<_> = series_indexed(residuals).into_iter().collect();
    keys.sort_by_key(|((m, a), _)| (marker_key(*m), *a));
    for ((marker, _), values) in keys {
        let class = matches!(marker, MarkerRef::Finger(_)) as usize;
        for w in values.windows(3) {
            if run_of(w[0].0) != run_of(w[2].0) {
                continue;
            }
            let d2 = w[0].1 - 2.0 * w[1].1 + w[2].1;
            sums[class].0 += d2 * d2;
            sums[class].1 += 1;
        }
    }
    let level = |(sum, n): (f64, usize)| (n >= 3).then(|| (sum / (6.0 * n as f64)).sqrt());
    let (object, finger) = (level(sums[0]), level(sums[1]));
    let floor = NOISE_FLOOR_M;
    let object_m = object.or(finger).unwrap_or(floor).max(floor);
    let finger_m = finger.or(object).unwrap_or(floor).max(floor);
    Noise {
        object_m,
        finger_m,
        object_count: sums[0].1,
        finger_count: sums[1].1,
    }
}

/// The samples where the load turns (from loading to unloading or back), as
/// [`estimate_noise_split`] takes its breaks: a residual turns where the load
/// turns, and across the turn its second differences would count as noise.
pub(super) fn load_turns(recording: &Recording) -> Vec<usize> {
    let loads: Vec<f64> = recording.samples.iter().map(|s| s.load).collect();
    (1..loads.len().saturating_sub(1))
        .filter(|&i| (loads[i] - loads[i - 1]) * (loads[i + 1] - loads[i]) < 0.0)
        .map(|i| i + 1)
        .collect()
}

/// Markers in a stable order: object markers by index, then fingers.
pub(super) fn marker_key(m: MarkerRef) -> (u8, usize) {
    match m {
        MarkerRef::Object(k) => (0, k),
        MarkerRef::Finger(k) => (1, k),
    }
}

/// The RMS distance of `residuals` (over every marker, fingers included,
/// as `nrmse_all` takes it) beyond what `noise` accounts for, m:
/// `sqrt(max(0, mean(d^2) - mean(sum of sigma^2 over the observed axes)))`,
/// the noise being independent of the model's error. 0 where the residual
/// is within the noise (the difference is then the estimate's own scatter).
pub fn rms_beyond_noise(residuals: &[Residual], noise: &Noise) -> f64 {
    let (mut d2, mut s2, mut n) = (0.0, 0.0, 0usize);
    for r in residuals {
        // Counted as `nrmse_all` counts it (an unobserved one as 0).
        let axes = r.recorded.iter().filter(|x| x.is_some()).count();
        d2 += r.difference().length_squared();
        s2 += axes as f64 * noise.sigma(r.marker).powi(2);
        n += 1;
    }
    if n == 0 {
        return 0.0;
    }
    ((d2 - s2) / n as f64).max(0.0).sqrt()
}

/// The noise-weighted residual sum of squares over every observed
/// component (fingers included), and the number of components.
pub fn weighted_rss(residuals: &[Residual], noise: &Noise) -> (f64, usize) {
    let mut rss = 0.0;
    let mut n = 0;
    for r in residuals {
        let s = noise.sigma(r.marker);
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                let e = (r.simulated[a] - x) / s;
                rss += e * e;
                n += 1;
            }
        }
    }
    (rss, n)
}

/// The residual of every observed component over its noise level
/// (fingers included), in the order of `residuals`.
pub fn weighted_residuals(residuals: &[Residual], noise: &Noise) -> Vec<f64> {
    let mut out = Vec::with_capacity(3 * residuals.len());
    for r in residuals {
        let s = noise.sigma(r.marker);
        for a in 0..3 {
            if let Some(x) = r.recorded[a] {
                out.push((r.simulated[a] - x) / s);
            }
        }
    }
    out
}
