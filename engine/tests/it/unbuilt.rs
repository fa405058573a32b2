//! No silent stubs: every G code of the parser's table (and of the Haas NGC's) and every
//! address letter, in every dialect, is either performed (an example program runs to its end; the function's own
//! behaviour tests are named beside it) or refused at its block with the dialect's alarm
//! (`interp::unbuilt`). A code added to the table without a decision fails
//! `every_g_code_has_a_decision`.

use crate::common;
use common::*;

use fivex_engine::check::check;
use fivex_engine::interp::gcode;
use fivex_engine::lang::parse_file;
use fivex_engine::Dialect::{self, Fanuc, Haas, Syntec};

/// The machine of these tests: X Y Z and the rotary axes B C (for G07.1 C and 5-axis codes).
const PRESET: &str = "head-bc";

/// FANUC codes the Syntec 5-axis manual does not have: COR-070 in the Syntec dialect.
const FANUC_ONLY: &[&str] = &[
    "G41.2", "G41.3", "G41.4", "G41.5", "G41.6", "G42.2", "G42.4", "G42.5", "G42.6", "G43.8", "G43.9", "G54.4", "G68.4",
];

/// Performed in the FANUC dialect only (refused in Syntec's, listed in `REFUSED`).
/// G66.1: Syntec's is not FANUC's (`syntec_calls.rs`); G27: Syntec's sources do not describe
/// it. Haas: its own table decides.
const PERFORMED_IN_FANUC_ONLY: &[&str] = &["G06.2", "G27", "G66.1"];

/// Performed in the Syntec dialect only: FANUC's tilted plane refuses G53.6 (the FANUC extract
/// does not name it) and outside a plane there is nothing to align to, PS5462 either way
/// (`modes.rs`, `docs/five-axis.md`).
const PERFORMED_IN_SYNTEC_ONLY: &[&str] = &["G53.6"];

/// Shared codes the Haas dialect refuses: the NGC's G87 is not FANUC's back boring (its back
/// bore is G77, refused too; `docs/dialects.md`, "Haas cycles").
const NOT_PERFORMED_IN_HAAS: &[&str] = &["G87"];

