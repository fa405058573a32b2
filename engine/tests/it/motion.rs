//! Motion (`fivex_engine::motion` through `run::run`): cycle times against closed-form S-curve
//! times, sampled axis motion within every velocity / acceleration / jerk limit, the tool tip on
//! the programmed path, look-ahead depth, exact stops and stroke limits.
//!
//! Preset linear axes (mill3, `docs/machine-config.md`): rapid 30000 mm/min (500 mm/s),
//! acceleration A = 4000 mm/s², jerk J = 80000 mm/s³, X stroke ±600.

use crate::common;

use common::{alarm_with, check_limits, interpreter, interpreter_with, run_with};
use fivex_engine::alarm::AlarmId;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use proptest::prelude::*;

const A: f64 = 4000.0;
const J: f64 = 80000.0;
const PERIOD: f64 = 0.001;

fn traced(src: &str, preset: &str) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter(src, preset, Dialect::Fanuc);
    let mut samples = Vec::new();
    let opts = RunOptions { period_s: PERIOD, ..RunOptions::default() };
    let r = run(&mut interp, &opts, |s| samples.push(*s));
    (r, samples)
}

/// Time of a speed change 0 → v with zero acceleration at both ends, written out independently
/// of the engine: two jerk phases of √(v/J) when v·J ≤ A², else v/A + A/J.
fn ramp_time(v: f64, a: f64, j: f64) -> f64 {
    if v * j <= a * a {
        2.0 * (v / j).sqrt()
    } else {
        v / a + a / j
    }
}

/// Rest-to-rest time over `len` at cruise speed `v` (long enough to reach it): the ramps are
/// symmetric, so the move lags the ideal one by exactly one ramp time.
fn move_time(len: f64, v: f64, a: f64, j: f64) -> f64 {
    len / v + ramp_time(v, a, j)
}

fn close(got: f64, want: f64) {
    assert!((got - want).abs() < 1e-9, "got {got}, want {want}");
}

#[test]
fn a_single_move_takes_its_closed_form_time() {
    // 100 mm/s: v·J = 8e6 ≤ A² = 16e6, the short ramp.
    let (r, _) = traced("G90 G01 X200. F6000.\nM30\n", "mill3");
    close(r.cycle_time_s, move_time(200.0, 100.0, A, J));
    // A diagonal rapid: each axis at 1/√2 of the path, so the path may go √2 times as fast,
    // accelerate and jerk √2 times as much; 500·√2 mm/s is reached (the ramp covers 100 mm).
    let (r, _) = traced("G90 G00 X400. Y400.\nM30\n", "mill3");
    let k = 2f64.sqrt();
    close(r.cycle_time_s, move_time(400.0 * k, 500.0 * k, A * k, J * k));
}

#[test]
fn exact_stop_modes_stop_at_every_block_and_g64_does_not_on_a_straight_line() {
    // Two collinear blocks: in G64 one continuous move, in G61 (or with G09) two.
    let straight = |mode: &str| format!("G90 {mode} G01 X100. F6000.\nX200.\nM30\n");
    let single = move_time(200.0, 100.0, A, J);
    let twice = 2.0 * move_time(100.0, 100.0, A, J);
    close(traced(&straight("G64"), "mill3").0.cycle_time_s, single);
    close(traced(&straight("G61"), "mill3").0.cycle_time_s, twice);
    close(traced("G90 G09 G01 X100. F6000.\nX200.\nM30\n", "mill3").0.cycle_time_s, twice);
    // A square in G61: four rest-to-rest moves.
    let square = "G90 G61 G01 X50. F3000.\nY50.\nX0.\nY0.\nM30\n";
    close(traced(square, "mill3").0.cycle_time_s, 4.0 * move_time(50.0, 50.0, A, J));
}

#[test]
fn helical_feed_is_along_the_arc_unless_htg_is_set() {
    // A full turn of radius 50 (arc 100π) going 30 down, at F600 (10 mm/s along the arc): the
    // path, √((100π)² + 30²), is travelled at 10·path/arc mm/s with HTG = 0 (arc time 10π s),
    // at 10 mm/s with HTG = 1.
    let src = "G90 G17 G92 X50. Y0. Z0.\nG03 I-50. Z-30. F600.\nM30\n";
    let arc = 100.0 * std::f64::consts::PI;
    let path = (arc * arc + 900.0f64).sqrt();
    // On an arc the plane's top speed turns with half of the plane axes' acceleration (the
    // faster choice here): w = √(A·r/2) = 316.2 mm/s, below ∛(J·r²/2) = 464.2, so w²/r = 2000
    // and w³/r² = 12649. Speed changes get a ≤ the cross term's 3·w·a/r within half of
    // √(J² − (w³/r²)²) (2081.7 mm/s², below √(A² − (w²/r)²) = 3464.1) and the jerk left,
    // j = √(J² − (3·w·a/r)²) − w³/r² = 56921 mm/s³ (`docs/motion.md`, Limits).
    let (r, w) = (50.0, (0.5 * A * 50.0f64).sqrt());
    let (pull, turn) = (w * w / r, w.powi(3) / (r * r));
    let plane_a = (0.5 * (J * J - turn * turn).sqrt() * r / (3.0 * w)).min((A * A - pull * pull).sqrt());
    let plane_j = (J * J - (3.0 * w * plane_a / r).powi(2)).sqrt() - turn;
    for (htg, v) in [(false, 10.0 * path / arc), (true, 10.0)] {
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.motion.helical_feed_on_path = htg;
        let mut cfg = fivex_engine::interp::Config::new(m, Dialect::Fanuc);
        cfg.max_blocks = 1000;
        let mut interp = fivex_engine::interp::Interpreter::new(fivex_engine::lang::parse_file(src), cfg);
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        // The plane axes move arc/path per unit of path (Z only 30/path, looser), so the path
        // may accelerate and jerk path/arc times as much as the plane.
        close(r.cycle_time_s, move_time(path, v, plane_a * path / arc, plane_j * path / arc));
    }
}

