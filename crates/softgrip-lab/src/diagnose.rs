//! Missing-physics diagnosis: when a fitted simulation and a recording still
//! differ, find where, name the physics the model left out, add it, fit it
//! and show the fit improve; say "none" when the residual is noise.
//!
//! 1. **Baseline.** The nominal model's uncertain parameters (E, alpha,
//!    tau_s, tau_c unless locked) are fitted to the recording, with every
//!    marker counted, the fingers' included: force lost along the load path
//!    or creep move the finger more than the object.
//! 2. **Noise**, from the data: per marker and axis, the second differences
//!    of the baseline's residual along the samples (`sigma^2 = mean(d2^2) /
//!    6`, Rice's estimator taken one order further), within each run of
//!    samples whose load moves one way (a residual turns where the load
//!    turns, and across the turn it would count as noise). A mismatch that
//!    varies smoothly with load or time cancels out of second differences;
//!    white measurement noise does not. Object markers and fingers get
//!    their own sigma.
//! 3. **Locate.** Each marker, axis and region's residual against that
//!    noise (a chi-square test at three of its standard deviations), and
//!    how the residual depends on the sample (grows with load, only on
//!    unloading, late at constant load).
//! 4. **Explain.** A catalogue of candidate effects, each a model
//!    extension of issue 6 with its own parameters, is fitted (its
//!    parameters plus the modulus, from the current fit). Besides the
//!    spec's six, time series get `damping` (the springs' damping ratio):
//!    a swing that dies faster or slower than the model's. Candidates are
//!    compared by the Bayesian information criterion of a Gaussian
//!    likelihood with the noise level free, `n ln(RSS / n) + k ln n` (RSS
//!    the noise-weighted residual sum of squares): it needs no refits
//!    (cross-validation on held-out samples would need one per fold per
//!    candidate, and a recording has 7 to 30 samples) and penalises each
//!    parameter by `ln n`. An effect is accepted when it lowers BIC by more
//!    than 10 ("very strong" evidence, Kass and Raftery 1995), removes at
//!    least a tenth of the residual sum of squares, **and** fits closer
//!    than the best candidate of any other effect by Vuong's test for
//!    non-nested models (`z >= 2`, about the 5 % level; with no other
//!    effect fitted in its round, than the model without it by the same
//!    test): the model's own
//!    form error (a lattice against a continuum, a coarse mesh against a
//!    fine one) is a smooth mismatch that several extra parameters absorb
//!    a little of each, none specifically, and that must not be named as
//!    missing physics. (Until 2026-11-23 the second condition was a third
//!    of the residual and there was no third: a weak heterogeneity
//!    removing 24 % was missed while a control's 32 % was named.) Accepted
//!    effects stay in and the rest are tried again (greedy), so two
//!    effects present at once are both found.
//! 5. **Verdict**: the effects found, or "none" (the residual is at the
//!    noise level, or nothing explains a significant share of it), or
//!    "unexplained" (a significant mismatch, with its location, that no
//!    candidate explains).

use std::collections::HashMap;

use glam::DVec3;

use crate::compare::{Errors, Residual};
use crate::discretisation::Discretisation;
use crate::fit::{FitOptions, FitParam, levenberg_marquardt};
use crate::params;
use crate::recording::{MarkerRef, Mode, Recording};
use crate::replay::{Replay, ReplayOptions, replay};
use crate::sweep::parallel_map;
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::{AaBox, Region, Scene, SupportKind};

/// Candidates that removed less than this share of the residual in the
/// first round are not tried again in later rounds.
pub const PROMISING: f64 = 0.05;
/// BIC must fall by more than this for an effect to be accepted.
pub const BIC_THRESHOLD: f64 = 10.0;
/// ... and the weighted residual sum of squares by at least this share ...
pub const MIN_EXPLAINED: f64 = 0.1;
/// ... and Vuong's statistic against the best other effect must reach this.
pub const VUONG_Z: f64 = 2.0;

/// Finite-difference step of the fits' Jacobian, in the unit box of each
/// parameter (2 % of E over its log range): large enough to stand above
/// the rest tolerance of a quasi-static replay.
pub const JACOBIAN_STEP: f64 = 0.01;

/// Local searches at most per fit: from its best point and, where its
/// `Search` says, from the next best (see `fit_model`).
pub const LOCAL_SEARCHES: usize = 2;

/// Where a fit searches from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Search {
    /// Levenberg-Marquardt from the best of the start and the given
    /// starts (a refit whose start is already near its optimum).
    Local,
    /// Also a small space-filling design, and the search from its best
    /// point.
    Design,
    /// The design, and searches from its best and next best points (the
    /// baseline: on control-3 at `b42c5be` the first search ended at NRMSE
    /// 0.0041 and the second found 0.0032, the noise's level).
    Twice,
    /// The design, and a second search from the next best point when the
    /// first explains a share (PROMISING) of the current fit's residual
    /// (a candidate).
    Contender,
}
/// A mismatch no candidate explains is "unexplained" when the baseline's
/// RMS residual is more than this many times the noise; below, the
/// verdict is "none": a residual within a few noise levels that no
/// physics explains is the model's own form error (a lattice against a
/// continuum, one mesh against another), not missing physics.
pub const UNEXPLAINED_RATIO: f64 = 3.0;

/// How a diagnosis runs.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagnoseOptions {
    /// Baseline parameters not to fit (kept at the scene's values).
    pub lock: Vec<String>,
    /// Ranges the user knows parameters to lie in, `(name, low, high)`:
    /// every fit that moves the parameter (the baseline's, each
    /// candidate's, the pair's) searches only there. E measured as the
    /// thesis did (the initial slope of a compression test, its section
    /// V.B) is a small-strain modulus: a fit that needs 3.6 times it
    /// (the suite's strain-stiffening-strong at `0120c43`) is absorbing
    /// physics the model lacks.
    pub bounds: Vec<(String, f64, f64)>,
    /// Simulations at most for the baseline fit ...
    pub max_evaluations: usize,
    /// ... and per parameter for each candidate's (a design of 2 points
    /// per parameter, then the local searches; the candidates start from
    /// the current fit's values).
    pub candidate_evaluations_per_param: usize,
    /// Simulations at once (0: one per core).
    pub workers: usize,
    /// At most this many effects are added.
    pub max_effects: usize,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            lock: Vec::new(),
            bounds: Vec::new(),
            max_evaluations: 80,
            candidate_evaluations_per_param: 20,
            workers: 0,
            max_effects: 2,
        }
    }
}

