//! Issue 4: tetrahedral mesh files written by the real tools (Gmsh 4.15.2,
//! meshio 5.3.5: `tests/data/meshes/README.md`), read back with the counts
//! and volumes those tools report; round trips through every writable
//! format; the checks every loaded mesh goes through; malformed files.

use std::path::{Path, PathBuf};

use glam::DVec3;
use softgrip_core::mesh::TetMesh;
use softgrip_core::mesh::checks::repair;
use softgrip_core::mesh::io::{self, Format, read_bytes_as};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name)
}

/// The table of `tests/data/meshes/README.md`: file, nodes, tetrahedra,
/// volume (m^3), and the cells the file holds besides.
const VOLUME_FIXTURES: &[(&str, usize, usize, f64, &str)] = &[
    ("cube_v22.msh", 143, 384, 8.0e-6, "264 triangles"),
    ("cube.msh", 143, 384, 8.0e-6, "264 triangles"),
    ("cube_binary.msh", 143, 384, 8.0e-6, "264 triangles"),
    ("cube_binary22.msh", 143, 384, 8.0e-6, "264 triangles"),
    ("sphere.msh", 118, 333, 3.93381983198049e-6, "198 triangles"),
    ("cube.vtk", 143, 384, 8.0e-6, ""),
    ("cube_binary.vtk", 143, 384, 8.0e-6, ""),
    ("cube_v42.vtk", 143, 384, 8.0e-6, ""),
    ("cube.node", 143, 384, 8.0e-6, ""),
    ("cube.vtu", 143, 384, 8.0e-6, ""),
    ("cube_binary.vtu", 143, 384, 8.0e-6, ""),
    // Written by VTK 9.7.2 itself, two triangles among the tetrahedra.
    ("cube_vtk_appended_raw.vtu", 143, 384, 8.0e-6, "2 triangles"),
    (
        "cube_vtk_appended_base64.vtu",
        143,
        384,
        8.0e-6,
        "2 triangles",
    ),
    ("cube_vtk_binary.vtu", 143, 384, 8.0e-6, "2 triangles"),
    ("cube_vtk_ascii.vtu", 143, 384, 8.0e-6, "2 triangles"),
];

