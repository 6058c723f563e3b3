//! Reports of the material library (`mrbrake_materials`): the list of materials and one
//! material's curves, derived values and provenance, as text and JSON.

use std::fmt::Write as _;

use mrbrake_materials::{BhCurve, Magnetic, Material, MrFluid, library};
use serde_json::{Value, json};

/// Field strengths (A/m) at which `materials show` reports B for a non-linear material, unless
/// asked for others (the CLI and the Python package share them).
pub const DEFAULT_H_A_PER_M: [f64; 3] = [1e3, 5e3, 20e3];

/// Flux densities (T) at which `materials show` reports τ_y for an MR fluid, unless asked for others
/// (0.46 and 0.49 T are thesis points).
pub const DEFAULT_B_T: [f64; 8] = [0.1, 0.2, 0.3, 0.46, 0.49, 0.6, 0.8, 1.0];

/// The JSON list of `materials` (name, kind, trust, description) with the default fluid.
pub fn list_json(materials: &[&Material]) -> Value {
    let materials: Vec<Value> = materials
        .iter()
        .map(|m| {
            json!({
                "name": m.name, "kind": m.kind, "trust": m.provenance.trust, "description": m.description,
            })
        })
        .collect();
    json!({ "default_fluid": library::DEFAULT_FLUID, "materials": materials })
}

/// The table of `materials`: name, kind, trust and description, one per line.
pub fn list_text(materials: &[&Material]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{:<22} {:<9} {:<12} description", "name", "kind", "trust");
    for m in materials {
        let _ = writeln!(
            out,
            "{:<22} {:<9} {:<12} {}",
            m.name,
            m.kind.as_str(),
            m.provenance.trust.as_str(),
            m.description
        );
    }
    out
}

/// The B-H curve as JSON, with B at the field strengths `h_values`.
fn curve_json(curve: &BhCurve, h_values: &[f64]) -> Value {
    let (h_last, b_last) = curve.last_point();
    json!({
        "points_H_A_per_m_B_T": curve.points(),
        "initial_relative_permeability": curve.initial_relative_permeability(),
        "B_at_H": h_values.iter().map(|&h| json!({ "H_A_per_m": h, "B_T": curve.b_of_h(h) })).collect::<Vec<_>>(),
        "last_point": { "H_A_per_m": h_last, "B_T": b_last },
        "beyond_last_point": "straight line of slope dB/dH = mu0",
        "interpolation": "monotone C1 cubic H(B) (Steffen 1990), odd first piece, exact at the points",
        "provenance": curve.provenance(),
    })
}

/// The fluid's part of the JSON report.
fn fluid_json(fluid: &MrFluid, b_values: &[f64], h_values: &[f64]) -> Value {
    let ys = fluid.yield_stress();
    json!({
        "tau_y_at_B": b_values.iter().map(|&b| json!({
            "B_T": b, "H_A_per_m": fluid.bh().h_of_b(b), "tau_y_Pa": fluid.tau_y_of_b(b),
        })).collect::<Vec<_>>(),
        "tau_y_at_H": h_values.iter().map(|&h| json!({
            "H_A_per_m": h, "B_T": fluid.bh().b_of_h(h), "tau_y_Pa": fluid.tau_y_of_h(h),
        })).collect::<Vec<_>>(),
        "tau_y_ceiling_Pa": fluid.tau_y_ceiling_pa(),
        "yield_stress": {
            "variable": ys.variable(),
            "points": ys.points(),
            "provenance": ys.provenance(),
        },
        "reference_checks": fluid.reference_checks(),
        "viscosities": fluid.viscosities,
        "iron_volume_fraction": fluid.iron_volume_fraction,
        "carrier": fluid.carrier,
        "density_kg_per_m3": fluid.density_kg_m3,
    })
}

/// The JSON report of material `m` (see [`show_text`] for `b_values` and `h_values`).
pub fn show_json(m: &Material, b_values: &[f64], h_values: &[f64]) -> Value {
    let mut v = json!({
        "name": m.name,
        "kind": m.kind,
        "description": m.description,
        "provenance": m.provenance,
        "density_kg_per_m3": m.density_kg_m3,
        "conductivity_S_per_m": m.conductivity_s_per_m,
        "mu_r_linear": m.mu_r_linear,
    });
    match (&m.magnetic, m.magnetic.bh_curve()) {
        (Magnetic::Linear { mu_r }, _) => {
            v["magnetic"] = json!({ "law": "linear", "mu_r": mu_r });
        }
        (_, Some(curve)) => {
            v["magnetic"] = json!({ "law": "non-linear", "bh_curve": curve_json(curve, h_values) });
        }
        (Magnetic::NonLinear(_), None) => v["magnetic"] = json!({ "law": "non-linear" }),
    }
    if let Some(fluid) = &m.fluid {
        v["fluid"] = fluid_json(fluid, b_values, h_values);
    }
    v
}

