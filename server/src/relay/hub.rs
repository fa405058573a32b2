//! The relaying node's side: one hub per controller of another node that some of this node's
//! websocket clients watch. A hub holds the one NATS subscription to the controller's stream
//! subjects, says every [`ALIVE`] that this node is interested (so the owner keeps publishing),
//! and hands what arrives to its clients' sessions: the newest position frame in a `watch`
//! (each session paces it at its own rate), everything else in a `broadcast` in arrival order.
//! Every message gets a number in that order, so a session tells what came before its snapshot.
//!
//! It follows its controller: when the owner leaves the members or says `gone`, the hub waits
//! for a placement on a member (a new one, not the old owner's), tells its sessions to take a
//! fresh snapshot there, and closes them with 1012 when none comes within [`FOLLOW_LIMIT`],
//! 4404 when the controller was deleted meanwhile. The subscription does not change: the
//! subjects are the controller's, whichever node publishes them.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, Weak};

use async_nats::HeaderMap;
use axum::extract::ws::Utf8Bytes;
use bytes::Bytes;
use futures_util::StreamExt;
use tokio::sync::{broadcast, oneshot, watch};
use tokio::time::Instant;

use super::{interest_subject, lock, stream_subjects, ALIVE, FOLLOW_LIMIT, INTEREST, SEQ, TOKEN};
use crate::http::AppState;
use crate::placement::view::Placed;
use crate::placement::Cluster;

/// Messages a session may fall behind by before it takes a fresh snapshot (as the local stream).
const BUFFER: usize = 1024;

/// What a hub hands its sessions, in the order it came (positions aside, in the `watch`).
#[derive(Debug, Clone)]
pub enum Item {
    /// An event message (`state`, `alarm`, `variables`, `message`), the owner's text.
    Event(Utf8Bytes),
    /// The snapshot asked for with `token`: the snapshot message and the position then.
    Snapshot { token: u64, n: u64, snapshot: Utf8Bytes, position: Utf8Bytes },
    /// Something may have been lost (the owner started publishing again, a message is
    /// missing, the controller moved to another node): take a fresh snapshot.
    Resync,
    /// The stream ends: close the websocket with this code and reason.
    Close(u16, Utf8Bytes),
}

/// A position frame as the owner published it, with its number among the hub's messages.
#[derive(Debug, Clone)]
pub struct Frame {
    pub n: u64,
    pub text: Utf8Bytes,
}

/// This node's hubs, by controller id.
#[derive(Default)]
pub struct Hubs {
    hubs: Arc<Mutex<HashMap<String, Weak<Hub>>>>,
    generation: AtomicU64,
    /// Hubs whose subscription is open.
    subscriptions: Arc<AtomicUsize>,
    /// Sessions (websocket clients) of all hubs.
    clients: Arc<AtomicUsize>,
}

/// One controller's hub, shared by its sessions; the last one dropped ends it (its subscription
/// closed, the owner told this node is no longer interested).
pub struct Hub {
    pub id: String,
    /// This hub's name in interest and snapshot requests: `NODE/N`.
    pub relay: String,
    items: broadcast::Sender<Item>,
    // Held here as well as by the hub's task: they end with the hub's last session, never
    // before it reads the hub's last message.
    positions: Arc<watch::Sender<Option<Frame>>>,
    owner: Arc<watch::Sender<Option<String>>>,
    tokens: AtomicU64,
    clients: Arc<AtomicUsize>,
    _stop: oneshot::Sender<()>,
}

impl Hub {
    pub fn items(&self) -> broadcast::Receiver<Item> {
        self.items.subscribe()
    }

    pub fn positions(&self) -> watch::Receiver<Option<Frame>> {
        self.positions.subscribe()
    }

    /// The node to ask for snapshots (`None` while the controller is between nodes).
    pub fn owner(&self) -> watch::Receiver<Option<String>> {
        self.owner.subscribe()
    }

    /// A token for a snapshot request, unique in this hub.
    pub fn token(&self) -> u64 {
        self.tokens.fetch_add(1, Ordering::Relaxed)
    }

    /// Counts a websocket client while the value lives.
    pub fn client(self: &Arc<Self>) -> Client {
        self.clients.fetch_add(1, Ordering::Relaxed);
        Client { clients: self.clients.clone() }
    }
}

/// A websocket client of a relayed controller, counted.
pub struct Client {
    clients: Arc<AtomicUsize>,
}

impl Drop for Client {
    fn drop(&mut self) {
        self.clients.fetch_sub(1, Ordering::Relaxed);
    }
}

impl Hubs {
    /// Open subscriptions: controllers of other nodes relayed here.
    pub fn subscriptions(&self) -> usize {
        self.subscriptions.load(Ordering::Relaxed)
    }

