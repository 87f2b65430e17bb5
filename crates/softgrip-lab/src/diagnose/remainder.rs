//! What the final model leaves unexplained: two checks of the verdict on its own residual, each
//! with the place and the time a user can look at. A catalogue effect can absorb part of a
//! mismatch it is not (a guide's friction takes up a permanent set's unloading), so a named
//! effect is kept only when the model with it passes both.
//!
//! - **Hysteresis**: on a later branch (the way back down), the residual at a load should be the
//!   one on the first branch at the same load. The model's own form error (mesh, element, contact
//!   law) is a function of the load, so it cancels out of the difference; the model's own
//!   hysteresis (friction) is in its simulated positions. What remains beyond the noise at the
//!   object markers, with some marker beyond its own level, is hysteresis the recording has and
//!   the model has not: a permanent set, adhesion, damage. The finger is left out: its depth
//!   around a loop carries the contact and friction laws' own form (a friction fitted right in
//!   size, in another law's form, leaves chi-square 96 on 36 there at a 0.03 mm noise); the
//!   kept share (below) still reads the finger.
//! - **Lone markers**: an object marker whose residual goes beyond the noise and the model's own
//!   discretisation error at it, while the other markers' stays within theirs: a marker
//!   slipping on the skin, a point the camera mislabelled. A model's error of form moves a marker
//!   more or less along the way it moves it (most under the finger), so each marker's own move,
//!   scaled to fit, is taken out first; and a slip stays where a camera's outlier is one sample,
//!   so each sample's part of a marker's chi-square is capped. A mismatch spread over many markers is the search's to
//!   explain, not this check's.
//!
//! Why these two and their levels: `docs/design/diagnosis.md`.

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;

use super::model_fit::ModelFit;
use super::noise::{Noise, load_turns, marker_key, weighted_residuals};
use super::screen::replay_columns;
use super::statistics::{VUONG_Z, upper_tail, vuong};
use crate::compare::Residual;
use crate::discretisation::FINER;
use crate::recording::{MarkerRef, Mode, Recording};
use softgrip_core::scene::Scene;

/// The level of each check: a named effect is set aside, and a verdict turned to "unexplained",
/// only on a p-value below this (the lone-marker check shares it among the markers).
pub const REMAINDER_LEVEL: f64 = 1e-3;

/// How many times the refined mesh's move a marker's discretisation error may be: the move from
/// edges `h` to `FINER h` of an error first order in `h` is `(1 - FINER)` of it.
pub const FORM_ERROR_FACTOR: f64 = 1.0 / (1.0 - FINER);

/// One check's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct Test {
    /// The chi-square of what the check measures, on its degrees of freedom.
    pub chi2: f64,
    /// Degrees of freedom of `chi2`.
    pub dof: usize,
    /// Its p-value (Wilson-Hilferty's normal approximation); for lone markers, the worst
    /// marker's times the markers tested.
    pub p_value: f64,
    /// Markers beyond their own bar, worst first, with their RMS over their bar.
    pub markers: Vec<(String, f64)>,
    /// Whether the check finds a mismatch the model leaves.
    pub fails: bool,
}

/// Both checks; `None` where one does not apply (no later branch, no discretisation measured).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Remainder {
    /// The hysteresis check (module docs): later branches against the first at the same load.
    pub hysteresis: Option<Test>,
    /// The lone-marker check (module docs, `lone_markers`).
    pub lone_markers: Option<Test>,
    /// The symptom's own description as a rival to the search's reading (module docs).
    pub kept_share: Option<KeptShare>,
}

/// On unloading every marker keeps a share of its way back from the peak (`share`, one for all,
/// on the baseline with its parameters refitted): hysteresis described, not explained. A reading
/// the search named must fit closer than this by Vuong's z ([`VUONG_Z`]); with none named,
/// a significant share is a mismatch to show.
#[derive(Debug, Clone, PartialEq)]
pub struct KeptShare {
    /// The share kept (positive: the markers stay nearer the peak than the model has them).
    pub share: f64,
    /// What it removes of the baseline's weighted residual (chi-square on 1 degree of freedom)
    /// and its p-value.
    pub chi2: f64,
    /// The p-value of `chi2`.
    pub p_value: f64,
    /// Vuong's z of the final model against it (positive: the final model fits closer); `None`
    /// when no effect was named.
    pub z: Option<f64>,
    /// Markers where the kept share moves most beyond the noise, worst first.
    pub markers: Vec<(String, f64)>,
    /// Whether it stands against the verdict: a positive share beyond [`REMAINDER_LEVEL`], and
    /// no effect named or the final model not closer by [`VUONG_Z`].
    pub fails: bool,
}

