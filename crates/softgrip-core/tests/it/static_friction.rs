//! Coulomb friction in static solves (a return mapping: `contact::table`, `contact::commit`): a block
//! pressed onto the table, or a plate pressed onto a block, and pushed sideways stays where the
//! push is below mu times the press (every table contact inside its friction cone) and finds no
//! rest where the push exceeds it.

use softgrip_core::contact::table::total_force;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::error::SimError;

use crate::support::{WEIGHTLESS, cuboid_scene, simulation};

const MU: f64 = 0.4;
const PRESS: f64 = 2.0;

/// A weightless neo-Hookean 30 x 20 x 10 mm block at 4 mm edges with the scene tables `rest`
/// (support, loads, fingers).
fn block(rest: &str, name: &str) -> softgrip_core::Simulation {
    let more = format!(
        "young_modulus = 5e4\npoisson_ratio = 0.45\n\n[model]\nelasticity = \"neo-hookean\"\n\n{rest}"
    );
    simulation(
        &cuboid_scene(WEIGHTLESS, [0.03, 0.02, 0.01], 0.004, &more),
        name,
    )
}

/// A static solve that must find no rest: something slides for ever.
fn assert_slides(mut sim: softgrip_core::Simulation, what: &str) {
    let result = sim.equilibrium(StaticOptions::default());
    assert!(
        matches!(result, Err(SimError::NoEquilibrium { .. })),
        "{what} slides for ever, yet: {result:?}"
    );
}

/// The block on a table with friction [`MU`], its top face pressed down by [`PRESS`] N and pushed
/// along x by `push` N.
fn pushed_block(push: f64) -> softgrip_core::Simulation {
    let rest = format!(
        r#"[support]
kind = "table"
friction = {MU}

[[load]]
min = [-0.02, -0.02, 0.0099]
max = [0.02, 0.02, 0.011]
force = [{push}, 0.0, -{PRESS}]
"#
    );
    block(&rest, "pushed_block.toml")
}

#[test]
fn a_push_below_the_friction_limit_is_held() {
    let push = 0.5 * MU * PRESS;
    let mut sim = pushed_block(push);
    sim.equilibrium(StaticOptions::default())
        .unwrap_or_else(|e| panic!("the table holds a push of half the limit: {e}"));
    // The table carries the whole load back (nothing else holds the block).
    let f = total_force(&sim.state);
    assert!(
        (f.x + push).abs() < 0.01 * push && (f.z - PRESS).abs() < 0.01 * PRESS,
        "table force {f} against the load ({push}, 0, -{PRESS})"
    );
    // Every contact inside its cone: Coulomb's law holds point by point.
    for c in &sim.state.table {
        assert!(
            c.tangential_force.length() <= MU * c.normal_force * (1.0 + 1e-9) + 1e-12,
            "a contact carries {} tangentially under {} normally",
            c.tangential_force.length(),
            c.normal_force
        );
    }
}

#[test]
fn a_push_beyond_the_friction_limit_has_no_rest() {
    assert_slides(
        pushed_block(1.5 * MU * PRESS),
        "a block pushed by 1.5 x mu times the press",
    );
}

/// The block bonded at the bottom under a plate with friction [`MU`], pressed down by [`PRESS`]
/// N and pushed along x by `push` N.
fn sheared_under_a_plate(push: f64) -> softgrip_core::Simulation {
    let rest = format!(
        r#"[support]
kind = "fixed-bottom"

[[finger]]
shape = "plate"
size = [0.06, 0.06]
position = [0.0, 0.0, 0.01]
free_axes = "xz"
control = "force"
force = [{push}, 0.0, -{PRESS}]
mass = 0.0
friction = {MU}
"#
    );
    block(&rest, "sheared_under_a_plate.toml")
}

#[test]
fn a_finger_holds_by_friction_below_its_limit_and_slides_beyond() {
    let mut held = sheared_under_a_plate(0.5 * MU * PRESS);
    held.equilibrium(StaticOptions::default())
        .unwrap_or_else(|e| panic!("friction holds half its limit: {e}"));
    let f = held.state.fingers[0].contact_force;
    assert!(
        (f.x + 0.5 * MU * PRESS).abs() < 0.01 * PRESS && (f.z - PRESS).abs() < 0.01 * PRESS,
        "the object pushes back on the plate with {f}"
    );
    assert_slides(
        sheared_under_a_plate(1.5 * MU * PRESS),
        "a plate pushed by 1.5 x mu times the press",
    );
}
