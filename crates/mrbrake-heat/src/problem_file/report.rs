//! The report of a file-driven heat solve (serialised as the `--json` output of
//! `mrbrake fem solve`; the text is composed by `mrbrake_report::heat`).

use std::path::Path;
use std::time::Instant;

use mrbrake_fem::workflow::time::{Event, Scheme, TimeStep};
use mrbrake_observe::Flow;
use serde::{Serialize, Serializer};

use super::{HeatFile, load};
use crate::solver::HeatSolver;
use crate::{ElementOrder, HeatError, celsius};

/// The temperature at a probe.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeReport {
    /// Name from the file.
    pub name: String,
    /// r in metres.
    #[serde(rename = "r_m")]
    pub r: f64,
    /// z in metres.
    #[serde(rename = "z_m")]
    pub z: f64,
    /// Temperature \[°C\].
    #[serde(rename = "T_C")]
    pub t_c: f64,
}

/// A region's temperatures and heat.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionReport {
    /// Physical tag.
    pub physical: u32,
    /// Volume-mean temperature \[°C\].
    #[serde(rename = "mean_T_C")]
    pub mean_t_c: f64,
    /// Largest temperature \[°C\].
    #[serde(rename = "max_T_C")]
    pub max_t_c: f64,
    /// Heat generated \[W\].
    #[serde(rename = "heat_W")]
    pub heat_w: f64,
}

/// Heat out of a boundary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryReport {
    /// Physical tag.
    pub physical: u32,
    /// Heat out \[W\].
    #[serde(rename = "heat_out_W")]
    pub heat_out_w: f64,
}

/// A probe's temperature over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeSeries {
    /// Probe name.
    pub name: String,
    /// Temperature at each time \[°C\].
    #[serde(rename = "T_C")]
    pub t_c: Vec<f64>,
}

/// A region's maximum temperature over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionSeries {
    /// Physical tag.
    pub physical: u32,
    /// Largest temperature at each time \[°C\].
    #[serde(rename = "max_T_C")]
    pub max_t_c: Vec<f64>,
}

/// The history of a transient run (the initial state first).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransientReport {
    /// Times \[s\].
    pub time_s: Vec<f64>,
    /// Probe temperatures.
    pub probes: Vec<ProbeSeries>,
    /// Region maxima.
    pub regions: Vec<RegionSeries>,
    /// Largest |generated − out − stored| over the steps \[W\].
    #[serde(rename = "max_energy_imbalance_W")]
    pub max_energy_imbalance_w: f64,
    /// Scheme used (`"Bdf2"` or `"ImplicitEuler"`, the names this report has always had).
    #[serde(serialize_with = "scheme_name")]
    pub scheme: Scheme,
    /// Numeric factorisations (linear) or Newton iterations (radiation) over the run.
    pub factorizations_or_iterations: usize,
    /// Rejected steps of an adaptive run (absent for fixed steps).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rejected_steps: Option<usize>,
}

/// The scheme as heat reports have always named it (the magnetics report says `"bdf2"`): kept so
/// that the `--json` output of existing files does not change.
fn scheme_name<S: Serializer>(scheme: &Scheme, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(match scheme {
        Scheme::Bdf2 => "Bdf2",
        Scheme::ImplicitEuler => "ImplicitEuler",
    })
}

/// Seconds spent per phase of a heat solve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeatTimings {
    /// Reading the file and the mesh.
    pub read: f64,
    /// Set-up and solves.
    pub solve: f64,
    /// Whole command.
    pub total: f64,
}

/// The report of a heat solve (steady, or the final state of a transient plus its history).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeatReport {
    /// Always `"heat"`.
    pub physics: &'static str,
    /// Probe temperatures.
    pub probes: Vec<ProbeReport>,
    /// Region statistics.
    pub regions: Vec<RegionReport>,
    /// Boundary heat.
    pub boundaries: Vec<BoundaryReport>,
    /// Sources − outflow (− stored rate for a transient's last step) \[W\]: round-off.
    #[serde(rename = "energy_balance_W")]
    pub energy_balance_w: f64,
    /// Heat generated \[W\].
    #[serde(rename = "heat_generated_W")]
    pub heat_generated_w: f64,
    /// The transient history, if the file asked for one.
    pub transient: Option<TransientReport>,
    /// Newton iterations of the steady solve (0 for a transient).
    pub newton_iterations: usize,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh elements.
    pub elements: usize,
    /// Element order.
    pub order: usize,
    /// Unknowns.
    pub unknowns: usize,
    /// Timings.
    pub timings_s: HeatTimings,
}

fn probes_at(
    solver: &HeatSolver,
    t: &[f64],
    file: &HeatFile,
    path: &Path,
) -> Result<Vec<f64>, HeatError> {
    file.probes
        .iter()
        .map(|p| {
            solver.temperature_at(t, p.point).map(celsius).map_err(|e| {
                let table = format!("probe[{}]", p.name);
                match e {
                    HeatError::Input(e) => {
                        HeatError::from(e.under(table).in_file(path.display().to_string(), None))
                    }
                    other => other,
                }
            })
        })
        .collect()
}

