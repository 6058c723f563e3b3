//! The integration tests of `mrbrake-explore`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-explore --test it <name>::`).

mod common;

mod bounds;
mod cascade;
mod design_keys;
mod expensive_metrics;
mod haptic_compact;
mod haptic_metrics;
mod material_variables;
mod resume_metrics;
mod stop;
mod surrogate_study;
mod uncertainty;
mod variables;
