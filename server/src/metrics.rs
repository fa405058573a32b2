//! The service's metrics, `GET /metrics` (docs/api.md, "Metrics"): the Prometheus text exposition
//! format 0.0.4, written by the `prometheus` crate's `TextEncoder`.
//!
//! Two kinds. What happens (a position frame sent, a request answered, a fleet subscriber
//! coming or going) is counted where it happens, each an atomic add: [`Metrics`]. What *is*
//! (controllers by run state, how far their simulated time trails the wall clock, stream
//! subscribers, fleet runs and jobs, workers, failed records) is read from the state when a
//! scrape asks ([`Now`]), so it costs the workers and the streams nothing; reading it locks each
//! controller once, briefly, and never across an `.await`.
//!
//! *Decision*: the official `prometheus-client` crate writes only the OpenMetrics text format (a
//! counter's `# TYPE` names it without `_total`, its samples with; `# EOF`), which a parser of
//! the 0.0.4 format reads as untyped samples; the `prometheus` crate writes 0.0.4 exactly.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

use fivex_engine::controller::RunState;
use prometheus::core::Collector;
use prometheus::{Gauge, Histogram, HistogramOpts, IntCounter, IntCounterVec, IntGauge, IntGaugeVec, Opts, Registry};

use crate::host::{Host, BEHIND};
use crate::service::fleet_runs::{self, Runs};

/// The content type of `/metrics`: the text exposition format 0.0.4.
pub const CONTENT_TYPE: &str = "text/plain; version=0.0.4; charset=utf-8";

/// The position frame lag's buckets, seconds: a healthy service sends within a tick or two
/// (10 ms each); its goal is a p99 under 100 ms.
const LAG_BUCKETS: [f64; 11] = [0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5];

/// The websocket streams whose subscribers are counted as they come and go (a controller's
/// are read from the controller at scrape time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// `GET /api/v1/stream`.
    Fleet = 0,
    /// `GET /api/v1/fleet/runs/{id}/stream`.
    FleetRun = 1,
}

/// What the layers count as it happens. Cheap to clone (a handle on shared counters).
#[derive(Clone)]
pub struct Metrics {
    inner: Arc<Counters>,
}

struct Counters {
    frames_sent: IntCounter,
    frame_lag: Histogram,
    /// Requests answered, by status class 1xx…5xx (index 0…4).
    requests: IntCounterVec,
    requests_by_class: [IntCounter; 5],
    /// Requests answered 500 for a database error.
    database_errors: AtomicU64,
    /// Subscribers by [`Stream`].
    subscribers: [AtomicUsize; 2],
}

impl std::fmt::Debug for Metrics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Metrics").field("frames_sent", &self.inner.frames_sent.get()).finish()
    }
}

impl Default for Metrics {
    fn default() -> Self {
        Metrics::new()
    }
}

impl Metrics {
    pub fn new() -> Metrics {
        let requests = IntCounterVec::new(
            Opts::new("fivex_http_requests_total", "HTTP requests answered, by status class (1xx: websocket upgrades)"),
            &["class"],
        )
        .expect("a valid metric");
        let requests_by_class = ["1xx", "2xx", "3xx", "4xx", "5xx"].map(|class| requests.with_label_values(&[class]));
        let inner = Counters {
            frames_sent: IntCounter::new(
                "fivex_position_frames_sent_total",
                "Position frames sent to controller stream subscribers",
            )
            .expect("a valid metric"),
            frame_lag: Histogram::with_opts(
                HistogramOpts::new(
                    "fivex_position_frame_lag_seconds",
                    "Age of a position frame when it is sent: the send's wall clock minus the frame's \
                     wall_ms (when the worker read the position)",
                )
                .buckets(LAG_BUCKETS.to_vec()),
            )
            .expect("a valid metric"),
            requests,
            requests_by_class,
            database_errors: AtomicU64::new(0),
            subscribers: Default::default(),
        };
        Metrics { inner: Arc::new(inner) }
    }

    /// A position frame was sent, `lag_s` seconds after the worker read it.
    pub fn frame_sent(&self, lag_s: f64) {
        self.inner.frames_sent.inc();
        self.inner.frame_lag.observe(if lag_s.is_finite() { lag_s.max(0.0) } else { 0.0 });
    }

