//! Macro variables: read any a program may read; write the common ones (#100–#199; not in the
//! Syntec dialect, where they are a program's locals: `service::settings::set_variable`) and the
//! retained ones (#500–#999, saved in the database before the answer).

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use fivex_engine::interp::expr::Variables;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::settings;

/// A variable and its value (`null`: vacant).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Variable {
    #[schema(example = 500)]
    pub number: u32,
    pub value: Option<f64>,
}

/// `PUT /variables/{number}`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetVariable {
    /// The new value, or `null` to make it vacant.
    pub value: Option<f64>,
}

/// Every common variable that is not vacant (#100–#199, #500–#999).
#[utoipa::path(
    get,
    operation_id = "list_variables",
    path = "/api/v1/controllers/{id}/variables",
    tag = "variables",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Non-vacant common variables", body = [Variable]),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn list(Addressed(hosted): Addressed) -> Result<Json<Vec<Variable>>, ApiError> {
    let values = hosted.station().controller.interpreter().state.common_variables();
    Ok(Json(values.into_iter().map(|(number, v)| Variable { number, value: Some(v) }).collect()))
}

/// One variable as a program would read it (system variables included).
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/variables/{number}",
    tag = "variables",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, description = "Variable number")),
    responses(
        (status = 200, description = "The value", body = Variable),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "No such variable", body = ErrorBody),
    )
)]
pub async fn read(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
) -> Result<Json<Variable>, ApiError> {
    let (id, number) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let value = hosted.station().controller.interpreter().state.read(number);
    let value = value.map_err(|e| {
        let (code, message) = hosted.dialect.describe(&e);
        ApiError::Unprocessable(format!("#{number}: {code} {message}"), None)
    })?;
    Ok(Json(Variable { number, value }))
}

/// Set a common (#100–#199, #100000–#199999) or retained (#500–#999, #500000–#999999)
/// variable, or an interface input signal (#1000–#1031 bits, #1032–#1035 groups: what the
/// machine's PLC would set); retained ones are in the database when this answers.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/variables/{number}",
    tag = "variables",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, description = "Variable number")),
    request_body = SetVariable,
    responses(
        (status = 200, description = "Set", body = Variable),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "Not a writable variable or not a finite number", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
        (status = 503, description = "The controller left this node while the request waited (deleted, or moving to another node: retry), the service is stopping, or the database writer did not store the change within 60 s (the value is set but may not be kept)", body = ErrorBody),
    )
)]
pub async fn write(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
    request: Result<JsonBody<SetVariable>, ApiError>,
) -> Result<Json<Variable>, ApiError> {
    let (id, number) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let value = body(request)?.value;
    settings::set_variable(&state.db, &state.host, &hosted, number, value).await?;
    Ok(Json(Variable { number, value }))
}
