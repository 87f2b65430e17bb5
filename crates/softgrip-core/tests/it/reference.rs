//! softgrip against an independent finite element code: NGSolve's solutions of the same
//! problems, computed by `scripts/reference/ngsolve_reference.py` and committed in
//! `tests/reference/ngsolve.json` (library, version and run time in its README). The continuum
//! option (neo-Hookean elements, nodal pressures) is compared with them; the spring lattice's
//! error on the same problems is printed. The figures of docs/results/accuracy.md at every mesh:
//! `cargo run --release -p softgrip-core --example reference_figures`.

use softgrip_core::equilibrium::StaticOptions;

use crate::support::{cuboid_scene, simulation};

/// The mean z displacement of the bottom face (m, negative down) of the 20 x 20 x 60 mm block
/// hanging from its top face under its own weight (reference problem 1).
pub fn hanging_sag(model: &str, poisson_ratio: f64, edge: f64) -> f64 {
    let more = format!(
        "density = 1070.0\nyoung_modulus = 57.6e3\npoisson_ratio = {poisson_ratio}\n[model]\n{model}\n[support]\nkind = \"none\"\n[[fixed]]\nmin = [-1.0, -1.0, {}]\nmax = [1.0, 1.0, 1.0]\n",
        0.06 - 1e-6
    );
    let mut sim = simulation(
        &cuboid_scene("", [0.02, 0.02, 0.06], edge, &more),
        "hanging",
    );
    sim.equilibrium(StaticOptions::default())
        .expect("equilibrium");
    let bottom: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| sim.model.rest_positions[i].z < 1e-9)
        .collect();
    bottom
        .iter()
        .map(|&i| sim.state.positions[i].z - sim.model.rest_positions[i].z)
        .sum::<f64>()
        / bottom.len() as f64
}

/// `tests/reference/ngsolve.json`.
fn reference() -> serde_json::Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/ngsolve.json"
    );
    let text = std::fs::read_to_string(path).expect("the committed reference");
    serde_json::from_str(&text).expect("JSON")
}

/// Problem 1: the continuum's sag at 2.5 mm edges within 2 % of NGSolve's (order 4, converged
/// to 0.2 %) at nu 0.45 and 0.49; the lattice's error is printed (about -35 %).
#[test]
#[ignore = "slow: 2.5 mm hanging blocks"]
fn the_hanging_block_agrees_with_the_reference() {
    let reference = reference();
    for nu in [0.45, 0.49] {
        let expected = reference["problems"]["hanging"]["runs"][format!("nu={nu}")]["result"]
            ["mean_uz_bottom_m"]
            .as_f64()
            .expect("a figure");
        let continuum = hanging_sag("elasticity = \"neo-hookean\"", nu, 0.0025);
        let lattice = hanging_sag("alpha = 0.0\nbulk_modulus = 9.6e5", nu, 0.0025);
        let error = continuum / expected - 1.0;
        eprintln!(
            "hanging, nu {nu}: NGSolve {:.4} mm, continuum {:.4} mm ({:+.1} %), lattice {:.4} mm ({:+.1} %)",
            -expected * 1e3,
            -continuum * 1e3,
            100.0 * error,
            -lattice * 1e3,
            100.0 * (lattice / expected - 1.0)
        );
        assert!(error.abs() < 0.02, "nu {nu}: {:+.2} %", 100.0 * error);
    }
}