#[test]
fn non_linear_rapids_move_each_axis_on_its_own() {
    // G00 X100 Y10: X alone takes 100/500 + 500/A + A/J = 0.375 s (it reaches 500 mm/s);
    // Y alone 10 mm, two S-curves to vp with vp·√(vp/J) = 5: 4·√(vp/J) = 0.159 s.
    let x_time = 100.0 / 500.0 + 500.0 / A + A / J;
    let vp = (5.0 * J.sqrt()).powf(2.0 / 3.0);
    let y_time = 4.0 * (vp / J).sqrt();
    let src = "G90 G00 X100. Y10.\nM30\n";
    for nonlinear in [false, true] {
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.motion.nonlinear_rapid = nonlinear;
        let mut interp = fivex_engine::interp::Interpreter::new(
            fivex_engine::lang::parse_file(src),
            fivex_engine::interp::Config::new(m, Dialect::Fanuc),
        );
        let mut samples = Vec::new();
        let r = run(&mut interp, &RunOptions { period_s: PERIOD, ..RunOptions::default() }, |s| samples.push(*s));
        // Either way the block lasts as long as its slowest axis alone (X dominates the line).
        close(r.cycle_time_s, x_time);
        let at = samples.iter().find(|s| (s.t - 0.2).abs() < 1e-9).unwrap();
        if nonlinear {
            // Y has arrived (after y_time) while X still moves: a dog-leg, not a line.
            assert!(y_time < 0.2);
            assert_eq!(at.machine[1], 10.0);
            assert!(at.machine[0] < 100.0);
        } else {
            assert!((at.machine[1] - at.machine[0] / 10.0).abs() < 1e-9, "on the line");
        }
    }
}

#[test]
fn the_feed_override_does_not_act_in_g63_or_tapping_cycles() {
    let timed = |src: &str, feed_override: f64| {
        let mut interp = interpreter(src, "mill3", Dialect::Fanuc);
        let opts = RunOptions { period_s: 0.0, feed_override, ..RunOptions::default() };
        run(&mut interp, &opts, |_| {}).cycle_time_s
    };
    // 100 mm at F3000: at 50% 25 mm/s in G64, the programmed 50 mm/s in G63.
    close(timed("G90 G64 G01 X100. F3000.\nM30\n", 0.5), move_time(100.0, 25.0, A, J));
    close(timed("G90 G63 G01 X100. F3000.\nM30\n", 0.5), move_time(100.0, 50.0, A, J));
    // A G84 tapping cycle takes as long at 50% as at 100%; a G81 drilling cycle does not.
    let cycle = |code: &str| format!("G90 G00 X0. Y0. Z10.\nS1000 M03\nG99 {code} R2. Z-20. F600.\nG80\nM30\n");
    close(timed(&cycle("G84"), 0.5), timed(&cycle("G84"), 1.0));
    assert!(timed(&cycle("G81"), 0.5) > timed(&cycle("G81"), 1.0) + 1.0);
}

#[test]
fn look_ahead_spans_more_than_200_blocks() {
    // 1000 collinear blocks of 0.02 mm at 6000 mm/min: stopping from 100 mm/s takes
    // 100·√(100/J) = 3.54 mm = 177 blocks, so full feed needs a look-ahead of 177 blocks or more.
    let mut src = String::from("G90 G01 F6000.\n");
    for i in 1..=1000 {
        src.push_str(&format!("X{:.2}\n", i as f64 * 0.02));
    }
    src.push_str("M30\n");
    let (r, samples) = traced(&src, "mill3");
    assert!(r.completed());
    let top = samples.iter().map(|s| s.feed).fold(0.0, f64::max);
    assert!((top - 6000.0).abs() < 1e-6, "top feed {top}");
    close(r.cycle_time_s, move_time(20.0, 100.0, A, J));
}

#[test]
fn a_move_beyond_the_stroke_alarms_before_it_starts() {
    let (r, samples) = traced("G90 G01 X500. F6000.\nN20 X700.\nM30\n", "mill3");
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line, r.alarms[0].n), ("OT0510", 2, Some(20)));
    assert_eq!(r.alarms[0].message, "+ OVERTRAVEL ( PRE-CHECK ) X");
    // The machine stopped at the end of the block before, at rest.
    assert_eq!(r.machine[0], 500.0);
    close(r.cycle_time_s, move_time(500.0, 100.0, A, J));
    assert!(samples.iter().all(|s| s.machine[0] <= 500.0 && s.line == 1));
    // An arc whose ends are inside but whose bulge is not: Y stroke ±450.
    let arc = "G90 G00 X-100. Y400.\nN20 G02 X100. Y400. R100. F1000.\nM30\n";
    let (r, _) = traced(arc, "mill3");
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("OT0510", 2));
    let neg = traced("G90 G01 Z-600. F1000.\nM30\n", "mill3").0;
    assert_eq!(neg.alarms[0].code, "OT0511");
    let mut interp = interpreter("G90 G01 Z-600. F1000.\nM30\n", "mill3", Dialect::Syntec);
    let syntec = run(&mut interp, &RunOptions::default(), |_| {});
    assert_eq!(syntec.alarms[0].code, "MOT-002");
}

/// `fivex check` on a machine (`check::run_without_motion`) reports the stored stroke limit the
/// run stops with, at its line, without planning: a rapid to X5000 (X stroke ±600), an arc whose
/// bulge alone passes Y450, Z-600 (stroke -500), an offset that carries X150 to machine 650, a
/// G20 X24. (609.6 mm), B120 on head-bc (range ±110°), a tip-following swing whose pivot passes
/// the Z limit between its ends; each compared with the run.
#[test]
fn check_reports_the_over_travel_the_run_stops_with() {
    let check = |src: &str, preset: &str, tweak: &dyn Fn(&mut fivex_engine::interp::Config)| {
        let mut interp = interpreter_with(src, preset, Dialect::Fanuc, tweak);
        fivex_engine::check::run_without_motion(&mut interp, true).map(|s| (s.alarm.code, s.alarm.line, s.by_strokes))
    };
    let run_of = |src: &str, preset: &str, tweak: &dyn Fn(&mut fivex_engine::interp::Config)| {
        let mut interp = interpreter_with(src, preset, Dialect::Fanuc, tweak);
        let r = run(&mut interp, &RunOptions::default(), |_| {});
        r.alarms.first().map(|a| (a.code.clone(), a.line, true))
    };
    let mut tight = MachineConfig::preset("head-bc").unwrap();
    // head-bc's B pivot at Z 100 when B passes 0 (the test below): a limit just under it.
    tight.axes[2].stroke = Some([-500.0, 99.9]);
    // (program, preset, with head-bc's Z limit under the pivot's peak, the alarm and its line)
    let cases = [
        ("G90 G00 X5000.\nM30\n", "mill3", false, Some(("OT0510", 1))),
        ("G90 G00 X-100. Y400.\nG02 X100. Y400. R100. F1000.\nM30\n", "mill3", false, Some(("OT0510", 2))),
        ("G90 G01 Z-600. F1000.\nM30\n", "mill3", false, Some(("OT0511", 1))),
        ("G10 L2 P1 X500.\nG90 G54 G00 X100.\nX150.\nM30\n", "mill3", false, Some(("OT0510", 3))),
        ("G20 G90 G00 X23.\nX24.\nM30\n", "mill3", false, Some(("OT0510", 2))),
        ("G90 G00 B100.\nB120.\nM30\n", "head-bc", false, Some(("OT0510", 2))),
        ("G90 G00 B-30. C0\nG43.4 H1\nG00 X0 Y0 Z0\nG01 B45. F2000.\nG49\nM30\n", "head-bc", true, Some(("OT0510", 4))),
        ("G90 G00 X599. Y-449. Z299.\nM30\n", "mill3", false, None),
    ];
    for (src, preset, tight_z, want) in cases {
        let tweak = |c: &mut fivex_engine::interp::Config| {
            if tight_z {
                c.machine = tight.clone().into();
            }
        };
        let want = want.map(|(code, line)| (code.to_string(), line, true));
        assert_eq!(check(src, preset, &tweak), want, "check of\n{src}");
        assert_eq!(run_of(src, preset, &tweak), want, "run of\n{src}");
    }
}

