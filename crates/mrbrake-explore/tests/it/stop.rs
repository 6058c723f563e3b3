//! A study's observer may stop it: the run ends after the designs in flight, every finished
//! evaluation stays in the store, and running again resumes without recomputing them.

use std::path::PathBuf;

use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_explore::optimize::{self, OptimizeProgress};
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_explore::{DesignSpace, EvaluationSettings, ExploreError, Progress, Runner};
use mrbrake_observe::{Flow, Silent};
use mrbrake_store::Store;

fn spec_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs/single-disc.toml")
}

fn coarse() -> EvaluationSettings {
    EvaluationSettings { mesh: MeshLevel::Coarse, ..EvaluationSettings::default() }
}

#[test]
fn a_stopped_run_keeps_what_it_stored_and_resumes() {
    let text = std::fs::read_to_string(spec_path()).unwrap();
    let space = DesignSpace::new(&text, "single-disc.toml", &[], &["g".into()], coarse()).unwrap();
    let designs: Vec<_> =
        [0.5e-3, 0.6e-3, 0.7e-3, 0.8e-3].iter().map(|&g| space.design(&[g]).unwrap()).collect();
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open_or_create(&dir.path().join("s.sqlite"), false).unwrap();
    let mut seen = 0;
    let stopped = Runner::new(&mut store, coarse(), 1)
        .run(&designs, &mut |p: &Progress| {
            seen += 1;
            Flow::stop_if(p.computed >= 1)
        })
        .unwrap_err();
    let ExploreError::Stopped { progress } = stopped else { panic!("not a stop: {stopped}") };
    // One worker: the design after the first may have started before the stop; no more.
    assert!((1..=2).contains(&progress.computed), "{progress:?}");
    assert_eq!(progress.to_compute, 4);
    assert_eq!(seen, 1 + progress.computed, "the start and every stored design are observed");
    assert_eq!(store.len().unwrap(), progress.computed);
    let (records, summary) =
        Runner::new(&mut store, coarse(), 1).run(&designs, &mut Silent).unwrap();
    assert_eq!(records.len(), 4);
    assert_eq!(summary.progress.reused, progress.computed);
    assert_eq!(summary.progress.computed, 4 - progress.computed);
}

#[test]
fn a_stopped_optimisation_returns_what_it_evaluated() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("problem.toml");
    let text = format!(
        "spec = {:?}\nmesh = \"coarse\"\nreference = false\n\
         [[variable]]\nname = \"g\"\nmin = \"0.4mm\"\nmax = \"1mm\"\n\
         [[objective]]\nmetric = \"mass_kg\"\ngoal = \"minimize\"\n\
         [algorithm]\nkind = \"pattern-search\"\nmax_evaluations = 7\n",
        spec_path().display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    let problem = OptimizationProblem::from_path(&path).unwrap();
    let mut store = Store::open_or_create(&dir.path().join("o.sqlite"), false).unwrap();
    let mut last = None;
    let result = optimize::run(&problem, &mut store, 1, &mut |p: &OptimizeProgress| {
        last = Some(p.done);
        // Stop as soon as the first poll has a design.
        Flow::stop_if(p.done >= 2)
    })
    .unwrap();
    assert!(result.stopped);
    // The stop comes within the first poll, or (when its last design was in flight) as the
    // second one starts.
    assert!(result.iterations <= 1, "{}", result.iterations);
    assert_eq!(result.evaluated.len(), store.len().unwrap());
    assert!((2..7).contains(&result.evaluated.len()), "{}", result.evaluated.len());
    assert_eq!(last, Some(result.evaluated.len()));
    // Running again on the same store resumes: the stored designs are read back.
    let again = optimize::run(&problem, &mut store, 1, &mut Silent).unwrap();
    assert!(!again.stopped);
    assert!(again.totals.progress.reused >= result.evaluated.len());
}
