//! The operator's switches and counters (`controller/operation.rs`, `docs/dialects.md` "The
//! operator's switches and counters"): dry run feeds cutting moves at the dry run rate with the
//! feed override and leaves rapids alone, changes only at a block boundary; the spindle
//! override scales the speed the controller reports; operating and cutting time count
//! automatic operation and its cutting feeds; the Haas timers #3020–#3025 and switches
//! #3030–#3033 follow them.

use fivex_engine::controller::{Controller, Refusal, RunState};
use fivex_engine::interp::Config;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;
use proptest::prelude::*;

const TICK: f64 = 0.001;

/// mill3 (500 mm/s, 80000 mm/s³) with a dry run rate of `dry_run` mm/min (No.1410).
fn controller(dry_run: f64) -> Controller {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.manual.dry_run_feed = dry_run;
    Controller::new(Config::new(m, Dialect::Fanuc))
}

fn run_to_end(c: &mut Controller) {
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < 120.0 {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Idle, "the program ends");
}

fn start(c: &mut Controller, src: &str) {
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
}

/// A mill3 controller (no dry run rate) that ran `src` to its end after `set` set its panel.
fn ran(src: &str, set: impl FnOnce(&mut Controller)) -> Controller {
    let mut c = controller(0.0);
    set(&mut c);
    start(&mut c, src);
    run_to_end(&mut c);
    c
}

/// The time `src` takes from cycle start, with dry run on or off and feed override `feed`.
fn duration(src: &str, dry_run: bool, feed: f64) -> f64 {
    let mut c = controller(3000.0);
    c.set_dry_run(dry_run).unwrap();
    c.panel.feed_override = feed;
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    run_to_end(&mut c);
    c.time()
}

/// 100 mm from rest to rest at `v` mm/s on mill3: the cruise and the short ramp 2·√(v/J).
fn line_time(v: f64) -> f64 {
    100.0 / v + 2.0 * (v / 80000.0f64).sqrt()
}

#[test]
fn dry_run_feeds_cutting_moves_at_the_dry_run_rate_whatever_f() {
    // F300 (5 mm/s) and F12000 (200 mm/s) both run at No.1410 = 3000 mm/min (50 mm/s).
    for f in ["F300.", "F12000."] {
        let src = format!("G90 G01 X100. {f}\nM30\n");
        assert!((duration(&src, true, 1.0) - line_time(50.0)).abs() <= TICK, "{f}");
    }
    // Without dry run F300 is F300.
    assert!((duration("G90 G01 X100. F300.\nM30\n", false, 1.0) - line_time(5.0)).abs() <= TICK);
    // G95 (per revolution) and G93 (inverse time) feeds too.
    let per_rev = duration("G90 G95 S1000 M03\nG01 X100. F0.01\nM30\n", true, 1.0);
    assert!((per_rev - line_time(50.0)).abs() <= TICK, "{per_rev}");
    // G95 with the spindle stopped waits for ever without dry run (FX0009); with it, it feeds.
    let stopped = duration("G90 G95\nG01 X100. F0.01\nM30\n", true, 1.0);
    assert!((stopped - line_time(50.0)).abs() <= TICK, "{stopped}");
}

#[test]
fn dry_run_takes_the_feed_override_and_leaves_rapids_alone() {
    let half = duration("G90 G01 X100. F300.\nM30\n", true, 0.5);
    assert!((half - line_time(25.0)).abs() <= TICK, "{half}");
    let rapid = "G90 G00 X100.\nM30\n";
    assert_eq!(duration(rapid, true, 1.0), duration(rapid, false, 1.0));
}

#[test]
fn without_a_dry_run_rate_the_jog_feed_is_used() {
    let c = ran("G90 G01 X100. F9000.\nM30\n", |c| {
        c.panel.jog_feed = 1500.0;
        c.set_dry_run(true).unwrap();
    });
    assert!((c.time() - line_time(25.0)).abs() <= TICK);
}

