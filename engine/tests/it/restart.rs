//! FANUC program restart (`interp/restart.rs`, `controller/restart.rs`; `docs/dialects.md`,
//! "Program restart"): the block search recovers what a run from the top leaves (modal groups,
//! F/S/T/H/D, work offsets, macro variables, the position), the return moves one axis at a time,
//! the program goes on from the restart block; P type and Q type and the manual's alarms.

use crate::common::cases;
use fivex_engine::controller::{
    Controller, Mode, Refusal, RestartPhase, RestartType, RunState, SEARCH_BLOCKS_PER_TICK,
};
use fivex_engine::interp::restart::Target;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use proptest::prelude::*;

const TICK: f64 = 0.01;

fn config(dialect: Dialect) -> Config {
    Config::new(MachineConfig::preset("mill3").unwrap(), dialect)
}

fn controller() -> Controller {
    Controller::new(config(Dialect::Fanuc))
}

fn n(n: u32) -> Target {
    Target::Sequence { n, occurrence: 1 }
}

/// Tick until the controller stops running (at most `limit` simulated seconds).
fn settle(c: &mut Controller, limit: f64) {
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < limit {
        c.tick(TICK);
    }
    assert_ne!(c.run_state(), RunState::Running, "still running after {limit} s");
}

/// A controller that ran `src` from the top to its end.
fn ran(src: &str) -> Controller {
    let mut c = controller();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 600.0);
    c
}

