//! The hypervolume of an optimisation as a first-class quantity: its reference point, its value,
//! and its growth with the evaluations, for every algorithm (NSGA-II, surrogate, pattern search)
//! and for any results store.
//!
//! Brief overview: the hypervolume indicator (Zitzler & Thiele 1998; exact, any number of
//! objectives: [`mrbrake_optim::pareto::hypervolume`]) of the feasible non-dominated designs, in
//! minimised objectives (a maximised metric negated) and SI units, below a **reference point**.
//! The reference is, in order of precedence:
//!
//! 1. given in the problem file (`algorithm.hypervolume_reference`, [`ReferenceSource::Problem`]);
//! 2. recorded in the results store by an earlier run of the same objectives (store meta
//!    [`META_KEY`], [`ReferenceSource::Store`]), so a resumed run and `mrbrake report --store` use
//!    the run's own reference;
//! 3. fixed by the run at the end of its first batch (NSGA-II generation, surrogate iteration,
//!    pattern-search poll) with a feasible design: 10 % of the feasible designs' range beyond
//!    their worst value in each objective, the rule of Ishibuchi et al. (2018) that the surrogate
//!    optimiser uses for its acquisition ([`mrbrake_optim::surrogate::beyond_worst`]; the same data
//!    gives the same point, so the reported and the acquisition's hypervolume agree)
//!    ([`ReferenceSource::FirstFeasibleBatch`]);
//! 4. for a store without a recorded one (a sweep, an older store): the same rule over every
//!    feasible design of the store ([`ReferenceSource::AllFeasible`]).
//!
//! [`trace`] is the hypervolume after every evaluation, in evaluation order: the curve of
//! hypervolume against evaluations of `optimize --out` (`hypervolume.csv`, `.svg`) and of the
//! study report, and the figure by which runs of different algorithms compare (measure them all
//! with one reference, given in the problem file).

use mrbrake_optim::pareto::{Evaluation, dominates, hypervolume};
use mrbrake_optim::surrogate::beyond_worst;
use mrbrake_store::{Store, StoreError};
use serde_json::{Value, json};

use crate::problem::{Goal, Objective};

/// The store meta entry holding the reference point a run fixed (JSON: the objectives and the
/// point in minimised units).
pub const META_KEY: &str = "hypervolume_reference";

/// Where a hypervolume's reference point comes from (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceSource {
    /// `algorithm.hypervolume_reference` of the problem file.
    Problem,
    /// Recorded in the results store by the run that fixed it.
    Store,
    /// Fixed by this run at the end of its first batch with a feasible design.
    FirstFeasibleBatch,
    /// From every feasible design of a store that records none.
    AllFeasible,
}

impl ReferenceSource {
    /// The source in words, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Problem => "given in the problem file (algorithm.hypervolume_reference)",
            Self::Store => "recorded in the store by the run that fixed it",
            Self::FirstFeasibleBatch => {
                "10 % of the range beyond the worst feasible design of the first batch with one"
            }
            Self::AllFeasible => "10 % of the range beyond the worst feasible design of the store",
        }
    }

    /// The source's key in JSON (`problem`, `store`, `first_feasible_batch`, `all_feasible`).
    pub fn key(self) -> &'static str {
        match self {
            Self::Problem => "problem",
            Self::Store => "store",
            Self::FirstFeasibleBatch => "first_feasible_batch",
            Self::AllFeasible => "all_feasible",
        }
    }
}

/// The hypervolume after one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracePoint {
    /// Designs evaluated so far (1, 2, …).
    pub evaluations: usize,
    /// The hypervolume of their feasible front.
    pub hypervolume: f64,
}

/// A run's (or a store's) hypervolume with its reference point and its growth.
#[derive(Debug, Clone, PartialEq)]
pub struct Hypervolume {
    /// The hypervolume of the feasible front of every design, in the product of the objectives'
    /// SI units.
    pub value: f64,
    /// The reference point, minimised units (a maximised objective's value negated).
    pub reference: Vec<f64>,
    /// Where the reference comes from.
    pub source: ReferenceSource,
    /// The hypervolume after every evaluation, in evaluation order.
    pub trace: Vec<TracePoint>,
}

