//! Merging stores: [`Store::merge_from`] and its [`MergeSummary`].
//!
//! Shards of one study (`--shard K/N`) each fill their own store; merging copies every record
//! whose key is absent. A key present on both sides is a *duplicate* when the two evaluations
//! agree (same status, same metric names, every metric within a relative
//! [`MERGE_RELATIVE_TOLERANCE`]) or when the destination's record already holds every metric of
//! the incoming one with the same value; it is *completed* when the incoming record holds every
//! metric of the destination's with the same value, and more (the same design evaluated by a
//! study that asked for more metrics): the destination's record then holds the union, as
//! [`Store::complete`] would store it (its place, creation time, variables and design kept, the
//! outcome of the record with more metrics). The record with fewer metrics must be `ok` or have
//! the other's status. Any other key on both sides is a *conflict* — a value that differs, a
//! static failure against a success, or each side holding metrics the other lacks (which is
//! also how one metric under two names looks) — and the destination's record is kept. The whole merge is one transaction: it lands completely or not at
//! all.
//!
//! Metric names may have changed between the versions that wrote two stores (see
//! `mrbrake_explore::evaluate::LEGACY_METRIC_NAMES`); [`Store::merge_from_upgrading`] takes the
//! renaming, which this crate does not know, and applies it to both sides before comparing.

use std::path::Path;

use rusqlite::{OptionalExtension, TransactionBehavior};

use crate::named_values;
use crate::row::{StoredRecord, insert_new, read_row, rewrite_outcome};
use crate::{MetricValue, Record, Status, Store, StoreError};

/// Relative tolerance under which two values of the same metric count as equal in a merge:
/// `|a - b| <= 1e-9 * max(|a|, |b|)`. NaN equals NaN and an infinity equals the same infinity.
/// Two runs of the same design and solver differ at most by floating-point summation order,
/// far below this.
pub const MERGE_RELATIVE_TOLERANCE: f64 = 1e-9;

/// What [`Store::merge_from`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MergeSummary {
    /// Records copied because their key was absent.
    pub inserted: usize,
    /// Records whose key was present with an agreeing evaluation (not copied).
    pub duplicates: usize,
    /// Records whose key was present with fewer metrics, completed with the incoming ones
    /// (module docs).
    pub completed: usize,
    /// Keys present on both sides with a different status or different metrics (not copied; the
    /// destination's record is kept), in the source's insertion order.
    pub conflicts: Vec<String>,
}

impl Store {
    /// Copies into this store every record of the store at `other` whose key is absent here,
    /// in `other`'s insertion order and keeping its creation times.
    ///
    /// `other` is opened read-only with the same checks as [`Store::open`] (so a corrupt, foreign
    /// or newer-schema file is refused and left untouched). Meta data is not merged; compare it
    /// first with [`Store::open_read_only`] and [`Store::meta`] if the stores must belong to the
    /// same study. Merging a store into itself fails with [`StoreError::Conflict`].
    pub fn merge_from(&mut self, other: &Path) -> Result<MergeSummary, StoreError> {
        self.merge_from_upgrading(other, &|_| {})
    }

