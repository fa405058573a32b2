//! Fleet runs (`docs/api.md` "Fleet runs", `docs/fleet.md`) over HTTP: `POST /fleet/runs` runs
//! one program on many machines — presets, machine documents, library machines, existing
//! controllers — (`service::fleet_runs`: queued, run, stored); `POST /fleet/runs/{id}/cancel`
//! stops one; `GET /fleet/runs`, `GET /fleet/runs/{id}` read them, and the progress goes out
//! over `GET /fleet/runs/{id}/stream` (a websocket).

use std::collections::BTreeMap;

use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::ws::{CloseFrame, Message as Ws, Utf8Bytes, WebSocket, WebSocketUpgrade};
use axum::extract::{Json, Path, Query, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use fivex_engine::Dialect;
use futures_util::{SinkExt, StreamExt};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use tokio::sync::watch;
use utoipa::{IntoParams, ToSchema};

use crate::cluster::Source;
use crate::db::FleetRunRow;
use crate::fleet::{self, Entry, Options, Tool};
use crate::http::extract::JsonBody;
use crate::http::extract::{body, path};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::service::fleet_runs::{self, MachineProgress, Plan, Progress, Started};
use crate::wire::{FleetResult, MachineDocument};

/// `POST /fleet/runs`: the program and the machines (at least one of `presets`, `machines`,
/// `library`, `controllers`; at most 200 machines in all, so at most 200 in each list).
#[derive(Debug, Clone, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FleetRequest {
    /// The NC program text (docs/contracts.md "NC program files").
    #[schema(min_length = 1)]
    pub program: String,
    /// Built-in presets (`mill3`, `head-bc`, `table-ac`, `table-bc`, `mixed-bc`).
    #[serde(default)]
    #[schema(max_items = 200)]
    pub presets: Vec<String>,
    /// Machine documents: models or vendor parameter lists (a list runs in its own dialect).
    #[serde(default)]
    #[schema(value_type = Vec<MachineDocument>, max_items = 200)]
    pub machines: Vec<Value>,
    /// Machines of the library by name (`docs/fleet.md`); `["*"]`: all of them.
    #[serde(default)]
    #[schema(max_items = 200)]
    pub library: Vec<String>,
    /// Existing controllers by id: their machine, dialect and tool and work offsets.
    #[serde(default)]
    #[schema(max_items = 200)]
    pub controllers: Vec<String>,
    /// Dialect of presets, models and library models: `fanuc` (default), `syntec` or `haas`.
    pub dialect: Option<String>,
    /// Tool offsets by number (the schema and its description: [`tool_table_schema`]).
    #[schema(schema_with = tool_table_schema)]
    pub tools: Option<BTreeMap<u32, Tool>>,
    /// What is clamped on every machine's table, the boxes a G31 probe touches (as
    /// `PUT /controllers/{id}/workpiece` takes it); absent: nothing (a controller keeps its own
    /// unless this is given).
    pub workpiece: Option<fivex_engine::workpiece::Workpiece>,
    /// Add each machine's run report (`"report"`).
    #[serde(default)]
    pub report: bool,
}

/// The schema of `FleetRequest.tools`: an object keyed by offset numbers 1–999, written as JSON
/// keys are (`"1"`), without sign, leading zero or white space: exactly the keys the service
/// takes (serde reads a key as a JSON number; `check_tools` then refuses 0 and beyond 999).
fn tool_table_schema() -> utoipa::openapi::Object {
    use utoipa::openapi::schema::{ObjectBuilder, SchemaType, Type};
    use utoipa::openapi::Ref;
    // `Tool` is listed in the document's components (`http::openapi`): a `schema_with` does not
    // collect the schemas it refers to.
    ObjectBuilder::new()
        .schema_type(SchemaType::from_iter([Type::Object, Type::Null]))
        .description(Some(
            "Tool offsets `{\"1\": {\"length\": 100.0, \"radius\": 5.0}}` (numbers 1–999; `length_wear`, \
             `radius_wear` and `corner_radius` optional, default 0; any other field is refused); default: 1–99 at \
             100 / 5 mm (a controller keeps its own unless this is given).",
        ))
        .additional_properties(Some(Ref::from_schema_name("Tool")))
        .property_names(Some(ObjectBuilder::new().schema_type(Type::String).pattern(Some(TOOL_NUMBER_KEY))))
        .build()
}

