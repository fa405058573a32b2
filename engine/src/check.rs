//! Static checks for `fivex check`: everything that can be known without running the program.
//!
//! Beyond the parser's diagnostics: G codes the dialect does not have, G codes and addresses of
//! functions fivex does not carry out (`interp::unbuilt`, with the literal values of the block's
//! addresses), DO/END structure, GOTO targets and called programs given as literal numbers that
//! do not exist, L in a block that names a canned cycle (K in the Haas dialect), FANUC's P with a
//! decimal point in a block that names G04 or a canned cycle (PS0007), a `,L` other
//! than `,L2` and a zero surface normal of cutting point control, Syntec's G05 format errors
//! that literal words show, the addresses Syntec's G68.2/G43.4/G43.5 do not take (P, Q, R; an
//! L other than 0/1), the words of a G10 block its form does not take (`interp::g10`), Haas's
//! M97/M98/G65 without P and M97 P of a line the program does not
//! have, two programming transforms started in one block and a literal G68 R beyond ±360°
//! (`interp::frames`), the conditional `[cond] M99 P<n>` outside the Haas dialect, in another form, or with a
//! literal P the program has no N for, Haas's G150 without P or with a P that is neither a
//! line of the program nor a program of the file, a block naming G93 and a cutting move
//! without F, and FANUC's blocks in NURBS interpolation mode that are not a curve's.
//!
//! And what only a run finds: [`run_without_motion`] runs a program through the interpreter and
//! the path stages of a run (`crate::stage::Pipeline`, cutter compensation C) and the
//! executor's stroke check without its planner, so the compensation's alarms (PS0033, PS0034,
//! PS0041 …) and the stored stroke limits (OT0510/OT0511) are found as a run finds them.

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind};
use crate::dialect::Dialect;
use crate::interp::expr::{syntec_divide, written_with_point, Ty};
use crate::interp::frames;
use crate::interp::gcode::{self, code, group};
use crate::interp::mcode;
use crate::interp::modes::syntec_improper_address;
use crate::interp::offsets;
use crate::interp::unbuilt::{self, Word};
use crate::interp::{Interpreter, Loaded, Step};
use crate::lang::Word as NcWord;
use crate::lang::{BinOp, BlockKind, Diagnostic, Expr, File, Output, PrintItem, WordValue};
use crate::motion::{Endpoint, Executor};
use crate::notice::Notice;
use std::collections::HashSet;

