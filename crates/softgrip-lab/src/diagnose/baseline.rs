//! The baseline: the nominal model's uncertain parameters (E, alpha, tau_s, tau_c unless
//! locked) fitted to the recording with every marker counted, the fingers' included: force
//! lost along the load path or creep move the finger more than the object. The noise needs a
//! residual and the weighted fit needs the noise: a first fit weighs every coordinate alike,
//! the noise comes from its residual, and the baseline is refitted weighed by it.

use super::model_fit::{FitTask, ModelFit, Search, fit_model};
use super::noise::Noise;
use super::options::{DiagnoseOptions, check_bounds, within_bounds};
use crate::error::LabError;
use crate::fit::FitParam;
use crate::params;
use crate::recording::Recording;
use softgrip_core::scene::Scene;

/// The baseline's parameters: E, alpha, tau_s and tau_c, less the locked
/// ones and those the scene's model does not use.
pub fn baseline_params(scene: &Scene, lock: &[String]) -> Result<Vec<FitParam>, LabError> {
    for name in lock {
        params::find(name)?;
    }
    let neo = scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean;
    let mut out = Vec::new();
    for name in ["young_modulus", "alpha", "tau_s", "tau_c"] {
        if lock.iter().any(|l| l == name) {
            continue;
        }
        if neo && name != "young_modulus" {
            continue; // the elements have no alpha or spring limits
        }
        if scene.model.alpha == 0.0 && name == "alpha" {
            continue; // off in the scene: nothing to fit
        }
        let p = params::find(name)?;
        let (mut lower, upper) = crate::fit::default_bounds(p, scene)?;
        // A limit below 0.08 acts on nearly every spring: the projection
        // then makes the response depend on the load path, and the fit
        // used it to mimic other physics (hysteresis from load loss) with
        // an unphysical modulus.
        if name.starts_with("tau") {
            lower = lower.max(0.08);
        }
        out.push(FitParam {
            param: p,
            lower,
            upper,
            log: p.log,
        });
    }
    Ok(out)
}

/// The baseline's parameters as its fits search them: [`baseline_params`]
/// within the user's ranges, once the ranges are checked and each is found
/// to meet the range the baseline searches.
pub(super) fn search_params(
    scene: &Scene,
    options: &DiagnoseOptions,
) -> Result<Vec<FitParam>, LabError> {
    check_bounds(&options.bounds)?;
    let own = baseline_params(scene, &options.lock)?;
    for p in &own {
        for (name, low, high) in &options.bounds {
            if p.param.name == name && (*high < p.lower || *low > p.upper) {
                return Err(LabError::Input(format!(
                    "--bound {name}={low}:{high} lies outside the range the baseline searches around the scene's {name} ({:.4e} to {:.4e}): set the scene's {name} inside your range",
                    p.lower, p.upper
                )));
            }
        }
    }
    Ok(within_bounds(own, &options.bounds))
}

/// The first fit's weights: every coordinate alike (1 mm), the noise being
/// unknown until this fit's residual gives it.
const UNWEIGHTED: Noise = Noise {
    object_m: 1e-3,
    finger_m: 1e-3,
    object_count: 0,
    finger_count: 0,
};

/// The first fit, every coordinate weighed alike: the design, and searches
/// from its best and next best points.
pub(super) fn fit_unweighted(
    recording: &Recording,
    options: &DiagnoseOptions,
    params: &[FitParam],
) -> Result<ModelFit, LabError> {
    fit_model(
        recording,
        &UNWEIGHTED,
        options,
        FitTask {
            scene: &recording.scene,
            params,
            k_total: params.len(),
            search: Search::Twice,
            budget: options.max_evaluations,
            starts: &[],
            floor: None,
            known: None,
        },
    )
}

/// The baseline: the `first` fit refitted weighed by `noise`.
pub(super) fn refit_weighted(
    recording: &Recording,
    noise: &Noise,
    options: &DiagnoseOptions,
    params: &[FitParam],
    first: &ModelFit,
) -> Result<ModelFit, LabError> {
    fit_model(
        recording,
        noise,
        options,
        FitTask {
            scene: &first.scene,
            params,
            k_total: params.len(),
            // From the first fit's optimum: the weights changed a little.
            search: Search::Local,
            budget: options.max_evaluations / 2,
            starts: &[],
            floor: None,
            known: Some(first),
        },
    )
}

/// The baseline's parameters that its fit left at a bound of their search
/// range (`fit::at_bound`, as `softgrip fit` flags them).
pub fn pinned_at_bounds(fitted: &[(String, f64)], params: &[FitParam]) -> Vec<String> {
    params
        .iter()
        .filter(|p| {
            fitted
                .iter()
                .find(|(n, _)| n == p.param.name)
                .is_some_and(|(_, v)| crate::fit::at_bound(p.unit(*v)))
        })
        .map(|p| p.param.name.to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fitted value at either end of its search range (on the log scale
    /// for E) is pinned; one inside it, or a parameter not fitted, is not.
    #[test]
    fn a_value_at_the_edge_of_its_range_is_pinned() {
        let param = |name: &str, lower: f64, upper: f64, log: bool| FitParam {
            param: params::find(name).expect("known"),
            lower,
            upper,
            log,
        };
        let ranges = [
            param("young_modulus", 6e3, 6e5, true),
            param("alpha", 6e4, 6e6, true),
            param("tau_c", 0.08, 0.5, false),
            param("tau_s", 0.08, 0.5, false),
        ];
        let fitted = |e: f64, alpha: f64, tau_c: f64| {
            vec![
                ("young_modulus".to_string(), e),
                ("alpha".to_string(), alpha),
                ("tau_c".to_string(), tau_c),
            ]
        };
        assert!(pinned_at_bounds(&fitted(2.1e5, 6.1e5, 0.2), &ranges).is_empty());
        assert_eq!(
            pinned_at_bounds(&fitted(2.1e5, 6e4, 0.08), &ranges),
            ["alpha", "tau_c"]
        );
        assert_eq!(
            pinned_at_bounds(&fitted(6e5, 6.1e5, 0.4999), &ranges),
            ["young_modulus", "tau_c"],
            "the upper end, within 0.1 % of the range"
        );
        // 1 % above E's lower end (0.2 % of its log range) is inside.
        assert!(pinned_at_bounds(&fitted(6e3 * 1.01, 6.1e5, 0.2), &ranges).is_empty());
    }
}
