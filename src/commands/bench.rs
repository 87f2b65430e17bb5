//! `softgrip bench`: wall time per simulated second of the thesis scene at
//! several mesh sizes, or of each physics option, or of whole diagnoses
//! (docs/results/benchmarks.md).

use anyhow::Result;

use super::progress::{progress_bar, show_stages};

/// Measure wall seconds per simulated second of the thesis scene at several mesh sizes.
#[derive(clap::Args)]
pub struct Args {
    /// Edge lengths in mm.
    #[arg(long, value_delimiter = ',', default_values_t = vec![4.0, 2.5, 1.6], value_parser = super::args::positive)]
    edges: Vec<f64>,
    /// Threads per simulation: 1, or 2 (a helper thread takes half the
    /// work; same results bit for bit). Default: 2 where there are two cores.
    #[arg(long, default_value_t = 0, value_parser = threads)]
    threads: usize,
    /// Simulated seconds per measurement.
    #[arg(long, default_value_t = 1.0, value_parser = super::args::positive)]
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
    /// Instead: replay these quasi-static recordings (comma-separated recording.toml paths)
    /// statically and by dynamic settling, side by side: seconds, Newton iterations per load,
    /// equilibria per second.
    #[arg(long, value_delimiter = ',')]
    statics: Vec<std::path::PathBuf>,
    /// Instead: time the grasp window of these scenes (comma-separated .toml paths with a
    /// `[grasp]` limit): the statics (both searches, on two threads) and the whole with its two
    /// dynamic confirmations.
    #[arg(long, value_delimiter = ',')]
    grasp_window: Vec<std::path::PathBuf>,
}

/// `--threads`: a simulation runs on its own thread and at most one helper.
fn threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n @ 0..=2) => Ok(n),
        _ => Err(format!(
            "{s}: give 1 (one thread), 2 (a helper thread takes half the work) or 0 (2 where there are two cores): a simulation uses at most two threads"
        )),
    }
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        edges,
        threads,
        seconds,
        options,
        diagnosis,
        statics,
        grasp_window,
    } = args;
    if !grasp_window.is_empty() {
        bench_grasp_window(&grasp_window)
    } else if !statics.is_empty() {
        bench_statics(&statics)
    } else if !diagnosis.is_empty() {
        bench_diagnosis(&diagnosis)
    } else if options {
        bench_options(edges.first().copied().unwrap_or(4.0), seconds, threads)
    } else {
        bench_sizes(&edges, seconds, threads)
    }
}

/// Peak memory is the process's high-water mark, so sizes run smallest first.
fn bench_sizes(edges_mm: &[f64], seconds: f64, threads: usize) -> Result<()> {
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
    println!("| edge (mm) | forces | solve (CG) | projection | arms | diagnostics |");
    println!("|---|---|---|---|---|---|");
    for (e, r) in &breakdown {
        let ms = |s: f64| format!("{:.3}", 1e3 * s / r.steps as f64);
        let t = r.stages;
        println!(
            "| {e:.1} | {} | {} | {} | {} | {} |",
            ms(t.forces),
            ms(t.solve),
            ms(t.projection),
            ms(t.arms),
            ms(t.diagnostics)
        );
    }
    println!("(ms per step in each stage)");
    print_force_stages(&breakdown);
    Ok(())
}

