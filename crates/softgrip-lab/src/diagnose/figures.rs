//! The typed JSON of the diagnosis (`softgrip diagnose --json`, Python's `diagnose`): the spec's
//! interchange keys with softgrip's additions (`docs/formats.md`). [`super::to_json`] fills
//! these; every field's `///` line is its description in the schema (`docs/schema/`,
//! [`crate::schema`]).

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::discretisation::DiscretisationFigures;

/// What `softgrip diagnose --json` writes: what physics the model left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiagnosisFigures {
    /// The pair fitted when the best two effects tied; null unless they did.
    pub pair: Option<PairFigures>,
    /// The model fitted before any effect.
    pub baseline: BaselineFigures,
    /// The noise estimated from the baseline's residual.
    pub noise: NoiseFigures,
    /// How far the final model moves on a finer mesh and at half the step.
    pub discretisation: DiscretisationFigures,
    /// What the baseline misses, against the noise.
    pub mismatch: MismatchFigures,
    /// Every candidate effect fitted, round by round.
    pub hypotheses: Vec<HypothesisFigures>,
    /// The effects named, their values and errors, the fit before and after, the evidence.
    pub verdict: VerdictFigures,
}

/// The baseline: the model fitted before any effect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BaselineFigures {
    /// The model: `continuum` (neo-Hookean elements) or `lattice` (the thesis's springs).
    pub model: String,
    /// NRMSE over the object markers (the finger markers where there are none),
    /// dimensionless.
    pub nrmse: f64,
    /// NRMSE over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance, simulated to recorded, over the object markers, m.
    pub rmse_m: f64,
    /// The fitted values by parameter name, in each parameter's unit.
    pub params: BTreeMap<String, f64>,
    /// The parameters that ended at the edge of their search range.
    pub pinned: Vec<String>,
    /// The ranges given with `--bound`: name to `[low, high]`, in the parameter's unit.
    pub bounds: BTreeMap<String, [f64; 2]>,
}

/// The noise estimated from the residual.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NoiseFigures {
    /// The object markers' noise, m.
    pub object_m: f64,
    /// The finger markers' noise, m.
    pub finger_m: f64,
}

/// What the baseline misses.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MismatchFigures {
    /// Markers whose residual is significant, worst first.
    pub markers: Vec<String>,
    /// Axes (`x`, `y`, `z`) whose residual is significant.
    pub axes: Vec<String>,
    /// Where, in words.
    #[serde(rename = "where")]
    pub at: String,
    /// When: how it depends on the sample (such as "grows with load").
    pub when: String,
    /// Regions of the object whose markers' residual is significant, worst first.
    pub regions: Vec<String>,
    /// Whether the whole residual is significant, by its chi-square against the noise.
    pub significant: bool,
}

/// One candidate effect fitted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HypothesisFigures {
    /// The effect's catalogue name (`table-friction`, ...).
    pub effect: String,
    /// Which variant (the region's place, the stiffening's form); absent for an effect with
    /// one.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub variant: String,
    /// BIC against the model it was added to (negative: better).
    pub score: f64,
    /// Share of the weighted residual sum of squares it removed (fraction).
    pub explained: f64,
    /// Vuong's z against its rival (positive: this one fits closer); null when the fit
    /// failed.
    pub vuong_z: Option<f64>,
    /// The z it needed, for the independent tests its round counts as.
    pub vuong_z_needed: f64,
    /// The independent tests its effect's forms or places in its round count as.
    pub tests: f64,
    /// The search's round it was fitted in, from 0.
    pub round: usize,
    /// Where the fit ran: its values by parameter name, in each parameter's unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub params: Option<BTreeMap<String, f64>>,
    /// Where the fit ran: its NRMSE, dimensionless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nrmse: Option<f64>,
    /// Where the fit ran: its NRMSE over every marker, dimensionless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nrmse_all: Option<f64>,
    /// Where the fit failed: why, in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// An effect of a pair, with its variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PairEffect {
    /// The effect's catalogue name.
    pub effect: String,
    /// Which variant; absent for an effect with one.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub variant: String,
}

/// The best two effects fitted together, and each tested against the pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PairFigures {
    /// The two effects, the better-scoring first.
    pub effects: [PairEffect; 2],
    /// The pair's fitted values by parameter name, in each parameter's unit.
    pub params: BTreeMap<String, f64>,
    /// The pair's NRMSE over every marker, dimensionless.
    pub nrmse_all: f64,
    /// What leaving each effect out costs, in the order of `effects`.
    pub without: [PairNeedFigures; 2],
    /// When the pair did not need one of the two at all: the other judged alone; else null.
    pub alone: Option<LoneFigures>,
}

