//! Dragging in the viewer, checked on the core: a held finger is
//! position-driven along its free axes only and returns to its control mode
//! when let go; the mouse spring pulls a material point of the object.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::state::Pull;
use softgrip_core::step::integrate::{HOLD_SPEED, HOLD_TIME};

use crate::support::{WEIGHTLESS_EXACT, free_block as free_block_text, rest, simulation};

fn thesis(edge: f64) -> Simulation {
    let mut scene = Scene::thesis();
    scene.object.edge_length = edge;
    Simulation::new(&scene).expect("thesis scene")
}

#[test]
fn held_finger_closes_the_gap_geometrically_along_its_free_axes_only() {
    let mut sim = thesis(0.006);
    let start = sim.state.fingers[0].position;
    // Up and sideways: the thesis finger is free along z only.
    let target = start + DVec3::new(0.01, -0.004, 0.004);
    sim.state.fingers[0].held = Some(target);
    let gap0 = target.z - start.z;
    assert!(
        gap0 / HOLD_TIME < HOLD_SPEED,
        "the test stays below the cap"
    );
    let ratio = 1.0 - sim.model.dt / HOLD_TIME;
    for n in 1..=200 {
        sim.step().expect("step");
        let p = sim.state.fingers[0].position;
        assert_eq!((p.x, p.y), (start.x, start.y), "locked axes moved");
        let expected = gap0 * ratio.powi(n);
        let gap = target.z - p.z;
        assert!(
            (gap - expected).abs() <= 1e-9 * gap0,
            "step {n}: gap {gap:e}, the hold law gives {expected:e}"
        );
    }
}

#[test]
fn held_finger_moves_no_faster_than_the_cap() {
    let mut sim = thesis(0.006);
    let start = sim.state.fingers[0].position;
    sim.state.fingers[0].held = Some(start + DVec3::new(0.0, 0.0, 0.05));
    sim.step().expect("step");
    let speed = sim.state.fingers[0].velocity.length();
    assert!(
        (speed - HOLD_SPEED).abs() < 1e-12,
        "a far target moves the finger at the cap: {speed} m/s"
    );
}

#[test]
fn finger_held_where_its_load_put_it_carries_that_load_and_stays_when_let_go() {
    // Force control: 9.73 N pushes the finger to its equilibrium depth.
    let mut pushed = thesis(0.006);
    pushed
        .settle(rest(), |_| {})
        .expect("force-controlled rest");
    let position = pushed.state.fingers[0].position;
    let load = pushed.state.fingers[0].normal_force;
    assert!(load > 9.0, "the weight rests on the object: {load} N");

    // Position control to the same point, from the untouched start.
    let mut held = thesis(0.006);
    held.state.fingers[0].held = Some(position);
    held.settle(rest(), |_| {}).expect("held rest");
    let p = held.state.fingers[0].position;
    // At rest to 1e-5 m/s, the hold law leaves at most HOLD_TIME * 1e-5.
    assert!(
        (p - position).length() < HOLD_TIME * rest().speed,
        "held at {p:?}, not {position:?}"
    );
    let force = held.state.fingers[0].normal_force;
    assert!(
        (force - load).abs() < 0.01 * load,
        "held where the load balances, the contact carries {force} N, not {load} N"
    );

    // Let go: back to force control, the weight keeps it where it was.
    held.state.fingers[0].held = None;
    held.settle(rest(), |_| {}).expect("released rest");
    let moved = (held.state.fingers[0].position - position).length();
    assert!(moved < 2e-5, "let go at equilibrium, it moved {moved:e} m");
}

#[test]
fn released_finger_returns_to_its_load() {
    let mut sim = thesis(0.006);
    let start = sim.state.fingers[0].position;
    // Lifted 3 mm off the object, then let go: the weight brings it back
    // to the depth it reaches when never lifted.
    sim.state.fingers[0].held = Some(start + DVec3::new(0.0, 0.0, 0.003));
    sim.run_until(0.3).expect("lifted");
    assert_eq!(sim.state.fingers[0].normal_force, 0.0, "lifted clear");
    sim.state.fingers[0].held = None;
    sim.settle(rest(), |_| {}).expect("released rest");
    let mut never = thesis(0.006);
    never.settle(rest(), |_| {}).expect("rest");
    let (a, b) = (sim.indentation(0), never.indentation(0));
    assert!(a > 1e-3, "it came back down: depth {a:e} m");
    assert!(
        (a - b).abs() < 0.01 * b,
        "depth after release {a:e} m, never lifted {b:e} m"
    );
}