    /// [`Store::merge_from`], with `upgrade` applied to the metrics of both records of a key
    /// before they are compared, and to every record copied in. `upgrade` renames metrics written
    /// under an older name to the current one, so that a store written before a renaming agrees
    /// with a newer store of the same designs (instead of every shared design being a conflict)
    /// and the merged store holds current names only.
    pub fn merge_from_upgrading(
        &mut self,
        other: &Path,
        upgrade: &MetricUpgrade<'_>,
    ) -> Result<MergeSummary, StoreError> {
        self.refuse_if_read_only()?;
        if is_same_file(self.path(), other) {
            return Err(StoreError::Conflict {
                path: self.path().to_owned(),
                other: other.to_owned(),
                detail: "they are the same file".to_owned(),
            });
        }
        let source = Store::open_read_only(other)?;
        let select_one = format!("{} WHERE key = ?1", self.select_records_sql());
        let self_path = self.path().to_owned();
        let write_error = |error| crate::schema::sqlite_error(&self_path, error);

        let mut summary = MergeSummary::default();
        let transaction = self
            .connection_mut()
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(write_error)?;
        {
            let mut rows = source
                .connection()
                .prepare(&format!("{} ORDER BY seq", source.select_records_sql()))
                .map_err(|error| source.sqlite_error(error))?;
            let rows = rows.query_map([], read_row).map_err(|error| source.sqlite_error(error))?;
            for row in rows {
                let row = row.map_err(|error| source.sqlite_error(error))?;
                let mut incoming = source.decode(row)?;
                upgrade(&mut incoming.record.metrics);
                let existing =
                    existing_outcome(&transaction, &incoming.record.key).map_err(write_error)?;
                match existing {
                    None => {
                        insert_new(
                            &transaction,
                            &incoming.record,
                            incoming.created_unix_s,
                            incoming.verified,
                        )
                        .map_err(write_error)?;
                        summary.inserted += 1;
                    }
                    Some((status, mut metrics)) => {
                        upgrade(&mut metrics);
                        let agrees = status == incoming.record.status
                            && metrics_agree(&metrics, &incoming.record.metrics);
                        if agrees {
                            summary.duplicates += 1;
                            continue;
                        }
                        let stored = stored_record(&transaction, &select_one, &incoming.record.key)
                            .map_err(write_error)?;
                        let relation = stored.map_or(Relation::Conflict, |mut stored| {
                            upgrade(&mut stored.record.metrics);
                            relate(stored, &incoming.record)
                        });
                        match relation {
                            Relation::Holds => summary.duplicates += 1,
                            Relation::Completes(record, created, verified) => {
                                rewrite_outcome(&transaction, &record, created, verified)
                                    .map_err(write_error)?;
                                summary.completed += 1;
                            }
                            Relation::Conflict => {
                                summary.conflicts.push(incoming.record.key.clone());
                            }
                        }
                    }
                }
            }
        }
        transaction.commit().map_err(write_error)?;
        Ok(summary)
    }
}

/// A renaming of metrics applied in place to a record's `(name, value)` list (see
/// [`Store::merge_from_upgrading`]).
pub type MetricUpgrade<'a> = dyn Fn(&mut [(String, MetricValue)]) + 'a;

/// Status and metrics of a stored record.
type StoredOutcome = (Status, Vec<(String, MetricValue)>);

/// Status and metrics of the record stored under `key`, if any. A stored row that cannot be
/// decoded counts as a conflict (status `Failed`, no metrics would rarely match).
fn existing_outcome(
    transaction: &rusqlite::Transaction<'_>,
    key: &str,
) -> rusqlite::Result<Option<StoredOutcome>> {
    let row: Option<(String, String)> = transaction
        .prepare_cached("SELECT status, metrics FROM evaluations WHERE key = ?1")?
        .query_row([key], |row| Ok((row.get(0)?, row.get(1)?)))
        .optional()?;
    Ok(row.map(|(status, metrics)| {
        (
            status.parse().unwrap_or(Status::Failed),
            named_values::decode(&metrics).unwrap_or_default(),
        )
    }))
}

/// How an incoming record relates to the destination's record of the same key (module docs).
enum Relation {
    /// The destination already holds every incoming metric with the same value.
    Holds,
    /// The union of both, to store in place (with the stored creation time and verification).
    Completes(Box<Record>, Option<f64>, bool),
    /// A metric differs, or the statuses cannot be reconciled.
    Conflict,
}

/// The destination's record of `key`, decoded; `None` when it cannot be decoded (a conflict: it
/// cannot be extended).
fn stored_record(
    transaction: &rusqlite::Transaction<'_>,
    select_one: &str,
    key: &str,
) -> rusqlite::Result<Option<StoredRecord>> {
    let row = transaction
        .prepare_cached(select_one)
        .and_then(|mut statement| statement.query_row([key], read_row).optional())?;
    Ok(row.and_then(|row| row.decode().ok()))
}

