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
use crate::interp::restart::{Found, Target};

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
    pub found: Found,
}

/// What the controller remembers for a P type restart.
#[derive(Debug, Clone, Default)]
pub(super) struct RestartMemory {
    /// The machine position the last automatic operation started from (none since power-on or
    /// the emergency stop: P type is PS0097).
    pub(super) start: Option<Pos>,
    /// The work offsets when the last automatic operation stopped (interrupted or ended;
    /// changed since: PS0096).
    pub(super) work: Vec<Pos>,
    /// An automatic operation runs (or is held, or stands at an operator stop): its stop takes
    /// `work`. A reset with nothing running is no stop and keeps it.
    pub(super) running: bool,
    /// The interpreter's state before the search under way, restored when the search is
    /// forgotten before its return (`Controller::forget_search`).
    pub(super) before_search: Option<Box<crate::interp::State>>,
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
    /// automatic operation since power-on or the emergency stop (PS0097), or after the work
    /// offsets changed (PS0096); the block not found (PS0071); a program alarm in the search.
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
        if kind == RestartType::P {
            let Some(start) = self.memory.start else {
                self.raise(AlarmId::RestartPNoRun, 0, None);
                return Ok(());
            };
            if !self.interp.state.offsets.same_work(&self.memory.work) {
                // FANUC's PS0097 text: P type needs an automatic operation after "P/S alarm 94
                // to 97 reset" too, so the reset of this alarm does not open the way.
                self.memory.start = None;
                self.raise(AlarmId::RestartPOffsetChanged, 0, None);
                return Ok(());
            }
            // The coordinates are the interrupted run's: the search starts where it started.
            self.interp.moved_to(&start);
        }
        self.memory.before_search = Some(Box::new(self.interp.state.clone()));
        self.interp.set_switches(self.panel.block_delete, self.panel.optional_stop);
        self.interp.load_source(&source);
        match self.interp.search(target) {
            Ok(found) => {
                self.settle_executing();
                (self.exec.here.line, self.exec.here.n) = (found.line, found.n);
                self.restart = Some(Restart { kind, phase: RestartPhase::Searched, found });
            }
            Err(alarm) => {
                self.forget_search();
                self.interp.reset();
                self.stand_here();
                self.alarm(alarm);
            }
        }
        Ok(())
    }

    /// Cycle start after a search: the M/S/T the search passed over are output, then each axis
    /// returns to the restart position on its own (in the machine's axis order) at rapid, and
    /// the program goes on from the restart block (`arrived`). MDI before it: PS0099.
    pub(super) fn restart_start(&mut self) -> bool {
        let Some(r) = self.restart.as_mut().filter(|r| r.phase == RestartPhase::Searched) else {
            return false;
        };
        if self.mode == Mode::Mdi {
            self.forget_search();
            self.interp.reset();
            self.raise(AlarmId::RestartMdi, 0, None);
            return true;
        }
        r.phase = RestartPhase::Returning;
        // From here the program runs: a reset is a run's reset.
        self.memory.before_search = None;
        self.memory.running = true;
        let (target, output) = (r.found.machine, r.found.output.clone());
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
                self.push_manual(MotionKind::MachineRapid, to, 0.0);
            }
        }
        self.set_state(RunState::Running);
        true
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
        self.restart = None;
    }

    /// The automatic operation stopped (interrupted by a reset, an emergency stop or an alarm,
    /// or ended): what a later P type restart compares the offsets with. A reset while nothing
    /// runs is not an interruption and keeps the interrupted run's offsets (FANUC's PS0096:
    /// the work offset changed after the interruption).
    pub(super) fn remember_stop(&mut self) {
        if std::mem::take(&mut self.memory.running) {
            self.memory.work = self.interp.state.offsets.work_copy();
        }
    }

    fn alarm(&mut self, a: Alarm) {
        self.alarms.push(a.clone());
        self.events.push(super::Event::Alarm(a));
        self.set_state(RunState::Alarm);
    }
}
