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

use std::sync::Arc;

use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{Method, StatusCode, Uri};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use serde::{Deserialize, Serialize};
use tokio::net::TcpListener;
use tokio::sync::watch;
use utoipa::{OpenApi, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;
use utoipa_swagger_ui::SwaggerUi;

use crate::auth::BearerDoc;
use crate::host::{Host, Hosted, Spec};
use crate::listen::Limits;
use crate::openapi_doc::RejectionDoc;
use crate::origin::{AllowedOrigins, OriginDoc};
use crate::{api, assets, auth, content_type, db, origin};

/// Where the OpenAPI document is served.
pub const OPENAPI_PATH: &str = "/api-docs/openapi.json";

/// Prefix of the versioned REST API.
pub const API_PREFIX: &str = "/api/v1";

/// How long in-flight requests may take to finish after a shutdown signal before the server
/// stops anyway.
pub const SHUTDOWN_GRACE: Duration = Duration::from_secs(10);

/// The largest request body accepted, bytes (a program text is the largest thing a client
/// sends).
pub const MAX_BODY_BYTES: usize = api::programs::MAX_PROGRAM_BYTES + 64 * 1024;

/// Everything a handler can reach. Cheap to clone (the pool and the host are handles over
/// shared state).
#[derive(Clone, Debug)]
pub struct AppState {
    /// The database: readers and the one writer (`db::Db`).
    pub db: db::Db,
    /// The hosted controllers and their workers.
    pub host: Host,
    /// Set when the service shuts down, so websockets close cleanly.
    closing: Arc<watch::Sender<bool>>,
    /// The database writer of the workers' records, awaited at shutdown.
    writer: Arc<std::sync::Mutex<Option<tokio::task::JoinHandle<()>>>>,
    /// The bearer token the API requires, if any.
    token: Option<Arc<str>>,
    /// The origins besides the served one whose pages may drive the service.
    allowed_origins: AllowedOrigins,
    /// The fleet runs under way and their progress.
    pub fleet_runs: api::fleet::Runs,
    /// What the fleet stream's subscribers share (`api::fleet_view`).
    pub fleet_view: api::fleet_view::FleetView,
}

/// A stored controller as the host runs it, in reset state with what it keeps (`None`, logged,
/// when this version refuses its machine or dialect).
pub async fn load_controller(
    db: &db::Db,
    row: db::ControllerRow,
    settings: &std::collections::HashMap<String, (f64, String)>,
) -> Result<Option<Hosted>, sqlx::Error> {
    let machine = match fivex_engine::machine_file::parse(&row.machine_json) {
        Ok(m) => m,
        Err(e) => {
            tracing::warn!(id = %row.id, error = %e, "stored controller not hosted: its machine is refused");
            return Ok(None);
        }
    };
    let Ok(dialect) = row.dialect.parse() else {
        tracing::warn!(id = %row.id, dialect = %row.dialect, "stored controller not hosted: unknown dialect");
        return Ok(None);
    };
    let retained = db::retained_variables(db, &row.id).await?;
    let row_id = row.id.clone();
    let hosted = Hosted::new(Spec {
        speed: settings.get(&row.id).map_or(1.0, |s| s.0),
        id: row.id,
        name: row.name,
        dialect,
        machine,
        created_at: row.created_at,
    });
    let (tools, work) = (db::tool_offsets(db, &row_id).await?, db::work_offsets(db, &row_id).await?);
    {
        let mut station = hosted.station();
        station.load_retained(&retained);
        station.load_offsets(&tools, &work);
        let extra = settings.get(&row_id).map_or("{}", |s| s.1.as_str());
        station.extra_parameters = serde_json::from_str(extra).unwrap_or_else(|e| {
            tracing::warn!(id = %row_id, error = %e, "stored extra parameters are not a parameter list");
            Default::default()
        });
        station.unmodelled =
            crate::api::parameters::unmodelled(dialect, &station.machine.clone(), &station.extra_parameters);
    }
    // Syntec Pr3014 = 2: the tilted working plane survives the restart.
    if let Some(json) = db::kept_plane(db, &row_id).await? {
        match serde_json::from_str(&json) {
            Ok(plane) => hosted.station().load_kept_plane(&plane),
            Err(e) => tracing::warn!(id = %row_id, error = %e, "stored tilted plane is not a plane"),
        }
    }
    Ok(Some(hosted))
}

impl AppState {
    /// Opens (creating if missing) and migrates the SQLite database at `path`, and brings back
    /// every stored controller in reset state.
    pub async fn open(path: &Path) -> Result<Self, db::OpenError> {
        let pool = db::open(path).await?;
        Self::restore(pool).await.map_err(|source| db::OpenError::Load { path: path.display().to_string(), source })
    }

    /// State over an already opened and migrated pool: the controllers it stores are hosted
    /// again (one that cannot be, a machine document this version refuses, is logged and left
    /// in the database untouched).
    pub async fn restore(db: db::Db) -> Result<Self, sqlx::Error> {
        Self::restore_with(db, Host::default_workers()).await
    }

    /// [`AppState::restore`] with `workers` worker threads.
    pub async fn restore_with(db: db::Db, workers: usize) -> Result<Self, sqlx::Error> {
        let (records, incoming) = tokio::sync::mpsc::unbounded_channel();
        let writer = tokio::spawn(db::write_records(db.clone(), incoming));
        let host = Host::new(workers, records);
        let settings = db::controller_settings(&db).await?;
        db::interrupt_fleet_runs(&db).await?;
        for row in db::list_controllers(&db).await? {
            if let Some(hosted) = load_controller(&db, row, &settings).await? {
                host.add(Arc::new(hosted));
            }
        }
        tracing::info!(controllers = host.len(), "controllers restored");
        let (closing, _) = watch::channel(false);
        Ok(Self {
            db,
            host,
            closing: Arc::new(closing),
            writer: Arc::new(std::sync::Mutex::new(Some(writer))),
            token: None,
            allowed_origins: AllowedOrigins::default(),
            fleet_runs: Default::default(),
            fleet_view: Default::default(),
        })
    }

    /// Require `Authorization: Bearer token` on the API (an empty token requires nothing).
    pub fn with_token(mut self, token: Option<String>) -> Self {
        self.token = token.filter(|t| !t.is_empty()).map(Arc::from);
        self
    }

    /// The bearer token the API requires, if any.
    pub fn token(&self) -> Option<&str> {
        self.token.as_deref()
    }

    /// Let pages from these origins drive the service too (`--allow-origin`, `origin.rs`).
    pub fn with_allowed_origins(mut self, origins: AllowedOrigins) -> Self {
        self.allowed_origins = origins;
        self
    }

    pub fn allowed_origins(&self) -> &AllowedOrigins {
        &self.allowed_origins
    }

    /// A receiver that changes when the service starts shutting down.
    pub fn closing(&self) -> watch::Receiver<bool> {
        self.closing.subscribe()
    }

    /// Tell every websocket to close (the start of a graceful shutdown).
    pub fn close(&self) {
        self.closing.send_replace(true);
    }

    /// How many fleet runs run at once (the others wait, `queued`).
    pub fn with_fleet_jobs(mut self, jobs: usize) -> Self {
        self.fleet_runs = api::fleet::Runs::new(jobs);
        self
    }

    /// The end of a graceful shutdown: websockets told to close, fleet runs interrupted and
    /// recorded, the workers stopped, and everything they produced written to the database.
    pub async fn shutdown(&self) {
        self.close();
        self.fleet_runs.interrupt_all();
        if tokio::time::timeout(SHUTDOWN_GRACE, self.fleet_runs.all_ended()).await.is_err() {
            tracing::warn!("fleet runs still under way after the grace period");
        }
        let host = self.host.clone();
        let _ = tokio::task::spawn_blocking(move || host.shutdown()).await;
        let writer = self.writer.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(writer) = writer {
            let _ = writer.await;
        }
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
    /// The request is well-formed but its content is not acceptable; `details` (for example
    /// the diagnostics of a program) go into the body.
    #[error("{0}")]
    Unprocessable(String, Option<serde_json::Value>),
    /// An extractor refused the request (bad JSON, wrong content type, bad path or query).
    #[error("{1}")]
    Rejected(StatusCode, String),
    #[error("service unavailable: {0}")]
    Unavailable(String),
    #[error("a bearer token is required (Authorization: Bearer TOKEN)")]
    Unauthorized,
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
            ApiError::Unprocessable(..) => StatusCode::UNPROCESSABLE_ENTITY,
            ApiError::Rejected(status, _) => *status,
            ApiError::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            ApiError::Unauthorized => StatusCode::UNAUTHORIZED,
            ApiError::Database(e) if owner_gone(e) => StatusCode::NOT_FOUND,
            ApiError::Database(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status();
        if let ApiError::Database(source) = &self {
            if owner_gone(source) {
                let body = ErrorBody { error: "no such controller (it was deleted meanwhile)".into(), details: None };
                return (status, Json(body)).into_response();
            }
            tracing::error!(error = %source, "database error");
        }
        let details = match &self {
            ApiError::Unprocessable(_, details) => details.clone(),
            _ => None,
        };
        let body = ErrorBody { error: self.to_string(), details };
        (status, Json(body)).into_response()
    }
}

/// A write for a controller that a concurrent request deleted after the handler found it fails on
/// the foreign key: that is the client's 404, not the service's 500.
fn owner_gone(e: &sqlx::Error) -> bool {
    e.as_database_error().is_some_and(|d| d.kind() == sqlx::error::ErrorKind::ForeignKeyViolation)
}

/// The body of every 4xx/5xx response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ErrorBody {
    /// What went wrong, for a person to read.
    #[schema(example = "no route for GET /api/v1/nope")]
    pub error: String,
    /// More about it, where there is more (the diagnostics of a refused program).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<serde_json::Value>)]
    pub details: Option<serde_json::Value>,
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

// ---------------------------------------------------------------------------------------------
// Handlers

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
    // The readers answer, and the writer is there (a query on it would wait behind the writes).
    let writer = if state.db.writes().is_closed() { Err(sqlx::Error::PoolClosed) } else { Ok(()) };
    let reader = sqlx::query("SELECT 1").execute(state.db.reads()).await.map(|_| ());
    writer.and(reader).map_err(|e| {
        tracing::warn!(error = %e, "health check: database does not answer");
        ApiError::Unavailable("database does not answer".into())
    })?;
    Ok(Json(Health { status: "ok".into() }))
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
    components(schemas(
        Health,
        ErrorBody,
        api::ControllerStatus,
        api::Position,
        api::PanelState,
        crate::host::stream::AlarmInfo,
        crate::host::stream::PositionFrame,
        crate::host::stream::Message,
        api::stream::Snapshot,
        api::stream::Fleet,
        api::stream::FleetDelta,
        api::stream::FleetEntry,
        api::fleet::FleetRequest,
        api::fleet::FleetRunInfo,
        api::fleet::FleetRun,
        api::fleet::Progress,
        api::fleet::MachineProgress,
        crate::wire::ControllerMessage,
        crate::wire::FleetMessage,
        crate::wire::RunSummary,
        crate::wire::FleetResult,
    )),
    tags(
        (name = "service", description = "Service health and documentation"),
        (name = "controllers", description = "Virtual CNC controllers"),
        (name = "programs", description = "Stored NC programs"),
        (name = "panel", description = "The operator panel"),
        (name = "manual", description = "JOG, HANDLE and the 5-axis manual feeds"),
        (name = "variables", description = "Custom macro variables"),
        (name = "offsets", description = "Tool and work offsets"),
        (name = "parameters", description = "Vendor parameters"),
        (name = "history", description = "Alarm and run history"),
        (name = "stream", description = "Live websocket stream"),
        (name = "fleet", description = "Fleet runs: one program on many machines"),
    )
)]
pub struct ApiDoc;

