//! Controllers hosted across nodes (issue 23 item 2; docs/cluster.md): `fivex serve --nats URL
//! --node NAME` with a PostgreSQL database joins a cluster in which every controller is hosted
//! by exactly one node at a time.
//!
//! - Membership: JetStream key-value bucket [`NODES_BUCKET`], one key per node, put every
//!   [`BEAT`]; the bucket's entries live [`LEASE`], so a node that stops beating (killed) drops
//!   out of it by itself.
//! - Placement: bucket [`PLACEMENT_BUCKET`], controller id → node name. A node claims a
//!   controller with a revision-checked write (`create` for a free one, `update` at the revision
//!   it read for one whose node is gone), so of several nodes claiming at once exactly one wins.
//! - Each node keeps the placement bucket in memory ([`view`]), current through a watch: a
//!   forwarded request and a beat read no bucket entry (the bucket is read while the view is
//!   being built, after a reconnect).
//! - Every [`BEAT`] each node reconciles ([`Cluster::reconcile`]): it claims controllers of the
//!   database whose node left (at once) or that were never placed (after one more beat, leaving
//!   the creating node its time to place it), up to a fair share, and hosts them from the
//!   database in reset state; it drops any it hosts whose placement names another node. Then a
//!   node above its fair share hands idle controllers over to the members below theirs
//!   ([`handover`]); the receiver's view wakes it to host them at once.
//! - Requests: any `/api/v1/controllers/{id}/…` request for a controller hosted elsewhere is
//!   forwarded ([`forward`]) to its node by NATS request/reply on `fivex.nodes.{node}.http`: the
//!   owner answers it through its own router. The stream websocket of a remote controller is
//!   relayed (`crate::relay`); any other websocket of one is refused (421) naming the owner.
//! - A node that stops cleanly releases its placements, so the others take its controllers at
//!   their next beat.

mod handover;
pub mod view;

use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use async_nats::jetstream::kv;
use async_nats::HeaderMap;
use axum::body::Body;
use axum::extract::{Request, State};
use axum::http::{HeaderName, HeaderValue, Method, StatusCode, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::Router;
use bytes::Bytes;
use futures_util::StreamExt;
use tower::ServiceExt;

use crate::http::{ApiError, AppState};
use crate::{db, service};
use view::{Placed, View};

/// Membership: node name → when it started; entries expire after [`LEASE`].
pub const NODES_BUCKET: &str = "fivex_nodes";
/// Placement: controller id → the name of the node hosting it.
pub const PLACEMENT_BUCKET: &str = "fivex_placement";
/// How often a node says it is alive and reconciles its placements.
pub const BEAT: Duration = Duration::from_secs(1);
/// How long a node stays a member after its last beat.
pub const LEASE: Duration = Duration::from_secs(5);
/// The longest a listing of the members may take.
const LIST_TIMEOUT: Duration = Duration::from_secs(2);
/// How long a forwarded request may take before the node that got it answers 504.
pub const FORWARD_TIMEOUT: Duration = Duration::from_secs(30);
/// Set on a forwarded request: its owner answers it itself (never forwards it again) and a
/// controller list answers only what the node hosts.
pub const FORWARDED: &str = "fivex-forwarded";

const METHOD: &str = "fivex-method";
const URI: &str = "fivex-uri";
const STATUS: &str = "fivex-status";
/// The largest forwarded answer read, bytes.
const MAX_ANSWER: usize = 64 * 1024 * 1024;

/// The subject on which node `node` answers forwarded requests.
pub fn http_subject(node: &str) -> String {
    format!("fivex.nodes.{node}.http")
}

/// Whether `name` can name a node: 1 to 64 of `A-Z a-z 0-9 _ -` (a key and a subject token).
pub fn valid_name(name: &str) -> bool {
    !name.is_empty() && name.len() <= 64 && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
}

/// The default node name: the host's name when it is a valid one, else a new uuid.
pub fn default_name() -> String {
    let host = std::fs::read_to_string("/etc/hostname").unwrap_or_default().trim().to_string();
    if valid_name(&host) {
        host
    } else {
        uuid::Uuid::new_v4().simple().to_string()
    }
}

/// This node's membership in a cluster of controller hosts.
#[derive(Clone)]
pub struct Cluster {
    inner: Arc<Inner>,
}

struct Inner {
    name: String,
    client: async_nats::Client,
    nodes: kv::Store,
    placement: kv::Store,
    /// Controllers seen in the database without a placement at the last reconcile.
    unplaced: Mutex<HashSet<String>>,
    /// The members seen at the last reconcile.
    members: tokio::sync::watch::Sender<Vec<String>>,
    /// Set once the node leaves: it claims nothing more.
    leaving: std::sync::atomic::AtomicBool,
    /// The placement bucket in memory, kept current by a watch.
    view: Arc<View>,
    /// Placement entries read from the bucket (while the view is not current, and by `leave`).
    reads: AtomicU64,
    /// The last beat's busy controllers of this node and the handovers that wait for them.
    waits: Mutex<(usize, usize)>,
    /// The controllers' streams this node publishes for other nodes and relays from them.
    relays: crate::relay::Relays,
}

impl std::fmt::Debug for Cluster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cluster").field("name", &self.inner.name).finish()
    }
}

