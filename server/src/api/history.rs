//! Alarms (active and history) and the run history of a controller.

use crate::http::extract::Addressed;
use axum::extract::rejection::QueryRejection;
use axum::extract::{Json, Query, State};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::host::stream::AlarmInfo;
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::history;

/// How many history rows an answer holds at most by default, and at all.
const DEFAULT_LIMIT: u32 = 100;
const MAX_LIMIT: u32 = 10_000;

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct Limit {
    /// At most this many rows, newest first (default 100, at most 10000).
    #[param(value_type = Option<u64>, maximum = 4294967295_u64)]
    pub limit: Option<u32>,
}

fn limit(q: Result<Query<Limit>, QueryRejection>) -> Result<u32, ApiError> {
    let q = q.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
    Ok(q.limit.unwrap_or(DEFAULT_LIMIT).min(MAX_LIMIT))
}

/// An alarm that was raised, with when.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct PastAlarm {
    /// RFC 3339 UTC.
    pub raised_at: String,
    #[serde(flatten)]
    pub alarm: AlarmInfo,
}

/// `GET /alarms`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Alarms {
    /// In force now.
    pub active: Vec<AlarmInfo>,
    /// Raised before, newest first.
    pub history: Vec<PastAlarm>,
}

/// A finished program run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Run {
    /// O number (null for MDI).
    pub program: Option<u32>,
    pub started_at: String,
    pub ended_at: String,
    /// Simulated seconds.
    pub cycle_time_s: f64,
    /// `completed`, `alarm`, `reset` or `interrupted` (the service stopped while it ran).
    #[schema(value_type = crate::wire::words::RunEnd)]
    pub result: String,
}

/// Active alarms and the alarm history.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/alarms",
    tag = "history",
    params(("id" = String, Path, description = "Controller id"), Limit),
    responses(
        (status = 200, description = "Alarms", body = Alarms),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn alarms(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    q: Result<Query<Limit>, QueryRejection>,
) -> Result<Json<Alarms>, ApiError> {
    let limit = limit(q)?;
    let active = {
        let station = hosted.station();
        station.layouts.alarms(station.controller.alarms())
    };
    let history = history::alarms(&state.db, &hosted, limit)
        .await?
        .into_iter()
        .map(|r| PastAlarm {
            raised_at: r.raised_at,
            alarm: AlarmInfo { code: r.code, message: r.message, line: r.line, n: r.n, program: r.program },
        })
        .collect();
    Ok(Json(Alarms { active, history }))
}

/// Finished program runs, newest first.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/runs",
    tag = "history",
    params(("id" = String, Path, description = "Controller id"), Limit),
    responses(
        (status = 200, description = "Runs", body = [Run]),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn runs(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    q: Result<Query<Limit>, QueryRejection>,
) -> Result<Json<Vec<Run>>, ApiError> {
    let limit = limit(q)?;
    let rows = history::runs(&state.db, &hosted, limit).await?;
    Ok(Json(
        rows.into_iter()
            .map(|r| Run {
                program: r.program,
                started_at: r.started_at,
                ended_at: r.ended_at,
                cycle_time_s: r.cycle_time_s,
                result: r.result,
            })
            .collect(),
    ))
}
