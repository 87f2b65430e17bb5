//! What the tests share: running the `softgrip` binary, the shipped files'
//! paths, scratch directories and the JSON a command wrote.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary run with `args`, its output kept.
pub fn softgrip(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softgrip"))
        .args(args)
        .output()
        .expect("softgrip runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A shipped scene, `assets/scenes/NAME`.
pub fn scene(name: &str) -> String {
    format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A shipped recording's path below `assets/recordings/`.
pub fn recording(rel: &str) -> String {
    format!("{}/assets/recordings/{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// One of the core crate's test meshes.
pub fn mesh_fixture(name: &str) -> String {
    format!(
        "{}/crates/softgrip-core/tests/data/meshes/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// `PREFIX-PID` in the temporary directory, not made.
pub fn scratch_path(prefix: &str) -> PathBuf {
    std::env::temp_dir().join(format!("{prefix}-{}", std::process::id()))
}

/// `PREFIX-PID` in the temporary directory, made.
pub fn scratch_dir(prefix: &str) -> PathBuf {
    let dir = scratch_path(prefix);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

/// `text` written to `dir/name`; its path.
pub fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("a scratch file");
    path
}

/// A path as a command-line argument.
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// The JSON file a command wrote.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("the JSON file")).expect("JSON")
}
