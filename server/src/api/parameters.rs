//! The machine as a parameter list in the controller's dialect (FANUC No.1020…, Syntec Pr21…),
//! and changing one parameter, which puts a new machine under the controller as a power cycle
//! would.

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use fivex_engine::vendor::{Params, Value as ParamValue};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::parameters::{self, ParameterSet};

/// A controller's parameters.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct ParameterList {
    /// `fanuc`, `syntec` or `haas` (the NGC calls its list Settings): whose numbering.
    #[schema(value_type = fivex_engine::Dialect)]
    pub dialect: String,
    /// `{"1020": [88, 89, 90, 65, 67], "19680": 12, …}`: a number, or one per axis.
    pub parameters: Params,
    /// What of them fivex keeps but does not carry out (unread parameters and bits, settings
    /// without effect; `docs/machine-config.md`).
    pub unmodelled_parameters: Vec<super::UnmodelledParameter>,
}

/// `PUT /parameters/{number}`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetParameter {
    /// A number, or one number per axis for an axis-type parameter.
    pub value: ParamValue,
}

impl ParameterList {
    fn of(dialect: fivex_engine::Dialect, set: ParameterSet) -> ParameterList {
        ParameterList {
            dialect: dialect.name().to_string(),
            parameters: set.parameters,
            unmodelled_parameters: super::UnmodelledParameter::list(&set.unmodelled),
        }
    }
}

/// The machine as the dialect's parameter list (canonical form).
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/parameters",
    tag = "parameters",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Parameters", body = ParameterList),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "The machine cannot be written in this dialect's parameters", body = ErrorBody),
    )
)]
pub async fn get_all(Addressed(hosted): Addressed) -> Result<Json<ParameterList>, ApiError> {
    Ok(Json(ParameterList::of(hosted.dialect, parameters::of(&hosted)?)))
}

/// Change one parameter. The new set must describe a machine that works (else 422 with the
/// vendor's alarm); the controller then restarts on it in reset state (offsets and retained
/// variables kept). Only while nothing runs.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/parameters/{number}",
    tag = "parameters",
    params(("id" = String, Path, description = "Controller id"), ("number" = u64, Path, maximum = 4294967295_u64, description = "Parameter number")),
    request_body = SetParameter,
    responses(
        (status = 200, description = "Changed; the whole list after the change", body = ParameterList),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "A program runs or holds, or the machine has no parameter form", body = ErrorBody),
        (status = 422, description = "The set does not describe a working machine (the vendor's alarm)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn set(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
    request: Result<JsonBody<SetParameter>, ApiError>,
) -> Result<Json<ParameterList>, ApiError> {
    let (id, number) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let value = body(request)?.value;
    let set = parameters::set(&state.db, &hosted, number, value).await?;
    Ok(Json(ParameterList::of(hosted.dialect, set)))
}
