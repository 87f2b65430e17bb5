//! The fields the viewer colours the object by (`softgrip_core::fields`),
//! against deformations whose values are known exactly.

use glam::{DMat3, DVec3};
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::fields::{self, Field};

use crate::support::{free_block, simulation};

/// A free block with every particle moved from its rest position `x0` to `map(x0)`.
fn deformed(map: impl Fn(DVec3) -> DVec3) -> Simulation {
    deformed_as("", map)
}

/// [`deformed`], the block's `[model]` holding `model` (springs or continuum).
fn deformed_as(model: &str, map: impl Fn(DVec3) -> DVec3) -> Simulation {
    let mut sim = simulation(&free_block("", model), "block");
    for (x, x0) in sim
        .state
        .positions
        .iter_mut()
        .zip(&sim.model.rest_positions)
    {
        *x = map(*x0);
    }
    sim
}

#[test]
fn uniform_stretch_gives_its_strain_and_volume_change_everywhere() {
    let e = 0.03;
    let sim = deformed(|x0| x0 * (1.0 + e));
    let (model, state) = (&sim.model, &sim.state);
    for (i, v) in Field::SpringStrain
        .particle_values(model, state)
        .iter()
        .enumerate()
    {
        assert!((v - e).abs() < 1e-12, "particle {i}: strain {v}");
    }
    let dv = (1.0 + e).powi(3) - 1.0;
    for v in Field::VolumeChange.particle_values(model, state) {
        assert!((v - dv).abs() < 1e-12, "volume change {v}, not {dv}");
    }
    for v in fields::element_volume_change(model, state) {
        assert!((v - dv).abs() < 1e-12);
    }
    for v in fields::element_max_spring_strain(model, state) {
        assert!((v - e).abs() < 1e-12);
    }
    let displacement = Field::Displacement.particle_values(model, state);
    for (d, x0) in displacement.iter().zip(&model.rest_positions) {
        assert!((d - e * x0.length()).abs() < 1e-15);
    }
}

#[test]
fn a_rotation_strains_nothing() {
    let r = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let shift = DVec3::new(0.01, -0.02, 0.03);
    let sim = deformed(|x0| r * x0 + shift);
    let (model, state) = (&sim.model, &sim.state);
    for v in Field::SpringStrain.particle_values(model, state) {
        assert!(v.abs() < 1e-12, "strain {v}");
    }
    for v in Field::VolumeChange.particle_values(model, state) {
        assert!(v.abs() < 1e-12, "volume change {v}");
    }
    let displacement = Field::Displacement.particle_values(model, state);
    for (d, x0) in displacement.iter().zip(&model.rest_positions) {
        assert!((d - (r * *x0 + shift - *x0).length()).abs() < 1e-15);
    }
}

#[test]
fn contact_pressure_integrates_to_the_normal_force() {
    let mut sim = Simulation::new(&Scene::thesis()).expect("sim");
    sim.run_until(0.3).expect("run");
    let (model, state) = (&sim.model, &sim.state);
    let pressure = Field::ContactPressure.particle_values(model, state);
    let area = fields::boundary_area(model, state);
    let total: f64 = pressure.iter().zip(&area).map(|(p, a)| p * a).sum();
    let normal: f64 = state.contacts.iter().map(|c| c.normal_force).sum();
    assert!(normal > 1.0, "the finger presses: {normal} N");
    assert!(
        (total - normal).abs() < 1e-9 * normal,
        "pressure integrates to {total} N, contacts carry {normal} N"
    );
    // Only particles of touched facets carry pressure, and none is negative.
    assert!(pressure.iter().all(|p| *p >= 0.0));
    let touched = pressure.iter().filter(|p| **p > 0.0).count();
    assert!(touched > 0 && touched < model.particle_count() / 10);
}

/// A block (springs or continuum, `model`) with every particle moved by `f`.
fn homogeneous(model: &str, f: DMat3) -> Simulation {
    deformed_as(model, |x0| f * x0)
}

#[test]
fn a_uniaxial_stretch_and_a_rotation_give_the_green_strain_of_the_stretch() {
    let stretch = 1.4;
    let r = DMat3::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.9);
    let f = r * DMat3::from_diagonal(DVec3::new(1.0, stretch, 0.9));
    let sim = homogeneous("", f);
    let expected = 0.5 * (stretch * stretch - 1.0);
    for (e, v) in fields::element_green_strain(&sim.model, &sim.state)
        .iter()
        .enumerate()
    {
        assert!(
            (v - expected).abs() < 1e-12,
            "element {e}: {v}, not {expected}"
        );
    }
    // Compressed in every direction: the largest principal strain is the least compression.
    let sim = homogeneous("", DMat3::from_diagonal(DVec3::new(0.8, 0.7, 0.9)));
    for v in fields::element_green_strain(&sim.model, &sim.state) {
        assert!((v - 0.5 * (0.81 - 1.0)).abs() < 1e-12, "{v}");
    }
}

/// Simple shear `x += gamma y` of a neo-Hookean solid: `sigma = mu B + p I` (J = 1), so its
/// von Mises stress is `mu gamma sqrt(3 + gamma^2)` whatever the pressure: the springs' stand-in
/// continuum and the elements alike, at the scene's E and nu.
#[test]
fn simple_shear_gives_the_neo_hookean_von_mises_stress() {
    let gamma = 0.3;
    let f = DMat3::from_cols(DVec3::X, DVec3::new(gamma, 1.0, 0.0), DVec3::Z);
    for model in ["", "elasticity = \"neo-hookean\""] {
        let sim = homogeneous(model, f);
        let (young, nu) = (sim.model.young_modulus, sim.model.poisson_ratio);
        assert!(nu > 0.0 && young > 0.0);
        let mu = young / (2.0 * (1.0 + nu));
        let expected = mu * gamma * (3.0 + gamma * gamma).sqrt();
        for (e, v) in fields::element_von_mises(&sim.model, &sim.state)
            .iter()
            .enumerate()
        {
            assert!(
                (v / expected - 1.0).abs() < 1e-10,
                "{model:?} element {e}: {v} Pa, not {expected}"
            );
        }
    }
    // A uniform dilation has no deviator.
    let sim = homogeneous("", DMat3::from_diagonal(DVec3::splat(1.05)));
    for v in fields::element_von_mises(&sim.model, &sim.state) {
        assert!(v.abs() < 1e-9 * sim.model.young_modulus, "{v}");
    }
}
