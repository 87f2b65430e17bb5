//! The neo-Hookean finite-element model (`[model] elasticity =
//! "neo-hookean"`): uniaxial compression against the energy's analytic
//! solution, and the thesis scene's indentation under mesh refinement.

use softgrip_core::Simulation;

use crate::support::{WEIGHTLESS, cuboid_scene, shipped_scene, simulation, strict_rest};

const E: f64 = 60e3;
const NU: f64 = 0.45;

/// The energy's constants (see `forces::fem`).
fn constants() -> (f64, f64, f64) {
    let mu = E / (2.0 * (1.0 + NU));
    let lambda = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU)) + mu;
    (mu, lambda, 1.0 + mu / lambda)
}

/// Uniaxial stress with free sides, `F = diag(l1, l2, l2)`, `J = l1 l2^2`.
/// With the stiffening on the isochoric invariant `I = J^(-2/3) (l1^2 + 2 J
/// / l1)`, `s = max(I - 3, 0)`, `phi = 1 + beta s / 3 + gamma s^2 / 9` (beta
/// with the softening's share) and `m = mu (1 + (phi - 1) J^(-2/3))`, the
/// stress is `P = m F + (lambda (J - a) - mu (phi - 1) I / (3 J)) cof F`.
/// `P_22 = 0` reads `m J / l1 - mu (phi - 1) I / 3 + lambda (J - a) J = 0`,
/// solved for J by bisection; then `P_11 = m (l1 - J / l1^2)` and `l2 =
/// sqrt(J / l1)`. `phi` is written out here, not taken from `forces::fem`.
fn analytic(stretch: f64, (beta, gamma, q): (f64, f64, f64)) -> (f64, f64) {
    let (mu, lambda, a) = constants();
    let b = beta - 2.0 * q * gamma.sqrt();
    let l1 = stretch;
    let terms = |j: f64| {
        let scale = j.powf(-2.0 / 3.0);
        let i = scale * (l1 * l1 + 2.0 * j / l1);
        let s = (i - 3.0).max(0.0);
        let phi = 1.0 + b * s / 3.0 + gamma * s * s / 9.0;
        (mu * (1.0 + (phi - 1.0) * scale), mu * (phi - 1.0) * i / 3.0)
    };
    let lateral = |j: f64| {
        let (m, shift) = terms(j);
        m * j / l1 - shift + lambda * (j - a) * j
    };
    let (mut lo, mut hi) = (0.5, 1.5);
    assert!(lateral(lo) < 0.0 && lateral(hi) > 0.0, "no root bracketed");
    for _ in 0..200 {
        let j = 0.5 * (lo + hi);
        if lateral(j) > 0.0 {
            hi = j;
        } else {
            lo = j;
        }
    }
    let j = 0.5 * (lo + hi);
    (terms(j).0 * (l1 - j / (l1 * l1)), (j / l1).sqrt())
}

const PLAIN: (f64, f64, f64) = (0.0, 0.0, 0.0);

fn settle(sim: &mut Simulation) {
    sim.settle(strict_rest(), |_| {}).expect("rest");
}

/// A 20 mm cube on a frictionless table under a frictionless plate: the
/// middle of the cube is in uniaxial stress. Its measured stretch and the
/// nominal stress F / A0 lie on the analytic curve within 2 %, and so does
/// its lateral stretch.
#[test]
fn uniaxial_compression_follows_the_analytic_neo_hookean_stress() {
    for force in [2.0, 6.0] {
        uniaxial(force, PLAIN);
    }
}

/// The same with strain stiffening (`[model] stiffening = 10`): at 6 N
/// (near 19 % strain) the plain curve is 7 % off at the
/// cube's stretch, and the cube follows the stiffened one.
#[test]
fn uniaxial_compression_with_stiffening_follows_its_analytic_stress() {
    let terms = (10.0, 0.0, 0.0);
    let stretch = uniaxial(6.0, terms);
    let (p_plain, _) = analytic(stretch, PLAIN);
    let (p_stiff, _) = analytic(stretch, terms);
    assert!(
        (p_stiff - p_plain).abs() > 0.05 * p_plain.abs(),
        "at stretch {stretch:.4} the stiffening changes the stress by less than 5 % ({p_plain:.1} against {p_stiff:.1} Pa): the test would not tell them apart"
    );
}

