//! Persistence: opening (and creating) the database, running the migrations, and the queries
//! the HTTP layer needs — on SQLite (the embedded default, a file) or on PostgreSQL (a
//! `postgres://` URL, for a cluster of nodes sharing their state).
//!
//! One set of queries serves both through sqlx's `Any` driver: plain SQL both understand
//! (`$1` placeholders, `ON CONFLICT … DO UPDATE`, `excluded`), on the same tables. The schema is
//! kept twice, `migrations/` for SQLite and `migrations/postgres/` for PostgreSQL (its column
//! types: BIGINT for INTEGER, DOUBLE PRECISION for REAL, an identity `rowid`), and a test holds
//! the two equal table by table and column by column.
//!
//! Queries are runtime queries (`sqlx::query`), not the compile-time checked macros, so building
//! the crate never needs a database. The migrations are embedded into the binary with
//! `sqlx::migrate!`, so a fresh database is migrated on start with no extra files at run time.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use sqlx::any::{AnyConnectOptions, AnyPoolOptions};
use sqlx::{AnyConnection, AnyPool, ConnectOptions, Executor, Row};

type AnyRow = sqlx::any::AnyRow;

/// The SQLite migrations embedded from the workspace's `migrations/` directory.
pub static MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("../migrations");

/// The same schema for PostgreSQL (`migrations/postgres/`).
pub static POSTGRES_MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("../migrations/postgres");

/// Why the database could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    #[error("cannot open database {path}: {source}")]
    Connect {
        path: String,
        #[source]
        source: sqlx::Error,
    },
    #[error("cannot migrate database {path}: {source}")]
    Migrate {
        path: String,
        #[source]
        source: sqlx::migrate::MigrateError,
    },
    #[error("cannot read the controllers of {path}: {source}")]
    Load {
        path: String,
        #[source]
        source: sqlx::Error,
    },
}

/// Which database the service keeps its state in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Sqlite,
    Postgres,
}

impl Backend {
    /// `sqlite` or `postgres`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Sqlite => "sqlite",
            Backend::Postgres => "postgres",
        }
    }
}

/// The database as the service uses it: readers and writers.
///
/// *Decision* (docs/api.md, "The database"): SQLite lets one connection write at a time. Several
/// connections that write race for the lock, and a transaction that reads before it writes
/// cannot wait for it (SQLite answers `SQLITE_BUSY` at once, the busy handler does not run), so
/// requests failed with "database is locked" whenever the workers' records were being written.
/// Here every write and every write transaction goes through the one connection of the writer
/// pool, in turn (a request waits for the connection, never for a lock), and a transaction
/// that reads before it writes starts with `BEGIN IMMEDIATE`. The readers are `query_only`, so a
/// write sent to them fails in every test instead of racing the writer; WAL lets them read
/// while the writer writes. The busy timeout stays as a defence against other processes
/// (`sqlite3` on the same file). PostgreSQL has row locks and many writers: there both are one
/// pool.
#[derive(Clone, Debug)]
pub struct Db {
    reads: AnyPool,
    writes: AnyPool,
    backend: Backend,
    /// The workers' records that could not be stored (`write_records`), for `/metrics`.
    failed_records: Arc<AtomicU64>,
    /// The workers' records `write_records` is done with (stored, or failed and counted): a
    /// `watch`, so a request can wait for the writer to reach its own record
    /// ([`Db::records_written`]).
    records_done: Arc<tokio::sync::watch::Sender<u64>>,
}

/// Readers: enough for the handlers that read at once on a small machine.
const READERS: u32 = 4;

/// Connections to PostgreSQL, readers and writers together.
const POSTGRES_CONNECTIONS: u32 = 8;

/// How long a request may wait for the writer before it fails (a defence: a write takes
/// milliseconds, and the queue is fair).
const WRITER_WAIT: Duration = Duration::from_secs(60);

/// How long a SQLite connection waits for a lock another process holds, ms.
const BUSY_TIMEOUT_MS: u32 = 5000;

impl Db {
    /// The pool of connections that read (on SQLite `query_only`).
    pub fn reads(&self) -> &AnyPool {
        &self.reads
    }

    /// The pool of connections that write (on SQLite the one connection).
    pub fn writes(&self) -> &AnyPool {
        &self.writes
    }

    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// The SQLite database's file (an in-memory database, or PostgreSQL: none), for what the
    /// service keeps beside it (the OPC UA server's certificates).
    pub fn sqlite_file(&self) -> Option<std::path::PathBuf> {
        if self.backend != Backend::Sqlite {
            return None;
        }
        let url = self.writes.connect_options().database_url.clone();
        // `sqlite_url` percent-encoded it.
        let path =
            std::path::PathBuf::from(percent_encoding::percent_decode_str(url.path()).decode_utf8().ok()?.as_ref());
        (url.scheme() == "sqlite" && path.is_absolute()).then_some(path)
    }

    /// The workers' records that could not be stored since the service started (each failed
    /// record, and each failed batch as one).
    pub fn failed_records(&self) -> u64 {
        self.failed_records.load(Ordering::Relaxed)
    }

    /// How many of the workers' records the writer is done with, in the order they were sent
    /// (`host::Host::records_sent`): stored, or failed (and counted in `failed_records`).
    pub fn records_done(&self) -> u64 {
        *self.records_done.borrow()
    }

    /// Waits until the writer is done with the first `count` records sent to it
    /// (`host::Host::record` numbers them), at most [`WRITER_WAIT`]: whether it got there.
    pub async fn records_written(&self, count: u64) -> bool {
        let mut done = self.records_done.subscribe();
        // (The sender lives as long as `self`: `wait_for` cannot fail on a closed channel.)
        let reached = tokio::time::timeout(WRITER_WAIT, done.wait_for(|d| *d >= count)).await;
        matches!(reached, Ok(Ok(_)))
    }

