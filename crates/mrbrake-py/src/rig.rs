//! `mrbrake.rig`: the virtual test rig's characterisation protocol (`mrbrake::sim::rig`), as
//! `mrbrake rig characterize` logs it, but as NumPy arrays at full precision. Runs without the GIL.

use std::path::PathBuf;

use mrbrake::sim::rig::{self, RigConfig};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(rig_characterize, m)?)?;
    Ok(())
}

/// The characterisation run of the rig (`config`: a TOML file, default the thesis rig; `seed`
/// overrides its noise seed): `{time_s, current_a, torque_nm, speed_rad_s}` float64 arrays.
#[pyfunction]
#[pyo3(signature = (config=None, seed=None))]
fn rig_characterize(
    py: Python<'_>,
    config: Option<PathBuf>,
    seed: Option<u64>,
) -> PyResult<Bound<'_, PyDict>> {
    let samples = py.detach(|| {
        let mut config = match &config {
            Some(path) => RigConfig::read(path).map_err(error::to_py)?,
            None => RigConfig::default(),
        };
        if let Some(seed) = seed {
            config.seed = seed;
        }
        rig::characterization_samples(&config).map_err(error::to_py)
    })?;
    let names = ["time_s", "current_a", "torque_nm", "speed_rad_s"];
    let dict = PyDict::new(py);
    for (k, name) in names.into_iter().enumerate() {
        let column: Vec<f64> = samples.iter().map(|s| s[k]).collect();
        dict.set_item(name, column.into_pyarray(py))?;
    }
    Ok(dict)
}
