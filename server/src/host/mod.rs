//! The controllers the service hosts: a registry of engine [`Controller`]s, each behind a mutex,
//! ticked by a pool of worker threads (not the async runtime) paced to real time.
//!
//! A handler locks a controller briefly to press a button or read its state; a worker locks it
//! once per tick. What clients watch leaves through channels that never block a worker: the
//! latest position in a `watch` (a slow reader skips frames, the newest wins; a position is
//! published only when it changed, encoded once for every reader) and the events in a
//! `broadcast` (a reader that falls too far behind is told it lagged and resynchronises from a
//! fresh snapshot). What must outlive the process and comes from the workers (variables a program
//! wrote, alarms, finished runs) goes to the database writer as [`Record`]s.

pub mod estimate;
pub mod station;
pub mod stream;
mod worker;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, LazyLock, Mutex, MutexGuard, RwLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use fivex_engine::controller::Controller;
use fivex_engine::interp::Config;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use tokio::sync::{broadcast, mpsc, watch};

pub use crate::db::Record;
pub use station::Station;
pub use stream::{Message, PositionFrame, Published, Reading};

/// How often the workers tick every controller (and so the finest position a stream can show).
pub const TICK: Duration = Duration::from_millis(10);

/// Events a stream subscriber may fall behind by before it is told to resynchronise.
const EVENT_BUFFER: usize = 1024;

/// The fastest simulated time may run, as a multiple of real time.
pub const MAX_SPEED: f64 = 1000.0;

/// How far a controller's simulated time may trail the wall clock before it counts as behind
/// real time (`/metrics`): ten ticks. A healthy worker brings each of its controllers up to the
/// wall clock every [`TICK`] plus the time its round takes; the service's goal for the position
/// frames' lag is 100 ms (docs/performance.md, "The service under load").
pub const BEHIND: Duration = Duration::from_millis(100);

/// The instant the controllers' tick times count from (the process's first use of it).
static EPOCH: LazyLock<Instant> = LazyLock::new(Instant::now);

/// `at` as nanoseconds since [`EPOCH`] (0 for an instant before it).
fn since_epoch(at: Instant) -> u64 {
    u64::try_from(at.saturating_duration_since(*EPOCH).as_nanos()).unwrap_or(u64::MAX)
}

/// A cheap handle on the registry and its workers. The workers stop when the last handle is
/// dropped or [`Host::shutdown`] is called.
#[derive(Clone)]
pub struct Host {
    inner: Arc<Inner>,
}

struct Inner {
    /// In creation order.
    controllers: RwLock<Vec<Arc<Hosted>>>,
    /// Bumped on every change of `controllers`, so workers re-read their share only then.
    generation: AtomicU64,
    stop: AtomicBool,
    workers: Mutex<Vec<JoinHandle<()>>>,
    /// How many worker threads were started.
    worker_count: usize,
    /// Taken at shutdown, so the database writer sees the end of its channel.
    records: Mutex<Option<mpsc::UnboundedSender<Record>>>,
    /// Records handed to the writer so far (counted under the `records` lock, in the channel's
    /// order: the writer's count of those done reaching it means these are written).
    sent: AtomicU64,
}

impl Inner {
    /// The record's number in the channel's order (counting from 1), `None` once the writer is
    /// gone.
    fn record(&self, record: Record) -> Option<u64> {
        let records = lock(&self.records);
        records.as_ref()?.send(record).ok()?;
        Some(self.sent.fetch_add(1, Ordering::SeqCst) + 1)
    }
}

impl std::fmt::Debug for Host {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Host").field("controllers", &self.len()).finish()
    }
}

impl Host {
    /// An empty registry with `workers` worker threads (at least one); what they produce for
    /// the database goes to `records`.
    pub fn new(workers: usize, records: mpsc::UnboundedSender<Record>) -> Host {
        let inner = Arc::new(Inner {
            controllers: RwLock::new(Vec::new()),
            generation: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            workers: Mutex::new(Vec::new()),
            worker_count: workers.max(1),
            records: Mutex::new(Some(records)),
            sent: AtomicU64::new(0),
        });
        let count = inner.worker_count;
        let handles = (0..count)
            .map(|index| {
                let weak = Arc::downgrade(&inner);
                std::thread::Builder::new()
                    .name(format!("fivex-worker-{index}"))
                    .spawn(move || worker::run(weak, index, count))
                    .expect("spawn a worker thread")
            })
            .collect();
        *lock(&inner.workers) = handles;
        Host { inner }
    }

    /// The number of worker threads that suits this machine: one per core.
    pub fn default_workers() -> usize {
        std::thread::available_parallelism().map_or(2, |n| n.get())
    }

    /// How many worker threads were started.
    pub fn workers(&self) -> usize {
        self.inner.worker_count
    }

