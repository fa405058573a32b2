//! The extractors: the controller a path names ([`Addressed`]) and a JSON request body
//! ([`JsonBody`]), each with its rejection as an [`ApiError`].
//!
//! A JSON request body is read as the OpenAPI document describes it. Two places where serde alone
//! is wider or narrower than the document's JSON Schema:
//!
//! - serde reads a struct from an array too (`[null, null]` as `{"feed": null, "rapid":
//!   null}`); every body the API takes is an object, so anything else is refused (422).
//! - JSON Schema counts a number without a fraction as an integer (`4.0` is the integer 4);
//!   serde refuses `4.0` for a `u32`. Such numbers are read as the integers they are.

use std::sync::Arc;

use axum::extract::rejection::PathRejection;
use axum::extract::{FromRequest, FromRequestParts, Json, Path, Request};
use serde::de::DeserializeOwned;
use serde_json::{Number, Value};

use super::{ApiError, AppState};
use crate::host::Hosted;

/// The extractor: a JSON object deserialized into `T`, or the JSON error (400 syntax, 413 size,
/// 415 content type, 422 shape).
pub struct JsonBody<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for JsonBody<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, ApiError> {
        let rejected = |e: axum::extract::rejection::JsonRejection| ApiError::Rejected(e.status(), e.body_text());
        let declared = req.headers().get(axum::http::header::CONTENT_TYPE).and_then(|v| v.to_str().ok());
        if !declared.is_some_and(crate::content_type::is_json) {
            // Refused as `Json` refuses it (415), whatever the body.
            return Json::<Value>::from_request(req, state)
                .await
                .map_err(rejected)
                .and_then(|Json(v)| from_object(v))
                .map(JsonBody);
        }
        let bytes = axum::body::Bytes::from_request(req, state)
            .await
            .map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
        let Json(value) = Json::<Value>::from_bytes(&bytes).map_err(rejected)?;
        // `Value` keeps the last of a key given twice: the request is ambiguous (`json_keys`).
        if let Some(twice) = crate::json_keys::duplicate_key(&bytes) {
            return Err(ApiError::Unprocessable(format!("the request body is ambiguous: {twice}"), None));
        }
        from_object(value).map(JsonBody)
    }
}

/// The body of an action that takes none (reset, feed hold, jog stop, …): nothing, or JSON,
/// which is ignored (`{}` and `null` are what clients send). A body that is not JSON is refused
/// with 400, as on every JSON endpoint: the content type says JSON (`content_type.rs`), and an
/// answer of 200 to `{` would tell a client its malformed request was understood.
pub struct Bodyless;

impl<S: Send + Sync> FromRequest<S> for Bodyless {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, ApiError> {
        let bytes = axum::body::Bytes::from_request(req, state)
            .await
            .map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
        if !bytes.iter().all(u8::is_ascii_whitespace) {
            // A `Value`, not `IgnoredAny`: that one skips numbers without reading them (`1e400`).
            serde_json::from_slice::<Value>(&bytes).map_err(|e| {
                ApiError::Rejected(axum::http::StatusCode::BAD_REQUEST, format!("the request body is not JSON: {e}"))
            })?;
        }
        Ok(Bodyless)
    }
}

/// `value`, which must be an object, as a `T` (422 with the field's path when it does not fit).
pub fn from_object<T: DeserializeOwned>(mut value: Value) -> Result<T, ApiError> {
    if !value.is_object() {
        return Err(ApiError::Unprocessable("the request body must be a JSON object".into(), None));
    }
    integers(&mut value);
    serde_path_to_error::deserialize(value).map_err(|e| {
        ApiError::Unprocessable(format!("Failed to deserialize the JSON body into the target type: {e}"), None)
    })
}

/// The largest magnitude below which every whole f64 is exactly an integer (2^53).
const EXACT: f64 = 9_007_199_254_740_992.0;

