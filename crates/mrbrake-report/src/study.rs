//! Reports of design studies (`mrbrake_explore`, `mrbrake_design::study`): a parameter sweep's
//! table and summary, an optimisation's summary, its designs and its output folder (CSV, plots,
//! ready-to-analyse spec files), the merge and export of results stores, and the thesis's
//! comparison tables.

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_design::formula::FILL_FACTOR_LIMIT;
use mrbrake_design::study::StudyTable;
use mrbrake_explore::evaluate::{METRICS, metric_info};
use mrbrake_explore::front::FrontDesign;
use mrbrake_explore::hypervolume::Hypervolume;
use mrbrake_explore::optimize::{Evaluated, OptimizationResult};
use mrbrake_explore::plan::Shard;
use mrbrake_explore::problem::{Constraint, Goal, OptimizationProblem};
use mrbrake_explore::surrogate::SurrogateRun;
use mrbrake_explore::variable::Variable;
use mrbrake_explore::{Progress, RunSummary};
use mrbrake_store::{MergeSummary, Record, Status};
use serde_json::{Value, json};

use crate::pareto::{
    ConstraintActivity, ObjectivePlot, constraint_activity_figure, constraint_legend,
    hypervolume_axis, hypervolume_figure, metric_plot_axis, objective_figure,
};
use crate::wording::count;
use crate::{ReportError, write_atomic};

/// The warning about the designs whose copper fill factor (metric `fill_factor`) is above what a
/// winding reaches in practice ([`FILL_FACTOR_LIMIT`]), if any: the turn formula (4.2), (4.3) packs
/// bare wire hexagonally and fills a window well beyond it.
fn fill_factor_note<'r>(records: impl Iterator<Item = &'r Record>) -> Option<String> {
    let (mut over, mut highest) = (0, 0.0_f64);
    for fill in records.filter_map(|r| r.metric("fill_factor")) {
        if fill > FILL_FACTOR_LIMIT {
            over += 1;
            highest = highest.max(fill);
        }
    }
    (over > 0).then(|| {
        format!(
            "warning: {} fill the coil window above a copper fill factor of {FILL_FACTOR_LIMIT} (up \
             to {highest:.3}), more than an orthocyclic winding reaches; constrain fill_factor \
             (max = {FILL_FACTOR_LIMIT}) or give fewer turns",
            count(over, "design", "designs")
        )
    })
}

/// Evaluations per minute of a run (0 before any time has passed).
fn evaluations_per_min(progress: &Progress) -> f64 {
    if progress.elapsed_s > 0.0 {
        progress.computed as f64 * 60.0 / progress.elapsed_s
    } else {
        0.0
    }
}

/// Display scale and axis or column label of a metric (lengths in mm, volumes in cm³, inertias
/// in kg·mm²; other metrics in their SI unit).
pub fn metric_axis(name: &str) -> (f64, String) {
    let (scale, unit) = match name {
        n if n.ends_with("_m3") => (1e6, "cm³"),
        n if n.ends_with("_kg_m2") => (1e6, "kg·mm²"),
        n if n.ends_with("_m") => (1e3, "mm"),
        _ => (1.0, metric_info(name).map_or("", |m| m.unit)),
    };
    (scale, format!("{name} [{unit}]"))
}

/// A hypervolume's reference point, one `unit value` per objective in its metric's display unit
/// (a maximised objective's value back to its sign), with `decimals` decimals.
pub fn reference_point_text(
    objectives: &[mrbrake_explore::problem::Objective],
    reference: &[f64],
    decimals: usize,
) -> Vec<String> {
    objectives
        .iter()
        .zip(reference)
        .map(|(o, r)| {
            let value = if o.goal == Goal::Maximize { -r } else { *r };
            let (scale, unit) = metric_axis(&o.metric);
            format!("{unit} {:.decimals$}", value * scale)
        })
        .collect()
}

/// The metrics a problem may constrain or optimise: name, unit and meaning, one per line.
pub fn metrics_text() -> String {
    let mut out = String::new();
    for m in METRICS {
        let _ = writeln!(out, "{:<28} {:<8} {}", m.name, m.unit, m.meaning);
    }
    out
}

/// A parameter sweep (or one shard of it) to report.
#[derive(Debug, Clone, Copy)]
pub struct SweepReport<'a> {
    /// Name of the base design.
    pub name: &'a str,
    /// The varied variables.
    pub variables: &'a [Variable],
    /// One record per design of this shard, in plan order.
    pub records: &'a [Record],
    /// The run's counts and times.
    pub summary: &'a RunSummary,
    /// Points of the whole plan (all shards).
    pub plan_points: usize,
    /// The shard evaluated.
    pub shard: Shard,
    /// The results store.
    pub store: &'a Path,
}

/// Headline metrics of a sweep's table: metric, column title, display scale.
const SWEEP_COLUMNS: [(&str, &str, f64); 7] = [
    ("torque_max_Nm", "T_max[N·m]", 1.0),
    ("torque_off_Nm", "T_off[N·m]", 1.0),
    ("mean_B_fluid_T", "B_gap[T]", 1.0),
    ("flux_path_q90_B_T", "B_steel90[T]", 1.0),
    ("volume_m3", "V[cm³]", 1e6),
    ("rotor_inertia_kg_m2", "J[kg·mm²]", 1e6),
    ("power_W", "P[W]", 1.0),
];