/// Without the program's machine (`fivex check` without `--preset`: mill3 stands in) the
/// strokes are not checked: a groove whose G54 puts it past mill3's X600 still reports the
/// compensation's PS0041 (line 7), which the stand-in's OT0510 at the first move would hide.
#[test]
fn check_on_a_stand_in_machine_leaves_the_strokes_out() {
    let src = "G10 L2 P1 X700.\nG21 G17 G40 G90 G94 G54\nG00 X-10. Y0. Z0.\nG41 D1 G01 X0. F1000.\nX20.\nY-2.\nX24.\nY0.\nX40.\nG40 X50.\nM30\n";
    let check = |strokes: bool| {
        let mut interp = interpreter(src, "mill3", Dialect::Fanuc);
        fivex_engine::check::run_without_motion(&mut interp, strokes).map(|s| (s.alarm.code, s.alarm.line))
    };
    assert_eq!(check(true), Some(("OT0510".to_string(), 3)));
    assert_eq!(check(false), Some(("PS0041".to_string(), 7)));
}

/// A tool-tip-following move whose axis peaks between the stroke check's 16 points along the
/// block: on head-bc (a 100 mm tool, the B pivot 150 mm above the nose) the tip stays put while B
/// swings from -30° to 45°, so the pivot's Z (250 cos B - 150) peaks at B0, 40 % along, between
/// the 6th and 7th point, 0.05 mm above the highest of them. With the Z limit just under the
/// peak the block must alarm before it moves, not run past the limit.
#[test]
fn a_kinematic_move_whose_axis_bulges_past_the_stroke_between_check_points_alarms() {
    let src = "G90 G00 B-30. C0\nG43.4 H1\nG00 X0 Y0 Z0\nN40 G01 B45. F2000.\nG49\nM30\n";
    let peak_of = |m: &MachineConfig| {
        let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |c| c.machine = m.clone().into());
        let mut peak = f64::MIN;
        let r = run(&mut interp, &RunOptions::default(), |s| {
            if s.line == 4 {
                peak = peak.max(s.machine[2]);
            }
        });
        (r, peak)
    };
    let mut m = MachineConfig::preset("head-bc").unwrap();
    let (free, peak) = peak_of(&m);
    assert!(free.completed() && (peak - 100.0).abs() < 0.01, "{:?} {peak}", free.alarms);
    m.axes[2].stroke = Some([-500.0, peak - 0.01]);
    let (r, peak_tight) = peak_of(&m);
    let first = r.alarms.first().map(|a| (a.code.as_str(), a.line));
    assert_eq!(first, Some(("OT0510", 4)));
    assert_eq!(peak_tight, f64::MIN, "the block does not start");
}

/// Distance of `p` from the segment `a`–`b` (in X, Y, Z).
fn off_line(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d: Vec<f64> = (0..3).map(|i| b[i] - a[i]).collect();
    let len2: f64 = d.iter().map(|x| x * x).sum();
    let u = if len2 > 0.0 { ((0..3).map(|i| (p[i] - a[i]) * d[i]).sum::<f64>() / len2).clamp(0.0, 1.0) } else { 0.0 };
    (0..3).map(|i| (p[i] - a[i] - u * d[i]).powi(2)).sum::<f64>().sqrt()
}

/// A random 3-axis program: straight moves and half circles or half helices (G02/G03 with I
/// and Z) in XY, each block one element, with the programmed geometry to compare the trace
/// against.
#[derive(Debug, Clone)]
enum Element {
    Line([f64; 3]),
    /// Half circle in XY about the current point + (r, 0): ends at current + (2r, 0), and `dz`
    /// lower or higher (a helix).
    Arc {
        r: f64,
        ccw: bool,
        dz: f64,
    },
}

fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn program(elements: &[Element], feed: f64, mode: &str) -> (String, Vec<(u32, Element, [f64; 3])>) {
    let mut src = format!("G90 G17 {mode} G00 X0. Y0. Z0.\nF{feed:.0}\n");
    let mut at = [0.0; 3];
    let mut blocks = Vec::new();
    for (k, e) in elements.iter().enumerate() {
        let line = k as u32 + 3;
        match e {
            Element::Line(p) => src.push_str(&format!("G01 X{:.3} Y{:.3} Z{:.3}\n", p[0], p[1], p[2])),
            Element::Arc { r, ccw, dz } => {
                let g = if *ccw { "G03" } else { "G02" };
                let (x, z) = (at[0] + 2.0 * r, at[2] + dz);
                src.push_str(&format!("{g} X{x:.3} Y{:.3} Z{z:.3} I{:.3} J0.\n", at[1], r));
            }
        }
        blocks.push((line, e.clone(), at));
        at = match e {
            Element::Line(p) => p.map(mm),
            Element::Arc { r, dz, .. } => [mm(at[0] + 2.0 * r), at[1], mm(at[2] + dz)],
        };
    }
    src.push_str("M30\n");
    (src, blocks)
}

