//! Helpers shared by the CLI test files: run the `mrbrake` binary, parse its JSON, check input errors.
//! (Each test file uses a subset, hence the `dead_code` allowance.)
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `mrbrake ARGS…` and returns its output.
pub fn mrbrake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mrbrake"))
        .args(args)
        .output()
        .expect("the mrbrake binary runs")
}

/// Runs `mrbrake ARGS…`, asserts success and parses stdout as JSON.
pub fn json(args: &[&str]) -> serde_json::Value {
    let out = mrbrake(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("valid JSON on stdout")
}

/// The number in `v[field]`, or a panic naming the field.
pub fn number(v: &serde_json::Value, field: &str) -> f64 {
    v[field].as_f64().unwrap_or_else(|| panic!("field '{field}' is not a number in {v}"))
}

/// True when `actual` is within `relative` of `expected`.
pub fn close(actual: f64, expected: f64, relative: f64) -> bool {
    (actual - expected).abs() <= relative * expected.abs()
}

/// A path as `&str` (temporary directories here are UTF-8).
pub fn path_str(path: &Path) -> &str {
    path.to_str().expect("UTF-8 temporary path")
}

/// Asserts that `mrbrake ARGS…` exits with code 2, without a panic, and that stderr names every needle.
pub fn expect_input_error(args: &[&str], needles: &[&str]) {
    let out = mrbrake(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?} should exit 2; stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr lacks '{n}': {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}
