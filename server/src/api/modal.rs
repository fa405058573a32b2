//! The modal state as a panel shows it: the G code of each modal group and F, S, T, H, D.

use crate::http::extract::Addressed;
use std::collections::BTreeMap;

use axum::extract::Json;
use fivex_engine::interp::gcode;
use serde::Serialize;
use utoipa::ToSchema;

use crate::http::{ApiError, ErrorBody};

// FANUC's group 33 carries its P (`"33": "G54.4 P1"`; `"G54.4 P0"` when off, `docs/api.md`).
/// `GET /modal`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ModalState {
    /// The G code in force per modal group number (`{"1": "G01", "8": "G43.4", "16": "G68.2"}`),
    /// as the controller's dialect names it (Haas: `G154` for its extra work offsets); a group
    /// whose code the dialect does not have (FANUC's power-on G15 on a Haas control) is absent.
    #[schema(value_type = std::collections::HashMap<String, String>)]
    pub groups: BTreeMap<u8, String>,
    /// Feed (mm/min; 1/min under G93), spindle speed, tool prepared, tool in the spindle, H and D.
    pub f: f64,
    pub s: f64,
    pub t: u32,
    pub spindle_tool: u32,
    pub h: u32,
    pub d: u32,
}

/// The modal G codes and words of the block being executed (the interpreter reads ahead of it).
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/modal",
    tag = "controllers",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Modal state", body = ModalState),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn modal(Addressed(hosted): Addressed) -> Result<Json<ModalState>, ApiError> {
    // The executing block's state, not the read-ahead interpreter's.
    let modal = hosted.station().controller.modal();
    let initial = gcode::initial_modes();
    // The groups the dialects use (group 1's G00 is code 0; the others start non-zero), each
    // as the dialect names its code; a code the dialect does not have is not shown.
    let mut groups: BTreeMap<u8, String> = (1..gcode::GROUPS)
        .filter(|&g| g == gcode::group::MOTION || initial[g] != 0)
        .filter_map(|g| Some((g as u8, gcode::shown(modal.modal(g), hosted.dialect)?)))
        .collect();
    // Group 33, workpiece setting error compensation (FANUC: "G54.4 is a modal G code that
    // belongs to group 33"), with its set: on, G54.4 Pn; off (power-on, P0, a reset), G54.4 P0.
    if gcode::written(gcode::code::G54_4, hosted.dialect).is_some() {
        groups.insert(gcode::group::WSE as u8, format!("G54.4 P{}", modal.wse_set));
    }
    let w = modal.words;
    Ok(Json(ModalState { groups, f: w.f, s: w.s, t: w.t, spindle_tool: w.spindle_tool, h: w.h, d: w.d }))
}
