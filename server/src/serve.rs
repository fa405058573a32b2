//! `fivex serve`: the command's start-up (runtime, database, restored controllers, listener,
//! logging), serving the HTTP application (`crate::http`) until a signal, and the graceful end.

use std::future::Future;
use std::path::Path;
use std::time::Duration;

use tokio::net::TcpListener;

use crate::db;
use crate::host::Host;
use crate::http::state::SHUTDOWN_GRACE;
use crate::http::{app, AppState};
use crate::listen::Limits;
use crate::origin::{self, AllowedOrigins};

/// Serves [`app`] on `listener` with the default [`Limits`] until `shutdown` resolves
/// ([`serve_with`]).
pub async fn serve<F>(listener: TcpListener, state: AppState, shutdown: F) -> std::io::Result<()>
where
    F: Future<Output = ()> + Send + 'static,
{
    serve_with(listener, state, Limits::default(), shutdown).await
}

/// Serves [`app`] on `listener` within `limits` (`crate::listen`) until `shutdown` resolves;
/// then accepts no more connections, tells every websocket to close, interrupts the fleet runs,
/// closes the idle connections and lets in-flight requests finish, for at most
/// [`SHUTDOWN_GRACE`].
pub async fn serve_with<F>(listener: TcpListener, state: AppState, limits: Limits, shutdown: F) -> std::io::Result<()>
where
    F: Future<Output = ()> + Send + 'static,
{
    let closing = state.clone();
    let signal = async move {
        shutdown.await;
        tracing::info!("shutting down: no new connections, finishing in-flight requests");
        closing.close();
        // A fleet run holds its request (`wait`) and a blocking thread until it ends: it ends now.
        closing.fleet_runs.interrupt_all();
    };
    crate::listen::serve(listener, app(state), limits, SHUTDOWN_GRACE, signal).await;
    Ok(())
}

/// A future that resolves on Ctrl-C (SIGINT) or, on Unix, SIGTERM. The handlers are installed
/// when this is called (it must run inside a tokio runtime), not when the future is first
/// polled, so no signal that arrives after the call is lost or kills the process.
pub fn shutdown_signal() -> std::io::Result<impl Future<Output = ()> + Send + 'static> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, SignalKind};
        let mut interrupt = signal(SignalKind::interrupt())?;
        let mut terminate = signal(SignalKind::terminate())?;
        Ok(async move {
            tokio::select! {
                _ = interrupt.recv() => tracing::info!("received Ctrl-C"),
                _ = terminate.recv() => tracing::info!("received SIGTERM"),
            }
        })
    }
    #[cfg(not(unix))]
    {
        Ok(async {
            match tokio::signal::ctrl_c().await {
                Ok(()) => tracing::info!("received Ctrl-C"),
                Err(e) => {
                    tracing::error!(error = %e, "cannot listen for Ctrl-C");
                    std::future::pending::<()>().await
                }
            }
        })
    }
}

/// Logs to stderr (colored only on a terminal); `RUST_LOG` filters, default `info` (async-opcua's
/// address-space warnings left out). Does nothing if a subscriber is already set.
fn init_tracing() {
    use std::io::IsTerminal;
    use tracing_subscriber::EnvFilter;
    // async-opcua warns at every start about nodes the companion nodesets reference twice in
    // their type trees (nothing a user can act on): only its errors by default.
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info,opcua_server::address_space=error"));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .try_init();
}

/// How `fivex serve` runs (flags or `FIVEX_DB`, `FIVEX_ADDR`, `FIVEX_TOKEN`, `FIVEX_WORKERS`,
/// `FIVEX_ALLOW_ORIGIN`, and the limits' `FIVEX_…`, `cli/limits.rs`).
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// A SQLite file, or a `postgres://` URL (`db::open_any`).
    pub db: std::path::PathBuf,
    pub addr: String,
    pub token: Option<String>,
    pub workers: Option<usize>,
    pub allow_origins: Vec<origin::Origin>,
    /// Connection timeouts and caps.
    pub limits: Limits,
    /// Fleet runs that run at once (at least 1).
    pub fleet_jobs: usize,
    /// `--nats`: the NATS server of a distributed fleet (`crate::cluster`).
    pub nats: Option<String>,
    /// Fleet jobs this node runs at once with `--nats` (default: one per core).
    pub nats_jobs: Option<usize>,
    /// With `--nats`: a run gives up when no node nor result was heard from for this long.
    pub nats_idle: Duration,
    /// `--node`: this node's name in the cluster of controller hosts (`--nats` with a
    /// PostgreSQL database, `crate::placement`); default: the host's name.
    pub node: Option<String>,
    /// `--mtconnect`, `--opcua`: the shop-floor interfaces (`crate::shopfloor`).
    pub shopfloor: crate::shopfloor::Options,
}

/// Joins the cluster of controller hosts as `name`, or else as the host's name (with a suffix
/// when a node already has it).
async fn join(nats: &crate::cluster::Nats, name: Option<&str>) -> Result<crate::placement::Cluster, String> {
    use crate::placement::{default_name, Cluster};
    match name {
        Some(name) => Cluster::join(nats, name).await,
        None => match Cluster::join(nats, &default_name()).await {
            Ok(cluster) => Ok(cluster),
            Err(_) => {
                Cluster::join(nats, &format!("{}-{}", default_name(), &uuid::Uuid::new_v4().simple().to_string()[..8]))
                    .await
            }
        },
    }
}

