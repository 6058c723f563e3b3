//! `mrbrake.rig`: the virtual test rig's protocols (`mrbrake::sim::rig`), as `mrbrake rig
//! characterize` and `mrbrake rig freqresp` log them, but as NumPy arrays at full precision. Runs
//! without the GIL.

use std::path::PathBuf;

use mrbrake::sim::rig::{self, RigConfig};
use mrbrake::sysid::model_file::read_inverse_model;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(rig_characterize, m)?)?;
    m.add_function(wrap_pyfunction!(rig_freqresp, m)?)?;
    Ok(())
}

/// The rig configuration from a TOML file (default: the thesis rig), with `seed` overriding its
/// noise seed. Called without the GIL.
fn load_config(config: Option<&PathBuf>, seed: Option<u64>) -> PyResult<RigConfig> {
    let mut config = match config {
        Some(path) => RigConfig::read(path).map_err(error::to_py)?,
        None => RigConfig::default(),
    };
    if let Some(seed) = seed {
        config.seed = seed;
    }
    Ok(config)
}

/// Columns of samples as a dict of float64 arrays, `names[k]` for column `k`.
fn columns<'py>(
    py: Python<'py>,
    samples: &[[f64; 4]],
    names: [&str; 4],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (k, name) in names.into_iter().enumerate() {
        let column: Vec<f64> = samples.iter().map(|s| s[k]).collect();
        dict.set_item(name, column.into_pyarray(py))?;
    }
    Ok(dict)
}

/// The characterisation run of the rig: `{time_s, current_a, torque_nm, speed_rad_s}` float64
/// arrays.
#[pyfunction]
#[pyo3(signature = (config=None, seed=None))]
fn rig_characterize(
    py: Python<'_>,
    config: Option<PathBuf>,
    seed: Option<u64>,
) -> PyResult<Bound<'_, PyDict>> {
    let samples = py.detach(|| {
        rig::characterization_samples(&load_config(config.as_ref(), seed)?).map_err(error::to_py)
    })?;
    columns(py, &samples, ["time_s", "current_a", "torque_nm", "speed_rad_s"])
}

/// The frequency-response runs of the rig, one dict per test frequency: `frequency_rad_s` and
/// `{time_s, input_nm, output_nm, current_a}` float64 arrays. `model`: the inverse model (JSON)
/// that shapes the current; default the configured branches.
#[pyfunction]
#[pyo3(signature = (config=None, seed=None, model=None))]
fn rig_freqresp(
    py: Python<'_>,
    config: Option<PathBuf>,
    seed: Option<u64>,
    model: Option<PathBuf>,
) -> PyResult<Bound<'_, PyList>> {
    let runs = py.detach(|| {
        let config = load_config(config.as_ref(), seed)?;
        let model = model.as_deref().map(read_inverse_model).transpose().map_err(error::to_py)?;
        rig::frequency_response_runs(&config, model.as_ref()).map_err(error::to_py)
    })?;
    let list = PyList::empty(py);
    for (omega, samples) in runs {
        let run = columns(py, &samples, ["time_s", "input_nm", "output_nm", "current_a"])?;
        run.set_item("frequency_rad_s", omega)?;
        list.append(run)?;
    }
    Ok(list)
}
