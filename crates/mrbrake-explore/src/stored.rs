//! Results stores read and merged under the current metric names: the one place a store written
//! before the unit convention (docs/CONVENTIONS.md) is upgraded, for every front end.
//!
//! Brief overview: [`read_records`] returns a store's records with legacy metric names renamed
//! ([`crate::evaluate::LEGACY_METRIC_NAMES`]), as `mrbrake export`, the study report and the
//! Python `store.load` show them; [`merge_into`] merges another store with the same renaming
//! applied to both sides before they are compared (`mrbrake merge`). The store itself is never
//! rewritten by a read.

use std::path::Path;

use mrbrake_store::{MergeSummary, Record, Store};

use crate::ExploreError;
use crate::evaluate::{upgrade_metric_list, upgrade_metric_names};

/// Every record of `store`, in insertion order, under the current metric names.
pub fn read_records(store: &Store) -> Result<Vec<Record>, ExploreError> {
    let mut records = store.records()?;
    records.iter_mut().for_each(upgrade_metric_names);
    Ok(records)
}

/// The record of `key` in `store` under the current metric names, if stored.
pub fn read_record(store: &Store, key: &str) -> Result<Option<Record>, ExploreError> {
    let mut record = store.get(key)?;
    record.iter_mut().for_each(upgrade_metric_names);
    Ok(record)
}

/// Merges the store at `input` into `store` ([`Store::merge_from_upgrading`]) with the metrics
/// of both sides under their current names, so a store written before a renaming agrees with a
/// newer store of the same designs and the merged store holds current names only.
pub fn merge_into(store: &mut Store, input: &Path) -> Result<MergeSummary, ExploreError> {
    Ok(store.merge_from_upgrading(input, &upgrade_metric_list)?)
}

#[cfg(test)]
mod tests {
    use mrbrake_store::Status;

    use super::*;

    fn record(key: char, metrics: &[(&str, f64)]) -> Record {
        Record {
            key: key.to_string().repeat(64),
            status: Status::Ok,
            reason: None,
            variables: vec![("g".into(), 1.0.into())],
            metrics: metrics.iter().map(|(n, v)| (n.to_string(), (*v).into())).collect(),
            spec_toml: String::new(),
            eval_seconds: 0.0,
            solver_version: "test".into(),
            settings: serde_json::Map::new(),
        }
    }

    /// A store written with legacy names reads, and merges, under the current ones.
    #[test]
    fn legacy_metric_names_read_and_merge_as_current_ones() {
        let dir = tempfile::tempdir().unwrap();
        let (old_path, new_path) = (dir.path().join("old.sqlite"), dir.path().join("new.sqlite"));
        let mut old = Store::open_or_create(&old_path, false).unwrap();
        old.insert(&record('a', &[("power_w", 3.0), ("torque_Nm", 1.0)])).unwrap();
        let records = read_records(&old).unwrap();
        let names: Vec<&str> = records[0].metrics.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["power_W", "torque_Nm"]);
        let key = "a".repeat(64);
        assert_eq!(read_record(&old, &key).unwrap().unwrap().metrics[0].0, "power_W");
        drop(old);
        let mut new = Store::open_or_create(&new_path, false).unwrap();
        new.insert(&record('a', &[("power_W", 3.0), ("torque_Nm", 1.0)])).unwrap();
        let summary = merge_into(&mut new, &old_path).unwrap();
        assert_eq!((summary.inserted, summary.duplicates, summary.conflicts.len()), (0, 1, 0));
    }
}
