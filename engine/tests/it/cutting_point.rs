//! Cutting point control (FANUC G43.8/G43.9; spec `fanuc-tcp.md` TCP-36…41, M-11, TV-29;
//! `docs/five-axis.md`, "Cutting point control"): the manual's example on a machine with A and C,
//! its direct rules, and the invariant at every sample on random machines — the tool's lowest
//! point along the surface normal is the programmed cutting point.

use crate::common;
use crate::tcp_random::{five_axis_machine, in_pi, mm, pi_frame_at, rotary_words, turned, zeros, LENGTH};

use common::random::{angles_inside, random_machine};
use common::{cases, check_limits_of, check_strokes, end_of, first_alarm_with, interpreter_with, motion_ends};
use fivex_engine::canon::Pos;
use fivex_engine::geom::Rigid;
use fivex_engine::interp::Config;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::report::run_with_report;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::tip::System;
use fivex_engine::Dialect;
use proptest::prelude::*;

/// The tool of offset 1: radius R (D geometry), corner radius r.
#[derive(Debug, Clone, Copy)]
struct Shape {
    radius: f64,
    corner: f64,
}

const BALL: Shape = Shape { radius: 5.0, corner: 5.0 };
const SQUARE: Shape = Shape { radius: 5.0, corner: 0.0 };
const BULL: Shape = Shape { radius: 6.0, corner: 2.0 };

/// Run `src` on `machine` with tool 1 of `shape`; every 1 ms sample.
fn run_tool(machine: &MachineConfig, shape: Shape, src: &str) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = machine.clone().into());
    set_tool(&mut interp, shape);
    let mut samples = Vec::new();
    let options = RunOptions { max_time_s: 120.0, ..RunOptions::default() };
    let r = run(&mut interp, &options, |s| samples.push(*s));
    (r, samples)
}

fn set_tool(interp: &mut fivex_engine::interp::Interpreter, shape: Shape) {
    let t = interp.state.offsets.tool_mut(1).unwrap();
    t.d_geometry = shape.radius;
    t.corner_radius = shape.corner;
}

/// The first alarm (code, line) of `src` on the preset with tool 1 of `shape`.
fn alarm_of(src: &str, preset: &str, shape: Shape) -> Option<(String, u32)> {
    alarm_with(src, preset, shape, |_| {})
}

/// [`alarm_of`] with the configuration `tweak` adjusts.
fn alarm_with(src: &str, preset: &str, shape: Shape, tweak: impl FnOnce(&mut Config)) -> Option<(String, u32)> {
    let mut interp = interpreter_with(src, preset, Dialect::Fanuc, tweak);
    set_tool(&mut interp, shape);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    r.alarms.first().map(|a| (a.code.clone(), a.line))
}

/// The surface normal `u` of the way from `a` to `b` (unit): on the great circle.
fn slerp(a: Vec3, b: Vec3, u: f64) -> Vec3 {
    let angle = a.angle(&b);
    if angle < 1e-12 {
        return a;
    }
    (a * ((1.0 - u) * angle).sin() + b * (u * angle).sin()) / angle.sin()
}

/// How far the tool's lowest point along the normal `n` is from the cutting point `p`: the tool
/// is a corner torus (its centre circle `r` above the tip, radius R − r about the axis `v`)
/// closed by a flat end; the circle's lowest point along `n` is across the axis against `n`'s
/// part across the tool, and the tool surface is `r` below it along `n`.
fn lowest_point_error(shape: Shape, tip: Vec3, v: Vec3, n: Vec3, p: Vec3) -> f64 {
    (lowest_point(shape, tip, v, n) - p).norm()
}

fn lowest_point(shape: Shape, tip: Vec3, v: Vec3, n: Vec3) -> Vec3 {
    let across = n - v * n.dot(&v);
    let side = across.try_normalize(1e-12).unwrap_or_else(Vec3::zeros);
    tip + v * shape.corner - side * (shape.radius - shape.corner) - n * shape.corner
}

