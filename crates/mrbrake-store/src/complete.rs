//! Completing a stored record with metrics computed later: [`Store::complete`].
//!
//! A study that asks for more metrics than a stored design holds (`--resume` with a longer metric
//! list) computes only the missing ones and completes the record. The completion is additive: the
//! stored metrics must all be kept, each with the same value (within
//! [`crate::MERGE_RELATIVE_TOLERANCE`]); the record keeps its place (`seq`), creation time,
//! variables and design, and takes the new status, reason, metrics, settings, run time and solver
//! version. A stored evaluation is thus never *changed*, only extended.

use rusqlite::{OptionalExtension, TransactionBehavior};

use crate::row::{insert_new, read_row, rewrite_outcome};
use crate::{MetricUpgrade, Record, Store, StoreError, values_agree};

impl Store {
    /// Stores `record` as the completion of the record stored under its key (module docs), or
    /// inserts it when the key is not stored. Returns `true` when the store changed. Fails with
    /// [`StoreError::InvalidRecord`] when `record` drops or changes a stored metric, or breaks the
    /// record contract; nothing is stored then.
    pub fn complete(&mut self, record: &Record) -> Result<bool, StoreError> {
        self.complete_upgrading(record, &|_| {})
    }

    /// [`Self::complete`] with the stored metrics renamed by `upgrade` before they are compared
    /// (as [`Self::merge_from_upgrading`]): a record stored under legacy metric names is completed
    /// by one under the current names, and is then stored under them.
    pub fn complete_upgrading(
        &mut self,
        record: &Record,
        upgrade: &MetricUpgrade<'_>,
    ) -> Result<bool, StoreError> {
        self.refuse_if_read_only()?;
        record.validate()?;
        let select = format!("{} WHERE key = ?1", self.select_records_sql());
        let path = self.path().to_owned();
        let sqlite = |error| crate::schema::sqlite_error(&path, error);
        let transaction = self
            .connection_mut()
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(sqlite)?;
        let row = transaction
            .prepare_cached(&select)
            .and_then(|mut statement| statement.query_row([&record.key], read_row).optional())
            .map_err(sqlite)?;
        let changed = match row {
            None => {
                let now = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0.0, |elapsed| elapsed.as_secs_f64());
                insert_new(&transaction, record, Some(now), true).map_err(sqlite)?
            }
            Some(row) => {
                let mut stored = row.decode().map_err(|(key, detail)| StoreError::Decode {
                    path: path.clone(),
                    key,
                    detail,
                })?;
                upgrade(&mut stored.record.metrics);
                check_completes(&stored.record, record)?;
                let completed = Record {
                    key: stored.record.key,
                    variables: stored.record.variables,
                    spec_toml: stored.record.spec_toml,
                    ..record.clone()
                };
                rewrite_outcome(&transaction, &completed, stored.created_unix_s, stored.verified)
                    .map_err(sqlite)?
            }
        };
        transaction.commit().map_err(sqlite)?;
        Ok(changed)
    }
}

/// `record` keeps every metric of `stored` with the same value.
fn check_completes(stored: &Record, record: &Record) -> Result<(), StoreError> {
    for (name, value) in &stored.metrics {
        let kept =
            record.metric_value(name).is_some_and(|new| new.agrees_with(*value, values_agree));
        if !kept {
            return Err(StoreError::InvalidRecord {
                key: record.key.clone(),
                detail: format!(
                    "a completion must keep the stored metric {name:?} = {value} (it has {})",
                    record.metric_value(name).map_or("none".to_owned(), |v| v.to_string())
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MetricValue, Status};

    fn record(key: char, metrics: Vec<(&str, MetricValue)>) -> Record {
        Record {
            key: key.to_string().repeat(64),
            status: Status::Ok,
            reason: None,
            variables: vec![("g".into(), 1e-3.into())],
            metrics: metrics.into_iter().map(|(n, v)| (n.to_owned(), v)).collect(),
            spec_toml: "[brake]\n".into(),
            eval_seconds: 1.0,
            solver_version: "test".into(),
            settings: Default::default(),
        }
    }

    /// A completion keeps the record's place and stored metrics, adds the new ones, and reads back
    /// verified after the store is reopened; dropping or changing a stored metric is refused.
    #[test]
    fn completion_extends_a_record_in_place_and_never_changes_a_stored_metric() {
        let directory = tempfile::tempdir().unwrap();
        let path = directory.path().join("s.mrbrake");
        let mut store = Store::create(&path).unwrap();
        store.insert(&record('a', vec![("torque", 2.0.into())])).unwrap();
        store.insert(&record('b', vec![("torque", 3.0.into())])).unwrap();
        let mut more = record('a', vec![("torque", 2.0.into())]);
        more.metrics.push(("bandwidth".into(), MetricValue::AtLeast(6283.0)));
        more.metrics.push(("t63_dir2".into(), MetricValue::NotApplicable));
        more.eval_seconds = 3.0;
        more.variables = vec![("other_name".into(), 1e-3.into())];
        assert!(store.complete(&more).unwrap());
        for bad in [
            record('a', vec![("bandwidth", MetricValue::AtLeast(6283.0))]),
            record('a', vec![("torque", 2.5.into()), ("bandwidth", MetricValue::AtLeast(6283.0))]),
        ] {
            let error = store.complete(&bad).unwrap_err();
            assert!(matches!(error, StoreError::InvalidRecord { .. }), "{error}");
        }
        assert!(store.complete(&record('c', vec![("torque", 1.0.into())])).unwrap(), "inserted");
        drop(store);
        let store = Store::open(&path).unwrap();
        let records = store.records().unwrap();
        let keys: Vec<char> = records.iter().map(|r| r.key.chars().next().unwrap()).collect();
        assert_eq!(keys, ['a', 'b', 'c'], "the completed record keeps its place");
        assert_eq!(records[0].metric("torque"), Some(2.0));
        assert_eq!(records[0].metric_value("bandwidth"), Some(MetricValue::AtLeast(6283.0)));
        assert_eq!(records[0].metric_value("t63_dir2"), Some(MetricValue::NotApplicable));
        assert_eq!(records[0].variables[0].0, "g", "the stored variables are kept");
        assert!((records[0].eval_seconds - 3.0).abs() < 1e-12);
        assert_eq!(store.unverified_len().unwrap(), 0);
    }

    /// A record stored under a legacy metric name is completed through the renaming.
    #[test]
    fn completion_through_a_renaming_keeps_the_renamed_metric() {
        let directory = tempfile::tempdir().unwrap();
        let mut store = Store::create(&directory.path().join("s.mrbrake")).unwrap();
        store.insert(&record('a', vec![("torque_nm", 2.0.into())])).unwrap();
        let rename = |metrics: &mut [(String, MetricValue)]| {
            for (name, _) in metrics {
                if name == "torque_nm" {
                    *name = "torque_Nm".into();
                }
            }
        };
        let more = record('a', vec![("torque_Nm", 2.0.into()), ("t63", 1e-3.into())]);
        assert!(store.complete(&more).is_err(), "without the renaming a metric is dropped");
        assert!(store.complete_upgrading(&more, &rename).unwrap());
        let back = store.get(&more.key).unwrap().unwrap();
        assert_eq!((back.metric("torque_Nm"), back.metric("torque_nm")), (Some(2.0), None));
    }
}
