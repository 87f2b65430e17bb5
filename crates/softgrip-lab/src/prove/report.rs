//! The report of `softgrip prove` (`--report`, by default `DIAGNOSIS.md`; the current one is
//! `docs/results/diagnosis.md`): how many cases the diagnosis got right, each case's figures, the
//! confusion matrix and every candidate fitted.

use std::fmt::Write as _;

use super::{Outcome, ProveOptions};
use crate::diagnose::{self, BaselineModel};
use glam::DVec3;
use softgrip_core::scene::{AaBox, Scene};

/// The report: the confusion matrix, NRMSE before and after, and the
/// recovered parameters against the hidden ones.
pub fn report(outcomes: &[Outcome], prove: &ProveOptions) -> String {
    let mut s = String::from("# The diagnosis on concealed data\n\n");
    write_summary(&mut s, outcomes, prove);
    write_table(&mut s, outcomes);
    write_confusion_matrix(&mut s, outcomes);
    write_candidates(&mut s, outcomes);
    s
}

/// A hidden parameter against what the diagnosis recovered.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovery {
    /// The parameter, by the diagnosis's name.
    pub name: &'static str,
    /// Its hidden value (a region's modulus as its ratio to the object's E).
    pub hidden: f64,
    /// The final model's value (a region's as its ratio to the object's E, as the hidden one),
    /// `None` where the effect was not named.
    pub recovered: Option<f64>,
    /// The final model's standard error of it, in its unit; `None` for a region's ratio, or
    /// where the effect was not named.
    pub standard_error: Option<f64>,
    /// Whether the two measure the same thing: the lattice's stiffening is another law than the
    /// truth's (Yeoh's on the continuum), so only a continuum baseline's is compared.
    pub comparable: bool,
}

impl Recovery {
    /// Within 30 % of the hidden value (or 0.01 of a coefficient below 0.033, where 30 % is
    /// below what 0.1 mm of noise can tell).
    pub fn within(&self) -> Option<bool> {
        let got = self.recovered?;
        self.comparable
            .then(|| (got - self.hidden).abs() <= (0.3 * self.hidden.abs()).max(0.01))
    }
}

/// The hidden parameters of `o`'s case against the diagnosis's final model.
pub fn recoveries(o: &Outcome) -> Vec<Recovery> {
    let Ok(d) = &o.diagnosis else {
        return Vec::new();
    };
    let get = |s: &Scene, name: &str| crate::params::get(s, name).ok().flatten();
    let fitted = &d.final_fit.scene;
    o.case
        .truth
        .iter()
        .map(|&(name, hidden)| {
            let effect = match name {
                "table_friction" => "table-friction",
                "stiffening" => "strain-stiffening",
                "prony_g" | "prony_tau" => "viscoelastic-creep",
                "friction" => "finger-friction",
                "region_young_modulus" => "heterogeneous-stiffness",
                _ => "load-loss",
            };
            let named = d.effects.contains(&effect);
            let (hidden, recovered, standard_error) = if name == "region_young_modulus" {
                let truth_e = o.case.truth_scene.object.young_modulus;
                let mut got = fitted
                    .regions
                    .last()
                    .map(|r| r.young_modulus / fitted.object.young_modulus);
                // A stiffer bottom half on a softer rest is the same specimen as a softer top
                // half: read from the opposite half, the hidden ratio is the inverse.
                if opposite_half(o) {
                    got = got.map(|r| 1.0 / r);
                }
                (hidden / truth_e, got, None)
            } else {
                (hidden, get(fitted, name), d.standard_error(name))
            };
            Recovery {
                name,
                hidden,
                recovered: recovered.filter(|_| named),
                standard_error: standard_error.filter(|_| named),
                comparable: name != "stiffening" || o.model == BaselineModel::Continuum,
            }
        })
        .collect()
}

/// The region the diagnosis named (its variant's words), where it named one.
fn place_named(o: &Outcome) -> Option<String> {
    let d = o.diagnosis.as_ref().ok()?;
    d.hypotheses
        .iter()
        .find(|h| h.effect == "heterogeneous-stiffness" && d.named(h))
        .map(|h| h.variant.clone())
}

/// How a named region stands to the hidden one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// Its centre inside the hidden region, its volume within a factor of 2.
    Same,
    /// The same of its complement in the object: a stiffer bottom half on a softer rest is the
    /// same specimen as a softer top half (the baseline's E is fitted too); the ratio inverts.
    Complement,
}

