//! The Scene file section and what opening a file does: a scene replaces the run's, a mesh
//! becomes the current scene's object (read on the solver thread, its error comes back in the
//! frame), a recording opens in the Recording panel. A file that fails leaves the run as it is.

use std::path::PathBuf;

use eframe::egui;
use softgrip_core::live::Command;
use softgrip_core::scene::Scene;

use crate::Panels;
use crate::recording;
use crate::widgets::ERROR_RED;

/// Files the Open button takes as a mesh for the current scene (the
/// scene spec's `shape = "mesh"` formats).
pub const MESH_EXTENSIONS: &[&str] = &["msh", "node", "ele", "vtk", "vtu", "stl", "obj"];

impl Panels {
    /// Open, reload and save scene files. A file that does not open shows
    /// its error here; the running scene is not touched.
    pub(crate) fn scene_file(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Scene file")
            .default_open(true)
            .show(ui, |ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut self.path)
                        .hint_text("path/to/scene.toml or a mesh")
                        .desired_width(f32::INFINITY),
                )
                .labelled_by(ui.label("scene file path").id);
                ui.horizontal(|ui| self.file_buttons(ui));
                if let Some(e) = &self.file_error {
                    ui.colored_label(ERROR_RED, e);
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

    /// Open, Browse..., Reload and Save as.
    fn file_buttons(&mut self, ui: &mut egui::Ui) {
        if ui.button("Open").clicked() {
            self.open(PathBuf::from(self.path.trim()));
        }
        if ui.button("Browse...").clicked() {
            // The desktop's file dialog (XDG portal); where there is none it
            // returns at once and the path box remains.
            match rfd::FileDialog::new()
                .add_filter("softgrip scene", &["toml"])
                .add_filter("tetrahedral or surface mesh", MESH_EXTENSIONS)
                .pick_file()
            {
                Some(path) => self.open(path),
                None => {
                    self.file_status =
                        Some("no file chosen (or no file dialog here): type a path above".into());
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
            let path = PathBuf::from(self.path.trim());
            match std::fs::write(&path, self.edited.to_toml_for(&path)) {
                Ok(()) => {
                    self.file_error = None;
                    self.file_status = Some(format!("saved {}", path.display()));
                }
                Err(e) => {
                    self.file_error = Some(format!("could not save {}: {e}", path.display()));
                }
            }
        }
    }

    /// Loads a scene file, or a mesh file into the current scene, and
    /// hands it to the solver; a file that fails to load leaves the run as
    /// it is (a mesh is read on the solver thread: its error comes back
    /// in the frame).
    pub fn open(&mut self, path: PathBuf) {
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
}
