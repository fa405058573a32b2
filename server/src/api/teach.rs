//! Syntec's tilted working plane teach screen (§3.3–§3.4; `fivex_engine::teach`): latch the tool
//! tip into P1/P2/P3 (F1), list what was latched, and teach a plane — its feature coordinate
//! system and the `G68.2` block that sets it, which the client runs through `/mdi` (F2). The
//! boxes live beside the controller (`Station::teach`) and are not saved: a screen's inputs.
//! A FANUC controller has no such screen: every request is 409.

use crate::http::extract::Addressed;
use axum::extract::rejection::PathRejection;
use axum::extract::{Json, Path, State};
use fivex_engine::geom::Vec3;
use fivex_engine::teach::{self, Latched, Method, Slot};
use fivex_engine::Dialect;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::host::Hosted;
use crate::http::extract::JsonBody;
use crate::http::extract::{body, hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};

/// One latched box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct TeachPoint {
    /// `p1`, `p2` or `p3`.
    #[schema(example = "p1")]
    pub slot: String,
    /// The tool tip's absolute coordinate (active workpiece system), mm.
    pub point: [f64; 3],
    /// The tool direction there (unit, tip toward holder), in the workpiece system's axes.
    pub tool: [f64; 3],
}

/// `GET /teach`: the boxes latched, and whether F1 may latch now.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct TeachState {
    /// The latched boxes, P1 first (absent boxes are not listed).
    pub points: Vec<TeachPoint>,
    /// Why a latch is refused now (G49, or a tilted plane in force); null when it is allowed.
    pub latch_refused: Option<String>,
}

/// The guidance mode of a teach.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum TeachMode {
    /// P1 the origin, P1→P2 the +X direction, P3 on the +Y side (§3.4.1).
    ThreePoints,
    /// P1 the origin, Z the tool direction latched with P1, turned by `i` degrees (§3.4.2).
    ToolDirection,
    /// P1 the origin, Euler angles `i`, `j`, `k` (Z–X–Z, as G68.2's) (§3.4.3).
    Euler,
    /// P1 the origin, the plane's X axis `x` and Z axis `z` in workpiece components (§3.4.4).
    TwoVectors,
}

/// `POST /teach/plane`: the mode and the values typed (each mode takes only its own).
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TeachRequest {
    pub mode: TeachMode,
    /// Degrees: tool direction's turn about the tool; Euler's first angle (absent: 0).
    pub i: Option<f64>,
    /// Degrees: Euler's second and third angles (absent: 0).
    pub j: Option<f64>,
    pub k: Option<f64>,
    /// Two vectors: the X and the Z axis of the plane (both required).
    pub x: Option<[f64; 3]>,
    pub z: Option<[f64; 3]>,
}

/// The taught plane.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct TaughtPlane {
    /// The block that sets it, `G68.2 X_ Y_ Z_ I_ J_ K_` (values to 0.001).
    #[schema(example = "G68.2 X0. Y0. Z0. I0. J180. K0.")]
    pub block: String,
    /// Its origin and X, Y, Z axes in the workpiece system.
    pub origin: [f64; 3],
    pub x: [f64; 3],
    pub y: [f64; 3],
    pub z: [f64; 3],
    /// Its Z–X–Z Euler angles I, J, K, degrees, unrounded.
    pub euler: [f64; 3],
}

fn syntec_only(hosted: &Hosted) -> Result<(), ApiError> {
    match hosted.dialect {
        Dialect::Syntec => Ok(()),
        Dialect::Fanuc | Dialect::Haas => Err(ApiError::Conflict(teach::LatchRefused::NotSyntec.reason().into())),
    }
}

fn point_of(slot: Slot, l: Latched) -> TeachPoint {
    TeachPoint { slot: slot.name().into(), point: l.point.into(), tool: l.tool.into() }
}

fn state_of(hosted: &Hosted) -> TeachState {
    let station = hosted.station();
    let points = Slot::ALL.into_iter().filter_map(|s| Some(point_of(s, station.teach.get(s)?))).collect();
    let latch_refused = teach::latch(&station.controller).err().map(|r| r.reason().to_string());
    TeachState { points, latch_refused }
}

/// The boxes latched and whether F1 may latch now.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/teach",
    tag = "teach",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "The teach screen's boxes", body = TeachState),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not a Syntec controller", body = ErrorBody),
    )
)]
pub async fn get(Addressed(hosted): Addressed) -> Result<Json<TeachState>, ApiError> {
    syntec_only(&hosted)?;
    Ok(Json(state_of(&hosted)))
}