/// The run of `src`'s blocks before block `n` (`prefix`) on a fresh controller, in MDI: that text
/// has no M30, and a FANUC memory run of it would end in PS5010 END OF RECORD after them.
fn ran_to(src: &str, n: u32) -> Controller {
    let mut c = controller();
    mdi(&mut c, &prefix(src, n));
    c
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

fn alarm_code(c: &Controller) -> &str {
    &c.alarms().first().expect("an alarm").code
}

const PROGRAM: &str = "\
O1000
N10 G90 G17 G21 G94 G54 G00 X10. Y10. Z50.
N20 G10 L2 P2 X30. Y-20. Z5.
N30 T5 M06
N40 S2400 M03
N50 G55 G43 H5 Z20. F800.
N60 #100 = 7
N65 #101 = [#100 * 3]
N70 G91 G01 X5. Y[#101] F1200.
N80 G90 G03 X-5. Y61. R20.
N90 M61
N100 G01 Z-2.
N110 X0 Y0
N120 M30
";

/// The program's text from its top up to (not including) the block numbered `n`.
fn prefix(src: &str, n: u32) -> String {
    let cut = src.find(&format!("\nN{n} ")).expect("the block");
    src[..=cut].to_string()
}

#[test]
fn the_search_stands_before_the_restart_block_with_the_state_of_a_run_from_the_top() {
    let mut searched = Interpreter::new(parse_file(PROGRAM), config(Dialect::Fanuc));
    let found = searched.search(n(100)).unwrap();
    assert_eq!((found.line, found.n), (12, Some(100)));
    assert_eq!(searched.next_block(), Some((12, Some(100), 1)));

    let mut top = Interpreter::new(parse_file(&prefix(PROGRAM, 100)), config(Dialect::Fanuc));
    // As MDI: the text of the blocks before N100 has no M30 (in memory operation: PS5010).
    top.set_mdi_operation(true);
    top.run(|_| {}).unwrap();
    assert_eq!(searched.state.modal_state(), top.state.modal_state());
    assert!(
        close(&found.machine, &top.state.machine_position()),
        "{:?} {:?}",
        found.machine,
        top.state.machine_position()
    );
    assert_eq!(searched.state.common_variables(), top.state.common_variables());
    assert_eq!(searched.state.offsets.work(2), top.state.offsets.work(2));
    // What the machine must be given: the tool change and the spindle, and the M codes shown.
    let kinds: Vec<String> = found.output.iter().map(|c| format!("{:?}", c.kind)).collect();
    assert_eq!(kinds.len(), 2, "{kinds:?}");
    assert!(kinds[0].starts_with("ToolChange") && kinds[1].starts_with("Spindle"), "{kinds:?}");
    assert_eq!(found.m_codes, vec![61], "M06 and M03 are output as tool and spindle; M61 is listed");
}

#[test]
fn the_coolant_passed_over_is_listed_for_the_operator_with_the_other_m_codes() {
    // The audit's program: M08, M10, M07, M21, M51 before N9; the list in program order.
    let src = "N1 G90 G17 G21 G94\nN2 T1 M06\nN3 S1000 M03\nN4 M08\nN5 M10\nN6 M07\nN7 M21\n\
        N8 M51 M09\nN9 G01 X10. F600\nN10 M30\n";
    let mut searched = Interpreter::new(parse_file(src), config(Dialect::Fanuc));
    let found = searched.search(n(9)).unwrap();
    assert_eq!(found.m_codes, vec![8, 10, 7, 21, 51, 9]);
}

#[test]
fn the_occurrence_counts_the_passes_of_a_loop_and_a_line_can_be_the_target() {
    let src = "#1 = 0\nWHILE [#1 LT 5] DO1\nN50 #1 = #1 + 1\nEND1\nN60 M30\n";
    let mut i = Interpreter::new(parse_file(src), config(Dialect::Fanuc));
    i.search(Target::Sequence { n: 50, occurrence: 3 }).unwrap();
    // Twice through N50 before: #1 is 2 when the third pass is about to run.
    assert_eq!(i.state.common_variables().iter().find(|(k, _)| *k == 1), None, "#1 is local");
    let mut i = Interpreter::new(parse_file(&src.replace("#1", "#100")), config(Dialect::Fanuc));
    i.search(Target::Sequence { n: 50, occurrence: 3 }).unwrap();
    assert_eq!(i.state.common_variables(), vec![(100, 2.0)]);
    let mut i = Interpreter::new(parse_file(&src.replace("#1", "#100")), config(Dialect::Fanuc));
    let found = i.search(Target::Line { line: 3, occurrence: 5 }).unwrap();
    assert_eq!((found.line, found.n), (3, Some(50)));
    assert_eq!(i.state.common_variables(), vec![(100, 4.0)]);
}

#[test]
fn a_block_never_reached_is_ps0071() {
    let mut i = Interpreter::new(parse_file(PROGRAM), config(Dialect::Fanuc));
    assert_eq!(i.search(n(999)).unwrap_err().code, "PS0071");
    // The sixth pass of a loop that runs five times is not reached either.
    let src = "#100 = 0\nWHILE [#100 LT 5] DO1\nN50 #100 = #100 + 1\nEND1\nM30\n";
    let mut i = Interpreter::new(parse_file(src), config(Dialect::Fanuc));
    assert_eq!(i.search(Target::Sequence { n: 50, occurrence: 6 }).unwrap_err().code, "PS0071");
}

#[test]
fn a_sequence_number_inside_a_subprogram_is_not_a_restart_block() {
    // The search stops only in the main program: N20 of O2000 is passed over, N20 of the main
    // program (after the call) is the restart block.
    let src = "O1000\nN10 M98 P2000\nN20 #101 = 1\nM30\nO2000\nN20 #100 = 1\nM99\n";
    let mut i = Interpreter::new(parse_file(src), config(Dialect::Fanuc));
    let found = i.search(n(20)).unwrap();
    assert_eq!(found.line, 3);
    assert_eq!(i.state.common_variables(), vec![(100, 1.0)]);
}

#[test]
fn a_program_alarm_in_the_search_stops_it() {
    let src = "N10 #100 = 1 / 0\nN20 X1.\nM30\n";
    let mut i = Interpreter::new(parse_file(src), config(Dialect::Fanuc));
    assert_eq!(i.search(n(20)).unwrap_err().code, "PS0112");
}

#[test]
fn a_restart_block_in_a_mode_the_return_cannot_enter_is_refused() {
    for (mode, why) in [
        ("G81 X10. Y10. Z-5. R2. F100.", "canned cycle"),
        ("G41 D1 G01 X10. Y10. F100.", "cutter compensation"),
        ("G66 P9000 A1.", "modal macro call"),
        ("G01 X10. ,C1. F100.", "a chamfer's corner held"),
    ] {
        let src = format!("N10 G90 G00 X0 Y0 Z10.\nN20 {mode}\nN30 X20.\nN40 G80 G40 G67\nM30\nO9000\nM99\n");
        let mut i = Interpreter::new(parse_file(&src), config(Dialect::Fanuc));
        assert_eq!(i.search(n(30)).unwrap_err().code, "FX0005", "{why}");
        // Before the mode, or after it is cancelled, the restart is allowed.
        let mut i = Interpreter::new(parse_file(&src), config(Dialect::Fanuc));
        i.search(n(20)).unwrap_or_else(|a| panic!("{why}: {a:?}"));
    }
    let tcp = "N10 G90 G00 X0 Y0 Z100. B0 C0\nN20 G43.4 H1 X10.\nN30 X20.\nN40 G49\nM30\n";
    let cfg = Config::new(MachineConfig::preset("head-bc").unwrap(), Dialect::Fanuc);
    let mut i = Interpreter::new(parse_file(tcp), cfg);
    assert_eq!(i.search(n(30)).unwrap_err().code, "FX0005", "tool centre point control");
}

#[test]
fn q_type_returns_one_axis_at_a_time_then_goes_on_as_a_run_from_the_top() {
    let full = ran(PROGRAM);
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    let r = c.restart_status().expect("searched");
    assert_eq!((r.phase, r.found.n, r.kind), (RestartPhase::Searched, Some(100), RestartType::Q));
    let target = r.found.machine;
    // Nothing moved: the search is not a run.
    assert!(close(&c.point().machine, &[0.0; 3]));
    assert_eq!(c.spindle(), 0.0);
    c.cycle_start().unwrap();
    assert_eq!(c.restart_status().unwrap().phase, RestartPhase::Returning);
    assert_eq!(c.spindle(), 2400.0, "the spindle the search passed over is output first");
    // The return: one axis at a time, in the machine's order (each ends on the restart position
    // before the next leaves where it stood).
    let from = c.point().machine;
    let mut arrived = false;
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < 60.0 {
        c.tick(0.001);
        let m = c.point().machine;
        if c.restart_status().is_none() {
            arrived = true;
            continue;
        }
        assert_eq!(c.point().n, Some(100), "the return shows the restart block");
        let left: Vec<bool> = (0..3).map(|i| (m[i] - from[i]).abs() > 1e-9).collect();
        let there: Vec<bool> = (0..3).map(|i| (m[i] - target[i]).abs() < 1e-9).collect();
        // No axis after the first one still on its way has left where it stood.
        if let Some(i) = there.iter().position(|t| !t) {
            assert!(!left[i + 1..].contains(&true), "an axis after {i} left before it arrived: {m:?}");
        }
    }
    assert!(arrived);
    assert_eq!(c.run_state(), RunState::Idle);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert!(close(&c.point().machine, &full.point().machine));
    assert_eq!(c.modal(), full.modal());
}

#[test]
fn single_block_stops_on_the_restart_position_before_the_restart_block() {
    let top = ran_to(PROGRAM, 110);
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(110), RestartType::Q).unwrap();
    c.panel.single_block = true;
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(c.restart_status().is_none());
    assert!(close(&c.point().machine, &top.point().machine), "{:?} {:?}", c.point().machine, top.point().machine);
    assert_eq!(c.modal(), top.modal());
    assert_eq!(c.interpreter().state.common_variables(), top.interpreter().state.common_variables());
    assert_eq!(c.point().n, Some(110), "the panel shows the restart block");
    // Cycle start goes on block by block.
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert_eq!(c.point().n, Some(110));
}

#[test]
fn a_feed_hold_in_the_return_waits_and_cycle_start_goes_on_an_emergency_stop_forgets_it() {
    let full = ran(PROGRAM);
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    c.cycle_start().unwrap();
    while c.point().machine[0] < 20.0 {
        c.tick(0.001);
    }
    c.feed_hold();
    settle(&mut c, 10.0);
    assert_eq!(c.run_state(), RunState::Hold);
    let x = c.point().machine[0];
    assert!(x > 20.0 && x < 70.0, "held on the way: {x}");
    assert_eq!(c.restart_status().unwrap().phase, RestartPhase::Returning);
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert!(close(&c.point().machine, &full.point().machine));
    // An emergency stop in the return ends the restart.
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    c.cycle_start().unwrap();
    c.tick(0.05);
    c.emergency_stop(true);
    assert!(c.restart_status().is_none());
}

#[test]
fn p_type_needs_an_automatic_operation_since_power_on_and_the_emergency_stop() {
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0097");
    c.reset();
    c.cycle_start().unwrap();
    settle(&mut c, 600.0);
    c.emergency_stop(true);
    c.emergency_stop(false);
    c.reset();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0097");
}

#[test]
fn p_type_is_refused_after_the_work_offsets_changed() {
    let mut c = ran(PROGRAM);
    c.interpreter_mut().state.offsets.work_mut(1)[0] += 1.0;
    c.offsets_changed();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0096");
    // A tool offset edit (the broken tool's new length) is what P type is for.
    let mut c = ran(PROGRAM);
    c.interpreter_mut().state.offsets.tool_mut(5).unwrap().h_wear = 0.5;
    c.offsets_changed();
    c.restart(n(100), RestartType::P).unwrap();
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
}

#[test]
fn p_type_searches_from_where_the_interrupted_run_started_wherever_the_machine_is_now() {
    // Incremental moves: the restart position depends on where the program started.
    let src = "N10 G91 G00 X10. Y5.\nN20 G01 X20. F3000.\nN30 Y15.\nN40 X-5.\nM30\n";
    let mut c = controller();
    c.set_mode(Mode::Handle).unwrap();
    c.handle('X', 40.0).unwrap();
    settle(&mut c, 10.0);
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    // The tool breaks in N30: reset, the tool is moved away by hand, P type from N30.
    while c.point().n != Some(30) {
        c.tick(0.001);
    }
    c.reset();
    settle(&mut c, 10.0);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('Z', 50.0).unwrap();
    settle(&mut c, 10.0);
    c.set_mode(Mode::Auto).unwrap();
    c.restart(n(30), RestartType::P).unwrap();
    let target = c.restart_status().unwrap().found.machine;
    assert!(close(&target, &[70.0, 5.0, 0.0]), "{target:?}");
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(close(&c.point().machine, &[65.0, 20.0, 0.0]), "{:?}", c.point().machine);
    // Q type from here would take the machine's position as the program's start.
    let mut q = controller();
    q.select_program(src).unwrap();
    q.restart(n(30), RestartType::Q).unwrap();
    assert!(close(&q.restart_status().unwrap().found.machine, &[30.0, 5.0, 0.0]));
}

/// Run `text` in MDI to its end, then back to AUTO.
fn mdi(c: &mut Controller, text: &str) {
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi(text).unwrap();
    c.cycle_start().unwrap();
    settle(c, 60.0);
    c.set_mode(Mode::Auto).unwrap();
}

#[test]
fn mdi_after_the_search_is_ps0099_and_reset_forgets_the_search() {
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("M08\nG00 X1.").unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 10.0);
    assert_eq!(alarm_code(&c), "PS0099");
    assert_eq!(c.alarms()[0].line, 2, "the block with the move");
    assert!(close(&c.point().machine, &[0.0; 3]), "the move is not made: {:?}", c.point().machine);
    assert!(c.restart_status().is_none());
    c.reset();
    c.set_mode(Mode::Auto).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    c.reset();
    assert!(c.restart_status().is_none());
    // Cycle start now runs the program from its top.
    c.cycle_start().unwrap();
    c.tick(0.001);
    assert_eq!(c.point().n, Some(10));
}

