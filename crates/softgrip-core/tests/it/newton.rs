//! Newton's method on the exact tangent, solved by a sparse factorisation
//! (`StaticSolver::Direct`): its tangent is the static force's derivative, its solves invert it,
//! and where the equilibrium is unique it finds CG's answer.

use glam::DVec3;
use softgrip_core::Simulation;
use softgrip_core::equilibrium::{StaticOptions, StaticSolver};
use softgrip_core::scene::{BulkPressure, Elasticity, Scene, SupportKind};

use crate::support::{largest_distance, shipped_scene};

/// The light-guide cuboid as the continuum (neo-Hookean, nodal pressures) at `edge` m, its
/// finger's friction `mu`.
fn continuum(edge: f64, mu: f64) -> Scene {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = edge;
    scene.model.elasticity = Elasticity::NeoHookean;
    scene.model.bulk_pressure = BulkPressure::Nodal;
    scene.model.tau_s = None;
    scene.model.tau_c = None;
    scene.fingers[0].friction = mu;
    scene
}

fn solved(scene: &Scene, loads: &[f64], solver: StaticSolver) -> Simulation {
    let mut sim = Simulation::new(scene).expect("simulation");
    let k = sim.load_finger().expect("a loaded finger");
    let options = StaticOptions {
        solver,
        tolerance: 1e-10,
        ..StaticOptions::default()
    };
    for &load in loads {
        let from: Vec<DVec3> = sim.state.fingers.iter().map(|f| f.applied_force).collect();
        sim.set_load(k, load);
        sim.equilibrium_from(&from, options).expect("equilibrium");
    }
    sim
}

#[test]
fn factorised_newton_finds_cgs_equilibrium_to_a_micrometre_where_it_is_unique() {
    // Frictionless, so that the answer depends on no path: the 4 mm continuum's loads to the
    // thesis's 14.3 N.
    let scene = continuum(0.004, 0.0);
    let loads = [2.04, 6.13, 10.21, 14.3];
    let cg = solved(&scene, &loads, StaticSolver::Cg);
    let direct = solved(&scene, &loads, StaticSolver::Direct);
    let d = largest_distance(&cg, &direct);
    eprintln!("largest difference {:.4} um", d * 1e6);
    assert!(
        d < 1e-6,
        "CG's and the factorised solve's equilibria differ by {d:e} m"
    );
}

#[test]
fn on_a_table_with_friction_factorised_newton_carries_every_load() {
    // The continuum loose on a table (mu 0.6): the friction's coupling to the penetration is in
    // the tangent, and the line search steps over contacts switching between stick and slip.
    let mut scene = continuum(0.008, 0.5);
    scene.support.kind = SupportKind::Table;
    scene.support.friction = 0.6;
    let loads = [3.0, 9.0, 14.3, 6.0];
    let sim = solved(&scene, &loads, StaticSolver::Direct);
    let carried = sim.state.fingers[0].contact_force.z;
    assert!(
        (carried - 6.0).abs() < 1e-6,
        "the finger's contact carries {carried} N of 6 N"
    );
    let table = softgrip_core::contact::table::total_force(&sim.state);
    let weight = sim.model.mass.iter().sum::<f64>() * 9.81;
    assert!(
        (table.z - (6.0 + weight)).abs() < 1e-5,
        "the table carries {} N of {} N",
        table.z,
        6.0 + weight
    );
}

#[test]
fn the_full_tangent_is_the_static_forces_derivative_and_the_factorised_solve_inverts_it() {
    // A continuum with one- and two-term stiffening on a table with friction, under the
    // finger with friction: at the equilibrium, Kp v against central differences of the force
    // along v, and the factorised solve of Kp y = Kp v gives back v.
    let mut scene = continuum(0.008, 0.5);
    scene.model.stiffening = 5.0;
    scene.model.stiffening_cubic = 20.0;
    scene.model.softening = 0.3;
    scene.support.kind = SupportKind::Table;
    scene.support.friction = 0.3;
    tangent_against_differences(&scene);
}

#[test]
fn with_gents_locking_the_full_tangent_is_still_the_forces_derivative() {
    // Gent's law (J_m 0.5: the loaded elements stiffened by their locking) on the same
    // continuum and table.
    let mut scene = continuum(0.008, 0.5);
    scene.model.gent_limit = 0.5;
    scene.support.kind = SupportKind::Table;
    scene.support.friction = 0.3;
    tangent_against_differences(&scene);
}

/// At the equilibrium of `scene` under 3 then 9 N: `Kp v` against central differences of the
/// force along a smooth `v`, asserted within 1e-5, and the factorised solve of `Kp y = Kp v`
/// giving back `v` (its residual within 1e-9).
fn tangent_against_differences(scene: &softgrip_core::Scene) {
    let sim = solved(scene, &[3.0, 9.0], StaticSolver::Direct);
    let mut fixed = sim.fixed_state();
    assert!(fixed.is_factorised(), "the 8 mm cuboid is factorised");
    let model = std::sync::Arc::clone(fixed.model());
    let mask = fixed.mask();
    // A smooth field over the particles, and the finger.
    let v: Vec<DVec3> = sim
        .model
        .rest_positions
        .iter()
        .map(|p| {
            DVec3::new(
                (80.0 * p.y).sin(),
                (60.0 * p.x).cos(),
                (70.0 * (p.x + p.z)).sin(),
            )
        })
        .chain(std::iter::once(DVec3::new(0.0, 0.0, 1.0)))
        .zip(&mask)
        .map(|(v, m)| v * *m)
        .collect();
    let kv = fixed.tangent_product(&v).expect("factorised");
    let h = 1e-8;
    let ahead = fixed.force(&model, Some((&v, h)));
    let behind = fixed.force(&model, Some((&v, -h)));
    let fd: Vec<DVec3> = ahead
        .iter()
        .zip(&behind)
        .map(|(a, b)| (*b - *a) / (2.0 * h))
        .collect();
    let largest = |x: &[DVec3]| x.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max);
    let diff: Vec<DVec3> = kv.iter().zip(&fd).map(|(a, b)| *a - *b).collect();
    let error = largest(&diff) / largest(&fd);
    eprintln!("|Kp v - differences| / |differences| = {error:.2e}");
    assert!(
        error < 1e-5,
        "the tangent is off its force's derivative by {error:e}"
    );
    let mut y = Vec::new();
    fixed
        .solve(
            &kv,
            &mut y,
            softgrip_core::solver::CgParams {
                tolerance: 1e-12,
                reference: 0.0,
                max_iterations: 1,
            },
        )
        .expect("solve");
    // The solve's residual is what it controls (GMRES to 1e-10 over the factor, for the
    // friction's non-symmetric part); the answer's error is that times the conditioning.
    let ky = fixed.tangent_product(&y).expect("factorised");
    let residual: Vec<DVec3> = ky.iter().zip(&kv).map(|(a, b)| *a - *b).collect();
    let solve_residual = largest(&residual) / largest(&kv);
    let back: Vec<DVec3> = y.iter().zip(&v).map(|(a, b)| *a - *b).collect();
    eprintln!(
        "|Kp y - Kp v| / |Kp v| = {solve_residual:.2e}, |y - v| / |v| = {:.2e}",
        largest(&back) / largest(&v)
    );
    assert!(
        solve_residual < 1e-9,
        "the factorised solve leaves {solve_residual:e}"
    );
}
