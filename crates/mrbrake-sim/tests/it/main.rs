//! The integration tests of `mrbrake-sim`, one test binary (one link) for the whole crate: each
//! module is one former `tests/<name>.rs` file (run one with `cargo test -p mrbrake-sim --test it <name>::`).

mod haptic_demag;
mod haptic_preisach;
mod haptic_scenarios;
mod haptic_sticky_wall;
mod haptic_zwidth;
mod rig_end_to_end;
