//! softgrip-viewer: the desktop viewer and the 3-D renderer.
//!
//! - [`render`]: CPU-built lit triangles drawn by wgpu into an offscreen texture, an orbit
//!   camera and mouse picking; headless on a software adapter for `softgrip screenshot`.
//! - [`viewer`]: the eframe application: panels that drive a `softgrip_core::live`
//!   simulation, the 3-D view, and lab jobs (replay, fit, diagnosis) on their own threads.

#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod render;
pub mod viewer;