/// What a reconcile saw: the members, the stored controllers, their placements.
struct Seen {
    members: Vec<String>,
    ids: Vec<String>,
    owners: HashMap<String, Placed>,
}

impl Cluster {
    /// Joins: makes sure of the buckets and takes the name `name` in [`NODES_BUCKET`] (refused
    /// while a node of that name is a member).
    pub async fn join(nats: &crate::cluster::Nats, name: &str) -> Result<Cluster, String> {
        if !valid_name(name) {
            return Err(format!("--node {name:?}: a node name has 1 to 64 of A-Z a-z 0-9 _ -"));
        }
        let js = nats.jetstream();
        let nodes = crate::cluster::key_value(js, NODES_BUCKET, LEASE).await?;
        let placement = crate::cluster::key_value(js, PLACEMENT_BUCKET, Duration::ZERO).await?;
        let started = Bytes::from(crate::host::now_rfc3339());
        if nodes.create(name, started).await.is_err() {
            return Err(format!(
                "a node named {name} is already in the cluster (a killed node stays a member for {} s): give another --node",
                LEASE.as_secs()
            ));
        }
        let view = Arc::new(View::new(name));
        tokio::spawn(view::follow(view.clone(), placement.clone(), nats.client().clone()));
        Ok(Cluster {
            inner: Arc::new(Inner {
                name: name.to_string(),
                client: nats.client().clone(),
                nodes,
                placement,
                unplaced: Mutex::default(),
                members: tokio::sync::watch::channel(vec![name.to_string()]).0,
                leaving: Default::default(),
                view,
                reads: AtomicU64::new(0),
                waits: Mutex::default(),
                relays: Default::default(),
            }),
        })
    }

    /// This node's name.
    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// The members seen at the last beat, sorted.
    pub fn members(&self) -> Vec<String> {
        self.inner.members.borrow().clone()
    }

    /// The members seen at the last beat, as they change.
    pub fn watch_members(&self) -> tokio::sync::watch::Receiver<Vec<String>> {
        self.inner.members.subscribe()
    }

    /// Whether node `node` is a member: as seen at the last beat, or else (a node that joined
    /// since) its key read from [`NODES_BUCKET`] now, so a request for a controller of a node
    /// that has just joined is not refused for up to a beat.
    pub async fn is_member(&self, node: &str) -> bool {
        if self.inner.members.borrow().iter().any(|m| m == node) {
            return true;
        }
        matches!(self.inner.nodes.get(node).await, Ok(Some(_)))
    }

    /// Lists the members (the keys of [`NODES_BUCKET`]) and keeps them for [`Cluster::members`].
    /// Bounded: a listing whose consumer misses its end (seen on nats-server 2.9 when a key is
    /// written while it is listed) fails after [`LIST_TIMEOUT`] instead of holding the beat.
    async fn refresh_members(&self) -> Result<Vec<String>, String> {
        let list = async {
            let mut keys = self.inner.nodes.keys().await.map_err(|e| format!("NATS: cannot list the nodes: {e}"))?;
            let mut members = Vec::new();
            while let Some(key) = keys.next().await {
                members.push(key.map_err(|e| format!("NATS: cannot list the nodes: {e}"))?);
            }
            members.sort();
            Ok::<_, String>(members)
        };
        let mut members = tokio::time::timeout(LIST_TIMEOUT, list)
            .await
            .map_err(|_| format!("NATS: the nodes not listed within {} s", LIST_TIMEOUT.as_secs()))??;
        // A listing misses a key written while it runs (nats-server 2.9: the key's message moves
        // past the listing's end), and every member writes its key every beat: a member seen
        // before is asked for directly (a read by key sees its last write) before it counts as
        // gone. Taking over a live node's controllers would reset them under it.
        let unlisted: Vec<String> =
            self.inner.members.borrow().iter().filter(|n| !members.contains(n)).cloned().collect();
        for node in unlisted {
            if matches!(self.inner.nodes.get(&node).await, Ok(Some(_))) {
                members.push(node);
            }
        }
        // A key rewritten while it is listed can also come twice.
        members.sort();
        members.dedup();
        self.inner.members.send_replace(members.clone());
        Ok(members)
    }

