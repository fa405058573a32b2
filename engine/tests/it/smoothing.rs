//! Nano smoothing, G05.1 Q3 (`docs/motion.md`, "Nano smoothing"): the tool tip (forward
//! kinematics of the sampled axes) against the programmed points — within the tolerance of its
//! block's programmed segment at every 1 ms sample, on 3-axis and under G43.4 — the curve
//! through points of a known circle, corners kept, every block counted once and in order, and
//! the mode's alarms.

use crate::common;

use common::{cases, first_alarm, first_alarm_with, interpreter_with};
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use proptest::prelude::*;

/// Run `src` on `preset` (FANUC, tool length 100), `tweak` adjusting the machine; every 1 ms
/// sample.
fn run_on(src: &str, preset: &str, tweak: impl FnOnce(&mut MachineConfig)) -> (RunResult, Vec<Sample>) {
    run_in(Dialect::Fanuc, src, preset, tweak)
}

pub(crate) fn run_in(
    dialect: Dialect,
    src: &str,
    preset: &str,
    tweak: impl FnOnce(&mut MachineConfig),
) -> (RunResult, Vec<Sample>) {
    let mut m = MachineConfig::preset(preset).unwrap();
    tweak(&mut m);
    let mut interp = interpreter_with(src, preset, dialect, |c| c.machine = m.into());
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions { max_time_s: 120.0, ..RunOptions::default() }, |s| samples.push(*s));
    (r, samples)
}

/// Each rotary axis `(k, axis index, tolerance)` of sample `s` within its tolerance (+ the
/// chords' 0.0001°) of the range between its programmed ends `from[k]` and `to[k]` (a rollover
/// axis is shown modulo 360: it is read near the range).
pub(crate) fn rotary_between(s: &Sample, axes: [(usize, usize, f64); 2], from: [f64; 2], to: [f64; 2]) {
    for (k, axis, tol) in axes {
        let (lo, hi) = (from[k].min(to[k]), from[k].max(to[k]));
        let v = s.machine[axis] - 360.0 * ((s.machine[axis] - lo + 180.0) / 360.0).floor();
        assert!(v > lo - tol - 2e-4 && v < hi + tol + 2e-4, "line {}: axis {k} at {v}, not in [{lo}, {hi}]", s.line);
    }
}

/// The distance from `p` to the segment `a`–`b`.
pub(crate) fn to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab: [f64; 3] = std::array::from_fn(|c| b[c] - a[c]);
    let ap: [f64; 3] = std::array::from_fn(|c| p[c] - a[c]);
    let l2: f64 = ab.iter().map(|x| x * x).sum();
    let t = if l2 > 0.0 { (ab.iter().zip(&ap).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0) } else { 0.0 };
    (0..3).map(|c| (a[c] + t * ab[c] - p[c]).powi(2)).sum::<f64>().sqrt()
}

/// A program that smooths `points` (X, Y, Z) from the first at F `feed`: line 3 is the first
/// block of the curve, line 3 + i the block ending at point i + 1; the program ends with G05.1
/// Q0 and M30.
pub(crate) fn program(points: &[[f64; 3]], feed: f64, smoothing: bool, prefix: &str) -> String {
    let p0 = points[0];
    let mut s = format!("G90 G00 X{:.4} Y{:.4} Z{:.4}\n{prefix}G01 F{feed:.0}\n", p0[0], p0[1], p0[2]);
    s += if smoothing { "G05.1 Q3 X0 Y0 Z0\n" } else { "G04 X0\n" };
    for p in &points[1..] {
        s += &format!("X{:.4} Y{:.4} Z{:.4}\n", p[0], p[1], p[2]);
    }
    s + if smoothing { "G05.1 Q0\n" } else { "G04 X0\n" } + "M30\n"
}

