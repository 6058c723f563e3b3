//! `mrbrake optimize PROBLEM.toml`: constrained single- or multi-objective optimisation of a brake
//! design (NSGA-II or pattern search), every evaluation by the FEA through the results store; writes
//! all evaluations and the Pareto front (CSV), plots, and the front's designs as spec files.

use std::path::PathBuf;

use clap::Args;
use mrbrake::explore::optimize::{self, OptimizeProgress};
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
    /// Continue an existing store: the seeded optimiser replays its designs, stored ones are read
    /// back instead of recomputed.
    #[arg(long)]
    resume: bool,
    /// Analyses run at the same time (0: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Output folder: evaluations.csv, pareto.csv, pareto.svg/.png, constraints.svg/.png,
    /// designs/front-NN.toml and designs/reference.toml.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// NSGA-II generations after the initial population, overriding the problem file's
    /// `algorithm.generations` (e.g. 1 for a quick run).
    #[arg(long, value_name = "N")]
    generations: Option<usize>,
    /// The most designs to evaluate, overriding the problem file's budget: pattern search's
    /// `algorithm.max_evaluations`; for NSGA-II, the generations that fit in N designs.
    #[arg(long, value_name = "N")]
    max_evaluations: Option<usize>,
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
    problem.apply_set(&parse_sets(&a.set)?)?;
    for note in &problem.notes {
        eprintln!("note: {note}");
    }
    let budget = BudgetOverride { generations: a.generations, max_evaluations: a.max_evaluations };
    problem.algorithm = problem.algorithm.with_budget(budget)?;
    let store_path = a.store.clone().unwrap_or_else(|| optimize::default_store_path(path));
    let mut store = optimize::open_problem_store(&problem, &store_path, a.resume)?;
    let mut display = ProgressDisplay::new("optimize", a.json);
    let result = optimize::run(&problem, &mut store, a.jobs, &mut |p: &OptimizeProgress| {
        display.update_optimize(p);
        Flow::Continue
    })?;
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
