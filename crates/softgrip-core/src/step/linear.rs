//! The step's force and matrix at a state held fixed, for the sensitivities of a static
//! equilibrium (`crate::sensitivity`): the free force, and solves with the static tangent
//! `-df/dx` the step assembles. Nothing here changes the simulation: the force stages run on a
//! copy of the state, so contacts, stick anchors and held fingers stay as they are (a table's
//! slipping contacts, evaluated at rest, stick).
//!
//! The static tangent is the step's matrix `A = M + dt Dp + dt^2 Kp` for a step so long
//! ([`STATIC_DT`]) that `M / dt^2` and `Dp / dt` vanish next to `Kp`, with the exact spring
//! tangent ([`Model::exact_tangent`]): `A y = dt^2 g` is `Kp y = g`. The method, what is held
//! fixed and its accuracy: `docs/design/equilibrium.md`, "Sensitivities".

use std::sync::Arc;

use glam::DVec3;

use super::parallel::SystemOperator;
use super::{Scratch, Simulation, assemble};
use crate::error::SimError;
use crate::model::{LinearSolver, Model};
use crate::solver::cg::{CgError, CgParams, CgReport, CgScratch, conjugate_gradient};
use crate::solver::direct::DirectSolver;
use crate::state::State;

/// The pseudo time step (s) of the static tangent: past every mode's period by so much that
/// `M / dt^2` and `Dp / dt` are about 1e-8 of the stiffness on the thesis scenes (a light
/// guide's damping `|F| / guide_speed` the most). The sensitivities' products have no shift.
pub const STATIC_DT: f64 = 1e6;

/// A finger contact whose tangential force is within this share of `mu F_n` is sliding: at a
/// converged equilibrium a sliding contact's force is on the edge to about 1e-9, a sticking
/// one's well inside.
pub const CONE_EDGE: f64 = 1e-6;

/// A guided finger whose driving force is within this share of its guide's friction `F_g`
/// slides in its guide (at a sliding equilibrium the force is `F_g` to the solver's tolerance).
pub const GUIDE_EDGE: f64 = 1e-4;

/// CG's relative tolerance of [`Simulation::solve_tangent`].
pub const TANGENT_CG_TOLERANCE: f64 = 1e-12;

/// `model` as the static tangent sees it: a step of [`STATIC_DT`], the exact tangent (the
/// whole of it, [`Model::full_tangent`]), the static solver's friction (a return mapping to
/// anchors held), and a factorised solve where the mesh is small enough
/// ([`crate::solver::direct::DIRECT_UNKNOWNS`]) and has no self-collision.
pub fn static_model(model: &Model) -> Model {
    let mut m = model.clone();
    m.dt = STATIC_DT;
    m.exact_tangent = true;
    m.full_tangent = true;
    m.quasi_static = true;
    let unknowns = 3 * m.fixed.iter().filter(|f| !**f).count();
    if unknowns <= crate::solver::direct::DIRECT_UNKNOWNS && m.self_collision.is_none() {
        m.linear_solver = crate::model::LinearSolver::Direct;
    }
    m
}

/// A state held fixed, at rest, with the static tangent of one model assembled at it.
#[derive(Debug)]
pub struct FixedState {
    model: Arc<Model>,
    state: State,
    /// Holds the tangent's system, assembled once.
    tangent: Scratch,
    /// For the force evaluations, which overwrite their system.
    forces: Scratch,
    work: State,
    /// Each finger sliding in its guide: the direction of the force that drives the slide (the
    /// guide's friction, `F_g` against it, is part of the force here).
    guide_slides: Vec<Option<DVec3>>,
    cg: CgScratch,
    /// The tangent's factorisation, where the model asks for one and it is positive definite.
    direct: Option<DirectSolver>,
    /// The static residual at the state (N, `super::static_residual`).
    residual: f64,
}

impl FixedState {
    /// Holds `state` (velocities set to zero) and assembles the tangent of `model` (a
    /// [`static_model`]) there.
    pub fn new(model: Arc<Model>, state: &State) -> FixedState {
        FixedState::reusing(model, state, None)
    }