impl SweepReport<'_> {
    /// The JSON report: the store, the plan, every design and the run's summary.
    pub fn json(&self) -> Value {
        let p = &self.summary.progress;
        let overhead = if p.elapsed_s > 0.0 { self.summary.store_s / p.elapsed_s } else { 0.0 };
        json!({
            "store": self.store.display().to_string(),
            "plan_points": self.plan_points,
            "shard": format!("{}/{}", self.shard.index, self.shard.count),
            "designs": mrbrake_store::to_json(self.records),
            "summary": {
                "computed": p.computed, "completed": p.completed, "reused": p.reused,
                "infeasible": p.infeasible,
                "failed": p.failed, "elapsed_s": p.elapsed_s,
                "evaluations_per_min": evaluations_per_min(p),
                "evaluation_s": self.summary.evaluation_s,
                "store_s": self.summary.store_s, "store_overhead": overhead,
            },
        })
    }

    /// The text report: a title line, one line per design, and what was computed.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} — {} of {} plan points (shard {}/{}), store {}",
            self.name,
            self.records.len(),
            self.plan_points,
            self.shard.index,
            self.shard.count,
            self.store.display()
        );
        self.table(&mut out);
        if let Some(note) = fill_factor_note(self.records.iter()) {
            let _ = writeln!(out, "{note}");
        }
        let p = &self.summary.progress;
        if p.computed == 0 {
            let all = if p.reused == 1 { "" } else { "all " };
            let _ = writeln!(
                out,
                "nothing to compute: {all}{} already in the store",
                count(p.reused, "design was", "designs were")
            );
        } else {
            // The writer thread inserts while the workers analyse, so the store's time overlaps
            // the analyses; the measured cost of the store is the evaluation-rate benchmark's.
            let _ = writeln!(
                out,
                "{} ({} infeasible, {} failed), reused {} from the store; {:.1} s wall, \
                 {:.0} evaluations/min; store writes {:.3} s on the writer thread, alongside the analyses",
                work_done(p),
                p.infeasible,
                p.failed,
                p.reused,
                p.elapsed_s,
                evaluations_per_min(p),
                self.summary.store_s,
            );
        }
        out
    }

    /// One line per design: the variables, then the headline metrics or the reason.
    fn table(&self, out: &mut String) {
        let mut header = String::new();
        for v in self.variables {
            let _ = write!(header, "{:>12} ", v.name);
        }
        let _ = write!(header, "{:>11} ", "status");
        for (_, title, _) in &SWEEP_COLUMNS {
            let _ = write!(header, "{title:>13} ");
        }
        let _ = writeln!(out, "{}", header.trim_end());
        for r in self.records {
            let mut line = String::new();
            for (v, (_, value)) in self.variables.iter().zip(&r.variables) {
                let _ = write!(line, "{:>12} ", v.display(value));
            }
            let _ = write!(line, "{:>11} ", r.status.as_str());
            if r.status == Status::Ok {
                for (name, _, scale) in &SWEEP_COLUMNS {
                    let cell = metric_text(r, name, *scale).unwrap_or_else(|| "—".into());
                    let _ = write!(line, "{cell:>13} ");
                }
            } else if let Some(reason) = &r.reason {
                let last = reason.lines().map(str::trim).rfind(|l| !l.is_empty());
                line.push_str(last.unwrap_or(""));
            }
            let _ = writeln!(out, "{}", line.trim_end());
        }
    }
}

/// What a sweep computed: `computed N`, or, when a resumed study completed stored designs with
/// the metrics they lacked, `computed N, completed M stored designs with the metrics they lacked`
/// (the completed are not counted as computed in the words).
fn work_done(p: &Progress) -> String {
    if p.completed == 0 {
        return format!("computed {}", p.computed);
    }
    format!(
        "computed {}, completed {} with the metrics they lacked",
        p.computed - p.completed,
        count(p.completed, "stored design", "stored designs")
    )
}

/// What an optimisation evaluated now, in the words of [`work_done`].
fn evaluated_now(p: &Progress) -> String {
    if p.completed == 0 {
        return format!("{} evaluated", p.computed);
    }
    format!(
        "{} evaluated, {} completed with the metrics they lacked",
        p.computed - p.completed,
        count(p.completed, "stored design", "stored designs")
    )
}

/// The line reporting the merge of the store at `input`.
pub fn merge_text(input: &Path, summary: &MergeSummary) -> String {
    let conflicts = if summary.conflicts.is_empty() {
        String::new()
    } else {
        format!(
            ", {} CONFLICTS (same design, different results; kept the existing): {}",
            summary.conflicts.len(),
            summary.conflicts.join(", ")
        )
    };
    let completed = if summary.completed == 0 {
        String::new()
    } else {
        format!(", {} completed with the metrics they lacked", summary.completed)
    };
    format!(
        "{}: {} added, {} already present{completed}{conflicts}\n",
        input.display(),
        summary.inserted,
        summary.duplicates
    )
}

/// The summary of a store's records when nothing is exported.
pub fn store_summary_text(store: &Path, records: &[Record]) -> String {
    let ok = records.iter().filter(|r| r.status == Status::Ok).count();
    format!(
        "{}: {} ({} ok, {} infeasible or failed); use --csv FILE or --json to export\n",
        store.display(),
        count(records.len(), "design", "designs"),
        ok,
        records.len() - ok
    )
}