/// A two-term Yeoh solid that softens first (`stiffening_cubic = 400`,
/// `softening = 0.9`: the shear modulus dips to 19 % of mu at s = 0.135):
/// at 2 N the cube is softer than the plain solid by far more than 5 %,
/// and follows its own analytic curve.
#[test]
fn uniaxial_compression_of_a_softening_solid_follows_its_analytic_stress() {
    let terms = (0.0, 400.0, 0.9);
    let stretch = uniaxial(2.0, terms);
    let (p_plain, _) = analytic(stretch, PLAIN);
    let (p_soft, _) = analytic(stretch, terms);
    assert!(
        (p_soft - p_plain).abs() > 0.05 * p_plain.abs(),
        "at stretch {stretch:.4} the softening changes the stress by less than 5 % ({p_plain:.1} against {p_soft:.1} Pa): the test would not tell them apart"
    );
}

/// Compresses the cube with `force` (N) and the stiffening terms `(beta,
/// gamma, q)`, checks the stress and lateral stretch against `analytic`,
/// returns the stretch.
fn uniaxial(force: f64, terms: (f64, f64, f64)) -> f64 {
    let (beta, gamma, q) = terms;
    {
        let more = format!(
            r#"young_modulus = {E}
poisson_ratio = {NU}

[model]
elasticity = "neo-hookean"
stiffening = {beta}
stiffening_cubic = {gamma}
softening = {q}

[support]
kind = "table"
friction = 0.0

[[finger]]
shape = "plate"
size = [0.06, 0.06]
position = [0.0, 0.0, 0.0201]
force = [0.0, 0.0, -{force}]
friction = 0.0
contact_stiffness_scale = 10
"#
        );
        let text = cuboid_scene(WEIGHTLESS, [0.02, 0.02, 0.02], 0.0025, &more);
        let mut sim = simulation(&text, "uniaxial.toml");
        settle(&mut sim);
        let m = &sim.model;
        let mean = |pick: &dyn Fn(glam::DVec3) -> bool, axis: usize| {
            let idx: Vec<usize> = (0..m.particle_count())
                .filter(|&i| pick(m.rest_positions[i]))
                .collect();
            idx.iter()
                .map(|&i| sim.state.positions[i][axis])
                .sum::<f64>()
                / idx.len() as f64
        };
        // Between the planes z = 5 mm and z = 15 mm, away from the ends.
        let near = |z: f64| move |p: glam::DVec3| (p.z - z).abs() < 1e-9;
        let stretch = (mean(&near(0.015), 2) - mean(&near(0.005), 2)) / 0.01;
        // Across the middle, between the side faces x = -10 and +10 mm.
        let side =
            |x: f64| move |p: glam::DVec3| (p.x - x).abs() < 1e-9 && (p.z - 0.01).abs() < 1e-9;
        let lateral = (mean(&side(0.01), 0) - mean(&side(-0.01), 0)) / 0.02;
        let nominal = -force / (0.02 * 0.02);
        let (p_exact, lateral_exact) = analytic(stretch, terms);
        eprintln!(
            "F {force} N, terms {terms:?}: stretch {stretch:.5}, nominal stress {nominal:.1} Pa, analytic {p_exact:.1} Pa; lateral {lateral:.5} (analytic {lateral_exact:.5})"
        );
        assert!(
            (nominal - p_exact).abs() < 0.02 * p_exact.abs(),
            "F = {force} N: stress {nominal:.1} Pa at stretch {stretch:.5}, the energy gives {p_exact:.1} Pa"
        );
        assert!(
            (lateral - lateral_exact).abs() < 0.02 * (lateral_exact - 1.0).abs().max(1e-3),
            "lateral stretch {lateral:.5}, the energy gives {lateral_exact:.5}"
        );
        stretch
    }
}

fn thesis_depth(edge: f64, elasticity: &str) -> f64 {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = edge;
    if elasticity == "neo-hookean" {
        scene.model.elasticity = softgrip_core::scene::Elasticity::NeoHookean;
    }
    let mut sim = Simulation::new(&scene).expect("sim");
    sim.set_load(0, 9.73);
    settle(&mut sim);
    sim.indentation(0)
}

/// The thesis scene (9.73 N through the light guide) indents the same as
/// the mesh is refined: successive differences shrink.
#[test]
fn the_thesis_indentation_converges_under_mesh_refinement() {
    let edges = [0.008, 0.0057, 0.004];
    let depths: Vec<f64> = edges
        .iter()
        .map(|&h| thesis_depth(h, "neo-hookean"))
        .collect();
    eprintln!(
        "neo-Hookean depths (mm) at edges {edges:?}: {:?}",
        depths.iter().map(|d| d * 1e3).collect::<Vec<_>>()
    );
    let first = (depths[1] - depths[0]).abs();
    let second = (depths[2] - depths[1]).abs();
    assert!(
        second < 0.7 * first,
        "differences {first:e} then {second:e} m: not converging"
    );
    assert!(
        second < 0.05 * depths[2],
        "the last refinement still moves the depth by {:.1} %",
        100.0 * second / depths[2]
    );
}
