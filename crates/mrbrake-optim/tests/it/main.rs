//! The integration tests of `mrbrake-optim`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-optim --test it <name>::`).

mod nsga2_validation;
mod pareto_properties;
mod pattern_search_validation;
mod sampling_plans;
mod space_properties;
mod surrogate_driver;
mod surrogate_validation;
