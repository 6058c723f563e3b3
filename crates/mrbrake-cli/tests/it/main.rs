//! The integration tests of `mrbrake-cli`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-cli --test it <name>::`).

mod browser;
mod common;
mod demag_cli;

mod analyze_cli;
mod analyze_hysteresis_cli;
mod brake_model_cli;
mod calibrate_cli;
mod fem_cli;
mod fem_dynamics_cli;
mod fem_heat_cli;
mod files_cli;
mod flags_cli;
mod formula_cli;
mod haptic_cli;
mod hardening2_cli;
mod help_cli;
mod hostile_cli;
mod hysteresis_cli;
mod json_conventions;
mod materials_cli;
mod report_cli;
mod report_thermal_cli;
mod response_cli;
mod schema_cli;
mod studio_cli;
mod study_cli;
mod study_metrics_cli;
mod study_variables_cli;
mod sysid_cli;
mod text_output_cli;
mod thermal_cli;
mod uncertainty_cli;