#[test]
fn files_written_by_gmsh_and_meshio_read_with_their_counts_and_volumes() {
    for &(name, nodes, tets, volume, skipped) in VOLUME_FIXTURES {
        let imported = io::read(&fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mesh = &imported.mesh;
        assert_eq!(mesh.nodes.len(), nodes, "{name}: nodes");
        assert_eq!(mesh.tets.len(), tets, "{name}: tetrahedra");
        let v = mesh.volume();
        assert!(
            (v - volume).abs() < 1e-12 * volume,
            "{name}: volume {v:e}, the tools say {volume:e}"
        );
        if skipped.is_empty() {
            assert!(
                imported.warnings.is_empty(),
                "{name}: {:?}",
                imported.warnings
            );
        } else {
            let w = imported.warnings.join("; ");
            assert!(w.contains(skipped), "{name}: warnings {w:?}");
        }
        // Gmsh and meshio write positively oriented tetrahedra: nothing to repair.
        let mut m = mesh.clone();
        let report = repair(&mut m).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((report.reordered, report.merged, report.unused), (0, 0, 0));
        assert_eq!(report.parts, 1);
    }
}

#[test]
fn the_four_msh_variants_hold_the_same_mesh() {
    let read = |n: &str| io::read(&fixture(n)).expect(n).mesh;
    // The binary file holds Gmsh's doubles exactly; its ASCII files print
    // 16 digits (1 ulp off at most), meshio's copies are exact again.
    let reference = read("cube_binary.msh");
    for other in [
        "cube.msh",
        "cube_v22.msh",
        "cube_binary22.msh",
        "cube.vtk",
        "cube_binary.vtk",
        "cube_v42.vtk",
        "cube.node",
        "cube_binary.vtu",
        "cube.vtu",
        "cube_vtk_appended_raw.vtu",
        "cube_vtk_appended_base64.vtu",
        "cube_vtk_binary.vtu",
        "cube_vtk_ascii.vtu",
    ] {
        let m = read(other);
        assert_eq!(m.tets, reference.tets, "{other}: connectivity");
        assert_eq!(m.nodes.len(), reference.nodes.len());
        // meshio's ASCII .vtu keeps 12 significant digits.
        let tolerance = if other == "cube.vtu" { 1e-13 } else { 1e-17 };
        for (a, b) in m.nodes.iter().zip(&reference.nodes) {
            assert!((*a - *b).length() < tolerance, "{other}: {a} vs {b}");
        }
    }
}

#[test]
fn round_trips_through_every_writable_format() {
    let mesh = TetMesh::cylinder(0.01, 0.02, 0.004);
    let dir = std::env::temp_dir().join(format!("softgrip-roundtrip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    for (format, file) in [
        (Format::Msh, "m.msh"),
        (Format::Msh22, "m22.msh"),
        (Format::Vtk, "m.vtk"),
        (Format::Tetgen, "m.node"),
        (Format::Vtu, "m.vtu"),
    ] {
        let path = dir.join(file);
        io::write(&mesh, &path, format).expect("write");
        let back = io::read(&path).expect("read");
        assert!(back.warnings.is_empty(), "{file}: {:?}", back.warnings);
        assert_eq!(back.mesh.tets, mesh.tets, "{file}: connectivity");
        assert_eq!(back.mesh.nodes, mesh.nodes, "{file}: nodes, bit for bit");
        let (a, b) = (back.mesh.volume(), mesh.volume());
        assert!((a - b).abs() <= 1e-12 * b, "{file}: volume");
    }
    let _ = std::fs::remove_dir_all(dir);
}

fn tet_mesh(nodes: &[[f64; 3]], tets: &[[u32; 4]]) -> TetMesh {
    TetMesh {
        nodes: nodes.iter().map(|p| DVec3::from_array(*p)).collect(),
        tets: tets.to_vec(),
    }
}

#[test]
fn checks_reorder_inside_out_merge_duplicates_drop_unused_count_parts() {
    // Two tetrahedra sharing a face, the second inside out; a duplicate of
    // node 1; an unused node; then a separate third tetrahedron.
    let mut m = tet_mesh(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [1.0, 0.0, 0.0], // duplicate of 1
            [9.0, 9.0, 9.0], // unused
            [5.0, 5.0, 5.0],
            [6.0, 5.0, 5.0],
            [5.0, 6.0, 5.0],
            [5.0, 5.0, 6.0],
        ],
        &[[0, 1, 2, 3], [5, 3, 2, 4], [7, 8, 9, 10]],
    );
    let volume_before: f64 = (0..3).map(|t| m.tet_volume(t).abs()).sum();
    let report = repair(&mut m).expect("repairable");
    assert_eq!(report.reordered, 1);
    assert_eq!(report.merged, 1);
    assert_eq!(report.unused, 1);
    assert_eq!(report.parts, 2);
    assert_eq!(report.warnings.len(), 4, "{:?}", report.warnings);
    assert_eq!(m.nodes.len(), 9);
    assert!((0..3).all(|t| m.tet_volume(t) > 0.0));
    assert!((m.volume() - volume_before).abs() < 1e-15);
    m.validate().expect("valid now");

    // A flat tetrahedron cannot be repaired: the error says where.
    let mut flat = tet_mesh(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
        ],
        &[[0, 1, 2, 3], [0, 1, 2, 4]],
    );
    let e = repair(&mut flat).expect_err("degenerate").to_string();
    assert!(
        e.contains("tetrahedron 1") && e.contains("degenerate"),
        "{e}"
    );
}

