//! Candidates screened by the score test (Rao 1948; the Lagrange multiplier test) before they
//! are fitted: at the current model, the gradient of the fit's residual sum of squares in each
//! candidate's parameters at "effect absent", with the modulus the candidate refits projected
//! out, tells from one replay with sensitivities how much the candidate could explain to first
//! order. A candidate whose statistic is not significant at [`SCREEN_LEVEL`] cannot come near
//! the thresholds that name an effect, and is not fitted.
//!
//! With `r` the noise-weighted residual at the current fit, `J` its derivative in the
//! candidate's parameters `psi` and `J_E` in the modulus, `J~ = (I - P_E) J` (`P_E` the
//! projection on `J_E`'s span: E is refitted with the effect), the statistic is
//! `T = r^T J~ (J~^T J~)^-1 J~^T r / s^2`, `s^2 = |r|^2 / (n - k)` the residual variance per
//! degree of freedom (the noise level is free, as in the BIC), chi-square with `dim psi`
//! degrees of freedom where the effect is absent. `T s^2` is the one-step (Gauss-Newton)
//! prediction of the residual the candidate removes. A parameter whose null is the end of its
//! range (a stiffening or a guide friction of 0) is tested one-sided: a gradient that asks for
//! it below the end counts as nothing. Which candidates are screened and why the others are
//! not: `docs/design/diagnosis.md`, "The screen".

use super::catalogue::Candidate;
use super::model_fit::ModelFit;
use super::noise::{Noise, weighted_residuals};
use super::regions::{Grid, RegionScan, scan};
use crate::recording::{Mode, Recording};
use crate::replay::{ReplayOptions, replay_observing};
use crate::sensitivity::{ParameterSteps, fit_sensitivity_options_for};
use softgrip_core::quasi_static::RestTolerance;
use softgrip_core::scene::{Region, Scene};

/// The screen's level: a candidate is fitted when its score test is significant at 5 %.
/// Naming it asks for a BIC gain over 10 (a likelihood-ratio statistic over `10 + ln n`, 14.7 on
/// the 112 coordinates of a 7-load recording with 8 markers) and a tenth of the residual; the
/// screen's 3.84 (one-sided 2.71) is a quarter of that, room for a response that grows faster
/// than its first-order prediction.
pub const SCREEN_LEVEL: f64 = 0.05;

/// One candidate's score test.
#[derive(Debug, Clone, PartialEq)]
pub struct Screen {
    /// The candidate's effect (catalogue name).
    pub effect: &'static str,
    /// The candidate's variant; empty for an effect with one.
    pub variant: String,
    /// The parameters tested, at the values where the effect is absent.
    pub tested: Vec<(&'static str, f64)>,
    /// The statistic `T` and its degrees of freedom.
    pub statistic: f64,
    /// Degrees of freedom of `statistic`.
    pub dof: usize,
    /// Its p-value where the effect is absent.
    pub p_value: f64,
    /// The share of the current residual the first-order step would remove (`T s^2 / |r|^2`).
    pub predicted_share: f64,
    /// Fitted (significant, or another variant of its effect is).
    pub kept: bool,
    /// A half the region scan stands in for (`super::regions`): not fitted itself, but its
    /// test, significant, opens the region's fit at the scan's best-fitting shape.
    pub in_scan: bool,
}

/// The parameters a candidate's score is taken in, at its null: `None` where it is tried on a
/// grid instead (`on_a_grid`) or not a quasi-static recording's.
fn tested(c: &Candidate) -> Option<Vec<&'static str>> {
    match (c.effect, c.variant.as_str()) {
        ("strain-stiffening", "") => Some(vec!["stiffening"]),
        // The two-term form at its null (no terms) spans the energy's second- and third-order
        // terms in `I - 3`: softening is a share of the cubic term's square root, without
        // effect (and without derivative) where that term is absent, so the score is taken in
        // the two coefficients themselves.
        ("strain-stiffening", "two-term") => Some(vec!["stiffening", "stiffening_cubic"]),
        ("heterogeneous-stiffness", _) => Some(vec!["region_young_modulus"]),
        ("load-loss", _) => Some(vec!["guide_friction"]),
        _ => None,
    }
}

