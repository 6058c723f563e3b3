//! `mrbrake.calibrate`: spec fields fitted to a rig log's loop, as the CLI's `mrbrake calibrate`
//! runs it (`mrbrake::explore::calibrate`), returning the same `--json` document
//! (`mrbrake::report::calibration`) and, on request, the calibrated spec's text. Runs without the
//! GIL.

use std::path::PathBuf;

use mrbrake::explore::calibrate::{CalibrationRequest, DEFAULT_POINTS, run};
use mrbrake::explore::metrics::StudyMetrics;
use mrbrake::explore::problem::known_metric;
use mrbrake::uq::calibration::CalibrationOptions;
use pyo3::prelude::*;
use serde_json::Value;

use crate::convert::{SpecInput, json_to_py};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    Ok(())
}

/// A calibration; see `python/mrbrake/__init__.py` (`calibrate`). Returns the JSON document
/// with the calibrated spec's text under `calibrated_spec`.
#[pyfunction]
#[pyo3(signature = (spec, log, parameters, overrides, *, frd=None, points=DEFAULT_POINTS,
                    max_evaluations=120, jobs=0, mesh="default", order=1, speed=None,
                    record=Vec::new()))]
#[allow(clippy::too_many_arguments)]
fn calibrate<'py>(
    py: Python<'py>,
    spec: Option<&Bound<'py, PyAny>>,
    log: PathBuf,
    parameters: Vec<String>,
    overrides: Vec<(String, String)>,
    frd: Option<PathBuf>,
    points: usize,
    max_evaluations: usize,
    jobs: usize,
    mesh: &str,
    order: u8,
    speed: Option<&Bound<'py, PyAny>>,
    record: Vec<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = SpecInput::from_py(spec)?;
    let mut settings = crate::study::settings(mesh, order, speed)?;
    let mut asked = Vec::with_capacity(record.len());
    for name in &record {
        asked.push(known_metric(name).map_err(error::to_py)?.name);
    }
    settings.study = StudyMetrics::new(asked, &[], Default::default(), Default::default());
    let options = CalibrationOptions { max_evaluations, ..CalibrationOptions::default() };
    let report = py.detach(|| -> PyResult<Value> {
        let (spec_toml, spec_origin) = spec.text()?;
        let request = CalibrationRequest {
            spec_toml,
            spec_origin,
            overrides,
            parameters,
            log,
            frd,
            points,
            settings,
            jobs,
            options,
        };
        let result = run(&request).map_err(error::to_py)?;
        let mut json = mrbrake::report::calibration::json(&result);
        json["calibrated_spec"] = Value::from(result.calibrated_spec.clone());
        Ok(json)
    })?;
    json_to_py(py, &report)
}