/// A box's part inside the object's bounds `(lo, hi)`: its centre and volume.
fn clipped(b: &AaBox, (lo, hi): (DVec3, DVec3)) -> (DVec3, f64) {
    let (min, max) = (b.min.max(lo), b.max.min(hi));
    let size = (max - min).max(DVec3::ZERO);
    (0.5 * (min + max), size.x * size.y * size.z)
}

/// Where `named` stands to `hidden` in an object with bounds `object` ([`Place`]).
pub fn place_of(hidden: &AaBox, named: &AaBox, object: (DVec3, DVec3)) -> Option<Place> {
    let (centre, volume) = clipped(named, object);
    let (_, hidden_volume) = clipped(hidden, object);
    let size = object.1 - object.0;
    let (whole_centre, whole) = (0.5 * (object.0 + object.1), size.x * size.y * size.z);
    let within_two = |v: f64| {
        v > 0.0 && hidden_volume > 0.0 && (v / hidden_volume).max(hidden_volume / v) <= 2.0
    };
    let inside = |c: DVec3| hidden.contains(c);
    if inside(centre) && within_two(volume) {
        return Some(Place::Same);
    }
    let rest = whole - volume;
    let rest_centre = (whole_centre * whole - centre * volume) / rest.max(f64::MIN_POSITIVE);
    (rest > 0.0 && inside(rest_centre) && within_two(rest)).then_some(Place::Complement)
}

/// Where the diagnosis's region stands to the hidden one, where both are.
pub fn place(o: &Outcome) -> Option<Place> {
    let d = o.diagnosis.as_ref().ok()?;
    if !d.effects.contains(&"heterogeneous-stiffness") {
        return None;
    }
    let hidden = o.case.truth_scene.regions.first()?;
    let named = d.final_fit.scene.regions.last()?;
    let mesh = softgrip_core::model::Model::mesh_of(&o.case.truth_scene).ok()?;
    place_of(&hidden.region, &named.region, mesh.bounds())
}

/// The diagnosis named the complement of the hidden region: the same two-modulus specimen,
/// read from the other side.
fn opposite_half(o: &Outcome) -> bool {
    place(o) == Some(Place::Complement)
}

/// After over the truth itself against the recording (the noise's floor).
fn after_over_floor(o: &Outcome) -> Option<f64> {
    Some(o.diagnosis.as_ref().ok()?.final_fit.errors.nrmse_all / o.noise_floor?)
}

/// Whether the hidden effect moves a marker by more than twice the noise (noise-free, RMS over
/// the samples).
pub fn above_noise(o: &Outcome) -> bool {
    o.moved.first().is_some_and(|m| m.1 > 2.0 * super::NOISE)
}

/// The model of the effect is right: every comparable parameter within 30 % and a region in
/// its place ([`Place`]: its centre inside the hidden one, its volume within a factor of 2, or
/// the same of its complement with the inverse ratio).
fn modelled(o: &Outcome) -> Option<bool> {
    let r = recoveries(o);
    let checked: Vec<bool> = r.iter().filter_map(Recovery::within).collect();
    let place = o.case.region.as_ref().map(|_| place(o).is_some());
    if checked.is_empty() && place.is_none() {
        return None;
    }
    Some(checked.iter().all(|b| *b) && place.unwrap_or(true))
}

