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
    /// The seed of its noise, drawn from the proof's seed.
    pub noise_seed: u64,
    /// Where a hidden region lies (the diagnosis's names: "left half", ...).
    pub region: Option<&'static str>,
}

/// The seed developed on: tests and by-hand runs use it (and any other but the scored ones).
pub const DEVELOPMENT_SEED: u64 = 1;

/// The seeds `softgrip prove` scores by default, drawn once (2026-11-28) and never run while
/// the diagnosis was developed: its score on them is a score on data it has not seen.
pub const SCORED_SEEDS: [u64; 3] = [
    0x5eed_2f71_09c4_a1d3,
    0x9b3e_77a0_4d12_c865,
    0x26c1_e8f5_b09a_7314,
];

/// A case's draws: SplitMix64 from the proof's seed and the case's name, so that a case is the
/// same whatever else is run.
struct Draws(u64);

impl Draws {
    fn new(seed: u64, name: &str) -> Draws {
        // FNV-1a of the name, mixed into the seed.
        let h = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
        });
        Draws(seed ^ h)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// Log-uniform in [lo, hi).
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.uniform(lo.ln(), hi.ln()).exp()
    }

    fn pick<T: Copy>(&mut self, of: &[T]) -> T {
        of[(self.next() % of.len() as u64) as usize]
    }
}

/// The range of the truth's E over the nominal's, drawn log-uniformly for every case: a lab's
/// nominal E is a datasheet's or a compression test's, off by up to a quarter.
pub const E_ERROR: (f64, f64) = (0.8, 1.25);

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

/// The truth's concealment: 1 ms steps, 3 mm edges, the spring limits elsewhere (E is drawn
/// per case).
fn conceal(mut s: Scene) -> Scene {
    s.simulation.dt = 1e-3;
    s.object.edge_length = TRUTH_EDGE;
    s.model.tau_s = Some(0.2);
    s.model.tau_c = Some(0.2);
    s
}

/// The truth before any effect is hidden in it, at the nominal E.
pub fn truth_base() -> Scene {
    conceal(nominal())
}

/// The half of the cuboid a hidden region fills, as the diagnosis's candidates name them.
fn half(name: &str) -> AaBox {
    let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
    let (min, max) = match name {
        "left half" => (lo, DVec3::new(0.0, 1.0, 1.0)),
        "right half" => (DVec3::new(0.0, -1.0, -1.0), hi),
        "bottom half" => (lo, DVec3::new(1.0, 1.0, 0.01)),
        _ => (DVec3::new(-1.0, -1.0, 0.01), hi),
    };
    AaBox { min, max }
}

