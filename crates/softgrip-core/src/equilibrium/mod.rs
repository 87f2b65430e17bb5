//! Static equilibrium under a quasi-static load: Newton's method on the force residual,
//! globalised by pseudo-transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 1998).
//!
//! An iteration is one implicit-Euler step from rest with a pseudo time step `h`: its move solves
//! `(M / h^2 + Dp / h + K) dx = f(x)`, Newton's step with the exact spring tangent
//! ([`Model::exact_tangent`]) shifted by `M / h^2`. Where `K` is indefinite (a saddle, a buckling
//! lattice) CG fails and `h` is cut until the shift makes the matrix definite, so the iteration
//! leaves saddles. `h` grows fourfold after each kept iteration; one that fails, turns an element
//! inside out or moves a point by more than a quarter of an edge is undone and `h` cut. CG solves
//! each move only to [`StaticOptions::forcing`] of the residual (an inexact Newton method). Converged:
//! the free force at most `tolerance` times the load, or a full Newton step that moves nothing.
//! Guide friction is a return mapping ([`Simulation::equilibrium`]). Design and measurements:
//! `docs/design/equilibrium.md`.

use std::sync::Arc;

use glam::DVec3;

use crate::error::SimError;
use crate::model::{AxisDrive, LinearSolver, Model};
use crate::state::State;
use crate::step::Simulation;

mod failure;
use failure::{Failure, loose_finger, no_equilibrium};

/// How the static solver iterates and when it stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticOptions {
    /// Converged when the 2-norm of the force on the free components is at most this times
    /// [`load_scale`].
    pub tolerance: f64,
    /// Iterations at most (undone ones count), then "no equilibrium".
    pub max_iterations: usize,
    /// The largest move of a point in one iteration, in edge lengths.
    pub max_move: f64,
    /// Converged also when a full Newton step moves no point by more than this (in edge
    /// lengths): where the spring-limit projection holds springs at their limits, its
    /// reaction is no force of the model and the residual stays.
    pub move_tolerance: f64,
    /// The largest pseudo time step (s): past the slowest mode's period the shift `M / h^2` is
    /// negligible and a larger `h` only worsens CG's conditioning.
    pub max_pseudo_step: f64,
    /// CG solves each iteration's linear system to this share of its right-hand side (the
    /// forcing term of an inexact Newton method, Eisenstat and Walker, SIAM J. Sci. Comput.
    /// 1996), and no further than a tenth of `tolerance` of the load. The tangent is not exact
    /// (the volume terms' Jacobians are their Gauss-Newton parts, the contacts switch), so a
    /// tighter solve does not converge in fewer iterations: 1e-5 took 2.3 times as long on the
    /// 4 mm cuboid's 7 loads to 15 N (`docs/design/equilibrium.md`).
    pub forcing: f64,
    /// The state is a guess near the answer (another parameter point's equilibrium under the
    /// same load, [`Simulation::equilibrium_near`]): the pseudo step starts at its largest, not
    /// at the scene's `dt`.
    pub warm: bool,
    /// How each Newton step is solved ([`StaticSolver`]).
    pub solver: StaticSolver,
}

/// How the static solver's Newton steps are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StaticSolver {
    /// [`StaticSolver::Direct`] where it was measured faster ([`prefers_direct`]), else
    /// [`StaticSolver::Cg`].
    #[default]
    Auto,
    /// CG's inexact steps on the time steps' tangent, from a pseudo step ramped from `dt`.
    Cg,
    /// Newton's steps on the exact tangent solved by a sparse factorisation
    /// (`crate::solver::direct`), globalised by a line search; a model with self-collision
    /// (whose couplings the factorisation's pattern does not hold) takes CG's.
    Direct,
}

pub use crate::solver::direct::DIRECT_UNKNOWNS;

/// Whether [`StaticSolver::Auto`] solves `model` by factorisation: a continuum on a table with
/// friction, of at most [`DIRECT_UNKNOWNS`] unknowns. There CG's tangent leaves out the friction
/// limit's coupling to the penetration and its pseudo step is held at
/// `FRICTION_PSEUDO_STEP`: on the 4 mm cuboid's 8 loads to 14.3 N, 2.6, 8.7 and 11.7 s at mu
/// 0.3, 0.6 and 1 against 1.9, 2.4 and 5.8 s by factorisation (0.9 against 1.5 s at mu 0.1).
/// Elsewhere CG's inexact steps were faster: the same cuboid bonded under the sphere 0.37
/// against 0.60 s, the plate 2.3 against 3.0 s (`docs/design/equilibrium.md`).
pub fn prefers_direct(model: &Model) -> bool {
    let table_friction = model.table.as_ref().is_some_and(|t| t.friction > 0.0);
    let unknowns = 3 * model.fixed.iter().filter(|f| !**f).count();
    model.fem.is_some() && table_friction && unknowns <= DIRECT_UNKNOWNS
}

