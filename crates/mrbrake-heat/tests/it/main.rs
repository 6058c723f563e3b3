//! The integration tests of `mrbrake-heat`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-heat --test it <name>::`).

mod problem_file;
mod validation;
