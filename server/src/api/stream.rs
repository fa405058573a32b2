//! `GET /controllers/{id}/stream`: a websocket with the controller's live state. The first
//! message is a snapshot (`{"type": "snapshot", "controller": status, "variables": {…},
//! "workpiece": {…}}`), the
//! next the position now; then position frames at most at the requested rate and only when
//! something in them changed (the newest wins, so a slow client sees fewer frames, never old
//! ones; each is encoded once and the same bytes go to every subscriber) and every event
//! message. A client that fell so far behind that events were dropped gets a fresh snapshot
//! instead. Nothing a client does
//! or fails to do slows a controller or another client.

use crate::http::extract::Addressed;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::rejection::QueryRejection;
use axum::extract::ws::rejection::WebSocketUpgradeRejection;
use axum::extract::ws::{close_code, CloseFrame, Message as Ws, Utf8Bytes, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::response::Response;
use futures_util::{SinkExt, StreamExt};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use tokio::sync::broadcast::error::RecvError;
use tokio::sync::watch;
use utoipa::{IntoParams, ToSchema};

use super::fleet_view::Update;
use super::ControllerStatus;
use crate::host::{now_unix_ms, Hosted, Published, Reading};
use crate::http::{ApiError, AppState, ErrorBody};
use crate::metrics::{Metrics, Stream};

/// Position frames per second by default, and the range a client may ask for.
pub const DEFAULT_RATE_HZ: f64 = 30.0;
const MAX_RATE_HZ: f64 = 1000.0;
const MIN_RATE_HZ: f64 = 0.1;

/// A client that cannot take a message within this time is dropped.
const SEND_TIMEOUT: Duration = Duration::from_secs(10);

/// The read buffer of every websocket the service accepts (tungstenite's default is 128 KiB).
/// tungstenite allocates it whole per connection and zero-fills it on every read attempt, so it
/// was resident: 128 KiB of every stream subscriber, more than a running controller holds
/// (`docs/performance.md`, "Memory per running controller"). It is not a limit: a frame longer
/// than the buffer gets a buffer of its length once its header is read; the size is only the
/// capacity kept and how much one read takes from the socket. Our clients send only control
/// frames (close, ping, pong: at most 2 + 4 + 125 = 131 bytes each; the web client sends
/// nothing else), so 256 bytes read any of them at once. What the service sends is written from
/// a buffer of its own that grows to the message (the write buffer size is a threshold for
/// sending, not an allocation; every send here is flushed at once).
const WS_READ_BUFFER: usize = 256;

/// A websocket upgrade with the service's buffer size ([`WS_READ_BUFFER`]).
pub(crate) fn upgrade_small(upgrade: WebSocketUpgrade) -> WebSocketUpgrade {
    upgrade.read_buffer_size(WS_READ_BUFFER)
}

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct StreamOptions {
    /// Position frames per second (0.1–1000, default 30).
    pub rate: Option<f64>,
}

/// The first message of a stream, and the one after a client fell behind.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Snapshot {
    /// Always `"snapshot"`.
    #[serde(rename = "type")]
    #[schema(value_type = crate::wire::words::SnapshotType, inline)]
    pub kind: &'static str,
    pub controller: ControllerStatus,
    /// Non-vacant common variables, `{"#500": 1.5}`.
    #[schema(value_type = std::collections::HashMap<String, f64>)]
    pub variables: Map<String, Value>,
    /// What is clamped on the table now (`GET …/workpiece`); a `workpiece` message tells a
    /// change.
    pub workpiece: fivex_engine::workpiece::Workpiece,
}

impl Snapshot {
    pub(crate) fn of(hosted: &Hosted) -> Snapshot {
        let station = hosted.station();
        let variables = station
            .controller
            .interpreter()
            .state
            .common_variables()
            .into_iter()
            .filter_map(|(n, v)| Some((format!("#{n}"), Value::Number(serde_json::Number::from_f64(v)?))))
            .collect();
        let workpiece = (**station.controller.workpiece()).clone();
        Snapshot { kind: "snapshot", controller: ControllerStatus::of(hosted, &station), variables, workpiece }
    }
}

