//! The controller state machine (`fivex_engine::controller`) driven by ticks: it moves exactly as
//! `run::run` does, and the panel's actions (feed hold, reset, single block, M00/M01, emergency
//! stop, overrides, JOG/HANDLE/REF) do what a FANUC panel does, decelerating within the limits.

use fivex_engine::controller::{Controller, Mode, Refusal, RunState};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect;

const TICK: f64 = 0.001;

fn controller() -> Controller {
    Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc))
}

/// A mill3 controller running `src` in AUTO.
fn started(src: &str) -> Controller {
    let mut c = controller();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    c
}

/// `n` ticks, X/Y/Z after each appended to `xs`.
fn record(c: &mut Controller, n: usize, xs: &mut Vec<[f64; 3]>) {
    for _ in 0..n {
        c.tick(TICK);
        let m = c.point().machine;
        xs.push([m[0], m[1], m[2]]);
    }
}

/// Tick until the controller is no longer running (or `limit` seconds), recording X, Y, Z.
fn run_until_stopped(c: &mut Controller, limit: f64) -> Vec<[f64; 3]> {
    let mut xs = Vec::new();
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < limit {
        c.tick(TICK);
        let m = c.point().machine;
        xs.push([m[0], m[1], m[2]]);
    }
    xs
}

/// Finite differences within mill3's limits (500 mm/s, 4000 mm/s², 80000 mm/s³).
fn assert_within_limits(xs: &[[f64; 3]]) {
    assert_within_limits_by_block(xs, &[]);
}

/// The same; where `lines` (one per sample) changes within a window, a junction: a line meeting
/// an arc may change an axis's acceleration at once by its jerk × 1 ms (`docs/motion.md`), so
/// the jerk is not checked there.
fn assert_within_limits_by_block(xs: &[[f64; 3]], lines: &[u32]) {
    for (k, w) in xs.windows(4).enumerate() {
        let junction = lines.get(k..k + 4).is_some_and(|l| l.iter().any(|x| *x != l[0]));
        for axis in 0..3 {
            let x: Vec<f64> = w.iter().map(|p| p[axis]).collect();
            let v = (x[1] - x[0]) / TICK;
            let a = (x[2] - 2.0 * x[1] + x[0]) / (TICK * TICK);
            let j = (x[3] - 3.0 * x[2] + 3.0 * x[1] - x[0]) / TICK.powi(3);
            assert!(v.abs() <= 500.0 * (1.0 + 1e-6), "speed {v}");
            assert!(a.abs() <= 4000.0 * (1.0 + 1e-6) + 1e-3, "acceleration {a}");
            assert!(junction || j.abs() <= 80000.0 * (1.0 + 1e-6) + 1.0, "jerk {j} at {w:?}");
        }
    }
}

#[test]
fn ticks_move_the_machine_exactly_as_run_does() {
    let src = "G90 G00 X50. Y20.\nG01 X100. F3000.\nG03 X120. Y40. R20.\nG04 X0.2\nG01 Y-10. Z-5.\nM30\n";
    let mut interp =
        Interpreter::new(parse_file(src), Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc));
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions { period_s: TICK, ..RunOptions::default() }, |s| samples.push(*s));
    let mut c = controller();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    let mut k = 1;
    while c.run_state() == RunState::Running {
        c.tick(TICK);
        if let Some(s) = samples.get(k) {
            for i in 0..3 {
                assert!((c.point().machine[i] - s.machine[i]).abs() < 1e-9, "t={} axis {i}", s.t);
            }
        }
        k += 1;
    }
    assert_eq!(c.point().machine[..3], r.machine[..3]);
    assert!((c.time() - r.cycle_time_s).abs() <= TICK, "{} vs {}", c.time(), r.cycle_time_s);
}

#[test]
fn feed_hold_decelerates_within_limits_and_cycle_start_finishes_the_path() {
    let mut c = started("G90 G01 X300. Y100. F12000.\nM30\n");
    let mut xs = Vec::new();
    record(&mut c, 500, &mut xs);
    c.feed_hold();
    assert_eq!(c.run_state(), RunState::Hold);
    record(&mut c, 400, &mut xs);
    let held = c.point().machine;
    assert_eq!(c.point().feed, 0.0);
    c.tick(1.0);
    assert_eq!(c.point().machine, held, "held means still");
    assert!(held[0] > 0.0 && held[0] < 300.0);
    c.cycle_start().unwrap();
    xs.extend(run_until_stopped(&mut c, 60.0));
    assert_within_limits(&xs);
    assert_eq!(c.run_state(), RunState::Idle);
    // On the line from (0, 0) to (300, 100) all along, and at its end.
    for p in &xs {
        assert!((p[0] / 3.0 - p[1]).abs() < 1e-6, "off the line: {p:?}");
    }
    assert_eq!(c.point().machine[..2], [300.0, 100.0]);
}

#[test]
fn reset_stops_the_program_and_cycle_start_runs_it_again_from_the_top() {
    let mut c = started("G91 G01 X100. F6000.\nX100.\nM30\n");
    c.tick(0.5);
    c.reset();
    // Moving at 100 mm/s, the axes take a while to stand: not idle meanwhile.
    assert_eq!(c.run_state(), RunState::Running, "the axes still decelerate");
    c.tick(0.5);
    assert_eq!(c.run_state(), RunState::Idle);
    let stopped = c.point().machine[0];
    assert!(stopped > 0.0 && stopped < 100.0, "{stopped}");
    c.tick(1.0);
    assert_eq!(c.point().machine[0], stopped);
    // From the top: two incremental moves of 100 from where it stopped.
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 60.0);
    assert!((c.point().machine[0] - (stopped + 200.0)).abs() < 1e-9);
}

/// A reset during a feed hold's deceleration: held until the axes stand, then idle.
#[test]
fn a_reset_while_holding_is_idle_once_the_axes_stand() {
    let mut c = started("G91 G01 X100. F6000.\nM30\n");
    c.tick(0.5);
    c.feed_hold();
    c.tick(0.01);
    c.reset();
    assert_eq!(c.run_state(), RunState::Hold, "the axes still decelerate");
    c.tick(1.0);
    assert_eq!(c.run_state(), RunState::Idle);
    let stopped = c.point().machine[0];
    c.tick(1.0);
    assert_eq!(c.point().machine[0], stopped);
}

#[test]
fn single_block_and_program_stops_wait_for_cycle_start() {
    let mut c = controller();
    c.panel.single_block = true;
    c.select_program("G90 G01 X10. F6000.\nX20.\nX30.\nM30\n").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[0], 10.0);
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[0], 20.0);
    c.panel.single_block = false;
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[0], 30.0);

    // M00 stops; M01 only with the optional stop switch on.
    let prog = "G90 G01 X10. F6000.\nM00\nX20.\nM01\nX30.\nM30\n";
    for (optional, stops) in [(false, vec![10.0, 30.0]), (true, vec![10.0, 20.0, 30.0])] {
        let mut c = controller();
        c.panel.optional_stop = optional;
        c.select_program(prog).unwrap();
        c.cycle_start().unwrap();
        let mut at = Vec::new();
        for _ in 0..5 {
            run_until_stopped(&mut c, 10.0);
            at.push(c.point().machine[0]);
            if c.cycle_start().is_err() || at.last() == Some(&30.0) {
                break;
            }
        }
        assert_eq!(at, stops, "optional stop {optional}");
    }
}

/// G88 (boring, manual retraction): after the dwell at the bottom the spindle stops and the
/// machine holds there; the operator jogs the tool out and cycle start goes on with the return
/// to the initial level (G98) and the spindle forward. It rapided out of the hole on its own.
#[test]
fn g88_holds_at_the_hole_bottom_for_the_manual_retraction() {
    use fivex_engine::controller::ProgramStop;
    let prog = "G90 G00 X0 Y0 Z50.\nS800 M03\nG98 G88 X10. Z-10. R2. P500 F600\nG80\nM30\n";
    let mut c = started(prog);
    run_until_stopped(&mut c, 30.0);
    assert_eq!((c.run_state(), c.program_stop()), (RunState::Idle, Some(ProgramStop::Stop)));
    assert_eq!((c.point().machine[0], c.point().machine[2], c.spindle()), (10.0, -10.0, 0.0));
    c.set_mode(Mode::Handle).unwrap();
    c.handle('Z', 30.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[2], 20.0, "jogged out of the hole");
    c.set_mode(Mode::Auto).unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 30.0);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert_eq!((c.run_state(), c.point().machine[2], c.spindle()), (RunState::Idle, 50.0, 800.0));
}

/// The optional stop switch acts where the machine reaches M01, and the block delete switch on
/// the blocks read after it is flipped, as the panel shows them: both were taken at cycle start
/// only, so an M01 the machine had not reached passed with the switch shown on, and a `/` block
/// ran with block delete shown on.
#[test]
fn the_optional_stop_and_block_delete_switches_act_when_flipped_under_way() {
    let prog = "G90 G01 X100. F600.\nM01\nX20.\nM01\nX30.\nM30\n";
    let mut c = started(prog);
    for _ in 0..10 {
        c.tick(TICK);
    }
    assert!(c.point().machine[0] < 100.0, "still in the first block");
    c.panel.optional_stop = true;
    run_until_stopped(&mut c, 30.0);
    assert_eq!((c.run_state(), c.point().machine[0]), (RunState::Idle, 100.0), "stops at the first M01");
    c.panel.optional_stop = false;
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 30.0);
    assert_eq!(c.point().machine[0], 30.0, "the second M01 passes with the switch off");
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());

    // Block delete switched on while the first block moves: the `/` block the interpreter reads
    // later is skipped (a 1000-block run keeps the `/` block out of the read-ahead's reach).
    let moves: String = (1..=1000).map(|i| format!("Y{}.\n", i % 2)).collect();
    let prog = format!("G90 G01 X100. F600.\n{moves}/X50.\nM30\n");
    let mut c = started(&prog);
    c.tick(TICK);
    c.panel.block_delete = true;
    run_until_stopped(&mut c, 3000.0);
    assert_eq!((c.run_state(), c.point().machine[0]), (RunState::Idle, 100.0), "the / block skipped");
}

#[test]
fn a_jog_after_a_program_that_ended_on_m00_ends_idle() {
    // The program's last block stops at M00 (alone, or with M30) and nothing follows: the
    // program is over, and a JOG afterwards ends idle like any other.
    for src in ["G90 G01 X10. F6000.\nM00\n", "G90 G01 X10. F6000.\nM00 M30\n"] {
        let mut c = started(src);
        run_until_stopped(&mut c, 10.0);
        assert_eq!(c.run_state(), RunState::Idle, "{src}");
        c.set_mode(Mode::Jog).unwrap();
        c.panel.jog_feed = 6000.0;
        c.jog_start('Y', true).unwrap();
        run_until_stopped(&mut c, 0.5);
        c.jog_stop();
        run_until_stopped(&mut c, 5.0);
        assert_eq!(c.run_state(), RunState::Idle, "{src}");
        assert!(c.point().machine[1] > 10.0, "{src}: {:?}", c.point().machine);
    }
}