impl Remainder {
    /// Whether either check finds a mismatch the final model leaves.
    pub fn fails(&self) -> bool {
        [&self.hysteresis, &self.lone_markers]
            .iter()
            .any(|t| t.as_ref().is_some_and(|t| t.fails))
            || self.kept_share.as_ref().is_some_and(|k| k.fails)
    }

    /// The markers the mismatch sits at, worst first (the hysteresis's before the lone ones').
    pub fn markers(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let kept = self
            .kept_share
            .as_ref()
            .filter(|k| k.fails)
            .map(|k| &k.markers);
        let tests = [&self.hysteresis, &self.lone_markers]
            .into_iter()
            .flatten()
            .filter(|t| t.fails)
            .map(|t| &t.markers);
        for markers in kept.into_iter().chain(tests) {
            for (m, _) in markers {
                if !out.contains(m) {
                    out.push(m.clone());
                }
            }
        }
        out
    }

    /// The failed checks in words: what the model leaves, where and when.
    pub fn describe(&self) -> Option<String> {
        let names = |t: &Test| {
            t.markers
                .iter()
                .take(4)
                .map(|(m, r)| format!("{m} ({r:.1})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut parts = Vec::new();
        if let Some(k) = self.kept_share.as_ref().filter(|k| k.fails) {
            let list = k
                .markers
                .iter()
                .take(4)
                .map(|(m, r)| format!("{m} ({r:.1})"))
                .collect::<Vec<_>>()
                .join(", ");
            parts.push(format!(
                "on unloading the markers keep {:.0} % of their way back from the peak (chi-square {:.0} on 1, p {:.1e}){}, at {list}",
                100.0 * k.share,
                k.chi2,
                k.p_value,
                k.z.map(|z| format!(
                    ", and the search's reading fits no closer than that description of it (Vuong's z {z:+.2}, needed {})",
                    VUONG_Z
                ))
                .unwrap_or_default()
            ));
        }
        if let Some(t) = self.hysteresis.as_ref().filter(|t| t.fails) {
            parts.push(format!(
                "on unloading the recording leaves its loading branch where the model does not (hysteresis the model lacks: chi-square {:.0} on {}, p {:.1e}), at markers {}",
                t.chi2,
                t.dof,
                t.p_value,
                names(t)
            ));
        }
        if let Some(t) = self.lone_markers.as_ref().filter(|t| t.fails) {
            parts.push(format!(
                "a marker moves where the model and its neighbours do not (beyond the noise and {FORM_ERROR_FACTOR:.0} times the refined mesh's move at it: p {:.1e} over the markers), at {}",
                t.p_value,
                names(t)
            ));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// `P(X > chi2)` for a chi-square `X` on `dof` degrees of freedom (Wilson-Hilferty).
pub fn chi2_upper_tail(chi2: f64, dof: usize) -> f64 {
    let k = dof.max(1) as f64;
    let s = 2.0 / (9.0 * k);
    let z = ((chi2.max(0.0) / k).cbrt() - (1.0 - s)) / s.sqrt();
    if z >= 0.0 {
        upper_tail(z)
    } else {
        1.0 - upper_tail(-z)
    }
}

/// Both checks of the final model's `residuals`; `moved` the refined mesh's move of each
/// (`crate::discretisation::Check::moved`), if measured.
pub fn check(
    recording: &Recording,
    residuals: &[Residual],
    noise: &Noise,
    moved: Option<&[DVec3]>,
) -> Remainder {
    if !noise.measured() {
        return Remainder::default();
    }
    Remainder {
        hysteresis: hysteresis(recording, residuals, noise),
        lone_markers: moved.and_then(|m| lone_markers(recording, residuals, noise, m)),
        kept_share: None,
    }
}

/// Every check of the final model (`final_fit`, against `baseline` for the kept share; `named`:
/// the search named an effect), as the diagnosis runs them.
pub(super) fn of_final(
    recording: &Recording,
    noise: &Noise,
    (baseline, final_fit): (&ModelFit, &ModelFit),
    moved: Option<&[DVec3]>,
    named: bool,
) -> Remainder {
    let residuals = &final_fit.replay.residuals;
    Remainder {
        kept_share: kept_share(recording, noise, baseline, residuals, named),
        ..check(recording, residuals, noise, moved)
    }
}

/// The kept share (`KeptShare`) on `baseline`, against the final model's `residuals` when
/// `named`. One replay of the baseline with its parameters' sensitivities; `None` for a time
/// series, one branch, or a replay that fails.
pub(super) fn kept_share(
    recording: &Recording,
    noise: &Noise,
    baseline: &ModelFit,
    residuals: &[Residual],
    named: bool,
) -> Option<KeptShare> {
    if recording.mode != Mode::QuasiStatic || !noise.measured() {
        return None;
    }
    let turn = *load_turns(recording).first()?;
    let peak = (0..turn).max_by(|&a, &b| {
        recording.samples[a]
            .load
            .total_cmp(&recording.samples[b].load)
    })?;
    let targets: Vec<(&Scene, &str)> = baseline
        .params
        .iter()
        .map(|(n, _)| (&baseline.scene, n.as_str()))
        .collect();
    let (r, columns) = replay_columns(recording, noise, &baseline.scene, &targets)?;
    // The way back from the peak, over the noise, on every coordinate after the turn.
    let at_peak: HashMap<MarkerRef, DVec3> = baseline
        .replay
        .residuals
        .iter()
        .filter(|q| q.sample == peak)
        .map(|q| (q.marker, q.simulated))
        .collect();
    let mut g = Vec::with_capacity(r.len());
    let mut owner = Vec::with_capacity(r.len());
    for q in &baseline.replay.residuals {
        let s = noise.sigma(q.marker);
        for axis in 0..3 {
            if q.recorded[axis].is_some() {
                let back = match at_peak.get(&q.marker) {
                    Some(p) if q.sample >= turn => (p[axis] - q.simulated[axis]) / s,
                    _ => 0.0,
                };
                g.push(back);
                owner.push(q.marker);
            }
        }
    }
    let f = weighted_residuals(residuals, noise);
    if g.len() != r.len() || f.len() != r.len() {
        return None;
    }
    let (share, chi2, described) = share_kept(&r, columns, &g)?;
    let p_value = chi2_upper_tail(chi2, 1);
    let z = named.then(|| vuong(&f, &described)).flatten();
    // Per marker, how far the kept share moves it over the noise.
    let mut per: BTreeMap<(u8, usize), (MarkerRef, f64, usize)> = BTreeMap::new();
    for ((gi, m), _) in g.iter().zip(&owner).zip(&r) {
        let e = per.entry(marker_key(*m)).or_insert((*m, 0.0, 0));
        e.1 += (share * gi).powi(2);
        e.2 += 1;
    }
    let per: Vec<(MarkerRef, f64, usize)> = per.into_values().collect();
    let markers = beyond(recording, &per, REMAINDER_LEVEL / per.len().max(1) as f64);
    let fails = share > 0.0
        && p_value < REMAINDER_LEVEL
        && !markers.is_empty()
        && z.is_none_or(|z| z < VUONG_Z);
    Some(KeptShare {
        share,
        chi2,
        p_value,
        z,
        markers,
        fails,
    })
}

/// The hysteresis check (module docs): each observed coordinate of a sample after the first
/// turn of the load against the first branch's residual interpolated linearly to its load,
/// `d = r - (w r_a + (1 - w) r_b)` over the noise, of variance `1 + w^2 + (1 - w)^2`. `None` for a
/// time series or a recording with one branch.
pub fn hysteresis(recording: &Recording, residuals: &[Residual], noise: &Noise) -> Option<Test> {
    if recording.mode != Mode::QuasiStatic {
        return None;
    }
    let turn = *load_turns(recording).first()?;
    let loads: Vec<f64> = recording.samples.iter().map(|s| s.load).collect();
    // The first branch's samples by load, in order.
    let mut first: Vec<(f64, usize)> = (0..turn).map(|i| (loads[i], i)).collect();
    first.sort_by(|a, b| a.0.total_cmp(&b.0));
    let at: HashMap<(usize, MarkerRef), &Residual> = residuals
        .iter()
        .map(|r| ((r.sample, r.marker), r))
        .collect();
    let mut per: BTreeMap<(u8, usize), (MarkerRef, f64, usize)> = BTreeMap::new();
    // Object markers only, as for lone markers: a finger's reading is the actuator's, and the
    // way its depth goes around a loop carries the contact law's and the friction law's own form.
    let on_object = |r: &&Residual| matches!(r.marker, MarkerRef::Object(_));
    for r in residuals
        .iter()
        .filter(|r| r.sample >= turn)
        .filter(on_object)
    {
        let load = loads[r.sample];
        let Some(k) = first
            .windows(2)
            .position(|w| w[0].0 <= load && load <= w[1].0)
        else {
            continue;
        };
        let ((la, a), (lb, b)) = (first[k], first[k + 1]);
        let w = if lb > la {
            (lb - load) / (lb - la)
        } else {
            1.0
        };
        let (Some(ra), Some(rb)) = (at.get(&(a, r.marker)), at.get(&(b, r.marker))) else {
            continue;
        };
        let s = noise.sigma(r.marker);
        let variance = 1.0 + w * w + (1.0 - w) * (1.0 - w);
        for axis in 0..3 {
            let (Some(x), Some(xa), Some(xb)) =
                (r.recorded[axis], ra.recorded[axis], rb.recorded[axis])
            else {
                continue;
            };
            let d = (r.simulated[axis] - x)
                - w * (ra.simulated[axis] - xa)
                - (1.0 - w) * (rb.simulated[axis] - xb);
            let e = per
                .entry(marker_key(r.marker))
                .or_insert((r.marker, 0.0, 0));
            e.1 += d * d / (s * s * variance);
            e.2 += 1;
        }
    }
    let per: Vec<(MarkerRef, f64, usize)> = per.into_values().collect();
    let (chi2, dof) = per.iter().fold((0.0, 0), |(c, n), m| (c + m.1, n + m.2));
    if dof == 0 {
        return None;
    }
    let p_value = chi2_upper_tail(chi2, dof);
    // Each marker against the same level shared among the markers.
    let level = REMAINDER_LEVEL / per.len() as f64;
    let markers = beyond(recording, &per, level);
    // A loop the model lacks shows at the markers it moves; a small excess spread thin over
    // every marker, none beyond its own level, is the named law's form around the loop.
    let fails = p_value < REMAINDER_LEVEL && !markers.is_empty();
    Some(Test {
        chi2,
        dof,
        p_value,
        markers,
        fails,
    })
}

/// The lone-marker check (module docs): each object marker's chi-square over the noise and
/// [`FORM_ERROR_FACTOR`] times the refined mesh's move at each coordinate, after its own simulated
/// move (from its reference) scaled to fit is taken out; it fails when some
/// markers, at most a quarter of them (one of up to seven), are beyond the level shared among the
/// markers and the others together are not, and some stay beyond it with each sample's part
/// capped (a slip stays, a camera's outlier does not: [`capped_chi2`]).
pub fn lone_markers(
    recording: &Recording,
    residuals: &[Residual],
    noise: &Noise,
    moved: &[DVec3],
) -> Option<Test> {
    if moved.len() != residuals.len() {
        return None;
    }
    let tracks = marker_tracks(recording, residuals, noise, moved);
    let (per, per_capped) = scaled_chi2(tracks);
    if per.len() < 2 {
        return None;
    }
    let level = REMAINDER_LEVEL / per.len() as f64;
    let markers = beyond(recording, &per, level);
    let worst = per
        .iter()
        .map(|(_, c, n)| chi2_upper_tail(*c, *n))
        .fold(1.0, f64::min);
    let (chi2, dof) = per.iter().fold((0.0, 0), |(c, n), m| (c + m.1, n + m.2));
    let lone: Vec<&(MarkerRef, f64, usize)> = per
        .iter()
        .filter(|(m, _, _)| markers.iter().any(|(n, _)| *n == recording.marker_name(*m)))
        .collect();
    let (rest_chi2, rest_dof) = per
        .iter()
        .filter(|m| !lone.contains(m))
        .fold((0.0, 0), |(c, n), m| (c + m.1, n + m.2));
    let few = !lone.is_empty() && 4 * lone.len() <= per.len().max(4);
    let rest_within = rest_dof == 0 || chi2_upper_tail(rest_chi2, rest_dof) >= REMAINDER_LEVEL;
    // A lone marker must stay beyond its level with each sample's part capped: not one outlier.
    let confirmed: Vec<(String, f64)> = beyond(recording, &per_capped, level)
        .into_iter()
        .filter(|(n, _)| markers.iter().any(|(m, _)| m == n))
        .collect();
    let fails = few && rest_within && !confirmed.is_empty();
    Some(Test {
        chi2,
        dof,
        p_value: (worst * per.len() as f64).min(1.0),
        markers: if fails { confirmed } else { markers },
        fails,
    })
}

/// Each marker's chi-square and degrees of freedom once its own move is scaled out, plain and
/// with each sample's part capped ([`capped_chi2`]), in the markers' order.
fn scaled_chi2(tracks: BTreeMap<(u8, usize), (MarkerRef, Coordinates)>) -> (PerMarker, PerMarker) {
    // What is left of each once its own move is scaled to fit: a model's error of form moves a
    // marker more or less along the way it moves it; a slip moves it where the model does not.
    let mut per: BTreeMap<(u8, usize), (MarkerRef, f64, usize)> = BTreeMap::new();
    let mut per_capped = per.clone();
    for (key, (marker, track)) in tracks {
        let (ru, uu) = track.iter().fold((0.0, 0.0), |(a, b), (_, r, u, w)| {
            (a + w * r * u, b + w * u * u)
        });
        let c = if uu > 0.0 { ru / uu } else { 0.0 };
        let (chi2, capped, dof) = capped_chi2(&track, c);
        per.insert(key, (marker, chi2, dof));
        per_capped.insert(key, (marker, capped, dof));
    }
    let per: Vec<(MarkerRef, f64, usize)> = per.into_values().collect();
    let per_capped: Vec<(MarkerRef, f64, usize)> = per_capped.into_values().collect();
    (per, per_capped)
}

/// A marker's coordinates: each one's sample, residual (simulated - recorded, m), own simulated
/// move from its reference (m), and weight (1 / m^2: the noise and the form error band).
type Coordinates = Vec<(usize, f64, f64, f64)>;

/// Each marker's chi-square and degrees of freedom.
type PerMarker = Vec<(MarkerRef, f64, usize)>;

/// Each object marker's coordinates ([`Coordinates`]), by marker. Object markers only: a
/// finger's reading is the actuator's, not a point on the skin, and its depth carries the
/// contact law's own error.
fn marker_tracks(
    recording: &Recording,
    residuals: &[Residual],
    noise: &Noise,
    moved: &[DVec3],
) -> BTreeMap<(u8, usize), (MarkerRef, Coordinates)> {
    let mut tracks: BTreeMap<(u8, usize), (MarkerRef, Coordinates)> = BTreeMap::new();
    for (r, m) in residuals.iter().zip(moved) {
        let MarkerRef::Object(i) = r.marker else {
            continue;
        };
        let Some(reference) = recording.markers.get(i).map(|m| m.reference) else {
            continue;
        };
        let s = noise.sigma(r.marker);
        for axis in 0..3 {
            let Some(x) = r.recorded[axis] else { continue };
            let band = FORM_ERROR_FACTOR * m[axis];
            let track = &mut tracks
                .entry(marker_key(r.marker))
                .or_insert((r.marker, Vec::new()))
                .1;
            track.push((
                r.sample,
                r.simulated[axis] - x,
                r.simulated[axis] - reference[axis],
                1.0 / (s * s + band * band),
            ));
        }
    }
    tracks
}

/// A marker's chi-square, the same with each sample's part capped at its 1 % point (9.21 for two
/// coordinates), and their degrees of freedom, once its own move scaled by `c` is taken out of its
/// `track` (sample, residual, own move, weight per coordinate). Capped, one outlying sample adds
/// at most what one sample in a hundred adds, while a slip, in every sample from its load on,
/// adds in each: the proof's controls, whose noise has a camera's outliers, failed the check at
/// p 1.4e-4 on one marker's few samples.
fn capped_chi2(track: &[(usize, f64, f64, f64)], c: f64) -> (f64, f64, usize) {
    let mut by_sample: BTreeMap<usize, (f64, usize)> = BTreeMap::new();
    for (sample, r, u, w) in track {
        let e = by_sample.entry(*sample).or_insert((0.0, 0));
        e.0 += w * (r - c * u).powi(2);
        e.1 += 1;
    }
    // chi-square's upper 1 % points for one to three degrees of freedom.
    let cap = |k: usize| [6.63, 9.21, 11.34][k.clamp(1, 3) - 1];
    let (chi2, capped, dof) = by_sample.values().fold((0.0, 0.0, 0), |(a, b, n), (x, k)| {
        (a + x, b + x.min(cap(*k)), n + k)
    });
    (chi2, capped, dof.saturating_sub(1))
}

/// The least-squares fit of the weighted residual `r` by the parameters' `columns` and the way
/// back `g` (modified Gram-Schmidt, the way orthogonalised last): the share along `g` (the
/// model's positions plus `share g` fit best), its chi-square (what it removes beyond the
/// columns), and the residual left. `None` when `g` lies in the columns' span.
pub fn share_kept(
    r: &[f64],
    mut columns: Vec<Vec<f64>>,
    g: &[f64],
) -> Option<(f64, f64, Vec<f64>)> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut basis: Vec<Vec<f64>> = Vec::new();
    columns.push(g.to_vec());
    let last = columns.len() - 1;
    let mut q_last: Option<(Vec<f64>, f64)> = None;
    for (j, mut c) in columns.into_iter().enumerate() {
        for b in &basis {
            let k = dot(&c, b);
            c.iter_mut().zip(b).for_each(|(x, y)| *x -= k * y);
        }
        let norm = dot(&c, &c).sqrt();
        if norm <= 1e-12 * dot(g, g).sqrt().max(1e-300) {
            continue;
        }
        c.iter_mut().for_each(|x| *x /= norm);
        if j == last {
            q_last = Some((c.clone(), norm));
        }
        basis.push(c);
    }
    let (q, norm) = q_last?;
    let along = dot(&q, r);
    let mut left = r.to_vec();
    for b in &basis {
        let k = dot(&left, b);
        left.iter_mut().zip(b).for_each(|(x, y)| *x -= k * y);
    }
    // r + J d + share g = left: along q, r's component is cancelled by share's.
    Some((-along / norm, along * along, left))
}

/// The markers of `per` (marker, chi-square, count) whose p-value is below `level`, worst first,
/// with their RMS over their bar.
fn beyond(
    recording: &Recording,
    per: &[(MarkerRef, f64, usize)],
    level: f64,
) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = per
        .iter()
        .filter(|(_, c, n)| *n > 0 && chi2_upper_tail(*c, *n) < level)
        .map(|(m, c, n)| (recording.marker_name(*m), (c / *n as f64).sqrt()))
        .collect();
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wilson-Hilferty against tabled quantiles: chi-square(10)'s 0.95 point 18.307 and 0.999
    /// point 29.588, chi-square(1)'s 0.95 point 3.841 (to the approximation's few percent).
    /// A residual made of a parameter's column, a share of the way back and a little noise: the
    /// share is recovered, its chi-square is the way's part of the residual, and what is left is
    /// the noise's.
    #[test]
    fn the_kept_share_is_recovered_beside_the_parameters() {
        let n = 40;
        let column: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin()).collect();
        let g: Vec<f64> = (0..n)
            .map(|i| if i >= 30 { 1.0 + 0.1 * i as f64 } else { 0.0 })
            .collect();
        let noise: Vec<f64> = (0..n).map(|i| 0.01 * ((i * 7 % 5) as f64 - 2.0)).collect();
        // The recording is the model plus 0.4 of the way back, the model off by 2 of the column.
        let r: Vec<f64> = (0..n)
            .map(|i| 2.0 * column[i] - 0.4 * g[i] + noise[i])
            .collect();
        let (share, chi2, left) = share_kept(&r, vec![column.clone()], &g).unwrap();
        assert!((share - 0.4).abs() < 0.01, "{share}");
        let gg: f64 = g.iter().map(|x| x * x).sum();
        assert!(chi2 > 0.1 * 0.4 * 0.4 * gg, "{chi2}");
        let rest: f64 = left.iter().map(|x| x * x).sum();
        let noise2: f64 = noise.iter().map(|x| x * x).sum();
        assert!(rest <= noise2 + 1e-12, "{rest} {noise2}");
        // A way back inside the columns' span has no share of its own.
        assert!(share_kept(&r, vec![g.clone()], &g).is_none());
    }

    #[test]
    fn the_chi_square_tail_matches_tabled_quantiles() {
        assert!((chi2_upper_tail(18.307, 10) - 0.05).abs() < 0.002);
        assert!((chi2_upper_tail(29.588, 10) - 0.001).abs() < 0.0002);
        assert!((chi2_upper_tail(3.841, 1) - 0.05).abs() < 0.005);
        assert!((chi2_upper_tail(10.0, 10) - 0.44).abs() < 0.01);
    }
}
