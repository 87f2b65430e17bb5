//! Command-line interface: errors are reported once, here, with `anyhow`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use softgrip_core::Simulation;
use softgrip_core::output::TrajectoryWriter;
use softgrip_core::scene::Scene;

mod diagnose;
mod grasp;
mod lab;

#[derive(Parser)]
#[command(
    name = "softgrip",
    version,
    about = "Soft-object grasp simulation (mass-spring-damper model with Hunt-Crossley contact)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene headless (the built-in thesis scene when none is given).
    Run {
        /// Scene file (.toml); omit for the built-in thesis scene.
        scene: Option<PathBuf>,
        /// Write ParaView files (frame_*.vtu, trajectory.pvd) and fingers.csv here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Simulated seconds (default: the scene's [simulation] duration).
        #[arg(long)]
        duration: Option<f64>,
        /// Frames per simulated second written with --out.
        #[arg(long, default_value_t = 50.0)]
        fps: f64,
        /// With --out: also write each frame's deformed surface
        /// (surface_NNNNN.stl or .obj).
        #[arg(long, value_enum)]
        surface: Option<softgrip_core::output::surface::SurfaceFormat>,
    },
    /// Quasi-static load steps: set the first force-controlled finger's load to
    /// each value in turn (N, along the scene's force direction) and step to rest.
    Ramp {
        scene: Option<PathBuf>,
        /// Loads in N, applied in this order (e.g. 1,2,4,9.73).
        #[arg(long, value_delimiter = ',', required = true)]
        loads: Vec<f64>,
        /// Simulated seconds allowed per load to come to rest.
        #[arg(long, default_value_t = 20.0)]
        max_seconds: f64,
        /// Rest: every particle and finger slower than this (m/s).
        #[arg(long, default_value_t = 1e-5)]
        rest_speed: f64,
    },
    /// Check a scene: print the defaults it relies on, the mesh and the model.
    Check { scene: Option<PathBuf> },
    /// Print the built-in thesis scene as TOML (a starting point for your own).
    Scene,
    /// Simulate a lab recording and measure the error as the thesis does
    /// (NRMSE, eq. 45-46): per marker, per axis, overall.
    Compare {
        /// The recording's .toml header.
        recording: PathBuf,
        /// Also write the figures as JSON (nrmse, rmse_m, nrmse_all, params).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Also replay on a mesh 0.8 times as fine and, for a time series,
        /// at half the step, and say how far the markers move against the
        /// noise (estimated from the residual, as `diagnose` does): how
        /// much of the error the model's own discretisation can make.
        #[arg(long)]
        discretisation: bool,
        #[command(flatten)]
        report: lab::ReportArgs,
    },
    /// Sweep scene parameters over a grid against a recording (thesis Fig.
    /// 19-23), in parallel, and report the NRMSE of each point and the best.
    Sweep {
        recording: PathBuf,
        /// name=start:end:count (add :log for log spacing) or name=v1,v2,...;
        /// once for a curve, twice for a grid. Names: young_modulus, alpha,
        /// tau_s, tau_c, damping_ratio, friction, ... (an unknown name lists
        /// them all).
        #[arg(long = "param", required = true)]
        params: Vec<String>,
        /// Write every point as CSV (the report has it too).
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Simulations at once (0: one per core).
        #[arg(long, default_value_t = 0)]
        workers: usize,
        /// Also write the figures as JSON (best point's nrmse, rmse_m, params).
        #[arg(long)]
        json: Option<PathBuf>,
        #[command(flatten)]
        report: lab::ReportArgs,
    },
    /// Make a recording from a scene (softgrip's own simulation, with
    /// Gaussian noise): for testing fits and sweeps where the truth is known.
    Synth {
        /// Scene file (.toml); omit for the built-in thesis scene.
        scene: Option<PathBuf>,
        /// Loads in N, one quasi-static sample each (along the first
        /// force-controlled finger's `force` direction).
        #[arg(long, value_delimiter = ',', required = true)]
        loads: Vec<f64>,
        /// Object markers NAME=X,Y,Z on the undeformed surface (m);
        /// default for a cuboid: 9 on the top face and 5 along the front.
        #[arg(long = "marker")]
        markers: Vec<String>,
        /// Observed axes, e.g. xz for a side camera.
        #[arg(long, default_value = "xyz")]
        axes: String,
        /// Standard deviation of the noise on each coordinate (m).
        #[arg(long, default_value_t = 1e-4)]
        noise: f64,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Directory for scene.toml, recording.toml and samples.csv.
        #[arg(long)]
        out: PathBuf,
    },
    /// Fit scene parameters to a recording: NRMSE minimised by a bounded
    /// Nelder-Mead search after a space-filling design, with each
    /// parameter's noise-implied uncertainty and +/-10 % sensitivity
    /// (unidentifiable parameters are flagged).
    Fit {
        recording: PathBuf,
        /// Parameters to fit: name or name=LOW:HIGH (add :log or :lin),
        /// comma-separated or repeated, e.g. --params young_modulus,alpha
        /// --params tau_c=0.05:0.3. Default bounds: 1/10 to 10 times the
        /// scene's modulus, 1/100 to 100 times its alpha, 0.02 to 0.5 for
        /// tau_s and tau_c.
        #[arg(long, required = true, num_args = 1..)]
        params: Vec<String>,
        /// Simulations at most in the search.
        #[arg(long, default_value_t = 400)]
        max_evaluations: usize,
        /// Simulations at once (0: one per core).
        #[arg(long, default_value_t = 0)]
        workers: usize,
        /// Also write the figures as JSON (nrmse before and after, fitted params, ...).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write the fitted scene here (TOML).
        #[arg(long)]
        scene_out: Option<PathBuf>,
        #[command(flatten)]
        report: lab::ReportArgs,
    },
    /// Young's modulus from a compression recording (thesis eq. 49-50): a
    /// line through the initial linear part of the stress-strain curve.
    Modulus {
        recording: PathBuf,
        /// Also write the figures as JSON (young_modulus in Pa, ...).
        #[arg(long)]
        json: Option<PathBuf>,
        #[command(flatten)]
        report: lab::ReportArgs,
    },
    /// Missing-physics diagnosis: fit the nominal model (E, alpha, tau_s,
    /// tau_c), locate what it still misses against the noise, fit a
    /// catalogue of candidate effects (table-friction, strain-stiffening,
    /// viscoelastic-creep, finger-friction, heterogeneous-stiffness,
    /// load-loss; damping for time series) and name the one(s) that
    /// explain it, or "none".
    Diagnose {
        recording: PathBuf,
        /// Baseline parameters to keep at the scene's values (e.g. alpha).
        #[arg(long, num_args = 1..)]
        lock: Vec<String>,
        /// Ranges you know parameters lie in, NAME=LOW:HIGH (e.g.
        /// young_modulus=30e3:120e3 for a modulus measured at 60 kPa to
        /// within a factor of 2): every fit searches only there. A fit
        /// that needs E far from a measured small-strain value is
        /// absorbing physics the model lacks (strain-stiffening, creep).
        #[arg(long, num_args = 1..)]
        bound: Vec<String>,
        /// Simulations at most for the baseline fit (each candidate's fit
        /// gets 20 per parameter).
        #[arg(long, default_value_t = 80)]
        max_evaluations: usize,
        /// Simulations at once (0: one per core).
        #[arg(long, default_value_t = 0)]
        workers: usize,
        /// Also write the spec's JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
        #[command(flatten)]
        report: lab::ReportArgs,
    },
    /// The diagnosis's proof on concealed data: make the suite of
    /// recordings (each effect at two strengths, three controls, one with
    /// two effects), diagnose each blind and write DIAGNOSIS.md.
    Prove {
        /// Where the recordings go.
        #[arg(long, default_value = "target/prove")]
        out: PathBuf,
        /// Only the cases whose name contains this (e.g. load-loss).
        #[arg(long, default_value = "")]
        only: String,
        /// The report.
        #[arg(long, default_value = "DIAGNOSIS.md")]
        report: PathBuf,
        /// Tell the diagnosis E was measured to within this factor of the
        /// nominal value either way (`diagnose --bound`); by default it is
        /// not told.
        #[arg(long)]
        e_measured_within: Option<f64>,
        /// Make the truths with this edge length, m, instead of the
        /// suite's 0.004: 0.005, the diagnosis's own, takes the mesh's form
        /// error out of the proof; a finer one brings the data nearer a
        /// continuum, as a lab's are.
        #[arg(long)]
        truth_edge_length: Option<f64>,
    },
    /// Grasp and lift (e.g. assets/scenes/grasp_lift.toml): the fingers
    /// squeeze, lift after their start_time and hold; says whether friction
    /// held the object and how far it slid, and with --boundary bisects the
    /// least finger friction that holds it, against the force balance.
    Grasp {
        scene: PathBuf,
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
    },
    /// Mesh files: figures, conversion, and the mesh a scene uses.
    Mesh {
        #[command(subcommand)]
        action: MeshCommand,
    },
    /// Open the viewer on a scene (the built-in thesis scene when none is
    /// given); what `softgrip` alone does.
    #[cfg(feature = "gui")]
    View {
        scene: Option<PathBuf>,
        /// Override the scene's tetrahedron edge length (m).
        #[arg(long)]
        edge_length: Option<f64>,
        /// Benchmark: run this many seconds with the solver playing as fast
        /// as it goes and the view redrawn continuously, print the UI frame
        /// times and close (BENCHMARKS.md).
        #[arg(long)]
        measure: Option<f64>,
        /// With --measure: keep the solver paused, for comparison.
        #[arg(long)]
        paused: bool,
        /// Open this lab recording (its .toml header) at start: its scene
        /// replaces the one given, and it is replayed for the Recording
        /// panel.
        #[arg(long)]
        recording: Option<PathBuf>,
    },
    /// Render a scene at a simulated time to a PNG, headless (no window, no
    /// display: a software adapter where there is no GPU).
    #[cfg(feature = "gui")]
    Screenshot {
        /// Scene file (.toml); omit for the built-in thesis scene.
        scene: Option<PathBuf>,
        /// Simulated time of the picture (s).
        #[arg(long, default_value_t = 0.0)]
        at: f64,
        /// The PNG to write.
        #[arg(long)]
        out: PathBuf,
        /// Image size, WIDTHxHEIGHT in pixels.
        #[arg(long, default_value = "800x600", value_parser = parse_size)]
        size: (u32, u32),
        #[arg(long, value_enum, default_value_t = softgrip_viewer::render::View::Iso)]
        view: softgrip_viewer::render::View,
        /// Colour the object by a field, with a colour bar at the right
        /// (its range is printed).
        #[arg(long, value_enum)]
        color: Option<softgrip_core::fields::Field>,
        /// Draw the springs as lines.
        #[arg(long)]
        wireframe: bool,
        /// Leave the surface out (with --wireframe: every spring inside shows).
        #[arg(long)]
        no_surface: bool,
        /// Cut the object open: AXIS:FRACTION, e.g. y:0.5 hides the
        /// elements in the front half (y below the middle); a leading `-`
        /// (-y:0.5) hides the other side.
        #[arg(long, value_parser = parse_cut)]
        cut: Option<softgrip_viewer::render::Cut>,
    },
    /// Measure wall seconds per simulated second of the thesis scene at several mesh sizes.
    Bench {
        /// Edge lengths in mm.
        #[arg(long, value_delimiter = ',', default_values_t = vec![4.0, 2.5, 1.6])]
        edges: Vec<f64>,
        /// Threads per simulation: 1, or 2 (a helper thread takes half the
        /// work; same results bit for bit). Default: 2 where there are two cores.
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Simulated seconds per measurement.
        #[arg(long, default_value_t = 1.0)]
        seconds: f64,
        /// Instead: the thesis scene at the first edge length with each
        /// physics option (table, stiffening, viscoelastic, regions, guide
        /// friction, self-collision, neo-Hookean, ...) on in turn.
        #[arg(long)]
        options: bool,
        /// Instead: time the full diagnosis of these `softgrip prove` cases
        /// (comma-separated names, e.g. load-loss-weak,control-1): 8 load
        /// steps, 8 markers and the finger, x and z; writing the recording
        /// is not timed.
        #[arg(long, value_delimiter = ',')]
        diagnosis: Vec<String>,
    },
}