/// The friction a candidate is tried at on a grid of values ([`FRICTION_GRID`]) rather than
/// tested at its null: a table in place of a bonded base is not nested in it at any friction
/// (the bonded limit is at infinite friction, and even there the rim lifts off), and the
/// finger's friction has no derivative where every contact sticks (a lower friction changes
/// nothing until contacts start to slide): a score of 0 there says nothing of a lower one.
fn on_a_grid(c: &Candidate) -> Option<&'static str> {
    match c.effect {
        "table-friction" => Some("table_friction"),
        "finger-friction" => Some("friction"),
        _ => None,
    }
}

/// The candidate's scene at its null for the tested parameters: the two-term form with both
/// coefficients at 0 (its catalogue start has them there already).
fn null_scene(c: &Candidate) -> Scene {
    let mut s = c.scene.clone();
    if c.variant == "two-term" {
        s.model.stiffening = 0.0;
        s.model.stiffening_cubic = 0.0;
        s.model.softening = 0.0;
    }
    s
}

/// Whether a tested parameter's null is the lower end of its range (one-sided test).
fn at_lower_end(c: &Candidate, name: &str, value: f64) -> bool {
    c.params
        .iter()
        .find(|p| p.param.name == name)
        .map_or(value == 0.0, |p| value <= p.lower)
}

