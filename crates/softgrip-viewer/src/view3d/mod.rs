//! The 3-D view in the central panel: the live frame, or the recording shown, drawn by
//! `crate::render` on eframe's wgpu device into a texture, again only when what it shows has
//! changed. Its stages each frame: the camera (a preset view asked for, or the one framing the
//! object), the mouse (`input`: drag a finger, pull the object, orbit, pan, zoom), the drawing,
//! and what is painted over it (`labels`).

mod input;
mod labels;

use std::sync::Arc;

use anyhow::{Result, anyhow};
use eframe::egui;
use glam::DVec3;

use crate::recording::{OverlayKey, RecordingPanel};
use crate::render::gpu::{Pipeline, Target};
use crate::render::{self, Camera, Legend, Style, View};
use input::{Drag, Drawn, Pixels};
use softgrip_core::live::{Command, Frame, RunState};

/// What a drawing of the 3-D view shows: the live frame (0 while a
/// recording is shown), camera, style, size and the recording's sample.
type DrawnKey = (usize, Camera, Style, u32, u32, Option<OverlayKey>);

/// The view's renderer, camera and the drag under way.
pub(crate) struct View3d {
    pipeline: Pipeline,
    target: Target,
    texture: egui::TextureId,
    camera: Option<Camera>,
    drag: Drag,
    /// What the texture shows (frame, camera, style, size), so an
    /// unchanged view is not drawn again, and the legend drawn with it.
    drawn: Option<DrawnKey>,
    legend: Option<Legend>,
    /// When the solver started re-meshing, for the overlay's clock.
    meshing_since: Option<std::time::Instant>,
    /// Where the view was last drawn (egui points) and its pixel size.
    rect: Option<(egui::Rect, u32, u32)>,
}

/// What the 3-D view takes from the panels each frame.
pub(crate) struct FromPanels<'a> {
    /// The solver's latest frame.
    pub(crate) frame: Option<Arc<Frame>>,
    /// Its overlay, while shown, replaces the live frame ...
    pub(crate) recording: &'a RecordingPanel,
    /// ... and else the Grasp panel's squeeze, while shown.
    pub(crate) grasp: &'a crate::grasp::GraspPanel,
    pub(crate) style: &'a Style,
    /// A preset view pressed; taken once there is a model to frame.
    pub(crate) view_request: &'a mut Option<View>,
    /// Where a drag's commands go.
    pub(crate) send: &'a dyn Fn(Command),
}

impl View3d {
    /// The renderer on eframe's wgpu device.
    pub(crate) fn new(cc: &eframe::CreationContext<'_>) -> Result<View3d> {
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
        Ok(View3d {
            pipeline,
            target,
            texture,
            camera: None,
            drag: Drag::None,
            drawn: None,
            legend: None,
            meshing_since: None,
            rect: None,
        })
    }

    /// The window pixel (egui points) where `world` appears as last drawn.
    pub(crate) fn screen_position(&self, world: DVec3) -> Option<egui::Pos2> {
        let (rect, w, h) = self.rect?;
        let camera = self.camera.as_ref()?;
        let (x, y) = camera.project(world.as_vec3(), w, h)?;
        Some(egui::pos2(
            rect.min.x + x * rect.width() / w as f32,
            rect.min.y + y * rect.height() / h as f32,
        ))
    }

    /// The colour map's legend as last drawn.
    pub(crate) fn legend(&self) -> Option<Legend> {
        self.legend
    }

    /// A drag is under way (the UI redraws for it).
    pub(crate) fn dragging(&self) -> bool {
        self.drag != Drag::None
    }