#[derive(Subcommand)]
enum MeshCommand {
    /// Nodes, tetrahedra, boundary facets, volume, bounds, edge lengths,
    /// smallest dihedral angle, worst aspect ratio, parts; and what the
    /// checks would change.
    Info { file: PathBuf },
    /// Convert between formats (.msh, .node/.ele, .vtk); the output's
    /// extension picks the format unless --format says (msh22 for Gmsh 2.2).
    Convert {
        input: PathBuf,
        output: PathBuf,
        #[arg(long, value_enum)]
        format: Option<softgrip_core::mesh::io::Format>,
    },
    /// Write the mesh a scene uses (built-in shapes meshed at their edge
    /// length; mesh files checked, scaled and placed).
    Make {
        scene: PathBuf,
        output: PathBuf,
        #[arg(long, value_enum)]
        format: Option<softgrip_core::mesh::io::Format>,
    },
}

fn mesh_command(action: MeshCommand) -> Result<()> {
    use softgrip_core::mesh::{checks, io};
    let format_for = |path: &Path, format: Option<io::Format>| {
        format.or_else(|| io::Format::of(path)).with_context(|| {
            format!(
                "{}: give a .msh, .node, .ele, .vtk or .vtu name, or --format",
                path.display()
            )
        })
    };
    match action {
        MeshCommand::Info { file } if io::is_surface(&file) => {
            let surface = softgrip_core::mesh::surface::read(
                &std::fs::read(&file).with_context(|| format!("reading {}", file.display()))?,
                &file.display().to_string(),
                file.extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("obj")),
            )?;
            println!(
                "{} (a surface: tetrahedralized when a scene uses it)",
                file.display()
            );
            println!("  triangles: {}", surface.triangles.len());
            println!("  vertices (welded): {}", surface.vertices.len());
            println!("  enclosed volume: {:.6e} m^3", surface.volume());
            println!("  mean edge: {:.3} mm", 1e3 * surface.mean_edge());
            softgrip_core::mesh::surface::check(&surface, &file.display().to_string())?;
            println!("  closed, consistently oriented, outward, not self-intersecting");
            Ok(())
        }
        MeshCommand::Info { file } => {
            let imported = io::read(&file)?;
            let raw = &imported.mesh;
            println!("{}", file.display());
            println!(
                "  as written: {} nodes, {} tetrahedra",
                raw.nodes.len(),
                raw.tets.len()
            );
            for w in &imported.warnings {
                println!("  note: {w}");
            }
            let mut mesh = imported.mesh.clone();
            let report = checks::repair(&mut mesh)
                .with_context(|| format!("{}: the mesh cannot be used", file.display()))?;
            for w in &report.warnings {
                println!("  check: {w}");
            }
            let stats = mesh.stats();
            let (lo, hi) = mesh.bounds();
            let (angle, aspect) = checks::shape_figures(&mesh);
            println!("  nodes: {}", stats.nodes);
            println!("  tetrahedra: {}", stats.tets);
            println!("  boundary facets: {}", stats.boundary_facets);
            println!("  volume: {:.6e} m^3", stats.volume);
            println!(
                "  bounds: ({:.4}, {:.4}, {:.4}) .. ({:.4}, {:.4}, {:.4}) m, size {:.4} x {:.4} x {:.4} m",
                lo.x,
                lo.y,
                lo.z,
                hi.x,
                hi.y,
                hi.z,
                hi.x - lo.x,
                hi.y - lo.y,
                hi.z - lo.z
            );
            println!(
                "  edges: {:.3} .. {:.3} mm",
                1e3 * stats.min_edge,
                1e3 * stats.max_edge
            );
            println!("  smallest dihedral angle: {angle:.2} degrees");
            println!("  worst aspect ratio (longest edge / smallest height): {aspect:.2}");
            println!("  connected parts: {}", report.parts);
            Ok(())
        }
        MeshCommand::Convert {
            input,
            output,
            format,
        } => {
            let format = format_for(&output, format)?;
            let imported = io::read(&input)?;
            for w in &imported.warnings {
                eprintln!("warning: {}: {w}", input.display());
            }
            let mut mesh = imported.mesh;
            let report = checks::repair(&mut mesh)
                .with_context(|| format!("{}: the mesh cannot be used", input.display()))?;
            for w in &report.warnings {
                eprintln!("warning: {}: {w}", input.display());
            }
            let written = io::write(&mesh, &output, format)
                .with_context(|| format!("writing {}", output.display()))?;
            for p in written {
                println!("wrote {}", p.display());
            }
            Ok(())
        }
        MeshCommand::Make {
            scene,
            output,
            format,
        } => {
            let format = format_for(&output, format)?;
            let scene = Scene::load(&scene)?;
            let (mesh, warnings) = softgrip_core::Model::load_mesh(&scene)?;
            for w in &warnings {
                eprintln!("warning: {w}");
            }
            let written = io::write(&mesh, &output, format)
                .with_context(|| format!("writing {}", output.display()))?;
            println!("{}", mesh.stats());
            for p in written {
                println!("wrote {}", p.display());
            }
            Ok(())
        }
    }
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        #[cfg(feature = "gui")]
        None => softgrip_viewer::viewer::run(Scene::thesis()),
        #[cfg(not(feature = "gui"))]
        None => {
            eprintln!(
                "softgrip: built without the viewer (feature `gui`); running the built-in thesis scene headless (see `softgrip --help`)."
            );
            run(None, None, None, 50.0, None)
        }
        #[cfg(feature = "gui")]
        Some(Command::View {
            scene,
            edge_length,
            measure,
            paused,
            recording,
        }) => load_scene(scene.as_deref()).and_then(|mut scene| {
            if let Some(edge) = edge_length {
                anyhow::ensure!(
                    edge.is_finite() && edge > 0.0,
                    "--edge-length {edge}: must be a positive length in metres"
                );
                scene.object.edge_length = edge;
            }
            let options = softgrip_viewer::viewer::Options {
                measure: measure.map(std::time::Duration::from_secs_f64),
                play: !paused,
                recording,
            };
            softgrip_viewer::viewer::run_with(scene, options)
        }),
        Some(Command::Run {
            scene,
            out,
            duration,
            fps,
            surface,
        }) => run(scene.as_deref(), out.as_deref(), duration, fps, surface),
        Some(Command::Check { scene }) => check(scene.as_deref()),
        Some(Command::Diagnose {
            recording,
            lock,
            bound,
            max_evaluations,
            workers,
            json,
            report,
        }) => diagnose::diagnose(
            &recording,
            &lock,
            &bound,
            max_evaluations,
            workers,
            json.as_deref(),
            &report,
        ),
        Some(Command::Prove {
            out,
            only,
            report,
            e_measured_within,
            truth_edge_length,
        }) => prove(
            &out,
            &only,
            &report,
            &softgrip_lab::prove::ProveOptions {
                e_measured_within,
                truth_edge_length,
            },
        ),
        Some(Command::Grasp {
            scene,
            hold,
            slip_bound,
            boundary,
            json,
        }) => load_scene(Some(&scene))
            .and_then(|scene| grasp::grasp(&scene, hold, slip_bound, boundary, json.as_deref())),
        Some(Command::Compare {
            recording,
            json,
            discretisation,
            report,
        }) => lab::compare(&recording, json.as_deref(), discretisation, &report),
        Some(Command::Modulus {
            recording,
            json,
            report,
        }) => lab::modulus(&recording, json.as_deref(), &report),
        Some(Command::Sweep {
            recording,
            params,
            csv,
            workers,
            json,
            report,
        }) => lab::sweep(
            &recording,
            &params,
            csv.as_deref(),
            workers,
            json.as_deref(),
            &report,
        ),
        Some(Command::Synth {
            scene,
            loads,
            markers,
            axes,
            noise,
            seed,
            out,
        }) => load_scene(scene.as_deref())
            .and_then(|scene| lab::synth(&scene, &loads, &markers, &axes, noise, seed, &out)),
        Some(Command::Fit {
            recording,
            params,
            max_evaluations,
            workers,
            json,
            scene_out,
            report,
        }) => lab::fit(
            &recording,
            &params,
            max_evaluations,
            workers,
            json.as_deref(),
            scene_out.as_deref(),
            &report,
        ),
        Some(Command::Mesh { action }) => mesh_command(action),
        Some(Command::Ramp {
            scene,
            loads,
            max_seconds,
            rest_speed,
        }) => ramp(scene.as_deref(), &loads, max_seconds, rest_speed),
        Some(Command::Scene) => {
            print!("{}", softgrip_core::scene::THESIS_SCENE);
            Ok(())
        }
        Some(Command::Bench {
            edges,
            seconds,
            threads,
            options,
            diagnosis,
        }) => {
            if !diagnosis.is_empty() {
                bench_diagnosis(&diagnosis)
            } else if options {
                bench_options(edges.first().copied().unwrap_or(4.0), seconds, threads)
            } else {
                bench(&edges, seconds, threads)
            }
        }
        #[cfg(feature = "gui")]
        Some(Command::Screenshot {
            scene,
            at,
            out,
            size,
            view,
            color,
            wireframe,
            no_surface,
            cut,
        }) => {
            let style = softgrip_viewer::render::Style {
                color_by: color,
                wireframe,
                surface: !no_surface,
                cut,
                ..Default::default()
            };
            screenshot(scene.as_deref(), at, &out, size, view, &style)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_text(&e));
            ExitCode::FAILURE
        }
    }
}

