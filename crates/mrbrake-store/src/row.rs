//! One row of `evaluations`: written from a [`Record`] with its checksum ([`insert_new`]), read back
//! exactly as SQLite returns it ([`read_row`]), then verified and decoded ([`RawRow::decode`]).
//!
//! Reading keeps every column as the raw value SQLite holds (texts as bytes), so a damaged row (a
//! text no longer valid UTF-8, a value whose type changed) becomes a clear error naming the record
//! instead of a conversion failure deep in SQLite's bindings.

use rusqlite::params;
use rusqlite::types::ValueRef;

use crate::checksum::record_checksum;
use crate::{Record, Status, named_values};

/// Columns read back into a [`Record`], in the order [`read_row`] expects; the query appends the
/// checksum column (or `NULL` for a store written before checksums).
pub(crate) const RECORD_COLUMNS_SQL: &str = "key, status, reason, variables, metrics, spec_toml, eval_seconds, solver_version, created_unix_s";

/// Number of columns in [`RECORD_COLUMNS_SQL`].
const RECORD_COLUMNS: usize = 9;

/// A column's value as SQLite stores it, borrowed: what the checksum is computed over.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Column<'a> {
    /// SQL NULL (also how SQLite stores a NaN).
    Null,
    /// An INTEGER or REAL value.
    Number(f64),
    /// TEXT, as bytes.
    Text(&'a [u8]),
    /// BLOB (never written by the store; only damage produces one).
    Blob(&'a [u8]),
}

/// A column's value as SQLite returned it, owned. Texts stay bytes until decoded.
#[derive(Debug, Clone)]
enum Raw {
    Null,
    Integer(i64),
    Real(f64),
    Text(Vec<u8>),
    Blob(Vec<u8>),
}

impl Raw {
    fn from_ref(value: ValueRef<'_>) -> Raw {
        match value {
            ValueRef::Null => Raw::Null,
            ValueRef::Integer(integer) => Raw::Integer(integer),
            ValueRef::Real(real) => Raw::Real(real),
            ValueRef::Text(bytes) => Raw::Text(bytes.to_vec()),
            ValueRef::Blob(bytes) => Raw::Blob(bytes.to_vec()),
        }
    }

    fn column(&self) -> Column<'_> {
        match self {
            Raw::Null => Column::Null,
            // SQLite may keep an integral REAL as an INTEGER on disk; both read as the number.
            Raw::Integer(integer) => Column::Number(*integer as f64),
            Raw::Real(real) => Column::Number(*real),
            Raw::Text(bytes) => Column::Text(bytes),
            Raw::Blob(bytes) => Column::Blob(bytes),
        }
    }

    fn type_name(&self) -> &'static str {
        match self {
            Raw::Null => "NULL",
            Raw::Integer(_) => "an integer",
            Raw::Real(_) => "a real number",
            Raw::Text(_) => "text",
            Raw::Blob(_) => "a blob",
        }
    }
}

/// A row of `evaluations` as SQLite returned it, before it is verified and decoded.
pub(crate) struct RawRow {
    columns: [Raw; RECORD_COLUMNS],
    /// The `settings` column (`NULL` before schema version 3 or for a record without settings).
    settings: Raw,
    checksum: Raw,
}

/// A decoded row: the record, when it was first stored, and whether a checksum vouched for it.
pub(crate) struct StoredRecord {
    pub(crate) record: Record,
    pub(crate) created_unix_s: Option<f64>,
    /// False for a record written before checksums (schema version 1): read unverified.
    pub(crate) verified: bool,
}

/// Reads the columns of [`RECORD_COLUMNS_SQL`] plus the settings and the checksum; never fails on
/// a value's type.
pub(crate) fn read_row(row: &rusqlite::Row<'_>) -> rusqlite::Result<RawRow> {
    let mut columns: [Raw; RECORD_COLUMNS] = std::array::from_fn(|_| Raw::Null);
    for (index, column) in columns.iter_mut().enumerate() {
        *column = Raw::from_ref(row.get_ref(index)?);
    }
    Ok(RawRow {
        columns,
        settings: Raw::from_ref(row.get_ref(RECORD_COLUMNS)?),
        checksum: Raw::from_ref(row.get_ref(RECORD_COLUMNS + 1)?),
    })
}

