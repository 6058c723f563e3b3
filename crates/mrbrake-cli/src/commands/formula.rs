//! `mrbrake formula …`: the thesis's closed-form models from the command line.
//!
//! Torque of a single disc (3.6)/(3.7), multi-disc (3.8), drum (3.9) and multi-drum (4.4)/(4.5) brake
//! from a yield stress (given, or looked up from the fluid's τ_y(B) curve at a flux density), with the
//! optional viscous term at a speed; and the coil of a winding window ((4.1)–(4.3), resistance, power).
//! The command only parses its flags into the library's requests
//! (`mrbrake_design::formula::{torque, coil}`), which hold every range rule.

use clap::{Args, Subcommand};
use mrbrake::design::formula::{self, ClosedFormBrake, CoilRequest, TorqueRequest, WireChoice};
use mrbrake::report::formula::{BrakeFormulaReport, CoilReport};
use mrbrake::units::{Dimension, parse};

use crate::error::CommandResult;
use crate::error::InputError;
use crate::output::{print_json, print_text};

/// `mrbrake formula` subcommands.
#[derive(Debug, Subcommand)]
pub enum FormulaCommand {
    /// Single-disc brake torque, thesis (3.6) and (3.7): T = 4π τ_y (R2³ − R1³)/3 [+ viscous term].
    SingleDisc(SingleDiscArgs),
    /// Multi-disc brake torque, thesis (3.8): n times the single disc.
    MultiDisc(MultiDiscArgs),
    /// Drum brake torque, thesis (3.9): T = 4π τ_y R² h [+ viscous term].
    Drum(DrumArgs),
    /// Multi-drum brake torque, thesis (4.4) and (4.5): T = 2π h τ_y Σ R_k², R_k = R_(k−1) + d + g.
    MultiDrum(MultiDrumArgs),
    /// Coil in a winding window: turns (4.2)/(4.3), wire length, resistance, current density (4.1), power.
    Coil(CoilArgs),
}

