//! Sensitivities `dx/dp` of a static equilibrium to the scene's named parameters
//! ([`crate::params`]): the models at `p -+ delta` are built on the equilibrium's own mesh and
//! handed to `softgrip_core::sensitivity`, which holds the equilibrium fixed and solves with
//! its tangent (no re-solve per parameter). Method and accuracy: `docs/design/equilibrium.md`,
//! "Sensitivities".

use glam::DVec3;
use softgrip_core::Simulation;
use softgrip_core::mesh::TetMesh;
use softgrip_core::model::Model;
use softgrip_core::scene::Scene;
use softgrip_core::sensitivity::{ParameterStep, SensitivityOptions};

use crate::error::LabError;
use crate::params;
use crate::recording::Recording;
use crate::replay::{MarkerSensitivities, Replay, ReplayOptions, SampleState, replay_observing};
use softgrip_core::error::SimError;

/// The force's difference quotient steps `delta = RELATIVE_STEP |p|` (the force is smooth in
/// every parameter but at the few springs a spring limit's start crosses) ...
pub const RELATIVE_STEP: f64 = 1e-5;
/// ... or this where `p = 0`.
pub const ABSOLUTE_STEP: f64 = 1e-6;

/// The sensitivity of an equilibrium to one named parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterSensitivity {
    /// The parameter's name ([`crate::params::PARAMS`]).
    pub name: &'static str,
    /// The parameter's value in the scene.
    pub value: f64,
    /// `dx/dp` (m per unit of the parameter): the particles, then the fingers.
    pub dx_dp: Vec<DVec3>,
    /// GMRES products the solve took.
    pub iterations: usize,
}

impl ParameterSensitivity {
    /// The particles' part of `dx/dp`.
    pub fn particles(&self, particles: usize) -> &[DVec3] {
        &self.dx_dp[..particles]
    }

    /// Finger `k`'s `dx/dp`.
    pub fn finger(&self, particles: usize, k: usize) -> DVec3 {
        self.dx_dp[particles + k]
    }
}

/// `dx/dp` at `sim`'s state, an equilibrium of `scene` on `mesh` (the mesh the simulation was
/// built on), for each parameter in `names`. A parameter that is off in the scene (a spring
/// limit not set, a finger parameter without fingers) is an input error.
pub fn sensitivities(
    scene: &Scene,
    mesh: &TetMesh,
    sim: &Simulation,
    names: &[&str],
    options: SensitivityOptions,
) -> Result<Vec<ParameterSensitivity>, LabError> {
    let targets: Vec<(&Scene, &str)> = names.iter().map(|n| (scene, *n)).collect();
    sensitivities_to(&targets, mesh, sim, options)
}

/// [`sensitivities`] to parameters of other scenes of the same model: each `(scene, name)`
/// is `name` in `scene`, a scene on the same mesh whose model at the parameter's present value
/// is the simulation's (a region of the object's own material added, a term switched off), so
/// that the simulation's equilibrium is its equilibrium too. The score test's screen
/// (`crate::diagnose`) asks for each candidate effect's parameters at its null so.
pub fn sensitivities_to(
    targets: &[(&Scene, &str)],
    mesh: &TetMesh,
    sim: &Simulation,
    options: SensitivityOptions,
) -> Result<Vec<ParameterSensitivity>, LabError> {
    let steps = ParameterSteps::new(targets, mesh)?;
    steps.solve(sim, options)
}

/// The models at `p -+ delta` of each target, built once for every equilibrium on one mesh (a
/// replay's loads): a model build costs about a force evaluation.
pub struct ParameterSteps {
    steps: Vec<ParameterStep>,
    found: Vec<(&'static str, f64)>,
}

impl ParameterSteps {
    /// The steps of each `(scene, name)` on `mesh` (see [`sensitivities_to`]).
    pub fn new(targets: &[(&Scene, &str)], mesh: &TetMesh) -> Result<ParameterSteps, LabError> {
        let mut steps = Vec::with_capacity(targets.len());
        let mut found = Vec::with_capacity(targets.len());
        for &(scene, name) in targets {
            let param = params::find(name)?;
            let value = params::get(scene, name)?.ok_or_else(|| {
                LabError::Input(format!(
                    "{name} is off in this scene: set it to find the sensitivity to it"
                ))
            })?;
            let delta = if value == 0.0 {
                ABSOLUTE_STEP
            } else {
                RELATIVE_STEP * value.abs()
            };
            let model_at = |v: f64| -> Result<Model, LabError> {
                Ok(Model::from_mesh(
                    &params::set(scene, name, v)?,
                    mesh.clone(),
                )?)
            };
            let plus = model_at(value + delta)?;
            // At a lower bound (a friction or a stiffening of 0) the step goes forward only.
            let (minus, span) = match model_at(value - delta) {
                Ok(m) => (m, 2.0 * delta),
                Err(LabError::Input(_)) => (model_at(value)?, delta),
                Err(e) => return Err(e),
            };
            steps.push(ParameterStep { span, minus, plus });
            found.push((param.name, value));
        }
        Ok(ParameterSteps { steps, found })
    }