/// A tool offset number 1–999 as a JSON object key.
pub const TOOL_NUMBER_KEY: &str = "^[1-9][0-9]{0,2}$";

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct CreateOptions {
    /// `true` (default): answer with the fleet array when the run is done; `false`: answer 202
    /// at once with the run's id (follow it on `/fleet/runs/{id}/stream`).
    pub wait: Option<bool>,
}

/// A stored fleet run in a list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct FleetRunInfo {
    pub id: String,
    /// RFC 3339 UTC.
    pub created_at: String,
    pub finished_at: Option<String>,
    /// `queued` (waiting for a place, `--fleet-jobs`), `running`, `done`, `cancelled`
    /// (`POST /fleet/runs/{id}/cancel`) or `interrupted` (the service stopped during the run).
    #[schema(value_type = crate::wire::words::FleetRunStatus)]
    pub status: String,
    pub machines: u32,
    /// Machines that completed the program, and that ended in an alarm.
    pub completed: u32,
    pub alarms: u32,
}

/// A stored fleet run with its request and results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct FleetRun {
    #[serde(flatten)]
    pub info: FleetRunInfo,
    /// The request as it was posted (as stored: written through `FleetRequest`).
    #[schema(value_type = FleetRequest)]
    pub request: Value,
    /// The fleet array (null while queued or running; `null` in it for each machine a
    /// cancelled or interrupted run did not finish), as stored: written through `FleetResult`.
    #[schema(value_type = Option<Vec<Option<FleetResult>>>)]
    pub results: Option<Value>,
}

impl FleetRunInfo {
    fn of(r: &FleetRunRow) -> FleetRunInfo {
        FleetRunInfo {
            id: r.id.clone(),
            created_at: r.created_at.clone(),
            finished_at: r.finished_at.clone(),
            status: r.status.clone(),
            machines: r.machines,
            completed: r.completed,
            alarms: r.alarms,
        }
    }
}

fn bad(why: impl Into<String>) -> ApiError {
    ApiError::Unprocessable(why.into(), None)
}

/// The machines of a request, in order: presets, machine documents, library, controllers; and
/// where each comes from, for a run over NATS (none for the controllers).
fn entries(state: &AppState, r: &FleetRequest, dialect: Dialect) -> Result<(Vec<Entry>, Vec<Source>), ApiError> {
    let mut out = Vec::new();
    for name in &r.presets {
        out.push(fleet::preset(name, dialect).map_err(bad)?);
    }
    for (i, m) in r.machines.iter().enumerate() {
        out.push(fleet::machine_file(&m.to_string(), dialect).map_err(|e| bad(format!("machines[{i}]: {e}")))?);
    }
    for name in &r.library {
        if name == "*" {
            out.extend(fleet::whole_library(dialect).map_err(bad)?);
        } else {
            out.push(fleet::library(name, dialect).map_err(bad)?);
        }
    }
    let sources = Source::requested(&r.presets, &r.machines, &r.library);
    for id in &r.controllers {
        let hosted = state.host.get(id).ok_or_else(|| bad(format!("no controller {id}")))?;
        let station = hosted.station();
        out.push(Entry {
            name: hosted.name(),
            machine: station.machine.config().clone(),
            dialect: hosted.dialect,
            offsets: Some(Box::new(station.controller.interpreter().state.offsets.clone())),
            workpiece: Some(station.controller.workpiece().clone()),
            start: Some(station.controller.program_machine()),
        });
    }
    Ok((out, sources))
}

