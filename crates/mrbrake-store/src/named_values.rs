//! Text encoding of the `variables` and `metrics` columns: a JSON array of `[name, value]` pairs.
//! A categorical variable's value is its level as a JSON string (any text but the three below).
//!
//! An array of pairs (rather than a JSON object) keeps the caller's order, which a JSON object
//! read back through `serde_json` (without its `preserve_order` feature) would lose. JSON has no
//! NaN or infinity, so non-finite values are written as the strings `"NaN"`, `"inf"` and `"-inf"`;
//! finite values are written with the shortest digits that round-trip (serde_json uses `ryu`)
//! and read back with Rust's correctly rounded `f64::from_str`, so every value, including `-0.0`,
//! comes back bit for bit.
//!
//! A metric that is not a value ([`MetricValue`]) is a JSON object: `{"at_least": x}`,
//! `{"at_most": x}` (beyond the analysed range) or `{"not_applicable": true}` (schema version 4).

use serde_json::value::RawValue;

use crate::{MetricValue, VariableValue};

/// The JSON text of a non-finite value, or `None` when the value is finite.
pub(crate) fn non_finite_text(value: f64) -> Option<&'static str> {
    if value.is_nan() {
        Some("NaN")
    } else if value.is_infinite() {
        Some(if value > 0.0 { "inf" } else { "-inf" })
    } else {
        None
    }
}

/// A value as a JSON value: a number when finite, otherwise `"NaN"`, `"inf"` or `"-inf"`.
pub(crate) fn value_to_json(value: f64) -> serde_json::Value {
    match serde_json::Number::from_f64(value) {
        Some(number) => serde_json::Value::Number(number),
        None => serde_json::Value::String(non_finite_text(value).unwrap_or("NaN").to_owned()),
    }
}

/// A metric as stored: a value as [`value_to_json`], a bound or "not applicable" as an object.
pub(crate) fn metric_to_json(value: MetricValue) -> serde_json::Value {
    match value {
        MetricValue::Value(x) => value_to_json(x),
        MetricValue::AtLeast(x) => serde_json::json!({ "at_least": value_to_json(x) }),
        MetricValue::AtMost(x) => serde_json::json!({ "at_most": value_to_json(x) }),
        MetricValue::NotApplicable => serde_json::json!({ "not_applicable": true }),
    }
}

/// Encodes `(name, metric)` pairs as `[["name", value], ...]` (see the module docs).
pub(crate) fn encode(values: &[(String, MetricValue)]) -> String {
    let pairs: Vec<(&str, serde_json::Value)> =
        values.iter().map(|(name, value)| (name.as_str(), metric_to_json(*value))).collect();
    // Serialising strings and numbers into a String cannot fail.
    serde_json::to_string(&pairs).expect("a list of (string, number) pairs always serialises")
}

/// A variable's value as a JSON value: a number as [`value_to_json`], a level as its name.
pub(crate) fn variable_to_json(value: &VariableValue) -> serde_json::Value {
    match value {
        VariableValue::Number(x) => value_to_json(*x),
        VariableValue::Level(name) => serde_json::Value::String(name.clone()),
    }
}

/// Encodes design variables as `[["name", value], ...]`: numbers as [`encode`], levels as strings.
pub(crate) fn encode_variables(values: &[(String, VariableValue)]) -> String {
    let pairs: Vec<(&str, serde_json::Value)> =
        values.iter().map(|(name, value)| (name.as_str(), variable_to_json(value))).collect();
    serde_json::to_string(&pairs).expect("a list of (string, number or string) pairs serialises")
}

/// The `[name, value]` pairs of a column's text, values still raw.
fn pairs(text: &str) -> Result<Vec<(String, Box<RawValue>)>, String> {
    serde_json::from_str(text)
        .map_err(|error| format!("expected a JSON array of [name, value] pairs: {error}"))
}

/// Decodes the text written by [`encode`]; the error says what is wrong.
pub(crate) fn decode(text: &str) -> Result<Vec<(String, MetricValue)>, String> {
    pairs(text)?
        .into_iter()
        .map(|(name, raw)| {
            let value = decode_metric(raw.get()).ok_or_else(|| {
                format!("value of {name:?} is neither a number nor a bound: {}", raw.get())
            })?;
            Ok((name, value))
        })
        .collect()
}

/// A metric's stored JSON: a number (or a non-finite one's text), or one of the objects of the
/// module docs, with exactly one entry.
fn decode_metric(raw: &str) -> Option<MetricValue> {
    if !raw.trim_start().starts_with('{') {
        return decode_value(raw).map(MetricValue::Value);
    }
    let object: std::collections::BTreeMap<String, Box<RawValue>> =
        serde_json::from_str(raw).ok()?;
    let [(kind, inner)] = <[_; 1]>::try_from(object.into_iter().collect::<Vec<_>>()).ok()?;
    match kind.as_str() {
        "at_least" => decode_value(inner.get()).map(MetricValue::AtLeast),
        "at_most" => decode_value(inner.get()).map(MetricValue::AtMost),
        "not_applicable" if inner.get().trim() == "true" => Some(MetricValue::NotApplicable),
        _ => None,
    }
}