/// TV-29a–f, the manual's example (§2.3.20) on the trunnion table-ac (A, C), with the seed's
/// `I-1..0` read as I-1.0: for a ball, a square and a bull-nose end mill the tool's lowest
/// point along the surface normal is the programmed point at every sample of N30–N50; N40 keeps
/// N30's normal; N50 turns it on the great circle to (0, −1, 1).
#[test]
fn tv29_the_tool_touches_the_programmed_cutting_point() {
    let src = "N10 G90 G00 X0.0 Y0.0 Z0.0 A0 C0.0\nN20 G43.8 H1 D1 ,L2 I-1.0 J0.0 K10.0\n\
               N30 G01 X20.0 Y0.0 Z0.0 A0.0 C0.0 F1800. ,L2 I-1.0 J0.0 K10.0\n\
               N40 G01 X20.0 Y20.0 Z0.0 A10.0 C5.0\nN50 G01 X0.0 Y20.0 Z0.0 A20.0 C7.0 ,L2 I0.0 J-1.0 K1.0\n\
               N200 G49\nM30\n";
    let m = MachineConfig::preset("table-ac").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let pi = pi_frame_at(&kin, &zeros(&m));
    let (n1, n2) = (Vec3::new(-1.0, 0.0, 10.0).normalize(), Vec3::new(0.0, -1.0, 1.0).normalize());
    for shape in [BALL, SQUARE, BULL] {
        let (r, samples) = run_tool(&m, shape, src);
        assert!(r.completed(), "{shape:?}: {:?}", r.alarms);
        let mut seen = [0usize; 3];
        for s in samples.iter().filter(|s| matches!(s.n, Some(30 | 40 | 50))) {
            assert_eq!(s.programmed_in, System::Programming);
            let p = Vec3::from(s.programmed);
            let n = match s.n {
                Some(50) => slerp(n1, n2, ((20.0 - p.x) / 20.0).clamp(0.0, 1.0)),
                _ => n1,
            };
            let (tip, v) = in_pi(&kin, &pi, &s.machine);
            let e = lowest_point_error(shape, tip, v, n, p);
            assert!(e < 1e-6, "{shape:?} N{:?} at {p:?}: the tool is {e} mm off the cutting point", s.n);
            // The sample's cutting point (Π is the workpiece system here) is the programmed one.
            let cutting = Vec3::from(s.cutting.expect("a cutting point under G43.8"));
            assert!((cutting - p).norm() < 1e-6, "{shape:?} N{:?}: {cutting:?} vs {p:?}", s.n);
            seen[(s.n.unwrap() / 10 - 3) as usize] += 1;
        }
        assert!(seen.iter().all(|&k| k > 10), "{seen:?}: too few samples to judge");
        assert!(samples.iter().filter(|s| s.n == Some(10)).all(|s| s.cutting.is_none()));
        // The run report measures the tip against the tip the cutting point asks for.
        let mut interp = interpreter_with(src, "table-ac", Dialect::Fanuc, |_| {});
        set_tool(&mut interp, shape);
        let (_, report) = run_with_report(&mut interp, &RunOptions::default());
        assert!(report.tip_deviation.max < 1e-6, "{shape:?}: {}", report.tip_deviation.max);
    }
}

/// TV-29g: no `,L2` in the G43.8 block: the normal is the reference tool direction (+Z here):
/// a square end mill along it faces with its flat end on the cutting point. TV-29h: `,L2 I1.0`
/// alone is (1, 0, 0) (J and K 0): the tool's side touches a wall, its axis R along +X from the cutting
/// point, the tip level with it.
#[test]
fn tv29g_h_the_normal_defaults_and_omitted_components() {
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let ends = |src: &str| {
        let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |_| {});
        set_tool(&mut interp, SQUARE);
        motion_ends(interp)
    };
    let facing = ends("G90 G00 X0 Y0 Z50. B0 C0\nG43.8 H1 D1\nG01 X10. F1000.\nG49\nM30\n");
    let tip = kin.forward(&end_of(&facing, 3), LENGTH).tip;
    assert!((tip - Vec3::new(10.0, 0.0, 50.0)).norm() < 1e-9, "{tip:?}");
    // (J0.0004 reads as 0: the normal has as many decimals as the increment system.)
    let wall = ends("G90 G00 X0 Y0 Z50. B0 C0\nG43.8 H1 D1 ,L2 I1. K1.\nG01 X10. F1000. ,L2 I1.0 J0.0004\nG49\nM30\n");
    let tip = kin.forward(&end_of(&wall, 3), LENGTH).tip;
    assert!((tip - Vec3::new(15.0, 0.0, 50.0)).norm() < 1e-9, "{tip:?}");
}

