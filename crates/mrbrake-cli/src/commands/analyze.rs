//! `mrbrake analyze [SPEC.toml]`: the main job — field, torque–current curve, coil and mechanics of a
//! brake design; with no spec, the thesis's bidirectional brake (embedded default).

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::{BrakeSpec, default_spec};
use mrbrake::observe::{Count, Flow};
use mrbrake::report::analysis as report;
use mrbrake::units::{Dimension, parse};

use super::field_flags;
use crate::error::InputError;
use crate::error::{CommandResult, Context};
use crate::output::{print_json, print_text};
use crate::progress::ProgressDisplay;

/// Arguments of `mrbrake analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// Brake specification (TOML; every key with its unit, range and default:
    /// docs/reference/spec.md or `mrbrake schema spec --markdown`). Omitted: the embedded thesis
    /// bidirectional brake (examples/specs/thesis-bidirectional.toml).
    spec: Option<PathBuf>,
    /// Mesh density: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Element order of the field solution: 1 (linear triangles) or 2 (quadratic, 6-node
    /// triangles on the same mesh: about four times the unknowns, B one order more accurate).
    #[arg(long, value_name = "1|2", default_value_t = 1)]
    order: u8,
    /// Number of currents in the torque–current sweep (0 to the maximum current).
    #[arg(long, default_value_t = 21)]
    points: usize,
    /// Relative speed for the viscous torque (e.g. 1rad/s, 60rpm).
    #[arg(long, default_value = "1rad/s", allow_hyphen_values = true)]
    speed: String,
    /// A measured constant friction added to every torque (e.g. 0.05Nm), on top of the spec's
    /// `[drag]` terms (seals, bearings, freewheel); reported within the seal term.
    #[arg(long, default_value = "0Nm", allow_hyphen_values = true)]
    seal_friction: String,
    /// Copper temperature for the coil resistance (e.g. 20C, 75C).
    #[arg(long, default_value = "20C", allow_hyphen_values = true)]
    temperature: String,
    /// Write plots here: field map, torque–current curve, |B| along the gaps (SVG).
    #[arg(long, value_name = "DIR")]
    plot_dir: Option<PathBuf>,
    /// Also write PNG versions of the plots.
    #[arg(long)]
    png: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Also write the brake model (JSON: static torque–current curve per unit, off-state torque,
    /// maximum current, provenance) that `rig … --brake-model` and `haptic … --brake-model` run.
    #[arg(long, value_name = "FILE.json")]
    save_model: Option<PathBuf>,
    /// Also predict the torque–current hysteresis loop from the magnetic hysteresis of the steel
    /// (`0 → peak → 0 → peak → 0 → −peak → 0 → peak`): branches, remanent torque at 0 A (also the
    /// remanent term of the off-state breakdown), loop width at mid current; JSON key `hysteresis`.
    #[arg(long)]
    hysteresis: bool,
    /// Peak current of the hysteresis loop (e.g. 1.5A); default: the coil's maximum current.
    #[arg(long, requires = "hysteresis", allow_hyphen_values = true)]
    peak: Option<String>,
    /// Currents per leg of the hysteresis loop's program.
    #[arg(long, requires = "hysteresis", default_value_t = mrbrake::design::hysteresis::DEFAULT_POINTS_PER_LEG)]
    loop_points: usize,
    /// With --hysteresis, also judge demagnetising releases after the peak on the predicted loop:
    /// the remanent torque at 0 A without one, after reverse pulses (scan + golden section for the
    /// least) and after a decaying alternating current; JSON key `hysteresis.demagnetisation`.
    #[arg(long, requires = "hysteresis")]
    demag: bool,
    /// Largest reverse current of the coil driver for --demag (e.g. 1A); default: the coil's
    /// maximum current.
    #[arg(long, requires = "demag", allow_hyphen_values = true, value_name = "CURRENT")]
    demag_reverse_limit: Option<String>,
    /// Levels of the first-order reversal curves whose Preisach model `--save-model` writes with
    /// `--hysteresis` (the FORCs are solved on `[0, I_max]`, in parallel).
    #[arg(long, requires = "hysteresis", default_value_t = mrbrake::design::forc::DEFAULT_LEVELS)]
    forc_levels: usize,
    /// Current steps per level step of the first-order reversal curves.
    #[arg(long, requires = "hysteresis", default_value_t = mrbrake::design::forc::DEFAULT_STEPS_PER_LEVEL)]
    forc_steps: usize,
}

