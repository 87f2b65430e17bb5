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
    #[arg(long, value_enum)]
    surface: Option<softgrip_core::output::surface::SurfaceFormat>,
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
        ascii: false,
    })
}

/// Time steps a `run` may take (hours of wall time on the built-in scene).
const MAX_STEPS: f64 = 1e7;
/// Frames a `run --out` may write.
const MAX_FRAMES: f64 = 1e5;

pub fn run(args: Args) -> Result<()> {
    let (scene_path, out) = (args.scene.as_deref(), args.out.as_deref());
    let (duration, fps, surface) = (args.duration, args.fps, args.surface);
    let scene = load_scene(scene_path)?;
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
    // A run of years or of a million frames is a typo, not a job: say so before it fills the disk.
    let steps = duration / sim.model.dt;
    anyhow::ensure!(
        steps <= MAX_STEPS,
        "{duration} s to simulate is {steps:.1e} steps of dt = {} s, more than {MAX_STEPS:.0e}: give a shorter --duration (or the scene's [simulation] duration)",
        sim.model.dt
    );
    if out.is_some() {
        let frames = duration * fps.min(1.0 / sim.model.dt);
        anyhow::ensure!(
            frames <= MAX_FRAMES,
            "--out would write {frames:.0} frames ({duration} s at {fps} frames/s), more than {MAX_FRAMES:.0}: give a lower --fps or a shorter --duration"
        );
    }
    let steps = steps.round() as u64;
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
    let bar = progress_bar(steps, "steps");
    let mut cg_total = 0u64;
    for i in 0..steps {
        if let Err(e) = sim.step() {
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
            return Err(e).with_context(|| format!("while running {name}"));
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

    let st = sim.state.stats;
    println!(
        "t = {:.3} s after {} steps in {:.2} s wall ({:.2} x real time)",
        sim.state.time,
        sim.state.step,
        sim.wall_seconds,
        sim.state.time / sim.wall_seconds.max(1e-12)
    );
    for (k, f) in sim.state.fingers.iter().enumerate() {
        let moved = f.position - sim.model.fingers[k].initial_position;
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
    println!(
        "volume error {:.3e} (|V - V0| / V0); contacts {}; spring-limit violation {:.2e}; energy {:.4e} J; top particle speed {:.1e} m/s",
        st.volume_error, st.contacts, st.limit_violation, st.energy, st.max_speed
    );
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
        println!(
            "warning: {inverted} of {} elements are inside out: the spring lattice has collapsed under this load and the result is not physical (see docs/results/accuracy.md, \"Large loads\"). {remedy}",
            sim.model.tets.len(),
        );
    }
    println!(
        "solver: {:.1} CG iterations per step on average, last residual {:.2e}",
        cg_total as f64 / steps.max(1) as f64,
        st.cg_residual
    );
    if let Some(w) = writer {
        let pvd = w.finish()?;
        println!("wrote {} (open in ParaView) and fingers.csv", pvd.display());
    }
    Ok(())
}
