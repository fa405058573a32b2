//! Accepting connections within limits (`docs/api.md`, "Connections and limits").
//!
//! `axum::serve` closes nothing that stalls: a connection that never finishes its request head
//! holds a file descriptor for ever, and enough of them (before any token is checked) stop the
//! service. Here every connection is served by hyper-util's `auto::Builder` (HTTP/1, keep-alive,
//! upgrades for the websockets) from our own accept loop, and a small watchdog per connection
//! closes it when
//! - its request head is not complete `header_timeout` after its first byte (or, on a new
//!   connection, after the accept: saying nothing is not finishing either), or
//! - it stays idle between requests (keep-alive) for `idle_timeout`, or
//! - the request body it is sending pauses for longer than `body_timeout` while the handler
//!   waits for it, or it takes nothing of what is written to it for as long (the same attack
//!   as a head that never ends, one step later, and the slow reader).
//!
//! hyper's own `header_read_timeout` is not used: its clock starts when the connection begins to
//! wait for a head, so it would also cut every idle keep-alive connection at the header timeout,
//! and hyper-util's version detection reads the first bytes before that clock runs at all.
//!
//! Open connections are counted per client address and in all; beyond either cap a new
//! connection is closed at once without an answer (answering would mean reading a request, which
//! is what the cap protects against). A websocket stays a counted connection for its whole life
//! and has its own caps; a refused upgrade is answered `429` (this client has too many) or `503`
//! (the service has too many) with the JSON error body.

use std::collections::HashMap;
use std::convert::Infallible;
use std::future::Future;
use std::io;
use std::net::{IpAddr, SocketAddr};
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::body::Body;
use axum::http::{header, Request, Response, StatusCode};
use axum::response::IntoResponse;
use axum::Router;
use hyper::body::{Frame, Incoming, SizeHint};
use hyper_util::rt::{TokioExecutor, TokioIo};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{watch, Notify};
use tokio::time::Instant;
use tower::ServiceExt;

use crate::http::ApiError;

/// The limits of `fivex serve` on connections (flags `--header-timeout`, `--idle-timeout`,
/// `--max-connections`, `--max-connections-per-client`, `--max-websockets`,
/// `--max-websockets-per-client`).
#[derive(Debug, Clone, PartialEq)]
pub struct Limits {
    /// A request head must be complete this long after its first byte (a new connection: after
    /// the accept).
    pub header_timeout: Duration,
    /// A kept-alive connection with no request under way is closed after this long.
    pub idle_timeout: Duration,
    /// The longest pause in a request body the handler is reading, and the longest a client
    /// may take nothing of what is written to it.
    pub body_timeout: Duration,
    pub max_connections: usize,
    pub max_connections_per_client: usize,
    pub max_websockets: usize,
    pub max_websockets_per_client: usize,
}

/// File descriptors kept for everything but client connections (the database, its WAL, logs,
/// the runtime).
const RESERVED_DESCRIPTORS: usize = 64;

impl Limits {
    /// The caps made to fit `descriptors` open files (the process's limit): a connection cap the
    /// process cannot reach would let a flood exhaust the descriptors first and stop `accept`
    /// (and `/healthz`) for everyone. The per-client and websocket caps follow the total.
    pub fn fitted(mut self, descriptors: u64) -> Limits {
        let room = usize::try_from(descriptors).unwrap_or(usize::MAX).saturating_sub(RESERVED_DESCRIPTORS).max(1);
        self.max_connections = self.max_connections.min(room);
        self.max_connections_per_client = self.max_connections_per_client.min(self.max_connections);
        self.max_websockets = self.max_websockets.min(self.max_connections);
        self.max_websockets_per_client = self.max_websockets_per_client.min(self.max_websockets);
        self
    }

