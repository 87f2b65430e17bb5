//! `softgrip diagnose`: find what physics a fitted model still misses
//! against a recording (`softgrip_lab::diagnose`).

use std::path::PathBuf;

use anyhow::Result;
use softgrip_lab::diagnose::{self, DiagnoseOptions};
use softgrip_lab::recording::Recording;

use super::args::{ReportArgs, WorkersArgs};
use super::figures::write_json_line;
use super::progress::{progress_bar, show_stages};

/// Missing-physics diagnosis: fit the model (by default the continuum's E;
/// `--model scene` the scene's own: the lattice's E, alpha, tau_s, tau_c), locate what it still misses against the noise, fit a
/// catalogue of candidate effects (table-friction, strain-stiffening,
/// viscoelastic-creep, finger-friction, heterogeneous-stiffness,
/// load-loss; damping for time series) and name the one(s) that
/// explain it, or "none". Each fit is saved in the report directory as it
/// ends (fits.checkpoint): run the same command again to resume a diagnosis
/// stopped midway.
#[derive(clap::Args)]
pub struct Args {
    recording: PathBuf,
    /// Baseline parameters to keep at the scene's values (e.g. alpha).
    #[arg(long, num_args = 1..)]
    lock: Vec<String>,
    /// Ranges you know parameters lie in, NAME=LOW:HIGH (e.g.
    /// young_modulus=30e3:120e3 for a modulus measured at 60 kPa to
    /// within a factor of 2): every fit searches only there. A fit
    /// that needs E far from a measured small-strain value is
    /// absorbing physics the model lacks (strain-stiffening, creep).
    #[arg(long, num_args = 1..)]
    bound: Vec<String>,
    /// Simulations at most for the baseline fit (each candidate's fit
    /// gets 20 per parameter).
    #[arg(long, default_value_t = 80, value_parser = baseline_budget)]
    max_evaluations: usize,
    #[command(flatten)]
    workers: WorkersArgs,
    /// Levenberg-Marquardt's Jacobian from the equilibria's sensitivities (one replay for all
    /// parameters) where the fitted parameters have them, instead of finite differences.
    #[arg(long)]
    sensitivities: bool,
    /// Fit every candidate: no score test first (by default each round's candidates are
    /// screened by it, and those it finds nothing for are not fitted).
    #[arg(long)]
    no_screen: bool,
    /// Let the region scan's shapes (48 layers, quarters, octants and the inner block, the best
    /// placed by short fits) name a region of other stiffness, not only the four halves;
    /// quasi-static recordings, screened. Without it a region the halves name is still placed
    /// by the scan. Off by default: it reads some strain stiffening as a stiff top layer.
    #[arg(long)]
    region_scan: bool,
    /// The model to start from: `continuum` (neo-Hookean tetrahedra with nodal pressures,
    /// locking-free: the least form error to mistake for physics), `lattice` (the thesis's
    /// springs) or `scene` (the scene's own, as written)
    #[arg(long, default_value = "continuum", value_parser = ["continuum", "lattice", "scene"])]
    model: String,
    /// Also write the spec's JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    #[command(flatten)]
    report: ReportArgs,
}

/// `--max-evaluations`: the baseline's Levenberg-Marquardt fit needs a few steps of a
/// Jacobian each (two simulations for E alone).
fn baseline_budget(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 10 => Ok(n),
        _ => Err(format!(
            "{s}: give a whole number of simulations, 10 or more (default 80): the baseline fit takes a few Levenberg-Marquardt steps of a Jacobian each"
        )),
    }
}

