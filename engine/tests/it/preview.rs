//! The programmed tool path (`fivex_engine::preview`) the dashboard draws, and the display
//! values the controller reports beside its position (distance to go, spindle, tool length).

use crate::common;

use common::interpreter;
use fivex_engine::controller::{Controller, RunState};
use fivex_engine::interp::Config;
use fivex_engine::kin::Kinematics;
use fivex_engine::machine::MachineConfig;
use fivex_engine::preview::tool_path;
use fivex_engine::Dialect;

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-6)
}

#[test]
fn a_three_axis_path_is_the_programmed_points_and_arcs_are_sampled_on_their_circle() {
    let src = "G90 G17 G00 X10. Y20. Z30.\nG01 X50. F100.\nG02 X70. Y20. R10.\nM30\n";
    let path = tool_path(&mut interpreter(src, "mill3", Dialect::Fanuc), 10_000);
    assert!(path.alarm.is_none() && !path.truncated);
    let nose = MachineConfig::preset("mill3").unwrap().nose;
    let at = |x: f64, y: f64, z: f64| [x + nose[0], y + nose[1], z + nose[2]];
    assert!(close(path.points[1], at(10.0, 20.0, 30.0)), "{:?}", path.points[1]);
    assert!(close(path.points[2], at(50.0, 20.0, 30.0)), "{:?}", path.points[2]);
    assert_eq!((path.lines[1], path.rapid[1], path.lines[2], path.rapid[2]), (1, true, 2, false));
    let arc: Vec<_> = path.points[3..].to_vec();
    assert!(arc.len() >= 31, "a half circle of radius 10 sampled every mm: {}", arc.len());
    for p in &arc {
        let r = ((p[0] - at(60.0, 0.0, 0.0)[0]).powi(2) + (p[1] - at(0.0, 20.0, 0.0)[1]).powi(2)).sqrt();
        assert!((r - 10.0).abs() < 1e-6, "{p:?} is {r} from the centre");
        assert!(p[1] >= at(0.0, 20.0, 0.0)[1] - 1e-9, "G02 from X50 to X70 passes above the centre: {p:?}");
    }
    assert!(close(*arc.last().unwrap(), at(70.0, 20.0, 30.0)));
    assert!(path.lines[3..].iter().all(|&l| l == 3));
}

#[test]
fn a_tcp_line_on_a_table_machine_stays_a_line_on_the_table_while_the_table_turns() {
    // G43.4 on table-ac: the tip moves on a straight line relative to the part while A and C
    // turn, so every sampled point of the move lies on that line in the table frame.
    let src = "G90 G00 X0 Y0 Z100. A0 C0\nG43.4 H1\nG01 X50. Y20. Z10. A30. C45. F500.\nG49\nM30\n";
    let path = tool_path(&mut interpreter(src, "table-ac", Dialect::Fanuc), 10_000);
    assert!(path.alarm.is_none(), "{:?}", path.alarm);
    let moved: Vec<[f64; 3]> = path.points.iter().zip(&path.lines).filter(|(_, &l)| l == 3).map(|(p, _)| *p).collect();
    assert!(moved.len() > 10, "the move is sampled: {}", moved.len());
    let start = path.points[path.lines.iter().position(|&l| l == 3).unwrap() - 1];
    let end = *moved.last().unwrap();
    let d = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    assert!(len > 40.0, "the tip travels: {len}");
    for p in &moved {
        let v = [p[0] - start[0], p[1] - start[1], p[2] - start[2]];
        let cross = [v[1] * d[2] - v[2] * d[1], v[2] * d[0] - v[0] * d[2], v[0] * d[1] - v[1] * d[0]];
        let off = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt() / len;
        assert!(off < 1e-3, "{p:?} is {off} mm off the line");
    }
}

