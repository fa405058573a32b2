//! The run report (`engine/src/report.rs`, `docs/fleet.md`): a run with a report gives the
//! same result as a plain run, bit for bit, and each figure is checked against a value worked
//! out by hand.

use crate::common;

use common::*;
use fivex_engine::canon::{Motion, Pos};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::motion::Segment;
use fivex_engine::report::{run_with_report, Recorder, Report};
use fivex_engine::run::{run, run_observed, Observer, RunOptions, Sample};
use fivex_engine::Dialect;

const PERIOD: f64 = 0.001;

fn opts() -> RunOptions {
    RunOptions { period_s: PERIOD, max_time_s: 600.0, ..RunOptions::default() }
}

fn report_on(src: &str, preset: &str) -> Report {
    run_with_report(&mut interpreter(src, preset, Dialect::Fanuc), &opts()).1
}

fn report_on_machine(src: &str, m: MachineConfig) -> Report {
    let mut interp = Interpreter::new(parse_file(src), Config::new(m, Dialect::Fanuc));
    interp.state.offsets.tool_mut(1).unwrap().h_geometry = 100.0;
    run_with_report(&mut interp, &opts()).1
}

fn axis(r: &Report, name: char) -> &fivex_engine::report::AxisReport {
    r.axes.iter().find(|a| a.name == name).unwrap()
}

#[test]
fn a_report_does_not_change_the_run() {
    for (path, src) in fixture_programs() {
        for (preset, dialect) in [("mill3", Dialect::Fanuc), ("head-bc", Dialect::Syntec), ("table-ac", Dialect::Fanuc)]
        {
            let plain = run(&mut interpreter(&src, preset, dialect), &RunOptions { period_s: 0.0, ..opts() }, |_| {});
            let (reported, report) = run_with_report(&mut interpreter(&src, preset, dialect), &opts());
            assert_eq!(plain, reported, "{path} on {preset}");
            assert_eq!(report.cycle_time_s.to_bits(), plain.cycle_time_s.to_bits());
            assert_eq!(report.status == "completed", plain.completed(), "{path}");
            assert_eq!(report.alarm.as_ref(), plain.alarms.first(), "{path}");
        }
    }
}

#[test]
fn travel_speeds_and_margins_of_a_straight_line() {
    // X 0 → 550 at 600 mm/min, then back to 500: travel 600, the margin to X+600 is 50. The
    // travel is sampled: the turn inside one period (the machine at rest there) is cut short
    // by far less than a micrometre.
    let r = report_on("G90 G01 X550. F600.\nX500.\nM30\n", "mill3");
    let x = axis(&r, 'X');
    assert!((x.travel - 600.0).abs() < 1e-3, "{}", x.travel);
    assert!((x.max_speed - 600.0).abs() < 1e-6, "{}", x.max_speed);
    assert!(x.mean_speed > 0.0 && x.mean_speed <= x.max_speed);
    assert_eq!((x.min, x.max), (0.0, 550.0));
    assert_eq!(x.limits, Some([-600.0, 600.0]));
    assert!((x.margin.unwrap() - 50.0).abs() < 1e-9);
    assert_eq!(x.margin_side, Some("positive"));
    assert_eq!(axis(&r, 'Y').travel, 0.0);
    assert_eq!(axis(&r, 'Y').mean_speed, 0.0);
    assert_eq!(r.status, "completed");
    assert_eq!(r.near_singular_deg, None, "a 3-axis machine has no singular posture");
}

#[test]
fn a_rotary_swing_without_tcp_deviates_by_the_sagitta() {
    // head-bc: the B pivot is 150 mm above the nose, the tool 100 mm long, so the tip is 250 mm
    // from the pivot. B 0 → 30 without TCP swings it on an arc; the programmed path is the
    // chord, and the largest distance from it is the sagitta 250·(1 − cos 15°).
    let r = report_on("G90 G43 H1 Z150.\nG01 B30. F1000.\nM30\n", "head-bc");
    let expected = 250.0 * (1.0 - 15f64.to_radians().cos());
    assert!((r.tip_deviation.max - expected).abs() < 1e-3, "{} vs {expected}", r.tip_deviation.max);
    assert_eq!(r.tip_deviation.line, Some(2));
    let b = axis(&r, 'B');
    assert!((b.travel - 30.0).abs() < 1e-9, "{}", b.travel);
    assert!((b.max_speed - 1000.0).abs() < 1e-6, "{}", b.max_speed);
    assert_eq!(b.margin, Some(80.0));
}