/// `at_rest`: nothing under way a restart would cut short (the service moves only such a
/// controller to another node).
#[test]
fn at_rest_only_when_no_program_motion_alarm_or_stop_is_under_way() {
    let mut c = controller();
    assert!(c.at_rest(), "a new controller");
    // A program under way, held, at a single-block stop: not at rest; over: at rest.
    c.panel.single_block = true;
    c.select_program("G90 G01 X10. F6000.\nX20.\nM30\n").unwrap();
    c.cycle_start().unwrap();
    c.tick(0.01);
    assert!(!c.at_rest(), "running");
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[0], 10.0);
    assert!(!c.at_rest(), "at a single-block stop ({:?})", c.run_state());
    c.panel.single_block = false;
    c.cycle_start().unwrap();
    c.tick(0.01);
    c.feed_hold();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.run_state(), RunState::Hold);
    assert!(!c.at_rest(), "held");
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[0], 20.0);
    assert!(c.at_rest(), "the program is over ({:?})", c.run_state());
    // A jog while it moves, and its deceleration: not at rest.
    c.set_mode(Mode::Jog).unwrap();
    c.panel.jog_feed = 6000.0;
    c.jog_start('Y', true).unwrap();
    c.tick(0.1);
    assert!(!c.at_rest(), "jogging");
    c.jog_stop();
    c.tick(0.001);
    for _ in 0..10_000 {
        if c.at_rest() {
            break;
        }
        c.tick(0.001);
    }
    assert!(c.at_rest(), "the jog stopped and the axes stand");
    // The emergency stop and an alarm: not at rest until reset.
    c.emergency_stop(true);
    assert!(!c.at_rest(), "emergency stop");
    c.emergency_stop(false);
    assert!(!c.at_rest(), "its alarm");
    c.reset();
    assert!(c.at_rest(), "reset");
    // Reset in the middle of a program: at rest once the axes stand.
    let mut c = started("G90 G01 X100. F600.\nM30\n");
    c.tick(0.2);
    c.reset();
    run_until_stopped(&mut c, 10.0);
    for _ in 0..10_000 {
        if c.run_state() == RunState::Idle {
            break;
        }
        c.tick(0.001);
    }
    assert!(c.at_rest(), "reset and standing ({:?})", c.run_state());
}

#[test]
fn emergency_stop_halts_at_once_and_only_reset_clears_it() {
    let mut c = started("G90 G01 X100. F6000.\nM30\n");
    c.tick(0.3);
    let at = c.point().machine[0];
    c.emergency_stop(true);
    c.tick(0.5);
    assert_eq!(c.point().machine[0], at);
    assert_eq!(c.run_state(), RunState::Alarm);
    assert_eq!(c.alarms()[0].code, "FX0004");
    assert_eq!(c.cycle_start(), Err(Refusal::Busy));
    c.reset();
    assert_eq!(c.run_state(), RunState::Alarm, "still pressed");
    c.emergency_stop(false);
    c.reset();
    assert_eq!((c.run_state(), c.alarms().len()), (RunState::Idle, 0));
}

#[test]
fn feed_override_scales_the_programmed_feed() {
    let time = |override_: f64| {
        let mut c = controller();
        c.panel.feed_override = override_;
        c.select_program("G90 G01 X100. F3000.\nM30\n").unwrap();
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 60.0);
        c.time()
    };
    // 100 mm at 50 and 25 mm/s, each with the short ramp 2·√(v/J).
    let expect = |v: f64| 100.0 / v + 2.0 * (v / 80000.0f64).sqrt();
    assert!((time(1.0) - expect(50.0)).abs() <= TICK);
    assert!((time(0.5) - expect(25.0)).abs() <= TICK);
}

#[test]
fn an_override_change_acts_on_the_motion_under_way_within_limits() {
    let mut c = started("G90 G01 X400. F3000.\nM30\n");
    let mut xs = Vec::new();
    let mut feeds = Vec::new();
    let mut step = |c: &mut Controller, n: usize| {
        for _ in 0..n {
            c.tick(TICK);
            let m = c.point().machine;
            xs.push([m[0], m[1], m[2]]);
            feeds.push(c.point().feed);
        }
    };
    step(&mut c, 1000);
    assert!((c.point().feed - 3000.0).abs() < 1e-6);
    c.set_overrides(0.5, 1.0);
    step(&mut c, 1000);
    assert!((c.point().feed - 1500.0).abs() < 1e-6, "{}", c.point().feed);
    c.set_overrides(1.5, 1.0);
    step(&mut c, 1000);
    assert!((c.point().feed - 4500.0).abs() < 1e-6, "{}", c.point().feed);
    xs.extend(run_until_stopped(&mut c, 60.0));
    assert_within_limits(&xs);
    assert_eq!(c.point().machine[0], 400.0);
    assert!(feeds.iter().all(|f| *f <= 4500.0 + 1e-6));
}

#[test]
fn feed_hold_in_a_non_linear_rapid_ends_the_block_first() {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.motion.nonlinear_rapid = true;
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    c.select_program("G90 G00 X100. Y10.\nG01 X0. F3000.\nM30\n").unwrap();
    c.cycle_start().unwrap();
    c.tick(0.1);
    c.feed_hold();
    assert_eq!(c.run_state(), RunState::Hold);
    c.tick(2.0);
    assert_eq!(c.point().machine[..2], [100.0, 10.0], "the rapid's axes finished their own profiles");
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[..2], [0.0, 10.0]);
}

#[test]
fn five_axis_manual_feeds_move_along_the_tool_axis_and_its_right_angles() {
    use fivex_engine::kin::ManualFeed;
    let mut c = Controller::new(Config::new(MachineConfig::preset("head-bc").unwrap(), Dialect::Fanuc));
    // B30: the tool leans toward +X (TV-MAN-04: T = (0.5, 0, 0.866)).
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("G90 G00 X0. Y0. Z0. B30. C0.").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 10.0);
    c.set_mode(Mode::Handle).unwrap();
    c.handle_direction(ManualFeed::ToolAxis, 10.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    let m = c.point().machine;
    assert!((m[0] - 5.0).abs() < 1e-9 && m[1].abs() < 1e-9 && (m[2] - 8.660254).abs() < 1e-6, "{m:?}");
    c.handle_direction(ManualFeed::RightAngle1, -2.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    let m = c.point().machine;
    assert!((m[0] - (5.0 - 2.0 * 0.866025)).abs() < 1e-6 && (m[2] - (8.660254 + 1.0)).abs() < 1e-6, "{m:?}");
    // Longitude about the vertical Z (FLL = 1): R1 = Z × T = +Y here.
    c.manual_options_mut().latitude_longitude = true;
    c.manual_options_mut().vertical = fivex_engine::machine::ManualVertical::Z;
    let before = c.point().machine;
    c.handle_direction(ManualFeed::RightAngle1, 3.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    let m = c.point().machine;
    assert!((m[1] - (before[1] + 3.0)).abs() < 1e-9 && (m[0] - before[0]).abs() < 1e-9, "{m:?}");
    c.manual_options_mut().latitude_longitude = false;
    // JOG along the tool axis stops at the first stroke it meets (Z at +300).
    c.set_mode(Mode::Jog).unwrap();
    c.jog_direction(ManualFeed::ToolAxis, true).unwrap();
    run_until_stopped(&mut c, 60.0);
    assert!((c.point().machine[2] - 300.0).abs() < 1e-9, "{:?}", c.point().machine);
    assert_eq!(c.handle_direction(ManualFeed::ToolAxis, 1.0), Err(Refusal::WrongMode));
}

#[test]
fn jog_handle_and_reference_return() {
    let mut c = controller();
    assert_eq!(c.jog_start('X', true), Err(Refusal::WrongMode));
    c.set_mode(Mode::Jog).unwrap();
    c.panel.jog_feed = 6000.0;
    c.jog_start('X', true).unwrap();
    let mut xs = run_until_stopped(&mut c, 1.0);
    c.jog_stop();
    xs.extend(run_until_stopped(&mut c, 1.0));
    assert_within_limits(&xs);
    assert_eq!(c.run_state(), RunState::Idle);
    let x = c.point().machine[0];
    assert!(x > 90.0 && x < 110.0, "about 1 s at 100 mm/s: {x}");
    // The program's current point followed the jog: G91 X10 goes on from there.
    c.set_mode(Mode::Handle).unwrap();
    c.handle('Y', -2.5).unwrap();
    run_until_stopped(&mut c, 5.0);
    assert_eq!(c.point().machine[1], -2.5);
    assert_eq!(c.handle('Q', 1.0), Err(Refusal::NoAxis));
    // A hand wheel turned past the stroke stops at the limit (Z −500…300), in the overtravel
    // alarm (`manual_moves_to_a_stroke_limit_end_in_the_overtravel_alarm`); reset clears it.
    c.handle('Z', 1000.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[2], 300.0);
    assert_eq!(c.alarms()[0].code, "OT0500");
    c.reset();
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("G91 G01 X10. F6000.").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 5.0);
    assert!((c.point().machine[0] - (x + 10.0)).abs() < 1e-9);
    c.set_mode(Mode::Ref).unwrap();
    c.reference_return().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.point().machine[..3], [0.0, 0.0, 0.0]);
}

/// Audit of views F2: a reference return made in REF mode moves the program's current point
/// with the machine, as a jog or a handle move does. The estimate and the path preview run a
/// copy of the interpreter from that point: they started where the MDI had left the machine
/// (X100 Y-50 Z-20) though it stood at the reference position.
#[test]
fn a_reference_return_moves_the_programs_current_point() {
    let mut c = controller();
    mdi(&mut c, "G90 G00 X100. Y-50. Z-20.\n");
    assert_eq!(c.interpreter().state.machine_position()[..3], [100.0, -50.0, -20.0]);
    c.set_mode(Mode::Ref).unwrap();
    c.reference_return().unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(c.point().machine[..3], [0.0, 0.0, 0.0]);
    assert_eq!(c.interpreter().state.machine_position()[..3], [0.0, 0.0, 0.0]);
    assert_eq!(c.interpreter().state.position()[..3], [0.0, 0.0, 0.0]);
    // The path preview of a program from here (what `GET …/programs/{n}/path` runs) starts at
    // the reference position, and its G91 move ends 10 mm from it.
    let mut copy = c.interpreter().clone();
    copy.load_source(&fivex_engine::lang::Source { main: "G91 G01 X10. F1000.\nM30\n".into(), library: Vec::new() });
    let path = fivex_engine::preview::tool_path(&mut copy, 100);
    assert!(path.alarm.is_none(), "{:?}", path.alarm);
    let (first, last) = (path.points[0], *path.points.last().unwrap());
    assert!(first.iter().all(|v| v.abs() < 1e-9), "{first:?}");
    assert!((last[0] - 10.0).abs() < 1e-9 && last[1].abs() < 1e-9, "{last:?}");
}

