//! `softgrip check`: what a scene relies on (its defaults), its mesh and
//! its model, without running it.

use std::path::PathBuf;

use anyhow::Result;

use super::load::{load_scene, simulation};

/// Check a scene: print the defaults it relies on, the mesh and the model.
#[derive(clap::Args)]
pub struct Args {
    scene: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<()> {
    let scene = load_scene(args.scene.as_deref())?;
    if scene.defaults_applied.is_empty() {
        println!("every key is set explicitly");
    } else {
        println!("defaults applied ({}):", scene.defaults_applied.len());
        for d in &scene.defaults_applied {
            println!("  {d}");
        }
    }
    let sim = simulation(&scene)?;
    let m = &sim.model;
    let mesh = softgrip_core::mesh::TetMesh {
        nodes: m.rest_positions.clone(),
        tets: m.tets.clone(),
    };
    println!("mesh: {}", mesh.stats());
    println!(
        "model: {} springs (k {:.3e}..{:.3e} N/m), mass {:.4} kg, {} pinned particles, {} fingers",
        m.springs.len(),
        m.springs
            .iter()
            .map(|s| s.stiffness)
            .fold(f64::INFINITY, f64::min),
        m.springs.iter().map(|s| s.stiffness).fold(0.0, f64::max),
        m.total_mass(),
        m.fixed.iter().filter(|f| **f).count(),
        m.fingers.len()
    );
    println!("scene is valid");
    Ok(())
}
