//! Picking and dragging geometry of the viewer (`softgrip_viewer::render::pick`):
//! the ray under a pixel hits what is drawn there, and a dragged finger
//! moves with the mouse along its free axes only.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_viewer::render::pick::{Picked, finger_target, on_plane, pick};
use softgrip_viewer::render::{View, frame_camera, geometry::plate_thickness};

const W: u32 = 640;
const H: u32 = 480;

fn thesis() -> Simulation {
    Simulation::new(&Scene::thesis()).expect("thesis scene")
}

#[test]
fn the_ray_through_a_projected_point_passes_through_it() {
    let sim = thesis();
    let camera = frame_camera(&sim.model, &sim.state, View::Iso);
    for p in [
        DVec3::new(0.01, -0.02, 0.005),
        DVec3::new(-0.02, 0.0, 0.03),
        DVec3::ZERO,
    ] {
        let (x, y) = camera.project(p.as_vec3(), W, H).expect("in front");
        let ray = camera.ray(x, y, W, H);
        let off = (p - ray.origin).cross(ray.direction).length();
        assert!(off < 1e-6, "ray misses {p:?} by {off:e} m");
    }
}

#[test]
fn picks_the_finger_under_its_projected_centre() {
    let sim = thesis();
    let camera = frame_camera(&sim.model, &sim.state, View::Front);
    let centre = sim.state.fingers[0].position;
    let (x, y) = camera.project(centre.as_vec3(), W, H).expect("in front");
    let ray = camera.ray(x, y, W, H);
    match pick(&sim.model, &sim.state, &ray, plate_thickness(&sim.model)) {
        Some(Picked::Finger { index: 0, point }) => {
            let radius = sim.model.fingers[0].shape.reach();
            let r = (point - centre).length();
            assert!((r - radius).abs() < 1e-6, "hit {r} m from the centre");
            assert!(
                point.y < centre.y,
                "the near side (front view looks along +y)"
            );
        }
        other => panic!("expected the finger, got {other:?}"),
    }
}

#[test]
fn picks_the_facet_under_a_point_of_the_surface() {
    let sim = thesis();
    let camera = frame_camera(&sim.model, &sim.state, View::Iso);
    // A point on the +x face, which the iso view sees.
    let p = DVec3::new(0.025, 0.0031, 0.0117);
    let (x, y) = camera.project(p.as_vec3(), W, H).expect("in front");
    let ray = camera.ray(x, y, W, H);
    match pick(&sim.model, &sim.state, &ray, plate_thickness(&sim.model)) {
        Some(Picked::Object {
            facet,
            weights,
            point,
        }) => {
            // The camera is f32: 10 um is 1/400 of a facet.
            assert!((point - p).length() < 1e-5, "hit {point:?}, not {p:?}");
            let tri = sim.model.facets[facet as usize];
            let from_weights: DVec3 = (0..3)
                .map(|a| weights[a] * sim.state.positions[tri[a] as usize])
                .sum();
            assert!((from_weights - point).length() < 1e-12);
            assert!(from_weights.x == 0.025 || (from_weights.x - 0.025).abs() < 1e-12);
            assert!(weights.iter().all(|w| (0.0..=1.0).contains(w)));
        }
        other => panic!("expected the object, got {other:?}"),
    }
}

#[test]
fn picks_nothing_off_the_object() {
    let sim = thesis();
    let camera = frame_camera(&sim.model, &sim.state, View::Iso);
    for (x, y) in [(2.0, 2.0), (W as f32 - 2.0, H as f32 - 2.0)] {
        let ray = camera.ray(x, y, W, H);
        assert_eq!(
            pick(&sim.model, &sim.state, &ray, plate_thickness(&sim.model)),
            None
        );
    }
}

#[test]
fn a_dragged_finger_follows_the_mouse_along_its_free_axes_only() {
    let sim = thesis(); // the finger is free along z only
    let camera = frame_camera(&sim.model, &sim.state, View::Front);
    let centre = sim.state.fingers[0].position;
    let (x, y) = camera.project(centre.as_vec3(), W, H).expect("in front");
    let grab = camera.ray(x, y, W, H);
    let Some(Picked::Finger { point, .. }) =
        pick(&sim.model, &sim.state, &grab, plate_thickness(&sim.model))
    else {
        panic!("the finger is under its centre");
    };
    let facing = camera.forward();
    // 40 pixels up and 30 right.
    let moved = camera.ray(x + 30.0, y - 40.0, W, H);
    let target = finger_target(&sim.model, 0, centre, point, facing, &moved).expect("target");
    assert_eq!(
        (target.x, target.y),
        (centre.x, centre.y),
        "x and y are locked"
    );
    // The mouse's own motion in the drag plane, along z.
    let a = on_plane(&grab, point, facing).unwrap();
    let b = on_plane(&moved, point, facing).unwrap();
    assert!(b.z - a.z > 1e-3);
    assert!(((target.z - centre.z) - (b.z - a.z)).abs() < 1e-9);

    // Free along x and z: both follow.
    let mut scene = Scene::thesis();
    scene.fingers[0].free_axes = [true, false, true];
    let sim = Simulation::new(&scene).expect("sim");
    let target = finger_target(&sim.model, 0, centre, point, facing, &moved).expect("target");
    assert!(((target.x - centre.x) - (b.x - a.x)).abs() < 1e-9);
    assert!(target.x - centre.x > 1e-3, "moved right");
    assert_eq!(target.y, centre.y);
}