fn element() -> impl Strategy<Value = Element> {
    prop_oneof![
        prop::array::uniform3(-100.0..100.0f64).prop_map(Element::Line),
        (-20.0..20.0f64, any::<bool>(), prop_oneof![Just(0.0), -30.0..30.0f64])
            .prop_filter("a real radius", |(r, _, _)| r.abs() > 0.5)
            // Radii in whole micrometres, so that the end point is exactly 2r away.
            .prop_map(|(r, ccw, dz)| Element::Arc { r: mm(r), ccw, dz }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(24)))]

    #[test]
    fn sampled_axes_stay_within_their_limits_and_the_tip_on_the_path(
        elements in prop::collection::vec(element(), 1..8),
        feed in 200u32..20000,
        exact in any::<bool>(),
    ) {
        let feed = feed as f64;
        let mode = if exact { "G61" } else { "G64" };
        let (src, blocks) = program(&elements, feed, mode);
        let (r, samples) = traced(&src, "mill3");
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        check_limits(&samples, "mill3", exact)?;
        for s in &samples {
            let Some((_, e, from)) = blocks.iter().find(|b| b.0 == s.line) else { continue };
            // F is the speed along the arc of a helix (HTG = 0): the tip goes faster.
            let helix = match e {
                Element::Arc { r, dz, .. } => (std::f64::consts::PI * r).hypot(*dz) / (std::f64::consts::PI * r.abs()),
                Element::Line(_) => 1.0,
            };
            prop_assert!(s.feed <= feed * helix * (1.0 + 1e-4), "feed {} above F{feed}", s.feed);
            let off = match e {
                Element::Line(p) => off_line(s.tip, *from, p.map(mm)),
                Element::Arc { r, dz, .. } => {
                    // On the cylinder, and Z in proportion to the angle swept from the start
                    // (half a turn: the angle is acos of the radial directions' dot product).
                    let (cx, cy) = (from[0] + mm(*r), from[1]);
                    let (dx, dy) = (s.tip[0] - cx, s.tip[1] - cy);
                    let radial = (dx.hypot(dy) - mm(*r).abs()).abs();
                    let swept = ((dx * (from[0] - cx) + dy * (from[1] - cy)) / (dx.hypot(dy) * mm(*r).abs())).clamp(-1.0, 1.0).acos();
                    let z = from[2] + (mm(from[2] + dz) - from[2]) * swept / std::f64::consts::PI;
                    radial + (s.tip[2] - z).abs()
                }
            };
            prop_assert!(off < 1e-3, "tip {:?} is {off} mm off block {} of\n{src}", s.tip, s.line);
        }
    }

    #[test]
    fn rest_to_rest_moves_take_their_closed_form_time(len in 1.0..500.0f64, feed in 60.0..30000.0f64) {
        let v = feed / 60.0;
        // Only when the cruise speed is reached (the ramps' distance, v·ramp, fits).
        prop_assume!(v * ramp_time(v, A, J) <= len);
        let (r, _) = traced(&format!("G90 G01 X{len:.4} F{feed:.4}\nM30\n", ), "mill3");
        let len = (len * 10000.0).round() / 10000.0;
        let v = (feed * 10000.0).round() / 10000.0 / 60.0;
        prop_assert!((r.cycle_time_s - move_time(len, v, A, J)).abs() < 1e-9);
    }

    #[test]
    fn rotary_moves_stay_within_the_rotary_limits(
        moves in prop::collection::vec((-80.0..80.0f64, 0.0..360.0f64, -100.0..100.0f64), 1..5),
        feed in 500u32..20000,
    ) {
        // head-bc: B ±100 of range, C unlimited; simultaneous linear + rotary G01 moves.
        let mut src = format!("G90 G61 G01 F{feed:.0}\n");
        for (b, c, x) in &moves {
            src.push_str(&format!("X{x:.3} B{b:.3} C{c:.3}\n"));
        }
        src.push_str("M30\n");
        let (r, samples) = traced(&src, "head-bc");
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        check_limits(&samples, "head-bc", true)?;
    }
}

/// A full circle at F3000 on head-bc (X, Y: 500 mm/s, A = 4000 mm/s², J = 80000 mm/s³) runs as
/// fast as the axes allow (r = 1 ran at 266.7 mm/min with every axis below 1 % of its limits,
/// r = 5 at 1333 mm/min). r = 5 and r = 20 cruise at F (the turning at F takes at most
/// 50²/5 = 500 mm/s² and 50³/25 = 5000 mm/s³). r = 1 cannot: its turning jerk w³/r² reaches J at
/// ∛(J·r²) = 43.1 mm/s; the arc cruises with half of it, ∛(J·r²/2) = 34.2 mm/s, the rest left
/// for the speed changes a 6.3 mm circle mostly consists of (with 0.9 of it the rest-to-rest time
/// is longer: `docs/motion.md`, Limits), and on its way some plane axis reaches 90 % of a limit.
/// The cruise is the arc's samples within 0.5 % of its top tip speed; the axes' speed,
/// acceleration and jerk are the finite differences of their sampled positions.
#[test]
fn a_circle_runs_as_fast_as_its_axes_allow() {
    let lim = common::limits("head-bc");
    for r in [1.0f64, 5.0, 20.0] {
        let src = format!("G90 G94 G17\nG01 X{r:.1} Y0 F3000.\nG02 X{r:.1} Y0 I-{r:.1} J0\nM30\n");
        let (run, samples) = traced(&src, "head-bc");
        assert!(run.completed(), "{:?}", run.alarms);
        // (tip speed mm/min, the highest share of a limit on X or Y) at each sample of the arc.
        let arc: Vec<(f64, f64)> = samples
            .windows(4)
            .filter(|w| w.iter().all(|s| s.line == 3))
            .map(|w| {
                let tip = (w[2].programmed[0] - w[1].programmed[0]).hypot(w[2].programmed[1] - w[1].programmed[1]);
                let used = (0..2)
                    .map(|i| {
                        let (v, a, j) = common::derivatives(common::positions([&w[0], &w[1], &w[2], &w[3]], i, false));
                        (v.abs() / lim[i].0).max(a.abs() / lim[i].1).max(j.abs() / lim[i].2)
                    })
                    .fold(0.0, f64::max);
                (tip / PERIOD * 60.0, used)
            })
            .collect();
        let top = arc.iter().map(|x| x.0).fold(0.0, f64::max);
        let cruise = arc.iter().filter(|x| x.0 >= 0.995 * top).count();
        let used = arc.iter().map(|x| x.1).fold(0.0, f64::max);
        println!(
            "r = {r}: {:.4} s, cruise {cruise} samples at {top:.1} mm/min, axes up to {:.1} %",
            run.cycle_time_s,
            used * 100.0
        );
        assert!(cruise >= 10, "r = {r}: no cruise");
        if r >= 5.0 {
            assert!((top - 3000.0).abs() < 0.5, "r = {r}: cruise at {top} mm/min, not F3000");
        } else {
            let half = 60.0 * (0.5 * J * r * r).cbrt();
            assert!((top - half).abs() < 1e-3 * half, "r = {r}: cruise at {top} mm/min, not {half}");
            assert!(used >= 0.9, "r = {r}: the axes only reach {used} of their limits");
        }
    }
}

