//! What fivex parses but does not carry out, in one table: a G code (or the address value that
//! selects a mode of it) listed here raises the dialect's "function not available" alarm at its
//! block, and `fivex check` reports it without running. Work that builds one of these functions
//! removes its row (and nothing else). Decisions and the list: `docs/dialects.md`, "Functions
//! not built".

use crate::dialect::Dialect;

/// An address of the block as the question "is this function performed?" sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Word {
    Absent,
    Value(f64),
    /// Given, but its value is not known without running (`fivex check` of `Q#1`).
    Unknown,
}

/// When a code of the table is refused.
#[derive(Debug, Clone, Copy)]
enum When {
    /// Always: fivex does not carry the function out.
    Always,
    /// Unless the address has one of these values (the cancel, or the mode fivex performs).
    Unless(u8, &'static [f64]),
    /// When any of these addresses is given.
    WithAny(&'static [u8]),
    /// When the address is given a positive value (its other values are format errors of the
    /// mode interlocks, `interp::modes`).
    Positive(u8),
    /// When every one of these addresses is given, unless a code of the block takes them as its
    /// own words ([`OWN_IJK`]).
    WithAll(&'static [u8]),
    /// When any of these addresses is given, unless a code of the block takes them as its own
    /// words ([`OWN_IJK`]: a bolt pattern in a cycle's block).
    WithAnyNotOwn(&'static [u8]),
}

/// The codes whose block's I, J, K are their own words: an arc's centre, and the Haas cycles'
/// arguments (G12/G13 and G150 take G41/G42 in their block to name the side they cut on).
pub const OWN_IJK: &[u16] = {
    use crate::interp::gcode::code::*;
    &[G02, G03, G12, G13, G70, G71, G72, G150]
};

struct NotBuilt {
    /// ×10, as in `gcode::TABLE`.
    code: u16,
    /// `None`: in both dialects.
    dialect: Option<Dialect>,
    when: When,
    function: &'static str,
}

const fn row(code: u16, when: When, function: &'static str) -> NotBuilt {
    NotBuilt { code, dialect: None, when, function }
}

const fn haas(code: u16, function: &'static str) -> NotBuilt {
    NotBuilt { code, dialect: Some(Dialect::Haas), when: When::Always, function }
}

/// A Haas canned cycle given one of `letters`, which select a form of it fivex does not build.
/// The cycle is modal: `State::refuse_unperformed_cycle_words` asks the same of a block that runs
/// the cycle in force without naming it.
const fn haas_cycle(code: u16, letters: &'static [u8], function: &'static str) -> NotBuilt {
    NotBuilt { code, dialect: Some(Dialect::Haas), when: When::WithAnyNotOwn(letters), function }
}

/// Every G code of `gcode::TABLE` (and `gcode::HAAS_TABLE`) that fivex does not perform, or performs only with some
/// values of an address. A code not listed here is performed (its behaviour has tests).
const TABLE: &[NotBuilt] = &[
    row(22, When::Always, "involute interpolation"),
    row(23, When::Always, "exponential interpolation"),
    row(24, When::Always, "3-D circular interpolation"),
    row(32, When::Always, "involute interpolation"),
    row(33, When::Always, "exponential interpolation"),
    row(34, When::Always, "3-D circular interpolation"),
    // FANUC: G05 P0 is the cancelled state; P10000 (HPCC) and the high-speed cycles are not
    // built.
    NotBuilt {
        code: 50,
        dialect: Some(Dialect::Fanuc),
        when: When::Unless(b'P', &[0.0]),
        function: "high-speed machining (G05 P10000 HPCC, high-speed cycle)",
    },
    // Syntec: G05 P10000 is HPCC (`interp::smoothing`); its E argument is nowhere described, so
    // a G05 with one is refused (a P other than 10000 / 0 or an E not positive is COR-107).
    NotBuilt {
        code: 50,
        dialect: Some(Dialect::Syntec),
        when: When::Positive(b'E'),
        function: "the E argument of G05 (HPCC)",
    },
    // Q1/Q0: look-ahead on/off, and FANUC's Q3 nano smoothing (`interp::smoothing`), are
    // performed; Q2 is not (smooth interpolation: its manual pages are not in fivex's sources).
    // Syntec's G05.1 is its own (Q0–Q2 with E), not described to build.
    NotBuilt {
        code: 51,
        dialect: Some(Dialect::Fanuc),
        when: When::Unless(b'Q', &[0.0, 1.0, 3.0]),
        function: "smooth interpolation (G05.1 Q2)",
    },
    NotBuilt {
        code: 51,
        dialect: Some(Dialect::Syntec),
        when: When::Unless(b'Q', &[0.0, 1.0]),
        function: "smoothing (G05.1 Q2, Q3)",
    },
    row(54, When::Always, "HRV3 servo control (G05.4)"),
    // G06.2 is performed in FANUC's format (`interp::nurbs`); Syntec's manual does not
    // describe it, so the Syntec dialect keeps refusing it rather than guess its format.
    NotBuilt { code: 62, dialect: Some(Dialect::Syntec), when: When::Always, function: "NURBS interpolation (G06.2)" },
    row(70, When::Always, "hypothetical axis interpolation (G07)"),
    // Also its cancel G07.1 C0: fivex would read C0 as a move of the C axis.
    row(71, When::Always, "cylindrical interpolation (G07.1)"),
    row(106, When::Always, "tool retract and recover (G10.6)"),
    row(121, When::Always, "polar coordinate interpolation (G12.1)"),
    row(171, When::Always, "plane conversion (G17.1)"),
    // G22 alone turns on stored stroke check 2, whose area fivex machines do not have (no
    // forbidden area: nothing to check); with limits it would define an area fivex ignores.
    row(220, When::WithAny(b"XYZIJK"), "stored stroke check 2 area (G22 with limits)"),
    row(260, When::Always, "spindle speed fluctuation detection (G26)"),
    // G27 is performed in the FANUC dialect (`nc`); Syntec's sources do not describe it (the
    // Haas NGC has no G27).
    NotBuilt {
        code: 270,
        dialect: Some(Dialect::Syntec),
        when: When::Always,
        function: "reference position return check (G27)",
    },
    row(282, When::Always, "G28.2"),
    row(301, When::Always, "floating reference position return (G30.1)"),
    // One probe, one skip signal (`interp::skip`): P selects among several inputs.
    row(310, When::WithAny(b"P"), "multi-step skip (G31 P)"),
    row(318, When::Always, "EGB skip (G31.8)"),
    row(319, When::Always, "continuous high-speed skip (G31.9)"),
    row(330, When::Always, "threading (G33)"),
    row(340, When::Always, "variable lead threading (G34)"),
    row(350, When::Always, "circular threading (G35)"),
    row(360, When::Always, "circular threading (G36)"),
    row(370, When::Always, "automatic tool length measurement (G37)"),
    // FANUC's three-dimensional tool compensation: I, J and K all given in the G41/G42 block
    // start it, and the I, J, K of the blocks after are the surface normals (FANUC 16/18-C,
    // "Three-dimensional tool compensation"; 30i-A descriptions B-63942EN/02 p.299, `G41 X_ I_
    // J_ K_ D_`). Run as cutter compensation C, the tool went R off the surface, silently
    // (audit crc2 N1). Syntec's and Haas's sources give I, J, K no meaning there (Haas's 3-D
    // compensation is G141): refused alike.
    row(410, When::WithAll(b"IJK"), "three-dimensional tool compensation (G41 with I, J and K)"),
    row(420, When::WithAll(b"IJK"), "three-dimensional tool compensation (G42 with I, J and K)"),
    row(411, When::Always, "normal direction control (G41.1)"),
    row(421, When::Always, "normal direction control (G42.1)"),
    row(431, When::Always, "tool length compensation in tool axis direction (G43.1)"),
    row(437, When::Always, "tool offset (G43.7)"),
    row(450, When::Always, "tool position offset (G45)"),
    row(460, When::Always, "tool position offset (G46)"),
    row(470, When::Always, "tool position offset (G47)"),
    row(480, When::Always, "tool position offset (G48)"),
    // G54.2 P0 is the cancel.
    row(542, When::Unless(b'P', &[0.0]), "rotary table dynamic fixture offset (G54.2)"),
    row(600, When::Always, "single direction positioning (G60)"),
    // Syntec's G66.1 is not FANUC's: the handbook (call semantics pack CALL-G661-001, §2.1;
    // GETTRAPARG) has each block carried out and the macro called after it ends, with the G66.1
    // block's arguments, where FANUC makes the block's words the arguments and moves nothing.
    // The source is secondary and leaves open which blocks call (macro statements, the G67
    // block, blocks of the called program): refused rather than guessed.
    NotBuilt {
        code: 661,
        dialect: Some(Dialect::Syntec),
        when: When::Always,
        function: "modal macro call after every block (G66.1)",
    },
    // FANUC's three-dimensional coordinate conversion: G68 with I, J, K (the axis of
    // rotation; 15i-MA B-63324EN §13.9, 16i-LA B-63194EN §12). Run as the plane's rotation the
    // axis was dropped and the contour turned in XY (audit xf 1). Syntec's and Haas's sources
    // give I, J, K no meaning there: refused alike.
    row(680, When::WithAny(b"IJK"), "three-dimensional coordinate conversion (G68 with I, J, K)"),
    row(721, When::Always, "figure copy (G72.1)"),
    row(722, When::Always, "figure copy (G72.2)"),
    row(811, When::Always, "chopping (G81.1)"),
    row(815, When::Always, "electronic gear box (G81.5)"),
    row(960, When::Always, "constant surface speed (G96)"),
    row(1610, When::Always, "in-feed control (G161)"),
    // The Haas NGC's own codes that fivex does not carry out (`gcode::HAAS_TABLE`); a Haas row
    // comes before a row for every dialect of the same number (G35, G36, G37, G47, G161 are other
    // functions on the NGC). Why G47 is not built: docs/dialects.md, "Haas cycles" (it needs the
    // NGC's engraving font).
    haas(350, "automatic tool diameter measurement (G35)"),
    haas(360, "automatic work offset measurement (G36)"),
    haas(370, "automatic tool offset measurement (G37)"),
    haas(470, "text engraving (G47)"),
    haas(770, "back bore canned cycle (G77)"),
    // FANUC's G87 is back boring; the NGC's back bore is G77 and its G87 another cycle, whose
    // page is not among fivex's sources (docs/dialects.md, "Haas cycles"): FANUC's cycle must
    // not run under the number.
    haas(870, "the NGC's G87 canned cycle (its back bore is G77)"),
    // The I, J, K peck forms of the Haas G73/G83 (96-8000, the G73 and G83 pages: first peck I,
    // reduced by J, down to K; G73's K with Q: back to R every K) and the G76 shift by I/J (the
    // NGC's G77 page gives I/J as the shift "if Q is not specified" and refers to G76; the G76
    // page itself is not among fivex's sources): not built (docs/dialects.md, "Haas cycles").
    haas_cycle(730, b"IJK", "the I, J, K peck forms of G73"),
    haas_cycle(760, b"IJ", "the shift by I, J of G76"),
    haas_cycle(830, b"IJK", "the I, J, K peck form of G83"),
    haas(1070, "cylindrical mapping (G107)"),
    haas(1360, "automatic work offset center measurement (G136)"),
    haas(1410, "3D+ cutter compensation (G141)"),
    haas(1430, "5-axis tool length compensation (G143)"),
    haas(1530, "5-axis high speed peck drilling (G153)"),
    haas(1550, "5-axis reverse tap (G155)"),
    haas(1610, "5-axis drill cycle (G161)"),
    haas(1620, "5-axis spot drill cycle (G162)"),
    haas(1630, "5-axis normal peck drilling cycle (G163)"),
    haas(1640, "5-axis tapping cycle (G164)"),
    haas(1650, "5-axis boring cycle (G165)"),
    haas(1660, "5-axis bore and stop cycle (G166)"),
    haas(1690, "5-axis bore and dwell cycle (G169)"),
    haas(1740, "non-vertical rigid tapping (G174)"),
    haas(1840, "non-vertical rigid tapping (G184)"),
    haas(2530, "spindle normal to the feature coordinate system (G253)"),
    haas(2660, "visible axes linear rapid motion (G266)"),
    haas(2680, "feature coordinate system (G268)"),
    haas(2690, "feature coordinate system cancel (G269)"),
    // Syntec codes that Autodesk's SYIL/Syntec post writes and no Syntec source among fivex's
    // references describes: its extended work offset and its smoothing mode with the cancel.
    NotBuilt {
        code: 591,
        dialect: Some(Dialect::Syntec),
        when: When::Always,
        function: "extended work coordinate system (G59.1)",
    },
    NotBuilt { code: 1201, dialect: Some(Dialect::Syntec), when: When::Always, function: "smoothing mode (G120.1)" },
    NotBuilt {
        code: 1210,
        dialect: Some(Dialect::Syntec),
        when: When::Always,
        function: "smoothing mode cancel (G121)",
    },
];

/// The function a G code (×10) selects with its block's addresses (and its other codes,
/// `codes`), if fivex does not carry it out in `dialect`.
pub fn g_code(code: u16, dialect: Dialect, codes: &[u16], word: impl Fn(u8) -> Word) -> Option<&'static str> {
    // The dialect's own row first, then the row for every dialect.
    let row = TABLE
        .iter()
        .find(|r| r.code == code && r.dialect == Some(dialect))
        .or_else(|| TABLE.iter().find(|r| r.code == code && r.dialect.is_none()))?;
    let value_in = |letter: u8, values: &[f64]| match word(letter) {
        Word::Value(v) => Some(values.contains(&v)),
        Word::Absent => Some(false),
        Word::Unknown => None,
    };
    let refused = match row.when {
        When::Always => Some(true),
        When::Unless(letter, values) => value_in(letter, values).map(|ok| !ok),
        When::WithAny(letters) => Some(letters.iter().any(|&l| word(l) != Word::Absent)),
        When::WithAll(letters) => {
            Some(letters.iter().all(|&l| word(l) != Word::Absent) && !codes.iter().any(|c| OWN_IJK.contains(c)))
        }
        When::WithAnyNotOwn(letters) => {
            Some(letters.iter().any(|&l| word(l) != Word::Absent) && !codes.iter().any(|c| OWN_IJK.contains(c)))
        }
        When::Positive(letter) => match word(letter) {
            Word::Value(v) => Some(v > 0.0),
            Word::Absent => Some(false),
            Word::Unknown => None,
        },
    };
    // A value known only when running is not refused statically; the run decides.
    refused.unwrap_or(false).then_some(row.function)
}

/// A block under cutter compensation (G41/G42, the tool side offset G41.2/G42.2 or the leading
/// edge offset G41.3, in force after it), as the question "does the stage perform it?" sees it
/// (`stage::cutter`, `stage::tool_side`, `stage::leading_edge`).
#[derive(Debug, Clone, Copy, Default)]
pub struct CutterBlock {
    /// G41.2/G42.2 or G41.6/G42.6 (5-axis tool side offset, type 1 or 2) rather than G41/G42.
    pub tool_side: bool,
    /// Type 2 (G41.6/G42.6: the tool direction by I/J/K) without tool centre point control of
    /// type 2 (G43.5), which turns I/J/K into rotary angles.
    pub type2_alone: bool,
    /// G41.3 (5-axis leading edge offset) rather than G41/G42.
    pub leading_edge: bool,
    /// The machine has no mechanism that turns the tool (no rotary axis, or kinematics that
    /// the machine file does not define): the leading edge offset has no tool direction.
    pub no_mechanism: bool,
    /// G68 rotation, G51 scaling, G51.1 mirror image or G16 polar coordinates in force.
    pub transform: bool,
    /// Tool centre point control in force.
    pub tcp: bool,
    /// Cutting point control (G43.8/G43.9) in force: it offsets the tool by D itself.
    pub cutting_point: bool,
    /// The tilted working plane or G54.4 in force.
    pub five_axis: bool,
    /// A canned cycle in force.
    pub cycle: bool,
    /// G28/G30/G53 (moves in machine coordinates), G52/G92 or a workpiece system selected.
    pub coordinates: bool,
    /// A rotary axis word in the block.
    pub rotary: bool,
    /// G93 inverse time feed (the corners' inserted moves would each take 1/F minutes).
    pub inverse_time: bool,
    /// G62 automatic corner override (its inner-corner feed reduction is not built).
    pub corner_override: bool,
    /// The machine turns the workpiece (a rotary table: table and mixed types).
    pub rotary_table: bool,
    /// Q in the block that the mode does not take: any Q under G41.3 and under type 2 (its
    /// inclination), under G41.2/G42.2 a Q other than Q1/Q2/Q3 (the tool side offset's answers
    /// to its interference check at a compensation plane change).
    pub q: bool,
    /// Nano smoothing (G05.1 Q3) or Syntec's HPCC (G05 P10000) in force after the block: its
    /// curve is built from the programmed points, before (not after) any compensation.
    pub smoothing: bool,
    /// I, J or K in a G41/G42 block in G00/G01 (not all three: that is [`TABLE`]'s
    /// three-dimensional tool compensation), where no code of the block takes them
    /// ([`OWN_IJK`]): some controls set the offset vector's direction by them, which the stage
    /// does not perform (it ignored them).
    pub ijk_in_comp_block: bool,
}

/// The function a block under cutter compensation asks for that its stage does not perform.
/// Cutter compensation C shifts the path in the plane by the same vector in programming and
/// machine coordinates: right only while the two differ by a translation, for plain motions.
/// The tool side offset compensates straight moves in the plane perpendicular to the tool, on a
/// machine of any mechanism type: type 1 with or without TCP, type 2 under G43.5 — on table
/// machines in the workpiece system (TBP = 0) or in the table system (TBP = 1, WKP = 0: under
/// TCP its Π, without it `interp::table_crc`). The leading edge offset: straight moves (by its
/// mode rules) on a machine whose rotary axes turn the tool only.
pub fn cutter(b: &CutterBlock) -> Option<&'static str> {
    let five_axis = b.tool_side || b.leading_edge;
    let conventional = !five_axis;
    [
        (b.cutting_point, "cutter radius compensation under cutting point control (G43.8/G43.9)"),
        (b.transform, "cutter radius compensation with rotation, scaling, mirror image or polar coordinates"),
        (b.five_axis || b.tcp && conventional, "cutter radius compensation with TCP, a tilted working plane or G54.4"),
        (b.cycle, "cutter radius compensation in a canned cycle"),
        (b.smoothing, "cutter radius compensation with smoothing (G05.1 Q3, HPCC)"),
        (b.coordinates, "cutter radius compensation with G28/G30/G53, G52/G92 or a workpiece system change"),
        (b.rotary && conventional, "cutter radius compensation with a rotary axis moving"),
        (b.inverse_time, "cutter radius compensation in inverse time feed (G93)"),
        (b.corner_override, "automatic corner override (G62) in cutter radius compensation"),
        (b.ijk_in_comp_block, "I, J, K in a G41/G42 block (the direction of the offset vector)"),
        (b.tool_side && b.q, "Q other than Q1/Q2/Q3 in the tool side offset (type 2: its inclination)"),
        (b.type2_alone, "the tool side offset of type 2 (G41.6/G42.6) without G43.5"),
        (b.leading_edge && b.rotary_table, "the leading edge offset (G41.3) on a machine with a rotary table"),
        (
            b.leading_edge && b.no_mechanism,
            "the leading edge offset (G41.3) on a machine without a tool rotation mechanism",
        ),
        (b.leading_edge && b.q, "Q in the leading edge offset (G41.3)"),
    ]
    .into_iter()
    .find_map(|(refused, function)| refused.then_some(function))
}

/// An address letter fivex reads but no function of it uses in `dialect`: E (FANUC M series and
/// Syntec: the thread lead of G33, which is not built; Haas: [`HAAS_E`]), the comma addresses of chamfering and corner
/// rounding (`,C` `,R`: performed in FANUC and Haas, `interp::chamfer`; Syntec's form is not
/// known) and of the angle of direct drawing dimension programming (`,A`), in the lower case
/// `lang::ast::Word::letter` gives them. Macro call arguments (G65/G66) are not addresses here.
pub fn address(letter: u8, dialect: Dialect) -> Option<&'static str> {
    match letter {
        b'E' if dialect == Dialect::Haas => Some(HAAS_E),
        b'E' => Some("address E (thread lead)"),
        b'c' if dialect == Dialect::Syntec => Some("chamfering (,C)"),
        b'r' if dialect == Dialect::Syntec => Some("corner rounding (,R)"),
        b'a' => Some("angle of direct drawing dimension programming (,A)"),
        _ => None,
    }
}

/// What the NGC mill's E is where fivex refuses it: the E of G187 (contouring accuracy,
/// performed) and of G47 (engraving feed, G47 refused as a whole) are `argument_of` those codes;
/// anywhere else it is the E of a function fivex does not build (the NGC's G82 chip-clean
/// speed…). The mill has no G33, so "thread lead" named no function of the dialect (Haas's
/// address list: "E Engraving Feed Rate or Contouring Accuracy", `docs/dialects.md`).
pub const HAAS_E: &str = "address E outside G187 (contouring accuracy) and G47 (engraving feed)";

/// A word of a subprogram call or return block (M98/M198, M99) that asks for a form of the call
/// fivex does not carry out in `dialect` (`docs/dialects.md`, "Functions not built"). Syntec:
/// - H of M98/M198, which Autodesk's SYIL/Syntec post writes as `M98 H<n>` to call the
///   subprogram it puts after M30 as the block N<n> of the same program; no Syntec source among
///   fivex's references describes the form, and read as a tool length offset (as it is in any
///   other block) it would change the tool length;
/// - Q of M99, the return to a line number of the caller (the Syntec MACRO syntax handbook,
///   §5.2); fivex ignored Q and returned to the block after the call.
pub fn call_address(m: u32, letter: u8, dialect: Dialect) -> Option<&'static str> {
    use crate::interp::mcode::{M99, SUBPROGRAM_CALLS};
    match (dialect, letter) {
        (Dialect::Syntec, b'H') if SUBPROGRAM_CALLS.contains(&m) => {
            Some("subprogram call of a sequence number (M98 H)")
        }
        (Dialect::Syntec, b'Q') if m == M99 => Some("return to a line number (M99 Q)"),
        _ => None,
    }
}

