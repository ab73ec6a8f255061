//! Opening a history and writing a night into it.
//!
//! Writers open the database in WAL mode with a busy timeout: a reader never blocks a writer, two
//! writers take turns, and a night goes in as one transaction — a killed or failed insert leaves
//! the database as it was. Nothing is written to a file before it is known to be an rsts history
//! (or a new, empty file) of a schema this rsts knows.

use std::path::{Path, PathBuf};
use std::time::Duration;

use rsts_harness::environment::Environment;
use rsts_validate::{Report, RunResult};
use rusqlite::{params, Connection, OpenFlags, TransactionBehavior};

use crate::schema::{self, Found, Migration};
use crate::HistoryError;

/// How long a writer waits for another one before giving up with [`HistoryError::Locked`].
pub const BUSY_TIMEOUT: Duration = Duration::from_secs(5);

/// Test hook: with this variable set to a number of seconds, a night's insert stops for that long
/// after half of its runs, inside its transaction, and says so on stderr (`history: paused
/// mid-insert`): what the test that kills a writer mid-insert needs.
pub const PAUSE_VARIABLE: &str = "RSTS_HISTORY_PAUSE_MID_INSERT";

/// An open history.
pub struct History {
    pub(crate) conn: Connection,
    path: PathBuf,
}

/// A night to record: a report (a whole suite, a shard, or a merge of shards), the night it
/// belongs to and where its report lives.
pub struct Night<'a> {
    pub report: &'a Report,
    /// UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub night: String,
    /// The report's directory (report.md, plots/, MCAP logs), linked from the dashboard.
    pub report_dir: Option<PathBuf>,
}

impl Night<'_> {
    /// The night of `report`: `night` when given, else the report's `created`.
    pub fn of<'a>(
        report: &'a Report,
        night: Option<&str>,
        report_dir: Option<PathBuf>,
        source: &str,
    ) -> Result<Night<'a>, HistoryError> {
        let text = match (night, report.created.as_deref()) {
            (Some(n), _) => n,
            (None, Some(c)) => c,
            (None, None) => {
                return Err(HistoryError::Usage(format!(
                    "{source} has no `created` time (a report of an older rsts): give --night TIME"
                )))
            }
        };
        let secs = rsts_io::utc::parse_utc(text).ok_or_else(|| {
            HistoryError::Usage(format!(
                "{source}: night '{text}' is not a UTC time (YYYY-MM-DDTHH:MM:SSZ or YYYY-MM-DD)"
            ))
        })?;
        Ok(Night {
            report,
            night: rsts_io::utc::format_utc(secs),
            report_dir,
        })
    }
}

fn display(path: &Path) -> String {
    path.display().to_string()
}

impl History {
    /// Open an existing history for reading. A missing file, another program's database, a
    /// file that is not SQLite, an empty database and a schema of another rsts are errors; the
    /// file is not written.
    pub fn open(path: &Path) -> Result<History, HistoryError> {
        if !path.is_file() {
            return Err(HistoryError::Missing(display(path)));
        }
        let conn = Connection::open_with_flags(
            path,
            OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
        )
        .map_err(|e| HistoryError::Foreign {
            path: display(path),
            why: e.to_string(),
        })?;
        conn.busy_timeout(BUSY_TIMEOUT)?;
        match schema::inspect(&conn, &display(path), schema::SCHEMA)? {
            Found::Empty => Err(HistoryError::Foreign {
                path: display(path),
                why: "an empty database, not a history yet".into(),
            }),
            Found::History(v) if v < schema::SCHEMA => Err(HistoryError::OldSchema {
                path: display(path),
                found: v,
                known: schema::SCHEMA,
            }),
            Found::History(_) => Ok(History {
                conn,
                path: path.to_path_buf(),
            }),
        }
    }

    /// Open a history for writing: a missing file is created (and its directory), an
    /// older schema is migrated, anything else that is not an rsts history is refused untouched.
    pub fn open_for_writing(path: &Path) -> Result<History, HistoryError> {
        Self::open_for_writing_with(path, schema::MIGRATIONS, BUSY_TIMEOUT)
    }

