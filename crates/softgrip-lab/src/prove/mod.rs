//! The proof of the diagnosis on concealed data (`softgrip prove`): a
//! suite of recordings made by softgrip with settings the diagnosis does
//! not know (a finer mesh, other material values, 0.1 mm of noise, x and z
//! seen by a side camera, 8 markers and the finger as in the thesis's
//! experiment), each with one effect at two strengths, eight controls with
//! none (four on the sphere, two of them time series, and one on each other
//! experiment), three with physics softgrip has no model of, and one with two
//! (`suite`); every recording is diagnosed blind ([`run`]) and the outcome
//! written as a Markdown report ([`report()`]; the current one is
//! `docs/results/diagnosis.md`).

mod report;
mod suite;

pub use report::{Place, Recovery, place, recoveries, report};
pub use suite::{
    Case, DEVELOPMENT_SEED, E_ERROR, NOISE, QUASI_STATIC_DT, SCORED_SEEDS, UNEXPLAINED, case,
    cases, nominal, nominal_plate, seeded, synthesis, thesis_markers, with_truth_edge, write_case,
};

use std::path::{Path, PathBuf};

use crate::diagnose::{self, BaselineModel, DiagnoseOptions, Diagnosis};
use crate::error::LabError;
use crate::recording::Recording;
use crate::synth::{synthesize, synthesize_with_clean};
use softgrip_core::scene::Scene;

/// How `softgrip prove` is run: by default, as the suite stands.
#[derive(Debug, Clone, Copy, Default)]
pub struct ProveOptions {
    /// Tell the diagnosis E's measured range, this factor either way of
    /// the nominal E (`options_for`).
    pub e_measured_within: Option<f64>,
    /// Make the truths with this edge length instead of the suite's 2 mm:
    /// the diagnosis's own 4 mm takes the mesh's form error out of the
    /// proof (what the diagnosis does with no discretisation between it
    /// and the data); a finer one brings the data nearer a continuum, as a
    /// lab's are.
    pub truth_edge_length: Option<f64>,
    /// The commit the running binary was built from (the CLI's build script), for the report:
    /// which rules ran.
    pub commit: Option<&'static str>,
    /// With a build's name (`diagnose::Checkpoint::open`), each case's fits are saved in its
    /// directory (`fits-MODEL.checkpoint`) as they end, and a rerun of the proof resumes.
    pub checkpoint_build: Option<&'static str>,
}

/// One case's outcome.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The proof's seed the case was drawn under.
    pub seed: u64,
    /// The model the diagnosis started from.
    pub model: BaselineModel,
    /// The case diagnosed.
    pub case: Case,
    /// The diagnosis of the case's recording, or why it failed.
    pub diagnosis: Result<Diagnosis, LabError>,
    /// Its wall time, counting a fit taken from a checkpoint at the time it took the run that
    /// saved it: about what the verdict costs uninterrupted.
    pub seconds: f64,
    /// Fits taken from a checkpoint.
    pub resumed: usize,
    /// How far the hidden effect moves each marker (RMS over the samples,
    /// noise-free, m), most first; empty for a control.
    pub moved: Vec<(String, f64)>,
    /// NRMSE all of the baseline fit and of the final fit against the
    /// noise-free recording of the truth (see [`truth_errors`]).
    pub truth_errors: Option<[f64; 2]>,
    /// NRMSE all of the truth itself against the (noisy) recording: what
    /// the noise leaves for a model that is exactly the truth, so the
    /// lowest "after" any diagnosis can reach, but for the little a fit's
    /// few parameters take out of the noise itself (p of N observations:
    /// about 2 % of this here; see [`truth_error`]).
    pub noise_floor: Option<f64>,
}

impl Outcome {
    /// The effects named, or [`UNEXPLAINED`] where the verdict was "unexplained".
    pub fn named(&self) -> Vec<&'static str> {
        match &self.diagnosis {
            Ok(d) if d.effects.is_empty() && d.unexplained => vec![UNEXPLAINED],
            Ok(d) => d.effects.clone(),
            Err(_) => Vec::new(),
        }
    }

    /// Right: every hidden effect named and nothing else ("none" for a control); for physics
    /// softgrip has no model of, "unexplained" with the marker it moves most among those
    /// located.
    pub fn right(&self) -> bool {
        let mut a = self.named();
        let mut b = self.case.effects.clone();
        a.sort_unstable();
        b.sort_unstable();
        let placed = b != [UNEXPLAINED] || self.located() == Some(true);
        self.diagnosis.is_ok() && a == b && placed
    }

    /// The markers the effect moves most: within half of the largest.
    pub fn moved_most(&self) -> Vec<&str> {
        let top = self.moved.first().map_or(0.0, |m| m.1);
        self.moved
            .iter()
            .filter(|m| m.1 >= 0.5 * top && top > 0.0)
            .map(|m| m.0.as_str())
            .collect()
    }

    /// The verdict's place is right: it names some markers (`Diagnosis::mismatch_markers`), and
    /// each is one the hidden effect moves by more than the noise (RMS over the samples): no
    /// wrong place. `None` for a control.
    pub fn located(&self) -> Option<bool> {
        if self.moved.is_empty() {
            return None;
        }
        let d = self.diagnosis.as_ref().ok()?;
        let named = d.mismatch_markers();
        Some(
            !named.is_empty()
                && named.iter().all(|m| {
                    self.moved
                        .iter()
                        .any(|(n, rms)| n == m && *rms > suite::NOISE)
                }),
        )
    }
}

