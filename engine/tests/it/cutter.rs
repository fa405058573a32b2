//! Cutter compensation C (`stage::cutter`): tool centre end points worked out by hand
//! (`docs/cutter-compensation.md` gives the rules), through the real interpreter and the
//! pipeline every driver uses, and the run's alarms. Tool offsets 1–99 have radius 5.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::interp::Step;
use fivex_engine::stage::Pipeline;
use fivex_engine::Dialect::{self, Fanuc, Syntec};

/// The end point (X, Y) of every motion that comes out of the stages, with its line; and the
/// alarm the interpreter raised, if any.
fn centre(src: &str, dialect: Dialect) -> (Vec<(u32, [f64; 2])>, Option<(String, u32)>) {
    let (ends, alarm) = centre_axes(src, dialect, (0, 1));
    (ends, alarm)
}

/// [`centre`] for the axes `(a, b)` (indices: X 0, Y 1, Z 2).
fn centre_axes(src: &str, dialect: Dialect, (a, b): (usize, usize)) -> (Vec<(u32, [f64; 2])>, Option<(String, u32)>) {
    let mut interp = interpreter(src, "mill3", dialect);
    let mut stages = Pipeline::for_config(interp.config());
    let mut out = Vec::new();
    let mut ends = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let end = !matches!(step, Ok(Step::Continue | Step::NeedInput));
        stages.process(&mut out, end);
        for c in out.drain(..) {
            if let CanonKind::Motion(m) = c.kind {
                assert_eq!(m.machine[a] - m.target[a], m.machine[b] - m.target[b], "same shift in both systems");
                ends.push((c.line, [m.target[a], m.target[b]]));
            }
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return (ends, None),
            Err(a) => return (ends, Some((a.code, a.line))),
        }
    }
}

/// Every motion end, compared with the expected (line, X, Y) in order, to 1e-6.
#[track_caller]
fn assert_ends(src: &str, want: &[(u32, f64, f64)]) {
    assert_ends_in(src, (0, 1), want);
}

#[track_caller]
fn assert_ends_in(src: &str, axes: (usize, usize), want: &[(u32, f64, f64)]) {
    let (got, alarm) = centre_axes(src, Fanuc, axes);
    assert_eq!(alarm, None, "{src}");
    let close = got.len() == want.len()
        && got.iter().zip(want).all(|((l, p), (wl, x, y))| l == wl && approx(p[0], *x) && approx(p[1], *y));
    assert!(close, "got {got:?}\nwant {want:?}\n{src}");
}

#[test]
fn outside_of_a_square_g42_counter_clockwise() {
    // Square 0..20; the tool (R5) right of counter-clockwise travel is outside: start-up from
    // below (inner corner: intersection), 90° outer corners at the offset lines' intersections,
    // a straight run into the cancel (the offset point, then the programmed end).
    let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n";
    assert_ends(
        src,
        &[(1, 0.0, -10.0), (2, 5.0, -5.0), (3, 25.0, -5.0), (4, 25.0, 25.0), (5, -5.0, 25.0), (6, -5.0, 0.0), (7, 0.0, -10.0)],
    );
}

#[test]
fn inside_of_a_pocket_g41_counter_clockwise() {
    // Pocket 0..40: every corner is inside (intersections); cancel at an inner corner.
    let src = "G90 G00 X20. Y10. Z0\nG41 D1 G01 Y0. F500\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y10.\nM30\n";
    assert_ends(
        src,
        &[
            (1, 20.0, 10.0),
            (2, 25.0, 5.0),
            (3, 35.0, 5.0),
            (4, 35.0, 35.0),
            (5, 5.0, 35.0),
            (6, 5.0, 5.0),
            (7, 15.0, 5.0),
            (8, 20.0, 10.0),
        ],
    );
}