    /// A write transaction; on SQLite it holds the write lock from its start (`BEGIN
    /// IMMEDIATE`), for a transaction that reads before it writes.
    async fn begin_write(&self) -> Result<sqlx::Transaction<'static, sqlx::Any>, sqlx::Error> {
        match self.backend {
            Backend::Sqlite => self.writes.begin_with("BEGIN IMMEDIATE").await,
            Backend::Postgres => self.writes.begin().await,
        }
    }

    /// Closes both pools (waiting for the connections in use); the writer last, so that it is
    /// the one that checkpoints SQLite's WAL into the file.
    pub async fn close(&self) {
        self.reads.close().await;
        self.writes.close().await;
    }

    pub fn is_closed(&self) -> bool {
        self.writes.is_closed() || self.reads.is_closed()
    }

    /// Whether the database answers: the readers run a query, and the writer is there (a query
    /// on SQLite's would wait behind the writes).
    pub async fn ping(&self) -> Result<(), sqlx::Error> {
        let writer = if self.writes.is_closed() { Err(sqlx::Error::PoolClosed) } else { Ok(()) };
        let reader = sqlx::query("SELECT 1").execute(&self.reads).await.map(|_| ());
        writer.and(reader)
    }
}

/// Opens the database `db` names — a `postgres://` (or `postgresql://`) URL, else the path of a
/// SQLite file — and brings its schema up to date.
pub async fn open_any(db: &str) -> Result<Db, OpenError> {
    if is_postgres(db) {
        open_postgres(db).await
    } else {
        open(Path::new(db)).await
    }
}

/// Whether `db` (as `open_any` takes it) names a PostgreSQL database rather than a SQLite file.
pub fn is_postgres(db: &str) -> bool {
    db.starts_with("postgres://") || db.starts_with("postgresql://")
}

/// `db` as `open_any` takes it, for messages and logs: a URL without its password.
pub fn shown(db: &str) -> String {
    match url::Url::parse(db) {
        Ok(mut url) if url.scheme().starts_with("postgres") => {
            if url.password().is_some() {
                let _ = url.set_password(Some("***"));
            }
            url.to_string()
        }
        _ => db.to_string(),
    }
}

/// Opens the SQLite database at `path`, creating the file if it is missing, and brings its schema
/// up to date. Foreign keys are enforced (deleting a controller deletes its programs and
/// variables) and the journal is in WAL mode so readers do not block the writer.
pub async fn open(path: &Path) -> Result<Db, OpenError> {
    sqlx::any::install_default_drivers();
    let shown = path.display().to_string();
    let connect = |source| OpenError::Connect { path: shown.clone(), source };
    let url = sqlite_url(path).map_err(connect)?;
    sqlite_usable(&url).await.map_err(connect)?;
    // The writer first: it creates the file and turns on WAL, which the readers then find.
    let writes = AnyPoolOptions::new()
        .max_connections(1)
        .min_connections(1)
        .acquire_timeout(WRITER_WAIT)
        .idle_timeout(None)
        .max_lifetime(None)
        .after_connect(|conn, _| Box::pin(async move { sqlite_pragmas(conn, false).await }))
        .connect_with(url.clone())
        .await
        .map_err(connect)?;
    MIGRATOR.run(&writes).await.map_err(|source| OpenError::Migrate { path: shown.clone(), source })?;
    let reads = AnyPoolOptions::new()
        .max_connections(READERS)
        .after_connect(|conn, _| Box::pin(async move { sqlite_pragmas(conn, true).await }))
        .connect_with(url)
        .await
        .map_err(connect)?;
    Ok(Db {
        reads,
        writes,
        backend: Backend::Sqlite,
        failed_records: Default::default(),
        records_done: Default::default(),
    })
}

/// The lock a `fivex serve` holds on its SQLite file for as long as it runs
/// ([`lock_sqlite`]); the operating system lets it go when the process ends, however it ends.
#[derive(Debug)]
pub struct FileLock {
    _file: std::fs::File,
}

/// Takes the lock of the SQLite database at `path`: an exclusive lock on `<path>.lock` beside
/// it (created if missing, left there), or a message for the user when another process holds
/// it.
///
/// *Decision* (docs/api.md, "The database"): each `fivex serve` keeps its controllers in memory
/// and writes whole rows from its copy, so two services on one file overwrote each other's
/// acknowledged changes. The second is refused at start. The lock is a file of its own, not
/// SQLite's locks: SQLite's exclusive locking mode would shut out the service's own readers,
/// and a tool that only reads the file (`sqlite3 fivex.db`) is still let in. The file is named
/// after the database's real path, so two spellings of one file take the same lock.
pub fn lock_sqlite(path: &Path) -> Result<FileLock, String> {
    use std::io::{Read, Seek, Write};
    let shown = path.display();
    let real = std::fs::canonicalize(path)
        .or_else(|_| std::path::absolute(path))
        .map_err(|e| format!("cannot open database {shown}: {e}"))?;
    let mut name = real.into_os_string();
    name.push(".lock");
    let lock = std::path::PathBuf::from(name);
    let opened = std::fs::OpenOptions::new().create(true).truncate(false).read(true).write(true).open(&lock);
    // A lock file another user made (an earlier service as root) locks as well read-only.
    let opened = match opened {
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => std::fs::File::open(&lock),
        opened => opened,
    };
    let mut file = opened
        .map_err(|e| format!("cannot open database {shown}: cannot open its lock file {}: {e}", lock.display()))?;
    match file.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => {
            let mut holder = String::new();
            let _ = file.read_to_string(&mut holder);
            let holder = match holder.trim() {
                "" => String::new(),
                pid => format!(" (process {pid})"),
            };
            return Err(format!(
                "cannot open database {shown}: another fivex serve uses it{holder}, holding {}; two services on                  one SQLite file would overwrite each other's changes: stop the other one, or give this one                  another --db",
                lock.display()
            ));
        }
        Err(std::fs::TryLockError::Error(e)) => {
            return Err(format!("cannot open database {shown}: cannot lock {}: {e}", lock.display()))
        }
    }
    // Who holds it, for the message above (the lock, not this text, is what counts).
    let _ = file.set_len(0).and_then(|_| file.rewind()).and_then(|_| writeln!(file, "{}", std::process::id()));
    Ok(FileLock { _file: file })
}