/// Every sample of the curve's blocks is within `tol` (+ 1 µm for the chords and the check's
/// sampling) of its own block's programmed segment; returns the largest distance.
pub(crate) fn within_segments(samples: &[Sample], points: &[[f64; 3]], tol: f64) -> Result<f64, String> {
    let mut worst = 0.0f64;
    let mut seen = 0;
    for s in samples {
        let k = s.line as usize;
        if !(4..4 + points.len() - 1).contains(&k) {
            continue;
        }
        let i = k - 3;
        let d = to_segment(s.tip, points[i - 1], points[i]);
        if d > tol + 1e-6 {
            return Err(format!("line {k} at t = {}: tip {:?} is {d} from its segment", s.t, s.tip));
        }
        worst = worst.max(d);
        seen += 1;
    }
    if seen < 10 {
        return Err(format!("only {seen} samples on the curve"));
    }
    Ok(worst)
}

/// A radius-20 arc cut into 1° blocks (sagitta 0.76 µm).
fn arc_points() -> Vec<[f64; 3]> {
    (0..=180).map(|i| (i as f64).to_radians()).map(|a| [20.0 * a.cos(), 20.0 * a.sin(), 0.0]).collect()
}

#[test]
fn points_of_a_circle_become_a_curve_on_it() {
    let points = arc_points();
    let (r, samples) = run_on(&program(&points, 3000.0, true, ""), "mill3", |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    within_segments(&samples, &points, 0.01).unwrap();
    // The polygon's chords sag 0.76 µm inside the circle; the curve through the corrected
    // points (each 3·R·δ⁴/35 = 0.16 nm inside: `crate::smoothing`'s circle test) follows it to
    // the chords' 0.1 µm.
    let off = |s: &[Sample]| {
        s.iter()
            .filter(|s| (4..184).contains(&s.line))
            .map(|s| (s.tip[0].hypot(s.tip[1]) - 20.0).abs())
            .fold(0.0, f64::max)
    };
    assert!(off(&samples) < 1.2e-4, "{}", off(&samples));
    let (plain, polygon) = run_on(&program(&points, 3000.0, false, ""), "mill3", |_| {});
    assert!(plain.completed());
    assert!(off(&polygon) > 7e-4, "{}", off(&polygon));
    // Every block's samples come in order, each block once (the chords are counted to the
    // block whose span they are).
    let lines: Vec<u32> = samples.iter().map(|s| s.line).filter(|l| (4..184).contains(l)).collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "lines out of order");
    assert_eq!(lines.first(), Some(&4));
    assert_eq!(lines.last(), Some(&183));
    // The last block ends at its programmed point.
    let end = common::end_of(&ends(&program(&points, 3000.0, true, "")), 183);
    assert!((end[0] + 20.0).abs() < 1e-12 && end[1].abs() < 1e-12, "{end:?}");
}

/// The machine position each motion of `src` on mill3 ends at, by line.
fn ends(src: &str) -> Vec<(u32, fivex_engine::canon::Pos)> {
    common::motion_ends(interpreter_with(src, "mill3", Dialect::Fanuc, |_| {}))
}

