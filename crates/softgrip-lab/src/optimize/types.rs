//! What the optimisers are told and what they return.

/// When a search has converged or stalled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Converged when the simplex (or the step) is this small in every
    /// unit coordinate...
    pub x_tolerance: f64,
    /// ... and the values differ by less than this fraction of the best;
    /// also, a search stops when the best has not improved by this
    /// fraction in `stall` evaluations per dimension plus one.
    pub f_tolerance: f64,
    /// Evaluations without progress before Nelder-Mead stops, per
    /// dimension plus one.
    pub stall: usize,
}

/// What one search found.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The best point found, in the unit box (length: dimensions).
    pub x: Vec<f64>,
    /// The cost there.
    pub f: f64,
    /// New evaluations spent (the start's not counted).
    pub evaluations: usize,
    /// Stopped by its own stopping rule (see each optimiser), not by the budget.
    pub converged: bool,
    /// Stopped because the best did not improve for a while.
    pub stalled: bool,
}
