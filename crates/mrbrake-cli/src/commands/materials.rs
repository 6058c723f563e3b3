//! `mrbrake materials …`: the built-in material library (names, curves, derived values, provenance).

use clap::{Args, Subcommand};
use mrbrake_materials::{BhCurve, Magnetic, Material, MrFluid, library};
use mrbrake_units::{Dimension, parse};
use serde_json::{Value, json};

use crate::exit::InputError;
use crate::output::print_json;

/// Field strengths [A/m] at which `show` reports B for a non-linear material.
const DEFAULT_H_A_PER_M: [f64; 3] = [1e3, 5e3, 20e3];

/// Flux densities (T) at which `show` reports τ_y for an MR fluid (0.46 and 0.49 T are thesis points).
const DEFAULT_B_T: [f64; 8] = [0.1, 0.2, 0.3, 0.46, 0.49, 0.6, 0.8, 1.0];

/// `mrbrake materials` subcommands.
#[derive(Debug, Subcommand)]
pub enum MaterialsCommand {
    /// List every built-in material with its kind, trust level and description.
    List(ListArgs),
    /// Show one material: B-H points, derived values (B at 1/5/20 kA/m, τ_y at chosen B), provenance.
    Show(ShowArgs),
}

/// Arguments of `materials list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Print a JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// Arguments of `materials show`.
#[derive(Debug, Args)]
pub struct ShowArgs {
    /// Material name, case-insensitive (see `mrbrake materials list`), e.g. steel-1008 or mrf-122eg.
    name: String,
    /// Flux densities at which to report τ_y for an MR fluid, comma-separated (e.g. 0.3T,460mT).
    #[arg(long, value_name = "FLUX_DENSITY", value_delimiter = ',', allow_hyphen_values = true)]
    b: Vec<String>,
    /// Field strengths at which to report B (and τ_y for a fluid), comma-separated (e.g. 1kA/m,50kA/m).
    #[arg(long, value_name = "FIELD_STRENGTH", value_delimiter = ',', allow_hyphen_values = true)]
    h: Vec<String>,
    /// Leave the table of curve points out of the text output.
    #[arg(long)]
    no_points: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs a `materials` subcommand.
pub fn run(command: MaterialsCommand) -> anyhow::Result<()> {
    match command {
        MaterialsCommand::List(a) => list(&a),
        MaterialsCommand::Show(a) => show(&a),
    }
}

fn list(a: &ListArgs) -> anyhow::Result<()> {
    let mut rows = Vec::new();
    for (name, _) in library::names() {
        rows.push(library::get(name)?);
    }
    if a.json {
        let materials: Vec<Value> = rows
            .iter()
            .map(|m| {
                json!({
                    "name": m.name, "kind": m.kind, "trust": m.provenance.trust, "description": m.description,
                })
            })
            .collect();
        return print_json(
            &json!({ "default_fluid": library::DEFAULT_FLUID, "materials": materials }),
        );
    }
    crate::outln!("{:<22} {:<9} {:<12} description", "name", "kind", "trust");
    for m in rows {
        crate::outln!(
            "{:<22} {:<9} {:<12} {}",
            m.name,
            m.kind.as_str(),
            m.provenance.trust.as_str(),
            m.description
        );
    }
    Ok(())
}

/// Parses a list of non-negative quantities of one dimension.
fn non_negative_values(flag: &str, texts: &[String], dim: Dimension) -> anyhow::Result<Vec<f64>> {
    texts
        .iter()
        .map(|t| {
            let v = parse(t, dim)?;
            if v < 0.0 {
                return Err(InputError(format!(
                    "{flag} {t}: must be >= 0 ({} in {})",
                    dim.describe(),
                    dim.si_unit()
                ))
                .into());
            }
            Ok(v)
        })
        .collect()
}

fn show(a: &ShowArgs) -> anyhow::Result<()> {
    let material = library::get(&a.name)?;
    let b_values = if a.b.is_empty() {
        DEFAULT_B_T.to_vec()
    } else {
        non_negative_values("--b", &a.b, Dimension::FluxDensity)?
    };
    let h_values = if a.h.is_empty() {
        DEFAULT_H_A_PER_M.to_vec()
    } else {
        non_negative_values("--h", &a.h, Dimension::FieldStrength)?
    };
    if a.json {
        return print_json(&show_json(material, &b_values, &h_values));
    }
    print_text(material, &b_values, &h_values, !a.no_points);
    Ok(())
}

fn curve_json(curve: &BhCurve, h_values: &[f64]) -> Value {
    let (h_last, b_last) = curve.last_point();
    json!({
        "points_H_A_per_m_B_T": curve.points(),
        "initial_relative_permeability": curve.initial_relative_permeability(),
        "b_at_h": h_values.iter().map(|&h| json!({ "H_A_per_m": h, "B_T": curve.b_of_h(h) })).collect::<Vec<_>>(),
        "last_point": { "H_A_per_m": h_last, "B_T": b_last },
        "beyond_last_point": "straight line of slope dB/dH = mu0",
        "interpolation": "monotone C1 cubic H(B) (Steffen 1990), odd first piece, exact at the points",
        "provenance": curve.provenance(),
    })
}

fn fluid_json(fluid: &MrFluid, b_values: &[f64], h_values: &[f64]) -> Value {
    let ys = fluid.yield_stress();
    json!({
        "tau_y_at_b": b_values.iter().map(|&b| json!({
            "B_T": b, "H_A_per_m": fluid.bh().h_of_b(b), "tau_y_Pa": fluid.tau_y_of_b(b),
        })).collect::<Vec<_>>(),
        "tau_y_at_h": h_values.iter().map(|&h| json!({
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
        "density_kg_m3": fluid.density_kg_m3,
    })
}

fn show_json(m: &Material, b_values: &[f64], h_values: &[f64]) -> Value {
    let mut v = json!({
        "name": m.name,
        "kind": m.kind,
        "description": m.description,
        "provenance": m.provenance,
        "density_kg_m3": m.density_kg_m3,
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

fn print_text(m: &Material, b_values: &[f64], h_values: &[f64], with_points: bool) {
    crate::outln!("{} ({}): {}", m.name, m.kind.as_str(), m.description);
    crate::outln!("  source  {}", m.provenance.source);
    crate::outln!("  method  {}", m.provenance.method);
    crate::outln!("  trust   {}", m.provenance.trust);
    if let Some(d) = &m.density_kg_m3 {
        crate::outln!(
            "  density {} kg/m³ ({}; trust {})",
            d.value,
            d.provenance.source,
            d.provenance.trust
        );
    }
    if let Some(s) = &m.conductivity_s_per_m {
        crate::outln!("  conductivity {:.4e} S/m", s.value);
    }
    match (&m.magnetic, m.magnetic.bh_curve()) {
        (Magnetic::Linear { mu_r }, _) => crate::outln!("  magnetic: linear, mu_r = {mu_r}"),
        (Magnetic::NonLinear(_), None) => crate::outln!("  magnetic: non-linear (analytic law)"),
        (_, Some(curve)) => {
            let (h_last, b_last) = curve.last_point();
            crate::outln!(
                "  magnetic: B-H curve, {} points up to H = {h_last} A/m, B = {b_last} T; slope mu0 beyond",
                curve.points().len()
            );
            crate::outln!(
                "    initial relative permeability {:.1}",
                curve.initial_relative_permeability()
            );
            for &h in h_values {
                crate::outln!("    B({:>9.0} A/m) = {:.4} T", h, curve.b_of_h(h));
            }
            if let Some(mu_r) = m.mu_r_linear {
                crate::outln!("    (the source's constant mu_r for linear solves: {mu_r})");
            }
        }
    }
    if let Some(fluid) = &m.fluid {
        print_fluid(fluid, b_values);
    }
    if let (true, Some(curve)) = (with_points, m.magnetic.bh_curve()) {
        crate::outln!("  B-H points:");
        crate::outln!("    {:>14} {:>10}", "H [A/m]", "B [T]");
        for (h, b) in curve.points() {
            crate::outln!("    {h:>14.6} {b:>10.6}");
        }
    }
}

fn print_fluid(fluid: &MrFluid, b_values: &[f64]) {
    let ys = fluid.yield_stress();
    crate::outln!("  yield stress: {}", ys.provenance().method);
    crate::outln!("    source {}", ys.provenance().source);
    crate::outln!("    trust  {}", ys.provenance().trust);
    crate::outln!("    tends to {:.0} Pa at high field", fluid.tau_y_ceiling_pa());
    crate::outln!("    {:>8} {:>12} {:>12}", "B [T]", "H [A/m]", "tau_y [Pa]");
    for &b in b_values {
        crate::outln!(
            "    {:>8.4} {:>12.0} {:>12.1}",
            b,
            fluid.bh().h_of_b(b),
            fluid.tau_y_of_b(b)
        );
    }
    for v in &fluid.viscosities {
        crate::outln!(
            "  viscosity {} Pa.s at {} °C ({}; trust {})",
            v.pa_s,
            v.temperature_c,
            v.provenance.source,
            v.provenance.trust
        );
    }
    crate::outln!(
        "  iron volume fraction {} ; carrier {}",
        fluid.iron_volume_fraction.value,
        fluid.carrier
    );
    let checks = fluid.reference_checks();
    if !checks.is_empty() {
        crate::outln!("  reference points (model vs reference):");
        crate::outln!("    {:>8} {:>12} {:>12} {:>9}", "B [T]", "ref [Pa]", "model [Pa]", "error");
        for c in checks {
            let b = c.reference.b_t.map_or("-".to_string(), |b| format!("{b:.4}"));
            crate::outln!(
                "    {:>8} {:>12.1} {:>12.1} {:>8.2}%",
                b,
                c.reference.tau_y_pa,
                c.model_tau_y_pa,
                c.error_percent
            );
        }
    }
}
