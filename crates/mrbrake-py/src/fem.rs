//! `mrbrake.fem.solve`: a problem file of `mrbrake fem solve` (axisymmetric magnetostatics, its
//! transient or harmonic variants, or `physics = "heat"`), solved by the library without the GIL;
//! the report is the CLI's `--json`, the field NumPy arrays.

use std::path::{Path, PathBuf};

use mrbrake::heat::problem_file::{is_heat_file, solve_file as solve_heat_file};
use mrbrake::magnetics::ElementOrder;
use mrbrake::magnetics::problem_file::solve_file_with_order;
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

/// The mesh and the solved nodal or element values of a problem, as plain data.
struct Fields {
    nodes: Vec<[f64; 2]>,
    triangles: Vec<[usize; 3]>,
    /// |B| per triangle (T) for magnetostatics, temperature per node (°C) for heat.
    values: Vec<f64>,
    /// Flux function per node (Wb/rad), magnetostatics only.
    flux_function: Option<Vec<f64>>,
}

/// Solves the magnetostatic problem file at `path`.
fn solve_magnetic(
    path: &Path,
    order: Option<ElementOrder>,
) -> PyResult<(serde_json::Value, Fields, &'static str)> {
    let (report, solver, solution) = solve_file_with_order(path, order).map_err(error::to_py)?;
    let snapshot = solver.field_snapshot(&solution);
    let fields = Fields {
        nodes: snapshot.nodes,
        triangles: snapshot.triangles,
        values: snapshot.element_b_abs_t,
        flux_function: Some(snapshot.flux_function_wb),
    };
    Ok((serde_json::to_value(&report).map_err(error::internal)?, fields, "magnetostatic"))
}

/// Solves the heat problem file at `path`.
fn solve_heat(
    path: &Path,
    order: Option<ElementOrder>,
) -> PyResult<(serde_json::Value, Fields, &'static str)> {
    let (report, solver, temperature) = solve_heat_file(path, order).map_err(error::to_py)?;
    let mesh = solver.problem().mesh.as_ref();
    let celsius = temperature[..mesh.nodes.len()].iter().map(|&t| mrbrake::heat::celsius(t));
    let fields = Fields {
        nodes: mesh.nodes.clone(),
        triangles: mesh.triangles.clone(),
        values: celsius.collect(),
        flux_function: None,
    };
    Ok((serde_json::to_value(&report).map_err(error::internal)?, fields, "heat"))
}

/// Solves a problem file; `order` (1 or 2) replaces the file's element order.
#[pyfunction]
#[pyo3(signature = (problem, order=None))]
fn fem_solve(py: Python<'_>, problem: PathBuf, order: Option<u8>) -> PyResult<PyFemSolution> {
    let order = order
        .map(|o| {
            ElementOrder::from_degree(o.into())
                .ok_or_else(|| error::input(format!("order must be 1 or 2, got {o}")))
        })
        .transpose()?;
    let (report, fields, physics) = py.detach(|| {
        let heat = std::fs::read_to_string(&problem).is_ok_and(|text| is_heat_file(&text));
        if heat { solve_heat(&problem, order) } else { solve_magnetic(&problem, order) }
    })?;
    Ok(PyFemSolution { report, fields, physics })
}

/// The result of `mrbrake.fem.solve`.
#[pyclass(name = "FemSolution", module = "mrbrake.fem", frozen)]
pub struct PyFemSolution {
    report: serde_json::Value,
    fields: Fields,
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
        self.fields.flux_function.clone().map(|psi| psi.into_pyarray(py))
    }
}
