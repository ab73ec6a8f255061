//! The database's schema and its migrations.
//!
//! A history is an SQLite file whose `application_id` is [`APPLICATION_ID`] and whose
//! `user_version` is the number of migrations applied. Migration k takes schema k − 1 to k; each
//! runs in its own transaction together with its `user_version`, so a killed or failed migration
//! leaves the previous schema whole.

use rusqlite::{Connection, TransactionBehavior};

use crate::HistoryError;

/// `PRAGMA application_id` of an rsts history ("RSTS" in ASCII).
pub const APPLICATION_ID: i32 = 0x5253_5453;

/// The schema this rsts writes and reads: the number of [`MIGRATIONS`].
pub const SCHEMA: i32 = MIGRATIONS.len() as i32;

/// One step of the schema: the SQL that takes schema k − 1 to k (k = its index + 1).
pub type Migration = &'static str;

/// The migrations, oldest first.
pub const MIGRATIONS: &[Migration] = &[
    // 1: nights, the environments they ran in (one per shard), runs and their figures.
    "CREATE TABLE environments (
        id INTEGER PRIMARY KEY,
        cpu TEXT NOT NULL,
        simd TEXT NOT NULL,
        cores INTEGER NOT NULL,
        os TEXT NOT NULL,
        UNIQUE (cpu, simd, cores, os)
    );
    CREATE TABLE nights (
        id INTEGER PRIMARY KEY,
        night TEXT NOT NULL,
        created TEXT,
        commit_id TEXT NOT NULL,
        rsts_version TEXT NOT NULL,
        suite TEXT NOT NULL,
        suite_digest TEXT NOT NULL,
        total_runs INTEGER NOT NULL,
        shard TEXT NOT NULL,
        runs INTEGER NOT NULL,
        passed INTEGER NOT NULL,
        failed INTEGER NOT NULL,
        errors INTEGER NOT NULL,
        wall_seconds REAL NOT NULL,
        report_dir TEXT,
        recorded TEXT NOT NULL,
        report_hash TEXT NOT NULL UNIQUE
    );
    CREATE INDEX nights_night ON nights (night);
    CREATE TABLE night_machines (
        night_id INTEGER NOT NULL REFERENCES nights(id) ON DELETE CASCADE,
        shard TEXT NOT NULL,
        environment_id INTEGER NOT NULL REFERENCES environments(id),
        environment TEXT NOT NULL,
        created TEXT,
        PRIMARY KEY (night_id, shard)
    );
    CREATE TABLE runs (
        night_id INTEGER NOT NULL REFERENCES nights(id) ON DELETE CASCADE,
        run_id TEXT NOT NULL,
        environment_id INTEGER NOT NULL REFERENCES environments(id),
        case_name TEXT NOT NULL,
        camera TEXT NOT NULL,
        torus INTEGER NOT NULL,
        method TEXT NOT NULL,
        tolerance TEXT NOT NULL,
        rtol REAL,
        digits INTEGER,
        status TEXT NOT NULL,
        failures TEXT NOT NULL,
        error TEXT,
        growth_kind TEXT,
        thresholds TEXT NOT NULL,
        result TEXT NOT NULL,
        PRIMARY KEY (night_id, run_id)
    );
    CREATE TABLE figures (
        night_id INTEGER NOT NULL,
        run_id TEXT NOT NULL,
        metric TEXT NOT NULL,
        value REAL,
        bits INTEGER NOT NULL,
        PRIMARY KEY (night_id, run_id, metric),
        FOREIGN KEY (night_id, run_id) REFERENCES runs(night_id, run_id) ON DELETE CASCADE
    );
    CREATE INDEX runs_series ON runs (case_name, method, tolerance);",
];

/// What an open file holds.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Found {
    /// No table at all: a new (or zero-length) file.
    Empty,
    /// An rsts history at this schema.
    History(i32),
}

/// Read what the file is, without writing anything: an rsts history (and its schema), an empty
/// database, or an error for a file that is not SQLite, another program's database, or a
/// history of a schema after `known`.
pub(crate) fn inspect(conn: &Connection, path: &str, known: i32) -> Result<Found, HistoryError> {
    let foreign = |why: String| HistoryError::Foreign {
        path: path.to_string(),
        why,
    };
    let app: i32 = conn
        .query_row("PRAGMA application_id", [], |r| r.get(0))
        .map_err(|e| foreign(e.to_string()))?;
    let version: i32 = conn
        .query_row("PRAGMA user_version", [], |r| r.get(0))
        .map_err(|e| foreign(e.to_string()))?;
    let tables: i64 = conn
        .query_row(
            "SELECT count(*) FROM sqlite_schema WHERE type = 'table'",
            [],
            |r| r.get(0),
        )
        .map_err(|e| foreign(e.to_string()))?;
    if app == 0 && version == 0 && tables == 0 {
        return Ok(Found::Empty);
    }
    if app != APPLICATION_ID {
        return Err(foreign(format!(
            "an SQLite database of another program (application_id {app:#x}, {tables} tables)"
        )));
    }
    if version > known {
        return Err(HistoryError::FutureSchema {
            path: path.to_string(),
            found: version,
            known,
        });
    }
    Ok(Found::History(version))
}

/// Bring the database to the last of `migrations`: each step in its own immediate transaction
/// (the version is read again inside it, so two writers migrating at once apply each step once).
pub(crate) fn migrate(conn: &mut Connection, migrations: &[Migration]) -> Result<(), HistoryError> {
    loop {
        let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
        let version: i32 = tx.query_row("PRAGMA user_version", [], |r| r.get(0))?;
        let Some(step) = migrations.get(version as usize) else {
            return Ok(());
        };
        tx.execute_batch(step)?;
        tx.execute_batch(&format!(
            "PRAGMA application_id = {APPLICATION_ID}; PRAGMA user_version = {};",
            version + 1
        ))?;
        tx.commit()?;
    }
}