#[test]
fn a_corner_between_smooth_runs_is_reached_exactly() {
    // Two straight lines of 0.5 mm blocks meeting at 90° (beyond the 30° corner angle): the
    // tool passes through the corner point itself.
    let mut points: Vec<[f64; 3]> = (0..=20).map(|i| [i as f64 * 0.5, 0.0, 0.0]).collect();
    points.extend((1..=20).map(|i| [10.0, i as f64 * 0.5, 0.0]));
    let (r, samples) = run_on(&program(&points, 2000.0, true, ""), "mill3", |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let src = program(&points, 2000.0, true, "");
    assert_eq!(common::end_of(&ends(&src), 23)[..2], [10.0, 0.0]);
    within_segments(&samples, &points, 0.01).unwrap();
}

#[test]
fn the_program_text_ending_in_the_mode_moves_what_is_held() {
    // No G05.1 Q0, no M30: the last point is still reached, then the end of record stops the
    // FANUC run at the last line (PS5010, `docs/dialects.md`, "The end of the program's text").
    let points = arc_points();
    let src = program(&points, 3000.0, true, "").replace("G05.1 Q0\nM30\n", "");
    let (r, _) = run_on(&src, "mill3", |_| {});
    let alarms: Vec<_> = r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect();
    assert_eq!(alarms, [("PS5010", 183)]);
    assert!((r.machine[0] + 20.0).abs() < 1e-9 && r.machine[1].abs() < 1e-9, "{:?}", r.machine);
    // The interpreter hands out the held moves before the alarm.
    let mut ends = Vec::new();
    let end = interpreter_with(&src, "mill3", Dialect::Fanuc, |_| {}).run(|c| {
        if let fivex_engine::canon::CanonKind::Motion(m) = c.kind {
            ends.push((c.line, m.machine))
        }
    });
    assert_eq!(end.map_err(|a| (a.code, a.line)), Err(("PS5010".into(), 183)));
    let (line, last) = ends.last().unwrap();
    assert_eq!(*line, 183);
    assert!((last[0] + 20.0).abs() < 1e-12 && last[1].abs() < 1e-12, "{last:?}");
}

#[test]
fn the_curve_is_fed_within_the_axes_limits() {
    // A wave sampled every 0.1 mm, exact (rounded to 0.1 µm) and with ±3 µm of noise, at
    // F15000 on mill3: the curve's spans are capped by each axis's acceleration against the
    // curve's bending (`smoothing::Span::speed_cap`), so the samples keep every axis's speed,
    // acceleration and jerk, corners between chords included, in 10 ms differences.
    for noise in [0.0, 0.003] {
        let points = wave(0.1, noise, 11);
        let (s, smooth) = run_on(&program(&points, 15000.0, true, ""), "mill3", |_| {});
        assert!(s.completed(), "{:?}", s.alarms);
        within_segments(&smooth, &points, 0.01).unwrap();
        let every: Vec<Sample> = smooth.iter().step_by(10).copied().collect();
        common::check_limits_every(&every, &MachineConfig::preset("mill3").unwrap(), true, 0.01).unwrap();
    }
}

/// Points along z = 2·sin(x/5) over 30 mm of X, `step` apart, with a deterministic noise of
/// ±`noise` mm on Z.
pub(crate) fn wave(step: f64, noise: f64, seed: u64) -> Vec<[f64; 3]> {
    let mut state = seed;
    let n = (30.0 / step) as usize;
    (0..=n)
        .map(|i| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let e =
                if i == 0 || i == n { 0.0 } else { ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 2.0 * noise };
            let x = i as f64 * step;
            [x, 0.3 * x, 2.0 * (x / 5.0).sin() + e].map(|v| (v * 1e4).round() / 1e4)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(12)))]

    /// Random waves, steps, noise, feeds and tolerances: every sample within the tolerance of
    /// its block's programmed segment.
    #[test]
    fn the_tip_stays_within_the_tolerance_of_the_programmed_segments(
        step in 0.05f64..1.5,
        noise in 0.0f64..0.005,
        seed in any::<u64>(),
        feed in 500.0f64..10000.0,
        tol in 0.002f64..0.05,
    ) {
        let points = wave(step, noise, seed);
        let (r, samples) = run_on(&program(&points, feed, true, ""), "mill3", |m| m.motion.nano_smoothing.tolerance = tol);
        prop_assert!(r.completed(), "{:?}", r.alarms);
        let checked = within_segments(&samples, &points, tol);
        prop_assert!(checked.is_ok(), "{:?}", checked);
    }
}

