//! Self-collision (`[model] self_collision`): a thin strip, clamped at one
//! end, has its other end pulled over and down onto itself. With
//! self-collision the end lands on the strip; without, it passes through.

use glam::DVec3;
use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::state::Pull;

use crate::support::{WEIGHTLESS, cuboid_scene, simulation};

fn strip(self_collision: bool) -> Simulation {
    let more = format!(
        r#"young_modulus = 20e3
poisson_ratio = 0.45

[model]
bulk_modulus = 6.7e4
self_collision = {self_collision}

[support]
kind = "none"

[[fixed]]
min = [-0.041, -0.01, -0.001]
max = [-0.030, 0.01, 0.004]
"#
    );
    simulation(
        &cuboid_scene(WEIGHTLESS, [0.08, 0.01, 0.003], 0.0015, &more),
        "strip.toml",
    )
}

/// Boundary particles inside an element they do not belong to: the surface
/// passing through the object.
fn penetrating(sim: &Simulation) -> usize {
    let m = &sim.model;
    let x = &sim.state.positions;
    let mut boundary: Vec<u32> = m.facets.iter().flatten().copied().collect();
    boundary.sort_unstable();
    boundary.dedup();
    let inside: Vec<u32> = boundary
        .iter()
        .copied()
        .filter(|&p| {
            let q = x[p as usize];
            m.tets.iter().any(|t| {
                if t.contains(&p) {
                    return false;
                }
                let v = t.map(|i| x[i as usize]);
                let lo = v[0].min(v[1]).min(v[2]).min(v[3]);
                let hi = v[0].max(v[1]).max(v[2]).max(v[3]);
                if q.cmplt(lo).any() || q.cmpgt(hi).any() {
                    return false;
                }
                let vol = |a: DVec3, b: DVec3, c: DVec3, d: DVec3| (b - a).cross(c - a).dot(d - a);
                let total = vol(v[0], v[1], v[2], v[3]);
                let w = [
                    vol(q, v[1], v[2], v[3]) / total,
                    vol(v[0], q, v[2], v[3]) / total,
                    vol(v[0], v[1], q, v[3]) / total,
                    vol(v[0], v[1], v[2], q) / total,
                ];
                w.iter().all(|&w| w > 1e-6)
            })
        })
        .collect();
    for &p in &inside {
        eprintln!(
            "inside: particle {p} at {:?} (rest {:?})",
            x[p as usize], m.rest_positions[p as usize]
        );
    }
    inside.len()
}

/// Pulls the free end's top over a half circle onto the strip near the
/// clamp, aiming at its mid-plane, and holds it there.
fn fold(sim: &mut Simulation) {
    let m = &sim.model;
    let x = &sim.state.positions;
    let (facet, _) = m
        .facets
        .iter()
        .enumerate()
        .filter(|(_, t)| t.iter().all(|&i| x[i as usize].z > 0.0029))
        .max_by(|a, b| {
            let cx = |t: &[u32; 3]| t.iter().map(|&i| x[i as usize].x).sum::<f64>();
            cx(a.1).total_cmp(&cx(b.1))
        })
        .expect("a top facet at the free end");
    let weights = [1.0 / 3.0; 3];
    let (hinge, radius) = (0.005, 0.033);
    let target = |theta: f64| {
        DVec3::new(
            hinge + radius * theta.cos(),
            0.0,
            0.0015 + radius * theta.sin(),
        )
    };
    sim.state.pull = Some(Pull {
        facet: facet as u32,
        weights,
        target: target(0.0),
        stiffness: 3.0 * Pull::default_stiffness(&sim.model),
    });
    let steps = 1500;
    for n in 0..=steps + 500 {
        let theta = std::f64::consts::PI * (n.min(steps) as f64 / steps as f64);
        if let Some(p) = &mut sim.state.pull {
            p.target = target(theta);
        }
        sim.step().expect("step");
    }
}

#[test]
#[ignore = "slow: a long folding run"]
fn a_strip_folded_onto_itself_does_not_pass_through_with_self_collision() {
    let mut off = strip(false);
    fold(&mut off);
    let through = penetrating(&off);
    let mut on = strip(true);
    fold(&mut on);
    let kept = penetrating(&on);
    eprintln!(
        "particles inside the strip after the fold: {through} without self-collision, {kept} with ({} contacts)",
        on.state.self_contacts.len()
    );
    assert!(through > 0, "without self-collision the end passes through");
    assert_eq!(kept, 0, "with it nothing passes through");
    assert!(
        !on.state.self_contacts.is_empty(),
        "the end rests on the strip"
    );
}

/// Nothing at rest touches itself: the surface's own neighbours are
/// excluded.
#[test]
fn an_undeformed_object_has_no_self_contacts() {
    let mut sim = strip(true);
    for _ in 0..5 {
        sim.step().expect("step");
    }
    assert!(sim.state.self_contacts.is_empty());
    let mut scene = Scene::thesis();
    scene.object.edge_length = 0.006;
    scene.model.self_collision = true;
    let mut sim = Simulation::new(&scene).expect("thesis");
    sim.run_until(0.05).expect("run");
    assert!(sim.state.self_contacts.is_empty());
}