    /// A request was answered with `status`.
    pub fn answered(&self, status: u16) {
        if let Some(counter) = (status / 100).checked_sub(1).and_then(|i| self.inner.requests_by_class.get(i as usize))
        {
            counter.inc();
        }
    }

    /// A request was answered 500 for a database error.
    pub fn database_error(&self) {
        self.inner.database_errors.fetch_add(1, Ordering::Relaxed);
    }

    /// A subscriber of a fleet or fleet run stream, counted as long as the value lives.
    pub fn subscriber(&self, stream: Stream) -> Subscriber {
        self.inner.subscribers[stream as usize].fetch_add(1, Ordering::Relaxed);
        Subscriber { counters: self.inner.clone(), stream }
    }

    /// Position frames sent so far.
    pub fn frames_sent(&self) -> u64 {
        self.inner.frames_sent.get()
    }

    /// Everything, in the text format: what was counted, and `now` as read from the state.
    pub fn render(&self, now: &Now) -> Result<String, prometheus::Error> {
        let registry = Registry::new();
        let c = &self.inner;
        registry.register(Box::new(c.frames_sent.clone()))?;
        registry.register(Box::new(c.frame_lag.clone()))?;
        registry.register(Box::new(c.requests.clone()))?;
        for collector in now.collectors(self)? {
            registry.register(collector)?;
        }
        let mut text = String::new();
        prometheus::TextEncoder::new().encode_utf8(&registry.gather(), &mut text)?;
        Ok(text)
    }
}

/// Counts a fleet or fleet run subscriber while it lives.
pub struct Subscriber {
    counters: Arc<Counters>,
    stream: Stream,
}

impl Drop for Subscriber {
    fn drop(&mut self) {
        self.counters.subscribers[self.stream as usize].fetch_sub(1, Ordering::Relaxed);
    }
}

/// What the service is now, read at scrape time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Now {
    /// Controllers hosted by run state: idle, running, hold, alarm.
    pub controllers: [usize; 4],
    /// Controllers whose simulated time trails the wall clock by more than [`BEHIND`].
    pub behind: usize,
    /// The largest such lag, seconds (0 without controllers).
    pub max_lag_s: f64,
    /// Subscribers of the controllers' streams: their position channels' receivers (a
    /// websocket on this node, or a relay publisher).
    pub controller_subscribers: usize,
    /// In a cluster (`crate::relay`): controllers of other nodes relayed here (a NATS
    /// subscription each), their websocket clients here, and the controllers hosted here whose
    /// stream this node publishes for other nodes (each holds a position receiver).
    pub relay_subscriptions: usize,
    pub relay_clients: usize,
    pub relay_publishers: usize,
    pub workers: usize,
    pub workers_running: usize,
    pub fleet: fleet_runs::Census,
    /// The workers' records that could not be stored.
    pub failed_records: u64,
}

/// The run states in the order of [`Now::controllers`], as the `state` label names them.
const STATES: [&str; 4] = ["idle", "running", "hold", "alarm"];

impl Now {
    /// Reads the controllers (each locked once, briefly), the workers and the fleet runs.
    pub fn read(host: &Host, runs: &Runs, failed_records: u64) -> Now {
        let mut now = Now {
            workers: host.workers(),
            workers_running: host.workers_running(),
            fleet: runs.census(),
            failed_records,
            ..Now::default()
        };
        let at = Instant::now();
        for hosted in host.list() {
            let state = crate::host::station::run_state(&hosted.station().controller);
            now.controllers[match state {
                RunState::Idle => 0,
                RunState::Running => 1,
                RunState::Hold => 2,
                RunState::Alarm => 3,
            }] += 1;
            let lag = hosted.lag(at);
            if lag > BEHIND {
                now.behind += 1;
            }
            now.max_lag_s = now.max_lag_s.max(lag.as_secs_f64());
            now.controller_subscribers += hosted.subscribers();
        }
        now
    }

