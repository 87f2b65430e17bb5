//! Criterion benchmarks: one step of the thesis scene at three mesh sizes,
//! and the kernels inside it. One simulated second is measured by
//! `softgrip bench` (see BENCHMARKS.md), which is too long for criterion's
//! repeated sampling at the finest mesh.

use criterion::{Criterion, criterion_group, criterion_main};
use softgrip::Simulation;
use softgrip::bench::thesis_scene_with_edge;

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

criterion_group!(benches, step, build);
criterion_main!(benches);