impl RawRow {
    /// Verifies the checksum and decodes the row; on failure returns `(key, what is wrong)`.
    pub(crate) fn decode(self) -> Result<StoredRecord, (String, String)> {
        let key = match &self.columns[0] {
            Raw::Text(bytes) => String::from_utf8_lossy(bytes).into_owned(),
            other => format!("<{} instead of a key>", other.type_name()),
        };
        self.decode_verified().map_err(|detail| (key, detail))
    }

    fn decode_verified(self) -> Result<StoredRecord, String> {
        let verified = self.verify()?;
        let settings = settings_of(self.settings)?;
        let [key, status, reason, variables, metrics, spec_toml, eval_seconds, solver, created] =
            self.columns;
        let status: Status = text(status, "status")?.parse().map_err(|e| format!("{e}"))?;
        let variables = named_values::decode_variables(&text(variables, "variables")?)
            .map_err(|detail| format!("variables: {detail}"))?;
        let metrics = named_values::decode(&text(metrics, "metrics")?)
            .map_err(|detail| format!("metrics: {detail}"))?;
        Ok(StoredRecord {
            record: Record {
                key: text(key, "key")?,
                status,
                reason: optional_text(reason, "reason")?,
                variables,
                metrics,
                spec_toml: text(spec_toml, "spec_toml")?,
                // SQLite stores a NaN REAL as NULL; read it back as the NaN it was.
                eval_seconds: number(eval_seconds, "eval_seconds")?.unwrap_or(f64::NAN),
                solver_version: optional_text(solver, "solver_version")?.unwrap_or_default(),
                settings,
            },
            created_unix_s: number(created, "created_unix_s")?,
            verified,
        })
    }

    /// `Ok(true)` when the stored checksum matches the row, `Ok(false)` when the row has none (a
    /// record written before checksums), an error when they differ.
    fn verify(&self) -> Result<bool, String> {
        let stored = match self.checksum {
            Raw::Null => return Ok(false),
            Raw::Integer(stored) => stored,
            ref other => {
                return Err(format!(
                    "its checksum is {} instead of an integer: the record is damaged",
                    other.type_name()
                ));
            }
        };
        let mut columns: Vec<Column<'_>> = self.columns.iter().map(Raw::column).collect();
        // Settings are hashed after the other columns when present (schema version 3), so a
        // record without them keeps the checksum it had in version 2.
        if !matches!(self.settings, Raw::Null) {
            columns.push(self.settings.column());
        }
        let computed = record_checksum(&columns);
        if computed == stored {
            Ok(true)
        } else {
            Err(format!(
                "checksum mismatch (stored {stored:#018x}, computed {computed:#018x}): the record \
                 was damaged or edited after it was written; it is refused rather than read wrong"
            ))
        }
    }
}

/// The `settings` column: `NULL` for none, else a JSON object.
fn settings_of(raw: Raw) -> Result<serde_json::Map<String, serde_json::Value>, String> {
    match optional_text(raw, "settings")? {
        None => Ok(serde_json::Map::new()),
        Some(text) => match serde_json::from_str(&text) {
            Ok(serde_json::Value::Object(map)) => Ok(map),
            _ => Err("settings: not a JSON object".into()),
        },
    }
}

fn text(raw: Raw, name: &str) -> Result<String, String> {
    match raw {
        Raw::Text(bytes) => String::from_utf8(bytes)
            .map_err(|e| format!("{name}: not valid UTF-8 ({})", e.utf8_error())),
        other => Err(format!("{name}: expected text, found {}", other.type_name())),
    }
}

fn optional_text(raw: Raw, name: &str) -> Result<Option<String>, String> {
    match raw {
        Raw::Null => Ok(None),
        other => text(other, name).map(Some),
    }
}

fn number(raw: Raw, name: &str) -> Result<Option<f64>, String> {
    match raw {
        Raw::Null => Ok(None),
        Raw::Real(real) => Ok(Some(real)),
        Raw::Integer(integer) => Ok(Some(integer as f64)),
        other => Err(format!("{name}: expected a number, found {}", other.type_name())),
    }
}

/// The `settings` column of `record`: `None` (NULL) when it has none.
fn settings_text(record: &Record) -> Option<String> {
    (!record.settings.is_empty())
        .then(|| serde_json::Value::Object(record.settings.clone()).to_string())
}