    /// How many worker threads are running now: all of them until [`Host::shutdown`] (a worker
    /// that ended otherwise, which only a panic could do, is not running: its controllers stand).
    pub fn workers_running(&self) -> usize {
        lock(&self.inner.workers).iter().filter(|w| !w.is_finished()).count()
    }

    /// Stop the workers and wait for them (the controllers stay registered, frozen); record
    /// every run under way as `interrupted` (it comes back in reset state: the run is over) and
    /// save what is not saved yet (`Station::final_records`); then close the channel to the database writer, which ends once it has written what it
    /// holds.
    pub fn shutdown(&self) {
        self.inner.stop.store(true, Ordering::SeqCst);
        // Taken before joining: the lock is not held while the workers finish their round.
        let handles = std::mem::take(&mut *lock(&self.inner.workers));
        for handle in handles {
            let _ = handle.join();
        }
        for hosted in self.list() {
            for record in hosted.station().final_records(&hosted.id) {
                self.inner.record(record);
            }
        }
        lock(&self.inner.records).take();
    }

    pub fn add(&self, hosted: Arc<Hosted>) {
        self.inner.controllers.write().unwrap_or_else(|e| e.into_inner()).push(hosted);
        self.inner.generation.fetch_add(1, Ordering::SeqCst);
    }

    /// Remove a controller; `None` if there is none with that id.
    pub fn remove(&self, id: &str) -> Option<Arc<Hosted>> {
        let mut list = self.inner.controllers.write().unwrap_or_else(|e| e.into_inner());
        let index = list.iter().position(|h| h.id == id)?;
        let removed = list.remove(index);
        self.inner.generation.fetch_add(1, Ordering::SeqCst);
        removed.removed.send_replace(true);
        Some(removed)
    }

    pub fn get(&self, id: &str) -> Option<Arc<Hosted>> {
        self.inner.controllers.read().unwrap_or_else(|e| e.into_inner()).iter().find(|h| h.id == id).cloned()
    }

    /// Every controller, in creation order.
    pub fn list(&self) -> Vec<Arc<Hosted>> {
        self.inner.controllers.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    pub fn len(&self) -> usize {
        self.inner.controllers.read().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Hand a record to the database writer: its number in the order the writer takes them
    /// (once `db::Db::records_done` reaches it, it is written), or `None` (the record dropped)
    /// once the writer is gone, at shutdown.
    pub fn record(&self, record: Record) -> Option<u64> {
        self.inner.record(record)
    }

    /// How many records were handed to the database writer so far: once the writer has done
    /// as many (`db::Db::records_done`), every one handed before this call is written.
    pub fn records_sent(&self) -> u64 {
        self.inner.sent.load(Ordering::SeqCst)
    }
}

/// One hosted controller: what never changes, and the [`Station`] behind its mutex.
pub struct Hosted {
    pub id: String,
    pub dialect: Dialect,
    pub created_at: String,
    name: RwLock<String>,
    /// Simulated seconds per real second, as f64 bits.
    speed: AtomicU64,
    station: Mutex<Station>,
    /// The latest position that differed from the one before (published only on a change).
    position: watch::Sender<Option<Arc<Published>>>,
    events: broadcast::Sender<Arc<Message>>,
    /// Set when the controller leaves the registry, so its streams close (a stream holds the
    /// controller alive, and would otherwise stay open on it forever).
    removed: watch::Sender<bool>,
    /// The wall-clock instant (ns since [`EPOCH`]) its simulated time has reached: the start of
    /// the worker round that ticked it last (a tick advances it by the real time up to there).
    ticked: AtomicU64,
    /// When (ns since [`EPOCH`]) a command or write last addressed it, or it was hosted here.
    used: AtomicU64,
    /// Held while a change of its settings is checked, stored and put into effect
    /// ([`Hosted::editing`]).
    editing: tokio::sync::Mutex<()>,
}

impl std::fmt::Debug for Hosted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hosted").field("id", &self.id).field("name", &self.name()).finish()
    }
}

/// Everything needed to host a controller.
pub struct Spec {
    pub id: String,
    pub name: String,
    pub dialect: Dialect,
    pub machine: MachineConfig,
    pub created_at: String,
    pub speed: f64,
}

impl Hosted {
    /// A controller in reset state (AUTO, idle) on `spec`'s machine.
    pub fn new(spec: Spec) -> Hosted {
        let mut controller = Controller::new(Config::new(spec.machine.clone(), spec.dialect));
        crate::tools::equip_defaults(&mut controller.interpreter_mut().state.offsets);
        let (position, _) = watch::channel(None);
        let (events, _) = broadcast::channel(EVENT_BUFFER);
        Hosted {
            id: spec.id,
            dialect: spec.dialect,
            created_at: spec.created_at,
            name: RwLock::new(spec.name),
            speed: AtomicU64::new(clamp_speed(spec.speed).to_bits()),
            station: Mutex::new(Station::new(controller, spec.machine)),
            position,
            events,
            removed: watch::channel(false).0,
            ticked: AtomicU64::new(since_epoch(Instant::now())),
            used: AtomicU64::new(since_epoch(Instant::now())),
            editing: tokio::sync::Mutex::new(()),
        }
    }

