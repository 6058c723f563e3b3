//! The integration tests of `mrbrake-design`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-design --test it <name>::`).

mod analysis;
mod demag_release;
mod forc_set;
mod hostile_geometry;
mod hysteresis_loop;
mod material_factors;
mod off_state;
mod response;
mod response_directions;
mod spec_fields;
mod spec_geometry;
mod spec_roundtrip;
mod thesis_tables;
