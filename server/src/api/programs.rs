//! A controller's stored programs (O numbers) and their NC text.

use crate::http::extract::Addressed;
use axum::body::Bytes;
use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::IntoResponse;
use axum::Json;
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::http::extract::{hosted, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::programs;

pub use crate::service::programs::MAX_PROGRAM_BYTES;

/// A stored program in a list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ProgramSummary {
    /// The O number.
    pub number: u32,
    /// Size of the NC text, bytes.
    pub size: usize,
}

/// What `fivex check` finds in a program, one problem per entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Diagnostic {
    pub line: u32,
    pub col: u32,
    /// The dialect's alarm code.
    #[schema(example = "PS0010")]
    pub code: String,
    pub message: String,
    /// What exactly is wrong.
    pub detail: String,
}

/// The answer to storing a program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct StoredProgram {
    pub number: u32,
    pub size: usize,
    /// Problems `check` found (stored anyway because the client asked with `force=true`).
    pub diagnostics: Vec<Diagnostic>,
}

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct StoreOptions {
    /// Store the text even if `check` finds problems.
    #[serde(default)]
    pub force: bool,
}

impl Diagnostic {
    fn of(p: programs::Problem) -> Diagnostic {
        Diagnostic { line: p.line, col: p.col, code: p.code, message: p.message, detail: p.detail }
    }
}

/// The stored programs, ascending.
#[utoipa::path(
    get,
    operation_id = "list_programs",
    path = "/api/v1/controllers/{id}/programs",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Stored programs", body = [ProgramSummary]),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn list(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
) -> Result<Json<Vec<ProgramSummary>>, ApiError> {
    let rows = programs::list(&state.db, &hosted).await?;
    Ok(Json(rows.into_iter().map(|(number, size)| ProgramSummary { number, size }).collect()))
}

/// Stores a program's NC text (`text/plain`, UTF-8). A text `check` finds problems in is
/// refused with the diagnostics (422) unless `force=true`; a program a run under way reads is
/// not replaced (409).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/programs/{number}",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 9999, description = "O number, 1–9999"), StoreOptions),
    request_body(content = Option<String>, content_type = "text/plain", description = "NC text (none: an empty program)"),
    responses(
        (status = 201, description = "Stored (new)", body = StoredProgram),
        (status = 200, description = "Stored (replaced)", body = StoredProgram),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 409, description = "A run under way reads this program (the one it started, or the one it called and is in): it can change once the run is over", body = ErrorBody),
        (status = 413, description = "Too large", body = ErrorBody),
        (status = 415, description = "Not text/plain in UTF-8 (another `charset`), or a body without a content type", body = ErrorBody),
        (status = 400, description = "The number is not a number, or the query is malformed", body = ErrorBody),
        (status = 422, description = "Not UTF-8 NC text, a number outside 1–9999, an O number in the text other than the slot's (`details`: `slot`, `text_number`; even with `force=true`), a second program in the text (`details`: `slot`, `line`, `text_number`; even with `force=true`), or `check` found problems (in `details`)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn store(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
    options: Result<Query<StoreOptions>, QueryRejection>,
    headers: HeaderMap,
    text: Bytes,
) -> Result<(StatusCode, Json<StoredProgram>), ApiError> {
    let (id, n) = path(params)?;
    let force = options.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?.force;
    let hosted = hosted(&state, &id)?;
    let n = programs::number(n)?;
    plain_utf8(&headers, !text.is_empty())
        .map_err(|why| ApiError::Rejected(StatusCode::UNSUPPORTED_MEDIA_TYPE, why))?;
    if text.len() > MAX_PROGRAM_BYTES {
        return Err(ApiError::Rejected(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("a program may have at most {MAX_PROGRAM_BYTES} bytes"),
        ));
    }
    let stored = programs::store(&state.db, &hosted, n, &text, force).await?;
    let status = if stored.new { StatusCode::CREATED } else { StatusCode::OK };
    let diagnostics = stored.problems.into_iter().map(Diagnostic::of).collect();
    Ok((status, Json(StoredProgram { number: n, size: stored.size, diagnostics })))
}

