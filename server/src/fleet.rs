//! A fleet run: one NC program on many machines at once (`fivex fleet`, `POST /fleet/runs`,
//! `docs/fleet.md`). Each machine runs exactly as `fivex run` runs it alone — same interpreter
//! settings, same tool offsets, same run options — so its summary is the same bit for bit; the
//! machines are shared out over worker threads, each taking the next machine when it is done.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use fivex_engine::canon::{Motion, Pos};
use fivex_engine::interp::{Config, Interpreter, Offsets};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::motion::Segment;
use fivex_engine::run::{run_observed, NoObserver, Observer, RunOptions, Sample};
use fivex_engine::workpiece::Workpiece;
use fivex_engine::Dialect;

use crate::wire::{FleetResult, RunStatus, RunSummary};

/// The library of machine files shipped in the repository (`machines/`), embedded at build time
/// so that the service and the CLI have it wherever they run.
pub const LIBRARY: &[(&str, &str)] = &include!(concat!(env!("OUT_DIR"), "/library.rs"));

/// One machine of a fleet.
#[derive(Debug, Clone)]
pub struct Entry {
    /// The name in the results (`"machine"`).
    pub name: String,
    pub machine: MachineConfig,
    pub dialect: Dialect,
    /// The tool and work offsets to start with (an existing controller's); `None`: the run's
    /// tool table.
    pub offsets: Option<Box<Offsets>>,
    /// What is on its table to start with (an existing controller's); `None`: the run's
    /// workpiece, or nothing.
    pub workpiece: Option<Arc<Workpiece>>,
    /// Where its axes stand to start with, machine coordinates (an existing controller's);
    /// `None`: where `fivex run` starts.
    pub start: Option<Pos>,
}

/// One tool offset of a tool table (`--tools`, a fleet run's `tools`): the values
/// `PUT /controllers/{id}/tool-offsets/{n}` takes (`api::offsets::SetToolOffset`), with the same
/// ranges (`tools::ToolValues`), length and radius required. Any other field is refused, not
/// dropped: a wear left out of the run by a misspelled name moved the tool by it without a word.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Tool {
    /// H geometry, mm, within ±999.999 (the range G10 takes, `tools::check_value`).
    #[schema(minimum = -999.999, maximum = 999.999)]
    pub length: f64,
    /// H wear, mm, within ±99.999. Absent: 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(minimum = -99.999, maximum = 99.999)]
    pub length_wear: Option<f64>,
    /// D geometry, mm, within ±999.999.
    #[schema(minimum = -999.999, maximum = 999.999)]
    pub radius: f64,
    /// D wear, mm, within ±99.999. Absent: 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(minimum = -99.999, maximum = 99.999)]
    pub radius_wear: Option<f64>,
    /// The tool's corner radius, read by cutting point control (G43.8/G43.9); not negative, at
    /// most 999.999 mm. Absent: 0 (a square end mill, or a ball end mill read from the radius).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(minimum = 0.0, maximum = 999.999)]
    pub corner_radius: Option<f64>,
}

impl Tool {
    /// Every value of the offset (what is absent: 0).
    pub fn values(&self) -> crate::tools::ToolValues {
        crate::tools::ToolValues {
            length: Some(self.length),
            length_wear: Some(self.length_wear.unwrap_or(0.0)),
            radius: Some(self.radius),
            radius_wear: Some(self.radius_wear.unwrap_or(0.0)),
            corner_radius: Some(self.corner_radius.unwrap_or(0.0)),
        }
    }
}

/// How the fleet runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Tool offsets by number; `None`: every number 1–99 at 100 mm length and 5 mm radius.
    pub tools: Option<BTreeMap<u32, Tool>>,
    /// Add each machine's run report (`"report"`), sampled every `report_period_s`.
    pub report: bool,
    pub report_period_s: f64,
    /// Worker threads (at least 1).
    pub jobs: usize,
    pub max_blocks: u64,
    pub max_time_s: f64,
    /// What is clamped on every machine's table, the boxes a G31 probe touches (checked with
    /// `Workpiece::check` before the run); `None`: nothing, or an existing controller's own.
    pub workpiece: Option<Arc<Workpiece>>,
    /// Set by someone else to cancel the run: no machine starts after it, and the machines
    /// running stop before their next block (or sample). `None`: the run cannot be cancelled.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Options {
    /// Whether the run was cancelled.
    pub fn cancelled(&self) -> bool {
        self.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// An observer that also stops the engine's run when the fleet run is cancelled.
struct Cancellable<'a, O> {
    inner: O,
    cancel: Option<&'a AtomicBool>,
}

