//! Every error response is the documented JSON (`{"error": …}`, docs/api.md "Errors").
//!
//! The handlers' own errors are [`ApiError`]s already; what is left are the responses made
//! outside them — an extractor's rejection that a handler takes without `Result` (an oversized
//! body, the optional JSON of cycle start, a request to a websocket route without the upgrade)
//! and the layers around the router. Those are `text/plain`. This layer turns any 4xx/5xx
//! response that is not JSON into an [`ApiError`] with the same status, its text as the
//! message, and the same headers (`Allow`, `WWW-Authenticate`, `Sec-WebSocket-Version`, …), so
//! a handler or extractor added later cannot break the rule.

use axum::body::to_bytes;
use axum::extract::Request;
use axum::http::{header, HeaderMap};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::http::ApiError;

/// The most of a plain-text error body kept as the message (they are one line).
const MESSAGE_BYTES: usize = 4096;

/// The middleware (`axum::middleware::from_fn`).
pub async fn json_errors(request: Request, next: Next) -> Response {
    let response = next.run(request).await;
    let status = response.status();
    if !(status.is_client_error() || status.is_server_error()) || is_json(response.headers()) {
        return response;
    }
    let (parts, body) = response.into_parts();
    let text = match to_bytes(body, MESSAGE_BYTES).await {
        Ok(bytes) => String::from_utf8_lossy(&bytes).trim().to_owned(),
        Err(_) => String::new(),
    };
    let message = if text.is_empty() { status.canonical_reason().unwrap_or("error").to_lowercase() } else { text };
    let mut json = ApiError::Rejected(status, message).into_response();
    for (name, value) in &parts.headers {
        if name != header::CONTENT_TYPE && name != header::CONTENT_LENGTH {
            json.headers_mut().append(name, value.clone());
        }
    }
    json
}

fn is_json(headers: &HeaderMap) -> bool {
    headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.trim_start().to_ascii_lowercase().starts_with("application/json"))
}