    /// As [`FixedState::new`], factorising with `solver` where the model asks for a factor: its
    /// symbolic analysis is kept while the tangent's pattern fits it (one simulation's loads).
    pub fn reusing(model: Arc<Model>, state: &State, solver: Option<DirectSolver>) -> FixedState {
        let mut state = state.clone();
        state.velocities.fill(DVec3::ZERO);
        for f in &mut state.fingers {
            f.velocity = DVec3::ZERO;
        }
        let mut fixed = FixedState {
            model,
            work: state.clone(),
            state,
            tangent: Scratch::default(),
            forces: Scratch::default(),
            guide_slides: Vec::new(),
            cg: CgScratch::default(),
            direct: None,
            residual: 0.0,
        };
        fixed.residual = assemble(&fixed.model, &mut fixed.work, &mut fixed.tangent);
        fixed.hold_sliding_contacts();
        fixed.hold_sliding_table();
        fixed.hold_guided_fingers();
        if fixed.guide_slides.iter().any(Option::is_some) {
            // A finger sliding in its guide feels `F_g` along the slide, a force that does not
            // change as it moves: the guide's friction damper (a time step's) leaves the
            // tangent.
            let mut m = (*fixed.model).clone();
            for (f, slide) in m.fingers.iter_mut().zip(&fixed.guide_slides) {
                if slide.is_some() {
                    f.guide_friction = 0.0;
                }
            }
            fixed.model = Arc::new(m);
        }
        // The tangent of the state as held: sliding contacts on the cone's edge, fingers held
        // by their guides masked out.
        fixed.work.clone_from(&fixed.state);
        assemble(&fixed.model, &mut fixed.work, &mut fixed.tangent);
        if fixed.model.linear_solver == LinearSolver::Direct {
            let mut direct = solver.unwrap_or_default();
            let factorised = system_of(&fixed.tangent, |s| {
                direct.factorise(&fixed.model, s).is_ok()
            });
            if factorised {
                fixed.direct = Some(direct);
            } else {
                // Not positive definite (a frictionless contact on a lattice with no volume
                // term): CG on the time steps' semi-definite tangent preconditions instead.
                let mut m = (*fixed.model).clone();
                m.full_tangent = false;
                m.linear_solver = LinearSolver::Cg;
                fixed.model = Arc::new(m);
                fixed.work.clone_from(&fixed.state);
                assemble(&fixed.model, &mut fixed.work, &mut fixed.tangent);
            }
        }
        fixed
    }

    /// The factorisation, to be reused by the next state held on the same mesh.
    pub fn into_solver(self) -> Option<DirectSolver> {
        self.direct
    }

    /// Whether the tangent is factorised ([`FixedState::solve`] is then exact to rounding).
    pub fn is_factorised(&self) -> bool {
        self.direct.is_some()
    }

    /// `Kp v` with the assembled tangent (factorised models only: `None` otherwise): what
    /// [`FixedState::solve`] inverts.
    pub fn tangent_product(&self, v: &[DVec3]) -> Option<Vec<DVec3>> {
        let direct = self.direct.as_ref()?;
        let dt2 = self.model.dt * self.model.dt;
        let mut out = vec![DVec3::ZERO; v.len()];
        system_of(&self.tangent, |s| direct.apply(s, v, &mut out));
        Some(out.into_iter().map(|x| x / dt2).collect())
    }

    /// Marks the finger contacts on their friction cone's edge as held sliding: at a sliding
    /// equilibrium they sit on the edge, and a force difference across it would mix the stick
    /// and the slip branch.
    fn hold_sliding_contacts(&mut self) {
        for c in &self.work.contacts {
            let mu = self.model.fingers[c.finger as usize].friction;
            let limit = mu * c.normal_force;
            if limit > 0.0
                && c.tangential_force.length() >= (1.0 - CONE_EDGE) * limit
                && let Some(m) = self.state.contact_memory.get_mut(&(c.finger, c.facet))
            {
                m.sliding = true;
                // The anchor where the last static increment held it: the linearisation is
                // that increment's.
                m.anchor_offset -= m.dragged;
            }
        }
    }