/// FANUC stored stroke check 1 in manual operation: a JOG, INC or HANDLE move that reaches a
/// stored stroke limit stops there with OT0500 (+) / OT0501 (−), "OVERTRAVEL (SOFT 1)" (the
/// 30i's alarm list); it was a silent stop. Reset clears the alarm; the axis then moves back
/// from the limit, and on into it alarms again at once. A jog released short of the limit
/// raises nothing. mill3: X −600…600, Y −450…450, Z −500…300.
#[test]
fn manual_moves_to_a_stroke_limit_end_in_the_overtravel_alarm() {
    let mut c = controller();
    c.set_mode(Mode::Jog).unwrap();
    c.panel.jog_feed = 30000.0;
    // JOG X+ held: 600 mm at 500 mm/s reach the limit in about 1.2 s.
    c.jog_start('X', true).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.run_state(), RunState::Alarm);
    assert_eq!(c.point().machine[0], 600.0);
    assert_eq!(c.alarms().len(), 1);
    assert_eq!((c.alarms()[0].code.as_str(), c.alarms()[0].message.as_str()), ("OT0500", "+ OVERTRAVEL ( SOFT 1 ) X"));
    assert_eq!(c.jog_start('X', false), Err(Refusal::Busy), "the alarm stands until reset");
    c.reset();
    assert!(c.alarms().is_empty() && c.run_state() == RunState::Idle);
    // On into the limit: the alarm at once, nothing moves.
    c.jog_start('X', true).unwrap();
    assert_eq!((c.run_state(), c.alarms()[0].code.as_str()), (RunState::Alarm, "OT0500"));
    c.reset();
    // Back from it, released after 0.5 s: no alarm.
    c.jog_start('X', false).unwrap();
    let mut xs = Vec::new();
    record(&mut c, 500, &mut xs);
    c.jog_stop();
    run_until_stopped(&mut c, 5.0);
    assert_eq!(c.run_state(), RunState::Idle);
    assert!(c.alarms().is_empty());
    let x = c.point().machine[0];
    assert!(x < 600.0 && x > 0.0, "{x}");
    // INC: an increment past the limit stops at it with the alarm; one inside does not.
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(1000.0).unwrap();
    c.jog_start('Y', false).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!((c.point().machine[1], c.alarms()[0].code.as_str()), (-450.0, "OT0501"));
    assert_eq!(c.alarms()[0].message, "- OVERTRAVEL ( SOFT 1 ) Y");
    c.reset();
    c.set_increment(10.0).unwrap();
    c.jog_start('Y', true).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!((c.point().machine[1], c.run_state()), (-440.0, RunState::Idle));
    // HANDLE −1000 from Z0: stops at −500 with OT0501; the program's current point is there.
    c.set_mode(Mode::Handle).unwrap();
    c.handle('Z', -1000.0).unwrap();
    run_until_stopped(&mut c, 10.0);
    assert_eq!((c.point().machine[2], c.alarms()[0].code.as_str()), (-500.0, "OT0501"));
    c.reset();
    assert_eq!(c.run_state(), RunState::Idle);
}

#[test]
fn the_manual_overtravel_alarm_is_each_dialects() {
    // Syntec's code is fivex's constructed MOT-001/002; Haas's 316–319 (X, Y, Z, A).
    for (dialect, code) in [(Dialect::Syntec, "MOT-001"), (Dialect::Haas, "318")] {
        let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), dialect));
        c.panel.jog_feed = 30000.0;
        c.set_mode(Mode::Handle).unwrap();
        c.handle('Z', 400.0).unwrap();
        run_until_stopped(&mut c, 10.0);
        assert_eq!((c.point().machine[2], c.alarms()[0].code.as_str()), (300.0, code), "{dialect:?}");
    }
}

#[test]
fn an_over_travel_stops_the_machine_before_the_block() {
    let mut c = started("G90 G01 X500. F12000.\nN20 X700.\nM30\n");
    run_until_stopped(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Alarm);
    assert_eq!((c.alarms()[0].code.as_str(), c.alarms()[0].n), ("OT0510", Some(20)));
    assert_eq!(c.point().machine[0], 500.0);
}

/// A stroke pre-check alarm (OT0510/OT0511) comes before the move, and the position stays where
/// the machine is: the workpiece position, the programmed point of the status and the stream,
/// and the interpreter's current point (#5001…, #5041…) showed the end of the move that never
/// happened (X1030 with the machine at X30) until a reset.
#[test]
fn a_stroke_pre_check_alarm_leaves_the_position_where_the_machine_is() {
    for (block, code) in [("G00 X1000.", "OT0510"), ("G00 Y-600.", "OT0511")] {
        let src = format!("N10 G91 G01 X30. F3000\nN20 {block}\nN30 M30\n");
        let mut c = started(&src);
        run_until_stopped(&mut c, 10.0);
        assert_eq!((c.run_state(), c.alarms()[0].code.as_str(), c.alarms()[0].n), (RunState::Alarm, code, Some(20)));
        let want = [30.0, 0.0, 0.0];
        assert_eq!(&c.point().machine[..3], &want, "{block}");
        assert_eq!(&c.point().work[..3], &want, "{block}: workpiece position");
        assert_eq!(c.sample().programmed, want, "{block}: programmed point");
        assert_eq!(c.tip().tip, want, "{block}: tip");
        let st = &c.interpreter().state;
        assert_eq!(&st.shown_position()[..3], &want, "{block}: #5041…");
        assert_eq!(&st.machine_position()[..3], &want, "{block}: machine position read");
    }
}

mod random_panel {
    use super::*;
    use proptest::prelude::*;

    #[derive(Debug, Clone)]
    enum Action {
        /// Milliseconds of 1 ms ticks.
        Ticks(usize),
        CycleStart,
        FeedHold,
        Reset,
        EmergencyStop(bool),
        Mode(Mode),
        Jog(char, bool),
        JogStop,
        Handle(char, f64),
        Reference,
        Mdi(usize),
        Override(f64),
        SingleBlock(bool),
        JogAlong(fivex_engine::kin::ManualFeed, bool),
        HandleAlong(fivex_engine::kin::ManualFeed, f64),
        ManualAbsolute(bool),
        Coordinates(fivex_engine::controller::ManualCoordinates),
    }

    const MDI: [&str; 3] = ["G91 G01 X5. Y-3. F2000.", "G90 G00 Z20.", "G91 G02 X10. R5. F1000."];
    /// No corners: every junction is tangent or a stop.
    const PROGRAM: &str = "G90 G00 X10. Y10. Z10.\nG01 X60. F3000.\nG03 X80. Y30. R20.\nG04 X0.1\nM00\n\
                           G01 Z-5. F500.\nM01\nG02 X60. Y50. R20. F2000.\nG00 Z50.\nM30\n";

    fn feed() -> impl Strategy<Value = fivex_engine::kin::ManualFeed> {
        prop::sample::select(fivex_engine::kin::ManualFeed::ALL.to_vec())
    }

    fn action() -> impl Strategy<Value = Action> {
        let axis = prop::sample::select(vec!['X', 'Y', 'Z', 'Q']);
        prop_oneof![
            4 => (1usize..300).prop_map(Action::Ticks),
            2 => Just(Action::CycleStart),
            1 => Just(Action::FeedHold),
            1 => Just(Action::Reset),
            1 => any::<bool>().prop_map(Action::EmergencyStop),
            1 => prop::sample::select(vec![Mode::Auto, Mode::Mdi, Mode::Jog, Mode::Handle, Mode::Ref]).prop_map(Action::Mode),
            1 => (axis.clone(), any::<bool>()).prop_map(|(a, p)| Action::Jog(a, p)),
            1 => Just(Action::JogStop),
            1 => (axis, -2000.0..2000.0f64).prop_map(|(a, d)| Action::Handle(a, d)),
            1 => Just(Action::Reference),
            1 => (0..MDI.len()).prop_map(Action::Mdi),
            1 => (0.0..2.0f64).prop_map(Action::Override),
            1 => any::<bool>().prop_map(Action::SingleBlock),
            1 => (feed(), any::<bool>()).prop_map(|(f, p)| Action::JogAlong(f, p)),
            1 => (feed(), -500.0..500.0f64).prop_map(|(f, d)| Action::HandleAlong(f, d)),
            1 => any::<bool>().prop_map(Action::ManualAbsolute),
            1 => prop::sample::select(vec![
                fivex_engine::controller::ManualCoordinates::Machine,
                fivex_engine::controller::ManualCoordinates::Program,
                fivex_engine::controller::ManualCoordinates::Tool,
            ])
            .prop_map(Action::Coordinates),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// Whatever the operator does, nothing panics, no axis leaves its stroke or exceeds its
        /// speed, acceleration or jerk (but at an emergency stop, which stops at once), and a
        /// machine that is not running stands still.
        #[test]
        fn any_sequence_of_panel_actions_is_safe(actions in prop::collection::vec(action(), 1..40)) {
            let mut c = controller();
            c.select_program(PROGRAM).unwrap();
            let strokes: Vec<[f64; 2]> =
                MachineConfig::preset("mill3").unwrap().axes.iter().map(|a| a.stroke.unwrap()).collect();
            // Positions (and their block) every millisecond since the last emergency stop.
            let mut xs: Vec<([f64; 3], u32)> = Vec::new();
            let ticks = |c: &mut Controller, xs: &mut Vec<([f64; 3], u32)>, n: usize| {
                for _ in 0..n {
                    c.tick(TICK);
                    let p = c.point();
                    xs.push(([p.machine[0], p.machine[1], p.machine[2]], p.line));
                }
            };
            for a in actions {
                let _ = match a {
                    Action::Ticks(n) => {
                        ticks(&mut c, &mut xs, n);
                        Ok(())
                    }
                    Action::CycleStart => c.cycle_start(),
                    Action::FeedHold => {
                        c.feed_hold();
                        Ok(())
                    }
                    Action::Reset => {
                        c.reset();
                        Ok(())
                    }
                    Action::EmergencyStop(p) => {
                        c.emergency_stop(p);
                        xs.clear();
                        Ok(())
                    }
                    Action::Mode(m) => c.set_mode(m),
                    Action::Jog(axis, p) => c.jog_start(axis, p),
                    Action::JogStop => {
                        c.jog_stop();
                        Ok(())
                    }
                    Action::Handle(axis, d) => c.handle(axis, d),
                    Action::Reference => c.reference_return(),
                    Action::Mdi(i) => c.set_mdi(MDI[i]),
                    Action::Override(f) => {
                        c.set_overrides(f, f.min(1.0));
                        Ok(())
                    }
                    Action::SingleBlock(on) => {
                        c.panel.single_block = on;
                        Ok(())
                    }
                    Action::JogAlong(f, p) => c.jog_direction(f, p),
                    Action::HandleAlong(f, d) => c.handle_direction(f, d),
                    Action::ManualAbsolute(on) => {
                        c.panel.manual_absolute = on;
                        Ok(())
                    }
                    Action::Coordinates(choice) => c.set_manual_coordinates(choice),
                };
                let m = c.point().machine;
                for (i, [lo, hi]) in strokes.iter().enumerate() {
                    prop_assert!(m[i] >= lo - 1e-6 && m[i] <= hi + 1e-6, "axis {i} at {}", m[i]);
                }
                if c.run_state() != RunState::Running {
                    // Holding or idle: once any stop has run out (1 s is plenty), nothing moves.
                    ticks(&mut c, &mut xs, 1000);
                    let settled = c.point().machine;
                    if c.run_state() != RunState::Running {
                        ticks(&mut c, &mut xs, 100);
                        prop_assert_eq!(c.point().machine, settled);
                        prop_assert_eq!(c.point().feed, 0.0);
                    }
                }
            }
            let (points, lines): (Vec<[f64; 3]>, Vec<u32>) = xs.into_iter().unzip();
            assert_within_limits_by_block(&points, &lines);
        }
    }
}

#[test]
fn tool_tip_centre_rotation_keeps_the_tip_on_the_table() {
    use fivex_engine::kin::Kinematics;
    for (preset, axis, index, amount) in
        [("head-bc", 'B', 3, 30.0), ("table-ac", 'A', 3, -20.0), ("mixed-bc", 'B', 3, 25.0)]
    {
        let m = MachineConfig::preset(preset).unwrap();
        let kin = Kinematics::new(&m).unwrap();
        let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
        c.manual_options_mut().tool_length = 100.0;
        c.set_mode(Mode::Mdi).unwrap();
        c.set_mdi("G90 G00 X10. Y-20. Z-30.").unwrap();
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 10.0);
        let tip = kin.forward(&c.point().machine, 100.0).tip;
        c.set_mode(Mode::Handle).unwrap();
        c.handle_tip_rotation(axis, amount).unwrap();
        let mut xs = Vec::new();
        while c.run_state() == RunState::Running {
            c.tick(TICK);
            let p = c.point().machine;
            xs.push([p[0], p[1], p[2]]);
            let off = (kin.forward(&p, 100.0).tip - tip).norm();
            assert!(off < 1e-6, "{preset}: tip moved {off} mm at {p:?}");
        }
        assert!((c.point().machine[index] - amount).abs() < 1e-9, "{preset}: {:?}", c.point().machine);
        assert_within_limits(&xs);
        assert_eq!(c.handle_tip_rotation('X', 1.0), Err(Refusal::NoAxis), "a linear axis cannot turn");
    }
}