pub fn run(args: Args) -> Result<()> {
    let (recording_path, lock, bound) = (args.recording.as_path(), &args.lock, &args.bound);
    let (max_evaluations, workers) = (args.max_evaluations, args.workers.workers);
    let (json, report) = (args.json.as_deref(), &args.report);
    let bounds = bound
        .iter()
        .map(|b| diagnose::parse_bound(b))
        .collect::<Result<Vec<_>, _>>()
        .map_err(anyhow::Error::msg)?;
    let recording = Recording::load(recording_path)?;
    super::outputs::Outputs::new()
        .recording(&recording)
        .file("--json", json)
        .dir(
            "--report",
            report.dir("diagnose", recording_path).as_deref(),
        )
        .check()?;
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
        sensitivities: args.sensitivities,
        screen: !args.no_screen,
        region_scan: args.region_scan,
        model: diagnose::BaselineModel::from_name(&args.model),
        checkpoint: report
            .dir("diagnose", recording_path)
            .map(|dir| open_checkpoint(&dir))
            .transpose()?,
        ..DiagnoseOptions::default()
    };
    if let Some(c) = options
        .checkpoint
        .as_ref()
        .filter(|c| !c.is_empty() || c.simulations_len() > 0)
    {
        println!(
            "{} fits and {} simulations saved in {}: those of this diagnosis are not run again (delete the file to refit)",
            c.len(),
            c.simulations_len(),
            c.path().display()
        );
    }
    let bar = progress_bar(1, "fits");
    let d =
        diagnose::diagnose(&recording, &options, &show_stages(&bar)).map_err(anyhow::Error::msg)?;
    bar.finish_and_clear();
    if let Some(c) = options.checkpoint.as_ref() {
        tell_checkpoint(c);
    }
    print_fits(&d);
    print_verdict(&d);
    if let Some(dir) = report.dir("diagnose", recording_path) {
        let written = softgrip_lab::report::diagnosis(&dir, &recording, &d)?;
        println!("report: {}", written.markdown.display());
    }
    if let Some(path) = json {
        write_json_line(path, &diagnose::to_json(&d, &recording))?;
    }
    Ok(())
}

/// What the checkpoint gave and what it could not: fits taken from it, saved fits refitted, a
/// file that could not be written.
fn tell_checkpoint(c: &diagnose::Checkpoint) {
    if let Some(c) = Some(c).filter(|c| c.reused() > 0) {
        let s = c.reused_seconds();
        let saved = if s < 120.0 {
            format!("{s:.0} s")
        } else {
            format!("{:.0} min", s / 60.0)
        };
        println!(
            "resumed: {} fits taken from {} ({saved} of fitting saved)",
            c.reused(),
            c.path().display()
        );
    }
    if c.reused_simulations() > 0 {
        println!(
            "resumed: {} simulations of fits that had not ended taken from {}",
            c.reused_simulations(),
            c.path().display()
        );
    }
    if let Some(c) = Some(c).filter(|c| c.damaged() > 0) {
        eprintln!(
            "warning: {}: {} saved line(s) not as softgrip wrote them (a line edited or damaged, or a fit's values outside their bounds) were run again; delete the file to start afresh",
            c.path().display(),
            c.damaged()
        );
    }
    if let Some(e) = c.failed() {
        eprintln!("warning: fits not saved, a rerun would fit them again: {e}");
    }
}

