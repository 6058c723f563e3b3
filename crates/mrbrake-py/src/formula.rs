//! `mrbrake.formula`: the thesis's closed-form models (`mrbrake::design::formula`) as the CLI's
//! `mrbrake formula … --json` documents (composed by `mrbrake::report::formula`).
//!
//! Quantities are floats in SI or strings with a unit (`"22.5mm"`, `"60rpm"`); argument names in
//! error messages are the Python ones.

use mrbrake::design::formula::{self, BrakeTorque, Viscous};
use mrbrake::materials::{CopperWire, library};
use mrbrake::report::formula::{BrakeFormulaReport, CoilReport, FluidSource, YieldStress};
use mrbrake::units::Dimension;
use pyo3::prelude::*;
use serde_json::{Value, json};

use crate::convert::{json_to_py, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(formula_disc, m)?)?;
    m.add_function(wrap_pyfunction!(formula_drum, m)?)?;
    m.add_function(wrap_pyfunction!(formula_multi_drum, m)?)?;
    m.add_function(wrap_pyfunction!(formula_coil, m)?)?;
    Ok(())
}

/// An optional quantity: `None` stays `None`.
fn optional(
    value: Option<&Bound<'_, PyAny>>,
    dimension: Dimension,
    name: &str,
) -> PyResult<Option<f64>> {
    match value {
        Some(v) if !v.is_none() => quantity(Some(v), "", dimension, name).map(Some),
        _ => Ok(None),
    }
}

/// The fluid arguments shared by the torque formulas, resolved as the CLI does.
struct Fluid {
    source: FluidSource,
    eta_pa_s: f64,
    speed: Option<f64>,
}

impl Fluid {
    fn from_py(
        tau_y: Option<&Bound<'_, PyAny>>,
        b: Option<&Bound<'_, PyAny>>,
        fluid: &str,
        speed: Option<&Bound<'_, PyAny>>,
        eta: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let mr_fluid = library::fluid(fluid).map_err(error::to_py)?;
        let tau_y = optional(tau_y, Dimension::Stress, "tau_y")?;
        let b = optional(b, Dimension::FluxDensity, "b")?;
        let yield_stress = match (tau_y, b) {
            (Some(_), Some(_)) => return Err(error::input("give tau_y or b, not both")),
            (Some(t), None) if t >= 0.0 => YieldStress::Given(t),
            (Some(t), None) => return Err(error::input(format!("tau_y must be >= 0, got {t}"))),
            (None, Some(b)) if (0.0..=3.0).contains(&b) => YieldStress::AtFluxDensity(b),
            (None, Some(b)) => {
                return Err(error::input(format!("b must be between 0 T and 3 T, got {b}")));
            }
            (None, None) => return Err(error::input("give tau_y or b")),
        };
        let eta = optional(eta, Dimension::Viscosity, "eta")?;
        if let Some(e) = eta.filter(|e| e.is_nan() || *e < 0.0) {
            return Err(error::input(format!("eta must be >= 0, got {e}")));
        }
        let speed = optional(speed, Dimension::AngularVelocity, "speed")?;
        let (source, eta_pa_s) = FluidSource::resolve(mr_fluid, yield_stress, eta);
        Ok(Self { source, eta_pa_s, speed })
    }

    /// The viscous term of a disc or drum brake, whose gap is needed only with a speed.
    fn viscous(&self, gap: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Viscous>> {
        let Some(omega_rad_s) = self.speed else { return Ok(None) };
        let gap_m = optional(gap, Dimension::Length, "gap")?
            .ok_or_else(|| error::input("speed needs gap (the fluid gap sheared at that speed)"))?;
        Ok(Some(Viscous { eta_pa_s: self.eta_pa_s, omega_rad_s, gap_m }))
    }

    fn report<'py>(
        &self,
        py: Python<'py>,
        names: (&str, &str),
        inputs: Value,
        viscous: Option<Viscous>,
        torque: BrakeTorque,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (configuration, equation) = names;
        let report = BrakeFormulaReport {
            configuration,
            equation,
            inputs,
            fluid: &self.source,
            viscous,
            torque,
        };
        json_to_py(py, &report.json())
    }
}

/// Disc brake torque, thesis (3.6)–(3.8) (`discs = 1`: single disc); the `formula single-disc` /
/// `multi-disc --json` document.
#[pyfunction]
#[pyo3(signature = (discs, r1, r2, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None, gap=None))]
#[allow(clippy::too_many_arguments)]
fn formula_disc<'py>(
    py: Python<'py>,
    discs: u32,
    r1: &Bound<'py, PyAny>,
    r2: &Bound<'py, PyAny>,
    tau_y: Option<&Bound<'py, PyAny>>,
    b: Option<&Bound<'py, PyAny>>,
    fluid: &str,
    speed: Option<&Bound<'py, PyAny>>,
    eta: Option<&Bound<'py, PyAny>>,
    gap: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let r1 = quantity(Some(r1), "", Dimension::Length, "r1")?;
    let r2 = quantity(Some(r2), "", Dimension::Length, "r2")?;
    let fluid = Fluid::from_py(tau_y, b, fluid, speed, eta)?;
    let viscous = fluid.viscous(gap)?;
    let torque =
        formula::multi_disc(discs, r1, r2, fluid.source.tau_y_pa, viscous).map_err(error::to_py)?;
    let names = if discs == 1 { ("single-disc", "(3.6)/(3.7)") } else { ("multi-disc", "(3.8)") };
    let inputs = json!({ "discs": discs, "r1_m": r1, "r2_m": r2 });
    fluid.report(py, names, inputs, viscous, torque)
}

