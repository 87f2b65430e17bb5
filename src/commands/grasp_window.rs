//! `softgrip grasp window SCENE`: the least squeeze that lifts the object and holds it through
//! the lift, the most before a damage measure reaches its limit, and the window between.

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::grasp::window::{self, Asked, Confirmation, Gripper, Measure, Most};
use softgrip_lab::report::shown;

use super::figures::write_json_line;
use super::load::load_scene;
use super::progress::progress_bar;

/// How hard may the gripper squeeze: the least squeeze (N per finger, as the scene drives its
/// force axes) that lifts the object and holds it through the lift, the most before the damage
/// measure reaches its limit anywhere in the object, and the window between. Solved by statics
/// (the lift's acceleration as a body force, friction by its return mapping); each bound then
/// confirmed by one dynamic lift. The scene's `[grasp]` gives the lift and the limit; the
/// options here win. Exit code 0: a window; 5: none (the object cannot be held undamaged).
#[derive(clap::Args)]
pub struct Args {
    scene: PathBuf,
    /// Upward acceleration of the lift the grip must hold through (m/s^2; 9.81 is one g).
    /// Default: [grasp] acceleration, else the scene's own lift (speed / ramp_time).
    #[arg(long)]
    acceleration: Option<f64>,
    /// Sideways acceleration (m/s^2), across gravity and the squeeze. Default: [grasp] shake, else 0.
    #[arg(long)]
    shake: Option<f64>,
    /// Held: the contacts slide by less than this as the object takes its load, and over the
    /// dynamic hold (m). Default: [grasp] slip_tolerance, else 5e-4.
    #[arg(long)]
    slip_tolerance: Option<f64>,
    /// Seconds held in each dynamic confirmation. Default: [grasp] hold, else 1.
    #[arg(long)]
    hold: Option<f64>,
    /// The damage measure. Default: [grasp] damage, else the material's.
    #[arg(long, value_parser = ["strain", "stress", "pressure"])]
    damage: Option<String>,
    /// Its limit (strain, or Pa). Default: [grasp] limit, else the material's.
    #[arg(long)]
    limit: Option<f64>,
    /// Skip the dynamic confirmations (statics only).
    #[arg(long)]
    no_confirm: bool,
    /// Also write the figures as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Also write a report (Markdown, the window's plot, the object at the upper bound as .vtu).
    #[arg(long)]
    report: Option<PathBuf>,
}

/// The exit code of a scene with no window.
pub const NO_WINDOW: u8 = 5;