/// A Haas M code that changes what the program does next from a machine state fivex does not
/// model (an input, a pallet, the operator's answer): refused rather than passed
/// on as an auxiliary function, which would run on as if the condition never held.
pub fn haas_m_code(m: u32) -> Option<&'static str> {
    match m {
        46 => Some("jump if the pallet is loaded (M46)"),
        47 => Some("jump on the pallet (M47)"),
        96 => Some("jump if no input (M96)"),
        109 => Some("interactive user input (M109)"),
        _ => None,
    }
}

/// `letter` is an argument of the G code `code` in `dialect`, decided by the code's row rather
/// than by [`address`]: every letter of a macro call G65/G66/G66.1 (E is argument #8 of
/// specification I; the call takes the words as arguments, none as an address), Syntec's G05 E
/// (decided by its row), Haas's G187 E (its maximum corner rounding, `interp::corner_blend`) and
/// G47 E (the engraving's plunge feed: the block is refused as G47, not as an E of G33).
pub fn argument_of(code: u16, dialect: Dialect, letter: u8) -> bool {
    use crate::interp::gcode::code::MACRO_CALLS;
    let haas_e = dialect == Dialect::Haas && matches!(code, 470 | 1870);
    MACRO_CALLS.contains(&code) && letter.is_ascii_uppercase()
        || letter == b'E' && (code == 50 && dialect == Dialect::Syntec || haas_e)
}

