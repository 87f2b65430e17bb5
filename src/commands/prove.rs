//! `softgrip prove`: the diagnosis on concealed data; makes the suite of
//! recordings, diagnoses each blind and writes the report (by default
//! DIAGNOSIS.md; the current one is docs/results/diagnosis.md)
//! (`softgrip_lab::prove`).

use std::path::PathBuf;

use anyhow::{Context, Result};

use super::progress::{progress_bar, show_stages};

/// The diagnosis's proof on concealed data: make the suite of
/// recordings from a continuum (each effect at two strengths, eight controls, one with
/// two effects), diagnose each blind and write DIAGNOSIS.md.
#[derive(clap::Args)]
pub struct Args {
    /// Where the recordings go, and each case's fits as they end (`fits-MODEL.checkpoint`): the
    /// same command again resumes a proof stopped midway (delete the directory to refit).
    #[arg(long, default_value = "target/prove")]
    out: PathBuf,
    /// Only the cases whose name contains this (e.g. load-loss).
    #[arg(long, default_value = "")]
    only: String,
    /// Draw the cases (noise, the truth's E error, each effect's strength, a region's place)
    /// from this seed (decimal or 0x-hex, as the report prints it); repeat for several.
    /// Default: the three scored seeds, never used while the diagnosis was developed
    /// (`softgrip_lab::prove::SCORED_SEEDS`); develop on others (e.g. 1).
    #[arg(long, value_parser = super::args::seed)]
    seed: Vec<u64>,
    /// The report.
    #[arg(long, default_value = "DIAGNOSIS.md")]
    report: PathBuf,
    /// Tell the diagnosis E was measured to within this factor of the
    /// nominal value either way (`diagnose --bound`); by default it is
    /// not told.
    #[arg(long)]
    e_measured_within: Option<f64>,
    /// Make the truths with this edge length, m, instead of the suite's 0.002 (half the
    /// diagnosis's 0.004).
    #[arg(long)]
    truth_edge_length: Option<f64>,
    /// The model each diagnosis starts from: `lattice` (the thesis's springs, as the lab's scene
    /// is written) or `continuum` (`diagnose --model`); repeat for both (each recording is made
    /// once). Default: both.
    #[arg(long, value_parser = ["lattice", "continuum"])]
    model: Vec<String>,
    /// Diagnose with `diagnose --region-scan`: a region of other stiffness found from the data
    /// instead of the four halves.
    #[arg(long)]
    region_scan: bool,
}

/// `softgrip prove`: for each seed, the suite's cases made and diagnosed blind, the report
/// rewritten after each case (marked partial), then written whole and printed.
pub fn run(args: Args) -> Result<()> {
    let (out, only, report) = (&args.out, &args.only, &args.report);
    let options = &prove_options(&args)?;
    super::outputs::Outputs::new()
        .dir("--out", Some(out))
        .file("--report", Some(report))
        .check()?;
    let seeds = if args.seed.is_empty() {
        softgrip_lab::prove::SCORED_SEEDS.to_vec()
    } else {
        args.seed.clone()
    };
    let proof = Proof {
        args: &args,
        options,
        models: baseline_models(&args.model),
        seed_count: seeds.len(),
    };
    let mut outcomes = Vec::new();
    for (k, seed) in seeds.into_iter().enumerate() {
        let found = proof.seed(k, seed, &outcomes);
        outcomes.extend(found);
    }
    anyhow::ensure!(
        !outcomes.is_empty(),
        "--only {only:?}: no case of the suite matches"
    );
    let text = softgrip_lab::prove::report(&outcomes, options);
    std::fs::write(report, &text).with_context(|| format!("cannot write {}", report.display()))?;
    print!("{text}");
    Ok(())
}

/// The lab's options of the proof from `--e-measured-within` and `--truth-edge-length` (both
/// checked), this build's commit and its name for the checkpoints.
fn prove_options(args: &Args) -> Result<softgrip_lab::prove::ProveOptions> {
    let options = softgrip_lab::prove::ProveOptions {
        e_measured_within: args.e_measured_within,
        truth_edge_length: args.truth_edge_length,
        commit: Some(env!("SOFTGRIP_COMMIT")),
        // Named once for the whole run.
        checkpoint_build: Some(String::leak(super::diagnose::build_name()?)),
    };
    if let Some(f) = options.e_measured_within {
        anyhow::ensure!(
            f.is_finite() && f > 1.0,
            "--e-measured-within {f}: give a factor above 1 (2: E within half to twice the nominal)"
        );
    }
    if let Some(h) = options.truth_edge_length {
        anyhow::ensure!(
            h.is_finite() && (0.002..=0.01).contains(&h),
            "--truth-edge-length {h}: give an edge length in metres between 0.002 and 0.01 (the suite's is 0.002, the diagnosis's 0.004)"
        );
    }
    Ok(options)
}