/// The checksum of the row `record` is written as (the encoded columns given).
fn checksum_of(
    record: &Record,
    created_unix_s: Option<f64>,
    variables: &str,
    metrics: &str,
    settings: Option<&str>,
) -> i64 {
    let mut columns = vec![
        Column::Text(record.key.as_bytes()),
        Column::Text(record.status.as_str().as_bytes()),
        record.reason.as_ref().map_or(Column::Null, |reason| Column::Text(reason.as_bytes())),
        Column::Text(variables.as_bytes()),
        Column::Text(metrics.as_bytes()),
        Column::Text(record.spec_toml.as_bytes()),
        Column::Number(record.eval_seconds),
        Column::Text(record.solver_version.as_bytes()),
        created_unix_s.map_or(Column::Null, Column::Number),
    ];
    columns.extend(settings.map(|text| Column::Text(text.as_bytes())));
    record_checksum(&columns)
}

/// The text columns of `record` and its checksum (when `checksummed`), as a row stores them.
struct Encoded {
    variables: String,
    metrics: String,
    settings: Option<String>,
    checksum: Option<i64>,
}

fn encode(record: &Record, created_unix_s: Option<f64>, checksummed: bool) -> Encoded {
    let variables = named_values::encode_variables(&record.variables);
    let metrics = named_values::encode(&record.metrics);
    let settings = settings_text(record);
    let checksum = checksummed
        .then(|| checksum_of(record, created_unix_s, &variables, &metrics, settings.as_deref()));
    Encoded { variables, metrics, settings, checksum }
}

/// Rewrites the outcome of the stored row of `record.key` (status, reason, metrics, settings, run
/// time, solver version) inside an open write transaction, keeping its place (`seq`), creation
/// time, variables and design; the checksum is recomputed when `checksummed`. The caller has
/// checked that the new record completes the stored one ([`crate::Store::complete`]).
pub(crate) fn rewrite_outcome(
    transaction: &rusqlite::Transaction<'_>,
    record: &Record,
    created_unix_s: Option<f64>,
    checksummed: bool,
) -> rusqlite::Result<bool> {
    let Encoded { metrics, settings, checksum, .. } = encode(record, created_unix_s, checksummed);
    let changed = transaction
        .prepare_cached(
            "UPDATE evaluations SET status = ?2, reason = ?3, metrics = ?4, eval_seconds = ?5, \
             solver_version = ?6, checksum = ?7, settings = ?8 WHERE key = ?1",
        )?
        .execute(params![
            record.key,
            record.status.as_str(),
            record.reason,
            metrics,
            record.eval_seconds,
            record.solver_version,
            checksum,
            settings,
        ])?;
    Ok(changed == 1)
}

/// Inserts `record` unless its key is present, inside an open write transaction, with its checksum
/// when `checksummed` (a record copied from a store without checksums stays unverified: a checksum
/// computed now would vouch for data nobody checked). The explicit look-up (rather than relying on
/// `ON CONFLICT DO NOTHING` alone) keeps `seq` free of gaps: SQLite allocates an AUTOINCREMENT
/// value even for a row the conflict clause then drops.
pub(crate) fn insert_new(
    transaction: &rusqlite::Transaction<'_>,
    record: &Record,
    created_unix_s: Option<f64>,
    checksummed: bool,
) -> rusqlite::Result<bool> {
    let present: bool = transaction
        .prepare_cached("SELECT EXISTS (SELECT 1 FROM evaluations WHERE key = ?1)")?
        .query_row([&record.key], |row| row.get(0))?;
    if present {
        return Ok(false);
    }
    let Encoded { variables, metrics, settings, checksum } =
        encode(record, created_unix_s, checksummed);
    let changed = transaction
        .prepare_cached(
            "INSERT INTO evaluations (key, status, reason, variables, metrics, spec_toml, \
             eval_seconds, solver_version, created_unix_s, checksum, settings) \
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11) ON CONFLICT (key) DO NOTHING",
        )?
        .execute(params![
            record.key,
            record.status.as_str(),
            record.reason,
            variables,
            metrics,
            record.spec_toml,
            record.eval_seconds,
            record.solver_version,
            created_unix_s,
            checksum,
            settings,
        ])?;
    Ok(changed == 1)
}
