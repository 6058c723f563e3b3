//! The store's SQL schema, its identity marks and the checks made before a file is trusted.
//!
//! A file is accepted as a store only if, in this order: it is a regular non-empty file whose
//! first 16 bytes are SQLite's magic string; its header is sane and it is a whole number of
//! pages long; its header carries the `application_id` [`APPLICATION_ID`] (otherwise it is a
//! *foreign* database, refused before SQLite opens it); its `user_version` is between 1 and [`SCHEMA_VERSION`]
//! (header, then confirmed by `PRAGMA`); `PRAGMA quick_check` reports `ok`; and the tables
//! `evaluations` and `meta` have the expected columns. The SQLite checks run on a read-only
//! connection, so a refused file is byte-for-byte unchanged.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use rusqlite::Connection;
use rusqlite::ErrorCode;

use crate::StoreError;

/// `PRAGMA application_id` of every mrbrake store: the ASCII bytes `MRBR` (0x4D524252). The
/// `file` utility and the sqlite3 shell's `.dbinfo` show it; any other id marks a foreign file.
pub const APPLICATION_ID: i32 = 0x4d52_4252;

/// Schema version written to `PRAGMA user_version` and the newest this build understands.
/// Version 2 added the per-record `checksum` column (see [`crate::checksum`]); a version-1 store is
/// read with its records unverified and migrated (the column added) when opened for writing.
/// Version 3 added the per-record `settings` column (the evaluation settings, JSON); older records
/// read with no settings. Version 4 lets a metric be a bound beyond the analysed range or "not
/// applicable" (a JSON object in the `metrics` column, see [`crate::MetricValue`]); no column
/// changes, so an older store is read as it is and only its version mark is raised when opened for
/// writing (an older mrbrake then refuses it rather than misread a bound).
pub const SCHEMA_VERSION: i64 = 4;

/// How long a writer waits for another process's write transaction before giving up.
pub const BUSY_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(10);

/// The first 16 bytes of every SQLite 3 database file.
const SQLITE_MAGIC: &[u8; 16] = b"SQLite format 3\0";

/// Size of the SQLite file header (<https://sqlite.org/fileformat.html#the_database_header>).
const SQLITE_HEADER_BYTES: usize = 100;

/// Offset of `PRAGMA user_version` (big-endian i32) in the SQLite header.
const HEADER_USER_VERSION_OFFSET: usize = 60;

/// Offset of `PRAGMA application_id` (big-endian i32) in the SQLite header.
const HEADER_APPLICATION_ID_OFFSET: usize = 68;

/// Tables, in the order created by [`CREATE_SCHEMA`], and the columns [`check_store`] requires.
const REQUIRED_COLUMNS: [(&str, &[&str]); 2] = [
    (
        "evaluations",
        &[
            "seq",
            "key",
            "status",
            "reason",
            "variables",
            "metrics",
            "spec_toml",
            "eval_seconds",
            "solver_version",
            "created_unix_s",
        ],
    ),
    ("meta", &["name", "value"]),
];

/// Schema version 1, created in one transaction together with the identity pragmas.
pub(crate) const CREATE_SCHEMA: &str = "
CREATE TABLE evaluations (
    seq            INTEGER PRIMARY KEY AUTOINCREMENT,
    key            TEXT NOT NULL UNIQUE CHECK (length(key) = 64),
    status         TEXT NOT NULL CHECK (status IN ('ok', 'infeasible', 'failed')),
    reason         TEXT,
    variables      TEXT NOT NULL,
    metrics        TEXT NOT NULL,
    spec_toml      TEXT NOT NULL,
    eval_seconds   REAL,
    solver_version TEXT,
    created_unix_s REAL,
    checksum       INTEGER,
    settings       TEXT
);
CREATE TABLE meta (
    name  TEXT PRIMARY KEY,
    value TEXT
);
CREATE VIEW variable_values AS
    SELECT e.seq, e.key, e.status, pair.key AS position,
           json_extract(pair.value, '$[0]') AS name,
           json_extract(pair.value, '$[1]') AS value
    FROM evaluations AS e, json_each(e.variables) AS pair;
