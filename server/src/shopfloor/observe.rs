//! What the shop-floor interfaces show of every hosted controller, read on one clock: an
//! [`Observer`] thread reads each controller every period into an [`Observed`] and publishes the
//! whole set as a [`Round`]; the MTConnect agent and the OPC UA server each keep the last round
//! they handled and act on what changed.
//!
//! Why a sampler and not the stream: the stream publishes positions only for a watched
//! controller and every tick; an integrator's client wants every controller at a steady, lower
//! rate (an MTConnect agent's sample period), and both protocols then show the same instant.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use fivex_engine::controller::{Mode, ProgramStop, RunState};
use fivex_engine::machine::Machine;
use fivex_engine::Dialect;
use tokio::sync::watch;

use crate::host::station::AlarmLog;
use crate::host::stream::AlarmInfo;
use crate::host::{Host, Hosted};

/// The default period: ten readings a second (a real MTConnect adapter samples a control at
/// 10–100 Hz; this keeps 1,000 controllers cheap).
pub const DEFAULT_PERIOD: Duration = Duration::from_millis(100);

/// One controller as the shop-floor interfaces show it at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct Observed {
    pub emergency_stop: bool,
    pub mode: Mode,
    pub run_state: RunState,
    /// Why a held program waits (`hold` at M00/M01/`#3006`/a single-block stop); `None`
    /// otherwise.
    pub program_stop: Option<ProgramStop>,
    /// The stored program (O number) AUTO runs, once one was started.
    pub program: Option<u32>,
    /// 1-based line of the executing block (0 before any) in the program `line_program` (the
    /// selected one or one it called; `None`: MDI's text), its sequence number and its text.
    pub line: u32,
    pub line_program: Option<u32>,
    pub n: Option<u32>,
    pub block: Option<String>,
    /// Machine coordinates per axis, in the machine's axis order (mm or degrees), sampled.
    pub machine: Vec<f64>,
    /// Tool tip in the active workpiece system (the stream's `tip`), mm.
    pub tip: [f64; 3],
    /// Tool tip speed relative to the workpiece, mm/min.
    pub feed: f64,
    /// Percent.
    pub feed_override: f64,
    pub rapid_override: f64,
    /// 1/min: positive M03, negative M04, 0 stopped (the commanded speed times the override).
    pub spindle: f64,
    /// Spindle speed override, percent.
    pub spindle_override: f64,
    /// The tool in the spindle (0: none).
    pub tool: u32,
    /// #3901 and #3902.
    pub parts: f64,
    pub parts_required: f64,
    pub alarms: Vec<AlarmInfo>,
    /// Every alarm raised and every reset, in order (the last ones): an alarm raised and reset
    /// between two readings is in it, not in `alarms`.
    pub alarm_log: AlarmLog,
    /// Simulated seconds since the controller was created (or the service started).
    pub time_s: f64,
}

impl Observed {
    pub fn of(station: &crate::host::Station) -> Observed {
        let c = &station.controller;
        let sample = c.sample();
        let axes = station.machine.axes.len();
        let line = sample.line;
        let (line_program, own_line) = station.layouts.locate(line);
        let (parts, parts_required) = c.interpreter().state.part_count();
        Observed {
            emergency_stop: c.emergency_stopped(),
            mode: c.mode(),
            run_state: crate::host::station::run_state(c),
            program_stop: c.program_stop(),
            program: station.program,
            line: own_line,
            line_program,
            n: sample.n,
            block: c.source_line(line).map(|text| text.trim().to_string()),
            machine: station.machine.shown(&sample.machine)[..axes].to_vec(),
            tip: sample.tip,
            feed: sample.feed,
            feed_override: (c.panel.feed_override * 100.0).round(),
            rapid_override: (c.panel.rapid_override * 100.0).round(),
            spindle: c.spindle(),
            spindle_override: (c.panel.spindle_override * 100.0).round(),
            tool: c.modal().words.spindle_tool,
            parts,
            parts_required,
            alarms: station.layouts.alarms(c.alarms()),
            alarm_log: station.alarm_log.clone(),
            time_s: c.time(),
        }
    }
}

/// A hosted controller in a round: what never changes, its machine and what was observed.
#[derive(Debug, Clone)]
pub struct Entry {
    pub id: String,
    pub name: String,
    pub dialect: Dialect,
    pub created_at: String,
    /// The machine the controller runs now (a parameter change replaces it: a new pointer).
    pub machine: Arc<Machine>,
    pub observed: Observed,
    /// How far its simulated time trailed the wall clock when read (`Hosted::lag`).
    pub lag: Duration,
}

/// Every hosted controller at one instant, in creation order.
#[derive(Debug, Clone, Default)]
pub struct Round {
    /// Counts the rounds from 1 (0: none yet).
    pub number: u64,
    /// The wall clock when the round began, RFC 3339 UTC with milliseconds.
    pub at: String,
    pub controllers: Vec<Arc<Entry>>,
}

impl Round {
    pub fn get(&self, id: &str) -> Option<&Arc<Entry>> {
        self.controllers.iter().find(|e| e.id == id)
    }
}

/// The sampler thread; stops when dropped.
pub struct Observer {
    rounds: watch::Receiver<Arc<Round>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Observer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Observer").field("round", &self.rounds.borrow().number).finish()
    }
}

impl Observer {
    /// Reads every controller of `host` every `period` from now on.
    pub fn start(host: Host, period: Duration) -> Observer {
        let (send, rounds) = watch::channel(Arc::new(Round::default()));
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let thread = std::thread::Builder::new()
            .name("fivex-observer".into())
            .spawn(move || {
                let mut next = Instant::now();
                let mut number = 0;
                while !stopped.load(Ordering::Relaxed) {
                    number += 1;
                    send.send_replace(Arc::new(read(&host, number)));
                    next += period;
                    let now = Instant::now();
                    // Behind (a stalled machine): the next round starts now, not in a burst.
                    next = next.max(now);
                    std::thread::sleep(next - now);
                }
            })
            .expect("spawn the observer thread");
        Observer { rounds, stop, thread: Some(thread) }
    }

    /// The rounds: the latest one, and a change whenever a new one is published.
    pub fn rounds(&self) -> watch::Receiver<Arc<Round>> {
        self.rounds.clone()
    }
}

impl Drop for Observer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// One round: every controller locked briefly, one after the other.
fn read(host: &Host, number: u64) -> Round {
    let at = crate::host::now_rfc3339();
    let controllers = host.list().iter().map(|hosted| Arc::new(entry(hosted))).collect();
    Round { number, at, controllers }
}

fn entry(hosted: &Hosted) -> Entry {
    let (machine, observed) = {
        let station = hosted.station();
        (station.machine.clone(), Observed::of(&station))
    };
    Entry {
        id: hosted.id.clone(),
        name: hosted.name(),
        dialect: hosted.dialect,
        created_at: hosted.created_at.clone(),
        machine,
        observed,
        lag: hosted.lag(Instant::now()),
    }
}