/// TV-29i and the other refusals: `,L2 I0 J0 K0` is PS5464 (also in the start block); `,L`
/// other than `,L2`, or outside cutting point control, is PS0009; G02 is PS5421 (TCP-41);
/// cutter compensation under it and cutting point control in a tilted plane are not built
/// (PS0010); a corner radius beyond the tool radius is PS5464.
#[test]
fn tv29i_and_the_refusals() {
    let cases: &[(&str, Shape, &str, u32)] = &[
        ("G43.8 H1 D1\nG01 X1. F100 ,L2 I0 J0 K0\n", SQUARE, "PS5464", 2),
        ("G43.8 H1 D1 ,L2 I0 J0 K0\n", SQUARE, "PS5464", 1),
        ("G43.8 H1 D1\nG01 X1. F100 ,L3 I1.\n", SQUARE, "PS0009", 2),
        ("G43.4 H1\nG01 X1. F100 ,L2 I1.\n", SQUARE, "PS0009", 2),
        ("G01 X1. F100 ,L2 K1.\n", SQUARE, "PS0009", 1),
        ("G43.8 H1 D1\nG02 X1. R1. F100\n", SQUARE, "PS5421", 2),
        ("G43.8 H1 D1\nG41 D1 G01 X1. F100\n", SQUARE, "PS0010", 2),
        ("G43.8 H1 D1\n", Shape { radius: 5.0, corner: 6.0 }, "PS5464", 1),
        // Opposite normals in one block.
        ("G43.8 H1 D1 ,L2 K1.\nG01 X1. F100 ,L2 K-1.\n", BALL, "PS5464", 2),
    ];
    for &(src, shape, code, line) in cases {
        let got = alarm_of(&format!("G90 G00 X0 Y0 Z50. B0 C0\n{src}M30\n"), "head-bc", shape);
        assert_eq!(got, Some((code.to_string(), line + 1)), "{src}");
    }
    // G54.4 (with its tool direction compensation, RCM = 1, under which TCP may start) and the
    // tilted plane never meet it: the interlocks refuse them either way round.
    let rcm = |c: &mut Config| c.edit_machine(|m| m.five_axis.tool_direction_compensation = true);
    let wse_first = "G90 G00 X0 Y0 Z50. B0 C0\nG05.1 Q1\nG54.4 P1\nG43.8 H1 D1\nM30\n";
    assert_eq!(alarm_with(wse_first, "head-bc", SQUARE, rcm), Some(("PS0437".into(), 4)));
    let cutting_first = "G90 G00 X0 Y0 Z50. B0 C0\nG05.1 Q1\nG43.8 H1 D1\nG54.4 P1\nM30\n";
    assert_eq!(alarm_with(cutting_first, "head-bc", SQUARE, rcm), Some(("PS5421".into(), 4)));
    let plane = "G90 G00 X0 Y0 Z50. B0 C0\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG43.8 H1 D1\nM30\n";
    assert_eq!(alarm_of(plane, "head-bc", SQUARE), Some(("PS5462".into(), 4)));
    // Comma addresses other than ,L: after ,L only I, J, K; ,C and ,R (performed,
    // `interp::chamfer`) need a next move in the plane, which M30 is not (PS0051).
    for (src, code) in
        [("G01 X1. ,C1. F100\n", "PS0051"), ("G01 X1. ,R1. F100\n", "PS0051"), ("G01 X1. ,Q1.\n", "PS0004")]
    {
        let got = first_alarm_with(&format!("{src}M30\n"), "mill3", |_| {});
        assert_eq!(got.map(|a| a.0), Some(code.to_string()), "{src}");
    }
}

/// With No.11262 = 0 a square end mill cannot pass through its singular posture (the tool
/// along the normal): its vector would turn half round at once, so the block is PS5464.
/// A facing pass with the tool along the normal all the way runs (the flat end on the point).
#[test]
fn a_flat_end_through_the_singular_posture_needs_no_11262() {
    let src = "G90 G00 X0 Y0 Z50. B-20. C0\nG43.8 H1 D1 ,L2 K1.\nG01 X40. B20. F1000.\nG49\nM30\n";
    assert_eq!(alarm_of(src, "head-bc", SQUARE), Some(("PS5464".into(), 3)));
    assert_eq!(alarm_of(src, "head-bc", BALL), None);
    let facing = "G90 G00 X0 Y0 Z50. B0 C0\nG43.8 H1 D1 ,L2 K1.\nG01 X40. F1000.\nG49\nM30\n";
    assert_eq!(alarm_of(facing, "head-bc", SQUARE), None);
}

/// TV-29k (§2.3.21): No.11262 = 5°, a square end mill tilting through the normal: while the
/// tool is within 5° of it the tip keeps the vector it had where it came within (the cutting
/// point drifts from the programmed one); after it leaves, the vector goes back to the tool's
/// own by the block's end (a decision), and before it the tool touches the programmed point.
#[test]
fn tv29k_near_the_singular_posture_the_vector_is_held() {
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.five_axis.cutting_point_singular_angle = 5.0;
    let kin = Kinematics::new(&m).unwrap();
    let src = "G90 G00 X0 Y0 Z50. B-20. C0\nG43.8 H1 D1 ,L2 K1.\nG01 X40. B20. F1000.\nG49\nM30\n";
    let (r, samples) = run_tool(&m, SQUARE, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let n = Vec3::z();
    // The tool at B = −5° (X = 15): R across the tool towards +X... its own vector there.
    let held = {
        let b = (-5f64).to_radians();
        let v = Vec3::new(b.sin(), 0.0, b.cos());
        let side = (n - v * n.dot(&v)).normalize();
        side * SQUARE.radius
    };
    let (mut before, mut inside, mut after, mut drift) = (0, 0, 0, 0.0f64);
    for s in samples.iter().filter(|s| s.line == 3) {
        let p = Vec3::from(s.programmed);
        let tool = kin.forward(&s.machine, LENGTH);
        let vector = tool.tip - p;
        if p.x < 14.9 {
            let e = lowest_point_error(SQUARE, tool.tip, tool.tool, n, p);
            assert!(e < 1e-6, "at X{}: {e}", p.x);
            before += 1;
        } else if p.x > 15.1 && p.x < 24.9 {
            assert!((vector - held).norm() < 1e-6, "at X{}: {vector:?}, held {held:?}", p.x);
            // The trace shows where the tool really touches: off the programmed point.
            let touches = lowest_point(SQUARE, tool.tip, tool.tool, n);
            let cutting = Vec3::from(s.cutting.expect("a cutting point under G43.8"));
            assert!((cutting - touches).norm() < 1e-6, "at X{}: {cutting:?} vs {touches:?}", p.x);
            drift = drift.max((cutting - p).norm());
            inside += 1;
        } else if p.x > 25.1 {
            after += 1;
        }
    }
    assert!(before > 10 && inside > 10 && after > 10, "{before} {inside} {after}");
    // Within 5° of the normal a square end mill's held vector lets the contact drift by up to
    // 2·R·sin 5° ≈ 0.87 mm.
    assert!(drift > 0.5, "{drift}");
    // At the end the tool's own vector again: the lowest point is the cutting point.
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = m.clone().into());
    set_tool(&mut interp, SQUARE);
    let tool = kin.forward(&end_of(&motion_ends(interp), 3), LENGTH);
    assert!(lowest_point_error(SQUARE, tool.tip, tool.tool, n, Vec3::new(40.0, 0.0, 50.0)) < 1e-6);
}

