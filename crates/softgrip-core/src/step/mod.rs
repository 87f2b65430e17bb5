//! One time step, in the order of thesis Fig. 9: forces, contact, volume,
//! integrate, constraints; then the diagnostics and the divergence check.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use crate::error::SimError;
use crate::model::Model;
use crate::scene::Scene;
use crate::solver::cg::{CgError, CgScratch};
use crate::solver::direct::DirectSolver;
use crate::state::State;
use crate::{contact, forces};
use constraints::{ProjectionScratch, project_spring_limits};
use parallel::Parallel;

pub mod adaptive;
pub mod assemble;
pub mod constraints;
pub mod integrate;
pub mod linear;
pub mod parallel;

/// Scratch memory of a step: allocated once, reused every step.
#[derive(Debug, Default)]
pub struct Scratch {
    force: Vec<DVec3>,
    /// The system matrix lives here, shared with the helper thread.
    parallel: Option<Parallel>,
    /// Threads to use (1 or 2); 0 = 2 while a core is free (see
    /// `Simulation::set_threads`).
    threads: usize,
    rhs: Vec<DVec3>,
    dv: Vec<DVec3>,
    cg: CgScratch,
    /// The sparse factorisation of a direct solve ([`crate::model::LinearSolver::Direct`]).
    direct: DirectSolver,
    /// The force stages' buffers and timings (main thread).
    stages: assemble::StageScratch,
    projection: ProjectionScratch,
    energy_watch: EnergyWatch,
    stage_seconds: StageSeconds,
    /// The last step's linear solve failed on a matrix that is not positive definite.
    indefinite: bool,
}

impl Clone for Scratch {
    /// Buffers are copied; the clone starts its own helper thread on its
    /// first step.
    fn clone(&self) -> Scratch {
        Scratch {
            force: self.force.clone(),
            parallel: None,
            threads: self.threads,
            rhs: self.rhs.clone(),
            dv: self.dv.clone(),
            cg: self.cg.clone(),
            direct: self.direct.clone(),
            stages: self.stages.clone(),
            projection: self.projection.clone(),
            energy_watch: self.energy_watch.clone(),
            stage_seconds: self.stage_seconds,
            indefinite: self.indefinite,
        }
    }
}

/// How often (in steps) a simulation on the default thread count looks
/// again at whether to take or give up a helper (see
/// [`Scratch::ensure_parallel`]): a look is two atomic loads, a change a
/// thread start or stop (~0.1 ms), a step ~1 ms.
const HELPER_LOOK_STEPS: u64 = 32;

impl Scratch {
    /// Starts the work split for `model` on first use, and again when the
    /// model changes. On the default thread count (0) the split follows
    /// the machine: a simulation takes the helper when a core is free and
    /// gives it up when another simulation wants the core (a fit's probes
    /// run side by side, one per core, and the last one left takes both).
    /// Results are the same bit for bit either way.
    fn ensure_parallel(&mut self, model: &Arc<Model>, step: u64) {
        let stale = self
            .parallel
            .as_ref()
            .is_none_or(|p| !Arc::ptr_eq(p.model(), model));
        let threads = match self.threads {
            0 => parallel::cores().min(2),
            n => n,
        };
        let rethink = self.threads == 0
            && threads >= 2
            && step.is_multiple_of(HELPER_LOOK_STEPS)
            && self.parallel.as_ref().is_some_and(|p| {
                if p.is_threaded() {
                    parallel::oversubscribed()
                } else {
                    parallel::helper_available()
                }
            });
        if stale || rethink {
            // The system (and the preconditioner it keeps over steps, its factorisations) goes
            // on where the mesh is the same: a step control that changes dt swaps models every
            // step (`adaptive`), and each new nodal-pressure factorisation cost a third of it.
            let kept = self.parallel.take().and_then(|p| {
                let same_mesh = p.model().tets.len() == model.tets.len()
                    && p.model().springs.len() == model.springs.len();
                same_mesh.then(|| std::mem::take(&mut *p.system_mut()))
            });
            let parallel = Parallel::new(Arc::clone(model), threads);
            if let Some(system) = kept {
                *parallel.system_mut() = system;
            }
            self.parallel = Some(parallel);
        }
    }
}

