//! AI contour control switched by the command (FANUC G05.1 Q1 / Q0 on a machine with
//! No.1604#0 SHP = 0): without look-ahead, cutting feed is interpolated at the commanded feed
//! at once and each axis passes through the filter after interpolation (No.1610 type, No.1622
//! time constant: `docs/motion.md`, "Without look-ahead"). The tip of every sample is forward
//! kinematics of the filtered axes, so the trace shows the rounded corners and the shrunk
//! circles the manuals describe; with G05.1 Q1 the path is the programmed one again.

use crate::common;

use common::{cases, first_alarm_with, interpreter_with};
use fivex_engine::machine::{AfterInterpolation, MachineConfig};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use proptest::prelude::*;

/// mill3 with look-ahead only between G05.1 Q1 and Q0, and X, Y, Z filtered after
/// interpolation with time constant `ms` of type `kind`; every 1 ms sample.
fn run_filtered(src: &str, kind: AfterInterpolation, ms: f64) -> (RunResult, Vec<Sample>) {
    run_sampled(src, kind, ms, 0.001)
}

/// [`run_filtered`] sampled every `period_s` (0: no trace).
fn run_sampled(src: &str, kind: AfterInterpolation, ms: f64, period_s: f64) -> (RunResult, Vec<Sample>) {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.motion.look_ahead_by_command = true;
    m.motion.after_interpolation = kind;
    for a in &mut m.axes {
        a.after_interpolation_ms = ms;
    }
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = m.into());
    let mut samples = Vec::new();
    let opts = RunOptions { max_time_s: 600.0, period_s, ..RunOptions::default() };
    let r = run(&mut interp, &opts, |s| samples.push(*s));
    assert!(r.alarms.is_empty(), "{:?}", r.alarms);
    (r, samples)
}

/// Three turns of a radius-10 circle about X0 Y0 at F6000 (v = 100 mm/s): lines 3, 4, 5.
const CIRCLE: &str =
    "G90 G00 X10. Y0 Z0\nG01 G17 F6000\nG03 X10. Y0 I-10. J0\nG03 X10. Y0 I-10. J0\nG03 X10. Y0 I-10. J0\nM30\n";

/// The least and the greatest distance of the tip from the centre over the third turn.
fn radius_range(samples: &[Sample]) -> (f64, f64) {
    // (Not its last 50 ms: the filter's window there holds the stop at its end.)
    // (Moving: the samples of the stop after it, the filter settling, are the end point's.)
    let mut turn: Vec<f64> =
        samples.iter().filter(|s| s.line == 5 && s.feed > 0.0).map(|s| s.tip[0].hypot(s.tip[1])).collect();
    assert!(turn.len() > 500, "the third turn is sampled");
    turn.truncate(turn.len() - 50);
    (turn.iter().cloned().fold(f64::INFINITY, f64::min), turn.iter().cloned().fold(0.0, f64::max))
}

#[test]
fn without_look_ahead_a_circle_shrinks_by_the_manuals_radius_error() {
    // FANUC 0i-A connection manual p.314: Δr = (T1²/24 + T2²/2)·v²/r for linear
    // acceleration/deceleration after interpolation (T2, the servo's, is not modelled: 0).
    // T1 = 32 ms, v = 100 mm/s, r = 10 mm: 0.032²/24 · 100²/10 = 0.042667 mm. The filter is a
    // moving average of 32 positions 1 ms apart, 0.01 rad of the circle apart: its gain
    // sin 0.16 / (32·sin 0.005) = 0.99574294, so Δr = 0.042571 mm exactly, all round.
    let (_, samples) = run_filtered(CIRCLE, AfterInterpolation::Linear, 32.0);
    let (least, most) = radius_range(&samples);
    assert!((10.0 - least - 0.042571).abs() < 2e-6, "least radius {least}");
    assert!((10.0 - most - 0.042571).abs() < 2e-6, "greatest radius {most}");
    assert!((10.0 - least - 0.042667).abs() < 0.042667 * 0.01, "within 1 % of the formula");
    // Exponential, T1 = 8 ms: Δr = T1²/2 · v²/r = 0.008²/2 · 100²/10 = 0.032 mm; the first
    // order filter's gain 1/√(1 + (ωT)²), ωT = 0.08, gives 0.031847 mm, and by 1 ms steps
    // (gain g = 1 − e^(−1/8), |g / (1 − (1 − g)·e^(−0.01i))|) 0.031806 mm (the formula
    // keeps the first term of the series: 0.6 % more).
    let (_, samples) = run_filtered(CIRCLE, AfterInterpolation::Exponential, 8.0);
    let (least, most) = radius_range(&samples);
    assert!((10.0 - least - 0.032).abs() < 0.032 * 0.01, "least radius {least}");
    assert!((10.0 - least - 0.031806).abs() < 2e-6, "least radius {least}");
    assert!(most - least < 1e-6, "round: {least} … {most}");
}

