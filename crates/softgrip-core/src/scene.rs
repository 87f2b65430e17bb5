//! Scene files: the interchange contract of `shared/spec/scene-and-recording.md`.
//!
//! Parsing happens in two layers. `RawScene` mirrors the TOML exactly, every
//! key optional and unknown keys rejected (`deny_unknown_fields`), so a typo is
//! an error that names the key and the file. The resolver then applies the
//! documented defaults (the thesis values), records which ones it applied, and
//! checks every value against its allowed range.
//!
//! Extensions to the contract (compatible: older files never use them):
//! - `[simulation] cg_tolerance`, `cg_max_iterations`: the linear solver.
//! - `[[finger]] travel`: a velocity-controlled finger stops after moving this
//!   far (m), so a pinch can squeeze and then hold.
//! - `[[finger]] guide_speed`: the speed (m/s) at which a mass-less
//!   force-controlled finger approaches before contact (see `model::finger`).
//! - `[[finger]] contact_stiffness_scale`: multiplies eq. 27's contact
//!   stiffness (the lattice already carries the object's compliance; see
//!   ARCHITECTURE.md, choice 10).
//! - `[[finger]] guide_friction`: Coulomb friction (N) in the finger's
//!   guide, so loading and unloading paths differ.
//! - `[[finger]] start_time`, `ramp_time`: velocity-driven axes hold still
//!   until `start_time` (s), then reach their velocity linearly over
//!   `ramp_time` (s), so a grasp can squeeze first and then lift smoothly.
//! - `[[finger]] shape = "box"` with `size = [x, y, z]`, and
//!   `[[finger.part]]` (`shape`, `radius` or `size`, `offset`): box fingers
//!   and fingers of several rigid shapes.
//! - `[support] kind = "table"` is the spec's; its contact law is ours
//!   (`contact::table`).

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;

/// A scene error: what is wrong, where, and what to do.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}: {source}. Check the path and its permissions.")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{file}: {message}")]
    Syntax { file: String, message: String },
    #[error("{file}{line}: {table}{key} = {value} is not allowed: {rule}")]
    Value {
        file: String,
        line: String,
        table: String,
        key: String,
        value: String,
        rule: String,
    },
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
}

