//! The TOML layout of heat problem files, as read by serde (unknown keys are errors), and its JSON
//! Schema ([`schema`]: structure and doc text from these types, the bounds the reader checks from
//! the constants below, which the reader uses too).

use mrbrake_fem::workflow::time::AdaptiveKeys;
use mrbrake_schema::{Bounds, annotate, choice, generate, node_mut, order};
use mrbrake_units::Dimension;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::Deserialize;
use serde_json::{Value, json};

/// Conductivities, densities, heat capacities, times, resistances, turns, diameters: finite, > 0.
pub(super) const POSITIVE: Bounds = Bounds::above(0.0);
/// `solver.tolerance`: a relative residual in (0, 1).
pub(super) const TOLERANCE: Bounds = Bounds::open(0.0, 1.0);
/// `joule.alpha_per_K`: the resistance's temperature coefficient, in [0, 0.1) per K.
pub(super) const ALPHA: Bounds = Bounds::closed_open(0.0, 0.1);
/// `boundary.h_W_per_m2K`: finite and ≥ 0.
pub(super) const CONVECTION: Bounds = Bounds::at_least(0.0);
/// `boundary.emissivity`: in [0, 1].
pub(super) const EMISSIVITY: Bounds = Bounds::closed(0.0, 1.0);

/// The numeric keys with their unit and bounds (the reader checks the same constants).
const NUMBERS: &[(&str, &str, Bounds)] = &[
    ("solver.tolerance", "", TOLERANCE),
    ("region.joule.turns", "", POSITIVE),
    ("region.joule.wire_diameter_m", "m", POSITIVE),
    ("region.joule.resistance_20C_ohm", "ohm", POSITIVE),
    ("region.joule.alpha_per_K", "1/K", ALPHA),
    ("boundary.h_W_per_m2K", "W/(m2 K)", CONVECTION),
    ("boundary.emissivity", "", EMISSIVITY),
    ("boundary.T_amb_C", "°C", crate::AMBIENT_C),
    ("boundary.T_C", "°C", crate::TEMPERATURE_C),
    ("transient.T_initial_C", "°C", crate::TEMPERATURE_C),
    ("transient.t_end", "s", POSITIVE),
    ("transient.dt", "s", POSITIVE),
];

/// The JSON Schema of a heat problem file (`physics = "heat"`, `mrbrake fem solve`).
pub fn schema() -> Value {
    let mut schema = generate::<RawFile>();
    schema["$id"] = json!("https://mrbrake.invalid/schema/heat.json");
    schema["title"] = json!("mrbrake heat problem file");
    schema["description"] = json!(
        "Axisymmetric heat conduction on a Gmsh mesh for `mrbrake fem solve`: steady or \
         transient temperatures with uniform, total or Joule heat sources and convection, \
         radiation or fixed-temperature boundaries. Coordinates are in `length_unit`, times in s, \
         temperatures in °C."
    );
    order::<RawSolver>(&mut schema, "solver");
    order::<RawRegion>(&mut schema, "region");
    order::<RawJoule>(&mut schema, "region.joule");
    order::<RawBoundary>(&mut schema, "boundary");
    order::<RawTransient>(&mut schema, "transient");
    order::<RawProbe>(&mut schema, "probe");
    for (path, unit, bounds) in NUMBERS {
        if let Some(node) = node_mut(&mut schema, path) {
            annotate(node, unit, *bounds);
        }
    }
    schema
}

/// A heat problem file.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    /// Must be `heat` (a file without it is a magnetic problem).
    #[schemars(schema_with = "physics")]
    pub physics: String,
    /// The mesh: a Gmsh MSH 2.2 or 4.1 ASCII file, its path relative to this file; x is r, y is z.
    pub mesh: String,
    /// The unit of the mesh coordinates and the probes.
    #[serde(default)]
    #[schemars(schema_with = "length_unit")]
    pub length_unit: Option<String>,
    /// The element order: 1 (linear triangles) or 2 (quadratic).
    #[serde(default)]
    #[schemars(schema_with = "element_order")]
    pub order: Option<i64>,
    /// Newton settings (used with radiation, the one non-linear boundary).
    #[serde(default)]
    pub solver: Option<RawSolver>,
    /// The material and heat source of each physical surface of the mesh.
    #[serde(default)]
    pub region: Vec<RawRegion>,
    /// Conditions on tagged curves; every other edge is adiabatic.
    #[serde(default)]
    pub boundary: Vec<RawBoundary>,
    /// A warm-up from a uniform initial temperature; without it the steady state.
    #[serde(default)]
    pub transient: Option<RawTransient>,
    /// Named points whose temperature is reported.
    #[serde(default)]
    pub probe: Vec<RawProbe>,
}

fn physics(_: &mut SchemaGenerator) -> Schema {
    json_schema!({ "type": "string", "const": "heat" })
}

fn length_unit(_: &mut SchemaGenerator) -> Schema {
    mrbrake_schema::unit_choice(Dimension::Length)
}

fn element_order(_: &mut SchemaGenerator) -> Schema {
    mrbrake_schema::element_order()
}

/// `[solver]`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSolver {
    /// The most Newton iterations.
    pub max_iterations: Option<usize>,
    /// Relative residual of the stopping rule.
    pub tolerance: Option<f64>,
}

