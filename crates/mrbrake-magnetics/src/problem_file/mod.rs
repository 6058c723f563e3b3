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
//!
//! Magnetodynamics (eddy currents, voltage-driven coils, `[transient]` or `[harmonic]`) adds the
//! keys described in [`dynamics`].

use mrbrake_error::FieldError;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesh::locate::Probe;

use crate::ElementOrder;
use crate::MagneticsError;
use crate::field::{CoilLinkage, Solution};
use crate::material::Magnetic;
use crate::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use crate::solver::{Solver, SolverOptions};

pub mod dynamics;
mod raw;
mod report;

pub use dynamics::{DynamicsReport, DynamicsSpec, vtu_files};
pub use raw::schema;
use raw::{RawBoundary, RawFile, RawRegion, RawSolver};
use report::probe_report;
pub use report::{
    CoilReport, LineReport, MagneticsTimings, ProbeReport, RegionReport, SolveReport,
};

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
    /// The transient or harmonic solve asked for (`None`: a static file).
    pub dynamics: Option<DynamicsSpec>,
}

/// The element order of the `order` key (absent: P1).
fn order_of(value: Option<&toml::Value>, file: &str) -> Result<ElementOrder, MagneticsError> {
    let Some(value) = value else { return Ok(ElementOrder::P1) };
    value.as_integer().and_then(ElementOrder::from_degree).ok_or_else(|| {
        let allowed = "1 (linear triangles) or 2 (quadratic, 6-node triangles)";
        MagneticsError::from(FieldError::out_of_range("order", value, allowed).in_file(file, None))
    })
}

