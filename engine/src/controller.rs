//! One virtual controller: operator panel, modes and the program cycle around the interpreter
//! and the motion planner, advanced by [`Controller::tick`] so that a host (the server's
//! worker threads, a test) decides how fast simulated time runs.
//!
//! What the buttons do follows the FANUC panel: cycle start runs the selected program (AUTO) or
//! the MDI text (MDI), or resumes after a feed hold, M00/M01 or a single-block stop; feed hold
//! decelerates along the path within every axis limit and waits; reset decelerates the same way,
//! then abandons the program and clears the alarms; emergency stop stops at once and raises an
//! alarm that only a reset clears. JOG moves one axis while the jog key is held, HANDLE moves it
//! by the amount a hand wheel gives, REF returns every axis to the reference position. Those
//! manual moves stop at the stroke limits and the program's current point follows them. The
//! 5-axis manual operation (feeds along the tool, manual intervention in a held program, Syntec's
//! manual RTCP) is in `manual.rs`; the program cycle's states and their transitions (blocks to
//! read, commands read ahead, a dwell, a stop, a manual intervention) in `cycle.rs`.

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, Motion, MotionContext, MotionKind, Pos, SpindleState, Tapping};
use crate::interp::{Config, Interpreter, ModalState, Step};
use crate::kin::Kinematics;
use crate::machine::Machine;
use crate::motion::{Braking, Endpoint, Executor, FeedContext, Finished, Point, Sample, Segment};
use crate::notice::Notice;
use crate::stage::Pipeline;
use std::sync::Arc;

mod cycle;
mod executing;
mod interrupt;
mod lock;
mod manual;
mod operation;
mod restart;
mod signals;
use cycle::Cycle;
use executing::{BlockState, Executing};
use interrupt::Interrupt;
use lock::Lock;
pub use manual::ManualCoordinates;
use manual::{Intervention, Shift};
pub use operation::{Times, SPINDLE_OVERRIDE};
pub use restart::{Restart, RestartPhase, RestartType, SEARCH_BLOCKS_PER_TICK};
pub use signals::{ManualSignals, ManualTarget};

/// A controller's mode: the operator panel's mode switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = ModeName))]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    Auto,
    Mdi,
    Jog,
    Handle,
    Ref,
    /// Incremental feed (FANUC INC): each JOG key press moves by `Panel::increment`.
    Inc,
}

/// A controller's run state (docs/contracts.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = RunStateName))]
#[serde(rename_all = "lowercase")]
pub enum RunState {
    Idle,
    Running,
    Hold,
    Alarm,
}

/// Why a program waits for cycle start at a block boundary ([`Controller::program_stop`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramStop {
    /// M00, or a `#3006` message stop.
    Stop,
    /// M01 with the optional stop switch on.
    Optional,
    /// The end of a block under single block.
    SingleBlock,
}

/// The operator panel's switches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Panel {
    pub single_block: bool,
    pub optional_stop: bool,
    pub block_delete: bool,
    /// Fractions, 1.0 = 100% (FANUC: feed 0–200%, rapid F0/25/50/100%).
    pub feed_override: f64,
    pub rapid_override: f64,
    /// JOG and HANDLE feed, mm/min or deg/min (FANUC No.1423).
    pub jog_feed: f64,
    /// Manual absolute (FANUC signal *ABSM = 0): after a manual intervention in a held program,
    /// cycle start goes on to the programmed end point; off (*ABSM = 1): the current and every
    /// later end point are shifted by the intervention.
    pub manual_absolute: bool,
    /// Syntec R518: the coordinate system X/Y/Z JOG and HANDLE move in.
    pub manual_coordinates: ManualCoordinates,
    /// Syntec R519 manual RTCP: under tool centre point control, jogging a rotary axis keeps
    /// the tool tip where it is (tool tip centre rotation).
    pub manual_rtcp: bool,
    /// FANUC's 5-axis manual feed signals (ALNGH, RGHTH, RNDH, TB_BASE) and the handle's axis
    /// select code, read by [`Controller::jog_signal`] and [`Controller::handle_pulses`].
    pub manual_signals: ManualSignals,
    /// The increment of INC mode, mm (deg for a rotary axis): one JOG key press moves this far
    /// (FANUC's ×1/×10/×100/×1000 of the least increment: 0.001, 0.01, 0.1, 1).
    pub increment: f64,
    /// Dry run (FANUC DRN): set through [`Controller::set_dry_run`], which keeps it to block
    /// boundaries (`operation.rs`).
    pub dry_run: bool,
    /// Spindle speed override, a fraction (FANUC SOV; [`SPINDLE_OVERRIDE`]).
    pub spindle_override: f64,
    /// Machine lock, all axes (FANUC MLK): set through [`Controller::set_machine_lock`]
    /// (`lock.rs`).
    pub machine_lock: bool,
    /// Z-axis neglect (FANUC ZNG): the Z axis alone locked ([`Controller::set_z_neglect`]).
    pub z_neglect: bool,
    /// Auxiliary function lock (FANUC AFL): the program's spindle commands and tool changes are
    /// not carried out (M00/M01/M02/M30/M98/M99 are).
    pub aux_lock: bool,
}

impl Default for Panel {
    fn default() -> Panel {
        Panel {
            single_block: false,
            optional_stop: false,
            block_delete: false,
            feed_override: 1.0,
            rapid_override: 1.0,
            jog_feed: 1000.0,
            manual_absolute: true,
            manual_coordinates: ManualCoordinates::Machine,
            manual_rtcp: false,
            manual_signals: ManualSignals::default(),
            increment: 0.001,
            dry_run: false,
            spindle_override: 1.0,
            machine_lock: false,
            z_neglect: false,
            aux_lock: false,
        }
    }
}

/// Something a client should hear about, in the order it happened.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    State(RunState),
    Alarm(Alarm),
    AlarmsCleared,
    Message(String),
    /// A block queued to run by a rule of fivex's own (`crate::notice`).
    Notice(crate::notice::Notice),
}

/// Refused operator actions (the panel would ignore them; a service answers 409).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// The action needs another mode.
    WrongMode,
    /// The machine is busy (running) or in alarm.
    Busy,
    /// There is nothing to run.
    NoProgram,
    /// The axis does not exist (or cannot do that: a linear axis cannot turn about the tip,
    /// a machine without 5-axis kinematics has no 5-axis feeds).
    NoAxis,
    /// The amount is not a finite number.
    BadValue,
    /// The dialect's manuals describe no such function (Syntec's program restart).
    NotInDialect,
}

/// What happens when a deceleration (to rest, or to a new override's speed) has ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AfterStop {
    /// Feed hold: the rest of the path waits for cycle start.
    Hold,
    /// Reset, end of a jog: the rest of the path is dropped.
    Drop,
    /// An override changed: the rest of the path is planned on from the speed reached.
    Continue,
}