#[test]
fn jog_tip_rotation_stops_on_jog_stop_with_the_tip_in_place() {
    use fivex_engine::kin::Kinematics;
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    c.manual_options_mut().tool_length = 50.0;
    c.panel.jog_feed = 3600.0;
    c.set_mode(Mode::Jog).unwrap();
    let tip = kin.forward(&c.point().machine, 50.0).tip;
    c.jog_tip_rotation('B', false).unwrap();
    c.tick(0.3);
    c.jog_stop();
    let mut xs = Vec::new();
    while c.run_state() == RunState::Running {
        c.tick(TICK);
        let p = c.point().machine;
        xs.push([p[0], p[1], p[2]]);
        assert!((kin.forward(&p, 50.0).tip - tip).norm() < 1e-6);
    }
    let b = c.point().machine[3];
    assert!(b < -5.0 && b > -20.0, "about 0.3 s at 60 deg/s, then the stop: B{b}");
    assert_within_limits(&xs);
}

/// The panel's modal state and line are the executing block's: the interpreter reads ahead of
/// the machine (look-ahead, the read-ahead of a loop), but while the first tool centre point
/// move runs the panel says G43.4 and G01, not the G49 and G00 read behind it; a dwell shows its
/// own line while it waits.
#[test]
fn the_modal_state_shown_is_the_executing_blocks() {
    use fivex_engine::interp::gcode::display;
    let m = MachineConfig::preset("head-bc").unwrap();
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 100.0;
    let program = "G90 G54 G00 X0 Y0 Z50.\n\
                   G43.4 H1\n\
                   G01 X40. B20. F2000.\n\
                   G01 X0 B0\n\
                   G49\n\
                   G04 X1.\n\
                   G00 Z80.\n\
                   M30\n";
    c.select_program(program).unwrap();
    c.cycle_start().unwrap();
    let group = |c: &Controller, g: usize| display(c.modal().modal(g));
    let mut seen = std::collections::BTreeSet::new();
    let mut read_ahead_seen = false;
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(TICK);
        let line = c.point().line;
        seen.insert(line);
        match line {
            3 | 4 => {
                assert_eq!(group(&c, 8), "G43.4", "line {line} executes under TCP");
                assert_eq!(group(&c, 1), "G01", "line {line}");
                assert_eq!(c.modal().words.h, 1);
                // The interpreter itself has read on (to the G49/G00 blocks) at some point.
                read_ahead_seen |= display(c.interpreter().state.modal(8)) == "G49";
            }
            6 => {
                assert_eq!(group(&c, 8), "G49", "the dwell comes after G49");
                assert_eq!(group(&c, 1), "G01", "the dwell's block has not reached G00");
            }
            7 => assert_eq!(group(&c, 1), "G00"),
            _ => {}
        }
    }
    assert!(seen.is_superset(&[3, 4, 6, 7].into()), "lines shown: {seen:?}");
    assert!(read_ahead_seen, "the interpreter never read ahead of the machine: the test proves nothing");
    // Once everything read is done, the shown state is the interpreter's.
    assert_eq!(c.modal(), c.interpreter().state.modal_state());
}

/// Cutter compensation holds a block until it has read the next (here the last compensated
/// move comes out with the G40 block): the block shows its own state while it runs — G41 and
/// its own line — not the G40 read with it.
#[test]
fn a_block_released_late_by_cutter_compensation_shows_its_own_state() {
    use fivex_engine::interp::gcode::display;
    let m = MachineConfig::preset("mill3").unwrap();
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
    let program = "G90 G54 G00 X-20. Y0 Z0\nG41 D1 G01 X0 F1000.\nY40.\nX40.\nG40 X60. Y60.\nM30\n";
    c.select_program(program).unwrap();
    c.cycle_start().unwrap();
    let mut seen = std::collections::BTreeSet::new();
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(TICK);
        let line = c.point().line;
        seen.insert(line);
        let comp = display(c.modal().modal(7));
        match line {
            2..=4 => assert_eq!(comp, "G41", "line {line} executes compensated"),
            5 => assert_eq!(comp, "G40", "the cancel block"),
            _ => {}
        }
    }
    assert!(seen.is_superset(&[2, 3, 4, 5].into()), "lines shown: {seen:?}");
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
}

/// The tilted working plane shown is the executing block's (the 3D view draws its frame): while
/// the moves in the plane run, the plane is G68.2's even after the interpreter has read the G69
/// behind them; after G69 there is none.
#[test]
fn the_tilted_plane_shown_is_the_executing_blocks() {
    let m = MachineConfig::preset("table-ac").unwrap();
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    let program = "G90 G54 G00 X0 Y0 Z100.\n\
                   G68.2 X10. Y0 Z0 I0 J30. K0\n\
                   G53.1\n\
                   G01 X20. Y10. Z30. F3000.\n\
                   G01 X-20. Y0 Z30.\n\
                   G69\n\
                   G00 Z120.\n\
                   M30\n";
    c.select_program(program).unwrap();
    c.cycle_start().unwrap();
    let mut in_plane = 0;
    let mut read_ahead_seen = false;
    while c.run_state() == RunState::Running && c.time() < 120.0 {
        c.tick(TICK);
        match c.point().line {
            4 | 5 => {
                let plane = c.plane().expect("the moves in the plane show it");
                assert_eq!(plane.code, 682);
                assert!((plane.origin[0] - 10.0).abs() < 1e-12, "{plane:?}");
                // Euler ZXZ I0 J30 K0: the FCS X axis stays the workpiece X, Z tilts by 30° about it.
                let z = plane.axes[2];
                let (s, co) = 30f64.to_radians().sin_cos();
                assert!((z[0]).abs() < 1e-12 && (z[1] + s).abs() < 1e-12 && (z[2] - co).abs() < 1e-12, "{plane:?}");
                in_plane += 1;
                read_ahead_seen |= c.interpreter().state.active_plane().is_none();
            }
            7 => assert_eq!(c.plane(), None, "G00 Z120. runs after G69"),
            _ => {}
        }
    }
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert!(in_plane > 10, "the moves in the plane were sampled {in_plane} times");
    assert!(
        read_ahead_seen,
        "the interpreter never read past G69 while the plane's moves ran: the test proves nothing"
    );
    assert_eq!(c.plane(), None);
}

/// Audit of views F3: a reset that cancels G68.2 (FANUC's default: the tilted working plane
/// ends at a reset) shows the workpiece coordinates at once, in the status's
/// `position.workpiece` and the stream's programmed point. They stayed in the feature
/// coordinate system until the next move (X10 Y23.66 Z20.98 for the workpiece's X20 Y10 Z30).
#[test]
fn a_reset_that_ends_the_tilted_plane_shows_workpiece_coordinates_at_once() {
    use fivex_engine::tip::System;
    let m = MachineConfig::preset("table-ac").unwrap();
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    mdi(&mut c, "G90 G54 G00 X20. Y10. Z30.\nG68.2 X10. Y0 Z0 I0 J30. K0\n");
    assert_eq!(c.sample().programmed_in, System::Feature, "in the plane: the test proves nothing");
    let feature = c.point().work;
    c.reset();
    assert_eq!(c.plane(), None);
    let (p, s) = (c.point(), c.sample());
    assert_eq!(s.programmed_in, System::Workpiece);
    // mill offsets zero, no tool length: the workpiece point is the machine's.
    for k in 0..3 {
        assert!((p.work[k] - [20.0, 10.0, 30.0][k]).abs() < 1e-9, "{:?} (in the plane {feature:?})", p.work);
        assert_eq!(s.programmed[k], p.work[k]);
    }
    // And it stays so as time goes on.
    c.tick(0.1);
    assert_eq!(c.point().work[..3], p.work[..3]);
}

