//! Tool offset memory (H/D, geometry and wear; the corner radius) and work offsets (external,
//! G54–G59, G54.1 P1–P300). Changes are in the database when the answer comes; a program's own
//! changes (G10, system variables) are saved when its run state changes, or with the next
//! change through the API (`service::settings`).

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::ToSchema;

use crate::db::ToolRow;
use crate::host::station::{tool_row, WORK_SLOTS};
use crate::host::stream::axes;
use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::settings::{self, ToolChange};
use fivex_engine::Dialect;

/// One tool offset number (mm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ToolOffsetDto {
    pub number: u32,
    /// H geometry and wear.
    pub length: f64,
    pub length_wear: f64,
    /// D geometry and wear.
    pub radius: f64,
    pub radius_wear: f64,
    /// The tool's corner radius, read by cutting point control (G43.8/G43.9): 0 for a square
    /// end mill (and for a ball end mill, whose corner radius is its radius D).
    pub corner_radius: f64,
}

impl From<ToolRow> for ToolOffsetDto {
    fn from(t: ToolRow) -> Self {
        ToolOffsetDto {
            number: t.number,
            length: t.length,
            length_wear: t.length_wear,
            radius: t.radius,
            radius_wear: t.radius_wear,
            corner_radius: t.corner_radius,
        }
    }
}

/// `PUT /tool-offsets/{number}`: the values to change.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetToolOffset {
    /// mm, within ±999.999 (the range G10 takes, `docs/conventions.md`, "Tool offset values").
    #[schema(minimum = -999.999, maximum = 999.999)]
    pub length: Option<f64>,
    /// mm, within ±99.999.
    #[schema(minimum = -99.999, maximum = 99.999)]
    pub length_wear: Option<f64>,
    /// mm, within ±999.999.
    #[schema(minimum = -999.999, maximum = 999.999)]
    pub radius: Option<f64>,
    /// mm, within ±99.999.
    #[schema(minimum = -99.999, maximum = 99.999)]
    pub radius_wear: Option<f64>,
    /// Not negative, at most 999.999 mm; absent: as it is (0 for an offset never given one).
    #[schema(minimum = 0.0, maximum = 999.999)]
    pub corner_radius: Option<f64>,
}

/// A work offset by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct WorkOffsetDto {
    /// `EXT` (Haas: `G52`, read only), `G54`…`G59`, `G54.1P1`…`G54.1P300`.
    #[schema(example = "G54")]
    pub name: String,
    /// Value per axis letter.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub axes: Map<String, Value>,
}

/// `PUT /work-offsets/{name}`: the axes to change.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetWorkOffset {
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub axes: Map<String, Value>,
}

/// The slot of a work offset name. Haas's names of the same storage are taken too: G154 P1–P99
/// is G54.1 P1–P99, G110–G129 are G154 P1–P20 (`docs/dialects.md`, "Work offsets G154").
fn slot_of(name: &str) -> Option<usize> {
    let upper = name.to_ascii_uppercase().replace(' ', "");
    let additional = |p: usize, most: usize| (1..=most).contains(&p).then_some(6 + p);
    match upper.as_str() {
        "EXT" => Some(0),
        _ => {
            if let Some(p) = upper.strip_prefix("G54.1P") {
                additional(p.parse().ok()?, WORK_SLOTS - 7)
            } else if let Some(p) = upper.strip_prefix("G154P") {
                additional(p.parse().ok()?, 99)
            } else {
                let g: usize = upper.strip_prefix('G')?.parse().ok()?;
                match g {
                    54..=59 => Some(g - 53),
                    110..=129 => additional(g - 109, 20),
                    _ => None,
                }
            }
        }
    }
}

fn name_of(slot: usize) -> String {
    match slot {
        0 => "EXT".into(),
        1..=6 => format!("G{}", 53 + slot),
        p => format!("G54.1P{}", p - 6),
    }
}

/// Tool offsets that are not all zero, by number.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/tool-offsets",
    tag = "offsets",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Tool offsets", body = [ToolOffsetDto]),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn tools(Addressed(hosted): Addressed) -> Result<Json<Vec<ToolOffsetDto>>, ApiError> {
    let station = hosted.station();
    let offsets = &station.controller.interpreter().state.offsets;
    let list = (1..=fivex_engine::interp::MAX_TOOL_OFFSETS as u32)
        .filter_map(|n| offsets.tool(n).filter(|t| **t != Default::default()).map(|t| tool_row(n, t).into()))
        .collect();
    Ok(Json(list))
}

/// Change a tool offset (it acts at the next H/D selection, as G10 does).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/tool-offsets/{number}",
    tag = "offsets",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 999, description = "Offset number 1–999")),
    request_body = SetToolOffset,
    responses(
        (status = 200, description = "Changed", body = ToolOffsetDto),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "No such offset number, a value outside the range G10 takes (geometry ±999.999 mm, wear ±99.999 mm), or a negative corner radius", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
        (status = 503, description = "The controller left this node while the request waited (deleted, or moving to another node: retry), the service is stopping, or the database writer did not store the change within 60 s (the value is set but may not be kept)", body = ErrorBody),
    )
)]
pub async fn set_tool(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
    request: Result<JsonBody<SetToolOffset>, ApiError>,
) -> Result<Json<ToolOffsetDto>, ApiError> {
    let (id, number) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let request = body(request)?;
    let change = ToolChange {
        length: request.length,
        length_wear: request.length_wear,
        radius: request.radius,
        radius_wear: request.radius_wear,
        corner_radius: request.corner_radius,
    };
    let row = settings::set_tool_offset(&state.db, &state.host, &hosted, number, change).await?;
    Ok(Json(row.into()))
}

