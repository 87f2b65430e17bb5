//! The table (`[support] kind = "table"`): a block rests on it, sticks on an
//! incline flatter than its friction angle, slides down a steeper one with
//! the textbook acceleration `g (sin - mu cos)`, and is lifted off freely.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::state::TableMode;

const G: f64 = 9.81;

/// A 30 x 30 x 12 mm block on the table under gravity tilted by `angle`
/// about y (the same as the table tilted: the block slides along +x).
fn block_on_table(friction: f64, angle: f64) -> Simulation {
    let text = format!(
        r#"
[simulation]
dt = 1e-3
gravity = [{gx}, 0.0, {gz}]

[object]
shape = "cuboid"
size = [0.03, 0.03, 0.012]
edge_length = 0.006
density = 1070.0
young_modulus = 200e3
poisson_ratio = 0.45

[model]
bulk_modulus = 1e6

[support]
kind = "table"
friction = {friction}
"#,
        gx = G * angle.sin(),
        gz = -G * angle.cos(),
    );
    let scene = Scene::from_toml_str(&text, "block.toml").expect("scene");
    Simulation::new(&scene).expect("block")
}

fn centre_of_mass(sim: &Simulation) -> DVec3 {
    sim.state.centre_of_mass(&sim.model)
}

#[test]
fn a_block_rests_on_the_table_carrying_its_weight() {
    let mut sim = block_on_table(0.5, 0.0);
    sim.run_until(0.5).expect("run");
    let weight = sim.model.total_mass() * G;
    let reaction = sim.support_reaction();
    assert!(
        (reaction.z - weight).abs() < 1e-3 * weight,
        "the table carries {:.6} N of a {weight:.6} N weight",
        reaction.z
    );
    assert!(reaction.truncate().length() < 1e-6 * weight);
    let lowest = sim
        .state
        .positions
        .iter()
        .map(|x| x.z)
        .fold(f64::INFINITY, f64::min);
    assert!(
        lowest < 0.0 && lowest > -1e-5,
        "sinks a little (penalty), not far: lowest z {lowest:e} m"
    );
    assert!(sim.state.stats.max_speed < 1e-4, "at rest");
    assert!(
        sim.state.table.iter().any(|c| c.mode == TableMode::Stick),
        "the bottom sticks"
    );
}

/// Displacement along the slope (m) after `seconds` at friction 0.5 on a
/// slope with `tan(angle) = ratio * 0.5`.
fn slide(ratio: f64, seconds: f64) -> (f64, Simulation) {
    let mu = 0.5;
    let angle = (ratio * mu).atan();
    let mut sim = block_on_table(mu, angle);
    let start = centre_of_mass(&sim);
    sim.run_until(seconds).expect("run");
    ((centre_of_mass(&sim) - start).x, sim)
}

#[test]
fn a_block_sticks_below_the_friction_angle_and_slides_above_it() {
    let (early, _) = slide(0.97, 0.25);
    let (below, sim) = slide(0.97, 0.5);
    // Only the block's own shear, the stick springs' give and the first
    // steps' settling.
    assert!(
        below.abs() < 5e-5,
        "tan(angle) = 0.97 mu: moved {below:e} m in 0.5 s"
    );
    assert!(
        (below - early).abs() < 1e-8,
        "and stopped: {:e} m from 0.25 s to 0.5 s",
        below - early
    );
    assert!(sim.state.stats.max_speed < 1e-6, "at rest");
    // Static friction carries the weight's share along the slope.
    let along = sim.model.total_mass() * sim.model.gravity.x;
    let friction = sim.support_reaction().x;
    assert!(
        (friction + along).abs() < 1e-3 * along,
        "friction {friction:.6} N against {along:.6} N down the slope"
    );
    let sticking = sim
        .state
        .table
        .iter()
        .filter(|c| c.mode == TableMode::Stick)
        .count();
    let touching = sim
        .state
        .table
        .iter()
        .filter(|c| c.mode != TableMode::Free)
        .count();
    assert!(
        sticking * 10 >= touching * 8,
        "{sticking} of {touching} contacts stick"
    );
    let (above, sim) = slide(1.03, 0.5);
    // g (sin - mu cos) = 0.13 m/s^2 at tan = 1.03 mu: ~1.6 cm in 0.5 s.
    assert!(
        above > 0.01,
        "tan(angle) = 1.03 mu: moved only {above:e} m in 0.5 s"
    );
    assert!(
        sim.state.table.iter().all(|c| c.mode != TableMode::Stick),
        "nothing sticks while it slides"
    );
}

