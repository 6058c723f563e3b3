//! The pages of `mrbrake report` (and `mrbrake.report` in Python) from what a front end parsed:
//! one place that runs the analyses a page needs and hands their results to [`design`],
//! [`study`] and [`characterization`], so the CLI and the Python package write the same file.
//!
//! Brief overview: [`DesignPageRequest::page`] runs the static analysis (and, when asked, the
//! response and thermal analyses with their commands' defaults) and composes the design page;
//! [`study_page`] reads a results store and the problem whose objectives define its front (the
//! given file, else the one the store records, else [`DEFAULT_OBJECTIVES`]);
//! [`characterization_page`] composes the page of a characterisation the caller ran (the caller
//! runs it, so its option errors can be named by the caller's flags or keywords). A [`Page`]
//! carries the warnings and notes a front end shows beside the file.
//!
//! [`design`]: super::design
//! [`study`]: super::study
//! [`characterization`]: super::characterization

use std::path::Path;

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_explore::problem::{Objective, OptimizationProblem};
use mrbrake_store::Store;

use super::Section;
use super::characterization::CharacterizationPage;
use super::design::DesignReport;
use super::study::{DEFAULT_OBJECTIVES, StudyReport};
use crate::ReportError;
use crate::identification::CharacterizationReport;
use crate::uncertainty::document::UncertaintyDocument;

/// A composed page and what the front end tells the user beside it.
#[derive(Debug, Clone)]
pub struct Page {
    /// The self-contained HTML file's text.
    pub html: String,
    /// Warnings of the analyses and notes of the problem, one line each.
    pub warnings: Vec<String>,
}

/// The design page of a spec.
#[derive(Debug)]
pub struct DesignPageRequest<'a> {
    /// The parsed spec.
    pub spec: &'a BrakeSpec,
    /// Its TOML text (shown on the page).
    pub spec_text: &'a str,
    /// Where it comes from, for the page (a path or "embedded default").
    pub source: &'a str,
    /// The embedded thesis brake: compare with the thesis's published values.
    pub thesis_comparison: bool,
    /// The static analysis (mesh, order, points, speed, temperature).
    pub options: AnalysisOptions,
    /// Add the predicted dynamics (`mrbrake response` with its defaults on the options' mesh).
    pub response: bool,
    /// Add the heat section (`mrbrake thermal` with its defaults at the maximum current).
    pub thermal: bool,
    /// Add the uncertainty section of this propagation, read from the named file.
    pub uncertainty: Option<(&'a UncertaintyDocument, &'a Path)>,
}

impl DesignPageRequest<'_> {
    /// Runs the analyses and composes the page.
    pub fn page(&self) -> Result<Page, ReportError> {
        let (analysis, field) =
            AnalysisRequest::of(self.spec).options(self.options).run_with_field()?;
        let geometry = mrbrake_design::geometry::build(self.spec)?;
        let report = DesignReport {
            analysis: &analysis,
            field: &field,
            geometry: &geometry,
            spec_text: self.spec_text,
            source: self.source,
            thesis_comparison: self.thesis_comparison,
            extra_sections: self.extra_sections(self.options.mesh)?,
        };
        Ok(Page { html: report.html()?, warnings: analysis.warnings.clone() })
    }

    /// The sections beside the static one, in the page's order: response, heat, uncertainty.
    fn extra_sections(&self, mesh: MeshLevel) -> Result<Vec<Section>, ReportError> {
        let mut sections = Vec::new();
        if self.response {
            let mut options =
                mrbrake_design::response::ResponseOptions { mesh, ..Default::default() };
            // The eddy-current map at the instant `mrbrake response --plot-dir` draws by default.
            options.eddy_at_s = Some(options.default_eddy_at_s());
            let r = mrbrake_design::response::response(self.spec, &options)?;
            sections.push(super::response::section(&r, self.thesis_comparison)?);
        }
        if self.thermal {
            let options = mrbrake_design::thermal::ThermalOptions {
                mesh,
                current_a: self.spec.coil.max_current.a(),
                behaviour: true,
                ..Default::default()
            };
            let (r, field) =
                mrbrake_design::thermal::analyze_thermal_with_field(self.spec, &options)?;
            sections.push(super::thermal::section(&r, &field)?);
        }
        if let Some((doc, path)) = self.uncertainty {
            let measured = self.thesis_comparison.then(crate::uncertainty::plots::thesis_prototype);
            let source = format!("{} (mrbrake uncertainty --json)", path.display());
            sections.push(super::uncertainty::section(doc, &source, measured.as_ref())?);
        }
        Ok(sections)
    }
}

/// The study page of `store`, with the objectives of `problem`, else of the problem the store
/// records, else the default pair.
pub fn study_page(store: &Path, problem: Option<&Path>) -> Result<Page, ReportError> {
    let opened = Store::open_read_only(store)?;
    let records = mrbrake_explore::stored::read_records(&opened)?;
    let recorded = opened.meta("problem")?;
    let problem = match (problem, recorded) {
        (Some(path), _) => {
            Some((OptimizationProblem::from_path(path)?, path.display().to_string()))
        }
        (None, Some(text)) => {
            let origin = format!("{} (problem recorded in the store)", store.display());
            let parsed = OptimizationProblem::from_toml_str(&text, Path::new(&origin))?;
            Some((parsed, "recorded in the store".into()))
        }
        (None, None) => None,
    };
    let warnings: Vec<String> =
        problem.iter().flat_map(|(p, _)| &p.notes).map(ToString::to_string).collect();
    let report = match problem {
        Some((p, source)) => StudyReport {
            store,
            records: &records,
            bounds: Some(p.variables.iter().map(|v| (v.name.clone(), v.min, v.max)).collect()),
            objectives: p.objectives,
            constraints: p.constraints,
            objectives_source: format!("problem {source}"),
            hypervolume_reference: p.hypervolume_reference,
        },
        None => StudyReport {
            store,
            records: &records,
            bounds: None,
            objectives: DEFAULT_OBJECTIVES
                .iter()
                .map(|&(metric, goal)| Objective { metric: metric.into(), goal })
                .collect(),
            constraints: Vec::new(),
            objectives_source: "no problem recorded: the default pair".into(),
            hypervolume_reference: None,
        },
    };
    Ok(Page { html: report.html()?, warnings })
}

/// The characterisation page of a run of `mrbrake_sysid::request` on the log at `log`.
pub fn characterization_page(
    run: &mrbrake_sysid::request::Characterized,
    log: &Path,
) -> Result<String, ReportError> {
    let report = CharacterizationReport {
        characterization: &run.characterization,
        log,
        samples: run.log.len(),
        sample_rate_hz: run.log.mean_sample_rate_hz(),
    };
    let page = CharacterizationPage {
        report,
        current_a: run.current_a(),
        torque_nm: run.torque_nm(),
        frequency: run.transfer_function.as_ref(),
    };
    page.html()
}