/// The external offset (Haas: G52), G54–G59, and the G54.1 offsets that are not zero.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/work-offsets",
    tag = "offsets",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Work offsets", body = [WorkOffsetDto]),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn works(Addressed(hosted): Addressed) -> Result<Json<Vec<WorkOffsetDto>>, ApiError> {
    let station = hosted.station();
    let interpreter = station.controller.interpreter();
    let offsets = &interpreter.state.offsets;
    let haas = interpreter.config().dialect == Dialect::Haas;
    let list = (0..WORK_SLOTS)
        .filter(|&i| i <= 6 || offsets.work(i).iter().any(|v| *v != 0.0))
        .map(|i| match i {
            // Haas has no external offset: its row is G52, what #5201… read and G52 and
            // G10 L2 P0 set (`docs/dialects.md`, "Haas: the dialect's core").
            0 if haas => {
                WorkOffsetDto { name: HAAS_G52.into(), axes: axes(&station.machine, &interpreter.state.local_offset()) }
            }
            _ => WorkOffsetDto { name: name_of(i), axes: axes(&station.machine, offsets.work(i)) },
        })
        .collect();
    Ok(Json(list))
}

/// The Haas dialect's row in place of `EXT`: its G52 (read only here).
const HAAS_G52: &str = "G52";

/// Why a work offset cannot be set through the API on a control of `dialect`, if it cannot:
/// a Haas control has no external offset (its `G10 L2 P0` and #5201… are G52), and its G52 is the
/// program's (G52, G10 L2 P0; gone at M30 and reset on the control), not a stored offset.
fn refused_on(dialect: Dialect, name: &str, slot: Option<usize>) -> Option<String> {
    let g52 = name.trim().eq_ignore_ascii_case(HAAS_G52);
    (dialect == Dialect::Haas && (slot == Some(0) || g52)).then(|| {
        format!(
            "work offset {name}: a Haas control has no external work offset; its G10 L2 P0 and #5201… are G52, \
             which programs set (G52, G10 L2 P0) and the API shows but does not set"
        )
    })
}

/// Change a work offset (only while nothing runs: the current position is derived again).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/work-offsets/{name}",
    tag = "offsets",
    params(("id" = String, Path, description = "Controller id"), ("name" = String, Path, description = "EXT, G54…G59, G54.1P1…G54.1P300 (Haas's G154P1…G154P99 and G110…G129 name the same storage)")),
    request_body = SetWorkOffset,
    responses(
        (status = 200, description = "Changed", body = WorkOffsetDto),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "A program runs or holds", body = ErrorBody),
        (status = 422, description = "No such offset or axis, a value beyond ±999999.999 mm (the range G10 takes), or `EXT`/`G52` on a Haas controller (it has no external offset; its G52 is the program's)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
        (status = 503, description = "The controller left this node while the request waited (deleted, or moving to another node: retry), the service is stopping, or the database writer did not store the change within 60 s (the value is set but may not be kept)", body = ErrorBody),
    )
)]
pub async fn set_work(
    State(state): State<AppState>,
    params: Result<Path<(String, String)>, PathRejection>,
    request: Result<JsonBody<SetWorkOffset>, ApiError>,
) -> Result<Json<WorkOffsetDto>, ApiError> {
    let (id, name) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let request = body(request)?;
    let dialect = hosted.station().controller.interpreter().config().dialect;
    if let Some(why) = refused_on(dialect, &name, slot_of(&name)) {
        return Err(ApiError::Unprocessable(why, None));
    }
    let slot = slot_of(&name).ok_or_else(|| ApiError::Unprocessable(format!("no work offset {name}"), None))?;
    let shown = settings::set_work_offset(&state.db, &state.host, &hosted, slot, &request.axes).await?;
    Ok(Json(WorkOffsetDto { name: name_of(slot), axes: shown }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_offset_names_and_slots() {
        for (name, slot) in [("EXT", 0), ("G54", 1), ("g59", 6), ("G54.1P1", 7), ("G54.1 P300", 306)] {
            assert_eq!(slot_of(name), Some(slot), "{name}");
        }
        // Haas's names of the same storage.
        for (name, slot) in [("G154P1", 7), ("g154 p99", 105), ("G110", 7), ("G129", 26)] {
            assert_eq!(slot_of(name), Some(slot), "{name}");
        }
        for bad in ["G53", "G60", "G54.1P0", "G54.1P301", "X", "", "G154P0", "G154P100", "G109", "G130", "G154"] {
            assert_eq!(slot_of(bad), None, "{bad}");
        }
        assert_eq!(name_of(306), "G54.1P300");
    }
}
