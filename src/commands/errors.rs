//! The error line a failing command prints.

/// An error and its causes, each cause once: the library's errors already
/// quote their cause (the scene's error in the recording's, the system's
/// in a read error), and printing the chain as well said it twice.
pub fn error_text(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&cause);
        }
    }
    text
}

/// A command's answer told by its exit code as well as its output (codes 3 and up: 1 is an
/// error, 2 a command line clap cannot parse). Printed already; nothing more is said.
#[derive(Debug)]
pub struct Outcome(pub u8);

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "exit code {}", self.0)
    }
}

impl std::error::Error for Outcome {}
