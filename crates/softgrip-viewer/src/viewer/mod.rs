//! The desktop viewer (eframe: winit + egui + egui-wgpu): the 3-D view
//! rendered by `crate::render` on eframe's wgpu device into a texture
//! shown in the central panel, the parameter panels on the left, the
//! statistics on the right. The simulation runs on `softgrip_core::live`'s solver
//! thread: the UI sends edits without waiting and draws the latest frame.
//! A lab recording (`recording`) is replayed and fitted on threads of its
//! own, and shown in the 3-D view in place of the live frame.

pub mod diagnosis;
mod grid;
pub mod recording;

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Result, anyhow};
use eframe::egui;
use glam::{DVec3, Vec3};

use crate::render::gpu::{Pipeline, Target};
use crate::render::{self, Camera, Style, View, pick};
use softgrip_core::live::{Command, Frame, LiveSimulation, RunState};
use softgrip_core::scene::{BulkPressure, Control, Elasticity, FingerShape, Scene, SupportKind};
use softgrip_core::state::Pull;

/// How the viewer runs.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Benchmark: redraw continuously for this long with the solver as
    /// fast as it goes, print the frame times, close.
    pub measure: Option<std::time::Duration>,
    /// Start playing (else paused).
    pub play: bool,
    /// A recording to open at start (`softgrip view --recording`).
    pub recording: Option<PathBuf>,
}

/// Opens the viewer on `scene`, playing; returns when the window is closed.
pub fn run(scene: Scene) -> Result<()> {
    run_with(
        scene,
        Options {
            measure: None,
            play: true,
            recording: None,
        },
    )
}

