//! Finger-object contact (thesis Sec. IV, Alg. 4): broad phase, narrow phase
//! per finger shape, Hunt-Crossley normal force, stick-slip friction, and the
//! distribution of each facet's force to its three particles (eq. 38-39) with
//! the equal and opposite reaction on the finger.
//!
//! Every facet in contact carries its own force, as in the thesis. Both the
//! normal and the tangential terms enter the implicit system through their
//! Jacobians (rank-one in the normal, the tangent projector in the plane):
//! contact stiffness far exceeds what an explicit step of 1 ms could carry.

pub mod box_facet;
pub mod friction;
mod geometry;
pub mod hunt_crossley;
pub mod plate_facet;
pub mod self_collision;
pub mod sphere_facet;
pub mod table;

use glam::{DMat3, DVec3};

use crate::geometry::FacetGrid;
use crate::model::{HUNT_CROSSLEY_MIN_APPROACH_SPEED, Model};
use crate::scene::FingerShape;
use crate::solver::System;
use crate::solver::system::outer;
use crate::state::{Contact, ContactMemory, State};
use friction::{StickSlipParams, limit_drift, slide_drift, stick_slip_force};
pub use geometry::Geometry;
use hunt_crossley::hunt_crossley_normal_force;

/// Reused buffers of the contact stage.
#[derive(Debug, Default, Clone)]
pub struct ContactScratch {
    /// The broad phase: the facets binned in a grid of cells two edges wide.
    pub grid: FacetGrid,
    candidates: Vec<u32>,
    touched: Vec<(u32, u32)>,
}

/// Contact stiffness and exponent of part `part` of a finger on a facet of
/// the given area.
fn stiffness_and_exponent(
    model: &Model,
    finger: usize,
    part: usize,
    facet_area: f64,
) -> (f64, f64) {
    let f = &model.fingers[finger];
    let part = &f.parts[part];
    match part.shape {
        FingerShape::Sphere { .. } => (part.hertz_stiffness * f.contact_stiffness_scale, 1.5),
        // A rigid flat punch of the facet's area: F = 2 a E* d (Boussinesq), exponent 1.
        FingerShape::Plate { .. } | FingerShape::Box { .. } => (
            2.0 * (facet_area / std::f64::consts::PI).sqrt()
                * f.effective_modulus
                * f.contact_stiffness_scale,
            1.0,
        ),
    }
}

/// The contact geometry of one shape centred at `centre` with facet `p`.
fn detect_shape(shape: FingerShape, centre: DVec3, p: [DVec3; 3]) -> Option<Geometry> {
    match shape {
        FingerShape::Sphere { radius } => sphere_facet::detect(centre, radius, p),
        FingerShape::Plate { half_size } => {
            plate_facet::detect(centre, half_size, 0.5 * half_size[0].min(half_size[1]), p)
        }
        FingerShape::Box { half_size } => box_facet::detect(centre, half_size, p),
    }
}

/// The contact geometry of finger `k` (at `centre`) with facet `p`, if any:
/// the deepest of its parts' (a facet has one contact per finger).
pub fn detect(model: &Model, k: usize, centre: DVec3, p: [DVec3; 3]) -> Option<Geometry> {
    let mut best: Option<Geometry> = None;
    for (i, part) in model.fingers[k].parts.iter().enumerate() {
        if let Some(mut g) = detect_shape(part.shape, centre + part.offset, p)
            && best.is_none_or(|b| g.penetration > b.penetration)
        {
            g.part = i;
            best = Some(g);
        }
    }
    best
}

/// The box around one shape centred at `centre` in which facets may touch it.
fn shape_bounds(shape: FingerShape, centre: DVec3, margin: f64) -> (DVec3, DVec3) {
    match shape {
        FingerShape::Sphere { radius } => (
            centre - DVec3::splat(radius + margin),
            centre + DVec3::splat(radius + margin),
        ),
        FingerShape::Plate { half_size } => {
            let depth = 0.5 * half_size[0].min(half_size[1]);
            (
                centre - DVec3::new(half_size[0] + margin, half_size[1] + margin, margin),
                centre + DVec3::new(half_size[0] + margin, half_size[1] + margin, depth + margin),
            )
        }
        FingerShape::Box { half_size } => {
            let h = DVec3::from_array(half_size) + DVec3::splat(margin);
            (centre - h, centre + h)
        }
    }
}

