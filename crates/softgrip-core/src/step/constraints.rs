//! Spring limits tau_s / tau_c (thesis eq. 13-17, Alg. 3): after integration, springs stretched
//! beyond `(1 + tau_s) l0` or compressed below `(1 - tau_c) l0` are projected back, in Jacobi
//! sweeps that average each particle's corrections over its *active* constraints; velocities
//! take the same displacement over dt. With `[model] constraint_tolerance` the sweeps go on
//! until no spring is out by more than that fraction of its rest length, up to
//! [`MAX_SWEEPS_FACTOR`] times `constraint_iterations`. With the limit springs of
//! `crate::forces::springs` (the default) the projection only caps what went past them by
//! more than [`PROJECTION_BAND`].
//!
//! The departures from Alg. 3 and why: `docs/design/spring-limits.md`.

use glam::DVec3;

use crate::model::Model;
use crate::state::State;

/// The projection's reused buffers.
#[derive(Debug, Default, Clone)]
pub struct ProjectionScratch {
    delta: Vec<DVec3>,
    count: Vec<u32>,
    total: Vec<DVec3>,
    held: Vec<bool>,
    /// The springs at each particle: `incident[incident_start[i]..incident_start[i + 1]]`.
    incident_start: Vec<u32>,
    incident: Vec<u32>,
    /// Springs to check in the next sweep, in index order.
    candidates: Vec<u32>,
    queued: Vec<bool>,
}

impl ProjectionScratch {
    /// Builds the particle-to-spring lists once per model.
    fn prepare(&mut self, model: &Model) {
        let n = model.particle_count();
        if self.incident_start.len() == n + 1 && self.incident.len() == 2 * model.springs.len() {
            return;
        }
        let mut degree = vec![0u32; n + 1];
        for s in &model.springs {
            degree[s.i as usize + 1] += 1;
            degree[s.j as usize + 1] += 1;
        }
        for i in 0..n {
            degree[i + 1] += degree[i];
        }
        self.incident_start = degree.clone();
        self.incident = vec![0; 2 * model.springs.len()];
        for (k, s) in model.springs.iter().enumerate() {
            for end in [s.i as usize, s.j as usize] {
                self.incident[degree[end] as usize] = k as u32;
                degree[end] += 1;
            }
        }
        self.queued = vec![false; model.springs.len()];
    }
}

/// With limit springs (`[model] limit_stiffness > 0`, the default) and no
/// `constraint_tolerance`, the projection moves a spring only when it is
/// beyond its limit by more than this fraction of its rest length, and only
/// back to that band's edge: the
/// limit springs hold the limit itself inside the implicit step, and the
/// projection is the cap on what a fast transient pushes past them. A
/// projection to the limit itself fought the limit springs: on the 1.6 mm
/// thesis mesh, where whole columns under the finger sit at tau_c, the two
/// kept particles moving at 0.1 m/s with springs 1-2 % past their limits,
/// for ever (ARCHITECTURE.md, choice 5).
pub const PROJECTION_BAND: f64 = 0.01;

/// With `constraint_tolerance`, the sweeps stop at this many times
/// `constraint_iterations` (at least this many) even if the tolerance is not met.
pub const MAX_SWEEPS_FACTOR: usize = 100;

/// What a projection did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProjectionReport {
    /// Jacobi sweeps that moved particles.
    pub sweeps: usize,
    /// The largest relative violation `|C| / l0` left after the projection.
    pub violation: f64,
}

/// The largest relative violation `|C| / l0` over all springs (0 without limits).
pub fn max_violation(model: &Model, positions: &[DVec3]) -> f64 {
    let hi = model.tau_s.map(|t| 1.0 + t).unwrap_or(f64::INFINITY);
    let lo = model.tau_c.map(|t| 1.0 - t).unwrap_or(f64::NEG_INFINITY);
    model
        .springs
        .iter()
        .map(|s| {
            let r = positions[s.i as usize].distance(positions[s.j as usize]) / s.rest_length;
            (r - hi).max(lo - r).max(0.0)
        })
        .fold(0.0, f64::max)
}