#[test]
fn under_tcp_the_tip_stays_on_the_programmed_line() {
    let r = report_on("G90 G43.4 H1 X0. Y0. Z50.\nG01 X10. B30. F1000.\nX-10. B-20. C90.\nG49\nM30\n", "head-bc");
    assert_eq!(r.status, "completed", "{:?}", r.alarm);
    assert!(r.tip_deviation.max < 1e-6, "{}", r.tip_deviation.max);
}

#[test]
fn linear_moves_deviate_by_nothing() {
    let r = report_on("G90 G43 H1 Z50.\nG01 X10. Y5. F1000.\nG02 X20. Y5. R5.\nM30\n", "table-ac");
    assert_eq!(r.tip_deviation.max, 0.0);
    assert_eq!(r.tip_deviation.line, None);
}

#[test]
fn time_near_the_singular_posture() {
    // head-bc at B0 has the tool along C: singular the whole time (the default 1°).
    let r = report_on("G90 G01 X10. F600.\nG04 X1.\nM30\n", "head-bc");
    assert_eq!(r.near_singular_deg, Some(1.0));
    assert!((r.near_singular_s - r.cycle_time_s).abs() <= PERIOD + 1e-9, "{} vs {}", r.near_singular_s, r.cycle_time_s);
    assert_eq!(r.min_singular_angle_deg, Some(0.0));
    // Tilted 30° the whole time after a quick move: only the move's first degree counts.
    let r = report_on("G90 G00 B30.\nG01 X10. F600.\nM30\n", "head-bc");
    assert!(r.near_singular_s < 0.1 * r.cycle_time_s, "{}", r.near_singular_s);
    // The machine's own angle: No.19738 first.
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.five_axis.singular_angle = 5.0;
    m.five_axis.singular_tolerance_deg = 2.0;
    assert_eq!(report_on_machine("G01 X1. F600.\nM30\n", m.clone()).near_singular_deg, Some(5.0));
    m.five_axis.singular_angle = 0.0;
    assert_eq!(report_on_machine("G01 X1. F600.\nM30\n", m).near_singular_deg, Some(2.0));
}

#[test]
fn unwinds_are_half_turns_back() {
    // table-ac with a C that does not roll over: C 170 → −170 turns 340° back: one unwind;
    // then 70° forward and 100° back: turns against the last direction, but under 180°.
    let mut m = MachineConfig::preset("table-ac").unwrap();
    let c = m.axis_index(b'C').unwrap();
    m.axes[c].rollover = false;
    m.axes[c].shortest = false;
    m.axes[c].stroke = Some([-400.0, 400.0]);
    let r = report_on_machine("G90 G01 C170. F7200.\nC-170.\nC-100.\nC-200.\nM30\n", m.clone());
    assert_eq!(axis(&r, 'C').unwinds, 1);
    // Sampled: each of the three turns inside a period is cut short by about accel·period².
    assert!(
        (axis(&r, 'C').travel - (170.0 + 340.0 + 70.0 + 100.0)).abs() < 3.0 * 1800.0 * PERIOD * PERIOD,
        "{}",
        axis(&r, 'C').travel
    );
    assert_eq!((axis(&r, 'C').min, axis(&r, 'C').max), (-200.0, 170.0));
    assert_eq!((axis(&r, 'C').margin, axis(&r, 'C').margin_side), (Some(200.0), Some("negative")));
    // Half a turn forward after a turn back is an unwind too; the same way on, not.
    let r = report_on_machine("G90 G01 C-10. F7200.\nC190.\nC380.\nM30\n", m);
    assert_eq!(axis(&r, 'C').unwinds, 1);
    // A rollover axis taking the short way never unwinds.
    let r = report_on("G90 G01 C170. F7200.\nC-170.\nC300.\nM30\n", "table-ac");
    assert_eq!(axis(&r, 'C').unwinds, 0);
}

/// Fleet audit: a rollover C from 10 to 350 the short way (through 0) reported min −10, max 10,
/// angles the machine never shows (its display and the trace read 0…360). The range is the
/// shown one; the travel stays unwound (30°).
#[test]
fn a_rollover_axis_reports_the_positions_it_shows() {
    let r = report_on("G90 G00 C10.\nG01 C350. F3000\nM30\n", "table-ac");
    let c = axis(&r, 'C');
    assert!(c.min >= 0.0 && c.min < 0.1 && c.max > 359.9 && c.max < 360.0, "{} {}", c.min, c.max);
    assert!((c.travel - 30.0).abs() < 0.01, "{}", c.travel);
    let r = report_on("G90 G00 C10.\nG01 C40. F3000\nM30\n", "table-ac");
    assert_eq!((axis(&r, 'C').min, axis(&r, 'C').max), (0.0, 40.0));
}

