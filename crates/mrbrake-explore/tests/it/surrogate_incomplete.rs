//! A surrogate run continued from a store whose designs were evaluated for fewer metrics: a
//! stored design holding every metric the objectives and constraints need is data (one lacking
//! only a recorded metric included), one lacking a needed metric is skipped, counted and said
//! (`SurrogateRun::skipped_incomplete`), never read as data nor a failure.

use std::path::Path;

use mrbrake_explore::optimize;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_observe::Silent;
use mrbrake_store::Store;

/// A surrogate problem on the single-disc example, 4 designs, with `objective` beside the rotor
/// inertia and `extra` top-level keys.
fn problem(dir: &Path, name: &str, objective: &str, extra: &str) -> OptimizationProblem {
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs/single-disc.toml");
    let path = dir.join(name);
    let text = format!(
        "spec = {:?}\nmesh = \"coarse\"\nreference = false\n{extra}\n\
         [[variable]]\nname = \"g\"\nmin = \"0.3mm\"\nmax = \"1mm\"\n\
         [[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n\
         [[objective]]\nmetric = \"{objective}\"\n\
         [algorithm]\nkind = \"surrogate\"\nmax_evaluations = 4\ninitial_size = 4\nbatch = 2\n\
         seed = 3\n",
        spec.display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    OptimizationProblem::from_path(&path).unwrap()
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: eight analyses and four thermal solves")]
fn stored_designs_lacking_a_needed_metric_are_skipped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open_or_create(&dir.path().join("s.sqlite"), false).unwrap();
    let static_only = problem(dir.path(), "a.toml", "torque_off_Nm", "");
    let first = optimize::run(&static_only, &mut store, 1, &mut Silent).unwrap();
    assert_eq!(first.evaluated.len(), 4);
    let stored = store.len().unwrap();

    // Only a recorded metric is missing: the stored designs are the data (nothing skipped).
    let recording = problem(dir.path(), "b.toml", "torque_off_Nm", "record = [\"coil_max_T_C\"]");
    let again = optimize::run(&recording, &mut store, 1, &mut Silent).unwrap();
    let run = again.surrogate.as_ref().unwrap();
    assert_eq!((run.resumed_from, run.skipped_incomplete), (stored, 0), "{run:?}");

    // An objective most stored designs lack (run b's front designs, evaluated again after
    // rounding, hold it): those are skipped and counted, the others are data, the study runs.
    let records = store.records().unwrap();
    let lacking = records.iter().filter(|r| r.metric_value("coil_max_T_C").is_none()).count();
    assert!(lacking > 0 && lacking <= records.len());
    let needing = problem(dir.path(), "c.toml", "coil_max_T_C", "");
    let third = optimize::run(&needing, &mut store, 1, &mut Silent).unwrap();
    let run = third.surrogate.as_ref().unwrap();
    assert_eq!(run.skipped_incomplete, lacking, "{run:?}");
    assert_eq!(run.resumed_from, records.len() - lacking, "{run:?}");
    assert_eq!(third.evaluated.len(), 4);
    assert!(third.evaluated.iter().all(|e| e.record.metric_value("coil_max_T_C").is_some()));
}
