//! Sensitivities of a static equilibrium (`softgrip_lab::sensitivity`) against central
//! differences of whole equilibrium solves at `p -+ 1e-3 p`, both started from the same state:
//! the thesis cuboid under the light-guide sphere, at 8 mm edges and at its own 4 mm. The
//! measured agreement is the table in `docs/design/equilibrium.md`, "Sensitivities" (run with
//! `--nocapture`).

use glam::DVec3;
use softgrip_core::Simulation;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::mesh::TetMesh;
use softgrip_core::model::Model;
use softgrip_core::scene::Scene;
use softgrip_core::sensitivity::SensitivityOptions;
use softgrip_core::state::State;
use softgrip_lab::params;
use softgrip_lab::sensitivity::{ParameterSensitivity, WITH_SENSITIVITY, sensitivities};

use crate::support::{asset, light_guide_scene};

/// The whole solves' relative step.
const STEP: f64 = 1e-3;

/// Agreement asked of every parameter: max-norm over particles and fingers, relative to the
/// largest component of the difference quotient.
const AGREEMENT: f64 = 1e-3;

fn tight() -> StaticOptions {
    StaticOptions {
        tolerance: 1e-11,
        move_tolerance: 1e-12,
        ..StaticOptions::default()
    }
}

/// The light-guide scene at 8 mm edges with a tight CG, the finger free along `free_axes`.
fn scene(friction: f64, free_axes: [bool; 3]) -> Scene {
    let mut scene = Scene::from_toml_str(&light_guide_scene(0.008), "light guide").expect("scene");
    scene.simulation.cg_tolerance = 1e-12;
    scene.fingers[0].free_axes = free_axes;
    params::set(&scene, "friction", friction).expect("friction")
}

fn points(sim: &Simulation) -> Vec<DVec3> {
    let fingers = sim.state.fingers.iter().map(|f| f.position);
    sim.state.positions.iter().copied().chain(fingers).collect()
}

/// The equilibrium of `scene` from `start` under the finger force `push`.
fn solve(scene: &Scene, mesh: &TetMesh, start: &State, push: DVec3) -> Simulation {
    solve_along(scene, mesh, start, &[push])
}

/// The equilibria of `scene` from `start` under each finger force of `path` in turn: the last.
fn solve_along(scene: &Scene, mesh: &TetMesh, start: &State, path: &[DVec3]) -> Simulation {
    let mut sim = Simulation::from_model(Model::from_mesh(scene, mesh.clone()).expect("model"));
    sim.state = start.clone();
    for &push in path {
        sim.state.fingers[0].applied_force = push;
        sim.equilibrium(tight()).expect("equilibrium");
    }
    sim
}

/// `dx/dp` by central differences of whole solves from `start` along the finger forces `path`.
fn whole_solves(
    scene: &Scene,
    mesh: &TetMesh,
    start: &State,
    path: &[DVec3],
    name: &str,
) -> Vec<DVec3> {
    let value = params::get(scene, name).expect("known").expect("set");
    let at = |v: f64| {
        let scene = params::set(scene, name, v).expect("set");
        points(&solve_along(&scene, mesh, start, path))
    };
    // Central, or forward from a parameter at 0 (its range's end: a guide friction from 0).
    let (up, down, span) = if value == 0.0 {
        (at(STEP), at(0.0), STEP)
    } else {
        let d = STEP * value;
        (at(value + d), at(value - d), 2.0 * d)
    };
    up.iter()
        .zip(&down)
        .map(|(u, w)| (*u - *w) / span)
        .collect()
}

/// The largest difference over the largest component of `reference`, and that component.
fn disagreement(s: &[DVec3], reference: &[DVec3]) -> (f64, f64) {
    let largest = |v: &[DVec3]| v.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max);
    let scale = largest(reference);
    let diff: Vec<DVec3> = s.iter().zip(reference).map(|(a, b)| *a - *b).collect();
    (largest(&diff) / scale, scale)
}

