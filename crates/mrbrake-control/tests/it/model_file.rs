//! The inverse-model file (feature `serde`): a model round-trips through JSON, the file
//! `mrbrake characterize --save-model` writes (with its extra fit statistics) loads, and a bad file is
//! refused with a message that says what was expected.

use mrbrake_control::{Branch, ControlError, InverseModel, InverseModelFile};

/// The shape of a saved characterisation: the schema's fields plus statistics the reader ignores.
const SAVED: &str = r#"{
  "rising": { "coefficients": [0.15, 1.8, 0.01], "fit_percent": 99.7, "fit_percent_mean": 99.9, "samples": 200 },
  "falling": { "coefficients": [0.3, 1.7, 0.01], "fit_percent": 99.6, "fit_percent_mean": 99.9, "samples": 200 },
  "current_min_A": 0.0, "current_max_A": 2.0, "off_state_torque_Nm": 0.15, "repetitions": 10
}"#;

#[test]
fn a_saved_characterisation_loads_and_round_trips() {
    let model: InverseModel = serde_json::from_str(SAVED).unwrap();
    assert!((model.torque_nm(Branch::Rising, 1.0) - 1.96).abs() < 1e-12);
    assert!((model.torque_nm(Branch::Falling, 1.0) - 2.01).abs() < 1e-12);
    let text = serde_json::to_string(&model).unwrap();
    assert_eq!(
        text,
        r#"{"rising":{"coefficients":[0.15,1.8,0.01]},"falling":{"coefficients":[0.3,1.7,0.01]},"current_min_A":0.0,"current_max_A":2.0}"#
    );
    assert_eq!(serde_json::from_str::<InverseModel>(&text).unwrap(), model);
}

#[test]
fn bad_files_are_refused_with_what_was_expected() {
    let message = |text: &str| serde_json::from_str::<InverseModel>(text).unwrap_err().to_string();
    let too_many = SAVED.replace("[0.15, 1.8, 0.01]", "[0.15, 1.8, 0, 0, 0, 0, 0, 0, 0.01]");
    assert!(
        message(&too_many).contains("invalid length 9, expected a list of 1 to 8 finite numbers")
    );
    let empty = SAVED.replace("[0.15, 1.8, 0.01]", "[]");
    assert!(message(&empty).contains("invalid length 0"), "{}", message(&empty));
    let text = SAVED.replace("1.8", "\"x\"");
    assert!(
        message(&text).contains("invalid type: string \"x\", expected f64"),
        "{}",
        message(&text)
    );
    let missing = SAVED.replace("\"falling\"", "\"fallen\"");
    assert!(message(&missing).contains("missing field `falling`"), "{}", message(&missing));
    // Validation after parsing: the typed error of the parts, and its text through serde.
    let decreasing = SAVED.replace("[0.15, 1.8, 0.01]", "[0.15, -1.8, 0.01]");
    let parts: InverseModelFile = serde_json::from_str(&decreasing).unwrap();
    assert_eq!(
        InverseModel::try_from(parts),
        Err(ControlError::NonMonotoneBranch { branch: "rising" })
    );
    assert!(message(&decreasing).contains("the rising branch decreases"));
}
