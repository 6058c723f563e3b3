//! TOML problem files for `mrbrake fem solve`, and the report of a file-driven solve.
//!
//! ```toml
//! mesh = "potcore.msh"          # Gmsh MSH 2.2 or 4.1 ASCII, path relative to this file; x = r, y = z
//! length_unit = "mm"            # "m" (default), "cm", "mm" or "um": unit of the mesh, probes, lines
//! order = 2                     # element order: 1 (linear triangles, the default) or 2 (quadratic,
//!                               # 6-node triangles on the same mesh; `fem solve --order` overrides)
//! [solver]                      # optional
//! max_iterations = 50
//! tolerance = 1e-9              # relative residual of the stopping rule
//! quadrature_degree = 2         # triangle rule degree 1 to 5 (P2 elements use at least 4)
//! [[region]]
//! physical = 1
//! material = { bh_csv = "bh.csv" }   # or "steel-1010" (library name) or { mu_r = 1000.0 }
//! [[region]]
//! physical = 2
//! material = "air"
//! source = { turns = 1000, current_A = 1.0 }   # or { current_density_A_per_m2 = 3.5e6 }
//! [[boundary]]
//! physical = 10
//! kind = "dirichlet"            # A = 0; "open" (asymptotic, circle centred at r = 0, z = centre_z);
//!                               # "neumann" (the default on every untagged edge)
//! [[probe]]
//! name = "gap_centre"
//! r = 0.0
//! z = 0.0
//! [[line]]                      # optional: B along a segment
//! name = "gap"
//! from = [10.0, 0.0]
//! to = [10.0, 5.0]
//! samples = 20
//! ```
//!
//! Every error names the file and the offending field (TOML syntax errors also give the line).
//! The symmetry axis always has `A = 0`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::ElementOrder;
use crate::MagneticsError;
use crate::field::{CoilLinkage, PointField, RegionStats, Solution};
use crate::material::MagneticMaterial;
use crate::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use crate::solver::{Solver, SolverOptions};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    mesh: String,
    #[serde(default)]
    length_unit: Option<String>,
    #[serde(default)]
    order: Option<toml::Value>,
    #[serde(default)]
    solver: Option<RawSolver>,
    #[serde(default)]
    region: Vec<RawRegion>,
    #[serde(default)]
    boundary: Vec<RawBoundary>,
    #[serde(default)]
    probe: Vec<RawProbe>,
    #[serde(default)]
    line: Vec<RawLine>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSolver {
    max_iterations: Option<usize>,
    tolerance: Option<f64>,
    quadrature_degree: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRegion {
    physical: u32,
    material: Option<toml::Value>,
    source: Option<toml::Value>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBoundary {
    physical: u32,
    kind: String,
    centre_z: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProbe {
    name: String,
    r: f64,
    z: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLine {
    name: String,
    from: [f64; 2],
    to: [f64; 2],
    samples: Option<usize>,
}

/// A named point where B is reported (coordinates in metres).
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name from the file.
    pub name: String,
    /// `[r, z]` in metres.
    pub point: [f64; 2],
}

/// A named segment along which B is reported (metres).
#[derive(Debug, Clone, PartialEq)]
pub struct LineProbe {
    /// Name from the file.
    pub name: String,
    /// Start `[r, z]` (m).
    pub from: [f64; 2],
    /// End `[r, z]` (m).
    pub to: [f64; 2],
    /// Number of intervals.
    pub samples: usize,
}

/// A problem file after reading and checking.
#[derive(Debug, Clone)]
pub struct ProblemFile {
    /// The problem (mesh loaded, materials resolved).
    pub problem: Problem,
    /// Solver settings.
    pub options: SolverOptions,
    /// Probes.
    pub probes: Vec<Probe>,
    /// Lines.
    pub lines: Vec<LineProbe>,
    /// The mesh file.
    pub mesh_path: PathBuf,
    /// Seconds spent reading the mesh file.
    pub mesh_read_s: f64,
}

/// Metres per unit for `length_unit`.
fn unit_scale(unit: &str, file: &str) -> Result<f64, MagneticsError> {
    Ok(match unit {
        "m" => 1.0,
        "cm" => 1e-2,
        "mm" => 1e-3,
        "um" | "µm" => 1e-6,
        other => {
            return Err(MagneticsError::Input(format!(
                "{file}: length_unit = \"{other}\" is not known; allowed: \"m\", \"cm\", \"mm\", \"um\""
            )));
        }
    })
}

/// The element order of the `order` key (absent: P1).
fn order_of(value: Option<&toml::Value>, file: &str) -> Result<ElementOrder, MagneticsError> {
    let Some(value) = value else { return Ok(ElementOrder::P1) };
    value.as_integer().and_then(ElementOrder::from_degree).ok_or_else(|| {
        MagneticsError::Input(format!(
            "{file}: order = {value} is not allowed; allowed: 1 (linear triangles) or 2 \
             (quadratic, 6-node triangles)"
        ))
    })
}

/// Reads a problem file and everything it refers to (mesh, B-H files).
pub fn load(path: &Path) -> Result<ProblemFile, MagneticsError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| MagneticsError::Input(format!("{file}: cannot read: {e}")))?;
    let raw: RawFile =
        toml::from_str(&text).map_err(|e| MagneticsError::Input(format!("{file}: {e}")))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let scale = unit_scale(raw.length_unit.as_deref().unwrap_or("m"), &file)?;
    let order = order_of(raw.order.as_ref(), &file)?;
    let mesh_path = dir.join(&raw.mesh);
    let start = Instant::now();
    let gmsh = mrbrake_fem::gmsh::read_msh(&mesh_path, scale).map_err(|e| match e {
        // Name the problem file and its `mesh` field, not only the resolved mesh path.
        mrbrake_fem::FemError::Io { source, .. } => MagneticsError::Input(format!(
            "{file}: mesh = \"{}\": cannot read {}: {source}",
            raw.mesh,
            mesh_path.display()
        )),
        other => other.into(),
    })?;
    let mesh_read_s = start.elapsed().as_secs_f64();

    let mut regions = Vec::new();
    for (k, r) in raw.region.iter().enumerate() {
        let field = format!("{file}: region[{k}] (physical = {})", r.physical);
        let material = match &r.material {
            None => return Err(MagneticsError::Input(format!("{field}: missing `material`"))),
            Some(value) => material_of(value, dir, &field)?,
        };
        let source = match &r.source {
            None => None,
            Some(value) => Some(source_of(value, &field)?),
        };
        regions.push(Region { tag: r.physical, material, source });
    }
    let mut boundaries = Vec::new();
    for (k, b) in raw.boundary.iter().enumerate() {
        let field = format!("{file}: boundary[{k}] (physical = {})", b.physical);
        let condition = match b.kind.as_str() {
            "dirichlet" => Some(BoundaryCondition::Dirichlet),
            "open" => {
                Some(BoundaryCondition::Open { centre_z_m: b.centre_z.unwrap_or(0.0) * scale })
            }
            "neumann" => None,
            other => {
                return Err(MagneticsError::Input(format!(
                    "{field}: kind = \"{other}\" is not known; allowed: \"dirichlet\", \"open\", \"neumann\""
                )));
            }
        };
        if !gmsh.mesh.edge_tags.contains(&b.physical) {
            return Err(MagneticsError::Input(format!(
                "{field}: the mesh {} has no curve with physical tag {}",
                mesh_path.display(),
                b.physical
            )));
        }
        if let Some(condition) = condition {
            boundaries.push(Boundary { tag: b.physical, condition });
        }
    }
    let mut options = SolverOptions { order, ..SolverOptions::default() };
    if let Some(s) = &raw.solver {
        if let Some(m) = s.max_iterations {
            if m == 0 {
                return Err(MagneticsError::Input(format!(
                    "{file}: solver.max_iterations must be >= 1"
                )));
            }
            options.max_iterations = m;
        }
        if let Some(t) = s.tolerance {
            if !(t > 0.0 && t < 1.0) {
                return Err(MagneticsError::Input(format!(
                    "{file}: solver.tolerance = {t} must be in (0, 1)"
                )));
            }
            options.residual_tolerance = t;
        }
        if let Some(q) = s.quadrature_degree {
            if !(1..=5).contains(&q) {
                return Err(MagneticsError::Input(format!(
                    "{file}: solver.quadrature_degree = {q} must be 1 to 5"
                )));
            }
            options.quadrature_degree = q;
        }
    }
    let probes = raw
        .probe
        .iter()
        .map(|p| Probe { name: p.name.clone(), point: [p.r * scale, p.z * scale] })
        .collect();
    let lines = raw
        .line
        .iter()
        .map(|l| LineProbe {
            name: l.name.clone(),
            from: [l.from[0] * scale, l.from[1] * scale],
            to: [l.to[0] * scale, l.to[1] * scale],
            samples: l.samples.unwrap_or(20).max(1),
        })
        .collect();
    let problem = Problem { mesh: Arc::new(gmsh.mesh), regions, boundaries };
    // Region/mesh consistency (unknown groups, missing materials) is checked here so the error names the file.
    check_regions(&problem, &file, &mesh_path)?;
    Ok(ProblemFile { problem, options, probes, lines, mesh_path, mesh_read_s })
}

fn check_regions(problem: &Problem, file: &str, mesh_path: &Path) -> Result<(), MagneticsError> {
    let tags = problem.mesh.region_tags();
    for region in &problem.regions {
        if tags.binary_search(&region.tag).is_err() {
            return Err(MagneticsError::Input(format!(
                "{file}: region physical = {} is not a physical surface of the mesh {} (its surfaces: {tags:?})",
                region.tag,
                mesh_path.display()
            )));
        }
    }
    for tag in tags {
        if problem.region(tag).is_none() {
            return Err(MagneticsError::Input(format!(
                "{file}: the mesh's physical surface {tag} has no [[region]] with a material"
            )));
        }
    }
    Ok(())
}

fn material_of(
    value: &toml::Value,
    dir: &Path,
    field: &str,
) -> Result<MagneticMaterial, MagneticsError> {
    match value {
        toml::Value::String(name) => {
            let material = mrbrake_materials::library::get(name)?;
            Ok(MagneticMaterial::from_library(&material.magnetic))
        }
        toml::Value::Table(table) => {
            if let Some(mu) = table.get("mu_r") {
                let mu_r = mu.as_float().or_else(|| mu.as_integer().map(|i| i as f64)).ok_or_else(
                    || MagneticsError::Input(format!("{field}: material.mu_r must be a number")),
                )?;
                if !(mu_r.is_finite() && mu_r > 0.0) {
                    return Err(MagneticsError::Input(format!(
                        "{field}: material.mu_r = {mu_r} must be > 0"
                    )));
                }
                Ok(MagneticMaterial::Linear { mu_r })
            } else if let Some(csv) = table.get("bh_csv") {
                let csv = csv.as_str().ok_or_else(|| {
                    MagneticsError::Input(format!("{field}: material.bh_csv must be a path string"))
                })?;
                let curve = mrbrake_materials::BhCurve::from_csv_file(&dir.join(csv))?;
                Ok(MagneticMaterial::NonLinear(Arc::new(curve)))
            } else {
                Err(MagneticsError::Input(format!(
                    "{field}: material table needs `mu_r` or `bh_csv` (or give a library name such as \"steel-1010\")"
                )))
            }
        }
        _ => Err(MagneticsError::Input(format!(
            "{field}: material must be a library name, {{ mu_r = ... }} or {{ bh_csv = \"file.csv\" }}"
        ))),
    }
}

fn number(table: &toml::Table, key: &str, field: &str) -> Result<Option<f64>, MagneticsError> {
    match table.get(key) {
        None => Ok(None),
        Some(v) => v
            .as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .filter(|x| x.is_finite())
            .map(Some)
            .ok_or_else(|| {
                MagneticsError::Input(format!("{field}: source.{key} must be a finite number"))
            }),
    }
}

fn source_of(value: &toml::Value, field: &str) -> Result<Source, MagneticsError> {
    let table = value.as_table().ok_or_else(|| {
        MagneticsError::Input(format!(
            "{field}: source must be a table such as {{ turns = 100, current_A = 1.0 }}"
        ))
    })?;
    for key in table.keys() {
        if !["turns", "current_A", "current_density_A_per_m2"].contains(&key.as_str()) {
            return Err(MagneticsError::Input(format!(
                "{field}: unknown source field `{key}`; allowed: turns, current_A, current_density_A_per_m2"
            )));
        }
    }
    if let Some(j) = number(table, "current_density_A_per_m2", field)? {
        return Ok(Source::CurrentDensity { a_per_m2: j });
    }
    match (number(table, "turns", field)?, number(table, "current_A", field)?) {
        (Some(turns), Some(current_a)) => {
            if turns <= 0.0 {
                return Err(MagneticsError::Input(format!(
                    "{field}: source.turns = {turns} must be > 0"
                )));
            }
            Ok(Source::Coil { turns, current_a })
        }
        _ => Err(MagneticsError::Input(format!(
            "{field}: source needs both `turns` and `current_A`, or `current_density_A_per_m2`"
        ))),
    }
}

/// B at a named probe (JSON field names as documented for `mrbrake fem solve --json`).
#[derive(Debug, Clone, Serialize)]
pub struct ProbeReport {
    /// Probe name.
    pub name: String,
    /// Radius (m).
    pub r: f64,
    /// Axial position (m).
    pub z: f64,
    /// Radial flux density (T).
    #[serde(rename = "B_r_T")]
    pub b_r_t: f64,
    /// Axial flux density (T).
    #[serde(rename = "B_z_T")]
    pub b_z_t: f64,
    /// |B| (T).
    #[serde(rename = "B_abs_T")]
    pub b_abs_t: f64,
}

/// Region statistics in the report.
#[derive(Debug, Clone, Serialize)]
pub struct RegionReport {
    /// Physical tag.
    pub physical: u32,
    /// Cross-section area (m²).
    pub area_m2: f64,
    /// Volume-weighted mean |B| (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Max |B| (T).
    #[serde(rename = "max_B_T")]
    pub max_b_t: f64,
    /// 10/50/90 % volume quantiles of |B| (T).
    #[serde(rename = "quantiles_B_T")]
    pub quantiles_b_t: [f64; 3],
}

/// Coil results in the report.
#[derive(Debug, Clone, Serialize)]
pub struct CoilReport {
    /// Physical tag.
    pub physical: u32,
    /// Flux linkage (Wb).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: f64,
    /// Secant inductance λ/I (H).
    #[serde(rename = "inductance_H")]
    pub inductance_h: f64,
    /// Incremental inductance dλ/dI (H).
    #[serde(rename = "incremental_inductance_H")]
    pub incremental_inductance_h: f64,
}

/// B along a named line.
#[derive(Debug, Clone, Serialize)]
pub struct LineReport {
    /// Line name.
    pub name: String,
    /// Samples.
    pub points: Vec<ProbeReport>,
}

/// Timings of a file-driven solve (s).
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timings {
    /// Reading the problem and mesh files.
    pub read: f64,
    /// Assembly (all Newton iterations and line-search trials).
    pub assemble: f64,
    /// Symbolic + numeric factorisations and triangular solves.
    pub solve: f64,
    /// Post-processing (probes, regions, coils, energy).
    pub post: f64,
    /// Everything.
    pub total: f64,
}

/// The result of `mrbrake fem solve` (the `--json` object).
#[derive(Debug, Clone, Serialize)]
pub struct SolveReport {
    /// B at the probes.
    pub probes: Vec<ProbeReport>,
    /// |B| statistics per region.
    pub regions: Vec<RegionReport>,
    /// Coils: flux linkage and inductances.
    pub coils: Vec<CoilReport>,
    /// B along the lines.
    pub lines: Vec<LineReport>,
    /// Stored magnetic energy (J).
    #[serde(rename = "energy_J")]
    pub energy_j: f64,
    /// Co-energy (J).
    #[serde(rename = "coenergy_J")]
    pub coenergy_j: f64,
    /// Newton iterations (linear solves).
    pub newton_iterations: usize,
    /// True when the stopping rule was met.
    pub converged: bool,
    /// Relative residual after each iteration.
    pub residual_history: Vec<f64>,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh triangles.
    pub elements: usize,
    /// Element order: 1 (linear) or 2 (quadratic triangles).
    pub order: usize,
    /// Free unknowns.
    pub unknowns: usize,
    /// Timings (s).
    pub timings_s: Timings,
}

fn probe_report(name: &str, f: &PointField) -> ProbeReport {
    ProbeReport {
        name: name.to_string(),
        r: f.r,
        z: f.z,
        b_r_t: f.b_r_t,
        b_z_t: f.b_z_t,
        b_abs_t: f.b_abs_t,
    }
}

/// Reads, solves and post-processes a problem file; returns the report and the solver and solution
/// (for VTU output and field maps).
pub fn solve_file(path: &Path) -> Result<(SolveReport, Solver, Solution), MagneticsError> {
    solve_file_with_order(path, None)
}

/// [`solve_file`] with the element order of the file's `order` key replaced by `order` when given
/// (`mrbrake fem solve --order`).
pub fn solve_file_with_order(
    path: &Path,
    order: Option<ElementOrder>,
) -> Result<(SolveReport, Solver, Solution), MagneticsError> {
    let start = Instant::now();
    let mut file = load(path)?;
    if let Some(order) = order {
        file.options.order = order;
    }
    let read = start.elapsed().as_secs_f64();
    let mut solver = Solver::new(file.problem, file.options)?;
    let solution = solver.solve(None)?;
    let post_start = Instant::now();
    let mut probes = Vec::new();
    for p in &file.probes {
        let f = solver.b_at(&solution, p.point).map_err(|e| {
            MagneticsError::Input(format!("{}: probe `{}`: {e}", path.display(), p.name))
        })?;
        probes.push(probe_report(&p.name, &f));
    }
    let mut lines = Vec::new();
    for l in &file.lines {
        let samples = solver.b_along(&solution, &[l.from, l.to], l.samples).map_err(|e| {
            MagneticsError::Input(format!("{}: line `{}`: {e}", path.display(), l.name))
        })?;
        lines.push(LineReport {
            name: l.name.clone(),
            points: samples.iter().map(|f| probe_report(&l.name, f)).collect(),
        });
    }
    let mut regions = Vec::new();
    for tag in solver.mesh().region_tags() {
        let s: RegionStats = solver.region_stats(&solution, tag)?;
        regions.push(RegionReport {
            physical: tag,
            area_m2: s.area_m2,
            mean_b_t: s.mean_b_t,
            max_b_t: s.max_b_t,
            quantiles_b_t: s.quantiles_b_t,
        });
    }
    let linkages: Vec<CoilLinkage> = solver.coils(&solution);
    let (energy_j, coenergy_j) = solver.energy(&solution);
    let post_first = post_start.elapsed().as_secs_f64();
    // The incremental inductance needs one more factorisation (counted as solve time).
    let inc_start = Instant::now();
    let mut coils = Vec::new();
    for c in linkages {
        let incremental = solver.incremental_inductance(&solution, c.physical)?;
        coils.push(CoilReport {
            physical: c.physical,
            flux_linkage_wb: c.flux_linkage_wb,
            inductance_h: c.inductance_h,
            incremental_inductance_h: incremental,
        });
    }
    let incremental_s = inc_start.elapsed().as_secs_f64();
    let t = solution.report.timings;
    let report = SolveReport {
        probes,
        regions,
        coils,
        lines,
        energy_j,
        coenergy_j,
        newton_iterations: solution.report.iterations,
        converged: solution.report.converged,
        residual_history: solution.report.history.iter().map(|s| s.relative_residual).collect(),
        nodes: solver.mesh().nodes.len(),
        elements: solver.mesh().triangles.len(),
        order: solver.order().degree(),
        unknowns: solver.unknowns(),
        timings_s: Timings {
            read,
            assemble: t.assemble_s,
            solve: solver.symbolic_factorisation_s() + t.factor_s + t.solve_s + incremental_s,
            post: post_first,
            total: start.elapsed().as_secs_f64(),
        },
    };
    Ok((report, solver, solution))
}
