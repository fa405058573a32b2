//! Custom macro B as the FANUC manual fixes it (`docs/references.md`): one or more tests per
//! rule, explicit expected values, every alarm the manual names in both dialects.
//!
//! Sections follow the spec: blocks and words, variables, vacant rules, expressions, control
//! flow, calls, system variables. Where the spec is silent and the implementation decides, the
//! test says "decision" and pins it.

use crate::common;
use common::*;

use fivex_engine::alarm::Alarm;
use fivex_engine::canon::{Canon, CanonKind, Motion, MotionKind, SpindleState};
use fivex_engine::interp::expr::Variables;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::run::{run, RunOptions, RunResult};
use fivex_engine::workpiece::{Cuboid, Workpiece};
use fivex_engine::Dialect;

// ---------------------------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------------------------

/// An interpreter on `preset`/`dialect` with `tweak` applied to its configuration (tool offsets
/// 1–99: length 100, radius 5, as in `common::interpreter`).
fn interp_cfg(src: &str, preset: &str, dialect: Dialect, tweak: impl FnOnce(&mut Config)) -> Interpreter {
    interpreter_with(src, preset, dialect, tweak)
}

fn run_interp(interp: &mut Interpreter) -> RunResult {
    run(interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
}

/// Run on mill3/FANUC with a configuration tweak; the full result.
fn run_cfg(src: &str, tweak: impl FnOnce(&mut Config)) -> RunResult {
    run_interp(&mut interp_cfg(src, "mill3", Dialect::Fanuc, tweak))
}

/// Common variable `n` after a run with a configuration tweak.
fn var_cfg(src: &str, n: u32, tweak: impl FnOnce(&mut Config)) -> Option<f64> {
    let r = run_cfg(src, tweak);
    assert!(r.completed(), "unexpected alarm {:?} in\n{src}", r.alarms);
    r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
}

/// Common variable `n`, which must be set.
fn val(src: &str, n: u32) -> f64 {
    var(src, n).unwrap_or_else(|| panic!("#{n} is vacant after\n{src}"))
}

/// All canonical commands of a program on `preset` with a configuration tweak.
fn canon_cfg(src: &str, preset: &str, tweak: impl FnOnce(&mut Config)) -> Vec<Canon> {
    let mut interp = interp_cfg(src, preset, Dialect::Fanuc, tweak);
    let mut v = Vec::new();
    interp.run(|c| v.push(c)).expect("no alarm");
    v
}

fn motions_cfg(src: &str, preset: &str, tweak: impl FnOnce(&mut Config)) -> Vec<Motion> {
    canon_cfg(src, preset, tweak)
        .into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Motion(m) => Some(m),
            _ => None,
        })
        .collect()
}

/// The first alarm of a run in `dialect` (panics if it completes).
fn alarm_full(src: &str, dialect: Dialect) -> Alarm {
    let r = run_with(src, "mill3", dialect);
    assert!(!r.completed(), "expected an alarm from\n{src}");
    r.alarms[0].clone()
}

/// The program alarms with `fanuc` in the FANUC dialect and `syntec` in the Syntec dialect.
#[track_caller]
fn alarms(src: &str, fanuc: &str, syntec: &str) {
    assert_eq!(alarm_with(src, Dialect::Fanuc), fanuc, "FANUC alarm of\n{src}");
    assert_eq!(alarm_with(src, Dialect::Syntec), syntec, "Syntec alarm of\n{src}");
}

/// Value of an expression (assigned to #100).
fn ev(expr: &str) -> f64 {
    val(&format!("#100={expr}\nM30\n"), 100)
}

/// Value of an expression with parameter NAT set to `nat`.
fn ev_nat(expr: &str, nat: bool) -> f64 {
    var_cfg(&format!("#100={expr}\nM30\n"), 100, |c| c.nat = nat).expect("#100 set")
}

#[track_caller]
fn close(actual: f64, expected: f64) {
    assert!((actual - expected).abs() < 1e-9, "got {actual}, expected {expected}");
}

// ---------------------------------------------------------------------------------------------
// Blocks and words
// ---------------------------------------------------------------------------------------------

#[test]
fn block_delete_switch() {
    let src = "/#100=1\n#101=2\n/G90 G00 X5.\nM30\n";
    // Switch off: the `/` blocks run.
    let off = run_cfg(src, |c| c.block_delete = false);
    assert_eq!(off.variables, vec![(100, 1.0), (101, 2.0)]);
    assert_eq!(off.workpiece[0], 5.0);
    // Switch on: they are skipped.
    let on = run_cfg(src, |c| c.block_delete = true);
    assert_eq!(on.variables, vec![(101, 2.0)]);
    assert_eq!(on.workpiece[0], 0.0);
    // `/1` is the same switch; `/2`…`/9` are the additional optional block skip switches 2–9,
    // off in fivex: their blocks run with switch 1 on (they were skipped with it).
    let src = "G90 G00 X0 Y0 Z0\n/1 #100=1\n/2 #101=2\n/9 G00 Z-7.\nM30\n";
    let on = run_cfg(src, |c| c.block_delete = true);
    assert_eq!(on.variables, vec![(101, 2.0)]);
    assert_eq!(on.workpiece[2], -7.0);
}

#[test]
fn word_values_number_variable_indirect_negated_expression() {
    let src = "#1=10.\n#2=2\n#3=3\nG90 G01 F100 X#1 Y#[#2+1] Z-#1\nX[#1*2] Y-[#2+1] Z#3\nM30\n";
    let m = motions(src);
    // X#1 = 10 mm (a variable's value is a real value, not increments), Y#[#2+1] = #3 = 3,
    // Z-#1 = -10.
    assert_eq!(&m[0].target[..3], &[10.0, 3.0, -10.0]);
    assert_eq!(&m[1].target[..3], &[20.0, -3.0, 3.0]);
    assert_eq!(m[0].feed, 100.0);
}

