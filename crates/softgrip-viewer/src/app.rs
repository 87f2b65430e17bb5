//! Opening the viewer's window: eframe with its wgpu renderer, the app built on its device, and
//! what `softgrip view` asks at start (paused, a recording opened, `--measure`).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use eframe::egui;
use softgrip_core::live::Command;
use softgrip_core::scene::Scene;

use crate::measure::Measure;
use crate::view3d::View3d;
use crate::{Panels, Viewer};

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
                app.measure = Some(Measure::new(span));
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow!("the viewer could not start: {e}"))
}

impl Viewer {
    /// Builds the app on eframe's wgpu device and starts the solver,
    /// playing.
    pub fn new(cc: &eframe::CreationContext<'_>, scene: Scene) -> Result<Viewer> {
        let view = View3d::new(cc)?;
        let panels = Panels::start(scene)?;
        // The viewer opens running, in real time.
        panels.send(Command::Play);
        Ok(Viewer {
            panels,
            view,
            measure: None,
        })
    }
}
