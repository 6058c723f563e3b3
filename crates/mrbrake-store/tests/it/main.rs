//! The integration tests of `mrbrake-store`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-store --test it <name>::`).

mod damage;
mod durability;
mod merge;
mod merge_complete;
mod refusals;
