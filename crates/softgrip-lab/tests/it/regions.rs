//! Heterogeneous material (`[[region]]`): boxes whose elements take their
//! own Young's modulus and density.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::quasi_static::RestTolerance;

const E_SOFT: f64 = 40e3;
const E_STIFF: f64 = 120e3;

/// A 60 x 30 x 20 mm block, its right half (x > 0) three times stiffer and
/// twice as dense, pressed by a 10 x 10 mm punch at the middle of one half.
fn block(punch_x: f64) -> Scene {
    let text = format!(
        r#"
[object]
shape = "cuboid"
size = [0.06, 0.03, 0.02]
edge_length = 0.004
density = 1000.0
young_modulus = {E_SOFT}
poisson_ratio = 0.45

[model]
bulk_modulus = 1.33e5           # E / (3 (1 - 2 nu)) of the soft half; scaled with E per region

[[region]]
min = [0.0, -0.02, -0.01]
max = [0.04, 0.02, 0.03]
young_modulus = {E_STIFF}
density = 2000.0

[[finger]]
shape = "box"
size = [0.01, 0.01, 0.01]
position = [{punch_x}, 0.0, 0.0251]
free_axes = "z"
force = [0.0, 0.0, -0.3]
friction = 0.0
"#
    );
    Scene::from_toml_str(&text, "two_regions.toml").expect("scene")
}

/// Mean downward displacement of the top particles under the punch (m).
fn sink_under_punch(punch_x: f64) -> f64 {
    let mut sim = Simulation::new(&block(punch_x)).expect("sim");
    sim.settle(
        RestTolerance {
            speed: 1e-6,
            consecutive_steps: 20,
            max_seconds: 10.0,
            give_up_after: None,
        },
        |_| {},
    )
    .expect("rest");
    let under: Vec<usize> = (0..sim.model.particle_count())
        .filter(|&i| {
            let p = sim.model.rest_positions[i];
            p.z > 0.0199 && (p.x - punch_x).abs() <= 0.005 && p.y.abs() <= 0.005
        })
        .collect();
    assert!(
        under.len() >= 4,
        "{} particles under the punch",
        under.len()
    );
    under
        .iter()
        .map(|&i| sim.model.rest_positions[i].z - sim.state.positions[i].z)
        .sum::<f64>()
        / under.len() as f64
}

/// Linear elasticity: under the same load the same patch sinks in inverse
/// proportion to the modulus, so the soft half sinks E_stiff / E_soft = 3
/// times as far (less, as each half leans on the other).
#[test]
fn the_stiffer_half_deforms_less_by_the_modulus_ratio() {
    let soft = sink_under_punch(-0.015);
    let stiff = sink_under_punch(0.015);
    let ratio = soft / stiff;
    let linear = E_STIFF / E_SOFT;
    eprintln!(
        "soft half {:.4} mm, stiff half {:.4} mm: ratio {ratio:.3}, linear estimate {linear}",
        soft * 1e3,
        stiff * 1e3
    );
    assert!(
        (ratio - linear).abs() < 0.2 * linear,
        "ratio {ratio:.3} against the linear estimate {linear}"
    );
}

#[test]
fn regions_set_the_mass_and_the_springs() {
    let sim = Simulation::new(&block(-0.015)).expect("sim");
    let m = &sim.model;
    // Half of 60 x 30 x 20 mm at 1000 and half at 2000 kg/m^3.
    let expected = 0.03 * 0.03 * 0.02 * (1000.0 + 2000.0);
    assert!(
        (m.total_mass() - expected).abs() < 1e-12,
        "{} kg against {expected} kg",
        m.total_mass()
    );
    // A spring wholly inside the right half is three times the mirror
    // spring in the left half (the mesh is symmetric about x = 0).
    let key = |p: DVec3| {
        [
            (p.x * 1e6).round() as i64,
            (p.y * 1e6).round() as i64,
            (p.z * 1e6).round() as i64,
        ]
    };
    let find = |a: DVec3, b: DVec3| {
        m.springs.iter().find(|s| {
            let (pi, pj) = (
                m.rest_positions[s.i as usize],
                m.rest_positions[s.j as usize],
            );
            (key(pi) == key(a) && key(pj) == key(b)) || (key(pi) == key(b) && key(pj) == key(a))
        })
    };
    let mut compared = 0;
    for s in &m.springs {
        let (a, b) = (
            m.rest_positions[s.i as usize],
            m.rest_positions[s.j as usize],
        );
        if a.x > 0.0041 && b.x > 0.0041 {
            let mirror = |p: DVec3| DVec3::new(-p.x, p.y, p.z);
            if let Some(t) = find(mirror(a), mirror(b)) {
                assert!(
                    (s.stiffness - 3.0 * t.stiffness).abs() < 1e-9 * s.stiffness,
                    "{} against {}",
                    s.stiffness,
                    t.stiffness
                );
                compared += 1;
            }
        }
        if compared > 20 {
            break;
        }
    }
    assert!(compared > 20);
}

#[test]
fn a_region_outside_the_object_is_an_error_naming_it() {
    let text = format!(
        "{}\n[[region]]\nmin = [1.0, 1.0, 1.0]\nmax = [2.0, 2.0, 2.0]\n",
        "[object]\nshape = \"cuboid\"\nsize = [0.03, 0.03, 0.02]"
    );
    let mut scene = Scene::from_toml_str(&text, "far.toml").expect("scene");
    scene.source = Some("far.toml".into());
    let e = Simulation::new(&scene)
        .expect_err("empty region")
        .to_string();
    assert!(e.contains("region") && e.contains("far.toml"), "{e}");
}

#[test]
fn region_modulus_is_a_parameter_for_sweeps_and_fits() {
    let scene = block(-0.015);
    assert_eq!(
        softgrip_lab::params::get(&scene, "region_young_modulus"),
        Ok(Some(E_STIFF))
    );
    let set = softgrip_lab::params::set(&scene, "region_young_modulus", 2e5).expect("set");
    assert_eq!(set.regions[0].young_modulus, 2e5);
    let e = softgrip_lab::params::set(&scene, "region_young_modulus", -1.0)
        .expect_err("negative")
        .to_string();
    assert!(e.contains("region_young_modulus"), "{e}");
}

/// The viewer's "Young's modulus" colouring shows the regions.
#[test]
fn the_modulus_field_shows_the_regions() {
    let sim = Simulation::new(&block(-0.015)).expect("sim");
    let values = softgrip_core::fields::Field::YoungModulus.particle_values(&sim.model, &sim.state);
    for (p, e) in sim.model.rest_positions.iter().zip(&values) {
        if p.x < -0.0041 {
            assert!((e - E_SOFT).abs() < 1e-6, "{p:?}: {e}");
        } else if p.x > 0.0041 {
            assert!((e - E_STIFF).abs() < 1e-6, "{p:?}: {e}");
        } else if p.x.abs() < 1e-9 {
            assert!(*e > E_SOFT && *e < E_STIFF, "on the interface: {e}");
        }
    }
}