    /// The NATS connection.
    pub fn client(&self) -> &async_nats::Client {
        &self.inner.client
    }

    /// The controllers' streams this node publishes and relays.
    pub fn relays(&self) -> &crate::relay::Relays {
        &self.inner.relays
    }

    /// The node that hosts controller `id`, if it is placed: from the view, or from the bucket
    /// while the view is not current.
    pub async fn owner(&self, id: &str) -> Result<Option<String>, String> {
        Ok(self.placement(id).await?.node)
    }

    /// The placement of `id` (revision 0: never placed).
    pub(crate) async fn placement(&self, id: &str) -> Result<Placed, String> {
        if let Some(placed) = self.inner.view.get(id) {
            return Ok(placed.unwrap_or(Placed { node: None, revision: 0 }));
        }
        self.inner.reads.fetch_add(1, Ordering::Relaxed);
        let entry = self
            .inner
            .placement
            .entry(id.to_string())
            .await
            .map_err(|e| format!("NATS: cannot read the placement of {id}: {e}"))?;
        Ok(entry.as_ref().map_or(Placed { node: None, revision: 0 }, Placed::of))
    }

    /// The placements of `ids` (a controller never placed has none).
    async fn placements(&self, ids: &[String]) -> Result<HashMap<String, Placed>, String> {
        if let Some(placed) = self.inner.view.of(ids) {
            return Ok(placed);
        }
        let mut placed = HashMap::new();
        for id in ids {
            let p = self.placement(id).await?;
            if p.revision != 0 {
                placed.insert(id.clone(), p);
            }
        }
        Ok(placed)
    }

    /// How many placement entries this node has read from the bucket: none while its view is
    /// current (docs/cluster.md, "The placement view").
    pub fn placement_reads(&self) -> u64 {
        self.inner.reads.load(Ordering::Relaxed)
    }

    /// Whether this node's view of the placement bucket is current (else it reads the bucket).
    pub fn view_current(&self) -> bool {
        self.inner.view.is_current()
    }

    /// How many times this node built its view of the placement bucket (1, then one more after
    /// each broken watch or reconnect).
    pub fn view_builds(&self) -> u64 {
        self.inner.view.builds()
    }

    /// Controller `id` (created here) is hosted here.
    pub async fn place(&self, id: &str) -> Result<(), String> {
        let revision = self
            .inner
            .placement
            .put(id, Bytes::from(self.inner.name.clone()))
            .await
            .map_err(|e| format!("NATS: cannot place {id}: {e}"))?;
        self.inner.view.wrote(id, Some(&self.inner.name), revision);
        Ok(())
    }

    /// Controller `id` is gone (removed).
    pub async fn forget(&self, id: &str) {
        if let Err(e) = self.inner.placement.delete(id).await {
            tracing::warn!(%id, error = %e, "placement of a removed controller not deleted");
        }
    }

