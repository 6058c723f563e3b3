//! Field errors: every invalid field of one input, collected so that a user sees all of them at
//! once (a spec with three wrong values names all three), each with where it is.

use std::fmt;

/// One invalid field: where it is (file and 1-based line when known), its dotted path in the
/// input (`drum.gap`, `region[2].material`), and what is wrong with it, including the allowed range.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldError {
    /// The file the field was read from, when the input came from a file.
    pub file: Option<String>,
    /// 1-based line of the field in that file, when known.
    pub line: Option<usize>,
    /// Dotted path of the field (`drum.gap`, `coil.turns`, `region[2].material`).
    pub field: String,
    /// What is wrong and what is allowed, e.g. `must be > 0 mm, got -0.5 mm`.
    pub message: String,
}

impl FieldError {
    /// A field error with no file or line yet (see [`FieldError::in_file`]).
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self { file: None, line: None, field: field.into(), message: message.into() }
    }

    /// The same error located in `file` (and at `line` when known).
    pub fn in_file(mut self, file: impl Into<String>, line: Option<usize>) -> Self {
        self.file = Some(file.into());
        self.line = line;
        self
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: ")?,
            (Some(file), None) => write!(f, "{file}: ")?,
            _ => {}
        }
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl std::error::Error for FieldError {}

/// A non-empty list of [`FieldError`]s (the error of a validation that checks every field).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FieldErrors(Vec<FieldError>);

impl FieldErrors {
    /// An empty collector.
    pub fn new() -> Self {
        Self(Vec::new())
    }

    /// Adds one error.
    pub fn push(&mut self, error: FieldError) {
        self.0.push(error);
    }

    /// Adds `field: message`.
    pub fn add(&mut self, field: impl Into<String>, message: impl Into<String>) {
        self.push(FieldError::new(field, message));
    }

    /// True when no error was collected.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Number of errors.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// The errors, in the order they were found.
    pub fn errors(&self) -> &[FieldError] {
        &self.0
    }

    /// Sets the file (and line, when not already known) of every error.
    pub fn in_file(mut self, file: &str) -> Self {
        for e in &mut self.0 {
            e.file.get_or_insert_with(|| file.to_string());
        }
        self
    }

    /// `Ok(value)` when nothing was collected, else `Err(self)`.
    pub fn into_result<T>(self, value: T) -> Result<T, Self> {
        if self.is_empty() { Ok(value) } else { Err(self) }
    }
}

impl From<FieldError> for FieldErrors {
    fn from(error: FieldError) -> Self {
        Self(vec![error])
    }
}

impl IntoIterator for FieldErrors {
    type Item = FieldError;
    type IntoIter = std::vec::IntoIter<FieldError>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

impl fmt::Display for FieldErrors {
    /// One error: its text. Several: a count, then one per line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.as_slice() {
            [] => f.write_str("no field errors"),
            [one] => write!(f, "{one}"),
            many => {
                write!(f, "{} invalid fields:", many.len())?;
                for e in many {
                    write!(f, "\n  {e}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for FieldErrors {}

impl crate::Kind for FieldError {
    fn kind(&self) -> crate::ErrorKind {
        crate::ErrorKind::Input
    }
}

impl crate::Kind for FieldErrors {
    fn kind(&self) -> crate::ErrorKind {
        crate::ErrorKind::Input
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_error_reads_as_itself_and_many_are_listed() {
        let mut errors = FieldErrors::new();
        errors.add("drum.gap", "must be > 0 mm, got -0.5 mm");
        assert_eq!(errors.to_string(), "drum.gap: must be > 0 mm, got -0.5 mm");
        errors
            .push(FieldError::new("coil.turns", "must be >= 1, got 0").in_file("b.toml", Some(7)));
        let errors = errors.in_file("a.toml");
        assert_eq!(
            errors.to_string(),
            "2 invalid fields:\n  a.toml: drum.gap: must be > 0 mm, got -0.5 mm\n  b.toml:7: coil.turns: must be >= 1, got 0"
        );
        assert!(FieldErrors::new().into_result(3).is_ok());
    }
}
