//! The integration tests of `mrbrake-sysid`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-sysid --test it <name>::`).

mod model_file;
mod properties;
mod tfest_validation;
