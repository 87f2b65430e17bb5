//! A fitted material's standard errors carried to the grasp window's two ends: each bound's
//! derivative in each fitted parameter by a central difference (the bound found again, near
//! itself, at the parameter plus and minus its standard error), combined as independent errors (the two sides of each difference on a thread each),
//! `se(B)^2 = sum_p (dB/dp se_p)^2` (`fit --json` gives standard errors, not their correlations).

use std::path::Path;

use super::plan::Plan;
use super::window::{Gripper, Window};
use crate::error::LabError;
use crate::params;
use softgrip_core::scene::Scene;

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Fitted {
    /// The parameter's name (as `--params` names it).
    pub name: String,
    /// Its fitted value, in its unit.
    pub value: f64,
    /// Its standard error, in its unit.
    pub standard_error: f64,
}

/// The parameters of a `softgrip fit --json` file with their standard errors.
pub fn read_fit(path: &Path) -> Result<Vec<Fitted>, LabError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        LabError::Input(format!(
            "{}: cannot read the fit ({e}): give the JSON that `softgrip fit --json` wrote",
            path.display()
        ))
    })?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        LabError::Input(format!(
            "{}: not JSON ({e}): give the file that `softgrip fit --json` wrote",
            path.display()
        ))
    })?;
    let (Some(values), Some(errors)) = (v["params"].as_object(), v["standard_errors"].as_object())
    else {
        return Err(LabError::Input(format!(
            "{}: no \"params\" and \"standard_errors\": give the file that `softgrip fit --json` wrote",
            path.display()
        )));
    };
    let mut fitted = Vec::new();
    for (name, value) in values {
        let value = value.as_f64();
        let se = errors.get(name).and_then(serde_json::Value::as_f64);
        match (value, se) {
            (Some(value), Some(se)) if value.is_finite() && se.is_finite() && se >= 0.0 => fitted
                .push(Fitted {
                    name: name.clone(),
                    value,
                    standard_error: se,
                }),
            _ => {
                return Err(LabError::Input(format!(
                    "{}: parameter {name:?} has no finite value and standard error (the fit could not estimate it): fit again, or leave --fit out",
                    path.display()
                )));
            }
        }
    }
    Ok(fitted)
}

/// The scene with the fitted values set (each through the scene file's own checks).
pub fn with_fit(scene: &Scene, fitted: &[Fitted]) -> Result<Scene, LabError> {
    fitted
        .iter()
        .try_fold(scene.clone(), |s, p| params::set(&s, &p.name, p.value))
}

/// Each bound's standard error, and each parameter's share.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundErrors {
    /// The least squeeze's standard error (N).
    pub least: f64,
    /// The most's, where the limit was reached.
    pub most: Option<f64>,
    /// Per parameter: name, d least / dp, d most / dp (N per unit).
    pub derivatives: Vec<(String, f64, Option<f64>)>,
    /// The relative tolerance each bound was found to for the differences.
    pub tolerance: f64,
    /// The fitted parameters the errors come from.
    pub fitted: Vec<Fitted>,
}

/// `bound +/- se N (95 %: low .. high)`, as the console and the report say it.
pub fn range_text(bound: f64, se: f64) -> String {
    format!(
        "{bound:.4} +/- {se:.4} N (95 %: {:.4} .. {:.4})",
        bound - Z95 * se,
        bound + Z95 * se
    )
}

/// The two-sided 95 % normal quantile.
pub const Z95: f64 = 1.959_963_984_540_054;

impl BoundErrors {
    /// Whether the 95 % ranges of the two bounds overlap: the window may be empty.
    pub fn overlaps(&self, window: &Window) -> bool {
        match (window.most_squeeze(), self.most) {
            (Some(most), Some(se)) => window.least_squeeze() + Z95 * self.least >= most - Z95 * se,
            _ => false,
        }
    }
}

/// The bounds of `window` (found on `scene` with the fitted values set) with their standard
/// errors. `progress` hears (done, total) parameter evaluations.
pub fn propagate(
    scene: &Scene,
    fitted: &[Fitted],
    plan: &Plan,
    window: &Window,
    mut progress: impl FnMut(usize, usize),
) -> Result<BoundErrors, LabError> {
    // The differences need the bounds finer than the window's 1 %.
    let tolerance = 0.002;
    let mut options = plan.options;
    options.tolerance = tolerance;
    let bounds = |s: &Scene| -> Result<(f64, Option<f64>), LabError> {
        let g = Gripper::new(s, plan.options.profile)?;
        let least = g.least_near(window.least_squeeze(), &options)?;
        let most = match window.most_squeeze() {
            Some(m) if m > 0.0 => Some(g.most_near(m, &options)?),
            _ => None,
        };
        Ok((least, most))
    };
    let mut derivatives = Vec::new();
    let (mut least_var, mut most_var) = (0.0, 0.0);
    let total = 2 * fitted.len();
    for (k, p) in fitted.iter().enumerate() {
        let h = p.standard_error.max(1e-6 * p.value.abs());
        let base = with_fit(scene, fitted)?;
        let (above, below) = (
            params::set(&base, &p.name, p.value + h)?,
            params::set(&base, &p.name, p.value - h)?,
        );
        // The two sides on a thread each.
        let cancel = softgrip_core::cancel::current();
        let (up, down) = std::thread::scope(|scope| {
            let up =
                scope.spawn(|| softgrip_core::cancel::scope(cancel.clone(), || bounds(&above)));
            let down = bounds(&below);
            let up = up.join().unwrap_or_else(|_| {
                Err(LabError::input("grasp window: a perturbed window stopped"))
            });
            (up, down)
        });
        let (up, down) = (up?, down?);
        progress(2 * k + 2, total);
        let d_least = (up.0 - down.0) / (2.0 * h);
        let d_most = up.1.zip(down.1).map(|(a, b)| (a - b) / (2.0 * h));
        least_var += (d_least * p.standard_error).powi(2);
        if let Some(d) = d_most {
            most_var += (d * p.standard_error).powi(2);
        }
        derivatives.push((p.name.clone(), d_least, d_most));
    }
    Ok(BoundErrors {
        least: least_var.sqrt(),
        most: window.most_squeeze().map(|_| most_var.sqrt()),
        derivatives,
        tolerance,
        fitted: fitted.to_vec(),
    })
}
