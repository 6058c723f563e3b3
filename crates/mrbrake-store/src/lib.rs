//! Durable results store for design studies: every evaluation of a sweep or an optimisation,
//! in one SQLite file, keyed by the hash of the design.
//!
//! # Brief overview
//!
//! - [`Store`] is one store file. [`Store::create`] makes a new one, [`Store::open`] checks and
//!   opens an existing one, [`Store::open_or_create`] does what a `--resume` flag asks.
//! - [`Record`] is one evaluation: its design key (SHA-256 of the canonical design, computed by
//!   the caller), [`Status`], reason, varied variables, metrics, the full design TOML, run time
//!   and solver version. [`Store::insert`] stores it durably and never overwrites a stored key,
//!   so a resumed or repeated run never recomputes or duplicates a design.
//! - [`Store::complete`] extends a stored record with metrics computed later (a resumed study
//!   asking for more metrics), keeping every stored metric as it was.
//! - [`Store::merge_from`] combines stores (shards of one study) into a [`MergeSummary`].
//! - [`to_csv`] and [`to_json`] export records; the caller writes the bytes.
//! - [`StoreError`] is the crate's one error type.
//!
//! ```
//! # fn main() -> Result<(), mrbrake_store::StoreError> {
//! use mrbrake_store::{Record, Status, Store};
//! # let directory = tempfile::tempdir().expect("temporary directory");
//! # let path = directory.path().join("study.mrbrake");
//! let mut store = Store::create(&path)?;
//! let record = Record {
//!     key: "3f".repeat(32),
//!     status: Status::Ok,
//!     reason: None,
//!     variables: vec![("gap_m".into(), 0.75e-3.into())],
//!     metrics: vec![("torque_on_nm".into(), 3.2.into()), ("torque_off_nm".into(), 0.04.into())],
//!     spec_toml: "[geometry]\ngap = \"0.75 mm\"\n".into(),
//!     eval_seconds: 0.31,
//!     solver_version: "mrbrake 0.1.0".into(),
//!     settings: Default::default(),
//! };
//! assert!(store.insert(&record)?); // on disk when this returns
//! assert!(!store.insert(&record)?); // already stored: nothing changes
//! drop(store);
//! let store = Store::open(&path)?; // as `--resume` would
//! assert_eq!(store.get(&record.key)?, Some(record));
//! # Ok(())
//! # }
//! ```
//!
//! # Schema (version 4)
//!
//! Researchers may query a store directly with the `sqlite3` shell (read-only is safest while a
//! run is writing: `sqlite3 -readonly study.mrbrake`).
//!
//! ```sql
//! CREATE TABLE evaluations (
//!     seq            INTEGER PRIMARY KEY AUTOINCREMENT, -- insertion order, 1, 2, 3, ... without gaps
//!     key            TEXT NOT NULL UNIQUE,  -- SHA-256 of the canonical design, 64 lowercase hex digits
//!     status         TEXT NOT NULL CHECK (status IN ('ok', 'infeasible', 'failed')),
//!     reason         TEXT,                  -- why infeasible / failed, NULL when ok
//!     variables      TEXT NOT NULL,         -- JSON array of [name, SI value or level] pairs, caller's order
//!     metrics        TEXT NOT NULL,         -- JSON array of [name, value] pairs, caller's order (value: see below)
//!     spec_toml      TEXT NOT NULL,         -- the full design, ready for `mrbrake analyze`
//!     eval_seconds   REAL,                  -- wall-clock time of the evaluation
//!     solver_version TEXT,
//!     created_unix_s REAL,                  -- when the record was first stored (kept by merges)
//!     checksum       INTEGER,               -- FNV-1a 64 of the row (version 2; NULL: unverified)
//!     settings       TEXT                   -- JSON object of the evaluation settings (version 3)
//! );
//! CREATE TABLE meta (name TEXT PRIMARY KEY, value TEXT);  -- study description, its hash, ...
//! -- One row per variable / metric: (seq, key, status, position, name, value), where position
//! -- is the 0-based place in the caller's order. Built with json_each over the columns above.
//! CREATE VIEW variable_values AS ...;
//! CREATE VIEW metric_values AS ...;
//! ```
//!
//! Values are JSON numbers, except non-finite ones, stored as the strings `"NaN"`, `"inf"`,
//! `"-inf"` (JSON has no such numbers), and the levels of categorical variables (a material by
//! name), stored as any other string. A metric the analysis did not resolve (version 4,
//! [`MetricValue`]) is an object: `{"at_least": x}` / `{"at_most": x}` (beyond the analysed range:
//! a release not reached within the simulated window is at least the window), or
//! `{"not_applicable": true}`; the view `metric_values` shows that object's text as the value.
//! Pairs rather than a JSON object keep the caller's order.
//! The file is marked with `PRAGMA application_id = 0x4D524252` ("MRBR") and
//! `PRAGMA user_version = 4`. Sample queries:
//!
//! ```sql
//! -- The ten designs with the highest torque, with their gap:
//! SELECT m.key, m.value AS torque_nm, v.value AS gap_m
//! FROM metric_values AS m JOIN variable_values AS v USING (key)
//! WHERE m.name = 'torque_on_nm' AND v.name = 'gap_m'
//! ORDER BY m.value DESC LIMIT 10;
//! -- The same without the views (json_each / json_extract are built into SQLite >= 3.38):
//! SELECT e.key, json_extract(p.value, '$[1]') AS torque_nm
//! FROM evaluations AS e, json_each(e.metrics) AS p
//! WHERE json_extract(p.value, '$[0]') = 'torque_on_nm';
//! -- Why designs failed:
//! SELECT status, reason, count(*) FROM evaluations WHERE status != 'ok' GROUP BY 1, 2;
//! ```
//!
//! # Durability
//!
//! - The store is created complete or not at all: the schema, identity marks and WAL mode are
//!   written in a temporary file in the same directory, which is then hard-linked to the chosen
//!   name (this never replaces a file created meanwhile) and the directory is synced.
//! - Connections use `PRAGMA journal_mode=WAL` and `PRAGMA synchronous=FULL`, and every
//!   [`Store::insert`] is its own `BEGIN IMMEDIATE` transaction: when it returns, the record
//!   survives `kill -9` and power loss (given a disk that honours `fsync`). A process killed
//!   mid-insert leaves the store exactly as before that insert (tested by killing writer processes
//!   with SIGKILL at random moments).
//! - Several processes may append to one store: writers wait up to 10 s for each other
//!   (`busy_timeout`), and a key already present is skipped inside the write transaction, so
//!   concurrent writers never duplicate a design. A store on a network file system is not
//!   supported (WAL needs shared memory between the processes on one machine).
//!
//! # What is refused
//!
//! [`Store::open`] and [`Store::merge_from`] check a file on a read-only connection before trusting
//! it, and never modify a file they refuse: a missing path ([`StoreError::NotFound`]), a directory
//! ([`StoreError::NotAFile`]), an empty file, a file that is not SQLite or fails
//! `PRAGMA quick_check` ([`StoreError::Corrupt`]), another application's SQLite database
//! ([`StoreError::Foreign`]) and a store from a newer mrbrake ([`StoreError::Version`]).
//! [`Store::create`] refuses any existing path ([`StoreError::Exists`]): only `--resume` reuses a
//! store. [`Store::insert`] refuses a record whose key is not 64 lowercase hexadecimal digits or
//! whose variable or metric names are empty or repeated ([`StoreError::InvalidRecord`]).
//! Every read of a record ([`Store::get`], [`Store::records`], exports, merges) checks its
//! [`checksum`]: a record changed on disk is refused with [`StoreError::Decode`] naming the store
//! file and the record's key, never returned altered. Records written before checksums (schema
//! version 1) are read unverified; [`Store::unverified_len`] counts them.

pub mod checksum;
mod complete;
mod error;
mod export;
mod merge;
mod named_values;
mod record;
mod row;
pub mod schema;
mod store;

pub use error::StoreError;
pub use export::{to_csv, to_json};
pub use merge::{
    MERGE_RELATIVE_TOLERANCE, MergeSummary, MetricUpgrade, metrics_agree, values_agree,
};
pub use record::{
    KEY_HEX_DIGITS, MetricValue, Record, Status, UnknownStatus, VariableValue, is_design_key,
};
pub use store::Store;
