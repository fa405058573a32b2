//! FANUC program restart on a [`Controller`]: the block search ([`Controller::restart`], the
//! interpreter's `Interpreter::search`) and, at the next cycle start, the output of the M/S/T
//! the search passed over, the return of the axes to the restart position one at a time, and
//! the program going on from the restart block.
//!
//! P type (after a broken tool: the coordinates are those of the interrupted run) searches from
//! the point the last automatic operation started at, wherever the machine stands now; Q type
//! (after a power-off, an emergency stop) searches from where the machine stands, which the
//! operator has brought to the program's start point. Rules, alarms and decisions:
//! `docs/dialects.md`, "Program restart".

use super::{Controller, Mode, Refusal, RunState};
use crate::alarm::{Alarm, AlarmId};
use crate::canon::{CanonKind, MotionKind, Pos};
use crate::dialect::Dialect;
use crate::interp::restart::{Coordinates, Found, Search, Target};

/// How many blocks the search runs per controller tick: a long search (a loop of a million
/// passes) goes on over ticks, the controller answering between them; a reset stops it.
pub const SEARCH_BLOCKS_PER_TICK: u64 = 5_000;

/// FANUC's two kinds of program restart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = RestartTypeName))]
#[serde(rename_all = "lowercase")]
pub enum RestartType {
    /// After a broken tool: coordinates from the interrupted run's start.
    P,
    /// After a power-off or an emergency stop: coordinates from where the machine stands.
    Q,
}

/// Where a restart is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = RestartPhaseName))]
#[serde(rename_all = "lowercase")]
pub enum RestartPhase {
    /// The search runs (over ticks: [`SEARCH_BLOCKS_PER_TICK`]); the controller is running.
    Searching,
    /// The search has found the restart block; cycle start returns the axes.
    Searched,
    /// The axes return to the restart position; then the program goes on.
    Returning,
}

/// A restart under way, for the status.
#[derive(Debug, Clone, PartialEq)]
pub struct Restart {
    pub kind: RestartType,
    pub phase: RestartPhase,
    /// What the search found (while `Searching`: where it has got to, what it passed over).
    pub found: Found,
    /// The machine position the search started the program from (P type: where the last
    /// automatic operation started; Q type: where the machine stood). Once the return starts,
    /// the restart run is the last automatic operation and a later P type starts here.
    pub from: Pos,
}

/// What the controller remembers for a P type restart.
#[derive(Debug, Clone, Default)]
pub(super) struct RestartMemory {
    /// The machine position the last automatic operation started from (none since power-on or
    /// the emergency stop: P type is PS0097).
    pub(super) start: Option<Pos>,
    /// The work offsets when the last automatic operation stopped (interrupted or ended;
    /// changed since: PS0095 for the external one, PS0096 for the others).
    pub(super) work: Vec<Pos>,
    /// The coordinate system (selection, G52, G92) when it stopped (changed since: PS0094).
    pub(super) coordinates: Coordinates,
    /// An automatic operation runs (or is held, or stands at an operator stop): its stop takes
    /// `work`. A reset with nothing running is no stop and keeps it.
    pub(super) running: bool,
    /// The interpreter's state before the search under way, restored when the search is
    /// forgotten before its return (`Controller::forget_search`).
    pub(super) before_search: Option<Box<crate::interp::State>>,
    /// The interpreter's state the search left, kept while MDI runs between the search and
    /// its cycle start (M/S/T, F, G04, variables: `Controller::keep_search_over_mdi`); that
    /// cycle start goes on from it.
    pub(super) searched: Option<Box<crate::interp::State>>,
    /// The search under way (`RestartPhase::Searching`).
    pub(super) search: Option<Search>,
}

impl Controller {
    /// The program restart under way, if any.
    pub fn restart_status(&self) -> Option<&Restart> {
        self.restart.as_ref()
    }

