//! A file written by `mrbrake characterize --save-model` before the model types were unified (the
//! release binary of 2026-11-23, on the default virtual rig's characterisation log) still loads into
//! the controller's model, with every coefficient and the current range as written.

use std::path::Path;

use mrbrake_control::Branch;
use mrbrake_sysid::model_file::read_inverse_model;

#[test]
fn a_saved_characterisation_of_the_previous_release_loads() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/characterize-save-model.json");
    let model = read_inverse_model(&path).unwrap();
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (name, branch) in [("rising", Branch::Rising), ("falling", Branch::Falling)] {
        let expected: Vec<f64> = written[name]["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        assert_eq!(expected.len(), 6, "the default order 5");
        let loaded = model.branch(branch).coefficients();
        for (a, b) in loaded.iter().zip(&expected) {
            assert!((a - b).abs() <= 1e-15 * b.abs(), "{name}: {loaded:?} vs {expected:?}");
        }
    }
    assert!((model.current_min_a() - written["current_min_A"].as_f64().unwrap()).abs() < 1e-300);
    assert!((model.current_max_a() - written["current_max_A"].as_f64().unwrap()).abs() < 1e-300);
    // The prototype-like loop of the rig: about 0.15 N·m off-state and 3.84 N·m at 2 A.
    assert!((model.torque_nm(Branch::Rising, 0.0) - 0.15).abs() < 0.02);
    assert!((model.torque_nm(Branch::Falling, 2.0) - 3.84).abs() < 0.05);
}
