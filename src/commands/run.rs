//! `softgrip run`: a scene headless, its figures printed at the end and,
//! with `--out`, its ParaView frames and finger track written.

use std::path::PathBuf;

use anyhow::{Context, Result};
use softgrip_core::output::TrajectoryWriter;

use super::load::{load_scene, simulation};
use super::progress::progress_bar;

const DEFAULT_FPS: f64 = 50.0;

/// Run a scene headless (the built-in thesis scene when none is given).
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (.toml); omit for the built-in thesis scene.
    scene: Option<PathBuf>,
    /// Write ParaView files (frame_*.vtu, finger*_*.vtu, trajectory.pvd),
    /// fingers.csv and steps.csv here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Simulated seconds (default: the scene's [simulation] duration).
    #[arg(long, value_parser = super::args::positive)]
    duration: Option<f64>,
    /// Frames per simulated second written with --out.
    #[arg(long, default_value_t = DEFAULT_FPS, value_parser = super::args::positive)]
    fps: f64,
    /// With --out: also write each frame's deformed surface
    /// (surface_NNNNN.stl or .obj).
    #[arg(long, value_enum, requires = "out")]
    surface: Option<super::values::SurfaceFormat>,
    /// Fail (exit 1) when a physical check finds the result unphysical (a finger through the
    /// object, a load not carried, spring limits not held, energy gained, elements inside
    /// out); without it they are warnings.
    #[arg(long)]
    strict: bool,
    /// Also write the end figures and the warnings as JSON here (SI units).
    #[arg(long)]
    json: Option<PathBuf>,
    /// With --out: write the .vtu files as ASCII text, the object's arrays
    /// all Float64 (about six times larger), instead of zlib-compressed binary.
    #[arg(long)]
    ascii: bool,
}

/// `softgrip` alone when built without the viewer: the built-in thesis
/// scene, headless.
#[cfg(not(feature = "gui"))]
pub fn without_viewer() -> Result<()> {
    eprintln!(
        "softgrip: built without the viewer (feature `gui`); running the built-in thesis scene headless (see `softgrip --help`)."
    );
    run(Args {
        scene: None,
        out: None,
        duration: None,
        fps: DEFAULT_FPS,
        surface: None,
        strict: false,
        json: None,
        ascii: false,
    })
}

/// Time steps a `run` may take (hours of wall time on the built-in scene).
const MAX_STEPS: f64 = 1e7;
/// Frames a `run --out` may write.
const MAX_FRAMES: f64 = 1e5;

/// `softgrip run`: steps the scene to the end, then prints (and with `--json` writes) its
/// figures and warnings; `--strict` turns the warnings into a failure.
pub fn run(args: Args) -> Result<()> {
    let (scene_path, out) = (args.scene.as_deref(), args.out.as_deref());
    let (duration, fps, surface) = (args.duration, args.fps, args.surface.map(|f| f.0));
    let scene = load_scene(scene_path)?;
    super::outputs::Outputs::new()
        .scene(&scene)
        .dir("--out", out)
        .file("--json", args.json.as_deref())
        .check()?;
    let mut sim = simulation(&scene)?;
    let duration = duration.unwrap_or(scene.simulation.duration);
    let name = scene_path
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "built-in thesis scene".into());
    println!(
        "{name}: {} particles, {} tetrahedra, {} springs, {} facets; dt = {} s, {} s to simulate",
        sim.model.particle_count(),
        sim.model.tets.len(),
        sim.model.springs.len(),
        sim.model.facets.len(),
        sim.model.dt,
        duration
    );
    let steps = step_count(&sim, duration, fps, out.is_some())?;
    let frame_every = ((1.0 / fps.max(1e-9)) / sim.model.dt).round().max(1.0) as u64;
    let mut writer = match out {
        Some(dir) => {
            let mut w = TrajectoryWriter::new(dir)?;
            w.surface = surface;
            if args.ascii {
                w.encoding = softgrip_core::output::vtu::Encoding::Ascii;
            }
            w.frame(&sim.model, &sim.state)?;
            Some(w)
        }
        None => None,
    };
    let ran = step_all(&mut sim, &scene, &name, steps, frame_every, &mut writer)?;

    let st = sim.state.stats;
    println!(
        "t = {:.3} s after {} steps in {:.2} s wall ({:.2} x real time)",
        sim.state.time,
        sim.state.step,
        sim.wall_seconds,
        sim.state.time / sim.wall_seconds.max(1e-12)
    );
    let untouched = print_fingers(&sim, &ran.touched);
    println!(
        "volume error {:.3e} (|V - V0| / V0); contacts {}; spring-limit violation {:.2e}; energy {:.4e} J; top particle speed {:.1e} m/s",
        st.volume_error, st.contacts, st.limit_violation, st.energy, st.max_speed
    );
    let (warnings, inverted) = warnings(&scene, &sim, ran.watch, untouched);
    for w in &warnings {
        println!("warning: {w}");
    }
    println!(
        "solver: {:.1} CG iterations per step on average, last residual {:.2e}",
        ran.cg_total as f64 / steps.max(1) as f64,
        st.cg_residual
    );
    if let Some(w) = writer {
        let pvd = w.finish()?;
        println!("wrote {} (open in ParaView) and fingers.csv", pvd.display());
    }
    if let Some(path) = &args.json {
        write_json(path, &name, &sim, inverted, &warnings)?;
    }
    anyhow::ensure!(
        !args.strict || warnings.is_empty(),
        "--strict: {} physical check(s) failed (the warnings above)",
        warnings.len()
    );
    Ok(())
}

