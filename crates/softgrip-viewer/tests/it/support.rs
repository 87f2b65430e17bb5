//! What the viewer tests share: a scratch folder, the panels (or the whole
//! app) on the thesis scene in a harness, typing a path, and stepping UI
//! frames until the solver runs or a background job is done. (Each test
//! module uses part of it.)
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use softgrip_core::Scene;
use softgrip_core::live::RunState;
use softgrip_viewer::recording::Replayed;
use softgrip_viewer::{Panels, Viewer};

/// How long the solver may take to publish its first frame.
pub const PATIENCE: Duration = Duration::from_secs(20);

/// Held by the slow tests for their whole run: they start simulations, and
/// the diagnosis test counts the process's simulations
/// (`parallel::running`), which other tests running beside it would change.
pub fn one_at_a_time() -> MutexGuard<'static, ()> {
    static SLOW: Mutex<()> = Mutex::new(());
    // A test that failed while holding it leaves nothing to clean up.
    SLOW.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// An empty folder of this name for this test process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("softgrip-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The panels (paused) on the thesis scene in a harness `height` pixels
/// tall (enough to show them whole), rendered with wgpu on the software
/// adapter when `render`.
pub fn panels(height: f32, render: bool) -> Harness<'static, Panels> {
    let panels = Panels::start(Scene::thesis()).expect("solver thread");
    panels
        .live
        .wait_for(PATIENCE, |f| f.run == RunState::Paused)
        .expect("first frame");
    let mut builder = Harness::builder()
        .with_size(egui::vec2(1280.0, height))
        // Frames from the solver arrive between steps; let the UI settle.
        .with_max_steps(32);
    if render {
        builder = builder.wgpu();
    }
    let mut harness = builder.build_ui_state(|ui, panels: &mut Panels| panels.ui(ui), panels);
    harness.run();
    harness
}

/// Steps UI frames until `done` or the time is up.
pub fn step_until<S>(
    harness: &mut Harness<'_, S>,
    patience: Duration,
    what: &str,
    done: impl Fn(&S) -> bool,
) {
    let start = Instant::now();
    while !done(harness.state()) {
        assert!(start.elapsed() < patience, "timed out waiting for {what}");
        harness.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    harness.step();
}

/// How long a replay of a small recording may take; the machine may be
/// busy.
pub const REPLAY_PATIENCE: Duration = Duration::from_secs(300);

/// The panels as [`panels`] makes them, 1800 pixels tall, with Play
/// pressed.
pub fn playing() -> Harness<'static, Panels> {
    let mut harness = panels(1800.0, false);
    harness.get_by_label("Play").click();
    harness.run();
    harness
}

/// The panels as [`playing`] makes them, once the solver has run 10 ms
/// of the scene.
pub fn running() -> Harness<'static, Panels> {
    let harness = playing();
    harness
        .state()
        .live
        .wait_for(PATIENCE, |f| f.state.time > 0.01)
        .expect("running");
    harness
}

/// A scratch folder `dir` (as [`temp_dir`] makes it) holding a file
/// `name` of `text`; the folder and the file's path.
pub fn scratch_file(dir: &str, name: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(dir);
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    (dir, path)
}

/// Types `path` into the scene file box.
pub fn type_path(harness: &mut Harness<'_, Panels>, path: &Path) {
    let field = harness.get_by_role(egui::accesskit::Role::TextInput);
    field.focus();
    harness.run();
    harness
        .get_by_role(egui::accesskit::Role::TextInput)
        .type_text(&path.display().to_string());
    harness.run();
}

/// Steps the panels until the recording's replay has ended.
pub fn until_replayed(harness: &mut Harness<'_, Panels>) {
    step_until(harness, REPLAY_PATIENCE, "the replay", |p| {
        !p.recording.replaying()
    });
}

/// The finished replay of the recording open in the panels.
pub fn finished_replay(harness: &Harness<'_, Panels>) -> Arc<Replayed> {
    harness
        .state()
        .recording
        .replayed()
        .expect("replayed")
        .clone()
}

/// The whole app (panels and 3-D view) on the thesis scene, rendered
/// with wgpu on the software adapter, `height` points tall.
pub fn app(height: f32) -> Harness<'static, Viewer> {
    Harness::builder()
        .with_size(egui::vec2(1280.0, height))
        .with_max_steps(8)
        .wgpu()
        .build_eframe(|cc| Viewer::new(cc, Scene::thesis()).expect("viewer"))
}

/// The app as [`app`] makes it with the recording at `path` opened and
/// replayed (within `patience`).
pub fn app_replaying(height: f32, path: &Path, patience: Duration) -> Harness<'static, Viewer> {
    let mut harness = app(height);
    harness.run_steps(2);
    harness
        .state_mut()
        .panels
        .open_recording(path.to_path_buf());
    step_until(&mut harness, patience, "the replay", |v| {
        !v.panels.recording.replaying()
    });
    harness
}
