//! The one error type of the HTTP layer: every handler, extractor and middleware answers a
//! failure as an [`ApiError`], which renders as a JSON [`ErrorBody`] with a 4xx/5xx status.

use axum::http::{Method, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

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
        let mut response = (status, Json(body)).into_response();
        if matches!(self, ApiError::Database(_)) {
            // For the request layer's count (`/metrics`, `fivex_database_errors_total`).
            response.extensions_mut().insert(DatabaseFailed);
        }
        response
    }
}

/// Marks a response that answers a database error (500), for the request layer to count.
#[derive(Debug, Clone, Copy)]
pub struct DatabaseFailed;

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

impl From<crate::service::ServiceError> for ApiError {
    fn from(e: crate::service::ServiceError) -> ApiError {
        use crate::service::ServiceError;
        match e {
            ServiceError::NotFound(why) => ApiError::NotFound(why),
            ServiceError::Invalid(why, details) => ApiError::Unprocessable(why, details),
            ServiceError::Conflict(why) => ApiError::Conflict(why),
            ServiceError::Unavailable(why) => ApiError::Unavailable(why),
            ServiceError::Database(source) => ApiError::Database(source),
        }
    }
}
