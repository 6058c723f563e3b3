//! Field errors: every invalid field of one input, collected so that a user sees all of them at
//! once (a spec with three wrong values names all three), each with where it is.

use std::fmt;

/// One invalid field: where it is (file and 1-based line when known), its dotted path in the
/// input (`drum.gap`, `region[2].material`, or a function argument such as `frequencies`), what is
/// wrong with it, and, when the check is a range or a set, the offending value and what is allowed.
///
/// The front ends read [`FieldError::field`] to name their own flag or keyword argument (the CLI's
/// `--poles` for the library's `poles`); the text of [`FieldError::value`] and
/// [`FieldError::allowed`] is for people.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldError {
    /// The file the field was read from, when the input came from a file.
    pub file: Option<String>,
    /// 1-based line of the field in that file, when known.
    pub line: Option<usize>,
    /// Dotted path of the field (`drum.gap`, `coil.turns`, `region[2].material`, `dt`); empty for
    /// an error about a whole file (it does not parse).
    pub field: String,
    /// What is wrong, e.g. `must be > 0 mm, got -0.5 mm`; may be empty when the value and the
    /// allowed range say it all.
    pub message: String,
    /// The offending value as the user wrote it or as it was read (`-0.5`, `NaN`, `"bdf3"`).
    pub value: Option<String>,
    /// What is allowed: a range or a set (`> 0`, `1..=12`, `1 or 2`, `finite`).
    pub allowed: Option<String>,
}

impl FieldError {
    /// A field error with no file or line yet (see [`FieldError::in_file`]).
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            file: None,
            line: None,
            field: field.into(),
            message: message.into(),
            value: None,
            allowed: None,
        }
    }

    /// `field` has the value `value`, outside what is `allowed` (`> 0`, `1..=12`, `bdf2 or
    /// euler`).
    pub fn out_of_range(
        field: impl Into<String>,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Self::new(field, "").with_value(value).with_allowed(allowed)
    }

    /// The same error with the offending value.
    pub fn with_value(mut self, value: impl fmt::Display) -> Self {
        self.value = Some(value.to_string());
        self
    }

    /// The same error with what is allowed.
    pub fn with_allowed(mut self, allowed: impl Into<String>) -> Self {
        self.allowed = Some(allowed.into());
        self
    }

    /// The same error located in `file` (and at `line` when known).
    pub fn in_file(mut self, file: impl Into<String>, line: Option<usize>) -> Self {
        self.file = Some(file.into());
        self.line = line;
        self
    }

    /// The same error with its field path inside `parent` (`coil[1]` and `turns` make
    /// `coil[1].turns`; an empty field becomes `parent`).
    pub fn under(mut self, parent: impl fmt::Display) -> Self {
        self.field = if self.field.is_empty() {
            parent.to_string()
        } else if self.field.starts_with('[') {
            format!("{parent}{}", self.field)
        } else {
            format!("{parent}.{}", self.field)
        };
        self
    }

    /// The same error with its field named as a front end names it: the first `(library name,
    /// front-end name)` pair whose library name is the field, or a prefix of it followed by `.`
    /// or `[`, is substituted (the CLI turns `poles` into `--poles`, Python keeps its keyword).
    pub fn renamed(mut self, names: &[(&str, &str)]) -> Self {
        for &(library, front_end) in names {
            let rest = self.field.strip_prefix(library);
            if let Some(rest) = rest.filter(|r| r.is_empty() || r.starts_with(['.', '['])) {
                self.field = format!("{front_end}{rest}");
                break;
            }
        }
        self
    }
}

impl fmt::Display for FieldError {
    /// `file:line: field: message (got V; allowed: A)`; without a message,
    /// `field: got V; allowed: A`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: ")?,
            (Some(file), None) => write!(f, "{file}: ")?,
            _ => {}
        }
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        f.write_str(&self.message)?;
        let got = self.value.as_ref().map(|v| format!("got {v}"));
        let allowed = self.allowed.as_ref().map(|a| format!("allowed: {a}"));
        let detail: Vec<String> = got.into_iter().chain(allowed).collect();
        match (detail.is_empty(), self.message.is_empty()) {
            (true, _) => Ok(()),
            (false, true) => f.write_str(&detail.join("; ")),
            (false, false) => write!(f, " ({})", detail.join("; ")),
        }
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

    #[test]
    fn a_range_error_carries_its_value_and_what_is_allowed() {
        let e = FieldError::out_of_range("poles", 0, ">= 1");
        assert_eq!((e.value.as_deref(), e.allowed.as_deref()), (Some("0"), Some(">= 1")));
        assert_eq!(e.to_string(), "poles: got 0; allowed: >= 1");
        let e =
            FieldError::new("dt", "must be a time step").with_value(-1.0).in_file("p.toml", None);
        assert_eq!(e.to_string(), "p.toml: dt: must be a time step (got -1)");
        let e = FieldError::out_of_range("turns", 0, "> 0").under("coil[2]");
        assert_eq!(e.field, "coil[2].turns");
        assert_eq!(FieldError::new("[3]", "x").under("points").field, "points[3]");
    }

    #[test]
    fn a_front_end_renames_a_field_and_its_children_only() {
        let names = [("poles", "--poles"), ("order", "--order")];
        assert_eq!(FieldError::new("poles", "").renamed(&names).field, "--poles");
        assert_eq!(FieldError::new("order[1]", "").renamed(&names).field, "--order[1]");
        assert_eq!(FieldError::new("polesx", "").renamed(&names).field, "polesx");
    }
}