/// Where the yield stress comes from, and the optional viscous term.
#[derive(Debug, Args)]
pub struct FluidArgs {
    /// Yield stress τ_y (e.g. 24.315kPa); or give --b to read it from the fluid's τ_y(B) curve.
    // Not `required_unless_present`: clap's message would name --tau-y alone; the library's
    // request names both ways.
    #[arg(long = "tau-y", value_name = "STRESS", allow_hyphen_values = true, conflicts_with = "b")]
    tau_y: Option<String>,
    /// Mean flux density in the fluid (e.g. 0.46T); τ_y is then read from the fluid's τ_y(B) curve.
    #[arg(long, value_name = "FLUX_DENSITY", allow_hyphen_values = true)]
    b: Option<String>,
    /// MR fluid used for --b and for the default viscosity (see `mrbrake materials list`);
    /// default: mrf-122eg, the thesis's fluid.
    #[arg(long, value_name = "NAME")]
    fluid: Option<String>,
    /// Relative speed for the viscous term (e.g. 60rpm, 6.28rad/s); omitted: yield torque only.
    #[arg(long, value_name = "SPEED", allow_hyphen_values = true)]
    speed: Option<String>,
    /// Newtonian (off-state) viscosity for the viscous term (e.g. 0.056Pa.s); default: the fluid's.
    #[arg(long, value_name = "VISCOSITY", allow_hyphen_values = true)]
    eta: Option<String>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `formula single-disc`.
#[derive(Debug, Args)]
pub struct SingleDiscArgs {
    /// Inner radius R1 of the fluid annulus (e.g. 22.5mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    r1: String,
    /// Outer radius R2 of the fluid annulus (e.g. 27.5mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    r2: String,
    /// Fluid gap g on each side of the disc (needed only with --speed).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    gap: Option<String>,
    #[command(flatten)]
    fluid: FluidArgs,
}

/// Arguments of `formula multi-disc`: the single disc's plus the number of discs.
#[derive(Debug, Args)]
pub struct MultiDiscArgs {
    /// Number of rotating discs n (each sheared on both faces).
    #[arg(long, value_name = "N")]
    discs: u32,
    #[command(flatten)]
    disc: SingleDiscArgs,
}

/// Arguments of `formula drum`.
#[derive(Debug, Args)]
pub struct DrumArgs {
    /// Radius R of the drum (both fluid faces are taken at R).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    r: String,
    /// Height h of the drum.
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    h: String,
    /// Fluid gap g on each side of the drum (needed only with --speed).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    gap: Option<String>,
    #[command(flatten)]
    fluid: FluidArgs,
}

/// Arguments of `formula multi-drum`.
#[derive(Debug, Args)]
pub struct MultiDrumArgs {
    /// Radius R0 of the innermost fluid surface (e.g. 25mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    r0: String,
    /// Height h of the cylinders (e.g. 9mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    h: String,
    /// Cylinder wall thickness d (e.g. 1mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    d: String,
    /// Fluid gap g (e.g. 0.5mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    g: String,
    /// Number of fluid surfaces (radii R_0 … R_(n−1)); the thesis's final design has 4.
    #[arg(long, value_name = "N")]
    surfaces: u32,
    #[command(flatten)]
    fluid: FluidArgs,
}

/// Arguments of `formula coil`.
#[derive(Debug, Args)]
pub struct CoilArgs {
    /// Radial width C_w of the winding window (e.g. 12mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    window_width: String,
    /// Axial height C_h of the winding window (e.g. 12mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    window_height: String,
    /// Wire gauge, AWG 18–32.
    #[arg(long, conflicts_with = "wire_diameter", required_unless_present = "wire_diameter")]
    awg: Option<u32>,
    /// Bare wire diameter instead of a gauge (e.g. 0.5mm).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    wire_diameter: Option<String>,
    /// Inner radius of the winding (default 5mm: the shaft radius of the thesis's Table 4.5, where
    /// the concept design winds the coil directly on the shaft).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    inner_radius: Option<String>,
    /// Number of turns; default: as many as fit the window by (4.2)/(4.3).
    #[arg(long)]
    turns: Option<u32>,
    /// Coil current (e.g. 2A); default 2A, the thesis's design current.
    #[arg(long, value_name = "CURRENT", allow_hyphen_values = true)]
    current: Option<String>,
    /// Copper temperature for the resistance (e.g. 20C, 75C); default 20C.
    #[arg(long, value_name = "TEMPERATURE", allow_hyphen_values = true)]
    temperature: Option<String>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake formula …`.
pub fn run(command: FormulaCommand) -> CommandResult {
    match command {
        FormulaCommand::SingleDisc(a) => disc(1, &a),
        FormulaCommand::MultiDisc(a) => disc(a.discs, &a.disc),
        FormulaCommand::Drum(a) => {
            let brake =
                ClosedFormBrake::Drum { r_m: length("--r", &a.r)?, h_m: length("--h", &a.h)? };
            brake_torque(brake, &a.fluid, a.gap.as_deref())
        }
        FormulaCommand::MultiDrum(a) => {
            let brake = ClosedFormBrake::MultiDrum {
                r0_m: length("--r0", &a.r0)?,
                h_m: length("--h", &a.h)?,
                d_m: length("--d", &a.d)?,
                g_m: length("--g", &a.g)?,
                surfaces: a.surfaces,
            };
            brake_torque(brake, &a.fluid, None)
        }
        FormulaCommand::Coil(a) => coil(a),
    }
}

/// Single disc (n = 1) or multi-disc brake torque, (3.6)–(3.8).
fn disc(discs: u32, a: &SingleDiscArgs) -> CommandResult {
    let brake = ClosedFormBrake::Discs {
        discs,
        r1_m: length("--r1", &a.r1)?,
        r2_m: length("--r2", &a.r2)?,
    };
    brake_torque(brake, &a.fluid, a.gap.as_deref())
}

fn length(flag: &str, text: &str) -> CommandResult<f64> {
    quantity(flag, text, Dimension::Length)
}

/// A quantity flag's value in SI, with the flag in front of any parse error.
fn quantity(flag: &str, text: &str, dimension: Dimension) -> CommandResult<f64> {
    parse(text, dimension).map_err(|e| InputError(format!("{flag}: {e}")).into())
}

/// An optional quantity flag's value in SI.
fn optional(flag: &str, text: Option<&str>, dimension: Dimension) -> CommandResult<Option<f64>> {
    text.map(|t| quantity(flag, t, dimension)).transpose()
}

/// The torque of `brake` by the library's closed-form request (which checks every value), as
/// text or JSON.
fn brake_torque(brake: ClosedFormBrake, a: &FluidArgs, gap: Option<&str>) -> CommandResult {
    let request = TorqueRequest {
        brake,
        tau_y_pa: optional("--tau-y", a.tau_y.as_deref(), Dimension::Stress)?,
        b_t: optional("--b", a.b.as_deref(), Dimension::FluxDensity)?,
        fluid: a.fluid.clone(),
        speed_rad_s: optional("--speed", a.speed.as_deref(), Dimension::AngularVelocity)?,
        eta_pa_s: optional("--eta", a.eta.as_deref(), Dimension::Viscosity)?,
        gap_m: optional("--gap", gap, Dimension::Length)?,
    };
    let answer = formula::torque(&request).map_err(super::field_flags::design)?;
    let report = BrakeFormulaReport(&answer);
    if a.json {
        return print_json(&report.json());
    }
    print_text(&report.text())
}

fn coil(a: CoilArgs) -> CommandResult {
    let wire = match (a.awg, &a.wire_diameter) {
        (Some(awg), _) => Some(WireChoice::Awg(awg)),
        (None, Some(d)) => Some(WireChoice::Diameter(length("--wire-diameter", d)?)),
        (None, None) => None,
    };
    let request = CoilRequest {
        window_width_m: length("--window-width", &a.window_width)?,
        window_height_m: length("--window-height", &a.window_height)?,
        wire,
        inner_radius_m: optional("--inner-radius", a.inner_radius.as_deref(), Dimension::Length)?,
        turns: a.turns,
        current_a: optional("--current", a.current.as_deref(), Dimension::Current)?,
        temperature_c: optional(
            "--temperature",
            a.temperature.as_deref(),
            Dimension::TemperatureCelsius,
        )?,
    };
    let answer = formula::coil(&request).map_err(super::field_flags::design)?;
    for warning in &answer.warnings {
        eprintln!("warning: {warning}");
    }
    let report = CoilReport(&answer);
    if a.json {
        return print_json(&report.json());
    }
    print_text(&report.text())
}
