//! The force stages of a step: the one list that the time step, the static solver
//! (`crate::equilibrium`, through `Simulation::assemble_here`) and the support reaction
//! (`Simulation::reaction`) assemble, each stage timed.
//!
//! A stage adds its forces to the force vector (particles, then fingers) and its negative
//! Jacobians to the system of eq. 43. The thesis's Fig. 9 groups them as forces (springs,
//! gravity and loads, eq. 3-4), contact (eq. 5, 18-39) and volume (eq. 10-12); softgrip adds
//! the bulk term, the neo-Hookean elements, Rayleigh damping, the Prony arms, the table, the
//! viewer's pull and self-collision. The work is split between the main thread ([`MAIN`]) and
//! a helper ([`HELPER`], `step/parallel.rs`): the springs on the helper, the element and dashpot
//! passes half on each. Each list is in the order its sums run; the helper's forces are added
//! after the main thread's, so the result is the same bit for bit on one thread or two.

use std::ops::Range;
use std::time::Instant;

use glam::DVec3;

use crate::contact::{self, ContactScratch};
use crate::forces;
use crate::model::Model;
use crate::solver::System;
use crate::state::State;

/// One force stage of the assembly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The springs (eq. 3-4) with their limit springs, under the model's spring law; with
    /// neo-Hookean elements only their dampers (eq. 4), the elasticity being the elements'.
    Springs,
    /// Gravity and constant loads on the particles, the fingers' drive and guides.
    External,
    /// The viewer's mouse pull on a surface point.
    Pull,
    /// Finger contact: Hunt-Crossley normal force and stick-slip friction (eq. 5, 18-39).
    FingerContact,
    /// The table under the object: penalty contact with friction.
    TableContact,
    /// The object's surface against itself.
    SelfCollision,
    /// The volume term averaged per node (`bulk_pressure = "nodal"`): once, over every element.
    NodalVolume,
    /// The elements' share: eq. 10-12's volume preservation and the bulk term, or, in a
    /// neo-Hookean model, the elements' elastic forces (`forces::fem`).
    Elements,
    /// Rayleigh's mass-proportional damping.
    MassDamping,
    /// Rayleigh's stiffness-proportional dashpots along the springs' share.
    Dashpots,
    /// The neo-Hookean elements' Maxwell (Prony) arms, the elements' share: viscoelastic creep.
    Arms,
    /// The neo-Hookean elements' Kelvin-Voigt (Rayleigh stiffness) viscosity, the elements' share.
    ElementDamping,
}

impl Stage {
    /// Every stage, in the thesis's order (forces, contact, volume; then the damping terms), as
    /// [`StageSeconds::stages`](super::StageSeconds) keeps them.
    pub const ALL: [Stage; 12] = [
        Stage::Springs,
        Stage::External,
        Stage::Pull,
        Stage::FingerContact,
        Stage::TableContact,
        Stage::SelfCollision,
        Stage::NodalVolume,
        Stage::Elements,
        Stage::MassDamping,
        Stage::Dashpots,
        Stage::Arms,
        Stage::ElementDamping,
    ];

    /// A short name for tables of timings.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Springs => "springs",
            Stage::NodalVolume => "nodal volume",
            Stage::External => "external",
            Stage::MassDamping => "mass damping",
            Stage::Pull => "pull",
            Stage::FingerContact => "finger contact",
            Stage::TableContact => "table contact",
            Stage::SelfCollision => "self-collision",
            Stage::Elements => "elements",
            Stage::Dashpots => "dashpots",
            Stage::Arms => "Prony arms",
            Stage::ElementDamping => "element damping",
        }
    }
}

/// The main thread's stages, in the order their forces are summed. The nodal volume term comes
/// first: it needs every element's volume before any element's share runs.
pub const MAIN: [Stage; 11] = [
    Stage::NodalVolume,
    Stage::External,
    Stage::MassDamping,
    Stage::Pull,
    Stage::FingerContact,
    Stage::TableContact,
    Stage::SelfCollision,
    Stage::Elements,
    Stage::Dashpots,
    Stage::Arms,
    Stage::ElementDamping,
];