/// The `Any` options of a SQLite file, created if missing (`mode=rwc`): its absolute path,
/// percent-encoded (a `?` or `#` in a file name stays in it).
fn sqlite_url(path: &Path) -> Result<AnyConnectOptions, sqlx::Error> {
    let absolute = std::path::absolute(path).map_err(|e| sqlx::Error::Configuration(e.into()))?;
    let mut url = url::Url::parse("sqlite:///").map_err(|e| sqlx::Error::Configuration(e.into()))?;
    url.set_path(&absolute.to_string_lossy());
    url.set_query(Some("mode=rwc"));
    AnyConnectOptions::from_url(&url)
}

/// One connection first, which fails at once with SQLite's own reason: a pool retries a
/// connection that fails until its acquire timeout (60 s), then says only that it timed out (a
/// file that is not a database took 68 s to refuse, "pool timed out"). It also writes (the
/// header's `user_version`, as it is), so a file the service may read but not write is refused
/// at start ("attempt to write a readonly database"), not answered 500 at every write.
async fn sqlite_usable(url: &AnyConnectOptions) -> Result<(), sqlx::Error> {
    use sqlx::Connection;
    let mut conn = url.connect().await?;
    sqlite_pragmas(&mut conn, false).await?;
    let version: i64 = sqlx::query_scalar("PRAGMA user_version").fetch_one(&mut conn).await?;
    sqlx::query(&format!("PRAGMA user_version = {version}")).execute(&mut conn).await?;
    conn.close().await
}

/// What every SQLite connection is set to: foreign keys enforced, WAL, synchronous NORMAL (safe
/// with WAL), the busy timeout; readers `query_only`.
async fn sqlite_pragmas(conn: &mut AnyConnection, read_only: bool) -> Result<(), sqlx::Error> {
    conn.execute(
        format!(
            "PRAGMA foreign_keys = ON; PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL; \
             PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}; PRAGMA query_only = {}",
            if read_only { "ON" } else { "OFF" }
        )
        .as_str(),
    )
    .await
    .map(|_| ())
}

/// Opens the PostgreSQL database at `url` and brings its schema up to date (the database must
/// exist; the tables are created).
pub async fn open_postgres(url: &str) -> Result<Db, OpenError> {
    sqlx::any::install_default_drivers();
    let shown = shown(url);
    let pool = AnyPoolOptions::new()
        .max_connections(POSTGRES_CONNECTIONS)
        .acquire_timeout(WRITER_WAIT)
        .connect(url)
        .await
        .map_err(|source| OpenError::Connect { path: shown.clone(), source })?;
    POSTGRES_MIGRATOR.run(&pool).await.map_err(|source| OpenError::Migrate { path: shown, source })?;
    Ok(Db {
        reads: pool.clone(),
        writes: pool,
        backend: Backend::Postgres,
        failed_records: Default::default(),
        records_done: Default::default(),
    })
}

/// One row of the `controllers` table.
#[derive(Debug, Clone, PartialEq)]
pub struct ControllerRow {
    pub id: String,
    pub name: String,
    pub dialect: String,
    pub machine_json: String,
    pub created_at: String,
}

impl ControllerRow {
    fn from_row(row: &AnyRow) -> Result<Self, sqlx::Error> {
        Ok(Self {
            id: row.try_get("id")?,
            name: row.try_get("name")?,
            dialect: row.try_get("dialect")?,
            machine_json: row.try_get("machine_json")?,
            created_at: row.try_get("created_at")?,
        })
    }
}

/// Every stored controller, oldest first (ties broken by id, so the order is stable).
pub async fn list_controllers(db: &Db) -> Result<Vec<ControllerRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT id, name, dialect, machine_json, created_at FROM controllers \
         ORDER BY created_at, id",
    )
    .fetch_all(db.reads())
    .await?;
    rows.iter().map(ControllerRow::from_row).collect()
}

/// The ids of every stored controller (what a node of a cluster places, `crate::placement`).
pub async fn controller_ids(db: &Db) -> Result<Vec<String>, sqlx::Error> {
    let rows = sqlx::query("SELECT id FROM controllers ORDER BY created_at, id").fetch_all(db.reads()).await?;
    rows.iter().map(|r| r.try_get("id")).collect()
}

/// Inserts a controller row. The controllers API (a later issue) builds on this; tests use it
/// to check the list endpoint against real rows.
pub async fn insert_controller(db: &Db, row: &ControllerRow) -> Result<(), sqlx::Error> {
    sqlx::query(
        "INSERT INTO controllers (id, name, dialect, machine_json, created_at) \
         VALUES ($1, $2, $3, $4, $5)",
    )
    .bind(&row.id)
    .bind(&row.name)
    .bind(&row.dialect)
    .bind(&row.machine_json)
    .bind(&row.created_at)
    .execute(db.writes())
    .await?;
    Ok(())
}

/// Removes a controller and (by the foreign keys) everything stored for it; false if there was
/// none.
pub async fn delete_controller(db: &Db, id: &str) -> Result<bool, sqlx::Error> {
    let done = sqlx::query("DELETE FROM controllers WHERE id = $1").bind(id).execute(db.writes()).await?;
    Ok(done.rows_affected() > 0)
}

/// Sets a controller's name and speed factor.
pub async fn update_controller(db: &Db, id: &str, name: &str, speed: f64) -> Result<(), sqlx::Error> {
    sqlx::query("UPDATE controllers SET name = $1, speed = $2 WHERE id = $3")
        .bind(name)
        .bind(speed)
        .bind(id)
        .execute(db.writes())
        .await?;
    Ok(())
}

