//! The scene a command works on: a file's or the built-in thesis scene,
//! and its simulation.

use std::path::Path;

use anyhow::Result;
use softgrip_core::Simulation;
use softgrip_core::scene::Scene;

/// The scene in `path`, or the built-in thesis scene when none is given.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    match path {
        Some(p) => Ok(Scene::load(p)?),
        None => Ok(Scene::thesis()),
    }
}

/// The scene's simulation; what loading its mesh changed or noticed goes
/// to stderr as warnings.
pub fn simulation(scene: &Scene) -> Result<Simulation> {
    let (mesh, warnings) = softgrip_core::Model::load_mesh(scene)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    Ok(Simulation::on_mesh(scene, mesh)?)
}
