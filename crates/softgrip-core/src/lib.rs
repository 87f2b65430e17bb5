//! softgrip-core: the simulation, with no GUI and no lab data.
//!
//! The model of the thesis "Deformation modelling and gripper contact simulation of deformable
//! objects" (chapter 3; summarised in `docs/model.md`): a tetrahedral mesh becomes a
//! mass-spring-damper system with volume preservation and spring limits; spherical and plate
//! fingers touch its boundary facets through Hunt-Crossley and stick-slip contact; implicit
//! Euler and conjugate gradient integrate it.
//!
//! Layers, lowest first (each module imports only those before it; `ARCHITECTURE.md`):
//! [`geometry`] -> [`mesh`] -> [`scene`] -> [`model`] -> [`state`] -> [`watch`], [`solver`]
//! -> [`forces`], [`contact`] -> [`step`] -> [`quasi_static`], [`equilibrium`], [`live`],
//! [`output`], [`fields`], [`mod@bench`] -> [`sensitivity`]. The step's force stages are listed,
//! in order, in [`step::assemble`].
//! [`error`], [`cancel`] and [`files`] are shared by all.

#![warn(missing_docs)]
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod bench;
pub mod cancel;
pub mod contact;
pub mod equilibrium;
pub mod error;
pub mod fields;
pub mod files;
pub mod forces;
pub mod geometry;
pub mod live;
pub mod mesh;
pub mod model;
pub mod output;
pub mod quasi_static;
pub mod scene;
pub mod sensitivity;
pub mod solver;
pub mod state;
pub mod step;
pub mod watch;

pub use error::SimError;
pub use model::Model;
pub use scene::Scene;
pub use state::State;
pub use step::Simulation;
