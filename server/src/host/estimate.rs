//! A program's simulated cycle time before it runs, and a run's progress against it.
//!
//! The estimate is the engine's [`run::run`] (what `fivex run` does) of the program on a copy of
//! the controller's interpreter: its machine, offsets, retained variables, modal state and the
//! point the machine stands on. It runs on a blocking thread and is kept per controller by a key
//! of exactly those inputs, so asking again costs nothing until one of them changes.
//!
//! The estimate is what the program takes at 100 % overrides without an operator: it cannot
//! know the overrides, the single-block and optional-stop switches, holds, or a program that
//! waits for handle pulses or reads input signals. [`progress`] says which of those it saw.

use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use fivex_engine::interp::Interpreter;
use fivex_engine::lang::Source;
use fivex_engine::run::{self, Observer, RunOptions};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::stream::AlarmInfo;

/// The wall-clock time an estimate may take before it gives up (`state: unknown`).
pub const WALL_BUDGET: Duration = Duration::from_secs(30);

/// The simulated time an estimated run may take (the budget of `fivex run`).
const SIMULATED_BUDGET_S: f64 = 1.0e6;

/// Estimates kept per controller; the oldest goes when there are more.
const KEPT: usize = 32;

/// The inputs of an estimate, hashed.
pub type Key = u64;

/// A program's estimated cycle time as the API shows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Estimate {
    /// `pending` (being computed), `ready` (the program ran to its end), `alarm` (it stopped at
    /// `alarm`: `cycle_time_s` is the time up to there) or `unknown` (no estimate: `reason`).
    #[schema(example = "ready")]
    pub state: String,
    /// Simulated seconds at 100 % overrides, without operator stops.
    pub cycle_time_s: Option<f64>,
    pub alarm: Option<AlarmInfo>,
    pub reason: Option<String>,
    /// What the program's time depends on that the estimate cannot know:
    /// `input_signals` (it reads #1000–#1035, which the host may change while it runs; the
    /// estimate reads them as they are now), `program_stop` (M00 waits for a cycle start: the
    /// wait is not in the estimate). Empty when there is none of them.
    #[serde(default)]
    pub depends_on: Vec<String>,
}

impl Estimate {
    fn pending() -> Estimate {
        Estimate { state: "pending".into(), cycle_time_s: None, alarm: None, reason: None, depends_on: Vec::new() }
    }
}

/// The estimates of one controller, by key.
#[derive(Debug, Default)]
pub struct Estimates {
    entries: HashMap<Key, (u64, Estimate)>,
    /// Insertion counter (the oldest entry is the one with the smallest number).
    count: u64,
}

impl Estimates {
    pub fn get(&self, key: Key) -> Option<&Estimate> {
        self.entries.get(&key).map(|(_, e)| e)
    }

    /// Mark `key` as being computed; false if it is known or under way already.
    pub fn begin(&mut self, key: Key) -> bool {
        if self.entries.contains_key(&key) {
            return false;
        }
        self.put(key, Estimate::pending());
        true
    }

    pub fn put(&mut self, key: Key, estimate: Estimate) {
        if self.entries.len() >= KEPT && !self.entries.contains_key(&key) {
            if let Some(oldest) = self.entries.iter().min_by_key(|(_, (n, _))| *n).map(|(k, _)| *k) {
                self.entries.remove(&oldest);
            }
        }
        self.count += 1;
        self.entries.insert(key, (self.count, estimate));
    }
}

/// The key of running `source` on `interp` now: its texts, the machine (by identity: a parameter
/// change makes a new one and clears the estimates), the dialect, the offsets, the common and
/// retained variables, the interface signals (#1000…: a program may branch on them), the
/// workpiece (what a G31 touches), the modal state and the machine position.
pub fn key(source: &Source, interp: &Interpreter) -> Key {
    let mut h = DefaultHasher::new();
    source.main.hash(&mut h);
    for stored in &source.library {
        (stored.number, &stored.text).hash(&mut h);
    }
    let state = &interp.state;
    (std::sync::Arc::as_ptr(&interp.config().machine) as usize).hash(&mut h);
    format!("{:?}", interp.config().dialect).hash(&mut h);
    format!("{:?}", state.offsets).hash(&mut h);
    (state.signals.inputs, state.signals.outputs).hash(&mut h);
    format!("{:?}", interp.config().workpiece).hash(&mut h);
    // Not the timers (#3001/#3002), which run on while it stands: a program that reads them
    // still takes the same time.
    let retained = state.retained_variables().into_iter().filter(|(n, _)| !(3001..=3002).contains(n));
    for (n, v) in state.common_variables().into_iter().chain(retained) {
        (n, v.to_bits()).hash(&mut h);
    }
    for v in state.machine_position() {
        v.to_bits().hash(&mut h);
    }
    format!("{:?}", state.modal_state()).hash(&mut h);
    h.finish()
}

