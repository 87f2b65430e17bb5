//! softgrip against an independent finite element code: NGSolve's solutions of the same
//! problems, computed by `scripts/reference/ngsolve_reference.py` and committed in
//! `tests/reference/ngsolve.json` (library, version and run time in its README). The continuum
//! option (neo-Hookean elements, nodal pressures) is compared with them; the spring lattice's
//! error on the same problems is printed. The figures of docs/results/accuracy.md at every mesh:
//! `cargo run --release -p softgrip-core --example reference_figures`.

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

/// The force (N) on the top plate of the 50 mm x 30 mm cylinder bonded to two plates and
/// compressed to each of `strains` (reference problem 2), with its barrel (the largest radial
/// displacement at mid-height, m). The top nodes are held at their compressed places, so no
/// point slides on a plate.
pub fn bonded_cylinder(model: &str, edge: f64, strains: &[f64]) -> Vec<(f64, f64)> {
    let (radius, height) = (0.025, 0.03);
    let text = format!(
        "[simulation]\n{}\n[object]\nshape = \"cylinder\"\nradius = {radius}\nheight = {height}\nedge_length = {edge:?}\ndensity = 1070.0\nyoung_modulus = 103.46e3\npoisson_ratio = 0.49\n[model]\n{model}\n[support]\nkind = \"fixed-bottom\"\n[[fixed]]\nmin = [-1.0, -1.0, {}]\nmax = [1.0, 1.0, 1.0]\n",
        crate::support::WEIGHTLESS,
        height - 1e-6
    );
    let mut sim = simulation(&text, "bonded cylinder");
    let top: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| sim.model.rest_positions[i].z > height - 1e-6)
        .collect();
    let middle: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| (sim.model.rest_positions[i].z - height / 2.0).abs() < 0.26 * edge)
        .collect();
    strains
        .iter()
        .map(|&strain| {
            for &i in &top {
                sim.state.positions[i].z = height * (1.0 - strain);
            }
            sim.equilibrium(StaticOptions::default())
                .unwrap_or_else(|e| panic!("strain {strain}: {e}"));
            let barrel = middle
                .iter()
                .map(|&i| {
                    let (p, r) = (sim.state.positions[i], sim.model.rest_positions[i]);
                    p.truncate().length() - r.truncate().length()
                })
                .fold(0.0, f64::max);
            (-sim.reaction(|i| top.contains(&i)).z, barrel)
        })
        .collect()
}