/// The text report of material `m`: provenance, density, the magnetic law (with B at the field
/// strengths `h_values`), for a fluid its yield stress at the flux densities `b_values`, viscosity
/// and reference points, and with `with_points` the B-H curve's points.
pub fn show_text(m: &Material, b_values: &[f64], h_values: &[f64], with_points: bool) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{} ({}): {}", m.name, m.kind.as_str(), m.description);
    let _ = writeln!(out, "  source  {}", m.provenance.source);
    let _ = writeln!(out, "  method  {}", m.provenance.method);
    let _ = writeln!(out, "  trust   {}", m.provenance.trust);
    if let Some(d) = &m.density_kg_m3 {
        let _ = writeln!(
            out,
            "  density {} kg/m³ ({}; trust {})",
            d.value, d.provenance.source, d.provenance.trust
        );
    }
    if let Some(s) = &m.conductivity_s_per_m {
        let _ = writeln!(out, "  conductivity {:.4e} S/m", s.value);
    }
    match (&m.magnetic, m.magnetic.bh_curve()) {
        (Magnetic::Linear { mu_r }, _) => _ = writeln!(out, "  magnetic: linear, mu_r = {mu_r}"),
        (Magnetic::NonLinear(_), None) => {
            _ = writeln!(out, "  magnetic: non-linear (analytic law)")
        }
        (_, Some(curve)) => {
            let (h_last, b_last) = curve.last_point();
            let _ = writeln!(
                out,
                "  magnetic: B-H curve, {} points up to H = {h_last} A/m, B = {b_last} T; slope mu0 beyond",
                curve.points().len()
            );
            let _ = writeln!(
                out,
                "    initial relative permeability {:.1}",
                curve.initial_relative_permeability()
            );
            for &h in h_values {
                let _ = writeln!(out, "    B({:>9.0} A/m) = {:.4} T", h, curve.b_of_h(h));
            }
            if let Some(mu_r) = m.mu_r_linear {
                let _ = writeln!(out, "    (the source's constant mu_r for linear solves: {mu_r})");
            }
        }
    }
    if let Some(fluid) = &m.fluid {
        fluid_text(&mut out, fluid, b_values);
    }
    if let (true, Some(curve)) = (with_points, m.magnetic.bh_curve()) {
        let _ = writeln!(out, "  B-H points:");
        let _ = writeln!(out, "    {:>14} {:>10}", "H [A/m]", "B [T]");
        for (h, b) in curve.points() {
            let _ = writeln!(out, "    {h:>14.6} {b:>10.6}");
        }
    }
    out
}

/// The fluid's part of the text report.
fn fluid_text(out: &mut String, fluid: &MrFluid, b_values: &[f64]) {
    let ys = fluid.yield_stress();
    let _ = writeln!(out, "  yield stress: {}", ys.provenance().method);
    let _ = writeln!(out, "    source {}", ys.provenance().source);
    let _ = writeln!(out, "    trust  {}", ys.provenance().trust);
    let _ = writeln!(out, "    tends to {:.0} Pa at high field", fluid.tau_y_ceiling_pa());
    let _ = writeln!(out, "    {:>8} {:>12} {:>12}", "B [T]", "H [A/m]", "tau_y [Pa]");
    for &b in b_values {
        let _ = writeln!(
            out,
            "    {:>8.4} {:>12.0} {:>12.1}",
            b,
            fluid.bh().h_of_b(b),
            fluid.tau_y_of_b(b)
        );
    }
    for v in &fluid.viscosities {
        let _ = writeln!(
            out,
            "  viscosity {} Pa.s at {} °C ({}; trust {})",
            v.pa_s, v.temperature_c, v.provenance.source, v.provenance.trust
        );
    }
    let _ = writeln!(
        out,
        "  iron volume fraction {} ; carrier {}",
        fluid.iron_volume_fraction.value, fluid.carrier
    );
    let checks = fluid.reference_checks();
    if !checks.is_empty() {
        let _ = writeln!(out, "  reference points (model vs reference):");
        let _ = writeln!(
            out,
            "    {:>8} {:>12} {:>12} {:>9}",
            "B [T]", "ref [Pa]", "model [Pa]", "error"
        );
        for c in checks {
            let b = c.reference.b_t.map_or("-".to_string(), |b| format!("{b:.4}"));
            let _ = writeln!(
                out,
                "    {:>8} {:>12.1} {:>12.1} {:>8.2}%",
                b, c.reference.tau_y_pa, c.model_tau_y_pa, c.error_percent
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_has_a_line_per_material_and_the_default_fluid() {
        let materials: Vec<&Material> =
            library::names().iter().map(|(name, _)| library::get(name).unwrap()).collect();
        let text = list_text(&materials);
        assert_eq!(text.lines().count(), materials.len() + 1);
        assert!(text.starts_with("name                   kind      trust        description\n"));
        let json = list_json(&materials);
        assert_eq!(json["default_fluid"], library::DEFAULT_FLUID);
        assert_eq!(json["materials"].as_array().unwrap().len(), materials.len());
    }

    #[test]
    fn a_fluid_shows_its_yield_stress_and_a_steel_its_curve() {
        let fluid = library::get("mrf-122eg").unwrap();
        let text = show_text(fluid, &[0.46], &[5e3], false);
        assert!(text.starts_with("mrf-122eg (mr-fluid): "), "{text}");
        assert!(text.contains("  yield stress: ") && !text.contains("B-H points"), "{text}");
        assert_eq!(
            show_json(fluid, &[0.46], &[]).pointer("/fluid/tau_y_at_B/0/B_T"),
            Some(&json!(0.46))
        );
        let steel = library::get("steel-1008").unwrap();
        let text = show_text(steel, &[], &[1e3, 2e4], true);
        assert_eq!(text.lines().filter(|l| l.starts_with("    B(")).count(), 2, "{text}");
        assert!(text.contains("  B-H points:\n"), "{text}");
        assert_eq!(show_json(steel, &[], &[1e3])["magnetic"]["law"], "non-linear");
    }
}
