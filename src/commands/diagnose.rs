//! `softgrip diagnose`: find what physics a fitted model still misses
//! against a recording (`softgrip_lab::diagnose`).

use std::path::Path;

use anyhow::Result;
use softgrip_lab::diagnose::{self, DiagnoseOptions};
use softgrip_lab::recording::Recording;

pub fn diagnose(
    recording_path: &Path,
    lock: &[String],
    bound: &[String],
    max_evaluations: usize,
    workers: usize,
    json: Option<&Path>,
    report: &super::lab::ReportArgs,
) -> Result<()> {
    let bounds = bound
        .iter()
        .map(|b| diagnose::parse_bound(b))
        .collect::<Result<Vec<_>, _>>()
        .map_err(anyhow::Error::msg)?;
    let recording = Recording::load(recording_path)?;
    println!(
        "{}: {} ({} samples, {} markers)",
        recording_path.display(),
        recording.description,
        recording.samples.len(),
        recording.markers.len()
    );
    let options = DiagnoseOptions {
        lock: lock.to_vec(),
        bounds,
        max_evaluations,
        workers,
        ..DiagnoseOptions::default()
    };
    let bar = super::progress_bar(1, "fits");
    let d = diagnose::diagnose(&recording, &options, &|done, total, what| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    })
    .map_err(anyhow::Error::msg)?;
    bar.finish_and_clear();
    let params = |p: &[(String, f64)]| {
        p.iter()
            .map(|(k, v)| format!("{k} {v:.4e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!(
        "baseline: {}; NRMSE {:.4}, over all markers {:.4}",
        params(&d.baseline.params),
        d.baseline.errors.nrmse,
        d.baseline.errors.nrmse_all
    );
    if !d.pinned.is_empty() {
        println!(
            "at the edge of its search range after the baseline fit: {}",
            d.pinned.join(", ")
        );
    }
    for (name, low, high) in &d.bounds {
        println!("searched within the range given: {name} {low:.4e} to {high:.4e}");
    }
    println!("noise (from the data): {}", d.noise.describe());
    println!("discretisation: {}", d.discretisation.describe());
    println!("mismatch: {}", d.location.description);
    println!(
        "| round | candidate | BIC change | residual removed | Vuong z against the best other effect | NRMSE all | parameters |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut ranked: Vec<&diagnose::Hypothesis> = d.hypotheses.iter().collect();
    ranked.sort_by(|a, b| {
        (a.round, a.score)
            .partial_cmp(&(b.round, b.score))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    for h in ranked {
        let name = diagnose::effect_label(h.effect, &h.variant);
        match &h.fit {
            Ok(f) => println!(
                "| {} | {name} | {:+.1} | {:.0} % | {} | {:.4} | {} |",
                h.round + 1,
                h.score,
                100.0 * h.explained,
                h.z_text(),
                f.errors.nrmse_all,
                params(&f.params)
            ),
            Err(e) => println!("| {} | {name} | failed | | | | {e} |", h.round + 1),
        }
    }
    if let Some(t) = &d.pair {
        println!(
            "| tie | {} + {}, together | | | | {:.4} | {} |",
            t.label(0),
            t.label(1),
            t.fit.errors.nrmse_all,
            params(&t.fit.params)
        );
    }
    println!("verdict: {}", d.verdict());
    if !d.effects.is_empty() {
        println!("effects: {}", d.effects.join(" + "));
        println!("fitted: {}", params(&d.fitted_params()));
        let (beyond_before, beyond_after) = d.nrmse_all_beyond_noise();
        println!(
            "NRMSE {:.4} -> {:.4}; over all markers {:.4} -> {:.4}; over all markers beyond the noise {:.4} -> {:.4}{}",
            d.baseline.errors.nrmse,
            d.final_fit.errors.nrmse,
            d.baseline.errors.nrmse_all,
            d.final_fit.errors.nrmse_all,
            beyond_before,
            beyond_after,
            if beyond_before > 0.0 {
                format!(" ({:.2} of it left)", beyond_after / beyond_before)
            } else {
                String::new()
            }
        );
    }
    println!("evidence: {}", d.evidence);
    let fits: Vec<usize> = d
        .hypotheses
        .iter()
        .filter_map(|h| h.fit.as_ref().ok())
        .map(|f| f.evaluations)
        .collect();
    let pair = d.pair.as_ref().map_or(0, |t| t.fit.evaluations);
    let candidates: usize = fits.iter().sum();
    println!(
        "{} simulations: baseline {} unweighted + {} weighted by the noise, {} candidate fits {}, pair {}",
        d.simulations,
        d.simulations
            .saturating_sub(d.baseline.evaluations + candidates + pair),
        d.baseline.evaluations,
        fits.len(),
        candidates,
        pair
    );
    if let Some(dir) = report.dir("diagnose", recording_path) {
        let written = softgrip_lab::report::diagnosis(&dir, &recording, &d)?;
        println!("report: {}", written.markdown.display());
    }
    if let Some(path) = json {
        let value = diagnose::to_json(&d, &recording);
        std::fs::write(path, serde_json::to_string_pretty(&value)? + "\n")
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}