/// Malformed files: each a specific error, none a panic.
#[test]
fn malformed_files_give_specific_errors() {
    let gmsh22 = std::fs::read_to_string(fixture("cube_v22.msh")).unwrap();
    let cases: Vec<(&str, Format, String, &str)> = vec![
        ("empty", Format::Msh, String::new(), "no $MeshFormat"),
        (
            "truncated",
            Format::Msh,
            gmsh22[..gmsh22.len() / 2].to_string(),
            "truncated",
        ),
        (
            "wrong node count",
            Format::Msh,
            gmsh22.replacen("$Nodes\n143", "$Nodes\n144", 1),
            "the section ended early",
        ),
        (
            "NaN coordinate",
            Format::Msh,
            gmsh22.replacen("$Nodes\n143\n1 0", "$Nodes\n143\n1 NaN", 1),
            "must be finite",
        ),
        (
            "index out of range",
            Format::Vtk,
            "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 7\nCELL_TYPES 1\n10\n".into(),
            "refers to node 7",
        ),
        (
            "binary garbage",
            Format::Msh,
            String::from_utf8_lossy(&[0u8, 159, 146, 150, 1, 2, 3, 255, 10, 36]).into_owned(),
            "expected a section",
        ),
        (
            "no tetrahedra",
            Format::Vtk,
            "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n".into(),
            "no tetrahedra (1 triangles)",
        ),
        (
            "not unstructured",
            Format::Vtk,
            "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\n".into(),
            "UNSTRUCTURED_GRID",
        ),
        (
            "huge count",
            Format::Msh,
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n99999999999999\n1 0 0 0\n".into(),
            "99999999999999 announced",
        ),
        (
            "tetgen missing point",
            Format::Tetgen,
            "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n---ele---\n1 4 0\n1 1 2 3 5\n".into(),
            "refers to node 5",
        ),
        (
            "tetgen wrong dimension",
            Format::Tetgen,
            "4 2 0 0\n---ele---\n".into(),
            "dimension 2",
        ),
        (
            "msh 4.0",
            Format::Msh,
            "$MeshFormat\n4 0 8\n$EndMeshFormat\n".into(),
            "4.0 is not supported",
        ),
    ];
    for (what, format, text, expected) in cases {
        let e = read_bytes_as(text.as_bytes(), format, "bad")
            .expect_err(what)
            .to_string();
        assert!(e.contains(expected), "{what}: {e:?} lacks {expected:?}");
        assert!(
            e.starts_with("bad"),
            "{what}: the error names the file: {e}"
        );
    }
}

