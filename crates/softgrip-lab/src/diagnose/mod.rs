//! Missing-physics diagnosis: when a fitted simulation and a recording still differ, find where,
//! name the physics the model left out, add it, fit it and show the fit improve; say "none" when
//! the residual is noise.
//!
//! [`diagnose`] runs the method's stages in order: the baseline fit (`baseline`, each fit by
//! `model_fit`), the noise from its residual (`noise`), where the residual stands out of the
//! noise (`locate`), the greedy search of the catalogue of candidate effects (`catalogue`,
//! `search`, ties fitted together by `pairs`, decided by `statistics` and `hypothesis`), and the
//! verdict with its evidence (`verdict`, `output`). The method and the reasons for its tests and
//! thresholds: `docs/design/diagnosis.md`.

mod baseline;
mod catalogue;
mod checkpoint;
pub mod figures;
mod hypothesis;
mod locate;
mod model_fit;
pub(crate) mod noise;
mod nominal;
mod options;
mod output;
mod pairs;
mod regions;
mod remainder;
mod screen;
mod search;
mod shapes;
mod statistics;
mod uncertainty;
mod verdict;

pub use baseline::{baseline_params, pinned_at_bounds};
pub use catalogue::{Candidate, EFFECTS, catalogue, effect_label};
pub use checkpoint::{Checkpoint, build_of};
pub use hypothesis::{Hypothesis, accepted};
pub use locate::{Location, locate};
pub use model_fit::{JACOBIAN_STEP, LOCAL_SEARCHES, ModelFit, same_model};
pub use noise::{
    NOISE_FLOOR_M, Noise, estimate_noise, estimate_noise_split, rms_beyond_noise,
    weighted_residuals, weighted_rss,
};
pub use nominal::{carries_the_loads, implied_bulk_modulus};
pub use options::{BaselineModel, DiagnoseOptions, FITTED, Progress, check_bounds, parse_bound};
pub use output::{diagnosis_figures, to_json};
pub use pairs::{LoneTest, PairNeed, PairTest, pair_verdict};
pub use regions::{CELLS, DRAWS, Grid, RegionScan, Shape};
pub use remainder::{
    FORM_ERROR_FACTOR, KeptShare, REMAINDER_LEVEL, Remainder, Test as RemainderTest,
    check as remainder, chi2_upper_tail,
};
pub use screen::{FRICTION_GRID, SCREEN_LEVEL, Screen};
pub use shapes::{FIRST_RATIO, Placed, SHAPES_FITTED, SHAPES_TRIED};
pub use statistics::{
    BIC_THRESHOLD, MIN_EXPLAINED, PROMISING, UNEXPLAINED_RATIO, VUONG_Z, bic, effective_tests,
    significant, vuong, vuong_by_sample, vuong_threshold,
};
pub use verdict::{Diagnosis, RegionFound};

use crate::discretisation::Discretisation;
use crate::error::LabError;
use crate::fit::FitParam;
use crate::recording::Recording;
use noise::load_turns;
use options::FitCount;
use softgrip_core::quasi_static::RestTolerance;

/// Refuses a recording too short to measure its noise: the noise is taken from second
/// differences along the samples within each run of loads moving one way, so some run needs
/// three samples. Without it every verdict would be measured against a noise level of nothing.
fn enough_samples(recording: &Recording) -> Result<(), LabError> {
    let n = recording.samples.len();
    let mut starts = vec![0];
    starts.extend(noise::load_turns(recording));
    starts.push(n);
    let differences: usize = starts
        .windows(2)
        .map(|w| w[1].saturating_sub(w[0]).saturating_sub(2))
        .sum();
    if n >= 3 && differences > 0 {
        return Ok(());
    }
    Err(LabError::Input(format!(
        "{}: {n} sample(s): the diagnosis measures the noise from second differences along the samples, so it needs at least 3 in a run of loads moving one way (or 3 times of a time series); record more, or compare the model with `softgrip compare` instead",
        recording.source.display()
    )))
}

/// Runs the diagnosis of `recording`: the baseline fit, the noise, where the residual stands
/// out of it, the search of the catalogue, the verdict with its evidence.
pub fn diagnose(
    recording: &Recording,
    options: &DiagnoseOptions,
    progress: Progress,
) -> Result<Diagnosis, LabError> {
    let remodelled = options.model.map(|m| Recording {
        scene: m.apply(&recording.scene),
        ..recording.clone()
    });
    let recording = remodelled.as_ref().unwrap_or(recording);
    enough_samples(recording)?;
    let (repaired, model_finding) = nominal::carries_the_loads(recording)?;
    let recording = repaired.as_ref().unwrap_or(recording);
    let base_params = baseline::search_params(&recording.scene, options)?;
    // The fits planned: the baseline's two, and each candidate once a round.
    let planned = 2 + catalogue(recording, &recording.scene).len() * options.max_effects;
    let mut fits = FitCount::new(planned, progress);
    let (first, noise, baseline) = fit_baseline(recording, options, &base_params, &mut fits)?;
    // Where the residual stands out of the noise.
    let location = locate(recording, &baseline.replay, &noise);
    // Reported, not acted on: a parameter at its bound is evidence of a form
    // error, and refitting it in every candidate adds freedom to each alike
    // (docs/results/diagnosis-history.md, "Variant: the baseline's pinned parameters refitted").
    let pinned = pinned_at_bounds(&baseline.params, &base_params);
    // The effects that explain it, by a greedy search of the catalogue.
    let mut found = search::explain(recording, &noise, options, &location, &baseline, &mut fits)?;
    // The verdict: what is left, how far the discretisation alone moves the
    // markers, and the evidence in words.
    let remaining = locate(recording, &found.current.replay, &noise);
    let (discretisation, remainder) = final_checks(recording, &noise, &baseline, &found, &mut fits);
    // The search's evidence as it stands, after the checks' finding when they failed.
    let mut evidence = verdict::evidence(&location, &found, &pinned, &baseline, &discretisation);
    let set_aside = set_aside_if_left(&remainder, &mut found, &mut evidence);
    if let Some(f) = &model_finding {
        evidence = after_finding(f, &evidence);
    }
    let simulations = first.evaluations + baseline.evaluations + found.simulations();
    let mut d = Diagnosis {
        baseline,
        noise,
        location,
        hypotheses: found.hypotheses,
        effects: found.effects,
        unexplained: found.unexplained,
        final_fit: found.current,
        standard_errors: Vec::new(),
        correlations: Vec::new(),
        remaining,
        evidence,
        pair: found.pair,
        simulations,
        bounds: options.bounds.clone(),
        pinned,
        discretisation,
        model_finding,
        stages: Vec::new(),
        screens: found.screens,
        remainder,
        set_aside,
    };
    let alternatives = alternatives_text(&d);
    // A sentence of its own ("NRMSE ... 0.0186. No other reading ...").
    if !alternatives.is_empty() && !d.evidence.trim_end().ends_with('.') {
        d.evidence.push('.');
    }
    d.evidence.push_str(&alternatives);
    finish(&mut d, recording, options, &mut fits);
    Ok(d)
}