// ---------------------------------------------------------------------------
// Raw layer: the file as written.
// ---------------------------------------------------------------------------

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    simulation: Option<RawSimulation>,
    object: Option<RawObject>,
    model: Option<RawModel>,
    support: Option<RawSupport>,
    #[serde(default)]
    fixed: Vec<RawBox>,
    #[serde(default)]
    load: Vec<RawLoad>,
    #[serde(default)]
    finger: Vec<RawFinger>,
    #[serde(default)]
    region: Vec<RawRegion>,
    #[allow(dead_code)] // free-form by contract; kept so it parses
    extra: Option<toml::Table>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSimulation {
    dt: Option<f64>,
    duration: Option<f64>,
    gravity: Option<[f64; 3]>,
    cg_tolerance: Option<f64>,
    cg_max_iterations: Option<i64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    shape: Option<String>,
    size: Option<[f64; 3]>,
    radius: Option<f64>,
    height: Option<f64>,
    path: Option<String>,
    scale: Option<f64>,
    position: Option<[f64; 3]>,
    edge_length: Option<f64>,
    density: Option<f64>,
    young_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawModel {
    damping_ratio: Option<f64>,
    alpha: Option<f64>,
    bulk_modulus: Option<f64>,
    bulk_pressure: Option<String>,
    limit_stiffness: Option<f64>,
    tau_s: Option<f64>,
    tau_c: Option<f64>,
    constraint_iterations: Option<i64>,
    constraint_tolerance: Option<f64>,
    stiffening: Option<f64>,
    stiffening_cubic: Option<f64>,
    softening: Option<f64>,
    compression_ratio: Option<f64>,
    prony_g: Option<f64>,
    prony_tau: Option<f64>,
    elasticity: Option<String>,
    self_collision: Option<bool>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSupport {
    kind: Option<String>,
    friction: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBox {
    min: [f64; 3],
    max: [f64; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoad {
    min: [f64; 3],
    max: [f64; 3],
    mass: Option<f64>,
    force: Option<[f64; 3]>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFinger {
    shape: Option<String>,
    radius: Option<f64>,
    /// `[x, y]` for a plate, `[x, y, z]` for a box.
    size: Option<Vec<f64>>,
    /// `[[finger.part]]`: more rigid shapes moving with the finger.
    part: Option<Vec<RawPart>>,
    position: Option<[f64; 3]>,
    free_axes: Option<String>,
    control: Option<String>,
    force: Option<[f64; 3]>,
    velocity: Option<[f64; 3]>,
    mass: Option<f64>,
    young_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    restitution: Option<f64>,
    friction: Option<f64>,
    stick_velocity: Option<f64>,
    stick_stiffness: Option<f64>,
    stick_damping: Option<f64>,
    travel: Option<f64>,
    start_time: Option<f64>,
    ramp_time: Option<f64>,
    guide_speed: Option<f64>,
    guide_friction: Option<f64>,
    contact_stiffness_scale: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRegion {
    min: [f64; 3],
    max: [f64; 3],
    young_modulus: Option<f64>,
    density: Option<f64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPart {
    shape: Option<String>,
    radius: Option<f64>,
    size: Option<Vec<f64>>,
    offset: Option<[f64; 3]>,
}

// ---------------------------------------------------------------------------
// Resolved layer: every value present and checked.
// ---------------------------------------------------------------------------

/// A fully resolved scene: defaults applied, every value in range.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub simulation: Simulation,
    pub object: Object,
    pub model: ModelParams,
    pub support: Support,
    pub fixed: Vec<AaBox>,
    pub loads: Vec<Load>,
    pub fingers: Vec<Finger>,
    /// `[[region]]`: boxes of other material (softgrip).
    pub regions: Vec<Region>,
    /// Where the scene came from (for error messages and relative mesh paths).
    pub source: Option<PathBuf>,
    /// `table.key = value` of every default the resolver applied.
    pub defaults_applied: Vec<String>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    pub dt: f64,
    pub duration: f64,
    pub gravity: DVec3,
    pub cg_tolerance: f64,
    pub cg_max_iterations: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Cuboid {
        size: DVec3,
    },
    Cylinder {
        radius: f64,
        height: f64,
    },
    /// A mesh file, its coordinates times `scale` (0.001 for a file in
    /// millimetres), placed with the centre of its bounding box's bottom
    /// face at `position` (default the origin: centred at x = y = 0,
    /// bottom at z = 0, as the built-in shapes).
    Mesh {
        path: PathBuf,
        scale: f64,
        position: DVec3,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    pub shape: Shape,
    pub edge_length: f64,
    pub density: f64,
    pub young_modulus: f64,
    pub poisson_ratio: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ModelParams {
    pub damping_ratio: f64,
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

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SupportKind {
    FixedBottom,
    Table,
    None,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    pub kind: SupportKind,
    pub friction: f64,
}

/// An axis-aligned box, closed (a point on the boundary is inside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AaBox {
    pub min: DVec3,
    pub max: DVec3,
}

impl AaBox {
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// A box of other material (`[[region]]`, softgrip): the elements whose
/// centroid lies inside take its Young's modulus and density (the last
/// region containing them wins).
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    pub region: AaBox,
    pub young_modulus: f64,
    pub density: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    pub region: AaBox,
    pub mass: f64,
    pub force: DVec3,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FingerShape {
    Sphere {
        radius: f64,
    },
    /// A rigid square plate, face normal -z; `half_size` are half its x, y extents.
    Plate {
        half_size: [f64; 2],
    },
    /// A rigid axis-aligned box (cuboid) centred on the finger; `half_size`
    /// are half its x, y, z extents (softgrip).
    Box {
        half_size: [f64; 3],
    },
}

/// One more rigid shape of a compound finger (`[[finger.part]]`), carried
/// at `offset` from the finger's position (softgrip).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerPart {
    pub shape: FingerShape,
    pub offset: DVec3,
}

impl FingerShape {
    /// How far the finger's pressing surface lies from its centre (m): the
    /// sphere's radius; 0 for a plate, whose centre is on its face.
    pub fn reach(&self) -> f64 {
        self.reach_along(DVec3::NEG_Z)
    }

    /// Its `shape` and `radius` or `size` keys, as a scene file writes them
    /// (for a `[[finger]]` and a `[[finger.part]]` alike).
    pub fn to_toml(&self) -> String {
        match *self {
            FingerShape::Sphere { radius } => format!("shape = \"sphere\"\nradius = {radius:?}\n"),
            FingerShape::Plate { half_size: [x, y] } => {
                format!("shape = \"plate\"\nsize = [{:?}, {:?}]\n", 2.0 * x, 2.0 * y)
            }
            FingerShape::Box {
                half_size: [x, y, z],
            } => format!(
                "shape = \"box\"\nsize = [{:?}, {:?}, {:?}]\n",
                2.0 * x,
                2.0 * y,
                2.0 * z
            ),
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

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Force,
    Velocity,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Finger {
    pub shape: FingerShape,
    /// More shapes moving with it (a compound finger); empty for one shape.
    pub parts: Vec<FingerPart>,
    pub position: DVec3,
    pub free_axes: [bool; 3],
    pub control: Control,
    pub force: DVec3,
    pub velocity: DVec3,
    pub mass: f64,
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    pub restitution: f64,
    pub friction: f64,
    pub stick_velocity: f64,
    pub stick_stiffness: f64,
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

/// Default `[model] limit_stiffness`: limit springs 1000 times stiffer than
/// the spring they guard (ARCHITECTURE.md, choice 5).
pub const DEFAULT_LIMIT_STIFFNESS: f64 = 1000.0;

/// CG's default relative residual. 20 steps into the thesis scene
/// (frictionless) the state is within 1.1e-8 m RMS of a 1e-10 solve; with
/// friction, the friction cone's threshold makes a 1e-8 solve differ from a
/// 1e-10 one by micrometres, so tighter buys nothing (`tests/solver_tolerance.rs`).
pub const DEFAULT_CG_TOLERANCE: f64 = 1e-5;

/// The built-in thesis scene: the Ecoflex 00-20 cuboid pressed by the large
/// spherical finger carrying 0.992 kg (thesis Sec. VI-VII), plus the
/// material's bulk modulus (ARCHITECTURE.md, "The built-in scene").
pub const THESIS_SCENE: &str =
    include_str!("../../../assets/scenes/thesis_cuboid_large_finger.toml");

impl Scene {
    /// The built-in thesis scene (see [`THESIS_SCENE`]).
    pub fn thesis() -> Scene {
        match Scene::from_toml_str(THESIS_SCENE, "<built-in thesis scene>") {
            Ok(scene) => scene,
            // The built-in text is checked by a test; this cannot happen in a release.
            Err(e) => panic!("built-in thesis scene is invalid: {e}"),
        }
    }

    /// Reads and resolves a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let mut scene = Scene::from_toml_str(&text, &path.display().to_string())?;
        scene.source = Some(path.to_path_buf());
        if let Shape::Mesh { path: mesh, .. } = &mut scene.object.shape
            && mesh.is_relative()
            && let Some(dir) = path.parent()
        {
            *mesh = dir.join(&*mesh);
        }
        Ok(scene)
    }

    /// Parses and resolves scene text; `file` names it in errors.
    pub fn from_toml_str(text: &str, file: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError::Syntax {
            file: file.to_string(),
            message: describe_toml_error(text, &e),
        })?;
        Resolver {
            text,
            file,
            applied: Vec::new(),
            parts_seen: 0,
        }
        .resolve(raw)
    }

    /// Writes the scene back as TOML, with every value explicit.
    pub fn to_toml(&self) -> String {
        use std::fmt::Write;
        let v3 = |v: DVec3| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
        let mut s = String::new();
        let sim = &self.simulation;
        let _ = writeln!(
            s,
            "[simulation]\ndt = {:?}\nduration = {:?}\ngravity = {}\ncg_tolerance = {:?}\ncg_max_iterations = {}\n",
            sim.dt,
            sim.duration,
            v3(sim.gravity),
            sim.cg_tolerance,
            sim.cg_max_iterations
        );
        let o = &self.object;
        s.push_str("[object]\n");
        match &o.shape {
            Shape::Cuboid { size } => {
                let _ = writeln!(s, "shape = \"cuboid\"\nsize = {}", v3(*size));
            }
            Shape::Cylinder { radius, height } => {
                let _ = writeln!(
                    s,
                    "shape = \"cylinder\"\nradius = {radius:?}\nheight = {height:?}"
                );
            }
            Shape::Mesh {
                path,
                scale,
                position,
            } => {
                let _ = writeln!(
                    s,
                    "shape = \"mesh\"\npath = {:?}\nscale = {scale:?}\nposition = {}",
                    path.display().to_string(),
                    v3(*position)
                );
            }
        }
        let _ = writeln!(
            s,
            "edge_length = {:?}\ndensity = {:?}\nyoung_modulus = {:?}\npoisson_ratio = {:?}\n",
            o.edge_length, o.density, o.young_modulus, o.poisson_ratio
        );
        let m = &self.model;
        let _ = writeln!(
            s,
            "[model]\ndamping_ratio = {:?}\nalpha = {:?}\nbulk_modulus = {:?}\nlimit_stiffness = {:?}",
            m.damping_ratio, m.alpha, m.bulk_modulus, m.limit_stiffness
        );
        if m.bulk_pressure == BulkPressure::Nodal {
            let _ = writeln!(s, "bulk_pressure = \"nodal\"");
        }
        if let Some(t) = m.tau_s {
            let _ = writeln!(s, "tau_s = {t:?}");
        }
        if let Some(t) = m.tau_c {
            let _ = writeln!(s, "tau_c = {t:?}");
        }
        let _ = writeln!(s, "constraint_iterations = {}", m.constraint_iterations);
        if let Some(t) = m.constraint_tolerance {
            let _ = writeln!(s, "constraint_tolerance = {t:?}");
        }
        if m.stiffening_cubic != 0.0 {
            let _ = writeln!(s, "stiffening_cubic = {:?}", m.stiffening_cubic);
        }
        if m.softening != 0.0 {
            let _ = writeln!(s, "softening = {:?}", m.softening);
        }
        let _ = writeln!(
            s,
            "stiffening = {:?}\ncompression_ratio = {:?}\nprony_g = {:?}\nprony_tau = {:?}\nelasticity = \"{}\"\nself_collision = {}",
            m.stiffening,
            m.compression_ratio,
            m.prony_g,
            m.prony_tau,
            match m.elasticity {
                Elasticity::Springs => "springs",
                Elasticity::NeoHookean => "neo-hookean",
            },
            m.self_collision
        );
        s.push('\n');
        let kind = match self.support.kind {
            SupportKind::FixedBottom => "fixed-bottom",
            SupportKind::Table => "table",
            SupportKind::None => "none",
        };
        let _ = writeln!(
            s,
            "[support]\nkind = \"{kind}\"\nfriction = {:?}\n",
            self.support.friction
        );
        for b in &self.fixed {
            let _ = writeln!(s, "[[fixed]]\nmin = {}\nmax = {}\n", v3(b.min), v3(b.max));
        }
        for l in &self.loads {
            let _ = writeln!(
                s,
                "[[load]]\nmin = {}\nmax = {}\nmass = {:?}\nforce = {}\n",
                v3(l.region.min),
                v3(l.region.max),
                l.mass,
                v3(l.force)
            );
        }
        for r in &self.regions {
            let _ = writeln!(
                s,
                "[[region]]\nmin = {}\nmax = {}\nyoung_modulus = {:?}\ndensity = {:?}\n",
                v3(r.region.min),
                v3(r.region.max),
                r.young_modulus,
                r.density
            );
        }
        for f in &self.fingers {
            s.push_str("[[finger]]\n");
            s.push_str(&f.shape.to_toml());
            let axes: String = ['x', 'y', 'z']
                .iter()
                .zip(f.free_axes)
                .filter(|(_, free)| *free)
                .map(|(c, _)| *c)
                .collect();
            let control = match f.control {
                Control::Force => "force",
                Control::Velocity => "velocity",
            };
            let _ = writeln!(
                s,
                "position = {}\nfree_axes = \"{axes}\"\ncontrol = \"{control}\"\nforce = {}\nvelocity = {}\nmass = {:?}\nyoung_modulus = {:?}\npoisson_ratio = {:?}\nrestitution = {:?}\nfriction = {:?}\nstick_velocity = {:?}\nstick_stiffness = {:?}\nstick_damping = {:?}\nguide_speed = {:?}\ncontact_stiffness_scale = {:?}",
                v3(f.position),
                v3(f.force),
                v3(f.velocity),
                f.mass,
                f.young_modulus,
                f.poisson_ratio,
                f.restitution,
                f.friction,
                f.stick_velocity,
                f.stick_stiffness,
                f.stick_damping,
                f.guide_speed,
                f.contact_stiffness_scale
            );
            if let Some(t) = f.travel {
                let _ = writeln!(s, "travel = {t:?}");
            }
            let _ = writeln!(
                s,
                "start_time = {:?}\nramp_time = {:?}\nguide_friction = {:?}",
                f.start_time, f.ramp_time, f.guide_friction
            );
            s.push('\n');
            for part in &f.parts {
                s.push_str("[[finger.part]]\n");
                s.push_str(&part.shape.to_toml());
                let _ = writeln!(s, "offset = {}\n", v3(part.offset));
            }
        }
        s
    }
}

/// Turns a TOML/serde error into one line with the line number and a hint.
pub fn describe_toml_error(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim().to_string();
    let location = e
        .span()
        .map(|span| {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            let source = text.lines().nth(line - 1).unwrap_or("").trim();
            format!("line {line} `{source}`: ")
        })
        .unwrap_or_default();
    let hint = if msg.contains("unknown field") {
        " (a typo? Unknown keys are errors; put free-form data under [extra])"
    } else if msg.contains("invalid type") {
        " (check the value's type: numbers, strings in quotes, vectors as [x, y, z])"
    } else {
        ""
    };
    format!("{location}{msg}{hint}")
}

struct Resolver<'a> {
    text: &'a str,
    file: &'a str,
    applied: Vec<String>,
    /// `[[finger.part]]` tables resolved so far (their file order).
    parts_seen: usize,
}

/// One key of a table: where to report it.
#[derive(Clone, Copy)]
struct At<'k> {
    table: &'k str,
    index: Option<usize>,
    key: &'k str,
}

impl<'a> Resolver<'a> {
    /// The line on which `key` is written inside `[table]` (or the index-th
    /// `[[table]]`), for error messages; empty when not found (a default).
    fn line_of(&self, at: At<'_>) -> String {
        let mut current = String::new();
        let mut count: i64 = -1;
        for (n, line) in self.text.lines().enumerate() {
            let t = line.trim();
            if let Some(rest) = t.strip_prefix("[[") {
                current = rest.trim_end_matches("]]").trim().to_string();
                if current == at.table {
                    count += 1;
                }
                continue;
            }
            if let Some(rest) = t.strip_prefix('[') {
                current = rest.split(']').next().unwrap_or("").trim().to_string();
                continue;
            }
            let in_table = current == at.table && at.index.is_none_or(|i| count == i as i64);
            if in_table
                && let Some((k, _)) = t.split_once('=')
                && k.trim() == at.key
            {
                return format!(":{}", n + 1);
            }
        }
        String::new()
    }

    fn table_name(at: At<'_>) -> String {
        match at.index {
            Some(i) => format!("[[{}]] #{} ", at.table, i + 1),
            None => format!("[{}] ", at.table),
        }
    }

    fn err(&self, at: At<'_>, value: impl std::fmt::Display, rule: &str) -> SceneError {
        SceneError::Value {
            file: self.file.to_string(),
            line: self.line_of(at),
            table: Self::table_name(at),
            key: at.key.to_string(),
            value: value.to_string(),
            rule: rule.to_string(),
        }
    }

    fn default<T: std::fmt::Debug>(&mut self, at: At<'_>, v: Option<T>, d: T) -> T {
        match v {
            Some(v) => v,
            None => {
                self.applied
                    .push(format!("{}{} = {:?}", Self::table_name(at), at.key, d));
                d
            }
        }
    }

    /// A finite number in `range` (described by `rule`).
    fn number(
        &mut self,
        at: At<'_>,
        v: Option<f64>,
        default: f64,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64, SceneError> {
        let x = self.default(at, v, default);
        if x.is_finite() && ok(x) {
            Ok(x)
        } else {
            Err(self.err(at, x, rule))
        }
    }

    /// A finite number in range, or `None` when the key is omitted (no default).
    fn optional(
        &self,
        at: At<'_>,
        v: Option<f64>,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<Option<f64>, SceneError> {
        match v {
            None => Ok(None),
            Some(x) if x.is_finite() && ok(x) => Ok(Some(x)),
            Some(x) => Err(self.err(at, x, rule)),
        }
    }

    fn required(
        &self,
        at: At<'_>,
        v: Option<f64>,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64, SceneError> {
        match v {
            Some(x) if x.is_finite() && ok(x) => Ok(x),
            Some(x) => Err(self.err(at, x, rule)),
            None => Err(SceneError::Invalid {
                file: self.file.to_string(),
                message: format!(
                    "{}{} is required for this shape ({rule})",
                    Self::table_name(at),
                    at.key
                ),
            }),
        }
    }

    fn vec3(
        &mut self,
        at: At<'_>,
        v: Option<[f64; 3]>,
        default: [f64; 3],
    ) -> Result<DVec3, SceneError> {
        let x = self.default(at, v, default);
        if x.iter().all(|c| c.is_finite()) {
            Ok(DVec3::from_array(x))
        } else {
            Err(self.err(
                at,
                format!("{x:?}"),
                "every component must be a finite number",
            ))
        }
    }

    fn resolve(mut self, raw: RawScene) -> Result<Scene, SceneError> {
        let at = |table, key| At {
            table,
            index: None,
            key,
        };

        // [simulation]
        let s = raw.simulation.unwrap_or_default();
        let dt = self.number(
            at("simulation", "dt"),
            s.dt,
            1e-3,
            |x| x > 0.0 && x <= 0.1,
            "must be > 0 and <= 0.1 s (the thesis uses 1e-3 s)",
        )?;
        let duration = self.number(
            at("simulation", "duration"),
            s.duration,
            2.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let gravity = self.vec3(at("simulation", "gravity"), s.gravity, [0.0, 0.0, -9.81])?;
        let cg_tolerance = self.number(
            at("simulation", "cg_tolerance"),
            s.cg_tolerance,
            DEFAULT_CG_TOLERANCE,
            |x| x > 0.0 && x < 1.0,
            "must be in (0, 1); a relative residual, e.g. 1e-5",
        )?;
        let cg_max = self.default(
            at("simulation", "cg_max_iterations"),
            s.cg_max_iterations,
            2000,
        );
        if !(1..=1_000_000).contains(&cg_max) {
            return Err(self.err(
                at("simulation", "cg_max_iterations"),
                cg_max,
                "must be in 1..=1000000",
            ));
        }

        // [object]
        let Some(o) = raw.object else {
            return Err(SceneError::Invalid {
                file: self.file.to_string(),
                message: "the [object] table is missing: a scene needs at least [object] shape = \"cuboid\" with size = [x, y, z]".into(),
            });
        };
        let shape_at = at("object", "shape");
        let shape = match o.shape.as_deref() {
            Some("cuboid") => {
                let size_at = at("object", "size");
                let Some(size) = o.size else {
                    return Err(SceneError::Invalid {
                        file: self.file.to_string(),
                        message: "[object] size = [x, y, z] (m) is required for shape = \"cuboid\""
                            .into(),
                    });
                };
                if !size.iter().all(|c| c.is_finite() && *c > 0.0) {
                    return Err(self.err(
                        size_at,
                        format!("{size:?}"),
                        "every extent must be > 0 m",
                    ));
                }
                Shape::Cuboid {
                    size: DVec3::from_array(size),
                }
            }
            Some("cylinder") => {
                let radius = self.required(
                    at("object", "radius"),
                    o.radius,
                    |x| x > 0.0,
                    "radius > 0 m",
                )?;
                let height = self.required(
                    at("object", "height"),
                    o.height,
                    |x| x > 0.0,
                    "height > 0 m",
                )?;
                Shape::Cylinder { radius, height }
            }
            Some("mesh") => match o.path.clone() {
                Some(p) if !p.trim().is_empty() => Shape::Mesh {
                    path: PathBuf::from(p),
                    scale: self.number(
                        at("object", "scale"),
                        o.scale,
                        1.0,
                        |x| x > 0.0,
                        "must be > 0 (0.001 for a file in millimetres)",
                    )?,
                    position: self.vec3(at("object", "position"), o.position, [0.0; 3])?,
                },
                _ => {
                    return Err(SceneError::Invalid {
                        file: self.file.to_string(),
                        message: "[object] path = \"file.msh\" is required for shape = \"mesh\""
                            .into(),
                    });
                }
            },
            Some(other) => {
                return Err(self.err(
                    shape_at,
                    format!("{other:?}"),
                    "must be \"cuboid\", \"cylinder\" or \"mesh\"",
                ));
            }
            None => {
                return Err(SceneError::Invalid {
                    file: self.file.to_string(),
                    message: "[object] shape is required: \"cuboid\", \"cylinder\" or \"mesh\""
                        .into(),
                });
            }
        };
        if !matches!(shape, Shape::Mesh { .. }) {
            for (key, given) in [
                ("scale", o.scale.is_some()),
                ("position", o.position.is_some()),
            ] {
                if given {
                    return Err(SceneError::Invalid {
                        file: self.file.to_string(),
                        message: format!(
                            "[object] {key} applies to shape = \"mesh\" only; remove it (built-in shapes are centred at x = y = 0 with their bottom at z = 0)"
                        ),
                    });
                }
            }
        }
        let smallest = match &shape {
            Shape::Cuboid { size } => size.min_element(),
            Shape::Cylinder { radius, height } => height.min(2.0 * radius),
            Shape::Mesh { .. } => f64::INFINITY,
        };
        let edge_length = self.number(
            at("object", "edge_length"),
            o.edge_length,
            0.004,
            |x| x > 0.0 && x <= smallest,
            "must be > 0 and no larger than the object's smallest extent (m)",
        )?;
        let density = self.number(
            at("object", "density"),
            o.density,
            1070.0,
            |x| x > 0.0,
            "must be > 0 kg/m^3 (silicone rubbers are about 1070)",
        )?;
        let young_modulus = self.number(
            at("object", "young_modulus"),
            o.young_modulus,
            57.6e3,
            |x| x > 0.0,
            "must be > 0 Pa (Ecoflex 00-20 is 57.6e3 Pa)",
        )?;
        let poisson_ratio = self.number(
            at("object", "poisson_ratio"),
            o.poisson_ratio,
            0.49,
            |x| x > -1.0 && x < 0.5,
            "must be in (-1, 0.5); 0.5 is perfectly incompressible and not allowed (use 0.49)",
        )?;
        let object = Object {
            shape,
            edge_length,
            density,
            young_modulus,
            poisson_ratio,
        };

        // [model]
        let m = raw.model.unwrap_or_default();
        let damping_ratio = self.number(
            at("model", "damping_ratio"),
            m.damping_ratio,
            1.0,
            |x| x >= 0.0,
            "must be >= 0 (1 = critical damping of each spring)",
        )?;
        let alpha = self.number(
            at("model", "alpha"),
            m.alpha,
            6e6,
            |x| x >= 0.0,
            "must be >= 0 (0 = no volume preservation; the thesis fits 6e6)",
        )?;
        let bulk_modulus = self.number(
            at("model", "bulk_modulus"),
            m.bulk_modulus,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 Pa (0 = off; E / (3 (1 - 2 nu)) is the material's own bulk modulus)",
        )?;
        let bulk_pressure_at = at("model", "bulk_pressure");
        let bulk_pressure = match self
            .default(
                bulk_pressure_at,
                m.bulk_pressure.clone(),
                "element".to_string(),
            )
            .as_str()
        {
            "element" => BulkPressure::Element,
            "nodal" => BulkPressure::Nodal,
            other => {
                return Err(self.err(
                    bulk_pressure_at,
                    format!("{other:?}"),
                    "must be \"element\" (each element's own volume) or \"nodal\" (averaged over each node's elements: less locking)",
                ));
            }
        };
        let limit_stiffness = self.number(
            at("model", "limit_stiffness"),
            m.limit_stiffness,
            DEFAULT_LIMIT_STIFFNESS,
            |x| (0.0..=1e6).contains(&x),
            "must be in [0, 1e6] (a multiple of each spring's stiffness; 0 = the thesis's projection alone)",
        )?;
        let tau_s = self.optional(
            at("model", "tau_s"),
            m.tau_s,
            |x| x > 0.0,
            "must be > 0 (omit the key for no limit; the thesis fits 0.16)",
        )?;
        let tau_c = self.optional(
            at("model", "tau_c"),
            m.tau_c,
            |x| x > 0.0 && x < 1.0,
            "must be in (0, 1) (omit the key for no limit; the thesis fits 0.155)",
        )?;
        let iters = self.default(
            at("model", "constraint_iterations"),
            m.constraint_iterations,
            10,
        );
        if !(0..=10_000).contains(&iters) {
            return Err(self.err(
                at("model", "constraint_iterations"),
                iters,
                "must be in 0..=10000",
            ));
        }
        let constraint_tolerance = self.optional(
            at("model", "constraint_tolerance"),
            m.constraint_tolerance,
            |x| x > 0.0 && x <= 0.1,
            "must be in (0, 0.1] (a fraction of the rest length; omit the key for exactly constraint_iterations sweeps)",
        )?;
        let stiffening = self.number(
            at("model", "stiffening"),
            m.stiffening,
            0.0,
            |x| (0.0..=1e5).contains(&x),
            "must be in [0, 1e5] (a spring's F = k dl (1 + stiffening (dl / l0)^2), an element's energy mu stiffening / 12 max(I1 - 3, 0)^2 more; 0 = none)",
        )?;
        let stiffening_cubic = self.number(
            at("model", "stiffening_cubic"),
            m.stiffening_cubic,
            0.0,
            |x| (0.0..=1e5).contains(&x),
            "must be in [0, 1e5] (an element's energy mu stiffening_cubic / 54 max(I1 - 3, 0)^3 more; 0 = none)",
        )?;
        let softening = self.number(
            at("model", "softening"),
            m.softening,
            0.0,
            |x| (0.0..1.0).contains(&x),
            "must be in [0, 1) (the early softening of a two-term Yeoh solid: the shear modulus dips to 1 - softening^2 of mu before stiffening_cubic lifts it; 0 = none)",
        )?;
        let compression_ratio = self.number(
            at("model", "compression_ratio"),
            m.compression_ratio,
            1.0,
            |x| x > 0.0 && x <= 100.0,
            "must be in (0, 100] (compression stiffness over tension stiffness; 1 = symmetric)",
        )?;
        let prony_g = self.number(
            at("model", "prony_g"),
            m.prony_g,
            0.0,
            |x| (0.0..1.0).contains(&x),
            "must be in [0, 1) (the share of the stiffness that relaxes; 0 = elastic)",
        )?;
        let prony_tau = self.number(
            at("model", "prony_tau"),
            m.prony_tau,
            1.0,
            |x| x > 0.0,
            "must be > 0 s (the relaxation time constant)",
        )?;
        let elasticity_at = at("model", "elasticity");
        let elasticity = match self
            .default(elasticity_at, m.elasticity.clone(), "springs".to_string())
            .as_str()
        {
            "springs" => Elasticity::Springs,
            "neo-hookean" => Elasticity::NeoHookean,
            other => {
                return Err(self.err(
                    elasticity_at,
                    format!("{other:?}"),
                    "must be \"springs\" (the thesis's lattice) or \"neo-hookean\" (finite elements)",
                ));
            }
        };
        if elasticity == Elasticity::Springs {
            for (key, value) in [
                ("stiffening_cubic", stiffening_cubic),
                ("softening", softening),
            ] {
                if value != 0.0 {
                    return Err(self.err(
                        at("model", key),
                        value,
                        "applies to neo-Hookean elements only: set [model] elasticity = \"neo-hookean\", or remove the key (the springs' law is stiffening alone)",
                    ));
                }
            }
        }
        let self_collision = self.default(at("model", "self_collision"), m.self_collision, false);
        let model = ModelParams {
            self_collision,
            elasticity,
            damping_ratio,
            alpha,
            bulk_modulus,
            bulk_pressure,
            limit_stiffness,
            tau_s,
            tau_c,
            constraint_iterations: iters as usize,
            constraint_tolerance,
            stiffening,
            stiffening_cubic,
            softening,
            compression_ratio,
            prony_g,
            prony_tau,
        };

        // [support]
        let sup = raw.support.unwrap_or_default();
        let kind_at = at("support", "kind");
        let kind = match self
            .default(kind_at, sup.kind, "fixed-bottom".to_string())
            .as_str()
        {
            "fixed-bottom" => SupportKind::FixedBottom,
            "table" => SupportKind::Table,
            "none" => SupportKind::None,
            other => {
                return Err(self.err(
                    kind_at,
                    format!("{other:?}"),
                    "must be \"fixed-bottom\", \"table\" or \"none\"",
                ));
            }
        };
        let friction = self.number(
            at("support", "friction"),
            sup.friction,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 (a Coulomb coefficient)",
        )?;
        let support = Support { kind, friction };

        // [[fixed]]
        let mut fixed = Vec::new();
        for (i, b) in raw.fixed.iter().enumerate() {
            let at = At {
                table: "fixed",
                index: Some(i),
                key: "max",
            };
            fixed.push(self.aabox(at, b.min, b.max)?);
        }

        // [[load]]
        let mut loads = Vec::new();
        for (i, l) in raw.load.iter().enumerate() {
            let at = |key| At {
                table: "load",
                index: Some(i),
                key,
            };
            let region = self.aabox(at("max"), l.min, l.max)?;
            let mass = self.number(at("mass"), l.mass, 0.0, |x| x >= 0.0, "must be >= 0 kg")?;
            let force = self.vec3(at("force"), l.force, [0.0; 3])?;
            loads.push(Load {
                region,
                mass,
                force,
            });
        }

        // [[finger]]
        let mut fingers = Vec::new();
        for (i, f) in raw.finger.iter().enumerate() {
            fingers.push(self.finger(i, f)?);
        }

        // [[region]]
        let mut regions = Vec::new();
        for (i, r) in raw.region.iter().enumerate() {
            let at = |key| At {
                table: "region",
                index: Some(i),
                key,
            };
            let region = self.aabox(at("max"), r.min, r.max)?;
            let young_modulus = self.number(
                at("young_modulus"),
                r.young_modulus,
                object.young_modulus,
                |x| x > 0.0,
                "must be > 0 Pa",
            )?;
            let density = self.number(
                at("density"),
                r.density,
                object.density,
                |x| x > 0.0,
                "must be > 0 kg/m^3",
            )?;
            regions.push(Region {
                region,
                young_modulus,
                density,
            });
        }

        Ok(Scene {
            simulation: Simulation {
                dt,
                duration,
                gravity,
                cg_tolerance,
                cg_max_iterations: cg_max as usize,
            },
            object,
            model,
            support,
            fixed,
            loads,
            fingers,
            regions,
            source: None,
            defaults_applied: self.applied,
        })
    }

    fn aabox(&self, at: At<'_>, min: [f64; 3], max: [f64; 3]) -> Result<AaBox, SceneError> {
        let (min, max) = (DVec3::from_array(min), DVec3::from_array(max));
        if !min.is_finite() || !max.is_finite() || !min.cmple(max).all() {
            return Err(self.err(
                at,
                format!("{:?} (min = {:?})", max.to_array(), min.to_array()),
                "min must be <= max on every axis, all finite (m)",
            ));
        }
        Ok(AaBox { min, max })
    }

    /// A finger's (or a part's) `shape` with its `radius` or `size`.
    fn finger_shape<'k>(
        &mut self,
        at: impl Fn(&'k str) -> At<'k>,
        shape: Option<String>,
        radius: Option<f64>,
        size: Option<Vec<f64>>,
    ) -> Result<FingerShape, SceneError> {
        let extents = |this: &mut Self, n: usize, default: &[f64]| {
            let size = this.default(at("size"), size.clone(), default.to_vec());
            if size.len() != n || !size.iter().all(|c| c.is_finite() && *c > 0.0) {
                let what = if n == 2 { "[x, y]" } else { "[x, y, z]" };
                return Err(this.err(
                    at("size"),
                    format!("{size:?}"),
                    &format!("must be {what}, every extent > 0 m"),
                ));
            }
            Ok(size)
        };
        Ok(
            match self
                .default(at("shape"), shape, "sphere".to_string())
                .as_str()
            {
                "sphere" => {
                    let radius =
                        self.number(at("radius"), radius, 0.015, |x| x > 0.0, "must be > 0 m")?;
                    FingerShape::Sphere { radius }
                }
                "plate" => {
                    let size = extents(self, 2, &[0.08, 0.08])?;
                    FingerShape::Plate {
                        half_size: [0.5 * size[0], 0.5 * size[1]],
                    }
                }
                "box" => {
                    let size = extents(self, 3, &[0.02, 0.02, 0.02])?;
                    FingerShape::Box {
                        half_size: [0.5 * size[0], 0.5 * size[1], 0.5 * size[2]],
                    }
                }
                other => {
                    return Err(self.err(
                        at("shape"),
                        format!("{other:?}"),
                        "must be \"sphere\", \"plate\" or \"box\"",
                    ));
                }
            },
        )
    }

    fn finger(&mut self, i: usize, f: &RawFinger) -> Result<Finger, SceneError> {
        let at = |key| At {
            table: "finger",
            index: Some(i),
            key,
        };
        let shape = self.finger_shape(at, f.shape.clone(), f.radius, f.size.clone())?;
        let mut parts = Vec::new();
        for raw in f.part.iter().flatten() {
            let index = self.parts_seen;
            self.parts_seen += 1;
            let at = |key| At {
                table: "finger.part",
                index: Some(index),
                key,
            };
            let shape = self.finger_shape(at, raw.shape.clone(), raw.radius, raw.size.clone())?;
            let offset = self.vec3(at("offset"), raw.offset, [0.0; 3])?;
            parts.push(FingerPart { shape, offset });
        }
        let position = self.vec3(at("position"), f.position, [0.0, 0.0, 0.035])?;
        let axes_text = self.default(at("free_axes"), f.free_axes.clone(), "z".to_string());
        let mut free_axes = [false; 3];
        for c in axes_text.chars() {
            let k = match c {
                'x' => 0,
                'y' => 1,
                'z' => 2,
                _ => return Err(self.err(at("free_axes"), format!("{axes_text:?}"),
                    "must be letters from \"xyz\", each once (e.g. \"z\" or \"xz\"); \"\" holds the finger still")),
            };
            if free_axes[k] {
                return Err(self.err(
                    at("free_axes"),
                    format!("{axes_text:?}"),
                    "names an axis twice",
                ));
            }
            free_axes[k] = true;
        }
        let control = match self
            .default(at("control"), f.control.clone(), "force".to_string())
            .as_str()
        {
            "force" => Control::Force,
            "velocity" => Control::Velocity,
            other => {
                return Err(self.err(
                    at("control"),
                    format!("{other:?}"),
                    "must be \"force\" or \"velocity\"",
                ));
            }
        };
        let force = self.vec3(at("force"), f.force, [0.0; 3])?;
        let velocity = self.vec3(at("velocity"), f.velocity, [0.0; 3])?;
        let mass = self.number(
            at("mass"),
            f.mass,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 kg (0 = a light guide)",
        )?;
        let young_modulus = self.number(
            at("young_modulus"),
            f.young_modulus,
            2e9,
            |x| x > 0.0,
            "must be > 0 Pa",
        )?;
        let poisson_ratio = self.number(
            at("poisson_ratio"),
            f.poisson_ratio,
            0.3,
            |x| x > -1.0 && x < 0.5,
            "must be in (-1, 0.5)",
        )?;
        let restitution = self.number(
            at("restitution"),
            f.restitution,
            0.5,
            |x| (0.0..=1.0).contains(&x),
            "must be in [0, 1]",
        )?;
        let friction = self.number(
            at("friction"),
            f.friction,
            0.5,
            |x| x >= 0.0,
            "must be >= 0",
        )?;
        let stick_velocity = self.number(
            at("stick_velocity"),
            f.stick_velocity,
            1e-3,
            |x| x > 0.0,
            "must be > 0 m/s",
        )?;
        let stick_stiffness = self.number(
            at("stick_stiffness"),
            f.stick_stiffness,
            500.0,
            |x| x >= 0.0,
            "must be >= 0 N/m",
        )?;
        let stick_damping = self.number(
            at("stick_damping"),
            f.stick_damping,
            5.0,
            |x| x >= 0.0,
            "must be >= 0 N s/m",
        )?;
        let travel = self.optional(at("travel"), f.travel, |x| x >= 0.0, "must be >= 0 m")?;
        let start_time = self.number(
            at("start_time"),
            f.start_time,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let ramp_time = self.number(
            at("ramp_time"),
            f.ramp_time,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 s",
        )?;
        let guide_friction = self.number(
            at("guide_friction"),
            f.guide_friction,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 N (the Coulomb friction force in the finger's guide)",
        )?;
        let guide_speed = self.number(
            at("guide_speed"),
            f.guide_speed,
            0.05,
            |x| x > 0.0,
            "must be > 0 m/s",
        )?;
        let contact_stiffness_scale = self.number(
            at("contact_stiffness_scale"),
            f.contact_stiffness_scale,
            1.0,
            |x| x > 0.0 && x <= 1e6,
            "must be in (0, 1e6] (1 = thesis eq. 27)",
        )?;
        Ok(Finger {
            shape,
            parts,
            position,
            free_axes,
            control,
            force,
            velocity,
            mass,
            young_modulus,
            poisson_ratio,
            restitution,
            friction,
            stick_velocity,
            stick_stiffness,
            stick_damping,
            travel,
            start_time,
            ramp_time,
            guide_friction,
            guide_speed,
            contact_stiffness_scale,
        })
    }
}