#[test]
fn g05_1_q1_puts_the_circle_back_on_its_radius() {
    // The same circle with look-ahead on: the planner slows the arc to what the axes allow
    // and the tip stays on the circle (the samples' 1 µm bound); the filter does not act.
    let (_, samples) = run_filtered(&format!("G05.1 Q1\n{CIRCLE}"), AfterInterpolation::Linear, 32.0);
    let turn: Vec<f64> = samples.iter().filter(|s| s.line == 6).map(|s| s.tip[0].hypot(s.tip[1])).collect();
    assert!(turn.iter().all(|r| (r - 10.0).abs() < 1e-6));
}

/// Two legs of a square's corner at F6000 from X0 Y0: X10, then Y10 (lines 2, 3).
const CORNER: &str = "G90 G01 X10. Y0 F6000\nY10.\nM30\n";

#[test]
fn without_look_ahead_a_corner_is_rounded_and_the_stop_waits_for_the_filter() {
    // The filter averages the positions of the last T = 32 ms. Half way through the turn,
    // T/2 after the interpolation passed the corner at v = 100 mm/s, X has averaged
    // v·(T/2)²/2 / T = v·T/8 = 0.4 mm short of the corner and Y as much past it: the tip
    // passes √2 · 0.4 = 0.566 mm from the corner (by 1 ms steps 0.1·(0 + 1 + … + 15)/32 =
    // 0.375 to 0.1·(1 + … + 16)/32 = 0.425 mm on each axis, by where the corner falls
    // between two ticks).
    let (r, samples) = run_filtered(CORNER, AfterInterpolation::Linear, 32.0);
    let nearest = samples.iter().map(|s| (s.tip[0] - 10.0).hypot(s.tip[1])).fold(f64::INFINITY, f64::min);
    assert!((0.375 * 2f64.sqrt() - 1e-9..=0.425 * 2f64.sqrt() + 1e-9).contains(&nearest), "nearest {nearest}");
    // The time: 20 mm at 100 mm/s, the feed reached within a tick (0.894 ms: the commanded
    // feed at once, jerk 5·10⁸ mm/s³), then the filter's lag at the stop: its window empties
    // 31 ticks after the last interpolated position (32 inputs, the last one the end point).
    assert!((r.cycle_time_s - (0.2 + 0.000894 + 0.031)).abs() < 0.0015, "cycle {}", r.cycle_time_s);
    let last = samples.last().unwrap();
    assert!((last.tip[0] - 10.0).abs() < 1e-6 && (last.tip[1] - 10.0).abs() < 1e-6);
    // With look-ahead the tip turns the corner exactly (it slows there) and the machine is
    // at rest at the end when the interpolation is.
    let (q1, samples) = run_filtered(&format!("G05.1 Q1\n{CORNER}"), AfterInterpolation::Linear, 32.0);
    assert!(samples.iter().all(|s| s.tip[1].abs() < 1e-6 || (s.tip[0] - 10.0).abs() < 1e-6));
    // It is slower here: each leg ramps to F and back with mill3's A = 4000 mm/s², J = 80000
    // mm/s³ (Δv·J = 8·10⁶ ≤ A²: 2·√(100/80000) = 0.0707 s a ramp pair), L/v + 0.0707 =
    // 0.1707 s a leg, 0.341 s for both, a little less as the corner is passed at the 4 mm/s
    // step the planner allows (A · 1 ms) rather than at rest.
    assert!((0.335..0.3415).contains(&q1.cycle_time_s), "cycle with look-ahead {}", q1.cycle_time_s);
}

