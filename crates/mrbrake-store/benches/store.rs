//! Cost of the results store next to an FEA evaluation (~0.3 s): one durable insert (a
//! `BEGIN IMMEDIATE` transaction committed with `synchronous=FULL`, so one WAL fsync), eight
//! records in one such transaction (`insert_all`), a key
//! look-up (done per design on `--resume`), and opening a store (two connections plus
//! `PRAGMA quick_check`, which reads the whole file) with 1 000 and 10 000 records.
//!
//! The stores live under Cargo's target temporary directory, on the same file system as the
//! build, not on a RAM disk, so the fsync cost is real.
//!
//! Run with `cargo bench -p mrbrake-store --bench store`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_store::{Record, Status, Store};

/// A record of realistic size: a ~2 kB design, 6 variables, 15 metrics.
fn realistic_record(index: u64) -> Record {
    let x = index as f64;
    Record {
        key: format!("{index:064x}"),
        status: Status::Ok,
        reason: None,
        variables: (0..6)
            .map(|variable| {
                (format!("variable_{variable}_m"), (1e-3 * (x + f64::from(variable))).into())
            })
            .collect(),
        metrics: (0..15)
            .map(|metric| (format!("metric_{metric}"), (x / (1.0 + f64::from(metric))).into()))
            .collect(),
        spec_toml: "[geometry]\nouter_radius = \"40 mm\"\ngap = \"0.75 mm\"\n".repeat(40),
        eval_seconds: 0.3,
        solver_version: "mrbrake 0.1.0".into(),
        settings: Default::default(),
    }
}

/// A closed store with `count` records, filled in one raw transaction (setup speed only; the
/// rows are exactly what `Store::insert` writes for the first record, with distinct keys).
fn filled_store(directory: &Path, count: i64) -> std::path::PathBuf {
    let path = directory.join(format!("filled-{count}.mrbrake"));
    let mut store = Store::create(&path).expect("create");
    store.insert(&realistic_record(0)).expect("template record");
    drop(store);
    let connection = rusqlite::Connection::open(&path).expect("raw connection");
    connection
        .execute(
            "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < ?1)
             INSERT INTO evaluations (key, status, reason, variables, metrics, spec_toml,
                                      eval_seconds, solver_version, created_unix_s)
             SELECT printf('%064x', n.i), t.status, t.reason, t.variables, t.metrics, t.spec_toml,
                    t.eval_seconds, t.solver_version, t.created_unix_s
             FROM n, (SELECT * FROM evaluations WHERE seq = 1) AS t",
            [count - 1],
        )
        .expect("bulk fill");
    drop(connection);
    path
}

fn store_benches(criterion: &mut Criterion) {
    let directory = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).expect("temporary directory");

    let mut group = criterion.benchmark_group("store");
    group.sample_size(30).measurement_time(Duration::from_secs(8));

    let mut store = Store::create(&directory.path().join("insert.mrbrake")).expect("create");
    let mut next_index = 0_u64;
    group.bench_function("insert_durable", |bencher| {
        bencher.iter_batched(
            || {
                next_index += 1;
                realistic_record(next_index)
            },
            |record| assert!(store.insert(&record).expect("insert")),
            criterion::BatchSize::SmallInput,
        )
    });
    group.bench_function("insert_all_8_records", |bencher| {
        bencher.iter_batched(
            || {
                (0..8)
                    .map(|_| {
                        next_index += 1;
                        realistic_record(next_index)
                    })
                    .collect::<Vec<_>>()
            },
            |records| store.insert_all(&records).expect("insert batch"),
            criterion::BatchSize::SmallInput,
        )
    });
    group.bench_function("contains", |bencher| {
        let key = realistic_record(1).key;
        bencher.iter(|| black_box(store.contains(black_box(&key)).expect("contains")))
    });
    drop(store);

    for count in [1_000, 10_000] {
        let path = filled_store(directory.path(), count);
        let size_mb = std::fs::metadata(&path).map_or(0.0, |m| m.len() as f64 / 1e6);
        eprintln!("store with {count} records: {size_mb:.1} MB");
        group.bench_function(format!("open_{count}_records"), |bencher| {
            bencher.iter(|| black_box(Store::open(&path).expect("open")))
        });
    }
    group.finish();
}

criterion_group!(benches, store_benches);
criterion_main!(benches);