    /// Program restart's block search: the selected program runs from its top to `target`
    /// without motion. Refused (as the panel would) outside AUTO, while anything runs, holds
    /// or is in alarm, without a program, and in the Syntec and Haas dialects (their manuals, as
    /// fivex has them, describe no FANUC-style P/Q restart: the NGC's restart is its Setting 36
    /// scan, not built). The manual's conditions are alarms: P type without an
    /// automatic operation since power-on or the emergency stop (PS0097), or after the
    /// coordinate system, the external or the work offsets changed (PS0094, PS0095, PS0096);
    /// the block not found (PS0071); a program alarm in the search.
    pub fn restart(&mut self, target: Target, kind: RestartType) -> Result<(), Refusal> {
        if self.interp.config().dialect != Dialect::Fanuc {
            return Err(Refusal::NotInDialect);
        }
        if self.mode != Mode::Auto {
            return Err(Refusal::WrongMode);
        }
        if self.estop
            || self.run_state != RunState::Idle
            || self.busy()
            || self.cycle.intervening()
            || self.exec.has_queued()
            || self.stopping.is_some()
        {
            return Err(Refusal::Busy);
        }
        let source = self.program.clone().ok_or(Refusal::NoProgram)?;
        self.forget_search();
        self.stand_here();
        let from = match kind {
            RestartType::Q => self.exec.here.machine,
            RestartType::P => {
                let Some(start) = self.memory.start else {
                    self.raise(AlarmId::RestartPNoRun, 0, None);
                    return Ok(());
                };
                if let Some(id) = self.changed_since_stop() {
                    // FANUC's PS0097 text: P type needs an automatic operation after "P/S alarm
                    // 94 to 97 reset" too, so the reset of this alarm does not open the way.
                    self.memory.start = None;
                    self.raise(id, 0, None);
                    return Ok(());
                }
                // The coordinates are the interrupted run's: the search starts where it started.
                self.interp.moved_to(&start);
                start
            }
        };
        self.memory.before_search = Some(Box::new(self.interp.state.clone()));
        self.interp.set_switches(self.panel.block_delete, self.panel.optional_stop);
        self.interp.load_source(&source);
        let search = Search::new(target, &self.interp);
        let found = search.so_far(&self.interp);
        self.restart = Some(Restart { kind, phase: RestartPhase::Searching, found, from });
        self.memory.search = Some(search);
        // The first slice now (a short program is searched at once); the rest over the ticks,
        // the controller running meanwhile (nothing else can start; a reset stops it).
        self.search_slice();
        if self.searching() {
            self.set_state(RunState::Running);
        }
        Ok(())
    }

    /// A block search is under way (`RestartPhase::Searching`).
    pub(super) fn searching(&self) -> bool {
        self.memory.search.is_some()
    }

    /// The next [`SEARCH_BLOCKS_PER_TICK`] blocks of the search under way: the restart block
    /// found, it waits for cycle start; an alarm in it stops it. True when a search was under way.
    pub(super) fn search_slice(&mut self) -> bool {
        let Some(mut search) = self.memory.search.take() else { return false };
        match self.interp.search_on(&mut search, SEARCH_BLOCKS_PER_TICK) {
            Ok(None) => {
                if let Some(r) = self.restart.as_mut() {
                    r.found = search.so_far(&self.interp);
                }
                self.memory.search = Some(search);
            }
            Ok(Some(found)) => {
                self.settle_executing();
                (self.exec.here.line, self.exec.here.n) = (found.line, found.n);
                if let Some(r) = self.restart.as_mut() {
                    (r.phase, r.found) = (RestartPhase::Searched, found);
                }
                self.set_state(RunState::Idle);
            }
            Err(alarm) => {
                self.forget_search();
                self.interp.reset();
                self.stand_here();
                self.alarm(alarm);
            }
        }
        true
    }

    /// Cycle start after a search: the M/S/T the search passed over are output, then each axis
    /// returns to the restart position on its own (in the machine's axis order) at rapid, and
    /// the program goes on from the restart block (`arrived`). In MDI the search is kept
    /// (`keep_search_over_mdi`) and the MDI program runs (false).
    pub(super) fn restart_start(&mut self) -> bool {
        if self.restart.as_ref().is_none_or(|r| r.phase != RestartPhase::Searched) {
            return false;
        }
        if self.mode == Mode::Mdi {
            self.keep_search_over_mdi();
            return false;
        }
        // MDI ran since the search: the program goes on in the state the search left (the
        // search had a program; selecting none or another forgets the search). What the MDI
        // wrote to memory (variables, offsets) stays; a coordinate system it set would be
        // dropped without effect, so it is refused (a decision).
        if let (Some(searched), Some(program)) = (self.memory.searched.take(), self.program.clone()) {
            let coordinates_set = searched.coordinates() != self.interp.state.coordinates();
            self.interp.load_source(&program);
            self.interp.state.forget_search(*searched);
            self.settle_executing();
            if coordinates_set {
                self.refuse_mdi(0, None);
                return true;
            }
        }
        let Some(r) = self.restart.as_mut() else { return false };
        r.phase = RestartPhase::Returning;
        // From here the program runs: a reset is a run's reset, and the restart run is the last
        // automatic operation (a later P type searches from where its search started).
        self.memory.before_search = None;
        self.memory.running = true;
        self.memory.start = Some(r.from);
        let (target, output, block) = (r.found.machine, r.found.output.clone(), (r.found.line, r.found.n));
        // Hand moves since the search moved the interpreter's current point with the machine:
        // the program goes on from the restart position.
        self.stand_here();
        self.interp.moved_to(&target);
        for c in &output {
            match &c.kind {
                CanonKind::Chain(chain) => self.follow_chain(*chain),
                CanonKind::Spindle { .. } => self.carry_out(&c.kind),
                // The interpreter already has the tool in the spindle; the change takes no time.
                _ => {}
            }
        }
        self.exec.stand_in(self.interp.state.tip_basis());
        let mut to = self.exec.here.machine;
        for i in 0..self.machine.axes.len() {
            if (to[i] - target[i]).abs() > 1e-9 {
                to[i] = target[i];
                // The panel shows the restart block the axes return to.
                self.push_manual_at(MotionKind::MachineRapid, to, 0.0, block);
            }
        }
        self.set_state(RunState::Running);
        true
    }

