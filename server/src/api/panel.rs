//! The operator panel: cycle start, feed hold, reset, MDI, mode, overrides, switches and the
//! emergency stop. Each answers the controller's status after the action; an action the panel
//! would ignore in this state is 409 with the reason.

use crate::http::extract::Addressed;
use axum::extract::{Json, State};
use fivex_engine::controller::{Mode, Refusal};
use serde::Deserialize;
use utoipa::ToSchema;

use super::ControllerStatus;
use crate::host::{Hosted, Station};
use crate::http::extract::body;
use crate::http::extract::JsonBody;
use crate::http::{ApiError, AppState, ErrorBody};

/// Why the panel ignored an action, for a person.
pub(super) fn refused(r: Refusal) -> ApiError {
    ApiError::Conflict(
        match r {
            Refusal::WrongMode => "not possible in this mode",
            Refusal::Busy => "not possible while the controller runs, holds or is in alarm",
            Refusal::NoProgram => "there is no program to run",
            Refusal::NoAxis => "no such axis (or no 5-axis mechanism for this feed)",
            Refusal::BadValue => "the value is not a finite number in range",
        }
        .into(),
    )
}

/// Apply `action` to the station, send out what it caused, and answer the status.
pub(super) fn act(
    state: &AppState,
    hosted: &Hosted,
    action: impl FnOnce(&mut Station) -> Result<(), ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let (result, messages, records, status) = {
        let mut station = hosted.station();
        let result = action(&mut station);
        let (messages, records) = station.collect(&hosted.id, 0.0, true);
        (result, messages, records, ControllerStatus::of(hosted, &station))
    };
    for r in records {
        state.host.record(r);
    }
    hosted.publish(messages);
    result.map(|()| Json(status))
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
    )
)]
pub async fn cycle_start(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    body: axum::body::Bytes,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = optional_json::<CycleStart>(&body)?;
    let text = match request.program {
        Some(n) => Some((n, crate::service::programs::composed(&state.db, &hosted, n).await?)),
        None => None,
    };
    act(&state, &hosted, |station| {
        let c = &mut station.controller;
        let fresh = c.run_state() == fivex_engine::controller::RunState::Idle;
        if let Some((n, text)) = &text {
            if !fresh {
                return Err(ApiError::Conflict(
                    "a program is under way: resume it with an empty cycle start, or reset first".into(),
                ));
            }
            if c.mode() != Mode::Auto {
                c.set_mode(Mode::Auto).map_err(refused)?;
            }
            c.select_program(text).map_err(refused)?;
            c.cycle_start().map_err(refused)?;
            station.begin_run(Some(*n));
        } else {
            c.cycle_start().map_err(refused)?;
            if fresh {
                let program = if c.mode() == Mode::Auto { station.program } else { None };
                station.begin_run(program);
            }
        }
        Ok(())
    })
}

/// Feed hold: decelerate along the path and wait for cycle start.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/feed-hold",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Holding (or nothing was running)", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn feed_hold(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
) -> Result<Json<ControllerStatus>, ApiError> {
    act(&state, &hosted, |station| {
        station.controller.feed_hold();
        Ok(())
    })
}

/// Reset: stop, abandon the program, clear the alarms.
#[utoipa::path(
    post,
    path = "/api/v1/controllers/{id}/reset",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    responses(
        (status = 200, description = "Reset", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn reset(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
) -> Result<Json<ControllerStatus>, ApiError> {
    act(&state, &hosted, |station| {
        if let Some(record) = station.end_run(&hosted.id, "reset") {
            state.host.record(record);
        }
        station.controller.reset();
        Ok(())
    })
}

/// `POST /mdi`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Mdi {
    /// NC blocks to run.
    #[schema(example = "G91 G01 X10. F100")]
    pub text: String,
}

/// MDI: switch to MDI mode (when idle) and run the blocks.
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
        (status = 422, description = "Not an MDI request", body = ErrorBody),
    )
)]
pub async fn mdi(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Mdi>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    if request.text.len() > super::programs::MAX_PROGRAM_BYTES {
        return Err(ApiError::Unprocessable("MDI text too long".into(), None));
    }
    act(&state, &hosted, |station| {
        let c = &mut station.controller;
        if c.mode() != Mode::Mdi {
            c.set_mode(Mode::Mdi).map_err(refused)?;
        }
        c.set_mdi(&request.text).map_err(refused)?;
        c.cycle_start().map_err(refused)?;
        station.begin_run(None);
        Ok(())
    })
}