/// `program` under G43.4 on head-bc with B and C turning along the points (B from 10° by up to
/// `tilt`° more, C by `turn`° over the run), both smoothed; the tips are the points, on the
/// lines `program` puts them.
pub(crate) fn program_5x(points: &[[f64; 3]], feed: f64, tilt: f64, turn: f64) -> String {
    let n = points.len() as f64;
    let angles = |i: usize| {
        let u = i as f64 / n;
        [(10.0 + tilt * (3.0 * u).sin().abs()) * 1e4, (turn * u) * 1e4].map(|v| v.round() / 1e4)
    };
    let p0 = points[0];
    let [b0, c0] = angles(0);
    let mut s =
        format!("G90 G00 X{:.4} Y{:.4} Z{:.4} B{b0:.4} C{c0:.4}\nG43.4 H1 G01 F{feed:.0}\n", p0[0], p0[1], p0[2]);
    s += "G05.1 Q3 X0 Y0 Z0 B0 C0\n";
    for (i, p) in points.iter().enumerate().skip(1) {
        let [b, c] = angles(i);
        s += &format!("X{:.4} Y{:.4} Z{:.4} B{b:.4} C{c:.4}\n", p[0], p[1], p[2]);
    }
    s + "G05.1 Q0\nG49\nM30\n"
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(8)))]

    /// The same under G43.4 on head-bc, B and C smoothed too (their tolerances 0.01°): the tip
    /// (forward kinematics of the sampled axes) within the tolerance of its block's segment.
    #[test]
    fn under_g43_4_the_tip_stays_within_the_tolerance(
        step in 0.1f64..1.0,
        noise in 0.0f64..0.004,
        seed in any::<u64>(),
        feed in 500.0f64..6000.0,
        tilt in 0.0f64..20.0,
        turn in -90.0f64..90.0,
    ) {
        let points = wave(step, noise, seed);
        let src = program_5x(&points, feed, tilt, turn);
        let (r, samples) = run_on(&src, "head-bc", |m| {
            for a in m.axes.iter_mut().filter(|a| a.kind == fivex_engine::machine::AxisKind::Rotary) {
                a.smoothing_tolerance = 0.01;
            }
        });
        prop_assert!(r.completed(), "{:?}", r.alarms);
        let checked = within_segments(&samples, &points, 0.01);
        prop_assert!(checked.is_ok(), "{:?}", checked);
    }
}

#[test]
fn under_g43_4_the_tip_and_the_rotary_axes_are_smoothed_within_their_tolerances() {
    // Head-bc under G43.4: the tip along an arc of radius 40 in 1° blocks, B and C turning with
    // it (B 20° → 34°, C −10° → 80°); C's tolerance 0.01°, B's 0 (the least increment).
    let mut src = String::from("G90 G00 X40. Y0 Z10. B20. C-10.\nG43.4 H1\nG01 F2000\nG05.1 Q3 X0 Y0 Z0 B0 C0\n");
    let mut tips = vec![[40.0, 0.0, 10.0]];
    let mut rot = vec![[20.0, -10.0]];
    for i in 1..=90 {
        let a = (i as f64).to_radians();
        let (p, b, c) =
            ([40.0 * a.cos(), 40.0 * a.sin(), 10.0], 20.0 + 14.0 * (i as f64 / 90.0).powi(2), -10.0 + i as f64);
        src += &format!("X{:.4} Y{:.4} Z10. B{b:.4} C{c:.4}\n", p[0], p[1]);
        tips.push([(p[0] * 1e4).round() / 1e4, (p[1] * 1e4).round() / 1e4, 10.0]);
        rot.push([(b * 1e4).round() / 1e4, c]);
    }
    src += "G05.1 Q0\nG49\nM30\n";
    let (r, samples) = run_on(&src, "head-bc", |m| {
        let c = m.axis_index(b'C').unwrap();
        m.axes[c].smoothing_tolerance = 0.01;
    });
    assert!(r.completed(), "{:?}", r.alarms);
    let m = MachineConfig::preset("head-bc").unwrap();
    let (b, c) = (m.axis_index(b'B').unwrap(), m.axis_index(b'C').unwrap());
    let mut seen = 0;
    for s in samples.iter().filter(|s| (5..=94).contains(&s.line)) {
        let i = s.line as usize - 4;
        let d = to_segment(s.tip, tips[i - 1], tips[i]);
        assert!(d < 0.01 + 1e-6, "line {}: tip {:?} {d} from its segment", s.line, s.tip);
        rotary_between(s, [(0, b, 0.001), (1, c, 0.01)], rot[i - 1], rot[i]);
        seen += 1;
    }
    assert!(seen > 90, "{seen}");
}

