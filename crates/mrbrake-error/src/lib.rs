//! The kind of an mrbrake error, shared by every crate.
//!
//! Brief overview: each library crate keeps its own error enum (variants documented, the causes
//! they wrap kept as typed values, never flattened into strings) and implements [`Kind`] for it,
//! returning one [`ErrorKind`]. An error that wraps another crate's error returns the inner
//! error's kind, so the kind crosses crate boundaries intact. The front ends decide from the kind
//! alone, without a list of error types to downcast:
//!
//! | kind | meaning | CLI exit code | Python exception |
//! |---|---|---|---|
//! | [`ErrorKind::Input`] | a file, field or flag is malformed or out of its allowed range; a file the user named does not exist or may not be read | 2 | `ValueError` |
//! | [`ErrorKind::Io`] | the system failed to read or write (disk full, device error) | 1 | `OSError` |
//! | [`ErrorKind::Numerical`] | the input was valid but the numerics failed (no convergence, a singular system); the error carries its history | 1 | `mrbrake.SolverError` |
//! | [`ErrorKind::Internal`] | a broken internal contract (a bug: please report it) | 1 | `RuntimeError` |
//!
//! With the default `std` feature, [`FieldErrors`] collects every invalid field of one input (a
//! spec, a problem file) so that a user sees all of them at once, and `std::io::Error` has the
//! kind [`ErrorKind::Input`] when the path is at fault (not found, permission denied, not a
//! directory, is a directory) and [`ErrorKind::Io`] otherwise. Without it the crate is `no_std` and allocation-free.
//!
//! ```
//! use mrbrake_error::{ErrorKind, Kind};
//!
//! #[derive(Debug)]
//! enum SolverError { BadMesh(String), NotConverged { history: Vec<f64> } }
//!
//! impl Kind for SolverError {
//!     fn kind(&self) -> ErrorKind {
//!         match self {
//!             Self::BadMesh(_) => ErrorKind::Input,
//!             Self::NotConverged { .. } => ErrorKind::Numerical,
//!         }
//!     }
//! }
//!
//! let e = SolverError::NotConverged { history: vec![1.0, 0.1] };
//! assert_eq!(e.kind().exit_code(), 1);
//! assert!(!e.is_input_error());
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]

/// What went wrong, in the terms a front end acts on (see the crate docs for the mapping).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ErrorKind {
    /// Bad input: a file, field or flag is malformed or outside its allowed range, or a file the
    /// user named does not exist or may not be read.
    Input,
    /// The system failed to read or write a file (disk full, device error).
    Io,
    /// Valid input, failed numerics: no convergence, a singular or indefinite system, a fit that
    /// cannot be made. The error carries the history that shows how far it got.
    Numerical,
    /// A broken internal contract: a bug in mrbrake.
    Internal,
}

impl ErrorKind {
    /// The process exit code of the command-line program: 2 for input errors (the user can fix
    /// the command or the file), 1 for I/O, numerical and internal failures.
    pub const fn exit_code(self) -> i32 {
        match self {
            Self::Input => 2,
            Self::Io | Self::Numerical | Self::Internal => 1,
        }
    }

    /// True for [`ErrorKind::Input`]: the user's input is at fault.
    pub const fn is_input(self) -> bool {
        matches!(self, Self::Input)
    }

    /// A short lower-case name (`"input"`, `"io"`, `"numerical"`, `"internal"`), e.g. for JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Input => "input",
            Self::Io => "io",
            Self::Numerical => "numerical",
            Self::Internal => "internal",
        }
    }
}

impl core::fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// An error that knows its [`ErrorKind`]. Every library crate's error type implements it; errors
/// that wrap another crate's error return the wrapped error's kind.
pub trait Kind {
    /// The kind of this error.
    fn kind(&self) -> ErrorKind;

    /// True when the user's input is at fault ([`ErrorKind::Input`]: CLI exit code 2).
    fn is_input_error(&self) -> bool {
        self.kind().is_input()
    }
}

impl<K: Kind + ?Sized> Kind for &K {
    fn kind(&self) -> ErrorKind {
        (**self).kind()
    }
}

/// An error that cannot happen (e.g. an evaluator that never fails) has every kind vacuously.
impl Kind for core::convert::Infallible {
    fn kind(&self) -> ErrorKind {
        match *self {}
    }
}

#[cfg(feature = "std")]
impl<K: Kind + ?Sized> Kind for Box<K> {
    fn kind(&self) -> ErrorKind {
        (**self).kind()
    }
}

/// A path the user gave that does not exist, may not be read, is of the wrong type or is larger
/// than its kind's limit ([`read`]) is an input error; any other I/O failure is [`ErrorKind::Io`].
#[cfg(feature = "std")]
impl Kind for std::io::Error {
    fn kind(&self) -> ErrorKind {
        use std::io::ErrorKind as Io;
        match std::io::Error::kind(self) {
            Io::NotFound
            | Io::PermissionDenied
            | Io::NotADirectory
            | Io::IsADirectory
            | Io::FileTooLarge => ErrorKind::Input,
            _ => ErrorKind::Io,
        }
    }
}

#[cfg(feature = "std")]
mod field;
#[cfg(feature = "std")]
pub mod message;
#[cfg(feature = "std")]
pub mod read;
#[cfg(feature = "std")]
pub use field::{FieldError, FieldErrors};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_follow_the_kind() {
        assert_eq!(ErrorKind::Input.exit_code(), 2);
        assert_eq!(ErrorKind::Io.exit_code(), 1);
        assert_eq!(ErrorKind::Numerical.exit_code(), 1);
        assert_eq!(ErrorKind::Internal.exit_code(), 1);
    }

    #[test]
    fn references_and_boxes_keep_the_kind() {
        let io = std::io::Error::other("disk full");
        assert_eq!(Kind::kind(&&io), ErrorKind::Io);
        let missing: Box<std::io::Error> = Box::new(std::io::ErrorKind::NotFound.into());
        assert!(missing.is_input_error());
    }
}