/// Opens the viewer on `scene` with `options`.
pub fn run_with(scene: Scene, options: Options) -> Result<()> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(anyhow!(
            "no display to open the viewer on (neither DISPLAY nor WAYLAND_DISPLAY is set). Headless, use `softgrip run` for the numbers or `softgrip screenshot --at 1 --out shot.png` for a picture"
        ));
    }
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1280.0, 820.0])
            .with_title("softgrip"),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration {
            surface: egui_wgpu::SurfaceConfig {
                present_mode: wgpu::PresentMode::AutoVsync,
                desired_maximum_frame_latency: Some(1),
            },
            ..Default::default()
        },
        ..Default::default()
    };
    eframe::run_native(
        "softgrip",
        native,
        Box::new(move |cc| {
            let mut app = Viewer::new(cc, scene).map_err(|e| e.to_string())?;
            if !options.play {
                app.panels.send(Command::Pause);
            }
            if let Some(path) = &options.recording {
                app.panels.open_recording(path.clone());
            }
            if let Some(span) = options.measure {
                app.panels.send(Command::SetSpeed(None));
                app.measure = Some(Measure {
                    span,
                    start: None,
                    frames: Vec::new(),
                    work: Vec::new(),
                    done: false,
                });
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow!("the viewer could not start: {e}"))
}

/// What a drawing of the 3-D view shows: the live frame (0 while a
/// recording is shown), camera, style, size and the recording's sample.
type DrawnKey = (
    usize,
    Camera,
    Style,
    u32,
    u32,
    Option<recording::OverlayKey>,
);

struct View3d {
    pipeline: Pipeline,
    target: Target,
    texture: egui::TextureId,
    camera: Option<Camera>,
    drag: Drag,
    /// What the texture shows (frame, camera, style, size), so an
    /// unchanged view is not drawn again, and the legend drawn with it.
    drawn: Option<DrawnKey>,
    legend: Option<render::Legend>,
    /// When the solver started re-meshing, for the overlay's clock.
    meshing_since: Option<std::time::Instant>,
}

/// While a finger with a locked axis is dragged: which way it can move and
/// where to free the others (a scene's `free_axes`; the thesis's finger
/// moves along z only, so a sideways drag alone does nothing).
fn locked_axes_hint(index: usize, free: [bool; 3]) -> Option<String> {
    if free.iter().all(|f| *f) {
        return None;
    }
    let names = |want: bool| {
        ["x", "y", "z"]
            .into_iter()
            .zip(free)
            .filter(|(_, f)| *f == want)
            .map(|(n, _)| n)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let finger = index + 1;
    Some(if free.iter().any(|f| *f) {
        format!(
            "finger {finger} moves along {} only: tick \"along {}\" under Fingers",
            names(true),
            names(false).replace(", ", "\" or \"along ")
        )
    } else {
        format!("finger {finger} has every axis locked: tick its \"along\" boxes under Fingers")
    })
}

/// What a primary-button drag in the 3-D view does, decided where it
/// starts: on a finger it moves the finger, on the object it pulls it with
/// the mouse spring, elsewhere (or with Alt held) it orbits.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Drag {
    None,
    Orbit,
    Finger {
        index: usize,
        /// Where the finger was grabbed and its centre then.
        grabbed: DVec3,
        centre: DVec3,
        /// The drag plane's normal: the camera's forward at the grab.
        facing: DVec3,
        last: Option<DVec3>,
    },
    Object {
        facet: u32,
        weights: [f64; 3],
        grabbed: DVec3,
        facing: DVec3,
        last: Option<DVec3>,
    },
}

/// Files the Open button takes as a mesh for the current scene (the
/// scene spec's `shape = "mesh"` formats).
pub const MESH_EXTENSIONS: &[&str] = &["msh", "node", "ele", "vtk", "vtu", "stl", "obj"];

/// The panels and the solver they drive, without the 3-D view: what the
/// UI tests exercise (`tests/viewer_ui.rs`).
pub struct Panels {
    pub live: LiveSimulation,
    /// The scene as the panels show it; sent when a widget changes it.
    pub edited: Scene,
    /// Commands sent so far; once the solver has taken them all, the
    /// panels show the scene it runs (a rejected edit springs back).
    sent: std::cell::Cell<u64>,
    /// The latest frame, read at the start of each UI frame.
    pub frame: Option<Arc<Frame>>,
    speed: f64,
    max_speed: bool,
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
    pub last_frame: Option<std::time::Instant>,
    /// The lab recording over the run, its replay and its fit.
    pub recording: recording::RecordingPanel,
    /// The live run was paused for a fit or a diagnosis, and is played
    /// again when it ends (unless the user played it meanwhile).
    paused_for_job: bool,
}

/// The whole app: the panels and the 3-D view. Public for the UI tests,
/// which run it in egui_kittest on a software adapter.
pub struct Viewer {
    pub panels: Panels,
    view: View3d,
    /// Where the 3-D view was last drawn (egui points) and its pixel size.
    view_rect: Option<(egui::Rect, u32, u32)>,
    measure: Option<Measure>,
}

/// `softgrip view --measure`: frame intervals and the UI's own work per
/// frame (panels, drawing built, GPU commands recorded), in seconds.
struct Measure {
    span: std::time::Duration,
    start: Option<std::time::Instant>,
    frames: Vec<f64>,
    work: Vec<f64>,
    done: bool,
}

impl Measure {
    /// Prints the figures; true when the span is over.
    fn record(&mut self, interval: Option<f64>, work: f64, frame: Option<&Frame>) -> bool {
        if self.done {
            return true;
        }
        let start = *self.start.get_or_insert_with(std::time::Instant::now);
        // The first second is warm-up (shader compilation, first mesh).
        if start.elapsed().as_secs_f64() < 1.0 {
            return false;
        }
        if let Some(i) = interval {
            self.frames.push(i);
        }
        self.work.push(work);
        if start.elapsed() < self.span + std::time::Duration::from_secs(1) {
            return false;
        }
        let stats = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
            let at = |q: f64| {
                v.get(((v.len() as f64 - 1.0) * q).round() as usize)
                    .copied()
            };
            (mean, at(0.5).unwrap_or(0.0), at(0.95).unwrap_or(0.0))
        };
        let (mean, median, p95) = stats(&mut self.frames);
        let (wmean, wmedian, wp95) = stats(&mut self.work);
        let tets = frame
            .and_then(|f| f.model.as_ref())
            .map_or(0, |m| m.tets.len());
        println!(
            "viewer: {} frames, {tets} tetrahedra; frame interval mean {:.1} ms, median {:.1} ms, 95 % {:.1} ms ({:.1} frames/s); UI work per frame mean {:.1} ms, median {:.1} ms, 95 % {:.1} ms; solver {:.0} steps/s ({:.2} x real time, {:?})",
            self.frames.len(),
            1e3 * mean,
            1e3 * median,
            1e3 * p95,
            1.0 / mean.max(1e-9),
            1e3 * wmean,
            1e3 * wmedian,
            1e3 * wp95,
            frame.map_or(0.0, |f| f.steps_per_second),
            frame.map_or(0.0, |f| f.realtime_factor),
            frame.map(|f| f.run),
        );
        self.done = true;
        true
    }
}

impl Viewer {
    /// The window pixel (egui points) where `world` appears in the 3-D
    /// view as last drawn; `None` before the first drawing or behind the
    /// camera.
    pub fn screen_position(&self, world: DVec3) -> Option<egui::Pos2> {
        let (rect, w, h) = self.view_rect?;
        let camera = self.view.camera.as_ref()?;
        let (x, y) = camera.project(world.as_vec3(), w, h)?;
        Some(egui::pos2(
            rect.min.x + x * rect.width() / w as f32,
            rect.min.y + y * rect.height() / h as f32,
        ))
    }

    /// The colour map's legend of the 3-D view as last drawn.
    pub fn legend(&self) -> Option<render::Legend> {
        self.view.legend
    }

    /// Builds the app on eframe's wgpu device and starts the solver,
    /// playing.
    pub fn new(cc: &eframe::CreationContext<'_>, scene: Scene) -> Result<Viewer> {
        let rs = cc
            .wgpu_render_state
            .as_ref()
            .ok_or_else(|| anyhow!("eframe started without wgpu"))?;
        let pipeline = Pipeline::new(&rs.device);
        let target = Target::new(&rs.device, 800, 600);
        let texture = rs.renderer.write().register_native_texture(
            &rs.device,
            &target.view,
            wgpu::FilterMode::Linear,
        );
        let panels = Panels::start(scene)?;
        // The viewer opens running, in real time.
        panels.send(Command::Play);
        Ok(Viewer {
            panels,
            view: View3d {
                pipeline,
                target,
                texture,
                camera: None,
                drag: Drag::None,
                drawn: None,
                legend: None,
                meshing_since: None,
            },
            view_rect: None,
            measure: None,
        })
    }
}

impl Panels {
    /// Starts the solver thread on `scene` (paused).
    pub fn start(scene: Scene) -> Result<Panels> {
        Ok(Panels {
            live: LiveSimulation::start(scene.clone())?,
            edited: scene,
            sent: std::cell::Cell::new(0),
            frame: None,
            speed: 1.0,
            max_speed: false,
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
            recording: recording::RecordingPanel::default(),
            paused_for_job: false,
        })
    }

    /// A fit or a diagnosis wants the cores the live run (and its drawing)
    /// would take: the run waits while one goes on (a diagnosis from the
    /// viewer took two and a half times the CLI's beside a running scene on
    /// a 2-core machine) and plays again when it ends, unless the user
    /// played it meanwhile (they may: the note says how).
    fn pause_for_long_jobs(&mut self) {
        let long = self.recording.fitting() || self.recording.diagnosis.running();
        let run = self.frame.as_ref().map(|f| f.run);
        if long && !self.paused_for_job && run == Some(RunState::Running) {
            self.send(Command::Pause);
            self.paused_for_job = true;
        } else if !long && self.paused_for_job {
            self.paused_for_job = false;
            if run == Some(RunState::Paused) {
                self.send(Command::Play);
            }
        }
    }

    /// The left and right panels for one UI frame (the central area is
    /// left to the caller).
    pub fn ui(&mut self, ui: &mut egui::Ui) {
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
        if let Some(f) = &self.frame
            && f.commands >= self.sent.get()
            && *f.scene != self.edited
        {
            // The solver took all our commands: show what it runs (a
            // rejected edit springs back, with the error beside it).
            self.edited = (*f.scene).clone();
        }
        egui::Panel::left("parameters")
            .resizable(true)
            .default_size(320.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.heading("softgrip");
                    self.controls(ui);
                    ui.separator();
                    self.file(ui);
                    ui.separator();
                    if let Some(action) = self.recording.ui(ui) {
                        self.recording_action(action);
                    }
                    self.pause_for_long_jobs();
                    if self.paused_for_job {
                        ui.label(
                            "the live run waits while this runs, so that it has the cores (Play runs both)",
                        );
                    }
                    ui.separator();
                    if self.parameters(ui) {
                        self.send(Command::SetScene(Box::new(self.edited.clone())));
                    }
                });
            });
        egui::Panel::right("statistics")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| {
                if let Some(error) = self.frame.as_ref().and_then(|f| f.error.clone()) {
                    ui.colored_label(egui::Color32::from_rgb(200, 40, 40), error);
                    ui.separator();
                }
                self.statistics(ui);
                ui.separator();
                self.plots(ui);
            });
    }

    fn send(&self, command: Command) {
        // A full channel only drops this click; the next frame can resend.
        if self.live.send(command).is_ok() {
            self.sent.set(self.sent.get() + 1);
        }
    }

    /// Open, reload and save scene files. A file that does not open shows
    /// its error here; the running scene is not touched.
    fn file(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Scene file")
            .default_open(true)
            .show(ui, |ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut self.path)
                        .hint_text("path/to/scene.toml or a mesh")
                        .desired_width(f32::INFINITY),
                )
                .labelled_by(ui.label("scene file path").id);
                ui.horizontal(|ui| {
                    if ui.button("Open").clicked() {
                        self.open(std::path::PathBuf::from(self.path.trim()));
                    }
                    if ui.button("Browse...").clicked() {
                        // The desktop's file dialog (XDG portal); where
                        // there is none it returns at once and the path box
                        // remains.
                        match rfd::FileDialog::new()
                            .add_filter("softgrip scene", &["toml"])
                            .add_filter("tetrahedral or surface mesh", MESH_EXTENSIONS)
                            .pick_file()
                        {
                            Some(path) => self.open(path),
                            None => {
                                self.file_status = Some(
                                    "no file chosen (or no file dialog here): type a path above"
                                        .into(),
                                );
                            }
                        }
                    }
                    let source = self.frame.as_ref().and_then(|f| f.scene.source.clone());
                    if ui
                        .add_enabled(source.is_some(), egui::Button::new("Reload"))
                        .clicked()
                        && let Some(path) = source
                    {
                        self.open(path);
                    }
                    if ui.button("Save as").clicked() {
                        let path = std::path::PathBuf::from(self.path.trim());
                        match std::fs::write(&path, self.edited.to_toml()) {
                            Ok(()) => {
                                self.file_error = None;
                                self.file_status = Some(format!("saved {}", path.display()));
                            }
                            Err(e) => {
                                self.file_error =
                                    Some(format!("could not save {}: {e}", path.display()));
                            }
                        }
                    }
                });
                if let Some(e) = &self.file_error {
                    ui.colored_label(egui::Color32::from_rgb(200, 40, 40), e);
                } else if let Some(status) = &self.file_status {
                    ui.label(status);
                }
                if let Some(f) = &self.frame {
                    for w in f.mesh_warnings.iter() {
                        ui.colored_label(egui::Color32::from_rgb(190, 120, 20), w);
                    }
                }
            });
    }

    /// Loads a scene file, or a mesh file into the current scene, and
    /// hands it to the solver; a file that fails to load leaves the run as
    /// it is (a mesh is read on the solver thread: its error comes back
    /// in the frame).
    pub fn open(&mut self, path: std::path::PathBuf) {
        if path.as_os_str().is_empty() {
            self.file_status = None;
            self.file_error = Some(
                "no path given: type the path of a scene (.toml), a mesh or a recording in the box, then press Open"
                    .into(),
            );
            return;
        }
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if extension
            .as_deref()
            .is_some_and(|e| MESH_EXTENSIONS.contains(&e))
        {
            let mut scene = self.edited.clone();
            let absolute = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
            scene.object.shape = softgrip_core::scene::Shape::Mesh {
                path: absolute,
                scale: 1.0,
                position: glam::DVec3::ZERO,
            };
            self.file_error = None;
            self.file_status = Some(format!(
                "opening mesh {} (errors show on the right)",
                path.display()
            ));
            self.path = path.display().to_string();
            self.send(Command::SetScene(Box::new(scene)));
            return;
        }
        if recording::is_recording_file(&path) {
            self.path = path.display().to_string();
            self.open_recording(path);
            return;
        }
        match Scene::load(&path) {
            Ok(scene) => {
                self.file_error = None;
                self.file_status = Some(format!("opened {}", path.display()));
                self.path = path.display().to_string();
                self.edited = scene.clone();
                self.send(Command::SetScene(Box::new(scene)));
            }
            Err(e) => self.file_error = Some(format!("{e}")),
        }
    }

    /// Opens a lab recording: its scene replaces the run's (as opening
    /// the scene file would) and its replay starts on a background
    /// thread. A recording that does not load shows its error in the
    /// Recording panel and leaves the run and any recording open as they
    /// were.
    pub fn open_recording(&mut self, path: PathBuf) {
        match softgrip_lab::recording::Recording::load(&path) {
            Ok(recording) => {
                self.file_error = None;
                self.edited = recording.scene.clone();
                self.send(Command::SetScene(Box::new(recording.scene.clone())));
                self.recording.open(recording);
            }
            Err(e) => self.recording.failed(&path, e),
        }
    }

    fn recording_action(&mut self, action: recording::Action) {
        match action {
            recording::Action::Open(path) => self.open_recording(path),
            recording::Action::ReplayEdited => self.recording.replay_on(self.edited.clone()),
            recording::Action::Apply(values) => {
                // As the sliders do: the edited scene, checked by the
                // scene file's rules, sent to the solver.
                let mut scene = self.edited.clone();
                for (name, v) in &values {
                    match softgrip_lab::params::set(&scene, name, *v) {
                        Ok(s) => scene = s,
                        Err(e) => {
                            self.recording.error =
                                Some(format!("cannot apply the fitted {name}: {e}"));
                            return;
                        }
                    }
                }
                self.edited = scene.clone();
                self.send(Command::SetScene(Box::new(scene)));
                self.recording.replay_fitted(&values);
            }
        }
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        let running = self
            .frame
            .as_ref()
            .is_some_and(|f| f.run == RunState::Running);
        ui.horizontal(|ui| {
            if running {
                if ui.button("Pause").clicked() {
                    self.send(Command::Pause);
                }
            } else if ui.button("Play").clicked() {
                self.send(Command::Play);
            }
            if ui.button("Step").clicked() {
                self.send(Command::Step(1));
            }
            if ui.button("Reset").clicked() {
                self.send(Command::Reset);
            }
        });
        let mut speed_changed = ui
            .checkbox(&mut self.max_speed, "as fast as it goes")
            .changed();
        ui.add_enabled_ui(!self.max_speed, |ui| {
            speed_changed |= ui
                .add(
                    egui::Slider::new(&mut self.speed, 0.01..=10.0)
                        .logarithmic(true)
                        .text("x real time"),
                )
                .changed();
        });
        if speed_changed {
            self.send(Command::SetSpeed((!self.max_speed).then_some(self.speed)));
        }
    }

    /// The parameter panels; true if the user changed the scene.
    fn parameters(&mut self, ui: &mut egui::Ui) -> bool {
        let mut changed = false;
        let s = &mut self.edited;
        egui::CollapsingHeader::new("Material")
            .default_open(true)
            .show(ui, |ui| {
                changed |= log_slider(ui, &mut s.object.young_modulus, 1e3..=1e8, "E (Pa)");
                changed |= ui
                    .add(egui::Slider::new(&mut s.object.poisson_ratio, 0.0..=0.499).text("nu"))
                    .changed();
                changed |= ui
                    .add(
                        egui::Slider::new(&mut s.object.density, 100.0..=3000.0)
                            .text("density (kg/m3)"),
                    )
                    .changed();
                // Re-meshing is costly: sent when the slider is let go.
                let edge = ui.add(
                    egui::Slider::new(&mut s.object.edge_length, 0.001..=0.02)
                        .logarithmic(true)
                        .text("edge length (m), re-meshes"),
                );
                changed |= edge.drag_stopped() || (edge.changed() && !edge.dragged());
                changed |= log_slider(ui, &mut s.simulation.dt, 1e-5..=1e-2, "dt (s)");
            });
        egui::CollapsingHeader::new("Model")
            .default_open(true)
            .show(ui, |ui| {
                changed |= log_slider(ui, &mut s.model.alpha, 0.0..=1e8, "alpha");
                changed |= optional_slider(ui, &mut s.model.tau_s, 0.0..=1.0, "tau_s", 0.16);
                changed |= optional_slider(ui, &mut s.model.tau_c, 0.0..=0.9, "tau_c", 0.155);
                changed |= ui
                    .add(
                        egui::Slider::new(&mut s.model.damping_ratio, 0.0..=5.0)
                            .text("damping ratio"),
                    )
                    .changed();
                changed |= ui
                    .add(
                        egui::Slider::new(&mut s.model.constraint_iterations, 0..=100)
                            .text("constraint iterations"),
                    )
                    .changed();
                changed |= log_slider(
                    ui,
                    &mut s.model.bulk_modulus,
                    0.0..=1e8,
                    "bulk modulus (Pa)",
                );
                changed |= log_slider(
                    ui,
                    &mut s.model.limit_stiffness,
                    0.0..=1e5,
                    "limit stiffness (x)",
                );
                changed |= log_slider(ui, &mut s.model.stiffening, 0.0..=1e5, "stiffening");
                if s.model.elasticity == Elasticity::NeoHookean {
                    // The elements' two-term Yeoh law (`forces::fem`).
                    changed |= log_slider(
                        ui,
                        &mut s.model.stiffening_cubic,
                        0.0..=1e5,
                        "stiffening, cubic (elements)",
                    );
                    changed |= ui
                        .add(
                            egui::Slider::new(&mut s.model.softening, 0.0..=0.99)
                                .text("early softening (elements)"),
                        )
                        .changed();
                }
                changed |= log_slider(
                    ui,
                    &mut s.model.compression_ratio,
                    0.05..=20.0,
                    "compression / tension stiffness",
                );
                changed |= ui
                    .add(
                        egui::Slider::new(&mut s.model.prony_g, 0.0..=0.95)
                            .text("viscoelastic g (relaxing share)"),
                    )
                    .changed();
                changed |= log_slider(
                    ui,
                    &mut s.model.prony_tau,
                    1e-3..=1e3,
                    "viscoelastic tau (s)",
                );
                ui.horizontal(|ui| {
                    ui.label("bulk pressure");
                    for (value, name) in [
                        (BulkPressure::Element, "per element"),
                        (BulkPressure::Nodal, "per node"),
                    ] {
                        changed |= ui
                            .radio_value(&mut s.model.bulk_pressure, value, name)
                            .changed();
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("elasticity");
                    changed |= ui
                        .radio_value(&mut s.model.elasticity, Elasticity::Springs, "springs")
                        .changed();
                    changed |= ui
                        .radio_value(
                            &mut s.model.elasticity,
                            Elasticity::NeoHookean,
                            "neo-Hookean FEM",
                        )
                        .changed();
                });
                changed |= ui
                    .checkbox(&mut s.model.self_collision, "self-collision")
                    .changed();
            });
        egui::CollapsingHeader::new("Support")
            .default_open(false)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    for (kind, name) in [
                        (SupportKind::FixedBottom, "fixed bottom"),
                        (SupportKind::Table, "table"),
                        (SupportKind::None, "none"),
                    ] {
                        changed |= ui.radio_value(&mut s.support.kind, kind, name).changed();
                    }
                });
                ui.add_enabled_ui(s.support.kind == SupportKind::Table, |ui| {
                    changed |= ui
                        .add(
                            egui::Slider::new(&mut s.support.friction, 0.0..=2.0)
                                .text("table friction"),
                        )
                        .changed();
                });
            });
        egui::CollapsingHeader::new("Fingers")
            .default_open(true)
            .show(ui, |ui| {
                let mut remove = None;
                for (k, f) in s.fingers.iter_mut().enumerate() {
                    ui.push_id(k, |ui| {
                        ui.horizontal(|ui| {
                            ui.label(format!("finger {}", k + 1));
                            if ui.small_button("remove").clicked() {
                                remove = Some(k);
                            }
                        });
                        ui.horizontal(|ui| {
                            changed |= ui
                                .radio_value(&mut f.control, Control::Force, "force")
                                .changed();
                            changed |= ui
                                .radio_value(&mut f.control, Control::Velocity, "velocity")
                                .changed();
                        });
                        ui.horizontal(|ui| {
                            ui.label("moves along");
                            for (a, name) in ["x", "y", "z"].into_iter().enumerate() {
                                changed |= ui
                                    .checkbox(&mut f.free_axes[a], format!("along {name}"))
                                    .changed();
                            }
                        });
                        changed |= ui
                            .add(
                                egui::Slider::new(&mut f.force.z, -50.0..=50.0).text("force z (N)"),
                            )
                            .changed();
                        changed |= ui
                            .add(
                                egui::Slider::new(&mut f.velocity.z, -0.05..=0.05)
                                    .text("velocity z (m/s)"),
                            )
                            .changed();
                        if let FingerShape::Sphere { radius } = &mut f.shape {
                            changed |= ui
                                .add(egui::Slider::new(radius, 0.001..=0.05).text("radius (m)"))
                                .changed();
                        }
                        changed |= ui
                            .add(egui::Slider::new(&mut f.friction, 0.0..=2.0).text("friction"))
                            .changed();
                        changed |= ui
                            .add(
                                egui::Slider::new(&mut f.guide_friction, 0.0..=10.0)
                                    .text("guide friction (N)"),
                            )
                            .changed();
                        changed |= ui
                            .add(
                                egui::Slider::new(&mut f.restitution, 0.0..=1.0)
                                    .text("restitution"),
                            )
                            .changed();
                        changed |= ui
                            .add(egui::Slider::new(&mut f.mass, 0.0..=5.0).text("mass (kg)"))
                            .changed();
                        changed |= ui
                            .add(egui::Slider::new(&mut f.poisson_ratio, 0.0..=0.499).text("nu"))
                            .changed();
                        changed |= log_slider(
                            ui,
                            &mut f.stick_velocity,
                            1e-5..=1e-1,
                            "stick velocity (m/s)",
                        );
                        changed |= log_slider(
                            ui,
                            &mut f.stick_stiffness,
                            1.0..=1e5,
                            "stick stiffness (N/m)",
                        );
                        changed |= log_slider(
                            ui,
                            &mut f.stick_damping,
                            0.01..=1e3,
                            "stick damping (N s/m)",
                        );
                        changed |= log_slider(ui, &mut f.young_modulus, 1e4..=1e11, "E (Pa)");
                        changed |= log_slider(
                            ui,
                            &mut f.contact_stiffness_scale,
                            0.1..=100.0,
                            "contact scale",
                        );
                    });
                    ui.separator();
                }
                if let Some(k) = remove {
                    s.fingers.remove(k);
                    changed = true;
                }
                if ui.button("Add finger").clicked() {
                    s.fingers.push(new_finger(s, self.frame.as_deref()));
                    changed = true;
                }
            });
        egui::CollapsingHeader::new("Display").show(ui, |ui| {
            let st = &mut self.style;
            ui.add(
                egui::Slider::new(&mut st.force_scale, 1e-4..=1e-2)
                    .logarithmic(true)
                    .text("arrow m per N"),
            );
            ui.add(egui::Slider::new(&mut st.finger_opacity, 0.1..=1.0).text("finger opacity"));
            ui.checkbox(&mut st.contacts, "contact points");
            ui.checkbox(&mut st.arrows, "force arrows");
            egui::ComboBox::from_label("colour by")
                .selected_text(st.color_by.map_or("nothing", |f| f.label()))
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut st.color_by, None, "nothing");
                    for field in softgrip_core::fields::Field::ALL {
                        ui.selectable_value(&mut st.color_by, Some(field), field.label());
                    }
                });
            ui.horizontal(|ui| {
                ui.checkbox(&mut st.surface, "surface");
                ui.checkbox(&mut st.wireframe, "springs (wireframe)");
            });
            let mut cut = st.cut.is_some();
            let mut c = st.cut.unwrap_or(render::Cut {
                axis: 1,
                fraction: 0.5,
                flip: false,
            });
            ui.horizontal(|ui| {
                ui.checkbox(&mut cut, "cut-away along");
                for (axis, name) in ["x", "y", "z"].iter().enumerate() {
                    ui.radio_value(&mut c.axis, axis, *name);
                }
                ui.checkbox(&mut c.flip, "flip");
            });
            ui.add_enabled(
                cut,
                egui::Slider::new(&mut c.fraction, 0.0..=1.0).text("cut at (fraction)"),
            );
            st.cut = cut.then_some(c);
            ui.horizontal(|ui| {
                if ui
                    .button("reset view")
                    .on_hover_text("back to the opening view, framing the object")
                    .clicked()
                {
                    self.view_request = Some(View::Iso);
                }
                for (name, view) in [
                    ("front", View::Front),
                    ("side", View::Side),
                    ("top", View::Top),
                    ("iso", View::Iso),
                ] {
                    if ui.button(name).clicked() {
                        self.view_request = Some(view);
                    }
                }
            });
        });
        changed
    }

    /// Finger depth and contact force over time, from the solver's history.
    fn plots(&self, ui: &mut egui::Ui) {
        let Some(f) = &self.frame else {
            return;
        };
        let series = |pick: fn(&softgrip_core::live::FingerSample) -> f64| {
            f.history
                .iter()
                .map(|samples| {
                    samples
                        .iter()
                        .map(|s| [s.time, pick(s)])
                        .collect::<Vec<[f64; 2]>>()
                })
                .collect::<Vec<_>>()
        };
        for (title, unit, lines) in [
            ("depth", "mm", series(|s| s.depth * 1e3)),
            ("normal force", "N", series(|s| s.normal_force)),
        ] {
            ui.label(format!("{title} ({unit})"));
            // Zero and some room above the largest value: a steady line
            // would otherwise sit on the frame with no value beside it.
            let top = lines
                .iter()
                .flatten()
                .map(|p| p[1])
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max);
            grid::with_grids(egui_plot::Plot::new(title))
                .height(140.0)
                .include_y(0.0)
                .include_y(top * 1.2)
                .x_axis_label("time (s)")
                .show(ui, |plot| {
                    for (k, points) in lines.into_iter().enumerate() {
                        plot.line(egui_plot::Line::new(format!("finger {}", k + 1), points));
                    }
                });
        }
    }

    fn statistics(&self, ui: &mut egui::Ui) {
        let Some(f) = &self.frame else {
            ui.label("starting...");
            return;
        };
        let st = &f.state.stats;
        egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.monospace(value);
                ui.end_row();
            };
            row("state", format!("{:?}", f.run));
            row("UI frame", format!("{:.1} ms", 1e3 * self.frame_time));
            row("time", format!("{:.3} s", f.state.time));
            row("steps/s", format!("{:.0}", f.steps_per_second));
            row("x real time", format!("{:.2}", f.realtime_factor));
            row("CG iterations", format!("{}", st.cg_iterations));
            row("CG residual", format!("{:.1e}", st.cg_residual));
            row("volume error", format!("{:.2e}", st.volume_error));
            row("energy", format!("{:.4e} J", st.energy));
            row("limit violation", format!("{:.1e}", st.limit_violation));
            row("contacts", format!("{}", st.contacts));
            for (k, fs) in f.state.fingers.iter().enumerate() {
                let depth = f
                    .history
                    .get(k)
                    .and_then(|h| h.last())
                    .map_or(0.0, |s| s.depth);
                row(
                    &format!("finger {}", k + 1),
                    format!(
                        "Fn {:.3} N, Ft {:.3} N, depth {:.3} mm",
                        fs.normal_force,
                        fs.tangential_force.length(),
                        depth * 1e3
                    ),
                );
            }
        });
    }
}