/// A block without `,L2` keeps the surface normal on the part (the table frame), whatever Π
/// is: with Π the workpiece system at each block's end angles (WKP = 1) or the table at zero
/// after a start elsewhere, the table turning, the tool stays on the programmed point without a
/// jump between blocks (a decision, `docs/five-axis.md`).
#[test]
fn the_normal_stays_on_the_part_as_the_table_turns() {
    use fivex_engine::machine::TcpCoordinates::{TableAtZero, Workpiece};
    let src = "G90 G00 X0 Y0 Z20. A10. C30.\nG43.8 H1 D1 ,L2 I1. K2.\nG01 X10. C60. F1000.\nX20. C90.\n\
               X30. A20. C120. ,L2 I1. K1.\nG49\nM30\n";
    for coordinates in [Workpiece, TableAtZero] {
        let mut m = MachineConfig::preset("table-ac").unwrap();
        m.five_axis.tcp_coordinates = coordinates;
        let (r, samples) = run_tool(&m, BULL, src);
        assert!(r.completed(), "{coordinates:?}: {:?}", r.alarms);
        // The tip on the part and where it touches (both from the axes) move on, never by a
        // jump (1 ms samples at F1000 with the table turning: well under 0.2 mm). Were the
        // kept normal read in each block's Π, the tool's vector would turn with the table at
        // every block start (about 2 mm here).
        let on: Vec<&Sample> = samples.iter().filter(|s| s.cutting.is_some()).collect();
        assert!(on.len() > 100, "{coordinates:?}");
        for w in on.windows(2) {
            let tip = (Vec3::from(w[1].tip_table) - Vec3::from(w[0].tip_table)).norm();
            let touch = (Vec3::from(w[1].cutting.unwrap()) - Vec3::from(w[0].cutting.unwrap())).norm();
            assert!(tip < 0.2 && touch < 0.2, "{coordinates:?} line {}: jumps {tip} / {touch} mm", w[1].line);
        }
    }
}

/// TCP-41: on a machine whose rotary axes turn the tool, a rotary axis moved by hand under
/// cutting point control makes the next move PS5464; a linear axis moved by hand does not.
#[test]
fn tcp41_a_tool_rotary_axis_moved_by_hand_is_ps5464() {
    let src = "G90 G00 X0 Y0 Z50. B0 C0\nG43.8 H1 D1\nG01 X10. F1000.\nG01 X20.\nG49\nM30\n";
    for (moved, want) in [(4usize, Some("PS5464")), (0, None)] {
        let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |_| {});
        set_tool(&mut interp, SQUARE);
        let mut out = Vec::new();
        let mut machine = None;
        while let Ok(step) = interp.step(&mut out) {
            if let Some(fivex_engine::canon::Canon { kind: fivex_engine::canon::CanonKind::Motion(mo), line, .. }) =
                out.last()
            {
                if *line == 3 {
                    machine = Some(mo.machine);
                    break;
                }
            }
            if matches!(step, fivex_engine::interp::Step::Ended) {
                break;
            }
        }
        let mut at = machine.expect("line 3 moves");
        at[moved] += 2.0;
        interp.moved_to(&at);
        let mut alarm = None;
        loop {
            match interp.step(&mut out) {
                Ok(fivex_engine::interp::Step::Ended) => break,
                Ok(_) => {}
                Err(a) => {
                    alarm = Some(a.code);
                    break;
                }
            }
        }
        assert_eq!(alarm.as_deref(), want, "axis {moved}");
    }
}