/// The baseline, first weighing every coordinate alike; the noise from
/// its residual; the baseline again, weighed by the noise. The unweighted fit, the noise and
/// the weighted fit.
fn fit_baseline(
    recording: &Recording,
    options: &DiagnoseOptions,
    base_params: &[FitParam],
    fits: &mut FitCount<'_>,
) -> Result<(ModelFit, Noise, ModelFit), LabError> {
    fits.starting("baseline");
    let first = baseline::fit_unweighted(recording, options, base_params)?;
    let noise = estimate_noise_split(&first.replay.residuals, &load_turns(recording));
    fits.done = 1;
    fits.starting("baseline, weighted by the noise");
    let baseline = baseline::refit_weighted(recording, &noise, options, base_params, &first)?;
    fits.done = 2;
    Ok((first, noise, baseline))
}

/// The final model on a finer mesh and step, and what it leaves beyond the noise.
fn final_checks(
    recording: &Recording,
    noise: &Noise,
    baseline: &ModelFit,
    found: &search::Explanation,
    fits: &mut FitCount<'_>,
) -> (Discretisation, Remainder) {
    // On the final model: the baseline's may not show it (a rate-dependent
    // effect makes the found model step-sensitive where the baseline is not).
    fits.done = fits.done.min(fits.planned);
    fits.starting("the final model on a finer mesh and step");
    let discretisation = crate::discretisation::check(
        recording,
        &found.current.scene,
        &found.current.replay,
        noise,
        RestTolerance::for_fits(),
    );
    // What the final model leaves: a reading that leaves hysteresis, a lone marker or a kept
    // share it does not beat is set aside, and the verdict is "unexplained" there.
    let remainder = remainder::of_final(
        recording,
        noise,
        (baseline, &found.current),
        discretisation.mesh.measured().map(|c| c.moved.as_slice()),
        !found.effects.is_empty(),
    );
    (discretisation, remainder)
}

/// The last stages: the final model's standard errors (where an effect is named), and the
/// stages' times.
fn finish(
    d: &mut Diagnosis,
    recording: &Recording,
    options: &DiagnoseOptions,
    fits: &mut FitCount<'_>,
) {
    fits.starting("the final model's standard errors");
    if !d.effects.is_empty() {
        (d.standard_errors, d.correlations) =
            uncertainty::standard_errors(recording, &d.noise, &d.final_fit, options.workers);
    }
    fits.done = fits.planned;
    fits.starting("done");
    d.stages = std::mem::take(&mut fits.stages);
}

/// When the remainder's checks fail, the search's effects (returned) are set aside, the verdict
/// turned "unexplained" and `evidence` opened with what is left.
fn set_aside_if_left(
    remainder: &Remainder,
    found: &mut search::Explanation,
    evidence: &mut String,
) -> Vec<&'static str> {
    let set_aside = if remainder.fails() {
        found.unexplained = true;
        std::mem::take(&mut found.effects)
    } else {
        Vec::new()
    };
    if let Some(text) = remainder.describe() {
        *evidence = verdict::remainder_text(&text, &set_aside, &found.hypotheses) + evidence;
    }
    set_aside
}

/// The evidence after the model's finding: its first letter raised.
fn after_finding(finding: &str, evidence: &str) -> String {
    let mut rest = evidence.chars();
    let first = rest
        .next()
        .map(|c| c.to_uppercase().to_string())
        .unwrap_or_default();
    format!("{finding} {first}{}", rest.as_str())
}

/// The evidence's last sentence: the readings that fit about as well, or, with an effect
/// named, that none does (said, not left to silence: a reader cannot tell "none" from "not
/// checked").
fn alternatives_text(d: &Diagnosis) -> String {
    let alternatives: Vec<String> = d
        .alternatives()
        .iter()
        .map(|h| format!("{} (z {})", effect_label(h.effect, &h.variant), h.z_text()))
        .collect();
    if !alternatives.is_empty() {
        format!(
            " Readings that fit about as well (Vuong's test does not find them worse than the best, z above -{VUONG_Z}): {}.",
            alternatives.join(", ")
        )
    } else if !d.effects.is_empty() {
        format!(
            " No other reading fits about as well (none that passes BIC and the share is within Vuong's z of -{VUONG_Z} of the best)."
        )
    } else {
        String::new()
    }
}
