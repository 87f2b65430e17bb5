//! How an object rings: the dominant damped oscillation of a time series, measured from the
//! data alone (a recording's markers, or a replay's simulated ones).
//!
//! A coordinate `z(t)` is fitted with `c + A exp(-s t) cos(w t + phi)` by least squares. The
//! model is linear in `c`, `A cos phi` and `A sin phi` once `w` and `s` are fixed, so those three
//! come from a linear solve inside the search (variable projection) and the search itself is
//! two-dimensional: Levenberg-Marquardt on `(w, s)`, started from the periodogram's peak and
//! from the zero crossings, with the decay started from the fall of the signal's RMS between the
//! window's halves. The frequency is `f = w / (2 pi)`, the decay rate `s` (1/s), the damping
//! ratio `zeta = s / sqrt(s^2 + w^2)` (the ratio of a mode `exp((-zeta w0 + i w) t)` with
//! `w0 = sqrt(s^2 + w^2)`).
//!
//! A recording's ringing is that of the marker axis that moves most (the largest standard
//! deviation of its recorded coordinate); the simulation's is measured on the same marker axis
//! of the replay, so the two compare like for like. Short, flat or non-finite data give a
//! [`NoRinging`], never a panic.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::compare::Residual;
use crate::recording::{MarkerRef, Mode, Recording};

/// Samples at least, and the smallest number of a fit's degrees of freedom left over.
pub const MIN_SAMPLES: usize = 8;

/// A damped oscillation fitted to a time series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ringing {
    /// f = w / (2 pi), Hz.
    pub frequency_hz: f64,
    /// s, 1/s: the amplitude falls as exp(-s t).
    pub decay_rate: f64,
    /// zeta = s / sqrt(s^2 + w^2).
    pub damping_ratio: f64,
    /// A at the window's first sample (the coordinate's unit, m for markers).
    pub amplitude: f64,
    /// c, the level the oscillation settles to.
    pub offset: f64,
    /// phi, rad, at the first sample.
    pub phase: f64,
    /// The root-mean-square of the fit's residual (the coordinate's unit).
    pub residual_rms: f64,
    /// The share of the signal's variance the fit explains (1 - SSR / SST).
    pub explained: f64,
    /// The samples fitted and the window they span (s).
    pub samples: usize,
    /// Start of the window fitted, s.
    pub start: f64,
    /// End of the window fitted, s.
    pub end: f64,
}

impl Ringing {
    /// The angular frequency w, rad/s.
    pub fn angular_frequency(&self) -> f64 {
        std::f64::consts::TAU * self.frequency_hz
    }

    /// The figures as JSON (SI units).
    pub fn to_json(&self) -> serde_json::Value {
        // Numbers only: nothing here fails to serialize.
        serde_json::to_value(self.figures()).unwrap_or(serde_json::Value::Null)
    }

    /// The figures as the JSON outputs give them (SI units).
    pub fn figures(&self) -> RingingFigures {
        RingingFigures {
            frequency_hz: self.frequency_hz,
            decay_rate_per_s: self.decay_rate,
            damping_ratio: self.damping_ratio,
            amplitude: self.amplitude,
            offset: self.offset,
            phase_rad: self.phase,
            residual_rms: self.residual_rms,
            explained: self.explained,
            samples: self.samples,
            window_s: [self.start, self.end],
        }
    }
}

/// A damped oscillation `c + A exp(-s t) cos(w t + phi)` fitted to a marker coordinate, as the
/// JSON outputs give it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RingingFigures {
    /// f = w / (2 pi), Hz.
    pub frequency_hz: f64,
    /// s, 1/s: the amplitude falls as exp(-s t).
    pub decay_rate_per_s: f64,
    /// zeta = s / sqrt(s^2 + w^2), dimensionless.
    pub damping_ratio: f64,
    /// A at the window's first sample, m.
    pub amplitude: f64,
    /// c, the level the oscillation settles to, m.
    pub offset: f64,
    /// phi at the window's first sample, rad.
    pub phase_rad: f64,
    /// Root-mean-square of the fit's residual, m.
    pub residual_rms: f64,
    /// Share of the signal's variance the fit explains, 1 - SSR / SST (fraction).
    pub explained: f64,
    /// Samples fitted.
    pub samples: usize,
    /// Start and end of the window fitted, s.
    pub window_s: [f64; 2],
}

