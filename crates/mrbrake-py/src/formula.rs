//! `mrbrake.formula`: the thesis's closed-form models (`mrbrake::design::formula`) as the CLI's
//! `mrbrake formula … --json` documents (composed by `mrbrake::report::formula`).
//!
//! Quantities are floats in SI or strings with a unit (`"22.5mm"`, `"60rpm"`). The binding only
//! translates its arguments into the library's requests (`formula::torque`, `formula::coil`),
//! which hold every range rule; their messages name the fields as the Python arguments do.

use mrbrake::design::formula::{self, ClosedFormBrake, CoilRequest, TorqueRequest, WireChoice};
use mrbrake::report::formula::{BrakeFormulaReport, CoilReport};
use mrbrake::units::Dimension;
use pyo3::prelude::*;

use crate::convert::{json_to_py, optional, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(formula_disc, m)?)?;
    m.add_function(wrap_pyfunction!(formula_drum, m)?)?;
    m.add_function(wrap_pyfunction!(formula_multi_drum, m)?)?;
    m.add_function(wrap_pyfunction!(formula_coil, m)?)?;
    Ok(())
}

/// A required length.
fn length(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    quantity(Some(value), "", Dimension::Length, name)
}

/// The fluid and viscous-term arguments shared by the torque formulas, translated.
struct FluidArgs<'a, 'py> {
    tau_y: Option<&'a Bound<'py, PyAny>>,
    b: Option<&'a Bound<'py, PyAny>>,
    fluid: &'a str,
    speed: Option<&'a Bound<'py, PyAny>>,
    eta: Option<&'a Bound<'py, PyAny>>,
    gap: Option<&'a Bound<'py, PyAny>>,
}

impl FluidArgs<'_, '_> {
    /// The library's request for `brake` (which checks every value) and its JSON document.
    fn torque<'py>(&self, py: Python<'py>, brake: ClosedFormBrake) -> PyResult<Bound<'py, PyAny>> {
        let request = TorqueRequest {
            brake,
            tau_y_pa: optional(self.tau_y, Dimension::Stress, "tau_y")?,
            b_t: optional(self.b, Dimension::FluxDensity, "b")?,
            fluid: Some(self.fluid.to_string()),
            speed_rad_s: optional(self.speed, Dimension::AngularVelocity, "speed")?,
            eta_pa_s: optional(self.eta, Dimension::Viscosity, "eta")?,
            gap_m: optional(self.gap, Dimension::Length, "gap")?,
        };
        let answer = formula::torque(&request).map_err(error::to_py)?;
        json_to_py(py, &BrakeFormulaReport(&answer).json())
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
    let brake = ClosedFormBrake::Discs { discs, r1_m: length(r1, "r1")?, r2_m: length(r2, "r2")? };
    FluidArgs { tau_y, b, fluid, speed, eta, gap }.torque(py, brake)
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
    let brake = ClosedFormBrake::Drum { r_m: length(r, "r")?, h_m: length(h, "h")? };
    FluidArgs { tau_y, b, fluid, speed, eta, gap }.torque(py, brake)
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
    let brake = ClosedFormBrake::MultiDrum {
        r0_m: length(r0, "r0")?,
        h_m: length(h, "h")?,
        d_m: length(d, "d")?,
        g_m: length(g, "g")?,
        surfaces,
    };
    FluidArgs { tau_y, b, fluid, speed, eta, gap: None }.torque(py, brake)
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
    let wire = match (awg, optional(wire_diameter, Dimension::Length, "wire_diameter")?) {
        (Some(_), Some(_)) => return Err(error::input("give awg or wire_diameter, not both")),
        (Some(awg), None) => Some(WireChoice::Awg(awg)),
        (None, Some(d)) => Some(WireChoice::Diameter(d)),
        (None, None) => None,
    };
    let request = CoilRequest {
        window_width_m: length(window_width, "window_width")?,
        window_height_m: length(window_height, "window_height")?,
        wire,
        inner_radius_m: optional(inner_radius, Dimension::Length, "inner_radius")?,
        turns,
        current_a: optional(current, Dimension::Current, "current")?,
        temperature_c: optional(temperature, Dimension::TemperatureCelsius, "temperature")?,
    };
    let answer = formula::coil(&request).map_err(error::to_py)?;
    json_to_py(py, &CoilReport(&answer).json())
}