/// The noise level, estimated from the data (m, one standard deviation per
/// coordinate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    pub object_m: f64,
    pub finger_m: f64,
    /// How many second differences each estimate rests on.
    pub object_count: usize,
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

    fn sigma(&self, marker: MarkerRef) -> f64 {
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

fn marker_key(m: MarkerRef) -> (u8, usize) {
    match m {
        MarkerRef::Object(k) => (0, k),
        MarkerRef::Finger(k) => (1, k),
    }
}

/// The marker's name in the recording.
pub fn marker_name(recording: &Recording, m: MarkerRef) -> String {
    match m {
        MarkerRef::Object(k) => recording.markers[k].name.clone(),
        MarkerRef::Finger(0) => "finger".into(),
        MarkerRef::Finger(k) => format!("finger{k}"),
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

/// BIC of a least-squares fit with the noise level free.
pub fn bic(rss: f64, n: usize, k: usize) -> f64 {
    let n = n.max(1) as f64;
    n * (rss.max(1e-300) / n).ln() + k as f64 * n.ln()
}

/// Is a candidate's evidence enough to name its effect?
pub fn accepted(h: &Hypothesis) -> bool {
    h.score < -BIC_THRESHOLD
        && h.explained >= MIN_EXPLAINED
        // Against the best other effect or, with none fitted in its
        // round, against the model without it.
        && h.vuong.is_some_and(|z| z >= VUONG_Z)
}

/// Vuong's statistic for two non-nested least-squares models fitted to the
/// same data, from their residuals (same order, weighted alike):
/// `sqrt(n) mean(d) / sd(d)` with `d_i = b_i^2 - a_i^2`, asymptotically
/// standard normal when neither model is closer to the truth; positive
/// when `a` fits closer. None when the residuals do not pair up.
pub fn vuong(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.len() < 3 {
        return None;
    }
    let d: Vec<f64> = a.iter().zip(b).map(|(a, b)| b * b - a * a).collect();
    Some(mean_over_error(&d))
}

/// `sqrt(n) mean(d) / sd(d)`: infinite with the sign of the mean when
/// every `d` is alike, 0 when they are all 0.
fn mean_over_error(d: &[f64]) -> f64 {
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    if var <= 0.0 {
        return if mean == 0.0 {
            0.0
        } else {
            mean.signum() * f64::INFINITY
        };
    }
    n.sqrt() * mean / var.sqrt()
}

/// Is a chi-square of `chi2` on `dof` degrees of freedom beyond three of
/// its standard deviations?
pub fn significant(chi2: f64, dof: usize) -> bool {
    let d = dof.max(1) as f64;
    chi2 > d + 3.0 * (2.0 * d).sqrt()
}

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
    pub dof: usize,
    pub significant: bool,
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
        .map(|(m, c, k)| (marker_name(recording, *m), (c / *k as f64).sqrt()))
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
    loc.description = if !loc.significant {
        "the residual is at the noise level".into()
    } else {
        let who = if loc.markers.is_empty() {
            "spread thinly over every marker".to_string()
        } else {
            format!(
                "markers {}",
                loc.markers
                    .iter()
                    .take(4)
                    .map(|(m, _)| m.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        let regions = if loc.regions.is_empty() {
            String::new()
        } else {
            format!(
                " ({})",
                loc.regions
                    .iter()
                    .take(2)
                    .map(|(r, _)| r.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        let axes = if loc.axes.is_empty() {
            String::new()
        } else {
            format!(", along {}", loc.axes.join(" and "))
        };
        format!("{who}{regions}{axes}; {}", loc.when)
    };
    loc
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

/// Spearman's rank correlation (0 for fewer than 3 points or no spread).
fn spearman(a: &[f64], b: &[f64]) -> f64 {
    if a.len() < 3 {
        return 0.0;
    }
    let rank = |v: &[f64]| {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        let mut r = vec![0.0; v.len()];
        for (k, &i) in idx.iter().enumerate() {
            r[i] = k as f64;
        }
        r
    };
    let (ra, rb) = (rank(a), rank(b));
    let n = ra.len() as f64;
    let ma = ra.iter().sum::<f64>() / n;
    let mb = rb.iter().sum::<f64>() / n;
    let cov: f64 = ra.iter().zip(&rb).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = ra.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = rb.iter().map(|y| (y - mb).powi(2)).sum();
    if va <= 0.0 || vb <= 0.0 {
        0.0
    } else {
        cov / (va * vb).sqrt()
    }
}

/// A candidate effect: a change to the scene and the parameters it brings.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The spec's name (`table-friction`, ...).
    pub effect: &'static str,
    /// Which variant, for effects with several (the region's half).
    pub variant: String,
    /// The scene with the effect added (at its parameters' start values).
    pub scene: Scene,
    pub params: Vec<FitParam>,
    /// For an effect whose start has it switched on: the values of
    /// `params` at which it is off, i.e. the model it is added to. The fit
    /// takes that point as a floor (it ends no worse), not as a start to
    /// search from.
    pub off: Option<Vec<f64>>,
}

fn param(name: &str, lower: f64, upper: f64, log: bool) -> Option<FitParam> {
    Some(FitParam {
        param: params::find(name).ok()?,
        lower,
        upper,
        log,
    })
}

/// The relaxing share the creep candidate's fit starts from.
const CREEP_START_G: f64 = 0.2;

/// The catalogue of candidate effects for `scene` (already carrying the
/// current fit) and `recording`: those that apply.
pub fn catalogue(recording: &Recording, scene: &Scene) -> Vec<Candidate> {
    let mut out = Vec::new();
    let e = scene.object.young_modulus;
    let Some(modulus) = param("young_modulus", e / 3.0, e * 3.0, true) else {
        return out;
    };
    // The modulus and the effect's own: a candidate whose parameter is not
    // known is left out rather than offered broken.
    let with_modulus = |ps: Vec<Option<FitParam>>| {
        ps.into_iter()
            .collect::<Option<Vec<_>>>()
            .map(|mut v| {
                v.insert(0, modulus);
                v
            })
            .unwrap_or_default()
    };
    let with = |f: &dyn Fn(&mut Scene)| {
        let mut s = scene.clone();
        f(&mut s);
        s
    };
    if scene.support.kind != SupportKind::None {
        out.push(Candidate {
            effect: "table-friction",
            variant: String::new(),
            scene: with(&|s| {
                s.support.kind = SupportKind::Table;
                s.support.friction = 0.0;
            }),
            params: with_modulus(vec![param("table_friction", 0.0, 2.0, false)]),
            off: None,
        });
    }
    // A spring's beta multiplies its own strain squared (a few percent in a
    // grasp); an element's, `max(I1 - 3, 0) / 3`, which is about 1 at the
    // 67 % compression of the Ecoflex recordings (incompressible, `I1 =
    // l^2 + 2 / l`): there beta 30 already multiplies the shear modulus by
    // 31.
    let stiffening_max = if scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean {
        30.0
    } else {
        3e4
    };
    out.push(Candidate {
        effect: "strain-stiffening",
        variant: String::new(),
        scene: scene.clone(),
        params: with_modulus(vec![param("stiffening", 0.0, stiffening_max, false)]),
        off: None,
    });
    // Elements can also soften first and stiffen late (filled silicones:
    // a two-term Yeoh solid, C20 < 0 < C30), which one growing term cannot
    // follow. gamma 100 multiplies the shear modulus by 101 at s = 3 (the
    // Ecoflex recordings' last level; 10 was too few: EF30_0T_A1's fit
    // ended on it), as beta 30 by 31; softening 0.95 dips it to 10 %.
    if scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean {
        out.push(Candidate {
            effect: "strain-stiffening",
            variant: "two-term".into(),
            scene: scene.clone(),
            params: with_modulus(vec![
                param("stiffening_cubic", 0.0, 100.0, false),
                param("softening", 0.0, 0.95, false),
            ]),
            off: None,
        });
    }
    if recording.mode == Mode::TimeSeries {
        out.push(Candidate {
            effect: "viscoelastic-creep",
            variant: String::new(),
            // Started inside the range, not at g = 0: with no relaxing
            // share the relaxation time moves nothing and the fit cannot
            // find its way out (creep-weak stayed at g 0.004, tau 1.0).
            // The baseline fitted the material as if fully relaxed, so the
            // start keeps that long-term modulus, E (1 - g), where it was.
            scene: with(&|s| {
                s.model.prony_g = CREEP_START_G;
                s.model.prony_tau = 1.0;
                s.object.young_modulus = e / (1.0 - CREEP_START_G);
            }),
            params: with_modulus(vec![
                param("prony_g", 0.0, 0.9, false),
                param("prony_tau", 0.05, 20.0, true),
            ]),
            // And no creep at all, the model it is added to (E, g 0, its
            // relaxation time), a floor for the fit (see `fit_model`): it
            // ends no worse than that model. After damping on the beam's
            // load52_a, the start above alone left it 9 % worse.
            off: Some(vec![e, 0.0, scene.model.prony_tau.clamp(0.05, 20.0)]),
        });
    }
    if recording.mode == Mode::TimeSeries {
        // Dissipation: the springs are damped at a ratio of their critical
        // damping (1 as the thesis sets it); a real material can lose more
        // or less energy per swing. Quasi-static samples are at rest, where
        // damping changes nothing, so it is offered for time series only.
        let d = scene.model.damping_ratio.max(0.01);
        out.push(Candidate {
            effect: "damping",
            variant: String::new(),
            scene: scene.clone(),
            params: with_modulus(vec![param("damping_ratio", d / 10.0, d * 30.0, true)]),
            off: None,
        });
    }
    if !scene.fingers.is_empty() {
        out.push(Candidate {
            effect: "finger-friction",
            variant: String::new(),
            scene: scene.clone(),
            params: with_modulus(vec![param("friction", 0.0, 2.0, false)]),
            off: None,
        });
    }
    if let Ok(mesh) = softgrip_core::model::Model::mesh_of(scene) {
        let (lo, hi) = mesh.bounds();
        let c = 0.5 * (lo + hi);
        let pad = 1e-3 * (hi - lo).max_element();
        let halves = [
            ("left half", lo - pad, DVec3::new(c.x, hi.y, hi.z) + pad),
            ("right half", DVec3::new(c.x, lo.y, lo.z) - pad, hi + pad),
            ("bottom half", lo - pad, DVec3::new(hi.x, hi.y, c.z) + pad),
            ("top half", DVec3::new(lo.x, lo.y, c.z) - pad, hi + pad),
        ];
        for (name, min, max) in halves {
            out.push(Candidate {
                effect: "heterogeneous-stiffness",
                variant: name.to_string(),
                scene: with(&|s| {
                    s.regions.push(Region {
                        region: AaBox { min, max },
                        young_modulus: e,
                        density: s.object.density,
                    })
                }),
                // A stiff insert in soft material (or a soft patch in
                // stiff) can differ by more than tenfold.
                params: with_modulus(vec![param(
                    "region_young_modulus",
                    e / 30.0,
                    e * 30.0,
                    true,
                )]),
                off: None,
            });
        }
    }
    let loads = recording.samples.iter().map(|s| s.load).fold(0.0, f64::max);
    let pressed = scene.fingers.iter().any(|f| f.force != DVec3::ZERO);
    if pressed && loads > 0.0 {
        out.push(Candidate {
            effect: "load-loss",
            variant: String::new(),
            scene: scene.clone(),
            params: with_modulus(vec![param("guide_friction", 0.0, 0.5 * loads, false)]),
            off: None,
        });
    }
    out
}

/// Two effects fitted together because Vuong's test could not tell them
/// apart alone (both lowered BIC and removed the share, neither beat the
/// other by z 2): each is named when the pair still needs it.
#[derive(Debug, Clone)]
pub struct PairTest {
    /// The two effects and their variants, the better-scoring first.
    pub effects: [(&'static str, String); 2],
    /// The two fitted together.
    pub fit: ModelFit,
    /// What leaving each effect out of the pair costs, in the order of
    /// `effects`.
    pub without: [PairNeed; 2],
    /// When the pair does not need one effect at all (leaving it out lowers
    /// BIC), the other was judged as a lone candidate is.
    pub alone: Option<LoneTest>,
}

/// A pair's effect judged alone: `(i, z)`, effect `i` of the pair and its
/// Vuong z against the model without it.
pub type LoneTest = (usize, Option<f64>);

impl PairTest {
    /// Effect `i` of the pair, with its variant: "heterogeneous-stiffness
    /// (bottom half)".
    pub fn label(&self, i: usize) -> String {
        effect_label(self.effects[i].0, &self.effects[i].1)
    }
}

/// An effect with its variant, as the reports print it.
pub fn effect_label(effect: &str, variant: &str) -> String {
    if variant.is_empty() {
        effect.to_string()
    } else {
        format!("{effect} ({variant})")
    }
}

/// What leaving one effect out of a fitted pair costs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairNeed {
    /// BIC of the pair without it, minus the pair's (positive: needed).
    pub bic: f64,
    /// Share of the residual without it that the pair removes.
    pub explained: f64,
    /// Vuong's statistic of the pair against the pair without it, over
    /// every coordinate (positive: the pair fits closer).
    pub vuong: Option<f64>,
    /// The same, with the coordinates of each sample summed first, so that
    /// residuals correlated within a sample (one load, one instant) count
    /// once: a t statistic on the samples.
    pub vuong_by_sample: Option<f64>,
    /// Named: BIC, share and z all pass the thresholds used for one effect.
    pub needed: bool,
}

impl PairNeed {
    fn new(pair: &ModelFit, without: &ModelFit, noise: &Noise) -> Self {
        let p = weighted_residuals(&pair.replay.residuals, noise);
        let w = weighted_residuals(&without.replay.residuals, noise);
        let z = vuong(&p, &w);
        let bic = without.bic - pair.bic;
        let explained = 1.0 - pair.rss / without.rss;
        Self {
            bic,
            explained,
            vuong: z,
            vuong_by_sample: vuong_by_sample(
                &pair.replay.residuals,
                &without.replay.residuals,
                noise,
            ),
            needed: bic > BIC_THRESHOLD
                && explained >= MIN_EXPLAINED
                && z.is_some_and(|z| z >= VUONG_Z),
        }
    }
}

/// Which effects of a pair are named, from what leaving each out costs
/// (`without`, in the pair's order), each one's Vuong z alone against the
/// model without it (`lone`) and the places left for effects (`room`);
/// with the `PairTest::alone` it records.
///
/// Each is named when the pair needs it; with one place left, the one it
/// needs more. A pair that needs neither but does not need one of the two
/// at all (leaving it out lowers BIC) says that one only mimicked the
/// other: the tie that called for the pair is gone, and the other faces
/// the test a candidate alone in its round faces, Vuong's z against the
/// model without it. (Where both effects stand for one form error, as on
/// the suite's control-2, leaving either out costs something.)
pub fn pair_verdict(
    without: &[PairNeed; 2],
    lone: [Option<f64>; 2],
    room: usize,
) -> ((bool, bool), Option<LoneTest>) {
    let needed = (without[0].needed, without[1].needed);
    match needed {
        (true, true) if room < 2 => {
            if without[0].bic >= without[1].bic {
                ((true, false), None)
            } else {
                ((false, true), None)
            }
        }
        (false, false) => {
            let Some(i) = (0..2).find(|&i| without[1 - i].bic < 0.0) else {
                return (needed, None);
            };
            let named = lone[i].is_some_and(|z| z >= VUONG_Z);
            let verdict = match (i, named) {
                (0, true) => (true, false),
                (1, true) => (false, true),
                _ => (false, false),
            };
            (verdict, Some((i, lone[i])))
        }
        _ => (needed, None),
    }
}

/// Vuong's statistic with the squared-residual differences summed per
/// sample first: `sqrt(m) mean(D) / sd(D)` over the m samples. Positive
/// when `a` fits closer; None with fewer than 3 samples or residuals that
/// do not pair up.
pub fn vuong_by_sample(a: &[Residual], b: &[Residual], noise: &Noise) -> Option<f64> {
    if a.len() != b.len() {
        return None;
    }
    let mut per: std::collections::BTreeMap<usize, f64> = std::collections::BTreeMap::new();
    for (ra, rb) in a.iter().zip(b) {
        if ra.sample != rb.sample || ra.marker != rb.marker {
            return None;
        }
        let s = noise.sigma(ra.marker);
        let mut d = 0.0;
        for k in 0..3 {
            if let Some(x) = ra.recorded[k] {
                let ea = (ra.simulated[k] - x) / s;
                let eb = (rb.simulated[k] - x) / s;
                d += eb * eb - ea * ea;
            }
        }
        *per.entry(ra.sample).or_insert(0.0) += d;
    }
    let d: Vec<f64> = per.into_values().collect();
    (d.len() >= 3).then(|| mean_over_error(&d))
}

/// One fitted model.
#[derive(Debug, Clone)]
pub struct ModelFit {
    pub scene: Scene,
    /// The fitted parameters, by name.
    pub params: Vec<(String, f64)>,
    pub errors: Errors,
    /// Noise-weighted residual sum of squares, components, parameters.
    pub rss: f64,
    pub n: usize,
    pub k: usize,
    pub bic: f64,
    pub replay: Replay,
    pub evaluations: usize,
}

/// A candidate tried.
#[derive(Debug, Clone)]
pub struct Hypothesis {
    pub effect: &'static str,
    pub variant: String,
    pub fit: Result<ModelFit, String>,
    /// BIC against the model it was added to (negative: better).
    pub score: f64,
    /// Share of the weighted residual sum of squares it removed.
    pub explained: f64,
    pub round: usize,
    /// Vuong's statistic against the best candidate of another effect in
    /// the same round (positive: this one fits closer) or, when no other
    /// effect was fitted in its round, against the model it was added to
    /// (`against_model`); None when the fit failed.
    pub vuong: Option<f64>,
    /// `vuong` is against the model without the effect: the round had no
    /// rival. (Until 2026-11-24 such a candidate had no Vuong test, and
    /// BIC and the share alone decided; with E's range given, two load
    /// losses took a wrong table friction in round 2 that way.)
    pub against_model: bool,
}

impl Hypothesis {
    /// What `vuong` compares it with, in words.
    pub fn rival_text(&self) -> &'static str {
        if self.against_model {
            "the model without it"
        } else {
            "the best other effect"
        }
    }

    /// Its Vuong z for tables: "+2.31", "+2.31 (against the model without
    /// it)", or "-".
    pub fn z_text(&self) -> String {
        match self.vuong {
            Some(z) if self.against_model => format!("{z:+.2} (against {})", self.rival_text()),
            Some(z) => format!("{z:+.2}"),
            None => "-".into(),
        }
    }
}

/// The outcome.
#[derive(Debug, Clone)]
pub struct Diagnosis {
    pub baseline: ModelFit,
    pub noise: Noise,
    pub location: Location,
    pub hypotheses: Vec<Hypothesis>,
    /// The effects accepted, in order; empty: none or unexplained.
    pub effects: Vec<&'static str>,
    pub unexplained: bool,
    pub final_fit: ModelFit,
    /// Location of what is left after the effects.
    pub remaining: Location,
    pub evidence: String,
    /// The pair fitted when the best two effects tied, if they did.
    pub pair: Option<PairTest>,
    /// Simulations run in all (both baseline fits and every candidate's).
    pub simulations: usize,
    /// The ranges the user gave (`DiagnoseOptions::bounds`).
    pub bounds: Vec<(String, f64, f64)>,
    /// The baseline's parameters left at a bound of their search range.
    pub pinned: Vec<String>,
    /// How far the final model moves on a finer mesh and at half the
    /// step, against the noise (`crate::discretisation`): reported, not
    /// acted on.
    pub discretisation: Discretisation,
}

impl Diagnosis {
    /// Whether `h` is the fit that named its effect: the best-scoring
    /// candidate of an effect found (the half chosen, not the other halves
    /// of the same effect). The report's chart and the viewer's bars colour
    /// it as accepted.
    pub fn named(&self, h: &Hypothesis) -> bool {
        self.effects.contains(&h.effect)
            && self
                .hypotheses
                .iter()
                .filter(|k| k.effect == h.effect)
                .all(|k| k.score >= h.score)
    }

    /// NRMSE over all markers (fingers included) before and after, of
    /// the part of the residual the noise does not account for
    /// ([`rms_beyond_noise`] over the object's extent): the model's own
    /// error, which a recording's NRMSE cannot show below its noise. On
    /// the concealed suite it follows the error against the noise-free
    /// truth, which a lab does not have.
    pub fn nrmse_all_beyond_noise(&self) -> (f64, f64) {
        let one = |f: &ModelFit| {
            let e = &f.errors;
            if e.nrmse_all > 0.0 {
                rms_beyond_noise(&f.replay.residuals, &self.noise) * e.nrmse_all / e.rmse_all_m
            } else {
                0.0
            }
        };
        (one(&self.baseline), one(&self.final_fit))
    }

    /// The spec's `verdict.effect`: the first effect found, "none" or
    /// "unexplained".
    pub fn verdict(&self) -> String {
        match self.effects.first() {
            Some(e) => e.to_string(),
            None if self.unexplained => "unexplained".into(),
            None => "none".into(),
        }
    }

    /// The final model's fitted parameters: the last fit's and those of
    /// every effect named before it (an earlier effect's parameters stay
    /// where its fit left them, and are read from the final scene).
    pub fn fitted_params(&self) -> Vec<(String, f64)> {
        let mut names: Vec<String> = Vec::new();
        let named = self
            .hypotheses
            .iter()
            .filter(|h| self.effects.contains(&h.effect))
            .filter_map(|h| h.fit.as_ref().ok());
        for f in named.chain(std::iter::once(&self.final_fit)) {
            for (n, _) in &f.params {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
        }
        names
            .into_iter()
            .filter_map(|n| {
                let v = params::get(&self.final_fit.scene, &n).ok().flatten()?;
                Some((n, v))
            })
            .collect()
    }
}

/// Progress: (fits done, fits planned, what is being fitted).
pub type Progress<'a> = &'a (dyn Fn(usize, usize, &str) + Sync);

/// One fit of the diagnosis: the model, what is fitted and how.
struct FitTask<'a> {
    scene: &'a Scene,
    params: &'a [FitParam],
    /// Parameters counted by BIC: the model's in all (the modulus is
    /// refitted, not added, by a candidate).
    k_total: usize,
    search: Search,
    /// Simulations at most.
    budget: usize,
    /// Points (values) to start from beside the scene's own.
    starts: &'a [Vec<f64>],
    /// A point (values) the fit ends no worse than, but does not search
    /// from: a candidate's effect switched off (`Candidate::off`).
    floor: Option<&'a [f64]>,
    /// A fit already run: a point that is its model takes its replay.
    known: Option<&'a ModelFit>,
}

/// Fits the task's parameters of its scene to `recording` minimising the
/// noise-weighted residual sum of squares over every marker (fingers
/// included). "cancelled" once the diagnosis's cancel token is set.
fn fit_model(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    task: FitTask<'_>,
) -> Result<ModelFit, String> {
    let fit = fit_task(recording, noise, options, task);
    check_cancel()?;
    fit
}

fn fit_task(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    task: FitTask<'_>,
) -> Result<ModelFit, String> {
    let FitTask {
        scene,
        params,
        k_total,
        search,
        budget,
        starts,
        floor,
        known,
    } = task;
    // On the default thread count: one simulation per core while a batch
    // has several, both cores for the last one left (`Simulation::set_threads`).
    let run = |values: &[f64]| -> Result<Replay, String> {
        let mut s = scene.clone();
        for (p, v) in params.iter().zip(values) {
            s = params::set(&s, p.param.name, *v)?;
        }
        replay(
            recording,
            &s,
            ReplayOptions {
                rest: RestTolerance::for_fits(),
                ..ReplayOptions::default()
            },
            |_| {},
        )
        .map_err(|e| e.to_string())
    };
    let own: Vec<Option<f64>> = params
        .iter()
        .map(|p| params::get(scene, p.param.name).ok().flatten())
        .collect();
    let start: Vec<f64> = params
        .iter()
        .zip(&own)
        .map(|(p, v)| v.map_or(0.5, |v| p.unit(v)))
        .collect();
    // The other starts and the floor, in the unit scale, with their values.
    let unit = |v: &[f64]| -> Vec<f64> { params.iter().zip(v).map(|(p, x)| p.unit(*x)).collect() };
    let floor_u: Option<Vec<f64>> = floor.map(unit);
    let others: Vec<(Vec<f64>, &[f64])> = starts
        .iter()
        .map(|v| v.as_slice())
        .chain(floor)
        .map(|v| (unit(v), v))
        .collect();
    // The start is the scene's own values exactly (not their round trip
    // through the unit scale), so it is the scene as given; so are the
    // other starts' and the floor's values.
    let value_at = |u: &[f64]| -> Vec<f64> {
        if let Some((_, v)) = others.iter().find(|(o, _)| o == u) {
            return v.to_vec();
        }
        params
            .iter()
            .zip(u)
            .zip(u.iter().zip(&start).zip(&own))
            .map(|((p, x), ((a, b), v))| match v {
                Some(v) if a.to_bits() == b.to_bits() => *v,
                _ => p.value(*x),
            })
            .collect()
    };
    // Every point run, with its replay: the fit's best point is one of
    // them, so its replay is not run again.
    let mut cache: HashMap<Vec<u64>, Option<(Vec<f64>, Replay)>> = HashMap::new();
    let key = |u: &[f64]| u.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    // A point that is the model a fit already ran (a candidate whose
    // effect starts switched off, or the floor, on the current fit) has
    // that fit's replay.
    if let Some(k) = known {
        let at = |u: &[f64]| -> Option<Scene> {
            let mut s = scene.clone();
            for (p, v) in params.iter().zip(value_at(u)) {
                s = params::set(&s, p.param.name, v).ok()?;
            }
            Some(s)
        };
        for u in std::iter::once(&start).chain(others.iter().map(|(u, _)| u)) {
            if at(u).is_some_and(|s| same_model(&k.scene, &s)) {
                let r = weighted_residuals(&k.replay.residuals, noise);
                cache.insert(key(u), Some((r, k.replay.clone())));
            }
        }
    }
    let mut evaluations = 0usize;
    let best_u = {
        let mut evaluate = |points: &[Vec<f64>]| -> Vec<Option<Vec<f64>>> {
            let mut todo: Vec<Vec<f64>> = Vec::new();
            for u in points {
                if !cache.contains_key(&key(u)) && !todo.contains(u) {
                    todo.push(u.clone());
                }
            }
            let results = parallel_map(
                &todo,
                options.workers,
                |u| {
                    run(&value_at(u))
                        .ok()
                        .map(|r| (weighted_residuals(&r.residuals, noise), r))
                },
                &|_| {},
            );
            for (u, f) in todo.iter().zip(results) {
                cache.insert(key(u), f);
            }
            evaluations += todo.len();
            points
                .iter()
                .map(|u| {
                    cache
                        .get(&key(u))
                        .and_then(|f| f.as_ref())
                        .map(|f| f.0.clone())
                })
                .collect()
        };
        let cost = |r: &Option<Vec<f64>>| {
            r.as_ref()
                .map_or(f64::INFINITY, |r| r.iter().map(|v| v * v).sum::<f64>())
        };
        let r0 = evaluate(std::slice::from_ref(&start)).remove(0);
        let f0 = cost(&r0);
        if !f0.is_finite() {
            return Err(run(&value_at(&start))
                .err()
                .unwrap_or_else(|| "the start failed".into()));
        }
        // A small space-filling design (2 points per parameter) against
        // local minima, then Levenberg-Marquardt (below: from the best
        // point, and where `search` says from the next best too).
        // Other starts the caller knows of (values, not unit), first, and
        // the floor. The floor is not a place to search from: where the
        // effect is off its own parameters do nothing (creep's time at
        // g 0), and a search from there stays near it (on the suite's weak
        // creep at `b42c5be`: 2 % of the residual from there, 6 % with it
        // as a floor). The fit ends at the floor when the search ends worse.
        let mut design: Vec<Vec<f64>> = others.iter().map(|(u, _)| u.clone()).collect();
        if search != Search::Local {
            design.extend((1..=2 * params.len()).map(|k| crate::fit::halton(k, params.len())));
        }
        let mut floor_f = f64::INFINITY;
        let mut points: Vec<(Vec<f64>, Vec<f64>, f64)> = Vec::new();
        if let Some(r) = r0 {
            points.push((start.clone(), r, f0));
        }
        for (u, r) in design.iter().zip(evaluate(&design)) {
            let f = cost(&r);
            if floor_u.as_ref() == Some(u) {
                floor_f = f;
            } else if let Some(r) = r.filter(|_| f.is_finite()) {
                points.push((u.clone(), r, f));
            }
        }
        points.sort_by(|a, b| a.2.total_cmp(&b.2));
        let spent = 1 + design.len() - usize::from(floor_u.is_some());
        let fit_options = FitOptions {
            max_evaluations: budget,
            workers: options.workers,
            x_tolerance: 2e-3,
            // A thousandth of the cost is 0.1-0.3 in BIC on these recordings,
            // against a threshold of 10: finer is runs spent on nothing.
            f_tolerance: 1e-3,
            ..FitOptions::default()
        };
        let (mut best_u, mut best_f) = (start.clone(), f0);
        // Levenberg-Marquardt from the best point; for a candidate that
        // explains something (PROMISING) from there, also from the next
        // best point of the design (on the budget left). A candidate's
        // cost can have two valleys, and which one the search from the
        // best point ends in can turn on its start's last bits: on
        // control-2, a soft bottom half ended at BIC -29 (`98bfad6`) and
        // at -12 (`b42c5be`); from the next best point it reaches -41.
        // A verdict must not turn on that. A candidate that explains
        // nothing from its best point is not searched again: that is where
        // most of the runs would go.
        let mut used = spent;
        for (i, (u, r, f)) in points.into_iter().enumerate() {
            let again = match search {
                Search::Twice => true,
                Search::Contender => known.is_some_and(|k| 1.0 - best_f / k.rss >= PROMISING),
                Search::Local | Search::Design => false,
            };
            if i >= LOCAL_SEARCHES || (i > 0 && !again) {
                break;
            }
            if f < best_f {
                (best_u, best_f) = (u.clone(), f);
            }
            let m = levenberg_marquardt(
                &mut evaluate,
                &u,
                r,
                budget.saturating_sub(used),
                fit_options,
                JACOBIAN_STEP,
            );
            used += m.evaluations;
            if m.f < best_f {
                (best_u, best_f) = (m.x, m.f);
            }
        }
        match floor_u {
            Some(u) if floor_f < best_f => u,
            _ => best_u,
        }
    };
    let values = value_at(&best_u);
    let replay = match cache.remove(&key(&best_u)).flatten() {
        Some((_, r)) => r,
        None => {
            evaluations += 1;
            run(&values)?
        }
    };
    let (rss, n) = weighted_rss(&replay.residuals, noise);
    let mut fitted_scene = scene.clone();
    for (p, v) in params.iter().zip(&values) {
        fitted_scene = params::set(&fitted_scene, p.param.name, *v)?;
    }
    Ok(ModelFit {
        scene: fitted_scene,
        params: params
            .iter()
            .zip(&values)
            .map(|(p, v)| (p.param.name.to_string(), *v))
            .collect(),
        errors: replay.errors,
        rss,
        n,
        k: k_total,
        bic: bic(rss, n, k_total),
        replay,
        evaluations,
    })
}

/// Whether two scenes are the same model: equal (which values were
/// defaults aside), once their regions are
/// left out where every one of them has the object's own material (a
/// heterogeneous-stiffness candidate at its start). Such regions change no
/// element (see
/// `tests/diagnose.rs::a_region_of_the_objects_material_changes_nothing`);
/// one that overrides another region would, so then both must be equal.
pub fn same_model(a: &Scene, b: &Scene) -> bool {
    let plain = |s: &Scene| {
        let mut s = s.clone();
        let (e, rho) = (s.object.young_modulus, s.object.density);
        if s.regions
            .iter()
            .all(|r| r.young_modulus == e && r.density == rho)
        {
            s.regions.clear();
        }
        // Which values were defaults is no part of the model.
        s.defaults_applied.clear();
        s
    };
    a == b || plain(a) == plain(b)
}

/// The baseline's parameters: E, alpha, tau_s and tau_c, less the locked
/// ones and those the scene's model does not use.
pub fn baseline_params(scene: &Scene, lock: &[String]) -> Result<Vec<FitParam>, String> {
    for name in lock {
        params::find(name)?;
    }
    let neo = scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean;
    let mut out = Vec::new();
    for name in ["young_modulus", "alpha", "tau_s", "tau_c"] {
        if lock.iter().any(|l| l == name) {
            continue;
        }
        if neo && name != "young_modulus" {
            continue; // the elements have no alpha or spring limits
        }
        if scene.model.alpha == 0.0 && name == "alpha" {
            continue; // off in the scene: nothing to fit
        }
        let p = params::find(name)?;
        let (mut lower, upper) = crate::fit::default_bounds(p, scene)?;
        // A limit below 0.08 acts on nearly every spring: the projection
        // then makes the response depend on the load path, and the fit
        // used it to mimic other physics (hysteresis from load loss) with
        // an unphysical modulus.
        if name.starts_with("tau") {
            lower = lower.max(0.08);
        }
        out.push(FitParam {
            param: p,
            lower,
            upper,
            log: p.log,
        });
    }
    Ok(out)
}

/// The object's modulus, which every candidate refits (unless locked).
fn is_modulus(p: &FitParam) -> bool {
    p.param.name == "young_modulus"
}

/// A candidate's own parameters: all but the modulus it refits.
fn own_params(params: &[FitParam]) -> usize {
    params.iter().filter(|p| !is_modulus(p)).count()
}

/// Parses `NAME=LOW:HIGH` (a `--bound`).
pub fn parse_bound(text: &str) -> Result<(String, f64, f64), String> {
    let bad = || format!("--bound {text:?}: write NAME=LOW:HIGH, e.g. young_modulus=30e3:120e3");
    let (name, range) = text.split_once('=').ok_or_else(bad)?;
    let (low, high) = range.split_once(':').ok_or_else(bad)?;
    let number = |v: &str| v.trim().parse::<f64>().map_err(|_| bad());
    let bound = (name.trim().to_string(), number(low)?, number(high)?);
    check_bounds(std::slice::from_ref(&bound))?;
    Ok(bound)
}

/// Checks the user's ranges (`DiagnoseOptions::bounds`): a known
/// parameter, low below high, both positive where the parameter is
/// searched on a log scale.
pub fn check_bounds(bounds: &[(String, f64, f64)]) -> Result<(), String> {
    for (name, low, high) in bounds {
        let p = params::find(name).map_err(|e| format!("--bound {name}: {e}"))?;
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(format!(
                "--bound {name}={low}:{high}: give two finite values, the low one first \
                 ({name}=LOW:HIGH{})",
                if p.unit.is_empty() || p.unit == "1" {
                    String::new()
                } else {
                    format!(", in {}", p.unit)
                }
            ));
        }
        if p.log && *low <= 0.0 {
            return Err(format!(
                "--bound {name}={low}:{high}: {name} is positive; give a positive low value"
            ));
        }
    }
    Ok(())
}

/// `params` with each range the user gave intersected with the fit's own;
/// a parameter whose own range misses the user's is searched at the
/// user's range's nearer end.
fn within_bounds(mut params: Vec<FitParam>, bounds: &[(String, f64, f64)]) -> Vec<FitParam> {
    for p in &mut params {
        for (name, low, high) in bounds {
            if p.param.name == name {
                let lower = p.lower.max(*low).min(*high);
                let upper = p.upper.min(*high).max(*low);
                p.lower = lower;
                p.upper = upper.max(lower);
            }
        }
    }
    params
}

/// Runs the diagnosis.
pub fn diagnose(
    recording: &Recording,
    options: &DiagnoseOptions,
    progress: Progress,
) -> Result<Diagnosis, String> {
    let scene = &recording.scene;
    check_bounds(&options.bounds)?;
    let own = baseline_params(scene, &options.lock)?;
    for p in &own {
        for (name, low, high) in &options.bounds {
            if p.param.name == name && (*high < p.lower || *low > p.upper) {
                return Err(format!(
                    "--bound {name}={low}:{high} lies outside the range the baseline searches around the scene's {name} ({:.4e} to {:.4e}): set the scene's {name} inside your range",
                    p.lower, p.upper
                ));
            }
        }
    }
    let base_params = within_bounds(own, &options.bounds);
    // A locked E stays at the scene's value in the candidates' fits too
    // (until 2026-11-24 they refitted it whatever the lock said).
    let e_locked = options.lock.iter().any(|l| l == "young_modulus");
    let candidates = |recording: &Recording, scene: &Scene| -> Vec<Candidate> {
        catalogue(recording, scene)
            .into_iter()
            .map(|mut c| {
                if e_locked {
                    let kept: Vec<bool> = c.params.iter().map(|p| !is_modulus(p)).collect();
                    if let Some(off) = &mut c.off {
                        *off = off
                            .iter()
                            .zip(&kept)
                            .filter(|(_, k)| **k)
                            .map(|(v, _)| *v)
                            .collect();
                    }
                    c.params.retain(|p| !is_modulus(p));
                }
                c.params = within_bounds(c.params, &options.bounds);
                c
            })
            .filter(|c| !c.params.is_empty())
            .collect()
    };
    // The noise needs a residual, and the weighted fit needs the noise:
    // a first fit weighs every coordinate alike (1 mm), the noise comes
    // from its residual, and the baseline is refitted with it.
    let unit = Noise {
        object_m: 1e-3,
        finger_m: 1e-3,
        object_count: 0,
        finger_count: 0,
    };
    let candidates_guess = catalogue(recording, scene).len();
    let planned = 2 + candidates_guess * options.max_effects;
    progress(0, planned, "baseline");
    let first = fit_model(
        recording,
        &unit,
        options,
        FitTask {
            scene,
            params: &base_params,
            k_total: base_params.len(),
            search: Search::Twice,
            budget: options.max_evaluations,
            starts: &[],
            floor: None,
            known: None,
        },
    )?;
    let loads: Vec<f64> = recording.samples.iter().map(|s| s.load).collect();
    let breaks: Vec<usize> = (1..loads.len().saturating_sub(1))
        .filter(|&i| (loads[i] - loads[i - 1]) * (loads[i + 1] - loads[i]) < 0.0)
        .map(|i| i + 1)
        .collect();
    let noise = estimate_noise_split(&first.replay.residuals, &breaks);
    progress(1, planned, "baseline, weighted by the noise");
    let baseline = fit_model(
        recording,
        &noise,
        options,
        FitTask {
            scene: &first.scene,
            params: &base_params,
            k_total: base_params.len(),
            // From the first fit's optimum: the weights changed a little.
            search: Search::Local,
            budget: options.max_evaluations / 2,
            starts: &[],
            floor: None,
            known: Some(&first),
        },
    )?;
    let location = locate(recording, &baseline.replay, &noise);
    // Reported, not acted on: refitting them in every candidate, and
    // trying the candidates at the noise level when one was pinned, named
    // one effect fewer on the suite (docs/diagnosis-pinned-refitted.md).
    let pinned = pinned_at_bounds(&baseline.params, &base_params);
    let mut hypotheses = Vec::new();
    let mut effects = Vec::new();
    let mut current = baseline.clone();
    let mut done = 2;
    let mut unexplained = false;
    let mut pair_test: Option<PairTest> = None;
    if location.significant {
        let mut tried: Vec<&'static str> = Vec::new();
        for round in 0..options.max_effects {
            // After the first round, only the candidates that explained
            // something (5 %) on their own are tried again: an effect that
            // changed nothing then will not change anything next to another.
            let promising = |c: &Candidate| {
                round == 0
                    || hypotheses.iter().any(|h: &Hypothesis| {
                        h.round == 0
                            && h.effect == c.effect
                            && h.variant == c.variant
                            && h.explained >= PROMISING
                    })
            };
            let cands: Vec<Candidate> = candidates(recording, &current.scene)
                .into_iter()
                .filter(|c| !effects.contains(&c.effect) && !tried.contains(&c.effect))
                .filter(promising)
                .collect();
            if cands.is_empty() {
                break;
            }
            let mut best: Option<usize> = None;
            let start = hypotheses.len();
            for c in cands {
                progress(done, planned, c.effect);
                let k = current.k + own_params(&c.params); // the modulus is refitted, not added
                let budget = options.candidate_evaluations_per_param * c.params.len();
                let fit = fit_model(
                    recording,
                    &noise,
                    options,
                    FitTask {
                        scene: &c.scene,
                        params: &c.params,
                        k_total: k,
                        search: Search::Contender,
                        budget,
                        starts: &[],
                        floor: c.off.as_deref(),
                        known: Some(&current),
                    },
                );
                // A cancelled fit is the diagnosis's end, not a candidate
                // that failed.
                check_cancel()?;
                done += 1;
                let (score, explained) = match &fit {
                    Ok(f) => (f.bic - current.bic, 1.0 - f.rss / current.rss),
                    Err(_) => (f64::INFINITY, 0.0),
                };
                hypotheses.push(Hypothesis {
                    effect: c.effect,
                    variant: c.variant,
                    fit,
                    score,
                    explained,
                    round,
                    vuong: None,
                    against_model: false,
                });
            }
            // Each candidate against the best-scoring fit of another effect.
            let without = weighted_residuals(&current.replay.residuals, &noise);
            let weighted: Vec<Option<Vec<f64>>> = hypotheses[start..]
                .iter()
                .map(|h| {
                    h.fit
                        .as_ref()
                        .ok()
                        .map(|f| weighted_residuals(&f.replay.residuals, &noise))
                })
                .collect();
            for i in 0..weighted.len() {
                let rival = (0..weighted.len())
                    .filter(|&j| hypotheses[start + j].effect != hypotheses[start + i].effect)
                    .filter(|&j| weighted[j].is_some())
                    .min_by(|&a, &b| {
                        hypotheses[start + a]
                            .score
                            .total_cmp(&hypotheses[start + b].score)
                    });
                let h = &mut hypotheses[start + i];
                (h.vuong, h.against_model) = match (&weighted[i], rival.map(|j| &weighted[j])) {
                    (Some(this), Some(Some(other))) => (vuong(this, other), false),
                    // No other effect fitted this round: the same test
                    // against the model it was added to (nested, as in
                    // the pair test), so that form error a lone candidate
                    // absorbs is not named on BIC and the share alone.
                    (Some(this), None) => (vuong(this, &without), true),
                    _ => (None, false),
                };
            }
            for (i, h) in hypotheses.iter().enumerate().skip(start) {
                if best.is_none_or(|b| h.score < hypotheses[b].score) {
                    best = Some(i);
                }
            }
            let Some(b) = best else { break };
            // Two effects that both pass BIC and the share but cannot be
            // told apart by Vuong's test are either two effects at once or
            // one form error seen by both: fitted together, each is named
            // when the pair still needs it (a nested comparison, BIC of the
            // pair against the other alone).
            let passes = |h: &Hypothesis| h.score < -BIC_THRESHOLD && h.explained >= MIN_EXPLAINED;
            let rival = (start..hypotheses.len())
                .filter(|&j| hypotheses[j].effect != hypotheses[b].effect)
                .min_by(|&x, &y| hypotheses[x].score.total_cmp(&hypotheses[y].score));
            if !accepted(&hypotheses[b])
                && passes(&hypotheses[b])
                && let Some(r) = rival
                && passes(&hypotheses[r])
                && let (Ok(hf), Ok(rf)) = (hypotheses[b].fit.clone(), hypotheses[r].fit.clone())
            {
                let find = |scene: &Scene, h: &Hypothesis| {
                    candidates(recording, scene)
                        .into_iter()
                        .find(|c| c.effect == h.effect && c.variant == h.variant)
                };
                let (Some(hc), Some(rc)) = (
                    find(&current.scene, &hypotheses[b]),
                    find(&hf.scene, &hypotheses[r]),
                ) else {
                    break;
                };
                let mut params = rc.params.clone();
                params.extend(hc.params.iter().filter(|p| !is_modulus(p)).cloned());
                let k = current.k + own_params(&hc.params) + own_params(&rc.params);
                let budget = options.candidate_evaluations_per_param * params.len();
                progress(done, planned, "the two closest effects together");
                // The pair starts where the better one ended, the other
                // at its catalogue start (no effect, or for table friction
                // a frictionless table, which is not the fixed bottom the
                // better one was fitted on), and also from both effects at
                // their own optima, with either one's modulus. (The pair can
                // still end worse than the better one alone when the two are
                // not nested: a table under the object is no fixed bottom at
                // any friction, as on control-3.)
                let at = |f: &ModelFit, name: &str| {
                    f.params.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
                };
                let starts: Vec<Vec<f64>> = [&hf, &rf]
                    .iter()
                    .map(|modulus| {
                        params
                            .iter()
                            .map(|p| {
                                let name = p.param.name;
                                if name == "young_modulus" {
                                    at(modulus, name)
                                } else {
                                    at(&rf, name).or_else(|| at(&hf, name))
                                }
                                .or_else(|| params::get(&rc.scene, name).ok().flatten())
                                .unwrap_or(p.lower)
                            })
                            .collect()
                    })
                    .collect();
                let pair = fit_model(
                    recording,
                    &noise,
                    options,
                    FitTask {
                        scene: &rc.scene,
                        params: &params,
                        k_total: k,
                        search: Search::Design,
                        budget,
                        starts: &starts,
                        floor: None,
                        known: None,
                    },
                );
                check_cancel()?;
                let Ok(pair) = pair else { break };
                // The pair needs an effect when leaving it out costs what
                // naming one costs: the BIC gain, the share of the residual
                // and Vuong's z, with the same thresholds.
                let (he, hv) = (hypotheses[b].effect, hypotheses[b].variant.clone());
                let (re, rv) = (hypotheses[r].effect, hypotheses[r].variant.clone());
                let mut test = PairTest {
                    effects: [(he, hv), (re, rv)],
                    without: [
                        PairNeed::new(&pair, &rf, &noise),
                        PairNeed::new(&pair, &hf, &noise),
                    ],
                    fit: pair,
                    alone: None,
                };
                let room = options.max_effects.saturating_sub(effects.len());
                let lone = [&hf, &rf]
                    .map(|f| vuong(&weighted_residuals(&f.replay.residuals, &noise), &without));
                let (needed, alone) = pair_verdict(&test.without, lone, room);
                test.alone = alone;
                match needed {
                    (true, true) => {
                        effects.extend([he, re]);
                        current = test.fit.clone();
                    }
                    (true, false) => {
                        effects.push(he);
                        current = hf;
                    }
                    (false, true) => {
                        effects.push(re);
                        current = rf;
                    }
                    (false, false) => {
                        let ratio = (location.chi2 / location.dof.max(1) as f64).sqrt();
                        unexplained = effects.is_empty() && ratio > UNEXPLAINED_RATIO;
                    }
                }
                pair_test = Some(test);
                break;
            }
            let h = &hypotheses[b];
            if accepted(h) {
                effects.push(h.effect);
                if let Ok(f) = &h.fit {
                    current = f.clone();
                }
                // Variants of an effect found are not tried again.
                tried.push(h.effect);
            } else {
                let ratio = (location.chi2 / location.dof.max(1) as f64).sqrt();
                unexplained = effects.is_empty() && ratio > UNEXPLAINED_RATIO;
                break;
            }
        }
    }
    let remaining = locate(recording, &current.replay, &noise);
    let mut evidence = evidence_text(
        &location,
        &hypotheses,
        &effects,
        unexplained,
        &pinned,
        (baseline.errors.nrmse_all, current.errors.nrmse_all),
    );
    if let Some(t) = &pair_test {
        evidence += &pair_text(t);
    }
    // On the final model: the baseline's may not show it (on the suite's
    // strong creep, half the step moves the baseline by 0.001 mm and the
    // model with the creep by about 0.1).
    progress(
        done.min(planned),
        planned,
        "the final model on a finer mesh and step",
    );
    let discretisation = crate::discretisation::check(
        recording,
        &current.scene,
        &current.replay,
        &noise,
        RestTolerance::for_fits(),
    );
    if let Some(c) = discretisation.caution() {
        if !evidence.trim_end().ends_with('.') {
            evidence = evidence.trim_end().to_string() + ".";
        }
        evidence += " ";
        evidence += &c;
    }
    progress(planned, planned, "done");
    let simulations = first.evaluations
        + baseline.evaluations
        + hypotheses
            .iter()
            .filter_map(|h| h.fit.as_ref().ok())
            .map(|f| f.evaluations)
            .sum::<usize>()
        + pair_test.as_ref().map_or(0, |t| t.fit.evaluations);
    Ok(Diagnosis {
        baseline,
        noise,
        location,
        hypotheses,
        effects,
        unexplained,
        final_fit: current,
        remaining,
        evidence,
        pair: pair_test,
        simulations,
        bounds: options.bounds.clone(),
        pinned,
        discretisation,
    })
}

/// The baseline's parameters that its fit left at a bound of their search
/// range (`fit::at_bound`, as `softgrip fit` flags them).
pub fn pinned_at_bounds(fitted: &[(String, f64)], params: &[FitParam]) -> Vec<String> {
    params
        .iter()
        .filter(|p| {
            fitted
                .iter()
                .find(|(n, _)| n == p.param.name)
                .is_some_and(|(_, v)| crate::fit::at_bound(p.unit(*v)))
        })
        .map(|p| p.param.name.to_string())
        .collect()
}

/// The cancel message once the diagnosis's token is set (`softgrip_core::cancel`):
/// its simulations then fail at once, which must not read as candidates
/// that explain nothing.
fn check_cancel() -> Result<(), String> {
    softgrip_core::cancel::check_scope(|| softgrip_core::cancel::CANCELLED.to_string())
}

/// The pair test in words, for the evidence.
fn pair_text(t: &PairTest) -> String {
    let z = |z: Option<f64>| z.map_or("-".to_string(), |z| format!("{z:+.1}"));
    let cost = |i: usize| {
        let w = &t.without[i];
        format!(
            "leaving out {} costs {:+.1} in BIC, {:.0} % of the residual, z {} ({} by sample): {}",
            t.label(i),
            w.bic,
            100.0 * w.explained,
            z(w.vuong),
            z(w.vuong_by_sample),
            if w.needed { "needed" } else { "not needed" }
        )
    };
    let alone = match t.alone {
        Some((i, lone)) => format!(
            "; the pair does not need {} at all, so {} was tested as a lone candidate is: z {} against the model without it ({})",
            t.label(1 - i),
            t.label(i),
            z(lone),
            if lone.is_some_and(|z| z >= VUONG_Z) {
                "named"
            } else {
                "not named"
            }
        ),
        None => String::new(),
    };
    format!(
        ". {} and {} could not be told apart alone, so they were fitted together; {}; {} (needed: BIC over {BIC_THRESHOLD}, {:.0} % and z {VUONG_Z}){alone}",
        t.label(0),
        t.label(1),
        cost(0),
        cost(1),
        100.0 * MIN_EXPLAINED
    )
}

fn evidence_text(
    location: &Location,
    hypotheses: &[Hypothesis],
    effects: &[&'static str],
    unexplained: bool,
    pinned: &[String],
    (nrmse_before, nrmse_after): (f64, f64),
) -> String {
    let ranked = |round: usize| {
        let mut v: Vec<&Hypothesis> = hypotheses.iter().filter(|h| h.round == round).collect();
        v.sort_by(|a, b| a.score.total_cmp(&b.score));
        v
    };
    let name = |h: &Hypothesis| effect_label(h.effect, &h.variant);
    if effects.is_empty() {
        let r = ranked(0);
        let best = r
            .first()
            .map(|h| {
                format!(
                    "; the best candidate, {}, changes BIC by {:+.1} and explains {:.0} % of it{}",
                    name(h),
                    h.score,
                    100.0 * h.explained,
                    h.vuong
                        .map(|z| format!(", Vuong z {z:+.2} against {}", h.rival_text()))
                        .unwrap_or_default()
                )
            })
            .unwrap_or_default();
        if !location.significant {
            let mut s = format!(
                "nothing is missing: after the baseline fit the residual is at the noise level (chi-square {:.0} on {} coordinates, within three standard deviations)",
                location.chi2, location.dof
            );
            if !pinned.is_empty() {
                let one = pinned.len() == 1;
                s += &format!(
                    ". The fit left {names} at the edge of {its} search range: either the data do not pin {it} down, or the model bends {it} to stand in for physics it lacks; if you measured {which} or E, give its range (`--bound NAME=LOW:HIGH`) or lock it (`--lock NAME`) and diagnose again",
                    names = pinned.join(" and "),
                    its = if one { "its" } else { "their" },
                    it = if one { "it" } else { "them" },
                    which = if one { "it" } else { "one of them" },
                );
            }
            return s;
        }
        let ratio = (location.chi2 / location.dof.max(1) as f64).sqrt();
        return if unexplained {
            format!(
                "unexplained: a mismatch {ratio:.1} times the noise ({}) that no candidate explains (none removes {:.0} % of it with a BIC gain over {BIC_THRESHOLD} and fits closer than every other effect by Vuong's z {VUONG_Z}){best}",
                location.description,
                100.0 * MIN_EXPLAINED
            )
        } else {
            format!(
                "nothing is missing: the residual left after the baseline fit, {ratio:.1} times the noise ({}), is explained by no candidate (none removes {:.0} % of it with a BIC gain over {BIC_THRESHOLD} and fits closer than every other effect by Vuong's z {VUONG_Z}): the model's own form error{best}",
                location.description,
                100.0 * MIN_EXPLAINED
            )
        };
    }
    let mut parts = Vec::new();
    for (round, effect) in effects.iter().enumerate() {
        let r = ranked(round);
        let chosen = r.iter().find(|h| h.effect == *effect);
        let runner = r.iter().find(|h| h.effect != *effect);
        if let Some(c) = chosen {
            let mut s = format!(
                "{} lowers BIC by {:.1} and removes {:.0} % of the weighted residual",
                name(c),
                -c.score,
                100.0 * c.explained
            );
            match runner {
                // Named by the pair test (see `pair_text`) though the
                // other scored better alone.
                Some(ru) if ru.score < c.score => {
                    s += &format!(
                        "; {} scores better alone, {:.1} ({:.0} %), but Vuong's test cannot tell the two apart{}, and fitted together the pair needs {} (below)",
                        name(ru),
                        -ru.score,
                        100.0 * ru.explained,
                        c.vuong
                            .map(|z| format!(" (z = {z:+.2})"))
                            .unwrap_or_default(),
                        c.effect
                    );
                }
                Some(ru) => {
                    s += &format!(
                        "; the runner-up, {}, only {:.1} ({:.0} %){}",
                        name(ru),
                        -ru.score,
                        100.0 * ru.explained,
                        c.vuong
                            .map(|z| if z >= VUONG_Z {
                                format!(
                                    ", and Vuong's test finds {} closer to the data at z = {z:.2}",
                                    c.effect
                                )
                            } else {
                                // Named through the pair (see `pair_text`).
                                format!(
                                    ", but Vuong's test cannot tell the two apart (z = {z:+.2}); fitted together, see below"
                                )
                            })
                            .unwrap_or_default()
                    );
                }
                None => {
                    if let Some(z) = c.vuong.filter(|_| c.against_model) {
                        s += &format!(
                            "; no other effect was fitted beside it, and Vuong's test finds it closer to the data than {} at z = {z:.2}",
                            c.rival_text()
                        );
                    }
                }
            }
            parts.push(s);
        }
    }
    format!(
        "{}. NRMSE (all markers) {nrmse_before:.4} -> {nrmse_after:.4}",
        parts.join("; then "),
    )
}

/// The spec's JSON (`diagnose --json`), with softgrip's additions
/// (`verdict.effects`, `verdict.evidence`, `noise`, `mismatch.regions`).
pub fn to_json(d: &Diagnosis, recording: &Recording) -> serde_json::Value {
    let beyond_noise = d.nrmse_all_beyond_noise();
    let params = |f: &ModelFit| {
        serde_json::Value::Object(
            f.params
                .iter()
                .map(|(k, v)| (k.clone(), serde_json::json!(v)))
                .collect(),
        )
    };
    let hypotheses: Vec<serde_json::Value> = d
        .hypotheses
        .iter()
        .map(|h| {
            let mut v = serde_json::json!({
                "effect": h.effect,
                "score": h.score,
                "explained": h.explained,
                "vuong_z": h.vuong,
                "round": h.round,
            });
            if !h.variant.is_empty() {
                v["variant"] = serde_json::json!(h.variant);
            }
            match &h.fit {
                Ok(f) => {
                    v["params"] = params(f);
                    v["nrmse"] = serde_json::json!(f.errors.nrmse);
                    v["nrmse_all"] = serde_json::json!(f.errors.nrmse_all);
                }
                Err(e) => v["error"] = serde_json::json!(e),
            }
            v
        })
        .collect();
    let _ = recording;
    let pair = d.pair.as_ref().map(|t| {
        let effect = |(e, v): &(&str, String)| {
            if v.is_empty() {
                serde_json::json!({"effect": e})
            } else {
                serde_json::json!({"effect": e, "variant": v})
            }
        };
        serde_json::json!({
            "effects": [effect(&t.effects[0]), effect(&t.effects[1])],
            "params": params(&t.fit),
            "nrmse_all": t.fit.errors.nrmse_all,
            "without": t.without.iter().map(|w| serde_json::json!({
                "bic": w.bic,
                "explained": w.explained,
                "vuong_z": w.vuong,
                "vuong_z_by_sample": w.vuong_by_sample,
                "needed": w.needed,
            })).collect::<Vec<_>>(),
            "alone": t.alone.map(|(i, z)| serde_json::json!({
                "effect": effect(&t.effects[i]),
                "vuong_z": z,
            })),
        })
    });
    serde_json::json!({
        "pair": pair,
        "baseline": {
            "nrmse": d.baseline.errors.nrmse,
            "nrmse_all": d.baseline.errors.nrmse_all,
            "rmse_m": d.baseline.errors.rmse_m,
            "params": params(&d.baseline),
            "pinned": d.pinned,
            "bounds": serde_json::Value::Object(
                d.bounds
                    .iter()
                    .map(|(k, lo, hi)| (k.clone(), serde_json::json!([lo, hi])))
                    .collect(),
            ),
        },
        "noise": {"object_m": d.noise.object_m, "finger_m": d.noise.finger_m},
        "discretisation": d.discretisation.to_json(),
        "mismatch": {
            "markers": d.location.markers.iter().map(|(m, _)| m.clone()).collect::<Vec<_>>(),
            "axes": d.location.axes,
            "where": d.location.description,
            "when": d.location.when,
            "regions": d.location.regions.iter().map(|(r, _)| r.clone()).collect::<Vec<_>>(),
            "significant": d.location.significant,
        },
        "hypotheses": hypotheses,
        "verdict": {
            "effect": d.verdict(),
            "effects": d.effects,
            "params": serde_json::Value::Object(
                d.fitted_params()
                    .into_iter()
                    .map(|(k, v)| (k, serde_json::json!(v)))
                    .collect(),
            ),
            "nrmse_before": d.baseline.errors.nrmse,
            "nrmse_after": d.final_fit.errors.nrmse,
            "nrmse_all_before": d.baseline.errors.nrmse_all,
            "nrmse_all_after": d.final_fit.errors.nrmse_all,
            "nrmse_all_beyond_noise_before": beyond_noise.0,
            "nrmse_all_beyond_noise_after": beyond_noise.1,
            "evidence": d.evidence,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What leaving one effect out of a pair costs, with the thresholds'
    /// verdict.
    fn need(bic: f64, explained: f64, z: f64) -> PairNeed {
        PairNeed {
            bic,
            explained,
            vuong: Some(z),
            vuong_by_sample: None,
            needed: bic > BIC_THRESHOLD && explained >= MIN_EXPLAINED && z >= VUONG_Z,
        }
    }

    /// The pair's verdicts, with the suite's figures (DIAGNOSIS.md): two
    /// effects both needed are both named, or with one place left the one
    /// needed more; a pair that needs neither names none when leaving
    /// either out costs something (control-2: +4 and +1, one form error
    /// seen by both), and when it does not need one at all (leaving table
    /// friction out of heterogeneous-stiffness-weak's pair lowers BIC by 3)
    /// the other is named only if it passes a lone candidate's Vuong test.
    #[test]
    fn a_pair_that_does_not_need_one_judges_the_other_alone() {
        let both = [need(200.0, 0.76, 5.5), need(144.0, 0.65, 3.7)];
        assert_eq!(pair_verdict(&both, [None, None], 2), ((true, true), None));
        assert_eq!(pair_verdict(&both, [None, None], 1), ((true, false), None));
        let one_form_error = [need(4.0, 0.06, 1.2), need(1.0, 0.04, 0.8)];
        assert_eq!(
            pair_verdict(&one_form_error, [Some(3.0), Some(3.0)], 2),
            ((false, false), None),
            "both cost something: no lone test"
        );
        let mimic = [need(13.0, 0.12, 1.9), need(-3.0, 0.01, 0.3)];
        assert_eq!(
            pair_verdict(&mimic, [Some(2.4), Some(-1.0)], 2),
            ((true, false), Some((0, Some(2.4))))
        );
        assert_eq!(
            pair_verdict(&mimic, [Some(1.5), Some(-1.0)], 2),
            ((false, false), Some((0, Some(1.5)))),
            "alone it must still beat the model without it by z 2"
        );
        // The same with the pair's order reversed: the second is judged.
        let reversed = [mimic[1], mimic[0]];
        assert_eq!(
            pair_verdict(&reversed, [Some(-1.0), Some(2.4)], 2),
            ((false, true), Some((1, Some(2.4))))
        );
        // One effect needed: named as before, no lone test.
        let first = [need(63.0, 0.29, 2.7), need(-3.0, 0.01, 0.3)];
        assert_eq!(pair_verdict(&first, [None, None], 2), ((true, false), None));
    }

    /// A candidate with no other effect beside it in its round is named
    /// only when it also fits closer than the model without it by Vuong's
    /// z: BIC and the share alone let form error through (the load losses'
    /// round 2 with E's range given: -12 / 11 % and -13 / 12 % for a wrong
    /// table friction).
    #[test]
    fn a_lone_candidate_needs_vuongs_test_against_the_model_without_it() {
        let mut lone = tried("table-friction", -13.0, 0.12, 1.5);
        lone.against_model = true;
        assert!(!accepted(&lone), "z 1.5 against the model: not named");
        assert_eq!(lone.z_text(), "+1.50 (against the model without it)");
        lone.vuong = Some(2.5);
        assert!(accepted(&lone), "z 2.5: named");
        // BIC and the share still gate it.
        lone.score = -9.0;
        assert!(!accepted(&lone));
        // A failed fit (no z at all) is never named.
        let mut failed = tried("load-loss", -50.0, 0.5, 0.0);
        failed.vuong = None;
        assert!(!accepted(&failed));
        assert_eq!(failed.z_text(), "-");
        assert_eq!(tried("load-loss", -50.0, 0.5, 3.0).z_text(), "+3.00");
    }

    /// A range the user gives narrows a fit's own and never widens it; one
    /// outside the fit's own leaves the search at its nearer end.
    #[test]
    fn a_given_range_narrows_the_fits_own() {
        let e = |lower: f64, upper: f64| FitParam {
            param: params::find("young_modulus").expect("known"),
            lower,
            upper,
            log: true,
        };
        let friction = FitParam {
            param: params::find("table_friction").expect("known"),
            lower: 0.0,
            upper: 2.0,
            log: false,
        };
        let given = vec![("young_modulus".to_string(), 3e4, 1.2e5)];
        let out = within_bounds(vec![e(6e3, 6e5), friction], &given);
        assert_eq!((out[0].lower, out[0].upper), (3e4, 1.2e5));
        assert_eq!(
            (out[1].lower, out[1].upper),
            (0.0, 2.0),
            "other names untouched"
        );
        let out = within_bounds(vec![e(5e4, 8e4)], &given);
        assert_eq!((out[0].lower, out[0].upper), (5e4, 8e4), "not widened");
        let out = within_bounds(vec![e(2e5, 6e5)], &given);
        assert_eq!(
            (out[0].lower, out[0].upper),
            (1.2e5, 1.2e5),
            "the nearer end"
        );
    }

    /// A fitted value at either end of its search range (on the log scale
    /// for E) is pinned; one inside it, or a parameter not fitted, is not.
    #[test]
    fn a_value_at_the_edge_of_its_range_is_pinned() {
        let param = |name: &str, lower: f64, upper: f64, log: bool| FitParam {
            param: params::find(name).expect("known"),
            lower,
            upper,
            log,
        };
        let ranges = [
            param("young_modulus", 6e3, 6e5, true),
            param("alpha", 6e4, 6e6, true),
            param("tau_c", 0.08, 0.5, false),
            param("tau_s", 0.08, 0.5, false),
        ];
        let fitted = |e: f64, alpha: f64, tau_c: f64| {
            vec![
                ("young_modulus".to_string(), e),
                ("alpha".to_string(), alpha),
                ("tau_c".to_string(), tau_c),
            ]
        };
        assert!(pinned_at_bounds(&fitted(2.1e5, 6.1e5, 0.2), &ranges).is_empty());
        assert_eq!(
            pinned_at_bounds(&fitted(2.1e5, 6e4, 0.08), &ranges),
            ["alpha", "tau_c"]
        );
        assert_eq!(
            pinned_at_bounds(&fitted(6e5, 6.1e5, 0.4999), &ranges),
            ["young_modulus", "tau_c"],
            "the upper end, within 0.1 % of the range"
        );
        // 1 % above E's lower end (0.2 % of its log range) is inside.
        assert!(pinned_at_bounds(&fitted(6e3 * 1.01, 6.1e5, 0.2), &ranges).is_empty());
    }

    #[test]
    fn a_bound_parses_and_bad_ones_say_what_to_write() {
        assert_eq!(
            parse_bound(" young_modulus = 3e4 : 1.2e5 "),
            Ok(("young_modulus".to_string(), 3e4, 1.2e5))
        );
        assert_eq!(
            parse_bound("table_friction=0:0.5"),
            Ok(("table_friction".to_string(), 0.0, 0.5))
        );
        for (text, says) in [
            ("young_modulus=1.2e5:3e4", "the low one first"),
            ("young_modulus=3e4:3e4", "the low one first"),
            ("young_modulus=0:3e4", "positive"),
            ("young_modulus=a:3e4", "NAME=LOW:HIGH"),
            ("young_modulus", "NAME=LOW:HIGH"),
            ("modulus=1:2", "unknown parameter"),
        ] {
            let e = parse_bound(text).expect_err(text);
            assert!(e.contains(says) && e.contains("--bound"), "{text}: {e}");
        }
    }

    fn tried(effect: &'static str, score: f64, explained: f64, vuong: f64) -> Hypothesis {
        Hypothesis {
            effect,
            variant: String::new(),
            fit: Err("not run".into()),
            score,
            explained,
            round: 0,
            vuong: Some(vuong),
            against_model: false,
        }
    }

    /// The evidence calls the other effect "the runner-up" only when it
    /// scored worse; when the pair test named the one that scored worse
    /// alone, it says so (EF30_0T_A1 on 2026-11-24 read "the runner-up,
    /// strain-stiffening, only 14.3" beside a named effect's 10.1).
    #[test]
    fn the_evidence_says_runner_up_only_of_a_worse_score() {
        let location = Location {
            significant: true,
            ..Location::default()
        };
        // Two effects tried in round 1, one of them named.
        let evidence = |a: Hypothesis, b: Hypothesis, named: &'static str, nrmse: (f64, f64)| {
            evidence_text(&location, &[a, b], &[named], false, &[], nrmse)
        };
        let best_named = evidence(
            tried("table-friction", -30.0, 0.4, 2.5),
            tried("load-loss", -12.0, 0.2, -2.5),
            "table-friction",
            (0.01, 0.005),
        );
        assert!(
            best_named.contains("the runner-up, load-loss, only 12.0 (20 %)")
                && best_named.contains("closer to the data at z = 2.50"),
            "{best_named}"
        );
        let pair_named = evidence(
            tried("strain-stiffening", -14.3, 0.85, 0.88),
            tried("heterogeneous-stiffness", -10.1, 0.71, -0.88),
            "heterogeneous-stiffness",
            (0.0358, 0.0193),
        );
        assert!(!pair_named.contains("runner-up"), "{pair_named}");
        assert!(
            pair_named.contains("strain-stiffening scores better alone, 14.3 (85 %)")
                && pair_named.contains("(z = -0.88)")
                && pair_named.contains("the pair needs heterogeneous-stiffness"),
            "{pair_named}"
        );
        assert!(pair_named.ends_with("NRMSE (all markers) 0.0358 -> 0.0193"));
        // Named through the pair though it scored better alone
        // (heterogeneous-stiffness-weak's figures): the runner-up, and no
        // claim that Vuong's test told them apart.
        let tied_better = evidence(
            tried("heterogeneous-stiffness", -27.0, 0.20, 1.2),
            tried("table-friction", -12.0, 0.11, -1.2),
            "heterogeneous-stiffness",
            (0.00378, 0.00339),
        );
        assert!(
            tied_better.contains("the runner-up, table-friction, only 12.0 (11 %)")
                && tied_better.contains("cannot tell the two apart (z = +1.20)")
                && !tied_better.contains("closer to the data"),
            "{tied_better}"
        );
    }

    /// Within the noise, "nothing is missing" stands alone when the fit
    /// pinned nothing; when it pinned a parameter, the evidence names it
    /// and says how to settle it.
    #[test]
    fn the_evidence_names_what_the_baseline_pinned() {
        let location = Location {
            significant: false,
            chi2: 193.0,
            dof: 144,
            ..Location::default()
        };
        let plain = evidence_text(&location, &[], &[], false, &[], (0.0034, 0.0034));
        assert!(plain.starts_with("nothing is missing"), "{plain}");
        assert!(!plain.contains("edge"), "{plain}");
        let pinned = evidence_text(
            &location,
            &[],
            &[],
            false,
            &["alpha".to_string(), "tau_c".to_string()],
            (0.0034, 0.0034),
        );
        assert!(pinned.starts_with("nothing is missing"), "{pinned}");
        assert!(
            pinned.contains("left alpha and tau_c at the edge of their search range")
                && pinned.contains("if you measured one of them or E")
                && pinned.contains("--bound NAME=LOW:HIGH"),
            "{pinned}"
        );
    }
}