#[test]
fn an_alarm_is_reported_with_its_line() {
    let r = report_on("G90 G01 X10. F600.\nX700.\nM30\n", "mill3");
    assert_eq!(r.status, "alarm");
    let alarm = r.alarm.clone().unwrap();
    assert_eq!((alarm.code.as_str(), alarm.line), ("OT0510", 2));
    // The refused block never moved: X stops at 10.
    assert_eq!(axis(&r, 'X').max, 10.0);
}

#[test]
fn the_speed_profile_shows_each_axis_speed_over_time() {
    // X100 at 6000 mm/min takes about a second: the X speed reaches 6000 in the middle of it,
    // Y stays 0, and the profile's travel adds up to the axis's travel.
    let r = report_on("G90 G01 X100. F6000.\nG04 X1.\nM30\n", "mill3");
    let p = &r.speeds;
    assert!((p.period_s - fivex_engine::report::SpeedProfile::FIRST_PERIOD_S).abs() < 1e-12);
    let x = &p.axes.iter().find(|a| a.axis == 'X').unwrap().speeds;
    let y = &p.axes.iter().find(|a| a.axis == 'Y').unwrap().speeds;
    let top = x.iter().cloned().fold(0.0, f64::max);
    assert!((top - 6000.0).abs() < 1.0, "{top}");
    assert!(y.iter().all(|&v| v == 0.0));
    let travel: f64 = x.iter().map(|v| v / 60.0 * p.period_s).sum();
    assert!((travel - axis(&r, 'X').travel).abs() < 1e-6, "{travel}");
    // The dwell: the machine stands.
    assert_eq!(*x.last().unwrap(), 0.0);
}

#[test]
fn a_long_run_keeps_its_speed_profile_to_a_thousand_points() {
    let src: String = (0..40).map(|i| format!("G01 X{}. F600.\n", if i % 2 == 0 { 100 } else { 0 })).collect();
    let r = report_on(&src, "mill3");
    let p = &r.speeds;
    let n = p.axes[0].speeds.len();
    assert!(
        r.cycle_time_s > 300.0 && (100..=fivex_engine::report::SpeedProfile::MAX_POINTS).contains(&n),
        "{n} points over {} s",
        r.cycle_time_s
    );
    assert!(p.period_s > fivex_engine::report::SpeedProfile::FIRST_PERIOD_S);
    let travel: f64 = p.axes[0].speeds.iter().map(|v| v / 60.0 * p.period_s).sum();
    assert!((travel - axis(&r, 'X').travel).abs() < 1e-6, "{travel}");
}

#[test]
fn a_kinematic_path_planned_in_pieces_unwinds_once() {
    // Under TCP C turns 340° back while the tip crosses the table: the planner runs the block
    // in pieces with limits of their own (`Segment::split`), none turning 180°; the report
    // counts the motion's turn, one unwind.
    struct Pieces {
        rec: Recorder,
        continued: usize,
    }
    impl Observer for Pieces {
        fn queued(&mut self, motion: &Motion, segment: &Segment) {
            self.rec.queued(motion, segment)
        }
        fn sample(&mut self, sample: &Sample, machine: &Pos, on: Option<(&Segment, f64, u64)>) {
            self.rec.sample(sample, machine, on)
        }
        fn executed(&mut self, segment: &Segment) {
            self.continued += usize::from(segment.continued());
            self.rec.executed(segment)
        }
    }
    let mut m = MachineConfig::preset("table-ac").unwrap();
    let c = m.axis_index(b'C').unwrap();
    m.axes[c].rollover = false;
    m.axes[c].shortest = false;
    m.axes[c].stroke = Some([-400.0, 400.0]);
    let src = "G90 G01 C170. F7200.\nG43.4 H1\nX-100. Y0 Z50.\nG01 X100. C-170. F3000.\nG49\nM30\n";
    let mut interp = Interpreter::new(parse_file(src), Config::new(m, Dialect::Fanuc));
    interp.state.offsets.tool_mut(1).unwrap().h_geometry = 100.0;
    let mut obs = Pieces { rec: Recorder::new(&interp, PERIOD), continued: 0 };
    let result = run_observed(&mut interp, &opts(), |_| {}, &mut obs);
    assert!(result.completed(), "{:?}", result.alarms);
    assert!(obs.continued > 0, "the block ran whole: nothing to check");
    let r = obs.rec.finish(&result);
    assert_eq!(axis(&r, 'C').unwinds, 1);
}
