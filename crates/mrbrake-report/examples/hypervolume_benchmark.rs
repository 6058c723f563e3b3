//! The README's benchmark of the surrogate-assisted optimiser against NSGA-II: every run's
//! hypervolume against evaluations, measured against common reference points, the median of the
//! surrogate's seeds, and the evaluations each run needs to reach 99 % of NSGA-II's final
//! hypervolume (`examples/optimize/surrogate-benchmark.sh` runs the studies and then this).
//!
//! ```text
//! cargo run --release -p mrbrake-report --example hypervolume_benchmark -- \
//!     PROBLEM.toml OUT.svg LABEL=RUN [LABEL=RUN ...]
//! ```
//!
//! `RUN` names a run of `mrbrake optimize --json --store RUN.sqlite > RUN.json`: its designs are
//! the first `evaluated` (from `RUN.json`) records of `RUN.sqlite` that carry variables, in the
//! store's order (the order they were evaluated in; the base spec, stored as the reference design,
//! and the front designs rounded after the run are not the algorithm's). `LABEL` is `nsga2` or
//! `surrogate`. Two reference points, so that the result does not hang on one choice:
//!
//! * `thesis`: the objectives of the thesis's design (the base spec, every store's reference
//!   record): the hypervolume of the designs better than the thesis's in both objectives;
//! * `nadir`: 10 % of the range beyond the nadir of the best front known (the non-dominated set of
//!   every run's designs), the recommendation of Ishibuchi et al. (2018) for comparing algorithms:
//!   tight, so it rewards the front's shape, not the box below the thesis design.
//!
//! Prints, for each reference, the final hypervolume of every run as a percentage of NSGA-II's
//! (the median of the NSGA-II seeds), the evaluations it took to reach 99 %, wall times and the
//! share of the surrogate's model fitting and acquisition in its wall time; writes the curves (y:
//! percent of NSGA-II's final hypervolume, x: evaluations, logarithmic) to `OUT.svg` and `.png`.

use std::path::Path;

use mrbrake_explore::hypervolume::{self, TracePoint};
use mrbrake_explore::optimize::evaluation_for;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_optim::pareto::{Evaluation, pareto_front};
use mrbrake_optim::surrogate::beyond_worst;
use mrbrake_report::chart::{Figure, GREY, Panel, Series};
use mrbrake_store::{Status, Store};
use serde_json::Value;

/// One run: its label, its evaluations in order, the reference design's, and its JSON report.
struct Run {
    label: String,
    name: String,
    evaluations: Vec<Evaluation>,
    /// Whether each design was analysed by the FEA (not refused as an invalid geometry first).
    analysed: Vec<bool>,
    base: Option<Evaluation>,
    report: Value,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        return Err("usage: hypervolume_benchmark PROBLEM.toml OUT.svg LABEL=RUN ...".into());
    }
    let problem = OptimizationProblem::from_path(Path::new(&args[0]))?;
    let runs: Vec<Run> =
        args[2..].iter().map(|a| read_run(&problem, a)).collect::<Result<_, _>>()?;
    let references = references(&problem, &runs)?;
    let mut panels = Vec::new();
    for (name, reference) in &references {
        let traces: Vec<Vec<TracePoint>> =
            runs.iter().map(|r| hypervolume::trace(&r.evaluations, reference)).collect();
        let target = median(
            runs.iter()
                .zip(&traces)
                .filter(|(r, _)| r.label == "nsga2")
                .map(|(_, t)| t.last().map_or(0.0, |p| p.hypervolume))
                .collect(),
        );
        print_summary(name, reference, &runs, &traces, target);
        panels.push(panel(name, &runs, &traces, target));
    }
    let out = Path::new(&args[1]);
    let mut figure = Figure::new(format!(
        "{}: hypervolume against evaluations, surrogate (median of {} seeds) and NSGA-II",
        problem.path.file_stem().and_then(|s| s.to_str()).unwrap_or("problem"),
        runs.iter().filter(|r| r.label == "surrogate").count()
    ))
    .columns(2)
    .size(1400, 560);
    for p in panels {
        figure = figure.panel(p);
    }
    figure.save(out)?;
    figure.save(&out.with_extension("png"))?;
    println!("wrote {} and .png", out.display());
    Ok(())
}

/// `LABEL=RUN`: the run's designs from `RUN.sqlite`, its report from `RUN.json`.
fn read_run(problem: &OptimizationProblem, arg: &str) -> Result<Run, Box<dyn std::error::Error>> {
    let (label, path) = arg.split_once('=').ok_or_else(|| format!("'{arg}': give LABEL=RUN"))?;
    let report: Value = serde_json::from_str(&std::fs::read_to_string(format!("{path}.json"))?)?;
    let count = report["evaluated"].as_u64().ok_or("the JSON report has no 'evaluated'")? as usize;
    let store = Store::open_read_only(Path::new(&format!("{path}.sqlite")))?;
    let records = mrbrake_explore::stored::read_records(&store)?;
    let base = records.iter().find(|r| r.variables.is_empty()).map(|r| evaluation_for(problem, r));
    let designs: Vec<&mrbrake_store::Record> =
        records.iter().filter(|r| !r.variables.is_empty()).take(count).collect();
    let evaluations = designs.iter().map(|r| evaluation_for(problem, r)).collect();
    let analysed = designs.iter().map(|r| r.status != Status::Infeasible).collect();
    let name = Path::new(path).file_name().map_or(path.into(), |n| n.to_string_lossy().into());
    Ok(Run { label: label.to_string(), name, evaluations, analysed, base, report })
}