/// Every diagnostic of `file`, sorted by line and column.
pub fn check(file: File, dialect: Dialect) -> Vec<Diagnostic> {
    let mut diags = file.diagnostics;
    let numbers: HashSet<u32> = file.programs.iter().filter_map(|p| p.number).collect();
    let mut main = true;
    for program in file.programs {
        let loaded = Loaded::new(program);
        if dialect == Dialect::Haas {
            haas_modes(&loaded, &mut diags);
            // The run starts at the first program, with no H in force.
            if main && !loaded.is_header() {
                haas_length_without_h(&loaded, &mut diags);
                main = false;
            }
        }
        if dialect == Dialect::Fanuc {
            nurbs_mode(&loaded, &mut diags);
        }
        for (i, block) in loaded.blocks().enumerate() {
            let at = |col: u32, id: AlarmId, detail: String| Diagnostic { line: block.line, col, id, detail };
            let block_start = diags.len();
            if let Some(id) = loaded.loop_error.get(&(i as u32)) {
                diags.push(at(
                    block.col,
                    id.clone(),
                    "DO/END: unmatched, crossing, or a loop number other than 1–3".into(),
                ));
            }
            if dialect == Dialect::Syntec {
                syntec_expressions(&block.kind, |id, detail| diags.push(at(block.col, id, detail)));
            }
            match &block.kind {
                BlockKind::Goto(Expr::Num { value: n, .. })
                | BlockKind::IfGoto { target: Expr::Num { value: n, .. }, .. }
                    if loaded.find_label(*n as u32, i).is_none() =>
                {
                    diags.push(at(block.col, AlarmId::IllegalSequenceNumber, format!("no block N{n} in this program")));
                }
                // Syntec's text fivex does not perform (`%@MACRO`, `(*` without `*)`, ALARM(…)…).
                BlockKind::SyntecOnly(s) => diags.extend(s.refusal(dialect).cloned()),
                // `[cond] M99 P<n>`: the Haas NGC's conditional M99 (`interp::exec`).
                BlockKind::IfWords { .. } if dialect != Dialect::Haas => {
                    diags.push(at(block.col, AlarmId::Syntax, "unexpected '['".into()));
                }
                BlockKind::IfWords { words, .. } if !crate::interp::program::is_conditional_m99(words) => {
                    diags.push(at(block.col, AlarmId::MacroFormat, "only M99 P<n> may follow a condition".into()));
                }
                BlockKind::IfWords { words, .. } => {
                    if let Word::Value(n) = literal(words, b'P') {
                        let col = words.iter().find(|w| w.letter == b'P').map_or(block.col, |w| w.col);
                        if n < 0.0 || n.fract() != 0.0 || loaded.find_label(n as u32, i).is_none() {
                            diags.push(at(col, AlarmId::LineNotFound, format!("no N{n} in this program")));
                        }
                    }
                }
                BlockKind::Words(words) => {
                    if let Some((col, id, detail)) = over_block_limits(words) {
                        // The run refuses the block as it reads it; nothing else of it matters
                        // (and a line of 100,000 words is not looked at word by word).
                        diags.push(at(col, id, detail));
                        continue;
                    }
                    let (mut calls, mut cycle, mut pattern, mut dwell) = (false, false, false, false);
                    // The block's literal G codes (an argument of one is not an address of its own).
                    let codes = || {
                        words.iter().filter_map(|w| match (w.letter, &w.value) {
                            (b'G', WordValue::Number { value, .. }) => gcode::code_of(*value),
                            _ => None,
                        })
                    };
                    let block_codes: Vec<u16> = codes().collect();
                    for w in words {
                        let WordValue::Number { value, .. } = w.value else { continue };
                        match w.letter {
                            b'G' => match gcode::code_of(value).and_then(|c| gcode::written(c, dialect)) {
                                None => diags.push(at(
                                    w.col,
                                    AlarmId::ImproperGCode,
                                    format!("G{value} is not a G code of the {} dialect", dialect.name()),
                                )),
                                Some(d) => {
                                    let word = |letter| literal(words, letter);
                                    let refused = unbuilt::g_code(d.code, dialect, &block_codes, word);
                                    // (A refused call, Syntec's G66.1, is refused before its P is looked for.)
                                    calls |= code::MACRO_CALLS.contains(&d.code) && refused.is_none();
                                    if let Some(function) = refused {
                                        diags.push(at(
                                            w.col,
                                            AlarmId::GCodeNotBuilt,
                                            format!("{}: {function} is not built in fivex", gcode::display(d.code)),
                                        ));
                                    }
                                    cycle |= d.group == group::CYCLE && d.code != code::G80;
                                    dwell |= d.code == code::G04;
                                    // Haas's bolt patterns take the block's I J K L.
                                    pattern |= matches!(d.code, code::G70 | code::G71 | code::G72);
                                }
                            },
                            b'M' => {
                                calls |= mcode::SUBPROGRAM_CALLS.contains(&(value as u32));
                                let haas = dialect == Dialect::Haas && value.fract() == 0.0 && value >= 0.0;
                                if let Some(function) = unbuilt::haas_m_code(value as u32).filter(|_| haas) {
                                    diags.push(at(
                                        w.col,
                                        AlarmId::MCodeNotBuilt,
                                        format!("{function} is not built in fivex"),
                                    ));
                                }
                                let whole = value.fract() == 0.0 && value >= 0.0;
                                let form = words.iter().find_map(|a| {
                                    unbuilt::call_address(value as u32, a.letter, dialect).map(|f| (a.col, f))
                                });
                                if let Some((col, function)) = form.filter(|_| whole) {
                                    diags.push(at(
                                        col,
                                        AlarmId::AddressNotBuilt,
                                        format!("{function} is not built in fivex"),
                                    ));
                                }
                            }
                            letter => {
                                let argument = codes().any(|c| unbuilt::argument_of(c, dialect, letter));
                                if let Some(function) = unbuilt::address(letter, dialect).filter(|_| !argument) {
                                    diags.push(at(
                                        w.col,
                                        AlarmId::AddressNotBuilt,
                                        format!("{function} is not built in fivex"),
                                    ));
                                }
                            }
                        }
                    }
                    // Cutting point control's `,L2 I J K` (FANUC): `,L` is `,L2`, and a normal of
                    // three literal zeros is PS5464 (`interp/cutting_point.rs`); Syntec has no `,L`.
                    if let Some(l) = words.iter().find(|w| w.letter == b'l') {
                        let ijk = [b'i', b'j', b'k'].map(|c| literal(words, c));
                        let zero = ijk.iter().any(|w| *w != Word::Absent)
                            && ijk.iter().all(|w| matches!(w, Word::Absent | Word::Value(0.0)));
                        let refusal = match (dialect, literal(words, b'l')) {
                            (Dialect::Syntec, _) => Some((AlarmId::ImproperAddress, "no ,L in the Syntec dialect")),
                            (_, Word::Value(v)) if v != 2.0 => Some((AlarmId::ImproperAddress, ",L other than ,L2")),
                            _ if zero => Some((AlarmId::CuttingPoint, ",L2 I0 J0 K0: the surface normal is zero")),
                            _ => None,
                        };
                        if let Some((id, detail)) = refusal {
                            diags.push(at(l.col, id, detail.into()));
                        }
                    }
                    // G10's block holds G10's data and nothing a run would drop (`interp::g10`).
                    if codes().any(|c| c == code::G10) {
                        if let Some((col, id, detail)) = g10_block(words, dialect) {
                            diags.push(at(col.unwrap_or(block.col), id, detail.into()));
                        }
                    }
                    // One programming transform started per block, and G68's literal R within
                    // ±360° (`interp::frames`; no decimal point: 0.001°).
                    if let Some(second) = frames::second_start(&block_codes) {
                        let col = words.iter().filter(|w| w.letter == b'G').find(|w| {
                            matches!(w.value, WordValue::Number { value, .. } if gcode::code_of(value) == Some(second))
                        });
                        let detail = "G51.1, G51 and G68 each take the block's axis words: one per block";
                        diags.push(at(
                            col.map_or(block.col, |w| w.col),
                            AlarmId::IllegalGCodeCombination,
                            detail.into(),
                        ));
                    }
                    let r = words.iter().rev().find(|w| w.letter == b'R').filter(|_| block_codes.contains(&code::G68));
                    if let Some(r) = r {
                        if let WordValue::Number { value, decimal_point } = r.value {
                            let degrees = if decimal_point { value } else { value * 0.001 };
                            if !frames::rotation_angle_fits(degrees) {
                                let detail = format!("G68 R{degrees}: the rotation angle is within ±360°");
                                diags.push(at(r.col, AlarmId::RotationAngleOutOfRange, detail));
                            }
                        }
                    }
                    // A P beside G54…G59 (`interp::offsets::work_system_p`); a canned cycle in
                    // force is the run's to know.
                    let block_codes: Vec<u16> = codes().collect();
                    let work = block_codes.iter().find(|&&c| (code::G54..=code::G59).contains(&c) && c % 10 == 0);
                    let p = words.iter().rev().find(|w| w.letter == b'P');
                    if let (Some(&work), Some(p)) = (work, p) {
                        let m_codes: Vec<u32> = words
                            .iter()
                            .filter_map(|w| match (w.letter, &w.value) {
                                (b'M', WordValue::Number { value, .. }) if value.fract() == 0.0 && *value >= 0.0 => {
                                    Some(*value as u32)
                                }
                                _ => None,
                            })
                            .collect();
                        let elsewhere = offsets::p_taken_elsewhere(dialect, &block_codes, &m_codes, false);
                        if let offsets::WorkP::Refused(id) = offsets::work_system_p(dialect, work, true, elsewhere) {
                            let detail = if id == AlarmId::AddressNotBuilt {
                                format!("P at {}: no meaning in the {} dialect", gcode::display(work), dialect.name())
                            } else {
                                "P of G54 (G54.1 Pn) and of another code of the block".into()
                            };
                            diags.push(at(p.col, id, detail));
                        }
                    }
                    if dialect == Dialect::Syntec {
                        let is_g05 = |w: &&NcWord| {
                            w.letter == b'G'
                                && matches!(w.value, WordValue::Number { value, .. } if gcode::code_of(value) == Some(code::G05))
                        };
                        if let Some(g05) = words.iter().find(is_g05) {
                            if let Some((col, detail)) = g05_format(words, g05.col) {
                                diags.push(at(col, AlarmId::HpccFormat, detail.into()));
                            }
                        }
                        // Addresses Syntec's G68.2/G43.4/G43.5 do not take (the mode table's row).
                        let block_codes: Vec<u16> = codes().collect();
                        let m_call = words.iter().any(|w| {
                            w.letter == b'M'
                                && matches!(w.value, WordValue::Number { value, .. }
                                    if value.fract() == 0.0 && mcode::call_or_return(value as u32))
                        });
                        for word in words {
                            let value = match word.value {
                                WordValue::Number { value, .. } => Some(value),
                                WordValue::Expr(_) => None,
                            };
                            if let Some(detail) = syntec_improper_address(&block_codes, m_call, word.letter, value) {
                                diags.push(at(word.col, AlarmId::ImproperAddress, detail.into()));
                            }
                        }
                        // (After what the run refuses first: an expression, a function not built.)
                        let refused_before = diags.len() > block_start;
                        if let Some(word) = syntec_undecided_unit(words, &block_codes).filter(|_| !refused_before) {
                            let detail = "a length or angle without a decimal point: its unit is Syntec's Pr3241 \
                                          (not built in fivex); write it with a point";
                            diags.push(at(word.col, AlarmId::UnitNotDecided, detail.into()));
                        }
                    }
                    // FANUC: the dwell's P (G04, a cycle's) takes no decimal point (PS0007,
                    // `interp::nc`'s `refuse_point_at_dwell_p`); a block that does not name G04
                    // or the cycle is left to the run.
                    let pointed_p = words
                        .iter()
                        .rev()
                        .find(|w| w.letter == b'P')
                        .filter(|w| matches!(w.value, WordValue::Number { decimal_point: true, .. }));
                    if let Some(p) = pointed_p.filter(|_| dialect == Dialect::Fanuc && (dwell || cycle)) {
                        diags.push(at(
                            p.col,
                            AlarmId::IllegalDecimalPoint,
                            "P with a decimal point: the dwell is in ms".into(),
                        ));
                    }
                    // G93's F is the block's own (`interp::nc`'s `forget_inverse_time_feed`): a
                    // block naming G93 and a cutting move (G01/G02/G03, a canned cycle) that
                    // moves without F is PS0011; a block in G93 without naming it is the run's.
                    let g93 = words.iter().find(|w| {
                        w.letter == b'G'
                            && matches!(w.value, WordValue::Number { value, .. } if gcode::code_of(value) == Some(code::G93))
                    });
                    let cuts = cycle || codes().any(|c| matches!(c, code::G01 | code::G02 | code::G03));
                    let moves = words.iter().any(|w| b"XYZABCUVWIJK".contains(&w.letter));
                    if let Some(g) = g93.filter(|_| cuts && moves && !words.iter().any(|w| w.letter == b'F')) {
                        diags.push(at(
                            g.col,
                            AlarmId::FeedZero,
                            "G93 without F: an inverse time is each block's own".into(),
                        ));
                    }
                    // Syntec's G93 arc is not built (`interp::nc`'s `arc`).
                    let arc = codes().any(|c| matches!(c, code::G02 | code::G03));
                    if let Some(g) = g93.filter(|_| arc && dialect == Dialect::Syntec) {
                        diags.push(at(
                            g.col,
                            AlarmId::GCodeNotBuilt,
                            "an arc in inverse time feed (G93): how Syntec times it is not known".into(),
                        ));
                    }
                    // The cycles' repeat count is K; the interpreter refuses L (`interp/cycles.rs`).
                    // The Haas NGC counts with L and its K is refused. Only a block naming the
                    // cycle is known to be one without running the program.
                    let (other, detail) = if dialect == Dialect::Haas {
                        (b'K', "K in a canned cycle: the repeat count is L")
                    } else {
                        (b'L', "L in a canned cycle: the repeat count is K")
                    };
                    if let Some(l) = words.iter().find(|w| w.letter == other).filter(|_| cycle && !pattern) {
                        diags.push(at(l.col, AlarmId::ImproperAddress, detail.into()));
                    }
                    // A call needs the P that names its program (Haas M97: its line). Syntec's
                    // M98/M198 without P are its own (below).
                    let literal_m = |m: u32| {
                        words.iter().find(|w| {
                            w.letter == b'M' && matches!(w.value, WordValue::Number { value, .. } if value == m as f64)
                        })
                    };
                    let m97 = literal_m(mcode::M97).filter(|_| dialect == Dialect::Haas);
                    if (calls || m97.is_some()) && !words.iter().any(|w| w.letter == b'P') {
                        let macro_call = || {
                            words.iter().find(|w| {
                                w.letter == b'G'
                                    && matches!(w.value, WordValue::Number { value, .. }
                                        if gcode::code_of(value).is_some_and(|c| code::MACRO_CALLS.contains(&c)))
                            })
                        };
                        let call = if dialect == Dialect::Syntec {
                            macro_call()
                        } else {
                            m97.or(literal_m(mcode::M98)).or_else(macro_call)
                        };
                        if let Some(call) = call {
                            diags.push(at(call.col, AlarmId::MissingP, "no P: the line or program to call".into()));
                        }
                    }
                    // Syntec: M198 needs its P (the handbook's COR-052); M98 without P calls the
                    // running program itself, not built.
                    // (An H there is refused on its own: `unbuilt::call_address`.)
                    let p_or_h = |w: &NcWord| w.letter == b'P' || w.letter == b'H';
                    if dialect == Dialect::Syntec && !words.iter().any(p_or_h) {
                        if let Some(m) = literal_m(mcode::M198) {
                            diags.push(at(m.col, AlarmId::MissingP, "M198 without P: the program to call".into()));
                        } else if let Some(m) = literal_m(mcode::M98) {
                            let detail = "M98 without P (a call of the running program) is not built in fivex";
                            diags.push(at(m.col, AlarmId::MCodeNotBuilt, detail.into()));
                        }
                    }
                    if let Some(m97) = m97 {
                        if let Word::Value(n) = literal(words, b'P') {
                            let col = words.iter().find(|w| w.letter == b'P').map_or(m97.col, |w| w.col);
                            let found = n >= 0.0 && n.fract() == 0.0 && loaded.find_label(n as u32, i).is_some();
                            if !found {
                                diags.push(at(col, AlarmId::LineNotFound, format!("no N{n} in this program")));
                            }
                        }
                    }
                    // Haas G150: its outline is the block N<P> of this program, else the program
                    // O<P> (`interp/haas_cycles.rs`).
                    let g150 = words.iter().find(|w| {
                        w.letter == b'G'
                            && matches!(w.value, WordValue::Number { value, .. } if gcode::code_of(value) == Some(code::G150))
                    });
                    if let Some(g) = g150.filter(|_| dialect == Dialect::Haas) {
                        match literal(words, b'P') {
                            Word::Absent => {
                                diags.push(at(g.col, AlarmId::MissingP, "no P: the pocket's outline".into()))
                            }
                            Word::Value(n) => {
                                let whole = n >= 0.0 && n.fract() == 0.0 && n <= u32::MAX as f64;
                                let found = whole
                                    && (loaded.find_label(n as u32, i).is_some() || numbers.contains(&(n as u32)));
                                if !found {
                                    let col = words.iter().find(|w| w.letter == b'P').map_or(g.col, |w| w.col);
                                    let detail = format!("no N{n} in this program and no program O{n} in this file");
                                    diags.push(at(col, AlarmId::ProgramNotFound, detail));
                                }
                            }
                            _ => {}
                        }
                    }
                    if calls {
                        let p = words.iter().find_map(|w| match (w.letter, &w.value) {
                            (b'P', WordValue::Number { value, .. }) => Some((*value, w.col)),
                            _ => None,
                        });
                        if let Some((p, col)) = p {
                            let m98 = words.iter().any(|w| w.letter == b'M');
                            let has_l = words.iter().any(|w| w.letter == b'L');
                            // Haas and Syntec: P is the program number itself (no count in
                            // front of it, `interp::nc`'s `subprogram_target`).
                            let count_form = m98 && !has_l && p >= 10_000.0 && dialect == Dialect::Fanuc;
                            let number = if count_form { p % 10_000.0 } else { p };
                            // A number with a fraction names no program, as the run finds
                            // (`find_program`; `P100.5` was read as O0100 here).
                            if number.fract() != 0.0 || !numbers.contains(&(number as u32)) {
                                diags.push(at(
                                    col,
                                    AlarmId::ProgramNotFound,
                                    format!("no program O{:04} in this file", number as u32),
                                ));
                            }
                        }
                    }
                }
                _ => {}
            }
        }
    }
    diags.sort_by_key(|d| (d.line, d.col));
    diags
}

