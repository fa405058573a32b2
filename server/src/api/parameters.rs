//! The machine as a parameter list in the controller's dialect (FANUC No.1020…, Syntec Pr21…),
//! and changing one parameter, which puts a new machine under the controller as a power cycle
//! would.

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use fivex_engine::controller::RunState;
use fivex_engine::vendor::{self, Params, Value as ParamValue};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::db;
use crate::http::{ApiError, AppState, ErrorBody};

/// A controller's parameters.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct ParameterList {
    /// `fanuc` or `syntec`: whose numbering.
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

/// The dialect's list: the model's canonical parameters and, for the numbers the model does not
/// write, the extra ones kept as given.
fn list(
    dialect: fivex_engine::Dialect,
    machine: &fivex_engine::machine::MachineConfig,
    extra: &Params,
) -> Result<ParameterList, ApiError> {
    let mut parameters = vendor::params_of(dialect, machine).map_err(|e| {
        ApiError::Conflict(format!("this machine has no {} parameter form: {}", dialect.name(), e.describe(dialect)))
    })?;
    for (number, value) in &extra.0 {
        parameters.0.entry(*number).or_insert_with(|| value.clone());
    }
    let unmodelled = super::UnmodelledParameter::list(&vendor::unmodelled::of_params(dialect, &parameters));
    Ok(ParameterList { dialect: dialect.name().to_string(), parameters, unmodelled_parameters: unmodelled })
}

/// What of the controller's machine (its model and the extra parameters kept beside it) fivex
/// does not carry out: of the dialect's list when the machine has one, else of the model.
pub fn unmodelled(
    dialect: fivex_engine::Dialect,
    machine: &fivex_engine::machine::MachineConfig,
    extra: &Params,
) -> Vec<vendor::unmodelled::Unmodelled> {
    match list(dialect, machine, extra) {
        Ok(l) => vendor::unmodelled::of_params(dialect, &l.parameters),
        Err(_) => vendor::unmodelled::of_model(machine),
    }
}

/// What of `given` the model of `machine` does not write back: a control keeps every parameter it
/// is given, so these are stored beside the machine and shown with it.
pub fn extras(
    dialect: fivex_engine::Dialect,
    machine: &fivex_engine::machine::MachineConfig,
    given: &Params,
) -> Params {
    let canonical = vendor::params_of(dialect, machine).unwrap_or_default();
    Params(given.0.iter().filter(|(n, _)| !canonical.0.contains_key(n)).map(|(n, v)| (*n, v.clone())).collect())
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
    let station = hosted.station();
    Ok(Json(list(hosted.dialect, &station.machine, &station.extra_parameters)?))
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
    let finite = match &value {
        ParamValue::One(x) => x.is_finite(),
        ParamValue::PerAxis(v) => v.iter().all(|x| x.is_finite()),
    };
    if !finite {
        return Err(ApiError::Unprocessable("parameter values must be finite numbers".into(), None));
    }
    let (current, extra) = {
        let station = hosted.station();
        (station.machine.clone(), station.extra_parameters.clone())
    };
    let mut parameters = list(hosted.dialect, &current, &extra)?.parameters;
    parameters.0.insert(number, value);
    let machine = vendor::machine_from(hosted.dialect, &current.name, &parameters)
        .map_err(|e| ApiError::Unprocessable(e.describe(hosted.dialect), None))?;
    let json = serde_json::to_string(&machine).map_err(|e| ApiError::Unprocessable(e.to_string(), None))?;
    if hosted.station().controller.run_state() != RunState::Idle {
        return Err(ApiError::Conflict("parameters change only while nothing runs".into()));
    }
    let extra = extras(hosted.dialect, &machine, &parameters);
    let extra_json = serde_json::to_string(&extra).unwrap_or_else(|_| "{}".into());
    db::update_machine(&state.db, &hosted.id, &json, &extra_json).await?;
    let answer = list(hosted.dialect, &machine, &extra)?;
    let mut station = hosted.station();
    station.replace_machine(machine, hosted.dialect);
    station.unmodelled = answer
        .unmodelled_parameters
        .iter()
        .map(|u| vendor::unmodelled::Unmodelled { parameter: u.parameter.clone(), reason: u.reason.clone() })
        .collect();
    station.extra_parameters = extra;
    tracing::info!(id = %hosted.id, number, "parameter changed; controller restarted on the new machine");
    Ok(Json(answer))
}
