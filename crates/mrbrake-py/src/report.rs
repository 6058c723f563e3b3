//! `mrbrake.report`: the self-contained HTML report of a design, a results store or a rig
//! characterisation, as `mrbrake report` writes it: the page is composed, its analyses run, by
//! `mrbrake::report::html::request`; this module parses the arguments, returns the page's text
//! and, when asked, writes it atomically. Runs without the GIL.

use std::path::{Path, PathBuf};

use mrbrake::design::analysis::{AnalysisOptions, ElementOrder};
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::BrakeSpec;
use mrbrake::report::html::request::{self, DesignPageRequest, Page};
use mrbrake::report::uncertainty::document::UncertaintyDocument;
use mrbrake::sysid::characterize::CharacterizeOptions;
use mrbrake::sysid::request::CharacterizationRequest;
use mrbrake::sysid::tfest::TfestOptions;
use mrbrake::units::Dimension;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{SpecInput, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(report, m)?)?;
    Ok(())
}

/// What the page reports: a design (with its analyses' options), a store or a rig log.
enum Subject {
    Design { spec: SpecInput, options: AnalysisOptions, response: bool, thermal: bool },
    Store { store: PathBuf, problem: Option<PathBuf> },
    Log { log: PathBuf, frd: Option<PathBuf>, order: usize, poles: usize, zeros: usize },
}

impl Subject {
    /// The page (module docs), composed without the GIL.
    fn page(self, uncertainty: Option<&Path>) -> PyResult<Page> {
        match self {
            Self::Store { store, problem } => {
                error::exists(&store)?;
                request::study_page(&store, problem.as_deref()).map_err(error::to_py)
            }
            Self::Log { log, frd, order, poles, zeros } => {
                error::exists(&log)?;
                let run = CharacterizationRequest {
                    options: CharacterizeOptions { order, ..CharacterizeOptions::default() },
                    frd,
                    tfest: TfestOptions::new(poles, zeros),
                    ..CharacterizationRequest::new(&log)
                }
                .run()
                .map_err(|e| error::to_py(e.with_field_names(&[("order", "fit_order")])))?;
                let html = request::characterization_page(&run, &log).map_err(error::to_py)?;
                Ok(Page { html, warnings: Vec::new() })
            }
            Self::Design { spec, options, response, thermal } => {
                let embedded = matches!(spec, SpecInput::Default);
                let (text, origin) = spec.text()?;
                let source = if embedded { "embedded default".to_string() } else { origin };
                let parsed = BrakeSpec::from_toml_str(&text, &source).map_err(error::to_py)?;
                let document = uncertainty.map(UncertaintyDocument::read).transpose();
                let document = document.map_err(error::to_py)?;
                let request = DesignPageRequest {
                    spec: &parsed,
                    spec_text: &text,
                    source: &source,
                    thesis_comparison: embedded,
                    options,
                    response,
                    thermal,
                    uncertainty: document.as_ref().zip(uncertainty),
                };
                request.page().map_err(error::to_py)
            }
        }
    }
}

/// The static analysis's options of a design page, checked (the library's rules).
fn analysis_options(
    mesh: &str,
    order: u8,
    points: usize,
    speed: Option<&Bound<'_, PyAny>>,
    temperature: Option<&Bound<'_, PyAny>>,
) -> PyResult<AnalysisOptions> {
    let options = AnalysisOptions {
        mesh: MeshLevel::parse(mesh).map_err(error::to_py)?,
        points,
        speed_rad_s: quantity(speed, "1rad/s", Dimension::AngularVelocity, "speed")?,
        temperature_c: quantity(temperature, "20C", Dimension::TemperatureCelsius, "temperature")?,
        order: ElementOrder::try_from(i64::from(order)).map_err(error::to_py)?,
        ..AnalysisOptions::default()
    };
    options.check().map_err(error::to_py)?;
    Ok(options)
}

/// An HTML report; see `python/mrbrake/__init__.py` (`report`). Returns `(html, warnings)`.
#[pyfunction]
#[pyo3(signature = (spec=None, output=None, *, store=None, problem=None, log=None, frd=None,
                    poles=mrbrake::sysid::request::DEFAULT_POLES,
                    zeros=mrbrake::sysid::request::DEFAULT_ZEROS,
                    fit_order=mrbrake::sysid::characterize::DEFAULT_ORDER, mesh="default",
                    order=1, points=21, speed=None, temperature=None, response=false,
                    thermal=false, uncertainty=None))]
#[allow(clippy::too_many_arguments)]
fn report<'py>(
    py: Python<'py>,
    spec: Option<&Bound<'py, PyAny>>,
    output: Option<PathBuf>,
    store: Option<PathBuf>,
    problem: Option<PathBuf>,
    log: Option<PathBuf>,
    frd: Option<PathBuf>,
    poles: usize,
    zeros: usize,
    fit_order: usize,
    mesh: &str,
    order: u8,
    points: usize,
    speed: Option<&Bound<'py, PyAny>>,
    temperature: Option<&Bound<'py, PyAny>>,
    response: bool,
    thermal: bool,
    uncertainty: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec_given = spec.is_some_and(|s| !s.is_none());
    let subject = match (store, log) {
        (Some(_), Some(_)) => return Err(error::input("store and log: give one of them")),
        (Some(_), _) | (_, Some(_)) if spec_given => {
            return Err(error::input("spec: a design report takes no store or log"));
        }
        (Some(store), None) => Subject::Store { store, problem },
        (None, Some(log)) => Subject::Log { log, frd, order: fit_order, poles, zeros },
        (None, None) => Subject::Design {
            spec: SpecInput::from_py(spec)?,
            options: analysis_options(mesh, order, points, speed, temperature)?,
            response,
            thermal,
        },
    };
    let page = py.detach(|| -> PyResult<Page> {
        let page = subject.page(uncertainty.as_deref())?;
        if let Some(path) = &output {
            mrbrake::report::write_atomic(path, page.html.as_bytes()).map_err(error::to_py)?;
        }
        Ok(page)
    })?;
    let result = PyDict::new(py);
    result.set_item("html", page.html)?;
    result.set_item("warnings", page.warnings)?;
    Ok(result)
}