    /// The legend, the recording's caption, the hint and the meshing clock over the view.
    fn draw_labels(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        f: &Frame,
        overlay: Option<&crate::recording::Overlay>,
        meshing: bool,
    ) {
        if let Some(legend) = &self.legend {
            labels::draw_legend(ui, rect, legend);
        }
        if let Some(o) = overlay {
            labels::draw_recording_caption(ui, rect, &o.caption);
        }
        labels::draw_hint(ui, rect, f, overlay.is_some(), self.drag);
        if meshing {
            let since = *self
                .meshing_since
                .get_or_insert_with(std::time::Instant::now);
            labels::draw_meshing(ui, rect, f, since);
        } else {
            self.meshing_since = None;
        }
    }

    /// Draws `model` in `state` into the view's texture, unless what it shows is unchanged.
    #[allow(clippy::too_many_arguments)]
    fn draw(
        &mut self,
        rs: &eframe::egui_wgpu::RenderState,
        f: &Arc<Frame>,
        camera: Camera,
        style: &Style,
        (w, h): (u32, u32),
        overlay: Option<&crate::recording::Overlay>,
        (model, state): (&softgrip_core::model::Model, &softgrip_core::state::State),
    ) {
        let live = if overlay.is_some() {
            0
        } else {
            Arc::as_ptr(f) as usize
        };
        let key = (live, camera, *style, w, h, overlay.as_ref().map(|o| o.key));
        if self.drawn != Some(key) {
            let mut drawing = render::geometry::build(model, state, style);
            if let Some(o) = &overlay {
                render::markers::add_markers(&mut drawing, model, &o.markers, o.exaggerate);
            }
            let mut encoder = rs
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("3-D view"),
                });
            self.pipeline.draw(
                &rs.device,
                &rs.queue,
                &mut encoder,
                &self.target,
                &drawing,
                &camera,
            );
            rs.queue.submit([encoder.finish()]);
            self.drawn = Some(key);
            self.legend = drawing.legend;
        }
    }

    /// Draws the 3-D view into the panel; drag orbits, right-drag pans,
    /// scroll zooms.
    pub(crate) fn ui(&mut self, ui: &mut egui::Ui, frame: &eframe::Frame, panels: FromPanels<'_>) {
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::drag());
        let Some(f) = panels.frame else {
            return;
        };
        // A recording shown replaces the live frame (and is not dragged).
        let overlay = panels
            .recording
            .overlay()
            .or_else(|| panels.grasp.overlay());
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
        if let Some(view) = panels.view_request.take() {
            self.camera = Some(render::frame_camera_aspect(model, state, view, aspect));
        }
        let camera = self
            .camera
            .get_or_insert_with(|| render::frame_camera_aspect(model, state, View::Iso, aspect));
        let Some(rs) = frame.wgpu_render_state() else {
            return;
        };
        let pixels = Pixels::of(ui, rect);
        let (w, h) = (pixels.width, pixels.height);
        let drawn = Drawn {
            model,
            state,
            pickable: overlay.is_none(),
        };
        input::handle(
            ui,
            &response,
            &pixels,
            camera,
            &mut self.drag,
            drawn,
            panels.send,
        );
        self.rect = Some((rect, w, h));
        fit_target(&mut self.target, rs, self.texture, (w, h));
        let camera = *camera;
        self.draw(
            rs,
            &f,
            camera,
            panels.style,
            (w, h),
            overlay.as_ref(),
            (model, state),
        );
        ui.painter().image(
            self.texture,
            rect,
            egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
            egui::Color32::WHITE,
        );
        self.draw_labels(ui, rect, &f, overlay.as_ref(), meshing);
    }
}

/// Makes `target` `w` x `h` pixels where it is not, and points the view's egui `texture` at the
/// new one.
fn fit_target(
    target: &mut Target,
    rs: &eframe::egui_wgpu::RenderState,
    texture: egui::TextureId,
    (w, h): (u32, u32),
) {
    if (w, h) != (target.width, target.height) {
        *target = Target::new(&rs.device, w, h);
        rs.renderer.write().update_egui_texture_from_wgpu_texture(
            &rs.device,
            &target.view,
            wgpu::FilterMode::Linear,
            texture,
        );
    }
}