/// A program's body is `text/plain` in UTF-8 (a `charset` parameter, if any, `utf-8` or its
/// subset `us-ascii`): the text is read as UTF-8, so another charset would be read wrongly. A
/// body needs its type declared (`docs/api.md`, "Security"); no body and no type is an empty
/// program.
fn plain_utf8(headers: &HeaderMap, has_body: bool) -> Result<(), String> {
    let Some(media) = headers.get(header::CONTENT_TYPE) else {
        return if has_body { Err("a program body needs Content-Type: text/plain".into()) } else { Ok(()) };
    };
    let media = media.to_str().unwrap_or("(not text)").to_ascii_lowercase();
    let mut parts = media.split(';').map(str::trim);
    if parts.next() != Some("text/plain") {
        return Err(format!("programs are text/plain, not {media}"));
    }
    for (name, value) in parts.filter_map(|p| p.split_once('=')) {
        let value = value.trim().trim_matches('"');
        if name.trim() == "charset" && !matches!(value, "utf-8" | "utf8" | "us-ascii") {
            return Err(format!("programs are UTF-8 text, not charset {value}"));
        }
    }
    Ok(())
}

/// A stored program's NC text.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/programs/{number}",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 9999, description = "O number, 1–9999")),
    responses(
        (status = 200, description = "NC text", body = String, content_type = "text/plain"),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn text(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
) -> Result<impl IntoResponse, ApiError> {
    let (id, n) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let text = programs::text(&state.db, &hosted, n).await?;
    Ok(([(header::CONTENT_TYPE, "text/plain; charset=utf-8")], text))
}

/// Removes a stored program (not while a run under way reads it).
#[utoipa::path(
    delete,
    operation_id = "remove_program",
    path = "/api/v1/controllers/{id}/programs/{number}",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 9999, description = "O number, 1–9999")),
    responses(
        (status = 204, description = "Removed"),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 409, description = "A run under way reads this program (the one it started, or the one it called and is in): it can be removed once the run is over", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn remove(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
) -> Result<StatusCode, ApiError> {
    let (id, n) = path(params)?;
    let hosted = hosted(&state, &id)?;
    programs::remove(&state.db, &hosted, n).await?;
    Ok(StatusCode::NO_CONTENT)
}

/// `GET /programs/{number}/path` options.
#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct PathOptions {
    /// Most points returned (1–1,000,000, default 200,000); `truncated` says when the path was
    /// longer.
    #[param(minimum = 1, maximum = 1000000)]
    pub max_points: Option<usize>,
}

/// The tool tip path a stored program asks for, as the 3D view draws it.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ToolPathBody {
    /// Tip positions in the table frame (`docs/machine-config.md`), x y z of each point in
    /// turn; the first point is where the machine is now.
    pub xyz: Vec<f64>,
    /// Per point: the 1-based line that moves to it (0 for the start), in the stored program
    /// `line_programs` names.
    pub lines: Vec<u32>,
    /// Per point: the O number of the stored program its line is in: the program asked for,
    /// or one it calls (M98/G65/G66…).
    pub line_programs: Vec<u32>,
    /// Per point: the move to it is a rapid.
    pub rapid: Vec<bool>,
    /// The alarm the program would stop with, if it does before its end.
    pub alarm: Option<crate::host::stream::AlarmInfo>,
    /// The path has more points than `max_points` (or the programmed path has).
    pub truncated: bool,
    /// Only when cutter compensation (G41/G42) is in force somewhere in the program: the
    /// programmed path, the interpreter's points before the path stages, while `xyz` is where
    /// the tool centre goes (`docs/cutter-compensation.md`). Equal to `xyz` until compensation
    /// starts; it goes as far as the interpreter read (the blocks held when a compensation
    /// alarm stopped the path included). Absent without compensation: `xyz` is the programmed
    /// path then.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false)]
    pub programmed: Option<ProgrammedPathBody>,
}

