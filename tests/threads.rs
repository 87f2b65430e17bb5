//! The helper thread changes nothing but the speed: the thesis scene on one
//! thread and on two gives bit-identical trajectories (the work is split in
//! the same places and summed in the same order either way). Its own test
//! binary, so no other simulation in the process holds the helper slot.

use softgrip::{Scene, Simulation};

#[test]
fn one_thread_and_two_give_bit_identical_runs() {
    let run = |threads: usize| {
        let mut sim = Simulation::new(&Scene::thesis()).expect("sim");
        sim.set_threads(threads);
        sim.run_until(0.3).expect("run");
        (sim.is_threaded(), sim.state)
    };
    let (threaded_one, one) = run(1);
    let (threaded_two, two) = run(2);
    assert!(!threaded_one);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cores >= 2 {
        assert!(threaded_two, "a second core is there, the helper must run");
    }
    // Through the drop, contact and spring limits: every bit the same.
    assert_eq!(one, two);
}
