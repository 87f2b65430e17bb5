//! `softgrip view`, and `softgrip` alone: the desktop viewer on a scene
//! (`softgrip_viewer::viewer`).

use std::path::PathBuf;

use anyhow::Result;
use softgrip_core::scene::Scene;

use super::load::load_scene;

/// Open the viewer on a scene (the built-in thesis scene when none is
/// given); what `softgrip` alone does.
#[derive(clap::Args)]
pub struct Args {
    scene: Option<PathBuf>,
    /// Override the scene's tetrahedron edge length (m).
    #[arg(long, value_parser = super::args::positive)]
    edge_length: Option<f64>,
    /// Benchmark: run this many seconds with the solver playing as fast
    /// as it goes and the view redrawn continuously, print the UI frame
    /// times and close (docs/results/benchmarks.md).
    #[arg(long, value_parser = super::args::positive)]
    measure: Option<f64>,
    /// With --measure: keep the solver paused, for comparison.
    #[arg(long)]
    paused: bool,
    /// Open this lab recording (its .toml header) at start: its scene
    /// replaces the one given, and it is replayed for the Recording
    /// panel.
    #[arg(long)]
    recording: Option<PathBuf>,
}

/// `softgrip` alone: the viewer on the built-in thesis scene.
pub fn open_thesis_scene() -> Result<()> {
    softgrip_viewer::viewer::run(Scene::thesis())
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        scene,
        edge_length,
        measure,
        paused,
        recording,
    } = args;
    load_scene(scene.as_deref()).and_then(|mut scene| {
        if let Some(edge) = edge_length {
            anyhow::ensure!(
                edge.is_finite() && edge > 0.0,
                "--edge-length {edge}: must be a positive length in metres"
            );
            scene.object.edge_length = edge;
        }
        let options = softgrip_viewer::viewer::Options {
            measure: measure.map(std::time::Duration::from_secs_f64),
            play: !paused,
            recording,
        };
        softgrip_viewer::viewer::run_with(scene, options)
    })
}