#[test]
fn g30_goes_to_the_second_to_fourth_reference_position() {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.axes[2].references = [250.0, 100.0, 0.0];
    m.axes[0].references = [-300.0, 0.0, 0.0];
    let end = |src: &str| {
        let mut interp = fivex_engine::interp::Interpreter::new(
            fivex_engine::lang::parse_file(src),
            fivex_engine::interp::Config::new(m.clone(), Dialect::Fanuc),
        );
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        (r.machine[0], r.machine[2], r.alarms.first().map(|a| a.code.clone()))
    };
    // Only the named axes go, through the intermediate point.
    assert_eq!(end("G90 G00 X10. Z-20.\nG91 G30 Z0.\nM30\n"), (10.0, 250.0, None));
    assert_eq!(end("G90 G00 X10. Z-20.\nG91 G30 P3 X0. Z0.\nM30\n"), (0.0, 100.0, None));
    assert_eq!(end("G90 G00 X10. Z-20.\nG30 P2 X10. Z-20.\nM30\n"), (-300.0, 250.0, None));
    assert_eq!(end("G90 G00 X10. Z-20.\nG91 G28 Z0.\nM30\n"), (10.0, 0.0, None));
    assert_eq!(end("G91 G30 P5 Z0.\nM30\n").2.as_deref(), Some("PS0046"));
}

/// G27 (FANUC): the named axes go to the point at rapid, then must stand at the 1st reference
/// position (machine zero on mill3), with the offsets in force counted; else PS0092 after the
/// move, and the program stops there. It was refused as not built (PS0010).
#[test]
fn g27_checks_the_named_axes_at_the_reference_position() {
    let end = |src: &str| {
        let r = run_with(src, "mill3", Dialect::Fanuc);
        let alarm = r.alarms.first().map(|a| (a.code.clone(), a.line));
        (r.machine[0], r.machine[1], r.machine[2], alarm)
    };
    // At machine zero: the lamp lights, the program goes on (X5. after it runs).
    assert_eq!(end("G90 G00 X10. Y10. Z-20.\nG27 X0 Y0 Z0\nG00 X5.\nM30\n"), (5.0, 0.0, 0.0, None));
    // Incremental, and only the named axes are checked (Y stays at 10).
    assert_eq!(end("G90 G00 X10. Y10. Z-20.\nG91 G27 X-10. Z20.\nM30\n"), (0.0, 10.0, 0.0, None));
    // Not there: the move is made, then PS0092; the block after it does not run.
    let missed = ("PS0092".to_string(), 2);
    assert_eq!(end("G90 G00 X10. Y10. Z-20.\nG27 X0 Y0 Z-1.\nG00 X5.\nM30\n"), (0.0, 0.0, -1.0, Some(missed.clone())));
    // The work offset counts: G55 X0 is machine X-100, not the reference position.
    assert_eq!(end("G10 L2 P2 X-100.\nG55 G00 X10.\nG27 X0\nM30\n").3, Some(("PS0092".to_string(), 3)));
    // So does the tool length: with H1 = 50 the tip at Z0 puts the machine 50 above it.
    let r = end("G10 L10 P1 R50.\nG43 H1 G00 Z-20.\nG27 Z0\nM30\n");
    assert_eq!((r.2, r.3), (50.0, Some(("PS0092".to_string(), 3))));
    // In a canned cycle: PS0044, before any move.
    assert_eq!(end("G90 G00 X10. Z10.\nG81 X10. Z-5. R2. F100.\nG27 X0\nM30\n").3, Some(("PS0044".to_string(), 3)));
    // Refused in the 5-axis modes, where the machine's position after a tip move is the
    // executor's to find: FANUC's own mode alarms (TCP, tilted plane, G54.4) come first.
    let five = |src: &str| run_with(src, "head-bc", Dialect::Fanuc).alarms.first().map(|a| (a.code.clone(), a.line));
    assert_eq!(five("G43.4 H1\nG27 X0\nM30\n"), Some(("PS5421".to_string(), 2)));
    assert_eq!(five("G68.2 X0 Y0 Z0 I0 J30. K0\nG27 X0\nM30\n"), Some(("PS5462".to_string(), 2)));
    let src = "#26001=10.\nG54.4 P1\nG27 X0\nM30\n";
    let wse = run_with(src, "mixed-bc", Dialect::Fanuc).alarms.first().map(|a| (a.code.clone(), a.line));
    assert_eq!(wse, Some(("PS0437".to_string(), 3)), "G54.4");
    // The Syntec dialect does not build it (its sources do not describe it).
    assert_eq!(alarm_with("G27 X0\nM30\n", Dialect::Syntec), "COR-100");
}

#[test]
fn a_tilting_axis_stops_at_its_range() {
    // head-bc: B turns -110..110 (its stroke); C rolls over without limit.
    let mut interp = interpreter("G90 G00 B100. C720.\nN30 G00 B-120.\nM30\n", "head-bc", Dialect::Fanuc);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].message.as_str()), ("OT0511", "- OVERTRAVEL ( PRE-CHECK ) B"));
    assert_eq!((r.machine[3], r.machine[4]), (100.0, 0.0));
}

// --- Feed modes: what a cutting block needs to have a feed ------------------------------------

/// The first alarm of `src` on head-bc in `dialect` (code, line), and what `fivex check` on the
/// machine finds (the run without motion), which must agree.
fn feed_alarm(src: &str, dialect: Dialect) -> Option<(String, u32)> {
    let mut interp = interpreter(src, "head-bc", dialect);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    let ran = r.alarms.first().map(|a| (a.code.clone(), a.line));
    let mut interp = interpreter(src, "head-bc", dialect);
    let checked = fivex_engine::check::run_without_motion(&mut interp, true).map(|s| (s.alarm.code, s.alarm.line));
    assert_eq!(ran, checked, "run and check of\n{src}");
    ran
}