/// The run's setting and, per model, today's figures against the acceptance.
fn write_summary(s: &mut String, outcomes: &[Outcome], prove: &ProveOptions) {
    let truth_edge = match prove.truth_edge_length {
        Some(h) => format!("{} mm edges (`--truth-edge-length {h}`)", h * 1e3),
        None => format!("{} mm edges", super::suite::TRUTH_EDGE * 1e3),
    };
    let mut seeds: Vec<u64> = outcomes.iter().map(|o| o.seed).collect();
    seeds.dedup();
    let seeds: Vec<String> = seeds.iter().map(|s| format!("{s:#x}")).collect();
    let _ = writeln!(
        s,
        "Made by `softgrip prove`{} on {}, seeds {}. Each recording is made by another model than the diagnosis's: a continuum (neo-Hookean tetrahedra with nodal pressures, checked against NGSolve) on {truth_edge}, 1 ms steps, E drawn log-uniformly in 0.8-1.25 times the nominal, each effect's strength (and a region's place) drawn from the seed within its stated range; 0.1 mm of Gaussian noise, x and z only, 8 markers on the contour of the object's mid-plane and the finger. The diagnosis gets the nominal scene as a lab writes it (the thesis's lattice at 4 mm, fitted as the continuum, `diagnose`'s default, or as the lattice: column model) and the recording{}, and is not told what is hidden.\n",
        prove
            .commit
            .filter(|c| !c.is_empty())
            .map(|c| format!(" built from commit `{c}`"))
            .unwrap_or_default(),
        softgrip_core::bench::machine_description(),
        seeds.join(", "),
        match prove.e_measured_within {
            Some(f) => format!(", and E's measured range, a factor of {f} either way"),
            None => String::new(),
        }
    );
    let resumed: Vec<&Outcome> = outcomes.iter().filter(|o| o.resumed > 0).collect();
    if !resumed.is_empty() {
        let _ = writeln!(
            s,
            "{} of the {} verdicts resumed from checkpoints ({} fits taken from them); a resumed verdict's seconds count each fit taken at the time it took the run that saved it.\n",
            resumed.len(),
            outcomes.len(),
            resumed.iter().map(|o| o.resumed).sum::<usize>()
        );
    }
    s.push_str("| model | effects named right | controls \"none\" | two effects both found (seeds) | after <= 1.25 x the truth itself (named, above the noise) | parameters within 30 %, region in its half (named) | verdicts without error | seconds a verdict (mean, max) |\n|---|---|---|---|---|---|---|---|\n");
    let mut models: Vec<BaselineModel> = outcomes.iter().map(|o| o.model).collect();
    models.sort_by_key(|m| m.name());
    models.dedup();
    for model in models {
        write_headline_row(s, outcomes, model);
    }
    let below: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.case.effects.is_empty() && !above_noise(o))
        .map(|o| {
            format!(
                "{} ({:.2} mm)",
                case_label(o),
                1e3 * o.moved.first().map_or(0.0, |m| m.1)
            )
        })
        .collect();
    let _ = writeln!(
        s,
        "\nTargets: named right in 90 % of effect cases, no false alarm, both effects in 2 of 3 seeds; after within 1.25 x the truth itself (the truth replayed against its own noisy recording: the noise's floor) in 80 % of the named cases whose effect moves a marker by more than twice the noise; the effect's parameters within 30 % (0.01 for a coefficient below 0.033) with the region in its place in 80 % of named cases (its centre inside the hidden region and its volume within a factor of 2, or the same of its complement in the object with the inverse ratio: a stiffer bottom half on a softer rest is the same specimen as a softer top half, since the baseline's E is fitted too). The lattice's stiffening is another law than the truth's and is not compared. Effects at or below twice the noise: {}.\n",
        if below.is_empty() {
            "none".to_string()
        } else {
            below.join(", ")
        }
    );
    write_modulus_bias(s, outcomes);
}

/// The headline table's row of one model: today's figures against the acceptance.
fn write_headline_row(s: &mut String, outcomes: &[Outcome], model: BaselineModel) {
    let of: Vec<&Outcome> = outcomes.iter().filter(|o| o.model == model).collect();
    let effects: Vec<&&Outcome> = of.iter().filter(|o| !o.case.effects.is_empty()).collect();
    let controls: Vec<&&Outcome> = of.iter().filter(|o| o.case.effects.is_empty()).collect();
    let pairs: Vec<&&Outcome> = effects
        .iter()
        .filter(|o| o.case.effects.len() > 1)
        .copied()
        .collect();
    let right = |v: &[&&Outcome]| v.iter().filter(|o| o.right()).count();
    let named: Vec<&&Outcome> = effects.iter().filter(|o| o.right()).copied().collect();
    let above: Vec<&&Outcome> = named.iter().filter(|o| above_noise(o)).copied().collect();
    let floor_ok = above
        .iter()
        .filter(|o| after_over_floor(o).is_some_and(|r| r <= 1.25))
        .count();
    let with_model: Vec<bool> = named.iter().filter_map(|o| modelled(o)).collect();
    let seconds: Vec<f64> = of.iter().map(|o| o.seconds).collect();
    let pct = |a: usize, b: usize| {
        if b == 0 {
            0.0
        } else {
            100.0 * a as f64 / b as f64
        }
    };
    let _ = writeln!(
        s,
        "| {} | {} of {} ({:.0} %) | {} of {} | {} of {} | {} of {} ({:.0} %) | {} of {} ({:.0} %) | {} of {} | {:.0}, {:.0} |",
        model.name(),
        right(&effects),
        effects.len(),
        pct(right(&effects), effects.len()),
        right(&controls),
        controls.len(),
        right(&pairs),
        pairs.len(),
        floor_ok,
        above.len(),
        pct(floor_ok, above.len()),
        with_model.iter().filter(|b| **b).count(),
        with_model.len(),
        pct(with_model.iter().filter(|b| **b).count(), with_model.len()),
        of.iter().filter(|o| o.diagnosis.is_ok()).count(),
        of.len(),
        seconds.iter().sum::<f64>() / seconds.len().max(1) as f64,
        seconds.iter().cloned().fold(0.0, f64::max),
    );
}

