//! The viewer's panels driven like a user would (issue 3): egui_kittest
//! presses Play and moves the alpha slider through the accessibility tree,
//! and the solver thread must have received both.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use softgrip_core::Scene;
use softgrip_core::live::RunState;
use softgrip_viewer::{Panels, Viewer};

use crate::support::{PATIENCE, playing, running, scratch_file, temp_dir, type_path};

#[test]
fn play_and_the_alpha_slider_reach_the_solver() {
    let mut harness = playing();
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

/// The bulk pressure's radio buttons reach the solver: "per node" builds
/// the nodal term (the built-in scene has a bulk modulus), live.
#[test]
fn the_bulk_pressure_buttons_reach_the_solver() {
    use softgrip_core::scene::BulkPressure;
    let mut harness = playing();
    assert!(harness.state().edited.model.bulk_modulus > 0.0);
    // Click a button; whether the solver's model then measures per node.
    let mut choose = |label: &str, value: BulkPressure| {
        harness.get_by_label(label).click();
        harness.run();
        let frame = harness
            .state()
            .live
            .wait_for(PATIENCE, |f| f.scene.model.bulk_pressure == value)
            .unwrap_or_else(|| panic!("the solver got {value:?}"));
        frame.model.as_ref().expect("model").nodal_bulk.is_some()
    };
    assert!(
        choose("per node", BulkPressure::Nodal),
        "the model measures it per node"
    );
    assert!(!choose("per element", BulkPressure::Element), "and back");
}

/// Acceptance 5 (for scene files; mesh files come with the importers):
/// opening a malformed file shows its error and leaves the running scene
/// alone; a good file replaces it.
#[test]
fn a_malformed_file_is_an_error_and_the_run_goes_on() {
    let (dir, bad) = scratch_file(
        "ui",
        "bad.toml",
        "[object]\nshape = \"cuboid\"\nsize = [0.05, 0.05]\n",
    );

    let mut harness = playing();

    let open = |harness: &mut Harness<'_, Panels>, path: &std::path::Path| {
        type_path(harness, path);
        harness.get_by_label("Open").click();
        harness.run();
    };
    // Open with the box empty says what to type, not "cannot read ''".
    harness.get_by_label("Open").click();
    harness.run();
    let message = harness.state().file_error.clone().expect("an error shown");
    assert!(message.starts_with("no path given"), "{message}");

    open(&mut harness, &bad);
    let message = harness.state().file_error.clone().expect("an error shown");
    assert!(message.contains("bad.toml"), "{message}");
    let frame = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.state.time > 0.01)
        .expect("still running");
    assert_eq!(
        *frame.scene,
        Scene::thesis(),
        "the running scene is untouched"
    );
    assert_eq!(frame.run, RunState::Running);

    // A good file replaces it.
    harness.state_mut().path.clear();
    let good = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("assets/scenes/pinch.toml");
    open(&mut harness, &good);
    assert_eq!(harness.state().file_error, None);
    let frame = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.scene.fingers.len() == 2)
        .expect("the pinch scene runs");
    assert!(frame.error.is_none(), "{:?}", frame.error);
    let _ = std::fs::remove_dir_all(dir);
}

/// Adding a finger from the panel reaches the solver without a restart;
/// removing it again too.
#[test]
fn fingers_are_added_and_removed_live() {
    let mut harness = running();

    harness.get_by_label("Add finger").click();
    harness.run();
    let frame = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.scene.fingers.len() == 2)
        .expect("the solver got the new finger");
    assert!(frame.error.is_none(), "{:?}", frame.error);
    assert_eq!(frame.state.fingers.len(), 2);
    assert!(frame.state.time > 0.01, "no restart");
    let new = &frame.scene.fingers[1];
    let top = frame
        .state
        .positions
        .iter()
        .map(|p| p.z)
        .fold(f64::MIN, f64::max);
    assert!(
        new.position.z > top,
        "the new finger starts above the object"
    );

    harness.run();
    let removes = harness.get_all_by_label("remove").count();
    assert_eq!(removes, 2);
    harness
        .get_all_by_label("remove")
        .last()
        .expect("a remove button")
        .click();
    harness.run();
    harness
        .state()
        .live
        .wait_for(PATIENCE, |f| {
            f.scene.fingers.len() == 1 && f.state.fingers.len() == 1
        })
        .expect("the solver dropped it");
}

type App = Harness<'static, Viewer>;

/// The whole app (panels and 3-D view) in a harness rendering with wgpu
/// on the software adapter, playing the thesis scene.
fn app() -> App {
    app_sized(820.0)
}

