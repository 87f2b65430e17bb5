//! The Grasp panel (issue 57): the window of the scene shown, computed on a thread of its own
//! while the UI goes on drawing frames, stopped by Stop, and the state at the slider's squeeze
//! shown in the 3-D view coloured by the damage measure.

use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use softgrip_core::Scene;
use softgrip_core::fields::Field;
use softgrip_core::live::RunState;
use softgrip_viewer::Panels;

use crate::support::{PATIENCE, step_until};

/// The panels on the shipped two-finger scene (its `[grasp]` limits the contact pressure).
fn grasp_panels() -> Harness<'static, Panels> {
    let scene = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/scenes/grasp_lift.toml"
    )))
    .expect("grasp scene");
    let panels = Panels::start(scene).expect("solver thread");
    panels
        .live
        .wait_for(PATIENCE, |f| f.run == RunState::Paused)
        .expect("first frame");
    let mut harness = Harness::builder()
        .with_size(eframe::egui::vec2(1280.0, 2400.0))
        .with_max_steps(32)
        .build_ui_state(|ui, panels: &mut Panels| panels.ui(ui), panels);
    harness.run();
    harness.get_by_label("Grasp window").click();
    harness.run();
    harness
}

#[test]
fn the_window_is_computed_in_the_background_and_its_squeeze_shown() {
    let mut harness = grasp_panels();
    harness.get_by_label("Compute the window").click();
    // The UI draws frames while the window is computed: it never waits for the job.
    harness.step();
    let mut frames_while_busy = 0;
    while harness.state().grasp.computed.is_none() {
        assert!(
            harness.state().grasp.busy(),
            "{:?}",
            harness.state().grasp.error
        );
        harness.step();
        frames_while_busy += 1;
        std::thread::sleep(Duration::from_millis(20));
    }
    step_until(
        &mut harness,
        Duration::from_secs(300),
        "the least squeeze's state",
        |p| p.grasp.gripped.is_some(),
    );
    let p = harness.state();
    let c = p.grasp.computed.as_ref().expect("computed");
    let least = c.window.least_squeeze();
    assert!(least > 0.28 && least < 0.30, "{least}");
    let g = p.grasp.gripped.as_ref().expect("the least squeeze's state");
    assert!(g.held && g.squeeze == least);
    harness.get_by_label_contains("window 0.2");
    assert!(
        frames_while_busy >= 3,
        "{frames_while_busy} frames drawn while computing"
    );
    harness
        .get_by_label("show this squeeze in the 3-D view")
        .click();
    harness.run();
    let p = harness.state();
    assert_eq!(p.style.color_by, Some(Field::ContactPressure));
    let overlay = p.grasp.overlay().expect("the squeeze's state is shown");
    assert!(overlay.caption.contains("held"), "{}", overlay.caption);
}

#[test]
fn stop_ends_the_window_and_says_so() {
    let mut harness = grasp_panels();
    harness.get_by_label("Compute the window").click();
    harness.step();
    harness.step();
    assert!(harness.state().grasp.busy());
    harness.get_by_label("Stop").click();
    step_until(&mut harness, Duration::from_secs(120), "the stop", |p| {
        !p.grasp.busy()
    });
    let p = harness.state();
    assert!(p.grasp.computed.is_none());
    assert_eq!(p.grasp.error.as_deref(), Some("grasp window: stopped"));
}
