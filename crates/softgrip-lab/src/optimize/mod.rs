//! General-purpose optimisers on the unit box, for costs that are
//! expensive, batched (points evaluated together, e.g. one simulation per
//! core) and may fail (a failed point counts as infinitely bad).
//!
//! - [`halton`]: a space-filling design to start from.
//! - [`nelder_mead`], [`minimize`]: derivative-free, restarted until a
//!   restart gains nothing.
//! - [`levenberg_marquardt`]: for least-squares costs with residual vectors.
//! - [`BoundedScale`]: a bounded coordinate mapped to 0..1, linear or log.
//!
//! Nothing here knows about recordings or scenes; `fit` and `diagnose` use
//! it. Why these methods: `docs/design/fitting.md`.

mod design;
mod levenberg_marquardt;
mod linalg;
mod nelder_mead;
mod scale;
mod types;

pub use design::halton;
pub use levenberg_marquardt::{
    JacobianAt, ResidualBatch, levenberg_marquardt, levenberg_marquardt_with,
};
pub use linalg::{invert, symmetric_eigenvalues};
pub use nelder_mead::{minimize, nelder_mead};
pub use scale::{BoundedScale, at_bound};
pub use types::{Minimum, Tolerances};
