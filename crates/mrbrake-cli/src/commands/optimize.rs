//! `mrbrake optimize PROBLEM.toml`: constrained single- or multi-objective optimisation of a brake
//! design (NSGA-II or pattern search), every evaluation by the FEA through the results store; writes
//! all evaluations and the Pareto front (CSV), plots, and the front's designs as spec files.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use mrbrake_explore::evaluate::{METRICS, metric_info};
use mrbrake_explore::optimize::{self, Evaluated, OptimizationResult};
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_report::pareto::{
    ConstraintActivity, ObjectivePlot, constraint_activity_figure, objective_figure,
};
use mrbrake_store::{Record, Store};

use crate::exit::InputError;
use crate::output::print_json;
use crate::progress::ProgressDisplay;

/// Arguments of `mrbrake optimize`.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// Problem file (TOML): base spec, variables with bounds, constraints, objectives, algorithm.
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
    /// List the metrics a problem may constrain or optimise, and exit.
    #[arg(long)]
    list_metrics: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake optimize`.
pub fn run(a: OptimizeArgs) -> anyhow::Result<()> {
    if a.list_metrics {
        for m in METRICS {
            crate::outln!("{:<28} {:<8} {}", m.name, m.unit, m.meaning);
        }
        return Ok(());
    }
    let path = a.problem.as_ref().ok_or_else(|| InputError("give a PROBLEM.toml".into()))?;
    let problem = OptimizationProblem::from_path(path)?;
    let store_path = a.store.clone().unwrap_or_else(|| {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("optimize");
        PathBuf::from(format!("{stem}.sqlite"))
    });
    let mut store = Store::open_or_create(&store_path, a.resume)?;
    if store.meta("problem")?.is_none() {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        store.set_meta("problem", &text)?;
    }
    let mut display = ProgressDisplay::new("optimize", a.json);
    let result = optimize::run(&problem, &mut store, a.jobs, &mut |p| display.update(p))?;
    display.finish();

    if let Some(dir) = &a.out {
        write_outputs(dir, &problem, &result)?;
    }
    let totals = &result.totals.progress;
    let rate =
        if totals.elapsed_s > 0.0 { totals.computed as f64 * 60.0 / totals.elapsed_s } else { 0.0 };
    if a.json {
        let front: Vec<&Record> =
            result.front.iter().map(|&i| &result.evaluated[i].record).collect();
        let front: Vec<Record> = front.into_iter().cloned().collect();
        return print_json(&serde_json::json!({
            "problem": path.display().to_string(),
            "store": store_path.display().to_string(),
            "evaluated": result.evaluated.len(),
            "requested": result.requested,
            "iterations": result.iterations,
            "converged": result.converged,
            "computed": totals.computed,
            "reused": totals.reused,
            "elapsed_s": totals.elapsed_s,
            "evaluations_per_min": rate,
            "front": mrbrake_store::to_json(&front),
            "reference": result.reference.as_ref().map(|r| mrbrake_store::to_json(std::slice::from_ref(&r.record))),
        }));
    }
    let how = match result.converged {
        None => format!("{} generations", result.iterations),
        Some(true) => format!("converged after {} iterations", result.iterations),
        Some(false) => {
            format!(
                "evaluation budget spent after {} iterations (not converged)",
                result.iterations
            )
        }
    };
    let work = if totals.computed == 0 {
        format!("all {} answers read from the store, nothing computed", totals.reused)
    } else {
        format!(
            "{} evaluated now, {} answers read from the store (repeated designs and earlier \
             runs); {:.1} s, {rate:.0} evaluations/min",
            totals.computed, totals.reused, totals.elapsed_s
        )
    };
    crate::outln!(
        "{}: {how}; {} distinct designs{}; {work}; store {}",
        path.display(),
        result.evaluated.len(),
        if result.reference.is_some() { " + the reference" } else { "" },
        store_path.display()
    );
    let feasible = result.evaluated.iter().filter(|e| e.evaluation.feasible()).count();
    if result.front.is_empty() {
        crate::outln!("no evaluated design meets every constraint");
    } else if problem.objectives.len() == 1 {
        crate::outln!("{feasible} feasible; the best feasible design:");
    } else {
        crate::outln!("{feasible} feasible; Pareto front of {} designs:", result.front.len());
    }
    print_designs(&problem, &result, result.front.iter().map(|&i| &result.evaluated[i]), "front");
    if let Some(reference) = &result.reference {
        print_designs(&problem, &result, std::iter::once(reference), "reference (base spec)");
    }
    if let Some(dir) = &a.out {
        crate::outln!("outputs in {}", dir.display());
    }
    Ok(())
}

fn metric(record: &Record, name: &str) -> Option<f64> {
    record.metrics.iter().find(|(k, _)| k == name).map(|(_, v)| *v)
}

fn print_designs<'a>(
    problem: &OptimizationProblem,
    result: &OptimizationResult,
    designs: impl Iterator<Item = &'a Evaluated>,
    what: &str,
) {
    let metrics: Vec<&String> = problem
        .objectives
        .iter()
        .map(|o| &o.metric)
        .chain(problem.constraints.iter().map(|c| &c.metric))
        .collect();
    // Every column as wide as its header (at least 10 characters), values right-aligned under it.
    let mut headers: Vec<String> = problem.variables.iter().map(|v| v.name.clone()).collect();
    headers.extend(metrics.iter().map(|name| axis(name).1));
    let widths: Vec<usize> = headers.iter().map(|h| h.chars().count().max(10)).collect();
    let first = what.chars().count().max(10);
    let mut header = format!("  {what:<first$}");
    for (h, w) in headers.iter().zip(&widths) {
        header.push_str(&format!(" {h:>w$}"));
    }
    crate::outln!("{header}");
    for (k, e) in designs.enumerate() {
        let mut cells: Vec<String> = result
            .variables
            .iter()
            .map(|v| {
                let value = e.record.variables.iter().find(|(k, _)| *k == v.name).map(|(_, x)| *x);
                value.map_or_else(|| "base".to_string(), |x| v.display_value(x))
            })
            .collect();
        cells.extend(metrics.iter().map(|name| match metric(&e.record, name) {
            Some(v) => format!("{:.4}", v * axis(name).0),
            None => e.record.status.as_str().to_string(),
        }));
        let mut line = format!("  {:<first$}", format!("#{}", k + 1));
        for (cell, w) in cells.iter().zip(&widths) {
            line.push_str(&format!(" {cell:>w$}"));
        }
        crate::outln!("{line}");
    }
}

/// Display scale and label of a metric on a plot axis.
fn axis(name: &str) -> (f64, String) {
    let (scale, unit) = match name {
        n if n.ends_with("_m3") => (1e6, "cm³"),
        n if n.ends_with("_kg_m2") => (1e6, "kg·mm²"),
        n if n.ends_with("_m") => (1e3, "mm"),
        _ => (1.0, metric_info(name).map_or("", |m| m.unit)),
    };
    (scale, format!("{name} [{unit}]"))
}

fn write_outputs(
    dir: &Path,
    problem: &OptimizationProblem,
    result: &OptimizationResult,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir.join("designs"))
        .with_context(|| format!("cannot create {}", dir.display()))?;
    let all: Vec<Record> = result.evaluated.iter().map(|e| e.record.clone()).collect();
    mrbrake_report::write_atomic(&dir.join("evaluations.csv"), &mrbrake_store::to_csv(&all)?)?;
    let front: Vec<Record> =
        result.front.iter().map(|&i| result.evaluated[i].record.clone()).collect();
    mrbrake_report::write_atomic(&dir.join("pareto.csv"), &mrbrake_store::to_csv(&front)?)?;
    for (k, record) in front.iter().enumerate() {
        let text = format!(
            "# Design {} of the front of {} (key {}).\n{}",
            k + 1,
            problem.path.display(),
            record.key,
            record.spec_toml
        );
        mrbrake_report::write_atomic(
            &dir.join("designs").join(format!("front-{:02}.toml", k + 1)),
            text.as_bytes(),
        )?;
    }
    if let Some(reference) = &result.reference {
        mrbrake_report::write_atomic(
            &dir.join("designs").join("reference.toml"),
            reference.record.spec_toml.as_bytes(),
        )?;
    }

    // Objective plot: the first two objectives (or objective vs. its first constraint metric).
    let x_metric = &problem.objectives[0].metric;
    let y_metric = problem
        .objectives
        .get(1)
        .map(|o| o.metric.clone())
        .or_else(|| problem.constraints.first().map(|c| c.metric.clone()));
    let (xs, x_label) = axis(x_metric);
    if let Some(y_metric) = y_metric {
        let (ys, y_label) = axis(&y_metric);
        let point = |r: &Record| Some((metric(r, x_metric)? * xs, metric(r, &y_metric)? * ys));
        let mut plot = ObjectivePlot {
            title: format!(
                "{} — {} evaluated designs",
                problem.path.file_stem().and_then(|s| s.to_str()).unwrap_or("optimisation"),
                result.evaluated.len()
            ),
            x_label: x_label.clone(),
            y_label,
            ..ObjectivePlot::default()
        };
        for e in &result.evaluated {
            if let Some(p) = point(&e.record) {
                if e.evaluation.feasible() {
                    plot.feasible.push(p)
                } else {
                    plot.infeasible.push(p)
                }
            }
        }
        plot.front = front.iter().filter_map(point).collect();
        plot.front.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(reference) = &result.reference {
            if let Some(p) = point(&reference.record) {
                let base = problem.spec_path.file_name().map(|f| f.to_string_lossy());
                plot.references
                    .push((format!("reference: base spec {}", base.unwrap_or_default()), p));
            }
        }
        let figure = objective_figure(&plot);
        figure.save(&dir.join("pareto.svg"))?;
        figure.save(&dir.join("pareto.png"))?;
    }

    if !problem.constraints.is_empty() && !front.is_empty() {
        let activity = ConstraintActivity {
            title: "Constraint activity along the front (0 = active)".into(),
            x_label,
            constraints: problem
                .constraints
                .iter()
                .map(|c| {
                    let label = format!(
                        "{}{}{}",
                        c.metric,
                        c.min.map_or(String::new(), |v| format!(" ≥ {v}")),
                        c.max.map_or(String::new(), |v| format!(" ≤ {v}"))
                    );
                    let mut points: Vec<(f64, f64)> = front
                        .iter()
                        .filter_map(|r| {
                            Some((metric(r, x_metric)? * xs, c.margin(metric(r, &c.metric)?)))
                        })
                        .collect();
                    points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    (label, points)
                })
                .collect(),
        };
        let figure = constraint_activity_figure(&activity);
        figure.save(&dir.join("constraints.svg"))?;
        figure.save(&dir.join("constraints.png"))?;
    }
    Ok(())
}