/// The speed factor and the extra parameters (JSON) stored for each controller.
pub async fn controller_settings(db: &Db) -> Result<std::collections::HashMap<String, (f64, String)>, sqlx::Error> {
    let rows = sqlx::query("SELECT id, speed, extra_parameters FROM controllers").fetch_all(db.reads()).await?;
    rows.iter().map(|r| Ok((r.try_get("id")?, (r.try_get("speed")?, r.try_get("extra_parameters")?)))).collect()
}

/// Inserts a controller row with its speed factor, the parameters its model does not read and
/// what is on its table (`None`: nothing).
pub async fn insert_controller_with(
    db: &Db,
    row: &ControllerRow,
    speed: f64,
    extra_json: &str,
    workpiece_json: Option<&str>,
) -> Result<(), sqlx::Error> {
    sqlx::query(
        "INSERT INTO controllers (id, name, dialect, machine_json, created_at, speed, extra_parameters, workpiece) \
         VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
    )
    .bind(&row.id)
    .bind(&row.name)
    .bind(&row.dialect)
    .bind(&row.machine_json)
    .bind(&row.created_at)
    .bind(speed)
    .bind(extra_json)
    .bind(workpiece_json)
    .execute(db.writes())
    .await?;
    Ok(())
}

/// Copies a controller with everything it keeps but its history (machine, dialect, speed,
/// parameters, the workpiece, programs, retained variables, tool and work offsets) to a new id
/// and name, in one transaction. False if there is no controller `from`.
pub async fn clone_controller(
    db: &Db,
    from: &str,
    id: &str,
    name: &str,
    created_at: &str,
) -> Result<bool, sqlx::Error> {
    let mut tx = db.begin_write().await?;
    let copied = sqlx::query(
        "INSERT INTO controllers (id, name, dialect, machine_json, created_at, speed, extra_parameters, workpiece) \
         SELECT $1, $2, dialect, machine_json, $3, speed, extra_parameters, workpiece FROM controllers WHERE id = $4",
    )
    .bind(id)
    .bind(name)
    .bind(created_at)
    .bind(from)
    .execute(&mut *tx)
    .await?;
    if copied.rows_affected() == 0 {
        return Ok(false);
    }
    for copy in [
        "INSERT INTO programs (controller_id, number, text) SELECT $1, number, text FROM programs WHERE controller_id = $2",
        "INSERT INTO variables (controller_id, number, value) SELECT $1, number, value FROM variables WHERE controller_id = $2",
        "INSERT INTO tool_offsets (controller_id, number, length, length_wear, radius, radius_wear, corner_radius) \
         SELECT $1, number, length, length_wear, radius, radius_wear, corner_radius FROM tool_offsets \
         WHERE controller_id = $2",
        "INSERT INTO work_offsets (controller_id, slot, axes) SELECT $1, slot, axes FROM work_offsets WHERE controller_id = $2",
    ] {
        sqlx::query(copy).bind(id).bind(from).execute(&mut *tx).await?;
    }
    tx.commit().await?;
    Ok(true)
}

/// One stored controller row.
pub async fn controller(db: &Db, id: &str) -> Result<Option<ControllerRow>, sqlx::Error> {
    let row = sqlx::query("SELECT id, name, dialect, machine_json, created_at FROM controllers WHERE id = $1")
        .bind(id)
        .fetch_optional(db.reads())
        .await?;
    row.as_ref().map(ControllerRow::from_row).transpose()
}

// --- programs -----------------------------------------------------------------------------

/// The O-numbers and sizes of a controller's stored programs, ascending.
pub async fn list_programs(db: &Db, controller: &str) -> Result<Vec<(u32, usize)>, sqlx::Error> {
    let rows = sqlx::query(
        // Bytes, as the store's answer gives them (`length` counts characters).
        "SELECT number, CAST(octet_length(text) AS BIGINT) AS size FROM programs WHERE controller_id = $1 ORDER BY number",
    )
    .bind(controller)
    .fetch_all(db.reads())
    .await?;
    rows.iter().map(|r| Ok((r.try_get::<i64, _>("number")? as u32, r.try_get::<i64, _>("size")? as usize))).collect()
}

/// Every stored program of a controller, ascending: (number, text).
pub async fn programs(db: &Db, controller: &str) -> Result<Vec<(u32, String)>, sqlx::Error> {
    let rows = sqlx::query("SELECT number, text FROM programs WHERE controller_id = $1 ORDER BY number")
        .bind(controller)
        .fetch_all(db.reads())
        .await?;
    rows.iter().map(|r| Ok((r.try_get::<i64, _>("number")? as u32, r.try_get("text")?))).collect()
}

pub async fn program(db: &Db, controller: &str, number: u32) -> Result<Option<String>, sqlx::Error> {
    let row = sqlx::query("SELECT text FROM programs WHERE controller_id = $1 AND number = $2")
        .bind(controller)
        .bind(number as i64)
        .fetch_optional(db.reads())
        .await?;
    row.map(|r| r.try_get("text")).transpose()
}

