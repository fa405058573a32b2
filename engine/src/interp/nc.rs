//! Execution of an NC statement (a block of address words): modal updates, data setting,
//! coordinate systems, motion, M codes and subprogram/macro calls, in FANUC's order.

use super::expr::{eval_typed, round_to, ExprSettings, Ty};
use super::g10;
use super::gcode::{self, GDef};
use super::gcode::{code, group};
use super::mcode;
use super::modes;
use super::offsets::{g54_1_index, p_taken_elsewhere, work_system_p, WorkP, MAX_G54_1};
use super::program::Slot;
use super::unbuilt;
use super::vars::Locals;
use super::{CallFrame, CallKind, CycleData, ModalCall, State};
use crate::alarm::AlarmId;
use crate::canon::{
    Arc, Canon, CanonKind, Coolant, CutterWord, FeedMode, Motion, MotionContext, MotionKind, Pos, SpindleState,
};
use crate::dialect::Dialect;
use crate::lang::{Block, Word, WordValue};
use crate::machine::{AxisKind, MAX_AXES};
use crate::stage::{CompStart, PerpendicularStart};
use arrayvec::ArrayVec;
use std::collections::HashMap;

/// A subprogram call of the block (`call_target`): the program, how many times, and the block
/// it starts at (Haas M97: a line of the calling program; else the program's top).
#[derive(Debug, Clone, Copy)]
struct Call {
    prog: usize,
    count: u32,
    at: Option<usize>,
}

/// Modal macro calls that may nest (FANUC: four macro levels).
const MAX_MODAL_CALLS: usize = 4;

/// Most words one block may hold (G65 with ten I/J/K sets needs 35).
pub(crate) const MAX_WORDS: usize = 48;
/// Most G codes one block may hold (a post's safe-start line holds about ten).
pub(crate) const MAX_G_CODES: usize = 12;
/// Most M codes one block may hold (FANUC's multiple M codes in a block: up to three).
pub(crate) const MAX_M_CODES: usize = 3;

/// How a word's value was written: it decides its unit and its rounding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Form {
    /// A number without a decimal point (least increments at a distance address).
    NoPoint,
    /// A number with a decimal point.
    Point,
    /// A variable or expression: FANUC rounds its value to the address's least input
    /// increment where the address is used (a whole number at M, S, T, H, D, P, L …; G codes
    /// excepted), while a macro call's argument keeps the exact value. With its Syntec type,
    /// which a macro call's argument keeps.
    Expr(Ty),
}

/// Where a letter's last word is kept in `Words::last`.
fn slot(letter: u8) -> usize {
    match letter {
        b'a'..=b'z' => 26 + (letter - b'a') as usize,
        _ => (letter - b'A') as usize,
    }
}

/// A block's words after evaluation: vacant words are gone, values are as written.
pub(super) struct Words {
    /// (letter, value, how it was written), in block order.
    list: ArrayVec<(u8, f64, Form), MAX_WORDS>,
    /// Index into `list` of the last word per letter, +1 (0 = absent): A–Z, then the comma
    /// addresses' lower-case letters a–z (`lang::ast::Word::letter`).
    last: [u8; 52],
    g: [u16; MAX_G_CODES],
    ng: usize,
    /// Bit `code % 64` set for every G code of the block: most `has_g` questions end here.
    g_bits: u64,
    m: [u32; MAX_M_CODES],
    nm: usize,
    /// An M word that is no M code (`M3.5`, a negative value): refused where the block's M
    /// codes run, but a macro call's argument (`G65 P9010 M0.070`, #13).
    improper_m: bool,
    /// Haas: the G54.1 P that G110 … G129 select (G154 P1 … P20); G154 itself takes the P word.
    pub(super) haas_wcs_p: Option<u16>,
}

impl Words {
    /// The last word of `letter`: its value as written and whether it had no decimal point.
    pub(super) fn raw(&self, letter: u8) -> Option<(f64, bool)> {
        self.word(letter).map(|(v, form)| (v, form == Form::NoPoint))
    }

    fn word(&self, letter: u8) -> Option<(f64, Form)> {
        let i = self.last[slot(letter)];
        (i != 0).then(|| {
            let (_, v, form) = self.list[i as usize - 1];
            (v, form)
        })
    }

    pub(super) fn has(&self, letter: u8) -> bool {
        self.last[slot(letter)] != 0
    }

    /// The last word of `letter` is a number written with a decimal point (not a variable or
    /// an expression).
    pub(super) fn has_point(&self, letter: u8) -> bool {
        self.word(letter).is_some_and(|(_, form)| form == Form::Point)
    }

    /// The block's G codes (×10), in block order.
    pub(super) fn gcodes(&self) -> &[u16] {
        &self.g[..self.ng]
    }

    /// The block's M codes, in block order.
    pub(super) fn mcodes(&self) -> &[u32] {
        &self.m[..self.nm]
    }

    /// The address letters of the block's words, in block order.
    pub(super) fn letters(&self) -> impl Iterator<Item = u8> + '_ {
        self.list.iter().map(|&(letter, _, _)| letter)
    }

    pub(super) fn has_g(&self, code: u16) -> bool {
        self.g_bits & (1 << (code % 64)) != 0 && self.g[..self.ng].contains(&code)
    }

    /// An address that takes whole numbers (M S T H D P L K Q …): a variable's or an
    /// expression's value is rounded half away from zero (`T[5.5]` is T6, `S#1` with 1000.4999
    /// S1000), a written number stays as written (so `T5.5` is still refused).
    pub(super) fn integer(&self, letter: u8) -> Option<f64> {
        self.word(letter).map(|(v, form)| if matches!(form, Form::Expr(_)) { round_to(v, 1.0) } else { v })
    }

    /// The value exactly as written or evaluated (F, E, and questions about the block's form).
    pub(super) fn number(&self, letter: u8) -> Option<f64> {
        self.word(letter).map(|(v, _)| v)
    }
}

impl Words {
    pub(super) fn new() -> Words {
        Words {
            list: ArrayVec::new(),
            last: [0; 52],
            g: [0; MAX_G_CODES],
            ng: 0,
            g_bits: 0,
            m: [0; MAX_M_CODES],
            nm: 0,
            improper_m: false,
            haas_wcs_p: None,
        }
    }
}

impl State {
    #[cfg(test)]
    pub(super) fn collect(&self, words: &[Word]) -> Result<Words, AlarmId> {
        let mut w = Words::new();
        self.collect_into(words, &mut w)?;
        Ok(w)
    }

    /// Evaluate a block's words into `w` (a fresh [`Words::new`]). Filled in place: returning
    /// the large `Words` through a `Result` would copy it once per block.
    pub(super) fn collect_into(&self, words: &[Word], w: &mut Words) -> Result<(), AlarmId> {
        for word in words {
            let (v, form) = match &word.value {
                WordValue::Number { value, decimal_point: false } => (*value, Form::NoPoint),
                WordValue::Number { value, decimal_point: true } => (*value, Form::Point),
                WordValue::Expr(e) => {
                    // ROUND in an NC address rounds to the address's least input increment.
                    let settings = ExprSettings { round_steps: self.steps_of(word.letter), ..self.expr };
                    match eval_typed(e, self, &settings)? {
                        (Some(v), ty) => (v, Form::Expr(ty)),
                        (None, _) => continue,
                    }
                }
            };
            match word.letter {
                b'G' => {
                    let written = gcode::code_of(v).ok_or(AlarmId::ImproperGCode)?;
                    // The code the block holds (Syntec's G70/G71 are G20/G21).
                    let mut code = gcode::written(written, self.cfg.dialect).ok_or(AlarmId::ImproperGCode)?.code;
                    // Haas: G154 P1–P99 and G110–G129 (= G154 P1–P20) are the G54.1 P work
                    // offsets (the same storage, #7001…/#14001…).
                    if self.cfg.dialect == crate::Dialect::Haas {
                        if let Some(p) = gcode::haas_work_offset(code) {
                            w.haas_wcs_p = p;
                            code = code::G54_1;
                        }
                    }
                    if w.ng == w.g.len() {
                        return Err(AlarmId::IllegalGCodeCombination);
                    }
                    w.g[w.ng] = code;
                    w.ng += 1;
                    w.g_bits |= 1 << (code % 64);
                }
                b'M' => {
                    let v = if matches!(form, Form::Expr(_)) { round_to(v, 1.0) } else { v };
                    if v < 0.0 || v.fract() != 0.0 || v > 99_999_999.0 {
                        w.improper_m = true;
                    } else {
                        if w.nm == w.m.len() {
                            return Err(AlarmId::ImproperAddress);
                        }
                        w.m[w.nm] = v as u32;
                        w.nm += 1;
                    }
                }
                _ => {}
            }
            w.list.try_push((word.letter, v, form)).map_err(|_| AlarmId::ImproperAddress)?;
            w.last[slot(word.letter)] = w.list.len() as u8;
        }
        self.work_system_p(w)
    }

    /// A P beside G54…G59: FANUC's `G54 Pn` is G54.1 Pn (held as G54.1 from here on); a P no
    /// code of the block takes is refused rather than dropped (`offsets::work_system_p`).
    fn work_system_p(&self, w: &mut Words) -> Result<(), AlarmId> {
        let Some(i) = w.gcodes().iter().position(|&c| (code::G54..=code::G59).contains(&c) && c % 10 == 0) else {
            return Ok(());
        };
        let in_cycle = self.modes[group::CYCLE] != code::G80;
        let elsewhere = p_taken_elsewhere(self.cfg.dialect, w.gcodes(), w.mcodes(), in_cycle);
        match work_system_p(self.cfg.dialect, w.g[i], w.has(b'P'), elsewhere) {
            WorkP::NotOurs => Ok(()),
            WorkP::Additional => {
                w.g[i] = code::G54_1;
                w.g_bits |= 1 << (code::G54_1 % 64);
                Ok(())
            }
            WorkP::Refused(alarm) => Err(alarm),
        }
    }

    fn inch(&self) -> bool {
        self.modes[group::UNITS] == code::G20
    }

    /// The least input increment of a length: 0.001 mm, or 0.0001 inch under G20.
    fn increment(&self) -> f64 {
        if self.inch() {
            0.0001
        } else {
            0.001
        }
    }

    /// What one least input increment is worth at an address that counts them: 0.001° at a
    /// rotary axis in mm and inch alike (an angle has no inch form: FANUC 30i-A5 manual §2.3.2
    /// gives the angles' increment apart from the input unit), the length increment elsewhere.
    fn increment_at(&self, letter: u8) -> f64 {
        match self.axis_of(letter) {
            Some(i) if self.cfg.machine.axes[i].kind != AxisKind::Linear => 0.001,
            _ => self.increment(),
        }
    }

    /// Whether a number without a decimal point at this address counts least increments.
    /// Haas also counts them at F (Setting 77 "Scale Integer F" at its default: `F12` is
    /// 0.0012 in/min in G20, 0.012 mm/min in G21).
    fn counts_increments(&self, letter: u8) -> bool {
        !self.cfg.pocket_calculator
            && (matches!(letter, b'I' | b'J' | b'K' | b'R' | b'Q' | b'i' | b'j' | b'k' | b'c' | b'r')
                || self.axis_of(letter).is_some()
                || letter == b'F' && self.cfg.dialect == crate::Dialect::Haas)
    }

    /// Least input increments per unit of an address: 1000 (0.001 mm or deg) at the axes and
    /// I J K R Q, 10000 for linear ones in G20 (0.0001 inch), 1 at the other addresses.
    pub(super) fn steps_of(&self, letter: u8) -> f64 {
        match self.axis_of(letter) {
            Some(_) => 1.0 / self.increment_at(letter),
            None if matches!(letter, b'I' | b'J' | b'K' | b'R' | b'Q' | b'i' | b'j' | b'k' | b'c' | b'r') => {
                1.0 / self.increment()
            }
            None => 1.0,
        }
    }

    /// A distance/angle word in mm or degrees. A variable's or expression's value is first
    /// rounded to the address's least input increment (`#1=1.2346`, `X#1` is X1.235).
    pub(super) fn value(&self, w: &Words, letter: u8) -> Option<f64> {
        let (v, form) = w.word(letter)?;
        let v = match form {
            Form::NoPoint if self.counts_increments(letter) => v * self.increment_at(letter),
            Form::Expr(_) => round_to(v, self.steps_of(letter)),
            _ => v,
        };
        let linear = match self.axis_of(letter) {
            Some(i) => self.cfg.machine.axes[i].kind == AxisKind::Linear,
            // `,C` `,R` (chamfer, corner radius) are lengths too.
            None => matches!(letter, b'I' | b'J' | b'K' | b'R' | b'Q' | b'c' | b'r'),
        };
        Some(if linear && self.inch() { v * 25.4 } else { v })
    }