/// Performed: (the code, an example that must run to its end, where its behaviour is tested).
/// `M30` is appended unless the example has it (to put subprograms after it).
const PERFORMED: &[(&str, &str, &str)] = &[
    ("G00", "G00 X1.", "fixture g00_g01_square"),
    ("G01", "G01 X1. F100", "fixture g00_g01_square"),
    ("G02", "G02 X2. R1. F100", "fixture arcs_ij, arc_r_word"),
    ("G03", "G03 X2. R1. F100", "fixture arcs_ij, helix"),
    ("G04", "G04 P100", "fixture dwell"),
    ("G04.1", "G04.1", "decision: fivex reads no block ahead that a program could see (docs/dialects.md)"),
    ("G05", "G05 P0", "G05 P0 is the cancelled state; Syntec's G05 P10000 (HPCC): hpcc.rs"),
    ("G05.1", "G05.1 Q1\nG05.1 Q0", "wse.rs (look-ahead on/off); FANUC's Q3: smoothing.rs"),
    ("G06.2", "G06.2 P3 K0 F100\nK0 X1. Y0\nK0 X1. Y1.\nK1.\nK1.\nK1.\nG01 X1.", "nurbs.rs (FANUC; Syntec refuses it)"),
    ("G08", "G08 P1\nG08 P0", "decision: the planner always looks ahead (docs/dialects.md)"),
    ("G09", "G09 G01 X1. F100", "fixture exact_stop_g09_g61_g64"),
    ("G10", "G10 L2 P1 X0\nG10 L10 P1 R100.", "fixture g10_tool_offsets"),
    ("G11", "G11", "cancel of a data input mode fivex does not have"),
    ("G13.1", "G13.1", "the cancelled state of G12.1"),
    ("G15", "G15", "frames.rs"),
    ("G16", "G16\nG15", "frames.rs"),
    ("G17", "G17", "fixture arcs_planes"),
    ("G18", "G18\nG17", "fixture arcs_planes"),
    ("G19", "G19\nG17", "fixture arcs_planes"),
    ("G20", "G20\nG21", "fixture g20_inch"),
    ("G21", "G21", "fixture g20_inch"),
    ("G22", "G22", "decision: no stored stroke check 2 area is set, nothing to check"),
    ("G23", "G23\nG22", "stroke check 2 off"),
    ("G25", "G25", "the cancelled state of G26"),
    ("G27", "G27 X0 Y0 Z0", "motion.rs (the check at the reference position; Syntec refuses it)"),
    ("G28", "G28 Z0", "fixture g28_g53"),
    ("G29", "G28 Z0\nG29 Z0", "fixture g28_g53"),
    ("G30", "G30 Z0", "fixture scaling_g51_g62_g63_g30"),
    ("G31", "G31 X1. F100", "data probing/skip_* (the probe and the workpiece, interp::skip)"),
    ("G38", "G41 D1 G01 X10. F500\nG38 Y10.\nG40 X0", "cutter.rs vector_hold (G38 vector hold)"),
    ("G39", "G41 D1 G01 X10. F500\nG39\nY10.\nG40 X0", "cutter.rs corner_arc (G39 corner circular interpolation)"),
    ("G40", "G40", "the cancelled state of cutter compensation"),
    ("G41", "G41 D1 G01 X10. F500\nG40 X0", "cutter.rs (cutter compensation C)"),
    ("G42", "G42 D1 G01 X10. F500\nG40 X0", "cutter.rs (cutter compensation C)"),
    ("G41.2", "G41.2 D1 G01 X10. F500\nG40 X0", "tool_side.rs (5-axis tool side offset, type 1)"),
    ("G41.3", "G01 F500\nG41.3 D1\nX10.\nG40", "leading_edge.rs (5-axis leading edge offset)"),
    ("G42.2", "G42.2 D1 G01 X10. F500\nG40 X0", "tool_side.rs (5-axis tool side offset, type 1)"),
    ("G41.6", "G43.5 H1\nG41.6 D1 G01 X10. F500\nG40 X0\nG49", "tool_side.rs (tool side offset, type 2, under G43.5)"),
    ("G42.6", "G43.5 H1\nG42.6 D1 G01 X10. F500\nG40 X0\nG49", "tool_side.rs (tool side offset, type 2, under G43.5)"),
    ("G40.1", "G40.1", "the cancelled state of normal direction control"),
    ("G43", "G43 H1 Z0\nG49", "fixture g43_g44_g49_tools_file"),
    ("G43.4", "G43.4 H1\nG49", "tcp.rs"),
    ("G43.5", "G43.5 H1\nG49", "tcp.rs"),
    ("G43.8", "G43.8 H1 D1 ,L2 I1.\nG01 X1. F100\nG49", "cutting_point.rs (cutting point control, type 1)"),
    ("G43.9", "G43.9 H1 D1 ,L2 I1.\nG01 X1. I0 J0 K1. F100\nG49", "cutting_point.rs (cutting point control, type 2)"),
    ("G44", "G44 H1 Z0\nG49", "fixture g43_g44_g49_tools_file"),
    ("G49", "G49", "fixture g43_g44_g49_tools_file"),
    ("G49.1", "G49.1", "tool length compensation cancel"),
    ("G50", "G51 X0 Y0 P2\nG50", "frames.rs"),
    ("G50.1", "G50.1", "frames.rs"),
    ("G51", "G51 X0 Y0 P2\nG50", "frames.rs"),
    ("G51.1", "G51.1 X0\nG50.1", "frames.rs"),
    ("G52", "G52 X1.\nG52 X0", "fixture g52_local"),
    ("G53", "G53 Z0", "fixture g28_g53"),
    ("G53.1", "G68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG69", "twp.rs"),
    ("G53.3", "G68.2 X0 Y0 Z0 I0 J30. K0\nG53.3\nG69", "fixture syntec_only_g_code, twp.rs"),
    ("G53.6", "G68.2 X0 Y0 Z0 I0 J30. K0\nG53.6 H1\nG49\nG69", "twp.rs, modes.rs"),
    ("G54", "G54", "fixture work_offsets_g54_g59"),
    ("G54.1", "G54.1 P1\nG54", "fixture g54_1_p"),
    ("G54.2", "G54.2 P0", "the cancelled state (G54.2 P1… is refused)"),
    ("G54.4", "G54.4 P1\nG54.4 P0", "wse.rs"),
    ("G55", "G55\nG54", "fixture work_offsets_g54_g59"),
    ("G56", "G56\nG54", "fixture work_offsets_g54_g59"),
    ("G57", "G57\nG54", "fixture work_offsets_g54_g59"),
    ("G58", "G58\nG54", "fixture work_offsets_g54_g59"),
    ("G59", "G59\nG54", "fixture work_offsets_g54_g59"),
    ("G61", "G61\nG64", "fixture exact_stop_g09_g61_g64"),
    ("G62", "G62\nG64", "decision: its override acts only in cutter compensation, where G62 is refused (cutter.rs)"),
    ("G63", "G63\nG64", "fixture scaling_g51_g62_g63_g30"),
    ("G64", "G64", "fixture exact_stop_g09_g61_g64"),
    ("G65", "G65 P9000\nM30\nO9000\nM99", "fixture g65_macro_args"),
    ("G66", "G66 P9000\nG67\nM30\nO9000\nM99", "fixture g66_modal_call"),
    ("G66.1", "G66.1 P9000\nG67\nM30\nO9000\nM99", "fixture g66_1_every_block"),
    ("G67", "G67", "fixture g66_modal_call"),
    ("G68", "G68 X0 Y0 R10.\nG69", "fixture coordinate_transforms"),
    ("G68.2", "G68.2 X0 Y0 Z0 I0 J30. K0\nG69", "twp.rs"),
    ("G68.3", "G68.3 X0 Y0 Z0\nG69", "twp.rs"),
    ("G68.4", "G68.4 X0 Y0 Z0 I0 J30. K0\nG69", "twp.rs"),
    ("G69", "G69", "twp.rs"),
    ("G69.1", "G69.1", "cancel of the rotation"),
    ("G73", "G73 X1. Z-1. R1. Q0.5 F100\nG80", "fixture g82_g83_g73_peck"),
    ("G74", "M04 S100\nG74 X1. Z-1. R1. F100\nG80", "fixture cycles_g74_g87_g88_g89"),
    ("G76", "M03 S100\nG76 X1. Z-1. R1. Q0.1 F100\nG80", "fixture g76_fine_boring"),
    ("G80", "G80", "fixture g81_drill_g98_g99_repeat"),
    ("G80.5", "G80.5", "the cancelled state of G81.5"),
    ("G81", "G81 X1. Z-1. R1. F100\nG80", "fixture g81_drill_g98_g99_repeat"),
    ("G82", "G82 X1. Z-1. R1. P100 F100\nG80", "fixture g82_g83_g73_peck"),
    ("G83", "G83 X1. Z-1. R1. Q0.5 F100\nG80", "fixture g82_g83_g73_peck"),
    ("G84", "M03 S100\nG84 X1. Z-1. R1. F100\nG80", "fixture g84_g85_g86_tap_bore"),
    ("G84.2", "M03 S100\nG84.2 X1. Z-1. R1. F100\nG80", "cycles.rs (as G84)"),
    ("G84.3", "M04 S100\nG84.3 X1. Z-1. R1. F100\nG80", "cycles.rs (as G74)"),
    ("G85", "G85 X1. Z-1. R1. F100\nG80", "fixture g84_g85_g86_tap_bore"),
    ("G86", "M03 S100\nG86 X1. Z-1. R1. F100\nG80", "fixture g84_g85_g86_tap_bore"),
    ("G87", "M03 S100\nG87 X1. Z1. R-5. Q0.1 F100\nG80", "fixture cycles_g74_g87_g88_g89"),
    ("G88", "M03 S100\nG88 X1. Z-1. R1. F100\nG80", "fixture cycles_g74_g87_g88_g89"),
    ("G89", "G89 X1. Z-1. R1. P100 F100\nG80", "fixture cycles_g74_g87_g88_g89"),
    ("G90", "G90", "fixture g91_incremental"),
    ("G91", "G91\nG90", "fixture g91_incremental"),
    ("G92", "G92 X0", "fixture g92_shift"),
    ("G92.1", "G92.1 X0", "fixture g92_shift"),
    ("G93", "G93\nG94", "fixture feed_modes_g93_g94_g95"),
    ("G94", "G94", "fixture feed_modes_g93_g94_g95"),
    ("G95", "G95\nG94", "fixture feed_modes_g93_g94_g95"),
    ("G97", "G97", "the cancelled state of G96"),
    ("G98", "G98", "fixture g81_drill_g98_g99_repeat"),
    ("G99", "G99\nG98", "fixture g81_drill_g98_g99_repeat"),
    ("G160", "G160", "the cancelled state of G161"),
];

