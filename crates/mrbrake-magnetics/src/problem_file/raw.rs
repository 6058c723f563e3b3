//! The TOML layout of problem files, as read by serde (unknown keys are errors), and its JSON
//! Schema ([`schema`]: structure and doc text from these types, the bounds the reader checks from
//! the constants below, which the reader uses too).

use mrbrake_fem::workflow::time::AdaptiveKeys;
use mrbrake_schema::{Bounds, annotate, choice, generate, node_mut, order};
use mrbrake_units::Dimension;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::Deserialize;
use serde_json::{Value, json};

/// `solver.max_iterations`: at least one Newton iteration.
pub(super) const MAX_ITERATIONS: Bounds = Bounds::at_least(1.0);
/// `solver.tolerance`: a relative residual in (0, 1).
pub(super) const TOLERANCE: Bounds = Bounds::open(0.0, 1.0);
/// `solver.quadrature_degree`: the triangle rules of degree 1 to 5.
pub(super) const QUADRATURE_DEGREE: Bounds = Bounds::closed(1.0, 5.0);
/// `region.conductivity_S_per_m`: in [0, 1e9] S/m (silver conducts 6.3e7 S/m; a larger value is
/// a unit mistake and makes the eddy term overflow the solve, issue 33).
pub(super) const CONDUCTIVITY: Bounds = Bounds::closed(0.0, 1e9);
/// `source.turns`: in (0, 1e7] (beyond it no winding fits any mesh of this solver).
pub(super) const TURNS: Bounds = Bounds::open_closed(0.0, 1e7);
/// `source.drive.series_resistance_ohm`: in [1e-6, 1e9] Ω (a winding has at least micro-ohms;
/// below, the circuit equation is singular in double precision).
pub(super) const SERIES_RESISTANCE: Bounds = Bounds::closed(1e-6, 1e9);
/// `transient.waveform.rise_s`: in [1e-9, 1e9] s (a faster change is a step: `kind = "step"`).
pub(super) const RISE: Bounds = Bounds::closed(1e-9, 1e9);
/// `transient.t_end`, `transient.dt` (s): finite and > 0.
pub(super) const DURATION: Bounds = Bounds::above(0.0);
/// `harmonic.frequencies_Hz`: finite and ≥ 0.
pub(super) const FREQUENCY: Bounds = Bounds::at_least(0.0);

/// The numeric keys with their SI unit and bounds (the schema's; the reader checks the same
/// constants). `samples` and the frequency count are bounded by `MAX_LINE_SAMPLES` and
/// `MAX_FREQUENCIES` in the schema function.
const NUMBERS: &[(&str, &str, Bounds)] = &[
    ("solver.max_iterations", "", MAX_ITERATIONS),
    ("solver.tolerance", "", TOLERANCE),
    ("solver.quadrature_degree", "", QUADRATURE_DEGREE),
    ("region.conductivity_S_per_m", "S/m", CONDUCTIVITY),
    ("transient.t_end", "s", DURATION),
    ("transient.dt", "s", DURATION),
    ("transient.adaptive.dt_initial", "s", DURATION),
    ("transient.waveform.rise_s", "s", RISE),
    ("transient.waveform.frequency_Hz", "Hz", FREQUENCY),
];

