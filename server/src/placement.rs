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
//! - Every [`BEAT`] each node reconciles ([`Cluster::reconcile`]): it claims controllers of the
//!   database whose node left (at once) or that were never placed (after one more beat, leaving
//!   the creating node its time to place it), up to a fair share, and hosts them from the
//!   database in reset state; it drops any it hosts whose placement names another node.
//! - Requests: any `/api/v1/controllers/{id}/…` request for a controller hosted elsewhere is
//!   forwarded ([`forward`]) to its node by NATS request/reply on `fivex.nodes.{node}.http`: the
//!   owner answers it through its own router. The stream websocket of a remote controller is
//!   relayed (`crate::relay`); any other websocket of one is refused (421) naming the owner.
//! - A node that stops cleanly releases its placements, so the others take its controllers at
//!   their next beat.

use std::collections::{HashMap, HashSet};
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

/// Membership: node name → when it started; entries expire after [`LEASE`].
pub const NODES_BUCKET: &str = "fivex_nodes";
/// Placement: controller id → the name of the node hosting it.
pub const PLACEMENT_BUCKET: &str = "fivex_placement";
/// How often a node says it is alive and reconciles its placements.
pub const BEAT: Duration = Duration::from_secs(1);
/// How long a node stays a member after its last beat.
pub const LEASE: Duration = Duration::from_secs(5);
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
    members: Mutex<Vec<String>>,
    /// Set once the node leaves: it claims nothing more.
    leaving: std::sync::atomic::AtomicBool,
    /// The controllers' streams this node publishes for other nodes and relays from them.
    relays: crate::relay::Relays,
}

impl std::fmt::Debug for Cluster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cluster").field("name", &self.inner.name).finish()
    }
}

async fn bucket(js: &async_nats::jetstream::Context, name: &str, max_age: Duration) -> Result<kv::Store, String> {
    // The bucket's stream made here as `create_key_value` would (it reads the account first,
    // which fails on nats-server 2.9, Debian's): one value per key, deletes as markers.
    let config = async_nats::jetstream::stream::Config {
        name: format!("KV_{name}"),
        subjects: vec![format!("$KV.{name}.>")],
        max_messages_per_subject: 1,
        max_age,
        max_message_size: -1,
        max_bytes: -1,
        allow_rollup: true,
        deny_delete: true,
        allow_direct: true,
        num_replicas: 1,
        discard: async_nats::jetstream::stream::DiscardPolicy::New,
        ..Default::default()
    };
    js.get_or_create_stream(config).await.map_err(|e| format!("NATS: cannot create the bucket {name}: {e}"))?;
    js.get_key_value(name).await.map_err(|e| format!("NATS: cannot open the bucket {name}: {e}"))
}