/// A new force-controlled 5 mm sphere finger just above the object's top,
/// a quarter of the object's width off its centre (away from a finger
/// already at the centre), carrying 1 N.
fn new_finger(scene: &Scene, frame: Option<&Frame>) -> softgrip_core::scene::Finger {
    let mut finger = Scene::thesis().fingers[0].clone();
    let radius = 0.005;
    finger.shape = FingerShape::Sphere { radius };
    finger.mass = 0.0;
    finger.force = glam::DVec3::new(0.0, 0.0, -1.0);
    finger.contact_stiffness_scale = 1.0;
    let positions = frame
        .filter(|f| !f.state.positions.is_empty())
        .map(|f| f.state.positions.clone())
        .or_else(|| {
            softgrip_core::model::Model::mesh_of(scene)
                .ok()
                .map(|m| m.nodes)
        });
    let (lo, hi) = positions
        .map(|p| softgrip_core::mesh::bounds_of(&p))
        .unwrap_or((glam::DVec3::splat(-0.01), glam::DVec3::splat(0.01)));
    let centre = 0.5 * (lo + hi);
    finger.position = glam::DVec3::new(
        centre.x + 0.25 * (hi.x - lo.x),
        centre.y,
        hi.z + radius + 0.0005,
    );
    finger
}