fn check(p: &ParameterSensitivity, reference: &[DVec3], assembled: &[DVec3]) {
    let (error, scale) = disagreement(&p.dx_dp, reference);
    let (assembled_error, _) = disagreement(assembled, reference);
    eprintln!(
        "{:>13}: |dx/dp| {scale:.3e} m, relative error {error:.1e} ({} GMRES products); \
         CG on the assembled tangent alone: {assembled_error:.1e}",
        p.name, p.iterations
    );
    // Not trivially zero: the parameter acts at this equilibrium.
    assert!(scale > 0.0, "{}: dx/dp is zero", p.name);
    assert!(error <= AGREEMENT, "{}: {error:e}", p.name);
}

fn assembled_only() -> SensitivityOptions {
    SensitivityOptions {
        exact: false,
        ..SensitivityOptions::default()
    }
}

#[test]
fn dx_dp_agrees_with_whole_solves_for_the_elastic_parameters() {
    // Frictionless, so that the equilibrium depends on no path; limits tight enough that
    // springs under the sphere sit on their tau_c limit springs and springs beside it on their
    // tau_s ones at 4 N; a stiffening that is not zero.
    let mut scene = scene(0.0, [false, false, true]);
    scene.model.tau_s = Some(0.04);
    scene.model.tau_c = Some(0.08);
    scene.model.stiffening = 2.0;
    // The lattice's parameters fits take sensitivities for (friction has its own test below;
    // the continuum's are checked on the continuum).
    let names = [
        "young_modulus",
        "alpha",
        "bulk_modulus",
        "stiffening",
        "tau_s",
        "tau_c",
    ];
    assert!(names.iter().all(|n| WITH_SENSITIVITY.contains(n)));
    check_frictionless(&scene, DVec3::new(0.0, 0.0, -4.0), &names);
}

/// Solves `scene` (frictionless: its equilibrium depends on no path) under the finger force
/// `push` and checks `dx/dp` for `names` against whole solves started from that equilibrium.
fn check_frictionless(scene: &Scene, push: DVec3, names: &[&str]) {
    let mesh = Model::mesh_of(scene).expect("mesh");
    let start = State::initial(&Model::from_mesh(scene, mesh.clone()).expect("model"));
    let sim = solve(scene, &mesh, &start, push);
    let exact = sensitivities(scene, &mesh, &sim, names, SensitivityOptions::default())
        .expect("sensitivities");
    let assembled = sensitivities(scene, &mesh, &sim, names, assembled_only()).expect("CG");
    for (p, a) in exact.iter().zip(&assembled) {
        let reference = whole_solves(scene, &mesh, &sim.state, &[push], p.name);
        check(p, &reference, &a.dx_dp);
    }
}

/// The scene pressed by 4 N, then pushed sideways by `sideways` N: its pressed state (the
/// whole solves' start) and its equilibrium.
fn pushed(scene: &Scene, mesh: &TetMesh, sideways: f64) -> (State, Simulation, DVec3) {
    let start = State::initial(&Model::from_mesh(scene, mesh.clone()).expect("model"));
    let pressed = solve(scene, mesh, &start, DVec3::new(0.0, 0.0, -4.0)).state;
    let push = DVec3::new(sideways, 0.0, -4.0);
    let sim = solve(scene, mesh, &pressed, push);
    (pressed, sim, push)
}

/// The finger contacts sliding at `sim`'s equilibrium.
fn sliding(sim: &Simulation) -> usize {
    sim.fixed_state().sliding_contacts().len()
}

