//! Criterion benchmarks of one study evaluation of the thesis brake on its default mesh (issue 27:
//! a full evaluation for the hand, target ≤ 4 s): `cargo bench -p mrbrake-explore --bench evaluate`.
//!
//! - `static/thesis`: the two-point static analysis every study design gets.
//! - `hand/thesis`: the cascade a design-for-the-hand study runs: static analysis, small-signal
//!   bandwidth, the continuous torque (thermal rating with the hot magnetic analysis) and the
//!   haptic wall driven by the design's brake model with its predicted dynamics.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_design::spec::default_spec;
use mrbrake_explore::EvaluationSettings;
use mrbrake_explore::evaluate::evaluate;
use mrbrake_explore::metrics::StudyMetrics;
use mrbrake_store::Status;

fn benchmarks(c: &mut Criterion) {
    let spec = default_spec();
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(10);
    let static_only = EvaluationSettings::default();
    group.bench_function("static/thesis", |b| {
        b.iter(|| assert_eq!(evaluate(&spec, &static_only).status, Status::Ok))
    });
    let asked = [
        "bandwidth_rad_s",
        "continuous_torque_Nm",
        "release_time_s",
        "displayed_stiffness_Nm_per_rad",
        "free_motion_torque_Nm",
    ];
    let hand = EvaluationSettings {
        study: StudyMetrics::new(asked, &[], Default::default(), Default::default()),
        ..EvaluationSettings::default()
    };
    group.bench_function("hand/thesis", |b| {
        b.iter(|| assert_eq!(evaluate(&spec, &hand).status, Status::Ok))
    });
    group.finish();
}

criterion_group!(benches, benchmarks);
criterion_main!(benches);