#[test]
fn same_group_g_codes_last_one_wins() {
    // Group 01: G00 then G01 → G01 (a feed move).
    let src = "G00 G01 X1. F100\n#100=#4001\nG01 G00 X2.\n#101=#4001\nM30\n";
    let m = motions(src);
    assert_eq!(m[0].kind, MotionKind::Linear);
    assert_eq!(m[1].kind, MotionKind::Rapid);
    // Group 03: G90 then G91 → incremental.
}

#[test]
fn rotary_axis_without_point_is_thousandths_of_a_degree() {
    let m = motions_cfg("G90 G00 B10\nB10.\nC-90000\nM30\n", "head-bc", |_| {});
    let (b, c) = (3, 4);
    assert_eq!(m[0].target[b], 0.01);
    assert_eq!(m[1].target[b], 10.0);
    assert_eq!(m[2].target[c], -90.0);
}

#[test]
fn feed_without_point_is_not_scaled() {
    let m = motions("G90 G01 X1. F100\nX2. F250.\nM30\n");
    assert_eq!(m[0].feed, 100.0);
    assert_eq!(m[1].feed, 250.0);
}

#[test]
fn pocket_calculator_input() {
    let src = "G90 G00 X10\nY2.5\nM30\n";
    let m = motions_cfg(src, "mill3", |c| c.pocket_calculator = true);
    assert_eq!(m[0].target[0], 10.0);
    assert_eq!(m[1].target[1], 2.5);
    let m = motions_cfg("G90 G00 B10\nM30\n", "head-bc", |c| c.pocket_calculator = true);
    assert_eq!(m[0].target[3], 10.0);
    // F is not affected either way.
    let m = motions_cfg("G01 X1 F100\nM30\n", "mill3", |c| c.pocket_calculator = true);
    assert_eq!((m[0].target[0], m[0].feed), (1.0, 100.0));
}

#[test]
fn arc_center_words_without_point_are_increments() {
    // I5000 = 5 mm: a half circle of radius 5 from X0 to X10.
    let m = motions("G90 G17 G02 X10. Y0 I5000 J0 F100\nM30\n");
    let arc = m[0].arc.as_deref().expect("an arc");
    assert_eq!(arc.radius, 5.0);
    assert_eq!((arc.center[0], arc.center[1]), (5.0, 0.0));
}

#[test]
fn dwell_x_without_point_is_milliseconds() {
    // G04 X2 = 0.002 s, G04 X2. = 2 s, G04 P2 = 0.002 s.
    let dwells: Vec<f64> = canon("G04 X2\nG04 X2.\nG04 P2\nM30\n")
        .into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Dwell { seconds } => Some(seconds),
            _ => None,
        })
        .collect();
    assert_eq!(dwells, vec![0.002, 2.0, 0.002]);
}

// ---------------------------------------------------------------------------------------------
// Variables
// ---------------------------------------------------------------------------------------------

#[test]
fn persistent_variables_survive_a_new_run() {
    let mut first = interp_cfg("#500=12.5\n#999=-1.\n#100=3.\nM30\n", "mill3", Dialect::Fanuc, |_| {});
    assert!(run_interp(&mut first).completed());
    let saved = *first.state.persistent();
    assert_eq!(saved[0], Some(12.5));
    assert_eq!(saved[499], Some(-1.0));
    assert_eq!(saved[1], None);

    let src = "#101=#500+1\n#102=#999\n#103=#100\n#104=#501\nM30\n";
    let mut second = interp_cfg(src, "mill3", Dialect::Fanuc, |_| {});
    second.state.load_persistent(&saved);
    let r = run_interp(&mut second);
    assert!(r.completed());
    let get = |n| r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v);
    assert_eq!(get(101), Some(13.5));
    assert_eq!(get(102), Some(-1.0));
    // #100 is not retained: a new controller starts with it vacant.
    assert_eq!(get(103), None);
    assert_eq!(get(104), None);
    assert_eq!(get(500), Some(12.5));
}

#[test]
fn undefined_variable_numbers_ps0115() {
    for src in [
        "#100=#34\nM30\n",
        "#100=#200\nM30\n",
        "#34=1\nM30\n",
        "#200=1\nM30\n",
        "#100=#499\nM30\n",
        "#1036=1\nM30\n",
        "#1136=1\nM30\n",
    ] {
        alarms(src, "PS0115", "COR-016");
    }
    // The bounds themselves exist.
    assert_eq!(var("#33=1\n#199=#33\n#500=#199\n#999=#500\nM30\n", 999), Some(1.0));
}

// ---------------------------------------------------------------------------------------------
// Vacant (null) rules
// ---------------------------------------------------------------------------------------------

#[test]
fn vacant_in_an_address_omits_the_word() {
    // `G90 X#1` with #1 vacant moves no X: alone it is no motion at all…
    // …and with another axis only that axis moves.
    let m = motions("G90 G00 X5. Y5.\nG90 X#1 Y7.\nM30\n");
    assert_eq!(&m[1].target[..3], &[5.0, 7.0, 0.0]);
    // Not the same as X0.
}

// ---------------------------------------------------------------------------------------------
// Expressions
// ---------------------------------------------------------------------------------------------

