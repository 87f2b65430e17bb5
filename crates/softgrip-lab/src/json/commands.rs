//! The typed JSON of the commands that build theirs from the core's figures (`modulus`, `mesh
//! info`, `check`, `grasp`, `run`, `ramp`): what their `--json` writes. The command fills the
//! struct and writes it as a `serde_json::Value` (keys sorted, as [`super::to_value`]). Every
//! field's `///` line is its description in the schema (`docs/schema/`, [`crate::schema`]).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What `softgrip modulus --json` writes: Young's modulus from a compression recording (thesis
/// eq. 49-50).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModulusFigures {
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// Young's modulus, the slope of the line through the initial linear part, Pa.
    pub young_modulus: f64,
    /// The smallest and largest modulus over the candidate ranges, from 2 points up to the
    /// chosen one: how much the answer depends on the range, Pa.
    pub young_modulus_range: [f64; 2],
    /// R^2 of the line, dimensionless.
    pub r_squared: f64,
    /// The strains the line runs through, from and to (dimensionless).
    pub strain_range: [f64; 2],
    /// Points on the line, the unloaded state included.
    pub points: usize,
    /// The line's intercept, its stress at zero strain (the toe), Pa.
    pub intercept_pa: f64,
}

/// What `softgrip mesh info --json` writes: a tetrahedral mesh's figures, or a closed
/// surface's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum MeshFigures {
    /// A tetrahedral mesh (.msh, .node/.ele, .vtk, .vtu), after the checks.
    Tetrahedra(TetMeshFigures),
    /// A closed surface (.stl, .obj), tetrahedralized when a scene uses it.
    Surface(SurfaceFigures),
}

/// A tetrahedral mesh's figures after the checks (`mesh info`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TetMeshFigures {
    /// The mesh file, as given.
    pub file: String,
    /// Nodes.
    pub nodes: usize,
    /// Tetrahedra.
    pub tetrahedra: usize,
    /// Faces on the boundary (those of one tetrahedron only).
    pub boundary_facets: usize,
    /// Total signed volume, m^3.
    pub volume_m3: f64,
    /// The bounding box's lowest and highest corner, m.
    pub bounds_m: [[f64; 3]; 2],
    /// Shortest tetrahedron edge, m.
    pub min_edge_m: f64,
    /// Longest tetrahedron edge, m.
    pub max_edge_m: f64,
    /// Smallest dihedral angle, degrees.
    pub smallest_dihedral_deg: f64,
    /// Worst aspect ratio, longest edge over smallest height (dimensionless).
    pub worst_aspect_ratio: f64,
    /// Connected parts (sharing nodes); 1 for a sound object.
    pub connected_parts: usize,
    /// What reading the file and the checks noted or changed, in words.
    pub warnings: Vec<String>,
}

/// A closed surface's figures (`mesh info` of an .stl or .obj).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceFigures {
    /// The surface file, as given.
    pub file: String,
    /// Always true: the file is a surface.
    pub surface: bool,
    /// Triangles.
    pub triangles: usize,
    /// Vertices, welded.
    pub vertices: usize,
    /// Enclosed volume, m^3.
    pub volume_m3: f64,
    /// Mean edge length, m.
    pub mean_edge_m: f64,
}

/// What `softgrip check --json` writes: the defaults a scene relies on, its mesh and model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckFigures {
    /// Each default applied, as `[table] key = value`.
    pub defaults_applied: Vec<String>,
    /// The mesh the scene's object is.
    pub mesh: CheckMeshFigures,
    /// The model built from the scene.
    pub model: CheckModelFigures,
    /// Warnings about the scene (such as a lattice that folds under its loads), in words.
    pub warnings: Vec<String>,
}

/// The mesh of a scene's object (`check`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckMeshFigures {
    /// Nodes.
    pub nodes: usize,
    /// Tetrahedra.
    pub tetrahedra: usize,
    /// Faces on the boundary (those of one tetrahedron only).
    pub boundary_facets: usize,
    /// Total signed volume, m^3.
    pub volume_m3: f64,
    /// Shortest tetrahedron edge, m.
    pub min_edge_m: f64,
    /// Longest tetrahedron edge, m.
    pub max_edge_m: f64,
    /// Worst shape quality `6 sqrt(2) V / l_rms^3` (1 for a regular tetrahedron).
    pub worst_quality: f64,
}

