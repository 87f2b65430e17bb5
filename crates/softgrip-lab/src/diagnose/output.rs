//! The diagnosis as the spec's JSON (`softgrip diagnose --json`).

use super::model_fit::ModelFit;
use super::remainder::Test as RemainderTest;
use super::statistics::vuong_threshold;
use super::verdict::Diagnosis;
use crate::recording::Recording;

/// The spec's JSON (`diagnose --json`), with softgrip's additions
/// (`verdict.effects`, `verdict.evidence`, `noise`, `mismatch.regions`).
pub fn to_json(d: &Diagnosis, recording: &Recording) -> serde_json::Value {
    let params = |f: &ModelFit| {
        serde_json::Value::Object(
            f.params
                .iter()
                .map(|(k, v)| (k.clone(), serde_json::json!(v)))
                .collect(),
        )
    };
    let hypotheses: Vec<serde_json::Value> = d
        .hypotheses
        .iter()
        .map(|h| {
            let mut v = serde_json::json!({
                "effect": h.effect,
                "score": h.score,
                "explained": h.explained,
                "vuong_z": h.vuong,
                "vuong_z_needed": vuong_threshold(h.tests),
                "tests": h.tests,
                "round": h.round,
            });
            if !h.variant.is_empty() {
                v["variant"] = serde_json::json!(h.variant);
            }
            match &h.fit {
                Ok(f) => {
                    v["params"] = params(f);
                    v["nrmse"] = serde_json::json!(f.errors.nrmse);
                    v["nrmse_all"] = serde_json::json!(f.errors.nrmse_all);
                }
                Err(e) => v["error"] = serde_json::json!(e.to_string()),
            }
            v
        })
        .collect();
    let _ = recording;
    let pair = d.pair.as_ref().map(|t| {
        let effect = |(e, v): &(&str, String)| {
            if v.is_empty() {
                serde_json::json!({"effect": e})
            } else {
                serde_json::json!({"effect": e, "variant": v})
            }
        };
        serde_json::json!({
            "effects": [effect(&t.effects[0]), effect(&t.effects[1])],
            "params": params(&t.fit),
            "nrmse_all": t.fit.errors.nrmse_all,
            "without": t.without.iter().map(|w| serde_json::json!({
                "bic": w.bic,
                "explained": w.explained,
                "vuong_z": w.vuong,
                "vuong_z_by_sample": w.vuong_by_sample,
                "needed": w.needed,
            })).collect::<Vec<_>>(),
            "alone": t.alone.map(|(i, z)| serde_json::json!({
                "effect": effect(&t.effects[i]),
                "vuong_z": z,
            })),
        })
    });
    serde_json::json!({
        "pair": pair,
        "baseline": {
            "model": d.model(),
            "nrmse": d.baseline.errors.nrmse,
            "nrmse_all": d.baseline.errors.nrmse_all,
            "rmse_m": d.baseline.errors.rmse_m,
            "params": params(&d.baseline),
            "pinned": d.pinned,
            "bounds": serde_json::Value::Object(
                d.bounds
                    .iter()
                    .map(|(k, lo, hi)| (k.clone(), serde_json::json!([lo, hi])))
                    .collect(),
            ),
        },
        "noise": {"object_m": d.noise.object_m, "finger_m": d.noise.finger_m},
        "discretisation": d.discretisation.to_json(),
        "mismatch": {
            "markers": d.location.markers.iter().map(|(m, _)| m.clone()).collect::<Vec<_>>(),
            "axes": d.location.axes,
            "where": d.location.description,
            "when": d.location.when,
            "regions": d.location.regions.iter().map(|(r, _)| r.clone()).collect::<Vec<_>>(),
            "significant": d.location.significant,
        },
        "hypotheses": hypotheses,
        "verdict": verdict(d),
    })
}

/// The JSON's `verdict`: the effects named, their values and errors, the fit before and after,
/// the region, what the final model leaves, the evidence.
fn verdict(d: &Diagnosis) -> serde_json::Value {
    let beyond_noise = d.nrmse_all_beyond_noise();
    serde_json::json!({
        "effect": d.verdict(),
        "effects": d.effects,
        "params": serde_json::Value::Object(
            d.fitted_params()
                .into_iter()
                .map(|(k, v)| (k, serde_json::json!(v)))
                .collect(),
        ),
        "alternatives": d.alternatives().iter().map(|h| serde_json::json!({
            "effect": h.effect,
            "variant": h.variant,
            "vuong_z": h.vuong,
            "explained": h.explained,
        })).collect::<Vec<_>>(),
        "standard_errors": serde_json::Value::Object(
            d.fitted_params()
                .into_iter()
                .filter_map(|(k, _)| {
                    let e = d.standard_error(&k)?;
                    Some((k, serde_json::json!(e.is_finite().then_some(e))))
                })
                .collect(),
        ),
        "nrmse_before": d.baseline.errors.nrmse,
        "nrmse_after": d.final_fit.errors.nrmse,
        "nrmse_all_before": d.baseline.errors.nrmse_all,
        "nrmse_all_after": d.final_fit.errors.nrmse_all,
        "nrmse_all_beyond_noise_before": beyond_noise.0,
        "nrmse_all_beyond_noise_after": beyond_noise.1,
        "region": d.region().map(|r| serde_json::json!({
            "variant": r.variant,
            "min": r.region.min.to_array(),
            "max": r.region.max.to_array(),
            "ratio": r.ratio,
            "ratio_standard_error": r.ratio_standard_error.is_finite().then_some(r.ratio_standard_error),
        })),
        "set_aside": d.set_aside,
        "remainder": {
            "hysteresis": d.remainder.hysteresis.as_ref().map(test),
            "lone_markers": d.remainder.lone_markers.as_ref().map(test),
            "kept_share": d.remainder.kept_share.as_ref().map(|k| serde_json::json!({
                "share": k.share,
                "chi2": k.chi2,
                "p_value": k.p_value,
                "vuong_z": k.z,
                "fails": k.fails,
                "markers": k.markers.iter().map(|(m, r)| serde_json::json!({"marker": m, "over_bar": r})).collect::<Vec<_>>(),
            })),
            "markers": d.remainder.markers(),
        },
        "evidence": d.evidence,
        "model_finding": d.model_finding,
    })
}

/// One of the remainder's checks.
fn test(t: &RemainderTest) -> serde_json::Value {
    serde_json::json!({
        "chi2": t.chi2,
        "dof": t.dof,
        "p_value": t.p_value,
        "fails": t.fails,
        "markers": t.markers.iter().map(|(m, r)| serde_json::json!({"marker": m, "over_bar": r})).collect::<Vec<_>>(),
    })
}
