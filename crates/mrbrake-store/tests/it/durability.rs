//! Durability under `kill -9` and concurrent writers (issue 7, "Reliability").
//!
//! The writer is this very test binary run again as a child process: the `child_writer` test
//! (ignored in normal runs) opens the store named by `MRBRAKE_STORE_CHILD` and inserts the
//! expected records in a given order. The parent kills it with SIGKILL (`Child::kill` on Unix)
//! after a pseudo-random delay, reopens the store (which runs `PRAGMA quick_check`) and checks
//! that every record present is complete and exact, stored once, and that `seq` has no gap;
//! then it lets a last child finish and checks the final set is exactly the expected one.
//!
//! Set `MRBRAKE_STORE_SEED` to replay a run; the seed in use is printed.

use std::collections::HashSet;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use mrbrake_store::{MetricValue, Record, Status, Store};

/// Path of the store the child writes to; unset in normal test runs.
const CHILD_ENV: &str = "MRBRAKE_STORE_CHILD";
/// Insertion order of the child: `forward`, `reverse` or `interleaved`.
const ORDER_ENV: &str = "MRBRAKE_STORE_CHILD_ORDER";
/// Number of designs in the study.
const TOTAL: u32 = 300;

/// The deterministic record of design `index`, with a spec large enough (~3 kB) that an insert
/// spans several database pages.
fn expected_record(index: u32) -> Record {
    let status = match index % 10 {
        7 => Status::Infeasible,
        9 => Status::Failed,
        _ => Status::Ok,
    };
    let ok = status == Status::Ok;
    let x = f64::from(index);
    Record {
        key: format!("{:064x}", u64::from(index).wrapping_mul(0x9e37_79b9_7f4a_7c15)),
        status,
        reason: (!ok).then(|| format!("design {index}: wall thinner than 0.5 mm")),
        variables: vec![
            ("gap_m".into(), (1e-4 * (1.0 + x)).into()),
            ("turns".into(), (50.0 + x).into()),
        ],
        metrics: if ok {
            vec![
                ("torque_on_nm".into(), (1.0 / (3.0 + x)).into()),
                ("dynamic_range".into(), (if index % 13 == 0 { f64::INFINITY } else { x }).into()),
                ("b_max_t".into(), (if index % 17 == 0 { f64::NAN } else { 1.5 }).into()),
            ]
        } else {
            vec![]
        },
        spec_toml: format!(
            "# design {index}\n{}",
            "[geometry]\nouter_radius = \"40 mm\"\n".repeat(80)
        ),
        eval_seconds: 0.3 + x * 1e-6,
        solver_version: "mrbrake-test".into(),
        settings: Default::default(),
    }
}

fn index_by_key() -> std::collections::HashMap<String, u32> {
    (0..TOTAL).map(|index| (expected_record(index).key, index)).collect()
}

fn order(name: &str) -> Vec<u32> {
    match name {
        "reverse" => (0..TOTAL).rev().collect(),
        "interleaved" => (0..TOTAL).step_by(2).chain((1..TOTAL).step_by(2)).collect(),
        _ => (0..TOTAL).collect(),
    }
}

/// The child process body; does nothing (and passes) unless run by a parent test.
#[test]
#[ignore = "child process of the durability tests; a no-op unless MRBRAKE_STORE_CHILD is set"]
fn child_writer() {
    let Some(path) = std::env::var_os(CHILD_ENV) else {
        return;
    };
    let order_name = std::env::var(ORDER_ENV).unwrap_or_default();
    let mut store = Store::open(Path::new(&path)).expect("child opens the store");
    for index in order(&order_name) {
        store.insert(&expected_record(index)).expect("child inserts");
    }
}

fn spawn_writer(path: &Path, order_name: &str) -> Child {
    // The test's full name in this binary: its module path without the crate's name.
    let child_test =
        module_path!().split_once("::").map_or(String::new(), |(_, m)| format!("{m}::"))
            + "child_writer";
    Command::new(std::env::current_exe().expect("test binary path"))
        .args([child_test.as_str(), "--exact", "--ignored", "--nocapture", "--test-threads=1"])
        .env(CHILD_ENV, path)
        .env(ORDER_ENV, order_name)
        // The child's test-harness chatter is noise; its panics (stderr) stay visible.
        .stdout(Stdio::null())
        .spawn()
        .expect("spawn child writer")
}

/// xorshift64*: a tiny reproducible generator for kill delays.
struct Random(u64);

impl Random {
    fn from_env_or_clock() -> Random {
        let seed = std::env::var("MRBRAKE_STORE_SEED")
            .ok()
            .and_then(|text| text.parse().ok())
            .unwrap_or_else(|| {
                SystemTime::now()
                    .duration_since(UNIX_EPOCH)
                    .map_or(1, |elapsed| elapsed.as_nanos() as u64)
            })
            | 1;
        eprintln!("MRBRAKE_STORE_SEED={seed}");
        Random(seed)
    }

    fn below(&mut self, bound: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % bound
    }
}

fn same_bits(a: &[(String, MetricValue)], b: &[(String, MetricValue)]) -> bool {
    let bits = |v: &MetricValue| v.value().map(f64::to_bits);
    a.len() == b.len()
        && a.iter().zip(b).all(|((na, va), (nb, vb))| na == nb && bits(va) == bits(vb))
}