/// An error and its causes, each cause once: the library's errors already
/// quote their cause (the scene's error in the recording's, the system's
/// in a read error), and printing the chain as well said it twice.
fn error_text(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&cause);
        }
    }
    text
}

/// `WIDTHxHEIGHT`, each 16 to 8192 pixels.
#[cfg(feature = "gui")]
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("size {text:?}: expected WIDTHxHEIGHT, e.g. 800x600 (16 to 8192 each)");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

#[cfg(feature = "gui")]
fn screenshot(
    scene_path: Option<&Path>,
    at: f64,
    out: &Path,
    (width, height): (u32, u32),
    view: softgrip_viewer::render::View,
    style: &softgrip_viewer::render::Style,
) -> Result<()> {
    anyhow::ensure!(
        at.is_finite() && at >= 0.0,
        "--at {at}: the simulated time must be 0 or more (s)"
    );
    let scene = load_scene(scene_path)?;
    let mut sim = simulation(&scene)?;
    let steps = (at / sim.model.dt).round() as u64;
    let bar = progress_bar(steps, "steps");
    for _ in 0..steps {
        sim.step()?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let image =
        softgrip_viewer::render::screenshot(&sim.model, &sim.state, view, width, height, style)?;
    image
        .save(out)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "{}: {width}x{height}, t = {:.3} s, view {view:?}",
        out.display(),
        sim.state.time
    );
    if let Some(field) = style.color_by {
        let values = field.particle_values(&sim.model, &sim.state);
        let (lo, hi) = softgrip_core::fields::range(&values, field.signed());
        let k = field.display_scale();
        println!(
            "colour bar: {} from {:.4} {unit} (bottom) to {:.4} {unit} (top)",
            field.label(),
            lo * k,
            hi * k,
            unit = field.unit()
        );
    }
    Ok(())
}