#[test]
fn dry_run_changes_only_at_a_block_boundary() {
    let mut c = controller(3000.0);
    c.panel.single_block = true;
    c.select_program("G90 G01 X10. F600.\nG01 X110.\nM30\n").unwrap();
    c.cycle_start().unwrap();
    c.tick(0.1);
    assert_eq!(c.set_dry_run(true), Err(Refusal::Busy), "not while the axes move");
    c.feed_hold();
    c.tick(0.5);
    assert_eq!(c.run_state(), RunState::Hold);
    assert_eq!(c.set_dry_run(true), Err(Refusal::Busy), "not while held with the path queued");
    assert!(!c.panel.dry_run);
    c.cycle_start().unwrap();
    run_to_end(&mut c);
    // At the single-block stop after the first block: the second block runs at the dry run rate.
    assert_eq!(c.point().line, 1);
    c.set_dry_run(true).unwrap();
    let t0 = c.time();
    c.cycle_start().unwrap();
    run_to_end(&mut c);
    assert!((c.time() - t0 - line_time(50.0)).abs() <= TICK, "{}", c.time() - t0);
}

#[test]
fn the_spindle_override_scales_the_speed_reported() {
    let mut c = ran("S1000 M04\nM30\n", |_| {});
    assert_eq!(c.spindle(), -1000.0);
    c.set_spindle_override(0.5);
    assert_eq!((c.spindle(), c.spindle_commanded()), (-500.0, -1000.0));
    c.set_spindle_override(1.2);
    assert!((c.spindle() + 1200.0).abs() < 1e-9);
    // Outside the panel's range it is clamped; a non-number changes nothing.
    c.set_spindle_override(3.0);
    assert!((c.spindle() + 1200.0).abs() < 1e-9);
    c.set_spindle_override(f64::NAN);
    assert_eq!(c.panel.spindle_override, 1.2);
}

#[test]
fn operating_time_counts_automatic_operation_and_cutting_time_its_feeds() {
    let cut = "G90 G01 X100. F3000.\nM30\n";
    let c = ran(cut, |_| {});
    let t = c.times();
    assert!((t.operating_s - line_time(50.0)).abs() <= 2.0 * TICK, "{t:?}");
    assert!((t.cutting_s - line_time(50.0)).abs() <= 2.0 * TICK, "{t:?}");

    // Rapids and a dwell are operating time, not cutting time; a hold is neither.
    let mut c = controller(0.0);
    c.select_program("G90 G00 X100.\nG04 X0.5\nM30\n").unwrap();
    c.cycle_start().unwrap();
    c.tick(0.05);
    c.feed_hold();
    for _ in 0..1000 {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Hold);
    let held = c.times();
    c.tick(1.0);
    assert_eq!(c.times(), held, "nothing counts while held");
    c.cycle_start().unwrap();
    run_to_end(&mut c);
    let t = c.times();
    assert_eq!(t.cutting_s, 0.0);
    assert!(t.operating_s >= 0.5 && t.operating_s < c.time() - 1.0, "{t:?} of {}", c.time());
    // Idle and manual modes count nothing.
    c.tick(1.0);
    assert_eq!(c.times(), t);
}

