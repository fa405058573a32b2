//! Program restart's block search (FANUC P type / Q type): the program runs from its top to the
//! restart block *without motion* — every block is executed, so the modal groups, F/S/T/H/D,
//! the work offsets, the call-free macro variables and the current point come out exactly as a
//! run from the top would leave them — and the M/S/T the machine must be given before it goes
//! on are collected instead of carried out. The controller (`controller/restart.rs`) returns
//! the axes to the point found and continues from the restart block.
//!
//! Rules and sources: `docs/dialects.md`, "Program restart".

use super::gcode::{code, group};
use super::mcode;
use super::{Interpreter, State, Step};
use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, Coolant, Pos};

/// The block a restart goes on from, in the main program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The `occurrence`-th time (from 1) the main program reaches the block numbered `n`.
    Sequence { n: u32, occurrence: u32 },
    /// The `occurrence`-th time (from 1) the main program reaches the block on `line`.
    Line { line: u32, occurrence: u32 },
}

/// What the search found: the restart block, where the machine must be, what to output.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// Line and N of the restart block.
    pub line: u32,
    pub n: Option<u32>,
    /// The machine position the restart block starts from (the end of the block before it).
    pub machine: Pos,
    /// Blocks executed by the search.
    pub blocks: u64,
    /// The last mechanism chain, tool change and spindle command the search passed over, in
    /// that order: carried out before the return (FANUC outputs the M/S/T of the search).
    pub output: Vec<Canon>,
    /// The M codes the search passed over, the last [`M_SHOWN`] (FANUC's program restart screen
    /// shows them for the operator).
    pub m_codes: Vec<u32>,
}

/// A block search under way ([`Interpreter::search_on`]): what it has passed over so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    target: Target,
    /// How many times the main program has reached the restart block.
    seen: u32,
    chain: Option<Canon>,
    tool: Option<Canon>,
    spindle: Option<Canon>,
    m_codes: Vec<u32>,
    /// The interpreter's block count when the search began.
    start: u64,
}

impl Search {
    /// A search of `interp`'s loaded program (from its top) for `target`.
    pub fn new(target: Target, interp: &Interpreter) -> Search {
        Search {
            target,
            seen: 0,
            chain: None,
            tool: None,
            spindle: None,
            m_codes: Vec::new(),
            start: interp.state.blocks,
        }
    }

    /// Where the search stands in `interp`: the next block, the position, what it passed over
    /// (once the restart block is reached, what it found).
    pub fn so_far(&self, interp: &Interpreter) -> Found {
        let (line, n) = match interp.next_block() {
            Some((line, n, _)) => (line, n),
            None => interp.state.current_block(),
        };
        Found {
            line,
            n,
            machine: interp.state.machine_position(),
            blocks: interp.state.blocks - self.start,
            output: [&self.chain, &self.tool, &self.spindle].into_iter().flatten().cloned().collect(),
            m_codes: self.m_codes.clone(),
        }
    }
}

/// How many of the searched M codes are kept for the operator (FANUC's restart screen: 35).
pub const M_SHOWN: usize = 35;

impl Interpreter {
    /// The block the next [`Interpreter::step`] executes: its line, N and call depth (1 in the
    /// main program). `None` at the end.
    pub fn next_block(&self) -> Option<(u32, Option<u32>, usize)> {
        let st = &self.state;
        if st.ended {
            return None;
        }
        let frame = st.frames.last()?;
        let prog = self.progs.get(frame.prog)?;
        (frame.pc < prog.len()).then(|| {
            let b = prog.block(frame.pc);
            (b.line, b.n, st.frames.len())
        })
    }

    /// Run the loaded program from its top to `target` without motion (a restart's block
    /// search): on success the interpreter stands before the restart block, its state what a
    /// run from the top would have left. The target not reached before the program's end is
    /// PS0071; the program's own alarms come as in a run; a restart block in a mode the search
    /// cannot carry into the return (see [`State::restart_refusal`]) is refused. The search in
    /// one go: [`Interpreter::search_on`] runs it in slices.
    pub fn search(&mut self, target: Target) -> Result<Found, Alarm> {
        let mut search = Search::new(target, self);
        loop {
            if let Some(found) = self.search_on(&mut search, u64::MAX)? {
                return Ok(found);
            }
        }
    }

