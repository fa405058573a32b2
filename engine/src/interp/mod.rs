//! The custom macro B interpreter: executes blocks one at a time and emits canonical commands.
//!
//! [`Interpreter`] owns the loaded programs (immutable while running) and the [`State`] (all that
//! a block can change). Splitting them lets a block be borrowed from the programs while the state
//! is mutated, with no copying on the hot path.

mod calendar;
mod chain;
mod chamfer;
mod corner_blend;
mod cutting_point;
mod cycles;
mod dwo;
pub mod expr;
pub(crate) mod frames;
pub(crate) mod g10;
pub mod gcode;
mod haas_cycles;
mod manual_view;
pub mod mcode;
pub(crate) mod modes;
mod nc;
pub(crate) use nc::{MAX_G_CODES, MAX_M_CODES, MAX_WORDS};
mod nurbs;
pub(crate) mod offsets;
mod plain;
mod plane;
pub(crate) mod program;
pub mod restart;
mod singular;
mod skip;
mod smoothing;
mod table_crc;
mod tcp;
pub mod unbuilt;
pub(crate) mod vars;
mod wse;

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, Pos};
use crate::dialect::Dialect;
use crate::lang::{Block, BlockKind, Output, PrintItem};
use crate::machine::{MachineConfig, MAX_AXES};
use expr::{eval, eval_typed, truth, ExprSettings, Value};
use gcode::GROUPS;
use gcode::{code, group};
pub use offsets::{
    tool_value_fits, tool_value_limit, work_value_fits, work_value_limit, Offsets, ToolOffset, MAX_G54_1,
    MAX_TOOL_OFFSETS,
};
pub use plane::TiltedPlane;
pub use skip::MachineView;
pub use vars::InterfaceSignals;

/// F, S, T, the tool in the spindle, H and D as they stand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalWords {
    /// Feed, mm/min (1/min under G93).
    pub f: f64,
    pub s: f64,
    /// The tool prepared (last T word) and the tool in the spindle.
    pub t: u32,
    pub spindle_tool: u32,
    /// Tool length and cutter radius offset numbers in force.
    pub h: u32,
    pub d: u32,
}

/// The modal state a panel shows: the G code of every group and the modal words. The
/// controller keeps one per block read ahead, so what it shows is the state of the block the
/// machine is executing, not the interpreter's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalState {
    /// The code in force per group (`gcode::display` names it).
    pub modes: [u16; GROUPS],
    pub words: ModalWords,
    /// The workpiece setting error set in force, G54.4 Pn's n (group 33; 0: G54.4 P0, none;
    /// the group's code alone does not tell, P0 being G54.4 too).
    pub wse_set: u8,
}

impl ModalState {
    pub fn modal(&self, group: usize) -> u16 {
        self.modes[group]
    }
}
pub(crate) use program::Loaded;
use program::Slot;
use std::collections::{BTreeMap, HashMap};

/// Number of local variables per level (`#1`–`#33`).
pub const LOCALS: usize = 33;
/// `#500`–`#999`.
pub const PERSISTENT: usize = 500;
/// `#100`–`#199`.
pub const COMMON: usize = 100;

const NO_AXIS: u8 = u8::MAX;

/// Macro call levels (G65/G66) that may nest, and calls of any kind in total.
pub const MAX_MACRO_LEVELS: usize = 5;
pub const MAX_NESTED_CALLS: usize = 15;

#[derive(Debug, Clone)]
pub struct Config {
    pub dialect: Dialect,
    /// The machine (its mechanism and limits compiled once), shared with the motion executor
    /// and the controller.
    pub machine: std::sync::Arc<crate::machine::Machine>,
    /// The block delete (optional block skip) switch: when on, `/` blocks are skipped.
    pub block_delete: bool,
    /// The optional stop switch: when on, M01 stops like M00.
    pub optional_stop: bool,
    /// "Pocket calculator" input (FANUC DPI): numbers without a point are mm/deg, not increments.
    pub pocket_calculator: bool,
    /// FANUC parameter NAT (ATAN/ASIN result ranges).
    pub nat: bool,
    /// Executed blocks after which the run stops with an alarm (endless loops, recursion).
    pub max_blocks: u64,
    /// Arc end-point radius tolerance, mm (FANUC No.3410).
    pub arc_tolerance: f64,
    /// FANUC No.5400#0 RIN: the G68 angle R follows G90/G91 (a G91 R is added to the active
    /// rotation) when true; R is always absolute when false.
    pub rotation_angle_incremental: bool,
    /// Run plain motion blocks through their fast path (`interp/plain.rs`). Off only to check
    /// that both paths agree.
    pub fast_paths: bool,
    /// The control is a FANUC 31i-A5 (not the 30i-A5): under tool centre point control a block
    /// may command at most five axes (TCP-05; PS5421, `docs/five-axis.md`). The model of the
    /// control, not a machine parameter.
    pub five_axes_per_block: bool,
    /// Refuse the functions fivex does not carry out (`unbuilt`). Always on in fivex (no
    /// command line, JSON or HTTP setting turns it off); off only in the tests of the mode
    /// interlocks that belong to those functions (`engine/tests/it/modes.rs`), so that their rules
    /// stay checked until the functions are built.
    pub refuse_unbuilt: bool,
    /// What this interpreter tells the path stages it feeds that the commands do not carry
    /// (`crate::stage::Link`): where cutter compensation started.
    pub stages: crate::stage::Link,
    /// What is clamped on the table: the boxes a G31 probe touches (`interp::skip`).
    pub workpiece: std::sync::Arc<crate::workpiece::Workpiece>,
}

impl Config {
    pub fn new(machine: impl Into<std::sync::Arc<crate::machine::Machine>>, dialect: Dialect) -> Config {
        Config {
            dialect,
            machine: machine.into(),
            block_delete: false,
            optional_stop: false,
            pocket_calculator: false,
            nat: false,
            max_blocks: 50_000_000,
            arc_tolerance: 0.02,
            rotation_angle_incremental: true,
            fast_paths: true,
            five_axes_per_block: false,
            refuse_unbuilt: true,
            stages: Default::default(),
            workpiece: Default::default(),
        }
    }

    /// Change the machine's configuration: the mechanism and limits are compiled again (a
    /// machine shared with others is left as it is).
    pub fn edit_machine(&mut self, edit: impl FnOnce(&mut MachineConfig)) {
        let mut config = self.machine.config().clone();
        edit(&mut config);
        self.machine = std::sync::Arc::new(crate::machine::Machine::new(config));
    }
}

/// What one call of [`Interpreter::step`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// A block was executed; more follow.
    Continue,
    /// The program ended (M02/M30, or the end of the main program).
    Ended,
    /// Only while programs are still arriving ([`Interpreter::new_incremental`]): the next
    /// block needs blocks that have not arrived yet. Nothing was executed; push a part (or
    /// finish) and step again.
    NeedInput,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CallKind {
    Main,
    /// M98: same local level as the caller.
    Sub,
    /// G65/G66/G66.1: a new local level.
    Macro,
}

#[derive(Debug, Clone)]
struct CallFrame {
    prog: usize,
    pc: usize,
    kind: CallKind,
    /// Further repetitions after this one (L of M98/G65).
    repeats: u32,
    /// Where each repetition starts: 0, or a Haas M97's block N<P>.
    start: usize,
    /// The arguments a G65 repetition starts from again.
    args: Option<Box<vars::Locals>>,
    /// O number of the program (for #4115).
    number: u32,
    /// Syntec: the G66 ([`ModalCall::serial`]) whose shared local variables this call runs on,
    /// kept back in it when the call returns.
    modal: Option<u32>,
}

/// An active G66/G66.1.
#[derive(Debug, Clone)]
struct ModalCall {
    /// true for G66.1 (every block is a call), false for G66 (after every move).
    every_block: bool,
    prog: usize,
    count: u32,
    args: Box<vars::Locals>,
    /// Local level the call was specified at; blocks of deeper levels do not trigger it.
    level: usize,
    /// Syntec: the local variables its calls share from G66 to G67 (the Syntec MACRO handbook
    /// §2.3, §5.1: "从 `G66` 到 `G67` 期间共用"), the arguments at first; FANUC gives each call
    /// fresh ones from `args`.
    shared: Box<vars::Locals>,
    /// Tells this G66 from one given later at the same place (a call's frame names it).
    serial: u32,
}

/// Data of the active canned cycle (group 09), kept between blocks.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct CycleData {
    /// R point and hole bottom on the drilling axis, absolute programming coordinates.
    r: f64,
    z: f64,
    /// The bottom's distance from R (`z - r`): a G91 block with a new R and no Z keeps it.
    depth: f64,
    q: f64,
    p: f64,
    /// Whether an R word was given since the cycle started.
    r_set: bool,
    /// Whether the hole bottom (the drilling axis's word) was given since the cycle started.
    z_set: bool,
    /// The tool length offset vector a G43/G44/G49 or H of the cycle block selected, due at the
    /// move to point R (the positioning over the hole runs with the length before the block).
    length_due: Option<Pos>,
    /// The drilling-axis level when the cycle started (G98 returns here).
    initial: f64,
}

