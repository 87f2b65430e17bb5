//! The report of `softgrip prove` (`--report`, by default `DIAGNOSIS.md`; the current one is
//! `docs/results/diagnosis.md`): how many cases the diagnosis got right, each case's figures, the
//! confusion matrix and every candidate fitted.

use std::fmt::Write as _;

use super::{Outcome, ProveOptions};
use crate::diagnose;
use softgrip_core::scene::Scene;

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

/// The run's setting and the counts: effects named right, markers located,
/// NRMSE halved.
fn write_summary(s: &mut String, outcomes: &[Outcome], prove: &ProveOptions) {
    let e_within = prove.e_measured_within;
    let truth_edge = match prove.truth_edge_length {
        Some(h) => format!(
            "{} mm edges (`--truth-edge-length {h}`; the suite's are 3 mm)",
            h * 1e3
        ),
        None => "3 mm edges".to_string(),
    };
    let _ = writeln!(
        s,
        "Made by `softgrip prove` ({}). Each recording is made by softgrip from a scene the diagnosis is not given ({truth_edge} and 1 ms steps instead of its 4 mm and 2 ms, E drawn log-uniformly in 0.8-1.25 times the nominal, the spring limits at 0.2; each effect's strength, and a region's place, drawn from the seed within its range), with 0.1 mm of Gaussian noise, x and z only, 8 markers on the contour of the object's mid-plane section (as the thesis's camera saw it) and the finger; the diagnosis gets the nominal scene (the thesis light guide with a sphere; a flat plate for the finger-friction cases and their control) and the recording{}, and is not told what is hidden.\n",
        softgrip_core::bench::machine_description(),
        match e_within {
            Some(f) => format!(
                ", and the range E was measured in: a factor of {f} either way of the nominal E, as a compression test's initial slope gives it (`softgrip prove --e-measured-within {f}`; by hand, `softgrip diagnose REC --bound young_modulus=LOW:HIGH`)"
            ),
            None => String::new(),
        }
    );
    let effect_cases: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| !o.case.effects.is_empty())
        .collect();
    let controls: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.case.effects.is_empty())
        .collect();
    let right = |v: &[&Outcome]| v.iter().filter(|o| o.right()).count();
    let _ = writeln!(
        s,
        "**Effects named right: {} of {}; controls called \"none\": {} of {}.**\n",
        right(&effect_cases),
        effect_cases.len(),
        right(&controls),
        controls.len()
    );
    let located: Vec<bool> = outcomes.iter().filter_map(Outcome::located).collect();
    let _ = writeln!(
        s,
        "**The marker the hidden effect moves most is among those called mismatched: {} of {}.**\n",
        located.iter().filter(|l| **l).count(),
        located.len()
    );
    // Acceptance 1's third part, where an effect is present and named.
    let named_right: Vec<&&Outcome> = effect_cases.iter().filter(|o| o.right()).collect();
    let halved = |ratio: &dyn Fn(&Outcome) -> Option<f64>| {
        named_right
            .iter()
            .filter(|o| ratio(o).is_some_and(|r| r <= 0.5))
            .count()
    };
    let against_recording = halved(&|o| {
        let d = o.diagnosis.as_ref().ok()?;
        Some(d.final_fit.errors.nrmse_all / d.baseline.errors.nrmse_all)
    });
    let against_truth = halved(&|o| o.truth_errors.map(|[b, a]| a / b));
    // The bound on the first: the truth itself in place of the final fit.
    let reachable = halved(&|o| {
        let d = o.diagnosis.as_ref().ok()?;
        Some(o.noise_floor? / d.baseline.errors.nrmse_all)
    });
    let beyond_noise = halved(&|o| {
        let (b, a) = o.diagnosis.as_ref().ok()?.nrmse_all_beyond_noise();
        (b > 0.0).then(|| a / b)
    });
    let _ = writeln!(
        s,
        "**NRMSE all falls by half in {against_recording} of the {} cases named right against the recording, and in {against_truth} against the noise-free recording of the truth** (the model's own error: the noise, about 0.003 here, is a floor the first cannot go below; the columns \"truth\" below). **The truth itself, the model that made the data, halves it against the recording in {reachable}** (the column \"the truth itself\": its NRMSE all against the recording is the noise's alone, the lowest \"after\" any model can reach but for the few per cent a fit's parameters take out of the noise itself; where it is well over half of \"before\", no diagnosis can halve the error). **Beyond the noise** (the part of the residual the diagnosis's own noise estimate does not account for, which a lab can compute without the truth; the column \"beyond the noise\"), **it falls by half in {beyond_noise}.**\n",
        named_right.len()
    );
}

/// One row per case: the verdict, NRMSE before and after against the
/// recording and the truth, the parameters recovered, the markers.
/// A case by its name, its seed and, for a hidden region, its place.
fn case_label(o: &Outcome) -> String {
    match o.case.region {
        Some(place) => format!("{} ({place}), seed {:x}", o.case.name, o.seed),
        None => format!("{}, seed {:x}", o.case.name, o.seed),
    }
}

