//! softgrip against an independent finite element code: NGSolve's solutions of the same
//! problems, computed by `scripts/reference/ngsolve_reference.py` and committed in
//! `tests/reference/ngsolve.json` (library, version and run time in its README). The continuum
//! option (neo-Hookean elements, nodal pressures) is compared with them; the spring lattice's
//! error on the same problems is printed for docs/results/accuracy.md.

use softgrip_core::Simulation;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::scene::{BulkPressure, Elasticity};

use crate::support::{cuboid_scene, shipped_scene, simulation};

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

/// The thesis indentation (reference problem 3): the light-guide scene without friction,
/// `elasticity` and `bulk_pressure` as given, at `edge`; the finger's depth (m) at each load,
/// NaN where it has no static equilibrium.
pub fn indentation(
    elasticity: Elasticity,
    pressure: BulkPressure,
    edge: f64,
    loads: &[f64],
) -> Vec<f64> {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = edge;
    scene.model.elasticity = elasticity;
    scene.model.bulk_pressure = pressure;
    scene.fingers[0].friction = 0.0;
    let mut sim = Simulation::new(&scene).expect("sim");
    loads
        .iter()
        .map(|&load| {
            sim.set_load(0, load);
            match sim.equilibrium(StaticOptions::default()) {
                Ok(_) => sim.indentation(0),
                Err(_) => f64::NAN,
            }
        })
        .collect()
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

/// The figures behind docs/results/accuracy.md's first table, printed (`-- --nocapture`).
#[test]
#[ignore = "slow: fine meshes of every problem"]
fn softgrip_on_the_reference_problems() {
    for nu in [0.45, 0.49] {
        for edge in [0.005, 0.0025] {
            let continuum = hanging_sag("elasticity = \"neo-hookean\"", nu, edge);
            let element = hanging_sag(
                "elasticity = \"neo-hookean\"\nbulk_pressure = \"element\"",
                nu,
                edge,
            );
            let lattice = hanging_sag("alpha = 0.0\nbulk_modulus = 9.6e5", nu, edge);
            eprintln!(
                "hanging, nu {nu}, edge {} mm: sag {:.4} mm nodal, {:.4} element, {:.4} lattice",
                edge * 1e3,
                -continuum * 1e3,
                -element * 1e3,
                -lattice * 1e3
            );
        }
    }
    let loads = [9.73, 14.3];
    for edge in [0.005, 0.004, 0.0025] {
        for (name, elasticity, pressure) in [
            ("nodal", Elasticity::NeoHookean, BulkPressure::Nodal),
            ("element", Elasticity::NeoHookean, BulkPressure::Element),
            ("lattice", Elasticity::Springs, BulkPressure::Element),
        ] {
            let depths = indentation(elasticity, pressure, edge, &loads);
            eprintln!(
                "indentation, {name}, edge {} mm: depth {:.3} mm at 9.73 N, {:.3} mm at 14.3 N",
                edge * 1e3,
                depths[0] * 1e3,
                depths[1] * 1e3
            );
        }
    }
}
