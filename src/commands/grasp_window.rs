//! `softgrip grasp window SCENE`: the least squeeze that lifts the object and holds it through
//! the lift, the most before a damage measure reaches its limit, and the window between.
// The options' doc comments are the command's help, where `[grasp]` names the scene's table.
#![allow(rustdoc::broken_intra_doc_links)]

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::grasp::compute::{Computed, Stage, compute};
use softgrip_lab::grasp::plan::{Asked, Plan};
use softgrip_lab::grasp::uncertainty::{self, BoundErrors};
use softgrip_lab::grasp::window::{self, Confirmation, Measure, Most};
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
    /// The material from a fit (`softgrip fit --json`): its values set in the scene, its standard
    /// errors carried to both bounds (a central difference per parameter).
    #[arg(long)]
    fit: Option<PathBuf>,
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
    let mut outputs = super::outputs::Outputs::new().scene(&scene);
    if let Some(path) = args.fit.as_deref() {
        outputs = outputs.input(path);
    }
    outputs
        .file("--json", args.json.as_deref())
        .dir("--report", args.report.as_deref())
        .check()?;
    let asked = asked(&args)?;
    let started = std::time::Instant::now();
    let bar = progress_bar(0, "steps");
    bar.set_message("statics");
    let named = |e: softgrip_lab::error::LabError| match e {
        softgrip_lab::error::LabError::Input(what) => {
            anyhow::anyhow!("{}: {what}", args.scene.display())
        }
        e => e.into(),
    };
    let computed = compute(
        &scene,
        asked,
        args.fit.as_deref(),
        !args.no_confirm,
        |stage| match stage {
            Stage::Squeeze(s) => {
                bar.inc(1);
                bar.set_message(format!(
                    "statics: {:.4} N {}",
                    s.squeeze,
                    if s.held { "held" } else { "fell" }
                ));
            }
            Stage::Lift(f, x) => {
                bar.set_message(format!("dynamic lift at {f:.4} N: {:.0} %", 100.0 * x))
            }
            Stage::Uncertainty(done, total) => {
                bar.set_message(format!("the fit's uncertainty: {done} of {total} windows"))
            }
        },
    )
    .map_err(named)?;
    bar.finish_and_clear();
    let (found, plan) = (&computed.window, &computed.plan);
    print_window(&args.scene, found, plan, &computed.confirmations);
    if let Some(e) = &computed.errors {
        print_errors(found, e);
    }
    println!(
        "solved by statics ({} squeezes){}; {:.1} s in all",
        found.samples.len(),
        if computed.confirmations.is_empty() {
            String::new()
        } else {
            format!(
                ", confirmed by {} dynamic lifts",
                computed.confirmations.len()
            )
        },
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = args.json.as_deref() {
        write_json_line(path, &computed.to_json())?;
    }
    if let Some(dir) = args.report.as_deref() {
        report(dir, &args.scene, &computed)?;
    }
    if found.exists() {
        Ok(())
    } else {
        Err(super::errors::Outcome(NO_WINDOW).into())
    }
}

/// The options over the scene's `[grasp]`, each checked.
fn asked(args: &Args) -> Result<Asked> {
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
    Ok(Asked {
        acceleration: args.acceleration,
        shake: args.shake,
        slip_tolerance: args.slip_tolerance,
        hold: args.hold,
        damage: args.damage.as_deref().and_then(Measure::from_name),
        limit: args.limit,
    })
}

/// The report, with the object held at the upper bound (its `.vtu`, and its picture where the
/// viewer is built in).
fn report(dir: &std::path::Path, scene: &std::path::Path, c: &Computed) -> Result<()> {
    let at_most = match c.window.most_squeeze().filter(|&f| f > 0.0) {
        Some(f) => c.gripper.grip(f, c.plan.options.statics)?.held.ok(),
        None => None,
    };
    let written = softgrip_lab::report::grasp_window(
        dir,
        &scene.display().to_string(),
        &c.window,
        &c.plan,
        &c.confirmations,
        c.errors.as_ref(),
        at_most.as_ref(),
    )?;
    #[cfg(feature = "gui")]
    if let Some(sim) = at_most.as_ref() {
        picture(
            sim,
            c.plan.options.damage.measure,
            &dir.join("upper_bound.png"),
        )?;
        append_picture(&written.markdown)?;
    }
    println!("report: {}", written.markdown.display());
    Ok(())
}

fn print_errors(w: &window::Window, e: &BoundErrors) {
    let range = uncertainty::range_text;
    println!(
        "with the fit's uncertainty: least {}",
        range(w.least_squeeze(), e.least)
    );
    if let (Some(m), Some(se)) = (w.most_squeeze(), e.most) {
        println!("with the fit's uncertainty: most {}", range(m, se));
    }
    if e.overlaps(w) {
        println!("the two ends overlap within their 95 % ranges: the window may be empty");
    }
}

fn print_window(
    scene: &std::path::Path,
    w: &window::Window,
    plan: &Plan,
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

/// The object held at the upper bound, coloured by the damage measure (the largest of each
/// node's elements, or the contact pressure), the most loaded element's centroid (or node) marked
/// by a magenta dot; headless.
#[cfg(feature = "gui")]
fn picture(
    sim: &softgrip_core::Simulation,
    measure: Measure,
    path: &std::path::Path,
) -> Result<()> {
    use softgrip_core::fields::Field;
    use softgrip_viewer::render::{self, View, markers};
    let field = match measure {
        Measure::Strain => Field::GreenStrain,
        Measure::Stress => Field::VonMises,
        Measure::Pressure => Field::ContactPressure,
    };
    let style = render::Style {
        color_by: Some(field),
        finger_opacity: 0.3,
        ..Default::default()
    };
    let at = window::peak(measure, sim).at;
    let (model, state) = (&sim.model, &sim.state);
    let (width, height) = (900, 700);
    let renderer = render::Offscreen::new(width, height)?;
    let mut drawing = render::geometry::build(model, state, &style);
    markers::add_markers(
        &mut drawing,
        model,
        &[markers::MarkerPair {
            simulated: at,
            recorded: at,
        }],
        1.0,
    );
    let mut camera =
        render::frame_camera_aspect(model, state, View::Iso, width as f32 / height as f32);
    // Turned about the vertical to look at the peak from outside the object.
    let centre = state.centre_of_mass(model);
    let (dx, dy) = (at.x - centre.x, at.y - centre.y);
    if dx.hypot(dy) > 1e-9 {
        camera.yaw = dx.atan2(-dy) as f32;
    }
    let mut image = renderer.render(&drawing, &camera)?;
    if let Some(legend) = &drawing.legend {
        render::draw_legend_bar(&mut image, legend);
    }
    image
        .save(path)
        .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))?;
    Ok(())
}

/// Shows `upper_bound.png` in the report.
#[cfg(feature = "gui")]
fn append_picture(markdown: &std::path::Path) -> Result<()> {
    let mut text = std::fs::read_to_string(markdown)?;
    text.push_str(
        "\n![the object at the upper bound, coloured by the damage measure](upper_bound.png)\n\nThe object held at the upper bound, coloured by the damage measure; the magenta dot marks where it peaks.\n",
    );
    std::fs::write(markdown, text)?;
    Ok(())
}