pub struct Controller {
    interp: Interpreter,
    /// The machine (the executor's, shared; its mechanism drives the 5-axis manual feeds).
    machine: Arc<Machine>,
    /// Where canonical motions become motion: the planner, the run under way, the clock.
    exec: Executor,
    /// The path stages between the interpreter and the executor (`crate::stage`).
    stages: Pipeline,
    program: Option<crate::lang::Source>,
    mdi: Option<crate::lang::Source>,
    mode: Mode,
    run_state: RunState,
    pub panel: Panel,
    alarms: Vec<Alarm>,
    events: Vec<Event>,
    estop: bool,
    /// A deceleration to rest in progress, and what follows it.
    stopping: Option<AfterStop>,
    /// Spindle speed, 1/min: positive clockwise (M03), negative counter-clockwise (M04).
    spindle: f64,
    /// The program cycle: blocks to read, commands read ahead, a dwell or a stop, a manual
    /// intervention holding it (`cycle.rs`).
    cycle: Cycle,
    /// Manual absolute off: what the interventions moved, added to every later motion.
    shift: Option<Shift>,
    /// Manual absolute on after an intervention at a block stop: the next tool tip path starts
    /// where the tip is, not where the program left it.
    reposition: bool,
    /// G54.4 with tool direction compensation on a table machine is in effect where the
    /// machine is (not where the interpreter has read to): manual moves raise an alarm (WSE-25).
    wse_no_manual: bool,
    /// Manual handle interruption: the shift laid over the program (`interrupt.rs`).
    interrupt: Interrupt,
    /// The block the machine is executing, behind the interpreter's reading (`executing.rs`).
    executing: Executing,
    /// Serial of the block whose commands are being handed on (its segments carry it).
    reading_block: u64,
    /// A program restart searched or returning (`restart.rs`).
    restart: Option<Restart>,
    /// What a P type restart needs from the interrupted run (`restart.rs`).
    memory: restart::RestartMemory,
    /// Operating and cutting time (`operation.rs`).
    times: Times,
    /// Machine lock: where the machine is held, what a locked run left (`lock.rs`).
    lock: Lock,
    /// What made the last operator stop (read while the program waits there).
    stop_kind: ProgramStop,
    /// Simulated time of the last run state change ([`Controller::state_changed_at`]).
    state_changed_at: f64,
    /// The manual move under way ends at a stored stroke limit: the overtravel alarm it raises
    /// when it gets there (FANUC OT0500/OT0501; a jog stopped short raises nothing).
    stroke_reached: Option<AlarmId>,
    /// The single block switch as the last tick found it: switched on under way, the blocks
    /// already read and queued stop at their ends too (`Executor::stop_at_block_ends`).
    single_block_seen: bool,
    /// The serial of the last block whose end the reader passed with single block off (its
    /// `Item::BlockEnd` gone): switched on later, nothing read stops at that block's end but
    /// the motion's own stop (`Controller::block_end_stop`).
    block_ends_passed: u64,
    /// The last run that ended was a tapping cycle's feed into the hole: the tap is at the
    /// bottom (dwelling, the spindle reversing) until its feed out ([`Controller::tapping`]).
    tap_at_bottom: bool,
    /// A feed hold pressed while the tap was in the hole: it takes effect at the end of the
    /// feed out, with the tap out of the hole (`Controller::feed_hold`).
    hold_after_tap: bool,
}

/// A pending canonical command, or a single-block stop point. (Commands stay inline, the other
/// items small beside them: a box per command would be an allocation for every block read.)
#[allow(clippy::large_enum_variant)]
enum Item {
    /// The commands of the block with this serial follow (`Executing`).
    Block(u64),
    Canon(Canon),
    BlockEnd,
    Alarm(Alarm),
    /// A G54.4 block turned the manual-move ban of WSE-25 on or off; it takes effect when the
    /// machine gets there (the motion before it ends first: G54.4 suppresses buffering, WSE-01).
    WseNoManual(bool),
}

/// Blocks the interpreter may run in one tick without motion before the tick ends (an endless
/// macro loop must not freeze the host; the block budget alarm ends it eventually).
const BLOCKS_PER_TICK: usize = 100_000;

impl Controller {
    pub fn new(cfg: Config) -> Controller {
        let machine = cfg.machine.clone();
        let interp = Interpreter::new(crate::lang::parse_file(""), cfg);
        let start = Endpoint {
            machine: interp.state.machine_position(),
            work: interp.state.shown_position(),
            basis: interp.state.tip_basis(),
        };
        let executing =
            Executing::new(interp.state.modal_state(), interp.state.active_plane(), interp.state.modal_part());
        Controller {
            exec: Executor::new(machine.clone(), start),
            stages: Pipeline::for_config(interp.config()),
            machine,
            interp,
            program: None,
            mdi: None,
            mode: Mode::Auto,
            run_state: RunState::Idle,
            panel: Panel::default(),
            alarms: Vec::new(),
            events: Vec::new(),
            estop: false,
            stopping: None,
            spindle: 0.0,
            cycle: Cycle::OFF,
            shift: None,
            reposition: false,
            wse_no_manual: false,
            interrupt: Interrupt::default(),
            executing,
            reading_block: 0,
            restart: None,
            memory: restart::RestartMemory::default(),
            times: Times::default(),
            lock: Lock::default(),
            stop_kind: ProgramStop::Stop,
            state_changed_at: 0.0,
            stroke_reached: None,
            single_block_seen: false,
            block_ends_passed: 0,
            tap_at_bottom: false,
            hold_after_tap: false,
        }
    }

    // --- what a client reads ------------------------------------------------------------

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn run_state(&self) -> RunState {
        self.run_state
    }

    pub fn time(&self) -> f64 {
        self.exec.time()
    }

    /// The simulated time at which the run state last changed: where within a tick a program
    /// ended (or stopped, or alarmed), which [`Controller::time`] after the tick is past.
    pub fn state_changed_at(&self) -> f64 {
        self.state_changed_at
    }

    /// The program waits for cycle start at M00, M01, `#3006` or a single-block stop, with
    /// blocks still to run (the run state is then `Idle`; the run is not over): why.
    pub fn program_stop(&self) -> Option<ProgramStop> {
        self.at_operator_stop().then_some(self.stop_kind)
    }

    /// The program waits for cycle start at a block stop with blocks or queued motion of it
    /// still to run (a single-block stop in the motion read ahead: `Controller::block_end_stop`).
    fn at_operator_stop(&self) -> bool {
        self.cycle.at_operator_stop()
            || self.cycle.course().stopped() && !self.cycle.intervening() && self.exec.has_queued()
    }

    /// A program held (feed hold or a block stop) is waiting while the operator intervenes by
    /// hand in JOG/HANDLE/INC (the run state is then `Idle` between the hand moves; the run is
    /// not over).
    pub fn intervening(&self) -> bool {
        self.cycle.intervening()
    }

    /// Nothing is under way that a restart in reset state would cut short: idle (no alarm, no
    /// emergency stop), no program started and not over (reading, held, at a single-block stop
    /// or M00/M01, or held for a manual intervention), no motion moving or queued (a jog, a
    /// handle or reference move, a deceleration). The service moves only such a controller to
    /// another node (`docs/cluster.md`, "Rebalancing").
    pub fn at_rest(&self) -> bool {
        self.run_state == RunState::Idle
            && !self.estop
            && self.cycle.program_over()
            && !self.exec.is_moving()
            && !self.exec.has_queued()
    }

    pub fn alarms(&self) -> &[Alarm] {
        &self.alarms
    }

    /// Whether the emergency stop is pressed.
    pub fn emergency_stopped(&self) -> bool {
        self.estop
    }

    /// The text of 1-based `line` of what the mode runs (the AUTO program or the MDI text),
    /// as a panel's program display shows the executing block; `None` past its end or before
    /// anything was selected.
    pub fn source_line(&self, line: u32) -> Option<&str> {
        let source = match self.mode {
            Mode::Mdi => self.mdi.as_ref(),
            _ => self.program.as_ref(),
        }?;
        source.line(line)
    }

    /// Where the machine is now (rollover axes shown modulo 360). The machine position includes
    /// a manual handle interruption's shift, the program's (absolute) position does not.
    pub fn point(&self) -> Point {
        Point {
            machine: self.machine.shown(&self.machine_now()),
            work: self.machine.shown(&self.exec.here.work),
            ..self.exec.here
        }
    }

    /// Distance to go: from here to the end of the block moving now, in workpiece coordinates
    /// per axis (zero when nothing moves). The end is that of the block's last segment in the
    /// run being executed.
    pub fn to_go(&self) -> Pos {
        let mut out = [0.0; crate::machine::MAX_AXES];
        {
            let line = self.exec.here.line;
            let end = self.exec.run_ahead().iter().take_while(|seg| seg.line == line).last();
            if let Some(seg) = end {
                for (o, (to, here)) in out.iter_mut().zip(seg.work_to().iter().zip(&self.exec.here.work)) {
                    *o = to - here;
                }
            }
        }
        out
    }

    /// Spindle speed, 1/min: positive clockwise (M03), negative counter-clockwise (M04), 0
    /// stopped; the commanded speed times the spindle override, except while the tap of a
    /// tapping cycle is in the hole: there the override does not act, as the feed override
    /// does not (the tap's feed is F, its pitch F/S; `docs/motion.md`, "The controller").
    pub fn spindle(&self) -> f64 {
        if self.tapping() {
            return self.spindle;
        }
        self.spindle * self.panel.spindle_override
    }

    /// The tap of a tapping cycle is in the hole: from the start of its feed in to the end of
    /// its feed out, the dwell and the spindle's reversal at the bottom between.
    fn tapping(&self) -> bool {
        match self.exec.on() {
            Some((seg, _, _)) => seg.tapping() != Tapping::No,
            None => self.tap_at_bottom,
        }
    }

