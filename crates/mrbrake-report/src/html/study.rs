//! The HTML report of a design study (`mrbrake report --store STUDY.sqlite`): the variables,
//! objectives and constraints, the Pareto front and the constraint activity along it, the table of
//! the front's designs, and one section per front design (its variables, every metric, its
//! cross-section and its spec, ready to analyse).
//!
//! The objectives and constraints are the optimisation problem's (recorded in the store by
//! `mrbrake optimize`, or given); a sweep's store has none, and its front is taken for the
//! default pair [`DEFAULT_OBJECTIVES`]. The front is the feasible non-dominated set
//! (`mrbrake_optim::pareto::pareto_front`, constrained domination of Deb et al. 2002) over every
//! successful record of the store. Every number is a value of [`StudyReport::json`], which is
//! `mrbrake export --json` of the store.

use std::path::Path;

use mrbrake_design::geometry;
use mrbrake_design::spec::{BrakeSpec, Quantity};
use mrbrake_explore::hypervolume::{self, Hypervolume, ReferenceSource};
use mrbrake_explore::problem::{Constraint, Goal, Objective};
use mrbrake_explore::variable::resolve;
use mrbrake_optim::pareto::{Evaluation, pareto_front};
use mrbrake_store::{Record, Status, Store, VariableValue};
use serde_json::Value;

use super::writer::{Cell, Table};
use super::{Page, Section, cross_section, figure, inline_svg};
use crate::ReportError;
use crate::pareto::{
    ConstraintActivity, ObjectivePlot, constraint_activity_figure, hypervolume_axis,
    hypervolume_figure, metric_plot_axis, objective_figure,
};
use crate::study::metric_axis;

/// The objectives of a store without a problem (a sweep): most torque, least volume.
pub const DEFAULT_OBJECTIVES: [(&str, Goal); 2] =
    [("torque_max_Nm", Goal::Maximize), ("volume_m3", Goal::Minimize)];

/// A results store to report.
#[derive(Debug)]
pub struct StudyReport<'a> {
    /// The store file.
    pub store: &'a Path,
    /// Every record, in the store's order (the order of `mrbrake export`).
    pub records: &'a [Record],
    /// The variables with their bounds (from the problem), or `None` to list the records' own.
    pub bounds: Option<Vec<(String, f64, f64)>>,
    /// The objectives (at least one).
    pub objectives: Vec<Objective>,
    /// The constraints.
    pub constraints: Vec<Constraint>,
    /// Where the objectives come from (the problem file, the store, or the default).
    pub objectives_source: String,
    /// The hypervolume's reference point the problem gives (`algorithm.hypervolume_reference`,
    /// minimised units); `None`: the one the store records, else from every feasible design
    /// ([`mrbrake_explore::hypervolume`]).
    pub hypervolume_reference: Option<Vec<f64>>,
}