/// The box around finger `k` (all its parts) in which facets may touch it.
pub fn finger_bounds(model: &Model, k: usize, centre: DVec3) -> (DVec3, DVec3) {
    let margin = 0.5 * model.edge_length;
    model.fingers[k]
        .parts
        .iter()
        .map(|p| shape_bounds(p.shape, centre + p.offset, margin))
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
        .unwrap_or((centre, centre))
}

/// After a static solve: each finger contact's anchor is dragged by what slid in the increment.
pub fn commit(state: &mut State) {
    for m in state.contact_memory.values_mut() {
        m.anchor_offset += m.pending;
        m.dragged = m.pending;
        m.pending = DVec3::ZERO;
    }
}

/// Adds the contact forces of every finger and records the contacts: for each finger the
/// broad phase (the facet grid), then per facet touched the narrow phase and the forces
/// (`pair_forces`), their stamp into the force vector and the system (`stamp`) and their
/// record (`record`); then the stick anchors of contacts that ended are forgotten.
pub fn accumulate(
    model: &Model,
    state: &mut State,
    force: &mut [DVec3],
    system: &mut System,
    scratch: &mut ContactScratch,
) {
    state.contacts.clear();
    scratch.touched.clear();
    for fs in &mut state.fingers {
        fs.contact_force = DVec3::ZERO;
        fs.normal_force = 0.0;
        fs.tangential_force = DVec3::ZERO;
        fs.max_penetration = 0.0;
    }
    if model.fingers.is_empty() {
        state.contact_memory.clear();
        return;
    }
    scratch
        .grid
        .rebuild(2.0 * model.edge_length, &model.facets, &state.positions);

    for k in 0..model.fingers.len() {
        let finger = &model.fingers[k];
        let (lo, hi) = finger_bounds(model, k, state.fingers[k].position);
        scratch.grid.query(lo, hi, &mut scratch.candidates);
        let params = StickSlipParams {
            friction: finger.friction,
            stick_velocity: finger.stick_velocity,
            stick_stiffness: finger.stick_stiffness,
            stick_damping: finger.stick_damping,
        };
        for ci in 0..scratch.candidates.len() {
            let j = scratch.candidates[ci] as usize;
            let Some(pair) = pair_forces(model, state, k, j, &params) else {
                continue;
            };
            scratch.touched.push((k as u32, j as u32));
            stamp(model, state, force, system, &pair, &params);
            record(state, &pair, &params);
        }
    }
    // Forget contacts that ended (touched is sorted: fingers, then facets in order).
    let touched = &scratch.touched;
    state
        .contact_memory
        .retain(|key, _| touched.binary_search(key).is_ok());
}

/// One finger-facet contact of a step and its forces.
struct Pair {
    /// The finger.
    k: usize,
    /// The facet (index into `model.facets`) and its particles.
    j: usize,
    tri: [u32; 3],
    /// The facet's corners at the step's positions, m.
    p: [DVec3; 3],
    g: Geometry,
    normal: hunt_crossley::NormalForce,
    tangential: friction::TangentialForce,
    /// The stick spring's stretch in the tangent plane after the friction limit, m.
    drift: DVec3,
}