    /// The tool length offset the tip is read with now: the moving block's; standing still,
    /// [`Controller::tip_basis`]'s — the last block's while commands read ahead wait, otherwise
    /// the interpreter's, so a G49 (or a G43 H) without a motion changes the shown length as it
    /// changes the tip (it showed the last motion's length after `G49 / M30`).
    pub fn tool_length(&self) -> f64 {
        if self.exec.is_moving() {
            self.exec.tool_length()
        } else {
            self.tip_basis().tool_length
        }
    }

    /// How the tool tip is read from the machine axes now (`crate::tip`): the tool length and
    /// workpiece system of the segment moving now; standing still, those of the last one while
    /// commands read ahead wait (the interpreter is ahead of the machine), otherwise the
    /// interpreter's: an MDI G54, an offset edit, or a program's G92/G52/G10 L2 before a stop
    /// takes effect at once (audit of offsets F3).
    pub fn tip_basis(&self) -> crate::tip::Basis {
        if self.exec.is_moving() {
            self.exec.basis()
        } else if !self.stands_where_read() {
            self.exec.last_basis()
        } else {
            self.interp.state.tip_basis()
        }
    }

    /// Where the tool tip is now, from the machine axes (with a handle interruption's shift)
    /// and [`Controller::tip_basis`].
    pub fn tip(&self) -> crate::tip::Tip {
        let basis = self.tip_basis();
        crate::tip::locate(self.machine.kinematics_of(basis.chain).map(|k| &**k), &self.machine_now(), &basis)
    }

    /// The machine now, as the trace reads it (`Sample`): axes with a handle interruption's
    /// shift, tip by forward kinematics with [`Controller::tip_basis`].
    pub fn sample(&self) -> Sample {
        self.exec.sample(self.exec.time(), &self.machine_now(), &self.tip_basis())
    }

    /// The modal state of the block the machine is executing. The interpreter's own state is
    /// the block it has read to; they differ while blocks read ahead are queued or moving.
    pub fn modal(&self) -> ModalState {
        if self.reading_is_executing() {
            self.interp.state.modal_state()
        } else {
            self.executing.shown().modal
        }
    }

    /// The tilted working plane of the block the machine is executing (as [`Controller::modal`]).
    pub fn plane(&self) -> Option<crate::interp::TiltedPlane> {
        if self.reading_is_executing() {
            self.interp.state.active_plane()
        } else {
            self.executing.shown().plane
        }
    }

    /// Nothing read ahead is queued or moving: the interpreter's state is the machine's.
    fn reading_is_executing(&self) -> bool {
        self.cycle.blocks().nothing_ahead() && !self.exec.is_moving() && !self.exec.has_queued()
    }

    /// The mechanism chain the machine executes in (Syntec G10 L5000: the program's, in program
    /// order).
    pub fn chain(&self) -> crate::machine::Chain {
        self.machine.chain()
    }

    /// The mechanism of the chain in force (compiled once with the machine).
    pub fn kinematics(&self) -> Option<&std::sync::Arc<Kinematics>> {
        self.machine.kinematics()
    }

    pub fn interpreter(&self) -> &Interpreter {
        &self.interp
    }

    pub fn interpreter_mut(&mut self) -> &mut Interpreter {
        &mut self.interp
    }

    /// The events since the last call.
    pub fn take_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    // --- operator actions ---------------------------------------------------------------

    /// Offsets were changed from outside (an operator, a host): while nothing runs, the
    /// program's current point is derived again from where the machine stands, as a real
    /// control's position display follows an offset edit.
    pub fn offsets_changed(&mut self) {
        if !self.busy() && !self.exec.has_queued() {
            self.stand_here();
        }
    }

    /// What is clamped on the table (`crate::workpiece`): the boxes a G31 probe touches.
    pub fn workpiece(&self) -> &Arc<crate::workpiece::Workpiece> {
        &self.interp.config().workpiece
    }

    /// Put `workpiece` on the table (an empty one: nothing there). Changed only at a block
    /// boundary, under the rule of machine lock (`Controller::at_block_boundary`): a skip block
    /// finds its contact when it is read, so a move planned or under way was found against the
    /// boxes that were there; a block read after the change probes the new ones. A workpiece
    /// that `check` refuses is `Refusal::BadValue`.
    pub fn set_workpiece(&mut self, workpiece: Arc<crate::workpiece::Workpiece>) -> Result<(), Refusal> {
        if workpiece.check().is_err() {
            return Err(Refusal::BadValue);
        }
        if !self.at_block_boundary() {
            return Err(Refusal::Busy);
        }
        self.interp.set_workpiece(workpiece);
        Ok(())
    }

    /// Change the mode: only while no program or motion is under way, or, for a manual
    /// intervention, from AUTO/MDI held (feed hold, single-block stop) to JOG/HANDLE and back.
    pub fn set_mode(&mut self, mode: Mode) -> Result<(), Refusal> {
        // A program that is over hands its coordinates back before a manual mode uses them.
        self.settle_interrupt();
        if self.exec.is_moving()
            || self.stopping.is_some()
            || self.run_state == RunState::Running
            || self.interrupt.moving.is_some()
        {
            return Err(Refusal::Busy);
        }
        if let Some(back) = self.cycle.intervention().map(|i| i.mode) {
            if self.exec.has_queued() {
                // A held hand move: cycle start finishes it first.
                return Err(Refusal::Busy);
            }
            return match mode {
                Mode::Jog | Mode::Handle | Mode::Inc => {
                    self.mode = mode;
                    Ok(())
                }
                m if m == back => {
                    self.end_intervention();
                    Ok(())
                }
                _ => Err(Refusal::Busy),
            };
        }
        let held = self.run_state == RunState::Hold;
        let at_block_stop = self.at_operator_stop();
        if (held || at_block_stop) && matches!(self.mode, Mode::Auto | Mode::Mdi) {
            if !matches!(mode, Mode::Jog | Mode::Handle | Mode::Inc) || self.estop {
                return Err(Refusal::Busy);
            }
            if self.in_five_axis_compensation() {
                // S000 §3.5.1: a manual interruption operation in the cutter compensation
                // mode for 5-axis machining is a PS alarm (its number is not given: fivex
                // raises the mode's PS5460); nothing has moved.
                let (line, n) = (self.exec.here.line, self.exec.here.n);
                self.raise(AlarmId::IllegalCommandInMode, line, n);
                self.mode = mode;
                return Ok(());
            }
            self.cycle.intervene(Intervention {
                mode: self.mode,
                held,
                start: self.exec.here.machine,
                path: self.exec.take_queued(),
                queued: (self.exec.queued.machine, self.exec.queued.work),
            });
            (self.exec.queued.machine, self.exec.queued.work) = (self.exec.here.machine, self.exec.here.work);
            self.exec.queued.basis = self.tip_basis();
            // The hand moves go where the machine stands (a handle interruption's shift in it).
            self.release_interrupt();
            self.mode = mode;
            return Ok(());
        }
        if self.busy() || held || self.exec.has_queued() {
            return Err(Refusal::Busy);
        }
        self.mode = mode;
        Ok(())
    }

    /// Whether the block the machine executes is in a cutter compensation for 5-axis machining
    /// (the tool side offsets G41.2…G42.6, the leading edge offset G41.3), where S000 §3.5.1
    /// makes a manual interruption a PS alarm and the manual handle interruption unusable.
    pub(super) fn in_five_axis_compensation(&self) -> bool {
        use crate::interp::gcode::{code, group};
        let comp = self.modal().modal(group::CUTTER_COMP);
        code::TOOL_SIDE.contains(&comp) || comp == code::G41_3
    }

    /// The program AUTO runs (an NC text, or a text and the stored programs it can call).
    pub fn select_program(&mut self, source: impl Into<crate::lang::Source>) -> Result<(), Refusal> {
        if self.busy() || self.cycle.intervening() {
            return Err(Refusal::Busy);
        }
        self.program = Some(source.into());
        self.forget_search();
        Ok(())
    }

    /// The text MDI runs (and the stored programs it can call).
    pub fn set_mdi(&mut self, source: impl Into<crate::lang::Source>) -> Result<(), Refusal> {
        if self.mode != Mode::Mdi {
            return Err(Refusal::WrongMode);
        }
        if self.busy() {
            return Err(Refusal::Busy);
        }
        self.mdi = Some(source.into());
        Ok(())
    }

