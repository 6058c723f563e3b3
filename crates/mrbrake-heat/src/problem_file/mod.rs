//! The `physics = "heat"` problem files of `mrbrake fem solve`, and the report of a solve.
//!
//! ```toml
//! physics = "heat"
//! mesh = "brake.msh"              # Gmsh MSH 2.2 or 4.1, relative to this file; x = r, y = z
//! length_unit = "mm"              # unit of the mesh and the probes (default "m")
//! order = 1                       # 1 (default) or 2
//! [solver]                        # optional (Newton, for radiation)
//! max_iterations = 50
//! tolerance = 1e-10
//! [[region]]
//! physical = 1
//! material = "steel-1008"         # library thermal data, or { k_W_per_mK = 50, rho_kg_per_m3 = 7870,
//!                                 # c_J_per_kgK = 450 } (k_radial_W_per_mK / k_axial_W_per_mK for an
//!                                 # anisotropic region), or { winding_fill_factor = 0.6 } (copper in
//!                                 # impregnating resin, homogenised: mrbrake_materials::thermal)
//! heat_source_W_per_m3 = 0.0      # or heat_W = 3.0 (total, spread uniformly), or
//! joule = { current_A = 2.0, turns = 450, wire_diameter_m = 5e-4, alpha_per_K = 0.00393 }
//!                                 # (or resistance_20C_ohm = 4.5 instead of turns and diameter)
//! [[boundary]]
//! physical = 20
//! kind = "convection"             # h_W_per_m2K, T_amb_C; "temperature" (T_C); "radiation"
//! h_W_per_m2K = 10.0              # (emissivity, T_amb_C); "adiabatic" (also every untagged edge)
//! T_amb_C = 25.0
//! [transient]                     # optional
//! t_end = 3600.0                  # s
//! dt = 10.0                       # s (fixed steps: t_end / ceil(t_end / dt), landing on t_end)
//!                                 # or adaptive = { rtol = 1e-4, dt_initial = 1.0 } (steps from
//!                                 # a local error estimate: mrbrake_fem::workflow::time)
//! T_initial_C = 25.0
//! scheme = "bdf2"                 # or "euler" (implicit Euler)
//! max_steps = 1000000             # optional bound on the number of steps
//! [[probe]]
//! name = "coil_centre"
//! r = 13.0
//! z = 20.0
//! ```
//!
//! The Joule resistance from turns and diameter is `R20 = ρ20 N 2π r̄ / (π d²/4)` with the IACS
//! copper resistivity (`mrbrake_materials::wire`) and `r̄` the centroid radius of the region (the
//! mean turn length of a winding filling it uniformly). Every invalid field is reported at once
//! with the file, its line and the allowed range (exit code 2 in the CLI).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use mrbrake_error::{FieldError, FieldErrors};
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesh::locate::Probe;
use mrbrake_fem::workflow::time::{StepKeys, TimeOptions};
use mrbrake_materials::thermal::Winding;

use crate::problem::{Boundary, BoundaryCondition, HeatProblem, Region, Source};
use crate::solver::SolverOptions;
use crate::{ElementOrder, HeatError, kelvin};

mod raw;
mod report;

pub use raw::schema;
use raw::{RawBoundary, RawFile, RawMaterial, RawRegion};
pub use report::{
    BoundaryReport, HeatReport, HeatTimings, ProbeReport, ProbeSeries, RegionReport, RegionSeries,
    TransientReport, solve_file,
};

/// A heat problem file after reading and checking.
#[derive(Debug, Clone)]
pub struct HeatFile {
    /// The problem.
    pub problem: HeatProblem,
    /// Solver settings.
    pub options: SolverOptions,
    /// The transient run and its initial temperature (K; `None`: the solver's reference
    /// temperature, the mean ambient), if any.
    pub transient: Option<(TimeOptions, Option<f64>)>,
    /// Probes.
    pub probes: Vec<Probe>,
    /// The mesh file.
    pub mesh_path: PathBuf,
}

/// The 1-based line of `key` inside the `k`-th `[[table]]` (or `[table]`) of `text`, if present.
fn line_of(text: &str, table: &str, k: usize, key: &str) -> Option<usize> {
    let (array, single) = (format!("[[{table}]]"), format!("[{table}]"));
    let mut seen = 0usize;
    let mut inside = false;
    for (n, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if trimmed.starts_with('[') {
            inside = if trimmed.starts_with(&array) || trimmed.starts_with(&single) {
                seen += 1;
                seen == k + 1
            } else {
                false
            };
            if inside && key.is_empty() {
                return Some(n + 1);
            }
            continue;
        }
        let is_key =
            trimmed.strip_prefix(key).is_some_and(|rest| rest.trim_start().starts_with('='));
        if inside && is_key {
            return Some(n + 1);
        }
    }
    None
}