/// Projects the spring limits (Alg. 3): Jacobi sweeps that move the ends of each spring past
/// its limit back to it (`correct_springs`), then the moves averaged per particle
/// (`move_particles`), until nothing is past or the sweeps run out; the velocities take the
/// total move over dt.
pub fn project_spring_limits(
    model: &Model,
    state: &mut State,
    scratch: &mut ProjectionScratch,
) -> ProjectionReport {
    if model.tau_s.is_none() && model.tau_c.is_none() {
        return ProjectionReport::default();
    }
    let n = model.particle_count();
    // With limit springs the projection only caps what gets past them
    // (unless the scene asks for a bound of its own).
    let band = if model.limit_stiffness > 0.0 && model.constraint_tolerance.is_none() {
        PROJECTION_BAND
    } else {
        0.0
    };
    let limits = Limits {
        max_len: model.tau_s.map(|t| 1.0 + t).unwrap_or(f64::INFINITY),
        min_len: model.tau_c.map(|t| 1.0 - t).unwrap_or(0.0),
        band,
    };
    scratch.total.clear();
    scratch.total.resize(n, DVec3::ZERO);
    hold_pressed(model, state, scratch);

    let max_sweeps = match model.constraint_tolerance {
        None => model.constraint_iterations,
        Some(_) => MAX_SWEEPS_FACTOR * model.constraint_iterations.max(1),
    };
    let tolerance = model.constraint_tolerance.unwrap_or(0.0);
    scratch.prepare(model);
    let mut sweeps = 0;
    let mut any_violated = false;
    // The first sweep checks every spring; later sweeps only the springs at
    // particles the previous sweep moved (no other spring changed length, and
    // a violated spring with a free end always moves that end). Violated
    // springs with both ends held never change: their worst carries over.
    let mut held_worst: f64 = 0.0;
    for sweep in 0..max_sweeps {
        scratch.delta.clear();
        scratch.delta.resize(n, DVec3::ZERO);
        scratch.count.clear();
        scratch.count.resize(n, 0);
        let all = 0..model.springs.len() as u32;
        let checked: &mut dyn Iterator<Item = u32> = if sweep == 0 {
            &mut all.into_iter()
        } else {
            &mut scratch.candidates.iter().copied()
        };
        let mut sums = Sweep {
            active: false,
            worst: held_worst,
            held_worst: &mut held_worst,
            any_violated: &mut any_violated,
        };
        correct_springs(
            model,
            &state.positions,
            &limits,
            checked,
            &scratch.held,
            &mut scratch.delta,
            &mut scratch.count,
            &mut sums,
        );
        let (active, worst) = (sums.active, sums.worst);
        let done = sweep >= model.constraint_iterations && worst <= tolerance;
        if !active || done {
            break;
        }
        sweeps += 1;
        move_particles(state, scratch, n);
    }
    let dt = model.dt;
    for (v, t) in state.velocities.iter_mut().zip(&scratch.total) {
        *v += *t / dt;
    }
    ProjectionReport {
        sweeps,
        // A first sweep that found every spring inside its limits moved nothing.
        violation: if any_violated || max_sweeps == 0 {
            max_violation(model, &state.positions)
        } else {
            0.0
        },
    }
}

/// The lengths a spring may have, as fractions of its rest length, and the band past them the
/// projection leaves to the limit springs.
struct Limits {
    max_len: f64,
    min_len: f64,
    band: f64,
}

/// What a sweep found: whether it moved anything, its worst relative violation; and, over the
/// sweeps, the worst of springs with both ends held and whether any spring was past a limit.
struct Sweep<'a> {
    active: bool,
    worst: f64,
    held_worst: &'a mut f64,
    any_violated: &'a mut bool,
}