/// G93's F is each block's own (Mitsubishi M700V §7.5, RS274/NGC), and F is needed again once
/// G93 is entered or left (FANUC A-91417E: PS0011 after a group-05 change): a G94 F600 read as
/// an inverse time would run 10 mm at 6000 mm/min, an FRN 6 read as mm/min at 6 mm/min.
#[test]
fn in_g93_every_cutting_block_needs_its_own_f() {
    let dialects = [(Dialect::Fanuc, "PS0011"), (Dialect::Syntec, "COR-010"), (Dialect::Haas, "320")];
    // The audit's program: line 3 enters G93 without F.
    let audit = "G90 G94 G17\nG01 X10. F600.\nG93 X20.\nG01 X30. F6.\nX40.\nG94 X50.\nM30\n";
    // (program, the line of the alarm)
    let cases = [
        (audit, 3),
        // G93 with F: line 3 is fine; line 4 is a G93 block without F.
        ("G90 G94 G01 X10. F600.\nG93 X20. F60.\nG01 X30. F6.\nX40.\nM30\n", 4),
        // Leaving G93 without a new F.
        ("G90 G93 G01 X10. F6.\nG94 X20.\nM30\n", 2),
        // F alone in a block of its own is not the next block's F.
        ("G90 G93 G01 X10. F6.\nF6.\nX20.\nM30\n", 3),
        // A G93 arc, and a canned cycle's next hole.
        ("G90 G93 G01 X10. F6.\nG02 X20. R5.\nM30\n", 2),
        ("G90 G00 Z10.\nG93 G81 X10. Z-5. R2. F6.\nX20.\nG80\nM30\n", 3),
        // G94 entered without a G93 block moving: G93's F is no feed of G94 either.
        ("G90 G93 G01 X10. F6.\nG94\nX20.\nM30\n", 3),
        // A tool length change moving in G01 with no F ever given (it ran for ever).
        ("G90 G01\nG43 H1 Z10.\nM30\n", 2),
        // Fine: every cutting block has its F; rapids need none; G94 F again after G93. (A
        // G93 arc with F: `g93_arcs_*`; Syntec refuses it.)
        ("G90 G93 G01 X10. F6.\nG00 X0\nG01 X10. F6.\nX20. F3.\nG94 G01 X30. F600.\nX40.\nM30\n", 0),
    ];
    for (dialect, code) in dialects {
        for (src, line) in cases {
            let want = (line > 0).then(|| (code.to_string(), line));
            assert_eq!(feed_alarm(src, dialect), want, "{dialect:?}:\n{src}");
        }
    }
    // `fivex check` without a machine sees a block that names G93 and a cutting move.
    for (src, want) in [
        ("G90 G94 G01 X10. F600.\nG93 G01 X20.\nM30\n", vec![(2, 1)]),
        ("G90 G93 G02 X10. R5.\nG93 G81 X0 Z-5. R2.\nG93 G00 X0\nG93 G01 X10. F6.\nM30\n", vec![(1, 5), (2, 1)]),
    ] {
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(src), Dialect::Fanuc);
        let got: Vec<_> = diags.iter().map(|d| (d.line, d.col, d.id.clone())).collect();
        let want: Vec<_> = want.into_iter().map(|(line, col)| (line, col, AlarmId::FeedZero)).collect();
        assert_eq!(got, want, "{src}");
    }
    // Where every block has its F: 10 mm at F6 takes 1/6 min (1 mm/s), then 10 mm at G94
    // F600 (10 mm/s), stopping between them (G09 in the first), each with its S-curve ramps.
    let (r, _) = traced("G90 G93 G09 G01 X10. F6.\nG94 X20. F600.\nM30\n", "head-bc");
    close(r.cycle_time_s, move_time(10.0, 1.0, A, J) + move_time(10.0, 10.0, A, J));
}

/// The cycle time of `src` on mill3 in `dialect`, and its first alarm.
fn timed(src: &str, dialect: Dialect, tweak: impl FnOnce(&mut fivex_engine::interp::Config)) -> (f64, Option<String>) {
    let mut interp = interpreter_with(src, "mill3", dialect, tweak);
    let r = run(&mut interp, &RunOptions { period_s: PERIOD, ..RunOptions::default() }, |_| {});
    (r.cycle_time_s, r.alarms.first().map(|a| format!("{} line {}", a.code, a.line)))
}

/// FANUC feeds an arc in G93 at FRN × its radius (16/18-MC B-62764EN/01, §5 "Inverse time
/// feed": FRN = feedrate / arc radius), so its block takes swept angle (rad) / FRN minutes; the
/// arc took 1/F minutes (a quarter arc 1.57× too fast, a full circle 2π×). A helix is fed
/// along its arc (HTG = 0) at that rate. Haas keeps 60/F seconds for every motion (its G93
/// page); Syntec, whose sources say neither, refuses the arc (COR-100).
#[test]
fn g93_arcs_take_their_swept_angle_over_frn_in_fanuc() {
    let quarter = std::f64::consts::FRAC_PI_2;
    // From X0 Y0 to X10 Y10 by G03 R10: the quarter arc about (0, 10), 5π mm long.
    let len = 5.0 * std::f64::consts::PI;
    // The run's arc lags its closed form by a ms or so (its profile on the circle): each arc is
    // held to its closed-form time within 5 ms, and to the same arc in G94 at FRN × R exactly.
    let near = |got: f64, want: f64, what: &str| assert!((got - want).abs() < 5e-3, "{what}: {got} s, not {want}");
    // FANUC: 10 mm/min along the arc, π/2 min.
    let (t, alarm) = timed("G90 G17 G93 G03 X10. Y10. R10. F1.\nM30\n", Dialect::Fanuc, |_| {});
    assert_eq!(alarm, None);
    let v = 10.0 / 60.0;
    near(t, quarter * 60.0, "quarter arc");
    near(t, move_time(len, v, A, J), "quarter arc with its ramps");
    assert_eq!(t, timed("G90 G17 G94 G03 X10. Y10. R10. F10.\nM30\n", Dialect::Fanuc, |_| {}).0);
    // The same in inch: R1 in at FRN 1 is 1 in/min = 25.4 mm/min, still π/2 min.
    let (t, _) = timed("G20 G90 G17 G93 G03 X1. Y1. R1. F1.\nM30\n", Dialect::Fanuc, |_| {});
    near(t, move_time(25.4 * quarter, 25.4 / 60.0, A, J), "inch quarter arc");
    // A three-quarter arc (G02 from (0,0) to (10,10) with R-10, centre (0,10)): 3π/2 min.
    let (t, _) = timed("G90 G17 G93 G02 X10. Y10. R-10. F1.\nM30\n", Dialect::Fanuc, |_| {});
    near(t, move_time(3.0 * len, v, A, J), "three-quarter arc");
    // A helix rising 5 mm: fed along its arc at 10 mm/min, so its path at 10·L/5π mm/min.
    let path = (len * len + 25.0).sqrt();
    let (t, _) = timed("G90 G17 G93 G03 X10. Y10. Z5. R10. F1.\nM30\n", Dialect::Fanuc, |_| {});
    near(t, move_time(path, v * path / len, A, J), "helix");
    // An inverse time the axes cannot follow: F60000 on R10 asks 600000 mm/min; the arc is
    // held to what the axes allow (slower than the rapid rate), not run in 1/F min.
    let (t, _) = timed("G90 G17 G93 G03 X10. Y10. R10. F60000.\nM30\n", Dialect::Fanuc, |_| {});
    assert!(t > len / 500.0, "an arc faster than the rapid rate: {t} s");
    // Haas: 60/F seconds whatever the motion.
    let (t, alarm) = timed("G90 G17 G93 G03 X10. Y10. R10. F1.\nM30\n", Dialect::Haas, |_| {});
    assert_eq!(alarm, None);
    near(t, move_time(len, len / 60.0, A, J), "Haas quarter arc");
    // Syntec: refused at the arc's block, and by `fivex check` where the block names G93.
    let (_, alarm) = timed("G90 G17 G93 G01 X1. F1.\nG03 X11. Y10. R10. F1.\nM30\n", Dialect::Syntec, |_| {});
    assert_eq!(alarm.as_deref(), Some("COR-100 line 2"));
    let diags = fivex_engine::check::check(
        fivex_engine::lang::parse_file("G90 G17 G93 G03 X10. Y10. R10. F1.\nM30\n"),
        Dialect::Syntec,
    );
    assert_eq!(diags.iter().map(|d| (d.line, d.id.clone())).collect::<Vec<_>>(), [(1, AlarmId::GCodeNotBuilt)]);
}

