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

pub fn run(args: Args) -> Result<()> {
    let (out, only, report) = (&args.out, &args.only, &args.report);
    let options = &softgrip_lab::prove::ProveOptions {
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
    super::outputs::Outputs::new()
        .dir("--out", Some(out))
        .file("--report", Some(report))
        .check()?;
    let seeds = if args.seed.is_empty() {
        softgrip_lab::prove::SCORED_SEEDS.to_vec()
    } else {
        args.seed.clone()
    };
    use softgrip_lab::diagnose::BaselineModel;
    let mut models: Vec<BaselineModel> = args
        .model
        .iter()
        .filter_map(|m| BaselineModel::from_name(m))
        .collect();
    if models.is_empty() {
        models = BaselineModel::ALL.to_vec();
    }
    models.dedup();
    let mut outcomes = Vec::new();
    let seed_count = seeds.len();
    for (k, seed) in seeds.into_iter().enumerate() {
        let bar = progress_bar(1, "recordings");
        let before = outcomes.len();
        // The report so far after each case, marked as such: a run of hours is read as it goes.
        let mut partial = |so_far: &[softgrip_lab::prove::Outcome], cases: usize| {
            let mut all = outcomes.clone();
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
        outcomes.extend(softgrip_lab::prove::run(
            out,
            seed,
            only,
            &models,
            &softgrip_lab::diagnose::DiagnoseOptions {
                region_scan: args.region_scan,
                ..Default::default()
            },
            options,
            &show_stages(&bar),
            &mut partial,
        ));
        bar.finish_and_clear();
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
