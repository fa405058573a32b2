//! G06.2 NURBS interpolation (FANUC format, `docs/dialects.md`, "NURBS interpolation"): the path
//! against curves computed here independently (the circle a rational quadratic is, and a
//! Cox–de Boor basis-function sum), the format's alarms, and the tip on the curve under G43.4.

use crate::common;

use common::{first_alarm, interpreter, interpreter_with, motions};
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, Sample};
use fivex_engine::Dialect;

/// Run `src` on `preset` (FANUC, tool length 100 on every offset); every 1 ms sample.
fn samples_of(src: &str, preset: &str) -> Vec<Sample> {
    let mut interp = interpreter(src, preset, Dialect::Fanuc);
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    assert!(r.completed(), "{:?}\n{src}", r.alarms);
    samples
}

/// The quarter circle of radius 10 about (0, 0) from (10, 0) to (0, 10) as a rational quadratic
/// (the middle weight √2/2), completed on line 8.
const QUARTER: &str = "G90 G17 G00 X10. Y0 Z0\n\
    #1=SQRT[2]/2\n\
    G06.2 P3 K0 X10. Y0 R1. F1000\n\
    K0 X10. Y10. R#1\n\
    K0 X0 Y10. R1.\n\
    K1.\n\
    K1.\n\
    K1.\n\
    G01 X0 Y10.\n\
    M30\n";

#[test]
fn a_quarter_circle_stays_on_the_circle() {
    let samples = samples_of(QUARTER, "mill3");
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == 8).collect();
    assert!(on.len() > 100, "{} samples", on.len());
    let mut nearest_middle = f64::MAX;
    for s in &on {
        let (x, y, z) = (s.machine[0], s.machine[1], s.machine[2]);
        let r = x.hypot(y);
        assert!((r - 10.0).abs() < 1e-3, "({x}, {y}) is {r} from the centre");
        assert!(z.abs() < 1e-9 && x > -1e-9 && y > -1e-9, "({x}, {y}, {z})");
        let m = 10.0 / 2f64.sqrt();
        nearest_middle = nearest_middle.min((x - m).hypot(y - m));
    }
    // The path passes through the circle's middle point (a path to the control point would
    // reach 14.14 from the centre there).
    assert!(nearest_middle < 0.05, "{nearest_middle}");
    // The chords' ends are on the circle; the last is the last control point.
    let m = motions(QUARTER);
    let last = m[m.len() - 2].target;
    assert!(last[0].abs() < 1e-12 && (last[1] - 10.0).abs() < 1e-12, "{last:?}");
    assert!(m.len() > 50, "{} motions", m.len());
    for mo in &m[1..m.len() - 1] {
        let r = mo.target[0].hypot(mo.target[1]);
        assert!((r - 10.0).abs() < 1e-9, "{:?}", mo.target);
    }
}

/// The distance of every sample of `line` from the circle of radius `r` about `(cx, cy)`.
fn off_circle(samples: &[Sample], line: u32, (cx, cy): (f64, f64), r: f64) -> f64 {
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == line).collect();
    assert!(on.len() > 100, "{} samples of line {line}", on.len());
    on.iter().map(|s| ((s.machine[0] - cx).hypot(s.machine[1] - cy) - r).abs()).fold(0.0, f64::max)
}

#[test]
fn incremental_control_points_and_a_rotated_curve() {
    // G91: each control point from the previous one.
    let g91 = "G90 G00 X60. Y50. Z0\n#1=SQRT[2]/2\nG91 G06.2 P3 K0 X0 Y0 F1000\nK0 Y10. R#1\nK0 X-10.\n\
               K1.\nK1.\nK1.\nG90 G01 X50. Y60.\nM30\n";
    let worst = off_circle(&samples_of(g91, "mill3"), 8, (50.0, 50.0), 10.0);
    assert!(worst < 1e-3, "{worst}");
    // G68 turns the control points (a NURBS curve is invariant under affine maps): the quarter
    // from (60, 50) to (50, 60) turned 90° about (50, 50) runs from (50, 60) to (40, 50).
    let g68 = "G90 G00 X50. Y60. Z0\nG68 X50. Y50. R90.\n#1=SQRT[2]/2\nG06.2 P3 K0 X60. Y50. F1000\n\
               K0 X60. Y60. R#1\nK0 X50. Y60.\nK1.\nK1.\nK1.\nG01 X50. Y60.\nG69\nM30\n";
    let samples = samples_of(g68, "mill3");
    assert!(off_circle(&samples, 9, (50.0, 50.0), 10.0) < 1e-3);
    let last = samples.iter().rfind(|s| s.line == 9).unwrap().machine;
    assert!(last[0] < 40.01 && (last[1] - 50.0).abs() < 0.5, "{last:?}");
}

/// Under G54.4 (workpiece setting error compensation, its error a shift and a turn about Z) the
/// curve is the programmed one carried by the error, as any programmed point is (p_w =
/// Rz(−20°)·p_s + (10, 20, 0), TV-WSE-17): the quarter about (50, 50) runs on the circle of
/// radius 10 about the carried centre. In a tilted working plane the mode interlocks refuse
/// G06.2 (PS5462: not in §6.2's list).
#[test]
fn under_g54_4_the_curve_is_carried_by_the_setting_error() {
    let src = "G90 G00 X60. Y50. Z0 B0 C0\nG54.4 P1\nG00 X60. Y50.\n#1=SQRT[2]/2\nG06.2 P3 K0 X60. Y50. F1000\n\
               K0 X60. Y60. R#1\nK0 X50. Y60.\nK1.\nK1.\nK1.\nG01 X50. Y60.\nG54.4 P0\nM30\n";
    let mut interp = interpreter(src, "head-bc", Dialect::Fanuc);
    interp.state.setting_errors.sets[1] =
        fivex_engine::wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    assert!(r.completed(), "{:?}", r.alarms);
    let a = (-20f64).to_radians();
    let centre = (50.0 * a.cos() - 50.0 * a.sin() + 10.0, 50.0 * a.sin() + 50.0 * a.cos() + 20.0);
    let worst = off_circle(&samples, 10, centre, 10.0);
    assert!(worst < 1e-3, "{worst}");
    let plane = "G90 G00 X0 Y0 Z100. B0 C0\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG06.2 P3 K0 X0 Y0 F1000\n";
    assert_eq!(first_alarm(&format!("{plane}M30\n"), "head-bc"), Some(("PS5462".into(), 4)));
}