/// Audit of views F5: one rule (`State::shown_at_rest`) gives the programmed point shown at rest
/// to the controller (status, stream) and to the run summary (`fivex run`, fleet runs). A
/// program whose text ends under G41 stands at the last block's perpendicular vector, X35 Y30
/// with D1 = 5 mm: the controller showed that tool centre, the summary the contour's X40 Y30
/// beside the machine's X35. A G92 without motion at the end is shown at once by both. (Both
/// texts end without M30: the run stops there with PS5010 END OF RECORD, at rest all the same.)
#[test]
fn the_programmed_point_at_rest_is_the_run_summarys() {
    let programs = [
        ("G90 G17 G00 X-20. Y0 Z0\nG41 D1 G01 X0 F3000.\nX40.\nY30.\n", [35.0, 30.0, 0.0]),
        ("G90 G00 X10. Y5.\nG92 X50.\n", [50.0, 5.0, 0.0]),
    ];
    for (src, want) in programs {
        let cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc);
        let mut interp = Interpreter::new(parse_file(src), cfg);
        interp.state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
        let r = run(&mut interp, &RunOptions::default(), |_| {});
        let last = src.lines().count() as u32;
        let end_of_record = |alarms: &[fivex_engine::Alarm]| {
            alarms.iter().map(|a| (a.code.clone(), a.line)).collect::<Vec<_>>() == [("PS5010".to_string(), last)]
        };
        assert!(end_of_record(&r.alarms), "{src}: {:?}", r.alarms);
        let mut c = controller();
        c.interpreter_mut().state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
        c.select_program(src).unwrap();
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 60.0);
        assert!(end_of_record(c.alarms()), "{src}: {:?}", c.alarms());
        let s = c.sample();
        assert_eq!((s.programmed, s.programmed_in), (r.programmed, r.programmed_in), "{src}");
        assert_eq!(c.point().work[..3], r.workpiece[..3], "{src}");
        for (got, want) in r.programmed.iter().zip(want) {
            assert!((got - want).abs() < 1e-9, "{src}: {:?}", r.programmed);
        }
    }
}

/// MDI `text` run to its end on a controller that stands idle.
fn mdi(c: &mut Controller, text: &str) {
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi(text).unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle);
}

/// Tick until the executing line is `line` (the interpreter has read far beyond it).
fn run_to_line(c: &mut Controller, line: u32) {
    while c.point().line < line && c.time() < 60.0 {
        c.tick(TICK);
    }
    assert_eq!(c.point().line, line);
}

/// Audit ops F1: a reset drops the blocks read ahead, and what they would have put in force with
/// them: the G55 read behind the G01 never became the work system, so the MDI's X0 Y0 Z0 is the
/// G54 zero (machine 0, 0, 0), not G55's (X−100 Z−50).
#[test]
fn a_reset_leaves_the_executed_blocks_work_system_not_the_read_aheads() {
    use fivex_engine::interp::gcode::{display, group};
    let mut c = controller();
    *c.interpreter_mut().state.offsets.work_mut(2) = [-100.0, 0.0, -50.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    c.select_program("G90 G54 G01 X50. F600.\nG55\nG00 X0 Y0 Z0\nM30\n").unwrap();
    c.cycle_start().unwrap();
    c.tick(1.0);
    assert_eq!(c.point().line, 1);
    assert_eq!(display(c.interpreter().state.modal(group::WORK_SYSTEM)), "G55", "read ahead: the test proves nothing");
    c.reset();
    c.tick(1.0);
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(display(c.modal().modal(group::WORK_SYSTEM)), "G54");
    let p = c.point();
    assert!((p.work[0] - p.machine[0]).abs() < 1e-9 && (p.work[2] - p.machine[2]).abs() < 1e-9, "{p:?}");
    mdi(&mut c, "G00 X0 Y0 Z0\n");
    assert_eq!(&c.point().machine[..3], &[0.0, 0.0, 0.0]);
}

/// Audit ops F1: G68 and G91 read ahead and dropped by a reset are not in force after it: the
/// MDI `G01 X20.` goes to X20 Y0 (absolute, not rotated).
#[test]
fn a_reset_leaves_the_executed_blocks_distance_mode_and_rotation() {
    let mut c = started("G90 G01 X50. F600.\nG68 X0 Y0 R90.\nG91\nG01 X100.\nM30\n");
    c.tick(1.0);
    assert_eq!(c.point().line, 1);
    c.reset();
    c.tick(1.0);
    assert_eq!(c.run_state(), RunState::Idle);
    mdi(&mut c, "G01 X20. F6000.\n");
    let m = c.point().machine;
    assert!((m[0] - 20.0).abs() < 1e-9 && m[1].abs() < 1e-9, "{m:?}");
}

/// The 40 short blocks of audit ops F2 (t9.py): `G01 X0/50. Y<i>. F3000.`, line i + 1.
fn zigzag() -> String {
    let mut p = String::from("G90 G00 X0 Y0\n");
    for i in 1..=40 {
        p += &format!("G01 X{}. Y{i}. F3000.\n", if i % 2 == 1 { 50 } else { 0 });
    }
    p + "M30\n"
}

/// Where line `line` of `zigzag` ends.
fn zigzag_end(line: u32) -> [f64; 2] {
    let i = line - 1;
    [if i % 2 == 1 { 50.0 } else { 0.0 }, i as f64]
}

/// Audit ops F2: single block switched on during a run stops at the end of the block executing
/// (or the next block end, if the machine cannot stop before it), not after the look-ahead's
/// blocks; each cycle start then runs one block.
#[test]
fn single_block_switched_on_under_way_stops_at_the_next_block_end() {
    use fivex_engine::controller::ProgramStop;
    let mut c = started(&zigzag());
    run_to_line(&mut c, 4);
    c.panel.single_block = true;
    run_until_stopped(&mut c, 60.0);
    assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock));
    let line = c.point().line;
    assert!((4..=5).contains(&line), "stopped at line {line}");
    let m = c.point().machine;
    assert_eq!([m[0], m[1]], zigzag_end(line));
    for next in line + 1..line + 3 {
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 60.0);
        assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock));
        let m = c.point().machine;
        assert_eq!((c.point().line, [m[0], m[1]]), (next, zigzag_end(next)));
    }
}

/// Single block switched on under way, then off at its stop: the program runs on without
/// stopping at the block ends read ahead while it was on. The marks stayed: the machine came to
/// rest at each of the hundreds of 1 mm blocks already read (no program stop, but 2.5× the time).
#[test]
fn single_block_switched_off_again_leaves_no_stops_behind() {
    use fivex_engine::controller::ProgramStop;
    let moves: String = (0..300).map(|_| "X1.\n").collect();
    let prog = format!("G91 G01 F3000.\n{moves}M30\n");
    let mut c = started(&prog);
    run_to_line(&mut c, 10);
    c.panel.single_block = true;
    run_until_stopped(&mut c, 60.0);
    assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock));
    c.panel.single_block = false;
    c.tick(TICK);
    c.cycle_start().unwrap();
    let (start, x0) = (c.time(), c.point().machine[0]);
    let mut rests = 0;
    let mut moving = false;
    while c.run_state() == RunState::Running && c.time() - start < 60.0 {
        c.tick(TICK);
        let feed = c.point().feed;
        if moving && feed == 0.0 {
            rests += 1;
        }
        moving = feed > 0.0;
    }
    assert_eq!(c.point().machine[0], 300.0);
    // The rest run at 3000 mm/min with one start and one stop, within the limits (about 50 ms
    // of acceleration each way): the marks made it several times longer.
    let (len, took) = (300.0 - x0, c.time() - start);
    assert!(took < len / 50.0 + 0.5, "{len} mm took {took} s, coming to rest {rests} times");
    assert!(rests <= 1, "came to rest {rests} times on the way");
}

/// Audit ops F2 (t14.py): feed hold, single block on, cycle start: the held block is finished
/// and the machine stops at its end.
#[test]
fn feed_hold_then_single_block_then_cycle_start_runs_the_held_block_and_stops() {
    use fivex_engine::controller::ProgramStop;
    let mut c = started(&zigzag());
    run_to_line(&mut c, 4);
    c.feed_hold();
    c.tick(0.5);
    assert_eq!(c.run_state(), RunState::Hold);
    c.panel.single_block = true;
    c.tick(0.1);
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 60.0);
    assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock));
    let m = c.point().machine;
    assert_eq!((c.point().line, [m[0], m[1]]), (4, zigzag_end(4)));
}

/// Audit of offsets F3: at a program stop after blocks without motion that change the workpiece
/// system (G92, G10 L2, G52) the shown workpiece position, the trace's programmed point and the
/// tip read the new system, as `#5041` does; they showed the system of the last motion (X10
/// after `G92 X50.`). By hand: machine X −90 (G54 X−100 + X10); `G92 X50.` makes it 50 (shift
/// −40); `G10 L2 P1 X-80.` moves the G54 zero +20: 30; `G52 X5.`: 25.
#[test]
fn the_position_shown_at_a_stop_reads_the_work_system_the_blocks_without_motion_set() {
    let src = "G90 G92.1 X0 Y0 Z0\nG52 X0 Y0 Z0\nG10 L2 P1 X-100. Y-50. Z-200.\nG54 G00 X10. Y0 Z0\n\
               G92 X50.\nM00\nG10 L2 P1 X-80.\nM00\nG52 X5.\nM00\nG00 X0\nM30\n";
    let mut c = started(src);
    for (line, want) in [(6, 50.0), (8, 30.0), (10, 25.0)] {
        run_until_stopped(&mut c, 10.0);
        let p = c.point();
        assert_eq!((p.line, c.run_state()), (line, RunState::Idle));
        assert!((p.work[0] - want).abs() < 1e-9, "line {line}: work X {} (machine {})", p.work[0], p.machine[0]);
        assert!((c.tip().tip[0] - want).abs() < 1e-9, "line {line}: tip {:?}", c.tip().tip);
        assert!((c.sample().programmed[0] - want).abs() < 1e-9, "line {line}");
        assert_eq!(p.machine[0], -90.0);
        c.cycle_start().unwrap();
    }
    run_until_stopped(&mut c, 10.0);
    // G00 X0: X0 of G54 (−80) with the G92 shift (−40 after the offset change) and G52 X5.
    assert!((c.point().machine[0] - (-80.0 - 40.0 + 5.0)).abs() < 1e-9, "{:?}", c.point());

    // MDI, from machine X0 in G54 (zero): each command shows its own result, not the one
    // before. `G92 X50.`: 50 (shift −50); `G10 L2 P1 X-120.`: 0 + 120 + 50 = 170.
    let mut c = controller();
    for (text, want) in [("G92 X50.\n", 50.0), ("G10 L2 P1 X-120.\n", 170.0)] {
        mdi(&mut c, text);
        assert!((c.point().work[0] - want).abs() < 1e-9, "{text}: {:?}", c.point());
        assert!((c.tip().tip[0] - want).abs() < 1e-9, "{text}: tip {:?}", c.tip());
    }
}

/// Audit ops F3 (t2.py): the tapping cycle of the audit, at X0 Y0 from Z50 (G54 zero, no tool
/// length: machine Z is the program's): R at Z5, the bottom at Z−20, F500 with S500 (pitch 1).
fn tap_program(cycle: &str) -> String {
    format!("G90 G0 X0 Y0 Z50.\nS500 M03\n{cycle} Z-20. R5. F500.\nG80\nM30\n")
}