impl StudyReport<'_> {
    /// The JSON document the page's numbers point into: `mrbrake export --json` of the store.
    pub fn json(&self) -> Value {
        mrbrake_store::to_json(self.records)
    }

    /// Indices (into the records) of the Pareto front, sorted by the first objective.
    pub fn front(&self) -> Vec<usize> {
        let evaluations: Vec<Evaluation> =
            self.records.iter().map(|r| self.evaluation(r)).collect();
        pareto_front(&evaluations)
    }

    /// A record as an evaluation to minimise (maximised metrics negated). The base spec stored as
    /// an optimisation's reference (a record without variables) is shown but never on the front,
    /// as in `mrbrake optimize`.
    fn evaluation(&self, r: &Record) -> Evaluation {
        if r.status != Status::Ok || is_reference(r) {
            return Evaluation::failed(self.objectives.len());
        }
        let objectives = self
            .objectives
            .iter()
            .map(|o| {
                // Ranked as `mrbrake optimize` ranks it (a bound on the good side by its bound).
                let v = r
                    .metric_value(&o.metric)
                    .unwrap_or(mrbrake_store::MetricValue::Value(f64::NAN));
                mrbrake_explore::optimize::objective_value(o.goal, v)
            })
            .collect();
        let violation = self
            .constraints
            .iter()
            .map(|c| r.metric_value(&c.metric).map_or(f64::INFINITY, |v| c.violation_of(v)))
            .sum();
        Evaluation::new(objectives, violation)
    }

    /// The HTML page.
    pub fn html(self) -> Result<String, ReportError> {
        let front = self.front();
        let ok = self.records.iter().filter(|r| r.status == Status::Ok).count();
        let facts = vec![
            format!("Results store {}", self.store.display()),
            format!(
                "{} ({ok} analysed, {} infeasible or failed); Pareto front of {}.",
                crate::wording::count(self.records.len(), "design", "designs"),
                self.records.len() - ok,
                crate::wording::count(front.len(), "design", "designs")
            ),
        ];
        let stem =
            self.store.file_stem().map_or("study".into(), |s| s.to_string_lossy().to_string());
        let mut sections = vec![self.problem_section(), self.plots_section(&front)?];
        sections.push(self.hypervolume_section()?);
        sections.push(self.front_table(&front));
        for (k, &i) in front.iter().enumerate() {
            sections.push(self.design_section(k, i));
        }
        Ok(Page { title: format!("Design study {stem}"), facts, sections }.render())
    }

    /// The hypervolume of the store's designs in the store's order (the order they were
    /// evaluated in), against the problem's reference point, the store's, or one from every
    /// feasible design; `None` when no design is feasible.
    pub fn hypervolume(&self) -> Result<Option<Hypervolume>, ReportError> {
        let evaluations: Vec<Evaluation> =
            self.records.iter().filter(|r| !is_reference(r)).map(|r| self.evaluation(r)).collect();
        let store = Store::open_read_only(self.store).ok();
        let resolved = match &store {
            Some(store) => hypervolume::store_reference(
                self.hypervolume_reference.as_deref(),
                store,
                &self.objectives,
                &evaluations,
            )?,
            None => hypervolume::reference_of(&evaluations, self.objectives.len())
                .map(|r| (r, ReferenceSource::AllFeasible)),
        };
        Ok(resolved.map(|(reference, source)| Hypervolume::of(&evaluations, reference, source)))
    }

    /// The hypervolume, its reference point and its growth with the evaluations.
    fn hypervolume_section(&self) -> Result<Section, ReportError> {
        let mut s = Section::new("hypervolume", "Hypervolume against evaluations");
        let Some(h) = self.hypervolume()? else {
            s.body.paragraph("No design meets every constraint: no hypervolume yet.");
            return Ok(s);
        };
        let metrics: Vec<&str> = self.objectives.iter().map(|o| o.metric.as_str()).collect();
        let (scale, label) = hypervolume_axis(&metrics);
        let reference = crate::study::reference_point_text(&self.objectives, &h.reference, 4);
        s.body.paragraph(&format!(
            "{label}: {:.4} after {} designs, against the reference point {} ({}).",
            h.value * scale,
            h.trace.len(),
            reference.join(", "),
            h.source.describe()
        ));
        let points: Vec<(f64, f64)> =
            h.trace.iter().map(|p| (p.evaluations as f64, p.hypervolume * scale)).collect();
        let chart = hypervolume_figure(
            "Hypervolume of the feasible front",
            &label,
            &[("this store".into(), points)],
        );
        let svg = inline_svg(&chart.to_svg()?, "Hypervolume against evaluations")?;
        figure(
            &mut s.body,
            &svg,
            "The hypervolume of the feasible front of the designs analysed so far, in the order they \
             were stored.",
        );
        Ok(s)
    }

    /// The metrics of the objectives, then of the constraints (each once).
    fn metrics(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        let all = self.objectives.iter().map(|o| o.metric.as_str());
        for m in all.chain(self.constraints.iter().map(|c| c.metric.as_str())) {
            if !names.contains(&m) {
                names.push(m);
            }
        }
        names
    }

    /// The variable names, in the records' order.
    fn variable_names(&self) -> Vec<String> {
        if let Some(b) = &self.bounds {
            return b.iter().map(|(n, _, _)| n.clone()).collect();
        }
        let mut names: Vec<String> = Vec::new();
        for r in self.records {
            for (n, _) in &r.variables {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
        }
        names
    }

    fn problem_section(&self) -> Section {
        let mut s = Section::new("problem", "Variables, objectives and constraints");
        let mut vars = Table::new("Design variables", &["variable", "from", "to", "unit"]);
        let observed = |name: &str| {
            let values = self.records.iter().filter_map(|r| r.variable(name));
            values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let ranges: Vec<(String, f64, f64)> = match &self.bounds {
            Some(b) => b.clone(),
            None => self
                .variable_names()
                .into_iter()
                .map(|n| {
                    let (lo, hi) = observed(&n);
                    (n, lo, hi)
                })
                .collect(),
        };
        for (name, lo, hi) in ranges {
            let (scale, unit, decimals) = variable_display(&name);
            vars.row(vec![
                Cell::text(name),
                Cell::number(lo * scale, decimals),
                Cell::number(hi * scale, decimals),
                Cell::text(unit),
            ]);
        }
        s.body.table(&vars);
        if self.bounds.is_none() {
            s.body.paragraph(
                "The store records no problem: the ranges are those of the stored designs.",
            );
        }
        let mut obj =
            Table::new(format!("Objectives ({})", self.objectives_source), &["metric", "goal"]);
        for o in &self.objectives {
            let goal = if o.goal == Goal::Maximize { "maximise" } else { "minimise" };
            obj.row(vec![Cell::text(metric_axis(&o.metric).1), Cell::text(goal)]);
        }
        s.body.table(&obj);
        let mut con = Table::new("Constraints", &["metric", "minimum (SI)", "maximum (SI)"]);
        for c in &self.constraints {
            let limit =
                |v: Option<f64>| v.map_or(Cell::text("—"), |v| Cell::text(format!("{v}")));
            con.row(vec![Cell::text(c.metric.clone()), limit(c.min), limit(c.max)]);
        }
        if self.constraints.is_empty() {
            s.body.paragraph("No constraints.");
        } else {
            s.body.table(&con);
        }
        s
    }

    fn plots_section(&self, front: &[usize]) -> Result<Section, ReportError> {
        let mut s = Section::new("front", "Pareto front and constraints");
        let x = self.objectives[0].metric.as_str();
        let y = self
            .objectives
            .get(1)
            .map(|o| o.metric.as_str())
            .or_else(|| self.constraints.first().map(|c| c.metric.as_str()));
        let Some(y) = y else {
            s.body.paragraph(
                "One objective and no constraint: nothing to plot against; see the table.",
            );
            return Ok(s);
        };
        let ((xs, x_label), (ys, y_label)) = (metric_plot_axis(x), metric_plot_axis(y));
        let point = |r: &Record| Some((r.metric(x)? * xs, r.metric(y)? * ys));
        let mut plot = ObjectivePlot {
            title: format!(
                "{} and the front",
                crate::wording::count(self.records.len(), "design", "designs")
            ),
            x_label: x_label.clone(),
            y_label,
            ..ObjectivePlot::default()
        };
        for r in self.records.iter().filter(|r| r.status == Status::Ok && !is_reference(r)) {
            if let Some(p) = point(r) {
                if self.evaluation(r).feasible() {
                    plot.feasible.push(p)
                } else {
                    plot.infeasible.push(p)
                }
            }
        }
        plot.front = front.iter().filter_map(|&i| point(&self.records[i])).collect();
        for r in self.records.iter().filter(|r| is_reference(r)) {
            if let Some(p) = point(r) {
                plot.references.push(("reference: the base spec".into(), p));
            }
        }
        let svg = inline_svg(&objective_figure(&plot).to_svg()?, "Pareto front")?;
        figure(
            &mut s.body,
            &svg,
            "Every analysed design (feasible and infeasible) in the objective space, and the Pareto front.",
        );
        if !self.constraints.is_empty() && !front.is_empty() {
            let along = |c: &Constraint| {
                let mut pts: Vec<(f64, f64)> = front
                    .iter()
                    .filter_map(|&i| {
                        let r = &self.records[i];
                        Some((r.metric(x)? * xs, c.margin(r.metric(&c.metric)?)))
                    })
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                pts
            };
            let activity = ConstraintActivity {
                title: "Constraint activity along the front (0 = active)".into(),
                x_label,
                constraints: self
                    .constraints
                    .iter()
                    .map(|c| (constraint_label(c), along(c)))
                    .collect(),
            };
            let svg = inline_svg(
                &constraint_activity_figure(&activity).to_svg()?,
                "constraint activity",
            )?;
            figure(
                &mut s.body,
                &svg,
                "Relative margin of each constraint along the front: 0 means the constraint is active.",
            );
        }
        Ok(s)
    }

    fn front_table(&self, front: &[usize]) -> Section {
        let mut s = Section::new("front-designs", "The front's designs");
        let variables = self.variable_names();
        let metrics = self.metrics();
        let mut headers: Vec<String> = vec!["design".into()];
        headers.extend(variables.iter().map(|v| {
            let (_, unit, _) = variable_display(v);
            format!("{v} [{unit}]")
        }));
        headers.extend(metrics.iter().map(|m| metric_axis(m).1));
        let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
        let mut t = Table::new("Pareto front (links go to each design's section)", &headers);
        for (k, &i) in front.iter().enumerate() {
            let r = &self.records[i];
            let mut row = vec![Cell::link(format!("#{}", k + 1), format!("#{}", front_id(k)))];
            row.extend(variables.iter().map(|v| variable_cell(r, i, v)));
            row.extend(metrics.iter().map(|m| metric_cell(r, i, m)));
            t.row(row);
        }
        if front.is_empty() {
            s.body.paragraph("No stored design meets every constraint: the front is empty.");
        } else {
            s.body.table(&t);
        }
        s
    }

    fn design_section(&self, k: usize, i: usize) -> Section {
        let r = &self.records[i];
        let mut s = Section::new(front_id(k), format!("Front design {}", k + 1));
        s.body.paragraph(&format!(
            "Design key {} (solver {}, evaluated in {:.1} s).",
            r.key, r.solver_version, r.eval_seconds
        ));
        let mut t = Table::new("Variables and every metric", &["quantity", "value"]);
        for (name, _) in &r.variables {
            t.row(vec![
                Cell::text(format!("{name} [{}]", variable_display(name).1)),
                variable_cell(r, i, name),
            ]);
        }
        for (name, _) in &r.metrics {
            t.row(vec![Cell::text(metric_axis(name).1), metric_cell(r, i, name)]);
        }
        s.body.table(&t);
        match BrakeSpec::from_toml_str(&r.spec_toml, "stored design")
            .and_then(|spec| geometry::build(&spec))
        {
            Ok(g) => {
                let title = format!("Front design {}: half cross-section", k + 1);
                figure(
                    &mut s.body,
                    &cross_section::svg(&g, &front_id(k), &title),
                    "Half cross-section of this design (axis on the left; hatched parts rotate).",
                );
            }
            Err(e) => {
                _ = s.body.paragraph(&format!("The stored spec does not build a geometry: {e}"))
            }
        }
        s.body.element(
            "h3",
            &[],
            "Spec (save as a .toml file and run mrbrake analyze or mrbrake report on it)",
        );
        s.body.element("pre", &[], &r.spec_toml);
        s
    }
}

/// The base spec evaluated as an optimisation's reference: a record that varies nothing.
fn is_reference(r: &Record) -> bool {
    r.variables.is_empty()
}

/// The anchor of front design `k` (0-based): `front-01`, …
fn front_id(k: usize) -> String {
    format!("front-{:02}", k + 1)
}

/// Display scale, unit and decimals of a variable: millimetres for lengths, amperes, counts.
fn variable_display(name: &str) -> (f64, &'static str, usize) {
    let field = resolve(name, true).or_else(|_| resolve(name, false));
    match field.map(|v| v.quantity()) {
        Ok(Some(Quantity::Length)) => (1e3, "mm", 4),
        Ok(Some(Quantity::Current)) => (1.0, "A", 4),
        Ok(Some(Quantity::Integer)) => (1.0, "count", 0),
        Ok(Some(Quantity::Factor)) => (1.0, "factor", 4),
        Ok(Some(Quantity::Conductivity)) => (1e-6, "MS/m", 4),
        Ok(Some(Quantity::Torque)) => (1e3, "mN·m", 4),
        Ok(None) => (1.0, "material", 0),
        Err(_) => (1.0, "SI", 6),
    }
}

/// A record's variable, pointing at its JSON value (`base` when the design keeps the base spec's);
/// a material by name.
fn variable_cell(r: &Record, index: usize, name: &str) -> Cell {
    let (scale, _, decimals) = variable_display(name);
    match r.variable_value(name) {
        Some(VariableValue::Number(v)) => {
            Cell::json(*v, decimals, format!("/{index}/variables/{}", pointer_escape(name)), scale)
        }
        Some(VariableValue::Level(level)) => Cell::text(level.as_str()),
        None => Cell::text("base"),
    }
}

/// A record's metric in display units, pointing at its JSON value.
fn metric_cell(r: &Record, index: usize, name: &str) -> Cell {
    let (scale, _) = metric_axis(name);
    match r.metric(name) {
        Some(v) => Cell::json(v, 4, format!("/{index}/metrics/{}", pointer_escape(name)), scale),
        None => Cell::text(r.status.as_str()),
    }
}

/// A name as one JSON-pointer token (RFC 6901: `~` → `~0`, `/` → `~1`).
fn pointer_escape(name: &str) -> String {
    name.replace('~', "~0").replace('/', "~1")
}

/// A constraint as a legend label in displayed units, e.g. `torque max ≥ 3 N·m`.
fn constraint_label(c: &Constraint) -> String {
    crate::pareto::constraint_legend(&c.metric, c.min, c.max)
}
