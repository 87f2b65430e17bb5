//! Why a static solve found no equilibrium, in words: what held Newton (elements inside out, a
//! failed step, a stall, an unbalanced force), where, and what to change; and a loaded finger
//! that touches nothing, named before supports or loads are blamed.

use glam::DVec3;

use crate::error::SimError;
use crate::model::Model;

/// Why an iteration was undone.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Failure {
    /// Kept; the largest move (m).
    Still(f64),
    /// The step itself failed (CG, divergence).
    Step(String),
    /// Elements turned inside out, and their centre.
    Inverted(Vec<usize>),
    /// The largest move (m), beyond the limit.
    Moved(f64),
    /// Full steps stopped reducing the residual (N); where the points move most.
    Stalled(f64, DVec3),
}

/// A force-controlled finger with a load that touches nothing, and why: its load pulls it away
/// from the object, the object is not in its path, or it starts far from it. What to change.
pub(super) fn loose_finger(model: &Model, state: &crate::state::State) -> Option<String> {
    for (k, (f, s)) in model.fingers.iter().zip(&state.fingers).enumerate() {
        let load = s.applied_force.length();
        if !f.is_force_controlled() || load == 0.0 || s.normal_force > 0.0 {
            continue;
        }
        let d = s.applied_force / load;
        // Where the scene puts it, against the undeformed object: what the scene can change.
        let (reach, at) = (f.shape.lateral_reach(), f.initial_position);
        // The object's nodes in the finger's path (within its reach of its line of action)...
        let in_path: Vec<f64> = model
            .rest_positions
            .iter()
            .filter(|p| (**p - at).reject_from_normalized(d).length() <= reach)
            .map(|p| (*p - at).dot(d))
            .collect();
        let name = format!(
            "finger {} carries a load of {load:.4} N but touches nothing",
            k + 1
        );
        let why = if in_path.is_empty() {
            format!(
                "{name}: the object is not in its path (it pushes along ({:.3}, {:.3}, {:.3})); place the finger over the object",
                d.x, d.y, d.z
            )
        } else if in_path.iter().all(|x| *x < 0.0) {
            format!(
                "{name}: its load points away from the object, and a contact only pushes; give loads of 0 or more (the direction is the finger's `force`)"
            )
        } else {
            let gap = in_path
                .iter()
                .filter(|x| **x >= 0.0)
                .fold(f64::INFINITY, |a, b| a.min(*b))
                - f.shape.reach_along(d);
            // Placed on the object: it lost touch because the object moved away (no support),
            // which is the object's matter, not the finger's.
            if gap <= 1e-4 {
                continue;
            }
            format!(
                "{name}: the scene puts it {gap:.4} m from the object along its load; place it touching the object: position = [{:.4}, {:.4}, {:.4}]",
                at.x + gap * d.x,
                at.y + gap * d.y,
                at.z + gap * d.z
            )
        };
        return Some(why);
    }
    None
}

/// What can hold Newton's iterations in a stall, and what to do, for `model`: spring limits
/// held by the projection (a lattice's, without limit springs), or contacts switching between
/// sticking and sliding (friction), or on and off. A continuum has no springs to blame.
fn stall_words(model: &Model) -> (&'static str, &'static str) {
    let limits_held = model.fem.is_none()
        && model.limit_stiffness == 0.0
        && (model.tau_s.is_some() || model.tau_c.is_some());
    let friction = model.table.as_ref().is_some_and(|t| t.friction > 0.0)
        || model.fingers.iter().any(|f| f.friction > 0.0);
    if limits_held {
        (
            "springs held at their tau_s / tau_c limits by the projection (whose reaction is no \
             force of the model), or contacts switching",
            "Give the spring limits a stiffness ([model] limit_stiffness, default 1000) so that \
             they act as forces Newton can balance",
        )
    } else if friction {
        (
            "contacts switching between sticking and sliding",
            "No rest found where the contacts hold: check the supports and the load's size; a \
             friction that lets the object slide (a table's) may leave it none",
        )
    } else {
        (
            "contacts switching on and off",
            "No rest found under this load: check the supports (with no friction anywhere \
             nothing holds the object sideways: give the table or a finger one, [support] \
             friction or [[finger]] friction) and the load's size",
        )
    }
}

