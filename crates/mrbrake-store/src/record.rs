//! One stored evaluation: [`Record`] and its [`Status`].
//!
//! A record is keyed by the SHA-256 of the canonical design, computed by the caller; the store
//! only checks that the key has the right shape (64 lowercase hexadecimal digits) and that the
//! variable and metric names are non-empty and unique, so the JSON objects of the exports are
//! well defined. A design variable is a number (SI) or, for a categorical variable (a material out
//! of a list), the chosen level by name ([`VariableValue`]).

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

/// The value of a design variable: a number in SI units, or a level of a categorical variable by
/// name (e.g. the material `pom`). Stored as a JSON number or string, so an export shows the level
/// by name.
#[derive(Debug, Clone, PartialEq)]
pub enum VariableValue {
    /// A numeric variable's value (SI).
    Number(f64),
    /// A categorical variable's level, by name.
    Level(String),
}

impl VariableValue {
    /// The number, for a numeric variable.
    pub fn as_number(&self) -> Option<f64> {
        match self {
            Self::Number(x) => Some(*x),
            Self::Level(_) => None,
        }
    }

    /// The level's name, for a categorical variable.
    pub fn as_level(&self) -> Option<&str> {
        match self {
            Self::Number(_) => None,
            Self::Level(name) => Some(name),
        }
    }

    /// The value as the exports write it: a JSON number (non-finite ones as `"NaN"`, `"inf"`,
    /// `"-inf"`) or the level's name as a string.
    pub fn to_json(&self) -> serde_json::Value {
        crate::named_values::variable_to_json(self)
    }
}

impl From<f64> for VariableValue {
    fn from(value: f64) -> Self {
        Self::Number(value)
    }
}

impl fmt::Display for VariableValue {
    /// A number in Rust's shortest round-trip form (as the CSV export writes it), a level as its
    /// name.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Number(x) => write!(f, "{x}"),
            Self::Level(name) => f.write_str(name),
        }
    }
}

/// A stored metric: a value, or what is known of a value the analysis did not resolve. Analyses
/// cover a finite range (a simulated window, a frequency grid): a release not reached within the
/// window is *at least* the window's length, a bandwidth above the highest frequency analysed is
/// *at least* that frequency. Such a bound is kept as a bound, never as an infinity, so a
/// constraint or an objective can use what it says (see `mrbrake_explore::problem`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MetricValue {
    /// The metric's value (NaN and ±inf only in records written before bounds were typed).
    Value(f64),
    /// Beyond the analysed range: at least this bound.
    AtLeast(f64),
    /// Beyond the analysed range: at most this bound.
    AtMost(f64),
    /// The metric does not apply to this design (e.g. a second direction of a one-way brake);
    /// stored so that a resumed study knows it was computed.
    NotApplicable,
}

impl MetricValue {
    /// The value, when it is one (`None` for a bound or a metric that does not apply).
    pub fn value(self) -> Option<f64> {
        match self {
            Self::Value(x) => Some(x),
            _ => None,
        }
    }

    /// The value or the bound (`None` for a metric that does not apply).
    pub fn number(self) -> Option<f64> {
        match self {
            Self::Value(x) | Self::AtLeast(x) | Self::AtMost(x) => Some(x),
            Self::NotApplicable => None,
        }
    }

    /// The kind of a non-value as the exports name it: `at_least`, `at_most`, `not_applicable`
    /// (`None` for a value).
    pub fn bound_kind(self) -> Option<&'static str> {
        match self {
            Self::Value(_) => None,
            Self::AtLeast(_) => Some("at_least"),
            Self::AtMost(_) => Some("at_most"),
            Self::NotApplicable => Some("not_applicable"),
        }
    }

    /// True when `self` and `other` say the same thing, numbers compared with `agree`.
    pub fn agrees_with(self, other: Self, agree: impl Fn(f64, f64) -> bool) -> bool {
        match (self, other) {
            (Self::Value(a), Self::Value(b))
            | (Self::AtLeast(a), Self::AtLeast(b))
            | (Self::AtMost(a), Self::AtMost(b)) => agree(a, b),
            (Self::NotApplicable, Self::NotApplicable) => true,
            _ => false,
        }
    }
}

impl From<f64> for MetricValue {
    fn from(value: f64) -> Self {
        Self::Value(value)
    }
}

impl fmt::Display for MetricValue {
    /// A value as the CSV export writes it (`{}`), a bound as `>=x` / `<=x`, `n/a` for a metric
    /// that does not apply.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Value(x) => write!(f, "{x}"),
            Self::AtLeast(x) => write!(f, ">={x}"),
            Self::AtMost(x) => write!(f, "<={x}"),
            Self::NotApplicable => f.write_str("n/a"),
        }
    }
}

