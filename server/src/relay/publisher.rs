//! The owner's side: one publisher per hosted controller that some relaying node is interested
//! in, publishing the controller's stream on `fivex.controllers.{id}.stream.*`, and the answers
//! to snapshot requests. Publishing ends when no relaying node said it is interested for
//! [`IDLE`](super::IDLE) (one that leaves says so at once), when the controller leaves this
//! node (`gone`: relaying nodes look for it elsewhere) or is deleted (`close`), and when this
//! node stops (`gone`).

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use async_nats::HeaderMap;
use axum::response::IntoResponse;
use bytes::{Bytes, BytesMut};
use tokio::sync::broadcast::error::{RecvError, TryRecvError};
use tokio::sync::{broadcast, mpsc, oneshot, watch};

use super::{lock, stream_subject, SnapshotRequest, ALIVE, IDLE, INTEREST, SEQ, SNAPSHOT_TIMEOUT, STATUS, TOKEN};
use crate::api::stream::{json, Snapshot};
use crate::host::{Hosted, Message, Published, Reading};
use crate::http::{ApiError, AppState};

/// The controllers whose stream this node publishes, by id.
#[derive(Default)]
pub struct Publishers {
    running: Arc<Mutex<HashMap<String, Handle>>>,
    generation: AtomicU64,
}

/// A running publisher: who is interested, and its queue of snapshot requests.
#[derive(Clone)]
struct Handle {
    generation: u64,
    /// Relaying hub (`NODE/N`) → when it last said it is interested.
    interest: Arc<Mutex<HashMap<String, Instant>>>,
    takes: mpsc::UnboundedSender<Take>,
}

/// A snapshot to publish with `token`; `done` once it is out.
struct Take {
    token: u64,
    done: oneshot::Sender<()>,
}

impl Publishers {
    /// How many controllers' streams this node publishes.
    pub fn count(&self) -> usize {
        lock(&self.running).len()
    }

    /// The publisher of `hosted`'s stream, started if none runs; `relay` is interested now.
    fn interested(&self, state: &AppState, client: &async_nats::Client, hosted: &Arc<Hosted>, relay: &str) -> Handle {
        let mut running = lock(&self.running);
        if let Some(handle) = running.get(&hosted.id).filter(|h| !h.takes.is_closed()) {
            lock(&handle.interest).insert(relay.to_string(), Instant::now());
            return handle.clone();
        }
        let (takes, incoming) = mpsc::unbounded_channel();
        let handle = Handle {
            generation: self.generation.fetch_add(1, Ordering::Relaxed),
            interest: Arc::new(Mutex::new(HashMap::from([(relay.to_string(), Instant::now())]))),
            takes,
        };
        running.insert(hosted.id.clone(), handle.clone());
        // Subscribed here, before anything is asked of it: every event from now on goes out.
        let publisher = Publisher {
            out: Out { client: client.clone(), id: hosted.id.clone(), seq: 0 },
            node: state.cluster.as_ref().map(|c| c.name().to_string()).unwrap_or_default(),
            positions: hosted.positions(),
            events: hosted.events(),
            hosted: hosted.clone(),
            state: state.clone(),
            incoming,
            handle: handle.clone(),
            running: self.running.clone(),
        };
        tokio::spawn(publisher.run());
        tracing::info!(id = %hosted.id, %relay, "publishing the controller's stream for relaying nodes");
        handle
    }

    /// `relay` is no longer interested in controller `id` (its last client left).
    fn not_interested(&self, id: &str, relay: &str) {
        if let Some(handle) = lock(&self.running).get(id) {
            lock(&handle.interest).remove(relay);
        }
    }
}