/// Wall-clock seconds spent in each stage of [`step`], summed over the steps
/// (MuJoCo's stage timers). Not part of the state: timings differ from run to
/// run, the physics does not.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct StageSeconds {
    /// Every force and its blocks: springs (eq. 3-4), gravity, loads, finger
    /// drive, contact (eq. 5, 18-39), volume (eq. 10-12), the bulk term, Rayleigh damping,
    /// both threads' shares added, and the preconditioner.
    pub forces: f64,
    /// The implicit-Euler solve (eq. 43) and the update.
    pub solve: f64,
    /// The spring-limit projection (Alg. 3).
    pub projection: f64,
    /// The viscoelastic state's update after the step: the springs' and the elements' Prony
    /// arms relax towards the new strain.
    pub arms: f64,
    /// Energy, volume error, speeds and the divergence checks.
    pub diagnostics: f64,
    /// The force stages one by one, summed over both threads (indexed as
    /// [`assemble::Stage::ALL`]): parts of `forces`, which also holds the wait for the helper
    /// and the preconditioner.
    pub stages: [f64; assemble::Stage::ALL.len()],
}

/// Adds the time since `*mark` to `slot` and moves the mark.
#[inline]
fn lap(mark: &mut Instant, slot: &mut f64) {
    let now = Instant::now();
    *slot += (now - *mark).as_secs_f64();
    *mark = now;
}

/// Steps in a row of rising energy, without input, that count as divergence
/// (together with [`ENERGY_GROWTH`]).
pub const ENERGY_RISING_STEPS: u32 = 100;
/// Relative growth over those steps that counts as divergence.
pub const ENERGY_GROWTH: f64 = 0.1;

/// Watches the total energy for growth without input. The model is
/// dissipative (dampers, Hunt-Crossley, implicit Euler), so with no work put
/// in by a moving velocity-driven finger or a changed load, the energy can
/// only wander by the spring-limit projection's corrections; a steady rise
/// over [`ENERGY_RISING_STEPS`] steps is an instability.
#[derive(Debug, Default, Clone)]
struct EnergyWatch {
    rising: u32,
    start: f64,
    last: f64,
    loads: Vec<DVec3>,
}

/// A model, its state and the scratch memory: everything a run needs.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// Shared with the helper thread ([`parallel`]); replace it
    /// whole to change it.
    pub model: Arc<Model>,
    /// Positions, velocities, fingers, contacts: what a step changes.
    pub state: State,
    scratch: Scratch,
    /// Wall-clock seconds spent in `step` so far.
    pub wall_seconds: f64,
    /// The static tangent's factorisation between states held fixed.
    tangent_solver: crate::solver::direct::KeptSolver,
}

impl Simulation {
    /// Meshes the scene, builds the model and checks the start state.
    pub fn new(scene: &Scene) -> Result<Simulation, SimError> {
        Simulation::on_mesh(scene, Model::mesh_of(scene)?)
    }

    /// As [`Simulation::new`], on a mesh already made for `scene`.
    pub fn on_mesh(scene: &Scene, mesh: crate::mesh::TetMesh) -> Result<Simulation, SimError> {
        let sim = Simulation::from_model(Model::from_mesh(scene, mesh)?);
        sim.check_fingers_outside(scene)?;
        Ok(sim)
    }

    /// A simulation of `model` from its initial state (at rest, at the mesh's positions).
    pub fn from_model(model: Model) -> Simulation {
        let state = State::initial(&model);
        Simulation {
            model: Arc::new(model),
            state,
            scratch: Scratch::default(),
            wall_seconds: 0.0,
            tangent_solver: crate::solver::direct::KeptSolver::default(),
        }
    }

