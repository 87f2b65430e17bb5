//! The catalogue of candidate effects: each a model extension with its own parameters, fitted
//! with the modulus from the current model. Besides the spec's six, time series get `damping`
//! (the springs' damping ratio): a swing that dies faster or slower than the model's.

use glam::DVec3;

use super::options::{DiagnoseOptions, within_bounds};
use crate::fit::FitParam;
use crate::params;
use crate::recording::{Mode, Recording};
use softgrip_core::scene::{AaBox, Region, Scene, SupportKind};

/// Every effect the catalogue may name: the spec's six, then `damping`.
pub const EFFECTS: [&str; 7] = [
    "table-friction",
    "strain-stiffening",
    "viscoelastic-creep",
    "finger-friction",
    "heterogeneous-stiffness",
    "load-loss",
    "damping",
];

/// A candidate effect: a change to the scene and the parameters it brings.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The spec's name (`table-friction`, ...).
    pub effect: &'static str,
    /// Which variant, for effects with several (the region's half).
    pub variant: String,
    /// The scene with the effect added (at its parameters' start values).
    pub scene: Scene,
    /// The parameters fitted: the object's modulus first (unless locked), then the effect's own.
    pub params: Vec<FitParam>,
    /// For an effect whose start has it switched on: the values of
    /// `params` at which it is off, i.e. the model it is added to. The fit
    /// takes that point as a floor (it ends no worse), not as a start to
    /// search from.
    pub off: Option<Vec<f64>>,
}

/// The fitted parameter `name` within `lower..upper` (on a log scale where `log`); `None` for an
/// unknown name.
fn param(name: &str, lower: f64, upper: f64, log: bool) -> Option<FitParam> {
    Some(FitParam {
        param: params::find(name).ok()?,
        lower,
        upper,
        log,
    })
}

/// The relaxing share the creep candidate's fit starts from.
const CREEP_START_G: f64 = 0.2;

/// The catalogue of candidate effects for `scene` (already carrying the
/// current fit) and `recording`: those that apply.
pub fn catalogue(recording: &Recording, scene: &Scene) -> Vec<Candidate> {
    let mut out = Vec::new();
    let e = scene.object.young_modulus;
    let Some(modulus) = param("young_modulus", e / 3.0, e * 3.0, true) else {
        return out;
    };
    let with_modulus = |ps: Vec<Option<FitParam>>| with_modulus(modulus, ps);
    out.extend(table_friction(scene, modulus));
    out.extend(stiffening(scene, modulus));
    if recording.mode == Mode::TimeSeries {
        out.extend(time_series(scene, modulus));
    }
    if !scene.fingers.is_empty() {
        out.push(Candidate {
            effect: "finger-friction",
            variant: String::new(),
            scene: scene.clone(),
            params: with_modulus(vec![param("friction", 0.0, 2.0, false)]),
            off: None,
        });
    }
    out.extend(halves(scene));
    let loads = recording.samples.iter().map(|s| s.load).fold(0.0, f64::max);
    let pressed = scene.fingers.iter().any(|f| f.force != DVec3::ZERO);
    if pressed && loads > 0.0 {
        out.push(Candidate {
            effect: "load-loss",
            variant: String::new(),
            scene: scene.clone(),
            params: with_modulus(vec![param("guide_friction", 0.0, 0.5 * loads, false)]),
            off: None,
        });
    }
    out
}

/// `scene` changed by `f`.
fn with(scene: &Scene, f: &dyn Fn(&mut Scene)) -> Scene {
    let mut s = scene.clone();
    f(&mut s);
    s
}

/// A table under the object in place of its support, its friction fitted: where it has one.
fn table_friction(scene: &Scene, modulus: FitParam) -> Option<Candidate> {
    // Friction above 1 holds a silicone's bottom nearly as a bonded one, and its static solves
    // cycle between stick and slip (on the 4 mm cuboid a replay took 0.7, 2.6, 6.3 and 26 s at
    // mu 0.1, 0.5, 1 and 2): the search stops at 1.
    (scene.support.kind != SupportKind::None).then(|| Candidate {
        effect: "table-friction",
        variant: String::new(),
        scene: with(scene, &|s| {
            s.support.kind = SupportKind::Table;
            s.support.friction = 0.0;
        }),
        params: with_modulus(modulus, vec![param("table_friction", 0.0, 1.0, false)]),
        off: None,
    })
}