    /// `dx/dp` at `sim`'s state, an equilibrium on the steps' mesh.
    pub fn solve(
        &self,
        sim: &Simulation,
        options: SensitivityOptions,
    ) -> Result<Vec<ParameterSensitivity>, LabError> {
        let solved = sim.sensitivity(&self.steps, options)?;
        Ok(self
            .found
            .iter()
            .zip(solved)
            .map(|(&(name, value), s)| ParameterSensitivity {
                name,
                value,
                dx_dp: s.dx_dp,
                iterations: s.report.iterations,
            })
            .collect())
    }
}

/// The parameters whose sensitivities are checked against finite differences of whole
/// equilibria (`tests/it/sensitivity.rs` takes its list from here); fits take the others'
/// Jacobian by differences.
pub const WITH_SENSITIVITY: &[&str] = &[
    "young_modulus",
    "alpha",
    "bulk_modulus",
    "stiffening",
    "tau_s",
    "tau_c",
    "friction",
    "stiffening_cubic",
    "softening",
    "prony_g",
    "region_young_modulus",
    "table_friction",
    "guide_friction",
];

/// How the equilibria's sensitivities are solved in a replay: to a percent, what a fit's step
/// needs (`softgrip_core::sensitivity`). On the 4 mm thesis cuboid, four parameters' add 0.8 of
/// a replay's time at 1e-2, 1.3 to 2.3 at 1e-5 (`softgrip bench --statics`).
pub fn fit_sensitivity_options() -> SensitivityOptions {
    SensitivityOptions {
        tolerance: 1e-2,
        acceptable: 1e-2,
        cg_tolerance: 1e-2,
        ..SensitivityOptions::default()
    }
}

/// [`fit_sensitivity_options`] for an equilibrium of `model`: where its static tangent is the
/// continuum's exact one and factorised (`softgrip_core::step::linear::static_model`), one
/// back-substitution per parameter, without GMRES's check by force differences (the factor alone
/// agrees with whole solves to 1e-4: `tests/it/sensitivity.rs`); elsewhere checked.
pub fn fit_sensitivity_options_for(model: &Model) -> SensitivityOptions {
    let unknowns = 3 * model.fixed.iter().filter(|f| !**f).count();
    let factorised =
        unknowns <= softgrip_core::equilibrium::DIRECT_UNKNOWNS && model.self_collision.is_none();
    SensitivityOptions {
        exact: !(factorised && model.fem.is_some()),
        ..fit_sensitivity_options()
    }
}

/// A replay with the markers' sensitivities to `names` at each load's equilibrium, solved as
/// [`fit_sensitivity_options`] says (the stick/slip state held). `None` where they cannot be had
/// (see [`replay_observing`], and for `warm`).
pub fn replay_with_sensitivities(
    recording: &Recording,
    scene: &Scene,
    options: ReplayOptions,
    warm: Option<&[SampleState]>,
    names: &[&str],
    progress: impl FnMut(usize),
) -> Result<(Replay, Option<MarkerSensitivities>), SimError> {
    let targets: Vec<(&Scene, &str)> = names.iter().map(|n| (scene, *n)).collect();
    let mut steps: Option<ParameterSteps> = None;
    let mut at = |sim: &Simulation, mesh: &TetMesh| -> Option<Vec<Vec<DVec3>>> {
        if steps.is_none() {
            steps = Some(ParameterSteps::new(&targets, mesh).ok()?);
        }
        let solved = steps
            .as_ref()?
            .solve(sim, fit_sensitivity_options_for(&sim.model))
            .ok()?;
        Some(solved.into_iter().map(|s| s.dx_dp).collect())
    };
    replay_observing(recording, scene, options, warm, Some(&mut at), progress)
}
