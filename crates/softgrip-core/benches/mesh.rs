//! Criterion benchmarks of meshes in (issue 4): reading a ~100k-tetrahedron
//! mesh in each writable format, checking it, and (with `--features
//! tetgen`) tetrahedralizing a closed surface into ~100k tetrahedra.
//! Figures in docs/results/benchmarks.md.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use softgrip_core::mesh::TetMesh;
use softgrip_core::mesh::io::{self, Format};

fn read(c: &mut Criterion) {
    // 34 x 34 x 14 cubes of 6 tetrahedra: 97104.
    let mesh = TetMesh::cuboid(glam::DVec3::new(0.05, 0.05, 0.02), 0.0015);
    let dir = std::env::temp_dir().join(format!("softgrip-bench-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mut group = c.benchmark_group(format!("read_{}tets", mesh.tets.len()));
    group.sample_size(10);
    for (format, file) in [
        (Format::Msh, "m.msh"),
        (Format::Msh22, "m22.msh"),
        (Format::Vtk, "m.vtk"),
        (Format::Vtu, "m.vtu"),
        (Format::Tetgen, "m.node"),
    ] {
        let path = dir.join(file);
        io::write(&mesh, &path, format).expect("write");
        group.bench_function(format!("{format:?}"), |b| {
            b.iter(|| black_box(io::read(&path).expect("read")))
        });
    }
    group.bench_function("checks", |b| {
        b.iter(|| {
            let mut m = mesh.clone();
            black_box(softgrip_core::mesh::checks::repair(&mut m).expect("sound"))
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(dir);
}

#[cfg(feature = "tetgen")]
fn tetrahedralize(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes/sphere_surface.stl");
    let surface = io::read_surface(&path).expect("sphere");
    let mut group = c.benchmark_group("tetgen_sphere");
    group.sample_size(10);
    for h in [0.001, 0.0015] {
        let n = softgrip_core::mesh::tetrahedralize::tetrahedralize(&surface, h)
            .expect("TetGen")
            .tets
            .len();
        group.bench_function(format!("edge_{}mm_{n}tets", h * 1e3), |b| {
            b.iter(|| {
                black_box(
                    softgrip_core::mesh::tetrahedralize::tetrahedralize(&surface, h)
                        .expect("TetGen"),
                )
            })
        });
    }
    group.finish();
}

#[cfg(not(feature = "tetgen"))]
fn tetrahedralize(_c: &mut Criterion) {}

criterion_group!(benches, read, tetrahedralize);
criterion_main!(benches);
