//! `GET /metrics`: the service's metrics in the Prometheus text format (`crate::metrics`,
//! docs/api.md, "Metrics").

use axum::extract::State;
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};

use crate::http::{ApiError, AppState};
use crate::metrics::{Now, CONTENT_TYPE};

/// The service's metrics for Prometheus: controllers by run state and how far they trail real
/// time, stream subscribers and position frames, fleet runs and jobs, requests by status class,
/// database errors.
#[utoipa::path(
    get,
    path = "/metrics",
    tag = "service",
    responses(
        (status = 200, description = "The Prometheus text exposition format 0.0.4 (docs/api.md, \"Metrics\")", body = String, content_type = "text/plain; version=0.0.4; charset=utf-8"),
    )
)]
pub async fn metrics(State(state): State<AppState>) -> Result<Response, ApiError> {
    let mut now = Now::read(&state.host, &state.fleet_runs, state.db.failed_records());
    if let Some(cluster) = &state.cluster {
        let relays = cluster.relays().census();
        (now.relay_subscriptions, now.relay_clients, now.relay_publishers) =
            (relays.subscriptions, relays.clients, relays.publishers);
    }
    let text = state.metrics.render(&now).map_err(|e| {
        tracing::error!(error = %e, "metrics not encoded");
        ApiError::Rejected(StatusCode::INTERNAL_SERVER_ERROR, "metrics not encoded".into())
    })?;
    Ok(([(header::CONTENT_TYPE, CONTENT_TYPE)], text).into_response())
}
