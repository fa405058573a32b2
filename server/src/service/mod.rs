//! What the service does, apart from HTTP: functions over domain types and the database
//! (`db.rs`, the only place with SQL), returning domain results or a [`ServiceError`] that the
//! HTTP layer (`http::error`) maps to a status. Nothing here knows axum or HTTP.

pub mod controllers;
pub mod fleet_rescue;
pub mod fleet_runs;
pub mod history;
pub mod panel;
pub mod parameters;
pub mod programs;
pub mod settings;
pub mod workpiece;

/// Why the service did not do what it was asked; `http::error` gives each its status.
#[derive(Debug, thiserror::Error)]
pub enum ServiceError {
    /// What was named does not exist.
    #[error("{0}")]
    NotFound(String),
    /// The request is understood but its content is not acceptable; `details` (the
    /// diagnostics of a program) say more.
    #[error("{0}")]
    Invalid(String, Option<serde_json::Value>),
    /// Not now, or not in this state (a program runs, a run is over).
    #[error("{0}")]
    Conflict(String),
    /// The service cannot do it at all now (it is stopping).
    #[error("{0}")]
    Unavailable(String),
    #[error("internal database error")]
    Database(#[from] sqlx::Error),
}

impl ServiceError {
    /// Not acceptable, with nothing more to say than `why`.
    pub fn invalid(why: impl Into<String>) -> ServiceError {
        ServiceError::Invalid(why.into(), None)
    }
}