    /// A manual move cannot start: a program or motion is under way, something is queued (a
    /// held manual move: cycle start finishes it), the emergency stop or an alarm.
    fn manual_blocked(&self) -> bool {
        self.busy() || self.exec.has_queued() || self.estop || self.run_state == RunState::Alarm
    }

    /// WSE-25: G54.4 with tool direction compensation on a machine that turns its table
    /// refuses manual moves with an alarm (the seed gives no number: PS0439, the alarm of the
    /// other table-machine restrictions, `docs/five-axis.md`). True when it did.
    fn manual_refused_in_wse(&mut self) -> bool {
        if !self.wse_no_manual {
            return false;
        }
        self.raise(AlarmId::WseModalState, self.exec.here.line, self.exec.here.n);
        true
    }

    /// A motion is under way or about to start.
    fn moving(&self) -> bool {
        self.run_state == RunState::Running || self.exec.is_moving()
    }

    /// A program or a motion is under way (a program held for a manual intervention lets
    /// the manual commands through).
    fn busy(&self) -> bool {
        self.run_state == RunState::Running || self.cycle.program_reading() || self.exec.is_moving()
    }

    pub fn cycle_start(&mut self) -> Result<(), Refusal> {
        if self.cycle.intervening() {
            // JOG/HANDLE of a manual intervention: cycle start only finishes a held hand move;
            // the program goes on after the return to its mode.
            if self.run_state == RunState::Hold && self.exec.has_queued() && !self.estop {
                self.set_state(RunState::Running);
                return Ok(());
            }
            return Err(Refusal::WrongMode);
        }
        if self.estop || self.run_state == RunState::Alarm {
            return Err(Refusal::Busy);
        }
        match self.run_state {
            // A program under way: nothing to start. A manual move in JOG/HANDLE/INC/REF: cycle
            // start has nothing to do there, as at rest in that mode.
            RunState::Running if matches!(self.mode, Mode::Auto | Mode::Mdi) => return Ok(()),
            RunState::Running => return Err(Refusal::WrongMode),
            RunState::Hold => {
                // Switched on while held: the held block's end stops (during the deceleration,
                // once it has ended: `after_stop`).
                self.stop_at_block_ends();
                self.cycle.course_mut().release_stop();
                self.set_state(RunState::Running);
                return Ok(());
            }
            _ => {}
        }
        if self.at_operator_stop() {
            self.cycle.course_mut().release_stop();
            self.set_state(RunState::Running);
            return Ok(());
        }
        if self.restart_start() {
            return Ok(());
        }
        let source = match self.mode {
            Mode::Auto => self.program.clone(),
            Mode::Mdi => self.mdi.clone(),
            _ => return Err(Refusal::WrongMode),
        };
        let source = source.ok_or(Refusal::NoProgram)?;
        if !self.exec.is_moving() && !self.exec.has_queued() {
            // A fresh start begins where the machine stands: a manual move (a HANDLE move that
            // ran to its end, an INC step) may have moved it since the program's current point
            // was last set.
            self.stand_here();
        }
        // A new run: the shift of manual absolute off lasts until the program's end, however
        // the last one ended (M02/M30, the end of its text, an MDI program).
        (self.shift, self.reposition) = (None, false);
        if self.mode == Mode::Auto {
            // Where a P type restart's search starts from (`restart.rs`).
            self.memory.start = Some(self.exec.here.machine);
            self.memory.running = true;
        }
        self.interp.set_switches(self.panel.block_delete, self.panel.optional_stop);
        self.interp.load_source(&source);
        // An MDI program ends after its last block; one from memory needs M02/M30 (FANUC).
        self.interp.set_mdi_operation(self.mode == Mode::Mdi);
        self.settle_executing();
        self.wse_no_manual = self.interp.wse_forbids_manual();
        self.apply_interrupt();
        // Until its first motion ends, the program stands in the state it starts from.
        self.exec.stand_in(self.interp.state.tip_basis());
        self.cycle.start();
        self.set_state(RunState::Running);
        Ok(())
    }

    /// Feed and rapid override (fractions; FANUC: feed 0–200%, rapid F0–100%): the motion
    /// under way changes speed at once, within the limits (acceleration jerked to zero, then
    /// an S-curve down to the new speed, or on up by the look-ahead).
    pub fn set_overrides(&mut self, feed: f64, rapid: f64) {
        let (feed, rapid) = (feed.clamp(0.0, 2.0), rapid.clamp(0.0, 1.0));
        self.panel.feed_override = feed;
        self.panel.rapid_override = rapid;
        if self.stopping.is_some() {
            return;
        }
        if self.exec.set_overrides(feed, rapid) {
            self.stopping = Some(AfterStop::Continue);
        }
    }

    /// Feed hold: decelerate along the path and wait for cycle start. While the tap of a
    /// tapping cycle is in the hole the machine goes on to the end of the tap's feed out
    /// (point R) and holds there: stopping the feed with the spindle turning would strip the
    /// thread or break the tap ("When feedhold or halt is applied, the tap will stop when it
    /// is out of the hole", `docs/motion.md`, "The controller").
    pub fn feed_hold(&mut self) {
        // A restart's search moves nothing to hold (a reset stops it).
        if self.run_state == RunState::Running && !self.searching() {
            if self.tapping() {
                self.hold_after_tap = true;
                return;
            }
            self.decelerate(AfterStop::Hold);
            self.set_state(RunState::Hold);
        }
    }

    /// Reset: decelerate, abandon the program, clear the alarms (not an emergency stop that is
    /// still pressed).
    pub fn reset(&mut self) {
        // Before anything read ahead is dropped (the current point is set from the machine
        // after it, here or at the end of the deceleration).
        self.take_back_read_ahead();
        // The machine's reset stops the spindle (as the usual machine ladder does).
        self.spindle = 0.0;
        self.cycle.end_intervention();
        self.stroke_reached = None;
        let moving = self.exec.is_moving();
        if moving {
            self.decelerate(AfterStop::Drop);
        } else {
            self.exec.take_queued();
        }
        self.abandon_program();
        self.interp.state.clear_commons_at_reset();
        // A G10 L5000 read ahead and dropped still switched the interpreter, whose state the next
        // program starts from: the machine takes its chain too.
        self.follow_chain(self.interp.config().machine.chain());
        if !moving {
            // After the interpreter's reset, as at the end of the deceleration (`after_stop`): what
            // the reset cancelled is shown cancelled at once — the position in the workpiece
            // system, not the feature coordinate system of a G68.2 it ended (audit of views F3).
            self.stand_here();
        }
        if !self.estop && !self.alarms.is_empty() {
            self.alarms.clear();
            self.events.push(Event::AlarmsCleared);
        }
        if !self.estop {
            // The axes decelerate to rest first: until they stand the machine is not idle (it
            // stays running or held); the stop's end makes it idle (`after_stop`).
            if !self.exec.is_moving() {
                self.set_state(RunState::Idle);
            }
        }
        self.settle_interrupt();
    }

    /// The program stops for good: nothing read ahead is carried out.
    fn abandon_program(&mut self) {
        self.forget_search();
        (self.tap_at_bottom, self.hold_after_tap) = (false, false);
        self.remember_stop();
        self.shift = None;
        self.reposition = false;
        self.cycle.abandon();
        self.stages.reset();
        self.interp.reset();
        self.settle_executing();
        self.wse_no_manual = self.interp.wse_forbids_manual();
    }

    /// Everything read is dropped or done: the block shown is the interpreter's state.
    fn settle_executing(&mut self) {
        let st = &self.interp.state;
        self.executing.settle(st.modal_state(), st.active_plane(), st.modal_part());
    }

    /// A reset or an emergency stop while blocks read ahead are queued or moving: they were
    /// never executed, so what they put in force is taken back (modal codes, the work offset
    /// selected, G52/G92, the transforms, the tool length vector, canned cycle data, the 5-axis
    /// modes): the state is the executing block's, as the panel showed it. The variables their
    /// macro statements set stay (run when read, `docs/motion.md`, "Reading ahead").
    fn take_back_read_ahead(&mut self) {
        if self.reading_is_executing() {
            return;
        }
        let executed = self.executing.shown().modal;
        self.interp.state.restore_executed(self.executing.shown_part(), &executed);
    }

