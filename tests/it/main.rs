//! The integration tests, one binary: one module per subject.

mod cli;
mod output_files;
mod screenshot_command;
mod support;
