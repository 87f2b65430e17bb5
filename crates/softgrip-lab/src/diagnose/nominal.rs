//! Before the diagnosis: whether the scene's own model carries the recorded loads. A lattice
//! without the bulk term its E and nu imply can have no equilibrium under a lab's weights; that
//! is a finding about the model, reported as such, and the diagnosis goes on with the term.

use softgrip_core::error::SimError;
use softgrip_core::quasi_static::RestTolerance;

use crate::error::LabError;
use crate::recording::{Mode, Recording};
use crate::replay::{ReplayOptions, replay};

/// `(None, None)` when the scene carries every recorded load; otherwise the recording with the
/// bulk term its material implies and the finding in words. An error when even that model
/// cannot carry them.
pub fn carries_the_loads(
    recording: &Recording,
) -> Result<(Option<Recording>, Option<String>), LabError> {
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    if recording.mode != Mode::QuasiStatic {
        return Ok((None, None));
    }
    let failure: LabError = match replay(recording, &recording.scene, options, |_| {}) {
        Ok(_) => return Ok((None, None)),
        Err(e @ SimError::NoEquilibrium { .. }) => e.into(),
        Err(e) => return Err(e.into()),
    };
    let repairs = repairs(recording);
    let LabError::Sim(e) = &failure else {
        unreachable!("made above")
    };
    let SimError::NoEquilibrium { load, near, .. } = &**e else {
        unreachable!("matched above")
    };
    if let Some((with, finding)) = repaired(recording, &repairs, options, *load, near)? {
        return Ok((Some(with), Some(finding)));
    }
    if let Some((before, finding)) = truncated(recording, options, *load, near) {
        return Ok((Some(before), Some(finding)));
    }
    Err(failure)
}

/// One repair of the scene's model: the parameter, its value, and the repair in words.
type Repair = (&'static str, f64, String);

/// What the scene leaves out that would let the model carry the loads: the bulk term its E
/// and nu imply, then the spring limits as forces (the projection alone lets a lattice
/// creep into collapse).
fn repairs(recording: &Recording) -> Vec<Repair> {
    let (object, model) = (&recording.scene.object, &recording.scene.model);
    let bulk = implied_bulk_modulus(object.young_modulus, object.poisson_ratio);
    let mut repairs: Vec<Repair> = Vec::new();
    if model.bulk_modulus == 0.0 && object.poisson_ratio > 0.0 {
        repairs.push((
            "bulk_modulus",
            bulk,
            format!(
                "the bulk term E and nu imply ([model] bulk_modulus = E / (3 (1 - 2 nu)) = \
                 {bulk:.4e} Pa; the lattice without it ignores the scene's poisson_ratio = {})",
                object.poisson_ratio
            ),
        ));
    }
    if model.limit_stiffness == 0.0 && (model.tau_s.is_some() || model.tau_c.is_some()) {
        let k = softgrip_core::scene::DEFAULT_LIMIT_STIFFNESS;
        repairs.push((
            "limit_stiffness",
            k,
            format!("spring limits that act as forces ([model] limit_stiffness = {k})"),
        ));
    }
    repairs
}

/// The recording with the fewest `repairs` that carry every load (the first alone, then the
/// first two), and the finding in words; `None` when none does. The model failed at `load`
/// (N) `near` (m).
fn repaired(
    recording: &Recording,
    repairs: &[Repair],
    options: ReplayOptions,
    load: f64,
    near: &[f64; 3],
) -> Result<Option<(Recording, String)>, LabError> {
    for n in 1..=repairs.len() {
        let mut with = recording.clone();
        for (name, value, _) in &repairs[..n] {
            with.scene = crate::params::set(&with.scene, name, *value)?;
        }
        if replay(&with, &with.scene, options, |_| {}).is_err() {
            continue;
        }
        let given: Vec<&str> = repairs[..n].iter().map(|r| r.2.as_str()).collect();
        let finding = format!(
            "The scene's model has no equilibrium at {load:.2} N (near ({:.1}, {:.1}, {:.1}) mm): \
             a finding about the model, not physics the lab left out. With {} it carries every \
             recorded load, and the diagnosis below is of that model.",
            1e3 * near[0],
            1e3 * near[1],
            1e3 * near[2],
            given.join(" and "),
        );
        return Ok(Some((with, finding)));
    }
    Ok(None)
}

/// The recording cut before the sample where the model failed at `load` (N) `near` (m), and
/// the finding in words, where at least `MIN_SAMPLES` are left and the model carries them.
fn truncated(
    recording: &Recording,
    options: ReplayOptions,
    load: f64,
    near: &[f64; 3],
) -> Option<(Recording, String)> {
    // No repair carries it: the samples before the first load the model cannot carry are still
    // evidence, and a verdict on them beats none (a lab's last levels can lie past where the
    // model holds, as the Ecoflex compressions' 67 % strain does).
    // The sample being reached when it failed: the first whose step from the one before passes
    // through the load it failed at (the solver halves a step before it gives up).
    let tol = 1e-6 * load.abs().max(1.0);
    let first = (0..recording.samples.len()).find(|&i| {
        let from = if i == 0 {
            0.0
        } else {
            recording.samples[i - 1].load.abs()
        };
        let to = recording.samples[i].load.abs();
        (from.min(to) - tol..=from.max(to) + tol).contains(&load.abs())
    });
    let k = first.filter(|&k| k >= MIN_SAMPLES)?;
    let mut before = recording.clone();
    before.samples.truncate(k);
    replay(&before, &before.scene, options, |_| {}).ok()?;
    let finding = format!(
        "The scene's model finds no equilibrium at {load:.2} N (sample {} of {}, near ({:.1}, {:.1}, {:.1}) mm); the diagnosis below is of the {k} samples before it.",
        k + 1,
        recording.samples.len(),
        1e3 * near[0],
        1e3 * near[1],
        1e3 * near[2],
    );
    Some((before, finding))
}

/// The fewest samples a diagnosis is run on when the model carries no more of a recording.
const MIN_SAMPLES: usize = 4;

/// The bulk modulus of an isotropic material, K = E / (3 (1 - 2 nu)), with nu held below 0.5
/// (where K is infinite) at 0.499.
pub fn implied_bulk_modulus(young_modulus: f64, poisson_ratio: f64) -> f64 {
    young_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio.min(0.499)))
}
