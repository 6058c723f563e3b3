//! `mrbrake.materials`: the built-in material library (`mrbrake::materials::library`), its
//! curves as NumPy arrays and the CLI's `materials list/show --json` documents.

use mrbrake::materials::{Material, library};
use mrbrake::report::materials::{DEFAULT_B_T, DEFAULT_H_A_PER_M, list_json, show_json};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::json_to_py;
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(materials_list, m)?)?;
    m.add_function(wrap_pyfunction!(materials_get, m)?)?;
    m.add_class::<PyMaterial>()?;
    Ok(())
}

/// The library's list, as `mrbrake materials list --json`.
#[pyfunction]
fn materials_list(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let rows = library::names()
        .into_iter()
        .map(|(name, _)| library::get(name))
        .collect::<Result<Vec<_>, _>>()
        .map_err(error::to_py)?;
    json_to_py(py, &list_json(&rows))
}

/// One material by name (case-insensitive).
#[pyfunction]
fn materials_get(name: &str) -> PyResult<PyMaterial> {
    Ok(PyMaterial { material: library::get(name).map_err(error::to_py)? })
}

/// A material of the built-in library.
#[pyclass(name = "Material", module = "mrbrake.materials", frozen)]
pub struct PyMaterial {
    material: &'static Material,
}

/// Values of a float64 array of curve points `name` (in `unit`), by the library's rule
/// ([`library::check_curve_points`]: finite, not negative).
fn curve_points(values: &PyReadonlyArray1<'_, f64>, name: &str, unit: &str) -> PyResult<Vec<f64>> {
    let values = values.as_array().to_vec();
    library::check_curve_points(name, &values, unit).map_err(error::to_py)?;
    Ok(values)
}

#[pymethods]
impl PyMaterial {
    /// Name in the library.
    #[getter]
    fn name(&self) -> &str {
        &self.material.name
    }

    /// `steel`, `fluid`, `copper`, `air`, … (the CLI's `kind`).
    #[getter]
    fn kind(&self) -> &str {
        self.material.kind.as_str()
    }

    /// One-line description.
    #[getter]
    fn description(&self) -> &str {
        &self.material.description
    }

    /// Where the data come from: dict with `source`, `method`, `trust`.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.material.provenance)
    }

    /// The tabulated B-H curve as `(H (A/m), B (T))` float64 arrays, or `None` for a linear
    /// material.
    #[getter]
    fn bh_curve<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let Some(curve) = self.material.magnetic.bh_curve() else { return Ok(None) };
        let (h, b): (Vec<f64>, Vec<f64>) = curve.points().iter().copied().unzip();
        Ok(Some(PyTuple::new(py, [h.into_pyarray(py), b.into_pyarray(py)])?))
    }

    /// An MR fluid's yield-stress table as `(x, τ_y (Pa), variable)`, x in T or A/m as
    /// `variable` says; `None` for other materials.
    #[getter]
    fn yield_stress_curve<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let Some(fluid) = &self.material.fluid else { return Ok(None) };
        let ys = fluid.yield_stress();
        let (x, tau): (Vec<f64>, Vec<f64>) = ys.points().iter().copied().unzip();
        let variable = json_to_py(py, &ys.variable())?;
        Ok(Some(PyTuple::new(
            py,
            [x.into_pyarray(py).into_any(), tau.into_pyarray(py).into_any(), variable],
        )?))
    }

    /// B (T) at field strengths `h` (A/m, float64 array) from the material's magnetic law.
    fn b_of_h<'py>(
        &self,
        py: Python<'py>,
        h: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let h = curve_points(&h, "h", "A/m")?;
        Ok(h.iter().map(|&h| self.material.magnetic.b_of_h(h)).collect::<Vec<_>>().into_pyarray(py))
    }

    /// An MR fluid's yield stress τ_y (Pa) at flux densities `b` (T, float64 array).
    fn tau_y_of_b<'py>(
        &self,
        py: Python<'py>,
        b: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let Some(fluid) = &self.material.fluid else {
            return Err(error::input(format!("{} is not an MR fluid", self.material.name)));
        };
        let b = curve_points(&b, "b", "T")?;
        Ok(b.iter().map(|&b| fluid.tau_y_of_b(b)).collect::<Vec<_>>().into_pyarray(py))
    }

    /// The dict of `mrbrake materials show NAME --json` (B at `h` A/m, τ_y at `b` T; `None`: the
    /// CLI's defaults).
    #[pyo3(signature = (b=None, h=None))]
    fn to_dict<'py>(
        &self,
        py: Python<'py>,
        b: Option<PyReadonlyArray1<'_, f64>>,
        h: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let b = b.map_or(Ok(DEFAULT_B_T.to_vec()), |b| curve_points(&b, "b", "T"))?;
        let h = h.map_or(Ok(DEFAULT_H_A_PER_M.to_vec()), |h| curve_points(&h, "h", "A/m"))?;
        json_to_py(py, &show_json(self.material, &b, &h))
    }

    fn __repr__(&self) -> String {
        format!("<mrbrake.materials.Material '{}' ({})>", self.material.name, self.kind())
    }
}