    /// A finger that starts inside the object would be shot out by the contact.
    fn check_fingers_outside(&self, scene: &Scene) -> Result<(), SimError> {
        let file = scene
            .source
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_else(|| "scene".into());
        // The object's own bounds catch a finger buried past its facets.
        let (lo, hi) = crate::mesh::bounds_of(&self.model.rest_positions);
        for (k, fs) in self.state.fingers.iter().enumerate() {
            let deepest = self
                .model
                .facets
                .iter()
                .filter_map(|tri| {
                    contact::detect(
                        &self.model,
                        k,
                        fs.position,
                        tri.map(|i| self.state.positions[i as usize]),
                    )
                })
                .map(|g| g.penetration)
                .fold(0.0, f64::max);
            let centre_inside = fs.position.cmpgt(lo).all() && fs.position.cmplt(hi).all();
            if deepest > 1e-9 || centre_inside {
                let reach = self.model.fingers[k].shape.reach();
                // A buried centre is at least its height below the top inside.
                let buried = if centre_inside {
                    hi.z - fs.position.z + reach
                } else {
                    0.0
                };
                return Err(SimError::FingerStartsInside {
                    file,
                    index: k + 1,
                    depth_mm: deepest.max(buried) * 1e3,
                    position: fs.position.to_array(),
                    suggest_z: hi.z + reach,
                });
            }
        }
        Ok(())
    }

    /// Advances one time step `dt`.
    pub fn step(&mut self) -> Result<(), SimError> {
        let started = Instant::now();
        let result = step(&self.model, &mut self.state, &mut self.scratch);
        self.wall_seconds += started.elapsed().as_secs_f64();
        result
    }

    /// Threads for the step: 1 (this thread only) or 2 (a helper takes
    /// half the work); 0 (the default) = 2 while the machine has a core
    /// free, 1 while other simulations in the process take the cores: a
    /// running simulation looks again every few steps, so the last of a
    /// batch run side by side takes the second core when the others end.
    /// The results are the same bit for bit whatever the count, and
    /// however it changes during a run.
    pub fn set_threads(&mut self, threads: usize) {
        self.scratch.threads = threads.min(2);
        self.scratch.parallel = None;
    }

    /// Whether a helper thread took part in the last step.
    pub fn is_threaded(&self) -> bool {
        self.scratch
            .parallel
            .as_ref()
            .is_some_and(|p| p.is_threaded())
    }

    /// The first half of [`Simulation::step`]: the fingers driven and every force and the
    /// system assembled at the present state (its contact records updated); returns the static
    /// residual there. [`Simulation::step_assembled`] goes on from it.
    pub(crate) fn assemble_here(&mut self) -> f64 {
        let started = Instant::now();
        integrate::drive_fingers(&self.model, &mut self.state);
        let residual = assemble(&self.model, &mut self.state, &mut self.scratch);
        self.scratch.stage_seconds.forces += started.elapsed().as_secs_f64();
        self.wall_seconds += started.elapsed().as_secs_f64();
        residual
    }

    /// The force on every unknown (particles, then fingers; N) that the step's stages
    /// ([`assemble`]) give at the present state, assembled on a copy of it: the state and what
    /// the stages keep in it (contacts, stick anchors) do not change.
    pub(crate) fn assembled_force(&self) -> Vec<DVec3> {
        let mut state = self.state.clone();
        let mut scratch = Scratch {
            threads: 1,
            stages: self.scratch.stages.clone(),
            ..Scratch::default()
        };
        assemble(&self.model, &mut state, &mut scratch);
        scratch.force
    }

    /// Where the last assembly's unbalanced force is largest: the position of the free particle
    /// it acts on (a stalled static solve names this place), or the object's first particle's
    /// before any assembly.
    pub(crate) fn most_unbalanced(&self) -> DVec3 {
        let n = self.model.particle_count();
        let Some(parallel) = self.scratch.parallel.as_ref() else {
            return self.state.positions.first().copied().unwrap_or(DVec3::ZERO);
        };
        let system = parallel.system();
        let worst = self.scratch.force[..n.min(self.scratch.force.len())]
            .iter()
            .zip(&system.mask)
            .map(|(f, m)| (*f * *m).length_squared())
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(i, _)| i);
        self.state
            .positions
            .get(worst)
            .copied()
            .unwrap_or(DVec3::ZERO)
    }

    /// The second half of [`Simulation::step`] after [`Simulation::assemble_here`].
    pub(crate) fn step_assembled(&mut self, force_residual: f64) -> Result<(), SimError> {
        let started = Instant::now();
        let result = step_assembled(
            &self.model,
            &mut self.state,
            &mut self.scratch,
            force_residual,
            started,
        );
        self.wall_seconds += started.elapsed().as_secs_f64();
        result
    }

    /// Whether the last step failed because its matrix is not positive definite (an indefinite
    /// tangent in a static solve).
    pub(crate) fn last_step_indefinite(&self) -> bool {
        self.scratch.indefinite
    }

    /// Wall-clock seconds per stage, summed over the steps so far.
    pub fn stage_seconds(&self) -> StageSeconds {
        StageSeconds {
            stages: self.scratch.stages.seconds,
            ..self.scratch.stage_seconds
        }
    }

    /// Steps until `time` (s) is reached.
    pub fn run_until(&mut self, time: f64) -> Result<(), SimError> {
        let cancel = crate::cancel::current();
        while self.state.time + 0.5 * self.model.dt < time {
            crate::cancel::check(cancel.as_ref())?;
            self.step()?;
        }
        Ok(())
    }
}