#[test]
fn the_modes_alarms() {
    let on = "G90 G00 X0 Y0 Z0\nG01 F1000\nG05.1 Q3 X0 Y0 Z0\n";
    // Axis words name axes with 0; at least one linear axis.
    assert_eq!(first_alarm("G05.1 Q3 X1. Y0 Z0\nM30\n", "mill3"), Some(("PS0010".into(), 1)));
    assert_eq!(first_alarm("G05.1 Q3\nM30\n", "mill3"), Some(("PS0010".into(), 1)));
    assert_eq!(first_alarm("G05.1 Q3 B0 C0\nM30\n", "head-bc"), Some(("PS0010".into(), 1)));
    // G05.1 Q2 (smooth interpolation) is not built.
    assert_eq!(first_alarm("G05.1 Q2 X0 Y0 Z0\nM30\n", "mill3"), Some(("PS0010".into(), 1)));
    // Cutter compensation with nano smoothing is not built, either order.
    assert_eq!(first_alarm(&format!("{on}G41 D1 X10.\nM30\n"), "mill3"), Some(("PS0010".into(), 4)));
    assert_eq!(first_alarm("G01 F1000\nG41 D1 X10.\nG05.1 Q3 X0 Y0 Z0\nM30\n", "mill3"), Some(("PS0010".into(), 3)));
    // G43.4 first, G05.1 Q0 before G49 (NSM-05); not with G43.5 (TV-38).
    assert_eq!(first_alarm(&format!("{on}G43.4 H1\nM30\n"), "head-bc"), Some(("PS5421".into(), 4)));
    assert_eq!(first_alarm("G43.4 H1\nG05.1 Q3 X0 Y0 Z0 B0 C0\nG49\nM30\n", "head-bc"), Some(("PS5421".into(), 3)));
    assert_eq!(first_alarm("G43.5 H1\nG05.1 Q3 X0 Y0 Z0\nM30\n", "head-bc"), Some(("PS5421".into(), 2)));
    // Tilted working plane and G54.4 do not take it, nor start inside it.
    assert_eq!(first_alarm(&format!("{on}G68.2 X0 Y0 Z0 I0 J30. K0\nM30\n"), "head-bc"), Some(("PS5462".into(), 4)));
    assert_eq!(
        first_alarm("G68.2 X0 Y0 Z0 I0 J30. K0\nG05.1 Q3 X0 Y0 Z0\nM30\n", "head-bc"),
        Some(("PS5462".into(), 2))
    );
    assert_eq!(first_alarm(&format!("{on}G54.4 P1\nM30\n"), "head-bc"), Some(("PS0439".into(), 4)));
    // The Syntec dialect has no nano smoothing.
    let syntec = common::alarm_with("G05.1 Q3 X0 Y0 Z0\nM30\n", Dialect::Syntec);
    assert!(syntec.starts_with("COR-100"), "{syntec}");
    // A program that uses it completes (the reference for the alarms above).
    assert_eq!(first_alarm(&format!("{on}X1. Y1.\nX2. Y1.5\nG05.1 Q0\nM30\n"), "mill3"), None);
    assert_eq!(
        first_alarm_with("G43.4 H1\nG05.1 Q3 X0 Y0 Z0 B0 C0\nX1. B1.\nG05.1 Q0\nG49\nM30\n", "head-bc", |_| {}),
        None
    );
}

/// Syntec STCP on head-bc: `program_5x`'s blocks (B and C turning, unless `still`) with `head`
/// (`G43.4 H1 L1` …) in place of G43.4 and G05.1 Q3.
fn stcp_program(points: &[[f64; 3]], feed: f64, head: &str) -> String {
    stcp_program_turning(points, feed, head, true)
}

fn stcp_program_turning(points: &[[f64; 3]], feed: f64, head: &str, turning: bool) -> String {
    let (tilt, turn) = if turning { (12.0, 40.0) } else { (0.0, 0.0) };
    program_5x(points, feed, tilt, turn)
        .replace("G43.4 H1 G01", &format!("{head} G01"))
        .replace("G05.1 Q3 X0 Y0 Z0 B0 C0\n", "G04 X0\n")
        .replace("G05.1 Q0\n", "G04 X0\n")
}

