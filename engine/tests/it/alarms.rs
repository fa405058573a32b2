//! Every NC-level alarm path not covered by `macro_b.rs`, in both dialects.

use crate::common;
use common::*;
use fivex_engine::Dialect::{Fanuc, Syntec};

/// The alarm `src` ends in, in both dialects, with the line it names.
fn both(src: &str, fanuc: &str, syntec: &str, line: u32) {
    for (dialect, code) in [(Fanuc, fanuc), (Syntec, syntec)] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!(r.alarms.len(), 1, "{dialect:?}: expected one alarm from\n{src}");
        assert_eq!(r.alarms[0].code, code, "{dialect:?}\n{src}");
        assert_eq!(r.alarms[0].line, line, "{dialect:?}\n{src}");
    }
}

#[test]
fn address_the_machine_does_not_have() {
    both("G00 X1.\nG00 A10.\n", "PS0009", "COR-002", 2);
}

#[test]
fn address_without_a_value() {
    both("G00 X\n", "PS0005", "COR-003", 1);
}

#[test]
fn too_many_digits() {
    both("G00 X1234567890123456\n", "PS0003", "COR-004", 1);
}

#[test]
fn two_decimal_points() {
    both("G00 X1.2.3\n", "PS0004", "COR-001", 1);
}

#[test]
fn cutting_feed_without_f() {
    both("G01 X10.\n", "PS0011", "COR-010", 1);
    both("G01 X10. F0\n", "PS0011", "COR-010", 1);
}

#[test]
fn offset_numbers_out_of_range() {
    both("G43 H1000 Z0\n", "PS0030", "COR-011", 1);
    both("G54.1 P301\n", "PS0030", "COR-011", 1);
    both("D-1 X1.\n", "PS0030", "COR-011", 1);
    both("G10 L10 P1000 R1.\n", "PS0030", "COR-011", 1);
}

#[test]
fn arc_end_point_off_the_circle() {
    both("G17 G02 X10. Y0 I3. J0 F100\n", "PS0020", "COR-012", 1);
    // R smaller than half the chord.
    both("G17 G02 X10. Y0 R4. F100\n", "PS0020", "COR-012", 1);
}

#[test]
fn plane_change_during_cutter_compensation() {
    both("G17 G41 D1 G01 X10. F100\nG18\n", "PS0037", "COR-013", 2);
    // Re-selecting the same plane is not a change.
    for dialect in [Fanuc, Syntec] {
        assert!(run_with("G17 G41 D1 G01 X10. F100\nG17\nG40 X0\nM30\n", "mill3", dialect).completed());
    }
}

#[test]
fn data_setting_format() {
    both("G10 P1 X10.\n", "PS1144", "COR-014", 1);
    both("G10 L2 X10.\n", "PS1144", "COR-014", 1);
    both("G10 L7 P1 X10.\n", "PS1144", "COR-014", 1);
    both("G10 L10 P1\n", "PS1144", "COR-014", 1);
    both("G10 L2 P7 X1.\n", "PS0030", "COR-011", 1);
}

#[test]
fn peck_cycle_without_q() {
    both("G00 Z10.\nG83 X0 Y0 Z-5. R2. F100\n", "PS0045", "COR-015", 2);
    both("G00 Z10.\nG73 X0 Y0 Z-5. R2. F100\n", "PS0045", "COR-015", 2);
}

#[test]
fn reference_return_inside_a_canned_cycle() {
    both("G00 Z10.\nG81 X0 Y0 Z-5. R2. F100\nG28 Z10.\n", "PS0044", "COR-016", 3);
}

#[test]
fn g_as_macro_argument() {
    both("O1\nG65 P2 G01 A1.\nM30\nO2\nM99\n", "PS0129", "COR-032", 2);
}

#[test]
fn macro_statement_and_nc_words_in_one_block() {
    both("G01 X1. #1=2\n", "PS0127", "COR-033", 1);
    both("#1=2 X1.\n", "PS0127", "COR-033", 1);
}

#[test]
fn unknown_g_codes() {
    both("G12.3\n", "PS0010", "COR-070", 1);
    both("G43.45\n", "PS0010", "COR-070", 1);
    // G53.3 exists only in the Syntec dialect.
    assert_eq!(alarm_with("G53.3\n", Fanuc), "PS0010");
    assert!(run_with("G53.3\nM30\n", "mill3", Syntec).completed());
}

#[test]
fn two_one_shot_codes_that_both_take_axes() {
    both("G28 G92 X0\n", "PS0010", "COR-070", 1);
}

#[test]
fn the_alarm_names_the_sequence_number() {
    let r = run_src("N10 G00 X1.\nN20 G01 X2.\n");
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line, r.alarms[0].n), ("PS0011", 2, Some(20)));
}

#[test]
fn a_block_that_would_expand_without_bound_alarms() {
    // One million pecks: stopped at the expansion limit, not after exhausting memory.
    both("G00 Z1.\nG83 X0 Y0 Z-1000. R0 Q0.001 F1000.\n", "FX0003", "FX0003", 2);
}

#[test]
fn g80_forgets_the_cycle_data() {
    // The dwell P of G82 must not survive G80 into a later G81.
    let src = "G00 Z10.\nG82 X0 Y0 Z-1. R1. P500 F600\nG80\nG81 X1. Y0 Z-1. R1.\nM30\n";
    let dwells = canon(src).iter().filter(|c| matches!(c.kind, fivex_engine::canon::CanonKind::Dwell { .. })).count();
    assert_eq!(dwells, 1);
}

#[test]
fn positions_read_in_inch_under_g20() {
    let r = run_src("G20 G00 X1. Y1\n#100=#5001\n#101=#5002\n#102=#5021\nM30\n");
    let v = |n| r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v).unwrap();
    assert!(approx(v(100), 1.0) && approx(v(101), 0.0001) && approx(v(102), 1.0), "{:?}", r.variables);
}

#[test]
fn g49_in_g49_mode_does_not_move() {
    assert!(motions("G21 G17 G40 G49 G80 G90 G94\nM30\n").is_empty());
}

#[test]
fn runaway_expressions_are_refused_not_crashing() {
    let long_sum = format!("#100=1{}\nM30\n", "+1".repeat(100_000));
    both(&long_sum, "PS0125", "COR-020", 1);
    let minus = format!("#100={}1\nM30\n", "-".repeat(100_000));
    both(&minus, "PS0125", "COR-020", 1);
    // Within the bound, fine.
    assert_eq!(var(&format!("#100=1{}\nM30\n", "+1".repeat(400)), 100), Some(401.0));
}

#[test]
fn a_time_budget_alarm_names_the_block() {
    let mut interp = interpreter("N10 G00 X0\nN20 G01 X500. F100.\nM30\n", "mill3", Fanuc);
    let r = fivex_engine::run::run(
        &mut interp,
        &fivex_engine::run::RunOptions { period_s: 0.0, max_time_s: 10.0, ..Default::default() },
        |_| {},
    );
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line, r.alarms[0].n), ("FX0002", 2, Some(20)));
    // The run stops where the budget runs out, inside the block: 10 s at 100 mm/min is about
    // 16.6 mm (less the speed-up).
    assert_eq!(r.cycle_time_s, 10.0);
    assert!(r.machine[0] > 16.0 && r.machine[0] < 16.7, "{}", r.machine[0]);
}
