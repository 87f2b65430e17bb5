//! Errors of the simulation core. Each says what went wrong, where, and what
//! to do about it; none is a panic.

use crate::mesh::MeshError;
use crate::scene::SceneError;

/// An error of the simulation core: a scene, a mesh, a recording or a run that cannot go on.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The scene file could not be read or is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),

    /// The object's mesh failed its checks or its repair.
    #[error("{file}: bad mesh: {source}")]
    Mesh {
        /// The mesh file, or the scene's where the mesh handed to the model fails its check.
        file: String,
        /// What is wrong with the mesh.
        source: MeshError,
    },

    /// A mesh file could not be read.
    #[error(transparent)]
    MeshFile(#[from] crate::mesh::io::ImportError),

    /// A recording has loads but the scene gives them no direction to act along.
    #[error(
        "{file}: the recording's loads (up to {load} N) act on the first force-controlled finger along its scene `force` direction, and {why}; set that finger's `control = \"force\"` and a nonzero `force` giving the direction"
    )]
    NoLoadDirection {
        /// The scene file.
        file: String,
        /// The recording's largest load magnitude, N.
        load: f64,
        /// Why there is no direction: no force-controlled finger, or its `force` is zero.
        why: String,
    },

    /// A recording's sample has a negative load, which would pull the finger off the object.
    #[error(
        "{file}: sample {sample} has load {load} N, but a load acts along finger #{finger}'s `force` direction {direction:?} and a contact only pushes: a negative load pulls the finger off the object, where nothing holds it. Give loads as positive numbers (N pushing along `force`), or turn the scene's `force` round"
    )]
    NegativeLoad {
        /// The recording's samples file.
        file: String,
        /// The sample's number, 1-based.
        sample: usize,
        /// Its load, N (negative).
        load: f64,
        /// The loaded finger's number, 1-based.
        finger: usize,
        /// The finger's load direction: its scene `force`, normalized.
        direction: [f64; 3],
    },

    /// A recording's marker lies too far from the object's undeformed surface.
    #[error(
        "{file}: marker {marker} at {reference:?} is {distance_mm:.1} mm from the object's surface (more than {limit_mm:.1} mm, a tenth of its largest extent). Reference positions are on the UNDEFORMED surface, in metres, in the scene's frame: check the units (millimetres written as metres?), the frame, and the scene's object size and position"
    )]
    MarkerOffSurface {
        /// The recording file.
        file: String,
        /// The marker's name.
        marker: String,
        /// Its reference position, m.
        reference: [f64; 3],
        /// Its distance from the undeformed surface, mm.
        distance_mm: f64,
        /// The largest distance allowed (a tenth of the object's largest extent), mm.
        limit_mm: f64,
    },

    /// The object's edge length would make more tetrahedra than the limit allows.
    #[error(
        "{file}: edge_length = {edge_length:e} m makes {count} tetrahedra of this {shape} (about {gib} GiB), over {limit}: {advice}"
    )]
    TooManyTetrahedra {
        /// The scene file.
        file: String,
        /// The object, in words ("50 x 50 x 20 mm cuboid").
        shape: String,
        /// `[object] edge_length`, m.
        edge_length: f64,
        /// The count in words ("37,324,800", "at least 2.1e9"): a tiny edge gives counts past u64.
        count: String,
        /// The memory they would take, in words.
        gib: String,
        /// The limit, in words.
        limit: String,
        /// What to do, in words: a coarser edge, or a higher limit.
        advice: String,
    },

    /// A mesh's size is implausible in metres: likely written in other units.
    #[error(
        "{file}: the mesh spans {extent:.3e} m (at scale = {scale}), {ratio} its {against}: are its units not metres? Set scale = {suggest} in [object] (it would then span {scaled:.3e} m)"
    )]
    MeshUnits {
        /// The mesh file.
        file: String,
        /// The mesh's largest extent at the present `scale`, m.
        extent: f64,
        /// `[object] scale`, as given.
        scale: f64,
        /// "4000 times the size of finger 1" or "more than any lab object".
        ratio: String,
        /// What the extent is compared with, in words (the largest finger's size, or a
        /// plausible size).
        against: String,
        /// The `scale` suggested instead.
        suggest: f64,
        /// The mesh's largest extent at `suggest`, m.
        scaled: f64,
    },

    /// Something the code does not do (yet).
    #[error("not supported yet: {what}")]
    NotSupported {
        /// What was asked, in words.
        what: String,
    },

    /// A `[[fixed]]` or `[[load]]` box holds no particle of the object, a `[[region]]` no
    /// element's centroid.
    #[error(
        "{file}: [[{table}]] #{index} (min {min:?}, max {max:?}) contains no particle of the object, whose bounds are {bounds_min:?} .. {bounds_max:?}; enlarge the box or move it onto the object"
    )]
    EmptyRegion {
        /// The scene file.
        file: String,
        /// The box's table: "fixed", "load" or "region".
        table: String,
        /// The box's number in its table, 1-based.
        index: usize,
        /// The box's lower corner, m.
        min: [f64; 3],
        /// The box's upper corner, m.
        max: [f64; 3],
        /// The lower corner of the object's bounding box, m.
        bounds_min: [f64; 3],
        /// The upper corner of the object's bounding box, m.
        bounds_max: [f64; 3],
    },

    /// A finger starts inside the object.
    #[error(
        "{file}: [[finger]] #{index} starts {depth_mm:.2} mm inside the object (at {position:?}); move it out, e.g. to z >= {suggest_z:.4}"
    )]
    FingerStartsInside {
        /// The scene file.
        file: String,
        /// The finger's number, 1-based.
        index: usize,
        /// How deep inside it starts, mm.
        depth_mm: f64,
        /// Its position, m.
        position: [f64; 3],
        /// A height that clears the object: its top plus the finger's reach, m.
        suggest_z: f64,
    },

    /// The run diverged: a non-finite value, or a speed past the limit.
    #[error("diverged at t = {time:.4} s (step {step}): {what}. {advice}")]
    Diverged {
        /// Simulated time, s.
        time: f64,
        /// The step's number.
        step: u64,
        /// What was seen, in words.
        what: String,
        /// The model's time step, s.
        dt: f64,
        /// The model's Young's modulus, Pa.
        young_modulus: f64,
        /// The model's volume-preservation scale `alpha`, N/m^3.
        alpha: f64,
        /// A smaller step worth trying where the step may be the cause (`None` where it is
        /// not: a load that accelerates a finger past the limit in any step). A caller that
        /// can re-run checks it before it advises it (`softgrip run`).
        suggest_dt: Option<f64>,
        /// What to change, in words.
        advice: String,
    },

    /// The conjugate gradient reached its iteration limit.
    #[error(
        "the linear solver stopped at t = {time:.4} s (step {step}) after its limit of {iterations} iterations ([simulation] cg_max_iterations = {iterations}; residual {residual:.2e}): raise cg_max_iterations (default 2000)"
    )]
    SolverLimit {
        /// Simulated time, s.
        time: f64,
        /// The step's number.
        step: u64,
        /// The iterations run: the limit, `[simulation] cg_max_iterations`.
        iterations: usize,
        /// The relative residual reached.
        residual: f64,
    },

    /// A quasi-static solve by time steps did not come to rest in the time allowed.
    #[error(
        "the quasi-static solve did not come to rest within {seconds} s of simulated time ({steps} steps; max speed still {max_speed:.3e} m/s > {tolerance:.1e} m/s); {advice}"
    )]
    NoRest {
        /// Simulated time spent, s.
        seconds: f64,
        /// What to do: more time where the motion decays (with how much), else more damping.
        advice: String,
        /// The time steps taken.
        steps: u64,
        /// The largest particle speed at the end, m/s.
        max_speed: f64,
        /// The speed under which it counts as at rest, m/s.
        tolerance: f64,
    },

    /// Newton's method found no static equilibrium.
    #[error("no static equilibrium under a load of {load:.4} N: {why}. {advice}")]
    NoEquilibrium {
        /// The applied load (N): the force-controlled fingers' forces.
        load: f64,
        /// What failed and where.
        why: String,
        /// Elements (0-based) the last rejected iteration turned inside out.
        inverted: Vec<usize>,
        /// The centre of the region where it fails (m).
        near: [f64; 3],
        /// What to do, in words.
        advice: String,
        /// The iterations stalled at the largest pseudo step: a smaller load step does not help
        /// (the spring-limit projection's reaction is no force of the model).
        stalled: bool,
    },

    /// The sensitivities of an equilibrium could not be found (`crate::sensitivity`).
    #[error("no sensitivity at this state: {why}")]
    NoSensitivity {
        /// Why not, in words.
        why: String,
    },

    /// The run was cancelled (`crate::cancel`).
    #[error("cancelled")]
    Cancelled,
}