/// The recording of `c`'s truth without noise (seed 1, noise 0), made in
/// `dir/noise-free`.
pub fn noise_free(c: &Case, dir: &Path) -> Result<Recording, LabError> {
    let clean = dir.join("noise-free");
    synthesize(&c.truth_scene, &synthesis(c, 1, 0.0), &clean)?;
    Ok(Recording::load(&clean.join("recording.toml"))?)
}

/// Writes case `c`'s recording into `dir` (as [`write_case`]) and its noise-free twin into
/// `dir/noise-free` from one simulation of the truth: (recording, noise-free).
pub fn write_case_with_clean(
    c: &Case,
    dir: &Path,
    seed: u64,
) -> Result<(Recording, Recording), LabError> {
    let (_, clean) = synthesize_with_clean(
        &c.truth_scene,
        &synthesis(c, seed, suite::NOISE),
        dir,
        &dir.join("noise-free"),
    )?;
    Ok((suite::with_nominal_scene(c, dir)?, clean))
}

/// NRMSE all of the noise-free recording `clean` against its noisy twin `noisy` (the same
/// samples): the truth itself against the recording, the noise's floor (see
/// [`Outcome::noise_floor`]), without simulating the truth again.
pub fn noise_floor(noisy: &Recording, clean: &Recording) -> Result<f64, LabError> {
    let extent = softgrip_core::Model::mesh_of(&clean.scene)
        .map_err(|e| LabError::Input(format!("the truth's mesh: {e}")))
        .map(|m| {
            let (lo, hi) = m.bounds();
            (hi - lo).max_element()
        })?;
    let residuals: Vec<crate::compare::Residual> = noisy
        .samples
        .iter()
        .zip(&clean.samples)
        .enumerate()
        .flat_map(|(sample, (n, c))| {
            n.observations
                .iter()
                .zip(&c.observations)
                .map(move |(o, t)| crate::compare::Residual {
                    sample,
                    marker: o.marker,
                    simulated: glam::DVec3::from_array(t.position.map(|v| v.unwrap_or(0.0))),
                    recorded: o.position,
                })
        })
        .collect();
    Ok(crate::compare::errors(&residuals, extent).nrmse_all)
}

/// How far `c`'s hidden effects move each marker: the noise-free
/// recording of the truth replayed on the truth without the effects.
pub fn moved_by_effect(c: &Case, dir: &Path) -> Result<Vec<(String, f64)>, LabError> {
    moved_in(c, &noise_free(c, dir)?)
}

/// [`moved_by_effect`] in the noise-free recording `clean` (empty for a
/// control).
fn moved_in(c: &Case, clean: &Recording) -> Result<Vec<(String, f64)>, LabError> {
    if c.effects.is_empty() {
        return Ok(Vec::new());
    }
    let r = crate::replay::replay(
        clean,
        &c.plain_scene,
        crate::replay::ReplayOptions::default(),
        |_| {},
    )?;
    let mut sums: std::collections::BTreeMap<String, (f64, usize)> = Default::default();
    for res in &r.residuals {
        let e = sums.entry(clean.marker_name(res.marker)).or_default();
        e.0 += res.difference().length_squared();
        e.1 += 1;
    }
    let mut out: Vec<(String, f64)> = sums
        .into_iter()
        .map(|(k, (s, n))| (k, (s / n.max(1) as f64).sqrt()))
        .collect();
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    Ok(out)
}