/// Marks the particles that do not move: pinned ones, and those a finger presses on; their
/// partners take the correction. Projecting a pressed particle would push it back into the
/// finger, the contact would push it out again, and the two would fight every step (measured:
/// the finger never comes to rest under 1 N, and at 4 N the contact force overshoots the load
/// fivefold).
fn hold_pressed(model: &Model, state: &State, scratch: &mut ProjectionScratch) {
    scratch.held.clear();
    scratch.held.extend_from_slice(&model.fixed);
    for c in &state.contacts {
        for (a, &i) in model.facets[c.facet as usize].iter().enumerate() {
            if c.weights[a] > 0.0 {
                scratch.held[i as usize] = true;
            }
        }
    }
}

/// One sweep's corrections (eq. 14-17) of the `checked` springs past their limits (by more
/// than the band) into `delta` and `count`, shared between the free ends.
#[allow(clippy::too_many_arguments)]
fn correct_springs(
    model: &Model,
    positions: &[DVec3],
    limits: &Limits,
    checked: &mut dyn Iterator<Item = u32>,
    held: &[bool],
    delta: &mut [DVec3],
    count: &mut [u32],
    sums: &mut Sweep,
) {
    let (max_len, min_len, band) = (limits.max_len, limits.min_len, limits.band);
    for k in checked {
        let s = &model.springs[k as usize];
        let (i, j) = (s.i as usize, s.j as usize);
        let d = positions[i] - positions[j];
        let l2 = d.length_squared();
        let (hi, lo) = (max_len * s.rest_length, min_len * s.rest_length);
        if l2 <= hi * hi && l2 >= lo * lo {
            continue;
        }
        *sums.any_violated = true;
        let (hi, lo) = (
            hi + band * s.rest_length,
            (lo - band * s.rest_length).max(0.0),
        );
        if l2 <= hi * hi && l2 >= lo * lo {
            continue;
        }
        let l = l2.sqrt();
        if l <= 0.0 {
            continue;
        }
        // Signed correction of the length: negative = too long (eq. 14), positive = too short (eq. 16).
        let c = if l > hi {
            hi - l
        } else if l < lo {
            lo - l
        } else {
            continue;
        };
        let u = d / l;
        sums.worst = sums.worst.max(c.abs() / s.rest_length);
        let (fi, fj) = (held[i], held[j]);
        let (share_i, share_j) = match (fi, fj) {
            (false, false) => (0.5, 0.5), // eq. 15 / 17
            (true, false) => (0.0, 1.0),
            (false, true) => (1.0, 0.0),
            (true, true) => {
                *sums.held_worst = sums.held_worst.max(c.abs() / s.rest_length);
                continue;
            }
        };
        sums.active = true;
        delta[i] += share_i * c * u;
        delta[j] -= share_j * c * u;
        count[i] += (share_i > 0.0) as u32;
        count[j] += (share_j > 0.0) as u32;
    }
}

/// Moves each corrected particle by its corrections' mean (eq. 13) and queues the springs at it
/// for the next sweep, in index order as a full sweep visits them (the same sums, bit for bit).
fn move_particles(state: &mut State, scratch: &mut ProjectionScratch, n: usize) {
    scratch.candidates.clear();
    for i in 0..n {
        if scratch.count[i] > 0 {
            let step = scratch.delta[i] / scratch.count[i] as f64; // eq. 13
            state.positions[i] += step;
            scratch.total[i] += step;
            let springs =
                scratch.incident_start[i] as usize..scratch.incident_start[i + 1] as usize;
            for &k in &scratch.incident[springs] {
                if !scratch.queued[k as usize] {
                    scratch.queued[k as usize] = true;
                    scratch.candidates.push(k);
                }
            }
        }
    }
    scratch.candidates.sort_unstable();
    for &k in &scratch.candidates {
        scratch.queued[k as usize] = false;
    }
}
