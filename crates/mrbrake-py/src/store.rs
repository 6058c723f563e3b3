//! `mrbrake.store.load`: the records of a results store (the SQLite file `mrbrake sweep` and
//! `mrbrake optimize` write) as the documents of `mrbrake export --json`; the Python wrapper makes
//! a pandas DataFrame of them when pandas is installed.

use std::path::PathBuf;

use mrbrake::explore::stored;
use mrbrake::store::{Store, to_json};
use pyo3::prelude::*;

use crate::convert::json_to_py;
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(store_records, m)?)?;
    Ok(())
}

/// Every record of the store at `path`, read-only, as `mrbrake export STORE --json` lists them.
#[pyfunction]
fn store_records(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyAny>> {
    // A store written before the unit convention reads under the current metric names.
    let records = py
        .detach(|| -> Result<_, mrbrake::explore::ExploreError> {
            let store = Store::open_read_only(&path)?;
            stored::read_records(&store)
        })
        .map_err(error::to_py)?;
    json_to_py(py, &to_json(&records))
}
