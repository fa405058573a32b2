//! Creating, listing, configuring and removing controllers.

use crate::http::extract::Addressed;

use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use axum::http::StatusCode;
use fivex_engine::machine::MachineConfig;
use serde::Deserialize;
use utoipa::ToSchema;

use super::ControllerStatus;
use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::controllers::{self, NewController};

/// `POST /controllers`: a name, and the machine as a preset name or a machine document (a model
/// or a vendor parameter list, as `--machine FILE.json` takes).
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CreateController {
    #[schema(example = "cell 1", min_length = 1, max_length = 200, pattern = r"^[^\u0000-\u001F\u007F-\u009F]*$")]
    pub name: String,
    /// A built-in preset (`mill3`, `head-bc`, `table-ac`, `table-bc`, `mixed-bc`).
    #[schema(example = "table-ac")]
    pub preset: Option<String>,
    /// A machine document instead of a preset (`docs/machine-config.md`).
    #[schema(value_type = Option<crate::wire::MachineDocument>)]
    pub machine: Option<serde_json::Value>,
    /// `fanuc` (default), `syntec` or `haas` (Haas NGC mill).
    #[schema(example = "fanuc")]
    pub dialect: Option<String>,
    /// Simulated seconds per real second (default 1; up to 1000).
    #[schema(exclusive_minimum = 0.0, maximum = 1000.0)]
    pub speed: Option<f64>,
    /// What is clamped on its table, the boxes a G31 probe touches (default: nothing; as
    /// `PUT /controllers/{id}/workpiece` takes it).
    pub workpiece: Option<fivex_engine::workpiece::Workpiece>,
}

/// `PATCH /controllers/{id}`: what may change on a controller that exists.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct UpdateController {
    #[schema(min_length = 1, max_length = 200, pattern = r"^[^\u0000-\u001F\u007F-\u009F]*$")]
    pub name: Option<String>,
    #[schema(exclusive_minimum = 0.0, maximum = 1000.0)]
    pub speed: Option<f64>,
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
        (status = 422, description = "Not a valid controller (name, preset, machine, dialect, speed, workpiece)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn create(
    State(state): State<AppState>,
    request: Result<JsonBody<CreateController>, ApiError>,
) -> Result<(StatusCode, Json<ControllerStatus>), ApiError> {
    let request = body(request)?;
    let new = NewController {
        name: request.name,
        preset: request.preset,
        machine: request.machine,
        dialect: request.dialect,
        speed: request.speed,
        workpiece: request.workpiece,
    };
    let hosted = controllers::create(&state.db, &state.host, new).await?;
    place(&state, &hosted.id).await;
    Ok((StatusCode::CREATED, Json(ControllerStatus::now(&hosted))))
}

/// Every controller with its status, oldest first; in a cluster of nodes, those of every
/// member (each asked over NATS).
#[utoipa::path(
    get,
    path = "/api/v1/controllers",
    tag = "controllers",
    responses(
        (status = 200, description = "Every controller (in a cluster: every controller each member hosts)", body = [ControllerStatus]),
        (status = 503, description = "In a cluster (docs/cluster.md): a member did not list its controllers", body = ErrorBody),
    )
)]
pub async fn list(
    State(state): State<AppState>,
    headers: axum::http::HeaderMap,
) -> Result<Json<Vec<ControllerStatus>>, ApiError> {
    let mut all: Vec<ControllerStatus> = state.host.list().iter().map(|h| ControllerStatus::now(h)).collect();
    // In a cluster (`crate::placement`), each other member answers for what it hosts.
    if let Some(cluster) = state.cluster.as_ref().filter(|_| !headers.contains_key(crate::placement::FORWARDED)) {
        let uri: axum::http::Uri = "/api/v1/controllers".parse().expect("a path");
        for node in cluster.members().into_iter().filter(|n| n != cluster.name()) {
            let answer = cluster.send(&node, &axum::http::Method::GET, &uri, &headers, Default::default()).await;
            let status = answer.status();
            let body = axum::body::to_bytes(answer.into_body(), usize::MAX).await.unwrap_or_default();
            match serde_json::from_slice::<Vec<ControllerStatus>>(&body) {
                Ok(theirs) if status.is_success() => all.extend(theirs),
                _ => {
                    return Err(ApiError::Unavailable(format!(
                        "node {node} did not list its controllers ({status}): the list would be incomplete"
                    )))
                }
            }
        }
        all.sort_by(|a, b| (&a.created_at, &a.id).cmp(&(&b.created_at, &b.id)));
    }
    Ok(Json(all))
}

/// In a cluster, a controller made here is placed here (a failure is logged: the node places
/// it at its next beat).
async fn place(state: &AppState, id: &str) {
    if let Some(cluster) = &state.cluster {
        if let Err(e) = cluster.place(id).await {
            tracing::warn!(%id, error = %e, "new controller not placed yet");
        }
    }
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
    controllers::update(&state.db, &hosted, request.name.as_deref(), request.speed).await?;
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
    controllers::remove(&state.db, &state.host, &hosted).await?;
    if let Some(cluster) = &state.cluster {
        cluster.forget(&hosted.id).await;
    }
    Ok(StatusCode::NO_CONTENT)
}

/// `POST /controllers/{id}/clone`: the new controller's name.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CloneController {
    #[schema(
        example = "cell 1 (copy)",
        min_length = 1,
        max_length = 200,
        pattern = r"^[^\u0000-\u001F\u007F-\u009F]*$"
    )]
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
    let name = body(request)?.name;
    let hosted = controllers::clone(&state.db, &state.host, &source, &name).await?;
    place(&state, &hosted.id).await;
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
    Ok(Json(machine.config().clone()))
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