/// The score tests of `candidates` at `current` (a quasi-static recording's fit): `None` where
/// they cannot be had (a time series, or the sensitivities fail at an equilibrium), and then
/// every candidate is fitted. The frictions of [`on_a_grid`] are tried on a grid
/// ([`best_on_a_grid`]). Where a region is a candidate, the scan of boxes of the object's cells
/// (`super::regions`) from the same replay. The replays run on `workers`.
pub(super) fn screen(
    recording: &Recording,
    noise: &Noise,
    current: &ModelFit,
    candidates: &[Candidate],
    (workers, region_scan): (usize, bool),
) -> Option<(Vec<Screen>, Option<RegionScan>)> {
    if recording.mode != Mode::QuasiStatic || candidates.is_empty() {
        return None;
    }
    let nulls: Vec<Option<(Scene, Vec<&'static str>)>> = candidates
        .iter()
        .map(|c| tested(c).map(|t| (null_scene(c), t)))
        .collect();
    let grids: Vec<Vec<(f64, Scene)>> = candidates
        .iter()
        .map(|c| {
            on_a_grid(c)
                .map(|name| friction_grid(current, c, name))
                .unwrap_or_default()
        })
        .collect();
    let cells = region_scan
        .then(|| cell_scenes(current, candidates))
        .flatten();
    let cell_nulls: Vec<&Scene> = cells
        .as_ref()
        .map_or(Vec::new(), |(_, s)| s.iter().collect());
    let ((r, columns), grid_solved) = replay_all(
        recording,
        noise,
        current,
        candidates,
        (&nulls, &cell_nulls),
        &grids,
        workers,
    )?;
    let rss: f64 = r.iter().map(|x| x * x).sum();
    let s2 = rss / r.len().saturating_sub(current.k).max(1) as f64;
    let (out, next) = candidate_screens(candidates, &nulls, &grid_solved, &columns, &r, (rss, s2));
    let region = cells.and_then(|(grid, _)| {
        region_screen(recording, noise, current, &grid, &columns, next, (&r, s2))
    });
    mark_kept(out, region)
}

/// Each candidate's test from the replays' residual `r` and `columns` (the modulus's first, then
/// the nested candidates' in order): on its grid, nested at its null, or untested. The tests,
/// and the index of the first column after the candidates' (the region scan's cells).
fn candidate_screens(
    candidates: &[Candidate],
    nulls: &[Null],
    grid_solved: &[GridColumns],
    columns: &[Vec<f64>],
    r: &[f64],
    (rss, s2): (f64, f64),
) -> (Vec<Screen>, usize) {
    let e = &columns[0];
    let mut next = 1;
    let mut out = Vec::with_capacity(candidates.len());
    for ((c, null), grid) in candidates.iter().zip(nulls).zip(grid_solved) {
        let screen = match (on_a_grid(c), null) {
            (Some(name), _) => best_on_a_grid(c, name, grid, rss, s2),
            (None, Some((scene, names))) => {
                let projected: Vec<Vec<f64>> = columns[next..next + names.len()]
                    .iter()
                    .map(|col| project_out(col, e))
                    .collect();
                next += names.len();
                Some(nested(c, scene, names, &projected, r, s2))
            }
            (None, None) => None,
        };
        out.push(screen.unwrap_or_else(|| Screen::untested(c)));
    }
    (out, next)
}

/// The region scan over `grid`'s cells, from their columns at `next` on (then the contact's),
/// with the modulus's (`columns[0]`) and the model's own form's directions projected out.
fn region_screen(
    recording: &Recording,
    noise: &Noise,
    current: &ModelFit,
    grid: &Grid,
    columns: &[Vec<f64>],
    next: usize,
    (r, s2): (&[f64], f64),
) -> Option<RegionScan> {
    let e = &columns[0];
    // What refining the mesh moves is the model's own form, not the specimen's: a region
    // gets no credit along it (nor along E, which is refitted).
    let cells = grid.cells().len();
    // The contact's stiffness is the model's own form too: a soft block under the finger
    // does what a softer contact does.
    let contact = columns.get(next + cells).cloned();
    let form = [
        mesh_direction(recording, noise, &current.scene, r.len()),
        contact,
    ];
    let nuisance = orthogonal_nuisance(e, form.into_iter().flatten());
    let projected: Vec<Vec<f64>> = columns[next..next + cells]
        .iter()
        .map(|c| {
            nuisance
                .iter()
                .fold(project_out(c, e), |c, d| project_out(&c, d))
        })
        .collect();
    scan(grid, &projected, r, s2)
}

/// The screens and the region scan as the search takes them: the halves stand aside for the
/// scan, and every variant of a kept effect is kept.
fn mark_kept(
    mut out: Vec<Screen>,
    mut region: Option<RegionScan>,
) -> Option<(Vec<Screen>, Option<RegionScan>)> {
    // The scan's shapes stand in for the halves (which are among them); a significant half
    // still opens the region's fit, as it opened the four halves' before the scan.
    if let Some(scan) = region.as_mut() {
        scan.halves_significant = out
            .iter()
            .any(|s| s.effect == REGION && s.p_value < SCREEN_LEVEL);
        for s in out.iter_mut().filter(|s| s.effect == REGION) {
            (s.kept, s.in_scan) = (false, true);
        }
    }
    // An effect's variants are fitted together (their Vuong threshold counts them all).
    let kept_effects: Vec<&str> = out.iter().filter(|s| s.kept).map(|s| s.effect).collect();
    for s in &mut out {
        s.kept |= kept_effects.contains(&s.effect);
    }
    Some((out, region))
}

/// The edge length, over the scene's, of the mesh whose difference from the scene's is taken as
/// the direction of the model's own discretisation error. 0.8 (the discretisation check's
/// `FINER`) moves the markers too little for remeshing's own jitter not to turn the direction:
/// on the proof's stiff-silicone control a soft inner block still took 41 % of the residual
/// (scan T 13.7); at 0.65 its T was 6.3, at 0.5 2.7. Replaying at 0.6 costs about a second.
pub const FORM_REFINEMENT: f64 = 0.6;

/// The weighted residual's change when `scene`'s mesh is refined to [`FORM_REFINEMENT`] of its
/// edges: the direction of the model's own discretisation error. `None` for a mesh
/// file (not refined) or where the refined replay fails or sees other observations.
fn mesh_direction(
    recording: &Recording,
    noise: &Noise,
    scene: &Scene,
    observations: usize,
) -> Option<Vec<f64>> {
    if matches!(scene.object.shape, softgrip_core::scene::Shape::Mesh { .. }) {
        return None;
    }
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    let coarse = crate::replay::replay(recording, scene, options, |_| {}).ok()?;
    let mut finer = scene.clone();
    finer.object.edge_length *= FORM_REFINEMENT;
    let fine = crate::replay::replay(recording, &finer, options, |_| {}).ok()?;
    let (a, b) = (
        weighted_residuals(&coarse.residuals, noise),
        weighted_residuals(&fine.residuals, noise),
    );
    (a.len() == observations && b.len() == observations)
        .then(|| b.iter().zip(&a).map(|(x, y)| x - y).collect())
}

/// The nuisance directions `form`, each orthogonal to `e` and to those before it (so that
/// projecting them out one after another projects out their span).
fn orthogonal_nuisance(e: &[f64], form: impl Iterator<Item = Vec<f64>>) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for d in form {
        let d = out
            .iter()
            .fold(project_out(&d, e), |d, q| project_out(&d, q));
        if d.iter().any(|x| *x != 0.0) {
            out.push(d);
        }
    }
    out
}

