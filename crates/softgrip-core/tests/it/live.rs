//! The solver thread the viewer drives (`softgrip_core::live`): commands in,
//! frames out, edits applied live, errors reported without stopping.

use std::sync::Arc;
use std::time::Duration;

use softgrip_core::Scene;
use softgrip_core::Simulation;
use softgrip_core::live::{Command, Frame, LiveSimulation, RunState};
use softgrip_core::scene::Control;

use crate::support::shipped_scene;

/// Generous: the solver answers a command within milliseconds; CI machines
/// are slow and shared.
const PATIENCE: Duration = Duration::from_secs(10);

/// For a command that is work (hundreds of steps): only a hang guard, as a loaded machine may
/// take many times its usual second.
const WORK_PATIENCE: Duration = Duration::from_secs(300);

fn started(scene: Scene) -> LiveSimulation {
    let live = LiveSimulation::start(scene).expect("solver thread");
    live.wait_for(PATIENCE, |f| f.run == RunState::Paused)
        .expect("first frame");
    live
}

/// Sends `command` and waits for the frame that shows it was taken.
fn send(live: &LiveSimulation, command: Command) -> Arc<Frame> {
    send_within(live, command, PATIENCE)
}

fn send_within(live: &LiveSimulation, command: Command, patience: Duration) -> Arc<Frame> {
    let before = live.latest().map_or(0, |f| f.commands);
    live.send(command).expect("sent");
    live.wait_for(patience, |f| f.commands > before)
        .expect("command taken")
}

#[test]
fn starts_paused_on_its_scene_and_steps_as_a_headless_run_does() {
    let live = started(Scene::thesis());
    let first = live.latest().expect("frame");
    assert!(first.model.is_some() && first.error.is_none());
    assert_eq!(first.state.step, 0);

    let frame = send(&live, Command::Step(25));
    assert_eq!(frame.state.step, 25);
    assert_eq!(frame.run, RunState::Paused);
    let mut headless = Simulation::new(&Scene::thesis()).expect("sim");
    for _ in 0..25 {
        headless.step().expect("step");
    }
    assert_eq!(frame.state.positions, headless.state.positions);
    assert_eq!(frame.state.fingers, headless.state.fingers);
    // The plots' history has a sample per step.
    assert_eq!(frame.history[0].len(), 25);
}

#[test]
fn play_runs_until_pause() {
    let live = started(Scene::thesis());
    send(&live, Command::SetSpeed(None));
    send(&live, Command::Play);
    let running = live
        .wait_for(PATIENCE, |f| f.state.time > 0.02)
        .expect("time advances while playing");
    assert_eq!(running.run, RunState::Running);
    let paused = send(&live, Command::Pause);
    assert_eq!(paused.run, RunState::Paused);
    std::thread::sleep(Duration::from_millis(100));
    let later = live.latest().expect("frame");
    assert_eq!(later.state.step, paused.state.step, "no steps while paused");
}

/// Acceptance 3 (the solver's side): alpha set to 0 while the run goes on
/// changes the volume error, and the run is not restarted.
#[test]
fn an_alpha_edit_acts_without_a_restart() {
    // The thesis model alone, whose volume error alpha governs.
    let scene = shipped_scene("thesis_cuboid_no_bulk.toml");
    let run = |edit: bool| {
        let live = started(scene.clone());
        send_within(&live, Command::Step(150), WORK_PATIENCE);
        if edit {
            let mut edited = scene.clone();
            edited.model.alpha = 0.0;
            let frame = send(&live, Command::SetScene(Box::new(edited)));
            assert!(frame.error.is_none(), "{:?}", frame.error);
            assert_eq!(frame.scene.model.alpha, 0.0);
            assert_eq!(frame.model.as_ref().expect("model").alpha, 0.0);
            assert_eq!(frame.state.step, 150, "the run goes on from where it was");
        }
        send_within(&live, Command::Step(150), WORK_PATIENCE)
            .state
            .stats
            .volume_error
    };
    let (kept, zeroed) = (run(false), run(true));
    println!("volume error 0.15 s after the edit: alpha 6e6 {kept:.3e}, alpha 0 {zeroed:.3e}");
    assert!(zeroed > 1.05 * kept, "alpha 6e6 {kept}, alpha 0 {zeroed}");
}

/// Acceptance 3: switching a finger to velocity control acts on the next step.
#[test]
fn switching_to_velocity_control_acts_at_once() {
    let live = started(Scene::thesis());
    send(&live, Command::Step(10));
    let mut scene = Scene::thesis();
    scene.fingers[0].control = Control::Velocity;
    scene.fingers[0].force = glam::DVec3::ZERO;
    scene.fingers[0].velocity = glam::DVec3::new(0.0, 0.0, -0.01);
    send(&live, Command::SetScene(Box::new(scene)));
    let frame = send(&live, Command::Step(1));
    assert_eq!(frame.state.step, 11);
    assert_eq!(frame.state.fingers[0].velocity.z, -0.01);
}