/// The force stages one by one (`softgrip_core::step::assemble`), both threads' time summed,
/// for the stages that ran.
fn print_force_stages(breakdown: &[(f64, softgrip_core::bench::BenchRun)]) {
    use softgrip_core::step::assemble::Stage;
    let ran: Vec<usize> = (0..Stage::ALL.len())
        .filter(|&k| breakdown.iter().any(|(_, r)| r.stages.stages[k] > 0.0))
        .collect();
    let names: Vec<&str> = ran.iter().map(|&k| Stage::ALL[k].name()).collect();
    println!();
    println!("| edge (mm) | {} |", names.join(" | "));
    println!("|---|{}", "---|".repeat(ran.len()));
    for (e, r) in breakdown {
        let ms: Vec<String> = ran
            .iter()
            .map(|&k| format!("{:.3}", 1e3 * r.stages.stages[k] / r.steps as f64))
            .collect();
        println!("| {e:.1} | {} |", ms.join(" | "));
    }
    println!("(ms per step in each force stage, both threads)");
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
    // The development seed: benchmarks never draw the scored seeds' cases.
    let cases = softgrip_lab::prove::seeded(softgrip_lab::prove::DEVELOPMENT_SEED, "");
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
            &show_stages(&bar),
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

/// Each recording replayed by the static solver and by dynamic settling in one run.
fn bench_statics(recordings: &[std::path::PathBuf]) -> Result<()> {
    use softgrip_core::scene::Settle;
    use softgrip_lab::recording::{Mode, Recording};
    use softgrip_lab::replay::{ReplayOptions, replay};
    println!("{}", softgrip_core::bench::machine_description());
    println!(
        "| recording | tetrahedra | loads | static (s) | Newton iterations per load | equilibria per s | dynamic (s) | dynamic / static | NRMSE static / dynamic | static with sensitivities (s, parameters) | a probe at E + 5 % from E's answers (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for path in recordings {
        let recording = Recording::load(path)?;
        if recording.mode != Mode::QuasiStatic {
            anyhow::bail!(
                "{}: not quasi-static: the static solver does not replay time series",
                path.display()
            );
        }
        let timed = |settle: Settle| -> Result<(f64, f64)> {
            let options = ReplayOptions {
                settle: Some(settle),
                ..ReplayOptions::default()
            };
            let started = std::time::Instant::now();
            let r = replay(&recording, &recording.scene, options, |_| {})?;
            Ok((started.elapsed().as_secs_f64(), r.errors.nrmse_all))
        };
        let (static_s, static_nrmse) = timed(Settle::Static)?;
        let warm = warm_probe(&recording)?;
        let (dynamic_s, dynamic_nrmse) = timed(Settle::Dynamic)?;
        let with = with_sensitivities(&recording)?;
        let (newton, loads, tetrahedra) = newton_per_load(&recording)?;
        println!(
            "| {} | {} | {loads} | {static_s:.2} | {newton} | {:.1} | {dynamic_s:.2} | {:.1} | {static_nrmse:.4} / {dynamic_nrmse:.4} | {with} | {warm} |",
            path.display(),
            tetrahedra,
            loads as f64 / static_s,
            dynamic_s / static_s,
        );
    }
    Ok(())
}

/// A fit's probe: E 5 % up, Newton started from each load's answer at the scene's E (s).
fn warm_probe(recording: &softgrip_lab::recording::Recording) -> Result<String> {
    use softgrip_core::scene::Settle;
    use softgrip_lab::replay::{ReplayOptions, replay};
    let kept = ReplayOptions {
        settle: Some(Settle::Static),
        keep_states: true,
        ..ReplayOptions::default()
    };
    let at_e = replay(recording, &recording.scene, kept, |_| {})?;
    let mut probe = recording.scene.clone();
    probe.object.young_modulus *= 1.05;
    let started = std::time::Instant::now();
    softgrip_lab::replay::replay_observing(
        recording,
        &probe,
        kept,
        Some(&at_e.states),
        None,
        |_| {},
    )?;
    let warm_s = started.elapsed().as_secs_f64();
    let warm = if softgrip_core::model::Model::from_scene(&probe)?.path_independent() {
        format!("{warm_s:.2}")
    } else {
        "n/a (path-dependent)".to_string()
    };
    Ok(warm)
}

/// The static replay with the sensitivities a baseline fit's Jacobian takes, where the scene
/// has them (s, parameters).
fn with_sensitivities(recording: &softgrip_lab::recording::Recording) -> Result<String> {
    use softgrip_core::scene::Settle;
    use softgrip_lab::replay::ReplayOptions;
    let names: Vec<&str> = ["young_modulus", "alpha", "tau_s", "tau_c"]
        .into_iter()
        .filter(|n| matches!(softgrip_lab::params::get(&recording.scene, n), Ok(Some(_))))
        .collect();
    let started = std::time::Instant::now();
    let (_, sensitivities) = softgrip_lab::sensitivity::replay_with_sensitivities(
        recording,
        &recording.scene,
        ReplayOptions {
            settle: Some(Settle::Static),
            ..ReplayOptions::default()
        },
        None,
        &names,
        |_| {},
    )?;
    let with_s = started.elapsed().as_secs_f64();
    let with = if sensitivities.is_some() {
        format!("{with_s:.2} ({})", names.len())
    } else {
        "n/a".to_string()
    };
    Ok(with)
}

/// The Newton iterations per load, counted on the same path of loads as the replay takes it;
/// the loads and the tetrahedra.
fn newton_per_load(
    recording: &softgrip_lab::recording::Recording,
) -> Result<(String, usize, usize)> {
    let mut sim = softgrip_core::Simulation::new(&recording.scene)?;
    let k = sim.load_finger();
    let (mut iterations, mut handed_over) = (0, 0);
    for s in &recording.samples {
        let from: Vec<_> = sim.state.fingers.iter().map(|f| f.applied_force).collect();
        if let Some(k) = k {
            sim.set_load(k, s.load);
        }
        let rest = softgrip_core::quasi_static::RestTolerance::default();
        match sim.settle_to_equilibrium(&from, Default::default(), rest, |_| {})? {
            softgrip_core::equilibrium::Settled::Static(r) => iterations += r.iterations,
            softgrip_core::equilibrium::Settled::Dynamic { .. } => handed_over += 1,
        }
    }
    let loads = recording.samples.len();
    let newton = match handed_over {
        0 => format!("{:.0}", iterations as f64 / loads as f64),
        n => format!(
            "{:.0} ({n} to time steps)",
            iterations as f64 / (loads - n).max(1) as f64
        ),
    };
    Ok((newton, loads, sim.model.tets.len()))
}

/// Wall time of the grasp window of each scene: the statics alone, then the dynamic
/// confirmations of its two bounds.
fn bench_grasp_window(scenes: &[std::path::PathBuf]) -> Result<()> {
    use softgrip_lab::grasp::window::Gripper;
    println!("{}", softgrip_core::bench::machine_description());
    println!(
        "| scene | tetrahedra | squeezes | statics (s) | window (N) | two dynamic lifts, side by side (s) | peak memory (MiB) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for path in scenes {
        let scene = super::load::load_scene(Some(path))?;
        let plan = softgrip_lab::grasp::plan::plan(&scene, Default::default())
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let gripper = Gripper::new(&scene, plan.options.profile)?;
        let started = std::time::Instant::now();
        let w = gripper.window(plan.options, |_| {})?;
        let statics = started.elapsed().as_secs_f64();
        let started = std::time::Instant::now();
        softgrip_lab::grasp::compute::confirm_bounds(&gripper, &scene, &w, &plan, &|_| {})?;
        let lifts = started.elapsed().as_secs_f64();
        println!(
            "| {} | {} | {} | {statics:.1} | {:.4} .. {} | {lifts:.1} | {} |",
            path.display(),
            softgrip_core::Model::from_scene(&scene)?.tets.len(),
            w.samples.len(),
            w.least_squeeze(),
            w.most_squeeze().map_or("-".into(), |m| format!("{m:.4}")),
            softgrip_core::bench::peak_memory_mib()
                .map(|m| format!("{m:.1}"))
                .unwrap_or_else(|| "n/a".into())
        );
    }
    Ok(())
}