/// The baseline models of `--model` in the order first given (unknown names skipped, repeats
/// dropped: each case is diagnosed once from each model); all of them when none is given.
fn baseline_models(names: &[String]) -> Vec<softgrip_lab::diagnose::BaselineModel> {
    use softgrip_lab::diagnose::BaselineModel;
    let mut models: Vec<BaselineModel> = Vec::new();
    for m in names.iter().filter_map(|m| BaselineModel::from_name(m)) {
        if !models.contains(&m) {
            models.push(m);
        }
    }
    if models.is_empty() {
        models = BaselineModel::ALL.to_vec();
    }
    models
}

/// What every seed of the proof shares.
struct Proof<'a> {
    /// The command's arguments.
    args: &'a Args,
    /// The lab's options of the proof.
    options: &'a softgrip_lab::prove::ProveOptions,
    /// The models each case is diagnosed from.
    models: Vec<softgrip_lab::diagnose::BaselineModel>,
    /// How many seeds the proof runs.
    seed_count: usize,
}

impl Proof<'_> {
    /// The outcomes of seed `seed` (the `k`th, from 0), each case's printed as it ends and the
    /// partial report rewritten after it, with the outcomes of the seeds before it
    /// (`before_seeds`).
    fn seed(
        &self,
        k: usize,
        seed: u64,
        before_seeds: &[softgrip_lab::prove::Outcome],
    ) -> Vec<softgrip_lab::prove::Outcome> {
        let (args, options, models) = (self.args, self.options, &self.models);
        let (seed_count, report) = (self.seed_count, &args.report);
        let bar = progress_bar(1, "recordings");
        let before = before_seeds.len();
        // The report so far after each case, marked as such: a run of hours is read as it goes.
        let mut partial = |so_far: &[softgrip_lab::prove::Outcome], cases: usize| {
            let mut all = before_seeds.to_vec();
            all.extend_from_slice(so_far);
            // The last case's outcomes: one per model.
            for o in &so_far[so_far.len().saturating_sub(models.len())..] {
                let verdict = match &o.diagnosis {
                    Ok(d) => d.verdict(),
                    Err(e) => format!("error: {e}"),
                };
                let line = format!(
                    "seed {seed:#x}, {}, {}: {verdict} ({:.0} s)",
                    o.case.name,
                    o.model.name(),
                    o.seconds
                );
                // A hidden bar (no terminal: a log) prints nothing of its own.
                if bar.is_hidden() {
                    eprintln!("{line}");
                } else {
                    bar.println(line);
                }
            }
            let text = format!(
                "> Partial: seed {} of {seed_count}, {} of {cases} cases so far.\n\n{}",
                k + 1,
                (all.len() - before) / models.len().max(1),
                softgrip_lab::prove::report(&all, options)
            );
            // The final write below reports an unwritable path; a partial one need not.
            let _ = std::fs::write(report, text);
        };
        let found = softgrip_lab::prove::run(
            &args.out,
            seed,
            &args.only,
            models,
            &softgrip_lab::diagnose::DiagnoseOptions {
                region_scan: args.region_scan,
                ..Default::default()
            },
            options,
            &show_stages(&bar),
            &mut partial,
        );
        bar.finish_and_clear();
        found
    }
}

#[cfg(test)]
mod tests {
    use super::baseline_models;
    use softgrip_lab::diagnose::BaselineModel;

    /// `--model continuum --model lattice --model continuum` diagnoses each case once from
    /// each model, in the order first given (a repeat apart from its twin ran it twice).
    #[test]
    fn a_model_given_twice_is_diagnosed_once() {
        let names: Vec<String> = ["continuum", "lattice", "continuum"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let models = baseline_models(&names);
        let expected: Vec<BaselineModel> = ["continuum", "lattice"]
            .iter()
            .filter_map(|n| BaselineModel::from_name(n))
            .collect();
        assert_eq!(expected.len(), 2);
        assert_eq!(models, expected);
        assert_eq!(baseline_models(&[]), BaselineModel::ALL.to_vec());
    }
}
