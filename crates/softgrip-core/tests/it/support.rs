//! Set-up shared by the tests: scenes from `assets/scenes` or from text, and rest tolerances.

use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::quasi_static::RestTolerance;

/// The path of `assets/scenes/<name>`.
pub fn shipped_scene_path(name: &str) -> String {
    format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A scene shipped in `assets/scenes`, loaded as `softgrip` loads it.
pub fn shipped_scene(name: &str) -> Scene {
    let path = shipped_scene_path(name);
    Scene::load(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"))
}

/// The RMS distance between the particles of two runs of one model (m).
pub fn rms_distance(a: &Simulation, b: &Simulation) -> f64 {
    let (x, y) = (&a.state.positions, &b.state.positions);
    let sum: f64 = x.iter().zip(y).map(|(p, q)| p.distance_squared(*q)).sum();
    (sum / x.len() as f64).sqrt()
}

/// Scene text resolved and ready to run; `name` names it in errors.
/// The largest distance between the two runs' particles and fingers (m).
pub fn largest_distance(a: &Simulation, b: &Simulation) -> f64 {
    let fingers = a.state.fingers.iter().zip(&b.state.fingers);
    a.state
        .positions
        .iter()
        .zip(&b.state.positions)
        .map(|(p, q)| p.distance(*q))
        .chain(fingers.map(|(f, g)| f.position.distance(g.position)))
        .fold(0.0, f64::max)
}

pub fn simulation(text: &str, name: &str) -> Simulation {
    let scene = Scene::from_toml_str(text, name).unwrap_or_else(|e| panic!("{e}"));
    Simulation::new(&scene).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Scene text of a cuboid of `size` (m) meshed at `edge_length`: `simulation` holds the keys of
/// `[simulation]`, `more` any further `[object]` keys and then the other tables.
pub fn cuboid_scene(simulation: &str, size: [f64; 3], edge_length: f64, more: &str) -> String {
    format!(
        "[simulation]\n{simulation}\n[object]\nshape = \"cuboid\"\nsize = {size:?}\nedge_length = {edge_length:?}\n{more}"
    )
}

/// `[simulation]` without gravity.
pub const WEIGHTLESS: &str = "gravity = [0.0, 0.0, 0.0]";

/// At rest once every particle has moved slower than `speed` (m/s) for 20 steps in a row, within
/// `max_seconds` of simulated time.
pub fn rest_within(speed: f64, max_seconds: f64) -> RestTolerance {
    RestTolerance {
        speed,
        consecutive_steps: 20,
        max_seconds,
        give_up_after: None,
    }
}

/// At rest once every particle has moved slower than 1e-6 m/s for 50 steps in a row, within 20 s.
pub fn strict_rest() -> RestTolerance {
    RestTolerance {
        consecutive_steps: 50,
        ..rest_within(1e-6, 20.0)
    }
}

/// `[simulation]` without gravity and with a tight linear solve, for conservation checks.
pub const WEIGHTLESS_EXACT: &str = "gravity = [0.0, 0.0, 0.0]\ncg_tolerance = 1e-13";

/// Scene text of an unsupported 30 x 20 x 10 mm block at 4 mm edges: `simulation` holds the
/// keys of `[simulation]`, `model` those of `[model]`.
pub fn free_block(simulation: &str, model: &str) -> String {
    let more = format!("[model]\n{model}\n[support]\nkind = \"none\"\n");
    cuboid_scene(simulation, [0.03, 0.02, 0.01], 0.004, &more)
}

/// At rest once every particle has moved slower than 1e-5 m/s for 20 steps in a row, within 5 s.
pub fn rest() -> RestTolerance {
    rest_within(1e-5, 5.0)
}
