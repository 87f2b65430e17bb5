//! A sweep split into shards that run anywhere (a Slurm job array, Ray tasks, several
//! machines) and merged back into what one run gives: the same points in the same grid order,
//! so the same CSV, JSON and best point, byte for byte. Each point is simulated alone (one
//! thread, `sweep::evaluate`), and a shard's figures go through JSON exactly (shortest
//! round-trip decimal of each f64), so where a point ran does not change it.

use std::path::Path;

use serde_json::{Value, json};

use crate::compare::Errors;
use crate::error::LabError;
use crate::params::{Axis, parse_axis};
use crate::recording::Recording;
use crate::sweep::{SweepPoint, evaluate, grid, parallel_map};

/// The format of a shard's file (`"softgrip_sweep_part"`): raised when it changes.
pub const PART_VERSION: u64 = 1;

/// One shard of `count`: the grid points whose index is `index` modulo `count` (round robin,
/// so a costly corner of the grid is spread over the shards).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// Parses `I/N` (I from 0 to N - 1: Slurm's `$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`
    /// with `--array=0-(N-1)`).
    pub fn parse(text: &str) -> Result<Shard, LabError> {
        let bad = || {
            LabError::input(format!(
                "--shard {text:?}: write I/N with 0 <= I < N, e.g. 0/4 for the first of four (Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT with --array=0-3)"
            ))
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The grid indices of this shard, of `total`.
    pub fn indices(self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }
}

/// Runs `shard` of the sweep of `recording` (read from `path`) over the axes `specs` (the
/// `--param` texts) on `workers` threads and returns the shard's file as JSON.
pub fn run_part(
    path: &Path,
    recording: &Recording,
    specs: &[String],
    shard: Shard,
    workers: usize,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Value, LabError> {
    let axes = parse_axes(specs)?;
    let points = grid(&axes);
    let names: Vec<&str> = axes.iter().map(|a| a.param.name).collect();
    let indices = shard.indices(points.len());
    let results = parallel_map(
        &indices,
        workers,
        |&i| evaluate(recording, &names, &points[i]),
        progress,
    );
    let rows: Vec<Value> = indices
        .iter()
        .zip(results)
        .map(|(&i, r)| {
            let mut row = match r {
                Ok(e) => crate::json::errors(&e),
                Err(e) => json!({ "error": e.to_string() }),
            };
            row["index"] = i.into();
            row["values"] = points[i].clone().into();
            row
        })
        .collect();
    Ok(json!({
        "softgrip_sweep_part": PART_VERSION,
        "recording": path.display().to_string(),
        "params": specs,
        "grid": points.len(),
        "shard": [shard.index, shard.count],
        "points": rows,
    }))
}

/// The axes of `--param` texts.
pub fn parse_axes(specs: &[String]) -> Result<Vec<Axis>, LabError> {
    if specs.is_empty() || specs.len() > 2 {
        return Err(LabError::input(format!(
            "{} --param given: a sweep is a curve (one) or a grid (two)",
            specs.len()
        )));
    }
    specs.iter().map(|s| parse_axis(s)).collect()
}

/// A merged sweep: the recording's path and axes as the shards give them, and every point in
/// grid order.
#[derive(Debug, Clone)]
pub struct Merged {
    pub recording: String,
    pub specs: Vec<String>,
    pub axes: Vec<Axis>,
    pub points: Vec<SweepPoint>,
}

/// Merges shards' files (`names` say which file each is, for the errors): one sweep (the same
/// recording and axes), each grid point exactly once.
pub fn merge(parts: &[(String, Value)]) -> Result<Merged, LabError> {
    let Some((_, first)) = parts.first() else {
        return Err(LabError::input(
            "no shard to merge: give the files `sweep --shard` wrote",
        ));
    };
    for (name, part) in parts {
        if part["softgrip_sweep_part"].as_u64() != Some(PART_VERSION) {
            return Err(LabError::input(format!(
                "{name}: not a shard of `softgrip sweep --shard` (format {PART_VERSION}): give the files it wrote with --part"
            )));
        }
    }
    let recording = first["recording"].as_str().unwrap_or_default().to_string();
    let specs: Vec<String> = first["params"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|v| v.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    let axes = parse_axes(&specs)?;
    let grid_values = grid(&axes);
    let total = grid_values.len();
    let mut slots: Vec<Option<SweepPoint>> = vec![None; total];
    for (name, part) in parts {
        let bad = |why: String| LabError::input(format!("{name}: {why}"));
        if part["recording"].as_str() != Some(&recording) || part["params"] != first["params"] {
            return Err(bad(format!(
                "another sweep than {}'s ({recording}, {}): merge the shards of one sweep",
                parts[0].0,
                specs.join(" ")
            )));
        }
        for row in part["points"].as_array().into_iter().flatten() {
            let index = row["index"]
                .as_u64()
                .map(|i| i as usize)
                .filter(|&i| i < total)
                .ok_or_else(|| bad(format!("a point's index is not one of the {total}")))?;
            if slots[index].is_some() {
                return Err(bad(format!(
                    "point {index} is in two shards: merge each shard once"
                )));
            }
            let p = point(row).ok_or_else(|| bad(format!("point {index} is malformed")))?;
            // What `sweep --shard` writes, and nothing else: its grid point's values, errors
            // that are errors (a changed file is refused, not merged into a best point).
            if p.values != grid_values[index] {
                return Err(bad(format!(
                    "point {index} has values {:?}, not the grid's {:?}: the file was changed since `sweep --shard` wrote it",
                    p.values, grid_values[index]
                )));
            }
            if let Ok(e) = &p.result {
                for (name, v) in [
                    ("nrmse", e.nrmse),
                    ("rmse_m", e.rmse_m),
                    ("nrmse_all", e.nrmse_all),
                    ("rmse_all_m", e.rmse_all_m),
                ] {
                    if !(v.is_finite() && v >= 0.0) {
                        return Err(bad(format!(
                            "point {index}: {name} = {v} is not an error (finite, 0 or more): the file was changed since `sweep --shard` wrote it"
                        )));
                    }
                }
            }
            slots[index] = Some(p);
        }
    }
    let missing: Vec<usize> = (0..total).filter(|&i| slots[i].is_none()).collect();
    if let Some(&first_missing) = missing.first() {
        return Err(LabError::input(format!(
            "{} of the {total} points are in no shard given (the first: {first_missing}): give every shard's file",
            missing.len()
        )));
    }
    Ok(Merged {
        recording,
        specs,
        axes,
        points: slots.into_iter().flatten().collect(),
    })
}

/// A point of a shard's file.
fn point(row: &Value) -> Option<SweepPoint> {
    let values: Vec<f64> = row["values"]
        .as_array()?
        .iter()
        .map(Value::as_f64)
        .collect::<Option<_>>()?;
    let result = match row["error"].as_str() {
        Some(message) => Err(LabError::Input(message.to_string())),
        None => Ok(Errors {
            nrmse: row["nrmse"].as_f64()?,
            rmse_m: row["rmse_m"].as_f64()?,
            nrmse_all: row["nrmse_all"].as_f64()?,
            rmse_all_m: row["rmse_all_m"].as_f64()?,
            count: row["observations"].as_u64()? as usize,
        }),
    };
    Some(SweepPoint { values, result })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shards_cover_the_grid_once_round_robin() {
        let shards: Vec<Vec<usize>> = (0..3)
            .map(|i| Shard { index: i, count: 3 }.indices(7))
            .collect();
        assert_eq!(shards, vec![vec![0, 3, 6], vec![1, 4], vec![2, 5]]);
        assert_eq!(Shard::parse("2/4").ok(), Some(Shard { index: 2, count: 4 }));
        for bad in ["4/4", "1", "a/2", "0/0", "-1/3"] {
            let e = Shard::parse(bad).expect_err(bad).to_string();
            assert!(e.contains("--shard") && e.contains("I/N"), "{bad}: {e}");
        }
    }

    /// A file that is no shard, and a grid point in no shard, are named, not merged.
    #[test]
    fn a_merge_names_what_is_wrong() {
        let e = merge(&[("x.json".into(), json!({}))]).expect_err("no shard");
        assert!(e.to_string().starts_with("x.json: not a shard"), "{e}");
        let part = |i: usize| {
            json!({"softgrip_sweep_part": PART_VERSION, "recording": "r.toml",
                   "params": ["young_modulus=1e4:2e4:3"], "grid": 3,
                   "points": [{"index": i, "values": [1e4 + 5e3 * i as f64], "error": "failed"}]})
        };
        let e = merge(&[("a".into(), part(0)), ("b".into(), part(2))]).expect_err("gap");
        assert!(
            e.to_string().contains("1 of the 3 points are in no shard"),
            "{e}"
        );
        let e = merge(&[("a".into(), part(0)), ("b".into(), part(0))]).expect_err("twice");
        assert!(e.to_string().contains("point 0 is in two shards"), "{e}");
    }

    /// A shard edited after `sweep --shard` wrote it (a negative NRMSE, a value off its grid
    /// point) is refused, not merged into a best point.
    #[test]
    fn a_changed_shard_is_refused() {
        let part = |values: f64, nrmse: f64| {
            json!({"softgrip_sweep_part": PART_VERSION, "recording": "r.toml",
                   "params": ["young_modulus=1e4:2e4:2"], "grid": 2,
                   "points": [{"index": 0, "values": [1e4], "nrmse": 0.1, "rmse_m": 1e-4,
                               "nrmse_all": 0.1, "rmse_all_m": 1e-4, "observations": 10},
                              {"index": 1, "values": [values], "nrmse": nrmse, "rmse_m": 1e-4,
                               "nrmse_all": 0.1, "rmse_all_m": 1e-4, "observations": 10}]})
        };
        assert!(merge(&[("a".into(), part(2e4, 0.05))]).is_ok());
        let e = merge(&[("a".into(), part(2e4, -0.5))]).expect_err("negative NRMSE");
        assert!(
            e.to_string().contains("nrmse = -0.5 is not an error"),
            "{e}"
        );
        let e = merge(&[("a".into(), part(1.5e4, 0.05))]).expect_err("off the grid");
        assert!(e.to_string().contains("not the grid's [20000.0]"), "{e}");
    }

    /// A point's figures survive the file exactly, an error by its message.
    #[test]
    fn a_point_goes_through_the_file_exactly() {
        let e = Errors {
            nrmse: 0.1 + 0.2,
            // Needs serde_json's exact parser (`float_roundtrip`): the default is 1 ulp off.
            rmse_m: 0.000_242_592_771_396_103_62,
            nrmse_all: std::f64::consts::PI * 1e-3,
            rmse_all_m: 2.0f64.sqrt() * 1e-4,
            count: 64,
        };
        let mut row = crate::json::errors(&e);
        row["values"] = vec![60e3 * 1.1, 0.155].into();
        let text = serde_json::to_string(&row).expect("json");
        let back = point(&serde_json::from_str(&text).expect("parse")).expect("point");
        assert_eq!(back.result, Ok(e));
        assert_eq!(back.values, vec![60e3 * 1.1, 0.155]);
        let failed =
            point(&json!({"values": [1.0], "error": "no equilibrium at 3 N"})).expect("point");
        assert_eq!(
            failed.result.map_err(|e| e.to_string()),
            Err("no equilibrium at 3 N".to_string())
        );
    }
}