/// Refused: (the block, the dialects it is refused in). The block's first G word is the code.
const REFUSED: &[(&str, &[Dialect])] = &[
    ("G02.2 X1. Y1. I1. J0 R1. F100", &[Fanuc, Syntec]),
    ("G02.3 X1. Y1. R1. F100", &[Fanuc, Syntec]),
    ("G02.4 X1. Y1. Z1. I1. J1. K1. F100", &[Fanuc, Syntec]),
    ("G03.2 X1. Y1. I1. J0 R1. F100", &[Fanuc, Syntec]),
    ("G03.3 X1. Y1. R1. F100", &[Fanuc, Syntec]),
    ("G03.4 X1. Y1. Z1. I1. J1. K1. F100", &[Fanuc, Syntec]),
    // Syntec: G05 P10000 is HPCC, its E argument is not built; a P other than 10000 or 0 is
    // its format error COR-107 (hpcc.rs).
    ("G05 P10000", &[Fanuc]),
    ("G05 P1", &[Fanuc]),
    ("G05", &[Fanuc]),
    ("G05 P10000 E1.", &[Syntec]),
    ("G05.1 Q3", &[Syntec]),
    ("G05.1 Q2", &[Fanuc, Syntec]),
    ("G05.1", &[Fanuc, Syntec]),
    ("G05.4 Q1", &[Fanuc, Syntec]),
    ("G06.2 P4 X0 Y0 Z0 K0", &[Syntec]),
    ("G66.1 P9000", &[Syntec]),
    ("G07 C10.", &[Fanuc, Syntec]),
    ("G07.1 C10.", &[Fanuc, Syntec]),
    ("G07.1 C0", &[Fanuc, Syntec]),
    ("G10.6 Z10.", &[Fanuc, Syntec]),
    ("G12.1", &[Fanuc, Syntec]),
    ("G17.1 P1", &[Fanuc, Syntec]),
    ("G22 X100. Y100. Z100. I-100. J-100. K-100.", &[Fanuc, Syntec]),
    ("G26 P1000 Q100 R10", &[Fanuc, Syntec]),
    ("G27 X0 Y0 Z0", &[Syntec]),
    ("G28.2 Z0", &[Fanuc, Syntec]),
    ("G30.1 Z0", &[Fanuc, Syntec]),
    ("G31.8 X1. F100", &[Fanuc, Syntec]),
    ("G31.9 X1. F100", &[Fanuc, Syntec]),
    ("G33 Z-10. F1.", &[Fanuc, Syntec]),
    ("G34 Z-10. F1. K0.1", &[Fanuc, Syntec]),
    ("G35 X10. Z0 R5. F1.", &[Fanuc, Syntec, Haas]),
    ("G36 X10. Z0 R5. F1.", &[Fanuc, Syntec, Haas]),
    ("G37 Z-10.", &[Fanuc, Syntec, Haas]),
    // FANUC's three-dimensional tool compensation: I, J and K all in the G41/G42 block (audit
    // crc2 N1). Syntec and Haas give them no meaning there: refused alike.
    ("G41 D1 G01 X10. Y0 Z0 I0 J0 K1. F500.", &[Fanuc, Syntec, Haas]),
    ("G42 D1 G01 X10. I0.5 J0 K0.866 F500.", &[Fanuc, Syntec, Haas]),
    ("G41.1", &[Fanuc, Syntec]),
    ("G41.2 D1", &[Syntec]),
    ("G41.3 D1", &[Syntec]),
    ("G41.4 D1", &[Syntec]),
    ("G41.5 D1", &[Syntec]),
    ("G41.6 D1", &[Syntec]),
    ("G42.1", &[Fanuc, Syntec]),
    ("G42.2 D1", &[Syntec]),
    ("G42.4 D1", &[Syntec]),
    ("G42.5 D1", &[Syntec]),
    ("G42.6 D1", &[Syntec]),
    ("G43.1 H1", &[Fanuc, Syntec]),
    ("G43.7 H1", &[Fanuc, Syntec]),
    ("G43.8 H1", &[Syntec]),
    ("G43.9 H1", &[Syntec]),
    ("G45 X1. D1", &[Fanuc, Syntec]),
    ("G46 X1. D1", &[Fanuc, Syntec]),
    ("G47 X1. D1", &[Fanuc, Syntec, Haas]),
    ("G48 X1. D1", &[Fanuc, Syntec]),
    ("G54.2 P1", &[Fanuc, Syntec]),
    ("G60 X1.", &[Fanuc, Syntec, Haas]),
    // FANUC's three-dimensional coordinate conversion: G68 with an axis of rotation I, J, K
    // (audit xf 1: it ran as the plane's rotation, the contour turned in XY). The 2-D G68 runs.
    ("G68 X0 Y0 Z0 I1. J0 K0 R90.", &[Fanuc, Syntec, Haas]),
    ("G68 X0 Y0 R90. K1.", &[Fanuc, Syntec, Haas]),
    ("G72.1 P10 L2 X0 Y0 R90.", &[Fanuc, Syntec]),
    ("G72.2 P10 L2 I10. J0", &[Fanuc, Syntec]),
    ("G81.1 Z10. Q5. R2. F1000", &[Fanuc, Syntec]),
    ("G81.5 T1 L1", &[Fanuc, Syntec]),
    ("G96 S100", &[Fanuc, Syntec]),
    ("G161 R1.", &[Fanuc, Syntec, Haas]),
    // The Haas NGC's own codes fivex does not carry out (its G35/G36/G37/G47/G161 are above).
    ("G77 X1. Z-1. R1. I0.1 F100.", &[Haas]),
    ("G87 X1. Z1. R-5. Q0.1 F100.", &[Haas]),
    ("G107 Y0 R10.", &[Haas]),
    ("G136 P1", &[Haas]),
    ("G141 D1 X1. F100.", &[Haas]),
    ("G143 H1", &[Haas]),
    ("G153 X1. Z-1. R1. Q0.5 F100.", &[Haas]),
    ("G155 X1. Z-1. R1. F100.", &[Haas]),
    ("G162 X1. Z-1. R1. F100.", &[Haas]),
    ("G163 X1. Z-1. R1. Q0.5 F100.", &[Haas]),
    ("G164 X1. Z-1. R1. F100.", &[Haas]),
    ("G165 X1. Z-1. R1. F100.", &[Haas]),
    ("G166 X1. Z-1. R1. F100.", &[Haas]),
    ("G169 X1. Z-1. R1. P100 F100.", &[Haas]),
    ("G174 X1. Z-1. F100.", &[Haas]),
    ("G184 X1. Z-1. F100.", &[Haas]),
    ("G253", &[Haas]),
    ("G266 X1.", &[Haas]),
    ("G268 X0 Y0 Z0 I0 J30. K0", &[Haas]),
    ("G269", &[Haas]),
    // Syntec codes Autodesk's SYIL post writes (audit A2 F5): COR-100 naming them, not COR-070.
    ("G59.1", &[Syntec]),
    ("G120.1 P2 Q2", &[Syntec]),
    ("G121", &[Syntec]),
];

