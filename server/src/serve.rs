//! `fivex serve`: the HTTP service.
//!
//! The shape follows axum's own examples: [`app`] builds the whole [`Router`] from an
//! [`AppState`] and knows nothing about sockets, so tests drive it with `oneshot`; [`serve`] runs
//! that router on a bound listener until a shutdown future resolves; [`run_blocking`] is what the
//! CLI calls (runtime, database, listener, signals, logging).
//!
//! Every error a handler returns is an [`ApiError`], which renders as a JSON `{"error": "…"}` body
//! with a 4xx/5xx status; unknown routes and methods give the same JSON shape.

use std::future::Future;
use std::path::Path;
use std::time::{Duration, Instant};

use axum::extract::{Request, State};
use axum::http::{Method, StatusCode, Uri};
use axum::middleware::{self, Next};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use serde::{Deserialize, Serialize};
use sqlx::SqlitePool;
use tokio::net::TcpListener;
use utoipa::{OpenApi, ToSchema};
use utoipa_swagger_ui::SwaggerUi;

use crate::db;

/// The dashboard page served at `/` (`web/index.html`, embedded at compile time).
pub const INDEX_HTML: &str = include_str!("../../web/index.html");

/// Where the OpenAPI document is served.
pub const OPENAPI_PATH: &str = "/api-docs/openapi.json";

/// Prefix of the versioned REST API.
pub const API_PREFIX: &str = "/api/v1";

/// How long in-flight requests may take to finish after a shutdown signal before the server
/// stops anyway.
pub const SHUTDOWN_GRACE: Duration = Duration::from_secs(10);

/// Everything a handler can reach. Cheap to clone (the pool is a handle over shared state).
#[derive(Clone, Debug)]
pub struct AppState {
    pub db: SqlitePool,
}

impl AppState {
    /// State over an already opened and migrated pool.
    pub fn new(db: SqlitePool) -> Self {
        Self { db }
    }

    /// Opens (creating if missing) and migrates the SQLite database at `path`.
    pub async fn open(path: &Path) -> Result<Self, db::OpenError> {
        Ok(Self::new(db::open(path).await?))
    }
}

// ---------------------------------------------------------------------------------------------
// Errors

/// The one error type of the HTTP layer. Its [`IntoResponse`] gives the status and a JSON
/// [`ErrorBody`]; server-side causes are logged, not sent to the client.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    #[error("{0}")]
    BadRequest(String),
    #[error("{0}")]
    NotFound(String),
    #[error("method {method} is not allowed on {path}")]
    MethodNotAllowed { method: Method, path: String },
    #[error("{0}")]
    Conflict(String),
    #[error("service unavailable: {0}")]
    Unavailable(String),
    #[error("internal database error")]
    Database(#[from] sqlx::Error),
}

impl ApiError {
    pub fn status(&self) -> StatusCode {
        match self {
            ApiError::BadRequest(_) => StatusCode::BAD_REQUEST,
            ApiError::NotFound(_) => StatusCode::NOT_FOUND,
            ApiError::MethodNotAllowed { .. } => StatusCode::METHOD_NOT_ALLOWED,
            ApiError::Conflict(_) => StatusCode::CONFLICT,
            ApiError::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            ApiError::Database(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status();
        if let ApiError::Database(source) = &self {
            tracing::error!(error = %source, "database error");
        }
        let body = ErrorBody { error: self.to_string() };
        (status, Json(body)).into_response()
    }
}

/// The body of every 4xx/5xx response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ErrorBody {
    /// What went wrong, for a person to read.
    #[schema(example = "no route for GET /api/v1/nope")]
    pub error: String,
}

// ---------------------------------------------------------------------------------------------
// DTOs

/// `GET /healthz` body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Health {
    /// Always `"ok"` when the service answers 200.
    #[schema(example = "ok")]
    pub status: String,
}

