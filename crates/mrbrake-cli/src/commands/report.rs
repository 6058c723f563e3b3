//! `mrbrake report`: one self-contained HTML file (inline CSS and figures, no script, nothing
//! fetched) for a design (`[SPEC]`), a study (`--store`) or a characterisation (`--log`, `--frd`).
//! The pages are composed by `mrbrake::report::html`; this command parses, runs the analyses and
//! writes the file atomically.

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake::design::geometry;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::{BrakeSpec, DEFAULT_SPEC_TOML, default_spec};
use mrbrake::report::html::design::DesignReport;
use mrbrake::report::uncertainty::{document::UncertaintyDocument, plots};
use mrbrake::units::{Dimension, parse};

use super::field_flags;
use crate::error::{CommandResult, InputError};

/// Arguments of `mrbrake report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Brake specification (TOML; its keys: docs/reference/spec.md or `mrbrake schema spec
    /// --markdown`) for a design report. Omitted (and no --store or --log): the embedded thesis
    /// bidirectional brake, compared with the thesis's published values.
    #[arg(conflicts_with_all = ["store", "log"])]
    spec: Option<PathBuf>,
    /// The HTML file to write.
    #[arg(short, long, value_name = "FILE.html")]
    output: PathBuf,
    /// A study report of this results store (from `mrbrake optimize` or `mrbrake sweep`).
    #[arg(long, value_name = "STUDY.sqlite", conflicts_with = "log")]
    store: Option<PathBuf>,
    /// The optimisation problem whose objectives and constraints define the study's front.
    /// Default: the problem recorded in the store by `mrbrake optimize`.
    #[arg(long, value_name = "PROBLEM.toml", requires = "store")]
    problem: Option<PathBuf>,
    /// A characterisation report of this repeated-ramp test-rig log (CSV).
    #[arg(long, value_name = "LOG.csv")]
    log: Option<PathBuf>,
    /// Frequency-response data (CSV, from `mrbrake freqresp`) for the characterisation report's
    /// Bode diagram and fitted transfer function.
    #[arg(long, value_name = "FRD.csv", requires = "log")]
    frd: Option<PathBuf>,
    /// Poles of the fitted transfer function (with --frd).
    #[arg(long, default_value_t = mrbrake::sysid::request::DEFAULT_POLES, requires = "frd")]
    poles: usize,
    /// Zeros of the fitted transfer function (with --frd).
    #[arg(long, default_value_t = mrbrake::sysid::request::DEFAULT_ZEROS, requires = "frd")]
    zeros: usize,
    /// Polynomial order of the hysteresis branch fits (with --log).
    #[arg(long, default_value_t = mrbrake::sysid::characterize::DEFAULT_ORDER, requires = "log")]
    fit_order: usize,
    /// Mesh density of a design report: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Element order of a design report's field solution: 1 or 2.
    #[arg(long, value_name = "1|2", default_value_t = 1)]
    order: u8,
    /// Currents in a design report's torque–current sweep.
    #[arg(long, default_value_t = 21)]
    points: usize,
    /// Relative speed for the viscous torque (e.g. 1rad/s, 60rpm).
    #[arg(long, default_value = "1rad/s", allow_hyphen_values = true)]
    speed: String,
    /// Copper temperature for the coil resistance (e.g. 20C, 75C).
    #[arg(long, default_value = "20C", allow_hyphen_values = true)]
    temperature: String,
    /// Add the predicted dynamics (step response, Bode diagram: `mrbrake response` with its
    /// defaults; about half a minute more on the default mesh).
    #[arg(long, conflicts_with_all = ["store", "log"])]
    response: bool,
    /// Add the heat section (temperature map, warm-up curve, continuous current rating, hot
    /// behaviour: `mrbrake thermal` with its defaults).
    #[arg(long, conflicts_with_all = ["store", "log"])]
    thermal: bool,
    /// Add the uncertainty section (bands, torque–current band, tornado chart, Sobol' indices) of
    /// a propagation saved with `mrbrake uncertainty --json > FILE.json`.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = ["store", "log"])]
    uncertainty: Option<PathBuf>,
}

