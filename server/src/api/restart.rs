//! FANUC program restart (`docs/dialects.md`, "Program restart"): `POST /restart` searches the
//! program to the restart block without motion (a [`PanelCommand::Restart`]); the next cycle
//! start returns the axes and goes on from it. The status shows the restart under way
//! ([`RestartInfo`]).

use axum::extract::{Json, State};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::ToSchema;

use super::ControllerStatus;
use crate::host::stream::axes;
use crate::host::Station;
use crate::http::extract::{body, Addressed, JsonBody};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::panel::{self, PanelCommand, RestartAt};
use crate::service::programs;
use fivex_engine::canon::{CanonKind, SpindleState};
use fivex_engine::controller::{RestartPhase, RestartType};

/// `POST /restart`: the restart block by its sequence number `n` or its `line` (one of them).
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RestartRequest {
    /// O number of a stored program: selected in AUTO and searched. Omitted: the program
    /// selected (the one AUTO last ran).
    pub program: Option<u32>,
    /// `p` (after a broken tool: the interrupted run's coordinates) or `q` (after a power-off or
    /// an emergency stop: the machine stands at the program's start point).
    #[serde(rename = "type")]
    #[schema(example = "p", value_type = fivex_engine::controller::RestartType)]
    pub kind: String,
    /// The restart block's sequence number (1–99999999).
    pub n: Option<u32>,
    /// Or its 1-based line in the program's text.
    pub line: Option<u32>,
    /// The how-many-th time execution reaches the block (a block in a loop); 1 when left out.
    pub occurrence: Option<u32>,
}

/// A program restart under way, in the status.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct RestartInfo {
    /// `p` or `q`.
    #[serde(rename = "type")]
    pub kind: RestartType,
    /// `searching` (the search runs over the controller's ticks, `run_state` `running`; a
    /// reset stops it), `searched` (cycle start returns the axes) or `returning`.
    pub phase: RestartPhase,
    /// The restart block's line (while `searching`: the block the search has got to).
    pub line: u32,
    /// Its sequence number (none for a block without N).
    pub n: Option<u32>,
    /// Blocks the search executed (so far).
    pub blocks: u64,
    /// The restart position per axis (machine coordinates): where the return goes (while
    /// `searching`: where the search has got to).
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub position: Map<String, Value>,
    /// What cycle start outputs before the return: the tool of the last tool change…
    pub tool: Option<u32>,
    /// …and the speed of the last spindle command (1/min; negative counter-clockwise, 0 stopped).
    pub spindle: Option<f64>,
    /// The other M codes the search passed over, the last 35 (for the operator to give).
    pub m_codes: Vec<u32>,
}

impl RestartInfo {
    pub fn of(station: &Station) -> Option<RestartInfo> {
        let r = station.controller.restart_status()?;
        let f = &r.found;
        let tool = f.output.iter().find_map(|c| match c.kind {
            CanonKind::ToolChange { tool } => Some(tool),
            _ => None,
        });
        let spindle = f.output.iter().find_map(|c| match c.kind {
            CanonKind::Spindle { state: SpindleState::Cw, speed } => Some(speed),
            CanonKind::Spindle { state: SpindleState::Ccw, speed } => Some(-speed),
            CanonKind::Spindle { state: SpindleState::Stop, .. } => Some(0.0),
            _ => None,
        });
        Some(RestartInfo {
            kind: r.kind,
            phase: r.phase,
            line: f.line,
            n: f.n,
            blocks: f.blocks,
            position: axes(&station.machine, &f.machine),
            tool,
            spindle,
            m_codes: f.m_codes.clone(),
        })
    }
}

/// Program restart: search the program (run from its top without motion) to the restart block;
/// the answer's `restart` shows what was found. The manual's conditions (P type without an
/// automatic operation since power-on or the emergency stop, the work offsets changed, the
/// block not found, a program alarm in the search, a restart block in a mode the return cannot
/// enter) are the dialect's alarms, in the status; the next cycle start outputs the M/S/T,
/// returns the axes one at a time and goes on from the restart block.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/restart",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = RestartRequest,
    responses(
        (status = 200, description = "Searched, or searching on (a long program), or the alarm that stopped the search", body = ControllerStatus),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 409, description = "Not possible now; `error` names the state (running, searching, holding, in alarm, the emergency stop, not in AUTO, no program selected, Syntec has no program restart)", body = ErrorBody),
        (status = 422, description = "Not a restart request", body = ErrorBody),
    )
)]
pub async fn restart(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<RestartRequest>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    let kind = panel::restart_type(&request.kind)?;
    let at = RestartAt::of(request.n, request.line, request.occurrence)?;
    let program = match request.program {
        Some(n) => Some((n, programs::composed(&state.db, &hosted, n).await?)),
        None => None,
    };
    super::panel::status_after(&state, &hosted, PanelCommand::Restart { program, kind, at })
}