CREATE VIEW metric_values AS
    SELECT e.seq, e.key, e.status, pair.key AS position,
           json_extract(pair.value, '$[0]') AS name,
           json_extract(pair.value, '$[1]') AS value
    FROM evaluations AS e, json_each(e.metrics) AS pair;
";

/// True for SQLite errors that mean "this file is damaged or not a database".
pub(crate) fn is_damage(error: &rusqlite::Error) -> bool {
    matches!(error.sqlite_error_code(), Some(ErrorCode::DatabaseCorrupt | ErrorCode::NotADatabase))
}

/// Maps a SQLite error on `path` to [`StoreError::Corrupt`] when it reports damage, else to
/// [`StoreError::Sqlite`].
pub(crate) fn sqlite_error(path: &Path, error: rusqlite::Error) -> StoreError {
    if is_damage(&error) {
        StoreError::Corrupt { path: path.to_owned(), detail: error.to_string() }
    } else {
        StoreError::Sqlite { path: path.to_owned(), source: error }
    }
}

/// File-level checks made before SQLite sees the file: it exists, is a regular file, is not
/// empty, starts with SQLite's magic string, has a valid page size (header bytes 16-17) and is a
/// whole number of pages long.
pub(crate) fn check_file(path: &Path) -> Result<(), StoreError> {
    let length = non_empty_file_length(path)?;
    let header = read_header(path, length)?;
    check_page_layout(path, &header, length)?;
    check_identity(path, &header)
}

/// The length of the regular, non-empty file at `path`.
fn non_empty_file_length(path: &Path) -> Result<u64, StoreError> {
    let metadata = match std::fs::metadata(path) {
        Ok(metadata) => metadata,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
            return Err(StoreError::NotFound { path: path.to_owned() });
        }
        Err(source) => return Err(StoreError::Io { path: path.to_owned(), source }),
    };
    if !metadata.is_file() {
        return Err(StoreError::NotAFile { path: path.to_owned() });
    }
    if metadata.len() == 0 {
        return Err(StoreError::Corrupt {
            path: path.to_owned(),
            detail: "the file is empty (0 bytes); a store is never empty, even before its first \
                     evaluation"
                .to_owned(),
        });
    }
    Ok(metadata.len())
}

/// The SQLite header of the file at `path` (`length` bytes long): it must start with SQLite's
/// magic string and be complete.
fn read_header(path: &Path, length: u64) -> Result<[u8; SQLITE_HEADER_BYTES], StoreError> {
    let mut header = Vec::with_capacity(SQLITE_HEADER_BYTES);
    File::open(path)
        .and_then(|file| file.take(SQLITE_HEADER_BYTES as u64).read_to_end(&mut header))
        .map_err(|source| StoreError::Io { path: path.to_owned(), source })?;
    let corrupt = |detail: String| StoreError::Corrupt { path: path.to_owned(), detail };
    if !header.starts_with(SQLITE_MAGIC) {
        return Err(corrupt(format!(
            "not a SQLite database: the file ({length} bytes) does not start with \"SQLite format 3\""
        )));
    }
    header.try_into().map_err(|_| {
        corrupt(format!(
            "the file ({length} bytes) is shorter than a SQLite header ({SQLITE_HEADER_BYTES} bytes)"
        ))
    })
}

/// The header's fixed fields are those of a valid database and the file is a whole number of
/// its pages long.
fn check_page_layout(
    path: &Path,
    header: &[u8; SQLITE_HEADER_BYTES],
    length: u64,
) -> Result<(), StoreError> {
    let corrupt = |detail: String| StoreError::Corrupt { path: path.to_owned(), detail };
    // SQLite itself reads missing pages as zeros; a whole number of pages is the cheapest sign
    // of truncation (a truncation on a page boundary is left to `PRAGMA quick_check`).
    let page_size = match [header[16], header[17]] {
        [0, 1] => 65_536,
        bytes => u64::from(u16::from_be_bytes(bytes)),
    };
    // Fixed fields of every valid header: page size, file format versions (1 rollback journal,
    // 2 WAL) and the payload fractions 64, 32, 32.
    let sane = page_size.is_power_of_two()
        && (512..=65_536).contains(&page_size)
        && matches!(header[18], 1 | 2)
        && matches!(header[19], 1 | 2)
        && header[21..24] == [64, 32, 32];
    if !sane {
        return Err(corrupt(
            "the SQLite header is invalid (page size, format version or payload fractions)"
                .to_owned(),
        ));
    }
    if length % page_size != 0 {
        return Err(corrupt(format!(
            "the file length ({length} bytes) is not a whole number of {page_size}-byte pages; \
             it was probably truncated"
        )));
    }
    Ok(())
}