/// Stops a run once the wall clock passes its deadline (the engine reads no clock itself).
struct Deadline {
    at: Instant,
    passed: bool,
}

impl Observer for Deadline {
    fn stop(&mut self) -> bool {
        self.passed = self.passed || Instant::now() >= self.at;
        self.passed
    }
}

/// Run `source` on `interp` (a copy of the controller's) to its end: blocking, up to `budget`
/// of wall-clock time.
pub fn compute(mut interp: Interpreter, source: &Source, budget: Duration) -> Estimate {
    interp.load_source(source);
    // No samples: only the cycle time is wanted.
    let opts = RunOptions { period_s: 0.0, max_time_s: SIMULATED_BUDGET_S, ..RunOptions::default() };
    let mut deadline = Deadline { at: Instant::now() + budget, passed: false };
    let result = run::run_observed(&mut interp, &opts, |_| {}, &mut deadline);
    // Any text may be called (which ones, only the run knows).
    let mut depends_on: Vec<String> = source.texts().flat_map(depends_on).collect();
    depends_on.sort();
    depends_on.dedup();
    if deadline.passed {
        return Estimate {
            state: "unknown".into(),
            cycle_time_s: None,
            alarm: None,
            reason: Some(format!("the simulation took longer than {} s", budget.as_secs())),
            depends_on,
        };
    }
    match result.alarms.first() {
        None => Estimate {
            state: "ready".into(),
            cycle_time_s: Some(result.cycle_time_s),
            alarm: None,
            reason: None,
            depends_on,
        },
        Some(alarm) => Estimate {
            state: "alarm".into(),
            cycle_time_s: Some(result.cycle_time_s),
            alarm: Some(AlarmInfo::from(alarm)),
            reason: Some("the program stops at an alarm: the time up to it".into()),
            depends_on,
        },
    }
}

/// What in `text` makes its time depend on the outside (see [`Estimate::depends_on`]), read
/// from the words outside comments: a variable number 1000–1035 after `#`, an M0 / M00. A
/// variable number computed at run time (`#[#1]`) cannot be read this way and is not counted.
pub fn depends_on(text: &str) -> Vec<String> {
    let (mut signals, mut stop) = (false, false);
    let mut comment = false;
    // Bytes, not chars: every character the scan looks at is ASCII, and a text may be megabytes.
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i].to_ascii_uppercase();
        i += 1;
        match c {
            b'(' => comment = true,
            b')' => comment = false,
            b'\n' => comment = false,
            b'#' | b'M' if !comment => {
                let start = i;
                while i < bytes.len() && bytes[i].is_ascii_digit() {
                    i += 1;
                }
                // A word's letter follows no other letter (`M` of `DPRNT`'s text does).
                let word = start < 2 || !bytes[start - 2].is_ascii_alphabetic();
                match (c, text[start..i].parse::<u32>()) {
                    (b'#', Ok(n)) => signals |= (1000..=1035).contains(&n),
                    (b'M', Ok(0)) => stop |= word,
                    _ => {}
                }
            }
            _ => {}
        }
    }
    [(signals, "input_signals"), (stop, "program_stop")]
        .into_iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| n.to_string())
        .collect()
}

