//! `GET /healthz` (liveness: the service and its database answer) and `GET /readyz` (this node
//! can take work).

use axum::extract::State;
use axum::Json;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::ToSchema;

use crate::http::{ApiError, AppState, ErrorBody};

/// `GET /healthz` body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Health {
    /// Always `"ok"` when the service answers 200.
    #[schema(example = "ok")]
    pub status: String,
}

/// Liveness and readiness: 200 when the service is up and its database answers.
#[utoipa::path(
    get,
    path = "/healthz",
    tag = "service",
    responses(
        (status = 200, description = "The service is up", body = Health),
        (status = 503, description = "The database does not answer", body = ErrorBody),
    )
)]
pub async fn healthz(State(state): State<AppState>) -> Result<Json<Health>, ApiError> {
    state.db.ping().await.map_err(|e| {
        tracing::warn!(error = %e, "health check: database does not answer");
        ApiError::Unavailable("database does not answer".into())
    })?;
    Ok(Json(Health { status: "ok".into() }))
}

/// `GET /readyz` body: this node can take work. The shape is meant to grow without breaking a
/// client: fields are only ever added.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Readiness {
    /// Always `"ready"` when the service answers 200.
    #[schema(example = "ready")]
    pub status: String,
    /// This process.
    pub node: NodeReadiness,
    /// The cluster of controller hosts this node belongs to (`fivex serve --nats` with a
    /// PostgreSQL database, docs/cluster.md): `node` (this node's name), `members` (the nodes
    /// seen alive at the last beat) and `controllers` (the ids hosted here). `null` for a single
    /// node.
    #[schema(value_type = Option<std::collections::HashMap<String, serde_json::Value>>, required = true)]
    pub cluster: Option<Map<String, Value>>,
}

/// One node in `/readyz`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct NodeReadiness {
    /// Made when the process starts: a new one after every restart.
    pub id: String,
    /// When the process started, RFC 3339 UTC.
    #[schema(example = "2025-01-01T00:00:00.000Z")]
    pub started_at: String,
    /// The fivex version.
    #[schema(example = "0.1.0")]
    pub version: String,
    /// `sqlite` or `postgres`.
    #[schema(example = "sqlite")]
    pub database: String,
    /// Worker threads running (all of those started, when ready).
    pub workers: usize,
    /// Controllers hosted.
    pub controllers: usize,
}

/// Readiness: 200 when this node can take work — its database answers, every worker thread
/// runs and it is not shutting down; 503 with the reasons otherwise.
#[utoipa::path(
    get,
    path = "/readyz",
    tag = "service",
    responses(
        (status = 200, description = "The node can take work", body = Readiness),
        (status = 503, description = "Not ready: the database does not answer, a worker thread stopped, or the service is shutting down (the reasons in `error`)", body = ErrorBody),
    )
)]
pub async fn readyz(State(state): State<AppState>) -> Result<Json<Readiness>, ApiError> {
    let mut not = Vec::new();
    if state.is_closing() {
        not.push("the service is shutting down".to_string());
    }
    if let Err(e) = state.db.ping().await {
        tracing::warn!(error = %e, "readiness check: database does not answer");
        not.push("the database does not answer".into());
    }
    let (workers, running) = (state.host.workers(), state.host.workers_running());
    if running < workers {
        not.push(format!("{} of {workers} worker threads stopped", workers - running));
    }
    if !not.is_empty() {
        return Err(ApiError::Unavailable(format!("not ready: {}", not.join("; "))));
    }
    Ok(Json(Readiness {
        status: "ready".into(),
        node: NodeReadiness {
            id: state.node.id.clone(),
            started_at: state.node.started_at.clone(),
            version: env!("CARGO_PKG_VERSION").into(),
            database: state.db.backend().name().into(),
            workers: running,
            controllers: state.host.len(),
        },
        cluster: state.cluster.as_ref().map(|c| {
            let mut cluster = Map::new();
            cluster.insert("node".into(), Value::from(c.name()));
            cluster.insert("members".into(), Value::from(c.members()));
            let hosted: Vec<Value> = state.host.list().iter().map(|h| Value::from(h.id.clone())).collect();
            cluster.insert("controllers".into(), Value::from(hosted));
            let view = if c.view_current() { "current" } else { "building" };
            cluster.insert("placement_view".into(), Value::from(view));
            cluster
        }),
    }))
}
