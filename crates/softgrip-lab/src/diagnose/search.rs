//! Explaining the residual by a greedy search of the catalogue: each round fits every candidate
//! that applies on top of the current model, scores it by BIC against that model, and tests it
//! against the best candidate of another effect by Vuong's test. The best is named when it
//! passes all three thresholds; two that tie are fitted together (`super::pairs`). Named effects
//! stay in and the rest are tried again, so two effects present at once are both found.

use super::catalogue::{Candidate, as_fitted, candidates, own_params, region};
use super::hypothesis::{Hypothesis, accepted};
use super::locate::Location;
use super::model_fit::{FitTask, ModelFit, Search, check_cancel, fit_model};
use super::noise::{Noise, weighted_residuals};
use super::options::{DiagnoseOptions, FitCount};
use super::pairs::{PairTest, fit_pair, judge_pair, tied_rival};
use super::regions::RegionScan;
use super::screen::{Screen, scanned, screen};
use super::shapes::place;
use super::statistics::{PROMISING, UNEXPLAINED_RATIO, effective_tests, vuong};
use crate::error::LabError;
use crate::recording::Recording;
use softgrip_core::scene::AaBox;

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
    /// Each round's score tests (`super::screen`), with the round.
    pub(super) screens: Vec<(usize, Screen)>,
}

impl Explanation {
    /// Nothing named: the model is `baseline`.
    fn nothing_beyond(baseline: &ModelFit) -> Explanation {
        Explanation {
            hypotheses: Vec::new(),
            effects: Vec::new(),
            current: baseline.clone(),
            unexplained: false,
            pair: None,
            screens: Vec::new(),
        }
    }

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
    let mut found = Explanation::nothing_beyond(baseline);
    if !location.significant {
        return Ok(found);
    }
    // Variants of an effect found are not tried again.
    let mut tried: Vec<&'static str> = Vec::new();
    for round in 0..options.max_effects {
        let candidates = next_candidates(recording, options, &found, &tried, round);
        if candidates.is_empty() {
            break;
        }
        let (round_candidates, scan_tests) = screened(
            recording,
            noise,
            options,
            &mut found,
            (candidates, round),
            fits,
        );
        if round_candidates.is_empty() {
            // Nothing could explain a share of it: as when the best fitted explains too little.
            found.unexplained = unexplained(location, &found.effects);
            break;
        }
        let start = found.hypotheses.len();
        let region_candidate = round_candidates
            .iter()
            .find(|c| c.effect == REGION)
            .cloned();
        fit_round(
            recording,
            noise,
            options,
            &mut found,
            (round_candidates, round, scan_tests),
            fits,
        )?;
        let Some(b) = best_of(&found.hypotheses, start) else {
            break;
        };
        if named_a_tie(
            recording,
            noise,
            options,
            location,
            &mut found,
            (start, b),
            fits,
        )? {
            break;
        }
        if !accepted(&found.hypotheses[b]) {
            found.unexplained = unexplained(location, &found.effects);
            break;
        }
        let halves_named = found.hypotheses[b].effect == REGION && scan_tests.is_none();
        let b = match region_candidate.filter(|_| halves_named) {
            Some(c) => place_named_region(recording, noise, options, &mut found, (b, c), fits)?,
            None => b,
        };
        let h = &found.hypotheses[b];
        found.effects.push(h.effect);
        if let Ok(f) = &h.fit {
            found.current = f.clone();
        }
        tried.push(h.effect);
    }
    Ok(found)
}

/// Fits round `round`'s `candidates` on the current model, adds their hypotheses to `found` and
/// tests each against the best of another effect; a region must also clear the scan's bar
/// (`scan_tests`, its count of independent places).
fn fit_round(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    found: &mut Explanation,
    (candidates, round, scan_tests): (Vec<Candidate>, usize, Option<f64>),
    fits: &mut FitCount,
) -> Result<(), LabError> {
    let start = found.hypotheses.len();
    let fitted = fit_candidates(
        recording,
        noise,
        options,
        &found.current,
        candidates,
        round,
        fits,
    )?;
    found.hypotheses.extend(fitted);
    compare_with_rivals(&mut found.hypotheses[start..], &found.current, noise);
    // A region chosen as the best of the scan's boxes must clear the scan's bar; the halves
    // are among its boxes.
    for h in &mut found.hypotheses[start..] {
        if let Some(t) = scan_tests.filter(|_| h.effect == REGION) {
            h.tests = h.tests.max(t);
        }
    }
    Ok(())
}

