//! The integration tests of `mrbrake-uq`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-uq --test it <name>::`).

mod calibration;
mod distributions;
mod propagation;
mod qmc;
mod sobol_validation;
