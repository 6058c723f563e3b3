//! [`Store`]: one SQLite file holding every evaluation of a study.
//!
//! Life cycle: [`Store::create`] builds the schema in a temporary file beside the target and
//! links it into place only when complete, so a store file is never half-created and never
//! replaces an existing file; [`Store::open`] checks the file (see [`crate::schema`]) on a
//! read-only connection before opening it for writing in WAL mode with `synchronous=FULL`;
//! [`Store::insert`] writes one record per `BEGIN IMMEDIATE` transaction, so it is on disk when
//! the call returns.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use rusqlite::{Connection, OpenFlags, OptionalExtension, TransactionBehavior};

use crate::row::{RECORD_COLUMNS_SQL, RawRow, StoredRecord, insert_new, read_row};
use crate::schema::{self, APPLICATION_ID, BUSY_TIMEOUT, SCHEMA_VERSION};
use crate::{Record, StoreError};

/// A results store: the evaluations of a study, keyed by design hash, in one SQLite file.
///
/// Several processes may append to the same store at once: each insert is one write transaction
/// and a key already present is skipped, never duplicated or overwritten.
#[derive(Debug)]
pub struct Store {
    path: PathBuf,
    connection: Connection,
    read_only: bool,
    /// False for a store of schema version 1 opened read-only (no `checksum` column yet).
    has_checksums: bool,
    /// Whether `evaluations` has the `settings` column (schema version 3).
    has_settings: bool,
}

impl Store {
    /// Creates a new, empty store at `path`.
    ///
    /// Fails with [`StoreError::Exists`] if anything exists at `path` (even an empty file) and
    /// with [`StoreError::NotAFile`] if it is a directory. The schema is built in a temporary file
    /// in the same directory, then hard-linked to `path` (which fails rather than replace a file
    /// created meanwhile) and the directory is synced; a crash leaves either no store or a
    /// complete empty one, plus at most a stray `.NAME.creating-*` file.
    pub fn create(path: &Path) -> Result<Store, StoreError> {
        refuse_existing(path)?;
        let staging = StagingFile::new(path);
        build_empty_store(&staging.path).map_err(|error| match error {
            StoreError::Sqlite { source, .. } => schema::sqlite_error(path, source),
            other => other,
        })?;
        publish(&staging.path, path)?;
        drop(staging);
        sync_parent_directory(path)?;
        Store::open(path)
    }

    /// Opens an existing store for reading and appending.
    ///
    /// Refuses, without modifying the file: a missing path ([`StoreError::NotFound`]), a
    /// directory ([`StoreError::NotAFile`]), an empty or non-SQLite or damaged file
    /// ([`StoreError::Corrupt`]), another application's SQLite database
    /// ([`StoreError::Foreign`]) and a store from a newer schema ([`StoreError::Version`]).
    pub fn open(path: &Path) -> Result<Store, StoreError> {
        Store::open_checked(path, false)
    }

    /// Opens an existing store read-only, with the same checks as [`Store::open`]. Inserts and
    /// [`Store::set_meta`] then fail with [`StoreError::ReadOnly`]. Useful to inspect a store
    /// (for instance compare its meta data) before merging it. Once closed it leaves no `-wal` or
    /// `-shm` file beside the store that was not there before (unless the store file is
    /// write-protected: SQLite then needs a read-only connection, which cannot remove them).
    pub fn open_read_only(path: &Path) -> Result<Store, StoreError> {
        Store::open_checked(path, true)
    }

