//! The integration tests of `mrbrake-control`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-control --test it <name>::`).

mod common;

mod controller_properties;
mod demag_properties;
mod hysteresis_compensation;
mod inverse_properties;
mod model_file;
mod no_std_source;
mod operator_properties;