/// Calls `f` with every operation under `/api/` (for the modifiers that document what a
/// middleware adds to all of them).
pub fn for_each_api_operation(
    openapi: &mut utoipa::openapi::OpenApi,
    mut f: impl FnMut(Method, &str, &mut utoipa::openapi::path::Operation),
) {
    for (path, item) in openapi.paths.paths.iter_mut().filter(|(path, _)| path.starts_with("/api/")) {
        let operations = [
            (Method::GET, &mut item.get),
            (Method::PUT, &mut item.put),
            (Method::POST, &mut item.post),
            (Method::DELETE, &mut item.delete),
            (Method::PATCH, &mut item.patch),
        ];
        for (method, operation) in operations {
            if let Some(operation) = operation {
                f(method, path, operation);
            }
        }
    }
}

/// Adds a `status` answer with the JSON error body to an operation.
pub fn error_response(operation: &mut utoipa::openapi::path::Operation, status: u16, description: &str) {
    use utoipa::openapi::{ContentBuilder, Ref, ResponseBuilder};
    let content = ContentBuilder::new().schema(Some(Ref::from_schema_name("ErrorBody"))).build();
    let response = ResponseBuilder::new().description(description).content("application/json", content).build();
    operation.responses.responses.insert(status.to_string(), response.into());
}

