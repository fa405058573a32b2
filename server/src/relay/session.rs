//! One client's websocket of a controller hosted by another node, on the node the client asked
//! (the relaying node). It gets what a websocket on the owner gives, byte for byte: a snapshot
//! (asked of the owner for this client), the position right after it, then position frames at
//! the client's rate (paced here from the owner's full-rate feed, the newest winning, a frame
//! saying what the last one sent said skipped) and every event after the snapshot. When the
//! controller moves to another node the websocket stays open and gets a fresh snapshot from
//! there (a second snapshot, as after falling behind: docs/api.md, "Websocket streams").

use std::sync::Arc;

use axum::body::Body;
use axum::extract::ws::{close_code, Utf8Bytes, WebSocket, WebSocketUpgrade};
use axum::extract::{FromRequestParts, Request};
use axum::http::{HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use bytes::Bytes;
use futures_util::StreamExt;
use tokio::sync::broadcast::error::RecvError;
use tokio::time::Instant;

use super::hub::{Frame, Hub, Item};
use super::{snapshot_subject, SnapshotRequest, FOLLOW_LIMIT, SNAPSHOT_TIMEOUT, STATUS};
use crate::api::stream::{goodbye, rate_of, send_text, still_there, upgrade_small, Pace, Sink, CONTROLLER_DELETED};
use crate::host::now_unix_ms;
use crate::http::{ApiError, AppState};
use crate::placement::Cluster;

/// How long a session waits before it asks again for a snapshot that was refused.
const RETRY: std::time::Duration = std::time::Duration::from_secs(1);

/// The websocket `…/{id}/stream` of controller `id`, hosted by node `owner`: the upgrade and
/// the rate checked as on the owner, the first snapshot asked for (the owner's refusal, such as
/// a 404, answered as it is), then the session.
pub async fn open(state: AppState, cluster: Cluster, owner: String, id: String, request: Request) -> Response {
    let (mut parts, _) = request.into_parts();
    let upgrade = match WebSocketUpgrade::from_request_parts(&mut parts, &state).await {
        Ok(u) => u,
        Err(e) => return ApiError::Rejected(e.status(), e.body_text()).into_response(),
    };
    let rate = match rate_of(&parts.uri) {
        Ok(rate) => rate,
        Err(e) => return e.into_response(),
    };
    let hub = match cluster.relays().hubs.hub(&state, &cluster, &id, &owner).await {
        Ok(hub) => hub,
        Err(e) => return ApiError::Unavailable(e).into_response(),
    };
    // Subscribed to the hub before asking: the snapshot comes through it.
    let items = hub.items();
    let token = hub.token();
    match ask(&cluster, &owner, &hub, token).await {
        Ok(()) => {}
        Err(Refusal::Answer(status, body)) => {
            let mut response = Response::new(Body::from(body));
            *response.status_mut() = status;
            response.headers_mut().insert("content-type", HeaderValue::from_static("application/json"));
            return response;
        }
        Err(Refusal::Unanswered(e)) => {
            return ApiError::Unavailable(format!("controller's node {owner} did not take a snapshot: {e}"))
                .into_response()
        }
    }
    upgrade_small(upgrade).on_upgrade(move |socket| {
        let session = Session::new(socket, state, cluster, hub, items, rate, token);
        session.run()
    })
}

/// Why a snapshot was not taken.
enum Refusal {
    /// The owner's answer: its status and JSON error.
    Answer(StatusCode, Bytes),
    /// No answer (the node is gone, or NATS is).
    Unanswered(String),
}

/// Asks node `owner` to publish a snapshot of the hub's controller with `token`.
async fn ask(cluster: &Cluster, owner: &str, hub: &Hub, token: u64) -> Result<(), Refusal> {
    let request = SnapshotRequest { id: hub.id.clone(), relay: hub.relay.clone(), token };
    let payload = Bytes::from(serde_json::to_vec(&request).unwrap_or_default());
    let request = async_nats::Request::new().payload(payload).timeout(Some(SNAPSHOT_TIMEOUT));
    let answer = cluster
        .client()
        .send_request(snapshot_subject(owner), request)
        .await
        .map_err(|e| Refusal::Unanswered(e.to_string()))?;
    let status = answer.headers.as_ref().and_then(|h| h.get(STATUS)).and_then(|s| s.as_str().parse::<u16>().ok());
    match status {
        Some(101) => Ok(()),
        status => Err(Refusal::Answer(
            status.and_then(|s| StatusCode::from_u16(s).ok()).unwrap_or(StatusCode::BAD_GATEWAY),
            answer.payload,
        )),
    }
}

struct Session {
    tx: Sink,
    rx: futures_util::stream::SplitStream<WebSocket>,
    state: AppState,
    cluster: Cluster,
    hub: Arc<Hub>,
    items: tokio::sync::broadcast::Receiver<Item>,
    pace: Pace<Option<Frame>>,
    /// The token of the snapshot awaited.
    token: u64,
    /// The number of the snapshot sent last; `None` while one is awaited.
    synced: Option<u64>,
    /// The position frame sent last.
    sent: Utf8Bytes,
    /// Since when a snapshot is awaited.
    unsynced_since: Instant,
    /// When to ask again for the snapshot awaited.
    retry: std::pin::Pin<Box<tokio::time::Sleep>>,
}

impl Session {
    fn new(
        socket: WebSocket,
        state: AppState,
        cluster: Cluster,
        hub: Arc<Hub>,
        items: tokio::sync::broadcast::Receiver<Item>,
        rate: f64,
        token: u64,
    ) -> Session {
        let (tx, rx) = socket.split();
        let pace = Pace::new(hub.positions(), rate);
        Session {
            tx,
            rx,
            state,
            cluster,
            hub,
            items,
            pace,
            token,
            synced: None,
            sent: Utf8Bytes::from_static(""),
            unsynced_since: Instant::now(),
            retry: Box::pin(tokio::time::sleep(SNAPSHOT_TIMEOUT)),
        }
    }

    async fn run(mut self) {
        let _counted = self.hub.client();
        let mut closing = self.state.closing();
        let mut owner = self.hub.owner();
        loop {
            let go_on = tokio::select! {
                item = self.items.recv() => self.item(item).await,
                due = self.pace.due(), if self.synced.is_some() => match due {
                    Some(Some(frame)) => self.frame(frame).await,
                    Some(None) => true,
                    None => false,
                },
                _ = self.retry.as_mut(), if self.synced.is_none() => self.resync().await,
                changed = owner.changed(), if self.synced.is_none() => changed.is_ok() && self.resync().await,
                incoming = self.rx.next() => still_there(&incoming),
                _ = closing.changed() => {
                    goodbye(&mut self.tx, close_code::AWAY, "server shutting down".into()).await;
                    false
                }
            };
            if !go_on {
                break;
            }
        }
    }

    /// What the hub handed on; false when the session ends.
    async fn item(&mut self, item: Result<Item, RecvError>) -> bool {
        match item {
            Ok(Item::Snapshot { token, n, snapshot, position }) if self.synced.is_none() && token == self.token => {
                if !send_text(&mut self.tx, snapshot).await {
                    return false;
                }
                self.synced = Some(n);
                self.pace.restart();
                self.send_frame(position).await
            }
            Ok(Item::Event(text)) if self.synced.is_some() => send_text(&mut self.tx, text).await,
            Ok(Item::Resync) if self.synced.is_some() => self.resync().await,
            Ok(Item::Close(code, reason)) => {
                goodbye(&mut self.tx, code, reason).await;
                false
            }
            // Before its snapshot a session takes nothing: the snapshot holds it.
            Ok(_) => true,
            // Fell behind (events lost, or the snapshot awaited): a fresh snapshot, as the
            // local stream sends one.
            Err(RecvError::Lagged(_)) => self.resync().await,
            Err(RecvError::Closed) => false,
        }
    }

    /// A position frame of the hub, sent if it came after the snapshot and says something new.
    async fn frame(&mut self, frame: Frame) -> bool {
        if self.synced.is_some_and(|n| frame.n < n) || same_frame(&frame.text, &self.sent) {
            return true;
        }
        self.send_frame(frame.text).await
    }

    async fn send_frame(&mut self, text: Utf8Bytes) -> bool {
        let lag_s = wall_ms(&text).map_or(0.0, |at| (now_unix_ms() - at) / 1000.0);
        self.sent = text.clone();
        let sent = send_text(&mut self.tx, text).await;
        if sent {
            self.state.metrics.frame_sent(lag_s);
        }
        sent
    }

    /// Asks the controller's node for a fresh snapshot (while it is between nodes, waits for
    /// the hub to find it); false when the session ends (deleted, or not back in time).
    async fn resync(&mut self) -> bool {
        if self.synced.take().is_some() {
            tracing::debug!(id = %self.hub.id, "relayed stream: a fresh snapshot");
            self.unsynced_since = Instant::now();
        }
        if self.unsynced_since.elapsed() > FOLLOW_LIMIT {
            let reason = format!("no snapshot of the controller within {} s; reconnect", FOLLOW_LIMIT.as_secs());
            goodbye(&mut self.tx, 1012, reason.into()).await;
            return false;
        }
        self.token = self.hub.token();
        self.retry.as_mut().reset(Instant::now() + RETRY);
        let Some(owner) = self.hub.owner().borrow().clone() else { return true };
        match ask(&self.cluster, &owner, &self.hub, self.token).await {
            Ok(()) => self.retry.as_mut().reset(Instant::now() + SNAPSHOT_TIMEOUT),
            Err(Refusal::Answer(StatusCode::NOT_FOUND, _))
                if matches!(crate::db::controller(&self.state.db, &self.hub.id).await, Ok(None)) =>
            {
                goodbye(&mut self.tx, CONTROLLER_DELETED, "controller deleted".into()).await;
                return false;
            }
            Err(_) => {}
        }
        true
    }
}

/// Whether two position frames say the same but for `t` and `wall_ms` (then the second is not
/// sent, as the local stream compares its readings): the text from `"machine"` on, which
/// follows them (`host::stream::PositionFrame`'s field order; numbers written shortest
/// round-trip, so the same bits give the same text).
fn same_frame(a: &str, b: &str) -> bool {
    fn content(f: &str) -> Option<&str> {
        f.find(",\"machine\":").map(|at| &f[at..])
    }
    content(a).is_some_and(|c| Some(c) == content(b))
}

/// A frame's `wall_ms` (for the lag `/metrics` counts).
fn wall_ms(frame: &str) -> Option<f64> {
    frame.split("\"wall_ms\":").nth(1)?.split(',').next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_differing_only_in_time_are_the_same() {
        let a = r#"{"type":"position","t":1.5,"wall_ms":1700000000000.5,"machine":{"X":1.0},"line":3}"#;
        let b = r#"{"type":"position","t":2.5,"wall_ms":1700000000100,"machine":{"X":1.0},"line":3}"#;
        let c = r#"{"type":"position","t":2.5,"wall_ms":1700000000100,"machine":{"X":1.5},"line":3}"#;
        assert!(same_frame(a, b));
        assert!(!same_frame(a, c));
        assert!(!same_frame(a, ""));
        assert_eq!(wall_ms(a), Some(1700000000000.5));
        assert_eq!(wall_ms("{}"), None);
    }
}