    /// Emergency stop pressed (`true`) or released: pressing stops every axis at once.
    pub fn emergency_stop(&mut self, pressed: bool) {
        self.estop = pressed;
        if pressed {
            // A P type restart needs an automatic operation after this (PS0097).
            self.memory.start = None;
            self.end_interrupt_move();
            self.take_back_read_ahead();
            self.spindle = 0.0;
            self.cycle.end_intervention();
            self.exec.halt();
            self.stopping = None;
            self.abandon_program();
            self.stand_here();
            self.raise(AlarmId::EmergencyStop, self.exec.here.line, self.exec.here.n);
            self.settle_interrupt();
        }
    }

    /// JOG: start moving `axis` in the direction of `positive` at its jog feed (FANUC No.1423,
    /// else the panel's; with override) until [`Controller::jog_stop`] or the stroke limit. X/Y/Z move in the coordinate system
    /// of `panel.manual_coordinates` (Syntec R518); a rotary axis with `panel.manual_rtcp`
    /// under tool centre point control turns about the tool tip (R519).
    ///
    /// In INC mode the key press moves by the panel's increment instead (stopping at the
    /// stroke limit), the same feeds and the same choices.
    pub fn jog_start(&mut self, axis: char, positive: bool) -> Result<(), Refusal> {
        let reach = self.jog_reach()?;
        let i = self.axis(axis)?;
        let jog_feed = self.jog_feed_of(i);
        if let Some(d) = self.coordinate_direction(i) {
            return self.move_along(if positive { d } else { -d }, reach, jog_feed);
        }
        if let Some(length) = self.rtcp_length(i) {
            let feed = jog_feed * self.panel.feed_override;
            let turn = reach.min(360.0);
            return self.turn_about_tip(axis, if positive { turn } else { -turn }, length, feed, None);
        }
        let far = if positive { reach.min(1.0e6) } else { -reach.min(1.0e6) };
        self.manual_move_within_stroke(i, self.exec.here.machine[i] + far, jog_feed)
    }

    /// How far a JOG key press moves: until jog stop (JOG mode), or the panel's increment (INC
    /// mode, FANUC incremental feed).
    fn jog_reach(&self) -> Result<f64, Refusal> {
        match self.mode {
            Mode::Jog => Ok(f64::INFINITY),
            Mode::Inc => Ok(self.panel.increment),
            _ => Err(Refusal::WrongMode),
        }
    }

    /// The increment of INC mode, mm (deg): positive and finite, changed while nothing moves.
    pub fn set_increment(&mut self, increment: f64) -> Result<(), Refusal> {
        if !increment.is_finite() || increment <= 0.0 {
            return Err(Refusal::BadValue);
        }
        if self.moving() {
            return Err(Refusal::Busy);
        }
        self.panel.increment = increment;
        Ok(())
    }

    pub fn jog_stop(&mut self) {
        if self.mode == Mode::Jog && self.exec.is_moving() {
            self.decelerate(AfterStop::Drop);
        }
    }

    /// HANDLE: move `axis` by `amount` (mm or deg; the hand wheel's pulses × increment),
    /// stopping at the stroke limit with the overtravel alarm.
    pub fn handle(&mut self, axis: char, amount: f64) -> Result<(), Refusal> {
        if self.mode != Mode::Handle {
            return Err(Refusal::WrongMode);
        }
        let i = self.axis(axis)?;
        if !amount.is_finite() {
            return Err(Refusal::BadValue);
        }
        if let Some(d) = self.coordinate_direction(i) {
            return self.move_along(if amount < 0.0 { -d } else { d }, amount.abs(), self.panel.jog_feed);
        }
        if let Some(length) = self.rtcp_length(i) {
            return self.turn_about_tip(axis, amount, length, self.panel.jog_feed, None);
        }
        self.manual_move_within_stroke(i, self.exec.here.machine[i] + amount, self.panel.jog_feed)
    }

    /// REF: every axis back to the reference position (machine zero) at rapid; a rollover axis
    /// less than a turn (`Axis::reference_return_end`).
    pub fn reference_return(&mut self) -> Result<(), Refusal> {
        if self.mode != Mode::Ref {
            return Err(Refusal::WrongMode);
        }
        if self.manual_blocked() {
            return Err(Refusal::Busy);
        }
        if self.manual_refused_in_wse() {
            return Ok(());
        }
        self.clear_interrupt();
        self.clear_lock_offset();
        let (mut to, dialect) = (self.exec.here.machine, self.interp.config().dialect);
        for (i, axis) in self.machine.axes.iter().enumerate() {
            to[i] = axis.reference_return_end(to[i], 0.0, dialect);
        }
        self.push_manual(MotionKind::MachineRapid, to, 0.0);
        Ok(())
    }

    fn axis(&self, name: char) -> Result<usize, Refusal> {
        self.machine.axes.iter().position(|a| a.name == name).ok_or(Refusal::NoAxis)
    }

    /// A manual move of one axis toward `wanted`, which stops at the axis's stored stroke
    /// limit: reaching it raises the overtravel alarm of stored stroke check 1 (FANUC
    /// OT0500/OT0501; `docs/motion.md`, "The controller"); at the limit already, at once.
    fn manual_move_within_stroke(&mut self, axis: usize, wanted: f64, feed: f64) -> Result<(), Refusal> {
        let Some((target, over)) = self.stroke_limited(axis, wanted) else {
            return self.manual_move(axis, wanted, feed);
        };
        if self.manual_blocked() {
            return Err(Refusal::Busy);
        }
        if target == self.exec.here.machine[axis] {
            self.raise(over, self.exec.here.line, self.exec.here.n);
            return Ok(());
        }
        self.manual_move(axis, target, feed)?;
        if self.run_state == RunState::Running {
            self.stroke_reached = Some(over);
        }
        Ok(())
    }

    /// Where a manual move of `axis` toward `wanted` must stop, and the alarm it raises there,
    /// if `wanted` is beyond the axis's stored stroke.
    fn stroke_limited(&self, axis: usize, wanted: f64) -> Option<(f64, AlarmId)> {
        let [lo, hi] = self.machine.axes[axis].stroke?;
        let name = self.machine.axes[axis].name;
        let over = |positive| AlarmId::OverTravel { axis: name, positive, precheck: false };
        if wanted > hi {
            Some((hi, over(true)))
        } else if wanted < lo {
            Some((lo, over(false)))
        } else {
            None
        }
    }

    fn manual_move(&mut self, axis: usize, target: f64, feed: f64) -> Result<(), Refusal> {
        if self.manual_blocked() {
            return Err(Refusal::Busy);
        }
        if self.manual_refused_in_wse() {
            return Ok(());
        }
        let mut to = self.exec.here.machine;
        to[axis] = target;
        self.push_manual(MotionKind::Linear, to, feed);
        Ok(())
    }

    /// A motion outside the program, in machine coordinates.
    fn push_manual(&mut self, kind: MotionKind, machine: Pos, feed: f64) {
        self.push_manual_at(kind, machine, feed, self.manual_shown_at());
    }

    /// The block a manual move shows: in a manual intervention the program block it interrupted
    /// (the program screen keeps it; the status showed line 0 until cycle start), none otherwise.
    fn manual_shown_at(&self) -> (u32, Option<u32>) {
        if self.cycle.intervening() {
            (self.exec.here.line, self.exec.here.n)
        } else {
            (0, None)
        }
    }

    /// [`Self::push_manual`] shown at a program block (`line`, N): a program restart's return.
    fn push_manual_at(&mut self, kind: MotionKind, machine: Pos, feed: f64, (line, n): (u32, Option<u32>)) {
        self.stroke_reached = None;
        let offset: Pos = std::array::from_fn(|i| self.exec.here.work[i] - self.exec.here.machine[i]);
        let target: Pos = std::array::from_fn(|i| machine[i] + offset[i]);
        let m = Motion {
            kind,
            target,
            machine,
            arc: None,
            tip: None,
            feed,
            feed_mode: crate::canon::FeedMode::PerMinute,
            spindle: 0.0,
            // Handle pulses go at the clamp, whatever the override.
            context: MotionContext { fixed_feed: feed >= manual::AT_CLAMP, ..MotionContext::default() },
            speed_cap: f32::INFINITY,
            offset: None,
            no_look_ahead: false,
            block_limit: 0,
            notice: None,
        };
        let ctx = self.exec.feed_context(self.panel.feed_override, self.panel.rapid_override, true);
        let mut seg = self.exec.segment_within(&m, ctx, &self.manual_limits());
        (seg.stop_after, seg.tip_basis, seg.line, seg.n) = (true, self.tip_basis(), line, n);
        self.exec.queued.basis = seg.tip_basis;
        self.exec.push(seg);
        self.set_state(RunState::Running);
    }

