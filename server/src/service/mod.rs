//! What the service does, apart from HTTP: functions over domain types and the database
//! (`db.rs`, the only place with SQL), returning domain results or a [`ServiceError`] that the
//! HTTP layer (`http::error`) maps to a status. Nothing here knows axum or HTTP.

pub mod controllers;