/// NRMSE all of `scene` replayed against the noise-free recording of the
/// truth: the model's own error, without the noise that an error against
/// the recording cannot fall below (0.1 mm on this 50 mm object is an
/// NRMSE all of about 0.003 for a perfect model). Only the proof can
/// measure it: it needs the truth. Given the noisy recording and the
/// truth's own scene, it measures that floor instead
/// ([`Outcome::noise_floor`]).
pub fn truth_error(scene: &Scene, clean: &Recording) -> Result<f64, LabError> {
    crate::replay::replay(
        clean,
        scene,
        crate::replay::ReplayOptions::default(),
        |_| {},
    )
    .map(|r| r.errors.nrmse_all)
    .map_err(LabError::from)
}

/// [`truth_error`] of the diagnosis's baseline fit and of its final fit.
pub fn truth_errors(d: &Diagnosis, clean: &Recording) -> Result<[f64; 2], LabError> {
    Ok([
        truth_error(&d.baseline.scene, clean)?,
        truth_error(&d.final_fit.scene, clean)?,
    ])
}

/// The diagnosis's options for `case`: `base`, and with `e_within` E's
/// measured range, that factor either way of the nominal E (as a
/// compression test's initial slope, the thesis's section V.B, tells it),
/// unless `base` already bounds E. `softgrip prove` gives no range unless
/// asked (`--e-measured-within`): on this suite, a range of 2 let the
/// diagnosis name strong stiffening and cost four cases a second effect
/// (docs/results/diagnosis-history.md, "Variant: E's measured range given").
pub fn options_for(case: &Case, base: &DiagnoseOptions, e_within: Option<f64>) -> DiagnoseOptions {
    let mut options = base.clone();
    if let Some(f) = e_within
        && !options.bounds.iter().any(|(n, _, _)| n == "young_modulus")
    {
        let e = case.nominal.object.young_modulus;
        options
            .bounds
            .push(("young_modulus".to_string(), e / f, e * f));
    }
    options
}

/// Runs the cases whose names contain `filter` (all for "") under the proof's `seed`, writing
/// the recordings under `dir/seed-SEED` and diagnosing each from every one of `models`;
/// `progress` gets (case index, cases, name), `done` the outcomes so far after each case (a
/// run of hours leaves its report as it goes).
#[allow(clippy::too_many_arguments)]
pub fn run(
    dir: &Path,
    seed: u64,
    filter: &str,
    models: &[BaselineModel],
    options: &DiagnoseOptions,
    prove: &ProveOptions,
    progress: &dyn Fn(usize, usize, &str),
    done: &mut dyn FnMut(&[Outcome], usize),
) -> Vec<Outcome> {
    let chosen = seeded(seed, filter);
    // Named as the report prints the seed.
    let dir = dir.join(format!("seed-{seed:016x}"));
    let total = chosen.len();
    let mut out = Vec::new();
    for (i, (noise_seed, case)) in chosen.into_iter().enumerate() {
        progress(i, total, &case.name);
        let case = match prove.truth_edge_length {
            Some(h) => with_truth_edge(case, h),
            None => case,
        };
        let case_dir: PathBuf = dir.join(&case.name);
        let written = write_case_with_clean(&case, &case_dir, noise_seed);
        // What only the proof can measure, against the truth: not timed.
        let clean = written.as_ref().ok().map(|(_, clean)| clean);
        let moved = clean
            .and_then(|r| moved_in(&case, r).ok())
            .unwrap_or_default();
        let noise_floor = written
            .as_ref()
            .ok()
            .and_then(|(rec, clean)| noise_floor(rec, clean).ok());
        for &model in models {
            let checkpoint = prove.checkpoint_build.map(|build| {
                let path = case_dir.join(format!("fits-{}.checkpoint", model.name()));
                diagnose::Checkpoint::open(&path, build)
            });
            let options = DiagnoseOptions {
                model: Some(model),
                checkpoint: checkpoint.clone().and_then(Result::ok),
                ..options_for(&case, options, prove.e_measured_within)
            };
            let started = std::time::Instant::now();
            let diagnosis = written.as_ref().map_err(Clone::clone).and_then(|(rec, _)| {
                // A checkpoint that cannot be used fails the case, named, not silently.
                checkpoint.transpose()?;
                diagnose::diagnose(rec, &options, &|_, _, _| {})
            });
            let (resumed, resumed_seconds) = options
                .checkpoint
                .as_ref()
                .map_or((0, 0.0), |c| (c.reused(), c.reused_seconds()));
            let seconds = started.elapsed().as_secs_f64() + resumed_seconds;
            let truth_errors = match (&diagnosis, clean) {
                (Ok(d), Some(r)) => truth_errors(d, r).ok(),
                _ => None,
            };
            out.push(Outcome {
                seed,
                model,
                case: case.clone(),
                diagnosis,
                seconds,
                resumed,
                moved: moved.clone(),
                truth_errors,
                noise_floor,
            });
        }
        done(&out, total);
    }
    out
}
