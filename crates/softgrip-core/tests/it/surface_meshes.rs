//! Closed surfaces (issue 4): `.stl` and `.obj` written by Gmsh and meshio
//! (tests/data/meshes/README.md) read with their triangle counts and
//! enclosed volumes; open, inside-out, inconsistent and self-intersecting
//! surfaces each get their own error. TetGen's tetrahedra of the sphere: tests/tetgen.rs.

use std::path::{Path, PathBuf};

use softgrip_core::mesh::io::read_surface;
use softgrip_core::mesh::surface::{self, Surface};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name)
}

#[test]
fn surfaces_written_by_the_tools_read_with_their_counts_and_volumes() {
    for (name, volume) in [
        ("sphere_surface.stl", 4.13085634109033e-06),
        ("sphere_surface_ascii.stl", 4.13085634943283e-06),
        ("sphere_surface.obj", 4.13085634943283e-06),
    ] {
        let s = read_surface(&fixture(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.triangles.len(), 806, "{name}");
        assert_eq!(s.vertices.len(), 405, "{name}");
        assert!(
            (s.volume() - volume).abs() < 1e-12 * volume,
            "{name}: {:e} vs {volume:e}",
            s.volume()
        );
    }
}

fn error_of(name: &str) -> String {
    read_surface(&fixture(name)).expect_err(name).to_string()
}

#[test]
fn open_and_inside_out_surfaces_are_errors_that_say_where() {
    let e = error_of("open_surface.stl");
    assert!(e.contains("not closed: 5 open edges near ("), "{e}");
    assert!(e.contains("0.0098) m"), "near the north pole: {e}");
    let e = error_of("inside_out.stl");
    assert!(e.contains("inside out"), "{e}");
}

fn sphere() -> Surface {
    read_surface(&fixture("sphere_surface.obj")).expect("sphere")
}

#[test]
fn inconsistent_and_self_intersecting_surfaces_are_errors() {
    let mut s = sphere();
    s.triangles[10].swap(1, 2);
    let e = surface::check(&s, "flipped")
        .expect_err("flipped")
        .to_string();
    assert!(e.contains("not consistently oriented"), "{e}");

    // Push one vertex through the far side of the ball.
    let mut s = sphere();
    let v = s.vertices[7];
    s.vertices[7] = -1.5 * v;
    let e = surface::check(&s, "crossed")
        .expect_err("crossed")
        .to_string();
    assert!(e.contains("intersects itself: triangles"), "{e}");

    // A non-manifold edge: a triangle repeated.
    let mut s = sphere();
    let t = s.triangles[3];
    s.triangles.push(t);
    s.triangles.push([t[0], t[2], t[1]]);
    let e = surface::check(&s, "fin").expect_err("fin").to_string();
    assert!(e.contains("shared by more than two triangles"), "{e}");

    // The sound sphere passes.
    surface::check(&sphere(), "sphere").expect("sound");
}

#[test]
fn malformed_surface_files_are_errors() {
    let cases: Vec<(&str, bool, Vec<u8>, &str)> = vec![
        ("empty", false, vec![], "too short"),
        ("empty obj", true, vec![], "no faces"),
        ("garbage", false, vec![7u8; 200], "neither a binary STL"),
        (
            "truncated binary",
            false,
            std::fs::read(fixture("sphere_surface.stl")).unwrap()[..1000].to_vec(),
            "but the file has 1000",
        ),
        (
            "truncated ascii",
            false,
            std::fs::read(fixture("sphere_surface_ascii.stl")).unwrap()[..5000].to_vec(),
            "bad:118: expected vertex",
        ),
        (
            "nan obj",
            true,
            b"v 0 0 nan\nf 1 1 1\n".to_vec(),
            "not a finite coordinate",
        ),
        (
            "index obj",
            true,
            b"v 0 0 0\nf 1 2 3\n".to_vec(),
            "refers to vertex 2",
        ),
    ];
    for (what, obj, bytes, expected) in cases {
        let e = surface::read(&bytes, "bad", obj)
            .expect_err(what)
            .to_string();
        assert!(e.contains(expected), "{what}: {e}");
    }
}
