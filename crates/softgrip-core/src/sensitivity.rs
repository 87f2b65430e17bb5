//! Sensitivities of a static equilibrium to the model's parameters: at an equilibrium
//! `f(x, p) = 0`, `dx/dp = (-df/dx)^-1 df/dp` on the free components.
//!
//! `df/dp` is a central difference of the force at the equilibrium held fixed, between models
//! built with `p - delta` and `p + delta` on the same mesh (no re-solve). The solve with
//! `-df/dx` is flexible GMRES whose products are central differences of the force along the
//! vector ([`SensitivityOptions::probe`]), right-preconditioned by CG on the tangent the step
//! assembles ([`crate::step::linear`]): the assembled tangent leaves out terms (the volume
//! forces' and the contact's geometric stiffness, a sliding contact's), which the products
//! have. Contacts, stick anchors and held fingers stay as at the equilibrium, sliding finger
//! contacts sliding; a table's slipping contacts stick (evaluated at rest). Method, what is
//! not covered and measured accuracy: `docs/design/equilibrium.md`, "Sensitivities".

use std::sync::Arc;

use glam::DVec3;

use crate::equilibrium::load_scale;
use crate::error::SimError;
use crate::model::Model;
use crate::solver::cg::{CgError, CgParams};
use crate::solver::gmres::{GmresError, GmresParams, GmresReport, flexible_gmres};
use crate::step::Simulation;
use crate::step::linear::{FixedState, static_model};

/// The state is an equilibrium when the force left on it is at most this share of the load
/// ([`load_scale`]): the static solver's default tolerance is 1e-6.
pub const AT_EQUILIBRIUM: f64 = 1e-4;

/// One parameter: the model at a value below and at one above `p` (on the simulation's mesh),
/// and `span`, the second value less the first: `df/dp = (f(plus) - f(minus)) / span`. Central
/// (`p - delta`, `p + delta`) where the parameter allows, forward at a bound (`p`, `p + delta`).
#[derive(Debug, Clone)]
pub struct ParameterStep {
    /// The parameter's value in `plus` less its value in `minus`, in the parameter's unit.
    pub span: f64,
    /// The model at the lower value.
    pub minus: Model,
    /// The model at the higher value.
    pub plus: Model,
}

/// How the sensitivities are solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensitivityOptions {
    /// GMRES stops at this relative residual of `-df/dx y = df/dp` ...
    pub tolerance: f64,
    /// ... or, where the force differences' rounding stops it earlier (at 5e-9 on the thesis
    /// cuboid's 4 mm mesh), at this one.
    pub acceptable: f64,
    /// GMRES products at most, per parameter.
    pub max_iterations: usize,
    /// Krylov vectors before a restart.
    pub restart: usize,
    /// The preconditioner's CG tolerance (relative).
    pub cg_tolerance: f64,
    /// The preconditioner's CG iterations at most, per application.
    pub cg_max_iterations: usize,
    /// The largest move of a point in a product's force difference, in edge lengths: small
    /// enough to cross no kink of the force (a limit spring's start, a contact's edge), large
    /// enough that rounding stays below the tolerance (at 1e-6 GMRES stalled near 1e-8).
    pub probe: f64,
    /// False: CG on the assembled tangent alone (its terms left out stay out).
    pub exact: bool,
}

impl Default for SensitivityOptions {
    fn default() -> Self {
        SensitivityOptions {
            tolerance: 1e-9,
            acceptable: 1e-6,
            max_iterations: 200,
            restart: 40,
            cg_tolerance: 1e-10,
            cg_max_iterations: 20_000,
            probe: 1e-5,
            exact: true,
        }
    }
}

/// The sensitivity to one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    /// `dx/dp` (m per unit of p), particles then fingers; zero on fixed components.
    pub dx_dp: Vec<DVec3>,
    /// `df/dp` at the equilibrium (N per unit of p), masked.
    pub df_dp: Vec<DVec3>,
    /// The solve: GMRES products (CG solves with `exact = false`: 1) and residual.
    pub report: GmresReport,
}

impl Simulation {
    /// `dx/dp` at the present state, an equilibrium (see the module docs), for each
    /// parameter step. The state is not changed.
    pub fn sensitivity(
        &self,
        steps: &[ParameterStep],
        options: SensitivityOptions,
    ) -> Result<Vec<Sensitivity>, SimError> {
        let mut fixed = self.fixed_state();
        let load = load_scale(&self.model, &self.state);
        if fixed.residual() > AT_EQUILIBRIUM * load {
            return Err(SimError::NoSensitivity {
                why: format!(
                    "the state is not an equilibrium (a force of {:.3e} N is left against a \
                     load of {load:.3e} N); solve it first (Simulation::equilibrium)",
                    fixed.residual()
                ),
            });
        }
        let solved = steps
            .iter()
            .map(|step| sensitivity_to(&mut fixed, step, options))
            .collect();
        self.keep_solver(fixed);
        solved
    }
}