fn write_table(s: &mut String, outcomes: &[Outcome]) {
    s.push_str("| case | hidden | named | right | NRMSE all before | after | after / before | the truth itself (/ before) | truth before | truth after | truth after / before | beyond the noise: before, after (after / before) | recovered (hidden) | moved most by the effect | called mismatched | finer mesh, half step: move / noise | seconds |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for o in outcomes {
        let hidden = if o.case.effects.is_empty() {
            "none".to_string()
        } else {
            o.case.effects.join(" + ")
        };
        match &o.diagnosis {
            Ok(d) => {
                let named = if d.effects.is_empty() {
                    d.verdict()
                } else {
                    d.effects.join(" + ")
                };
                let recovered: Vec<String> = o
                    .case
                    .truth
                    .iter()
                    .map(|(name, v)| {
                        let got = d
                            .final_fit
                            .params
                            .iter()
                            .find(|(n, _)| n == name)
                            .map(|(_, g)| *g)
                            // An effect accepted in an earlier round keeps
                            // its value in the scene.
                            .or_else(|| {
                                let get = |s: &Scene| crate::params::get(s, name).ok().flatten();
                                get(&d.final_fit.scene).filter(|g| Some(*g) != get(&o.case.nominal))
                            })
                            .map_or("-".to_string(), |g| format!("{g:.3}"));
                        format!("{name} {got} ({v})")
                    })
                    .collect();
                let moved: Vec<String> = o
                    .moved
                    .iter()
                    .take(3)
                    .map(|(m, v)| format!("{m} {:.2} mm", 1e3 * v))
                    .collect();
                let mismatched: Vec<&str> =
                    d.location.markers.iter().map(|(m, _)| m.as_str()).collect();
                let itself = o.noise_floor.map_or(String::new(), |f| {
                    format!("{f:.5} ({:.2})", f / d.baseline.errors.nrmse_all)
                });
                let truth = o.truth_errors.map_or(" | | ".to_string(), |[b, a]| {
                    format!("{b:.5} | {a:.5} | {:.2}", a / b)
                });
                let over = |check: &crate::discretisation::Outcome| {
                    check
                        .measured()
                        .filter(|c| c.noise_measured)
                        .map_or("-".to_string(), |c| format!("{:.1}", c.over_noise))
                };
                let beyond = {
                    let (b, a) = d.nrmse_all_beyond_noise();
                    if b > 0.0 {
                        format!("{b:.5}, {a:.5} ({:.2})", a / b)
                    } else {
                        format!("{b:.5}, {a:.5}")
                    }
                };
                let discretisation = format!(
                    "{}, {}",
                    over(&d.discretisation.mesh),
                    over(&d.discretisation.time_step)
                );
                let _ = writeln!(
                    s,
                    "| {} | {hidden} | {named} | {} | {:.5} | {:.5} | {:.2} | {itself} | {truth} | {beyond} | {} | {} | {} | {discretisation} | {:.0} |",
                    case_label(o),
                    if o.right() { "yes" } else { "NO" },
                    d.baseline.errors.nrmse_all,
                    d.final_fit.errors.nrmse_all,
                    d.final_fit.errors.nrmse_all / d.baseline.errors.nrmse_all,
                    recovered.join(", "),
                    moved.join(", "),
                    mismatched.join(" "),
                    o.seconds
                );
            }
            Err(e) => {
                let _ = writeln!(
                    s,
                    "| {} | {hidden} | failed: {e} | NO | | | | | | | | | | | | | {:.0} |",
                    case_label(o),
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
    s.push_str("\n## Candidates per case\n\nEvery candidate fitted, by round: the change of BIC against the model it was added to (an effect is accepted below -10 when it also removes 10 % of the weighted residual and Vuong's z against the best other effect, or against the model without it when its round has no other, is 2 or more), the share removed and z. When the best two effects both pass BIC and the share but neither beats the other by z 2, they are fitted together, and each is named when the pair needs it: leaving it out must cost the same three thresholds (Vuong's z here is the pair against the pair without it; z by sample, which counts each sample once, is shown beside it); when leaving one out lowers BIC, the pair does not need it at all, and the other is judged as a lone candidate: by Vuong's z against the model without it.\n\n");
    for o in outcomes {
        let Ok(d) = &o.diagnosis else { continue };
        let mut line = format!("- **{}**: ", case_label(o));
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
        let parts: Vec<String> = ranked
            .iter()
            .map(|h| {
                let name = diagnose::effect_label(h.effect, &h.variant);
                format!(
                    "r{} {name} {:+.0} / {:.0} %{}",
                    h.round + 1,
                    h.score,
                    100.0 * h.explained,
                    match h.vuong {
                        Some(z) if h.against_model =>
                            format!(" / z {z:+.1} against {}", h.rival_text()),
                        Some(z) => format!(" / z {z:+.1}"),
                        None => String::new(),
                    }
                )
            })
            .collect();
        line.push_str(&parts.join("; "));
        if let Some(t) = &d.pair {
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
        let _ = writeln!(s, "{line}");
    }
}
