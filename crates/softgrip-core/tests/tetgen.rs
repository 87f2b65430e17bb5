//! With the `tetgen` feature (AGPL, off by default): the sphere surface Gmsh wrote
//! (tests/data/meshes/README.md) becomes tetrahedra of the ball's volume within the edge length
//! asked. Its own test target (`required-features`), so that `.ci/run`'s TetGen step compiles
//! only this file beside the core: `cargo test -p softgrip-core --features tetgen --test tetgen`.

use std::path::Path;

use softgrip_core::mesh::io::read_surface;

#[test]
fn the_sphere_surface_tetrahedralizes_to_the_ball() {
    use softgrip_core::mesh::tetrahedralize::tetrahedralize;
    let s = read_surface(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/sphere_surface.stl"),
    )
    .expect("sphere");
    // The surface's own edges are 2 mm: ask for 3 mm elements inside.
    let h = 0.003;
    let mut mesh = tetrahedralize(&s, h).expect("TetGen");
    let report = softgrip_core::mesh::checks::repair(&mut mesh).expect("sound");
    assert_eq!(report.reordered, 0, "no inverted element");
    assert_eq!(report.parts, 1);
    mesh.validate().expect("valid");
    let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.01f64.powi(3);
    let v = mesh.volume();
    assert!((v - ball).abs() < 0.02 * ball, "{v:e} vs {ball:e}");
    // The boundary is the surface's: the volume is the surface's volume.
    assert!(
        (v - s.volume()).abs() < 1e-9 * ball,
        "{v:e} vs {:e}",
        s.volume()
    );
    // The edge length bound: no element above a regular one of that edge.
    let largest = (0..mesh.tets.len())
        .map(|t| mesh.tet_volume(t))
        .fold(0.0, f64::max);
    let bound = softgrip_core::mesh::tetrahedralize::max_volume(h);
    assert!(
        largest <= bound * (1.0 + 1e-9),
        "largest {largest:e} > {bound:e}"
    );
}