#[test]
fn atan_two_argument_forms_quadrants_nat0() {
    for (a, b, deg) in [
        (1.0, 1.0, 45.0),
        (1.0, -1.0, 135.0),
        (-1.0, -1.0, 225.0),
        (-1.0, 1.0, 315.0),
        (0.0, 1.0, 0.0),
        (1.0, 0.0, 90.0),
        (0.0, -1.0, 180.0),
        (-1.0, 0.0, 270.0),
    ] {
        close(ev_nat(&format!("ATAN[{a}]/[{b}]"), false), deg);
        close(ev_nat(&format!("ATAN[{a},{b}]"), false), deg);
    }
    close(ev("ATAN[1]/[SQRT[3]]"), 30.0);
}

#[test]
fn atan_two_argument_forms_quadrants_nat1() {
    for (a, b, deg) in [
        (1.0, 1.0, 45.0),
        (1.0, -1.0, 135.0),
        (-1.0, -1.0, -135.0),
        (-1.0, 1.0, -45.0),
        (0.0, 1.0, 0.0),
        (1.0, 0.0, 90.0),
        (0.0, -1.0, 180.0),
        (-1.0, 0.0, -90.0),
    ] {
        close(ev_nat(&format!("ATAN[{a}]/[{b}]"), true), deg);
        close(ev_nat(&format!("ATAN[{a},{b}]"), true), deg);
    }
    // (-180, 180]: the negative x axis with a -0 y is +180, never -180.
    close(ev_nat("ATAN[-0]/[-1]", true), 180.0);
}

#[test]
fn sqrt_abs_ln_exp() {
    close(ev("EXP[1]"), std::f64::consts::E);
}

#[test]
fn pow() {
    close(ev("POW[2,0.5]"), std::f64::consts::SQRT_2);
}

// ---------------------------------------------------------------------------------------------
// Control flow
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// Calls
// ---------------------------------------------------------------------------------------------

#[test]
fn m99_in_main_restarts_it() {
    // Without an exit it runs until the block budget stops it.
    let r = run_cfg("#100=#100+1\nM99\n", |c| c.max_blocks = 50);
    assert_eq!(r.alarms.len(), 1);
    assert_eq!(r.alarms[0].code, "FX0001");
    assert_eq!(r.variables, vec![(100, 25.0)]);
}

const DUMP_26: &str = "\
O9000
#101=#1
#102=#2
#103=#3
#104=#4
#105=#5
#106=#6
#107=#7
#108=#8
#109=#9
#110=#10
#111=#11
#112=#12
#113=#13
#114=#14
#115=#15
#116=#16
#117=#17
#118=#18
#119=#19
#120=#20
#121=#21
#122=#22
#123=#23
#124=#24
#125=#25
#126=#26
M99
";

#[test]
fn g65_argument_specification_1() {
    let src = format!(
        "G65 P9000 A1. B2. C3. I4. J5. K6. D7. E8. F9. H11. M13. Q17. R18. S19. T20. U21. V22. W23. X24. Y25. Z26.\nM30\n{DUMP_26}"
    );
    let r = run_src(&src);
    assert!(r.completed(), "{:?}", r.alarms);
    let expected: Vec<(u32, f64)> = [1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26]
        .iter()
        .map(|&k| (100 + k, k as f64))
        .collect();
    assert_eq!(r.variables, expected);
    // #10 #12 #14 #15 #16 (no letter: G L N O P) are vacant.
}

#[test]
fn g65_argument_specification_2() {
    // A B C, then ten I J K sets → #4 … #33.
    let mut words = String::from("G65 P9100 A1. B2. C3.");
    for set in 0..10 {
        for (k, letter) in ['I', 'J', 'K'].iter().enumerate() {
            words.push_str(&format!(" {letter}{}.", 4 + 3 * set + k));
        }
    }
    let src = format!("{words}\nM30\nO9100\n#1=1\nWHILE[#1LE33]DO1\n#[100+#1]=#[#1]\n#1=#1+1\nEND1\nM99\n");
    let r = run_src(&src);
    assert!(r.completed(), "{:?}", r.alarms);
    // #1 was overwritten by the loop counter: 1.
    let expected: Vec<(u32, f64)> = (1..=33).map(|k| (100 + k, k as f64)).collect();
    assert_eq!(r.variables, expected);
}

