//! Explaining the residual by a greedy search of the catalogue: each round fits every candidate
//! that applies on top of the current model, scores it by BIC against that model, and tests it
//! against the best candidate of another effect by Vuong's test. The best is named when it
//! passes all three thresholds; two that tie are fitted together (`super::pairs`). Named effects
//! stay in and the rest are tried again, so two effects present at once are both found.

use super::catalogue::{Candidate, candidates, own_params};
use super::hypothesis::{Hypothesis, accepted};
use super::locate::Location;
use super::model_fit::{FitTask, ModelFit, Search, check_cancel, fit_model};
use super::noise::{Noise, weighted_residuals};
use super::options::{DiagnoseOptions, FitCount};
use super::pairs::{PairTest, fit_pair, judge_pair, tied_rival};
use super::statistics::{PROMISING, UNEXPLAINED_RATIO, vuong};
use crate::error::LabError;
use crate::recording::Recording;

/// What the search found.
pub(super) struct Explanation {
    /// Every candidate fitted, round by round.
    pub(super) hypotheses: Vec<Hypothesis>,
    /// The effects named, in order.
    pub(super) effects: Vec<&'static str>,
    /// The model with them: the baseline when none was named.
    pub(super) current: ModelFit,
    /// A significant mismatch well above the noise that no candidate
    /// explains.
    pub(super) unexplained: bool,
    /// The pair fitted when a round's best two effects tied, if they did.
    pub(super) pair: Option<PairTest>,
}

impl Explanation {
    /// Simulations its fits ran: every candidate's and the pair's.
    pub(super) fn simulations(&self) -> usize {
        self.hypotheses
            .iter()
            .filter_map(|h| h.fit.as_ref().ok())
            .map(|f| f.evaluations)
            .sum::<usize>()
            + self.pair.as_ref().map_or(0, |t| t.fit.evaluations)
    }
}

/// Explains the residual that `location` found after the `baseline` fit,
/// one effect a round, `options.max_effects` at most. Nothing is tried
/// when the residual is at the noise level.
pub(super) fn explain(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    location: &Location,
    baseline: &ModelFit,
    fits: &mut FitCount,
) -> Result<Explanation, LabError> {
    let mut found = Explanation {
        hypotheses: Vec::new(),
        effects: Vec::new(),
        current: baseline.clone(),
        unexplained: false,
        pair: None,
    };
    if !location.significant {
        return Ok(found);
    }
    // Variants of an effect found are not tried again.
    let mut tried: Vec<&'static str> = Vec::new();
    for round in 0..options.max_effects {
        let round_candidates = next_candidates(recording, options, &found, &tried, round);
        if round_candidates.is_empty() {
            break;
        }
        let start = found.hypotheses.len();
        for c in round_candidates {
            let h = fit_candidate(recording, noise, options, &found.current, c, round, fits)?;
            found.hypotheses.push(h);
        }
        let round_fits = &mut found.hypotheses[start..];
        let effects: Vec<&'static str> = round_fits.iter().map(|h| h.effect).collect();
        for h in round_fits.iter_mut() {
            h.variants = effects.iter().filter(|e| **e == h.effect).count();
        }
        compare_with_rivals(&mut found.hypotheses[start..], &found.current, noise);
        let Some(b) = best_of(&found.hypotheses, start) else {
            break;
        };
        if let Some(r) = tied_rival(&found.hypotheses, start, b)
            && let (Ok(hf), Ok(rf)) = (
                found.hypotheses[b].fit.clone(),
                found.hypotheses[r].fit.clone(),
            )
        {
            name_pair(
                recording,
                noise,
                options,
                location,
                &mut found,
                (b, hf),
                (r, rf),
                fits,
            )?;
            break;
        }
        let h = &found.hypotheses[b];
        if accepted(h) {
            found.effects.push(h.effect);
            if let Ok(f) = &h.fit {
                found.current = f.clone();
            }
            tried.push(h.effect);
        } else {
            found.unexplained = unexplained(location, &found.effects);
            break;
        }
    }
    Ok(found)
}