/// A feed hold in the held stretch of TV-29k's block, and one after it (where the vector fades
/// back), then cycle start: the rest of the block is the rest of the same path — every tip of
/// the interrupted run lies on the uninterrupted run's tip path, and both end alike.
#[test]
fn a_feed_hold_under_cutting_point_control_resumes_on_the_same_path() {
    use fivex_engine::controller::{Controller, RunState};
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.five_axis.cutting_point_singular_angle = 5.0;
    let kin = Kinematics::new(&m).unwrap();
    let src = "G90 G00 X0 Y0 Z50. B-20. C0\nG43.8 H1 D1 ,L2 K1.\nG01 X40. B20. F1000.\nG49\nM30\n";
    let held_run = |holds: &[f64]| {
        let mut c = Controller::new(fivex_engine::interp::Config::new(m.clone(), Dialect::Fanuc));
        c.select_program(src).unwrap();
        let t = c.interpreter_mut().state.offsets.tool_mut(1).unwrap();
        (t.h_geometry, t.d_geometry, t.corner_radius) = (100.0, SQUARE.radius, SQUARE.corner);
        c.cycle_start().unwrap();
        let mut tips = Vec::new();
        let mut holds = holds.iter().peekable();
        while c.run_state() != RunState::Idle && c.time() < 120.0 {
            c.tick(0.001);
            let s = c.sample();
            if s.line == 3 {
                tips.push(kin.forward(&c.point().machine, 100.0).tip);
            }
            // Hold where the cutting point passes X, then go on after standing a while.
            if let Some(&&x) = holds.peek() {
                if s.line == 3 && s.programmed[0] > x {
                    holds.next();
                    c.feed_hold();
                    for _ in 0..400 {
                        c.tick(0.001);
                        tips.push(kin.forward(&c.point().machine, 100.0).tip);
                    }
                    c.cycle_start().unwrap();
                }
            }
        }
        assert_eq!(c.run_state(), RunState::Idle);
        (tips, c.point().machine)
    };
    // The uninterrupted run sampled ten times as often as the ticks (its polyline within the
    // tolerance of its own curve).
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = m.clone().into());
    set_tool(&mut interp, SQUARE);
    let mut whole = Vec::new();
    let r = run(&mut interp, &RunOptions { period_s: 0.0001, ..RunOptions::default() }, |s| {
        if s.line == 3 {
            whole.push(kin.forward(&s.machine, 100.0).tip);
        }
    });
    let end = r.machine;
    let (held, held_end) = held_run(&[20.0, 30.0]);
    assert!(end.iter().zip(&held_end).all(|(a, b)| (a - b).abs() < 1e-9), "{end:?} {held_end:?}");
    // Both runs go along the path in order: look for each tip near where the last one was.
    let mut at = 0usize;
    let mut worst = 0.0f64;
    for p in &held {
        let (mut best, mut best_k) = (f64::INFINITY, at);
        for k in at.saturating_sub(20)..(at + 400).min(whole.len() - 1) {
            let (a, d) = (whole[k], whole[k + 1] - whole[k]);
            let u = if d.norm() > 0.0 { ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
            let e = (p - (a + d * u)).norm();
            if e < best {
                (best, best_k) = (e, k);
            }
        }
        at = best_k;
        worst = worst.max(best);
    }
    assert!(worst < 1e-6, "the resumed tip leaves the path by {worst} mm");
}

/// Tool 1 of a random shape: a ball, a square or a bull-nose end mill.
fn shape() -> impl Strategy<Value = Shape> {
    (1.0..8.0f64, 0..3u8, 0.1..0.9f64).prop_map(|(radius, kind, share)| {
        let radius = mm(radius);
        let corner = match kind {
            0 => radius,
            1 => 0.0,
            _ => mm(radius * share),
        };
        Shape { radius, corner }
    })
}

/// A normal within about 60° of `v` (the tool on the material's side): the words
/// `,L2 I J K` a program writes for it, and the unit normal they give.
fn normal_near(v: Vec3, a: [f64; 3]) -> (String, Vec3) {
    let n = (v + Vec3::from(a) * 0.9).normalize() * 1000.0;
    let words = format!(",L2 I{:.3} J{:.3} K{:.3}", n.x, n.y, n.z);
    let written = Vec3::new(mm(n.x), mm(n.y), mm(n.z));
    (words, written.normalize())
}

/// Where the random programs start: the machine's mechanism and Π (TCP started at commanded
/// angles 0), the program up to its first move (`code` H1 D1 with a normal near the tool, the tip
/// to (0, 0, 50)), and that normal.
fn start(m: &MachineConfig, code: &str, tilt: [f64; 3]) -> (Kinematics, Rigid, String, Vec3) {
    let kin = Kinematics::new(m).unwrap();
    let pi = pi_frame_at(&kin, &zeros(m));
    let v0 = pi.r.transpose() * kin.forward(&zeros(m), LENGTH).tool;
    let (words, n0) = normal_near(v0, tilt);
    let src = format!("G90 G17 G00{}\n{code} H1 D1 {words}\nX0 Y0 Z50.\nG01 F2000.\n", rotary_words(m, &zeros(m)));
    (kin, pi, src, n0)
}

