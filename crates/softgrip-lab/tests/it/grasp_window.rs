//! The grasp window (`softgrip_lab::grasp::window`) against force balance: a stiff cube between
//! two flat pads is held by friction alone, so the least squeeze that holds it through a lift
//! of acceleration `a` is `m (g + a) / (2 mu)`.

use softgrip_core::Scene;
use softgrip_core::equilibrium::StaticOptions;
use softgrip_lab::grasp::window::{Damage, Gripper, LiftProfile, Measure, WindowOptions};

/// A 20 mm cube (8 g) between two 10 x 30 x 30 mm box pads squeezing along x, each finger's
/// friction `mu`; its modulus, 100 kPa, is 100 times the pads' largest mean pressure in these
/// tests (0.39 N over 4 cm^2): stiff, as the force balance assumes.
fn pads(mu: f64) -> Scene {
    let finger = |x: f64, sign: f64| {
        format!(
            "[[finger]]\nshape = \"box\"\nsize = [0.01, 0.03, 0.03]\nposition = [{x}, 0.0, 0.01]\nfree_axes = \"x\"\ncontrol = \"force\"\nforce = [{sign}, 0.0, 0.0]\nfriction = {mu}\n"
        )
    };
    let text = format!(
        "[simulation]\ndt = 1e-3\ngravity = [0.0, 0.0, -9.81]\n\n[object]\nshape = \"cuboid\"\nsize = [0.02, 0.02, 0.02]\nedge_length = 0.005\ndensity = 1000.0\nyoung_modulus = 1e5\npoisson_ratio = 0.45\n\n[model]\nbulk_modulus = 3e5\n\n[support]\nkind = \"none\"\n\n{}\n{}",
        finger(-0.0152, 1.0),
        finger(0.0152, -1.0)
    );
    Scene::from_toml_str(&text, "pads.toml").expect("pads scene")
}

#[test]
fn the_least_squeeze_between_flat_pads_is_the_force_balance_within_two_percent() {
    let g = 9.81;
    for (mu, a) in [(0.3, 0.0), (0.5, g), (0.8, 2.0 * g)] {
        let profile = LiftProfile {
            acceleration: a,
            shake: 0.0,
            slip_tolerance: 1e-3,
        };
        let gripper = Gripper::new(&pads(mu), profile).expect("gripper");
        let options = WindowOptions {
            profile,
            damage: Damage {
                measure: Measure::Strain,
                limit: 0.5,
            },
            tolerance: 0.005,
            statics: StaticOptions {
                max_iterations: 2000,
                ..StaticOptions::default()
            },
        };
        let window = gripper.window(options, |_| {}).expect("window");
        let balance = gripper.mass() * (g + a) / (2.0 * mu);
        let least = window.least_squeeze();
        eprintln!(
            "mu {mu}, a {a}: least squeeze {least:.5} N (dropped at {:.5}), m (g + a) / (2 mu) = {balance:.5} N",
            window.least.dropped
        );
        assert!(
            (least / balance - 1.0).abs() < 0.02,
            "mu {mu}, a {a}: {least} N against {balance} N"
        );
        assert!(window.least.dropped < balance * 1.02 && window.least.dropped > 0.0);
    }
}

/// The shipped two-finger scene (`assets/scenes/grasp_lift.toml`): its window by statics, and
/// each bound lifted dynamically: held at the least squeeze, and at the most the dynamic peak of
/// the contact pressure within 5 % of the limit the statics stopped at (the lift adds only
/// 0.1 m/s^2).
#[test]
fn the_shipped_cube_window_holds_dynamically_at_both_bounds() {
    let scene = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/scenes/grasp_lift.toml"
    )))
    .expect("grasp scene");
    let asked = softgrip_lab::grasp::plan::Asked {
        damage: Some(Measure::Pressure),
        limit: Some(5e3),
        ..Default::default()
    };
    let plan = softgrip_lab::grasp::plan::plan(&scene, asked).expect("plan");
    assert!(
        (plan.options.profile.acceleration - 0.1).abs() < 1e-12,
        "the scene's lift: 0.02 m/s over 0.2 s"
    );
    let gripper = Gripper::new(&scene, plan.options.profile).expect("gripper");
    let window = gripper.window(plan.options, |_| {}).expect("window");
    let least = window.least_squeeze();
    let most = window.most_squeeze().expect("the limit is reached");
    let balance = gripper.mass() * (9.81 + 0.1) / (2.0 * 0.5);
    eprintln!("window {least:.4} .. {most:.4} N, force balance {balance:.4} N");
    assert!(
        (least / balance - 1.0).abs() < 0.02,
        "{least} against {balance}"
    );
    assert!(window.exists() && most > 5.0 * least);
    let at_least = gripper
        .confirm(&scene, least, Measure::Pressure, 1.0, |_| {})
        .expect("lift at the least squeeze");
    assert!(at_least.run.held, "{:?}", at_least.run.hold_slip);
    let at_most = gripper
        .confirm(&scene, most, Measure::Pressure, 1.0, |_| {})
        .expect("lift at the most");
    assert!(at_most.run.held);
    let ratio = at_most.peak.value / 5e3;
    eprintln!(
        "dynamic peak pressure at the most squeeze: {:.1} Pa ({ratio:.3} of the limit)",
        at_most.peak.value
    );
    assert!((ratio - 1.0).abs() < 0.05, "{ratio}");
}