#[test]
fn a_sliding_block_accelerates_at_g_sin_minus_mu_cos() {
    // 3 % past the friction angle, where 1 % too much friction would be
    // 30 % too little acceleration; well past it; no friction.
    let near = (1.03_f64 * 0.5).atan().to_degrees();
    for (mu, angle_deg) in [(0.5_f64, near), (0.5, 35.0_f64), (0.3, 25.0), (0.0, 10.0)] {
        let angle = angle_deg.to_radians();
        let mut sim = block_on_table(mu, angle);
        let expected = G * (angle.sin() - mu * angle.cos());
        // Positions along the slope at three times, 0.1 s apart, after
        // the start transient: a = (x0 - 2 x1 + x2) / h^2.
        let mut x = [0.0; 3];
        for (i, t) in [0.2, 0.3, 0.4].into_iter().enumerate() {
            sim.run_until(t).expect("run");
            x[i] = centre_of_mass(&sim).x;
        }
        let a = (x[0] - 2.0 * x[1] + x[2]) / 0.01;
        eprintln!(
            "mu {mu}, {angle_deg:.2} deg: a = {a:.4} m/s^2, g (sin - mu cos) = {expected:.4}"
        );
        assert!(
            (a - expected).abs() < 0.01 * expected,
            "mu {mu}, {angle_deg} deg: a = {a:.4} m/s^2, g (sin - mu cos) = {expected:.4}"
        );
    }
}

#[test]
fn the_table_never_pulls_a_block_lifted_off() {
    let mut sim = block_on_table(0.8, 0.0);
    sim.run_until(0.2).expect("settle");
    // Gravity turned upside down: the block falls upwards, freely.
    let mut model = (*sim.model).clone();
    let up = DVec3::new(0.0, 0.0, G);
    for (f, m) in model.constant_force.iter_mut().zip(&model.mass) {
        *f = *m * up;
    }
    model.gravity = up;
    sim.model = std::sync::Arc::new(model);
    let z0 = centre_of_mass(&sim).z;
    sim.run_until(0.3).expect("run");
    let rise = centre_of_mass(&sim).z - z0;
    let free = 0.5 * G * 0.1 * 0.1;
    assert!(
        (rise - free).abs() < 0.03 * free,
        "rose {rise:e} m in 0.1 s; free fall gives {free:e} m"
    );
    assert!(sim.state.table.iter().all(|c| c.mode == TableMode::Free));
    assert_eq!(sim.support_reaction(), DVec3::ZERO);
}

#[test]
fn a_table_block_runs_the_same_twice() {
    let run = || {
        let (_, sim) = slide(1.2, 0.2);
        sim.state.positions
    };
    assert_eq!(run(), run());
}

#[test]
fn table_friction_is_a_parameter_for_sweeps_and_fits() {
    let sim_scene = |kind: &str| {
        Scene::from_toml_str(
            &format!(
                "[object]\nshape = \"cuboid\"\nsize = [0.03, 0.03, 0.012]\n[support]\nkind = \"{kind}\"\nfriction = 0.2\n"
            ),
            "s.toml",
        )
        .expect("scene")
    };
    let table = sim_scene("table");
    assert_eq!(
        softgrip_lab::params::get(&table, "table_friction"),
        Ok(Some(0.2))
    );
    let set = softgrip_lab::params::set(&table, "table_friction", 0.45).expect("set");
    assert_eq!(set.support.friction, 0.45);
    let negative = softgrip_lab::params::set(&table, "table_friction", -0.1)
        .expect_err("negative")
        .to_string();
    assert!(
        negative.contains("table_friction") && negative.contains(">= 0"),
        "{negative}"
    );
    let pinned = softgrip_lab::params::set(&sim_scene("fixed-bottom"), "table_friction", 0.3)
        .expect_err("no table")
        .to_string();
    assert!(pinned.contains("needs a table"), "{pinned}");
}