    /// Marks the table contacts on (or within [`CONE_EDGE`] of) their Coulomb disc's edge as held
    /// sliding, as [`FixedState::hold_sliding_contacts`] does the fingers'.
    fn hold_sliding_table(&mut self) {
        let Some(table) = &self.model.table else {
            return;
        };
        let k = table.stiffness;
        for (c, &p) in self.state.table.iter_mut().zip(&table.particles) {
            let x = self.state.positions[p as usize];
            if c.mode == crate::state::TableMode::Free || x.z >= 0.0 {
                continue;
            }
            let limit = table.friction * k * (-x.z);
            let trial = k * (x * DVec3::new(1.0, 1.0, 0.0) - c.anchor).length();
            if limit > 0.0 && trial >= (1.0 - CONE_EDGE) * limit {
                c.sliding = true;
                // The anchor where the increment held it: the linearisation is the
                // increment's.
                c.anchor -= c.dragged;
            }
        }
    }

    /// A force-controlled finger with guide friction either slides in its guide (the force on
    /// its axes is `F_g`: the guide's friction joins the force, against that direction) or is
    /// held by it (the force is less: held where it is, its axes fixed).
    fn hold_guided_fingers(&mut self) {
        let n = self.model.particle_count();
        self.guide_slides = vec![None; self.model.fingers.len()];
        for (k, f) in self.model.fingers.iter().enumerate() {
            if !f.is_force_controlled() || self.state.fingers[k].held.is_some() {
                continue;
            }
            let axes = DVec3::from_array(f.drive.map(|d| {
                if d == crate::model::AxisDrive::Force {
                    1.0
                } else {
                    0.0
                }
            }));
            let net = self.tangent.force[n + k] * axes;
            let moved = self.state.fingers[k].last_move * axes;
            if f.guide_friction > 0.0 && net.length() >= (1.0 - GUIDE_EDGE) * f.guide_friction {
                self.guide_slides[k] = Some(net.normalize());
            } else if f.guide_friction > 0.0 {
                self.state.fingers[k].held = Some(self.state.fingers[k].position);
            } else if moved != DVec3::ZERO {
                // Without guide friction the finger slid where the last increment moved it: a
                // friction from 0 up opposes that slide (its derivative at 0, the load-loss
                // candidate's null).
                self.guide_slides[k] = Some(moved.normalize());
            }
        }
    }

    /// The finger contacts held sliding (finger, facet).
    pub fn sliding_contacts(&self) -> Vec<(u32, u32)> {
        let memory = &self.state.contact_memory;
        memory
            .iter()
            .filter(|(_, m)| m.sliding)
            .map(|(k, _)| *k)
            .collect()
    }

    /// The model whose tangent is assembled.
    pub fn model(&self) -> &Arc<Model> {
        &self.model
    }

    /// The state held (at rest).
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The 2-norm of the force on the free components there (N), less what the fingers'
    /// guides hold: zero at an equilibrium.
    pub fn residual(&self) -> f64 {
        self.residual
    }

    /// 1 on the free components, 0 on the fixed ones (particles then fingers).
    pub fn mask(&self) -> Vec<DVec3> {
        system_of(&self.tangent, |s| s.mask.clone())
    }

    /// The masked force of `model` (on the same mesh) at the held state, its particles and
    /// fingers moved by `scale` times `displacement` (particles then fingers) if given.
    pub fn force(
        &mut self,
        model: &Arc<Model>,
        displacement: Option<(&[DVec3], f64)>,
    ) -> Vec<DVec3> {
        self.work.clone_from(&self.state);
        if let Some((d, scale)) = displacement {
            let n = self.work.positions.len();
            for (x, d) in self.work.positions.iter_mut().zip(d) {
                *x += scale * *d;
            }
            for (f, d) in self.work.fingers.iter_mut().zip(&d[n..]) {
                f.position += scale * *d;
            }
        }
        assemble(model, &mut self.work, &mut self.forces);
        let n = model.particle_count();
        for (k, slide) in self.guide_slides.iter().enumerate() {
            if let Some(direction) = slide {
                self.forces.force[n + k] -= *direction * model.fingers[k].guide_friction;
            }
        }
        let force = &self.forces.force;
        system_of(&self.forces, |s| {
            force.iter().zip(&s.mask).map(|(f, m)| *f * *m).collect()
        })
    }