/// Runs a program on many machines at once; with `wait` (the default) the answer is the
/// `fivex fleet` array, one `fivex run` summary per machine with `"machine"` and `"dialect"`
/// (and `"report"` when asked for).
#[utoipa::path(
    post,
    operation_id = "create_fleet_run",
    path = "/api/v1/fleet/runs",
    tag = "fleet",
    request_body = FleetRequest,
    params(CreateOptions),
    responses(
        (status = 200, description = "The fleet array (the run's id in `Location` and `X-Fleet-Run`)", body = [FleetResult]),
        (status = 202, description = "`wait=false`: started; follow it on the stream", body = FleetRunInfo),
        (status = 400, description = "Not JSON", body = ErrorBody),
        (status = 409, description = "`wait`: the run was cancelled before it finished", body = ErrorBody),
        (status = 422, description = "No machines, too many, an unknown preset, library machine or controller, a refused machine document, a bad dialect, tool table or workpiece, an empty program or one with a NUL; on a node with `--nats`, existing controllers (they cannot be sent to other nodes)", body = ErrorBody),
        (status = 503, description = "The service is stopping; `wait`: it stopped before the run finished (`interrupted`), or, on a node with `--nats`, the run gave up (`interrupted`: no node heard from for `--nats-timeout-s`, NATS failing)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn create(
    State(state): State<AppState>,
    options: Result<Query<CreateOptions>, QueryRejection>,
    request: Result<JsonBody<FleetRequest>, ApiError>,
) -> Result<Response, ApiError> {
    let wait = options.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?.wait.unwrap_or(true);
    let request = body(request)?;
    if request.program.trim().is_empty() {
        return Err(bad("program is empty"));
    }
    crate::service::programs::no_nul(&request.program)?;
    let dialect: Dialect = match &request.dialect {
        Some(d) => d.parse().map_err(|e: String| bad(e))?,
        None => Dialect::Fanuc,
    };
    let (entries, sources) = entries(&state, &request, dialect)?;
    let workpiece = request.workpiece.clone().map(std::sync::Arc::new);
    let plan = Plan {
        sources,
        request_json: serde_json::to_string(&request).unwrap_or_else(|_| "{}".into()),
        options: Options { tools: request.tools, report: request.report, workpiece, ..Options::default() },
        program: request.program,
        entries,
    };
    let Started { row, end: task } = fleet_runs::start(&state.db, &state.fleet_runs, plan).await?;
    let id = row.id.clone();
    let location = format!("{}/fleet/runs/{id}", crate::http::API_PREFIX);
    let mut headers = HeaderMap::new();
    if let Ok(v) = HeaderValue::from_str(&location) {
        headers.insert(header::LOCATION, v);
    }
    if let Ok(v) = HeaderValue::from_str(&id) {
        headers.insert("x-fleet-run", v);
    }
    if !wait {
        let info = FleetRunInfo::of(&row);
        return Ok((StatusCode::ACCEPTED, headers, Json(info)).into_response());
    }
    let ended = task.await.map_err(|e| ApiError::Unavailable(format!("fleet run failed: {e}")))?;
    match (ended.status, ended.error) {
        ("done", _) => Ok((StatusCode::OK, headers, Json(ended.results)).into_response()),
        ("cancelled", _) => Err(ApiError::Conflict(format!("fleet run {id} was cancelled"))),
        ("running", error) => Err(ApiError::Unavailable(format!(
            "fleet run {id}: {}",
            error.as_deref().unwrap_or("no longer collected by this node")
        ))),
        (_, Some(error)) => Err(ApiError::Unavailable(format!("fleet run {id} was interrupted: {error}"))),
        _ => Err(ApiError::Unavailable(format!("fleet run {id} was interrupted: the service is stopping"))),
    }
}

/// Stops a queued or running fleet run: a queued run never starts, a running one stops before
/// the next block of each machine (an endless program loop too). Answers the run as stored once
/// it has stopped: `cancelled` (`done` if it ended first).
#[utoipa::path(
    post,
    operation_id = "cancel_fleet_run",
    path = "/api/v1/fleet/runs/{id}/cancel",
    tag = "fleet",
    params(("id" = String, Path, description = "Fleet run id")),
    responses(
        (status = 200, description = "The run, stopped", body = FleetRunInfo),
        (status = 400, description = "A body that is not JSON (the action takes none: JSON is ignored)", body = ErrorBody),
        (status = 404, description = "No such run", body = ErrorBody),
        (status = 409, description = "The run is already over (done, cancelled or interrupted)", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn cancel(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    _: crate::http::extract::Bodyless,
) -> Result<Json<FleetRunInfo>, ApiError> {
    let id = path(id)?;
    let row = fleet_runs::cancel(&state.db, &state.fleet_runs, &id).await?;
    Ok(Json(FleetRunInfo::of(&row)))
}

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct Limit {
    /// At most this many runs, newest first (default 100, at most 10000).
    #[param(value_type = Option<u64>, maximum = 4294967295_u64)]
    pub limit: Option<u32>,
}

/// Fleet runs, newest first.
#[utoipa::path(
    get,
    operation_id = "list_fleet_runs",
    path = "/api/v1/fleet/runs",
    tag = "fleet",
    params(Limit),
    responses(
        (status = 200, description = "Fleet runs", body = [FleetRunInfo]),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn list(
    State(state): State<AppState>,
    q: Result<Query<Limit>, QueryRejection>,
) -> Result<Json<Vec<FleetRunInfo>>, ApiError> {
    let q = q.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
    let rows = fleet_runs::list(&state.db, q.limit.unwrap_or(100)).await?;
    Ok(Json(rows.iter().map(FleetRunInfo::of).collect()))
}

/// One fleet run: what was asked and, once done, the fleet array.
#[utoipa::path(
    get,
    operation_id = "get_fleet_run",
    path = "/api/v1/fleet/runs/{id}",
    tag = "fleet",
    params(("id" = String, Path, description = "Fleet run id")),
    responses(
        (status = 200, description = "The run", body = FleetRun),
        (status = 404, description = "No such run", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<FleetRun>, ApiError> {
    let id = path(id)?;
    let row = fleet_runs::get(&state.db, &id).await?;
    Ok(Json(FleetRun {
        info: FleetRunInfo::of(&row),
        request: serde_json::from_str(&row.request_json).unwrap_or(Value::Null),
        results: row.results_json.as_deref().and_then(|t| serde_json::from_str(t).ok()),
    }))
}

/// A fleet run's progress over a websocket: a `progress` message at once and whenever a
/// machine starts or finishes; the last one has `"finished": true`, then the socket closes. A
/// run that is already over sends its final state and closes.
#[utoipa::path(
    get,
    operation_id = "fleet_run_stream",
    path = "/api/v1/fleet/runs/{id}/stream",
    tag = "fleet",
    params(("id" = String, Path, description = "Fleet run id")),
    responses(
        (status = 101, description = "Websocket of progress messages", body = Progress),
        (status = 404, description = "No such run", body = ErrorBody),
        (status = 500, description = "Database error (logged, not returned)", body = ErrorBody),
    )
)]
pub async fn stream(
    State(state): State<AppState>,
    id: Result<Path<String>, PathRejection>,
    upgrade: WebSocketUpgrade,
) -> Result<Response, ApiError> {
    let id = path(id)?;
    let upgrade = super::stream::upgrade_small(upgrade);
    let progress = fleet_runs::follow(&state.db, &state.fleet_runs, &id).await?.ok();
    Ok(upgrade.on_upgrade(move |socket| session(socket, state, id, progress)))
}

/// The machines' names in the order of a stored request (`entries`' order), for those a
/// stopped run has no result for; an existing controller by its id (its name then is not
/// stored).
fn requested_names(request_json: &str) -> Vec<String> {
    let Ok(r) = serde_json::from_str::<FleetRequest>(request_json) else { return Vec::new() };
    let mut names = r.presets;
    names.extend(r.machines.iter().map(|m| m["name"].as_str().unwrap_or_default().to_string()));
    for name in r.library {
        if name == "*" {
            names.extend(crate::fleet::LIBRARY.iter().map(|(n, _)| n.to_string()));
        } else {
            names.push(name);
        }
    }
    names.extend(r.controllers);
    names
}

/// The progress of a stored run: final once it is over; under way (collected by another node
/// of a cluster), from the results recorded so far.
async fn stored_progress(state: &AppState, id: &str) -> Result<Progress, ApiError> {
    let row = fleet_runs::get(&state.db, id).await?;
    let total = row.machines as usize;
    let under_way = matches!(row.status.as_str(), "queued" | "running");
    let results: Vec<Value> = if under_way {
        let recorded = fleet_runs::recorded(&state.db, id, total).await.map_err(crate::service::ServiceError::from)?;
        recorded.into_iter().map(|r| r.unwrap_or(Value::Null)).collect()
    } else {
        row.results_json.as_deref().and_then(|t| serde_json::from_str(t).ok()).unwrap_or_default()
    };
    let names = requested_names(&row.request_json);
    Ok(Progress {
        kind: "progress",
        id: row.id.clone(),
        status: match row.status.as_str() {
            "queued" => "queued",
            "running" => "running",
            "done" => "done",
            "cancelled" => "cancelled",
            _ => "interrupted",
        },
        total,
        done: results.iter().filter(|r| !r.is_null()).count(),
        finished: !under_way,
        machines: results
            .iter()
            .enumerate()
            .map(|(i, r)| MachineProgress {
                machine: match r["machine"].as_str() {
                    Some(name) => name.to_string(),
                    None => names.get(i).cloned().unwrap_or_default(),
                },
                state: match &r["status"] {
                    Value::Null if under_way => "queued",
                    Value::Null => "cancelled",
                    s if s == "completed" => "completed",
                    _ => "alarm",
                },
                cycle_time_s: r["cycle_time_s"].as_f64(),
            })
            .collect(),
    })
}

/// How often the progress of a run collected by another node is read again.
const STORED_POLL: std::time::Duration = std::time::Duration::from_secs(1);

/// The progress websocket: from the run's own progress while this node runs or collects it,
/// else (and once this node hands it over) from the database, read every [`STORED_POLL`]
/// until the run is over.
async fn session(socket: WebSocket, state: AppState, id: String, rx: Option<watch::Receiver<Progress>>) {
    let _counted = state.metrics.subscriber(crate::metrics::Stream::FleetRun);
    let (mut tx, _) = socket.split();
    let text = |p: &Progress| Ws::Text(Utf8Bytes::from(serde_json::to_string(p).unwrap_or_default()));
    let mut closing = state.closing();
    let mut sent: Option<Progress> = None;
    if let Some(mut rx) = rx {
        loop {
            let p = rx.borrow_and_update().clone();
            if tx.send(text(&p)).await.is_err() {
                return;
            }
            let finished = p.finished;
            sent = Some(p);
            if finished {
                break;
            }
            tokio::select! {
                changed = rx.changed() => if changed.is_err() {
                    // The run's sender is gone: its final state (if not sent yet), or, handed
                    // over to another node, on from the database below.
                    let p = rx.borrow().clone();
                    if p.finished {
                        let _ = tx.send(text(&p)).await;
                        sent = Some(p);
                    }
                    break;
                },
                _ = closing.changed() => break,
            }
        }
    }
    while !sent.as_ref().is_some_and(|p| p.finished) && !state.is_closing() {
        let Ok(p) = stored_progress(&state, &id).await else { break };
        if sent.as_ref() != Some(&p) {
            if tx.send(text(&p)).await.is_err() {
                return;
            }
            sent = Some(p);
            continue;
        }
        tokio::select! {
            _ = tokio::time::sleep(STORED_POLL) => {}
            _ = closing.changed() => break,
        }
    }
    let _ = tx.send(Ws::Close(Some(CloseFrame { code: 1000, reason: Utf8Bytes::from_static("fleet run over") }))).await;
}

/// A machine of the library (`machines/`, `docs/fleet.md`).
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct LibraryMachine {
    #[schema(example = "trunnion-ac-120")]
    pub name: String,
    /// The mechanism, as a controller's status names it.
    #[schema(value_type = crate::wire::words::MechanismName)]
    pub kind: String,
    /// `fanuc`, `syntec` or `haas` for a vendor parameter list (it runs in that dialect); null for a
    /// model file (it runs in the fleet's dialect).
    #[schema(value_type = Option<fivex_engine::Dialect>)]
    pub dialect: Option<String>,
    /// The axis letters in order.
    pub axes: Vec<String>,
    /// The file as it is: what `POST /controllers` takes as `machine`.
    #[schema(value_type = MachineDocument)]
    pub machine: Value,
}

fn library_machine(name: &str, text: &str) -> Option<LibraryMachine> {
    let machine = fivex_engine::machine_file::parse(text).ok()?;
    Some(LibraryMachine {
        name: name.to_string(),
        kind: super::machine_kind(&machine),
        dialect: fivex_engine::machine_file::dialect_of(text).map(|d| d.name().to_string()),
        axes: machine.axes.iter().map(|a| a.name.to_string()).collect(),
        machine: serde_json::from_str(text).ok()?,
    })
}

/// The machine library, in name order: what `"library"` in a fleet run names.
#[utoipa::path(
    get,
    path = "/api/v1/fleet/library",
    tag = "fleet",
    responses(
        (status = 200, description = "Every library machine", body = [LibraryMachine]),
    )
)]
pub async fn library() -> Json<Vec<LibraryMachine>> {
    Json(crate::fleet::LIBRARY.iter().filter_map(|(name, text)| library_machine(name, text)).collect())
}

/// One library machine.
#[utoipa::path(
    get,
    path = "/api/v1/fleet/library/{name}",
    tag = "fleet",
    params(("name" = String, Path, description = "Library machine name")),
    responses(
        (status = 200, description = "The machine", body = LibraryMachine),
        (status = 404, description = "No such library machine", body = ErrorBody),
    )
)]
pub async fn library_one(name: Result<Path<String>, PathRejection>) -> Result<Json<LibraryMachine>, ApiError> {
    let name = crate::http::extract::path(name)?;
    crate::fleet::LIBRARY
        .iter()
        .find(|(n, _)| *n == name)
        .and_then(|(n, text)| library_machine(n, text))
        .map(Json)
        .ok_or_else(|| ApiError::NotFound(format!("no library machine '{name}'")))
}