#[test]
fn a_rotary_move_without_tcp_draws_the_curve_the_tip_makes() {
    // Without TCP, turning B on head-bc swings the tip (here the spindle nose: no length offset)
    // round the pivot: the points are not on the chord.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG49\nG01 B60. F1000.\nM30\n";
    let path = tool_path(&mut interpreter(src, "head-bc", Dialect::Fanuc), 10_000);
    let swing: Vec<_> = path.points.iter().zip(&path.lines).filter(|(_, &l)| l == 3).map(|(p, _)| *p).collect();
    assert!(swing.len() >= 60, "{}", swing.len());
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let mid = kin.forward(&[0.0, 0.0, 0.0, 30.0, 0.0], 0.0).tip;
    assert!(swing.iter().any(|p| close(*p, mid.into())), "the tip at B30 is on the path");
}

#[test]
fn the_path_ends_at_an_alarm_and_at_the_point_budget() {
    let path = tool_path(&mut interpreter("G00 X10.\nG01 X20. F100.\nG04 X-1.\nG65 P\n", "mill3", Dialect::Fanuc), 100);
    assert!(path.alarm.is_some(), "{path:?}");
    assert_eq!(path.points.len(), 3);
    let many: String = (1..=50).map(|i| format!("G01 X{i}. F100.\n")).collect();
    let path = tool_path(&mut interpreter(&many, "mill3", Dialect::Fanuc), 10);
    assert!(path.truncated);
    assert_eq!(path.points.len(), 10);
}

/// A 40 mm square cut on the outside with G41 (clockwise), tool radius 5 (D1).
const G41_SQUARE: &str =
    "G21 G17 G40 G90\nG00 X-20. Y-20.\nG41 D1 G01 X0. Y0. F500.\nY40.\nX40.\nY0.\nX0.\nG40 X-20. Y-20.\nM30\n";

#[test]
fn under_cutter_compensation_the_programmed_path_comes_beside_the_tool_centre_path() {
    let path = tool_path(&mut interpreter(G41_SQUARE, "mill3", Dialect::Fanuc), 10_000);
    assert!(path.alarm.is_none() && !path.truncated, "{path:?}");
    let programmed = path.programmed.as_ref().expect("compensation was in force: the programmed path too");
    let nose = MachineConfig::preset("mill3").unwrap().nose;
    let xy = |p: [f64; 3]| [p[0] - nose[0], p[1] - nose[1]];
    // The end of each line's moves on a path.
    let end = |points: &[[f64; 3]], lines: &[u32], line: u32| {
        let i = lines.iter().rposition(|&l| l == line).unwrap_or_else(|| panic!("no point of line {line}"));
        xy(points[i])
    };
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6;
    // Programmed: the square's corners. Tool centre: the outside corners offset by the radius
    // (obtuse-or-right outside corners: the offset lines' intersections).
    for (line, corner, centre) in
        [(4, [0.0, 40.0], [-5.0, 45.0]), (5, [40.0, 40.0], [45.0, 45.0]), (6, [40.0, 0.0], [45.0, -5.0])]
    {
        let p = end(&programmed.points, &programmed.lines, line);
        assert!(near(p, corner), "programmed line {line} ends at {p:?}, not {corner:?}");
        let c = end(&path.points, &path.lines, line);
        assert!(near(c, centre), "the tool centre of line {line} ends at {c:?}, not {centre:?}");
    }
    // Every tool centre point of the edges is on the square's offset lines (5 outside it; its
    // corners farther), every programmed one on the square.
    let outside = |p: [f64; 2]| {
        let (dx, dy) = ((-p[0]).max(p[0] - 40.0).max(0.0), (-p[1]).max(p[1] - 40.0).max(0.0));
        (dx * dx + dy * dy).sqrt()
    };
    for (i, &l) in path.lines.iter().enumerate().filter(|(_, &l)| (4..=7).contains(&l)) {
        let (d, p) = (outside(xy(path.points[i])), xy(path.points[i]));
        let on_offset_line = [p[0] + 5.0, p[0] - 45.0, p[1] + 5.0, p[1] - 45.0].iter().any(|v| v.abs() < 1e-6);
        assert!(l == 7 || (d >= 5.0 - 1e-6 && on_offset_line), "line {l}: tool centre {p:?} is {d} from the square");
    }
    for (i, _) in programmed.lines.iter().enumerate().filter(|(_, &l)| (3..=7).contains(&l)) {
        assert!(outside(xy(programmed.points[i])) < 1e-9, "{:?}", programmed.points[i]);
    }
    // Before compensation the two are the same; both end at the cancel's programmed point.
    assert_eq!((&programmed.points[..2], &programmed.lines[..2]), (&path.points[..2], &path.lines[..2]));
    assert_eq!(programmed.points.last(), path.points.last());
    assert_eq!(programmed.lines.len(), programmed.points.len());
    assert_eq!(programmed.rapid.len(), programmed.points.len());
    // Without compensation there is no second path.
    let plain = tool_path(&mut interpreter("G00 X10.\nG01 Y10. F100.\nM30\n", "mill3", Dialect::Fanuc), 100);
    assert_eq!(plain.programmed, None);
    // The 5-axis tool side offset with the tool vertical (head-bc) is the same square's: the
    // programmed path beside the tool centre's, which runs 5 outside it.
    let five = G41_SQUARE.replace("G41 D1", "G41.2 D1");
    let path5 = tool_path(&mut interpreter(&five, "head-bc", Dialect::Fanuc), 10_000);
    assert!(path5.alarm.is_none() && path5.programmed.is_some(), "{path5:?}");
    let nose5 = MachineConfig::preset("head-bc").unwrap().nose;
    let i = path5.lines.iter().rposition(|&l| l == 5).unwrap();
    let c = [path5.points[i][0] - nose5[0], path5.points[i][1] - nose5[1]];
    assert!(near(c, [45.0, 45.0]), "the tool centre of line 5 ends at {c:?}");
}

