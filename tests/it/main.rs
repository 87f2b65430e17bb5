//! The integration tests, one binary: one module per subject.

mod cli;
mod hostile;
mod json_schema;
mod output_files;
mod screenshot_command;
mod support;
