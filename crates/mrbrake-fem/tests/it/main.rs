//! The integration tests of `mrbrake-fem`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-fem --test it <name>::`).

mod gmsh_reader;
mod second_physics;