/// An optimisation run to report: the problem, its result, and where they were read and stored.
#[derive(Debug, Clone, Copy)]
pub struct OptimizationReport<'a> {
    /// The problem.
    pub problem: &'a OptimizationProblem,
    /// The result.
    pub result: &'a OptimizationResult,
    /// The problem file, as the user named it.
    pub problem_path: &'a Path,
    /// The results store.
    pub store: &'a Path,
}

impl OptimizationReport<'_> {
    /// The records of the front, in the front's order.
    fn front(&self) -> Vec<Record> {
        self.result.front.iter().map(|&i| self.result.evaluated[i].record.clone()).collect()
    }

    /// The JSON report: the run's counts, the front and reference designs, the hypervolume with
    /// its reference point and growth, a surrogate run's iterations, the written front designs
    /// and a polish.
    pub fn json(&self) -> Value {
        let (result, totals) = (self.result, &self.result.totals.progress);
        json!({
            "problem": self.problem_path.display().to_string(),
            "store": self.store.display().to_string(),
            "algorithm": self.problem.algorithm.kind(),
            "evaluated": result.evaluated.len(),
            "requested": result.requested,
            "iterations": result.iterations,
            "converged": result.converged,
            "stopped": result.stopped,
            "computed": totals.computed,
            "completed": totals.completed,
            "reused": totals.reused,
            "elapsed_s": totals.elapsed_s,
            "evaluations_per_min": evaluations_per_min(totals),
            "front": mrbrake_store::to_json(&self.front()),
            "reference": result.reference.as_ref().map(|r| mrbrake_store::to_json(std::slice::from_ref(&r.record))),
            "hypervolume": result.hypervolume.as_ref().map(|h| self.hypervolume_json(h)),
            "surrogate": result.surrogate.as_ref().map(surrogate_json),
            "manufacturing_resolution_m": self.problem.manufacturing_resolution,
            "front_designs": result.front_designs.iter().map(front_design_json).collect::<Vec<_>>(),
            "polish": result.polish.as_ref().map(|p| json!({
                "design": p.design,
                "objective": p.objective,
                "evaluations": p.evaluated.len(),
                "iterations": p.iterations,
                "converged": p.converged,
                "start": record_json(&p.start.record),
                "best": record_json(&p.best.record),
            })),
        })
    }

    /// The hypervolume: its value, its reference point by metric and where it comes from, and
    /// its value after every evaluation.
    fn hypervolume_json(&self, h: &Hypervolume) -> Value {
        let trace: Vec<Value> = h
            .trace
            .iter()
            .map(|p| json!({ "evaluations": p.evaluations, "hypervolume": p.hypervolume }))
            .collect();
        json!({
            "value": h.value,
            "reference": h.reference_json(&self.problem.objectives),
            "reference_source": h.source.key(),
            "trace": trace,
        })
    }

    /// The text report: how the run ended and what it cost, then the front (or the best design)
    /// and the reference design as tables; `out_dir` is the output folder, if one was written.
    pub fn text(&self, out_dir: Option<&Path>) -> String {
        let (problem, result) = (self.problem, self.result);
        let mut out = String::new();
        let _ = writeln!(out, "{}", self.run_summary());
        let feasible = result.evaluated.iter().filter(|e| e.evaluation.feasible()).count();
        if result.front.is_empty() {
            let _ = writeln!(out, "no evaluated design meets every constraint");
        } else if problem.objectives.len() == 1 {
            let _ = writeln!(out, "{feasible} feasible; the best feasible design:");
        } else {
            let _ = writeln!(
                out,
                "{feasible} feasible; Pareto front of {}:",
                count(result.front.len(), "design", "designs")
            );
        }
        let front = result.front.iter().map(|&i| &result.evaluated[i]);
        self.designs_table(&mut out, front, "front");
        if let Some(reference) = &result.reference {
            self.designs_table(&mut out, std::iter::once(reference), "reference (base spec)");
        }
        out.push_str(&self.extras_text());
        let front_records = result.front.iter().map(|&i| &result.evaluated[i].record);
        if let Some(note) = fill_factor_note(front_records) {
            let _ = writeln!(out, "{note}");
        }
        if let Some(dir) = out_dir {
            let _ = writeln!(out, "outputs in {}", dir.display());
        }
        out
    }

    /// The hypervolume, a surrogate run's models, the written front designs and a polish, a line
    /// each.
    fn extras_text(&self) -> String {
        let (problem, result) = (self.problem, self.result);
        let mut out = String::new();
        if let Some(h) = &result.hypervolume {
            let metrics: Vec<&str> = problem.objectives.iter().map(|o| o.metric.as_str()).collect();
            let (scale, label) = hypervolume_axis(&metrics);
            let reference = reference_point_text(&problem.objectives, &h.reference, 6);
            let _ = writeln!(
                out,
                "{label}: {:.6} ({:.6e} in SI) against the reference point {}: {}",
                h.value * scale,
                h.value,
                reference.join(", "),
                h.source.describe()
            );
        }
        if let Some(s) = &result.surrogate {
            let _ = writeln!(out, "{}", surrogate_text(s, result.totals.progress.elapsed_s));
        }
        out.push_str(&front_designs_text(problem, &result.front_designs));
        if let Some(p) = &result.polish {
            let (scale, label) = metric_axis(&p.objective);
            let value =
                |e: &Evaluated| e.record.metric(&p.objective).map_or(f64::NAN, |v| v * scale);
            let _ = writeln!(
                out,
                "polish of front design {} ({label}): {:.4} -> {:.4} in {} ({})",
                p.design,
                value(&p.start),
                value(&p.best),
                count(p.evaluated.len(), "design", "designs"),
                if p.converged { "converged" } else { "budget spent" }
            );
        }
        out
    }

    /// How the run ended, the designs and what they cost (one line).
    fn run_summary(&self) -> String {
        let (result, totals) = (self.result, &self.result.totals.progress);
        let how = match (&result.surrogate, result.converged) {
            (Some(s), _) => format!(
                "{} after the initial design (stopped: {})",
                count(result.iterations, "iteration", "iterations"),
                stop_words(s)
            ),
            (None, None) => count(result.iterations, "generation", "generations"),
            (None, Some(true)) => {
                format!("converged after {}", count(result.iterations, "iteration", "iterations"))
            }
            (None, Some(false)) => format!(
                "evaluation budget spent after {} (not converged)",
                count(result.iterations, "iteration", "iterations")
            ),
        };
        let work = if totals.computed == 0 {
            format!("all {} answers read from the store, nothing computed", totals.reused)
        } else {
            format!(
                "{} now, {} answers read from the store (repeated designs and earlier \
                 runs); {:.1} s, {:.0} evaluations/min",
                evaluated_now(totals),
                totals.reused,
                totals.elapsed_s,
                evaluations_per_min(totals)
            )
        };
        format!(
            "{}: {how}; {}{}; {work}; store {}",
            self.problem_path.display(),
            count(result.evaluated.len(), "distinct design", "distinct designs"),
            if result.reference.is_some() { " + the reference" } else { "" },
            self.store.display()
        )
    }

    /// A table of `designs` under the title `what`: the variables (`base` where a design keeps the
    /// base spec's value), then the objectives' and constraints' metrics in display units.
    fn designs_table<'e>(
        &self,
        out: &mut String,
        designs: impl Iterator<Item = &'e Evaluated>,
        what: &str,
    ) {
        let problem = self.problem;
        let metrics: Vec<&String> = problem
            .objectives
            .iter()
            .map(|o| &o.metric)
            .chain(problem.constraints.iter().map(|c| &c.metric))
            .collect();
        // Every column as wide as its header (at least 10 characters), values right-aligned under it.
        let mut headers: Vec<String> = problem.variables.iter().map(|v| v.name.clone()).collect();
        headers.extend(metrics.iter().map(|name| metric_axis(name).1));
        let widths: Vec<usize> = headers.iter().map(|h| h.chars().count().max(10)).collect();
        let first = what.chars().count().max(10);
        let mut header = format!("  {what:<first$}");
        for (h, w) in headers.iter().zip(&widths) {
            let _ = write!(header, " {h:>w$}");
        }
        let _ = writeln!(out, "{header}");
        for (k, e) in designs.enumerate() {
            let mut cells: Vec<String> = self
                .result
                .variables
                .iter()
                .map(|v| {
                    // A material is stored by name (`display` shows it), a number as a number.
                    let value = e.record.variable_value(&v.name);
                    value.map_or_else(|| "base".to_string(), |x| v.display(x))
                })
                .collect();
            cells.extend(metrics.iter().map(|name| {
                metric_text(&e.record, name, metric_axis(name).0)
                    .unwrap_or_else(|| e.record.status.as_str().to_string())
            }));
            let mut line = format!("  {:<first$}", format!("#{}", k + 1));
            for (cell, w) in cells.iter().zip(&widths) {
                let _ = write!(line, " {cell:>w$}");
            }
            let _ = writeln!(out, "{line}");
        }
    }

    /// Writes the output folder `dir`: `evaluations.csv`, `pareto.csv` (the front as evaluated),
    /// `front-designs.csv` and `designs/front-NN.toml` (the front's designs as written: in the base
    /// spec's units, rounded and evaluated again), `designs/reference.toml`, the objective plot
    /// `pareto.svg/.png`, the constraint activity `constraints.svg/.png`, and the hypervolume
    /// against evaluations `hypervolume.csv` and `hypervolume.svg/.png` (creating the folder if
    /// needed).
    pub fn write_outputs(&self, dir: &Path) -> Result<(), ReportError> {
        let designs = dir.join("designs");
        std::fs::create_dir_all(&designs)
            .map_err(|source| ReportError::Folder { path: dir.to_path_buf(), source })?;
        let all: Vec<Record> = self.result.evaluated.iter().map(|e| e.record.clone()).collect();
        write_atomic(&dir.join("evaluations.csv"), &mrbrake_store::to_csv(&all)?)?;
        let front = self.front();
        write_atomic(&dir.join("pareto.csv"), &mrbrake_store::to_csv(&front)?)?;
        self.write_front_designs(&designs, &front)?;
        if let Some(reference) = &self.result.reference {
            write_atomic(&designs.join("reference.toml"), reference.record.spec_toml.as_bytes())?;
        }
        if let Some(plot) = self.objective_plot(&front) {
            let figure = objective_figure(&plot);
            figure.save(&dir.join("pareto.svg"))?;
            figure.save(&dir.join("pareto.png"))?;
        }
        if !self.problem.constraints.is_empty() && !front.is_empty() {
            let figure = constraint_activity_figure(&self.constraint_activity(&front));
            figure.save(&dir.join("constraints.svg"))?;
            figure.save(&dir.join("constraints.png"))?;
        }
        if let Some(h) = &self.result.hypervolume {
            self.write_hypervolume(dir, h)?;
        }
        Ok(())
    }

    /// `designs/front-NN.toml` and `front-designs.csv`: the written designs when the run made
    /// them, else the front's records as evaluated.
    fn write_front_designs(&self, designs: &Path, front: &[Record]) -> Result<(), ReportError> {
        let written = &self.result.front_designs;
        if written.is_empty() {
            for (k, record) in front.iter().enumerate() {
                let text = format!(
                    "# Design {} of the front of {} (key {}).\n{}",
                    k + 1,
                    self.problem.path.display(),
                    record.key,
                    record.spec_toml
                );
                write_atomic(&designs.join(format!("front-{:02}.toml", k + 1)), text.as_bytes())?;
            }
            return Ok(());
        }
        for d in written {
            let text = format!("{}{}", self.front_design_header(d), d.spec_text);
            write_atomic(&designs.join(format!("front-{:02}.toml", d.number)), text.as_bytes())?;
        }
        let records: Vec<Record> = written.iter().map(|d| d.evaluated.record.clone()).collect();
        let folder = designs.parent().unwrap_or(designs);
        write_atomic(&folder.join("front-designs.csv"), &mrbrake_store::to_csv(&records)?)?;
        Ok(())
    }

    /// The comment lines above a written front design: where it comes from, its metrics, how it
    /// was rounded, and a warning if the rounding broke a constraint.
    fn front_design_header(&self, d: &FrontDesign) -> String {
        let problem = self.problem;
        let record = &d.evaluated.record;
        let mut out = format!(
            "# Design {} of the front of {} (key {}).\n",
            d.number,
            problem.path.display(),
            record.key
        );
        let metrics: Vec<String> = problem
            .objectives
            .iter()
            .map(|o| &o.metric)
            .chain(problem.constraints.iter().map(|c| &c.metric))
            .filter_map(|m| {
                let (scale, label) = metric_axis(m);
                record.metric(m).map(|v| format!("{label} {:.4}", v * scale))
            })
            .collect();
        if !metrics.is_empty() {
            let _ = writeln!(out, "# Its evaluation: {}.", metrics.join(", "));
        }
        let _ = writeln!(out, "# {}", rounding_words(problem.manufacturing_resolution, d.rounded));
        if let Some(note) = &d.note {
            let _ = writeln!(out, "# NOTE: {note}.");
        }
        if !d.evaluated.evaluation.feasible() {
            let _ = writeln!(out, "# WARNING: {}", broken_constraints(problem, record));
        }
        let _ = writeln!(
            out,
            "# Below: the base spec {} with the problem's [set] changes, its comments kept.\n",
            problem.spec_path.display()
        );
        out
    }

    /// `hypervolume.csv` (evaluations, hypervolume in SI) and its plot.
    fn write_hypervolume(&self, dir: &Path, h: &Hypervolume) -> Result<(), ReportError> {
        let mut csv = String::from("evaluations,hypervolume\n");
        for p in &h.trace {
            let _ = writeln!(csv, "{},{:e}", p.evaluations, p.hypervolume);
        }
        write_atomic(&dir.join("hypervolume.csv"), csv.as_bytes())?;
        let metrics: Vec<&str> =
            self.problem.objectives.iter().map(|o| o.metric.as_str()).collect();
        let (scale, label) = hypervolume_axis(&metrics);
        let points =
            h.trace.iter().map(|p| (p.evaluations as f64, p.hypervolume * scale)).collect();
        let name = self.problem.path.file_stem().and_then(|s| s.to_str()).unwrap_or("optimisation");
        let title =
            format!("{name} — hypervolume against evaluations ({})", self.problem.algorithm.kind());
        let figure =
            hypervolume_figure(&title, &label, &[(self.problem.algorithm.kind().into(), points)]);
        figure.save(&dir.join("hypervolume.svg"))?;
        figure.save(&dir.join("hypervolume.png"))?;
        Ok(())
    }

    /// The metrics on the plots' axes: the first objective on x; on y the second objective, or
    /// else the first constraint's metric (`None`: nothing to plot against).
    fn plot_metrics(&self) -> (&str, Option<&str>) {
        let problem = self.problem;
        let x = problem.objectives[0].metric.as_str();
        let y = problem
            .objectives
            .get(1)
            .map(|o| o.metric.as_str())
            .or_else(|| problem.constraints.first().map(|c| c.metric.as_str()));
        (x, y)
    }

    /// The objective plot: every evaluated design, the front and the reference.
    fn objective_plot(&self, front: &[Record]) -> Option<ObjectivePlot> {
        let (problem, result) = (self.problem, self.result);
        let (x_metric, y_metric) = self.plot_metrics();
        let y_metric = y_metric?;
        let ((xs, x_label), (ys, y_label)) =
            (metric_plot_axis(x_metric), metric_plot_axis(y_metric));
        let point = |r: &Record| Some((r.metric(x_metric)? * xs, r.metric(y_metric)? * ys));
        let mut plot = ObjectivePlot {
            title: format!(
                "{} — {}",
                problem.path.file_stem().and_then(|s| s.to_str()).unwrap_or("optimisation"),
                count(result.evaluated.len(), "evaluated design", "evaluated designs")
            ),
            x_label,
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
        Some(plot)
    }

    /// Each constraint's margin (0 = active) along the front, against the first objective.
    fn constraint_activity(&self, front: &[Record]) -> ConstraintActivity {
        let (x_metric, _) = self.plot_metrics();
        let (xs, x_label) = metric_plot_axis(x_metric);
        let along_front = |c: &Constraint| {
            let mut points: Vec<(f64, f64)> = front
                .iter()
                .filter_map(|r| Some((r.metric(x_metric)? * xs, c.margin(r.metric(&c.metric)?))))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            points
        };
        ConstraintActivity {
            title: "Constraint activity along the front (0 = active)".into(),
            x_label,
            constraints: self
                .problem
                .constraints
                .iter()
                .map(|c| (constraint_label(c), along_front(c)))
                .collect(),
        }
    }
}