impl Default for StaticOptions {
    fn default() -> Self {
        StaticOptions {
            tolerance: 1e-6,
            max_iterations: 400,
            max_move: 0.25,
            move_tolerance: 1e-6,
            max_pseudo_step: 100.0,
            forcing: 0.1,
            warm: false,
            solver: StaticSolver::Auto,
        }
    }
}

/// What a static solve did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StaticReport {
    /// Iterations, undone ones included.
    pub iterations: usize,
    /// Iterations undone (and retried with a smaller pseudo step).
    pub rejected: usize,
    /// The force on the free components at the answer (N).
    pub residual: f64,
    /// The load the residual is measured against (N, [`load_scale`]).
    pub load_scale: f64,
    /// CG iterations, summed.
    pub cg_iterations: usize,
    /// Converged by [`StaticOptions::move_tolerance`] (a full Newton step moved nothing) with
    /// a residual above the tolerance: the spring-limit projection's reaction, or CG's floor.
    pub by_move: bool,
    /// Cycles of two states met, each answered by a smaller largest pseudo step.
    pub cycles: usize,
    /// Force evaluations of the direct solver's line search.
    pub line_search: usize,
}

impl StaticReport {
    /// This solve's work followed by `next`'s, with `next`'s answer.
    fn then(self, next: StaticReport) -> StaticReport {
        StaticReport {
            iterations: self.iterations + next.iterations,
            rejected: self.rejected + next.rejected,
            cg_iterations: self.cg_iterations + next.cg_iterations,
            cycles: self.cycles + next.cycles,
            line_search: self.line_search + next.line_search,
            ..next
        }
    }
}

/// The applied load (N) the residual is measured against: the sum of the magnitudes of every
/// constant force (gravity, `[[load]]`) and of the fingers' applied forces and weights.
pub fn load_scale(model: &Model, state: &crate::state::State) -> f64 {
    let object: f64 = model.constant_force.iter().map(|f| f.length()).sum();
    let fingers: f64 = model
        .fingers
        .iter()
        .zip(&state.fingers)
        .map(|(f, s)| f.driving_force(s.applied_force).length())
        .sum();
    object + fingers
}

/// Pseudo steps below this share of the scene's `dt` are not tried: the model gets no nearer to
/// an equilibrium that way.
const SMALLEST_STEP: f64 = 1e-3;

/// A kept iteration at the largest pseudo step that lands nearer than this share of its move to
/// the state two back is a cycle.
const CYCLE: f64 = 0.1;

/// Full Newton steps in a row that do not take the residual below [`STALL_DROP`] times its
/// smallest yet: the iteration stalls (held by the spring-limit projection, whose reaction is no
/// force of the model, or cycling through contact states).
const STALL_ITERATIONS: usize = 100;
const STALL_DROP: f64 = 0.5;

/// The forcing of a solve done again after a stall: the time steps' own CG tolerance.
pub const TIGHT_FORCING: f64 = 1e-5;

/// The largest pseudo step with table friction (s): the return mapping's friction limit follows
/// the normal force, a coupling its tangent leaves out (it is not symmetric); at pseudo steps past
/// the object's slowest period nothing damps that, and the residual grew 5 % an iteration. On the
/// 4 mm table cuboid (mu 0.1, 8 loads) the default 100 s failed one load; 0.3, 0.1, 0.03 and 0.01 s
/// converged all in 700, 480, 500 and 680 iterations; at mu 0.3, 0.03 s failed none of the loading
/// steps (`docs/design/table-contact.md`).
const FRICTION_PSEUDO_STEP: f64 = 0.03;

/// The pseudo step grows by this after an iteration that was kept.
const GROWTH: f64 = 4.0;

/// How [`Simulation::settle_to_equilibrium`] came to rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Settled {
    /// The static solver converged.
    Static(StaticReport),
    /// It did not (stalled, or out of iterations), and time steps came to rest.
    Dynamic {
        /// How the time steps came to rest.
        rest: crate::quasi_static::RestReport,
        /// Whether the static solver stalled (rather than ran out of iterations).
        stalled: bool,
    },
}