#[test]
fn after_a_stage_alarm_the_programmed_path_shows_what_was_read() {
    // A groove narrower than the tool: PS0041 at line 6; the tool centre path stops before it,
    // the programmed one holds the blocks read up to it.
    let src = "G21 G17 G40 G90\nG00 X-10. Y0.\nG41 D1 G01 X0. F1000.\nX20.\nY-2.\nX24.\nY0.\nX40.\nG40 X50.\nM30\n";
    let path = tool_path(&mut interpreter(src, "mill3", Dialect::Fanuc), 10_000);
    let alarm = path.alarm.as_ref().expect("PS0041");
    assert_eq!((alarm.code.as_str(), alarm.line), ("PS0041", 6));
    assert!(path.lines.iter().all(|&l| l < 6), "{:?}", path.lines);
    let programmed = path.programmed.expect("programmed path");
    assert!(programmed.lines.contains(&6), "{:?}", programmed.lines);
}

fn run_until(c: &mut Controller, mut done: impl FnMut(&Controller) -> bool) {
    for _ in 0..100_000 {
        if done(c) {
            return;
        }
        c.tick(0.001);
    }
    panic!("never happened");
}

#[test]
fn the_controller_reports_distance_to_go_spindle_and_tool_length() {
    let mut cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc);
    cfg.max_blocks = 1000;
    let mut c = Controller::new(cfg);
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 80.0;
    c.select_program("G43 H1 Z0\nM03 S1200\nG01 X100. F600.\nM04 S500\nG01 X0\nM05\nM30\n").unwrap();
    c.cycle_start().unwrap();
    // Halfway along X100 at 600 mm/min: 50 mm to go on X, nothing on Y and Z.
    run_until(&mut c, |c| c.point().line == 3 && c.point().work[0] > 50.0);
    let to_go = c.to_go();
    assert!((to_go[0] - (100.0 - c.point().work[0])).abs() < 1e-9, "{to_go:?}");
    assert_eq!((to_go[1], to_go[2]), (0.0, 0.0));
    assert_eq!(c.spindle(), 1200.0);
    assert_eq!(c.tool_length(), 80.0);
    run_until(&mut c, |c| c.point().line == 5);
    assert_eq!(c.spindle(), -500.0);
    run_until(&mut c, |c| c.run_state() == RunState::Idle);
    assert_eq!(c.spindle(), 0.0);
    assert_eq!(c.to_go(), [0.0; fivex_engine::machine::MAX_AXES]);
    assert_eq!(c.tool_length(), 80.0, "the last block's length offset while nothing moves");
    c.reset();
    assert_eq!(c.spindle(), 0.0);
}
