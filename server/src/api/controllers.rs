//! Creating, listing, configuring and removing controllers.

use crate::http::extract::Addressed;
use std::sync::Arc;

use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use axum::http::StatusCode;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use serde::Deserialize;
use utoipa::ToSchema;

use crate::http::extract::JsonBody;
use super::ControllerStatus;
use crate::http::extract::{body, hosted, path};
use crate::db::{self, ControllerRow};
use crate::host::{now_rfc3339, Hosted, Spec, MAX_SPEED};
use crate::http::{ApiError, AppState, ErrorBody};

/// `POST /controllers`: a name, and the machine as a preset name or a machine document (a model
/// or a vendor parameter list, as `--machine FILE.json` takes).
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CreateController {
    #[schema(example = "cell 1", min_length = 1, max_length = 200)]
    pub name: String,
    /// A built-in preset (`mill3`, `head-bc`, `table-ac`, `table-bc`, `mixed-bc`).
    #[schema(example = "table-ac")]
    pub preset: Option<String>,
    /// A machine document instead of a preset (`docs/machine-config.md`).
    #[schema(value_type = Option<crate::wire::MachineDocument>)]
    pub machine: Option<serde_json::Value>,
    /// `fanuc` (default) or `syntec`.
    #[schema(example = "fanuc")]
    pub dialect: Option<String>,
    /// Simulated seconds per real second (default 1; up to 1000).
    #[schema(exclusive_minimum = 0.0, maximum = 1000.0)]
    pub speed: Option<f64>,
}

/// `PATCH /controllers/{id}`: what may change on a controller that exists.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct UpdateController {
    #[schema(min_length = 1, max_length = 200)]
    pub name: Option<String>,
    #[schema(exclusive_minimum = 0.0, maximum = 1000.0)]
    pub speed: Option<f64>,
}

fn check_name(name: &str) -> Result<String, ApiError> {
    let name = name.trim();
    if name.is_empty() || name.chars().count() > 200 {
        return Err(ApiError::Unprocessable("name must have 1 to 200 characters".into(), None));
    }
    Ok(name.to_string())
}

fn check_speed(speed: f64) -> Result<f64, ApiError> {
    if !(speed.is_finite() && speed > 0.0 && speed <= MAX_SPEED) {
        return Err(ApiError::Unprocessable(format!("speed must be above 0 and at most {MAX_SPEED}"), None));
    }
    Ok(speed)
}

fn machine_of(request: &CreateController) -> Result<MachineConfig, ApiError> {
    let bad = |why: String| ApiError::Unprocessable(why, None);
    match (&request.preset, &request.machine) {
        (Some(preset), None) => MachineConfig::preset(preset)
            .ok_or_else(|| bad(format!("unknown preset '{preset}' ({})", MachineConfig::PRESETS.join(", ")))),
        (None, Some(machine)) => fivex_engine::machine_file::parse(&machine.to_string()).map_err(bad),
        _ => Err(bad("give exactly one of preset and machine".into())),
    }
}

/// Creates a controller in reset state (AUTO, idle) and keeps it in the database.
#[utoipa::path(
    post,
    path = "/api/v1/controllers",
    tag = "controllers",
    request_body = CreateController,
    responses(
        (status = 201, description = "Created", body = ControllerStatus),
        (status = 400, description = "Not JSON", body = ErrorBody),
        (status = 422, description = "Not a valid controller (name, preset, machine, dialect, speed)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn create(
    State(state): State<AppState>,
    request: Result<JsonBody<CreateController>, ApiError>,
) -> Result<(StatusCode, Json<ControllerStatus>), ApiError> {
    let request = body(request)?;
    let name = check_name(&request.name)?;
    let machine = machine_of(&request)?;
    // A parameter list gives its own dialect unless the request names one.
    let given: Option<fivex_engine::vendor::ParamFile> = request
        .machine
        .as_ref()
        .filter(|m| m.get("parameters").is_some())
        .and_then(|m| serde_json::from_value(m.clone()).ok());
    let dialect: Dialect = match (&request.dialect, &given) {
        (Some(d), _) => d.parse().map_err(|e: String| ApiError::Unprocessable(e, None))?,
        (None, Some(file)) => file.dialect,
        (None, None) => Dialect::Fanuc,
    };
    let extra = match &given {
        Some(file) if file.dialect == dialect => super::parameters::extras(dialect, &machine, &file.parameters),
        _ => Default::default(),
    };
    let speed = check_speed(request.speed.unwrap_or(1.0))?;
    let row = ControllerRow {
        id: uuid::Uuid::new_v4().simple().to_string(),
        name: name.clone(),
        dialect: dialect.name().to_string(),
        machine_json: serde_json::to_string(&machine).map_err(|e| ApiError::Unprocessable(e.to_string(), None))?,
        created_at: now_rfc3339(),
    };
    let extra_json = serde_json::to_string(&extra).unwrap_or_else(|_| "{}".into());
    db::insert_controller_with(&state.db, &row, speed, &extra_json).await?;
    let machine_name = machine.name.clone();
    let hosted = Arc::new(Hosted::new(Spec {
        id: row.id.clone(),
        name,
        dialect,
        machine,
        created_at: row.created_at.clone(),
        speed,
    }));
    {
        let mut station = hosted.station();
        // Everything the request's document sets that fivex does not carry out (its unknown
        // fields too, which the stored model no longer holds).
        station.unmodelled = match &request.machine {
            Some(doc) => fivex_engine::machine_file::unmodelled(&doc.to_string()),
            None => super::parameters::unmodelled(dialect, &station.machine, &extra),
        };
        station.extra_parameters = extra;
    }
    state.host.add(hosted.clone());
    tracing::info!(id = %row.id, name = %row.name, machine = %machine_name, "controller created");
    Ok((StatusCode::CREATED, Json(ControllerStatus::now(&hosted))))
}

/// Every controller with its status, oldest first.
#[utoipa::path(
    get,
    path = "/api/v1/controllers",
    tag = "controllers",
    responses(
        (status = 200, description = "Every controller", body = [ControllerStatus]),
    )
)]
pub async fn list(State(state): State<AppState>) -> Json<Vec<ControllerStatus>> {
    Json(state.host.list().iter().map(|h| ControllerStatus::now(h)).collect())
}

