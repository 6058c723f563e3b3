//! Files that are not usable stores are refused with a clear error naming the path, and are left
//! byte-for-byte unchanged (issue 7: "A corrupt or foreign database file is a clear error, never
//! silently overwritten").

use mrbrake_error::Kind as _;
use std::path::{Path, PathBuf};

use mrbrake_store::{Record, Status, Store, StoreError};

fn record(index: u32) -> Record {
    Record {
        key: format!("{index:064x}"),
        status: Status::Ok,
        reason: None,
        variables: vec![("gap_m".into(), 1e-3.into())],
        metrics: vec![("torque_on_nm".into(), f64::from(index).into())],
        spec_toml: "[geometry]\nouter_radius = \"40 mm\"\n".repeat(20),
        eval_seconds: 0.3,
        solver_version: "test".into(),
        settings: Default::default(),
    }
}

/// A closed store with `count` records (several pages), at `directory/name`.
fn real_store(directory: &Path, name: &str, count: u32) -> PathBuf {
    let path = directory.join(name);
    let mut store = Store::create(&path).expect("create");
    for index in 0..count {
        store.insert(&record(index)).expect("insert");
    }
    path
}

/// Deterministic pseudo-random bytes.
fn noise(length: usize, mut state: u64) -> Vec<u8> {
    (0..length)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 56) as u8
        })
        .collect()
}

/// Every entry point that reads an existing file refuses `path` with an error matching `expected`,
/// mentioning the path, classed as an input error; the file's bytes are unchanged.
fn assert_refused(path: &Path, expected: fn(&StoreError) -> bool) {
    let before = std::fs::read(path).ok();
    let listing_before = listing(path.parent().expect("parent"));
    let destination_directory = tempfile::tempdir().expect("temporary directory");
    let mut destination =
        Store::create(&destination_directory.path().join("destination.mrbrake")).expect("create");

    let attempts = [
        ("open", Store::open(path).map(drop)),
        ("open_read_only", Store::open_read_only(path).map(drop)),
        ("open_or_create(resume)", Store::open_or_create(path, true).map(drop)),
        ("merge_from", destination.merge_from(path).map(drop)),
    ];
    for (entry, result) in attempts {
        let error = result.expect_err(entry);
        assert!(expected(&error), "{entry}: unexpected error {error:?}");
        let message = error.to_string();
        assert!(
            message.contains(&path.display().to_string()),
            "{entry}: message does not name the file: {message}"
        );
        assert!(error.is_input_error(), "{entry}: {error:?} should be an input error");
    }
    assert_eq!(std::fs::read(path).ok(), before, "the refused file was modified");
    assert_eq!(
        listing(path.parent().expect("parent")),
        listing_before,
        "files appeared or vanished beside the refused file"
    );
    assert!(destination.is_empty().expect("is_empty"));
}

fn listing(directory: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(directory)
        .expect("list directory")
        .map(|entry| entry.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn corrupt(error: &StoreError) -> bool {
    matches!(error, StoreError::Corrupt { .. })
}

#[test]
fn random_bytes_are_corrupt() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("noise.mrbrake");
    std::fs::write(&path, noise(20_000, 7)).expect("write noise");
    assert_refused(&path, corrupt);
}

#[test]
fn random_bytes_behind_the_sqlite_magic_are_corrupt() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("fake.mrbrake");
    let mut bytes = b"SQLite format 3\0".to_vec();
    bytes.extend(noise(20_000, 11));
    std::fs::write(&path, bytes).expect("write fake database");
    assert_refused(&path, corrupt);
}

#[test]
fn truncated_copies_of_a_real_store_are_corrupt() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let original = real_store(directory.path(), "original.mrbrake", 200);
    let bytes = std::fs::read(&original).expect("read store");
    assert!(bytes.len() > 16 * 4096, "the store spans many pages: {}", bytes.len());
    let page = 4096;
    let pages = bytes.len() / page;
    // Unaligned lengths are caught by the file checks; whole-page truncations by SQLite itself.
    for length in [10, 50, 100, page + 17, page, 2 * page, pages / 2 * page, (pages - 1) * page] {
        let path = directory.path().join(format!("truncated-{length}.mrbrake"));
        std::fs::write(&path, &bytes[..length]).expect("write truncated copy");
        assert_refused(&path, corrupt);
        eprintln!("{length} bytes: {}", Store::open(&path).expect_err("truncated"));
    }
}

#[test]
fn a_store_with_damaged_pages_is_corrupt() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let original = real_store(directory.path(), "original.mrbrake", 200);
    let bytes = std::fs::read(&original).expect("read store");
    let page = 4096;
    // Page 1 after the file header holds the schema; later pages hold the records.
    for (name, start) in [("schema", 100), ("middle", bytes.len() / page / 2 * page)] {
        let mut damaged = bytes.clone();
        let end = (start + page).min(damaged.len()) - 100;
        damaged[start..end].copy_from_slice(&noise(end - start, start as u64));
        let path = directory.path().join(format!("damaged-{name}.mrbrake"));
        std::fs::write(&path, &damaged).expect("write damaged copy");
        assert_refused(&path, corrupt);
        eprintln!("{name}: {}", Store::open(&path).expect_err("damaged"));
    }
}

