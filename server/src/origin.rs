//! Cross-origin protection: a web page the operator happens to have open must not be able to
//! drive the service through the operator's browser.
//!
//! Browsers let any page send "simple" requests (a POST without a body or with a `text/plain`
//! or form body) to any address without asking the server first, and open websockets to any
//! address; CORS only stops the page from *reading* the answer, which is too late for a cycle
//! start. What a browser cannot forge are the `Origin` and `Sec-Fetch-Site` request headers, so
//! every state-changing request (any method but GET, HEAD and OPTIONS) and every websocket
//! upgrade is checked against them, as Go's `net/http.CrossOriginProtection` does:
//!
//! 1. `Sec-Fetch-Site: same-origin` or `none` (the page of the service itself, or a request the
//!    user typed) is allowed; any other value (`same-site`, `cross-site`) only from an
//!    allow-listed `Origin`.
//! 2. Without `Sec-Fetch-Site` (older browsers, other programs): no `Origin` is allowed (curl, the
//!    CLI, scripts: not a browser acting for a page); an `Origin` whose `host[:port]` is the
//!    request's `Host` (the served origin) or that is allow-listed is allowed.
//! 3. Everything else is refused with 403 and the JSON error body.
//!
//! Before all that, every request's `Host` must be a name the service answers to: an IP address,
//! `localhost` (or a name under it), or the host of an allow-listed origin. Otherwise a page
//! could rebind its own DNS name to the operator's 127.0.0.1 (DNS rebinding) and, being then
//! "same-origin" to the browser, drive the service and read its answers; it cannot make the
//! browser send a `Host` other than its own name.
//!
//! The allow-list (`--allow-origin`) is for a page served from elsewhere (the dashboard's
//! development server, a reverse proxy that rewrites `Host` for browsers without
//! `Sec-Fetch-Site`).

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, Method, StatusCode, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::http::{ApiError, AppState};

/// A web origin as browsers send it in `Origin`: `scheme://host[:port]`, lower case.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Origin(String);

impl FromStr for Origin {
    type Err = String;

    /// Reads `scheme://host[:port]` (a trailing `/` is dropped); anything with a path, query or
    /// user name is refused, since a browser never sends one and it could never match.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let refused = |why: &str| format!("{text:?} is not an origin (scheme://host[:port]): {why}");
        let trimmed = text.trim();
        let uri: Uri = trimmed.parse().map_err(|e| refused(&format!("{e}")))?;
        let scheme = uri.scheme_str().ok_or_else(|| refused("no scheme"))?;
        let authority = uri.authority().ok_or_else(|| refused("no host"))?;
        if authority.as_str().contains('@') {
            return Err(refused("a user name is not part of an origin"));
        }
        if uri.path_and_query().is_some_and(|p| p.as_str() != "/") {
            return Err(refused("a path or query is not part of an origin"));
        }
        Ok(Origin(format!("{scheme}://{authority}").to_ascii_lowercase()))
    }
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// The origins besides the served one that may drive the service (`--allow-origin`).
#[derive(Debug, Clone, Default)]
pub struct AllowedOrigins(Arc<[Origin]>);

impl AllowedOrigins {
    pub fn new(origins: Vec<Origin>) -> Self {
        AllowedOrigins(origins.into())
    }

    fn contains(&self, origin: &str) -> bool {
        self.0.iter().any(|o| o.0.eq_ignore_ascii_case(origin))
    }

    /// Whether `host` (no port) is the host of an allow-listed origin.
    fn names(&self, host: &str) -> bool {
        self.0.iter().any(|o| {
            o.0.parse::<Uri>().ok().and_then(|u| u.host().map(|h| h.eq_ignore_ascii_case(host))).unwrap_or(false)
        })
    }
}

/// `Ok` when the request's `Host` is a name the service answers to (see the module's text).
pub fn check_host(headers: &HeaderMap, allowed: &AllowedOrigins) -> Result<(), String> {
    let Some(value) = headers.get(header::HOST) else { return Ok(()) };
    let text = value.to_str().unwrap_or("");
    let Some(host) = format!("http://{text}").parse::<Uri>().ok().and_then(|u| u.host().map(str::to_owned)) else {
        return Err(format!("Host {text:?} is not a host name"));
    };
    let bare = host.trim_start_matches('[').trim_end_matches(']');
    let lower = bare.to_ascii_lowercase();
    if bare.parse::<std::net::IpAddr>().is_ok()
        || lower == "localhost"
        || lower.ends_with(".localhost")
        || allowed.names(bare)
    {
        return Ok(());
    }
    Err(format!(
        "cross-origin request refused: Host {text:?} is not a name this service answers to (IP addresses and localhost are); \
         serving under a DNS name, allow it with --allow-origin http://{text}"
    ))
}

