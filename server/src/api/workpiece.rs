//! What is clamped on a controller's table: the boxes a G31 probe touches
//! (`fivex_engine::workpiece`, in the table frame). Kept in the database when the answer comes.

use axum::extract::{Json, State};

use crate::http::extract::{body, Addressed, JsonBody};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::workpiece;
use fivex_engine::workpiece::Workpiece;

/// The boxes on the table (`{"boxes": []}`: nothing there, and a G31 runs its whole move).
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/workpiece",
    tag = "workpiece",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "The workpiece", body = Workpiece),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn get_workpiece(Addressed(hosted): Addressed) -> Result<Json<Workpiece>, ApiError> {
    Ok(Json((*workpiece::of(&hosted)).clone()))
}

/// Put boxes on the table (replacing what was there; `{"boxes": []}` clears it): axis-aligned
/// boxes in the table frame, mm, at most 256, each `min` below `max` on every axis. A skip
/// block read from now on probes them. Only at a block boundary, as machine lock: not while the
/// axes move or a move is planned.
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/workpiece",
    tag = "workpiece",
    params(("id" = String, Path, description = "Controller id")),
    request_body = Workpiece,
    responses(
        (status = 200, description = "On the table and stored", body = Workpiece),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "The axes move or a move is planned", body = ErrorBody),
        (status = 422, description = "Not a workpiece: an unknown field, a corner not finite, min not below max, more than 256 boxes", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn put_workpiece(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Workpiece>, ApiError>,
) -> Result<Json<Workpiece>, ApiError> {
    let set = workpiece::set(&state.db, &hosted, body(request)?).await?;
    Ok(Json((*set).clone()))
}