/// A block as the motions of a move held across blocks name it: its line, sequence number and
/// F (`State::as_block`).
pub(super) type BlockTag = (u32, Option<u32>, f64);

/// Everything a block can change.
#[derive(Debug, Clone)]
pub struct State {
    cfg: Config,
    expr: ExprSettings,
    frames: Vec<CallFrame>,
    locals: Vec<vars::Locals>,
    common: Box<[Value; COMMON]>,
    /// Syntec: the types of #100–#199 (`vars::Types`).
    common_types: vars::Types<2>,
    persistent: Box<[Value; PERSISTENT]>,
    /// The optional extended common variables, non-vacant ones only: #100000–#199999 (like
    /// #100–#199) and #500000–#999999 (retained like #500–#999). Few programs use more than a
    /// handful of the 600,000, so they are kept sparse.
    extended: BTreeMap<u32, f64>,
    /// Modal G codes per group, ×10.
    modes: [u16; GROUPS],
    /// P of G54.1.
    wcs_p: u16,
    f: f64,
    s: f64,
    /// Last T word (the tool prepared) and the tool in the spindle.
    t: u32,
    tool_in_spindle: u32,
    h: u32,
    d: u32,
    /// The offset value of D in effect: read from the offset memory when a D is given or
    /// compensation starts up, so a G10 (or `#13001…`, the API) to the offset in use waits for
    /// the next (FANUC No.5001#4 EVR = 0), as the length waits for the next H.
    radius: f64,
    e: f64,
    last_m: u32,
    /// G09 in the block being executed: its motions stop at their end.
    exact_stop: bool,
    /// The last G31's result (`#5061…`, Haas M78/M79).
    skip: skip::Skip,
    /// Where the real axes are beside the program's (the controller's locks).
    machine_view: skip::MachineView,
    last_n: u32,
    spindle: crate::canon::SpindleState,
    pub offsets: Offsets,
    /// Workpiece setting error data (G54.4), No.00 COMMON and No.01…07.
    pub setting_errors: crate::wse::SettingErrors,
    /// The G54.4 set in effect.
    wse: Option<wse::Active>,
    /// The compensation of the tip move being made, from `wse_compensate` to `follow_motion`.
    wse_between: Option<crate::canon::Compensation>,
    /// Look-ahead (FANUC AI contour control) is on: from power-on unless it needs G05.1 Q1
    /// (`motion.look_ahead_by_command`), then G05.1 Q1 / Q0. A reset keeps it, as it keeps
    /// the modal G codes (CLR = 0). Each motion carries it to the executor
    /// (`Motion::no_look_ahead`), which plans cutting feed without it through the filter
    /// after interpolation (`docs/motion.md`, "Without look-ahead").
    look_ahead: bool,
    /// Haas G103 P: the look-ahead of the motions limited to this many blocks (0: not limited).
    /// A reset and the program end (M02/M30) end it (`docs/dialects.md`, "Haas cycles").
    block_limit: u8,
    /// Haas G150: the last R plane given to it (a G150 without R uses it, as the manual says).
    pocket_r: Option<f64>,
    /// Programming coordinates of the current point (the last block's end point), after the
    /// programming transforms (G51.1, G51, G68): the workpiece coordinates of the tool.
    pos: Pos,
    /// Programming transforms and the programmed (untransformed) current point.
    xf: frames::Transforms,
    /// G52 local offset and G92 shift, added to the work offset.
    local: Pos,
    shift: Pos,
    /// Tool length offset vector currently applied.
    tool_vec: Pos,
    /// FANUC/Syntec: a G28/G30/G53 moving Z in G43/G44 cancelled the tool length offset
    /// vector; the mode and H stay (`State::cancel_length_vector`).
    length_cancelled: bool,
    cycle: CycleData,
    /// The intermediate point of the last G28, for G29.
    last_g28_mid: Pos,
    /// The modal macro calls in force (G66/G66.1), in the order given: they nest, and each
    /// G67 cancels the latest ([`State::modal_call_here`]).
    modal_calls: Vec<ModalCall>,
    /// The serial number of the last G66/G66.1 given (`ModalCall::serial`).
    modal_serial: u32,
    /// What the modal groups do not hold about the 5-axis modes (nesting, definition sequences).
    five: modes::FiveAxisModes,
    /// The machine's mechanism (`None` when the kinematics refuses it: no 5-axis function).
    kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
    /// The mechanism G54.4's tool direction compensation computes with (`wse::compensation_kinematics`).
    wse_kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
    /// Tool centre point control in force.
    tcp: Option<tcp::Tcp>,
    /// 5-axis cutter compensation in the table coordinate system without TCP (`table_crc`).
    table_crc: Option<table_crc::TableCrc>,
    /// A NURBS curve (G06.2) being given, from its G06.2 block to its last knot.
    nurbs: Option<Box<nurbs::Builder>>,
    /// Nano smoothing (G05.1 Q3), Syntec STCP or HPCC (G05 P10000) in force, with the points it
    /// holds.
    smoothing: Option<Box<smoothing::Smoothing>>,
    /// Haas G187 rounding corners, with the move it holds (`corner_blend`).
    blend: Option<Box<corner_blend::CornerBlend>>,
    /// A G01 block with `,C`/`,R` whose move waits for the next block (`chamfer`).
    corner: Option<Box<chamfer::HeldCorner>>,
    /// The machine position while X/Y/Z follow a tool tip (TCP, tilted working plane): not the
    /// programmed point plus offsets then.
    follow_machine: Option<Pos>,
    /// The tilted working plane's feature coordinate system in the workpiece system.
    plane: Option<crate::geom::Rigid>,
    /// A G68.2 P2/P3 definition in progress.
    definition: plane::Definition,
    /// Haas DWO (G254): the linear axes (bits X 0, Y 1, Z 2) not yet commanded since G254;
    /// a cutting move waits for all three (`dwo`).
    dwo_due: u8,
    /// Simulated time, seconds, advanced by the executor.
    clock_s: f64,
    /// The host's local time against `clock_s` (`#3011`/`#3012`; none: both read 0).
    wall_clock: Option<calendar::WallClock>,
    /// #3001 / #3002 are the clock minus these (they are writable).
    timer_ms_base: f64,
    timer_h_base: f64,
    /// Haas #3020–#3025 (`vars.rs`): the seconds of automatic operation and of cutting feed
    /// counted as the controller counts its operating and cutting time (`Controller::times`;
    /// in `fivex run` the whole run operates).
    operating_s: f64,
    cutting_s: f64,
    /// #3021 / #3022 are the counters minus these (they are writable).
    cycle_timer_base: f64,
    feed_timer_base: f64,
    /// Haas part timers: the operating time when the present part began, and the operating
    /// times of the last complete part and of the one before it.
    part_start_s: f64,
    last_part_s: f64,
    previous_part_s: f64,
    /// Parts completed whose time is not yet closed (`count_operation`).
    parts_to_time: u32,
    /// The panel's single block and dry run switches as the controller last gave them (Haas
    /// #3030, #3031; block delete and optional stop are in `cfg`).
    single_block: bool,
    dry_run: bool,
    sys3003: f64,
    /// The custom macro interface signals (#1000–#1035 in, #1100–#1135 out).
    pub signals: InterfaceSignals,
    sys3004: f64,
    parts_done: f64,
    parts_required: f64,
    blocks: u64,
    /// Where the commands of the block being executed begin in the step's output: before them
    /// are what the block released of the ones before it (a smoothing or corner rounding run).
    block_out: usize,
    ended: bool,
    /// The program runs in MDI (`Interpreter::set_mdi_operation`): its text may end without M02/M30.
    mdi: bool,
    /// The program has moved since its start (`Interpreter::load`): a G20/G21 that switches the
    /// unit from here on is reported (`unit_switch`).
    moved: bool,
    /// The line and sequence number of a G20/G21 that switched the unit after the program had
    /// moved, until the next motion carries its notice (`BlockNotice::UnitSwitched`).
    unit_switch: Option<(u32, Option<u32>)>,
    /// A cutter compensation vector may stand at the current point: the last block that moved
    /// did so in a mode of `code::COMPENSATED_BY_STAGES` (until a move in G40 or a reset). The
    /// current position variables are then not built (`AlarmId::PositionInCompensation`).
    cutter_vector: bool,
    /// Axis index per address letter A..Z (`NO_AXIS` when the machine has no such axis).
    axis_by_letter: [u8; 26],
    /// Line and N of the block being executed, for alarms.
    line: u32,
    n: Option<u32>,
    /// The block executed last may have changed the state of [`ModalPart`] beyond the motion
    /// group and F (`State::moves_only`): a controller keeps a copy of it.
    modal_part_changed: bool,
    /// The block executed last is an NC block that ends in a single-block stop although it
    /// made no command (`G90`, `F500`, `G92 …`, `G80`; `State::single_block_stop`).
    single_block_stop: bool,
}