/// The relation of `incoming` to the `stored` record of its key (module docs), whose statuses or
/// metric names differ (equal ones are duplicates before this is asked).
fn relate(stored: StoredRecord, incoming: &Record) -> Relation {
    let held = |record: &Record, name: &str| record.metric_value(name);
    let shared_agree = incoming.metrics.iter().all(|(name, value)| {
        held(&stored.record, name).is_none_or(|s| s.agrees_with(*value, values_agree))
    });
    if !shared_agree {
        return Relation::Conflict;
    }
    let extra = incoming.metrics.iter().any(|(name, _)| held(&stored.record, name).is_none());
    let stored_has_more =
        stored.record.metrics.iter().any(|(name, _)| held(incoming, name).is_none());
    // The record with fewer metrics must be `ok` (a study that asked for less) or have the
    // outcome of the one with more: a static failure is not completed by a success.
    let extends =
        |fewer: &Record, more: &Record| fewer.status == Status::Ok || fewer.status == more.status;
    match (extra, stored_has_more) {
        (false, true) if extends(incoming, &stored.record) => Relation::Holds,
        // The incoming record completes the stored one (as `Store::complete`).
        (true, false) if extends(&stored.record, incoming) => Relation::Completes(
            Box::new(Record {
                key: stored.record.key,
                variables: stored.record.variables,
                spec_toml: stored.record.spec_toml,
                ..incoming.clone()
            }),
            stored.created_unix_s,
            stored.verified,
        ),
        // Each has metrics the other lacks (e.g. the same metric under two names), the same
        // names with different statuses, or a failure against a success.
        _ => Relation::Conflict,
    }
}

/// True when both lists hold the same metric names (in any order) with agreeing values.
pub fn metrics_agree(a: &[(String, MetricValue)], b: &[(String, MetricValue)]) -> bool {
    a.len() == b.len()
        && a.iter().all(|(name, value)| {
            b.iter()
                .find(|(other_name, _)| other_name == name)
                .is_some_and(|(_, other)| value.agrees_with(*other, values_agree))
        })
}

/// `|a - b| <= MERGE_RELATIVE_TOLERANCE * max(|a|, |b|)`, with NaN equal to NaN and each infinity
/// equal only to itself.
pub fn values_agree(a: f64, b: f64) -> bool {
    if a.is_nan() || b.is_nan() {
        return a.is_nan() && b.is_nan();
    }
    if a.is_infinite() || b.is_infinite() {
        return a.is_infinite() && b.is_infinite() && a.is_sign_positive() == b.is_sign_positive();
    }
    (a - b).abs() <= MERGE_RELATIVE_TOLERANCE * a.abs().max(b.abs())
}

/// True when both paths name the same file (same device and inode on Unix, same canonical path
/// elsewhere); false when either cannot be inspected (the open then reports the problem).
fn is_same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_agree_within_relative_tolerance_only() {
        assert!(values_agree(1.0, 1.0 + 0.5e-9));
        assert!(!values_agree(1.0, 1.0 + 2e-9));
        assert!(values_agree(0.0, 0.0));
        assert!(values_agree(0.0, -0.0));
        assert!(!values_agree(0.0, 1e-300), "purely relative: any non-zero differs from zero");
        assert!(values_agree(f64::NAN, f64::NAN));
        assert!(!values_agree(f64::NAN, 1.0));
        assert!(values_agree(f64::INFINITY, f64::INFINITY));
        assert!(!values_agree(f64::INFINITY, f64::NEG_INFINITY));
        assert!(!values_agree(f64::INFINITY, f64::MAX));
    }

    #[test]
    fn metrics_agree_ignores_order_but_not_names() {
        let m = |pairs: &[(&str, f64)]| -> Vec<(String, MetricValue)> {
            pairs.iter().map(|&(n, v)| (n.to_owned(), v.into())).collect()
        };
        let a = m(&[("t", 1.0), ("v", 2.0)]);
        let reordered = m(&[("v", 2.0), ("t", 1.0)]);
        let renamed = m(&[("t", 1.0), ("w", 2.0)]);
        let shorter = m(&[("t", 1.0)]);
        let mut bounded = a.clone();
        bounded[1].1 = MetricValue::AtLeast(2.0);
        assert!(metrics_agree(&a, &reordered));
        assert!(!metrics_agree(&a, &renamed));
        assert!(!metrics_agree(&a, &shorter));
        assert!(!metrics_agree(&shorter, &a));
        assert!(!metrics_agree(&a, &bounded), "a bound is not the value");
        assert!(metrics_agree(&bounded, &bounded));
    }
}