/// What leaving one effect out of the pair costs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PairNeedFigures {
    /// BIC of the pair without it, minus the pair's (positive: needed).
    pub bic: f64,
    /// Share of the residual without it that the pair removes (fraction).
    pub explained: f64,
    /// Vuong's z of the pair against the pair without it; null where not had.
    pub vuong_z: Option<f64>,
    /// The same with each sample's coordinates summed first; null where not had.
    pub vuong_z_by_sample: Option<f64>,
    /// BIC, share and z all pass the thresholds used for one effect.
    pub needed: bool,
}

/// A pair's effect judged alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoneFigures {
    /// The effect.
    pub effect: PairEffect,
    /// Its Vuong z against the model without it; null where not had.
    pub vuong_z: Option<f64>,
}

/// The verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VerdictFigures {
    /// The first effect named, `none` or `unexplained`.
    pub effect: String,
    /// Every effect named, in order.
    pub effects: Vec<String>,
    /// The final model's fitted values by parameter name, in each parameter's unit.
    pub params: BTreeMap<String, f64>,
    /// Other readings that fit about as well.
    pub alternatives: Vec<AlternativeFigures>,
    /// The final fit's standard errors by parameter name, in each parameter's unit (null where
    /// the data do not determine it).
    pub standard_errors: BTreeMap<String, Option<f64>>,
    /// The baseline's NRMSE, dimensionless.
    pub nrmse_before: f64,
    /// The final model's NRMSE, dimensionless.
    pub nrmse_after: f64,
    /// The baseline's NRMSE over every marker, dimensionless.
    pub nrmse_all_before: f64,
    /// The final model's NRMSE over every marker, dimensionless.
    pub nrmse_all_after: f64,
    /// The baseline's NRMSE over every marker of the part of the residual the noise does not
    /// account for, dimensionless.
    pub nrmse_all_beyond_noise_before: f64,
    /// The same for the final model, dimensionless.
    pub nrmse_all_beyond_noise_after: f64,
    /// The region of other stiffness named; null where none was.
    pub region: Option<RegionFigures>,
    /// Effects the search named that the remainder's checks set aside.
    pub set_aside: Vec<String>,
    /// What the final model leaves.
    pub remainder: RemainderFigures,
    /// The reasons, in words.
    pub evidence: String,
    /// The scene's model had no equilibrium under a recorded load: which, where, what it was
    /// given to carry them; null where it had.
    pub model_finding: Option<String>,
}

/// Another reading that fits about as well as the verdict's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AlternativeFigures {
    /// The effect's catalogue name.
    pub effect: String,
    /// Which variant (empty for an effect with one).
    pub variant: String,
    /// Vuong's z against its rival (positive: this one fits closer); null where not had.
    pub vuong_z: Option<f64>,
    /// Share of the weighted residual sum of squares it removed (fraction).
    pub explained: f64,
}

/// The region of other stiffness named.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegionFigures {
    /// Its shape and place, in words.
    pub variant: String,
    /// Its box's lowest corner, m.
    pub min: [f64; 3],
    /// Its box's highest corner, m.
    pub max: [f64; 3],
    /// Its Young's modulus over the rest's, dimensionless.
    pub ratio: f64,
    /// The ratio's standard error (delta method); null where not had.
    pub ratio_standard_error: Option<f64>,
}

/// What the final model leaves: each check null where it does not apply.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RemainderFigures {
    /// The residual on unloading against the loading branch's at the same load.
    pub hysteresis: Option<TestFigures>,
    /// An object marker beyond the noise and the refined mesh's move, the others within.
    pub lone_markers: Option<TestFigures>,
    /// The symptom's own description (a share of the way kept on unloading) as a rival.
    pub kept_share: Option<KeptShareFigures>,
    /// Where the failed checks place the mismatch: markers, worst first.
    pub markers: Vec<String>,
}

/// One of the remainder's checks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TestFigures {
    /// The chi-square statistic, dimensionless.
    pub chi2: f64,
    /// Its degrees of freedom.
    pub dof: usize,
    /// Its p-value.
    pub p_value: f64,
    /// Whether the check finds a mismatch the model leaves (p below 0.001).
    pub fails: bool,
    /// Markers beyond their own bar, worst first.
    pub markers: Vec<MarkerOverBar>,
}

/// The kept share as a rival to the verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KeptShareFigures {
    /// The share kept (positive: the markers stay nearer the peak than the model has them),
    /// fraction.
    pub share: f64,
    /// The chi-square statistic, dimensionless.
    pub chi2: f64,
    /// Its p-value.
    pub p_value: f64,
    /// Vuong's z of the final model against it (positive: the final model fits closer); null
    /// when no effect was named.
    pub vuong_z: Option<f64>,
    /// Whether it stands against the verdict.
    pub fails: bool,
    /// Markers where the kept share moves most beyond the noise, worst first.
    pub markers: Vec<MarkerOverBar>,
}

/// A marker and how far beyond its bar it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MarkerOverBar {
    /// The marker's name.
    pub marker: String,
    /// Its RMS over its bar, dimensionless.
    pub over_bar: f64,
}
