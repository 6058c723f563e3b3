//! `mrbrake formula …`: the thesis's closed-form models from the command line.
//!
//! Torque of a single disc (3.6)/(3.7), multi-disc (3.8), drum (3.9) and multi-drum (4.4)/(4.5) brake
//! from a yield stress (given, or looked up from the fluid's τ_y(B) curve at a flux density), with the
//! optional viscous term at a speed; and the coil of a winding window ((4.1)–(4.3), resistance, power).

use clap::{Args, Subcommand};
use mrbrake_design::formula::{self, BrakeTorque, Viscous};
use mrbrake_materials::{CopperWire, library};
use mrbrake_report::formula::{
    self as formula_report, BrakeFormulaReport, CoilReport, FluidSource, YieldStress,
};
use mrbrake_units::{Dimension, parse};
use serde_json::{Value, json};

use crate::error::CommandResult;
use crate::error::InputError;
use crate::output::print_json;

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
    // Not `required_unless_present`: clap's message would name --tau-y alone; `yield_stress`
    // names both ways.
    #[arg(long = "tau-y", value_name = "STRESS", allow_hyphen_values = true, conflicts_with = "b")]
    tau_y: Option<String>,
    /// Mean flux density in the fluid (e.g. 0.46T); τ_y is then read from the fluid's τ_y(B) curve.
    #[arg(long, value_name = "FLUX_DENSITY", allow_hyphen_values = true)]
    b: Option<String>,
    /// MR fluid used for --b and for the default viscosity (see `mrbrake materials list`).
    #[arg(long, default_value = "mrf-122eg")]
    fluid: String,
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
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true, default_value = "5mm")]
    inner_radius: String,
    /// Number of turns; default: as many as fit the window by (4.2)/(4.3).
    #[arg(long)]
    turns: Option<u32>,
    /// Coil current (e.g. 2A).
    #[arg(long, value_name = "CURRENT", allow_hyphen_values = true, default_value = "2A")]
    current: String,
    /// Copper temperature for the resistance (e.g. 20C, 75C).
    #[arg(long, value_name = "TEMPERATURE", allow_hyphen_values = true, default_value = "20C")]
    temperature: String,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake formula …`.
pub fn run(command: FormulaCommand) -> CommandResult {
    match command {
        FormulaCommand::SingleDisc(a) => disc(1, &a, "single-disc", "(3.6)/(3.7)"),
        FormulaCommand::MultiDisc(a) => disc(a.discs, &a.disc, "multi-disc", "(3.8)"),
        FormulaCommand::Drum(a) => {
            let r = length("--r", &a.r)?;
            let h = length("--h", &a.h)?;
            let fluid = resolve_fluid(&a.fluid)?;
            let viscous = fluid.viscous(a.gap.as_deref())?;
            let t = formula::drum(r, h, fluid.source.tau_y_pa, viscous)?;
            let inputs = json!({ "r_m": r, "h_m": h });
            report("drum", "(3.9)", inputs, &fluid, viscous, t, a.fluid.json)
        }
        FormulaCommand::MultiDrum(a) => {
            let r0 = length("--r0", &a.r0)?;
            let h = length("--h", &a.h)?;
            let d = length("--d", &a.d)?;
            let g = length("--g", &a.g)?;
            let fluid = resolve_fluid(&a.fluid)?;
            let eta_omega = fluid.speed.map(|w| (fluid.eta_pa_s, w));
            let t = formula::multi_drum(r0, h, d, g, a.surfaces, fluid.source.tau_y_pa, eta_omega)?;
            let radii = formula::multi_drum_radii(r0, d, g, a.surfaces);
            let inputs = json!({
                "r0_m": r0, "h_m": h, "d_m": d, "g_m": g, "surfaces": a.surfaces, "radii_m": radii,
            });
            let viscous =
                fluid.speed.map(|w| Viscous { eta_pa_s: fluid.eta_pa_s, omega_rad_s: w, gap_m: g });
            report("multi-drum", "(4.4)/(4.5)", inputs, &fluid, viscous, t, a.fluid.json)
        }
        FormulaCommand::Coil(a) => coil(a),
    }
}

/// Single disc (n = 1) or multi-disc brake torque, (3.6)–(3.8).
fn disc(n: u32, a: &SingleDiscArgs, configuration: &str, equation: &str) -> CommandResult {
    let r1 = length("--r1", &a.r1)?;
    let r2 = length("--r2", &a.r2)?;
    let fluid = resolve_fluid(&a.fluid)?;
    let viscous = fluid.viscous(a.gap.as_deref())?;
    let t = formula::multi_disc(n, r1, r2, fluid.source.tau_y_pa, viscous)?;
    let inputs = json!({ "discs": n, "r1_m": r1, "r2_m": r2 });
    report(configuration, equation, inputs, &fluid, viscous, t, a.fluid.json)
}

fn length(flag: &str, text: &str) -> CommandResult<f64> {
    parse(text, Dimension::Length).map_err(|e| InputError(format!("{flag}: {e}")).into())
}

/// The yield stress (and where it came from) plus the viscous-term inputs.
struct ResolvedFluid {
    source: FluidSource,
    eta_pa_s: f64,
    speed: Option<f64>,
}

impl ResolvedFluid {
    /// The viscous term for brakes whose gap is an extra option (disc, drum).
    fn viscous(&self, gap: Option<&str>) -> CommandResult<Option<Viscous>> {
        let Some(omega) = self.speed else { return Ok(None) };
        let Some(gap) = gap else {
            return Err(InputError(
                "--speed needs --gap (the fluid gap sheared at that speed)".into(),
            )
            .into());
        };
        Ok(Some(Viscous {
            eta_pa_s: self.eta_pa_s,
            omega_rad_s: omega,
            gap_m: length("--gap", gap)?,
        }))
    }
}

/// The yield stress from `--tau-y` or from the fluid's curve at `--b`, range-checked.
fn yield_stress(a: &FluidArgs) -> CommandResult<YieldStress> {
    match (&a.tau_y, &a.b) {
        (Some(t), _) => {
            let tau =
                parse(t, Dimension::Stress).map_err(|e| InputError(format!("--tau-y: {e}")))?;
            if tau < 0.0 {
                return Err(InputError(format!("--tau-y must be >= 0, got {t}")).into());
            }
            Ok(YieldStress::Given(tau))
        }
        (None, Some(b)) => {
            let b_t =
                parse(b, Dimension::FluxDensity).map_err(|e| InputError(format!("--b: {e}")))?;
            if !(0.0..=3.0).contains(&b_t) {
                return Err(InputError(format!("--b must be between 0 T and 3 T, got {b}")).into());
            }
            Ok(YieldStress::AtFluxDensity(b_t))
        }
        (None, None) => Err(InputError(
            "give the yield stress: --tau-y STRESS (e.g. 24.315kPa), or --b FLUX_DENSITY (e.g. \
             0.46T) to read it from the fluid's τ_y(B) curve"
                .into(),
        )
        .into()),
    }
}

fn resolve_fluid(a: &FluidArgs) -> CommandResult<ResolvedFluid> {
    let fluid = library::fluid(&a.fluid)?;
    let yield_stress = yield_stress(a)?;
    let speed = match &a.speed {
        Some(s) => Some(
            parse(s, Dimension::AngularVelocity)
                .map_err(|e| InputError(format!("--speed: {e}")))?,
        ),
        None => None,
    };
    let eta = match &a.eta {
        Some(e) => {
            let eta = parse(e, Dimension::Viscosity)
                .map_err(|err| InputError(format!("--eta: {err}")))?;
            if eta < 0.0 {
                return Err(InputError(format!("--eta must be >= 0, got {e}")).into());
            }
            Some(eta)
        }
        None => None,
    };
    let (source, eta_pa_s) = FluidSource::resolve(fluid, yield_stress, eta);
    Ok(ResolvedFluid { source, eta_pa_s, speed })
}

fn report(
    configuration: &str,
    equation: &str,
    inputs: Value,
    fluid: &ResolvedFluid,
    viscous: Option<Viscous>,
    torque: BrakeTorque,
    as_json: bool,
) -> CommandResult {
    let report = BrakeFormulaReport {
        configuration,
        equation,
        inputs,
        fluid: &fluid.source,
        viscous,
        torque,
    };
    if as_json {
        return print_json(&report.json());
    }
    crate::out!("{}", report.text());
    Ok(())
}

fn coil(a: CoilArgs) -> CommandResult {
    let cw = length("--window-width", &a.window_width)?;
    let ch = length("--window-height", &a.window_height)?;
    let inner = length("--inner-radius", &a.inner_radius)?;
    let current =
        parse(&a.current, Dimension::Current).map_err(|e| InputError(format!("--current: {e}")))?;
    let temperature = parse(&a.temperature, Dimension::TemperatureCelsius)
        .map_err(|e| InputError(format!("--temperature: {e}")))?;
    let wire = match (a.awg, &a.wire_diameter) {
        (Some(awg), _) => CopperWire::awg(awg)?,
        (None, Some(d)) => CopperWire::from_diameter(length("--wire-diameter", d)?)?,
        (None, None) => return Err(InputError("give --awg or --wire-diameter".into()).into()),
    };
    let window = formula::turns_in_window(cw, ch, wire.diameter_m / 2.0)?;
    let turns = a.turns.unwrap_or(window.turns);
    if let Some(warning) = formula_report::turns_warning(turns, &window) {
        eprintln!("warning: {warning}");
    }
    let mean_radius = formula::coil_mean_radius(inner, cw);
    let electrics = formula::coil_electrics(turns, mean_radius, &wire, current, temperature)?;
    if let Some(warning) = formula_report::rating_warning(&wire, current) {
        eprintln!("warning: {warning}");
    }
    let report = CoilReport {
        window_width_m: cw,
        window_height_m: ch,
        inner_radius_m: inner,
        wire: &wire,
        current_a: current,
        temperature_c: temperature,
        window,
        turns,
        mean_radius_m: mean_radius,
        electrics,
    };
    if a.json {
        return print_json(&report.json());
    }
    crate::out!("{}", report.text());
    Ok(())
}
