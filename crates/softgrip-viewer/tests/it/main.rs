//! The integration tests, one binary: one module per subject.

mod picking;
mod screenshots;
mod support;
mod viewer_diagnosis;
mod viewer_grasp;
mod viewer_recording;
mod viewer_ui;