    /// The open-file limit raised (up to the hard limit) to what the caps need, and the caps
    /// fitted to what it is then.
    pub fn fitted_to_process(self) -> Limits {
        let wanted = (self.max_connections + RESERVED_DESCRIPTORS) as u64;
        match rlimit::increase_nofile_limit(wanted) {
            Ok(descriptors) => {
                let fitted = self.clone().fitted(descriptors);
                if fitted != self {
                    tracing::warn!(
                        descriptors,
                        max_connections = fitted.max_connections,
                        "the connection caps are lowered to the open-file limit"
                    );
                }
                fitted
            }
            Err(e) => {
                tracing::warn!(error = %e, "cannot read the open-file limit; the caps stay as given");
                self
            }
        }
    }
}

impl Default for Limits {
    /// Generous for a client that behaves (the 1,000-controller load program opens 1,000
    /// websockets from one address), under a file descriptor limit of 20,000.
    fn default() -> Self {
        Limits {
            header_timeout: Duration::from_secs(10),
            idle_timeout: Duration::from_secs(60),
            body_timeout: Duration::from_secs(10),
            max_connections: 10_000,
            max_connections_per_client: 2_000,
            max_websockets: 5_000,
            max_websockets_per_client: 1_500,
        }
    }
}

/// Open things (connections or websockets) counted per client address and in all, each under
/// its cap.
#[derive(Debug)]
struct Counter {
    max: usize,
    max_per_client: usize,
    by_client: Mutex<HashMap<IpAddr, usize>>,
    /// The total, watched so that a shutdown can wait for it to reach 0.
    total: watch::Sender<usize>,
}

/// Why a [`Counter`] refused.
enum Full {
    Client,
    All,
}

/// One counted thing; dropping it gives its place back.
#[derive(Debug)]
struct Ticket {
    counter: Arc<Counter>,
    client: IpAddr,
}

impl Counter {
    fn new(max: usize, max_per_client: usize) -> Arc<Self> {
        Arc::new(Counter { max, max_per_client, by_client: Mutex::default(), total: watch::channel(0).0 })
    }

    fn take(self: &Arc<Self>, client: IpAddr) -> Result<Ticket, Full> {
        let mut by_client = self.by_client.lock().unwrap_or_else(|e| e.into_inner());
        if *self.total.borrow() >= self.max {
            return Err(Full::All);
        }
        let n = by_client.entry(client).or_insert(0);
        if *n >= self.max_per_client {
            return Err(Full::Client);
        }
        *n += 1;
        self.total.send_modify(|t| *t += 1);
        Ok(Ticket { counter: Arc::clone(self), client })
    }

    fn open(&self) -> usize {
        *self.total.borrow()
    }
}

impl Drop for Ticket {
    fn drop(&mut self) {
        let mut by_client = self.counter.by_client.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(n) = by_client.get_mut(&self.client) {
            *n -= 1;
            if *n == 0 {
                by_client.remove(&self.client);
            }
        }
        self.counter.total.send_modify(|t| *t -= 1);
    }
}

/// The open connections and websockets of a server.
#[derive(Debug, Clone)]
pub struct Open {
    connections: Arc<Counter>,
    websockets: Arc<Counter>,
}

impl Open {
    fn new(limits: &Limits) -> Self {
        Open {
            connections: Counter::new(limits.max_connections, limits.max_connections_per_client),
            websockets: Counter::new(limits.max_websockets, limits.max_websockets_per_client),
        }
    }

    /// Connections open now (websockets among them).
    pub fn connections(&self) -> usize {
        self.connections.open()
    }

    /// Resolves when no connection is open any more.
    pub async fn all_closed(&self) {
        let mut rx = self.connections.total.subscribe();
        let _ = rx.wait_for(|n| *n == 0).await;
    }
}

/// The times in [`Activity`] are milliseconds since the accept; `NONE`: not set.
const NONE: u64 = u64::MAX;

/// What one connection is doing, shared by its socket wrapper, its service and its watchdog.
#[derive(Debug)]
struct Activity {
    accepted: Instant,
    /// Requests under way (from the head parsed to the response body sent).
    in_flight: AtomicUsize,
    /// When the connection became idle: the accept, or the end of the last response.
    idle_since: AtomicU64,
    /// When the first byte of the next request head arrived (`NONE`: none yet).
    head_since: AtomicU64,
    /// Since when the handler has been waiting for more of the request body (`NONE`: it is
    /// not).
    body_since: AtomicU64,
    /// Since when a write has been waiting for the client to take what was written.
    write_since: AtomicU64,
    /// Whether a request has been served (a kept-alive connection gets the idle timeout).
    served: AtomicBool,
    /// Wakes the watchdog when its deadline may have come nearer.
    changed: Notify,
    /// The websocket place this connection took for its upgrade.
    websocket: Mutex<Option<Ticket>>,
}

