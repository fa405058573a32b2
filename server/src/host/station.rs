//! A hosted controller's mutable side: the engine [`Controller`] and what the service keeps
//! beside it (the stored program it runs, the run under way, what was last saved and streamed),
//! and the translation of the controller's events into stream messages and database records.

use std::collections::BTreeMap;
use std::sync::Arc;

use fivex_engine::controller::{Controller, Event, Mode, RestartPhase, RunState};
use fivex_engine::interp::State;
use fivex_engine::interp::MAX_G54_1;
use fivex_engine::machine::{Machine, MachineConfig};
use fivex_engine::notice::Notice;

use crate::db::ToolRow;

use super::estimate::{progress, Conditions, Estimate, Estimates, Key, RunProgress};
use super::stream::{AlarmInfo, Message};
use super::{now_rfc3339, Record};
use crate::service::programs::Layout;

/// How often, in real seconds, a running controller's variables are compared with what was
/// streamed, and its retained variables and offsets with what was saved.
const STREAM_VARIABLES_EVERY: f64 = 0.1;
const SAVE_VARIABLES_EVERY: f64 = 1.0;

/// The run state the service shows (status, stream, MTConnect, OPC UA, metrics, the panel's
/// checks): a program waiting for cycle start at M00, M01, `#3006` or a single-block stop is
/// `hold`, as after a feed hold — the run goes on at the next cycle start, so it is neither over
/// (`idle`) nor running — although the engine's controller is idle there.
pub fn run_state(c: &Controller) -> RunState {
    match c.run_state() {
        RunState::Idle if program_waits(c) => RunState::Hold,
        state => state,
    }
}

/// The engine is idle but its program is not over: stopped at M00/M01/`#3006`/single block, or
/// held for a manual intervention between the hand moves. The run goes on from there.
fn program_waits(c: &Controller) -> bool {
    c.program_stop().is_some() || c.intervening()
}

pub struct Station {
    pub controller: Controller,
    /// The machine the controller runs (replaced, with the controller, by a parameter change).
    pub machine: Arc<Machine>,
    /// Vendor parameters the machine model does not read, kept as given.
    pub extra_parameters: fivex_engine::vendor::Params,
    /// What the machine description sets that fivex does not carry out (shown with the status
    /// and the parameters; `service::parameters::unmodelled`).
    pub unmodelled: Vec<fivex_engine::vendor::unmodelled::Unmodelled>,
    /// The stored program (O number) AUTO runs, once one was started.
    pub program: Option<u32>,
    /// Where the stored programs lie in the texts the controller runs, so that lines are given
    /// in the program they are in.
    pub layouts: Layouts,
    /// Syntec's teach screen: the boxes F1 latched (`api::teach`; not saved).
    pub teach: fivex_engine::teach::Points,
    run: Option<RunStart>,
    /// The programs' estimated cycle times (`estimate.rs`), by their inputs.
    pub estimates: Estimates,
    /// The retained variables (#500–#999, #500000–#999999, #3002, #3901/#3902) as last saved,
    /// non-vacant ones only.
    saved: BTreeMap<u32, f64>,
    /// The counters of automatic operation as last saved.
    saved_times: fivex_engine::controller::Times,
    /// The tilted working plane kept over a restart, as last saved.
    saved_plane: Option<fivex_engine::interp::TiltedPlane>,
    /// Common variables as last streamed.
    streamed: BTreeMap<u32, f64>,
    since_streamed: f64,
    since_saved: f64,
    /// The run state last streamed ([`run_state`]).
    shown_state: RunState,
    /// Every alarm raised and every clearing, in order: what the shop-floor interfaces read, so
    /// that an alarm raised and reset between two of their readings is seen too.
    pub alarm_log: AlarmLog,
}

/// What happened to a controller's alarms: one was raised, or all were cleared (a reset).
#[derive(Debug, Clone, PartialEq)]
pub enum AlarmChange {
    Raised(AlarmInfo),
    Cleared,
}