/// The effect a region's candidates are.
const REGION: &str = "heterogeneous-stiffness";

/// Where a region is among `candidates` and the current model has none of its own: the grid of
/// the object's cells and, for each occupied cell, the current scene with that cell as a region
/// at the object's modulus (the null of its modulus's sensitivity).
fn cell_scenes(current: &ModelFit, candidates: &[Candidate]) -> Option<(Grid, Vec<Scene>)> {
    let scene = &current.scene;
    if !candidates.iter().any(|c| c.effect == REGION) || !scene.regions.is_empty() {
        return None;
    }
    let grid = Grid::of(&softgrip_core::model::Model::mesh_of(scene).ok()?);
    let scenes = grid
        .cells()
        .into_iter()
        .map(|cell| {
            let mut s = scene.clone();
            s.regions.push(Region {
                region: grid.cell_box(cell, cell),
                young_modulus: scene.object.young_modulus,
                density: scene.object.density,
            });
            s
        })
        .collect();
    Some((grid, scenes))
}

/// The scan as a screened candidate of its own: fitted (its shape placed by `super::shapes`)
/// when significant, or when one of the halves is.
pub(super) fn scanned(scan: &RegionScan, modulus: f64) -> Screen {
    Screen {
        effect: REGION,
        variant: format!(
            "scan of {} shapes, best at first order: {}",
            scan.boxes,
            scan.shapes.first().map_or("", |s| s.variant.as_str())
        ),
        tested: vec![("region_young_modulus", modulus)],
        statistic: scan.statistic,
        dof: 1,
        p_value: scan.p_value,
        predicted_share: scan.predicted_share,
        kept: scan.p_value < SCREEN_LEVEL || scan.halves_significant,
        in_scan: false,
    }
}

impl Screen {
    /// A candidate whose test could not be had: fitted.
    fn untested(c: &Candidate) -> Screen {
        Screen {
            effect: c.effect,
            variant: c.variant.clone(),
            tested: Vec::new(),
            statistic: f64::INFINITY,
            dof: 0,
            p_value: 0.0,
            predicted_share: f64::NAN,
            kept: true,
            in_scan: false,
        }
    }
}

