//! The inverse-model file: the JSON that `mrbrake characterize --save-model` writes and that the
//! virtual rig (`rig freqresp --model`) and the haptic simulation (`haptic wall --model`) read back.
//!
//! One model type serves every stage: [`mrbrake_control::InverseModel`], the fixed-size model the
//! controller runs. Its schema is documented on [`mrbrake_control::InverseModelFile`]: `rising` and
//! `falling` objects with `coefficients` (ascending powers of the current in A, torque in N·m, 1 to 8
//! finite numbers each) and `current_min_A`, `current_max_A`; other fields are ignored. The
//! [`crate::characterize::Characterization`] of a log serialises to a superset of that schema (the
//! same fields plus fit statistics), so the file it writes is the file this module reads.
//!
//! Reading is typed end to end: a file that is not JSON or lacks a field of the schema is a
//! [`SysidError::ModelFile`] naming the file and the field (e.g. `rising.coefficients[1]`); a model
//! whose values are unusable (a decreasing branch, a backwards current range) is a
//! [`SysidError::Model`] carrying the controller's own [`mrbrake_control::ControlError`].

use std::path::Path;

use mrbrake_control::{InverseModel, InverseModelFile};

use crate::SysidError;

/// Reads an inverse-model file (see the module docs); errors name the file and the field.
pub fn read_inverse_model(path: &Path) -> Result<InverseModel, SysidError> {
    parse_inverse_model(path, &read_text(path)?)
}

/// Parses inverse-model JSON text; `source` names it in errors.
pub fn parse_inverse_model(source: &Path, text: &str) -> Result<InverseModel, SysidError> {
    let parts: InverseModelFile = deserialize_json(source, text)?;
    InverseModel::try_from(parts)
        .map_err(|e| SysidError::Model { file: source.to_path_buf(), source: e })
}

/// The text of a model file (an I/O error names it).
pub(crate) fn read_text(path: &Path) -> Result<String, SysidError> {
    mrbrake_error::read::text(path, mrbrake_error::read::MODEL)
        .map_err(|source| SysidError::Io { path: path.to_path_buf(), source })
}

/// Deserialises a model file's JSON text; an error names the file `source` and the field.
pub(crate) fn deserialize_json<T: serde::de::DeserializeOwned>(
    source: &Path,
    text: &str,
) -> Result<T, SysidError> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut deserializer).map_err(|e| {
        // The path is "." at the root and "?" where the parser stopped outside any field.
        let field = e.path().to_string();
        SysidError::ModelFile {
            file: source.to_path_buf(),
            field: (field != "." && field != "?").then_some(field),
            source: e.into_inner(),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::characterize::{CharacterizeOptions, characterize};
    use mrbrake_control::{Branch, ControlError};
    use mrbrake_error::Kind as _;

    /// A static loop swept twice: rising T = 0.15 + 1.8 I, falling T = 0.25 + 1.75 I.
    fn swept_loop() -> (Vec<f64>, Vec<f64>) {
        let (mut current, mut torque) = (Vec::new(), Vec::new());
        for _ in 0..2 {
            for k in 0..=400 {
                current.push(k as f64 * 5e-3);
                torque.push(0.15 + 1.8 * k as f64 * 5e-3);
            }
            for k in (0..400).rev() {
                current.push(k as f64 * 5e-3);
                torque.push(0.25 + 1.75 * k as f64 * 5e-3);
            }
            current.extend([0.0; 50]);
            torque.extend([0.15; 50]);
        }
        (current, torque)
    }

    #[test]
    fn the_characterisation_json_is_the_model_file() {
        let (current, torque) = swept_loop();
        let c =
            characterize(&current, &torque, CharacterizeOptions { order: 1, bins: 40 }).unwrap();
        let text = serde_json::to_string_pretty(&c).unwrap();
        let model = parse_inverse_model(Path::new("model.json"), &text).unwrap();
        // serde_json parses decimals to within an ulp (not always the exact round trip).
        let fitted = c.model().unwrap();
        for branch in [Branch::Rising, Branch::Falling] {
            let (a, b) =
                (model.branch(branch).coefficients(), fitted.branch(branch).coefficients());
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-15 * y.abs()), "{a:?} {b:?}");
        }
        assert!((model.torque_nm(Branch::Rising, 1.0) - 1.95).abs() < 1e-9);
        assert!((model.torque_nm(Branch::Falling, 1.0) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn bad_files_name_the_file_and_the_field() {
        let good = r#"{"rising": {"coefficients": [0.15, 1.8]}, "falling": {"coefficients": [0.3, 1.7]},
                       "current_min_A": 0.0, "current_max_A": 2.0}"#;
        let err = |text: &str| parse_inverse_model(Path::new("m.json"), text).unwrap_err();
        let chain = |e: &SysidError| {
            let mut s = e.to_string();
            let mut cause = std::error::Error::source(e);
            while let Some(c) = cause {
                s.push_str(&format!(": {c}"));
                cause = c.source();
            }
            s
        };
        let e = err(&good.replace("1.8", "\"x\""));
        assert!(e.is_input_error());
        assert!(
            chain(&e).starts_with(
                "inverse-model file 'm.json', field rising.coefficients[1]: invalid type"
            ),
            "{}",
            chain(&e)
        );
        let e = err(&good.replace("\"falling\"", "\"fallen\""));
        assert!(
            chain(&e).contains("'m.json'") && chain(&e).contains("missing field `falling`"),
            "{}",
            chain(&e)
        );
        let e = err(&good[..40]);
        assert!(
            chain(&e).starts_with("inverse-model file 'm.json': EOF while parsing"),
            "{}",
            chain(&e)
        );
        let e = err(&good.replace("[0.15, 1.8]", "[0.15, -1.8]"));
        assert!(matches!(
            e,
            SysidError::Model { source: ControlError::NonMonotoneBranch { branch: "rising" }, .. }
        ));
        assert!(e.is_input_error());
        assert!(chain(&e).starts_with("inverse-model file 'm.json': the rising branch decreases"));
        let missing = read_inverse_model(Path::new("no/such/model.json")).unwrap_err();
        assert!(missing.is_input_error() && chain(&missing).contains("no/such/model.json"));
    }
}
