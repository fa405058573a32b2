//! The 5-axis mode interlocks (`interp::modes`): one test per rule, each with the alarm in the
//! dialect(s) that state the rule, the other dialect's behaviour (a rule one vendor states does not
//! fire in the other), and the legal variant. The rule's spec row is in the test's comment.
//!
//! `fanuc(preset, src)` / `syntec(preset, src)` give the first alarm code of a run, or "ok".

use crate::common;
use common::*;

use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::{Axis, AxisKind, MachineConfig};
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect;

const MILL: &str = "mill3";
const HEAD: &str = "head-bc";

fn outcome(r: fivex_engine::run::RunResult) -> String {
    if r.completed() {
        "ok".into()
    } else {
        r.alarms[0].code.clone()
    }
}

/// A run with the functions fivex does not build yet allowed (`Config::refuse_unbuilt` off):
/// most interlocks belong to 5-axis cutter compensation, NURBS and smoothing, which a
/// normal run refuses at their first block (`engine/tests/unbuilt.rs`); their rules stay
/// checked here until those functions are built.
fn run_interlocks(src: &str, preset: &str, dialect: Dialect) -> fivex_engine::run::RunResult {
    let src = ended(src);
    let mut interp = interpreter_with(&src, preset, dialect, |c| c.refuse_unbuilt = false);
    run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
}

/// `src` ended by M30: the rules are about its blocks, and a FANUC program whose text ends
/// without M02/M30 stops with PS5010 END OF RECORD (`docs/dialects.md`).
fn ended(src: &str) -> String {
    format!("{src}\nM30\n")
}

fn fanuc(preset: &str, src: &str) -> String {
    outcome(run_interlocks(src, preset, Dialect::Fanuc))
}

fn syntec(preset: &str, src: &str) -> String {
    outcome(run_interlocks(src, preset, Dialect::Syntec))
}

/// What Syntec answers a program whose rule only FANUC states: nothing ("ok"), or COR-070
/// when the program uses a FANUC code the Syntec manual does not have (3-D cutter
/// compensation, cutting point command, G54.4, G68.4).
fn fanuc_only_in(src: &str) -> &'static str {
    const FANUC_ONLY: [&str; 13] = [
        "G41.2", "G41.3", "G41.4", "G41.5", "G41.6", "G42.2", "G42.4", "G42.5", "G42.6", "G43.8", "G43.9", "G54.4",
        "G68.4",
    ];
    if FANUC_ONLY.iter().any(|g| src.contains(g)) {
        "COR-070"
    } else {
        "ok"
    }
}

/// A machine with the given axes (linear X Y Z U V W, rotary A B C), in this order.
fn custom(axes: &str, dialect: Dialect, src: &str) -> String {
    custom_with(axes, dialect, src, |_| {})
}

/// As [`custom`], with the interpreter's configuration changed by `f`.
fn custom_with(axes: &str, dialect: Dialect, src: &str, f: impl FnOnce(&mut Config)) -> String {
    outcome(custom_run(axes, dialect, src, f))
}

/// As [`custom_with`], the whole result.
fn custom_run(axes: &str, dialect: Dialect, src: &str, f: impl FnOnce(&mut Config)) -> fivex_engine::run::RunResult {
    let axes = axes
        .chars()
        .map(|name| {
            let kind = if "ABC".contains(name) { AxisKind::Rotary } else { AxisKind::Linear };
            Axis::new(name, kind, 10_000.0)
        })
        .collect();
    let mut cfg = Config::new(
        MachineConfig {
            name: "custom".into(),
            axes,
            rotary: vec![],
            tool_axis: [0.0, 0.0, 1.0],
            nose: [0.0; 3],
            holder: 0.0,
            sub_chains: Vec::new(),
            chains: Vec::new(),
            motion: Default::default(),
            five_axis: Default::default(),
            manual: Default::default(),
            cycles: Default::default(),
        },
        dialect,
    );
    cfg.max_blocks = 10_000;
    cfg.refuse_unbuilt = false;
    f(&mut cfg);
    let mut interp = Interpreter::new(parse_file(&ended(src)), cfg);
    for n in 1..=9 {
        interp.state.offsets.tool_mut(n).unwrap().h_geometry = 100.0;
    }
    run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
}