/// Where hypothesis `b`, the best of the round whose hypotheses begin at `start`, ties with a
/// rival of another effect: both fitted together and the pair judged ([`name_pair`]). Whether
/// they tied (and the search ends).
fn named_a_tie(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    location: &Location,
    found: &mut Explanation,
    (start, b): (usize, usize),
    fits: &mut FitCount,
) -> Result<bool, LabError> {
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
            found,
            (b, hf),
            (r, rf),
            fits,
        )?;
        return Ok(true);
    }
    Ok(false)
}

/// Round `round`'s `candidates` that the score tests keep (all of them where the tests cannot be
/// had or `options.screen` is off), the scan's region among them where it ran and is significant,
/// and the scan's count of independent places (`super::regions`). The tests are kept in `found`.
fn screened(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    found: &mut Explanation,
    (candidates, round): (Vec<Candidate>, usize),
    fits: &mut FitCount,
) -> (Vec<Candidate>, Option<f64>) {
    if !options.screen {
        return (candidates, None);
    }
    fits.starting("the score test of every candidate");
    let Some((mut screens, scan)) = screen(
        recording,
        noise,
        &found.current,
        &candidates,
        (options.workers, options.region_scan),
    ) else {
        return (candidates, None);
    };
    let mut kept: Vec<Candidate> = candidates
        .into_iter()
        .zip(&screens)
        .filter(|(_, s)| s.kept)
        .map(|(c, _)| c)
        .collect();
    let mut scan_tests = None;
    if let Some(scan) = scan {
        scan_tests = Some(scan.tests);
        let screened = scanned(&scan, found.current.scene.object.young_modulus);
        if screened.kept {
            fits.starting("placing the region of other stiffness");
            kept.extend(placed_region(
                recording,
                noise,
                options,
                &found.current,
                &scan,
            ));
        }
        screens.push(screened);
    }
    found
        .screens
        .extend(screens.into_iter().map(|s| (round, s)));
    (kept, scan_tests)
}

/// The effect a region's candidates are.
const REGION: &str = "heterogeneous-stiffness";

/// Where the four halves named a region (hypothesis `named` of `found`, its round's `candidate`
/// one of them), the place the data favour on the side the half chose: the scan of the object's
/// cells (`super::regions`) at the model without it, its shapes within the half or within the
/// other half ([`on_one_side`]) placed beyond first order (`super::shapes`) and the best fitted
/// as a candidate, kept where it fits closer than the half (the same parameters: a lower
/// BIC is a lower residual). The halves decide whether there is a region; the scan only where:
/// deciding by the scan's 48 shapes, a stiff top layer took strain stiffening's name
/// (`docs/design/diagnosis.md`). Returns the index of the hypothesis to name; a time series, or
/// a scan or fit that fails, keeps the half.
fn place_named_region(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    found: &mut Explanation,
    (named, candidate): (usize, Candidate),
    fits: &mut FitCount,
) -> Result<usize, LabError> {
    fits.starting("placing the region the halves named");
    let current = &found.current;
    let Some(half) = found.hypotheses[named]
        .fit
        .as_ref()
        .ok()
        .and_then(|f| f.scene.regions.last())
        .map(|r| r.region)
    else {
        return Ok(named);
    };
    let Some((_, Some(mut scan))) = screen(
        recording,
        noise,
        current,
        std::slice::from_ref(&candidate),
        (options.workers, true),
    ) else {
        return Ok(named);
    };
    scan.shapes.retain(|s| on_one_side(s.region, half));
    let Some(c) = placed_region(recording, noise, options, current, &scan) else {
        return Ok(named);
    };
    let round = found.hypotheses[named].round;
    let placed = fit_candidate(recording, noise, options, current, c, round)?;
    if placed.fit.is_err() || placed.score >= found.hypotheses[named].score {
        return Ok(named);
    }
    let start = found
        .hypotheses
        .iter()
        .position(|h| h.round == round)
        .unwrap_or(named);
    found.hypotheses.push(placed);
    compare_with_rivals(&mut found.hypotheses[start..], &found.current, noise);
    Ok(found.hypotheses.len() - 1)
}

/// `shape` lies within `half` or wholly outside it (within the other half): a place the half's
/// verdict allows, refined.
fn on_one_side(shape: AaBox, half: AaBox) -> bool {
    let tolerance = 1e-2 * (half.max - half.min).max_element();
    let inside = (shape.min - half.min).min_element() >= -tolerance
        && (half.max - shape.max).min_element() >= -tolerance;
    let overlap = shape.max.min(half.max) - shape.min.max(half.min);
    inside || overlap.min_element() <= tolerance
}