impl Activity {
    fn now(&self) -> u64 {
        self.accepted.elapsed().as_millis() as u64
    }

    /// When the connection is to be closed if nothing changes: while a request is under way
    /// only if its body or a write stalls (the handler takes as long as it takes), else when
    /// the head is late or the idle time is up.
    fn deadline(&self, limits: &Limits) -> Option<Instant> {
        let ms = |at: u64, after: Duration| self.accepted + Duration::from_millis(at) + after;
        let since = |at: &AtomicU64| Some(at.load(Ordering::SeqCst)).filter(|&t| t != NONE);
        let stalled = [since(&self.body_since), since(&self.write_since)]
            .into_iter()
            .flatten()
            .min()
            .map(|t| ms(t, limits.body_timeout));
        if self.in_flight.load(Ordering::SeqCst) > 0 {
            return stalled;
        }
        let head = self.head_since.load(Ordering::SeqCst);
        if head != NONE {
            return Some(ms(head, limits.header_timeout));
        }
        let idle = self.idle_since.load(Ordering::SeqCst);
        let wait = if self.served.load(Ordering::SeqCst) { limits.idle_timeout } else { limits.header_timeout };
        Some(ms(idle, wait)).into_iter().chain(stalled).min()
    }

    /// Notes whether a write had to wait for the client.
    fn wrote<T>(&self, polled: &Poll<T>) {
        if polled.is_pending() {
            if self.write_since.load(Ordering::SeqCst) == NONE {
                self.write_since.store(self.now(), Ordering::SeqCst);
                self.changed.notify_one();
            }
        } else if self.write_since.load(Ordering::SeqCst) != NONE {
            self.write_since.store(NONE, Ordering::SeqCst);
        }
    }
}

/// A request under way on a connection: from the service call until hyper drops the response
/// body (sent, or the connection gone).
struct InFlight(Arc<Activity>);

impl InFlight {
    fn enter(activity: &Arc<Activity>) -> Self {
        activity.in_flight.fetch_add(1, Ordering::SeqCst);
        activity.head_since.store(NONE, Ordering::SeqCst);
        InFlight(Arc::clone(activity))
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        let a = &self.0;
        a.served.store(true, Ordering::SeqCst);
        a.idle_since.store(a.now(), Ordering::SeqCst);
        a.in_flight.fetch_sub(1, Ordering::SeqCst);
        a.changed.notify_one();
    }
}

/// A response body that keeps its request counted as under way until it is dropped.
struct Counted {
    body: Body,
    _in_flight: InFlight,
}

