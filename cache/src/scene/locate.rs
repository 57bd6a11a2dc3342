//! Finding where a dotted key sits in the scene text, for error messages.

use std::ops::Range;

use toml::de::{DeTable, DeValue};

/// `text` with every control character (a raw byte of the input echoed into a
/// message: a terminal escape, a carriage return, a newline inside a name) written
/// as a Rust escape (`\u{1b}`, `\r`, `\n`), so a message is one line of plain text.
pub(crate) fn escape_controls(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// 1-based line and column of byte `offset` in `text`.
pub(super) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text.as_bytes()[..offset];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = offset
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1)
        + 1;
    (line, column)
}

/// The span of the value at `path` (table keys and array indices as strings),
/// or of the deepest existing prefix of it.
pub(super) fn span_of(text: &str, path: &[String]) -> Option<Range<usize>> {
    let root = DeTable::parse(text).ok()?;
    let mut span = None;
    let mut value: Option<&DeValue<'_>> = None;
    let mut table = Some(root.get_ref());
    for part in path {
        let next = match (table, value) {
            (Some(t), _) => t
                .iter()
                .find(|(k, _)| k.get_ref().as_ref() == part.as_str())
                .map(|(_, v)| v),
            (None, Some(DeValue::Array(items))) => {
                part.parse::<usize>().ok().and_then(|i| items.get(i))
            }
            _ => None,
        };
        let Some(next) = next else { break };
        span = Some(next.span());
        value = Some(next.get_ref());
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    span
}

/// The dotted key whose line contains `offset` (best effort, for parse errors).
pub(super) fn key_at(text: &str, offset: usize) -> String {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |p| p + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |p| offset + p);
    let line = text[line_start..line_end].trim();
    let key = line.split('=').next().unwrap_or("").trim();
    let table = text[..line_start]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .map(|l| l.trim_matches(|c| c == '[' || c == ']').to_string());
    match (table, key.is_empty() || key.starts_with('[')) {
        (Some(t), false) => format!("{t}.{key}"),
        (Some(t), true) => t,
        (None, false) => key.to_string(),
        (None, true) => "(top level)".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_nested_keys_and_array_items() {
        let text = "[scene]\nname = \"a\"\n\n[materials.glass]\ndensity = -1\n\n[[body]]\nresolution = 0.1\n[[body]]\nresolution = 0.2\n";
        let span = span_of(
            text,
            &["materials".into(), "glass".into(), "density".into()],
        )
        .unwrap();
        assert_eq!(line_column(text, span.start).0, 5);
        let span = span_of(text, &["body".into(), "1".into(), "resolution".into()]).unwrap();
        assert_eq!(line_column(text, span.start).0, 10);
    }
}
