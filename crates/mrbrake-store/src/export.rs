//! Exports of records to CSV and JSON, returned as bytes / values for the caller to write
//! (atomically, with `mrbrake_report::write_atomic`).
//!
//! CSV columns: `key,status,reason`, then every variable name in first-seen order over all
//! records (a categorical variable's cell holds its level's name), then every metric name in first-seen order, then every evaluation setting (mesh level,
//! element order, speed, … as the caller recorded them; empty for records written before schema
//! version 3), then `eval_seconds,solver_version`. A
//! record without a given variable or metric leaves the cell empty. Numbers use Rust's `{}`
//! formatting, the shortest decimal text that parses back to the same `f64` (NaN is `NaN`,
//! infinities `inf` / `-inf`). A name used both as a variable and as a metric gives two columns
//! with the same heading, variable first.
//!
//! A metric that is not a value ([`crate::MetricValue`]) has an empty cell in its column (as JSON
//! has `null`, docs/CONVENTIONS.md) and its bound in a column `<metric>_beyond`, right after the
//! metric columns, present only for metrics with such a record: `>=x` (beyond the analysed
//! range, at least x), `<=x` (at most x) or `n/a` (does not apply). The JSON export has the
//! metric `null` and the bound in `metric_bounds`: `{"at_least": x}`, `{"at_most": x}` or
//! `{"not_applicable": true}`.

use std::collections::HashSet;

use crate::named_values::{metric_to_json, value_to_json, variable_to_json};
use crate::{MetricValue, Record, StoreError};

/// Names in first-seen order over all records.
fn union_of_names<'a, I>(records: &'a [Record], list: impl Fn(&'a Record) -> I) -> Vec<&'a str>
where
    I: Iterator<Item = &'a str>,
{
    let mut seen = HashSet::new();
    let mut names = Vec::new();
    for record in records {
        for name in list(record) {
            if seen.insert(name) {
                names.push(name);
            }
        }
    }
    names
}

/// Setting names in first-seen order over all records.
fn setting_names(records: &[Record]) -> Vec<&str> {
    let mut seen = HashSet::new();
    let mut names = Vec::new();
    for name in records.iter().flat_map(|record| record.settings.keys()) {
        if seen.insert(name.as_str()) {
            names.push(name.as_str());
        }
    }
    names
}

/// A setting as a CSV cell: text as it is, other values as JSON, empty when absent.
fn setting_cell(record: &Record, name: &str) -> String {
    match record.settings.get(name) {
        None => String::new(),
        Some(serde_json::Value::String(text)) => text.clone(),
        Some(other) => other.to_string(),
    }
}

/// A metric's cell: its value, empty when absent or not a value.
fn cell(record: &Record, name: &str) -> String {
    record.metric(name).map(|value| format!("{value}")).unwrap_or_default()
}

/// A metric's `_beyond` cell: its bound (module docs), empty for a value or when absent.
fn beyond_cell(record: &Record, name: &str) -> String {
    match record.metric_value(name) {
        Some(
            value @ (MetricValue::AtLeast(_) | MetricValue::AtMost(_) | MetricValue::NotApplicable),
        ) => value.to_string(),
        _ => String::new(),
    }
}

/// The records as CSV bytes (UTF-8, header row first, `\n` line ends); see the module docs for
/// the columns.
pub fn to_csv(records: &[Record]) -> Result<Vec<u8>, StoreError> {
    let variable_names =
        union_of_names(records, |record| record.variables.iter().map(|(n, _)| n.as_str()));
    let metric_names =
        union_of_names(records, |record| record.metrics.iter().map(|(n, _)| n.as_str()));
    let bounded_names: Vec<&str> = metric_names
        .iter()
        .copied()
        .filter(|name| {
            records.iter().any(|r| r.metric_value(name).is_some_and(|v| v.value().is_none()))
        })
        .collect();
    let beyond_headers: Vec<String> =
        bounded_names.iter().map(|name| format!("{name}_beyond")).collect();
    let setting_names = setting_names(records);
    let mut writer =
        csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());

    let mut header = vec!["key", "status", "reason"];
    header.extend(&variable_names);
    header.extend(&metric_names);
    header.extend(beyond_headers.iter().map(String::as_str));
    header.extend(&setting_names);
    header.extend(["eval_seconds", "solver_version"]);
    writer.write_record(&header)?;

    for record in records {
        let mut row = vec![
            record.key.clone(),
            record.status.as_str().to_owned(),
            record.reason.clone().unwrap_or_default(),
        ];
        row.extend(
            variable_names.iter().map(|name| {
                record.variable_value(name).map(ToString::to_string).unwrap_or_default()
            }),
        );
        row.extend(metric_names.iter().map(|name| cell(record, name)));
        row.extend(bounded_names.iter().map(|name| beyond_cell(record, name)));
        row.extend(setting_names.iter().map(|name| setting_cell(record, name)));
        row.push(format!("{}", record.eval_seconds));
        row.push(record.solver_version.clone());
        writer.write_record(&row)?;
    }
    writer.into_inner().map_err(|error| StoreError::Csv(error.into_error().into()))
}

