//! Reports of `softgrip compare`, `modulus`, `fit`, `sweep` and `diagnose`: a
//! Markdown file with its figures as PNG plots beside it, in a directory of
//! their own. One file per report kind; the tables and figures they share are
//! in `tables` and `figures`.
//!
//! The plots show what a reader would otherwise dig out of tables: each marker's
//! path recorded against simulated (`paths.png`), the most-moving coordinate
//! against load or time (`motion.png`), the residual per sample
//! (`residuals.png`); fits add the search's convergence and the residuals before
//! and after, sweeps the NRMSE curve or heat map. More: `docs/design/reports.md`.

mod compare;
mod diagnosis;
mod figures;
mod fit;
mod grasp_window;
mod modulus;
mod out;
mod sweep;
mod tables;

pub use compare::compare;
pub use diagnosis::diagnosis;
pub use fit::{fit, fit_many, recording_name};
pub use grasp_window::{grasp_window, shown, window_chart};
pub use modulus::modulus;
pub use out::{ReportError, Written};
pub use sweep::sweep;