/// One record as JSON (`mrbrake export --json`'s form).
fn record_json(record: &Record) -> Value {
    mrbrake_store::to_json(std::slice::from_ref(record))
        .as_array()
        .and_then(|a| a.first().cloned())
        .unwrap_or(Value::Null)
}

/// A written front design as JSON: its number and file, whether it was rounded and is feasible,
/// and its record.
fn front_design_json(d: &FrontDesign) -> Value {
    json!({
        "number": d.number,
        "file": format!("designs/front-{:02}.toml", d.number),
        "rounded": d.rounded,
        "feasible": d.evaluated.evaluation.feasible(),
        "note": d.note,
        "design": record_json(&d.evaluated.record),
    })
}

/// A surrogate run as JSON: its settings as run, why it stopped, the models' total times and
/// every iteration.
fn surrogate_json(s: &SurrogateRun) -> Value {
    let iterations: Vec<Value> = s
        .iterations
        .iter()
        .map(|i| {
            let models: Vec<Value> = i
                .models
                .iter()
                .map(|m| json!({ "model": m.model, "points": m.points, "loo_error": m.loo_error }))
                .collect();
            json!({
                "iteration": i.iteration,
                "batch": i.batch,
                "evaluations": i.evaluations,
                "hypervolume": i.hypervolume,
                "models": models,
                "fallback": i.fallback,
                "fit_s": i.fit_s,
                "acquisition_s": i.acquisition_s,
            })
        })
        .collect();
    json!({
        "stop": s.stop,
        "resumed_from": s.resumed_from,
        "skipped_incomplete": s.skipped_incomplete,
        "batch": s.batch,
        "initial_size": s.initial_size,
        "max_evaluations": s.max_evaluations,
        "fit_s": s.fit_s(),
        "acquisition_s": s.acquisition_s(),
        "iterations": iterations,
    })
}