/// The texts a level may not take: the store writes non-finite numbers as these strings.
pub(crate) const RESERVED_LEVELS: [&str; 3] = ["NaN", "inf", "-inf"];

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
    /// The varied design variables as `(name, value)`, a number (SI) or a categorical variable's
    /// level, in the caller's order (kept on read).
    pub variables: Vec<(String, VariableValue)>,
    /// The results as `(name, value)`, in the caller's order (kept on read); normally empty unless
    /// the status is [`Status::Ok`]. A value may be a bound beyond the analysed range or mark a
    /// metric that does not apply ([`MetricValue`]). Non-finite values (NaN, ±inf) are stored
    /// faithfully.
    pub metrics: Vec<(String, MetricValue)>,
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
    /// Looks up a metric's value by name (`None` when absent, a bound or not applicable: see
    /// [`Self::metric_value`]).
    pub fn metric(&self, name: &str) -> Option<f64> {
        self.metric_value(name).and_then(MetricValue::value)
    }

    /// Looks up a metric by name: its value, bound or "not applicable".
    pub fn metric_value(&self, name: &str) -> Option<MetricValue> {
        self.metrics.iter().find(|(candidate, _)| candidate == name).map(|&(_, value)| value)
    }

    /// Looks up a numeric design variable by name (`None` for a categorical one: see
    /// [`Self::variable_value`]).
    pub fn variable(&self, name: &str) -> Option<f64> {
        self.variable_value(name).and_then(VariableValue::as_number)
    }

    /// Looks up a design variable's value, numeric or categorical, by name.
    pub fn variable_value(&self, name: &str) -> Option<&VariableValue> {
        self.variables.iter().find(|(candidate, _)| candidate == name).map(|(_, value)| value)
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
        let variables = self.variables.iter().map(|(name, _)| name);
        let metrics = self.metrics.iter().map(|(name, _)| name);
        for (list, names) in
            [("variable", variables.collect::<Vec<_>>()), ("metric", metrics.collect())]
        {
            let mut seen = HashSet::new();
            for name in names {
                if name.is_empty() {
                    return Err(invalid(format!("a {list} has an empty name")));
                }
                if !seen.insert(name.as_str()) {
                    return Err(invalid(format!("{list} {name:?} appears twice")));
                }
            }
        }
        for (name, value) in &self.variables {
            if let VariableValue::Level(level) = value
                && (level.trim().is_empty() || RESERVED_LEVELS.contains(&level.as_str()))
            {
                return Err(invalid(format!(
                    "variable {name:?}: the level {level:?} is not a name (empty, or the text of a \
                     non-finite number)"
                )));
            }
        }
        Ok(())
    }
}

/// True when `key` has the shape of a design key: exactly 64 lowercase hexadecimal digits.
pub fn is_design_key(key: &str) -> bool {
    key.len() == KEY_HEX_DIGITS && key.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(key: &str) -> Record {
        Record {
            key: key.to_owned(),
            status: Status::Ok,
            reason: None,
            variables: vec![("gap".into(), 1e-3.into()), ("bobbin".into(), level("pom"))],
            metrics: vec![("torque".into(), 3.1.into()), ("t63".into(), MetricValue::AtLeast(0.2))],
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
        repeated.metrics.push(("torque".into(), 2.0.into()));
        assert!(repeated.validate().is_err());
        let mut empty = record(&"0".repeat(64));
        empty.variables.push((String::new(), 2.0.into()));
        assert!(empty.validate().is_err());
        for bad in ["", "NaN", "inf", "-inf"] {
            let mut record = record(&"0".repeat(64));
            record.variables[1].1 = level(bad);
            assert!(record.validate().is_err(), "{bad:?}");
        }
    }

    fn level(name: &str) -> VariableValue {
        VariableValue::Level(name.into())
    }

    #[test]
    fn lookups_by_name() {
        let record = record(&"0".repeat(64));
        assert_eq!(record.metric("torque"), Some(3.1));
        assert_eq!(record.variable("gap"), Some(1e-3));
        assert_eq!(record.metric("gap"), None);
        assert_eq!(record.metric("t63"), None, "a bound is not a value");
        assert_eq!(record.metric_value("t63"), Some(MetricValue::AtLeast(0.2)));
        assert_eq!(record.metric_value("t63").unwrap().to_string(), ">=0.2");
        assert_eq!(record.variable("bobbin"), None, "a level is not a number");
        assert_eq!(record.variable_value("bobbin").and_then(VariableValue::as_level), Some("pom"));
        assert_eq!(record.variable_value("bobbin").unwrap().to_string(), "pom");
    }
}
