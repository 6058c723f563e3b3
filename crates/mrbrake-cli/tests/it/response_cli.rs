//! `mrbrake response`: bad input exits 2 with a message naming the flag and what is allowed,
//! before any field solve.

use crate::common;

use common::expect_input_error;

#[test]
fn bad_response_input_is_exit_code_2() {
    expect_input_error(&["response", "--step", "2A"], &["--step", "FROM..TO"]);
    // A step down to 0 is a release (the fall times); a step that changes nothing is refused.
    expect_input_error(&["response", "--step", "1A..0A", "--duration", "-1s"], &["duration"]);
    expect_input_error(&["response", "--step", "0A..0A"], &["must change the current"]);
    expect_input_error(&["response", "--drive", "pwm"], &["--drive", "current or voltage"]);
    expect_input_error(&["response", "--duration", "0s"], &["duration", "> 0"]);
    expect_input_error(
        &["response", "--conductivity", "nan"],
        &["--conductivity", "not a finite number"],
    );
    expect_input_error(&["response", "--conductivity=-1MS/m"], &["conductivity", "> 0"]);
    expect_input_error(&["response", "--fluid-lag=-1ms"], &["--fluid-lag", "got -0.001 s", ">= 0"]);
    expect_input_error(&["response", "--bias", "2V"], &["--bias"]);
    // Rules of the library: the CLI only parses the quantities.
    expect_input_error(&["response", "--step=-1A..2A"], &["--step: FROM", "got -1 A", ">= 0"]);
    expect_input_error(&["response", "--bias=-0.5A"], &["--bias", "got -0.5 A", ">= 0"]);
    expect_input_error(&["response", "--eddy-at", "1s"], &["eddy-current instant", "duration"]);
    expect_input_error(&["response", "--eddy-at", "2A"], &["--eddy-at"]);
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: two transients of the thesis brake")]
fn plots_include_the_eddy_current_map_at_the_instant_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::mrbrake(&[
        "response",
        "--mesh",
        "coarse",
        "--duration",
        "10ms",
        "--eddy-at",
        "1ms",
        "--plot-dir",
        common::path_str(dir.path()),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let svg = std::fs::read_to_string(dir.path().join("eddy_current.svg")).unwrap();
    // The first time level at or after 1 ms: within the adaptive steps of it.
    let title = svg.find("eddy-current density").expect("titled map");
    let shown = &svg[title..title + 80];
    let t_ms: f64 = shown
        .split("t = ")
        .nth(1)
        .and_then(|rest| rest.split(" ms").next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no instant in {shown}"));
    assert!((1.0..1.5).contains(&t_ms), "instant {t_ms} ms");
    assert!(svg.contains("J_φ [A/mm²]"));
    for name in ["step_response.svg", "bode.svg"] {
        assert!(dir.path().join(name).exists(), "{name}");
    }
}
