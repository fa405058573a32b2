//! A node's view of the placement bucket (docs/cluster.md, "The placement view"): every
//! controller's placement kept in memory by a watch of the bucket, so that forwarding a request
//! (`Cluster::owner`) and a beat (`Cluster::reconcile`) read no bucket entry.
//!
//! The view is a cache; the bucket stays the truth. A claim or a handover still writes
//! revision-checked to the bucket and only a write the bucket accepted enters the view (at the
//! revision it got). The watch delivers every key's last value first (deliver policy
//! last-per-subject, which Debian's nats-server 2.9 serves), then every change; the view is
//! *current* once the initial values are in. When the watch ends or fails, or the connection to
//! NATS was re-established (a change may have been missed meanwhile), the view stops being
//! current and is built again from a new watch; until it is current the callers read the
//! bucket.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, RwLock};
use std::time::Duration;

use async_nats::jetstream::kv;
use futures_util::StreamExt;
use tokio::sync::Notify;

/// How often the follower checks the connection for a reconnect.
const CHECK: Duration = Duration::from_secs(1);
/// How long the follower waits before it tries again to watch the bucket.
const RETRY: Duration = Duration::from_millis(500);

/// One controller's placement: the node that hosts it (`None`: deleted, free) at a revision of
/// the bucket.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Placed {
    pub node: Option<String>,
    pub revision: u64,
}

impl Placed {
    /// The placement a bucket entry says.
    pub fn of(entry: &kv::Entry) -> Placed {
        let node = (entry.operation == kv::Operation::Put).then(|| String::from_utf8_lossy(&entry.value).into_owned());
        Placed { node, revision: entry.revision }
    }
}

/// The placements this node knows, kept current by [`follow`].
pub struct View {
    /// This node's name: a placement naming it wakes [`View::kicked`].
    me: String,
    placed: RwLock<HashMap<String, Placed>>,
    /// The initial values are in and the watch goes on: `placed` is the bucket as of its
    /// last change delivered.
    current: AtomicBool,
    /// A controller was placed on this node by another (a handover): host it now.
    kick: Notify,
    /// How many times the view was built (the first, then after each broken watch).
    builds: AtomicU64,
}

impl View {
    pub fn new(me: &str) -> View {
        View {
            me: me.to_string(),
            placed: Default::default(),
            current: AtomicBool::new(false),
            kick: Notify::new(),
            builds: AtomicU64::new(0),
        }
    }

    /// How many times the view was built: 1 once current, one more after each broken watch.
    pub fn builds(&self) -> u64 {
        self.builds.load(Ordering::SeqCst)
    }

    /// Whether the view holds the bucket (else read the bucket).
    pub fn is_current(&self) -> bool {
        self.current.load(Ordering::SeqCst)
    }

    /// The placement of `id`: `None` when the view is not current (read the bucket), else
    /// `Some(None)` for a controller never placed.
    pub fn get(&self, id: &str) -> Option<Option<Placed>> {
        let placed = self.placed.read().unwrap_or_else(|e| e.into_inner());
        self.is_current().then(|| placed.get(id).cloned())
    }

    /// The placements of `ids` (`None`: the view is not current).
    pub fn of(&self, ids: &[String]) -> Option<HashMap<String, Placed>> {
        let placed = self.placed.read().unwrap_or_else(|e| e.into_inner());
        self.is_current().then(|| ids.iter().filter_map(|id| Some((id.clone(), placed.get(id)?.clone()))).collect())
    }

    /// The controllers placed on this node (`None`: the view is not current).
    pub fn mine(&self) -> Option<Vec<String>> {
        let placed = self.placed.read().unwrap_or_else(|e| e.into_inner());
        self.is_current().then(|| {
            placed
                .iter()
                .filter(|(_, p)| p.node.as_deref() == Some(self.me.as_str()))
                .map(|(id, _)| id.clone())
                .collect()
        })
    }

    /// This node's write the bucket accepted at `revision` (a claim, a placement, a handover):
    /// in the view at once, before the watch brings it.
    pub fn wrote(&self, id: &str, node: Option<&str>, revision: u64) {
        let mut placed = self.placed.write().unwrap_or_else(|e| e.into_inner());
        apply(&mut placed, id, Placed { node: node.map(str::to_string), revision });
    }

    /// Resolves when a placement naming this node arrived from another node (or the view was
    /// built again): the node should host what is placed on it.
    pub async fn kicked(&self) {
        self.kick.notified().await;
    }

    /// Takes a built view: current from now on.
    fn install(&self, built: HashMap<String, Placed>) {
        *self.placed.write().unwrap_or_else(|e| e.into_inner()) = built;
        self.current.store(true, Ordering::SeqCst);
        self.builds.fetch_add(1, Ordering::SeqCst);
        self.kick.notify_one();
    }

