//! Box fingers and compound fingers (`[[finger.part]]`): contact detected and
//! forces applied for each shape.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;

use crate::support::rest;

fn scene(text: &str) -> Scene {
    Scene::from_toml_str(text, "shapes.toml").expect("scene")
}

const BLOCK: &str = r#"
[object]
shape = "cuboid"
size = [0.03, 0.03, 0.02]
edge_length = 0.005
young_modulus = 60e3
poisson_ratio = 0.45

[model]
bulk_modulus = 6e5
"#;

/// A box's bottom face is a plate: pressing a block, the box and a plate of
/// the same extent in the same place run the same.
#[test]
fn a_box_pressing_with_its_bottom_face_is_the_plate() {
    let finger = |shape: &str| {
        format!(
            "{BLOCK}\n[[finger]]\n{shape}\nfree_axes = \"z\"\ncontrol = \"force\"\nforce = [0.0, 0.0, -2.0]\nfriction = 0.3\n"
        )
    };
    let plate = scene(&finger(
        "shape = \"plate\"\nsize = [0.05, 0.05]\nposition = [0.0, 0.0, 0.0201]",
    ));
    let boxed = scene(&finger(
        "shape = \"box\"\nsize = [0.05, 0.05, 0.01]\nposition = [0.0, 0.0, 0.0251]",
    ));
    let mut a = Simulation::new(&plate).expect("plate");
    let mut b = Simulation::new(&boxed).expect("box");
    for _ in 0..400 {
        a.step().expect("plate step");
        b.step().expect("box step");
    }
    assert!(a.state.contacts.len() > 10, "the plate presses");
    assert_eq!(a.state.contacts.len(), b.state.contacts.len());
    // The same law on the same facets; only rounding differs (the stick
    // anchors are kept relative to centres 5 mm apart).
    let worst = a
        .state
        .positions
        .iter()
        .zip(&b.state.positions)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "particles differ by up to {worst:e} m");
    let (fa, fb) = (a.state.fingers[0], b.state.fingers[0]);
    assert!((fa.position.z - (fb.position.z - 0.005)).abs() < 1e-9);
    assert!(
        fa.contact_force.distance(fb.contact_force) < 1e-6,
        "{:?} against {:?}",
        fa.contact_force,
        fb.contact_force
    );
    assert!(fa.position.z < 0.0199, "and it pressed in");
}

/// Two boxes squeeze a block from either side along x: each face pushes
/// along its own normal, the contact forces balance the applied ones and
/// the block stays centred.
#[test]
fn boxes_pinch_a_block_from_the_sides() {
    let text = format!(
        "{BLOCK}
[[finger]]
shape = \"box\"
size = [0.01, 0.04, 0.01]
position = [-0.0201, 0.0, 0.01]
free_axes = \"x\"
force = [1.5, 0.0, 0.0]
friction = 0.0

[[finger]]
shape = \"box\"
size = [0.01, 0.04, 0.01]
position = [0.0201, 0.0, 0.01]
free_axes = \"x\"
force = [-1.5, 0.0, 0.0]
friction = 0.0
"
    );
    let mut sim = Simulation::new(&scene(&text)).expect("pinch");
    sim.settle(rest(), |_| {}).expect("rest");
    for (k, sign) in [(0, 1.0), (1, -1.0)] {
        let f = sim.state.fingers[k].contact_force;
        assert!(
            (f.x + sign * 1.5).abs() < 1e-3 * 1.5,
            "finger {k}: contact force {f:?} against an applied {} N",
            sign * 1.5
        );
        assert!(f.y.abs() < 1e-6 && f.z.abs() < 1e-6, "frictionless: {f:?}");
    }
    for c in &sim.state.contacts {
        let expected = if c.finger == 0 {
            DVec3::X
        } else {
            DVec3::NEG_X
        };
        assert_eq!(c.normal, expected, "a side face pushes along its normal");
    }
    let gap = sim.state.fingers[1].position.x + sim.state.fingers[0].position.x;
    assert!(gap.abs() < 1e-6, "centred: {gap:e} m off");
    let squeezed =
        0.03 - (sim.state.fingers[1].position.x - sim.state.fingers[0].position.x - 0.01);
    assert!(squeezed > 1e-4, "the block is squeezed by {squeezed:e} m");
}

/// A finger of two spheres side by side presses a block: both touch, each
/// carries half the load (the scene is symmetric about x = 0), and their
/// contacts say which part they belong to.
#[test]
fn a_compound_finger_presses_with_each_of_its_parts() {
    let text = format!(
        "{BLOCK}
[[finger]]
shape = \"sphere\"
radius = 0.005
position = [-0.008, 0.0, 0.0251]
free_axes = \"z\"
force = [0.0, 0.0, -2.0]
friction = 0.0
contact_stiffness_scale = 3

[[finger.part]]
shape = \"sphere\"
radius = 0.005
offset = [0.016, 0.0, 0.0]
"
    );
    let sc = scene(&text);
    assert_eq!(sc.fingers[0].parts.len(), 1);
    // The file written back reads the same.
    assert_eq!(
        Scene::from_toml_str(&sc.to_toml(), "again.toml")
            .expect("round trip")
            .fingers,
        sc.fingers
    );
    let mut sim = Simulation::new(&sc).expect("compound");
    sim.settle(rest(), |_| {}).expect("rest");
    let by_part = |part: u32| -> DVec3 {
        sim.state
            .contacts
            .iter()
            .filter(|c| c.part == part)
            .map(|c| -(c.normal * c.normal_force + c.tangential_force))
            .sum()
    };
    let (a, b) = (by_part(0), by_part(1));
    assert!(a.z > 0.0 && b.z > 0.0, "both spheres press: {a:?} {b:?}");
    assert!(
        (a.z + b.z - 2.0).abs() < 2e-3,
        "together they carry the load: {} N",
        a.z + b.z
    );
    assert!(
        (a.z - b.z).abs() < 0.02 * 2.0,
        "and share it evenly: {} N and {} N",
        a.z,
        b.z
    );
}

#[test]
fn bad_finger_shapes_name_the_key_and_line() {
    let cases = [
        (
            "[[finger]]\nshape = \"box\"\nsize = [0.01, 0.02]\nposition = [0.0, 0.0, 0.05]\n",
            "size",
        ),
        (
            "[[finger]]\nshape = \"cone\"\nposition = [0.0, 0.0, 0.05]\n",
            "\"sphere\", \"plate\" or \"box\"",
        ),
        (
            "[[finger]]\nposition = [0.0, 0.0, 0.05]\n[[finger.part]]\nshape = \"sphere\"\nradius = -0.01\n",
            "[[finger.part]] #1",
        ),
        (
            "[[finger]]\nposition = [0.0, 0.0, 0.05]\n[[finger.part]]\nshape = \"box\"\nsize = [0.01, 0.01, 0.01]\nofset = [0.0, 0.0, 0.0]\n",
            "ofset",
        ),
    ];
    for (finger, expect) in cases {
        let text = format!("{BLOCK}\n{finger}");
        let e = Scene::from_toml_str(&text, "bad.toml").expect_err(finger);
        let message = e.to_string();
        assert!(
            message.contains(expect) && message.contains("bad.toml"),
            "{finger}: {message}"
        );
    }
}