/// A load step is halved after a failed solve down to this share of the whole change; then
/// the answer is "no equilibrium" at the load last tried.
pub const SMALLEST_INCREMENT: f64 = 1.0 / 16.0;

impl Simulation {
    /// As [`Simulation::equilibrium`], from an equilibrium under the fingers' applied forces
    /// `from` to one under their present ones, in load increments: the whole change first,
    /// each failed solve undone and its increment halved (down to [`SMALLEST_INCREMENT`]),
    /// each success followed by a doubled one. Near a limit load Newton's basin shrinks; a
    /// slow load passes through the states between, as the lab's weights did.
    pub fn equilibrium_from(
        &mut self,
        from: &[DVec3],
        options: StaticOptions,
    ) -> Result<StaticReport, SimError> {
        let to: Vec<DVec3> = self.state.fingers.iter().map(|f| f.applied_force).collect();
        if from == to {
            return self.equilibrium(options);
        }
        let load_at = |share: f64| -> Vec<DVec3> {
            from.iter()
                .zip(&to)
                .map(|(a, b)| {
                    if share >= 1.0 {
                        *b
                    } else {
                        *a + (*b - *a) * share
                    }
                })
                .collect()
        };
        let mut total = StaticReport::default();
        let (mut done, mut increment) = (0.0f64, 1.0f64);
        loop {
            let share = (done + increment).min(1.0);
            let saved = self.state.clone();
            for (f, load) in self.state.fingers.iter_mut().zip(load_at(share)) {
                f.applied_force = load;
            }
            match self.equilibrium(options) {
                Ok(r) => {
                    total = total.then(r);
                    if share >= 1.0 {
                        return Ok(total);
                    }
                    done = share;
                    increment = (2.0 * increment).min(1.0 - done);
                }
                Err(SimError::NoEquilibrium { stalled: false, .. })
                    if increment > SMALLEST_INCREMENT =>
                {
                    self.state = saved;
                    increment *= 0.5;
                }
                Err(mut e) => {
                    // The load that failed is a step on the way: said with the one asked.
                    if let SimError::NoEquilibrium { why, load, .. } = &mut e {
                        let sum = |v: &[DVec3]| v.iter().map(|f| f.length()).sum::<f64>();
                        let (start, asked) = (sum(from), sum(&to));
                        if (asked - *load).abs() > 1e-9 * asked.max(1.0) {
                            *why = format!(
                                "{why} (a step on the way from {start:.4} N to the {asked:.4} N asked)"
                            );
                        }
                    }
                    // A caller's dynamic fallback goes on under the asked load from a stalled
                    // iteration (near rest), else from the last equilibrium on the way.
                    if !matches!(e, SimError::NoEquilibrium { stalled: true, .. }) {
                        self.state = saved;
                    }
                    for (f, load) in self.state.fingers.iter_mut().zip(&to) {
                        f.applied_force = *load;
                    }
                    return Err(e);
                }
            }
        }
    }

    /// A quasi-static load brought to rest: [`Simulation::equilibrium_from`], and where it finds
    /// no answer, time steps from where it stopped until at rest ([`Simulation::settle`]).
    /// Neither finding a rest without elements inside out is [`SimError::NoEquilibrium`].
    pub fn settle_to_equilibrium(
        &mut self,
        from: &[DVec3],
        options: StaticOptions,
        rest: crate::quasi_static::RestTolerance,
        progress: impl FnMut(u64),
    ) -> Result<Settled, SimError> {
        let mut failure = match self.equilibrium_from(from, options) {
            Ok(r) => return Ok(Settled::Static(r)),
            Err(e @ SimError::NoEquilibrium { .. }) => e,
            Err(e) => return Err(e),
        };
        let SimError::NoEquilibrium { why, stalled, .. } = &mut failure else {
            unreachable!("matched above")
        };
        // Newton's path can fail where time steps still find rest (an element turned inside out
        // by a full step under a plate's edge): they are the judge. Neither finding a rest
        // without inverted elements is the answer.
        let dynamics = match self.settle(rest, progress) {
            Ok(r) if self.state.inverted_elements(&self.model) == 0 => {
                return Ok(Settled::Dynamic {
                    rest: r,
                    stalled: *stalled,
                });
            }
            Ok(_) => "time steps come to rest with elements inside out".to_string(),
            Err(SimError::NoRest { max_speed, .. }) => format!(
                "time steps from there do not come to rest either (still {max_speed:.1e} m/s)"
            ),
            Err(SimError::Diverged { what, .. }) => {
                format!("time steps from there diverge ({what})")
            }
            Err(e) => return Err(e),
        };
        *why = format!("{why}; {dynamics}");
        // The advice is the cause, where one shows: a finger that carries a load and touches
        // nothing is not a matter of supports.
        if let SimError::NoEquilibrium { advice, .. } = &mut failure
            && let Some(cause) = loose_finger(&self.model, &self.state)
        {
            *advice = cause;
        }
        Err(failure)
    }