/// What a block leaves in force for the blocks after it, besides data (variables, offsets,
/// counters): modal codes and words, the programming transforms, G52/G92 shifts, the tool
/// length vector, canned cycle data, the 5-axis modes (F is the executed block's modal state's).
/// The controller keeps one per block read
/// ahead that changed it, so that a reset leaves the state of the block the machine executed,
/// not the read-ahead's ([`State::restore_executed`], `docs/motion.md`, "Reading ahead").
#[derive(Debug, Clone)]
pub struct ModalPart {
    modes: [u16; GROUPS],
    wcs_p: u16,
    s: f64,
    t: u32,
    tool_in_spindle: u32,
    h: u32,
    d: u32,
    radius: f64,
    e: f64,
    spindle: crate::canon::SpindleState,
    look_ahead: bool,
    pocket_r: Option<f64>,
    expr: ExprSettings,
    pos: Pos,
    xf: frames::Transforms,
    local: Pos,
    shift: Pos,
    tool_vec: Pos,
    length_cancelled: bool,
    cycle: CycleData,
    last_g28_mid: Pos,
    five: modes::FiveAxisModes,
    tcp: Option<tcp::Tcp>,
    table_crc: Option<table_crc::TableCrc>,
    follow_machine: Option<Pos>,
    plane: Option<crate::geom::Rigid>,
    definition: plane::Definition,
    dwo_due: u8,
    wse: Option<wse::Active>,
}

/// A loaded set of programs and the state that runs them.
#[derive(Debug, Clone)]
pub struct Interpreter {
    progs: Vec<Slot>,
    by_number: HashMap<u32, usize>,
    pub state: State,
    /// Every program has arrived (always, unless built with `new_incremental`).
    complete: bool,
    /// What stopped the run, once `step` has returned an alarm: the identity behind its dialect
    /// code (several causes share FANUC's PS0078; a check tells them apart by this).
    stopped_by: Option<AlarmId>,
}

impl Interpreter {
    /// Prepare to run `file`'s first program; its other programs can be called.
    pub fn new(file: crate::lang::File, cfg: Config) -> Interpreter {
        let progs: Vec<Slot> = file.programs.into_iter().map(|p| Loaded::new(p).into()).collect();
        let mut by_number = HashMap::new();
        for (i, p) in progs.iter().enumerate() {
            if let Some(n) = p.number() {
                by_number.entry(n).or_insert(i);
            }
        }
        let state = State::new(cfg);
        let mut interp = Interpreter { progs, by_number, state, complete: true, stopped_by: None };
        interp.start_main();
        if interp.progs.is_empty() {
            interp.state.ended = true;
        }
        interp
    }

    /// An interpreter whose file arrives in parts (`lang::parse_part`, in order, then
    /// [`Interpreter::finish`]), so that running can start before the whole file is parsed. It
    /// runs plain blocks as they arrive and answers [`Step::NeedInput`] before any block whose
    /// jump, loop or call target may lie in a part that has not arrived; the outcome is the same
    /// as with [`Interpreter::new`] on the whole file (`engine/tests/it/incremental.rs`).
    pub fn new_incremental(cfg: Config) -> Interpreter {
        Interpreter {
            progs: Vec::new(),
            by_number: HashMap::new(),
            state: State::new(cfg),
            complete: false,
            stopped_by: None,
        }
    }

    /// The next part of the file.
    pub fn push_part(&mut self, part: crate::lang::File) {
        let mut programs = part.programs.into_iter().peekable();
        // A part starts inside the previous part's last program.
        if let Some(first) = programs.next_if(|p| p.number.is_none()) {
            match self.progs.last_mut() {
                Some(last) if !last.finished => last.extend(first.blocks),
                _ => self.progs.push(Loaded::new_open(first).into()),
            }
        }
        let mut carried = Vec::new();
        if programs.peek().is_some() {
            // Comments before the first O number were a header, not a program; the Syntec
            // dialect's refusals among them go on to the program (as `lang::parse_part` does).
            if self.progs.len() == 1 && self.state.frames.is_empty() && self.progs[0].is_header() {
                let header = self.progs.remove(0);
                carried = header.blocks().filter(|b| matches!(b.kind, BlockKind::SyntecOnly(_))).cloned().collect();
            }
            if let Some(last) = self.progs.last_mut() {
                last.finish();
            }
        }
        for mut p in programs {
            p.blocks.splice(0..0, std::mem::take(&mut carried));
            if let Some(last) = self.progs.last_mut() {
                last.finish();
            }
            if let Some(n) = p.number {
                self.by_number.entry(n).or_insert(self.progs.len());
            }
            self.progs.push(Loaded::new_open(p).into());
        }
        // A first program of comments only may still turn out to be a header: wait.
        let maybe_header = self.progs.len() == 1 && self.progs[0].is_header();
        if self.state.frames.is_empty() && !self.progs.is_empty() && !maybe_header {
            self.start_main();
        }
    }

    /// The whole file has arrived.
    pub fn finish(&mut self) {
        self.complete = true;
        for p in self.progs.iter_mut().filter(|p| p.is_loaded()) {
            p.finish();
        }
        if self.state.frames.is_empty() {
            self.start_main();
        }
        if self.progs.is_empty() {
            self.state.ended = true;
        }
    }

    fn start_main(&mut self) {
        if let Some(first) = self.progs.first() {
            let mut main = CallFrame::main();
            main.number = first.number().unwrap_or(0);
            // Syntec: a `%@MACRO` line anywhere in the file refuses it before anything of it
            // runs (verification audit §6: one before a later program was never reached, and
            // the file ran): the run starts at that line, which raises the refusal.
            if self.state.cfg.dialect == Dialect::Syntec {
                let mut loaded = self.progs.iter().enumerate().filter(|(_, p)| p.is_loaded());
                if let Some((prog, pc)) = loaded.find_map(|(i, p)| p.macro_format.map(|pc| (i, pc))) {
                    main.prog = prog;
                    main.pc = pc as usize;
                    main.number = self.progs[prog].number().unwrap_or(0);
                }
            }
            self.state.frames.push(main);
        }
    }

    /// Load a new file to run from its first program, keeping the state (modal codes,
    /// offsets, variables, position): what cycle start of a newly selected program does.
    pub fn load(&mut self, file: crate::lang::File) {
        let fresh = Interpreter::new(file, self.state.cfg.clone());
        self.progs = fresh.progs;
        self.by_number = fresh.by_number;
        self.complete = true;
        self.reset();
        if self.state.cfg.dialect == Dialect::Syntec {
            // #100–#199 are the main program's local variables on a Syntec control (vacant at
            // each start; the Syntec MACRO syntax handbook, §2.1, §2.3), fivex's common ones,
            // which keep their value: a run must not read the last run's.
            *self.state.common = [None; COMMON];
            self.state.common_types = vars::Types::default();
        }
        self.state.ended = self.progs.is_empty();
        // Memory operation unless the controller says the text is an MDI one (`set_mdi_operation`).
        self.state.mdi = false;
        self.state.moved = false;
        self.state.unit_switch = None;
        self.start_main();
    }

    /// [`Interpreter::load`] `source`'s main program; its stored programs are parsed when a
    /// call first reaches them. The same run as loading one text of them all, each program
    /// cut to its first.
    pub fn load_source(&mut self, source: &crate::lang::Source) {
        let mut file = crate::lang::parse_file(&source.main);
        file.programs.truncate(1);
        self.load(file);
        if self.progs.is_empty() {
            // A main text of no program runs nothing and calls nothing.
            return;
        }
        for stored in &source.library {
            if let std::collections::hash_map::Entry::Vacant(e) = self.by_number.entry(stored.number) {
                e.insert(self.progs.len());
                self.progs.push(Slot::stored(stored.clone()));
            }
        }
    }

    /// Reset: the program stops where it is and cannot continue; local variables, call
    /// frames and the modal macro call are dropped (modal G codes, offsets, common variables
    /// and the position stay, FANUC No.3402 CLR = 0; but G40, and G80 below).
    pub fn reset(&mut self) {
        let st = &mut self.state;
        st.frames.clear();
        st.locals.truncate(1);
        st.locals[0] = vars::Locals::default();
        st.modal_calls.clear();
        // What the modal display and #4012 show follows: no call is left (it showed G66).
        st.modes[group::MODAL_CALL] = code::G67;
        st.wse_between = None;
        st.block_limit = 0;
        st.nurbs = None;
        st.smoothing_reset();
        st.blend_end();
        st.corner = None;
        st.ended = true;
        st.cfg.stages.clear();
        // Modal codes survive a reset (No.3402 CLR = 0) except cutter compensation: a reset
        // puts group 07 in G40 (CRC-44, TV-30; the manual lists the 5-axis codes, fivex ends
        // G41/G42 the same way, as their offset vector does not survive a reset either).
        st.modes[group::CUTTER_COMP] = code::G40;
        // A reset ends NURBS interpolation mode too (*decision*: the Mitsubishi M700 manual
        // cancels it at a reset; FANUC's pages are silent): left in G06.2, where only a curve or
        // another group-01 code may come (`nurbs::refuse_in_nurbs_mode`), every program after it
        // would stop at its first block (`G90 G17 G40 …`, PS5116), reset after reset. Group 01
        // goes to its power-on code.
        if st.modes[group::MOTION] == code::G06_2 {
            st.modes[group::MOTION] = gcode::initial_modes()[group::MOTION];
        }
        // A reset ends the canned cycle (G80; *decision*, `docs/conventions.md`, "Reset"): left in
        // force, the next MDI or program block with X/Y (`X50. Y5.`) drilled a hole at once. No
        // FANUC page at hand tells whether a reset in the reset state (CLR = 0) keeps it.
        st.modes[group::CYCLE] = code::G80;
        // As G80 does: the next cycle takes none of the old one's data (its hole bottom).
        st.cycle = CycleData::default();
        st.cutter_vector = false;
        st.table_crc_end();
        st.five.compensation_ended();
        let after_reset = st.cfg.machine.five_axis.plane_after_reset;
        if st.plane_active() && after_reset == crate::machine::PlaneAfterReset::Cancelled {
            st.end_plane();
            st.five.plane_ended();
        }
        st.wse_reset();
        st.haas_end_five_axis();
        st.haas_cancel_length_comp();
    }

