//! The browser dashboard's files (`web/dist`, built by `npm run build` in `web/`).
//!
//! A release build embeds whatever `web/dist` holds when it is compiled; a debug build reads the
//! folder at run time, so a rebuilt dashboard shows on reload without recompiling. Neither needs
//! npm: without a built dashboard, `/` serves a small fallback page that lists the controllers
//! and says how to build the real one.

use axum::http::{header, HeaderValue, StatusCode, Uri};
use axum::response::{Html, IntoResponse, Response};
use rust_embed::Embed;

/// The fallback page served at `/` when the dashboard is not built.
pub const FALLBACK_HTML: &str = include_str!("fallback.html");

#[derive(Embed)]
#[folder = "../web/dist/"]
#[allow_missing = true]
struct Dashboard;

/// Whether the built dashboard is available.
pub fn dashboard_built() -> bool {
    Dashboard::get("index.html").is_some()
}

/// `GET /`: the dashboard's page, or the fallback.
pub async fn index() -> Response {
    match Dashboard::get("index.html") {
        Some(file) => with_type(file.data.into_owned(), "text/html; charset=utf-8", "no-cache"),
        None => Html(FALLBACK_HTML).into_response(),
    }
}

/// `GET /assets/{file}`: the dashboard's scripts and styles. Their names carry a content hash,
/// so they may be cached for good.
pub async fn asset(uri: Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    match Dashboard::get(path) {
        Some(file) => {
            let mime = file.metadata.mimetype().to_string();
            with_type(file.data.into_owned(), &mime, "public, max-age=31536000, immutable")
        }
        None => crate::http::ApiError::NotFound(format!("no file {path}")).into_response(),
    }
}

fn with_type(body: Vec<u8>, mime: &str, cache: &'static str) -> Response {
    let mut response = (StatusCode::OK, body).into_response();
    let headers = response.headers_mut();
    if let Ok(value) = HeaderValue::from_str(mime) {
        headers.insert(header::CONTENT_TYPE, value);
    }
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static(cache));
    response
}