/// An inverse time has no length unit. FANUC counts an F without a decimal point in 0.001 under
/// G93 (DPI = 0), "regardless of whether the input mode is inches or metric" (B-62764EN/01:
/// F1 is FRN 0.001); with DPI = 1 (`pocket_calculator`) F1 is 1. It ran F600 as FRN 600, 1000×
/// too fast. The Haas dialect counted Setting 77's 0.001 mm / 0.0001 in, so an inch program ran
/// 10× slower: refused (no Haas source gives G93's increment).
#[test]
fn g93_f_without_a_decimal_point() {
    // FRN 0.6: 10 mm (or 1 in) in 1/0.6 min = 100 s, at 6 mm/min (15.24 mm/min).
    for (src, len) in [("G21 G90 G93 G01 X10. F600\nM30\n", 10.0), ("G20 G90 G93 G01 X1. F600\nM30\n", 25.4)] {
        let (t, alarm) = timed(src, Dialect::Fanuc, |_| {});
        assert_eq!(alarm, None);
        assert!((t - move_time(len, len / 100.0, A, J)).abs() < 1e-6, "{src}: {t} s");
        // DPI = 1: F6 is FRN 6, 10 s.
        let (t, _) = timed(&src.replace("F600", "F6"), Dialect::Fanuc, |c| c.pocket_calculator = true);
        assert!((t - move_time(len, len / 10.0, A, J)).abs() < 1e-6, "{src} with DPI = 1: {t} s");
        // Haas: refused at the block (311); with a point F6. runs 10 s in both units.
        let (_, alarm) = timed(src, Dialect::Haas, |_| {});
        assert_eq!(alarm.as_deref(), Some("311 line 1"), "{src}");
        let (t, _) = timed(&src.replace("F600", "F6."), Dialect::Haas, |_| {});
        assert!((t - move_time(len, len / 10.0, A, J)).abs() < 1e-6, "Haas {src} with F6.: {t} s");
    }
    // G94's F without a point is unchanged: FANUC as written, Haas in Setting 77's increment.
    let (t, _) = timed("G21 G90 G94 G01 X10. F600\nM30\n", Dialect::Fanuc, |_| {});
    assert!((t - move_time(10.0, 10.0, A, J)).abs() < 1e-6, "G94 F600: {t} s");
}

/// G95's feed follows the spindle's turning: with the spindle stopped (M05, never started, S0)
/// a control waits for it without end, so the block is refused (FX0009, fivex's own) rather
/// than fed at F × S or run for ever; M03 in the block starts the spindle before the move,
/// M05 in it stops it after.
#[test]
fn feed_per_revolution_with_the_spindle_stopped_is_refused() {
    let code = "FX0009";
    let cases = [
        ("G90 G95 S1000 M03\nM05\nG01 X10. F0.1\nM30\n", 3),
        ("G90 G95\nG01 X10. F0.1\nM30\n", 2),
        ("G90 G95 S1000 M03\nG01 X10. F0.1 S0\nM30\n", 2),
        ("G90 G95 M03\nG02 X10. R5. F0.1\nM30\n", 2),
        ("G90 G95 S1000 M03\nM05\nG00 Z10.\nG81 X10. Z-5. R2. F0.1\nM30\n", 4),
        // Fine: M03 in the block, M05 after the move in it, rapids, and G94.
        ("G90 G95 S1000\nG01 X10. F0.1 M03\nX20. M05\nG00 X0\nG94 G01 X10. F100.\nM30\n", 0),
    ];
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        for (src, line) in cases {
            let want = (line > 0).then(|| (code.to_string(), line));
            assert_eq!(feed_alarm(src, dialect), want, "{dialect:?}:\n{src}");
        }
    }
}

// --- Inch input (G20) and rotary axes -----------------------------------------------------------

/// The common variables of a completed run of `src` on `preset` in `dialect`, `tweak`ed.
fn vars_of(
    src: &str,
    preset: &str,
    dialect: Dialect,
    tweak: impl FnOnce(&mut fivex_engine::interp::Config),
) -> Vec<(u32, f64)> {
    let mut interp = interpreter_with(src, preset, dialect, tweak);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{dialect:?}: unexpected alarm {:?} in\n{src}", r.alarms);
    r.variables.clone()
}

fn var_of(vars: &[(u32, f64)], n: u32) -> f64 {
    vars.iter().find(|(k, _)| *k == n).map(|(_, v)| *v).unwrap_or_else(|| panic!("#{n} vacant"))
}