/// Tick until machine Z satisfies `at` (the program running), Z after each tick in the result.
fn run_until_z(c: &mut Controller, at: impl Fn(f64) -> bool) -> Vec<f64> {
    let mut zs = Vec::new();
    while !at(c.point().machine[2]) {
        assert_eq!(c.run_state(), RunState::Running, "at Z {}", c.point().machine[2]);
        c.tick(TICK);
        zs.push(c.point().machine[2]);
    }
    zs
}

/// Audit ops F3: a feed hold while the tap is in the hole stops the machine only once the tap
/// is out, at the end of its feed out to point R (FANUC ignores feed hold in the tapping and its
/// return; "When feedhold or halt is applied, the tap will stop when it is out of the hole"):
/// pressed on the way in (G84), at the bottom's dwell (G84 P) and on the way out (G74, M04),
/// the machine holds at R (Z5), not in the hole and not at the initial level (G98); cycle
/// start then finishes the cycle.
#[test]
fn a_feed_hold_in_a_tap_holds_once_the_tap_is_out_of_the_hole() {
    // Where the hold is pressed: on the way in below Z−5, at the bottom, on the way out above
    // Z−10 (after having been below it).
    type Press = fn(f64) -> bool;
    let cases: [(&str, bool, Press); 3] = [
        ("G99 G84", false, |z| z < -5.0),
        ("G98 G84 P1000", false, |z| z <= -20.0 + 1e-9),
        ("G98 G74", true, |z| z < -19.0),
    ];
    for (cycle, out, press) in cases {
        let program = tap_program(cycle).replace("M03", if cycle.contains("G74") { "M04" } else { "M03" });
        let mut c = started(&program);
        run_until_z(&mut c, press);
        if out {
            run_until_z(&mut c, |z| z > -10.0);
        }
        c.feed_hold();
        // The machine goes on: to the bottom (if not there yet), then out to R.
        let mut zs = vec![c.point().machine[2]];
        while c.run_state() == RunState::Running && c.time() < 30.0 {
            c.tick(TICK);
            zs.push(c.point().machine[2]);
        }
        assert_eq!(c.run_state(), RunState::Hold, "{cycle}");
        let z = c.point().machine[2];
        assert!((z - 5.0).abs() < 1e-9, "{cycle}: held at Z {z}, not at R");
        let bottom = zs.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(out || (bottom + 20.0).abs() < 1e-3, "{cycle}: the tap reached Z {bottom}");
        // Held: it stays there (the spindle turns on, as in any feed hold).
        c.tick(3.0);
        assert_eq!((c.run_state(), c.point().machine[2]), (RunState::Hold, z), "{cycle}");
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 30.0);
        assert_eq!((c.run_state(), c.program_stop()), (RunState::Idle, None), "{cycle}");
        let end = if cycle.contains("G98") { 50.0 } else { 5.0 };
        assert!((c.point().machine[2] - end).abs() < 1e-9, "{cycle}: ended at Z {}", c.point().machine[2]);
    }
}

/// A feed hold outside the tap (the rapid to R of a tapping cycle) stops at once, as ever.
#[test]
fn a_feed_hold_before_the_tap_enters_the_hole_stops_where_it_is() {
    let mut c = started(&tap_program("G98 G84"));
    run_until_z(&mut c, |z| z > 49.0);
    run_until_z(&mut c, |z| z < 30.0);
    c.feed_hold();
    run_until_stopped(&mut c, 30.0);
    assert_eq!(c.run_state(), RunState::Hold);
    let z = c.point().machine[2];
    assert!(z > 5.0 + 1.0 && z < 30.0, "held at Z {z}");
}

/// Audit ops F3 (t13.py): with the spindle override at 50 % the tap still feeds at F500 (the
/// feed override does not act in tapping) and the spindle it reports is the commanded 500, not
/// 250 (a 2 mm pitch for a 1 mm tap): in tapping the spindle override does not act either.
/// Before and after the tap, it does.
#[test]
fn the_spindle_override_does_not_act_while_the_tap_is_in_the_hole() {
    for rigid in ["", "M29 S500\n"] {
        let mut c = controller();
        c.set_spindle_override(0.5);
        c.set_overrides(0.5, 1.0);
        let program = tap_program("G99 G84").replace("S500 M03\n", &format!("S500 M03\n{rigid}"));
        c.select_program(program.as_str()).unwrap();
        c.cycle_start().unwrap();
        run_until_z(&mut c, |z| z > 49.0);
        run_until_z(&mut c, |z| z < 30.0);
        assert_eq!(c.spindle(), 250.0, "{rigid:?}: on the way to R");
        run_until_z(&mut c, |z| z < -10.0);
        let feed = c.point().feed;
        assert!((feed - 500.0).abs() < 1e-6, "{rigid:?}: feed {feed} mm/min");
        assert_eq!(c.spindle(), 500.0, "{rigid:?}: in the hole");
        // At the bottom, reversed; on the way out, still the commanded speed.
        run_until_z(&mut c, |z| z > -10.0);
        assert_eq!(c.spindle(), -500.0, "{rigid:?}: on the way out");
        run_until_stopped(&mut c, 30.0);
        assert_eq!(c.spindle(), 250.0, "{rigid:?}: after the cycle");
    }
}

/// Where a controller stops under single block from the start of `program`, until it ends: the
/// machine X/Y/Z of each stop.
fn single_block_stops(dialect: Dialect, program: &str) -> Vec<[f64; 3]> {
    single_block_stops_by(dialect, program, |c| {
        let m = c.point().machine;
        [m[0], m[1], m[2]].map(|v| (v * 1e6).round() / 1e6)
    })
}

/// `program` run on mill3 in single block to its end, cycle start after every stop: `record`
/// of each stop.
fn single_block_stops_by<T>(dialect: Dialect, program: &str, record: impl Fn(&Controller) -> T) -> Vec<T> {
    use fivex_engine::controller::ProgramStop;
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), dialect));
    c.panel.single_block = true;
    c.select_program(program).unwrap();
    c.cycle_start().unwrap();
    let mut stops = Vec::new();
    loop {
        run_until_stopped(&mut c, 60.0);
        if c.program_stop() != Some(ProgramStop::SingleBlock) {
            assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
            return stops;
        }
        stops.push(record(&c));
        c.cycle_start().unwrap();
    }
}

/// A FANUC control in single block stops after every NC block executed, those without motion
/// or M/S/T too; fivex stopped only after the moves, M/S/T and dwells (here only after T1 and
/// G04). Not a block with nothing but N or a comment, nor a macro statement (SBM = 0).
#[test]
fn single_block_stops_after_every_nc_block_with_or_without_motion() {
    let src = "N10 G90\nN20 F500\nN30 T1\nN40 G10 L2 P1 X0\nN50 G92 X0 Y0 Z0\nN60 G43 H1\nN70 G52 X1.\n\
               N80 G04 X0.1\nN81 G90 G54 G17\nN82 G80\nN83\n(COMMENT)\n#100=1\nN90 M30\n";
    let stops = single_block_stops_by(Dialect::Fanuc, src, |c| c.point().n);
    let want: Vec<_> = [10, 20, 30, 40, 50, 60, 70, 80, 81, 82].map(Some).into();
    assert_eq!(stops, want);
}

/// Audit ops F6 (t3.py): single block in a canned cycle stops three times per hole (FANUC "the
/// operation stops at the end of operations 1, 2 and 6"): over the hole at the initial level,
/// at R, and at the return level; none in the hole (G84: "the cycle does not stop until the tap
/// is completed"). K repeats stop so at every hole (G91: the second hole positions at R, already
/// there, so no move to R and no stop for it). Syntec and Haas stop once per cycle block. The
/// G80 block after the cycle stops as every NC block does.
#[test]
fn single_block_in_a_canned_cycle_stops_after_the_positioning_the_move_to_r_and_the_hole() {
    let top = [0.0, 0.0, 50.0];
    for cycle in ["G81", "G83 Q7.", "G84", "G86"] {
        let program = format!("G90 G0 X0 Y0 Z50.\nS500 M03\nG98 {cycle} X10. Y10. Z-20. R5. F500.\nX30.\nG80\nM30\n");
        let stops = single_block_stops(Dialect::Fanuc, &program);
        let hole = |x: f64| [[x, 10.0, 50.0], [x, 10.0, 5.0], [x, 10.0, 50.0]];
        // The G80 block stops too, where the last hole ended.
        let expected: Vec<[f64; 3]> =
            [vec![top, top], hole(10.0).to_vec(), hole(30.0).to_vec(), vec![[30.0, 10.0, 50.0]]].concat();
        assert_eq!(stops, expected, "{cycle}");
    }
    let program = "G90 G0 X0 Y0 Z50.\nG91 G99 G81 X10. Z-25. R-45. F500. K2\nG80\nM30\n";
    let expected = vec![
        top,
        [10.0, 0.0, 50.0],
        [10.0, 0.0, 5.0],
        [10.0, 0.0, 5.0],
        [20.0, 0.0, 5.0],
        [20.0, 0.0, 5.0],
        [20.0, 0.0, 5.0],
    ];
    assert_eq!(single_block_stops(Dialect::Fanuc, program), expected, "K2");
    let program = "G90 G0 X0 Y0 Z50.\nG98 G81 X10. Y10. Z-20. R5. F500.\nX30.\nG80\nM30\n";
    for dialect in [Dialect::Syntec, Dialect::Haas] {
        let expected = vec![top, [10.0, 10.0, 50.0], [30.0, 10.0, 50.0], [30.0, 10.0, 50.0]];
        assert_eq!(single_block_stops(dialect, program), expected, "{dialect:?}");
    }
}

/// Single block switched on while a canned cycle block of many holes runs (its moves read and
/// queued with the switch off): the stops come at the cycle's stop points too, from the next
/// one the machine can stop at.
#[test]
fn single_block_switched_on_in_a_cycle_stops_at_the_cycles_next_stop_point() {
    use fivex_engine::controller::ProgramStop;
    let mut c = started("G90 G0 X0 Y0 Z10.\nG91 G99 G81 X10. Z-3. R-8. F3000. K10\nG80\nM30\n");
    run_to_line(&mut c, 2);
    run_until_z(&mut c, |z| z < 0.0);
    c.panel.single_block = true;
    run_until_stopped(&mut c, 60.0);
    assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock));
    let m = c.point().machine;
    // At R (Z2) of the hole under way or the next: not at the end of the block's ten holes.
    assert!((m[2] - 2.0).abs() < 1e-9 && m[0] <= 30.0 + 1e-9, "stopped at {m:?}");
}

