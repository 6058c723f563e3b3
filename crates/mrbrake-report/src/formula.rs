//! Reports of the thesis's closed-form models (`mrbrake_design::formula`): the brake torque of a
//! configuration (single disc, multi-disc, drum, multi-drum) with where its yield stress and
//! viscosity came from, and the coil of a winding window; as text and JSON. The requests and their
//! rules are the design crate's ([`mrbrake_design::formula::torque`],
//! [`mrbrake_design::formula::coil`]); this module only presents their answers.

use std::fmt::Write as _;

use mrbrake_design::formula::{ClosedFormBrake, ClosedFormCoil, ClosedFormTorque, surface_radii};
use serde_json::{Value, json};

/// The report of a closed-form torque ([`mrbrake_design::formula::torque`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrakeFormulaReport<'a>(pub &'a ClosedFormTorque);

impl BrakeFormulaReport<'_> {
    /// The inputs (geometry, yield stress and its source, the viscous term's inputs) as JSON.
    fn inputs_json(&self) -> Value {
        let t = self.0;
        let mut inputs = match t.brake {
            ClosedFormBrake::Discs { discs, r1_m, r2_m } => {
                json!({ "discs": discs, "r1_m": r1_m, "r2_m": r2_m })
            }
            ClosedFormBrake::Drum { r_m, h_m } => json!({ "r_m": r_m, "h_m": h_m }),
            ClosedFormBrake::MultiDrum { r0_m, h_m, d_m, g_m, surfaces } => json!({
                "r0_m": r0_m, "h_m": h_m, "d_m": d_m, "g_m": g_m, "surfaces": surfaces,
                "radii_m": surface_radii(&t.brake),
            }),
        };
        inputs["tau_y_Pa"] = json!(t.fluid.tau_y_pa);
        inputs["tau_y_source"] = json!(t.fluid.tau_y_source);
        if let Some(b) = t.fluid.b_t {
            inputs["B_T"] = json!(b);
            inputs["fluid"] = json!(t.fluid.fluid);
        }
        if let Some(v) = t.viscous {
            inputs["eta_Pa_s"] = json!(v.eta_pa_s);
            inputs["eta_source"] = json!(t.fluid.eta_source);
            inputs["omega_rad_s"] = json!(v.omega_rad_s);
            inputs["gap_m"] = json!(v.gap_m);
        }
        inputs
    }

    /// The JSON report: configuration, equation, inputs and the torque split.
    pub fn json(&self) -> Value {
        let t = self.0;
        json!({
            "configuration": t.brake.name(),
            "equation": t.brake.equation(),
            "inputs": self.inputs_json(),
            "torque_Nm": t.torque.total_nm,
            "yield_torque_Nm": t.torque.yield_nm,
            "viscous_torque_Nm": t.torque.viscous_nm,
        })
    }

    /// The text report.
    pub fn text(&self) -> String {
        let (fluid, t) = (&self.0.fluid, &self.0.torque);
        let mut out = String::new();
        let _ = writeln!(out, "{} brake, thesis {}", self.0.brake.name(), self.0.brake.equation());
        let _ = writeln!(
            out,
            "  yield stress   tau_y = {:.4} kPa  ({})",
            fluid.tau_y_pa / 1e3,
            fluid.tau_y_source
        );
        if let Some(v) = self.0.viscous {
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

/// The report of a coil in a winding window ([`mrbrake_design::formula::coil`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoilReport<'a>(pub &'a ClosedFormCoil);

impl CoilReport<'_> {
    /// The JSON report: the inputs, the turns, and the electrical figures.
    pub fn json(&self) -> Value {
        let c = self.0;
        let (wire, window, e) = (&c.wire, &c.window, &c.electrics);
        json!({
            "inputs": {
                "window_width_m": c.window_width_m, "window_height_m": c.window_height_m,
                "inner_radius_m": c.inner_radius_m, "wire_diameter_m": wire.diameter_m,
                "awg": wire.awg, "current_A": c.current_a, "temperature_C": c.temperature_c,
            },
            "layers_i": window.layers_i,
            "turns_fit": window.turns,
            "turns_exact": window.turns_exact,
            "turns": c.turns,
            "mean_radius_m": c.mean_radius_m,
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
        let c = self.0;
        let (wire, window, e) = (&c.wire, &c.window, &c.electrics);
        let gauge = wire.awg.map_or(String::new(), |g| format!("AWG {g}, "));
        let mut out = String::new();
        let _ = writeln!(out, "coil, thesis (4.1)-(4.3)");
        let _ = writeln!(
            out,
            "  window         {:.3} mm (radial) × {:.3} mm (axial), inner radius {:.3} mm",
            c.window_width_m * 1e3,
            c.window_height_m * 1e3,
            c.inner_radius_m * 1e3
        );
        let _ =
            writeln!(out, "  wire           {gauge}{:.4} mm bare copper", wire.diameter_m * 1e3);
        let _ = writeln!(
            out,
            "  layers i       {} (4.2); turns that fit N_c = {:.2} -> {} (4.3)",
            window.layers_i, window.turns_exact, window.turns
        );
        let _ = writeln!(out, "  turns used     {}", c.turns);
        let _ = writeln!(
            out,
            "  wire length    {:.2} m (mean radius {:.3} mm)",
            e.wire_length_m,
            c.mean_radius_m * 1e3
        );
        // At 20 °C the two resistances are the same number: say it once.
        if (c.temperature_c - 20.0).abs() < 1e-9 {
            let _ = writeln!(out, "  resistance     {:.3} Ω at 20 °C", e.resistance_ohm);
        } else {
            let _ = writeln!(
                out,
                "  resistance     {:.3} Ω at 20 °C, {:.3} Ω at {} °C",
                e.resistance_20c_ohm, e.resistance_ohm, c.temperature_c
            );
        }
        let _ = writeln!(
            out,
            "  current        {} A: J_D = {:.3} A/mm² (4.1), {:.3} A/mm² in the copper",
            c.current_a, e.current_density_a_per_mm2, e.conductor_current_density_a_per_mm2
        );
        let _ = writeln!(out, "  power          {:.3} W at {:.3} V", e.power_w, e.voltage_v);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::formula::{
        CoilRequest, TorqueRequest, Viscous, WireChoice, coil, rating_warning, torque,
        turns_warning,
    };
    use mrbrake_materials::CopperWire;

    fn single_disc(speed_rad_s: Option<f64>, eta_pa_s: Option<f64>) -> ClosedFormTorque {
        torque(&TorqueRequest {
            brake: ClosedFormBrake::Discs { discs: 1, r1_m: 0.0225, r2_m: 0.0275 },
            tau_y_pa: Some(24_315.0),
            b_t: None,
            fluid: None,
            speed_rad_s,
            eta_pa_s,
            gap_m: speed_rad_s.map(|_| 0.5e-3),
        })
        .unwrap()
    }

    /// The README's `mrbrake formula single-disc` example, line for line.
    #[test]
    fn single_disc_text_is_the_readme_example() {
        let t = single_disc(None, None);
        let report = BrakeFormulaReport(&t);
        assert_eq!(
            report.text(),
            "single-disc brake, thesis (3.6)/(3.7)\n  yield stress   tau_y = 24.3150 kPa  (given)\n  \
             torque         T = 0.9580 N·m\n"
        );
        let v = report.json();
        assert_eq!(v["inputs"]["tau_y_source"], "given");
        assert_eq!(v["inputs"]["discs"], 1);
        assert!(v["inputs"].get("eta_Pa_s").is_none(), "no viscous term without a speed: {v}");
        assert!((v["torque_Nm"].as_f64().unwrap() - 0.958).abs() < 5e-4, "{v}");
    }

    #[test]
    fn the_viscous_term_adds_its_inputs_and_lines() {
        let t = single_disc(Some(6.0), Some(0.09));
        assert_eq!(t.viscous, Some(Viscous { eta_pa_s: 0.09, omega_rad_s: 6.0, gap_m: 0.5e-3 }));
        let report = BrakeFormulaReport(&t);
        let text = report.text();
        assert!(text.contains("  viscous term   eta = 0.09 Pa·s (given)"), "{text}");
        assert_eq!(text.lines().count(), 6, "{text}");
        let omega = report.json()["inputs"]["omega_rad_s"].as_f64().unwrap();
        assert!((omega - 6.0).abs() < 1e-12, "{omega}");
    }

    /// The README's `mrbrake formula coil` example: 644 turns in the 10 × 14.4 mm window.
    #[test]
    fn coil_text_is_the_readme_example() {
        let c = coil(&CoilRequest {
            window_width_m: 10e-3,
            window_height_m: 14.4e-3,
            wire: Some(WireChoice::Diameter(0.5e-3)),
            inner_radius_m: Some(5e-3),
            turns: None,
            current_a: Some(2.0),
            temperature_c: Some(20.0),
        })
        .unwrap();
        let report = CoilReport(&c);
        let text = report.text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[3], "  layers i       32 (4.2); turns that fit N_c = 644.00 -> 644 (4.3)");
        assert_eq!(lines[8], "  power          14.212 W at 7.106 V");
        assert_eq!(report.json()["turns_fit"], 644);
        assert_eq!(turns_warning(644, &c.window), None);
        assert!(turns_warning(645, &c.window).unwrap().contains("at most 644 turns"));
        let awg24 = CopperWire::awg(24).unwrap();
        assert!(rating_warning(&awg24, 3.0).unwrap().contains("rating of 2.1 A"));
        assert_eq!(rating_warning(&awg24, 2.0), None);
    }
}