/// The OpenAPI document as a value.
pub fn openapi() -> utoipa::openapi::OpenApi {
    let (_, mut doc) = routes().split_for_parts();
    // The modifiers document what the middleware adds to every operation: they run once the
    // routes have put their operations in.
    for modifier in [&BearerDoc as &dyn utoipa::Modify, &OriginDoc, &RejectionDoc] {
        modifier.modify(&mut doc);
    }
    doc
}

/// Every documented route: `/healthz` and the API, over the document's info, schemas and tags.
fn routes() -> OpenApiRouter<AppState> {
    OpenApiRouter::with_openapi(ApiDoc::openapi()).routes(routes!(healthz)).merge(api::routes())
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
    Router::new()
        .route("/", get(assets::index))
        .route("/assets/{*file}", get(assets::asset))
        .merge(routes().split_for_parts().0.route_layer(middleware::from_fn(content_type::require_json)))
        .merge(SwaggerUi::new("/swagger-ui").url(OPENAPI_PATH, openapi()))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .layer(middleware::from_fn_with_state(state.clone(), auth::require_token))
        // Added after the token check, so it runs before it: a foreign page's request is
        // refused (403) before the token is looked at.
        .layer(middleware::from_fn_with_state(state.clone(), origin::refuse_cross_origin))
        // Outside every check: whatever error any layer answers leaves as the JSON body.
        .layer(middleware::from_fn(crate::json_errors::json_errors))
        .layer(middleware::from_fn(log_request))
        .with_state(state)
}