/// Decodes the text written by [`encode_variables`]: a number (or a non-finite one's text) is a
/// number, any other string a level; the error says what is wrong.
pub(crate) fn decode_variables(text: &str) -> Result<Vec<(String, VariableValue)>, String> {
    pairs(text)?
        .into_iter()
        .map(|(name, raw)| {
            let value = match decode_value(raw.get()) {
                Some(x) => VariableValue::Number(x),
                None => match serde_json::from_str::<String>(raw.get()) {
                    Ok(level) => VariableValue::Level(level),
                    Err(_) => {
                        return Err(format!(
                            "value of {name:?} is neither a number nor a level: {}",
                            raw.get()
                        ));
                    }
                },
            };
            Ok((name, value))
        })
        .collect()
}

fn decode_value(raw: &str) -> Option<f64> {
    match raw.trim() {
        "\"NaN\"" => Some(f64::NAN),
        "\"inf\"" => Some(f64::INFINITY),
        "\"-inf\"" => Some(f64::NEG_INFINITY),
        // A quoted string other than the three above, `null`, `true`, ... are refused; Rust's
        // parser accepts every JSON number form (sign, fraction, exponent with sign).
        number if number.starts_with(['-', '0', '1', '2', '3', '4', '5', '6', '7', '8', '9']) => {
            number.parse().ok()
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn same_bits(a: &[(String, f64)], b: &[(String, MetricValue)]) -> bool {
        a.len() == b.len()
            && a.iter().zip(b).all(|((na, va), (nb, vb))| {
                na == nb && vb.value().is_some_and(|vb| va.to_bits() == vb.to_bits())
            })
    }

    fn as_metrics(values: &[(String, f64)]) -> Vec<(String, MetricValue)> {
        values.iter().map(|(n, v)| (n.clone(), MetricValue::Value(*v))).collect()
    }

    #[test]
    fn bounds_and_not_applicable_are_objects() {
        let values = vec![
            ("bw".to_owned(), MetricValue::AtLeast(6283.0)),
            ("t".to_owned(), MetricValue::AtMost(1e-3)),
            ("dir2".to_owned(), MetricValue::NotApplicable),
            ("x".to_owned(), MetricValue::Value(2.0)),
        ];
        let text = encode(&values);
        assert_eq!(
            text,
            r#"[["bw",{"at_least":6283.0}],["t",{"at_most":0.001}],["dir2",{"not_applicable":true}],["x",2.0]]"#
        );
        assert_eq!(decode(&text).expect("decodes"), values);
        for bad in [
            r#"[["a", {}]]"#,
            r#"[["a", {"at_least": 1, "at_most": 2}]]"#,
            r#"[["a", {"at_least": "x"}]]"#,
            r#"[["a", {"not_applicable": false}]]"#,
            r#"[["a", {"above": 1}]]"#,
        ] {
            assert!(decode(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn non_finite_values_are_strings() {
        let values = vec![
            ("nan".to_owned(), f64::NAN),
            ("inf".to_owned(), f64::INFINITY),
            ("ninf".to_owned(), f64::NEG_INFINITY),
            ("neg_zero".to_owned(), -0.0),
            ("tiny".to_owned(), 5e-324),
        ];
        let text = encode(&as_metrics(&values));
        assert_eq!(
            text,
            r#"[["nan","NaN"],["inf","inf"],["ninf","-inf"],["neg_zero",-0.0],["tiny",5e-324]]"#
        );
        let back = decode(&text).expect("decodes");
        assert!(back[0].1.value().unwrap().is_nan());
        assert!(same_bits(&values[1..], &back[1..]));
    }

    #[test]
    fn variables_hold_numbers_and_levels() {
        let values = vec![
            ("g".to_owned(), VariableValue::Number(5e-4)),
            ("materials.bobbin".to_owned(), VariableValue::Level("pom".into())),
            ("n".to_owned(), VariableValue::Number(f64::INFINITY)),
        ];
        let text = encode_variables(&values);
        assert_eq!(text, r#"[["g",0.0005],["materials.bobbin","pom"],["n","inf"]]"#);
        assert_eq!(decode_variables(&text).expect("decodes"), values);
        // A numeric column still refuses a level, and a variable refuses what is neither.
        assert!(decode(&text).is_err());
        for bad in ["[[\"a\", null]]", "[[\"a\", true]]", "[[\"a\", [1]]]"] {
            assert!(decode_variables(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn malformed_text_is_refused_with_a_reason() {
        for bad in ["{}", "[[\"a\"]]", "[[\"a\", null]]", "[[\"a\", \"x\"]]", "[[\"a\", true]]"] {
            let error = decode(bad).expect_err(bad);
            assert!(!error.is_empty());
        }
        assert_eq!(decode("[]"), Ok(vec![]));
    }

    proptest! {
        /// Every finite f64 (any bit pattern) and any name survives encode/decode bit for bit.
        #[test]
        fn finite_values_round_trip_exactly(
            bits in proptest::collection::vec(any::<u64>(), 0..8),
            names in proptest::collection::vec("\\PC{0,12}", 8),
        ) {
            let values: Vec<(String, f64)> = bits
                .iter()
                .zip(&names)
                .map(|(&bits, name)| (name.clone(), f64::from_bits(bits)))
                .filter(|(_, value)| value.is_finite())
                .collect();
            let back = decode(&encode(&as_metrics(&values))).expect("decodes");
            prop_assert!(same_bits(&values, &back), "{values:?} != {back:?}");
        }
    }
}