/// Performed in the Haas dialect only: the NGC's own codes fivex carries out.
const PERFORMED_IN_HAAS: &[(&str, &str, &str)] = &[
    ("G100", "G101 X0\nG100", "data fixture frames/haas_g101_mirrors_about_work_zero (mirror image off)"),
    ("G101", "G101 X0\nG100", "data fixture frames/haas_g101_mirrors_about_work_zero (mirror image about work zero)"),
    ("G154", "G154 P5\nG54", "data fixture frames/haas_g154_work_offsets (the G54.1 P offsets)"),
    ("G187", "G187 P3 E0.01\nG01 X1. F100.\nY1.", "corner_rounding.rs (G187 rounds corners within E)"),
    ("G110", "G110\nG54", "data fixture frames/haas_g154_work_offsets (G154 P1)"),
    ("G111", "G111\nG54", "G154 P2"),
    ("G112", "G112\nG54", "G154 P3"),
    ("G113", "G113\nG54", "G154 P4"),
    ("G114", "G114\nG54", "G154 P5"),
    ("G115", "G115\nG54", "G154 P6"),
    ("G116", "G116\nG54", "G154 P7"),
    ("G117", "G117\nG54", "G154 P8"),
    ("G118", "G118\nG54", "G154 P9"),
    ("G119", "G119\nG54", "G154 P10"),
    ("G120", "G120\nG54", "G154 P11"),
    ("G121", "G121\nG54", "G154 P12"),
    ("G122", "G122\nG54", "G154 P13"),
    ("G123", "G123\nG54", "G154 P14"),
    ("G124", "G124\nG54", "G154 P15"),
    ("G125", "G125\nG54", "G154 P16"),
    ("G126", "G126\nG54", "G154 P17"),
    ("G127", "G127\nG54", "G154 P18"),
    ("G128", "G128\nG54", "G154 P19"),
    ("G129", "G129\nG54", "G154 P20"),
    ("G234", "G234 H1\nG49", "haas_five_axis.rs"),
    ("G254", "G254\nG255", "haas_five_axis.rs"),
    ("G255", "G255", "haas_five_axis.rs"),
    ("G12", "G00 Z10.\nG12 I10. D1 Z-1. F100.", "haas_cycles.rs, fixture haas_g13_circular_pocket"),
    ("G13", "G00 Z10.\nG13 I10. D1 Z-1. F100.", "haas_cycles.rs, fixture haas_g13_circular_pocket"),
    ("G70", "G81 Z-1. R1. F100. L0\nG70 I10. J0 L4\nG80", "fixture haas_g70_bolt_hole_circle"),
    ("G71", "G81 Z-1. R1. F100. L0\nG71 I10. J0 K10. L4\nG80", "fixture haas_g71_bolt_hole_arc"),
    ("G72", "G81 Z-1. R1. F100. L0\nG72 I10. J0 L4\nG80", "fixture haas_g72_bolt_holes_along_an_angle"),
    ("G103", "G103 P1\nG103 P0", "haas_cycles.rs g103_p1_slows_a_chain_of_short_blocks"),
    (
        "G150",
        "G00 Z10.\nG150 X15. Y10. Z-2. R1. Q2. J4. K0.5 P100 D1 F100.\nM30\nN100 G01 Y20.\nX0\nY0\nX30.\nY20.\nX15.\nM99",
        "haas_cycles.rs g150_*, fixture haas_g150_manual_example_o0100",
    ),
];

