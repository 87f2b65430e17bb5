//! How far the model's own discretisation moves what a recording sees,
//! against the recording's noise (`softgrip diagnose` reports it).
//!
//! The fitted model is replayed once more on a finer mesh (edges [`FINER`]
//! times the scene's) and, for a time series, once at half the time step.
//! The RMS move of the observed coordinates over the noise level says how
//! large a mismatch the discretisation alone can make: near the noise or
//! above, a residual of that size may be the mesh's or the step's rather
//! than missing physics. Why, and what it measures on the proof's cuboid:
//! `docs/design/diagnosis.md`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::compare::{Residual, per_marker};
use crate::diagnose::noise::{Noise, weighted_residuals};
use crate::recording::{Mode, Recording};
use crate::replay::{Replay, ReplayOptions, replay};
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::{Scene, Shape};

/// The finer mesh's edge length, as a fraction of the scene's (5 mm to
/// 4 mm: about twice the nodes, so about twice a replay's time).
pub const FINER: f64 = 0.8;

/// One comparison: the fitted model against itself refined.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// The scene's edge length or time step, and the refined one.
    pub coarse: f64,
    /// The refined edge length (m) or time step (s).
    pub fine: f64,
    /// RMS move of the observed coordinates, fingers included (m).
    pub rms_m: f64,
    /// The same, each coordinate over its noise level, on the classes
    /// (object markers, fingers) that showed noise (0 when the recording
    /// showed none: `noise_measured`).
    pub over_noise: f64,
    /// Whether the recording had noise to measure the move against (a
    /// noise-free one has not: [`Noise::measured`]).
    pub noise_measured: bool,
    /// The marker that moves most, and its RMS distance over the observed
    /// axes (m).
    pub worst: (String, f64),
    /// Each residual's move (refined minus the scene's simulated position, m), in the order of
    /// the scene's replay: where the discretisation's error sits, marker by marker.
    pub moved: Vec<glam::DVec3>,
}

/// A check made, or why not.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The check was made.
    Measured(Check),
    /// Why the check was not made.
    Skipped(String),
}

impl Outcome {
    /// The check, where it was made.
    pub fn measured(&self) -> Option<&Check> {
        match self {
            Outcome::Measured(c) => Some(c),
            Outcome::Skipped(_) => None,
        }
    }
}

/// Both checks.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretisation {
    /// The mesh refined: edge length times [`FINER`].
    pub mesh: Outcome,
    /// The time step halved.
    pub time_step: Outcome,
}

impl Discretisation {
    /// The larger of the two moves over the noise (0 if neither was
    /// measured).
    pub fn over_noise(&self) -> f64 {
        [&self.mesh, &self.time_step]
            .iter()
            .filter_map(|o| o.measured())
            .filter(|c| c.noise_measured)
            .map(|c| c.over_noise)
            .fold(0.0, f64::max)
    }

    /// In words, for the CLI and the report.
    pub fn describe(&self) -> String {
        let one = |what: &str, o: &Outcome, unit: &str| match o {
            Outcome::Measured(c) if !c.noise_measured => format!(
                "{what} ({} {unit} instead of {} {unit}) moves the markers by {:.3} mm RMS (most: {} by {:.3} mm); the recording shows no noise to weigh that against",
                short(c.fine * 1e3),
                short(c.coarse * 1e3),
                c.rms_m * 1e3,
                c.worst.0,
                c.worst.1 * 1e3
            ),
            Outcome::Measured(c) => format!(
                "{what} ({} {unit} instead of {} {unit}) moves the markers by {:.3} mm RMS, {:.1} times the noise (most: {} by {:.3} mm)",
                short(c.fine * 1e3),
                short(c.coarse * 1e3),
                c.rms_m * 1e3,
                c.over_noise,
                c.worst.0,
                c.worst.1 * 1e3
            ),
            Outcome::Skipped(why) => format!("{what}: not checked ({why})"),
        };
        format!(
            "{}; {}",
            one("a finer mesh", &self.mesh, "mm"),
            one(
                "half the time step and a quarter of the step control's error",
                &self.time_step,
                "ms"
            )
        )
    }

