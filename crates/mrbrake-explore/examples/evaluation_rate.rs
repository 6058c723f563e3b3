//! Design evaluations per minute for the thesis brake at the default mesh (issue 7's benchmark), and
//! the results store's share of it.
//!
//! ```text
//! cargo run --release -p mrbrake-explore --example evaluation_rate -- [designs] [jobs] [rounds]
//! ```
//! Evaluates `designs` distinct variants of the thesis's bidirectional brake (the gap swept over
//! 0.45–0.55 mm; each evaluation is the full two-point analysis: off state and maximum current, both
//! directions, inductances) on `jobs` threads, alternately (a) through the [`Runner`] into a fresh
//! SQLite store (WAL, one durable transaction per design) and (b) with the same thread pool and no
//! store, `rounds` times each. Prints every round's wall time and rate, their medians, and the
//! store's overhead as the ratio of the medians.

use std::time::Instant;

use mrbrake_design::spec::DEFAULT_SPEC_TOML;
use mrbrake_explore::evaluate::evaluate;
use mrbrake_explore::{DesignSpace, EvaluationSettings, Runner};
use mrbrake_store::Store;
use rayon::prelude::*;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let designs: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(40);
    let jobs: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(2);
    let rounds: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(3);
    let settings = EvaluationSettings::default();
    let space =
        DesignSpace::new(DEFAULT_SPEC_TOML, "default", &[], &["g".into()], settings.clone())?;
    let points: Vec<f64> =
        (0..designs).map(|k| 0.45e-3 + 0.1e-3 * k as f64 / designs.max(2) as f64).collect();
    let batch = points.iter().map(|&g| space.design(&[g])).collect::<Result<Vec<_>, _>>()?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    let dir = std::env::temp_dir().join(format!("mrbrake-rate-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;

    let (mut with_store, mut without, mut store_s) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        let t0 = Instant::now();
        let ok = pool.install(|| {
            batch
                .par_iter()
                .map(|d| d.spec.as_ref().map(|s| evaluate(s, &settings).status).is_ok())
                .filter(|ok| *ok)
                .count()
        });
        let plain = t0.elapsed().as_secs_f64();
        assert_eq!(ok, designs, "every design is valid");

        let path = dir.join(format!("round-{round}.sqlite"));
        let mut store = Store::create(&path)?;
        let t0 = Instant::now();
        let (_, summary) = Runner::new(&mut store, settings.clone(), jobs)
            .run(&batch, &mut mrbrake_observe::Silent)?;
        let stored = t0.elapsed().as_secs_f64();
        assert_eq!(summary.progress.computed, designs);
        println!(
            "round {round}: no store {plain:.2} s ({:.0}/min), with store {stored:.2} s ({:.0}/min), \
             store writes {:.3} s on the writer thread",
            designs as f64 * 60.0 / plain,
            designs as f64 * 60.0 / stored,
            summary.store_s
        );
        without.push(plain);
        with_store.push(stored);
        store_s.push(summary.store_s);
    }
    std::fs::remove_dir_all(&dir)?;
    let (a, b) = (median(with_store), median(without));
    println!(
        "{designs} designs, {jobs} jobs: median {:.0} evaluations/min with the store, {:.0}/min \
         without; store overhead {:+.2} % of wall time (writer-thread time {:.3} s per round)",
        designs as f64 * 60.0 / a,
        designs as f64 * 60.0 / b,
        (a / b - 1.0) * 100.0,
        median(store_s)
    );
    Ok(())
}