/// The baseline's E over the truth's on the controls, per model: the bias the model's own form
/// puts into every fitted size (the truth's E is its small-strain modulus).
fn write_modulus_bias(s: &mut String, outcomes: &[Outcome]) {
    let mut models: Vec<BaselineModel> = outcomes.iter().map(|o| o.model).collect();
    models.sort_by_key(|m| m.name());
    models.dedup();
    for model in models {
        let ratios: Vec<(String, f64)> = outcomes
            .iter()
            .filter(|o| o.model == model && o.case.effects.is_empty())
            .filter_map(|o| {
                let d = o.diagnosis.as_ref().ok()?;
                let e = d
                    .baseline
                    .params
                    .iter()
                    .find(|(n, _)| n == "young_modulus")?
                    .1;
                Some((
                    o.case.name.clone(),
                    e / o.case.truth_scene.object.young_modulus,
                ))
            })
            .collect();
        if ratios.is_empty() {
            continue;
        }
        let mean = ratios.iter().map(|r| r.1).sum::<f64>() / ratios.len() as f64;
        let each: Vec<String> = ratios
            .iter()
            .map(|(n, r)| format!("{n} {:+.1} %", 100.0 * (r - 1.0)))
            .collect();
        let _ = writeln!(
            s,
            "The {} baseline's E against the truth's on the controls (the model's own form, in every size it fits): {:+.1} % on average; {}.\n",
            model.name(),
            100.0 * (mean - 1.0),
            each.join(", ")
        );
    }
}

/// A case by its name, its seed, the model and, for a hidden region, its place.
fn case_label(o: &Outcome) -> String {
    match &o.case.region {
        Some(place) => format!("{} ({place}), seed {:x}", o.case.name, o.seed),
        None => format!("{}, seed {:x}", o.case.name, o.seed),
    }
}

/// One row per case and model: the verdict, NRMSE all before and after over the truth itself,
/// hidden against recovered, where.
fn write_table(s: &mut String, outcomes: &[Outcome]) {
    s.push_str("\n## Case by case\n\n| case | model | hidden | named | right | moved most by the effect | NRMSE all before, after / the truth itself | hidden -> recovered +/- standard error | region named | truth's own error before -> after | seconds |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for o in outcomes {
        let hidden = if o.case.effects.is_empty() {
            "none".to_string()
        } else {
            o.case.effects.join(" + ")
        };
        let moved = o
            .moved
            .first()
            .map_or("-".to_string(), |(m, v)| format!("{m} {:.2} mm", 1e3 * v));
        match &o.diagnosis {
            Ok(d) => {
                let named = if d.effects.is_empty() {
                    d.verdict()
                } else {
                    d.effects.join(" + ")
                };
                let recovered: Vec<String> = recoveries(o)
                    .iter()
                    .map(|r| {
                        let name = if r.name == "region_young_modulus" {
                            "region E / E"
                        } else {
                            r.name
                        };
                        let got = match (r.recovered, r.standard_error) {
                            (Some(g), Some(e)) if e.is_finite() => format!("{g:.3} +/- {e:.2}"),
                            (Some(g), _) => format!("{g:.3}"),
                            (None, _) => "-".to_string(),
                        };
                        let mark = match r.within() {
                            Some(true) => "",
                            Some(false) => " (off)",
                            None if !r.comparable => " (other law)",
                            None => "",
                        };
                        format!("{name} {:.3} -> {got}{mark}", r.hidden)
                    })
                    .collect();
                let floor = |v: f64| {
                    o.noise_floor
                        .map_or("-".to_string(), |f| format!("{:.2}", v / f))
                };
                let truth = o
                    .truth_errors
                    .map_or("-".to_string(), |[b, a]| format!("{b:.4} -> {a:.4}"));
                let _ = writeln!(
                    s,
                    "| {} | {} | {hidden} | {named} | {} | {moved} | {}, {} | {} | {} | {truth} | {:.0} |",
                    case_label(o),
                    o.model.name(),
                    if o.right() { "yes" } else { "NO" },
                    floor(d.baseline.errors.nrmse_all),
                    floor(d.final_fit.errors.nrmse_all),
                    recovered.join("; "),
                    match (place_named(o), place(o)) {
                        (Some(p), Some(Place::Complement)) =>
                            format!("{p} (placed: the complement, ratio inverted)"),
                        (Some(p), Some(Place::Same)) => format!("{p} (placed)"),
                        (Some(p), None) if o.case.region.is_some() => format!("{p} (misplaced)"),
                        (Some(p), None) => p,
                        (None, _) => "-".into(),
                    },
                    o.seconds
                );
            }
            Err(e) => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {hidden} | failed: {e} | NO | {moved} | | | | | {:.0} |",
                    case_label(o),
                    o.model.name(),
                    o.seconds
                );
            }
        }
    }
}