/// The region the scan found significant, placed by `super::shapes` and offered as a candidate
/// that starts where the shape's own fit ended.
fn placed_region(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    current: &ModelFit,
    scan: &RegionScan,
) -> Option<Candidate> {
    let placed = place(recording, noise, current, scan, options.workers)?;
    let mut c = region(&current.scene, &placed.variant, placed.region)?;
    c.scene.object.young_modulus = placed.moduli.0;
    if let Some(r) = c.scene.regions.last_mut() {
        r.young_modulus = placed.moduli.1;
    }
    as_fitted(c, options)
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
/// A round's candidates fitted, in their order. With several workers, as many candidates at
/// once, each fit on one (a fit's own batches of replays leave a second core idle between
/// them); the fits are the same either way (each fit's replays do not depend on how many run
/// beside them). Each candidate's stage is reported as it ends.
fn fit_candidates(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    current: &ModelFit,
    candidates: Vec<Candidate>,
    round: usize,
    fits: &mut FitCount,
) -> Result<Vec<Hypothesis>, LabError> {
    let workers = if options.workers == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        options.workers
    };
    if workers < 2 || candidates.len() < 2 {
        return candidates
            .into_iter()
            .map(|c| {
                fits.starting(c.effect);
                fit_candidate(recording, noise, options, current, c, round)
                    .inspect(|_| fits.done += 1)
            })
            .collect();
    }
    let one = DiagnoseOptions {
        workers: 1,
        ..options.clone()
    };
    fits.starting(&format!(
        "{} candidates, {} at once",
        candidates.len(),
        workers.min(candidates.len())
    ));
    let shared = std::sync::Mutex::new(&mut *fits);
    let results = crate::sweep::parallel_map(
        &candidates,
        workers,
        |c| {
            let h = fit_candidate(recording, noise, &one, current, c.clone(), round);
            if let (Ok(h), Ok(mut fits)) = (&h, shared.lock()) {
                fits.finished(
                    &super::catalogue::effect_label(c.effect, &c.variant),
                    h.seconds,
                );
            }
            h
        },
        &|_| {},
    );
    results.into_iter().collect()
}

fn fit_candidate(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    current: &ModelFit,
    c: Candidate,
    round: usize,
) -> Result<Hypothesis, LabError> {
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
    let (score, explained) = match &fit {
        Ok(f) => (f.bic - current.bic, 1.0 - f.rss / current.rss),
        Err(_) => (f64::INFINITY, 0.0),
    };
    // A fit taken from a checkpoint counts the time it took the run that saved it.
    let seconds = fit
        .as_ref()
        .map_or(started.elapsed().as_secs_f64(), |f| f.seconds);
    Ok(Hypothesis {
        effect: c.effect,
        variant: c.variant,
        fit,
        score,
        explained,
        round,
        vuong: None,
        against_model: false,
        tests: 1.0,
        seconds,
    })
}

/// Each candidate of a round against the best-scoring fit of another
/// effect in it, by Vuong's test, and the independent tests its effect's
/// candidates count as.
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
    let effects: Vec<&str> = round.iter().map(|h| h.effect).collect();
    let scores: Vec<f64> = round.iter().map(|h| h.score).collect();
    let tested = rival_tests(&effects, &scores, &weighted, &without);
    for (h, (z, against_model, tests)) in round.iter_mut().zip(tested) {
        (h.vuong, h.against_model, h.tests) = (z, against_model, tests);
    }
}

/// For each candidate (its effect, BIC score and weighted residuals, None
/// when its fit failed): Vuong's z against the best-scoring fitted candidate
/// of another effect or, with none, against the model without it (`true`:
/// nested, as in the pair test, so that form error a lone candidate absorbs
/// is not named on BIC and the share alone); and the independent tests its
/// effect's candidates count as, from their statistics against that rival.
fn rival_tests(
    effects: &[&str],
    scores: &[f64],
    weighted: &[Option<Vec<f64>>],
    without: &[f64],
) -> Vec<(Option<f64>, bool, f64)> {
    let n = effects.len();
    let against: Vec<(&[f64], bool)> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| effects[j] != effects[i])
                .filter_map(|j| weighted[j].as_deref().map(|w| (j, w)))
                .min_by(|a, b| scores[a.0].total_cmp(&scores[b.0]))
                .map_or((without, true), |(_, w)| (w, false))
        })
        .collect();
    // The per-observation statistic each z is the mean of.
    let statistic = |i: usize| -> Option<Vec<f64>> {
        let (this, other) = (weighted[i].as_deref()?, against[i].0);
        (other.len() == this.len())
            .then(|| other.iter().zip(this).map(|(b, a)| b * b - a * a).collect())
    };
    (0..n)
        .map(|i| {
            let Some(this) = weighted[i].as_deref() else {
                return (None, false, 1.0);
            };
            let family: Vec<Vec<f64>> = (0..n)
                .filter(|&j| effects[j] == effects[i])
                .filter_map(statistic)
                .collect();
            let (other, against_model) = against[i];
            (
                vuong(this, other),
                against_model,
                effective_tests(&family).max(1.0),
            )
        })
        .collect()
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
    fits: &mut FitCount,
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