/// One controller in a list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ControllerSummary {
    /// Stable identifier used in `/api/v1/controllers/{id}/…` paths.
    pub id: String,
    /// Display name given at creation.
    pub name: String,
    /// `fanuc` or `syntec`.
    #[schema(example = "fanuc")]
    pub dialect: String,
    /// Creation time, RFC 3339 UTC.
    #[schema(example = "2025-01-01T00:00:00Z")]
    pub created_at: String,
}

impl From<db::ControllerRow> for ControllerSummary {
    fn from(row: db::ControllerRow) -> Self {
        Self { id: row.id, name: row.name, dialect: row.dialect, created_at: row.created_at }
    }
}

// ---------------------------------------------------------------------------------------------
// Handlers

/// The dashboard.
async fn index() -> Html<&'static str> {
    Html(INDEX_HTML)
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
async fn healthz(State(state): State<AppState>) -> Result<Json<Health>, ApiError> {
    sqlx::query("SELECT 1").execute(&state.db).await.map_err(|e| {
        tracing::warn!(error = %e, "health check: database does not answer");
        ApiError::Unavailable("database does not answer".into())
    })?;
    Ok(Json(Health { status: "ok".into() }))
}

/// Lists the controllers, oldest first.
#[utoipa::path(
    get,
    path = "/api/v1/controllers",
    tag = "controllers",
    responses(
        (status = 200, description = "Every controller", body = [ControllerSummary]),
        (status = 500, description = "Database error", body = ErrorBody),
    )
)]
async fn list_controllers(State(state): State<AppState>) -> Result<Json<Vec<ControllerSummary>>, ApiError> {
    let rows = db::list_controllers(&state.db).await?;
    Ok(Json(rows.into_iter().map(Into::into).collect()))
}

async fn not_found(method: Method, uri: Uri) -> ApiError {
    ApiError::NotFound(format!("no route for {method} {}", uri.path()))
}

async fn method_not_allowed(method: Method, uri: Uri) -> ApiError {
    ApiError::MethodNotAllowed { method, path: uri.path().to_owned() }
}

/// One log line per request: method, path, status, latency.
async fn log_request(req: Request, next: Next) -> Response {
    let method = req.method().clone();
    let path = req.uri().path().to_owned();
    let start = Instant::now();
    let response = next.run(req).await;
    let status = response.status().as_u16();
    let micros = start.elapsed().as_micros() as u64;
    if status >= 500 {
        tracing::warn!(%method, %path, status, micros, "request");
    } else {
        tracing::info!(%method, %path, status, micros, "request");
    }
    response
}

// ---------------------------------------------------------------------------------------------
// OpenAPI

/// The OpenAPI 3.1 description of the service, generated from the handlers above.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "fivex",
        description = "A service hosting virtual 5-axis CNC controllers (FANUC 30i-A5 and Syntec \
                       dialects). Errors are JSON `{\"error\": \"…\"}` bodies with a 4xx/5xx status."
    ),
    paths(healthz, list_controllers),
    components(schemas(Health, ControllerSummary, ErrorBody)),
    tags(
        (name = "service", description = "Service health and documentation"),
        (name = "controllers", description = "Virtual CNC controllers"),
    )
)]
pub struct ApiDoc;

/// The OpenAPI document as a value.
pub fn openapi() -> utoipa::openapi::OpenApi {
    ApiDoc::openapi()
}

/// The OpenAPI document exactly as checked in at `openapi/openapi.json`: pretty-printed JSON
/// with a trailing newline.
pub fn openapi_json() -> String {
    let mut text = openapi().to_pretty_json().expect("the OpenAPI document serializes");
    text.push('\n');
    text
}

// ---------------------------------------------------------------------------------------------
// Router and server