/// Run a random program to its end; the samples. Left out (not failed): a square or bull-nose
/// end mill taken through its singular posture (PS5464 without No.11262, as
/// `a_flat_end_through_the_singular_posture_needs_no_11262` shows; not seen in 500 cases of
/// each property). An axis beyond its stroke fails (the rotary axes turn between angles within
/// their ranges; none in those cases), and so does a run past the time budget, as in `tcp_random`.
fn run_or_skip(m: &MachineConfig, tool: Shape, src: &str) -> Result<Vec<Sample>, TestCaseError> {
    let (r, samples) = run_tool(m, tool, src);
    prop_assume!(r.completed() || r.alarms[0].code != "PS5464" || tool.corner >= tool.radius);
    prop_assert!(r.completed(), "{:?}\n{src}\n{m:?}", r.alarms);
    Ok(samples)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(12), ..ProptestConfig::default() })]

    /// G43.8 on random machines, random tools, normals and angles: at every sample the tool's
    /// lowest point along the normal (on the great circle between the block's normals at the
    /// fraction of the cutting point's travel) is the programmed cutting point, and every axis
    /// within its stroke.
    #[test]
    fn type1_the_tool_touches_the_cutting_point_on_random_machines(
        m in random_machine(),
        tool in shape(),
        blocks in prop::collection::vec((prop::array::uniform3(-40.0..40.0f64), prop::collection::vec(0.0..1.0f64, 8), prop::array::uniform3(-0.5..0.5f64)), 1..4),
        first in prop::array::uniform3(-0.5..0.5f64),
    ) {
        let (kin, pi, mut src, n0) = start(&m, "G43.8", first);
        let (mut at, mut normal) = (Vec3::new(0.0, 0.0, 50.0), n0);
        let mut moves = Vec::new();
        for (k, (p, fractions, tilt)) in blocks.iter().enumerate() {
            let q = angles_inside(&m, fractions, 3.0);
            let v = pi.r.transpose() * kin.forward(&q, LENGTH).tool;
            let (words, n) = normal_near(v, *tilt);
            let end = Vec3::from(p.map(mm));
            src += &format!("X{:.3} Y{:.3} Z{:.3}{} {words}\n", end.x, end.y, end.z, rotary_words(&m, &q));
            moves.push((5 + k as u32, at, end, normal, n));
            (at, normal) = (end, n);
        }
        src += "G49\nM30\n";
        let samples = run_or_skip(&m, tool, &src)?;
        let mut interp = interpreter_with(&src, "mill3", Dialect::Fanuc, |c| c.machine = m.clone().into());
        set_tool(&mut interp, tool);
        let ends = motion_ends(interp);
        for &(line, a, b, n0, n1) in &moves {
            let of_line: Vec<&Sample> = samples.iter().filter(|s| s.line == line).collect();
            prop_assert!(!of_line.is_empty(), "line {line}: no sample\n{src}");
            for s in of_line {
                let p = Vec3::from(s.programmed);
                let n = slerp(n0, n1, fraction(&kin, &ends, line, (a, b), s));
                let (tip, v) = in_pi(&kin, &pi, &s.machine);
                let e = lowest_point_error(tool, tip, v, n, p);
                prop_assert!(e < 1e-6, "line {line} at {p:?}: the tool is {e} mm off the cutting point\n{src}\n{m:?}");
            }
        }
        check_strokes(&samples, &m)?;
        check_limits(&samples, &m, &src)?;
    }

    /// G43.9 on random 5-axis machines: the tool ends along the programmed I, J, K and touches
    /// the programmed cutting point there.
    #[test]
    fn type2_ends_on_the_cutting_point_on_random_machines(
        m in five_axis_machine(),
        tool in shape(),
        blocks in prop::collection::vec((prop::array::uniform3(-40.0..40.0f64), prop::collection::vec(0.0..1.0f64, 8), prop::array::uniform3(-0.5..0.5f64)), 1..4),
        first in prop::array::uniform3(-0.5..0.5f64),
    ) {
        let (kin, pi, mut src, n0) = start(&m, "G43.9", first);
        let mut want = Vec::new();
        let (mut at, mut normal) = (Vec3::new(0.0, 0.0, 50.0), n0);
        for (k, (p, fractions, tilt)) in blocks.iter().enumerate() {
            let q = angles_inside(&m, fractions, 5.0);
            let v = pi.r.transpose() * kin.forward(&q, LENGTH).tool;
            let (words, n) = normal_near(v, *tilt);
            let end = Vec3::from(p.map(mm));
            src += &format!("X{:.3} Y{:.3} Z{:.3} I{:.9} J{:.9} K{:.9} {words}\n", end.x, end.y, end.z, v.x, v.y, v.z);
            let v = Vec3::new(format!("{:.9}", v.x).parse().unwrap(), format!("{:.9}", v.y).parse().unwrap(), format!("{:.9}", v.z).parse().unwrap()).normalize();
            want.push((5 + k as u32, at, end, v, normal, n));
            (at, normal) = (end, n);
        }
        src += "G49\nM30\n";
        let samples = run_or_skip(&m, tool, &src)?;
        let mut interp = interpreter_with(&src, "mill3", Dialect::Fanuc, |c| c.machine = m.clone().into());
        set_tool(&mut interp, tool);
        let ends = motion_ends(interp);
        for &(line, _, p, v, _, n) in &want {
            let (tip, tool_dir) = in_pi(&kin, &pi, &end_of(&ends, line));
            prop_assert!((tool_dir - v).norm() < 1e-6, "line {line}: the tool ends along {tool_dir:?}, not {v:?}\n{src}");
            let e = lowest_point_error(tool, tip, tool_dir, n, p);
            prop_assert!(e < 1e-6, "line {line}: the tool ends {e} mm off the cutting point\n{src}\n{m:?}");
        }
        check_limits(&samples, &m, &src)?;
    }
}

