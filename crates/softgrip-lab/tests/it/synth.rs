//! Recordings made by softgrip itself, with physics it has no model of laid on them
//! (`synth::Distortion`, the proof's out-of-catalogue cases).

use glam::DVec3;
use softgrip_lab::recording::{Mode, Recording, Start};
use softgrip_lab::synth::{Distortion, Synthesis, synthesize};

use crate::support;

/// Up to 3 N and back to 1, noise-free: the plain recording and the distorted one.
fn pair(distortion: Distortion, name: &str) -> (Recording, Recording) {
    let scene = softgrip_lab::prove::nominal();
    let spec = Synthesis {
        mode: Mode::QuasiStatic,
        start: Start::Rest,
        samples: [1.0, 3.0, 1.0].iter().map(|l| (None, *l)).collect(),
        markers: softgrip_lab::prove::thesis_markers(),
        finger: true,
        axes: [true, false, true],
        noise: 0.0,
        seed: 1,
        description: "distortion test".into(),
        distortion: None,
    };
    let plain = synthesize(&scene, &spec, &support::temp_dir(&format!("{name}-plain"))).unwrap();
    let distorted_spec = Synthesis {
        distortion: Some(distortion),
        ..spec
    };
    let dir = support::temp_dir(&format!("{name}-distorted"));
    let distorted = synthesize(&scene, &distorted_spec, &dir).unwrap();
    (plain, distorted)
}

/// Marker `name`'s recorded position in sample `k` (x and z; y is not observed).
fn at(r: &Recording, k: usize, name: &str) -> DVec3 {
    let o = r.samples[k]
        .observations
        .iter()
        .find(|o| r.marker_name(o.marker) == name)
        .unwrap();
    DVec3::new(o.position[0].unwrap(), 0.0, o.position[2].unwrap())
}

#[test]
fn a_permanent_set_keeps_its_share_of_the_peak_on_unloading_only() {
    let share = 0.4;
    let (plain, set) = pair(Distortion::PermanentSet { share }, "set");
    for name in ["p3", "finger"] {
        for k in 0..2 {
            assert_eq!(at(&plain, k, name), at(&set, k, name), "{name} loading {k}");
        }
        let expected = at(&plain, 2, name) + share * (at(&plain, 1, name) - at(&plain, 2, name));
        assert!((at(&set, 2, name) - expected).length() < 1e-12, "{name}");
        assert!(
            (at(&set, 2, name) - at(&plain, 2, name)).length() > 1e-5,
            "{name} moved"
        );
    }
}

#[test]
fn a_slipping_marker_moves_by_its_rate_times_the_load_and_no_other_does() {
    let rate = 1e-4;
    let (plain, slip) = pair(
        Distortion::MarkerSlip {
            marker: "p3".into(),
            rate,
        },
        "slip",
    );
    for (k, load) in [1.0, 3.0, 1.0].into_iter().enumerate() {
        let d = at(&slip, k, "p3") - at(&plain, k, "p3");
        assert!(
            (d - DVec3::X * rate * load).length() < 1e-12,
            "sample {k}: {d}"
        );
        assert_eq!(at(&slip, k, "p0"), at(&plain, k, "p0"));
        assert_eq!(at(&slip, k, "finger"), at(&plain, k, "finger"));
    }
}
