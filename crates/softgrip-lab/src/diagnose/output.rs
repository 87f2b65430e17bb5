//! The diagnosis as the spec's JSON (`softgrip diagnose --json`).

use std::collections::BTreeMap;

use super::figures::{
    AlternativeFigures, BaselineFigures, DiagnosisFigures, HypothesisFigures, KeptShareFigures,
    LoneFigures, MarkerOverBar, MismatchFigures, NoiseFigures, PairEffect, PairFigures,
    PairNeedFigures, RegionFigures, RemainderFigures, TestFigures, VerdictFigures,
};
use super::hypothesis::Hypothesis;
use super::model_fit::ModelFit;
use super::pairs::PairTest;
use super::remainder::Test as RemainderTest;
use super::statistics::vuong_threshold;
use super::verdict::Diagnosis;
use crate::recording::Recording;

/// The spec's JSON (`diagnose --json`), with softgrip's additions
/// (`verdict.effects`, `verdict.evidence`, `noise`, `mismatch.regions`).
pub fn to_json(d: &Diagnosis, recording: &Recording) -> serde_json::Value {
    crate::json::to_value(&diagnosis_figures(d, recording))
}

/// The diagnosis as its JSON's typed figures.
pub fn diagnosis_figures(d: &Diagnosis, recording: &Recording) -> DiagnosisFigures {
    let _ = recording;
    DiagnosisFigures {
        pair: d.pair.as_ref().map(pair),
        baseline: BaselineFigures {
            model: d.model().to_string(),
            nrmse: d.baseline.errors.nrmse,
            nrmse_all: d.baseline.errors.nrmse_all,
            rmse_m: d.baseline.errors.rmse_m,
            params: params(&d.baseline),
            pinned: d.pinned.clone(),
            bounds: d
                .bounds
                .iter()
                .map(|(k, lo, hi)| (k.clone(), [*lo, *hi]))
                .collect(),
        },
        noise: NoiseFigures {
            object_m: d.noise.object_m,
            finger_m: d.noise.finger_m,
        },
        discretisation: d.discretisation.figures(),
        mismatch: MismatchFigures {
            markers: d.location.markers.iter().map(|(m, _)| m.clone()).collect(),
            axes: d.location.axes.clone(),
            at: d.location.description.clone(),
            when: d.location.when.clone(),
            regions: d.location.regions.iter().map(|(r, _)| r.clone()).collect(),
            significant: d.location.significant,
        },
        hypotheses: d.hypotheses.iter().map(hypothesis).collect(),
        verdict: verdict(d),
    }
}

/// A fit's parameters, by name.
fn params(f: &ModelFit) -> BTreeMap<String, f64> {
    f.params.iter().map(|(k, v)| (k.clone(), *v)).collect()
}

/// One of the JSON's `hypotheses`: a candidate fitted, its scores, its fit or why it failed.
fn hypothesis(h: &Hypothesis) -> HypothesisFigures {
    let fit = h.fit.as_ref().ok();
    HypothesisFigures {
        effect: h.effect.to_string(),
        variant: h.variant.clone(),
        score: h.score,
        explained: h.explained,
        vuong_z: h.vuong,
        vuong_z_needed: vuong_threshold(h.tests),
        tests: h.tests,
        round: h.round,
        params: fit.map(params),
        nrmse: fit.map(|f| f.errors.nrmse),
        nrmse_all: fit.map(|f| f.errors.nrmse_all),
        error: h.fit.as_ref().err().map(|e| e.to_string()),
    }
}

/// The JSON's `pair`: two effects fitted together, and each tested against the pair.
fn pair(t: &PairTest) -> PairFigures {
    let effect = |(e, v): &(&str, String)| PairEffect {
        effect: e.to_string(),
        variant: v.clone(),
    };
    PairFigures {
        effects: [effect(&t.effects[0]), effect(&t.effects[1])],
        params: params(&t.fit),
        nrmse_all: t.fit.errors.nrmse_all,
        without: t.without.map(|w| PairNeedFigures {
            bic: w.bic,
            explained: w.explained,
            vuong_z: w.vuong,
            vuong_z_by_sample: w.vuong_by_sample,
            needed: w.needed,
        }),
        alone: t.alone.map(|(i, z)| LoneFigures {
            effect: effect(&t.effects[i]),
            vuong_z: z,
        }),
    }
}

/// The JSON's `verdict`: the effects named, their values and errors, the fit before and after,
/// the region, what the final model leaves, the evidence.
fn verdict(d: &Diagnosis) -> VerdictFigures {
    let beyond_noise = d.nrmse_all_beyond_noise();
    VerdictFigures {
        effect: d.verdict(),
        effects: d.effects.iter().map(|e| e.to_string()).collect(),
        params: d.fitted_params().into_iter().collect(),
        alternatives: d
            .alternatives()
            .iter()
            .map(|h| AlternativeFigures {
                effect: h.effect.to_string(),
                variant: h.variant.clone(),
                vuong_z: h.vuong,
                explained: h.explained,
            })
            .collect(),
        standard_errors: d
            .fitted_params()
            .into_iter()
            .filter_map(|(k, _)| {
                let e = d.standard_error(&k)?;
                Some((k, e.is_finite().then_some(e)))
            })
            .collect(),
        nrmse_before: d.baseline.errors.nrmse,
        nrmse_after: d.final_fit.errors.nrmse,
        nrmse_all_before: d.baseline.errors.nrmse_all,
        nrmse_all_after: d.final_fit.errors.nrmse_all,
        nrmse_all_beyond_noise_before: beyond_noise.0,
        nrmse_all_beyond_noise_after: beyond_noise.1,
        region: d.region().map(|r| RegionFigures {
            variant: r.variant,
            min: r.region.min.to_array(),
            max: r.region.max.to_array(),
            ratio: r.ratio,
            ratio_standard_error: r
                .ratio_standard_error
                .is_finite()
                .then_some(r.ratio_standard_error),
        }),
        set_aside: d.set_aside.iter().map(|e| e.to_string()).collect(),
        remainder: RemainderFigures {
            hysteresis: d.remainder.hysteresis.as_ref().map(test),
            lone_markers: d.remainder.lone_markers.as_ref().map(test),
            kept_share: d.remainder.kept_share.as_ref().map(|k| KeptShareFigures {
                share: k.share,
                chi2: k.chi2,
                p_value: k.p_value,
                vuong_z: k.z,
                fails: k.fails,
                markers: over_bar(&k.markers),
            }),
            markers: d.remainder.markers(),
        },
        evidence: d.evidence.clone(),
        model_finding: d.model_finding.clone(),
    }
}

/// Markers with their RMS over their bar.
fn over_bar(markers: &[(String, f64)]) -> Vec<MarkerOverBar> {
    markers
        .iter()
        .map(|(m, r)| MarkerOverBar {
            marker: m.clone(),
            over_bar: *r,
        })
        .collect()
}

/// One of the remainder's checks.
fn test(t: &RemainderTest) -> TestFigures {
    TestFigures {
        chi2: t.chi2,
        dof: t.dof,
        p_value: t.p_value,
        fails: t.fails,
        markers: over_bar(&t.markers),
    }
}
