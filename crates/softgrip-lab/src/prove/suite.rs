//! The concealed suite: each case's truth (a scene the diagnosis is not given, with its hidden
//! effects), the nominal scene it is given, and the recording made from the truth as the
//! thesis's camera saw it.

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::LabError;
use crate::recording::{Mode, Recording, Start};
use crate::synth::{Synthesis, synthesize};
use softgrip_core::scene::{AaBox, Region, Scene, SupportKind};

/// One recording of the suite.
#[derive(Debug, Clone)]
pub struct Case {
    pub name: String,
    /// The effects hidden in it (empty: a control).
    pub effects: Vec<&'static str>,
    /// The hidden parameters, by the diagnosis's names.
    pub truth: Vec<(&'static str, f64)>,
    /// The scene the diagnosis is given.
    pub nominal: Scene,
    /// The scene the data come from.
    pub truth_scene: Scene,
    /// The same without the hidden effects: what the effect moves is the
    /// difference.
    pub plain_scene: Scene,
    pub mode: Mode,
    /// Quasi-static loads, N (7 loads, 8 samples: up and back down).
    pub loads: Vec<f64>,
}

/// The scene the diagnosis is given: the thesis cuboid through a light
/// guide, lattice model, the lab's 4 mm edges, 2 ms steps (time series only: loads are solved
/// statically).
pub fn nominal() -> Scene {
    nominal_from(
        include_str!("../../../../assets/scenes/thesis_cuboid_light_guide.toml"),
        "thesis_cuboid_light_guide.toml",
    )
}

/// A shipped scene at the diagnosis's 4 mm edges and 2 ms steps.
fn nominal_from(text: &str, name: &str) -> Scene {
    let mut s = Scene::from_toml_str(text, name).unwrap_or_else(|_| Scene::thesis());
    s.object.edge_length = NOMINAL_EDGE;
    s.simulation.dt = QUASI_STATIC_DT;
    s
}

/// The scene of the finger-friction cases: the same cuboid under a flat
/// plate, where friction holds the top face from spreading. (Under the
/// sphere, friction moves no marker by more than 0.05 mm: nearly
/// incompressible material hardly slides along an indenter.)
pub fn nominal_plate() -> Scene {
    nominal_from(
        include_str!("../../../../assets/scenes/thesis_cuboid_plate.toml"),
        "thesis_cuboid_plate.toml",
    )
}

/// The nominal scenes' edge length (m): the lab's own mesh of the thesis cuboid. It was 5 mm while
/// every load was settled by time steps (36 minutes for the suite).
pub const NOMINAL_EDGE: f64 = 0.004;

/// The truths' edge length (m): finer than the diagnosis's, as a lab's data are.
pub const TRUTH_EDGE: f64 = 0.003;

/// The nominal scenes' time step: the loads are steps to rest, which 2 ms
/// reach as 1 ms do, in fewer steps (compared by hand with `softgrip
/// compare` on a table case: RMSE 0.241 mm against 0.238).
pub const QUASI_STATIC_DT: f64 = 2e-3;

/// The truth's concealment: 1 ms steps, 3 mm edges, E 10 % higher, the spring limits
/// elsewhere.
fn conceal(mut s: Scene) -> Scene {
    s.simulation.dt = 1e-3;
    s.object.edge_length = TRUTH_EDGE;
    s.object.young_modulus *= 1.1;
    s.model.tau_s = Some(0.2);
    s.model.tau_c = Some(0.2);
    s
}

/// The truth before any effect is hidden in it.
pub fn truth_base() -> Scene {
    conceal(nominal())
}

/// The suite. The truth differs from the nominal scene everywhere the
/// diagnosis may not look: 3 mm edges instead of 4, 1 ms steps instead
/// of 2, E 10 % higher, the spring limits elsewhere.
pub fn cases() -> Vec<Case> {
    let base = truth_base();
    let right_half = |e: f64| Region {
        region: AaBox {
            min: DVec3::new(0.0, -1.0, -1.0),
            max: DVec3::new(1.0, 1.0, 1.0),
        },
        young_modulus: e,
        density: base.object.density,
    };
    let plate_base = conceal(nominal_plate());
    let case_on = |plate: bool,
                   name: &str,
                   effects: Vec<&'static str>,
                   truth: Vec<(&'static str, f64)>,
                   mode: Mode,
                   f: &dyn Fn(&mut Scene)| {
        let base = if plate { &plate_base } else { &base };
        let mut s = base.clone();
        f(&mut s);
        let mut plain = base.clone();
        plain.object.young_modulus = s.object.young_modulus;
        Case {
            name: name.to_string(),
            effects,
            truth,
            nominal: if plate { nominal_plate() } else { nominal() },
            truth_scene: s,
            plain_scene: plain,
            mode,
            // The plate spreads its load: three times the sphere's for a
            // like strain (20 % at the top).
            loads: [1.5, 3.0, 4.5, 6.0, 7.5, 9.0, 4.5, 1.5]
                .iter()
                .map(|l| if plate { l * 10.0 / 3.0 } else { *l })
                .collect(),
        }
    };
    let case =
        |name: &str,
         effects: Vec<&'static str>,
         truth: Vec<(&'static str, f64)>,
         mode: Mode,
         f: &dyn Fn(&mut Scene)| case_on(false, name, effects, truth, mode, f);
    let qs = Mode::QuasiStatic;
    let e = base.object.young_modulus;
    let mut out = Vec::new();
    for (k, young) in [(1, 1.0), (2, 0.9), (3, 1.2)] {
        out.push(case(
            &format!("control-{k}"),
            vec![],
            vec![],
            qs,
            &|s: &mut Scene| s.object.young_modulus *= young,
        ));
    }
    for (strength, mu) in [("weak", 0.2), ("strong", 0.05)] {
        out.push(case(
            &format!("table-friction-{strength}"),
            vec!["table-friction"],
            vec![("table_friction", mu)],
            qs,
            &|s: &mut Scene| {
                s.support.kind = SupportKind::Table;
                s.support.friction = mu;
            },
        ));
    }
    for (strength, beta) in [("weak", 5000.0), ("strong", 10000.0)] {
        out.push(case(
            &format!("strain-stiffening-{strength}"),
            vec!["strain-stiffening"],
            vec![("stiffening", beta)],
            qs,
            &|s: &mut Scene| s.model.stiffening = beta,
        ));
    }
    for (strength, g) in [("weak", 0.6), ("strong", 0.8)] {
        out.push(case(
            &format!("viscoelastic-creep-{strength}"),
            vec!["viscoelastic-creep"],
            vec![("prony_g", g), ("prony_tau", 0.5)],
            Mode::TimeSeries,
            &|s: &mut Scene| {
                s.model.prony_g = g;
                s.model.prony_tau = 0.5;
            },
        ));
    }
    out.push(case_on(
        true,
        "control-plate",
        vec![],
        vec![],
        qs,
        &|_: &mut Scene| {},
    ));
    for (strength, mu) in [("weak", 0.1), ("strong", 0.0)] {
        out.push(case_on(
            true,
            &format!("finger-friction-{strength}"),
            vec!["finger-friction"],
            vec![("friction", mu)],
            qs,
            &|s: &mut Scene| s.fingers[0].friction = mu,
        ));
    }
    for (strength, ratio) in [("weak", 1.0 / 3.0), ("strong", 0.1)] {
        out.push(case(
            &format!("heterogeneous-stiffness-{strength}"),
            vec!["heterogeneous-stiffness"],
            vec![("region_young_modulus", ratio * e)],
            qs,
            &|s: &mut Scene| s.regions.push(right_half(ratio * e)),
        ));
    }
    for (strength, f) in [("weak", 2.0), ("strong", 3.0)] {
        out.push(case(
            &format!("load-loss-{strength}"),
            vec!["load-loss"],
            vec![("guide_friction", f)],
            qs,
            &|s: &mut Scene| s.fingers[0].guide_friction = f,
        ));
    }
    out.push(case(
        "table-friction+load-loss",
        vec!["table-friction", "load-loss"],
        vec![("table_friction", 0.1), ("guide_friction", 1.0)],
        qs,
        &|s: &mut Scene| {
            s.support.kind = SupportKind::Table;
            s.support.friction = 0.1;
            s.fingers[0].guide_friction = 1.0;
        },
    ));
    out
}

/// The thesis experiment's view (its Fig. 12): 8 points on the contour of
/// the object's mid-plane section, where the finger's dent is deepest
/// (bottom corners, side mid-heights, four along the top, two of them in
/// the dent), seen in x and z, plus the finger. On the front face, 25 mm
/// from the finger, the points move too little against the noise to see
/// any effect by.
pub fn thesis_markers() -> Vec<(String, DVec3)> {
    let y = 0.0;
    [
        (-0.025, 0.0),
        (-0.025, 0.01),
        (-0.015, 0.02),
        (-0.005, 0.02),
        (0.005, 0.02),
        (0.015, 0.02),
        (0.025, 0.01),
        (0.025, 0.0),
    ]
    .iter()
    .enumerate()
    .map(|(i, (x, z))| (format!("p{i}"), DVec3::new(*x, y, *z)))
    .collect()
}

/// Writes case `c`'s recording into `dir` (the data from its truth, the
/// nominal scene beside them) and reads it back.
pub fn write_case(c: &Case, dir: &Path, seed: u64) -> Result<Recording, LabError> {
    synthesize(&c.truth_scene, &synthesis(c, seed, NOISE), dir)?;
    std::fs::write(dir.join("scene.toml"), c.nominal.to_toml()).map_err(|e| LabError::Write {
        dir: dir.to_path_buf(),
        source: Arc::new(e),
    })?;
    Ok(Recording::load(&dir.join("recording.toml"))?)
}

/// The noise on each observed coordinate, m.
pub const NOISE: f64 = 1e-4;

/// What case `c`'s recording samples, with `noise`.
pub fn synthesis(c: &Case, seed: u64, noise: f64) -> Synthesis {
    let samples: Vec<(Option<f64>, f64)> = match c.mode {
        // Loading to 9 N and back: 7 loads, 8 samples.
        Mode::QuasiStatic => c.loads.iter().map(|l| (None, *l)).collect(),
        // 5 N stepped on, held 1.5 s, then 9 N held 1.5 s: 0.25 s apart.
        Mode::TimeSeries => (0..12)
            .map(|k| {
                let t = 0.25 * (k + 1) as f64;
                (Some(t), if t <= 1.5 { 5.0 } else { 9.0 })
            })
            .collect(),
    };
    Synthesis {
        mode: c.mode,
        start: Start::Rest,
        samples,
        markers: thesis_markers(),
        finger: true,
        axes: [true, false, true],
        noise,
        seed,
        description: format!("concealed case {} (softgrip prove)", c.name),
    }
}

/// `case` with its truth (and the truth's effect-free twin) meshed at
/// `edge` instead of the suite's [`TRUTH_EDGE`].
pub fn with_truth_edge(mut case: Case, edge: f64) -> Case {
    case.truth_scene.object.edge_length = edge;
    case.plain_scene.object.edge_length = edge;
    case
}

/// The case called `name`.
pub fn case(name: &str) -> Option<Case> {
    cases().into_iter().find(|c| c.name == name)
}

/// The cases whose names contain `filter` (all for ""), each with its
/// noise seed: by its place in the whole suite, so that `--only` (and
/// `softgrip bench --diagnosis`) make the very recording the full run
/// makes.
pub fn seeded(filter: &str) -> Vec<(u64, Case)> {
    cases()
        .into_iter()
        .enumerate()
        .filter(|(_, c)| c.name.contains(filter))
        .map(|(i, c)| (100 + i as u64, c))
        .collect()
}