    /// [`Interpreter::search`] for at most `budget` more blocks: `None` when the restart block
    /// is not reached yet (call again with the same `search` and nothing else run between).
    pub fn search_on(&mut self, search: &mut Search, budget: u64) -> Result<Option<Found>, Alarm> {
        let (want, occurrence) = match search.target {
            Target::Sequence { n, occurrence } | Target::Line { line: n, occurrence } => (n, occurrence.max(1)),
        };
        let mut out = Vec::with_capacity(16);
        for _ in 0..budget {
            if let Some((line, n, 1)) = self.next_block() {
                let here = match search.target {
                    Target::Sequence { .. } => n == Some(want),
                    Target::Line { .. } => line == want,
                };
                if here {
                    search.seen += 1;
                    if search.seen == occurrence {
                        if let Some(id) = self.state.restart_refusal() {
                            return Err(self.alarm_at(id, line, n));
                        }
                        return Ok(Some(search.so_far(self)));
                    }
                }
            }
            let step = match self.step(&mut out) {
                // The end of the main program's text (FANUC's PS5010 in a run): the search
                // went through the whole program without finding the block, as at its M30.
                Err(_) if self.stopped_by == Some(AlarmId::EndOfRecord) && self.state.frames.len() == 1 => Step::Ended,
                step => step?,
            };
            for c in out.drain(..) {
                match &c.kind {
                    CanonKind::Chain(_) => search.chain = Some(c),
                    CanonKind::ToolChange { .. } => search.tool = Some(c),
                    CanonKind::Spindle { .. } => search.spindle = Some(c),
                    CanonKind::Aux { m } | CanonKind::ProgramEnd { m } => search.m_codes.push(*m),
                    // Coolant is the operator's to give again (fivex outputs only the tool
                    // change and the spindle): the screen lists it with the other M codes.
                    CanonKind::Coolant(coolant) => search.m_codes.push(coolant_m(*coolant)),
                    _ => {}
                }
            }
            if search.m_codes.len() > M_SHOWN {
                search.m_codes.drain(..search.m_codes.len() - M_SHOWN);
            }
            match step {
                Step::Continue => {}
                Step::NeedInput => self.finish(),
                Step::Ended => {
                    let (line, n) = self.state.current_block();
                    return Err(self.alarm_at(AlarmId::RestartBlockNotFound, line, n));
                }
            }
        }
        Ok(None)
    }

    fn alarm_at(&mut self, id: AlarmId, line: u32, n: Option<u32>) -> Alarm {
        self.state.ended = true;
        let (code, message) = self.state.cfg.dialect.describe(&id);
        Alarm { code, message, line, n }
    }
}

/// The M code that gave a coolant command.
fn coolant_m(coolant: Coolant) -> u32 {
    match coolant {
        Coolant::Mist => mcode::M07,
        Coolant::Flood => mcode::M08,
        Coolant::Off => mcode::M09,
    }
}

/// The coordinate system the program's positions are in, beside the offsets' values: the work
/// coordinate system selected (G54…, G54.1 P), the G52 local offset and the G92 shift. Set or
/// changed since the interruption, a P type restart is refused (FANUC PS0094).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coordinates {
    work: usize,
    local: Pos,
    shift: Pos,
}

impl State {
    /// The coordinate system in force ([`Coordinates`]).
    pub fn coordinates(&self) -> Coordinates {
        Coordinates { work: self.work_index(), local: self.local, shift: self.shift }
    }

    /// Why a restart cannot go on from here. The search runs neither the path stages nor the
    /// executor, so a mode whose next move depends on what they hold (a compensation vector, a
    /// canned cycle's hole pattern, a tool tip followed through the kinematics, a curve being
    /// collected, a `,C`/`,R` corner held, a modal macro call) cannot be entered by a return in machine coordinates:
    /// fivex refuses a restart block in it (a decision, `docs/dialects.md`).
    pub(super) fn restart_refusal(&self) -> Option<AlarmId> {
        let in_mode = self.modes[group::CUTTER_COMP] != code::G40
            || self.modes[group::CYCLE] != code::G80
            || self.tcp_active()
            || self.plane_active()
            || self.table_crc_active()
            || self.wse_follows()
            || self.follow_machine.is_some()
            || self.nurbs.is_some()
            || self.smoothing.is_some()
            || self.blend.is_some()
            || self.corner.is_some()
            || !self.modal_calls.is_empty();
        in_mode.then_some(AlarmId::RestartInMode)
    }
}

impl State {
    /// A search abandoned before its return (a reset, an emergency stop, another program or
    /// another search: `docs/dialects.md`, "Program restart") is forgotten: the search moved
    /// nothing, so the program's state — modal groups, F/S/T/H/D, the programming transforms,
    /// G52/G92, the current point — goes back to `before`, what it was when the search began,
    /// and the next program does not start in the searched modes (G91, G68…). What the search
    /// wrote to memory (G10 offsets, common variables) stays, as a run's writes stay after its
    /// reset and as the operator may have edited it since; so do the clocks and counters, the
    /// configuration and the interface signals.
    pub fn forget_search(&mut self, before: State) {
        let now = std::mem::replace(self, before);
        self.cfg = now.cfg;
        self.expr = now.expr;
        self.common = now.common;
        self.persistent = now.persistent;
        self.extended = now.extended;
        self.offsets = now.offsets;
        self.setting_errors = now.setting_errors;
        self.machine_view = now.machine_view;
        self.kinematics = now.kinematics;
        self.wse_kinematics = now.wse_kinematics;
        self.axis_by_letter = now.axis_by_letter;
        self.clock_s = now.clock_s;
        self.wall_clock = now.wall_clock;
        self.timer_ms_base = now.timer_ms_base;
        self.timer_h_base = now.timer_h_base;
        self.operating_s = now.operating_s;
        self.cutting_s = now.cutting_s;
        self.cycle_timer_base = now.cycle_timer_base;
        self.feed_timer_base = now.feed_timer_base;
        self.part_start_s = now.part_start_s;
        self.last_part_s = now.last_part_s;
        self.previous_part_s = now.previous_part_s;
        self.parts_to_time = now.parts_to_time;
        self.single_block = now.single_block;
        self.dry_run = now.dry_run;
        self.sys3003 = now.sys3003;
        self.sys3004 = now.sys3004;
        self.signals = now.signals;
        self.parts_done = now.parts_done;
        self.parts_required = now.parts_required;
        self.blocks = now.blocks;
    }
}