/// The modes `PUT /mode` takes (the document's enum; the handler reads the word).
#[allow(dead_code)]
#[derive(ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum ModeName {
    Auto,
    Mdi,
    Jog,
    Handle,
    Ref,
    Inc,
}

/// `PUT /mode`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SetMode {
    /// `auto`, `mdi`, `jog`, `handle`, `ref` or `inc`.
    #[schema(example = "jog", value_type = ModeName)]
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
    )
)]
pub async fn set_mode(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<SetMode>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let mode = match body(request)?.mode.to_ascii_lowercase().as_str() {
        "auto" => Mode::Auto,
        "mdi" => Mode::Mdi,
        "jog" => Mode::Jog,
        "handle" => Mode::Handle,
        "ref" => Mode::Ref,
        "inc" => Mode::Inc,
        other => {
            return Err(ApiError::Unprocessable(
                format!("unknown mode '{other}' (auto, mdi, jog, handle, ref, inc)"),
                None,
            ))
        }
    };
    act(&state, &hosted, |station| station.controller.set_mode(mode).map_err(refused))
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
}

/// Feed and rapid override; the motion under way changes speed at once within the limits.
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
    )
)]
pub async fn set_overrides(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Overrides>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    let within = |v: Option<f64>, max: f64, what: &str| match v {
        Some(p) if !(p.is_finite() && (0.0..=max).contains(&p)) => {
            Err(ApiError::Unprocessable(format!("{what} override must be 0–{max} %"), None))
        }
        other => Ok(other.map(|p| p / 100.0)),
    };
    let (feed, rapid) = (within(request.feed, 200.0, "feed")?, within(request.rapid, 100.0, "rapid")?);
    act(&state, &hosted, |station| {
        let c = &mut station.controller;
        let (f, r) = (feed.unwrap_or(c.panel.feed_override), rapid.unwrap_or(c.panel.rapid_override));
        c.set_overrides(f, r);
        Ok(())
    })
}

/// `PUT /switches`.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Switches {
    pub single_block: Option<bool>,
    pub optional_stop: Option<bool>,
    pub block_delete: Option<bool>,
}

/// Single block, optional stop (M01) and block delete (`/`).
#[utoipa::path(
    put,
    path = "/api/v1/controllers/{id}/switches",
    tag = "panel",
    params(("id" = String, Path, description = "Controller id")),
    request_body = Switches,
    responses(
        (status = 200, description = "Set", body = ControllerStatus),
        (status = 404, description = "No such controller", body = ErrorBody),
    )
)]
pub async fn set_switches(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<Switches>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let request = body(request)?;
    act(&state, &hosted, |station| {
        let p = &mut station.controller.panel;
        p.single_block = request.single_block.unwrap_or(p.single_block);
        p.optional_stop = request.optional_stop.unwrap_or(p.optional_stop);
        p.block_delete = request.block_delete.unwrap_or(p.block_delete);
        Ok(())
    })
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
    )
)]
pub async fn emergency_stop(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    request: Result<JsonBody<EmergencyStop>, ApiError>,
) -> Result<Json<ControllerStatus>, ApiError> {
    let pressed = body(request)?.pressed;
    act(&state, &hosted, |station| {
        if pressed {
            if let Some(record) = station.end_run(&hosted.id, "alarm") {
                state.host.record(record);
            }
        }
        station.controller.emergency_stop(pressed);
        Ok(())
    })
}
