//! Scene files: the interchange format of `docs/formats.md` ("Scene"), with
//! softgrip's compatible extensions (listed in `docs/design/scene-files.md`).
//!
//! The stages, in order: `raw` mirrors the TOML exactly (every key optional, an unknown key an
//! error that names it and the file); `resolve` applies the documented defaults, records which
//! it applied and checks every value against its allowed range, giving the [`Scene`] below;
//! `read` holds the entry points ([`Scene::load`], [`Scene::from_toml_str`]); `to_toml` writes
//! a scene back through the same raw structs, so the keys have one source.

// Errors first: every stage reports through them.
mod error;

// The file as written, and the values its absent keys take.
mod defaults;
mod raw;

// Reading: text -> raw -> resolved.
mod read;
mod resolve;

// Writing: resolved -> raw -> text.
mod to_toml;
mod toml_text;

pub use defaults::{DEFAULT_CG_TOLERANCE, DEFAULT_LIMIT_STIFFNESS, THESIS_SCENE};
pub use error::{SceneError, describe_toml_error};

use std::path::PathBuf;

use glam::DVec3;

// ---------------------------------------------------------------------------
// Resolved layer: every value present and checked.
// ---------------------------------------------------------------------------

/// A fully resolved scene: defaults applied, every value in range.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// `[simulation]`: the time step, the duration, gravity, the solver's settings.
    pub simulation: Simulation,
    /// `[object]`: the soft body's shape, meshing and material.
    pub object: Object,
    /// `[model]`: the elastic law, damping, volume preservation, spring limits.
    pub model: ModelParams,
    /// `[support]`: what holds the object.
    pub support: Support,
    /// `[[fixed]]`: boxes whose particles are pinned, in file order.
    pub fixed: Vec<AaBox>,
    /// `[[load]]`: masses and forces on the particles in boxes, in file order.
    pub loads: Vec<Load>,
    /// `[[finger]]`: the rigid fingers, in file order.
    pub fingers: Vec<Finger>,
    /// `[[region]]`: boxes of other material (softgrip).
    pub regions: Vec<Region>,
    /// `[grasp]`: what the grasp window asks of the grip (softgrip).
    pub grasp: Grasp,
    /// Where the scene came from (for error messages and relative mesh paths).
    pub source: Option<PathBuf>,
    /// `table.key = value` of every default the resolver applied.
    pub defaults_applied: Vec<String>,
}

/// `[simulation]`: time stepping, gravity and the linear solver's limits.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// Implicit Euler time step, s.
    pub dt: f64,
    /// Length of a plain run, s.
    pub duration: f64,
    /// Gravitational acceleration, m/s^2.
    pub gravity: DVec3,
    /// Relative residual at which the conjugate gradient stops.
    pub cg_tolerance: f64,
    /// Iteration cap of the conjugate gradient; reaching it is an error.
    pub cg_max_iterations: usize,
    /// How a quasi-static load comes to rest in replays and ramps.
    pub settle: Settle,
}

/// How a quasi-static load comes to rest (`[simulation] settle`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Settle {
    /// The static equilibrium, by Newton's method (`crate::equilibrium`).
    #[default]
    Static,
    /// Time steps until nothing moves (`Simulation::settle`).
    Dynamic,
}

impl Settle {
    /// Its name in a scene file: "static" or "dynamic".
    pub fn as_str(self) -> &'static str {
        match self {
            Settle::Static => "static",
            Settle::Dynamic => "dynamic",
        }
    }
}

/// `[object] shape`: the object's geometry. The built-in shapes are centred on x = y = 0 with
/// their bottom at z = 0.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A box.
    Cuboid {
        /// Extents along x, y, z, m.
        size: DVec3,
    },
    /// A cylinder, its axis along z.
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Height, m.
        height: f64,
    },
    /// A mesh file, its coordinates times `scale` (0.001 for a file in
    /// millimetres), placed with the centre of its bounding box's bottom
    /// face at `position` (default the origin: centred at x = y = 0,
    /// bottom at z = 0, as the built-in shapes).
    Mesh {
        /// The mesh file; relative paths are joined to the scene file's folder on load.
        path: PathBuf,
        /// Multiplies the file's coordinates.
        scale: f64,
        /// Where the centre of the bounding box's bottom face goes, m.
        position: DVec3,
    },
}