impl Hypervolume {
    /// The hypervolume of `evaluations` (in evaluation order) below `reference`.
    pub fn of(evaluations: &[Evaluation], reference: Vec<f64>, source: ReferenceSource) -> Self {
        let trace = trace(evaluations, &reference);
        let value = trace.last().map_or(0.0, |p| p.hypervolume);
        Self { value, reference, source, trace }
    }

    /// The reference point in each objective's own metric (maximised objectives back to their
    /// sign), keyed by metric name, as `optimize --json` shows it.
    pub fn reference_json(&self, objectives: &[Objective]) -> Value {
        let mut map = serde_json::Map::new();
        for (o, r) in objectives.iter().zip(&self.reference) {
            let value = if o.goal == Goal::Maximize { -r } else { *r };
            map.insert(o.metric.clone(), json!(value));
        }
        Value::Object(map)
    }

    /// The fewest evaluations after which the hypervolume reached `fraction` of `target` (`None`
    /// if it never did).
    pub fn evaluations_to(&self, fraction: f64, target: f64) -> Option<usize> {
        self.trace.iter().find(|p| p.hypervolume >= fraction * target).map(|p| p.evaluations)
    }
}

/// The hypervolume after every evaluation of `evaluations` (in order) below `reference`: the
/// feasible non-dominated set kept incrementally, its exact hypervolume recomputed when it changes.
pub fn trace(evaluations: &[Evaluation], reference: &[f64]) -> Vec<TracePoint> {
    let mut front: Vec<&[f64]> = Vec::new();
    let mut value = 0.0;
    let mut out = Vec::with_capacity(evaluations.len());
    for (k, e) in evaluations.iter().enumerate() {
        let point = e.objectives.as_slice();
        let usable =
            e.feasible() && point.len() == reference.len() && point.iter().all(|v| v.is_finite());
        let covered = front.iter().any(|f| dominates(f, point) || same(f, point));
        if usable && !covered {
            front.retain(|f| !dominates(point, f));
            front.push(point);
            let points: Vec<Vec<f64>> = front.iter().map(|p| p.to_vec()).collect();
            value = hypervolume(&points, reference);
        }
        out.push(TracePoint { evaluations: k + 1, hypervolume: value });
    }
    out
}

fn same(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.total_cmp(y).is_eq())
}

/// The reference rule (module docs, 3.) applied to the feasible designs among `evaluations`;
/// `None` when none is feasible.
pub fn reference_of(evaluations: &[Evaluation], objectives: usize) -> Option<Vec<f64>> {
    let feasible: Vec<&[f64]> = evaluations
        .iter()
        .filter(|e| e.feasible() && e.objectives.iter().all(|v| v.is_finite()))
        .map(|e| e.objectives.as_slice())
        .collect();
    (!feasible.is_empty()).then(|| beyond_worst(&feasible, objectives))
}

/// The objectives as the store meta names them (`metric:goal`), to tell whether a recorded
/// reference belongs to these objectives.
fn objective_names(objectives: &[Objective]) -> Vec<String> {
    objectives
        .iter()
        .map(|o| {
            let goal = if o.goal == Goal::Maximize { "maximize" } else { "minimize" };
            format!("{}:{goal}", o.metric)
        })
        .collect()
}

/// The reference point `store` records for `objectives` ([`META_KEY`]); `None` when it records
/// none, or one of other objectives.
pub fn stored_reference(
    store: &Store,
    objectives: &[Objective],
) -> Result<Option<Vec<f64>>, StoreError> {
    let Some(text) = store.meta(META_KEY)? else { return Ok(None) };
    let Ok(value) = serde_json::from_str::<Value>(&text) else { return Ok(None) };
    let names: Option<Vec<String>> = value["objectives"]
        .as_array()
        .map(|a| a.iter().filter_map(|v| v.as_str().map(str::to_owned)).collect());
    if names != Some(objective_names(objectives)) {
        return Ok(None);
    }
    let point: Option<Vec<f64>> =
        value["reference"].as_array().and_then(|a| a.iter().map(Value::as_f64).collect());
    Ok(point.filter(|p| p.len() == objectives.len() && p.iter().all(|v| v.is_finite())))
}

