//! Damaged stores are never read back silently changed (issue 18, class 7): a byte flipped anywhere
//! in a store file is either refused with a message naming the file (and the record, when one
//! record is damaged) or read back identical. Stores written before checksums (schema version 1)
//! stay readable, unverified, and are migrated when opened for writing. Readers leave no `-wal` or
//! `-shm` files behind.

use std::path::{Path, PathBuf};

use mrbrake_store::{Record, Status, Store, StoreError};

fn record(index: u32) -> Record {
    Record {
        key: format!("{:064x}", u64::from(index) * 0x9e37_79b9 + 1),
        status: if index % 3 == 2 { Status::Failed } else { Status::Ok },
        reason: (index % 3 == 2).then(|| format!("design {index}: gap below 0.1 mm")),
        variables: vec![
            ("gap_m".into(), (1e-4 * f64::from(index + 1)).into()),
            ("turns".into(), 120.0.into()),
        ],
        metrics: vec![
            ("torque_on_nm".into(), (3.0 + f64::from(index) / 7.0).into()),
            ("ratio".into(), f64::INFINITY.into()),
            ("mass_kg".into(), (0.25 + f64::from(index) * 1e-3).into()),
        ],
        spec_toml: format!("[geometry]\n# design {index}\ngap = \"{} mm\"\n", index + 1),
        eval_seconds: 0.1 + f64::from(index) * 1e-3,
        solver_version: "mrbrake 0.1.0 (test)".into(),
        settings: Default::default(),
    }
}

/// A closed store with `count` records at `directory/name`.
fn store_with(directory: &Path, name: &str, count: u32) -> PathBuf {
    let path = directory.join(name);
    let mut store = Store::create(&path).expect("create");
    for index in 0..count {
        store.insert(&record(index)).expect("insert");
    }
    store.set_meta("study", "damage test").expect("meta");
    store.close().expect("close");
    path
}

/// Records compared bit for bit (NaN and infinities included).
fn fingerprint(records: &[Record]) -> Vec<String> {
    records
        .iter()
        .map(|r| {
            let bits = |values: &[(String, mrbrake_store::MetricValue)]| {
                values.iter().map(|(n, v)| format!("{n}={v:?}")).collect::<Vec<_>>()
            };
            format!(
                "{}|{}|{:?}|{:?}|{:?}|{:?}|{:x}|{}",
                r.key,
                r.status,
                r.reason,
                r.variables.iter().map(|(n, v)| format!("{n}={v:?}")).collect::<Vec<_>>(),
                bits(&r.metrics),
                r.spec_toml,
                r.eval_seconds.to_bits(),
                r.solver_version
            )
        })
        .collect()
}

fn side_files(path: &Path) -> Vec<PathBuf> {
    ["-wal", "-shm"]
        .iter()
        .map(|suffix| {
            let mut side = path.as_os_str().to_owned();
            side.push(suffix);
            PathBuf::from(side)
        })
        .filter(|side| side.exists())
        .collect()
}

/// Flips one bit at each of a deterministic set of positions over the whole file (header, schema,
/// B-tree pages, record payloads, free space): every copy is refused with a message naming it, or
/// reads back the same records.
#[test]
fn a_flipped_byte_is_refused_or_harmless_never_silent() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let original = store_with(directory.path(), "original.mrbrake", 12);
    let bytes = std::fs::read(&original).expect("read store");
    let reference =
        fingerprint(&Store::open_read_only(&original).expect("open").records().expect("records"));
    let copy = directory.path().join("flipped.mrbrake");
    let (mut refused, mut identical) = (0, 0);
    // A stride coprime to the page size visits every offset within a page over the file.
    for (n, position) in (0..bytes.len()).step_by(11).enumerate() {
        let mut damaged = bytes.clone();
        damaged[position] ^= 1 << (n % 8);
        std::fs::write(&copy, &damaged).expect("write copy");
        let read = Store::open_read_only(&copy).and_then(|store| store.records());
        match read {
            Ok(records) => {
                assert_eq!(
                    fingerprint(&records),
                    reference,
                    "flip at byte {position} (bit {}) changed the records silently",
                    n % 8
                );
                identical += 1;
            }
            Err(error) => {
                let message = error.to_string();
                assert!(message.contains(&*copy.to_string_lossy()), "{message}");
                refused += 1;
            }
        }
        for side in side_files(&copy) {
            std::fs::remove_file(side).expect("remove side file");
        }
    }
    eprintln!("{} bytes, {refused} flips refused, {identical} read back identical", bytes.len());
    assert!(refused > 0 && identical > 0, "{refused} refused, {identical} identical");
}

/// A record edited behind the store's back (the sqlite3 shell, a bad sector inside a text) is
/// refused by every reader, naming the file and the record.
#[test]
fn an_edited_record_is_refused_naming_file_and_key() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = store_with(directory.path(), "edited.mrbrake", 3);
    let key = record(1).key;
    {
        let raw = rusqlite::Connection::open(&path).expect("raw connection");
        let changed = raw
            .execute(
                "UPDATE evaluations SET metrics = replace(metrics, 'torque_on_nm', 'torque_on_nx') \
                 WHERE key = ?1",
                [&key],
            )
            .expect("edit");
        assert_eq!(changed, 1);
    }
    let store = Store::open(&path).expect("the file itself is sound");
    let errors = [store.records().expect_err("records"), store.get(&key).expect_err("get"), {
        let mut destination =
            Store::create(&directory.path().join("merged.mrbrake")).expect("create");
        destination.merge_from(&path).expect_err("merge")
    }];
    for error in errors {
        assert!(matches!(error, StoreError::Decode { .. }), "{error:?}");
        let message = error.to_string();
        assert!(message.contains("edited.mrbrake") && message.contains(&key), "{message}");
        assert!(message.contains("checksum mismatch"), "{message}");
    }
    assert!(store.get(&record(0).key).expect("an undamaged record").is_some());
}