/// `[object]`: the soft object.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// Its geometry.
    pub shape: Shape,
    /// Target tetrahedron edge for the built-in shapes and surface meshes, m.
    pub edge_length: f64,
    /// Mass density, kg/m^3.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young_modulus: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
}

/// `[model]`: the model's terms and options.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelParams {
    /// Each spring's damping as a fraction of its critical damping (1 = critical).
    pub damping_ratio: f64,
    /// Rayleigh damping `D = a M + b K`, its mass-proportional a (1/s): each
    /// particle's `-a m v`, which damps rigid motion too; 0 = off (softgrip;
    /// `forces::viscosity`) ...
    pub rayleigh_mass: f64,
    /// ... and its stiffness-proportional b (s): a dashpot `b k` along each
    /// spring, or a Kelvin-Voigt viscosity `2 mu b` on each element's Green
    /// strain rate; neither damps rigid motion. 0 = off.
    pub rayleigh_stiffness: f64,
    /// Scale of the volume-preservation force (thesis eq. 10-11), N/m^3; 0 = none.
    pub alpha: f64,
    /// Element volumetric stiffness (Pa); 0 = off (the thesis model). See
    /// `forces::volume`.
    pub bulk_modulus: f64,
    /// Where the bulk term measures the volume change: per element, or
    /// averaged over each node's elements (softgrip; `forces::volume`).
    pub bulk_pressure: BulkPressure,
    /// Stiffness of the limit springs, as a multiple of each spring's own
    /// (a softgrip extension); 0 = the projection alone (thesis Alg. 3). See
    /// `forces::springs`.
    pub limit_stiffness: f64,
    /// Over-stretch limit; `None` = no limit (the key omitted).
    pub tau_s: Option<f64>,
    /// Over-compression limit; `None` = no limit (the key omitted).
    pub tau_c: Option<f64>,
    /// Sweeps of the spring-limit projection per step (thesis Alg. 3).
    pub constraint_iterations: usize,
    /// Keep projecting past `constraint_iterations` until no spring is
    /// outside its limits by more than this fraction of its rest length
    /// (a softgrip extension; `None` = exactly `constraint_iterations`
    /// sweeps, as the thesis).
    pub constraint_tolerance: Option<f64>,
    /// Strain stiffening, beta: each spring's `F = k dl (1 + beta e^2)`
    /// with `e = dl / l0`, or for neo-Hookean elements the energy's
    /// `mu beta / 12 max(I1 - 3, 0)^2` (the same share at small uniaxial
    /// strain, `forces::fem`); 0 = the thesis's linear spring (softgrip).
    pub stiffening: f64,
    /// Neo-Hookean elements only: a third-order term, gamma, the energy's
    /// `mu gamma / 54 max(I1 - 3, 0)^3` (Yeoh's C30 form; at small uniaxial
    /// strain the shear modulus grows by `gamma e^4`) ...
    pub stiffening_cubic: f64,
    /// ... and an early softening q in [0, 1): a second-order term of
    /// `-2 q sqrt(gamma)` beside `stiffening`, so that the shear modulus
    /// first dips (to `1 - q^2` of mu at the lowest, with `stiffening` 0)
    /// and then stiffens, as filled silicones do (a two-term Yeoh solid
    /// with C20 < 0 < C30); never below zero for any q < 1
    /// (`forces::fem`). 0 = none (softgrip).
    pub softening: f64,
    /// Neo-Hookean elements only: Gent's limit J_m of `I1bar - 3`, where the material locks
    /// (its energy `-mu J_m / 2 ln(1 - (I1bar - 3) / J_m)` in place of the neo-Hookean term's
    /// growth; the shear modulus is `mu J_m / (J_m - s)`). 0 = none (softgrip).
    pub gent_limit: f64,
    /// A spring's stiffness in compression over its stiffness in tension;
    /// 1 = symmetric, the thesis (softgrip).
    pub compression_ratio: f64,
    /// Viscoelastic springs, one Prony term: the relative modulus g that
    /// relaxes (0 = elastic, the thesis) ...
    pub prony_g: f64,
    /// ... with this time constant (s) (softgrip).
    pub prony_tau: f64,
    /// The elastic model: the thesis's springs, or neo-Hookean elements
    /// (softgrip; `forces::fem`).
    pub elasticity: Elasticity,
    /// Self-collision of the object's surface (softgrip;
    /// `contact::self_collision`).
    pub self_collision: bool,
}