#[test]
fn a_full_circle_of_nine_control_points() {
    let src = "G90 G17 G00 X60. Y50. Z0\n\
        #1=SQRT[2]/2\n\
        G06.2 P3 K0 X60. Y50. F2000\n\
        K0 X60. Y60. R#1\n\
        K0 X50. Y60.\n\
        K1. X40. Y60. R#1\n\
        K1. X40. Y50.\n\
        K2. X40. Y40. R#1\n\
        K2. X50. Y40.\n\
        K3. X60. Y40. R#1\n\
        K3. X60. Y50.\n\
        K4.\n\
        K4.\n\
        K4.\n\
        G01 X60.\n\
        M30\n";
    let samples = samples_of(src, "mill3");
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == 14).collect();
    assert!(on.len() > 100);
    let mut seen = [false; 36];
    for s in &on {
        let (dx, dy) = (s.machine[0] - 50.0, s.machine[1] - 50.0);
        let r = dx.hypot(dy);
        assert!((r - 10.0).abs() < 1e-3, "{:?} is {r} from the centre", s.machine);
        let a = dy.atan2(dx).to_degrees().rem_euclid(360.0);
        seen[(a / 10.0) as usize % 36] = true;
    }
    assert!(seen.iter().all(|&s| s), "the path goes round: {seen:?}");
}

/// Cox–de Boor: the B-spline basis function `N_{i,p}(u)` of `knots` (0/0 = 0).
fn basis(knots: &[f64], i: usize, p: usize, u: f64) -> f64 {
    if p == 0 {
        let last = knots[knots.len() - 1];
        // The end of the range belongs to the last non-empty span.
        let inside = knots[i] <= u && (u < knots[i + 1] || (u == last && knots[i + 1] == last && knots[i] < last));
        return if inside { 1.0 } else { 0.0 };
    }
    let mut n = 0.0;
    if knots[i + p] > knots[i] {
        n += (u - knots[i]) / (knots[i + p] - knots[i]) * basis(knots, i, p - 1, u);
    }
    if knots[i + p + 1] > knots[i + 1] {
        n += (knots[i + p + 1] - u) / (knots[i + p + 1] - knots[i + 1]) * basis(knots, i + 1, p - 1, u);
    }
    n
}

fn reference(knots: &[f64], points: &[[f64; 3]], u: f64) -> Vec3 {
    let mut c = Vec3::zeros();
    for (i, p) in points.iter().enumerate() {
        c += Vec3::from(*p) * basis(knots, i, 3, u);
    }
    c
}