/// The model of a scene (`check`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckModelFigures {
    /// Springs of the lattice.
    pub springs: usize,
    /// The object's total mass, kg.
    pub mass_kg: f64,
    /// Particles held fixed.
    pub pinned_particles: usize,
    /// Fingers.
    pub fingers: usize,
}

/// What `softgrip grasp --json` writes: a grasp and lift, and with `--boundary` the least
/// friction that holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GraspFigures {
    /// The first finger's friction coefficient (0 without fingers), dimensionless.
    pub friction: f64,
    /// When the lift ends: every lifting finger has moved its travel, s.
    pub lift_end_s: f64,
    /// How far the fingers rose by the lift's end, m.
    pub finger_rise_m: f64,
    /// How far the object's centre of mass rose by the lift's end, m.
    pub object_rise_m: f64,
    /// Seconds held after the lift (`--hold`), s.
    pub hold_s: f64,
    /// How far the object slid down the fingers during the hold, m.
    pub hold_slip_m: f64,
    /// Held: the object slid by less than this over the hold (`--slip-bound`), m.
    pub slip_bound_m: f64,
    /// No particle touched the table at the end.
    pub off_table: bool,
    /// Off the table, risen by more than half the fingers' rise, and slid by less than the
    /// bound.
    pub held: bool,
    /// The friction the force balance asks for, weight over the squeeze (dimensionless); null
    /// without gravity or squeeze.
    pub force_balance_friction: Option<f64>,
    /// With `--boundary`: the least friction that holds, bisected (dimensionless); else null.
    pub boundary_friction: Option<f64>,
    /// With `--boundary`: every friction tried and whether it held, in order; else null.
    pub boundary_tries: Option<Vec<(f64, bool)>>,
}

/// What `softgrip run --json` writes: the state at the end (SI units), each finger's, and the
/// warnings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunFigures {
    /// The scene's file, as given, or `built-in thesis scene`.
    pub scene: String,
    /// Simulated time at the end, s.
    pub time_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock time spent stepping, s (differs run to run).
    pub wall_s: f64,
    /// Each finger at the end, in the scene's order.
    pub fingers: Vec<RunFingerFigures>,
    /// |V - V0| / V0 of the whole object (thesis eq. 47-48), dimensionless.
    pub volume_error: f64,
    /// Finger-facet contacts of the last step.
    pub contacts: usize,
    /// Largest spring-limit violation after projection, relative to rest length.
    pub limit_violation: f64,
    /// Kinetic, elastic, gravity, applied-force and contact energy, J.
    pub energy_j: f64,
    /// Elements turned inside out.
    pub inverted_elements: usize,
    /// What the run warns of (a collapse, a finger that never touched, ...), in words.
    pub warnings: Vec<String>,
}

/// One finger at the end of `run`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunFingerFigures {
    /// The finger's number, from 1.
    pub finger: usize,
    /// How deep the finger is below the object's undeformed surface along its press
    /// direction, m (0 when not pressing into it).
    pub indentation_m: f64,
    /// The finger's move from its start, m.
    pub moved_m: [f64; 3],
    /// Total contact force the object exerts on the finger, N.
    pub contact_force_n: [f64; 3],
    /// Sum of the normal-force magnitudes of its contacts, N.
    pub normal_force_n: f64,
    /// Largest penetration of any of its contacts, m.
    pub penetration_m: f64,
}

/// What `softgrip ramp --json` writes: each load brought to rest in turn on the scene's first
/// force-controlled finger.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RampFigures {
    /// One row per load, in the order given.
    pub loads: Vec<RampRowFigures>,
}

/// One load of `ramp`, at rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RampRowFigures {
    /// The load on the finger, N.
    pub load_n: f64,
    /// How deep the finger is below the object's undeformed surface along its press
    /// direction, m.
    pub indentation_m: f64,
    /// The object's contact force on the finger against the load's direction, N.
    pub contact_force_n: f64,
    /// Largest penetration of any of the finger's contacts, m.
    pub penetration_m: f64,
    /// |V - V0| / V0 of the whole object, dimensionless.
    pub volume_error: f64,
    /// Elements turned inside out.
    pub inverted_elements: usize,
    /// How it came to rest, in words.
    pub to_rest: String,
}
