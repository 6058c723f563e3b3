//! `mrbrake response`: bad input exits 2 with a message naming the flag and what is allowed,
//! before any field solve.

mod common;

use common::expect_input_error;

#[test]
fn bad_response_input_is_exit_code_2() {
    expect_input_error(&["response", "--step", "2A"], &["--step", "FROM..TO"]);
    expect_input_error(&["response", "--step", "1A..0A"], &["non-zero"]);
    expect_input_error(&["response", "--drive", "pwm"], &["--drive", "current or voltage"]);
    expect_input_error(&["response", "--duration", "0s"], &["duration", "> 0"]);
    expect_input_error(
        &["response", "--conductivity", "nan"],
        &["--conductivity", "not a finite number"],
    );
    expect_input_error(&["response", "--conductivity=-1MS/m"], &["conductivity", "> 0"]);
    expect_input_error(&["response", "--fluid-lag=-1ms"], &["fluid lag", ">= 0"]);
    expect_input_error(&["response", "--bias", "2V"], &["--bias"]);
}