fn to_segment(q: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let t = if d.norm_squared() > 0.0 { ((q - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (q - (a + d * t)).norm()
}

#[test]
fn a_cubic_with_interior_knots_is_the_basis_function_sum() {
    let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 3.0, 3.0, 3.0, 3.0];
    let points = [
        [0.0, 0.0, 0.0],
        [5.0, 12.0, 1.0],
        [15.0, 14.0, -2.0],
        [22.0, 3.0, 0.5],
        [30.0, -6.0, 3.0],
        [35.0, 8.0, 1.0],
        [44.0, 10.0, -1.0],
    ];
    let mut src = String::from("G90 G00 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F1500\n");
    for (k, p) in knots[1..points.len()].iter().zip(&points[1..]) {
        src += &format!("K{k:.1} X{:.1} Y{:.1} Z{:.1}\n", p[0], p[1], p[2]);
    }
    for k in &knots[points.len()..] {
        src += &format!("K{k:.1}\n");
    }
    src += "G01 X44.\nM30\n";
    let ends: Vec<Vec3> = motions(&src).iter().map(|m| Vec3::new(m.target[0], m.target[1], m.target[2])).collect();
    let (_, chords) = ends.split_first().unwrap();
    let chords = &chords[..chords.len() - 1];
    assert!(chords.len() > 100, "{} chords", chords.len());
    assert!((chords.last().unwrap() - Vec3::new(44.0, 10.0, -1.0)).norm() < 1e-12);
    // The reference curve, densely: every chord end lies on it, and every reference point
    // lies within the tolerance of the chords.
    const N: usize = 3000;
    let at = |u: f64| reference(&knots, &points, u);
    let dense: Vec<Vec3> = (0..=N).map(|j| at(3.0 * j as f64 / N as f64)).collect();
    assert!((dense[0] - Vec3::zeros()).norm() < 1e-12 && (dense[N] - Vec3::new(44.0, 10.0, -1.0)).norm() < 1e-12);
    for q in chords {
        // The nearest grid point, then a ternary search around it.
        let j = (0..=N).min_by(|&a, &b| (dense[a] - q).norm().total_cmp(&(dense[b] - q).norm())).unwrap();
        let step = 3.0 / N as f64;
        let (mut lo, mut hi) = ((j as f64 - 1.0) * step, (j as f64 + 1.0) * step);
        for _ in 0..100 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if (at(m1.clamp(0.0, 3.0)) - q).norm() < (at(m2.clamp(0.0, 3.0)) - q).norm() {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let d = (at(lo.clamp(0.0, 3.0)) - q).norm();
        assert!(d < 1e-9, "chord end {q:?} is {d} mm off the curve");
    }
    let mut path = vec![Vec3::zeros()];
    path.extend_from_slice(chords);
    for q in &dense {
        let d = path.windows(2).map(|w| to_segment(*q, w[0], w[1])).fold(f64::MAX, f64::min);
        assert!(d < 1.5e-4, "curve point {q:?} is {d} mm off the path");
    }
}

// ---------------------------------------------------------------------------------------------
// alarms
// ---------------------------------------------------------------------------------------------

fn alarm_of(body: &str) -> Option<(String, u32)> {
    first_alarm(&format!("G90 G00 X0 Y0 Z0\n{body}\nM30\n"), "mill3")
}

#[test]
fn rank_and_knot_errors_are_ps5115() {
    let a = |code: &str, line: u32| Some((code.to_string(), line));
    // Rank 5.
    assert_eq!(alarm_of("G06.2 P5 K0 X0 Y0 F100"), a("PS5115", 2));
    // No knot in a control-point block. (Without K the G06.2 block takes the second block's.)
    assert_eq!(alarm_of("G06.2 P3 X0 Y0 F100\nX10. Y10."), a("PS5115", 3));
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nX10. Y10."), a("PS5115", 3));
    assert_eq!(alarm_of("G06.2 P3 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1.\nK1.\nG01 X20."), None);
    assert_eq!(alarm_of("G06.2 P3 X0 Y0 F100\nK0.5 X10. Y10.\nK0.5 X20. Y0\nK1.\nK1.\nK1.\nG01 X20."), None);
    // Decreasing knots (found when the curve is complete).
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK0.5\nK1."), a("PS5115", 7));
    // The first knots not equal.
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nK0.5 X10. Y10.\nK0.5 X20. Y0\nK1.\nK1.\nK1."), a("PS5115", 7));
    // A run of equal knots as long as the rank inside the curve.
    assert_eq!(
        alarm_of(
            "G06.2 P3 K0 X0 Y0 F100\nK0 X5. Y5.\nK0 X10. Y10.\nK1. X15. Y5.\nK1. X20. Y0\nK1. X25. Y5.\nK2.\nK2.\nK2."
        ),
        a("PS5115", 10)
    );
    // A wrong number of knots: a control point after the closing knots; too few control points.
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1. X30."), a("PS5115", 6));
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK1.\nK1.\nK1."), a("PS5115", 6));
    // A weight that is not positive.
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10. R0\nK0 X20. Y0\nK1.\nK1.\nK1."), a("PS5115", 7));
}

#[test]
fn a_curve_needing_too_many_chords_is_ps5115() {
    // A full circle of radius 4 km needs about 440,000 chords within 0.1 µm: more than
    // nurbs::MAX_CHORDS (200,000).
    let body = "#1=SQRT[2]/2\n#2=4000000\nG06.2 P3 K0 X0 Y0 F1000\nK0 Y#2 R#1\nK0 X#2 Y#2\n\
        K1. X[2*#2] Y#2 R#1\nK1. X[2*#2] Y0\nK2. X[2*#2] Y-#2 R#1\nK2. X#2 Y-#2\nK3. X0 Y-#2 R#1\n\
        K3. X0 Y0\nK4.\nK4.\nK4.";
    assert_eq!(alarm_of(body), Some(("PS5115".into(), 15)));
}

#[test]
fn g01_before_the_last_knot_is_ps5115() {
    let body = "G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1.\nG01 X30.";
    assert_eq!(alarm_of(body), Some(("PS5115".into(), 7)));
    // Nothing of the curve was emitted: the machine stands at its start.
    let r = common::run_with(&format!("G90 G00 X0 Y0 Z0\n{body}\nM30\n"), "mill3", Dialect::Fanuc);
    assert_eq!(r.machine[..3], [0.0, 0.0, 0.0]);
}

#[test]
fn a_hand_move_inside_the_curve_is_ps5117() {
    let src = "G90 G00 X0 Y0 Z0\nG06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1.\nK1.\nM30\n";
    let mut interp = interpreter(src, "mill3", Dialect::Fanuc);
    let mut out = Vec::new();
    // Up to the G06.2 block, then a jog of X by 2 mm.
    while interp.state.current_block().0 < 3 {
        interp.step(&mut out).expect("no alarm before the jog");
    }
    let mut at = interp.state.machine_position();
    at[0] += 2.0;
    interp.moved_to(&at);
    let err = loop {
        match interp.step(&mut out) {
            Ok(fivex_engine::interp::Step::Ended) => panic!("the curve ran after a hand move"),
            Ok(_) => {}
            Err(a) => break a,
        }
    };
    assert_eq!((err.code.as_str(), err.line), ("PS5117", 4));
}

#[test]
fn a_program_text_ending_inside_the_curve_is_ps5115() {
    let src = "G90 G00 X0 Y0 Z0\nG06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\n";
    let r = common::run_with(src, "mill3", Dialect::Fanuc);
    assert_eq!(r.alarms.first().map(|a| a.code.as_str()), Some("PS5115"));
}

#[test]
fn the_first_control_point_must_be_the_current_position() {
    assert_eq!(alarm_of("G06.2 P3 K0 X5. Y0 F100"), Some(("PS5117".into(), 2)));
    // Omitted axes are the current position.
    assert_eq!(alarm_of("G06.2 P3 K0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1.\nK1.\nG01 X20."), None);
}

#[test]
fn an_axis_not_in_the_curve_s_first_control_point_cannot_join_it_later() {
    // 15i-MA (NURBS): an axis without a control point in the first block cannot be specified
    // until the next curve; Z here would have been a NURBS component ending at Z20.
    let body = "G06.2 P3 X0. Y0. K0. F500\nX10. Y10. K0.\nX20. Y20. Z20. K0.\nK1.\nK1.\nK1.";
    assert_eq!(alarm_of(body), Some(("PS5115".into(), 4)));
    // A G06.2 block without axis words: the second block's axes are the curve's.
    let body = "G06.2 P3 K0 F100\nK0 X10. Y10.\nK0 X20. Y0 Z5.\nK1.\nK1.\nK1.";
    assert_eq!(alarm_of(body), Some(("PS5115".into(), 4)));
    // The curve's own axes may be omitted in later blocks (they keep their value).
    let body = "G06.2 P3 X0. Y0. Z0. K0. F500\nX10. K0.\nY20. Z5. K0.\nK1.\nK1.\nK1.\nG01 X20.";
    assert_eq!(alarm_of(body), None);
}

#[test]
fn a_foreign_block_inside_the_curve_is_ps5116() {
    for foreign in ["M08", "G04 P100", "S1000", "G90 K0 X5.", "F200 K0 X5.", "M30"] {
        let body = format!("G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\n{foreign}\nK0 X20. Y0\nK1.\nK1.\nK1.");
        assert_eq!(alarm_of(&body), Some(("PS5116".into(), 4)), "{foreign}");
    }
    // After the curve a new one needs G06.2.
    let body = "G06.2 P3 K0 X0 Y0 F100\nK0 X10. Y10.\nK0 X20. Y0\nK1.\nK1.\nK1.\nK0 X30.";
    assert_eq!(alarm_of(body), Some(("PS5116".into(), 8)));
}

#[test]
fn not_built_around_nurbs_is_refused() {
    // Cutter compensation, polar coordinates, inverse time feed, feed per revolution: PS0010
    // (the 15i-MA manual's alarm 1006: G06.2 in G41/G42, G93/G95 or G12.1 mode).
    for before in ["G41 D1 G01 X0 Y0 F100", "G42 D1 G01 X0 Y0 F100", "G16", "G93", "G95 M03 S1000"] {
        let body = format!("{before}\nG06.2 P3 K0 X0 Y0 F100");
        assert_eq!(alarm_of(&body), Some(("PS0010".into(), 3)), "{before}");
    }
    // G95 given in the G06.2 block itself: the same.
    assert_eq!(alarm_of("M03 S1000\nG95 G06.2 P3 K0 X0 Y0 F0.2"), Some(("PS0010".into(), 3)));
    // Syntec keeps refusing G06.2 (its manual does not describe it).
    let r = common::run_with("G90 G00 X0 Y0\nG06.2 P3 K0 X0 Y0 F100\nM30\n", "mill3", Dialect::Syntec);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("COR-100", 2));
}

#[test]
fn a_line_of_rank_2_and_its_feed() {
    // Rank 2 is the control polygon; the chords keep the feed.
    let src = "G90 G00 X0 Y0 Z0\nG06.2 P2 K0 X0 Y0 F600\nK0 X10.\nK1. X10. Y10.\nK2.\nK2.\nG01 X10.\nM30\n";
    let m = motions(src);
    assert!(m[1..].iter().all(|m| m.feed == 600.0));
    let corner = m.iter().any(|m| (m.target[0] - 10.0).abs() < 1e-12 && m.target[1].abs() < 1e-12);
    assert!(corner, "the polygon's corner is on the path");
    let end = m.last().unwrap().target;
    assert!((end[0] - 10.0).abs() < 1e-12 && (end[1] - 10.0).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// 5-axis: G43.4 with the rotary axes as NURBS components
// ---------------------------------------------------------------------------------------------

#[test]
fn under_g43_4_the_tip_follows_the_curve_while_b_turns() {
    let src = "G00 G90 B0 C0\nG55\nG43.4 H01\nG00 X150. Y100. Z20.\n\
        #1=SQRT[2]/2\n\
        G06.2 P3 K0 X150. Y100. Z20. B0 F1000\n\
        K0 X150. Y150. B15. R#1\n\
        K0 X100. Y150. B30.\n\
        K1.\n\
        K1.\n\
        K1.\n\
        G01 X100. Y150.\n\
        G49\n\
        M30\n";
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |_| {});
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    assert!(r.completed(), "{:?}", r.alarms);
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == 11).collect();
    assert!(on.len() > 100);
    let b = m.axis_index(b'B').unwrap();
    let (mut b_min, mut b_max) = (f64::MAX, f64::MIN);
    for s in &on {
        let tip = kin.forward(&s.machine, 100.0).tip;
        let r = (tip.x - 100.0).hypot(tip.y - 100.0);
        assert!((r - 50.0).abs() < 1e-3 && (tip.z - 20.0).abs() < 1e-3, "tip {tip:?} ({r} from the centre)");
        (b_min, b_max) = (b_min.min(s.machine[b]), b_max.max(s.machine[b]));
    }
    assert!(b_min < 1.0 && b_max > 29.0, "B turned from {b_min} to {b_max}");
    let ends = common::motion_ends(interpreter_with(src, "head-bc", Dialect::Fanuc, |_| {}));
    let end = kin.forward(&common::end_of(&ends, 11), 100.0);
    assert!((end.tip - Vec3::new(100.0, 150.0, 20.0)).norm() < 1e-6, "{:?}", end.tip);
}

/// C a cubic of X: control points C 0, 190, 270, 360 over X 0–30 (one Bézier span, so X = 30·u
/// runs evenly and C turns unevenly). A chord is run as a G01, every axis at one share of its
/// travel; the chords were once tested on X/Y/Z and on B/C apart, and this curve got few of
/// them, the machine 3° off C at X11.25. Every 1 ms sample, without TCP on the machine's axes
/// and under G43.4 on the tip, must be on the curve (computed here by Cox–de Boor): some u
/// with the linear axes within 0.1 µm and C within 0.0001° (X within 0.1 µm of 30·u puts u
/// within 0.1/30 µm of X/30, where C, rising, spans C((X − 0.0001)/30) to C((X + 0.0001)/30)).
#[test]
fn a_rotary_axis_turning_unevenly_stays_on_the_curve_between_the_chords() {
    let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let cs = [0.0, 190.0, 270.0, 360.0];
    let curve_c = |u: f64| (0..4).map(|i| cs[i] * basis(&knots, i, 3, u.clamp(0.0, 1.0))).sum::<f64>();
    assert!((curve_c(0.5) - 217.5).abs() < 1e-12 && (curve_c(1.0) - 360.0).abs() < 1e-12);
    let (tol_mm, tol_deg, slack) = (1e-4, 1e-4, 1e-9);
    let on_curve = |x: f64, y: f64, z: f64, c: f64| {
        let (lo, hi) = (curve_c((x - tol_mm) / 30.0), curve_c((x + tol_mm) / 30.0));
        assert!(y.hypot(z) <= tol_mm + slack, "X{x} Y{y} Z{z} off the line");
        assert!(c >= lo - tol_deg - slack && c <= hi + tol_deg + slack, "X{x}: C{c}, the curve's C{lo}–{hi}");
    };
    // head-bc's C taken as written (RAB = 1): 0 → 190 is a step of more than half a turn.
    let mut m = MachineConfig::preset("head-bc").unwrap();
    let [x, y, z, b, c] = [b'X', b'Y', b'Z', b'B', b'C'].map(|n| m.axis_index(n).unwrap());
    m.axes[c].shortest = false;
    let kin = Kinematics::new(&m).unwrap();
    let body = "G06.2 P4 K0 X0 Y0 Z0 C0 F2000\nK0 X10. C190.\nK0 X20. C270.\nK0 X30. C360.\nK1.\nK1.\nK1.\nK1.\n";
    for (src, line, tcp) in [
        (format!("G90 G00 X0 Y0 Z0 B0 C0\n{body}G01 X40.\nM30\n"), 9, false),
        (format!("G90 G00 B30. C0\nG43.4 H01\nG00 X0 Y0 Z0\n{body}G01 X40.\nG49\nM30\n"), 11, true),
    ] {
        let machine = m.clone();
        let mut interp = interpreter_with(&src, "head-bc", Dialect::Fanuc, |cfg| cfg.machine = machine.into());
        let mut samples = Vec::new();
        let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
        assert!(r.completed(), "{:?}", r.alarms);
        let on: Vec<&Sample> = samples.iter().filter(|s| s.line == line).collect();
        assert!(on.len() > 500, "{} samples", on.len());
        for s in &on {
            let p = if tcp {
                kin.forward(&s.machine, 100.0).tip
            } else {
                Vec3::new(s.machine[x], s.machine[y], s.machine[z])
            };
            assert!((s.machine[b] - if tcp { 30.0 } else { 0.0 }).abs() < 1e-9, "B{}", s.machine[b]);
            on_curve(p.x, p.y, p.z, s.machine[c]);
        }
    }
}

#[test]
fn the_feed_along_the_curve_is_what_its_bending_leaves_the_axes() {
    // A full circle of radius 3 (nine control points) at F30000 (500 mm/s) on mill3 (4000 mm/s²
    // per axis): at a steady v an axis accelerates v²/R·|cos| on the circle, so with 90 % of 4000
    // the tool may go √(3600·3) = 103.9 mm/s where one axis takes the whole bending, √√2 times
    // that at 45°; the jerk of the bending, v³/R², caps it at ∛(0.9·80000·9) = 86.5 mm/s (the
    // chords' caps rounded down to steps of 2^(1/8)). It gets near that; its chords' junction
    // steps alone held it to 29 mm/s (a run per chord).
    let src = "G90 G17 G00 X3. Y0 Z0\n#1=SQRT[2]/2\n\
        G06.2 P3 K0 X3. Y0 R1. F30000\nK0 X3. Y3. R#1\nK0 X0 Y3. R1.\nK1. X-3. Y3. R#1\n\
        K1. X-3. Y0 R1.\nK2. X-3. Y-3. R#1\nK2. X0 Y-3. R1.\nK3. X3. Y-3. R#1\nK3. X3. Y0 R1.\n\
        K4.\nK4.\nK4.\nG01 X3. Y0\nM30\n";
    let samples = samples_of(src, "mill3");
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == 14).collect();
    assert!(on.len() > 100, "{} samples", on.len());
    let top = on.iter().map(|s| s.feed / 60.0).fold(0.0, f64::max);
    let by_jerk = (0.9f64 * 80000.0 * 9.0).cbrt();
    assert!(top <= by_jerk * 1.001, "{top} mm/s");
    assert!(top > 0.8 * by_jerk, "{top} mm/s");
    // And the axes within their speed and acceleration in 10 ms differences. (Their jerk is
    // not: while the tool speeds up along the chords, their junction steps add to the bending's
    // — the planner's corner rule, `docs/motion.md`.)
    let m = MachineConfig::preset("mill3").unwrap();
    let every: Vec<&Sample> = samples.iter().step_by(10).collect();
    for w in every.windows(4) {
        for (i, axis) in m.axes.iter().enumerate() {
            let (v, a, _) = common::derivatives_every(common::positions([w[0], w[1], w[2], w[3]], i, false), 0.01);
            assert!(
                v.abs() <= axis.rapid / 60.0 && a.abs() <= axis.max_accel(),
                "axis {i}: {v} mm/s, {a} mm/s² at t = {}",
                w[0].t
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// speed along the curve: the chords the machine runs, not a point of the curve between them
// ---------------------------------------------------------------------------------------------

/// Seconds the 1 ms samples of `line` span.
fn seconds_on(samples: &[Sample], line: u32) -> f64 {
    samples.iter().filter(|s| s.line == line).count() as f64 * 1e-3
}

/// The time lost against cruising when a straight move along `dir` (unit, X/Y) starts from rest
/// on mill3 (jerk 80,000 mm/s³ per axis, acceleration 4000 mm/s² not reached below 200 mm/s):
/// the S-curve reaches v in 2·√(v/J) over v·√(v/J), so it loses √(v/J) with J the path's jerk,
/// the lowest J/|dᵢ| over the axes.
fn start_from_rest(v: f64, dir: [f64; 2]) -> f64 {
    let j = dir.iter().filter(|d| d.abs() > 1e-12).map(|d| 80000.0 / d.abs()).fold(f64::INFINITY, f64::min);
    (v / j).sqrt()
}

/// The audit's F1a: a rational quadratic whose middle weight is tiny is the straight line from
/// (0, 0) to (5, 5) within a micrometre, except a stretch of micrometres at its end where it
/// turns toward its end tangent (0,5)→(5,5). Its chords are straight; it ran at 1.1 mm/min for
/// 7513 s, the slowest speed of that stretch given to whole chords.
#[test]
fn a_nearly_straight_curve_with_a_tiny_weight_runs_at_its_feed() {
    let src = "G90 G17 G00 X0 Y0 Z0\nG06.2 P3 K0 X0 Y0 F1000\nK0 X0 Y5. R0.000001\nK0 X5. Y5.\nK1.\nK1.\nK1.\n\
               G01 X10. Y10.\nM30\n";
    let samples = samples_of(src, "mill3");
    // 5·√2 mm at 1000 mm/min, from rest, on into the G01 along the same line.
    let v = 1000.0 / 60.0;
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let ideal = 50f64.sqrt() / v + start_from_rest(v, [h, h]);
    let t = seconds_on(&samples, 7);
    assert!((t - ideal).abs() < 0.02 * ideal, "{t} s against {ideal} s");
}

/// The audit's F1b: a cubic whose second control point is 1 µm off the start (a CAM rounding):
/// the curve's radius of curvature is 0.3 µm at its start, 5 mm a few micrometres on. The first
/// chord (57 µm) ran at 1.88 mm/min.
#[test]
fn a_control_point_a_micrometre_off_the_tangent_does_not_slow_a_chord() {
    let src = "G90 G17 G00 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F3000\nK0 X0 Y0.001 Z0\nK0 X10. Y0.001 Z0\n\
               K0 X20. Y5. Z0\nK1. X30. Y5. Z0\nK2.\nK2.\nK2.\nK2.\nG01 X40. Y5.\nM30\n";
    // The curve's length by the basis-function sum above (the chords of 200,000 steps: within
    // 1e-9 of the length).
    let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0];
    let points = [[0.0, 0.0, 0.0], [0.0, 0.001, 0.0], [10.0, 0.001, 0.0], [20.0, 5.0, 0.0], [30.0, 5.0, 0.0]];
    let steps = 200_000;
    let at = |k: usize| reference(&knots, &points, 2.0 * k as f64 / steps as f64);
    let length: f64 = (1..=steps).map(|k| (at(k) - at(k - 1)).norm()).sum();
    assert!((length - 30.545).abs() < 1e-3, "{length}");
    let v = 3000.0 / 60.0;
    let ideal = length / v + start_from_rest(v, [1.0, 0.0]);
    let samples = samples_of(src, "mill3");
    let t = seconds_on(&samples, 10);
    assert!((t - ideal).abs() < 0.02 * ideal, "{t} s against {ideal} s");
}

/// A genuinely curved NURBS is still slowed as an arc of its radius is: a full circle of radius
/// 5 (nine control points) at F20000 (333 mm/s) against G02 of the same circle. fivex's arc
/// rule holds the plane's speed to w = min(√(σ·4000·5), ∛(σ·80000·25)) with the share σ of
/// the axes' limits that gives the arc the shorter time: 121.6 mm/s at σ = 0.9, 100 mm/s at
/// 0.5 — which this G02 takes, as its speed changes get the rest. The chords' caps are the
/// bending at 0.9, per axis (between 1 and 2^(1/6) times w, the most at 45° where each axis
/// takes a part of it), rounded down to steps of 2^(1/8); their speed changes are not charged
/// the bending's share (`docs/motion.md`, "NURBS"), so the curve cruises at the σ = 0.9 figure.
#[test]
fn a_circle_of_radius_5_is_slowed_as_its_arc_is() {
    let nurbs = "G90 G17 G00 X0 Y0 Z0
#1=SQRT[2]/2
G06.2 P3 K0 X0 Y0 F20000
K0 X0 Y5. R#1
K0 X5. Y5.
                 K1. X10. Y5. R#1
K1. X10. Y0
K2. X10. Y-5. R#1
K2. X5. Y-5.
K3. X0 Y-5. R#1
K3. X0 Y0
                 K4.
K4.
K4.
G01 X0 Y10.
M30
";
    let arc = "G90 G17 G00 X0 Y0 Z0
G02 I5. F20000
G01 X0 Y10.
M30
";
    let (on_curve, on_arc) = (samples_of(nurbs, "mill3"), samples_of(arc, "mill3"));
    // The speed along the middle half of each (the first and last quarters hold the speed
    // changes from rest and into the line).
    let middle = |s: &[Sample], line: u32| {
        let on: Vec<f64> = s.iter().filter(|s| s.line == line).map(|s| s.feed / 60.0).collect();
        let half = &on[on.len() / 4..on.len() * 3 / 4];
        (half.iter().sum::<f64>() / half.len() as f64, on.iter().copied().fold(0.0, f64::max))
    };
    let ((v_curve, top_curve), (v_arc, top_arc)) = (middle(&on_curve, 14), middle(&on_arc, 2));
    let w = |share: f64| (share * 4000.0 * 5.0f64).sqrt().min((share * 80000.0 * 25.0f64).cbrt());
    assert!((top_arc / w(0.5) - 1.0).abs() < 0.01 && v_arc > 0.9 * w(0.5), "arc {v_arc} mm/s, at most {top_arc}");
    assert!((top_curve / w(0.9) - 1.0).abs() < 0.05, "curve at most {top_curve} mm/s");
    assert!(v_curve > 0.85 * w(0.9) && v_curve < w(0.9), "curve {v_curve} mm/s");
    // Before, a curve's chord took the slowest point of the curve it replaced; with no cap at
    // all it would run at F (333 mm/s).
    assert!(seconds_on(&on_curve, 14) > 31.4 / w(0.9), "{}", seconds_on(&on_curve, 14));
}

// ---------------------------------------------------------------------------------------------
// NURBS interpolation mode: as long as G06.2 is the group-01 code
// ---------------------------------------------------------------------------------------------

/// A curve on lines 2–7 of `alarm_of`'s program; the mode stays G06.2 after it.
const CURVE: &str = "G06.2 P3 K0 X0 Y0 F1000\nK0 X0 Y5.\nK0 X5. Y5.\nK1.\nK1.\nK1.";

/// Verification audit F1: a program that stops in NURBS mode (its M30 right after the curve is
/// PS5116, or a reset during a curve) left G06.2 in force, and the next program alarmed at its
/// first block, `G90 G17 G40 G49 G80`, PS5116 again. A reset (and a new program's start) ends
/// the mode: group 01 at its power-on G00.
#[test]
fn a_reset_ends_nurbs_mode_so_the_next_program_runs() {
    let mut interp = interpreter(&format!("G90 G00 X0 Y0 Z0\n{CURVE}\nM30\n"), "mill3", Dialect::Fanuc);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("PS5116", 8)));
    use fivex_engine::interp::gcode::{code, group};
    assert_eq!(interp.state.modal_state().modes[group::MOTION], code::G06_2);
    interp.reset();
    assert_eq!(interp.state.modal_state().modes[group::MOTION], code::G00);
    interp.load(fivex_engine::lang::parse_file("G90 G17 G40 G49 G80\nG01 X10. F500\nM30\n"));
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
}

/// 15i-MA (NURBS): "In NURBS interpolation mode, commands (such as auxiliary functions) other
/// than NURBS interpolation cannot be specified", and the mode ends only with another group-01
/// code. They all ran (the audit's F2).
#[test]
fn after_the_curve_only_a_curve_or_another_group_01_code_may_come() {
    let foreign = [
        "M08",
        "S1000 M03",
        "T2 M06",
        "G04 P500",
        "G43 H2",
        "G49",
        "G68 X0 Y0 R10.",
        "G69",
        "G51 X0 Y0 P2000",
        "G50",
        "G91",
        "G55",
        "G92 X0 Y0",
        "G28 X0",
        "G53 X0",
        "G10 L2 P1 X5.",
        "F500",
        "G61",
        "M00",
        "M30",
        "G65 P9010 A1.",
    ];
    for block in foreign {
        assert_eq!(alarm_of(&format!("{CURVE}\n{block}\nG01 X0 Y0")), Some(("PS5116".into(), 8)), "{block}");
    }
    // In the G06.2 block itself too.
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F1000 M08\nK0 X0 Y5."), Some(("PS5116".into(), 2)));
    assert_eq!(alarm_of("G06.2 P3 K0 X0 Y0 F1000 S500\nK0 X0 Y5."), Some(("PS5116".into(), 2)));
    // A block ending the mode (with what it holds), a new curve, comments and macro
    // statements are accepted.
    for after in [
        "G01 X0 Y0",
        "G00 Z10. M09",
        "#100=#5001\n(comment)\nG01 X0 Y0",
        "G91 G06.2 P2 K0 X0 Y0\nK0 X1.\nK1.\nK1.\nG01 X0",
    ] {
        assert_eq!(alarm_of(&format!("{CURVE}\n{after}")), None, "{after}");
    }
    // `fivex check` finds them in the text.
    let lines = |src: &str| -> Vec<(u32, String)> {
        fivex_engine::check::check(fivex_engine::lang::parse_file(src), Dialect::Fanuc)
            .into_iter()
            .map(|d| (d.line, Dialect::Fanuc.describe(&d.id).0))
            .collect()
    };
    let src = format!("G90 G00 X0 Y0 Z0\n{CURVE}\nG69\nT2 M06\nG01 X0 Y0\nM08\nM30\n");
    assert_eq!(lines(&src), [(8, "PS5116".to_string()), (9, "PS5116".to_string())]);
    assert_eq!(lines("G06.2 P3 K0 X0 Y0 F100 M08\nK0 X1. Y1.\nG04 P1\n"), [(1, "PS5116".into()), (3, "PS5116".into())]);
    assert!(lines("G06.2 P3 K0 X0 Y0 F100\nK0 X1. Y1. R0.5\nN10 K1.\n#1=1\nG00 G49 Z0\nM08\n").is_empty());
    // A program that ends or retracts right after the curve (the verification audit's §4: M30,
    // M02, an M99 subprogram, G91 G28 Z0.) is told before the run, with what to write instead.
    for end in ["M30", "M02", "M99", "G91 G28 Z0."] {
        let src = format!("G90 G00 X0 Y0 Z0\n{CURVE}\n{end}\n");
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(&src), Dialect::Fanuc);
        assert_eq!(diags.iter().map(|d| d.line).collect::<Vec<_>>(), [8], "{end}");
        assert!(diags[0].detail.contains("end the mode with a G01 or G00 block"), "{}", diags[0].detail);
        assert!(lines(&format!("G90 G00 X0 Y0 Z0\n{CURVE}\nG01 X0 Y0\n{end}\n")).is_empty(), "{end}");
    }
}

// ---------------------------------------------------------------------------------------------
// rollover axes: a control point is not re-wrapped
// ---------------------------------------------------------------------------------------------

/// head-bc's C rolls over the shorter way (FANUC RAB = 0). The audit's F3: C control points 0,
/// 190, 270, 360 were taken as 0, −170, −90, 0 (the shorter way from each to the next), and C
/// turned backwards along the cut. A control point the rule would move is refused (PS5115,
/// decision); where the rule leaves every written step (RAB = 1 here, or steps under a half
/// turn) the curve is the written one.
#[test]
fn a_rollover_axis_s_control_point_is_taken_as_written_or_refused() {
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG06.2 P4 K0 X0 Y0 Z0 B0 C0 F2000\nK0 X10. C190.\nK0 X20. C270.\nK0 X30. C360.\n\
               K1.\nK1.\nK1.\nK1.\nG01 X40.\nM30\n";
    assert_eq!(first_alarm(src, "head-bc"), Some(("PS5115".into(), 3)));
    // Taken the written way (RAB = 1: by the command's sign): the literal curve.
    let mut m = MachineConfig::preset("head-bc").unwrap();
    let (x, c) = (m.axis_index(b'X').unwrap(), m.axis_index(b'C').unwrap());
    m.axes[c].shortest = false;
    let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |cfg| cfg.machine = m.into());
    let mut targets = Vec::new();
    interp
        .run(|cmd| {
            if let fivex_engine::canon::CanonKind::Motion(mo) = cmd.kind {
                targets.push(mo.target);
            }
        })
        .expect("no alarm");
    // X runs evenly (30·t), so each chord vertex is the Bézier at t = X/30; C at X15 (t = ½)
    // is (3·190 + 3·270 + 360)/8 = 217.5.
    let bezier = |t: f64| 3.0 * t * (1.0 - t).powi(2) * 190.0 + 3.0 * t * t * (1.0 - t) * 270.0 + t.powi(3) * 360.0;
    assert_eq!(bezier(0.5), 217.5);
    let on: Vec<_> = targets.iter().filter(|p| p[x] <= 30.0).collect();
    assert!(on.len() >= 4, "{} vertices", on.len());
    for p in on {
        let off = (p[c] - bezier(p[x] / 30.0) + 180.0).rem_euclid(360.0) - 180.0;
        assert!(off.abs() < 1e-6, "X{} C{} against C{}", p[x], p[c], bezier(p[x] / 30.0));
    }
    // The shorter way keeps steps under half a turn: 0, 90, 170, 250 and 300, 350, 400, 450
    // (400 is 40 written on another turn) run.
    let ok = "G90 G00 X0 Y0 Z0 B0 C0\nG06.2 P4 K0 X0 Y0 Z0 B0 C0 F2000\nK0 X10. C90.\nK0 X20. C170.\nK0 X30. C250.\n\
              K1.\nK1.\nK1.\nK1.\nG01 X40.\nM30\n";
    assert_eq!(first_alarm(ok, "head-bc"), None);
    let on =
        "G90 G00 X0 Y0 Z0 B0 C300.\nG06.2 P4 K0 X0 Y0 Z0 C300. F2000\nK0 X10. C350.\nK0 X20. C400.\nK0 X30. C450.\n\
              K1.\nK1.\nK1.\nK1.\nG01 X40.\nM30\n";
    assert_eq!(first_alarm(on, "head-bc"), None);
    // 350 → 0 is −350 written, +10 the shorter way: refused.
    let back = "G90 G00 X0 Y0 Z0 B0 C350.\nG06.2 P4 K0 X0 Y0 Z0 C350. F2000\nK0 X10. C0\nK0 X20. C10.\nK0 X30. C20.\n\
                K1.\nK1.\nK1.\nK1.\nG01 X40.\nM30\n";
    assert_eq!(first_alarm(back, "head-bc"), Some(("PS5115".into(), 3)));
    // Incremental control points are the steps themselves.
    let g91 = "G90 G00 X0 Y0 Z0 B0 C0\nG91 G06.2 P4 K0 X0 C0 F2000\nK0 X10. C190.\nK0 X10. C80.\nK0 X10. C90.\n\
               K1.\nK1.\nK1.\nK1.\nG90 G01 X40.\nM30\n";
    assert_eq!(first_alarm(g91, "head-bc"), None);
}