/// Random mutations of valid files: flipped bytes, cut and repeated spans,
/// truncations. The readers return errors or meshes, never panic.
#[test]
fn mutated_files_never_panic() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let node = std::fs::read(fixture("cube.node")).unwrap();
    let ele = std::fs::read(fixture("cube.ele")).unwrap();
    let mut tetgen = node.clone();
    tetgen.extend_from_slice(b"\n---ele---\n");
    tetgen.extend_from_slice(&ele);
    let sources: Vec<(Format, Vec<u8>)> = vec![
        (Format::Msh, std::fs::read(fixture("cube_v22.msh")).unwrap()),
        (Format::Msh, std::fs::read(fixture("cube.msh")).unwrap()),
        (
            Format::Msh,
            std::fs::read(fixture("cube_binary.msh")).unwrap(),
        ),
        (
            Format::Msh,
            std::fs::read(fixture("cube_binary22.msh")).unwrap(),
        ),
        (Format::Vtk, std::fs::read(fixture("cube.vtk")).unwrap()),
        (
            Format::Vtk,
            std::fs::read(fixture("cube_binary.vtk")).unwrap(),
        ),
        (Format::Vtk, std::fs::read(fixture("cube_v42.vtk")).unwrap()),
        (Format::Vtu, std::fs::read(fixture("cube.vtu")).unwrap()),
        (
            Format::Vtu,
            std::fs::read(fixture("cube_binary.vtu")).unwrap(),
        ),
        (
            Format::Vtu,
            std::fs::read(fixture("cube_vtk_appended_raw.vtu")).unwrap(),
        ),
        (
            Format::Vtu,
            std::fs::read(fixture("cube_vtk_appended_base64.vtu")).unwrap(),
        ),
        (Format::Tetgen, tetgen),
    ];
    let mut outcomes = [0usize; 2];
    for (format, bytes) in &sources {
        for _ in 0..300 {
            let mut b = bytes.clone();
            for _ in 0..1 + next() % 4 {
                let len = b.len().max(1);
                let at = (next() as usize) % len;
                match next() % 5 {
                    0 => {
                        if let Some(x) = b.get_mut(at) {
                            *x ^= 1 << (next() % 8);
                        }
                    }
                    1 => b.truncate(at),
                    2 => {
                        let end = (at + (next() as usize) % 64).min(b.len());
                        b.drain(at..end);
                    }
                    3 => {
                        let end = (at + (next() as usize) % 64).min(b.len());
                        let span: Vec<u8> = b[at.min(end)..end].to_vec();
                        let at2 = (next() as usize) % len;
                        let at2 = at2.min(b.len());
                        b.splice(at2..at2, span);
                    }
                    _ => {
                        if let Some(x) = b.get_mut(at) {
                            *x = b"0123456789-.e \n$"[(next() % 16) as usize];
                        }
                    }
                }
            }
            let result = read_bytes_as(&b, *format, "mutant");
            outcomes[result.is_ok() as usize] += 1;
            if let Ok(imported) = result {
                // What reads is checked like any mesh; that must not panic either.
                let mut m = imported.mesh;
                let _ = repair(&mut m);
            }
        }
    }
    // Surfaces too: the readers and the checks.
    for (obj, name) in [
        (false, "sphere_surface.stl"),
        (false, "sphere_surface_ascii.stl"),
        (true, "sphere_surface.obj"),
    ] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        for _ in 0..100 {
            let mut b = bytes.clone();
            let len = b.len();
            let at = (next() as usize) % len;
            match next() % 3 {
                0 => b.truncate(at),
                1 => b[at] ^= 1 << (next() % 8),
                _ => {
                    let end = (at + (next() as usize) % 64).min(b.len());
                    b.drain(at..end);
                }
            }
            if let Ok(s) = softgrip_core::mesh::surface::read(&b, "mutant", obj) {
                let _ = softgrip_core::mesh::surface::check(&s, "mutant");
            }
        }
    }
    // Both kinds happen: the mutations are neither all fatal nor all harmless.
    assert!(outcomes[0] > 100 && outcomes[1] > 10, "{outcomes:?}");
}

