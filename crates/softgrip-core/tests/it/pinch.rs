//! Acceptance 7 (pinch): two velocity-controlled fingers squeeze the cuboid
//! (thesis Fig. 5.10), then hold; at steady state their contact forces are
//! equal and opposite within 5 %.

use softgrip_core::Simulation;

use crate::support::shipped_scene;

#[test]
fn pinch_forces_balance_at_steady_state() {
    let scene = shipped_scene("pinch.toml");
    let mut sim = Simulation::new(&scene).expect("sim");
    // 2 s of squeezing (4 mm each at 2 mm/s), then hold.
    sim.run_until(2.6).expect("run");
    let (a, b) = (sim.state.fingers[0], sim.state.fingers[1]);
    assert!((a.travelled - 0.004).abs() < 1e-5 && (b.travelled - 0.004).abs() < 1e-5);
    // Each finger is pushed back by the object ...
    assert!(
        a.contact_force.x < -0.5 && b.contact_force.x > 0.5,
        "{:?} {:?}",
        a.contact_force,
        b.contact_force
    );
    println!(
        "finger forces {:.4} N and {:.4} N",
        a.contact_force.x, b.contact_force.x
    );
    // ... and the two forces balance.
    let imbalance = (a.contact_force.x + b.contact_force.x).abs() / a.contact_force.x.abs();
    assert!(
        imbalance < 0.05,
        "forces {} and {} N",
        a.contact_force.x,
        b.contact_force.x
    );
}