    /// The machine was moved outside the program (jog, handle, reference return): the
    /// current point follows it (FANUC manual absolute on).
    pub fn moved_to(&mut self, machine: &Pos) {
        let st = &mut self.state;
        let before = st.machine_position();
        if before.iter().zip(machine).any(|(a, b)| (a - b).abs() > 1e-9) {
            // Moved by hand inside a NURBS curve: it no longer starts where the tool stands.
            if let Some(b) = st.nurbs.as_deref_mut() {
                b.moved_by_hand = true;
            }
        }
        if st.plane_active() {
            st.plane_moved_to(*machine);
        } else if st.tcp_active() {
            st.tcp_moved_to(*machine);
        } else if st.table_crc_active() {
            st.table_crc_moved_to(*machine);
        } else if st.wse_follows() {
            st.wse_moved_to(*machine);
        } else {
            st.pos = st.machine_to_program(machine);
            st.sync_programmed();
        }
    }

    /// The panel's block delete (`/` blocks skipped) and optional stop (M01 stops) switches.
    pub fn set_switches(&mut self, block_delete: bool, optional_stop: bool) {
        self.state.cfg.block_delete = block_delete;
        self.state.cfg.optional_stop = optional_stop;
    }

    /// The program loaded runs in MDI, not from memory (set after each load): on a FANUC control
    /// an MDI program ends after its last block, where a memory one that reaches the end of its
    /// text without M02/M30 stops with PS5010 END OF RECORD (`State::step`).
    pub fn set_mdi_operation(&mut self, mdi: bool) {
        self.state.mdi = mdi;
    }

    /// Execute the next block; its canonical commands are appended to `out`.
    pub fn step(&mut self, out: &mut Vec<Canon>) -> Result<Step, Alarm> {
        let st = &mut self.state;
        if st.ended {
            return Ok(Step::Ended);
        }
        if !self.complete && st.needs_input(&self.progs) {
            return Ok(Step::NeedInput);
        }
        let before = out.len();
        let mut result = st.step(&self.progs, &self.by_number, out);
        // What the end of record released (`State::step`) runs as well: it is checked too.
        if matches!(&result, Ok(_) | Err(AlarmId::EndOfRecord)) && out[before..].iter().any(|c| !finite_motion(c)) {
            // Offsets or setting data of absurd size (1e30, a NaN of the kinematics) must not
            // turn into a move to nowhere that "completes": the block alarms instead.
            out.truncate(before);
            result = Err(AlarmId::FloatOverflow);
        }
        match result {
            Ok(step) => {
                let own = st.block_out.max(before) - before;
                st.mark_unit_switch(&mut out[before..], own);
                Ok(step)
            }
            Err(id) => {
                // A block refused with an alarm does nothing: none of its own commands run, even
                // those it made before the alarm was found (a call found missing after the
                // block's tool length change). What it released of the blocks before it runs.
                // Only an alarm about the block's own move comes after it (`follows_motion`).
                if !id.follows_motion() {
                    out.truncate(st.block_out.max(before));
                }
                st.ended = true;
                let (code, message) = st.cfg.dialect.describe(&id);
                let alarm = Alarm { code, message, line: st.line, n: st.n };
                self.stopped_by = Some(id);
                Err(alarm)
            }
        }
    }

    /// Run to the end, handing every canonical command to `sink`.
    pub fn run(&mut self, mut sink: impl FnMut(Canon)) -> Result<(), Alarm> {
        let mut out = Vec::with_capacity(16);
        loop {
            let step = self.step(&mut out);
            for c in out.drain(..) {
                sink(c);
            }
            match step? {
                Step::Ended => return Ok(()),
                Step::NeedInput => self.finish(),
                Step::Continue => {}
            }
        }
    }

    /// The identity of the alarm `step` stopped with, if it did.
    pub fn stopped_by(&self) -> Option<&AlarmId> {
        self.stopped_by.as_ref()
    }

    /// Executed blocks so far.
    pub fn blocks(&self) -> u64 {
        self.state.blocks
    }

    pub fn config(&self) -> &Config {
        &self.state.cfg
    }

    /// Where the real axes stand beside the program's machine coordinates (the controller's
    /// machine lock and Z-axis neglect): a skip move's probe moves with the real axes.
    pub fn set_machine_view(&mut self, view: MachineView) {
        self.state.machine_view = view;
    }

    /// Put `workpiece` on the table (the boxes a G31 probe touches, `crate::workpiece`).
    pub fn set_workpiece(&mut self, workpiece: std::sync::Arc<crate::workpiece::Workpiece>) {
        self.state.cfg.workpiece = workpiece;
    }

    /// The machine's mechanism, compiled once from the configuration (`None` when the
    /// kinematics refuses it); the controller, a run and the preview share it.
    pub fn kinematics(&self) -> Option<&std::sync::Arc<crate::kin::Kinematics>> {
        self.state.kinematics.as_ref()
    }
}

impl State {
    /// After a block ran: the first motion after a G20/G21 that switched the unit mid-program
    /// carries its notice (a switch nothing moves after changes no motion), and whether the
    /// program has moved is kept. `out` holds the step's commands; those before `own` are what
    /// the block released of the blocks before it (a smoothing or corner rounding run): they
    /// count as moving but do not carry the notice.
    fn mark_unit_switch(&mut self, out: &mut [Canon], own: usize) {
        for (i, c) in out.iter_mut().enumerate() {
            let CanonKind::Motion(m) = &mut c.kind else { continue };
            self.moved = true;
            if let Some((line, n)) = self.unit_switch.filter(|_| i >= own) {
                if m.notice.is_none() {
                    m.notice = Some(crate::notice::BlockNotice::UnitSwitched { line, n });
                    self.unit_switch = None;
                }
            }
        }
    }

    fn new(cfg: Config) -> State {
        let syntec_division = cfg.dialect == Dialect::Syntec;
        let syntec_pow = cfg.dialect == Dialect::Syntec;
        let expr = ExprSettings { nat: cfg.nat, increment: 0.001, round_steps: 1.0, syntec_division, syntec_pow };
        let mut axis_by_letter = [NO_AXIS; 26];
        for (i, axis) in cfg.machine.axes.iter().enumerate() {
            if axis.name.is_ascii_uppercase() {
                axis_by_letter[(axis.name as u8 - b'A') as usize] = i as u8;
            }
        }
        let kinematics = cfg.machine.kinematics().cloned();
        let wse_kinematics = wse::compensation_kinematics(&cfg.machine, kinematics.as_ref());
        State {
            axis_by_letter,
            expr,
            frames: Vec::new(),
            locals: vec![vars::Locals::default()],
            common: Box::new([None; COMMON]),
            common_types: vars::Types::default(),
            persistent: Box::new([None; PERSISTENT]),
            extended: BTreeMap::new(),
            modes: {
                let mut modes = gcode::initial_modes();
                if cfg.machine.motion.power_on_inch {
                    modes[group::UNITS] = code::G20;
                }
                modes
            },
            wcs_p: 0,
            f: 0.0,
            s: 0.0,
            t: 0,
            tool_in_spindle: 0,
            h: 0,
            d: 0,
            radius: 0.0,
            e: 0.0,
            last_m: 0,
            exact_stop: false,
            skip: Default::default(),
            machine_view: Default::default(),
            last_n: 0,
            spindle: crate::canon::SpindleState::Stop,
            offsets: Offsets::default(),
            setting_errors: crate::wse::SettingErrors::default(),
            wse: None,
            wse_between: None,
            look_ahead: !cfg.machine.motion.look_ahead_by_command,
            block_limit: 0,
            pocket_r: None,
            pos: [0.0; MAX_AXES],
            xf: frames::Transforms::default(),
            local: [0.0; MAX_AXES],
            shift: [0.0; MAX_AXES],
            tool_vec: [0.0; MAX_AXES],
            length_cancelled: false,
            cycle: CycleData::default(),
            last_g28_mid: [0.0; MAX_AXES],
            modal_calls: Vec::new(),
            modal_serial: 0,
            five: modes::FiveAxisModes::default(),
            kinematics,
            wse_kinematics,
            tcp: None,
            table_crc: None,
            nurbs: None,
            smoothing: None,
            blend: None,
            corner: None,
            follow_machine: None,
            plane: None,
            definition: plane::Definition::default(),
            dwo_due: 0,
            clock_s: 0.0,
            wall_clock: None,
            timer_ms_base: 0.0,
            timer_h_base: 0.0,
            operating_s: 0.0,
            cutting_s: 0.0,
            cycle_timer_base: 0.0,
            feed_timer_base: 0.0,
            part_start_s: 0.0,
            last_part_s: 0.0,
            previous_part_s: 0.0,
            parts_to_time: 0,
            single_block: false,
            dry_run: false,
            sys3003: 0.0,
            signals: InterfaceSignals::default(),
            sys3004: 0.0,
            parts_done: 0.0,
            parts_required: 0.0,
            blocks: 0,
            block_out: 0,
            ended: false,
            mdi: false,
            moved: false,
            unit_switch: None,
            cutter_vector: false,
            line: 0,
            n: None,
            modal_part_changed: false,
            single_block_stop: false,
            cfg,
        }
    }