/// `[model] bulk_pressure`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BulkPressure {
    /// Each element's own volume change (a linear tetrahedron's constant
    /// pressure: it locks as nu nears 1/2).
    Element,
    /// The volume change of each node's share of its elements, averaged to
    /// the elements (average nodal pressure, Bonet and Burton 1998): one
    /// volume constraint per node instead of about six, which locks much
    /// less on the same mesh.
    Nodal,
}

/// `[model] elasticity`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Elasticity {
    /// The thesis's mass-spring lattice (eq. 3-12).
    Springs,
    /// Linear tetrahedra with the stable neo-Hookean energy.
    NeoHookean,
}

/// `[support] kind`: what holds the object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SupportKind {
    /// The particles at z = 0 are pinned.
    FixedBottom,
    /// The object rests on the plane z = 0, free to slide, tip and lift off.
    Table,
    /// Nothing holds it.
    None,
}

/// `[support]`: what holds the object.
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    /// What holds it.
    pub kind: SupportKind,
    /// Coulomb coefficient between object and table (a table only).
    pub friction: f64,
}

/// An axis-aligned box, closed (a point on the boundary is inside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AaBox {
    /// Lower corner, m.
    pub min: DVec3,
    /// Upper corner, m.
    pub max: DVec3,
}

impl AaBox {
    /// Whether `p` lies inside or on the boundary.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// A box of other material (`[[region]]`, softgrip): the elements whose
/// centroid lies inside take its Young's modulus and density (the last
/// region containing them wins).
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// The box.
    pub region: AaBox,
    /// Young's modulus of its elements, Pa.
    pub young_modulus: f64,
    /// Density of its elements, kg/m^3.
    pub density: f64,
}

/// `[[load]]`: a mass and a force shared evenly by the particles in a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// The box.
    pub region: AaBox,
    /// A mass hanging from them (its weight and its inertia), kg.
    pub mass: f64,
    /// An extra constant force, N.
    pub force: DVec3,
}

/// A finger's (or a part's) rigid shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FingerShape {
    /// A sphere centred on the finger's position.
    Sphere {
        /// Radius, m.
        radius: f64,
    },
    /// A rigid square plate, face normal -z; `half_size` are half its x, y extents.
    Plate {
        /// Half its x, y extents, m.
        half_size: [f64; 2],
    },
    /// A rigid axis-aligned box (cuboid) centred on the finger; `half_size`
    /// are half its x, y, z extents (softgrip).
    Box {
        /// Half its x, y, z extents, m.
        half_size: [f64; 3],
    },
}

/// One more rigid shape of a compound finger (`[[finger.part]]`), carried
/// at `offset` from the finger's position (softgrip).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerPart {
    /// Its shape.
    pub shape: FingerShape,
    /// Its centre relative to the finger's position, m.
    pub offset: DVec3,
}

impl FingerShape {
    /// How far the finger's pressing surface lies from its centre (m): the
    /// sphere's radius; 0 for a plate, whose centre is on its face.
    pub fn reach(&self) -> f64 {
        self.reach_along(DVec3::NEG_Z)
    }

    /// How far the finger reaches sideways from its line of action (m): the sphere's radius,
    /// the half diagonal of a plate or of a box's face (what lies under it when it presses).
    pub fn lateral_reach(&self) -> f64 {
        match *self {
            FingerShape::Sphere { radius } => radius,
            FingerShape::Plate { half_size } => half_size[0].hypot(half_size[1]),
            FingerShape::Box { half_size } => half_size[0].hypot(half_size[1]),
        }
    }

    /// Its largest extent (m): a sphere's diameter, a plate's or box's longest side.
    pub fn size(&self) -> f64 {
        match *self {
            FingerShape::Sphere { radius } => 2.0 * radius,
            FingerShape::Plate { half_size } => 2.0 * half_size[0].max(half_size[1]),
            FingerShape::Box { half_size } => 2.0 * half_size.iter().fold(0.0f64, |a, b| a.max(*b)),
        }
    }

