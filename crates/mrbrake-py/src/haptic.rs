//! `mrbrake.haptic.wall`: the 1-DOF haptic simulation of a hand pressing into a virtual wall
//! (`mrbrake::sim::haptic::simulate`), as `mrbrake haptic wall`: the metrics of its `--json` and
//! the time histories of its `--csv` as NumPy arrays. The simulation runs without the GIL.

use std::path::PathBuf;

use mrbrake::sim::haptic::{DeviceKind, HapticConfig, Scenario, Trace, simulate};
use mrbrake::sysid::model_file::read_inverse_model;
use mrbrake::units::Dimension;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{json_to_py, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(haptic_wall, m)?)?;
    Ok(())
}

/// The device and scenario by their CLI names; a `ValueError` lists the allowed ones.
fn kinds(device: &str, scenario: &str) -> PyResult<(DeviceKind, Scenario)> {
    let device = DeviceKind::from_name(device).ok_or_else(|| {
        let names: Vec<_> = DeviceKind::ALL.iter().map(|d| d.name()).collect();
        error::input(format!("device '{device}': expected one of {}", names.join(", ")))
    })?;
    let scenario = Scenario::from_name(scenario).ok_or_else(|| {
        let names: Vec<_> = Scenario::ALL.iter().map(|s| s.name()).collect();
        error::input(format!("scenario '{scenario}': expected one of {}", names.join(", ")))
    })?;
    Ok((device, scenario))
}

/// The time histories as a dict of float64 arrays (the columns of `haptic wall --csv`, the two
/// brakes' currents and capacities as `(N, 2)` arrays).
fn trace_dict<'py>(py: Python<'py>, trace: Trace) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let pairs = |[a, b]: [Vec<f64>; 2]| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = a.into_iter().zip(b).map(|(x, y)| vec![x, y]).collect();
        PyArray2::from_vec2(py, &rows).map_err(error::internal)
    };
    dict.set_item("current_a", pairs(trace.current_a)?)?;
    dict.set_item("capacity_nm", pairs(trace.capacity_nm)?)?;
    let columns = [
        ("time_s", trace.time_s),
        ("angle_rad", trace.angle_rad),
        ("intended_rad", trace.intended_rad),
        ("wall_rad", trace.wall_rad),
        ("actuator_torque_nm", trace.actuator_torque_nm),
        ("device_torque_nm", trace.device_torque_nm),
        ("hand_torque_nm", trace.hand_torque_nm),
        ("ideal_wall_torque_nm", trace.ideal_wall_torque_nm),
    ];
    for (name, column) in columns {
        dict.set_item(name, column.into_pyarray(py))?;
    }
    Ok(dict)
}

/// One haptic wall run; see `python/mrbrake/haptic.py` (`wall`). Returns `(metrics, trace)`.
#[pyfunction]
#[pyo3(signature = (device, *, scenario="press-withdraw", stiffness=30.0, damping=0.02,
                    duration=None, model=None))]
fn haptic_wall<'py>(
    py: Python<'py>,
    device: &str,
    scenario: &str,
    stiffness: f64,
    damping: f64,
    duration: Option<&Bound<'py, PyAny>>,
    model: Option<PathBuf>,
) -> PyResult<Bound<'py, PyTuple>> {
    let (device, scenario) = kinds(device, scenario)?;
    let mut config = HapticConfig::new(device, scenario);
    config.wall_stiffness_nm_per_rad = stiffness;
    config.wall_damping_nms_per_rad = damping;
    if duration.is_some_and(|d| !d.is_none()) {
        config.duration_s = quantity(duration, "", Dimension::Time, "duration")?;
    }
    // The ranges are the library's, named by this function's keywords.
    let keywords = [
        ("wall_stiffness_nm_per_rad", "stiffness"),
        ("wall_damping_nms_per_rad", "damping"),
        ("duration_s", "duration"),
    ];
    config.validate().map_err(|e| error::to_py(e.with_field_names(&keywords)))?;
    let run = py.detach(|| {
        if let Some(path) = &model {
            config.use_inverse_model(read_inverse_model(path).map_err(error::to_py)?);
        }
        simulate(&config, true).map_err(error::to_py)
    })?;
    let metrics = json_to_py(py, &run.metrics)?;
    let trace = run.trace.ok_or_else(|| error::internal("a recorded run without a trace"))?;
    PyTuple::new(py, [metrics, trace_dict(py, trace)?.into_any()])
}