/// The suite under the proof's `seed`. The truth differs from the nominal scene everywhere the
/// diagnosis may not look: 3 mm edges instead of 4, 1 ms steps instead of 2, E drawn in
/// [`E_ERROR`] of the nominal, the spring limits elsewhere. Each effect's strength (and a
/// region's place) is drawn from the seed within its stated range, weak and strong.
pub fn cases(seed: u64) -> Vec<Case> {
    let base = truth_base();
    let plate_base = conceal(nominal_plate());
    // `hide` hides the case's effects in the truth (its E already drawn), with the case's own
    // draws, and returns the hidden values by the diagnosis's names.
    type Hide<'a> = &'a dyn Fn(&mut Scene, &mut Draws) -> Vec<(&'static str, f64)>;
    let case_on = |plate: bool, name: &str, effects: Vec<&'static str>, mode: Mode, hide: Hide| {
        let base = if plate { &plate_base } else { &base };
        let mut draws = Draws::new(seed, name);
        let mut s = base.clone();
        s.object.young_modulus *= draws.log_uniform(E_ERROR.0, E_ERROR.1);
        let truth = hide(&mut s, &mut draws);
        let mut plain = base.clone();
        plain.object.young_modulus = s.object.young_modulus;
        let region = s.regions.first().map(|r| {
            ["left half", "right half", "bottom half", "top half"]
                .into_iter()
                .find(|h| half(h) == r.region)
                .unwrap_or("a region")
        });
        Case {
            noise_seed: draws.next() >> 1,
            region,
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
    let case = |name: &str, effects: Vec<&'static str>, mode: Mode, hide: Hide| {
        case_on(false, name, effects, mode, hide)
    };
    let qs = Mode::QuasiStatic;
    let none: Hide = &|_, _| vec![];
    let mut out = Vec::new();
    for k in 1..=3 {
        out.push(case(&format!("control-{k}"), vec![], qs, none));
    }
    // Each effect at two strengths: (name, low, high) of its drawn range.
    for (strength, lo, hi) in [("weak", 0.15, 0.3), ("strong", 0.03, 0.1)] {
        out.push(case(
            &format!("table-friction-{strength}"),
            vec!["table-friction"],
            qs,
            &|s, d| {
                let mu = d.uniform(lo, hi);
                s.support.kind = SupportKind::Table;
                s.support.friction = mu;
                vec![("table_friction", mu)]
            },
        ));
    }
    for (strength, lo, hi) in [("weak", 3000.0, 6000.0), ("strong", 8000.0, 12000.0)] {
        out.push(case(
            &format!("strain-stiffening-{strength}"),
            vec!["strain-stiffening"],
            qs,
            &|s, d| {
                let beta = d.uniform(lo, hi);
                s.model.stiffening = beta;
                vec![("stiffening", beta)]
            },
        ));
    }
    for (strength, lo, hi) in [("weak", 0.5, 0.65), ("strong", 0.75, 0.85)] {
        out.push(case(
            &format!("viscoelastic-creep-{strength}"),
            vec!["viscoelastic-creep"],
            Mode::TimeSeries,
            &|s, d| {
                let (g, tau) = (d.uniform(lo, hi), d.log_uniform(0.3, 0.8));
                s.model.prony_g = g;
                s.model.prony_tau = tau;
                vec![("prony_g", g), ("prony_tau", tau)]
            },
        ));
    }
    out.push(case_on(true, "control-plate", vec![], qs, none));
    for (strength, lo, hi) in [("weak", 0.05, 0.15), ("strong", 0.0, 0.02)] {
        out.push(case_on(
            true,
            &format!("finger-friction-{strength}"),
            vec!["finger-friction"],
            qs,
            &|s, d| {
                let mu = d.uniform(lo, hi);
                s.fingers[0].friction = mu;
                vec![("friction", mu)]
            },
        ));
    }
    // A softer or a stiffer half, any of four.
    for (strength, lo, hi) in [("weak", 2.0, 3.5), ("strong", 5.0, 10.0)] {
        out.push(case(
            &format!("heterogeneous-stiffness-{strength}"),
            vec!["heterogeneous-stiffness"],
            qs,
            &|s, d| {
                let place = d.pick(&["left half", "right half", "bottom half", "top half"]);
                let ratio = d.uniform(lo, hi);
                let ratio = if d.next() % 2 == 0 {
                    ratio
                } else {
                    1.0 / ratio
                };
                let e = ratio * s.object.young_modulus;
                s.regions.push(Region {
                    region: half(place),
                    young_modulus: e,
                    density: s.object.density,
                });
                vec![("region_young_modulus", e)]
            },
        ));
    }
    for (strength, lo, hi) in [("weak", 1.5, 2.5), ("strong", 2.5, 3.5)] {
        out.push(case(
            &format!("load-loss-{strength}"),
            vec!["load-loss"],
            qs,
            &|s, d| {
                let f = d.uniform(lo, hi);
                s.fingers[0].guide_friction = f;
                vec![("guide_friction", f)]
            },
        ));
    }
    out.push(case(
        "table-friction+load-loss",
        vec!["table-friction", "load-loss"],
        qs,
        &|s, d| {
            let (mu, f) = (d.uniform(0.05, 0.15), d.uniform(0.7, 1.3));
            s.support.kind = SupportKind::Table;
            s.support.friction = mu;
            s.fingers[0].guide_friction = f;
            vec![("table_friction", mu), ("guide_friction", f)]
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
    with_nominal_scene(c, dir)
}

/// Puts `c`'s nominal scene beside the recording in `dir` (the diagnosis is given it, not the
/// truth's) and reads the recording back.
pub(super) fn with_nominal_scene(c: &Case, dir: &Path) -> Result<Recording, LabError> {
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

/// The case called `name` under the proof's `seed`.
pub fn case(seed: u64, name: &str) -> Option<Case> {
    cases(seed).into_iter().find(|c| c.name == name)
}

/// The cases whose names contain `filter` (all for ""), each with its noise seed (drawn from
/// `seed` and its name, so that `--only` and `softgrip bench --diagnosis` make the very
/// recording the full run makes).
pub fn seeded(seed: u64, filter: &str) -> Vec<(u64, Case)> {
    cases(seed)
        .into_iter()
        .filter(|c| c.name.contains(filter))
        .map(|c| (c.noise_seed, c))
        .collect()
}
