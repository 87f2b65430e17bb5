//! softgrip-viewer: the desktop viewer and the 3-D renderer.
//!
//! - [`render`]: CPU-built lit triangles drawn by wgpu into an offscreen texture, an orbit
//!   camera and mouse picking; headless on a software adapter for `softgrip screenshot`.
//! - [`Viewer`]: the eframe app ([`run`]): [`Panels`] that drive a `softgrip_core::live`
//!   simulation on its solver thread (the UI sends edits without waiting and draws the latest
//!   frame), the 3-D view, and the [`recording`] panel's lab jobs on threads of their own.
//!
//! This file holds the two and the order of a frame: the left panel, the right panel, the 3-D
//! view in the centre. Each section of a panel has its file.

#![warn(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod recording;
pub mod render;

mod app;
mod controls;
mod display;
pub mod grasp;
mod jobs;
mod measure;
mod parameters;
mod plot_grid;
mod plots;
mod recording_actions;
mod scene_file;
mod statistics;
mod view3d;
mod widgets;

pub use app::{Options, run, run_with};
pub use scene_file::MESH_EXTENSIONS;

/// The paths the viewer had before its files moved to the crate root
/// (`softgrip_viewer::viewer::run`, as the CLI names it).
pub mod viewer {
    pub use crate::recording::{self, diagnosis};
    pub use crate::{MESH_EXTENSIONS, Options, Panels, Viewer, run, run_with};
}

use std::cell::Cell;
use std::sync::Arc;

use anyhow::Result;
use eframe::egui;
use glam::DVec3;

use controls::RunControls;
use measure::Measure;
use recording::RecordingPanel;
use render::{Style, View};
use softgrip_core::live::{Command, Frame, LiveSimulation, RunState};
use softgrip_core::scene::Scene;
use view3d::{FromPanels, View3d};
use widgets::ERROR_RED;

/// The whole app: the panels and the 3-D view. Public for the UI tests,
/// which run it in egui_kittest on a software adapter.
pub struct Viewer {
    /// The left and right panels and the solver they drive.
    pub panels: Panels,
    view: View3d,
    measure: Option<Measure>,
}

/// The panels and the solver they drive, without the 3-D view: what the
/// UI tests exercise (`tests/it/viewer_ui.rs`).
pub struct Panels {
    /// The simulation running on its solver thread; edits go to it as commands.
    pub live: LiveSimulation,
    /// The scene as the panels show it; sent when a widget changes it.
    pub edited: Scene,
    /// Commands sent so far; once the solver has taken them all, the
    /// panels show the scene it runs (a rejected edit springs back).
    sent: Cell<u64>,
    /// The latest frame, read at the start of each UI frame.
    pub frame: Option<Arc<Frame>>,
    controls: RunControls,
    /// The 3-D view's colours and what it shows, as the Display section sets them.
    pub style: Style,
    /// A preset view button pressed this frame.
    view_request: Option<View>,
    /// The scene file box: a path to open or save.
    pub path: String,
    /// The last file error (a file that would not open or save); the run
    /// is not touched.
    pub file_error: Option<String>,
    /// What the last save or open did, for the user.
    pub file_status: Option<String>,
    /// UI frame time (s), smoothed, and when the last frame started.
    frame_time: f64,
    /// When the last UI frame started; `None` before the first.
    pub last_frame: Option<std::time::Instant>,
    /// The lab recording over the run, its replay and its fit.
    pub recording: RecordingPanel,
    /// The grasp window of the scene shown.
    pub grasp: grasp::GraspPanel,
    /// The live run was paused for a fit or a diagnosis, and is played
    /// again when it ends (unless the user played it meanwhile).
    paused_for_job: bool,
}

impl Viewer {
    /// The window pixel (egui points) where `world` appears in the 3-D
    /// view as last drawn; `None` before the first drawing or behind the
    /// camera.
    pub fn screen_position(&self, world: DVec3) -> Option<egui::Pos2> {
        self.view.screen_position(world)
    }

    /// The colour map's legend of the 3-D view as last drawn.
    pub fn legend(&self) -> Option<render::Legend> {
        self.view.legend()
    }

    /// The 3-D view, fed by the panels.
    fn view3d(&mut self, ui: &mut egui::Ui, frame: &eframe::Frame) {
        let panels = &mut self.panels;
        let to_solver = |command| send(&panels.live, &panels.sent, command);
        let from_panels = FromPanels {
            frame: panels.frame.clone(),
            recording: &panels.recording,
            grasp: &panels.grasp,
            style: &panels.style,
            view_request: &mut panels.view_request,
            send: &to_solver,
        };
        self.view.ui(ui, frame, from_panels);
    }
}

