//! Measured runs behind `softgrip bench` and the criterion benchmarks.

use crate::error::SimError;
use crate::scene::Scene;
use crate::step::{Simulation, StageSeconds};

/// What a timed run measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenchRun {
    /// Particles of the model.
    pub particles: usize,
    /// Tetrahedra of the model.
    pub tets: usize,
    /// Time steps taken.
    pub steps: u64,
    /// Simulated time at the end, s.
    pub simulated_seconds: f64,
    /// Wall time spent stepping, s.
    pub wall_seconds: f64,
    /// CG iterations summed over the steps.
    pub cg_iterations: u64,
    /// Where the time went, per stage of the step.
    pub stages: StageSeconds,
}

/// The thesis scene at another edge length.
pub fn thesis_scene_with_edge(edge_length: f64) -> Scene {
    let mut scene = Scene::thesis();
    scene.object.edge_length = edge_length;
    scene
}

/// Runs the thesis scene for `seconds` of simulated time and times it, on
/// `threads` threads (0 = the default, see [`Simulation::set_threads`]).
pub fn thesis_scene_run(
    edge_length: f64,
    seconds: f64,
    threads: usize,
) -> Result<BenchRun, SimError> {
    scene_run(&thesis_scene_with_edge(edge_length), seconds, threads)
}

/// The thesis scene with each of the physics options of issue 6 turned on
/// in turn (the first: none), for `softgrip bench --options`.
pub fn option_variants(edge_length: f64) -> Vec<(&'static str, Scene)> {
    use crate::scene::{AaBox, BulkPressure, Elasticity, Region, SupportKind};
    let base = thesis_scene_with_edge(edge_length);
    let with = |f: &dyn Fn(&mut Scene)| {
        let mut s = base.clone();
        f(&mut s);
        s
    };
    vec![
        ("none (the thesis scene)", base.clone()),
        (
            "table, friction 0.5",
            with(&|s| {
                s.support.kind = SupportKind::Table;
                s.support.friction = 0.5;
            }),
        ),
        ("strain stiffening 30", with(&|s| s.model.stiffening = 30.0)),
        (
            "compression ratio 2",
            with(&|s| s.model.compression_ratio = 2.0),
        ),
        (
            "viscoelastic g 0.3, tau 0.5 s",
            with(&|s| {
                s.model.prony_g = 0.3;
                s.model.prony_tau = 0.5;
            }),
        ),
        (
            "[[region]]: right half E x 3",
            with(&|s| {
                s.regions.push(Region {
                    region: AaBox {
                        min: glam::DVec3::new(0.0, -1.0, -1.0),
                        max: glam::DVec3::new(1.0, 1.0, 1.0),
                    },
                    young_modulus: 3.0 * s.object.young_modulus,
                    density: s.object.density,
                })
            }),
        ),
        (
            "guide friction 0.5 N",
            with(&|s| s.fingers[0].guide_friction = 0.5),
        ),
        ("self-collision", with(&|s| s.model.self_collision = true)),
        (
            "neo-Hookean, nodal pressures",
            with(&|s| {
                s.model.elasticity = Elasticity::NeoHookean;
                s.model.bulk_pressure = BulkPressure::Nodal;
            }),
        ),
        (
            "neo-Hookean, plain tetrahedra",
            with(&|s| {
                s.model.elasticity = Elasticity::NeoHookean;
                s.model.bulk_pressure = BulkPressure::Element;
            }),
        ),
        (
            "Rayleigh a 2 1/s, b 3e-4 s",
            with(&|s| {
                s.model.rayleigh_mass = 2.0;
                s.model.rayleigh_stiffness = 3e-4;
            }),
        ),
    ]
}

/// Runs `scene` for `seconds` of simulated time and times it.
pub fn scene_run(scene: &Scene, seconds: f64, threads: usize) -> Result<BenchRun, SimError> {
    let mut sim = Simulation::new(scene)?;
    sim.set_threads(threads);
    let steps = (seconds / sim.model.dt).round() as u64;
    let mut cg = 0;
    for _ in 0..steps {
        sim.step()?;
        cg += sim.state.stats.cg_iterations as u64;
    }
    Ok(BenchRun {
        particles: sim.model.particle_count(),
        tets: sim.model.tets.len(),
        steps,
        simulated_seconds: sim.state.time,
        wall_seconds: sim.wall_seconds,
        cg_iterations: cg,
        stages: sim.stage_seconds(),
    })
}

/// CPU model, core count and date, for docs/results/benchmarks.md.
pub fn machine_description() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    format!(
        "machine: {cpu}, {cores} cores available; softgrip {}",
        env!("CARGO_PKG_VERSION")
    )
}

/// The process's peak resident memory so far (MiB), where the OS reports it
/// (Linux `/proc/self/status`, `VmHWM`).
pub fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}
