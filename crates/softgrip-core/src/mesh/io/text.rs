//! Numbers as the writers print them.

/// Number formatting shared by the writers: shortest round-trip text.
pub(super) fn num(v: f64) -> String {
    format!("{v:?}")
}