    // --- time ---------------------------------------------------------------------------

    /// Advance simulated time by `dt` seconds.
    pub fn tick(&mut self, dt: f64) {
        let end = self.exec.time() + dt.max(0.0);
        if self.run_state == RunState::Running && self.search_slice() {
            // A program restart's search: nothing moves, time goes on (`restart.rs`).
            self.exec.idle_until(end);
            return;
        }
        let mut blocks = 0;
        // The blocks read now see the panel's switches (Haas #3030–#3033): block delete skips
        // the `/` blocks read after it is switched, as the control checks it when it reads a
        // block into its buffer.
        self.interp.state.set_panel_switches(self.panel.single_block, self.panel.dry_run);
        self.interp.set_switches(self.panel.block_delete, self.panel.optional_stop);
        if self.panel.single_block != self.single_block_seen {
            self.single_block_seen = self.panel.single_block;
            // Switched on under way: the blocks read ahead (the look-ahead's hundreds) stop at
            // their ends too, from the first the machine can still stop at. Switched off: those
            // stops go again.
            match self.panel.single_block {
                true => self.stop_at_block_ends(),
                false => self.exec.clear_block_stops(),
            }
        }
        let before = self.times;
        // The counters take each stretch of time by what was under way at its start.
        let mut piece = self.piece();
        while self.exec.time() < end {
            self.count(&mut piece);
            if self.exec.is_moving() {
                self.exec.advance_to(end);
                if let Some((seg, _, _)) = self.exec.on() {
                    self.executing.begin(seg.block);
                }
                if let Some(finished) = self.exec.finish() {
                    self.finish_run(finished);
                }
                continue;
            }
            if self.run_state != RunState::Running || self.estop {
                self.exec.idle_until(end);
                break;
            }
            if let Some(until) = self.cycle.course().dwell_end() {
                self.exec.idle_until(until.min(end));
                if self.exec.time() >= until {
                    self.cycle.course_mut().dwell_over();
                }
                continue;
            }
            if self.cycle.intervening() {
                // Only the manual moves run; the program waits for the return to its mode.
                if self.exec.release(true) {
                    continue;
                }
                self.exec.here.feed = 0.0;
                self.set_state(RunState::Idle);
                self.exec.idle_until(end);
                break;
            }
            if self.cycle.course().stopped() {
                self.exec.idle_until(end);
                break;
            }
            if self.exec.release(false) {
                continue;
            }
            if blocks >= BLOCKS_PER_TICK {
                // A long stretch of blocks without motion: the rest next tick, time goes on.
                self.exec.idle_until(end);
                break;
            }
            blocks += 1;
            if !self.advance_program() {
                // Nothing more to read: carry out the rest and stop.
                self.cycle.over();
                self.remember_stop();
                if self.exec.release(true) {
                    continue;
                }
                if matches!(self.mode, Mode::Jog | Mode::Handle | Mode::Inc | Mode::Ref) {
                    // A manual move ended (a reference return too): the program's current point
                    // (#5001…, #5021…) is where the machine stands now, not at the next block,
                    // so that what starts from it (the estimate, the path preview, a fleet run
                    // of this controller) starts there.
                    self.stand_here();
                }
                self.exec.here.feed = 0.0;
                if self.run_state == RunState::Running {
                    self.set_state(RunState::Idle);
                }
                // The program ended here, not at the end of the tick: the rest of it is not
                // automatic operation.
                self.count(&mut piece);
                self.exec.idle_until(end);
            }
        }
        self.count(&mut piece);
        self.interp.state.advance_time(dt.max(0.0));
        // The interpreter's timers (Haas #3021…) count what the controller's counters counted.
        let operating = self.times.operating_s - before.operating_s;
        self.interp.state.count_operation(operating, self.times.cutting_s - before.cutting_s);
        self.settle_interrupt();
    }

    /// A run ended: on its last point, or after a deceleration to rest, keep or drop the rest
    /// of the path.
    fn finish_run(&mut self, finished: Finished) {
        let Some(after) = self.stopping.take() else {
            // A whole run ends exactly on its last point.
            self.exec.arrive(&finished);
            self.at_stroke_limit();
            if self.tap_out_hold(&finished) {
                return;
            }
            self.block_end_stop(&finished);
            return;
        };
        // Stopped short (jog stop, reset): no limit reached.
        self.stroke_reached = None;
        let p = &finished.planned;
        self.after_stop(after, p.rest(p.profile.len()), p.profile.end_speed());
    }

    /// Where the tap stands after `finished` ended on its last point; a feed hold pressed while
    /// it was in the hole takes effect once it is out, at rest at the end of its feed out (the
    /// spindle's restart and the rest of the cycle wait for cycle start). True when it did.
    fn tap_out_hold(&mut self, finished: &Finished) -> bool {
        let p = &finished.planned;
        let Some(last) = p.segments.last() else { return false };
        self.tap_at_bottom = last.tapping() == Tapping::In;
        let out = last.tapping() == Tapping::Out && !last.continued() && p.profile.end_speed() <= 0.0;
        if !(out && self.hold_after_tap) {
            return false;
        }
        self.hold_after_tap = false;
        self.exec.here.feed = 0.0;
        if self.run_state == RunState::Running {
            self.set_state(RunState::Hold);
        }
        true
    }

    /// Single block on: a program run that ends at rest at the end of a block (or of a stretch
    /// of a canned cycle's block, `run_block`) read before the switch went on stops there for
    /// cycle start, with the motion after it queued or with nothing queued (the program's last
    /// moves, commands still to carry out); the commands read ahead wait with it. (A block
    /// read with the switch on stops at its `Item::BlockEnd`, with nothing of a later block
    /// queued.)
    fn block_end_stop(&mut self, finished: &Finished) {
        let p = &finished.planned;
        let Some(last) = p.segments.last() else { return };
        let ended = match self.exec.queued_segments().next() {
            Some(next) => crate::motion::executor::block_end(last, Some(next), self.block_ends_passed),
            // Its `Item::BlockEnd` is gone: nothing else stops at its end.
            None => last.block <= self.block_ends_passed && self.cycle.blocks().has_more(),
        };
        if !self.panel.single_block
            || self.cycle.intervening()
            || !matches!(self.mode, Mode::Auto | Mode::Mdi)
            || !last.stop_after
            || p.profile.end_speed() > 0.0
            || !ended
        {
            return;
        }
        self.stop_kind = ProgramStop::SingleBlock;
        self.cycle.course_mut().stop();
        self.exec.here.feed = 0.0;
        self.set_state(RunState::Idle);
    }

    /// Single block on in a program under way: the blocks already read and queued stop at
    /// their ends too, from the first the machine can still stop at (`Executor::stop_at_block_ends`).
    /// Not during a feed hold's or a reset's deceleration: it stops where it stops, and the
    /// rest of the path is marked when it has ended (`after_stop`).
    fn stop_at_block_ends(&mut self) {
        if !self.panel.single_block
            || self.cycle.intervening()
            || matches!(self.stopping, Some(AfterStop::Hold | AfterStop::Drop))
        {
            return;
        }
        if self.exec.stop_at_block_ends(self.block_ends_passed) && self.stopping == Some(AfterStop::Continue) {
            // An override's speed change was under way: the run now ends at rest at the stop.
            self.stopping = None;
        }
    }

    /// A manual move that ended at a stored stroke limit stops there in the overtravel alarm;
    /// the program's current point is where the machine stands. The alarm clears with reset,
    /// after which the axis moves again (back from the limit; on, it alarms again at once).
    fn at_stroke_limit(&mut self) {
        let Some(over) = self.stroke_reached.take() else { return };
        self.stand_here();
        self.exec.here.feed = 0.0;
        self.raise(over, self.exec.here.line, self.exec.here.n);
    }