/// The narrow phase of finger `k` with facet `j` and, where they touch, the Hunt-Crossley
/// normal force and the stick-slip friction (eq. 18-36), the stick anchor remembered from
/// where the contact began (and moved by what slid).
fn pair_forces(
    model: &Model,
    state: &mut State,
    k: usize,
    j: usize,
    params: &StickSlipParams,
) -> Option<Pair> {
    let finger = &model.fingers[k];
    let centre = state.fingers[k].position;
    let tri = model.facets[j];
    let p = tri.map(|i| state.positions[i as usize]);
    let g = detect(model, k, centre, p)?;
    let w = g.weights;
    let v_point: DVec3 = (0..3)
        .map(|a| w[a] * state.velocities[tri[a] as usize])
        .sum();
    let v_rel = v_point - state.fingers[k].velocity;
    let penetration_rate = -g.normal.dot(v_rel);

    let key = (k as u32, j as u32);
    let memory = state.contact_memory.entry(key).or_insert(ContactMemory {
        approach_speed: penetration_rate.max(HUNT_CROSSLEY_MIN_APPROACH_SPEED),
        anchor_weights: w,
        anchor_offset: g.point - centre,
        sliding: false,
        pending: DVec3::ZERO,
        dragged: DVec3::ZERO,
    });

    let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    let (stiffness, exponent) = stiffness_and_exponent(model, k, g.part, area);
    let normal = hunt_crossley_normal_force(
        stiffness,
        exponent,
        finger.restitution,
        g.penetration,
        penetration_rate,
        memory.approach_speed,
    );

    let Drift {
        projector,
        raw: raw_drift,
        limited: drift,
        moved: anchor_moved,
    } = stick_drift(params, normal.force, memory, p, centre, g.normal);
    let v_t = projector * v_rel; // eq. 33
    let tangential = if model.quasi_static {
        // A static solve's iterations are no time: the anchor is held over the load
        // increment and the force is the stick spring on the drift projected onto the
        // friction cone (a return mapping, as for the table); the anchor is dragged when
        // the solve ends (`commit`). On the cone's edge the tangent is the projection's
        // (the 2 mm plate's 8 loads in 23 s; with the stick spring's, one load took 2000
        // iterations). Without friction the stick spring's stays: the force is zero
        // either way, and the bare lattice under a frictionless sphere had no definite
        // matrix at any pseudo step without it.
        memory.pending = anchor_moved;
        let mut t = stick_slip_force(params, normal.force, drift, v_t, 0.0);
        let raw = raw_drift.length();
        if params.friction > 0.0 && anchor_moved != DVec3::ZERO && raw > 0.0 {
            t.stiffness *= drift.length() / raw;
        }
        t
    } else {
        memory.anchor_offset += anchor_moved;
        memory.pending = DVec3::ZERO;
        let slip_speed = anchor_moved.length() / model.dt;
        stick_slip_force(params, normal.force, drift, v_t, slip_speed)
    };
    Some(Pair {
        k,
        j,
        tri,
        p,
        g,
        normal,
        tangential,
        drift,
    })
}

/// The stick spring's stretch in a contact's tangent plane.
struct Drift {
    /// The projector onto the tangent plane.
    projector: DMat3,
    /// The anchor's offset from where it was on the finger, in the plane, m.
    raw: DVec3,
    /// `raw` limited by the friction cone, m.
    limited: DVec3,
    /// How far the anchor is dragged by what slid, m.
    moved: DVec3,
}

/// The stick spring of a contact with unit normal `normal` and normal force `normal_force` (N):
/// from the anchor (the facet's material point where contact began, on the corners `p`) to where
/// it was on the finger at `centre`, in the tangent plane, limited by the friction cone.
fn stick_drift(
    params: &StickSlipParams,
    normal_force: f64,
    memory: &ContactMemory,
    p: [DVec3; 3],
    centre: DVec3,
    normal: DVec3,
) -> Drift {
    let projector = DMat3::IDENTITY - outer(normal, normal);
    let anchor_point: DVec3 = (0..3).map(|a| memory.anchor_weights[a] * p[a]).sum();
    let raw = projector * (anchor_point - centre - memory.anchor_offset);
    let (limited, moved) = if memory.sliding {
        slide_drift(params, normal_force, raw)
    } else {
        limit_drift(params, normal_force, raw)
    };
    Drift {
        projector,
        raw,
        limited,
        moved,
    }
}

/// A contact's nodal forces (eq. 37-39) and the reaction on the finger into `force`, and its
/// Jacobian into `system`: Newton's exact tangent in a static solve that asks for it, the
/// time step's blocks otherwise.
fn stamp(
    model: &Model,
    state: &State,
    force: &mut [DVec3],
    system: &mut System,
    pair: &Pair,
    params: &StickSlipParams,
) {
    let n = model.particle_count();
    let Pair {
        k,
        j,
        tri,
        p,
        g,
        normal,
        tangential,
        ..
    } = *pair;
    let w = g.weights;
    let total = normal.force * g.normal + tangential.force;
    for a in 0..3 {
        force[tri[a] as usize] += w[a] * total;
    }
    force[n + k] -= total;

    let centre = state.fingers[k].position;
    let exact = (model.full_tangent && model.quasi_static).then(|| {
        let memory = &state.contact_memory[&(k as u32, j as u32)];
        pair_stiffness(model, k, centre, p, memory, params)
    });
    if let Some((_, skew)) = &exact
        && let Some(skew) = skew
    {
        let dofs = [tri[0], tri[1], tri[2], (n + k) as u32];
        system.add_asym(dofs, *skew);
    }
    let exact = exact.map(|(sym, _)| sym);
    let vel = |dof: usize| crate::forces::velocity_of(state, dof);
    if let Some(blocks) = exact {
        // Newton's tangent: the static force's whole derivative, by central differences
        // of the pair's force in its twelve coordinates (see `pair_stiffness`).
        let dq = outer(g.normal, g.normal) * normal.damping;
        let ends = [tri[0] as usize, tri[1] as usize, tri[2] as usize, n + k];
        let weights = [w[0], w[1], w[2], -1.0];
        for a in 0..4 {
            let damping = dq * (weights[a] * weights[a]);
            system.add_diag(ends[a], blocks[a][a], damping, &vel);
        }
        for a in 0..3 {
            let b = (a + 1) % 3;
            let (lo, hi) = if tri[a] < tri[b] { (a, b) } else { (b, a) };
            let damping = dq * (weights[lo] * weights[hi]);
            system.add_off(
                &model.springs,
                model.facet_springs[j][a],
                ends[lo],
                ends[hi],
                blocks[lo][hi],
                damping,
                &vel,
            );
            let damping = dq * -weights[a];
            system.add_coupling(ends[a], n + k, blocks[a][3], damping, &vel);
        }
    } else {
        add_pair_jacobian(model, system, pair, &vel);
    }
}

