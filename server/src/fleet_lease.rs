//! Which node of a cluster collects each fleet run over NATS (issue 23; docs/fleet.md "Over
//! NATS", docs/cluster.md): with a shared PostgreSQL database a run outlives the node it was
//! submitted to, because any node can find out that its collector is gone and take it over
//! (`service::fleet_rescue`).
//!
//! - Bucket [`RUNS_BUCKET`] (JetStream key-value, no expiry): run id → the name of the node
//!   collecting its results. The submitting node creates the key before it stores the run, so
//!   a run of the database under way without a key has no collector.
//! - The lease is the collector's membership of the cluster (`placement::NODES_BUCKET`,
//!   refreshed every beat, 5 s; the members as the node's last beat saw them come in): a run is free ([`Leases::free`]) when its collector is no longer a member (killed,
//!   cut off), when its key is deleted (the collector stopped cleanly and handed the run over),
//!   or when the key names this node but the run is not collected here (this node restarted
//!   under the same name). A claim is revision-checked (`create` for a missing key, `update` at
//!   the revision read otherwise), so of several nodes claiming at once exactly one wins.
//! - A run over has its key purged from the bucket's stream ([`Leases::end`]): no marker is
//!   left, the bucket does not grow with the runs.

use std::time::Duration;

use async_nats::jetstream::{self, kv};
use bytes::Bytes;
use futures_util::StreamExt;

use tokio::sync::watch;

use crate::cluster::Nats;

/// Run id → the node collecting it.
pub const RUNS_BUCKET: &str = "fivex_fleet_runs";

/// How often a node of a cluster looks after the fleet runs (`service::fleet_rescue`).
pub const BEAT: Duration = Duration::from_secs(1);

/// This node's view of the collectors' leases.
#[derive(Clone)]
pub struct Leases {
    /// This node's name.
    node: String,
    /// The members of the cluster as this node's last beat saw them.
    members: watch::Receiver<Vec<String>>,
    bucket: kv::Store,
    /// The bucket's stream, to purge a key with its markers.
    stream: jetstream::stream::Stream,
}

impl std::fmt::Debug for Leases {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Leases").field("node", &self.node).finish()
    }
}

/// Who collects a run, as the bucket says.
#[derive(Debug, Clone, PartialEq)]
pub struct Holder {
    /// The collecting node; `None`: no key, or a deleted one.
    pub node: Option<String>,
    /// The key's revision (0: no key), for a claim.
    pub revision: u64,
}

impl Leases {
    /// Makes sure of the bucket; this node is `node` among `members`.
    pub async fn open(nats: &Nats, node: &str, members: watch::Receiver<Vec<String>>) -> Result<Leases, String> {
        let bucket = crate::cluster::key_value(nats.jetstream(), RUNS_BUCKET, Duration::ZERO).await?;
        let stream = nats
            .jetstream()
            .get_stream(format!("KV_{RUNS_BUCKET}"))
            .await
            .map_err(|e| format!("NATS: cannot open the bucket {RUNS_BUCKET}: {e}"))?;
        Ok(Leases { node: node.to_string(), members, bucket, stream })
    }

    /// This node's name.
    pub fn node(&self) -> &str {
        &self.node
    }

    /// A run submitted here is collected here (its key made before the run is stored).
    pub async fn take_new(&self, run: &str) -> Result<(), String> {
        self.bucket
            .create(run, Bytes::from(self.node().to_string()))
            .await
            .map(|_| ())
            .map_err(|e| format!("NATS: cannot record the collector of fleet run {run}: {e}"))
    }

    /// Who collects run `run`.
    pub async fn holder(&self, run: &str) -> Result<Holder, String> {
        let entry = self
            .bucket
            .entry(run)
            .await
            .map_err(|e| format!("NATS: cannot read the collector of fleet run {run}: {e}"))?;
        Ok(match entry {
            Some(e) if e.operation == kv::Operation::Put => {
                Holder { node: Some(String::from_utf8_lossy(&e.value).into_owned()), revision: e.revision }
            }
            Some(e) => Holder { node: None, revision: e.revision },
            None => Holder { node: None, revision: 0 },
        })
    }

    /// Whether a run not collected here, held by `holder`, is to be taken over: no collector,
    /// one that is no longer a member, or this node's name from before a restart.
    pub fn free(&self, holder: &Holder) -> bool {
        match &holder.node {
            None => true,
            Some(node) => node == self.node() || !self.members.borrow().contains(node),
        }
    }

    /// Claims run `run` for this node at `revision` (0: no key); whether this node won.
    pub async fn claim(&self, run: &str, revision: u64) -> bool {
        let me = Bytes::from(self.node().to_string());
        let won = if revision == 0 {
            self.bucket.create(run, me).await.is_ok()
        } else {
            self.bucket.update(run, me, revision).await.is_ok()
        };
        if won {
            tracing::info!(%run, node = %self.node(), "fleet run claimed");
        }
        won
    }

    /// Hands run `run` over (this node stops cleanly): its key is deleted if it still names
    /// this node, so any node (this one after a restart too) takes it at its next beat.
    pub async fn release(&self, run: &str) {
        match self.holder(run).await {
            Ok(Holder { node: Some(node), revision }) if node == self.node() => {
                if let Err(e) = self.bucket.delete_expect_revision(run, Some(revision)).await {
                    tracing::warn!(%run, error = %e, "fleet run not handed over: its collector stays recorded");
                }
            }
            Ok(_) => {}
            Err(e) => tracing::warn!(%run, error = %e, "fleet run not handed over"),
        }
    }

    /// Run `run` is over: its key leaves the bucket, markers and all.
    pub async fn end(&self, run: &str) {
        if let Err(e) = self.stream.purge().filter(format!("$KV.{RUNS_BUCKET}.{run}")).await {
            tracing::warn!(%run, error = %e, "fleet run's collector key not purged");
        }
    }

    /// Every run with a key (or a marker) in the bucket.
    pub async fn runs(&self) -> Result<Vec<String>, String> {
        let mut keys =
            self.bucket.keys().await.map_err(|e| format!("NATS: cannot list the bucket {RUNS_BUCKET}: {e}"))?;
        let mut out = Vec::new();
        while let Some(key) = keys.next().await {
            out.push(key.map_err(|e| format!("NATS: cannot list the bucket {RUNS_BUCKET}: {e}"))?);
        }
        Ok(out)
    }
}
