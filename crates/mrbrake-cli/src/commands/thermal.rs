//! `mrbrake thermal [SPEC]`: the brake's temperatures at a current and duty cycle — steady hot
//! spot, warm-up, time to the insulation limit, continuous current rating, largest duty at the
//! maximum current — and what heat does to the brake (hot coil, hot fluid, voltage drive).

use std::path::PathBuf;

use clap::Args;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::spec::{BrakeSpec, default_spec};
use mrbrake::design::thermal::{Cooling, ThermalError, ThermalOptions, analyze_thermal_with_field};
use mrbrake::report::thermal as report;
use mrbrake::units::{Dimension, parse};

use super::field_flags;
use crate::error::{CommandError, CommandResult, InputError};
use crate::output::{print_json, print_text};

/// Arguments of `mrbrake thermal`.
#[derive(Debug, Args)]
pub struct ThermalArgs {
    /// Brake specification (TOML). Omitted: the embedded thesis bidirectional brake.
    spec: Option<PathBuf>,
    /// Coil current when on (e.g. 2A); default the spec's maximum current.
    #[arg(long, allow_hyphen_values = true)]
    current: Option<String>,
    /// Duty cycle in (0, 1]: the fraction of time the current is on.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    duty: f64,
    /// Period of the duty cycle (e.g. 10s); checked against the thermal time constant.
    #[arg(long, allow_hyphen_values = true)]
    period: Option<String>,
    /// Ambient temperature (e.g. 25C).
    #[arg(long, default_value = "25C", allow_hyphen_values = true)]
    ambient: String,
    /// Heat-transfer coefficient of the housing (e.g. 10W/(m²·K), 10W/m2K; a bare number is
    /// W/(m²·K)), or `natural` for natural convection to still air with the axis horizontal
    /// (Churchill–Chu, iterated with the surface temperature).
    #[arg(
        long,
        value_name = "COEFFICIENT|natural",
        default_value = "10",
        allow_hyphen_values = true
    )]
    h: String,
    /// Emissivity of the housing for radiation to surroundings at the ambient, in [0, 1] (0: none;
    /// about 0.8–0.95 for painted or oxidised steel).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    emissivity: f64,
    /// Insulation limit of the winding: a temperature (e.g. 155C) or an IEC 60085 thermal class
    /// letter (A 105, E 120, B 130, F 155, H 180 °C).
    #[arg(long, default_value = "155C", allow_hyphen_values = true)]
    insulation_class: String,
    /// Duration of the warm-up (e.g. 2h, 30min).
    #[arg(long, default_value = "2h", allow_hyphen_values = true)]
    time: String,
    /// Time step of the warm-up (e.g. 10s).
    #[arg(long, default_value = "10s", allow_hyphen_values = true)]
    dt: String,
    /// Shaft speed for the viscous heat in the gaps and the off-state torque (e.g. 0rad/s, 60rpm;
    /// the off-state torque is quoted at 1 rad/s when the speed is 0).
    #[arg(long, default_value = "0rad/s", allow_hyphen_values = true)]
    speed: String,
    /// Mesh density: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Skip what heat does to the brake (viscosity, resistance, voltage drive: a magnetic analysis).
    #[arg(long)]
    no_behaviour: bool,
    /// Write plots here: temperature map, warm-up curve (SVG).
    #[arg(long, value_name = "DIR")]
    plot_dir: Option<PathBuf>,
    /// Also write PNG versions of the plots.
    #[arg(long)]
    png: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Add the hot coil (steady mean temperature, its resistance, the continuous current) to this
    /// brake model file, written before by `mrbrake analyze --save-model` for the same design; the
    /// file is rewritten atomically.
    #[arg(long, value_name = "FILE.json")]
    save_model: Option<PathBuf>,
}

fn quantity(flag: &str, text: &str, dimension: Dimension) -> Result<f64, InputError> {
    parse(text, dimension).map_err(|e| InputError(format!("--{flag}: {e}")))
}

/// The limit of an IEC 60085 class letter, or a temperature.
fn insulation_limit(text: &str) -> Result<f64, InputError> {
    mrbrake::design::thermal::insulation_limit_c(text)
        .map_err(|e| InputError(format!("--insulation-class: {e}")))
}

fn cooling(text: &str) -> Result<Cooling, InputError> {
    Cooling::parse(text).map_err(|e| InputError(format!("--h: {e}")))
}

fn options(a: &ThermalArgs, spec: &BrakeSpec) -> Result<ThermalOptions, InputError> {
    Ok(ThermalOptions {
        current_a: match &a.current {
            Some(c) => quantity("current", c, Dimension::Current)?,
            None => spec.coil.max_current.a(),
        },
        duty: a.duty,
        period_s: a
            .period
            .as_deref()
            .map(|p| quantity("period", p, Dimension::Time))
            .transpose()?,
        ambient_c: quantity("ambient", &a.ambient, Dimension::TemperatureCelsius)?,
        cooling: cooling(&a.h)?,
        emissivity: a.emissivity,
        limit_c: insulation_limit(&a.insulation_class)?,
        time_s: quantity("time", &a.time, Dimension::Time)?,
        dt_s: quantity("dt", &a.dt, Dimension::Time)?,
        speed_rad_s: quantity("speed", &a.speed, Dimension::AngularVelocity)?,
        mesh: MeshLevel::parse(&a.mesh)
            .map_err(|e| InputError(field_flags::design(e).to_string()))?,
        behaviour: !a.no_behaviour,
    })
}

/// An option out of range named by its flag.
fn flagged(e: ThermalError) -> CommandError {
    field_flags::thermal(e).into()
}

/// Runs `mrbrake thermal`.
pub fn run(a: ThermalArgs) -> CommandResult {
    let spec = match &a.spec {
        Some(path) => BrakeSpec::from_path(path)?,
        None => default_spec(),
    };
    let (result, field) =
        analyze_thermal_with_field(&spec, &options(&a, &spec)?).map_err(flagged)?;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(dir) = &a.plot_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            InputError(format!("--plot-dir {}: cannot create it: {e}", dir.display()))
        })?;
        report::write_plots(&result, &field, dir, a.png)?;
    }
    let source =
        a.spec.as_ref().map_or("embedded default".to_string(), |p| p.display().to_string());
    if let Some(path) = &a.save_model {
        let mut model = mrbrake::sim::brake_model::BrakeModel::read(path)?;
        let word = super::analyze::command_word(a.spec.as_deref(), &source);
        let how = format!("mrbrake thermal {word} (--mesh {} --h {})", a.mesh, a.h);
        mrbrake::device::brake_model::add_thermal(&mut model, &result, &spec.name, &how)?;
        mrbrake::report::write_atomic(path, model.to_json().as_bytes())?;
    }
    if a.json {
        return print_json(&result);
    }
    print_text(&report::text(&result, &source))
}
