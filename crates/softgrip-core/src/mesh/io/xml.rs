//! The little XML scanning the `.vtu` reader needs: start tags with their
//! attributes, and where a tag's section closes. No entities, comments or
//! nesting checks: VTK's files need none.

/// An XML start tag: its attributes and where it ends.
pub(crate) struct Tag<'a> {
    /// `(key, value)` pairs, in the tag's order.
    attributes: Vec<(&'a str, &'a str)>,
    /// Byte just after the tag's `>`.
    pub(crate) end: usize,
    /// Whether the tag ends in `/>` (no content, no closing tag).
    pub(crate) self_closing: bool,
}

impl Tag<'_> {
    /// The value of attribute `key`, if the tag has it.
    pub(crate) fn get(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| *v)
    }
}

/// The next start tag named `name` at or after `from`.
pub(crate) fn find_tag<'a>(text: &'a str, from: usize, name: &str) -> Option<Tag<'a>> {
    let mut at = from;
    loop {
        let open = at + text.get(at..)?.find('<')?;
        let rest = &text[open + 1..];
        let name_end = rest
            .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
            .unwrap_or(rest.len());
        let close = open + 1 + rest.find('>')?;
        if &rest[..name_end] == name {
            let inner = &text[open + 1 + name_end..close];
            let self_closing = inner.trim_end().ends_with('/');
            return Some(Tag {
                attributes: attributes(inner.trim_end_matches('/')),
                end: close + 1,
                self_closing,
            });
        }
        at = close + 1;
    }
}

/// `key="value"` pairs (single or double quotes).
fn attributes(s: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    let mut rest = s;
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let Some(quote) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            break;
        };
        let Some(len) = after[1..].find(quote) else {
            break;
        };
        out.push((key, &after[1..1 + len]));
        rest = &after[1 + len + 1..];
    }
    out
}

/// The byte where the first `</name>` after `tag` starts, if there is one.
pub(crate) fn closing(text: &str, tag: &Tag, name: &str) -> Option<usize> {
    text[tag.end..]
        .find(&format!("</{name}>"))
        .map(|e| tag.end + e)
}

/// The byte where `tag`'s section `name` closes: its `</name>`, or the end
/// of `text` when it is not closed.
pub(crate) fn section_end(text: &str, tag: &Tag, name: &str) -> usize {
    closing(text, tag, name).unwrap_or(text.len())
}
