//! User B-H files: every validation rule gives an error naming the file, the line and the rule.

use mrbrake_error::Kind as _;
use std::io::Write;

use mrbrake_materials::{BhCurve, MaterialError, Provenance, Trust};

fn write_temp(content: &str) -> tempfile::NamedTempFile {
    let mut file = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    file.write_all(content.as_bytes()).unwrap();
    file
}

/// Loads `content` from a real file and returns the error message, checking file and line are named.
fn error_for(content: &str, line: u64) -> String {
    let file = write_temp(content);
    let err = BhCurve::from_csv_file(file.path()).unwrap_err();
    assert!(err.is_input_error());
    let msg = err.to_string();
    let prefix = format!("{}:{line}:", file.path().display());
    assert!(msg.starts_with(&prefix), "expected `{prefix}` in `{msg}`");
    msg
}

const GOOD: &str = "H_A_per_m,B_T\n0,0\n100,0.5\n1000,1.2\n10000,1.7\n";

#[test]
fn a_good_file_loads_with_user_provenance() {
    let file = write_temp(GOOD);
    let c = BhCurve::from_csv_file(file.path()).unwrap();
    assert_eq!(c.points().len(), 4);
    assert_eq!(c.provenance().trust, Trust::User);
    assert!(c.provenance().source.contains(&file.path().display().to_string()));
}

#[test]
fn non_finite_values_are_rejected() {
    let msg = error_for("H_A_per_m,B_T\n0,0\n100,0.5\ninf,1.2\n10000,1.7\n", 4);
    assert!(msg.contains("rule `finite`"), "{msg}");
    let msg = error_for("H_A_per_m,B_T\n0,0\n100,NaN\n1000,1.2\n10000,1.7\n", 3);
    assert!(msg.contains("rule `finite`"), "{msg}");
}

#[test]
fn the_curve_must_start_at_the_origin() {
    let msg = error_for("H_A_per_m,B_T\n10,0.01\n100,0.5\n1000,1.2\n10000,1.7\n", 2);
    assert!(msg.contains("rule `starts at origin`"), "{msg}");
}

#[test]
fn h_must_increase_strictly() {
    let msg = error_for("H_A_per_m,B_T\n0,0\n100,0.5\n100,1.2\n10000,1.7\n", 4);
    assert!(msg.contains("rule `strictly increasing H`"), "{msg}");
    assert!(msg.contains("line 3"), "{msg}");
}

#[test]
fn b_must_increase_strictly() {
    let msg = error_for("H_A_per_m,B_T\n0,0\n100,0.5\n1000,0.4\n10000,1.7\n", 4);
    assert!(msg.contains("rule `strictly increasing B`"), "{msg}");
}

#[test]
fn too_few_points_are_rejected() {
    let msg = error_for("H_A_per_m,B_T\n0,0\n100,0.5\n1000,1.2\n", 4);
    assert!(msg.contains("rule `enough points`") && msg.contains("at least 4"), "{msg}");
}

#[test]
fn parse_errors_name_the_line() {
    let msg = error_for("H,B\n0,0\n", 1);
    assert!(msg.contains("header must be `H_A_per_m,B_T`"), "{msg}");
    let msg = error_for("H_A_per_m,B_T\n0,0\n100;0.5\n", 3);
    assert!(msg.contains("expected 2 fields"), "{msg}");
    let msg = error_for("# comment\nH_A_per_m,B_T\n0,0\n\n100,x\n", 5);
    assert!(msg.contains("`x`, which is not a number"), "{msg}");
}

#[test]
fn a_missing_file_is_an_input_error() {
    let err = BhCurve::from_csv_file(std::path::Path::new("/nonexistent/curve.csv")).unwrap_err();
    assert!(matches!(err, MaterialError::Io { .. }));
    assert!(err.is_input_error());
    assert!(err.to_string().contains("/nonexistent/curve.csv"));
}

#[test]
fn in_memory_points_name_the_point_number() {
    let err = BhCurve::from_points(
        &[(0.0, 0.0), (1.0, 0.1), (0.5, 0.2), (3.0, 0.3)],
        Provenance::user_file("x"),
    )
    .unwrap_err();
    assert!(err.to_string().starts_with("points:3: rule `strictly increasing H`"), "{err}");
}
