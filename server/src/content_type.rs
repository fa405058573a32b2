//! JSON endpoints take JSON only. A state-changing request to an `/api/` route that declares a
//! content type other than `application/json` (or `application/…+json`), or that has a body
//! without declaring one, is refused with 415 and the JSON error body before its handler runs.
//! Without this a bodyless handler (reset, feed hold) would take a `text/plain` or form POST,
//! the kind of request any web page can send without the browser asking first; the Origin check
//! (`origin.rs`) refuses those from foreign pages, this keeps the API's contract strict for
//! every client. The one route that takes text, a program's NC text, checks its own type.

use axum::extract::{MatchedPath, Request};
use axum::http::{header, HeaderMap, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::http::ApiError;

/// The routes whose body is not JSON (they check their own content type).
const TEXT_ROUTES: &[(Method, &str)] = &[(Method::PUT, "/api/v1/controllers/{id}/programs/{number}")];

/// Whether a media type is JSON: `application/json` or `application/…+json`, any parameters.
pub fn is_json(media: &str) -> bool {
    let essence = media.split(';').next().unwrap_or("").trim().to_ascii_lowercase();
    essence == "application/json" || (essence.starts_with("application/") && essence.ends_with("+json"))
}

/// Whether the request has a body (a `Content-Length` above 0, or a chunked one).
fn has_body(headers: &HeaderMap) -> bool {
    let length = headers.get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()).and_then(|v| v.trim().parse().ok());
    length.is_some_and(|n: u64| n > 0) || headers.contains_key(header::TRANSFER_ENCODING)
}

/// `Ok` when the request may go on, else why it is refused.
pub fn check(method: &Method, route: Option<&str>, headers: &HeaderMap) -> Result<(), String> {
    if matches!(*method, Method::GET | Method::HEAD | Method::OPTIONS) {
        return Ok(());
    }
    if TEXT_ROUTES.iter().any(|(m, r)| m == method && Some(*r) == route) {
        return Ok(());
    }
    match headers.get(header::CONTENT_TYPE) {
        Some(media) => {
            let media = media.to_str().unwrap_or("(not text)");
            if is_json(media) {
                Ok(())
            } else {
                Err(format!("this endpoint takes application/json, not {media}"))
            }
        }
        None if has_body(headers) => Err("a request body needs Content-Type: application/json".to_owned()),
        None => Ok(()),
    }
}

/// The middleware, as a route layer of the API (so the matched route is known).
pub async fn require_json(req: Request, next: Next) -> Response {
    let route = req.extensions().get::<MatchedPath>().map(MatchedPath::as_str);
    match check(req.method(), route, req.headers()) {
        Ok(()) => next.run(req).await,
        Err(reason) => ApiError::Rejected(StatusCode::UNSUPPORTED_MEDIA_TYPE, reason).into_response(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        pairs.iter().map(|(n, v)| (header::HeaderName::from_static(n), v.parse().unwrap())).collect()
    }

    #[test]
    fn json_media_types() {
        for yes in ["application/json", "Application/JSON; charset=utf-8", "application/merge-patch+json"] {
            assert!(is_json(yes), "{yes}");
        }
        for no in ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x", "text/json+x"]
        {
            assert!(!is_json(no), "{no}");
        }
    }

    #[test]
    fn state_changing_requests_declare_json_or_send_nothing() {
        let post = |pairs| check(&Method::POST, Some("/api/v1/controllers/{id}/reset"), &headers(pairs));
        assert!(post(&[]).is_ok());
        assert!(post(&[("content-length", "0")]).is_ok());
        assert!(post(&[("content-type", "application/json"), ("content-length", "2")]).is_ok());
        assert!(post(&[("content-type", "text/plain")]).is_err());
        assert!(post(&[("content-type", "text/plain"), ("content-length", "0")]).is_err());
        assert!(post(&[("content-length", "12")]).is_err());
        assert!(post(&[("transfer-encoding", "chunked")]).is_err());
        assert!(check(&Method::GET, None, &headers(&[("content-type", "text/plain")])).is_ok());
    }

    #[test]
    fn program_text_is_left_to_its_handler() {
        let text = headers(&[("content-type", "text/plain"), ("content-length", "5")]);
        let route = Some("/api/v1/controllers/{id}/programs/{number}");
        assert!(check(&Method::PUT, route, &text).is_ok());
        assert!(check(&Method::DELETE, route, &text).is_err());
    }
}