/// #3901 counts a part when the machine reaches M30, not when the reading (which runs ahead of
/// the machine) reads it; a reset before M30 counts none.
#[test]
fn a_part_is_counted_when_the_machine_reaches_m30() {
    let src = "G90 G01 X100. F3000.\nM30\n";
    let mut c = controller(0.0);
    start(&mut c, src);
    let mut read_ahead = false;
    while c.run_state() == RunState::Running && c.time() < 10.0 {
        c.tick(TICK);
        if c.point().line == 1 {
            read_ahead |= c.interpreter().state.current_block().0 == 2;
            assert_eq!(c.interpreter().state.part_count().0, 0.0, "counted while X100. still moves");
        }
    }
    assert!(read_ahead, "M30 was never read while the move ran: the test proves nothing");
    assert_eq!(c.interpreter().state.part_count().0, 1.0);

    // Reset during the move: no part.
    let mut c = controller(0.0);
    start(&mut c, src);
    c.tick(0.2);
    c.reset();
    assert_eq!(c.interpreter().state.part_count().0, 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Whatever the program's feed, cutting time never exceeds operating time, which never
    /// exceeds the time that passed.
    #[test]
    fn counters_stay_ordered(f in 600.0f64..20000.0, x in 1.0f64..60.0, dwell in 0.0f64..0.3, ticks in 1usize..40) {
        let mut c = controller(0.0);
        let src = format!("G90 G00 X{x:.3}\nG01 X0. F{f:.1}\nG04 X{dwell:.3}\nG01 Y{x:.3}\nM30\n");
        c.select_program(&src).unwrap();
        c.cycle_start().unwrap();
        let step = ticks as f64 * TICK;
        while c.run_state() == RunState::Running && c.time() < 60.0 {
            c.tick(step);
            let t = c.times();
            prop_assert!(t.cutting_s <= t.operating_s + 1e-12);
            prop_assert!(t.operating_s <= c.time() + 1e-9);
        }
        prop_assert!(c.times().cutting_s > 0.0);
    }
}

#[test]
fn machine_lock_runs_the_program_without_moving_the_machine() {
    let src = "G90 G01 X100. Y20. F3000.\nM30\n";
    let free = ran(src, |_| {});

    let mut c = controller(0.0);
    c.set_machine_lock(true).unwrap();
    start(&mut c, src);
    c.tick(0.5);
    assert_eq!(c.set_machine_lock(false), Err(Refusal::Busy), "not while the program moves");
    let (p, s) = (c.point(), c.sample());
    assert!(p.work[0] > 10.0 && p.work[0] < 90.0, "the position shown advances: {:?}", p.work);
    assert_eq!(&p.machine[..3], &[0.0; 3], "the machine stays");
    assert_eq!(&s.machine[..3], &[0.0; 3]);
    assert_eq!(s.tip, [0.0; 3], "the tip is where the machine is");
    run_to_end(&mut c);
    // The program took its time; it ended where it ends unlocked.
    assert!((c.time() - free.time()).abs() < 1e-9);
    assert_eq!(&c.point().work[..2], &[100.0, 20.0]);
    assert_eq!(&c.point().line, &free.point().line);
    assert_eq!(&c.lock_offset()[..2], &[-100.0, -20.0]);
}

/// `#5021…` read where the machine is, as the status's machine position: under machine lock
/// the axes stand still while `#5041…` follow the program (they read the program's machine
/// coordinates, 100 mm off here).
#[test]
fn machine_position_variables_read_the_locked_axes_where_they_stand() {
    let src = "G90 G01 X100. Y20. F3000.\n#100=#5021\n#101=#5022\n#102=#5041\nM30\n";
    let c = ran(src, |c| c.set_machine_lock(true).unwrap());
    let vars: Vec<_> = c.interpreter().state.common_variables();
    assert_eq!(vars, [(100, 0.0), (101, 0.0), (102, 100.0)]);
    assert_eq!(&c.point().machine[..2], &[0.0, 0.0]);
}

#[test]
fn after_machine_lock_the_positions_disagree_until_the_reference_return() {
    let mut c = ran("G90 G01 X100. F3000.\nM30\n", |c| c.set_machine_lock(true).unwrap());
    c.set_machine_lock(false).unwrap();
    assert_eq!((c.point().machine[0], c.point().work[0]), (0.0, 100.0));
    // An incremental move moves the machine by its increment from where it stands.
    start(&mut c, "G91 G01 X10. F3000.\nM30\n");
    run_to_end(&mut c);
    let p = c.point();
    assert!((p.machine[0] - 10.0).abs() < 1e-9 && (p.work[0] - 110.0).abs() < 1e-9, "{p:?}");
    // The reference return sets them equal again.
    c.set_mode(fivex_engine::controller::Mode::Ref).unwrap();
    c.reference_return().unwrap();
    run_to_end(&mut c);
    let p = c.point();
    assert_eq!((p.machine[0], p.work[0]), (0.0, 0.0));
    assert_eq!(c.lock_offset(), [0.0; fivex_engine::machine::MAX_AXES]);
}

/// G27 checks the real axes: after a locked run the machine stands at X0 where the program
/// reads X100, so `G27 X100.` finds the reference position and `G27 X0` does not; under machine
/// lock it checks nothing (FANUC: no check while the machine is locked).
#[test]
fn g27_checks_where_the_axes_really_are() {
    // Runs `src` on `c` to its end or alarm: the alarm's code.
    let alarm_after = |c: &mut Controller, src: &str| {
        start(c, src);
        while c.run_state() == RunState::Running && c.time() < 120.0 {
            c.tick(TICK);
        }
        c.alarms().first().map(|a| a.code.clone())
    };
    let after_lock = || {
        let mut c = ran("G90 G01 X100. F3000.\nM30\n", |c| c.set_machine_lock(true).unwrap());
        c.set_machine_lock(false).unwrap();
        c
    };
    let mut c = after_lock();
    assert_eq!(alarm_after(&mut c, "G90 G27 X100.\nM30\n"), None);
    assert_eq!((c.run_state(), c.point().machine[0]), (RunState::Idle, 0.0));
    let mut c = after_lock();
    assert_eq!(alarm_after(&mut c, "G90 G27 X0\nM30\n").as_deref(), Some("PS0092"));
    let mut c = controller(0.0);
    c.set_machine_lock(true).unwrap();
    assert_eq!(alarm_after(&mut c, "G90 G27 X50.\nM30\n"), None, "machine lock: no check");
    assert_eq!(c.run_state(), RunState::Idle);
}

#[test]
fn z_axis_neglect_locks_z_alone() {
    let mut c = ran("G90 G01 X50. Z-20. F3000.\nM30\n", |c| c.set_z_neglect(true).unwrap());
    let (p, s) = (c.point(), c.sample());
    assert!((p.machine[0] - 50.0).abs() < 1e-9 && p.machine[2] == 0.0, "{p:?}");
    assert_eq!(p.work[2], -20.0);
    assert_eq!(s.tip[2], 0.0, "the tip stays at the machine's Z");
    c.set_z_neglect(false).unwrap();
    assert_eq!(c.lock_offset()[2], 20.0);
    assert_eq!(c.lock_offset()[0], 0.0);
    // Syntec: no such switch in its manual.
    let mut syntec = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Syntec));
    assert_eq!(syntec.set_z_neglect(true), Err(Refusal::NoAxis));
    assert!(!syntec.panel.z_neglect);
}

