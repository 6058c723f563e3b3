//! Reports of the thesis's closed-form models (`mrbrake_design::formula`): the brake torque of a
//! configuration (single disc, multi-disc, drum, multi-drum) with where its yield stress and
//! viscosity came from, and the coil of a winding window; as text and JSON.

use std::fmt::Write as _;

use mrbrake_design::formula::{BrakeTorque, CoilElectrics, Viscous, WindowTurns};
use mrbrake_materials::{CopperWire, MrFluid};
use serde_json::{Value, json};

/// Where the yield stress (and the viscosity of the viscous term) of a closed-form torque came
/// from.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidSource {
    /// Yield stress τ_y (Pa).
    pub tau_y_pa: f64,
    /// Its origin: `"given"`, or the fluid's τ_y(B) curve at a flux density.
    pub tau_y_source: String,
    /// The flux density τ_y was read at (T); `None` when τ_y was given.
    pub b_t: Option<f64>,
    /// The fluid whose curve and viscosity were used.
    pub fluid: String,
    /// Origin of the viscosity: `"given"` or the fluid's off-state viscosity.
    pub eta_source: String,
}

/// Where a closed-form torque's yield stress comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum YieldStress {
    /// τ_y given directly (Pa).
    Given(f64),
    /// τ_y read from the fluid's τ_y(B) curve at this mean flux density (T).
    AtFluxDensity(f64),
}

impl FluidSource {
    /// The yield stress of `fluid` (given, or from its τ_y(B) curve) and its source, with the
    /// viscosity of the viscous term (Pa·s): `eta_pa_s` when given, else the fluid's off-state
    /// viscosity. Shared by the CLI's `formula` commands and the Python binding; the callers
    /// check the ranges of the values (with their own argument names).
    pub fn resolve(
        fluid: &MrFluid,
        yield_stress: YieldStress,
        eta_pa_s: Option<f64>,
    ) -> (Self, f64) {
        let (tau_y_pa, tau_y_source, b_t) = match yield_stress {
            YieldStress::Given(tau) => (tau, "given".to_string(), None),
            YieldStress::AtFluxDensity(b) => {
                (fluid.tau_y_of_b(b), format!("{} tau_y(B) at {b} T", fluid.name()), Some(b))
            }
        };
        let (eta, eta_source) = match eta_pa_s {
            Some(eta) => (eta, "given".to_string()),
            None => (fluid.viscosity_pa_s(), format!("{} off-state viscosity", fluid.name())),
        };
        let source =
            Self { tau_y_pa, tau_y_source, b_t, fluid: fluid.name().to_string(), eta_source };
        (source, eta)
    }
}

/// The torque of one brake configuration by a closed-form model.
#[derive(Debug, Clone, PartialEq)]
pub struct BrakeFormulaReport<'a> {
    /// Configuration name (e.g. `single-disc`).
    pub configuration: &'a str,
    /// Thesis equation numbers (e.g. `(3.6)/(3.7)`).
    pub equation: &'a str,
    /// The geometry inputs as a JSON object (e.g. `{"r1_m": …, "r2_m": …}`).
    pub inputs: Value,
    /// The yield stress and its source.
    pub fluid: &'a FluidSource,
    /// The viscous term's inputs, when a speed was given.
    pub viscous: Option<Viscous>,
    /// The result.
    pub torque: BrakeTorque,
}

impl BrakeFormulaReport<'_> {
    /// The inputs (geometry, yield stress and its source, the viscous term's inputs) as JSON.
    fn inputs_json(&self) -> Value {
        let mut inputs = self.inputs.clone();
        inputs["tau_y_Pa"] = json!(self.fluid.tau_y_pa);
        inputs["tau_y_source"] = json!(self.fluid.tau_y_source);
        if let Some(b) = self.fluid.b_t {
            inputs["B_T"] = json!(b);
            inputs["fluid"] = json!(self.fluid.fluid);
        }
        if let Some(v) = self.viscous {
            inputs["eta_Pa_s"] = json!(v.eta_pa_s);
            inputs["eta_source"] = json!(self.fluid.eta_source);
            inputs["omega_rad_s"] = json!(v.omega_rad_s);
            inputs["gap_m"] = json!(v.gap_m);
        }
        inputs
    }

    /// The JSON report: configuration, equation, inputs and the torque split.
    pub fn json(&self) -> Value {
        json!({
            "configuration": self.configuration,
            "equation": self.equation,
            "inputs": self.inputs_json(),
            "torque_Nm": self.torque.total_nm,
            "yield_torque_Nm": self.torque.yield_nm,
            "viscous_torque_Nm": self.torque.viscous_nm,
        })
    }

    /// The text report.
    pub fn text(&self) -> String {
        let (fluid, t) = (self.fluid, &self.torque);
        let mut out = String::new();
        let _ = writeln!(out, "{} brake, thesis {}", self.configuration, self.equation);
        let _ = writeln!(
            out,
            "  yield stress   tau_y = {:.4} kPa  ({})",
            fluid.tau_y_pa / 1e3,
            fluid.tau_y_source
        );
        if let Some(v) = self.viscous {
            let _ = writeln!(
                out,
                "  viscous term   eta = {} Pa·s ({}), omega = {:.4} rad/s, g = {} mm",
                v.eta_pa_s,
                fluid.eta_source,
                v.omega_rad_s,
                v.gap_m * 1e3
            );
            let _ = writeln!(out, "  yield torque   {:.4} N·m", t.yield_nm);
            let _ = writeln!(out, "  viscous torque {:.4} N·m", t.viscous_nm);
        }
        let _ = writeln!(out, "  torque         T = {:.4} N·m", t.total_nm);
        out
    }
}