/// A run under way against its estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct RunProgress {
    /// The stored program running.
    pub program: u32,
    /// Simulated seconds since its cycle start (holds and stops included).
    pub elapsed_s: f64,
    pub estimate: Estimate,
    /// `cycle_time_s − elapsed_s`, never below 0; absent without an estimate.
    pub remaining_s: Option<f64>,
    /// `elapsed_s / cycle_time_s` in percent, at most 100; absent without an estimate.
    pub percent: Option<f64>,
    /// What makes this run differ from the estimate: `feed_override`, `rapid_override`,
    /// `single_block`, `optional_stop` (the switch is on), `held` (it was held or stopped),
    /// `dry_run`, `aux_lock` (the switch is on); empty when it runs as estimated.
    pub caveats: Vec<String>,
}

/// What the run sees that the estimate assumed away.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Conditions {
    pub feed_override: f64,
    pub rapid_override: f64,
    pub single_block: bool,
    pub optional_stop: bool,
    pub held: bool,
    /// Dry run changes every cutting feed; the auxiliary function lock drops the tool changes'
    /// time (machine lock changes no time: the program's timing runs on).
    pub dry_run: bool,
    pub aux_lock: bool,
}

/// The progress of a run of `program` that has been under way `elapsed_s`.
pub fn progress(program: u32, elapsed_s: f64, estimate: Estimate, seen: Conditions) -> RunProgress {
    let mut caveats = Vec::new();
    for (differs, name) in [
        (seen.feed_override != 1.0, "feed_override"),
        (seen.rapid_override != 1.0, "rapid_override"),
        (seen.single_block, "single_block"),
        (seen.optional_stop, "optional_stop"),
        (seen.held, "held"),
        (seen.dry_run, "dry_run"),
        (seen.aux_lock, "aux_lock"),
    ] {
        if differs {
            caveats.push(name.to_string());
        }
    }
    let total = estimate.cycle_time_s.filter(|_| estimate.state == "ready");
    let remaining_s = total.map(|t| (t - elapsed_s).max(0.0));
    let percent = total.map(|t| if t > 0.0 { (elapsed_s / t * 100.0).min(100.0) } else { 100.0 });
    RunProgress { program, elapsed_s, estimate, remaining_s, percent, caveats }
}

/// Estimates computing at once, in the whole service: one per core, so that clients asking for
/// many cannot take the cores the controllers' workers tick on.
static RUNNING: Slots = Slots::new();

/// A count of things under way with a limit.
pub struct Slots(AtomicUsize);

/// A slot taken: given back when dropped (also when the estimate panicked).
pub struct Slot<'a>(&'a AtomicUsize);

impl Slots {
    pub const fn new() -> Slots {
        Slots(AtomicUsize::new(0))
    }

    /// A slot, if fewer than `limit` are taken.
    pub fn take(&self, limit: usize) -> Option<Slot<'_>> {
        self.0.fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| (n < limit).then_some(n + 1)).ok()?;
        Some(Slot(&self.0))
    }
}

impl Default for Slots {
    fn default() -> Self {
        Slots::new()
    }
}

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// The estimate of running `text` on `hosted` as it stands now: known, or begun on a blocking
/// thread (then `pending`; ask again). While every slot is taken nothing begins and the answer
/// is `pending` too. Needs a tokio runtime.
pub fn ensure(hosted: &std::sync::Arc<super::Hosted>, program: crate::service::programs::Composed) -> Estimate {
    let crate::service::programs::Composed { source, layout } = program;
    let Some(slot) = RUNNING.take(super::Host::default_workers()) else {
        let station = hosted.station();
        let key = key(&source, station.controller.interpreter());
        return station.estimates.get(key).cloned().unwrap_or_else(Estimate::pending);
    };
    let (key, interp) = {
        let mut station = hosted.station();
        let key = key(&source, station.controller.interpreter());
        if !station.estimates.begin(key) {
            return station.estimates.get(key).cloned().unwrap_or_else(Estimate::pending);
        }
        (key, station.controller.interpreter().clone())
    };
    let hosted = hosted.clone();
    tokio::task::spawn_blocking(move || {
        let _slot = slot;
        let mut estimate = compute(interp, &source, WALL_BUDGET);
        // Its alarm's line in the program it is in.
        estimate.alarm = estimate.alarm.map(|a| layout.relocate(a));
        hosted.station().estimates.put(key, estimate);
    });
    Estimate::pending()
}
