//! The whole HTTP application: the documented routes (each listed once), the dashboard's
//! assets, the fallbacks and the middleware stack. It knows nothing about sockets, so tests
//! drive it with `oneshot`; `serve.rs` runs it on a listener.

use std::time::Instant;

use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{Method, Uri};
use axum::middleware::{self, Next};
use axum::response::Response;
use axum::routing::get;
use axum::Router;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;
use utoipa_swagger_ui::SwaggerUi;

use super::error::DatabaseFailed;
use super::openapi::{openapi, ApiDoc};
use super::{ApiError, AppState};
use crate::metrics::Metrics;
use crate::{api, assets, auth, content_type, origin};

/// Where the OpenAPI document is served.
pub const OPENAPI_PATH: &str = "/api-docs/openapi.json";

/// Prefix of the versioned REST API.
pub const API_PREFIX: &str = "/api/v1";

/// The largest request body accepted, bytes (a program text is the largest thing a client
/// sends).
pub const MAX_BODY_BYTES: usize = api::programs::MAX_PROGRAM_BYTES + 64 * 1024;

/// The log target of the request lines: the one operators and `fivex-load` filter on
/// (`RUST_LOG=fivex_server::serve=info`), kept from before the HTTP layer had its own module.
const LOG_TARGET: &str = "fivex_server::serve";

/// Every documented route: `/healthz`, `/readyz`, `/metrics` and the API, over the document's
/// info, schemas and tags.
pub(super) fn routes() -> OpenApiRouter<AppState> {
    OpenApiRouter::with_openapi(ApiDoc::openapi())
        .routes(routes!(api::health::healthz))
        .routes(routes!(api::health::readyz))
        .routes(routes!(api::metrics::metrics))
        .merge(api::routes())
}

/// The whole HTTP application. Separate from serving so tests can call it directly.
pub fn app(state: AppState) -> Router {
    Router::new()
        .route("/", get(assets::index))
        .route("/assets/{*file}", get(assets::asset))
        .merge(routes().split_for_parts().0.route_layer(middleware::from_fn(content_type::require_json)))
        .merge(SwaggerUi::new("/swagger-ui").url(OPENAPI_PATH, openapi()))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        // Innermost: after the token and origin checks, a request for a controller of
        // another node goes there (`crate::placement`).
        .layer(middleware::from_fn_with_state(state.clone(), crate::placement::forward))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .layer(middleware::from_fn_with_state(state.clone(), auth::require_token))
        // Added after the token check, so it runs before it: a foreign page's request is
        // refused (403) before the token is looked at.
        .layer(middleware::from_fn_with_state(state.clone(), origin::refuse_cross_origin))
        // Outside every check: whatever error any layer answers leaves as the JSON body.
        .layer(middleware::from_fn(crate::json_errors::json_errors))
        .layer(middleware::from_fn_with_state(state.metrics.clone(), log_request))
        .with_state(state)
}

async fn not_found(method: Method, uri: Uri) -> ApiError {
    ApiError::NotFound(format!("no route for {method} {}", uri.path()))
}

async fn method_not_allowed(method: Method, uri: Uri) -> ApiError {
    ApiError::MethodNotAllowed { method, path: uri.path().to_owned() }
}

/// One log line per request: method, path, status, latency; and the request counted by its
/// status class (and as a database error if it answers one) for `/metrics`.
async fn log_request(State(metrics): State<Metrics>, req: Request, next: Next) -> Response {
    let method = req.method().clone();
    let path = req.uri().path().to_owned();
    let start = Instant::now();
    let response = next.run(req).await;
    let status = response.status().as_u16();
    metrics.answered(status);
    if response.extensions().get::<DatabaseFailed>().is_some() {
        metrics.database_error();
    }
    let micros = start.elapsed().as_micros() as u64;
    if status >= 500 {
        tracing::warn!(target: LOG_TARGET, %method, %path, status, micros, "request");
    } else {
        tracing::info!(target: LOG_TARGET, %method, %path, status, micros, "request");
    }
    response
}