/// Why a surrogate run stopped, in words.
fn stop_words(s: &SurrogateRun) -> String {
    match s.stop {
        "budget" => format!("budget of {} evaluations", s.max_evaluations),
        "stall" => "the hypervolume stalled".into(),
        "observer" => "interrupted".into(),
        _ => "no design left to propose".into(),
    }
}

/// How a surrogate run continued from its store: the designs it read, and those it skipped for
/// lacking a metric the problem needs (empty for a fresh run).
fn resumed_words(s: &SurrogateRun) -> String {
    let mut words = String::new();
    if s.resumed_from > 0 {
        words = format!(", continued from {} stored designs", s.resumed_from);
    }
    if s.skipped_incomplete > 0 {
        let _ = write!(
            words,
            ", skipped {} lacking metrics the objectives or constraints need (a study asking for \
             them completes them)",
            count(s.skipped_incomplete, "stored design", "stored designs")
        );
    }
    words
}

/// A surrogate run's models in one line: iterations, fallbacks, the last fit's worst
/// leave-one-out error, and the models' share of the wall time.
fn surrogate_text(s: &SurrogateRun, elapsed_s: f64) -> String {
    let fallbacks = s.iterations.iter().filter(|i| i.fallback.is_some()).count();
    let last = s.iterations.iter().rev().find(|i| !i.models.is_empty());
    let fits = last.map_or("no model fitted".to_string(), |i| {
        let each: Vec<String> =
            i.models.iter().map(|m| format!("{} {:.3}", m.model, m.loo_error)).collect();
        format!("last leave-one-out errors: {}", each.join(", "))
    });
    let overhead = s.fit_s() + s.acquisition_s();
    let share = if elapsed_s > 0.0 { 100.0 * overhead / (overhead + elapsed_s) } else { 0.0 };
    format!(
        "surrogate: batch {}, initial design {}{}; {} fell back to space-filling designs; {fits}; \
         models {:.1} s + acquisition {:.1} s ({share:.1} % of the run's wall time)",
        s.batch,
        s.initial_size,
        resumed_words(s),
        count(fallbacks, "iteration", "iterations"),
        s.fit_s(),
        s.acquisition_s()
    )
}

