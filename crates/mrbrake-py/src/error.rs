//! Library errors as Python exceptions, chosen by the error's kind ([`mrbrake::ErrorKind`]), never
//! by its type, as the CLI chooses its exit code (`crates/mrbrake-cli/src/error.rs`).

use std::error::Error;

use mrbrake::{ErrorKind, Kind};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::{PyErr, create_exception};

create_exception!(
    mrbrake,
    SolverError,
    PyRuntimeError,
    "A numerical failure of a solve or a fit (Newton without convergence, a singular system, a \
     fit that did not converge): the error kind for which the CLI exits 1."
);

/// The message the CLI prints after `error: `: the error and its causes, `outer: inner: …`
/// (anyhow's alternate form, which the CLI uses).
pub fn chain_message(error: &(dyn Error + 'static)) -> String {
    let mut message = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        message.push_str(": ");
        message.push_str(&cause.to_string());
        source = cause.source();
    }
    message
}

/// True when `error` or one of its causes is an I/O error saying a file does not exist.
fn is_missing_file(error: &(dyn Error + 'static)) -> bool {
    let mut next: Option<&(dyn Error + 'static)> = Some(error);
    while let Some(e) = next {
        if e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::NotFound)
        {
            return true;
        }
        next = e.source();
    }
    false
}

/// The Python exception of a library error: `FileNotFoundError` (an `OSError`) when an input
/// file does not exist, else by its kind: `ValueError` for input, `OSError` for I/O,
/// `SolverError` for numerical failures, `RuntimeError` for internal ones.
pub fn to_py<E: Kind + Error + 'static>(error: E) -> PyErr {
    let message = chain_message(&error);
    if is_missing_file(&error) {
        return PyFileNotFoundError::new_err(message);
    }
    match error.kind() {
        ErrorKind::Input => PyValueError::new_err(message),
        ErrorKind::Io => PyOSError::new_err(message),
        ErrorKind::Numerical => SolverError::new_err(message),
        _ => PyRuntimeError::new_err(message),
    }
}

/// A `ValueError` for an argument the binding itself checks.
pub fn input(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// An internal error (a result that cannot be written as JSON is a bug).
pub fn internal(error: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(format!("internal error: {error} (please report it)"))
}

/// `FileNotFoundError` naming `path` when it does not exist (an input a library opens in a way
/// that does not say so itself, such as a results store).
pub fn exists(path: &std::path::Path) -> Result<(), PyErr> {
    if path.exists() {
        return Ok(());
    }
    Err(PyFileNotFoundError::new_err(format!("{}: no such file", path.display())))
}