/// A block `2 half` wide and `depth` deep, edge `edge`, its bottom fixed, a sphere of radius
/// `radius` pressing its top centre with `force` N.
fn sphere_on_block(edge: f64, force: f64, radius: f64) -> Scene {
    let text = format!(
        "[simulation]\ndt = 1e-3\ngravity = [0.0, 0.0, 0.0]\n\n[object]\nshape = \"cuboid\"\nsize = [0.03, 0.03, 0.015]\nedge_length = {edge}\ndensity = 1000.0\nyoung_modulus = 1e5\npoisson_ratio = 0.45\n\n[model]\nelasticity = \"neo-hookean\"\n\n[support]\nkind = \"fixed-bottom\"\n\n[[finger]]\nshape = \"sphere\"\nradius = {radius}\nposition = [0.0, 0.0, {}]\nfree_axes = \"z\"\ncontrol = \"force\"\nforce = [0.0, 0.0, {}]\nfriction = 0.0\n",
        0.015 + radius + 1e-4,
        -force
    );
    Scene::from_toml_str(&text, "sphere_on_block.toml").expect("sphere scene")
}

/// Against contact mechanics: a rigid sphere (R 20 mm) pressed with 1 N into a 30 x 30 x 15 mm
/// neo-Hookean block (E 100 kPa, nu 0.45) whose bottom is fixed. Hertz's peak pressure
/// `(6 F E*^2 / (pi^3 R^2))^(1/3)`, `E* = E / (1 - nu^2)`, is 19.67 kPa over a contact radius
/// of 4.9 mm. The damage measure `pressure` (`fields::contact_pressure`, a node's share of the
/// contact force over its share of the surface) peaks within 10 % of it on the 1.2 mm mesh
/// (52,728 tetrahedra), and its error shrinks as the mesh is refined from 2 mm: -10.0, -5.1,
/// +1.3 % (at 1 mm +3.0 %: a block three contact radii deep is stiffer than Hertz's half-space).
#[test]
fn sphere_pressure_peak_converges_to_hertz_within_ten_percent() {
    let (force, radius) = (1.0, 0.02);
    let e_star = 1e5 / (1.0 - 0.45 * 0.45);
    let hertz =
        (6.0 * force * e_star * e_star / (std::f64::consts::PI.powi(3) * radius * radius)).cbrt();
    let mut errors = Vec::new();
    for edge in [0.002, 0.0015, 0.0012] {
        let mut sim = softgrip_core::Simulation::new(&sphere_on_block(edge, force, radius))
            .expect("sphere on block");
        sim.set_threads(1);
        sim.equilibrium(StaticOptions::default())
            .expect("equilibrium");
        let peak = softgrip_core::fields::contact_pressure(&sim.model, &sim.state)
            .into_iter()
            .fold(0.0, f64::max);
        let error = peak / hertz - 1.0;
        eprintln!(
            "edge {edge} m, {} tetrahedra: peak {peak:.1} Pa against Hertz {hertz:.1} Pa ({:+.1} %)",
            sim.model.tets.len(),
            100.0 * error
        );
        errors.push(error.abs());
    }
    assert!(errors[2] < 0.10, "{errors:?}");
    assert!(
        errors[2] < errors[1] && errors[1] < errors[0],
        "the error shrinks as the mesh is refined: {errors:?}"
    );
}
