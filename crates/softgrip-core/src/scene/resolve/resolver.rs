//! The resolver and its value checks, shared by every table: a default applied and recorded, a
//! number in its range, an error that names the table, the key and its line.

use glam::DVec3;

use crate::scene::error::SceneError;

/// Resolves one scene text's tables, collecting the defaults it applies.
pub(super) struct Resolver<'a> {
    text: &'a str,
    file: &'a str,
    /// `table.key = value` of every default applied so far.
    pub(super) applied: Vec<String>,
}

/// One key of a table: where to report it.
#[derive(Clone, Copy)]
pub(super) struct At<'k> {
    pub(super) table: &'k str,
    pub(super) index: Option<usize>,
    pub(super) key: &'k str,
}

impl<'a> Resolver<'a> {
    pub(super) fn new(text: &'a str, file: &'a str) -> Self {
        Resolver {
            text,
            file,
            applied: Vec::new(),
        }
    }

    /// An error that is not one key's value: a missing table or key, a key out of place.
    pub(super) fn invalid(&self, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            file: self.file.to_string(),
            message: message.into(),
        }
    }

    /// The line on which `key` is written inside `[table]` (or the index-th
    /// `[[table]]`), for error messages; empty when not found (a default).
    fn line_of(&self, at: At<'_>) -> String {
        let mut current = String::new();
        let mut count: i64 = -1;
        for (n, line) in self.text.lines().enumerate() {
            let t = line.trim();
            if let Some(rest) = t.strip_prefix("[[") {
                current = rest.trim_end_matches("]]").trim().to_string();
                if current == at.table {
                    count += 1;
                }
                continue;
            }
            if let Some(rest) = t.strip_prefix('[') {
                current = rest.split(']').next().unwrap_or("").trim().to_string();
                continue;
            }
            let in_table = current == at.table && at.index.is_none_or(|i| count == i as i64);
            if in_table
                && let Some((k, _)) = t.split_once('=')
                && k.trim() == at.key
            {
                return format!(":{}", n + 1);
            }
        }
        String::new()
    }

    fn table_name(at: At<'_>) -> String {
        match at.index {
            Some(i) => format!("[[{}]] #{} ", at.table, i + 1),
            None => format!("[{}] ", at.table),
        }
    }

    pub(super) fn err(&self, at: At<'_>, value: impl std::fmt::Display, rule: &str) -> SceneError {
        SceneError::Value {
            file: self.file.to_string(),
            line: self.line_of(at),
            table: Self::table_name(at),
            key: at.key.to_string(),
            value: value.to_string(),
            rule: rule.to_string(),
        }
    }

    pub(super) fn default<T: std::fmt::Debug>(&mut self, at: At<'_>, v: Option<T>, d: T) -> T {
        match v {
            Some(v) => v,
            None => {
                self.applied
                    .push(format!("{}{} = {:?}", Self::table_name(at), at.key, d));
                d
            }
        }
    }

    /// A finite number in `range` (described by `rule`).
    pub(super) fn number(
        &mut self,
        at: At<'_>,
        v: Option<f64>,
        default: f64,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64, SceneError> {
        let x = self.default(at, v, default);
        if x.is_finite() && ok(x) {
            Ok(x)
        } else {
            Err(self.err(at, x, rule))
        }
    }

    /// A finite number in range, or `None` when the key is omitted (no default).
    pub(super) fn optional(
        &self,
        at: At<'_>,
        v: Option<f64>,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<Option<f64>, SceneError> {
        match v {
            None => Ok(None),
            Some(x) if x.is_finite() && ok(x) => Ok(Some(x)),
            Some(x) => Err(self.err(at, x, rule)),
        }
    }

    pub(super) fn required(
        &self,
        at: At<'_>,
        v: Option<f64>,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64, SceneError> {
        match v {
            Some(x) if x.is_finite() && ok(x) => Ok(x),
            Some(x) => Err(self.err(at, x, rule)),
            None => Err(self.invalid(format!(
                "{}{} is required for this shape ({rule})",
                Self::table_name(at),
                at.key
            ))),
        }
    }

    pub(super) fn vec3(
        &mut self,
        at: At<'_>,
        v: Option<[f64; 3]>,
        default: [f64; 3],
    ) -> Result<DVec3, SceneError> {
        let x = self.default(at, v, default);
        if x.iter().all(|c| c.is_finite()) {
            Ok(DVec3::from_array(x))
        } else {
            Err(self.err(
                at,
                format!("{x:?}"),
                "every component must be a finite number",
            ))
        }
    }
}