    /// Starts the beat (membership and reconcile) and the answering of forwarded requests on
    /// `app`. Reconciles once before it returns, so the node hosts its share from the start.
    pub async fn start(&self, state: AppState, app: Router) -> Result<(), String> {
        self.reconcile(&state).await?;
        let mut requests = self
            .inner
            .client
            .subscribe(http_subject(&self.inner.name))
            .await
            .map_err(|e| format!("NATS: cannot subscribe to {}: {e}", http_subject(&self.inner.name)))?;
        let subscribe = |subject: String| async move {
            self.inner
                .client
                .subscribe(subject.clone())
                .await
                .map_err(|e| format!("NATS: cannot subscribe to {subject}: {e}"))
        };
        let mut snapshots = subscribe(crate::relay::snapshot_subject(&self.inner.name)).await?;
        let mut interest = subscribe(crate::relay::INTEREST_SUBJECTS.to_string()).await?;
        let (client, publishing) = (self.inner.client.clone(), state.clone());
        tokio::spawn(async move {
            while let Some(message) = snapshots.next().await {
                tokio::spawn(crate::relay::publisher::snapshot(publishing.clone(), client.clone(), message));
            }
        });
        let (client, publishing) = (self.inner.client.clone(), state.clone());
        tokio::spawn(async move {
            while let Some(message) = interest.next().await {
                crate::relay::publisher::interest(&publishing, &client, message);
            }
        });
        let client = self.inner.client.clone();
        tokio::spawn(async move {
            while let Some(message) = requests.next().await {
                let (app, client) = (app.clone(), client.clone());
                tokio::spawn(async move { answer(app, client, message).await });
            }
        });
        // Membership on its own task (this node's key written, then the members listed): a slow
        // reconcile or handover never delays it.
        let (cluster, started) = (self.clone(), Bytes::from(state.node.started_at.clone()));
        tokio::spawn(async move {
            let mut beat = tokio::time::interval(BEAT);
            beat.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
            loop {
                beat.tick().await;
                if cluster.leaving() {
                    break;
                }
                if let Err(e) = cluster.inner.nodes.put(&cluster.inner.name, started.clone()).await {
                    tracing::warn!(error = %e, "cluster heartbeat not written");
                }
                if let Err(e) = cluster.refresh_members().await {
                    tracing::warn!(error = %e, "cluster members not listed: the last list is kept");
                }
            }
        });
        let cluster = self.clone();
        tokio::spawn(async move {
            let mut beat = tokio::time::interval(BEAT);
            beat.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
            loop {
                let kicked = tokio::select! {
                    _ = beat.tick() => false,
                    () = cluster.inner.view.kicked() => true,
                };
                if cluster.leaving() {
                    break;
                }
                let done = if kicked { cluster.adopt(&state).await } else { cluster.beat(&state).await };
                if let Err(e) = done {
                    tracing::warn!(error = %e, "cluster placements not reconciled");
                }
            }
        });
        Ok(())
    }

    fn leaving(&self) -> bool {
        self.inner.leaving.load(Ordering::SeqCst)
    }

    /// One beat: [`Cluster::reconcile`] with the members the membership task listed last, then
    /// the surplus handed over (`handover`).
    async fn beat(&self, state: &AppState) -> Result<(), String> {
        let Some(seen) = self.reconciled(state, self.members()).await? else { return Ok(()) };
        let me = self.inner.name.as_str();
        let mut placed: BTreeMap<String, usize> = seen.members.iter().map(|m| (m.clone(), 0)).collect();
        let mut settled = true;
        for id in &seen.ids {
            match seen.owners.get(id).and_then(|p| p.node.as_ref()).and_then(|n| placed.get_mut(n)) {
                Some(count) => *count += 1,
                None => settled = false,
            }
        }
        let to = handover::receivers(me, &placed, seen.ids.len(), settled);
        handover::hand_over(self, state, &seen.owners, to).await;
        Ok(())
    }

    /// Reconciles once (the members listed first): claims the controllers of the database that
    /// no live node hosts (up to a fair share) and hosts them in reset state; drops those it
    /// hosts that another node owns.
    pub async fn reconcile(&self, state: &AppState) -> Result<(), String> {
        let members = self.refresh_members().await?;
        self.reconciled(state, members).await.map(|_| ())
    }

