//! Criterion benchmarks of the brake's heat model (issue 14 targets):
//! `cargo bench -p mrbrake-design --bench thermal`.
//!
//! - `steady/thesis_default_mesh`: the steady temperature of the thesis brake at 2 A on its
//!   default mesh, the solver set up once (the heat problem's assembly and factorisation per
//!   solve). Target ≤ 50 ms. `setup_and_steady` adds the problem build (geometry, mesh) and the
//!   solver set-up.
//! - `warmup/2h_10s`: a 2 h warm-up at 10 s steps (720 BDF2 steps) on the same mesh, set-up
//!   excluded. Target ≤ 1 s.
//! - `command/thesis`: the whole `mrbrake thermal` analysis of the thesis brake with its defaults
//!   (steady state, continuous-current search, 2 h warm-up, the hot behaviour with its magnetic
//!   analysis). Target ≤ 5 s.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_design::spec::default_spec;
use mrbrake_design::thermal::{ThermalOptions, analyze_thermal, thermal_problem};
use mrbrake_fem::workflow::time::{Event, Scheme, TimeOptions, TimeStep};
use mrbrake_heat::{HeatSolver, SolverOptions, kelvin};
use mrbrake_observe::Flow;

fn solver() -> HeatSolver {
    let (problem, _) =
        thermal_problem(&default_spec(), &ThermalOptions::default()).expect("problem");
    HeatSolver::new(problem, SolverOptions::default()).expect("setup")
}

fn benchmarks(c: &mut Criterion) {
    let mut group = c.benchmark_group("thermal");
    group.sample_size(10);
    let mut s = solver();
    group.bench_function("steady/thesis_default_mesh", |b| {
        b.iter(|| s.steady(None).expect("steady").0.len())
    });
    group.bench_function("setup_and_steady/thesis_default_mesh", |b| {
        b.iter(|| solver().steady(None).expect("steady").0.len())
    });
    let settings = TimeOptions::new(7200.0, Scheme::Bdf2, TimeStep::Fixed { dt_s: 10.0 });
    group.bench_function("warmup/2h_10s", |b| {
        b.iter(|| {
            let start = s.uniform(kelvin(25.0));
            let mut steps = 0;
            s.transient(&start, &settings, |e: &Event<'_, HeatSolver>| {
                steps = e.level.index;
                Flow::Continue
            })
            .expect("transient");
            assert_eq!(steps, 720);
        })
    });
    let options = ThermalOptions { behaviour: true, ..ThermalOptions::default() };
    group.bench_function("command/thesis", |b| {
        b.iter(|| analyze_thermal(&default_spec(), &options).expect("thermal").continuous_current_a)
    });
    group.finish();
}

criterion_group!(benches, benchmarks);
criterion_main!(benches);