/// The spec as a word of a printed command: the path quoted for a shell (a path with spaces
/// pastes as one word), or `source` ("embedded default") when no spec was given.
pub fn command_word(spec: Option<&std::path::Path>, source: &str) -> String {
    spec.map_or_else(|| source.to_string(), mrbrake::report::wording::shell_quote)
}

/// Runs `mrbrake analyze`.
pub fn run(a: AnalyzeArgs) -> CommandResult {
    let spec = match &a.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let options = AnalysisOptions {
        mesh: MeshLevel::parse(&a.mesh).map_err(field_flags::design)?,
        points: a.points,
        speed_rad_s: parse(&a.speed, Dimension::AngularVelocity)
            .map_err(|e| InputError(format!("--speed: {e}")))?,
        seal_friction_nm: parse(&a.seal_friction, Dimension::Torque)
            .map_err(|e| InputError(format!("--seal-friction: {e}")))?,
        temperature_c: parse(&a.temperature, Dimension::TemperatureCelsius)
            .map_err(|e| InputError(format!("--temperature: {e}")))?,
        order: super::field_flags::order(a.order)?,
    };
    // The scan's options are checked before any solve (a bad flag costs no FEA time).
    let demag_options = if a.demag { Some(demag_options(&a, &spec)?) } else { None };
    let mut display = ProgressDisplay::steps("analyze", "currents", a.json);
    let request = AnalysisRequest::of(&spec).options(options).observe(|c: &Count| {
        display.step(c.done, c.total);
        Flow::Continue
    });
    let (analysis, field) = if a.plot_dir.is_some() {
        let (analysis, field) = request.run_with_field().map_err(field_flags::design)?;
        (analysis, Some(field))
    } else {
        (request.run().map_err(field_flags::design)?, None)
    };
    display.finish();
    for w in &analysis.warnings {
        eprintln!("warning: {w}");
    }
    let predicted = if a.hysteresis { Some(predict_loop(&a, &spec, &options)?) } else { None };
    let demag = match &demag_options {
        Some(d) => {
            Some(mrbrake::design::demag::run(&spec, &options, d).map_err(field_flags::design)?)
        }
        None => None,
    };
    // What is shown and saved: with the loop's remanent torque when it ran (the plots are the
    // analysis's own).
    let with_loop =
        predicted.as_ref().map(|p| mrbrake::report::predicted_loop::with_remanence(&analysis, p));
    let (plotted, analysis) = (&analysis, with_loop.as_ref().unwrap_or(&analysis));
    let source =
        a.spec.as_ref().map_or("embedded default".to_string(), |p| p.display().to_string());
    // The brake model is made and checked before anything is written (all or nothing: a refused
    // model leaves no plots behind either).
    let model = match &a.save_model {
        Some(path) => Some((path, saved_model(&a, path, (&spec, &options), analysis, &source)?)),
        None => None,
    };
    if let (Some(dir), Some(field)) = (&a.plot_dir, &field) {
        write_plots(&a, dir, plotted, field, predicted.as_ref())?;
    }
    if let Some((path, (json, _))) = &model {
        mrbrake::report::write_atomic(path, json.as_bytes())?;
    }
    if a.json {
        let Some(p) = &predicted else { return print_json(analysis) };
        let mut value = mrbrake::report::predicted_loop::json(analysis, p)?;
        if let Some(d) = &demag {
            mrbrake::report::demag::insert_json(&mut value, d)?;
        }
        if let Some((_, (_, Some(forc)))) = &model {
            value["forc"] = forc.clone();
        }
        return print_json(&value);
    }
    let mut text = report::text(analysis, &source);
    if let Some(p) = &predicted {
        text.push_str(&mrbrake::report::predicted_loop::text(p));
    }
    if let Some(d) = &demag {
        text.push_str(&mrbrake::report::demag::text(d));
    }
    print_text(&text)
}