#[test]
fn look_ahead_switched_on_and_off_stops_the_machine_between() {
    // G05.1 Q1 between two legs: the first runs without look-ahead (filtered), the second
    // with it; the machine comes to rest at X10 with the filter settled, so the second leg
    // starts from the corner itself and its samples are on the line X = 10.
    let (_, samples) =
        run_filtered("G90 G01 X10. Y0 F6000\nG05.1 Q1\nY10.\nG05.1 Q0\nX0\nM30\n", AfterInterpolation::Bell, 32.0);
    let second: Vec<&Sample> = samples.iter().filter(|s| s.line == 3).collect();
    assert!(!second.is_empty() && second.iter().all(|s| (s.tip[0] - 10.0).abs() < 1e-6));
    // And back off for the third: rounded again at its start only by the filter's own ramp,
    // ending on X0 Y10.
    let last = samples.last().unwrap();
    assert!(last.tip[0].abs() < 1e-6 && (last.tip[1] - 10.0).abs() < 1e-6);
}

#[test]
fn the_functions_that_need_look_ahead_still_refuse_without_it() {
    // G54.4 with tool direction compensation (RCM) before G05.1 Q1 on an SHP = 0 machine:
    // PS0438, with the filter after interpolation set or not (WSE-11).
    let tweak = |c: &mut fivex_engine::interp::Config| {
        c.edit_machine(|m| {
            m.motion.look_ahead_by_command = true;
            m.five_axis.tool_direction_compensation = true;
            for a in &mut m.axes {
                a.after_interpolation_ms = 32.0;
            }
        })
    };
    assert_eq!(first_alarm_with("G54.4 P1\nG54.4 P0\nM30\n", "head-bc", tweak), Some(("PS0438".into(), 1)));
    assert_eq!(first_alarm_with("G05.1 Q1\nG54.4 P1\nG54.4 P0\nM30\n", "head-bc", tweak), None);
    // TCP needs look-ahead set up for cutting feed (TCP-14): PS5420 without it.
    let no_feed = |c: &mut fivex_engine::interp::Config| {
        c.edit_machine(|m| {
            m.motion.no_feed_look_ahead = true;
            for a in &mut m.axes {
                a.after_interpolation_ms = 32.0;
            }
        })
    };
    assert_eq!(first_alarm_with("G43.4 H1\nM30\n", "head-bc", no_feed), Some(("PS5420".into(), 1)));
}

#[test]
fn a_controller_moves_through_the_filter_exactly_as_run_does() {
    // The hosted controller drives the same executor tick by tick: the same filtered axes at
    // every 1 ms, the same waits for the filter at the stops (the dwell, G05.1 Q1's, the end).
    let src = "G90 G01 X10. Y0 F6000\nG03 X0 Y10. R10.\nG04 X0.05\nX-5. Y5.\nG05.1 Q1\nX0 Y0\nM30\n";
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.motion.look_ahead_by_command = true;
    m.motion.after_interpolation = AfterInterpolation::Bell;
    for a in &mut m.axes {
        a.after_interpolation_ms = 24.0;
    }
    let cfg = fivex_engine::interp::Config::new(m, Dialect::Fanuc);
    let mut interp = fivex_engine::interp::Interpreter::new(fivex_engine::lang::parse_file(src), cfg.clone());
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    let mut c = fivex_engine::controller::Controller::new(cfg);
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    let mut k = 1;
    let mut rounded = false;
    while c.run_state() == fivex_engine::controller::RunState::Running {
        c.tick(0.001);
        if let Some(s) = samples.get(k) {
            for i in 0..3 {
                assert!((c.point().machine[i] - s.machine[i]).abs() < 1e-9, "t={} axis {i}", s.t);
            }
            // The corner at X10 Y0 cut inside the arc by more than 0.1 mm (the arc's own radius
            // error, two averages of 12 ms at 100 mm/s on r = 10, is 0.012 mm): the filter is
            // in the controller's axes too.
            rounded |= s.line == 2 && s.machine[0].hypot(s.machine[1]) < 9.9;
        }
        k += 1;
    }
    assert!(rounded);
    assert_eq!(c.point().machine[..3], r.machine[..3]);
    assert!((c.time() - r.cycle_time_s).abs() <= 0.001, "{} vs {}", c.time(), r.cycle_time_s);
}