/// Identity from the header bytes, so another application's database is refused before SQLite
/// opens it (a read-only SQLite connection to a WAL-mode database leaves -wal and -shm files
/// beside it), and so is a store from a newer mrbrake. The PRAGMA checks in [`check_store`]
/// confirm these values.
fn check_identity(path: &Path, header: &[u8; SQLITE_HEADER_BYTES]) -> Result<(), StoreError> {
    let header_field = |offset: usize| {
        i32::from_be_bytes([
            header[offset],
            header[offset + 1],
            header[offset + 2],
            header[offset + 3],
        ])
    };
    let application_id = header_field(HEADER_APPLICATION_ID_OFFSET);
    if application_id != APPLICATION_ID {
        let rollback_journal = header[18] == 1 && header[19] == 1;
        return Err(StoreError::Foreign {
            path: path.to_owned(),
            detail: foreign_detail(path, application_id, rollback_journal),
        });
    }
    let version = i64::from(header_field(HEADER_USER_VERSION_OFFSET));
    if version > SCHEMA_VERSION {
        return Err(StoreError::Version {
            path: path.to_owned(),
            found: version,
            supported: SCHEMA_VERSION,
        });
    }
    Ok(())
}

/// Database-level checks on an open (read-only) connection: identity, version, integrity and
/// tables. Reads only.
pub(crate) fn check_store(connection: &Connection, path: &Path) -> Result<(), StoreError> {
    let application_id: i64 = connection
        .pragma_query_value(None, "application_id", |row| row.get(0))
        .map_err(|error| sqlite_error(path, error))?;
    if application_id != i64::from(APPLICATION_ID) {
        return Err(StoreError::Foreign {
            path: path.to_owned(),
            detail: format!(
                "its application_id is {application_id:#x}, an mrbrake store's is \
                 {APPLICATION_ID:#x} (\"MRBR\")"
            ),
        });
    }

    let version: i64 = connection
        .pragma_query_value(None, "user_version", |row| row.get(0))
        .map_err(|error| sqlite_error(path, error))?;
    if version > SCHEMA_VERSION {
        return Err(StoreError::Version {
            path: path.to_owned(),
            found: version,
            supported: SCHEMA_VERSION,
        });
    }
    if version < 1 {
        return Err(StoreError::Corrupt {
            path: path.to_owned(),
            detail: format!(
                "schema version {version} (PRAGMA user_version); an mrbrake store has 1 or more"
            ),
        });
    }

    let findings = quick_check(connection).map_err(|error| sqlite_error(path, error))?;
    if findings != ["ok"] {
        return Err(StoreError::Corrupt {
            path: path.to_owned(),
            detail: format!("PRAGMA quick_check found: {}", findings.join("; ")),
        });
    }

    if version >= 2
        && !has_checksum_column(connection).map_err(|error| sqlite_error(path, error))?
    {
        return Err(StoreError::Corrupt {
            path: path.to_owned(),
            detail: format!(
                "schema version {version} but the table evaluations has no checksum column"
            ),
        });
    }
    for (table, columns) in REQUIRED_COLUMNS {
        let present =
            table_columns(connection, table).map_err(|error| sqlite_error(path, error))?;
        let missing: Vec<&str> = columns
            .iter()
            .copied()
            .filter(|column| !present.iter().any(|name| name == column))
            .collect();
        if !missing.is_empty() {
            return Err(StoreError::Corrupt {
                path: path.to_owned(),
                detail: if present.is_empty() {
                    format!("the table {table} is missing")
                } else {
                    format!("the table {table} lacks the columns {}", missing.join(", "))
                },
            });
        }
    }
    Ok(())
}

