//! What the viewer tests share: a scratch folder, the panels on the
//! thesis scene in a harness, and stepping UI frames until a background
//! job is done. (Each test crate uses part of it.)
#![allow(dead_code)]

use std::path::PathBuf;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use softgrip_core::Scene;
use softgrip_core::live::RunState;
use softgrip_viewer::viewer::Panels;

/// How long the solver may take to publish its first frame.
pub const PATIENCE: Duration = Duration::from_secs(20);

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
