//! The integration tests of `mrbrake-explore`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-explore --test it <name>::`).
//! `tests/cascade.rs` and `tests/resume_metrics.rs` stay binaries of their own: they assert the
//! analysis counts, which are per process (`mrbrake_explore::metrics::analysis_counts`).

mod common;

mod bounds;
mod design_keys;
mod expensive_metrics;
mod haptic_compact;
mod haptic_metrics;
mod material_variables;
mod stop;
mod surrogate_incomplete;
mod surrogate_study;
mod uncertainty;
mod variables;