/// The error for `failure` after `iterations` of a solve to `tolerance`.
pub(super) fn no_equilibrium(
    model: &Model,
    state: &crate::state::State,
    failure: Failure,
    (iterations, tolerance): (usize, f64),
) -> SimError {
    let load: f64 = model
        .fingers
        .iter()
        .zip(&state.fingers)
        .filter(|(f, _)| f.is_force_controlled())
        .map(|(_, s)| s.applied_force.length())
        .sum();
    let centre = |points: &mut dyn Iterator<Item = DVec3>| {
        let (sum, n) = points.fold((DVec3::ZERO, 0.0), |(s, n), p| (s + p, n + 1.0));
        if n > 0.0 { sum / n } else { DVec3::ZERO }
    };
    let stalled = matches!(failure, Failure::Stalled(..));
    let (why, inverted, near, advice) = match failure {
        Failure::Inverted(elements) => {
            let near = centre(
                &mut elements
                    .iter()
                    .flat_map(|&t| model.tets[t].map(|i| state.positions[i as usize])),
            );
            (
                format!(
                    "every step towards it turns {} element(s) inside out near ({:.4}, {:.4}, {:.4}) m",
                    elements.len(),
                    near.x,
                    near.y,
                    near.z
                ),
                elements,
                near,
                "The lattice cannot carry this load there: give the object the bulk term its material \
                 implies ([model] bulk_modulus = E / (3 (1 - 2 nu))), or a smaller load"
                    .to_string(),
            )
        }
        Failure::Step(what) => {
            let near = centre(&mut state.positions.iter().copied());
            (
                format!("the iterations fail ({what})"),
                Vec::new(),
                near,
                "Check the scene's supports (is the object held?) and its loads".to_string(),
            )
        }
        Failure::Stalled(residual, near) => {
            let (cause, advice) = stall_words(model);
            (
                format!(
                    "Newton's iterations stall with {residual:.2e} N unbalanced near \
                     ({:.4}, {:.4}, {:.4}) m: {cause}",
                    near.x, near.y, near.z
                ),
                Vec::new(),
                near,
                advice.to_string(),
            )
        }
        Failure::Still(_) | Failure::Moved(_) => {
            let near = centre(&mut state.positions.iter().copied());
            (
                format!(
                    "after {} iterations the unbalanced force is still above {:.1e} of the load",
                    iterations, tolerance
                ),
                Vec::new(),
                near,
                "The object may be free to move (no support, a frictionless table) or at a \
                 buckling load: check its supports and the load"
                    .to_string(),
            )
        }
    };
    SimError::NoEquilibrium {
        load,
        why,
        inverted,
        near: near.to_array(),
        advice,
        stalled,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Elasticity, Scene};

    /// A stall names springs only where a lattice holds them by the projection; a continuum's
    /// names its contacts (once it blamed "springs held at their tau_s / tau_c limits" on a
    /// neo-Hookean model, which has none).
    #[test]
    fn a_stall_blames_springs_only_on_a_lattice_with_projected_limits() {
        let mut lattice = Scene::thesis();
        lattice.model.limit_stiffness = 0.0;
        lattice.model.tau_s = Some(0.16);
        let model = Model::from_scene(&lattice).expect("lattice");
        assert!(stall_words(&model).0.contains("tau_s"));
        assert!(stall_words(&model).1.contains("limit_stiffness"));
        let mut continuum = lattice.clone();
        continuum.model.elasticity = Elasticity::NeoHookean;
        let model = Model::from_scene(&continuum).expect("continuum");
        let (cause, advice) = stall_words(&model);
        assert!(
            !cause.contains("spring") && !advice.contains("spring"),
            "{cause} / {advice}"
        );
        assert!(
            cause.contains("sticking and sliding"),
            "the finger's friction 0.5: {cause}"
        );
    }
}