/// A contact's share of its finger's sums and its [`Contact`] record.
fn record(state: &mut State, pair: &Pair, params: &StickSlipParams) {
    let Pair {
        k,
        j,
        g,
        normal,
        tangential,
        drift,
        ..
    } = *pair;
    let total = normal.force * g.normal + tangential.force;
    let fs = &mut state.fingers[k];
    fs.contact_force -= total;
    fs.normal_force += normal.force;
    fs.tangential_force += tangential.force;
    fs.max_penetration = fs.max_penetration.max(g.penetration);
    state.contacts.push(Contact {
        finger: k as u32,
        facet: j as u32,
        point: g.point,
        normal: g.normal,
        penetration: g.penetration,
        normal_force: normal.force,
        tangential_force: tangential.force,
        stick: tangential.stick,
        weights: g.weights,
        part: g.part as u32,
        stick_energy: 0.5 * params.stick_stiffness * drift.length_squared(),
    });
}

/// The Jacobian blocks of one finger-facet contact in time steps: `[w_0, w_1, w_2, -1] (x) Q`
/// with `Q` the normal stiffness along the normal and the stick spring's in the plane, and the
/// sphere's lever stiffness (all symmetric positive semi-definite).
fn add_pair_jacobian(
    model: &Model,
    system: &mut System,
    pair: &Pair,
    vel: &impl Fn(usize) -> DVec3,
) {
    let Pair {
        k,
        j,
        tri,
        p,
        g,
        normal,
        tangential,
        ..
    } = *pair;
    let n = model.particle_count();
    let w = g.weights;
    let finger = &model.fingers[k];
    let projector = DMat3::IDENTITY - outer(g.normal, g.normal);
    // Jacobian: J = [w_0, w_1, w_2, -1] (x) Q.
    let kq = outer(g.normal, g.normal) * normal.stiffness + projector * tangential.stiffness;
    let dq = outer(g.normal, g.normal) * normal.damping + projector * tangential.damping;
    for a in 0..3 {
        let ia = tri[a] as usize;
        system.add_diag(ia, kq * (w[a] * w[a]), dq * (w[a] * w[a]), vel);
        let b = (a + 1) % 3;
        let ww = w[a] * w[b];
        if ww != 0.0 {
            system.add_off(
                &model.springs,
                model.facet_springs[j][a],
                ia,
                tri[b] as usize,
                kq * ww,
                dq * ww,
                vel,
            );
        }
        if w[a] != 0.0 {
            system.add_coupling(ia, n + k, kq * -w[a], dq * -w[a], vel);
        }
    }
    system.add_diag(n + k, kq, dq, vel);

    // Lever stiffness: the contact point is the foot of the finger
    // centre on the facet, so when the facet tilts, the point (and the
    // share w_a of the force each particle takes) slides by the lever
    // arm (R - penetration) times the tilt. For a facet of size h this
    // stiffness, F (R - d) grad(w_a) . grad(w_b), exceeds the springs'
    // by R / h and, left out, makes implicit Euler oscillate at period
    // two. It is positive semi-definite (a Gram matrix) and restoring.
    if let FingerShape::Sphere { radius } = finger.parts[g.part].shape {
        let grads = sphere_facet::barycentric_gradients(p, w);
        let lever = normal.force * (radius - g.penetration).max(0.0);
        if lever > 0.0 && grads.iter().any(|g| *g != DVec3::ZERO) {
            let nn = outer(g.normal, g.normal);
            let zero = DMat3::ZERO;
            for a in 0..3 {
                let kaa = nn * (lever * grads[a].length_squared());
                system.add_diag(tri[a] as usize, kaa, zero, vel);
                let b = (a + 1) % 3;
                let kab = nn * (lever * grads[a].dot(grads[b]));
                system.add_off(
                    &model.springs,
                    model.facet_springs[j][a],
                    tri[a] as usize,
                    tri[b] as usize,
                    kab,
                    zero,
                    vel,
                );
            }
        }
    }
}