/// The Haas dialect reads an F without a decimal point in least increments (Setting 77): the
/// examples' feeds get their point there, so that they mean what they mean in FANUC's.
fn in_dialect(body: &str, dialect: Dialect) -> String {
    if dialect != Haas {
        return body.to_string();
    }
    body.split_inclusive([' ', '\n'])
        .map(|w| {
            let t = w.trim_end();
            if t.starts_with('F') && t.len() > 1 && t[1..].chars().all(|c| c.is_ascii_digit()) {
                format!("{t}.{}", &w[t.len()..])
            } else {
                w.to_string()
            }
        })
        .collect()
}

/// Address letters on `PRESET` (axes X Y Z B C): performed, with an example that runs to its
/// end; E is refused; A U V W are not axes of the machine (PS0009 / COR-002).
const LETTERS_PERFORMED: &[(u8, &str)] = &[
    (b'B', "G00 B10."),
    (b'C', "G00 C10."),
    (b'D', "D1"),
    (b'F', "G01 X1. F100"),
    (b'G', "G00"),
    (b'H', "G43 H1 Z0\nG49"),
    (b'I', "G02 X2. I1. F100"),
    (b'J', "G19 G02 Y2. J1. F100\nG17"),
    (b'K', "G18 G02 Z2. K1. F100\nG17"),
    (b'L', "G10 L2 P1 X0"),
    (b'M', "M05"),
    (b'N', "N10 G00 X1."),
    (b'O', "M98 P20\nM30\nO0020\nM99"),
    (b'P', "G04 P10"),
    (b'Q', "G83 X1. Z-1. R1. Q0.5 F100\nG80"),
    (b'R', "G02 X2. R1. F100"),
    (b'S', "S1000"),
    (b'T', "T1"),
    (b'X', "G00 X1."),
    (b'Y', "G00 Y1."),
    (b'Z', "G00 Z1."),
];
const LETTERS_REFUSED: &[u8] = b"E";
const LETTERS_NOT_AXES: &[u8] = b"AUVW";

fn program(body: &str) -> String {
    if body.contains("M30") {
        format!("#100=1\n{body}\n")
    } else {
        format!("#100=1\n{body}\nM30\n")
    }
}

fn first_g(block: &str) -> &str {
    block.split_whitespace().find(|w| w.starts_with('G')).expect("a G word")
}

fn has_code(dialect: Dialect, name: &str) -> bool {
    let code = gcode::code_of(name[1..].parse().unwrap()).unwrap();
    gcode::written(code, dialect).is_some()
}

/// The alarm a refused function gives in `dialect`.
fn refusal(dialect: Dialect, code: &str) -> &'static str {
    match dialect {
        Fanuc => "PS0010",
        Syntec if FANUC_ONLY.contains(&code) => "COR-070",
        Syntec => "COR-100",
        Haas => "310",
    }
}

