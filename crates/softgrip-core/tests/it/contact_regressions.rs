//! Regression tests named after what broke.

use softgrip_core::Simulation;

use crate::support::{WEIGHTLESS, cuboid_scene, rest_within, shipped_scene, simulation};

/// Without the lever stiffness in the contact Jacobian, particles under a
/// 15 mm sphere on a 3 mm mesh oscillated at period two from about 3 N and
/// never came to rest.
#[test]
fn sphere_on_fine_mesh_comes_to_rest_at_5n_without_period_two_oscillation() {
    let text = cuboid_scene(
        WEIGHTLESS,
        [0.06, 0.06, 0.03],
        0.003,
        r#"[model]
alpha = 0.0
[[finger]]
radius = 0.015
position = [0.0, 0.0, 0.045]
force = [0.0, 0.0, -5.0]
friction = 0.0
"#,
    );
    let mut sim = simulation(&text, "fine block");
    let rest = sim
        .settle(rest_within(1e-6, 3.0), |_| {})
        .expect("comes to rest");
    assert!((sim.state.fingers[0].contact_force.z - 5.0).abs() < 0.01 * 5.0);
    assert!(rest.steps < 3000);
}

/// Projecting the spring limits used to push particles back into the finger
/// pressing them; the finger never came to rest, even at 1 N.
#[test]
fn spring_limits_do_not_fight_the_finger_at_1n() {
    let scene = shipped_scene("thesis_cuboid_no_bulk.toml");
    let mut sim = Simulation::new(&scene).expect("sim");
    sim.set_load(0, 1.0);
    sim.settle(rest_within(1e-5, 3.0), |_| {})
        .expect("comes to rest");
    let finger = sim.state.fingers[0];
    assert!((finger.contact_force.z - 1.0).abs() < 0.01);
    assert!(finger.max_penetration < 0.05 * 0.015);
}