    /// [`Cluster::reconcile`] with `members`, answering what it saw (`None` once leaving).
    async fn reconciled(&self, state: &AppState, members: Vec<String>) -> Result<Option<Seen>, String> {
        if self.leaving() {
            return Ok(None);
        }
        let me = self.inner.name.clone();
        let ids = db::controller_ids(&state.db).await.map_err(|e| format!("cannot list the controllers: {e}"))?;
        let mut owners = self.placements(&ids).await?;
        let stored: HashSet<&String> = ids.iter().collect();
        // Hosted here but placed elsewhere: dropped. Hosted here and not placed: placed here.
        for hosted in state.host.list() {
            let placed = owners.get(&hosted.id).cloned();
            match placed {
                Some(Placed { node: Some(owner), .. }) if owner != me => {
                    tracing::warn!(id = %hosted.id, %owner, "controller hosted by another node: dropped here");
                    state.host.remove(&hosted.id);
                }
                Some(Placed { node: Some(_), .. }) => {}
                // Not placed (deleted marker, or never): placed here if it is still stored.
                _ if stored.contains(&hosted.id) => {
                    let revision = placed.map_or(0, |p| p.revision);
                    if let Some(won) = self.claim(&hosted.id, revision).await {
                        owners.insert(hosted.id.clone(), Placed { node: Some(me.clone()), revision: won });
                    }
                }
                _ => {}
            }
        }
        let mine = owners.values().filter(|p| p.node.as_deref() == Some(me.as_str())).count();
        let share = ids.len().div_ceil(members.len().max(1));
        let mut room = share.saturating_sub(mine);
        let mut unplaced_now = HashSet::new();
        let previously = lock(&self.inner.unplaced).clone();
        let mut to_host = Vec::new();
        for id in &ids {
            let placed = owners.get(id).cloned().unwrap_or(Placed { node: None, revision: 0 });
            let orphan = match &placed.node {
                // Owned (a claim of an earlier beat whose load failed, or a handover to this
                // node): hosted now.
                Some(o) if *o == me => state.host.get(id).is_none(),
                // Gone from the members; read by key once more before its controllers are
                // taken: a takeover resets a controller, it must never hit a live node's.
                Some(o) => !members.contains(o) && !self.is_member(o).await,
                None => {
                    unplaced_now.insert(id.clone());
                    previously.contains(id)
                }
            };
            if !orphan || state.host.get(id).is_some() {
                continue;
            }
            if placed.node.as_deref() != Some(me.as_str()) {
                if room == 0 {
                    continue;
                }
                let Some(won) = self.claim(id, placed.revision).await else { continue };
                owners.insert(id.clone(), Placed { node: Some(me.clone()), revision: won });
                room -= 1;
                tracing::info!(%id, from = ?placed.node, "controller taken over by this node, in reset state");
            }
            to_host.push(id.clone());
        }
        self.host_stored(state, to_host).await;
        *lock(&self.inner.unplaced) = unplaced_now;
        Ok(Some(Seen { members, ids, owners }))
    }

    /// Hosts what the view says is placed on this node and is not hosted here (a handover to
    /// this node: the view woke it).
    async fn adopt(&self, state: &AppState) -> Result<(), String> {
        let Some(mine) = self.inner.view.mine() else { return Ok(()) };
        let missing: Vec<String> = mine.into_iter().filter(|id| state.host.get(id).is_none()).collect();
        self.host_stored(state, missing).await;
        Ok(())
    }

    /// Hosts controllers `ids` from the database in reset state (one no longer stored is
    /// skipped; one that fails to load is tried again at the next beat).
    async fn host_stored(&self, state: &AppState, ids: Vec<String>) {
        if ids.is_empty() {
            return;
        }
        let settings = match db::controller_settings(&state.db).await {
            Ok(s) => s,
            Err(e) => return tracing::warn!(error = %e, "controllers placed here not loaded: retried at the next beat"),
        };
        for id in ids {
            let row = match db::controller(&state.db, &id).await {
                Ok(Some(row)) => row,
                Ok(None) => continue,
                Err(e) => {
                    tracing::warn!(%id, error = %e, "controller placed here not loaded: retried at the next beat");
                    continue;
                }
            };
            match service::controllers::load(&state.db, row, &settings).await {
                Ok(Some(hosted)) if state.host.get(&id).is_none() && !self.leaving() => {
                    state.host.add(Arc::new(hosted));
                    tracing::info!(%id, "controller hosted here, from the database in reset state");
                }
                Ok(_) => {}
                Err(e) => {
                    tracing::warn!(%id, error = %e, "controller placed here not loaded: retried at the next beat")
                }
            }
        }
    }

    /// Claims controller `id` at `revision` (0: never placed); the revision of the claim when
    /// this node won (a claim that lost is not believed: the view waits for the watch).
    async fn claim(&self, id: &str, revision: u64) -> Option<u64> {
        let me = Bytes::from(self.inner.name.clone());
        let won = if revision == 0 {
            self.inner.placement.create(id, me).await.ok()
        } else {
            self.inner.placement.update(id, me, revision).await.ok()
        }?;
        self.inner.view.wrote(id, Some(&self.inner.name), won);
        tracing::info!(%id, node = %self.inner.name, "controller claimed");
        Some(won)
    }