/// A controller's last [`AlarmLog::KEPT`] alarm changes, numbered from 0 on. A reader keeps
/// the number it read up to ([`AlarmLog::next`]) and asks for what came after
/// ([`AlarmLog::since`]). Cloning it is cheap (the changes are shared until the next one).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AlarmLog {
    next: u64,
    kept: Arc<std::collections::VecDeque<AlarmChange>>,
}

impl AlarmLog {
    /// Changes kept: an alarm stops the program until a reset, so a reader loses one only after
    /// dozens of alarms and resets between two of its readings (at most 10 s apart).
    pub const KEPT: usize = 64;

    pub fn push(&mut self, change: AlarmChange) {
        let kept = Arc::make_mut(&mut self.kept);
        if kept.len() == Self::KEPT {
            kept.pop_front();
        }
        kept.push_back(change);
        self.next += 1;
    }

    /// The number the next change gets.
    pub fn next(&self) -> u64 {
        self.next
    }

    /// The changes numbered `from` on (those still kept), in order.
    pub fn since(&self, from: u64) -> impl Iterator<Item = &AlarmChange> {
        let first = self.next - self.kept.len() as u64;
        let skip = usize::try_from(from.saturating_sub(first)).unwrap_or(usize::MAX);
        self.kept.iter().skip(skip)
    }
}

/// Where the stored programs lie in the texts AUTO and MDI run (`programs::Layout`), and which
/// of the two the last start ran: the line the controller reports is a line of that text.
#[derive(Debug, Clone, Default)]
pub struct Layouts {
    /// The selected program's (AUTO).
    pub auto: Layout,
    pub mdi: Layout,
    mdi_ran: bool,
}

impl Layouts {
    /// A run of what `mode` runs began.
    pub fn started(&mut self, mode: Mode) {
        self.mdi_ran = mode == Mode::Mdi;
    }

    /// The layout of the text the last start ran.
    pub fn running(&self) -> &Layout {
        if self.mdi_ran {
            &self.mdi
        } else {
            &self.auto
        }
    }

    /// The program and its own line for a line the controller reports.
    pub fn locate(&self, line: u32) -> (Option<u32>, u32) {
        self.running().locate(line)
    }

    /// An alarm as clients see it, its line in the program it is in.
    pub fn alarm(&self, alarm: &fivex_engine::Alarm) -> AlarmInfo {
        AlarmInfo::located(alarm, self.running())
    }

    pub fn alarms(&self, alarms: &[fivex_engine::Alarm]) -> Vec<AlarmInfo> {
        alarms.iter().map(|a| self.alarm(a)).collect()
    }
}

/// A program run under way.
struct RunStart {
    program: Option<u32>,
    started_at: String,
    sim_start: f64,
    /// The estimate of a stored program's run, by its key (taken before its cycle start).
    estimate: Option<Key>,
    /// It was held or stopped (feed hold, single block, M00/M01, `#3006`) on its way.
    held: bool,
}

impl Station {
    pub fn new(controller: Controller, machine: MachineConfig) -> Station {
        let saved = controller.interpreter().state.retained_variables().into_iter().collect();
        let streamed = controller.interpreter().state.common_variables().into_iter().collect();
        let controller_times = controller.times();
        let mut controller = controller;
        // What the controller starts with counts as saved (the defaults, or rows just read).
        controller.interpreter_mut().state.offsets.take_touched();
        Station {
            extra_parameters: Default::default(),
            unmodelled: fivex_engine::vendor::unmodelled::of_model(&machine),
            // The interpreter's, shared (the same model as `machine`).
            machine: controller.interpreter().config().machine.clone(),
            controller,
            program: None,
            layouts: Layouts::default(),
            teach: Default::default(),
            run: None,
            estimates: Estimates::default(),
            saved,
            saved_plane: None,
            saved_times: controller_times,
            streamed,
            since_streamed: 0.0,
            since_saved: 0.0,
            shown_state: RunState::Idle,
            alarm_log: AlarmLog::default(),
        }
    }

