//! Issue 5: markers follow the material point of the nearest boundary
//! facet, and the error measures are the spec's (thesis eq. 45-46).

use glam::{DMat3, DVec3};
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_lab::compare::{Residual, attach, errors, marker_position, position};
use softgrip_lab::recording::MarkerRef;

fn block() -> Simulation {
    let text = r#"
[object]
shape = "cuboid"
size = [0.05, 0.05, 0.02]
edge_length = 0.005
[support]
kind = "none"
"#;
    Simulation::new(&Scene::from_toml_str(text, "block").expect("scene")).expect("sim")
}

#[test]
fn markers_on_the_surface_attach_where_they_are_and_off_it_say_how_far() {
    let sim = block();
    let on = [
        DVec3::new(0.0123, -0.0071, 0.02), // top face
        DVec3::new(-0.025, 0.01, 0.0087),  // -x side
        DVec3::new(0.025, 0.025, 0.02),    // a corner
    ];
    for (a, r) in attach(&sim.model, &on).iter().zip(on) {
        assert!(a.distance < 1e-15, "{r}: {}", a.distance);
        assert!((position(&sim.model, &sim.state, a) - r).length() < 1e-15);
        assert!(a.weights.iter().all(|w| (-1e-12..=1.0 + 1e-12).contains(w)));
    }
    // 2 mm above the top face: attached to the point below, 2 mm away.
    let off = [DVec3::new(0.01, 0.004, 0.022)];
    let a = attach(&sim.model, &off)[0];
    assert!((a.distance - 0.002).abs() < 1e-15);
    let p = position(&sim.model, &sim.state, &a);
    assert!((p - DVec3::new(0.01, 0.004, 0.02)).length() < 1e-15);
}

#[test]
fn markers_follow_the_material_under_any_affine_motion() {
    let mut sim = block();
    let refs = [
        DVec3::new(0.0123, -0.0071, 0.02),
        DVec3::new(-0.025, 0.01, 0.0087),
        DVec3::new(0.003, 0.025, 0.011),
    ];
    let attached = attach(&sim.model, &refs);
    // A stretch, a shear and a turn, then a shift: barycentric weights are
    // affine-invariant, so each marker lands on the image of its reference.
    let m = DMat3::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.4)
        * DMat3::from_cols(
            DVec3::new(1.1, 0.0, 0.0),
            DVec3::new(0.2, 0.9, 0.0),
            DVec3::new(0.0, 0.1, 1.05),
        );
    let b = DVec3::new(0.01, -0.02, 0.005);
    for (x, x0) in sim
        .state
        .positions
        .iter_mut()
        .zip(&sim.model.rest_positions)
    {
        *x = m * *x0 + b;
    }
    for (k, r) in refs.iter().enumerate() {
        let p = marker_position(&sim.model, &sim.state, &attached, MarkerRef::Object(k)).unwrap();
        assert!((p - (m * *r + b)).length() < 1e-15, "marker {k}");
    }
    // A finger marker is the finger's centre.
    assert_eq!(
        marker_position(&sim.model, &sim.state, &attached, MarkerRef::Finger(0)),
        None
    );
}

fn residual(marker: MarkerRef, simulated: [f64; 3], recorded: [Option<f64>; 3]) -> Residual {
    Residual {
        sample: 0,
        marker,
        simulated: DVec3::from_array(simulated),
        recorded,
    }
}

#[test]
fn nrmse_is_the_rms_distance_over_observed_axes_divided_by_the_extent() {
    let o = MarkerRef::Object(0);
    let f = MarkerRef::Finger(0);
    let rs = [
        // 3 mm off in x; y not observed (its 1 m error must not count).
        residual(o, [0.003, 1.0, 0.0], [Some(0.0), None, Some(0.0)]),
        // 4 mm off in z.
        residual(
            MarkerRef::Object(1),
            [0.0, 0.0, 0.014],
            [Some(0.0), Some(0.0), Some(0.010)],
        ),
        // The finger, 12 mm off: excluded from nrmse, in nrmse_all.
        residual(f, [0.0, 0.0, 0.012], [None, None, Some(0.0)]),
    ];
    let e = errors(&rs, 0.05);
    let rmse = ((0.003f64.powi(2) + 0.004f64.powi(2)) / 2.0).sqrt();
    assert!((e.rmse_m - rmse).abs() < 1e-15);
    assert!((e.nrmse - rmse / 0.05).abs() < 1e-15);
    assert_eq!(e.count, 2);
    let all = ((0.003f64.powi(2) + 0.004f64.powi(2) + 0.012f64.powi(2)) / 3.0).sqrt();
    assert!((e.rmse_all_m - all).abs() < 1e-15);
    assert!((e.nrmse_all - all / 0.05).abs() < 1e-15);

    // No object markers (a plate compression test): the fingers count.
    let only = [residual(f, [0.0, 0.0, 0.012], [None, None, Some(0.0)])];
    let e = errors(&only, 0.03);
    assert!((e.rmse_m - 0.012).abs() < 1e-15);
    assert!((e.nrmse - 0.4).abs() < 1e-12);
    assert_eq!(e.count, 1);
}

#[test]
fn per_marker_errors_are_rms_over_each_observed_axis() {
    let (a, b) = (MarkerRef::Object(0), MarkerRef::Finger(0));
    let rs = [
        residual(a, [1.0, 0.0, 0.0], [Some(0.0), None, Some(0.0)]),
        residual(b, [0.0, 0.0, 2.0], [None, None, Some(0.0)]),
        residual(a, [3.0, 5.0, 4.0], [Some(0.0), None, Some(4.0)]),
    ];
    let e = softgrip_lab::compare::per_marker(&rs);
    assert_eq!(e.len(), 2);
    assert_eq!(e[0].marker, a);
    // x: sqrt((1 + 9) / 2); y never observed; z: 0.
    assert!((e[0].axes[0].unwrap() - 5f64.sqrt()).abs() < 1e-15);
    assert_eq!(e[0].axes[1], None);
    assert_eq!(e[0].axes[2], Some(0.0));
    assert!((e[0].distance - 5f64.sqrt()).abs() < 1e-15);
    assert_eq!(
        (e[1].marker, e[1].axes, e[1].distance),
        (b, [None, None, Some(2.0)], 2.0)
    );
}