/// `fivex serve` with the database and address only.
pub fn run_blocking(db: &Path, addr: &str) -> Result<(), String> {
    run_with(ServeOptions {
        db: db.to_path_buf(),
        addr: addr.to_string(),
        token: None,
        workers: None,
        allow_origins: Vec::new(),
        limits: Limits::default(),
        fleet_jobs: 1,
        nats: None,
        nats_jobs: None,
        nats_idle: crate::cluster::IDLE_TIMEOUT,
        node: None,
        shopfloor: Default::default(),
    })
}

/// `fivex serve`: opens (creating and migrating) the database, brings the stored controllers
/// back, listens on the address and serves until Ctrl-C or SIGTERM, then shuts down gracefully
/// (websockets closed, workers stopped, their records written). Returns a message for the user
/// on any failure (database, address in use, …).
pub fn run_with(options: ServeOptions) -> Result<(), String> {
    init_tracing();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_name("fivex-serve")
        .build()
        .map_err(|e| format!("cannot start the async runtime: {e}"))?;
    let served = runtime.block_on(async {
        let (db, addr) = (db::shown(&options.db.to_string_lossy()), &options.addr);
        // One service per SQLite file, for the process's life (`db::lock_sqlite`); PostgreSQL
        // is shared by design (the nodes of a cluster).
        let _lock =
            if db::is_postgres(&options.db.to_string_lossy()) { None } else { Some(db::lock_sqlite(&options.db)?) };
        let pool = db::open_any(&options.db.to_string_lossy()).await.map_err(|e| e.to_string())?;
        let workers = options.workers.unwrap_or_else(Host::default_workers);
        let postgres = pool.backend() == db::Backend::Postgres;
        let nats = match &options.nats {
            Some(url) => Some(crate::cluster::connect(url).await?),
            None => None,
        };
        // Controllers across nodes: with NATS and a shared (PostgreSQL) database only.
        let cluster = match (&nats, postgres) {
            (Some(nats), true) => Some(join(nats, options.node.as_deref()).await?),
            (Some(_), false) if options.node.is_some() => {
                return Err("--node: controllers hosted across nodes need a shared PostgreSQL --db (SQLite is one process's file)".to_string());
            }
            (Some(_), false) => {
                tracing::warn!("--nats with SQLite: fleet runs go to the cluster; controllers stay on this node (they need a PostgreSQL --db to be shared)");
                None
            }
            (None, _) => None,
        };
        // A single node with --nats marks the runs its last process left under way interrupted
        // (restoring): their jobs and results are withdrawn from NATS too.
        let orphans = match (&nats, &cluster) {
            (Some(_), None) => db::unfinished_fleet_runs(&pool).await.map_err(|e| format!("cannot read {db}: {e}"))?,
            _ => Vec::new(),
        };
        let state = match cluster.clone() {
            Some(cluster) => AppState::clustered(pool, workers, cluster).await,
            None => AppState::restore_with(pool, workers).await,
        };
        let state = state
            .map_err(|e| format!("cannot read the controllers of {db}: {e}"))?
            .with_token(options.token.clone())
            .with_allowed_origins(AllowedOrigins::new(options.allow_origins.clone()))
            .with_fleet_jobs(options.fleet_jobs);
        let state = match (&options.nats, nats) {
            (Some(url), Some(nats)) => {
                for id in &orphans {
                    crate::cluster::withdraw(&nats, id).await;
                    crate::cluster::clean(&nats, id).await;
                }
                let jobs = options.nats_jobs.unwrap_or_else(crate::fleet::default_jobs).max(1);
                let node = crate::cluster::start_node(&nats, jobs).await?;
                // On a cluster, runs outlive their node (`crate::fleet_lease`).
                let leases = match &cluster {
                    Some(c) => Some(crate::fleet_lease::Leases::open(&nats, c.name(), c.watch_members()).await?),
                    None => None,
                };
                tracing::info!(nats = %url, jobs, "fleet runs go to the cluster");
                let remote = crate::service::fleet_runs::Remote { nats, node, idle: options.nats_idle, leases };
                state.with_fleet_remote(remote)
            }
            _ => state,
        };
        if let Some(cluster) = &cluster {
            cluster.start(state.clone(), app(state.clone())).await?;
            crate::service::fleet_rescue::start(state.db.clone(), state.fleet_runs.clone());
            tracing::info!(node = cluster.name(), members = ?cluster.members(), controllers = state.host.len(), "joined the cluster of controller hosts");
        }
        tracing::info!(db = %db, workers, token = state.token().is_some(), "database ready");
        tracing::info!(limits = ?options.limits, fleet_jobs = options.fleet_jobs, "limits");
        let shopfloor = crate::shopfloor::start(&options.shopfloor, &state).await?;
        let listener = TcpListener::bind(addr).await.map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        let local = listener.local_addr().map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        // Installed before announcing the address: once the line below is logged, SIGINT and
        // SIGTERM shut the server down gracefully instead of killing it.
        let shutdown = shutdown_signal().map_err(|e| format!("cannot install signal handlers: {e}"))?;
        tracing::info!("fivex listening on http://{local}");
        let after = state.clone();
        serve_with(listener, state, options.limits.clone().fitted_to_process(), shutdown)
            .await
            .map_err(|e| format!("server error: {e}"))?;
        if let Some(shopfloor) = shopfloor {
            shopfloor.stop().await;
        }
        after.shutdown().await;
        after.db.close().await;
        tracing::info!("fivex stopped");
        Ok(())
    });
    // Dropping a runtime waits for its blocking threads; whatever is still on one (a request
    // stuck past the grace period) must not hold the exit.
    runtime.shutdown_timeout(Duration::from_secs(1));
    served
}