/// One line on the written front designs: their rounding, and those it made infeasible.
fn front_designs_text(problem: &OptimizationProblem, designs: &[FrontDesign]) -> String {
    if designs.is_empty() {
        return String::new();
    }
    let rounded = designs.iter().filter(|d| d.rounded).count();
    let broken: Vec<String> = designs
        .iter()
        .filter(|d| !d.evaluated.evaluation.feasible())
        .map(|d| format!("#{} ({})", d.number, broken_constraints(problem, &d.evaluated.record)))
        .collect();
    // The table above shows the front as the optimiser found it; the written designs' own
    // metrics are in their files and front-designs.csv.
    let how = if problem.manufacturing_resolution <= 0.0 {
        "values as evaluated, in SI".to_string()
    } else {
        format!(
            "lengths rounded to {} mm, currents to 1 mA",
            problem.manufacturing_resolution * 1e3
        )
    };
    let mut out = format!(
        "front designs written in the base spec's units ({how}; {rounded} changed by the \
         rounding, evaluated again: their own metrics are in front-designs.csv and their files)"
    );
    if broken.is_empty() {
        out.push_str("; every one meets the constraints\n");
    } else {
        let _ = writeln!(
            out,
            "; after rounding {} break a constraint: {}",
            broken.len(),
            broken.join("; ")
        );
    }
    out
}