/// The metrics' values, `null` for a metric that is not a value.
fn named_object(values: &[(String, MetricValue)]) -> serde_json::Value {
    serde_json::Value::Object(
        values
            .iter()
            .map(|(name, value)| {
                (name.clone(), value.value().map_or(serde_json::Value::Null, value_to_json))
            })
            .collect(),
    )
}

/// The bounds of the metrics that are not values (module docs).
fn bounds_object(values: &[(String, MetricValue)]) -> serde_json::Value {
    serde_json::Value::Object(
        values
            .iter()
            .filter(|(_, value)| value.value().is_none())
            .map(|(name, value)| (name.clone(), metric_to_json(*value)))
            .collect(),
    )
}

/// The records as a JSON array of objects
/// `{key, status, reason, variables: {name: value}, metrics: {name: value}, metric_bounds: {name:
/// bound}, settings: {name: value}, eval_seconds, solver_version}` (the design TOML is left out;
/// it is in the store; `metric_bounds` and a metric's `null`: module docs). Non-finite values are the
/// strings `"NaN"`, `"inf"`, `"-inf"`; `reason` is `null` when absent. Object keys come out
/// sorted (serde_json's map), the array keeps the order of `records`.
pub fn to_json(records: &[Record]) -> serde_json::Value {
    serde_json::Value::Array(
        records
            .iter()
            .map(|record| {
                serde_json::json!({
                    "key": record.key,
                    "status": record.status.as_str(),
                    "reason": record.reason,
                    "variables": serde_json::Value::Object(
                        record
                            .variables
                            .iter()
                            .map(|(name, value)| (name.clone(), variable_to_json(value)))
                            .collect(),
                    ),
                    "metrics": named_object(&record.metrics),
                    "metric_bounds": bounds_object(&record.metrics),
                    "settings": record.settings,
                    "eval_seconds": value_to_json(record.eval_seconds),
                    "solver_version": record.solver_version,
                })
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Status;

    fn record(key_digit: char, variables: &[(&str, f64)], metrics: &[(&str, f64)]) -> Record {
        let named = |values: &[(&str, f64)]| {
            values.iter().map(|&(name, value)| (name.to_owned(), value.into())).collect()
        };
        let variables =
            variables.iter().map(|&(name, value)| (name.to_owned(), value.into())).collect();
        Record {
            key: key_digit.to_string().repeat(64),
            status: if metrics.is_empty() { Status::Infeasible } else { Status::Ok },
            reason: metrics.is_empty().then(|| "gap, below 0.1 mm, is too small".to_owned()),
            variables,
            metrics: named(metrics),
            spec_toml: "[brake]\n".into(),
            eval_seconds: 0.25,
            solver_version: "0.1.0".into(),
            settings: Default::default(),
        }
    }

    #[test]
    fn csv_has_union_columns_in_first_seen_order_and_empty_cells() {
        let records = [
            record('a', &[("g", 0.001), ("h", 0.005)], &[("torque", 3.5)]),
            record('b', &[("h", 0.006), ("n", 2.0)], &[]),
            record('c', &[("g", 1e-4)], &[("volume", f64::NAN), ("torque", f64::NEG_INFINITY)]),
        ];
        let text = String::from_utf8(to_csv(&records).expect("csv")).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "key,status,reason,g,h,n,torque,volume,eval_seconds,solver_version");
        assert_eq!(lines[1], format!("{},ok,,0.001,0.005,,3.5,,0.25,0.1.0", "a".repeat(64)));
        assert_eq!(
            lines[2],
            format!(
                "{},infeasible,\"gap, below 0.1 mm, is too small\",,0.006,2,,,0.25,0.1.0",
                "b".repeat(64)
            )
        );
        assert_eq!(lines[3], format!("{},ok,,0.0001,,,-inf,NaN,0.25,0.1.0", "c".repeat(64)));
        assert_eq!(lines.len(), 4);
    }

    #[test]
    fn a_categorical_variable_exports_by_name() {
        let mut r = record('e', &[("g", 0.001)], &[("torque", 3.5)]);
        r.variables.push(("materials.bobbin".into(), crate::VariableValue::Level("pom".into())));
        let text = String::from_utf8(to_csv(std::slice::from_ref(&r)).expect("csv")).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("key,status,reason,g,materials.bobbin,torque"), "{text}");
        assert!(lines[1].contains(",0.001,pom,3.5,"), "{text}");
        assert_eq!(to_json(&[r])[0]["variables"]["materials.bobbin"], "pom");
    }

    #[test]
    fn bounds_export_as_null_or_empty_with_the_bound_beside() {
        let mut a = record('a', &[("g", 0.001)], &[("torque", 3.5)]);
        a.metrics.push(("bandwidth".into(), MetricValue::AtLeast(6283.0)));
        a.metrics.push(("t63_dir2".into(), MetricValue::NotApplicable));
        let mut b = record('b', &[("g", 0.002)], &[("torque", 3.0), ("bandwidth", 900.0)]);
        b.metrics.push(("release".into(), MetricValue::AtMost(0.25)));
        let records = [a, b];
        let text = String::from_utf8(to_csv(&records).expect("csv")).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "key,status,reason,g,torque,bandwidth,t63_dir2,release,bandwidth_beyond,\
             t63_dir2_beyond,release_beyond,eval_seconds,solver_version"
        );
        assert!(lines[1].contains(",0.001,3.5,,,,>=6283,n/a,,0.25,"), "{text}");
        assert!(lines[2].contains(",0.002,3,900,,,,,<=0.25,0.25,"), "{text}");
        let json = to_json(&records);
        assert!(json[0]["metrics"]["bandwidth"].is_null());
        assert_eq!(json[0]["metric_bounds"]["bandwidth"]["at_least"], 6283.0);
        assert_eq!(json[0]["metric_bounds"]["t63_dir2"]["not_applicable"], true);
        assert_eq!(json[1]["metrics"]["bandwidth"], 900.0);
        assert_eq!(json[1]["metric_bounds"], serde_json::json!({"release": {"at_most": 0.25}}));
    }

    #[test]
    fn csv_of_no_records_is_the_fixed_header() {
        let text = String::from_utf8(to_csv(&[]).expect("csv")).expect("utf-8");
        assert_eq!(text, "key,status,reason,eval_seconds,solver_version\n");
    }

    #[test]
    fn json_objects_carry_non_finite_values_as_strings() {
        let records = [record('d', &[("g", 0.001)], &[("torque", 3.5), ("ratio", f64::INFINITY)])];
        let json = to_json(&records);
        let first = &json[0];
        assert_eq!(first["key"], "d".repeat(64));
        assert_eq!(first["status"], "ok");
        assert!(first["reason"].is_null());
        assert_eq!(first["variables"]["g"], 0.001);
        assert_eq!(first["metrics"]["torque"], 3.5);
        assert_eq!(first["metrics"]["ratio"], "inf");
        assert_eq!(first["eval_seconds"], 0.25);
        assert_eq!(first["solver_version"], "0.1.0");
    }
}