    /// Places controller `id`, placed here at `revision`, on node `to` (revision-checked: a
    /// placement changed meanwhile stays as it is).
    async fn hand(&self, id: &str, to: &str, revision: u64) -> Result<(), String> {
        let written = self
            .inner
            .placement
            .update(id, Bytes::from(to.to_string()), revision)
            .await
            .map_err(|e| format!("NATS: placement not changed: {e}"))?;
        self.inner.view.wrote(id, Some(to), written);
        Ok(())
    }

    /// Leaves cleanly (after the controllers' records are written): claims nothing more,
    /// releases every placement of this node and its membership, so the other nodes take its
    /// controllers at their next beat.
    pub async fn leave(&self, state: &AppState) {
        self.inner.leaving.store(true, Ordering::SeqCst);
        for hosted in state.host.list() {
            self.inner.reads.fetch_add(1, Ordering::Relaxed);
            if let Ok(Some(entry)) = self.inner.placement.entry(hosted.id.clone()).await {
                if entry.operation == kv::Operation::Put && entry.value.as_ref() == self.inner.name.as_bytes() {
                    // Revision-checked: a placement another node took meanwhile stays.
                    let _ = self.inner.placement.delete_expect_revision(&hosted.id, Some(entry.revision)).await;
                }
            }
        }
        let _ = self.inner.nodes.delete(&self.inner.name).await;
        let _ = self.inner.client.flush().await;
        tracing::info!(node = %self.inner.name, controllers = state.host.len(), "left the cluster: controllers released");
    }

    /// Sends `request` to node `node` and returns its answer.
    pub async fn send(
        &self,
        node: &str,
        method: &Method,
        uri: &Uri,
        headers: &axum::http::HeaderMap,
        body: Bytes,
    ) -> Response {
        let mut nats_headers = HeaderMap::new();
        nats_headers.insert(METHOD, method.as_str());
        nats_headers.insert(URI, uri.to_string().as_str());
        for (name, value) in headers {
            if matches!(name.as_str(), "connection" | "content-length" | "transfer-encoding" | "upgrade" | "keep-alive")
            {
                continue;
            }
            if let Ok(value) = value.to_str() {
                nats_headers.append(name.as_str(), value);
            }
        }
        nats_headers.insert(FORWARDED, self.inner.name.as_str());
        let request = async_nats::Request::new().headers(nats_headers).payload(body).timeout(Some(FORWARD_TIMEOUT));
        match self.inner.client.send_request(http_subject(node), request).await {
            Ok(message) => {
                let headers = message.headers.unwrap_or_default();
                let status = headers
                    .get(STATUS)
                    .and_then(|s| s.as_str().parse::<u16>().ok())
                    .and_then(|s| StatusCode::from_u16(s).ok())
                    .unwrap_or(StatusCode::BAD_GATEWAY);
                let mut response = Response::new(Body::from(message.payload));
                *response.status_mut() = status;
                for (name, values) in headers.iter() {
                    let name: &str = name.as_ref();
                    if name.starts_with("fivex-") {
                        continue;
                    }
                    for value in values {
                        if let (Ok(n), Ok(v)) = (HeaderName::try_from(name), HeaderValue::from_str(value.as_str())) {
                            response.headers_mut().append(n, v);
                        }
                    }
                }
                response
            }
            Err(e) => {
                ApiError::Unavailable(format!("controller's node {node} did not answer the forwarded request: {e}"))
                    .into_response()
            }
        }
    }
}

