//! The rest test of the quasi-static mode, and the early give-up that
//! fits use (`RestTolerance::for_fits`): a load that is not calming down
//! is given up on after 5 simulated seconds instead of 20; a load that
//! comes to rest comes to rest exactly as without it.

use softgrip_core::Scene;
use softgrip_core::SimError;
use softgrip_core::Simulation;
use softgrip_core::quasi_static::{HOPELESS_SPEED_RATIO, RestTolerance};

use crate::support::shipped_scene;

fn light_guide() -> Scene {
    let mut scene = shipped_scene("thesis_cuboid_light_guide.toml");
    scene.object.edge_length = 0.006;
    scene.simulation.dt = 2e-3;
    scene
}

#[test]
fn a_load_that_comes_to_rest_is_not_given_up_on_and_one_that_never_calms_is() {
    // Loads the object comes to rest under: the same steps and state, to
    // the last bit, with and without the give-up.
    let settle = |tol: RestTolerance| {
        let mut sim = Simulation::new(&light_guide()).expect("sim");
        let k = sim.load_finger().expect("a force-controlled finger");
        let mut steps = Vec::new();
        for load in [3.0, 9.0, 1.5] {
            sim.set_load(k, load);
            steps.push(sim.settle(tol, |_| {}).expect("comes to rest").steps);
        }
        (steps, sim.state)
    };
    assert_eq!(
        settle(RestTolerance::for_fits()),
        settle(RestTolerance::default())
    );

    // The finger beside the object presses on nothing: it moves at its
    // approach speed (0.05 m/s) for ever, which never calms down.
    let mut scene = light_guide();
    scene.fingers[0].position.x = 0.1;
    let mut sim = Simulation::new(&scene).expect("sim");
    let k = sim.load_finger().expect("a force-controlled finger");
    sim.set_load(k, 3.0);
    let tol = RestTolerance::for_fits();
    match sim.settle(tol, |_| {}) {
        Err(SimError::NoRest {
            seconds, max_speed, ..
        }) => {
            let after = tol.give_up_after.expect("fits give up early");
            // Given up in the first step after 5 s whose last whole
            // second did not calm down: [4 s, 5 s) against [3 s, 4 s).
            assert!(
                seconds > after && seconds < after + 0.01,
                "given up after {seconds} s"
            );
            assert!(max_speed > HOPELESS_SPEED_RATIO * tol.speed);
        }
        other => panic!("expected no rest, got {other:?}"),
    }
}
