//! `mrbrake.fem.solve`: a problem file of `mrbrake fem solve` (axisymmetric magnetostatics, its
//! transient or harmonic variants, or `physics = "heat"`), solved by the library without the GIL;
//! the report is the CLI's `--json`, the field NumPy arrays.

use std::path::PathBuf;

use mrbrake::fem::discretisation::dofs::ElementOrder;
use mrbrake::problem_file::{self, ProblemField};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{json_to_py, mesh_arrays};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fem_solve, m)?)?;
    m.add_class::<PyFemSolution>()?;
    Ok(())
}

/// Solves a problem file by its physics (`mrbrake::problem_file::solve`); `order` (1 or 2)
/// replaces the file's element order.
#[pyfunction]
#[pyo3(signature = (problem, order=None))]
fn fem_solve(py: Python<'_>, problem: PathBuf, order: Option<u8>) -> PyResult<PyFemSolution> {
    let order =
        order.map(|o| ElementOrder::try_from(i64::from(o))).transpose().map_err(error::to_py)?;
    py.detach(|| {
        let solved = problem_file::solve(&problem, order).map_err(error::to_py)?;
        let report = serde_json::to_value(solved.report()).map_err(error::internal)?;
        Ok(PyFemSolution { report, fields: solved.field(), physics: solved.physics().name() })
    })
}

/// The result of `mrbrake.fem.solve`.
#[pyclass(name = "FemSolution", module = "mrbrake.fem", frozen)]
pub struct PyFemSolution {
    report: serde_json::Value,
    fields: ProblemField,
    physics: &'static str,
}

#[pymethods]
impl PyFemSolution {
    /// `"magnetostatic"` or `"heat"`.
    #[getter]
    fn physics(&self) -> &str {
        self.physics
    }

    /// The dict of `mrbrake fem solve PROBLEM --json` (probes, region results, timings, …).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.report)
    }

    /// `(nodes (N, 2) [r, z] in m, triangles (M, 3) int64, values)`: |B| per triangle (T) for
    /// magnetostatics, the temperature per node (°C) for heat.
    fn field<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let f = &self.fields;
        mesh_arrays(py, &f.nodes, &f.triangles, f.values.clone().into_pyarray(py).into_any())
    }

    /// The flux function ψ = r·A_phi per node (Wb/rad) of a magnetostatic solution; `None` for
    /// heat.
    fn flux_function<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.fields.flux_function_wb.clone().map(|psi| psi.into_pyarray(py))
    }
}
