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

use std::collections::HashSet;

use crate::named_values::{value_to_json, variable_to_json};
use crate::{Record, StoreError};

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

fn cell(values: &[(String, f64)], name: &str) -> String {
    values
        .iter()
        .find(|(candidate, _)| candidate == name)
        .map(|(_, value)| format!("{value}"))
        .unwrap_or_default()
}

/// The records as CSV bytes (UTF-8, header row first, `\n` line ends); see the module docs for
/// the columns.
pub fn to_csv(records: &[Record]) -> Result<Vec<u8>, StoreError> {
    let variable_names =
        union_of_names(records, |record| record.variables.iter().map(|(n, _)| n.as_str()));
    let metric_names =
        union_of_names(records, |record| record.metrics.iter().map(|(n, _)| n.as_str()));
    let setting_names = setting_names(records);
    let mut writer =
        csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());

    let mut header = vec!["key", "status", "reason"];
    header.extend(&variable_names);
    header.extend(&metric_names);
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
        row.extend(metric_names.iter().map(|name| cell(&record.metrics, name)));
        row.extend(setting_names.iter().map(|name| setting_cell(record, name)));
        row.push(format!("{}", record.eval_seconds));
        row.push(record.solver_version.clone());
        writer.write_record(&row)?;
    }
    writer.into_inner().map_err(|error| StoreError::Csv(error.into_error().into()))
}

fn named_object(values: &[(String, f64)]) -> serde_json::Value {
    serde_json::Value::Object(
        values.iter().map(|(name, value)| (name.clone(), value_to_json(*value))).collect(),
    )
}

/// The records as a JSON array of objects
/// `{key, status, reason, variables: {name: value}, metrics: {name: value}, settings: {name: value},
/// eval_seconds, solver_version}` (the design TOML is left out; it is in the store). Non-finite values are the
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
            values.iter().map(|&(name, value)| (name.to_owned(), value)).collect()
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
