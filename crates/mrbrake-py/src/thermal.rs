//! `mrbrake.thermal`: the brake's temperatures at a current and duty cycle and what heat does to
//! it, as `mrbrake thermal --json` (`mrbrake::design::thermal`). Runs without the GIL.

use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::thermal::{Cooling, ThermalOptions, analyze_thermal, insulation_limit_c};
use mrbrake::units::Dimension;
use pyo3::prelude::*;
use serde_json::Value;

use crate::convert::{SpecInput, json_to_py, optional, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(thermal, m)?)?;
    Ok(())
}

/// The options with the CLI's defaults; `current` is filled in from the spec (its maximum
/// current) once the spec is read.
#[allow(clippy::too_many_arguments)]
fn options(
    mesh: &str,
    duty: f64,
    period: Option<&Bound<'_, PyAny>>,
    ambient: Option<&Bound<'_, PyAny>>,
    h: Option<&Bound<'_, PyAny>>,
    emissivity: f64,
    insulation_class: &str,
    time: Option<&Bound<'_, PyAny>>,
    dt: Option<&Bound<'_, PyAny>>,
    speed: Option<&Bound<'_, PyAny>>,
    behaviour: bool,
) -> PyResult<ThermalOptions> {
    // A number is W/(m²·K), as a bare number of `--h`.
    let cooling = match h {
        Some(v) if !v.is_none() => match v.extract::<f64>() {
            Ok(h_w_per_m2k) => Cooling::Fixed { h_w_per_m2k },
            Err(_) => Cooling::parse(&v.extract::<String>()?)
                .map_err(|e| error::input(format!("h: {e}")))?,
        },
        _ => Cooling::Fixed { h_w_per_m2k: 10.0 },
    };
    Ok(ThermalOptions {
        current_a: 0.0,
        duty,
        period_s: optional(period, Dimension::Time, "period")?,
        ambient_c: quantity(ambient, "25C", Dimension::TemperatureCelsius, "ambient")?,
        cooling,
        emissivity,
        limit_c: insulation_limit_c(insulation_class)
            .map_err(|e| error::input(format!("insulation_class: {e}")))?,
        time_s: quantity(time, "2h", Dimension::Time, "time")?,
        dt_s: quantity(dt, "10s", Dimension::Time, "dt")?,
        speed_rad_s: quantity(speed, "0rad/s", Dimension::AngularVelocity, "speed")?,
        mesh: MeshLevel::parse(mesh).map_err(error::to_py)?,
        behaviour,
    })
}

/// A thermal analysis; see `python/mrbrake/__init__.py` (`thermal`).
#[pyfunction]
#[pyo3(signature = (spec=None, mesh="default", *, current=None, duty=1.0, period=None,
                    ambient=None, h=None, emissivity=0.0, insulation_class="155C", time=None,
                    dt=None, speed=None, behaviour=true))]
#[allow(clippy::too_many_arguments)]
fn thermal<'py>(
    py: Python<'py>,
    spec: Option<&Bound<'py, PyAny>>,
    mesh: &str,
    current: Option<&Bound<'py, PyAny>>,
    duty: f64,
    period: Option<&Bound<'py, PyAny>>,
    ambient: Option<&Bound<'py, PyAny>>,
    h: Option<&Bound<'py, PyAny>>,
    emissivity: f64,
    insulation_class: &str,
    time: Option<&Bound<'py, PyAny>>,
    dt: Option<&Bound<'py, PyAny>>,
    speed: Option<&Bound<'py, PyAny>>,
    behaviour: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = SpecInput::from_py(spec)?;
    let current = optional(current, Dimension::Current, "current")?;
    let mut options = options(
        mesh,
        duty,
        period,
        ambient,
        h,
        emissivity,
        insulation_class,
        time,
        dt,
        speed,
        behaviour,
    )?;
    let report = py.detach(|| -> PyResult<Value> {
        let spec = spec.load().map_err(error::to_py)?;
        options.current_a = current.unwrap_or_else(|| spec.coil.max_current.a());
        let result = analyze_thermal(&spec, &options).map_err(error::to_py)?;
        serde_json::to_value(&result).map_err(|e| error::internal(e.to_string()))
    })?;
    json_to_py(py, &report)
}
