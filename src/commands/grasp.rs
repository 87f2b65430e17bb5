//! `softgrip grasp`: run a grasp-and-lift scene, say whether friction held
//! the object, and (with `--boundary`) find the least friction that does.

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::grasp::{self, GraspOptions};

use super::figures::write_json_line;
use super::load::load_scene;
use super::progress::progress_bar;

/// Grasp and lift (e.g. assets/scenes/grasp_lift.toml): the fingers
/// squeeze, lift after their start_time and hold; says whether friction
/// held the object and how far it slid, and with --boundary bisects the
/// least finger friction that holds it, against the force balance.
/// Exit code: 0 held, 3 slipping (off the table, slid past --slip-bound), 4 dropped (on the
/// table); with --boundary too, for the scene's own friction.
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    #[command(subcommand)]
    command: Option<GraspCommand>,
    #[arg(required = true)]
    scene: Option<PathBuf>,
    /// Seconds to hold after the lift.
    #[arg(long, default_value_t = 2.0)]
    hold: f64,
    /// Held: the object slid down the fingers by less than this over the
    /// hold (m).
    #[arg(long, default_value_t = 1e-4)]
    slip_bound: f64,
    /// Also find the least friction that holds it (a dozen lifts).
    #[arg(long)]
    boundary: bool,
    /// Also write the figures as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
}

#[derive(clap::Subcommand)]
enum GraspCommand {
    Window(super::grasp_window::Args),
}

pub fn run(args: Args) -> Result<()> {
    if let Some(GraspCommand::Window(w)) = args.command {
        return super::grasp_window::run(w);
    }
    let scene = &load_scene(args.scene.as_deref())?;
    let (hold, slip_bound) = (args.hold, args.slip_bound);
    let (boundary, json) = (args.boundary, args.json.as_deref());
    super::outputs::Outputs::new()
        .scene(scene)
        .file("--json", json)
        .check()?;
    anyhow::ensure!(
        hold.is_finite() && hold >= 0.0,
        "--hold {hold}: must be >= 0 s"
    );
    anyhow::ensure!(
        slip_bound.is_finite() && slip_bound > 0.0,
        "--slip-bound {slip_bound}: must be > 0 m"
    );
    let options = GraspOptions { hold, slip_bound };
    let model = softgrip_core::model::Model::from_scene(scene)?;
    let end = grasp::lift_end(&model).map_err(anyhow::Error::msg)?;
    let balance = grasp::force_balance_friction(&model);

    let bar = progress_bar(1000, "per mille");
    bar.set_message("grasp and lift");
    let run = grasp::lift(scene, options, |f| bar.set_position((f * 1000.0) as u64))?;
    bar.finish_and_clear();
    let friction = scene.fingers.first().map_or(0.0, |f| f.friction);
    println!(
        "friction {friction}: fingers rose {:.2} mm by t = {:.2} s, the object's centre {:.2} mm; over the {hold} s hold it slid {:.3} mm down the fingers (bound {:.3} mm); {}",
        run.finger_rise * 1e3,
        run.lift_end,
        run.object_rise * 1e3,
        run.hold_slip * 1e3,
        slip_bound * 1e3,
        if run.held {
            "HELD"
        } else if run.off_table {
            "SLIPPING"
        } else {
            "DROPPED (left on the table)"
        }
    );
    if let Some(b) = balance {
        println!("force balance: weight / squeeze = {b:.4} (the least friction that can hold it)");
    }
    let found = if boundary {
        Some(find_boundary(scene, options, friction, balance)?)
    } else {
        None
    };
    if let Some(path) = json {
        let figures = softgrip_lab::json::commands::GraspFigures {
            friction,
            lift_end_s: end,
            finger_rise_m: run.finger_rise,
            object_rise_m: run.object_rise,
            hold_s: hold,
            hold_slip_m: run.hold_slip,
            slip_bound_m: slip_bound,
            off_table: run.off_table,
            held: run.held,
            force_balance_friction: balance,
            boundary_friction: found.as_ref().map(|b| b.estimate()),
            boundary_tries: found.as_ref().map(|b| b.tries.clone()),
        };
        write_json_line(path, &serde_json::to_value(&figures)?)?;
    }
    // Scripts tell the three apart without parsing the text.
    match (run.held, run.off_table) {
        (true, _) => Ok(()),
        (false, true) => Err(super::errors::Outcome(SLIPPING).into()),
        (false, false) => Err(super::errors::Outcome(DROPPED).into()),
    }
}

/// `--boundary`: the least friction that holds, bisected in `[0, max(2 friction, 1)]` with a
/// progress bar, printed with its distance from the force balance's.
fn find_boundary(
    scene: &softgrip_core::Scene,
    options: GraspOptions,
    friction: f64,
    balance: Option<f64>,
) -> Result<grasp::Boundary> {
    let high = (2.0 * friction).max(1.0);
    let bar = progress_bar(1, "lifts");
    bar.set_message("bisecting the friction");
    let b = grasp::boundary_friction(scene, options, (0.0, high), 0.002, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    print!(
        "boundary friction {:.4} (dropped at {:.4}, held at {:.4}; {} lifts)",
        b.estimate(),
        b.dropped,
        b.held,
        b.tries.len()
    );
    match balance {
        Some(bal) => println!(
            "; force balance {bal:.4} ({:+.1} %)",
            100.0 * (b.estimate() / bal - 1.0)
        ),
        None => println!(),
    }
    Ok(b)
}

/// The exit code of a lift that is still off the table but slid past the bound ...
pub const SLIPPING: u8 = 3;
/// ... and of one that ended on the table.
pub const DROPPED: u8 = 4;