    /// Put a new machine under the controller (a parameter change): a fresh controller in reset
    /// state that keeps the offsets, the retained variables, the panel settings and the
    /// workpiece.
    pub fn replace_machine(&mut self, machine: MachineConfig, dialect: fivex_engine::Dialect) {
        let old = &self.controller;
        let (offsets, retained, panel, plane, times) = (
            old.interpreter().state.offsets.clone(),
            old.interpreter().state.retained_variables(),
            old.panel,
            old.interpreter().state.kept_plane(),
            old.times(),
        );
        let workpiece = old.workpiece().clone();
        if !old.alarms().is_empty() {
            // The fresh controller has none: they are gone as at a reset.
            self.alarm_log.push(AlarmChange::Cleared);
        }
        let mut controller = Controller::new(fivex_engine::interp::Config::new(machine, dialect));
        // What is clamped on the table stays there when the machine's parameters change. (A
        // fresh controller is at rest and the boxes were checked once: it takes them.)
        let _ = controller.set_workpiece(workpiece);
        controller.interpreter_mut().state.offsets = offsets;
        let retained: Vec<(u32, Option<f64>)> = retained.into_iter().map(|(n, v)| (n, Some(v))).collect();
        // (The numbers come from the same engine's retained list: none is refused.)
        let _ = controller.interpreter_mut().state.load_retained(&retained);
        controller.panel = panel;
        controller.load_times(times);
        // A restart on the new machine keeps the plane as a power cycle would (Pr3014 = 2).
        if let Some(plane) = &plane {
            controller.interpreter_mut().state.restore_plane(plane);
        }
        // The program's current point from the offsets kept (it was the machine position).
        controller.offsets_changed();
        self.machine = controller.interpreter().config().machine.clone();
        self.controller = controller;
        self.program = None;
        self.layouts = Layouts::default();
        self.run = None;
        // The key names the machine by its address, which a later model may reuse.
        self.estimates = Estimates::default();
    }

    /// Retained values read from the database: they count as saved. A value the engine does
    /// not retain in this dialect (a row of an older version) is left out, one by one: the
    /// dialect's own (Haas #100–#199) are kept.
    pub fn load_retained(&mut self, values: &[(u32, f64)]) {
        let state = &mut self.controller.interpreter_mut().state;
        for &(n, v) in values {
            let _ = state.load_retained(&[(n, Some(v))]);
        }
        self.saved = state.retained_variables().into_iter().collect();
        self.streamed = self.controller.interpreter().state.common_variables().into_iter().collect();
    }

    /// Offsets read from the database (over the defaults): they count as saved.
    pub fn load_offsets(&mut self, tools: &[ToolRow], work: &[(usize, Vec<f64>)]) {
        let offsets = &mut self.controller.interpreter_mut().state.offsets;
        for t in tools {
            if let Some(slot) = offsets.tool_mut(t.number) {
                (slot.h_geometry, slot.h_wear, slot.d_geometry, slot.d_wear, slot.corner_radius) =
                    (t.length, t.length_wear, t.radius, t.radius_wear, t.corner_radius);
            }
        }
        for (index, axes) in work {
            if *index < WORK_SLOTS {
                for (k, v) in axes.iter().enumerate().take(fivex_engine::machine::MAX_AXES) {
                    offsets.work_mut(*index)[k] = *v;
                }
            }
        }
        self.offsets_saved();
        self.controller.offsets_changed();
    }

    /// The counters of automatic operation, read from the database: counting goes on from
    /// them, and they count as saved.
    pub fn load_times(&mut self, times: fivex_engine::controller::Times) {
        self.controller.load_times(times);
        self.saved_times = self.controller.times();
    }

    /// The plane kept over a restart, read from the database: active again, and saved.
    pub fn load_kept_plane(&mut self, plane: &fivex_engine::interp::TiltedPlane) {
        self.controller.interpreter_mut().state.restore_plane(plane);
        self.controller.offsets_changed();
        self.saved_plane = self.controller.interpreter().state.kept_plane();
    }

