//! The one error type of the store, [`StoreError`].
//!
//! Every variant that concerns a file names it, so a message such as
//! `results store /data/run.sqlite is not an mrbrake store: ...` tells the user exactly which file
//! is at fault. [`StoreError::is_input_error`] separates problems the user can fix by choosing
//! another file or flag (exit code 2 in the CLI) from I/O failures and bugs (exit code 1).

use std::path::PathBuf;

/// Everything that can go wrong while creating, opening, reading, writing or merging a store.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// [`Store::create`](crate::Store::create) was asked for a path that already exists (even an
    /// empty file): an existing store is never overwritten.
    #[error(
        "results store {} already exists; use --resume to continue it, or choose a new path",
        path.display()
    )]
    Exists {
        /// The path that already exists.
        path: PathBuf,
    },

    /// [`Store::open`](crate::Store::open) was asked for a path that does not exist.
    #[error("results store {} does not exist", path.display())]
    NotFound {
        /// The missing path.
        path: PathBuf,
    },

    /// The path exists but is a directory (or another non-regular file), not a store file.
    #[error("results store path {} is a directory or special file, not a store file", path.display())]
    NotAFile {
        /// The offending path.
        path: PathBuf,
    },

    /// The file is not a SQLite database at all (random bytes, an empty file) or is a damaged one
    /// (truncated, failed `PRAGMA quick_check`). The file is left untouched.
    #[error("results store {} is corrupt or not a database: {detail}", path.display())]
    Corrupt {
        /// The damaged file.
        path: PathBuf,
        /// What was found wrong (SQLite's message or the first `quick_check` findings).
        detail: String,
    },

    /// The file is a valid SQLite database that belongs to something else (its
    /// `PRAGMA application_id` is not the mrbrake store's). It is never modified.
    #[error(
        "{} is a SQLite database but not an mrbrake results store ({detail}); it was not modified",
        path.display()
    )]
    Foreign {
        /// The foreign database file.
        path: PathBuf,
        /// Its application id and tables, to help the user recognise it.
        detail: String,
    },

    /// The store was written by a newer mrbrake whose schema this build does not know.
    #[error(
        "results store {} has schema version {found}, this build supports up to {supported}; \
         use a newer mrbrake",
        path.display()
    )]
    Version {
        /// The store file.
        path: PathBuf,
        /// The schema version found in the file (`PRAGMA user_version`).
        found: i64,
        /// The newest schema version this build reads and writes.
        supported: i64,
    },

    /// A SQLite operation failed for a reason other than damage (disk full, I/O error, a lock held
    /// longer than the busy timeout).
    #[error("results store {}: SQLite error: {source}", path.display())]
    Sqlite {
        /// The store file.
        path: PathBuf,
        /// The underlying SQLite error.
        #[source]
        source: rusqlite::Error,
    },

    /// A file-system operation around the database failed (creating the file, linking it into
    /// place, reading its header).
    #[error("results store {}: {source}", path.display())]
    Io {
        /// The path being worked on.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },

    /// A merge was refused as a whole (merging a store into itself). Per-key conflicts are not an
    /// error: they are listed in [`MergeSummary::conflicts`](crate::MergeSummary::conflicts).
    #[error("cannot merge {} into {}: {detail}", other.display(), path.display())]
    Conflict {
        /// The store being merged into.
        path: PathBuf,
        /// The store being merged from.
        other: PathBuf,
        /// Why the merge was refused.
        detail: String,
    },

    /// A write was attempted on a store opened with
    /// [`Store::open_read_only`](crate::Store::open_read_only).
    #[error("results store {} was opened read-only", path.display())]
    ReadOnly {
        /// The store file.
        path: PathBuf,
    },

    /// A record handed to [`Store::insert`](crate::Store::insert) breaks the record contract
    /// (key not 64 lowercase hex digits, empty or repeated names). This is a bug in the caller.
    #[error("invalid record {key:?}: {detail}")]
    InvalidRecord {
        /// The record's key as given.
        key: String,
        /// Which rule it breaks.
        detail: String,
    },

    /// A row read back from the store could not be decoded (a value edited by hand with the
    /// sqlite3 shell, for instance).
    #[error("results store {}: evaluation {key:?} cannot be decoded: {detail}", path.display())]
    Decode {
        /// The store file.
        path: PathBuf,
        /// The key of the undecodable row.
        key: String,
        /// What is wrong with it.
        detail: String,
    },

    /// Writing the CSV export failed.
    #[error("CSV export failed: {0}")]
    Csv(#[from] csv::Error),
}

impl mrbrake_error::Kind for StoreError {
    /// Input when the user can fix the problem by pointing at another file or passing another flag;
    /// file-system failures take the kind of their I/O error (a missing path is input, a full disk
    /// is I/O); SQLite and CSV failures are I/O; caller bugs are internal.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            StoreError::Exists { .. }
            | StoreError::NotFound { .. }
            | StoreError::NotAFile { .. }
            | StoreError::Corrupt { .. }
            | StoreError::Foreign { .. }
            | StoreError::Version { .. }
            | StoreError::Conflict { .. }
            | StoreError::Decode { .. } => ErrorKind::Input,
            StoreError::Io { source, .. } => Kind::kind(source),
            StoreError::Sqlite { .. } | StoreError::Csv(_) => ErrorKind::Io,
            StoreError::ReadOnly { .. } | StoreError::InvalidRecord { .. } => ErrorKind::Internal,
        }
    }
}
