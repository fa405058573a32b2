//! Manual operation: JOG and HANDLE of one axis or along a 5-axis manual feed (tool axis, its
//! right angles, table vertical and horizontal), tool tip centre rotation, reference return,
//! and the manual settings (jog feed, manual absolute, Syntec R518/R519).

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use fivex_engine::controller::ManualCoordinates;
use fivex_engine::kin::ManualFeed;
use serde::Deserialize;
use utoipa::ToSchema;

use super::panel::{command, status_after};
use super::ControllerStatus;
use crate::http::extract::{body, hosted, path};
use crate::http::extract::{Bodyless, JsonBody};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::panel::{self, Applied, ManualTarget, PanelCommand};

/// What a JOG or HANDLE move moves: exactly one of `axis`, `feed`, `tip_rotation`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ManualMove {
    /// One axis by its letter.
    #[schema(example = "X", pattern = r"^[ \t\n\r]*[A-Za-z][ \t\n\r]*$")]
    pub axis: Option<String>,
    /// A 5-axis manual feed: `tool-axis`, `right-angle1`, `right-angle2`, `table-vertical`,
    /// `table-horizontal1`, `table-horizontal2`.
    pub feed: Option<ManualFeed>,
    /// Tool tip centre rotation: the rotary axis to turn while X/Y/Z keep the tip in place.
    #[schema(example = "B", pattern = r"^[ \t\n\r]*[A-Za-z][ \t\n\r]*$")]
    pub tip_rotation: Option<String>,
    /// JOG: the direction (`true`: +).
    pub positive: Option<bool>,
    /// HANDLE: the distance, mm or degrees (the hand wheel's pulses times its increment).
    pub amount: Option<f64>,
}

/// JOG: move until `jog-stop` (or a stroke limit) at the jog feed, in JOG mode.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/jog",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = ManualMove,
    responses(
        (status = 200, description = "Moving", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not in JOG mode, busy, or no such axis or feed on this machine", body = ErrorBody),
        (status = 422, description = "Not a JOG request", body = ErrorBody),
    )
)]
pub async fn jog(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    request: Result<JsonBody<ManualMove>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let hosted = hosted(&state, &path(id)?)?;
    let request = body(request)?;
    let target = target(&request)?;
    let positive =
        request.positive.ok_or_else(|| ApiError::Unprocessable("JOG needs positive: true or false".into(), None))?;
    status_after(&state, &hosted, PanelCommand::Jog { target, positive })
}

/// Stop a JOG move (decelerating along its path).
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/jog-stop",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Stopping", body = ControllerStatus),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn jog_stop(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    _: Bodyless,
) -> Result<Json<ControllerStatus>, ApiError> {
    let hosted = hosted(&state, &path(id)?)?;
    status_after(&state, &hosted, PanelCommand::JogStop)
}

/// HANDLE: move by `amount` (stopping at the strokes), in HANDLE mode.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/handle",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = ManualMove,
    responses(
        (status = 200, description = "Moving", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not in HANDLE mode, busy, or no such axis or feed on this machine", body = ErrorBody),
        (status = 422, description = "Not a HANDLE request", body = ErrorBody),
    )
)]
pub async fn handle(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    request: Result<JsonBody<ManualMove>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let hosted = hosted(&state, &path(id)?)?;
    let request = body(request)?;
    let target = target(&request)?;
    // A missing amount is refused as an amount out of range is (`PanelCommand::check`).
    let amount = request.amount.unwrap_or(f64::NAN);
    status_after(&state, &hosted, PanelCommand::Handle { target, amount })
}

/// What a manual move request moves.
fn target(m: &ManualMove) -> Result<ManualTarget, ApiError> {
    Ok(ManualTarget::of(m.axis.as_deref(), m.feed, m.tip_rotation.as_deref())?)
}

/// Every axis back to the reference position, in REF mode.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/reference-return",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Returning", body = ControllerStatus),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not in REF mode or busy", body = ErrorBody),
    )
)]
pub async fn reference_return(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    _: Bodyless,
) -> Result<Json<ControllerStatus>, ApiError> {
    status_after(&state, &hosted, PanelCommand::ReferenceReturn)
}

/// `PUT /manual`: the manual settings to change.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ManualSettings {
    /// JOG and HANDLE feed, mm/min (or °/min).
    #[schema(exclusive_minimum = 0.0, maximum = 1.0e6)]
    pub jog_feed: Option<f64>,
    /// Manual absolute (FANUC *ABSM = 0): after an intervention the program goes back to its
    /// programmed points; off: later points shift by the intervention.
    pub manual_absolute: Option<bool>,
    /// Syntec R518: `machine`, `program` or `tool` coordinates for manual X/Y/Z.
    #[schema(value_type = Option<fivex_engine::controller::ManualCoordinates>, example = "program")]
    pub coordinates: Option<ManualCoordinates>,
    /// Syntec R519: manual rotary moves under TCP keep the tool tip.
    pub rtcp: Option<bool>,
    /// INC mode: the distance of one key press, mm or degrees (FANUC ×1/×10/×100/×1000:
    /// 0.001/0.01/0.1/1).
    #[schema(exclusive_minimum = 0.0, maximum = 1000.0)]
    pub increment: Option<f64>,
}