    /// The evidence's sentence when the discretisation is at the noise's
    /// level or above, else None.
    pub fn caution(&self) -> Option<String> {
        let r = self.over_noise();
        let moves: Vec<String> = [
            ("a finer mesh", &self.mesh),
            ("half the step", &self.time_step),
        ]
        .iter()
        .filter_map(|(what, o)| {
            o.measured()
                .map(|c| format!("{what} {:.3} mm RMS", c.rms_m * 1e3))
        })
        .collect();
        (r >= 1.0).then(|| {
            format!(
                "The model's own discretisation moves the markers by up to {r:.1} times the noise ({}): a mismatch of that size may be the mesh's or the step's rather than missing physics; a finer `edge_length` or `dt` in the scene narrows it, at the cost of time.",
                moves.join(", ")
            )
        })
    }

    /// Both checks as JSON (SI units).
    pub fn to_json(&self) -> serde_json::Value {
        // Numbers and strings only: nothing here fails to serialize.
        serde_json::to_value(self.figures()).unwrap_or(serde_json::Value::Null)
    }

    /// Both checks as the JSON outputs give them (SI units).
    pub fn figures(&self) -> DiscretisationFigures {
        let one = |o: &Outcome| match o {
            Outcome::Measured(c) => OutcomeFigures::Measured(MeasuredFigures {
                coarse: c.coarse,
                fine: c.fine,
                rms_m: c.rms_m,
                over_noise: c.noise_measured.then_some(c.over_noise),
                worst_marker: c.worst.0.clone(),
                worst_m: c.worst.1,
            }),
            Outcome::Skipped(why) => OutcomeFigures::Skipped(SkippedFigures {
                skipped: why.clone(),
            }),
        };
        DiscretisationFigures {
            mesh: one(&self.mesh),
            time_step: one(&self.time_step),
        }
    }
}

/// Both discretisation checks, as `compare --discretisation --json` and `diagnose --json` give
/// them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiscretisationFigures {
    /// The mesh refined: edge length times 0.8.
    pub mesh: OutcomeFigures,
    /// The time step halved (skipped for a quasi-static recording).
    pub time_step: OutcomeFigures,
}

/// One check in the JSON outputs: made, or why not.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum OutcomeFigures {
    /// The check was made.
    Measured(MeasuredFigures),
    /// Why it was not.
    Skipped(SkippedFigures),
}

/// A check made: the fitted model against itself refined.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeasuredFigures {
    /// The scene's edge length (m) or time step (s).
    pub coarse: f64,
    /// The refined edge length (m) or time step (s).
    pub fine: f64,
    /// RMS move of the observed coordinates, fingers included, m.
    pub rms_m: f64,
    /// The move over the noise level, dimensionless; null where the recording showed no noise.
    pub over_noise: Option<f64>,
    /// The marker that moves most.
    pub worst_marker: String,
    /// That marker's RMS move over the observed axes, m.
    pub worst_m: f64,
}

/// A check not made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SkippedFigures {
    /// Why the check was not made, in words.
    pub skipped: String,
}

