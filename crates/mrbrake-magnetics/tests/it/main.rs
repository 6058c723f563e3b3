//! The integration tests of `mrbrake-magnetics`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-magnetics --test it <name>::`).

mod dynamics;
mod forces;
mod hysteresis_convergence;
mod hysteresis_solve;
mod problem_file;
mod problem_file_dynamics;
mod validation;