/// One step: the thesis's simulation loop body (Fig. 9).
pub fn step(model: &Arc<Model>, state: &mut State, s: &mut Scratch) -> Result<(), SimError> {
    let mut mark = Instant::now();
    integrate::drive_fingers(model, state);
    let force_residual = assemble(model, state, s);
    lap(&mut mark, &mut s.stage_seconds.forces);
    step_assembled(model, state, s, force_residual, mark)
}

/// The rest of [`step`] once its forces and matrix are assembled at `state` (whose static
/// residual is `force_residual`): the solve, the update, the constraints and the checks.
fn step_assembled(
    model: &Arc<Model>,
    state: &mut State,
    s: &mut Scratch,
    force_residual: f64,
    mut mark: Instant,
) -> Result<(), SimError> {
    let times = &mut s.stage_seconds;
    let Some(parallel) = s.parallel.as_ref() else {
        unreachable!("assemble sets it")
    };

    let report = match model.linear_solver {
        crate::model::LinearSolver::Cg => integrate::implicit_euler_update(
            model,
            state,
            &s.force,
            &parallel.system(),
            parallel,
            &mut s.rhs,
            &mut s.dv,
            &mut s.cg,
        ),
        crate::model::LinearSolver::Direct => integrate::implicit_euler_direct(
            model,
            state,
            &s.force,
            &parallel.system(),
            &mut s.direct,
            &mut s.rhs,
            &mut s.dv,
        ),
    };
    s.indefinite = matches!(report, Err(CgError::NotPositiveDefinite { .. }));
    let report = report.map_err(|e| match e {
        // A limit the scene set too low is no divergence, and no fault of dt.
        CgError::NoConvergence {
            iterations,
            residual,
        } if iterations < 100 => SimError::SolverLimit {
            time: state.time,
            step: state.step,
            iterations,
            residual,
        },
        e => diverged(model, state, cg_message(e)),
    })?;
    lap(&mut mark, &mut times.solve);
    let projection = project_spring_limits(model, state, &mut s.projection);
    lap(&mut mark, &mut times.projection);
    forces::springs::relax(model, state);
    forces::viscosity::relax_elements(model, state);
    lap(&mut mark, &mut times.arms);

    state.time += model.dt;
    state.step += 1;
    let st = &mut state.stats;
    st.cg_iterations = report.iterations;
    st.cg_residual = report.relative_residual;
    st.limit_violation = projection.violation;
    st.projection_sweeps = projection.sweeps;
    st.contacts = state.contacts.len();
    st.force_residual = force_residual;
    update_diagnostics(model, state);
    let checked = check_divergence(model, state)
        .and_then(|()| watch_energy(model, state, &mut s.energy_watch));
    lap(&mut mark, &mut times.diagnostics);
    checked
}

