//! The bearer token (`fivex serve --token`): with one configured, every `/api/` request must
//! carry it, as `Authorization: Bearer TOKEN` (the scheme in any case, RFC 9110 §11.1) or as
//! `?token=TOKEN` (browsers cannot set headers on a websocket). The query value is
//! percent-decoded (RFC 3986: `%2B` is `+`, and a `+` stays a `+`, since tokens are often
//! base64), so a token with `+ / =` works both as the dashboard encodes it and pasted as is.
//! The dashboard, the health check and the API documentation stay open.

use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use percent_encoding::percent_decode_str;

use crate::http::{ApiError, AppState};

/// The token of an `Authorization: Bearer …` header.
fn bearer(headers: &HeaderMap) -> Option<&[u8]> {
    let value = headers.get(header::AUTHORIZATION)?.to_str().ok()?;
    let (scheme, token) = value.trim_start().split_once(' ')?;
    scheme.eq_ignore_ascii_case("bearer").then(|| token.trim().as_bytes())
}

/// The percent-decoded value of the first `token=` in a query string.
fn query_token(query: &str) -> Option<Vec<u8>> {
    let raw = query.split('&').find_map(|pair| pair.strip_prefix("token="))?;
    Some(percent_decode_str(raw).collect())
}

/// The middleware: with a token configured, an `/api/` request without it gets 401.
pub async fn require_token(State(state): State<AppState>, req: Request, next: Next) -> Response {
    let Some(token) = state.token() else { return next.run(req).await };
    if !req.uri().path().starts_with("/api/") {
        return next.run(req).await;
    }
    let given = match bearer(req.headers()) {
        Some(header) => header.to_vec(),
        None => req.uri().query().and_then(query_token).unwrap_or_default(),
    };
    if constant_time_eq(&given, token.as_bytes()) {
        next.run(req).await
    } else {
        let mut response = ApiError::Unauthorized.into_response();
        response.headers_mut().insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        response
    }
}

/// The token in the OpenAPI document: an HTTP bearer scheme (Swagger UI's Authorize button)
/// that every `/api/` operation accepts, or no authentication at all when the service runs
/// without `--token` (the default), and the 401 answer.
pub struct BearerDoc;

impl utoipa::Modify for BearerDoc {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityRequirement, SecurityScheme};
        let scheme = HttpBuilder::new().scheme(HttpAuthScheme::Bearer).description(Some(
            "The token of `fivex serve --token`, as `Authorization: Bearer TOKEN` (websockets: \
             `?token=TOKEN`, percent-encoded). A service started without a token needs none.",
        ));
        openapi
            .components
            .get_or_insert_with(Default::default)
            .add_security_scheme("bearer", SecurityScheme::Http(scheme.build()));
        let required = vec![SecurityRequirement::new("bearer", Vec::<String>::new()), SecurityRequirement::default()];
        crate::http::openapi::for_each_api_operation(openapi, |_, _, operation| {
            operation.security = Some(required.clone());
            crate::http::openapi::error_response(
                operation,
                401,
                "The service has a token and the request does not carry it",
            );
        });
    }
}

/// Equal without an early exit, so the time taken does not tell how much of a guess was right.
pub(crate) fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bearer_scheme_is_case_insensitive() {
        let mut headers = HeaderMap::new();
        for (value, token) in [("Bearer a+b/c=d", Some("a+b/c=d")), ("bearer x", Some("x")), ("BEARER  y ", Some("y"))]
        {
            headers.insert(header::AUTHORIZATION, value.parse().unwrap());
            assert_eq!(bearer(&headers), token.map(str::as_bytes), "{value}");
        }
        for value in ["Basic eDp5", "Bearer", "Bearerx y"] {
            headers.insert(header::AUTHORIZATION, value.parse().unwrap());
            assert_eq!(bearer(&headers), None, "{value}");
        }
    }

    #[test]
    fn the_query_token_is_percent_decoded_and_plus_stays_plus() {
        assert_eq!(query_token("rate=30&token=a%2Bb%2Fc%3Dd").as_deref(), Some(&b"a+b/c=d"[..]));
        assert_eq!(query_token("token=a+b/c=d&rate=1").as_deref(), Some(&b"a+b/c=d"[..]));
        assert_eq!(query_token("token=a%20b").as_deref(), Some(&b"a b"[..]));
        assert_eq!(query_token("xtoken=1&rate=2"), None);
    }
}
