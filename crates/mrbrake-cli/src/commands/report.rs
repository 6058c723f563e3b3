//! `mrbrake report`: one self-contained HTML file (inline CSS and figures, no script, nothing
//! fetched) for a design (`[SPEC]`), a study (`--store`) or a characterisation (`--log`, `--frd`).
//! The pages are composed, their analyses run, by `mrbrake::report::html::request` (as for
//! Python's `mrbrake.report`); this command parses and writes the file atomically.

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::analysis::AnalysisOptions;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::{BrakeSpec, DEFAULT_SPEC_TOML, default_spec};
use mrbrake::report::html::request;
use mrbrake::report::uncertainty::document::UncertaintyDocument;
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
        request::study_page(store, a.problem.as_deref())?
    } else if let Some(log) = &a.log {
        let html = characterization_page(log, a.frd.as_deref(), a.fit_order, a.poles, a.zeros)?;
        request::Page { html, warnings: Vec::new() }
    } else {
        design_page(&a)?
    };
    for w in &page.warnings {
        let label = if a.store.is_some() { "note" } else { "warning" };
        eprintln!("{label}: {w}");
    }
    mrbrake::report::write_atomic(&a.output, page.html.as_bytes())?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// The design report of the spec (or the embedded default).
fn design_page(a: &ReportArgs) -> CommandResult<request::Page> {
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
    // The options' range errors named by their flags, before any analysis.
    options.check().map_err(field_flags::design)?;
    let source =
        a.spec.as_ref().map_or("embedded default".to_string(), |p| p.display().to_string());
    let request = request::DesignPageRequest {
        spec: &spec,
        spec_text: &text,
        source: &source,
        thesis_comparison: a.spec.is_none(),
        options,
        response: a.response,
        thermal: a.thermal,
        uncertainty: uncertainty.as_ref().zip(a.uncertainty.as_deref()),
    };
    Ok(request.page()?)
}

/// The characterisation report of `log_path` (columns `time_s`, `current_A`, `torque_Nm`, as the
/// rig writes them) and, with `frd_path`, of a `poles`/`zeros` transfer function fitted to it.
fn characterization_page(
    log_path: &std::path::Path,
    frd_path: Option<&std::path::Path>,
    order: usize,
    poles: usize,
    zeros: usize,
) -> CommandResult<String> {
    use mrbrake::sysid::characterize::CharacterizeOptions;
    use mrbrake::sysid::request::CharacterizationRequest;
    use mrbrake::sysid::tfest::TfestOptions;
    let request = CharacterizationRequest {
        options: CharacterizeOptions { order, ..CharacterizeOptions::default() },
        frd: frd_path.map(std::path::Path::to_path_buf),
        tfest: TfestOptions::new(poles, zeros),
        ..CharacterizationRequest::new(log_path)
    };
    let flags = [("order", "--fit-order"), ("poles", "--poles"), ("zeros", "--zeros")];
    let run = request.run().map_err(|e| e.with_field_names(&flags))?;
    Ok(request::characterization_page(&run, log_path)?)
}