/// Live positions, state changes, alarms and variables over a websocket.
#[utoipa::path(
    get,
    path = "/api/v1/controllers/{id}/stream",
    tag = "stream",
    params(("id" = String, Path, description = "Controller id"), StreamOptions),
    responses(
        (status = 101, description = "Websocket: a snapshot, then `position`, `state`, `alarm`, `variables`, `message` and `workpiece` objects; closed with 4404 \"controller deleted\" when the controller is deleted, 1001 when the service stops", body = Snapshot),
        (status = 400, description = "Not a websocket upgrade request", body = ErrorBody),
        (status = 404, description = "No such controller", body = ErrorBody),
        (status = 422, description = "Bad rate", body = ErrorBody),
    )
)]
pub async fn stream(
    State(state): State<AppState>,
    Addressed(hosted): Addressed,
    options: Result<Query<StreamOptions>, QueryRejection>,
    upgrade: Result<WebSocketUpgrade, WebSocketUpgradeRejection>,
) -> Result<Response, ApiError> {
    // After the lookup: an unknown (or deleted) controller is 404 whether or not the request
    // asks for a websocket.
    let upgrade = upgrade.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
    let rate = options.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?.rate.unwrap_or(DEFAULT_RATE_HZ);
    if !(rate.is_finite() && (MIN_RATE_HZ..=MAX_RATE_HZ).contains(&rate)) {
        return Err(ApiError::Unprocessable(
            format!("rate must be {MIN_RATE_HZ}–{MAX_RATE_HZ} frames per second"),
            None,
        ));
    }
    let closing = state.closing();
    let metrics = state.metrics.clone();
    let db = state.db.clone();
    Ok(upgrade_small(upgrade).on_upgrade(move |socket| {
        let (tx, rx) = socket.split();
        session(tx, rx, hosted, rate, closing, metrics, db)
    }))
}

/// The rate a stream request asks for (`?rate=`), checked.
pub fn rate_of(uri: &axum::http::Uri) -> Result<f64, ApiError> {
    let options =
        Query::<StreamOptions>::try_from_uri(uri).map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
    let rate = options.rate.unwrap_or(DEFAULT_RATE_HZ);
    if !(rate.is_finite() && (MIN_RATE_HZ..=MAX_RATE_HZ).contains(&rate)) {
        return Err(ApiError::Unprocessable(
            format!("rate must be {MIN_RATE_HZ}–{MAX_RATE_HZ} frames per second"),
            None,
        ));
    }
    Ok(rate)
}

async fn session(
    mut tx: Sink,
    mut rx: futures_util::stream::SplitStream<WebSocket>,
    hosted: Arc<Hosted>,
    rate: f64,
    mut closing: watch::Receiver<bool>,
    metrics: Metrics,
    db: crate::db::Db,
) {
    let mut pace = Pace::new(hosted.positions(), rate);
    let mut events = hosted.events();
    let removed = hosted.removed();
    tokio::pin!(removed);
    if !send(&mut tx, json(&Snapshot::of(&hosted))).await {
        return;
    }
    // Where the machine is now, once: the watch only carries changes, and an idle controller
    // makes none.
    let now = Arc::new(Published::new(Reading::of(&hosted.station())));
    if !send_frame(&mut tx, &now, &metrics).await {
        return;
    }
    // What this client was sent last: the first publication after a quiet spell may say the same.
    let mut sent = now;
    loop {
        let ok = tokio::select! {
            due = pace.due() => match due {
                Some(Some(published)) if !published.reading.same_frame(&sent.reading) => {
                    sent = published;
                    send_frame(&mut tx, &sent, &metrics).await
                }
                Some(_) => true,
                None => false,
            },
            event = events.recv() => match event {
                Ok(message) => send(&mut tx, json(&*message)).await,
                Err(RecvError::Lagged(_)) => send(&mut tx, json(&Snapshot::of(&hosted))).await,
                Err(RecvError::Closed) => false,
            },
            incoming = rx.next() => still_there(&incoming),
            _ = closing.changed() => {
                goodbye(&mut tx, close_code::AWAY, "server shutting down".into()).await;
                false
            }
            () = &mut removed => {
                // Gone from this node but still stored: another node of the cluster hosts it
                // now (this one was cut off, or handed it over). Not "deleted": reconnect.
                if crate::service::controllers::still_stored(&db, &hosted.id).await {
                    let reason = format!("controller {}: hosted by another node now; reconnect", hosted.id);
                    goodbye(&mut tx, CONTROLLER_MOVED, reason.into()).await;
                } else {
                    goodbye(&mut tx, CONTROLLER_DELETED, "controller deleted".into()).await;
                }
                false
            }
        };
        if !ok {
            break;
        }
    }
}