/// Reads a problem file and everything it refers to (mesh, B-H files).
pub fn load(path: &Path) -> Result<ProblemFile, MagneticsError> {
    let file = path.display().to_string();
    let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
        .map_err(|e| MagneticsError::in_file(&file, "", format!("cannot read: {e}")))?;
    let raw: RawFile =
        toml::from_str(&text).map_err(|e| MagneticsError::in_file(&file, "", e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let order = order_of(raw.order.as_ref(), &file)?;
    let mesh_path = dir.join(&raw.mesh);
    let start = Instant::now();
    let (gmsh, scale) =
        mrbrake_fem::mesh::gmsh::read_problem_mesh(path, &raw.mesh, raw.length_unit.as_deref())?;
    let mesh_read_s = start.elapsed().as_secs_f64();
    let regions = regions_of(&raw.region, dir, &file)?;
    let boundaries = boundaries_of(&raw.boundary, &gmsh.mesh, scale, &file, &mesh_path)?;
    let options = options_of(raw.solver.as_ref(), order, &file)?;
    let (probes, lines) = probes_of(&raw, scale, &file)?;
    let problem = Problem { mesh: Arc::new(gmsh.mesh), regions, boundaries };
    // Region/mesh consistency (unknown groups, missing materials) is checked here so the error
    // names the file.
    check_regions(&problem, &file, &mesh_path)?;
    let dynamics = dynamics::spec_of(&raw, &problem, dir, &file)?;
    Ok(ProblemFile { problem, options, probes, lines, mesh_path, mesh_read_s, dynamics })
}

/// An input error of a solver query (a probe's `point`) under the problem-file table `table`
/// (`probe[far]`), located in the problem file.
fn located_at(error: MagneticsError, table: &str, file: &Path) -> MagneticsError {
    match error {
        MagneticsError::Input(e) => {
            MagneticsError::from(e.under(table).in_file(file.display().to_string(), None))
        }
        other => other,
    }
}

/// An input error about a key of the `[[region]]` or `[[boundary]]` table with physical tag
/// `physical`, located in `file` (the tag is said in the message: the table index alone is hard
/// to find in a long file).
pub(super) fn located(error: MagneticsError, file: &str, physical: u32) -> MagneticsError {
    match error {
        MagneticsError::Input(mut e) => {
            e.message = match e.message.as_str() {
                "" => format!("physical = {physical}"),
                message => format!("physical = {physical}: {message}"),
            };
            MagneticsError::from(e.in_file(file, None))
        }
        other => other,
    }
}

/// The `[[region]]` tables: material and source of each physical surface.
fn regions_of(raw: &[RawRegion], dir: &Path, file: &str) -> Result<Vec<Region>, MagneticsError> {
    let mut regions = Vec::new();
    for (k, r) in raw.iter().enumerate() {
        let field = format!("region[{k}]");
        let located = |e| located(e, file, r.physical);
        let material = match &r.material {
            None => return Err(located(MagneticsError::field(&field, "missing `material`"))),
            Some(value) => material_of(value, dir, &field).map_err(located)?,
        };
        let source = match &r.source {
            None => None,
            Some(value) => Some(source_of(value, &field).map_err(located)?),
        };
        regions.push(Region { tag: r.physical, material, source });
    }
    Ok(regions)
}

/// The `[[boundary]]` tables (Neumann boundaries are left out: they are the natural condition).
fn boundaries_of(
    raw: &[RawBoundary],
    mesh: &Mesh,
    scale: f64,
    file: &str,
    mesh_path: &Path,
) -> Result<Vec<Boundary>, MagneticsError> {
    let mut boundaries = Vec::new();
    for (k, b) in raw.iter().enumerate() {
        let field = format!("boundary[{k}]");
        let located = |e| located(e, file, b.physical);
        let condition = match b.kind.as_str() {
            "dirichlet" => Some(BoundaryCondition::Dirichlet),
            "open" => {
                Some(BoundaryCondition::Open { centre_z_m: b.centre_z.unwrap_or(0.0) * scale })
            }
            "neumann" => None,
            other => {
                let e = FieldError::out_of_range(
                    "kind",
                    format!("\"{other}\""),
                    "dirichlet, open, neumann",
                );
                return Err(located(e.under(&field).into()));
            }
        };
        if !mesh.edge_tags.contains(&b.physical) {
            let message = format!("the mesh {} has no curve with this tag", mesh_path.display());
            return Err(located(MagneticsError::field(format!("{field}.physical"), message)));
        }
        if let Some(condition) = condition {
            boundaries.push(Boundary { tag: b.physical, condition });
        }
    }
    Ok(boundaries)
}

/// The `[solver]` table on top of the defaults.
fn options_of(
    raw: Option<&RawSolver>,
    order: ElementOrder,
    file: &str,
) -> Result<SolverOptions, MagneticsError> {
    let mut options = SolverOptions { order, ..SolverOptions::default() };
    let Some(s) = raw else { return Ok(options) };
    if let Some(m) = s.max_iterations {
        if !raw::MAX_ITERATIONS.contains(m as f64) {
            let e = FieldError::out_of_range("solver.max_iterations", m, ">= 1");
            return Err(e.in_file(file, None).into());
        }
        options.max_iterations = m;
    }
    if let Some(t) = s.tolerance {
        if !raw::TOLERANCE.contains(t) {
            let e = FieldError::out_of_range("solver.tolerance", t, "(0, 1)");
            return Err(e.in_file(file, None).into());
        }
        options.residual_tolerance = t;
    }
    if let Some(q) = s.quadrature_degree {
        if !raw::QUADRATURE_DEGREE.contains(q as f64) {
            let e = FieldError::out_of_range("solver.quadrature_degree", q, "1 to 5");
            return Err(e.in_file(file, None).into());
        }
        options.quadrature_degree = q;
    }
    Ok(options)
}

/// The secant inductance λ/I of a coil, finite: at zero current with no linked flux (no other
/// source) it is its limit I → 0, the incremental inductance dλ/dI at zero (λ = L_inc(0)·I + O(I²));
/// at zero current with flux from other sources λ/I has no value, an input error naming the coil.
fn secant_inductance(
    coil: &CoilLinkage,
    incremental_h: f64,
    file: &str,
) -> Result<f64, MagneticsError> {
    if coil.inductance_h.is_finite() {
        return Ok(coil.inductance_h);
    }
    if coil.flux_linkage_wb.abs() <= f64::MIN_POSITIVE && incremental_h.is_finite() {
        return Ok(incremental_h);
    }
    Err(MagneticsError::in_file(
        file,
        "region",
        format!(
            "region physical = {}: source current_A = {} links {:.4e} Wb from other sources, so \
         its secant inductance λ/I is undefined; give the coil a non-zero current",
            coil.physical, coil.current_a, coil.flux_linkage_wb
        ),
    ))
}

/// The most intervals of one `[[line]]` (each is a point location and a field evaluation; the
/// report holds them all).
pub const MAX_LINE_SAMPLES: usize = 100_000;

/// The `[[probe]]` and `[[line]]` tables, in metres; `samples` beyond [`MAX_LINE_SAMPLES`] is an
/// input error naming the line.
fn probes_of(
    raw: &RawFile,
    scale: f64,
    file: &str,
) -> Result<(Vec<Probe>, Vec<LineProbe>), MagneticsError> {
    if let Some((i, l)) =
        raw.line.iter().enumerate().find(|(_, l)| l.samples.is_some_and(|n| n > MAX_LINE_SAMPLES))
    {
        let e = FieldError::new(format!("line[{i}].samples"), format!("line '{}'", l.name))
            .with_value(l.samples.unwrap_or_default())
            .with_allowed(format!("1 to {MAX_LINE_SAMPLES}"));
        return Err(e.in_file(file, None).into());
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
    Ok((probes, lines))
}

fn check_regions(problem: &Problem, file: &str, mesh_path: &Path) -> Result<(), MagneticsError> {
    let tags = problem.mesh.region_tags();
    for region in &problem.regions {
        if tags.binary_search(&region.tag).is_err() {
            return Err(MagneticsError::in_file(
                file,
                "region",
                format!(
                    "region physical = {} is not a physical surface of the mesh {} (its surfaces: {tags:?})",
                    region.tag,
                    mesh_path.display()
                ),
            ));
        }
    }
    for tag in tags {
        if problem.region(tag).is_none() {
            return Err(MagneticsError::in_file(
                file,
                "region",
                format!("the mesh's physical surface {tag} has no [[region]] with a material"),
            ));
        }
    }
    Ok(())
}

fn material_of(value: &toml::Value, dir: &Path, field: &str) -> Result<Magnetic, MagneticsError> {
    match value {
        toml::Value::String(name) => {
            // The library's error names the material; the region (file and physical tag) is ours.
            let material = mrbrake_materials::library::get(name)
                .map_err(|e| MagneticsError::field(field, format!("material = \"{name}\": {e}")))?;
            Ok(material.magnetic.clone())
        }
        toml::Value::Table(table) => {
            if let Some(mu) = table.get("mu_r") {
                let mu_r = mu.as_float().or_else(|| mu.as_integer().map(|i| i as f64)).ok_or_else(
                    || MagneticsError::field(field, "material.mu_r must be a number"),
                )?;
                if !(mu_r.is_finite() && mu_r > 0.0) {
                    let e = FieldError::out_of_range("material.mu_r", mu_r, "finite, > 0");
                    return Err(e.under(field).into());
                }
                Ok(Magnetic::Linear { mu_r })
            } else if let Some(csv) = table.get("bh_csv") {
                let csv = csv.as_str().ok_or_else(|| {
                    MagneticsError::field(field, "material.bh_csv must be a path string")
                })?;
                let curve = mrbrake_materials::BhCurve::from_csv_file(&dir.join(csv))?;
                Ok(Magnetic::NonLinear(Arc::new(curve)))
            } else {
                Err(MagneticsError::field(
                    field,
                    "material table needs `mu_r` or `bh_csv` (or give a library name such as \"steel-1010\")".to_string(),
                ))
            }
        }
        _ => Err(MagneticsError::field(
            field,
            "material must be a library name, { mu_r = ... } or { bh_csv = \"file.csv\" }"
                .to_string(),
        )),
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
                MagneticsError::field(field, format!("source.{key} must be a finite number"))
            }),
    }
}

fn source_of(value: &toml::Value, field: &str) -> Result<Source, MagneticsError> {
    let table = value.as_table().ok_or_else(|| {
        MagneticsError::field(
            field,
            "source must be a table such as { turns = 100, current_A = 1.0 }".to_string(),
        )
    })?;
    for key in table.keys() {
        if !["turns", "current_A", "current_density_A_per_m2", "drive"].contains(&key.as_str()) {
            return Err(MagneticsError::field(
                field,
                format!(
                    "unknown source field `{key}`; allowed: turns, current_A, current_density_A_per_m2, drive"
                ),
            ));
        }
    }
    if let Some(drive) = table.get("drive") {
        return voltage_source(table, drive, field);
    }
    if let Some(j) = number(table, "current_density_A_per_m2", field)? {
        return Ok(Source::CurrentDensity { a_per_m2: j });
    }
    match (number(table, "turns", field)?, number(table, "current_A", field)?) {
        (Some(turns), Some(current_a)) => {
            if !raw::TURNS.contains(turns) {
                return Err(FieldError::out_of_range(
                    "source.turns",
                    turns,
                    raw::TURNS.describe(""),
                )
                .under(field)
                .into());
            }
            Ok(Source::Coil { turns, current_a })
        }
        _ => Err(MagneticsError::field(
            field,
            "source needs both `turns` and `current_A`, or `current_density_A_per_m2`".to_string(),
        )),
    }
}

/// A voltage-driven coil; its static source is the DC current `V/R`.
fn voltage_source(
    table: &toml::Table,
    drive: &toml::Value,
    field: &str,
) -> Result<Source, MagneticsError> {
    let turns =
        number(table, "turns", field)?.filter(|&n| raw::TURNS.contains(n)).ok_or_else(|| {
            let allowed = raw::TURNS.describe("");
            MagneticsError::field(
                field,
                format!("a voltage-driven source needs `turns` in {allowed}"),
            )
        })?;
    if table.contains_key("current_A") || table.contains_key("current_density_A_per_m2") {
        return Err(MagneticsError::field(
            field,
            "source takes `current_A` or `drive`, not both".to_string(),
        ));
    }
    let current_a = match dynamics::voltage_drive(drive, field)? {
        crate::dynamics::Drive::Voltage { amplitude_v, series_resistance_ohm } => {
            amplitude_v / series_resistance_ohm
        }
        crate::dynamics::Drive::Current { amplitude_a } => amplitude_a,
    };
    Ok(Source::Coil { turns, current_a })
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
    let mut solver = Solver::new(file.problem.clone(), file.options)?;
    let solution = solver.solve(None)?;
    let post_start = Instant::now();
    let (probes, lines) = sample_probes(&solver, &solution, &file, path)?;
    let mut regions = Vec::new();
    for tag in solver.mesh().region_tags() {
        let force_z_n = solver.axial_force(&solution, &[tag])?;
        regions.push(RegionReport::new(&solver.region_stats(&solution, tag)?, force_z_n));
    }
    let linkages: Vec<CoilLinkage> = solver.coils(&solution);
    let (energy_j, coenergy_j) = solver.energy(&solution);
    let post = post_start.elapsed().as_secs_f64();
    // The incremental inductance needs one more factorisation (counted as solve time).
    let inc_start = Instant::now();
    let mut coils = Vec::new();
    for c in linkages {
        let incremental = solver.incremental_inductance(&solution, c.physical)?;
        let inductance_h = secant_inductance(&c, incremental, &path.display().to_string())?;
        coils.push(CoilReport {
            physical: c.physical,
            flux_linkage_wb: c.flux_linkage_wb,
            inductance_h,
            incremental_inductance_h: incremental,
        });
    }
    let incremental_s = inc_start.elapsed().as_secs_f64();
    let t = solution.report.timings;
    let timings_s = MagneticsTimings {
        read,
        assemble: t.assemble_s,
        solve: solver.symbolic_factorisation_s() + t.factor_s + t.solve_s + incremental_s,
        post,
        total: start.elapsed().as_secs_f64(),
    };
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
        timings_s,
        dynamics: None,
    };
    let mut report = report;
    if let Some(spec) = &file.dynamics {
        report.dynamics = Some(dynamics::run(spec, &file, path)?);
        report.timings_s.total = start.elapsed().as_secs_f64();
    }
    Ok((report, solver, solution))
}

/// B at the file's probes and along its lines; a point outside the mesh is an input error naming
/// the probe or line.
fn sample_probes(
    solver: &Solver,
    solution: &Solution,
    file: &ProblemFile,
    path: &Path,
) -> Result<(Vec<ProbeReport>, Vec<LineReport>), MagneticsError> {
    let mut probes = Vec::new();
    for p in &file.probes {
        let f = solver
            .b_at(solution, p.point)
            .map_err(|e| located_at(e, &format!("probe[{}]", p.name), path))?;
        probes.push(probe_report(&p.name, &f));
    }
    let mut lines = Vec::new();
    for l in &file.lines {
        let samples = solver
            .b_along(solution, &[l.from, l.to], l.samples)
            .map_err(|e| located_at(e, &format!("line[{}]", l.name), path))?;
        lines.push(LineReport {
            name: l.name.clone(),
            points: samples.iter().map(|f| probe_report(&l.name, f)).collect(),
        });
    }
    Ok((probes, lines))
}