/// A reset while a canned cycle is in force ends it (G80, decision: `docs/conventions.md`,
/// "Reset"): the MDI block `X50. Y5.` after it positions and drills nothing. It drilled a hole
/// (Z down to R and the bottom) at once, the cycle left in force by the reset.
#[test]
fn a_reset_ends_the_canned_cycle() {
    use fivex_engine::interp::gcode::{code, group};
    let mut c = started("G90 G00 X0 Y0 Z50.\nG81 X10. Y0 Z-5. R2. F100.\nX20.\nX30.\nX40.\nM30\n");
    while c.point().line < 3 && c.time() < 30.0 {
        c.tick(TICK);
    }
    assert_eq!(c.modal().modal(group::CYCLE), code::G81, "reset while the cycle runs");
    c.reset();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.modal().modal(group::CYCLE), code::G80);
    assert_eq!(c.interpreter().state.modal(group::CYCLE), code::G80);
    let z = c.point().machine[2];
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("X50. Y5.").unwrap();
    c.cycle_start().unwrap();
    let xs = run_until_stopped(&mut c, 30.0);
    assert_eq!(c.point().machine[..3], [50.0, 5.0, z], "a positioning only");
    assert!(xs.iter().all(|p| p[2] == z), "Z never moved");
    // As after G80, a new cycle takes none of the old data: without Z it has no hole bottom.
    c.set_mdi("G81 X60. Y5. R2. F100.").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 30.0);
    assert_eq!(c.alarms().first().map(|a| a.code.as_str()), Some("FX0008"));
    assert_eq!(c.point().machine[2], z);
}

#[test]
fn a_reset_ends_the_modal_macro_call_and_shows_g67() {
    use fivex_engine::interp::gcode::{code, group};
    use fivex_engine::lang::{Source, Stored};
    let main = "O1\nG90 G00 X0 Y0 Z50.\nG66 P9999 A5.\nX10.\nX20.\nX30.\nM30\n";
    let macro_ = Stored { number: 9999, first_line: 8, text: "O9999\n#501=#501+1\nM99\n".into() };
    let mut c = controller();
    c.select_program(Source { main: main.into(), library: vec![std::sync::Arc::new(macro_)] }).unwrap();
    c.cycle_start().unwrap();
    while c.point().line != 5 && c.time() < 30.0 {
        c.tick(TICK);
    }
    assert_eq!(c.modal().modal(group::MODAL_CALL), code::G66, "reset in the modal call");
    c.reset();
    run_until_stopped(&mut c, 10.0);
    assert_eq!(c.interpreter().state.modal(group::MODAL_CALL), code::G67);
    assert_eq!(c.modal().modal(group::MODAL_CALL), code::G67);
    // And nothing calls O9999 at the next move.
    let calls = c.interpreter().state.persistent()[1];
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("X40.").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 30.0);
    assert_eq!(c.interpreter().state.persistent()[1], calls);
}

/// FANUC No.6001#6 CCV = 0 (the default): a reset clears the common variables #100–#199 and
/// #100000–#199999 to vacant; CCV = 1 keeps them. #500–#999 stay either way; the Haas NGC
/// keeps them always.
#[test]
fn a_reset_clears_the_common_variables_unless_ccv_keeps_them() {
    let after_reset = |dialect: Dialect, kept: bool, mdi: &str| {
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.motion.commons_kept_at_reset = kept;
        let mut c = Controller::new(Config::new(m, dialect));
        c.set_mode(Mode::Mdi).unwrap();
        c.set_mdi(mdi).unwrap();
        c.cycle_start().unwrap();
        c.tick(1.0);
        assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
        let set = c.interpreter().state.common_variables();
        c.reset();
        (set, c.interpreter().state.common_variables())
    };
    let fanuc = "#102=9.\n#100102=8.\n#502=7.";
    let all = vec![(102, 9.0), (502, 7.0), (100_102, 8.0)];
    assert_eq!(after_reset(Dialect::Fanuc, false, fanuc), (all.clone(), vec![(502, 7.0)]));
    assert_eq!(after_reset(Dialect::Fanuc, true, fanuc), (all.clone(), all));
    let haas = vec![(102, 9.0), (502, 7.0)];
    assert_eq!(after_reset(Dialect::Haas, false, "#102=9.\n#502=7."), (haas.clone(), haas));
}

/// Stopping distance of mill3 (J = 80000 mm/s³, A = 4000 mm/s²) from a steady `v` mm/s: jerk
/// down to a deceleration √(J·v) (within A for v ≤ A²/J = 200 mm/s) and back, in 2·√(v/J) s at
/// a mean speed of v/2: v·√(v/J).
fn mill3_stop_distance(v: f64) -> f64 {
    assert!(v <= 200.0);
    v * (v / 80000.0).sqrt()
}

/// Verification audit of F2 (s2.py): `c` runs until `at` holds, then single block goes on, and
/// cycle start is pressed at every single-block stop until the program ends (idle, no alarm):
/// the line and machine X/Y/Z of each stop, and the machine X/Y/Z where the switch went on and
/// at every tick from there to the first stop.
type Stops = Vec<(u32, [f64; 3])>;
fn stops_after_switching_on(c: &mut Controller, at: impl Fn(&Controller) -> bool) -> (Stops, Vec<[f64; 3]>) {
    use fivex_engine::controller::ProgramStop;
    while !at(c) {
        assert!(c.time() < 120.0 && c.run_state() == RunState::Running, "never got there");
        c.tick(TICK);
    }
    c.panel.single_block = true;
    let m = c.point().machine;
    let (mut stops, mut first) = (Vec::new(), None);
    loop {
        let xs = run_until_stopped(c, 120.0);
        first.get_or_insert_with(|| [vec![[m[0], m[1], m[2]]], xs].concat());
        if c.program_stop() != Some(ProgramStop::SingleBlock) {
            assert_eq!((c.run_state(), c.alarms().len()), (RunState::Idle, 0));
            return (stops, first.unwrap_or_default());
        }
        let m = c.point().machine;
        stops.push((c.point().line, [m[0], m[1], m[2]]));
        c.cycle_start().unwrap();
    }
}

/// Collinear blocks of `step` mm along X at `feed` mm/min (`count` of them, on lines 3…):
/// switched on once X reaches `x_on` at the programmed feed, the machine stops at every block
/// end from the first at least the stopping distance ahead, exactly on it, within the limits.
/// A line of collinear blocks is one planned move (one run of the look-ahead): its block ends
/// were not stops at all (1 mm blocks: no stop to the program's end; 0.05 mm: 160 blocks late).
fn collinear_stops(step: f64, feed: f64, count: u32, x_on: f64) {
    let mut src = format!("O0001\nG90 G01 X0 Y0 F{feed:.1}\n");
    for i in 1..=count {
        src += &format!("G01 X{:.3}\n", f64::from(i) * step);
    }
    let mut c = started(&(src + "M30\n"));
    let on = |c: &Controller| {
        let p = c.point();
        p.machine[0] >= x_on && {
            assert!((p.feed - feed).abs() < 1e-6, "not at the feed: {}", p.feed);
            true
        }
    };
    let (stops, xs) = stops_after_switching_on(&mut c, on);
    let x = xs.first().map_or(0.0, |m| m[0]);
    // Where the switch went on, the machine ran at the feed (no acceleration).
    let d = mill3_stop_distance(feed / 60.0);
    let first = (1..=count).find(|&i| f64::from(i) * step - x >= d).unwrap();
    assert!((f64::from(first) * step - x - d).abs() > 1e-4, "too near to tell: {x}");
    let want: Vec<(u32, [f64; 3])> = (first..=count).map(|i| (i + 2, [f64::from(i) * step, 0.0, 0.0])).collect();
    let got: Vec<(u32, [f64; 3])> = stops.iter().map(|&(l, m)| (l, m.map(|v| (v * 1e9).round() / 1e9))).collect();
    let want: Vec<(u32, [f64; 3])> = want.iter().map(|&(l, m)| (l, m.map(|v| (v * 1e9).round() / 1e9))).collect();
    assert_eq!(got, want, "{step} mm at F{feed}, switched on at X{x}");
    assert_within_limits(&xs);
}

#[test]
fn single_block_switched_on_in_collinear_blocks_stops_at_the_first_reachable_block_end() {
    // t_sb_col_1mm: 1.25 mm to stop from 50 mm/s; on at X23.98 (line 26): X26, line 28.
    collinear_stops(1.0, 3000.0, 39, 23.98);
    // t_sb_collinear: 0.112 mm from 10 mm/s.
    collinear_stops(0.05, 600.0, 200, 4.93);
    // t_sb_col_fast: 1.25 mm of 0.1 mm blocks: the 13th block end or so, no sooner within J.
    collinear_stops(0.1, 3000.0, 300, 10.0);
}

/// The machine ends of `stops`, rounded to a nanometre.
fn rounded(stops: &[(u32, [f64; 3])]) -> Vec<(u32, [f64; 3])> {
    stops.iter().map(|&(l, m)| (l, m.map(|v| (v * 1e9).round() / 1e9 + 0.0))).collect()
}

/// t_sb_4blocks, t_sb_full_tail, t_sb_tail2: switched on far from the end of the block under
/// way (tens of mm, more than the 1.25 mm a stop from 50 mm/s takes), the machine stops at that
/// block's end and at every later one, the program's last moves included (the end of the block
/// under way and the last block read were not stops: its `BlockEnd` was passed with the switch
/// off and nothing followed it in the queue).
#[test]
fn single_block_switched_on_under_way_stops_at_the_end_of_the_block_under_way_and_every_later_one() {
    let mut c = started("O0001\nG90 G01 X50. F600.\nY50.\nX0\nY0\nM30\n");
    let (stops, _) = stops_after_switching_on(&mut c, |c| c.point().machine[0] >= 9.9);
    let want = vec![(2, [50.0, 0.0, 0.0]), (3, [50.0, 50.0, 0.0]), (4, [0.0, 50.0, 0.0]), (5, [0.0, 0.0, 0.0])];
    assert_eq!(rounded(&stops), want, "t_sb_4blocks");

    let mut src = String::from("O0001\nG90\n");
    for i in 1..=10 {
        src += &format!("G01 X{}. Y{i}. F3000.\n", (i % 2) * 50);
    }
    let mut c = started(&(src + "M30\n"));
    let (stops, _) = stops_after_switching_on(&mut c, |c| c.point().line == 3 && c.point().machine[0] >= 20.0);
    let want: Vec<(u32, [f64; 3])> = (1..=10).map(|i| (i + 2, [f64::from((i % 2) * 50), f64::from(i), 0.0])).collect();
    assert_eq!(rounded(&stops), want, "t_sb_full_tail");

    let mut c = started("O0001\nG90 G01 X50. F1200.\nY10.\nX0\nY20.\nX50.\nY30.\nG00 Z50.\nM05\nM30\n");
    let (stops, _) = stops_after_switching_on(&mut c, |c| c.point().machine[0] >= 10.0);
    let want = vec![
        (2, [50.0, 0.0, 0.0]),
        (3, [50.0, 10.0, 0.0]),
        (4, [0.0, 10.0, 0.0]),
        (5, [0.0, 20.0, 0.0]),
        (6, [50.0, 20.0, 0.0]),
        (7, [50.0, 30.0, 0.0]),
        (8, [50.0, 30.0, 50.0]),
        (9, [50.0, 30.0, 50.0]),
    ];
    assert_eq!(rounded(&stops), want, "t_sb_tail2");
}