    /// How far the finger's surface lies from its centre along the unit
    /// direction `d` (m): the radius, 0 for a plate, the box's support
    /// distance `sum |d_i| h_i` (its half height for -z).
    pub fn reach_along(&self, d: DVec3) -> f64 {
        match *self {
            FingerShape::Sphere { radius } => radius,
            FingerShape::Plate { .. } => 0.0,
            FingerShape::Box { half_size } => d.abs().dot(DVec3::from_array(half_size)),
        }
    }
}

/// `[[finger]] control`: how a finger's free axes are driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Pushed by `force`, plus its weight when it has a mass.
    Force,
    /// Moved at `velocity`, except free axes with a non-zero `force` component.
    Velocity,
}

/// `[[finger]]`: a rigid finger pressing on the object.
#[derive(Debug, Clone, PartialEq)]
pub struct Finger {
    /// Its main shape, centred on its position.
    pub shape: FingerShape,
    /// More shapes moving with it (a compound finger); empty for one shape.
    pub parts: Vec<FingerPart>,
    /// Its starting position, m: the sphere's or box's centre, the plate's (on its face).
    pub position: DVec3,
    /// The axes x, y, z along which it may move; the others are held.
    pub free_axes: [bool; 3],
    /// How its free axes are driven.
    pub control: Control,
    /// The driving force, N.
    pub force: DVec3,
    /// The driving velocity, m/s.
    pub velocity: DVec3,
    /// Its mass, kg (its weight acts on its force-driven axes); 0 = a light guide.
    pub mass: f64,
    /// Its Young's modulus, for the contact stiffness (thesis eq. 27-28), Pa.
    pub young_modulus: f64,
    /// Its Poisson's ratio, for the contact stiffness.
    pub poisson_ratio: f64,
    /// Hunt-Crossley coefficient of restitution of its contacts.
    pub restitution: f64,
    /// Coulomb coefficient between object and finger.
    pub friction: f64,
    /// Slip speed of the stick-slip transition (thesis eq. 31), m/s.
    pub stick_velocity: f64,
    /// Stiffness of the stick spring (thesis eq. 35), N/m.
    pub stick_stiffness: f64,
    /// Damping of the stick spring (thesis eq. 36), N s/m.
    pub stick_damping: f64,
    /// Velocity control: stop after this distance (m); `None` = never stop.
    pub travel: Option<f64>,
    /// Velocity-driven axes hold still until this time (s).
    pub start_time: f64,
    /// ... and then reach their velocity linearly over this time (s).
    pub ramp_time: f64,
    /// Coulomb friction in the finger's guide (N) on its force-driven axes:
    /// against its motion, and holding it while the forces on it are
    /// smaller (softgrip).
    pub guide_friction: f64,
    /// Mass-less force control: approach speed before contact (m/s).
    pub guide_speed: f64,
    /// Multiplies the contact stiffness of thesis eq. 27 (1 = the thesis).
    pub contact_stiffness_scale: f64,
}

impl Finger {
    /// Is `axis` driven by velocity (true) or by force (false)? Only meaningful
    /// for free axes. The spec: under velocity control a free axis with a
    /// non-zero force component stays force-driven.
    pub fn axis_is_velocity_driven(&self, axis: usize) -> bool {
        self.control == Control::Velocity && self.force[axis] == 0.0
    }
}

/// What can damage the object, for the grasp window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DamageMeasure {
    /// The largest principal Green strain, per element.
    Strain,
    /// The von Mises Cauchy stress (Pa), per element.
    Stress,
    /// The fingers' contact pressure (Pa), per surface node.
    Pressure,
}

impl DamageMeasure {
    /// Every measure, in declaration order.
    pub const ALL: [DamageMeasure; 3] = [
        DamageMeasure::Strain,
        DamageMeasure::Stress,
        DamageMeasure::Pressure,
    ];