/// How far along its block (`line`, the cutting point from `a` to `b`) sample `s` is: by the
/// cutting point's travel, or where it stays, by the rotary axes' turn (`turned`).
fn fraction(kin: &Kinematics, ends: &[(u32, Pos)], line: u32, (a, b): (Vec3, Vec3), s: &Sample) -> f64 {
    if (b - a).norm() > 0.0 {
        return ((Vec3::from(s.programmed) - a).norm() / (b - a).norm()).min(1.0);
    }
    let (q0, q1) = (end_of(ends, if line == 5 { 3 } else { line - 1 }), end_of(ends, line));
    turned(kin, &q0, &q1, &s.machine).unwrap_or(1.0)
}

/// Every axis within its speed, acceleration and jerk (also where a flat end passes near its
/// singular posture: `a_flat_end_passing_near_its_singular_posture_on_random_machines`).
fn check_limits(samples: &[Sample], m: &MachineConfig, src: &str) -> Result<(), TestCaseError> {
    check_limits_of(samples, m, false).map_err(|e| TestCaseError::fail(format!("{e}\n{src}\n{m:?}")))
}

/// A square end mill tilting past its singular posture (No.11262 = 0) at δ from the normal
/// (10⁻⁶ … 10⁻² rad, all outside PS5464's 10⁻⁷): its vector turns half round within a sliver of
/// the block about 2δ wide in the tool's angle — the tip swings half round the flat end — and
/// the axes follow it within their limits (before the grid was refined there, Y's jerk ran 23 %
/// over at 10⁻⁶ and X's 4 % at 10⁻⁴; `Grid::refine`).
#[test]
fn a_flat_end_passing_near_its_singular_posture_keeps_the_axis_limits() {
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    for (j, k) in [("0.001", "1000."), ("0.001", "100."), ("0.001", "10."), ("0.001", "1."), ("0.01", "1.")] {
        let src = format!("G90 G00 X0 Y0 Z50. B-20. C0\nG43.8 H1 D1 ,L2 J{j} K{k}\nG01 X40. B20. F1000.\nG49\nM30\n");
        let (r, samples) = run_tool(&m, SQUARE, &src);
        assert!(r.completed(), "{:?}\n{src}", r.alarms);
        let n = Vec3::new(0.0, j.parse().unwrap(), k.parse().unwrap()).normalize();
        // The tip swings half round the flat end: the contact point changes sides.
        let mut sides = (false, false);
        for s in samples.iter().filter(|s| s.line == 3) {
            let p = Vec3::from(s.programmed);
            let tool = kin.forward(&s.machine, LENGTH);
            let e = lowest_point_error(SQUARE, tool.tip, tool.tool, n, p);
            assert!(e < 1e-6, "{src}at X{}: {e} mm off the cutting point", p.x);
            let across = tool.tip.x - p.x;
            sides = (sides.0 || across > 4.9, sides.1 || across < -4.9);
        }
        assert_eq!(sides, (true, true), "{src}");
        check_limits_of(&samples, &m, false).unwrap_or_else(|e| panic!("{e}\n{src}"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(12), ..ProptestConfig::default() })]

    /// A square or bull-nose end mill under G43.8 (No.11262 = 0) on random machines, its tool
    /// turning from random angles to random angles past the normal at 10⁻⁵·⁵ … 10⁻² rad (across
    /// its way there): at every sample the tool touches the programmed cutting point, and every
    /// axis keeps within its speed, acceleration and jerk while the tip swings round the flat end.
    #[test]
    fn a_flat_end_passing_near_its_singular_posture_on_random_machines(
        m in random_machine(),
        (radius, square, share) in (1.0..8.0f64, any::<bool>(), 0.1..0.9f64),
        (from, to) in (prop::collection::vec(0.0..1.0f64, 8), prop::collection::vec(0.0..1.0f64, 8)),
        end in prop::array::uniform3(-20.0..20.0f64),
        exponent in 2.0..5.5f64,
    ) {
        let tool = Shape { radius: mm(radius), corner: if square { 0.0 } else { mm(radius * share) } };
        let kin = Kinematics::new(&m).unwrap();
        // The angles as the program writes them.
        let written = |f: &[f64]| angles_inside(&m, f, 3.0).into_iter().map(mm).collect::<Vec<f64>>();
        let (q0, q1) = (written(&from), written(&to));
        let pi = pi_frame_at(&kin, &q0);
        let along = |u: f64| {
            let q: Vec<f64> = q0.iter().zip(&q1).map(|(a, b)| a + (b - a) * u).collect();
            in_pi(&kin, &pi, &q).1
        };
        let (middle, tangent) = (along(0.5), along(0.5 + 1e-6) - along(0.5 - 1e-6));
        let Some(side) = tangent.cross(&middle).try_normalize(1e-12) else {
            return Err(TestCaseError::reject("the tool does not turn"));
        };
        let delta = 10f64.powf(-exponent);
        let n = (middle * delta.cos() + side * delta.sin()) * 1e4;
        let normal = Vec3::new(mm(n.x), mm(n.y), mm(n.z)).normalize();
        let p = Vec3::from(end.map(mm));
        let src = format!(
            "G90 G17 G00{}\nG43.8 H1 D1 ,L2 I{:.3} J{:.3} K{:.3}\nX0 Y0 Z50.\nG01 F2000.\nX{:.3} Y{:.3} Z{:.3}{}\nG49\nM30\n",
            rotary_words(&m, &q0), n.x, n.y, n.z, p.x, p.y, p.z, rotary_words(&m, &q1),
        );
        let (r, samples) = run_tool(&m, tool, &src);
        prop_assert!(r.completed(), "{:?}\n{src}\n{m:?}", r.alarms);
        let mut seen = 0;
        for s in samples.iter().filter(|s| s.line == 5) {
            let (tip, v) = in_pi(&kin, &pi, &s.machine);
            let e = lowest_point_error(tool, tip, v, normal, Vec3::from(s.programmed));
            prop_assert!(e < 1e-6, "at {:?}: the tool is {e} mm off the cutting point\n{src}\n{m:?}", s.programmed);
            seen += 1;
        }
        prop_assert!(seen > 0, "no sample of the block\n{src}");
        check_strokes(&samples, &m)?;
        check_limits(&samples, &m, &src)?;
    }
}