#[test]
fn g66_calls_after_every_move_only() {
    let src = "\
G66 P9300 A1.
G90 G00 X1.
#1=5.
M05
G04 P100
G00 X2.
G67
G00 X3.
M30
O9300
#100=#100+1
#101=#1
G91 G00 Z1.
G90
M99
";
    // The call comes after the move; the macro's own move does not call it again.
    let m = motions(src);
    let xz: Vec<(f64, f64)> = m.iter().map(|m| (m.target[0], m.target[2])).collect();
    assert_eq!(xz, vec![(1.0, 0.0), (1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (3.0, 2.0)]);
}

#[test]
fn g66_1_calls_every_block_with_its_words_as_arguments() {
    let src = "\
G66.1 P9400 A1.
X5.
A7. X2.
#103=1
G67
G90 G00 X9.
M30
O9400
#100=#100+1
#[110+#100]=#1
#[120+#100]=#24
M99
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
    // The called blocks do not move themselves: only the X9. after G67 moves.
}

#[test]
fn g66_opens_a_macro_level_too() {
    // Four G65 levels plus the G66 call = five: fine; five G65 levels plus G66 = six: alarm.
    // (#500…: the Syntec dialect refuses #100–#199 in a macro call, `syntec_macro.rs`.)
    let inner = "O9600\nG66 P9601\nG00 X1.\nG67\nM99\nO9601\n#502=1\nM99\n";
    let src = format!(
        "#501=4\nG65 P9500\nM30\nO9500\n#500=#500+1\nIF[#500GE#501]GOTO 9\nG65 P9500\nM99\nN9 M98 P9600\nM99\n{inner}"
    );
    assert_eq!(var(&src, 502), Some(1.0));
    let src = src.replacen("#501=4", "#501=5", 1);
    alarms(&src, "PS0077", "COR-031");
}

#[test]
fn nested_call_limit_counts_macro_and_subprogram_calls_together() {
    // Five G65 levels, then M98 subprograms: 15 calls in all are fine, 16 are not.
    // (#500…: the Syntec dialect refuses #100–#199 in a macro call, `syntec_macro.rs`.)
    let macros = "O9500\n#500=#500+1\nIF[#500GE5]GOTO 9\nG65 P9500\nM99\nN9 M98 P100\nM99\n";
    let subs = "O0100\n#503=#503+1\nIF[#503GE#501]GOTO 9\nM98 P100\nN9 M99\n";
    let ok = format!("#501=10\nG65 P9500\n#502=1\nM30\n{macros}{subs}");
    let too_deep = ok.replacen("#501=10", "#501=11", 1);
    alarms(&too_deep, "PS0077", "COR-031");
}

// ---------------------------------------------------------------------------------------------
// System variables
// ---------------------------------------------------------------------------------------------

#[test]
fn macro_alarm_3000_fanuc() {
    let src = "#100=1\nN20 #3000=12 (TOOL BROKEN)\n#101=1\nM30\n";
    let a = alarm_full(src, Dialect::Fanuc);
    assert_eq!(a.message, "TOOL BROKEN");
    assert_eq!(a.n, Some(20));
}

/// Syntec raises a program's alarm with ALARM(…) and #3000 is one of its modal variables (the
/// Syntec MACRO syntax handbook, §2.6): refused there, not MAR-012 (`docs/dialects.md`).
#[test]
fn macro_alarm_3000_is_refused_in_syntec() {
    let src = "#100=1\nN20 #3000=12 (TOOL BROKEN)\n#101=1\nM30\n";
    let a = alarm_full(src, Dialect::Syntec);
    assert_eq!((a.code.as_str(), a.line), ("COR-016", 2));
    assert_eq!(run_with(src, "mill3", Dialect::Syntec).variables, vec![(100, 1.0)]);
}

#[test]
fn macro_alarm_number_from_an_expression_in_a_subprogram() {
    let src = "#1=7\nM98 P20\nM30\nO0020\n#3000=#1*10+1 (BAD PART)\nM99\n";
    let a = alarm_full(src, Dialect::Fanuc);
    assert_eq!((a.code.as_str(), a.message.as_str(), a.line), ("MC3071", "BAD PART", 5));
    assert_eq!(alarm_full(src, Dialect::Syntec).code, "COR-016");
    // Without a comment the message is empty.
    assert_eq!(alarm_full("#3000=1\nM30\n", Dialect::Fanuc).message, "");
}

/// Decision (`docs/dialects.md`, "Macro alarms"): n is rounded and must be 0–999; out of that
/// range or vacant the block is PS0115 (as an interface signal written out of its range), never
/// a clamped alarm number (the audit's -1 gave MC3000, 1000 and 4096 both MC3999).
#[test]
fn macro_alarm_numbers_out_of_range_are_refused_not_clamped() {
    for n in ["-1", "1000", "4096", "#0", "999.5"] {
        let src = format!("#100=1\n#3000={n} (MSG)\nM30\n");
        alarms(&src, "PS0115", "COR-016");
        assert_eq!(alarm_with(&src, Dialect::Haas), "503", "Haas, #3000={n}");
        assert_eq!(alarm_full(&src, Dialect::Fanuc).line, 2, "#3000={n}");
    }
    // The ends of the range, and a value rounded into it (half away from zero).
    for (n, fanuc, syntec, haas) in [
        ("0", "MC3000", "COR-016", "1000"),
        ("999", "MC3999", "COR-016", "1999"),
        ("-0.4", "MC3000", "COR-016", "1000"),
        ("12.5", "MC3013", "COR-016", "1013"),
    ] {
        let src = format!("#3000={n} (MSG)\nM30\n");
        alarms(&src, fanuc, syntec);
        assert_eq!(alarm_with(&src, Dialect::Haas), haas, "Haas, #3000={n}");
    }
}

#[test]
fn stop_with_message_3006() {
    let src = "#3006=1 (CHECK PART)\n#100=1\nM30\n";
    let stops: Vec<(u32, bool, Option<String>)> = canon(src)
        .into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Stop { optional, message } => Some((c.line, optional, message)),
            _ => None,
        })
        .collect();
    assert_eq!(stops, vec![(1, false, Some("CHECK PART".to_string()))]);
    // The run continues after the stop.
    let r = run_src(src);
    assert!(r.completed());
    assert_eq!(r.messages, vec!["CHECK PART".to_string()]);
}

#[test]
fn timer_3001_counts_simulated_milliseconds() {
    // G04 P2500: 2.5 s.
    // Writable: counts on from the value written.
    // Motion time too, once the motion has been carried out: macro statements are read ahead
    // of the motion (look-ahead), and a non-motion command such as G04 waits for it. 100 mm at
    // 6000 mm/min = 1 s, plus the jerk-limited start and stop (100 mm/s with 80000 mm/s³ of
    // jerk and 4000 mm/s² of acceleration: two jerk phases of √(v/J) = 35.36 ms).
    let src = "#3001=0\nG90 G01 X100. F6000\nG04 P0\n#100=#3001\nM30\n";
    close(val(src, 100), 1000.0 + 2000.0 * (100.0f64 / 80000.0).sqrt());
}