fn log_slider(
    ui: &mut egui::Ui,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
) -> bool {
    ui.add(egui::Slider::new(value, range).logarithmic(true).text(text))
        .changed()
}

/// A limit that may be off (`None`: the key omitted).
fn optional_slider(
    ui: &mut egui::Ui,
    value: &mut Option<f64>,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
    default: f64,
) -> bool {
    let mut on = value.is_some();
    let mut changed = false;
    ui.horizontal(|ui| {
        changed |= ui
            .checkbox(&mut on, "on")
            .on_hover_text(format!("{text}: off means no limit"))
            .changed();
        let mut v = value.unwrap_or(default);
        ui.add_enabled_ui(on, |ui| {
            changed |= ui
                .add(egui::Slider::new(&mut v, range).text(text))
                .changed();
        });
        *value = on.then_some(v);
    });
    changed
}

impl Viewer {
    /// Draws the 3-D view into the panel; drag orbits, right-drag pans,
    /// scroll zooms.
    fn view3d(&mut self, ui: &mut egui::Ui, frame: &eframe::Frame) {
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::drag());
        let Some(f) = self.panels.frame.clone() else {
            return;
        };
        // A recording shown replaces the live frame (and is not dragged).
        let overlay = self.panels.recording.overlay();
        let meshing = f.run == RunState::Meshing && overlay.is_none();
        let (model, state) = match (&overlay, &f.model) {
            (Some(o), _) => (&o.model, &o.state),
            (None, Some(m)) => (m, &f.state),
            (None, None) => {
                ui.painter().text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    "building the model...",
                    Default::default(),
                    egui::Color32::GRAY,
                );
                return;
            }
        };
        let aspect = rect.width() / rect.height().max(1.0);
        if let Some(view) = self.panels.view_request.take() {
            self.view.camera = Some(render::frame_camera_aspect(model, state, view, aspect));
        }
        let camera = self
            .view
            .camera
            .get_or_insert_with(|| render::frame_camera_aspect(model, state, View::Iso, aspect));
        let Some(rs) = frame.wgpu_render_state() else {
            return;
        };
        let ppp = ui.ctx().pixels_per_point();
        let (w, h) = (
            (rect.width() * ppp).round().max(16.0) as u32,
            (rect.height() * ppp).round().max(16.0) as u32,
        );
        let ray_at = |camera: &Camera, pos: egui::Pos2| {
            camera.ray((pos.x - rect.min.x) * ppp, (pos.y - rect.min.y) * ppp, w, h)
        };
        let alt = ui.input(|i| i.modifiers.alt);
        if response.drag_started_by(egui::PointerButton::Primary)
            && let Some(pos) = response.interact_pointer_pos()
        {
            let ray = ray_at(camera, pos);
            let facing = camera.forward();
            let thickness = render::geometry::plate_thickness(model);
            self.view.drag = match (!alt && overlay.is_none())
                .then(|| pick::pick(model, state, &ray, thickness))
                .flatten()
            {
                Some(pick::Picked::Finger { index, point }) => Drag::Finger {
                    index,
                    grabbed: point,
                    centre: state.fingers[index].position,
                    facing,
                    last: None,
                },
                Some(pick::Picked::Object {
                    facet,
                    weights,
                    point,
                }) => Drag::Object {
                    facet,
                    weights,
                    grabbed: point,
                    facing,
                    last: None,
                },
                None => Drag::Orbit,
            };
        }
        let orbit = (response.dragged_by(egui::PointerButton::Primary)
            && self.view.drag == Drag::Orbit)
            || response.dragged_by(egui::PointerButton::Middle);
        if orbit {
            let d = response.drag_delta();
            camera.yaw -= d.x * 0.008;
            camera.pitch = (camera.pitch + d.y * 0.008).clamp(-1.55, 1.55);
        }
        if response.dragged_by(egui::PointerButton::Primary)
            && let Some(pos) = response.interact_pointer_pos()
        {
            let ray = ray_at(camera, pos);
            match &mut self.view.drag {
                Drag::Finger {
                    index,
                    grabbed,
                    centre,
                    facing,
                    last,
                } => {
                    let target =
                        pick::finger_target(model, *index, *centre, *grabbed, *facing, &ray);
                    if target.is_some() && target != *last {
                        *last = target;
                        self.panels.send(Command::Hold {
                            finger: *index,
                            at: target,
                        });
                    }
                }
                Drag::Object {
                    facet,
                    weights,
                    grabbed,
                    facing,
                    last,
                } => {
                    let target = pick::on_plane(&ray, *grabbed, *facing);
                    if let Some(target) = target
                        && Some(target) != *last
                    {
                        *last = Some(target);
                        self.panels.send(Command::Pull(Some(Pull {
                            facet: *facet,
                            weights: *weights,
                            target,
                            stiffness: Pull::default_stiffness(model),
                        })));
                    }
                }
                Drag::None | Drag::Orbit => {}
            }
        }
        if response.drag_stopped() || (!response.dragged() && self.view.drag != Drag::None) {
            match self.view.drag {
                Drag::Finger { index, .. } => self.panels.send(Command::Hold {
                    finger: index,
                    at: None,
                }),
                Drag::Object { .. } => self.panels.send(Command::Pull(None)),
                Drag::None | Drag::Orbit => {}
            }
            self.view.drag = Drag::None;
        }
        if response.dragged_by(egui::PointerButton::Secondary) {
            let d = response.drag_delta();
            let eye = camera.eye();
            let forward = (camera.target - eye).normalize_or_zero();
            let right = forward.cross(Vec3::Z).normalize_or_zero();
            let up = right.cross(forward);
            let per_pixel = camera.distance * 0.0015;
            camera.target += (-d.x * right + d.y * up) * per_pixel;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            camera.distance *= (-scroll * 0.002).exp();
        }
        self.view_rect = Some((rect, w, h));
        if (w, h) != (self.view.target.width, self.view.target.height) {
            self.view.target = Target::new(&rs.device, w, h);
            rs.renderer.write().update_egui_texture_from_wgpu_texture(
                &rs.device,
                &self.view.target.view,
                wgpu::FilterMode::Linear,
                self.view.texture,
            );
        }
        let live = if overlay.is_some() {
            0
        } else {
            Arc::as_ptr(&f) as usize
        };
        let key = (
            live,
            *camera,
            self.panels.style,
            w,
            h,
            overlay.as_ref().map(|o| o.key),
        );
        if self.view.drawn != Some(key) {
            let mut drawing = render::geometry::build(model, state, &self.panels.style);
            if let Some(o) = &overlay {
                render::markers::add_markers(&mut drawing, model, &o.markers, o.exaggerate);
            }
            let mut encoder = rs
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("3-D view"),
                });
            self.view.pipeline.draw(
                &rs.device,
                &rs.queue,
                &mut encoder,
                &self.view.target,
                &drawing,
                camera,
            );
            rs.queue.submit([encoder.finish()]);
            self.view.drawn = Some(key);
            self.view.legend = drawing.legend;
        }
        ui.painter().image(
            self.view.texture,
            rect,
            egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
            egui::Color32::WHITE,
        );
        if let Some(legend) = &self.view.legend {
            draw_legend(ui, rect, legend);
        }
        if let Some(o) = &overlay {
            draw_recording_caption(ui, rect, &o.caption);
        }
        let hint = if overlay.is_some() {
            "showing the recording (untick \"show recording\" for the live run) | drag: orbit | right-drag: pan | scroll: zoom".to_string()
        } else if f.run == RunState::Paused && self.view.drag != Drag::None {
            "paused: press Play to see the drag act".to_string()
        } else if let Drag::Finger { index, .. } = self.view.drag
            && let Some(locked) = f
                .scene
                .fingers
                .get(index)
                .and_then(|s| locked_axes_hint(index, s.free_axes))
        {
            locked
        } else {
            "drag: finger moves, object is pulled, elsewhere orbits | right-drag: pan | scroll: zoom".to_string()
        };
        // Wrapped to the view's width: a narrow view keeps the whole hint.
        let galley = ui.painter().layout(
            hint,
            egui::FontId::proportional(12.0),
            egui::Color32::from_gray(90),
            (rect.width() - 16.0).max(40.0),
        );
        let at = rect.left_bottom() + egui::vec2(8.0, -8.0 - galley.size().y);
        ui.painter()
            .galley(at, galley, egui::Color32::from_gray(90));
        if meshing {
            // The old model stays drawn under a spinner, with the new
            // edge length and how long it has taken so far.
            let since = *self
                .view
                .meshing_since
                .get_or_insert_with(std::time::Instant::now);
            let spinner = egui::Rect::from_center_size(rect.center(), egui::vec2(40.0, 40.0));
            ui.put(spinner, egui::Spinner::new().size(40.0));
            ui.painter().text(
                rect.center() + egui::vec2(0.0, 36.0),
                egui::Align2::CENTER_TOP,
                format!(
                    "re-meshing at {:.2} mm edge length... {:.1} s",
                    1e3 * f.scene.object.edge_length,
                    since.elapsed().as_secs_f64()
                ),
                egui::FontId::proportional(18.0),
                egui::Color32::DARK_GRAY,
            );
        } else {
            self.view.meshing_since = None;
        }
    }
}