    /// Opens the store at `path` if it exists and `resume` is set, creates it if it does not
    /// exist, and fails with [`StoreError::Exists`] if it exists and `resume` is not set.
    pub fn open_or_create(path: &Path, resume: bool) -> Result<Store, StoreError> {
        match std::fs::symlink_metadata(path) {
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
                match Store::create(path) {
                    // Another process created it between our look and our link.
                    Err(StoreError::Exists { .. }) if resume => Store::open(path),
                    other => other,
                }
            }
            Err(source) => Err(StoreError::Io { path: path.to_owned(), source }),
            Ok(_) if resume => Store::open(path),
            Ok(metadata) => Err(existing_error(path, &metadata)),
        }
    }

    /// Closes the store, reporting any error SQLite meets while doing so (dropping a store
    /// closes it too, silently). The last connection to close checkpoints the WAL into the main
    /// file and removes the `-wal` and `-shm` side files.
    pub fn close(self) -> Result<(), StoreError> {
        let path = self.path;
        self.connection.close().map_err(|(_, error)| schema::sqlite_error(&path, error))
    }

    /// The path the store was opened with.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// True when an evaluation with this key is stored.
    pub fn contains(&self, key: &str) -> Result<bool, StoreError> {
        self.connection
            .prepare_cached("SELECT EXISTS (SELECT 1 FROM evaluations WHERE key = ?1)")
            .and_then(|mut statement| statement.query_row([key], |row| row.get(0)))
            .map_err(|error| self.sqlite_error(error))
    }

    /// The evaluation stored under `key`, if any.
    pub fn get(&self, key: &str) -> Result<Option<Record>, StoreError> {
        let row = self
            .connection
            .prepare_cached(&format!("{} WHERE key = ?1", self.select_records_sql()))
            .and_then(|mut statement| statement.query_row([key], read_row).optional())
            .map_err(|error| self.sqlite_error(error))?;
        row.map(|row| self.decode(row).map(|stored| stored.record)).transpose()
    }

    /// Stores `record` durably (the transaction is committed with `synchronous=FULL` before this
    /// returns). Returns `false`, changing nothing, if its key is already stored: a stored
    /// evaluation is never overwritten. Fails with [`StoreError::InvalidRecord`] if the record
    /// breaks the record contract (see [`Record::validate`]).
    pub fn insert(&mut self, record: &Record) -> Result<bool, StoreError> {
        let inserted = self.insert_all(std::slice::from_ref(record))?;
        Ok(inserted[0])
    }

    /// Stores several records in one durable transaction: one disk flush for all of them instead
    /// of one each (a flush costs milliseconds, see the crate's benchmark). Meant for a writer
    /// that drains the evaluations finished while its previous flush was running. Returns, per
    /// record, whether it was inserted (`false` for a key already stored, including earlier in
    /// the same batch). All records are validated first; on any error nothing is stored.
    pub fn insert_all(&mut self, records: &[Record]) -> Result<Vec<bool>, StoreError> {
        self.refuse_if_read_only()?;
        for record in records {
            record.validate()?;
        }
        let created_unix_s = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0.0, |elapsed| elapsed.as_secs_f64());
        let transaction = self
            .connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|error| schema::sqlite_error(&self.path, error))?;
        let inserted = records
            .iter()
            .map(|record| insert_new(&transaction, record, Some(created_unix_s), true))
            .collect::<rusqlite::Result<Vec<bool>>>()
            .and_then(|inserted| transaction.commit().map(|()| inserted))
            .map_err(|error| schema::sqlite_error(&self.path, error))?;
        Ok(inserted)
    }

    /// Every stored key.
    pub fn keys(&self) -> Result<HashSet<String>, StoreError> {
        self.connection
            .prepare_cached("SELECT key FROM evaluations")
            .and_then(|mut statement| {
                statement.query_map([], |row| row.get::<_, String>(0))?.collect()
            })
            .map_err(|error| self.sqlite_error(error))
    }

    /// Every stored evaluation, in insertion order.
    pub fn records(&self) -> Result<Vec<Record>, StoreError> {
        Ok(self.stored_records()?.into_iter().map(|stored| stored.record).collect())
    }

    /// Number of stored evaluations.
    pub fn len(&self) -> Result<usize, StoreError> {
        let count: i64 = self
            .connection
            .prepare_cached("SELECT count(*) FROM evaluations")
            .and_then(|mut statement| statement.query_row([], |row| row.get(0)))
            .map_err(|error| self.sqlite_error(error))?;
        // A row count is never negative.
        Ok(usize::try_from(count).unwrap_or(0))
    }

    /// True when no evaluation is stored.
    pub fn is_empty(&self) -> Result<bool, StoreError> {
        Ok(self.len()? == 0)
    }

    /// Sets (or replaces) a meta data entry, durably. Meant for small values such as the study
    /// description and its hash, checked when a run is resumed.
    pub fn set_meta(&mut self, name: &str, value: &str) -> Result<(), StoreError> {
        self.refuse_if_read_only()?;
        self.connection
            .execute(
                "INSERT INTO meta (name, value) VALUES (?1, ?2) \
                 ON CONFLICT (name) DO UPDATE SET value = excluded.value",
                [name, value],
            )
            .map(|_| ())
            .map_err(|error| self.sqlite_error(error))
    }

    /// The meta data entry `name`, if set.
    pub fn meta(&self, name: &str) -> Result<Option<String>, StoreError> {
        self.connection
            .prepare_cached("SELECT value FROM meta WHERE name = ?1")
            .and_then(|mut statement| {
                statement.query_row([name], |row| row.get::<_, Option<String>>(0)).optional()
            })
            .map(Option::flatten)
            .map_err(|error| self.sqlite_error(error))
    }

    /// Every meta data entry as `(name, value)`, sorted by name.
    pub fn meta_entries(&self) -> Result<Vec<(String, String)>, StoreError> {
        self.connection
            .prepare_cached("SELECT name, coalesce(value, '') FROM meta ORDER BY name")
            .and_then(|mut statement| {
                statement.query_map([], |row| Ok((row.get(0)?, row.get(1)?)))?.collect()
            })
            .map_err(|error| self.sqlite_error(error))
    }

    /// The connection, for the merge module.
    pub(crate) fn connection(&self) -> &Connection {
        &self.connection
    }

    /// The connection, for the merge module.
    pub(crate) fn connection_mut(&mut self) -> &mut Connection {
        &mut self.connection
    }

    /// Every row with its creation time, in insertion order.
    pub(crate) fn stored_records(&self) -> Result<Vec<StoredRecord>, StoreError> {
        let rows: Vec<RawRow> = self
            .connection
            .prepare_cached(&format!("{} ORDER BY seq", self.select_records_sql()))
            .and_then(|mut statement| statement.query_map([], read_row)?.collect())
            .map_err(|error| self.sqlite_error(error))?;
        rows.into_iter().map(|row| self.decode(row)).collect()
    }

    /// `SELECT` of every record column and the checksum (`NULL` where the store has none).
    pub(crate) fn select_records_sql(&self) -> String {
        let checksum = if self.has_checksums { "checksum" } else { "NULL" };
        let settings = if self.has_settings { "settings" } else { "NULL" };
        format!("SELECT {RECORD_COLUMNS_SQL}, {settings}, {checksum} FROM evaluations")
    }

    /// Number of records without a checksum (written before schema version 2, or merged from such
    /// a store): they are read back unverified.
    pub fn unverified_len(&self) -> Result<usize, StoreError> {
        if !self.has_checksums {
            return self.len();
        }
        let count: i64 = self
            .connection
            .prepare_cached("SELECT count(*) FROM evaluations WHERE checksum IS NULL")
            .and_then(|mut statement| statement.query_row([], |row| row.get(0)))
            .map_err(|error| self.sqlite_error(error))?;
        Ok(usize::try_from(count).unwrap_or(0))
    }

    pub(crate) fn refuse_if_read_only(&self) -> Result<(), StoreError> {
        if self.read_only { Err(StoreError::ReadOnly { path: self.path.clone() }) } else { Ok(()) }
    }

    pub(crate) fn sqlite_error(&self, error: rusqlite::Error) -> StoreError {
        schema::sqlite_error(&self.path, error)
    }

    pub(crate) fn decode(&self, row: RawRow) -> Result<StoredRecord, StoreError> {
        row.decode().map_err(|detail| StoreError::Decode {
            path: self.path.clone(),
            key: detail.0,
            detail: detail.1,
        })
    }

    fn open_checked(path: &Path, read_only: bool) -> Result<Store, StoreError> {
        schema::check_file(path)?;
        let side_files = SideFiles::look(path);
        let checked = open_read_only_and_check(path).inspect_err(|error| {
            if matches!(
                error,
                StoreError::Corrupt { .. }
                    | StoreError::Foreign { .. }
                    | StoreError::Version { .. }
            ) {
                side_files.remove_new_empty_ones();
            }
        })?;
        drop(checked);
        if read_only {
            let connection = open_for_reading(path)?;
            let has_checksums = schema::has_checksum_column(&connection)
                .map_err(|error| schema::sqlite_error(path, error))?;
            let has_settings = schema::has_settings_column(&connection)
                .map_err(|error| schema::sqlite_error(path, error))?;
            return Ok(Store {
                path: path.to_owned(),
                connection,
                read_only,
                has_checksums,
                has_settings,
            });
        }

        // No CREATE flag: if the file vanished since the checks, fail instead of making a new one.
        let connection = Connection::open_with_flags(
            path,
            OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX,
        )
        .map_err(|error| schema::sqlite_error(path, error))?;
        configure_for_writing(&connection).map_err(|error| schema::sqlite_error(path, error))?;
        schema::migrate(&connection).map_err(|error| schema::sqlite_error(path, error))?;
        Ok(Store {
            path: path.to_owned(),
            connection,
            read_only,
            has_checksums: true,
            has_settings: true,
        })
    }
}

