//! Merging two stores of the same designs evaluated for different metrics: the record with more
//! metrics completes the other (the union of the metrics), a differing value stays a conflict.

use std::path::{Path, PathBuf};

use mrbrake_store::{MergeSummary, MetricValue, Record, Status, Store};

fn record(index: u32, status: Status, metrics: &[(&str, f64)]) -> Record {
    Record {
        key: format!("{index:064x}"),
        status,
        reason: None,
        variables: vec![("gap_m".into(), (1e-4 * f64::from(index + 1)).into())],
        metrics: metrics.iter().map(|(n, v)| (n.to_string(), (*v).into())).collect(),
        spec_toml: format!("# design {index}\n"),
        eval_seconds: 1.0,
        solver_version: "test".into(),
        settings: Default::default(),
    }
}

fn store_with(directory: &Path, name: &str, records: &[Record]) -> PathBuf {
    let path = directory.join(name);
    let mut store = Store::create(&path).expect("create");
    for record in records {
        assert!(store.insert(record).expect("insert"));
    }
    path
}

fn metric(store: &Store, index: u32, name: &str) -> Option<MetricValue> {
    let record = store.get(&format!("{index:064x}")).expect("get").expect("present");
    record.metric_value(name)
}

/// Key 0: the incoming record has every stored metric and one more (it completes the stored
/// one); key 1: the stored record has more (already complete: a duplicate); key 2: each side has
/// a metric the other lacks (a conflict: also how one metric under two names looks); key 3: a
/// shared metric differs (a conflict, the stored record kept); key 4: same metrics, different
/// status (a conflict); key 5: the stored record stopped at a gate of the study (infeasible,
/// fewer metrics) is completed by the same outcome with more.
#[test]
fn a_record_with_more_metrics_completes_the_stored_one_and_a_differing_value_conflicts() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let torque = ("torque_max_Nm", 2.0);
    let bandwidth = ("bandwidth_rad_s", 350.0);
    let heat = ("coil_max_T_C", 80.0);
    let stored = [
        record(0, Status::Ok, &[torque]),
        record(1, Status::Ok, &[torque, bandwidth]),
        record(2, Status::Ok, &[torque, bandwidth]),
        record(3, Status::Ok, &[torque]),
        record(4, Status::Ok, &[torque]),
        record(5, Status::Infeasible, &[torque]),
    ];
    let incoming = [
        record(0, Status::Ok, &[torque, bandwidth]),
        record(1, Status::Ok, &[torque]),
        record(2, Status::Ok, &[torque, heat]),
        record(3, Status::Ok, &[("torque_max_Nm", 2.5), bandwidth]),
        record(4, Status::Infeasible, &[torque]),
        record(5, Status::Infeasible, &[torque, heat]),
    ];
    let path_a = store_with(directory.path(), "a.mrbrake", &stored);
    let path_b = store_with(directory.path(), "b.mrbrake", &incoming);
    let mut merged = Store::open(&path_a).expect("open a");
    let summary = merged.merge_from(&path_b).expect("merge");
    let conflicts: Vec<String> = [2, 3, 4].iter().map(|i| format!("{i:064x}")).collect();
    assert_eq!(summary, MergeSummary { inserted: 0, duplicates: 1, completed: 2, conflicts });
    drop(merged);
    let merged = Store::open(&path_a).expect("reopen: the completed records verify");
    assert_eq!(metric(&merged, 0, "bandwidth_rad_s"), Some(MetricValue::Value(350.0)));
    assert_eq!(metric(&merged, 2, "coil_max_T_C"), None, "a conflict is not completed");
    assert_eq!(metric(&merged, 5, "coil_max_T_C"), Some(MetricValue::Value(80.0)));
    assert_eq!(metric(&merged, 3, "torque_max_Nm"), Some(MetricValue::Value(2.0)), "kept");
    assert_eq!(metric(&merged, 3, "bandwidth_rad_s"), None, "a conflict is not completed");
    let keys: Vec<String> = merged.records().expect("records").into_iter().map(|r| r.key).collect();
    let expected: Vec<String> = (0..6).map(|i| format!("{i:064x}")).collect();
    assert_eq!(keys, expected, "completed records keep their place");
    // Merging again changes nothing: every record now holds what the other store has.
    let mut again = Store::open(&path_a).expect("open");
    let summary = again.merge_from(&path_b).expect("merge again");
    assert_eq!((summary.completed, summary.duplicates, summary.conflicts.len()), (0, 3, 3));
}
