//! Criterion benchmarks of the magnetodynamics (issue 13 targets):
//! `cargo bench -p mrbrake-magnetics --bench dynamics`.
//!
//! - `linear_transient/16k`: the pot core of the saturating benchmark with a linear conducting
//!   core (μr = 1000, σ = 5.8 MS/m, FEMM's steel value) on ~16 k nodes, a current step, 500 fixed
//!   BDF2 steps (two factorisations: the Euler start and the rest). Target ≤ 0.5 s.
//! - `harmonic/16k_31_frequencies`: the same problem, 31 frequencies (1–1000 Hz), by the default
//!   reduced-basis sweep (`mrbrake_fem::linalg::sweep`: real shifted Cholesky solves, every frequency's
//!   residual checked); `harmonic_direct/16k_31_frequencies`: the reference, one complex sparse LU
//!   per frequency.
//!
//! Each sample includes the set-up (pattern, symbolic factorisation, mass matrices).

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_fem::workflow::time::{Scheme, TimeStep};
use mrbrake_magnetics::benchmark::conducting_pot_core;
use mrbrake_magnetics::dynamics::Dynamics;
use mrbrake_magnetics::dynamics::harmonic::HarmonicMethod;
use mrbrake_magnetics::dynamics::transient::TransientOptions;

fn dynamics() -> Dynamics {
    conducting_pot_core(16_000).expect("dynamics")
}

fn benchmarks(c: &mut Criterion) {
    let mut group = c.benchmark_group("dynamics");
    group.sample_size(10);
    let options = TransientOptions::new(0.05, Scheme::Bdf2, TimeStep::Fixed { dt_s: 1e-4 });
    group.bench_function("linear_transient/16k_500_steps", |b| {
        b.iter(|| {
            let mut d = dynamics();
            let result = d.transient(&options).expect("transient");
            assert_eq!(result.time_s.len(), 501);
            assert_eq!(result.factorizations, 2);
            result.coils[0].flux_linkage_wb[500]
        })
    });
    let frequencies: Vec<f64> = (0..31).map(|k| 10f64.powf(k as f64 / 10.0)).collect();
    group.bench_function("harmonic/16k_31_frequencies", |b| {
        b.iter(|| {
            let mut d = dynamics();
            let (_, report) = d
                .harmonic_potentials_by(&frequencies, None, HarmonicMethod::default())
                .expect("harmonic");
            report.map(|r| r.basis)
        })
    });
    group.bench_function("harmonic_direct/16k_31_frequencies", |b| {
        b.iter(|| {
            let mut d = dynamics();
            d.harmonic_potentials_by(&frequencies, None, HarmonicMethod::Direct)
                .expect("harmonic")
                .0
                .len()
        })
    });
    group.finish();
}

criterion_group!(benches, benchmarks);
criterion_main!(benches);