/// Drum brake torque, thesis (3.9); the `formula drum --json` document.
#[pyfunction]
#[pyo3(signature = (r, h, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None, gap=None))]
#[allow(clippy::too_many_arguments)]
fn formula_drum<'py>(
    py: Python<'py>,
    r: &Bound<'py, PyAny>,
    h: &Bound<'py, PyAny>,
    tau_y: Option<&Bound<'py, PyAny>>,
    b: Option<&Bound<'py, PyAny>>,
    fluid: &str,
    speed: Option<&Bound<'py, PyAny>>,
    eta: Option<&Bound<'py, PyAny>>,
    gap: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let r = quantity(Some(r), "", Dimension::Length, "r")?;
    let h = quantity(Some(h), "", Dimension::Length, "h")?;
    let fluid = Fluid::from_py(tau_y, b, fluid, speed, eta)?;
    let viscous = fluid.viscous(gap)?;
    let torque = formula::drum(r, h, fluid.source.tau_y_pa, viscous).map_err(error::to_py)?;
    fluid.report(py, ("drum", "(3.9)"), json!({ "r_m": r, "h_m": h }), viscous, torque)
}

/// Multi-drum brake torque, thesis (4.4)/(4.5); the `formula multi-drum --json` document.
#[pyfunction]
#[pyo3(signature = (r0, h, d, g, surfaces, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None))]
#[allow(clippy::too_many_arguments)]
fn formula_multi_drum<'py>(
    py: Python<'py>,
    r0: &Bound<'py, PyAny>,
    h: &Bound<'py, PyAny>,
    d: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    surfaces: u32,
    tau_y: Option<&Bound<'py, PyAny>>,
    b: Option<&Bound<'py, PyAny>>,
    fluid: &str,
    speed: Option<&Bound<'py, PyAny>>,
    eta: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let [r0, h, d, g] = [(r0, "r0"), (h, "h"), (d, "d"), (g, "g")]
        .map(|(v, name)| quantity(Some(v), "", Dimension::Length, name));
    let (r0, h, d, g) = (r0?, h?, d?, g?);
    let fluid = Fluid::from_py(tau_y, b, fluid, speed, eta)?;
    let eta_omega = fluid.speed.map(|w| (fluid.eta_pa_s, w));
    let torque = formula::multi_drum(r0, h, d, g, surfaces, fluid.source.tau_y_pa, eta_omega)
        .map_err(error::to_py)?;
    let radii = formula::multi_drum_radii(r0, d, g, surfaces);
    let inputs = json!({
        "r0_m": r0, "h_m": h, "d_m": d, "g_m": g, "surfaces": surfaces, "radii_m": radii,
    });
    let viscous =
        fluid.speed.map(|w| Viscous { eta_pa_s: fluid.eta_pa_s, omega_rad_s: w, gap_m: g });
    fluid.report(py, ("multi-drum", "(4.4)/(4.5)"), inputs, viscous, torque)
}

/// A coil in a winding window, thesis (4.1)–(4.3); the `formula coil --json` document.
#[pyfunction]
#[pyo3(signature = (window_width, window_height, *, awg=None, wire_diameter=None, inner_radius=None, turns=None, current=None, temperature=None))]
#[allow(clippy::too_many_arguments)]
fn formula_coil<'py>(
    py: Python<'py>,
    window_width: &Bound<'py, PyAny>,
    window_height: &Bound<'py, PyAny>,
    awg: Option<u32>,
    wire_diameter: Option<&Bound<'py, PyAny>>,
    inner_radius: Option<&Bound<'py, PyAny>>,
    turns: Option<u32>,
    current: Option<&Bound<'py, PyAny>>,
    temperature: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let cw = quantity(Some(window_width), "", Dimension::Length, "window_width")?;
    let ch = quantity(Some(window_height), "", Dimension::Length, "window_height")?;
    let inner = quantity(inner_radius, "5mm", Dimension::Length, "inner_radius")?;
    let current_a = quantity(current, "2A", Dimension::Current, "current")?;
    let temperature_c = quantity(temperature, "20C", Dimension::TemperatureCelsius, "temperature")?;
    let wire = match (awg, optional(wire_diameter, Dimension::Length, "wire_diameter")?) {
        (Some(_), Some(_)) => return Err(error::input("give awg or wire_diameter, not both")),
        (Some(awg), None) => CopperWire::awg(awg),
        (None, Some(d)) => CopperWire::from_diameter(d),
        (None, None) => return Err(error::input("give awg or wire_diameter")),
    }
    .map_err(error::to_py)?;
    let window = formula::turns_in_window(cw, ch, wire.diameter_m / 2.0).map_err(error::to_py)?;
    let turns = turns.unwrap_or(window.turns);
    let mean_radius_m = formula::coil_mean_radius(inner, cw);
    let electrics = formula::coil_electrics(turns, mean_radius_m, &wire, current_a, temperature_c)
        .map_err(error::to_py)?;
    let report = CoilReport {
        window_width_m: cw,
        window_height_m: ch,
        inner_radius_m: inner,
        wire: &wire,
        current_a,
        temperature_c,
        window,
        turns,
        mean_radius_m,
        electrics,
    };
    json_to_py(py, &report.json())
}