/// Performed only on a machine setting's request: (the code, the preset, an example that runs to
/// its end there with FANUC's SPG = 1, where its behaviour is tested). Elsewhere the mode
/// interlocks refuse them (PS0010 without SPG, PS5460 on another mechanism; `tool_side.rs`).
const PERFORMED_WITH_SPG: &[(&str, &str, &str)] = &[
    ("G41.4", "table-ac", "G41.4 D1 G01 X10. F500\nG40 X0"),
    ("G42.4", "table-ac", "G42.4 D1 G01 X10. F500\nG40 X0"),
    ("G41.5", "mixed-bc", "G41.5 D1 G01 X10. F500\nG40 X0"),
    ("G42.5", "mixed-bc", "G42.5 D1 G01 X10. F500\nG40 X0"),
];

#[test]
fn codes_by_mechanism_run_with_spg() {
    for (name, preset, body) in PERFORMED_WITH_SPG {
        let spg = |c: &mut fivex_engine::interp::Config| c.edit_machine(|m| m.five_axis.crc_codes_by_mechanism = true);
        assert_eq!(first_alarm_with(&program(body), preset, spg), None, "{name} on {preset}");
        // And `fivex check` does not call them unbuilt.
        assert!(check(parse_file(&program(body)), Fanuc).is_empty(), "{name}");
    }
}

#[test]
fn every_g_code_has_a_decision() {
    for dialect in [Fanuc, Syntec, Haas] {
        let table = gcode::TABLE.iter().chain(gcode::HAAS_TABLE);
        // A code the dialect reads as another (Syntec's G70/G71 are G20/G21) is that code's.
        for def in table.filter(|d| gcode::written(d.code, dialect).is_some_and(|w| w.code == d.code)) {
            let name = gcode::display(def.code);
            let haas_own = gcode::HAAS_TABLE.contains(def);
            let performed = PERFORMED.iter().any(|(g, _, _)| *g == name) && !haas_own
                || dialect == Haas && PERFORMED_IN_HAAS.iter().any(|(g, _, _)| *g == name)
                || dialect == Fanuc && PERFORMED_WITH_SPG.iter().any(|(g, _, _)| *g == name);
            let refused = REFUSED.iter().any(|(b, ds)| first_g(b) == name && ds.contains(&dialect));
            assert!(performed || refused, "{dialect:?}: {name} is neither performed nor refused: decide");
        }
    }
}

#[test]
fn performed_codes_run_to_their_end() {
    for dialect in [Fanuc, Syntec, Haas] {
        let here = |g: &str| {
            has_code(dialect, g)
                && !(dialect == Syntec && PERFORMED_IN_FANUC_ONLY.contains(&g))
                && !(dialect == Fanuc && PERFORMED_IN_SYNTEC_ONLY.contains(&g))
                && !(dialect == Haas && NOT_PERFORMED_IN_HAAS.contains(&g))
        };
        // The NGC's own codes of FANUC's numbers (G35 … G161) are not FANUC's functions.
        let haas_own = |g: &str| dialect == Haas && gcode::HAAS_TABLE.iter().any(|d| gcode::display(d.code) == g);
        let haas = PERFORMED_IN_HAAS.iter().filter(|_| dialect == Haas);
        for (name, body, _) in PERFORMED.iter().filter(|(g, _, _)| here(g) && !haas_own(g)).chain(haas) {
            // Codes refused with some values are listed on both sides: only this form runs.
            // G254 needs rotary axes on the table (decision, `docs/dialects.md`, "Haas 5-axis").
            let preset = if *name == "G254" { "table-bc" } else { PRESET };
            let r = run_with(&program(&in_dialect(body, dialect)), preset, dialect);
            assert!(r.completed(), "{dialect:?} {name}: {:?}\n{body}", r.alarms);
        }
    }
}

#[test]
fn refused_codes_alarm_at_their_block_and_change_nothing() {
    for (block, dialects) in REFUSED {
        let name = first_g(block);
        for &dialect in dialects.iter() {
            let r = run_with(&program(block), PRESET, dialect);
            let alarm = r.alarms.first().unwrap_or_else(|| panic!("{dialect:?}: {block} ran"));
            assert_eq!((alarm.code.as_str(), alarm.line), (refusal(dialect, name), 2), "{dialect:?}: {block}");
            assert_eq!(r.variables, vec![(100, 1.0)], "{block}");
            assert!(r.machine.iter().all(|&v| v == 0.0), "{dialect:?}: {block} moved");
        }
    }
}

#[test]
fn refused_codes_are_reported_by_check_at_their_word() {
    for (block, dialects) in REFUSED {
        let name = first_g(block);
        let col = block.find(name).unwrap() as u32 + 1;
        for &dialect in dialects.iter() {
            let diags = check(parse_file(&program(block)), dialect);
            let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, dialect.describe(&d.id).0)).collect();
            assert_eq!(found, vec![(2, col, refusal(dialect, name).to_string())], "{dialect:?}: {block}");
        }
    }
}

#[test]
fn every_address_letter_has_a_decision() {
    for letter in b'A'..=b'Z' {
        let decided = [
            LETTERS_PERFORMED.iter().any(|&(l, _)| l == letter),
            LETTERS_REFUSED.contains(&letter),
            LETTERS_NOT_AXES.contains(&letter),
        ];
        assert_eq!(decided.iter().filter(|&&d| d).count(), 1, "{}", letter as char);
    }
    for dialect in [Fanuc, Syntec, Haas] {
        for (letter, body) in LETTERS_PERFORMED {
            let r = run_with(&program(&in_dialect(body, dialect)), PRESET, dialect);
            assert!(r.completed(), "{dialect:?} {}: {:?}", *letter as char, r.alarms);
        }
        let refused =
            [(LETTERS_REFUSED, ["PS0009", "COR-100", "311"]), (LETTERS_NOT_AXES, ["PS0009", "COR-002", "311"])];
        for (letters, code) in refused {
            for &letter in letters {
                let r = run_with(&program(&format!("G01 X1. {}2. F100.", letter as char)), PRESET, dialect);
                let expected = code[dialect as usize];
                assert_eq!(r.alarms[0].code, expected, "{dialect:?} {}", letter as char);
                assert_eq!(r.alarms[0].line, 2);
            }
        }
    }
}