// ---------------------------------------------------------------------------------------------
// a forbidden block changes nothing
// ---------------------------------------------------------------------------------------------

#[test]
fn a_forbidden_block_changes_nothing() {
    let src = "G41.2 D1\nG55 G91 X10. F100\n";
    let mut interp = interpreter_with(src, HEAD, Dialect::Fanuc, |c| c.refuse_unbuilt = false);
    let mut out = Vec::new();
    interp.step(&mut out).unwrap();
    let alarm = interp.step(&mut out).unwrap_err();
    assert_eq!(alarm.code, "PS5460");
    assert_eq!((interp.state.modal(14), interp.state.modal(3)), (540, 900));
    assert_eq!(interp.state.position()[0], 0.0);
}

// ---------------------------------------------------------------------------------------------
// workpiece setting error compensation (FANUC only: Syntec has no G54.4 rules)
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// 5-axis cutter compensation (FANUC only: Syntec has only G41/G42)
// ---------------------------------------------------------------------------------------------

#[test]
fn g41_6_needs_two_rotary_axes() {
    assert_eq!(custom("XYZC", Dialect::Fanuc, "G42.6 D1"), "PS5460");
}

/// crc CRC-44, TV-30: a reset in any cutter compensation mode leaves group 07 in G40 (the other
/// modal codes stay, CLR = 0), and TCP, which stays on, no longer nests with it.
#[test]
fn reset_leaves_cutter_compensation_in_g40() {
    const BOTH: &[Dialect] = &[Dialect::Fanuc, Dialect::Syntec];
    // 5-axis cutter compensation (G41.2/G42.2) is FANUC-only: COR-070 in Syntec.
    const FANUC: &[Dialect] = &[Dialect::Fanuc];
    for (src, tcp, dialects) in [
        ("G42.2 D1 X1.\nM00\n", 490, FANUC),
        ("G41 D1 X1.\nM00\n", 490, BOTH),
        ("G43.4 H1\nG41.2 D1 X1.\nM00\n", 434, FANUC),
        ("G41.2 D1\nG43.4 H1 X1.\nM00\n", 434, FANUC),
    ] {
        for &dialect in dialects {
            // Cutter compensation is not built (refused); the reset rule is tested with it allowed.
            let mut interp = interpreter_with(src, HEAD, dialect, |c| c.refuse_unbuilt = false);
            run(&mut interp, &RunOptions::default(), |_| {});
            assert_ne!(interp.state.modal(7), 400, "{src}: compensation is on before the reset");
            interp.reset();
            assert_eq!((interp.state.modal(7), interp.state.modal(8)), (400, tcp), "{src} {dialect:?}");
            // After the reset TCP ends by itself (no G40 is due first).
            interp.load(parse_file("G49\nM30\n"));
            let r = run(&mut interp, &RunOptions::default(), |_| {});
            assert!(r.completed(), "{src} {dialect:?}: {:?}", r.alarms);
        }
    }
}

#[test]
fn g_codes_forbidden_in_5_axis_compensation() {
    // crc §6.1, CRC-47, TV-34, NRB-04 (alarm number not stated: PS5460, decision)
    let bad = [
        "G28 Z0",
        "G53 X0",
        "G55",
        "G54.1 P1",
        "G92 X0",
        "G52 X0",
        "G81 X0 Y0 Z-1. R1. F100",
        "G80",
        "G41 D1",
        "G39",
        "G68 X0 Y0 R10.",
        "G69",
        "G95",
        "G97",
        "G16",
        "G51.1 X0",
        "G06.2 P4 X1. F100",
    ];
    for b in bad {
        let src = format!("G41.2 D1\n{b}");
        assert_eq!(fanuc(HEAD, &src), "PS5460", "{b}");
        assert_eq!(syntec(HEAD, &format!("{src}\nG40")), fanuc_only_in(&format!("{src}\nG40")), "{b}");
    }
    // 3-axis machines have no 5-axis modes (decision); the cancel block is out of the mode.
    assert_eq!(fanuc(MILL, "G41.2 D1\nG28 Z0\nG40"), "ok");
}