    /// Websocket clients of relayed controllers.
    pub fn clients(&self) -> usize {
        self.clients.load(Ordering::Relaxed)
    }

    /// The hub of controller `id` (hosted by `owner`), subscribed before it returns: a
    /// snapshot asked for afterwards comes through it.
    pub async fn hub(&self, state: &AppState, cluster: &Cluster, id: &str, owner: &str) -> Result<Arc<Hub>, String> {
        if let Some(hub) = lock(&self.hubs).get(id).and_then(Weak::upgrade) {
            return Ok(hub);
        }
        let subscription = cluster
            .client()
            .subscribe(stream_subjects(id))
            .await
            .map_err(|e| format!("NATS: cannot subscribe to the stream of controller {id}: {e}"))?;
        let mut hubs = lock(&self.hubs);
        // Another client's session may have made it meanwhile (this subscription is dropped).
        if let Some(hub) = hubs.get(id).and_then(Weak::upgrade) {
            return Ok(hub);
        }
        let relay = format!("{}/{}", cluster.name(), self.generation.fetch_add(1, Ordering::Relaxed));
        let (items, _) = broadcast::channel(BUFFER);
        let positions = Arc::new(watch::channel(None).0);
        let owner = Arc::new(watch::channel(Some(owner.to_string())).0);
        let (stop, stopped) = oneshot::channel();
        let hub = Arc::new(Hub {
            id: id.to_string(),
            relay: relay.clone(),
            items: items.clone(),
            positions: positions.clone(),
            owner: owner.clone(),
            tokens: AtomicU64::new(0),
            clients: self.clients.clone(),
            _stop: stop,
        });
        hubs.retain(|_, h| h.strong_count() > 0);
        hubs.insert(id.to_string(), Arc::downgrade(&hub));
        self.subscriptions.fetch_add(1, Ordering::Relaxed);
        let task = Task {
            id: id.to_string(),
            me: Arc::downgrade(&hub),
            hubs: self.hubs.clone(),
            relay,
            cluster: cluster.clone(),
            state: state.clone(),
            items,
            positions,
            owner,
            n: 0,
            expected: None,
            follow: None,
            subscriptions: self.subscriptions.clone(),
        };
        tokio::spawn(task.run(subscription, stopped));
        tracing::info!(%id, owner = ?hub.owner.borrow(), "relaying the controller's stream: subscribed");
        Ok(hub)
    }
}

/// The controller is between nodes: its node `left` (at placement `revision`) since `since`.
struct Follow {
    left: Option<String>,
    revision: u64,
    since: Instant,
}

struct Task {
    id: String,
    /// Its hub, and the registry it is in (left when the stream ends).
    me: Weak<Hub>,
    hubs: Arc<Mutex<HashMap<String, Weak<Hub>>>>,
    relay: String,
    cluster: Cluster,
    state: AppState,
    items: broadcast::Sender<Item>,
    positions: Arc<watch::Sender<Option<Frame>>>,
    owner: Arc<watch::Sender<Option<String>>>,
    /// The number of the last message handed on.
    n: u64,
    /// The number ([`SEQ`]) the owner's next message should have.
    expected: Option<u64>,
    follow: Option<Follow>,
    subscriptions: Arc<AtomicUsize>,
}

impl Task {
    async fn run(mut self, mut subscription: async_nats::Subscriber, mut stopped: oneshot::Receiver<()>) {
        let mut alive = tokio::time::interval(ALIVE);
        alive.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        loop {
            let go_on = tokio::select! {
                message = subscription.next() => match message {
                    Some(message) => self.take(message).await,
                    // The NATS connection was closed (it survives reconnects): nothing more comes.
                    None => {
                        self.hand(Item::Close(1012, Utf8Bytes::from_static("the relay's subscription ended; reconnect")));
                        false
                    }
                },
                _ = alive.tick() => {
                    self.interest(false).await;
                    self.check().await
                }
                _ = &mut stopped => false,
            };
            if !go_on {
                break;
            }
        }
        {
            let mut hubs = lock(&self.hubs);
            if hubs.get(&self.id).is_some_and(|h| h.ptr_eq(&self.me)) {
                hubs.remove(&self.id);
            }
        }
        self.interest(true).await;
        drop(subscription);
        self.subscriptions.fetch_sub(1, Ordering::Relaxed);
        tracing::info!(id = %self.id, "relayed stream: unsubscribed");
    }

    /// Tells the owner (whoever hosts the controller) this node is interested, or no longer.
    async fn interest(&self, end: bool) {
        let client = self.cluster.client();
        let payload = Bytes::from(self.relay.clone());
        let sent = if end {
            let mut headers = HeaderMap::new();
            headers.insert(INTEREST, "end");
            let sent = client.publish_with_headers(interest_subject(&self.id), headers, payload).await;
            let _ = client.flush().await;
            sent
        } else {
            client.publish(interest_subject(&self.id), payload).await
        };
        if let Err(e) = sent {
            tracing::warn!(id = %self.id, error = %e, "interest in a relayed stream not published");
        }
    }

