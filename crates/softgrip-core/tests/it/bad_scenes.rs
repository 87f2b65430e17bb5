//! Acceptance 9: bad scenes give their own clear error; nothing panics.

use softgrip_core::Scene;
use softgrip_core::SimError;
use softgrip_core::Simulation;

const BASE: &str = r#"
[object]
shape = "cuboid"
size = [0.05, 0.05, 0.02]
edge_length = 0.005
"#;

/// Loads `text` as a scene file and builds the simulation; the error text.
fn error_of(text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("softgrip-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(format!(
        "case-{:x}.toml",
        text.len() * 31 + text.bytes().map(|b| b as usize).sum::<usize>()
    ));
    std::fs::write(&path, text).expect("write");
    let result = Scene::load(&path)
        .map_err(SimError::from)
        .and_then(|s| Simulation::new(&s));
    match result {
        Ok(_) => panic!("scene was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn expect(text: &str, fragments: &[&str]) {
    let msg = error_of(text);
    for f in fragments {
        assert!(msg.contains(f), "error {msg:?} does not mention {f:?}");
    }
}

#[test]
fn unknown_key_names_key_line_and_file() {
    expect(
        &format!("{BASE}youngs_modulus = 5e4\n"),
        &["youngs_modulus", "line 6", "case-", "[extra]"],
    );
}

#[test]
fn unknown_table() {
    expect(&format!("{BASE}[materail]\nx = 1\n"), &["materail"]);
}

#[test]
fn negative_modulus() {
    expect(
        &format!("{BASE}young_modulus = -5.0\n"),
        &["young_modulus", "-5", "from 1 Pa to 1e12 Pa", ":6"],
    );
}

#[test]
fn incompressible_poisson_ratio() {
    expect(
        &format!("{BASE}poisson_ratio = 0.5\n"),
        &["poisson_ratio", "0.5", "(-1, 0.5)"],
    );
}

#[test]
fn non_positive_time_step() {
    expect(&format!("[simulation]\ndt = 0.0\n{BASE}"), &["dt", "> 0"]);
}

#[test]
fn missing_shape() {
    expect(
        "[object]\nsize = [0.05, 0.05, 0.02]\n",
        &["shape is required"],
    );
}

#[test]
fn unknown_shape() {
    expect(
        "[object]\nshape = \"sphere\"\nradius = 0.02\n",
        &["shape", "\"sphere\"", "cuboid"],
    );
}

#[test]
fn cylinder_without_height() {
    expect(
        "[object]\nshape = \"cylinder\"\nradius = 0.02\n",
        &["height", "required"],
    );
}

#[test]
fn wrong_value_type() {
    expect(
        &format!("{BASE}density = \"heavy\"\n"),
        &["density", "type"],
    );
}

#[test]
fn finger_inside_the_object() {
    expect(
        &format!("{BASE}[[finger]]\nradius = 0.015\nposition = [0.0, 0.0, 0.03]\n"),
        &["finger", "inside", "z >="],
    );
}

#[test]
fn empty_fixed_box() {
    expect(
        &format!("{BASE}[[fixed]]\nmin = [1.0, 1.0, 1.0]\nmax = [1.1, 1.1, 1.1]\n"),
        &["[[fixed]] #1", "no particle"],
    );
}

#[test]
fn inverted_fixed_box() {
    expect(
        &format!("{BASE}[[fixed]]\nmin = [0.1, 0.0, 0.0]\nmax = [0.0, 0.1, 0.1]\n"),
        &["fixed", "min must be <= max"],
    );
}

#[test]
fn empty_load_box() {
    expect(
        &format!("{BASE}[[load]]\nmin = [1.0, 1.0, 1.0]\nmax = [1.1, 1.1, 1.1]\nmass = 0.1\n"),
        &["[[load]] #1", "no particle"],
    );
}

#[test]
fn bad_free_axes() {
    expect(
        &format!("{BASE}[[finger]]\nposition = [0.0, 0.0, 0.05]\nfree_axes = \"zz\"\n"),
        &["free_axes", "twice"],
    );
}

#[test]
fn unknown_settle_mode() {
    expect(
        &format!("[simulation]\nsettle = \"implicit\"\n{BASE}"),
        &["settle", "\"static\"", "\"dynamic\""],
    );
}

#[test]
fn bad_control_mode() {
    expect(
        &format!("{BASE}[[finger]]\nposition = [0.0, 0.0, 0.05]\ncontrol = \"position\"\n"),
        &["control", "\"force\" or \"velocity\""],
    );
}

#[test]
fn restitution_out_of_range() {
    expect(
        &format!("{BASE}[[finger]]\nposition = [0.0, 0.0, 0.05]\nrestitution = 1.5\n"),
        &["restitution", "[0, 1]"],
    );
}

#[test]
fn malformed_toml() {
    expect("[object\nshape = \"cuboid\"\n", &["line"]);
}

#[test]
fn unreadable_file() {
    let e = Scene::load(std::path::Path::new("/nonexistent/scene.toml")).expect_err("missing file");
    assert!(e.to_string().contains("/nonexistent/scene.toml"), "{e}");
}

#[test]
fn edge_length_larger_than_the_object() {
    expect(
        "[object]\nshape = \"cuboid\"\nsize = [0.05, 0.05, 0.02]\nedge_length = 0.05\n",
        &["edge_length", "smallest extent"],
    );
}

#[test]
fn extra_table_is_free_form() {
    let scene = Scene::from_toml_str(
        &format!("{BASE}[extra]\nanything = \"goes\"\nnested = {{ a = 1 }}\n"),
        "x",
    )
    .expect("accepted");
    assert!(
        scene
            .defaults_applied
            .iter()
            .any(|d| d.contains("young_modulus"))
    );
}

#[test]
fn diverging_run_is_an_error_not_a_panic() {
    // A stiff object whose linear solve is capped far below what it needs:
    // the solver fails on the first step, and the run must stop with an
    // error naming the limit (not a panic, not a silently wrong state).
    let text = format!(
        "[simulation]\ncg_tolerance = 1e-12\ncg_max_iterations = 2\n{BASE}young_modulus = 5e9\n[support]\nkind = \"none\"\n"
    );
    let scene = Scene::from_toml_str(&text, "stiff").expect("scene");
    let mut sim = Simulation::new(&scene).expect("sim");
    for (i, v) in sim.state.velocities.iter_mut().enumerate() {
        *v = glam::DVec3::new(0.0, 0.0, if i % 2 == 0 { 1.0 } else { -1.0 });
    }
    let mut outcome = Ok(());
    for _ in 0..200 {
        outcome = sim.step();
        if outcome.is_err() {
            break;
        }
    }
    let msg = outcome.expect_err("this run must diverge").to_string();
    // The scene's own limit is the cause, and the message says so rather than blame dt.
    assert!(
        msg.contains("the linear solver stopped at t =")
            && msg.contains("cg_max_iterations = 2")
            && !msg.contains("dt"),
        "{msg}"
    );
}

/// Two free 1 kg particles 1 cm apart, joined by a spring (N/m) and damper
/// (N s/m), separating at 1 cm/s.
fn separating_pair(stiffness: f64, damping: f64) -> Simulation {
    let model = softgrip_core::Model::from_particles(
        vec![glam::DVec3::ZERO, glam::DVec3::new(0.01, 0.0, 0.0)],
        vec![1.0, 1.0],
        vec![false, false],
        &[(0, 1, stiffness, damping)],
        glam::DVec3::ZERO,
        1e-3,
    );
    let mut sim = Simulation::from_model(model);
    sim.state.velocities[1].x = 0.01;
    sim
}

#[test]
fn energy_growing_without_input_is_divergence() {
    // Two free particles joined by a damper with a negative coefficient (no
    // scene accepts one; the model is built by hand): their relative speed
    // grows by e every second, far below the speed limit for many seconds.
    // The energy watch must stop the run long before.
    let mut sim = separating_pair(0.0, -0.5);
    let mut outcome = Ok(());
    for _ in 0..2000 {
        outcome = sim.step();
        if outcome.is_err() {
            break;
        }
    }
    let msg = outcome.expect_err("this run must diverge").to_string();
    assert!(
        msg.contains("energy rose for") && msg.contains("no input"),
        "{msg}"
    );
    // Caught within a few hundred steps, while the speed is still tiny.
    assert!(sim.state.time < 0.5, "caught at t = {}", sim.state.time);
    assert!(sim.state.stats.max_speed < 0.1);
}

#[test]
fn a_damped_run_does_not_trip_the_energy_watch() {
    // The same pair with a positive damper loses energy: 2000 steps pass.
    let mut sim = separating_pair(10.0, 0.5);
    for _ in 0..2000 {
        sim.step().expect("a damped pair is stable");
    }
}

#[test]
fn negative_limit_stiffness() {
    expect(
        &format!("{BASE}[model]\nlimit_stiffness = -1.0\n"),
        &["limit_stiffness", "-1", "[0, 1e6]"],
    );
}

#[test]
fn negative_or_nan_rayleigh_damping() {
    for key in ["rayleigh_mass", "rayleigh_stiffness"] {
        for (value, shown) in [("-0.5", "-0.5"), ("nan", "NaN")] {
            expect(
                &format!("{BASE}[model]\n{key} = {value}\n"),
                &[key, shown, "must be >= 0", "Rayleigh", ":7", "case-"],
            );
        }
    }
}

#[test]
fn constraint_tolerance_out_of_range() {
    expect(
        &format!("{BASE}[model]\nconstraint_tolerance = 0.5\n"),
        &["constraint_tolerance", "0.5", "(0, 0.1]"],
    );
}

#[test]
fn non_positive_contact_stiffness_scale() {
    expect(
        &format!("{BASE}[[finger]]\nposition = [0.0, 0.0, 0.05]\ncontact_stiffness_scale = 0.0\n"),
        &["contact_stiffness_scale", "0", "(0, 1e6]"],
    );
}

#[test]
fn softening_out_of_range_or_on_springs() {
    // q = 1 would let the shear modulus reach zero.
    expect(
        &format!("{BASE}[model]\nelasticity = \"neo-hookean\"\nsoftening = 1.0\n"),
        &["softening", "[0, 1)", ":8"],
    );
    expect(
        &format!("{BASE}[model]\nelasticity = \"neo-hookean\"\nstiffening_cubic = -2.0\n"),
        &["stiffening_cubic", "-2", "[0, 1e5]"],
    );
    // The lattice has no such law: an error, not a key silently ignored.
    expect(
        &format!("{BASE}[model]\nstiffening_cubic = 3.0\nsoftening = 0.4\n"),
        &["stiffening_cubic", "3", ":7", "neo-Hookean elements only"],
    );
}

#[test]
fn spring_only_laws_on_elements() {
    // The elements have no compression asymmetry: an error, not a key silently ignored.
    expect(
        &format!("{BASE}[model]\nelasticity = \"neo-hookean\"\ncompression_ratio = 2.0\n"),
        &["compression_ratio", "2", ":8", "springs only"],
    );
}

#[test]
fn unknown_bulk_pressure() {
    expect(
        &format!("{BASE}[model]\nbulk_modulus = 1e6\nbulk_pressure = \"node\"\n"),
        &["bulk_pressure", "node", ":8", "\"nodal\""],
    );
}

/// The one key of `[simulation]` that is a word: read, defaulted to "static", written back.
#[test]
fn the_settle_mode_is_read_and_written_back() {
    use softgrip_core::scene::Settle;
    let dynamic = Scene::from_toml_str(&format!("[simulation]\nsettle = \"dynamic\"\n{BASE}"), "t")
        .expect("dynamic");
    assert_eq!(dynamic.simulation.settle, Settle::Dynamic);
    let again = Scene::from_toml_str(&dynamic.to_toml(), "round trip").expect("round trip");
    assert_eq!(again.simulation.settle, Settle::Dynamic);
    let plain = Scene::from_toml_str(BASE, "t").expect("plain");
    assert_eq!(plain.simulation.settle, Settle::Static);
}