/// A time series's candidates: viscoelastic creep, then damping.
fn time_series(scene: &Scene, modulus: FitParam) -> Vec<Candidate> {
    let e = scene.object.young_modulus;
    let with_modulus = |ps: Vec<Option<FitParam>>| with_modulus(modulus, ps);
    let creep = Candidate {
        effect: "viscoelastic-creep",
        variant: String::new(),
        // Started inside the range, not at g = 0: with no relaxing
        // share the relaxation time moves nothing (a zero gradient),
        // and the fit cannot find its way out.
        // The baseline fitted the material as if fully relaxed, so the
        // start keeps that long-term modulus, E (1 - g), where it was.
        scene: with(scene, &|s| {
            s.model.prony_g = CREEP_START_G;
            s.model.prony_tau = 1.0;
            s.object.young_modulus = e / (1.0 - CREEP_START_G);
        }),
        params: with_modulus(vec![
            param("prony_g", 0.0, 0.9, false),
            param("prony_tau", 0.05, 20.0, true),
        ]),
        // And no creep at all, the model it is added to (E, g 0, its
        // relaxation time), a floor for the fit (see `fit_model`): it
        // ends no worse than that model. After damping on the beam's
        // load52_a, the start above alone left it 9 % worse.
        off: Some(vec![e, 0.0, scene.model.prony_tau.clamp(0.05, 20.0)]),
    };
    // Dissipation: the springs are damped at a ratio of their critical
    // damping (1 as the thesis sets it); a real material can lose more
    // or less energy per swing. Quasi-static samples are at rest, where
    // damping changes nothing, so it is offered for time series only.
    let d = scene.model.damping_ratio.max(0.01);
    let damping = Candidate {
        effect: "damping",
        variant: String::new(),
        scene: scene.clone(),
        params: with_modulus(vec![param("damping_ratio", d / 10.0, d * 30.0, true)]),
        off: None,
    };
    vec![creep, damping]
}

/// Strain stiffening: Yeoh's one term and, for elements, the two-term form.
fn stiffening(scene: &Scene, modulus: FitParam) -> Vec<Candidate> {
    let mut out = Vec::new();
    // A spring's beta multiplies its own strain squared (a few percent in a
    // grasp); an element's, `max(I1 - 3, 0) / 3`, which is about 1 at the
    // 67 % compression of the Ecoflex recordings (incompressible, `I1 =
    // l^2 + 2 / l`): there beta 30 already multiplies the shear modulus by
    // 31.
    let stiffening_max = if scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean {
        30.0
    } else {
        3e4
    };
    out.push(Candidate {
        effect: "strain-stiffening",
        variant: String::new(),
        scene: scene.clone(),
        params: with_modulus(
            modulus,
            vec![param("stiffening", 0.0, stiffening_max, false)],
        ),
        off: None,
    });
    // Elements can also soften first and stiffen late (filled silicones:
    // a two-term Yeoh solid, C20 < 0 < C30), which one growing term cannot
    // follow. gamma 100 multiplies the shear modulus by 101 at s = 3 (the
    // Ecoflex recordings' last level; 10 was too few: EF30_0T_A1's fit
    // ended on it), as beta 30 by 31; softening 0.95 dips it to 10 %.
    if scene.model.elasticity == softgrip_core::scene::Elasticity::NeoHookean {
        out.push(Candidate {
            effect: "strain-stiffening",
            variant: "two-term".into(),
            scene: scene.clone(),
            params: with_modulus(
                modulus,
                vec![
                    param("stiffening_cubic", 0.0, 100.0, false),
                    param("softening", 0.0, 0.95, false),
                ],
            ),
            off: None,
        });
    }
    out
}