    /// The state a block leaves in force besides data ([`ModalPart`]).
    pub fn modal_part(&self) -> ModalPart {
        ModalPart {
            modes: self.modes,
            wcs_p: self.wcs_p,
            s: self.s,
            t: self.t,
            tool_in_spindle: self.tool_in_spindle,
            h: self.h,
            d: self.d,
            radius: self.radius,
            e: self.e,
            spindle: self.spindle,
            look_ahead: self.look_ahead,
            pocket_r: self.pocket_r,
            expr: self.expr,
            pos: self.pos,
            xf: self.xf.clone(),
            local: self.local,
            shift: self.shift,
            tool_vec: self.tool_vec,
            length_cancelled: self.length_cancelled,
            cycle: self.cycle,
            last_g28_mid: self.last_g28_mid,
            five: self.five,
            tcp: self.tcp.clone(),
            table_crc: self.table_crc.clone(),
            follow_machine: self.follow_machine,
            plane: self.plane,
            definition: self.definition,
            dwo_due: self.dwo_due,
            wse: self.wse,
        }
    }

    /// The block executed last may have changed [`ModalPart`] beyond the motion group and F.
    pub fn modal_part_changed(&self) -> bool {
        self.modal_part_changed
    }

    /// The block executed last is an NC block that made no command and still ends in a stop
    /// in single block, as every executed NC block does on the control (a block of only `G90`,
    /// `F500`, `G92 …`, `G10 …`, `G52 …`, `G43 H1`, `G80`). Not: a block with nothing but N or
    /// a comment, a macro statement (FANUC No.6000#5 SBM = 0), a subprogram or macro call or
    /// return with nothing else (as a macro statement; the blocks it leads to stop), nor under
    /// cutter compensation, where the path stage places the block ends (`docs/motion.md`,
    /// `panel.single_block`). A block that made commands ends in its stop anyway.
    pub fn single_block_stop(&self) -> bool {
        self.single_block_stop
    }

    /// Before a reset with blocks read ahead of the machine: the state in force becomes the
    /// executed block's again — `part` (left by it, or by the last block before it that changed
    /// more than the motion group and F) with the motion group and F of `executed`, the
    /// executed block's modal state. Data stays as read: variables (macro statements run when
    /// read, as in FANUC's buffering), offsets, counters. The current point is set again from
    /// the machine afterwards ([`Interpreter::moved_to`]).
    pub fn restore_executed(&mut self, part: &ModalPart, executed: &ModalState) {
        // Every field named (no `..`): a field added to `ModalPart` must be restored here.
        let ModalPart {
            modes,
            wcs_p,
            s,
            t,
            tool_in_spindle,
            h,
            d,
            radius,
            e,
            spindle,
            look_ahead,
            pocket_r,
            expr,
            pos,
            xf,
            local,
            shift,
            tool_vec,
            length_cancelled,
            cycle,
            last_g28_mid,
            five,
            tcp,
            table_crc,
            follow_machine,
            plane,
            definition,
            dwo_due,
            wse,
        } = part.clone();
        (self.modes, self.wcs_p, self.s, self.t, self.tool_in_spindle) = (modes, wcs_p, s, t, tool_in_spindle);
        (self.h, self.d, self.radius, self.e, self.spindle, self.look_ahead) = (h, d, radius, e, spindle, look_ahead);
        (self.pocket_r, self.expr, self.pos, self.xf, self.local) = (pocket_r, expr, pos, xf, local);
        (self.shift, self.tool_vec, self.length_cancelled, self.cycle) = (shift, tool_vec, length_cancelled, cycle);
        (self.last_g28_mid, self.five, self.tcp, self.table_crc) = (last_g28_mid, five, tcp, table_crc);
        (self.follow_machine, self.plane, self.definition) = (follow_machine, plane, definition);
        (self.dwo_due, self.wse) = (dwo_due, wse);
        // The blocks after `part` that did not change it changed only these.
        self.modes[group::MOTION] = executed.modes[group::MOTION];
        self.f = executed.words.f;
    }

    /// The index of the axis an address letter names, if the machine has it.
    pub(super) fn axis_of(&self, letter: u8) -> Option<usize> {
        let i = *self.axis_by_letter.get(letter.wrapping_sub(b'A') as usize)?;
        (i != NO_AXIS).then_some(i as usize)
    }

    /// Line and sequence number of the block executed last.
    pub fn current_block(&self) -> (u32, Option<u32>) {
        (self.line, self.n)
    }

    /// Advance simulated time (the executor calls this as motion takes time).
    pub fn advance_time(&mut self, seconds: f64) {
        self.clock_s += seconds;
    }

    /// The host's local wall clock now (Unix seconds plus the UTC offset): `#3011`/`#3012` read
    /// it, running on with simulated time (`calendar`).
    pub fn set_wall_clock(&mut self, local_s: f64) {
        self.wall_clock = Some(calendar::WallClock { local_s, at_clock_s: self.clock_s });
    }

    /// The operator's reset: FANUC clears the common variables #100–#199 and #100000–#199999
    /// to vacant unless the machine keeps them (No.6001#6 CCV); the Haas NGC keeps them, and
    /// Syntec's are a program's locals, vacant at each start anyway.
    pub fn clear_commons_at_reset(&mut self) {
        if self.cfg.dialect == crate::Dialect::Fanuc && !self.cfg.machine.motion.commons_kept_at_reset {
            *self.common = [None; COMMON];
            self.extended.retain(|&n, _| !(100_000..=199_999).contains(&n));
        }
    }

    /// Persistent common variables `#500`–`#999`, to save between runs.
    pub fn persistent(&self) -> &[Value; PERSISTENT] {
        &self.persistent
    }

    pub fn load_persistent(&mut self, values: &[Value; PERSISTENT]) {
        *self.persistent = *values;
    }

    /// Every non-vacant variable a power cycle keeps, as (number, value): #500–#999, the
    /// extended #500000–#999999, and the retained system values — the hour timer #3002,
    /// the part counts #3901/#3902 (FANUC keeps them through power off) and FANUC's inch/metric
    /// mode #4006. A host saves these
    /// and hands them back with [`State::load_retained`] after a restart.
    pub fn retained_variables(&self) -> Vec<(u32, f64)> {
        let p = self.persistent.iter().enumerate().filter_map(|(i, v)| v.map(|x| (500 + i as u32, x)));
        let e = self.extended.range(500_000..=999_999).map(|(&n, &v)| (n, v));
        let system = [(3002, self.hour_timer()), (3901, self.parts_done), (3902, self.parts_required)];
        // FANUC: "When the power is turned on, the G code is the same as that held before the
        // power was turned off" (G20/G21, B-63944EN/02 §8.2): kept as its #4006, 20 or 21.
        let unit = (self.cfg.dialect == crate::Dialect::Fanuc)
            .then(|| (4006, if self.modes[group::UNITS] == code::G20 { 20.0 } else { 21.0 }));
        // Haas: #100–#199 and the NGC's own #10000… general purpose variables are kept too.
        let haas = self.cfg.dialect == crate::Dialect::Haas;
        let c = self.common.iter().enumerate().filter_map(|(i, v)| v.map(|x| (100 + i as u32, x)));
        let c = c.filter(|_| haas);
        let ngc = self.extended.range(10_000..=10_999).map(|(&n, &v)| (n, v)).filter(|_| haas);
        c.chain(p).chain(e).chain(ngc).chain(system.into_iter().filter(|&(_, v)| v != 0.0)).chain(unit).collect()
    }

