//! The MTConnect agent: every controller this process hosts as an MTConnect device, served on
//! its own address with the standard's requests (`/probe`, `/current`, `/sample`, `/assets`, each
//! also under `/{device}/`), XML by default and the JSON form on request (docs/shopfloor.md).
//!
//! `model` makes a controller a device; `buffer` numbers the observations and keeps the last
//! ones; `documents` builds the response documents as trees that `doc` prints as XML or JSON;
//! `http` answers the requests.

mod buffer;
mod doc;
mod documents;
mod http;
mod model;

use std::sync::{Arc, Mutex, MutexGuard};

use tokio::net::TcpListener;
use tokio::sync::watch;

use super::observe::Round;
use crate::host::Host;
use crate::http::AppState;

/// Observations kept for `/sample` by default (the reference agent's 2^17).
pub const DEFAULT_BUFFER: usize = 131_072;

/// The version of the standard the documents follow (their namespaces and schemas).
pub const SCHEMA_VERSION: &str = "2.5";

/// The header's `version`: the standard's version the agent implements.
const AGENT_VERSION: &str = "2.5.0.0";

/// What the request handlers share.
#[derive(Clone)]
struct Shared {
    buffer: Arc<Mutex<buffer::Buffer>>,
    /// The buffer's next sequence, for `/sample` clients waiting for more.
    next: watch::Receiver<u64>,
    sender: Arc<documents::Sender>,
    host: Host,
    /// Set when the agent stops: streaming responses end.
    stopped: watch::Receiver<bool>,
}

impl Shared {
    fn buffer(&self) -> MutexGuard<'_, buffer::Buffer> {
        self.buffer.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The agent running; [`Agent::stop`] ends it.
#[derive(Debug)]
pub struct Agent {
    stop: watch::Sender<bool>,
    tasks: Vec<tokio::task::JoinHandle<()>>,
}

impl Agent {
    /// Listens on `addr` and serves the controllers of `state` as the observer's `rounds` show
    /// them, keeping `capacity` observations.
    pub async fn start(
        addr: &str,
        capacity: usize,
        mut rounds: watch::Receiver<Arc<Round>>,
        state: &AppState,
    ) -> Result<Agent, String> {
        let listener =
            TcpListener::bind(addr).await.map_err(|e| format!("--mtconnect: cannot listen on {addr}: {e}"))?;
        let local = listener.local_addr().map_err(|e| format!("--mtconnect: {e}"))?;
        let buffer = Arc::new(Mutex::new(buffer::Buffer::new(capacity)));
        let (next_tx, next) = watch::channel(1);
        let sender = documents::Sender {
            sender: crate::placement::default_name(),
            instance_id: u64::try_from(time::OffsetDateTime::now_utc().unix_timestamp()).unwrap_or(1),
            buffer_size: capacity.max(1),
        };
        let (stop, stopped) = watch::channel(false);
        let shared = Shared {
            buffer: buffer.clone(),
            next,
            sender: Arc::new(sender),
            host: state.host.clone(),
            stopped: stopped.clone(),
        };

        // Every round of the observer becomes observations.
        let mut until = stopped.clone();
        let observing = tokio::spawn(async move {
            loop {
                tokio::select! {
                    changed = rounds.changed() => if changed.is_err() { break },
                    _ = until.wait_for(|s| *s) => break,
                }
                let round = rounds.borrow_and_update().clone();
                let next = {
                    let mut b = buffer.lock().unwrap_or_else(|e| e.into_inner());
                    b.observe(&round);
                    b.next_sequence()
                };
                next_tx.send_replace(next);
            }
        });

        let mut until = stopped;
        let app = http::router(shared);
        let serving = tokio::spawn(async move {
            let shutdown = async move {
                let _ = until.wait_for(|s| *s).await;
            };
            if let Err(e) = axum::serve(listener, app).with_graceful_shutdown(shutdown).await {
                tracing::error!(error = %e, "the MTConnect agent stopped");
            }
        });
        tracing::info!("MTConnect agent at http://{local}/");
        Ok(Agent { stop, tasks: vec![observing, serving] })
    }

    /// Stops serving (streams in progress end) and observing.
    pub async fn stop(self) {
        self.stop.send_replace(true);
        for mut task in self.tasks {
            // Streams end at the stop (they watch it); a connection that still holds on after
            // a grace is cut.
            if tokio::time::timeout(std::time::Duration::from_secs(5), &mut task).await.is_err() {
                task.abort();
            }
        }
    }
}