    /// The offsets as they are now are in the database (read from it).
    fn offsets_saved(&mut self) {
        self.controller.interpreter_mut().state.offsets.take_touched();
    }

    /// A variable was set from outside: the caller saves it (`service::settings`), so a tick
    /// does not.
    pub fn variable_saved(&mut self, number: u32, value: Option<f64>) {
        if State::is_retained(number) {
            match value {
                Some(v) => self.saved.insert(number, v),
                None => self.saved.remove(&number),
            };
        }
    }

    /// A program run begins (cycle start from idle): remembered for the run history.
    pub fn begin_run(&mut self, program: Option<u32>) {
        // An MDI run (no program) leaves the program AUTO runs: a restart's search held over
        // MDI (`docs/dialects.md`, "Program restart") goes on in it.
        if program.is_some() {
            self.program = program;
        }
        self.run = Some(RunStart {
            program,
            started_at: now_rfc3339(),
            sim_start: self.controller.time(),
            estimate: None,
            held: false,
        });
    }

    /// The stored programs a run under way reads now: the one it started (AUTO), and the one
    /// its block is in (a program it called, from AUTO or MDI); none when no run is under way.
    /// They may not be replaced or removed meanwhile (`service::programs`).
    pub fn programs_in_use(&self) -> [Option<u32>; 2] {
        match &self.run {
            Some(run) => [run.program, self.layouts.locate(self.controller.point().line).0],
            None => [None, None],
        }
    }

    /// The stored program a program restart's search holds (searching, or searched and waiting
    /// for the cycle start that returns the axes, when the run begins): it may not be replaced
    /// or removed meanwhile, as the restart would go on in the text searched while the status
    /// showed lines of another (`service::programs`).
    pub fn program_searched(&self) -> Option<u32> {
        let searched = self.controller.restart_status().is_some_and(|r| r.phase != RestartPhase::Returning);
        self.program.filter(|_| searched)
    }

    /// The run just begun is the one estimated under `key`.
    pub fn estimate_run(&mut self, key: Key) {
        if let Some(run) = &mut self.run {
            run.estimate = Some(key);
        }
    }

    /// The run of a stored program under way against its estimate (`None` for none, or MDI).
    pub fn progress(&self) -> Option<RunProgress> {
        let run = self.run.as_ref()?;
        let program = run.program?;
        let estimate = match run.estimate.and_then(|k| self.estimates.get(k)) {
            Some(e) => e.clone(),
            None => Estimate {
                state: "unknown".into(),
                cycle_time_s: None,
                alarm: None,
                reason: Some(
                    "no estimate was begun for this run (the service was busy with others, or the run began before this service held it)"
                        .into(),
                ),
                depends_on: Vec::new(),
            },
        };
        let panel = &self.controller.panel;
        let seen = Conditions {
            feed_override: panel.feed_override,
            rapid_override: panel.rapid_override,
            single_block: panel.single_block,
            optional_stop: panel.optional_stop,
            held: run.held || run_state(&self.controller) == RunState::Hold,
            dry_run: panel.dry_run,
            aux_lock: panel.aux_lock,
        };
        Some(progress(program, self.controller.time() - run.sim_start, estimate, seen))
    }

    /// The run under way ends with `result` now (an operator's action).
    pub fn end_run(&mut self, controller: &str, result: &'static str) -> Option<Record> {
        self.end_run_at(controller, result, self.controller.time())
    }

    /// The run under way ended with `result` at simulated time `at`: where the program ended
    /// within the tick, not the tick's end (`cycle_time_s` equals `fivex run`'s at any speed).
    fn end_run_at(&mut self, controller: &str, result: &'static str, at: f64) -> Option<Record> {
        let run = self.run.take()?;
        Some(Record::Run {
            controller: controller.to_string(),
            program: run.program,
            started_at: run.started_at,
            ended_at: now_rfc3339(),
            cycle_time_s: at - run.sim_start,
            result,
        })
    }