/// `[-]AXIS:FRACTION`, e.g. `y:0.5`.
#[cfg(feature = "gui")]
fn parse_cut(text: &str) -> Result<softgrip_viewer::render::Cut, String> {
    let bad = || {
        format!(
            "cut {text:?}: expected AXIS:FRACTION with AXIS x, y or z (a leading - flips the side) and FRACTION from 0 to 1, e.g. y:0.5"
        )
    };
    let (axis, fraction) = text.split_once(':').ok_or_else(bad)?;
    let (flip, axis) = match axis.trim().strip_prefix('-') {
        Some(a) => (true, a),
        None => (false, axis.trim()),
    };
    let axis = match axis {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        _ => return Err(bad()),
    };
    let fraction: f32 = fraction.trim().parse().map_err(|_| bad())?;
    if !(0.0..=1.0).contains(&fraction) {
        return Err(bad());
    }
    Ok(softgrip_viewer::render::Cut {
        axis,
        fraction,
        flip,
    })
}

/// The scene's simulation; what loading its mesh changed or noticed goes
/// to stderr as warnings.
fn simulation(scene: &Scene) -> Result<Simulation> {
    let (mesh, warnings) = softgrip_core::Model::load_mesh(scene)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    Ok(Simulation::on_mesh(scene, mesh)?)
}

