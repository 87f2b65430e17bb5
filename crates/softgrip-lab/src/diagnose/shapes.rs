//! The region's shape, chosen beyond first order. The scan (`super::regions`) ranks the shapes
//! by their score at "no region", a first-order view: a region a few times stiffer or softer
//! moves the markers far from its linear prediction (a small block must change its modulus
//! tenfold to move them as a half does threefold, and its response has saturated long before).
//! So the [`SHAPES_TRIED`] best-scoring shapes are each evaluated at a modulus [`FIRST_RATIO`]
//! times the object's (the way the scan points) with one Gauss-Newton step in the object's and
//! the region's moduli, from one replay with both sensitivities; the [`SHAPES_FITTED`] best are
//! fitted by Gauss-Newton to convergence, and the lowest residual names the shape.

use super::model_fit::ModelFit;
use super::noise::Noise;
use super::regions::{RegionScan, Shape};
use super::screen::{replay_columns, score_statistic};
use crate::recording::Recording;
use softgrip_core::scene::{AaBox, Region, Scene};

/// Shapes evaluated beyond first order, from the scan's best.
pub const SHAPES_TRIED: usize = 12;

/// Of those, the best fitted by Gauss-Newton (to a 1 % gain a step, five steps at most).
pub const SHAPES_FITTED: usize = 4;

/// The region's modulus over the object's at which each shape is first evaluated (the scan's
/// direction): 3, the middle of a lab's two-material parts (1.5 to 10).
pub const FIRST_RATIO: f64 = 3.0;

/// The shape found: its place and the moduli its fit ended at.
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// Its name ([`super::regions::Grid::describe`]).
    pub variant: String,
    /// Its bounds.
    pub region: AaBox,
    /// The object's modulus and the region's, Pa.
    pub moduli: (f64, f64),
    /// The weighted residual sum of squares at them.
    pub rss: f64,
}

/// `current`'s scene with `shape` at `moduli` (the object's, the region's).
fn with_region(current: &Scene, region: AaBox, (e, e_region): (f64, f64)) -> Scene {
    let mut s = current.clone();
    s.object.young_modulus = e;
    s.regions.push(Region {
        region,
        young_modulus: e_region,
        density: s.object.density,
    });
    s
}

/// One replay at `moduli` with the sensitivities in both moduli's logarithms: the weighted
/// residual sum of squares, and the Gauss-Newton step's `(rss after, step)`.
fn step_at(
    recording: &Recording,
    noise: &Noise,
    current: &Scene,
    region: AaBox,
    moduli: (f64, f64),
    damping: f64,
) -> Option<(f64, f64, [f64; 2])> {
    let scene = with_region(current, region, moduli);
    let targets = [(&scene, "young_modulus"), (&scene, "region_young_modulus")];
    let (r, columns) = replay_columns(recording, noise, &scene, &targets)?;
    let scaled: Vec<Vec<f64>> = columns
        .iter()
        .zip([moduli.0, moduli.1])
        .map(|(c, v)| c.iter().map(|x| x * v).collect())
        .collect();
    let rss: f64 = r.iter().map(|x| x * x).sum();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let (a, b, c) = (
        dot(&scaled[0], &scaled[0]),
        dot(&scaled[0], &scaled[1]),
        dot(&scaled[1], &scaled[1]),
    );
    let (g0, g1) = (dot(&scaled[0], &r), dot(&scaled[1], &r));
    let (a, c) = (a * (1.0 + damping), c * (1.0 + damping));
    let det = a * c - b * b;
    if det <= 0.0 || !det.is_finite() {
        return Some((rss, rss, [0.0, 0.0]));
    }
    let step = [-(c * g0 - b * g1) / det, -(a * g1 - b * g0) / det];
    let predicted = rss - score_statistic(&scaled, &r, 1.0, false);
    Some((rss, predicted, step))
}

/// The moduli after a step in their logarithms, held within the catalogue's ranges (the
/// object's within 3 times `e`, the region's within 30 times).
fn stepped((e0, e_r0): (f64, f64), step: [f64; 2], e: f64) -> (f64, f64) {
    let clamp = |v: f64, f: f64| v.clamp(e / f, e * f);
    (
        clamp(e0 * step[0].clamp(-1.0, 1.0).exp(), 3.0),
        clamp(e_r0 * step[1].clamp(-1.5, 1.5).exp(), 30.0),
    )
}

/// A shape's Gauss-Newton fit of both moduli (Levenberg's damping on a failed step), from
/// `moduli`: the moduli and the residual where it ends.
fn fit_shape(
    recording: &Recording,
    noise: &Noise,
    current: &Scene,
    region: AaBox,
    mut moduli: (f64, f64),
) -> Option<((f64, f64), f64)> {
    let e = current.object.young_modulus;
    let mut damping = 1e-3;
    let (mut rss, _, mut step) = step_at(recording, noise, current, region, moduli, damping)?;
    // Enough to rank the shapes: the one chosen is fitted again as a candidate.
    for _ in 0..5 {
        let next = stepped(moduli, step, e);
        let Some((rss_next, _, step_next)) =
            step_at(recording, noise, current, region, next, damping)
        else {
            damping *= 10.0;
            continue;
        };
        if rss_next < rss {
            let gain = (rss - rss_next) / rss.max(f64::MIN_POSITIVE);
            (moduli, rss, step) = (next, rss_next, step_next);
            damping = (damping / 10.0).max(1e-6);
            if gain < 1e-2 {
                break;
            }
        } else {
            damping *= 10.0;
            if damping > 1e3 {
                break;
            }
        }
    }
    Some((moduli, rss))
}

/// The scan's shape that fits best: each of the [`SHAPES_TRIED`] best evaluated by one step,
/// the [`SHAPES_FITTED`] best of those fitted, on `workers`. `None` when no replay succeeded.
pub(super) fn place(
    recording: &Recording,
    noise: &Noise,
    current: &ModelFit,
    scan: &RegionScan,
    workers: usize,
) -> Option<Placed> {
    let scene = &current.scene;
    let e = scene.object.young_modulus;
    let start = |s: &Shape| (e, e * FIRST_RATIO.powf(s.sign));
    let tried: Vec<&Shape> = scan.shapes.iter().take(SHAPES_TRIED).collect();
    let one_step = crate::sweep::parallel_map(
        &tried,
        workers,
        |s| step_at(recording, noise, scene, s.region, start(s), 0.0).map(|(_, p, _)| p),
        &|_| {},
    );
    let mut ranked: Vec<(f64, &Shape)> = one_step
        .into_iter()
        .zip(&tried)
        .filter_map(|(p, s)| Some((p?, *s)))
        .collect();
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    ranked.truncate(SHAPES_FITTED);
    let fitted = crate::sweep::parallel_map(
        &ranked,
        workers,
        |(_, s)| fit_shape(recording, noise, scene, s.region, start(s)),
        &|_| {},
    );
    fitted
        .into_iter()
        .zip(&ranked)
        .filter_map(|(f, (_, s))| {
            let (moduli, rss) = f?;
            Some(Placed {
                variant: s.variant.clone(),
                region: s.region,
                moduli,
                rss,
            })
        })
        .min_by(|a, b| a.rss.total_cmp(&b.rss))
}