    /// One change of its settings at a time (held across the database write, which the
    /// station's lock cannot be).
    pub async fn editing(&self) -> tokio::sync::MutexGuard<'_, ()> {
        self.editing.lock().await
    }

    pub fn name(&self) -> String {
        self.name.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    pub fn rename(&self, name: String) {
        *self.name.write().unwrap_or_else(|e| e.into_inner()) = name;
    }

    pub fn speed(&self) -> f64 {
        f64::from_bits(self.speed.load(Ordering::Relaxed))
    }

    pub fn set_speed(&self, speed: f64) {
        self.speed.store(clamp_speed(speed).to_bits(), Ordering::Relaxed);
    }

    /// The controller and what the service keeps beside it, locked.
    pub fn station(&self) -> MutexGuard<'_, Station> {
        lock(&self.station)
    }

    /// Positions, latest first (`None` until a worker has produced one for a subscriber). A new
    /// one comes only when something in the frame changed, so an idle controller sends none.
    pub fn positions(&self) -> watch::Receiver<Option<Arc<Published>>> {
        self.position.subscribe()
    }

    pub fn events(&self) -> broadcast::Receiver<Arc<Message>> {
        self.events.subscribe()
    }

    /// A command or a write addressed it now.
    pub fn touch(&self) {
        self.used.store(since_epoch(Instant::now()), Ordering::Relaxed);
    }

    /// How long before `now` a command or write last addressed it (or it was hosted here).
    pub fn unused_for(&self, now: Instant) -> Duration {
        Duration::from_nanos(since_epoch(now).saturating_sub(self.used.load(Ordering::Relaxed)))
    }

    /// Whether the controller has left the registry (deleted, or hosted by another node now):
    /// a command that locked its station after that must not act on it.
    pub fn is_removed(&self) -> bool {
        *self.removed.borrow()
    }

    /// Resolves once the controller is removed from the registry (at once if it already is).
    pub fn removed(&self) -> impl std::future::Future<Output = ()> + Send + 'static {
        let mut removed = self.removed.subscribe();
        async move {
            // An error means the controller itself is gone: removed too.
            let _ = removed.wait_for(|gone| *gone).await;
        }
    }

    /// How far its simulated time trails the wall clock at `now`: the real time since the worker
    /// round that ticked it last began (a round advances every controller by the real time up to
    /// its start; a new controller counts from its creation).
    pub fn lag(&self, now: Instant) -> Duration {
        Duration::from_nanos(since_epoch(now).saturating_sub(self.ticked.load(Ordering::Relaxed)))
    }

    /// Its position stream's subscribers now (each open `…/stream` websocket holds one receiver;
    /// the workers read a position only for a controller that has any).
    pub fn subscribers(&self) -> usize {
        self.position.receiver_count()
    }

    /// Tell subscribers (events produced outside a worker tick: an operator action).
    pub fn publish(&self, messages: Vec<Message>) {
        for m in messages {
            let _ = self.events.send(Arc::new(m));
        }
    }
}

fn clamp_speed(speed: f64) -> f64 {
    if speed.is_finite() {
        speed.clamp(0.0, MAX_SPEED)
    } else {
        1.0
    }
}

/// Lock a mutex; a panic elsewhere (which the engine must never do) does not poison the service.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// The wall clock as RFC 3339 UTC with milliseconds.
pub fn now_rfc3339() -> String {
    let now = time::OffsetDateTime::now_utc();
    let now = now.replace_nanosecond(now.millisecond() as u32 * 1_000_000).unwrap_or(now);
    now.format(&time::format_description::well_known::Rfc3339).unwrap_or_default()
}

/// The host's local time as seconds since 1970-01-01 00:00 local (Unix time plus the zone's
/// offset now): the controllers' calendar clock, `#3011`/`#3012`.
pub fn local_now_s() -> f64 {
    let now = chrono::Local::now();
    (now.timestamp() + i64::from(now.offset().local_minus_utc())) as f64
        + f64::from(now.timestamp_subsec_millis()) / 1000.0
}

/// The wall clock in Unix milliseconds (stream frames carry it so a client can measure lag).
pub fn now_unix_ms() -> f64 {
    (time::OffsetDateTime::now_utc().unix_timestamp_nanos() / 1000) as f64 / 1000.0
}
