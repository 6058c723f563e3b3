//! The analyses the page runs on request, beside the static solve of every edit: the step and
//! frequency response (`mrbrake response`), the warm-up and continuous rating (`mrbrake thermal`)
//! and the haptic wall with the design's brake model (`mrbrake analyze --save-model` then
//! `mrbrake haptic wall --brake-model`). Each runs the library function the CLI calls, with the
//! CLI's defaults, and answers the CLI's JSON (so every number on the page is the command's), the
//! report's figures and the command that prints the same numbers.
//!
//! Cancellation: an analysis runs to its end on its worker (the response, thermal and haptic
//! functions have no stop points), but a cancel or an edit made meanwhile makes it obsolete — its
//! result is dropped and the page shows it cancelled at once.

use std::time::Instant;

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::response::{ResponseOptions, response};
use mrbrake_design::spec::BrakeSpec;
use mrbrake_design::thermal::{ThermalOptions, analyze_thermal};
use mrbrake_report::bode::bode_figure;
use mrbrake_report::chart::Figure;
use mrbrake_report::haptic::{wall_plot_title, wall_runs_figure};
use mrbrake_report::html::inline_svg;
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, Scenario, simulate};
use serde_json::{Value, json};

use crate::session::{Solved, chain};

/// An analysis the page can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// Step responses and the small-signal frequency response.
    Response,
    /// Steady temperatures, continuous rating and the warm-up.
    Thermal,
    /// The haptic wall driven by the design's brake model.
    Haptic,
}

impl Kind {
    /// Every kind, in the page's order.
    pub const ALL: [Kind; 3] = [Kind::Response, Kind::Thermal, Kind::Haptic];

    /// The name in URLs and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Response => "response",
            Kind::Thermal => "thermal",
            Kind::Haptic => "haptic",
        }
    }

    /// The kind of `name`.
    pub fn from_name(name: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The CLI commands that print the same numbers.
    pub fn command(self, device: DeviceKind) -> String {
        match self {
            Kind::Response => "mrbrake response SPEC --json".to_string(),
            Kind::Thermal => "mrbrake thermal SPEC --json".to_string(),
            Kind::Haptic => format!(
                "mrbrake analyze SPEC --save-model model.json && mrbrake haptic wall --device {} \
                 --brake-model model.json --json",
                device.name()
            ),
        }
    }
}

/// The haptic device a design drives: the bidirectional device for a two-unit brake, the
/// conventional one (one brake) otherwise.
pub fn device_of(spec: &BrakeSpec) -> DeviceKind {
    match mrbrake_design::geometry::build(spec) {
        Ok(g) if g.units == 2 => DeviceKind::Bidirectional,
        _ => DeviceKind::Conventional,
    }
}

/// Runs `kind` on `spec`; `solved` is the latest default-mesh solve when it is of this spec
/// (the haptic wall's brake model then needs no new static analysis). The answer: `kind`, `cli`,
/// `result` (the CLI's JSON), `figures` (inline SVG), `notes` (what the CLI says on its error
/// stream) and `elapsed_s`; an error is the message with its causes, in the CLI's words.
pub fn run(kind: Kind, spec: &BrakeSpec, solved: Option<&Solved>) -> Result<Value, String> {
    let start = Instant::now();
    let device = device_of(spec);
    let (result, figures, notes) = match kind {
        Kind::Response => response_of(spec)?,
        Kind::Thermal => thermal_of(spec)?,
        Kind::Haptic => haptic_of(spec, solved, device)?,
    };
    Ok(json!({
        "kind": kind.name(),
        "cli": kind.command(device),
        "result": result,
        "figures": figures,
        "notes": notes,
        "elapsed_s": start.elapsed().as_secs_f64(),
    }))
}

fn svg(figure: Figure, label: &str) -> Result<String, String> {
    figure.to_svg().and_then(|s| inline_svg(&s, label)).map_err(|e| chain(&e))
}

/// What one analysis answers: the CLI's JSON, the figures, the notes.
type Answer = (Value, Value, Vec<String>);

fn to_json<T: serde::Serialize>(value: &T) -> Result<Value, String> {
    serde_json::to_value(value).map_err(|e| e.to_string())
}

/// `mrbrake response SPEC --json` and its step and Bode figures.
fn response_of(spec: &BrakeSpec) -> Result<Answer, String> {
    let r = response(spec, &ResponseOptions::default()).map_err(|e| chain(&e))?;
    let curves = mrbrake_report::response::bode_curves(&r, false).map_err(|e| chain(&e))?;
    let title = format!("{}: torque per current, small signal", r.name);
    let figures = json!({
        "step": svg(mrbrake_report::response::step_figure(&r), "torque step response")?,
        "bode": svg(bode_figure(&title, &curves), "frequency response")?,
    });
    Ok((to_json(&r)?, figures, Vec::new()))
}

/// `mrbrake thermal SPEC --json` (the command's defaults: the spec's maximum current, what heat
/// does to the brake included) and its warm-up figure.
fn thermal_of(spec: &BrakeSpec) -> Result<Answer, String> {
    let options = ThermalOptions {
        current_a: spec.coil.max_current.a(),
        behaviour: true,
        ..ThermalOptions::default()
    };
    let r = analyze_thermal(spec, &options).map_err(|e| chain(&e))?;
    let figures = json!({
        "warmup": svg(mrbrake_report::thermal::warmup_figure(&r), "coil warm-up")?,
    });
    let warnings = r.warnings.clone();
    Ok((to_json(&r)?, figures, warnings))
}

/// The haptic wall (`press-withdraw`, the command's gains) with the brake model `analyze
/// --save-model` writes for the design, and its time-history figure.
fn haptic_of(
    spec: &BrakeSpec,
    solved: Option<&Solved>,
    device: DeviceKind,
) -> Result<Answer, String> {
    let options = AnalysisOptions::default();
    let fresh;
    let analysis = match solved {
        Some(s) if s.options == options => &s.analysis,
        _ => {
            fresh = AnalysisRequest::of(spec).options(options).run().map_err(|e| chain(&e))?;
            &fresh
        }
    };
    let source = "mrbrake studio (as mrbrake analyze --save-model)";
    let model = mrbrake_device::brake_model::from_analysis(analysis, &options, None, source)
        .map_err(|e| chain(&e))?;
    let mut config = HapticConfig::new(device, Scenario::PressWithdraw);
    let notes = mrbrake_sim::brake_model::apply::apply_to_haptic(&model, &mut config)
        .map_err(|e| chain(&e))?;
    let run = simulate(&config, true).map_err(|e| chain(&e))?;
    let title = wall_plot_title(
        run.metrics.scenario,
        config.wall_stiffness_nm_per_rad,
        config.wall_damping_nms_per_rad,
    );
    let figure = wall_runs_figure(&title, &[(device, &run)]).map_err(|e| chain(&e))?;
    let figures = json!({ "wall": svg(figure, "haptic wall time histories")? });
    Ok((to_json(&run.metrics)?, figures, notes))
}
