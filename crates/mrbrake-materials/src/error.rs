//! The one error type of this crate.

use std::sync::Arc;

/// Everything that can go wrong when reading, validating or looking up material data.
///
/// Every variant but [`MaterialError::Io`], [`MaterialError::BuiltinData`] and
/// [`MaterialError::MissingRow`] is caused by the caller's input (a file, a name, a number), and its
/// [`mrbrake_error::Kind`] says so (the `mrbrake` CLI exits with code 2 for those). A file that
/// cannot be read keeps its [`std::io::Error`] as its source and takes that error's kind: a missing
/// file is input, a failing disk is I/O. Broken built-in data is an internal error (a bug).
///
/// The error is `Clone` (the library keeps the outcome of its one-time parse), so the I/O source is
/// shared behind an [`Arc`].
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A file could not be read at all; the operating system's reason is the
    /// [source](std::error::Error::source) (an `Arc<std::io::Error>`).
    #[error("{file}: cannot read the file")]
    Io {
        /// The file (path as given).
        file: String,
        /// The operating system's reason.
        #[source]
        source: Arc<std::io::Error>,
    },
    /// A line of a CSV file could not be parsed: wrong header, wrong number of fields, not a number.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// The file (or `points` for an in-memory list).
        file: String,
        /// 1-based line number in the file (for in-memory lists: the 1-based point number).
        line: u64,
        /// What was wrong and what was expected.
        message: String,
    },
    /// A curve parsed fine but breaks one of the validation rules (finite, starts at the origin,
    /// strictly increasing, enough points).
    #[error("{file}:{line}: {rule}")]
    InvalidCurve {
        /// The file (or `points` for an in-memory list).
        file: String,
        /// 1-based line number of the offending point (for in-memory lists: the 1-based point number).
        line: u64,
        /// The rule broken, with the offending values and what is allowed.
        rule: String,
    },
    /// A material name that is not in the built-in library.
    #[error("unknown material `{name}`; known materials: {}", known.join(", "))]
    UnknownMaterial {
        /// The name asked for.
        name: String,
        /// Every name the library knows.
        known: Vec<String>,
    },
    /// A hysteretic solve asked for a material that has no hysteresis model (only the library's
    /// steels have one).
    #[error("material `{name}` has no hysteresis model; materials with one: {}", known.join(", "))]
    NoHysteresisModel {
        /// The material asked for.
        name: String,
        /// The materials that have a hysteresis model.
        known: Vec<String>,
    },
    /// A number outside its allowed range (an AWG size, a wire diameter, a temperature).
    #[error("{quantity} = {value} is out of range; allowed: {allowed}")]
    OutOfRange {
        /// What the number is.
        quantity: String,
        /// The value given.
        value: f64,
        /// The allowed range in words.
        allowed: String,
    },
    /// A table compiled into the library lacks a row the catalogue refers to. A bug in mrbrake.
    #[error("{file} has no row `{row}`")]
    MissingRow {
        /// The embedded data file.
        file: String,
        /// The row's name (first column).
        row: String,
    },
    /// The data compiled into the library failed to load. This is a bug in mrbrake, not bad input;
    /// the [source](std::error::Error::source) says which file and line.
    #[error("built-in material data is broken (a bug in mrbrake)")]
    BuiltinData {
        /// What failed while loading the built-in data.
        #[source]
        source: Box<MaterialError>,
    },
}

impl MaterialError {
    /// A file that could not be read, keeping the operating system's error.
    pub(crate) fn io(file: impl Into<String>, source: std::io::Error) -> Self {
        Self::Io { file: file.into(), source: Arc::new(source) }
    }

    /// Marks an error met while loading the built-in data as a bug in mrbrake.
    pub(crate) fn builtin(source: MaterialError) -> Self {
        match source {
            already @ Self::BuiltinData { .. } => already,
            other => Self::BuiltinData { source: Box::new(other) },
        }
    }
}

impl mrbrake_error::Kind for MaterialError {
    /// A file that cannot be read takes the kind of its I/O error; broken built-in data is an
    /// internal error; everything else comes from the caller's input.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            Self::Io { source, .. } => Kind::kind(source.as_ref()),
            Self::BuiltinData { .. } | Self::MissingRow { .. } => ErrorKind::Internal,
            Self::Parse { .. }
            | Self::InvalidCurve { .. }
            | Self::UnknownMaterial { .. }
            | Self::NoHysteresisModel { .. }
            | Self::OutOfRange { .. } => ErrorKind::Input,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::{ErrorKind, Kind};

    fn full_message(error: &dyn std::error::Error) -> String {
        let mut message = error.to_string();
        let mut cause = error.source();
        while let Some(inner) = cause {
            message.push_str(&format!(": {inner}"));
            cause = inner.source();
        }
        message
    }

    #[test]
    fn a_missing_file_is_input_a_failing_disk_is_io() {
        let missing = MaterialError::io("bh.csv", std::io::ErrorKind::NotFound.into());
        assert_eq!(missing.kind(), ErrorKind::Input);
        let disk = MaterialError::io("bh.csv", std::io::Error::other("device error"));
        assert_eq!(disk.kind(), ErrorKind::Io);
        // The reason is the typed source; the whole chain reads as one message.
        let source = std::error::Error::source(&disk).expect("the I/O error is the source");
        let io = source.downcast_ref::<Arc<std::io::Error>>().expect("typed, not a string");
        assert_eq!(io.kind(), std::io::ErrorKind::Other);
        assert_eq!(full_message(&disk), "bh.csv: cannot read the file: device error");
    }

    #[test]
    fn broken_builtin_data_is_internal_and_keeps_its_cause() {
        let parse =
            MaterialError::Parse { file: "data/x.csv".into(), line: 3, message: "bad".into() };
        assert_eq!(parse.kind(), ErrorKind::Input);
        let builtin = MaterialError::builtin(parse);
        assert_eq!(builtin.kind(), ErrorKind::Internal);
        assert_eq!(
            full_message(&builtin),
            "built-in material data is broken (a bug in mrbrake): data/x.csv:3: bad"
        );
        // Marking twice does not nest.
        let again = MaterialError::builtin(builtin);
        assert_eq!(full_message(&again).matches("broken").count(), 1);
        let missing = MaterialError::MissingRow { file: "data/y.csv".into(), row: "z".into() };
        assert_eq!(missing.kind(), ErrorKind::Internal);
    }
}