/// Fitted parameters as "name value, ...".
fn params(p: &[(String, f64)]) -> String {
    p.iter()
        .map(|(k, v)| format!("{k} {v:.4e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The baseline, the noise, the mismatch, the score test and every candidate fitted.
fn print_fits(d: &diagnose::Diagnosis) {
    println!(
        "baseline ({}): {}; NRMSE {:.4}, over all markers {:.4}",
        d.model(),
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
    if let Some(line) = screen_line(&d.screens) {
        println!("{line}");
    }
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
}

/// The verdict, the fitted parameters with their errors, the fit before and after, the evidence
/// and the simulations it took.
fn print_verdict(d: &diagnose::Diagnosis) {
    // Every effect named, as the report's heading says ("none" or "unexplained" without one).
    let verdict = if d.effects.is_empty() {
        d.verdict()
    } else {
        d.effects.join(" + ")
    };
    if d.model_finding.is_some() {
        // The finding leads the evidence; the verdict is of the model that carries the loads.
        println!(
            "verdict: {verdict} (of the model and samples the finding at the start of the evidence names)"
        );
    } else {
        println!("verdict: {verdict}");
    }
    if !d.effects.is_empty() {
        let with_errors: Vec<String> = d
            .fitted_params()
            .iter()
            .map(|(n, v)| match d.standard_error(n) {
                Some(e) if e.is_finite() => format!("{n} {v:.4e} +/- {e:.1e}"),
                Some(_) => format!("{n} {v:.4e} (not determined by the data)"),
                None => format!("{n} {v:.4e}"),
            })
            .collect();
        println!("fitted: {}", with_errors.join(", "));
        if let Some(r) = d.region() {
            println!("{}", r.describe());
        }
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
    println!("time: {}", stage_times(&d.stages));
}

/// The report directory's `fits.checkpoint`, under a hash of this binary: a rebuilt softgrip
/// fits again rather than trust fits its older code made.
fn open_checkpoint(dir: &std::path::Path) -> Result<diagnose::Checkpoint> {
    diagnose::Checkpoint::open(&dir.join(CHECKPOINT), &build_name()?).map_err(|e| {
        anyhow::anyhow!("{e}: give --report a directory you can write, or --no-report (no resume)")
    })
}

/// This binary's build, for checkpoints: its commit and a hash of its bytes.
pub(super) fn build_name() -> Result<String> {
    let exe = std::env::current_exe()?;
    diagnose::build_of(env!("SOFTGRIP_COMMIT"), &exe).map_err(|e| {
        anyhow::anyhow!(
            "{}: {e} (reading this program to name its build)",
            exe.display()
        )
    })
}

/// Where in the report directory a diagnosis saves its fits.
const CHECKPOINT: &str = "fits.checkpoint";

/// The stages' wall times in one line: the total, then each stage (a candidate fitted in
/// several rounds summed), longest first.
fn stage_times(stages: &[(String, f64)]) -> String {
    let total: f64 = stages.iter().map(|(_, s)| s).sum();
    let mut summed: Vec<(String, f64)> = Vec::new();
    for (name, seconds) in stages {
        match summed.iter_mut().find(|(n, _)| n == name) {
            Some((_, s)) => *s += seconds,
            None => summed.push((name.clone(), *seconds)),
        }
    }
    summed.sort_by(|a, b| b.1.total_cmp(&a.1));
    let parts: Vec<String> = summed
        .iter()
        .map(|(name, s)| format!("{name} {s:.1} s"))
        .collect();
    format!("{total:.1} s in all: {}", parts.join(", "))
}

/// The score tests in one line: what each round fitted and what it ruled out.
fn screen_line(screens: &[(usize, diagnose::Screen)]) -> Option<String> {
    if screens.is_empty() {
        return None;
    }
    let label = |s: &diagnose::Screen| {
        let name = softgrip_lab::diagnose::effect_label(s.effect, &s.variant);
        if s.dof == 0 {
            format!("{name} (not tested: always fitted)")
        } else {
            format!("{name} (T {:.1}, p {:.2})", s.statistic, s.p_value)
        }
    };
    let rounds = screens.iter().map(|(r, _)| *r).max().unwrap_or(0);
    let mut parts = Vec::new();
    for round in 0..=rounds {
        let of: Vec<&diagnose::Screen> = screens
            .iter()
            .filter(|(r, _)| *r == round)
            .map(|(_, s)| s)
            .collect();
        let fitted: Vec<String> = of.iter().filter(|s| s.kept).map(|s| label(s)).collect();
        let scanned: Vec<String> = of.iter().filter(|s| s.in_scan).map(|s| label(s)).collect();
        let out: Vec<String> = of
            .iter()
            .filter(|s| !s.kept && !s.in_scan)
            .map(|s| label(s))
            .collect();
        let scanned = if scanned.is_empty() {
            String::new()
        } else {
            format!("; among the region scan's shapes {}", scanned.join(", "))
        };
        parts.push(format!(
            "round {}: fitted {}{scanned}; ruled out (p >= {}) {}",
            round + 1,
            if fitted.is_empty() {
                "none".to_string()
            } else {
                fitted.join(", ")
            },
            diagnose::SCREEN_LEVEL,
            if out.is_empty() {
                "none".to_string()
            } else {
                out.join(", ")
            }
        ));
    }
    Some(format!("score test: {}", parts.join("; ")))
}