#[test]
fn dx_dmu_agrees_with_whole_solves_where_contacts_slide_and_is_zero_where_they_stick() {
    // The sphere pressed by 4 N and pushed sideways, free along x and z: at 1.6 N the two
    // facets at the front of the contact patch slide (mu F_n reached), the others stick.
    let scene = scene(0.5, [true, false, true]);
    let mesh = Model::mesh_of(&scene).expect("mesh");
    let (pressed, sim, push) = pushed(&scene, &mesh, 1.6);
    let slide = sliding(&sim);
    eprintln!("{slide} contacts slide");
    assert!(slide > 0);
    let names = ["friction"];
    let exact = sensitivities(&scene, &mesh, &sim, &names, SensitivityOptions::default())
        .expect("sensitivities");
    let assembled = sensitivities(&scene, &mesh, &sim, &names, assembled_only()).expect("CG");
    let reference = whole_solves(&scene, &mesh, &pressed, &[push], "friction");
    check(&exact[0], &reference, &assembled[0].dx_dp);
    // The answer depends on the path: pushed in two steps, through 0.8 N, the sliding
    // contacts' drifts turn otherwise. The sensitivity agrees with that path too.
    let half = DVec3::new(0.8, 0.0, -4.0);
    let two_steps = whole_solves(&scene, &mesh, &pressed, &[half, push], "friction");
    let (path, _) = disagreement(&two_steps, &reference);
    let (error, _) = disagreement(&exact[0].dx_dp, &two_steps);
    eprintln!("pushed in two steps: the reference moves by {path:.1e}, the error is {error:.1e}");
    assert!(error <= AGREEMENT, "{error:e}");

    // At 0.9 N every contact sticks: their stick springs do not depend on mu, so dx/dmu is
    // zero by construction, and the whole solves agree.
    let (pressed, sim, push) = pushed(&scene, &mesh, 0.9);
    assert_eq!(sliding(&sim), 0);
    let s = sensitivities(&scene, &mesh, &sim, &names, SensitivityOptions::default())
        .expect("sensitivities");
    assert!(s[0].dx_dp.iter().all(|v| *v == DVec3::ZERO));
    let reference = whole_solves(&scene, &mesh, &pressed, &[push], "friction");
    assert!(reference.iter().all(|v| *v == DVec3::ZERO));
}

/// The shipped light-guide scene at its own 4 mm edges and fitted limits, frictionless.
fn shipped() -> Scene {
    let path = asset("assets/scenes/thesis_cuboid_light_guide.toml");
    let mut scene = Scene::load(&path).expect("scene");
    scene.simulation.cg_tolerance = 1e-12;
    params::set(&scene, "friction", 0.0).expect("friction")
}

#[test]
fn dx_dp_agrees_with_whole_solves_on_the_shipped_scene_at_its_own_mesh() {
    // At 4.17 N tau_c acts under the sphere, tau_s nowhere.
    let scene = shipped();
    let names = ["young_modulus", "alpha", "bulk_modulus", "tau_c"];
    check_frictionless(&scene, DVec3::new(0.0, 0.0, -4.17), &names);
}

#[test]
fn dx_de_agrees_with_whole_solves_with_each_volume_term_on_and_off() {
    // Which terms the assembled tangent lacks shows in its error (printed) as the bulk term
    // and alpha are switched off: with both off only the contact's are left out.
    for (alpha, bulk_modulus) in [(6e6, 9.6e5), (0.0, 9.6e5), (6e6, 0.0), (0.0, 0.0)] {
        let mut scene = shipped();
        scene.model.alpha = alpha;
        scene.model.bulk_modulus = bulk_modulus;
        eprintln!("alpha = {alpha:e}, bulk_modulus = {bulk_modulus:e}:");
        check_frictionless(&scene, DVec3::new(0.0, 0.0, -2.0), &["young_modulus"]);
    }
}

/// Acceptance asked of the continuum's sensitivities, from the factorised exact tangent alone
/// and with the force differences' check.
const CONTINUUM_AGREEMENT: f64 = 1e-4;

/// The light-guide cuboid at 8 mm as the continuum (neo-Hookean, nodal pressures), with the
/// finger's `friction`; `change` sets the effect under test.
fn continuum(friction: f64, change: impl FnOnce(&mut Scene)) -> Scene {
    let mut scene = scene(friction, [false, false, true]);
    scene.model.elasticity = softgrip_core::scene::Elasticity::NeoHookean;
    scene.model.bulk_pressure = softgrip_core::scene::BulkPressure::Nodal;
    scene.model.tau_s = None;
    scene.model.tau_c = None;
    scene.model.stiffening = 0.0;
    change(&mut scene);
    scene
}

