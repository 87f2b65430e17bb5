//! The scene's errors: what is wrong, where, and what to do.

use std::path::PathBuf;

/// A scene error: what is wrong, where, and what to do.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file {path}: {source}. Check the path and its permissions.")]
    Read {
        /// The scene file.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// The text is not UTF-8 or not valid TOML, or a key or a type is not the format's.
    #[error("{file}: {message}")]
    Syntax {
        /// The scene file.
        file: String,
        /// Where and what, with a hint ([`describe_toml_error`]).
        message: String,
    },
    /// A key's value is outside its allowed range or set.
    #[error("{file}{line}: {table}{key} = {value} is not allowed: {rule}")]
    Value {
        /// The scene file.
        file: String,
        /// `:N`, the key's line, or empty where it is not written (a default).
        line: String,
        /// The table with a trailing space: `[model] `, or `[[finger]] #2 ` (1-based).
        table: String,
        /// The key.
        key: String,
        /// The value, as resolved.
        value: String,
        /// What is allowed.
        rule: String,
    },
    /// Anything else wrong: a missing table or key, a key out of place, a file that is no
    /// scene.
    #[error("{file}: {message}")]
    Invalid {
        /// The scene file.
        file: String,
        /// What is wrong and what to do.
        message: String,
    },
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