/// Stores (or replaces) a program; true if it was new.
pub async fn put_program(db: &Db, controller: &str, number: u32, text: &str) -> Result<bool, sqlx::Error> {
    let mut tx = db.begin_write().await?;
    let existed = sqlx::query("SELECT 1 FROM programs WHERE controller_id = $1 AND number = $2")
        .bind(controller)
        .bind(number as i64)
        .fetch_optional(&mut *tx)
        .await?
        .is_some();
    sqlx::query(
        "INSERT INTO programs (controller_id, number, text) VALUES ($1, $2, $3) \
         ON CONFLICT (controller_id, number) DO UPDATE SET text = excluded.text",
    )
    .bind(controller)
    .bind(number as i64)
    .bind(text)
    .execute(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(!existed)
}

pub async fn delete_program(db: &Db, controller: &str, number: u32) -> Result<bool, sqlx::Error> {
    let done = sqlx::query("DELETE FROM programs WHERE controller_id = $1 AND number = $2")
        .bind(controller)
        .bind(number as i64)
        .execute(db.writes())
        .await?;
    Ok(done.rows_affected() > 0)
}

// --- retained variables ---------------------------------------------------------------------

/// A controller's retained variables (#500–#999, #500000–#999999, #3002, #3901/#3902): every
/// row with a value (a NULL row is vacant).
pub async fn retained_variables(db: &Db, controller: &str) -> Result<Vec<(u32, f64)>, sqlx::Error> {
    let rows = sqlx::query("SELECT number, value FROM variables WHERE controller_id = $1 AND value IS NOT NULL")
        .bind(controller)
        .fetch_all(db.reads())
        .await?;
    let mut values = Vec::with_capacity(rows.len());
    for r in rows {
        let number: i64 = r.try_get("number")?;
        if let Ok(number) = u32::try_from(number) {
            values.push((number, r.try_get("value")?));
        }
    }
    Ok(values)
}

/// Saves retained variables (`None`: vacant) in one transaction.
pub async fn save_variables(db: &Db, controller: &str, values: &[(u32, Option<f64>)]) -> Result<(), sqlx::Error> {
    let mut tx = db.begin_write().await?;
    variables_on(&mut tx, controller, values).await?;
    tx.commit().await
}

async fn variables_on(
    conn: &mut AnyConnection,
    controller: &str,
    values: &[(u32, Option<f64>)],
) -> Result<(), sqlx::Error> {
    for (number, value) in values {
        sqlx::query(
            "INSERT INTO variables (controller_id, number, value) VALUES ($1, $2, $3) \
             ON CONFLICT (controller_id, number) DO UPDATE SET value = excluded.value",
        )
        .bind(controller)
        .bind(*number as i64)
        .bind(*value)
        .execute(&mut *conn)
        .await?;
    }
    Ok(())
}

// --- history ------------------------------------------------------------------------------

/// One row of `alarm_history`.
#[derive(Debug, Clone, PartialEq)]
pub struct AlarmRow {
    pub raised_at: String,
    pub code: String,
    pub message: String,
    pub line: u32,
    pub n: Option<u32>,
    /// The O number of the program `line` is in (none: MDI, or a row from before it was kept).
    pub program: Option<u32>,
}

/// A controller's alarm history, newest first, at most `limit` rows.
pub async fn alarm_history(db: &Db, controller: &str, limit: u32) -> Result<Vec<AlarmRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT raised_at, code, message, line, n, program FROM alarm_history WHERE controller_id = $1 \
         ORDER BY id DESC LIMIT $2",
    )
    .bind(controller)
    .bind(limit as i64)
    .fetch_all(db.reads())
    .await?;
    rows.iter()
        .map(|r| {
            Ok(AlarmRow {
                raised_at: r.try_get("raised_at")?,
                code: r.try_get("code")?,
                message: r.try_get("message")?,
                line: r.try_get::<i64, _>("line")? as u32,
                n: r.try_get::<Option<i64>, _>("n")?.map(|n| n as u32),
                program: r.try_get::<Option<i64>, _>("program")?.map(|n| n as u32),
            })
        })
        .collect()
}

/// One row of `run_history`.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    pub program: Option<u32>,
    pub started_at: String,
    pub ended_at: String,
    pub cycle_time_s: f64,
    pub result: String,
}

/// A controller's run history, newest first, at most `limit` rows.
pub async fn run_history(db: &Db, controller: &str, limit: u32) -> Result<Vec<RunRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT program, started_at, ended_at, cycle_time_s, result FROM run_history \
         WHERE controller_id = $1 ORDER BY id DESC LIMIT $2",
    )
    .bind(controller)
    .bind(limit as i64)
    .fetch_all(db.reads())
    .await?;
    rows.iter()
        .map(|r| {
            Ok(RunRow {
                program: r.try_get::<Option<i64>, _>("program")?.map(|n| n as u32),
                started_at: r.try_get("started_at")?,
                ended_at: r.try_get("ended_at")?,
                cycle_time_s: r.try_get("cycle_time_s")?,
                result: r.try_get("result")?,
            })
        })
        .collect()
}

/// The most records the background writer puts in one transaction.
const RECORDS_PER_TRANSACTION: usize = 256;

/// What the database writer must keep, produced by the workers.
#[derive(Debug, Clone, PartialEq)]
pub enum Record {
    /// Retained variables (#500–#999) a program changed; `None` is vacant.
    Variables { controller: String, values: Vec<(u32, Option<f64>)> },
    /// Tool offsets a program changed (G10, #2001…).
    ToolOffsets { controller: String, rows: Vec<ToolRow> },
    /// Work offsets a program changed (G10 L2/L20, #5201…): (slot, value per axis).
    WorkOffsets { controller: String, rows: Vec<(usize, Vec<f64>)> },
    /// The counters of automatic operation changed (operating and cutting time, seconds).
    Times { controller: String, times: fivex_engine::controller::Times },
    /// The tilted working plane kept over a restart changed (Syntec Pr3014 = 2).
    TiltedPlane { controller: String, plane: Option<fivex_engine::interp::TiltedPlane> },
    /// An alarm was raised (the row as `alarm_history` keeps it).
    Alarm { controller: String, alarm: AlarmRow },
    /// A program run ended (`completed`, `alarm` or `reset`).
    Run {
        controller: String,
        program: Option<u32>,
        started_at: String,
        ended_at: String,
        cycle_time_s: f64,
        result: &'static str,
    },
}

