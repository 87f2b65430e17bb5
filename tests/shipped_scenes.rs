//! Every scene in assets/scenes parses, builds and steps; the built-in
//! thesis scene is the file it claims to be.

use softgrip::{Scene, Simulation};

#[test]
fn every_shipped_scene_builds_and_steps() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .expect("scenes folder")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .collect();
    names.sort();
    assert!(names.len() >= 7, "{names:?}");
    for path in names {
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut sim = Simulation::new(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for _ in 0..20 {
            sim.step()
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
    }
}

#[test]
fn thesis_scene_has_the_thesis_values() {
    let s = Scene::thesis();
    assert_eq!(s.object.young_modulus, 57.6e3);
    assert_eq!(s.model.tau_s, Some(0.16));
    assert_eq!(s.model.tau_c, Some(0.155));
    assert_eq!(s.model.alpha, 6e6);
    assert_eq!(s.fingers[0].mass, 0.992);
    // Its one extension: the bulk modulus that keeps it from collapsing.
    assert_eq!(s.model.bulk_modulus, 9.6e5);
    // Every contract key is explicit; only softgrip's extension keys default.
    let contract: Vec<_> = s
        .defaults_applied
        .iter()
        .filter(|d| {
            ![
                "cg_tolerance",
                "cg_max_iterations",
                "guide_speed",
                "constraint_tolerance",
                "limit_stiffness",
            ]
            .iter()
            .any(|k| d.contains(k))
        })
        .collect();
    assert!(contract.is_empty(), "{contract:?}");
    // Written back and read again, it is the same scene.
    let again = Scene::from_toml_str(&s.to_toml(), "round trip").expect("round trip");
    assert_eq!(again.object, s.object);
    assert_eq!(again.fingers, s.fingers);
    assert_eq!(again.model, s.model);
}