/// The JSON Schema of a magnetic problem file (`mrbrake fem solve`), its magnetodynamics
/// (`[transient]`, `[harmonic]`) included.
pub fn schema() -> Value {
    let mut schema = generate::<RawFile>();
    schema["$id"] = json!("https://mrbrake.invalid/schema/magnetics.json");
    schema["title"] = json!("mrbrake magnetic problem file");
    schema["description"] = json!(
        "An axisymmetric magnetostatic problem on a Gmsh mesh for `mrbrake fem solve`; with \
         `[transient]` or `[harmonic]` a magnetodynamic one (eddy currents, voltage-driven coils). \
         Coordinates are in `length_unit`, times in s, frequencies in Hz."
    );
    order::<RawSolver>(&mut schema, "solver");
    order::<RawRegion>(&mut schema, "region");
    order::<RawBoundary>(&mut schema, "boundary");
    order::<RawProbe>(&mut schema, "probe");
    order::<RawLine>(&mut schema, "line");
    order::<RawTransient>(&mut schema, "transient");
    order::<RawHarmonic>(&mut schema, "harmonic");
    for (path, unit, bounds) in NUMBERS {
        if let Some(node) = node_mut(&mut schema, path) {
            annotate(node, unit, *bounds);
        }
    }
    let samples = Bounds::closed(1.0, super::MAX_LINE_SAMPLES as f64);
    if let Some(node) = node_mut(&mut schema, "line.samples") {
        annotate(node, "", samples);
    }
    if let Some(node) = node_mut(&mut schema, "harmonic.frequencies_Hz") {
        node["maxItems"] = json!(super::dynamics::MAX_FREQUENCIES);
        node["minItems"] = json!(1);
        node["x-unit"] = json!("Hz");
        annotate(&mut node["items"], "", FREQUENCY);
    }
    schema
}

/// A magnetic problem file.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    /// The mesh: a Gmsh MSH 2.2 or 4.1 ASCII file, its path relative to this file; x is r, y is z.
    /// Every physical surface needs a `[[region]]`.
    pub mesh: String,
    /// The unit of the mesh coordinates, the probes and the lines (times and frequencies stay in
    /// s and Hz).
    #[serde(default)]
    #[schemars(schema_with = "length_unit")]
    pub length_unit: Option<String>,
    /// The element order: 1 (linear triangles) or 2 (quadratic, 6-node triangles on the same
    /// mesh); `fem solve --order` overrides it.
    #[serde(default)]
    #[schemars(schema_with = "element_order")]
    pub order: Option<toml::Value>,
    /// Newton solver settings.
    #[serde(default)]
    pub solver: Option<RawSolver>,
    /// The material (and source) of each physical surface of the mesh.
    #[serde(default)]
    pub region: Vec<RawRegion>,
    /// Conditions on tagged curves; every other edge is Neumann (flux parallel to it). The
    /// symmetry axis always has A = 0.
    #[serde(default)]
    pub boundary: Vec<RawBoundary>,
    /// Named points where B is reported.
    #[serde(default)]
    pub probe: Vec<RawProbe>,
    /// Named segments along which B is reported.
    #[serde(default)]
    pub line: Vec<RawLine>,
    /// A time-stepped solve (magnetodynamics: eddy currents, voltage-driven coils), from the DC
    /// state at the waveform's value at t = 0.
    #[serde(default)]
    pub transient: Option<RawTransient>,
    /// Time-harmonic solves (peak phasors, time factor exp(+jωt)), instead of `[transient]`.
    #[serde(default)]
    pub harmonic: Option<RawHarmonic>,
}

/// `length_unit`: one of the length units, default `m`.
fn length_unit(_: &mut SchemaGenerator) -> Schema {
    mrbrake_schema::unit_choice(Dimension::Length)
}

/// `order`: 1 or 2, default 1.
fn element_order(_: &mut SchemaGenerator) -> Schema {
    mrbrake_schema::element_order()
}

/// `[solver]`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSolver {
    /// The most Newton iterations (default 50).
    pub max_iterations: Option<usize>,
    /// Relative residual of the stopping rule (default 1e-9).
    pub tolerance: Option<f64>,
    /// Degree of the triangle quadrature rule (P2 elements use at least 4).
    pub quadrature_degree: Option<usize>,
}

/// `[[region]]`: one physical surface of the mesh.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegion {
    /// Its physical tag in the mesh.
    pub physical: u32,
    /// A library material by name (`mrbrake materials list`), `{ mu_r = … }` (linear) or
    /// `{ bh_csv = "file.csv" }` (a B-H curve, H in A/m and B in T, relative to this file).
    #[schemars(schema_with = "material")]
    pub material: Option<toml::Value>,
    /// A coil `{ turns, current_A }`, a voltage-driven coil `{ turns, drive = { voltage_V,
    /// series_resistance_ohm } }` or a uniform `{ current_density_A_per_m2 }`.
    #[serde(default)]
    #[schemars(schema_with = "source")]
    pub source: Option<toml::Value>,
    /// Electrical conductivity for eddy currents, overriding the library material's (a coil is
    /// a stranded winding and must not conduct).
    #[serde(rename = "conductivity_S_per_m")]
    pub conductivity: Option<f64>,
}