/// The comma addresses: `,L2 I J K` belongs to cutting point control (FANUC, `cutting_point.rs`);
/// chamfering `,C` and corner rounding `,R` are performed in FANUC and Haas (`interp::chamfer`)
/// and refused in Syntec; the drawing angle `,A` is refused in every dialect. A refused one is
/// refused at its block and reported by `fivex check` at its word.
#[test]
fn comma_addresses_have_a_decision() {
    for dialect in [Fanuc, Syntec, Haas] {
        for (letter, body) in [("C", "G01 X1. ,C1. F100"), ("R", "G01 X1. ,R1. F100"), ("A", "G01 X1. ,A30. F100")] {
            let refused = dialect == Syntec || letter == "A";
            let diags = check(parse_file(&program(body)), dialect);
            let found = diags.iter().find(|d| d.detail.contains("not built"));
            if !refused {
                assert_eq!(found.map(|d| (d.line, d.col)), None, "{dialect:?} ,{letter}: {diags:?}");
                // Performed: with a next move in the plane the program runs.
                let r = run_with(&program(&format!("{body}\nY1.")), PRESET, dialect);
                assert!(r.alarms.is_empty(), "{dialect:?} ,{letter}: {:?}", r.alarms);
                continue;
            }
            let r = run_with(&program(body), PRESET, dialect);
            let expected = match dialect {
                Fanuc => "PS0009",
                Syntec => "COR-100",
                Haas => "311",
            };
            assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (expected, 2), "{dialect:?} ,{letter}");
            assert_eq!(found.map(|d| (d.line, d.col)), Some((2, 9)), "{dialect:?} ,{letter}: {diags:?}");
        }
    }
    // ,L is FANUC's (cutting point control); Syntec has no such address.
    let r = run_with(&program("G01 X1. F100 ,L2 I1."), PRESET, Syntec);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("COR-002", 2));
    // `fivex check` finds what the words alone decide, at the ,L; a normal given by an
    // expression, or one not all zero, is left to the run.
    let diag = |text: &str, dialect| {
        check(parse_file(&program(text)), dialect)
            .iter()
            .map(|d| (d.line, d.col, dialect.describe(&d.id).0))
            .collect::<Vec<_>>()
    };
    assert_eq!(diag("G01 X1. F100 ,L2 I1.", Syntec), vec![(2, 14, "COR-002".to_string())]);
    assert_eq!(diag("G01 X1. F100 ,L3 I1.", Fanuc), vec![(2, 14, "PS0009".to_string())]);
    assert_eq!(diag("G01 X1. F100 ,L2 I0 J0. K0", Fanuc), vec![(2, 14, "PS5464".to_string())]);
    assert_eq!(diag("G01 X1. F100 ,L2 I0 J[#1] K0", Fanuc), vec![]);
    assert_eq!(diag("G01 X1. F100 ,L2 I0 K1.", Fanuc), vec![]);
}

/// The words of a macro call are its arguments, not addresses: E is argument #8 of
/// specification I (`macro-b.md`), so `G65 P9001 E0.5` and `G66 P9001 E0.25` are neither
/// refused by the run nor reported by `fivex check` (which reported PS0009 "address E").
#[test]
fn e_in_a_macro_call_is_an_argument_for_check_as_for_the_run() {
    for dialect in [Fanuc, Syntec, Haas] {
        let modal = if has_code(dialect, "G66") { "G66 P9001 E0.25\nG00 X1.\nG67\n" } else { "" };
        let src = format!("G65 P9001 E0.5\n{modal}M30\nO9001\n#502=#501\n#501=#8\nM99\n");
        assert_eq!(check(parse_file(&src), dialect), vec![], "{dialect:?}: check of\n{src}");
        let r = run_with(&src, PRESET, dialect);
        assert!(r.completed(), "{dialect:?}: {:?}", r.alarms);
        let want = if modal.is_empty() { vec![(501, 0.5)] } else { vec![(501, 0.25), (502, 0.5)] };
        assert_eq!(r.variables, want, "{dialect:?}");
    }
    // Outside a call E stays refused, by check too.
    let diags = check(parse_file("G01 X1. E0.5 F100\nM30\n"), Fanuc);
    assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(1, 9)]);
}

/// E outside its codes is refused in every dialect; what `fivex check` calls it is the
/// dialect's own E: FANUC's and Syntec's thread lead of G33, but the Haas NGC mill has no G33
/// (its E is G187's contouring accuracy and G47's engraving feed, Haas's address list), where
/// "thread lead" named no function the control has (verification audit, Haas item 5).
#[test]
fn check_names_the_dialect_s_own_e() {
    let detail = |dialect| {
        let diags = check(parse_file("G01 X1. E0.5 F100\nM30\n"), dialect);
        assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(1, 9)], "{dialect:?}");
        diags[0].detail.clone()
    };
    for dialect in [Fanuc, Syntec] {
        assert_eq!(detail(dialect), "address E (thread lead) is not built in fivex");
    }
    let haas = detail(Haas);
    assert!(!haas.contains("thread"), "{haas}");
    assert!(haas.contains("G187") && haas.contains("G47"), "{haas}");
    // The run refuses it at its block all the same (311 UNKNOWN CODE).
    let r = run_with("G01 X1. E0.5 F100\nM30\n", PRESET, Haas);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("311", 1));
}

