//! Tool centre point control (spec `fanuc-tcp.md`, `syntec.md` SYN-07…SYN-11): the examples of
//! the extracts with the machines they need, and the tip-on-path invariant.

// The extract prints its vectors to five places (0.70711 and the like); they are compared as
// printed.
#![allow(clippy::approx_constant)]

use crate::common;

use common::{end_of, interpreter_with, motion_ends};
use fivex_engine::canon::Pos;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::{Axis, AxisKind, Hand, MachineConfig, RotaryLink, Side, TcpCoordinates};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::tip::System;
use fivex_engine::Dialect;
use proptest::prelude::*;

/// Run `src` on `machine` with tool length 100 on every offset; every 1 ms sample.
fn run_on(machine: MachineConfig, dialect: Dialect, src: &str) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter_with(src, "mill3", dialect, |c| c.machine = machine.into());
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    (r, samples)
}

/// The machine position each motion block of `src` ends at, by line.
fn ends(machine: MachineConfig, dialect: Dialect, src: &str) -> Vec<(u32, Pos)> {
    motion_ends(interpreter_with(src, "mill3", dialect, |c| c.machine = machine.into()))
}

fn preset(name: &str) -> MachineConfig {
    MachineConfig::preset(name).unwrap()
}

fn close(a: Vec3, b: Vec3, tol: f64) -> bool {
    (a - b).norm() < tol
}

