//! Rollover rotary axes and the moves to machine positions (`docs/conventions.md`, "Rollover
//! axes and machine positions"): a reference return (G28, G30, manual REF) turns a rollover axis
//! less than a turn, positive (FANUC rotary axis A type: the machine coordinate kept within a
//! turn, the return the way of the manual one, No.1006#5 ZMI = 0; the Haas dialect the shorter
//! way); G53 goes the way an absolute command goes. Neither unwinds the turns made.
//!
//! table-ac: X Y Z A C, C (index 4) rolls over the shorter way; no work offset, so program C
//! is machine C.

use crate::common::{interpreter, motion_ends};
use fivex_engine::canon::Pos;
use fivex_engine::controller::{Controller, Mode, RunState};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::vendor;
use fivex_engine::Dialect;

const C: usize = 4;

/// The machine C at the end of each motion, with its line.
fn c_ends(interp: Interpreter) -> Vec<(u32, f64)> {
    motion_ends(interp).into_iter().map(|(line, m): (u32, Pos)| (line, m[C])).collect()
}

/// table-ac with its C changed by `tweak`, running `src` in FANUC's dialect.
fn table_ac_with(src: &str, tweak: impl FnOnce(&mut fivex_engine::machine::Axis)) -> Interpreter {
    let mut m = MachineConfig::preset("table-ac").unwrap();
    tweak(&mut m.axes[C]);
    Interpreter::new(parse_file(src), Config::new(m, Dialect::Fanuc))
}

/// The travels of C by the motions of `line` (each from where the motion before ended).
fn travels(ends: &[(u32, f64)], line: u32) -> Vec<f64> {
    let mut from = 0.0;
    let mut out = Vec::new();
    for &(l, c) in ends {
        if l == line {
            out.push(c - from);
        }
        from = c;
    }
    out
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
}

#[test]
fn g28_turns_a_rollover_axis_less_than_a_turn() {
    // The audit's g28a.nc: 3600 + 30 = 3630 turned; 3630 is 30 past machine zero (10 turns),
    // so the way to zero going positive is 360 − 30 = 330 (FANUC; Syntec follows FANUC), the
    // shorter way −30 (Haas), never −3630.
    let src = "G91 G01 C3600. F36000.\nC30.\nG28 C0.\nM30\n";
    for (dialect, travel) in [(Dialect::Fanuc, 330.0), (Dialect::Syntec, 330.0), (Dialect::Haas, -30.0)] {
        let ends = c_ends(interpreter(src, "table-ac", dialect));
        // G91 C0: the intermediate point is where C stands, then the return.
        assert!(close(&travels(&ends, 3), &[0.0, travel]), "{dialect:?}: {:?}", travels(&ends, 3));
    }
    // Turned by a whole number of turns the axis is at its reference: no travel (the audit's
    // 4th-axis wrap, A1800 = 5 turns, on C here).
    let ends = c_ends(interpreter("G91 G01 X10. C1800. F20000.\nG91 G28 C0\nM30\n", "table-ac", Dialect::Fanuc));
    assert!(close(&travels(&ends, 2), &[0.0, 0.0]), "{:?}", travels(&ends, 2));
    // Backwards: −3630 is 330 past zero (−3630 + 11·360 = 330): +30 to 360.
    let ends = c_ends(interpreter("G91 G01 C-3630. F36000.\nG28 C0.\nM30\n", "table-ac", Dialect::Fanuc));
    assert!(close(&travels(&ends, 2), &[0.0, 30.0]), "{:?}", travels(&ends, 2));
}

#[test]
fn haas_g28_without_axis_words_returns_the_platter_the_shorter_way() {
    // Haas G28 without axis words returns every axis, the rotary ones too: C at 7210 = 20 turns
    // and 10, back 10 to zero.
    let ends = c_ends(interpreter("G91 G01 C7210. F36000.\nG28\nM30\n", "table-ac", Dialect::Haas));
    let t = travels(&ends, 2);
    assert!((t.iter().sum::<f64>() + 10.0).abs() < 1e-9 && t.iter().all(|&d| d <= 0.0), "{t:?}");
}

#[test]
fn g30_goes_to_a_rollover_reference_less_than_a_turn() {
    // The audit's g53a.nc line 6: from C10, C−725 ends at −715 (= 5); G90 G30 C0: the
    // intermediate point C0 the shorter way, −5 (to −720), then the 2nd reference (0) is there.
    let src = "G90 G00 C10.\nG91 G00 C-725.\nG90 G30 C0.\nM30\n";
    let ends = c_ends(interpreter(src, "table-ac", Dialect::Fanuc));
    assert!(close(&travels(&ends, 3), &[-5.0, 0.0]), "{:?}", travels(&ends, 3));
    // 2nd reference C270 (tacref.json): from 3600 (= 0) the return goes +270, not −3330.
    let src = "G91 G01 C3600. F36000.\nG91 G30 C0\nM30\n";
    let tweak = |a: &mut fivex_engine::machine::Axis| a.references = [270.0, 0.0, 0.0];
    let ends = c_ends(table_ac_with(src, tweak));
    assert!(close(&travels(&ends, 2), &[0.0, 270.0]), "{:?}", travels(&ends, 2));
    // From 3600 + 300 = 300 past zero to 270: positive, 330 (not −30).
    let src = "G91 G01 C3900. F36000.\nG91 G30 C0\nM30\n";
    let ends = c_ends(table_ac_with(src, tweak));
    assert!(close(&travels(&ends, 2), &[0.0, 330.0]), "{:?}", travels(&ends, 2));
}