    /// After a tick of `real_dt` real seconds or an operator action: the controller's events as
    /// stream messages (`watching`: someone listens) and database records.
    pub fn collect(&mut self, controller: &str, real_dt: f64, watching: bool) -> (Vec<Message>, Vec<Record>) {
        let (mut messages, mut records) = (Vec::new(), Vec::new());
        let mut changed = false;
        for event in self.controller.take_events() {
            match event {
                Event::State(state) => {
                    changed = true;
                    let stopped = state == RunState::Idle && program_waits(&self.controller);
                    if let Some(run) = &mut self.run {
                        run.held |= state == RunState::Hold || stopped;
                    }
                    messages.push(Message::state(self));
                    self.shown_state = run_state(&self.controller);
                    let result = match state {
                        RunState::Idle if stopped => None,
                        RunState::Idle => Some("completed"),
                        RunState::Alarm => Some("alarm"),
                        _ => None,
                    };
                    let at = self.controller.state_changed_at();
                    if let Some(record) = result.and_then(|r| self.end_run_at(controller, r, at)) {
                        records.push(record);
                    }
                }
                Event::Alarm(alarm) => {
                    let alarm = self.layouts.alarm(&alarm);
                    let row = crate::db::AlarmRow {
                        raised_at: now_rfc3339(),
                        code: alarm.code.clone(),
                        message: alarm.message.clone(),
                        line: alarm.line,
                        n: alarm.n,
                        program: alarm.program,
                    };
                    records.push(Record::Alarm { controller: controller.to_string(), alarm: row });
                    self.alarm_log.push(AlarmChange::Raised(alarm.clone()));
                    messages.push(Message::Alarm {
                        event: "raised",
                        raised: Some(alarm),
                        active: self.layouts.alarms(self.controller.alarms()),
                    });
                }
                Event::AlarmsCleared => {
                    self.alarm_log.push(AlarmChange::Cleared);
                    messages.push(Message::Alarm { event: "cleared", raised: None, active: Vec::new() });
                }
                Event::Message(text) => messages.push(Message::Message { text }),
                Event::Notice(notice) => {
                    let (program, line) = self.layouts.locate(notice.line);
                    messages.push(Message::Notice { notice: Notice { line, ..notice }, program });
                }
            }
        }
        if run_state(&self.controller) != self.shown_state {
            // A reset at an operator stop leaves the engine idle as it was (no event), while the
            // state shown goes from hold to idle.
            changed = true;
            messages.push(Message::state(self));
            self.shown_state = run_state(&self.controller);
        }
        let running = self.controller.run_state() == RunState::Running;
        self.since_streamed += real_dt;
        self.since_saved += real_dt;
        if watching && (changed || running && self.since_streamed >= STREAM_VARIABLES_EVERY) {
            self.since_streamed = 0.0;
            let changes = self.stream_changes();
            if !changes.is_empty() {
                messages.push(Message::variables(&changes));
            }
        }
        if changed || running && self.since_saved >= SAVE_VARIABLES_EVERY {
            self.since_saved = 0.0;
            self.save_counting(controller, &mut records);
            // The offsets a running program writes (G10, #5221…, #2001…) too, as the retained
            // variables: they were saved only at run state changes, and a `kill -9` during a
            // long program lost its G10 while its `#500=…` was kept.
            self.save_settings(controller, &mut records);
        }
        (messages, records)
    }

    /// At a graceful stop of the service: the run under way ends `interrupted`, and what is not
    /// saved yet is, as it stands — among it `#3002`, which counts while the controller stands
    /// idle too and was saved only at run state changes (it went back over a restart).
    pub fn final_records(&mut self, controller: &str) -> Vec<Record> {
        let mut records: Vec<Record> = self.end_run(controller, "interrupted").into_iter().collect();
        self.save_counting(controller, &mut records);
        self.save_settings(controller, &mut records);
        records
    }

