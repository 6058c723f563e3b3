//! Build script shared by the crates with heavy validation tests (their `Cargo.toml` names it as
//! `build = "../../build/heavy_tests.rs"`): it sets `cfg(heavy_tests)` in a release-based build.
//!
//! The heavy tests carry `#[cfg_attr(not(heavy_tests), ignore = "release only: …")]`: they run under
//! the README's test command (`cargo test --release`) and are skipped in a debug `cargo test`, where
//! they would take minutes to hours. The gate used to be `debug_assertions`; it is the build's
//! profile now so that CI can run every test once in a release build with the workspace's debug
//! assertions and overflow checks switched on (`.ci/run`) instead of building the tests twice.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(heavy_tests)");
    println!("cargo::rerun-if-changed=../../build/heavy_tests.rs");
    // Cargo sets PROFILE to "release" for the release profile and every profile inheriting from it.
    if std::env::var("PROFILE").is_ok_and(|profile| profile == "release") {
        println!("cargo::rustc-cfg=heavy_tests");
    }
}