#[cfg(test)]
mod tests {
    use super::super::statistics::vuong_threshold;
    use super::*;

    /// The scan's shapes a named half allows: within it (a quarter, an octant, a layer of it) or
    /// within the other half; a shape across the two (the middle layer for a bottom half) is
    /// another reading of the data, not the half's place refined.
    #[test]
    fn a_half_allows_the_shapes_within_it_or_within_the_other_half() {
        let b = |min: [f64; 3], max: [f64; 3]| AaBox {
            min: min.into(),
            max: max.into(),
        };
        let bottom = b([-25.0, -25.0, 0.0], [25.0, 25.0, 10.0]);
        let right_bottom_quarter = b([0.0, -25.0, 0.0], [25.0, 25.0, 10.0]);
        let top_layer = b([-25.0, -25.0, 15.0], [25.0, 25.0, 20.0]);
        let middle_layer = b([-25.0, -25.0, 5.0], [25.0, 25.0, 15.0]);
        let left_half = b([-25.0, -25.0, 0.0], [0.0, 25.0, 20.0]);
        assert!(on_one_side(bottom, bottom));
        assert!(on_one_side(right_bottom_quarter, bottom));
        assert!(on_one_side(top_layer, bottom));
        assert!(!on_one_side(middle_layer, bottom));
        assert!(!on_one_side(left_half, bottom));
    }

    /// A pseudo-random sequence in [-1, 1): the tests' residuals.
    fn wiggle(seed: u64, n: usize) -> Vec<f64> {
        let mut x = seed.wrapping_mul(6_364_136_223_846_793_005) | 1;
        (0..n)
            .map(|_| {
                x = x
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            })
            .collect()
    }

    /// Two forms of one effect that leave nearly the same residual count as about one test and
    /// face a threshold near 2; four places that leave unrelated residuals count as about four
    /// (Bonferroni's 2.53); the z is Vuong's against the best other effect, or against the model
    /// without it when the round has no other effect.
    #[test]
    fn forms_alike_count_as_one_test_places_apart_as_many() {
        let n = 400;
        let base = wiggle(1, n);
        let near = |k: u64| -> Vec<f64> {
            base.iter()
                .zip(wiggle(k, n))
                .map(|(b, w)| 0.8 * b + 0.02 * w)
                .collect()
        };
        let rival: Vec<f64> = base
            .iter()
            .zip(wiggle(9, n))
            .map(|(b, w)| b + 0.3 * w)
            .collect();
        let weighted = vec![Some(near(2)), Some(near(3)), Some(rival.clone())];
        let out = rival_tests(
            &["stiffening", "stiffening", "friction"],
            &[-40.0, -35.0, -5.0],
            &weighted,
            &base,
        );
        let (z, against_model, tests) = out[0];
        assert_eq!(z, vuong(weighted[0].as_deref().unwrap(), &rival));
        assert!(!against_model);
        assert!((1.0..1.1).contains(&tests), "{tests}");
        assert!(vuong_threshold(tests) < 2.1);
        // The rival alone in its effect: one test, against the best stiffening form.
        assert_eq!(out[2].2, 1.0);
        assert_eq!(out[2].0, vuong(&rival, weighted[0].as_deref().unwrap()));

        // Four halves, each off the baseline in its own way.
        let halves: Vec<Option<Vec<f64>>> = (0..4)
            .map(|k| {
                Some(
                    base.iter()
                        .zip(wiggle(20 + k, n))
                        .map(|(b, w)| 0.5 * b + 0.5 * w)
                        .collect(),
                )
            })
            .collect();
        let mut weighted = halves.clone();
        weighted.push(Some(rival.clone()));
        let effects = ["region", "region", "region", "region", "friction"];
        let out = rival_tests(
            &effects,
            &[-30.0, -20.0, -10.0, -5.0, -1.0],
            &weighted,
            &base,
        );
        assert!(
            out[..4].iter().all(|t| (3.0..=4.0).contains(&t.2)),
            "{out:?}"
        );

        // A failed fit has no z and does not count; alone in the round, a candidate is tested
        // against the model without it.
        let out = rival_tests(
            &["region", "region"],
            &[-30.0, f64::INFINITY],
            &[halves[0].clone(), None],
            &base,
        );
        assert_eq!(out[1], (None, false, 1.0));
        assert!(out[0].1);
        assert_eq!(out[0].0, vuong(halves[0].as_deref().unwrap(), &base));
        assert_eq!(out[0].2, 1.0);
    }
}
