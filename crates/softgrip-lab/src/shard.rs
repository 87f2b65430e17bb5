//! A sweep split into shards that run anywhere (a Slurm job array, Ray tasks, several
//! machines) and merged back into what one run gives: the same points in the same grid order,
//! so the same CSV, JSON and best point, byte for byte. Each point is simulated alone (one
//! thread, `sweep::evaluate`), and a shard's figures go through JSON exactly (shortest
//! round-trip decimal of each f64), so where a point ran does not change it.

use std::path::Path;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::Value;

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
    /// This shard's number, from 0 to `count - 1`.
    pub index: usize,
    /// The number of shards.
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
    let rows: Vec<PartPoint> = indices
        .iter()
        .zip(results)
        .map(|(&i, r)| match r {
            Ok(e) => PartPoint::Ran(RanPoint {
                nrmse: e.nrmse,
                rmse_m: e.rmse_m,
                nrmse_all: e.nrmse_all,
                rmse_all_m: e.rmse_all_m,
                observations: e.count,
                index: i,
                values: points[i].clone(),
            }),
            Err(e) => PartPoint::Failed(FailedPoint {
                error: e.to_string(),
                index: i,
                values: points[i].clone(),
            }),
        })
        .collect();
    Ok(crate::json::to_value(&SweepPartFigures {
        softgrip_sweep_part: PART_VERSION,
        recording: path.display().to_string(),
        params: specs.to_vec(),
        grid: points.len(),
        shard: [shard.index, shard.count],
        points: rows,
    }))
}

/// A shard's file, what `softgrip sweep --shard I/N --part FILE` writes and `softgrip merge`
/// reads (`sweep_part` of Python): the shard's grid points, each simulated alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepPartFigures {
    /// The file's format, [`PART_VERSION`].
    pub softgrip_sweep_part: u64,
    /// The recording's header (.toml), as given.
    pub recording: String,
    /// The axes' specifications (`name=start:end:count`, ...), as given with `--param`.
    pub params: Vec<String>,
    /// Points in the whole grid, every shard's.
    pub grid: usize,
    /// This shard's number (from 0) and the number of shards.
    pub shard: [usize; 2],
    /// This shard's points, in grid order.
    pub points: Vec<PartPoint>,
}

/// One grid point of a shard: its figures, or why its simulation failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum PartPoint {
    /// The point's simulation ran.
    Ran(RanPoint),
    /// It failed.
    Failed(FailedPoint),
}

/// A grid point simulated, with its errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RanPoint {
    /// NRMSE: `rmse_m` over the object's largest extent, dimensionless.
    pub nrmse: f64,
    /// RMS distance, simulated to recorded, over the object markers (the finger markers where
    /// the recording has none), m.
    pub rmse_m: f64,
    /// NRMSE over every marker, fingers included, dimensionless.
    pub nrmse_all: f64,
    /// RMS distance over every marker, fingers included, m.
    pub rmse_all_m: f64,
    /// Marker positions counted in `rmse_m` (markers times samples).
    pub observations: usize,
    /// The point's index in the whole grid (grid order, from 0).
    pub index: usize,
    /// The point's values, one per axis in `params`' order, in each parameter's unit.
    pub values: Vec<f64>,
}

/// A grid point whose simulation failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FailedPoint {
    /// Why it failed, in words.
    pub error: String,
    /// The point's index in the whole grid (grid order, from 0).
    pub index: usize,
    /// The point's values, one per axis in `params`' order, in each parameter's unit.
    pub values: Vec<f64>,
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
    /// The recording's path, as the shards give it.
    pub recording: String,
    /// The axes' specifications (`name=start:end:count`), as the shards give them.
    pub specs: Vec<String>,
    /// The axes, parsed.
    pub axes: Vec<Axis>,
    /// Every grid point, in grid order.
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
    check_versions(parts)?;
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
            check_point(&p, index, &grid_values[index]).map_err(bad)?;
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

/// Every part is a shard's file of this format.
fn check_versions(parts: &[(String, Value)]) -> Result<(), LabError> {
    for (name, part) in parts {
        if part["softgrip_sweep_part"].as_u64() != Some(PART_VERSION) {
            return Err(LabError::input(format!(
                "{name}: not a shard of `softgrip sweep --shard` (format {PART_VERSION}): give the files it wrote with --part"
            )));
        }
    }
    Ok(())
}

/// Point `index` of a shard is what `sweep --shard` writes, and nothing else: its grid point's
/// values (`grid_values`), errors that are errors (a changed file is refused, not merged into a
/// best point).
fn check_point(p: &SweepPoint, index: usize, grid_values: &[f64]) -> Result<(), String> {
    if p.values != grid_values {
        return Err(format!(
            "point {index} has values {:?}, not the grid's {:?}: the file was changed since `sweep --shard` wrote it",
            p.values, grid_values
        ));
    }
    if let Ok(e) = &p.result {
        for (name, v) in [
            ("nrmse", e.nrmse),
            ("rmse_m", e.rmse_m),
            ("nrmse_all", e.nrmse_all),
            ("rmse_all_m", e.rmse_all_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "point {index}: {name} = {v} is not an error (finite, 0 or more): the file was changed since `sweep --shard` wrote it"
                ));
            }
        }
    }
    Ok(())
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
    use serde_json::json;

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