/// The corpus in tests/data/meshes/malformed (its README lists how each
/// was made): every file gives its own specific error through the path a
/// scene or `softgrip mesh info` uses, naming the file.
#[test]
fn the_malformed_corpus_gives_specific_errors() {
    let expected: &[(&str, &str)] = &[
        (
            "bad_reference.obj",
            "bad_reference.obj:4: face refers to vertex 4, but 3 vertices",
        ),
        (
            "binary_garbage.msh",
            "binary_garbage.msh:1: expected a section such as $Nodes",
        ),
        ("empty.msh", "no $MeshFormat section"),
        ("empty.stl", "0 bytes: too short for a binary STL"),
        (
            "huge_count.msh",
            "99999999999999 announced, but the file has only 9 bytes left",
        ),
        ("index_out_of_range.msh", "tetrahedron 1 refers to node 999"),
        ("index_out_of_range.vtk", "tetrahedron 1 refers to node 7"),
        ("inside_out.stl", "the surface is inside out"),
        (
            "missing_point.node",
            "missing_point.ele: tetrahedron 1 refers to node 999",
        ),
        (
            "nan_coordinate.msh",
            "nan_coordinate.msh:38: an x coordinate is nan",
        ),
        (
            "nan_vertex.obj",
            "nan_vertex.obj:1: \"nan\" is not a finite coordinate",
        ),
        ("no_tetrahedra.vtk", "no tetrahedra (1 triangles)"),
        ("open_surface.stl", "not closed: 5 open edges near"),
        ("polydata.vtk", "polydata.vtk:4: DATASET POLYDATA"),
        (
            "truncated.msh",
            "truncated.msh:151: elements: 704 announced",
        ),
        (
            "truncated.stl",
            "announces 806 triangles, 40384 bytes, but the file has 1000",
        ),
        (
            "truncated.vtu",
            "DataArray connectivity is not closed (truncated?)",
        ),
        (
            "truncated_binary.msh",
            "the file ends inside an element's node",
        ),
        ("version_4_0.msh", "Gmsh format 4.0 is not supported"),
        (
            "wrong_counts.vtu",
            "384 offsets and 384 types for the 385 cells announced",
        ),
        (
            "wrong_node_count.msh",
            "found $EndNodes where a node number should be",
        ),
    ];
    let dir = fixture("malformed");
    let mut listed: Vec<String> = std::fs::read_dir(&dir)
        .expect("corpus")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n != "README.md" && !n.ends_with(".ele"))
        .collect();
    listed.sort();
    let mut names: Vec<String> = expected.iter().map(|(n, _)| n.to_string()).collect();
    names.sort();
    assert_eq!(listed, names, "every corpus file has its expected error");
    assert!(expected.len() >= 15);
    for (name, message) in expected {
        let path = dir.join(name);
        let error = if io::is_surface(&path) {
            io::read_surface(&path)
                .map(|_| ())
                .expect_err(name)
                .to_string()
        } else {
            io::read(&path)
                .and_then(|i| {
                    let mut m = i.mesh;
                    repair(&mut m)
                        .map(|_| ())
                        .map_err(|e| io::ImportError::at(name, None, e.to_string()))
                })
                .expect_err(name)
                .to_string()
        };
        assert!(
            error.contains(message),
            "{name}: {error:?} lacks {message:?}"
        );
        assert!(
            error.contains(name.split('.').next().unwrap()),
            "{name}: names the file: {error}"
        );
    }
}

/// The appended data's encoding is read as an XML attribute, whichever quotes and spacing the
/// writer used: `encoding = 'raw'` reads the raw file's mesh (a search for the text
/// `encoding="raw"` took it for base64), and an encoding softgrip cannot read is named.
#[test]
fn the_appended_encoding_is_read_as_an_attribute() {
    let bytes = std::fs::read(fixture("cube_vtk_appended_raw.vtu")).unwrap();
    let find = |b: &[u8], what: &[u8]| b.windows(what.len()).position(|w| w == what);
    let at = find(&bytes, b"encoding=\"raw\"").expect("the fixture's attribute");
    let with = |attribute: &[u8]| {
        let mut b = bytes[..at].to_vec();
        b.extend_from_slice(attribute);
        b.extend_from_slice(&bytes[at + b"encoding=\"raw\"".len()..]);
        b
    };
    let plain = read_bytes_as(&bytes, Format::Vtu, "raw").expect("the fixture");
    let spaced = read_bytes_as(&with(b"encoding = 'raw'"), Format::Vtu, "spaced")
        .expect("single quotes and spaces");
    assert_eq!(spaced.mesh.tets, plain.mesh.tets);
    assert_eq!(spaced.mesh.nodes, plain.mesh.nodes);
    let e = read_bytes_as(&with(b"encoding=\"hex\""), Format::Vtu, "hex")
        .expect_err("an encoding it cannot read")
        .to_string();
    assert!(
        e.starts_with("hex") && e.contains("encoding \"hex\""),
        "{e}"
    );
}