#[test]
fn the_refused_forms_of_a_code_are_values_not_the_code() {
    // Conditional refusals: the performed values of the same code run (the PERFORMED list has
    // the cancels); here the modes that select a different function.
    for (src, dialect) in [
        ("G43.4 H1 L0\nG49", Syntec),
        ("G43.4 H1\nG49", Syntec),
        ("G10 L2 P1 X0", Syntec),
        ("G05 P10000\nG01 X1. F100\nG05 P0", Syntec),
    ] {
        assert!(run_with(&program(src), PRESET, dialect).completed(), "{src}");
    }
    // G10 L5000 is Syntec's; in FANUC it is a G10 format error, as before.
    assert_eq!(run_with(&program("G10 L5000 P2"), PRESET, Fanuc).alarms[0].code, "PS1144");
}

#[test]
fn g41_square_runs_with_the_tool_centre_offset() {
    // Issue 17: G41 D1 (radius 5) on a 10 mm square left the tool centre on the programmed
    // line, then was refused; now the stage offsets it (issue 20) and the run completes there.
    let src = "G90 G00 X0 Y0 Z0\nG41 D1 G01 X10. F500\nY10.\nX0\nY0\nG40 X-5.\nM30\n";
    for dialect in [Fanuc, Syntec] {
        let mut interp = interpreter(src, "mill3", dialect);
        let path = fivex_engine::preview::tool_path(&mut interp, 100);
        assert_eq!(path.alarm, None);
        // Block 2 (start-up, inner corner with block 3) ends at (5, 5), not at (10, 0).
        let i = path.lines.iter().position(|&l| l == 2).unwrap();
        assert!(approx(path.points[i][0], 5.0) && approx(path.points[i][1], 5.0), "{:?}", path.points[i]);
    }
}

/// Audit A2 F5 / A F2: lines every program of Autodesk's SYIL/Syntec post starts with, and the
/// Fusion FANUC post's head-machine check, were refused as syntax errors ("unexpected address
/// R", "unexpected character '@'", "unexpected address P"): another control's functions are
/// refused as not built, named, by the run and by `fivex check` alike.
#[test]
fn other_controls_functions_are_refused_by_name() {
    let cases = [
        ("#199 = R_G53G59_COOR[0,59,3]", Syntec, "COR-100", 8, "R_G53G59_COOR[]"),
        ("@980 = TIME[3]", Syntec, "COR-100", 1, "@ variables"),
        ("IF[PRM[5006,6]NE1]THEN#3000=91(PARAMETER_5006_BIT_6_MUST_BE_SET_TO_1)", Fanuc, "PS0009", 4, "PRM[]"),
        ("#100=PRM[5006,6]", Fanuc, "PS0009", 6, "PRM[]"),
        ("#100=TIME[3]", Haas, "311", 6, "TIME[]"),
    ];
    for (block, dialect, code, col, name) in cases {
        let r = run_with(&program(block), PRESET, dialect);
        assert_eq!(r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect::<Vec<_>>(), [(code, 2)], "{block}");
        let diags = check(parse_file(&program(block)), dialect);
        let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, dialect.describe(&d.id).0)).collect();
        assert_eq!(found, [(2, col, code.to_string())], "{block}");
        assert!(diags[0].detail.contains(name) && diags[0].detail.contains("not built"), "{}", diags[0].detail);
    }
    // A known function is still a function, and a stray letter still a syntax error.
    assert!(run_with(&program("#101=SIN[30.]"), PRESET, Fanuc).completed());
    assert_eq!(run_with(&program("#101=X[1]"), PRESET, Fanuc).alarms[0].code, "PS0004");
}

/// Audit A2 F4: Syntec's M98 with H (the SYIL post's `M98 H<n>`, a call of the block N<n>) is
/// refused as not built, with or without P, before anything of the block is done; `fivex check`
/// reports it at the H. FANUC and Haas keep H as the tool length offset (the M98 without P is the
/// dialect's missing program alarm).
#[test]
fn syntec_m98_h_is_refused_by_the_run_and_by_check() {
    for block in ["M98 H2", "M98 P20 H2"] {
        let src = format!("#100=1\n{block}\nM30\nO0020\nM99\n");
        let r = run_with(&src, PRESET, Syntec);
        assert_eq!(r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect::<Vec<_>>(), [("COR-100", 2)]);
        assert_eq!(r.variables, vec![(100, 1.0)]);
        let diags = check(parse_file(&src), Syntec);
        let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Syntec.describe(&d.id).0)).collect();
        assert_eq!(found, [(2, block.find('H').unwrap() as u32 + 1, "COR-100".to_string())], "{block}");
        assert!(check(parse_file(&src), Fanuc).iter().all(|d| !d.detail.contains("not built")));
    }
    assert!(run_with("M98 P20 H2\nM30\nO0020\nM99\n", PRESET, Fanuc).completed());
}