// ---------------------------------------------------------------------------------------------
// an interior run of knots as long as the rank
// ---------------------------------------------------------------------------------------------

/// 15i-MA: "Knots of the same value that continue in excess of the rank value cannot be
/// specified". A run equal to the rank ends one piece of the curve at the control point before
/// it and starts the next at the one after: where those coincide the curve is continuous, with
/// a corner, which the tool slows down for as at any corner (the audit's F4: it was PS5115).
/// Where they differ the curve jumps: PS5115 (decision).
#[test]
fn an_interior_run_as_long_as_the_rank_is_a_corner_where_the_curve_is_continuous() {
    let src = "G90 G00 X0 Y0 Z0\nG06.2 P3 K0 X0 Y0 F1000\nK0 X5. Y5.\nK0 X10. Y0\nK1. X10. Y0\nK1. X15. Y5.\n\
               K1. X20. Y0\nK2.\nK2.\nK2.\nG01 X30. Y0\nM30\n";
    let samples = samples_of(src, "mill3");
    let on: Vec<&Sample> = samples.iter().filter(|s| s.line == 10).collect();
    // Each piece is the quadratic Bézier of its three points: x runs 0→10 and 10→20 evenly,
    // y = 10·t·(1 − t) on each (t = x/10 − its start), a parabola; the corner is (10, 0).
    for s in &on {
        let (x, y) = (s.machine[0], s.machine[1]);
        let t = if x <= 10.0 { x / 10.0 } else { x / 10.0 - 1.0 };
        assert!((y - 10.0 * t * (1.0 - t)).abs() < 1e-3, "({x}, {y})");
    }
    let corner = on.iter().min_by(|a, b| (a.machine[0] - 10.0).abs().total_cmp(&(b.machine[0] - 10.0).abs())).unwrap();
    assert!((corner.machine[0] - 10.0).abs() < 1e-3 && corner.machine[1].abs() < 1e-3, "{:?}", corner.machine);
    // At the corner Y's direction turns from −1/√2 to +1/√2: a speed step of 4 mm/s (mill3's
    // 4000 mm/s² for 1 ms) allows 4/√2 = 2.83 mm/s there (170 mm/min), against 1000 mm/min.
    assert!(corner.feed <= 170.0 * 1.05, "{} mm/min at the corner", corner.feed);
    // The curve jumps where the points either side differ: (10, 0) to (10, 1).
    let jump =
        "G06.2 P3 K0 X0 Y0 F1000\nK0 X5. Y5.\nK0 X10. Y0\nK1. X10. Y1.\nK1. X15. Y5.\nK1. X20. Y0\nK2.\nK2.\nK2.";
    assert_eq!(alarm_of(jump), Some(("PS5115".into(), 10)));
    // A run longer than the rank stays PS5115.
    let long =
        "G06.2 P3 K0 X0 Y0 F1000\nK0 X5. Y5.\nK0 X10. Y0\nK1. X10. Y0\nK1. X15. Y5.\nK1. X20. Y0\nK1. X25. Y5.\n\
                K2.\nK2.\nK2.";
    assert_eq!(alarm_of(long), Some(("PS5115".into(), 11)));
}