    /// Its name in a scene file and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DamageMeasure::Strain => "strain",
            DamageMeasure::Stress => "stress",
            DamageMeasure::Pressure => "pressure",
        }
    }

    /// The measure of that name ([`DamageMeasure::name`]), if any.
    pub fn from_name(name: &str) -> Option<DamageMeasure> {
        DamageMeasure::ALL.into_iter().find(|m| m.name() == name)
    }

    /// What it is, for a sentence.
    pub fn describe(self) -> &'static str {
        match self {
            DamageMeasure::Strain => "largest principal Green strain",
            DamageMeasure::Stress => "von Mises stress",
            DamageMeasure::Pressure => "contact pressure",
        }
    }

    /// SI unit ("" for a strain).
    pub fn unit(self) -> &'static str {
        match self {
            DamageMeasure::Strain => "",
            DamageMeasure::Stress | DamageMeasure::Pressure => "Pa",
        }
    }
}

/// A material of the damage-limit table: `[grasp] material`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamageMaterial {
    /// Its name in a scene file (`"apple"`).
    pub name: &'static str,
    /// Each measure's limit, where the source gives one: the Green strain ...
    pub strain: Option<f64>,
    /// ... the von Mises stress, Pa ...
    pub stress: Option<f64>,
    /// ... and the contact pressure, Pa.
    pub pressure: Option<f64>,
    /// Where the figures come from.
    pub source: &'static str,
}

impl DamageMaterial {
    /// Its limit of `measure`, in the measure's unit, where the source gives one.
    pub fn limit(&self, measure: DamageMeasure) -> Option<f64> {
        match measure {
            DamageMeasure::Strain => self.strain,
            DamageMeasure::Stress => self.stress,
            DamageMeasure::Pressure => self.pressure,
        }
    }
}

/// The silicones' tensile break (ASTM D412 die C at 450 mm/min, one curve each, the Soft
/// Robotics Materials Database): the Green strain `(lambda^2 - 1) / 2` of the break's stretch
/// and the true stress there. Crosshead strain, so the break stretch is an upper bound (about
/// twice the datasheets' elongation at break). Apple flesh: no bruise below a contact pressure
/// of 0.10 MPa, flesh failure stress 0.29 MPa (Wang, Wang and Wu, Processes 12 (2024) 543).
pub const DAMAGE_MATERIALS: [DamageMaterial; 5] = [
    DamageMaterial {
        name: "ecoflex-00-10",
        strain: Some(163.1),
        stress: Some(16.7e6),
        pressure: None,
        source: "Soft Robotics Materials Database, tensile break (upper bound)",
    },
    DamageMaterial {
        name: "ecoflex-00-30",
        strain: Some(145.2),
        stress: Some(23.2e6),
        pressure: None,
        source: "Soft Robotics Materials Database, tensile break (upper bound)",
    },
    DamageMaterial {
        name: "ecoflex-00-50",
        strain: Some(151.0),
        stress: Some(34.5e6),
        pressure: None,
        source: "Soft Robotics Materials Database, tensile break (upper bound)",
    },
    DamageMaterial {
        name: "dragon-skin-10",
        strain: Some(64.6),
        stress: Some(21.0e6),
        pressure: None,
        source: "Soft Robotics Materials Database, tensile break (upper bound)",
    },
    DamageMaterial {
        name: "apple",
        strain: None,
        stress: Some(0.29e6),
        pressure: Some(0.10e6),
        source: "Wang, Wang and Wu, Processes 12 (2024) 543: no bruise below 0.10 MPa; flesh failure stress 0.29 MPa",
    },
];

/// `[grasp]` (softgrip): the lift the grip must hold through and the damage limit of the grasp
/// window (`softgrip grasp window`). Every key may be left out: the command's options or its
/// defaults stand in.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Grasp {
    /// Upward acceleration of the lift (m/s^2).
    pub acceleration: Option<f64>,
    /// Sideways acceleration (m/s^2), across gravity and the squeeze.
    pub shake: Option<f64>,
    /// The contacts' mean slide allowed as the object takes its load (m).
    pub slip_tolerance: Option<f64>,
    /// Seconds held in the dynamic confirmation.
    pub hold: Option<f64>,
    /// The damage measure the grip may not bring to its limit anywhere in the object.
    pub damage: Option<DamageMeasure>,
    /// The damage measure's limit, in its unit.
    pub limit: Option<f64>,
    /// A material of [`DAMAGE_MATERIALS`], whose limit stands in for `limit`.
    pub material: Option<DamageMaterial>,
}
