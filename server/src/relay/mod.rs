//! A controller's stream across nodes (issue 23 item 2; docs/cluster.md, "Streams across
//! nodes"): the websocket `/api/v1/controllers/{id}/stream` of a controller hosted by another
//! node, on the node that holds the client's websocket (the *relaying* node).
//!
//! - The owner publishes the stream of each of its controllers that some node relays, once,
//!   on the controller's subjects `fivex.controllers.{id}.stream.*`, while a relaying node says
//!   it is interested ([`publisher`]): every position frame as the workers publish it (full
//!   rate: up to one per tick), every event message, the snapshots relaying nodes ask for.
//! - A relaying node subscribes once per controller, however many of its clients watch it, and
//!   fans the messages out to them ([`hub`]); each client's `?rate=` is kept at the relaying
//!   node, from the full-rate feed, by the pacing the local stream uses (`api::stream::Pace`).
//! - A client's stream ([`session`]) starts with a snapshot it asks the owner for (request/reply
//!   on `fivex.nodes.{owner}.stream`), which the owner publishes on the controller's subject
//!   behind everything published before it: what came before it on the subject is in it, what
//!   comes after is news. When the controller moves to another node (its owner killed or
//!   stopped), the hub finds it there and every client gets a fresh snapshot from its new node.
//!
//! Every message a client gets is the text the owner's local stream sends, byte for byte.

pub mod hub;
pub mod publisher;
pub mod session;

use std::time::Duration;

/// How often a relaying node says it is still interested in a controller's stream, and looks
/// whether the controller's node is still a member.
pub const ALIVE: Duration = Duration::from_secs(1);
/// The owner stops publishing a controller's stream when no relaying node said it is
/// interested for this long (a relaying node that leaves says so at once).
pub const IDLE: Duration = Duration::from_secs(5);
/// How long a relayed stream waits for its controller to be hosted again (or for a snapshot of
/// it) before it closes with 1012.
pub const FOLLOW_LIMIT: Duration = Duration::from_secs(30);
/// How long a relaying node waits for the owner's answer to a snapshot request, and then for
/// the snapshot, before it asks again.
pub const SNAPSHOT_TIMEOUT: Duration = Duration::from_secs(5);

/// Header: a publisher's message number (`start` is 0, each later message but a position one
/// more), so a relaying node notices a message lost.
pub const SEQ: &str = "fivex-seq";
/// Header of a snapshot message: the token of the request it answers.
pub const TOKEN: &str = "fivex-token";
/// Header of an interest message: `end` when the relaying node's last client left.
pub const INTEREST: &str = "fivex-interest";
/// Header of an answer: the HTTP status (`101`: the snapshot is published).
pub const STATUS: &str = "fivex-status";

/// The subject of one kind of message of controller `id`'s stream: `start`, `position`,
/// `event`, `snapshot`, `gone`, `close`.
pub fn stream_subject(id: &str, kind: &str) -> String {
    format!("fivex.controllers.{id}.stream.{kind}")
}

/// Every message of controller `id`'s stream (what a relaying node subscribes to).
pub fn stream_subjects(id: &str) -> String {
    format!("fivex.controllers.{id}.stream.>")
}

/// Where relaying nodes say they are interested in controller `id`'s stream.
pub fn interest_subject(id: &str) -> String {
    format!("fivex.controllers.{id}.interest")
}

/// Every controller's interest subject (what every node of the cluster listens to).
pub const INTEREST_SUBJECTS: &str = "fivex.controllers.*.interest";

/// The subject on which node `node` takes snapshot requests for its controllers.
pub fn snapshot_subject(node: &str) -> String {
    format!("fivex.nodes.{node}.stream")
}

/// A relaying node asks the owner for a snapshot of controller `id`, published on its
/// `snapshot` subject with `token`; `relay` names the asking hub (`NODE/N`), interested from now.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct SnapshotRequest {
    pub id: String,
    pub relay: String,
    pub token: u64,
}

/// Both sides of this node's relaying: the streams it publishes for other nodes and the
/// streams of other nodes' controllers it relays to its clients.
#[derive(Default)]
pub struct Relays {
    pub publishers: publisher::Publishers,
    pub hubs: hub::Hubs,
}

/// What `/metrics` shows of the relaying.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Census {
    /// Controllers of other nodes this node relays: one NATS subscription each, shared by all
    /// of this node's websocket clients of that controller.
    pub subscriptions: usize,
    /// Controllers hosted here whose stream this node publishes for relaying nodes.
    pub publishers: usize,
    /// Websocket clients of relayed controllers on this node.
    pub clients: usize,
}

impl Relays {
    pub fn census(&self) -> Census {
        Census {
            subscriptions: self.hubs.subscriptions(),
            publishers: self.publishers.count(),
            clients: self.hubs.clients(),
        }
    }
}

fn lock<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}