/// Answers a forwarded request through this node's router.
async fn answer(app: Router, client: async_nats::Client, message: async_nats::Message) {
    let Some(reply) = message.reply.clone() else { return };
    let headers = message.headers.clone().unwrap_or_default();
    let method =
        headers.get(METHOD).and_then(|m| Method::from_bytes(m.as_str().as_bytes()).ok()).unwrap_or(Method::GET);
    let uri = headers.get(URI).map(|u| u.as_str().to_string()).unwrap_or_else(|| "/".into());
    let mut request = Request::new(Body::from(message.payload.clone()));
    *request.method_mut() = method;
    *request.uri_mut() = uri.parse().unwrap_or_else(|_| Uri::from_static("/"));
    for (name, values) in headers.iter() {
        let name: &str = name.as_ref();
        if name == METHOD || name == URI {
            continue;
        }
        for value in values {
            if let (Ok(n), Ok(v)) = (HeaderName::try_from(name), HeaderValue::from_str(value.as_str())) {
                request.headers_mut().append(n, v);
            }
        }
    }
    let response = match app.oneshot(request).await {
        Ok(r) => r,
        Err(never) => match never {},
    };
    let (parts, body) = response.into_parts();
    let body = axum::body::to_bytes(body, MAX_ANSWER).await.unwrap_or_default();
    let mut out = HeaderMap::new();
    out.insert(STATUS, parts.status.as_u16().to_string().as_str());
    for (name, value) in &parts.headers {
        if matches!(name.as_str(), "content-length" | "transfer-encoding" | "connection") {
            continue;
        }
        if let Ok(value) = value.to_str() {
            out.append(name.as_str(), value);
        }
    }
    if let Err(e) = client.publish_with_headers(reply, out, body).await {
        tracing::warn!(error = %e, "forwarded request's answer not sent");
    }
}

/// Middleware: a `/api/v1/controllers/{id}…` request for a controller hosted by another node
/// goes to that node (its stream websocket is relayed, any other websocket refused, 421, naming
/// it); one whose node left answers 503 until a node takes it over.
pub async fn forward(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let Some(cluster) = state.cluster.clone() else { return next.run(request).await };
    let path = request.uri().path();
    let Some(id) = path.strip_prefix("/api/v1/controllers/").map(|r| r.split('/').next().unwrap_or("")) else {
        return next.run(request).await;
    };
    // An id that cannot be a key (ids are uuids) is no controller's: the route answers.
    if !valid_name(id) || state.host.get(id).is_some() {
        return next.run(request).await;
    }
    let id = id.to_string();
    let stored = || async { db::controller(&state.db, &id).await.ok().flatten().is_some() };
    if request.headers().contains_key(FORWARDED) {
        // Sent here as to its owner, but not hosted here (yet, or any more: a handover or a
        // takeover under way): retried, it reaches the node that hosts it.
        if stored().await {
            return unavailable(format!("controller {id} is moving between nodes"));
        }
        return next.run(request).await;
    }
    let owner = match cluster.owner(&id).await {
        Ok(owner) => owner,
        Err(e) => return ApiError::Unavailable(e).into_response(),
    };
    let live = match &owner {
        Some(owner) if owner != cluster.name() => cluster.is_member(owner).await,
        _ => false,
    };
    match owner {
        Some(owner) if owner != cluster.name() && live => {
            if request.headers().get("upgrade").is_some() {
                if path.ends_with("/stream") && path.matches('/').count() == 5 {
                    return crate::relay::session::open(state.clone(), cluster, owner, id, request).await;
                }
                return ApiError::Rejected(
                    StatusCode::MISDIRECTED_REQUEST,
                    format!("controller {id} is hosted by node {owner}: this websocket is not relayed between nodes"),
                )
                .into_response();
            }
            let (parts, body) = request.into_parts();
            let body = match axum::body::to_bytes(body, crate::http::router::MAX_BODY_BYTES).await {
                Ok(b) => b,
                Err(e) => return ApiError::BadRequest(format!("cannot read the request body: {e}")).into_response(),
            };
            cluster.send(&owner, &parts.method, &parts.uri, &parts.headers, body).await
        }
        Some(owner) if owner == cluster.name() && stored().await => {
            unavailable(format!("controller {id} is moving between nodes (placed on this node, {owner}, not hosted yet or any more)"))
        }
        Some(owner) if stored().await => {
            unavailable(format!("controller {id} is not hosted right now (placed on node {owner}, which is not serving it): a node takes it over"))
        }
        None if stored().await => unavailable(format!("controller {id} is being placed on a node")),
        _ => next.run(request).await,
    }
}

fn unavailable(reason: String) -> Response {
    let mut response = ApiError::Unavailable(format!("{reason} (retry in a few seconds)")).into_response();
    response.headers_mut().insert("retry-after", HeaderValue::from_static("2"));
    response
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_names_are_keys_and_subject_tokens() {
        for good in ["n1", "node-2", "A_b", &"x".repeat(64)] {
            assert!(valid_name(good), "{good}");
        }
        for bad in ["", "a.b", "a b", "a*", "a>", "é", &"x".repeat(65)] {
            assert!(!valid_name(bad), "{bad}");
        }
        assert!(valid_name(&default_name()));
    }
}