#[test]
fn g53_on_a_rollover_axis_goes_the_way_an_absolute_command_goes() {
    // The audit's g53a.nc line 2: 3630 is 30 past zero; G53 C0 the shorter way: −30.
    let src = "G91 G01 C3630. F36000.\nG90 G53 C0.\nM30\n";
    let ends = c_ends(interpreter(src, "table-ac", Dialect::Fanuc));
    assert!(close(&travels(&ends, 2), &[-30.0]), "{:?}", travels(&ends, 2));
    // G53 C200 from 30: 170 ahead, the shorter way is positive.
    let ends = c_ends(interpreter("G91 G01 C3630. F36000.\nG90 G53 C200.\nM30\n", "table-ac", Dialect::Fanuc));
    assert!(close(&travels(&ends, 2), &[170.0]), "{:?}", travels(&ends, 2));
    // The sign gives the way (No.1008#1 RAB = 1, Syntec Pr201 = 2): C0 goes +330, C−0. −30.
    let sign = |a: &mut fivex_engine::machine::Axis| a.shortest = false;
    let src = "G91 G01 C3630. F36000.\nG90 G53 C0.\nG91 G01 C30.\nG90 G53 C-0.\nM30\n";
    let ends = c_ends(table_ac_with(src, sign));
    assert!(close(&travels(&ends, 2), &[330.0]), "{:?}", travels(&ends, 2));
    assert!(close(&travels(&ends, 4), &[-30.0]), "{:?}", travels(&ends, 4));
    // A rotary axis that does not roll over goes to the machine coordinate as said.
    let linear = |a: &mut fivex_engine::machine::Axis| (a.rollover, a.shortest) = (false, false);
    let ends = c_ends(table_ac_with("G91 G01 C730. F36000.\nG90 G53 C0.\nG91 C30.\nG28 C0.\nM30\n", linear));
    assert!(close(&travels(&ends, 2), &[-730.0]), "{:?}", travels(&ends, 2));
    assert!(close(&travels(&ends, 4), &[0.0, -30.0]), "{:?}", travels(&ends, 4));
}

/// The unwound travel of C while the controller runs: the shown C (within a turn) sampled
/// every tick, each step taken as the shorter difference.
fn c_travel(c: &mut Controller, limit: f64) -> (f64, f64, f64) {
    let (mut total, mut lo, mut hi) = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut last = c.point().machine[C];
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < limit {
        c.tick(0.002);
        let now = c.point().machine[C];
        total += (now - last + 540.0).rem_euclid(360.0) - 180.0;
        (lo, hi, last) = (lo.min(total), hi.max(total), now);
    }
    (total, lo, hi)
}

#[test]
fn manual_reference_return_turns_a_rollover_axis_less_than_a_turn() {
    // The audit's service case: C turned 3630 in MDI, then REF: +330, never backwards.
    let mut c = Controller::new(Config::new(MachineConfig::preset("table-ac").unwrap(), Dialect::Fanuc));
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("G91 G01 C3630. F360000.").unwrap();
    c.cycle_start().unwrap();
    let (turned, ..) = c_travel(&mut c, 120.0);
    assert!((turned - 3630.0).abs() < 1e-6, "{turned}");
    c.set_mode(Mode::Ref).unwrap();
    c.reference_return().unwrap();
    let (total, lo, hi) = c_travel(&mut c, 120.0);
    assert_eq!(c.run_state(), RunState::Idle);
    assert!((total - 330.0).abs() < 1e-6 && lo > -1e-9 && hi < 330.0 + 1e-6, "{total} {lo} {hi}");
    assert!(c.point().machine[C].abs() < 1e-9 || (c.point().machine[C] - 360.0).abs() < 1e-9);
}

#[test]
fn a_fanuc_list_with_a_negative_reference_return_on_a_rollover_axis_is_refused() {
    // No.1006#5 ZMI = 1 would send the returns negative; fivex turns them positive only, so the
    // list is refused rather than run the other way round.
    let m = MachineConfig::preset("table-ac").unwrap();
    let mut p = vendor::params_of(Dialect::Fanuc, &m).unwrap();
    assert!(vendor::machine_from(Dialect::Fanuc, "t", &p).unwrap().axes[C].rollover);
    p.set_axes(1006, vec![0.0, 0.0, 0.0, 1.0, 33.0]);
    let e = vendor::machine_from(Dialect::Fanuc, "t", &p).unwrap_err();
    assert!(e.detail.contains("No.1006#5"), "{}", e.detail);
    // On an axis that does not roll over the direction changes nothing fivex moves.
    p.set_axes(1006, vec![32.0, 0.0, 0.0, 33.0, 1.0]);
    assert!(vendor::machine_from(Dialect::Fanuc, "t", &p).is_ok());
}