/// Collects field errors with their lines.
struct Errors<'a> {
    file: &'a str,
    text: &'a str,
    errors: FieldErrors,
}

impl Errors<'_> {
    fn add(&mut self, table: &str, k: usize, key: &str, message: String) {
        let line = line_of(self.text, table, k, key).or_else(|| line_of(self.text, table, k, ""));
        let field =
            if key.is_empty() { format!("{table}[{k}]") } else { format!("{table}[{k}].{key}") };
        self.errors.push(FieldError::new(field, message).in_file(self.file, line));
    }
}

fn positive(v: f64) -> bool {
    raw::POSITIVE.contains(v)
}

/// An error about the whole file (a read or TOML error: no one field).
fn file_error(message: String, file: &str) -> HeatError {
    FieldError::new("", message).in_file(file, None).into()
}

/// Reads and checks a heat problem file and its mesh.
pub fn load(path: &Path) -> Result<HeatFile, HeatError> {
    let file = path.display().to_string();
    let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
        .map_err(|e| file_error(format!("cannot read: {e}"), &file))?;
    let raw: RawFile = toml::from_str(&text).map_err(|e| file_error(e.to_string(), &file))?;
    if raw.physics != "heat" {
        let e = FieldError::out_of_range("physics", format!("\"{}\"", raw.physics), "\"heat\"");
        return Err(e.in_file(file, None).into());
    }
    let order = match raw.order {
        None => ElementOrder::P1,
        Some(d) => {
            ElementOrder::try_from(d).map_err(|e| HeatError::from(e.in_file(&file, None)))?
        }
    };
    let mesh_path = path.parent().unwrap_or(Path::new(".")).join(&raw.mesh);
    let (gmsh, scale) =
        mrbrake_fem::mesh::gmsh::read_problem_mesh(path, &raw.mesh, raw.length_unit.as_deref())?;
    let mesh = Arc::new(gmsh.mesh);
    let mut errors = Errors { file: &file, text: &text, errors: FieldErrors::new() };
    let regions = regions_of(&raw.region, &mesh, &mut errors);
    let boundaries = boundaries_of(&raw.boundary, &mesh, &mut errors);
    check_coverage(&raw.region, &mesh, &mut errors);
    let transient = transient_of(&raw, &mut errors);
    let mut options = SolverOptions { order, ..SolverOptions::default() };
    if let Some(s) = &raw.solver {
        if let Some(m) = s.max_iterations {
            options.max_iterations = m.max(1);
        }
        if let Some(t) = s.tolerance {
            if !raw::TOLERANCE.contains(t) {
                errors.add("solver", 0, "tolerance", format!("= {t} must be in (0, 1)"));
            }
            options.tolerance = t;
        }
    }
    let probes = raw
        .probe
        .iter()
        .map(|p| Probe { name: p.name.clone(), point: [p.r * scale, p.z * scale] })
        .collect();
    errors.errors.into_result(())?;
    let problem = HeatProblem { mesh, regions, boundaries };
    Ok(HeatFile { problem, options, transient, probes, mesh_path })
}

/// The centroid radius `∫ r dA / ∫ dA` of the triangles tagged `tag`.
fn centroid_radius(mesh: &Mesh, tag: u32) -> f64 {
    let (mut moment, mut area) = (0.0, 0.0);
    for (t, tri) in mesh.triangles.iter().enumerate().filter(|(t, _)| mesh.triangle_tags[*t] == tag)
    {
        let a = mesh.signed_area(t).abs();
        moment += a * (mesh.nodes[tri[0]][0] + mesh.nodes[tri[1]][0] + mesh.nodes[tri[2]][0]) / 3.0;
        area += a;
    }
    if area > 0.0 { moment / area } else { 0.0 }
}