/// A reference point and its name.
type NamedReference = (&'static str, Vec<f64>);

/// The two common reference points (module docs).
fn references(
    problem: &OptimizationProblem,
    runs: &[Run],
) -> Result<Vec<NamedReference>, Box<dyn std::error::Error>> {
    let objectives = problem.objectives.len();
    let thesis = runs
        .iter()
        .find_map(|r| r.base.clone())
        .filter(Evaluation::feasible)
        .ok_or("no store holds a feasible reference design (the base spec)")?;
    let all: Vec<Evaluation> = runs.iter().flat_map(|r| r.evaluations.iter().cloned()).collect();
    let front: Vec<&[f64]> =
        pareto_front(&all).iter().map(|&i| all[i].objectives.as_slice()).collect();
    if front.is_empty() {
        return Err("no feasible design in any run".into());
    }
    Ok(vec![("thesis", thesis.objectives), ("nadir", beyond_worst(&front, objectives))])
}

/// The median of `values` (0 for none).
fn median(mut values: Vec<f64>) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 { values[n / 2] } else { 0.5 * (values[n / 2 - 1] + values[n / 2]) }
}

/// The hypervolume after `n` evaluations of a trace (its last value once the run has stopped).
fn at(trace: &[TracePoint], n: usize) -> f64 {
    match trace.get(n.saturating_sub(1)) {
        Some(p) => p.hypervolume,
        None => trace.last().map_or(0.0, |p| p.hypervolume),
    }
}

/// The median over the `label` runs of the hypervolume after 1, 2, … evaluations, as a percentage
/// of `target`.
fn median_curve(
    runs: &[Run],
    traces: &[Vec<TracePoint>],
    label: &str,
    target: f64,
) -> Vec<(f64, f64)> {
    let chosen: Vec<&Vec<TracePoint>> =
        runs.iter().zip(traces).filter(|(r, _)| r.label == label).map(|(_, t)| t).collect();
    let longest = chosen.iter().map(|t| t.len()).max().unwrap_or(0);
    (1..=longest)
        .map(|n| (n as f64, 100.0 * median(chosen.iter().map(|t| at(t, n)).collect()) / target))
        .collect()
}

fn print_summary(
    name: &str,
    reference: &[f64],
    runs: &[Run],
    traces: &[Vec<TracePoint>],
    target: f64,
) {
    println!("reference '{name}' {reference:?}: NSGA-II's final hypervolume (median) {target:.6e}");
    println!(
        "  {:<18} {:>8} {:>9} {:>9} {:>22} {:>9} {:>9} {:>9}",
        "run",
        "designs",
        "analysed",
        "final %",
        "99 % after (analysed)",
        "wall s",
        "models s",
        "models %"
    );
    for (run, trace) in runs.iter().zip(traces) {
        let last = trace.last().map_or(0.0, |p| p.hypervolume);
        let analysed_by = |n: usize| run.analysed.iter().take(n).filter(|a| **a).count();
        let reached = trace
            .iter()
            .find(|p| p.hypervolume >= 0.99 * target)
            .map(|p| format!("{} ({})", p.evaluations, analysed_by(p.evaluations)));
        let wall = run.report["elapsed_s"].as_f64().unwrap_or(f64::NAN);
        let models = run.report["surrogate"]["fit_s"].as_f64().unwrap_or(0.0)
            + run.report["surrogate"]["acquisition_s"].as_f64().unwrap_or(0.0);
        println!(
            "  {:<18} {:>8} {:>9} {:>9.2} {:>22} {:>9.1} {:>9.2} {:>9.2}",
            run.name,
            trace.len(),
            analysed_by(trace.len()),
            100.0 * last / target,
            reached.unwrap_or_else(|| "not reached".into()),
            wall + models,
            models,
            100.0 * models / (wall + models)
        );
    }
    let surrogate = median_curve(runs, traces, "surrogate", target);
    if let Some(n) = surrogate.iter().find(|p| p.1 >= 99.0) {
        println!("  surrogate median reaches 99 % after {} designs", n.0);
    } else if let Some(last) = surrogate.last() {
        println!("  surrogate median: {:.2} % after {} designs (99 % not reached)", last.1, last.0);
    }
}

/// One panel: the NSGA-II runs, each surrogate seed (grey) and the surrogate's median, in percent
/// of NSGA-II's final hypervolume, with the 99 % line.
fn panel(name: &str, runs: &[Run], traces: &[Vec<TracePoint>], target: f64) -> Panel {
    let longest = traces.iter().map(Vec::len).max().unwrap_or(1) as f64;
    let mut panel =
        Panel::new("evaluations (designs analysed)", "hypervolume [% of NSGA-II's final]")
            .caption(format!("reference point: {name}"))
            .log_x()
            .x_range(1.0, longest)
            .y_range(0.0, 105.0);
    for (_, trace) in runs.iter().zip(traces).filter(|(r, _)| r.label == "surrogate") {
        let points =
            trace.iter().map(|p| (p.evaluations as f64, 100.0 * p.hypervolume / target)).collect();
        panel = panel.series(Series::line("", points).color(GREY).line_width(1));
    }
    for (k, (run, trace)) in runs.iter().zip(traces).filter(|(r, _)| r.label == "nsga2").enumerate()
    {
        let points =
            trace.iter().map(|p| (p.evaluations as f64, 100.0 * p.hypervolume / target)).collect();
        panel = panel.series(
            Series::line(format!("NSGA-II ({})", run.name), points).color(1 + k).line_width(2),
        );
    }
    let median = median_curve(runs, traces, "surrogate", target);
    panel = panel.series(
        Series::line("surrogate, median of the seeds (grey)", median).color(0).line_width(3),
    );
    panel.series(Series::dashed("99 %", vec![(1.0, 99.0), (longest, 99.0)]).color(6))
}