/// The helper thread's stages (run by the main thread when there is no helper), summed into
/// their own buffers and added after [`MAIN`]'s.
pub const HELPER: [Stage; 5] = [
    Stage::Springs,
    Stage::Dashpots,
    Stage::Elements,
    Stage::Arms,
    Stage::ElementDamping,
];

/// The share of the split passes one thread takes.
#[derive(Debug, Clone)]
pub struct Share {
    /// Elements (indices into `model.tets`).
    pub elements: Range<usize>,
    /// Springs whose Rayleigh dashpots it assembles (indices into `model.springs`).
    pub springs: Range<usize>,
}

/// What one thread's stages keep between steps: the contact stages' buffers and the time
/// spent in each stage.
#[derive(Debug, Default, Clone)]
pub struct StageScratch {
    /// Finger contact's buffers.
    pub contact: ContactScratch,
    /// Self-collision's buffers.
    pub self_collision: contact::self_collision::SelfScratch,
    /// Wall-clock seconds spent in each stage so far, s (indexed as [`Stage::ALL`]).
    pub seconds: [f64; Stage::ALL.len()],
}

/// Runs `stages` in order at `state`, adding into `force` and `system`; each stage's time goes
/// to `scratch.seconds`.
pub fn run(
    stages: &[Stage],
    model: &Model,
    state: &mut State,
    force: &mut [DVec3],
    system: &mut System,
    share: &Share,
    scratch: &mut StageScratch,
) {
    let mut mark = Instant::now();
    for &stage in stages {
        let elements = share.elements.clone();
        match stage {
            Stage::Springs => match &model.fem {
                Some(_) => forces::springs::accumulate_dampers(model, state, force, system),
                None => forces::springs::accumulate(model, state, force, system),
            },
            Stage::NodalVolume => forces::volume::nodal(model, state, force, system),
            Stage::External => forces::external::accumulate(model, state, force, system),
            Stage::MassDamping => forces::viscosity::accumulate_mass(model, state, force, system),
            Stage::Pull => forces::pull::accumulate(model, state, force, system),
            Stage::FingerContact => {
                contact::accumulate(model, state, force, system, &mut scratch.contact);
            }
            Stage::TableContact => contact::table::accumulate(model, state, force, system),
            Stage::SelfCollision => contact::self_collision::accumulate(
                model,
                state,
                force,
                system,
                &mut scratch.self_collision,
            ),
            Stage::Elements => match &model.fem {
                Some(fem) => {
                    forces::fem::accumulate_elements(model, fem, state, force, system, elements);
                }
                None => forces::volume::accumulate_elements(model, state, force, system, elements),
            },
            Stage::Dashpots => {
                let springs = share.springs.clone();
                forces::viscosity::accumulate_dashpots(model, state, force, system, springs);
            }
            Stage::Arms => {
                forces::viscosity::accumulate_arms(model, state, force, system, elements)
            }
            Stage::ElementDamping => {
                forces::viscosity::accumulate_element_damping(
                    model, state, force, system, elements,
                );
            }
        }
        let now = Instant::now();
        scratch.seconds[stage as usize] += (now - mark).as_secs_f64();
        mark = now;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stage's index in [`Stage::ALL`] is its discriminant (the timings are kept by it).
    #[test]
    fn all_lists_each_stage_at_its_own_index() {
        for (k, stage) in Stage::ALL.iter().enumerate() {
            assert_eq!(*stage as usize, k, "{stage:?}");
        }
    }

    /// The split passes (elements, dashpots, arms, element damping) run on both threads, each on
    /// its share; every other stage on exactly one of them, once.
    #[test]
    fn each_stage_runs_once_or_once_per_share() {
        let split = [
            Stage::Elements,
            Stage::Dashpots,
            Stage::Arms,
            Stage::ElementDamping,
        ];
        for stage in Stage::ALL {
            let main = MAIN.iter().filter(|&&s| s == stage).count();
            let helper = HELPER.iter().filter(|&&s| s == stage).count();
            let expected = if split.contains(&stage) { 2 } else { 1 };
            assert_eq!(main + helper, expected, "{stage:?}");
            if split.contains(&stage) {
                assert_eq!((main, helper), (1, 1), "{stage:?}");
            }
        }
    }
}