// ---------------------------------------------------------------------------------------------
// tool centre point control
// ---------------------------------------------------------------------------------------------

#[test]
fn g43_5_needs_two_rotary_axes() {
    assert_eq!(custom("XYZC", Dialect::Fanuc, "G43.5 H1"), "PS5459");
}

#[test]
fn stcp_moves_only_the_rtcp_axes() {
    // syn SYN-09, TV-25 (Syntec only)
    let src = "G43.4 H1 L1\nG01 U10. F100";
    assert_eq!(custom("XYZBCU", Dialect::Syntec, src), "COR-107");
    assert_eq!(custom("XYZBCU", Dialect::Fanuc, src), "ok");
    assert_eq!(custom("XYZBCU", Dialect::Syntec, "G43.4 H1\nG01 U10. F100"), "ok");
    assert_eq!(custom("XYZBCU", Dialect::Syntec, "G43.4 H1 L1\nG43.4 H1 L0\nG01 U10. F100"), "ok");
    // TV-25b/c/d: Pr3051 = 1 turns STCP on without L; L0 still turns it off.
    let pr3051 = |c: &mut Config| c.edit_machine(|m| m.five_axis.smooth_tcp = true);
    assert_eq!(custom_with("XYZBCU", Dialect::Syntec, "G43.4 H1\nG01 U10. F100", pr3051), "COR-107");
    assert_eq!(custom_with("XYZBCU", Dialect::Syntec, "G43.4 H1 L0\nG01 U10. F100", pr3051), "ok");
}

#[test]
fn at_most_two_other_axes_in_tcp() {
    // tcp TCP-05, TV-57 (FANUC only)
    let src = "G43.4 H1\nG01 U1. V1. W1. F100";
    assert_eq!(custom("XYZBCUVW", Dialect::Fanuc, src), "PS5421");
    assert_eq!(custom("XYZBCUVW", Dialect::Syntec, src), "ok");
    assert_eq!(custom("XYZBCUVW", Dialect::Fanuc, "G43.4 H1\nG01 U1. V1. F100"), "ok");
}

#[test]
fn five_axes_per_block_on_the_31i_a5() {
    // tcp TCP-05, Q-20 (alarm not named: PS5421, decision; the FANUC 31i-A5 only, a control
    // model setting `Config::five_axes_per_block`, off for the 30i-A5)
    let i31 = |c: &mut Config| c.five_axes_per_block = true;
    let six = "G43.4 H1\nG01 X1. Y1. Z1. B1. C1. U1. F100\nG49";
    assert_eq!(custom_with("XYZBCU", Dialect::Fanuc, six, i31), "PS5421");
    let r = custom_run("XYZBCU", Dialect::Fanuc, six, i31);
    assert_eq!((r.alarms[0].message.as_str(), r.alarms[0].line), ("ILLEGAL COMMAND IN G43.4/G43.5", 2));
    assert_eq!(custom("XYZBCU", Dialect::Fanuc, six), "ok", "the 30i-A5 has no such limit");
    assert_eq!(custom_with("XYZBCU", Dialect::Syntec, six, i31), "ok", "a FANUC rule");
    let five = "G43.4 H1\nG01 X1. Y1. Z1. B1. C1. F100\nG01 X2. Y2. U1. V1. F100\nG49";
    assert_eq!(custom_with("XYZBCUV", Dialect::Fanuc, five, i31), "ok");
    // Type 2: I/J/K are not axes; the start block counts too; outside TCP six axes are fine.
    let type2 = "G43.5 H1\nG01 X1. Y1. Z1. U1. V1. I0 J0 K1. F100\nG49";
    assert_eq!(custom_with("XYZBCUV", Dialect::Fanuc, type2, i31), "ok");
    let start = "G43.4 H1 X1. Y1. Z1. B1. C1. U1.\nG49";
    assert_eq!(custom_with("XYZBCU", Dialect::Fanuc, start, i31), "PS5421");
    assert_eq!(custom_with("XYZBCU", Dialect::Fanuc, "G01 X1. Y1. Z1. B1. C1. U1. F100", i31), "ok");
}

