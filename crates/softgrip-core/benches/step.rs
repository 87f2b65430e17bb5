//! Criterion benchmarks: one step of the thesis scene at three mesh sizes,
//! and the kernels inside it. One simulated second is measured by
//! `softgrip bench` (see docs/results/benchmarks.md), which is too long for criterion's
//! repeated sampling at the finest mesh.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use softgrip_core::Simulation;
use softgrip_core::bench::thesis_scene_with_edge;
use softgrip_core::solver::System;

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("thesis_step");
    group.sample_size(10);
    for edge_mm in [4.0, 2.5, 1.6] {
        let Ok(mut sim) = Simulation::new(&thesis_scene_with_edge(edge_mm * 1e-3)) else {
            continue;
        };
        // Into contact first, so the step measured includes contact work.
        for _ in 0..200 {
            if sim.step().is_err() {
                break;
            }
        }
        group.bench_function(
            format!("edge_{edge_mm}mm_{}tets", sim.model.tets.len()),
            |b| b.iter(|| sim.step().is_ok()),
        );
    }
    group.finish();
}

fn build(c: &mut Criterion) {
    let scene = thesis_scene_with_edge(4e-3);
    c.bench_function("model_build_4mm", |b| {
        b.iter(|| Simulation::new(&scene).is_ok())
    });
}

/// The kernels of one step on the 4 mm thesis scene with the finger pressed
/// in (0.3 s after release): what `softgrip bench`'s stage timers add up.
fn kernels(c: &mut Criterion) {
    let Ok(mut sim) = Simulation::new(&thesis_scene_with_edge(4e-3)) else {
        return;
    };
    if sim.run_until(0.3).is_err() {
        return;
    }
    let (model, state) = (&sim.model, &sim.state);
    let total = model.particle_count() + model.fingers.len();
    let mut force = vec![DVec3::ZERO; total];
    let mut system = System::default();
    let mut group = c.benchmark_group("kernels_4mm");
    group.bench_function("springs", |b| {
        b.iter(|| {
            system.begin(model, model.dt);
            softgrip_core::forces::springs::accumulate(model, state, &mut force, &mut system);
        })
    });
    group.bench_function("volume", |b| {
        b.iter(|| {
            system.begin(model, model.dt);
            softgrip_core::forces::volume::accumulate(model, state, &mut force, &mut system);
        })
    });
    system.begin(model, model.dt);
    softgrip_core::step::integrate::set_mask(model, state, &mut system);
    softgrip_core::forces::springs::accumulate(model, state, &mut force, &mut system);
    softgrip_core::forces::volume::accumulate(model, state, &mut force, &mut system);
    system.finish(&model.tets, 0);
    let x: Vec<DVec3> = (0..total)
        .map(|i| DVec3::new(1.0, (i as f64).sin(), 0.5) * system.mask[i])
        .collect();
    let mut y = vec![DVec3::ZERO; total];
    let mut second = Vec::new();
    group.bench_function("system_multiply", |b| {
        b.iter(|| system.multiply(&model.tets, black_box(&x), &mut y, &mut second))
    });
    let mut diagnosed = state.clone();
    group.bench_function("diagnostics", |b| {
        b.iter(|| softgrip_core::step::update_diagnostics(model, &mut diagnosed))
    });
    group.bench_function("limit_check", |b| {
        b.iter(|| {
            softgrip_core::step::constraints::max_violation(model, black_box(&state.positions))
        })
    });
    group.finish();
}

criterion_group!(benches, step, build, kernels);
criterion_main!(benches);