impl<O: Observer> Observer for Cancellable<'_, O> {
    fn queued(&mut self, motion: &Motion, segment: &Segment) {
        self.inner.queued(motion, segment)
    }
    fn sample(&mut self, sample: &Sample, machine: &Pos, on: Option<(&Segment, f64, u64)>) {
        self.inner.sample(sample, machine, on)
    }
    fn executed(&mut self, segment: &Segment) {
        self.inner.executed(segment)
    }
    fn stop(&mut self) -> bool {
        // Relaxed: the flag carries no other data, and a block later is soon enough.
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tools: None,
            report: false,
            report_period_s: 0.001,
            jobs: default_jobs(),
            max_blocks: 50_000_000,
            max_time_s: 1.0e6,
            workpiece: None,
            cancel: None,
        }
    }
}

/// One worker per core.
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// What happens while a fleet runs, in the order it happens on each worker.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    Started {
        index: usize,
        machine: String,
    },
    Finished {
        index: usize,
        machine: String,
        status: &'static str,
        cycle_time_s: f64,
    },
    /// The run was cancelled while this machine ran; it has no result.
    Cancelled {
        index: usize,
        machine: String,
    },
}

/// A machine by preset name, library name, or machine file text.
pub fn preset(name: &str, dialect: Dialect) -> Result<Entry, String> {
    let machine = MachineConfig::preset(name)
        .ok_or_else(|| format!("unknown preset '{name}' (presets: {})", MachineConfig::PRESETS.join(", ")))?;
    Ok(Entry { name: name.to_string(), machine, dialect, offsets: None, workpiece: None, start: None })
}

/// A machine file (model or parameter list; a parameter list runs in its own dialect, a model
/// in `dialect`).
pub fn machine_file(text: &str, dialect: Dialect) -> Result<Entry, String> {
    let machine = fivex_engine::machine_file::parse(text)?;
    let dialect = fivex_engine::machine_file::dialect_of(text).unwrap_or(dialect);
    Ok(Entry { name: machine.name.clone(), machine, dialect, offsets: None, workpiece: None, start: None })
}

/// A machine of the library (`machines/NAME.json`).
pub fn library(name: &str, dialect: Dialect) -> Result<Entry, String> {
    let text = LIBRARY
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| format!("no library machine '{name}' (see docs/fleet.md)"))?;
    machine_file(text, dialect).map_err(|e| format!("library machine {name}: {e}"))
}

/// Every machine of the library, in name order.
pub fn whole_library(dialect: Dialect) -> Result<Vec<Entry>, String> {
    LIBRARY.iter().map(|(name, _)| library(name, dialect)).collect()
}

/// Set the tool offsets as `fivex run --tools` does (without a table: the defaults).
pub fn equip(interp: &mut Interpreter, tools: Option<&BTreeMap<u32, Tool>>) -> Result<(), String> {
    match tools {
        None => crate::tools::equip_defaults(&mut interp.state.offsets),
        Some(tools) => {
            for (n, t) in tools {
                let slot = interp
                    .state
                    .offsets
                    .tool_mut(*n)
                    .ok_or_else(|| format!("tool offset number {n} is out of range 1–999"))?;
                t.values().apply(slot);
            }
        }
    }
    Ok(())
}

/// The work offsets of `offsets`, with every tool offset zero (as a run's own tool table
/// starts).
fn work_offsets_of(offsets: &Offsets) -> Offsets {
    let mut fresh = Offsets::default();
    for (slot, axes) in offsets.work_copy().into_iter().enumerate() {
        *fresh.work_mut(slot) = axes;
    }
    fresh
}