fn material_of(raw: &RawRegion, k: usize, errors: &mut Errors) -> Option<(f64, f64, f64)> {
    match &raw.material {
        None => {
            errors.add(
                "region",
                k,
                "material",
                "missing: a library name or a table of thermal data".into(),
            );
            None
        }
        Some(RawMaterial::Name(name)) => match mrbrake_materials::thermal::thermal(name) {
            Ok(p) => Some((p.k_w_per_mk, p.k_w_per_mk, p.volumetric_heat_capacity())),
            Err(e) => {
                errors.add("region", k, "material", e.to_string());
                None
            }
        },
        Some(RawMaterial::Table(t)) => {
            if let Some(fill) = t.winding_fill_factor {
                let winding = Winding::impregnated(fill).and_then(|w| w.properties());
                return match winding {
                    Ok(w) => Some((w.k_radial_w_per_mk, w.k_axial_w_per_mk, w.rho_c)),
                    Err(e) => {
                        errors.add("region", k, "material", e.to_string());
                        None
                    }
                };
            }
            let kr = t.k_radial.or(t.k);
            let kz = t.k_axial.or(t.k);
            let radial_name = if t.k_radial.is_some() { "k_radial_W_per_mK" } else { "k_W_per_mK" };
            let mut checks =
                vec![(radial_name, kr), ("rho_kg_per_m3", t.rho), ("c_J_per_kgK", t.c)];
            if t.k_axial.is_some() || t.k.is_none() {
                checks.push(("k_axial_W_per_mK", kz));
            }
            let mut ok = true;
            for (name, value) in checks {
                match value {
                    Some(v) if positive(v) => {}
                    Some(v) => {
                        errors.add("region", k, "material", format!("{name} = {v} must be > 0"));
                        ok = false;
                    }
                    None => {
                        errors.add("region", k, "material", format!("missing {name}"));
                        ok = false;
                    }
                }
            }
            ok.then(|| {
                (kr.unwrap_or(1.0), kz.unwrap_or(1.0), t.rho.unwrap_or(1.0) * t.c.unwrap_or(1.0))
            })
        }
    }
}

fn source_of(raw: &RawRegion, mesh: &Mesh, k: usize, errors: &mut Errors) -> Source {
    let given = [raw.heat_source_w_per_m3.is_some(), raw.heat_w.is_some(), raw.joule.is_some()];
    if given.iter().filter(|g| **g).count() > 1 {
        errors.add("region", k, "", "give one of heat_source_W_per_m3, heat_W, joule".into());
    }
    if let Some(q) = raw.heat_source_w_per_m3 {
        if !q.is_finite() {
            errors.add("region", k, "heat_source_W_per_m3", format!("= {q} must be finite"));
        }
        return Source::Uniform { w_per_m3: q };
    }
    if let Some(w) = raw.heat_w {
        if !w.is_finite() {
            errors.add("region", k, "heat_W", format!("= {w} must be finite"));
        }
        return Source::Power { watts: w };
    }
    let Some(j) = &raw.joule else { return Source::None };
    let alpha =
        j.alpha_per_k.unwrap_or(mrbrake_materials::wire::COPPER_TEMPERATURE_COEFFICIENT_PER_K);
    if !raw::ALPHA.contains(alpha) {
        errors.add("region", k, "joule", format!("alpha_per_K = {alpha} must be in [0, 0.1)"));
    }
    if !j.current_a.is_finite() {
        errors.add("region", k, "joule", format!("current_A = {} must be finite", j.current_a));
    }
    let resistance = match (j.resistance_20c_ohm, j.turns, j.wire_diameter_m) {
        (Some(r), _, _) if positive(r) => r,
        (None, Some(n), Some(d)) if positive(n) && positive(d) => {
            let area = std::f64::consts::PI * d * d / 4.0;
            mrbrake_materials::wire::COPPER_RESISTIVITY_20C_OHM_M
                * n
                * 2.0
                * std::f64::consts::PI
                * centroid_radius(mesh, raw.physical)
                / area
        }
        _ => {
            errors.add(
                "region",
                k,
                "joule",
                "needs resistance_20C_ohm > 0, or turns > 0 and wire_diameter_m > 0".into(),
            );
            1.0
        }
    };
    Source::Joule { current_a: j.current_a, resistance_20c_ohm: resistance, alpha_per_k: alpha }
}

fn regions_of(raw: &[RawRegion], mesh: &Mesh, errors: &mut Errors) -> Vec<Region> {
    let mut regions = Vec::new();
    for (k, r) in raw.iter().enumerate() {
        // One material per surface, as the magnetic reader requires: a second [[region]] of the
        // same surface used to be ignored silently (issue 33).
        if let Some(first) = raw[..k].iter().position(|earlier| earlier.physical == r.physical) {
            let message = format!(
                "= {} is defined twice (also region[{first}]): one [[region]] per surface",
                r.physical
            );
            errors.add("region", k, "physical", message);
        }
        let material = material_of(r, k, errors);
        let source = source_of(r, mesh, k, errors);
        if let Some((k_radial, k_axial, rho_c)) = material {
            regions.push(Region { tag: r.physical, k_radial, k_axial, rho_c, source });
        }
    }
    regions
}

