//! `mrbrake.store.load`: the records of a results store (the SQLite file `mrbrake sweep` and
//! `mrbrake optimize` write) as the documents of `mrbrake export --json`; the Python wrapper makes
//! a pandas DataFrame of them when pandas is installed.

use std::path::PathBuf;

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
    let mut records = py
        .detach(|| Store::open_read_only(&path).and_then(|store| store.records()))
        .map_err(error::to_py)?;
    // A store written before the unit convention reads under the current metric names.
    records.iter_mut().for_each(mrbrake::explore::evaluate::upgrade_metric_names);
    json_to_py(py, &to_json(&records))
}