    /// MDI between the search and its cycle start: FANUC allows the M/S/T (and fivex F, G04 and
    /// macro statements) to be given; the search's state is kept for the restart's cycle start
    /// while the MDI program has the interpreter. A move in it is PS0099 (`mdi_moves_after_search`).
    fn keep_search_over_mdi(&mut self) {
        if self.memory.searched.is_none() {
            self.memory.searched = Some(Box::new(self.interp.state.clone()));
        }
    }

    /// An MDI program reads a move while a search waits for its cycle start: PS0099, the search
    /// is forgotten. True when it did (the move is not made).
    pub(super) fn mdi_moves_after_search(&mut self, line: u32, n: Option<u32>) -> bool {
        let held = self.restart.as_ref().is_some_and(|r| r.phase == RestartPhase::Searched);
        if self.mode != Mode::Mdi || !held {
            return false;
        }
        self.refuse_mdi(line, n);
        true
    }

    /// PS0099 MDI EXEC NOT ALLOWED AFT. SEARCH: the search is forgotten.
    fn refuse_mdi(&mut self, line: u32, n: Option<u32>) {
        self.forget_search();
        self.interp.reset();
        self.raise(AlarmId::RestartMdi, line, n);
    }

    /// Called before the program reads on: when the return has ended, the program goes on from
    /// the restart block (single block: it stops there first, as after a block).
    pub(super) fn restart_arrived(&mut self) -> bool {
        let returning = self.restart.as_ref().is_some_and(|r| r.phase == RestartPhase::Returning);
        if !returning || self.exec.is_moving() || self.exec.has_queued() {
            return false;
        }
        let Some(r) = self.restart.take() else { return false };
        // The panel shows the restart block until it runs.
        (self.exec.here.line, self.exec.here.n) = (r.found.line, r.found.n);
        // Where the machine stands is exactly where the search left the program.
        self.exec.here.work = self.interp.state.shown_position();
        self.exec.queue_from_here(self.exec.here.work, self.interp.state.tip_basis());
        self.wse_no_manual = self.interp.wse_forbids_manual();
        self.cycle.start();
        if self.panel.single_block {
            self.cycle.course_mut().stop();
            self.set_state(RunState::Idle);
        }
        true
    }

    /// The search under way is forgotten (a reset, an emergency stop, another program, another
    /// search, an alarm): before its return the interpreter goes back to the state the search
    /// began from (`State::forget_search`): the searched modes (G91, G68…) must not carry
    /// into the next program, as the search moved nothing.
    pub(super) fn forget_search(&mut self) {
        if let Some(before) = self.memory.before_search.take() {
            self.interp.state.forget_search(*before);
        }
        self.memory.searched = None;
        self.memory.search = None;
        self.restart = None;
    }

    /// The automatic operation stopped (interrupted by a reset, an emergency stop or an alarm,
    /// or ended): what a later P type restart compares the offsets with. A reset while nothing
    /// runs is not an interruption and keeps the interrupted run's offsets (FANUC's PS0096:
    /// the work offset changed after the interruption).
    pub(super) fn remember_stop(&mut self) {
        if std::mem::take(&mut self.memory.running) {
            self.memory.work = self.interp.state.offsets.work_copy();
            self.memory.coordinates = self.interp.state.coordinates();
        }
    }

    /// What changed since the last automatic operation stopped that makes its coordinates
    /// wrong for a P type restart: the coordinate system set or another selected (G92, G52,
    /// G92.1, G54… in MDI: PS0094), the external work offset (PS0095), a work offset (PS0096).
    /// Tool offsets may change (the broken tool's replacement).
    fn changed_since_stop(&self) -> Option<AlarmId> {
        let st = &self.interp.state;
        if st.coordinates() != self.memory.coordinates {
            Some(AlarmId::RestartPCoordinatesChanged)
        } else if !st.offsets.same_external(&self.memory.work) {
            Some(AlarmId::RestartPExternalOffsetChanged)
        } else if !st.offsets.same_work(&self.memory.work) {
            Some(AlarmId::RestartPOffsetChanged)
        } else {
            None
        }
    }

    fn alarm(&mut self, a: Alarm) {
        self.alarms.push(a.clone());
        self.events.push(super::Event::Alarm(a));
        self.set_state(RunState::Alarm);
    }
}
