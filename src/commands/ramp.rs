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
}

pub fn run(args: Args) -> Result<()> {
    let (loads, max_seconds, rest_speed) = (&args.loads, args.max_seconds, args.rest_speed);
    let scene = load_scene(args.scene.as_deref())?;
    let mut sim = simulation(&scene)?;
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
    for &load in loads {
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
        println!(
            "| {load} | {:.3} | {:.4} | {:.3} | {:.2e} | {} | {rest} |",
            sim.indentation(k) * 1e3,
            -f.contact_force.dot(sim.model.fingers[k].load_direction),
            f.max_penetration * 1e3,
            sim.state.stats.volume_error,
            sim.state.inverted_elements(&sim.model),
        );
    }
    Ok(())
}