/// The static force of one finger-facet contact on the facet's three particles and the finger,
/// its memory (anchor, sliding) held: the Hunt-Crossley force at rest along the normal and the
/// stick spring returned onto the friction cone. Zero where they do not touch.
fn static_pair_force(
    model: &Model,
    k: usize,
    centre: DVec3,
    p: [DVec3; 3],
    memory: &ContactMemory,
    params: &StickSlipParams,
) -> [DVec3; 4] {
    let Some(g) = detect(model, k, centre, p) else {
        return [DVec3::ZERO; 4];
    };
    let finger = &model.fingers[k];
    let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    let (stiffness, exponent) = stiffness_and_exponent(model, k, g.part, area);
    let normal = hunt_crossley_normal_force(
        stiffness,
        exponent,
        finger.restitution,
        g.penetration,
        0.0,
        memory.approach_speed,
    );
    let drift = stick_drift(params, normal.force, memory, p, centre, g.normal).limited;
    let t = stick_slip_force(params, normal.force, drift, DVec3::ZERO, 0.0);
    let total = normal.force * g.normal + t.force;
    let w = g.weights;
    [w[0] * total, w[1] * total, w[2] * total, -total]
}

/// The step in each coordinate of [`pair_stiffness`]'s central differences, in edge lengths:
/// the force's third derivative is about the contact's over its penetration (a few tenths of an
/// edge), so the truncation error is some 1e-13 of the stiffness, and rounding some 1e-9.
const PAIR_STEP: f64 = 1e-6;

/// `-df_a/dx_b` of one contact's static force ([`static_pair_force`]), `a, b` over the facet's
/// three particles and the finger, by central differences in the twelve coordinates: its
/// symmetric part, and the rest where friction makes it not symmetric (a sliding contact's
/// force follows the normal force). Newton's exact tangent: the time steps' Jacobian leaves out
/// the contact point sliding over the facet and the normal turning.
fn pair_stiffness(
    model: &Model,
    k: usize,
    centre: DVec3,
    p: [DVec3; 3],
    memory: &ContactMemory,
    params: &StickSlipParams,
) -> ([[DMat3; 4]; 4], Option<[[DMat3; 4]; 4]>) {
    let h = PAIR_STEP * model.edge_length;
    let mut columns = [[[DVec3::ZERO; 3]; 4]; 4];
    for b in 0..4 {
        for axis in 0..3 {
            let moved = |sign: f64| {
                let (mut c, mut q) = (centre, p);
                if b == 3 {
                    c[axis] += sign * h;
                } else {
                    q[b][axis] += sign * h;
                }
                static_pair_force(model, k, c, q, memory, params)
            };
            let (plus, minus) = (moved(1.0), moved(-1.0));
            for a in 0..4 {
                columns[a][b][axis] = -(plus[a] - minus[a]) / (2.0 * h);
            }
        }
    }
    let block = |a: usize, b: usize| {
        let c = columns[a][b];
        DMat3::from_cols(c[0], c[1], c[2])
    };
    let (mut sym, mut skew) = ([[DMat3::ZERO; 4]; 4], [[DMat3::ZERO; 4]; 4]);
    let (mut size, mut asymmetry) = (0.0f64, 0.0f64);
    for a in 0..4 {
        for b in 0..4 {
            sym[a][b] = (block(a, b) + block(b, a).transpose()) * 0.5;
            skew[a][b] = block(a, b) - sym[a][b];
            size = size.max(largest(block(a, b)));
            asymmetry = asymmetry.max(largest(skew[a][b]));
        }
    }
    // Below the differences' own error the remainder is noise.
    (sym, (asymmetry > 1e-7 * size).then_some(skew))
}

/// The largest entry's magnitude.
fn largest(m: DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// Elastic energy stored in the contacts of the last step, the stick springs
/// included (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    state
        .contacts
        .iter()
        .map(|c| {
            let tri = model.facets[c.facet as usize];
            let p = tri.map(|i| state.positions[i as usize]);
            let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            let (k, e) = stiffness_and_exponent(model, c.finger as usize, c.part as usize, area);
            hunt_crossley::elastic_energy(k, e, c.penetration) + c.stick_energy
        })
        .sum()
}