/// `material`: a library name, `{ mu_r }` or `{ bh_csv }`.
fn material(_: &mut SchemaGenerator) -> Schema {
    let names: Vec<&str> = mrbrake_materials::library::names().iter().map(|(n, _)| *n).collect();
    json_schema!({
        "anyOf": [
            { "type": "string", "enum": names },
            {
                "type": "object",
                "properties": {
                    "mu_r": { "type": "number", "exclusiveMinimum": 0,
                              "description": "Relative permeability of a linear material." }
                },
                "required": ["mu_r"],
                "additionalProperties": false
            },
            {
                "type": "object",
                "properties": {
                    "bh_csv": { "type": "string",
                                "description": "A B-H curve file (H in A/m, B in T), relative to this file." }
                },
                "required": ["bh_csv"],
                "additionalProperties": false
            }
        ]
    })
}

/// `source`: a current-driven coil, a voltage-driven coil or a current density.
fn source(_: &mut SchemaGenerator) -> Schema {
    let turns =
        json!({ "type": "number", "exclusiveMinimum": 0, "description": "Turns of the coil." });
    json_schema!({
        "anyOf": [
            {
                "type": "object",
                "properties": {
                    "turns": turns,
                    "current_A": { "type": "number", "x-unit": "A",
                                   "description": "Current (the amplitude a waveform scales)." }
                },
                "required": ["turns", "current_A"],
                "additionalProperties": false
            },
            {
                "type": "object",
                "properties": {
                    "turns": turns,
                    "drive": {
                        "type": "object",
                        "properties": {
                            "voltage_V": { "type": "number", "x-unit": "V" },
                            "series_resistance_ohm": { "type": "number", "exclusiveMinimum": 0, "x-unit": "ohm" }
                        },
                        "required": ["voltage_V", "series_resistance_ohm"],
                        "additionalProperties": false,
                        "description": "A voltage source in series with a resistance (the circuit v = R i + dλ/dt)."
                    }
                },
                "required": ["turns", "drive"],
                "additionalProperties": false
            },
            {
                "type": "object",
                "properties": {
                    "current_density_A_per_m2": { "type": "number", "x-unit": "A/m2",
                                                  "description": "A uniform azimuthal current density (a constant load)." }
                },
                "required": ["current_density_A_per_m2"],
                "additionalProperties": false
            }
        ]
    })
}

/// `[[boundary]]`: a condition on the curves of one physical tag.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBoundary {
    /// Its physical tag in the mesh (a curve).
    pub physical: u32,
    /// `dirichlet` (A = 0), `open` (asymptotic boundary on a circle centred on the axis at
    /// `centre_z`) or `neumann` (the natural condition of every untagged edge).
    #[schemars(schema_with = "boundary_kind")]
    pub kind: String,
    /// Of an `open` boundary: the z of its circle's centre, in `length_unit` (default 0).
    pub centre_z: Option<f64>,
}

fn boundary_kind(_: &mut SchemaGenerator) -> Schema {
    choice(&["dirichlet", "open", "neumann"], None)
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

/// `[[line]]`: a named segment.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLine {
    /// Its name in the report.
    pub name: String,
    /// Start `[r, z]`, in `length_unit`.
    pub from: [f64; 2],
    /// End `[r, z]`, in `length_unit`.
    pub to: [f64; 2],
    /// Number of intervals (default 20).
    pub samples: Option<usize>,
}

