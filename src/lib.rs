//! softgrip: soft-object grasp simulation.
//!
//! The model of the thesis (`shared/thesis.md`, chapter 3): a tetrahedral mesh
//! becomes a mass-spring-damper system with volume preservation and spring
//! limits; spherical and plate fingers touch its boundary facets through
//! Hunt-Crossley and stick-slip contact; implicit Euler and conjugate gradient
//! integrate it.
//!
//! Module map (one file per stage, see ARCHITECTURE.md):
//! - [`scene`]: scene files (the user contract), defaults and validation.
//! - [`mesh`]: tetrahedral meshes and the built-in cuboid and cylinder.
//! - [`model`]: the constant model built from a scene (masses, springs, facets, fingers).
//! - [`state`]: the mutable state and the per-step diagnostics.
//! - [`forces`]: springs and dampers, gravity and loads, volume preservation.
//! - [`contact`]: broad phase, sphere/plate narrow phase, Hunt-Crossley, stick-slip.
//! - [`solver`]: the block-sparse system and preconditioned CG.
//! - [`integrate`]: implicit Euler; [`constraints`]: spring limits.
//! - [`step`]: one time step and [`step::Simulation`]; [`quasi_static`]: loads to rest.
//! - [`output`]: ParaView and CSV output; [`mod@bench`]: the `softgrip bench` runs.
//! - [`parallel`]: the helper thread that takes half of each step's work.
//! - [`recording`], [`compare`], [`replay`], [`modulus`]: lab recordings,
//!   markers and NRMSE, a recording simulated, E from a compression test.
//! - [`params`], [`sweep`], [`fit`], [`synth`]: parameters by name, grids,
//!   fitting with its evidence, recordings made by softgrip itself.
//! - [`plot`], [`report`]: PNG plots and the Markdown reports around them.
//! - [`cancel`]: stopping a fit, sweep or diagnosis from another thread.
//! - [`live`]: a simulation on its own thread, driven by commands, publishing frames (the viewer's core).
//! - `render`, `viewer` (feature `gui`): the 3-D renderer (also headless, for
//!   `softgrip screenshot`) and the desktop viewer.
//!
//! The core has no GUI dependency: `cargo test --no-default-features`.

#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod bench;
pub mod cancel;
pub mod compare;
pub mod constraints;
pub mod contact;
pub mod diagnose;
pub mod discretisation;
pub mod error;
pub mod fields;
pub mod fit;
pub mod forces;
pub mod grasp;
pub mod integrate;
pub mod live;
pub mod mesh;
pub mod model;
pub mod modulus;
pub mod output;
pub mod parallel;
pub mod params;
pub mod plot;
pub mod prove;
pub mod quasi_static;
pub mod recording;
#[cfg(feature = "gui")]
pub mod render;
pub mod replay;
pub mod report;
pub mod scene;
pub mod solver;
pub mod state;
pub mod step;
pub mod sweep;
pub mod synth;
#[cfg(feature = "gui")]
pub mod viewer;

pub use error::SimError;
pub use model::Model;
pub use scene::Scene;
pub use state::State;
pub use step::Simulation;