/// The light-guide scene (the thesis indentation) without friction at `edge`, its contact
/// `contact_scale` times the thesis's stiffness: at each load the top centre's sag (m, positive
/// down), the body's depth under the finger. (The finger's own depth adds the penalty's
/// penetration, and facet contact lets the surface's nodes poke into the sphere by about
/// `h^2 / (2 R)`: both mesh and penalty artefacts, not the solid's.)
pub fn indentation_sag(
    elasticity: Elasticity,
    pressure: BulkPressure,
    edge: f64,
    contact_scale: f64,
    loads: &[f64],
) -> Vec<f64> {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = edge;
    scene.model.elasticity = elasticity;
    scene.model.bulk_pressure = pressure;
    scene.fingers[0].friction = 0.0;
    scene.fingers[0].contact_stiffness_scale = contact_scale;
    let mut sim = softgrip_core::Simulation::new(&scene).expect("the scene");
    let top = glam::DVec3::new(0.0, 0.0, 0.02);
    let centre = (0..sim.model.particle_count())
        .find(|&i| (sim.model.rest_positions[i] - top).length() < 1e-9)
        .expect("a node at the top centre");
    loads
        .iter()
        .map(|&load| {
            sim.set_load(0, load);
            sim.equilibrium(StaticOptions::default())
                .unwrap_or_else(|e| panic!("{load} N: {e}"));
            sim.model.rest_positions[centre].z - sim.state.positions[centre].z
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

/// Problem 2: the bonded cylinder's force against NGSolve's (axisymmetric, order 4, converged to
/// 0.3 %) at strains 0.02 to 0.2. Linear tetrahedra converge slowly at the bonded rims (a
/// singular corner): the continuum is 10-20 % stiff at 5 mm, 4.5-11 % at 2.5 mm (2-6 % at
/// 1.25 mm, measured once by hand). So the test asserts convergence to the reference: the error at least
/// 40 % smaller from 5 to 2.5 mm at every strain, and the first-order extrapolation
/// `2 f(2.5) - f(5)` within 2 %. The lattice's and the plain tetrahedra's errors are printed.
#[test]
#[ignore = "slow: bonded cylinders at 5 and 2.5 mm"]
fn the_bonded_cylinder_converges_to_the_reference() {
    let reference = reference();
    let steps = reference["problems"]["cylinder"]["result"]["steps"]
        .as_array()
        .expect("steps")
        .clone();
    let figure = |s: &serde_json::Value, key: &str| s[key].as_f64().expect("a figure");
    let strains: Vec<f64> = steps.iter().map(|s| figure(s, "strain")).collect();
    let expected: Vec<f64> = steps.iter().map(|s| figure(s, "force_N")).collect();
    let forces = |model: &str, edge: f64| -> Vec<f64> {
        bonded_cylinder(model, edge, &strains)
            .into_iter()
            .map(|(force, _)| force)
            .collect()
    };
    let coarse = forces("elasticity = \"neo-hookean\"", 0.005);
    let fine = forces("elasticity = \"neo-hookean\"", 0.0025);
    let element = forces(
        "elasticity = \"neo-hookean\"\nbulk_pressure = \"element\"",
        0.0025,
    );
    let lattice = forces("alpha = 0.0\nbulk_modulus = 9.6e5", 0.0025);
    let error = |f: f64, r: f64| 100.0 * (f / r - 1.0);
    for (k, &strain) in strains.iter().enumerate() {
        let r = expected[k];
        let extrapolated = 2.0 * fine[k] - coarse[k];
        eprintln!(
            "strain {strain:.2}: NGSolve {r:.3} N; continuum 5 mm {:+.1} %, 2.5 mm {:+.1} %, extrapolated {:+.1} %; plain tets 2.5 mm {:+.1} %; lattice 2.5 mm {:+.1} %",
            error(coarse[k], r),
            error(fine[k], r),
            error(extrapolated, r),
            error(element[k], r),
            error(lattice[k], r)
        );
        assert!(
            (fine[k] - r).abs() < 0.6 * (coarse[k] - r).abs(),
            "strain {strain}: no convergence to the reference"
        );
        assert!(
            error(extrapolated, r).abs() < 2.0,
            "strain {strain}: extrapolated {:+.2} %",
            error(extrapolated, r)
        );
    }
}

/// Problem 3: the thesis indentation's depth at 9.73 and 14.3 N (the body's, at the top centre)
/// within 2 % of NGSolve's (order 3, converged to 0.2 %) at 4 mm and within 1 % at 2.5 mm; the
/// plain tetrahedra's and the lattice's errors printed.
#[test]
#[ignore = "slow: the 4 and 2.5 mm indentations"]
fn the_indentation_agrees_with_the_reference() {
    let reference = reference();
    let loads = [9.73, 14.3];
    let expected: Vec<f64> = loads
        .iter()
        .map(|f| {
            -reference["problems"]["indentation"]["result"][format!("F={f}")]["top_uz_m"][0]
                .as_f64()
                .expect("a figure")
        })
        .collect();
    let stiff = 30.0;
    let nodal = indentation_sag(
        Elasticity::NeoHookean,
        BulkPressure::Nodal,
        0.004,
        stiff,
        &loads,
    );
    let fine = indentation_sag(
        Elasticity::NeoHookean,
        BulkPressure::Nodal,
        0.0025,
        stiff,
        &loads,
    );
    let plain = indentation_sag(
        Elasticity::NeoHookean,
        BulkPressure::Element,
        0.004,
        stiff,
        &loads,
    );
    let lattice = indentation_sag(
        Elasticity::Springs,
        BulkPressure::Element,
        0.004,
        3.0,
        &loads,
    );
    let error = |x: f64, r: f64| 100.0 * (x / r - 1.0);
    for (k, f) in loads.iter().enumerate() {
        let r = expected[k];
        eprintln!(
            "indentation, {f} N: NGSolve {:.3} mm; continuum 2.5 mm {:.3} mm ({:+.1} %); 4 mm: continuum {:.3} mm ({:+.1} %), plain tets {:.3} ({:+.1} %), lattice {:.3} ({:+.1} %)",
            r * 1e3,
            fine[k] * 1e3,
            error(fine[k], r),
            nodal[k] * 1e3,
            error(nodal[k], r),
            plain[k] * 1e3,
            error(plain[k], r),
            lattice[k] * 1e3,
            error(lattice[k], r)
        );
        assert!(
            error(nodal[k], r).abs() < 2.0,
            "{f} N, 4 mm: {:+.2} %",
            error(nodal[k], r)
        );
        assert!(
            error(fine[k], r).abs() < 1.0,
            "{f} N, 2.5 mm: {:+.2} %",
            error(fine[k], r)
        );
    }
}