/// `dx/dp` for one parameter step: `df/dp` by a central difference of the force, then the
/// solve with `-df/dx` (CG on the assembled tangent with `exact = false`, else GMRES).
fn sensitivity_to(
    fixed: &mut FixedState,
    step: &ParameterStep,
    o: SensitivityOptions,
) -> Result<Sensitivity, SimError> {
    let df_dp = force_derivative(fixed, step);
    let cg = CgParams {
        tolerance: o.cg_tolerance,
        reference: 0.0,
        max_iterations: o.cg_max_iterations,
    };
    let mut dx_dp = Vec::new();
    if !o.exact {
        fixed
            .solve(&df_dp, &mut dx_dp, cg)
            .map_err(|e| tangent_failed(&e))?;
        return Ok(Sensitivity {
            dx_dp,
            df_dp,
            report: GmresReport {
                iterations: 1,
                relative_residual: 0.0,
            },
        });
    }
    let report = solve_exact(fixed, &df_dp, &mut dx_dp, cg, o)?;
    Ok(Sensitivity {
        dx_dp,
        df_dp,
        report,
    })
}

/// `df/dp` at the equilibrium held fixed: the force on the step's `plus` model less that on
/// its `minus` model, over the span.
fn force_derivative(fixed: &mut FixedState, step: &ParameterStep) -> Vec<DVec3> {
    let minus = Arc::new(static_model(&step.minus));
    let plus = Arc::new(static_model(&step.plus));
    let (f_minus, f_plus) = (fixed.force(&minus, None), fixed.force(&plus, None));
    f_plus
        .iter()
        .zip(&f_minus)
        .map(|(p, m)| (*p - *m) / step.span)
        .collect()
}

/// Solves `-df/dx dx_dp = df_dp` by flexible GMRES on central differences of the force,
/// preconditioned by CG on the assembled tangent.
fn solve_exact(
    fixed: &mut FixedState,
    df_dp: &[DVec3],
    dx_dp: &mut Vec<DVec3>,
    cg: CgParams,
    o: SensitivityOptions,
) -> Result<GmresReport, SimError> {
    let model = Arc::clone(fixed.model());
    let probe = o.probe * model.edge_length;
    let fixed = std::cell::RefCell::new(fixed);
    // -df/dx v by a central difference of the force along v.
    let apply = |v: &[DVec3], out: &mut Vec<DVec3>| -> Result<(), SimError> {
        let largest = v.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max);
        out.clear();
        if largest == 0.0 {
            out.resize(v.len(), DVec3::ZERO);
            return Ok(());
        }
        let h = probe / largest;
        let mut f = fixed.borrow_mut();
        let ahead = f.force(&model, Some((v, h)));
        let behind = f.force(&model, Some((v, -h)));
        out.extend(
            ahead
                .iter()
                .zip(&behind)
                .map(|(a, b)| (*b - *a) / (2.0 * h)),
        );
        Ok(())
    };
    let precondition = |r: &[DVec3], z: &mut Vec<DVec3>| -> Result<(), SimError> {
        z.clear();
        fixed
            .borrow_mut()
            .solve(r, z, cg)
            .map(|_| ())
            .map_err(|e| tangent_failed(&e))
    };
    let params = GmresParams {
        tolerance: o.tolerance,
        max_iterations: o.max_iterations,
        restart: o.restart,
    };
    dx_dp.resize(df_dp.len(), DVec3::ZERO);
    gmres_outcome(
        flexible_gmres(apply, precondition, df_dp, dx_dp, params),
        o.acceptable,
    )
}

/// GMRES's report, also when it stopped short of its tolerance at a residual of at most
/// `acceptable`; otherwise the error.
fn gmres_outcome(
    result: Result<GmresReport, GmresError<SimError>>,
    acceptable: f64,
) -> Result<GmresReport, SimError> {
    match result {
        Ok(report) => Ok(report),
        Err(GmresError::Operator(e)) => Err(e),
        Err(GmresError::NoConvergence {
            iterations,
            residual,
        }) if residual <= acceptable => Ok(GmresReport {
            iterations,
            relative_residual: residual,
        }),
        Err(GmresError::NoConvergence {
            iterations,
            residual,
        }) => Err(SimError::NoSensitivity {
            why: format!(
                "GMRES on the static tangent left a relative residual of {residual:.1e} \
                 after {iterations} products"
            ),
        }),
    }
}

fn tangent_failed(e: &CgError) -> SimError {
    SimError::NoSensitivity {
        why: format!(
            "CG on the assembled static tangent failed ({e}); the equilibrium may be at a \
             buckling load, where the tangent is singular"
        ),
    }
}