/// Reopens the store with all checks and verifies its invariants; returns the stored indices
/// in insertion order.
fn check_store(path: &Path) -> Vec<u32> {
    let store = Store::open(path).expect("reopen after kill passes the integrity checks");
    let records = store.records().expect("records");
    let index_by_key = index_by_key();
    let mut indices = Vec::with_capacity(records.len());
    for record in &records {
        let index = *index_by_key.get(&record.key).expect("every stored key is an expected design");
        let expected = expected_record(index);
        assert!(
            record.status == expected.status
                && record.reason == expected.reason
                && record.variables == expected.variables
                && same_bits(&record.metrics, &expected.metrics)
                && record.spec_toml == expected.spec_toml
                && record.eval_seconds.to_bits() == expected.eval_seconds.to_bits()
                && record.solver_version == expected.solver_version,
            "record {index} is incomplete or altered: {record:?}"
        );
        indices.push(index);
    }
    let unique: HashSet<u32> = indices.iter().copied().collect();
    assert_eq!(unique.len(), indices.len(), "a design is stored twice");
    assert_eq!(store.keys().expect("keys").len(), indices.len());

    let connection =
        rusqlite::Connection::open_with_flags(path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
            .expect("raw read-only connection");
    let sequence: Vec<i64> = connection
        .prepare("SELECT seq FROM evaluations ORDER BY seq")
        .expect("prepare")
        .query_map([], |row| row.get(0))
        .expect("query")
        .collect::<rusqlite::Result<_>>()
        .expect("rows");
    let contiguous: Vec<i64> = (1..=sequence.len() as i64).collect();
    assert_eq!(sequence, contiguous, "seq has a gap or does not start at 1");
    indices
}

#[test]
fn sigkill_at_random_moments_loses_and_duplicates_nothing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let store_path = |attempt: usize| directory.path().join(format!("study-{attempt}.mrbrake"));
    let mut attempt = 0;
    let mut path = store_path(attempt);
    drop(Store::create(&path).expect("create"));
    let mut random = Random::from_env_or_clock();
    // How long a whole uninterrupted run takes on this machine (a fast disk stores all designs
    // in a few milliseconds, a loaded one in a second): the kills fall inside that time, so a
    // round kills a running writer whatever the machine.
    let full_run_us = {
        let scratch = directory.path().join("timing.mrbrake");
        drop(Store::create(&scratch).expect("create"));
        let start = std::time::Instant::now();
        let status = spawn_writer(&scratch, "forward").wait().expect("timing run");
        assert!(status.success(), "the uninterrupted writer failed");
        (start.elapsed().as_micros() as u64).max(2)
    };

    // A machine whose load drops after the timing run can let a writer finish before its kill:
    // then the window halves, and a store completed without any kill starts again empty, so the
    // test always ends with writers killed while running (bounded: 40 rounds).
    let mut window_us = (full_run_us * 3 / 4).max(1);
    let mut killed_while_running = 0;
    let mut stored_after_kills = Vec::new();
    for _round in 0..40 {
        let mut child = spawn_writer(&path, "forward");
        std::thread::sleep(Duration::from_micros(random.below(window_us).max(1)));
        child.kill().expect("SIGKILL the writer");
        let status = child.wait().expect("reap child");
        // The writer may finish between the sleep and the kill: only a child the signal ended
        // was killed while running; any other must have succeeded on its own.
        if std::os::unix::process::ExitStatusExt::signal(&status) == Some(9) {
            killed_while_running += 1;
        } else {
            assert!(status.success(), "the writer failed on its own: {status}");
            window_us = (window_us / 2).max(1);
        }
        let indices = check_store(&path);
        // A forward writer that skips stored keys always leaves a prefix of the design list.
        let prefix: Vec<u32> = (0..indices.len() as u32).collect();
        assert_eq!(indices, prefix, "the store is not a prefix of the insertion order");
        stored_after_kills.push(indices.len());
        let complete = indices.len() == TOTAL as usize;
        if killed_while_running > 0 && (complete || stored_after_kills.len() >= 6) {
            break;
        }
        if complete {
            attempt += 1;
            path = store_path(attempt);
            drop(Store::create(&path).expect("create"));
        }
    }
    eprintln!("records stored after each SIGKILL: {stored_after_kills:?} of {TOTAL}");
    assert!(
        killed_while_running > 0,
        "no child was still running when killed; the test proved nothing"
    );

    let status = spawn_writer(&path, "forward").wait().expect("final child");
    assert!(status.success(), "the resuming writer fails: {status}");
    let indices = check_store(&path);
    assert_eq!(indices, (0..TOTAL).collect::<Vec<_>>());
}

#[test]
fn concurrent_writers_never_duplicate_even_when_one_is_killed() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("shared.mrbrake");
    drop(Store::create(&path).expect("create"));
    let mut random = Random::from_env_or_clock();

    let mut victim = spawn_writer(&path, "interleaved");
    let forward = spawn_writer(&path, "forward");
    let reverse = spawn_writer(&path, "reverse");
    std::thread::sleep(Duration::from_millis(5 + random.below(100)));
    victim.kill().expect("SIGKILL one writer");
    victim.wait().expect("reap killed writer");
    for (name, child) in [("forward", forward), ("reverse", reverse)] {
        let status = child.wait_with_output().expect("writer finishes").status;
        assert!(status.success(), "{name} writer failed: {status}");
    }

    let indices = check_store(&path);
    let stored: HashSet<u32> = indices.into_iter().collect();
    assert_eq!(stored, (0..TOTAL).collect::<HashSet<_>>());
}