/// The codes of the table (for documentation checks).
pub fn codes() -> impl Iterator<Item = (u16, Option<Dialect>, &'static str)> {
    TABLE.iter().map(|r| (r.code, r.dialect, r.function))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::gcode;

    #[test]
    fn every_row_is_a_code_of_the_table() {
        for (code, dialect, _) in codes() {
            let d = dialect.unwrap_or(Dialect::Fanuc);
            assert!(gcode::lookup(code, d).is_some(), "{}", gcode::display(code));
        }
    }

    #[test]
    fn docs_list_every_function_not_built() {
        let table: String = codes()
            .map(|(code, dialect, function)| {
                let dialects = dialect.map_or("both", |d| d.name());
                format!("| `{}` | {dialects} | {function} |\n", gcode::display(code))
            })
            .collect();
        let docs = include_str!("../../../docs/dialects.md");
        assert!(docs.contains(&table), "docs/dialects.md must contain this table:\n{table}");
    }

    #[test]
    fn values_decide() {
        let q = |v: Word| move |l: u8| if l == b'Q' { v } else { Word::Absent };
        assert!(g_code(51, Dialect::Fanuc, &[], q(Word::Value(1.0))).is_none());
        assert!(g_code(51, Dialect::Fanuc, &[], q(Word::Value(3.0))).is_none());
        assert!(g_code(51, Dialect::Fanuc, &[], q(Word::Value(2.0))).is_some());
        assert!(g_code(51, Dialect::Syntec, &[], q(Word::Value(3.0))).is_some());
        assert!(g_code(51, Dialect::Fanuc, &[], q(Word::Absent)).is_some());
        assert!(g_code(51, Dialect::Fanuc, &[], q(Word::Unknown)).is_none());
        let p_e = |p: f64, e: Word| {
            move |l: u8| match l {
                b'P' => Word::Value(p),
                b'E' => e,
                _ => Word::Absent,
            }
        };
        assert!(g_code(50, Dialect::Syntec, &[], p_e(10000.0, Word::Absent)).is_none());
        assert!(g_code(50, Dialect::Syntec, &[], p_e(10000.0, Word::Value(1.0))).is_some());
        assert!(g_code(50, Dialect::Syntec, &[], p_e(10000.0, Word::Value(0.0))).is_none());
        assert!(g_code(50, Dialect::Syntec, &[], p_e(10000.0, Word::Unknown)).is_none());
        assert!(g_code(50, Dialect::Fanuc, &[], p_e(10000.0, Word::Absent)).is_some());
        assert!(g_code(50, Dialect::Fanuc, &[], p_e(0.0, Word::Absent)).is_none());
    }

    #[test]
    fn haas_rows_name_the_ngc_function() {
        let none = |_: u8| Word::Absent;
        assert_eq!(g_code(370, Dialect::Haas, &[], none), Some("automatic tool offset measurement (G37)"));
        assert_eq!(g_code(370, Dialect::Fanuc, &[], none), Some("automatic tool length measurement (G37)"));
        assert_eq!(
            g_code(2530, Dialect::Haas, &[], none),
            Some("spindle normal to the feature coordinate system (G253)")
        );
        // G234, G254/G255 are performed (`interp::tcp`, `interp::dwo`).
        assert_eq!(g_code(2340, Dialect::Haas, &[], none), None);
        // G154 / G110–G129 are performed (the G54.1 P work offsets).
        assert_eq!(g_code(1540, Dialect::Haas, &[], none), None);
        assert_eq!(g_code(1100, Dialect::Haas, &[], none), None);
    }
}