    /// A change the watch delivered.
    fn changed(&self, id: &str, now: Placed) {
        let mine = now.node.as_deref() == Some(self.me.as_str());
        let newer = apply(&mut self.placed.write().unwrap_or_else(|e| e.into_inner()), id, now);
        if newer && mine {
            self.kick.notify_one();
        }
    }
}

/// Puts `now` in `placed` unless it holds a later revision of `id`; whether it did.
fn apply(placed: &mut HashMap<String, Placed>, id: &str, now: Placed) -> bool {
    match placed.get_mut(id) {
        Some(known) if known.revision >= now.revision => false,
        Some(known) => {
            *known = now;
            true
        }
        None => {
            placed.insert(id.to_string(), now);
            true
        }
    }
}

/// Keeps `view` current with the bucket `store` for as long as the process runs: builds it from
/// a watch and follows the watch's changes; builds it again when the watch ends or the client
/// reconnected.
pub async fn follow(view: Arc<View>, store: kv::Store, client: async_nats::Client) {
    loop {
        let why = watch(&view, &store, &client).await;
        view.current.store(false, Ordering::SeqCst);
        tracing::warn!(reason = %why, "placement view not current: the bucket is read until it is built again");
        tokio::time::sleep(RETRY).await;
    }
}

/// One watch of the bucket: the view built from it, then its changes followed; returns why it
/// ended.
async fn watch(view: &View, store: &kv::Store, client: &async_nats::Client) -> String {
    let connects = client.statistics().connects.load(Ordering::SeqCst);
    let mut watch = match store.watch_with_history(">").await {
        Ok(w) => w,
        Err(e) => return format!("cannot watch the placement bucket: {e}"),
    };
    // A bucket without a message delivers no initial value: the view is current at once. (Its
    // count never falls: one message per key, deletes are markers, nothing expires.)
    let mut building = Some(HashMap::new());
    match store.status().await {
        Ok(status) if status.values() == 0 => view.install(building.take().unwrap_or_default()),
        Ok(_) => {}
        Err(e) => return format!("cannot read the placement bucket's state: {e}"),
    }
    let mut check = tokio::time::interval(CHECK);
    loop {
        tokio::select! {
            entry = watch.next() => {
                let entry = match entry {
                    Some(Ok(entry)) => entry,
                    Some(Err(e)) => return format!("the placement watch failed: {e}"),
                    None => return "the placement watch ended".into(),
                };
                let now = Placed::of(&entry);
                match &mut building {
                    Some(built) => {
                        apply(built, &entry.key, now);
                        // The last of the initial values (or a change after them).
                        if entry.delta == 0 {
                            view.install(building.take().unwrap_or_default());
                            tracing::info!("placement view current");
                        }
                    }
                    None => view.changed(&entry.key, now),
                }
            }
            _ = check.tick() => {
                let reconnected = client.statistics().connects.load(Ordering::SeqCst) != connects;
                if reconnected || client.connection_state() != async_nats::connection::State::Connected {
                    return "the connection to NATS was lost".into();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(node: &str, revision: u64) -> Placed {
        Placed { node: Some(node.into()), revision }
    }

    #[test]
    fn a_later_revision_wins_whatever_the_order_it_arrives_in() {
        let mut placed = HashMap::new();
        assert!(apply(&mut placed, "c", at("a", 3)));
        assert!(!apply(&mut placed, "c", at("b", 2)), "an older change");
        assert!(!apply(&mut placed, "c", at("b", 3)), "the same revision");
        assert!(apply(&mut placed, "c", Placed { node: None, revision: 5 }));
        assert_eq!(placed["c"], Placed { node: None, revision: 5 });
    }

    #[test]
    fn a_view_not_current_answers_nothing_and_a_placement_on_this_node_kicks() {
        let view = View::new("me");
        view.wrote("c", Some("me"), 1);
        assert_eq!(view.get("c"), None, "not current: the bucket is read");
        assert_eq!(view.mine(), None);
        view.install(HashMap::from([("c".to_string(), at("other", 4))]));
        assert_eq!(view.get("c"), Some(Some(at("other", 4))));
        assert_eq!(view.get("d"), Some(None));
        // install kicked once; a change naming this node kicks again, another node's does not.
        let kicked = || {
            let waker = futures_util::task::noop_waker();
            let mut cx = std::task::Context::from_waker(&waker);
            let kicked = std::pin::pin!(view.kicked());
            kicked.poll(&mut cx).is_ready()
        };
        use std::future::Future;
        assert!(kicked());
        view.changed("c", at("third", 5));
        assert!(!kicked());
        view.changed("c", at("me", 6));
        assert!(kicked());
        assert_eq!(view.mine(), Some(vec!["c".to_string()]));
    }
}
