//! The defaults other modules name, and the built-in scene. The rest of the documented defaults
//! stand beside their ranges in `resolve`.

/// Default `[model] limit_stiffness`: limit springs 1000 times stiffer than
/// the spring they guard (ARCHITECTURE.md, choice 5).
pub const DEFAULT_LIMIT_STIFFNESS: f64 = 1000.0;

/// CG's default relative residual. 20 steps into the thesis scene
/// (frictionless) the state is within 1.1e-8 m RMS of a 1e-10 solve; with
/// friction, the friction cone's threshold makes a 1e-8 solve differ from a
/// 1e-10 one by micrometres, so tighter buys nothing (`tests/it/solver_tolerance.rs`).
pub const DEFAULT_CG_TOLERANCE: f64 = 1e-5;

/// The built-in thesis scene: the Ecoflex 00-20 cuboid pressed by the large
/// spherical finger carrying 0.992 kg (thesis Sec. VI-VII), plus the
/// material's bulk modulus (ARCHITECTURE.md, "The built-in scene").
pub const THESIS_SCENE: &str =
    include_str!("../../../../assets/scenes/thesis_cuboid_large_finger.toml");
