//! The integration tests of `mrbrake-materials`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-materials --test it <name>::`).

mod bh_curve_numerics;
mod csv_validation;
mod hysteresis;
mod hysteresis_jiles_atherton;
mod hysteresis_properties;
mod library;
mod mr_fluids;