    /// Count `operating_s` seconds of automatic operation, `cutting_s` of them along a cutting
    /// feed (Haas #3021–#3025), as the controller counts its operating and cutting time.
    /// The parts completed since the last call ([`State::count_part`]) close here, so that a
    /// part's time is all that was counted up to its end (the controller counts a tick's
    /// stretches after it carries out the M30 within it).
    pub fn count_operation(&mut self, operating_s: f64, cutting_s: f64) {
        self.operating_s += operating_s.max(0.0);
        self.cutting_s += cutting_s.max(0.0);
        for _ in 0..std::mem::take(&mut self.parts_to_time) {
            self.previous_part_s = self.last_part_s;
            self.last_part_s = self.operating_s - self.part_start_s;
            self.part_start_s = self.operating_s;
        }
    }

    /// The operation counters as kept through a power cycle (the controller's, loaded with
    /// its own): Haas #3021/#3022 go on from there.
    pub fn load_operation_times(&mut self, operating_s: f64, cutting_s: f64) {
        // The present part keeps the time it has run.
        self.part_start_s += operating_s - self.operating_s;
        self.operating_s = operating_s;
        self.cutting_s = cutting_s;
    }

    /// The panel's single block and dry run switches (Haas #3030, #3031), for the blocks read
    /// from now on.
    pub fn set_panel_switches(&mut self, single_block: bool, dry_run: bool) {
        self.single_block = single_block;
        self.dry_run = dry_run;
    }

    /// A program end (M02/M30) was carried out: one more part machined (#3901); the Haas part
    /// timers (#3023 present, #3024 last complete, #3025 previous part) move on at the next
    /// [`State::count_operation`], with the time counted up to the end.
    pub fn count_part(&mut self) {
        self.parts_done += 1.0;
        self.parts_to_time += 1;
    }

    /// The part count (#3901, parts machined) and the parts required (#3902).
    pub fn part_count(&self) -> (f64, f64) {
        (self.parts_done, self.parts_required)
    }

    /// Whether a power cycle keeps variable `n` ([`State::retained_variables`]).
    pub fn is_retained(n: u32) -> bool {
        matches!(n, 500..=999 | 500_000..=999_999 | 3002 | 3901 | 3902 | 4006)
    }

    /// Restore retained variables saved before a restart (numbers that are not retained are
    /// refused: `VariableOutOfRange`).
    pub fn load_retained(&mut self, values: &[(u32, Value)]) -> Result<(), AlarmId> {
        for &(n, value) in values {
            match n {
                500..=999 => self.persistent[n as usize - 500] = value,
                500_000..=999_999 => self.set_extended(n, value),
                // Haas (`retained_variables`).
                100..=199 if self.cfg.dialect == crate::Dialect::Haas => {
                    self.common[n as usize - 100] = value;
                    self.common_types.set(n as usize - 100, expr::Ty::Unknown);
                }
                10_000..=10_999 if self.cfg.dialect == crate::Dialect::Haas => self.set_extended(n, value),
                3002 => self.timer_h_base = self.clock_s / 3600.0 - value.unwrap_or(0.0),
                3901 => self.parts_done = value.unwrap_or(0.0),
                3902 => self.parts_required = value.unwrap_or(0.0),
                4006 if self.cfg.dialect == crate::Dialect::Fanuc => {
                    self.modes[group::UNITS] = match value {
                        Some(20.0) => code::G20,
                        Some(21.0) => code::G21,
                        _ => return Err(AlarmId::VariableOutOfRange),
                    }
                }
                _ => return Err(AlarmId::VariableOutOfRange),
            }
        }
        Ok(())
    }

    fn set_extended(&mut self, n: u32, value: Value) {
        match value {
            Some(v) => self.extended.insert(n, v),
            None => self.extended.remove(&n),
        };
    }

    /// Every non-vacant common variable (#100–#199, #500–#999, and the extended
    /// #100000–#199999, #500000–#999999) as (number, value), in number order.
    pub fn common_variables(&self) -> Vec<(u32, f64)> {
        let c = self.common.iter().enumerate().filter_map(|(i, v)| v.map(|x| (100 + i as u32, x)));
        let p = self.persistent.iter().enumerate().filter_map(|(i, v)| v.map(|x| (500 + i as u32, x)));
        let e = self.extended.iter().map(|(&n, &v)| (n, v));
        let mut all: Vec<(u32, f64)> = c.chain(p).chain(e).collect();
        all.sort_by_key(|&(n, _)| n);
        all
    }

    /// Set common variable `n` (#100–#199, #500–#999 or an extended one) from outside a
    /// program (a host, an operator); other numbers are not the host's to write:
    /// `WriteProtectedVariable`. In the Syntec dialect only #500–#999: #100–#199 are a Syntec
    /// program's local variables, vacant at each cycle start (`Interpreter::load`), so a value
    /// set before it would be wiped unseen, and the extended numbers are no Syntec program's
    /// (`vars::syntec_differs`).
    pub fn set_common_variable(&mut self, n: u32, value: Value) -> Result<(), AlarmId> {
        if self.cfg.dialect == Dialect::Syntec && !matches!(n, 500..=999) {
            return Err(AlarmId::WriteProtectedVariable);
        }
        match n {
            100..=199 => {
                self.common[n as usize - 100] = value;
                // A host's value has no Syntec type.
                self.common_types.set(n as usize - 100, expr::Ty::Unknown);
            }
            500..=999 => self.persistent[n as usize - 500] = value,
            100_000..=199_999 | 500_000..=999_999 => self.set_extended(n, value),
            // Haas: the NGC's #10000 + n names #n (`vars::haas_slot`).
            10_000..=10_999 if self.cfg.dialect == crate::Dialect::Haas => match n - 10_000 {
                k @ (100..=199 | 500..=699 | 800..=999) => return self.set_common_variable(k, value),
                _ => self.set_extended(n, value),
            },
            _ => return Err(AlarmId::WriteProtectedVariable),
        }
        Ok(())
    }

    /// Current position in programming (workpiece) coordinates.
    pub fn position(&self) -> Pos {
        self.pos
    }

    /// The G52 local coordinate system's shift per axis, mm (what G52 sets; Haas: also G10 L2 P0,
    /// read as #5201…).
    pub fn local_offset(&self) -> Pos {
        self.local
    }

    /// The external work offset in effect (work offset slot 0: FANUC's G10 L2 P0, #5201…).
    /// Zero in the Haas dialect, which has none (its P0 and #5201… are G52): a value stored
    /// there (set before, or kept from another dialect's machine) would shift every work system
    /// with nothing a Haas program can read or cancel (audit of offsets, Haas `EXT`).
    pub(super) fn external_offset(&self) -> Pos {
        if self.cfg.dialect == crate::Dialect::Haas {
            [0.0; MAX_AXES]
        } else {
            *self.offsets.work(0)
        }
    }

    /// Current position in machine coordinates.
    pub fn machine_position(&self) -> Pos {
        match self.follow_machine {
            Some(m) => m,
            None => self.program_to_machine(&self.pos),
        }
    }

    /// The programmed point a view shows while the machine stands where the interpreter has
    /// read to — the controller at rest (its status and stream) and the end of a run (the
    /// summary of `fivex run` and of a fleet run): the current point as the position display
    /// shows it ([`State::shown_position`], which has the G92/G52/G10 L2/G5x of blocks without
    /// motion at once), except under a cutter compensation, where it is `commanded`, the point
    /// the path stages made and the machine went to (the tool centre, off the programmed
    /// contour). One rule, so that the views and the run summary cannot disagree (audit of
    /// views F5: under G41 the summary gave the contour's point, the controller the centre).
    pub fn shown_at_rest(&self, commanded: &Pos) -> Pos {
        if self.modes[group::CUTTER_COMP] == code::G40 {
            self.shown_position()
        } else {
            *commanded
        }
    }

    /// How the tool tip is read from the machine axes now (`crate::tip`): the tool length in
    /// effect, the active workpiece system's origin in the table frame, and the system the
    /// programmed point is in.
    pub fn tip_basis(&self) -> crate::tip::Basis {
        use crate::tip::System;
        let off = self.offset_vector();
        let nose = self.kinematics.as_ref().map_or([0.0; 3], |k| k.nose.into());
        let origin: [f64; 3] = std::array::from_fn(|k| self.axis_of(b'X' + k as u8).map_or(0.0, |i| off[i]) + nose[k]);
        let (tool_length, programmed_in) = match &self.tcp {
            Some(t) => (
                t.tool_length,
                if tcp::shows_workpiece(self) { System::WorkpieceMachineAxes } else { System::Programming },
            ),
            None if self.plane_active() => (self.active_tool_length(), System::Feature),
            // The table coordinate system of 5-axis cutter compensation: shown as Π is (DET).
            None if self.table_crc_active() => (
                self.active_tool_length(),
                if tcp::shows_workpiece(self) { System::WorkpieceMachineAxes } else { System::Programming },
            ),
            None => {
                // The length applied at the last H selection (a G10 to the offset in use waits
                // for the next one, as the machine position does).
                let applied = self.axis_of(b'Z').map_or(0.0, |z| self.tool_vec[z]);
                let shown = if self.wse.is_some() && !self.wse_shows_wcs() { System::Wscs } else { System::Workpiece };
                (applied, shown)
            }
        };
        crate::tip::Basis { tool_length, origin, programmed_in, chain: self.cfg.machine.chain() }
    }