/// A message on `fivex.controllers.*.interest`: a relaying node keeps (or ends) its interest in
/// a controller's stream. A controller hosted here starts being published.
pub fn interest(state: &AppState, client: &async_nats::Client, message: async_nats::Message) {
    let Some(cluster) = &state.cluster else { return };
    let Some(id) = message.subject.as_str().split('.').nth(2) else { return };
    let relay = String::from_utf8_lossy(&message.payload).into_owned();
    let publishers = &cluster.relays().publishers;
    if message.headers.as_ref().and_then(|h| h.get(INTEREST)).is_some_and(|v| v.as_str() == "end") {
        publishers.not_interested(id, &relay);
    } else if let Some(hosted) = state.host.get(id).filter(|_| !state.is_closing()) {
        // (A node that stops publishes nothing more: the relaying nodes follow the controller.)
        publishers.interested(state, client, &hosted, &relay);
    }
}

/// A request on `fivex.nodes.{this node}.stream`: publishes a snapshot of a controller hosted
/// here on its `snapshot` subject and answers `fivex-status: 101`, or the error (404: not
/// hosted here) as a forwarded request's answer.
pub async fn snapshot(state: AppState, client: async_nats::Client, message: async_nats::Message) {
    let Some(reply) = message.reply.clone() else { return };
    let taken = async {
        let request: SnapshotRequest = serde_json::from_slice(&message.payload)
            .map_err(|e| ApiError::BadRequest(format!("not a snapshot request: {e}")))?;
        let Some(cluster) = state.cluster.as_ref().filter(|_| !state.is_closing()) else {
            return Err(ApiError::Unavailable("the node is stopping".into()));
        };
        // Twice: a publisher that was just ending takes no more requests; a new one does.
        for _ in 0..2 {
            let hosted = state
                .host
                .get(&request.id)
                .ok_or_else(|| ApiError::NotFound(format!("no controller {}", request.id)))?;
            let handle = cluster.relays().publishers.interested(&state, &client, &hosted, &request.relay);
            let (done, published) = oneshot::channel();
            if handle.takes.send(Take { token: request.token, done }).is_err() {
                continue;
            }
            match tokio::time::timeout(SNAPSHOT_TIMEOUT, published).await {
                Ok(Ok(())) => return Ok(()),
                Ok(Err(_)) => continue,
                Err(_) => break,
            }
        }
        Err(ApiError::Unavailable(format!("the stream of controller {} is not published", request.id)))
    }
    .await;
    let (status, body) = match taken {
        Ok(()) => (101, Bytes::new()),
        Err(e) => {
            let response = e.into_response();
            let status = response.status().as_u16();
            (status, axum::body::to_bytes(response.into_body(), 1 << 20).await.unwrap_or_default())
        }
    };
    let mut headers = HeaderMap::new();
    headers.insert(STATUS, status.to_string().as_str());
    headers.insert("content-type", "application/json");
    let _ = client.publish_with_headers(reply, headers, body).await;
}

/// The messages of one controller's stream, numbered ([`SEQ`]) from its `start`.
struct Out {
    client: async_nats::Client,
    id: String,
    seq: u64,
}

impl Out {
    /// A numbered message of `kind` (`start` numbers from 0 again).
    async fn numbered(&mut self, kind: &str, extra: Option<(&str, String)>, payload: Bytes) {
        self.seq = if kind == "start" { 0 } else { self.seq + 1 };
        let mut headers = HeaderMap::new();
        headers.insert(SEQ, self.seq.to_string().as_str());
        if let Some((name, value)) = extra {
            headers.insert(name, value.as_str());
        }
        if let Err(e) = self.client.publish_with_headers(stream_subject(&self.id, kind), headers, payload).await {
            tracing::warn!(id = %self.id, error = %e, "stream message not published");
        }
    }

    /// A position frame: not numbered (a lost one is replaced by the next: the newest wins).
    async fn position(&mut self, published: &Published) {
        let text = Bytes::copy_from_slice(published.text().as_bytes());
        let _ = self.client.publish(stream_subject(&self.id, "position"), text).await;
    }

    async fn event(&mut self, message: &Message) {
        self.numbered("event", None, Bytes::from(json(message))).await;
    }
}

struct Publisher {
    out: Out,
    /// This node's name (the payload of `start` and `gone`).
    node: String,
    positions: watch::Receiver<Option<Arc<Published>>>,
    events: broadcast::Receiver<Arc<Message>>,
    hosted: Arc<Hosted>,
    state: AppState,
    incoming: mpsc::UnboundedReceiver<Take>,
    handle: Handle,
    running: Arc<Mutex<HashMap<String, Handle>>>,
}