/// `v` with no trailing zeros: 4, 4.5, 0.25.
fn short(v: f64) -> String {
    let t = format!("{v:.3}");
    t.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Replays `scene` (the fitted model, whose replay of `recording` is
/// `coarse`) on a finer mesh and, for a time series, at half the step,
/// and measures the moves against `noise`. A refined replay that fails is
/// reported as skipped, with its error: the check never stops a diagnosis.
///
/// The refined replays come to rest as `rest` says: as `coarse` did, so
/// that the tolerance is not taken for the mesh's move (the diagnosis's
/// `RestTolerance::for_fits`, `softgrip compare`'s default).
pub fn check(
    recording: &Recording,
    scene: &Scene,
    coarse: &Replay,
    noise: &Noise,
    rest: RestTolerance,
) -> Discretisation {
    let refined = |s: Scene, finer_steps: bool| {
        let mut options = ReplayOptions {
            rest,
            ..ReplayOptions::default()
        };
        // Error-controlled steps are refined as the shortest step is: a quarter of the local
        // error (implicit Euler's is O(h^2)) with half the step.
        if let (true, Some(a)) = (finer_steps, options.adaptive.as_mut()) {
            a.tolerance /= 4.0;
        }
        replay(recording, &s, options, |_| {})
    };
    let measure = |s: Scene, from: f64, to: f64, finer_steps: bool| match refined(s, finer_steps) {
        Ok(fine) => match moves(recording, &coarse.residuals, &fine.residuals, noise) {
            Some((rms_m, over_noise, worst)) => Outcome::Measured(Check {
                coarse: from,
                fine: to,
                rms_m,
                over_noise: if noise.measured() { over_noise } else { 0.0 },
                noise_measured: noise.measured(),
                worst,
                moved: coarse
                    .residuals
                    .iter()
                    .zip(&fine.residuals)
                    .map(|(c, f)| f.simulated - c.simulated)
                    .collect(),
            }),
            None => Outcome::Skipped("the refined model sees other markers".into()),
        },
        Err(e) => Outcome::Skipped(format!("the refined model does not run: {e}")),
    };
    let mesh = match scene.object.shape {
        Shape::Mesh { .. } => {
            Outcome::Skipped("the object is a mesh file, which softgrip does not refine".into())
        }
        _ => {
            let mut s = scene.clone();
            let edge = s.object.edge_length;
            s.object.edge_length = edge * FINER;
            measure(s, edge, edge * FINER, false)
        }
    };
    let time_step = match recording.mode {
        Mode::QuasiStatic => {
            Outcome::Skipped("quasi-static: rest states do not depend on the step".into())
        }
        Mode::TimeSeries => {
            let mut s = scene.clone();
            let dt = s.simulation.dt;
            s.simulation.dt = dt / 2.0;
            measure(s, dt, dt / 2.0, true)
        }
    };
    Discretisation { mesh, time_step }
}

/// How far the markers of replay `b` are from those of replay `a`: the
/// RMS over the observed coordinates, fingers included (m); the same with
/// each coordinate over its noise, over the classes (object markers,
/// fingers) that showed noise ([`Noise::measured_on`]); and the marker that moves most, with
/// its RMS distance over the observed axes (m, `softgrip compare`'s
/// per-marker "rmse"). None when they are not the same observations.
///
/// It is `a`'s residual against `b`'s simulated positions taken as the
/// record, so the measures are the residuals' own (`Residual::distance`,
/// `compare::per_marker`, `diagnose::weighted_residuals`).
pub fn moves(
    recording: &Recording,
    a: &[Residual],
    b: &[Residual],
    noise: &Noise,
) -> Option<(f64, f64, (String, f64))> {
    if a.len() != b.len() || a.is_empty() {
        return None;
    }
    let mut between = Vec::with_capacity(a.len());
    for (ra, rb) in a.iter().zip(b) {
        if ra.sample != rb.sample || ra.marker != rb.marker {
            return None;
        }
        between.push(Residual {
            recorded: std::array::from_fn(|k| ra.recorded[k].map(|_| rb.simulated[k])),
            ..*ra
        });
    }
    let observed = between
        .iter()
        .flat_map(|r| r.recorded.iter().filter(|x| x.is_some()))
        .count();
    if observed == 0 {
        return None;
    }
    let n = observed as f64;
    let sum: f64 = between
        .iter()
        .map(|r| r.difference().length_squared())
        .sum();
    // Over the noise only where the class showed noise: a noise-free
    // class's move over the 1 um floor would say nothing.
    let noisy: Vec<Residual> = between
        .iter()
        .filter(|r| noise.measured_on(r.marker))
        .copied()
        .collect();
    let weighted = weighted_residuals(&noisy, noise);
    let over = if weighted.is_empty() {
        0.0
    } else {
        (weighted.iter().map(|w| w * w).sum::<f64>() / weighted.len() as f64).sqrt()
    };
    let worst = per_marker(&between)
        .into_iter()
        .max_by(|x, y| x.distance.total_cmp(&y.distance))
        .map(|m| (recording.marker_name(m.marker), m.distance))?;
    Some(((sum / n).sqrt(), over, worst))
}
