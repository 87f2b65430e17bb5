//! The scene's errors: what is wrong, where, and what to do.

use std::path::PathBuf;

/// A scene error: what is wrong, where, and what to do.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read scene file {path}: {source}. Check the path and its permissions.")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{file}: {message}")]
    Syntax { file: String, message: String },
    #[error("{file}{line}: {table}{key} = {value} is not allowed: {rule}")]
    Value {
        file: String,
        line: String,
        table: String,
        key: String,
        value: String,
        rule: String,
    },
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
}

/// Turns a TOML/serde error into one line with the line number and a hint.
pub fn describe_toml_error(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim().to_string();
    let location = e
        .span()
        .map(|span| {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            let source = text.lines().nth(line - 1).unwrap_or("").trim();
            // A line is quoted to show where, not echoed whole (a one-line 50 MB file).
            let source: String = match source.char_indices().nth(120) {
                Some((cut, _)) => format!("{}...", &source[..cut]),
                None => source.to_string(),
            };
            format!("line {line} `{source}`: ")
        })
        .unwrap_or_default();
    let hint = if msg.contains("unknown field") {
        " (a typo? Unknown keys are errors; put free-form data under [extra])"
    } else if msg.contains("invalid type") {
        " (check the value's type: numbers, strings in quotes, vectors as [x, y, z])"
    } else {
        ""
    };
    format!("{location}{msg}{hint}")
}
