//! `softgrip check`: what a scene relies on (its defaults), its mesh and
//! its model, without running it.

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::json::commands::{CheckFigures, CheckMeshFigures, CheckModelFigures};

use super::load::{load_scene, simulation};

/// Check a scene: print the defaults it relies on, the mesh and the model.
#[derive(clap::Args)]
pub struct Args {
    scene: Option<PathBuf>,
    /// Also write the defaults, the mesh and model figures and any warning as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<()> {
    let scene = load_scene(args.scene.as_deref())?;
    super::outputs::Outputs::new()
        .scene(&scene)
        .file("--json", args.json.as_deref())
        .check()?;
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
        "model: {} springs (k {:.3e}..{:.3e} N/m), mass {:.4} kg, {} pinned particles, {} finger(s)",
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
    let warning = collapse_warning(&scene, &sim);
    if let Some(w) = &warning {
        println!("warning: {w}");
    }
    println!("scene is valid");
    if let Some(path) = &args.json {
        let stats = mesh.stats();
        let figures = CheckFigures {
            defaults_applied: scene.defaults_applied.clone(),
            mesh: CheckMeshFigures {
                nodes: stats.nodes,
                tetrahedra: stats.tets,
                boundary_facets: stats.boundary_facets,
                volume_m3: stats.volume,
                min_edge_m: stats.min_edge,
                max_edge_m: stats.max_edge,
                worst_quality: stats.worst_quality,
            },
            model: CheckModelFigures {
                springs: m.springs.len(),
                mass_kg: m.total_mass(),
                pinned_particles: m.fixed.iter().filter(|f| **f).count(),
                fingers: m.fingers.len(),
            },
            warnings: warning.into_iter().collect(),
        };
        super::figures::write_json_line(path, &serde_json::to_value(&figures)?)?;
    }
    Ok(())
}

/// A spring lattice without the bulk term (the thesis model, the default) ignores the
/// material's Poisson ratio and can fold under a load the material carries easily (the thesis
/// cuboid between 7 and 8 N). Where the scene's finger loads are on, its equilibrium under them
/// is solved (a static solve, a fraction of a second): if there is none, the warning names the
/// bulk term its E and nu imply, checked to carry them.
fn collapse_warning(
    scene: &softgrip_core::Scene,
    sim: &softgrip_core::Simulation,
) -> Option<String> {
    use softgrip_core::equilibrium::StaticOptions;
    use softgrip_core::scene::DEFAULT_LIMIT_STIFFNESS;
    use softgrip_core::scene::Elasticity;
    let loaded = scene.fingers.iter().any(|f| f.force.length() > 0.0);
    if scene.model.bulk_modulus != 0.0 || scene.model.elasticity != Elasticity::Springs || !loaded {
        return None;
    }
    let mut at_load = sim.clone();
    // Only a collapse (elements turned inside out) is this warning's: a stall of the
    // spring-limit projection is not.
    let err = match at_load.equilibrium(StaticOptions::default()) {
        Err(e @ softgrip_core::error::SimError::NoEquilibrium { .. }) => e,
        _ => return None,
    };
    if !matches!(&err, softgrip_core::error::SimError::NoEquilibrium { inverted, .. } if !inverted.is_empty())
    {
        return None;
    }
    let (e, nu) = (scene.object.young_modulus, scene.object.poisson_ratio);
    let k = e / (3.0 * (1.0 - 2.0 * nu));
    let mut with_bulk = scene.clone();
    with_bulk.model.bulk_modulus = k;
    // The projection alone (limit_stiffness = 0) leaves a static solve no force to balance
    // at the limits: the fix names the limit springs' default too.
    let limits = scene.model.limit_stiffness == 0.0
        && (scene.model.tau_s.is_some() || scene.model.tau_c.is_some());
    if limits {
        with_bulk.model.limit_stiffness = DEFAULT_LIMIT_STIFFNESS;
    }
    let carried = softgrip_core::Simulation::new(&with_bulk)
        .is_ok_and(|mut s| s.equilibrium(StaticOptions::default()).is_ok());
    let fix = if limits {
        format!(
            "[model] bulk_modulus = {k:.4e} (E / (3 (1 - 2 nu)), the material's own) and limit_stiffness = {DEFAULT_LIMIT_STIFFNESS} (the limits as forces)"
        )
    } else {
        format!("[model] bulk_modulus = {k:.4e} (E / (3 (1 - 2 nu)), the material's own)")
    };
    Some(format!(
        "bulk_modulus = 0 (the default, the thesis model): the spring lattice ignores poisson_ratio = {nu} and folds under this scene's finger loads ({err}). Add {fix}{}",
        if carried {
            " (checked: with it the loads are carried)"
        } else {
            "; with it the loads are not carried either: lower them"
        }
    ))
}