#[test]
fn syntec_stcp_smooths_the_tip_within_pr407_and_the_rotary_axes_within_pr3052_3053() {
    // SYN-09: RTCP plus smoothing of the tip path (Pr407, default 3 µm) and of the tool
    // orientation (Pr3052/3053, default 0.5°). The wave's ±3 µm of noise at 0.1 mm steps: the
    // tip within 3 µm of its blocks' segments while B and C turn.
    let points = wave(0.1, 0.003, 5);
    let (s, smooth) = run_in(Dialect::Syntec, &stcp_program(&points, 12000.0, "G43.4 H1 L1"), "head-bc", |_| {});
    assert!(s.completed(), "{:?}", s.alarms);
    let narrow = within_segments(&smooth, &points, 0.003).unwrap();
    assert!(narrow > 0.0005, "the noise is smoothed away: {narrow}");
    // Pr407 = 10 µm on a wave with ±8 µm of noise: within 10 µm of the blocks and using it
    // (beyond 3 µm somewhere), where Pr407 = 3 µm keeps within 3 µm. (The farthest sample of
    // the ±3 µm wave is about the noise's amplitude with either tolerance.)
    let points = wave(0.1, 0.008, 5);
    let program = stcp_program(&points, 12000.0, "G43.4 H1 L1");
    let (_, narrow) = run_in(Dialect::Syntec, &program, "head-bc", |_| {});
    within_segments(&narrow, &points, 0.003).unwrap();
    let (_, wide) = run_in(Dialect::Syntec, &program, "head-bc", |m| m.five_axis.smooth_path_tolerance = Some(0.010));
    let worst = within_segments(&wide, &points, 0.010).unwrap();
    assert!(worst > 0.005, "Pr407 = 10 µm keeps within {worst} of the blocks");
}

#[test]
fn syntec_stcp_by_pr3051_and_its_end() {
    // TV-25b/d: with Pr3051 = 1 a G43.4 without L is STCP; L0 is plain RTCP, whose motions are
    // the blocks themselves. After G49 the blocks are plain again.
    let points = wave(0.1, 0.003, 9);
    let count = |src: &str, pr3051: bool| {
        let m = {
            let mut m = MachineConfig::preset("head-bc").unwrap();
            m.five_axis.smooth_tcp = pr3051;
            m
        };
        let interp = interpreter_with(src, "head-bc", Dialect::Syntec, |c| c.machine = m.into());
        common::motion_ends(interp)
    };
    let plain = count(&stcp_program(&points, 3000.0, "G43.4 H1 L0"), true);
    let by_parameter = count(&stcp_program(&points, 3000.0, "G43.4 H1"), true);
    let by_l1 = count(&stcp_program(&points, 3000.0, "G43.4 H1 L1"), false);
    // One motion per block, and the rapid and the tool length taking effect at G43.4 (Syntec's
    // G49 without axis words moves nothing, `docs/dialects.md`, "Syntec G49").
    assert_eq!(plain.len(), points.len() + 1);
    assert_eq!(by_parameter, by_l1);
    assert_ne!(by_parameter, plain);
    // The blocks after G49 are not smoothed: their ends are the programmed points.
    let after =
        stcp_program(&points, 3000.0, "G43.4 H1 L1").replace("G49\nM30\n", "G49\nX1. Y1. Z1.\nX2. Y1.5 Z1.2\nM30\n");
    let ends = count(&after, false);
    let n = ends.len();
    assert_eq!(ends[n - 2].1[..3], [1.0, 1.0, 1.0]);
}

#[test]
fn a_polygon_of_short_blocks_is_fed_within_the_axes_limits() {
    // The same wave unsmoothed, in blocks of 0.2, 0.1 and 0.025 mm, exact and with noise: the
    // planner's corners of short blocks run as the circle they make (`docs/motion.md`,
    // "Polygons of short blocks"), so every axis keeps its speed, acceleration and jerk in 10 ms
    // differences, corners included. (Before, 0.1 mm blocks ran in 0.262 s with Z's jerk 1.7
    // times its limit, and 0.025 mm blocks with X's 1.04 times.)
    let mill3 = MachineConfig::preset("mill3").unwrap();
    for noise in [0.0, 0.003] {
        for step in [0.2, 0.1, 0.025] {
            let points = wave(step, noise, 11);
            let (r, polygon) = run_on(&program(&points, 15000.0, false, ""), "mill3", |_| {});
            assert!(r.completed(), "{:?}", r.alarms);
            let every: Vec<Sample> = polygon.iter().step_by(10).copied().collect();
            common::check_limits_every(&every, &mill3, true, 0.01)
                .unwrap_or_else(|e| panic!("step {step}, noise {noise}: {e}"));
        }
    }
}