/// A read-only connection to `path` on which [`schema::check_store`] passed.
fn open_read_only_and_check(path: &Path) -> Result<Connection, StoreError> {
    let connection = Connection::open_with_flags(
        path,
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(|error| schema::sqlite_error(path, error))?;
    connection.busy_timeout(BUSY_TIMEOUT).map_err(|error| schema::sqlite_error(path, error))?;
    schema::check_store(&connection, path)?;
    Ok(connection)
}

/// A connection that reads `path` and, once closed, leaves no `-wal` or `-shm` file it created.
///
/// A read-only SQLite connection to a WAL-mode database creates those side files and cannot remove
/// them; so, where the file is writable, the reader opens it read-write with `PRAGMA query_only`
/// (SQLite then refuses any write) and the last connection to close removes the side files as
/// SQLite always does. A write-protected file falls back to read-only (SQLite's own fallback).
fn open_for_reading(path: &Path) -> Result<Connection, StoreError> {
    let sqlite = |error| schema::sqlite_error(path, error);
    let connection = Connection::open_with_flags(
        path,
        OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(sqlite)?;
    connection.busy_timeout(BUSY_TIMEOUT).map_err(sqlite)?;
    connection.pragma_update(None, "query_only", true).map_err(sqlite)?;
    Ok(connection)
}

/// The `-wal` and `-shm` files SQLite keeps beside a WAL-mode database, and whether they existed
/// before we opened it. A read-only connection creates them and, unable to checkpoint, leaves
/// them behind; for a file we then refuse, we remove the ones we created so that a refused file
/// leaves its directory as it was.
struct SideFiles {
    wal: PathBuf,
    shm: PathBuf,
    wal_existed: bool,
    shm_existed: bool,
}

impl SideFiles {
    fn look(database: &Path) -> SideFiles {
        let with_suffix = |suffix: &str| {
            let mut side = database.as_os_str().to_owned();
            side.push(suffix);
            PathBuf::from(side)
        };
        let (wal, shm) = (with_suffix("-wal"), with_suffix("-shm"));
        SideFiles { wal_existed: wal.exists(), shm_existed: shm.exists(), wal, shm }
    }

    /// Removes the side files that did not exist before, and only if the WAL holds nothing: a
    /// non-empty WAL was written by someone else and is never touched.
    fn remove_new_empty_ones(&self) {
        let wal_is_empty_or_absent =
            std::fs::metadata(&self.wal).map_or(true, |metadata| metadata.len() == 0);
        if self.wal_existed || !wal_is_empty_or_absent {
            return;
        }
        // Best effort: leftover side files are harmless.
        let _ = std::fs::remove_file(&self.wal);
        if !self.shm_existed {
            let _ = std::fs::remove_file(&self.shm);
        }
    }
}

/// Busy timeout, WAL journal and full synchronisation: a committed transaction survives a crash
/// of the process or of the machine.
fn configure_for_writing(connection: &Connection) -> rusqlite::Result<()> {
    connection.busy_timeout(BUSY_TIMEOUT)?;
    let mode: String =
        connection.pragma_update_and_check(None, "journal_mode", "WAL", |row| row.get(0))?;
    if !mode.eq_ignore_ascii_case("wal") {
        // A file system without shared memory support (some network mounts) cannot do WAL.
        return Err(rusqlite::Error::SqliteFailure(
            rusqlite::ffi::Error::new(rusqlite::ffi::SQLITE_CANTOPEN),
            Some(format!(
                "cannot switch to WAL journal mode (got {mode:?}); is the store on a network file system?"
            )),
        ));
    }
    connection.pragma_update(None, "synchronous", "FULL")?;
    Ok(())
}

/// Fails unless nothing exists at `path` and its parent is an existing directory.
fn refuse_existing(path: &Path) -> Result<(), StoreError> {
    match std::fs::symlink_metadata(path) {
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {}
        Err(source) => {
            return Err(StoreError::Io { path: path.to_owned(), source });
        }
        Ok(metadata) => return Err(existing_error(path, &metadata)),
    }
    let directory = parent_directory(path);
    let metadata = std::fs::metadata(directory)
        .map_err(|source| StoreError::Io { path: directory.to_owned(), source })?;
    if metadata.is_dir() {
        Ok(())
    } else {
        Err(StoreError::Io {
            path: directory.to_owned(),
            source: std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                "the parent of the store path is not a directory",
            ),
        })
    }
}

/// The error for a store path where something already exists.
fn existing_error(path: &Path, metadata: &std::fs::Metadata) -> StoreError {
    if metadata.is_dir() {
        StoreError::NotAFile { path: path.to_owned() }
    } else {
        StoreError::Exists { path: path.to_owned() }
    }
}

/// Builds schema version 1 in a new file and leaves it in WAL mode, fully checkpointed.
fn build_empty_store(staging: &Path) -> Result<(), StoreError> {
    let sqlite = |source| StoreError::Sqlite { path: staging.to_owned(), source };
    let mut connection = Connection::open_with_flags(
        staging,
        OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(sqlite)?;
    connection.pragma_update(None, "synchronous", "FULL").map_err(sqlite)?;
    let transaction =
        connection.transaction_with_behavior(TransactionBehavior::Exclusive).map_err(sqlite)?;
    transaction.execute_batch(schema::CREATE_SCHEMA).map_err(sqlite)?;
    transaction.pragma_update(None, "application_id", APPLICATION_ID).map_err(sqlite)?;
    transaction.pragma_update(None, "user_version", SCHEMA_VERSION).map_err(sqlite)?;
    transaction.commit().map_err(sqlite)?;
    // WAL mode is recorded in the file header, so every later connection uses it.
    configure_for_writing(&connection).map_err(sqlite)?;
    connection.close().map_err(|(_, source)| sqlite(source))
}

/// Puts the finished staging file at `path` without ever replacing an existing file.
fn publish(staging: &Path, path: &Path) -> Result<(), StoreError> {
    match std::fs::hard_link(staging, path) {
        Ok(()) => Ok(()),
        Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => {
            Err(StoreError::Exists { path: path.to_owned() })
        }
        Err(_) => {
            // Some file systems (FAT, some network mounts) have no hard links: fall back to a
            // rename after a last look, which can only lose a race against a file created in
            // the same instant.
            refuse_existing(path)?;
            std::fs::rename(staging, path)
                .map_err(|source| StoreError::Io { path: path.to_owned(), source })
        }
    }
}

/// Makes the new directory entry durable.
fn sync_parent_directory(path: &Path) -> Result<(), StoreError> {
    let directory = parent_directory(path);
    match std::fs::File::open(directory).and_then(|directory| directory.sync_all()) {
        Ok(()) => Ok(()),
        // Not every platform can open or sync a directory; the entry is still there.
        Err(error)
            if matches!(
                error.kind(),
                std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::Unsupported
            ) =>
        {
            Ok(())
        }
        Err(source) => Err(StoreError::Io { path: directory.to_owned(), source }),
    }
}

fn parent_directory(path: &Path) -> &Path {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    }
}

/// The temporary file a new store is built in; removed (with any SQLite side files) on drop.
struct StagingFile {
    path: PathBuf,
}

impl StagingFile {
    fn new(target: &Path) -> StagingFile {
        let name = target
            .file_name()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_else(|| "store".to_owned());
        let nanos = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |elapsed| elapsed.subsec_nanos());
        let unique = format!(".{name}.creating-{}-{nanos}", std::process::id());
        StagingFile { path: parent_directory(target).join(unique) }
    }
}