/// "G20 and G21 must not be switched during a program" (FANUC 30i user's manual B-63944EN/02
/// §8.2, a warning; what the control does then is not described): a switch after the program
/// has moved runs with notice FX1005 at the switching block, carried by the next motion, in
/// every dialect (Syntec's G70/G71). A unit set before the first move, the same unit given
/// again, or a switch nothing moves after, are not told. Before, nothing was.
#[test]
fn a_unit_switched_after_the_first_motion_runs_with_a_notice() {
    let notices = |src: &str, dialect: Dialect| {
        let r = common::run_with(src, "mill3", dialect);
        assert!(r.completed(), "{dialect:?}: {:?}\n{src}", r.alarms);
        r.notices.iter().map(|n| (n.code.clone(), n.line, n.n)).collect::<Vec<_>>()
    };
    for (dialect, inch, mm) in
        [(Dialect::Fanuc, "G20", "G21"), (Dialect::Haas, "G20", "G21"), (Dialect::Syntec, "G70", "G71")]
    {
        let switched = format!("{mm} G90 G00 X0 Y0\nG01 X10. F600.\nN7 {inch}\nG01 X1. F20.\nM30\n");
        assert_eq!(notices(&switched, dialect), vec![("FX1005".to_string(), 3, Some(7))], "{dialect:?}");
        // In the moving block itself, and back again: each switch is told.
        let twice = format!("{mm} G00 X5.\n{inch} G01 X1. F20.\n{mm} X5.\nM30\n");
        let got: Vec<u32> = notices(&twice, dialect).iter().map(|n| n.1).collect();
        assert_eq!(got, vec![2, 3], "{dialect:?}");
        for quiet in [
            format!("{inch}\nG90 G00 X1.\nM30\n"),
            format!("{mm} G00 X1.\n{mm}\nG00 X2.\nM30\n"),
            format!("{mm} G00 X1.\n{inch}\nM30\n"),
        ] {
            assert_eq!(notices(&quiet, dialect), vec![], "{dialect:?}: {quiet}");
        }
    }
}

/// A rotary word without a decimal point counts 0.001° in G20 as in G21: only lengths have an
/// inch increment (FANUC 30i-A5 manual §2.3.2 gives the angles' increment apart from the
/// input unit; 30i user's manual §8.2: "The unit of data input for degrees remains unchanged").
/// `C10` is 0.010°, `A1000` 1.000°, while `X10` is 0.0010 inch. It was 0.001° and 0.1°.
#[test]
fn a_rotary_word_without_a_point_counts_thousandths_of_a_degree_in_inch_too() {
    // Hand values: C10 → 0.010°, A1000 → 1.000° (both units); X10 → 0.0010 in = 0.0254 mm,
    // which #5021 reads back in inch under G20.
    let body = |mm: &str, inch: &str| {
        format!(
            "{mm} G91 G00 C10 A1000\n#100=#5025\n#101=#5024\n{inch} C10 A1000 X10\n#102=#5025-#100\n\
             #103=#5024-#101\n#104=#5021\nG91 G00 C10 A1000\n#105=#5025-#100-#102\n#106=#5024-#101-#103\nM30\n"
        )
    };
    // (Syntec's #5021… are user parameters there, refused: its machine position says it below.)
    for (dialect, mm, inch) in [(Dialect::Fanuc, "G21", "G20"), (Dialect::Haas, "G21", "G20")] {
        let v = vars_of(&body(mm, inch), "table-ac", dialect, |_| {});
        let got: Vec<f64> = (100..=106).map(|n| var_of(&v, n)).collect();
        let want = [0.010, 1.000, 0.010, 1.000, 0.001, 0.010, 1.000];
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{dialect:?}: got {got:?}, want {want:?}");
        }
    }
    // Syntec: such a word's unit is the machine's Pr3241, which fivex does not model: refused
    // (`syntec_macro.rs`, `a_length_without_a_decimal_point_is_refused_in_the_syntec_dialect`).
    let mut interp =
        interpreter_with("G71 G91 G00 C10 A1000\nG70 C10 A1000 X10\nM30\n", "table-ac", Dialect::Syntec, |_| {});
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("COR-048", 1));
    // Inch at power on (FANUC No.0000#2 INI): the same without a G20 in the program.
    let mut m = MachineConfig::preset("table-ac").unwrap();
    m.motion.power_on_inch = true;
    let v =
        vars_of("G91 G00 C10 A1000 X10\n#100=#5025\n#101=#5024\n#102=#5021\nM30\n", "table-ac", Dialect::Fanuc, |c| {
            c.machine = m.into()
        });
    let got = [var_of(&v, 100), var_of(&v, 101), var_of(&v, 102)];
    assert!(got.iter().zip([0.010, 1.000, 0.001]).all(|(g, w)| (g - w).abs() < 1e-9), "power-on inch: {got:?}");
}

/// A macro call's argument at a rotary axis's letter counts the axis's increment too: in G20
/// `G65 C10` passes 0.010 (a length's letter 0.0010 inch, as FANUC's I/J/K example).
#[test]
fn a_macro_argument_at_a_rotary_letter_counts_thousandths_in_inch_too() {
    let src = "G20\nG65 P9001 C10 X10\nM30\nO9001\n#100=#3\n#101=#24\nM99\n";
    let v = vars_of(src, "table-ac", Dialect::Fanuc, |_| {});
    let got = [var_of(&v, 100), var_of(&v, 101)];
    assert!((got[0] - 0.010).abs() < 1e-12 && (got[1] - 0.0010).abs() < 1e-12, "{got:?}");
}

/// Decision (`docs/conventions.md`, "Motion"; open question there): under G20 F is converted to
/// mm/min when read and the composite feed counts a degree as a millimetre, the machine's unit
/// (a metric machine, FANUC No.1001#0 INM = 0), not as an inch. So `G20 X1. C10. F10.` runs as
/// `G21 X25.4 C10. F254.`: √(25.4² + 10²) = 27.298 at 254/min, 6.448 s before the ramps (60.3 s
/// if the degree counted as an inch); a rotary-only `C90. F10.` at 254 °/min (10 °/min would
/// take 540 s).
#[test]
fn decision_under_g20_the_composite_feed_counts_a_degree_as_a_millimetre() {
    let time = |src: &str| {
        let (r, _) = traced(src, "table-ac");
        assert!(r.completed(), "{:?}\n{src}", r.alarms);
        r.cycle_time_s
    };
    let inch = time("G20 G91 G01 X1. C10. F10.\nM30\n");
    close(inch, time("G21 G91 G01 X25.4 C10. F254.\nM30\n"));
    let ideal = (25.4f64.powi(2) + 100.0).sqrt() / 254.0 * 60.0;
    assert!((6.448..6.449).contains(&ideal) && inch > ideal && inch < ideal + 0.1, "{inch} s against {ideal} s");
    close(time("G20 G91 G01 C90. F10.\nM30\n"), time("G21 G91 G01 C90. F254.\nM30\n"));
}