/// As [`app`], `height` points tall (tall enough, every panel shows).
fn app_sized(height: f32) -> App {
    let mut harness = crate::support::app(height);
    harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| f.run == RunState::Running)
        .expect("playing");
    harness.run_steps(4);
    harness
}

/// Grabs finger 1, moves the mouse four `step`s from there, waits until
/// the solver holds the finger where `reached(centre, held)` says, lets
/// go and waits for the release; returns where the finger was and the
/// target it was held at.
fn drag_finger(
    harness: &mut App,
    step: egui::Vec2,
    reached: impl Fn(glam::DVec3, glam::DVec3) -> bool,
) -> (glam::DVec3, glam::DVec3) {
    let frame = harness.state().panels.live.latest().expect("frame");
    let centre = frame.state.fingers[0].position;
    let at = harness
        .state()
        .screen_position(centre)
        .expect("the finger is in view");
    harness.hover_at(at);
    harness.run_steps(1);
    harness.drag_at(at);
    harness.run_steps(1);
    for k in 1..=4 {
        harness.hover_at(at + step * k as f32);
        harness.run_steps(1);
    }
    let held = harness
        .state()
        .panels
        .live
        // The solver thread takes the drag's targets one frame at a time:
        // under load the first frame it holds the finger may still carry
        // the grab point, so wait for the last target, not the first.
        .wait_for(PATIENCE, |f| {
            f.state.fingers[0].held.is_some_and(|h| reached(centre, h))
        })
        .unwrap_or_else(|| panic!("the solver never held the finger where asked, from {centre:?}"));
    let target = held.state.fingers[0].held.expect("held");
    harness.drop_at(at + step * 4.0);
    harness.run_steps(2);
    harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| f.state.fingers[0].held.is_none())
        .expect("let go");
    (centre, target)
}

#[test]
fn dragging_the_finger_holds_it_and_letting_go_releases_it() {
    let mut harness = app();
    // Up the screen: the finger (free along z) is held higher.
    let (centre, target) = drag_finger(&mut harness, egui::vec2(0.0, -10.0), |c, h| {
        h.z > c.z + 1e-3
    });
    assert!(
        target.z > centre.z + 1e-3,
        "held above: {target:?} from {centre:?}"
    );
    assert_eq!(
        (target.x, target.y),
        (centre.x, centre.y),
        "x, y are locked"
    );
}

/// The thesis's finger moves along z only, so a sideways drag alone holds
/// it where it was; ticking "along x" under Fingers frees x live, and the
/// same sideways drag then moves it along x.
#[test]
fn freeing_an_axis_in_the_panel_lets_a_sideways_drag_move_the_finger() {
    let mut harness = app_sized(2400.0);
    let frame = harness.state().panels.live.latest().expect("frame");
    assert_eq!(frame.scene.fingers[0].free_axes, [false, false, true]);
    // One screen step along +x's direction on screen.
    let centre = frame.state.fingers[0].position;
    let screen = |p: glam::DVec3| harness.state().screen_position(p).expect("in view");
    let step = (screen(centre + glam::DVec3::X * 0.01) - screen(centre)).normalized() * 10.0;

    // Every target of a locked axis is the grab's: any held one will do.
    let (centre, held) = drag_finger(&mut harness, step, |_, _| true);
    assert_eq!(held.x, centre.x, "x is locked: {held:?} from {centre:?}");

    harness.get_by_label("along x").click();
    harness.run();
    harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| {
            f.scene.fingers[0].free_axes == [true, false, true]
        })
        .expect("the solver got the freed axis");
    let (centre, held) = drag_finger(&mut harness, step, |c, h| h.x > c.x + 1e-3);
    assert!(
        held.x > centre.x + 1e-3,
        "x is free, the drag went +x: {held:?} from {centre:?}"
    );
    assert_eq!(held.y, centre.y, "y is still locked");
}

