//! `mrbrake.response`: the predicted dynamics of a brake design, as `mrbrake response --json`
//! (`mrbrake::design::response`): step responses per direction and the small-signal frequency
//! response. Runs without the GIL.

use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::response::{ResponseDrive, ResponseOptions, parse_step, response};
use mrbrake::units::Dimension;
use pyo3::prelude::*;
use serde_json::Value;

use crate::convert::{SpecInput, json_to_py, optional, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(response_of, m)?)?;
    Ok(())
}

/// A response prediction; see `python/mrbrake/__init__.py` (`response`).
#[pyfunction]
#[pyo3(name = "response", signature = (spec=None, mesh="default", *, drive="current",
                    duration=None, step=None, bias=None, fluid_lag=None, conductivity=None))]
#[allow(clippy::too_many_arguments)]
fn response_of<'py>(
    py: Python<'py>,
    spec: Option<&Bound<'py, PyAny>>,
    mesh: &str,
    drive: &str,
    duration: Option<&Bound<'py, PyAny>>,
    step: Option<&str>,
    bias: Option<&Bound<'py, PyAny>>,
    fluid_lag: Option<&Bound<'py, PyAny>>,
    conductivity: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = SpecInput::from_py(spec)?;
    let mut options = ResponseOptions {
        mesh: MeshLevel::parse(mesh).map_err(error::to_py)?,
        drive: ResponseDrive::parse(drive).map_err(|e| error::input(format!("drive: {e}")))?,
        duration_s: quantity(duration, "100ms", Dimension::Time, "duration")?,
        bias_a: optional(bias, Dimension::Current, "bias")?,
        flux_path_conductivity_s_per_m: optional(
            conductivity,
            Dimension::Conductivity,
            "conductivity",
        )?,
        ..ResponseOptions::default()
    };
    if let Some(lag) = optional(fluid_lag, Dimension::Time, "fluid_lag")? {
        options.fluid_lag_s = lag;
    }
    if let Some(text) = step {
        let (from, to) = parse_step(text).map_err(|e| error::input(format!("step: {e}")))?;
        options.step_from_a = from;
        options.step_to_a = Some(to);
    }
    let report = py.detach(|| -> PyResult<Value> {
        let spec = spec.load().map_err(error::to_py)?;
        let r = response(&spec, &options).map_err(error::to_py)?;
        serde_json::to_value(&r).map_err(|e| error::internal(e.to_string()))
    })?;
    json_to_py(py, &report)
}