    /// [`History::open_for_writing`] with other migrations and busy timeout (tests).
    pub fn open_for_writing_with(
        path: &Path,
        migrations: &[Migration],
        busy: Duration,
    ) -> Result<History, HistoryError> {
        let p = display(path);
        if path.exists() && !path.is_file() {
            return Err(HistoryError::Usage(format!("{p} is not a regular file")));
        }
        if !path.exists() {
            // A new history: its directory is made as for any output (rsts_io::check_writable).
            if let Some(parent) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(parent).map_err(|e| {
                    HistoryError::Io(format!("{p}: cannot create {}: {e}", parent.display()))
                })?;
            }
        }
        let mut conn = Connection::open(path).map_err(|e| HistoryError::Foreign {
            path: p.clone(),
            why: e.to_string(),
        })?;
        conn.busy_timeout(busy)?;
        schema::inspect(&conn, &p, migrations.len() as i32)?;
        // Ours (or new): WAL, so that readers and one writer never block each other, and a
        // commit is one append to the log.
        let mode: String = conn
            .query_row("PRAGMA journal_mode = WAL", [], |r| r.get(0))
            .map_err(|e| locked_or(e, &p))?;
        if !mode.eq_ignore_ascii_case("wal") {
            return Err(HistoryError::Usage(format!(
                "{p}: cannot use write-ahead logging (journal mode {mode}); a history needs a local file system"
            )));
        }
        conn.execute_batch("PRAGMA synchronous = FULL; PRAGMA foreign_keys = ON;")?;
        schema::migrate(&mut conn, migrations).map_err(|e| match e {
            HistoryError::Sqlite(s) => locked_or(s, &p),
            other => other,
        })?;
        Ok(History {
            conn,
            path: path.to_path_buf(),
        })
    }

    /// Check, before a long run, that a night could be recorded at `path`: an existing file
    /// must be a history this rsts can write and not locked by another writer (older schemas are
    /// migrated now); for a missing one, its directory must take a new file (nothing is created).
    pub fn check_for_writing(path: &Path) -> Result<(), HistoryError> {
        if path.exists() {
            return Self::open_for_writing(path)?.check_writable();
        }
        rsts_io::check_writable(path)
            .map_err(|e| HistoryError::Io(format!("{}: {e}", display(path))))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Check, before a long run, that a night could be written now: take the write lock and
    /// give it back (waits [`BUSY_TIMEOUT`] for another writer).
    pub fn check_writable(&mut self) -> Result<(), HistoryError> {
        let p = display(&self.path);
        let tx = self
            .conn
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| locked_or(e, &p))?;
        tx.rollback()?;
        Ok(())
    }

    /// Whether this report is already recorded (the same report.json, whatever its night).
    pub fn has(&self, night: &Night) -> Result<bool, HistoryError> {
        let n: i64 = self.conn.query_row(
            "SELECT count(*) FROM nights WHERE report_hash = ?1",
            params![report_hash(night.report)],
            |r| r.get(0),
        )?;
        Ok(n > 0)
    }

    /// Record a night, all of it in one transaction; returns its id. A report already recorded
    /// is an error and changes nothing.
    pub fn record(&mut self, night: &Night) -> Result<i64, HistoryError> {
        let p = display(&self.path);
        if self.has(night)? {
            return Err(HistoryError::Usage(format!(
                "{p} already holds this report of suite {} (shard {}, made {})",
                night.report.suite,
                shard_of(night.report),
                night
                    .report
                    .created
                    .as_deref()
                    .unwrap_or("at an unknown time")
            )));
        }
        let pause = std::env::var(PAUSE_VARIABLE)
            .ok()
            .and_then(|s| s.parse::<f64>().ok());
        let tx = self
            .conn
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| locked_or(e, &p))?;
        let r = night.report;
        tx.execute(
            "INSERT INTO nights (night, created, commit_id, rsts_version, suite, suite_digest,
                total_runs, shard, runs, passed, failed, errors, wall_seconds, report_dir, recorded,
                report_hash)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)",
            params![
                night.night,
                r.created,
                r.commit.as_deref().unwrap_or("unknown"),
                r.rsts_version.as_deref().unwrap_or("unknown"),
                r.suite,
                r.suite_digest,
                r.total_runs as i64,
                shard_of(r),
                r.summary.runs as i64,
                r.summary.passed as i64,
                r.summary.failed as i64,
                r.summary.errors as i64,
                r.timing.wall_seconds,
                night.report_dir.as_ref().map(|d| display(d)),
                rsts_io::utc::now_utc(),
                report_hash(r),
            ],
        )?;
        let night_id = tx.last_insert_rowid();
        // The environment of each shard (one for a whole run).
        let machines = machines_of(r);
        let mut env_ids = Vec::new();
        for (shard, env, created) in &machines {
            tx.execute(
                "INSERT OR IGNORE INTO environments (cpu, simd, cores, os) VALUES (?1, ?2, ?3, ?4)",
                params![env.cpu, env.simd, env.cores as i64, env.os],
            )?;
            let id: i64 = tx.query_row(
                "SELECT id FROM environments WHERE cpu = ?1 AND simd = ?2 AND cores = ?3 AND os = ?4",
                params![env.cpu, env.simd, env.cores as i64, env.os],
                |row| row.get(0),
            )?;
            tx.execute(
                "INSERT INTO night_machines (night_id, shard, environment_id, environment, created)
                 VALUES (?1, ?2, ?3, ?4, ?5)",
                params![
                    night_id,
                    shard,
                    id,
                    serde_json::to_string(env).expect("environment serialises"),
                    created
                ],
            )?;
            env_ids.push(id);
        }
        let mut run_stmt = tx.prepare(
            "INSERT INTO runs (night_id, run_id, environment_id, case_name, camera, torus, method,
                tolerance, rtol, digits, status, failures, error, growth_kind, thresholds, result)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)",
        )?;
        let mut fig_stmt = tx.prepare(
            "INSERT INTO figures (night_id, run_id, metric, value, bits) VALUES (?1, ?2, ?3, ?4, ?5)",
        )?;
        for (k, run) in r.runs.iter().enumerate() {
            if pause.is_some() && k == r.runs.len() / 2 {
                eprintln!("history: paused mid-insert");
                std::thread::sleep(Duration::from_secs_f64(
                    pause.unwrap_or(0.0).clamp(0.0, 600.0),
                ));
            }
            // A merged report: run k of the id-sorted suite ran in shard (k mod n) + 1.
            let env_id = if env_ids.len() > 1 {
                env_ids[k % env_ids.len()]
            } else {
                env_ids[0]
            };
            let mut lean = run.clone();
            lean.series = Default::default();
            run_stmt.execute(params![
                night_id,
                run.id,
                env_id,
                run.case,
                run.camera,
                run.torus as i64,
                run.method,
                tolerance_of(run),
                run.rtol,
                run.digits.map(i64::from),
                serde_json::to_value(run.status)
                    .expect("status")
                    .as_str()
                    .unwrap_or(""),
                serde_json::to_string(&run.failures).expect("failures serialise"),
                run.error,
                run.growth
                    .state_error
                    .map(|g| format!("{:?}", g.model).to_lowercase()),
                serde_json::to_string(&run.thresholds).expect("thresholds serialise"),
                serde_json::to_string(&lean).expect("run serialises"),
            ])?;
            for (metric, value) in crate::series::figures_of(run) {
                fig_stmt.execute(params![
                    night_id,
                    run.id,
                    metric.name(),
                    value,
                    value.to_bits() as i64
                ])?;
            }
        }
        drop(run_stmt);
        drop(fig_stmt);
        tx.commit().map_err(|e| locked_or(e, &p))?;
        Ok(night_id)
    }
}