/// The forces of every stage into `s.force` (particles then fingers) and the system `A` of
/// eq. 43 with its mask into the work split's system, at `state`'s positions and velocities:
/// the stages of [`assemble::MAIN`] here while the helper runs [`assemble::HELPER`], whose sums
/// are added last. Updates what the force stages keep in `state` (contacts and their stick
/// anchors, table modes, the fingers' contact forces); returns [`static_residual`].
fn assemble(model: &Arc<Model>, state: &mut State, s: &mut Scratch) -> f64 {
    let n = model.particle_count();
    let total = n + model.fingers.len();
    s.force.clear();
    s.force.resize(total, DVec3::ZERO);
    s.ensure_parallel(model, state.step);
    let Some(parallel) = s.parallel.as_ref() else {
        unreachable!("ensure_parallel sets it")
    };
    parallel.start_assembly(state);
    let mut system = parallel.system_mut();
    system.begin(model, model.dt);
    integrate::set_mask(model, state, &mut system);
    let share = parallel.main_share();
    assemble::run(
        &assemble::MAIN,
        model,
        state,
        &mut s.force,
        &mut system,
        &share,
        &mut s.stages,
    );
    parallel.finish_assembly(&mut s.force, &mut system, &mut s.stages.seconds);
    system.finish(&model.tets, state.stats.cg_iterations);
    static_residual(model, state, &s.force, &system.mask)
}

/// The 2-norm of the force on the free components (N), less on each finger what its guide's
/// static friction can hold: the equilibrium residual of `crate::equilibrium` (whose
/// iterations start at rest, where the guide's friction, a damper, exerts no force).
fn static_residual(model: &Model, state: &State, force: &[DVec3], mask: &[DVec3]) -> f64 {
    let n = model.particle_count();
    let particles: f64 = force[..n]
        .iter()
        .zip(mask)
        .map(|(f, m)| (*f * *m).length_squared())
        .sum();
    let fingers: f64 = (0..model.fingers.len())
        .map(|k| {
            let f = (force[n + k] * mask[n + k]).length();
            let held = state.fingers[k]
                .held
                .is_none()
                .then_some(model.fingers[k].guide_friction);
            (f - held.unwrap_or(0.0)).max(0.0).powi(2)
        })
        .sum();
    (particles + fingers).sqrt()
}

fn watch_energy(model: &Model, state: &State, w: &mut EnergyWatch) -> Result<(), SimError> {
    let energy = state.stats.energy;
    let dragged = state.pull.is_some() || state.fingers.iter().any(|f| f.held.is_some());
    let driven = dragged
        || model.fingers.iter().zip(&state.fingers).any(|(f, fs)| {
            let stopped = f.travel.is_some_and(|t| fs.travelled >= t);
            !stopped
                && f.drive
                    .iter()
                    .any(|d| matches!(d, crate::model::AxisDrive::Velocity(v) if *v != 0.0))
        });
    let loads_changed = w.loads.len() != state.fingers.len()
        || w.loads
            .iter()
            .zip(&state.fingers)
            .any(|(l, fs)| *l != fs.applied_force);
    if driven || loads_changed || state.step <= 1 || energy <= w.last {
        w.rising = 0;
        w.start = energy;
        w.loads.clear();
        w.loads
            .extend(state.fingers.iter().map(|f| f.applied_force));
    } else {
        w.rising += 1;
    }
    w.last = energy;
    let scale = w.start.abs().max(state.stats.kinetic_energy).max(1e-12);
    if w.rising >= ENERGY_RISING_STEPS && energy - w.start > ENERGY_GROWTH * scale {
        return Err(diverged(
            model,
            state,
            format!(
                "the energy rose for {} steps in a row with no input, from {:.4e} J to {:.4e} J",
                w.rising, w.start, energy
            ),
        ));
    }
    Ok(())
}

fn cg_message(e: CgError) -> String {
    match e {
        CgError::NoConvergence {
            iterations,
            residual,
        } => format!(
            "the linear solver did not converge ({iterations} iterations, residual {residual:.2e}; raise [simulation] cg_max_iterations if the state looks sane)"
        ),
        other => format!("the linear solver failed: {other}"),
    }
}

