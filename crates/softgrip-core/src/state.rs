//! The mutable state of a run (MuJoCo's `mjData`): positions, velocities,
//! fingers, contacts and the diagnostics of the last step.

use std::collections::BTreeMap;

use glam::DVec3;

use crate::model::Model;

/// The state of one finger.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FingerState {
    /// The finger's position (its first shape's centre), m.
    pub position: DVec3,
    /// The finger's velocity, m/s.
    pub velocity: DVec3,
    /// Total contact force the object exerts on the finger (N).
    pub contact_force: DVec3,
    /// Sum of the normal-force magnitudes of its contacts (N).
    pub normal_force: f64,
    /// Sum of the tangential forces on the object (N).
    pub tangential_force: DVec3,
    /// Largest penetration of any of its contacts (m).
    pub max_penetration: f64,
    /// Distance moved by velocity control so far (m).
    pub travelled: f64,
    /// The applied force (N): the scene's `force`, changed by quasi-static loading.
    pub applied_force: DVec3,
    /// Held (the viewer drags it): position-driven towards this point along
    /// its free axes, whatever its control mode, until let go (`None`).
    pub held: Option<DVec3>,
    /// How far the last static solve moved it (m): the direction it slid in its guide, which
    /// the guide's friction opposes (`crate::sensitivity`).
    pub last_move: DVec3,
}

/// A material point of the object pulled towards a target by a spring:
/// the viewer's mouse spring (MuJoCo's perturbation). See `forces::pull`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pull {
    /// The boundary facet the point lies on (index into `Model::facets`).
    pub facet: u32,
    /// The point's barycentric weights on the facet.
    pub weights: [f64; 3],
    /// Where the spring's other end is (m).
    pub target: DVec3,
    /// Spring stiffness (N/m); see [`Pull::default_stiffness`].
    pub stiffness: f64,
}

impl Pull {
    /// `2 E h`: about the stiffness of the object under a point load spread
    /// over one facet of size `h` (a half-space pressed over a patch of
    /// radius a is `2 E* a` stiff), so the grabbed point goes about half way
    /// to the mouse.
    pub fn default_stiffness(model: &Model) -> f64 {
        2.0 * model.young_modulus * model.edge_length
    }
}

/// One finger-facet contact of the last step (for output and the viewer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The finger (index into `Model::fingers`).
    pub finger: u32,
    /// The boundary facet touched (index into `Model::facets`).
    pub facet: u32,
    /// The contact point on the facet, m.
    pub point: DVec3,
    /// Unit normal from the finger into the object (the force on the object is along it).
    pub normal: DVec3,
    /// How deep the finger is into the facet along `normal`, m.
    pub penetration: f64,
    /// Magnitude of the normal force (Hunt-Crossley, thesis eq. 26), N.
    pub normal_force: f64,
    /// Tangential force on the object (N).
    pub tangential_force: DVec3,
    /// Stick weight S of eq. 31: 1 sticking, 0 slipping.
    pub stick: f64,
    /// Barycentric weights of the contact point (the H of eq. 38).
    pub weights: [f64; 3],
    /// Which part of the finger touches (`FingerModel::parts`; 0 = its own shape).
    pub part: u32,
    /// Energy stored in the stick spring, `k_stick |d|^2 / 2` (J).
    pub stick_energy: f64,
}

/// What a contact remembers between steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMemory {
    /// Normal speed at first contact (eq. 26's delta-dot-0), floored.
    pub approach_speed: f64,
    /// The stick anchor: a material point of the facet (barycentric) ...
    pub anchor_weights: [f64; 3],
    /// ... and where it should be relative to the finger centre.
    pub anchor_offset: DVec3,
    /// Held sliding: the stick drift kept on the friction cone's edge whatever its length, so
    /// that a linearisation at a sliding equilibrium stays on the sliding branch
    /// (`crate::sensitivity`). Steps never set it.
    pub sliding: bool,
    /// In a static solve, how far the anchor is to be dragged when the solve ends
    /// (`crate::contact::commit`): it stays put over the load increment.
    pub pending: DVec3,
    /// How far the last commit dragged it: a linearisation of that increment puts it back.
    pub dragged: DVec3,
}

/// A boundary particle pressed against a facet of the same object
/// (`contact::self_collision`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfContact {
    /// The boundary particle pressed (index into the positions).
    pub particle: u32,
    /// The facet it presses against (index into `Model::facets`).
    pub facet: u32,
    /// The facet's point closest to the particle.
    pub point: DVec3,
    /// The facet's outward unit normal: the force on the particle is along it.
    pub normal: DVec3,
    /// Force on the particle (N).
    pub force: f64,
    /// How far inside the contact thickness (m).
    pub depth: f64,
}

/// How a particle touches the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TableMode {
    /// Not touching.
    #[default]
    Free,
    /// Held by static friction at its anchor.
    Stick,
    /// Sliding: kinetic friction against `direction`.
    Slip,
}

