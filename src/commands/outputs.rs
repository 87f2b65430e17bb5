//! Output paths checked before the work they are to hold: writable, and not one of the
//! command's inputs (`check X.toml --json X.toml` once wrote JSON over the scene; `fit
//! --scene-out` to a directory that does not exist failed after the whole fit).

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

/// A command's outputs, checked against its inputs.
#[derive(Default)]
pub struct Outputs {
    inputs: Vec<PathBuf>,
    files: Vec<(String, PathBuf)>,
    dirs: Vec<(String, PathBuf)>,
}

impl Outputs {
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// A file the command reads.
    pub fn input(mut self, path: &Path) -> Outputs {
        self.inputs.push(path.to_path_buf());
        self
    }

    /// A scene's file and the mesh file it names.
    pub fn scene(mut self, scene: &softgrip_core::Scene) -> Outputs {
        if let Some(p) = &scene.source {
            self.inputs.push(p.clone());
        }
        if let softgrip_core::scene::Shape::Mesh { path, .. } = &scene.object.shape {
            self.inputs.push(path.clone());
        }
        self
    }

    /// A recording and the scene and samples it names.
    pub fn recording(self, r: &softgrip_lab::recording::Recording) -> Outputs {
        self.input(&r.source)
            .input(&r.scene_path)
            .input(&r.samples_path)
    }

    /// A file the command writes, named by its option (`--json`).
    pub fn file(mut self, option: &str, path: Option<&Path>) -> Outputs {
        if let Some(p) = path {
            self.files.push((option.to_string(), p.to_path_buf()));
        }
        self
    }

    /// A directory the command writes into (made if missing).
    pub fn dir(mut self, option: &str, path: Option<&Path>) -> Outputs {
        if let Some(p) = path {
            self.dirs.push((option.to_string(), p.to_path_buf()));
        }
        self
    }

    /// Refuses an output that is an input or cannot be written, before any work. Directories
    /// first (made where missing), so that a file in one is checked where it will be.
    pub fn check(self) -> Result<()> {
        let inputs: Vec<PathBuf> = self.inputs.iter().filter_map(|p| resolved(p)).collect();
        let is_input = |p: &Path| resolved(p).is_some_and(|r| inputs.contains(&r));
        for (option, path) in &self.dirs {
            if inputs
                .iter()
                .any(|i| resolved(path).is_some_and(|d| *i == d))
            {
                bail!(
                    "{option} {}: that is one of this command's inputs; give a directory",
                    path.display()
                );
            }
            writable_dir(option, path)?;
        }
        for (option, path) in &self.files {
            if is_input(path) {
                bail!(
                    "{option} {}: that is one of this command's inputs, and writing would replace it; give another path",
                    path.display()
                );
            }
            writable_file(option, path)?;
        }
        Ok(())
    }
}

/// `path` made absolute with its links resolved, for a file that may not exist yet: its
/// directory resolved and its name appended.
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.canonicalize().ok()?,
        _ => std::env::current_dir().ok()?,
    };
    Some(dir.join(name))
}

fn writable_file(option: &str, path: &Path) -> Result<()> {
    let fail = |why: String| -> Result<()> {
        bail!(
            "{option} {}: cannot be written ({why}); give a path in a directory you can write, before the work starts",
            path.display()
        )
    };
    if path.is_dir() {
        return fail("it is a directory; give a file name".into());
    }
    if path.exists() {
        // Opened for appending: the permission is checked, the content left alone.
        return match std::fs::OpenOptions::new().append(true).open(path) {
            Ok(_) => Ok(()),
            Err(e) => fail(e.to_string()),
        };
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return fail(format!("no directory {}", dir.display()));
    }
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(path);
            Ok(())
        }
        Err(e) => fail(e.to_string()),
    }
}

fn writable_dir(option: &str, path: &Path) -> Result<()> {
    let fail = |why: String| -> Result<()> {
        bail!(
            "{option} {}: cannot be written ({why}); give a directory you can write",
            path.display()
        )
    };
    if path.exists() && !path.is_dir() {
        return fail("it is a file, not a directory".into());
    }
    if let Err(e) = std::fs::create_dir_all(path) {
        return fail(e.to_string());
    }
    let probe = path.join(format!(".softgrip-write-check-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => fail(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("softgrip-outputs-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp dir");
        d
    }

    #[test]
    fn an_output_that_is_an_input_is_refused_and_left_alone() {
        let d = temp("input");
        let scene = d.join("X.toml");
        std::fs::write(&scene, "[object]\n").expect("write");
        // The same file by another spelling.
        let other = d.join(".").join("X.toml");
        let e = Outputs::new()
            .input(&scene)
            .file("--json", Some(&other))
            .check()
            .expect_err("the scene as --json")
            .to_string();
        assert!(e.contains("--json") && e.contains("inputs"), "{e}");
        assert_eq!(std::fs::read_to_string(&scene).expect("read"), "[object]\n");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn an_output_in_a_missing_directory_is_refused_and_a_new_file_is_not_left_behind() {
        let d = temp("missing");
        let e = Outputs::new()
            .file("--scene-out", Some(&d.join("no/such/dir/fit.toml")))
            .check()
            .expect_err("no directory")
            .to_string();
        assert!(
            e.contains("--scene-out") && e.contains("no directory"),
            "{e}"
        );
        let fine = d.join("fit.toml");
        Outputs::new()
            .file("--scene-out", Some(&fine))
            .check()
            .expect("a writable path");
        assert!(!fine.exists(), "the check leaves no file behind");
        let _ = std::fs::remove_dir_all(&d);
    }
}