/// A block whose cutting point stands while its `,L2` normal changes moves the tool tip (the
/// vector r·n + (R−r)·ŵ − r·v follows n): it is a block of its own, fed at F, not a zero move
/// the planner drops (before, it had no sample and the next block's first sample stepped the
/// axes 6.23 mm in 1 ms). Bull nose R5 r2 on head-bc at B20 (v = (sin 20°, 0, cos 20°)): by hand,
/// tip − cut is (−3.5031, 0, 1.1467) for n = (0, 0, 1), and for n = (0.5, 0.2, 1)/1.1358
/// ŵ = (n − v(n·v))/|…| = (0.5304, 0.3874, −0.7541), so 2n + 3ŵ − 2v = (1.7146, 2.8800, −0.6711):
/// the tip travels 6.2308 mm.
#[test]
fn a_new_normal_at_a_standing_cutting_point_moves_the_tip_within_the_limits() {
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let bull = Shape { radius: 5.0, corner: 2.0 };
    for g91 in ["", "G91 "] {
        let src = format!(
            "G90 G00 X0. Y0. Z50. B0. C0.\nG43.8 H1 D1 X0. Y0. Z0. B20. C0. ,L2 I0. J0. K1.\n\
             {g91}G01 X0. F1000. ,L2 I0.5 J0.2 K1.\nG90 X10.\nG49\nM30\n"
        );
        let (r, samples) = run_tool(&m, bull, &src);
        assert!(r.completed(), "{:?}\n{src}", r.alarms);
        check_limits(&samples, &m, &src).unwrap();
        let line3: Vec<&Sample> = samples.iter().filter(|s| s.line == 3).collect();
        // 6.23 mm at 1000 mm/min is about 0.37 s.
        assert!(line3.len() > 300, "{} samples of line 3\n{src}", line3.len());
        let tip = |machine: &Pos| kin.forward(machine, LENGTH).tip;
        let near = |a: Vec3, b: [f64; 3], tol: f64| (a - Vec3::from(b)).norm() < tol;
        let (hand_start, hand_end) = ([-3.5031, 0.0, 1.1467], [1.7146, 2.8800, -0.6711]);
        // The samples: from the start vector to within one sample's travel (F1000: 0.017 mm)
        // of the end vector.
        assert!(near(tip(&line3[0].machine), hand_start, 1e-3), "{src}");
        assert!(near(tip(&line3.last().unwrap().machine), hand_end, 0.02), "{src}");
        // The block's end: the tool touches the standing cutting point with the new normal.
        let mut interp = interpreter_with(&src, "head-bc", Dialect::Fanuc, |_| {});
        set_tool(&mut interp, bull);
        let end = end_of(&motion_ends(interp), 3);
        assert!(near(tip(&end), hand_end, 1e-4), "{end:?}\n{src}");
        let n = Vec3::new(0.5, 0.2, 1.0).normalize();
        let tool = kin.forward(&end, LENGTH);
        assert!(lowest_point_error(bull, tool.tip, tool.tool, n, Vec3::zeros()) < 1e-6, "{src}");
    }
}

/// A D word selecting another offset inside cutting point control is PS5464 at its block
/// (decision: §2.3.20 places the tool by D's radius and corner radius but does not say what a
/// D changed in the mode does; the mode had kept D1's ball while D2 was shown, 4.13 mm off for
/// a square end mill D2). The same D, and a D in the G49 block that ends the mode, run.
#[test]
fn a_d_change_in_cutting_point_control_is_refused() {
    let head = "G90 G00 X0. Y0. Z50. B0. C0.\nG43.8 H1 D1 X0. Y0. Z0. B10. ,L2 I0. J0. K1.\n";
    let refused = format!("{head}G01 X10. F100. D2\nX20.\nG49\nM30\n");
    assert_eq!(alarm_of(&refused, "head-bc", BALL), Some(("PS5464".into(), 3)));
    for tail in ["G01 X10. F100. D1\nG49\nM30\n", "G01 X10. F100.\nG49 D2\nM30\n"] {
        assert_eq!(alarm_of(&format!("{head}{tail}"), "head-bc", BALL), None, "{tail}");
    }
}
