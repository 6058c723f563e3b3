//! `mrbrake.sweep` and `mrbrake.optimize`: design studies into the results store, as the CLI's
//! `mrbrake sweep` and `mrbrake optimize` run them (`mrbrake::explore`), returning the same
//! `--json` documents (`mrbrake::report::study`). The whole study runs without the GIL.

use std::path::PathBuf;

use mrbrake::design::analysis::ElementOrder;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::explore::plan::{self, Sampling, Shard, SweepRequest};
use mrbrake::explore::problem::{BudgetOverride, OptimizationProblem};
use mrbrake::explore::variable::parse_sets;
use mrbrake::explore::{EvaluationSettings, ExploreError, Runner, optimize, runner};
use mrbrake::observe::Silent;
use mrbrake::report::study::{OptimizationReport, SweepReport};
use mrbrake::units::Dimension;
use pyo3::prelude::*;
use serde_json::Value;

use crate::convert::{SpecInput, json_to_py, quantity};
use crate::error;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(optimize_problem, m)?)?;
    Ok(())
}

/// The evaluation settings of every analysis of a sweep (their ranges are the library's rules).
pub(crate) fn settings(
    mesh: &str,
    order: u8,
    speed: Option<&Bound<'_, PyAny>>,
) -> PyResult<EvaluationSettings> {
    let order = ElementOrder::try_from(i64::from(order)).map_err(error::to_py)?;
    Ok(EvaluationSettings {
        mesh: MeshLevel::parse(mesh).map_err(error::to_py)?,
        speed_rad_s: quantity(speed, "1rad/s", Dimension::AngularVelocity, "speed")?,
        order,
        ..EvaluationSettings::default()
    })
}

/// The sweep's inputs that do not need Python objects, moved into the GIL-free part.
struct SweepJob {
    overrides: Vec<(String, String)>,
    vary: Vec<String>,
    sampling: Sampling,
    shard: Shard,
    settings: EvaluationSettings,
    store: PathBuf,
    resume: bool,
    jobs: usize,
}

impl SweepJob {
    /// Plans, evaluates into the store and composes the `sweep --json` document.
    fn run(&self, spec_text: &str, origin: &str) -> Result<Value, ExploreError> {
        let request = SweepRequest {
            spec_text,
            origin,
            overrides: &self.overrides,
            vary: &self.vary,
            sampling: self.sampling,
            shard: self.shard,
            settings: self.settings.clone(),
        };
        let sweep = plan::sweep_plan(&request)?;
        let created_by = format!("mrbrake {}", env!("CARGO_PKG_VERSION"));
        let mut store = runner::open_sweep_store(&self.store, self.resume, &created_by)?;
        let mut runner = Runner::new(&mut store, sweep.space.settings().clone(), self.jobs);
        let (records, summary) = runner.run(&sweep.designs, &mut Silent)?;
        let report = SweepReport {
            name: "",
            variables: sweep.space.variables(),
            records: &records,
            summary: &summary,
            plan_points: sweep.plan_points,
            shard: self.shard,
            store: &self.store,
        };
        Ok(report.json())
    }
}

/// A parameter sweep into a results store; see `python/mrbrake/__init__.py` (`sweep`).
#[pyfunction]
#[pyo3(signature = (spec, vary, store, overrides, *, sample=None, seed=1, resume=false, jobs=0,
                    shard=None, mesh="default", order=1, speed=None))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    spec: Option<&Bound<'py, PyAny>>,
    vary: Vec<String>,
    store: PathBuf,
    overrides: Vec<(String, String)>,
    sample: Option<String>,
    seed: u64,
    resume: bool,
    jobs: usize,
    shard: Option<String>,
    mesh: &str,
    order: u8,
    speed: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = SpecInput::from_py(spec)?;
    let sampling = match sample {
        Some(text) => Sampling::parse(&text, seed).map_err(error::to_py)?,
        None => Sampling::FullFactorial,
    };
    let shard = match shard {
        Some(text) => Shard::parse(&text).map_err(error::to_py)?,
        None => Shard::ALL,
    };
    let settings = settings(mesh, order, speed)?;
    let job = SweepJob { overrides, vary, sampling, shard, settings, store, resume, jobs };
    let report = py.detach(|| -> PyResult<Value> {
        let (text, origin) = spec.text()?;
        job.run(&text, &origin).map_err(error::to_py)
    })?;
    json_to_py(py, &report)
}

/// The budget and fixed changes a Python caller gives beside the problem file (the CLI's
/// `--generations`, `--max-evaluations`, `--seed` and `--set`).
struct ProblemOverrides {
    budget: BudgetOverride,
    sets: Vec<String>,
}

impl ProblemOverrides {
    /// `problem` with the fixed changes and the budget applied, as the CLI applies them (the
    /// library's field names, `set`, `generations`, `max_evaluations`, are the keywords).
    fn apply(&self, problem: &mut OptimizationProblem) -> Result<(), ExploreError> {
        problem.apply_set(&parse_sets(&self.sets)?)?;
        problem.algorithm = problem.algorithm.with_budget(self.budget)?;
        Ok(())
    }
}

/// An optimisation study; see `python/mrbrake/__init__.py` (`optimize`).
#[pyfunction]
#[pyo3(signature = (problem, store=None, *, resume=false, jobs=0, out=None, generations=None,
                    max_evaluations=None, seed=None, set=Vec::new()))]
#[allow(clippy::too_many_arguments)]
fn optimize_problem(
    py: Python<'_>,
    problem: PathBuf,
    store: Option<PathBuf>,
    resume: bool,
    jobs: usize,
    out: Option<PathBuf>,
    generations: Option<usize>,
    max_evaluations: Option<usize>,
    seed: Option<u64>,
    set: Vec<String>,
) -> PyResult<Bound<'_, PyAny>> {
    let overrides = ProblemOverrides {
        budget: BudgetOverride { generations, max_evaluations, seed },
        sets: set,
    };
    let report = py.detach(|| -> PyResult<Value> {
        error::exists(&problem)?;
        let mut parsed = OptimizationProblem::from_path(&problem).map_err(error::to_py)?;
        overrides.apply(&mut parsed).map_err(error::to_py)?;
        let store_path = store.unwrap_or_else(|| optimize::default_store_path(&problem));
        let mut store =
            optimize::open_problem_store(&parsed, &store_path, resume).map_err(error::to_py)?;
        let result = optimize::run(&parsed, &mut store, jobs, &mut Silent).map_err(error::to_py)?;
        let report = OptimizationReport {
            problem: &parsed,
            result: &result,
            problem_path: &problem,
            store: &store_path,
        };
        if let Some(dir) = &out {
            report.write_outputs(dir).map_err(error::to_py)?;
        }
        Ok(report.json())
    })?;
    json_to_py(py, &report)
}
