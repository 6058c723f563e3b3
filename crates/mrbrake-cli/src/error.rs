//! The error of a command and its exit code: 2 for bad input, 1 for I/O, numerical or internal
//! failure — decided by the error's [`ErrorKind`], never by a list of error types.
//!
//! Every library crate's error implements [`Kind`]; a `?` on it converts it into a
//! [`CommandError`] that records the kind at that moment and keeps the error itself, with its whole
//! chain, for the message. An error type without a kind (a new crate that forgot to implement
//! [`Kind`], or a third-party error such as `serde_json::Error`) does not convert: the program does
//! not compile until someone decides what kind it is. Context added with [`Context`] keeps the kind
//! of the error it wraps.

use std::fmt::Display;

use mrbrake::error::{ErrorKind, Kind};

/// An error the command itself found in its arguments (a flag out of range): kind input, exit
/// code 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

impl Kind for InputError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Input
    }
}

/// A broken internal contract found by the binary (e.g. a result that cannot be written as JSON):
/// kind internal, exit code 1.
#[derive(Debug, thiserror::Error)]
#[error("internal error: {0} (please report it)")]
pub struct InternalError(pub String);

impl Kind for InternalError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Internal
    }
}

/// The error of a command: the error with its chain (and any context), and its kind.
#[derive(Debug)]
pub struct CommandError {
    kind: ErrorKind,
    error: anyhow::Error,
}

impl CommandError {
    /// The process exit code: 2 for input errors, 1 otherwise ([`ErrorKind::exit_code`]).
    pub fn exit_code(&self) -> i32 {
        self.kind.exit_code()
    }

    /// The same error behind a line of context (`context: error`), with the same kind.
    pub fn context(self, context: impl Display + Send + Sync + 'static) -> Self {
        Self { kind: self.kind, error: self.error.context(context) }
    }
}

/// The message: the error and its causes, `outer: inner: …`, each cause once (an error that prints
/// its source and also returns it would repeat it), with echoed source lines cut to a readable width.
impl Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use mrbrake::error::message::{clip_excerpts, join_causes};
        let message = join_causes(self.error.chain().map(|cause| cause.to_string()));
        f.write_str(&clip_excerpts(&message))
    }
}

impl<E> From<E> for CommandError
where
    E: Kind + std::error::Error + Send + Sync + 'static,
{
    fn from(error: E) -> Self {
        Self { kind: error.kind(), error: anyhow::Error::new(error) }
    }
}

/// The result of a command.
pub type CommandResult<T = ()> = Result<T, CommandError>;

/// Context for a failed result, keeping the error's kind (the CLI's counterpart of
/// `anyhow::Context`).
pub trait Context<T> {
    /// Puts `context` in front of the error's message.
    fn context(self, context: impl Display + Send + Sync + 'static) -> CommandResult<T>;

    /// Puts the context made by `f` in front of the error's message (made only on failure).
    fn with_context<C: Display + Send + Sync + 'static>(
        self,
        f: impl FnOnce() -> C,
    ) -> CommandResult<T>;
}

impl<T, E: Into<CommandError>> Context<T> for Result<T, E> {
    fn context(self, context: impl Display + Send + Sync + 'static) -> CommandResult<T> {
        self.map_err(|e| e.into().context(context))
    }

    fn with_context<C: Display + Send + Sync + 'static>(
        self,
        f: impl FnOnce() -> C,
    ) -> CommandResult<T> {
        self.map_err(|e| e.into().context(f()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn failing<E: Into<CommandError>>(e: E) -> CommandResult {
        Err(e.into())
    }

    #[test]
    fn the_exit_code_follows_the_kind_through_context() {
        let unit =
            mrbrake::units::parse("5 parsecs", mrbrake::units::Dimension::Length).unwrap_err();
        let e = failing(unit).context("--speed").unwrap_err();
        assert_eq!((e.kind, e.exit_code()), (ErrorKind::Input, 2));
        assert!(e.to_string().starts_with("--speed: "), "{e}");

        let missing = std::io::Error::from(std::io::ErrorKind::NotFound);
        let e = failing(missing).with_context(|| "cannot read spec.toml").unwrap_err();
        assert_eq!(e.exit_code(), 2, "a missing file is the user's input");

        let disk = std::io::Error::other("device error");
        assert_eq!(failing(disk).unwrap_err().exit_code(), 1);
        assert_eq!(failing(InternalError("bug".into())).unwrap_err().exit_code(), 1);
    }

    /// A Newton failure crossing the design crate keeps its numerical kind (exit 1) and its history
    /// in the message.
    #[test]
    fn a_numerical_failure_exits_1_with_its_history() {
        let newton = mrbrake::fem::workflow::newton::NewtonError {
            failure: mrbrake::fem::workflow::newton::NewtonFailure::IterationLimit {
                iterations: 2,
            },
            history: Vec::new(),
            residual_scale: 1.0,
        };
        let design =
            mrbrake::design::DesignError::from(mrbrake::magnetics::MagneticsError::from(newton));
        let e = failing(design).context("analysing spec.toml").unwrap_err();
        assert_eq!((e.kind, e.exit_code()), (ErrorKind::Numerical, 1));
        assert!(e.to_string().contains("residual history"), "{e}");
    }
}
