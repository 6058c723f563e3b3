//! The one error type of this crate.

/// Everything that can go wrong when reading, validating or looking up material data.
///
/// Every variant except [`MaterialError::BuiltinData`] is caused by the caller's input (a file, a name,
/// a number) and its [`mrbrake_error::Kind`] says so; the `mrbrake` CLI exits with code 2 for those.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A file could not be read at all.
    #[error("{file}: cannot read the file: {message}")]
    Io {
        /// The file (path as given).
        file: String,
        /// The operating system's reason.
        message: String,
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
    /// The data compiled into the library failed to load. This is a bug in mrbrake, not bad input.
    #[error("built-in material data is broken (a bug in mrbrake): {message}")]
    BuiltinData {
        /// The underlying error.
        message: String,
    },
}

impl mrbrake_error::Kind for MaterialError {
    /// Every variant but [`MaterialError::BuiltinData`] comes from the caller's input;
    /// broken built-in data is an internal error (a bug).
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::BuiltinData { .. } => mrbrake_error::ErrorKind::Internal,
            _ => mrbrake_error::ErrorKind::Input,
        }
    }
}