impl Drop for StagingFile {
    fn drop(&mut self) {
        for suffix in ["", "-wal", "-shm", "-journal"] {
            let mut side = self.path.clone().into_os_string();
            side.push(suffix);
            // Best effort: a leftover temporary file is harmless and clearly named.
            let _ = std::fs::remove_file(side);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MetricValue, Status};
    use mrbrake_error::Kind as _;

    fn record(index: u32, status: Status) -> Record {
        let ok = status == Status::Ok;
        Record {
            key: format!("{index:064x}"),
            status,
            reason: (!ok).then(|| format!("design {index} rejected: gap < 0.1 mm")),
            variables: vec![
                ("outer_radius_m".into(), 0.04.into()),
                ("gap_m".into(), (1e-4 * f64::from(index + 1)).into()),
                ("turns".into(), 120.0.into()),
                ("materials.bobbin".into(), crate::VariableValue::Level("pom".into())),
            ],
            metrics: if ok {
                vec![
                    ("torque_on_nm".into(), (3.0 + f64::from(index) / 7.0).into()),
                    ("ratio".into(), f64::INFINITY.into()),
                    ("unknown".into(), f64::NAN.into()),
                    ("negative_inf".into(), f64::NEG_INFINITY.into()),
                    ("negative_zero".into(), (-0.0).into()),
                    ("bandwidth_rad_s".into(), MetricValue::AtLeast(6283.0)),
                    ("t63_dir2_s".into(), MetricValue::NotApplicable),
                ]
            } else {
                vec![]
            },
            spec_toml: format!("[geometry]\n# design {index}\ngap = \"{} mm\"\n", index + 1),
            eval_seconds: 0.1 + f64::from(index) * 1e-3,
            solver_version: "mrbrake 0.1.0 (test)".into(),
            settings: Default::default(),
        }
    }

    /// Bitwise equality, so NaN metrics compare equal to themselves.
    fn assert_same(a: &Record, b: &Record) {
        let bits = |values: &[(String, MetricValue)]| {
            let bits = |x: Option<f64>| x.map(f64::to_bits);
            values
                .iter()
                .map(|(name, v)| (name.clone(), v.bound_kind(), bits(v.number())))
                .collect::<Vec<_>>()
        };
        assert_eq!(a.key, b.key);
        assert_eq!(a.status, b.status);
        assert_eq!(a.reason, b.reason);
        assert_eq!(a.variables, b.variables);
        assert_eq!(bits(&a.metrics), bits(&b.metrics));
        assert_eq!(a.spec_toml, b.spec_toml);
        assert_eq!(a.eval_seconds.to_bits(), b.eval_seconds.to_bits());
        assert_eq!(a.solver_version, b.solver_version);
        assert_eq!(a.settings, b.settings);
    }

    fn new_store() -> (tempfile::TempDir, Store) {
        let directory = tempfile::tempdir().expect("temporary directory");
        let store = Store::create(&directory.path().join("study.mrbrake")).expect("create");
        (directory, store)
    }

    #[test]
    fn records_round_trip_including_non_finite_values_across_reopen() {
        let (directory, mut store) = new_store();
        let written =
            [record(0, Status::Ok), record(1, Status::Infeasible), record(2, Status::Failed)];
        for record in &written {
            assert!(store.insert(record).expect("insert"));
        }
        for record in &written {
            assert_same(&store.get(&record.key).expect("get").expect("present"), record);
        }
        drop(store);
        let store = Store::open(&directory.path().join("study.mrbrake")).expect("reopen");
        let read = store.records().expect("records");
        assert_eq!(read.len(), written.len());
        for (read, written) in read.iter().zip(&written) {
            assert_same(read, written);
        }
        assert_eq!(store.get(&"e".repeat(64)).expect("get"), None);
    }

    #[test]
    fn settings_round_trip_and_a_record_without_them_reads_empty() {
        let (directory, mut store) = new_store();
        let mut with = record(3, Status::Ok);
        with.settings.insert("mesh_level".into(), serde_json::json!("coarse"));
        with.settings.insert("element_order".into(), serde_json::json!(2));
        let without = record(4, Status::Ok);
        assert!(store.insert(&with).expect("insert") && store.insert(&without).expect("insert"));
        drop(store);
        let store = Store::open_read_only(&directory.path().join("study.mrbrake")).expect("open");
        let read = store.records().expect("records, checksums verified");
        assert_same(&read[0], &with);
        assert_same(&read[1], &without);
        assert!(read[1].settings.is_empty());
        assert_eq!(store.unverified_len().expect("count"), 0);
    }

    #[test]
    fn nan_run_time_survives_sqlite_null() {
        let (_directory, mut store) = new_store();
        let mut unknown_time = record(9, Status::Failed);
        unknown_time.eval_seconds = f64::NAN;
        store.insert(&unknown_time).expect("insert");
        let back = store.get(&unknown_time.key).expect("get").expect("present");
        assert!(back.eval_seconds.is_nan());
    }

    #[test]
    fn duplicate_insert_returns_false_and_keeps_the_first() {
        let (_directory, mut store) = new_store();
        let first = record(5, Status::Ok);
        let mut second = record(5, Status::Failed);
        second.spec_toml = "different".into();
        assert!(store.insert(&first).expect("first insert"));
        assert!(!store.insert(&second).expect("second insert"));
        assert_eq!(store.len().expect("len"), 1);
        assert_same(&store.get(&first.key).expect("get").expect("present"), &first);
    }

    #[test]
    fn records_come_back_in_insertion_order_not_key_order() {
        let (_directory, mut store) = new_store();
        let order = [7, 3, 11, 0, 5];
        for index in order {
            store.insert(&record(index, Status::Ok)).expect("insert");
            // Re-inserting an earlier key must neither move it nor leave a gap in `seq`.
            store.insert(&record(order[0], Status::Ok)).expect("re-insert");
        }
        let keys: Vec<String> =
            store.records().expect("records").into_iter().map(|record| record.key).collect();
        let expected: Vec<String> = order.iter().map(|&index| format!("{index:064x}")).collect();
        assert_eq!(keys, expected);
        let sequence: Vec<i64> = store
            .connection
            .prepare("SELECT seq FROM evaluations ORDER BY seq")
            .expect("prepare")
            .query_map([], |row| row.get(0))
            .expect("query")
            .collect::<rusqlite::Result<_>>()
            .expect("rows");
        assert_eq!(sequence, vec![1, 2, 3, 4, 5]);
        assert_eq!(store.keys().expect("keys"), expected.into_iter().collect());
        assert!(store.contains(&format!("{:064x}", 11)).expect("contains"));
        assert!(!store.contains(&format!("{:064x}", 12)).expect("contains"));
    }

    #[test]
    fn insert_all_is_one_transaction_with_per_record_outcomes() {
        let (_directory, mut store) = new_store();
        store.insert(&record(2, Status::Ok)).expect("insert");
        let batch = [
            record(1, Status::Ok),
            record(2, Status::Failed),
            record(3, Status::Ok),
            record(1, Status::Failed),
        ];
        assert_eq!(store.insert_all(&batch).expect("batch"), vec![true, false, true, false]);
        assert_eq!(store.len().expect("len"), 3);
        assert_same(&store.get(&batch[0].key).expect("get").expect("present"), &batch[0]);

        let mut invalid = record(9, Status::Ok);
        invalid.key = "not a key".into();
        let error = store.insert_all(&[record(8, Status::Ok), invalid]).expect_err("invalid");
        assert!(matches!(error, StoreError::InvalidRecord { .. }));
        assert!(!store.contains(&record(8, Status::Ok).key).expect("contains"), "all or nothing");
    }

    #[test]
    fn meta_is_set_replaced_and_listed() {
        let (directory, mut store) = new_store();
        assert_eq!(store.meta("study").expect("meta"), None);
        store.set_meta("study", "sweep g").expect("set");
        store.set_meta("study_hash", "abc").expect("set");
        store.set_meta("study", "sweep g and h").expect("replace");
        drop(store);
        let store = Store::open(&directory.path().join("study.mrbrake")).expect("reopen");
        assert_eq!(store.meta("study").expect("meta").as_deref(), Some("sweep g and h"));
        assert_eq!(
            store.meta_entries().expect("entries"),
            vec![
                ("study".to_owned(), "sweep g and h".to_owned()),
                ("study_hash".to_owned(), "abc".to_owned()),
            ]
        );
        assert!(store.is_empty().expect("is_empty"));
    }

    #[test]
    fn invalid_records_are_refused_before_touching_the_store() {
        let (_directory, mut store) = new_store();
        let mut bad = record(1, Status::Ok);
        bad.key = "ABC".into();
        let error = store.insert(&bad).expect_err("invalid key");
        assert!(matches!(error, StoreError::InvalidRecord { .. }));
        assert!(!error.is_input_error());
        assert!(store.is_empty().expect("is_empty"));
    }

    #[test]
    fn read_only_store_refuses_writes() {
        let (directory, mut store) = new_store();
        store.insert(&record(1, Status::Ok)).expect("insert");
        let path = directory.path().join("study.mrbrake");
        let mut reader = Store::open_read_only(&path).expect("open read-only");
        assert_eq!(reader.len().expect("len"), 1);
        assert!(matches!(reader.insert(&record(2, Status::Ok)), Err(StoreError::ReadOnly { .. })));
        assert!(matches!(reader.set_meta("a", "b"), Err(StoreError::ReadOnly { .. })));
    }

    #[test]
    fn open_or_create_follows_the_resume_flag() {
        let directory = tempfile::tempdir().expect("temporary directory");
        let path = directory.path().join("study.mrbrake");
        let mut store = Store::open_or_create(&path, false).expect("create when missing");
        store.insert(&record(1, Status::Ok)).expect("insert");
        drop(store);
        let error = Store::open_or_create(&path, false).expect_err("exists without resume");
        assert!(matches!(error, StoreError::Exists { .. }));
        assert!(error.to_string().contains("--resume"), "{error}");
        let store = Store::open_or_create(&path, true).expect("resume");
        assert_eq!(store.len().expect("len"), 1);
        let fresh = Store::open_or_create(&directory.path().join("new.mrbrake"), true)
            .expect("resume of a missing store creates it");
        assert!(fresh.is_empty().expect("is_empty"));
    }

    #[test]
    fn views_and_documented_queries_work_in_sqlite() {
        let (_directory, mut store) = new_store();
        for index in 0..3 {
            store.insert(&record(index, Status::Ok)).expect("insert");
        }
        store.insert(&record(3, Status::Failed)).expect("insert");
        let metric_rows: Vec<(String, Option<f64>)> = store
            .connection
            .prepare("SELECT name, value FROM metric_values WHERE key = ?1 ORDER BY position")
            .expect("prepare")
            .query_map([format!("{:064x}", 1)], |row| {
                // Non-finite values are the strings "inf", "NaN", "-inf" in SQL.
                Ok((
                    row.get(0)?,
                    row.get::<_, rusqlite::types::Value>(1).map(|value| match value {
                        rusqlite::types::Value::Real(real) => Some(real),
                        _ => None,
                    })?,
                ))
            })
            .expect("query")
            .collect::<rusqlite::Result<_>>()
            .expect("rows");
        let names: Vec<&str> = metric_rows.iter().map(|(name, _)| name.as_str()).collect();
        assert_eq!(
            names,
            [
                "torque_on_nm",
                "ratio",
                "unknown",
                "negative_inf",
                "negative_zero",
                "bandwidth_rad_s",
                "t63_dir2_s"
            ]
        );
        assert_eq!(metric_rows[0].1, Some(3.0 + 1.0 / 7.0));
        assert_eq!(metric_rows[1].1, None);

        // The sample queries of the crate documentation.
        let top: (String, f64, f64) = store
            .connection
            .query_row(
                "SELECT m.key, m.value AS torque_nm, v.value AS gap_m \
                 FROM metric_values AS m JOIN variable_values AS v USING (key) \
                 WHERE m.name = 'torque_on_nm' AND v.name = 'gap_m' \
                 ORDER BY m.value DESC LIMIT 10",
                [],
                |row| Ok((row.get(0)?, row.get(1)?, row.get(2)?)),
            )
            .expect("top design");
        assert_eq!(top, (format!("{:064x}", 2), 3.0 + 2.0 / 7.0, 1e-4 * 3.0));
        let raw_count: i64 = store
            .connection
            .query_row(
                "SELECT count(*) FROM (SELECT e.key, json_extract(p.value, '$[1]') AS torque_nm \
                 FROM evaluations AS e, json_each(e.metrics) AS p \
                 WHERE json_extract(p.value, '$[0]') = 'torque_on_nm')",
                [],
                |row| row.get(0),
            )
            .expect("json_each query");
        assert_eq!(raw_count, 3);
        let failures: (String, i64) = store
            .connection
            .query_row(
                "SELECT status, count(*) FROM evaluations WHERE status != 'ok' GROUP BY status",
                [],
                |row| Ok((row.get(0)?, row.get(1)?)),
            )
            .expect("failure summary");
        assert_eq!(failures, ("failed".to_owned(), 1));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]

        /// Any names, texts and finite or non-finite values survive a store round trip.
        #[test]
        fn any_record_round_trips(
            key_bits in proptest::prelude::any::<[u64; 4]>(),
            status_index in 0_usize..3,
            reason in proptest::option::of("\\PC{0,40}"),
            names in proptest::collection::hash_set("\\PC{1,16}", 0..6),
            value_bits in proptest::collection::vec(proptest::prelude::any::<u64>(), 6),
            spec_toml in "\\PC{0,200}",
            eval_seconds in proptest::prelude::any::<f64>(),
            solver_version in "\\PC{0,20}",
        ) {
            let named: Vec<(String, f64)> = names
                .into_iter()
                .zip(value_bits)
                .map(|(name, bits)| (name, f64::from_bits(bits)))
                .collect();
            let original = Record {
                key: key_bits.iter().map(|part| format!("{part:016x}")).collect(),
                status: Status::ALL[status_index],
                reason,
                variables: named.iter().map(|(n, v)| (n.clone(), (*v).into())).collect(),
                metrics: named.into_iter().rev().map(|(n, v)| (n, v.into())).collect(),
                spec_toml,
                eval_seconds,
                solver_version,
                settings: Default::default(),
            };
            let (_directory, mut store) = new_store();
            proptest::prop_assert!(store.insert(&original).expect("insert"));
            let back = store.get(&original.key).expect("get").expect("present");
            // NaN payloads need not survive; every other value must, bit for bit.
            let canonical = |values: &[(String, f64)]| -> Vec<(String, u64)> {
                values
                    .iter()
                    .map(|(name, value)| {
                        (name.clone(), if value.is_nan() { f64::NAN.to_bits() } else { value.to_bits() })
                    })
                    .collect()
            };
            let numbers = |values: &[(String, crate::VariableValue)]| -> Vec<(String, f64)> {
                values.iter().map(|(n, v)| (n.clone(), v.as_number().unwrap_or(0.5))).collect()
            };
            proptest::prop_assert_eq!(
                canonical(&numbers(&back.variables)),
                canonical(&numbers(&original.variables))
            );
            let values = |values: &[(String, MetricValue)]| -> Vec<(String, f64)> {
                values.iter().map(|(n, v)| (n.clone(), v.value().unwrap_or(0.5))).collect()
            };
            proptest::prop_assert_eq!(
                canonical(&values(&back.metrics)),
                canonical(&values(&original.metrics))
            );
            proptest::prop_assert_eq!(&back.reason, &original.reason);
            proptest::prop_assert_eq!(&back.spec_toml, &original.spec_toml);
            proptest::prop_assert_eq!(&back.solver_version, &original.solver_version);
            proptest::prop_assert!(
                back.eval_seconds.to_bits() == original.eval_seconds.to_bits()
                    || (back.eval_seconds.is_nan() && original.eval_seconds.is_nan())
                    // A REAL column stores -0.0 as the integer 0.
                    || (back.eval_seconds == 0.0 && original.eval_seconds == 0.0),
                "eval_seconds {} came back as {}", original.eval_seconds, back.eval_seconds
            );
            store.close().expect("close");
        }
    }

    #[test]
    fn create_leaves_no_staging_files_and_writes_identity_marks() {
        let (directory, store) = new_store();
        let (application_id, version, journal, synchronous): (i64, i64, String, i64) = store
            .connection
            .query_row(
                "SELECT (SELECT application_id FROM pragma_application_id), \
                 (SELECT user_version FROM pragma_user_version), \
                 (SELECT journal_mode FROM pragma_journal_mode), \
                 (SELECT synchronous FROM pragma_synchronous)",
                [],
                |row| Ok((row.get(0)?, row.get(1)?, row.get(2)?, row.get(3)?)),
            )
            .expect("pragmas");
        assert_eq!(application_id, i64::from(APPLICATION_ID));
        assert_eq!(version, SCHEMA_VERSION);
        assert_eq!(journal, "wal");
        assert_eq!(synchronous, 2, "synchronous=FULL");
        let names: Vec<String> = std::fs::read_dir(directory.path())
            .expect("list")
            .map(|entry| entry.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|name| !name.contains(".creating-")), "{names:?}");
    }
}
