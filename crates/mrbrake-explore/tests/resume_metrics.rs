//! `--resume` computes only the missing metrics: a study run with the static metrics, then
//! resumed asking for one more metric, finds its designs under the same keys and runs that
//! metric's analysis once per design and nothing else — no static analysis again (evaluations
//! counted, not timed). One test in this file: the analysis counts are per process.

use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::DEFAULT_SPEC_TOML;
use mrbrake_explore::evaluate::static_analysis_count;
use mrbrake_explore::metrics::{Analysis, StudyMetrics, analysis_counts};
use mrbrake_explore::{Design, DesignSpace, EvaluationSettings, Runner};
use mrbrake_observe::Silent;
use mrbrake_store::{Status, Store};

fn settings(metrics: &[&str]) -> EvaluationSettings {
    let mut settings = EvaluationSettings { mesh: MeshLevel::Coarse, ..Default::default() };
    settings.study =
        StudyMetrics::new(metrics.iter().copied(), &[], Default::default(), Default::default());
    settings
}

fn designs(settings: &EvaluationSettings) -> Vec<Design> {
    let space =
        DesignSpace::new(DEFAULT_SPEC_TOML, "default", &[], &["g".to_string()], settings.clone())
            .unwrap();
    [0.45e-3, 0.55e-3].iter().map(|g| space.design(&[*g]).unwrap()).collect()
}

fn runs(of: Analysis) -> usize {
    analysis_counts().into_iter().find(|(a, _)| *a == of).map_or(0, |(_, n)| n)
}

fn expensive_runs() -> usize {
    analysis_counts().iter().map(|(_, n)| n).sum()
}

#[test]
fn resuming_with_one_more_metric_evaluates_only_that_metric() {
    let directory = tempfile::tempdir().unwrap();
    let mut store = Store::create(&directory.path().join("study.mrbrake")).unwrap();
    let static_only = settings(&[]);
    let first = designs(&static_only);
    let (records, summary) =
        Runner::new(&mut store, static_only, 1).run(&first, &mut Silent).unwrap();
    assert_eq!(summary.progress.computed, 2);
    assert!(records.iter().all(|r| r.status == Status::Ok), "{records:?}");
    assert_eq!((static_analysis_count(), expensive_runs()), (2, 0));

    // Resumed asking for the steady coil temperature too: the same keys, completed in place.
    let more = settings(&["coil_max_T_C"]);
    let second = designs(&more);
    let keys = |d: &[Design]| d.iter().map(|d| d.key.clone()).collect::<Vec<_>>();
    assert_eq!(keys(&first), keys(&second), "the metric list is not part of the key");
    let (records, summary) =
        Runner::new(&mut store, more.clone(), 1).run(&second, &mut Silent).unwrap();
    assert_eq!((summary.progress.computed, summary.progress.reused), (2, 0));
    assert_eq!(static_analysis_count(), 2, "no static analysis again");
    assert_eq!(runs(Analysis::ThermalSteady), 2, "{:?}", analysis_counts());
    assert_eq!(expensive_runs(), 2, "nothing but the missing metric: {:?}", analysis_counts());
    for record in &records {
        assert_eq!(record.status, Status::Ok, "{:?}", record.reason);
        assert!(record.metric_value("coil_max_T_C").is_some(), "{:?}", record.metrics);
        assert!(record.metric("torque_max_Nm").is_some(), "the stored metrics are kept");
    }
    assert_eq!(store.len().unwrap(), 2, "completed, not added");

    // Once more with the same metrics: everything is stored, nothing runs.
    let (_, summary) = Runner::new(&mut store, more, 1).run(&second, &mut Silent).unwrap();
    assert_eq!((summary.progress.computed, summary.progress.reused), (0, 2));
    assert_eq!((static_analysis_count(), expensive_runs()), (2, 2));
}
