//! What every handler can reach ([`AppState`]) and the service's graceful end.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::watch;

use crate::host::Host;
use crate::origin::AllowedOrigins;
use crate::{api, db, metrics, service};

/// How long in-flight requests may take to finish after a shutdown signal before the server
/// stops anyway.
pub const SHUTDOWN_GRACE: Duration = Duration::from_secs(10);

/// Everything a handler can reach. Cheap to clone (the pool and the host are handles over
/// shared state).
#[derive(Clone, Debug)]
pub struct AppState {
    /// The database: readers and the one writer (`db::Db`).
    pub db: db::Db,
    /// The hosted controllers and their workers.
    pub host: Host,
    /// Set when the service shuts down, so websockets close cleanly.
    closing: Arc<watch::Sender<bool>>,
    /// The database writer of the workers' records, awaited at shutdown.
    writer: Arc<std::sync::Mutex<Option<tokio::task::JoinHandle<()>>>>,
    /// The bearer token the API requires, if any.
    token: Option<Arc<str>>,
    /// The origins besides the served one whose pages may drive the service.
    allowed_origins: AllowedOrigins,
    /// The fleet runs under way and their progress.
    pub fleet_runs: service::fleet_runs::Runs,
    /// What the fleet stream's subscribers share (`api::fleet_view`).
    pub fleet_view: api::fleet_view::FleetView,
    /// What the layers count for `/metrics`.
    pub metrics: metrics::Metrics,
    /// This process as a node (`/readyz`).
    pub node: Arc<Node>,
    /// With `--nats` and PostgreSQL: the cluster of controller hosts (`crate::placement`); the
    /// host holds only the controllers placed on this node.
    pub cluster: Option<crate::placement::Cluster>,
}

/// This process as a node of the service: one today; the cluster (issue 23) will have several.
#[derive(Debug, Clone)]
pub struct Node {
    /// Made at start: a new one every time the process starts.
    pub id: String,
    /// When the process started, RFC 3339 UTC.
    pub started_at: String,
}

impl Node {
    fn new() -> Node {
        Node { id: uuid::Uuid::new_v4().simple().to_string(), started_at: crate::host::now_rfc3339() }
    }
}

impl AppState {
    /// Opens (creating if missing) and migrates the SQLite database at `path`, and brings back
    /// every stored controller in reset state.
    pub async fn open(path: &Path) -> Result<Self, db::OpenError> {
        let pool = db::open(path).await?;
        Self::restore(pool).await.map_err(|source| db::OpenError::Load { path: path.display().to_string(), source })
    }

    /// State over an already opened and migrated pool: the controllers it stores are hosted
    /// again (one that cannot be, a machine document this version refuses, is logged and left
    /// in the database untouched).
    pub async fn restore(db: db::Db) -> Result<Self, sqlx::Error> {
        Self::restore_with(db, Host::default_workers()).await
    }

    /// [`AppState::restore`] with `workers` worker threads.
    pub async fn restore_with(db: db::Db, workers: usize) -> Result<Self, sqlx::Error> {
        Self::start_with(db, workers, true).await
    }

    /// State over `db` hosting no controller yet: a node of a cluster hosts those placed on it
    /// (`crate::placement`).
    pub async fn clustered(
        db: db::Db,
        workers: usize,
        cluster: crate::placement::Cluster,
    ) -> Result<Self, sqlx::Error> {
        let mut state = Self::start_with(db, workers, false).await?;
        state.cluster = Some(cluster);
        Ok(state)
    }

    async fn start_with(db: db::Db, workers: usize, restore: bool) -> Result<Self, sqlx::Error> {
        let (records, incoming) = tokio::sync::mpsc::unbounded_channel();
        let writer = tokio::spawn(db::write_records(db.clone(), incoming));
        let host = Host::new(workers, records);
        // A single node marks the fleet runs its last process left under way as interrupted
        // (in `restore`); a node of a cluster does not: on the shared database they may be
        // other nodes' runs, under way, and those whose node is gone are taken over
        // (`service::fleet_rescue`).
        if restore {
            service::controllers::restore(&db, &host).await?;
        }
        let (closing, _) = watch::channel(false);
        Ok(Self {
            db,
            host,
            closing: Arc::new(closing),
            writer: Arc::new(std::sync::Mutex::new(Some(writer))),
            token: None,
            allowed_origins: AllowedOrigins::default(),
            fleet_runs: Default::default(),
            fleet_view: Default::default(),
            metrics: Default::default(),
            node: Arc::new(Node::new()),
            cluster: None,
        })
    }

    /// Require `Authorization: Bearer token` on the API (an empty token requires nothing).
    pub fn with_token(mut self, token: Option<String>) -> Self {
        self.token = token.filter(|t| !t.is_empty()).map(Arc::from);
        self
    }

    /// The bearer token the API requires, if any.
    pub fn token(&self) -> Option<&str> {
        self.token.as_deref()
    }

    /// Let pages from these origins drive the service too (`--allow-origin`, `origin.rs`).
    pub fn with_allowed_origins(mut self, origins: AllowedOrigins) -> Self {
        self.allowed_origins = origins;
        self
    }

    pub fn allowed_origins(&self) -> &AllowedOrigins {
        &self.allowed_origins
    }

    /// A receiver that changes when the service starts shutting down.
    pub fn closing(&self) -> watch::Receiver<bool> {
        self.closing.subscribe()
    }

    /// Whether the service is shutting down.
    pub fn is_closing(&self) -> bool {
        *self.closing.borrow()
    }

    /// Tell every websocket to close (the start of a graceful shutdown).
    pub fn close(&self) {
        self.closing.send_replace(true);
    }

    /// How many fleet runs run at once (the others wait, `queued`).
    pub fn with_fleet_jobs(mut self, jobs: usize) -> Self {
        self.fleet_runs = service::fleet_runs::Runs::new(jobs);
        self
    }

    /// Fleet runs go to a cluster over NATS (`fivex serve --nats`, `crate::cluster`).
    pub fn with_fleet_remote(mut self, remote: service::fleet_runs::Remote) -> Self {
        self.fleet_runs = self.fleet_runs.with_remote(remote);
        self
    }

    /// The end of a graceful shutdown: websockets told to close, fleet runs interrupted and
    /// recorded, the workers stopped, and everything they produced written to the database.
    pub async fn shutdown(&self) {
        self.close();
        self.fleet_runs.interrupt_all();
        if tokio::time::timeout(SHUTDOWN_GRACE, self.fleet_runs.all_ended()).await.is_err() {
            tracing::warn!("fleet runs still under way after the grace period");
        }
        let host = self.host.clone();
        let _ = tokio::task::spawn_blocking(move || host.shutdown()).await;
        let writer = self.writer.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(writer) = writer {
            let _ = writer.await;
        }
        // Everything written: the other nodes may take the controllers over.
        if let Some(cluster) = &self.cluster {
            cluster.leave(self).await;
        }
    }
}
