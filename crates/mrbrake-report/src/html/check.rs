//! Checks a page against its JSON document: every numeric cell that names a JSON value
//! (`data-json` pointer, `data-scale`) must show that value times the scale, rounded to the digits
//! it displays. The tests of every report (and of the CLI) run it, so a table cannot drift from
//! `--json`.

use serde_json::Value;

/// Reads the value of attribute `name` inside the start tag `tag`.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let from = tag.find(&key)? + key.len();
    tag[from..].split('"').next()
}

/// A JSON number, or the results store's spelling of a non-finite one.
fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(n) => n.as_f64(),
        Value::Null => Some(f64::NAN),
        Value::String(s) if s == "NaN" => Some(f64::NAN),
        Value::String(s) if s == "inf" => Some(f64::INFINITY),
        Value::String(s) if s == "-inf" => Some(f64::NEG_INFINITY),
        _ => None,
    }
}

/// Checks every cell of `page` with a `data-json` attribute against `json`; returns how many were
/// checked, or the first disagreement.
pub fn numbers_agree(page: &str, json: &Value) -> Result<usize, String> {
    let mut checked = 0;
    let mut rest = page;
    while let Some(at) = rest.find(" data-json=\"") {
        let tag_start = rest[..at].rfind('<').ok_or("data-json outside a tag")?;
        let tag_end = at + rest[at..].find('>').ok_or("unterminated tag")?;
        let tag = &rest[tag_start..tag_end];
        let content_end = tag_end + rest[tag_end..].find('<').ok_or("unterminated cell")?;
        let shown = &rest[tag_end + 1..content_end];
        let pointer = attribute(tag, "data-json").ok_or("no pointer")?;
        let scale: f64 = attribute(tag, "data-scale")
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| format!("{pointer}: no data-scale"))?;
        let value = json
            .pointer(pointer)
            .and_then(as_number)
            .ok_or_else(|| format!("{pointer}: not a number in the JSON"))?;
        agree(pointer, shown, value * scale)?;
        checked += 1;
        rest = &rest[content_end..];
    }
    Ok(checked)
}

/// `shown` is `expected` rounded to the digits `shown` has.
fn agree(pointer: &str, shown: &str, expected: f64) -> Result<(), String> {
    let spelled = |s: &str| match s {
        "NaN" | super::writer::UNDEFINED => Some(f64::NAN),
        "inf" => Some(f64::INFINITY),
        "-inf" => Some(f64::NEG_INFINITY),
        _ => s.parse::<f64>().ok(),
    };
    let x = spelled(shown).ok_or_else(|| format!("{pointer}: '{shown}' is not a number"))?;
    if !x.is_finite() || !expected.is_finite() {
        let undefined = shown == super::writer::UNDEFINED && !expected.is_finite();
        let same = undefined || (x.is_nan() && expected.is_nan()) || x.total_cmp(&expected).is_eq();
        return if same {
            Ok(())
        } else {
            Err(format!("{pointer}: shows {shown}, JSON {expected}"))
        };
    }
    let decimals = shown.split_once('.').map_or(0, |(_, f)| f.len());
    let half_unit = 0.5 * 10f64.powi(-(decimals as i32));
    if (x - expected).abs() <= half_unit * (1.0 + 1e-9) + expected.abs() * 1e-12 {
        Ok(())
    } else {
        Err(format!("{pointer}: shows {shown}, JSON × scale = {expected}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn cells_are_checked_against_the_json() {
        let json = json!({ "a": { "r_m": 0.02551 }, "n": [1, "NaN"] });
        let good = "<tr><td class=\"num\" data-json=\"/a/r_m\" data-scale=\"1000\">25.51</td>\
                    <td data-json=\"/n/0\" data-scale=\"1\">1</td><td data-json=\"/n/1\" data-scale=\"1\">NaN</td></tr>";
        assert_eq!(numbers_agree(good, &json), Ok(3));
        let off = good.replace("25.51", "25.52");
        assert!(numbers_agree(&off, &json).unwrap_err().contains("/a/r_m: shows 25.52"));
        let missing = good.replace("/a/r_m", "/a/r");
        assert!(numbers_agree(&missing, &json).unwrap_err().contains("not a number"));
    }
}
