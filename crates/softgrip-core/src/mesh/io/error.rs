//! The error of a mesh file that could not be read.

/// A mesh file that could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}: {message}", file, line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ImportError {
    /// The file's name as given.
    pub file: String,
    /// The line the problem is on, counting from 1 (`None`: the whole file, or binary data).
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl ImportError {
    /// The error `message` in `file` at `line`.
    pub fn at(file: &str, line: Option<usize>, message: impl Into<String>) -> ImportError {
        ImportError {
            file: file.to_string(),
            line,
            message: message.into(),
        }
    }
}
