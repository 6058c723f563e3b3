//! The spec's material factors (`[fluid]`, `[steel]`) in the analysis: at their defaults the
//! results are bit-identical to a spec without them; the yield-stress scale scales the yield
//! torque exactly (the field does not depend on it); a partly filled gap and a weaker steel brake
//! less; out-of-range factors are input errors naming the field.

use mrbrake_design::analysis::{Analysis, AnalysisOptions, AnalysisRequest};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{BrakeSpec, DEFAULT_SPEC_TOML};
use mrbrake_error::Kind as _;

fn spec_with(factors: &str) -> BrakeSpec {
    BrakeSpec::from_toml_str(&format!("{DEFAULT_SPEC_TOML}\n{factors}"), "factors.toml")
        .expect("a valid spec")
}

fn analyse(spec: &BrakeSpec) -> Analysis {
    let options =
        AnalysisOptions { mesh: MeshLevel::Coarse, points: 3, ..AnalysisOptions::default() };
    AnalysisRequest::of(spec).options(options).run().expect("the analysis runs")
}

fn yield_at_max(a: &Analysis) -> f64 {
    a.torque_current_curve.last().unwrap().yield_torque_nm
}

#[test]
fn factors_at_their_defaults_change_nothing_and_are_not_written() {
    let plain = spec_with("");
    let explicit = spec_with(
        "[fluid]\nyield_stress_scale = 1.0\nfill_fraction = 1.0\n[steel]\nB_scale = 1.0\n",
    );
    assert_eq!(plain, explicit);
    assert_eq!(serde_json::to_string(&plain).unwrap(), serde_json::to_string(&explicit).unwrap());
    let (a, b) = (analyse(&plain), analyse(&explicit));
    for (p, q) in a.torque_current_curve.iter().zip(&b.torque_current_curve) {
        assert_eq!(p.torque_nm.to_bits(), q.torque_nm.to_bits());
        assert_eq!(p.thesis_formula_nm.to_bits(), q.thesis_formula_nm.to_bits());
    }
}

#[test]
fn each_factor_moves_the_torque_its_way() {
    let nominal = analyse(&spec_with(""));
    let t0 = yield_at_max(&nominal);
    // The field does not see the yield stress: the yield torque scales exactly.
    let scaled = analyse(&spec_with("[fluid]\nyield_stress_scale = 0.85\n"));
    assert!((yield_at_max(&scaled) - 0.85 * t0).abs() < 1e-9 * t0);
    // Air in the gaps: half the fluid surface carries stress. The gap's permeance drops, so a
    // larger share of the coil's mmf falls across it: H in the gap, hence B in the fluid share,
    // rises a little, and the torque falls by somewhat less than half (5.38 -> 2.77 N·m on the
    // coarse mesh).
    let half = analyse(&spec_with("[fluid]\nfill_fraction = 0.5\n"));
    let t_half = yield_at_max(&half);
    assert!(t_half > 0.5 * t0 && t_half < 0.6 * t0, "{t_half} vs {t0}");
    // The off-state (viscous) torque scales with the wetted share too.
    let off = |a: &Analysis| {
        a.torque_current_curve[0].torque_nm - AnalysisOptions::default().seal_friction_nm
    };
    assert!((off(&half) - 0.5 * off(&nominal)).abs() < 1e-9 * off(&nominal).abs().max(1e-12));
    // A steel that saturates lower, and a fluid that magnetises less, both brake less.
    let weak_steel = analyse(&spec_with("[steel]\nB_scale = 0.8\n"));
    assert!(yield_at_max(&weak_steel) < t0);
    let weak_fluid = analyse(&spec_with("[fluid]\nB_scale = 0.8\n"));
    assert!(yield_at_max(&weak_fluid) < t0);
}

#[test]
fn out_of_range_factors_are_input_errors_naming_the_field() {
    for (text, field) in [
        ("[fluid]\nfill_fraction = 0.0\n", "fluid.fill_fraction"),
        ("[fluid]\nyield_stress_scale = -1\n", "fluid.yield_stress_scale"),
        ("[steel]\nconductivity_S_per_m = 1e9\n", "steel.conductivity_S_per_m"),
    ] {
        let err = spec_with(text).validate().unwrap_err();
        assert!(err.is_input_error());
        let message = err.to_string();
        assert!(message.contains("factors.toml:") && message.contains(field), "{message}");
    }
    let unknown =
        BrakeSpec::from_toml_str(&format!("{DEFAULT_SPEC_TOML}\n[fluid]\nfill = 0.5\n"), "u.toml");
    assert!(unknown.unwrap_err().is_input_error());
}