impl hyper::body::Body for Counted {
    type Data = bytes::Bytes;
    type Error = axum::Error;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Self::Data>, Self::Error>>> {
        Pin::new(&mut self.body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

/// A request body that notes when its reader waits for the client (`Activity::body_since`).
struct WatchedBody {
    body: Incoming,
    activity: Arc<Activity>,
}

impl hyper::body::Body for WatchedBody {
    type Data = bytes::Bytes;
    type Error = hyper::Error;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Self::Data>, Self::Error>>> {
        let polled = Pin::new(&mut self.body).poll_frame(cx);
        let a = &self.activity;
        if polled.is_pending() {
            if a.body_since.load(Ordering::SeqCst) == NONE {
                a.body_since.store(a.now(), Ordering::SeqCst);
                a.changed.notify_one();
            }
        } else {
            a.body_since.store(NONE, Ordering::SeqCst);
        }
        polled
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

impl Drop for WatchedBody {
    fn drop(&mut self) {
        // A handler that stops reading (a body over the limit) is no longer waiting.
        self.activity.body_since.store(NONE, Ordering::SeqCst);
    }
}

/// The socket of a connection: notes when a request head starts arriving, and holds the
/// connection's place (and its websocket's) for as long as the socket lives — after an upgrade,
/// as long as the websocket.
struct Watched {
    stream: TcpStream,
    activity: Arc<Activity>,
    _ticket: Ticket,
}

impl AsyncRead for Watched {
    fn poll_read(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        let before = buf.filled().len();
        let polled = Pin::new(&mut self.stream).poll_read(cx, buf);
        let a = &self.activity;
        if buf.filled().len() > before
            && a.in_flight.load(Ordering::SeqCst) == 0
            && a.head_since.load(Ordering::SeqCst) == NONE
        {
            a.head_since.store(a.now(), Ordering::SeqCst);
            a.changed.notify_one();
        }
        polled
    }
}

impl AsyncWrite for Watched {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        let polled = Pin::new(&mut self.stream).poll_write(cx, buf);
        self.activity.wrote(&polled);
        polled
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let polled = Pin::new(&mut self.stream).poll_flush(cx);
        self.activity.wrote(&polled);
        polled
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_shutdown(cx)
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let polled = Pin::new(&mut self.stream).poll_write_vectored(cx, bufs);
        self.activity.wrote(&polled);
        polled
    }

    fn is_write_vectored(&self) -> bool {
        self.stream.is_write_vectored()
    }
}

fn is_websocket(req: &Request<Incoming>) -> bool {
    req.headers()
        .get(header::UPGRADE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.eq_ignore_ascii_case("websocket"))
}

/// Serves `app` on `listener` within `limits` until `shutdown` resolves; then accepts no more,
/// closes every connection that has no request under way, lets the others finish (websockets
/// are told to close by the application) and returns when all are closed or after `grace`.
pub async fn serve(
    listener: TcpListener,
    app: Router,
    limits: Limits,
    grace: Duration,
    shutdown: impl Future<Output = ()>,
) -> Open {
    let open = Open::new(&limits);
    let limits = Arc::new(limits);
    let (stop, stopping) = watch::channel(false);
    tokio::pin!(shutdown);
    loop {
        let (stream, peer) = tokio::select! {
            () = &mut shutdown => break,
            accepted = listener.accept() => match accepted {
                Ok(accepted) => accepted,
                Err(e) => {
                    // Out of file descriptors (or the like): wait for connections to close
                    // instead of spinning on the error.
                    tracing::warn!(error = %e, open = open.connections(), "cannot accept a connection");
                    tokio::time::sleep(Duration::from_millis(100)).await;
                    continue;
                }
            },
        };
        match open.connections.take(peer.ip()) {
            Ok(ticket) => {
                let task =
                    connection(stream, peer, ticket, app.clone(), open.clone(), limits.clone(), stopping.clone());
                tokio::spawn(task);
            }
            // Dropping the stream closes it. Logged at debug only: a flood must not flood the log.
            Err(Full::Client) => tracing::debug!(%peer, "connection refused: too many from this client"),
            Err(Full::All) => tracing::debug!(%peer, "connection refused: too many open"),
        }
    }
    drop(listener);
    let _ = stop.send(true);
    if tokio::time::timeout(grace, open.all_closed()).await.is_err() {
        tracing::warn!(
            ?grace,
            open = open.connections(),
            "connections still open after the grace period; stopping anyway"
        );
    }
    open
}

/// One connection, from the accept to its close.
async fn connection(
    stream: TcpStream,
    peer: SocketAddr,
    ticket: Ticket,
    app: Router,
    open: Open,
    limits: Arc<Limits>,
    mut stopping: watch::Receiver<bool>,
) {
    let activity = Arc::new(Activity {
        accepted: Instant::now(),
        in_flight: AtomicUsize::new(0),
        idle_since: AtomicU64::new(0),
        head_since: AtomicU64::new(NONE),
        body_since: AtomicU64::new(NONE),
        write_since: AtomicU64::new(NONE),
        served: AtomicBool::new(false),
        changed: Notify::new(),
        websocket: Mutex::new(None),
    });
    let io = TokioIo::new(Watched { stream, activity: Arc::clone(&activity), _ticket: ticket });
    let service_activity = Arc::clone(&activity);
    let service = hyper::service::service_fn(move |req: Request<Incoming>| {
        let (app, open, activity) = (app.clone(), open.clone(), Arc::clone(&service_activity));
        async move { Ok::<_, Infallible>(respond(req, peer, app, &open, activity).await) }
    });
    let mut builder = hyper_util::server::conn::auto::Builder::new(TokioExecutor::new());
    builder.http1().keep_alive(true);
    let conn = builder.serve_connection_with_upgrades(io, service);
    tokio::pin!(conn);
    let mut stopping_now = *stopping.borrow();
    loop {
        if stopping_now && activity.in_flight.load(Ordering::SeqCst) == 0 {
            // Nothing under way: nothing to finish.
            return;
        }
        let deadline = activity.deadline(&limits);
        let expired = async {
            match deadline {
                Some(at) => tokio::time::sleep_until(at).await,
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            result = conn.as_mut() => {
                if let Err(e) = result {
                    tracing::debug!(%peer, error = %e, "connection ended with an error");
                }
                return;
            }
            () = expired => {
                // Looked at again: a request may have started just now.
                if activity.deadline(&limits).is_some_and(|at| at <= Instant::now()) {
                    tracing::debug!(%peer, "connection closed: request head, body, write or keep-alive timeout");
                    return;
                }
            }
            () = activity.changed.notified() => {}
            _ = stopping.changed(), if !stopping_now => {
                stopping_now = true;
                conn.as_mut().graceful_shutdown();
            }
        }
    }
}

/// The application's answer to one request, counted as under way until its body is sent; a
/// websocket upgrade takes a websocket place first.
async fn respond(
    req: Request<Incoming>,
    peer: SocketAddr,
    app: Router,
    open: &Open,
    activity: Arc<Activity>,
) -> Response<Counted> {
    let in_flight = InFlight::enter(&activity);
    let upgrade = is_websocket(&req);
    let response = if upgrade {
        match open.websockets.take(peer.ip()) {
            Ok(ticket) => {
                *activity.websocket.lock().unwrap_or_else(|e| e.into_inner()) = Some(ticket);
                None
            }
            Err(Full::Client) => Some(refused(StatusCode::TOO_MANY_REQUESTS, "too many websockets from this client")),
            Err(Full::All) => Some(refused(StatusCode::SERVICE_UNAVAILABLE, "too many websockets open")),
        }
    } else {
        None
    };
    let response = match response {
        Some(refused) => refused,
        None => {
            let watched = Arc::clone(&activity);
            let mut req = req.map(|body| Body::new(WatchedBody { body, activity: watched }));
            req.extensions_mut().insert(axum::extract::ConnectInfo(peer));
            let response = app.oneshot(req).await.unwrap_or_else(|never| match never {});
            if upgrade && response.status() != StatusCode::SWITCHING_PROTOCOLS {
                activity.websocket.lock().unwrap_or_else(|e| e.into_inner()).take();
            }
            response
        }
    };
    response.map(|body| Counted { body, _in_flight: in_flight })
}

fn refused(status: StatusCode, why: &str) -> Response<Body> {
    let mut response = ApiError::Rejected(status, why.to_string()).into_response();
    response.headers_mut().insert(header::RETRY_AFTER, header::HeaderValue::from_static("5"));
    response
}

#[cfg(test)]
mod fitting {
    use super::*;

    #[test]
    fn the_caps_fit_the_open_file_limit() {
        let wide = Limits::default();
        assert_eq!(wide.clone().fitted(1_000_000), wide, "room enough: unchanged");
        let tight = wide.fitted(1024);
        assert_eq!(tight.max_connections, 1024 - RESERVED_DESCRIPTORS);
        assert_eq!(tight.max_connections_per_client, tight.max_connections);
        assert_eq!(tight.max_websockets, tight.max_connections);
        assert_eq!(tight.max_websockets_per_client, tight.max_connections);
        assert_eq!(Limits::default().fitted(10).max_connections, 1, "never zero");
    }
}
