//! The helper thread changes nothing but the speed: the thesis scene on one
//! thread and on two gives bit-identical trajectories (the work is split in
//! the same places and summed in the same order either way). Its own test
//! binary, the one exception to one binary per crate: the helper slot is
//! the process's, and the other tests of a binary run side by side and take
//! it (one test function here for the same reason).

use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::scene::Elasticity;

#[test]
#[ignore = "slow: two long runs"]
fn one_thread_and_two_give_bit_identical_runs() {
    let run_scene = |scene: &Scene, threads: usize, until: f64| {
        let mut sim = Simulation::new(scene).expect("sim");
        sim.set_threads(threads);
        sim.run_until(until).expect("run");
        (sim.is_threaded(), sim.state)
    };
    let run = |threads: usize| run_scene(&Scene::thesis(), threads, 0.3);
    let (threaded_one, one) = run(1);
    let (threaded_two, two) = run(2);
    // The neo-Hookean elements with their nodal volume term (computed once,
    // applied matrix-free on the main thread's half of each product) and their Maxwell arms
    // (each thread's elements read the viscous strains the step started from).
    let mut continuum = Scene::thesis();
    continuum.model.elasticity = softgrip_core::scene::Elasticity::NeoHookean;
    continuum.model.bulk_pressure = softgrip_core::scene::BulkPressure::Nodal;
    continuum.model.prony_g = 0.3;
    continuum.model.prony_tau = 0.05;
    assert_eq!(
        run_scene(&continuum, 1, 0.1).1,
        run_scene(&continuum, 2, 0.1).1
    );
    assert!(!threaded_one);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cores >= 2 {
        assert!(threaded_two, "a second core is there, the helper must run");
    }
    // Through the drop, contact and spring limits: every bit the same.
    assert_eq!(one, two);

    // On the default count a simulation gives the helper up while another
    // one runs, and takes it again when that one ends: bit-identical still.
    let mut sim = Simulation::new(&Scene::thesis()).expect("sim");
    sim.run_until(0.1).expect("run");
    let alone = sim.is_threaded();
    let mut other = Simulation::new(&Scene::thesis()).expect("sim");
    other.set_threads(1);
    other.step().expect("step");
    sim.run_until(0.2).expect("run");
    let beside = sim.is_threaded();
    drop(other);
    sim.run_until(0.3).expect("run");
    let after = sim.is_threaded();
    if cores >= 2 {
        assert!(alone, "alone, it takes the second core");
        assert!(after, "it takes the second core back");
    }
    if cores == 2 {
        assert!(!beside, "beside another simulation, the cores are taken");
    }
    assert_eq!(sim.state, one);
    drop(sim);

    // Rayleigh damping's passes (`forces::viscosity`) split alike: the springs' dashpots and
    // the elements' viscosity, each half on the helper.
    for elasticity in [Elasticity::Springs, Elasticity::NeoHookean] {
        let run = |threads: usize| {
            let mut scene = Scene::thesis();
            scene.model.elasticity = elasticity;
            scene.model.rayleigh_mass = 2.0;
            scene.model.rayleigh_stiffness = 2e-4;
            let mut sim = Simulation::new(&scene).expect("sim");
            sim.set_threads(threads);
            sim.run_until(0.1).expect("run");
            (sim.is_threaded(), sim.state)
        };
        let (_, one) = run(1);
        let (threaded, two) = run(2);
        if cores >= 2 {
            assert!(threaded);
        }
        assert_eq!(one, two, "{elasticity:?}");
    }
}