#[test]
fn smoothing_shortens_the_cycle_time_of_short_blocks() {
    // Both runs within the axes' limits (the tests above), the smoothed one quicker: its curve
    // turns as the points do without the polygon's corners (`docs/performance.md`, "Nano
    // smoothing", has the times).
    for noise in [0.0, 0.003] {
        for step in [0.5, 0.2, 0.1, 0.05] {
            let points = wave(step, noise, 11);
            let (polygon, _) = run_on(&program(&points, 15000.0, false, ""), "mill3", |_| {});
            let (smoothed, _) = run_on(&program(&points, 15000.0, true, ""), "mill3", |_| {});
            assert!(polygon.completed() && smoothed.completed());
            assert!(
                smoothed.cycle_time_s < polygon.cycle_time_s,
                "step {step}, noise {noise}: smoothed {} s, polygon {} s",
                smoothed.cycle_time_s,
                polygon.cycle_time_s
            );
        }
    }
}

/// G05.1 Q3 under G43.4 on head-bc (B and C turning) through a wave of short blocks, and the
/// same blocks unsmoothed: every axis within its speed, acceleration and jerk in 10 ms
/// differences. The curve's speed cap is the bending of the programmed axes; the machine's X,
/// swinging with the head, bends more, and ran at 1.3 times its jerk before the planner held
/// the chords' junctions to its jerk rule. Unsmoothed, X ran at 1.03 times its jerk in 0.1 mm
/// blocks while a run over their small corners was planned tick by tick (`motion::optimal`
/// does not see corners).
#[test]
fn under_g43_4_the_wave_keeps_the_axes_limits_smoothed_or_not() {
    let head_bc = MachineConfig::preset("head-bc").unwrap();
    for step in [0.2, 0.1, 0.05, 0.025] {
        let points = wave(step, 0.0, 1);
        let smoothed = program_5x(&points, 6000.0, 12.0, 40.0);
        let plain = smoothed.replace("G05.1 Q3 X0 Y0 Z0 B0 C0\n", "G04 X0\n").replace("G05.1 Q0\n", "G04 X0\n");
        let mut times = Vec::new();
        for src in [&plain, &smoothed] {
            let (r, samples) = run_on(src, "head-bc", |_| {});
            assert!(r.completed(), "{:?}", r.alarms);
            within_segments(&samples, &points, 0.003).unwrap_or_else(|e| panic!("step {step}: {e}"));
            let every: Vec<Sample> = samples.iter().step_by(10).copied().collect();
            common::check_limits_every(&every, &head_bc, true, 0.01).unwrap_or_else(|e| panic!("step {step}: {e}"));
            times.push(r.cycle_time_s);
        }
        eprintln!("wave under G43.4, {step} mm blocks: {:.3} s unsmoothed, {:.3} s in G05.1 Q3", times[0], times[1]);
    }
}

/// 20,000 blocks of 1 µm along X at F1000 on mill3 (a WHILE loop, as `tests/it/cli.rs` runs
/// it — fewer did not meet the case): the look-ahead's 256 blocks are about the distance
/// the machine needs to stop, and the last run before the stop was entered faster than it could
/// slow to what the short run after it asks for (under a jerk limit braking to 4.3 mm/s takes
/// longer than braking to rest). Its profile ran past its length (a debug assertion in
/// `Profile::plan`; in a release build the axes stood at the block's end while the feed went
/// on). Now the run slows down further: the machine never stands while fed, within its limits.
#[test]
fn micron_blocks_slow_down_in_time_for_the_stop() {
    let src = "#1=0\nWHILE[#1LT20000]DO1\nG91 G01 X0.001 F1000.\n#1=#1+1\nEND1\nM30\n";
    let (r, samples) = run_on(src, "mill3", |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let end = r.machine[0];
    assert!((end - 20.0).abs() < 1e-6, "ends at X{end}");
    let stalls = samples.windows(2).filter(|w| w[1].feed > 1.0 && w[0].machine == w[1].machine).count();
    assert_eq!(stalls, 0, "samples where the axes stand while the feed is not 0");
    let mill3 = MachineConfig::preset("mill3").unwrap();
    let every: Vec<Sample> = samples.iter().step_by(10).copied().collect();
    common::check_limits_every(&every, &mill3, true, 0.01).unwrap();
}