#[test]
fn modal_g_codes_at_power_on() {
    let groups = [
        (1, 0.0),
        (2, 17.0),
        (3, 90.0),
        (5, 94.0),
        (6, 21.0),
        (7, 40.0),
        (8, 49.0),
        (9, 80.0),
        (10, 98.0),
        (12, 67.0),
        (13, 97.0),
        (14, 54.0),
        (15, 64.0),
        (16, 69.0),
    ];
    for (g, value) in groups {
        let src = format!("#100=#{}\nM30\n", 4000 + g);
        assert_eq!(var(&src, 100), Some(value), "#{}", 4000 + g);
    }
}

#[test]
fn modal_g_code_variables_follow_the_program() {
    let src = "\
G01 X1. F100
#101=#4001
G91
#103=#4003
G43.4 H1
#108=#4008
G54.1 P2
#114=#4014
#130=#4130
G18
#102=#4002
G95
#105=#4005
G20
#106=#4006
G99
#110=#4010
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn modal_g_codes_cover_groups_1_to_30() {
    // Every #4001–#4030 is readable.
    let mut src = String::new();
    for g in 1..=30 {
        src.push_str(&format!("#{}=#{}\n", 100 + g, 4000 + g));
    }
    src.push_str("M30\n");
    let r = run_src(&src);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.variables.len(), 30);
}