#[test]
fn type_2_arcs_are_given_by_r() {
    // tcp TCP-10, M-4 (alarm not named: PS5421, decision). Syntec says nothing of arcs under
    // G43.5; its I/J/K are the tool vector there too, so the circle needs R (COR-100).
    // tcp TCP-10/11, Q-20: no full circle in type 2 (start = end in the plane; alarm not named:
    // PS5421, decision), also as a helix; type 1 may (its centre by I/J/K).
    let full = "G43.5 H1\nG00 X10. Y0 Z0\nG02 X10. Y0 R10. F100\nG01\nG49";
    assert_eq!(fanuc(HEAD, &full.replace("Y0 R10.", "Y0 Z5. R10.")), "PS5421");
    // tcp TCP-16: G04 is allowed in TCP; its X is the dwell time, not an arc end point, so a
    // dwell right after a type 2 arc (G02 still modal) needs no R, nor does G10 / G51 data.
    let after_arc = "G43.5 H1\nG02 X10. Y10. R10. F100\n{}\nG01 X0\nG49";
    assert_eq!(fanuc(HEAD, &after_arc.replace("{}", "G04 X0.5")), "ok");
    assert_eq!(fanuc(HEAD, &after_arc.replace("{}", "G51 X0 Y0 Z0 P2")), "ok");
    assert_eq!(syntec(HEAD, &after_arc.replace("{}", "G04 X0.5")), "ok");
}

// ---------------------------------------------------------------------------------------------
// tilted working plane and tool alignment
// ---------------------------------------------------------------------------------------------

#[test]
fn g68_2_p2_and_p3_blocks_are_consecutive() {
    // twp TWP-03/04, TV-TWP-11d (the interrupting block alarms: decision)
    let q1 = "G68.2 P2 Q1 X0 Y0 Z0";
    let q2 = "G68.2 P2 Q2 X10. Y0 Z0";
    let q3 = "G68.2 P2 Q3 X0 Y10. Z10.";
    for bad in
        [format!("{q1}\nG01 X10. F100\n{q2}"), q2.to_string(), format!("{q1}\n{q3}"), format!("{q1}\n{q2}\n{q2}")]
    {
        assert_eq!(fanuc(MILL, &bad), "PS5457", "{bad}");
        // Syntec's G68.2 has no P (syn SYN-18): COR-002 at the first block.
        assert_eq!(syntec(MILL, &format!("{bad}\nG69")), "COR-002", "{bad}");
    }
    assert_eq!(fanuc(MILL, "G68.2 P3 Q2 I0 J0 K1."), "PS5457");
}

