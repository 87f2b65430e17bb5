//! softgrip's figures on the reference problems of `tests/reference` at several meshes, for
//! docs/results/accuracy.md: `cargo run --release -p softgrip-core --example reference_figures`.
//! (The tests compare them with the reference; this prints the tables, about two minutes.)

use softgrip_core::Simulation;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::scene::{BulkPressure, Elasticity, Scene};

const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/scenes/");

/// The mean z displacement of the bottom face (m) of the hanging 20 x 20 x 60 mm block.
fn hanging_sag(model: &str, poisson_ratio: f64, edge: f64) -> Result<f64, String> {
    let text = format!(
        "[simulation]\n[object]\nshape = \"cuboid\"\nsize = [0.02, 0.02, 0.06]\nedge_length = {edge:?}\ndensity = 1070.0\nyoung_modulus = 57.6e3\npoisson_ratio = {poisson_ratio}\n[model]\n{model}\n[support]\nkind = \"none\"\n[[fixed]]\nmin = [-1.0, -1.0, 0.059999]\nmax = [1.0, 1.0, 1.0]\n"
    );
    let scene = Scene::from_toml_str(&text, "hanging.toml").map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(&scene).map_err(|e| e.to_string())?;
    sim.equilibrium(StaticOptions::default())
        .map_err(|e| e.to_string())?;
    let bottom: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| sim.model.rest_positions[i].z < 1e-9)
        .collect();
    Ok(bottom
        .iter()
        .map(|&i| sim.state.positions[i].z - sim.model.rest_positions[i].z)
        .sum::<f64>()
        / bottom.len() as f64)
}

/// The light-guide scene without friction: at each load the finger's depth and the top centre's
/// sag (m; the depth less the penalty contact's penetration), NaN where it has no static
/// equilibrium.
fn indentation(
    elasticity: Elasticity,
    pressure: BulkPressure,
    edge: f64,
    contact_scale: f64,
    loads: &[f64],
) -> Vec<(f64, f64)> {
    let path = format!("{SCENES}thesis_cuboid_light_guide.toml");
    let mut scene = Scene::load(std::path::Path::new(&path)).expect("the shipped scene");
    scene.object.edge_length = edge;
    scene.model.elasticity = elasticity;
    scene.model.bulk_pressure = pressure;
    scene.fingers[0].friction = 0.0;
    scene.fingers[0].contact_stiffness_scale = contact_scale;
    let mut sim = Simulation::new(&scene).expect("sim");
    let top = 0.02; // the block's height
    let centre = (0..sim.model.particle_count())
        .min_by(|&a, &b| {
            let d =
                |i: usize| (sim.model.rest_positions[i] - glam::DVec3::new(0.0, 0.0, top)).length();
            d(a).total_cmp(&d(b))
        })
        .expect("nodes");
    loads
        .iter()
        .map(|&load| {
            sim.set_load(0, load);
            match sim.equilibrium(StaticOptions::default()) {
                Ok(_) => (
                    sim.indentation(0),
                    sim.model.rest_positions[centre].z - sim.state.positions[centre].z,
                ),
                Err(_) => (f64::NAN, f64::NAN),
            }
        })
        .collect()
}

fn main() {
    let mm = |x: Result<f64, String>| x.map_or(f64::NAN, |v| -v * 1e3);
    for nu in if std::env::args().any(|a| a == "--indentation") {
        vec![]
    } else {
        vec![0.45, 0.49]
    } {
        for edge in [0.005, 0.0025] {
            let nodal = mm(hanging_sag("elasticity = \"neo-hookean\"", nu, edge));
            let element = mm(hanging_sag(
                "elasticity = \"neo-hookean\"\nbulk_pressure = \"element\"",
                nu,
                edge,
            ));
            let lattice = mm(hanging_sag("alpha = 0.0\nbulk_modulus = 9.6e5", nu, edge));
            println!(
                "hanging, nu {nu}, edge {} mm: sag {nodal:.4} mm nodal, {element:.4} element, {lattice:.4} lattice",
                edge * 1e3
            );
        }
    }
    let loads = [9.73, 14.3];
    for edge in [0.005, 0.004, 0.0025] {
        for (name, elasticity, pressure, contact) in [
            ("nodal", Elasticity::NeoHookean, BulkPressure::Nodal, 3.0),
            (
                "nodal, stiff contact",
                Elasticity::NeoHookean,
                BulkPressure::Nodal,
                30.0,
            ),
            (
                "element",
                Elasticity::NeoHookean,
                BulkPressure::Element,
                3.0,
            ),
            ("lattice", Elasticity::Springs, BulkPressure::Element, 3.0),
        ] {
            let d = indentation(elasticity, pressure, edge, contact, &loads);
            println!(
                "indentation, {name}, edge {} mm: depth {:.3} / {:.3} mm at 9.73 / 14.3 N, top centre {:.3} / {:.3} mm",
                edge * 1e3,
                d[0].0 * 1e3,
                d[1].0 * 1e3,
                d[0].1 * 1e3,
                d[1].1 * 1e3
            );
        }
    }
}