    /// The metrics read from the state, and the counters that are kept beside it.
    fn collectors(&self, metrics: &Metrics) -> Result<Vec<Box<dyn Collector>>, prometheus::Error> {
        let c = &metrics.inner;
        let int_gauge = |name: &str, help: &str, value: usize| -> Result<Box<dyn Collector>, prometheus::Error> {
            let gauge = IntGauge::new(name, help)?;
            gauge.set(i64::try_from(value).unwrap_or(i64::MAX));
            Ok(Box::new(gauge))
        };
        let by = |name: &str, help: &str, label: &str, values: &[(&str, i64)]| {
            let family = IntGaugeVec::new(Opts::new(name, help), &[label])?;
            for (value, n) in values {
                family.with_label_values(&[*value]).set(*n);
            }
            Ok::<Box<dyn Collector>, prometheus::Error>(Box::new(family))
        };
        let count = |n: usize| i64::try_from(n).unwrap_or(i64::MAX);

        let states: Vec<(&str, i64)> = STATES.iter().zip(self.controllers).map(|(s, n)| (*s, count(n))).collect();
        // Websockets open on this node: the local ones (the receivers but the publishers') and
        // the relayed ones.
        let websockets = self.controller_subscribers.saturating_sub(self.relay_publishers) + self.relay_clients;
        let subscribers = [
            ("controller", count(websockets)),
            ("fleet", count(c.subscribers[Stream::Fleet as usize].load(Ordering::Relaxed))),
            ("fleet_run", count(c.subscribers[Stream::FleetRun as usize].load(Ordering::Relaxed))),
        ];
        let max_lag = Gauge::new(
            "fivex_controllers_max_lag_seconds",
            "The largest lag of a controller's simulated time behind the wall clock: the real time since \
             the worker round that ticked it last began",
        )?;
        max_lag.set(self.max_lag_s);
        let fleet_finished = IntCounterVec::new(
            Opts::new("fivex_fleet_runs_finished_total", "Fleet runs over since the service started, by status"),
            &["status"],
        )?;
        for (status, n) in fleet_runs::FINISHED.iter().zip(self.fleet.finished) {
            fleet_finished.with_label_values(&[*status]).inc_by(n);
        }
        let database_errors = IntCounterVec::new(
            Opts::new(
                "fivex_database_errors_total",
                "Database errors: requests answered 500 for one (request), the workers' records not stored (records)",
            ),
            &["source"],
        )?;
        database_errors.with_label_values(&["request"]).inc_by(c.database_errors.load(Ordering::Relaxed));
        database_errors.with_label_values(&["records"]).inc_by(self.failed_records);

        Ok(vec![
            by("fivex_controllers", "Controllers hosted, by run state", "state", &states)?,
            int_gauge(
                "fivex_controllers_behind_real_time",
                "Controllers whose simulated time trails the wall clock by more than 0.1 s (ten ticks)",
                self.behind,
            )?,
            Box::new(max_lag),
            by("fivex_websocket_subscribers", "Open websocket streams, by stream", "stream", &subscribers)?,
            int_gauge(
                "fivex_relay_subscriptions",
                "Controllers of other nodes whose stream this node relays to its websockets: one NATS \
                 subscription each, shared by all of that controller's websockets here",
                self.relay_subscriptions,
            )?,
            int_gauge(
                "fivex_relay_publishers",
                "Controllers hosted here whose stream this node publishes on NATS for relaying nodes",
                self.relay_publishers,
            )?,
            int_gauge("fivex_workers", "Worker threads started (--workers)", self.workers)?,
            int_gauge("fivex_workers_running", "Worker threads running", self.workers_running)?,
            by(
                "fivex_fleet_runs",
                "Fleet runs not over, by status",
                "status",
                &[("queued", count(self.fleet.queued)), ("running", count(self.fleet.running))],
            )?,
            Box::new(fleet_finished),
            int_gauge("fivex_fleet_jobs", "Fleet runs that may run at once (--fleet-jobs)", self.fleet.jobs)?,
            int_gauge("fivex_fleet_jobs_running", "Fleet job places taken", self.fleet.jobs_running)?,
            Box::new(database_errors),
        ])
    }
}