/// The largest distance of the tip (from the sampled axes) to the segment `a`–`b` over the
/// samples of `line`.
fn off_line(kin: &Kinematics, samples: &[Sample], line: u32, a: Vec3, b: Vec3, length: f64) -> f64 {
    let of_line: Vec<&Sample> = samples.iter().filter(|s| s.line == line).collect();
    assert!(!of_line.is_empty(), "no sample of line {line}: nothing to measure");
    of_line
        .into_iter()
        .map(|s| {
            let tip = kin.forward(&s.machine, length).tip;
            let d = b - a;
            let u = ((tip - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (tip - (a + d * u)).norm()
        })
        .fold(0.0, f64::max)
}

#[test]
fn tv20_head_type1_tip_moves_straight_while_b_and_c_turn() {
    let src = "N1 G00 G90 B0 C0\nN2 G55\nN3 G43.4 H01\nN4 G00 X200.0 Y150.0 Z20.0\n\
               N5 G01 X5.0 Y5.0 Z5.0 C60.0 B45.0 F500\nN6 G49\nN7 M30\n";
    let m = preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m, Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let n5: Vec<&Sample> = samples.iter().filter(|s| s.line == 5).collect();
    assert!(n5.len() > 100);
    let worst = off_line(&kin, &samples, 5, Vec3::new(200.0, 150.0, 20.0), Vec3::new(5.0, 5.0, 5.0), 100.0);
    assert!(worst < 1e-3, "tip left the line by {worst} mm");
    // At the end of N5: v = (sinB cosC, sinB sinC, cosB) at B45 C60, the tip at (5, 5, 5).
    let end = end_of(&ends(preset("head-bc"), Dialect::Fanuc, src), 5);
    let pose = kin.forward(&end, 100.0);
    assert!(close(pose.tip, Vec3::new(5.0, 5.0, 5.0), 1e-6), "{:?}", pose.tip);
    let (b, c) = (45f64.to_radians(), 60f64.to_radians());
    let v = Vec3::new(b.sin() * c.cos(), b.sin() * c.sin(), b.cos());
    assert!(close(pose.tool, v, 1e-9), "{:?}", pose.tool);
    // The extract's printed value: (0.35355, 0.61237, 0.70711).
    assert!(close(v, Vec3::new(0.35355, 0.61237, 0.70711), 1e-5));
}

/// A machine from the presets' axes with the given rotary links (X Y Z then the rotary axes in
/// letter order), for the example geometries the extract reverse-engineers (§3.4).
fn machine_with(links: Vec<RotaryLink>) -> MachineConfig {
    let mut m = preset("mill3");
    m.name = "example".into();
    let mut letters: Vec<char> = links.iter().map(|l| l.axis).collect();
    letters.sort();
    for c in letters {
        let mut a = Axis::new(c, AxisKind::Rotary, 10_800.0);
        (a.accel, a.jerk) = (Some(1_800.0), Some(36_000.0));
        m.axes.push(a);
    }
    for a in &mut m.axes {
        a.stroke = None;
    }
    m.rotary = links;
    m
}

fn link(axis: char, side: Side, direction: [f64; 3], hand: Hand, point: [f64; 3]) -> RotaryLink {
    RotaryLink { axis, side, direction, hand, point, zero_offset: 0.0, fixed: None, range: None }
}

/// §2.4.2: B table (about Y) on A (about X), both through (50, 50, 50); a table point goes to
/// `c + Rx(−60°)·Ry(+45°)·(p − c)` at A60 B45 (A left-hand, B right-hand).
fn table_ab() -> MachineConfig {
    machine_with(vec![
        link('A', Side::Table, [1.0, 0.0, 0.0], Hand::Left, [50.0, 50.0, 50.0]),
        link('B', Side::Table, [0.0, 1.0, 0.0], Hand::Right, [50.0, 50.0, 50.0]),
    ])
}

/// §2.4.3: tool B (about Y, right-hand) and table A (about X through Y100 Z0, right-hand).
fn mixed_ab() -> MachineConfig {
    machine_with(vec![
        link('B', Side::Head, [0.0, 1.0, 0.0], Hand::Right, [0.0, 0.0, 150.0]),
        link('A', Side::Table, [1.0, 0.0, 0.0], Hand::Right, [0.0, 100.0, 0.0]),
    ])
}

fn with_coordinates(mut m: MachineConfig, c: TcpCoordinates) -> MachineConfig {
    m.five_axis.tcp_coordinates = c;
    m
}

/// The tool tip in machine coordinates (= G55 with zero offsets) at the end of `line`.
fn tip_at_end(m: &MachineConfig, src: &str, line: u32) -> (Vec3, Pos) {
    let end = end_of(&ends(m.clone(), Dialect::Fanuc, src), line);
    (Kinematics::new(m).unwrap().forward(&end, 100.0).tip_machine, end)
}

#[test]
fn tv21_head_type2_reaches_the_type1_state() {
    let type1 = "N1 G00 G90 B0 C0\nN2 G55\nN3 G43.4 H01\nN4 G00 X200.0 Y150.0 Z20.0\n\
                 N5 G01 X5.0 Y5.0 Z5.0 C60.0 B45.0 F500\nN6 G49\nN7 M30\n";
    let type2 = "N1 G00 G90 B0 C0\nN2 G55\nN3 G43.5 H01\nN4 G00 X200.0 Y150.0 Z20.0\n\
                 N5 G01 X5.0 Y5.0 Z5.0 I1.0 J1.732 K2.0 F500\nN6 G49\nN7 M30\n";
    let m = preset("head-bc");
    let (a, b) = (end_of(&ends(m.clone(), Dialect::Fanuc, type1), 5), end_of(&ends(m, Dialect::Fanuc, type2), 5));
    // I1 J1.732 K2 is (B45, C60) to the printed precision (1.732 for √3: 0.003° on C, a few
    // µm on the pivot 250 mm from the tip).
    for i in 0..5 {
        assert!((a[i] - b[i]).abs() < 1e-2, "axis {i}: {} vs {}", a[i], b[i]);
    }
    assert!((b[3] - 45.0).abs() < 1e-2 && (b[4] - 60.0).abs() < 1e-2, "{b:?}");
}

#[test]
fn tv22_tv23_table_type1_table_and_workpiece_coordinates() {
    // WKP = 0: X10 Y20 Z30 in the table system is W (7.574, 47.247, 83.052) at A60 B45.
    let table = "N1 G00 G90 A0 B0\nN2 G55\nN3 G43.4 H01\nN4 G00 X20.0 Y100.0 Z0\n\
                 N5 G01 X10.0 Y20.0 Z30.0 A60.0 B45.0 F500\nN6 G49\nN7 M30\n";
    let (tip, state) = tip_at_end(&table_ab(), table, 5);
    assert!(close(tip, Vec3::new(7.5736, 47.2474, 83.0518), 1e-4), "{tip:?}");
    // WKP = 1: the same end point given in W reaches the same machine state.
    let work = "N1 G00 G90 A0 B0\nN2 G55\nN3 G43.4 H01\nN4 G00 X200.0 Y150.0 Z20.0\n\
                N5 G01 X7.574 Y47.247 Z83.052 A60.0 B45.0 F500\nN6 G49\nN7 M30\n";
    let m = with_coordinates(table_ab(), TcpCoordinates::Workpiece);
    let (tip_w, state_w) = tip_at_end(&m, work, 5);
    assert!(close(tip_w, Vec3::new(7.574, 47.247, 83.052), 1e-9), "{tip_w:?}");
    for i in 0..5 {
        assert!((state[i] - state_w[i]).abs() < 1e-3, "axis {i}: {} vs {}", state[i], state_w[i]);
    }
}

#[test]
fn tv25_to_tv27_mixed_machine_three_ways_to_one_state() {
    let head = "N1 G00 G90 A0 B0\nN2 G55\n";
    let type1 = format!(
        "{head}N3 G43.4 H01\nN4 G00 X200.0 Y150.0 Z20.0\nN5 G01 X5.0 Y5.0 Z5.0 A60.0 B45.0 F500\nN6 G49\nN7 M30\n"
    );
    let (tip, state) = tip_at_end(&mixed_ab(), &type1, 5);
    assert!(close(tip, Vec3::new(5.0, 48.1699, -79.7724), 1e-4), "{tip:?}");
    let wkp = format!("{head}N3 G43.4 H01\nN4 G00 X200.0 Y150.0 Z20.0\nN5 G01 X5.0 Y48.170 Z-79.772 A60.0 B45.0 F500\nN6 G49\nN7 M30\n");
    let (_, state_w) = tip_at_end(&with_coordinates(mixed_ab(), TcpCoordinates::Workpiece), &wkp, 5);
    let type2 = format!(
        "{head}N3 G43.5 H01\nN4 G00 X200.0 Y150.0 Z20.0\nN5 G01 X5.0 Y5.0 Z5.0 I2.0 J1.732 K1.0 F500\nN6 G49\nN7 M30\n"
    );
    let (_, state_2) = tip_at_end(&mixed_ab(), &type2, 5);
    for i in 0..5 {
        assert!((state[i] - state_w[i]).abs() < 2e-3, "WKP axis {i}: {} vs {}", state[i], state_w[i]);
        assert!((state[i] - state_2[i]).abs() < 2e-2, "type 2 axis {i}: {} vs {}", state[i], state_2[i]);
    }
}

/// One block of a random TCP program: a line to a tip point, or an arc in G17 about a centre
/// `(i, j)` from the start, ending at `end_angle` on that circle; with the rotary axes' end
/// angles (type 1) or a tool direction (type 2).
#[derive(Debug, Clone)]
enum Block {
    Line([f64; 3]),
    Arc { i: f64, j: f64, end_angle: f64, ccw: bool },
}

fn block() -> impl Strategy<Value = Block> {
    prop_oneof![
        3 => prop::array::uniform3(-60.0..60.0f64).prop_map(Block::Line),
        1 => (-30.0..30.0f64, -30.0..30.0f64, -180.0..180.0f64, any::<bool>())
            .prop_filter("a real circle", |(i, j, _, _)| i.hypot(*j) > 2.0)
            .prop_map(|(i, j, end_angle, ccw)| Block::Arc { i, j, end_angle, ccw }),
    ]
}

/// Rotary end angles well inside the preset's ranges: tilting axis, then the other.
fn angles() -> impl Strategy<Value = (f64, f64)> {
    (-25.0..25.0f64, -170.0..170.0f64)
}

/// The preset's tilting axis letter (with a range) and its other rotary axis.
fn rotary_letters(m: &MachineConfig) -> (char, char) {
    let tilt = m.rotary.iter().find(|l| l.range.is_some()).unwrap().axis;
    let other = m.rotary.iter().find(|l| l.range.is_none()).unwrap().axis;
    (tilt, other)
}

fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// A type 1 program and, per motion line, the tip path it asks for: a segment, or a circle
/// (centre, radius) at a height.
fn type1_program(m: &MachineConfig, blocks: &[(Block, (f64, f64))], feed: f64) -> (String, Vec<(u32, Path)>) {
    let (tilt, other) = rotary_letters(m);
    let mut src = format!("G90 G17 G00 {tilt}0 {other}0\nG43.4 H1\nX0 Y0 Z50.\nG01 F{feed:.3}\n");
    let mut at = [0.0, 0.0, 50.0];
    let mut paths = Vec::new();
    for (k, (b, (t, o))) in blocks.iter().enumerate() {
        let line = 5 + k as u32;
        let (t, o) = (mm(*t), mm(*o));
        match b {
            Block::Line(p) => {
                let p = p.map(mm);
                src += &format!("G01 X{:.3} Y{:.3} Z{:.3} {tilt}{t:.3} {other}{o:.3}\n", p[0], p[1], p[2]);
                paths.push((line, Path::Line(at, p)));
                at = p;
            }
            Block::Arc { i, j, end_angle, ccw } => {
                let (i, j) = (mm(*i), mm(*j));
                let c = [at[0] + i, at[1] + j];
                let r = i.hypot(j);
                let (s, co) = end_angle.to_radians().sin_cos();
                let e = [mm(c[0] + r * co), mm(c[1] + r * s)];
                let g = if *ccw { 3 } else { 2 };
                src += &format!("G{g} X{:.3} Y{:.3} I{i:.3} J{j:.3} {tilt}{t:.3} {other}{o:.3}\nG01\n", e[0], e[1]);
                paths.push((line, Path::Circle([c[0], c[1], at[2]], r)));
                at = [e[0], e[1], at[2]];
            }
        }
    }
    // Each arc block is followed by a G01 line, which shifts the later lines.
    let mut shift = 0;
    for (line, p) in &mut paths {
        *line += shift;
        if matches!(p, Path::Circle(..)) {
            shift += 1;
        }
    }
    src += "G49\nM30\n";
    (src, paths)
}

#[derive(Debug, Clone, Copy)]
enum Path {
    Line([f64; 3], [f64; 3]),
    Circle([f64; 3], f64),
}

impl Path {
    fn distance(&self, p: Vec3) -> f64 {
        match *self {
            Path::Line(a, b) => {
                let (a, b) = (Vec3::from(a), Vec3::from(b));
                let d = b - a;
                if d.norm() < 1e-12 {
                    return (p - a).norm();
                }
                let u = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                (p - (a + d * u)).norm()
            }
            Path::Circle(c, r) => ((p.x - c[0]).hypot(p.y - c[1]) - r).abs().max((p.z - c[2]).abs()),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// TCP-04/06 on every kind of machine: at every 1 ms sample the tool tip is on the
    /// programmed line or arc relative to the table within 1 µm while the rotary axes turn,
    /// and every axis keeps within its speed, acceleration and jerk inside each block.
    #[test]
    fn type1_tip_stays_on_the_programmed_path(
        preset_index in 0..4usize,
        blocks in prop::collection::vec((block(), angles()), 1..5),
        feed in 300.0..6000.0f64,
    ) {
        let name = ["head-bc", "table-ac", "table-bc", "mixed-bc"][preset_index];
        let m = preset(name);
        let kin = Kinematics::new(&m).unwrap();
        let (src, paths) = type1_program(&m, &blocks, mm(feed));
        let (r, samples) = run_on(m, Dialect::Fanuc, &src);
        prop_assume!(r.completed() || !r.alarms[0].code.starts_with("OT"));
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        for (line, path) in &paths {
            let of_line: Vec<&Sample> = samples.iter().filter(|s| s.line == *line).collect();
            prop_assert!(!of_line.is_empty(), "no sample of line {line}\n{src}");
            for s in of_line {
                let tip = kin.forward(&s.machine, 100.0).tip;
                let d = path.distance(tip);
                prop_assert!(d < 1e-3, "line {line}: tip {tip:?} is {d} mm off {path:?}\n{src}");
            }
        }
        common::check_limits(&samples, name, false)?;
    }
}

/// Samples of `line`.
fn of_line(samples: &[Sample], line: u32) -> Vec<Sample> {
    let of_line: Vec<Sample> = samples.iter().filter(|s| s.line == line).copied().collect();
    assert!(!of_line.is_empty(), "no sample of line {line}: nothing to check");
    of_line
}

#[test]
fn tv51_tv52_helical_feed_under_tcp_follows_htg() {
    // R10 over 90° (arc 15.708) with 5 mm of Z at F1000: HTG = 0 → the arc at 1000, the whole
    // path at 1000·16.4845/15.708 = 1049.4; HTG = 1 → the whole path at 1000 (arc 952.89).
    let src = "G90 G17 G00 B0 C0\nG43.4 H1\nX10. Y0 Z0\nG03 X0 Y10. Z5. R10. F1000.\nG01\nG49\nM30\n";
    for (htg, want) in [(false, 1000.0 * 16.4845 / 15.708), (true, 1000.0)] {
        let mut m = preset("head-bc");
        m.motion.helical_feed_on_path = htg;
        let (r, samples) = run_on(m, Dialect::Fanuc, src);
        assert!(r.completed(), "{:?}", r.alarms);
        let top = of_line(&samples, 4).iter().map(|s| s.feed).fold(0.0, f64::max);
        assert!((top - want).abs() < 0.5, "HTG {htg}: {top} mm/min, want {want}");
    }
}

#[test]
fn tv53_tv54_inverse_time_under_tcp() {
    // TV-53: 50 mm at F2 (1/min) takes 0.5 min: 100 mm/min. TV-54: 90° of B alone at F4 takes
    // 0.25 min (360°/min). The axes start and stop within each block's time.
    let src = "G90 G00 B0 C0\nG43.4 H1\nX0 Y0 Z0\nG93 G01 X50. F2.\nB90. F4.\nG94 F1000.\nG49\nM30\n";
    let (r, samples) = run_on(preset("head-bc"), Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let (a, b) = (of_line(&samples, 4), of_line(&samples, 5));
    let top = a.iter().map(|s| s.feed).fold(0.0, f64::max);
    assert!((top - 100.0).abs() < 1e-6, "{top}");
    let secs = |v: &[Sample]| v.last().unwrap().t - v[0].t;
    assert!((secs(&a) - 30.0).abs() < 0.2, "{}", secs(&a));
    assert!((secs(&b) - 15.0).abs() < 0.2, "{}", secs(&b));
}

#[test]
fn tv55_tv56_rotary_only_moves_run_at_f_only_with_rfc() {
    // The tip stays on the C axis of table-ac while C turns 90°: at F3000 (3000°/min) with
    // RFC = 1, as fast as C goes (10800°/min rapid) otherwise.
    let src = "G90 G00 A0 C0\nG43.4 H1\nX0 Y0 Z0\nG01 C90. F3000.\nG49\nM30\n";
    for (rfc, want) in [(true, 3000.0), (false, 10_800.0)] {
        let mut m = preset("table-ac");
        m.five_axis.rotary_feed = rfc;
        let (r, samples) = run_on(m, Dialect::Fanuc, src);
        assert!(r.completed(), "{:?}", r.alarms);
        let c = of_line(&samples, 4);
        let top =
            c.windows(2).map(|w| (w[1].machine[4] - w[0].machine[4]) / (w[1].t - w[0].t) * 60.0).fold(0.0, f64::max);
        assert!((top - want).abs() < 1.0, "RFC {rfc}: {top}°/min, want {want}");
    }
}

#[test]
fn tv43_tv44_tool_posture_control_turns_on_the_great_circle() {
    // v from (0,0,1) (B0, C30) to (1,0,0) (B90, C0) over a 100 mm line: at 50 mm the tool is
    // (0.70711, 0, 0.70711), at 25 mm (sin 22.5°, 0, cos 22.5°). Conventional control (P0)
    // turns C too and leaves that plane.
    let src = |p: u8| format!("G90 G00 B0 C30.\nG43.4 H1 P{p}\nX0 Y0 Z0\nG01 X100. B90. C0 F600.\nG49\nM30\n");
    let m = preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    let tool_at = |samples: &[Sample], x: f64| {
        let s = of_line(samples, 4)
            .into_iter()
            .min_by(|a, b| {
                let d = |s: &Sample| (kin.forward(&s.machine, 100.0).tip.x - x).abs();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        kin.forward(&s.machine, 100.0).tool
    };
    let (r, posture) = run_on(m.clone(), Dialect::Fanuc, &src(1));
    assert!(r.completed(), "{:?}", r.alarms);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert!(close(tool_at(&posture, 50.0), Vec3::new(s, 0.0, s), 1e-3), "{:?}", tool_at(&posture, 50.0));
    let q = 22.5f64.to_radians();
    assert!(close(tool_at(&posture, 25.0), Vec3::new(q.sin(), 0.0, q.cos()), 1e-3));
    let (_, conventional) = run_on(m, Dialect::Fanuc, &src(0));
    assert!(tool_at(&conventional, 50.0).y.abs() > 0.05, "P0 leaves the XZ plane");
}

/// Tool posture control from or to the singular posture: the free axis has no angle of its own
/// there, yet the tool leaves (reaches) the posture on its great circle only with that axis at
/// one angle. The axes stepped to it within one millisecond (C by 30° in TV-43, 1.8·10⁶ °/min),
/// or — beyond a 30° step — the block ran with conventional control. The free axis now turns
/// there with the tip standing (which does not turn the tool), then the tool follows the
/// great circle: every sample on it, every axis within its limits, no notice.
#[test]
fn posture_control_at_the_singular_posture_turns_the_free_axis_with_the_tip_standing() {
    let nutating: MachineConfig =
        serde_json::from_str(include_str!("../../../machines/nutating-head-b45.json")).unwrap();
    let cases = [
        // Leaving it: C turns 90° → 0 first (the great circle is the XZ meridian).
        (preset("head-bc"), "G90 G00 B0 C90.\nG43.4 H1 P1\nX0 Y0 Z0\nG01 X100. B90. C0 F600.\nG49\nM30\n", Turn::By(90.0)),
        // Within 0.001° of it (a program's angles on a machine whose singular angle is not a
        // round number): the same turn, which turns the tool by at most twice that.
        (preset("head-bc"), "G90 G00 B0.0005 C90.\nG43.4 H1 P1\nX0 Y0 Z0\nG01 X100. B90. C0 F600.\nG49\nM30\n", Turn::By(90.0)),
        // Reaching it: C turns 0 → 30° last.
        (preset("head-bc"), "G90 G00 B90. C0\nG43.4 H1 P1\nX0 Y0 Z0\nG01 X100. B0 C30. F600.\nG49\nM30\n", Turn::By(30.0)),
        // A nutating head (B about a line 45° off Z): B90 C0 points the tool at (√½, ½, ½),
        // azimuth atan(½/√½) = 35.26°, while a little B at C0 tilts it toward +X: C turns
        // 35.26° first, then back to 0 along the way.
        (
            nutating,
            "G90 G00 X0 Y0 Z200. B0 C0\nG43.4 H1 P1\nG00 X0 Y0 Z150.\nG01 X20. B90. C0 F2000.\nG49\nM30\n",
            Turn::By(0.5f64.sqrt().atan().to_degrees()),
        ),
        // A head whose B zero is 3.998° off (found by random machines): B−3.998 is 1.3·10⁻⁴°
        // from the posture, and the tool leans off it the other way than the way leaves. A
        // (the free axis, ±60°) turns until the lean lies in the way's plane — to the angle
        // the block ends at, since A keeps it along this head's meridians — and B then passes
        // the posture's line; turning it until the tool leaned toward the way took A 180°
        // round, beyond its range.
        (zero_offset_head(), "G90 G00 A-55. B-3.998\nG43.5 H1 P1\nX0 Y0 Z50.\nG01 X0 Y0 Z0 I-0.129855578 J0.138293346 K0.981841372 F1000.\nG49\nM30\n", Turn::ToEnd),
        // A head whose B is 2° off square to A (found by random machines): A still turns along
        // the way, so the angle the way leaves the posture at is a limit. Taken at the way's
        // last point followed, 2·10⁻⁴ of the block short of the posture, it was 10⁻⁶° off: A
        // stepped that in the way's first millisecond, X's jerk 2 % over its limit.
        (inclined_head(), "G90 G00 A-55. B0\nG43.5 H1 P1\nX0 Y0 Z50.\nG01 X0 Y0 Z0 I0.740943015 J-0.549457625 K-0.386134389 F1000.\nG49\nM30\n", Turn::ToWay),
        // Both axes inclined and off their lines, the start 2.6·10⁻⁴° off the posture (from
        // random machines): within 10⁻⁸ rad of the posture the inverse's free axis held still,
        // then stepped 10⁻⁷°; Z's jerk 0.5 % over its limit where the way began.
        (skew_head(), "G90 G00 A-125.569 B-2.482\nG43.5 H1 P1\nX0 Y0 Z50.\nG01 X0 Y0 Z0 I0.099663484 J0.967877712 K-0.230824447 F1000.\nG49\nM30\n", Turn::ToWay),
    ];
    for (m, src, turn) in cases {
        let (kin, samples, q0, q1) = posture_run(&m, src);
        let line = 4;
        let (a, b) = (kin.forward(&q0, 100.0).tip, kin.forward(&q1, 100.0).tip);
        let (v0, v1) = (kin.forward(&q0, 0.0).tool, kin.forward(&q1, 0.0).tool);
        let angle = v0.dot(&v1).clamp(-1.0, 1.0).acos();
        let block = of_line(&samples, line);
        let mut worst = 0.0f64;
        for s in &block {
            let pose = kin.forward(&s.machine, 100.0);
            let u = ((pose.tip - a).norm() / (b - a).norm()).min(1.0);
            let want = (v0 * ((1.0 - u) * angle).sin() + v1 * (u * angle).sin()) / angle.sin();
            worst = worst.max((pose.tool - want).norm());
        }
        let off = kin.singularity(&q0).map_or(0.0, |s| s.angle.to_radians());
        assert!(worst < 1e-6 + 2.0 * off, "the tool {worst} off the great circle\n{src}");
        // The turn and the way are two motion segments, each from rest to rest: where they meet,
        // a third difference spans the turn's last jerk and the way's first, a mean of the two
        // where the axes do not step.
        common::check_limits_of(&samples, &m, false).unwrap_or_else(|e| panic!("{e}\n{src}"));
        // The free axis turns with the tip standing at the block's end it turns at: C where
        // the tip first (last) moves is the start's (end's) turned by `turn`, within what the
        // way turns it in its first (last) millisecond from rest.
        let free = kin.singularity(&q0).unwrap().axis;
        let c = m.axes.iter().position(|x| x.name == free).unwrap();
        // (A rollover axis's positions are taken within a turn.)
        let apart = |a: f64, b: f64| ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs();
        let turn = match turn {
            Turn::By(turn) => turn,
            Turn::ToEnd => apart(q1[c], q0[c]),
            Turn::ToWay => {
                // The way followed back from its end, each point's inverse nearest the last, to
                // 10⁻⁴ of it off the posture (where the inverse keeps its digits; the way turns
                // the free axis by 10⁻⁴° there).
                // From the posture itself (the start is within 0.001° of it).
                let line = kin.joints().into_iter().find(|j| j.name == free).unwrap().direction;
                let p = line * line.dot(&v0).signum();
                let angle = p.dot(&v1).clamp(-1.0, 1.0).acos();
                let mut q = q1;
                for k in (1..=10_000).rev() {
                    let u = k as f64 * 1e-4;
                    let v = (p * ((1.0 - u) * angle).sin() + v1 * (u * angle).sin()) / angle.sin();
                    q = kin.angles_near(v, &q).unwrap();
                }
                apart(q[c], q0[c])
            }
        };
        let moving: Vec<&Sample> = block
            .iter()
            .filter(|s| {
                let tip = kin.forward(&s.machine, 100.0).tip;
                (tip - a).norm() > 1e-9 && (tip - b).norm() > 1e-9
            })
            .collect();
        // The programmed point is where the tip is, while the free axis turns and after (these
        // heads carry no table: the programming system is the workpiece system).
        for s in &block {
            let off = Vec3::from(s.programmed) - Vec3::from(s.tip);
            assert!(off.norm() < 1e-9, "the programmed point is {off:?} off the tip at t={}\n{src}", s.t);
        }
        let (first, last) = (moving[0].machine[c], moving[moving.len() - 1].machine[c]);
        let turned = apart(first, q0[c]) + apart(q1[c], last);
        assert!((turned - turn).abs() < 1e-3, "C turned {turned}° with the tip standing, not {turn}\n{src}");
    }
}

/// Tool posture control between two ends within 0.001° of the singular posture: the directions
/// count as equal (TCP-27), the rotary axes turn in proportion to the tip's travel, no notice.
/// Followed as a great circle, the way reached the end's free axis only by a step — 90° of C
/// on head-bc (then a conventional fallback with a notice), 3·10⁻⁵° of A on a head whose B is
/// 7.6° off square to the tool's line (found by random machines; X at twice its jerk).
#[test]
fn posture_control_between_two_ends_at_the_singular_posture_turns_the_axes_in_proportion() {
    let head = ab_head(
        "inclined-b",
        r#"{"axis": "A", "side": "head", "direction": [0.0, 1.0, 0.0], "hand": "left", "point": [0.0, 0.0, 160.6], "range": [-60.0, 60.0]},
           {"axis": "B", "side": "head", "direction": [0.9913, 0.1317, 0.0], "hand": "left", "point": [0.0, 0.0, 0.0],
            "zero_offset": -3.7496, "range": [-60.0, 60.0]}"#,
        [0.0, 1.0, 0.0],
    );
    let cases = [
        (preset("head-bc"), "G90 G00 B0.0005 C90.\nG43.4 H1 P1\nX0 Y0 Z0\nG01 X100. B0 C0 F600.\nG49\nM30\n"),
        (head, "G90 G00 A-55. B3.75\nG43.5 H1 P1\nX0 Y0 Z50.\nG01 X0 Y0 Z0 I0 J1. K0 F1000.\nG49\nM30\n"),
    ];
    for (m, src) in cases {
        let (kin, samples, q0, q1) = posture_run(&m, src);
        let line = 4;
        for q in [&q0, &q1] {
            assert!(kin.singularity(q).unwrap().angle < 1e-3, "{q:?} is not at the singular posture\n{src}");
        }
        let (a, b) = (kin.forward(&q0, 100.0).tip, kin.forward(&q1, 100.0).tip);
        let mut worst = 0.0f64;
        for s in &of_line(&samples, line) {
            let u = ((kin.forward(&s.machine, 100.0).tip - a).norm() / (b - a).norm()).min(1.0);
            for j in kin.joints() {
                let i = j.index.unwrap();
                worst = worst.max((s.machine[i] - (q0[i] + (q1[i] - q0[i]) * u)).abs());
            }
        }
        assert!(worst < 1e-6, "the rotary axes {worst}° off proportional\n{src}");
        common::check_limits_of(&samples, &m, false).unwrap_or_else(|e| panic!("{e}\n{src}"));
    }
}

/// Runs `src`, whose line 4 is a block of tool posture control, on `m`: it completes without a
/// notice. The kinematics, every sample, and the axes where line 4 starts and ends.
fn posture_run(m: &MachineConfig, src: &str) -> (Kinematics, Vec<Sample>, Pos, Pos) {
    let (r, samples) = run_on(m.clone(), Dialect::Fanuc, src);
    assert!(r.completed() && r.notices.is_empty(), "{:?} {:?}\n{src}", r.alarms, r.notices);
    let e = ends(m.clone(), Dialect::Fanuc, src);
    (Kinematics::new(m).unwrap(), samples, end_of(&e, 3), end_of(&e, 4))
}

/// How far the free axis turns with the tip standing (`posture_control_at_the_singular_posture_…`).
enum Turn {
    By(f64),
    /// To the angle the block ends at.
    ToEnd,
    /// To the angle the way has just off the posture.
    ToWay,
}

/// A head-head machine: A about Z carries B about a line 2° off X (from random machines), both
/// lines off the tool's, the tool along Z.
fn inclined_head() -> MachineConfig {
    serde_json::from_str(
        r#"{"name": "inclined-head", "axes": [
            {"name": "X", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
            {"name": "Y", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
            {"name": "Z", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
            {"name": "B", "kind": "rotary", "rapid": 3600.0, "accel": 500.0, "jerk": 56000.0, "stroke": [-118.0, 60.0]},
            {"name": "A", "kind": "rotary", "rapid": 3600.0, "accel": 500.0, "jerk": 10000.0, "stroke": [-60.0, 78.0]}],
          "rotary": [
            {"axis": "A", "side": "head", "direction": [0.0, 0.0, -1.0], "hand": "right", "point": [46.7, -10.2, 0.0], "range": [-60.0, 78.0]},
            {"axis": "B", "side": "head", "direction": [0.9993, 0.0196, -0.0311], "hand": "left", "point": [0.0, 0.0, 0.0], "range": [-118.0, 60.0]}],
          "tool_axis": [0.0, 0.0, 1.0], "nose": [-30.7, 2.1, 0.0]}"#,
    )
    .unwrap()
}

/// A head-head machine: A about Y carries B about a line 12° off −Z, each off its line and
/// off zero (from random machines), the tool along Y.
fn skew_head() -> MachineConfig {
    serde_json::from_str(
        r#"{"name": "skew-head", "axes": [
            {"name": "X", "kind": "linear", "rapid": 16955.0, "accel": 3371.0, "jerk": 28813.0},
            {"name": "Y", "kind": "linear", "rapid": 16955.0, "accel": 3371.0, "jerk": 28813.0},
            {"name": "Z", "kind": "linear", "rapid": 16955.0, "accel": 3371.0, "jerk": 28813.0},
            {"name": "A", "kind": "rotary", "rapid": 11925.0, "accel": 806.0, "jerk": 43556.0, "rollover": true},
            {"name": "B", "kind": "rotary", "rapid": 3600.0, "accel": 500.0, "jerk": 10000.0, "rollover": true}],
          "rotary": [
            {"axis": "A", "side": "head", "direction": [0.0, 1.0, 0.0], "hand": "right", "point": [33.68, 0.0, 154.55], "zero_offset": -3.806},
            {"axis": "B", "side": "head", "direction": [0.0836, 0.1949, -0.9773], "hand": "right", "point": [36.42, 0.0, 0.0], "zero_offset": 2.482265}],
          "tool_axis": [0.0, 1.0, 0.0], "nose": [19.37, 4.51, -35.04]}"#,
    )
    .unwrap()
}

/// A head-head machine: A about Z carries B about X (left-handed both, ±60°), B's zero 3.998°
/// off, the tool along Z.
fn zero_offset_head() -> MachineConfig {
    ab_head(
        "zero-offset-head",
        r#"{"axis": "A", "side": "head", "direction": [0.0, 0.0, 1.0], "hand": "left", "point": [0.0, 0.0, 0.0], "range": [-60.0, 60.0]},
           {"axis": "B", "side": "head", "direction": [1.0, 0.0, 0.0], "hand": "left", "point": [0.0, 0.0, 0.0],
            "zero_offset": 3.9978745311791073, "range": [-60.0, 60.0]}"#,
        [0.0, 0.0, 1.0],
    )
}

/// A head-head machine of A and B (±60°) with the usual limits: its rotary links (JSON objects)
/// and tool axis.
fn ab_head(name: &str, rotary: &str, tool_axis: [f64; 3]) -> MachineConfig {
    let axes = r#"
        {"name": "X", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
        {"name": "Y", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
        {"name": "Z", "kind": "linear", "rapid": 10000.0, "accel": 1000.0, "jerk": 20000.0},
        {"name": "A", "kind": "rotary", "rapid": 3600.0, "accel": 500.0, "jerk": 10000.0, "stroke": [-60.0, 60.0]},
        {"name": "B", "kind": "rotary", "rapid": 3600.0, "accel": 500.0, "jerk": 10000.0, "stroke": [-60.0, 60.0]}"#;
    let [x, y, z] = tool_axis;
    let json =
        format!(r#"{{"name": "{name}", "axes": [{axes}], "rotary": [{rotary}], "tool_axis": [{x:?}, {y:?}, {z:?}]}}"#);
    serde_json::from_str(&json).unwrap()
}

/// A preset without stroke limits, with Π the workpiece system (WKP = 1).
fn workpiece_preset(name: &str) -> MachineConfig {
    let mut m = with_coordinates(preset(name), TcpCoordinates::Workpiece);
    for a in &mut m.axes {
        a.stroke = None;
    }
    m
}

/// Runs `before` (axis moves before TCP), G43.4, `inside` (moves in TCP, may be empty), then
/// the circle of `plane` (G17/G18/G19, a quarter circle of R10 from the point the program
/// moves to) with the extra words `rotary`: the alarm code, or `None` when it runs.
fn workpiece_arc(machine: &str, before: &str, inside: &str, plane: u8, rotary: &str) -> Option<String> {
    let arc = match plane {
        17 => format!("G00 X10. Y0 Z10.\nG17 G02 X0 Y-10. R10. {rotary} F500."),
        18 => format!("G00 X10. Y0 Z10.\nG18 G02 X0 Z0 R10. {rotary} F500."),
        _ => format!("G00 X10. Y0 Z10.\nG19 G02 Y10. Z0 R10. {rotary} F500."),
    };
    let src = format!("G90 G00 X0 Y0 Z100.\n{before}\nG43.4 H1\n{inside}\n{arc}\nG01 F500.\nG49\nM30\n");
    let (r, _) = run_on(workpiece_preset(machine), Dialect::Fanuc, &src);
    r.alarms.first().map(|a| a.code.clone())
}

#[test]
fn tv30_to_tv33_workpiece_arcs_on_a_mixed_machine() {
    let ps = Some("PS5421".to_string());
    // TV-30: C (table) is normal to XY and may turn; B is a tool axis.
    assert_eq!(workpiece_arc("mixed-bc", "G01 C90. F1000.", "", 17, "B10. C20."), None);
    assert_eq!(workpiece_arc("mixed-bc", "", "", 17, "B10. C20."), None);
    // TV-31: in ZX or YZ with C unmoved since G43.4 (also after C moved before G43.4).
    for plane in [18, 19] {
        assert_eq!(workpiece_arc("mixed-bc", "", "", plane, ""), None, "G{plane}");
        assert_eq!(workpiece_arc("mixed-bc", "G01 C90. F1000.", "", plane, ""), None, "G{plane}");
        assert_eq!(workpiece_arc("mixed-bc", "", "", plane, "B10."), None, "tool axis, G{plane}");
        // TV-32: C turns in the circle.
        assert_eq!(workpiece_arc("mixed-bc", "", "", plane, "C20."), ps, "TV-32 G{plane}");
        // TV-33: C turned since G43.4.
        assert_eq!(workpiece_arc("mixed-bc", "", "G01 C10. F1000.", plane, ""), ps, "TV-33 G{plane}");
    }
}

#[test]
fn tv34_to_tv42_workpiece_arcs_on_a_table_machine() {
    // table-ac: A (about X) carries C (about Z).
    let ps = Some("PS5421".to_string());
    let a90 = "G01 A90. F1000.";
    // TV-34: neither axis turns nor has turned since G43.4.
    assert_eq!(workpiece_arc("table-ac", a90, "", 17, ""), None, "TV-34");
    assert_eq!(workpiece_arc("table-ac", "G01 A90. C10. F1000.", "", 17, ""), None, "TV-34 with C10");
    // TV-35: C (along Y at A90) turned since G43.4.
    assert_eq!(workpiece_arc("table-ac", a90, "G01 C10. F1000.", 17, ""), ps, "TV-35");
    // TV-36: C turns in the circle.
    assert_eq!(workpiece_arc("table-ac", a90, "", 17, "C10."), ps, "TV-36");
    // TV-37: A (not normal to XY) turned since G43.4.
    assert_eq!(workpiece_arc("table-ac", "", "G01 A10. F1000.", 17, "C10."), ps, "TV-37");
    // TV-38: A is normal to YZ and may turn. (The rule lets it through; this quarter circle
    // is then on the table, and A's 80° turn carries its start (130 mm from A's line) over 100 mm
    // away, beyond the reach of R10: PS0020. `workpiece_circles_are_on_the_table_while_it_turns` runs one that fits.)
    assert_eq!(workpiece_arc("table-ac", a90, "", 19, "A10."), Some("PS0020".to_string()), "TV-38");
    // TV-39: C (along Z at A0) turned since G43.4, not normal to YZ.
    assert_eq!(workpiece_arc("table-ac", "", "G01 C10. F1000.", 19, ""), ps, "TV-39");
    // TV-40: at A90 C is along Y, normal to ZX; A unmoved.
    assert_eq!(workpiece_arc("table-ac", "G01 A90. C10. F1000.", "", 18, ""), None, "TV-40");
    // TV-41: A turned since G43.4 (with or without C).
    assert_eq!(workpiece_arc("table-ac", "", "G01 A10. F1000.", 18, ""), ps, "TV-41");
    assert_eq!(workpiece_arc("table-ac", "", "G01 A10. C10. F1000.", 18, ""), ps, "TV-41 with C");
    // TV-42: at A0 C is normal to XY and may turn.
    assert_eq!(workpiece_arc("table-ac", "", "", 17, "C10."), None, "TV-42");
}

#[test]
fn workpiece_arc_rule_is_only_for_wkp_1() {
    // Decision (Q-21): with Π on the table (WKP = 0) the circle is on the table and the table
    // axes may turn in it (TV-32's program runs).
    let src = "G90 G00 X0 Y0 Z100.\nG43.4 H1\nG00 X10. Y0 Z10.\nG18 G02 X0 Z0 R10. C20. F500.\nG01\nG49\nM30\n";
    let mut m = preset("mixed-bc");
    for a in &mut m.axes {
        a.stroke = None;
    }
    let (r, _) = run_on(m, Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
}

/// Runs a WKP = 1 circle (line 4 of `src`, line 5 the G49 block after it) and checks it is the
/// circle about `center` (table frame) of radius `radius` at every sample, ends with the tip
/// at the programmed point `end` (workpiece system = machine coordinates here), and no linear
/// axis steps more than 0.5 mm in a 1 ms sample (the axes ran 19–25 mm in one when the circle
/// missed its end point).
fn check_workpiece_circle(machine: &str, src: &str, center: Vec3, radius: f64, end: Vec3) {
    let m = workpiece_preset(machine);
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m.clone(), Dialect::Fanuc, src);
    assert!(r.completed(), "{src}: {:?}", r.alarms);
    for s in of_line(&samples, 4) {
        let off = (kin.forward(&s.machine, 100.0).tip - center).norm() - radius;
        assert!(off.abs() < 2e-3, "{src}: the tip {off} mm off the circle on the table at t = {}", s.t);
    }
    let (tip, _) = tip_at_end(&m, src, 4);
    assert!(close(tip, end, 1e-6), "{src}: the circle ends at {tip:?}, not at {end:?}");
    let around: Vec<&Sample> = samples.iter().filter(|s| s.line == 4 || s.line == 5).collect();
    for w in around.windows(2) {
        let step = (0..3).map(|i| (w[1].machine[i] - w[0].machine[i]).abs()).fold(0.0, f64::max);
        assert!(step < 0.5, "{src}: a linear axis steps {step} mm at t = {}", w[1].t);
    }
}

#[test]
fn workpiece_circles_are_on_the_table_while_it_turns() {
    // §2.3.7/§2.3.8 (TV-30's program with numbers): under WKP = 1 a circle during which the
    // table axis normal to its plane turns is a circle on the table whose start point and I/J/K
    // are read where the table stands at the block's start and its end point where it stands
    // at the end. mixed-bc: C (table, about Z through the origin, left-hand) puts a table point
    // p at Rz(−C)·p. The tip starts at W (50, 0) at C90: the table point (0, 50). The circle on
    // the table about (0, 30), R20, clockwise to (20, 30), which at C20 is at W Rz(−20)·(20, 30)
    // = (29.0545, 21.3504). I/J/K at C90: the centre at W Rz(−90)·(0, 30) = (30, 0), I−20 J0.
    for words in ["R20.", "I-20. J0"] {
        let src = format!(
            "G90 G00 X0 Y0 Z50. B0 C0\nG01 C90. F2000\nG43.4 H01 X50. Y0 Z0\n\
             G17 G02 X29.054 Y21.350 {words} B10. C20. F500\nG01 G49\nM30\n"
        );
        let end = Vec3::new(29.054, 21.35, 0.0);
        check_workpiece_circle("mixed-bc", &src, Vec3::new(0.0, 30.0, 0.0), 20.0, end);
    }
    // table-ac, TV-38's case (A normal to YZ turns): A (about X through (0, 0, −120),
    // left-hand) puts a table point p at Rx(−A) about that line. W (0, 0, 50) at A90 is the
    // table point (0, −170, −120); the circle on the table about (0, −170, −100), R20,
    // counter-clockwise seen from +X to (0, −150, −100), which at A10 is at W
    // (0, −150·cos10° + 20·sin10°, −120 − 150·sin(−10°) + 20·cos10°) = (0, −144.2482, −74.2566).
    let src = "G90 G00 X0 Y0 Z100. A0 C0\nG01 A90. F2000\nG43.4 H01 X0 Y0 Z50.\n\
               G19 G03 Y-144.248 Z-74.257 R20. A10. F500\nG01 G49\nM30\n";
    let end = Vec3::new(0.0, -144.248, -74.257);
    check_workpiece_circle("table-ac", src, Vec3::new(0.0, -170.0, -100.0), 20.0, end);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(32), ..ProptestConfig::default() })]

    /// The executed path ends at the block's end point: random circles on the table of
    /// mixed-bc (G17) while C turns, written as WKP = 1 programs (each end point in the
    /// workpiece system where the table stands then, `Kinematics::table_frame`). Every sample
    /// on the circle, the block's end at its programmed point, no axis step.
    #[test]
    fn workpiece_circles_end_where_programmed_while_the_table_turns(
        c0 in -180.0..180.0f64,
        turn in -90.0..90.0f64,
        center in (-60.0..60.0f64, -60.0..60.0f64),
        radius in 5.0..40.0f64,
        phase in 0.0..360.0f64,
        sweep in 10.0..150.0f64,
        cw in any::<bool>(),
    ) {
        let m = workpiece_preset("mixed-bc");
        let kin = Kinematics::new(&m).unwrap();
        let c = m.axes.iter().position(|a| a.name == 'C').unwrap();
        let on_circle = |deg: f64| {
            let (s, co) = deg.to_radians().sin_cos();
            Vec3::new(center.0 + radius * co, center.1 + radius * s, 0.0)
        };
        let end_phase = if cw { phase - sweep } else { phase + sweep };
        let at = |angle: f64, p: Vec3| {
            let mut pos = [0.0; 8];
            pos[c] = angle;
            kin.table_frame(&pos).to_parent(&p)
        };
        let (c0, c1) = (mm(c0), mm(c0 + turn));
        let (start, end) = (at(c0, on_circle(phase)), at(c1, on_circle(end_phase)));
        let (start, end) = (start.map(mm), end.map(mm));
        let src = format!(
            "G90 G00 X0 Y0 Z50. B0 C{c0:.3}\nG43.4 H01 X{:.3} Y{:.3} Z0\nG01 F2000\n\
             G17 G0{} X{:.3} Y{:.3} R{radius:.3} B10. C{c1:.3} F1000\nG01 G49\nM30\n",
            start.x, start.y, if cw { 2 } else { 3 }, end.x, end.y
        );
        let (r, samples) = run_on(m.clone(), Dialect::Fanuc, &src);
        prop_assert!(r.completed(), "{}: {:?}", src, r.alarms);
        let centre = Vec3::new(center.0, center.1, 0.0);
        for s in of_line(&samples, 4) {
            let off = (kin.forward(&s.machine, 100.0).tip - centre).norm() - radius;
            // (The program's 0.001 mm digits move an R circle's centre by up to about 4 times
            // that at 150°.)
            prop_assert!(off.abs() < 5e-3, "{}: the tip {} mm off the circle at t = {}", src, off, s.t);
        }
        let (tip, _) = tip_at_end(&m, &src, 4);
        prop_assert!(close(tip, end, 1e-6), "{}: ends at {:?}, not {:?}", src, tip, end);
        let around: Vec<&Sample> = samples.iter().filter(|s| s.line == 4 || s.line == 5).collect();
        for w in around.windows(2) {
            let step = (0..3).map(|i| (w[1].machine[i] - w[0].machine[i]).abs()).fold(0.0, f64::max);
            prop_assert!(step < 0.5, "{}: a linear axis steps {} mm at t = {}", src, step, w[1].t);
        }
    }
}

#[test]
fn a_workpiece_circle_that_cannot_be_on_the_table_is_refused() {
    // The audit's numbers: from W (50, 0) at C90 (table (0, 50)) to W (30, −20) at C20 (table
    // Rz(20)·(30, −20) = (35.031, −8.533)): a chord of 68.2 mm on the table, an R20 circle
    // cannot join them (PS0020, as any arc whose radius is short of half its chord); I−20 J0
    // puts the centre at the table point (0, 30), 52 mm from the end.
    for words in ["R20.", "I-20. J0"] {
        let src = format!(
            "G90 G00 X0 Y0 Z50. B0 C0\nG01 C90. F2000\nG43.4 H01 X50. Y0 Z0\n\
             G17 G02 X30. Y-20. {words} B10. C20. F500\nG01 G49\nM30\n"
        );
        let (r, _) = run_on(workpiece_preset("mixed-bc"), Dialect::Fanuc, &src);
        let first = r.alarms.first().map(|a| (a.code.clone(), a.line));
        assert_eq!(first, Some(("PS0020".to_string(), 4)), "{words}");
    }
}

/// A preset without stroke limits.
fn free_preset(name: &str) -> MachineConfig {
    let mut m = preset(name);
    for a in &mut m.axes {
        a.stroke = None;
    }
    m
}

/// The tool direction (table frame) and tip (relative to Π's origin) at every sample of `line`.
fn tools_and_tips(kin: &Kinematics, samples: &[Sample], line: u32) -> Vec<(Vec3, Vec3)> {
    of_line(samples, line)
        .iter()
        .map(|s| {
            let pose = kin.forward(&s.machine, 100.0);
            (pose.tool, pose.tip - kin.nose)
        })
        .collect()
}

#[test]
fn tv46_posture_control_on_an_arc_keeps_the_angle_to_the_centre() {
    // G19 quarter circle about Y0 Z0 from Y20 to Z-20 (clockwise seen from +X): the tool is 60°
    // from the centre direction and square to the travel at both ends (B90 C-30 → B60 C0), so
    // it sweeps a cone: at every point v·c = cos 60° and v·X = sin 60°.
    let src = |p: u8| {
        format!(
            "G90 G00 B90. C-30.\nG43.4 H1 P{p}\nG00 X0 Y20. Z0\nG19 G02 Y0 Z-20. R20. B60. C0 F600.\nG01\nG49\nM30\n"
        )
    };
    let m = free_preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m.clone(), Dialect::Fanuc, &src(1));
    assert!(r.completed(), "{:?}", r.alarms);
    let points = tools_and_tips(&kin, &samples, 4);
    assert!(points.len() > 50);
    let s60 = 3f64.sqrt() / 2.0;
    for (v, tip) in &points {
        let c = Vec3::new(0.0, -tip.y, -tip.z).normalize();
        assert!((v.dot(&c) - 0.5).abs() < 1e-6 && (v.x - s60).abs() < 1e-6, "v {v:?} at {tip:?}");
        let travel = Vec3::x().cross(&c);
        assert!(v.dot(&travel).abs() < 1e-6);
    }
    // Conventional control (P0) moves B and C in proportion and leaves the cone.
    let (_, samples) = run_on(m, Dialect::Fanuc, &src(0));
    let worst = tools_and_tips(&kin, &samples, 4)
        .iter()
        .map(|(v, tip)| (v.dot(&Vec3::new(0.0, -tip.y, -tip.z).normalize()) - 0.5).abs())
        .fold(0.0, f64::max);
    assert!(worst > 0.01, "P0 stays on the cone ({worst})");
}

#[test]
fn tv47_posture_on_an_arc_interpolates_alpha_through_the_normal() {
    // G17 quarter circle about the origin from X20 to Y20: α from 60° to 120°, β = 90°: the
    // tool is cos α_t·c + sin α_t·Z at each point, straight up (σ·n) half-way.
    let src = "G90 G00 B-30. C0\nG43.4 H1 P1\nG00 X20. Y0 Z0\nG17 G03 X0 Y20. R20. B30. C90. F600.\nG01\nG49\nM30\n";
    let m = free_preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m, Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let mut nearest_half = (f64::INFINITY, Vec3::zeros());
    for (v, tip) in tools_and_tips(&kin, &samples, 4) {
        let phi = tip.y.atan2(tip.x);
        let t = phi / std::f64::consts::FRAC_PI_2;
        let alpha = (60.0 + 60.0 * t).to_radians();
        let c = -Vec3::new(tip.x, tip.y, 0.0).normalize();
        let want = c * alpha.cos() + Vec3::z() * alpha.sin();
        assert!(close(v, want, 1e-6), "at t {t}: {v:?}, want {want:?}");
        if (t - 0.5).abs() < nearest_half.0 {
            nearest_half = ((t - 0.5).abs(), v);
        }
    }
    assert!(nearest_half.0 < 0.01 && close(nearest_half.1, Vec3::z(), 0.02), "{nearest_half:?}");
}

#[test]
fn tv48_posture_control_refuses_an_arc_that_turns_the_tool_across_the_plane() {
    // B30 → B100: the tool starts above the XY plane (cos 30° > 0) and would end below it.
    let src = |p: u8| {
        format!(
            "G90 G00 B30. C0\nG43.4 H1 P{p}\nG00 X20. Y0 Z0\nG17 G03 X0 Y20. R20. B100. C90. F600.\nG01\nG49\nM30\n"
        )
    };
    let (r, _) = run_on(free_preset("head-bc"), Dialect::Fanuc, &src(1));
    assert_eq!(r.alarms.first().map(|a| a.code.as_str()), Some("PS0432"), "{:?}", r.alarms);
    assert_eq!(r.alarms[0].message, "UNAVAILABLE POSTURE IN TPC");
    // Conventional control has no such rule, nor has Syntec's tool-vector interpolation (the
    // great circle on arcs too).
    let (r, _) = run_on(free_preset("head-bc"), Dialect::Fanuc, &src(0));
    assert!(r.completed(), "{:?}", r.alarms);
    let mut m = free_preset("head-bc");
    m.five_axis.posture_control = true;
    let syntec = "G90 G00 B30. C0\nG43.4 H1\nG00 X20. Y0 Z0\nG17 G03 X0 Y20. R20. B100. C90. F600.\nG01\nG49\nM30\n";
    let (r, _) = run_on(m, Dialect::Syntec, syntec);
    assert!(r.completed(), "{:?}", r.alarms);
    // In G18 (normal Y) both ends are in the plane (v·Y = 0): allowed, and (decision, Q-7) the
    // tool turns on the great circle in that plane as on a line.
    let g18 = "G90 G00 B30. C0\nG43.4 H1 P1\nG00 X20. Y0 Z0\nG18 G02 X0 Z20. R20. B60. F600.\nG01\nG49\nM30\n";
    let (r, samples) = run_on(free_preset("head-bc"), Dialect::Fanuc, g18);
    assert!(r.completed(), "{:?}", r.alarms);
    let kin = Kinematics::new(&free_preset("head-bc")).unwrap();
    for (v, tip) in tools_and_tips(&kin, &samples, 4) {
        assert!(v.y.abs() < 1e-9, "{v:?} at {tip:?}");
    }
}

#[test]
fn tv45_equal_or_opposite_directions_run_with_conventional_control() {
    // B30 C0 and B-30 C180 are the same direction; B90 C0 (+X) and B90 C180 (−X) opposite.
    // Tool posture control cannot choose a plane: B and C move in proportion, as with P0, so
    // the tool half-way is B0 (straight up) and B90 C90 (+Y).
    let m = free_preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    for (start, end, half) in [("B30. C0", "B-30. C180.", Vec3::z()), ("B90. C0", "B90. C180.", Vec3::y())] {
        for p in [0, 1] {
            let src = format!("G90 G00 {start}\nG43.4 H1 P{p}\nG00 X0 Y0 Z0\nG01 X100. {end} F600.\nG49\nM30\n");
            let (r, samples) = run_on(m.clone(), Dialect::Fanuc, &src);
            assert!(r.completed(), "{:?}", r.alarms);
            let (v, _) = tools_and_tips(&kin, &samples, 4)
                .into_iter()
                .min_by(|a, b| (a.1.x - 50.0).abs().total_cmp(&(b.1.x - 50.0).abs()))
                .unwrap();
            assert!(close(v, half, 2e-3), "{start} → {end} P{p}: {v:?}");
        }
    }
}

/// head-bc with PRI = 1 (the tool-side B judged first, so type 2 keeps B on its side and
/// swings C round the singular posture B0) and the singular-posture settings.
fn singular_head(angle: f64, tolerance: f64, alarm: bool) -> MachineConfig {
    let mut m = free_preset("head-bc");
    m.five_axis.second_axis_first = true;
    (m.five_axis.singular_angle, m.five_axis.singular_tolerance, m.five_axis.singular_alarm) =
        (angle, tolerance, alarm);
    m
}

fn singular_src(ijk: &str) -> String {
    format!("G90 G00 B10. C0\nG43.5 H1 P1\nG00 X0 Y0 Z0\nG01 X10. {ijk} F600.\nG49\nM30\n")
}

/// From B10 C0 along X to the direction `ijk` under G43.5 P1: the alarm or the end (B, C) of
/// the line (interpreted only: a line that swings C round the singular posture runs slowly).
fn singular_line(m: MachineConfig, ijk: &str) -> (Option<String>, (f64, f64)) {
    let mut interp = interpreter_with(&singular_src(ijk), "mill3", Dialect::Fanuc, |c| c.machine = m.into());
    let mut end = (f64::NAN, f64::NAN);
    let r = interp.run(|c| {
        if let fivex_engine::canon::CanonKind::Motion(m) = c.kind {
            if c.line == 4 {
                end = (m.machine[3], m.machine[4]);
            }
        }
    });
    (r.err().map(|a| a.code), end)
}

#[test]
fn tv06_to_tv11_singular_posture_end_point_change_on_a_bc_head() {
    // The target is B10 C175.01 (I-0.1730 J0.0151 K0.9848): the great circle from B10 C0
    // passes 0.44° from +Z. With No.19738 = 10° the block ends instead at B −10 (mirrored about
    // the singular B0, TV-06) and C 0 (its start, TV-07): the deviation |175.01 − 180| = 4.99
    // is within No.19739 = 5 (TV-08). B passes through 0 while C stays.
    let near = "I-0.1730 J0.0151 K0.9848";
    let (alarm, (b, c)) = singular_line(singular_head(10.0, 5.0, false), near);
    assert_eq!(alarm, None);
    assert!((b + 10.0).abs() < 0.01 && c.abs() < 1e-9, "B {b} C {c}");
    let (r, samples) = run_on(singular_head(10.0, 5.0, false), Dialect::Fanuc, &singular_src(near));
    assert!(r.completed(), "{:?}", r.alarms);
    let line = of_line(&samples, 4);
    assert!(line.len() > 100 && line.iter().all(|s| s.machine[4].abs() < 1e-9));
    assert!(line.iter().map(|s| s.machine[3].abs()).fold(f64::INFINITY, f64::min) < 0.1);
    // TV-09: No.19739 = 4 < 4.99 with NPC = 0: the block ends as selected, C swings to 175.
    let (alarm, (b, c)) = singular_line(singular_head(10.0, 4.0, false), near);
    assert_eq!(alarm, None);
    assert!((b - 10.0).abs() < 0.01 && (c - 175.01).abs() < 0.01, "B {b} C {c}");
    // TV-10: the same with NPC = 1: PS5421.
    let (alarm, _) = singular_line(singular_head(10.0, 4.0, true), near);
    assert_eq!(alarm.as_deref(), Some("PS5421"));
    // TV-11: No.19738 = 0: never.
    let (_, (b, c)) = singular_line(singular_head(0.0, 5.0, true), near);
    assert!((b - 10.0).abs() < 0.01 && (c - 175.01).abs() < 0.01, "B {b} C {c}");
    // Farther than No.19738 (0.3° < 0.44°): unchanged.
    let (_, (b, _)) = singular_line(singular_head(0.3, 5.0, true), near);
    assert!((b - 10.0).abs() < 0.01, "B {b}");
}

#[test]
fn posture_control_passing_a_hair_from_the_singular_posture_does_not_step_the_free_axis() {
    // No.19738 = 0 (no end-point change). From B1.277 C52.432 to the direction of B10 with C
    // half a turn and `dc` on: the great circle passes 0.01°, 0.001° and 0.0001° from +Z, where
    // the free axis C turns half round within a hair of the way. The axes following the way
    // (the inverse nearest the proportional angles) change branch there; at the two smaller
    // distances that hid between the looks of `no_jump`, and C stepped 180° in a millisecond
    // with no notice. Every block's axes now keep their limits; a block that does not turn on
    // the great circle says so (FX1002).
    let m = free_preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    for dc in [0.5, 0.05, 0.005] {
        let mut q: Pos = [0.0; fivex_engine::machine::MAX_AXES];
        (q[3], q[4]) = (10.0, 52.432 + 180.0 + dc);
        let v = kin.forward(&q, 0.0).tool;
        let src = format!(
            "G90 G17 G00 B1.277 C52.432\nG43.5 H1 P1\nX0 Y0 Z50.\nG01 X0 Y0 Z0 I{:.9} J{:.9} K{:.9} F1000.\nG49\nM30\n",
            v.x, v.y, v.z
        );
        let (r, samples) = run_on(m.clone(), Dialect::Fanuc, &src);
        assert!(r.completed(), "{:?}\n{src}", r.alarms);
        common::check_limits_of(&samples, &m, false).unwrap_or_else(|e| panic!("{e}\n{src}"));
        let line = of_line(&samples, 4);
        let turned = line.iter().map(|s| s.machine[4]).fold(f64::NEG_INFINITY, f64::max)
            - line.iter().map(|s| s.machine[4]).fold(f64::INFINITY, f64::min);
        let noticed: Vec<&str> = r.notices.iter().filter(|n| n.line == 4).map(|n| n.code.as_str()).collect();
        // Either C turns half round (on the great circle) or the block says it does not.
        assert!(turned > 170.0 || noticed == ["FX1002"], "dc {dc}: C turned {turned}°, notices {noticed:?}\n{src}");
    }
}

#[test]
fn tv12_no_change_when_the_posture_is_exactly_singular() {
    // Through +Z exactly on the way (B10 C0 → B10 C180, both in the XZ plane): unchanged.
    let (alarm, (b, c)) = singular_line(singular_head(10.0, 5.0, true), "I-0.1736 J0 K0.9848");
    assert_eq!(alarm, None);
    assert!((b - 10.0).abs() < 0.01 && (c.abs() - 180.0).abs() < 1e-6, "B {b} C {c}");
    // Ending exactly singular (+Z): B0 with C where it was (TV-05), no change either.
    let (alarm, (b, c)) = singular_line(singular_head(10.0, 5.0, true), "I0 J0 K1.");
    assert_eq!(alarm, None);
    assert!(b.abs() < 1e-9 && c.abs() < 1e-9, "B {b} C {c}");
}

/// The tool tip (Π, zero offsets) and direction at the end of `line` of `src` on `m`.
fn pose_at_end(m: &MachineConfig, src: &str, line: u32) -> (Vec3, Vec3) {
    let end = end_of(&ends(m.clone(), Dialect::Fanuc, src), line);
    let kin = Kinematics::new(m).unwrap();
    let pose = kin.forward(&end, 100.0);
    (pose.tip - kin.nose, pose.tool)
}

#[test]
fn tcp46_type1_mirror_image_mirrors_the_linear_axes_only() {
    // G51.1 X0: the tip goes to X-20; B30 stays B30, so the tool still leans to +X.
    let src = "G90 G00 B0 C0\nG43.4 H1\nG00 X0 Y0 Z0\nG51.1 X0\nG01 X20. Y10. B30. C0 F600.\nG50.1\nG49\nM30\n";
    let m = free_preset("head-bc");
    let (tip, tool) = pose_at_end(&m, src, 5);
    assert!(close(tip, Vec3::new(-20.0, 10.0, 0.0), 1e-9), "{tip:?}");
    assert!(close(tool, Vec3::new(0.5, 0.0, 3f64.sqrt() / 2.0), 1e-9), "{tool:?}");
}

#[test]
fn tcp46_type2_mirror_image_mirrors_ijk_only_with_mir() {
    let src = "G90 G00 B0 C0\nG43.5 H1\nG00 X0 Y0 Z0\nG51.1 X0\nG01 X20. Y10. I1. J0 K1. F600.\nG50.1\nG49\nM30\n";
    let s = std::f64::consts::FRAC_1_SQRT_2;
    for (mir, lean) in [(false, s), (true, -s)] {
        let mut m = free_preset("head-bc");
        m.five_axis.mirror_direction = mir;
        let (tip, tool) = pose_at_end(&m, src, 5);
        assert!(close(tip, Vec3::new(-20.0, 10.0, 0.0), 1e-9), "MIR {mir}: {tip:?}");
        assert!(close(tool, Vec3::new(lean, 0.0, s), 1e-9), "MIR {mir}: {tool:?}");
    }
}

#[test]
fn tv22_det_shows_the_tip_in_the_workpiece_system() {
    // O200 on the §2.4.2 table machine (WKP = 0): at the end of N5 the tip is Π (10, 20, 30);
    // DET = 1 shows it in W, (7.574, 47.247, 83.052). Mid-block too the display is the tip's
    // machine position less the offsets (zero here).
    let src = "N1 G00 G90 A0 B0\nN2 G55\nN3 G43.4 H01\nN4 G00 X20.0 Y100.0 Z0\n\
               N5 G01 X10.0 Y20.0 Z30.0 A60.0 B45.0 F500\nN6 G49\nN7 M30\n";
    for (det, want) in [(false, Vec3::new(10.0, 20.0, 30.0)), (true, Vec3::new(7.5736, 47.2474, 83.0518))] {
        let mut m = table_ab();
        m.five_axis.display_workpiece = det;
        let kin = Kinematics::new(&m).unwrap();
        let (r, samples) = run_on(m, Dialect::Fanuc, src);
        assert!(r.completed(), "{:?}", r.alarms);
        let n5 = of_line(&samples, 5);
        let end = n5.last().unwrap();
        // The last 1 ms sample is within one sample's travel (F500: 8 µm) of the end; DET on
        // and off differ by tens of mm.
        // The display is the trace's `programmed`; its `tip` is the tip in the workpiece
        // system fixed on the table whatever DET says (`trace_tip.rs`).
        assert!(close(Vec3::from(end.programmed), want, 1e-2), "DET {det}: {:?}", end.programmed);
        let system = if det { System::WorkpieceMachineAxes } else { System::Programming };
        assert_eq!(end.programmed_in, system);
        let mid = &n5[n5.len() / 2];
        let pose = kin.forward(&mid.machine, 100.0);
        let shown = if det { pose.tip_machine - kin.nose } else { pose.tip - kin.nose };
        assert!(close(Vec3::from(mid.programmed), shown, 1e-6), "DET {det}: {:?} vs {shown:?}", mid.programmed);
        assert!(close(Vec3::from(mid.tip), pose.tip - kin.nose, 1e-9), "DET {det}: {:?}", mid.tip);
    }
}

#[test]
fn tv22_det_chooses_the_summary_position() {
    // TCP-26, TV-22: the run summary's workpiece position is what the display shows: with
    // DET = 1 the tip in W (7.574, 47.247, 83.052), with DET = 0 in Π (10, 20, 30); the program
    // ends with TCP on so the last point is shown under it.
    let src = "N1 G00 G90 A0 B0\nN2 G55\nN3 G43.4 H01\nN4 G00 X20.0 Y100.0 Z0\n\
               N5 G01 X10.0 Y20.0 Z30.0 A60.0 B45.0 F500\nN7 M30\n";
    for (det, want) in [(false, Vec3::new(10.0, 20.0, 30.0)), (true, Vec3::new(7.5736, 47.2474, 83.0518))] {
        let mut m = table_ab();
        m.five_axis.display_workpiece = det;
        let (r, _) = run_on(m, Dialect::Fanuc, src);
        assert!(r.completed(), "{:?}", r.alarms);
        let shown = Vec3::new(r.workpiece[0], r.workpiece[1], r.workpiece[2]);
        assert!(close(shown, want, 1e-3), "DET {det}: {shown:?}");
        assert_eq!((r.workpiece[3], r.workpiece[4]), (60.0, 45.0), "DET {det}: the rotary axes as programmed");
    }
}

#[test]
fn syntec_rtcp_moves_stay_in_the_rotary_ranges() {
    // syn §1.4 (Pr3009–3012), COR-151/152 (§6.1, §6.2 alarms 151/152): an RTCP move whose
    // master (C) or slave (B) target or swept path leaves its range is refused; FANUC's ranges
    // (No.19741–19744) only choose among type 2 solutions.
    let mut m = free_preset("head-bc");
    // C: "Area 2", 70 → 290 (Pr3009 = 70000, Pr3010 = 290000); B: −110 … 110 (the preset).
    m.rotary[0].range = Some([70.0, 290.0]);
    let run = |dialect, moves: &str| {
        let src = format!("G90 G00 B0 C180.\nG43.4 H1\nG01 X0 Y0 Z0 F1000\n{moves}\nG49\nM30\n");
        let (r, _) = run_on(m.clone(), dialect, &src);
        r.alarms.first().map(|a| (a.code.clone(), a.line))
    };
    assert_eq!(run(Dialect::Syntec, "B100.\nB120."), Some(("COR-152".into(), 5)), "slave target");
    assert_eq!(run(Dialect::Syntec, "C80.\nC60."), Some(("COR-151".into(), 5)), "master target");
    // 80 → 280: both ends are in the area, the rollover axis's shortest way through 0 is not.
    assert_eq!(run(Dialect::Syntec, "C80.\nC280."), Some(("COR-151".into(), 5)), "master path");
    assert_eq!(run(Dialect::Syntec, "C100.\nC260.\nB-100."), None, "100 → 260 through 180 stays in");
    assert_eq!(run(Dialect::Fanuc, "B100.\nB120.\nC80.\nC280."), None, "FANUC: no such alarm");
}

/// head-bc with axes ten times as fast (so that the rotary axes can turn far between two
/// interpolation points) and the CRS settings.
fn fast_head(clamp: bool, cutting: f64) -> MachineConfig {
    let mut m = free_preset("head-bc");
    for a in &mut m.axes {
        a.rapid *= 10.0;
        (a.accel, a.jerk) = (Some(a.max_accel() * 100.0), Some(a.max_jerk() * 10_000.0));
    }
    (m.five_axis.deviation_clamp, m.five_axis.cutting_deviation) = (clamp, cutting);
    m
}

/// Over consecutive 1 ms samples of `line`: the largest distance from the X axis of the tip
/// the axes give half-way when they move straight between the two samples, and the top feed.
fn chord_deviation(m: MachineConfig, src: &str, line: u32) -> (f64, f64) {
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m, Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let s = of_line(&samples, line);
    let worst = s
        .windows(2)
        .map(|w| {
            let middle: Pos = std::array::from_fn(|i| 0.5 * (w[0].machine[i] + w[1].machine[i]));
            let tip = kin.forward(&middle, 100.0).tip - kin.nose;
            tip.y.hypot(tip.z)
        })
        .fold(0.0, f64::max);
    (worst, s.iter().map(|s| s.feed).fold(0.0, f64::max))
}

#[test]
fn tcp25_crs_lowers_the_speed_to_keep_the_chord_deviation() {
    // 20 mm along X while B turns 60° (the tip 250 mm from the pivot) at F10000. Without CRS
    // the axes' straight steps between 1 ms points take the tip µm off the line; CRS with
    // No.19752 = 0 (the least increment, 0.001 mm) slows the block until they stay within it.
    let src = "G90 G00 B0 C0\nG43.4 H1\nG00 X0 Y0 Z0\nG01 X20. B60. F10000.\nG49\nM30\n";
    let (free, top_free) = chord_deviation(fast_head(false, 0.0), src, 4);
    assert!(free > 0.0015, "no clamp: {free} mm at {top_free}");
    let (clamped, top) = chord_deviation(fast_head(true, 0.0), src, 4);
    assert!(clamped <= 0.0011, "CRS: {clamped} mm");
    assert!(top < 0.9 * top_free, "CRS {top} vs {top_free} mm/min");
    // A looser limit (No.19752 = 0.01 mm) or a negative one (no clamp) leaves it alone.
    let (_, loose) = chord_deviation(fast_head(true, 0.01), src, 4);
    assert!((loose - top_free).abs() < 1.0, "{loose} vs {top_free}");
    let (_, off) = chord_deviation(fast_head(true, -1.0), src, 4);
    assert!((off - top_free).abs() < 1e-6);
    // Without rotary motion there is nothing to clamp.
    let line = "G90 G00 B0 C0\nG43.4 H1\nG00 X0 Y0 Z0\nG01 X100. F10000.\nG49\nM30\n";
    let (_, plain) = chord_deviation(fast_head(true, 0.0), line, 4);
    assert!((plain - 10_000.0).abs() < 1e-6, "{plain}");
}

/// The alarm code of `src` on `m` (FANUC), or "ok".
fn outcome(m: MachineConfig, src: &str) -> String {
    let (r, _) = run_on(m, Dialect::Fanuc, src);
    r.alarms.first().map_or("ok".into(), |a| a.code.clone())
}

#[test]
fn tv60_g43_5_refused_in_the_workpiece_system() {
    for name in ["head-bc", "table-ac", "mixed-bc"] {
        assert_eq!(outcome(workpiece_preset(name), "G43.5 H1\nG49\nM30\n"), "PS5459", "{name}");
        assert_eq!(outcome(workpiece_preset(name), "G43.4 H1\nG49\nM30\n"), "ok", "{name}");
        assert_eq!(outcome(free_preset(name), "G43.5 H1\nG49\nM30\n"), "ok", "{name}");
    }
}

#[test]
fn tv61_g43_5_refused_with_a_hypothetical_axis() {
    // head-bc with C fixed at 0 (a hypothetical master): one real rotary axis.
    let mut m = free_preset("head-bc");
    m.rotary[0].fixed = Some(0.0);
    m.axes.retain(|a| a.name != 'C');
    assert_eq!(outcome(m.clone(), "G43.5 H1\nG49\nM30\n"), "PS5459");
    assert_eq!(outcome(m, "G43.4 H1\nG01 X10. B20. F500.\nG49\nM30\n"), "ok");
}

#[test]
fn tv65_tcp_needs_linear_type_rapids() {
    let mut m = free_preset("head-bc");
    m.motion.nonlinear_rapid = true;
    assert_eq!(outcome(m.clone(), "G43.4 H1\nG49\nM30\n"), "PS5420");
    assert_eq!(outcome(m.clone(), "G43.5 H1\nG49\nM30\n"), "PS5420");
    let (r, _) = run_on(m.clone(), Dialect::Syntec, "G43.4 H1\nG49\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
    m.motion.nonlinear_rapid = false;
    assert_eq!(outcome(m, "G43.4 H1\nG49\nM30\n"), "ok");
}

#[test]
fn tv69_cutter_compensation_nested_with_tcp_in_the_workpiece_system() {
    // Both nestings accepted with WKP = 1 on a mixed machine (the tool side offset and TCP in
    // the same system, TV-24); with Π on the table (WKP = 0) the second to start is PS5460.
    for src in ["G41.2 D1\nG43.4 H1\nG49\nG40\nM30\n", "G43.4 H1\nG41.2 D1\nG40\nG49\nM30\n"] {
        assert_eq!(outcome(workpiece_preset("mixed-bc"), src), "ok", "{src}");
        assert_eq!(outcome(free_preset("mixed-bc"), src), "PS5460", "{src}");
    }
}

#[test]
fn tcp25_crs_uses_no_19751_for_rapids() {
    // The CRS test's block as a rapid: No.19751 (rapid_deviation) decides, No.19752 does not.
    let src = "G90 G00 B0 C0\nG43.4 H1\nG00 X0 Y0 Z0\nG00 X20. B60.\nG49\nM30\n";
    let rapid = |limit: f64| {
        let mut m = fast_head(true, -1.0);
        m.five_axis.rapid_deviation = limit;
        chord_deviation(m, src, 4)
    };
    let (free, top_free) = rapid(-1.0);
    let (clamped, top) = rapid(0.0);
    assert!(free > 0.0015 && clamped <= 0.0011, "{free} / {clamped} mm");
    assert!(top < 0.9 * top_free, "{top} vs {top_free}");
}

#[test]
fn wse_24_no_singular_change_while_g54_4_is_on() {
    // TV-06's line with G54.4 P1 on (RCM = 1, a zero error): the end-point change is not made
    // (FANUC WSE-24), the block ends as selected.
    let mut m = singular_head(10.0, 5.0, false);
    m.five_axis.tool_direction_compensation = true;
    let src =
        format!("G54.4 P1\n{}", singular_src("I-0.1730 J0.0151 K0.9848")).replace("G49\nM30", "G49\nG54.4 P0\nM30");
    let mut interp = interpreter_with(&src, "mill3", Dialect::Fanuc, |c| c.machine = m.into());
    let mut end = (f64::NAN, f64::NAN);
    let r = interp.run(|c| {
        if let (fivex_engine::canon::CanonKind::Motion(m), 5) = (c.kind, c.line) {
            end = (m.machine[3], m.machine[4]);
        }
    });
    assert!(r.is_ok(), "{r:?}");
    assert!((end.0 - 10.0).abs() < 0.01 && (end.1 - 175.01).abs() < 0.01, "B {} C {}", end.0, end.1);
}

#[test]
fn syntec_tool_vector_interpolation_takes_the_equivalent_end_pair() {
    // SYN-10, TV-10, TV-35a: with Pr3054 = 1 a block is read as a tool vector, so `B-30. C90.`
    // from B30 C0 (the same end vector as TV-35a's B30 C-90, on the other branch of the
    // inverse) runs on the V1–V2 plane and ends at the equivalent pair B30 C-90 instead of
    // leaving the plane; u = 0.5 is TV-35a's B 22.207654 C −45.
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG43.4 H1\nX0 Y0 Z0\nG01 B-30. C90. F3000.\nG49\nM30\n";
    let mut m = free_preset("head-bc");
    m.five_axis.posture_control = true;
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m, Dialect::Syntec, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let line = of_line(&samples, 4);
    let at = |b: f64, c: f64| kin.forward(&[0.0, 0.0, 0.0, b, c, 0.0, 0.0, 0.0], 0.0).tool;
    let (v1, v2) = (at(30.0, 0.0), at(30.0, -90.0));
    assert!(close(v1, Vec3::new(0.5, 0.0, 0.866025), 1e-6) && close(v2, at(-30.0, 90.0), 1e-12));
    let n = v1.cross(&v2).normalize();
    let mut lowest_b = f64::INFINITY;
    for s in &line {
        let tool = kin.forward(&s.machine, 100.0).tool;
        assert!(tool.dot(&n).abs() < 1e-6, "the tool on the V1–V2 plane: {tool:?} at {:?}", s.machine);
        lowest_b = lowest_b.min(s.machine[3]);
    }
    assert!((lowest_b - 22.207654).abs() < 0.01, "B dips to {lowest_b} (TV-35a u = 0.5)");
    let last = line.last().unwrap().machine;
    // (Its last sample is up to 1 ms before the block's end, which it passes at the junction
    // speed into the G49 block: the rotary axes still turn there, by about 0.001°.)
    assert!((last[3] - 30.0).abs() < 0.01 && (last[4] - 270.0).abs() < 0.01, "ends at B30 C-90: {last:?}");
    // The block's end itself (the G49 block moves X, Y, Z only).
    let end = kin.forward(&r.machine, 100.0).tool;
    assert!(close(end, v2, 1e-9), "{end:?}");
}

#[test]
fn q6_posture_control_on_a_rotary_only_block_turns_on_the_great_circle() {
    // Q-6 (decision): the tip stays, so the distance ratio of M-7 is undefined; the tool turns
    // on the great circle from the start to the end direction (TCP-28's plane, as Syntec's
    // Pr3054 example 1 shows for `G01 C-90.` from B30 C0: B dips and returns), its angle in
    // proportion to the block's progress (the rotary path parameter, fed at F with RFC = 1 as in
    // TCP-20), so the tool's angular speed is Ω·F/90° in the constant-speed part.
    let src = |p: u8| format!("G90 G00 X0 Y0 Z0 B30. C0\nG43.4 H1 P{p}\nX0 Y0 Z0\nG01 C-90. F3000.\nG49\nM30\n");
    let mut m = free_preset("head-bc");
    m.five_axis.rotary_feed = true;
    let kin = Kinematics::new(&m).unwrap();
    let (r, samples) = run_on(m.clone(), Dialect::Fanuc, &src(1));
    assert!(r.completed(), "{:?}", r.alarms);
    let line = of_line(&samples, 4);
    assert!(line.len() > 1000, "{} samples", line.len());
    let v0 = kin.forward(&line[0].machine, 100.0).tool;
    let last = line.last().unwrap().machine;
    let v1 = kin.forward(&last, 100.0).tool;
    // C rolls over (−90 is shown as 270); the last sample is within 1 ms of the end, which the
    // block passes at speed into G49's move: within what an axis turns in 1 ms (180°/s).
    assert!((last[3] - 30.0).abs() < 0.18 && (last[4] - 270.0).abs() < 0.18, "ends at B30 C-90: {last:?}");
    let n = v0.cross(&v1).normalize();
    let omega = v0.dot(&v1).acos().to_degrees();
    let tip0 = kin.forward(&line[0].machine, 100.0).tip;
    let mut lowest_b = f64::INFINITY;
    for s in &line {
        let pose = kin.forward(&s.machine, 100.0);
        assert!((pose.tip - tip0).norm() < 1e-6, "the tip stays: {:?}", pose.tip);
        assert!(pose.tool.dot(&n).abs() < 1e-9, "the tool on the plane of v0, v1: {:?}", pose.tool);
        lowest_b = lowest_b.min(s.machine[3]);
    }
    // Half-way the tool is (v0 + v1)/|v0 + v1|: B = acos(0.9258) = 22.21°.
    let half = (v0 + v1).normalize();
    assert!((lowest_b - half.z.acos().to_degrees()).abs() < 0.01, "B dips to {lowest_b}");
    // The constant-speed middle: Ω/90 · 3000°/min.
    let angle = |s: &Sample| v0.dot(&kin.forward(&s.machine, 100.0).tool).clamp(-1.0, 1.0).acos().to_degrees();
    let mid = line.len() / 2;
    let rate = (angle(&line[mid + 1]) - angle(&line[mid])) / (line[mid + 1].t - line[mid].t) * 60.0;
    assert!((rate - omega / 90.0 * 3000.0).abs() < 1.0, "{rate}°/min of the tool, Ω {omega}");
    // Conventional control (P0) keeps B at 30 and leaves the plane.
    let (_, conventional) = run_on(m.clone(), Dialect::Fanuc, &src(0));
    assert!(of_line(&conventional, 4).iter().all(|s| (s.machine[3] - 30.0).abs() < 1e-9));
    // Syntec's tool-vector interpolation (Pr3054 = 1) does the same on this block.
    let mut syntec = m.clone();
    syntec.five_axis.posture_control = true;
    let (r, samples) = run_on(syntec, Dialect::Syntec, &src(1).replace(" P1", ""));
    assert!(r.completed(), "{:?}", r.alarms);
    let low = of_line(&samples, 4).iter().map(|s| s.machine[3]).fold(f64::INFINITY, f64::min);
    assert!((low - lowest_b).abs() < 1e-6, "Syntec B dips to {low}");
    // G93: the block time is 1/F min also under posture control (TCP-19: the rotary amount).
    let g93 = src(1).replace("G01 C-90. F3000.", "G93 G01 C-90. F4.\nG94 F1000.");
    let (r, samples) = run_on(m, Dialect::Fanuc, &g93);
    assert!(r.completed(), "{:?}", r.alarms);
    let b = of_line(&samples, 4);
    assert!((b.last().unwrap().t - b[0].t - 15.0).abs() < 0.2, "{}", b.last().unwrap().t - b[0].t);
}

/// Syntec: "Disable RTCP mode with G49 before applying G53, G28, G29 or G30 to avoid abnormal
/// motions" (§2.2.2 #4, §2.3.2 #5; no alarm named, syntec Q-34). fivex cannot know that motion,
/// so it refuses G28/G29/G30 under RTCP (decision: COR-100, as FANUC refuses them, PS5421) on
/// head and table machines, in both types, and in the G49 block; after it the return runs,
/// without a step.
#[test]
fn syntec_reference_returns_under_rtcp_are_refused() {
    for preset in ["head-bc", "table-ac"] {
        let m = MachineConfig::preset(preset).unwrap();
        for (start, words) in [("G43.4 H1", " B30."), ("G43.5 H1", " I0 J0 K1.")] {
            let words = if preset == "table-ac" { words.replace("B30.", "A30.") } else { words.to_string() };
            let start_block = format!("G90 G00 X0 Y0 Z100.\nG28 X0 Y0 Z100.\n{start}\nG01 X0 Y0 Z0{words} F1000\n");
            for (block, code) in [("G91 G28 Z0", "G28"), ("G91 G30 Z0", "G30"), ("G29 X0 Y0 Z50.", "G29")] {
                let block = if start == "G43.5 H1" { block.replace("G91 ", "") } else { block.to_string() };
                let src = format!("{start_block}{block}\nG90 G01 X10. Y0 Z0\nG49\nM30\n");
                let (r, _) = run_on(m.clone(), Dialect::Syntec, &src);
                let alarm = r.alarms.first().map(|a| (a.code.as_str(), a.line));
                assert_eq!(alarm, Some(("COR-100", 5)), "{preset} {start} {code}: {:?}", r.alarms);
            }
            // Not in the G49 block either ("G49 before"); after it the return is an ordinary one.
            let src = format!("{start_block}G49 G28 Z50.\nM30\n");
            let (r, _) = run_on(m.clone(), Dialect::Syntec, &src);
            assert_eq!(
                r.alarms.first().map(|a| (a.code.as_str(), a.line)),
                Some(("COR-100", 5)),
                "{preset} {start} G49 G28"
            );
            let src = format!("{start_block}G49\nG91 G28 Z0\nG90 G00 X10. Y0 Z50.\nM30\n");
            let (r, samples) = run_on(m.clone(), Dialect::Syntec, &src);
            assert!(r.completed(), "{preset} {start}: {:?}", r.alarms);
            // The speed bound holds across block ends too: no block starts where the machine is not.
            if let Err(e) = common::check_limits_of(&samples, &m, false) {
                panic!("{preset} {start}: {e}");
            }
        }
    }
}

#[test]
fn after_an_inz_start_block_the_current_point_is_the_tip_in_the_table_system() {
    // §2.3.5 (INZ = 1): the start block moves in the workpiece system, the next blocks in the
    // table system at zero. table-ac at A30 C20: the tip at W (0, 0, 50) is the table point
    // Rz(20)·(Rx(30) about (0, 0, −120))·(0, 0, 50): (0, −170·sin30°, −120 + 170·cos30°)
    // turned by C: (85·sin20°, −85·cos20°, −120 + 170·cos30°) = (29.072, −79.874, 27.224).
    let m = with_coordinates(free_preset("table-ac"), TcpCoordinates::TableAtZero);
    let kin = Kinematics::new(&m).unwrap();
    let here = Vec3::new(
        85.0 * 20f64.to_radians().sin(),
        -85.0 * 20f64.to_radians().cos(),
        170.0 * 30f64.to_radians().cos() - 120.0,
    );
    let start = "G90 G00 X0 Y0 Z100. A0 C0\nG00 A30. C20.\nG43.4 H01 X0 Y0 Z50.\n";
    // G91 X0 does not move the tip; X10. moves it 10 along Π's X; an absolute X30. keeps the
    // omitted Y and Z where the tip is.
    let cases = [
        ("G91 G01 X0 F1000\nX10.\n", [0.0, 10.0]),
        ("G90 G01 X29.072 F1000\nX30.\n", [29.072 - here.x, 30.0 - here.x]),
    ];
    for (moves, dx) in cases {
        let src = format!("{start}{moves}G90 G49\nM30\n");
        let ends = ends(m.clone(), Dialect::Fanuc, &src);
        for (line, dx) in [(4, dx[0]), (5, dx[1])] {
            let tip = kin.forward(&end_of(&ends, line), 100.0).tip;
            let want = here + Vec3::new(dx, 0.0, 0.0);
            assert!(close(tip, want, 1e-3), "{moves:?} line {line}: the tip at {tip:?} in Π, want {want:?}");
        }
    }
}

#[test]
fn g43_5_with_i_j_k_on_a_tool_rotation_machine_turns_the_tool_in_the_start_block() {
    // §2.2.3: a tool rotation machine may give I, J, K in the G43.5 block. head-bc from B0 C0:
    // (1, 0, 1) is B45 C0 or B−45 C180; C (the first axis judged) moves least with C0. The
    // start block ends with the tip at (10, 0, 50) and the tool along (1, 0, 1)/√2, and the
    // next block, without I/J/K, keeps that direction.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG43.5 H01 X10. Y0 Z50. I1. J0 K1.\nG01 X20. F1000\nG49\nM30\n";
    let m = free_preset("head-bc");
    let kin = Kinematics::new(&m).unwrap();
    let ends = ends(m.clone(), Dialect::Fanuc, src);
    let tool = Vec3::new(1.0, 0.0, 1.0).normalize();
    for (line, tip) in [(2, Vec3::new(10.0, 0.0, 50.0)), (3, Vec3::new(20.0, 0.0, 50.0))] {
        let end = end_of(&ends, line);
        let pose = kin.forward(&end, 100.0);
        assert!(close(pose.tip_machine, tip, 1e-6), "line {line}: tip {:?}", pose.tip_machine);
        assert!(close(pose.tool, tool, 1e-9), "line {line}: tool {:?}", pose.tool);
        assert!((end[3] - 45.0).abs() < 1e-9 && end[4].abs() < 1e-9, "line {line}: B{} C{}", end[3], end[4]);
    }
    // Decision: the start block's lean Q with a direction in it is not defined: refused.
    let q = "G90 G00 X0 Y0 Z0 B0 C0\nG43.5 H01 X10. Y0 Z50. I1. J0 K1. Q5.\nG49\nM30\n";
    assert_eq!(common::first_alarm_with(q, "head-bc", |_| {}), Some(("PS5421".to_string(), 2)));
}

/// head-bc with a movement range on C.
fn head_with_c_range(range: [f64; 2]) -> MachineConfig {
    let mut m = preset("head-bc");
    m.rotary.iter_mut().find(|l| l.axis == 'C').unwrap().range = Some(range);
    m
}

#[test]
fn a_rollover_axis_with_a_range_of_0_to_360_does_not_cross_0() {
    // §2.3.19 CAUTION 4: with rollover and a 0–360 range the axis does not take the shortcut
    // across 0°/360°. From C350 (reached from C0 the short way), (B60, C10) or (B−60, C190):
    // C10 is only reached across 360° (or 340° the other way), C190 by 160°: B−60 C190, with C
    // turning down from 350 to 190.
    let m = head_with_c_range([0.0, 360.0]);
    let c = m.axes.iter().find(|a| a.name == 'C').unwrap();
    assert!(c.rollover && c.shortest, "the preset's C rolls over the short way");
    let src = "G90 G00 X0 Y0 Z0 B0 C350.\nG43.5 H01 X0 Y0 Z50.\nG01 X10. I0.852869 J0.150384 K0.5 F2000\nM30\n";
    let (r, samples) = run_on(m.clone(), Dialect::Fanuc, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let shown = |s: &Sample| m.shown(&s.machine);
    let last = shown(samples.last().unwrap());
    assert!((last[3] + 60.0).abs() < 1e-3 && (last[4] - 190.0).abs() < 1e-3, "ends at B{} C{}", last[3], last[4]);
    for s in of_line(&samples, 3) {
        let c = shown(&s)[4];
        assert!((190.0 - 1e-6..=350.0 + 1e-6).contains(&c), "C at {c} at t = {}", s.t);
    }
}

#[test]
fn a_movement_range_with_lower_above_upper_is_refused_at_g43_5() {
    // §2.3.19 CAUTION 1: PS5459 when G43.5 is specified, also when no block needs the angles.
    let m = head_with_c_range([200.0, 100.0]);
    for src in [
        "G90 G00 X0 Y0 Z0 B0 C25.\nG43.5 H01 X0 Y0 Z50.\nG01 X10. F2000\nG49\nM30\n",
        "G90 G00 X0 Y0 Z0 B0 C25.\nG43.5 H01 X0 Y0 Z50.\nG49\nM30\n",
    ] {
        let (r, _) = run_on(m.clone(), Dialect::Fanuc, src);
        let first = r.alarms.first().map(|a| (a.code.clone(), a.line));
        assert_eq!(first, Some(("PS5459".to_string(), 2)), "{src}");
    }
}

#[test]
fn a_circle_whose_tip_stands_while_a_rotary_axis_turns_is_refused() {
    // §2.2.2 CAUTION: a command that does not move the tip relative to the workpiece must be
    // G00/G01, also when it names X/Y (an R circle to its own start point) or G91 X0 Y0.
    for circle in ["G17 G03 X40. Y0 B20. R10. F1000", "G91 G17 G03 X0 Y0 R10. B20. F1000"] {
        let src = format!("G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H01 X40. Y0 Z20.\n{circle}\nG90 G01 G49\nM30\n");
        let (r, _) = run_on(free_preset("head-bc"), Dialect::Fanuc, &src);
        let first = r.alarms.first().map(|a| (a.code.clone(), a.line));
        assert_eq!(first, Some(("PS5421".to_string(), 3)), "{circle}");
    }
}