fn load_scene(path: Option<&Path>) -> Result<Scene> {
    match path {
        Some(p) => Ok(Scene::load(p)?),
        None => Ok(Scene::thesis()),
    }
}

/// A progress bar counting `unit`s (steps, samples, grid points).
pub(crate) fn progress_bar(len: u64, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{{bar:40}} {{pos}}/{{len}} {unit}  {{msg}}  [{{elapsed}} < {{eta}}]"
    )) {
        bar.set_style(style);
    }
    bar
}

fn run(
    scene_path: Option<&Path>,
    out: Option<&Path>,
    duration: Option<f64>,
    fps: f64,
    surface: Option<softgrip_core::output::surface::SurfaceFormat>,
) -> Result<()> {
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
    let steps = (duration / sim.model.dt).round() as u64;
    let frame_every = ((1.0 / fps.max(1e-9)) / sim.model.dt).round().max(1.0) as u64;
    let mut writer = match out {
        Some(dir) => {
            let mut w = TrajectoryWriter::new(dir)?;
            w.surface = surface;
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
            "warning: {inverted} of {} elements are inside out: the spring lattice has collapsed under this load and the result is not physical (see ACCURACY.md, \"Large loads\"). {remedy}",
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

fn ramp(scene_path: Option<&Path>, loads: &[f64], max_seconds: f64, rest_speed: f64) -> Result<()> {
    let scene = load_scene(scene_path)?;
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
    println!(
        "| load (N) | indentation (mm) | contact force (N) | penetration (mm) | volume error | inverted elements | steps to rest |"
    );
    println!("|---|---|---|---|---|---|---|");
    for &load in loads {
        sim.set_load(k, load);
        let bar = progress_bar((max_seconds / sim.model.dt) as u64, "steps");
        bar.set_message(format!("load {load} N"));
        let rest = sim.settle(tol, |s| bar.set_position(s));
        bar.finish_and_clear();
        let f = sim.state.fingers[k];
        let rest = match rest {
            Ok(r) => r.steps.to_string(),
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

fn check(scene_path: Option<&Path>) -> Result<()> {
    let scene = load_scene(scene_path)?;
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

/// Peak memory is the process's high-water mark, so sizes run smallest first.
fn prove(
    out: &Path,
    only: &str,
    report: &Path,
    options: &softgrip_lab::prove::ProveOptions,
) -> Result<()> {
    if let Some(f) = options.e_measured_within {
        anyhow::ensure!(
            f.is_finite() && f > 1.0,
            "--e-measured-within {f}: give a factor above 1 (2: E within half to twice the nominal)"
        );
    }
    if let Some(h) = options.truth_edge_length {
        anyhow::ensure!(
            h.is_finite() && (0.002..=0.01).contains(&h),
            "--truth-edge-length {h}: give an edge length in metres between 0.002 and 0.01 (the suite's is 0.004, the diagnosis's 0.005)"
        );
    }
    let bar = progress_bar(1, "recordings");
    let outcomes = softgrip_lab::prove::run(
        out,
        only,
        &softgrip_lab::diagnose::DiagnoseOptions::default(),
        options,
        &|i, total, name| {
            bar.set_length(total as u64);
            bar.set_position(i as u64);
            bar.set_message(name.to_string());
        },
    );
    bar.finish_and_clear();
    anyhow::ensure!(
        !outcomes.is_empty(),
        "--only {only:?}: no case of the suite matches"
    );
    let text = softgrip_lab::prove::report(&outcomes, options);
    std::fs::write(report, &text).with_context(|| format!("cannot write {}", report.display()))?;
    print!("{text}");
    Ok(())
}

/// The cost of each physics option on the thesis scene.
fn bench_options(edge_mm: f64, seconds: f64, threads: usize) -> Result<()> {
    println!("{}", softgrip_core::bench::machine_description());
    println!(
        "the thesis scene at {edge_mm} mm edges, {seconds} s simulated, each option on in turn"
    );
    println!("| option | ms per step | CG iterations per step | against none |");
    println!("|---|---|---|---|");
    let mut base = None;
    for (name, scene) in softgrip_core::bench::option_variants(edge_mm * 1e-3) {
        let r = softgrip_core::bench::scene_run(&scene, seconds, threads)?;
        let ms = 1e3 * r.wall_seconds / r.steps as f64;
        let reference = *base.get_or_insert(ms);
        println!(
            "| {name} | {ms:.2} | {:.1} | {:.2} x |",
            r.cg_iterations as f64 / r.steps as f64,
            ms / reference
        );
    }
    Ok(())
}

/// Wall time of the whole diagnosis of `softgrip prove` cases.
fn bench_diagnosis(names: &[String]) -> Result<()> {
    use softgrip_lab::diagnose::{DiagnoseOptions, diagnose};
    let cases = softgrip_lab::prove::seeded("");
    // Every name checked before the first (long) diagnosis starts.
    let mut chosen = Vec::new();
    for name in names {
        let Some(found) = cases.iter().find(|(_, c)| &c.name == name) else {
            anyhow::bail!(
                "no prove case {name}; the cases are: {}",
                cases
                    .iter()
                    .map(|(_, c)| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        };
        chosen.push((name, found));
    }
    println!("{}", softgrip_core::bench::machine_description());
    println!(
        "| case | distinct loads | samples | markers (object + finger) | simulations | seconds | named | peak memory (MiB) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, (seed, case)) in chosen {
        let dir =
            std::env::temp_dir().join(format!("softgrip-bench-{}-{name}", std::process::id()));
        // The seed `softgrip prove` gives the case: the same recording.
        let recording =
            softgrip_lab::prove::write_case(case, &dir, *seed).map_err(anyhow::Error::msg)?;
        let bar = progress_bar(1, "fits");
        let started = std::time::Instant::now();
        let d = diagnose(
            &recording,
            // As `softgrip prove` without --e-measured-within.
            &DiagnoseOptions::default(),
            &|done, total, what| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
                bar.set_message(what.to_string());
            },
        );
        let seconds = started.elapsed().as_secs_f64();
        bar.finish_and_clear();
        std::fs::remove_dir_all(&dir).ok();
        let d = d.map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let mut loads: Vec<f64> = recording.samples.iter().map(|s| s.load).collect();
        loads.sort_by(f64::total_cmp);
        loads.dedup();
        let named = if d.effects.is_empty() {
            d.verdict()
        } else {
            d.effects.join(" + ")
        };
        println!(
            "| {name} | {} | {} | {} + {} | {} | {seconds:.0} | {named} | {} |",
            loads.len(),
            recording.samples.len(),
            recording.markers.len(),
            recording.scene.fingers.len(),
            d.simulations,
            softgrip_core::bench::peak_memory_mib()
                .map(|m| format!("{m:.1}"))
                .unwrap_or_else(|| "n/a".into())
        );
    }
    Ok(())
}

fn bench(edges_mm: &[f64], seconds: f64, threads: usize) -> Result<()> {
    let mut edges_mm = edges_mm.to_vec();
    edges_mm.sort_by(|a, b| b.total_cmp(a));
    println!("{}", softgrip_core::bench::machine_description());
    println!(
        "| edge (mm) | particles | tetrahedra | ms per step | CG iterations per step | wall s per simulated s | peak memory (MiB) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut breakdown = Vec::new();
    for &e in &edges_mm {
        let r = softgrip_core::bench::thesis_scene_run(e * 1e-3, seconds, threads)?;
        breakdown.push((e, r));
        println!(
            "| {:.1} | {} | {} | {:.2} | {:.1} | {:.2} | {} |",
            e,
            r.particles,
            r.tets,
            1e3 * r.wall_seconds / r.steps as f64,
            r.cg_iterations as f64 / r.steps as f64,
            r.wall_seconds / r.simulated_seconds,
            softgrip_core::bench::peak_memory_mib()
                .map(|m| format!("{m:.1}"))
                .unwrap_or_else(|| "n/a".into())
        );
    }
    println!();
    println!("| edge (mm) | forces | solve (CG) | projection | diagnostics |");
    println!("|---|---|---|---|---|");
    for (e, r) in breakdown {
        let ms = |s: f64| format!("{:.3}", 1e3 * s / r.steps as f64);
        let t = r.stages;
        println!(
            "| {e:.1} | {} | {} | {} | {} |",
            ms(t.forces),
            ms(t.solve),
            ms(t.projection),
            ms(t.diagnostics)
        );
    }
    println!("(ms per step in each stage)");
    Ok(())
}