/// One controller's status: mode, run state, position, alarms, program and line.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "The controller", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn status(Addressed(hosted): Addressed) -> Result<Json<ControllerStatus>, ApiError> {
    Ok(Json(ControllerStatus::now(&hosted)))
}

/// Renames a controller or changes its speed factor.
#[utoipa::path(
    patch,
    path = "/api/v1/controllers/{id}",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    request_body = UpdateController,
    responses(
        (status = 200, description = "Changed", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "Invalid name or speed", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn update(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<UpdateController>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    let name = match &request.name {
        Some(n) => check_name(n)?,
        None => hosted.name(),
    };
    let speed = match request.speed {
        Some(s) => check_speed(s)?,
        None => hosted.speed(),
    };
    db::update_controller(&state.db, &hosted.id, &name, speed).await?;
    hosted.rename(name);
    hosted.set_speed(speed);
    Ok(Json(ControllerStatus::now(&hosted)))
}

/// Removes a controller with its programs, variables and history; its websocket streams close
/// at once with code 4404 "controller deleted".
#[utoipa::path(
    delete,
    path = "/api/v1/controllers/{id}",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 204, description = "Removed"),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn remove(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
) -> Result<StatusCode, ApiError> {
    let id = path(id)?;
    let hosted = hosted(&state, &id)?;
    db::delete_controller(&state.db, &hosted.id).await?;
    state.host.remove(&id);
    tracing::info!(%id, "controller removed");
    Ok(StatusCode::NO_CONTENT)
}

/// `POST /controllers/{id}/clone`: the new controller's name.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CloneController {
    #[schema(example = "cell 1 (copy)", min_length = 1, max_length = 200)]
    pub name: String,
}

/// A new controller with the same machine, dialect, speed, parameters, stored programs,
/// retained variables and tool and work offsets as this one (as stored; not its history), in
/// reset state.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/clone",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    request_body = CloneController,
    responses(
        (status = 201, description = "Created", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "Invalid name", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn clone(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    request: Result<JsonBody<CloneController>, ApiError>,
) -> Result<(StatusCode, Json<ControllerStatus>), ApiError> {
    let source = hosted(&state, &path(id)?)?;
    let name = check_name(&body(request)?.name)?;
    let id = uuid::Uuid::new_v4().simple().to_string();
    if !db::clone_controller(&state.db, &source.id, &id, &name, &now_rfc3339()).await? {
        return Err(ApiError::NotFound(format!("no controller {}", source.id)));
    }
    let row = db::controller(&state.db, &id).await?.ok_or_else(|| ApiError::NotFound(format!("no controller {id}")))?;
    let settings = db::controller_settings(&state.db).await?;
    let Some(hosted) = crate::service::controllers::load(&state.db, row, &settings).await? else {
        db::delete_controller(&state.db, &id).await?;
        return Err(ApiError::Unprocessable("the source controller's machine cannot be loaded".into(), None));
    };
    let hosted = Arc::new(hosted);
    state.host.add(hosted.clone());
    tracing::info!(%id, from = %source.id, "controller cloned");
    Ok((StatusCode::CREATED, Json(ControllerStatus::now(&hosted))))
}

/// The controller's machine as a model document (`docs/machine-config.md`): axes, strokes and
/// the kinematic chain, as the dashboard draws it.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/machine",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "The machine model", body = MachineConfig),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn machine(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<MachineConfig>, ApiError> {
    let hosted = hosted(&state, &path(id)?)?;
    let machine = hosted.station().machine.clone();
    Ok(Json((*machine).clone()))
}

/// A built-in machine preset.
#[derive(Debug, Clone, serde::Serialize, ToSchema)]
pub struct Preset {
    #[schema(example = "head-bc")]
    pub name: String,
    /// The mechanism, as [`ControllerStatus::kind`] names it.
    #[schema(value_type = crate::wire::words::MechanismName)]
    pub kind: String,
    /// The axis letters in order.
    pub axes: Vec<String>,
}

/// The machine presets `POST /controllers` takes by name.
#[utoipa::path(
    get,
    path = "/api/v1/presets",
    tag = "controllers",
    responses(
        (status = 200, description = "Every preset", body = [Preset]),
    )
)]
pub async fn presets() -> Json<Vec<Preset>> {
    Json(
        MachineConfig::PRESETS
            .iter()
            .filter_map(|name| MachineConfig::preset(name))
            .map(|m| Preset {
                kind: super::machine_kind(&m),
                axes: m.axes.iter().map(|a| a.name.to_string()).collect(),
                name: m.name,
            })
            .collect(),
    )
}
