//! Two effects that both pass BIC and the share of the residual but cannot be told apart by
//! Vuong's test are either two effects at once or one form error seen by both: fitted together,
//! each is named when the pair still needs it (a nested comparison: the pair against the other
//! alone), with the thresholds one effect faces.

use super::catalogue::{candidates, effect_label, is_modulus, own_params};
use super::hypothesis::{Hypothesis, accepted};
use super::model_fit::{FitTask, ModelFit, Search, check_cancel, fit_model};
use super::noise::{Noise, weighted_residuals};
use super::options::{DiagnoseOptions, FitCount};
use super::statistics::{BIC_THRESHOLD, MIN_EXPLAINED, vuong, vuong_by_sample, vuong_threshold};
use crate::error::LabError;
use crate::params;
use crate::recording::Recording;
use softgrip_core::scene::Scene;

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
    /// The z the effect left out must reach: [`vuong_threshold`] of its variants' tests.
    pub threshold: f64,
}

impl PairNeed {
    fn new(pair: &ModelFit, without: &ModelFit, noise: &Noise, threshold: f64) -> Self {
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
                && z.is_some_and(|z| z >= threshold),
            threshold,
        }
    }
}

/// The rival the round's best candidate `b` ties with, if it does: `b` is
/// not accepted but passes BIC and the share, and so does the best-scoring
/// candidate of another effect in its round (from index `start`).
pub(super) fn tied_rival(hypotheses: &[Hypothesis], start: usize, b: usize) -> Option<usize> {
    let passes = |h: &Hypothesis| h.score < -BIC_THRESHOLD && h.explained >= MIN_EXPLAINED;
    let rival = (start..hypotheses.len())
        .filter(|&j| hypotheses[j].effect != hypotheses[b].effect)
        .min_by(|&x, &y| hypotheses[x].score.total_cmp(&hypotheses[y].score));
    rival.filter(|&r| !accepted(&hypotheses[b]) && passes(&hypotheses[b]) && passes(&hypotheses[r]))
}

/// Fits two tied effects together on `current`, the model both were added
/// to: `best` (the better-scoring, with its fit `hf`) and `rival` (with
/// `rf`). None when either is gone from the catalogue or the pair's fit
/// fails.
pub(super) fn fit_pair(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    current: &ModelFit,
    (best, hf): (&Hypothesis, &ModelFit),
    (rival, rf): (&Hypothesis, &ModelFit),
    fits: &mut FitCount,
) -> Result<Option<PairTest>, LabError> {
    let find = |scene: &Scene, h: &Hypothesis| {
        candidates(recording, scene, options)
            .into_iter()
            .find(|c| c.effect == h.effect && c.variant == h.variant)
    };
    let (Some(hc), Some(rc)) = (find(&current.scene, best), find(&hf.scene, rival)) else {
        return Ok(None);
    };
    let mut params = rc.params.clone();
    params.extend(hc.params.iter().filter(|p| !is_modulus(p)).cloned());
    let k = current.k + own_params(&hc.params) + own_params(&rc.params);
    let budget = options.candidate_evaluations_per_param * params.len();
    fits.starting("the two closest effects together");
    // The pair starts where the better one ended, the other at its catalogue
    // start (no effect, or for table friction a frictionless table, which is
    // not the fixed bottom the better one was fitted on), and also from both
    // effects at their own optima, with either one's modulus. (The pair can
    // still end worse than the better one alone when the two are not nested:
    // a table under the object is no fixed bottom at any friction.)
    let at = |f: &ModelFit, name: &str| f.params.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
    let starts: Vec<Vec<f64>> = [hf, rf]
        .iter()
        .map(|modulus| {
            params
                .iter()
                .map(|p| {
                    let name = p.param.name;
                    if name == "young_modulus" {
                        at(modulus, name)
                    } else {
                        at(rf, name).or_else(|| at(hf, name))
                    }
                    .or_else(|| params::get(&rc.scene, name).ok().flatten())
                    .unwrap_or(p.lower)
                })
                .collect()
        })
        .collect();
    let pair = fit_model(
        recording,
        noise,
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
    let Ok(pair) = pair else { return Ok(None) };
    // The pair needs an effect when leaving it out costs what naming one
    // costs: the BIC gain, the share of the residual and Vuong's z, with the
    // same thresholds.
    Ok(Some(PairTest {
        effects: [
            (best.effect, best.variant.clone()),
            (rival.effect, rival.variant.clone()),
        ],
        without: [
            PairNeed::new(&pair, rf, noise, vuong_threshold(best.tests)),
            PairNeed::new(&pair, hf, noise, vuong_threshold(rival.tests)),
        ],
        fit: pair,
        alone: None,
    }))
}

/// Which of a fitted pair's effects are named with `room` places left (see
/// [`pair_verdict`]), each effect alone (`alone_fits`, in the pair's order)
/// judged against `current`, the model without either; the lone test goes
/// in `test.alone`.
pub(super) fn judge_pair(
    test: &mut PairTest,
    alone_fits: [&ModelFit; 2],
    current: &ModelFit,
    noise: &Noise,
    room: usize,
) -> (bool, bool) {
    let without = weighted_residuals(&current.replay.residuals, noise);
    let lone = alone_fits.map(|f| vuong(&weighted_residuals(&f.replay.residuals, noise), &without));
    let (needed, alone) = pair_verdict(&test.without, lone, room);
    test.alone = alone;
    needed
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
/// model without it. (Where both effects stand for one form error, leaving
/// either out costs something.)
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
            let named = lone[i].is_some_and(|z| z >= without[i].threshold);
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

#[cfg(test)]
mod tests {
    use super::super::statistics::VUONG_Z;
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
            threshold: VUONG_Z,
        }
    }

    /// The pair's verdicts on constructed figures: two effects both needed are both named, or
    /// with one place left the one needed more; a pair that needs neither names none when
    /// leaving either out costs something (+4 and +1: one form error seen by both), and when it
    /// does not need one at all (leaving one out lowers BIC by 3) the other is named only if it
    /// passes a lone candidate's Vuong test.
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
}
