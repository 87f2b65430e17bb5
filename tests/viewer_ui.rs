//! The viewer's panels driven like a user would (issue 3): egui_kittest
//! presses Play and moves the alpha slider through the accessibility tree,
//! and the solver thread must have received both.
#![cfg(feature = "gui")]

use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use softgrip::Scene;
use softgrip::live::RunState;
use softgrip::viewer::Panels;

const PATIENCE: Duration = Duration::from_secs(10);

#[test]
fn play_and_the_alpha_slider_reach_the_solver() {
    let panels = Panels::start(Scene::thesis()).expect("solver thread");
    panels
        .live
        .wait_for(PATIENCE, |f| f.run == RunState::Paused)
        .expect("first frame");
    let mut harness = Harness::new_ui_state(|ui, panels: &mut Panels| panels.ui(ui), panels);
    harness.run();

    harness.get_by_label("Play").click();
    harness.run();
    let running = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| {
            f.run == RunState::Running && f.state.time > 0.0
        })
        .expect("the solver runs after Play");
    assert!(running.error.is_none());
    // The button now offers the opposite.
    harness.run();
    harness.get_by_label("Pause");

    harness
        .get_by_role_and_label(egui::accesskit::Role::Slider, "alpha")
        .set_value_accesskit(0.0);
    harness.run();
    let edited = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.scene.model.alpha == 0.0)
        .expect("the solver got the new alpha");
    assert_eq!(edited.model.as_ref().expect("model").alpha, 0.0);
    assert_eq!(edited.run, RunState::Running, "no restart: still running");
    assert!(edited.state.time > 0.0, "no restart: time went on");
}
