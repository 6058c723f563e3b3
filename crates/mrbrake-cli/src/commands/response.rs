//! `mrbrake response [SPEC]`: how fast the brake's torque follows its current — the predicted
//! step response and small-signal frequency response (eddy currents, coil circuit, fluid lag).

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::response::{
    ElementOrder, ResponseDrive, ResponseOptions, parse_step, response,
};
use mrbrake::design::spec::{BrakeSpec, default_spec};
use mrbrake::report::atomic::StagedDir;
use mrbrake::report::response as report;
use mrbrake::units::{Dimension, parse};

use super::field_flags;
use crate::error::{CommandResult, InputError};
use crate::output::{print_json, print_text};

/// Arguments of `mrbrake response`.
#[derive(Debug, Args)]
pub struct ResponseArgs {
    /// Brake specification (TOML). Omitted: the embedded thesis bidirectional brake.
    spec: Option<PathBuf>,
    /// Mesh density: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Coil drive: current (a current amplifier, as on the thesis's rig) or voltage (through the
    /// coil's resistance: its L/R adds to the eddy currents).
    #[arg(long, value_name = "current|voltage", default_value = "current")]
    drive: String,
    /// Current step FROM..TO (e.g. 0A..2A); default 0 A to the spec's maximum current. A step
    /// down to 0 (e.g. 2A..0A) is the release: its t63/t90 are the fall times.
    #[arg(long, value_name = "FROM..TO", allow_hyphen_values = true)]
    step: Option<String>,
    /// DC bias of the frequency response (e.g. 1A); default half the maximum current.
    #[arg(long, allow_hyphen_values = true)]
    bias: Option<String>,
    /// Duration of the step response (e.g. 100ms).
    #[arg(long, default_value = "100ms", allow_hyphen_values = true)]
    duration: String,
    /// Conductivity of the flux-path steel (e.g. 5.8MS/m; a bare number is S/m); default: the
    /// material library's value.
    #[arg(long, value_name = "CONDUCTIVITY", allow_hyphen_values = true)]
    conductivity: Option<String>,
    /// First-order lag of the MR fluid (e.g. 0.48ms, 0s for none); default T90 = 1.1 ms (Kubík et
    /// al. 2022) over ln 10.
    #[arg(long, allow_hyphen_values = true)]
    fluid_lag: Option<String>,
    /// Write the frequency response as FRD CSV (the form `mrbrake tfest` reads).
    #[arg(long, value_name = "FILE.csv")]
    frd: Option<PathBuf>,
    /// Write plots here: step response, Bode diagram, eddy-current density map (SVG).
    #[arg(long, value_name = "DIR")]
    plot_dir: Option<PathBuf>,
    /// Instant of the eddy-current density map in `--plot-dir` (e.g. 2ms; the first time step at
    /// or after it, direction 1); default a fiftieth of the duration.
    #[arg(long, value_name = "TIME")]
    eddy_at: Option<String>,
    /// Also write PNG versions of the plots.
    #[arg(long)]
    png: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Add the predicted dynamics (a two-pole transfer function fitted to the frequency response)
    /// to this brake model file, written before by `mrbrake analyze --save-model` for the same
    /// design; the file is rewritten atomically.
    #[arg(long, value_name = "FILE.json")]
    save_model: Option<PathBuf>,
}

fn quantity(flag: &str, text: &str, dimension: Dimension) -> Result<f64, InputError> {
    parse(text, dimension).map_err(|e| InputError(format!("--{flag}: {e}")))
}

fn options(a: &ResponseArgs) -> Result<ResponseOptions, InputError> {
    let mut o = ResponseOptions {
        mesh: MeshLevel::parse(&a.mesh)
            .map_err(|e| InputError(field_flags::design(e).to_string()))?,
        order: ElementOrder::P1,
        drive: ResponseDrive::parse(&a.drive).map_err(|e| InputError(format!("--drive: {e}")))?,
        duration_s: quantity("duration", &a.duration, Dimension::Time)?,
        flux_path_conductivity_s_per_m: a
            .conductivity
            .as_deref()
            .map(|text| quantity("conductivity", text, Dimension::Conductivity))
            .transpose()?,
        ..ResponseOptions::default()
    };
    if let Some(step) = &a.step {
        let (from, to) = parse_step(step).map_err(|e| InputError(format!("--step: {e}")))?;
        o.step_from_a = from;
        o.step_to_a = Some(to);
    }
    if let Some(bias) = &a.bias {
        o.bias_a = Some(quantity("bias", bias, Dimension::Current)?);
    }
    if let Some(lag) = &a.fluid_lag {
        o.fluid_lag_s = quantity("fluid-lag", lag, Dimension::Time)?;
    }
    o.eddy_at_s = match (&a.eddy_at, &a.plot_dir) {
        (Some(text), _) => Some(quantity("eddy-at", text, Dimension::Time)?),
        (None, Some(_)) => Some(o.default_eddy_at_s()),
        (None, None) => None,
    };
    Ok(o)
}

/// Runs `mrbrake response`. All or nothing: the plots are staged, the model and the FRD composed
/// in memory, and nothing is written until every output is ready.
pub fn run(a: ResponseArgs) -> CommandResult {
    let spec = match &a.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let r = response(&spec, &options(&a)?).map_err(field_flags::design)?;
    let source =
        a.spec.as_ref().map_or("embedded default".to_string(), |p| p.display().to_string());
    let model = match &a.save_model {
        Some(path) => {
            let mut model = mrbrake::sim::brake_model::BrakeModel::read(path)?;
            let word = super::analyze::command_word(a.spec.as_deref(), &source);
            let how = format!("mrbrake response {word} (--mesh {} --drive {})", a.mesh, a.drive);
            mrbrake::device::brake_model::add_dynamics(&mut model, &r, &how)?;
            Some((path, model.to_json()))
        }
        None => None,
    };
    let plots = match &a.plot_dir {
        Some(dir) => Some(StagedDir::write(dir, |staging| {
            report::write_plots(&r, staging, a.spec.is_none(), a.png)
        })?),
        None => None,
    };
    if let Some(path) = &a.frd {
        mrbrake::report::write_atomic(path, r.frequency_response.to_csv().as_bytes())?;
    }
    if let Some(plots) = plots {
        plots.commit()?;
    }
    if let Some((path, json)) = model {
        mrbrake::report::write_atomic(path, json.as_bytes())?;
    }
    if a.json {
        return print_json(&r);
    }
    print_text(&report::text(&r, &source))
}
