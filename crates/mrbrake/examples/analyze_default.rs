//! mrbrake as a library: analyse the embedded thesis brake through the facade crate and print its
//! torque at the maximum current, the number `mrbrake analyze` reports first.
//!
//! ```text
//! cargo run --release -p mrbrake --example analyze_default
//! ```
//! Asserts the key number: 5.384 N·m at 2 A (direction 1, default mesh, linear elements), as the
//! README's `mrbrake analyze` output shows.

use mrbrake::design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake::design::spec::default_spec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let spec = default_spec();
    let options = AnalysisOptions { points: 3, ..AnalysisOptions::default() };
    let analysis = AnalysisRequest::of(&spec).options(options).run()?;
    let torque = analysis.torque.at_max_current_nm;
    println!(
        "{}: {:.4} N·m at {} A (mean B in the gaps {:.4} T), {:.4} N·m off",
        analysis.name,
        torque,
        analysis.max_current_a,
        analysis.torque.mean_b_t,
        analysis.torque.off_state_nm
    );
    assert!((torque - 5.384).abs() < 1e-3, "torque at the maximum current: {torque} N·m");
    Ok(())
}