/// Jog feed, INC increment, manual absolute, and Syntec's manual RTCP settings (R518, R519).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/manual",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = ManualSettings,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Something moves", body = ErrorBody),
        (status = 422, description = "Out of range", body = ErrorBody),
    )
)]
pub async fn settings(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<ManualSettings>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let ManualSettings { jog_feed, manual_absolute, coordinates, rtcp, increment } = body(request)?;
    let command = PanelCommand::ManualSettings { coordinates, rtcp, jog_feed, manual_absolute, increment };
    status_after(&state, &hosted, command)
}

/// FANUC's 5-axis manual feed signals (`PUT /manual-signals`): the feed mode signals and the
/// first handle's axis select code (`docs/five-axis.md`, 5-axis manual operation). Omitted
/// fields keep their value.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, serde::Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct PanelSignals {
    /// Tool axis direction feed mode (ALNGH).
    pub alngh: Option<bool>,
    /// Tool axis right-angle direction feed mode (RGHTH).
    pub rghth: Option<bool>,
    /// Tool tip centre rotation feed mode (RNDH).
    pub rndh: Option<bool>,
    /// Table base (TB_BASE): ALNGH / RGHTH choose the table vertical / horizontal feeds.
    pub tb_base: Option<bool>,
    /// The handle's axis select code HS1A–HS1E (0–31): an axis number (1 = first axis) or one
    /// of the codes in No.12310–12314; 0 selects nothing.
    #[schema(maximum = 31)]
    pub handle_select: Option<u8>,
}

/// Sets the panel signals that choose what the JOG keys and the handle move (FANUC MAN-05…17).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/manual-signals",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = PanelSignals,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Something moves", body = ErrorBody),
        (status = 422, description = "A select code above 31", body = ErrorBody),
    )
)]
pub async fn set_signals(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<PanelSignals>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let PanelSignals { alngh, rghth, rndh, tb_base, handle_select } = body(request)?;
    status_after(&state, &hosted, PanelCommand::ManualSignals { alngh, rghth, rndh, tb_base, handle_select })
}

/// `POST /jog-signal`: a ±J key of the panel.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct JogSignal {
    /// The axis whose key is pressed (`Z` is ±J3 on an X Y Z … machine).
    #[schema(example = "Z", pattern = r"^[ \t\n\r]*[A-Za-z][ \t\n\r]*$")]
    pub axis: String,
    pub positive: bool,
}

/// JOG by the panel's ±J key: the 5-axis feed the signals select for that key (FANUC No.19697
/// decides which key drives the tool-axis feed), or the axis alone; moves until `jog-stop`.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/jog-signal",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = JogSignal,
    responses(
        (status = 200, description = "Moving", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not in JOG mode, busy, or no such axis", body = ErrorBody),
        (status = 422, description = "Not an axis letter", body = ErrorBody),
    )
)]
pub async fn jog_signal(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<JogSignal>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    let axis = panel::letter(&request.axis)?;
    status_after(&state, &hosted, PanelCommand::JogSignal { axis, positive: request.positive })
}

/// `POST /handle-pulses`: what the hand wheel turned.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct HandlePulses {
    /// Pulses times the increment, mm or degrees (signed).
    #[schema(minimum = -1.0e5, maximum = 1.0e5)]
    pub amount: f64,
}

/// The answer to handle pulses: how much of them the machine takes, and the status.
#[derive(Debug, Clone, serde::Serialize, ToSchema)]
pub struct HandleTaken {
    /// The amount taken: 0 when the pulses are discarded (the select code chooses nothing, or
    /// the earlier pulses are still moving: the handle turned faster than the clamp allows).
    pub taken: f64,
    pub status: ControllerStatus,
}

/// HANDLE by the panel: the handle's select code and the signals choose what moves (FANUC
/// MAN-05/07/11/14/16), clamped by the manual rapid rates.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/handle-pulses",
    tag = "manual",
    params(("id" = String, Path, description = "Controller id")),
    request_body = HandlePulses,
    responses(
        (status = 200, description = "Taken (maybe 0)", body = HandleTaken),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not in HANDLE mode", body = ErrorBody),
        (status = 422, description = "Not a finite amount (at most 1e5)", body = ErrorBody),
    )
)]
pub async fn handle_pulses(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<HandlePulses>, ApiError>,
) -> Result<Json<HandleTaken>, ApiError> {
    let amount = body(request)?.amount;
    match command(&state, &hosted, PanelCommand::HandlePulses { amount })? {
        (Applied::Taken(taken), Json(status)) => Ok(Json(HandleTaken { taken, status })),
        (Applied::Done, Json(status)) => Ok(Json(HandleTaken { taken: 0.0, status })),
    }
}