/// A coil wound in a winding window, thesis (4.1)–(4.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoilReport<'a> {
    /// Radial width C_w of the window (m).
    pub window_width_m: f64,
    /// Axial height C_h of the window (m).
    pub window_height_m: f64,
    /// Inner radius of the winding (m).
    pub inner_radius_m: f64,
    /// The wire.
    pub wire: &'a CopperWire,
    /// Coil current (A).
    pub current_a: f64,
    /// Copper temperature (°C).
    pub temperature_c: f64,
    /// Turns that fit the window.
    pub window: WindowTurns,
    /// Turns used.
    pub turns: u32,
    /// Mean radius of the winding (m).
    pub mean_radius_m: f64,
    /// Wire length, resistance, current density, power.
    pub electrics: CoilElectrics,
}

/// The warning for more turns than fit the window by (4.2)/(4.3), if there are.
pub fn turns_warning(turns: u32, window: &WindowTurns) -> Option<String> {
    (turns > window.turns).then(|| {
        format!(
            "{turns} turns do not fit the window by (4.2)/(4.3) (at most {} turns)",
            window.turns
        )
    })
}

/// The warning for a current above the wire's rating (thesis Table 4.6), if it is.
pub fn rating_warning(wire: &CopperWire, current_a: f64) -> Option<String> {
    wire.thesis_current_rating_a.filter(|&limit| current_a > limit).map(|limit| {
        format!("{current_a} A exceeds the wire's rating of {limit} A (thesis Table 4.6)")
    })
}