    /// What changes as time passes, where it differs from what was saved: the retained
    /// variables (`#3002`, a program's `#500=…`) and the counters of automatic operation.
    fn save_counting(&mut self, controller: &str, records: &mut Vec<Record>) {
        if let Some(record) = self.save_changes(controller) {
            records.push(record);
        }
        let times = self.controller.times();
        if times != self.saved_times {
            self.saved_times = times;
            records.push(Record::Times { controller: controller.to_string(), times });
        }
    }

    /// What a program sets now and then, where it differs from what was saved: the offsets
    /// (G10) and the tilted plane kept over a restart.
    fn save_settings(&mut self, controller: &str, records: &mut Vec<Record>) {
        records.extend(self.offset_records(controller));
        let plane = self.controller.interpreter().state.kept_plane();
        if plane != self.saved_plane {
            self.saved_plane = plane;
            records.push(Record::TiltedPlane { controller: controller.to_string(), plane });
        }
    }

    /// Common variables that differ from what was streamed last.
    fn stream_changes(&mut self) -> Vec<(u32, Option<f64>)> {
        let now: BTreeMap<u32, f64> = self.controller.interpreter().state.common_variables().into_iter().collect();
        let mut changes: Vec<(u32, Option<f64>)> = now
            .iter()
            .filter(|(n, v)| self.streamed.get(n).is_none_or(|old| old.to_bits() != v.to_bits()))
            .map(|(n, v)| (*n, Some(*v)))
            .collect();
        changes.extend(self.streamed.keys().filter(|n| !now.contains_key(n)).map(|n| (*n, None)));
        changes.sort_by_key(|(n, _)| *n);
        self.streamed = now;
        changes
    }

    /// The tool and work offsets written since they were last saved (a program's G10, an API
    /// write), as records; from now on they count as saved.
    pub fn offset_records(&mut self, controller: &str) -> Vec<Record> {
        let axes = self.controller.interpreter().config().machine.axes.len();
        let (tools, work) = self.controller.interpreter_mut().state.offsets.take_touched();
        let now = &self.controller.interpreter().state.offsets;
        let tools: Vec<ToolRow> = tools.into_iter().filter_map(|n| now.tool(n).map(|t| tool_row(n, t))).collect();
        let work: Vec<(usize, Vec<f64>)> =
            work.into_iter().filter(|&i| i < WORK_SLOTS).map(|i| (i, now.work(i)[..axes].to_vec())).collect();
        let mut records = Vec::new();
        if !tools.is_empty() {
            records.push(Record::ToolOffsets { controller: controller.to_string(), rows: tools });
        }
        if !work.is_empty() {
            records.push(Record::WorkOffsets { controller: controller.to_string(), rows: work });
        }
        records
    }

    /// Retained variables that differ from what was saved last, as a record for the database
    /// (a variable that became vacant is saved as NULL).
    fn save_changes(&mut self, controller: &str) -> Option<Record> {
        let now: BTreeMap<u32, f64> = self.controller.interpreter().state.retained_variables().into_iter().collect();
        let changed = now.iter().filter(|(n, v)| self.saved.get(n).map(|s| s.to_bits()) != Some(v.to_bits()));
        let vacated = self.saved.keys().filter(|n| !now.contains_key(n));
        let values: Vec<(u32, Option<f64>)> =
            changed.map(|(&n, &v)| (n, Some(v))).chain(vacated.map(|&n| (n, None))).collect();
        if values.is_empty() {
            return None;
        }
        self.saved = now;
        Some(Record::Variables { controller: controller.to_string(), values })
    }
}

/// Work offset slots: the external offset, G54–G59, G54.1 P1–P300.
pub const WORK_SLOTS: usize = 7 + MAX_G54_1;

/// A tool offset as a database row.
pub fn tool_row(number: u32, t: &fivex_engine::interp::ToolOffset) -> ToolRow {
    ToolRow {
        number,
        length: t.h_geometry,
        length_wear: t.h_wear,
        radius: t.d_geometry,
        radius_wear: t.d_wear,
        corner_radius: t.corner_radius,
    }
}