/// Whether a request can change something or open a stream: every method but the safe ones,
/// and a websocket upgrade (a GET that a browser sends from any page without asking).
fn guarded(method: &Method, headers: &HeaderMap) -> bool {
    let upgrade = headers
        .get_all(header::UPGRADE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .any(|v| v.split(',').any(|p| p.trim().eq_ignore_ascii_case("websocket")));
    upgrade || !matches!(*method, Method::GET | Method::HEAD | Method::OPTIONS)
}

/// `Ok` when the request may go on, else why it is refused.
pub fn check(method: &Method, headers: &HeaderMap, allowed: &AllowedOrigins) -> Result<(), String> {
    if !guarded(method, headers) {
        return Ok(());
    }
    let text = |name| headers.get(name).map(|v| v.to_str().unwrap_or("(not text)"));
    let origin = text(header::ORIGIN);
    let allow_listed = origin.is_some_and(|o| allowed.contains(o));
    let advice = "allow an origin with --allow-origin";
    match text(header::HeaderName::from_static("sec-fetch-site")) {
        Some(site) if site.eq_ignore_ascii_case("same-origin") || site.eq_ignore_ascii_case("none") => return Ok(()),
        Some(_) if allow_listed => return Ok(()),
        Some(site) => {
            let origin = origin.unwrap_or("none");
            return Err(format!("cross-origin request refused (Sec-Fetch-Site: {site}, Origin: {origin}); {advice}"));
        }
        None => {}
    }
    let Some(origin) = origin else { return Ok(()) };
    let served = headers.get(header::HOST).and_then(|h| h.to_str().ok());
    let host_of_origin = origin.parse::<Uri>().ok().and_then(|u| u.authority().map(|a| a.as_str().to_owned()));
    if allow_listed || host_of_origin.is_some_and(|h| served.is_some_and(|s| s.eq_ignore_ascii_case(&h))) {
        return Ok(());
    }
    let served = served.unwrap_or("no Host");
    Err(format!("cross-origin request refused (Origin: {origin}, served as {served}); {advice}"))
}

/// The middleware: refuses a cross-origin request with 403 before anything else sees it.
pub async fn refuse_cross_origin(State(state): State<AppState>, req: Request, next: Next) -> Response {
    let checked = check_host(req.headers(), state.allowed_origins())
        .and_then(|()| check(req.method(), req.headers(), state.allowed_origins()));
    match checked {
        Ok(()) => next.run(req).await,
        Err(reason) => {
            tracing::warn!(method = %req.method(), path = %req.uri().path(), %reason, "refused");
            ApiError::Rejected(StatusCode::FORBIDDEN, reason).into_response()
        }
    }
}

/// The 403 in the OpenAPI document: every operation checks `Host`; the state-changing ones and
/// the websockets also the origin.
pub struct OriginDoc;

const HOST_REFUSED: &str =
    "Host is not a name the service answers to (an IP address, localhost, an allowed origin's host)";

impl utoipa::Modify for OriginDoc {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        crate::http::openapi::for_each_api_operation(openapi, |method, path, operation| {
            let why = if method != Method::GET || path.ends_with("/stream") {
                "A web page from a foreign origin sent it (Origin, Sec-Fetch-Site), or Host is not a name the service answers to"
            } else {
                HOST_REFUSED
            };
            crate::http::openapi::error_response(operation, 403, why);
        });
        // The Host check answers every request, `/healthz`, `/readyz` and `/metrics` too.
        for path in ["/healthz", "/readyz", "/metrics"] {
            if let Some(operation) = openapi.paths.paths.get_mut(path).and_then(|item| item.get.as_mut()) {
                crate::http::openapi::error_response(operation, 403, HOST_REFUSED);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut map = HeaderMap::new();
        for (name, value) in pairs {
            map.append(*name, value.parse().unwrap());
        }
        map
    }

    #[test]
    fn origins_are_read_in_the_form_browsers_send_them() {
        assert_eq!("HTTP://Example.com:8080/".parse::<Origin>().unwrap().to_string(), "http://example.com:8080");
        assert_eq!("https://fivex.example".parse::<Origin>().unwrap().to_string(), "https://fivex.example");
        for bad in ["example.com", "http://example.com/app", "http://u@example.com", "http://a.b?x=1", "", "*"] {
            assert!(bad.parse::<Origin>().is_err(), "{bad:?} taken as an origin");
        }
    }

    #[test]
    fn safe_methods_pass_and_websocket_upgrades_are_checked() {
        let none = AllowedOrigins::default();
        let foreign = [("host", "127.0.0.1:8080"), ("origin", "http://evil.example")];
        assert!(check(&Method::GET, &headers(&foreign), &none).is_ok());
        assert!(check(&Method::OPTIONS, &headers(&foreign), &none).is_ok());
        let upgrade = [foreign[0], foreign[1], ("upgrade", "WebSocket")];
        assert!(check(&Method::GET, &headers(&upgrade), &none).is_err());
        assert!(check(&Method::DELETE, &headers(&foreign), &none).is_err());
    }

    #[test]
    fn fetch_metadata_decides_before_the_origin() {
        let allowed = AllowedOrigins::new(vec!["http://localhost:5173".parse().unwrap()]);
        let with = |site: &'static str, origin: &'static str| {
            check(
                &Method::POST,
                &headers(&[("host", "127.0.0.1:8080"), ("sec-fetch-site", site), ("origin", origin)]),
                &allowed,
            )
        };
        // A proxy rewrote Host: the browser still says same-origin.
        assert!(with("same-origin", "https://fivex.example").is_ok());
        assert!(with("cross-site", "http://localhost:5173").is_ok());
        assert!(with("same-site", "http://127.0.0.1:9999").is_err());
        assert!(with("cross-site", "http://127.0.0.1:8080").is_err(), "the browser's word wins over a matching Origin");
        let no_origin = headers(&[("host", "127.0.0.1:8080"), ("sec-fetch-site", "cross-site")]);
        assert!(check(&Method::POST, &no_origin, &allowed).is_err());
    }

    #[test]
    fn the_host_must_be_an_address_localhost_or_an_allowed_origins() {
        let allowed = AllowedOrigins::new(vec!["http://cnc.example:8080".parse().unwrap()]);
        let host = |h: &'static str| check_host(&headers(&[("host", h)]), &allowed);
        for ok in [
            "127.0.0.1:8080",
            "[::1]:8080",
            "10.1.2.3",
            "localhost:8080",
            "LOCALHOST",
            "app.localhost:1",
            "cnc.example:8080",
            "CNC.example",
        ] {
            assert!(host(ok).is_ok(), "{ok} refused");
        }
        for bad in ["evil.example:8080", "127.0.0.1.evil.example", "localhost.evil.example", "cnc.example.evil"] {
            assert!(host(bad).is_err(), "{bad} accepted");
        }
        assert!(check_host(&HeaderMap::new(), &allowed).is_ok(), "no Host: not a browser");
    }

    #[test]
    fn without_fetch_metadata_the_origin_must_be_the_host_or_allowed() {
        let allowed = AllowedOrigins::new(vec!["https://ops.example".parse().unwrap()]);
        let post = |pairs: &[(&'static str, &str)]| check(&Method::POST, &headers(pairs), &allowed);
        assert!(post(&[("host", "127.0.0.1:8080")]).is_ok(), "no Origin: not a browser");
        assert!(post(&[("host", "127.0.0.1:8080"), ("origin", "http://127.0.0.1:8080")]).is_ok());
        assert!(post(&[("host", "Fivex.Example"), ("origin", "https://fivex.example")]).is_ok());
        assert!(post(&[("host", "127.0.0.1:8080"), ("origin", "https://OPS.example")]).is_ok());
        assert!(post(&[("host", "127.0.0.1:8080"), ("origin", "http://127.0.0.1:8081")]).is_err());
        assert!(post(&[("host", "127.0.0.1:8080"), ("origin", "null")]).is_err());
        assert!(post(&[("origin", "http://127.0.0.1:8080")]).is_err(), "no Host to compare with");
    }
}