/// Confusion matrix: hidden (rows) against named (columns).
fn write_confusion_matrix(s: &mut String, outcomes: &[Outcome]) {
    let mut names = vec!["none"];
    names.extend(diagnose::EFFECTS);
    names.push("unexplained");
    s.push_str("\n## Confusion matrix\n\nRows: what was hidden; columns: what the diagnosis named (a two-effect case counts once per effect hidden, under each effect named).\n\n| hidden \\ named |");
    for n in &names {
        let _ = write!(s, " {n} |");
    }
    s.push_str("\n|---|");
    for _ in &names {
        s.push_str("---|");
    }
    s.push('\n');
    for row in names.iter().take(7) {
        let _ = write!(s, "| {row} |");
        for &col in &names {
            let count = outcomes
                .iter()
                .filter(|o| {
                    let hidden: Vec<&str> = if o.case.effects.is_empty() {
                        vec!["none"]
                    } else {
                        o.case.effects.clone()
                    };
                    let named: Vec<String> = match &o.diagnosis {
                        Ok(d) if d.effects.is_empty() => vec![d.verdict()],
                        Ok(d) => d.effects.iter().map(|e| e.to_string()).collect(),
                        Err(_) => vec![],
                    };
                    hidden.contains(row) && named.iter().any(|n| n == col)
                })
                .count();
            let _ = write!(s, " {count} |");
        }
        s.push('\n');
    }
}