/// The brake model of `--save-model` as JSON, checked as the simulators will run it: a refusal
/// names the output flag and the spec it came from. With `--hysteresis`, also the summary of the
/// FORC set its Preisach model comes from (JSON key `forc`).
fn saved_model(
    a: &AnalyzeArgs,
    path: &std::path::Path,
    (spec, options): (&BrakeSpec, &AnalysisOptions),
    analysis: &mrbrake::design::analysis::Analysis,
    source: &str,
) -> CommandResult<(String, Option<serde_json::Value>)> {
    let how = format!(
        "mrbrake analyze {} (--mesh {} --order {} --points {})",
        command_word(a.spec.as_deref(), source),
        a.mesh,
        a.order,
        a.points
    );
    let identity = mrbrake::explore::design::analysis_identity(spec, options)?;
    let context = format!("--save-model {} (from {source})", path.display());
    let mut model =
        mrbrake::device::brake_model::from_analysis(analysis, options, Some(identity), &how)
            .context(context.clone())?;
    let mut summary = None;
    if a.hysteresis {
        let forc_options = mrbrake::design::forc::ForcOptions {
            levels: a.forc_levels,
            steps_per_level: a.forc_steps,
            chains: None,
        };
        let forcs = mrbrake::design::forc::run(spec, options, &forc_options)
            .map_err(field_flags::design)?;
        let how = format!("{how} --hysteresis --forc-levels {}", a.forc_levels);
        let identified = mrbrake::device::brake_model::set_predicted_hysteresis(
            &mut model, &forcs, analysis, &how,
        )
        .context(context)?;
        let projection = (identified.projected_weight_nm, identified.projection_nm);
        eprintln!("{}", mrbrake::report::predicted_loop::forc_line(&forcs, projection));
        summary = Some(mrbrake::report::predicted_loop::forc_json(&forcs, projection));
    }
    Ok((model.to_json(), summary))
}

/// The plots of `--plot-dir`: the analysis's, and the loop's with `--hysteresis`.
fn write_plots(
    a: &AnalyzeArgs,
    dir: &std::path::Path,
    analysis: &mrbrake::design::analysis::Analysis,
    field: &mrbrake::design::analysis::FieldAtMaxCurrent,
    predicted: Option<&mrbrake::design::hysteresis::HysteresisLoop>,
) -> CommandResult {
    std::fs::create_dir_all(dir)
        .map_err(|e| InputError(format!("--plot-dir {}: cannot create it: {e}", dir.display())))?;
    report::write_plots(analysis, field, dir, a.png)?;
    if let Some(predicted) = predicted {
        mrbrake::report::predicted_loop::save_figure(&dir.join("hysteresis_loop.svg"), predicted)?;
        if a.png {
            let png = dir.join("hysteresis_loop.png");
            mrbrake::report::predicted_loop::save_figure(&png, predicted)?;
        }
    }
    Ok(())
}

/// A current flag's value in A, `None` when not given.
fn optional_current(flag: &str, text: Option<&str>) -> Result<Option<f64>, InputError> {
    text.map(|t| parse(t, Dimension::Current).map_err(|e| InputError(format!("{flag}: {e}"))))
        .transpose()
}

/// The options of the `--demag` scan (after the loop's peak), checked against the spec's coil.
fn demag_options(
    a: &AnalyzeArgs,
    spec: &BrakeSpec,
) -> Result<mrbrake::design::demag::DemagOptions, crate::error::CommandError> {
    let options = mrbrake::design::demag::DemagOptions {
        peak_current_a: optional_current("--peak", a.peak.as_deref())?,
        reverse_limit_a: optional_current(
            "--demag-reverse-limit",
            a.demag_reverse_limit.as_deref(),
        )?,
        ..Default::default()
    };
    options.check(spec.coil.max_current.a()).map_err(field_flags::design)?;
    Ok(options)
}

/// The predicted hysteresis loop of `--hysteresis`.
fn predict_loop(
    a: &AnalyzeArgs,
    spec: &BrakeSpec,
    options: &AnalysisOptions,
) -> Result<mrbrake::design::hysteresis::HysteresisLoop, crate::error::CommandError> {
    let peak = optional_current("--peak", a.peak.as_deref())?;
    let loop_options = mrbrake::design::hysteresis::LoopOptions {
        peak_current_a: peak,
        points_per_leg: a.loop_points,
    };
    Ok(mrbrake::design::hysteresis::run(spec, options, &loop_options)
        .map_err(field_flags::design)?)
}