/// Syntec: what a block's expressions show that the run refuses (`docs/dialects.md`, "The
/// Syntec macro language"): a variable of a number whose Syntec meaning is not fivex's
/// (`interp::vars::syntec_differs`; #100–#199, refused in a macro call only, are left to the
/// run: a program may be called by M98 and by G65), and a `/` of two literal integers whose
/// quotient is negative and not whole (`interp::expr::syntec_divide`).
fn syntec_expressions(kind: &BlockKind, mut report: impl FnMut(AlarmId, String)) {
    let mut visit = |e: &Expr| match e {
        Expr::Var(n) if crate::interp::vars::syntec_differs(*n, false) => report(
            AlarmId::VariableOutOfRange,
            format!("#{n} has another meaning on a Syntec control, or one fivex does not know (not built in fivex)"),
        ),
        Expr::Binary(BinOp::Div, a, b) => {
            if let (Some(x), Some(y)) = (literal_number(a), literal_number(b)) {
                let ty = |e: &Expr| if written_with_point(e) { Ty::Double } else { Ty::Long };
                if syntec_divide((x, ty(a)), (y, ty(b))) == Err(AlarmId::AddressNotBuilt) {
                    report(
                        AlarmId::AddressNotBuilt,
                        format!("{x}/{y}: Syntec's integer division of a negative quotient is not built in fivex"),
                    );
                }
            }
        }
        _ => {}
    };
    for e in block_expressions(kind) {
        walk(e, &mut visit);
    }
}

