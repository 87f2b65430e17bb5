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
