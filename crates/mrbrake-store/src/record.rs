//! One stored evaluation: [`Record`] and its [`Status`].
//!
//! A record is keyed by the SHA-256 of the canonical design, computed by the caller; the store
//! only checks that the key has the right shape (64 lowercase hexadecimal digits) and that the
//! variable and metric names are non-empty and unique, so the JSON objects of the exports are
//! well defined.

use std::collections::HashSet;
use std::fmt;
use std::str::FromStr;

use crate::StoreError;

/// Number of hexadecimal digits of a SHA-256 design key.
pub const KEY_HEX_DIGITS: usize = 64;

/// Outcome of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// The design was analysed; its metrics are stored.
    Ok,
    /// The design is invalid (impossible geometry, a violated hard limit); the reason is stored.
    Infeasible,
    /// The analysis itself failed (non-convergence, mesh failure); the reason is stored.
    Failed,
}

impl Status {
    /// All statuses, in the order of the schema's `CHECK` constraint.
    pub const ALL: [Status; 3] = [Status::Ok, Status::Infeasible, Status::Failed];

    /// The text stored in the `status` column: `"ok"`, `"infeasible"` or `"failed"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Infeasible => "infeasible",
            Status::Failed => "failed",
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Error of [`Status::from_str`]: the text is not one of `ok`, `infeasible`, `failed`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown evaluation status {0:?} (expected ok, infeasible or failed)")]
pub struct UnknownStatus(pub String);

impl FromStr for Status {
    type Err = UnknownStatus;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Status::ALL
            .into_iter()
            .find(|status| status.as_str() == text)
            .ok_or_else(|| UnknownStatus(text.to_owned()))
    }
}

/// One evaluation of one design, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// SHA-256 of the canonical design, 64 lowercase hexadecimal digits, computed by the caller.
    /// The store's primary key: a key is stored at most once and never overwritten.
    pub key: String,
    /// Outcome of the evaluation.
    pub status: Status,
    /// Why the design is infeasible or the evaluation failed; `None` for a successful evaluation.
    pub reason: Option<String>,
    /// The varied design variables as `(name, SI value)`, in the caller's order (kept on read).
    pub variables: Vec<(String, f64)>,
    /// The results as `(name, value)`, in the caller's order (kept on read); normally empty unless
    /// the status is [`Status::Ok`]. Non-finite values (NaN, ±inf) are stored faithfully.
    pub metrics: Vec<(String, f64)>,
    /// The full design as TOML, ready to analyse again.
    pub spec_toml: String,
    /// Wall-clock time of the evaluation in seconds. Kept in a SQLite `REAL` column, which stores
    /// NaN as `NULL` (read back as NaN) and does not keep the sign of zero.
    pub eval_seconds: f64,
    /// Version of the solver that produced the record.
    pub solver_version: String,
    /// The evaluation settings the caller records with the result (e.g. mesh level, element
    /// order, speed), so rows of merged stores with different settings can be told apart; empty
    /// for a record written before schema version 3. Kept in the `settings` column as a JSON
    /// object and covered by the checksum when present.
    pub settings: serde_json::Map<String, serde_json::Value>,
}

impl Record {
    /// Looks up a metric by name.
    pub fn metric(&self, name: &str) -> Option<f64> {
        find_named(&self.metrics, name)
    }

    /// Looks up a design variable by name.
    pub fn variable(&self, name: &str) -> Option<f64> {
        find_named(&self.variables, name)
    }

    /// Checks the record contract: the key is 64 lowercase hexadecimal digits, and the variable
    /// and metric names are non-empty and unique within their list.
    pub fn validate(&self) -> Result<(), StoreError> {
        let invalid = |detail: String| StoreError::InvalidRecord { key: self.key.clone(), detail };
        if !is_design_key(&self.key) {
            return Err(invalid(format!(
                "the key must be {KEY_HEX_DIGITS} lowercase hexadecimal digits (a SHA-256)"
            )));
        }
        for (list, values) in [("variable", &self.variables), ("metric", &self.metrics)] {
            let mut seen = HashSet::new();
            for (name, _) in values {
                if name.is_empty() {
                    return Err(invalid(format!("a {list} has an empty name")));
                }
                if !seen.insert(name.as_str()) {
                    return Err(invalid(format!("{list} {name:?} appears twice")));
                }
            }
        }
        Ok(())
    }
}

/// True when `key` has the shape of a design key: exactly 64 lowercase hexadecimal digits.
pub fn is_design_key(key: &str) -> bool {
    key.len() == KEY_HEX_DIGITS && key.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}

fn find_named(values: &[(String, f64)], name: &str) -> Option<f64> {
    values.iter().find(|(candidate, _)| candidate == name).map(|&(_, value)| value)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(key: &str) -> Record {
        Record {
            key: key.to_owned(),
            status: Status::Ok,
            reason: None,
            variables: vec![("gap".into(), 1e-3)],
            metrics: vec![("torque".into(), 3.1)],
            spec_toml: String::new(),
            eval_seconds: 0.3,
            solver_version: "test".into(),
            settings: Default::default(),
        }
    }

    #[test]
    fn status_text_round_trips_and_rejects_unknown() {
        for status in Status::ALL {
            assert_eq!(status.as_str().parse::<Status>(), Ok(status));
            assert_eq!(status.to_string(), status.as_str());
        }
        assert_eq!(
            "OK".parse::<Status>(),
            Err(UnknownStatus("OK".to_owned())),
            "statuses are case-sensitive, like the schema's CHECK constraint"
        );
    }

    #[test]
    fn key_shape_is_checked() {
        assert!(record(&"a".repeat(64)).validate().is_ok());
        for bad in ["", "abc", &"A".repeat(64), &"g".repeat(64), &"a".repeat(65)] {
            let error = record(bad).validate().expect_err(bad);
            assert!(matches!(error, StoreError::InvalidRecord { .. }), "{error}");
        }
    }

    #[test]
    fn repeated_or_empty_names_are_refused() {
        let mut repeated = record(&"0".repeat(64));
        repeated.metrics.push(("torque".into(), 2.0));
        assert!(repeated.validate().is_err());
        let mut empty = record(&"0".repeat(64));
        empty.variables.push((String::new(), 2.0));
        assert!(empty.validate().is_err());
    }

    #[test]
    fn lookups_by_name() {
        let record = record(&"0".repeat(64));
        assert_eq!(record.metric("torque"), Some(3.1));
        assert_eq!(record.variable("gap"), Some(1e-3));
        assert_eq!(record.metric("gap"), None);
    }
}