/// One replay of the current model with the sensitivities to the modulus and every nested
/// candidate's parameters at their nulls, and beside it the grid candidates' replays (the most
/// friction first: the longest), on `workers`: the current model's columns, then each grid's.
fn replay_all(
    recording: &Recording,
    noise: &Noise,
    current: &ModelFit,
    candidates: &[Candidate],
    (nulls, cells): (&[Null], &[&Scene]),
    grids: &[Vec<(f64, Scene)>],
    workers: usize,
) -> Option<(Columns, Vec<GridColumns>)> {
    let mut targets: Vec<(&Scene, &str)> = vec![(&current.scene, "young_modulus")];
    for (scene, names) in nulls.iter().flatten() {
        targets.extend(names.iter().map(|n| (scene, *n)));
    }
    targets.extend(cells.iter().map(|s| (*s, "region_young_modulus")));
    // The contact's stiffness, a nuisance of the region scan (`contact_direction`).
    if !cells.is_empty() && !current.scene.fingers.is_empty() {
        targets.push((&current.scene, "contact_stiffness_scale"));
    }
    let mut jobs: Vec<(&Scene, Vec<(&Scene, &str)>)> = vec![(&current.scene, targets)];
    for (c, grid) in candidates.iter().zip(grids) {
        let name = on_a_grid(c).unwrap_or("friction");
        jobs.extend(
            grid.iter()
                .map(|(_, s)| (s, vec![(s, "young_modulus"), (s, name)])),
        );
    }
    // The main replay second, after the first grid point (a friction of 0.3 on a table is the
    // longest replay).
    if jobs.len() > 1 {
        jobs.swap(0, 1);
    }
    let mut solved = crate::sweep::parallel_map(
        &jobs,
        workers,
        |(scene, targets)| replay_columns(recording, noise, scene, targets),
        &|_| {},
    );
    if solved.len() > 1 {
        solved.swap(0, 1);
    }
    let mut solved = solved.into_iter();
    let main = solved.next().flatten()?;
    let grids = grids
        .iter()
        .map(|grid| {
            grid.iter()
                .map(|(mu, _)| (*mu, solved.next().flatten()))
                .collect()
        })
        .collect();
    Some((main, grids))
}