/// How a written design was rounded, in words.
fn rounding_words(resolution: f64, rounded: bool) -> String {
    if resolution <= 0.0 {
        "Values as evaluated, in SI (manufacturing_resolution = 0).".into()
    } else if rounded {
        format!(
            "Lengths rounded to {} mm, currents to 1 mA, in the base spec's units; the metrics \
             above are those of the rounded design.",
            resolution * 1e3
        )
    } else {
        format!("Lengths on the {} mm resolution already: nothing rounded.", resolution * 1e3)
    }
}

/// The constraints `record` breaks, with their limits, or why it has no metrics.
fn broken_constraints(problem: &OptimizationProblem, record: &Record) -> String {
    if record.status != Status::Ok {
        return format!(
            "{}: {}",
            record.status.as_str(),
            record.reason.clone().unwrap_or_default()
        );
    }
    let broken: Vec<String> = problem
        .constraints
        .iter()
        .filter(|c| record.metric_value(&c.metric).is_none_or(|v| c.violation_of(v) > 0.0))
        .map(|c| {
            let (scale, _) = metric_axis(&c.metric);
            let value = record.metric(&c.metric).map_or(f64::NAN, |v| v * scale);
            format!("{} at {value:.4}", constraint_label(c))
        })
        .collect();
    format!("breaks {}", broken.join(", "))
}

/// A constraint as a legend label in displayed units, e.g. `torque max ≥ 3 N·m`.
fn constraint_label(c: &Constraint) -> String {
    constraint_legend(&c.metric, c.min, c.max)
}

/// The thesis's comparison tables (Tables 4.1–4.4) beside mrbrake's values, one block per table.
pub fn thesis_tables_text(tables: &[StudyTable]) -> String {
    let mut out = String::new();
    for t in tables {
        // Torque is spelled out: a column "T" beside "B [T]" reads as tesla.
        let _ = writeln!(out, "{}: {} — ours | thesis (torques in N·m)", t.table, t.title);
        let _ = writeln!(
            out,
            "  {:<32} {:>8} {:>11} {:>15} {:>14} | {:>8} {:>11} {:>8}",
            "",
            "B [T]",
            "tau_y [kPa]",
            "torque (mean B)",
            "torque (local)",
            "B [T]",
            "tau_y [kPa]",
            "torque"
        );
        for r in &t.rows {
            let _ = writeln!(
                out,
                "  {:<32} {:>8.4} {:>11.3} {:>15.3} {:>14.3} | {:>8.4} {:>11.4} {:>8.2}",
                r.label,
                r.mean_b_t,
                r.tau_y_kpa,
                r.thesis_method_nm,
                r.local_nm,
                r.thesis_b_t,
                r.thesis_tau_y_kpa,
                r.thesis_torque_nm
            );
        }
        let _ = writeln!(out);
    }
    out
}