    /// [`Simulation::equilibrium`] started from `positions` and `fingers` (the particles' and
    /// fingers' positions at another parameter point's equilibrium under the present loads) at
    /// the largest pseudo step: a fit's probes near evaluated points need a few Newton steps,
    /// not the ramp from `dt`. `None`, with the state as it was, where the model is not
    /// [`Model::path_independent`] (the answer would depend on the guess), the guess is for
    /// another mesh or the solve fails: the caller takes the usual path.
    pub fn equilibrium_near(
        &mut self,
        positions: &[DVec3],
        fingers: &[DVec3],
        options: StaticOptions,
    ) -> Result<Option<StaticReport>, SimError> {
        let fits = positions.len() == self.state.positions.len()
            && fingers.len() == self.state.fingers.len();
        if !fits || !self.model.path_independent() {
            return Ok(None);
        }
        let saved = self.state.clone();
        self.state.positions.copy_from_slice(positions);
        for (f, &p) in self.state.fingers.iter_mut().zip(fingers) {
            f.position = p;
        }
        match self.solve(StaticOptions {
            warm: true,
            ..options
        }) {
            Ok(r) => Ok(Some(r)),
            Err(SimError::Cancelled) => Err(SimError::Cancelled),
            Err(_) => {
                self.state = saved;
                Ok(None)
            }
        }
    }

    /// Moves the state to the static equilibrium under the present loads (see the module
    /// docs). Time does not advance; velocities end at zero. A model with no equilibrium
    /// there gets [`SimError::NoEquilibrium`], with where and why.
    pub fn equilibrium(&mut self, options: StaticOptions) -> Result<StaticReport, SimError> {
        crate::contact::table::begin_increment(&self.model, &mut self.state);
        let start: Vec<DVec3> = self.state.fingers.iter().map(|f| f.position).collect();
        let report = self.equilibrium_guided(options)?;
        for (f, p) in self.state.fingers.iter_mut().zip(start) {
            f.last_move = f.position - p;
        }
        crate::contact::table::commit(&self.model, &mut self.state);
        crate::contact::commit(&mut self.state);
        Ok(report)
    }

    /// [`Simulation::equilibrium`] before the friction anchors (table and fingers) are dragged.
    fn equilibrium_guided(&mut self, options: StaticOptions) -> Result<StaticReport, SimError> {
        // Guide friction is a return mapping on the finger's force axes: held where it is, the
        // finger stays if the guide can bear the force on it; if not it slides until the force
        // left is the friction's, F_g against the slide.
        let guided: Vec<usize> = (0..self.model.fingers.len())
            .filter(|&k| {
                let f = &self.model.fingers[k];
                f.guide_friction > 0.0
                    && f.is_force_controlled()
                    && self.state.fingers[k].held.is_none()
            })
            .collect();
        if guided.is_empty() {
            return self.solve(options);
        }
        for &k in &guided {
            self.state.fingers[k].held = Some(self.state.fingers[k].position);
        }
        let held = self.solve(options);
        for &k in &guided {
            self.state.fingers[k].held = None;
        }
        let held = held?;
        let slides: Vec<(usize, DVec3)> = guided
            .iter()
            .filter_map(|&k| {
                let (f, fs) = (&self.model.fingers[k], &self.state.fingers[k]);
                let axes = DVec3::from_array(
                    f.drive
                        .map(|d| if d == AxisDrive::Force { 1.0 } else { 0.0 }),
                );
                let force = (f.driving_force(fs.applied_force) + fs.contact_force) * axes;
                (force.length() > f.guide_friction)
                    .then(|| (k, force.normalize() * f.guide_friction))
            })
            .collect();
        if slides.is_empty() {
            return Ok(held);
        }
        let base = Arc::clone(&self.model);
        let mut sliding = (*base).clone();
        let applied: Vec<DVec3> = self.state.fingers.iter().map(|f| f.applied_force).collect();
        for &(k, friction) in &slides {
            sliding.fingers[k].guide_friction = 0.0;
            self.state.fingers[k].applied_force -= friction;
        }
        self.model = Arc::new(sliding);
        let slid = self.solve(options);
        self.model = base;
        for (f, a) in self.state.fingers.iter_mut().zip(applied) {
            f.applied_force = a;
        }
        slid.map(|r| held.then(r))
    }

