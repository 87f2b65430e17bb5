//! What the lab's tests share: the repository's assets, temporary directories and recordings
//! written by hand.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use softgrip_lab::recording::Recording;

/// A file of the repository's, by its path from the repository's root.
pub fn asset(path: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(path)
}

/// The committed synthetic recording of the thesis's seven loads.
pub fn thesis_7_loads() -> Recording {
    Recording::load(&asset(
        "assets/recordings/synthetic/thesis_7_loads/recording.toml",
    ))
    .expect("the committed recording loads")
}

/// A directory of this test run's own: `softgrip-NAME-PID` in the system's
/// temporary directory.
pub fn temp_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("softgrip-{name}-{}", std::process::id()))
}

/// The thesis cuboid through a light guide (its scene file's text), at
/// `edge` (m).
pub fn light_guide_scene(edge: f64) -> String {
    let text = std::fs::read_to_string(asset("assets/scenes/thesis_cuboid_light_guide.toml"))
        .expect("scene");
    let scene = text.replace("edge_length = 0.004", &format!("edge_length = {edge:?}"));
    assert_ne!(scene, text, "the scene's edge length was set");
    scene
}

/// Writes a recording in `dir` of `markers` on the scene text `scene`, in
/// `mode`, with the samples' `rows` (time, load, marker, x, y, z as text),
/// and loads it.
pub fn write_recording(
    dir: &Path,
    scene: &str,
    mode: &str,
    markers: &[(&str, DVec3)],
    rows: &str,
) -> Recording {
    std::fs::create_dir_all(dir).expect("dir");
    std::fs::write(dir.join("scene.toml"), scene).expect("scene.toml");
    let mut header = format!(
        "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"{mode}\"\n[markers]\n"
    );
    for (name, p) in markers {
        let _ = writeln!(header, "{name} = [{:?}, {:?}, {:?}]", p.x, p.y, p.z);
    }
    std::fs::write(dir.join("recording.toml"), header).expect("recording.toml");
    std::fs::write(
        dir.join("samples.csv"),
        format!("time,load,marker,x,y,z\n{rows}"),
    )
    .expect("samples.csv");
    Recording::load(&dir.join("recording.toml")).expect("recording")
}