    pub fn modal(&self, group: usize) -> u16 {
        self.modes[group]
    }

    /// The modal words a panel shows beside the G codes.
    pub fn modal_words(&self) -> ModalWords {
        ModalWords { f: self.f, s: self.s, t: self.t, spindle_tool: self.tool_in_spindle, h: self.h, d: self.d }
    }

    /// The G codes and words as the interpreter has read to.
    pub fn modal_state(&self) -> ModalState {
        ModalState { modes: self.modes, words: self.modal_words(), wse_set: self.wse.map_or(0, |a| a.set) }
    }

    /// Whether the next block may need blocks that have not arrived: the end of the text of a
    /// program still growing, a block that may reach beyond itself (`Loaded::reaches_beyond`),
    /// or any block while a modal call is active.
    fn needs_input(&self, progs: &[Slot]) -> bool {
        let Some(frame) = self.frames.last() else { return true };
        let prog = &progs[frame.prog];
        match prog.reaches_beyond.get(frame.pc) {
            Some(&beyond) => beyond || !self.modal_calls.is_empty(),
            None => !prog.finished,
        }
    }

    fn step(&mut self, progs: &[Slot], by_number: &HashMap<u32, usize>, out: &mut Vec<Canon>) -> Result<Step, AlarmId> {
        let frame = self.frames.last_mut().expect("a running interpreter has a frame");
        let prog = &progs[frame.prog];
        if frame.pc >= prog.len() {
            // The end of a program's text: the main program ends, a called one returns.
            if self.frames.len() == 1 {
                if self.nurbs.is_some() {
                    // The text ends inside a NURBS curve: its last knot never comes.
                    return Err(AlarmId::NurbsFormat);
                }
                self.smoothing_flush(out)?;
                self.blend_flush(out)?;
                self.corner_end()?;
                self.hpcc_end();
                self.blend_end();
                if self.cfg.dialect == crate::Dialect::Fanuc && !self.mdi {
                    // A FANUC control in memory operation reads the end of record (%) after the
                    // last block and stops with PS5010: only M02/M30 (or M99) end a program.
                    // The last moves, released above, are made first (they are not the alarm
                    // block's own: `Interpreter::step` keeps them); the alarm is at the main
                    // program's last block, also when a call returned there. Syntec and Haas
                    // end the program here (`docs/dialects.md`, "The end of the program's text").
                    self.block_out = out.len();
                    if let Some(last) = prog.len().checked_sub(1).map(|i| prog.block(i)) {
                        (self.line, self.n) = (last.line, last.n);
                    }
                    return Err(AlarmId::EndOfRecord);
                }
                self.ended = true;
                return Ok(Step::Ended);
            }
            // A 30i reads the end of record (%) there and stops with PS5010 (a 0i names it
            // SR5010 END OF RECORD): the caller's blocks after the call never run.
            if self.cfg.dialect == crate::Dialect::Fanuc {
                return Err(AlarmId::EndOfRecord);
            }
            self.return_from_call(progs, None)?;
            return Ok(Step::Continue);
        }
        let idx = frame.pc;
        frame.pc += 1;
        let prog_idx = frame.prog;
        // Macro statements, control flow and calls change data only; an NC block says
        // (`nc::exec_words`).
        self.modal_part_changed = false;
        self.single_block_stop = false;
        let block = prog.block(idx);
        self.line = block.line;
        self.n = block.n;
        if block.deleted(self.cfg.block_delete) {
            return Ok(Step::Continue);
        }
        self.blocks += 1;
        if self.blocks > self.cfg.max_blocks {
            return Err(AlarmId::BlockBudgetExceeded { budget: self.cfg.max_blocks });
        }
        if let Some(n) = block.n {
            self.last_n = n;
        }
        self.block_out = out.len();
        self.exec(progs, by_number, prog_idx, idx, block, out)?;
        Ok(if self.ended { Step::Ended } else { Step::Continue })
    }

    fn exec(
        &mut self,
        progs: &[Slot],
        by_number: &HashMap<u32, usize>,
        prog_idx: usize,
        idx: usize,
        block: &Block,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let prog = &progs[prog_idx];
        if !matches!(block.kind, BlockKind::Words(_) | BlockKind::Empty | BlockKind::SyntecOnly(_)) {
            // Under G187 a macro statement or a branch between two moves keeps their corner
            // exact: what is held moves first (`corner_blend`).
            self.blend_flush(out)?;
            self.block_out = out.len();
        }
        match &block.kind {
            BlockKind::Empty => {}
            BlockKind::Error(d) => return Err(d.id.clone()),
            BlockKind::SyntecOnly(s) => {
                if let Some(d) = s.refusal(self.cfg.dialect) {
                    return Err(d.id.clone());
                }
            }
            BlockKind::Assign { var, value } => {
                let number = self.target_number(var)?;
                let v = eval_typed(value, self, &self.expr)?;
                self.write(number, v, block, out)?;
            }
            BlockKind::IfGoto { cond, target } => {
                if truth(eval(cond, self, &self.expr)?) {
                    self.goto(prog, idx, target)?;
                }
            }
            BlockKind::IfThen { cond, var, value } => {
                if truth(eval(cond, self, &self.expr)?) {
                    let number = self.target_number(var)?;
                    let v = eval_typed(value, self, &self.expr)?;
                    self.write(number, v, block, out)?;
                }
            }
            BlockKind::IfWords { cond, words } => {
                self.modal_part_changed = true;
                // Haas NGC's conditional M99 (`docs/dialects.md`, "Subprograms and macros"):
                // M99 P<n> branches only when the condition holds. No other dialect has the form
                // (a block cannot start with '[' there), and no other words may follow it.
                if self.cfg.dialect != Dialect::Haas {
                    return Err(AlarmId::Syntax);
                }
                if !program::is_conditional_m99(words) {
                    return Err(AlarmId::MacroFormat);
                }
                if truth(eval(cond, self, &self.expr)?) {
                    self.exec_words(progs, by_number, words, block, out)?;
                }
            }
            BlockKind::Goto(target) => self.goto(prog, idx, target)?,
            BlockKind::Do { cond, .. } => {
                if let Some(e) = prog.loop_error.get(&(idx as u32)) {
                    return Err(e.clone());
                }
                let end = prog.pair_of(idx).ok_or(AlarmId::MissingEnd)?;
                let go_on = match cond {
                    Some(c) => truth(eval(c, self, &self.expr)?),
                    None => true,
                };
                if !go_on {
                    self.frame_mut().pc = end + 1;
                }
            }
            BlockKind::End { .. } => {
                if let Some(e) = prog.loop_error.get(&(idx as u32)) {
                    return Err(e.clone());
                }
                let start = prog.pair_of(idx).ok_or(AlarmId::IllegalLoopNumber)?;
                self.frame_mut().pc = start;
            }
            BlockKind::Output(o) => self.output(o, out)?,
            BlockKind::Words(words) => self.exec_words(progs, by_number, words, block, out)?,
        }
        Ok(())
    }

    fn frame_mut(&mut self) -> &mut CallFrame {
        self.frames.last_mut().expect("a running interpreter has a frame")
    }

    fn target_number(&self, var: &crate::lang::Expr) -> Result<u32, AlarmId> {
        match var {
            crate::lang::Expr::Var(n) => Ok(*n),
            crate::lang::Expr::IndirectVar(e) => expr::var_number(eval(e, self, &self.expr)?),
            _ => Err(AlarmId::MacroFormat),
        }
    }

    fn goto(&mut self, prog: &Loaded, from: usize, target: &crate::lang::Expr) -> Result<(), AlarmId> {
        let v = eval(target, self, &self.expr)?.ok_or(AlarmId::IllegalSequenceNumber)?;
        let n = v.round();
        if !(0.0..=99_999_999.0).contains(&n) {
            return Err(AlarmId::IllegalSequenceNumber);
        }
        // FANUC searches on from the GOTO, then from the top; Syntec takes the first (its
        // macro handbook, `docs/dialects.md`).
        let to = match self.cfg.dialect {
            crate::Dialect::Syntec => prog.first_label(n as u32),
            _ => prog.find_label(n as u32, from),
        };
        let to = to.ok_or(AlarmId::IllegalSequenceNumber)?;
        if prog.jump_enters_loop(from, to) {
            return Err(AlarmId::IllegalLoopNumber);
        }
        self.frame_mut().pc = to;
        Ok(())
    }