/// A metric of `record` as a table shows it, times `scale`: the value with 4 decimals, a bound
/// beyond the analysed range as `≥x` / `≤x`, `n/a` for a metric that does not apply; `None` when
/// the record lacks it.
fn metric_text(record: &Record, name: &str, scale: f64) -> Option<String> {
    use mrbrake_store::MetricValue;
    Some(match record.metric_value(name)? {
        MetricValue::Value(v) => format!("{:.4}", v * scale),
        MetricValue::AtLeast(b) => format!("≥{:.4}", b * scale),
        MetricValue::AtMost(b) => format!("≤{:.4}", b * scale),
        MetricValue::NotApplicable => "n/a".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(key: char, status: Status, reason: Option<&str>, metrics: &[(&str, f64)]) -> Record {
        Record {
            key: key.to_string().repeat(64),
            status,
            reason: reason.map(str::to_string),
            variables: Vec::new(),
            metrics: metrics.iter().map(|(k, v)| (k.to_string(), (*v).into())).collect(),
            spec_toml: String::new(),
            eval_seconds: 0.5,
            solver_version: "test".into(),
            settings: Default::default(),
        }
    }

    fn run_summary(computed: usize, reused: usize) -> RunSummary {
        let progress = Progress {
            to_compute: computed,
            computed,
            completed: 0,
            reused,
            infeasible: 1,
            failed: 0,
            elapsed_s: 2.0,
        };
        RunSummary { progress, evaluation_s: 3.0, store_s: 0.01 }
    }

    #[test]
    fn windows_filled_beyond_winding_practice_are_warned_about() {
        let records = [
            record('a', Status::Ok, None, &[("fill_factor", 0.74)]),
            record('b', Status::Ok, None, &[("fill_factor", 0.81)]),
            record('c', Status::Ok, None, &[("fill_factor", 0.86)]),
            record('d', Status::Infeasible, Some("too wide"), &[]),
        ];
        let note = fill_factor_note(records.iter()).expect("two are above the limit");
        assert!(note.starts_with("warning: 2 designs fill the coil window"), "{note}");
        assert!(note.contains("0.75") && note.contains("up to 0.860"), "{note}");
        assert_eq!(fill_factor_note(records[..1].iter()), None);
    }

    #[test]
    fn a_sweep_table_has_the_headline_metrics_or_the_reason() {
        let records = [
            record('a', Status::Ok, None, &[("torque_max_Nm", 5.38), ("volume_m3", 396.092e-6)]),
            record('b', Status::Infeasible, Some("coil.window_width: too wide\n  "), &[]),
        ];
        let summary = run_summary(2, 0);
        let report = SweepReport {
            name: "brake",
            variables: &[],
            records: &records,
            summary: &summary,
            plan_points: 4,
            shard: Shard { index: 1, count: 2 },
            store: Path::new("s.sqlite"),
        };
        let text = report.text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "brake — 2 of 4 plan points (shard 1/2), store s.sqlite");
        assert!(lines[1].ends_with("status    T_max[N·m]    T_off[N·m]      B_gap[T]  B_steel90[T]        V[cm³]     J[kg·mm²]          P[W]"), "{}", lines[1]);
        // Missing metrics are a dash; volumes in cm³.
        assert!(lines[2].starts_with("         ok        5.3800             —"), "{}", lines[2]);
        assert!(lines[2].contains("      396.0920"), "{}", lines[2]);
        assert_eq!(lines[3], " infeasible coil.window_width: too wide");
        assert!(
            lines[4].starts_with("computed 2 (1 infeasible, 0 failed), reused 0"),
            "{}",
            lines[4]
        );
        assert!(lines[4].contains("60 evaluations/min"), "{}", lines[4]);
        let json = report.json();
        assert_eq!(json["shard"], "1/2");
        assert_eq!(json["designs"].as_array().unwrap().len(), 2);
        assert!((json["summary"]["store_overhead"].as_f64().unwrap() - 0.005).abs() < 1e-15);

        let resumed = run_summary(0, 2);
        let text = SweepReport { summary: &resumed, ..report }.text();
        assert!(text.ends_with("nothing to compute: all 2 designs were already in the store\n"));
        let one = run_summary(0, 1);
        let text = SweepReport { summary: &one, ..report }.text();
        assert!(
            text.ends_with("nothing to compute: 1 design was already in the store\n"),
            "{text}"
        );
    }

    #[test]
    fn metrics_are_shown_in_readable_units() {
        let cases = [
            ("volume_m3", 1e6, "volume_m3 [cm³]"),
            ("rotor_inertia_kg_m2", 1e6, "rotor_inertia_kg_m2 [kg·mm²]"),
            ("outer_diameter_m", 1e3, "outer_diameter_m [mm]"),
            ("torque_max_Nm", 1.0, "torque_max_Nm [N·m]"),
            ("no_such_metric", 1.0, "no_such_metric []"),
        ];
        for (name, scale, label) in cases {
            let (s, l) = metric_axis(name);
            assert!((s - scale).abs() < 1e-9 * scale && l == label, "{name}: {s} {l}");
        }
        assert_eq!(metrics_text().lines().count(), METRICS.len());
    }

    /// A resumed study that completed stored designs says so: "completed", not "computed".
    #[test]
    fn designs_completed_by_a_resume_are_called_completed() {
        let mut progress = run_summary(3, 1).progress;
        progress.completed = 2;
        assert_eq!(
            work_done(&progress),
            "computed 1, completed 2 stored designs with the metrics they lacked"
        );
        assert_eq!(
            evaluated_now(&progress),
            "1 evaluated, 2 stored designs completed with the metrics they lacked"
        );
        progress.completed = 0;
        assert_eq!(work_done(&progress), "computed 3");
        let completed =
            MergeSummary { inserted: 1, duplicates: 0, completed: 2, conflicts: vec![] };
        assert_eq!(
            merge_text(Path::new("a.sqlite"), &completed),
            "a.sqlite: 1 added, 0 already present, 2 completed with the metrics they lacked\n"
        );
    }

    #[test]
    fn merges_report_their_conflicts() {
        let clean =
            MergeSummary { inserted: 3, duplicates: 1, completed: 0, conflicts: Vec::new() };
        assert_eq!(
            merge_text(Path::new("a.sqlite"), &clean),
            "a.sqlite: 3 added, 1 already present\n"
        );
        let conflicting =
            MergeSummary { conflicts: vec!["k1".into(), "k2".into()], ..MergeSummary::default() };
        let text = merge_text(Path::new("b.sqlite"), &conflicting);
        assert!(
            text.ends_with(
                ", 2 CONFLICTS (same design, different results; kept the existing): k1, k2\n"
            ),
            "{text}"
        );
        let records =
            [record('a', Status::Ok, None, &[]), record('b', Status::Failed, Some("x"), &[])];
        assert_eq!(
            store_summary_text(Path::new("s.sqlite"), &records),
            "s.sqlite: 2 designs (1 ok, 1 infeasible or failed); use --csv FILE or --json to export\n"
        );
    }

    #[test]
    fn constraint_labels_show_their_bounds() {
        let c = Constraint { metric: "torque_max_Nm".into(), min: Some(3.0), max: None };
        assert_eq!(constraint_label(&c), "torque max ≥ 3 N·m");
        let c = Constraint { metric: "outer_diameter_m".into(), min: Some(0.01), max: Some(0.08) };
        assert_eq!(constraint_label(&c), "outer diameter ≥ 10 mm ≤ 80 mm");
    }
}