#[test]
fn boss_full_circle_g41_clockwise() {
    // Circle of radius 10 about the origin, clockwise, tool left = outside (offset radius 15).
    // Start-up along y = 0 meets it at y = 5, cancel along y = 0 backwards leaves it at y = −5.
    let src = "G90 G00 X-20. Y0. Z0\nG41 D1 G01 X-10. F500\nG02 I10.\nG40 G01 X-20.\nM30\n";
    let x = -(15.0f64 * 15.0 - 25.0).sqrt();
    assert_ends(src, &[(1, -20.0, 0.0), (2, x, 5.0), (3, x, -5.0), (4, -20.0, 0.0)]);
}

#[test]
fn outer_acute_corner_inserts_the_lengthened_vectors() {
    // +X then back up-left (−2, 1): tool right (R5) is outside an acute corner. The first
    // block runs on to (20,0) + (0,−5) + 5·(1,0); a straight move goes to (20,0) + 5·n2 − 5·t2
    // with t2 = (−2,1)/√5, n2 (right) = (1,2)/√5: (20 + 3√5, √5). The cancel at an outer
    // corner leaves from the perpendicular vector of the block before.
    let s5 = 5f64.sqrt();
    let src = "G90 G00 X-10. Y0 Z0\nG42 D1 G01 X0. F500\nX20.\nX0. Y10.\nG40 X-10.\nM30\n";
    assert_ends(
        src,
        &[
            (1, -10.0, 0.0),
            (2, 0.0, -5.0),
            (3, 25.0, -5.0),
            (3, 20.0 + 3.0 * s5, s5),
            (4, s5, 10.0 + 2.0 * s5),
            (5, -10.0, 10.0),
        ],
    );
}

#[test]
fn negative_d_swaps_the_sides() {
    // D2 = −5 with G41 is D1 = 5 with G42 (the outside of the square).
    let g42 = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n";
    let g41 = g42.replace("G42 D1", "G10 L12 P2 R-5.\nG41 D2");
    let (a, alarm_a) = centre(g42, Fanuc);
    let (b, alarm_b) = centre(&g41, Fanuc);
    assert_eq!((alarm_a, alarm_b), (None, None));
    let points = |v: &[(u32, [f64; 2])]| v.iter().map(|(_, p)| *p).collect::<Vec<_>>();
    assert_eq!(points(&a), points(&b));
    assert_eq!(points(&a)[2], [25.0, -5.0]);
}

#[test]
fn side_change_on_a_straight_line_moves_across() {
    // G41 → G42 between two blocks in line: no intersection; the first ends at its left
    // vector, a straight move crosses to the right one.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG42 X40.\nG40 X50.\nM30\n";
    assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (3, 20.0, -5.0), (4, 40.0, -5.0), (5, 50.0, 0.0)]);
}

#[test]
fn change_of_radius_takes_effect_at_the_end_of_its_block() {
    // D2 = 3 from block 4: the corner before it is placed with 5, the one after with 3.
    let src = "G10 L12 P2 R3.\nG90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nD2 Y20.\nX0.\nG40 Y30.\nM30\n";
    assert_ends(src, &[(2, -10.0, 0.0), (3, 0.0, 5.0), (4, 15.0, 5.0), (5, 17.0, 17.0), (6, 0.0, 17.0), (7, 0.0, 30.0)]);
}

#[test]
fn one_block_without_motion_in_the_plane_keeps_the_corner() {
    // Z between two moves in the plane: the corner is the intersection (15,5); Z moves there.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nZ-1.\nY20.\nG40 X0.\nM30\n";
    assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (4, 15.0, 5.0), (5, 15.0, 15.0), (6, 0.0, 20.0)]);
}

#[test]
fn two_blocks_without_motion_in_the_plane_lose_the_vector() {
    // Z and M08: more than the read-ahead holds (No.19625 = 3 blocks: one may not move). The
    // block before ends with its perpendicular vector; the next runs from there.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nZ-1.\nM08\nY20.\nG40 X0.\nM30\n";
    assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 20.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)]);
}

