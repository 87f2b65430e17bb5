//! `softgrip merge`: the files of a sweep's shards (`sweep --shard`) combined into the sweep's
//! CSV and JSON, as one run writes them (`softgrip_lab::shard`).

use std::path::PathBuf;

use anyhow::{Context, Result};

use super::figures::write_json;

/// Merge the files of a sweep's shards (`softgrip sweep --shard I/N --part FILE`) into the
/// sweep's CSV and JSON, byte for byte what one run of the whole sweep writes.
#[derive(clap::Args)]
pub struct Args {
    /// Every shard's file.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// Write every point as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the figures as JSON (best point's nrmse, rmse_m, params).
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<()> {
    let mut outputs = super::outputs::Outputs::new()
        .file("--csv", args.csv.as_deref())
        .file("--json", args.json.as_deref());
    for p in &args.parts {
        outputs = outputs.input(p);
    }
    outputs.check()?;
    let parts = args
        .parts
        .iter()
        .map(|p| {
            let bytes = softgrip_core::files::read_at_most(p, 1_000_000_000)
                .with_context(|| format!("cannot read {}", p.display()))?;
            let text = String::from_utf8(bytes).with_context(|| {
                format!("{}: not text (a file `sweep --shard` wrote?)", p.display())
            })?;
            let value: serde_json::Value = serde_json::from_str(&text).with_context(|| {
                format!("{}: not JSON (a file `sweep --shard` wrote?)", p.display())
            })?;
            Ok((p.display().to_string(), value))
        })
        .collect::<Result<Vec<_>>>()?;
    let merged = softgrip_lab::shard::merge(&parts)?;
    let path = std::path::Path::new(&merged.recording);
    let points = &merged.points;
    let failed = points.iter().filter(|p| p.result.is_err()).count();
    println!(
        "{}: {} points from {} shards ({failed} did not run)",
        merged.recording,
        points.len(),
        parts.len()
    );
    let value = softgrip_lab::json::sweep(path, &merged.axes, points)
        .ok_or_else(|| anyhow::anyhow!("no point of the sweep ran"))?;
    let at: Vec<String> = value["params"]
        .as_object()
        .into_iter()
        .flatten()
        .map(|(k, v)| match v.as_f64() {
            Some(x) => format!("{k} = {}", super::args::number(x)),
            None => format!("{k} = {v}"),
        })
        .collect();
    println!(
        "best: {}: NRMSE {}",
        at.join(", "),
        value["nrmse"]
            .as_f64()
            .map_or_else(|| value["nrmse"].to_string(), |x| format!("{x:.5}"))
    );
    if let Some(csv) = &args.csv {
        std::fs::write(csv, softgrip_lab::sweep::to_csv(&merged.axes, points))
            .with_context(|| format!("writing {}", csv.display()))?;
        println!("wrote {}", csv.display());
    }
    if let Some(json) = &args.json {
        write_json(json, &value)?;
    }
    Ok(())
}