#[test]
fn auxiliary_function_lock_skips_the_spindle_and_the_tool_change_not_the_program_end() {
    let src = "S1000 M03\nT2 M06\nG04 X0.1\nM30\n";
    let free = ran(src, |_| {});
    let c = ran(src, |c| c.panel.aux_lock = true);
    assert_eq!((free.spindle(), c.spindle()), (1000.0, 0.0));
    // Without the tool change's time; the dwell (a G function) and M30 are carried out.
    assert!(free.time() > c.time() && (c.time() - 0.1).abs() <= 2.0 * TICK, "{} {}", free.time(), c.time());
    assert_eq!(c.point().line, free.point().line);
    // M00 still stops.
    let mut c = controller(0.0);
    c.panel.aux_lock = true;
    start(&mut c, "M00\nG01 X1. F100.\nM30\n");
    c.tick(0.01);
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(c.point().machine[0], 0.0);
}

/// Haas #3020–#3025 on a controller: the cycle start and feed timers count what the operating
/// and cutting time count; the part timers move on at each M30 the machine reaches
/// (`docs/dialects.md`, "Haas: the dialect's core").
#[test]
fn haas_timers_follow_the_operating_time_and_the_parts() {
    use fivex_engine::interp::expr::Variables;
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Haas));
    let read = |c: &Controller, n: u32| Variables::read(&c.interpreter().state, n).unwrap().unwrap();
    // Idle time before the first cycle start: power on counts it, the cycle start timer not.
    c.tick(0.5);
    start(&mut c, "G90 G01 X100. F3000.\nG04 P1.\nM30\n");
    run_to_end(&mut c);
    let first = c.times();
    assert!((first.operating_s - (line_time(50.0) + 1.0)).abs() <= 2.0 * TICK, "{first:?}");
    assert!((read(&c, 3020) - c.time()).abs() < 1e-9);
    assert!((read(&c, 3021) - first.operating_s).abs() < 1e-9);
    assert!((read(&c, 3022) - first.cutting_s).abs() < 1e-9);
    assert!((read(&c, 3024) - first.operating_s).abs() < 1e-9, "the part just completed");
    assert_eq!(read(&c, 3023), 0.0);
    assert_eq!(read(&c, 3025), 0.0);

    // A second part (a 2 s dwell): the first part's time moves to #3025.
    c.tick(0.3);
    start(&mut c, "G04 P2.\nM30\n");
    run_to_end(&mut c);
    let second = c.times().operating_s - first.operating_s;
    assert!((second - 2.0).abs() <= 2.0 * TICK, "{second}");
    assert!((read(&c, 3024) - second).abs() < 1e-9);
    assert!((read(&c, 3025) - first.operating_s).abs() < 1e-9);
    assert!((read(&c, 3022) - first.cutting_s).abs() < 1e-9, "a dwell is no feed");

    // The counters kept through a restart: #3021/#3022 go on from them.
    c.load_times(fivex_engine::controller::Times { operating_s: 100.0, cutting_s: 40.0 });
    assert_eq!((read(&c, 3021), read(&c, 3022)), (100.0, 40.0));
    assert_eq!(read(&c, 3023), 0.0, "the present part keeps its time");
}