/// The pace of a stream's position frames, at most `rate` a second, the newest winning: after a
/// frame, wait out the period, then hand on the newest position if it changed, or else wait for
/// a change and hand it on at once. One wake-up per frame while the machine moves; none while it
/// stands. Shared by the local stream and the relayed one (`crate::relay`), which paces the
/// owner's full-rate feed here, at the client's node.
pub(crate) struct Pace<T> {
    positions: watch::Receiver<T>,
    period: Duration,
    sleep: std::pin::Pin<Box<tokio::time::Sleep>>,
    pacing: bool,
}

impl<T: Clone> Pace<T> {
    /// Paces `positions`, starting with a period to wait out (a frame was just sent).
    pub(crate) fn new(positions: watch::Receiver<T>, rate: f64) -> Pace<T> {
        let period = Duration::from_secs_f64(1.0 / rate);
        Pace { positions, period, sleep: Box::pin(tokio::time::sleep(period)), pacing: true }
    }

    /// A frame was just sent from elsewhere (a snapshot's): wait out a period, then look at the
    /// newest position whether or not it changed since this pace last looked.
    pub(crate) fn restart(&mut self) {
        self.positions.mark_changed();
        self.pacing = true;
        self.sleep.as_mut().reset(tokio::time::Instant::now() + self.period);
    }

    /// The newest position when one is due (the caller sends it unless it says what the last one
    /// sent said); `None` when the positions end. Cancel-safe: nothing changes across an await.
    pub(crate) async fn due(&mut self) -> Option<T> {
        loop {
            if self.pacing {
                self.sleep.as_mut().await;
                self.pacing = self.positions.has_changed().unwrap_or(false);
                if !self.pacing {
                    continue;
                }
            } else {
                self.positions.changed().await.ok()?;
                self.pacing = true;
            }
            self.sleep.as_mut().reset(tokio::time::Instant::now() + self.period);
            return Some(self.positions.borrow_and_update().clone());
        }
    }
}

/// The close code of a controller's stream when the controller is deleted (4000–4999 are for
/// applications; 4404 reads as "not found").
pub const CONTROLLER_DELETED: u16 = 4404;
/// Close code when the controller left this node for another of the cluster (1012, "service
/// restart": reconnecting, through any node, reaches it there).
pub const CONTROLLER_MOVED: u16 = 1012;

pub(crate) type Sink = futures_util::stream::SplitSink<WebSocket, Ws>;

/// Send a position frame, counted with its age (the wall clock now, as the service hands it
/// to the socket, minus the worker's reading: the part of the lag the service can see).
async fn send_frame(tx: &mut Sink, frame: &Published, metrics: &Metrics) -> bool {
    let lag_s = (now_unix_ms() - frame.reading.wall_ms()) / 1000.0;
    let sent = send_text(tx, frame.text()).await;
    if sent {
        metrics.frame_sent(lag_s);
    }
    sent
}

/// What the client sent, as whether it is still there (a close, an error or the end: gone).
pub(crate) fn still_there(incoming: &Option<Result<Ws, axum::Error>>) -> bool {
    !matches!(incoming, None | Some(Err(_)) | Some(Ok(Ws::Close(_))))
}

/// Close with `code` and `reason` (not waiting long for a slow client): 1001 "going away" when
/// the service shuts down, [`CONTROLLER_DELETED`] when the controller is deleted.
pub(crate) async fn goodbye(tx: &mut Sink, code: u16, reason: Utf8Bytes) {
    let bye = CloseFrame { code, reason };
    let _ = tokio::time::timeout(Duration::from_secs(1), tx.send(Ws::Close(Some(bye)))).await;
}

/// Send one text message; false if the client is gone or does not take it in time.
async fn send(tx: &mut Sink, text: String) -> bool {
    send_text(tx, Utf8Bytes::from(text)).await
}

/// [`send`] of text encoded already (shared with other subscribers).
pub(crate) async fn send_text(tx: &mut Sink, text: Utf8Bytes) -> bool {
    matches!(tokio::time::timeout(SEND_TIMEOUT, tx.send(Ws::Text(text))).await, Ok(Ok(())))
}

pub(crate) fn json<T: Serialize>(value: &T) -> String {
    serde_json::to_string(value).unwrap_or_else(|e| format!("{{\"type\":\"error\",\"error\":\"{e}\"}}"))
}