#[test]
fn a_feed_hold_without_look_ahead_stops_the_interpolation_and_the_filter_brings_the_axes_to_rest() {
    // X10 at F6000 without look-ahead, linear 32 ms: a feed hold 50 ms in stops the
    // interpolation within two ticks (its limits: the feed at once), and the axes follow it to
    // rest through the filter, the held point reached 31 ticks later; then they stand still,
    // and cycle start finishes the move exactly on X10.
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.motion.look_ahead_by_command = true;
    m.motion.after_interpolation = AfterInterpolation::Linear;
    for a in &mut m.axes {
        a.after_interpolation_ms = 32.0;
    }
    let mut c = fivex_engine::controller::Controller::new(fivex_engine::interp::Config::new(m, Dialect::Fanuc));
    c.select_program("G90 G01 X10. F6000\nM30\n").unwrap();
    c.cycle_start().unwrap();
    for _ in 0..50 {
        c.tick(0.001);
    }
    let lagging = c.point().machine[0];
    c.feed_hold();
    let mut xs = vec![lagging];
    for _ in 0..60 {
        c.tick(0.001);
        xs.push(c.point().machine[0]);
    }
    assert_eq!(c.run_state(), fivex_engine::controller::RunState::Hold);
    // Moving forward all the way (a mean of points that only advance), still moving for a
    // while after the hold (the filter's lag: at 100 mm/s the axis is 1.55 mm behind the
    // interpolation), then still.
    assert!(xs.windows(2).all(|w| w[1] >= w[0] - 1e-12));
    assert!(xs[20] - lagging > 1.0, "still moving 20 ms after the hold: {} → {}", lagging, xs[20]);
    assert!((xs[35] - xs[60]).abs() < 1e-9, "at rest 2 + 31 ticks after it (+ a tick of slack)");
    let held = c.point().machine;
    c.tick(0.5);
    assert_eq!(c.point().machine, held, "held means still");
    assert!(held[0] < 10.0);
    c.cycle_start().unwrap();
    while c.run_state() == fivex_engine::controller::RunState::Running {
        c.tick(0.001);
    }
    assert!((c.point().machine[0] - 10.0).abs() < 1e-6);
}

/// The distance from `p` to the segment `a`–`b` in X/Y.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a[0] + t * dx - p[0]).hypot(a[1] + t * dy - p[1])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(16)))]

    /// Random polylines at random feeds through a random filter (with rapids and G05.1 Q1/Q0
    /// among the moves): every sample within v·T of
    /// the programmed path (a linear or bell filter averages points of the last T, at most v·T
    /// of path apart, and an exponential one's weights beyond 8·T are below e⁻⁸), the run ends
    /// exactly on the last point, and the trace's period does not change the motion (the
    /// filter runs on its own 1 ms ticks): the same cycle time and end sampled every 1 ms,
    /// every 3 ms or not at all.
    #[test]
    fn the_filtered_path_stays_near_the_programmed_one_whatever_the_trace(
        points in prop::collection::vec((-50.0f64..50.0, -50.0f64..50.0, 0u8..6), 2..7),
        feed in 300.0f64..9000.0,
        kind in prop_oneof![
            Just(AfterInterpolation::Linear),
            Just(AfterInterpolation::Bell),
            Just(AfterInterpolation::Exponential)
        ],
        ms in 1.0f64..100.0,
    ) {
        let mut src = format!("G90 G01 F{feed:.0}\n");
        let mut path = vec![[0.0, 0.0]];
        for (x, y, how) in &points {
            // Mostly cutting feed; now and then a rapid, or look-ahead switched on or off
            // before the move (the machine stops between the two kinds of motion).
            let word = match how {
                0 => "G00 ",
                1 => "G05.1 Q1\nG01 ",
                2 => "G05.1 Q0\nG01 ",
                _ => "G01 ",
            };
            src += &format!("{word}X{x:.3} Y{y:.3}\n");
            path.push([(x * 1000.0).round() / 1000.0, (y * 1000.0).round() / 1000.0]);
        }
        src += "M30\n";
        let (r, samples) = run_filtered(&src, kind, ms);
        let reach = feed / 60.0 * ms * 0.001 * if kind == AfterInterpolation::Exponential { 8.0 } else { 1.0 };
        for s in &samples {
            let d = path.windows(2).map(|w| to_segment([s.tip[0], s.tip[1]], w[0], w[1])).fold(f64::INFINITY, f64::min);
            prop_assert!(d <= reach + 1e-6, "t={} {:?}: {d} from the path, bound {reach}", s.t, s.tip);
        }
        let end = path[path.len() - 1];
        prop_assert!((r.machine[0] - end[0]).abs() < 1e-6 && (r.machine[1] - end[1]).abs() < 1e-6);
        // The last sample: at the end once the filter has settled there; a last move with
        // look-ahead ends between two samples, the last one at most a tick of feed before it.
        let last = samples.last().unwrap();
        let tick = feed / 60.0 * 0.001 + 1e-6;
        prop_assert!((last.tip[0] - end[0]).hypot(last.tip[1] - end[1]) < tick, "{:?}", last.tip);
        for period in [0.003, 0.0] {
            let (other, _) = run_sampled(&src, kind, ms, period);
            prop_assert_eq!(other.cycle_time_s, r.cycle_time_s);
            prop_assert_eq!(other.machine, r.machine);
        }
    }
}