/// `dx/dp` of the continuum at the equilibrium reached along `path` (finger forces), for
/// `names`, from the factor alone and with GMRES's force differences, against whole solves of
/// the path's last step (the friction anchors dragged before it held, as the linearisation
/// holds them).
fn check_continuum(scene: &Scene, path: &[DVec3], names: &[&str]) {
    let mesh = Model::mesh_of(scene).expect("mesh");
    let start = State::initial(&Model::from_mesh(scene, mesh.clone()).expect("model"));
    // The last load step is the one linearised: the friction anchors its start holds (where
    // earlier steps dragged them) are held in the reference too.
    let (last, before) = path.split_last().expect("a load");
    let pressed = solve_along(scene, &mesh, &start, before);
    let rest = &[*last][..];
    let sim = solve_along(scene, &mesh, &pressed.state, rest);
    let factor = sensitivities(scene, &mesh, &sim, names, assembled_only()).expect("factor");
    let checked = sensitivities(scene, &mesh, &sim, names, SensitivityOptions::default())
        .expect("sensitivities");
    for (p, f) in checked.iter().zip(&factor) {
        let reference = whole_solves(scene, &mesh, &pressed.state, rest, p.name);
        let (error, scale) = disagreement(&p.dx_dp, &reference);
        let (factor_error, _) = disagreement(&f.dx_dp, &reference);
        eprintln!(
            "{:>20}: |dx/dp| {scale:.3e}, factor alone {factor_error:.1e}, checked by force \
             differences {error:.1e} ({} products)",
            p.name, p.iterations
        );
        assert!(scale > 0.0, "{}: dx/dp is zero", p.name);
        assert!(
            factor_error <= CONTINUUM_AGREEMENT,
            "{}: {factor_error:e}",
            p.name
        );
        assert!(error <= CONTINUUM_AGREEMENT, "{}: {error:e}", p.name);
    }
}

#[test]
fn the_continuums_sensitivities_from_the_factor_agree_with_whole_solves() {
    let down = |f: f64| DVec3::new(0.0, 0.0, -f);
    // The elastic parameters, frictionless (no path): E, one- and two-term stiffening with
    // softening, the creep's relaxed share (its static limit: the long-term modulus), a
    // stiffer top half.
    let scene = continuum(0.0, |s| {
        s.model.stiffening = 5.0;
        s.model.stiffening_cubic = 20.0;
        s.model.softening = 0.3;
        s.model.prony_g = 0.3;
        s.regions.push(softgrip_core::scene::Region {
            region: softgrip_core::scene::AaBox {
                min: DVec3::new(-0.03, -0.03, 0.01),
                max: DVec3::new(0.03, 0.03, 0.03),
            },
            young_modulus: 2.0 * s.object.young_modulus,
            density: s.object.density,
        });
    });
    let names = [
        "young_modulus",
        "stiffening",
        "stiffening_cubic",
        "softening",
        "prony_g",
        "region_young_modulus",
    ];
    check_continuum(&scene, &[DVec3::ZERO, down(4.0)], &names);
    // On a table with friction, loaded in two steps: contacts at the rim slide.
    let scene = continuum(0.0, |s| {
        s.support.kind = softgrip_core::scene::SupportKind::Table;
        s.support.friction = 0.3;
    });
    check_continuum(
        &scene,
        &[DVec3::ZERO, down(2.0), down(4.0)],
        &["young_modulus", "table_friction"],
    );
    // The finger's friction, pressed and then pushed sideways so that contacts slide.
    let mut scene = continuum(0.5, |_| {});
    scene.fingers[0].free_axes = [true, true, true];
    check_continuum(
        &scene,
        &[
            down(4.0),
            DVec3::new(0.8, 0.0, -4.0),
            DVec3::new(1.6, 0.0, -4.0),
        ],
        &["friction"],
    );
    // The guide's friction: the finger slides in its guide, held back by F_g; and from 0 (the
    // load-loss candidate's null), where the last load step's slide sets its direction.
    let scene = continuum(0.0, |s| s.fingers[0].guide_friction = 0.5);
    check_continuum(&scene, &[DVec3::ZERO, down(4.0)], &["guide_friction"]);
    let scene = continuum(0.0, |_| {});
    check_continuum(&scene, &[down(2.0), down(4.0)], &["guide_friction"]);
}