/// Writes what the workers produce ([`Record`]) until every sender is gone: what
/// has arrived, up to [`RECORDS_PER_TRANSACTION`], in one write transaction, so a busy fleet
/// holds the writer for few commits. A failed record is logged and the others are kept (a
/// deleted controller's late records fail on the foreign key, harmlessly; only the failed
/// record is undone).
pub async fn write_records(db: Db, mut records: tokio::sync::mpsc::UnboundedReceiver<Record>) {
    let mut batch = Vec::with_capacity(RECORDS_PER_TRANSACTION);
    while records.recv_many(&mut batch, RECORDS_PER_TRANSACTION).await > 0 {
        if let Err(e) = write_batch(&db, &batch).await {
            db.failed_records.fetch_add(1, Ordering::Relaxed);
            tracing::warn!(error = %e, records = batch.len(), "cannot store the workers' records");
        }
        db.records_done.send_modify(|done| *done += batch.len() as u64);
        batch.clear();
    }
}

async fn write_batch(db: &Db, batch: &[Record]) -> Result<(), sqlx::Error> {
    let mut tx = db.begin_write().await?;
    for record in batch {
        // PostgreSQL aborts the whole transaction at a failed statement: there each record
        // goes in a savepoint of its own, so a failed one is undone alone, as on SQLite.
        let stored = match db.backend {
            Backend::Sqlite => record_on(&mut tx, record).await,
            Backend::Postgres => {
                let mut savepoint = sqlx::Connection::begin(&mut *tx).await?;
                match record_on(&mut savepoint, record).await {
                    Ok(()) => savepoint.commit().await,
                    Err(e) => savepoint.rollback().await.and(Err(e)),
                }
            }
        };
        if let Err(e) = stored {
            db.failed_records.fetch_add(1, Ordering::Relaxed);
            tracing::warn!(error = %e, ?record, "cannot store a record");
        }
    }
    tx.commit().await
}

async fn record_on(conn: &mut AnyConnection, record: &Record) -> Result<(), sqlx::Error> {
    match record {
        Record::Variables { controller, values } => variables_on(conn, controller, values).await,
        Record::ToolOffsets { controller, rows } => tool_offsets_on(conn, controller, rows).await,
        Record::TiltedPlane { controller, plane } => kept_plane_on(conn, controller, plane.as_ref()).await,
        Record::Times { controller, times } => {
            sqlx::query("UPDATE controllers SET operating_time_s = $1, cutting_time_s = $2 WHERE id = $3")
                .bind(times.operating_s)
                .bind(times.cutting_s)
                .bind(controller)
                .execute(conn)
                .await
                .map(|_| ())
        }
        Record::WorkOffsets { controller, rows } => work_offsets_on(conn, controller, rows).await,
        Record::Alarm { controller, alarm } => sqlx::query(
            "INSERT INTO alarm_history (controller_id, raised_at, code, message, line, n, program) \
             VALUES ($1, $2, $3, $4, $5, $6, $7)",
        )
        .bind(controller)
        .bind(&alarm.raised_at)
        .bind(&alarm.code)
        .bind(&alarm.message)
        .bind(alarm.line as i64)
        .bind(alarm.n.map(|n| n as i64))
        .bind(alarm.program.map(|n| n as i64))
        .execute(conn)
        .await
        .map(|_| ()),
        Record::Run { controller, program, started_at, ended_at, cycle_time_s, result } => sqlx::query(
            "INSERT INTO run_history (controller_id, program, started_at, ended_at, cycle_time_s, result) \
             VALUES ($1, $2, $3, $4, $5, $6)",
        )
        .bind(controller)
        .bind(program.map(|n| n as i64))
        .bind(started_at)
        .bind(ended_at)
        .bind(cycle_time_s)
        .bind(*result)
        .execute(conn)
        .await
        .map(|_| ()),
    }
}

// --- offsets --------------------------------------------------------------------------------

/// One tool offset number's values: H and D geometry and wear, and the corner radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolRow {
    pub number: u32,
    pub length: f64,
    pub length_wear: f64,
    pub radius: f64,
    pub radius_wear: f64,
    /// The tool's corner radius (migration 0006; 0 in the rows stored before it).
    pub corner_radius: f64,
}

pub async fn tool_offsets(db: &Db, controller: &str) -> Result<Vec<ToolRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT number, length, length_wear, radius, radius_wear, corner_radius FROM tool_offsets \
         WHERE controller_id = $1 ORDER BY number",
    )
    .bind(controller)
    .fetch_all(db.reads())
    .await?;
    rows.iter()
        .map(|r| {
            Ok(ToolRow {
                number: r.try_get::<i64, _>("number")? as u32,
                length: r.try_get("length")?,
                length_wear: r.try_get("length_wear")?,
                radius: r.try_get("radius")?,
                radius_wear: r.try_get("radius_wear")?,
                corner_radius: r.try_get("corner_radius")?,
            })
        })
        .collect()
}

/// Saves tool offsets in one transaction.
pub async fn save_tool_offsets(db: &Db, controller: &str, rows: &[ToolRow]) -> Result<(), sqlx::Error> {
    let mut tx = db.begin_write().await?;
    tool_offsets_on(&mut tx, controller, rows).await?;
    tx.commit().await
}

async fn tool_offsets_on(conn: &mut AnyConnection, controller: &str, rows: &[ToolRow]) -> Result<(), sqlx::Error> {
    for t in rows {
        sqlx::query(
            "INSERT INTO tool_offsets (controller_id, number, length, length_wear, radius, radius_wear, corner_radius) \
             VALUES ($1, $2, $3, $4, $5, $6, $7) ON CONFLICT (controller_id, number) DO UPDATE SET \
             length = excluded.length, length_wear = excluded.length_wear, radius = excluded.radius, \
             radius_wear = excluded.radius_wear, corner_radius = excluded.corner_radius",
        )
        .bind(controller)
        .bind(t.number as i64)
        .bind(t.length)
        .bind(t.length_wear)
        .bind(t.radius)
        .bind(t.radius_wear)
        .bind(t.corner_radius)
        .execute(&mut *conn)
        .await?;
    }
    Ok(())
}