/// One controller in the fleet stream.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct FleetEntry {
    pub id: String,
    pub name: String,
    pub machine: String,
    /// The mechanism kind, as in the status.
    #[schema(value_type = crate::wire::words::MechanismName)]
    pub kind: String,
    #[schema(value_type = fivex_engine::Dialect)]
    pub dialect: String,
    #[schema(value_type = fivex_engine::controller::Mode)]
    pub mode: String,
    #[schema(value_type = fivex_engine::controller::RunState)]
    pub run_state: String,
    pub program: Option<u32>,
    /// 1-based line of the executing block in the program `line_program`, as in the status.
    pub line: u32,
    /// The O number of the stored program `line` is in (`program`, or a program it called);
    /// `null` for MDI's own blocks and before any block.
    pub line_program: Option<u32>,
    /// The first alarm in force, if any.
    pub alarm: Option<crate::host::stream::AlarmInfo>,
}

/// `{"type": "fleet", "controllers": […]}`.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Fleet {
    /// Always `"fleet"`.
    #[serde(rename = "type")]
    #[schema(value_type = crate::wire::words::FleetType, inline)]
    pub kind: &'static str,
    pub controllers: Vec<FleetEntry>,
}

/// `{"type": "fleet_delta", "controllers": […], "removed": […]}`: what changed since the
/// message before (apply `removed` first, then put each entry in place of the one with its id,
/// or after the others when it is new).
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct FleetDelta {
    /// Always `"fleet_delta"`.
    #[serde(rename = "type")]
    #[schema(value_type = crate::wire::words::FleetDeltaType, inline)]
    pub kind: &'static str,
    /// The controllers that changed or were added, whole.
    pub controllers: Vec<FleetEntry>,
    /// The ids of the controllers removed.
    pub removed: Vec<String>,
}

#[derive(Debug, Clone, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct FleetOptions {
    /// Fleet messages per second (0.1–30, default 2); one is sent only when something changed.
    pub rate: Option<f64>,
    /// `false`: every message is the whole fleet (`fleet`), as before deltas (default `true`).
    pub deltas: Option<bool>,
}

/// The status of every controller over a websocket: `{"type": "fleet", "controllers": […]}`
/// at once, then `{"type": "fleet_delta", "controllers": [changed], "removed": [ids]}` whenever
/// something changed (checked at the requested rate); with `deltas=false` the whole fleet each
/// time.
#[utoipa::path(
    get,
    path = "/api/v1/stream",
    tag = "stream",
    params(FleetOptions),
    responses(
        (status = 101, description = "Websocket: a `fleet` message, then `fleet_delta` messages (FleetDelta)", body = Fleet),
        (status = 422, description = "Bad rate", body = ErrorBody),
    )
)]
pub async fn fleet(
    State(state): State<AppState>,
    options: Result<Query<FleetOptions>, QueryRejection>,
    upgrade: WebSocketUpgrade,
) -> Result<Response, ApiError> {
    let options = options.map_err(|e| ApiError::Rejected(e.status(), e.body_text()))?;
    let rate = options.rate.unwrap_or(2.0);
    if !(rate.is_finite() && (0.1..=30.0).contains(&rate)) {
        return Err(ApiError::Unprocessable("rate must be 0.1–30 messages per second".into(), None));
    }
    let deltas = options.deltas.unwrap_or(true);
    Ok(upgrade_small(upgrade).on_upgrade(move |socket| fleet_session(socket, state, rate, deltas)))
}

async fn fleet_session(socket: WebSocket, state: AppState, rate: f64, deltas: bool) {
    let _counted = state.metrics.subscriber(Stream::Fleet);
    let (mut tx, mut rx) = socket.split();
    let mut closing = state.closing();
    let mut every = tokio::time::interval(Duration::from_secs_f64(1.0 / rate));
    every.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let view = state.fleet_view.clone();
    let mut seen = None;
    loop {
        let ok = tokio::select! {
            _ = every.tick() => {
                view.refresh(&state.host).await;
                let (update, version) = view.since(seen, deltas);
                seen = Some(version);
                match update {
                    Update::None => true,
                    Update::Snapshot(text) | Update::Delta(text) => send(&mut tx, text).await,
                }
            }
            incoming = rx.next() => still_there(&incoming),
            _ = closing.changed() => {
                goodbye(&mut tx, close_code::AWAY, "server shutting down".into()).await;
                false
            }
        };
        if !ok {
            break;
        }
    }
}
