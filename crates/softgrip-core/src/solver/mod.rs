//! Linear algebra of the implicit step: the block-sparse system matrix of
//! thesis eq. 43 and the preconditioned conjugate gradient that solves it.

pub mod cg;
pub mod direct;
pub mod gmres;
pub mod pressure;
pub mod system;

pub use cg::{CgError, CgParams, CgReport, LinearOperator, conjugate_gradient};
pub use system::System;
