//! `mrbrake.sysid`: identification on NumPy arrays — the hysteresis characterisation, one
//! sinusoidal test's frequency-response point and transfer-function estimation, the library's
//! `mrbrake::sysid` functions without the GIL. Inputs are borrowed read-only from the arrays
//! (contiguous float64; the Python wrapper makes other arrays so, the one copy).

use std::path::Path;

use mrbrake::report::identification::CharacterizationReport;
use mrbrake::sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake::sysid::frd::{Frd, FrequencyPoint};
use mrbrake::sysid::freqresp::{FreqRespOptions, analyse_test};
use mrbrake::sysid::log::{check_columns, mean_sample_rate_hz};
use mrbrake::sysid::tfest::{TfestOptions, TfestResult, Weighting, tfest};
use numpy::{Complex64, IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::json_to_py;
use crate::error;

/// What the arrays are called in messages (the CLI names the log file there).
const ARRAYS: &str = "<arrays>";

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sysid_characterize, m)?)?;
    m.add_function(wrap_pyfunction!(sysid_freqresp, m)?)?;
    m.add_function(wrap_pyfunction!(sysid_tfest, m)?)?;
    m.add_class::<PyTfestFit>()?;
    Ok(())
}

/// The contiguous data of a read-only array (no copy).
fn slice<'a>(array: &'a PyReadonlyArray1<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    array.as_slice().map_err(|_| error::input(format!("{name}: the array must be contiguous")))
}

/// The characterisation of a repeated-ramp log; returns the dict of `mrbrake characterize
/// --json` (`log` is `"<arrays>"`).
#[pyfunction]
#[pyo3(signature = (
    time,
    current,
    torque,
    order = mrbrake::sysid::characterize::DEFAULT_ORDER,
    bins = mrbrake::sysid::characterize::DEFAULT_BINS
))]
fn sysid_characterize<'py>(
    py: Python<'py>,
    time: PyReadonlyArray1<'py, f64>,
    current: PyReadonlyArray1<'py, f64>,
    torque: PyReadonlyArray1<'py, f64>,
    order: usize,
    bins: usize,
) -> PyResult<Bound<'py, PyAny>> {
    // The library's rules, named by the keywords (`order`, `bins`) the binding shares with it.
    let options = CharacterizeOptions { order, bins };
    options.check().map_err(error::to_py)?;
    let (t, i, tau) =
        (slice(&time, "time")?, slice(&current, "current")?, slice(&torque, "torque")?);
    let source = Path::new(ARRAYS);
    let characterization = py
        .detach(|| {
            check_columns(
                source,
                ("time", t),
                &[("current", i), ("torque", tau)],
                2 * (order + 1),
            )?;
            characterize(i, tau, options)
        })
        .map_err(error::to_py)?;
    let report = CharacterizationReport {
        characterization: &characterization,
        log: source,
        samples: t.len(),
        sample_rate_hz: mean_sample_rate_hz(t),
    };
    json_to_py(py, &report.json().map_err(error::internal)?)
}

/// One frequency-response point from a sinusoidal test at `omega` rad/s: gain and phase of
/// `output` against `input` by sine fits, tracking error; the dict of one point of `mrbrake
/// freqresp --json`.
#[pyfunction]
#[pyo3(signature = (time, input, output, omega, discard_periods=1.0, settle=0.5))]
fn sysid_freqresp<'py>(
    py: Python<'py>,
    time: PyReadonlyArray1<'py, f64>,
    input: PyReadonlyArray1<'py, f64>,
    output: PyReadonlyArray1<'py, f64>,
    omega: f64,
    discard_periods: f64,
    settle: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (t, u, y) = (slice(&time, "time")?, slice(&input, "input")?, slice(&output, "output")?);
    let options = FreqRespOptions {
        time_col: "time".into(),
        input_col: "input".into(),
        output_col: "output".into(),
        discard_periods,
        settle_s: settle,
        ..FreqRespOptions::default()
    };
    options.check().map_err(error::to_py)?;
    let source = Path::new(ARRAYS);
    let point = py
        .detach(|| {
            check_columns(source, ("time", t), &[("input", u), ("output", y)], 4)?;
            analyse_test(source, omega, t, u, y, &options)
        })
        .map_err(error::to_py)?;
    json_to_py(py, &point)
}

/// A transfer function fitted to frequency-response data (`response` complex, at `omega` rad/s).
#[pyfunction]
#[pyo3(signature = (omega, response, poles, zeros=0, weighting="uniform", delay=0.0, weight=None))]
fn sysid_tfest(
    py: Python<'_>,
    omega: PyReadonlyArray1<'_, f64>,
    response: PyReadonlyArray1<'_, Complex64>,
    poles: usize,
    zeros: usize,
    weighting: &str,
    delay: f64,
    weight: Option<PyReadonlyArray1<'_, f64>>,
) -> PyResult<PyTfestFit> {
    let mut options = TfestOptions::new(poles, zeros);
    options.delay_s = delay;
    options.weighting = match weighting {
        "uniform" => Weighting::Uniform,
        "relative" => Weighting::InverseMagnitude,
        other => {
            return Err(error::input(format!(
                "weighting '{other}' is not one of uniform, relative"
            )));
        }
    };
    options.check().map_err(error::to_py)?;
    let (omega, response) = (omega.as_array(), response.as_array());
    if omega.len() != response.len() {
        return Err(error::input(format!(
            "omega and response have {} and {} values: one response per frequency",
            omega.len(),
            response.len()
        )));
    }
    let points = omega.iter().zip(response).map(|(w, g)| FrequencyPoint::new(*w, *g)).collect();
    let frd = Frd { weight: weight.map(|w| w.as_array().to_vec()), ..Frd::new(points) };
    let fit = py.detach(|| tfest(&frd, &options)).map_err(error::to_py)?;
    Ok(PyTfestFit { fit })
}

/// The result of `mrbrake.sysid.tfest`.
#[pyclass(name = "TransferFunctionFit", module = "mrbrake.sysid", frozen)]
pub struct PyTfestFit {
    fit: TfestResult,
}

#[pymethods]
impl PyTfestFit {
    /// Numerator coefficients, highest power of s first (float64).
    #[getter]
    fn numerator<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.fit.model.numerator.clone().into_pyarray(py)
    }

    /// Denominator coefficients, highest power of s first, constant term 1 (float64).
    #[getter]
    fn denominator<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.fit.model.denominator.clone().into_pyarray(py)
    }

    /// Input delay (s) removed before fitting.
    #[getter]
    fn delay_s(&self) -> f64 {
        self.fit.delay_s
    }

    /// Fit percentage on the complex response, 100·(1 − ‖G − Ĝ‖/‖G − mean G‖).
    #[getter]
    fn fit_percent(&self) -> f64 {
        self.fit.fit_percent
    }

    /// The model's response e^{−jωτ} N(jω)/D(jω) at `omega` (rad/s), complex128.
    fn response<'py>(
        &self,
        py: Python<'py>,
        omega: PyReadonlyArray1<'_, f64>,
    ) -> Bound<'py, PyArray1<Complex64>> {
        omega.as_array().iter().map(|&w| self.fit.response(w)).collect::<Vec<_>>().into_pyarray(py)
    }

    /// The dict of `mrbrake tfest --json` (poles, zeros, DC gain, bandwidth, fit, iterations).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.fit.summary().map_err(error::to_py)?)
    }

    fn __repr__(&self) -> String {
        format!(
            "<mrbrake.sysid.TransferFunctionFit num={:?} den={:?} fit={:.2} %>",
            self.fit.model.numerator, self.fit.model.denominator, self.fit.fit_percent
        )
    }
}