/// Turns every whole number written with a fraction or exponent (`4.0`, `1e3`) into the integer.
fn integers(value: &mut Value) {
    match value {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            // -0.0 stays a float: it is not the integer 0 to a program that reads its sign.
            let whole = x.fract() == 0.0 && x.abs() < EXACT && !(x == 0.0 && x.is_sign_negative());
            if whole {
                *n = if x < 0.0 { Number::from(x as i64) } else { Number::from(x as u64) };
            }
        }
        Value::Array(items) => items.iter_mut().for_each(integers),
        Value::Object(fields) => fields.values_mut().for_each(integers),
        _ => {}
    }
}

/// The hosted controller `id`, or 404.
pub fn hosted(state: &AppState, id: &str) -> Result<Arc<Hosted>, ApiError> {
    state.host.get(id).ok_or_else(|| ApiError::NotFound(format!("no controller {id}")))
}

/// The controller a route's `{id}` names (404 when there is none): the first thing every
/// `/controllers/{id}/…` handler needs.
pub struct Addressed(pub Arc<Hosted>);

impl FromRequestParts<AppState> for Addressed {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut axum::http::request::Parts, state: &AppState) -> Result<Self, ApiError> {
        let params = axum::extract::RawPathParams::from_request_parts(parts, state)
            .await
            .map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
        let id = params.iter().find(|(name, _)| *name == "id").map(|(_, value)| value.to_owned());
        let id = id.ok_or_else(|| ApiError::NotFound("the path names no controller".into()))?;
        let hosted = hosted(state, &id)?;
        // A command or a write: its operator is at it, so a node of a cluster leaves it where it
        // is for a while (`placement::handover`). Reading it (a dashboard polling) does not.
        if !matches!(parts.method, axum::http::Method::GET | axum::http::Method::HEAD) {
            hosted.touch();
        }
        Ok(Addressed(hosted))
    }
}

/// A JSON body (an object, [`JsonBody`]), or the reason it is not one as a JSON error.
pub fn body<T>(json: Result<JsonBody<T>, ApiError>) -> Result<T, ApiError> {
    json.map(|JsonBody(v)| v)
}

/// Path parameters, or the reason they do not parse as a JSON error.
pub fn path<T>(path: Result<Path<T>, PathRejection>) -> Result<T, ApiError> {
    path.map(|Path(v)| v).map_err(|e| ApiError::Rejected(e.status(), e.body_text()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Pick {
        program: Option<u32>,
        feed: Option<f64>,
    }

    #[test]
    fn only_objects_are_taken() {
        for not_object in [serde_json::json!([null, null]), serde_json::json!(null), serde_json::json!(3)] {
            let refused = from_object::<Pick>(not_object.clone()).unwrap_err();
            assert_eq!(refused.status(), axum::http::StatusCode::UNPROCESSABLE_ENTITY, "{not_object}");
        }
        let taken: Pick = from_object(serde_json::json!({"program": 1})).unwrap();
        assert_eq!(taken, Pick { program: Some(1), feed: None });
    }

    #[test]
    fn whole_numbers_are_integers_and_fractions_stay() {
        let taken: Pick = from_object(serde_json::json!({"program": 6861.0, "feed": 2.5})).unwrap();
        assert_eq!(taken, Pick { program: Some(6861), feed: Some(2.5) });
        let refused = from_object::<Pick>(serde_json::json!({"program": 1.5})).unwrap_err();
        assert!(refused.to_string().contains("program"), "{refused}");
        let negative_zero: Value = {
            let mut v = serde_json::json!({"feed": -0.0});
            integers(&mut v);
            v
        };
        assert!(negative_zero["feed"].as_f64().unwrap().is_sign_negative());
    }

    #[test]
    fn unknown_fields_are_named() {
        let refused = from_object::<Pick>(serde_json::json!({"programme": 1})).unwrap_err();
        assert!(refused.to_string().contains("unknown field `programme`"), "{refused}");
    }
}