/// mill3 with look-ahead only between G05.1 Q1 and Q0 and rapid time constants `[T1, T2]` on
/// X and Y (`x`, `y`); every 1 ms sample.
fn run_rapid(src: &str, x: [f64; 2], y: [f64; 2]) -> (RunResult, Vec<Sample>) {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.motion.look_ahead_by_command = true;
    (m.axes[0].rapid_after_interpolation_ms, m.axes[1].rapid_after_interpolation_ms) = (x, y);
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = m.into());
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    assert!(r.alarms.is_empty(), "{:?}", r.alarms);
    (r, samples)
}

#[test]
fn without_look_ahead_a_rapid_moves_through_its_own_time_constants() {
    // G00 X100 at mill3's 30000 mm/min (500 mm/s), T1 = 100 ms (No.1620), linear: the
    // interpolation takes 0.2 s + 2 ms (Δv·J = 500 · 5·10⁸ = A²: 2·√(500/5·10⁸)), then the
    // window of 100 positions empties 99 ticks after the last: 0.301 s. With look-ahead the
    // axis's own S-curve (A = 4000, J = 80000: Δv/A + A/J = 0.125 + 0.05 s): 0.375 s.
    let (r, _) = run_rapid("G00 X100.\nM30\n", [100.0, 0.0], [100.0, 0.0]);
    assert!((r.cycle_time_s - 0.301).abs() < 0.0015, "cycle {}", r.cycle_time_s);
    let (q1, _) = run_rapid("G05.1 Q1\nG00 X100.\nM30\n", [100.0, 0.0], [100.0, 0.0]);
    assert!((q1.cycle_time_s - 0.375).abs() < 1e-6, "cycle {}", q1.cycle_time_s);
    // T2 = 40 ms more (No.1621, bell-shaped): 39 ticks more to empty the second window.
    let (bell, _) = run_rapid("G00 X100.\nM30\n", [100.0, 40.0], [100.0, 0.0]);
    assert!((bell.cycle_time_s - 0.340).abs() < 0.0015, "cycle {}", bell.cycle_time_s);
}

#[test]
fn a_rapid_leaves_its_line_where_the_axes_time_constants_differ() {
    // G00 X50 Y50, both axes at 500 mm/s for 0.1 s, X filtered over 100 ms and Y over 50 ms
    // (each axis accelerates on its own: the 15i descriptions' "the path may not match the
    // specified line"). At 0.1 s X has averaged 500·t over [0, 0.1] = 25 mm and Y over
    // [0.05, 0.1] = 37.5 mm: 12.5/√2 = 8.84 mm off the diagonal (by 1 ms steps 24.75 and
    // 37.25 mm, the same 12.5).
    let (_, samples) = run_rapid("G00 X50. Y50.\nM30\n", [100.0, 0.0], [50.0, 0.0]);
    let off = samples.iter().map(|s| (s.tip[1] - s.tip[0]) / 2f64.sqrt()).fold(0.0, f64::max);
    assert!((off - 12.5 / 2f64.sqrt()).abs() < 0.01, "off the line by {off}");
    let last = samples.last().unwrap();
    assert!((last.tip[0] - 50.0).abs() < 1e-6 && (last.tip[1] - 50.0).abs() < 1e-6);
}
