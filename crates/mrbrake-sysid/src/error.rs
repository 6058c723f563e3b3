//! The one error type of this crate.

use std::path::PathBuf;

use mrbrake_error::FieldError;

/// Errors of `mrbrake-sysid`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SysidError {
    /// Invalid argument or data (a value out of range, too few points): the field (an argument
    /// such as `poles`, `order`, `torque`), the value and what is allowed.
    #[error(transparent)]
    Input(Box<FieldError>),
    /// A log, manifest or FRD file is malformed: the message names the file, the line (1-based, the
    /// header being line 1) when known, and what was expected.
    #[error("{file}{}: {message}", line.map(|l| format!(", line {l}")).unwrap_or_default())]
    File {
        /// The file (or in-memory source name) being read.
        file: PathBuf,
        /// The 1-based line, when the problem is on one line.
        line: Option<u64>,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A CSV log, manifest or FRD file cannot be parsed (or read), with the file, the 1-based line
    /// when known, what was being read, and the CSV reader's error.
    #[error("{}{}: {what}", file.display(), line.map(|l| format!(", line {l}")).unwrap_or_default())]
    Csv {
        /// The file (or in-memory source name) being read.
        file: PathBuf,
        /// The 1-based line, when known.
        line: Option<u64>,
        /// What was being read, e.g. `"cannot read the header row"`.
        what: &'static str,
        /// The CSV reader's error.
        source: csv::Error,
    },
    /// A file could not be opened or read.
    #[error("cannot read '{path}'")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// An inverse-model file is not JSON or does not follow the schema of
    /// [`mrbrake_control::InverseModelFile`]: names the file and, when known, the field (e.g.
    /// `rising.coefficients[1]`).
    #[error("inverse-model file '{}'{}", file.display(), field.as_ref().map(|f| format!(", field {f}")).unwrap_or_default())]
    ModelFile {
        /// The file (or in-memory source name) being read.
        file: PathBuf,
        /// The path of the offending field, when the error is inside one.
        field: Option<String>,
        /// What the JSON parser found.
        source: serde_json::Error,
    },
    /// An inverse model's values are unusable (a decreasing branch, a backwards current range, too
    /// many coefficients): the controller's own error.
    #[error("inverse-model file '{}'", file.display())]
    Model {
        /// The file (or in-memory source name) the model came from.
        file: PathBuf,
        /// Why the controller refuses the model.
        source: mrbrake_control::ControlError,
    },
    /// A numerical method failed (singular least-squares problem, non-convergence); `history` holds the
    /// cost (or residual) per iteration so the failure can be diagnosed.
    #[error("{message} (history of the cost per iteration: {history:?})")]
    Numerical {
        /// What failed.
        message: String,
        /// Cost or residual per iteration up to the failure.
        history: Vec<f64>,
    },
}

impl mrbrake_error::Kind for SysidError {
    /// Input for bad arguments and files (an unreadable file takes the kind of its I/O error),
    /// numerical for failed fits.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            Self::Input(_) | Self::File { .. } | Self::ModelFile { .. } => ErrorKind::Input,
            Self::Model { source, .. } => source.kind(),
            Self::Io { source, .. } => Kind::kind(source),
            Self::Csv { source, .. } => match source.kind() {
                csv::ErrorKind::Io(e) => Kind::kind(e),
                _ => ErrorKind::Input,
            },
            Self::Numerical { .. } => ErrorKind::Numerical,
        }
    }
}

impl From<FieldError> for SysidError {
    fn from(error: FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl SysidError {
    /// The same error with the field of an input error named as a front end names it (see
    /// [`FieldError::renamed`]: the CLI's `--poles` for `poles`); other errors are unchanged.
    pub fn with_field_names(self, names: &[(&str, &str)]) -> Self {
        match self {
            Self::Input(field) => Self::Input(Box::new(field.renamed(names))),
            other => other,
        }
    }

    pub(crate) fn numerical(message: impl Into<String>, history: Vec<f64>) -> Self {
        Self::Numerical { message: message.into(), history }
    }
}