    /// [`Simulation::equilibrium`] with the guide's friction as the model says. A solve that
    /// stalls with inexact steps is done again from the start with CG's steps to
    /// [`TIGHT_FORCING`]: where the spring-limit projection holds springs, the inexact steps
    /// can cycle round the answer (the thesis lattice without the bulk term at 4 N).
    fn solve(&mut self, options: StaticOptions) -> Result<StaticReport, SimError> {
        let start = (options.forcing > TIGHT_FORCING).then(|| self.state.clone());
        match (self.solve_with(options), start) {
            (Err(SimError::NoEquilibrium { stalled: true, .. }), Some(start)) => {
                self.state = start;
                self.solve_with(StaticOptions {
                    forcing: TIGHT_FORCING,
                    ..options
                })
            }
            (result, _) => result,
        }
    }

    fn solve_with(&mut self, options: StaticOptions) -> Result<StaticReport, SimError> {
        let base = Arc::clone(&self.model);
        let (time, step) = (self.state.time, self.state.step);
        let direct = match options.solver {
            StaticSolver::Auto => prefers_direct(&base),
            StaticSolver::Cg => false,
            StaticSolver::Direct => true,
        };
        let result = if direct && base.self_collision.is_none() {
            self.newton(&base, options)
        } else {
            self.iterate(&base, options)
        };
        self.model = base;
        self.state.time = time;
        self.state.step = step;
        self.state.velocities.fill(DVec3::ZERO);
        for f in &mut self.state.fingers {
            f.velocity = DVec3::ZERO;
        }
        result
    }

    fn iterate(&mut self, base: &Arc<Model>, o: StaticOptions) -> Result<StaticReport, SimError> {
        let (b, mut report) = bounds(base, &self.state, o);
        let (tolerance, max_move, smallest) = (b.tolerance, b.max_move, b.smallest);
        let guide_hold = b.guide_hold;
        let mut models: Vec<(f64, bool, Arc<Model>)> = Vec::new();
        let mut h = if o.warm { o.max_pseudo_step } else { base.dt };
        let mut last_failure = Failure::Still(0.0);
        let cancel = crate::cancel::current();
        // The state before the last kept iteration, for spotting a cycle of two states.
        let mut two_back: Option<Vec<DVec3>> = None;
        let mut largest_step = largest_pseudo_step(base, o);
        // The smallest residual at the largest pseudo step, and the iterations since it fell.
        let (mut best, mut since_best) = (f64::INFINITY, 0usize);
        while report.iterations < o.max_iterations {
            crate::cancel::check(cancel.as_ref())?;
            report.iterations += 1;
            let before = self.state.clone();
            self.model = model_with_step(&mut models, base, h, guide_hold, o, false, true);
            let stepped = self.step();
            let (before_points, now_points) = (points(&before), points(&self.state));
            let residual = self.state.stats.force_residual;
            report.cg_iterations += self.state.stats.cg_iterations;
            let failure = match stepped {
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(SimError::Diverged { what, .. }) => Failure::Step(what),
                Err(e) => Failure::Step(e.to_string()),
                Ok(()) if residual <= tolerance => {
                    self.state = before;
                    report.residual = residual;
                    return Ok(report);
                }
                Ok(()) => judge(
                    base,
                    &before_points,
                    &now_points,
                    &before,
                    &self.state,
                    max_move,
                ),
            };
            // The projection or a contact's stick/slip switch can send Newton round a cycle of
            // two states.
            let cycled = two_back.as_ref().map_or(f64::INFINITY, |x: &Vec<DVec3>| {
                largest_distance(x, &now_points)
            });
            let Failure::Still(moved) = failure else {
                self.state = before;
                report.rejected += 1;
                h *= match failure {
                    Failure::Moved(moved) => (0.5 * max_move / moved).min(0.25),
                    _ => 0.25,
                };
                last_failure = failure;
                if h < smallest {
                    break;
                }
                continue;
            };
            if h >= largest_step && moved.min(cycled) <= o.move_tolerance * base.edge_length {
                // A full step moves nothing: what force is left is the reaction of the
                // spring-limit projection (no force of the model) or below CG's accuracy.
                report.residual = residual;
                report.by_move = true;
                return Ok(report);
            }
            if h >= largest_step {
                if residual < STALL_DROP * best {
                    (best, since_best) = (residual, 0);
                } else {
                    since_best += 1;
                }
                if since_best >= STALL_ITERATIONS {
                    last_failure = Failure::Stalled(residual, moving(&before_points, &now_points));
                    break;
                }
            }
            two_back = Some(before_points);
            if h >= largest_step && cycled < CYCLE * moved && largest_step > base.dt {
                // A cycle: smaller pseudo steps damp the switch as time steps do.
                largest_step = (largest_step / (GROWTH * GROWTH)).max(base.dt);
                report.cycles += 1;
            }
            // First-order continuation: no momentum carried to the next iteration.
            come_to_rest(&mut self.state);
            h = (GROWTH * h).min(largest_step);
        }
        let solve = (report.iterations, o.tolerance);
        Err(no_equilibrium(base, &self.state, last_failure, solve))
    }
}