/// Check a tool table before a run (so a bad number, a value out of range or a negative corner
/// radius is a usage error, not a failed machine).
pub fn check_tools(tools: &BTreeMap<u32, Tool>) -> Result<(), String> {
    let mut probe = Offsets::default();
    for (n, t) in tools {
        probe.tool_mut(*n).ok_or_else(|| format!("tool offset number {n} is out of range 1–999"))?;
        // The range G10 takes (`tools::check_value`): a run never starts with an offset no
        // program could set.
        t.values().checked().map_err(|e| format!("tool offset {n}: {e}"))?;
    }
    Ok(())
}

/// One machine's result: `{"machine": NAME, "dialect": …, <the fivex run summary>, "report"}`.
pub fn run_one(text: &str, entry: &Entry, opts: &Options) -> FleetResult {
    let mut cfg = Config::new(entry.machine.clone(), entry.dialect);
    cfg.max_blocks = opts.max_blocks;
    // The run's workpiece wins over a controller's own, as its tool table does.
    if let Some(w) = opts.workpiece.as_ref().or(entry.workpiece.as_ref()) {
        cfg.workpiece = w.clone();
    }
    let mut interp = Interpreter::new(parse_file(text), cfg);
    match (&entry.offsets, &opts.tools) {
        (Some(offsets), None) => interp.state.offsets = (**offsets).clone(),
        (Some(offsets), Some(_)) => {
            // The run's tool table replaces the controller's tool offsets only: its work
            // offsets stay (without them the part is cut where G54 is not).
            interp.state.offsets = work_offsets_of(offsets);
            let _ = equip(&mut interp, opts.tools.as_ref());
        }
        (None, _) => {
            // Checked before the fleet starts (`check_tools`).
            let _ = equip(&mut interp, opts.tools.as_ref());
        }
    }
    if let Some(at) = &entry.start {
        // An existing controller's machine starts where its axes stand, as a program started
        // there would; its modal state and variables are not taken over: a fresh run's
        // (`docs/api.md`, "Fleet runs").
        interp.moved_to(at);
    }
    let axes: Vec<char> = entry.machine.axes.iter().map(|a| a.name).collect();
    let mut run_opts = RunOptions { period_s: 0.0, max_time_s: opts.max_time_s, ..RunOptions::default() };
    let cancel = opts.cancel.as_deref();
    // As `report::run_with_report` and `run::run` do, with the cancel flag looked at.
    let (result, report) = if opts.report {
        run_opts.period_s = opts.report_period_s;
        let recorder = fivex_engine::report::Recorder::new(&interp, run_opts.period_s);
        let mut observer = Cancellable { inner: recorder, cancel };
        let r = run_observed(&mut interp, &run_opts, |_| {}, &mut observer);
        let report = observer.inner.finish(&r);
        (r, Some(report))
    } else {
        (run_observed(&mut interp, &run_opts, |_| {}, &mut Cancellable { inner: NoObserver, cancel }), None)
    };
    FleetResult { machine: entry.name.clone(), dialect: entry.dialect, summary: RunSummary::of(&result, &axes), report }
}

/// Run the program on every machine, `opts.jobs` at a time; the results in `entries` order. A
/// cancelled run leaves `None` (`null`) for every machine that had not finished when it was
/// cancelled.
pub fn run_fleet(
    text: &str,
    entries: &[Entry],
    opts: &Options,
    progress: &(dyn Fn(Event) + Sync),
) -> Vec<Option<FleetResult>> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<FleetResult>>> = Mutex::new(vec![None; entries.len()]);
    let jobs = opts.jobs.clamp(1, entries.len().max(1));
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                let Some(entry) = entries.get(index) else { return };
                if opts.cancelled() {
                    return;
                }
                progress(Event::Started { index, machine: entry.name.clone() });
                let value = run_one(text, entry, opts);
                if opts.cancelled() {
                    // Stopped in the middle (or so near the end that it makes no difference):
                    // its summary is not the program's.
                    progress(Event::Cancelled { index, machine: entry.name.clone() });
                    return;
                }
                progress(Event::Finished {
                    index,
                    machine: entry.name.clone(),
                    status: match value.summary.status {
                        RunStatus::Completed => "completed",
                        RunStatus::Alarm => "alarm",
                    },
                    cycle_time_s: value.summary.cycle_time_s,
                });
                results.lock().unwrap_or_else(|e| e.into_inner())[index] = Some(value);
            });
        }
    });
    results.into_inner().unwrap_or_else(|e| e.into_inner())
}