/// Haas #3030/#3031 read the panel's single block and dry run switches as the program is read.
#[test]
fn haas_3030_3031_read_the_panel() {
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Haas));
    c.panel.single_block = true;
    c.set_dry_run(true).unwrap();
    start(&mut c, "#100=#3030\n#101=#3031\n#102=#3032\nM30\n");
    for _ in 0..100 {
        if c.run_state() == RunState::Idle {
            break;
        }
        if c.run_state() != RunState::Running {
            c.cycle_start().unwrap();
        }
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Idle);
    let vars: Vec<_> = c.interpreter().state.common_variables();
    assert_eq!(vars, vec![(100, 1.0), (101, 1.0), (102, 0.0)]);
}

/// Haas #3022 in `fivex run` (the planned profile's time along the segments that are no rapid)
/// agrees with the controller's cutting time (counted tick by tick from the segment under way)
/// on a program that mixes feeds and rapids: two independent counts of the same motion.
#[test]
fn haas_feed_timer_of_a_run_agrees_with_the_controller() {
    use fivex_engine::interp::expr::Variables;
    use fivex_engine::run::{run, RunOptions};
    let src = "G90 G01 X20. F3000.\nG00 X60.\nG01 X80. Y10.\nG00 Y30.\nG01 X0 Y0 F6000.\nG04 P0\n#100=#3022\nM30\n";
    let mut interp = fivex_engine::interp::Interpreter::new(
        fivex_engine::lang::parse_file(src),
        Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Haas),
    );
    assert!(run(&mut interp, &RunOptions::default(), |_| {}).completed());
    let feed = Variables::read(&interp.state, 100).unwrap().unwrap();
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Haas));
    start(&mut c, src);
    run_to_end(&mut c);
    let t = c.times();
    assert!(feed > 0.0 && feed < t.operating_s - 0.1, "{feed} of {t:?}");
    // Each of the five changes between feed and rapid may fall inside a tick.
    assert!((feed - t.cutting_s).abs() <= 5.0 * TICK, "run {feed}, controller {t:?}");
}

/// The workpiece (`crate::workpiece`) changes at a block boundary only, like machine lock: the
/// skip move read after the change probes the new boxes, and while a move is under way the
/// change is refused and the boxes stay.
#[test]
fn the_workpiece_changes_at_a_block_boundary_and_the_next_skip_probes_it() {
    use fivex_engine::workpiece::{Cuboid, Workpiece};
    use std::sync::Arc;
    let block = Arc::new(Workpiece { boxes: vec![Cuboid { min: [0.0, 0.0, -20.0], max: [50.0, 40.0, 0.0] }] });
    // G43 H1: the tip is 100 below the spindle nose (the defaults of a new controller have no
    // length: set one), so on mill3 G54 = 0 the table frame is the workpiece system.
    let probe = "G90 G21 G54 G00 G43 H1 Z10.\nX25. Y20.\nG31 Z-10. F100.\n#100=#5063\nM30\n";
    let mut c = controller(0.0);
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 100.0;
    assert!(c.workpiece().is_empty(), "nothing on the table at first");
    start(&mut c, probe);
    run_to_end(&mut c);
    let var100 =
        |c: &Controller| c.interpreter().state.common_variables().into_iter().find(|v| v.0 == 100).map(|v| v.1);
    assert_eq!(var100(&c), Some(-10.0), "without boxes the skip runs its whole move");

    c.set_workpiece(block.clone()).unwrap();
    assert_eq!(c.workpiece(), &block);
    start(&mut c, probe);
    run_to_end(&mut c);
    let top = var100(&c).unwrap();
    assert!(top.abs() < 1e-9, "the skip stops on the top of the box: {top}");

    // Refused while the axes move: the boxes stay.
    start(&mut c, "G90 G01 X100. F3000.\nM30\n");
    c.tick(0.2);
    assert_eq!(c.set_workpiece(Arc::default()), Err(Refusal::Busy));
    assert_eq!(c.workpiece(), &block);
    run_to_end(&mut c);
    // A workpiece `check` refuses is a bad value, whatever the state.
    let flat = Workpiece { boxes: vec![Cuboid { min: [0.0; 3], max: [1.0, 1.0, 0.0] }] };
    assert_eq!(c.set_workpiece(Arc::new(flat)), Err(Refusal::BadValue));
    c.set_workpiece(Arc::default()).unwrap();
    assert!(c.workpiece().is_empty());
}