impl Simulation {
    /// Newton's method on the exact tangent, each step solved by a sparse factorisation
    /// ([`StaticSolver::Direct`]). Globalised by the pseudo-transient continuation as
    /// [`Simulation::iterate`] is, and by three safeguards it does without: a backtracking line
    /// search on the free force (a step is halved until the force at its end is below the force
    /// at its start; near a stick/slip switch Newton's full step can raise it), a step longer
    /// than `max_move` shortened along its direction (damped Newton) rather than solved again,
    /// and an indefinite tangent replaced, for that iteration, by the time steps' positive
    /// semi-definite one at the same `h`. The force at a trial step is the next iteration's own
    /// assembly, so a step the search keeps costs nothing extra.
    fn newton(&mut self, base: &Arc<Model>, o: StaticOptions) -> Result<StaticReport, SimError> {
        let (b, mut report) = bounds(base, &self.state, o);
        let (tolerance, max_move, smallest) = (b.tolerance, b.max_move, b.smallest);
        let guide_hold = b.guide_hold;
        let mut models: Vec<(f64, bool, Arc<Model>)> = Vec::new();
        // From an equilibrium with its contacts made, Newton's full step; a finger or table not
        // touching yet ramps the pseudo step from dt, so that a free body's first moves stay
        // small.
        let mut h = first_pseudo_step(base, &self.state, o);
        let mut exact = true;
        let mut last_failure = Failure::Still(0.0);
        let cancel = crate::cancel::current();
        let mut trial: Option<Trial> = None;
        let (mut best, mut since_best) = (f64::INFINITY, 0usize);
        while report.iterations < o.max_iterations {
            crate::cancel::check(cancel.as_ref())?;
            report.iterations += 1;
            self.model = model_with_step(&mut models, base, h, guide_hold, o, true, exact);
            let residual = self.assemble_here();
            if let Some(t) = trial.as_mut() {
                if residual >= (1.0 - 1e-4 * t.share) * t.start_residual {
                    if t.share > 0.5f64.powi(LINE_SEARCH_HALVINGS as i32) {
                        // Halve the step and look again.
                        t.share *= 0.5;
                        self.state.clone_from(&t.full);
                        shorten(&t.start, &mut self.state, t.share);
                        report.line_search += 1;
                        continue;
                    }
                    // No length of this step lowers the force: a smaller pseudo step.
                    self.state.clone_from(&t.start);
                    h = t.h / GROWTH;
                    trial = None;
                    report.rejected += 1;
                    if h < smallest {
                        last_failure = Failure::Stalled(residual, self.most_unbalanced());
                        break;
                    }
                    continue;
                }
                trial = None;
            }
            if residual <= tolerance {
                report.residual = residual;
                return Ok(report);
            }
            if residual < STALL_DROP * best {
                (best, since_best) = (residual, 0);
            } else {
                since_best += 1;
                if since_best >= STALL_ITERATIONS {
                    last_failure = Failure::Stalled(residual, self.most_unbalanced());
                    break;
                }
            }
            let before = self.state.clone();
            let stepped = self.step_assembled(residual);
            report.cg_iterations += self.state.stats.cg_iterations.min(1000);
            if let Err(SimError::Cancelled) = stepped {
                return Err(SimError::Cancelled);
            }
            if stepped.is_err() && exact && self.last_step_indefinite() {
                // Not a descent direction: the same pseudo step with the semi-definite tangent.
                self.state = before;
                report.rejected += 1;
                exact = false;
                continue;
            }
            exact = true;
            let failure = judge_newton_step(base, stepped, &before, &mut self.state, max_move);
            let Failure::Still(moved) = failure else {
                self.state = before;
                report.rejected += 1;
                h *= 0.25;
                last_failure = failure;
                if h < smallest {
                    break;
                }
                continue;
            };
            if h >= o.max_pseudo_step && moved <= o.move_tolerance * base.edge_length {
                // A full Newton step moves nothing: the force left is below what the solve can
                // resolve.
                self.state = before;
                report.residual = residual;
                report.by_move = true;
                return Ok(report);
            }
            trial = Some(Trial::of_step(&mut self.state, before, residual, h));
            h = (GROWTH * h).min(o.max_pseudo_step);
        }
        let solve = (report.iterations, o.tolerance);
        Err(no_equilibrium(base, &self.state, last_failure, solve))
    }
}