#[test]
fn a_bad_edit_is_an_error_and_the_run_goes_on() {
    let live = started(Scene::thesis());
    send(&live, Command::Step(5));
    let mut bad = Scene::thesis();
    bad.object.young_modulus = -1.0;
    let frame = send(&live, Command::SetScene(Box::new(bad)));
    let message = frame.error.clone().expect("an error");
    println!("{message}");
    assert!(message.contains("young_modulus"), "{message}");
    assert!(
        !message.contains("edit:"),
        "no line of the written-out text: {message}"
    );
    assert!(
        frame.scene.object.young_modulus > 0.0,
        "the old scene stays"
    );
    let frame = send(&live, Command::Step(1));
    assert_eq!(frame.state.step, 6);
}

#[test]
fn a_scene_that_cannot_be_built_keeps_the_current_one() {
    let live = started(Scene::thesis());
    send(&live, Command::Step(5));
    let mut bad = Scene::thesis();
    bad.object.edge_length = 0.5; // larger than the object
    let frame = send(&live, Command::SetScene(Box::new(bad)));
    assert!(frame.error.is_some());
    assert_eq!(frame.scene.object.edge_length, 0.004);
    assert!(frame.model.is_some());
    assert_eq!(frame.state.step, 5, "the run goes on where it was");
    let frame = send(&live, Command::Step(1));
    assert_eq!(frame.error, None);
    assert_eq!(frame.state.step, 6);
}

#[test]
fn a_failing_step_pauses_with_the_error_and_reset_recovers() {
    let live = started(Scene::thesis());
    let mut starved = Scene::thesis();
    starved.simulation.cg_tolerance = 1e-12;
    starved.simulation.cg_max_iterations = 2;
    let frame = send(&live, Command::SetScene(Box::new(starved)));
    assert_eq!(frame.error, None);
    assert_eq!(frame.scene.simulation.cg_max_iterations, 2);
    send(&live, Command::SetSpeed(None));
    send(&live, Command::Play);
    let failed = live
        .wait_for(PATIENCE, |f| f.error.is_some())
        .expect("the step fails");
    assert_eq!(failed.run, RunState::Paused);
    assert!(
        failed
            .error
            .as_deref()
            .is_some_and(|e| e.contains("the linear solver stopped")),
        "{:?}",
        failed.error
    );
    assert!(live.is_alive());
    send(&live, Command::SetScene(Box::new(Scene::thesis())));
    let frame = send(&live, Command::Reset);
    assert_eq!(frame.state.step, 0);
    let frame = send(&live, Command::Step(3));
    assert_eq!((frame.state.step, frame.error.clone()), (3, None));
}

/// The plots' history stays bounded and evenly spaced over a long run.
#[test]
fn history_is_bounded_and_even() {
    let live = started(Scene::thesis());
    let mut frame = send_within(&live, Command::Step(500), WORK_PATIENCE);
    for _ in 0..4 {
        frame = send_within(&live, Command::Step(500), WORK_PATIENCE);
    }
    assert_eq!(frame.state.step, 2500);
    let samples = &frame.history[0];
    assert!(
        samples.len() <= softgrip_core::live::HISTORY_LENGTH,
        "{}",
        samples.len()
    );
    assert!(samples.len() >= softgrip_core::live::HISTORY_LENGTH / 2);
    let gaps: Vec<f64> = samples.windows(2).map(|w| w[1].time - w[0].time).collect();
    let (lo, hi) = gaps
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), g| (lo.min(*g), hi.max(*g)));
    assert!(hi < 1.5 * lo, "uneven spacing: {lo} .. {hi}");
    assert!(
        samples[0].time < 0.01,
        "the start is kept: {}",
        samples[0].time
    );
}

/// A new edge length re-meshes and starts the scene afresh on the new mesh.
#[test]
fn a_new_edge_length_re_meshes_and_restarts() {
    let live = started(Scene::thesis());
    let before = send(&live, Command::Step(5));
    let particles = before.state.positions.len();
    let mut coarser = Scene::thesis();
    coarser.object.edge_length = 0.005;
    send(&live, Command::SetScene(Box::new(coarser)));
    // A frame says "meshing" first; then the new model.
    let frame = live
        .wait_for(PATIENCE, |f| f.run != RunState::Meshing)
        .expect("meshed");
    assert!(frame.error.is_none(), "{:?}", frame.error);
    assert_eq!(frame.scene.object.edge_length, 0.005);
    assert_eq!(frame.state.step, 0, "a new mesh starts afresh");
    let model = frame.model.as_ref().expect("model");
    assert_eq!(frame.state.positions.len(), model.particle_count());
    assert!(
        model.particle_count() < particles,
        "coarser: fewer particles"
    );
    assert_eq!(send(&live, Command::Step(2)).state.step, 2);
}

