//! The concealed suite of `softgrip prove`: what it hides and how it
//! hides it.

use softgrip::prove;
use softgrip::recording::MarkerRef;

#[test]
fn the_suite_hides_each_effect_at_two_strengths_with_controls() {
    let cases = prove::cases();
    let count = |effect: &str| cases.iter().filter(|c| c.effects == vec![effect]).count();
    for effect in [
        "table-friction",
        "strain-stiffening",
        "viscoelastic-creep",
        "finger-friction",
        "heterogeneous-stiffness",
        "load-loss",
    ] {
        assert_eq!(count(effect), 2, "{effect}");
    }
    assert!(cases.iter().filter(|c| c.effects.is_empty()).count() >= 3);
    assert!(cases.iter().any(|c| c.effects.len() == 2));
    // The truth is never the nominal scene: another mesh, another modulus.
    let nominal = prove::nominal();
    for c in &cases {
        assert_ne!(c.truth_scene.object.edge_length, nominal.object.edge_length);
        assert_ne!(
            c.truth_scene.object.young_modulus,
            nominal.object.young_modulus
        );
    }
}

/// A case's recording: 8 markers and the finger, x and z only, the data
/// from the truth and the nominal scene beside them.
#[test]
fn a_case_is_written_as_the_thesis_experiment_saw_it() {
    let dir = std::env::temp_dir().join(format!("softgrip-prove-{}", std::process::id()));
    let cases = prove::cases();
    let case = cases
        .iter()
        .find(|c| c.name == "load-loss-strong")
        .expect("case");
    let rec = prove::write_case(case, &dir, 1).expect("written");
    assert_eq!(rec.markers.len(), 8);
    assert_eq!(rec.samples.len(), 8);
    for s in &rec.samples {
        assert_eq!(s.observations.len(), 9, "8 markers and the finger");
        for o in &s.observations {
            assert!(o.position[0].is_some() && o.position[2].is_some());
            assert!(o.position[1].is_none(), "y is not seen");
        }
        assert!(
            s.observations
                .iter()
                .any(|o| o.marker == MarkerRef::Finger(0))
        );
    }
    // The diagnosis is given the nominal scene, not the truth.
    assert_eq!(rec.scene.object.edge_length, 0.008);
    assert_eq!(rec.scene.fingers[0].guide_friction, 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