/// Runs `mrbrake report`.
pub fn run(a: ReportArgs) -> CommandResult {
    let page = if let Some(store) = &a.store {
        study::page(store, a.problem.as_deref())?
    } else if let Some(log) = &a.log {
        characterization::page(log, a.frd.as_deref(), a.fit_order, a.poles, a.zeros)?
    } else {
        design_page(&a)?
    };
    mrbrake::report::write_atomic(&a.output, page.as_bytes())?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// The design report of the spec (or the embedded default).
fn design_page(a: &ReportArgs) -> CommandResult<String> {
    let (spec, text) = match &a.spec {
        Some(path) => {
            let spec = BrakeSpec::from_path(path)?;
            let text = mrbrake::error::read::text(path, mrbrake::error::read::SETTINGS)
                .map_err(|e| InputError(format!("{}: cannot read: {e}", path.display())))?;
            (spec, text)
        }
        None => (default_spec(), DEFAULT_SPEC_TOML.to_string()),
    };
    // Read before the analysis, so a bad file costs nothing.
    let uncertainty = a.uncertainty.as_deref().map(UncertaintyDocument::read).transpose()?;
    let options = AnalysisOptions {
        mesh: MeshLevel::parse(&a.mesh).map_err(field_flags::design)?,
        points: a.points,
        speed_rad_s: parse(&a.speed, Dimension::AngularVelocity)
            .map_err(|e| InputError(format!("--speed: {e}")))?,
        temperature_c: parse(&a.temperature, Dimension::TemperatureCelsius)
            .map_err(|e| InputError(format!("--temperature: {e}")))?,
        order: super::field_flags::order(a.order)?,
        ..AnalysisOptions::default()
    };
    let (analysis, field) = AnalysisRequest::of(&spec)
        .options(options)
        .run_with_field()
        .map_err(field_flags::design)?;
    for w in &analysis.warnings {
        eprintln!("warning: {w}");
    }
    let geometry = geometry::build(&spec)?;
    let source =
        a.spec.as_ref().map_or("embedded default".to_string(), |p| p.display().to_string());
    let report = DesignReport {
        analysis: &analysis,
        field: &field,
        geometry: &geometry,
        spec_text: &text,
        source: &source,
        thesis_comparison: a.spec.is_none(),
        extra_sections: extra_sections(a, &spec, uncertainty.as_ref())?,
    };
    Ok(report.html()?)
}

/// The study report of a results store.
mod study {
    use std::path::Path;

    use mrbrake::explore::problem::{Objective, OptimizationProblem};
    use mrbrake::report::html::study::{DEFAULT_OBJECTIVES, StudyReport};
    use mrbrake::store::Store;

    use crate::error::CommandResult;

    /// The page of `store`, with the objectives of `problem`, else of the problem the store
    /// records, else the default pair.
    pub fn page(store: &Path, problem: Option<&Path>) -> CommandResult<String> {
        let opened = Store::open_read_only(store)?;
        let records = mrbrake::explore::stored::read_records(&opened)?;
        let recorded = opened.meta("problem")?;
        let problem = match (problem, recorded) {
            (Some(path), _) => {
                Some((OptimizationProblem::from_path(path)?, path.display().to_string()))
            }
            (None, Some(text)) => {
                let origin = format!("{} (problem recorded in the store)", store.display());
                Some((
                    OptimizationProblem::from_toml_str(&text, Path::new(&origin))?,
                    "recorded in the store".into(),
                ))
            }
            (None, None) => None,
        };
        for note in problem.iter().flat_map(|(p, _)| &p.notes) {
            eprintln!("note: {note}");
        }
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
        Ok(report.html()?)
    }
}

/// The characterisation report of a rig log.
mod characterization {
    use std::path::Path;

    use mrbrake::report::html::characterization::CharacterizationPage;
    use mrbrake::report::identification::CharacterizationReport;
    use mrbrake::sysid::characterize::CharacterizeOptions;
    use mrbrake::sysid::request::CharacterizationRequest;
    use mrbrake::sysid::tfest::TfestOptions;

    use crate::error::CommandResult;

    /// The page of `log` (columns `time_s`, `current_A`, `torque_Nm`, as the rig writes them) and,
    /// with `frd`, of a `poles`/`zeros` transfer function fitted to it.
    pub fn page(
        log_path: &Path,
        frd_path: Option<&Path>,
        order: usize,
        poles: usize,
        zeros: usize,
    ) -> CommandResult<String> {
        let request = CharacterizationRequest {
            options: CharacterizeOptions { order, ..CharacterizeOptions::default() },
            frd: frd_path.map(Path::to_path_buf),
            tfest: TfestOptions::new(poles, zeros),
            ..CharacterizationRequest::new(log_path)
        };
        let flags = [("order", "--fit-order"), ("poles", "--poles"), ("zeros", "--zeros")];
        let run = request.run().map_err(|e| e.with_field_names(&flags))?;
        let report = CharacterizationReport {
            characterization: &run.characterization,
            log: log_path,
            samples: run.log.len(),
            sample_rate_hz: run.log.mean_sample_rate_hz(),
        };
        let page = CharacterizationPage {
            report,
            current_a: run.current_a(),
            torque_nm: run.torque_nm(),
            frequency: run.transfer_function.as_ref(),
        };
        Ok(page.html()?)
    }
}

/// The sections of the analyses asked for beside the static one (`--response`, `--thermal`,
/// `--uncertainty`).
fn extra_sections(
    a: &ReportArgs,
    spec: &mrbrake::design::spec::BrakeSpec,
    uncertainty: Option<&UncertaintyDocument>,
) -> CommandResult<Vec<mrbrake::report::html::Section>> {
    let mut sections = Vec::new();
    if a.response {
        let mut options = mrbrake::design::response::ResponseOptions {
            mesh: MeshLevel::parse(&a.mesh).map_err(field_flags::design)?,
            ..Default::default()
        };
        // The eddy-current map at the instant `mrbrake response --plot-dir` draws by default.
        options.eddy_at_s = Some(options.default_eddy_at_s());
        let r = mrbrake::design::response::response(spec, &options)?;
        sections.push(mrbrake::report::html::response::section(&r, a.spec.is_none())?);
    }
    if a.thermal {
        let options = mrbrake::design::thermal::ThermalOptions {
            mesh: MeshLevel::parse(&a.mesh).map_err(field_flags::design)?,
            current_a: spec.coil.max_current.a(),
            behaviour: true,
            ..Default::default()
        };
        let (r, field) = mrbrake::design::thermal::analyze_thermal_with_field(spec, &options)?;
        sections.push(mrbrake::report::html::thermal::section(&r, &field)?);
    }
    if let (Some(path), Some(doc)) = (&a.uncertainty, uncertainty) {
        let measured = a.spec.is_none().then(plots::thesis_prototype);
        let source = format!("{} (mrbrake uncertainty --json)", path.display());
        let section = mrbrake::report::html::uncertainty::section(doc, &source, measured.as_ref());
        sections.push(section?);
    }
    Ok(sections)
}
