//! Merging shard stores: union without duplicates, conflicts reported and never applied.

use mrbrake_error::Kind as _;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

use mrbrake_store::{MergeSummary, Record, Status, Store, StoreError};

fn record(index: u32, torque_nm: f64) -> Record {
    Record {
        key: format!("{index:064x}"),
        status: Status::Ok,
        reason: None,
        variables: vec![("gap_m".into(), (1e-4 * f64::from(index + 1)).into())],
        metrics: vec![
            ("torque_on_nm".into(), torque_nm.into()),
            ("ratio".into(), f64::INFINITY.into()),
            ("unknown".into(), f64::NAN.into()),
        ],
        spec_toml: format!("# design {index}\n"),
        eval_seconds: 0.3,
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

fn keys(store: &Store) -> Vec<String> {
    store.records().expect("records").into_iter().map(|record| record.key).collect()
}

#[test]
fn overlapping_shards_merge_to_their_union() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let shard_a: Vec<Record> = (0..6).map(|index| record(index, 3.0 + f64::from(index))).collect();
    // Shard b overlaps a on 4 and 5 (agreeing to 1e-12 relative, below the 1e-9 tolerance),
    // disagrees on 3 and adds 6..9.
    let mut shard_b =
        vec![record(4, 7.0 * (1.0 + 1e-12)), record(5, 8.0), record(3, 6.0 * (1.0 + 1e-6))];
    shard_b.extend((6..9).map(|index| record(index, 3.0 + f64::from(index))));
    let path_a = store_with(directory.path(), "a.mrbrake", &shard_a);
    let path_b = store_with(directory.path(), "b.mrbrake", &shard_b);

    let mut merged = Store::open(&path_a).expect("open a");
    let summary = merged.merge_from(&path_b).expect("merge");
    assert_eq!(
        summary,
        MergeSummary {
            inserted: 3,
            duplicates: 2,
            completed: 0,
            conflicts: vec![format!("{:064x}", 3)]
        }
    );
    let expected: Vec<String> = (0..9).map(|index| format!("{index:064x}")).collect();
    assert_eq!(keys(&merged), expected, "a's order, then b's new records in b's order");
    let kept = merged.get(&format!("{:064x}", 3)).expect("get").expect("present");
    assert_eq!(kept.metric("torque_on_nm"), Some(6.0), "the destination's record is kept");
    let copied = merged.get(&format!("{:064x}", 7)).expect("get").expect("present");
    assert!(copied.metric("unknown").is_some_and(f64::is_nan));

    // Merging again changes nothing: everything is a duplicate or the same conflict.
    let again = merged.merge_from(&path_b).expect("merge again");
    assert_eq!((again.inserted, again.duplicates, again.conflicts.len()), (0, 5, 1));
    assert_eq!(merged.len().expect("len"), 9);
}

#[test]
fn a_status_change_is_a_conflict() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let mut failed = record(1, 3.0);
    failed.status = Status::Failed;
    failed.metrics.clear();
    failed.reason = Some("mesh failure".into());
    let path_a = store_with(directory.path(), "a.mrbrake", &[record(1, 3.0)]);
    let path_b = store_with(directory.path(), "b.mrbrake", &[failed]);
    let mut merged = Store::open(&path_a).expect("open");
    let summary = merged.merge_from(&path_b).expect("merge");
    assert_eq!(summary.conflicts, vec![format!("{:064x}", 1)]);
    assert_eq!(summary.inserted + summary.duplicates, 0);
}

#[test]
fn shards_merged_in_any_order_hold_the_same_set() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let all: Vec<Record> = (0..20).map(|index| record(index, f64::from(index))).collect();
    let shard_paths: Vec<PathBuf> = (0..3)
        .map(|shard| {
            let records: Vec<Record> = all.iter().skip(shard).step_by(3).cloned().collect();
            store_with(directory.path(), &format!("shard-{shard}.mrbrake"), &records)
        })
        .collect();
    let mut forward = Store::create(&directory.path().join("forward.mrbrake")).expect("create");
    let mut backward = Store::create(&directory.path().join("backward.mrbrake")).expect("create");
    for path in &shard_paths {
        assert!(forward.merge_from(path).expect("merge").conflicts.is_empty());
    }
    for path in shard_paths.iter().rev() {
        assert!(backward.merge_from(path).expect("merge").conflicts.is_empty());
    }
    let as_set = |store: &Store| keys(store).into_iter().collect::<HashSet<_>>();
    assert_eq!(as_set(&forward), as_set(&backward));
    assert_eq!(forward.len().expect("len"), all.len());
    for record in &all {
        let stored = forward.get(&record.key).expect("get").expect("present");
        assert_eq!(stored.variables, record.variables);
    }
}