impl CoilReport<'_> {
    /// The JSON report: the inputs, the turns, and the electrical figures.
    pub fn json(&self) -> Value {
        let (wire, window, e) = (self.wire, &self.window, &self.electrics);
        json!({
            "inputs": {
                "window_width_m": self.window_width_m, "window_height_m": self.window_height_m,
                "inner_radius_m": self.inner_radius_m, "wire_diameter_m": wire.diameter_m,
                "awg": wire.awg, "current_A": self.current_a, "temperature_C": self.temperature_c,
            },
            "layers_i": window.layers_i,
            "turns_fit": window.turns,
            "turns_exact": window.turns_exact,
            "turns": self.turns,
            "mean_radius_m": self.mean_radius_m,
            "wire_length_m": e.wire_length_m,
            "resistance_20C_ohm": e.resistance_20c_ohm,
            "resistance_ohm": e.resistance_ohm,
            "current_density_A_per_mm2": e.current_density_a_per_mm2,
            "conductor_current_density_A_per_mm2": e.conductor_current_density_a_per_mm2,
            "power_W": e.power_w,
            "voltage_V": e.voltage_v,
            "wire_current_rating_A": wire.thesis_current_rating_a,
        })
    }

    /// The text report.
    pub fn text(&self) -> String {
        let (wire, window, e) = (self.wire, &self.window, &self.electrics);
        let gauge = wire.awg.map_or(String::new(), |g| format!("AWG {g}, "));
        let mut out = String::new();
        let _ = writeln!(out, "coil, thesis (4.1)-(4.3)");
        let _ = writeln!(
            out,
            "  window         {:.3} mm (radial) × {:.3} mm (axial), inner radius {:.3} mm",
            self.window_width_m * 1e3,
            self.window_height_m * 1e3,
            self.inner_radius_m * 1e3
        );
        let _ =
            writeln!(out, "  wire           {gauge}{:.4} mm bare copper", wire.diameter_m * 1e3);
        let _ = writeln!(
            out,
            "  layers i       {} (4.2); turns that fit N_c = {:.2} -> {} (4.3)",
            window.layers_i, window.turns_exact, window.turns
        );
        let _ = writeln!(out, "  turns used     {}", self.turns);
        let _ = writeln!(
            out,
            "  wire length    {:.2} m (mean radius {:.3} mm)",
            e.wire_length_m,
            self.mean_radius_m * 1e3
        );
        // At 20 °C the two resistances are the same number: say it once.
        if (self.temperature_c - 20.0).abs() < 1e-9 {
            let _ = writeln!(out, "  resistance     {:.3} Ω at 20 °C", e.resistance_ohm);
        } else {
            let _ = writeln!(
                out,
                "  resistance     {:.3} Ω at 20 °C, {:.3} Ω at {} °C",
                e.resistance_20c_ohm, e.resistance_ohm, self.temperature_c
            );
        }
        let _ = writeln!(
            out,
            "  current        {} A: J_D = {:.3} A/mm² (4.1), {:.3} A/mm² in the copper",
            self.current_a, e.current_density_a_per_mm2, e.conductor_current_density_a_per_mm2
        );
        let _ = writeln!(out, "  power          {:.3} W at {:.3} V", e.power_w, e.voltage_v);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::formula::{coil_electrics, single_disc, turns_in_window};

    fn given(tau_y_pa: f64) -> FluidSource {
        FluidSource {
            tau_y_pa,
            tau_y_source: "given".into(),
            b_t: None,
            fluid: "mrf-122eg".into(),
            eta_source: "mrf-122eg off-state viscosity".into(),
        }
    }

    /// The README's `mrbrake formula single-disc` example, line for line.
    #[test]
    fn single_disc_text_is_the_readme_example() {
        let fluid = given(24_315.0);
        let report = BrakeFormulaReport {
            configuration: "single-disc",
            equation: "(3.6)/(3.7)",
            inputs: json!({ "discs": 1, "r1_m": 0.0225, "r2_m": 0.0275 }),
            fluid: &fluid,
            viscous: None,
            torque: single_disc(0.0225, 0.0275, 24_315.0, None).unwrap(),
        };
        assert_eq!(
            report.text(),
            "single-disc brake, thesis (3.6)/(3.7)\n  yield stress   tau_y = 24.3150 kPa  (given)\n  \
             torque         T = 0.9580 N·m\n"
        );
        let v = report.json();
        assert_eq!(v["inputs"]["tau_y_source"], "given");
        assert!(v["inputs"].get("eta_Pa_s").is_none(), "no viscous term without a speed: {v}");
        assert!((v["torque_Nm"].as_f64().unwrap() - 0.958).abs() < 5e-4, "{v}");
    }

    #[test]
    fn the_viscous_term_adds_its_inputs_and_lines() {
        let fluid = given(24_315.0);
        let viscous = Viscous { eta_pa_s: 0.09, omega_rad_s: 6.0, gap_m: 0.5e-3 };
        let report = BrakeFormulaReport {
            configuration: "single-disc",
            equation: "(3.6)/(3.7)",
            inputs: json!({}),
            fluid: &fluid,
            viscous: Some(viscous),
            torque: single_disc(0.0225, 0.0275, 24_315.0, Some(viscous)).unwrap(),
        };
        let text = report.text();
        assert!(text.contains("  viscous term   eta = 0.09 Pa·s (mrf-122eg off-state"), "{text}");
        assert_eq!(text.lines().count(), 6, "{text}");
        let omega = report.json()["inputs"]["omega_rad_s"].as_f64().unwrap();
        assert!((omega - 6.0).abs() < 1e-12, "{omega}");
    }

    /// The README's `mrbrake formula coil` example: 644 turns in the 10 × 14.4 mm window.
    #[test]
    fn coil_text_is_the_readme_example() {
        let wire = CopperWire::from_diameter(0.5e-3).unwrap();
        let window = turns_in_window(10e-3, 14.4e-3, 0.25e-3).unwrap();
        let electrics = coil_electrics(window.turns, 10e-3, &wire, 2.0, 20.0).unwrap();
        let report = CoilReport {
            window_width_m: 10e-3,
            window_height_m: 14.4e-3,
            inner_radius_m: 5e-3,
            wire: &wire,
            current_a: 2.0,
            temperature_c: 20.0,
            window,
            turns: window.turns,
            mean_radius_m: 10e-3,
            electrics,
        };
        let text = report.text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[3], "  layers i       32 (4.2); turns that fit N_c = 644.00 -> 644 (4.3)");
        assert_eq!(lines[8], "  power          14.212 W at 7.106 V");
        assert_eq!(report.json()["turns_fit"], 644);
        assert_eq!(turns_warning(644, &window), None);
        assert!(turns_warning(645, &window).unwrap().contains("at most 644 turns"));
        let awg24 = CopperWire::awg(24).unwrap();
        assert!(rating_warning(&awg24, 3.0).unwrap().contains("rating of 2.1 A"));
        assert_eq!(rating_warning(&awg24, 2.0), None);
    }
}