/// t_sb_crc: switched on at the start of the G41 start-up block (line 4), a tool of radius 5
/// around the outside of the square 0…50 clockwise: every block stops at its tool centre end —
/// the start-up's at the intersection of its offset line with X−5 (an inside corner,
/// `docs/cutter-compensation.md` rule 3: through (0, −10) + 5·(−1, 2)/√5 along (2, 1), at
/// X−5: Y = −12.5 + 2.5·√5), the offset lines' intersections at the outer corners, line 8's
/// at the cancel's inside corner (the mirror image of the start-up's: X = −12.5 + 2.5·√5,
/// Y−5), and the G40 block at its programmed point. Line 8, which the stage releases with the
/// G40 block under its serial, ran without a stop.
#[test]
fn single_block_switched_on_under_cutter_compensation_stops_at_every_later_block() {
    let mut c = controller();
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
    c.select_program(
        "O0001\nG90 G17 G00 X-20. Y-20.\nG01 F1200.\nG41 D1 X0. Y-10.\nY50.\nX50.\nY0.\nX-10.\nG40 X-20. Y-20.\nM30\n",
    )
    .unwrap();
    c.cycle_start().unwrap();
    let (stops, _) = stops_after_switching_on(&mut c, |c| c.point().line == 4 && c.point().machine[0] >= -18.0);
    let corner = ((-12.5 + 2.5 * 5f64.sqrt()) * 1e9).round() / 1e9;
    let want = vec![
        (4, [-5.0, corner, 0.0]),
        (5, [-5.0, 55.0, 0.0]),
        (6, [55.0, 55.0, 0.0]),
        (7, [55.0, -5.0, 0.0]),
        (8, [corner, -5.0, 0.0]),
        (9, [-20.0, -20.0, 0.0]),
    ];
    assert_eq!(rounded(&stops), want);
}

/// t_sb_canned: switched on while the first hole of a G81 (G99) is drilled, FANUC's three stops
/// per hole (positioning, point R, the hole's end; from the second hole on it positions at R,
/// so there is no move to R) come at every later hole, the last one included (hole 4 ran
/// without a stop).
#[test]
fn single_block_switched_on_in_a_canned_cycle_stops_at_every_later_holes_stop_points() {
    let mut c = started("O0001\nG90 G00 X0 Y0 Z50.\nG99 G81 X10. Y0 Z-20. R5. F300.\nX20.\nX30.\nX40.\nG80\nM30\n");
    let (stops, _) = stops_after_switching_on(&mut c, |c| c.point().line == 3 && c.point().machine[2] < 0.0);
    let mut want = vec![(3, [10.0, 0.0, 5.0])];
    for (line, x) in [(4, 20.0), (5, 30.0), (6, 40.0)] {
        want.extend([(line, [x, 0.0, 5.0]), (line, [x, 0.0, 5.0])]);
    }
    assert_eq!(rounded(&stops), want);
}

/// t_sb_hold_r0: feed hold, single block on and cycle start in one instant or in consecutive
/// ticks, during the deceleration: the held block is finished and the machine stops at its end
/// (it ran to M30: the deceleration's rest of the path was queued again unmarked).
#[test]
fn feed_hold_single_block_and_cycle_start_at_once_stop_at_the_held_blocks_end() {
    use fivex_engine::controller::ProgramStop;
    for gaps in [[0, 0], [1, 0], [0, 1], [1, 1], [5, 5]] {
        let mut c = started(&zigzag());
        run_to_line(&mut c, 4);
        c.feed_hold();
        for _ in 0..gaps[0] {
            c.tick(TICK);
        }
        c.panel.single_block = true;
        for _ in 0..gaps[1] {
            c.tick(TICK);
        }
        c.cycle_start().unwrap();
        run_until_stopped(&mut c, 60.0);
        assert_eq!(c.program_stop(), Some(ProgramStop::SingleBlock), "{gaps:?}");
        let m = c.point().machine;
        assert_eq!((c.point().line, [m[0], m[1]]), (4, zigzag_end(4)), "{gaps:?}");
    }
}

/// `src` started in `mode` (AUTO or MDI) on a mill3 controller of `dialect`, run until it stops.
fn run_in(dialect: Dialect, mode: Mode, src: impl Into<fivex_engine::lang::Source>) -> Controller {
    let src = src.into();
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), dialect));
    match mode {
        Mode::Mdi => {
            c.set_mode(Mode::Mdi).unwrap();
            c.set_mdi(src).unwrap();
        }
        _ => c.select_program(src).unwrap(),
    }
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 60.0);
    c
}

/// A FANUC control in memory operation that reaches the end of the main program's text without
/// M02/M30 reads the end of record and stops with PS5010 (`docs/dialects.md`, "The end of the
/// program's text"): after the last block's move, at the last line. fivex ended the run there
/// as completed.
#[test]
fn end_of_record_a_fanuc_program_without_m30_alarms_after_its_last_move() {
    for src in ["G90 G01 X10. F1000.\n", "G90 G01 X10. F1000.\n%\n", "G90 G00 X5.\nG01 X10. F1000."] {
        let c = run_in(Dialect::Fanuc, Mode::Auto, src);
        assert_eq!(c.run_state(), RunState::Alarm, "{src:?}");
        let lines = src.trim_end_matches(['\n', '%']).lines().count() as u32;
        let got: Vec<_> = c.alarms().iter().map(|a| (a.code.as_str(), a.message.as_str(), a.line)).collect();
        assert_eq!(got, [("PS5010", "END OF RECORD", lines)], "{src:?}");
        assert!((c.point().machine[0] - 10.0).abs() < 1e-9, "{src:?}: {:?}", c.point().machine);
        // The run summary (`fivex run`): the same alarm, after the same move.
        let cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc);
        let r = run(&mut Interpreter::new(parse_file(src), cfg), &RunOptions::default(), |_| {});
        let got: Vec<_> = r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect();
        assert_eq!(got, [("PS5010", lines)], "{src:?}");
        assert!((r.machine[0] - 10.0).abs() < 1e-9, "{src:?}: {:?}", r.machine);
    }
}

/// The end of record stands at the main program's last block also when a call returned there,
/// and comes after the moves a smoothing mode still held (they are made first).
#[test]
fn end_of_record_after_a_call_and_after_smoothing_is_at_the_main_programs_last_line() {
    use fivex_engine::lang::{Source, Stored};
    let sub = Stored { number: 2, first_line: 3, text: "O0002\nG01 X20.\nM99\n".into() };
    let src = Source { main: "G90 G01 X10. F1000.\nM98 P2\n".into(), library: vec![std::sync::Arc::new(sub)] };
    let c = run_in(Dialect::Fanuc, Mode::Auto, src);
    let got: Vec<_> = c.alarms().iter().map(|a| (a.code.as_str(), a.line)).collect();
    assert_eq!(got, [("PS5010", 2)]);
    assert!((c.point().machine[0] - 20.0).abs() < 1e-9, "{:?}", c.point().machine);
    let src = "G90 G00 X0 Y0 Z0\nG01 F1000.\nG05.1 Q3 X0 Y0 Z0\nX10. Y1.\nX20. Y0.\nX30. Y2.\n";
    let c = run_in(Dialect::Fanuc, Mode::Auto, src);
    let got: Vec<_> = c.alarms().iter().map(|a| (a.code.as_str(), a.line)).collect();
    assert_eq!(got, [("PS5010", 6)]);
    let m = c.point().machine;
    assert!((m[0] - 30.0).abs() < 1e-9 && (m[1] - 2.0).abs() < 1e-9, "{m:?}");
}

/// M02, M30 and the end of an MDI program end the run as before; Syntec and Haas end it at the
/// end of the text too (their manuals describe no alarm there: a decision).
#[test]
fn end_of_record_not_raised_at_m30_m02_in_mdi_nor_in_syntec_and_haas() {
    let runs = [
        (Dialect::Fanuc, Mode::Auto, "G90 G01 X10. F1000.\nM30\n"),
        (Dialect::Fanuc, Mode::Auto, "G90 G01 X10. F1000.\nM02\n"),
        (Dialect::Fanuc, Mode::Mdi, "G90 G01 X10. F1000.\n"),
        (Dialect::Syntec, Mode::Auto, "G90 G01 X10. F1000.\n"),
        (Dialect::Haas, Mode::Auto, "G90 G01 X10. F1000.\n"),
    ];
    for (dialect, mode, src) in runs {
        let c = run_in(dialect, mode, src);
        assert!(c.alarms().is_empty(), "{dialect:?} {mode:?} {src:?}: {:?}", c.alarms());
        assert_eq!(c.run_state(), RunState::Idle, "{dialect:?} {mode:?} {src:?}");
        assert!((c.point().machine[0] - 10.0).abs() < 1e-9, "{dialect:?} {mode:?} {src:?}");
    }
    // An MDI run does not leave the next memory run exempt.
    let mut c = run_in(Dialect::Fanuc, Mode::Mdi, "G90 G01 X10. F1000.\n");
    c.set_mode(Mode::Auto).unwrap();
    c.select_program("G90 G01 X20. F1000.\n").unwrap();
    c.cycle_start().unwrap();
    run_until_stopped(&mut c, 60.0);
    let got: Vec<_> = c.alarms().iter().map(|a| (a.code.as_str(), a.line)).collect();
    assert_eq!(got, [("PS5010", 1)]);
}

/// The tool length the panel shows (the position frame's `tool_length`) is the one the tip is
/// read with: after `G43 H1 Z100.` then `G49` without a motion the tip is read with no length,
/// and the shown length is 0 too — it stayed the last motion's 120.5 beside the G49 modal.
#[test]
fn the_tool_length_shown_is_the_one_the_tip_is_read_with_after_g49() {
    let mut c = controller();
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 120.5;
    c.select_program("G90 G54 G00 X0 Y0 Z200.\nG43 H1 Z100.\nG49\nM30\n").unwrap();
    c.cycle_start().unwrap();
    let mut during = None;
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(TICK);
        if c.point().line == 2 {
            during = Some(c.tool_length());
        }
        assert_eq!(c.tool_length(), c.tip_basis().tool_length, "line {}", c.point().line);
    }
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(during, Some(120.5), "the G43 block moves with the 120.5 mm tool");
    assert_eq!(c.tip_basis().tool_length, 0.0, "after G49 the tip is read without a length");
    assert_eq!(c.tool_length(), 0.0, "and the length shown says so");
}