/// A region of other stiffness in each half of the object.
fn halves(scene: &Scene) -> Vec<Candidate> {
    let mut out = Vec::new();
    if let Ok(mesh) = softgrip_core::model::Model::mesh_of(scene) {
        let (lo, hi) = mesh.bounds();
        let c = 0.5 * (lo + hi);
        let pad = 1e-3 * (hi - lo).max_element();
        let halves = [
            ("left half", lo - pad, DVec3::new(c.x, hi.y, hi.z) + pad),
            ("right half", DVec3::new(c.x, lo.y, lo.z) - pad, hi + pad),
            ("bottom half", lo - pad, DVec3::new(hi.x, hi.y, c.z) + pad),
            ("top half", DVec3::new(lo.x, lo.y, c.z) - pad, hi + pad),
        ];
        for (name, min, max) in halves {
            out.extend(region(scene, name, AaBox { min, max }));
        }
    }
    out
}

/// The modulus and the effect's own parameters: empty where one is not known, so that a
/// candidate is left out rather than offered broken.
fn with_modulus(modulus: FitParam, ps: Vec<Option<FitParam>>) -> Vec<FitParam> {
    ps.into_iter()
        .collect::<Option<Vec<_>>>()
        .map(|mut v| {
            v.insert(0, modulus);
            v
        })
        .unwrap_or_default()
}

/// A region of other stiffness at `place` (named `variant`), its modulus fitted with the
/// object's: a half of the catalogue's, or the box the screen's scan found (`super::regions`).
pub(super) fn region(scene: &Scene, variant: &str, place: AaBox) -> Option<Candidate> {
    let e = scene.object.young_modulus;
    let mut s = scene.clone();
    s.regions.push(Region {
        region: place,
        young_modulus: e,
        density: s.object.density,
    });
    Some(Candidate {
        effect: "heterogeneous-stiffness",
        variant: variant.to_string(),
        scene: s,
        // A stiff insert in soft material (or a soft patch in stiff) can differ by more than
        // tenfold.
        params: vec![
            param("young_modulus", e / 3.0, e * 3.0, true)?,
            param("region_young_modulus", e / 30.0, e * 30.0, true)?,
        ],
        off: None,
    })
}

/// The catalogue as the diagnosis fits it: each parameter searched within
/// the user's ranges, and a locked E kept at the scene's value in the
/// candidates' fits too (out of their parameters and off points); a
/// candidate left with nothing to fit is dropped.
pub(super) fn candidates(
    recording: &Recording,
    scene: &Scene,
    options: &DiagnoseOptions,
) -> Vec<Candidate> {
    catalogue(recording, scene)
        .into_iter()
        .filter_map(|c| as_fitted(c, options))
        .collect()
}

/// Candidate `c` as the diagnosis fits it (see [`candidates`]): `None` when nothing is left to
/// fit.
pub(super) fn as_fitted(mut c: Candidate, options: &DiagnoseOptions) -> Option<Candidate> {
    let e_locked = options.lock.iter().any(|l| l == "young_modulus");
    if e_locked {
        let kept: Vec<bool> = c.params.iter().map(|p| !is_modulus(p)).collect();
        if let Some(off) = &mut c.off {
            *off = off
                .iter()
                .zip(&kept)
                .filter(|(_, k)| **k)
                .map(|(v, _)| *v)
                .collect();
        }
        c.params.retain(|p| !is_modulus(p));
    }
    c.params = within_bounds(c.params, &options.bounds);
    (!c.params.is_empty()).then_some(c)
}

/// An effect with its variant, as the reports print it.
pub fn effect_label(effect: &str, variant: &str) -> String {
    if variant.is_empty() {
        effect.to_string()
    } else {
        format!("{effect} ({variant})")
    }
}

/// The object's modulus, which every candidate refits (unless locked).
pub(super) fn is_modulus(p: &FitParam) -> bool {
    p.param.name == "young_modulus"
}

/// A candidate's own parameters: all but the modulus it refits.
pub(super) fn own_params(params: &[FitParam]) -> usize {
    params.iter().filter(|p| !is_modulus(p)).count()
}