    /// Arguments of G65/G66/G66.1: specification I and II mixed as FANUC does (later wins).
    fn macro_args(&self, w: &Words) -> Result<Box<Locals>, AlarmId> {
        let mut args = State::empty_locals();
        let (mut set, mut last_ijk) = (0usize, 0u8);
        for &(letter, v, form) in &w.list {
            // (An argument keeps a variable's exact value: no rounding to the increment.)
            let scaled = form == Form::NoPoint && self.counts_increments(letter);
            let v = if scaled { v * self.increment_at(letter) } else { v };
            // Its Syntec type (the handbook, §3.4: an integer is a number without a decimal
            // point; `STD` turns such an argument into the input unit, §9.3); one read in
            // increments is fivex's reading, not Syntec's: not known.
            let ty = match form {
                Form::Point => Ty::Double,
                Form::NoPoint if scaled => Ty::Unknown,
                Form::NoPoint => Ty::Long,
                Form::Expr(ty) => ty,
            };
            let var = match letter {
                b'G' | b'L' | b'N' | b'O' | b'P' => continue,
                b'A' => 1,
                b'B' => 2,
                b'C' => 3,
                b'I' | b'J' | b'K' => {
                    let k = letter - b'I' + 1;
                    if last_ijk != 0 && k <= last_ijk {
                        set += 1;
                    }
                    last_ijk = k;
                    if set >= 10 {
                        return Err(AlarmId::ImproperAddress);
                    }
                    4 + 3 * set + (k as usize - 1)
                }
                b'D' => 7,
                b'E' => 8,
                b'F' => 9,
                b'H' => 11,
                b'M' => 13,
                b'Q' => 17,
                b'R' => 18,
                b'S' => 19,
                b'T' => 20,
                b'U' => 21,
                b'V' => 22,
                b'W' => 23,
                b'X' => 24,
                b'Y' => 25,
                b'Z' => 26,
                _ => return Err(AlarmId::ImproperAddress),
            };
            args.v[var - 1] = Some(v);
            args.ty.set(var - 1, ty);
        }
        Ok(args)
    }

    fn find_program(&self, by_number: &HashMap<u32, usize>, p: Option<f64>) -> Result<usize, AlarmId> {
        // No P is an error of the block, not a program the file may lack (a check tells them
        // apart; FANUC and Syntec give both the same code).
        let p = p.ok_or(AlarmId::MissingP)?;
        if p < 0.0 || p.fract() != 0.0 || p > u32::MAX as f64 {
            return Err(AlarmId::ProgramNotFound);
        }
        by_number.get(&(p as u32)).copied().ok_or(AlarmId::ProgramNotFound)
    }

    pub(super) fn count(w: &Words) -> Result<u32, AlarmId> {
        match w.integer(b'L') {
            None => Ok(1),
            Some(l) if (0.0..=9999.0).contains(&l) && l.fract() == 0.0 => Ok(l as u32),
            Some(_) => Err(AlarmId::ImproperAddress),
        }
    }

    /// Syntec: a number without a decimal point at a length or angle address is in mm/degrees
    /// or in least input increments as the machine's Pr3241 "工件程序小数点型态" (and Pr17, the
    /// increment) decide (the Syntec MACRO handbook §7.3, §8.4.1, §9.3), which fivex does not model:
    /// the Syntec 5-axis manual's own RTCP example writes `B-45` for −45°, which fivex read as
    /// −0.045°. A Long value there (`#1=10`, `X#1`) is the same question (the handbook writes
    /// `X(1.0 * #1)`, §3.10, and converts a Long argument with `STD` first, §9.3), and so is a
    /// macro call's argument so written, which Syntec hands over as a Long of the digits while
    /// fivex reads it in increments. A non-zero one is refused at its block (zero is zero in every
    /// reading); a value whose type fivex does not know is read as before.
    pub(super) fn refuse_syntec_undecided_unit(&self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect != Dialect::Syntec || !self.cfg.refuse_unbuilt {
            return Ok(());
        }
        let call = w.gcodes().iter().any(|c| code::MACRO_CALLS.contains(c));
        let in_cycle = self.after_block(w, group::CYCLE) != code::G80;
        let undecided = |&(letter, v, form): &(u8, f64, Form)| {
            v != 0.0
                && match form {
                    // A call's argument: where fivex scales it.
                    Form::NoPoint if call => self.counts_increments(letter),
                    Form::NoPoint | Form::Expr(Ty::Long) if !call => self.syntec_length_address(letter, in_cycle),
                    _ => false,
                }
        };
        match w.list.iter().any(undecided) {
            true => Err(AlarmId::UnitNotDecided),
            false => Ok(()),
        }
    }

    /// Syntec: an address a block reads as a length or an angle: the machine's axes, I J R, the
    /// corner's `,C` `,R`, K but a canned cycle's (its repetitions), Q only a canned cycle's (the
    /// peck; elsewhere a number: G05.1 Q3, G68.2 Q…, G10 L5000 Q…).
    fn syntec_length_address(&self, letter: u8, in_cycle: bool) -> bool {
        match letter {
            b'I' | b'J' | b'R' | b'c' | b'r' => true,
            b'K' => !in_cycle,
            b'Q' => in_cycle,
            _ => self.axis_of(letter).is_some(),
        }
    }

    /// The modal call a block of the current level triggers: the latest from the level it was
    /// given at, the one before it from one level deeper (inside the latest's macro), and so on
    /// (FANUC, multiple modal calls: the macros are called in turn from the last specified).
    fn modal_call_here(&self) -> Option<&ModalCall> {
        let n = self.modal_calls.len();
        self.modal_calls.iter().enumerate().find(|(i, mc)| mc.level + (n - 1 - i) == self.level()).map(|(_, mc)| mc)
    }

    /// The local variables a G66 call starts with: FANUC's fresh ones from the G66 block's
    /// arguments; Syntec's shared by the G66's calls until G67 (`ModalCall::shared`), those
    /// whose reading the handbook leaves open unsettled (`Locals::shared_call`).
    fn modal_call_locals(&self, mc: &ModalCall) -> Box<Locals> {
        match self.cfg.dialect {
            Dialect::Syntec => Box::new(Locals::shared_call(&mc.shared, &mc.args)),
            _ => mc.args.clone(),
        }
    }

    fn push_frame(
        &mut self,
        progs: &[Slot],
        prog: usize,
        count: u32,
        args: Option<Box<Locals>>,
    ) -> Result<(), AlarmId> {
        let depth = self.frames.len();
        self.call(prog, count, args)?;
        let refuse_here = self.cfg.dialect == Dialect::Syntec && self.frames.len() > depth;
        if let Some(f) = self.frames.last_mut() {
            f.number = progs[f.prog].number().unwrap_or(0);
            // A called program holding Syntec's `%@MACRO` line is refused before any of it runs.
            if refuse_here {
                if let Some(pc) = progs[prog].macro_format {
                    f.pc = pc as usize;
                }
            }
        }
        Ok(())
    }

    pub(super) fn exec_words(
        &mut self,
        progs: &[Slot],
        by_number: &HashMap<u32, usize>,
        words: &[Word],
        block: &Block,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let mut w = Words::new();
        self.collect_into(words, &mut w)?;
        let (first, depth) = (out.len(), self.frames.len());
        let offset_mode = code::COMPENSATED_BY_STAGES.contains(&self.modes[group::CUTTER_COMP]);
        let machine_before = offset_mode.then(|| self.machine_position());
        let in_cycle = self.modes[group::CYCLE] != code::G80;
        let modes_before = self.modes;
        self.modal_part_changed = true;
        self.nc_words(progs, by_number, &w, block, out)?;
        self.modal_part_changed =
            in_cycle || self.modes[group::CYCLE] != code::G80 || !self.moves_only(&w, &modes_before);
        if out[first..].iter().any(|c| matches!(c.kind, CanonKind::Motion(_))) {
            self.cutter_vector = code::COMPENSATED_BY_STAGES.contains(&self.modes[group::CUTTER_COMP]);
        }
        // Single block stops after every NC block; one that made commands ends in its stop
        // anyway, one that made none is marked (a call or return alone passes, as a macro
        // statement; under cutter compensation the stage places the ends).
        self.single_block_stop = out.len() == first
            && !offset_mode
            && !code::COMPENSATED_BY_STAGES.contains(&self.modes[group::CUTTER_COMP])
            && !self.call_alone(&w, depth);
        if let Some(before) = machine_before {
            self.count_without_motion(&w, first, depth, &before, out);
        }
        Ok(())
    }

    /// The block only moves (G00–G03, F, axis words, an arc's I/J/K/R): of the state a reset
    /// keeps (`ModalPart`) it changed only the motion group, F and the current point.
    fn moves_only(&self, w: &Words, modes_before: &[u16; gcode::GROUPS]) -> bool {
        let arc = matches!(self.modes[group::MOTION], code::G02 | code::G03);
        // A code of a group that holds no data, given again while in force (the `G90 G01 …` a
        // post writes on every line): nothing changes, and a copy per such block (hundreds read
        // ahead) would more than double a running controller's memory.
        let again = |g: u16| {
            gcode::lookup(g, self.cfg.dialect).is_some_and(|d| {
                matches!(
                    d.group,
                    group::PLANE
                        | group::DISTANCE
                        | group::FEED_MODE
                        | group::UNITS
                        | group::RETURN_LEVEL
                        | group::PATH_MODE
                ) && modes_before[d.group] == g
            })
        };
        w.gcodes().iter().all(|&g| matches!(g, code::G00 | code::G01 | code::G02 | code::G03) || again(g))
            && w.mcodes().is_empty()
            && w.letters().all(|l| {
                matches!(l, b'G' | b'F') || self.axis_of(l).is_some() || arc && matches!(l, b'I' | b'J' | b'K' | b'R')
            })
    }

    /// In offset mode (before and after the block) the control reads a few blocks ahead to place
    /// the next corner, and the blocks without movement among them count (`MAX_BLOCKS_BETWEEN`,
    /// `docs/cutter-compensation.md` rule 8). Most give a command the stages see (M, S, T, a
    /// dwell, a move off the plane); this marks the others: a block that gave none (a G code
    /// alone, F, S with the spindle stopped, G10), and — FANUC: "when the move distance is
    /// zero, even if the block is commanded singly", the tool moves as after two blocks without
    /// movement — a block whose move is zero, once more. Not counted (decision): a block with
    /// no word but N (a comment, a sequence number), macro statements (never NC blocks here),
    /// and subprogram and macro calls and returns with nothing else (FANUC treats such a block
    /// like a macro statement, e.g. in single block); the blocks they lead to count. A call or
    /// return with anything else (`G90 M99`, `G91 M98 P…`) counts as any block: its G code is
    /// an NC command ("G90 ; G code only"). A Syntec subprogram's M02/M30 is its return (as
    /// M99), alone or not.
    /// The block is a subprogram or macro call or return with nothing else (`depth`: the
    /// call frames before it): M98/M99/M97 with P and L only, G65/G66 (whose other letters are
    /// arguments) with no other G code, or a block whose words are the arguments of a macro
    /// another code called (G66's modal call, an M or T code's macro). FANUC handles it like a
    /// macro statement (no single-block stop, not a block without movement of compensation).
    fn call_alone(&self, w: &Words, depth: usize) -> bool {
        let macro_code = |c: &u16| code::MACRO_CALLS.contains(c) || *c == code::G67;
        // A Syntec subprogram's M02/M30 that returned to the caller is that return, as M99.
        let returned = self.frames.len() < depth;
        let sub_code = |m: &u32| {
            mcode::call_or_return(*m) || *m == mcode::M97 || returned && matches!(*m, mcode::M02 | mcode::M30)
        };
        if w.gcodes().iter().any(macro_code) {
            // Every other letter of G65/G66 is an argument.
            w.gcodes().iter().all(macro_code)
        } else if w.mcodes().iter().any(sub_code) {
            w.gcodes().is_empty() && w.mcodes().iter().all(sub_code) && w.letters().all(|l| b"MPL".contains(&l))
        } else {
            self.frames.len() != depth
        }
    }

    fn count_without_motion(
        &mut self,
        w: &Words,
        first: usize,
        depth: usize,
        machine_before: &Pos,
        out: &mut Vec<Canon>,
    ) {
        if !code::COMPENSATED_BY_STAGES.contains(&self.modes[group::CUTTER_COMP]) || self.ended {
            return;
        }
        if self.call_alone(w, depth) || w.gcodes().is_empty() && w.mcodes().is_empty() && w.list.is_empty() {
            return;
        }
        let made = &out[first..];
        let commands = made.iter().filter(|c| !matches!(c.kind, CanonKind::Cutter(_)));
        let motions = || made.iter().filter_map(|c| if let CanonKind::Motion(m) = &c.kind { Some(m) } else { None });
        // (A whole circle ends where it starts, and moves; G38/G39/G40 I J K give their motion
        // a meaning of its own.)
        let owned = made.iter().any(|c| matches!(c.kind, CanonKind::Cutter(w) if w != CutterWord::Perpendicular));
        let still = |m: &Motion| {
            m.machine == *machine_before && m.arc.is_none() && m.tip.as_ref().is_none_or(|t| t.arc.is_none())
        };
        let zero_move = !owned && motions().next().is_some() && motions().all(still);
        if commands.count() == 0 || zero_move {
            self.emit(out, CanonKind::Cutter(CutterWord::WithoutMotion));
        }
    }