/// Runs the transient of `file` and records its history.
fn run_transient(
    solver: &mut HeatSolver,
    file: &HeatFile,
    path: &Path,
) -> Result<(Vec<f64>, TransientReport), HeatError> {
    let (options, initial) = file.transient.expect("called for transient files");
    let start = solver.uniform(initial.unwrap_or_else(|| solver.reference_temperature()));
    let mut time_s = Vec::new();
    let mut probes: Vec<Vec<f64>> = vec![Vec::new(); file.probes.len()];
    let mut regions: Vec<Vec<f64>> = vec![Vec::new(); solver.problem().regions.len()];
    let mut worst: f64 = 0.0;
    let mut failure = None;
    let outcome = solver.transient(&start, &options, |e: &Event<'_, HeatSolver>| {
        let (s, t) = (e.problem, e.level.u);
        time_s.push(e.level.t);
        match probes_at(s, t, file, path) {
            Ok(values) => probes.iter_mut().zip(values).for_each(|(series, v)| series.push(v)),
            Err(error) => {
                failure = Some(error);
                return Flow::Stop;
            }
        }
        for (series, stats) in regions.iter_mut().zip(s.region_stats(t)) {
            series.push(celsius(stats.max_k));
        }
        if e.level.index > 0 {
            worst = worst.max(s.energy_balance(t).imbalance_w.abs());
        }
        Flow::Continue
    })?;
    if let Some(error) = failure {
        return Err(error);
    }
    let report = TransientReport {
        time_s,
        probes: file
            .probes
            .iter()
            .zip(probes)
            .map(|(p, t_c)| ProbeSeries { name: p.name.clone(), t_c })
            .collect(),
        regions: solver
            .problem()
            .regions
            .iter()
            .zip(regions)
            .map(|(r, max_t_c)| RegionSeries { physical: r.tag, max_t_c })
            .collect(),
        max_energy_imbalance_w: worst,
        scheme: options.scheme,
        factorizations_or_iterations: if solver.radiation {
            outcome.newton_iterations
        } else {
            outcome.factorizations
        },
        rejected_steps: matches!(options.step, TimeStep::Adaptive { .. })
            .then_some(outcome.rejected_steps),
    };
    Ok((outcome.u, report))
}

/// Reads, solves and post-processes a heat problem file (`order` overrides the file's); returns
/// the report, the solver and the final temperature (K per DOF).
pub fn solve_file(
    path: &Path,
    order: Option<ElementOrder>,
) -> Result<(HeatReport, HeatSolver, Vec<f64>), HeatError> {
    let start = Instant::now();
    let mut file = load(path)?;
    if let Some(order) = order {
        file.options.order = order;
    }
    let read = start.elapsed().as_secs_f64();
    let solve_start = Instant::now();
    let mut solver = HeatSolver::new(file.problem.clone(), file.options)?;
    let (t, transient, newton_iterations) = if file.transient.is_some() {
        let (t, report) = run_transient(&mut solver, &file, path)?;
        (t, Some(report), 0)
    } else {
        let (t, report) = solver.steady(None).map_err(|e| match e {
            HeatError::Input(f) => HeatError::from((*f).in_file(path.display().to_string(), None)),
            other => other,
        })?;
        (t, None, report.iterations)
    };
    let solve = solve_start.elapsed().as_secs_f64();
    let values = probes_at(&solver, &t, &file, path)?;
    let probes = file
        .probes
        .iter()
        .zip(values)
        .map(|(p, t_c)| ProbeReport { name: p.name.clone(), r: p.point[0], z: p.point[1], t_c })
        .collect();
    let regions = solver
        .region_stats(&t)
        .iter()
        .map(|s| RegionReport {
            physical: s.physical,
            mean_t_c: celsius(s.mean_k),
            max_t_c: celsius(s.max_k),
            heat_w: s.heat_w,
        })
        .collect();
    let boundaries = solver
        .boundary_heat(&t)
        .iter()
        .map(|b| BoundaryReport { physical: b.physical, heat_out_w: b.heat_out_w })
        .collect();
    let balance = solver.energy_balance(&t);
    let mesh = &solver.problem().mesh;
    let report = HeatReport {
        physics: "heat",
        probes,
        regions,
        boundaries,
        energy_balance_w: balance.imbalance_w,
        heat_generated_w: balance.generated_w,
        transient,
        newton_iterations,
        nodes: mesh.nodes.len(),
        elements: mesh.triangles.len(),
        order: solver.basis().order().degree(),
        unknowns: solver.unknowns(),
        timings_s: HeatTimings { read, solve, total: start.elapsed().as_secs_f64() },
    };
    Ok((report, solver, t))
}