/// Why a publisher ended.
enum End {
    /// No relaying node is interested any more.
    Idle,
    /// The controller is no longer hosted here (dropped, or this node stops): relaying nodes
    /// look for it on its new node.
    Gone,
    /// The controller was deleted.
    Deleted,
}

impl Publisher {
    async fn run(mut self) {
        let id = self.hosted.id.clone();
        let removed = self.hosted.removed();
        tokio::pin!(removed);
        let mut closing = self.state.closing();
        let mut check = tokio::time::interval(ALIVE);
        check.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        self.out.numbered("start", None, Bytes::from(self.node.clone())).await;
        let end = loop {
            tokio::select! {
                changed = self.positions.changed() => {
                    if changed.is_err() {
                        break End::Gone;
                    }
                    let latest = self.positions.borrow_and_update().clone();
                    if let Some(published) = latest {
                        self.out.position(&published).await;
                    }
                }
                event = self.events.recv() => match event {
                    Ok(message) => self.out.event(&message).await,
                    // Events lost: a new start, so the relaying nodes take fresh snapshots.
                    Err(RecvError::Lagged(_)) => self.out.numbered("start", None, Bytes::from(self.node.clone())).await,
                    Err(RecvError::Closed) => break End::Gone,
                },
                take = self.incoming.recv() => match take {
                    Some(take) => self.snapshot(take).await,
                    None => break End::Idle,
                },
                _ = check.tick() => {
                    let mut running = lock(&self.running);
                    let mut interest = lock(&self.handle.interest);
                    interest.retain(|_, at| at.elapsed() < IDLE);
                    if interest.is_empty() {
                        // Under both locks: an interest arriving now finds no publisher and
                        // starts a new one.
                        if running.get(&id).is_some_and(|h| h.generation == self.handle.generation) {
                            running.remove(&id);
                        }
                        break End::Idle;
                    }
                }
                () = &mut removed => {
                    let stored = crate::db::controller(&self.state.db, &id).await;
                    break if matches!(stored, Ok(None)) { End::Deleted } else { End::Gone };
                }
                // `wait_for`, not `changed`: a publisher started while the node stops ends at once.
                _ = async { closing.wait_for(|c| *c).await.is_ok() } => break End::Gone,
            }
        };
        {
            let mut running = lock(&self.running);
            if running.get(&id).is_some_and(|h| h.generation == self.handle.generation) {
                running.remove(&id);
            }
        }
        match end {
            End::Idle => tracing::info!(%id, "stream no longer published: no relaying node is interested"),
            End::Gone => self.out.numbered("gone", None, Bytes::from(self.node.clone())).await,
            End::Deleted => {
                let reason = format!("{} controller deleted", crate::api::stream::CONTROLLER_DELETED);
                self.out.numbered("close", None, Bytes::from(reason)).await
            }
        }
        let _ = self.out.client.flush().await;
    }

    /// Publishes a snapshot behind every event already out (a relaying node drops what came
    /// before it: the snapshot holds it): the snapshot message, a newline, the position now.
    async fn snapshot(&mut self, take: Take) {
        loop {
            match self.events.try_recv() {
                Ok(message) => self.out.event(&message).await,
                Err(TryRecvError::Lagged(_)) => self.out.numbered("start", None, Bytes::from(self.node.clone())).await,
                Err(_) => break,
            }
        }
        let snapshot = json(&Snapshot::of(&self.hosted));
        let now = Published::new(Reading::of(&self.hosted.station()));
        let mut payload = BytesMut::with_capacity(snapshot.len() + 1 + 1024);
        payload.extend_from_slice(snapshot.as_bytes());
        payload.extend_from_slice(b"\n");
        payload.extend_from_slice(now.text().as_bytes());
        self.out.numbered("snapshot", Some((TOKEN, take.token.to_string())), payload.freeze()).await;
        let _ = take.done.send(());
    }
}