/// True when `evaluations` has the `settings` column (schema version 3 and later).
pub(crate) fn has_settings_column(connection: &Connection) -> rusqlite::Result<bool> {
    Ok(table_columns(connection, "evaluations")?.iter().any(|name| name == "settings"))
}

/// True when `evaluations` has the `checksum` column (schema version 2 and later).
pub(crate) fn has_checksum_column(connection: &Connection) -> rusqlite::Result<bool> {
    Ok(table_columns(connection, "evaluations")?.iter().any(|name| name == "checksum"))
}

/// Brings a store opened for writing to [`SCHEMA_VERSION`]: version 1 gains the `checksum` column
/// (its existing records keep `NULL`, "unverified"), versions 1 and 2 the `settings` column
/// (existing records keep `NULL`, no settings); version 4 changes no column. One write transaction, so concurrent writers
/// migrate once; adding a column does not rewrite the table.
pub(crate) fn migrate(connection: &Connection) -> rusqlite::Result<()> {
    let read_version = |connection: &Connection| -> rusqlite::Result<i64> {
        connection.pragma_query_value(None, "user_version", |row| row.get(0))
    };
    if read_version(connection)? >= SCHEMA_VERSION {
        return Ok(());
    }
    connection.execute_batch("BEGIN IMMEDIATE")?;
    let migrated = (|| {
        if read_version(connection)? < 2 && !has_checksum_column(connection)? {
            connection.execute_batch("ALTER TABLE evaluations ADD COLUMN checksum INTEGER")?;
        }
        if !has_settings_column(connection)? {
            connection.execute_batch("ALTER TABLE evaluations ADD COLUMN settings TEXT")?;
        }
        connection.pragma_update(None, "user_version", SCHEMA_VERSION)?;
        connection.execute_batch("COMMIT")
    })();
    if migrated.is_err() {
        let _ = connection.execute_batch("ROLLBACK");
    }
    migrated
}

/// At most a few findings of `PRAGMA quick_check` (`["ok"]` for a sound file).
fn quick_check(connection: &Connection) -> rusqlite::Result<Vec<String>> {
    let mut statement = connection.prepare("PRAGMA quick_check(5)")?;
    let findings = statement
        .query_map([], |row| row.get::<_, String>(0))?
        .collect::<rusqlite::Result<Vec<String>>>()?;
    Ok(findings)
}

fn table_columns(connection: &Connection, table: &str) -> rusqlite::Result<Vec<String>> {
    let mut statement = connection.prepare("SELECT name FROM pragma_table_info(?1)")?;
    let columns = statement
        .query_map([table], |row| row.get::<_, String>(0))?
        .collect::<rusqlite::Result<Vec<String>>>()?;
    Ok(columns)
}

/// The application id and first tables of a foreign database, so the user recognises it. The
/// tables are listed only for a rollback-journal database, which a read-only connection leaves
/// exactly as it was (no side files).
fn foreign_detail(path: &Path, application_id: i32, rollback_journal: bool) -> String {
    let id = format!(
        "its application_id is {application_id:#x}, an mrbrake store's is {APPLICATION_ID:#x} \
         (\"MRBR\")"
    );
    if !rollback_journal {
        return format!("{id}; it is in WAL mode");
    }
    let tables: Vec<String> = Connection::open_with_flags(
        path,
        rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY | rusqlite::OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .and_then(|connection| {
        let mut statement = connection
            .prepare("SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name LIMIT 8")?;
        let rows = statement.query_map([], |row| row.get::<_, String>(0))?;
        rows.collect::<rusqlite::Result<Vec<String>>>()
    })
    .unwrap_or_default();
    if tables.is_empty() {
        format!("{id}; no tables")
    } else {
        format!("{id}; tables: {}", tables.join(", "))
    }
}
