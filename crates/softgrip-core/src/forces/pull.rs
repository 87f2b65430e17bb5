//! The mouse spring ([`Pull`]): a material point of a boundary facet pulled
//! towards a target by a spring with critical damping, the force spread
//! over the facet's nodes by the point's barycentric weights (as a contact
//! force is, thesis eq. 37-39). Implicit like every other force, so a stiff
//! pull does not shake the object.

use glam::{DMat3, DVec3};

use crate::model::Model;
use crate::solver::System;
use crate::state::{Pull, State};

/// The pulled point (m) and its velocity.
fn point(model: &Model, state: &State, pull: &Pull) -> Option<(DVec3, DVec3, [u32; 3])> {
    let tri = *model.facets.get(pull.facet as usize)?;
    let w = pull.weights;
    let x = (0..3)
        .map(|a| w[a] * state.positions[tri[a] as usize])
        .sum();
    let v = (0..3)
        .map(|a| w[a] * state.velocities[tri[a] as usize])
        .sum();
    Some((x, v, tri))
}

/// The damping of the pull (N s/m): critical for the point's share of mass.
fn damping(model: &Model, pull: &Pull, tri: [u32; 3]) -> f64 {
    let mass: f64 = (0..3)
        .map(|a| pull.weights[a] * model.mass[tri[a] as usize])
        .sum();
    2.0 * (pull.stiffness.max(0.0) * mass).sqrt()
}

/// The force the spring puts on the object (N), for the viewer.
pub fn force(model: &Model, state: &State) -> Option<DVec3> {
    let pull = state.pull.as_ref()?;
    let (x, v, tri) = point(model, state, pull)?;
    Some(pull.stiffness * (pull.target - x) - damping(model, pull, tri) * v)
}

/// Adds the viewer's pull: a damped spring from the picked surface point to its target.
pub fn accumulate(model: &Model, state: &State, force: &mut [DVec3], system: &mut System) {
    let Some(pull) = state.pull.as_ref() else {
        return;
    };
    let Some((x, v, tri)) = point(model, state, pull) else {
        return;
    };
    let k = pull.stiffness.max(0.0);
    let c = damping(model, pull, tri);
    let total = k * (pull.target - x) - c * v;
    let w = pull.weights;
    let vel = |dof: usize| super::velocity_of(state, dof);
    let j = pull.facet as usize;
    for a in 0..3 {
        let ia = tri[a] as usize;
        force[ia] += w[a] * total;
        let waa = w[a] * w[a];
        system.add_diag(
            ia,
            DMat3::from_diagonal(DVec3::splat(k * waa)),
            DMat3::from_diagonal(DVec3::splat(c * waa)),
            &vel,
        );
        let b = (a + 1) % 3;
        let ww = w[a] * w[b];
        if ww != 0.0 {
            system.add_off(
                &model.springs,
                model.facet_springs[j][a],
                ia,
                tri[b] as usize,
                DMat3::from_diagonal(DVec3::splat(k * ww)),
                DMat3::from_diagonal(DVec3::splat(c * ww)),
                &vel,
            );
        }
    }
}

/// Energy stored in the spring (J).
pub fn energy(model: &Model, state: &State) -> f64 {
    let Some(pull) = state.pull.as_ref() else {
        return 0.0;
    };
    point(model, state, pull).map_or(0.0, |(x, _, _)| {
        0.5 * pull.stiffness * (pull.target - x).length_squared()
    })
}
