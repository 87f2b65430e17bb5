//! The table's Coulomb friction in static solves (a return mapping, `contact::table`): a block
//! pressed onto the table and pushed sideways stays where the push is below mu times the press,
//! with every contact inside its friction cone, and finds no rest where the push exceeds it.

use softgrip_core::contact::table::total_force;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_core::error::SimError;

use crate::support::{WEIGHTLESS, cuboid_scene, simulation};

const MU: f64 = 0.4;
const PRESS: f64 = 2.0;

/// A weightless neo-Hookean 30 x 20 x 10 mm block on a table with friction [`MU`], its top face pressed down
/// by [`PRESS`] N and pushed along x by `push` N.
fn pushed_block(push: f64) -> softgrip_core::Simulation {
    let more = format!(
        r#"young_modulus = 5e4
poisson_ratio = 0.45

[model]
elasticity = "neo-hookean"

[support]
kind = "table"
friction = {MU}

[[load]]
min = [-0.02, -0.02, 0.0099]
max = [0.02, 0.02, 0.011]
force = [{push}, 0.0, -{PRESS}]
"#
    );
    let text = cuboid_scene(WEIGHTLESS, [0.03, 0.02, 0.01], 0.004, &more);
    simulation(&text, "pushed_block.toml")
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
    let mut sim = pushed_block(1.5 * MU * PRESS);
    let result = sim.equilibrium(StaticOptions::default());
    assert!(
        matches!(result, Err(SimError::NoEquilibrium { .. })),
        "a push of 1.5 x mu times the press slides for ever, yet: {result:?}"
    );
}