/// Round `round`'s candidates: the effects not yet named and, after the
/// first round, only those that explained something (PROMISING) on their
/// own in it: an effect that changed nothing then will not change anything
/// next to another.
fn next_candidates(
    recording: &Recording,
    options: &DiagnoseOptions,
    found: &Explanation,
    tried: &[&'static str],
    round: usize,
) -> Vec<Candidate> {
    let promising = |c: &Candidate| {
        round == 0
            || found.hypotheses.iter().any(|h: &Hypothesis| {
                h.round == 0
                    && h.effect == c.effect
                    && h.variant == c.variant
                    && h.explained >= PROMISING
            })
    };
    candidates(recording, &found.current.scene, options)
        .into_iter()
        .filter(|c| !found.effects.contains(&c.effect) && !tried.contains(&c.effect))
        .filter(promising)
        .collect()
}

/// Candidate `c` fitted on top of `current`, scored against it.
fn fit_candidate(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    current: &ModelFit,
    c: Candidate,
    round: usize,
    fits: &mut FitCount,
) -> Result<Hypothesis, LabError> {
    fits.starting(c.effect);
    let started = std::time::Instant::now();
    let k = current.k + own_params(&c.params); // the modulus is refitted, not added
    let budget = options.candidate_evaluations_per_param * c.params.len();
    let fit = fit_model(
        recording,
        noise,
        options,
        FitTask {
            scene: &c.scene,
            params: &c.params,
            k_total: k,
            search: Search::Contender,
            budget,
            starts: &[],
            floor: c.off.as_deref(),
            known: Some(current),
        },
    );
    // A cancelled fit is the diagnosis's end, not a candidate that failed.
    check_cancel()?;
    fits.done += 1;
    let (score, explained) = match &fit {
        Ok(f) => (f.bic - current.bic, 1.0 - f.rss / current.rss),
        Err(_) => (f64::INFINITY, 0.0),
    };
    Ok(Hypothesis {
        effect: c.effect,
        variant: c.variant,
        fit,
        score,
        explained,
        round,
        vuong: None,
        against_model: false,
        variants: 1,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Each candidate of a round against the best-scoring fit of another
/// effect in it, by Vuong's test.
fn compare_with_rivals(round: &mut [Hypothesis], current: &ModelFit, noise: &Noise) {
    let without = weighted_residuals(&current.replay.residuals, noise);
    let weighted: Vec<Option<Vec<f64>>> = round
        .iter()
        .map(|h| {
            h.fit
                .as_ref()
                .ok()
                .map(|f| weighted_residuals(&f.replay.residuals, noise))
        })
        .collect();
    for i in 0..weighted.len() {
        let rival = (0..weighted.len())
            .filter(|&j| round[j].effect != round[i].effect)
            .filter(|&j| weighted[j].is_some())
            .min_by(|&a, &b| round[a].score.total_cmp(&round[b].score));
        let h = &mut round[i];
        (h.vuong, h.against_model) = match (&weighted[i], rival.map(|j| &weighted[j])) {
            (Some(this), Some(Some(other))) => (vuong(this, other), false),
            // No other effect fitted this round: the same test against the
            // model it was added to (nested, as in the pair test), so that
            // form error a lone candidate absorbs is not named on BIC and the
            // share alone.
            (Some(this), None) => (vuong(this, &without), true),
            _ => (None, false),
        };
    }
}

/// The best-scoring candidate from index `start` on (the first of equals).
fn best_of(hypotheses: &[Hypothesis], start: usize) -> Option<usize> {
    let mut best: Option<usize> = None;
    for (i, h) in hypotheses.iter().enumerate().skip(start) {
        if best.is_none_or(|b| h.score < hypotheses[b].score) {
            best = Some(i);
        }
    }
    best
}

/// Fits the round's best candidate `b` and its tied rival `r` together
/// (`hf` and `rf` their fits) and names the effects the pair needs.
fn name_pair(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    location: &Location,
    found: &mut Explanation,
    (b, hf): (usize, ModelFit),
    (r, rf): (usize, ModelFit),
    fits: &FitCount,
) -> Result<(), LabError> {
    let Some(mut test) = fit_pair(
        recording,
        noise,
        options,
        &found.current,
        (&found.hypotheses[b], &hf),
        (&found.hypotheses[r], &rf),
        fits,
    )?
    else {
        return Ok(());
    };
    let room = options.max_effects.saturating_sub(found.effects.len());
    let needed = judge_pair(&mut test, [&hf, &rf], &found.current, noise, room);
    let (he, re) = (test.effects[0].0, test.effects[1].0);
    match needed {
        (true, true) => {
            found.effects.extend([he, re]);
            found.current = test.fit.clone();
        }
        (true, false) => {
            found.effects.push(he);
            found.current = hf;
        }
        (false, true) => {
            found.effects.push(re);
            found.current = rf;
        }
        (false, false) => found.unexplained = unexplained(location, &found.effects),
    }
    found.pair = Some(test);
    Ok(())
}

/// "unexplained" rather than "none": no effect named, and the baseline's
/// residual more than UNEXPLAINED_RATIO times the noise.
fn unexplained(location: &Location, effects: &[&'static str]) -> bool {
    effects.is_empty() && location.over_noise() > UNEXPLAINED_RATIO
}
