//! A small surrogate-assisted study end to end on the coarse mesh: the budget, the hypervolume and
//! the model reports; a resumed run continues from the stored designs without recomputing them; a
//! stopped run keeps what it stored; the written front designs re-read as the designs whose
//! metrics are stored; a polish never worsens the design it starts from.

use std::path::{Path, PathBuf};

use mrbrake_design::spec::BrakeSpec;
use mrbrake_explore::design::design_key;
use mrbrake_explore::optimize::{self, OptimizeProgress, Stage};
use mrbrake_explore::polish::PolishRequest;
use mrbrake_explore::problem::{BudgetOverride, OptimizationProblem};
use mrbrake_observe::{Flow, Silent};
use mrbrake_store::Store;

fn spec_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs/single-disc.toml")
}

/// Two variables, two objectives, one constraint, 8 designs from an initial plan of 4, batch 2.
fn problem(dir: &Path, extra: &str) -> OptimizationProblem {
    let path = dir.join("problem.toml");
    let text = format!(
        "spec = {:?}\nmesh = \"coarse\"\nreference = false\n{extra}\n\
         [[variable]]\nname = \"g\"\nmin = \"0.3mm\"\nmax = \"1mm\"\n\
         [[variable]]\nname = \"R2\"\nmin = \"24mm\"\nmax = \"30mm\"\n\
         [[constraint]]\nmetric = \"torque_max_Nm\"\nmin = \"0.8Nm\"\n\
         [[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n\
         [[objective]]\nmetric = \"torque_max_Nm\"\ngoal = \"maximize\"\n\
         [algorithm]\nkind = \"surrogate\"\nmax_evaluations = 8\ninitial_size = 4\nbatch = 2\n\
         seed = 3\n",
        spec_path().display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    OptimizationProblem::from_path(&path).unwrap()
}

fn budget(problem: &mut OptimizationProblem, max_evaluations: usize) {
    let b = BudgetOverride { max_evaluations: Some(max_evaluations), ..Default::default() };
    problem.algorithm = problem.algorithm.with_budget(b).unwrap();
}

#[test]
fn a_surrogate_study_runs_resumes_and_writes_its_front() {
    let dir = tempfile::tempdir().unwrap();
    let problem = problem(dir.path(), "");
    let mut store = Store::open_or_create(&dir.path().join("s.sqlite"), false).unwrap();
    let mut iterations = Vec::new();
    let result = optimize::run(&problem, &mut store, 1, &mut |p: &OptimizeProgress| {
        if let Some(status) = &p.iteration {
            assert!(matches!(p.stage, Stage::Iteration { .. }));
            iterations.push(status.clone());
        }
        Flow::Continue
    })
    .unwrap();
    assert_eq!(result.evaluated.len(), 8);
    let surrogate = result.surrogate.as_ref().unwrap();
    assert_eq!((surrogate.stop, surrogate.batch, surrogate.resumed_from), ("budget", 2, 0));
    assert_eq!(surrogate.iterations, iterations, "every iteration is shown and kept");
    assert_eq!(iterations[0].evaluations, 4, "the initial design");
    assert!(
        iterations
            .iter()
            .skip(1)
            .all(|i| i.batch == 2 && (i.fallback.is_some() || !i.models.is_empty()))
    );
    for status in iterations.iter().filter(|i| !i.models.is_empty()) {
        assert!(
            status.models.iter().all(|m| m.loo_error.is_finite() && m.points >= 2),
            "{status:?}"
        );
    }
    // The constraint reaches the models as a signed margin.
    assert!(
        result.evaluated.iter().filter(|e| e.evaluation.violation.is_finite()).all(|e| e
            .evaluation
            .constraints
            .len()
            == 1)
    );
    let hv = result.hypervolume.as_ref().expect("a feasible design");
    assert_eq!(hv.trace.len(), 8);
    assert!(hv.value > 0.0 && hv.trace.windows(2).all(|w| w[1].hypervolume >= w[0].hypervolume));
    assert!(!result.front.is_empty() && result.front_designs.len() == result.front.len());
    check_front_designs(&problem, &result);

    // Resumed with a larger budget: the 8 stored designs are the data, two more are evaluated.
    let mut more = problem.clone();
    budget(&mut more, 10);
    let again = optimize::run(&more, &mut store, 1, &mut Silent).unwrap();
    let surrogate = again.surrogate.as_ref().unwrap();
    assert_eq!(surrogate.resumed_from, 8 + rounded_designs(&result), "{surrogate:?}");
    assert_eq!(again.evaluated.len(), 10.max(surrogate.resumed_from));
    let keys: Vec<&str> = result.evaluated.iter().map(|e| e.record.key.as_str()).collect();
    assert!(keys.iter().all(|k| again.evaluated.iter().any(|e| e.record.key == *k)));
    // The reference point the first run fixed is recorded and used again.
    let first = result.hypervolume.as_ref().unwrap();
    let second = again.hypervolume.as_ref().unwrap();
    assert_eq!(first.reference, second.reference);
    assert_eq!(second.source.key(), "store");
}

/// The designs the first run added to the store by rounding its front (they are designs of the
/// problem, so a resumed run reads them as data).
fn rounded_designs(result: &optimize::OptimizationResult) -> usize {
    let mut keys: Vec<&str> = result
        .front_designs
        .iter()
        .filter(|d| d.rounded)
        .map(|d| d.evaluated.record.key.as_str())
        .filter(|k| !result.evaluated.iter().any(|e| e.record.key == *k))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}

/// Every written front design re-reads as the design whose metrics are stored: the same key, its
/// lengths on the 0.01 mm grid in the base spec's millimetres, the base file's comments kept.
fn check_front_designs(problem: &OptimizationProblem, result: &optimize::OptimizationResult) {
    for d in &result.front_designs {
        let spec = BrakeSpec::from_toml_str(&d.spec_text, "front design").unwrap();
        spec.validate().unwrap();
        assert_eq!(design_key(&spec, &problem.settings).unwrap(), d.evaluated.record.key);
        assert!(d.note.is_none(), "{:?}", d.note);
        let gap = d.evaluated.record.variable("g").unwrap();
        assert!(((gap * 1e5).round() - gap * 1e5).abs() < 1e-6, "{gap} on the 0.01 mm grid");
        assert!(d.spec_text.contains("mm\""), "in the base spec's units:\n{}", d.spec_text);
        assert!(d.spec_text.contains('#'), "the base file's comments are kept");
        assert!(d.evaluated.record.metric("torque_max_Nm").is_some());
    }
}

#[test]
fn a_stopped_surrogate_run_resumes_from_what_it_stored() {
    let dir = tempfile::tempdir().unwrap();
    let problem = problem(dir.path(), "manufacturing_resolution = 0");
    let mut store = Store::open_or_create(&dir.path().join("s.sqlite"), false).unwrap();
    let stopped = optimize::run(&problem, &mut store, 1, &mut |p: &OptimizeProgress| {
        Flow::stop_if(p.done >= 5)
    })
    .unwrap();
    assert!(stopped.stopped);
    let stored = store.len().unwrap();
    assert!((5..8).contains(&stored), "{stored}");
    assert_eq!(stopped.evaluated.len(), stored);
    let resumed = optimize::run(&problem, &mut store, 1, &mut Silent).unwrap();
    let surrogate = resumed.surrogate.as_ref().unwrap();
    assert_eq!(surrogate.resumed_from, stored);
    assert_eq!(resumed.totals.progress.computed, 8 - stored, "nothing stored is computed again");
    assert_eq!(resumed.evaluated.len(), 8);
    assert_eq!(store.len().unwrap(), 8);
    // Written as evaluated: nothing rounded, nothing evaluated again.
    assert!(resumed.front_designs.iter().all(|d| !d.rounded));

    // A polish of front design 1 improves its inertia without losing torque, through the store.
    let request = PolishRequest { design: 1, objective: None, max_evaluations: 6 };
    let polished =
        optimize::run_with(&problem, &mut store, 1, Some(&request), &mut Silent).unwrap();
    let polish = polished.polish.as_ref().unwrap();
    let metric = |e: &optimize::Evaluated, m: &str| e.record.metric(m).unwrap();
    assert!(
        metric(&polish.best, "rotor_inertia_kg_m2") <= metric(&polish.start, "rotor_inertia_kg_m2")
    );
    assert!(metric(&polish.best, "torque_max_Nm") >= metric(&polish.start, "torque_max_Nm"));
    assert!(polish.evaluated.len() <= 6);
    let bad = PolishRequest { design: 99, objective: None, max_evaluations: 6 };
    let e = optimize::run_with(&problem, &mut store, 1, Some(&bad), &mut Silent).unwrap_err();
    assert!(e.to_string().starts_with("polish: the front has"), "{e}");
    assert!(e.to_string().contains("got 99"), "{e}");
}