#[test]
fn g_codes_allowed_in_the_tilted_plane() {
    // twp TWP-12, §6.2, TV-TWP-23/25 (MTW = 0; FANUC only)
    let bad = [
        "G92 X0",
        "G52 X0",
        "G54.1 P1",
        "G55",
        "G68 X0 Y0 R10.",
        "G05.1 Q1",
        "G43.4 H1",
        "G61",
        "G20",
        "G51 P2",
        "G68.2 X1. Y0 Z0 I0 J0 K0",
        "G68.4 X1. Y0 Z0 I0 J0 K0",
        "G68.3",
        "G54.4 P1",
    ];
    for b in bad {
        let src = format!("G68.2 X0 Y0 Z0 I0 J0 K0\n{b}");
        assert_eq!(fanuc(HEAD, &src), "PS5462", "{b}");
        if !b.starts_with("G43.4") && !b.starts_with("G68.3") {
            assert_eq!(syntec(HEAD, &format!("{src}\nG50\nG69")), fanuc_only_in(&format!("{src}\nG50\nG69")), "{b}");
        }
    }
    let legal = "G68.2 X0 Y0 Z0 I0 J0 K0\nG43 H1\nG49\nG81 X0 Y0 Z-1. R1. F100\nG80\nG18\nG17\nG53 X0\nG28 Z0\nG69";
    assert_eq!(fanuc(HEAD, legal), "ok");
}

#[test]
fn modal_states_the_tilted_plane_starts_in() {
    // twp TWP-11/16, §6.1, TV-TWP-20/22 (FANUC only; G54.4 may be on: OQ-21)
    for bad in ["G41 D1", "G51 P2", "G51.1 X0", "G54.1 P1", "G16", "G81 X0 Y0 Z-1. R1. F100"] {
        let src = format!("{bad}\nG68.2 X0 Y0 Z0 I0 J0 K0");
        assert_eq!(fanuc(MILL, &src), "PS5462", "{bad}");
        // A canned cycle must not span the plane in Syntec either (docs/five-axis.md, decision).
        let syntec_ok = if bad.starts_with("G81") { "COR-100" } else { "ok" };
        assert_eq!(syntec(MILL, &format!("{src}\nG69")), syntec_ok, "{bad}");
    }
}

#[test]
fn a_tool_alignment_needs_the_tilted_plane() {
    // syn §4.2.3/§4.3.3/§4.4.3 #1 "can't be executed before G68.2" (no alarm named: COR-100,
    // decision); FANUC TWP-07 aligns "after G68.2" (no alarm named: PS5462, decision). Each of
    // these blocks did nothing at all before (G53.3 not even its move and tool length).
    for block in ["G53.1", "G53.1 P1", "G53.3 X0 Y0 Z0 H1", "G53.6 H1"] {
        let src = format!("G01 X0 Y0 Z100. F1000\n{block}\nG01 X10.");
        assert_eq!(syntec(HEAD, &src), "COR-100", "{block}");
        // After G69 the plane is over: the same.
        assert_eq!(syntec(HEAD, &format!("G68.2 X0 Y0 Z0 I0 J30. K0\nG69\n{block}")), "COR-100", "{block}");
        assert_eq!(syntec(HEAD, &format!("G68.2 X0 Y0 Z0 I0 J30. K0\n{block}\nG49\nG69")), "ok", "{block}");
    }
    assert_eq!(fanuc(HEAD, "G01 X0 Y0 Z100. F1000\nG53.1\nG01 X10."), "PS5462");
    assert_eq!(fanuc(HEAD, "G53.6 H1"), "PS5462");
    assert_eq!(fanuc(HEAD, "G68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG69"), "ok");
    // The plane defined in the same block is there when the alignment runs.
    assert_eq!(syntec(HEAD, "G68.2 X0 Y0 Z0 I0 J30. K0 G53.1\nG69"), "ok");
}

#[test]
fn syntec_g68_2_takes_no_fanuc_form() {
    // syn SYN-18, §4.1.3: `G68.2 X_ Y_ Z_ I_ J_ K_` (Euler angles) only; FANUC's P1…P4 forms
    // ran as Euler angles before (a three-point program got another plane). COR-002.
    for block in [
        "G68.2 P2 Q1 X10. Y0 Z0",
        "G68.2 P1 X10. Y20. Z30. I10. J20. K30.",
        "G68.2 P0 X0 Y0 Z0 I0 J30. K0",
        "G68.2 X0 Y0 Z0 I0 J30. K0 Q123",
        "G68.2 X0 Y0 Z0 I0 J30. K0 R5.",
    ] {
        assert_eq!(syntec(HEAD, &format!("{block}\nG69")), "COR-002", "{block}");
    }
    assert_eq!(fanuc(HEAD, "G68.2 P1 X10. Y20. Z30. I10. J20. K30.\nG69"), "ok");
    assert_eq!(syntec(HEAD, "G68.2 X10. Y20. Z30. I10. J20. K30.\nG69"), "ok");
}