fn check_coverage(raw: &[RawRegion], mesh: &Mesh, errors: &mut Errors) {
    let tags = mesh.region_tags();
    for (k, r) in raw.iter().enumerate() {
        if tags.binary_search(&r.physical).is_err() {
            errors.add(
                "region",
                k,
                "physical",
                format!("= {} is not a surface of the mesh; its surfaces: {tags:?}", r.physical),
            );
        }
    }
    for tag in tags {
        if !raw.iter().any(|r| r.physical == tag) {
            errors.errors.push(
                FieldError::new(
                    "region",
                    format!(
                        "the mesh's physical surface {tag} has no [[region]] with thermal data"
                    ),
                )
                .in_file(errors.file, None),
            );
        }
    }
}

/// Why a temperature outside its bounds is refused, in words.
fn why_out(celsius: f64) -> &'static str {
    if celsius <= -crate::ZERO_CELSIUS_K { " is below absolute zero" } else { " is out of range" }
}

fn temperature(value: Option<f64>, key: &str, k: usize, errors: &mut Errors) -> f64 {
    let bounds = if key == "T_amb_C" { crate::AMBIENT_C } else { crate::TEMPERATURE_C };
    match value {
        Some(t) if bounds.contains(t) => kelvin(t),
        Some(t) => {
            let allowed = bounds.describe("°C");
            errors.add("boundary", k, key, format!("= {t} °C{}: allowed {allowed}", why_out(t)));
            crate::T20_K
        }
        None => {
            errors.add("boundary", k, key, "missing (°C)".into());
            crate::T20_K
        }
    }
}

fn condition_of(b: &RawBoundary, k: usize, errors: &mut Errors) -> Option<BoundaryCondition> {
    Some(match b.kind.as_str() {
        "convection" => {
            let h = b.h.unwrap_or(f64::NAN);
            if !raw::CONVECTION.contains(h) {
                errors.add("boundary", k, "h_W_per_m2K", format!("= {h} must be >= 0 (W/(m² K))"));
            }
            BoundaryCondition::Convection {
                h_w_per_m2k: h,
                ambient_k: temperature(b.t_amb_c, "T_amb_C", k, errors),
            }
        }
        "radiation" => {
            let e = b.emissivity.unwrap_or(f64::NAN);
            if !raw::EMISSIVITY.contains(e) {
                errors.add("boundary", k, "emissivity", format!("= {e} must be in [0, 1]"));
            }
            BoundaryCondition::Radiation {
                emissivity: e,
                ambient_k: temperature(b.t_amb_c, "T_amb_C", k, errors),
            }
        }
        "temperature" => {
            BoundaryCondition::Temperature { t_k: temperature(b.t_c, "T_C", k, errors) }
        }
        "adiabatic" => return None,
        other => {
            errors.add(
                "boundary",
                k,
                "kind",
                format!("= \"{other}\" is not known; allowed: \"convection\", \"radiation\", \"temperature\", \"adiabatic\""),
            );
            return None;
        }
    })
}

fn boundaries_of(raw: &[RawBoundary], mesh: &Mesh, errors: &mut Errors) -> Vec<Boundary> {
    let mut boundaries = Vec::new();
    for (k, b) in raw.iter().enumerate() {
        if !mesh.edge_tags.contains(&b.physical) {
            errors.add(
                "boundary",
                k,
                "physical",
                format!("= {}: the mesh has no curve with this tag", b.physical),
            );
        }
        if let Some(condition) = condition_of(b, k, errors) {
            boundaries.push(Boundary { tag: b.physical, condition });
        }
    }
    boundaries
}

fn transient_of(raw: &RawFile, errors: &mut Errors) -> Option<(TimeOptions, Option<f64>)> {
    let t = raw.transient.as_ref()?;
    let keys = StepKeys {
        t_end: t.t_end,
        dt: t.dt,
        adaptive: t.adaptive,
        scheme: t.scheme.as_deref(),
        max_steps: t.max_steps,
    };
    let options = TimeOptions::from_keys(&keys)
        .map_err(|bad| {
            for e in bad.errors() {
                errors.add("transient", 0, &e.field, e.message.clone());
            }
        })
        .ok();
    let initial = match t.t_initial_c {
        Some(c) if crate::TEMPERATURE_C.contains(c) => Some(kelvin(c)),
        Some(c) => {
            let allowed = crate::TEMPERATURE_C.describe("°C");
            let message = format!("= {c} °C{}: allowed {allowed}", why_out(c));
            errors.add("transient", 0, "T_initial_C", message);
            None
        }
        None => None,
    };
    options.map(|o| (o, initial))
}
