//! Errors of the simulation core. Each says what went wrong, where, and what
//! to do about it; none is a panic.

use crate::mesh::MeshError;
use crate::scene::SceneError;

#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error(transparent)]
    Scene(#[from] SceneError),

    #[error("{file}: bad mesh: {source}")]
    Mesh { file: String, source: MeshError },

    #[error(transparent)]
    MeshFile(#[from] crate::mesh::io::ImportError),

    #[error(
        "{file}: the recording's loads (up to {load} N) act on the first force-controlled finger along its scene `force` direction, and {why}; set that finger's `control = \"force\"` and a nonzero `force` giving the direction"
    )]
    NoLoadDirection {
        file: String,
        load: f64,
        why: String,
    },

    #[error(
        "{file}: sample {sample} has load {load} N, but a load acts along finger #{finger}'s `force` direction {direction:?} and a contact only pushes: a negative load pulls the finger off the object, where nothing holds it. Give loads as positive numbers (N pushing along `force`), or turn the scene's `force` round"
    )]
    NegativeLoad {
        file: String,
        sample: usize,
        load: f64,
        finger: usize,
        direction: [f64; 3],
    },

    #[error(
        "{file}: marker {marker} at {reference:?} is {distance_mm:.1} mm from the object's surface (more than {limit_mm:.1} mm, a tenth of its largest extent). Reference positions are on the UNDEFORMED surface, in metres, in the scene's frame: check the units (millimetres written as metres?), the frame, and the scene's object size and position"
    )]
    MarkerOffSurface {
        file: String,
        marker: String,
        reference: [f64; 3],
        distance_mm: f64,
        limit_mm: f64,
    },

    #[error(
        "{file}: edge_length = {edge_length:e} m makes {count} tetrahedra of this {shape} (about {gib} GiB), over {limit}: {advice}"
    )]
    TooManyTetrahedra {
        file: String,
        shape: String,
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

    #[error(
        "{file}: the mesh spans {extent:.3e} m (at scale = {scale}), {ratio} its {against}: are its units not metres? Set scale = {suggest} in [object] (it would then span {scaled:.3e} m)"
    )]
    MeshUnits {
        file: String,
        extent: f64,
        scale: f64,
        /// "4000 times the size of finger 1" or "more than any lab object".
        ratio: String,
        against: String,
        suggest: f64,
        scaled: f64,
    },

    #[error("not supported yet: {what}")]
    NotSupported { what: String },

    #[error(
        "{file}: [[{table}]] #{index} (min {min:?}, max {max:?}) contains no particle of the object, whose bounds are {bounds_min:?} .. {bounds_max:?}; enlarge the box or move it onto the object"
    )]
    EmptyRegion {
        file: String,
        table: String,
        index: usize,
        min: [f64; 3],
        max: [f64; 3],
        bounds_min: [f64; 3],
        bounds_max: [f64; 3],
    },

    #[error(
        "{file}: [[finger]] #{index} starts {depth_mm:.2} mm inside the object (at {position:?}); move it out, e.g. to z >= {suggest_z:.4}"
    )]
    FingerStartsInside {
        file: String,
        index: usize,
        depth_mm: f64,
        position: [f64; 3],
        suggest_z: f64,
    },

    #[error("diverged at t = {time:.4} s (step {step}): {what}. {advice}")]
    Diverged {
        time: f64,
        step: u64,
        what: String,
        dt: f64,
        young_modulus: f64,
        alpha: f64,
        /// A smaller step worth trying where the step may be the cause (`None` where it is
        /// not: a load that accelerates a finger past the limit in any step). A caller that
        /// can re-run checks it before it advises it (`softgrip run`).
        suggest_dt: Option<f64>,
        /// What to change, in words.
        advice: String,
    },

    #[error(
        "the linear solver stopped at t = {time:.4} s (step {step}) after its limit of {iterations} iterations ([simulation] cg_max_iterations = {iterations}; residual {residual:.2e}): raise cg_max_iterations (default 2000)"
    )]
    SolverLimit {
        time: f64,
        step: u64,
        iterations: usize,
        residual: f64,
    },

    #[error(
        "the quasi-static solve did not come to rest within {seconds} s of simulated time ({steps} steps; max speed still {max_speed:.3e} m/s > {tolerance:.1e} m/s); {advice}"
    )]
    NoRest {
        seconds: f64,
        /// What to do: more time where the motion decays (with how much), else more damping.
        advice: String,
        steps: u64,
        max_speed: f64,
        tolerance: f64,
    },

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
        advice: String,
        /// The iterations stalled at the largest pseudo step: a smaller load step does not help
        /// (the spring-limit projection's reaction is no force of the model).
        stalled: bool,
    },

    /// The sensitivities of an equilibrium could not be found (`crate::sensitivity`).
    #[error("no sensitivity at this state: {why}")]
    NoSensitivity { why: String },

    #[error("cancelled")]
    Cancelled,
}