/// Why a coordinate shows no ringing, as the JSON outputs give it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NoRingingFigures {
    /// Why no damped oscillation was measured, in words.
    pub error: String,
}

/// One side's ringing in the JSON outputs: the figures, or why there are none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum RingingSide {
    /// The oscillation measured.
    Measured(RingingFigures),
    /// Why none was.
    None(NoRingingFigures),
}

impl From<&Result<Ringing, NoRinging>> for RingingSide {
    fn from(r: &Result<Ringing, NoRinging>) -> Self {
        match r {
            Ok(r) => RingingSide::Measured(r.figures()),
            Err(e) => RingingSide::None(NoRingingFigures {
                error: e.to_string(),
            }),
        }
    }
}

/// The recording's ringing and the simulation's on the same marker axis, as `compare --json`
/// gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RingingComparisonFigures {
    /// The marker whose coordinate moves most (its name in the recording).
    pub marker: String,
    /// Its axis: `x`, `y` or `z`.
    pub axis: String,
    /// The recorded coordinate's ringing.
    pub recorded: RingingSide,
    /// The simulated coordinate's ringing.
    pub simulated: RingingSide,
}

/// Why no oscillation could be measured.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum NoRinging {
    /// Fewer samples than [`MIN_SAMPLES`].
    #[error("{0} samples; a ringing needs at least {MIN_SAMPLES}")]
    TooShort(usize),
    /// A time or value is not finite, or the times do not increase.
    #[error("a time or value is not finite, or the times do not increase")]
    BadData,
    /// The coordinate does not move.
    #[error("the coordinate does not move")]
    Flat,
    /// No damped oscillation fits.
    #[error("no damped oscillation fits the data")]
    NoFit,
}

/// The linear part at fixed `(w, s)`: `c`, `a`, `b` of `c + exp(-s t) (a cos wt + b sin wt)`,
/// and the residual (model minus data). `None` where the 3x3 system is singular.
fn project(t: &[f64], z: &[f64], w: f64, s: f64) -> Option<([f64; 3], Vec<f64>)> {
    let mut ata = [[0.0; 3]; 3];
    let mut atz = [0.0; 3];
    let basis = |t: f64| {
        let e = (-s * t).exp();
        [1.0, e * (w * t).cos(), e * (w * t).sin()]
    };
    for (&ti, &zi) in t.iter().zip(z) {
        let g = basis(ti);
        for i in 0..3 {
            atz[i] += g[i] * zi;
            for j in 0..3 {
                ata[i][j] += g[i] * g[j];
            }
        }
    }
    let coef = solve3(ata, atz)?;
    let residual: Vec<f64> = t
        .iter()
        .zip(z)
        .map(|(&ti, &zi)| {
            let g = basis(ti);
            coef[0] * g[0] + coef[1] * g[1] + coef[2] * g[2] - zi
        })
        .collect();
    residual
        .iter()
        .all(|r| r.is_finite())
        .then_some((coef, residual))
}

