//! `softgrip ramp`: quasi-static load steps on the first force-controlled
//! finger, a table row per load at rest.

use std::path::PathBuf;

use anyhow::Result;

use super::load::{load_scene, simulation};
use super::progress::progress_bar;
use softgrip_core::equilibrium::Settled;
use softgrip_core::scene::Settle;

/// Quasi-static load steps: set the first force-controlled finger's load to
/// each value in turn (N, along the scene's force direction) and step to rest.
#[derive(clap::Args)]
pub struct Args {
    scene: Option<PathBuf>,
    /// Loads in N, applied in this order (e.g. 1,2,4,9.73).
    #[arg(long, value_delimiter = ',', required = true, value_parser = super::args::finite)]
    loads: Vec<f64>,
    /// Simulated seconds allowed per load to come to rest.
    #[arg(long, default_value_t = 20.0, value_parser = super::args::positive)]
    max_seconds: f64,
    /// Rest: every particle and finger slower than this (m/s).
    #[arg(long, default_value_t = 1e-5, value_parser = super::args::positive)]
    rest_speed: f64,
    #[command(flatten)]
    settle: super::args::SettleArgs,
    /// Also write the table as CSV here (SI units).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Also write the table as JSON here (SI units).
    #[arg(long)]
    json: Option<PathBuf>,
}

/// One load's row, in SI units.
struct Row {
    load: f64,
    indentation: f64,
    contact_force: f64,
    penetration: f64,
    volume_error: f64,
    inverted: usize,
    /// How it came to rest, in words (the table's last column).
    rest: String,
}

const CSV_HEADER: &str =
    "load_n,indentation_m,contact_force_n,penetration_m,volume_error,inverted_elements,to_rest";

/// `softgrip ramp`: each load in turn on the scene's first force-controlled finger, brought to
/// rest, a table row printed per load; with `--csv` and `--json` the table written.
pub fn run(args: Args) -> Result<()> {
    let (loads, max_seconds, rest_speed) = (&args.loads, args.max_seconds, args.rest_speed);
    if let Some(bad) = loads.iter().find(|l| **l < 0.0) {
        anyhow::bail!(
            "--loads {bad}: a negative load pulls the finger away from the object, and a contact only pushes; give loads of 0 or more (their direction is the finger's `force` in the scene)"
        );
    }
    let scene = load_scene(args.scene.as_deref())?;
    super::outputs::Outputs::new()
        .scene(&scene)
        .file("--csv", args.csv.as_deref())
        .file("--json", args.json.as_deref())
        .check()?;
    let mut sim = simulation(&scene)?;
    let k = loaded_finger(&sim)?;
    let tol = softgrip_core::quasi_static::RestTolerance {
        speed: rest_speed,
        consecutive_steps: 20,
        max_seconds,
        give_up_after: None,
    };
    let settle = args
        .settle
        .settle
        .map_or(scene.simulation.settle, super::args::SettleMode::replay);
    let to_rest = match settle {
        Settle::Dynamic => "steps to rest",
        Settle::Static => "to equilibrium",
    };
    println!(
        "| load (N) | indentation (mm) | contact force (N) | penetration (mm) | volume error | inverted elements | {to_rest} |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for &load in loads {
        let row = rest_at(&mut sim, k, load, settle, tol, max_seconds)?;
        println!(
            "| {load} | {:.3} | {:.4} | {:.3} | {:.2e} | {} | {} |",
            row.indentation * 1e3,
            row.contact_force,
            row.penetration * 1e3,
            row.volume_error,
            row.inverted,
            row.rest
        );
        rows.push(row);
    }
    if let Some(path) = &args.csv {
        write_csv(path, &rows)?;
    }
    if let Some(path) = &args.json {
        write_json(path, &rows)?;
    }
    Ok(())
}

/// The finger the loads go on: the first force-controlled one, which must have a load
/// direction.
fn loaded_finger(sim: &softgrip_core::Simulation) -> Result<usize> {
    let Some(k) = sim.load_finger() else {
        anyhow::bail!(
            "the scene has no force-controlled finger to load; add a [[finger]] with control = \"force\""
        );
    };
    if sim.model.fingers[k].load_direction == glam::DVec3::ZERO {
        anyhow::bail!(
            "finger {} has force = [0, 0, 0], so the load has no direction; give it a force (e.g. [0, 0, -1]) and, for a pure load, mass = 0",
            k + 1
        );
    }
    Ok(k)
}

/// Sets finger `k`'s load to `load` (N), brings the run to rest as `settle` says (time steps
/// within `max_seconds` simulated, or Newton), and reads its row.
fn rest_at(
    sim: &mut softgrip_core::Simulation,
    k: usize,
    load: f64,
    settle: Settle,
    tol: softgrip_core::quasi_static::RestTolerance,
    max_seconds: f64,
) -> Result<Row> {
    let from: Vec<_> = sim.state.fingers.iter().map(|f| f.applied_force).collect();
    sim.set_load(k, load);
    let bar = progress_bar((max_seconds / sim.model.dt) as u64, "steps");
    bar.set_message(format!("load {load} N"));
    let rest = match settle {
        Settle::Dynamic => sim
            .settle(tol, |s| bar.set_position(s))
            .map(|r| r.steps.to_string()),
        Settle::Static => sim
            .settle_to_equilibrium(&from, Default::default(), tol, |s| bar.set_position(s))
            .map(|r| match r {
                Settled::Static(r) => format!("{} Newton iterations", r.iterations),
                Settled::Dynamic { rest, stalled } => format!(
                    "Newton {}, then {} time steps",
                    if stalled {
                        "stalled"
                    } else {
                        "did not converge"
                    },
                    rest.steps
                ),
            }),
    };
    bar.finish_and_clear();
    let f = sim.state.fingers[k];
    let rest = match rest {
        Ok(r) => r,
        Err(softgrip_core::SimError::NoRest { max_speed, .. }) => {
            format!("not at rest (speed {max_speed:.1e} m/s)")
        }
        Err(e) => return Err(e.into()),
    };
    Ok(Row {
        load,
        indentation: sim.indentation(k),
        contact_force: -f.contact_force.dot(sim.model.fingers[k].load_direction),
        penetration: f.max_penetration,
        volume_error: sim.state.stats.volume_error,
        inverted: sim.state.inverted_elements(&sim.model),
        rest,
    })
}

/// Writes the table as CSV (`--csv`), SI units.
fn write_csv(path: &std::path::Path, rows: &[Row]) -> Result<()> {
    let mut text = format!("{CSV_HEADER}\n");
    for r in rows {
        text.push_str(&format!(
            "{},{:e},{:e},{:e},{:e},{},\"{}\"\n",
            r.load,
            r.indentation,
            r.contact_force,
            r.penetration,
            r.volume_error,
            r.inverted,
            r.rest
        ));
    }
    std::fs::write(path, text)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

/// Writes the table as JSON (`--json`), SI units.
fn write_json(path: &std::path::Path, rows: &[Row]) -> Result<()> {
    use softgrip_lab::json::commands::{RampFigures, RampRowFigures};
    let loads = rows
        .iter()
        .map(|r| RampRowFigures {
            load_n: r.load,
            indentation_m: r.indentation,
            contact_force_n: r.contact_force,
            penetration_m: r.penetration,
            volume_error: r.volume_error,
            inverted_elements: r.inverted,
            to_rest: r.rest.clone(),
        })
        .collect();
    super::figures::write_json_line(path, &serde_json::to_value(&RampFigures { loads })?)
}