#[test]
fn dragging_the_object_pulls_it_with_the_mouse_spring() {
    let mut harness = app();
    // A point on the +x face, which the opening (iso) view shows.
    let p = glam::DVec3::new(0.025, 0.0, 0.01);
    let at = harness.state().screen_position(p).expect("in view");
    harness.hover_at(at);
    harness.run_steps(1);
    harness.drag_at(at);
    harness.run_steps(1);
    for dx in [10.0, 20.0, 30.0] {
        harness.hover_at(at + egui::vec2(dx, 0.0));
        harness.run_steps(1);
    }
    let pulled = harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| f.state.pull.is_some())
        .expect("the solver pulls the object");
    let pull = pulled.state.pull.unwrap();
    let model = pulled.model.clone().expect("model");
    let tri = model.facets[pull.facet as usize];
    let grabbed: glam::DVec3 = (0..3)
        .map(|a| pull.weights[a] * model.rest_positions[tri[a] as usize])
        .sum();
    assert!(
        (grabbed - p).length() < 2e-3,
        "grabbed {grabbed:?} near {p:?}"
    );
    assert!(
        pull.target.x > grabbed.x,
        "pulled to the right (+x in iso view)"
    );
    harness.drop_at(at + egui::vec2(30.0, 0.0));
    harness.run_steps(2);
    harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| f.state.pull.is_none())
        .expect("let go");
}

#[test]
fn colouring_by_a_field_draws_its_legend() {
    let mut harness = app_sized(2400.0);
    assert_eq!(harness.state().legend(), None, "plain colours at first");
    harness.get_by_label("Display").click();
    harness.run_steps(2);
    harness.get_by_label("colour by").click();
    harness.run_steps(2);
    harness.get_by_label("displacement").click();
    // The live run has moved the object (on a loaded machine it may not have, a few frames in).
    harness
        .state()
        .panels
        .live
        .wait_for(PATIENCE, |f| {
            f.model.as_ref().is_some_and(|m| {
                let moved = f.state.positions.iter().zip(&m.rest_positions);
                moved.into_iter().any(|(p, r)| p.distance(*r) > 2e-4)
            })
        })
        .expect("the object moves");
    harness.run_steps(4);
    let legend = harness.state().legend().expect("a legend");
    assert_eq!(legend.field, softgrip_core::fields::Field::Displacement);
    assert!(legend.min == 0.0 && legend.max > 1e-4, "{legend:?}");
    // The cut-away and wireframe switches reach the style.
    harness.get_by_label("cut-away along").click();
    harness.get_by_label("springs (wireframe)").click();
    harness.run_steps(2);
    let style = harness.state().panels.style;
    assert!(style.cut.is_some() && style.wireframe);
}

/// "Save as" writes the scene as the panels show it, edits included, and
/// the file opens again to the same scene.
#[test]
fn save_as_writes_the_edited_scene() {
    let dir = temp_dir("save");
    let path = dir.join("saved.toml");
    let mut harness = playing();
    harness
        .get_by_role_and_label(egui::accesskit::Role::Slider, "alpha")
        .set_value_accesskit(1234.0);
    harness.run();
    harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.scene.model.alpha == 1234.0)
        .expect("edit taken");
    type_path(&mut harness, &path);
    harness.get_by_label("Save as").click();
    harness.run();
    assert_eq!(harness.state().file_error, None);
    let saved = Scene::load(&path).expect("the saved file loads");
    assert_eq!(saved.model.alpha, 1234.0);
    let mut shown = harness.state().edited.clone();
    shown.source = saved.source.clone();
    assert_eq!(saved, shown, "the file holds the scene the panels show");
    // A place that cannot be written is an error, not a crash.
    harness.state_mut().path = dir.join("no/such/dir/x.toml").display().to_string();
    harness.get_by_label("Save as").click();
    harness.run();
    let error = harness.state().file_error.clone().expect("an error");
    assert!(error.contains("could not save"), "{error}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Acceptance 5 for meshes: a mesh file that cannot be read shows its
/// error (naming the file) and the scene that ran runs on.
#[test]
fn a_mesh_that_cannot_be_read_is_an_error_and_the_run_goes_on() {
    let (dir, bad) = scratch_file(
        "mesh",
        "broken.msh",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0\n",
    );
    let mut harness = running();
    harness.state_mut().open(bad.clone());
    harness.run();
    let frame = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.error.is_some())
        .expect("an error in the frame");
    let error = frame.error.clone().unwrap();
    assert!(error.contains("broken.msh"), "{error}");
    // The reader's own diagnosis, with the line.
    assert!(
        error.contains("broken.msh:5") && error.contains("truncated"),
        "{error}"
    );
    assert_eq!(*frame.scene, Scene::thesis(), "the scene that ran is back");
    assert!(
        frame.state.time > 0.01,
        "not restarted: t = {}",
        frame.state.time
    );
    assert_eq!(frame.run, RunState::Running, "still running");
    let later = harness
        .state()
        .live
        .wait_for(PATIENCE, |f| {
            f.state.time > frame.state.time + 0.01 || f.state.step > 0
        })
        .expect("runs on");
    assert!(later.model.is_some());
    let _ = std::fs::remove_dir_all(dir);
}