/// A nested candidate's score test in `names` at their values in its null `scene`, from its
/// columns with the modulus projected out.
fn nested(
    c: &Candidate,
    scene: &Scene,
    names: &[&'static str],
    columns: &[Vec<f64>],
    r: &[f64],
    s2: f64,
) -> Screen {
    let rss: f64 = r.iter().map(|x| x * x).sum();
    let values: Vec<(&'static str, f64)> = names
        .iter()
        .map(|n| {
            (
                *n,
                crate::params::get(scene, n).ok().flatten().unwrap_or(0.0),
            )
        })
        .collect();
    let one_sided = names.len() == 1 && at_lower_end(c, names[0], values[0].1);
    let statistic = score_statistic(columns, r, s2, one_sided);
    let p_value = chi_square_tail(statistic, names.len()) * if one_sided { 0.5 } else { 1.0 };
    Screen {
        effect: c.effect,
        variant: c.variant.clone(),
        tested: values,
        statistic,
        dof: names.len(),
        p_value,
        predicted_share: statistic * s2 / rss.max(f64::MIN_POSITIVE),
        kept: p_value < SCREEN_LEVEL,
        in_scan: false,
    }
}

/// The frictions a grid candidate (`on_a_grid`) is tried at, a decade in three steps below a
/// silicone's usual 0.3 to 1 (where contacts stick, and a higher friction changes little).
pub const FRICTION_GRID: [f64; 3] = [0.03, 0.1, 0.3];

/// The scenes of a grid candidate's grid: [`FRICTION_GRID`] and the model's own value of the
/// friction where it has one (a table's, the finger's: there the candidate is the model); the
/// current fit's modulus throughout.
fn friction_grid(current: &ModelFit, c: &Candidate, name: &str) -> Vec<(f64, Scene)> {
    use softgrip_core::scene::SupportKind;
    let mut grid: Vec<f64> = FRICTION_GRID.iter().rev().copied().collect();
    let own = match name {
        "table_friction" => (current.scene.support.kind == SupportKind::Table)
            .then_some(current.scene.support.friction),
        _ => crate::params::get(&current.scene, name).ok().flatten(),
    };
    if let Some(own) = own.filter(|v| !grid.contains(v)) {
        grid.push(own);
    }
    let modulus = crate::params::get(&current.scene, "young_modulus")
        .ok()
        .flatten();
    grid.into_iter()
        .filter_map(|mu| {
            let mut scene = crate::params::set(&c.scene, name, mu).ok()?;
            if let Some(e) = modulus {
                scene = crate::params::set(&scene, "young_modulus", e).ok()?;
            }
            Some((mu, scene))
        })
        .collect()
}

/// A nested candidate's null scene and the parameters its score is taken in.
type Null = Option<(Scene, Vec<&'static str>)>;

/// A replay's noise-weighted residual and its derivative in each parameter, column by column.
type Columns = (Vec<f64>, Vec<Vec<f64>>);

/// A grid candidate's replays: each friction with its columns, `None` where the replay failed.
type GridColumns = Vec<(f64, Option<Columns>)>;

/// A replay of `scene` with the sensitivities to `targets`: the noise-weighted residual and its
/// derivative in each target, column by column.
pub(super) fn replay_columns(
    recording: &Recording,
    noise: &Noise,
    scene: &Scene,
    targets: &[(&Scene, &str)],
) -> Option<Columns> {
    let options = ReplayOptions {
        rest: RestTolerance::for_fits(),
        ..ReplayOptions::default()
    };
    let mut steps: Option<ParameterSteps> = None;
    let mut at = |sim: &softgrip_core::Simulation,
                  mesh: &softgrip_core::mesh::TetMesh|
     -> Option<Vec<Vec<glam::DVec3>>> {
        if steps.is_none() {
            steps = Some(ParameterSteps::new(targets, mesh).ok()?);
        }
        let solved = steps
            .as_ref()?
            .solve(sim, fit_sensitivity_options_for(&sim.model))
            .ok()?;
        Some(solved.into_iter().map(|s| s.dx_dp).collect())
    };
    let (replay, d) =
        replay_observing(recording, scene, options, None, Some(&mut at), |_| {}).ok()?;
    let d = d?;
    let r = weighted_residuals(&replay.residuals, noise);
    let columns = (0..targets.len())
        .map(|j| {
            let mut c = Vec::with_capacity(r.len());
            for (res, dr) in replay.residuals.iter().zip(&d) {
                let sigma = noise.sigma(res.marker);
                for a in 0..3 {
                    if res.recorded[a].is_some() {
                        c.push(dr[j][a] / sigma);
                    }
                }
            }
            c
        })
        .collect();
    Some((r, columns))
}

/// A grid candidate ([`on_a_grid`]): its likelihood ratio against the current model at each
/// point of its grid ([`friction_grid`]) followed by one Gauss-Newton step in E and the
/// friction, `(RSS_current - RSS_j + r_j^T J (J^T J)^-1 J^T r_j) / s^2`, the supremum over the
/// grid taken as the statistic of a one-parameter test. `None` where a replay or its
/// sensitivities failed: the candidate is then fitted.
fn best_on_a_grid(
    c: &Candidate,
    name: &'static str,
    grid: &[(f64, Option<Columns>)],
    rss: f64,
    s2: f64,
) -> Option<Screen> {
    let mut best: Option<(f64, f64)> = None;
    for (mu, solved) in grid {
        let (r, columns) = solved.as_ref()?;
        let rss_j: f64 = r.iter().map(|x| x * x).sum();
        let ratio = (rss - rss_j) / s2 + score_statistic(columns, r, s2, false);
        if best.is_none_or(|(b, _)| ratio > b) {
            best = Some((ratio, *mu));
        }
    }
    let (statistic, mu) = best?;
    let p_value = if statistic > 0.0 {
        chi_square_tail(statistic, 1)
    } else {
        1.0
    };
    Some(Screen {
        effect: c.effect,
        variant: c.variant.clone(),
        tested: vec![(name, mu)],
        statistic,
        dof: 1,
        p_value,
        predicted_share: statistic * s2 / rss.max(f64::MIN_POSITIVE),
        kept: p_value < SCREEN_LEVEL,
        in_scan: false,
    })
}

/// `v` less its projection on `e`.
fn project_out(v: &[f64], e: &[f64]) -> Vec<f64> {
    let ee: f64 = e.iter().map(|x| x * x).sum();
    if ee == 0.0 {
        return v.to_vec();
    }
    let k = v.iter().zip(e).map(|(a, b)| a * b).sum::<f64>() / ee;
    v.iter().zip(e).map(|(a, b)| a - k * b).collect()
}

/// `r^T J (J^T J)^-1 J^T r / s2` for the columns `J` (one or two); one-sided for one column: 0
/// where the gradient asks the parameter to go below its end (`J^T r > 0`: raising it raises
/// the residual).
pub(super) fn score_statistic(columns: &[Vec<f64>], r: &[f64], s2: f64, one_sided: bool) -> f64 {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let g: Vec<f64> = columns.iter().map(|c| dot(c, r)).collect();
    let t = match columns.len() {
        1 => {
            let h = dot(&columns[0], &columns[0]);
            if h <= 0.0 || (one_sided && g[0] > 0.0) {
                0.0
            } else {
                g[0] * g[0] / h
            }
        }
        2 => {
            let (a, b, c) = (
                dot(&columns[0], &columns[0]),
                dot(&columns[0], &columns[1]),
                dot(&columns[1], &columns[1]),
            );
            let det = a * c - b * b;
            if det <= 1e-12 * a * c {
                // Collinear: the better of the two alone.
                let one = |h: f64, g: f64| if h > 0.0 { g * g / h } else { 0.0 };
                one(a, g[0]).max(one(c, g[1]))
            } else {
                (c * g[0] * g[0] - 2.0 * b * g[0] * g[1] + a * g[1] * g[1]) / det
            }
        }
        _ => 0.0,
    };
    t / s2
}

/// `P(X > t)` for X chi-square with 1 or 2 degrees of freedom.
fn chi_square_tail(t: f64, dof: usize) -> f64 {
    match dof {
        1 => 2.0 * super::statistics::upper_tail(t.max(0.0).sqrt()),
        2 => (-0.5 * t.max(0.0)).exp(),
        _ => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_statistic_is_the_share_a_regression_on_the_columns_removes() {
        // r = 2 x + noise-free orthogonal rest: the column x explains |2 x|^2 of |r|^2.
        let x = [1.0, -1.0, 0.5, 0.0];
        let rest = [0.0, 0.0, 0.0, 3.0];
        let r: Vec<f64> = x.iter().zip(&rest).map(|(a, b)| 2.0 * a + b).collect();
        let t = score_statistic(&[x.to_vec()], &r, 1.0, false);
        let explained: f64 = x.iter().map(|a| 4.0 * a * a).sum();
        assert!((t - explained).abs() < 1e-12, "{t} against {explained}");
        // One-sided: r along +x asks the parameter to go down (the residual is sim - data).
        assert_eq!(score_statistic(&[x.to_vec()], &r, 1.0, true), 0.0);
        let minus: Vec<f64> = r.iter().map(|v| -v).collect();
        assert!((score_statistic(&[x.to_vec()], &minus, 1.0, true) - explained).abs() < 1e-12);
    }

    #[test]
    fn two_columns_give_the_projection_on_their_span() {
        let a = vec![1.0, 0.0, 1.0, 0.0];
        let b = vec![1.0, 1.0, 0.0, 0.0];
        let r = vec![0.3, -0.7, 1.1, 2.0];
        // The span's projection of r, by the normal equations solved by hand.
        let t = score_statistic(&[a.clone(), b.clone()], &r, 1.0, false);
        // Orthonormal basis of span{a, b}: u = a / |a|, w = (b - (b.u) u) / |.|.
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let u: Vec<f64> = a.iter().map(|x| x / norm(&a)).collect();
        let bu: f64 = b.iter().zip(&u).map(|(x, y)| x * y).sum();
        let w0: Vec<f64> = b.iter().zip(&u).map(|(x, y)| x - bu * y).collect();
        let w: Vec<f64> = w0.iter().map(|x| x / norm(&w0)).collect();
        let ru: f64 = r.iter().zip(&u).map(|(x, y)| x * y).sum();
        let rw: f64 = r.iter().zip(&w).map(|(x, y)| x * y).sum();
        assert!((t - (ru * ru + rw * rw)).abs() < 1e-12);
    }

    #[test]
    fn the_chi_square_tails_are_the_known_quantiles() {
        assert!((chi_square_tail(3.841_458_820_694_124, 1) - 0.05).abs() < 1e-6);
        assert!((chi_square_tail(5.991_464_547_107_979, 2) - 0.05).abs() < 1e-9);
    }
}
