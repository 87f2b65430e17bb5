//! The typed JSON of `compare`, `fit` and `sweep` (and `merge`, which writes a sweep's): what
//! the CLI's `--json` writes and the Python package returns. Every field's `///` line is its
//! description in the schema (`docs/schema/`, [`crate::schema`]).

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::discretisation::DiscretisationFigures;
use crate::ringing::{RingingComparisonFigures, RingingSide};

/// The error figures of a replay against its recording (thesis eq. 45-46, `docs/formats.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorFigures {
    /// NRMSE: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// RMS distance, simulated to recorded, over the object markers (the finger markers where
    /// the recording has none), m.
    pub rmse_m: f64,
    /// NRMSE over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
}

/// The scene's parameters a comparison ran with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneParams {
    /// The object's Young's modulus, Pa.
    pub young_modulus: f64,
    /// Scale of the volume-preservation force (thesis eq. 10-11), N/m^3.
    pub alpha: f64,
    /// Over-stretch limit of the springs (strain, dimensionless); null where there is none.
    pub tau_s: Option<f64>,
    /// Over-compression limit of the springs (strain, dimensionless); null where there is none.
    pub tau_c: Option<f64>,
}

/// What `softgrip compare --json` writes and Python's `compare` returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CompareFigures {
    /// NRMSE: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// RMS distance, simulated to recorded, over the object markers (the finger markers where
    /// the recording has none), m.
    pub rmse_m: f64,
    /// NRMSE over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// The scene's parameters the replay ran with.
    pub params: SceneParams,
    /// With `--discretisation`: how far a finer mesh and a smaller step move the markers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub discretisation: Option<DiscretisationFigures>,
    /// For a time series: the recorded and simulated ringing of the most-moving marker axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ringing: Option<RingingComparisonFigures>,
}

/// A fit's ringing: the recording's and the replays' at the start and at the fit, on the
/// recording's most-moving marker axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FitRingingFigures {
    /// The marker whose coordinate moves most (its name in the recording).
    pub marker: String,
    /// Its axis: `x`, `y` or `z`.
    pub axis: String,
    /// The recorded coordinate's ringing.
    pub recorded: RingingSide,
    /// The simulated coordinate's ringing with the start's parameters.
    pub start: RingingSide,
    /// The simulated coordinate's ringing with the fitted parameters.
    pub fitted: RingingSide,
}

/// What `softgrip fit --json` writes for one recording and Python's `fit` returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FitFigures {
    /// NRMSE at the fit: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// RMS distance at the fit, simulated to recorded, over the object markers (the finger
    /// markers where the recording has none), m.
    pub rmse_m: f64,
    /// NRMSE at the fit over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance at the fit over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// The fitted values by parameter name, in each parameter's unit (null where not finite).
    pub params: BTreeMap<String, Option<f64>>,
    /// The start's values by parameter name, in each parameter's unit (null where not finite).
    pub start: BTreeMap<String, Option<f64>>,
    /// Each fitted value's noise-implied standard error, in its unit (null where the data do
    /// not determine it).
    pub standard_errors: BTreeMap<String, Option<f64>>,
    /// Each parameter's verdict from the NRMSE at +/-10 %: `identified`, `weakly identified
    /// (...)`, `bounded on one side only` or `UNIDENTIFIABLE`.
    pub identifiability: BTreeMap<String, String>,
    /// The errors at the start.
    pub before: ErrorFigures,
    /// The noise the fit's residuals imply, sqrt(SSR / (m - p)), m.
    pub noise_m: f64,
    /// Simulations the search ran.
    pub simulations: usize,
    /// The search converged or stopped improving (not stopped by its budget).
    pub converged: bool,
    /// For a time series: the ringing recorded, at the start and at the fit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ringing: Option<FitRingingFigures>,
}

/// One recording of a fit of several.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FitManyRecording {
    /// NRMSE at the fit: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// RMS distance at the fit, simulated to recorded, over the object markers (the finger
    /// markers where the recording has none), m.
    pub rmse_m: f64,
    /// NRMSE at the fit over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance at the fit over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// This recording's errors at the start.
    pub before: ErrorFigures,
    /// The recording's mode: `quasi-static` or `time-series`.
    pub mode: String,
    /// For a time series: the ringing recorded, at the start and at the fit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ringing: Option<FitRingingFigures>,
}

/// An NRMSE alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NrmseFigures {
    /// The mean of the recordings' NRMSE, dimensionless.
    pub nrmse: f64,
}

/// What `softgrip fit --json` writes for several recordings sharing one set of parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FitManyFigures {
    /// Each recording's figures, in the order given.
    pub recordings: Vec<FitManyRecording>,
    /// The objective at the fit: the mean of the recordings' NRMSE, dimensionless.
    pub nrmse: f64,
    /// The objective at the start.
    pub before: NrmseFigures,
    /// What was minimised, in words.
    pub objective: String,
    /// The fitted values by parameter name, in each parameter's unit (null where not finite).
    pub params: BTreeMap<String, Option<f64>>,
    /// The start's values (the first recording's scene) by parameter name, in each
    /// parameter's unit (null where not finite).
    pub start: BTreeMap<String, Option<f64>>,
    /// Each fitted value's noise-implied standard error, in its unit (null where the data do
    /// not determine it).
    pub standard_errors: BTreeMap<String, Option<f64>>,
    /// Each parameter's verdict from the mean NRMSE at +/-10 %: `identified`, `weakly
    /// identified (...)`, `bounded on one side only` or `UNIDENTIFIABLE`.
    pub identifiability: BTreeMap<String, String>,
    /// The noise the stacked residuals imply, sqrt(SSR / (m - p)), m.
    pub noise_m: f64,
    /// Parameter sets the search tried.
    pub points: usize,
    /// Simulations run: `points` times the recordings.
    pub simulations: usize,
    /// The search converged or stopped improving (not stopped by its budget).
    pub converged: bool,
}

/// What `softgrip sweep --json` and `softgrip merge --json` write and Python's `sweep` and
/// `sweep_merge` return: the best point's figures (the wall time is not here: a sweep split over
/// machines gives the same file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepFigures {
    /// The best point's NRMSE: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// The best point's RMS distance, simulated to recorded, over the object markers (the
    /// finger markers where the recording has none), m.
    pub rmse_m: f64,
    /// The best point's NRMSE over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// The best point's RMS distance over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// The best point's values by parameter name, in each parameter's unit.
    pub params: BTreeMap<String, f64>,
    /// Grid points swept.
    pub points: usize,
    /// Grid points whose simulation failed.
    pub failed: usize,
}