/// What the 3-D view shows while a recording is shown, and its colours'
/// key, at the view's top left.
fn draw_recording_caption(ui: &egui::Ui, view: egui::Rect, caption: &str) {
    let painter = ui.painter();
    let color = |c: [f32; 4]| egui::Rgba::from_rgb(c[0], c[1], c[2]);
    let top = view.left_top() + egui::vec2(10.0, 10.0);
    painter.text(
        top,
        egui::Align2::LEFT_TOP,
        caption,
        egui::FontId::proportional(14.0),
        egui::Color32::from_gray(30),
    );
    let mut at = top + egui::vec2(6.0, 28.0);
    for (c, text) in [
        (render::markers::RECORDED, "recorded"),
        (render::markers::SIMULATED, "simulated"),
        (render::markers::RESIDUAL, "residual"),
    ] {
        painter.circle_filled(at, 5.0, color(c));
        let label = painter.text(
            at + egui::vec2(10.0, 0.0),
            egui::Align2::LEFT_CENTER,
            text,
            egui::FontId::proportional(13.0),
            egui::Color32::from_gray(40),
        );
        at.x = label.right() + 18.0;
    }
}

/// The colour map's bar at the right of the 3-D view, with its range and
/// the field's name and unit.
fn draw_legend(ui: &egui::Ui, view: egui::Rect, legend: &render::Legend) {
    const STEPS: usize = 48;
    let painter = ui.painter();
    let height = (view.height() * 0.5).clamp(80.0, 320.0);
    let bar = egui::Rect::from_min_size(
        egui::pos2(view.right() - 90.0, view.top() + 40.0),
        egui::vec2(16.0, height),
    );
    for k in 0..STEPS {
        // Top is the maximum.
        let t = 1.0 - (k as f64 + 0.5) / STEPS as f64;
        let [r, g, b, _] = legend.color(legend.min + t * (legend.max - legend.min));
        let y0 = bar.top() + bar.height() * k as f32 / STEPS as f32;
        let y1 = bar.top() + bar.height() * (k + 1) as f32 / STEPS as f32;
        painter.rect_filled(
            egui::Rect::from_x_y_ranges(bar.x_range(), y0..=y1 + 0.5),
            0.0,
            egui::Rgba::from_rgb(r, g, b),
        );
    }
    painter.rect_stroke(
        bar,
        0.0,
        egui::Stroke::new(1.0, egui::Color32::from_gray(60)),
        egui::StrokeKind::Outside,
    );
    let field = legend.field;
    let k = field.display_scale();
    let text = |y: f32, value: f64| {
        painter.text(
            egui::pos2(bar.right() + 4.0, y),
            egui::Align2::LEFT_CENTER,
            format!("{:.3}", value * k),
            egui::FontId::monospace(11.0),
            egui::Color32::from_gray(40),
        );
    };
    text(bar.top(), legend.max);
    text(bar.center().y, 0.5 * (legend.min + legend.max));
    text(bar.bottom(), legend.min);
    painter.text(
        egui::pos2(bar.right() + 4.0, bar.top() - 18.0),
        egui::Align2::RIGHT_BOTTOM,
        format!("{} ({})", field.label(), field.unit()),
        egui::FontId::proportional(12.0),
        egui::Color32::from_gray(40),
    );
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
        if running || self.view.drag != Drag::None {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(16));
        } else if self.panels.recording.busy() {
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
