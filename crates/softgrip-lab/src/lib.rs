//! softgrip-lab: a simulation against lab data.
//!
//! Recordings (the format is `docs/formats.md`), replaying them, the thesis's NRMSE, sweeps and
//! fits of parameters by name, recordings made by softgrip itself, and the missing-physics
//! diagnosis with its proof. Built on `softgrip-core`; no GUI.
//!
//! - [`recording`], [`replay`], [`compare`], [`modulus`]: lab recordings, a recording
//!   simulated, markers and NRMSE, E from a compression test.
//! - [`params`], [`sweep`], [`fit`], [`synth`]: parameters by name, grids, fitting with its
//!   evidence, recordings made by softgrip itself; [`optimize`]: the optimisers fits use.
//! - [`diagnose`], [`discretisation`], [`prove`]: what physics the model left out, how much of
//!   a mismatch the mesh and step make, the diagnosis scored on hidden effects.
//! - [`ringing`]: the frequency and decay of a time series' dominant damped oscillation.
//! - [`grasp`]: squeeze, lift and hold, and the least friction that holds.
//! - [`sensitivity`]: `dx/dp` of a static equilibrium for named parameters.
//! - [`plot`], [`report`]: PNG plots and the Markdown reports around them.
//! - [`LabError`]: why a sweep, fit, diagnosis or proof could not run.

#![warn(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod compare;
pub mod diagnose;
pub mod discretisation;
pub mod error;
pub mod fit;
pub mod grasp;
pub mod json;
pub mod modulus;
pub mod optimize;
pub mod params;
pub mod plot;
pub mod prove;
pub mod recording;
pub mod replay;
pub mod report;
pub mod ringing;
pub mod schema;
pub mod sensitivity;
pub mod shard;
pub mod sweep;
pub mod synth;

pub use error::LabError;