    /// `y` with `Kp y = g` on the free components (zero on the fixed ones): by the
    /// factorisation where there is one, else by CG on the assembled tangent from the start `y`
    /// holds (zero if its length is wrong).
    pub fn solve(
        &mut self,
        g: &[DVec3],
        y: &mut Vec<DVec3>,
        params: CgParams,
    ) -> Result<CgReport, CgError> {
        let Some(parallel) = self.tangent.parallel.as_ref() else {
            unreachable!("assemble sets it")
        };
        let system = parallel.system();
        if y.len() != g.len() {
            y.clear();
            y.resize(g.len(), DVec3::ZERO);
        }
        for (y, m) in y.iter_mut().zip(&system.mask) {
            *y *= *m;
        }
        let dt2 = self.model.dt * self.model.dt;
        let rhs: Vec<DVec3> = g
            .iter()
            .zip(&system.mask)
            .map(|(g, m)| *g * *m * dt2)
            .collect();
        if let Some(direct) = self.direct.as_mut() {
            let iterations = direct.solve_system(&system, &rhs, y).unwrap_or(0);
            return Ok(CgReport {
                iterations,
                relative_residual: 0.0,
            });
        }
        let op = SystemOperator {
            system: &system,
            parallel,
        };
        conjugate_gradient(&op, &rhs, y, params, &mut self.cg)
    }
}

/// `read` of the system a [`Scratch`] assembled.
fn system_of<T>(scratch: &Scratch, read: impl FnOnce(&crate::solver::System) -> T) -> T {
    let Some(parallel) = scratch.parallel.as_ref() else {
        unreachable!("assemble sets it")
    };
    read(&parallel.system())
}

impl Simulation {
    /// The present state held fixed, with the [`static_model`] of the simulation's model (and
    /// the factorisation the last one left, [`Simulation::keep_solver`]).
    pub fn fixed_state(&self) -> FixedState {
        let solver = self.tangent_solver.take();
        FixedState::reusing(Arc::new(static_model(&self.model)), &self.state, solver)
    }

    /// Keeps `fixed`'s factorisation for the next [`Simulation::fixed_state`].
    pub fn keep_solver(&self, fixed: FixedState) {
        if let Some(solver) = fixed.into_solver() {
            self.tangent_solver.keep(solver);
        }
    }

    /// The force at the present state (N, particles then fingers), zero on the fixed
    /// components: what the next step would start from, its fingers not driven. The state
    /// is not changed.
    pub fn free_force(&mut self) -> Vec<DVec3> {
        let mut state = self.state.clone();
        assemble(&self.model, &mut state, &mut self.scratch);
        let force = &self.scratch.force;
        system_of(&self.scratch, |s| {
            force.iter().zip(&s.mask).map(|(f, m)| *f * *m).collect()
        })
    }

    /// `y` with `Kp y = g` on the free components, `Kp = -df/dx` the static tangent the step
    /// assembles at the present state, held at rest (see the module docs); CG to
    /// [`TANGENT_CG_TOLERANCE`] in at most `max_iterations`. The state is not changed.
    pub fn solve_tangent(
        &self,
        g: &[DVec3],
        max_iterations: usize,
    ) -> Result<Vec<DVec3>, SimError> {
        let mut fixed = self.fixed_state();
        let mut y = Vec::new();
        let params = CgParams {
            tolerance: TANGENT_CG_TOLERANCE,
            reference: 0.0,
            max_iterations,
        };
        fixed
            .solve(g, &mut y, params)
            .map_err(|e| SimError::NoSensitivity {
                why: format!("the static tangent's solve failed: {e}"),
            })?;
        Ok(y)
    }
}