#[test]
fn hold_drags_a_finger_and_letting_go_returns_it_to_its_control() {
    let live = started(Scene::thesis());
    let start = live.latest().expect("frame").state.fingers[0].position;
    let above = start + glam::DVec3::new(0.0, 0.0, 0.005);
    send(
        &live,
        Command::Hold {
            finger: 0,
            at: Some(above),
        },
    );
    let held = send_within(&live, Command::Step(300), WORK_PATIENCE);
    assert!(held.state.fingers[0].held.is_some());
    let gap = (held.state.fingers[0].position - above).length();
    assert!(gap < 1e-5, "held finger {gap:e} m from where it is held");
    send(
        &live,
        Command::Hold {
            finger: 0,
            at: None,
        },
    );
    // Force control again: its weight brings it down.
    let fallen = send_within(&live, Command::Step(100), WORK_PATIENCE);
    assert!(fallen.state.fingers[0].held.is_none());
    assert!(fallen.state.fingers[0].position.z < above.z - 1e-3);
    // A finger that is not there is ignored.
    let frame = send(
        &live,
        Command::Hold {
            finger: 7,
            at: Some(above),
        },
    );
    assert!(frame.error.is_none());
}

#[test]
fn pull_grabs_the_object_and_a_stale_facet_is_ignored() {
    let live = started(Scene::thesis());
    let frame = live.latest().expect("frame");
    let model = frame.model.clone().expect("model");
    let stiffness = softgrip_core::state::Pull::default_stiffness(&model);
    let pull = |facet: u32| softgrip_core::state::Pull {
        facet,
        weights: [1.0 / 3.0; 3],
        target: glam::DVec3::new(0.03, 0.0, 0.03),
        stiffness,
    };
    let stale = send(&live, Command::Pull(Some(pull(u32::MAX))));
    assert!(stale.state.pull.is_none(), "a facet of no mesh is no pull");
    // A side facet on +x, pulled outwards.
    let facet = model
        .facets
        .iter()
        .position(|t| {
            t.iter()
                .all(|&i| model.rest_positions[i as usize].x > 0.0249)
        })
        .expect("a facet on the +x side") as u32;
    send(&live, Command::Pull(Some(pull(facet))));
    let pulled = send(&live, Command::Step(50));
    let tri = model.facets[facet as usize];
    let moved: f64 = tri
        .iter()
        .map(|&i| pulled.state.positions[i as usize].x - model.rest_positions[i as usize].x)
        .sum::<f64>()
        / 3.0;
    assert!(moved > 1e-4, "the pulled facet moved out by {moved:e} m");
    let released = send(&live, Command::Pull(None));
    assert!(released.state.pull.is_none());
}

#[test]
fn rates_are_never_negative_across_a_reset() {
    let live = started(Scene::thesis());
    send(&live, Command::SetSpeed(None));
    send(&live, Command::Play);
    live.wait_for(PATIENCE, |f| f.state.time > 0.05)
        .expect("running");
    let reset = send(&live, Command::Reset);
    assert!(reset.state.time < 0.05, "reset went back");
    assert!(
        reset.realtime_factor >= 0.0 && reset.steps_per_second >= 0.0,
        "rates across the reset: {} x real time, {} steps/s",
        reset.realtime_factor,
        reset.steps_per_second
    );
}

/// The live run makes `softgrip run`'s physical checks: a finger pushed through a stiff cube by
/// a load its contact cannot carry is a warning in the frames, and a reset clears it.
#[test]
fn a_finger_through_the_object_is_a_warning_in_the_frames() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/hostile/files/tunnel_stiff_cube.toml"
    );
    let scene = Scene::load(std::path::Path::new(path)).expect("scene");
    let live = started(scene);
    assert!(live.latest().is_some_and(|f| f.physics_warnings.is_empty()));
    send(&live, Command::SetSpeed(None));
    send(&live, Command::Play);
    let warned = live
        .wait_for(PATIENCE, |f| !f.physics_warnings.is_empty())
        .expect("the tunnelling is found");
    assert!(
        warned.physics_warnings[0].contains("passed through the object"),
        "{:?}",
        warned.physics_warnings
    );
    send(&live, Command::Pause);
    let reset = send(&live, Command::Reset);
    assert!(
        reset.physics_warnings.is_empty(),
        "{:?}",
        reset.physics_warnings
    );
}