    fn output(&mut self, o: &Output, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let (items, binary) = match o {
            Output::Open | Output::Close => return Ok(()),
            Output::Print(items) => (items, false),
            Output::BinaryPrint(items) => (items, true),
        };
        let mut text = String::new();
        for item in items {
            match item {
                PrintItem::Text(t) => text.push_str(t),
                PrintItem::Var { var, int_digits, frac_digits } => {
                    let v = eval(var, self, &self.expr)?.unwrap_or(0.0);
                    if binary {
                        // The control sends the 32-bit integer of `frac_digits` decimals; the
                        // message shows its value in decimal, in braces (binary, not text).
                        let word = expr::round_to(v * 10f64.powi(*frac_digits as i32), 1.0);
                        let word = word.clamp(i32::MIN as f64, i32::MAX as f64) as i32;
                        text.push_str(&format!("{{{word}}}"));
                    } else {
                        text.push_str(&format_dprnt(v, *int_digits, *frac_digits));
                    }
                }
            }
        }
        self.emit(out, CanonKind::Print { text });
        Ok(())
    }

    fn emit(&self, out: &mut Vec<Canon>, kind: CanonKind) {
        out.push(Canon { line: self.line, n: self.n, kind, tip_basis: self.tip_basis() });
    }

    /// Call a program: M98 (`macro_args` None, same local level) or G65/G66 (a new level).
    fn call(&mut self, prog: usize, count: u32, macro_args: Option<Box<vars::Locals>>) -> Result<(), AlarmId> {
        if self.frames.len() > MAX_NESTED_CALLS {
            return Err(AlarmId::NestingTooDeep);
        }
        if count == 0 {
            return Ok(());
        }
        let kind = match macro_args {
            Some(args) => {
                if self.locals.len() > MAX_MACRO_LEVELS {
                    return Err(AlarmId::NestingTooDeep);
                }
                self.locals.push(*args);
                self.frames.push(CallFrame {
                    prog,
                    pc: 0,
                    kind: CallKind::Macro,
                    repeats: count - 1,
                    start: 0,
                    args: Some(args),
                    number: 0,
                    modal: None,
                });
                return Ok(());
            }
            None => CallKind::Sub,
        };
        self.frames.push(CallFrame {
            prog,
            pc: 0,
            kind,
            repeats: count - 1,
            start: 0,
            args: None,
            number: 0,
            modal: None,
        });
        Ok(())
    }

    /// The call just made (Haas M97) starts, and each repetition starts again, at block `pc`.
    fn start_at(&mut self, pc: usize) {
        let frame = self.frame_mut();
        if frame.kind == CallKind::Sub {
            frame.pc = pc;
            frame.start = pc;
        }
    }

    /// M99 (or the end of a called program's text): repeat, or return to the caller, optionally
    /// to its sequence number `to_n`.
    fn return_from_call(&mut self, progs: &[Slot], to_n: Option<u32>) -> Result<(), AlarmId> {
        let frame = self.frames.last_mut().expect("frame");
        if frame.kind == CallKind::Main {
            // M99 in the main program: start again (at N to_n if given).
            frame.pc = match to_n {
                Some(n) => progs[frame.prog].find_label(n, 0).ok_or(AlarmId::LineNotFound)?,
                None => 0,
            };
            return Ok(());
        }
        // Haas: M99 P<n> in a subprogram branches to N<n> of that subprogram and does not return
        // (the classic mill manual, "M99 … does not return control to the calling subroutine").
        if let (Some(n), crate::Dialect::Haas) = (to_n, self.cfg.dialect) {
            let from = frame.pc.saturating_sub(1);
            frame.pc = progs[frame.prog].find_label(n, from).ok_or(AlarmId::LineNotFound)?;
            return Ok(());
        }
        if frame.repeats > 0 {
            frame.repeats -= 1;
            frame.pc = frame.start;
            // FANUC starts each repetition of G65 … L from the arguments again; Haas sets them on
            // the first only and keeps the local variables from repetition to repetition (the
            // mill manual, "Local Variables"); a Syntec G66's repetitions are calls sharing them.
            let fresh_args = self.cfg.dialect != crate::Dialect::Haas;
            let modal = frame.modal.and_then(|serial| self.modal_calls.iter().find(|mc| mc.serial == serial));
            let level = self.locals.last_mut().expect("macro level");
            if let Some(mc) = modal {
                *level = vars::Locals::shared_call(level, &mc.args);
            } else if let Some(args) = frame.args.as_ref().filter(|_| fresh_args) {
                *level = **args;
            }
            return Ok(());
        }
        let frame = self.frames.pop().expect("frame");
        if frame.kind == CallKind::Macro {
            let locals = self.locals.pop().expect("macro level");
            // A Syntec G66's calls share their locals until G67 (gone if the macro gave it).
            if let Some(mc) = self.modal_calls.iter_mut().find(|mc| Some(mc.serial) == frame.modal) {
                *mc.shared = locals;
            }
        }
        if let Some(n) = to_n {
            let caller = self.frames.last_mut().expect("caller frame");
            let from = caller.pc.saturating_sub(1);
            caller.pc = progs[caller.prog].find_label(n, from).ok_or(AlarmId::LineNotFound)?;
        }
        Ok(())
    }

    fn level(&self) -> usize {
        self.locals.len() - 1
    }

    /// Programming → machine coordinates (G54.4 error, work offset, local, G92 shift, tool length).
    fn program_to_machine(&self, p: &Pos) -> Pos {
        let off = self.offset_vector();
        let mut m = [0.0; MAX_AXES];
        let mut p = *p;
        self.wse_to_wcs(&mut p);
        for i in 0..self.cfg.machine.axes.len() {
            m[i] = p[i] + off[i] + self.tool_vec[i];
        }
        m
    }

    /// Sets work offset `index` (the external offset, G54–G59, G54.1 P) to `set`: the one way
    /// G10 L2/L20 and the work offset variables (#5201…, #7001…, #14001…) change one. No axis
    /// moves: the coordinate system shifts at once under the machine, standing at `machine`
    /// (`State::work_system_shifted`).
    pub(super) fn set_work_offset(&mut self, index: usize, set: Pos, machine: &Pos) {
        *self.offsets.work_mut(index) = set;
        self.work_system_shifted(machine);
    }

    /// The workpiece system moved without an axis moving (a work offset, G52, Haas's G10 L2 P0):
    /// the current point is read again from where the machine stands (`machine`, where it
    /// stood before the change), so an axis the next block does not command stays where it is
    /// in machine coordinates and its absolute position changes (a FANUC-compatible manual: a
    /// change of a work offset "do[es] not cause axis motion. It does immediately shift the
    /// active coordinate system").
    pub(super) fn work_system_shifted(&mut self, machine: &Pos) {
        self.pos = self.machine_to_program(machine);
        self.sync_programmed();
    }

    fn machine_to_program(&self, m: &Pos) -> Pos {
        let off = self.offset_vector();
        let mut p = [0.0; MAX_AXES];
        for i in 0..self.cfg.machine.axes.len() {
            p[i] = m[i] - off[i] - self.tool_vec[i];
        }
        self.wse_from_wcs(&mut p);
        p
    }

    /// Index in [`Offsets`] of the active work coordinate system.
    fn work_index(&self) -> usize {
        match self.modes[group::WORK_SYSTEM] {
            code::G54_1 => offsets::g54_1_index(self.wcs_p as usize),
            g54_to_59 => ((g54_to_59 - code::G54) / 10) as usize + 1,
        }
    }
}

/// DPRNT number format: sign, `int_digits` integer digits at most, `frac_digits` decimals.
fn format_dprnt(v: f64, int_digits: u8, frac_digits: u8) -> String {
    let s = format!("{:.*}", frac_digits as usize, v.abs());
    let (int_part, frac_part) = s.split_once('.').unwrap_or((&s, ""));
    let int_part =
        if int_part.len() > int_digits as usize { &int_part[int_part.len() - int_digits as usize..] } else { int_part };
    let sign = if v < 0.0 { "-" } else { "" };
    if frac_digits == 0 {
        format!("{sign}{int_part}")
    } else {
        format!("{sign}{int_part}.{frac_part}")
    }
}

/// A canonical command's positions are numbers (motion only: the rest carry no position).
fn finite_motion(c: &Canon) -> bool {
    match &c.kind {
        CanonKind::Motion(m) => m.target.iter().chain(&m.machine).all(|x| x.is_finite()),
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::{Source, Stored};
    use std::sync::Arc;

    #[test]
    fn a_stored_program_is_parsed_when_a_call_first_reaches_it() {
        let machine = crate::machine::MachineConfig::preset("mill3").unwrap();
        let mut interp = Interpreter::new(crate::lang::parse_file(""), Config::new(machine, Dialect::Fanuc));
        let stored = |number, first_line, text: &str| Arc::new(Stored { number, first_line, text: text.into() });
        let library = vec![stored(2, 10, "O0002\n#101=2\nM99\n"), stored(3, 20, "#101=3\nM99\n")];
        interp.load_source(&Source { main: "G00 X1.\nM98 P2\nM30\n".into(), library });
        let loaded = |i: &Interpreter| i.progs.iter().map(|p| p.is_loaded()).collect::<Vec<_>>();
        assert_eq!(loaded(&interp), [true, false, false]);
        let mut out = Vec::new();
        while let Ok(Step::Continue) = interp.step(&mut out) {}
        assert_eq!(interp.state.common_variables(), vec![(101, 2.0)]);
        assert_eq!(loaded(&interp), [true, true, false], "O0003 is never called");
    }
}