/// `A x = b` for a 3x3 system by Gaussian elimination with partial pivoting, scaled so that a
/// near-singular system (a basis column that vanishes) reads as singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    let scale = (0..3).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 || scale.is_infinite() {
        return None;
    }
    for k in 0..3 {
        let p = (k..3).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[p][k].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..3 {
            let f = a[i][k] / a[k][k];
            for j in k..3 {
                a[i][j] -= f * a[k][j];
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = [0.0; 3];
    for k in (0..3).rev() {
        let rest: f64 = (k + 1..3).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - rest) / a[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

fn ssr(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// The bounds of the search: w in (0, Nyquist], |s| at most a few times w plus the window's own
/// rate (a signal that grows or dies within a sample interval is not a ringing).
struct Bounds {
    w_max: f64,
    s_max: f64,
}

impl Bounds {
    fn clamp(&self, w: f64, s: f64) -> (f64, f64) {
        (
            w.clamp(1e-6 * self.w_max, self.w_max),
            s.clamp(-self.s_max, self.s_max),
        )
    }
}

/// Levenberg-Marquardt on `(w, s)` of the projected residual, from `(w, s)`.
fn refine(t: &[f64], z: &[f64], bounds: &Bounds, w: f64, s: f64) -> Option<(f64, f64, f64)> {
    let (mut w, mut s) = bounds.clamp(w, s);
    let (_, mut r) = project(t, z, w, s)?;
    let mut f = ssr(&r);
    let mut lambda = 1e-3;
    for _ in 0..200 {
        // Central differences; steps relative to the scale of each coordinate.
        let hw = 1e-6 * w.max(1e-3 * bounds.w_max);
        let hs = 1e-6 * (s.abs() + w);
        let column = |dw: f64, ds: f64| -> Option<Vec<f64>> {
            let (_, a) = project(t, z, w + dw, s + ds)?;
            let (_, b) = project(t, z, w - dw, s - ds)?;
            let h = 2.0 * (dw + ds);
            Some(a.iter().zip(&b).map(|(x, y)| (x - y) / h).collect())
        };
        let (jw, js) = (column(hw, 0.0)?, column(0.0, hs)?);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let (aww, ass, aws) = (dot(&jw, &jw), dot(&js, &js), dot(&jw, &js));
        let (gw, gs) = (dot(&jw, &r), dot(&js, &r));
        let mut improved = false;
        for _ in 0..30 {
            let (a11, a22) = (aww * (1.0 + lambda), ass * (1.0 + lambda));
            let det = a11 * a22 - aws * aws;
            if !det.is_finite() || det <= 0.0 {
                lambda *= 10.0;
                continue;
            }
            let dw = -(a22 * gw - aws * gs) / det;
            let ds = -(a11 * gs - aws * gw) / det;
            let (nw, ns) = bounds.clamp(w + dw, s + ds);
            match project(t, z, nw, ns) {
                Some((_, nr)) if ssr(&nr) < f => {
                    let nf = ssr(&nr);
                    let small =
                        (nw - w).abs() <= 1e-10 * w && (ns - s).abs() <= 1e-10 * (w + s.abs());
                    let gain = f - nf;
                    (w, s, r, f) = (nw, ns, nr, nf);
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = !small && gain > 1e-14 * f;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved {
            break;
        }
    }
    Some((w, s, f))
}

/// The periodogram's peak (Hz) of `z` minus its mean, on a grid four times finer than the
/// window resolves, between half a cycle in the window and the Nyquist frequency; refined by a
/// parabola through the peak and its neighbours.
fn spectrum_peak(t: &[f64], z: &[f64], f_max: f64) -> Option<f64> {
    let span = t[t.len() - 1] - t[0];
    let f_min = 0.5 / span;
    let df = 0.25 / span;
    let count = (((f_max - f_min) / df).ceil() as usize).clamp(3, 4000);
    let df = (f_max - f_min) / (count - 1) as f64;
    let power: Vec<f64> = (0..count)
        .map(|k| {
            let w = std::f64::consts::TAU * (f_min + k as f64 * df);
            let (c, s) = t.iter().zip(z).fold((0.0, 0.0), |(c, s), (&ti, &zi)| {
                let (sin, cos) = (w * (ti - t[0])).sin_cos();
                (c + zi * cos, s + zi * sin)
            });
            c * c + s * s
        })
        .collect();
    let k = (0..count).max_by(|&i, &j| power[i].total_cmp(&power[j]))?;
    let mut f = f_min + k as f64 * df;
    if k > 0 && k + 1 < count {
        let (a, b, c) = (power[k - 1], power[k], power[k + 1]);
        let d = a - 2.0 * b + c;
        if d < 0.0 {
            f += 0.5 * df * (a - c) / d;
        }
    }
    (f > 0.0).then_some(f)
}

/// The frequency (Hz) from the crossings of the mean: half a period between crossings.
fn crossings_frequency(t: &[f64], z: &[f64]) -> Option<f64> {
    let mut at: Vec<f64> = Vec::new();
    for i in 1..z.len() {
        let (a, b) = (z[i - 1], z[i]);
        if (a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0) {
            at.push(t[i - 1] + (t[i] - t[i - 1]) * a / (a - b));
        }
    }
    (at.len() >= 2).then(|| (at.len() - 1) as f64 / (2.0 * (at[at.len() - 1] - at[0])))
}

/// The damped oscillation of `values` sampled at `times` (s, increasing).
pub fn measure(times: &[f64], values: &[f64]) -> Result<Ringing, NoRinging> {
    let n = times.len().min(values.len());
    if n < MIN_SAMPLES {
        return Err(NoRinging::TooShort(n));
    }
    let (times, values) = (&times[..n], &values[..n]);
    if times.iter().chain(values).any(|x| !x.is_finite()) || times.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(NoRinging::BadData);
    }
    // From the first sample, and the mean taken out: the fit is then well scaled.
    let t: Vec<f64> = times.iter().map(|x| x - times[0]).collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let z: Vec<f64> = values.iter().map(|v| v - mean).collect();
    let sst = ssr(&z);
    let size = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if sst.is_nan()
        || sst <= 0.0
        || sst.sqrt() / (n as f64).sqrt() <= 1e-12 * size.max(f64::MIN_POSITIVE)
    {
        return Err(NoRinging::Flat);
    }
    let span = t[n - 1];
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let dt = steps[steps.len() / 2];
    let f_nyquist = 0.5 / dt;
    let bounds = Bounds {
        w_max: std::f64::consts::TAU * f_nyquist,
        s_max: 4.0 * std::f64::consts::TAU * f_nyquist + 10.0 / span,
    };
    // The decay from the RMS of the two halves: exp(-s span / 2) is their ratio.
    let rms = |part: &[f64]| {
        let m = part.iter().sum::<f64>() / part.len() as f64;
        (part.iter().map(|x| (x - m).powi(2)).sum::<f64>() / part.len() as f64).sqrt()
    };
    let (first, second) = z.split_at(n / 2);
    let s0 = match (rms(first), rms(second)) {
        (a, b) if a > 0.0 && b > 0.0 => (2.0 * (a / b).ln() / span).max(0.0),
        _ => 1.0 / span,
    };
    let mut starts: Vec<f64> = [
        spectrum_peak(&t, &z, f_nyquist),
        crossings_frequency(&t, &z),
    ]
    .into_iter()
    .flatten()
    .collect();
    starts.dedup();
    let mut best: Option<(f64, f64, f64)> = None;
    for f in starts {
        let w = std::f64::consts::TAU * f;
        for s in [s0, 0.3 * s0, 3.0 * s0 + 1.0 / span] {
            if let Some(r) = refine(&t, &z, &bounds, w, s)
                && best.is_none_or(|b| r.2 < b.2)
            {
                best = Some(r);
            }
        }
    }
    let (w, s, f) = best.ok_or(NoRinging::NoFit)?;
    let (coef, _) = project(&t, &z, w, s).ok_or(NoRinging::NoFit)?;
    let amplitude = coef[1].hypot(coef[2]);
    if !amplitude.is_finite() || amplitude <= 0.0 {
        return Err(NoRinging::NoFit);
    }
    Ok(Ringing {
        frequency_hz: w / std::f64::consts::TAU,
        decay_rate: s,
        damping_ratio: s / s.hypot(w),
        amplitude,
        offset: mean + coef[0],
        phase: (-coef[2]).atan2(coef[1]),
        residual_rms: (f / n as f64).sqrt(),
        explained: 1.0 - f / sst,
        samples: n,
        start: times[0],
        end: times[n - 1],
    })
}

/// One marker axis's ringing.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisRinging {
    /// The marker.
    pub marker: MarkerRef,
    /// 0, 1, 2 for x, y, z.
    pub axis: usize,
    /// The standard deviation of the recorded coordinate (m): how much it moves.
    pub motion: f64,
    /// The damped oscillation fitted to the recorded coordinate, or why none.
    pub ringing: Result<Ringing, NoRinging>,
}

/// The axis's letter.
pub fn axis_name(axis: usize) -> &'static str {
    ["x", "y", "z"].get(axis).copied().unwrap_or("?")
}

/// The recorded coordinate `axis` of `marker` over time: (times, values), where observed.
pub fn recorded_series(
    recording: &Recording,
    marker: MarkerRef,
    axis: usize,
) -> (Vec<f64>, Vec<f64>) {
    recording
        .samples
        .iter()
        .filter_map(|s| {
            let t = s.time?;
            let o = s.observations.iter().find(|o| o.marker == marker)?;
            Some((t, o.position.get(axis).copied().flatten()?))
        })
        .unzip()
}

/// The simulated coordinate `axis` of `marker` over time from a replay's residuals (where the
/// recording observed it).
pub fn simulated_series(
    recording: &Recording,
    residuals: &[Residual],
    marker: MarkerRef,
    axis: usize,
) -> (Vec<f64>, Vec<f64>) {
    residuals
        .iter()
        .filter(|r| r.marker == marker && r.recorded.get(axis).copied().flatten().is_some())
        .filter_map(|r| {
            let t = recording.samples.get(r.sample)?.time?;
            Some((t, r.simulated[axis]))
        })
        .unzip()
}

/// The markers NRMSE scores (the object's, or the fingers' when there are none), in order.
fn scored_markers(recording: &Recording) -> Vec<MarkerRef> {
    let mut all: Vec<MarkerRef> = recording
        .samples
        .iter()
        .flat_map(|s| s.observations.iter().map(|o| o.marker))
        .collect();
    all.sort();
    all.dedup();
    let object = all.iter().any(|m| matches!(m, MarkerRef::Object(_)));
    all.retain(|m| !object || matches!(m, MarkerRef::Object(_)));
    all
}

/// Every scored marker axis's ringing, in marker then axis order (empty for a quasi-static
/// recording: it has no time).
pub fn of_recording(recording: &Recording) -> Vec<AxisRinging> {
    if recording.mode != Mode::TimeSeries {
        return Vec::new();
    }
    let mut out = Vec::new();
    for marker in scored_markers(recording) {
        for axis in 0..3 {
            let (t, z) = recorded_series(recording, marker, axis);
            if t.is_empty() {
                continue;
            }
            let mean = z.iter().sum::<f64>() / z.len() as f64;
            let motion =
                (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / z.len() as f64).sqrt();
            out.push(AxisRinging {
                marker,
                axis,
                motion,
                ringing: measure(&t, &z),
            });
        }
    }
    out
}

/// The recording's ringing: that of the marker axis that moves most (ties: the first).
pub fn dominant(recording: &Recording) -> Option<AxisRinging> {
    of_recording(recording)
        .into_iter()
        .fold(None, |best: Option<AxisRinging>, a| match best {
            Some(b) if b.motion >= a.motion => Some(b),
            _ => Some(a),
        })
}

/// The recording's ringing and the simulation's on the same marker axis.
#[derive(Debug, Clone, PartialEq)]
pub struct RingingComparison {
    /// The marker.
    pub marker: MarkerRef,
    /// The axis: 0, 1, 2 for x, y, z.
    pub axis: usize,
    /// The recorded coordinate's ringing, or why none.
    pub recorded: Result<Ringing, NoRinging>,
    /// The simulated coordinate's ringing, or why none.
    pub simulated: Result<Ringing, NoRinging>,
}

impl RingingComparison {
    /// The figures as JSON: the marker axis, and each side's ringing (or why there is none).
    pub fn to_json(&self, recording: &Recording) -> serde_json::Value {
        // Numbers and strings only: nothing here fails to serialize.
        serde_json::to_value(self.figures(recording)).unwrap_or(serde_json::Value::Null)
    }

    /// The figures as the JSON outputs give them.
    pub fn figures(&self, recording: &Recording) -> RingingComparisonFigures {
        RingingComparisonFigures {
            marker: recording.marker_name(self.marker),
            axis: axis_name(self.axis).to_string(),
            recorded: (&self.recorded).into(),
            simulated: (&self.simulated).into(),
        }
    }
}

/// The recording's ringing (its most-moving marker axis) against the replay's on that axis;
/// `None` for a quasi-static recording or one with no time-series marker axis.
pub fn compare(recording: &Recording, residuals: &[Residual]) -> Option<RingingComparison> {
    let d = dominant(recording)?;
    let (t, z) = simulated_series(recording, residuals, d.marker, d.axis);
    Some(RingingComparison {
        marker: d.marker,
        axis: d.axis,
        recorded: d.ringing,
        simulated: measure(&t, &z),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::Gaussian;

    fn damped(
        f: f64,
        s: f64,
        a: f64,
        c: f64,
        phi: f64,
        noise: f64,
        n: usize,
        dt: f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut g = Gaussian::new(3);
        let w = std::f64::consts::TAU * f;
        (0..n)
            .map(|i| {
                let t = 0.5 + i as f64 * dt;
                let x = t - 0.5;
                (
                    t,
                    c + a * (-s * x).exp() * (w * x + phi).cos() + noise * g.sample(),
                )
            })
            .unzip()
    }

    /// Exact damped sinusoids come back to rounding; with noise of 2 % of the amplitude, within
    /// 1 % in f and 5 % in s (the beam recordings' scale: 100 Hz, 1.6 to 2.5 s, zeta 0.05).
    #[test]
    fn recovers_frequency_and_decay_of_damped_sinusoids() {
        for &(f, s, phi) in &[
            (7.7, 2.7, 0.3),
            (4.35, 1.8, -2.0),
            (3.41, 1.4, 1.2),
            (1.0, 0.2, 0.0),
        ] {
            let (t, z) = damped(f, s, 5e-3, 0.03, phi, 0.0, 200, 0.01);
            let r = measure(&t, &z).unwrap();
            assert!((r.frequency_hz - f).abs() < 1e-6 * f, "{f}: {r:?}");
            assert!((r.decay_rate - s).abs() < 1e-5 * s, "{s}: {r:?}");
            assert!((r.amplitude - 5e-3).abs() < 1e-8, "{r:?}");
            assert!((r.offset - 0.03).abs() < 1e-9, "{r:?}");
            let w = std::f64::consts::TAU * f;
            assert!((r.damping_ratio - s / (s * s + w * w).sqrt()).abs() < 1e-6);
            assert!(r.residual_rms < 1e-9 && r.explained > 0.999_999, "{r:?}");
            let (t, z) = damped(f, s, 5e-3, 0.03, phi, 1e-4, 200, 0.01);
            let r = measure(&t, &z).unwrap();
            assert!((r.frequency_hz - f).abs() < 0.01 * f, "{f}: {r:?}");
            assert!((r.decay_rate - s).abs() < 0.05 * s, "{s}: {r:?}");
            assert!((r.residual_rms / 1e-4 - 1.0).abs() < 0.15, "{r:?}");
        }
    }

    /// A ringing that is undamped, or one whose window starts after the first cycles, is found.
    #[test]
    fn undamped_and_late_windows() {
        let (t, z) = damped(12.0, 0.0, 1.0, -2.0, 0.7, 0.01, 100, 0.01);
        let r = measure(&t, &z).unwrap();
        assert!((r.frequency_hz - 12.0).abs() < 0.02, "{r:?}");
        assert!(r.decay_rate.abs() < 0.05, "{r:?}");
        let (t, z) = damped(5.0, 3.0, 1.0, 0.0, 0.0, 0.001, 300, 0.01);
        let r = measure(&t[50..], &z[50..]).unwrap();
        assert!(
            (r.frequency_hz - 5.0).abs() < 0.01 && (r.decay_rate - 3.0).abs() < 0.05,
            "{r:?}"
        );
        // The amplitude is at the window's start.
        assert!((r.amplitude - (-3.0f64 * 0.5).exp()).abs() < 0.01, "{r:?}");
    }

    #[test]
    fn short_flat_and_bad_data_are_errors_not_panics() {
        assert_eq!(measure(&[], &[]), Err(NoRinging::TooShort(0)));
        assert_eq!(
            measure(&[0.0, 1.0], &[0.0, 1.0]),
            Err(NoRinging::TooShort(2))
        );
        let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.01).collect();
        assert_eq!(measure(&t, &[0.05; 20]), Err(NoRinging::Flat));
        assert_eq!(measure(&t, &[0.0; 20]), Err(NoRinging::Flat));
        let mut z: Vec<f64> = t.iter().map(|x| x.sin()).collect();
        z[3] = f64::NAN;
        assert_eq!(measure(&t, &z), Err(NoRinging::BadData));
        let back: Vec<f64> = t.iter().rev().copied().collect();
        assert_eq!(measure(&back, &[1.0; 20]), Err(NoRinging::BadData));
        // Noise alone, a line and a step fit something or nothing, but never panic.
        let mut g = Gaussian::new(1);
        let noise: Vec<f64> = t.iter().map(|_| g.sample()).collect();
        let _ = measure(&t, &noise);
        let line: Vec<f64> = t.clone();
        let _ = measure(&t, &line);
        let step: Vec<f64> = t.iter().map(|x| if *x < 0.1 { 0.0 } else { 1.0 }).collect();
        let _ = measure(&t, &step);
        let tiny: Vec<f64> = t.iter().map(|x| 1e-300 * x.sin()).collect();
        let _ = measure(&t, &tiny);
    }
}