/// The programmed path beside a compensated tool path, in the same form.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ProgrammedPathBody {
    /// Programmed tip positions in the table frame, x y z of each point in turn; the first is
    /// where the machine is now.
    pub xyz: Vec<f64>,
    /// Per point: the 1-based line that moves to it (0 for the start), in the stored program
    /// `line_programs` names.
    pub lines: Vec<u32>,
    /// Per point: the O number of the stored program its line is in.
    pub line_programs: Vec<u32>,
    /// Per point: the move to it is a rapid.
    pub rapid: Vec<bool>,
}

/// The programmed tool tip path of a stored program, run from where the machine is now with
/// the controller's offsets and variables, without moving anything (the interpreter and the
/// path stages). Straight moves are their ends; arcs, rotary moves and tool-tip-path moves are
/// sampled at least every mm or degree. Under cutter compensation `xyz` is the tool centre's
/// path and `programmed` the programmed one beside it.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/programs/{number}/path",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 9999, description = "O number, 1–9999"), PathOptions),
    responses(
        (status = 200, description = "The path", body = ToolPathBody),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 422, description = "max_points out of range", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn tool_path(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
    options: Result<Query<PathOptions>, QueryRejection>,
) -> Result<Json<ToolPathBody>, ApiError> {
    let (id, n) = path(params)?;
    let max_points =
        options.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?.0.max_points.unwrap_or(200_000);
    if !(1..=1_000_000).contains(&max_points) {
        return Err(ApiError::Unprocessable("max_points must be 1 to 1000000".into(), None));
    }
    let hosted = hosted(&state, &id)?;
    let programs::Composed { source, layout } = programs::composed(&state.db, &hosted, n).await?;
    let mut interp = hosted.station().controller.interpreter().clone();
    let body = tokio::task::spawn_blocking(move || {
        interp.load_source(&source);
        let path = fivex_engine::preview::tool_path(&mut interp, max_points);
        // The composed source's lines, each as its own program's (`docs/api.md`, "Lines of stored
        // programs"); the start (line 0) belongs to the program asked for.
        let located = |lines: &[u32]| -> (Vec<u32>, Vec<u32>) {
            lines.iter().map(|&line| layout.locate(line)).map(|(program, line)| (line, program.unwrap_or(n))).unzip()
        };
        let (lines, line_programs) = located(&path.lines);
        ToolPathBody {
            xyz: path.points.iter().flatten().copied().collect(),
            lines,
            line_programs,
            rapid: path.rapid,
            alarm: path.alarm.as_ref().map(|a| crate::host::stream::AlarmInfo::located(a, &layout)),
            truncated: path.truncated,
            programmed: path.programmed.map(|p| {
                let (lines, line_programs) = located(&p.lines);
                ProgrammedPathBody {
                    xyz: p.points.iter().flatten().copied().collect(),
                    lines,
                    line_programs,
                    rapid: p.rapid,
                }
            }),
        }
    })
    .await
    .map_err(|e| ApiError::Unprocessable(format!("the path could not be made: {e}"), None))?;
    Ok(Json(body))
}

/// The simulated cycle time of a stored program run from where the machine is now, with the
/// controller's machine, offsets, variables and modal state (the engine's `run`, as `fivex run`
/// runs it, at 100 % overrides and without operator stops). The first request begins it on a
/// background thread and answers `pending`; ask again. Kept until one of those inputs changes.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/programs/{number}/estimate",
    tag = "programs",
    params(("id" = String, Path, description = "Controller id"), ("number" = u32, Path, minimum = 1, maximum = 9999, description = "O number, 1–9999")),
    responses(
        (status = 200, description = "The estimate, or `pending` while it is computed", body = crate::host::estimate::Estimate),
        (status = 404, description = "No such controller or program", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn estimate(
    State(state): State<AppState>,
    params: Result<Path<(String, u32)>, PathRejection>,
) -> Result<Json<crate::host::estimate::Estimate>, ApiError> {
    let (id, n) = path(params)?;
    let hosted = hosted(&state, &id)?;
    let program = programs::composed(&state.db, &hosted, n).await?;
    Ok(Json(crate::host::estimate::ensure(&hosted, program)))
}