#[test]
fn m_s_t_f_a_dwell_and_variables_in_mdi_keep_the_search_and_the_restart_goes_on_from_it() {
    // FANUC allows the M/S/T to be given by MDI after the search; only a move there is PS0099.
    let full = ran(PROGRAM);
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    mdi(&mut c, "M08\nS500 M03\nT2 M06\nG94 F300.\nG04 X0.1\n#500 = 42\n");
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert_eq!(c.restart_status().map(|r| r.phase), Some(RestartPhase::Searched));
    c.cycle_start().unwrap();
    assert_eq!(c.spindle(), 2400.0, "the search's spindle is output");
    settle(&mut c, 60.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert!(close(&c.point().machine, &full.point().machine), "{:?}", c.point().machine);
    assert_eq!(c.modal(), full.modal(), "the program goes on in the searched modes (F1200., not F300.)");
    let vars = c.interpreter().state.common_variables();
    assert!(vars.contains(&(500, 42.0)), "the MDI's variable write stays: {vars:?}");
    // A coordinate system set in MDI would be dropped by the restart: refused at its cycle start.
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.restart(n(100), RestartType::Q).unwrap();
    mdi(&mut c, "G92 X0 Y0\n");
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c.cycle_start().unwrap();
    assert_eq!(alarm_code(&c), "PS0099");
    assert!(c.restart_status().is_none());
    assert!(close(&c.point().machine, &[0.0; 3]));
}

#[test]
fn a_restart_run_is_the_last_automatic_operation() {
    // Incremental moves: where the search starts decides the restart position.
    let src = "N10 G91 G00 X10. Y5.\nN20 G01 X20. F3000.\nN30 Y15.\nN40 X-5.\nM30\n";
    // The first run starts at X0 Y0 and ends at X25 Y20. The operator brings the machine to
    // X40 Y0 and restarts there by Q type; the restart run ends.
    let mut c = ran(src);
    assert!(close(&c.point().machine, &[25.0, 20.0, 0.0]), "{:?}", c.point().machine);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('X', 15.0).unwrap();
    settle(&mut c, 10.0);
    c.handle('Y', -20.0).unwrap();
    settle(&mut c, 10.0);
    c.set_mode(Mode::Auto).unwrap();
    c.restart(n(20), RestartType::Q).unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert!(close(&c.point().machine, &[65.0, 20.0, 0.0]), "{:?}", c.point().machine);
    // P type now takes the restart run's coordinates: from X40 Y0, N40 starts at X70 Y20 (the
    // first run's would give X30 Y20).
    c.restart(n(40), RestartType::P).unwrap();
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    let target = c.restart_status().unwrap().found.machine;
    assert!(close(&target, &[70.0, 20.0, 0.0]), "{target:?}");

    // After an emergency stop, a Q type restart run is an automatic operation: P type follows.
    let mut c = ran(src);
    c.emergency_stop(true);
    c.emergency_stop(false);
    c.reset();
    c.restart(n(20), RestartType::Q).unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c.restart(n(40), RestartType::P).unwrap();
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert_eq!(c.restart_status().map(|r| r.found.n), Some(Some(40)));
}

#[test]
fn p_type_is_refused_after_the_coordinate_system_was_set_in_mdi() {
    // The program ends in G55 with a G92 shift on X.
    let src = "N10 G90 G55 G00 X10. Y10.\nN20 G92 X0\nN30 G01 X5. F3000.\nN40 M30\n";
    for (text, changed) in [
        ("G92 Y3.", true),
        ("G52 X5.", true),
        ("G92.1 X0", true),
        ("G54", true),
        ("G56", true),
        ("G55", false),
        ("S100 M03\nG04 X0.1\n#500 = 1", false),
    ] {
        let mut c = ran(src);
        mdi(&mut c, text);
        assert!(c.alarms().is_empty(), "{text}: {:?}", c.alarms());
        c.restart(n(30), RestartType::P).unwrap();
        if changed {
            assert_eq!(alarm_code(&c), "PS0094", "{text}");
            assert_eq!(c.alarms()[0].message, "P TYPE NOT ALLOWED (COORD CHG)");
            // As after PS0095–PS0097: P type needs an automatic operation first.
            c.reset();
            c.restart(n(30), RestartType::P).unwrap();
            assert_eq!(alarm_code(&c), "PS0097", "{text}");
        } else {
            assert!(c.alarms().is_empty(), "{text}: {:?}", c.alarms());
        }
    }
}

#[test]
fn p_type_after_the_external_work_offset_changed_is_ps0095() {
    let mut c = ran(PROGRAM);
    c.interpreter_mut().state.offsets.work_mut(0)[0] += 1.0;
    c.offsets_changed();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0095");
    assert_eq!(c.alarms()[0].message, "P TYPE NOT ALLOWED (EXT OFS CHG)");
    // In MDI too (G10 L2 P0: the external offset).
    let mut c = ran(PROGRAM);
    mdi(&mut c, "G10 L2 P0 Z1.");
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0095");
}

#[test]
fn a_search_forgotten_by_a_reset_leaves_none_of_its_modes_to_the_next_program() {
    // The search passes G68 R90 and G91; the reset forgets it; the next program (no G90/G69 of
    // its own) starts in the modes the controller had before the search: absolute, unrotated.
    let searched = "N1 G90 G17 G21 G94\nN2 G68 X0 Y0 R90.\nN3 G91 G01 X10. F600\nN4 X5.\nN5 G69 G90\nN6 M30\n";
    let next = "N1 G01 X30. Y3. F600\nN2 M30\n";
    for forget in ["reset", "emergency stop", "another program", "an alarm in the next search"] {
        let mut c = controller();
        c.select_program(searched).unwrap();
        c.restart(n(4), RestartType::Q).unwrap();
        // In the search's state the restart point is X0 Y10 (X10 rotated 90°).
        assert!(close(&c.restart_status().unwrap().found.machine, &[0.0, 10.0, 0.0]));
        match forget {
            "reset" => c.reset(),
            "emergency stop" => {
                c.emergency_stop(true);
                c.emergency_stop(false);
                c.reset();
            }
            "another program" => {}
            _ => {
                c.restart(n(99), RestartType::Q).unwrap();
                assert_eq!(alarm_code(&c), "PS0071");
                c.reset();
            }
        }
        c.select_program(next).unwrap();
        assert!(c.restart_status().is_none());
        c.cycle_start().unwrap();
        settle(&mut c, 60.0);
        assert!(c.alarms().is_empty(), "{forget}: {:?}", c.alarms());
        assert!(close(&c.point().work[..3], &[30.0, 3.0, 0.0]), "{forget}: {:?}", c.point().work);
    }
}

#[test]
fn a_reset_with_nothing_running_does_not_take_the_changed_offsets_as_the_interruption_s() {
    // The run ends; G54 X changes; an idle reset (or the reset of the PS0096 it gives) must not
    // make the changed offset the interrupted run's.
    let mut c = ran(PROGRAM);
    c.interpreter_mut().state.offsets.work_mut(1)[0] += 5.0;
    c.offsets_changed();
    c.reset();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0096");
    // After the reset of PS0096, P type needs an automatic operation first (FANUC PS0097's
    // "after … P/S alarm 94 to 97 reset").
    c.reset();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0097");
    // A new run with the new offset is the new interruption: P type is allowed again.
    c.reset();
    c.cycle_start().unwrap();
    settle(&mut c, 600.0);
    c.restart(n(100), RestartType::P).unwrap();
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    // A run interrupted by a reset: the offsets at that reset are the baseline, and a later
    // idle reset keeps them.
    let mut c = controller();
    c.select_program(PROGRAM).unwrap();
    c.cycle_start().unwrap();
    while c.point().n != Some(100) {
        c.tick(0.001);
    }
    c.reset();
    settle(&mut c, 10.0);
    c.interpreter_mut().state.offsets.work_mut(2)[1] -= 1.0;
    c.offsets_changed();
    c.reset();
    c.restart(n(100), RestartType::P).unwrap();
    assert_eq!(alarm_code(&c), "PS0096");
}

#[test]
fn a_long_search_runs_over_the_ticks_and_a_reset_stops_it() {
    // 100,000 passes of a loop (three blocks each) before the restart block.
    let src = "N1 G90 G00 X0 Y0\n#500 = 0\nWHILE [#500 LT 100000] DO1\n#500 = #500 + 1\nEND1\n\
        N50 G01 X10. F600.\nN60 M30\n";
    let mut c = controller();
    c.select_program(src).unwrap();
    c.restart(n(50), RestartType::Q).unwrap();
    let r = c.restart_status().expect("a search under way");
    assert_eq!(r.phase, RestartPhase::Searching);
    assert!(r.found.blocks <= SEARCH_BLOCKS_PER_TICK, "one slice at once: {}", r.found.blocks);
    assert_eq!(c.run_state(), RunState::Running);
    // Nothing else starts meanwhile; a feed hold does not stop it.
    assert_eq!(c.set_mode(Mode::Jog), Err(Refusal::Busy));
    assert_eq!(c.restart(n(50), RestartType::Q), Err(Refusal::Busy));
    c.feed_hold();
    c.tick(TICK);
    let r = c.restart_status().unwrap();
    assert_eq!(r.phase, RestartPhase::Searching);
    assert!(r.found.blocks > SEARCH_BLOCKS_PER_TICK && r.found.blocks <= 2 * SEARCH_BLOCKS_PER_TICK);
    // A reset stops it: nothing of it stays, cycle start runs the program from its top.
    c.reset();
    assert!(c.restart_status().is_none());
    assert_eq!(c.run_state(), RunState::Idle);
    // Searched to its end over the ticks: the state is a run's from the top.
    c.restart(n(50), RestartType::Q).unwrap();
    let mut ticks = 0;
    while c.restart_status().is_some_and(|r| r.phase == RestartPhase::Searching) {
        c.tick(TICK);
        ticks += 1;
    }
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    let blocks = c.restart_status().unwrap().found.blocks;
    assert!(blocks > 100_000, "{blocks}");
    assert_eq!(ticks as u64, blocks / SEARCH_BLOCKS_PER_TICK, "{ticks} ticks for {blocks} blocks");
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(c.restart_status().map(|r| (r.phase, r.found.n)), Some((RestartPhase::Searched, Some(50))));
    assert!(c.interpreter().state.common_variables().contains(&(500, 100000.0)));
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(close(&c.point().machine, &[10.0, 0.0, 0.0]), "{:?}", c.point().machine);
}

#[test]
fn the_panel_refuses_a_restart_where_it_cannot_be_made() {
    let mut c = controller();
    assert_eq!(c.restart(n(10), RestartType::Q), Err(Refusal::NoProgram));
    c.select_program(PROGRAM).unwrap();
    c.set_mode(Mode::Jog).unwrap();
    assert_eq!(c.restart(n(10), RestartType::Q), Err(Refusal::WrongMode));
    c.set_mode(Mode::Auto).unwrap();
    c.cycle_start().unwrap();
    c.tick(0.01);
    assert_eq!(c.restart(n(10), RestartType::Q), Err(Refusal::Busy));
    for dialect in [Dialect::Syntec, Dialect::Haas] {
        let mut s = Controller::new(config(dialect));
        s.select_program(PROGRAM).unwrap();
        assert_eq!(s.restart(n(10), RestartType::Q), Err(Refusal::NotInDialect), "{dialect:?}");
    }
}

// --- the property: a restart at block k is a run from the top to block k ------------------------

/// One random block of the generator (its N added by `program`).
fn block() -> impl Strategy<Value = String> {
    let c = || -60.0f64..60.0;
    prop_oneof![
        (c(), c(), -30.0f64..30.0).prop_map(|(x, y, z)| format!("G90 G00 X{x:.3} Y{y:.3} Z{z:.3}")),
        (-20.0f64..20.0, -20.0f64..20.0, 1000.0f64..6000.0)
            .prop_map(|(x, y, f)| format!("G91 G01 X{x:.3} Y{y:.3} F{f:.0}")),
        (-15.0f64..15.0, -15.0f64..15.0, 0.5f64..10.0, any::<bool>()).prop_map(|(x, y, extra, cw)| {
            let r = (x * x + y * y).sqrt() / 2.0 + extra;
            format!("G17 G91 G0{} X{x:.3} Y{y:.3} R{r:.3} F2000.", if cw { 2 } else { 3 })
        }),
        (1u32..3, c(), c(), -10.0f64..10.0).prop_map(|(p, x, y, z)| format!("G10 L2 P{p} X{x:.3} Y{y:.3} Z{z:.3}")),
        prop_oneof![Just("G54"), Just("G55"), Just("G61"), Just("G64"), Just("G90"), Just("G91")]
            .prop_map(str::to_string),
        (100u32..104, -50.0f64..50.0).prop_map(|(v, x)| format!("#{v} = [#{} + {x:.3}]", v + 1)),
        (100u32..104).prop_map(|v| format!("G90 G01 X[#{v} + 1] F3000.")),
        (100.0f64..8000.0, any::<bool>()).prop_map(|(s, cw)| format!("S{s:.0} M0{}", if cw { 3 } else { 4 })),
        (1u32..6).prop_map(|t| format!("G43 H{t} T{t}")),
    ]
}

fn program(blocks: &[String]) -> String {
    let mut src = String::from("N1 G90 G54 G00 X0 Y0 Z0\n");
    for (i, b) in blocks.iter().enumerate() {
        src += &format!("N{} {b}\n", 10 * (i + 1));
    }
    src + "M30\n"
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(24)))]

    /// Q type at block k (from the machine's start point), returned with single block on, leaves
    /// the machine where a run of the blocks before k does, with the same modal state, spindle
    /// and macro variables; the rest of the program then ends where the whole program ends.
    #[test]
    fn a_restart_at_block_k_is_a_run_from_the_top_to_block_k(
        blocks in prop::collection::vec(block(), 2..10),
        pick in any::<prop::sample::Index>(),
    ) {
        let k = 1 + pick.index(blocks.len() - 1);
        let src = program(&blocks);
        let target = 10 * (k as u32 + 1);
        let top = ran_to(&src, target);
        prop_assume!(top.alarms().is_empty());
        let mut c = controller();
        c.select_program(&src).unwrap();
        c.restart(n(target), RestartType::Q).unwrap();
        prop_assert!(c.alarms().is_empty(), "{:?}", c.alarms());
        c.panel.single_block = true;
        c.cycle_start().unwrap();
        settle(&mut c, 600.0);
        prop_assert!(c.restart_status().is_none());
        prop_assert!(close(&c.point().machine, &top.point().machine), "{:?} {:?}", c.point().machine, top.point().machine);
        // The program's current point (the display of a run that ended on a G10 keeps the point
        // of its last motion until the next one: compare the interpreters').
        let (p, q) = (c.interpreter().state.position(), top.interpreter().state.position());
        prop_assert!(close(&p, &q), "{:?} {:?}", p, q);
        prop_assert_eq!(c.modal(), top.modal());
        prop_assert_eq!(c.spindle(), top.spindle());
        prop_assert_eq!(c.interpreter().state.common_variables(), top.interpreter().state.common_variables());
        prop_assert_eq!(c.interpreter().state.offsets.work(2), top.interpreter().state.offsets.work(2));
        let full = ran(&src);
        c.panel.single_block = false;
        c.cycle_start().unwrap();
        settle(&mut c, 600.0);
        prop_assert_eq!(c.alarms(), full.alarms());
        prop_assert!(close(&c.point().machine, &full.point().machine), "{:?} {:?}", c.point().machine, full.point().machine);
    }
}
