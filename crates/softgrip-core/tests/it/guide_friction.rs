//! Load-path friction (`[[finger]] guide_friction`): Coulomb friction in the
//! finger's guide makes loading and unloading take different paths; at the
//! same depth the loads differ by twice the friction force.

use softgrip_core::Simulation;

use crate::support::{rest_within, shipped_scene};

pub fn light_guide(guide_friction: f64) -> Simulation {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = 0.006;
    // Nothing else path-dependent: no contact friction, no spring limits.
    scene.fingers[0].friction = 0.0;
    scene.fingers[0].guide_friction = guide_friction;
    scene.model.tau_s = None;
    scene.model.tau_c = None;
    Simulation::new(&scene).expect("sim")
}

/// Loads up, then down; the depth at rest after each.
fn loop_path(sim: &mut Simulation, up: &[f64], down: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let tol = rest_within(1e-5, 10.0);
    let mut at = |load: f64| {
        sim.set_load(0, load);
        sim.settle(tol, |_| {}).expect("rest");
        sim.indentation(0)
    };
    let a = up.iter().map(|&l| at(l)).collect();
    let b = down.iter().map(|&l| at(l)).collect();
    (a, b)
}

/// The loading curve's load at depth `d` (linear interpolation).
pub fn load_at(depths: &[f64], loads: &[f64], d: f64) -> f64 {
    let i = depths
        .windows(2)
        .position(|w| w[0] <= d && d <= w[1])
        .expect("inside the loading curve");
    let t = (d - depths[i]) / (depths[i + 1] - depths[i]);
    loads[i] + t * (loads[i + 1] - loads[i])
}

fn widths(guide_friction: f64) -> Vec<f64> {
    let up: Vec<f64> = (1..=20).map(|k| 0.5 * k as f64).collect();
    let down = [8.0, 6.0, 4.0, 3.0];
    let (d_up, d_down) = loop_path(&mut light_guide(guide_friction), &up, &down);
    down.iter()
        .zip(&d_down)
        .map(|(&l, &d)| load_at(&d_up, &up, d) - l)
        .collect()
}

#[test]
#[ignore = "slow: a load cycle"]
fn the_hysteresis_loop_is_twice_the_guide_friction_wide() {
    let friction = 0.5;
    let w = widths(friction);
    eprintln!("loop widths (N) at guide friction {friction} N: {w:?}");
    for width in &w {
        assert!(
            (width - 2.0 * friction).abs() < 0.05 * 2.0 * friction,
            "loop width {width:.4} N, twice the friction is {} N",
            2.0 * friction
        );
    }
    // Without it, loading and unloading take the same path.
    let none = widths(0.0);
    eprintln!("loop widths (N) without: {none:?}");
    assert!(none.iter().all(|w| w.abs() < 0.02), "{none:?}");
}