/// The time steps to `duration`, refused where they (or, with `--out`, the frames at `fps`)
/// would be more than a run may take.
fn step_count(
    sim: &softgrip_core::Simulation,
    duration: f64,
    fps: f64,
    writes_frames: bool,
) -> Result<u64> {
    // A run of years or of a million frames is a typo, not a job: say so before it fills the disk.
    let steps = duration / sim.model.dt;
    anyhow::ensure!(
        steps <= MAX_STEPS,
        "{duration} s to simulate is {steps:.1e} steps of dt = {} s, more than {MAX_STEPS:.0e}: give a shorter --duration (or the scene's [simulation] duration)",
        sim.model.dt
    );
    if writes_frames {
        let frames = duration * fps.min(1.0 / sim.model.dt);
        anyhow::ensure!(
            frames <= MAX_FRAMES,
            "--out would write {frames:.0} frames ({duration} s at {fps} frames/s), more than {MAX_FRAMES:.0}: give a lower --fps or a shorter --duration"
        );
    }
    Ok(steps.round() as u64)
}

/// What stepping the whole run gathered beside the state.
struct Ran {
    /// CG iterations summed over the steps.
    cg_total: u64,
    /// The physical checks, fed every step that succeeded.
    watch: softgrip_core::watch::Watch,
    /// Whether each finger touched the object at any step.
    touched: Vec<bool>,
}