/// The whole HTTP application. Separate from serving so tests can call it directly.
pub fn app(state: AppState) -> Router {
    let api = Router::new().route("/controllers", get(list_controllers));
    Router::new()
        .route("/", get(index))
        .route("/healthz", get(healthz))
        .nest(API_PREFIX, api)
        .merge(SwaggerUi::new("/swagger-ui").url(OPENAPI_PATH, openapi()))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(middleware::from_fn(log_request))
        .with_state(state)
}

/// Serves [`app`] on `listener` until `shutdown` resolves, then stops accepting connections and
/// lets in-flight requests finish, for at most [`SHUTDOWN_GRACE`].
pub async fn serve<F>(listener: TcpListener, state: AppState, shutdown: F) -> std::io::Result<()>
where
    F: Future<Output = ()> + Send + 'static,
{
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let signal = async move {
        shutdown.await;
        tracing::info!("shutting down: no new connections, finishing in-flight requests");
        let _ = tx.send(());
    };
    let server = axum::serve(listener, app(state)).with_graceful_shutdown(signal);
    let deadline = async move {
        if rx.await.is_ok() {
            tokio::time::sleep(SHUTDOWN_GRACE).await;
        } else {
            // The server ended without a shutdown signal; never fire.
            std::future::pending::<()>().await;
        }
    };
    tokio::select! {
        result = server => result,
        () = deadline => {
            tracing::warn!(grace = ?SHUTDOWN_GRACE, "requests still open after the grace period; stopping anyway");
            Ok(())
        }
    }
}

/// A future that resolves on Ctrl-C (SIGINT) or, on Unix, SIGTERM. The handlers are installed
/// when this is called (it must run inside a tokio runtime), not when the future is first
/// polled, so no signal that arrives after the call is lost or kills the process.
pub fn shutdown_signal() -> std::io::Result<impl Future<Output = ()> + Send + 'static> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, SignalKind};
        let mut interrupt = signal(SignalKind::interrupt())?;
        let mut terminate = signal(SignalKind::terminate())?;
        Ok(async move {
            tokio::select! {
                _ = interrupt.recv() => tracing::info!("received Ctrl-C"),
                _ = terminate.recv() => tracing::info!("received SIGTERM"),
            }
        })
    }
    #[cfg(not(unix))]
    {
        Ok(async {
            match tokio::signal::ctrl_c().await {
                Ok(()) => tracing::info!("received Ctrl-C"),
                Err(e) => {
                    tracing::error!(error = %e, "cannot listen for Ctrl-C");
                    std::future::pending::<()>().await
                }
            }
        })
    }
}

/// Logs to stderr (colored only on a terminal); `RUST_LOG` filters, default `info`. Does nothing
/// if a subscriber is already set.
fn init_tracing() {
    use std::io::IsTerminal;
    use tracing_subscriber::EnvFilter;
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info"));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .try_init();
}

/// `fivex serve`: opens (creating and migrating) the database at `db`, listens on `addr` and
/// serves until Ctrl-C or SIGTERM, then shuts down gracefully. Returns a message for the user on
/// any failure (database, address in use, …).
pub fn run_blocking(db: &Path, addr: &str) -> Result<(), String> {
    init_tracing();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_name("fivex-serve")
        .build()
        .map_err(|e| format!("cannot start the async runtime: {e}"))?;
    runtime.block_on(async {
        let state = AppState::open(db).await.map_err(|e| e.to_string())?;
        tracing::info!(db = %db.display(), "database ready");
        let listener = TcpListener::bind(addr).await.map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        let local = listener.local_addr().map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        // Installed before announcing the address: once the line below is logged, SIGINT and
        // SIGTERM shut the server down gracefully instead of killing it.
        let shutdown = shutdown_signal().map_err(|e| format!("cannot install signal handlers: {e}"))?;
        tracing::info!("fivex listening on http://{local}");
        let pool = state.db.clone();
        serve(listener, state, shutdown).await.map_err(|e| format!("server error: {e}"))?;
        pool.close().await;
        tracing::info!("fivex stopped");
        Ok(())
    })
}