/// Every candidate fitted per case, by round, and the pair test.
fn write_candidates(s: &mut String, outcomes: &[Outcome]) {
    s.push_str("\n## Candidates per case\n\nEvery candidate fitted, by round: the change of BIC against the model it was added to (an effect is accepted below -10 when it also removes 10 % of the weighted residual and Vuong's z against the best other effect, or against the model without it when its round has no other, is 2 or more: for the best of an effect's forms or places, \"z of\" gives the z its forms' independent tests ask, up to 2.53), the share removed and z. When the best two effects both pass BIC and the share but neither beats the other by z 2, they are fitted together, and each is named when the pair needs it: leaving it out must cost the same three thresholds (Vuong's z here is the pair against the pair without it; z by sample, which counts each sample once, is shown beside it); when leaving one out lowers BIC, the pair does not need it at all, and the other is judged as a lone candidate: by Vuong's z against the model without it.\n\n");
    for o in outcomes {
        let Ok(d) = &o.diagnosis else { continue };
        let mut line = format!("- **{}, {}**: ", case_label(o), o.model.name());
        if !d.pinned.is_empty() {
            let _ = write!(
                line,
                "baseline at the edge of its range in {}; ",
                d.pinned.join(", ")
            );
        }
        if d.hypotheses.is_empty() {
            line.push_str("the baseline's residual is within the noise; nothing tried");
        }
        let mut ranked: Vec<&diagnose::Hypothesis> = d.hypotheses.iter().collect();
        ranked.sort_by(|a, b| {
            (a.round, a.score)
                .partial_cmp(&(b.round, b.score))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let parts: Vec<String> = ranked.iter().map(|h| candidate_text(h)).collect();
        line.push_str(&parts.join("; "));
        if let Some(left) = d.remainder.describe() {
            let aside = if d.set_aside.is_empty() {
                String::new()
            } else {
                format!("{} (set aside): ", d.set_aside.join(" + "))
            };
            let _ = write!(line, "; {aside}{left}");
        }
        if let Some(t) = &d.pair {
            write_pair(&mut line, t);
        }
        let _ = writeln!(s, "{line}");
    }
}

/// One candidate fitted: its round, name, change of BIC, share removed, Vuong's z (and the z its
/// forms' tests ask) and its fit's seconds.
fn candidate_text(h: &diagnose::Hypothesis) -> String {
    let name = diagnose::effect_label(h.effect, &h.variant);
    format!(
        "r{} {name} {:+.0} / {:.0} %{} ({:.0} s)",
        h.round + 1,
        h.score,
        100.0 * h.explained,
        match h.vuong {
            Some(z) if h.against_model => format!(" / z {z:+.2} against {}", h.rival_text()),
            Some(z) => format!(" / z {z:+.2}"),
            None => String::new(),
        } + &if h.tests > 1.0 && h.vuong.is_some() {
            format!(" of {:.2}", diagnose::vuong_threshold(h.tests))
        } else {
            String::new()
        },
        h.seconds
    )
}

/// The pair test of two tied effects, appended to `line`: each left out, and the lone test.
fn write_pair(line: &mut String, t: &diagnose::PairTest) {
    let z = |z: Option<f64>| z.map_or("-".into(), |z| format!("{z:+.1}"));
    let without: Vec<String> = (0..2)
        .map(|i| {
            let w = &t.without[i];
            format!(
                "without {} {:+.0} / {:.0} % / z {} ({} by sample){}",
                t.label(i),
                w.bic,
                100.0 * w.explained,
                z(w.vuong),
                z(w.vuong_by_sample),
                if w.needed { ", needed" } else { "" }
            )
        })
        .collect();
    let _ = write!(line, "; tied, fitted together: {}", without.join(", "));
    if let Some((i, lone)) = t.alone {
        let _ = write!(
            line,
            "; not needing {}, {} alone against the model without it: z {}",
            t.label(1 - i),
            t.label(i),
            z(lone)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn aabox(min: [f64; 3], max: [f64; 3]) -> AaBox {
        AaBox {
            min: DVec3::from_array(min),
            max: DVec3::from_array(max),
        }
    }

    /// A region is in its place when its centre is inside the hidden one and its volume within
    /// a factor of 2; naming the complement (the opposite half) is the same specimen; a half
    /// across the other axis, or a sliver inside, is not.
    #[test]
    fn a_named_region_is_placed_by_its_centre_and_volume_or_its_complements() {
        let object = (DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 2.0));
        let bottom_half = aabox([-2.0, -2.0, -1.0], [2.0, 2.0, 1.0]);
        let top_half = aabox([-2.0, -2.0, 1.0], [2.0, 2.0, 3.0]);
        let left_half = aabox([-2.0, -2.0, -1.0], [0.0, 2.0, 3.0]);
        let bottom_layer = aabox([-2.0, -2.0, -1.0], [2.0, 2.0, 0.5]);
        let sliver = aabox([-2.0, -2.0, -1.0], [2.0, 2.0, 0.2]);
        assert_eq!(
            place_of(&bottom_half, &bottom_half, object),
            Some(Place::Same)
        );
        assert_eq!(
            place_of(&bottom_half, &top_half, object),
            Some(Place::Complement)
        );
        assert_eq!(place_of(&bottom_layer, &left_half, object), None);
        // A quarter of the height in the bottom half: half its volume.
        assert_eq!(
            place_of(&bottom_half, &bottom_layer, object),
            Some(Place::Same)
        );
        assert_eq!(place_of(&bottom_half, &sliver, object), None);
    }

    /// The report says which build ran (the rules are the commit's), and says nothing of a
    /// commit it was not given.
    #[test]
    fn the_report_names_the_commit_it_was_built_from() {
        let with = ProveOptions {
            commit: Some("abc1234"),
            ..Default::default()
        };
        assert!(report(&[], &with).contains("built from commit `abc1234`"));
        for commit in [None, Some("")] {
            let without = ProveOptions {
                commit,
                ..Default::default()
            };
            assert!(!report(&[], &without).contains("built from commit"));
        }
    }
}
