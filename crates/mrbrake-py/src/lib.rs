//! The `mrbrake` Python package's compiled part, `mrbrake._native`: a thin PyO3 binding over the
//! facade crate [`mrbrake`].
//!
//! Brief overview: every function here parses its Python arguments, calls one library entry point
//! with the GIL released (`Python::detach`), and returns what the library (or the report
//! composition of `mrbrake-report`, for the JSON documents the CLI prints) produced: NumPy arrays
//! for columns of numbers, dictionaries with the CLI's `--json` keys for the rest. There are no
//! numerics here. Errors are mapped by their [`mrbrake::ErrorKind`] (module `error`; a missing input
//! file is `FileNotFoundError` whatever the kind): input →
//! `ValueError` with the CLI's message, I/O → `OSError`, numerical → `mrbrake.SolverError`,
//! internal → `RuntimeError`.
//!
//! The pure-Python package around it (`python/mrbrake`: the `materials`, `sysid`, `fem`, `store`
//! submodules, type stubs, `store.load`'s pandas branch) re-exports these functions under their
//! public names; see `python/mrbrake/__init__.pyi` for the documented signatures.

use pyo3::prelude::*;

mod analyze;
mod calibrate;
mod convert;
mod error;
mod fem;
mod formula;
mod haptic;
mod materials;
mod report;
mod response;
mod rig;
mod store;
mod study;
mod sysid;
mod thermal;

/// The extension module `mrbrake._native`.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SolverError", m.py().get_type::<error::SolverError>())?;
    analyze::register(m)?;
    materials::register(m)?;
    sysid::register(m)?;
    store::register(m)?;
    fem::register(m)?;
    formula::register(m)?;
    study::register(m)?;
    calibrate::register(m)?;
    haptic::register(m)?;
    rig::register(m)?;
    response::register(m)?;
    thermal::register(m)?;
    report::register(m)?;
    Ok(())
}