pub fn run(args: Args) -> Result<()> {
    let scene = load_scene(Some(&args.scene))?;
    super::outputs::Outputs::new()
        .scene(&scene)
        .file("--json", args.json.as_deref())
        .dir("--report", args.report.as_deref())
        .check()?;
    for (name, v) in [
        ("--acceleration", args.acceleration),
        ("--shake", args.shake),
        ("--hold", args.hold),
    ] {
        if let Some(v) = v {
            anyhow::ensure!(v.is_finite() && v >= 0.0, "{name} {v}: must be >= 0");
        }
    }
    for (name, v) in [
        ("--slip-tolerance", args.slip_tolerance),
        ("--limit", args.limit),
    ] {
        if let Some(v) = v {
            anyhow::ensure!(v.is_finite() && v > 0.0, "{name} {v}: must be > 0");
        }
    }
    let asked = Asked {
        acceleration: args.acceleration,
        shake: args.shake,
        slip_tolerance: args.slip_tolerance,
        hold: args.hold,
        damage: args.damage.as_deref().and_then(Measure::from_name),
        limit: args.limit,
    };
    let named = |e: softgrip_lab::error::LabError| anyhow::anyhow!("{}: {e}", args.scene.display());
    let plan = window::plan(&scene, asked).map_err(named)?;
    let gripper = Gripper::new(&scene, plan.options.profile).map_err(named)?;
    let started = std::time::Instant::now();
    let bar = progress_bar(0, "squeezes");
    bar.set_message("statics");
    let found = gripper.window(plan.options, |s| {
        bar.inc(1);
        bar.set_message(format!(
            "{:.4} N: {}",
            s.squeeze,
            if s.held { "held" } else { "fell" }
        ));
    })?;
    bar.finish_and_clear();
    let statics_seconds = started.elapsed().as_secs_f64();
    let mut confirmations: Vec<Confirmation> = Vec::new();
    if !args.no_confirm {
        let mut bounds = vec![found.least_squeeze()];
        bounds.extend(found.most_squeeze().filter(|&f| f > 0.0));
        for f in bounds {
            let bar = progress_bar(1000, "per mille");
            bar.set_message(format!("dynamic lift at {f:.4} N"));
            let c = gripper.confirm(&scene, f, plan.options.damage.measure, plan.hold, |x| {
                bar.set_position((x * 1000.0) as u64)
            })?;
            bar.finish_and_clear();
            confirmations.push(c);
        }
    }
    print_window(&args.scene, &found, &plan, &confirmations);
    println!(
        "solved by statics ({} squeezes, {statics_seconds:.1} s){}; {:.1} s in all",
        found.samples.len(),
        if confirmations.is_empty() {
            String::new()
        } else {
            format!(", confirmed by {} dynamic lifts", confirmations.len())
        },
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = args.json.as_deref() {
        write_json_line(path, &window::to_json(&found, &plan, &confirmations))?;
    }
    if let Some(dir) = args.report.as_deref() {
        let at_most = match found.most_squeeze().filter(|&f| f > 0.0) {
            Some(f) => gripper.grip(f, plan.options.statics)?.held.ok(),
            None => None,
        };
        let name = args.scene.display().to_string();
        let written = softgrip_lab::report::grasp_window(
            dir,
            &name,
            &found,
            &plan,
            &confirmations,
            at_most.as_ref(),
        )?;
        println!("report: {}", written.markdown.display());
    }
    if found.exists() {
        Ok(())
    } else {
        Err(super::errors::Outcome(NO_WINDOW).into())
    }
}

fn print_window(
    scene: &std::path::Path,
    w: &window::Window,
    plan: &window::Plan,
    confirmations: &[Confirmation],
) {
    let o = &w.options;
    let m = o.damage.measure;
    println!(
        "{}: load {:.4} N (m |g - a|, lift {:.3} m/s^2 from {}, shake {:.3} m/s^2)",
        scene.display(),
        w.load,
        o.profile.acceleration,
        plan.acceleration_from,
        o.profile.shake
    );
    println!(
        "least squeeze that holds: {:.4} N (dropped at {:.4} N; rigid force balance {:.4} N)",
        w.least.held, w.least.dropped, w.force_balance
    );
    match w.most {
        Most::Found { below, above } => println!(
            "most before damage: {below:.4} N ({} limit {} from {}, reached at {above:.4} N)",
            m.describe(),
            shown(m, o.damage.limit),
            plan.limit_from
        ),
        Most::NotReached(f) => println!(
            "most before damage: the {} stays below {} up to {f:.4} N (the largest squeeze tried)",
            m.describe(),
            shown(m, o.damage.limit)
        ),
    }
    if w.exists() {
        println!(
            "window: {:.4} .. {} N",
            w.least.held,
            w.most_squeeze()
                .map_or("(no limit reached)".to_string(), |f| format!("{f:.4}"))
        );
    } else if let Some(s) = w.at_least() {
        println!(
            "NO WINDOW: where it first holds the {} is already {} (limit {}), at ({:.1}, {:.1}, {:.1}) mm: lower the lift's acceleration, raise the fingers' friction or spread the squeeze",
            m.describe(),
            shown(m, s.peak.value),
            shown(m, o.damage.limit),
            s.peak.at.x * 1e3,
            s.peak.at.y * 1e3,
            s.peak.at.z * 1e3
        );
    }
    for c in confirmations {
        println!(
            "dynamic lift at {:.4} N: {} (slid {:.4} mm over the {} s hold), peak {} {}",
            c.squeeze,
            if c.run.held { "held" } else { "NOT held" },
            c.run.hold_slip * 1e3,
            plan.hold,
            m.describe(),
            shown(m, c.peak.value)
        );
    }
}