/// Energy, volume error and speeds of the state.
pub fn update_diagnostics(model: &Model, state: &mut State) {
    let kinetic: f64 = state
        .velocities
        .iter()
        .zip(&model.mass)
        .map(|(v, m)| 0.5 * m * v.length_squared())
        .sum::<f64>()
        + state
            .fingers
            .iter()
            .zip(&model.fingers)
            .map(|(s, f)| 0.5 * f.mass * s.velocity.length_squared())
            .sum::<f64>();
    let (volume, bulk_energy) = forces::volume::volume_and_bulk_energy(model, state);
    let energy = kinetic
        + forces::springs::energy(model, state)
        + forces::viscosity::arm_energy(model, state)
        + forces::external::energy(model, state)
        + contact::energy(model, state)
        + contact::table::energy(model, state)
        + contact::self_collision::energy(model, state)
        + forces::pull::energy(model, state)
        + bulk_energy;
    let st = &mut state.stats;
    st.kinetic_energy = kinetic;
    st.energy = energy;
    st.volume_error = if model.rest_total_volume > 0.0 {
        (volume - model.rest_total_volume).abs() / model.rest_total_volume
    } else {
        0.0
    };
    st.max_speed = state
        .velocities
        .iter()
        .map(|v| v.length())
        .fold(0.0, f64::max);
}

/// Speed beyond which a state is taken as diverged (m/s): far above the
/// material's wave speed and anything a gripper does.
pub fn speed_limit(model: &Model) -> f64 {
    (50.0 * (model.young_modulus / model.density).sqrt()).max(100.0)
}

fn diverged(model: &Model, state: &State, what: String) -> SimError {
    let limit = speed_limit(model);
    // A finger whose load alone takes its mass past the speed limit within a few steps does
    // so at any dt: the load is the cause (1e6 N once sent users halving dt again and again).
    let overloaded = model
        .fingers
        .iter()
        .zip(&state.fingers)
        .enumerate()
        .find_map(|(k, (f, fs))| {
            let load = f.driving_force(fs.applied_force).length();
            (f.mass > 0.0 && load > 0.0 && limit * f.mass / load < 10.0 * model.dt).then_some((
                k,
                load,
                f.mass,
                limit * f.mass / load,
            ))
        });
    let (suggest_dt, advice) = match overloaded {
        Some((k, load, mass, t)) => (
            None,
            format!(
                "Finger {}'s load of {load:.4e} N takes its {mass} kg past {limit:.0} m/s in {t:.2e} s, whatever the time step: lower the load (a soft object carries a few to a few hundred N)",
                k + 1
            ),
        ),
        None => {
            // A rough explicit-stability estimate for the smallest element: a quarter of the
            // current step when nothing better is known.
            let wave = (model.young_modulus / model.density).sqrt();
            let suggest = (model.dt / 4.0).min(model.edge_length / wave).max(1e-7);
            (
                Some(suggest),
                format!(
                    "The time step dt = {:e} s may be too large for this stiffness (E = {:e} Pa, alpha = {:e}); try dt <= {suggest:e} s, a smaller alpha, or a softer contact",
                    model.dt, model.young_modulus, model.alpha
                ),
            )
        }
    };
    SimError::Diverged {
        time: state.time,
        step: state.step,
        what,
        dt: model.dt,
        young_modulus: model.young_modulus,
        alpha: model.alpha,
        suggest_dt,
        advice,
    }
}

/// NaN, infinity or an impossible speed end the run with an error.
fn check_divergence(model: &Model, state: &State) -> Result<(), SimError> {
    let limit = speed_limit(model);
    for (i, (x, v)) in state.positions.iter().zip(&state.velocities).enumerate() {
        if !x.is_finite() || !v.is_finite() {
            return Err(diverged(
                model,
                state,
                format!("particle {i} has a non-finite position or velocity"),
            ));
        }
        let speed = v.length();
        if speed > limit {
            return Err(diverged(
                model,
                state,
                format!(
                    "particle {i} near ({:.4}, {:.4}, {:.4}) m moves at {speed:.3e} m/s (limit {limit:.0} m/s)",
                    x.x, x.y, x.z
                ),
            ));
        }
    }
    for (k, f) in state.fingers.iter().enumerate() {
        if !f.position.is_finite() || !f.velocity.is_finite() || f.velocity.length() > limit {
            return Err(diverged(
                model,
                state,
                format!(
                    "finger {} left the scene (velocity {:?})",
                    k + 1,
                    f.velocity.to_array()
                ),
            ));
        }
    }
    Ok(())
}