/// A controller's stored work offsets: (slot, value per axis).
pub async fn work_offsets(db: &Db, controller: &str) -> Result<Vec<(usize, Vec<f64>)>, sqlx::Error> {
    let rows = sqlx::query("SELECT slot, axes FROM work_offsets WHERE controller_id = $1 ORDER BY slot")
        .bind(controller)
        .fetch_all(db.reads())
        .await?;
    let mut out = Vec::new();
    for r in rows {
        let slot = r.try_get::<i64, _>("slot")? as usize;
        let axes: String = r.try_get("axes")?;
        match serde_json::from_str::<Vec<f64>>(&axes) {
            Ok(v) => out.push((slot, v)),
            Err(e) => tracing::warn!(controller, slot, error = %e, "a stored work offset is not a list of numbers"),
        }
    }
    Ok(out)
}

async fn work_offsets_on(
    conn: &mut AnyConnection,
    controller: &str,
    rows: &[(usize, Vec<f64>)],
) -> Result<(), sqlx::Error> {
    for (slot, axes) in rows {
        let axes = serde_json::to_string(axes).unwrap_or_else(|_| "[]".into());
        sqlx::query(
            "INSERT INTO work_offsets (controller_id, slot, axes) VALUES ($1, $2, $3) \
             ON CONFLICT (controller_id, slot) DO UPDATE SET axes = excluded.axes",
        )
        .bind(controller)
        .bind(*slot as i64)
        .bind(axes)
        .execute(&mut *conn)
        .await?;
    }
    Ok(())
}

/// Replaces a controller's machine document and the parameters its model does not read.
pub async fn update_machine(db: &Db, id: &str, machine_json: &str, extra_json: &str) -> Result<(), sqlx::Error> {
    sqlx::query("UPDATE controllers SET machine_json = $1, extra_parameters = $2 WHERE id = $3")
        .bind(machine_json)
        .bind(extra_json)
        .bind(id)
        .execute(db.writes())
        .await?;
    Ok(())
}

/// The tilted working plane a controller keeps over a restart (JSON), if any.
pub async fn kept_plane(db: &Db, id: &str) -> Result<Option<String>, sqlx::Error> {
    let row =
        sqlx::query("SELECT kept_plane FROM controllers WHERE id = $1").bind(id).fetch_optional(db.reads()).await?;
    Ok(row.and_then(|r| r.try_get::<Option<String>, _>("kept_plane").ok().flatten()))
}

/// The counters of automatic operation a controller kept (0 for a controller that never ran).
pub async fn operation_times(db: &Db, id: &str) -> Result<fivex_engine::controller::Times, sqlx::Error> {
    let row = sqlx::query("SELECT operating_time_s, cutting_time_s FROM controllers WHERE id = $1")
        .bind(id)
        .fetch_optional(db.reads())
        .await?;
    Ok(row.map_or_else(Default::default, |r| fivex_engine::controller::Times {
        operating_s: r.try_get("operating_time_s").unwrap_or(0.0),
        cutting_s: r.try_get("cutting_time_s").unwrap_or(0.0),
    }))
}

/// What is on a controller's table (the engine's workpiece JSON), if anything was stored.
pub async fn workpiece(db: &Db, id: &str) -> Result<Option<String>, sqlx::Error> {
    let row =
        sqlx::query("SELECT workpiece FROM controllers WHERE id = $1").bind(id).fetch_optional(db.reads()).await?;
    Ok(row.and_then(|r| r.try_get::<Option<String>, _>("workpiece").ok().flatten()))
}

/// Stores what is on a controller's table (the engine's workpiece JSON); false if there is no
/// controller `id`.
pub async fn save_workpiece(db: &Db, id: &str, json: &str) -> Result<bool, sqlx::Error> {
    let done = sqlx::query("UPDATE controllers SET workpiece = $1 WHERE id = $2")
        .bind(json)
        .bind(id)
        .execute(db.writes())
        .await?;
    Ok(done.rows_affected() > 0)
}

/// Stores (or, `None`, clears) the tilted working plane a controller keeps over a restart.
pub async fn save_kept_plane(
    db: &Db,
    id: &str,
    plane: Option<&fivex_engine::interp::TiltedPlane>,
) -> Result<(), sqlx::Error> {
    kept_plane_on(&mut *db.writes().acquire().await?, id, plane).await
}

async fn kept_plane_on(
    conn: &mut AnyConnection,
    id: &str,
    plane: Option<&fivex_engine::interp::TiltedPlane>,
) -> Result<(), sqlx::Error> {
    let json = plane.and_then(|p| serde_json::to_string(p).ok());
    sqlx::query("UPDATE controllers SET kept_plane = $1 WHERE id = $2").bind(json).bind(id).execute(conn).await?;
    Ok(())
}

/// One row of `fleet_runs` (the program, request and results as stored JSON text).
#[derive(Debug, Clone, PartialEq)]
pub struct FleetRunRow {
    pub id: String,
    pub created_at: String,
    pub finished_at: Option<String>,
    /// `queued`, `running`, `done`, `cancelled` or `interrupted`.
    pub status: String,
    pub machines: u32,
    pub completed: u32,
    pub alarms: u32,
    pub program: String,
    pub request_json: String,
    pub results_json: Option<String>,
}

/// A fleet run that was asked for (`queued`, or `running` at once).
pub async fn insert_fleet_run(db: &Db, row: &FleetRunRow) -> Result<(), sqlx::Error> {
    sqlx::query(
        "INSERT INTO fleet_runs (id, created_at, status, machines, program, request_json) VALUES ($1, $2, $3, $4, $5, $6)",
    )
    .bind(&row.id)
    .bind(&row.created_at)
    .bind(&row.status)
    .bind(row.machines as i64)
    .bind(&row.program)
    .bind(&row.request_json)
    .execute(db.writes())
    .await?;
    Ok(())
}

