//! Conversions between Python values and the library's inputs and outputs: JSON documents to
//! Python objects (the CLI's `--json` keys unchanged), brake specs from a path, TOML text or a
//! dict, quantities from a number in SI or a string with a unit.

use std::path::PathBuf;

use mrbrake::design::spec::{BrakeSpec, DEFAULT_SPEC_TOML, default_spec};
use mrbrake::units::{Dimension, parse};
use numpy::PyArray2;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};
use serde::Serialize;

use crate::error;

/// A JSON document as Python objects (dicts, lists, floats, ints, str, None), through Python's
/// own `json` module: exactly what `json.loads` of the CLI's `--json` output gives.
pub fn json_to_py<'py>(py: Python<'py>, value: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(error::internal)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A Python object as a JSON value (through `json.dumps`; non-JSON values are a `ValueError`).
pub fn py_to_json(object: &Bound<'_, PyAny>) -> PyResult<serde_json::Value> {
    let text: String = object
        .py()
        .import("json")?
        .call_method1("dumps", (object,))
        .map_err(|e| error::input(format!("not representable as JSON/TOML: {e}")))?
        .extract()?;
    serde_json::from_str(&text).map_err(error::internal)
}

/// Where a spec comes from, read without the GIL.
pub enum SpecInput {
    /// The embedded thesis brake.
    Default,
    /// A file.
    Path(PathBuf),
    /// TOML text and the name it goes by in messages.
    Text(String, &'static str),
}

impl SpecInput {
    /// `None`, a path (`str` without `=` or a newline, or `os.PathLike`), TOML text, or a dict
    /// with the TOML file's tables.
    pub fn from_py(spec: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let Some(spec) = spec else { return Ok(Self::Default) };
        if spec.is_none() {
            return Ok(Self::Default);
        }
        if let Ok(dict) = spec.cast::<PyDict>() {
            let value = py_to_json(dict.as_any())?;
            let text = toml::to_string(&value)
                .map_err(|e| error::input(format!("spec dict: not a TOML document: {e}")))?;
            return Ok(Self::Text(text, "<dict>"));
        }
        if let Ok(text) = spec.cast::<PyString>() {
            let text = text.to_cow()?;
            if text.contains('\n') || text.contains('=') {
                return Ok(Self::Text(text.to_string(), "<string>"));
            }
            return Ok(Self::Path(PathBuf::from(text.as_ref())));
        }
        if spec.hasattr("__fspath__")? {
            return Ok(Self::Path(spec.extract::<PathBuf>()?));
        }
        Err(error::input(format!(
            "spec must be None, a path, TOML text or a dict, got {}",
            spec.get_type().name()?
        )))
    }

    /// The spec's TOML text and the name it goes by in messages (a study plans from the text).
    /// A file that cannot be read is an `OSError` naming it.
    pub fn text(self) -> PyResult<(String, String)> {
        Ok(match self {
            Self::Default => {
                (DEFAULT_SPEC_TOML.to_string(), "thesis-bidirectional.toml (embedded)".into())
            }
            Self::Path(path) => (
                mrbrake::error::read::text(&path, mrbrake::error::read::SETTINGS).map_err(|e| {
                    let message = format!("cannot read the spec {}: {e}", path.display());
                    if e.kind() == std::io::ErrorKind::NotFound {
                        pyo3::exceptions::PyFileNotFoundError::new_err(message)
                    } else {
                        PyOSError::new_err(message)
                    }
                })?,
                path.display().to_string(),
            ),
            Self::Text(text, origin) => (text, origin.to_string()),
        })
    }

    /// The parsed spec (file reading and parsing happen here, without the GIL).
    pub fn load(self) -> Result<BrakeSpec, mrbrake::design::DesignError> {
        match self {
            Self::Default => Ok(default_spec()),
            Self::Path(path) => BrakeSpec::from_path(&path),
            Self::Text(text, origin) => BrakeSpec::from_toml_str(&text, origin),
        }
    }
}

/// A quantity given as a number (already SI) or a string with a unit (`"60rpm"`, `"75C"`);
/// `None` takes `default` (a string with its unit). `name` prefixes a parse error.
pub fn quantity(
    value: Option<&Bound<'_, PyAny>>,
    default: &str,
    dimension: Dimension,
    name: &str,
) -> PyResult<f64> {
    let text = match value {
        None => default.to_string(),
        Some(v) if v.is_none() => default.to_string(),
        Some(v) => match v.extract::<f64>() {
            Ok(number) => return Ok(number),
            Err(_) => v.extract::<String>().map_err(|_| {
                error::input(format!("{name}: expected a number in SI or a string with a unit"))
            })?,
        },
    };
    parse(&text, dimension).map_err(|e| error::input(format!("{name}: {e}")))
}

/// An optional [`quantity`]: absent or `None` stays `None`.
pub fn optional(
    value: Option<&Bound<'_, PyAny>>,
    dimension: Dimension,
    name: &str,
) -> PyResult<Option<f64>> {
    match value {
        Some(v) if !v.is_none() => quantity(Some(v), "", dimension, name).map(Some),
        _ => Ok(None),
    }
}

/// `(nodes (N, 2) float64, triangles (M, 3) int64, values)`: a mesh for matplotlib's `tripcolor`
/// with the values drawn on it.
pub fn mesh_arrays<'py>(
    py: Python<'py>,
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    values: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyTuple>> {
    let nodes: Vec<Vec<f64>> = nodes.iter().map(|n| n.to_vec()).collect();
    let triangles: Vec<Vec<i64>> =
        triangles.iter().map(|t| t.iter().map(|&i| i as i64).collect()).collect();
    let nodes = PyArray2::from_vec2(py, &nodes).map_err(error::internal)?;
    let triangles = PyArray2::from_vec2(py, &triangles).map_err(error::internal)?;
    PyTuple::new(py, [nodes.into_any(), triangles.into_any(), values])
}
