//! Parameter sweeps over a recording (thesis Fig. 19-23): every point of a
//! 1-D or 2-D grid of scene parameters simulated against the recording,
//! in parallel (one simulation per core, each on one thread: the results
//! do not depend on how many run at once), with the NRMSE of each.

use std::fmt::Write as _;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::compare::Errors;
use crate::error::LabError;
use crate::params::{self, Axis};
use crate::recording::Recording;
use crate::replay::{ReplayOptions, replay};

/// One grid point and how it compared (or why it could not run).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPoint {
    /// One value per axis, in the axes' order.
    pub values: Vec<f64>,
    /// The point's errors, or why it could not run.
    pub result: Result<Errors, LabError>,
}

/// The grid points, the last axis varying fastest.
pub fn grid(axes: &[Axis]) -> Vec<Vec<f64>> {
    let mut points = vec![Vec::new()];
    for axis in axes {
        points = points
            .into_iter()
            .flat_map(|p| {
                axis.values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(*v);
                    q
                })
            })
            .collect();
    }
    points
}

/// Runs the sweep on `workers` threads (0: one per core); `progress` gets
/// the number of points done.
pub fn sweep(
    recording: &Recording,
    axes: &[Axis],
    workers: usize,
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<SweepPoint> {
    let points = grid(axes);
    let names: Vec<&str> = axes.iter().map(|a| a.param.name).collect();
    let results = parallel_map(
        &points,
        workers,
        |values| evaluate(recording, &names, values),
        progress,
    );
    points
        .into_iter()
        .zip(results)
        .map(|(values, result)| SweepPoint { values, result })
        .collect()
}

/// The recording simulated with the parameters `names` set to `values`
/// (one thread: callers run several at once).
pub fn evaluate(recording: &Recording, names: &[&str], values: &[f64]) -> Result<Errors, LabError> {
    let mut scene = recording.scene.clone();
    for (name, v) in names.iter().zip(values) {
        scene = params::set(&scene, name, *v)?;
    }
    let options = ReplayOptions {
        // One per core while the sweep has points left, both for the last
        // (`Simulation::set_threads`).
        threads: 0,
        ..ReplayOptions::default()
    };
    replay(recording, &scene, options, |_| {})
        .map(|r| r.errors)
        .map_err(LabError::from)
}

/// `f` of each item on `workers` threads (0: one per core), results in
/// the items' order whatever the number of threads; `progress` gets the
/// number done.
pub fn parallel_map<T: Sync, R: Send>(
    items: &[T],
    workers: usize,
    f: impl Fn(&T) -> R + Sync,
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<R> {
    let workers = if workers == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        workers
    }
    .clamp(1, items.len().max(1));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    // The workers run under the caller's cancel token: once it is set,
    // each item left ends at its simulation's first step with
    // `SimError::Cancelled` (the results stay one per item).
    let cancel = softgrip_core::cancel::current();
    std::thread::scope(|s| {
        for _ in 0..workers {
            let cancel = cancel.clone();
            s.spawn(|| {
                softgrip_core::cancel::scope(cancel, || {
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else {
                            break;
                        };
                        let r = f(item);
                        if let Ok(mut all) = results.lock() {
                            all[i] = Some(r);
                        }
                        progress(done.fetch_add(1, Ordering::Relaxed) + 1);
                    }
                })
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .flatten()
        .collect()
}

/// The point with the smallest NRMSE.
pub fn best(points: &[SweepPoint]) -> Option<&SweepPoint> {
    points
        .iter()
        .filter(|p| p.result.as_ref().is_ok_and(|e| e.nrmse.is_finite()))
        .min_by(|a, b| {
            let (x, y) = (a.result.as_ref(), b.result.as_ref());
            let (x, y) = (
                x.map_or(f64::INFINITY, |e| e.nrmse),
                y.map_or(f64::INFINITY, |e| e.nrmse),
            );
            x.total_cmp(&y)
        })
}

/// The sweep as CSV: one column per parameter, then nrmse, rmse_m,
/// nrmse_all, rmse_all_m and error (empty when the point ran).
pub fn to_csv(axes: &[Axis], points: &[SweepPoint]) -> String {
    let mut s = String::new();
    for a in axes {
        let _ = write!(s, "{},", a.param.name);
    }
    s.push_str("nrmse,rmse_m,nrmse_all,rmse_all_m,error\n");
    for p in points {
        for v in &p.values {
            let _ = write!(s, "{v:?},");
        }
        match &p.result {
            Ok(e) => {
                let _ = writeln!(
                    s,
                    "{:?},{:?},{:?},{:?},",
                    e.nrmse, e.rmse_m, e.nrmse_all, e.rmse_all_m
                );
            }
            Err(m) => {
                let _ = writeln!(s, ",,,,\"{}\"", m.to_string().replace('"', "'"));
            }
        }
    }
    s
}