/// Records `reference` for `objectives` in `store`, unless it records one already.
pub fn record_reference(
    store: &mut Store,
    objectives: &[Objective],
    reference: &[f64],
) -> Result<(), StoreError> {
    if store.meta(META_KEY)?.is_some() {
        return Ok(());
    }
    let value = json!({ "objectives": objective_names(objectives), "reference": reference });
    store.set_meta(META_KEY, &value.to_string())?;
    Ok(())
}

/// The reference of a store's report: the problem's, else the one the store records, else the
/// rule over every feasible design (`evaluations`, the store's records as evaluations).
pub fn store_reference(
    given: Option<&[f64]>,
    store: &Store,
    objectives: &[Objective],
    evaluations: &[Evaluation],
) -> Result<Option<(Vec<f64>, ReferenceSource)>, StoreError> {
    if let Some(r) = given {
        return Ok(Some((r.to_vec(), ReferenceSource::Problem)));
    }
    if let Some(r) = stored_reference(store, objectives)? {
        return Ok(Some((r, ReferenceSource::Store)));
    }
    Ok(reference_of(evaluations, objectives.len()).map(|r| (r, ReferenceSource::AllFeasible)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(f1: f64, f2: f64, violation: f64) -> Evaluation {
        Evaluation::new(vec![f1, f2], violation)
    }

    #[test]
    fn the_trace_grows_with_each_new_front_point_and_ignores_the_rest() {
        let evaluations = [
            e(3.0, 3.0, 1.0), // infeasible: nothing
            e(2.0, 2.0, 0.0), // (4 − 2)(4 − 2) = 4
            e(2.5, 2.5, 0.0), // dominated: unchanged
            e(1.0, 3.0, 0.0), // adds (2 − 1)(4 − 3) = 1
            Evaluation::failed(2),
            e(1.0, 1.0, 0.0), // dominates both: (4 − 1)² = 9
        ];
        let t = trace(&evaluations, &[4.0, 4.0]);
        let values: Vec<f64> = t.iter().map(|p| p.hypervolume).collect();
        let expected = [0.0, 4.0, 4.0, 5.0, 5.0, 9.0];
        for (v, x) in values.iter().zip(expected) {
            assert!((v - x).abs() < 1e-12, "{values:?}");
        }
        assert_eq!(t.last().map(|p| p.evaluations), Some(6));
        let hv = Hypervolume::of(&evaluations, vec![4.0, 4.0], ReferenceSource::Problem);
        assert!((hv.value - 9.0).abs() < 1e-12);
        assert_eq!(hv.evaluations_to(0.5, 9.0), Some(4));
        assert_eq!(hv.evaluations_to(1.0, 10.0), None);
    }

    #[test]
    fn the_rule_reaches_beyond_the_worst_feasible_design() {
        let evaluations = [e(1.0, 5.0, 0.0), e(3.0, 1.0, 0.0), e(9.0, 9.0, 0.5)];
        let r = reference_of(&evaluations, 2).unwrap();
        assert!((r[0] - 3.2).abs() < 1e-12 && (r[1] - 5.4).abs() < 1e-12, "{r:?}");
        assert!(reference_of(&evaluations[2..], 2).is_none());
    }

    #[test]
    fn a_recorded_reference_belongs_to_its_objectives() {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open_or_create(&dir.path().join("s.sqlite"), false).unwrap();
        let objectives = vec![
            Objective { metric: "volume_m3".into(), goal: Goal::Minimize },
            Objective { metric: "torque_max_Nm".into(), goal: Goal::Maximize },
        ];
        assert_eq!(stored_reference(&store, &objectives).unwrap(), None);
        record_reference(&mut store, &objectives, &[1e-3, -2.0]).unwrap();
        record_reference(&mut store, &objectives, &[5.0, 5.0]).unwrap();
        assert_eq!(stored_reference(&store, &objectives).unwrap(), Some(vec![1e-3, -2.0]));
        let hv = Hypervolume::of(&[], vec![1e-3, -2.0], ReferenceSource::Store);
        assert_eq!(hv.reference_json(&objectives)["torque_max_Nm"], json!(2.0));
        assert_eq!(stored_reference(&store, &objectives[..1]).unwrap(), None);
    }
}
