//! The operator panel: cycle start, feed hold, reset, MDI, mode, overrides, switches and the
//! emergency stop: each a [`PanelCommand`] (`service::panel`) that answers the controller's
//! status after it; an action the panel would ignore in this state is 409 with the reason.

use crate::http::extract::Addressed;
use axum::extract::{Json, State};
use serde::Deserialize;
use utoipa::ToSchema;

use super::ControllerStatus;
use crate::host::Hosted;
use crate::http::extract::body;
use crate::http::extract::{Bodyless, JsonBody};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::panel::{self, Applied, PanelCommand, Switches};
use crate::service::programs;

/// Applies `command` to the controller and answers its status after it (`service::panel`).
pub(super) fn command(
    state: &AppState,
    hosted: &Hosted,
    command: PanelCommand,
) -> Result<(Applied, Json<ControllerStatus>), ApiError> {
    let (applied, status) = panel::execute(&state.host, hosted, command, ControllerStatus::of)?;
    Ok((applied, Json(status)))
}

/// [`command`] when only the status is answered.
pub(super) fn status_after(
    state: &AppState,
    hosted: &Hosted,
    action: PanelCommand,
) -> Result<Json<ControllerStatus>, ApiError> {
    command(state, hosted, action).map(|(_, status)| status)
}

/// `POST /cycle-start`: optionally the stored program to run.
#[derive(Debug, Clone, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CycleStart {
    /// O number of a stored program: selected and started in AUTO. Omitted: resume after a
    /// feed hold or stop, or run the program already selected.
    pub program: Option<u32>,
}

/// An optional JSON body: none (or only white space, whatever the content type says) is the
/// default. Malformed JSON is 400, JSON of the wrong shape 422, as for a `Json` body.
fn optional_json<T: serde::de::DeserializeOwned + Default>(body: &[u8]) -> Result<T, ApiError> {
    if body.iter().all(u8::is_ascii_whitespace) {
        return Ok(T::default());
    }
    let value: serde_json::Value = serde_json::from_slice(body)
        .map_err(|e| ApiError::Rejected(axum::http::StatusCode::BAD_REQUEST, format!("the request body: {e}")))?;
    // `null` is no body too (the document's optional body).
    if value.is_null() {
        return Ok(T::default());
    }
    crate::http::extract::from_object(value)
}

/// Cycle start: with `program`, select that stored program and run it in AUTO; without, resume
/// (feed hold, M00/M01, single block) or run what is selected.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/cycle-start",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body(content = Option<CycleStart>, description = "Optional; an empty body resumes"),
    responses(
        (status = 200, description = "Started", body = ControllerStatus),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 409, description = "Not possible now (running another program, alarm, wrong mode)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn cycle_start(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    body: axum::body::Bytes,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = optional_json::<CycleStart>(&body)?;
    let program = match request.program {
        Some(n) => Some((n, programs::composed(&state.db, &hosted, n).await?)),
        None => None,
    };
    if let Some((_, composed)) = &program {
        // Begun (or found) before the start, from the state the run starts in: the run's
        // progress reads it under the same key.
        crate::host::estimate::ensure(&hosted, composed.clone());
    }
    status_after(&state, &hosted, PanelCommand::CycleStart { program })
}

/// Feed hold: decelerate along the path and wait for cycle start.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/feed-hold",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Holding (or nothing was running)", body = ControllerStatus),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn feed_hold(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    _: Bodyless,
) -> Result<Json<ControllerStatus>, ApiError> {
    status_after(&state, &hosted, PanelCommand::FeedHold)
}

/// Reset: stop, abandon the program, clear the alarms.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/reset",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Reset", body = ControllerStatus),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn reset(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    _: Bodyless,
) -> Result<Json<ControllerStatus>, ApiError> {
    status_after(&state, &hosted, PanelCommand::Reset)
}

/// `POST /mdi`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Mdi {
    /// NC blocks to run.
    #[schema(example = "G91 G01 X10. F100")]
    pub text: String,
}

/// MDI: switch to MDI mode (when idle) and run the blocks. They may call the stored programs
/// (`M98 P1`, `G65 P1`), as an MDI program calls programs in memory on the control.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/mdi",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = Mdi,
    responses(
        (status = 200, description = "Running", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Busy or in alarm", body = ErrorBody),
        (status = 422, description = "Not an MDI request, or a text with a NUL", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn mdi(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Mdi>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let text = body(request)?.text;
    programs::no_nul(&text)?;
    let stored = programs::all(&state.db, &hosted).await?;
    status_after(&state, &hosted, PanelCommand::Mdi { text, stored })
}

/// `PUT /mode`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetMode {
    /// `auto`, `mdi`, `jog`, `handle`, `ref` or `inc`.
    #[schema(example = "jog", value_type = fivex_engine::controller::Mode)]
    pub mode: String,
}

/// Select the mode (only while nothing runs or holds).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/mode",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = SetMode,
    responses(
        (status = 200, description = "Mode selected", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Busy", body = ErrorBody),
        (status = 422, description = "Unknown mode", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn set_mode(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<SetMode>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let mode = panel::mode(&body(request)?.mode)?;
    status_after(&state, &hosted, PanelCommand::SetMode { mode })
}

/// `PUT /overrides`, percent.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Overrides {
    /// Feed override, 0–200 %.
    #[schema(minimum = 0.0, maximum = 200.0)]
    pub feed: Option<f64>,
    /// Rapid override, 0–100 %.
    #[schema(minimum = 0.0, maximum = 100.0)]
    pub rapid: Option<f64>,
    /// Spindle speed override, 50–120 % in steps of 10.
    #[schema(minimum = 50.0, maximum = 120.0, multiple_of = 10.0)]
    pub spindle: Option<f64>,
}

/// Feed, rapid and spindle override; the motion under way changes speed at once within the
/// limits, the spindle at once.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/overrides",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = Overrides,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "Out of range", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn set_overrides(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Overrides>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let Overrides { feed, rapid, spindle } = body(request)?;
    status_after(&state, &hosted, PanelCommand::Overrides { feed, rapid, spindle })
}

/// Single block, optional stop (M01), block delete (`/`), dry run, machine lock, Z-axis
/// neglect and auxiliary function lock (`docs/dialects.md`, "The operator's switches and
/// counters"). Refused with 409 (nothing changed) when dry run, machine lock or Z-axis neglect
/// would change while the axes move or a held path waits, or Z-axis neglect where the dialect
/// or the machine has none.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/switches",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = Switches,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not now (the axes move or a path waits), or no Z-axis neglect here", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn set_switches(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Switches>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    status_after(&state, &hosted, PanelCommand::Switches(body(request)?))
}

/// `PUT /emergency-stop`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct EmergencyStop {
    /// Pressed (stop every axis at once, alarm) or released.
    pub pressed: bool,
}

/// The emergency stop button; after releasing it a reset clears the alarm.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/emergency-stop",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = EmergencyStop,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 503, description = "In a cluster (docs/cluster.md): the controller is moving to another node; retry in a few seconds", body = ErrorBody),
    )
)]
pub async fn emergency_stop(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<EmergencyStop>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    status_after(&state, &hosted, PanelCommand::EmergencyStop { pressed: body(request)?.pressed })
}