/// No momentum carried to the next iteration (first-order continuation).
fn come_to_rest(state: &mut State) {
    state.velocities.fill(DVec3::ZERO);
    for f in &mut state.fingers {
        f.velocity = DVec3::ZERO;
    }
}

/// The time steps' largest pseudo step: shorter on a table with friction, whose stick and slip
/// a long step can send round a cycle.
fn largest_pseudo_step(base: &Model, o: StaticOptions) -> f64 {
    match &base.table {
        Some(t) if t.friction > 0.0 => o.max_pseudo_step.min(FRICTION_PSEUDO_STEP),
        _ => o.max_pseudo_step,
    }
}

/// The first pseudo step of a Newton solve: from an equilibrium with its contacts made, Newton's
/// full step; a finger or table not touching yet ramps it from dt, so that a free body's first
/// moves stay small.
fn first_pseudo_step(base: &Model, state: &State, o: StaticOptions) -> f64 {
    if o.warm || contacts_made(base, state) {
        o.max_pseudo_step
    } else {
        base.dt
    }
}

/// What a Newton step from `before` to `state` did: its error, or [`judge`]'s verdict on the
/// move, a move too long shortened to 0.9 of `max_move` first.
fn judge_newton_step(
    base: &Model,
    stepped: Result<(), SimError>,
    before: &State,
    state: &mut State,
    max_move: f64,
) -> Failure {
    match stepped {
        Err(SimError::Diverged { what, .. }) => Failure::Step(what),
        Err(e) => Failure::Step(e.to_string()),
        Ok(()) => {
            let (from, to) = (points(before), points(state));
            match judge(base, &from, &to, before, state, max_move) {
                Failure::Moved(moved) => {
                    shorten(before, state, 0.9 * max_move / moved);
                    let to = points(state);
                    judge(base, &from, &to, before, state, max_move)
                }
                failure => failure,
            }
        }
    }
}

impl Trial {
    /// The step just taken to `state` (at rest: velocities zeroed) from `start`, where the force
    /// was `start_residual`, on trial at its full length.
    fn of_step(state: &mut State, start: State, start_residual: f64, h: f64) -> Trial {
        come_to_rest(state);
        Trial {
            full: state.clone(),
            start,
            start_residual,
            share: 1.0,
            h,
        }
    }
}

/// A Newton step on trial in the line search: where it started, the force there, its full
/// length's end, the share of it being tried and its pseudo step.
struct Trial {
    start: crate::state::State,
    start_residual: f64,
    full: crate::state::State,
    share: f64,
    h: f64,
}

/// Trial steps of a line search at most: the step halved this often.
const LINE_SEARCH_HALVINGS: usize = 4;

/// Whether the iteration from `before` to `after` (their [`points`] given) is kept.
fn judge(
    model: &Model,
    before_points: &[DVec3],
    after_points: &[DVec3],
    before: &crate::state::State,
    after: &crate::state::State,
    max_move: f64,
) -> Failure {
    let moved = largest_distance(before_points, after_points);
    if moved > max_move {
        return Failure::Moved(moved);
    }
    let inverted = newly_inverted(model, &before.positions, &after.positions);
    if !inverted.is_empty() {
        return Failure::Inverted(inverted);
    }
    Failure::Still(moved)
}

/// `after`'s particles and fingers moved back towards `before`'s, to `share` of the way.
fn shorten(before: &crate::state::State, after: &mut crate::state::State, share: f64) {
    for (x, x0) in after.positions.iter_mut().zip(&before.positions) {
        *x = *x0 + (*x - *x0) * share;
    }
    for (f, f0) in after.fingers.iter_mut().zip(&before.fingers) {
        f.position = f0.position + (f.position - f0.position) * share;
    }
}

