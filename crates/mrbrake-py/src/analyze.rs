//! `mrbrake.analyze`: the main job (field, torque–current curve, gaps, coil, mechanics of a
//! brake design), the library's `design::analysis::AnalysisRequest` (with the field) without the
//! GIL.

use mrbrake::design::analysis::{
    Analysis, AnalysisOptions, AnalysisRequest, CurvePoint, ElementOrder, FieldAtMaxCurrent,
};
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::units::Dimension;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{SpecInput, json_to_py, mesh_arrays, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    m.add_class::<PyAnalysis>()?;
    Ok(())
}

/// The analysis options from `analyze`'s keyword arguments (their ranges are the library's rules,
/// checked when it runs).
fn options(
    mesh: &str,
    order: u8,
    currents: Option<usize>,
    speed: Option<&Bound<'_, PyAny>>,
    seal_friction: Option<&Bound<'_, PyAny>>,
    temperature: Option<&Bound<'_, PyAny>>,
) -> PyResult<AnalysisOptions> {
    let points = currents.unwrap_or(AnalysisOptions::default().points);
    let order = ElementOrder::try_from(i64::from(order)).map_err(error::to_py)?;
    Ok(AnalysisOptions {
        mesh: MeshLevel::parse(mesh).map_err(error::to_py)?,
        points,
        speed_rad_s: quantity(speed, "1rad/s", Dimension::AngularVelocity, "speed")?,
        seal_friction_nm: quantity(seal_friction, "0Nm", Dimension::Torque, "seal_friction")?,
        temperature_c: quantity(temperature, "20C", Dimension::TemperatureCelsius, "temperature")?,
        order,
    })
}

/// Analyses a brake design; see `python/mrbrake/__init__.pyi` for the documentation.
#[pyfunction]
#[pyo3(signature = (spec=None, mesh="default", order=1, currents=None, *, speed=None,
                    seal_friction=None, temperature=None))]
fn analyze(
    py: Python<'_>,
    spec: Option<&Bound<'_, PyAny>>,
    mesh: &str,
    order: u8,
    currents: Option<usize>,
    speed: Option<&Bound<'_, PyAny>>,
    seal_friction: Option<&Bound<'_, PyAny>>,
    temperature: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyAnalysis> {
    let input = SpecInput::from_py(spec)?;
    let options = options(mesh, order, currents, speed, seal_friction, temperature)?;
    let (analysis, field) = py
        .detach(|| {
            let spec = input.load()?;
            AnalysisRequest::of(&spec).options(options).run_with_field()
        })
        // The library's `points` is the keyword `currents`.
        .map_err(|e| error::to_py(e.with_field_names(&[("points", "currents")])))?;
    Ok(PyAnalysis { analysis, field })
}

/// The result of `mrbrake.analyze` (unit 1 energised for the curve and the field).
#[pyclass(name = "Analysis", module = "mrbrake", frozen)]
pub struct PyAnalysis {
    analysis: Analysis,
    field: FieldAtMaxCurrent,
}

impl PyAnalysis {
    /// One column of the torque–current curve as a float64 array.
    fn column<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&CurvePoint) -> f64,
    ) -> Bound<'py, PyArray1<f64>> {
        self.analysis.torque_current_curve.iter().map(f).collect::<Vec<_>>().into_pyarray(py)
    }
}

#[pymethods]
impl PyAnalysis {
    /// Spec name.
    #[getter]
    fn name(&self) -> &str {
        &self.analysis.name
    }

    /// Configuration (`single-disc`, `drum`, `bidirectional`, …).
    #[getter]
    fn configuration(&self) -> &str {
        self.analysis.configuration
    }

    /// Maximum coil current (A).
    #[getter]
    fn max_current_a(&self) -> f64 {
        self.analysis.max_current_a
    }

    /// Currents of the sweep (A), float64, shape (points,).
    #[getter]
    fn current_a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.current_a)
    }

    /// Total torque at each current (N·m): yield + viscous + seal friction.
    #[getter]
    fn torque_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.torque_nm)
    }

    /// Field-dependent yield torque at each current (N·m), local Bingham integration.
    #[getter]
    fn yield_torque_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.yield_torque_nm)
    }

    /// The thesis method's torque (mean gap |B|, closed form) at each current (N·m).
    #[getter]
    fn thesis_formula_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.thesis_formula_nm)
    }

    /// Mean |B| over the gaps of direction 1 at each current (T).
    #[getter]
    fn mean_b_t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.mean_b_t)
    }

    /// Flux linkage of the coil at each current (Wb).
    #[getter]
    fn flux_linkage_wb<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.column(py, |p| p.flux_linkage_wb)
    }

    /// Torque summary (dict, the CLI's `torque` keys).
    #[getter]
    fn torque<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.torque)
    }

    /// Per-gap results at the maximum current (list of dicts, the CLI's `gaps`).
    #[getter]
    fn gaps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.gaps)
    }

    /// Coil figures (dict, the CLI's `coil` keys: turns, resistance, power, inductance, …).
    #[getter]
    fn coil<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.coil)
    }

    /// Mechanical figures (dict, the CLI's `mechanics`: mass, volume, inertia, torque density).
    #[getter]
    fn mechanics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.mechanics)
    }

    /// Mesh size (dict: nodes, elements, order, unknowns).
    #[getter]
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.mesh)
    }

    /// Wall-clock time of each stage (dict, seconds: mesh, setup, solve, post, total).
    #[getter]
    fn timings_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis.timings_s)
    }

    /// Spec warnings (e.g. a current above the wire's rating).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.analysis.warnings.clone()
    }

    /// The whole result as a dict with the keys of `mrbrake analyze --json`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.analysis)
    }

    /// The field at the maximum current for matplotlib's `tripcolor`:
    /// `(nodes (N, 2) float64 [r, z] in m, triangles (M, 3) int64, |B| (M,) float64 in T per
    /// triangle)`.
    fn field<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let f = &self.field;
        mesh_arrays(py, &f.nodes, &f.triangles, f.b_abs_t.clone().into_pyarray(py).into_any())
    }

    /// The flux function ψ = r·A_phi at the nodes (Wb/rad, float64, shape (N,)): its level lines
    /// are the flux lines (matplotlib's `tricontour`).
    fn flux_function<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.field.flux_function_wb.clone().into_pyarray(py)
    }

    /// Region of every triangle: `(tags (M,) int64, {tag: (part name, material)})`.
    fn regions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let tags: Vec<i64> = self.field.region_tags.iter().map(|&t| i64::from(t)).collect();
        let names = pyo3::types::PyDict::new(py);
        for r in &self.field.regions {
            names.set_item(r.tag, (r.name.as_str(), r.material.as_str()))?;
        }
        PyTuple::new(py, [tags.into_pyarray(py).into_any(), names.into_any()])
    }

    fn __repr__(&self) -> String {
        let a = &self.analysis;
        format!(
            "<mrbrake.Analysis '{}' ({}): {:.4} N·m at {} A, {:.4} N·m off-state>",
            a.name,
            a.configuration,
            a.torque.at_max_current_nm,
            a.max_current_a,
            a.torque.off_state_nm
        )
    }
}