/// `[[region]]`: one physical surface of the mesh.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegion {
    /// Its physical tag in the mesh.
    pub physical: u32,
    /// A library material with thermal data (by name) or its properties.
    pub material: Option<RawMaterial>,
    /// A uniform heat source (W/m³).
    #[serde(rename = "heat_source_W_per_m3")]
    pub heat_source_w_per_m3: Option<f64>,
    /// Or a total heat (W), spread uniformly.
    #[serde(rename = "heat_W")]
    pub heat_w: Option<f64>,
    /// Or Joule heat `I² R(T)` of a winding, applied at the local temperature.
    pub joule: Option<RawJoule>,
}

/// A material: a library name or its properties.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(untagged)]
pub(super) enum RawMaterial {
    /// A material of the library with thermal data (`mrbrake materials list`).
    Name(String),
    /// The properties of the region.
    Table(RawMaterialTable),
}

/// A material's thermal properties.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMaterialTable {
    /// Thermal conductivity, isotropic (W/(m K)).
    #[serde(rename = "k_W_per_mK")]
    pub k: Option<f64>,
    /// Radial conductivity of an anisotropic region (W/(m K)).
    #[serde(rename = "k_radial_W_per_mK")]
    pub k_radial: Option<f64>,
    /// Axial conductivity of an anisotropic region (W/(m K)).
    #[serde(rename = "k_axial_W_per_mK")]
    pub k_axial: Option<f64>,
    /// Density (kg/m³), for transients.
    #[serde(rename = "rho_kg_per_m3")]
    pub rho: Option<f64>,
    /// Specific heat capacity (J/(kg K)), for transients.
    #[serde(rename = "c_J_per_kgK")]
    pub c: Option<f64>,
    /// A homogenised winding in impregnating resin with this copper fill factor.
    pub winding_fill_factor: Option<f64>,
}

/// `joule`: the Joule heat of a winding.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawJoule {
    /// The current (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// Turns (with `wire_diameter_m`: R20 = ρ20 N 2π r̄ / (π d²/4), r̄ the region's centroid
    /// radius).
    pub turns: Option<f64>,
    /// Bare copper diameter (m).
    pub wire_diameter_m: Option<f64>,
    /// Or the resistance at 20 °C (Ω) instead of turns and diameter.
    #[serde(rename = "resistance_20C_ohm")]
    pub resistance_20c_ohm: Option<f64>,
    /// Temperature coefficient of the resistance (1/K; default copper's).
    #[serde(rename = "alpha_per_K")]
    pub alpha_per_k: Option<f64>,
}

/// `[[boundary]]`: a condition on the curves of one physical tag.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBoundary {
    /// Its physical tag in the mesh (a curve).
    pub physical: u32,
    /// `convection` (`h_W_per_m2K`, `T_amb_C`), `radiation` (`emissivity`, `T_amb_C`),
    /// `temperature` (`T_C`) or `adiabatic` (also every untagged edge).
    #[schemars(schema_with = "boundary_kind")]
    pub kind: String,
    /// Heat transfer coefficient of a convection boundary (W/(m² K)).
    #[serde(rename = "h_W_per_m2K")]
    pub h: Option<f64>,
    /// Ambient temperature of convection and radiation (°C).
    #[serde(rename = "T_amb_C")]
    pub t_amb_c: Option<f64>,
    /// The fixed temperature of a temperature boundary (°C).
    #[serde(rename = "T_C")]
    pub t_c: Option<f64>,
    /// Emissivity of a radiating surface.
    pub emissivity: Option<f64>,
}

fn boundary_kind(_: &mut SchemaGenerator) -> Schema {
    choice(&["convection", "radiation", "temperature", "adiabatic"], None)
}

/// `[transient]`: a warm-up.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTransient {
    /// End time (s).
    pub t_end: f64,
    /// Fixed time step (s), at most `t_end`; or give `adaptive`.
    pub dt: Option<f64>,
    /// Adaptive steps instead of `dt`.
    pub adaptive: Option<AdaptiveKeys>,
    /// Initial temperature, uniform (°C).
    #[serde(rename = "T_initial_C")]
    pub t_initial_c: Option<f64>,
    /// The time integrator: `bdf2` (default) or `euler` (implicit Euler).
    #[serde(default)]
    #[schemars(schema_with = "scheme")]
    pub scheme: Option<String>,
    pub max_steps: Option<usize>,
}

fn scheme(_: &mut SchemaGenerator) -> Schema {
    choice(&["bdf2", "euler"], Some("bdf2"))
}

/// `[[probe]]`: a named point.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProbe {
    /// Its name in the report.
    pub name: String,
    /// Radius, in `length_unit`.
    pub r: f64,
    /// Axial position, in `length_unit`.
    pub z: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schema_has_every_table_with_docs_bounds_and_order() {
        let mut schema = schema();
        assert_eq!(schema["x-order"][0], "physics");
        let emissivity = node_mut(&mut schema, "boundary.emissivity").unwrap().clone();
        assert_eq!(
            (emissivity["minimum"].clone(), emissivity["maximum"].clone()),
            (json!(0), json!(1))
        );
        let kind = node_mut(&mut schema, "boundary.kind").unwrap().clone();
        assert_eq!(kind["enum"].as_array().unwrap().len(), 4);
        let material = node_mut(&mut schema, "region.material").unwrap().clone();
        assert_eq!(material["anyOf"].as_array().unwrap().len(), 2, "{material}");
        assert_eq!(node_mut(&mut schema, "transient.dt").unwrap()["x-unit"], "s");
    }
}