/// Empty every box.
#[utoipa::path(
    delete,
    path = "/api/v1/controllers/{id}/teach/points",
    tag = "teach",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Emptied", body = TeachState),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not a Syntec controller", body = ErrorBody),
    )
)]
pub async fn clear(Addressed(hosted): Addressed) -> Result<Json<TeachState>, ApiError> {
    syntec_only(&hosted)?;
    hosted.station().teach.clear();
    Ok(Json(state_of(&hosted)))
}

/// F1 Latch G54 Coordinate: the tool tip where the machine stands now into a box.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/teach/points/{slot}",
    tag = "teach",
    params(("id" = String, Path, description = "Controller id"), ("slot" = String, Path, description = "p1, p2 or p3")),
    responses(
        (status = 200, description = "Latched", body = TeachPoint),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not a Syntec controller; G49 in force; or a tilted plane in force", body = ErrorBody),
        (status = 422, description = "No such box", body = ErrorBody),
    )
)]
pub async fn latch(
    State(state): State<AppState>,
    params: Result<Path<(String, String)>, PathRejection>,
    _: crate::http::extract::Bodyless,
) -> Result<Json<TeachPoint>, ApiError> {
    let (id, name) = path(params)?;
    let hosted = hosted(&state, &id)?;
    syntec_only(&hosted)?;
    let slot = Slot::parse(&name)
        .ok_or_else(|| ApiError::Unprocessable(format!("no teach box {name}: p1, p2 or p3"), None))?;
    let mut station = hosted.station();
    let latched = teach::latch(&station.controller).map_err(|r| ApiError::Conflict(r.reason().into()))?;
    station.teach.set(slot, latched);
    Ok(Json(point_of(slot, latched)))
}

/// The method of a request: each mode takes its own values only (a value it would not use is
/// refused rather than ignored).
fn method_of(r: &TeachRequest) -> Result<Method, String> {
    let given =
        [("i", r.i.is_some()), ("j", r.j.is_some()), ("k", r.k.is_some()), ("x", r.x.is_some()), ("z", r.z.is_some())];
    let takes: &[&str] = match r.mode {
        TeachMode::ThreePoints => &[],
        TeachMode::ToolDirection => &["i"],
        TeachMode::Euler => &["i", "j", "k"],
        TeachMode::TwoVectors => &["x", "z"],
    };
    if let Some((name, _)) = given.iter().find(|(name, set)| *set && !takes.contains(name)) {
        return Err(format!("{name} is not a value of this teach mode"));
    }
    let angle = |v: Option<f64>| v.unwrap_or(0.0);
    Ok(match r.mode {
        TeachMode::ThreePoints => Method::ThreePoints,
        TeachMode::ToolDirection => Method::ToolDirection { i: angle(r.i) },
        TeachMode::Euler => Method::Euler { i: angle(r.i), j: angle(r.j), k: angle(r.k) },
        TeachMode::TwoVectors => match (r.x, r.z) {
            (Some(x), Some(z)) => Method::TwoVectors { x: Vec3::from(x), z: Vec3::from(z) },
            _ => return Err("two vectors needs both x and z".into()),
        },
    })
}

/// Teach: the feature coordinate system of the mode from the latched boxes, and the G68.2 block
/// that sets it. Nothing changes on the controller (run the block through `/mdi` to set it).
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/teach/plane",
    tag = "teach",
    params(("id" = String, Path, description = "Controller id")),
    request_body = TeachRequest,
    responses(
        (status = 200, description = "The plane taught", body = TaughtPlane),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "Not a Syntec controller", body = ErrorBody),
        (status = 422, description = "The teach fails (collinear points, vectors zero or not orthogonal, a box not latched) or a value the mode does not take", body = ErrorBody),
    )
)]
pub async fn plane(
    Addressed(hosted): Addressed,
    request: Result<JsonBody<TeachRequest>, ApiError>,
) -> Result<Json<TaughtPlane>, ApiError> {
    syntec_only(&hosted)?;
    let request = body(request)?;
    let method = method_of(&request).map_err(|e| ApiError::Unprocessable(e, None))?;
    let points = hosted.station().teach;
    let taught = teach::teach(method, &points).map_err(|f| ApiError::Unprocessable(f.reason(), None))?;
    let f = taught.frame;
    Ok(Json(TaughtPlane {
        block: taught.block,
        origin: f.o.into(),
        x: f.x().into(),
        y: f.y().into(),
        z: f.z().into(),
        euler: taught.euler,
    }))
}