    /// Carry on after a deceleration that ended at `speed` with `rest` of the path ahead.
    fn after_stop(&mut self, after: AfterStop, rest: Vec<Segment>, speed: f64) {
        match after {
            AfterStop::Hold => {
                self.exec.requeue(rest);
                // Single block switched on during the deceleration (and cycle start perhaps
                // already pressed): the held block's end stops.
                self.stop_at_block_ends();
            }
            AfterStop::Continue => self.exec.resume(rest, speed),
            AfterStop::Drop => {
                self.stand_here();
                if matches!(self.run_state, RunState::Running | RunState::Hold) {
                    self.set_state(RunState::Idle);
                }
            }
        }
    }

    /// Whatever was planned is gone: the next motion starts where the machine stands, and so
    /// does the program's current point (it had read ahead).
    fn stand_here(&mut self) {
        if self.cycle.intervening() {
            // The held program's current point stays where the program put it.
            self.exec.queue_from_here(self.exec.here.work, self.tip_basis());
            return;
        }
        self.interp.moved_to(&self.program_machine());
        self.exec.here.work = self.interp.state.shown_position();
        self.exec.queue_from_here(self.exec.here.work, self.interp.state.tip_basis());
    }

    /// Decelerate to rest along the path, within the limits of every segment the stop covers;
    /// the path after the stop point is kept for `after`.
    fn decelerate(&mut self, after: AfterStop) {
        if after == AfterStop::Drop {
            // The move will not get to its end: no stroke limit reached.
            self.stroke_reached = None;
        }
        if let Some(already @ (AfterStop::Hold | AfterStop::Drop)) = self.stopping {
            // Already stopping: only what follows may change (dropping wins over holding).
            if already == AfterStop::Hold {
                self.stopping = Some(after);
            }
            if after == AfterStop::Drop {
                self.drop_pending();
            }
            return;
        }
        // A speed change under way is a motion like any other: stop from where it is.
        self.stopping = None;
        match self.exec.brake() {
            Braking::Idle => {
                if after == AfterStop::Drop {
                    self.exec.take_queued();
                }
            }
            // The run under way ends at rest as planned (a non-linear rapid, or a run too near
            // its own stop), then what follows waits or is dropped.
            Braking::Finishing => {
                self.stopping = Some(after);
                if after == AfterStop::Drop {
                    self.exec.take_queued();
                    self.drop_pending();
                }
            }
            // At the very end of the path: already there.
            Braking::AtEnd { rest } => self.after_stop(after, rest, 0.0),
            Braking::Started => {
                self.stopping = Some(after);
                if after == AfterStop::Drop {
                    self.drop_pending();
                }
            }
        }
    }

    /// A stop that drops the path also drops what the program read ahead, unless the path
    /// was a manual intervention's (the held program keeps its blocks).
    fn drop_pending(&mut self) {
        if !self.cycle.intervening() {
            self.cycle.blocks_mut().drop_ahead();
        }
    }

    /// Read the program on: hand the next pending command to the planner (or carry it out),
    /// or run the next block. Returns false when there is nothing more to read.
    fn advance_program(&mut self) -> bool {
        let more = self.read_on();
        self.show_work_at_rest();
        more
    }

    /// Standing with nothing read ahead, the interpreter's state is the machine's: the
    /// workpiece position shown (the status, the stream's programmed point) is its current
    /// point, which has the blocks without motion since the last motion — G92, G52, G10 L2, a
    /// G5x change. The executor's is where the last segment ended, in that segment's system, so
    /// at a stop after `G92 X50.` the position showed the old system while #5041 read the new
    /// one (audit of offsets F3). Under cutter compensation the executor's (the tool centre)
    /// stays (`State::shown_at_rest`, the run summary's rule too), during a manual intervention
    /// the held program's point, and the manual modes set their own (`stand_here`, the
    /// reference return).
    fn show_work_at_rest(&mut self) {
        if matches!(self.mode, Mode::Auto | Mode::Mdi) && self.stands_where_read() && !self.cycle.intervening() {
            self.exec.here.work = self.interp.state.shown_at_rest(&self.exec.here.work);
        }
    }

    /// Nothing of the program moves or waits to move: the machine stands where the interpreter
    /// has read to. (The commands still ahead are the last block's — the interpreter reads a
    /// block only when none are left — such as its M00 and its end.)
    fn stands_where_read(&self) -> bool {
        let motion = |i: &Item| matches!(i, Item::Canon(c) if matches!(c.kind, CanonKind::Motion(_)));
        !self.exec.is_moving()
            && !self.exec.has_queued()
            && self.cycle.blocks().ahead().is_none_or(|q| !q.iter().any(motion))
    }

    /// [`Controller::advance_program`]'s step.
    fn read_on(&mut self) -> bool {
        if self.restart_arrived() {
            return true;
        }
        if !self.exec.is_moving() && !self.exec.has_queued() {
            if let Some(block) = self.executing.motion_ended() {
                self.show(block);
            }
        }
        let Some(item) = self.cycle.blocks_mut().pop() else {
            if !self.cycle.blocks().reading() {
                return false;
            }
            self.run_block();
            return true;
        };
        let motion_pending = self.exec.is_moving() || self.exec.has_queued();
        match item {
            Item::Block(serial) => {
                self.reading_block = serial;
                if let Some(block) = self.executing.reached(serial, motion_pending) {
                    self.show(block);
                }
            }
            Item::Canon(c) => match &c.kind {
                CanonKind::Motion(_) if self.mdi_moves_after_search(c.line, c.n) => return true,
                CanonKind::Motion(m) => {
                    if self.shift.as_ref().is_some_and(|s| self.refuses_on_tip_path(s, m)) {
                        if motion_pending {
                            // The alarm comes when the machine has stopped before the block.
                            self.cycle.blocks_mut().push_front(Item::Canon(c));
                            self.flush();
                        } else {
                            self.raise(AlarmId::RotaryShiftOnTipPath, c.line, c.n);
                        }
                        return true;
                    }
                    let (shifted, dry);
                    // After a manual intervention only (a plain run pays one test).
                    let m = if self.shift.is_none() && !self.reposition {
                        m
                    } else {
                        shifted = self.moved_motion(m, self.shift.as_ref());
                        self.reposition = false;
                        &shifted
                    };
                    let m = match self.dry_run_motion(m) {
                        Some(d) => {
                            dry = d;
                            &dry
                        }
                        None => m,
                    };
                    let ctx = self.program_feed(m);
                    let shift = (!self.interrupt.is_zero()).then(|| self.interrupt.last());
                    let events = &mut self.events;
                    let noticed = |seg: &Segment| events.extend(Notice::of(seg).map(Event::Notice));
                    let queued = self.exec.queue(&c, m, ctx, self.reading_block, shift.as_ref(), noticed);
                    if let Ok(Some(id)) = queued {
                        // A stroke limit stops the block on its way (G54.4): the alarm comes when
                        // the machine stands there, and nothing after it is read.
                        let (code, message) = self.interp.config().dialect.describe(&id);
                        let alarm = Alarm { code, message, line: c.line, n: c.n };
                        self.cycle.blocks_mut().push_front(Item::Alarm(alarm));
                        self.cycle.blocks_mut().end_reading();
                        return true;
                    }
                    if let Err(id) = queued {
                        if motion_pending {
                            // The alarm comes when the machine has stopped before the block.
                            self.cycle.blocks_mut().push_front(Item::Canon(c));
                            self.flush();
                        } else {
                            // Refused before it starts (the stroke pre-check OT0510/OT0511):
                            // the interpreter had read on to the move's end, so its current
                            // point (the workpiece position shown, the programmed point,
                            // #5001…, #5041…) is taken back to where the machine stands, as at
                            // every other stop that drops what was read.
                            self.stand_here();
                            self.raise(id, c.line, c.n);
                        }
                        return true;
                    }
                    self.events.extend(Notice::of_command(&c).map(Event::Notice));
                }
                _ if motion_pending => {
                    // Every other command waits for the motion before it.
                    self.cycle.blocks_mut().push_front(Item::Canon(c));
                    self.flush();
                }
                kind => self.carry_out(kind),
            },
            Item::BlockEnd if !self.panel.single_block => self.block_ends_passed = self.reading_block,
            Item::BlockEnd if motion_pending => {
                self.cycle.blocks_mut().push_front(Item::BlockEnd);
                self.flush();
            }
            Item::BlockEnd => {
                if self.panel.single_block && self.cycle.blocks().has_more() {
                    self.stop_kind = ProgramStop::SingleBlock;
                    self.cycle.course_mut().stop();
                    self.set_state(RunState::Idle);
                }
            }
            Item::WseNoManual(on) if motion_pending => {
                self.cycle.blocks_mut().push_front(Item::WseNoManual(on));
                self.flush();
            }
            Item::WseNoManual(on) => self.wse_no_manual = on,
            Item::Alarm(a) if motion_pending => {
                self.cycle.blocks_mut().push_front(Item::Alarm(a));
                self.flush();
            }
            Item::Alarm(a) => {
                // The run is interrupted here (not at the reset that clears the alarm).
                self.remember_stop();
                self.alarms.push(a.clone());
                self.events.push(Event::Alarm(a));
                self.set_state(RunState::Alarm);
            }
        }
        true
    }