#[test]
fn modal_addresses_d_f_h_m_n_o_s_t() {
    let src = "\
O1234
N77 G01 X1. F250. S1200 T5 M03 D7 H3
#107=#4107
#109=#4109
#111=#4111
#113=#4113
#114=#4114
#115=#4115
#119=#4119
#120=#4120
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn d_is_modal_without_cutter_compensation() {
    // D given in G40 is kept: #4107 and the motion context show it (no radius: compensation is
    // off; G41 itself is not built, `unbuilt.rs`).
    let src = "D7\n#100=#4107\nG01 X10. F100\nM30\n";
    let m = motions(src);
    assert_eq!((m[0].context.d, m[0].context.cutter_radius), (7, 0.0));
}

#[test]
fn end_point_axes_beyond_the_machine_ps0115() {
    // …but head-bc's 4th axis is B.
    let r = run_with("G90 G00 B10.\n#100=#5004\n#101=#5024\nM30\n", "head-bc", Dialect::Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.variables, vec![(100, 10.0), (101, 10.0)]);
}

#[test]
fn machine_position_5021_includes_work_offset_and_tool_length() {
    let src = "\
#5221=100.
#5223=-50.
G90 G54 G00 X10.
#100=#5001
#101=#5021
#102=#5041
G43 H1 Z5.
#103=#5003
#104=#5023
#105=#5043
#106=#5083
#107=#5081
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(
        r.variables,
        // Z: 5 + work offset -50 + tool length 100 = 55.
        vec![(100, 10.0), (101, 110.0), (102, 10.0), (103, 5.0), (104, 55.0), (105, 5.0), (106, 100.0), (107, 0.0)]
    );
}

#[test]
fn g54_1_offsets_7001() {
    let src =
        "#7001=3.\n#7021=4.\n#7023=-1.\nG90 G54.1 P1 G00 X0\n#100=#5021\nG54.1 P2 X0 Z0\n#101=#5021\n#102=#5023\nM30\n";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn g10_l2_writes_work_offsets() {
    let src = "\
G10 L2 P1 X12. Y-3.
G10 L2 P6 Z7.
G10 L2 P0 X0.5
#100=#5221
#101=#5222
#102=#5323
#103=#5201
G91 G10 L2 P1 X1.
#104=#5221
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn g10_l10_to_l13_write_tool_offsets() {
    let src = "\
G10 L10 P3 R50.
G10 L11 P3 R0.2
G10 L12 P3 R4.
G10 L13 P3 R-0.1
#100=#11003
#101=#10003
#102=#13003
#103=#12003
#104=#2203
#105=#2003
G91 G10 L10 P3 R1.
#106=#11003
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn tool_offset_variables_and_aliases() {
    let src = "\
#100=#11001
#101=#13001
#10001=1.5
#12001=-0.25
#102=#2001
#2201=80.
#103=#11001
#104=#12001
#2200=3.
#105=#10200
#10999=9.
#106=#10999
M30
";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
}

// --- Values of variables and expressions in NC addresses --------------------------------------
// FANUC (custom macro, "ROUND" and "real versus integer values"): a variable's or expression's
// value used at an address is rounded half away from zero to the address's least input
// increment — 0.001 mm / deg at a distance address (IS-B), a whole number at M, S, T, H, D, P,
// L …; G codes excepted. ROUND inside an NC address rounds to that increment too.

/// The X of each motion's end, in block order.
fn x_ends(src: &str) -> Vec<f64> {
    motions(src).iter().map(|m| m.target[0]).collect()
}

#[test]
fn a_variable_at_a_distance_address_is_rounded_to_the_least_increment() {
    assert_eq!(x_ends("#1=1.2346\nG91 G01 X#1 F100\nM30\n"), vec![1.235]);
    assert_eq!(x_ends("#1=-1.2345\nG91 G01 X#1 F100\nM30\n"), vec![-1.235], "half away from zero");
    assert_eq!(x_ends("G90 G01 X[1.00049] F100\nM30\n"), vec![1.0]);
    // Rotary axes: 0.001 deg; arc centre words too.
    let m = motions_cfg("#1=10.00051\nG90 G00 B#1\nM30\n", "head-bc", |_| {});
    assert_eq!(m[0].target[3], 10.001);
    // Inch (G20): 0.0001 inch, then converted.
    let m = motions("#1=1.00006\nG20 G91 G01 X#1 F10.\nM30\n");
    assert!((m[0].target[0] - 1.0001 * 25.4).abs() < 1e-12, "{}", m[0].target[0]);
}

#[test]
fn the_manuals_drilling_example_returns_home_only_with_round() {
    // FANUC operator's manual, custom macro, ROUND: after G91 X-#1 (1.2345 → 1.235) and
    // X-#2 (2.3456 → 2.346) the return X[#1+#2] (3.5801 → 3.580) ends 0.001 short of the start;
    // X[ROUND[#1]+ROUND[#2]] (1.235 + 2.346 = 3.581) ends exactly there.
    let moves = "#1=1.2345\n#2=2.3456\nG00 G91 X-#1\nG01 X-#2 F300\n";
    let short = x_ends(&format!("{moves}G00 X[#1+#2]\nM30\n"));
    assert_eq!(short[0], -1.235);
    assert!((short[1] + 3.581).abs() < 1e-12, "{short:?}");
    assert!((short[2] + 0.001).abs() < 1e-12, "0.001 short: {short:?}");
    let home = x_ends(&format!("{moves}G00 X[ROUND[#1]+ROUND[#2]]\nM30\n"));
    assert!(home[2].abs() < 1e-12, "home: {home:?}");
}

#[test]
fn round_in_an_address_rounds_to_its_increment_in_a_statement_to_a_whole_number() {
    assert_eq!(x_ends("G90 G01 X[ROUND[1.2346]] F100\nM30\n"), vec![1.235]);
    // In a macro call's arguments the value is passed exactly.
    let src = "G65 P9010 A1.2346 B[ROUND[1.2346]]\nM30\nO9010\n#100=#1\n#101=#2\nM99\n";
    assert_eq!((val(src, 100), val(src, 101)), (1.2346, 1.0));
}

#[test]
fn a_variable_at_a_whole_number_address_is_rounded_not_refused() {
    let kinds = |src: &str| canon(src).into_iter().map(|c| c.kind).collect::<Vec<_>>();
    let has = |src: &str, want: CanonKind| kinds(src).contains(&want);
    assert!(has("#1=3.4999999\nM#1 S1000\nM30\n", CanonKind::Spindle { state: SpindleState::Cw, speed: 1000.0 }));
    assert!(has("M[3.5] S1000\nM30\n", CanonKind::Spindle { state: SpindleState::Ccw, speed: 1000.0 }));
    assert!(has("#1=1000.4999\nM03 S#1\nM30\n", CanonKind::Spindle { state: SpindleState::Cw, speed: 1000.0 }));
    assert!(has("M03 S[1000.5]\nM30\n", CanonKind::Spindle { state: SpindleState::Cw, speed: 1001.0 }));
    assert!(has("T[5.5]\nM30\n", CanonKind::ToolSelect { tool: 6 }));
}

#[test]
fn macro_call_arguments_take_a_decimal_point_at_every_address() {
    // Real shop programs pass tolerances through M (#13) and other "integer" addresses:
    // G65 P9010 M0.070 — an argument, not an M code.
    let src =
        "G65 P9010 M0.070 T1.5 S2.25 H-1.5 D0.5\nM30\nO9010\n#100=#13\n#101=#20\n#102=#19\n#103=#11\n#104=#7\nM99\n";
    let got: Vec<f64> = (100..=104).map(|n| val(src, n)).collect();
    assert_eq!(got, vec![0.07, 1.5, 2.25, -1.5, 0.5]);
    // The same in the blocks a G66.1 modal call takes its arguments from.
}

#[test]
fn a_colon_is_the_program_number_address() {
    // ISO code: `:1234` is O1234 (FANUC program number address in ISO tapes).
    let src = ":1234\nG65 P5678 A1.\nM30\n:5678\n#100=#1+1\nM99\n";
    let file = fivex_engine::lang::parse_file(src);
    assert!(fivex_engine::check::check(file, Dialect::Fanuc).is_empty());
}

#[test]
fn extended_common_variables_are_common_variables() {
    // The optional extended common variables #100000–#199999 and #500000–#999999.
    let r = run_src("#100001=3\n#500002=4\n#199999=1\n#999999=2\n#100=#100001+#500002\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn retained_variables_come_back_after_a_restart() {
    // #500–#999, #500000–#999999, the hour timer #3002, the part counts #3901/#3902 and the
    // inch/metric mode #4006 are kept through power off; #100–#199 and #100000–#199999 are not.
    let mut before = interpreter("#500=1\n#500000=2\n#100000=3\n#3002=1.25\n#3902=40\nM30\n", "mill3", Dialect::Fanuc);
    let r = run(&mut before, &RunOptions::default(), |_| {});
    assert!(r.completed());
    let kept = before.state.retained_variables();
    assert_eq!(kept, vec![(500, 1.0), (500000, 2.0), (3002, 1.25), (3901, 1.0), (3902, 40.0), (4006, 21.0)]);
    let mut after = interpreter("#100=#3002\n#101=#100000\n#102=#500000\nM30\n", "mill3", Dialect::Fanuc);
    let values: Vec<(u32, Option<f64>)> = kept.iter().map(|&(n, v)| (n, Some(v))).collect();
    after.state.load_retained(&values).unwrap();
    let r = run(&mut after, &RunOptions::default(), |_| {});
    assert_eq!(
        r.variables.iter().filter(|(n, _)| *n < 200).copied().collect::<Vec<_>>(),
        vec![(100, 1.25), (102, 2.0)]
    );
    assert!(after.state.load_retained(&[(100, Some(1.0))]).is_err(), "#100 is not retained");
}

#[test]
fn a_second_g66_nests_on_the_first_and_g67_cancels_the_latest() {
    // FANUC multiple modal calls: a move calls the latest macro; a move inside it calls the
    // one given before; G67 cancels the latest, so the first is in force again.
    // The log #121… records the macros in the order they are called (1: O9100, 2: O9200).
    let src =
        "#110=0\nG66 P9100\nG66 P9200\nG91 G00 X1.\n#111=#4012\nG67\n#112=#4012\nX1.\nG67\n#113=#4012\nX1.\nM30\n\
               O9100\n#110=#110+1\n#[120+#110]=1\nG91 G00 Z0.5\nM99\n\
               O9200\n#110=#110+1\n#[120+#110]=2\nG91 G00 Y1.\nM99\n";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
    let v = |n: u32| r.variables.iter().find(|(k, _)| *k == n).map(|p| p.1);
    assert_eq!((v(110), v(121), v(122), v(123)), (Some(3.0), Some(2.0), Some(1.0), Some(1.0)));
    assert_eq!((v(111), v(112), v(113)), (Some(66.0), Some(66.0), Some(67.0)), "group 12 follows the calls in force");
}

#[test]
fn bprnt_takes_its_one_digit_format_and_outputs_binary_words() {
    // FANUC BPRNT: `#var[c]`, c decimal places; each variable goes out as a 32-bit integer
    // (vacant: 0). fivex's message shows each word's value in braces.
    let r = run_src("#100=12.3456\n#101=-0.5\nPOPEN\nBPRNT[C**X#100[3]Y#101[3]M#10[0]]\nPCLOS\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.messages, vec!["C  X{12346}Y{-500}M{0}".to_string()]);
    let file = fivex_engine::lang::parse_file("BPRNT[X#100[3]]\n");
    assert!(fivex_engine::check::check(file, Dialect::Fanuc).is_empty());
}

#[test]
fn interface_signals_read_inputs_and_write_outputs() {
    // #1100–#1131 are the output bits UO000–UO031, #1132–#1135 the output groups; the inputs
    // #1000–#1035 are read-only to programs and set by the host (the PLC side).
    let src = "#1100=1\n#1103=1\n#100=#1132\n#1133=65536\n#101=#1133\n#102=#1000\n#103=#1032\nM30\n";
    let mut interp = interpreter(src, "mill3", Dialect::Fanuc);
    interp.state.signals.set_input(1000, 1.0).unwrap();
    interp.state.signals.set_input(1033, 7.0).unwrap();
    let r = run(&mut interp, &RunOptions::default(), |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let v = |n: u32| r.variables.iter().find(|(k, _)| *k == n).map(|p| p.1);
    assert_eq!((v(100), v(101), v(102), v(103)), (Some(9.0), Some(65536.0), Some(1.0), Some(1.0)));
    assert_eq!(interp.state.signals.inputs[1], 7);
}

#[test]
fn a_machine_set_to_inch_at_power_on_starts_in_g20() {
    // FANUC No.0000#2 INI = 1 (`motion.power_on_inch`): X1. is an inch until a G21.
    let src = "#100=#4006\nG91 G01 X1. F10.\nG21\nX1.\nM30\n";
    let mut interp =
        interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.edit_machine(|m| m.motion.power_on_inch = true));
    let mut ends = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                ends.push(m.target[0])
            }
        })
        .unwrap();
    assert_eq!(ends, vec![25.4, 26.4]);
    assert_eq!(interp.state.read(100).unwrap(), Some(20.0));
}

// --- Inch (G20): offsets and the modal F in the input unit -----------------------------------
// Decision (`docs/conventions.md`, "Units and numbers"): under G20 the offset variables hold
// inch like G10, the axis words and the position variables, so one macro line means one thing.
// Expected values by hand: 1 in = 25.4 mm.

/// A G20 program's interpreter after its run on mill3 in `dialect`, with `workpiece` on the
/// table; panics on an alarm.
fn inch_run(src: &str, dialect: Dialect, workpiece: Workpiece) -> (Interpreter, RunResult) {
    let mut interp = interp_cfg(src, "mill3", dialect, |c| c.workpiece = workpiece.into());
    let r = run_interp(&mut interp);
    assert!(r.completed(), "{:?} in\n{src}", r.alarms);
    (interp, r)
}

fn value_of(r: &RunResult, n: u32) -> f64 {
    r.variables.iter().find(|(k, _)| *k == n).unwrap_or_else(|| panic!("#{n} vacant")).1
}

/// `got` equals `want` within 1 nm (a value that went to mm and back may lose an ulp).
#[track_caller]
fn assert_near(got: &[f64], want: &[f64], what: &str) {
    assert!(
        got.len() == want.len() && got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-9),
        "{what}: {got:?}, want {want:?}"
    );
}

#[test]
fn under_g20_a_probed_height_added_to_the_work_offset_sets_it_in_inch() {
    // The stock's top at -50.8 mm = -2 in; tool length 0 and no D: the probe is the tip.
    let src = "\
G20 G90 G17 G40 G49 G80 G54
G10 L10 P1 R0
G00 G43 H1 X0 Y0 Z0
G31 Z-5. F20.
#100=#5063
#5223=#5223+#100
G00 Z1.
#101=#5023
#102=#5043
#103=#5223
M30
";
    let stock = Cuboid { min: [-100.0, -100.0, -200.0], max: [100.0, 100.0, -50.8] };
    let (interp, r) = inch_run(src, Dialect::Fanuc, Workpiece { boxes: vec![stock] });
    // Touch at Z -2 in; G54 Z = 0 + (-2) = -2 in; Z1. in G54 is machine Z 1 - 2 = -1 in.
    let v = |n| value_of(&r, n);
    assert_near(&[v(100), v(103)], &[-2.0, -2.0], "#5063 (the touch), #5223 (G54 Z)");
    assert_near(&[v(101), v(102)], &[-1.0, 1.0], "#5023, #5043 after G00 Z1.");
    assert_near(&[interp.state.offsets.work(1)[2]], &[-50.8], "G54 Z held in mm");
}

#[test]
fn under_g20_an_offset_copied_by_variables_equals_one_copied_by_g10() {
    // FANUC and Haas in G20; the length geometry of H1 is #11001, Haas #2001. (Syntec refuses
    // #5021… and #5221…: its #4001–#5500 are user parameters, `syntec_macro.rs`.)
    for (dialect, inch, h) in [(Dialect::Fanuc, "G20", 11000), (Dialect::Haas, "G20", 2000)] {
        let src = format!(
            "\
{inch} G90 G17 G40 G49 G80
G10 L2 P1 X2. Y1. Z-3.
#100=#5221
#5241=#5221
#5242=#5222
#5243=#5223
G10 L2 P3 X#5221 Y#5222 Z#5223
G55 G00 X0 Y0 Z0
#101=#5021
#102=#5022
#103=#5023
G56 X0 Y0 Z0
#104=#5021
#105=#5022
#106=#5023
G10 L10 P1 R4.
#107=#{h1}
#{h2}=#{h1}
G10 L10 P3 R#{h1}
M30
",
            h1 = h + 1,
            h2 = h + 2,
        );
        let (interp, r) = inch_run(&src, dialect, Workpiece::default());
        let v = |n| value_of(&r, n);
        let what = |s: &str| format!("{dialect:?}: {s}");
        assert_near(&[v(100)], &[2.0], &what("#5221 after G10 L2 P1 X2. in inch"));
        assert_near(&[v(101), v(102), v(103)], &[2.0, 1.0, -3.0], &what("G55 X0 Y0 Z0 in machine inch"));
        assert_near(&[v(104), v(105), v(106)], &[2.0, 1.0, -3.0], &what("G56 X0 Y0 Z0 in machine inch"));
        let o = &interp.state.offsets;
        for slot in [2, 3] {
            assert_near(&o.work(slot)[..3], &[50.8, 25.4, -76.2], &what("G55/G56 held in mm"));
        }
        assert_near(&[v(107)], &[4.0], &what("H1 after G10 L10 P1 R4."));
        assert_near(&[o.length(2), o.length(3)], &[101.6, 101.6], &what("H2 and H3 held in mm"));
    }
}

#[test]
fn under_g20_the_haas_g52_offset_reads_in_inch() {
    let src = "G20\nG52 X1. Z-0.5\n#100=#5201\n#101=#5203\nM30\n";
    let (_, r) = inch_run(src, Dialect::Haas, Workpiece::default());
    assert_near(&[value_of(&r, 100), value_of(&r, 101)], &[1.0, -0.5], "#5201, #5203");
}

#[test]
fn under_g20_the_modal_f_reads_in_inch_per_minute_and_f4109_restores_the_feed() {
    // The audit's save/restore idiom: F10. in/min = 254 mm/min before and after the macro.
    let src = "\
G20 G90 G94 G00 X0 Y0 Z0
G01 X1. F10.
#101=#4109
G65 P9030
G01 X2.
G93 G01 X3. F2.
#102=#4109
M30
O9030
#1=#4109
G01 Y1. F50.
F#1
M99
";
    let (_, r) = inch_run(src, Dialect::Fanuc, Workpiece::default());
    // G93: F is 1/min, not a length (2 = half a minute per block).
    assert_near(&[value_of(&r, 101), value_of(&r, 102)], &[10.0, 2.0], "#4109 in G94, in G93");
    let (lines, feeds): (Vec<u32>, Vec<f64>) = canon(src)
        .into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Motion(m) if m.kind != MotionKind::Rapid => Some((c.line, m.feed)),
            _ => None,
        })
        .unzip();
    assert_eq!(lines, vec![2, 11, 5, 6]);
    assert_near(&feeds, &[254.0, 1270.0, 254.0, 2.0], "feeds of lines 2, 11, 5, 6 (mm/min; G93 1/min)");
}

/// Audit ops F5: `#3003` (single block stop, FIN wait) and `#3004` (feed hold, feed override,
/// exact stop check) suppression are not built: a value that would suppress anything is
/// refused at its block (the value was stored, and the operator's stops and overrides still
/// acted); 0, everything in effect, is what fivex does and is taken.
#[test]
fn suppressing_single_block_or_feed_hold_by_3003_3004_is_refused_not_ignored() {
    alarms("G01 X10. F600.\n#3004=3\nG01 X100.\nM30\n", "PS0115", "COR-016");
    alarms("#3003=1\nG01 X10. F600.\nM30\n", "PS0115", "COR-016");
    assert_eq!(alarm_with("#3004=4\nM30\n", Dialect::Haas), "503");
    assert_eq!(val("#3003=0\n#3004=0\n#100=#3003+#3004+1\nM30\n", 100), 1.0);
}