/// `[transient]`: a time-stepped solve (see `super::dynamics`).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTransient {
    /// End time (s).
    pub t_end: f64,
    /// Fixed time step (s); or give `adaptive`.
    pub dt: Option<f64>,
    /// Adaptive steps instead of `dt`.
    pub adaptive: Option<AdaptiveKeys>,
    /// The time integrator.
    #[serde(default)]
    #[schemars(schema_with = "scheme")]
    pub scheme: Option<String>,
    /// What scales every coil's amplitude over time (default: a step from 0 to 1 at t = 0).
    pub waveform: Option<RawWaveform>,
    /// Instants (s, increasing, within [0, t_end]) that `fem solve --vtu` writes (default: t_end).
    pub vtu_times: Option<Vec<f64>>,
    /// A bound on the number of steps.
    pub max_steps: Option<usize>,
}

fn scheme(_: &mut SchemaGenerator) -> Schema {
    let mut schema = choice(&["bdf2", "euler"], Some("bdf2"));
    schema.insert(
        "description".into(),
        json!("`bdf2` (second order, variable step) or `euler` (implicit Euler)."),
    );
    schema
}

/// `transient.waveform`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWaveform {
    /// `step` (0 at t ≤ 0, 1 after), `ramp` (0 to 1 over `rise_s`), `sine` (`frequency_Hz`,
    /// `offset`) or `csv` (`file` of `time_s,value` rows, strictly increasing time).
    #[schemars(schema_with = "waveform_kind")]
    pub kind: String,
    /// Of a ramp: its rise time (s).
    pub rise_s: Option<f64>,
    /// Of a sine: its frequency (Hz).
    #[serde(rename = "frequency_Hz")]
    pub frequency_hz: Option<f64>,
    /// Of a sine: the offset added to it.
    pub offset: Option<f64>,
    /// Of a csv waveform: the file, relative to this file.
    pub file: Option<String>,
}

fn waveform_kind(_: &mut SchemaGenerator) -> Schema {
    choice(&["step", "ramp", "sine", "csv"], Some("step"))
}

/// `[harmonic]`: time-harmonic (or small-signal) solves.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHarmonic {
    /// The frequencies (Hz).
    #[serde(rename = "frequencies_Hz")]
    pub frequencies_hz: Vec<f64>,
    /// Linearise about the DC state at this bias (the small-signal response of a saturated
    /// device); without it, about A = 0 (initial permeability).
    pub bias: Option<RawBias>,
    /// The frequencies (of `frequencies_Hz`) whose phasors `fem solve --vtu` writes (default:
    /// every one).
    #[serde(rename = "vtu_frequencies_Hz")]
    pub vtu_frequencies_hz: Option<Vec<f64>>,
}

/// `harmonic.bias`: every coil at `current_A`, or each listed coil at its own.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBias {
    /// Every coil at this current (A).
    #[serde(rename = "current_A")]
    pub current_a: Option<f64>,
    /// Or each listed coil at its own current (the others at 0 A).
    pub coils: Option<Vec<RawCoilBias>>,
}

/// One coil's bias current.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCoilBias {
    /// The coil region's physical tag.
    pub physical: u32,
    /// Its bias current (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schema_has_every_table_with_docs_bounds_and_order() {
        let mut schema = schema();
        assert_eq!(schema["x-order"][0], "mesh");
        assert_eq!(schema["required"], json!(["mesh"]));
        let tolerance = node_mut(&mut schema, "solver.tolerance").unwrap().clone();
        assert_eq!(
            (tolerance["exclusiveMinimum"].clone(), tolerance["exclusiveMaximum"].clone()),
            (json!(0), json!(1))
        );
        let kind = node_mut(&mut schema, "boundary.kind").unwrap().clone();
        assert_eq!(kind["enum"], json!(["dirichlet", "open", "neumann"]));
        assert!(kind["description"].as_str().unwrap().contains("asymptotic"));
        let material = node_mut(&mut schema, "region.material").unwrap().clone();
        assert!(material["anyOf"][0]["enum"].as_array().unwrap().contains(&json!("air")));
        let region = node_mut(&mut schema, "region").unwrap().clone();
        assert_eq!(region["items"]["required"], json!(["physical", "material"]));
        let samples = node_mut(&mut schema, "line.samples").unwrap().clone();
        assert_eq!(samples["maximum"], super::super::MAX_LINE_SAMPLES);
        assert_eq!(node_mut(&mut schema, "transient.dt").unwrap()["x-unit"], "s");
    }
}