/// Serves [`app`] on `listener` with the default [`Limits`] until `shutdown` resolves
/// ([`serve_with`]).
pub async fn serve<F>(listener: TcpListener, state: AppState, shutdown: F) -> std::io::Result<()>
where
    F: Future<Output = ()> + Send + 'static,
{
    serve_with(listener, state, Limits::default(), shutdown).await
}

/// Serves [`app`] on `listener` within `limits` (`crate::listen`) until `shutdown` resolves;
/// then accepts no more connections, tells every websocket to close, interrupts the fleet runs,
/// closes the idle connections and lets in-flight requests finish, for at most
/// [`SHUTDOWN_GRACE`].
pub async fn serve_with<F>(listener: TcpListener, state: AppState, limits: Limits, shutdown: F) -> std::io::Result<()>
where
    F: Future<Output = ()> + Send + 'static,
{
    let closing = state.clone();
    let signal = async move {
        shutdown.await;
        tracing::info!("shutting down: no new connections, finishing in-flight requests");
        closing.close();
        // A fleet run holds its request (`wait`) and a blocking thread until it ends: it ends now.
        closing.fleet_runs.interrupt_all();
    };
    crate::listen::serve(listener, app(state), limits, SHUTDOWN_GRACE, signal).await;
    Ok(())
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

/// How `fivex serve` runs (flags or `FIVEX_DB`, `FIVEX_ADDR`, `FIVEX_TOKEN`, `FIVEX_WORKERS`,
/// `FIVEX_ALLOW_ORIGIN`, and the limits' `FIVEX_…`, `cli/limits.rs`).
#[derive(Debug, Clone)]
pub struct ServeOptions {
    pub db: std::path::PathBuf,
    pub addr: String,
    pub token: Option<String>,
    pub workers: Option<usize>,
    pub allow_origins: Vec<origin::Origin>,
    /// Connection timeouts and caps.
    pub limits: Limits,
    /// Fleet runs that run at once (at least 1).
    pub fleet_jobs: usize,
}

/// `fivex serve` with the database and address only.
pub fn run_blocking(db: &Path, addr: &str) -> Result<(), String> {
    run_with(ServeOptions {
        db: db.to_path_buf(),
        addr: addr.to_string(),
        token: None,
        workers: None,
        allow_origins: Vec::new(),
        limits: Limits::default(),
        fleet_jobs: 1,
    })
}

/// `fivex serve`: opens (creating and migrating) the database, brings the stored controllers
/// back, listens on the address and serves until Ctrl-C or SIGTERM, then shuts down gracefully
/// (websockets closed, workers stopped, their records written). Returns a message for the user
/// on any failure (database, address in use, …).
pub fn run_with(options: ServeOptions) -> Result<(), String> {
    init_tracing();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_name("fivex-serve")
        .build()
        .map_err(|e| format!("cannot start the async runtime: {e}"))?;
    let served = runtime.block_on(async {
        let (db, addr) = (&options.db, &options.addr);
        let pool = db::open(db).await.map_err(|e| e.to_string())?;
        let workers = options.workers.unwrap_or_else(Host::default_workers);
        let state = AppState::restore_with(pool, workers)
            .await
            .map_err(|e| format!("cannot read the controllers of {}: {e}", db.display()))?
            .with_token(options.token.clone())
            .with_allowed_origins(AllowedOrigins::new(options.allow_origins.clone()))
            .with_fleet_jobs(options.fleet_jobs);
        tracing::info!(db = %db.display(), workers, token = state.token.is_some(), "database ready");
        tracing::info!(limits = ?options.limits, fleet_jobs = options.fleet_jobs, "limits");
        let listener = TcpListener::bind(addr).await.map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        let local = listener.local_addr().map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        // Installed before announcing the address: once the line below is logged, SIGINT and
        // SIGTERM shut the server down gracefully instead of killing it.
        let shutdown = shutdown_signal().map_err(|e| format!("cannot install signal handlers: {e}"))?;
        tracing::info!("fivex listening on http://{local}");
        let after = state.clone();
        serve_with(listener, state, options.limits.clone().fitted_to_process(), shutdown)
            .await
            .map_err(|e| format!("server error: {e}"))?;
        after.shutdown().await;
        after.db.close().await;
        tracing::info!("fivex stopped");
        Ok(())
    });
    // Dropping a runtime waits for its blocking threads; whatever is still on one (a request
    // stuck past the grace period) must not hold the exit.
    runtime.shutdown_timeout(Duration::from_secs(1));
    served
}