/// Takes `steps` time steps with the progress bar, writing a frame every `frame_every` and at
/// the end; on a failure, writes what was computed (the failing state last) and returns the
/// error with its advice checked.
fn step_all(
    sim: &mut softgrip_core::Simulation,
    scene: &softgrip_core::Scene,
    name: &str,
    steps: u64,
    frame_every: u64,
    writer: &mut Option<TrajectoryWriter>,
) -> Result<Ran> {
    let bar = progress_bar(steps, "steps");
    let mut cg_total = 0u64;
    let mut watch = softgrip_core::watch::Watch::new();
    // Whether each finger touched the object at any step.
    let mut touched = vec![false; sim.state.fingers.len()];
    for i in 0..steps {
        let stepped = sim.step();
        if stepped.is_ok() {
            watch.step(&sim.model, &sim.state);
        }
        if let Err(e) = stepped {
            bar.finish_and_clear();
            // Keep what was computed: the frames so far and the state that failed.
            if let Some(mut w) = writer.take() {
                w.frame(&sim.model, &sim.state)?;
                let pvd = w.finish()?;
                eprintln!(
                    "wrote the {} s computed before the failure (and the failing state as the last frame) to {}",
                    sim.state.time,
                    pvd.display()
                );
            }
            let e = check_the_advice(scene, e);
            return Err(e).with_context(|| format!("while running {name}"));
        }
        for (t, f) in touched.iter_mut().zip(&sim.state.fingers) {
            *t |= f.max_penetration > 0.0 || f.normal_force > 0.0;
        }
        cg_total += sim.state.stats.cg_iterations as u64;
        if let Some(w) = writer.as_mut() {
            w.step(&sim.state);
            if (i + 1) % frame_every == 0 || i + 1 == steps {
                w.frame(&sim.model, &sim.state)?;
            }
        }
        if i % 20 == 0 {
            bar.set_message(format!("t = {:.3} s", sim.state.time));
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(Ran {
        cg_total,
        watch,
        touched,
    })
}

/// Prints each finger's line: how far it moved and, if it `touched` the object, its
/// indentation, contact force and deepest penetration. Returns the fingers (from 1) that never
/// touched it.
fn print_fingers(sim: &softgrip_core::Simulation, touched: &[bool]) -> Vec<usize> {
    let mut untouched = Vec::new();
    for (k, f) in sim.state.fingers.iter().enumerate() {
        let moved = f.position - sim.model.fingers[k].initial_position;
        if !touched[k] {
            println!(
                "finger {}: never touched the object; moved ({:.3}, {:.3}, {:.3}) mm",
                k + 1,
                moved.x * 1e3,
                moved.y * 1e3,
                moved.z * 1e3
            );
            untouched.push(k + 1);
            continue;
        }
        println!(
            "finger {}: indentation depth {:.3} mm, moved ({:.3}, {:.3}, {:.3}) mm, contact force ({:.4}, {:.4}, {:.4}) N (normal {:.4} N), deepest penetration {:.3} mm",
            k + 1,
            sim.indentation(k) * 1e3,
            moved.x * 1e3,
            moved.y * 1e3,
            moved.z * 1e3,
            f.contact_force.x,
            f.contact_force.y,
            f.contact_force.z,
            f.normal_force,
            f.max_penetration * 1e3
        );
    }
    untouched
}

/// The run's warnings: the physical checks' findings (a tunnelling one with its smaller `dt`
/// checked), the `untouched` fingers that did not pass through, and elements inside out; and
/// the count of those elements.
fn warnings(
    scene: &softgrip_core::Scene,
    sim: &softgrip_core::Simulation,
    mut watch: softgrip_core::watch::Watch,
    untouched: Vec<usize>,
) -> (Vec<String>, usize) {
    let findings = watch.finish(&sim.model, &sim.state);
    let mut warnings: Vec<String> = findings
        .iter()
        .map(|f| match f.try_dt {
            Some(dt) => format!("{} {}", f.message, check_tunnelling(scene, f, dt)),
            None => f.message.clone(),
        })
        .collect();
    // A finger that passed through is said so, with its own cause:
    // "check its position" is for one that never reached the object.
    let explained = |k: usize| {
        findings
            .iter()
            .any(|f| f.finger == Some(k - 1) && f.kind == softgrip_core::watch::Kind::Tunnelled)
    };
    for k in untouched.into_iter().filter(|k| !explained(*k)) {
        warnings.push(format!(
            "finger {k} never touched the object in {:.3} s: no indentation or contact force to report; check its position, its path and its start_time",
            sim.state.time
        ));
    }
    let inverted = sim.state.inverted_elements(&sim.model);
    if inverted > 0 {
        let remedy = if scene.model.bulk_modulus == 0.0 {
            format!(
                "Add [model] bulk_modulus = {:.3e} (E / (3 (1 - 2 nu)) for this material) or lower the load",
                scene.object.young_modulus / (3.0 * (1.0 - 2.0 * scene.object.poisson_ratio))
            )
        } else {
            "Lower the load, refine the mesh, or raise [model] bulk_modulus".to_string()
        };
        warnings.push(format!(
            "{inverted} of {} elements are inside out: the spring lattice has collapsed under this load and the result is not physical (see docs/results/accuracy.md, \"Large loads\"). {remedy}",
            sim.model.tets.len(),
        ));
    }
    (warnings, inverted)
}

/// Writes `--json`: the end figures (SI units), each finger's, and the warnings.
fn write_json(
    path: &std::path::Path,
    name: &str,
    sim: &softgrip_core::Simulation,
    inverted: usize,
    warnings: &[String],
) -> Result<()> {
    use softgrip_lab::json::commands::{RunFigures, RunFingerFigures};
    let st = sim.state.stats;
    let fingers = sim
        .state
        .fingers
        .iter()
        .enumerate()
        .map(|(k, f)| RunFingerFigures {
            finger: k + 1,
            indentation_m: sim.indentation(k),
            moved_m: (f.position - sim.model.fingers[k].initial_position).to_array(),
            contact_force_n: f.contact_force.to_array(),
            normal_force_n: f.normal_force,
            penetration_m: f.max_penetration,
        })
        .collect();
    let figures = RunFigures {
        scene: name.to_string(),
        time_s: sim.state.time,
        steps: sim.state.step,
        wall_s: sim.wall_seconds,
        fingers,
        volume_error: st.volume_error,
        contacts: st.contacts,
        limit_violation: st.limit_violation,
        energy_j: st.energy,
        inverted_elements: inverted,
        warnings: warnings.to_vec(),
    };
    super::figures::write_json_line(path, &serde_json::to_value(&figures)?)
}

/// Steps a check of a smaller `dt` may take.
const CHECK_STEPS: f64 = 2e5;

/// How the scene ran again at a smaller `dt` to `until`.
enum Rerun {
    /// Not run: this many steps would be too many.
    TooLong(f64),
    Passed,
    Failed(softgrip_core::error::SimError),
    /// The physical check found the same as before.
    Found,
}

/// Runs `scene` again at `dt` to `until` (the advice's check); with `same`, stops where the
/// physical checks find it again.
fn rerun(
    scene: &softgrip_core::Scene,
    dt: f64,
    until: f64,
    same: Option<&softgrip_core::watch::Finding>,
) -> Rerun {
    if until / dt > CHECK_STEPS {
        return Rerun::TooLong(until / dt);
    }
    let mut smaller = scene.clone();
    smaller.simulation.dt = dt;
    let mut sim = match softgrip_core::Simulation::new(&smaller) {
        Ok(sim) => sim,
        Err(e) => return Rerun::Failed(e),
    };
    let mut watch = softgrip_core::watch::Watch::new();
    while sim.state.time < until {
        if let Err(e) = sim.step() {
            return Rerun::Failed(e);
        }
        watch.step(&sim.model, &sim.state);
        if same.is_some_and(|f| {
            watch
                .findings()
                .iter()
                .any(|g| g.kind == f.kind && g.finger == f.finger)
        }) {
            return Rerun::Found;
        }
    }
    Rerun::Passed
}

/// A divergence whose advice is a smaller `dt`, checked: the scene is run again at that `dt`
/// to a little past where it failed. Advice that does not work is replaced by what does.
fn check_the_advice(
    scene: &softgrip_core::Scene,
    e: softgrip_core::error::SimError,
) -> softgrip_core::error::SimError {
    use softgrip_core::error::SimError;
    let SimError::Diverged {
        time,
        suggest_dt: Some(dt),
        mut advice,
        what,
        step,
        dt: old_dt,
        young_modulus,
        alpha,
    } = e
    else {
        return e;
    };
    let until = 1.5 * time + 10.0 * old_dt;
    advice = match rerun(scene, dt, until, None) {
        Rerun::TooLong(steps) => format!("{advice} (not checked: {steps:.0e} steps at that dt)"),
        Rerun::Passed | Rerun::Found => {
            format!("{advice} (checked: at dt = {dt:e} s the run passes t = {until:.4} s)")
        }
        Rerun::Failed(SimError::Diverged { time: t, .. }) => {
            let loads: Vec<String> = scene
                .fingers
                .iter()
                .enumerate()
                .filter(|(_, f)| f.force.length() > 0.0)
                .map(|(k, f)| format!("finger {}: {:.4e} N", k + 1, f.force.length()))
                .collect();
            format!(
                "A smaller dt does not help (checked: at dt = {dt:e} s it diverges too, at t = {t:.4} s): the loads ({}) or the stiffness (E = {young_modulus:e} Pa, alpha = {alpha:e}) are more than this object and contact can take; lower them",
                if loads.is_empty() {
                    "none on fingers".to_string()
                } else {
                    loads.join(", ")
                }
            )
        }
        Rerun::Failed(_) => {
            format!("{advice} (not checked: the run at dt = {dt:e} s failed otherwise)")
        }
    };
    SimError::Diverged {
        time,
        suggest_dt: Some(dt),
        advice,
        what,
        step,
        dt: old_dt,
        young_modulus,
        alpha,
    }
}

/// Whether a finger that went through still does at `dt`, run again to a little past where it
/// did: advice only once checked.
fn check_tunnelling(
    scene: &softgrip_core::Scene,
    f: &softgrip_core::watch::Finding,
    dt: f64,
) -> String {
    let until = 1.5 * f.time + 10.0 * scene.simulation.dt;
    match rerun(scene, dt, until, Some(f)) {
        Rerun::TooLong(steps) => {
            format!("A smaller dt may help (not checked: {steps:.0e} steps at dt = {dt:e} s).")
        }
        Rerun::Failed(_) => {
            format!("At dt = {dt:e} s the run fails instead: lower the load or the finger's speed.")
        }
        Rerun::Found => format!(
            "A smaller dt does not help (checked: at dt = {dt:e} s it passes through too): lower the load or the finger's speed, or stiffen the contact (contact_stiffness_scale)."
        ),
        Rerun::Passed => format!(
            "Use dt <= {dt:e} s (checked: at that dt it does not pass through by t = {until:.4} s)."
        ),
    }
}