#[test]
fn an_empty_file_is_refused_not_initialised() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("empty.mrbrake");
    std::fs::write(&path, b"").expect("write empty file");
    assert_refused(&path, corrupt);
    let error = Store::create(&path).expect_err("create on an empty file");
    assert!(matches!(error, StoreError::Exists { .. }), "{error:?}");
    assert!(error.to_string().contains("--resume"), "{error}");
    let error = Store::open_or_create(&path, false).expect_err("no resume");
    assert!(matches!(error, StoreError::Exists { .. }), "{error:?}");
    assert_eq!(std::fs::metadata(&path).expect("still there").len(), 0);
}

#[test]
fn a_foreign_sqlite_database_is_refused_and_untouched() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("inventory.db");
    {
        let connection = rusqlite::Connection::open(&path).expect("create foreign database");
        connection
            .execute_batch(
                "CREATE TABLE parts (id INTEGER PRIMARY KEY, name TEXT);
                 INSERT INTO parts (name) VALUES ('rotor'), ('coil');",
            )
            .expect("fill foreign database");
    }
    assert_refused(&path, |error| matches!(error, StoreError::Foreign { .. }));
    let message = Store::open(&path).expect_err("foreign").to_string();
    assert!(message.contains("parts"), "the message lists the tables: {message}");
    assert!(message.contains("not an mrbrake results store"), "{message}");
    let listing: Vec<String> = std::fs::read_dir(directory.path())
        .expect("list")
        .map(|entry| entry.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(listing, vec!["inventory.db".to_owned()], "no side files were left");
}

#[test]
fn a_newer_schema_is_refused_with_both_versions() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = real_store(directory.path(), "future.mrbrake", 3);
    {
        let connection = rusqlite::Connection::open(&path).expect("raw connection");
        connection.pragma_update(None, "user_version", 99).expect("pretend a newer schema");
    }
    assert_refused(&path, |error| {
        matches!(
            error,
            StoreError::Version { found: 99, supported: mrbrake_store::schema::SCHEMA_VERSION, .. }
        )
    });
}

#[test]
fn an_mrbrake_id_without_the_tables_is_corrupt() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("hollow.mrbrake");
    {
        let connection = rusqlite::Connection::open(&path).expect("raw connection");
        connection
            .execute_batch("CREATE TABLE meta (name TEXT PRIMARY KEY, value TEXT);")
            .expect("partial schema");
        connection
            .pragma_update(None, "application_id", mrbrake_store::schema::APPLICATION_ID)
            .expect("application id");
        connection.pragma_update(None, "user_version", 1).expect("version");
    }
    assert_refused(&path, corrupt);
    let message = Store::open(&path).expect_err("hollow").to_string();
    assert!(message.contains("evaluations"), "{message}");
}

#[test]
fn a_directory_is_not_a_store() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("folder.mrbrake");
    std::fs::create_dir(&path).expect("make directory");
    assert_refused(&path, |error| matches!(error, StoreError::NotAFile { .. }));
    for result in [Store::create(&path), Store::open_or_create(&path, false)] {
        let error = result.expect_err("directory");
        assert!(matches!(error, StoreError::NotAFile { .. }), "{error:?}");
    }
}

#[test]
fn a_missing_file_is_not_found_and_not_created_by_open() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("missing.mrbrake");
    for result in [Store::open(&path).map(drop), Store::open_read_only(&path).map(drop)] {
        let error = result.expect_err("missing");
        assert!(matches!(error, StoreError::NotFound { .. }), "{error:?}");
        assert!(error.to_string().contains(&path.display().to_string()));
        assert!(error.is_input_error());
    }
    assert!(!path.exists(), "open must not create a store");
}

#[test]
fn a_missing_parent_directory_is_an_input_error_naming_it() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let parent = directory.path().join("no-such-directory");
    let error = Store::create(&parent.join("study.mrbrake")).expect_err("no parent");
    assert!(matches!(error, StoreError::Io { .. }), "{error:?}");
    assert!(error.is_input_error(), "{error:?}");
    assert!(error.to_string().contains("no-such-directory"), "{error}");
}

#[test]
fn creating_over_an_existing_store_keeps_its_records() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = real_store(directory.path(), "kept.mrbrake", 5);
    let before = std::fs::read(&path).expect("read");
    let error = Store::create(&path).expect_err("exists");
    assert!(matches!(error, StoreError::Exists { .. }), "{error:?}");
    assert_eq!(std::fs::read(&path).expect("read"), before);
    assert_eq!(Store::open(&path).expect("open").len().expect("len"), 5);
}