    /// A block of NC words (`exec_words` after reading them).
    fn nc_words(
        &mut self,
        progs: &[Slot],
        by_number: &HashMap<u32, usize>,
        w: &Words,
        block: &Block,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        self.exact_stop = false;
        self.forget_inverse_time_feed();
        let first = out.len();
        if self.nurbs.is_some() {
            // Inside a NURBS curve only its control points and knots may come (`nurbs`).
            return self.nurbs_block(w, out);
        }
        self.smoothing_block(w, out)?;
        self.blend_block(w, out)?;
        self.corner_block(w)?;
        // What smoothing and blending released belongs to the blocks before: this block's own
        // commands start here (an alarm of this block drops only those).
        self.block_out = out.len();
        if self.cfg.fast_paths && self.is_plain_motion(w) {
            return self.plain_motion(w, out);
        }
        // In NURBS interpolation mode only the curves' blocks may come (a macro call included).
        self.refuse_in_nurbs_mode(w)?;

        // --- macro calls: the block's words are arguments, nothing else runs ----------------
        if w.has_g(code::G65) {
            if w.ng > 1 {
                return Err(AlarmId::GAsArgument);
            }
            let prog = self.find_program(by_number, w.integer(b'P'))?;
            self.refuse_syntec_undecided_unit(w)?;
            let args = self.macro_args(w)?;
            return self.push_frame(progs, prog, Self::count(w)?, Some(args));
        }
        if w.has_g(code::G66) || w.has_g(code::G66_1) {
            let every_block = w.has_g(code::G66_1);
            // (Syntec's G66.1 is a row of `unbuilt`; this block's other words are arguments.)
            let not_built = unbuilt::g_code(code::G66_1, self.cfg.dialect, &[], |_| unbuilt::Word::Absent);
            if every_block && self.cfg.refuse_unbuilt && not_built.is_some() {
                return Err(AlarmId::GCodeNotBuilt);
            }
            let prog = self.find_program(by_number, w.integer(b'P'))?;
            self.refuse_syntec_undecided_unit(w)?;
            let args = self.macro_args(w)?;
            let count = Self::count(w)?;
            // Modal calls nest: the latest is called from this level, the one before from inside
            // it, and so on (four calls deep at most, like any macro nesting).
            if self.modal_calls.len() == MAX_MODAL_CALLS {
                return Err(AlarmId::NestingTooDeep);
            }
            self.modes[group::MODAL_CALL] = if every_block { code::G66_1 } else { code::G66 };
            self.modal_serial = self.modal_serial.wrapping_add(1);
            self.modal_calls.push(ModalCall {
                every_block,
                prog,
                count,
                shared: args.clone(),
                args: args.clone(),
                level: self.level(),
                serial: self.modal_serial,
            });
            if every_block {
                return self.push_frame(progs, prog, count, Some(args));
            }
            return Ok(());
        }
        if let (false, Some(mc)) = (w.has_g(code::G67), self.modal_call_here()) {
            if mc.every_block && !w.list.is_empty() {
                if w.ng > 0 {
                    return Err(AlarmId::GAsArgument);
                }
                let (prog, count) = (mc.prog, mc.count);
                let args = self.macro_args(w)?;
                return self.push_frame(progs, prog, count, Some(args));
            }
        }

        if w.improper_m {
            return Err(AlarmId::ImproperAddress);
        }
        let haas_refuses = self.cfg.refuse_unbuilt && self.cfg.dialect == crate::Dialect::Haas;
        if haas_refuses && w.mcodes().iter().any(|&m| unbuilt::haas_m_code(m).is_some()) {
            return Err(AlarmId::MCodeNotBuilt);
        }

        // --- addresses this machine does not have ------------------------------------------
        for &(letter, _, _) in &w.list {
            let known = matches!(
                letter,
                b'D' | b'E'
                    | b'F'
                    | b'G'
                    | b'H'
                    | b'I'
                    | b'J'
                    | b'K'
                    | b'L'
                    | b'M'
                    | b'N'
                    | b'P'
                    | b'Q'
                    | b'R'
                    | b'S'
                    | b'T'
                    | b'a'
                    | b'c'
                    | b'r'
            ) || self.axis_of(letter).is_some()
                // FANUC's `,L2 I J K` (cutting point control; checked where it is read).
                || (matches!(letter, b'l' | b'i' | b'j' | b'k') && self.cfg.dialect == crate::Dialect::Fanuc);
            if !known {
                return Err(AlarmId::ImproperAddress);
            }
            let argument = w.gcodes().iter().any(|&c| unbuilt::argument_of(c, self.cfg.dialect, letter));
            if self.cfg.refuse_unbuilt && unbuilt::address(letter, self.cfg.dialect).is_some() && !argument {
                return Err(AlarmId::AddressNotBuilt);
            }
        }

        let call_form = |m: u32| w.letters().any(|l| unbuilt::call_address(m, l, self.cfg.dialect).is_some());
        if self.cfg.refuse_unbuilt && w.mcodes().iter().any(|&m| call_form(m)) {
            return Err(AlarmId::AddressNotBuilt);
        }
        if self.cfg.refuse_unbuilt && self.syntec_end_not_built(w) {
            return Err(AlarmId::MCodeNotBuilt);
        }

        // --- mode interlocks, then functions not built: a refused block changes nothing -------
        // (The interlocks first: their alarm is the more precise one where both apply.)
        self.refuse_g10_strangers(w)?;
        self.refuse_point_at_numbers(w)?;
        // G53 under G91 (in force, or in its block): FANUC's manuals give G53 in absolute
        // terms only, and controls differ on an incremental one (ignored, or moved by the
        // increment); fivex moved to the absolute machine position. Refused, not guessed
        // (`docs/conventions.md`, "G53 under G91").
        if w.has_g(code::G53) && self.after_block(w, group::DISTANCE) == code::G91 {
            return Err(AlarmId::IllegalGCodeCombination);
        }
        let five = modes::check(self, w)?;
        self.refuse_unbuilt(w)?;
        self.refuse_transform_block(w)?;
        self.refuse_syntec_undecided_unit(w)?;
        self.refuse_unperformed_cycle_words(w)?;
        self.refuse_plane_change_in_cycle(w)?;
        self.refuse_length_change_in_tip_cycle(w)?;
        self.refuse_shift_under_transforms(w)?;
        self.refuse_d_change_in_cutting(w)?;
        if self.cfg.refuse_unbuilt {
            self.refuse_unbuilt_nurbs(w)?;
        }
        // A call whose program or line is missing is refused before the block changes anything.
        let call = self.call_target(progs, by_number, w)?;
        self.five = five;
        self.follow_stcp();
        if w.has_g(code::G67) {
            // G67 cancels the latest modal call; the one before it is in force again.
            self.modal_calls.pop();
            self.modes[group::MODAL_CALL] =
                self.modal_calls.last().map_or(code::G67, |mc| if mc.every_block { code::G66_1 } else { code::G66 });
        }

        // --- G codes: units first, then the modal groups in block order ---------------------
        let unit_before = self.modes[group::UNITS];
        if w.has_g(code::G20) {
            self.modes[group::UNITS] = code::G20;
        }
        if w.has_g(code::G21) {
            self.modes[group::UNITS] = code::G21;
        }
        if self.moved && self.modes[group::UNITS] != unit_before {
            // "G20 and G21 must not be switched during a program" (FANUC B-63944EN/02 §8.2):
            // what a control does then is not described; fivex converts every later word and
            // reports the switch on the next motion (`BlockNotice::UnitSwitched`).
            self.unit_switch = Some((self.line, self.n));
        }
        let machine_before = self.machine_position();
        let length_before = self.tool_vec;
        let comp_before = self.modes[group::CUTTER_COMP];
        let d_before = self.d;
        let dwo_before = self.modes[group::DYNAMIC_FIXTURE];
        let mut axes_owner: Option<u16> = None;
        let mut one_shots: [u16; 12] = [0; 12];
        let mut n_one_shots = 0;
        let mut tool_length_changed = false;
        let mut wcs_changed = false;
        for &code in &w.g[..w.ng] {
            let def: &GDef = gcode::lookup(code, self.cfg.dialect).ok_or(AlarmId::ImproperGCode)?;
            if def.group == group::ONE_SHOT {
                // Syntec's G05 owns the axis words it has; without any, its block moves as any
                // other (the tool length change of `G05 P0 G43.4 H1`).
                let axis_words = || self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8));
                if def.owns_axes(self.cfg.dialect) && (def.takes_axes || axis_words()) {
                    if axes_owner.is_some() {
                        return Err(AlarmId::IllegalGCodeCombination);
                    }
                    axes_owner = Some(code);
                }
                one_shots[n_one_shots] = code;
                n_one_shots += 1;
                continue;
            }
            let group = def.group;
            match group {
                group::MOTION => {
                    // A group-01 code cancels the canned cycle and forgets its data.
                    self.modes[group::CYCLE] = code::G80;
                    self.cycle = CycleData::default();
                }
                group::CYCLE if code == code::G80 => self.cycle = CycleData::default(),
                // An F of G94/G95 is no inverse time: the G93 block needs its own F.
                group::FEED_MODE if code == code::G93 => self.f = 0.0,
                group::PLANE if self.modes[group::CUTTER_COMP] != code::G40 && self.modes[group::PLANE] != code => {
                    return Err(AlarmId::PlaneChangeInCompensation)
                }
                group::CUTTER_COMP => {
                    if let Some(d) = w.integer(b'D') {
                        self.d = offset_number(d, self.cfg.dialect)?;
                    }
                    // Haas G150's G41/G42 name the side of its outline the tool cuts on; the
                    // cycle offsets its path itself and the mode stays as it was (`haas_cycles`).
                    if w.has_g(code::G150) {
                        continue;
                    }
                }
                group::LENGTH_COMP => tool_length_changed = true,
                group::CYCLE if code != code::G80 && self.modes[group::CYCLE] == code::G80 => {
                    let axis = self.drill_axis();
                    self.cycle.initial = axis.map_or(0.0, |a| self.cycle_level(a, self.xf.programmed[a]));
                }
                group::WORK_SYSTEM => {
                    wcs_changed = true;
                    if code == code::G54_1 {
                        let haas = self.cfg.dialect == crate::Dialect::Haas;
                        // Haas: G110–G129 name their P; G154 needs one (P1–P99).
                        let p = match w.haas_wcs_p {
                            Some(p) => p as f64,
                            None if haas => w.integer(b'P').ok_or(AlarmId::IllegalOffsetNumber)?,
                            None => w.integer(b'P').unwrap_or(1.0),
                        };
                        let max = if haas { 99 } else { MAX_G54_1 };
                        if !(1.0..=max as f64).contains(&p) || p.fract() != 0.0 {
                            return Err(AlarmId::IllegalOffsetNumber);
                        }
                        self.wcs_p = p as u16;
                    } else {
                        self.wcs_p = 0;
                    }
                }
                _ => {}
            }
            // (Group 12 was set above from the modal calls still in force after G67.)
            if group != group::MODAL_CALL {
                self.modes[group] = code;
            }
        }
        self.exact_stop = one_shots[..n_one_shots].contains(&code::G09);
        // D is modal whether or not cutter compensation is on (#4107 shows it, a later G41
        // without D uses it).
        if let Some(d) = w.integer(b'D') {
            self.d = offset_number(d, self.cfg.dialect)?;
        }
        if wcs_changed {
            self.work_system_shifted(&machine_before);
        }
        let comp = self.modes[group::CUTTER_COMP];
        let conventional = matches!(comp, code::G41 | code::G42);
        // G41/G42 in force since an offset number 0 (which is no offset, `stage::cutter`) and
        // now another D: a start-up as after G40.
        let offset_again = conventional && matches!(comp_before, code::G41 | code::G42) && d_before == 0 && self.d != 0;
        let starts_up = comp_before == code::G40 && code::COMPENSATED_BY_STAGES.contains(&comp) || offset_again;
        if w.integer(b'D').is_some() || starts_up {
            self.radius = self.offsets.radius(self.d);
        }
        if starts_up {
            // The start-up block starts here (`stage::cutter`); with No.5003#1 SUV a G00/G01
            // block without an axis word of the plane starts up perpendicular to the next move.
            // The G41.3 block moves by the leading edge offset's first vector when the next
            // block comes (`stage::leading_edge`).
            let tool_side = code::TOOL_SIDE.contains(&comp);
            let inserts =
                (conventional || tool_side) && self.perpendicular_start_stop(w, tool_side) || comp == code::G41_3;
            let perpendicular = inserts.then_some(PerpendicularStart {
                line: self.line,
                n: self.n,
                rapid: self.modes[group::MOTION] == code::G00,
            });
            let machine = self.machine_position();
            self.cfg.stages.comp_started(CompStart { pos: self.pos, machine, perpendicular, table: None });
        }
        // G51/G51.1/G68 take the block's axis words as their data: the block does not move.
        self.apply_wse(w)?;
        let transform_axes = self.apply_transforms(w)? | self.apply_plane(w)?;
        self.apply_dwo(w, dwo_before);
        if transform_axes && axes_owner.is_some() {
            return Err(AlarmId::IllegalGCodeCombination);
        }

        // --- F S T, and the M codes that act before motion ----------------------------------
        self.set_feed(w)?;
        if let Some(e) = w.number(b'E') {
            self.e = e;
        }
        if let Some(s) = w.integer(b'S') {
            if s < 0.0 {
                return Err(AlarmId::ImproperAddress);
            }
            self.s = s;
            if self.spindle != SpindleState::Stop && !w.m[..w.nm].iter().any(|&m| matches!(m, mcode::M03..=mcode::M05))
            {
                self.emit(out, CanonKind::Spindle { state: self.spindle, speed: s });
            }
        }
        if let Some(t) = w.integer(b'T') {
            if t < 0.0 || t.fract() != 0.0 || t > 99_999_999.0 {
                return Err(AlarmId::ImproperAddress);
            }
            self.t = t as u32;
            self.emit(out, CanonKind::ToolSelect { tool: self.t });
        }
        let mut tool_change = None;
        for &m in &w.m[..w.nm] {
            self.last_m = m;
            match m {
                mcode::M03 | mcode::M04 => {
                    self.spindle = if m == mcode::M03 { SpindleState::Cw } else { SpindleState::Ccw };
                    self.emit(out, CanonKind::Spindle { state: self.spindle, speed: self.s });
                }
                mcode::M06 => {
                    self.tool_in_spindle = self.t;
                    tool_change = Some(out.len());
                    self.emit(out, CanonKind::ToolChange { tool: self.t });
                }
                mcode::M07 => self.emit(out, CanonKind::Coolant(Coolant::Mist)),
                mcode::M08 => self.emit(out, CanonKind::Coolant(Coolant::Flood)),
                _ => {}
            }
        }

        // --- tool length compensation (group 08) --------------------------------------------
        // (A G10 block holds no H: `refuse_g10_strangers`.)
        if let Some(h) = w.integer(b'H') {
            self.h = offset_number(h, self.cfg.dialect)?;
            tool_length_changed |= self.modes[group::LENGTH_COMP] != code::G49;
            // Haas: H0 cancels G43/G44 as G49 does (96-8000 rev R, G49); the tool moves
            // by the offset in this block (a G49 block without axis words does not:
            // `g49_in_place_dialect`; no source for H0 either way).
            let haas = self.cfg.dialect == Dialect::Haas;
            if haas && self.h == 0 && matches!(self.modes[group::LENGTH_COMP], code::G43 | code::G44) {
                self.modes[group::LENGTH_COMP] = code::G49;
            }
        }
        self.refuse_length_without_h(w)?;
        if !tool_length_changed && self.restores_length_vector(w, axes_owner, transform_axes) {
            self.refresh_tool_length();
        }
        if tool_length_changed {
            let before = self.tool_vec;
            self.refresh_tool_length();
            // Only a different offset moves the tool (G49 in G49 mode does nothing).
            tool_length_changed = self.tool_vec != before;
        }
        // Tool centre point control starts or ends here (its start and end blocks move by the
        // tool length, computed at their end only).
        let tcp_mode = code::TCP.contains(&self.modes[group::LENGTH_COMP]);
        let mut tcp_switch = false;
        if tcp_mode && w.gcodes().iter().any(|g| code::TCP.contains(g)) {
            self.tcp_begin(w, machine_before)?;
            tool_length_changed = true;
            tcp_switch = true;
        } else if !tcp_mode && self.tcp_active() {
            self.tcp_end();
            tcp_switch = true;
        }
        self.tcp_words(w)?;
        let fanuc_shift = tool_length_changed && !tcp_switch && self.length_shifts_coordinates();
        let in_place = fanuc_shift || self.g49_in_place_dialect(w);
        if in_place && self.length_in_place(w, fanuc_shift, axes_owner.is_none(), machine_before) {
            tool_length_changed = false;
        }
        // The machine stands through a tool change with its block's own state (`docs/conventions.md`,
        // "Positions"): the length the block selects (`T3 M06 H3`) is the new tool's, so its
        // samples show it, not the old tool's (audit of offsets F7).
        if let Some(i) = tool_change {
            out[i].tip_basis = self.tip_basis();
        }

        // --- one-shot G codes ---------------------------------------------------------------
        let mut moved = false;
        for &code in &one_shots[..n_one_shots] {
            moved |= match code {
                // It reads its outline from another block or program (`haas_cycles`).
                code::G150 => self.general_pocket(progs, by_number, w, out)?,
                // The Haas dialect's bolt patterns (`haas_cycles`): the cycle in force at each
                // hole, the block's length change at the move to R.
                code::G70 | code::G71 | code::G72 => self.bolt_pattern(code, w, length_before, out)?,
                _ => self.one_shot(code, w, machine_before, out)?,
            };
        }

        // --- motion -------------------------------------------------------------------------
        self.table_crc_cancel_stop(comp_before, out);
        let has_axes = self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8));
        // G40 with I/J/K in G00/G01 ending offset mode: the direction goes to the cutter
        // compensation stage with the block's motion; without axis words the block still moves
        // (to where it stands: the vector goes there).
        let cancel_direction = (matches!(comp_before, code::G41 | code::G42)
            && w.has_g(code::G40)
            && matches!(self.modes[group::MOTION], code::G00 | code::G01)
            && self.modes[group::CYCLE] == code::G80
            && axes_owner.is_none()
            && !transform_axes)
            .then(|| self.cutter_direction(w))
            .flatten();
        if let Some(d) = cancel_direction {
            self.emit(out, CanonKind::Cutter(CutterWord::CancelDirection(d)));
            if !has_axes {
                let kind = if self.modes[group::MOTION] == code::G00 { MotionKind::Rapid } else { MotionKind::Linear };
                self.push_motion(kind, self.pos, None, out);
                moved = true;
            }
        } else if (matches!(comp_before, code::G41 | code::G42) || code::TOOL_SIDE.contains(&comp_before))
            && self.modes[group::CUTTER_COMP] == code::G40
            && !has_axes
            && axes_owner.is_none()
            && !transform_axes
            && self.modes[group::CYCLE] == code::G80
            && self.perpendicular_start_stop(w, code::TOOL_SIDE.contains(&comp_before))
        {
            // No.5003#1 SUV: a G40 block in G00/G01 without motion removes the vector itself,
            // straight to where the program stands (`stage::cutter`, `stage::tool_side`; under
            // TCP the tool side offset's tip goes there, the axes following it).
            let kind = if self.modes[group::MOTION] == code::G00 { MotionKind::Rapid } else { MotionKind::Linear };
            if self.tcp_active() || self.table_crc_active() {
                self.tip_motion(kind, self.pos, None, out)?;
            } else {
                self.push_motion(kind, self.pos, None, out);
            }
            moved = true;
        } else if comp_before == code::G41_3
            && self.cfg.refuse_unbuilt
            && self.modes[group::CUTTER_COMP] == code::G40
            && !has_axes
            && axes_owner.is_none()
            && !transform_axes
        {
            // The G40 block of the leading edge offset moves the tool back by its vector
            // (`stage::leading_edge`), to where the program stands. (Not in the tests of the
            // mode interlocks, which keep the paths as they were before the stage existed.)
            let kind = if self.modes[group::MOTION] == code::G00 { MotionKind::Rapid } else { MotionKind::Linear };
            if self.follows_tip() {
                self.tip_motion(kind, self.pos, None, out)?;
            } else {
                self.push_motion(kind, self.pos, None, out);
            }
            moved = true;
        }
        // G41/G42 (cutter compensation C) and G41.2/G42.2 given again in their own mode go to
        // their stage before the block's motion, and under the tool side offset Q1/Q2/Q3
        // (`stage::cutter`, `stage::tool_side`; other Q values are refused, `unbuilt`).
        let comp = self.modes[group::CUTTER_COMP];
        let again = matches!(comp, code::G41 | code::G42) || code::TOOL_SIDE.contains(&comp);
        if again && comp_before == comp && w.has_g(comp) {
            self.emit(out, CanonKind::Cutter(CutterWord::Perpendicular));
        }
        if code::TOOL_SIDE.contains(&comp) {
            if let Some(q) = w.integer(b'Q').filter(|_| code::TOOL_SIDE_TYPE1.contains(&comp)) {
                self.emit(out, CanonKind::Cutter(CutterWord::PlaneChange(q as u8)));
            }
        }
        let nurbs_start = w.has_g(code::G06_2);
        if nurbs_start && (axes_owner.is_some() || transform_axes || tool_length_changed) {
            return Err(AlarmId::IllegalGCodeCombination);
        }
        if nurbs_start {
            self.nurbs_start(w)?;
        } else if axes_owner.is_none() && !transform_axes {
            if self.modes[group::CYCLE] != code::G80
                && (has_axes || w.has(b'R') || w.g[..w.ng].iter().any(|&c| is_cycle(c)))
            {
                let drilled = (has_axes || w.has(b'R') || w.has(b'Z')) && self.canned_cycle(w, length_before, out)?;
                moved |= drilled;
                // A block that drills no hole (K0, no position) has no move to R to take the
                // length at: it takes effect at once, as in a block of its own.
                if !drilled && tool_length_changed {
                    self.length_change_move(out)?;
                }
            } else if has_axes
                || (matches!(self.modes[group::MOTION], code::G02 | code::G03)
                    && (w.has(b'I') || w.has(b'J') || w.has(b'K')))
            {
                self.group01_motion(w, out)?;
                moved = true;
            } else if tool_length_changed {
                self.length_change_move(out)?;
            }
        }

        // --- M codes after motion, program end, subprogram calls ----------------------------
        for &m in &w.m[..w.nm] {
            match m {
                mcode::M00 => self.emit(out, CanonKind::Stop { optional: false, message: block.comment.clone() }),
                // Whether M01 stops is the optional stop switch's where the machine reaches it
                // (the controller's panel, `fivex run`'s option), not where it is read ahead.
                mcode::M01 => self.emit(out, CanonKind::Stop { optional: true, message: block.comment.clone() }),
                // Syntec: M02/M30 in an M98 subprogram ends it and returns to the caller, as M99.
                mcode::M02 | mcode::M30 if self.syntec_in_subprogram() => self.return_from_call(progs, None)?,
                mcode::M02 | mcode::M30 => {
                    // The part is counted when the machine gets there (`State::count_part`), not
                    // here: the reading runs ahead of the machine.
                    self.emit(out, CanonKind::ProgramEnd { m });
                    self.ended = true;
                    self.block_limit = 0;
                    self.hpcc_end();
                    self.blend_end();
                    // M02/M30 end cutter compensation (its stage drops the vector there).
                    if code::COMPENSATED_BY_STAGES.contains(&self.modes[group::CUTTER_COMP]) {
                        self.modes[group::CUTTER_COMP] = code::G40;
                    }
                    // Haas: M02/M30 end DWO and TCPC; M30 (not M02) G43/G44 too.
                    self.haas_end_five_axis();
                    if m == mcode::M30 {
                        self.haas_cancel_length_comp();
                    }
                }
                mcode::M05 => {
                    self.spindle = SpindleState::Stop;
                    self.emit(out, CanonKind::Spindle { state: SpindleState::Stop, speed: self.s });
                }
                mcode::M09 => self.emit(out, CanonKind::Coolant(Coolant::Off)),
                mcode::M03 | mcode::M04 | mcode::M06 | mcode::M07 | mcode::M08 => {}
                // Haas: alarm if the last skip move touched (M78) or did not (M79).
                mcode::M78 if self.cfg.dialect == crate::Dialect::Haas && self.skip.found => {
                    return Err(AlarmId::SkipSignalFound)
                }
                mcode::M79 if self.cfg.dialect == crate::Dialect::Haas && !self.skip.found => {
                    return Err(AlarmId::SkipSignalNotFound)
                }
                mcode::M78 | mcode::M79 if self.cfg.dialect == crate::Dialect::Haas => {}
                mcode::M97 if self.cfg.dialect == crate::Dialect::Haas => {
                    // Haas local subprogram: N<P> of this program, L times, back after M99.
                    if let Some(Call { prog, count, at: Some(to) }) = call {
                        if count > 0 {
                            self.push_frame(progs, prog, count, None)?;
                            self.start_at(to);
                        }
                    }
                }
                mcode::M98 | mcode::M198 => {
                    if let Some(Call { prog, count, .. }) = call {
                        self.push_frame(progs, prog, count, None)?;
                    }
                }
                mcode::M99 => {
                    let to_n = match w.integer(b'P') {
                        Some(p) => Some(sequence_number(p).ok_or(AlarmId::LineNotFound)?),
                        None => None,
                    };
                    self.return_from_call(progs, to_n)?;
                }
                other => self.emit(out, CanonKind::Aux { m: other }),
            }
        }
        // The table coordinate system of 5-axis cutter compensation without TCP is frozen after
        // the start block's move and left after the G40 block's (`table_crc`).
        self.table_crc_after_block(comp_before, first, out);
        if moved && !self.ended {
            if let Some(mc) = self.modal_call_here() {
                if !mc.every_block {
                    let (prog, count, serial) = (mc.prog, mc.count, mc.serial);
                    let locals = self.modal_call_locals(mc);
                    let depth = self.frames.len();
                    self.push_frame(progs, prog, count, Some(locals))?;
                    if self.cfg.dialect == Dialect::Syntec && self.frames.len() > depth {
                        self.frame_mut().modal = Some(serial);
                    }
                }
            }
        }
        Ok(())
    }

    /// F: mm/min (inch/min is converted), or 1/min under G93. An inverse time has no length
    /// unit: written without a decimal point FANUC counts it in 0.001 (DPI = 0) "regardless of
    /// whether the input mode is inches or metric" (16/18-MC B-62764EN/01, §5 "Inverse time
    /// feed": F1 is FRN 0.001); the Haas dialect refuses it (its sources give Setting 77's
    /// increment for feeds in in/min and mm/min only, `docs/dialects.md`, "Haas").
    pub(super) fn set_feed(&mut self, w: &Words) -> Result<(), AlarmId> {
        if let Some((f, form)) = w.word(b'F') {
            let inverse_time = self.modes[group::FEED_MODE] == code::G93;
            let f = match self.cfg.dialect {
                _ if form != Form::NoPoint || self.cfg.pocket_calculator => f,
                crate::Dialect::Fanuc if inverse_time => f * 0.001,
                crate::Dialect::Haas if inverse_time => return Err(AlarmId::AddressNotBuilt),
                _ if self.counts_increments(b'F') => f * self.increment(),
                _ => f,
            };
            if f < 0.0 {
                return Err(AlarmId::ImproperAddress);
            }
            self.f = if self.inch() && self.modes[group::FEED_MODE] != code::G93 { f * 25.4 } else { f };
        }
        Ok(())
    }

    /// Syntec: the running program was called by M98/M198 (not G65/G66, not the main program).
    /// There M02/M30 "视同结束子程序并返回主程序" — is taken as the subprogram's end and returns
    /// to the caller (the Syntec MACRO handbook's call semantics pack §2.2, citing Syntec's
    /// "副程序控制(M98)(M99)(C-type)"): like M99, with no part counted and no reset of modes.
    fn syntec_in_subprogram(&self) -> bool {
        self.cfg.dialect == crate::Dialect::Syntec && self.frames.last().is_some_and(|f| f.kind == CallKind::Sub)
    }

    /// Syntec: an M02/M30 whose meaning the handbook leaves open — in a G65/G66 macro (it speaks
    /// of subprograms only), or in a subprogram whose call has repetitions (L) still to come
    /// (whether they run is not said) — is refused as not built rather than end the whole run.
    fn syntec_end_not_built(&self, w: &Words) -> bool {
        let ends = w.mcodes().iter().any(|&m| m == mcode::M02 || m == mcode::M30);
        let frame = self.frames.last().expect("frame");
        self.cfg.dialect == crate::Dialect::Syntec
            && ends
            && (frame.kind == CallKind::Macro || frame.kind == CallKind::Sub && frame.repeats > 0)
    }

    /// The subprogram the block's M98/M198 (Haas: M97) calls, found before the block runs.
    fn call_target(&self, progs: &[Slot], by_number: &HashMap<u32, usize>, w: &Words) -> Result<Option<Call>, AlarmId> {
        let haas = self.cfg.dialect == crate::Dialect::Haas;
        for &m in w.mcodes() {
            if m == mcode::M97 && haas {
                let n = w.integer(b'P').ok_or(AlarmId::MissingP)?;
                let count = Self::count(w)?;
                let (prog, pc) = self.frames.last().map_or((0, 0), |f| (f.prog, f.pc));
                let from = pc.saturating_sub(1);
                let to = sequence_number(n).and_then(|n| progs[prog].find_label(n, from));
                let to = to.ok_or(AlarmId::LineNotFound)?;
                if progs[prog].jump_enters_loop(from, to) {
                    return Err(AlarmId::IllegalLoopNumber);
                }
                return Ok(Some(Call { prog, count, at: Some(to) }));
            }
            if mcode::SUBPROGRAM_CALLS.contains(&m) {
                let (prog, count) = self.subprogram_target(by_number, w)?;
                return Ok(Some(Call { prog, count, at: None }));
            }
        }
        Ok(None)
    }

    /// M98 P… L…, or (FANUC) P with the count in front of a four-digit number (`P30010` = O0010
    /// ×3). Haas: P is the program number (O00001–O99999) and L the count; no P is alarm 313.
    /// Syntec: the same, P is the program's name and L the count (the Syntec MACRO handbook §5.1,
    /// CALL-M98-001: no count in P, so `P12345` is O12345); M198 without P is the handbook's
    /// COR-052, and M98 without P, which calls the running program itself there, is not built
    /// (`docs/dialects.md`, "Syntec's subprogram and macro calls").
    fn subprogram_target(&self, by_number: &HashMap<u32, usize>, w: &Words) -> Result<(usize, u32), AlarmId> {
        let dialect = self.cfg.dialect;
        let Some(p) = w.integer(b'P') else {
            return Err(match dialect {
                crate::Dialect::Haas => AlarmId::MissingP,
                crate::Dialect::Syntec if w.mcodes().contains(&mcode::M198) => AlarmId::MissingP,
                crate::Dialect::Syntec => AlarmId::MCodeNotBuilt,
                crate::Dialect::Fanuc => AlarmId::MissingP,
            });
        };
        if dialect != crate::Dialect::Fanuc || w.has(b'L') || p < 10_000.0 {
            return Ok((self.find_program(by_number, Some(p))?, Self::count(w)?));
        }
        let count = (p / 10_000.0).trunc();
        let number = p - count * 10_000.0;
        Ok((self.find_program(by_number, Some(number))?, count as u32))
    }

    /// A tool length offset taking effect at once: the tool moves, the programmed point stays.
    fn length_change_move(&mut self, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let target = self.pos;
        let kind = if self.modes[group::MOTION] == code::G00 { MotionKind::Rapid } else { MotionKind::Linear };
        if kind == MotionKind::Linear {
            self.check_feed()?;
        }
        if self.follows_tip() {
            self.tip_motion(kind, target, None, out)?;
        } else {
            self.push_motion(kind, target, None, out);
        }
        Ok(())
    }

    /// FANUC: the dwell's P (G04, the canned cycles' dwell at the bottom) is a whole number of
    /// milliseconds, and a decimal point at an address that takes none is PS0007 (the 30i's
    /// alarm list): `P1.5` meant as 1.5 s would otherwise dwell 1.5 ms. A variable or an
    /// expression is rounded as at any such address. Syntec and Haas keep their readings
    /// (`docs/dialects.md`).
    pub(super) fn refuse_point_at_dwell_p(&self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect == crate::Dialect::Fanuc && w.has_point(b'P') {
            return Err(AlarmId::IllegalDecimalPoint);
        }
        Ok(())
    }

    /// FANUC: H, D and T name an offset or a tool, and the P of G54.1 (or G54) a work system:
    /// numbers without a decimal point, so one written with a point is PS0007 ("a decimal
    /// point specified at an address where no decimal point may be specified", the 30i's alarm
    /// list), as at L and the dwell's P; `H1.` ran as H1. A variable or an expression is
    /// rounded as at any such address; a macro call's arguments (G65/G66) were taken before.
    /// Syntec and Haas read the whole value (`docs/conventions.md`, "Units and numbers").
    fn refuse_point_at_numbers(&self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect != crate::Dialect::Fanuc {
            return Ok(());
        }
        let work_p = w.has_g(code::G54_1) || w.has_g(code::G54);
        if [b'H', b'D', b'T'].into_iter().any(|l| w.has_point(l)) || (work_p && w.has_point(b'P')) {
            return Err(AlarmId::IllegalDecimalPoint);
        }
        Ok(())
    }

    /// The dwell a P word of the block asks for (G04, and the canned cycles' dwell), seconds:
    /// P counts milliseconds, except that in the Haas dialect a P written with a decimal point
    /// counts seconds (`docs/dialects.md`, "Decimal point": the NGC's G82 example `P0.3`, the
    /// G83 page's `P5.` "five seconds"). A P given by an expression counts milliseconds.
    pub(super) fn dwell_p_seconds(&self, w: &Words, p: f64) -> f64 {
        let haas_seconds =
            self.cfg.dialect == crate::Dialect::Haas && w.word(b'P').is_some_and(|(_, form)| form == Form::Point);
        if haas_seconds {
            p
        } else {
            p / 1000.0
        }
    }

    /// Tool length offset vector from group 08 and H (along Z: FANUC tool length type A). A
    /// selection re-establishes a vector a reference return cancelled.
    pub(super) fn refresh_tool_length(&mut self) {
        self.length_cancelled = false;
        let mut v = [0.0; MAX_AXES];
        if let Some(z) = self.axis_of(b'Z') {
            v[z] = self.signed_tool_length();
        }
        self.tool_vec = v;
    }

    /// FANUC/Syntec: G28/G30 (the return to the reference position) and G53 that move the tool
    /// length offset axis Z in G43/G44 cancel the offset vector; the mode stays G43/G44 and H
    /// stays selected (FANUC 0i-MB B-63844EN §14.1.2: "tool length offset vectors are canceled
    /// … the previously specified modal G code remains displayed"). So the `G49` posts write
    /// after `G28 G91 Z0.` has nothing left to remove. Called before the machine motion, whose
    /// end point is then read without the vector. In the tilted plane the whole length along
    /// the tool goes (*decision*, `docs/five-axis.md`). Haas cancels G43 itself at G28
    /// (`haas_cancel_length_comp`).
    fn cancel_length_vector(&mut self, w: &Words) {
        let in_length_comp = matches!(self.modes[group::LENGTH_COMP], code::G43 | code::G44);
        if self.cfg.dialect == Dialect::Haas || !in_length_comp || !w.has(b'Z') || self.axis_of(b'Z').is_none() {
            return;
        }
        self.length_cancelled = true;
        self.tool_vec = [0.0; MAX_AXES];
    }

    /// Whether the block re-establishes a vector a reference return cancelled: it moves Z
    /// (not as the data of G10/G52/G92/G68/G51, nor as a G28/G30/G53 return, which keeps it
    /// cancelled). *Decision* (the manual's page on restoration is not in the text at hand):
    /// the next move of the offset axis, its end point with the vector, as a G43 H block's;
    /// a move of other axes leaves Z where the return put it.
    fn restores_length_vector(&self, w: &Words, axes_owner: Option<u16>, transform_axes: bool) -> bool {
        self.length_cancelled
            && w.has(b'Z')
            && !transform_axes
            && axes_owner.is_none_or(|g| matches!(g, code::G29 | code::G31))
    }

    /// Haas: a G28 without axis words returns every axis, the rotary ones too, to machine zero
    /// (96-8000 rev R, G28: "all axes … unless an axis (or axes) is specified"). FANUC's G28
    /// moves only the axes it names.
    fn g28_returns_every_axis(&self, w: &Words) -> bool {
        self.cfg.dialect == Dialect::Haas && !self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8))
    }

    /// Haas: a block that selects G43/G44 with no tool length offset H in it or in force (none
    /// since power-on or a reset, or H0) is refused (`754`, constructed). The length would be
    /// 0: `G43 Z50.` would put the spindle nose at Z50., the real tip a tool length below it.
    /// No Haas source says what the NGC does (*decision*, `docs/dialects.md`, "Haas:
    /// the dialect's core", as G234 without H). FANUC and Syntec run it with H0's length 0.
    fn refuse_length_without_h(&self, w: &Words) -> Result<(), AlarmId> {
        let selects = matches!(self.block_code(w, group::LENGTH_COMP), Some(code::G43 | code::G44));
        let in_force = matches!(self.modes[group::LENGTH_COMP], code::G43 | code::G44);
        if self.cfg.dialect == Dialect::Haas && selects && in_force && self.h == 0 {
            return Err(AlarmId::LengthCompWithoutH);
        }
        Ok(())
    }

    /// Haas and Syntec: a G49 block (G43/G44, G234 or RTCP ending) moves nothing when it has no
    /// axis words (`length_in_place`). Haas: `docs/dialects.md`, "Haas 5-axis" (Autodesk's Haas
    /// NGC post ends every TCPC section with `G49 (TCPC OFF)` at its last cutting point and then
    /// retracts with `G53 G0 Z`, which a G49 that dropped the spindle by the tool length would
    /// crash). Syntec: *decision*, `docs/dialects.md`, "Syntec G49" (the manual's G49 cancels
    /// "tool tip control" and describes no motion; Autodesk's SYIL post writes G49 at clearance
    /// height before G69 and the retract).
    fn g49_in_place_dialect(&self, w: &Words) -> bool {
        matches!(self.cfg.dialect, Dialect::Haas | Dialect::Syntec) && w.has_g(code::G49)
    }

    /// FANUC with No.5006#6 TOS = 1 (`five_axis.length_offset_by_motion` false, fivex's
    /// default): tool length offset shifts the coordinate system instead of moving the axes,
    /// so a G43/G44/G49 or H block moves nothing by itself (`docs/five-axis.md`, "TOS";
    /// Autodesk's fanuc.cps requires it: "Ensure that the G49 command does not cause axis
    /// movement"). TCP's start and end blocks move by the length all the same (TCP-03, TCP-17):
    /// the caller leaves them out.
    fn length_shifts_coordinates(&self) -> bool {
        self.cfg.dialect == Dialect::Fanuc && !self.cfg.machine.five_axis.length_offset_by_motion
    }

    /// A length change in a block that runs no canned cycle (whose length is taken at the move
    /// to R) moves nothing by itself: the current point is read again where the machine
    /// stands, and the length is in force from the next move of the axis on. Haas/Syntec G49:
    /// only without axis words. FANUC TOS = 1 (`shift`): with axis words too, so that a G90
    /// move ends where it would have anyway, an axis the block does not name stays, and a G91
    /// move moves by its increment only. Returns whether it applied (`machine`: where the
    /// machine stands).
    fn length_in_place(&mut self, w: &Words, shift: bool, owns_axes: bool, machine: Pos) -> bool {
        let axis_words = self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8));
        let cycle = self.modes[group::CYCLE] != code::G80
            && (axis_words || w.has(b'R') || w.gcodes().iter().any(|&c| is_cycle(c)));
        if (axis_words && !shift) || !owns_axes || cycle {
            return false;
        }
        self.follow_machine = None;
        if self.plane_active() {
            self.plane_moved_to(machine);
        } else if self.wse_follows() {
            // G54.4 with RCM = 1 (TOS = 1 is its condition, WSE-24): the tip in the WSCS with
            // the new length, the rotary coordinates the programmed angles.
            self.wse_moved_to(machine);
        } else {
            self.pos = self.machine_to_program(&machine);
            self.sync_programmed();
        }
        true
    }

    /// Haas: H0, G28, M30 and reset cancel tool length compensation (96-8000 rev R, G49; the
    /// G28 page: "for the following lines of code"), the machine staying where it is; FANUC
    /// keeps G43/G44 through them. G234 has its own end (`haas_end_five_axis`).
    pub(super) fn haas_cancel_length_comp(&mut self) {
        if self.cfg.dialect != Dialect::Haas || !matches!(self.modes[group::LENGTH_COMP], code::G43 | code::G44) {
            return;
        }
        let machine = self.machine_position();
        self.modes[group::LENGTH_COMP] = code::G49;
        self.refresh_tool_length();
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
    }

    /// The tool length group 08 applies along the tool: +H (G43, G43.4…), −H (G44), 0 (G49).
    pub(super) fn signed_tool_length(&self) -> f64 {
        let length = self.offsets.length(self.h);
        match self.modes[group::LENGTH_COMP] {
            code::G49 | code::G49_1 => 0.0,
            code::G44 => -length,
            _ => length,
        }
    }

    pub(super) fn context(&self) -> MotionContext {
        // (A vector a reference return cancelled is no length in effect.)
        let length_on = !code::LENGTH_CANCEL.contains(&self.modes[group::LENGTH_COMP]) && !self.length_cancelled;
        let comp_on = self.modes[group::CUTTER_COMP] != code::G40;
        MotionContext {
            plane: self.modes[group::PLANE],
            wcs: self.modes[group::WORK_SYSTEM],
            wcs_p: self.wcs_p,
            length_comp: self.modes[group::LENGTH_COMP],
            h: self.h,
            tool_length: if length_on { self.offsets.length(self.h) } else { 0.0 },
            cutter_comp: self.modes[group::CUTTER_COMP],
            d: self.d,
            cutter_radius: if comp_on { self.radius } else { 0.0 },
            path_mode: self.modes[group::PATH_MODE],
            exact_stop: self.exact_stop || self.modes[group::PATH_MODE] == code::G61,
            fixed_feed: self.modes[group::PATH_MODE] == code::G63 || code::TAPPING.contains(&self.modes[group::CYCLE]),
            // Set on the motions of a canned cycle where it makes them (`cycles.rs`).
            tapping: crate::canon::Tapping::No,
            cycle_stop: false,
            rotation: self.modes[group::ROTATION],
            // S000 III.2: "In the mode of Workpiece setting error compensation, Stroke limit
            // check before movement is not available."
            no_stroke_precheck: self.wse.is_some(),
        }
    }

    /// A motion's feed and its mode; `radius`: an arc's (at its start, mm). FANUC feeds an
    /// arc in G93 at FRN × its radius: "For circular interpolation FRN = 1/time (min) =
    /// feedrate / arc radius … the feedrate is calculated not from the actual amount of
    /// movement in the block but from the arc radius" (FANUC 16/18-MC B-62764EN/01, §5
    /// "Inverse time feed"), so the arc is fed per minute at that rate, as an F of G94 would
    /// be (its plane part takes swept angle in rad / FRN minutes). The Haas dialect keeps
    /// 60/F seconds for every motion (its G93 page); Syntec's G93 arc is refused (`arc`).
    fn feed_of(&self, radius: Option<f64>) -> (f64, FeedMode) {
        match (self.feed_mode(), radius) {
            (FeedMode::InverseTime, Some(r)) if self.cfg.dialect == crate::Dialect::Fanuc => {
                (self.f * r, FeedMode::PerMinute)
            }
            (mode, _) => (self.f, mode),
        }
    }

    pub(super) fn feed_mode(&self) -> FeedMode {
        match self.modes[group::FEED_MODE] {
            code::G93 => FeedMode::InverseTime,
            code::G95 => FeedMode::PerRevolution,
            _ => FeedMode::PerMinute,
        }
    }

    /// Move to a point in programmed coordinates: it goes through the programming transforms
    /// (`frames`) and becomes the current point.
    pub(super) fn move_to(&mut self, kind: MotionKind, programmed: Pos, out: &mut Vec<Canon>) {
        let target = self.xf.forward(&programmed);
        self.push_motion(kind, target, None, out);
        self.xf.programmed = programmed;
    }

    /// Emit a motion to `target` (workpiece coordinates, after the programming transforms) and
    /// make it the current point; the caller keeps the programmed point.
    pub(super) fn push_motion(&mut self, kind: MotionKind, target: Pos, arc: Option<Box<Arc>>, out: &mut Vec<Canon>) {
        let machine = self.program_to_machine(&target);
        self.emit_motion_at(kind, target, machine, arc, out);
        // A plain move (canned cycle, G28 intermediate point) under G54.4 tool direction
        // compensation: the machine position kept beside the tip is this one now.
        self.wse_plain_move_done(machine);
    }

    /// Emit a motion whose end point is known in both systems and make it the current point.
    fn emit_motion_at(
        &mut self,
        kind: MotionKind,
        target: Pos,
        machine: Pos,
        arc: Option<Box<Arc>>,
        out: &mut Vec<Canon>,
    ) {
        let mut motion = self.motion(kind, target, machine, arc, None);
        if self.wse.is_some() {
            self.wse_display(&mut motion);
        }
        self.emit(out, CanonKind::Motion(motion));
        self.pos = target;
    }

    /// The block being read, as the motions of a move held across blocks name it (nano
    /// smoothing, G187 corner rounding, a `,C`/`,R` corner).
    pub(super) fn block_tag(&self) -> super::BlockTag {
        (self.line, self.n, self.f)
    }

    /// `emit` as the block `tag`: the motions it makes carry that block's line, sequence number
    /// and F; then back to the block being read.
    pub(super) fn as_block<T>(&mut self, tag: super::BlockTag, emit: impl FnOnce(&mut State) -> T) -> T {
        let here = self.block_tag();
        (self.line, self.n, self.f) = tag;
        let result = emit(self);
        (self.line, self.n, self.f) = here;
        result
    }

    /// A motion with the block's feed, spindle speed and modal context.
    pub(super) fn motion(
        &self,
        kind: MotionKind,
        target: Pos,
        machine: Pos,
        arc: Option<Box<Arc>>,
        tip: Option<Box<crate::canon::TipMove>>,
    ) -> Motion {
        let radius =
            arc.as_ref().map(|a| a.radius).or_else(|| tip.as_deref().and_then(crate::canon::TipMove::arc_radius));
        let (feed, feed_mode) = self.feed_of(radius);
        Motion {
            kind,
            target,
            machine,
            arc,
            tip,
            feed,
            feed_mode,
            spindle: self.s,
            context: self.context(),
            speed_cap: f32::INFINITY,
            offset: None,
            notice: None,
            block_limit: self.block_limit,
            no_look_ahead: !self.look_ahead || {
                let motion = &self.cfg.machine.motion;
                match kind {
                    MotionKind::Rapid | MotionKind::MachineRapid => motion.no_rapid_look_ahead,
                    _ => motion.no_feed_look_ahead,
                }
            },
        }
    }

    /// A rapid of a reference return to a program point (G28/G30's intermediate point, G29's
    /// end point): through the programming transforms like any point, and in the tilted plane
    /// an FCS point the tip goes to like a G00 there (twp §1.3.2 allows G28/G29/G30 in the
    /// plane; only the return itself is in machine coordinates, TWP-13, OQ-16).
    fn rapid_to_program_point(&mut self, programmed: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        self.rapid_to_workpiece_point(self.xf.forward(&programmed), out)?;
        self.xf.programmed = programmed;
        Ok(())
    }

    /// As `rapid_to_program_point` for a point after the programming transforms; the caller
    /// keeps the programmed point.
    fn rapid_to_workpiece_point(&mut self, target: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        if self.plane_active() {
            self.tip_motion(MotionKind::Rapid, target, None, out)
        } else {
            self.push_motion(MotionKind::Rapid, target, None, out);
            Ok(())
        }
    }

    /// A motion in machine coordinates (G53, reference returns). Its programmed point is the
    /// current point after it, in the system the block programs in: in a tilted plane the tip
    /// in the FCS (TWP-13), under G54.4's tool direction compensation the tip in the WSCS
    /// (the workpiece point read off the machine would be another system's under that name).
    fn emit_machine_motion(&mut self, machine: Pos, out: &mut Vec<Canon>) {
        self.pos = self.machine_to_program(&machine);
        self.plane_moved_to(machine);
        self.wse_moved_to(machine);
        self.emit_motion_at(MotionKind::MachineRapid, self.pos, machine, None, out);
        self.sync_programmed();
    }

    /// The end point of the block's axis words (absolute or incremental, polar under G16) in
    /// programmed coordinates, before the programming transforms.
    pub(super) fn target(&self, w: &Words) -> Pos {
        self.programmed_target(w, None)
    }

    /// In G93 F is each block's own (Mitsubishi M700V §7.5: "The F command in G93 modal is
    /// unmodal. Issue an F command for each block"; RS274/NGC), so a cutting block without F
    /// is PS0011, as is the first one after G93 is left without a new F (FANUC A-91417E:
    /// PS0011 after a group-05 change): an inverse time is no feed of G94/G95 either way.
    fn forget_inverse_time_feed(&mut self) {
        if self.modes[group::FEED_MODE] == code::G93 {
            self.f = 0.0;
        }
    }

    /// A cutting block's feed: F given (PS0011 without), and in G95 a turning spindle: the
    /// feed per revolution follows the spindle's position coder, so with the spindle stopped
    /// (M05, S0) a control waits without end; fivex says so at the block (FX0009, decision).
    /// Dry run feeds at its own rate per minute, the spindle no matter: no wait there.
    pub(super) fn check_feed(&self) -> Result<(), AlarmId> {
        if self.f <= 0.0 {
            return Err(AlarmId::FeedZero);
        }
        let stopped = self.spindle == SpindleState::Stop || self.s <= 0.0;
        if self.modes[group::FEED_MODE] == code::G95 && stopped && !self.dry_run {
            return Err(AlarmId::FeedPerRevolutionSpindleStopped);
        }
        Ok(())
    }

    pub(super) fn group01_motion(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let programmed = self.target(w);
        if self.smoothing_point_block() {
            self.check_feed()?;
            self.smoothing_point(self.xf.forward(&programmed), out)?;
            self.xf.programmed = programmed;
            return Ok(());
        }
        if self.blend_point_block() {
            self.check_feed()?;
            self.blend_point(self.xf.forward(&programmed), out)?;
            self.xf.programmed = programmed;
            return Ok(());
        }
        if matches!(self.modes[group::MOTION], code::G01 | code::G02 | code::G03) && self.corner_motion_block(w) {
            return self.corner_motion(w, programmed, out);
        }
        if self.follows_tip() {
            let target = self.xf.forward(&programmed);
            let (kind, arc) = match self.modes[group::MOTION] {
                code::G00 => (MotionKind::Rapid, None),
                code::G02 | code::G03 => {
                    self.check_feed()?;
                    let (cw, arc) = self.arc(w, &target)?;
                    (if cw { MotionKind::ArcCw } else { MotionKind::ArcCcw }, arc)
                }
                _ => {
                    self.check_feed()?;
                    (MotionKind::Linear, None)
                }
            };
            let reread = self.tcp_start_changes_system();
            self.tip_motion(kind, target, arc, out)?;
            if !reread {
                self.xf.programmed = programmed;
            }
            return Ok(());
        }
        match self.modes[group::MOTION] {
            code::G00 => self.move_to(MotionKind::Rapid, programmed, out),
            code::G02 | code::G03 => {
                self.check_feed()?;
                let target = self.xf.forward(&programmed);
                let (cw, arc) = self.arc(w, &target)?;
                let kind = if cw { MotionKind::ArcCw } else { MotionKind::ArcCcw };
                match arc {
                    Some(arc) if self.wse_arc() => self.wse_arc_motion(kind, target, arc, out)?,
                    arc => self.push_motion(kind, target, arc, out),
                }
                self.xf.programmed = programmed;
            }
            _ => {
                self.check_feed()?;
                self.move_to(MotionKind::Linear, programmed, out);
            }
        }
        Ok(())
    }

    /// G39 corner circular interpolation (FANUC 15i §14.4.9): only in offset mode, after G41/G42
    /// was given (in G40 or in a block with a group-07 code: PS0010), without a move command
    /// (PS0273). The block emits the corner word, then a motion that does not move, which the
    /// cutter compensation stage turns into the arc. It is cut at the F in force whatever the
    /// group-01 mode (no F yet: PS0011; FANUC's No.1493 rate is not modelled).
    fn corner_arc(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let group07_here = [code::G40, code::G41, code::G42].iter().any(|&c| w.has_g(c));
        if group07_here || !matches!(self.modes[group::CUTTER_COMP], code::G41 | code::G42) {
            return Err(AlarmId::ImproperGCode);
        }
        if self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8)) {
            return Err(AlarmId::CornerArcWithMove);
        }
        self.check_feed()?;
        let direction = self.cutter_direction(w);
        self.emit(out, CanonKind::Cutter(CutterWord::CornerArc(direction)));
        let motion = self.motion(MotionKind::Linear, self.pos, self.program_to_machine(&self.pos), None, None);
        self.emit(out, CanonKind::Motion(motion));
        Ok(())
    }

    /// G38 vector hold (NCT 99M/2000M §14.5.5, Mitsubishi M700V §12.4): only in offset mode,
    /// after G41/G42 was given (in G40 or in a block with a group-07 code: PS0010), in G00/G01
    /// (G02/G03: PS0010). The block emits the hold word before its motion; the cutter
    /// compensation stage ends that motion at its programmed point plus the vector where it
    /// starts, or plus the offset value along I/J/K. A G38 with I/J/K and no axis word moves to
    /// where it stands (the vector goes there); one with neither does nothing.
    fn vector_hold(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        let group07_here = [code::G40, code::G41, code::G42].iter().any(|&c| w.has_g(c));
        if group07_here
            || !matches!(self.modes[group::CUTTER_COMP], code::G41 | code::G42)
            || !matches!(self.modes[group::MOTION], code::G00 | code::G01)
        {
            return Err(AlarmId::ImproperGCode);
        }
        let direction = self.cutter_direction(w);
        let has_axes = self.cfg.machine.axes.iter().any(|a| w.has(a.name as u8));
        if !has_axes && direction.is_none() {
            return Ok(false);
        }
        self.emit(out, CanonKind::Cutter(CutterWord::VectorHold(direction)));
        if has_axes {
            return Ok(false);
        }
        let kind = if self.modes[group::MOTION] == code::G00 { MotionKind::Rapid } else { MotionKind::Linear };
        self.push_motion(kind, self.pos, None, out);
        Ok(true)
    }

    /// Start-up and cancel "perpendicular to the next movement" (FANUC No.5003#1 SUV = 1,
    /// `motion.cutter_startup_perpendicular`) apply to this G41/G42/G40 block: it is in G00/G01
    /// and has no axis word of the plane (`docs/cutter-compensation.md`, rule 13) — for the tool
    /// side offset (`tool_side`), whose plane is perpendicular to the tool, no X, Y or Z word.
    fn perpendicular_start_stop(&self, w: &Words, tool_side: bool) -> bool {
        let letters: &[u8] = match self.modes[group::PLANE] {
            _ if tool_side => b"XYZ",
            code::G18 => b"ZX",
            code::G19 => b"YZ",
            _ => b"XY",
        };
        self.cfg.machine.motion.cutter_startup_perpendicular
            && matches!(self.modes[group::MOTION], code::G00 | code::G01)
            && !letters.iter().any(|&l| w.has(l))
    }

    /// The I/J/K of a cutter compensation block as a direction (I along X, J along Y, K along Z),
    /// when one of the two of the plane is given and they are not both zero.
    fn cutter_direction(&self, w: &Words) -> Option<[f64; 3]> {
        let letters: [u8; 2] = match self.modes[group::PLANE] {
            code::G18 => [b'K', b'I'],
            code::G19 => [b'J', b'K'],
            _ => [b'I', b'J'],
        };
        if !letters.iter().any(|&l| w.has(l)) {
            return None;
        }
        let d = [b'I', b'J', b'K'].map(|l| self.value(w, l).unwrap_or(0.0));
        let in_plane = letters.map(|l| d[(l - b'I') as usize]);
        (in_plane.iter().any(|x| *x != 0.0)).then_some(d)
    }

    /// The plane's first, second and normal axis indices.
    pub(super) fn plane_axes(&self) -> Result<(usize, usize, usize), AlarmId> {
        let m = &self.cfg.machine;
        let (a, b, c) = match self.modes[group::PLANE] {
            code::G18 => (b'Z', b'X', b'Y'),
            code::G19 => (b'Y', b'Z', b'X'),
            _ => (b'X', b'Y', b'Z'),
        };
        match (m.axis_index(a), m.axis_index(b), m.axis_index(c)) {
            (Some(a), Some(b), Some(c)) => Ok((a, b, c)),
            _ => Err(AlarmId::ImproperGCode),
        }
    }

    /// The drilling axis of canned cycles: the plane normal.
    pub(super) fn drill_axis(&self) -> Option<usize> {
        self.plane_axes().ok().map(|(_, _, c)| c)
    }

    /// Circle geometry of a G02/G03 block from I/J/K or R, in workpiece coordinates (`target`
    /// is the end point after the programming transforms), and whether it turns clockwise there
    /// (a mirror image swaps G02 and G03). No geometry for an R arc whose end point equals its
    /// start (no movement in the plane).
    pub(super) fn arc(&self, w: &Words, target: &Pos) -> Result<(bool, Option<Box<Arc>>), AlarmId> {
        // No Syntec source says how its G93 times an arc (FANUC's FRN × radius or the block's
        // 1/F minutes): refused rather than guessed (`docs/motion.md`, "G93 on arcs").
        let inverse_time = self.modes[group::FEED_MODE] == code::G93;
        if inverse_time && self.cfg.dialect == crate::Dialect::Syntec && self.cfg.refuse_unbuilt {
            return Err(AlarmId::GCodeNotBuilt);
        }
        let (a, b, c) = self.plane_axes()?;
        // Under TCP in the workpiece system a circle is on the table: where the table turns in
        // the block, its start (and centre) are read where the table carries them by the end.
        let carry = self.workpiece_arc_carry(target, c)?;
        let start = carry.as_ref().map_or(self.pos, |m| m.point(&self.pos));
        let (sx, sy) = (start[a], start[b]);
        let (ex, ey) = (target[a], target[b]);
        let ijk = |axis: usize| -> Option<f64> {
            let letter = match self.cfg.machine.axes[axis].name {
                'X' => b'I',
                'Y' => b'J',
                _ => b'K',
            };
            self.value(w, letter)
        };
        // Under TCP type 2, I/J/K are the tool direction: the circle is given by R only, and a
        // full circle cannot be (TCP-10; the manual names no alarm, PS5421 is its family's).
        let by_radius = self.ijk_is_direction();
        if by_radius && (!w.has(b'R') || (target[a] - sx).hypot(target[b] - sy) < 1e-9) {
            return Err(AlarmId::IllegalCommandInTcp);
        }
        // Neither R nor a centre word of the plane: the control has no circle (FANUC PS0022; its
        // No.3403#5 CIR, which makes such a block a straight move, is not modelled). Read as a
        // centre at the start, it was PS0020, the alarm of a circle that is given.
        if !by_radius && !w.has(b'R') && ijk(a).is_none() && ijk(b).is_none() {
            return Err(AlarmId::ArcCentreMissing);
        }
        let offset = if by_radius { (0.0, 0.0) } else { (ijk(a).unwrap_or(0.0), ijk(b).unwrap_or(0.0)) };
        let words =
            super::frames::ArcWords { r: self.value(w, b'R'), offset, cw: self.modes[group::MOTION] == code::G02 };
        let super::frames::ArcWords { r: radius, offset, cw } = self.arc_words((a, b), words)?;
        let offset = carry.as_ref().map_or(offset, |m| m.vector((a, b), offset));
        let (cx, cy) = if let Some(r) = radius {
            let (dx, dy) = (ex - sx, ey - sy);
            let d = (dx * dx + dy * dy).sqrt();
            if d < 1e-9 {
                return Ok((cw, None));
            }
            let half = d / 2.0;
            if half - r.abs() > self.cfg.arc_tolerance {
                return Err(AlarmId::ArcRadiusTolerance);
            }
            let h = (r * r - half * half).max(0.0).sqrt();
            let (ux, uy) = (dx / d, dy / d);
            // Left normal of the chord; CCW arcs of at most 180° have their center on the left.
            let side = if cw { -1.0 } else { 1.0 } * if r < 0.0 { -1.0 } else { 1.0 };
            (sx + dx / 2.0 - side * h * uy, sy + dy / 2.0 + side * h * ux)
        } else {
            (sx + offset.0, sy + offset.1)
        };
        let r0 = ((sx - cx).powi(2) + (sy - cy).powi(2)).sqrt();
        let r1 = ((ex - cx).powi(2) + (ey - cy).powi(2)).sqrt();
        if (r0 - r1).abs() > self.cfg.arc_tolerance || r0 < 1e-9 {
            return Err(AlarmId::ArcRadiusTolerance);
        }
        let a0 = (sy - cy).atan2(sx - cx);
        let a1 = (ey - cy).atan2(ex - cx);
        let full = (ex - sx).abs() < 1e-9 && (ey - sy).abs() < 1e-9;
        let tau = std::f64::consts::TAU;
        let sweep = if cw {
            let s = (a0 - a1).rem_euclid(tau);
            -(if full || s == 0.0 { tau } else { s })
        } else {
            let s = (a1 - a0).rem_euclid(tau);
            if full || s == 0.0 {
                tau
            } else {
                s
            }
        };
        let mut center = start;
        center[a] = cx;
        center[b] = cy;
        Ok((cw, Some(Box::new(Arc { center, plane_axes: (a, b, c), radius: r0, sweep_deg: sweep.to_degrees() }))))
    }

    /// A group 00 code. Returns whether it moved the tool.
    fn one_shot(&mut self, code: u16, w: &Words, machine_before: Pos, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        let axes = self.cfg.machine.axes.len();
        match code {
            code::G04 => {
                self.refuse_point_at_dwell_p(w)?;
                let seconds = match (w.integer(b'P'), w.raw(b'X')) {
                    (Some(p), _) => self.dwell_p_seconds(w, p),
                    (None, Some((x, no_point))) => {
                        if no_point && !self.cfg.pocket_calculator {
                            x * 0.001
                        } else {
                            x
                        }
                    }
                    (None, None) => 0.0,
                };
                if seconds < 0.0 {
                    return Err(AlarmId::ImproperAddress);
                }
                self.emit(out, CanonKind::Dwell { seconds });
            }
            code::G10 => self.data_setting(w, machine_before, out)?,
            code::G38 => return self.vector_hold(w, out),
            code::G39 => {
                self.corner_arc(w, out)?;
                return Ok(true);
            }
            code::G52 => {
                let incremental = self.modes[group::DISTANCE] == code::G91;
                for i in 0..axes {
                    if let Some(v) = self.value(w, self.cfg.machine.axes[i].name as u8) {
                        self.local[i] = if incremental { self.local[i] + v } else { v };
                    }
                }
                self.work_system_shifted(&machine_before);
            }
            code::G53_1 | code::G53_3 | code::G53_6 => return self.align(code, w, out),
            code::G53 => {
                let mut m = machine_before;
                for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                    if let Some(v) = self.value(w, axis.name as u8) {
                        m[i] = axis.machine_command_end(m[i], v);
                    }
                }
                self.cancel_length_vector(w);
                self.emit_machine_motion(m, out);
                return Ok(true);
            }
            code::G92 => {
                let w0 = *self.offsets.work(self.work_index());
                let ext = self.external_offset();
                for i in 0..axes {
                    if let Some(v) = self.value(w, self.cfg.machine.axes[i].name as u8) {
                        // FANUC (local coordinate system): G92 cancels G52 on the axes it names.
                        self.local[i] = 0.0;
                        self.shift[i] = machine_before[i] - w0[i] - ext[i] - self.local[i] - self.tool_vec[i] - v;
                        self.pos[i] = v;
                    }
                }
                self.sync_programmed();
            }
            code::G92_1 => {
                for i in 0..axes {
                    if w.has(self.cfg.machine.axes[i].name as u8) {
                        self.shift[i] = 0.0;
                        self.local[i] = 0.0;
                    }
                }
                self.work_system_shifted(&machine_before);
            }
            code::G28 | code::G30 => {
                if self.modes[group::CYCLE] != code::G80 {
                    return Err(AlarmId::ReferenceReturnInCycle);
                }
                // G28: the 1st reference position (machine zero); G30 P2 (default), P3, P4.
                let which = match (code, w.integer(b'P')) {
                    (code::G28, _) => 1,
                    (_, None) => 2,
                    (_, Some(p)) if (2.0..=4.0).contains(&p) && p.fract() == 0.0 => p as usize,
                    _ => return Err(AlarmId::IllegalReferenceReturn),
                };
                // Through the intermediate point, then to the reference position.
                let mid = self.target(w);
                self.rapid_to_program_point(mid, out)?;
                self.last_g28_mid = self.pos;
                let all = code == code::G28 && self.g28_returns_every_axis(w);
                let mut m = self.machine_position();
                for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                    if all || w.has(axis.name as u8) {
                        let reference = if which == 1 { 0.0 } else { axis.references[which - 2] };
                        m[i] = axis.reference_return_end(m[i], reference, self.cfg.dialect);
                    }
                }
                self.cancel_length_vector(w);
                self.emit_machine_motion(m, out);
                if code == code::G28 {
                    self.haas_cancel_length_comp();
                }
                return Ok(true);
            }
            code::G27 => {
                if self.modes[group::CYCLE] != code::G80 {
                    return Err(AlarmId::ReferenceReturnInCycle);
                }
                // Where the machine stands after a tip move of TCP, the tilted plane or G54.4
                // is the executor's to find, not this check's: not built there.
                if code::TCP.contains(&self.modes[group::LENGTH_COMP]) || self.plane_active() || self.wse.is_some() {
                    return Err(AlarmId::GCodeNotBuilt);
                }
                // To the point at rapid, then the named axes must stand at the 1st reference
                // position (machine zero): the offsets in force count, as on the control. The
                // real axes are checked (a handle interruption's shift counts); an axis under
                // machine lock is not (FANUC: no check while the machine is locked).
                let target = self.target(w);
                self.rapid_to_program_point(target, out)?;
                let real = self.machine_view.real(&self.machine_position());
                for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                    let locked = self.machine_view.held[i].is_some();
                    if w.has(axis.name as u8) && !locked && !axis.at_reference(real[i], 0.0) {
                        return Err(AlarmId::ReferenceReturnCheck);
                    }
                }
                return Ok(true);
            }
            code::G29 => {
                // The intermediate point's coordinates as G28/G30 stored them, read in the
                // system in force now.
                let mut mid = self.pos;
                for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                    if w.has(axis.name as u8) {
                        mid[i] = self.last_g28_mid[i];
                    }
                }
                self.rapid_to_workpiece_point(mid, out)?;
                self.sync_programmed();
                let target = self.target(w);
                self.rapid_to_program_point(target, out)?;
                return Ok(true);
            }
            // G31: to the end point or where the probe touches the workpiece (`skip`).
            code::G31 => {
                self.skip_move(w, out)?;
                return Ok(true);
            }
            // G05.1 Q1 / Q0: look-ahead (AI contour control) on / off; Q3 nano smoothing
            // (`smoothing`; other Q: `unbuilt`).
            code::G05_1 => self.g05_1(w)?,
            // Syntec's G05 P10000 / P0: HPCC on / off (`smoothing`; FANUC's P0 does nothing,
            // its other forms are refused, `unbuilt`).
            code::G05 => self.g05(w)?,
            // The Haas dialect's own (`haas_cycles`; `gcode::GDef::haas_only`).
            code::G12 | code::G13 => return self.circular_pocket(code == code::G12, w, out),
            code::G103 => self.block_look_ahead(w)?,
            // G187: corner rounding (`corner_blend`).
            code::G187 => self.g187(w)?,
            // The one-shot codes left are performed by doing nothing here (G04.1, G09, G22
            // without limits…), or refused before this (`unbuilt`).
            _ => {}
        }
        Ok(false)
    }

    /// The block's first G code whose function (with the block's addresses) fivex does not
    /// carry out raises `GCodeNotBuilt` (`unbuilt`).
    fn refuse_unbuilt(&self, w: &Words) -> Result<(), AlarmId> {
        if !self.cfg.refuse_unbuilt {
            return Ok(());
        }
        let word = |letter: u8| w.integer(letter).map_or(unbuilt::Word::Absent, unbuilt::Word::Value);
        if w.gcodes().iter().any(|&code| unbuilt::g_code(code, self.cfg.dialect, w.gcodes(), word).is_some()) {
            return Err(AlarmId::GCodeNotBuilt);
        }
        self.refuse_unbuilt_blend(w)?;
        self.refuse_unbuilt_cutter(w)
    }

    /// The block's code of `group` (its last one: the one that counts), if it gives one.
    pub(super) fn block_code(&self, w: &Words, group: usize) -> Option<u16> {
        let dialect = self.cfg.dialect;
        w.gcodes().iter().rev().copied().find(|&c| gcode::lookup(c, dialect).is_some_and(|d| d.group == group))
    }

    /// The code of `group` after this block: the block's own, or the mode in force.
    pub(super) fn after_block(&self, w: &Words, group: usize) -> u16 {
        self.block_code(w, group).unwrap_or(self.modes[group])
    }

    /// Under cutter compensation (G41/G42, G41.2/G42.2 or G41.3 in force after the block), what its
    /// stage does not perform is refused like a function not built (`unbuilt::cutter`).
    fn refuse_unbuilt_cutter(&self, w: &Words) -> Result<(), AlarmId> {
        let in_block = |group: usize| self.block_code(w, group);
        let after = |group: usize| self.after_block(w, group);
        let comp = after(group::CUTTER_COMP);
        if !code::COMPENSATED_BY_STAGES.contains(&comp) {
            return Ok(());
        }
        let rotary =
            w.letters().any(|l| self.axis_of(l).is_some_and(|i| self.cfg.machine.axes[i].kind == AxisKind::Rotary));
        let rotary_table = self.cfg.machine.rotary.iter().any(|l| l.side == crate::machine::Side::Table);
        let block = unbuilt::CutterBlock {
            tool_side: code::TOOL_SIDE.contains(&comp),
            type2_alone: matches!(comp, code::G41_6 | code::G42_6) && after(group::LENGTH_COMP) != code::G43_5,
            leading_edge: comp == code::G41_3,
            no_mechanism: self.kinematics.is_none()
                || !self.cfg.machine.axes.iter().any(|a| a.kind == AxisKind::Rotary),
            transform: !matches!(after(group::ROTATION), code::G69 | code::G69_1)
                || after(group::SCALING) != code::G50
                || after(group::MIRROR) != code::G50_1
                || after(group::POLAR) == code::G16,
            tcp: code::TCP.contains(&after(group::LENGTH_COMP)),
            cutting_point: matches!(after(group::LENGTH_COMP), code::G43_8 | code::G43_9),
            five_axis: self.plane_active() || self.wse.is_some() || in_block(group::WSE).is_some(),
            cycle: after(group::CYCLE) != code::G80,
            coordinates: [code::G27, code::G28, code::G30, code::G53, code::G52, code::G92].iter().any(|&c| w.has_g(c))
                || in_block(group::WORK_SYSTEM).is_some(),
            rotary,
            inverse_time: after(group::FEED_MODE) == code::G93,
            corner_override: after(group::PATH_MODE) == code::G62,
            rotary_table,
            q: w.has(b'Q')
                && (matches!(comp, code::G41_6 | code::G42_6 | code::G41_3)
                    || !matches!(w.integer(b'Q'), Some(1.0 | 2.0 | 3.0))),
            ijk_in_comp_block: matches!(in_block(group::CUTTER_COMP), Some(code::G41 | code::G42))
                && [b'I', b'J', b'K'].into_iter().any(|l| w.has(l))
                && matches!(after(group::MOTION), code::G00 | code::G01)
                && !w.gcodes().iter().any(|c| unbuilt::OWN_IJK.contains(c)),
            smoothing: if w.has_g(code::G05_1) {
                w.integer(b'Q') == Some(3.0)
            } else if w.has_g(code::G05) && self.cfg.dialect == crate::Dialect::Syntec {
                w.integer(b'P') == Some(10000.0)
            } else {
                self.smoothing.is_some()
            },
        };
        match unbuilt::cutter(&block) {
            Some(_) => Err(AlarmId::GCodeNotBuilt),
            None => Ok(()),
        }
    }

    /// A G10 block holds G10's data and nothing that would be dropped (`g10`): a G code but
    /// G90/G91, an address its form does not take, an address given twice (the G10 format
    /// alarm: which of two P's is meant is not the control's guess).
    fn refuse_g10_strangers(&self, w: &Words) -> Result<(), AlarmId> {
        if !w.has_g(code::G10) {
            return Ok(());
        }
        let dialect = self.cfg.dialect;
        let (l, written) = w.word(b'L').ok_or(AlarmId::DataSettingFormat)?;
        let l = if matches!(written, Form::Expr(_)) { round_to(l, 1.0) } else { l };
        let form = g10::form(l, written == Form::Point, dialect)?;
        if let Some((id, _)) = w.gcodes().iter().find_map(|&c| g10::g_code(c, Some(form), dialect)) {
            return Err(id);
        }
        for (i, letter) in w.letters().enumerate() {
            if letter != b'G' && w.letters().skip(i + 1).any(|other| other == letter) {
                return Err(AlarmId::DataSettingFormat);
            }
            if g10::address(letter, self.axis_of(letter).is_some(), form).is_some() {
                return Err(AlarmId::ImproperAddress);
            }
        }
        Ok(())
    }

    /// G10: programmable data input of work and tool offsets (its block's words checked by
    /// `refuse_g10_strangers`).
    fn data_setting(&mut self, w: &Words, machine_before: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let l = w.integer(b'L').ok_or(AlarmId::DataSettingFormat)?;
        let form = g10::form(l, w.has_point(b'L'), self.cfg.dialect)?;
        let p = g10::p_number(w.integer(b'P'), w.has_point(b'P'), form, self.cfg.dialect)?;
        let incremental = self.modes[group::DISTANCE] == code::G91;
        match form {
            // Haas: G10 L2 P0 is the G52 offset (FANUC's P0 is the external offset).
            g10::Form::WorkOffset if l == 2.0 && p == 0 && self.cfg.dialect == Dialect::Haas => {
                for (i, axis) in self.cfg.machine.axes.clone().iter().enumerate() {
                    if let Some(v) = self.value(w, axis.name as u8) {
                        self.local[i] = if incremental { self.local[i] + v } else { v };
                    }
                }
                self.work_system_shifted(&machine_before);
            }
            g10::Form::WorkOffset => {
                // Haas: G10 L20 P1–P99 (G154 P1–P99).
                let max = if self.cfg.dialect == Dialect::Haas { 99 } else { MAX_G54_1 };
                let index = match (l == 2.0, p) {
                    (true, 0..=6) => p,
                    (false, 1..) if p <= max => g54_1_index(p),
                    _ => return Err(AlarmId::IllegalG10Command),
                };
                let (unit, inch) = (self.mm_per_input_unit(), self.modes[group::UNITS] == code::G20);
                let mut set = *self.offsets.work(index);
                for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                    if let Some(v) = self.value(w, axis.name as u8) {
                        set[i] = if incremental { set[i] + v } else { v };
                        // The value set (under G91 the sum) within the range, in the input unit
                        // (degrees on a rotary axis, in inch too).
                        let linear = axis.kind == AxisKind::Linear;
                        let input = if linear { set[i] / unit } else { set[i] };
                        if !super::offsets::work_value_fits(input, inch && linear) {
                            return Err(AlarmId::IllegalOffsetValue);
                        }
                    }
                }
                self.set_work_offset(index, set, &machine_before);
            }
            g10::Form::ToolOffset => {
                let r = self.value(w, b'R').ok_or(AlarmId::IllegalG10Command)?;
                if p > super::offsets::max_tool_offset(self.cfg.dialect) {
                    return Err(AlarmId::IllegalG10Command);
                }
                let (unit, inch) = (self.mm_per_input_unit(), self.modes[group::UNITS] == code::G20);
                let t = self.offsets.tool_mut(p as u32).ok_or(AlarmId::IllegalG10Command)?;
                let slot = match l as u32 {
                    10 => &mut t.h_geometry,
                    1 | 11 => &mut t.h_wear,
                    12 => &mut t.d_geometry,
                    _ => &mut t.d_wear,
                };
                let value = if incremental { *slot + r } else { r };
                // The value set (under G91 the sum) within the input range, in the input unit.
                let wear = matches!(l as u32, 1 | 11 | 13);
                if !super::offsets::tool_value_fits(value / unit, wear, inch) {
                    return Err(AlarmId::IllegalOffsetValue);
                }
                *slot = value;
            }
            // Syntec: select the mechanism chain (its Q and its modes are checked in `modes`).
            g10::Form::Chain => self.switch_chain(w, p, out)?,
        }
        Ok(())
    }
}

/// An H or D word's offset number, within the dialect's tool offsets.
fn offset_number(v: f64, dialect: Dialect) -> Result<u32, AlarmId> {
    if v < 0.0 || v.fract() != 0.0 || v > super::offsets::max_tool_offset(dialect) as f64 {
        return Err(AlarmId::IllegalOffsetNumber);
    }
    Ok(v as u32)
}

fn is_cycle(code: u16) -> bool {
    matches!(gcode::lookup(code, Dialect::Fanuc), Some(d) if d.group == group::CYCLE && code != code::G80)
}

impl CallFrame {
    pub(super) fn main() -> CallFrame {
        CallFrame { prog: 0, pc: 0, kind: CallKind::Main, repeats: 0, start: 0, args: None, number: 0, modal: None }
    }
}

/// A P value as a sequence number (N0–N99999999), if it is one.
pub(super) fn sequence_number(p: f64) -> Option<u32> {
    ((0.0..=99_999_999.0).contains(&p) && p.fract() == 0.0).then_some(p as u32)
}
