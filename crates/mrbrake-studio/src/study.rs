//! A results store opened with `--store`: its records, the objectives and constraints of the
//! problem it records (else the default pair, as `mrbrake report --store` chooses), and the
//! front (`mrbrake_report::html::study::StudyReport::front`, the report's own), as one JSON
//! document for the page's Pareto plot; a record's spec on request.

use std::path::Path;

use mrbrake_explore::problem::{Objective, OptimizationProblem};
use mrbrake_report::html::study::{DEFAULT_OBJECTIVES, StudyReport};
use mrbrake_report::pareto::metric_words;
use mrbrake_store::{Record, Status, Store};
use serde_json::{Value, json};

use crate::StudioError;
use crate::session::chain;

/// The opened store.
#[derive(Debug)]
pub struct Study {
    /// What the page shows.
    pub json: Value,
    records: Vec<Record>,
}

impl Study {
    /// Reads the store at `path` (read-only) and its recorded problem.
    pub fn open(path: &Path) -> Result<Self, StudioError> {
        let open_error = |e: &dyn std::error::Error| StudioError::Open(chain(e));
        let store = Store::open_read_only(path).map_err(|e| open_error(&e))?;
        let records = mrbrake_explore::stored::read_records(&store).map_err(|e| open_error(&e))?;
        let recorded = store.meta("problem").map_err(|e| open_error(&e))?;
        let problem = match recorded {
            Some(text) => {
                let origin = format!("{} (problem recorded in the store)", path.display());
                Some(
                    OptimizationProblem::from_toml_str(&text, Path::new(&origin))
                        .map_err(|e| open_error(&e))?,
                )
            }
            None => None,
        };
        let (objectives, constraints) = match problem {
            Some(p) => (p.objectives, p.constraints),
            None => (
                DEFAULT_OBJECTIVES
                    .iter()
                    .map(|&(metric, goal)| Objective { metric: metric.into(), goal })
                    .collect(),
                Vec::new(),
            ),
        };
        let report = StudyReport {
            store: path,
            records: &records,
            bounds: None,
            objectives: objectives.clone(),
            constraints: constraints.clone(),
            objectives_source: String::new(),
            hypervolume_reference: None,
        };
        let front = report.front();
        let json = document(path, &records, &objectives, &constraints, &front);
        Ok(Self { json, records })
    }

    /// The spec of record `index` (as stored, ready to analyse).
    pub fn spec_of(&self, index: usize) -> Option<&str> {
        self.records.get(index).map(|r| r.spec_toml.as_str())
    }
}

fn document(
    path: &Path,
    records: &[Record],
    objectives: &[Objective],
    constraints: &[mrbrake_explore::problem::Constraint],
    front: &[usize],
) -> Value {
    let rows: Vec<Value> = records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let metrics: serde_json::Map<String, Value> =
                // A bound beyond the analysed range is no value to plot: `null`.
                r.metrics.iter().map(|(n, v)| (n.clone(), json!(v.value()))).collect();
            let variables: serde_json::Map<String, Value> =
                r.variables.iter().map(|(n, v)| (n.clone(), v.to_json())).collect();
            json!({
                "index": k,
                "key": r.key,
                "ok": r.status == Status::Ok,
                "reason": r.reason,
                "variables": variables,
                "metrics": metrics,
                "on_front": front.contains(&k),
            })
        })
        .collect();
    let mut names: Vec<String> =
        records.iter().flat_map(|r| r.metrics.iter().map(|(n, _)| n.clone())).collect();
    names.sort();
    names.dedup();
    let metrics: Vec<Value> =
        names.iter().map(|n| json!({ "name": n, "words": metric_words(n) })).collect();
    json!({
        "store": path.display().to_string(),
        "objectives": objectives.iter().map(|o| json!({ "metric": o.metric, "maximize": o.goal == mrbrake_explore::problem::Goal::Maximize })).collect::<Vec<_>>(),
        "constraints": constraints.iter().map(|c| json!({ "metric": c.metric, "min": c.min, "max": c.max })).collect::<Vec<_>>(),
        "metrics": metrics,
        "records": rows,
        "front": front,
    })
}
