//! SQLite persistence: opening (and creating) the database, running the migrations in
//! `migrations/`, and the queries the HTTP layer needs.
//!
//! Queries are runtime queries (`sqlx::query`), not the compile-time checked macros, so building
//! the crate never needs a database. The migrations are embedded into the binary with
//! `sqlx::migrate!`, so a fresh file is migrated on start with no extra files at run time.

use std::path::Path;
use std::time::Duration;

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions};
use sqlx::sqlite::{SqliteRow, SqliteSynchronous};
use sqlx::Row;

/// The migrations embedded from the workspace's `migrations/` directory.
pub static MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("../migrations");

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
}

/// Opens the SQLite database at `path`, creating the file if it is missing, and brings its schema
/// up to date. Foreign keys are enforced (deleting a controller deletes its programs and
/// variables) and the journal is in WAL mode so readers do not block the writer.
pub async fn open(path: &Path) -> Result<SqlitePool, OpenError> {
    let shown = path.display().to_string();
    let options = SqliteConnectOptions::new()
        .filename(path)
        .create_if_missing(true)
        .foreign_keys(true)
        .journal_mode(SqliteJournalMode::Wal)
        .synchronous(SqliteSynchronous::Normal)
        .busy_timeout(Duration::from_secs(5));
    let pool = SqlitePoolOptions::new()
        .max_connections(4)
        .connect_with(options)
        .await
        .map_err(|source| OpenError::Connect { path: shown.clone(), source })?;
    MIGRATOR.run(&pool).await.map_err(|source| OpenError::Migrate { path: shown, source })?;
    Ok(pool)
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
    fn from_row(row: &SqliteRow) -> Result<Self, sqlx::Error> {
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
pub async fn list_controllers(pool: &SqlitePool) -> Result<Vec<ControllerRow>, sqlx::Error> {
    let rows = sqlx::query(
        "SELECT id, name, dialect, machine_json, created_at FROM controllers \
         ORDER BY created_at, id",
    )
    .fetch_all(pool)
    .await?;
    rows.iter().map(ControllerRow::from_row).collect()
}

/// Inserts a controller row. The controllers API (a later issue) builds on this; tests use it
/// to check the list endpoint against real rows.
pub async fn insert_controller(pool: &SqlitePool, row: &ControllerRow) -> Result<(), sqlx::Error> {
    sqlx::query(
        "INSERT INTO controllers (id, name, dialect, machine_json, created_at) \
         VALUES (?, ?, ?, ?, ?)",
    )
    .bind(&row.id)
    .bind(&row.name)
    .bind(&row.dialect)
    .bind(&row.machine_json)
    .bind(&row.created_at)
    .execute(pool)
    .await?;
    Ok(())
}