    fn hand(&mut self, item: Item) {
        let _ = self.items.send(item);
    }

    /// One message of the controller's stream; false when the stream ended.
    async fn take(&mut self, message: async_nats::Message) -> bool {
        self.n += 1;
        let kind = message.subject.as_str().rsplit('.').next().unwrap_or("").to_string();
        let Ok(text) = Utf8Bytes::try_from(message.payload.clone()) else {
            tracing::warn!(id = %self.id, %kind, "a relayed stream message is not UTF-8: dropped");
            return true;
        };
        if kind == "position" {
            self.positions.send_replace(Some(Frame { n: self.n, text }));
            return true;
        }
        let header = |name: &str| message.headers.as_ref().and_then(|h| h.get(name)).map(|v| v.as_str().to_string());
        let seq = header(SEQ).and_then(|s| s.parse::<u64>().ok());
        if kind == "start" {
            tracing::info!(id = %self.id, node = %text, "relayed stream (re)started by its node: fresh snapshots");
            self.expected = Some(1);
            self.hand(Item::Resync);
            return true;
        }
        if let (Some(expected), Some(seq)) = (self.expected, seq) {
            if seq != expected {
                tracing::warn!(id = %self.id, expected, seq, "relayed stream: messages lost; fresh snapshots");
                self.hand(Item::Resync);
            }
        }
        self.expected = seq.map(|s| s + 1);
        match kind.as_str() {
            "event" => self.hand(Item::Event(text)),
            "snapshot" => {
                let token = header(TOKEN).and_then(|t| t.parse().ok()).unwrap_or(u64::MAX);
                let at = message.payload.iter().position(|b| *b == b'\n').unwrap_or(message.payload.len());
                let part = |from: usize, to: usize| Utf8Bytes::try_from(message.payload.slice(from..to)).ok();
                let (Some(snapshot), Some(position)) =
                    (part(0, at), part((at + 1).min(message.payload.len()), message.payload.len()))
                else {
                    return true;
                };
                let n = self.n;
                self.hand(Item::Snapshot { token, n, snapshot, position });
            }
            "gone" => {
                tracing::info!(id = %self.id, node = %text, "relayed controller left its node: following it");
                self.start_following().await;
            }
            "close" => {
                let (code, reason) = text.as_str().split_once(' ').unwrap_or(("1011", "closed"));
                self.hand(Item::Close(code.parse().unwrap_or(1011), Utf8Bytes::from(reason)));
                return false;
            }
            _ => {}
        }
        true
    }

    /// The controller left its node: from now on, look for its new placement.
    async fn start_following(&mut self) {
        if self.follow.is_some() {
            return;
        }
        let left = self.owner.send_replace(None);
        let revision = self.cluster.placement(&self.id).await.map_or(0, |p| p.revision);
        self.follow = Some(Follow { left, revision, since: Instant::now() });
    }

    /// Every [`ALIVE`]: is the owner still a member, and while following, where is the
    /// controller now. False when the stream ended.
    async fn check(&mut self) -> bool {
        if self.follow.is_none() {
            let owner = self.owner.borrow().clone();
            if owner.is_some_and(|o| !self.cluster.members().contains(&o)) {
                tracing::info!(id = %self.id, "relayed controller's node left: following the controller");
                self.start_following().await;
            }
        }
        let Some(follow) = &self.follow else { return true };
        let placement = self.cluster.placement(&self.id).await;
        match placement {
            Ok(Placed { node: Some(node), revision })
                if self.cluster.members().contains(&node)
                    && (follow.left.as_ref() != Some(&node) || revision != follow.revision) =>
            {
                tracing::info!(id = %self.id, %node, "relayed controller found on its new node: fresh snapshots");
                self.follow = None;
                self.owner.send_replace(Some(node));
                self.hand(Item::Resync);
                return true;
            }
            Ok(Placed { node: None, .. })
                if matches!(crate::db::controller(&self.state.db, &self.id).await, Ok(None)) =>
            {
                let reason = "controller deleted";
                self.hand(Item::Close(crate::api::stream::CONTROLLER_DELETED, Utf8Bytes::from_static(reason)));
                return false;
            }
            _ => {}
        }
        if follow.since.elapsed() > FOLLOW_LIMIT {
            let node = follow.left.clone().unwrap_or_else(|| "?".into());
            let reason =
                format!("its node {node} left; not hosted again within {} s; reconnect", FOLLOW_LIMIT.as_secs());
            self.hand(Item::Close(1012, Utf8Bytes::from(reason)));
            return false;
        }
        true
    }
}