#[test]
fn syntec_g43_4_and_g43_5_take_no_posture_p_and_l_is_0_or_1() {
    // syn §2.2.1, §3.1.1: `G43.4 H_ [L_]` with L1 (STCP on) or L0 (off); §2.3.1 `G43.5 H_`. P
    // turned FANUC's tool posture control on (or off against Pr3054 = 1) before; L2, L-1 and
    // L0.5 ran as L0. COR-002.
    for block in ["G43.4 H1 P1", "G43.4 H1 P0", "G43.5 H1 P1", "G43.4 H1 L2", "G43.4 H1 L-1", "G43.4 H1 L0.5"] {
        assert_eq!(syntec(HEAD, &format!("{block}\nG01 X10. F1000\nG49")), "COR-002", "{block}");
    }
    for block in ["G43.4 H1", "G43.4 H1 L1", "G43.4 H1 L1.", "G43.4 H1 L0", "G43.5 H1"] {
        assert_eq!(syntec(HEAD, &format!("{block}\nG01 X10. F1000\nG49")), "ok", "{block}");
    }
    assert_eq!(fanuc(HEAD, "G43.4 H1 P1\nG01 X10. F1000\nG49"), "ok");
    // A P another code of the block takes is that code's (G05 P0, M98 P).
    assert_eq!(syntec(HEAD, "G05 P10000\nG05 P0 G43.4 H1\nG49"), "ok");
}

#[test]
fn a_tool_alignment_block_takes_no_rotary_word() {
    // twp TWP-07 (`G53.1 ;`), syn §4.2.1 (`G53.1 [P_]`): the alignment turns the rotary axes
    // itself; `G53.1 B10.` took C from the alignment and B from the word (decision: PS0009 /
    // COR-002, the dialects' illegal address).
    let plane = "G68.2 X0 Y0 Z0 I0 J30. K0";
    assert_eq!(fanuc(HEAD, &format!("{plane}\nG53.1 B10.\nG69")), "PS0009");
    assert_eq!(syntec(HEAD, &format!("{plane}\nG53.1 C10.\nG69")), "COR-002");
    assert_eq!(syntec(HEAD, &format!("{plane}\nG53.6 H1 B10.\nG49\nG69")), "COR-002");
}

#[test]
fn no_tilted_plane_while_g68_rotation_is_on() {
    // twp TWP-11, §1.3.1: G68 is not among the modal states the plane may start in (PS5462);
    // the rotation was dropped silently before. Syntec: not composed either (decision, COR-100).
    let src = "G00 X0 Y0 Z100.\nG68 X0 Y0 R30.\nG68.2 X10. Y20. Z5. I0 J0 K0\nG01 X10. Y0 Z0 F1000\nG69";
    assert_eq!(fanuc(HEAD, src), "PS5462");
    assert_eq!(syntec(HEAD, src), "COR-100");
    assert_eq!(fanuc(HEAD, "G68 X0 Y0 R30.\nG69\nG68.2 X10. Y20. Z5. I0 J0 K0\nG69"), "ok");
    assert_eq!(fanuc(HEAD, "G68 X0 Y0 R30.\nG68.3\nG69"), "PS5462");
}

