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
    /// The keys whose values are bare numbers, as written (`drum.gap` → `0.5`).
    bare: BTreeMap<String, String>,
}

impl SpecSource {
    /// The lines of every key of `text`, read from `origin`. Text the TOML parser refuses has no
    /// lines (the spec parser then reports the error itself).
    pub(crate) fn read(origin: &str, text: &str) -> Self {
        let mut source = Self { origin: Some(origin.to_string()), ..Self::default() };
        if let Ok(table) = DeTable::parse(text) {
            source.collect(table.get_ref(), "", &LineIndex::new(text));
        }
        source
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
        for mut error in errors {
            let line = error.line.or_else(|| self.line_of(&error.field));
            if let Some(hint) = self.bare_length_hint(&error.field) {
                error.message.push_str(&hint);
            }
            located.push(FieldError { file: Some(origin.clone()), line, ..error });
        }
        located
    }

    /// For a length field the file gives as a bare number: that it is read in metres (SI), the
    /// commonest slip being millimetres meant.
    fn bare_length_hint(&self, field: &str) -> Option<String> {
        let written = self.bare.get(field)?;
        let is_length = super::numeric_fields()
            .any(|f| f.path == field && f.quantity == super::Quantity::Length);
        is_length.then(|| {
            format!(
                "; the file writes a bare {written}, read in metres (SI): write \"{written}mm\" if \
                 millimetres were meant"
            )
        })
    }

    fn collect(&mut self, table: &DeTable<'_>, prefix: &str, index: &LineIndex) {
        for (key, value) in table {
            let path = if prefix.is_empty() {
                key.get_ref().to_string()
            } else {
                format!("{prefix}.{}", key.get_ref())
            };
            self.lines.entry(path.clone()).or_insert_with(|| index.line(key.span().start));
            match value.get_ref() {
                DeValue::Table(inner) => self.collect(inner, &path, index),
                DeValue::Integer(n) => {
                    self.bare.insert(path, n.as_str().to_string());
                }
                DeValue::Float(x) => {
                    self.bare.insert(path, x.as_str().to_string());
                }
                _ => {}
            }
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
        let located = source.locate(FieldError::new("drum.height", "must be > 0").into());
        assert_eq!(located.to_string(), "a.toml:3: drum.height: must be > 0");
        // A length written as a bare number is read in metres: its errors say so.
        let located = source.locate(FieldError::new("drum.gap", "is too wide").into());
        assert_eq!(
            located.to_string(),
            "a.toml:5: drum.gap: is too wide; the file writes a bare 2, read in metres (SI): \
             write \"2mm\" if millimetres were meant"
        );
        // A bare number that is not a length has no such note.
        let located = source.locate(FieldError::new("coil.wire.awg", "is odd").into());
        assert_eq!(located.to_string(), "a.toml:7: coil.wire.awg: is odd");
    }
}