#[test]
fn g18_compensates_z_and_x() {
    // G18: the plane is (Z, X); left of +Z is +X. Y never moves.
    let src = "G18 G90 G00 X0. Z-10.\nG41 D1 G01 Z0. F500\nZ20.\nG40 Z30.\nM30\n";
    assert_ends_in(src, (2, 0), &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 30.0, 0.0)]);
}

#[test]
fn a_notch_narrower_than_the_tool_is_an_interference_alarm() {
    // The notch X20–24 is 4 wide, the tool 10: compensated, block 5 would run from (25,3) back
    // to (19,3). PS0041 at block 5; the tool stops at the end of block 4.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nY-2.\nX24.\nY0.\nX40.\nG40 X50.\nM30\n";
    let (ends, alarm) = centre(src, Fanuc);
    assert_eq!(alarm, Some(("PS0041".to_string(), 5)));
    assert_eq!(ends.iter().map(|e| e.0).collect::<Vec<_>>(), [1, 2, 3, 4]);
    assert_eq!(ends[3].1, [25.0, 3.0]);
    for (dialect, code) in [(Fanuc, "PS0041"), (Syntec, "COR-100")] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!((r.alarms.len(), r.alarms[0].code.as_str(), r.alarms[0].line), (1, code, 5));
    }
}

#[test]
fn an_arc_too_small_for_the_tool_inside_is_an_interference_alarm() {
    // A counter-clockwise arc of radius 3 with the tool (5) on its inside (G41).
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nG03 X3. Y3. R3.\nG01 Y20.\nG40 X-10.\nM30\n";
    assert_eq!(centre(src, Fanuc).1, Some(("PS0041".to_string(), 3)));
}

#[test]
fn an_interference_in_the_last_block_before_the_end_is_raised() {
    // No G40: M30 ends the compensation; the notch's block is the last but one.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nY-2.\nX24.\nY0.\nM30\n";
    let r = run_with(src, "mill3", Fanuc);
    assert_eq!((r.alarms.len(), r.alarms[0].code.as_str(), r.alarms[0].line), (1, "PS0041", 5));
}

#[test]
fn an_arc_in_the_start_up_or_cancel_block_is_ps0034() {
    for src in [
        "G90 G00 X0. Y0 Z0\nG41 D1 G02 X10. R5. F500\nG40 G01 X20.\nM30\n",
        "G90 G00 X0. Y0 Z0\nG41 D1 G01 X10. F500\nG40 G02 X20. R5.\nM30\n",
    ] {
        let line = if src.contains("G40 G02") { 3 } else { 2 };
        for (dialect, code) in [(Fanuc, "PS0034"), (Syntec, "COR-100")] {
            let r = run_with(src, "mill3", dialect);
            assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, line), "{src}");
        }
    }
}

#[test]
fn what_the_stage_does_not_perform_stays_refused() {
    // Rotation, scaling, a canned cycle, G28/G53, a work system change, a rotary axis, inverse
    // time, G62, G39 and G38 under G41: refused at their block (PS0010 / COR-100).
    let cases = [
        ("G68 X0 Y0 R30.\nG41 D1 G01 X10. F500\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG68 X0 Y0 R30.\n", 2, "mill3"),
        ("G51 X0 Y0 P2\nG41 D1 G01 X10. F500\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG81 X20. Z-5. R2.\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG28 X0\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG53 X0\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG55 X20.\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG92 X0\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG93 X20. F10.\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG62\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG39 X20.\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nG38 X20.\n", 2, "mill3"),
        ("G41 D1 G01 X10. F500\nC10.\n", 2, "table-ac"),
    ];
    for (src, line, preset) in cases {
        let src = format!("G90 G00 X0 Y0 Z0\n{src}G40 X0\nM30\n");
        for (dialect, code) in [(Fanuc, "PS0010"), (Syntec, "COR-100")] {
            let r = run_with(&src, preset, dialect);
            assert_eq!(r.alarms.len(), 1, "{dialect:?} {src}");
            assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, line + 1), "{dialect:?} {src}");
        }
    }
}