/// FNV-1a (64 bits) of the report's JSON: tells a report already recorded (two runs of a suite
/// differ at least in their times; not a defence against a forged file).
fn report_hash(r: &Report) -> String {
    let json = serde_json::to_string(r).expect("report serialises");
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in json.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// `k/n` of a shard, `1/1` for a whole (or merged) suite.
pub(crate) fn shard_of(r: &Report) -> String {
    r.shard.map_or("1/1".to_string(), |s| s.to_string())
}

/// The tolerance of a run as a series names it: `1e-12`, `1e-12/30d`, `30d`, or `-`.
pub fn tolerance_of(run: &RunResult) -> String {
    match (run.rtol, run.digits) {
        (Some(t), Some(d)) => format!("{t:e}/{d}d"),
        (Some(t), None) => format!("{t:e}"),
        (None, Some(d)) => format!("{d}d"),
        (None, None) => "-".into(),
    }
}

/// Each shard's (shard, environment, created) of a report: its parts for a merge whose shards
/// ran apart, else the report's own. A report without an environment (an older rsts) gets
/// "unknown" in every field.
fn machines_of(r: &Report) -> Vec<(String, Environment, Option<String>)> {
    let unknown = || Environment {
        cpu: "unknown".into(),
        simd: "unknown".into(),
        cores: 0,
        os: "unknown".into(),
        rsts_version: r.rsts_version.clone().unwrap_or_else(|| "unknown".into()),
        commit: r.commit.clone().unwrap_or_else(|| "unknown".into()),
        adapters: Vec::new(),
    };
    if r.environment.is_none() && !r.parts.is_empty() {
        let mut parts = r.parts.clone();
        parts.sort_by_key(|p| p.shard.k);
        return parts
            .into_iter()
            .map(|p| {
                (
                    p.shard.to_string(),
                    p.environment.unwrap_or_else(unknown),
                    p.created,
                )
            })
            .collect();
    }
    vec![(
        shard_of(r),
        r.environment.clone().unwrap_or_else(unknown),
        r.created.clone(),
    )]
}

/// SQLITE_BUSY / SQLITE_LOCKED as [`HistoryError::Locked`]; anything else as it is.
fn locked_or(e: rusqlite::Error, path: &str) -> HistoryError {
    match e.sqlite_error_code() {
        Some(rusqlite::ErrorCode::DatabaseBusy | rusqlite::ErrorCode::DatabaseLocked) => {
            HistoryError::Locked(path.to_string())
        }
        _ => HistoryError::Sqlite(e),
    }
}
