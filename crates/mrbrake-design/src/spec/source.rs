//! Where a spec was read from: the file and the line of every key, from the TOML parser's spans,
//! so that a validation error points at the line to change (`spec.toml:61: drum.gap: …`).

use std::collections::BTreeMap;

use mrbrake_error::{FieldError, FieldErrors};
use toml::de::{DeTable, DeValue};

/// The file a spec was read from and the 1-based line of each of its keys (dotted paths, tables
/// included: `drum` is the line of `[drum]`). Empty for a spec that was not read from a file.
#[derive(Debug, Clone, Default)]
pub struct SpecSource {
    origin: Option<String>,
    lines: BTreeMap<String, usize>,
}

impl SpecSource {
    /// The lines of every key of `text`, read from `origin`. Text the TOML parser refuses has no
    /// lines (the spec parser then reports the error itself).
    pub(crate) fn read(origin: &str, text: &str) -> Self {
        let mut lines = BTreeMap::new();
        if let Ok(table) = DeTable::parse(text) {
            collect_lines(table.get_ref(), "", &LineIndex::new(text), &mut lines);
        }
        Self { origin: Some(origin.to_string()), lines }
    }

    /// The file (or in-memory origin) the spec was read from.
    pub fn origin(&self) -> Option<&str> {
        self.origin.as_deref()
    }

    /// The line of `path` (`drum.gap`), or of its nearest enclosing table that the file has
    /// (`housing` for a missing `housing.cover_thickness`).
    pub fn line_of(&self, path: &str) -> Option<usize> {
        let mut path = path;
        loop {
            if let Some(&line) = self.lines.get(path) {
                return Some(line);
            }
            path = &path[..path.rfind('.')?];
        }
    }

    /// Each error with the file and, where it is not already known, the line of its field.
    pub(crate) fn locate(&self, errors: FieldErrors) -> FieldErrors {
        let Some(origin) = &self.origin else { return errors };
        let mut located = FieldErrors::new();
        for error in errors {
            let line = error.line.or_else(|| self.line_of(&error.field));
            located.push(FieldError { file: Some(origin.clone()), line, ..error });
        }
        located
    }
}

fn collect_lines(
    table: &DeTable<'_>,
    prefix: &str,
    index: &LineIndex,
    lines: &mut BTreeMap<String, usize>,
) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.get_ref().to_string()
        } else {
            format!("{prefix}.{}", key.get_ref())
        };
        lines.entry(path.clone()).or_insert_with(|| index.line(key.span().start));
        if let DeValue::Table(inner) = value.get_ref() {
            collect_lines(inner, &path, index, lines);
        }
    }
}

/// Byte offset → 1-based line number.
struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    fn new(text: &str) -> Self {
        let starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1));
        Self { starts: starts.collect() }
    }

    fn line(&self, offset: usize) -> usize {
        self.starts.partition_point(|&start| start <= offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_tables_and_inline_tables_have_their_lines() {
        let text = "name = \"x\"\n\n[drum]\nr0 = 1\ngap = 2\n[coil]\nwire = { awg = 24 }\n";
        let source = SpecSource::read("a.toml", text);
        assert_eq!(source.line_of("name"), Some(1));
        assert_eq!(source.line_of("drum"), Some(3));
        assert_eq!(source.line_of("drum.gap"), Some(5));
        assert_eq!(source.line_of("coil.wire.awg"), Some(7));
        // A field the file does not have points at its table.
        assert_eq!(source.line_of("drum.height"), Some(3));
        assert_eq!(source.line_of("spacer.thickness"), None);
        let located = source.locate(FieldError::new("drum.gap", "must be > 0").into());
        assert_eq!(located.to_string(), "a.toml:5: drum.gap: must be > 0");
    }
}