#[test]
fn merging_a_store_into_itself_is_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = store_with(directory.path(), "self.mrbrake", &[record(1, 1.0)]);
    let mut store = Store::open(&path).expect("open");
    let error = store.merge_from(&path).expect_err("self merge");
    assert!(matches!(error, StoreError::Conflict { .. }), "{error:?}");
    assert!(error.is_input_error());
}

#[test]
fn creation_times_are_kept_by_a_merge() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path_a = store_with(directory.path(), "a.mrbrake", &[record(1, 1.0)]);
    let path_b = directory.path().join("b.mrbrake");
    Store::create(&path_b).expect("create").merge_from(&path_a).expect("merge");
    let created = |path: &Path| -> f64 {
        rusqlite::Connection::open(path)
            .expect("raw connection")
            .query_row("SELECT created_unix_s FROM evaluations", [], |row| row.get(0))
            .expect("created_unix_s")
    };
    assert_eq!(created(&path_a).to_bits(), created(&path_b).to_bits());
}

#[test]
fn a_merged_source_is_unchanged_and_its_side_files_go_with_the_next_writer() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let source = store_with(directory.path(), "source.mrbrake", &[record(1, 1.0), record(2, 2.0)]);
    let before = std::fs::read(&source).expect("read source");
    let destination_directory = tempfile::tempdir().expect("temporary directory");
    let mut destination =
        Store::create(&destination_directory.path().join("merged.mrbrake")).expect("create");
    assert_eq!(destination.merge_from(&source).expect("merge").inserted, 2);
    assert_eq!(std::fs::read(&source).expect("read source"), before, "merge only reads");

    Store::open(&source).expect("reopen source").close().expect("close");
    let names: Vec<String> = std::fs::read_dir(directory.path())
        .expect("list")
        .map(|entry| entry.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["source.mrbrake".to_owned()]);
}

/// A store written before a metric was renamed merges with a newer store of the same designs
/// through the renaming: agreeing designs are duplicates (not conflicts), copied records carry
/// the current name and keep a valid checksum.
#[test]
fn a_renaming_applies_to_both_sides_before_comparing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let rename = |metrics: &mut [(String, mrbrake_store::MetricValue)]| {
        for (name, _) in metrics {
            if name == "torque_on_nm" {
                *name = "torque_on_Nm".into();
            }
        }
    };
    let renamed = |record: Record| {
        let mut record = record;
        rename(record.metrics.as_mut_slice());
        record
    };
    let old: Vec<Record> = (0..3).map(|index| record(index, 2.0)).collect();
    let new: Vec<Record> = (1..4).map(|index| renamed(record(index, 2.0))).collect();
    let path_old = store_with(directory.path(), "old.mrbrake", &old);
    let path_new = store_with(directory.path(), "new.mrbrake", &new);

    // Without the renaming every shared design differs by its metric names.
    let path_plain = store_with(directory.path(), "plain.mrbrake", &new);
    let mut plain = Store::open(&path_plain).expect("open");
    let summary = plain.merge_from(&path_old).expect("merge");
    assert_eq!(summary.conflicts.len(), 2, "{summary:?}");
    plain.close().expect("close");

    let path_into = store_with(directory.path(), "into.mrbrake", &new);
    let mut merged = Store::open(&path_into).expect("open");
    let summary = merged.merge_from_upgrading(&path_old, &rename).expect("merge");
    assert_eq!(
        summary,
        MergeSummary { inserted: 1, duplicates: 2, completed: 0, conflicts: vec![] }
    );
    let copied = merged.get(&format!("{:064x}", 0)).expect("get (checksum verified)");
    let copied = copied.expect("copied");
    assert_eq!(copied.metric("torque_on_Nm"), Some(2.0));
    assert_eq!(copied.metric("torque_on_nm"), None);
    // And the other way round: an old-name destination against a new-name source.
    let mut old_store = Store::open(&path_old).expect("open old");
    let summary = old_store.merge_from_upgrading(&path_new, &rename).expect("merge");
    assert_eq!(
        summary,
        MergeSummary { inserted: 1, duplicates: 2, completed: 0, conflicts: vec![] }
    );
}