/// A particle's contact with the table (`contact::table`): its mode, what it
/// remembers between steps, and the forces of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TableContact {
    /// Free, sticking or slipping.
    pub mode: TableMode,
    /// Where the stick spring is tied to the table (z = 0).
    pub anchor: DVec3,
    /// Unit sliding direction in the plane, while slipping.
    pub direction: DVec3,
    /// Depth below z = 0 (m).
    pub penetration: f64,
    /// Normal force on the particle, along +z (N).
    pub normal_force: f64,
    /// Friction force on the particle, in the plane (N).
    pub tangential_force: DVec3,
    /// Sliding speed at the start of the last step (m/s); 0 unless slipping.
    pub last_speed: f64,
    /// How far the last static solve's commit dragged the anchor (`anchor` less where it was
    /// over the solve's increment): a linearisation of that increment puts it back.
    pub dragged: DVec3,
    /// Held sliding: in a static solve's return mapping the friction stays on the Coulomb
    /// disc's edge whatever the stick spring's stretch, so that a linearisation at a sliding
    /// equilibrium stays on the sliding branch (`crate::sensitivity`). Steps never set it.
    pub sliding: bool,
}

/// Diagnostics of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStats {
    /// CG iterations of the step's linear solve.
    pub cg_iterations: usize,
    /// Relative residual |b - A dv| / |b| at the end of CG.
    pub cg_residual: f64,
    /// Kinetic energy of the particles and the fingers, J.
    pub kinetic_energy: f64,
    /// Kinetic + spring (with limit springs) + bulk + gravity + applied-force
    /// + contact (with stick springs) energy (J).
    pub energy: f64,
    /// |V - V0| / V0 of the whole object (thesis eq. 47-48).
    pub volume_error: f64,
    /// Largest spring-limit violation after projection, relative to rest length.
    pub limit_violation: f64,
    /// Jacobi sweeps of the spring-limit projection that moved particles.
    pub projection_sweeps: usize,
    /// Number of finger-facet contacts.
    pub contacts: usize,
    /// Largest particle speed (m/s).
    pub max_speed: f64,
    /// 2-norm of the force on the free components at the step's start (N):
    /// the equilibrium residual the static solver drives to zero.
    pub force_residual: f64,
}

/// The state of a run: what changes as it steps.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct State {
    /// Simulated time, s.
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Position of each particle, m (length: particles).
    pub positions: Vec<DVec3>,
    /// Velocity of each particle, m/s (length: particles).
    pub velocities: Vec<DVec3>,
    /// The state of each finger (length: fingers).
    pub fingers: Vec<FingerState>,
    /// The finger-facet contacts of the last step (length: contacts).
    pub contacts: Vec<Contact>,
    /// Keyed by (finger, facet); ordered, so runs are deterministic.
    pub contact_memory: BTreeMap<(u32, u32), ContactMemory>,
    /// The mouse spring, if the object is being pulled.
    pub pull: Option<Pull>,
    /// One per particle that can touch the table (`Model::table`), in its
    /// order; empty without a table.
    pub table: Vec<TableContact>,
    /// Viscoelastic springs: each spring's Maxwell-arm dashpot extension
    /// (m), in spring order; with neo-Hookean elements each element's viscous Green strain (six
    /// entries: xx, yy, zz, xy, xz, yz); empty unless `[model] prony_g > 0`.
    pub maxwell: Vec<f64>,
    /// This step's self-collision contacts (`[model] self_collision`).
    pub self_contacts: Vec<SelfContact>,
    /// Diagnostics of the last step.
    pub stats: StepStats,
}

impl State {
    /// The undeformed object at rest, fingers at their scene positions.
    pub fn initial(model: &Model) -> State {
        State {
            time: 0.0,
            step: 0,
            positions: model.rest_positions.clone(),
            velocities: vec![DVec3::ZERO; model.particle_count()],
            fingers: model
                .fingers
                .iter()
                .map(|f| FingerState {
                    position: f.initial_position,
                    applied_force: f.force,
                    ..Default::default()
                })
                .collect(),
            contacts: Vec::new(),
            contact_memory: BTreeMap::new(),
            pull: None,
            table: vec![
                TableContact::default();
                model.table.as_ref().map_or(0, |t| t.particles.len())
            ],
            maxwell: if model.spring_law.is_viscoelastic() {
                match model.fem {
                    Some(_) => vec![0.0; 6 * model.tets.len()],
                    None => vec![0.0; model.springs.len()],
                }
            } else {
                Vec::new()
            },
            self_contacts: Vec::new(),
            stats: StepStats::default(),
        }
    }

    /// Number of elements turned inside out (signed volume <= 0).
    pub fn inverted_elements(&self, model: &Model) -> usize {
        model
            .tets
            .iter()
            .filter(|t| {
                let p = t.map(|i| self.positions[i as usize]);
                crate::mesh::signed_volume(p[0], p[1], p[2], p[3]) <= 0.0
            })
            .count()
    }

    /// The object's centre of mass (m), loads' masses included.
    pub fn centre_of_mass(&self, model: &Model) -> DVec3 {
        let total: f64 = model.mass.iter().sum();
        self.positions
            .iter()
            .zip(&model.mass)
            .map(|(x, m)| *x * *m)
            .sum::<DVec3>()
            / total
    }

    /// Total linear momentum of the object and the fingers.
    pub fn momentum(&self, model: &Model) -> DVec3 {
        let object: DVec3 = self
            .velocities
            .iter()
            .zip(&model.mass)
            .map(|(v, m)| *v * *m)
            .sum();
        let fingers: DVec3 = self
            .fingers
            .iter()
            .zip(&model.fingers)
            .map(|(s, f)| s.velocity * f.mass)
            .sum();
        object + fingers
    }
}
