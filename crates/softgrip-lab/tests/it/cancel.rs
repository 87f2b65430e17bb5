//! Stopping long work: a replay, a fit and a diagnosis run under a cancel
//! token (`softgrip_core::cancel`) end with "cancelled" once it is set, not
//! with a result made of failed simulations; a token never set changes
//! nothing, bit for bit.

use std::sync::atomic::{AtomicUsize, Ordering};

use softgrip_core::SimError;
use softgrip_core::cancel::{self, Cancel};
use softgrip_lab::LabError;
use softgrip_lab::diagnose::{self, DiagnoseOptions};
use softgrip_lab::fit::{self, FitError, FitOptions, parse_params};
use softgrip_lab::replay::{ReplayOptions, replay};

use crate::support::thesis_7_loads;

#[test]
#[ignore = "slow: whole replays and fits"]
fn a_replay_stops_at_its_first_step_once_cancelled_and_is_unchanged_by_a_token_never_set() {
    let rec = thesis_7_loads();
    let outside = replay(&rec, &rec.scene, ReplayOptions::default(), |_| {}).expect("replays");
    let token = Cancel::new();
    let inside = cancel::scope(Some(token.clone()), || {
        replay(&rec, &rec.scene, ReplayOptions::default(), |_| {})
    })
    .expect("replays");
    assert_eq!(outside.residuals.len(), inside.residuals.len());
    for (a, b) in outside.residuals.iter().zip(&inside.residuals) {
        assert_eq!(
            a.simulated, b.simulated,
            "a token never set changes nothing"
        );
    }
    // Cancelled after the second sample: the third does not start.
    let samples = AtomicUsize::new(0);
    let token = Cancel::new();
    let r = cancel::scope(Some(token.clone()), || {
        replay(&rec, &rec.scene, ReplayOptions::default(), |done| {
            samples.store(done, Ordering::Relaxed);
            if done == 2 {
                token.cancel();
            }
        })
    });
    assert!(matches!(r, Err(SimError::Cancelled)), "{r:?}");
    assert_eq!(samples.load(Ordering::Relaxed), 2);
    assert!(
        rec.samples.len() > 2,
        "the recording has more samples to skip"
    );
    // Outside the scope the token is not this thread's any more.
    assert!(!cancel::requested());
    assert!(replay(&rec, &rec.scene, ReplayOptions::default(), |_| {}).is_ok());
}

#[test]
#[ignore = "slow: whole replays and fits"]
fn a_fit_cancelled_midway_says_so_instead_of_returning_a_fit() {
    let rec = thesis_7_loads();
    let params = parse_params(&["young_modulus".to_string()], &rec.scene).expect("params");
    let token = Cancel::new();
    let calls = AtomicUsize::new(0);
    let r = cancel::scope(Some(token.clone()), || {
        fit::fit(&rec, &params, FitOptions::default(), &|done, _| {
            calls.fetch_add(1, Ordering::Relaxed);
            // After the first simulation of the design, while the other
            // worker may be in the middle of its own.
            if done >= 1 {
                token.cancel();
            }
        })
    });
    assert_eq!(r.err(), Some(FitError::Cancelled));
    assert!(calls.load(Ordering::Relaxed) >= 1);
}

#[test]
fn a_diagnosis_cancelled_says_so_instead_of_a_verdict() {
    let rec = thesis_7_loads();
    let token = Cancel::new();
    let stages = std::sync::Mutex::new(Vec::<String>::new());
    let r = cancel::scope(Some(token.clone()), || {
        diagnose::diagnose(&rec, &DiagnoseOptions::default(), &|_, _, what| {
            if let Ok(mut s) = stages.lock() {
                s.push(what.to_string());
            }
            token.cancel();
        })
    });
    assert_eq!(r.err(), Some(LabError::Cancelled));
    // It stopped in its first fit: it never reached the weighted one.
    assert_eq!(*stages.lock().unwrap(), vec!["baseline".to_string()]);
}
