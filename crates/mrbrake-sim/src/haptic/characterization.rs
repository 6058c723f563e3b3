//! Host-side conversion of a characterisation JSON (the output of the identification) into the
//! controller's fixed-size [`InverseModel`].
//!
//! Expected shape (extra fields are ignored):
//! `{"rising": {"coefficients": [c0, c1, …]}, "falling": {"coefficients": […]},
//!   "current_min_A": 0.0, "current_max_A": 2.0}` — coefficients in ascending powers of the current
//! in A giving torque in Nm. `current_min_A`/`current_max_A` may also sit inside the branch objects.

use std::path::Path;

use mrbrake_control::{InverseModel, MAX_DEGREE};
use serde_json::Value;

use crate::SimError;

/// Reads a characterisation file into an inverse model. Errors name the file and the field.
pub fn load_inverse_model(path: &Path) -> Result<InverseModel, SimError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        SimError::Input(format!("cannot read characterisation '{}': {e}", path.display()))
    })?;
    parse_inverse_model(&text, &path.display().to_string())
}

/// Parses characterisation JSON text; `origin` names the source in error messages.
pub fn parse_inverse_model(text: &str, origin: &str) -> Result<InverseModel, SimError> {
    let root: Value = serde_json::from_str(text).map_err(|e| {
        SimError::Input(format!("{origin}:{}:{}: not valid JSON: {e}", e.line(), e.column()))
    })?;
    let coefficients = |branch: &str| -> Result<Vec<f64>, SimError> {
        let field = format!("{branch}.coefficients");
        let list = root
            .get(branch)
            .and_then(|b| b.get("coefficients"))
            .and_then(Value::as_array)
            .ok_or_else(|| {
            SimError::Input(format!("{origin}: missing array field '{field}'"))
        })?;
        if list.is_empty() || list.len() > MAX_DEGREE + 1 {
            return Err(SimError::Input(format!(
                "{origin}: '{field}' has {} entries; allowed 1 to {}",
                list.len(),
                MAX_DEGREE + 1
            )));
        }
        list.iter()
            .enumerate()
            .map(|(k, v)| {
                v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    SimError::Input(format!(
                        "{origin}: '{field}[{k}]' = {v} is not a finite number"
                    ))
                })
            })
            .collect()
    };
    let current = |name: &str| -> Result<f64, SimError> {
        let value = root
            .get(name)
            .or_else(|| root.get("rising").and_then(|b| b.get(name)))
            .ok_or_else(|| SimError::Input(format!("{origin}: missing number field '{name}'")))?;
        value.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
            SimError::Input(format!("{origin}: '{name}' = {value} is not a finite number"))
        })
    };
    let rising = coefficients("rising")?;
    let falling = coefficients("falling")?;
    let current_min_a = current("current_min_A")?;
    let current_max_a = current("current_max_A")?;
    InverseModel::new(&rising, &falling, current_min_a, current_max_a)
        .map_err(|e| SimError::Input(format!("{origin}: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_control::Branch;

    #[test]
    fn parses_a_characterisation_and_names_bad_fields() {
        let text = r#"{"rising": {"coefficients": [0.15, 1.8, 0.01]}, "falling": {"coefficients": [0.3, 1.7, 0.01]},
                       "current_min_A": 0.0, "current_max_A": 2.0, "rmse_percent": 3.5}"#;
        let m = parse_inverse_model(text, "c.json").unwrap();
        assert!((m.torque_nm(Branch::Rising, 1.0) - 1.96).abs() < 1e-12);
        let bad = text.replace("1.8", "\"x\"");
        let err = parse_inverse_model(&bad, "c.json").unwrap_err().to_string();
        assert!(err.contains("rising.coefficients[1]"), "{err}");
        let missing = r#"{"rising": {"coefficients": [0.1]}}"#;
        assert!(
            parse_inverse_model(missing, "c.json")
                .unwrap_err()
                .to_string()
                .contains("falling.coefficients")
        );
        let decreasing = text.replace("1.8, 0.01", "-1.8, 0.01");
        assert!(
            parse_inverse_model(&decreasing, "c.json").unwrap_err().to_string().contains("rising")
        );
    }
}