/// A queued fleet run that starts running.
pub async fn start_fleet_run(db: &Db, id: &str) -> Result<(), sqlx::Error> {
    sqlx::query("UPDATE fleet_runs SET status = 'running' WHERE id = $1").bind(id).execute(db.writes()).await?;
    Ok(())
}

/// A fleet run that is over (`status`: `done`, `cancelled` or `interrupted`), with its results
/// (`null` for a machine that did not finish); its results recorded one by one
/// ([`record_fleet_result`]) leave. Only a run still `queued` or `running` is changed (of two
/// nodes collecting the same run, one cut off meanwhile, the first to end it is kept):
/// whether it was.
pub async fn finish_fleet_run(
    db: &Db,
    id: &str,
    status: &str,
    finished_at: &str,
    completed: u32,
    alarms: u32,
    results_json: &str,
) -> Result<bool, sqlx::Error> {
    let mut tx = db.begin_write().await?;
    let changed = sqlx::query(
        "UPDATE fleet_runs SET status = $1, finished_at = $2, completed = $3, alarms = $4, results_json = $5 \
         WHERE id = $6 AND status IN ('queued', 'running')",
    )
    .bind(status)
    .bind(finished_at)
    .bind(completed as i64)
    .bind(alarms as i64)
    .bind(results_json)
    .bind(id)
    .execute(&mut *tx)
    .await?
    .rows_affected()
        == 1;
    sqlx::query("DELETE FROM fleet_run_results WHERE run_id = $1").bind(id).execute(&mut *tx).await?;
    tx.commit().await?;
    Ok(changed)
}

/// Machine `index`'s result of fleet run `id` under way (over NATS), as its collecting node hears
/// it, and the run's `completed` or `alarms` one more. Idempotent: a result recorded already (a
/// node taking the run over reads the results again), or one of a run that is over, changes
/// nothing (`false`).
pub async fn record_fleet_result(
    db: &Db,
    id: &str,
    index: usize,
    result_json: &str,
    completed: bool,
) -> Result<bool, sqlx::Error> {
    let counter = if completed {
        "UPDATE fleet_runs SET completed = completed + 1 WHERE id = $1 AND status IN ('queued', 'running')"
    } else {
        "UPDATE fleet_runs SET alarms = alarms + 1 WHERE id = $1 AND status IN ('queued', 'running')"
    };
    let mut tx = db.begin_write().await?;
    // The run's row first: on PostgreSQL its lock orders this with the run's end and with another
    // node recording the same result (which then finds it there and takes its count back).
    if sqlx::query(counter).bind(id).execute(&mut *tx).await?.rows_affected() != 1 {
        return Ok(false);
    }
    let recorded = sqlx::query(
        "INSERT INTO fleet_run_results (run_id, idx, result_json) VALUES ($1, $2, $3) \
         ON CONFLICT (run_id, idx) DO NOTHING",
    )
    .bind(id)
    .bind(index as i64)
    .bind(result_json)
    .execute(&mut *tx)
    .await?
    .rows_affected()
        == 1;
    if recorded {
        tx.commit().await?;
    } else {
        tx.rollback().await?;
    }
    Ok(recorded)
}

/// The results recorded so far of fleet run `id` under way, by machine index.
pub async fn fleet_run_results(db: &Db, id: &str) -> Result<Vec<(usize, String)>, sqlx::Error> {
    let rows = sqlx::query("SELECT idx, result_json FROM fleet_run_results WHERE run_id = $1 ORDER BY idx")
        .bind(id)
        .fetch_all(db.reads())
        .await?;
    rows.iter().map(|r| Ok((r.try_get::<i64, _>("idx")? as usize, r.try_get("result_json")?))).collect()
}

/// The ids of the fleet runs `queued` or `running`.
pub async fn unfinished_fleet_runs(db: &Db) -> Result<Vec<String>, sqlx::Error> {
    let rows = sqlx::query("SELECT id FROM fleet_runs WHERE status IN ('queued', 'running') ORDER BY rowid")
        .fetch_all(db.reads())
        .await?;
    rows.iter().map(|r| r.try_get("id")).collect()
}

fn fleet_run_row(r: &AnyRow, full: bool) -> Result<FleetRunRow, sqlx::Error> {
    Ok(FleetRunRow {
        id: r.try_get("id")?,
        created_at: r.try_get("created_at")?,
        finished_at: r.try_get("finished_at")?,
        status: r.try_get("status")?,
        machines: r.try_get::<i64, _>("machines")? as u32,
        completed: r.try_get::<i64, _>("completed")? as u32,
        alarms: r.try_get::<i64, _>("alarms")? as u32,
        program: if full { r.try_get("program")? } else { String::new() },
        request_json: if full { r.try_get("request_json")? } else { String::new() },
        results_json: if full { r.try_get("results_json")? } else { None },
    })
}

/// Fleet runs, newest first, at most `limit` (without program, request and results).
pub async fn fleet_runs(db: &Db, limit: u32) -> Result<Vec<FleetRunRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT id, created_at, finished_at, status, machines, completed, alarms FROM fleet_runs \
         ORDER BY rowid DESC LIMIT $1",
    )
    .bind(limit as i64)
    .fetch_all(db.reads())
    .await?;
    rows.iter().map(|r| fleet_run_row(r, false)).collect()
}

/// One fleet run with everything stored.
pub async fn fleet_run(db: &Db, id: &str) -> Result<Option<FleetRunRow>, sqlx::Error> {
    let row = sqlx::query("SELECT * FROM fleet_runs WHERE id = $1").bind(id).fetch_optional(db.reads()).await?;
    row.as_ref().map(|r| fleet_run_row(r, true)).transpose()
}
