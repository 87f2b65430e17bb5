//! The entry points: the built-in scene, a scene file, scene text. Each parses the text into the
//! raw layer and resolves it.

use std::path::Path;

use super::defaults::THESIS_SCENE;
use super::error::{SceneError, describe_toml_error};
use super::raw::RawScene;
use super::resolve::resolve;
use super::{Scene, Shape};

impl Scene {
    /// The built-in thesis scene (see [`THESIS_SCENE`]).
    pub fn thesis() -> Scene {
        match Scene::from_toml_str(THESIS_SCENE, "<built-in thesis scene>") {
            Ok(scene) => scene,
            // The built-in text is checked by a test; this cannot happen in a release.
            Err(e) => panic!("built-in thesis scene is invalid: {e}"),
        }
    }

    /// Reads and resolves a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let file = path.display().to_string();
        let read_err = |source| SceneError::Read {
            path: path.to_path_buf(),
            source,
        };
        // A scene is a few KB of TOML: a huge file is the wrong file, not one to read whole; the
        // bytes read bound it, not the size it reports (`/dev/zero` reports none).
        let bytes = crate::files::read_at_most(path, MAX_SCENE_BYTES).map_err(|e| match e {
            crate::files::ReadError::Io(source) => read_err(source),
            crate::files::ReadError::TooLarge { .. } => SceneError::Invalid {
                file: file.clone(),
                message: format!(
                    "more than {} MB: a scene is a few KB of TOML; is this the right file?",
                    MAX_SCENE_BYTES / 1_000_000
                ),
            },
        })?;
        if let Some(kind) = crate::files::kind_of(&bytes) {
            return Err(SceneError::Invalid {
                file,
                message: format!(
                    "this is {kind}, not a scene: a scene is TOML (`softgrip scene` prints one to start from){}",
                    if kind.contains("mesh") || kind.contains("surface") {
                        "; a mesh is named in a scene's [object] as shape = \"mesh\", path = \"...\" (docs/meshes.md)"
                    } else {
                        ""
                    }
                ),
            });
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
            SceneError::Syntax {
                file: file.clone(),
                message: format!(
                    "line {line}: not UTF-8 text (byte {at}): a scene is a TOML text file; save it as UTF-8"
                ),
            }
        })?;
        let mut scene = Scene::from_toml_str(&text, &path.display().to_string())?;
        scene.source = Some(path.to_path_buf());
        if let Shape::Mesh { path: mesh, .. } = &mut scene.object.shape
            && mesh.is_relative()
            && let Some(dir) = path.parent()
        {
            *mesh = dir.join(&*mesh);
        }
        Ok(scene)
    }

    /// Parses and resolves scene text; `file` names it in errors.
    pub fn from_toml_str(text: &str, file: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError::Syntax {
            file: file.to_string(),
            message: describe_toml_error(text, &e),
        })?;
        resolve(raw, text, file)
    }
}

/// The largest scene file read (bytes).
pub const MAX_SCENE_BYTES: u64 = 10_000_000;