impl Cluster {
    /// Joins: makes sure of the buckets and takes the name `name` in [`NODES_BUCKET`] (refused
    /// while a node of that name is a member).
    pub async fn join(nats: &crate::cluster::Nats, name: &str) -> Result<Cluster, String> {
        if !valid_name(name) {
            return Err(format!("--node {name:?}: a node name has 1 to 64 of A-Z a-z 0-9 _ -"));
        }
        let js = nats.jetstream();
        let nodes = bucket(js, NODES_BUCKET, LEASE).await?;
        let placement = bucket(js, PLACEMENT_BUCKET, Duration::ZERO).await?;
        let started = Bytes::from(crate::host::now_rfc3339());
        if nodes.create(name, started).await.is_err() {
            return Err(format!(
                "a node named {name} is already in the cluster (a killed node stays a member for {} s): give another --node",
                LEASE.as_secs()
            ));
        }
        Ok(Cluster {
            inner: Arc::new(Inner {
                name: name.to_string(),
                client: nats.client().clone(),
                nodes,
                placement,
                unplaced: Mutex::default(),
                members: Mutex::new(vec![name.to_string()]),
                leaving: Default::default(),
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
        lock(&self.inner.members).clone()
    }

    async fn live_members(&self) -> Result<Vec<String>, String> {
        let mut keys = self.inner.nodes.keys().await.map_err(|e| format!("NATS: cannot list the nodes: {e}"))?;
        let mut members = Vec::new();
        while let Some(key) = keys.next().await {
            members.push(key.map_err(|e| format!("NATS: cannot list the nodes: {e}"))?);
        }
        members.sort();
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

    /// The placement of controller `id`: its node (`None`: not placed, or deleted) and the
    /// entry's revision (0: never placed).
    pub async fn placement(&self, id: &str) -> Result<(Option<String>, u64), String> {
        let entry = self
            .inner
            .placement
            .entry(id.to_string())
            .await
            .map_err(|e| format!("NATS: cannot read the placement of {id}: {e}"))?;
        Ok(match entry {
            Some(e) if e.operation == kv::Operation::Put => {
                (Some(String::from_utf8_lossy(&e.value).into_owned()), e.revision)
            }
            Some(e) => (None, e.revision),
            None => (None, 0),
        })
    }

    /// The node that hosts controller `id`, if it is placed.
    pub async fn owner(&self, id: &str) -> Result<Option<String>, String> {
        let value =
            self.inner.placement.get(id).await.map_err(|e| format!("NATS: cannot read the placement of {id}: {e}"))?;
        Ok(value.map(|v| String::from_utf8_lossy(&v).into_owned()))
    }

    /// Controller `id` (created here) is hosted here.
    pub async fn place(&self, id: &str) -> Result<(), String> {
        self.inner
            .placement
            .put(id, Bytes::from(self.inner.name.clone()))
            .await
            .map(|_| ())
            .map_err(|e| format!("NATS: cannot place {id}: {e}"))
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
        let cluster = self.clone();
        tokio::spawn(async move {
            let mut beat = tokio::time::interval(BEAT);
            beat.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
            loop {
                beat.tick().await;
                if cluster.leaving() {
                    break;
                }
                let started = Bytes::from(state.node.started_at.clone());
                if let Err(e) = cluster.inner.nodes.put(&cluster.inner.name, started).await {
                    tracing::warn!(error = %e, "cluster heartbeat not written");
                }
                if let Err(e) = cluster.reconcile(&state).await {
                    tracing::warn!(error = %e, "cluster placements not reconciled");
                }
            }
        });
        Ok(())
    }

    fn leaving(&self) -> bool {
        self.inner.leaving.load(std::sync::atomic::Ordering::SeqCst)
    }

    /// One beat: claims the controllers of the database that no live node hosts (up to a fair
    /// share) and hosts them in reset state; drops those it hosts that another node owns.
    pub async fn reconcile(&self, state: &AppState) -> Result<(), String> {
        if self.leaving() {
            return Ok(());
        }
        let me = self.inner.name.clone();
        let members = self.live_members().await?;
        *lock(&self.inner.members) = members.clone();
        let rows = db::list_controllers(&state.db).await.map_err(|e| format!("cannot list the controllers: {e}"))?;
        let mut owners: HashMap<String, (Option<String>, u64)> = HashMap::new();
        for row in &rows {
            owners.insert(row.id.clone(), self.placement(&row.id).await?);
        }
        // Hosted here but placed elsewhere: dropped. Hosted here and not placed: placed here.
        for hosted in state.host.list() {
            match owners.get(&hosted.id) {
                Some((Some(owner), _)) if *owner != me => {
                    tracing::warn!(id = %hosted.id, %owner, "controller hosted by another node: dropped here");
                    state.host.remove(&hosted.id);
                }
                Some((None, revision)) if self.claim(&hosted.id, *revision).await => {
                    owners.insert(hosted.id.clone(), (Some(me.clone()), 0));
                }
                _ => {}
            }
        }
        let mine = owners.values().filter(|(o, _)| o.as_deref() == Some(me.as_str())).count();
        let share = rows.len().div_ceil(members.len().max(1));
        let mut room = share.saturating_sub(mine);
        let mut unplaced_now = HashSet::new();
        let previously = lock(&self.inner.unplaced).clone();
        let settings =
            db::controller_settings(&state.db).await.map_err(|e| format!("cannot read the controllers: {e}"))?;
        for row in rows {
            let (owner, revision) = owners.get(&row.id).cloned().unwrap_or((None, 0));
            let orphan = match &owner {
                Some(o) if *o == me => {
                    // Owned (a claim of an earlier beat whose load failed): hosted now.
                    state.host.get(&row.id).is_none()
                }
                Some(o) => !members.contains(o),
                None => {
                    unplaced_now.insert(row.id.clone());
                    previously.contains(&row.id)
                }
            };
            if !orphan || state.host.get(&row.id).is_some() {
                continue;
            }
            let owned = owner.as_deref() == Some(me.as_str());
            if !owned {
                if room == 0 {
                    continue;
                }
                if !self.claim(&row.id, revision).await {
                    continue;
                }
                room -= 1;
            }
            let id = row.id.clone();
            match service::controllers::load(&state.db, row, &settings).await {
                Ok(Some(hosted)) => {
                    if state.host.get(&id).is_none() {
                        state.host.add(Arc::new(hosted));
                        tracing::info!(%id, from = ?owner, "controller taken over by this node, in reset state");
                    }
                }
                Ok(None) => {}
                Err(e) => tracing::warn!(%id, error = %e, "claimed controller not loaded: retried at the next beat"),
            }
        }
        *lock(&self.inner.unplaced) = unplaced_now;
        Ok(())
    }

    /// Claims controller `id` at `revision` (0: never placed); whether this node won.
    async fn claim(&self, id: &str, revision: u64) -> bool {
        let me = Bytes::from(self.inner.name.clone());
        let won = if revision == 0 {
            self.inner.placement.create(id, me).await.is_ok()
        } else {
            self.inner.placement.update(id, me, revision).await.is_ok()
        };
        if won {
            tracing::info!(%id, node = %self.inner.name, "controller claimed");
        }
        won
    }

    /// Leaves cleanly (after the controllers' records are written): claims nothing more,
    /// releases every placement of this node and its membership, so the other nodes take its
    /// controllers at their next beat.
    pub async fn leave(&self, state: &AppState) {
        self.inner.leaving.store(true, std::sync::atomic::Ordering::SeqCst);
        for hosted in state.host.list() {
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
    if !valid_name(id) || state.host.get(id).is_some() || request.headers().contains_key(FORWARDED) {
        return next.run(request).await;
    }
    let id = id.to_string();
    let owner = match cluster.owner(&id).await {
        Ok(owner) => owner,
        Err(e) => return ApiError::Unavailable(e).into_response(),
    };
    let stored = || async { db::controller(&state.db, &id).await.ok().flatten().is_some() };
    match owner {
        Some(owner) if owner != cluster.name() && cluster.members().contains(&owner) => {
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