impl eframe::App for Viewer {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let started = std::time::Instant::now();
        let interval = self.panels.last_frame.map(|t| (started - t).as_secs_f64());
        self.panels.ui(ui);
        egui::CentralPanel::default().show(ui, |ui| self.view3d(ui, frame));
        let work = started.elapsed().as_secs_f64();
        if let Some(m) = &mut self.measure {
            if m.record(interval, work, self.panels.frame.as_deref()) {
                ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
            }
            ui.ctx().request_repaint();
            return;
        }
        // Redraw when the solver may have published (it does every 15 ms
        // while running) or a drag goes on; otherwise egui redraws on input.
        let running = self
            .panels
            .frame
            .as_ref()
            .is_some_and(|f| f.run != RunState::Paused);
        if running || self.view.dragging() {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(16));
        } else if self.panels.recording.busy() || self.panels.grasp.busy() {
            // A progress bar: two frames a second leave the cores to the
            // job (a frame on a software renderer costs about 0.1 s).
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(500));
        } else {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(250));
        }
    }
}

impl Panels {
    /// Starts the solver thread on `scene` (paused).
    pub fn start(scene: Scene) -> Result<Panels> {
        Ok(Panels {
            live: LiveSimulation::start(scene.clone())?,
            edited: scene,
            sent: Cell::new(0),
            frame: None,
            controls: RunControls::default(),
            style: Style {
                finger_opacity: 0.45,
                ..Style::default()
            },
            view_request: None,
            frame_time: 0.0,
            last_frame: None,
            path: String::new(),
            file_error: None,
            file_status: None,
            recording: RecordingPanel::default(),
            grasp: grasp::GraspPanel::default(),
            paused_for_job: false,
        })
    }

    /// The left and right panels for one UI frame (the central area is
    /// left to the caller).
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        self.take_latest();
        egui::Panel::left("parameters")
            .resizable(true)
            .default_size(320.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.left(ui));
            });
        egui::Panel::right("statistics")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                if let Some(error) = self.frame.as_ref().and_then(|f| f.error.clone()) {
                    ui.colored_label(ERROR_RED, error);
                    ui.separator();
                }
                // What the run's physical checks found: the numbers below are not physical.
                if let Some(f) = &self.frame
                    && !f.physics_warnings.is_empty()
                {
                    for w in f.physics_warnings.iter() {
                        ui.colored_label(egui::Color32::from_rgb(190, 120, 20), w);
                    }
                    ui.separator();
                }
                statistics::ui(ui, self.frame.as_deref(), self.frame_time);
                ui.separator();
                plots::ui(ui, self.frame.as_deref());
            });
    }

    /// The frame time, the solver's latest frame and the jobs' results,
    /// at the start of a UI frame.
    fn take_latest(&mut self) {
        let now = std::time::Instant::now();
        if let Some(last) = self.last_frame {
            let dt = (now - last).as_secs_f64();
            self.frame_time = if self.frame_time == 0.0 {
                dt
            } else {
                0.95 * self.frame_time + 0.05 * dt
            };
        }
        self.last_frame = Some(now);
        self.frame = self.live.latest();
        self.recording.poll();
        self.grasp.poll();
        if let Some(f) = &self.frame
            && f.commands >= self.sent.get()
            && *f.scene != self.edited
        {
            // The solver took all our commands: show what it runs (a
            // rejected edit springs back, with the error beside it).
            self.edited = (*f.scene).clone();
        }
    }

    /// The left panel, top to bottom.
    fn left(&mut self, ui: &mut egui::Ui) {
        ui.heading("softgrip");
        let running = self
            .frame
            .as_ref()
            .is_some_and(|f| f.run == RunState::Running);
        let to_solver = |command| send(&self.live, &self.sent, command);
        self.controls.ui(ui, running, &to_solver);
        ui.separator();
        self.scene_file(ui);
        ui.separator();
        if let Some(action) = self.recording.ui(ui) {
            self.recording_action(action);
        }
        ui.separator();
        if let Some(grasp::Action::ColorBy(field)) = self.grasp.ui(ui, &self.edited) {
            self.style.color_by = Some(field);
        }
        self.pause_for_long_jobs();
        if self.paused_for_job {
            ui.label(
                "the live run waits while this runs, so that it has the cores (Play runs both)",
            );
        }
        ui.separator();
        let changed = parameters::ui(ui, &mut self.edited, self.frame.as_deref());
        display::ui(ui, &mut self.style, &mut self.view_request);
        if changed {
            self.send(Command::SetScene(Box::new(self.edited.clone())));
        }
    }

    fn send(&self, command: Command) {
        send(&self.live, &self.sent, command);
    }
}

/// Sends `command` to the solver and counts it.
fn send(live: &LiveSimulation, sent: &Cell<u64>, command: Command) {
    // A full channel only drops this click; the next frame can resend.
    if live.send(command).is_ok() {
        sent.set(sent.get() + 1);
    }
}
