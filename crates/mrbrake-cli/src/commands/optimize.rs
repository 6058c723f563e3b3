//! `mrbrake optimize PROBLEM.toml`: constrained single- or multi-objective optimisation of a brake
//! design (NSGA-II, surrogate-assisted, or pattern search), every evaluation by the FEA through the
//! results store; writes all evaluations and the Pareto front (CSV), plots (the front, the
//! constraints, the hypervolume against evaluations), and the front's designs as spec files;
//! `--polish N` refines front design N by a pattern search started at it.

use std::path::PathBuf;

use clap::Args;
use mrbrake::explore::optimize::{self, OptimizeProgress};
use mrbrake::explore::polish::{DEFAULT_POLISH_EVALUATIONS, PolishRequest};
use mrbrake::explore::problem::{BudgetOverride, OptimizationProblem};
use mrbrake::explore::variable::parse_sets;
use mrbrake::observe::Flow;
use mrbrake::report::study::{self as study_report, OptimizationReport};

use crate::error::CommandResult;
use crate::error::InputError;
use crate::output::{print_json, print_text};
use crate::progress::ProgressDisplay;

/// Arguments of `mrbrake optimize`.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// Problem file (TOML): base spec, variables with bounds, constraints, objectives, algorithm
    /// (every key: docs/reference/study.md or `mrbrake schema study --markdown`).
    #[arg(required_unless_present = "list_metrics")]
    problem: Option<PathBuf>,
    /// Results store (SQLite). Default: `<problem name>.sqlite` in the current folder. An existing
    /// store needs --resume.
    #[arg(long, value_name = "FILE")]
    store: Option<PathBuf>,
    /// Continue an existing store: NSGA-II and pattern search replay their designs (stored ones
    /// are read back instead of recomputed); the surrogate rebuilds its models from the stored
    /// designs and continues.
    #[arg(long)]
    resume: bool,
    /// Analyses run at the same time (0: one per core); also the surrogate's designs per
    /// iteration unless the problem sets `algorithm.batch`.
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Output folder: evaluations.csv, pareto.csv, hypervolume.csv, pareto.svg/.png,
    /// constraints.svg/.png, hypervolume.svg/.png, designs/front-NN.toml (in the base spec's
    /// units, rounded to the problem's manufacturing_resolution) and designs/reference.toml.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// NSGA-II generations after the initial population, overriding the problem file's
    /// `algorithm.generations` (e.g. 1 for a quick run).
    #[arg(long, value_name = "N")]
    generations: Option<usize>,
    /// The most designs to evaluate, overriding the problem file's budget: the surrogate's and
    /// pattern search's `algorithm.max_evaluations` (a finished surrogate run continues with
    /// --resume and a larger N); for NSGA-II, the generations that fit in N designs.
    #[arg(long, value_name = "N")]
    max_evaluations: Option<usize>,
    /// The seed, overriding the problem file's `algorithm.seed` (repeated runs of a benchmark).
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// After the run, polish front design N (as in designs/front-NN.toml) by a pattern search
    /// started at it: it improves one objective (--polish-objective) without worsening the others.
    #[arg(long, value_name = "N")]
    polish: Option<usize>,
    /// The objective the polish improves (its metric; default the first objective).
    #[arg(long, value_name = "METRIC", requires = "polish")]
    polish_objective: Option<String>,
    /// The most designs the polish evaluates.
    #[arg(long, value_name = "N", requires = "polish", default_value_t = DEFAULT_POLISH_EVALUATIONS)]
    polish_evaluations: usize,
    /// A fixed change to the base spec after the problem's `[set]`, as `mrbrake sweep --set`
    /// (e.g. `materials.bobbin=pom`, `coil.turns=fill`); a variable of the problem on the same
    /// field is then fixed at that value, not varied. Repeatable.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    set: Vec<String>,
    /// List the metrics a problem may constrain or optimise, and exit.
    #[arg(long)]
    list_metrics: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake optimize`.
pub fn run(a: OptimizeArgs) -> CommandResult {
    if a.list_metrics {
        return print_text(&study_report::metrics_text());
    }
    let path = a.problem.as_ref().ok_or_else(|| InputError("give a PROBLEM.toml".into()))?;
    let mut problem = OptimizationProblem::from_path(path)?;
    let sets = parse_sets(&a.set).map_err(super::field_flags::study)?;
    problem.apply_set(&sets).map_err(super::field_flags::study)?;
    for note in &problem.notes {
        eprintln!("note: {note}");
    }
    let budget = BudgetOverride {
        generations: a.generations,
        max_evaluations: a.max_evaluations,
        seed: a.seed,
    };
    problem.algorithm = problem.algorithm.with_budget(budget).map_err(super::field_flags::study)?;
    let polish = a.polish.map(|design| PolishRequest {
        design,
        objective: a.polish_objective.clone(),
        max_evaluations: a.polish_evaluations,
    });
    // The library's rules, checked before the optimisation runs.
    if let Some(request) = &polish {
        request.check().map_err(super::field_flags::study)?;
    }
    let store_path = a.store.clone().unwrap_or_else(|| optimize::default_store_path(path));
    let mut store = optimize::open_problem_store(&problem, &store_path, a.resume)?;
    let mut display = ProgressDisplay::new("optimize", a.json);
    let mut observer = |p: &OptimizeProgress| {
        display.update_optimize(p);
        Flow::Continue
    };
    let result = optimize::run_with(&problem, &mut store, a.jobs, polish.as_ref(), &mut observer)
        .map_err(super::field_flags::study)?;
    display.finish();

    let report = OptimizationReport {
        problem: &problem,
        result: &result,
        problem_path: path,
        store: &store_path,
    };
    if let Some(dir) = &a.out {
        report.write_outputs(dir)?;
    }
    if a.json {
        return print_json(&report.json());
    }
    print_text(&report.text(a.out.as_deref()))
}