/// The particles' and the fingers' positions.
fn points(state: &crate::state::State) -> Vec<DVec3> {
    let fingers = state.fingers.iter().map(|f| f.position);
    state.positions.iter().copied().chain(fingers).collect()
}

/// The centre of the points that move at least half as far as the farthest.
fn moving(before: &[DVec3], after: &[DVec3]) -> DVec3 {
    let far = largest_distance(before, after);
    let (sum, n) = before
        .iter()
        .zip(after)
        .filter(|(p, q)| p.distance(**q) >= 0.5 * far)
        .fold((DVec3::ZERO, 0.0), |(s, n), (_, q)| (s + *q, n + 1.0));
    if n > 0.0 { sum / n } else { DVec3::ZERO }
}

fn largest_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

fn signed_volume(model: &Model, x: &[DVec3], t: usize) -> f64 {
    let [a, b, c, d] = model.tets[t].map(|i| x[i as usize]);
    crate::mesh::signed_volume(a, b, c, d)
}

/// Elements with a positive volume in `before` and none in `after`.
fn newly_inverted(model: &Model, before: &[DVec3], after: &[DVec3]) -> Vec<usize> {
    (0..model.tets.len())
        .filter(|&t| signed_volume(model, after, t) <= 0.0 && signed_volume(model, before, t) > 0.0)
        .collect()
}

/// The model with pseudo step `h` (cached: the helper thread restarts when the model changes),
/// solved by CG or by a factorisation (`direct`) on the exact tangent or not (`exact`).
fn model_with_step(
    cache: &mut Vec<(f64, bool, Arc<Model>)>,
    base: &Arc<Model>,
    h: f64,
    guide_hold: f64,
    o: StaticOptions,
    direct: bool,
    exact: bool,
) -> Arc<Model> {
    if let Some((_, _, m)) = cache.iter().find(|(k, e, _)| *k == h && *e == exact) {
        return Arc::clone(m);
    }
    let mut m = (**base).clone();
    m.dt = h;
    m.guide_rest_speed = guide_hold / h;
    m.quasi_static = true;
    // CG's steps take the springs' exact tangent; a factorised step the whole exact tangent, or
    // (after it was found indefinite) the time steps' semi-definite one.
    m.exact_tangent = !direct || exact;
    if direct {
        m.linear_solver = LinearSolver::Direct;
        m.full_tangent = exact;
    }
    // CG stops at `forcing` times max(|rhs|, reference h |load|): the reference makes the floor
    // a tenth of the convergence test.
    m.cg_tolerance = o.forcing;
    m.cg_reference = 0.1 * o.tolerance / o.forcing;
    let m = Arc::new(m);
    cache.push((h, exact, Arc::clone(&m)));
    m
}

/// Whether every force-controlled finger touches the object and a table, if any, carries it:
/// the state of a solved load, from which Newton's full step is safe.
fn contacts_made(model: &Model, state: &crate::state::State) -> bool {
    let fingers = (0..model.fingers.len())
        .filter(|&k| model.fingers[k].is_force_controlled())
        .all(|k| state.contacts.iter().any(|c| c.finger as usize == k));
    let table = model.table.is_none()
        || state
            .table
            .iter()
            .any(|c| c.mode != crate::state::TableMode::Free);
    fingers && table
}

/// What both static iterations measure against.
struct Bounds {
    /// The force residual that counts as equilibrium, N (the options' share of the load's scale).
    tolerance: f64,
    /// The largest move of a particle in one iteration, m.
    max_move: f64,
    /// The smallest pseudo step, s.
    smallest: f64,
    /// The guide holds a finger to the distance it creeps in one step of the scene's dt, m.
    guide_hold: f64,
}

/// [`Bounds`] for `base` at `state` under `o`, and an empty report with the load's scale.
fn bounds(base: &Model, state: &State, o: StaticOptions) -> (Bounds, StaticReport) {
    let scale = load_scale(base, state);
    let bounds = Bounds {
        tolerance: o.tolerance * scale.max(f64::MIN_POSITIVE),
        max_move: o.max_move * base.edge_length,
        smallest: SMALLEST_STEP * base.dt,
        guide_hold: base.guide_rest_speed * base.dt,
    };
    let report = StaticReport {
        load_scale: scale,
        ..StaticReport::default()
    };
    (bounds, report)
}