/// A number as written, also signed or bracketed (`-7`, `[2]`).
fn literal_number(e: &Expr) -> Option<f64> {
    match e {
        Expr::Num { value, .. } => Some(*value),
        Expr::Neg(inner) => literal_number(inner).map(|v| -v),
        Expr::Bracket(inner) => literal_number(inner),
        _ => None,
    }
}

/// Every expression of a block, assignment targets included.
fn block_expressions(kind: &BlockKind) -> Vec<&Expr> {
    fn words(w: &[NcWord]) -> Vec<&Expr> {
        w.iter()
            .filter_map(|w| match &w.value {
                WordValue::Expr(e) => Some(&**e),
                WordValue::Number { .. } => None,
            })
            .collect()
    }
    match kind {
        BlockKind::Assign { var, value } => vec![var, value],
        BlockKind::IfGoto { cond, target } => vec![cond, target],
        BlockKind::IfThen { cond, var, value } => vec![cond, var, value],
        BlockKind::IfWords { cond, words: w } => [vec![cond], words(w)].concat(),
        BlockKind::Goto(target) => vec![target],
        BlockKind::Do { cond: Some(cond), .. } => vec![cond],
        BlockKind::Words(w) => words(w),
        BlockKind::Output(Output::Print(items) | Output::BinaryPrint(items)) => items
            .iter()
            .filter_map(|i| match i {
                PrintItem::Var { var, .. } => Some(var),
                PrintItem::Text(_) => None,
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// `e` and every expression inside it, outermost first.
fn walk(e: &Expr, visit: &mut impl FnMut(&Expr)) {
    visit(e);
    match e {
        Expr::IndirectVar(inner) | Expr::Neg(inner) | Expr::Bracket(inner) | Expr::Func(_, inner) => walk(inner, visit),
        Expr::Binary(_, a, b) | Expr::Func2(_, a, b) => {
            walk(a, visit);
            walk(b, visit);
        }
        Expr::Num { .. } | Expr::Var(_) => {}
    }
}

/// Haas: what the modes refuse that the text shows, reading the program's blocks in order (a
/// jump or a call is not followed; the run finds the rest): G28/G29 while DWO (G254) is on
/// (730, the `interp::modes` row), and G254 or G234 while G187 rounds corners, or G187 rounding
/// corners while either is on (753, `interp::corner_blend`). G187 rounds corners with a literal
/// E above 0 (without E the machines' Setting 85 is 0: corners exact); an E given by an
/// expression is left to the run. G255 ends DWO, G49/G43/G44 end TCPC, M02/M30 end all three.
fn haas_modes(loaded: &Loaded, diags: &mut Vec<Diagnostic>) {
    let (mut dwo, mut tcpc, mut rounding) = (false, false, false);
    for block in loaded.blocks() {
        let BlockKind::Words(words) = &block.kind else { continue };
        let word = |letter: u8, wanted: &dyn Fn(f64) -> bool| {
            words
                .iter()
                .find(|w| w.letter == letter && matches!(w.value, WordValue::Number { value, .. } if wanted(value)))
        };
        let g = |c: u16| word(b'G', &|v| gcode::code_of(v) == Some(c));
        let at = |w: &NcWord, id: AlarmId, detail: &str| Diagnostic {
            line: block.line,
            col: w.col,
            id,
            detail: detail.into(),
        };
        let (g187, g254, g234) = (g(code::G187), g(code::G254), g(code::G234));
        if g254.is_some() {
            dwo = true;
        }
        if g(code::G255).is_some() {
            dwo = false;
        }
        if g234.is_some() {
            tcpc = true;
        }
        if [code::G49, code::G43, code::G44].iter().any(|&c| g(c).is_some()) {
            tcpc = false;
        }
        if g187.is_some() {
            rounding = matches!(literal(words, b'E'), Word::Value(e) if e > 0.0);
        }
        if let Some(g28) = g(code::G28).or_else(|| g(code::G29)).filter(|_| dwo) {
            diags.push(at(g28, AlarmId::IllegalCommandInMode, "G28/G29 while DWO (G254) is on (decision)"));
        }
        // Where the two meet: the block that starts the mode, or the rounding, in the other.
        let meets = g254.or(g234).or(g187).filter(|_| rounding && (dwo || tcpc));
        if let Some(w) = meets {
            diags.push(at(w, AlarmId::CornerRoundingInMode, "G187 corner rounding with DWO or TCPC"));
        }
        if word(b'M', &|v| v == mcode::M02 as f64 || v == mcode::M30 as f64).is_some() {
            (dwo, tcpc, rounding) = (false, false, false);
        }
    }
}

/// Haas: a G43/G44 block without H where no H is in force (`754`, the interpreter's
/// `refuse_length_without_h`), found in the main program from its top, where the run starts
/// with none: the blocks are read in order up to the first one after which the text no longer
/// tells the H in force (a jump, a loop, a call or return, M02/M30, an H given by an expression,
/// an unparsed block). A block the block delete switch may skip neither reports nor clears.
fn haas_length_without_h(loaded: &Loaded, diags: &mut Vec<Diagnostic>) {
    let mut no_h = true;
    for block in loaded.blocks() {
        let words = match &block.kind {
            BlockKind::Empty | BlockKind::Assign { .. } | BlockKind::Output(_) => continue,
            BlockKind::Words(words) => words,
            _ => return,
        };
        let number = |letter: u8, wanted: &dyn Fn(f64) -> bool| {
            words
                .iter()
                .any(|w| w.letter == letter && matches!(w.value, WordValue::Number { value, .. } if wanted(value)))
        };
        let optional = block.block_delete.is_some();
        match literal(words, b'H') {
            Word::Unknown => return,
            Word::Value(h) if !optional => no_h = h == 0.0,
            Word::Value(_) => no_h = false,
            Word::Absent => {}
        }
        let length = words.iter().find(|w| {
            w.letter == b'G'
                && matches!(w.value, WordValue::Number { value, .. }
                    if matches!(gcode::code_of(value), Some(code::G43 | code::G44)))
        });
        if let Some(g) = length.filter(|_| no_h && !optional && literal(words, b'H') == Word::Absent) {
            diags.push(Diagnostic {
                line: block.line,
                col: g.col,
                id: AlarmId::LengthCompWithoutH,
                detail: "G43/G44 without H, and no tool length offset H in force (decision)".into(),
            });
        }
        let flow = [mcode::M02, mcode::M30, mcode::M97, mcode::M98, mcode::M99];
        if number(b'M', &|v| flow.iter().any(|&m| v == m as f64))
            || number(b'G', &|v| gcode::code_of(v).is_some_and(|c| code::MACRO_CALLS.contains(&c)))
        {
            return;
        }
    }
}

/// FANUC: what NURBS interpolation mode refuses that the text shows (`interp::nurbs`,
/// `refuse_in_nurbs_mode`), reading the program's blocks in order (a jump or a call is not
/// followed; the run finds the rest): from a G06.2 block to a block with another group-01 code,
/// a word that is not a curve's — K, R, an axis address (A–C, U–Z); in the G06.2 block also
/// G06.2, G90/G91, P and F — is PS5116.
fn nurbs_mode(loaded: &Loaded, diags: &mut Vec<Diagnostic>) {
    let g_of = |w: &NcWord| match (w.letter, &w.value) {
        (b'G', WordValue::Number { value, .. }) => gcode::code_of(*value),
        _ => None,
    };
    let mut mode = false;
    for block in loaded.blocks() {
        let BlockKind::Words(words) = &block.kind else { continue };
        let motion = words
            .iter()
            .filter_map(|w| g_of(w).and_then(|c| gcode::written(c, Dialect::Fanuc)))
            .find(|d| d.group == group::MOTION)
            .map(|d| d.code);
        let starts = motion == Some(code::G06_2);
        mode = starts || (mode && motion.is_none());
        if !mode {
            continue;
        }
        let curve_word = |w: &NcWord| match w.letter {
            b'K' | b'R' | b'A'..=b'C' | b'U'..=b'Z' => true,
            b'P' | b'F' => starts,
            b'G' => starts && matches!(g_of(w), Some(code::G06_2 | code::G90 | code::G91)),
            _ => false,
        };
        if let Some(w) = words.iter().find(|w| !curve_word(w)) {
            diags.push(Diagnostic {
                line: block.line,
                col: w.col,
                id: AlarmId::NurbsBlock,
                // What to write, not only what is wrong: the common case is a program ending
                // (M30, M02, M99) or retracting (G91 G28) right after the curve's last knot.
                detail: "in NURBS interpolation mode (G06.2) only a curve's blocks may come: end the mode with \
                         a G01 or G00 block (another group-01 code) after the curve's last knot, before any \
                         other command (M30, M02, M99, G28, M and T codes…)"
                    .into(),
            });
        }
    }
}

/// The last `letter` word of a block (the one that counts), as `unbuilt` asks for it: an
/// expression's value is not known without running.
/// A block holding more words, G codes or M codes than the interpreter takes in one block
/// (`interp::MAX_WORDS`, `MAX_G_CODES`, `MAX_M_CODES`): where, the alarm and why. Only literal
/// words count (a vacant expression is dropped from the block).
fn over_block_limits(words: &[NcWord]) -> Option<(u32, AlarmId, String)> {
    use crate::interp::{MAX_G_CODES, MAX_M_CODES, MAX_WORDS};
    let literal: Vec<&NcWord> = words.iter().filter(|w| matches!(w.value, WordValue::Number { .. })).collect();
    let nth = |letter: Option<u8>, n: usize| {
        literal.iter().filter(|w| letter.is_none_or(|l| w.letter == l)).nth(n).map(|w| w.col)
    };
    let whole_m =
        |w: &&&NcWord| matches!(w.value, WordValue::Number { value, .. } if value >= 0.0 && value.fract() == 0.0);
    if let Some(col) = nth(Some(b'G'), MAX_G_CODES) {
        return Some((col, AlarmId::IllegalGCodeCombination, format!("more than {MAX_G_CODES} G codes in one block")));
    }
    let m_codes: Vec<u32> = literal.iter().filter(|w| w.letter == b'M').filter(whole_m).map(|w| w.col).collect();
    if let Some(&col) = m_codes.get(MAX_M_CODES) {
        return Some((col, AlarmId::ImproperAddress, format!("more than {MAX_M_CODES} M codes in one block")));
    }
    nth(None, MAX_WORDS).map(|col| (col, AlarmId::ImproperAddress, format!("more than {MAX_WORDS} words in one block")))
}

/// Syntec: the first literal number without a decimal point, not zero, at an address the run
/// reads as a length or an angle (`interp::nc`'s `refuse_syntec_undecided_unit`) whatever the
/// machine and the modes: X Y Z A B C I J R `,C` `,R`, in a G65/G66 block the arguments fivex
/// scales at X Y Z I J K R Q (K and Q of other blocks, and a call's A B C, depend on the canned
/// cycle and the machine: the run finds them).
fn syntec_undecided_unit<'a>(words: &'a [NcWord], block_codes: &[u16]) -> Option<&'a NcWord> {
    let call = block_codes.iter().any(|c| code::MACRO_CALLS.contains(c));
    let letters: &[u8] = if call { b"XYZIJKRQ" } else { b"XYZABCIJRcr" };
    words.iter().find(|w| {
        letters.contains(&w.letter)
            && matches!(w.value, WordValue::Number { value, decimal_point: false } if value != 0.0)
    })
}

fn literal(words: &[NcWord], letter: u8) -> Word {
    match words.iter().rev().find(|w| w.letter == letter).map(|w| &w.value) {
        None => Word::Absent,
        Some(WordValue::Number { value, .. }) => Word::Value(*value),
        Some(WordValue::Expr(_)) => Word::Unknown,
    }
}

/// The first word of a G10 block that a run refuses (`interp::g10`, the interpreter's
/// `refuse_g10_strangers`), with its column: an L no form has, a G code other than G90/G91, an
/// address given twice or one the form does not take. The axis letters are X Y Z A B C U V W
/// (a check knows no machine); an L that is an expression is left to the run.
fn g10_block(words: &[NcWord], dialect: Dialect) -> Option<(Option<u32>, AlarmId, &'static str)> {
    use crate::interp::g10;
    let l = words.iter().rev().find(|w| w.letter == b'L');
    let form = match l.map(|w| &w.value) {
        None => return Some((None, AlarmId::DataSettingFormat, "G10 without L")),
        Some(WordValue::Number { value, decimal_point }) => match g10::form(*value, *decimal_point, dialect) {
            Ok(form) => form,
            Err(id) => return Some((l.map(|w| w.col), id, "G10 L of no G10 form")),
        },
        Some(WordValue::Expr(_)) => return None,
    };
    for (i, w) in words.iter().enumerate() {
        if w.letter == b'G' {
            let WordValue::Number { value, .. } = w.value else { continue };
            let found = gcode::code_of(value).and_then(|c| g10::g_code(c, Some(form), dialect));
            if let Some((id, detail)) = found {
                return Some((Some(w.col), id, detail));
            }
        } else if words[i + 1..].iter().any(|other| other.letter == w.letter) {
            return Some((Some(w.col), AlarmId::DataSettingFormat, "an address given twice in a G10 block"));
        } else if let Some(detail) = g10::address(w.letter, b"XYZABCUVW".contains(&w.letter), form) {
            return Some((Some(w.col), AlarmId::ImproperAddress, detail));
        }
    }
    None
}

/// The first word of a Syntec G05 block whose literal value is a format error (COR-107,
/// `interp::smoothing`'s `g05_form`): P other than 10000 or 0 (at the G word when P is
/// missing), E not positive, X/Y/Z other than 0 or in a G05 P0 block. Which rotary axes the
/// axis form may name is the machine's: left to the run.
fn g05_format(words: &[NcWord], g_col: u32) -> Option<(u32, &'static str)> {
    let col = |letter: u8| words.iter().rev().find(|w| w.letter == letter).map_or(g_col, |w| w.col);
    let p = literal(words, b'P');
    match p {
        Word::Absent => return Some((g_col, "G05 without P (P10000 or P0)")),
        Word::Value(v) if v != 0.0 && v != 10000.0 => return Some((col(b'P'), "G05 P other than P10000 or P0")),
        _ => {}
    }
    if matches!(literal(words, b'E'), Word::Value(e) if e <= 0.0) {
        return Some((col(b'E'), "G05 E not positive"));
    }
    for letter in [b'X', b'Y', b'Z'] {
        match literal(words, letter) {
            Word::Value(_) if p == Word::Value(0.0) => return Some((col(letter), "an axis argument in G05 P0")),
            Word::Value(v) if v != 0.0 => return Some((col(letter), "a geometry axis argument of G05 other than 0")),
            _ => {}
        }
    }
    None
}

/// How a run without motion stopped ([`run_without_motion`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RunStop {
    /// The alarm, as a run would raise it (code, message, line, sequence number).
    pub alarm: Alarm,
    /// A path stage raised it (cutter compensation's corner, interference, start-up checks),
    /// not the interpreter.
    pub by_stage: bool,
    /// Cutter compensation (G41/G42) was in force where it was raised (always for a stage).
    pub compensating: bool,
    /// The stored stroke check raised it (an over-travel: the machine's strokes decide it).
    pub by_strokes: bool,
    /// The identity behind the code, when the interpreter or the stroke check raised it (a
    /// stage's alarm has none here).
    pub id: Option<AlarmId>,
}

/// Runs `interp` (loaded, in its start state) to its end through the interpreter and the path
/// stages a run uses (`crate::stage::Pipeline::for_config`), and with `strokes` every motion
/// through the executor's stroke check (`Executor::check_strokes`: the end point, an arc's
/// extremes, the points along a kinematic path, as the run checks them before a block moves),
/// never planned: nothing moves and no speed or time is checked. `strokes` is for the machine
/// the program is meant for; on a stand-in (the default machine of a check without one) its
/// strokes would stop the run before the compensation's alarms it is run for. The first
/// alarm, if any, in the run's order — a stroke limit of a command the stages released, then a
/// stage's (found where a run finds it: a corner when the next motion has been read, what the
/// stage still holds at the program end), then the interpreter's.
pub fn run_without_motion(interp: &mut Interpreter, strokes: bool) -> Option<RunStop> {
    run_noting(interp, strokes, &mut Vec::new())
}

/// [`run_without_motion`], adding to `notices` what the commands the stages release have to
/// report (`Notice::of_command`: the notices a block's commands carry; those only the planner
/// finds, of a segment's posture, are not looked for).
pub fn run_noting(interp: &mut Interpreter, strokes: bool, notices: &mut Vec<Notice>) -> Option<RunStop> {
    let mut stages = crate::stage::Pipeline::for_config(interp.config());
    let start = Endpoint {
        machine: interp.state.machine_position(),
        work: interp.state.position(),
        basis: interp.state.tip_basis(),
    };
    let mut exec = Executor::new(interp.config().machine.clone(), start);
    let mut out = Vec::new();
    loop {
        out.clear();
        let step = interp.step(&mut out);
        let stage_alarm = stages.process(&mut out, crate::run::ends(&step));
        for notice in out.iter().filter_map(Notice::of_command) {
            Notice::add(notices, notice);
        }
        for c in out.iter().filter(|_| strokes) {
            if let Err(id) = check_strokes(&mut exec, c) {
                let (code, message) = interp.config().dialect.describe(&id);
                let alarm = Alarm { code, message, line: c.line, n: c.n };
                return Some(RunStop { alarm, by_stage: false, compensating: false, by_strokes: true, id: Some(id) });
            }
        }
        if let Some(alarm) = stage_alarm {
            return Some(RunStop { alarm, by_stage: true, compensating: true, by_strokes: false, id: None });
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return None,
            Err(alarm) => {
                let mode = interp.state.modal(group::CUTTER_COMP);
                let compensating = mode == code::G41 || mode == code::G42;
                let id = interp.stopped_by().cloned();
                return Some(RunStop { alarm, by_stage: false, compensating, by_strokes: false, id });
            }
        }
    }
}

/// The run's stroke check of command `c` (`run::Driver::apply`): a motion is checked from where
/// the one before ended; any other command leaves the machine standing in its block's system
/// (and Syntec's chain switch selects the mechanism the next motions are made with).
fn check_strokes(exec: &mut Executor, c: &Canon) -> Result<(), AlarmId> {
    match &c.kind {
        CanonKind::Motion(m) => {
            let ctx = exec.feed_context(1.0, 1.0, m.context.exact_stop);
            exec.check_strokes(c, m, ctx)
        }
        other => {
            exec.stand_in(c.tip_basis);
            if let CanonKind::Chain(chain) = other {
                exec.follow_chain(*chain);
            }
            Ok(())
        }
    }
}