/// Turns a fresh store into one as schema version 1 wrote it: no checksum column.
fn make_version_1(path: &Path) {
    let raw = rusqlite::Connection::open(path).expect("raw connection");
    raw.execute_batch("ALTER TABLE evaluations DROP COLUMN checksum; PRAGMA user_version = 1;")
        .expect("downgrade");
}

#[test]
fn a_version_1_store_reads_unverified_and_migrates_on_write() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = store_with(directory.path(), "old.mrbrake", 4);
    make_version_1(&path);
    let expected = fingerprint(&(0..4).map(record).collect::<Vec<_>>());

    let reader = Store::open_read_only(&path).expect("a version-1 store opens");
    assert_eq!(fingerprint(&reader.records().expect("records")), expected);
    assert_eq!(reader.unverified_len().expect("count"), 4);
    reader.close().expect("close");

    // Merged records stay unverified: nobody checked them.
    let mut merged = Store::create(&directory.path().join("merged.mrbrake")).expect("create");
    merged.insert(&record(9)).expect("insert");
    assert_eq!(merged.merge_from(&path).expect("merge").inserted, 4);
    assert_eq!(merged.unverified_len().expect("count"), 4);

    let mut writer = Store::open(&path).expect("open for writing migrates");
    writer.insert(&record(5)).expect("insert after migration");
    assert_eq!(writer.unverified_len().expect("count"), 4);
    assert_eq!(writer.records().expect("records").len(), 5);
    let version: i64 = rusqlite::Connection::open(&path)
        .expect("raw")
        .pragma_query_value(None, "user_version", |row| row.get(0))
        .expect("version");
    assert_eq!(version, mrbrake_store::schema::SCHEMA_VERSION);
}

/// A store as schema version 3 wrote it (the same columns, metrics all numbers) opens, reads
/// verified and takes bounds once opened for writing, which raises its version mark to 4.
#[test]
fn a_version_3_store_reads_verified_and_takes_bounds_after_opening_for_writing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = store_with(directory.path(), "v3.mrbrake", 3);
    rusqlite::Connection::open(&path)
        .expect("raw")
        .execute_batch("PRAGMA user_version = 3;")
        .expect("downgrade");
    let expected = fingerprint(&(0..3).map(record).collect::<Vec<_>>());
    let reader = Store::open_read_only(&path).expect("a version-3 store opens");
    assert_eq!(fingerprint(&reader.records().expect("records")), expected);
    assert_eq!(reader.unverified_len().expect("count"), 0);
    reader.close().expect("close");
    let mut writer = Store::open(&path).expect("open for writing");
    let mut bounded = record(7);
    bounded.metrics.push(("bandwidth_rad_s".into(), mrbrake_store::MetricValue::AtLeast(6283.0)));
    writer.insert(&bounded).expect("insert a bound");
    let back = writer.get(&bounded.key).expect("get").expect("stored");
    assert_eq!(
        back.metric_value("bandwidth_rad_s"),
        Some(mrbrake_store::MetricValue::AtLeast(6283.0))
    );
    let version: i64 = rusqlite::Connection::open(&path)
        .expect("raw")
        .pragma_query_value(None, "user_version", |row| row.get(0))
        .expect("version");
    assert_eq!(version, 4);
}

/// Without a checksum to catch it first, a text that is no longer UTF-8 is named once, with the
/// record, not as a SQLite conversion error.
#[test]
fn invalid_utf8_in_an_unverified_record_names_the_record_once() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = store_with(directory.path(), "bytes.mrbrake", 2);
    make_version_1(&path);
    let key = record(0).key;
    rusqlite::Connection::open(&path)
        .expect("raw")
        .execute(
            "UPDATE evaluations SET spec_toml = CAST(x'5bff5d' AS TEXT) WHERE key = ?1",
            [&key],
        )
        .expect("edit");
    let error = Store::open_read_only(&path).expect("open").records().expect_err("bad text");
    let message = error.to_string();
    assert!(message.contains(&key) && message.contains("spec_toml: not valid UTF-8"), "{message}");
    assert_eq!(message.matches("invalid utf-8").count(), 1, "{message}");
    assert!(std::error::Error::source(&error).is_none(), "no cause repeating the message");
}

#[test]
fn readers_and_merges_leave_no_side_files() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let input = store_with(directory.path(), "shard.mrbrake", 3);
    assert!(side_files(&input).is_empty(), "a closed writer removes its side files");
    let reader = Store::open_read_only(&input).expect("open");
    assert_eq!(reader.len().expect("len"), 3);
    drop(reader);
    assert!(side_files(&input).is_empty(), "{:?}", side_files(&input));
    let mut merged = Store::create(&directory.path().join("merged.mrbrake")).expect("create");
    merged.merge_from(&input).expect("merge");
    assert!(side_files(&input).is_empty(), "{:?}", side_files(&input));
}