fn free_block() -> Simulation {
    simulation(&free_block_text(WEIGHTLESS_EXACT, ""), "free block")
}

/// The facet of the face z = `top` nearest the centre line, and its centroid.
fn top_facet(sim: &Simulation, top: f64) -> (u32, DVec3) {
    let centroid = |j: usize| {
        sim.model.facets[j]
            .iter()
            .map(|&i| sim.state.positions[i as usize])
            .sum::<DVec3>()
            / 3.0
    };
    let best = (0..sim.model.facets.len())
        .min_by(|&a, &b| {
            let d = |j: usize| {
                let c = centroid(j);
                (c.z - top).abs() * 1e3 + c.x.hypot(c.y)
            };
            d(a).total_cmp(&d(b))
        })
        .expect("facets");
    (best as u32, centroid(best))
}

#[test]
fn pull_changes_momentum_by_its_impulse_and_brings_the_point_to_the_target() {
    let mut sim = free_block();
    let (facet, centroid) = top_facet(&sim, 0.01);
    let target = centroid + DVec3::new(0.004, 0.0, 0.01);
    sim.state.pull = Some(Pull {
        facet,
        weights: [1.0 / 3.0; 3],
        target,
        stiffness: Pull::default_stiffness(&sim.model),
    });
    // The pull force is affine in positions and velocities, so implicit
    // Euler's linearisation is exact: each step changes the momentum by
    // dt times the pull at the end of the step (the internal forces sum to
    // zero).
    let mut impulse = DVec3::ZERO;
    let mut largest: f64 = 0.0;
    for i in 0..300 {
        sim.step().expect("step");
        impulse +=
            sim.model.dt * softgrip_core::forces::pull::force(&sim.model, &sim.state).unwrap();
        largest = largest.max(impulse.length());
        let p = sim.state.momentum(&sim.model);
        assert!(
            (p - impulse).length() < 1e-6 * largest,
            "step {i}: momentum {p:?} against impulse {impulse:?}"
        );
    }
    // A 6.4 g block pulled 1 cm in about 20 ms: ~3e-3 N s.
    assert!(largest > 1e-3, "the pull did something: {largest:e} N s");
    // Nothing else holds the block: at rest the spring is slack, the
    // point on the target.
    for _ in 0..1700 {
        sim.step().expect("step");
    }
    let tri = sim.model.facets[facet as usize];
    let point = tri
        .iter()
        .map(|&i| sim.state.positions[i as usize])
        .sum::<DVec3>()
        / 3.0;
    let off = (point - target).length();
    assert!(off < 1e-5, "the pulled point is {off:e} m off its target");
}

#[test]
fn pull_stretches_a_fixed_block_until_the_spring_balances_it() {
    // Pulled up with nothing but the mouse spring, a fixed-bottom block
    // stretches; the support carries the spring's force at rest.
    let mut scene = Scene::thesis();
    scene.object.edge_length = 0.006;
    scene.fingers.clear();
    scene.simulation.gravity = DVec3::ZERO;
    let mut sim = Simulation::new(&scene).expect("sim");
    let (facet, centroid) = top_facet(&sim, 0.02);
    let target = centroid + DVec3::new(0.0, 0.0, 0.01);
    sim.state.pull = Some(Pull {
        facet,
        weights: [1.0 / 3.0; 3],
        target,
        stiffness: Pull::default_stiffness(&sim.model),
    });
    sim.settle(rest(), |_| {}).expect("rest");
    let force = softgrip_core::forces::pull::force(&sim.model, &sim.state).unwrap();
    let reaction = sim.support_reaction();
    assert!(force.z > 0.1, "the spring pulls up: {force:?}");
    let tri = sim.model.facets[facet as usize];
    let lifted = tri
        .iter()
        .map(|&i| sim.state.positions[i as usize].z)
        .sum::<f64>()
        / 3.0
        - centroid.z;
    assert!(
        lifted > 0.1e-3 && lifted < 0.01,
        "the point rose part of the way: {lifted:e} m"
    );
    assert!(
        (force + reaction).length() < 1e-3 * force.length(),
        "the support balances the pull: {force:?} against {reaction:?}"
    );
}