#[test]
fn length_compensation_and_mirror_image_end_before_g69() {
    // twp TWP-16, §1.4 "Relationships with other modal commands": G43/G49 and G51.1/G50.1 nest
    // inside G68.2 … G69 (no alarm named: PS5462, as for the cycle). G49 in the G69 block itself
    // is refused too (decision: fivex would end the plane first). FANUC only: Syntec's manual
    // ends its program with `G69 G49` (§4.6.5).
    let plane = "G00 X0 Y0 Z100.\nG68.2 X10. Y20. Z5. I0 J30. K0\nG53.1";
    for (end, want) in [
        ("G43 H1\nG00 X0 Y0 Z50.\nG69", "PS5462"),
        ("G44 H1\nG69", "PS5462"),
        ("G43 H1\nG49 G69", "PS5462"),
        ("G69 G43 H1", "PS5462"),
        ("G51.1 X0\nG69", "PS5462"),
        ("G51.1 X0 G69", "PS5462"),
        ("G43 H1\nG49\nG69", "ok"),
        ("G51.1 X0\nG50.1 X0\nG69", "ok"),
        ("G51.1 X0\nG50.1 X0 G69", "ok"),
    ] {
        assert_eq!(fanuc(HEAD, &format!("{plane}\n{end}\nG49\nG50.1 X0")), want, "{end}");
    }
    assert_eq!(syntec(HEAD, &format!("{plane}\nG43 H1\nG69 G49")), "ok");
}

#[test]
fn the_tilted_plane_needs_linear_rapids() {
    // twp TWP-14, TV-TWP-27, OQ-17: LRP (No.1401#1) = 1 required, no alarm named: PS5462 at the
    // plane's start (the extract's proposal); G43.4 there is PS5420. FANUC only.
    let lrp0 = |dialect| {
        outcome({
            let mut interp = interpreter_with("G68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG00 X10.\nG69", HEAD, dialect, |c| {
                c.refuse_unbuilt = false;
                c.edit_machine(|m| m.motion.nonlinear_rapid = true);
            });
            run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
        })
    };
    assert_eq!(lrp0(Dialect::Fanuc), "PS5462");
    assert_eq!(lrp0(Dialect::Syntec), "ok");
    assert_eq!(fanuc(HEAD, "G68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG00 X10.\nG69"), "ok");
}

#[test]
fn fivex_check_reports_the_syntec_addresses_literal_words_decide() {
    // The rows of `syntec_g68_2_takes_no_fanuc_form` and of the G43.4/G43.5 P and L, at the word;
    // a value given by an expression is left to the run.
    let diag = |text: &str, dialect: Dialect| {
        fivex_engine::check::check(parse_file(&format!("{text}\nM30\n")), dialect)
            .iter()
            .map(|d| (d.col, dialect.describe(&d.id).0))
            .collect::<Vec<_>>()
    };
    let at = |cols: &[u32]| cols.iter().map(|&c| (c, "COR-002".to_string())).collect::<Vec<_>>();
    assert_eq!(diag("G68.2 P2 Q1 X10. Y0 Z0", Dialect::Syntec), at(&[7, 10]));
    assert_eq!(diag("G68.2 X0 Y0 Z0 I0 J30. K0 R5.", Dialect::Syntec), at(&[27]));
    assert_eq!(diag("G43.4 H1 P1", Dialect::Syntec), at(&[10]));
    assert_eq!(diag("G43.5 H1 P0", Dialect::Syntec), at(&[10]));
    assert_eq!(diag("G43.4 H1 L2", Dialect::Syntec), at(&[10]));
    for fine in ["G43.4 H1 L1", "G43.4 H1 L0", "G43.4 H1 L#1", "G05 P0 G43.4 H1", "G68.2 X0 Y0 Z0 I0 J30. K0"] {
        assert_eq!(diag(fine, Dialect::Syntec), vec![], "{fine}");
    }
    assert_eq!(diag("G43.4 H1 P1", Dialect::Fanuc), vec![]);
    assert_eq!(diag("G68.2 P2 Q1 X10. Y0 Z0", Dialect::Fanuc), vec![]);
}