    /// Release everything queued, ending at rest.
    fn flush(&mut self) {
        self.exec.release(true);
    }

    /// Queue a block's commands (`block`: the block just read, whose stretches they may be).
    /// A canned cycle's stop point (FANUC: operations 1, 2 and 6 of each hole) ends a stretch
    /// of the block, before the next motion (after the commands without motion that follow the
    /// marked one: a spindle restarted), and the next stretch is read as a block of its own
    /// (the same line and state, a new serial), so that single block switched on under way
    /// finds the stop among the segments read ahead too. Commands of several lines end each
    /// line at its own stop.
    fn push_commands(&mut self, commands: Vec<Canon>, block: Option<BlockState>) {
        let mut line = commands.first().map(|c| c.line);
        let mut cycle_stop = false;
        for c in commands {
            let motion = match &c.kind {
                CanonKind::Motion(m) => Some(m.context.cycle_stop),
                _ => None,
            };
            if line != Some(c.line) || (cycle_stop && motion.is_some()) {
                self.cycle.blocks_mut().push(Item::BlockEnd);
                if let Some(stretch) = block.filter(|_| line == Some(c.line)) {
                    self.cycle.blocks_mut().push(Item::Block(self.executing.read(stretch, false, None)));
                }
                (line, cycle_stop) = (Some(c.line), false);
            }
            cycle_stop = motion.unwrap_or(cycle_stop);
            self.cycle.blocks_mut().push(Item::Canon(c));
        }
    }

    fn run_block(&mut self) {
        let mut out = Vec::new();
        let banned = self.interp.wse_forbids_manual();
        let step = self.interp.step(&mut out);
        let stage_alarm = self.stages.process(&mut out, crate::run::ends(&step));
        let produced = !out.is_empty();
        let read = (!matches!(step, Ok(Step::NeedInput))).then(|| {
            let (line, n) = self.interp.state.current_block();
            let state = &self.interp.state;
            let part = state.modal_part_changed().then(|| Box::new(state.modal_part()));
            (BlockState { line, n, modal: state.modal_state(), plane: state.active_plane() }, part)
        });
        // A path stage may release blocks it held together with the one just read (cutter
        // compensation: the block before a G40, or every block while it reads ahead): their
        // commands go ahead of this block's marker, so that they are shown with the block
        // they belong to (they showed the one read, a G40 while the machine cut compensated),
        // and each block's commands end at its own stop.
        let own = read.as_ref().map_or(0, |(b, _)| out.iter().position(|c| c.line == b.line).unwrap_or(out.len()));
        let mut out = out.into_iter();
        let earlier: Vec<Canon> = out.by_ref().take(own).collect();
        if !earlier.is_empty() {
            self.push_commands(earlier, None);
            self.cycle.blocks_mut().push(Item::BlockEnd);
        }
        let block = read.map(|(read, part)| {
            self.cycle.blocks_mut().push(Item::Block(self.executing.read(read, !produced, part)));
            read
        });
        let mine: Vec<Canon> = out.collect();
        let ends_own = !mine.is_empty();
        self.push_commands(mine, block);
        if self.interp.wse_forbids_manual() != banned {
            self.cycle.blocks_mut().push(Item::WseNoManual(!banned));
        }
        if let Some(alarm) = stage_alarm {
            // A path stage's program error: the program stops after what was released before it.
            self.cycle.blocks_mut().push(Item::Alarm(alarm));
            self.cycle.blocks_mut().end_reading();
            return;
        }
        match step {
            Ok(Step::Continue) => {
                // Single block stops after every NC block executed, those without commands too
                // (`State::single_block_stop`).
                if ends_own || self.interp.state.single_block_stop() {
                    self.cycle.blocks_mut().push(Item::BlockEnd);
                }
            }
            Ok(Step::NeedInput) => self.interp.finish(),
            Ok(Step::Ended) => self.cycle.blocks_mut().end_reading(),
            Err(alarm) => {
                self.cycle.blocks_mut().push(Item::Alarm(alarm));
                self.cycle.blocks_mut().end_reading();
            }
        }
    }

    /// The executor and the manual feeds take mechanism chain `chain` (Syntec G10 L5000).
    fn follow_chain(&mut self, chain: crate::machine::Chain) {
        self.exec.follow_chain(chain);
        // From the controller's own machine: it keeps the manual feed settings edited here.
        if chain != self.machine.chain() {
            if let Some(m) = self.machine.with_chain(chain) {
                self.machine = Arc::new(m);
            }
        }
    }

    fn carry_out(&mut self, kind: &CanonKind) {
        match kind {
            CanonKind::Dwell { seconds } => self.cycle.course_mut().dwell(self.exec.time() + seconds),
            // Auxiliary function lock: the M, S and T functions are not sent to the machine.
            CanonKind::ToolChange { .. } | CanonKind::Spindle { .. } if self.panel.aux_lock => {}
            CanonKind::ToolChange { .. } => {
                self.cycle.course_mut().dwell(self.exec.time() + self.machine.motion.tool_change_s)
            }
            // M01 with the optional stop switch off, as the machine reaches it: nothing to do.
            CanonKind::Stop { optional: true, .. } if !self.panel.optional_stop => {}
            CanonKind::Stop { optional, message } => {
                if let Some(m) = message {
                    self.events.push(Event::Message(m.clone()));
                }
                self.stop_kind = if *optional { ProgramStop::Optional } else { ProgramStop::Stop };
                self.cycle.course_mut().stop();
                self.set_state(RunState::Idle);
            }
            CanonKind::Print { text } => self.events.push(Event::Message(text.clone())),
            // The machine has reached the program's end: a part is done (FANUC No.6700#0 PCM = 0).
            // Manual absolute off: the shift of the interventions ends with the program.
            CanonKind::ProgramEnd { .. } => {
                self.interp.state.count_part();
                self.shift = None;
            }
            // The manual feeds use the mechanism the program switched to, from here on.
            CanonKind::Chain(chain) => self.follow_chain(*chain),
            CanonKind::Spindle { state, speed } => {
                self.spindle = match state {
                    SpindleState::Cw => *speed,
                    SpindleState::Ccw => -*speed,
                    SpindleState::Stop => 0.0,
                }
            }
            _ => {}
        }
    }

    /// How a program motion is fed: the panel's overrides, and single block stops at every end.
    fn program_feed(&self, m: &Motion) -> FeedContext {
        let exact_stop = m.context.exact_stop || self.panel.single_block;
        self.exec.feed_context(self.panel.feed_override, self.panel.rapid_override, exact_stop)
    }

    /// The segment of a program motion from where the last queued one ends.
    fn segment(&self, m: &Motion) -> Segment {
        self.exec.segment_within(m, self.program_feed(m), self.exec.axes())
    }

    /// A block without motion of its own is reached: the panel shows its line.
    fn show(&mut self, block: BlockState) {
        (self.exec.here.line, self.exec.here.n) = (block.line, block.n);
    }

    fn raise(&mut self, id: AlarmId, line: u32, n: Option<u32>) {
        let (code, message) = self.interp.config().dialect.describe(&id);
        let alarm = Alarm { code, message, line, n };
        self.remember_stop();
        self.alarms.push(alarm.clone());
        self.events.push(Event::Alarm(alarm));
        self.cycle.abort();
        self.set_state(RunState::Alarm);
    }

    fn set_state(&mut self, s: RunState) {
        if self.run_state != s {
            self.run_state = s;
            self.state_changed_at = self.exec.time();
            self.events.push(Event::State(s));
        }
    }
}
