//! Cutter compensation C (`stage::cutter`): tool centre end points worked out by hand
//! (`docs/cutter-compensation.md` gives the rules), through the real interpreter and the
//! pipeline every driver uses, and the run's alarms. Tool offsets 1–99 have radius 5.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::interp::Step;
use fivex_engine::stage::Pipeline;
use fivex_engine::Dialect::{self, Fanuc, Syntec};

/// Motion ends (line, two axes) and the alarm (code, line), if any.
type Centre = (Vec<(u32, [f64; 2])>, Option<(String, u32)>);

/// The end point (X, Y) of every motion that comes out of the stages, with its line; and the
/// alarm the interpreter raised, if any.
fn centre(src: &str, dialect: Dialect) -> Centre {
    let (ends, alarm) = centre_axes(src, dialect, (0, 1));
    (ends, alarm)
}

/// [`centre`] for the axes `(a, b)` (indices: X 0, Y 1, Z 2).
fn centre_axes(src: &str, dialect: Dialect, axes: (usize, usize)) -> Centre {
    centre_of(interpreter(src, "mill3", dialect), axes)
}

/// [`centre`] of an interpreter set up by the caller.
fn centre_of(interp: fivex_engine::interp::Interpreter, (a, b): (usize, usize)) -> Centre {
    let mut ends = Vec::new();
    let alarm = through_stages(interp, |c| {
        if let CanonKind::Motion(m) = c.kind {
            // No work offset here: the stage moved both systems by the same.
            assert!((m.machine[a] - m.target[a]).abs() < 1e-9 && (m.machine[b] - m.target[b]).abs() < 1e-9);
            ends.push((c.line, [m.target[a], m.target[b]]));
        }
    });
    (ends, alarm)
}

/// Every motion end, compared with the expected (line, X, Y) in order, to 1e-6.
#[track_caller]
fn assert_ends(src: &str, want: &[(u32, f64, f64)]) {
    assert_ends_in(src, (0, 1), want);
}

#[track_caller]
fn assert_ends_in(src: &str, axes: (usize, usize), want: &[(u32, f64, f64)]) {
    assert_centre(centre_axes(src, Fanuc, axes), src, want);
}

/// No alarm, and the motion ends `want` (line, the two axes).
#[track_caller]
fn assert_centre((got, alarm): Centre, src: &str, want: &[(u32, f64, f64)]) {
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
        &[
            (1, 0.0, -10.0),
            (2, 5.0, -5.0),
            (3, 25.0, -5.0),
            (4, 25.0, 25.0),
            (5, -5.0, 25.0),
            (6, -5.0, 0.0),
            (7, 0.0, -10.0),
        ],
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
    assert_ends(
        src,
        &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (3, 20.0, -5.0), (4, 40.0, -5.0), (5, 50.0, 0.0)],
    );
}

#[test]
fn change_of_radius_takes_effect_at_the_end_of_its_block() {
    // D2 = 3 from block 4: the corner before it is placed with 5, the one after with 3.
    let src = "G10 L12 P2 R3.\nG90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nD2 Y20.\nX0.\nG40 Y30.\nM30\n";
    assert_ends(
        src,
        &[(2, -10.0, 0.0), (3, 0.0, 5.0), (4, 15.0, 5.0), (5, 17.0, 17.0), (6, 0.0, 17.0), (7, 0.0, 30.0)],
    );
}

/// A new value in the offset memory (G10 L12, `#13001…`, the API) for the D in use waits for
/// the next D (FANUC No.5001#4 EVR = 0), as a length waits for the next H: the contour after
/// the G10 keeps 5 until `D1` is given again, then that block runs to the new value's vector.
/// It acted at once.
#[test]
fn a_new_offset_value_waits_for_the_next_d() {
    let src = "G90 G00 X-20. Y0 Z0\nG41 D1 G01 X0. Y0. F500\nX20.\nG10 L12 P1 R1.\nX40.\nD1 X60.\nG40 X80.\nM30\n";
    assert_ends(src, &[(1, -20.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (5, 40.0, 5.0), (6, 60.0, 1.0), (7, 80.0, 0.0)]);
}

#[test]
fn one_block_without_motion_in_the_plane_keeps_the_corner() {
    // Z between two moves in the plane: the corner is the intersection (15,5); Z moves there.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nZ-1.\nY20.\nG40 X0.\nM30\n";
    assert_ends(
        src,
        &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (4, 15.0, 5.0), (5, 15.0, 15.0), (6, 0.0, 20.0)],
    );
}

#[test]
fn two_blocks_without_motion_in_the_plane_lose_the_vector() {
    // Z and M08: more than the read-ahead holds (No.19625 = 3 blocks: one may not move). The
    // block before ends with its perpendicular vector; the next runs from there.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nZ-1.\nM08\nY20.\nG40 X0.\nM30\n";
    assert_ends(
        src,
        &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 20.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)],
    );
}

#[test]
fn a_block_that_gives_no_command_is_a_block_without_motion() {
    // FANUC lists "G90 ; G code only", "S21 ; S code output" and "G10 L11 …" among the blocks
    // without tool movement (16i-LB §12), Mitsubishi M700V §12.4 "F100 ;" and "S500 ;" (the
    // spindle stopped here, so S gives no command): with M08 they are two, the vector is lost
    // as in `two_blocks_without_motion_in_the_plane_lose_the_vector`.
    for block in ["G90", "F400.", "G17", "S1000", "G10 L12 P2 R4.", "G94 G21"] {
        let src = format!("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nM08\n{block}\nY20.\nG40 X0.\nM30\n");
        assert_ends(&src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)]);
    }
    // Not blocks of the read-ahead (decision, `docs/cutter-compensation.md` rule 8): a comment,
    // a sequence number alone, a macro statement, a subprogram's return. M08 alone keeps the
    // corner (15,5).
    for block in ["(A COMMENT)", "N100", "#1=2.", "M98 P9"] {
        let src =
            format!("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nM08\n{block}\nY20.\nG40 X0.\nM30\nO0009\nM99\n");
        assert_ends(&src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)]);
    }
}

#[test]
fn a_call_or_return_with_a_g_code_is_a_block_without_motion() {
    // Audit crc2 N2: rule 8 exempts a call or return "with nothing else"; a G code beside it
    // is an NC command ("G90 ; G code only", 16i-LB §12) and the block counts. With M08 that
    // is two blocks without motion: the vector is lost, X20. ends perpendicular at (20,5) as
    // in `a_block_that_gives_no_command_is_a_block_without_motion` (until then the corner
    // (15,5) was kept: the overcut the control makes, hidden).
    let lost = [(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)];
    let kept = [(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)];
    let cases = [
        // (the call in the main program, the return in O0009, the corner lost)
        ("G90 M98 P9", "M99", true),
        ("M98 P9", "G90 M99", true),
        ("M98 P9", "G90 M99 (RETURN)", true),
        ("M98 P9", "G91 M99", true),
        // With nothing else: neither counts, the corner stays.
        ("M98 P9", "M99", false),
        ("M98 P9 L2", "M99 (RETURN)", false),
    ];
    for (call, ret, lost_here) in cases {
        let src = format!(
            "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nM08\n{call}\nY20.\nG90 G40 X0.\nM30\nO0009\n{ret}\n"
        );
        assert_ends(&src, if lost_here { &lost } else { &kept });
    }
}

/// Syntec: an M02/M30 in an M98 subprogram returns to the caller as M99 does (`docs/dialects.md`,
/// "Syntec's subprogram and macro calls"), so, alone in its block, it is no more a block of the
/// read-ahead than M99 alone (rule 8): with M08 one block without motion, the corner (15,5)
/// stays, as in `a_call_or_return_with_a_g_code_is_a_block_without_motion`'s `M99` case.
/// Beside a G code it counts, as `G90 M99` does: the vector is lost, X20. ends at (20,5).
/// `G90 M30` did not count (M02/M30 were no call or return words, and the block was taken for
/// a call's because the call level changed): the corner (15,5) the control loses was kept.
#[test]
fn a_syntec_subprograms_m30_return_counts_as_m99() {
    let lost = [(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)];
    let kept = [(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (6, 15.0, 15.0), (7, 0.0, 20.0)];
    for (ret, lost_here) in [("M99", false), ("M30", false), ("M02", false), ("G90 M30", true), ("G90 M99", true)] {
        let src = format!(
            "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nM08\nM98 P9\nY20.\nG90 G40 X0.\nM30\nO0009\n{ret}\n"
        );
        assert_centre(centre(&src, Syntec), &src, if lost_here { &lost } else { &kept });
    }
}

#[test]
fn a_block_whose_move_is_zero_counts_as_two_blocks_without_motion() {
    // FANUC 16i-LB §12: "when the move distance is zero, even if the block is commanded
    // singly", the tool moves as after two blocks without movement: X20. at X20 loses the vector.
    for block in ["X20.", "G91 X0 Y0\nG90"] {
        let src = format!("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\n{block}\nY20.\nG40 X0.\nM30\n");
        let (ends, alarm) = centre(&src, Fanuc);
        assert_eq!(alarm, None);
        let at = |line: u32| ends.iter().find(|(l, _)| *l == line).map(|(_, p)| *p);
        assert_eq!(at(3), Some([20.0, 5.0]), "{src}: {ends:?}");
    }
}

#[test]
fn g41_given_again_in_offset_mode_ends_the_block_before_perpendicular() {
    // FANUC 30i §6.6, "cutter compensation G code in the offset mode": the block before ends
    // at the vector perpendicular to its move "irrespective of machining inner or outer side";
    // the inside corner (15,5) of `one_block_without_motion_in_the_plane_keeps_the_corner`
    // becomes (20,5), the G41 block runs from there to its own corner (15,15).
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG41 Y20.\nG40 X0.\nM30\n";
    assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 15.0, 15.0), (5, 0.0, 20.0)]);
    // G41 alone, a block without movement of its own: the same at the next move.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG41\nY20.\nG40 X0.\nM30\n";
    assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (5, 15.0, 15.0), (6, 0.0, 20.0)]);
    // G42 in G42 mode at an outside corner: the block before ends perpendicular too, (20,-5)
    // where the corner's intersection was (25,-5).
    let src = "G90 G00 X-10. Y0 Z0\nG42 D1 G01 X0. F500\nX20.\nG42 Y20.\nG40 X0.\nM30\n";
    let (ends, alarm) = centre(src, Fanuc);
    assert_eq!(alarm, None);
    assert!(ends.iter().any(|(l, p)| *l == 3 && approx(p[0], 20.0) && approx(p[1], -5.0)), "{ends:?}");
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
fn a_depression_smaller_than_the_offset_is_an_interference_alarm() {
    // FANUC 30i §5 <1>: a V 2 wide and 2 deep in a +X wall, tool left (R5). Block 4 runs along
    // (1,−2)/√5; its offset line (left normal (2,1)/√5) meets y = 5 (outside, obtuse) at
    // x = 17.5 + 2.5√5 and, by symmetry, block 5's offset at x = 21, y = 5√5 − 2: compensated
    // it runs along (−1,2), against the programmed (1,−2). PS0041 at block 4; the tool stops at
    // the end of block 3, 17.5 + 2.5√5, 5.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-2.\nX22. Y0\nX40.\nG40 X50.\nM30\n";
    let (ends, alarm) = centre(src, Fanuc);
    assert_eq!(alarm, Some(("PS0041".to_string(), 4)));
    assert_eq!(ends.iter().map(|e| e.0).collect::<Vec<_>>(), [1, 2, 3]);
    assert!(approx(ends[2].1[0], 17.5 + 2.5 * 5f64.sqrt()) && approx(ends[2].1[1], 5.0), "{ends:?}");
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
fn a_cancel_block_that_runs_backwards_is_an_interference_alarm() {
    // Audit crc2 N3 (shortexit.nc): rule 9 holds for the G40 block as for any block. The square
    // 0..50 clockwise with G41 (R5) outside; X0. (line 6, −X) turns left into the 3 mm exit
    // G40 Y-3. (−Y): an inside corner, X0. ends at the crossing of y = −5 and x = 5, (5,−5). The
    // cancel would run from (5,−5) to (0,−3), direction (−5,2) against the programmed (0,−3):
    // dot −6 < 0, PS0041 at line 7; the tool stops at (5,−5) (it ran on to (0,−3), 3 mm from
    // the part's corner (0,0): a 2 mm gouge). Start-up (line 2) by hand: its offset line
    // 5·(−1,1)/√2 + t·(1,1) meets x = −5 at y = 5√2 − 5.
    let body = "G90 G00 X-20. Y-20. Z0\nG41 D1 G01 X0. Y0. F500\nY50.\nX50.\nY0.\nX0.\n";
    let src = format!("{body}G40 Y-3.\nM30\n");
    let (ends, alarm) = centre(&src, Fanuc);
    assert_eq!(alarm, Some(("PS0041".to_string(), 7)));
    let want = [
        (1, -20.0, -20.0),
        (2, -5.0, 50f64.sqrt() - 5.0),
        (3, -5.0, 55.0),
        (4, 55.0, 55.0),
        (5, 55.0, -5.0),
        (6, 5.0, -5.0),
    ];
    let close = ends.len() == want.len()
        && ends.iter().zip(&want).all(|((l, p), (wl, x, y))| l == wl && approx(p[0], *x) && approx(p[1], *y));
    assert!(close, "got {ends:?}\nwant {want:?}");
    for (dialect, code) in [(Fanuc, "PS0041"), (Syntec, "COR-100")] {
        let r = run_with(&src, "mill3", dialect);
        assert_eq!((r.alarms.len(), r.alarms[0].code.as_str(), r.alarms[0].line), (1, code, 7));
    }
    // A cancel that leaves the corner forward runs: G40 Y-10. from (5,−5) to (0,−10), direction
    // (−5,−5), dot 50 > 0.
    let src = format!("{body}G40 Y-10.\nM30\n");
    let mut want = want.to_vec();
    want.push((7, 0.0, -10.0));
    assert_ends(&src, &want);
    // G40 with I/J (rule 11): X0. ends where y = −5 meets the line from (0,0) along (0,−1)
    // offset left, x = 5: the same (5,−5), and the same alarm.
    let src = format!("{body}G40 Y-3. I0 J-1.\nM30\n");
    assert_eq!(centre(&src, Fanuc).1, Some(("PS0041".to_string(), 7)));
}

#[test]
fn i_j_k_in_a_g41_block_are_refused_not_ignored() {
    // Audit crc2 N1 (tdc.nc): I, J and K all in the G41 block start FANUC's three-dimensional
    // tool compensation (the vector R·(I,J,K)/|IJK|: (0,0,5) at the end of line 5), which ran as
    // cutter compensation C: the tool centre at (0,5,0), 5 mm off in Y and in Z. Refused at the
    // G41 block, by the run and by `fivex check`; nothing of it moves (the tool stays at the
    // end of line 4, X-20. Y0 Z0).
    let src = "G90 G17 G21 G40\nG00 X-20. Y0.\nZ5.\nG01 Z0. F500.\nG41 X0. Y0. Z0. I0. J0. K1. D01\n\
               G01 X20. Z-5. I0.5 J0. K0.866\nX40. I0. J0. K1.\nG40 X60.\nG00 Z50.\nM30\n";
    for (dialect, code) in [(Fanuc, "PS0010"), (Syntec, "COR-100"), (fivex_engine::Dialect::Haas, "310")] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!(r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect::<Vec<_>>(), [(code, 5)], "{dialect:?}");
        assert_eq!(&r.machine[..3], &[-20.0, 0.0, 0.0], "{dialect:?}");
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(src), dialect);
        let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, dialect.describe(&d.id).0)).collect();
        assert_eq!(found, [(5, 1, code.to_string())], "{dialect:?}");
        assert!(diags[0].detail.contains("three-dimensional tool compensation"), "{}", diags[0].detail);
    }
    // Only some of them: two-dimensional compensation C (FANUC 16/18-C), where some controls
    // set the offset vector's direction by them; fivex ignored them. Refused at the block, in
    // the start-up and in offset mode alike.
    for (src, line) in [
        ("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. Y0. I1. J0 F500\nX20.\nG40 X30.\nM30\n", 2),
        ("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nG41 X20. I1.\nY20.\nG40 X0.\nM30\n", 3),
    ] {
        assert_eq!(centre(src, Fanuc).1, Some(("PS0010".to_string(), line)), "{src}");
        let mut interp = interpreter(src, "mill3", Fanuc);
        let stop = fivex_engine::check::run_without_motion(&mut interp, false).map(|s| (s.alarm.code, s.alarm.line));
        assert_eq!(stop, Some(("PS0010".to_string(), line)), "fivex check's run: {src}");
    }
    // In an arc's block I and J are its centre: G41 given again there runs (rule 5).
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG41 G03 X30. Y10. I0 J10.\nG01 Y20.\nG40 X40.\nM30\n";
    assert_eq!(centre(src, Fanuc).1, None);
}

/// D0 in offset mode is an offset cancel, as G40 is (FANUC 15i-MA §14.3, "Offset mode
/// cancel": "0 has been commanded as the offset number"), and a later D other than 0 is a new
/// start-up: the block before D0 ends at its perpendicular vector (type A, outside corner) and
/// the D0 block runs from there to its programmed end; the D1 block starts up perpendicular to
/// the block after it. It compensated by 0 instead: the corners before and after were placed
/// as offset-mode corners (3.8 mm off at the D1 block).
#[test]
fn d0_in_offset_mode_cancels_and_the_next_d_starts_up_again() {
    let src = "G90 G00 X-20. Y0 Z0\nG42 D1 G01 X0. Y0. F500\nX50.\nX0. Y20. D0\nY40.\nD1 X-10. Y60.\n\
               X-60. Y50.\nG40 X-110. Y40.\nM30\n";
    // Right of the direction (−50, −10): (−10, 50)/√2600.
    let n = [-10.0 / 2600f64.sqrt(), 50.0 / 2600f64.sqrt()];
    assert_ends(
        src,
        &[
            (1, -20.0, 0.0),
            (2, 0.0, -5.0),
            (3, 50.0, -5.0),
            (4, 0.0, 20.0),
            (5, 0.0, 40.0),
            (6, -10.0 + 5.0 * n[0], 60.0 + 5.0 * n[1]),
            (7, -60.0 + 5.0 * n[0], 50.0 + 5.0 * n[1]),
            (8, -110.0, 40.0),
        ],
    );
    // G41 D0 starts nothing: the block with D1 is the start-up (perpendicular to the next one).
    let src = "G90 G00 X0 Y0 Z0\nG41 D0 G01 X0. Y0. F500\nY50. D1\nX40. Y20.\nG40 X80. Y-10.\nM30\n";
    let d = [0.8, -0.6];
    assert_ends(
        src,
        &[(1, 0.0, 0.0), (2, 0.0, 0.0), (3, 5.0 * -d[1], 50.0 + 5.0 * d[0]), (4, 43.0, 24.0), (5, 80.0, -10.0)],
    );
    // An arc with D0 in offset mode is an arc in the cancel block: PS0034, the tool stops.
    let src = "G90 G00 X-20. Y-20. Z0\nG41 D1 G01 X0. Y0. F500\nY50.\nG02 X50. Y0. R50. D0\nG01 X0.\nG40 X-30.\nM30\n";
    let r = run_with(src, "mill3", Fanuc);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("PS0034", 4), "{:?}", r.alarms);
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
    // time and G62 under G41: refused at their block (PS0010 / COR-100).
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

#[test]
fn the_current_position_is_refused_where_a_compensation_vector_may_stand() {
    // FANUC's #5021…/#5041… include the compensation vector and stop the read-ahead (the block
    // before then ends perpendicular): not modelled, so FX0006 rather than the programmed point.
    let refused = [
        // In offset mode, after the start-up.
        "G41 D1 G01 X10. F500\n#100=#5041\n",
        "G42 D1 G01 X10. F500\nY10.\n#100=#5022\n",
        // After a G40 that has not moved yet: the vector still stands.
        "G41 D1 G01 X10. F500\nG40\n#100=#5041\n",
        // The 5-axis tool side offset.
        "G41.2 D1 G01 X10. F500\n#100=#5043\n",
    ];
    for body in refused {
        let src = format!("G90 G00 X0 Y0 Z0\n{body}G40 X0\nM30\n");
        let line = src.lines().position(|l| l.starts_with("#100")).unwrap() as u32 + 1;
        // (The tool side offset is FANUC's.)
        let dialects: &[Dialect] = if body.contains("G41.2") { &[Fanuc] } else { &[Fanuc, Syntec, Dialect::Haas] };
        for &dialect in dialects {
            let r = run_with(&src, if body.contains("G41.2") { "head-bc" } else { "mill3" }, dialect);
            assert_eq!(r.alarms.len(), 1, "{dialect:?} {src}");
            // Syntec's #5001…#5500 are its user parameters: refused as any use of them.
            let code = if dialect == Syntec { "COR-016" } else { "FX0006" };
            assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, line), "{dialect:?} {src}");
        }
    }
    // G41 given but nothing moved yet, and after the cancel's move: the programmed point is
    // where the tool is.
    for body in ["G41 D1\n#100=#5041\nG01 X10. F500\nG40 X0\n", "G41 D1 G01 X10. F500\nG40 X0\n#100=#5041\n"] {
        let src = format!("G90 G00 X0 Y0 Z0\n{body}M30\n");
        let r = run_with(&src, "mill3", Fanuc);
        assert!(r.completed(), "{:?}\n{src}", r.alarms);
        assert_eq!(r.variables.iter().find(|v| v.0 == 100).map(|v| v.1), Some(0.0), "{src}");
    }
}

mod random {
    //! Random contours of lines and arcs with no feature smaller than the radius: the tool
    //! centre path is at exactly R from each block's own line or circle along its interior, on
    //! the commanded side, and never closer than R − 1 µm to the contour anywhere.

    use super::*;
    use fivex_engine::canon::{Canon, Motion, Pos};
    use proptest::prelude::*;
    use std::f64::consts::PI;

    const R: f64 = 5.0;

    /// A programmed block as the interpreter emitted it: a segment, or an arc (centre, start
    /// radius, signed sweep in radians).
    #[derive(Debug, Clone, Copy)]
    enum Block {
        Line([f64; 2], [f64; 2]),
        Arc { from: [f64; 2], to: [f64; 2], center: [f64; 2], sweep: f64 },
    }

    fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
        [a[0] - b[0], a[1] - b[1]]
    }
    fn len(a: [f64; 2]) -> f64 {
        a[0].hypot(a[1])
    }

    fn distance(p: [f64; 2], b: &Block) -> f64 {
        match *b {
            Block::Line(a, e) => {
                let d = sub(e, a);
                let u = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
                let u = u.clamp(0.0, 1.0);
                len(sub(p, [a[0] + u * d[0], a[1] + u * d[1]]))
            }
            Block::Arc { from, to, center, sweep } => {
                let angle = |q: [f64; 2]| (q[1] - center[1]).atan2(q[0] - center[0]);
                // The point's angle measured from the start in the sweep's direction.
                let mut a = (angle(p) - angle(from)) * sweep.signum();
                a = a.rem_euclid(2.0 * PI);
                if a <= sweep.abs() {
                    let rho =
                        len(sub(from, center)) + (len(sub(to, center)) - len(sub(from, center))) * a / sweep.abs();
                    (len(sub(p, center)) - rho).abs()
                } else {
                    len(sub(p, from)).min(len(sub(p, to)))
                }
            }
        }
    }

    /// Points along a motion from `from` (the executor's reading of `Motion`).
    fn samples(from: &Pos, m: &Motion, n: usize) -> Vec<[f64; 2]> {
        (0..=n)
            .map(|k| {
                let u = k as f64 / n as f64;
                match m.arc.as_deref() {
                    None => [from[0] + u * (m.target[0] - from[0]), from[1] + u * (m.target[1] - from[1])],
                    Some(arc) => {
                        let c = [arc.center[0], arc.center[1]];
                        let r1 = len(sub([m.target[0], m.target[1]], c));
                        let start = (from[1] - c[1]).atan2(from[0] - c[0]);
                        let phi = start + u * arc.sweep_deg.to_radians();
                        let rho = arc.radius + u * (r1 - arc.radius);
                        [c[0] + rho * phi.cos(), c[1] + rho * phi.sin()]
                    }
                }
            })
            .collect()
    }

    /// One contour element: heading change before it (degrees), then a line of `length` or an
    /// arc of `radius` and `sweep` (degrees, signed).
    #[derive(Debug, Clone, Copy)]
    struct Element {
        turn: f64,
        arc: bool,
        length: f64,
        radius: f64,
        sweep: f64,
    }

    fn element() -> impl Strategy<Value = Element> {
        (
            prop_oneof![Just(0.0), -100.0..100.0f64],
            any::<bool>(),
            4.0 * R..8.0 * R,
            2.0 * R..6.0 * R,
            40.0..150.0f64,
            any::<bool>(),
        )
            .prop_map(|(turn, arc, length, radius, sweep, ccw)| Element {
                turn,
                arc,
                length,
                radius,
                // At least 4R along the arc.
                sweep: sweep.max((4.0 * R / radius).to_degrees()) * if ccw { 1.0 } else { -1.0 },
            })
    }

    /// The NC program of a contour, with compensation on `side` (41/42) or none (40), and the
    /// programmed blocks as the NC text states them (for the far-apart check).
    fn program(elements: &[Element], side: u32) -> Option<String> {
        // An arc with the tool on its inside needs room: radius at least 3R, and a corner next
        // to it turning at most 45° (two such arcs of radius ρ meeting at a turn δ leave the
        // tool room only while sin(δ/2) ≤ 1 − R/ρ; beyond, the control has no solution, PS0033).
        let s = match side {
            41 => 1.0,
            42 => -1.0,
            _ => 0.0,
        };
        for (i, e) in elements.iter().enumerate() {
            let concave = e.arc && e.sweep * s > 0.0;
            let inner = |turn: f64| turn.abs() > 45.0;
            let next_turn = elements.get(i + 1).map_or(0.0, |n| n.turn);
            if concave && (e.radius < 3.0 * R || inner(e.turn) || inner(next_turn)) {
                return None;
            }
        }
        let (mut p, mut h) = ([0.0f64, 0.0f64], 0.0f64);
        let mut body = String::new();
        let mut blocks = Vec::new();
        for e in elements {
            h += e.turn.to_radians();
            let t = [h.cos(), h.sin()];
            let left = [-t[1], t[0]];
            if e.arc {
                let s = e.sweep.to_radians();
                let c = if s > 0.0 {
                    [p[0] + e.radius * left[0], p[1] + e.radius * left[1]]
                } else {
                    [p[0] - e.radius * left[0], p[1] - e.radius * left[1]]
                };
                let a0 = (p[1] - c[1]).atan2(p[0] - c[0]);
                let q = [c[0] + e.radius * (a0 + s).cos(), c[1] + e.radius * (a0 + s).sin()];
                body += &format!(
                    "G0{} X{:.6} Y{:.6} I{:.6} J{:.6}\n",
                    if s > 0.0 { 3 } else { 2 },
                    q[0],
                    q[1],
                    c[0] - p[0],
                    c[1] - p[1]
                );
                blocks.push(Block::Arc { from: p, to: q, center: c, sweep: s });
                p = q;
                h += s;
            } else {
                let q = [p[0] + e.length * t[0], p[1] + e.length * t[1]];
                body += &format!("G01 X{:.6} Y{:.6}\n", q[0], q[1]);
                blocks.push(Block::Line(p, q));
                p = q;
            }
        }
        // No two blocks that are not neighbours come within 3R of each other; neighbours only
        // near their common corner (no narrow slot or spike between them).
        let point = |b: &Block, u: f64| match *b {
            Block::Line(a, e) => [a[0] + u * (e[0] - a[0]), a[1] + u * (e[1] - a[1])],
            Block::Arc { from, center, sweep, .. } => {
                let a0 = (from[1] - center[1]).atan2(from[0] - center[0]);
                let r = len(sub(from, center));
                let phi = a0 + sweep * u;
                [center[0] + r * phi.cos(), center[1] + r * phi.sin()]
            }
        };
        for i in 0..blocks.len() {
            for j in i + 1..blocks.len() {
                let corner = if j == i + 1 { Some(point(&blocks[j], 0.0)) } else { None };
                for (x, y) in [(i, j), (j, i)] {
                    let close = (0..=40).map(|k| point(&blocks[x], k as f64 / 40.0)).any(|q| match corner {
                        Some(c) => len(sub(q, c)) > 3.0 * R && distance(q, &blocks[y]) < 2.0 * R,
                        None => distance(q, &blocks[y]) < 3.0 * R,
                    });
                    if close {
                        return None;
                    }
                }
            }
        }
        let first = blocks[0];
        let last = blocks[blocks.len() - 1];
        let dir = |b: &Block, end: bool| match *b {
            Block::Line(a, e) => {
                let d = sub(e, a);
                [d[0] / len(d), d[1] / len(d)]
            }
            Block::Arc { from, to, center, sweep } => {
                let q = if end { to } else { from };
                let r = sub(q, center);
                let l = len(r);
                [-r[1] / l * sweep.signum(), r[0] / l * sweep.signum()]
            }
        };
        // Start up and cancel in line with the first and last block, 3R before and after.
        let (t0, te) = (dir(&first, false), dir(&last, true));
        let start = [-3.0 * R * t0[0], -3.0 * R * t0[1]];
        let end = [p[0] + 3.0 * R * te[0], p[1] + 3.0 * R * te[1]];
        let on = if side == 40 { String::new() } else { format!("G{side} D1 ") };
        let off = if side == 40 { "" } else { "G40 " };
        Some(format!(
            "G90 G17 G00 X{:.6} Y{:.6} Z0\n{on}G01 X0 Y0 F1000\n{body}{off}G01 X{:.6} Y{:.6}\nM30\n",
            start[0], start[1], end[0], end[1]
        ))
    }

    /// The programmed blocks of the contour (lines 3…) as the interpreter emitted them.
    fn programmed(src: &str) -> Vec<(u32, Block)> {
        let mut from = [0.0; 2];
        let mut v = Vec::new();
        for c in canon(src) {
            let CanonKind::Motion(m) = c.kind else { continue };
            let to = [m.target[0], m.target[1]];
            let b = match m.arc.as_deref() {
                Some(a) => Block::Arc { from, to, center: [a.center[0], a.center[1]], sweep: a.sweep_deg.to_radians() },
                None => Block::Line(from, to),
            };
            v.push((c.line, b));
            from = to;
        }
        v
    }

    fn through_stages(src: &str) -> (Vec<Canon>, Option<fivex_engine::alarm::Alarm>) {
        let mut interp = interpreter(src, "mill3", Fanuc);
        let mut stages = Pipeline::for_config(interp.config());
        let (mut out, mut all) = (Vec::new(), Vec::new());
        loop {
            let step = interp.step(&mut out);
            let stage_alarm = stages.process(&mut out, !matches!(step, Ok(Step::Continue | Step::NeedInput)));
            all.append(&mut out);
            if stage_alarm.is_some() {
                return (all, stage_alarm);
            }
            match step {
                Ok(Step::Continue) => {}
                Ok(Step::NeedInput) => interp.finish(),
                Ok(Step::Ended) => return (all, None),
                Err(a) => return (all, Some(a)),
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(300), max_global_rejects: 100_000, ..ProptestConfig::default() })]

        #[test]
        fn the_tool_centre_stays_at_the_radius(elements in prop::collection::vec(element(), 2..6), left in any::<bool>()) {
            let side = if left { 41 } else { 42 };
            let src = program(&elements, side);
            prop_assume!(src.is_some());
            let src = src.unwrap();
            let blocks = programmed(&src);
            let contour: Vec<Block> = blocks.iter().filter(|(l, _)| *l >= 3 && (*l as usize) < 3 + elements.len()).map(|b| b.1).collect();
            let (out, alarm) = through_stages(&src);
            prop_assert!(alarm.is_none(), "{alarm:?}\n{src}");
            let r = if side == 41 { R } else { -R };
            let mut from: Pos = [0.0; fivex_engine::machine::MAX_AXES];
            let mut seen = std::collections::HashSet::new();
            for c in &out {
                let CanonKind::Motion(m) = &c.kind else { continue };
                let pts = samples(&from, m, 24);
                // (The start-up and cancel blocks run between the contour and points off it.)
                if c.line >= 3 && (c.line as usize) < 3 + elements.len() {
                    for p in &pts {
                        let d = contour.iter().map(|b| distance(*p, b)).fold(f64::INFINITY, f64::min);
                        prop_assert!(d >= R - 1e-3, "line {}: {p:?} is {d} from the contour\n{src}", c.line);
                    }
                }
                // A contour block's own move (the first motion of its line) runs on its
                // offset: at R from its line or circle, on the commanded side.
                let own = blocks.iter().find(|(l, _)| *l == c.line && *l >= 3 && (*l as usize) < 3 + elements.len());
                if let (Some((_, b)), true) = (own, seen.insert(c.line)) {
                    for p in &pts[1..pts.len() - 1] {
                        let off = match *b {
                            Block::Line(a, e) => {
                                let t = sub(e, a);
                                ((p[1] - a[1]) * t[0] - (p[0] - a[0]) * t[1]) / len(t)
                            }
                            Block::Arc { to, center, sweep, .. } => {
                                (len(sub(to, center)) - len(sub(*p, center))) * sweep.signum()
                            }
                        };
                        // (The program's points are rounded to 1 µm: its arcs are spirals of that size.)
                        prop_assert!((off - r).abs() < 1e-4, "line {}: {p:?} is {off} off its block, not {r}\n{src}", c.line);
                    }
                }
                from = m.target;
            }
        }

        /// The run's cutting point (`Sample::cutting`, from the sampled axes and the tool's
        /// radius): wherever the tool runs on a contour block's offset (its tip at R from the
        /// block, inside it), the tool touches the block there — on it within 1 µm, at R from
        /// the tip; and it never shows inside the contour by more than the tool cuts past it.
        #[test]
        fn the_cutting_point_is_on_the_contour_where_the_tool_touches(
            elements in prop::collection::vec(element(), 2..5),
            left in any::<bool>(),
        ) {
            let side = if left { 41 } else { 42 };
            let src = program(&elements, side);
            prop_assume!(src.is_some());
            let src = src.unwrap();
            let blocks = programmed(&src);
            let own = |line: u32| blocks.iter().find(|(l, _)| *l == line && *l >= 3 && (*l as usize) < 3 + elements.len());
            let mut interp = interpreter(&src, "mill3", Fanuc);
            let (mut touching, mut worst, mut without) = (0, 0.0f64, 0);
            let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
                let Some((_, b)) = own(s.line) else { return };
                let Some(cut) = s.cutting else {
                    without += 1;
                    return;
                };
                let (tip, cut) = ([s.tip[0], s.tip[1]], [cut[0], cut[1]]);
                // Always the tool's side: at R from the tip, at its height.
                worst = worst.max((len(sub(cut, tip)) - R).abs()).max((s.cutting.unwrap()[2] - s.tip[2]).abs());
                let inside = match *b {
                    Block::Line(a, e) => {
                        let d = sub(e, a);
                        let u = ((tip[0] - a[0]) * d[0] + (tip[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
                        (0.01..=0.99).contains(&u)
                    }
                    Block::Arc { from, to, .. } => len(sub(tip, from)) > 0.5 && len(sub(tip, to)) > 0.5,
                };
                if inside && (distance(tip, b) - R).abs() < 1e-4 {
                    touching += 1;
                    worst = worst.max(distance(cut, b));
                }
            });
            prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
            prop_assert_eq!(without, 0, "samples of the contour's blocks without a cutting point\n{}", src);
            prop_assert!(touching > 20 * elements.len(), "{} samples touching\n{}", touching, src);
            prop_assert!(worst < 1e-3, "the cutting point {} mm off\n{}", worst, src);
        }

        #[test]
        fn without_compensation_the_stages_hand_on_the_same_commands(elements in prop::collection::vec(element(), 2..6)) {
            let src = program(&elements, 40);
            prop_assume!(src.is_some());
            let src = src.unwrap();
            let (out, alarm) = through_stages(&src);
            prop_assert!(alarm.is_none());
            prop_assert_eq!(out, canon(&src));
        }
    }
}

mod in_the_controller {
    //! The stage under the controller: the same tool centre path as a run, in single block too.

    use fivex_engine::controller::{Controller, RunState};
    use fivex_engine::interp::Config;
    use fivex_engine::machine::MachineConfig;
    use fivex_engine::Dialect;

    const SQUARE: &str =
        "G10 L12 P1 R5.\nG90 G00 X0. Y-10. Z0.\nG42 D1 G01 Y0. F3000.\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n";

    /// Cycle start (again after every single-block stop) until the program ends; the X/Y
    /// where the machine stood at each stop.
    fn stops(single_block: bool) -> Vec<[f64; 2]> {
        let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc));
        c.panel.single_block = single_block;
        c.select_program(SQUARE).unwrap();
        let mut stops = Vec::new();
        for _ in 0..12 {
            if c.cycle_start().is_err() {
                break;
            }
            let start = c.time();
            while c.run_state() == RunState::Running && c.time() - start < 30.0 {
                c.tick(0.001);
            }
            assert!(c.alarms().is_empty(), "{:?}", c.alarms());
            let m = c.point().machine;
            stops.push([m[0], m[1]]);
        }
        stops
    }

    #[test]
    fn the_controller_stops_at_the_compensated_corners_in_single_block() {
        assert_eq!(stops(false)[0], [0.0, -10.0]);
        // Each cycle start runs the block whose end the stage has placed, the block before the
        // G40 block too (the stage releases both when the G40 block is read). The G10 block
        // before the compensation stops as every NC block does, where the machine stands.
        let single = stops(true);
        assert_eq!(
            single[..8],
            [
                [0.0, 0.0],
                [0.0, -10.0],
                [5.0, -5.0],
                [25.0, -5.0],
                [25.0, 25.0],
                [-5.0, 25.0],
                [-5.0, 0.0],
                [0.0, -10.0]
            ]
        );
    }
}

mod in_mdi {
    //! MDI under G41/G42 (`docs/cutter-compensation.md`, "MDI"): the blocks of one MDI text
    //! are read ahead like a program's, so their corners are placed by the same rules; at the
    //! end of the text the stage releases what it holds, the last block ending at its
    //! perpendicular vector. The next cycle start loads the next text, which starts in G40 like
    //! any program (a load resets group 07): its first move removes the vector as a G40 block
    //! does, and compensating again is a new start-up.

    use fivex_engine::controller::{Controller, Mode, RunState};
    use fivex_engine::interp::gcode::{code, group};
    use fivex_engine::interp::Config;
    use fivex_engine::machine::MachineConfig;
    use fivex_engine::Dialect;

    /// Runs `text` in MDI (cycle start again after every single-block stop: one per block, as
    /// a cycle start after the end would run the text again); the X/Y where the machine stood
    /// at each stop.
    fn mdi(c: &mut Controller, text: &str) -> Vec<[f64; 2]> {
        c.set_mode(Mode::Mdi).unwrap();
        c.set_mdi(text).unwrap();
        let mut stops = Vec::new();
        let starts = if c.panel.single_block { text.lines().count() } else { 1 };
        let run = |c: &mut Controller, stops: &mut Vec<[f64; 2]>| {
            c.cycle_start().unwrap();
            let start = c.time();
            while c.run_state() == RunState::Running && c.time() - start < 30.0 {
                c.tick(0.001);
            }
            assert!(c.alarms().is_empty(), "{text}: {:?}", c.alarms());
            let m = c.point().machine;
            if stops.last() != Some(&[m[0], m[1]]) {
                stops.push([m[0], m[1]]);
            }
        };
        for _ in 0..starts {
            run(c, &mut stops);
        }
        // A stop after the last block's motion (the program's end still to read): one more.
        for _ in 0..3 {
            if c.set_mdi(text).is_ok() {
                break;
            }
            run(c, &mut stops);
        }
        stops
    }

    fn controller(single_block: bool) -> Controller {
        let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc));
        c.interpreter_mut().state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
        c.panel.single_block = single_block;
        c
    }

    fn cutter_mode(c: &Controller) -> u16 {
        c.interpreter().state.modal(group::CUTTER_COMP)
    }

    #[test]
    fn a_compensated_mdi_text_moves_the_tool_centre_at_the_offset_and_the_next_text_removes_the_vector() {
        for single_block in [false, true] {
            let mut c = controller(single_block);
            // One text: start-up along +X (the next block in line: the vector is 0,5), an inside
            // corner at 40,0 (the offset lines meet at 35,5), the text's last block ends at its
            // perpendicular vector (35,30): nothing comes after it to meet.
            let stops = mdi(&mut c, "G90 G17 G00 X-20. Y0. Z0.\nG41 D1 G01 X0. F3000.\nX40.\nY30.\n");
            let want: &[[f64; 2]] =
                if single_block { &[[-20.0, 0.0], [0.0, 5.0], [35.0, 5.0], [35.0, 30.0]] } else { &[[35.0, 30.0]] };
            assert_eq!(stops, want, "single block {single_block}");
            assert_eq!(cutter_mode(&c), code::G41, "G41 stays in force after the MDI text");
            // The next text starts in G40: its first move goes from the vector where the tool
            // stands (35,30) to its programmed point, as a cancel block (no corner with the text
            // before, which had already been carried out).
            assert_eq!(mdi(&mut c, "X0.\n"), [[0.0, 30.0]], "single block {single_block}");
            assert_eq!(cutter_mode(&c), code::G40, "each MDI text starts in G40");
            // Compensating again is a new start-up: along −X, G41 ends at the vector 0,−5.
            assert_eq!(mdi(&mut c, "G41 D1 G01 X-20.\n"), [[-20.0, 25.0]], "single block {single_block}");
            assert_eq!(mdi(&mut c, "G40 Y0.\n"), [[-20.0, 0.0]], "single block {single_block}");
            assert_eq!(cutter_mode(&c), code::G40);
        }
    }

    #[test]
    fn a_reset_after_a_compensated_mdi_text_drops_the_vector() {
        let mut c = controller(false);
        assert_eq!(mdi(&mut c, "G90 G17 G00 X0. Y0. Z0.\nG41 D1 G01 X20. F3000.\n"), [[20.0, 5.0]]);
        c.reset();
        // FANUC 16/18-C: "the offset vector is cleared by reset"; group 07 is back to G40 too.
        assert_eq!(cutter_mode(&c), code::G40);
        assert_eq!(mdi(&mut c, "G01 X30. F3000.\n"), [[30.0, 5.0]], "the machine moves only along X");
    }
}

#[test]
fn side_change_between_blocks_almost_in_line_does_not_run_away() {
    // 1° apart: the offsets cross about 573 mm ahead; fivex crosses over at the corner instead.
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG42 X40. Y0.349\nG40 X50.\nM30\n";
    let (ends, alarm) = centre(src, Fanuc);
    assert_eq!(alarm, None);
    assert!(ends.iter().all(|(_, p)| p[0].abs() < 60.0 && p[1].abs() < 10.0), "{ends:?}");
    assert_eq!(ends[2], (3, [20.0, 5.0]));
}

#[test]
fn a_work_offset_moves_with_the_compensated_point() {
    // G54 at X100 Y50: every compensated point is 100, 50 away in machine coordinates.
    let src = "G10 L2 P1 X100. Y50.\nG90 G54 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nG40 X0.\nM30\n";
    let mut interp = interpreter(src, "mill3", Fanuc);
    let mut stages = Pipeline::for_config(interp.config());
    let (mut out, mut seen) = (Vec::new(), Vec::new());
    loop {
        let step = interp.step(&mut out);
        let stage_alarm = stages.process(&mut out, !matches!(step, Ok(Step::Continue | Step::NeedInput)));
        assert_eq!(stage_alarm, None);
        for c in out.drain(..) {
            if let CanonKind::Motion(m) = c.kind {
                assert!(approx(m.machine[0] - m.target[0], 100.0) && approx(m.machine[1] - m.target[1], 50.0));
                seen.push([m.target[0], m.target[1]]);
            }
        }
        if !matches!(step, Ok(Step::Continue)) {
            break;
        }
    }
    assert_eq!(seen[2], [25.0, -5.0]);
}

#[test]
fn the_peer_programs_agree_with_linuxcnc_but_at_the_cancel() {
    // The programs of scripts/peer-crc.sh. LinuxCNC's rs274 gives the same points but for the
    // block before an inside-corner cancel, which it ends at its perpendicular vector (20,5 and
    // 15,−2) where FANUC's cancel type A takes the intersection (15,5 and 10,−2).
    let head = "G21 G17 G40 G90 G94\n";
    let pocket = format!("{head}G00 X20. Y20. Z0.\nG41 D1 G01 Y0. F1000.\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y20.\nM30\n");
    let ends = |src: &str| centre(src, Fanuc).0.into_iter().skip(1).map(|(_, p)| p).collect::<Vec<_>>();
    assert_eq!(
        ends(&pocket),
        [[25.0, 5.0], [35.0, 5.0], [35.0, 35.0], [5.0, 35.0], [5.0, 5.0], [15.0, 5.0], [20.0, 20.0]]
    );
    let slot = format!("{head}G00 X15. Y20. Z0.\nG41 D1 G01 Y-7. F1000.\nX30.\nY7.\nX0.\nY-7.\nX15.\nG40 Y20.\nM30\n");
    assert_eq!(
        ends(&slot),
        [[20.0, -2.0], [25.0, -2.0], [25.0, 2.0], [5.0, 2.0], [5.0, -2.0], [10.0, -2.0], [15.0, 20.0]]
    );
    let arcs = format!(
        "{head}G00 X-20. Y0. Z0.\nG41 D1 G01 X0. F1000.\nX30.\nG03 X40. Y10. R10.\nG01 Y30.\nG02 X50. Y40. R10.\nG01 X70.\nG40 X90.\nM30\n"
    );
    let got = ends(&arcs);
    let want = [[0.0, 5.0], [30.0, 5.0], [35.0, 10.0], [35.0, 30.0], [50.0, 45.0], [70.0, 45.0], [90.0, 40.0]];
    assert!(got.iter().zip(&want).all(|(g, w)| approx(g[0], w[0]) && approx(g[1], w[1])) && got.len() == 7, "{got:?}");
}

#[test]
fn a_g40_without_motion_then_g41_cancels_and_starts_up_again() {
    // Block 4 cancels without moving: block 3 ends at its perpendicular vector (20,5); block 5
    // starts up again from the programmed 20,0 (type A, inside corner with block 6: 25,5).
    let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40\nG41 X30.\nY20.\nG40 X50.\nM30\n";
    assert_ends(
        src,
        &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (5, 25.0, 5.0), (6, 25.0, 20.0), (7, 50.0, 20.0)],
    );
}

#[test]
fn a_helix_is_compensated_in_its_plane_only() {
    // The boss circle as a helix down 5: X/Y as for the circle, Z as programmed.
    let src = "G90 G00 X-20. Y0. Z0\nG41 D1 G01 X-10. F500\nG02 I10. Z-5.\nG40 G01 X-20.\nM30\n";
    let x = -(15.0f64 * 15.0 - 25.0).sqrt();
    assert_ends(src, &[(1, -20.0, 0.0), (2, x, 5.0), (3, x, -5.0), (4, -20.0, 0.0)]);
    let (ends, _) = centre_axes(src, Fanuc, (2, 0));
    assert_eq!(ends.iter().map(|(_, p)| p[0]).collect::<Vec<_>>(), [0.0, 0.0, -5.0, -5.0]);
}

#[test]
fn an_arc_into_an_outer_acute_corner_ends_on_its_circle_then_the_lengthened_vectors() {
    // A "D": the quarter circle R10 counter-clockwise from (10,0) to (0,10), then the chord
    // back; G42 keeps the tool outside (circle radius 15, chord offset toward the origin).
    // At (0,10) the turn is acute: the arc ends at its own vector (0,15), then (0,15) + 5·t1 =
    // (−5,15), then (0,10) + 5·n2 − 5·t2 = (−5√2, 10).
    let src = "G90 G00 X20. Y0 Z0\nG42 D1 G01 X10. F500\nG03 X0. Y10. R10.\nG01 X10. Y0.\nG40 X20.\nM30\n";
    let h = 50f64.sqrt() / 2.0;
    assert_ends(
        src,
        &[
            (1, 20.0, 0.0),
            (2, 200f64.sqrt(), 5.0),
            (3, 0.0, 15.0),
            (3, -5.0, 15.0),
            (3, -50f64.sqrt(), 10.0),
            (4, 10.0 - h, -h),
            (5, 20.0, 0.0),
        ],
    );
}

/// An arc's centre X/Y and signed sweep in degrees.
type ArcOf = ([f64; 2], f64);

/// Every motion out of the stages (FANUC, mill3): line, end X/Y, and the arc if it is one.
fn motions(src: &str) -> Vec<(u32, [f64; 2], Option<ArcOf>)> {
    let mut interp = interpreter(src, "mill3", Fanuc);
    let mut stages = Pipeline::for_config(interp.config());
    let mut out = Vec::new();
    let mut seen = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let end = !matches!(step, Ok(Step::Continue | Step::NeedInput));
        assert_eq!(stages.process(&mut out, end), None, "{src}");
        for c in out.drain(..) {
            if let CanonKind::Motion(m) = c.kind {
                let arc = m.arc.map(|a| ([a.center[0], a.center[1]], a.sweep_deg));
                seen.push((c.line, [m.target[0], m.target[1]], arc));
            }
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            _ => return seen,
        }
    }
}

mod corner_arc {
    //! G39 corner circular interpolation (FANUC 15i §14.4.9).

    use super::*;

    #[test]
    fn g39_without_ijk_ends_perpendicular_to_the_next_block() {
        // G42 R5, +Y into (0,0) (inside corner with +X: 5,−5), then +X to 20,0, G39, +Y to
        // 20,20, cancel +X to 30,20 (inside corner: 25,15). Block 3 ends at its own vector:
        // right of +X is (0,−5): 20,−5. G39: the new vector is perpendicular to block 5 at its
        // start, right of +Y: (5,0), so 25,0; the arc turns about 20,0 from −90° to 0°,
        // counter-clockwise for G42: +90°. Block 5 runs from 25,0 up x = 25.
        let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nG39\nY20.\nG40 X30.\nM30\n";
        assert_ends(
            src,
            &[(1, 0.0, -10.0), (2, 5.0, -5.0), (3, 20.0, -5.0), (4, 25.0, 0.0), (5, 25.0, 15.0), (6, 30.0, 20.0)],
        );
        let arc = motions(src).into_iter().find(|m| m.0 == 4).unwrap().2.expect("an arc");
        assert!(approx(arc.0[0], 20.0) && approx(arc.0[1], 0.0) && approx(arc.1, 90.0), "{arc:?}");
    }

    #[test]
    fn g39_turns_clockwise_under_g41() {
        // G41 R5, −Y into (0,0), +X to 20,0 (left of +X: (0,5)), G39, −Y to 20,−20, cancel +X.
        // Old vector (0,5) at 90°, new: left of −Y is (5,0) at 0°: clockwise −90° about 20,0.
        // Block 5 ends at the inside corner with the cancel: x = 25, y = −20 + 5.
        let src = "G90 G00 X0. Y10. Z0\nG41 D1 G01 Y0. F500\nX20.\nG39\nY-20.\nG40 X30.\nM30\n";
        assert_ends(
            src,
            &[(1, 0.0, 10.0), (2, 5.0, 5.0), (3, 20.0, 5.0), (4, 25.0, 0.0), (5, 25.0, -15.0), (6, 30.0, -20.0)],
        );
        let arc = motions(src).into_iter().find(|m| m.0 == 4).unwrap().2.expect("an arc");
        assert!(approx(arc.0[0], 20.0) && approx(arc.0[1], 0.0) && approx(arc.1, -90.0), "{arc:?}");
    }

    #[test]
    fn g39_with_ij_ends_perpendicular_to_their_direction() {
        // As the first, with G39 I1. J1.: the new vector is right of (1,1)/√2 by 5:
        // (5/√2, −5/√2), at −45°: the arc turns +45° from −90°. Block 5 starts there and ends
        // at the inside corner with the cancel, 25,15, as before.
        let h = 5.0 / 2f64.sqrt();
        let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nG39 I1. J1.\nY20.\nG40 X30.\nM30\n";
        assert_ends(
            src,
            &[(1, 0.0, -10.0), (2, 5.0, -5.0), (3, 20.0, -5.0), (4, 20.0 + h, -h), (5, 25.0, 15.0), (6, 30.0, 20.0)],
        );
        let arc = motions(src).into_iter().find(|m| m.0 == 4).unwrap().2.expect("an arc");
        assert!(approx(arc.1, 45.0), "{arc:?}");
    }

    #[test]
    fn g39_keeps_a_move_out_of_the_plane_behind_it() {
        // A Z move between G39 and the next block: it runs after the arc, at the new vector.
        let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nG39\nZ-1.\nY20.\nG40 X30.\nM30\n";
        assert_ends(
            src,
            &[
                (1, 0.0, -10.0),
                (2, 5.0, -5.0),
                (3, 20.0, -5.0),
                (4, 25.0, 0.0),
                (5, 25.0, 0.0),
                (6, 25.0, 15.0),
                (7, 30.0, 20.0),
            ],
        );
    }

    #[test]
    fn g39_alarms() {
        let cases = [
            // Not in offset mode: PS0010 / COR-070 at the G39 block.
            ("G90 G00 X0. Y0. Z0\nG01 X10. F500\nG39\nM30\n", 3, ("PS0010", "COR-070")),
            // In the block that turns compensation on.
            ("G90 G00 X0. Y0. Z0\nG41 D1 G39\nG01 X10. F500\nM30\n", 2, ("PS0010", "COR-070")),
            // A move command in the G39 block: PS0273.
            ("G90 G00 X0. Y0. Z0\nG41 D1 G01 X10. F500\nG39 X20.\nM30\n", 3, ("PS0273", "COR-100")),
            // G41 given, but no block in offset mode before the corner.
            ("G90 G00 X0. Y0. Z0 F500\nG41 D1\nG39\nG01 X10.\nM30\n", 3, ("PS0010", "COR-070")),
            // No block after it in the plane: its arc has no end (PS0033 at the G39).
            ("G90 G00 X0. Y0. Z0\nG41 D1 G01 X10. F500\nG39\nM30\n", 3, ("PS0033", "COR-100")),
            ("G90 G00 X0. Y0. Z0\nG41 D1 G01 X10. F500\nG39\nG40 Z5.\nM30\n", 3, ("PS0033", "COR-100")),
        ];
        for (src, line, (fanuc, syntec)) in cases {
            for (dialect, code) in [(Fanuc, fanuc), (Syntec, syntec)] {
                let r = run_with(src, "mill3", dialect);
                assert_eq!(r.alarms.len(), 1, "{dialect:?} {src}");
                assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, line), "{dialect:?} {src}");
            }
        }
    }
}

mod cancel_direction {
    //! G40 with I/J/K: the block before the cancel ends where its offset path meets the line
    //! along (I, J) from its programmed end, offset to the same side.

    use super::*;

    #[test]
    fn at_an_outside_corner_the_block_before_runs_on_to_the_intersection() {
        // G41 R5 along +X, y = 5 offset. The cancel turns right (outside for G41); type A would
        // end block 3 at its perpendicular vector 20,5. With I0 J-1: the line from 20,0 along
        // −Y, offset to its left (left of −Y is +X) by 5: x = 25; it meets y = 5 at 25,5.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 X30. Y-10. I0 J-1.\nM30\n";
        assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 25.0, 5.0), (4, 30.0, -10.0)]);
        // Without I/J: type A.
        let plain = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 X30. Y-10.\nM30\n";
        assert_ends(plain, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 30.0, -10.0)]);
    }

    #[test]
    fn at_an_inside_corner_the_line_of_ij_decides_not_the_cancel_block() {
        // I-1. J1.: the line x + y = 20 through 20,0, offset to the left of (−1,1)/√2 (toward
        // (−1,−1)/√2) by 5: x + y = 20 − 5√2; with y = 5: x = 15 − 5√2. The cancel block goes
        // to 10,10 (its own offset line would give another point: the I/J line decides).
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 X10. Y10. I-1. J1.\nM30\n";
        let x = 15.0 - 5.0 * 2f64.sqrt();
        assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, x, 5.0), (4, 10.0, 10.0)]);
    }

    #[test]
    fn a_g40_with_ij_and_no_move_goes_to_the_intersection_then_removes_the_vector() {
        // The G40 I0 J-1. block moves to where it stands: 25,5 (as above), then 20,0.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 I0 J-1.\nG00 X50.\nM30\n";
        assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 25.0, 5.0), (4, 20.0, 0.0), (5, 50.0, 0.0)]);
    }

    #[test]
    fn parallel_ij_leaves_the_perpendicular_vector() {
        // I1. J0 along the block before: no intersection; block 3 ends at 20,5.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 X30. Y-10. I1. J0\nM30\n";
        assert_ends(src, &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 30.0, -10.0)]);
    }

    #[test]
    fn after_an_arc_the_line_meets_its_offset_circle() {
        // G42 R5, a counter-clockwise quarter circle R10 about the origin from 10,0 to 0,10
        // (the tool right of it is outside: radius 15), then G40 X-10. Y10. I-1. J0: the line
        // y = 10 offset to the right of −X (toward +Y) by 5: y = 15, meets the circle of
        // radius 15 at 0,15 (tangent: the crossing nearest the corner).
        let src = "G90 G00 X20. Y0 Z0\nG42 D1 G01 X10. F500\nG03 X0. Y10. R10.\nG40 G01 X-10. Y10. I-1. J0\nM30\n";
        let got = centre(src, Fanuc);
        assert_eq!(got.1, None);
        let (line, p) = got.0[2];
        assert_eq!(line, 3);
        assert!(p[0].abs() < 1e-3 && approx(p[1], 15.0), "{p:?}");
    }
}

mod type_b {
    //! Start-up and cancel type B (FANUC No.5003#0 SUP = 1): at an outside corner the start-up
    //! block ends perpendicular to itself and the cancel block starts perpendicular to itself,
    //! the corner's own vectors between.

    use super::*;

    /// Motion ends with type B on mill3 (FANUC).
    #[track_caller]
    fn assert_ends_b(src: &str, want: &[(u32, f64, f64)]) {
        let interp =
            interpreter_with(src, "mill3", Fanuc, |c| c.edit_machine(|m| m.motion.cutter_startup_type_b = true));
        assert_centre(centre_of(interp, (0, 1)), src, want);
    }

    #[test]
    fn at_right_angle_outside_corners_the_intersection_comes_after_the_perpendicular_vectors() {
        // G41 R5: +Y into 0,0, +X to 20,0, cancel −Y to 20,−10. Both corners turn right, outside
        // for the tool on the left, α = 90° (the intersection rule). Start-up: its own vector,
        // left of +Y: −5,0; then the intersection of x = −5 and y = 5: −5,5. Cancel: the
        // intersection of y = 5 and x = 25 (left of −Y is +X): 25,5; then the cancel block's own
        // vector at its start: 25,0; then its programmed end.
        let src = "G90 G00 X0. Y-10. Z0\nG41 D1 G01 Y0. F500\nX20.\nG40 Y-10.\nM30\n";
        assert_ends_b(
            src,
            &[(1, 0.0, -10.0), (2, -5.0, 0.0), (2, -5.0, 5.0), (3, 25.0, 5.0), (3, 25.0, 0.0), (4, 20.0, -10.0)],
        );
        // Type A (the default): perpendicular to the next block / to the block before.
        assert_ends(src, &[(1, 0.0, -10.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 20.0, -10.0)]);
    }

    #[test]
    fn at_an_acute_start_up_the_lengthened_vectors_follow_its_own() {
        // G41 R5: +Y into 0,0, then toward 10,−10: t2 = (1,−1)/√2, a right turn (outside), acute.
        // Start-up: −5,0 (its own vector), −5,5 (lengthened by 5 along +Y), then
        // 5·n2 − 5·t2 with n2 = (1,1)/√2: (0, 5√2). Block 3 meets block 4 (+X) inside: its
        // offset line x + y = 5√2 and y = −5: 5 + 5√2, −5. Block 4 runs in line into the
        // cancel: 30,−5; the cancel to 40,−10.
        let s2 = 2f64.sqrt();
        let src = "G90 G00 X0. Y-10. Z0\nG41 D1 G01 Y0. F500\nX10. Y-10.\nX30.\nG40 X40.\nM30\n";
        assert_ends_b(
            src,
            &[
                (1, 0.0, -10.0),
                (2, -5.0, 0.0),
                (2, -5.0, 5.0),
                (2, 0.0, 5.0 * s2),
                (3, 5.0 + 5.0 * s2, -5.0),
                (4, 30.0, -5.0),
                (5, 40.0, -10.0),
            ],
        );
        // Type A ends the start-up block at 5·n2 instead.
        let h = 5.0 / s2;
        assert_ends(src, &[(1, 0.0, -10.0), (2, h, h), (3, 5.0 + 5.0 * s2, -5.0), (4, 30.0, -5.0), (5, 40.0, -10.0)]);
    }

    #[test]
    fn at_an_acute_cancel_its_own_vector_comes_after_the_lengthened_ones() {
        // G41 R5 along +X at y = 5, cancel toward 10,−10: t2 = (−1,−1)/√2, right turn, acute.
        // 20,5 + 5·(1,0) = 25,5; 5·n2 − 5·t2 with n2 = (1,−1)/√2: 20 + 5√2, 0; then the cancel
        // block's own vector 20 + 5/√2, −5/√2; then 10,−10. (The start-up runs in line: 0,5.)
        let s2 = 2f64.sqrt();
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG40 X10. Y-10.\nM30\n";
        assert_ends_b(
            src,
            &[
                (1, -10.0, 0.0),
                (2, 0.0, 5.0),
                (3, 25.0, 5.0),
                (3, 20.0 + 5.0 * s2, 0.0),
                (3, 20.0 + 5.0 / s2, -5.0 / s2),
                (4, 10.0, -10.0),
            ],
        );
    }

    #[test]
    fn inside_corners_are_the_same_as_type_a() {
        // The pocket of `inside_of_a_pocket_g41_counter_clockwise`: every corner inside.
        let src = "G90 G00 X20. Y10. Z0\nG41 D1 G01 Y0. F500\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y10.\nM30\n";
        let want = [
            (1, 20.0, 10.0),
            (2, 25.0, 5.0),
            (3, 35.0, 5.0),
            (4, 35.0, 35.0),
            (5, 5.0, 35.0),
            (6, 5.0, 5.0),
            (7, 15.0, 5.0),
            (8, 20.0, 10.0),
        ];
        assert_ends_b(src, &want);
        assert_ends(src, &want);
    }
}

mod vector_hold {
    //! G38 vector hold (NCT 99M/2000M §14.5.5, Mitsubishi M700V §12.4): the G38 block ends at
    //! its programmed point plus the vector where it starts (or the offset value along I/J),
    //! with no corner to the block after it.

    use super::*;

    #[test]
    fn the_g38_block_keeps_the_vector_of_the_corner_before_it() {
        // G41 R5. Block 3 (+X, y = 5) meets block 4 (+Y, offset x = 15) inside: 15,5. Block 4
        // (G38) holds (15,5) − (20,0) = (−5,5): it ends at 20,10 + (−5,5) = 15,15. Block 5 runs
        // from there toward 30,20 along (1,1)/√2; it meets the cancel (+X) outside at 45°:
        // type A, its perpendicular vector, left of (1,1)/√2 by 5: 30 − h, 20 + h, h = 5/√2.
        // (Without G38 block 4 would end where x = 15 meets block 5's offset line, 15, 5 + 5√2.)
        let h = 5.0 / 2f64.sqrt();
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG38 Y10.\nX30. Y20.\nG40 X40.\nM30\n";
        assert_ends(
            src,
            &[
                (1, -10.0, 0.0),
                (2, 0.0, 5.0),
                (3, 15.0, 5.0),
                (4, 15.0, 15.0),
                (5, 30.0 - h, 20.0 + h),
                (6, 40.0, 20.0),
            ],
        );
        let plain = src.replace("G38 ", "");
        assert_ends(
            &plain,
            &[
                (1, -10.0, 0.0),
                (2, 0.0, 5.0),
                (3, 15.0, 5.0),
                (4, 15.0, 5.0 + 5.0 * 2f64.sqrt()),
                (5, 30.0 - h, 20.0 + h),
                (6, 40.0, 20.0),
            ],
        );
    }

    #[test]
    fn g38_with_ij_ends_at_the_offset_value_along_them() {
        // As above, G38 Y10. I-1. J1.: the vector is 5·(−1,1)/√2 = (−h, h): block 4 ends at
        // 20 − h, 10 + h; block 5 starts there and ends as before.
        let h = 5.0 / 2f64.sqrt();
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG38 Y10. I-1. J1.\nX30. Y20.\nG40 X40.\nM30\n";
        assert_ends(
            src,
            &[
                (1, -10.0, 0.0),
                (2, 0.0, 5.0),
                (3, 15.0, 5.0),
                (4, 20.0 - h, 10.0 + h),
                (5, 30.0 - h, 20.0 + h),
                (6, 40.0, 20.0),
            ],
        );
    }

    #[test]
    fn consecutive_g38_blocks_step_over_with_the_same_vector() {
        // G42 R5: block 3 (+X, y = −5) meets block 4 (+Y, x = 25) outside at 90°: 25,−5, vector
        // (5,−5). Blocks 4–6 hold it: 20,10 → 25,5; 30,10 → 35,5; 30,0 → 35,−5. Block 7 (+X)
        // starts there and meets the cancel in line: 50,−5; the cancel ends at 60,0.
        let src = "G90 G00 X-10. Y0 Z0\nG42 D1 G01 X0. F500\nX20.\nG38 Y10.\nG38 X30.\nG38 Y0\nX50.\nG40 X60.\nM30\n";
        assert_ends(
            src,
            &[
                (1, -10.0, 0.0),
                (2, 0.0, -5.0),
                (3, 25.0, -5.0),
                (4, 25.0, 5.0),
                (5, 35.0, 5.0),
                (6, 35.0, -5.0),
                (7, 50.0, -5.0),
                (8, 60.0, 0.0),
            ],
        );
    }

    #[test]
    fn g38_with_ij_and_no_move_changes_the_vector_where_it_stands() {
        // G41 R5: block 3 ends at its perpendicular vector 20,5; G38 I1. J0 moves to 20,0 +
        // (5,0) = 25,0. Block 5 (+Y) starts there and meets the cancel (−X) inside: x = 15,
        // y = 20 − 5 = 15.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG38 I1. J0\nY20.\nG40 X10.\nM30\n";
        assert_ends(
            src,
            &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 20.0, 5.0), (4, 25.0, 0.0), (5, 15.0, 15.0), (6, 10.0, 20.0)],
        );
    }

    #[test]
    fn g38_out_of_the_plane_keeps_the_corner() {
        // G38 Z-1. between two blocks is a block without motion in the plane: the corner 15,5.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nG38 Z-1.\nY20.\nG40 X10.\nM30\n";
        assert_ends(
            src,
            &[(1, -10.0, 0.0), (2, 0.0, 5.0), (3, 15.0, 5.0), (4, 15.0, 5.0), (5, 15.0, 15.0), (6, 10.0, 20.0)],
        );
    }

    #[test]
    fn g38_alarms() {
        let cases = [
            // Not in offset mode: PS0010 / COR-070 at the G38 block.
            ("G90 G00 X0. Y0. Z0\nG01 X10. F500\nG38 X20.\nM30\n", 3),
            // In the block that turns compensation on.
            ("G90 G00 X0. Y0. Z0\nG41 D1 G38 G01 X10. F500\nX20.\nG40 X30.\nM30\n", 2),
            // In G02/G03.
            ("G90 G00 X0. Y0. Z0\nG41 D1 G01 X10. F500\nG38 G02 X20. R5.\nG40 G01 X30.\nM30\n", 3),
            // G41 given, but no block has moved in offset mode: no vector to hold.
            ("G90 G00 X0. Y0. Z0 F500\nG41 D1\nG38 G01 X10.\nX20.\nG40 X30.\nM30\n", 3),
        ];
        for (src, line) in cases {
            for (dialect, code) in [(Fanuc, "PS0010"), (Syntec, "COR-070")] {
                let r = run_with(src, "mill3", dialect);
                assert_eq!(r.alarms.len(), 1, "{dialect:?} {src}");
                assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, line), "{dialect:?} {src}");
            }
        }
    }
}

mod perpendicular {
    //! Start-up and cancel "perpendicular to the next movement" (FANUC No.5003#1 SUV = 1,
    //! `motion.cutter_startup_perpendicular`): a G41/G42 block in G00/G01 without an axis word
    //! of the plane is followed by a straight move of the offset value perpendicular to the next
    //! block at its start; a G40 block in G00/G01 without an axis word moves straight back from
    //! the vector perpendicular to the block before. Blocks that move in the plane fall back to
    //! type A (SUP = 0) or B (SUP = 1).

    use super::*;

    /// Motion ends with SUV (and SUP = `type_b`) on mill3 (FANUC).
    fn ends_c(src: &str, type_b: bool) -> Centre {
        let interp = interpreter_with(src, "mill3", Fanuc, |c| {
            c.edit_machine(|m| {
                m.motion.cutter_startup_perpendicular = true;
                m.motion.cutter_startup_type_b = type_b;
            })
        });
        centre_of(interp, (0, 1))
    }

    #[test]
    fn a_start_up_from_a_point_moves_perpendicular_to_the_next_block_first() {
        // G41 R5 at 0,−10 with no move; the next block goes +Y to 0,0: left of +Y is −X, so the
        // inserted block (line 2) moves to −5,−10. Block 3 then runs in offset mode: the corner
        // with +X (turning right, outside for the tool on the left, 90°) is the intersection of
        // x = −5 and y = 5: −5,5. Block 4 ends at its perpendicular vector 20,5 (the G40 block
        // does not move), and the G40 block (line 5) moves straight back to 20,0; the rapid to
        // 20,−10 is uncompensated. Type A would end block 3 at 0,5 (perpendicular to block 4).
        let src = "G90 G00 X0. Y-10. Z0\nG41 D1 G01 F500\nY0.\nX20.\nG40\nG00 Y-10.\nM30\n";
        let want =
            [(1, 0.0, -10.0), (2, -5.0, -10.0), (3, -5.0, 5.0), (4, 20.0, 5.0), (5, 20.0, 0.0), (6, 20.0, -10.0)];
        assert_centre(ends_c(src, false), src, &want);
        assert_centre(ends_c(src, true), src, &want);
        // Without SUV the same program starts up by type A at block 3, and the G40 block does
        // not move: the rapid of line 6 removes the vector.
        assert_ends(src, &[(1, 0.0, -10.0), (3, 0.0, 5.0), (4, 20.0, 5.0), (6, 20.0, -10.0)]);
    }

    #[test]
    fn an_arc_may_follow_the_start_up_block() {
        // G41 R5 at 10,0; then a counter-clockwise half circle R10 about 0,0 to −10,0 (left of
        // counter-clockwise travel is toward the centre: offset radius 5). Inserted: 10,0 moved
        // left of the arc's start tangent (0,1), to 5,0. The arc ends where it meets the next
        // block, −Y from −10,0 (tangent: the offsets meet at −5,0); that block ends at its
        // perpendicular vector −5,−10 and the G40 block moves back to −10,−10. Without SUV the
        // arc would be the start-up block: PS0034.
        let src = "G90 G00 X10. Y0 Z0\nG41 D1 G01 F500\nG03 X-10. Y0 R10.\nG01 Y-10.\nG40\nM30\n";
        let want = [(1, 10.0, 0.0), (2, 5.0, 0.0), (3, -5.0, 0.0), (4, -5.0, -10.0), (5, -10.0, -10.0)];
        assert_centre(ends_c(src, false), src, &want);
        let (_, alarm) = centre(src, Fanuc);
        assert_eq!(alarm, Some(("PS0034".to_string(), 3)));
    }

    #[test]
    fn a_move_out_of_the_plane_in_the_start_up_block_comes_first() {
        // G41 D1 Z−1.: Z goes down at 0,−10 uncompensated; the inserted move comes before the
        // next block in the plane, and is of the G41 block (line 2).
        let src = "G90 G00 X0. Y-10. Z0\nG41 D1 G01 Z-1. F500\nY0.\nX20.\nG40\nM30\n";
        let want = [(1, 0.0, -10.0), (2, 0.0, -10.0), (2, -5.0, -10.0), (3, -5.0, 5.0), (4, 20.0, 5.0), (5, 20.0, 0.0)];
        assert_centre(ends_c(src, false), src, &want);
    }

    #[test]
    fn start_up_and_cancel_blocks_that_move_fall_back_to_type_a_or_b() {
        // The outside square of `outside_of_a_square_g42_counter_clockwise`: its G42 and G40
        // blocks move in the plane, so SUV changes nothing (type A); with SUP = 1 it is type B.
        let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n";
        let a = [
            (1, 0.0, -10.0),
            (2, 5.0, -5.0),
            (3, 25.0, -5.0),
            (4, 25.0, 25.0),
            (5, -5.0, 25.0),
            (6, -5.0, 0.0),
            (7, 0.0, -10.0),
        ];
        assert_centre(ends_c(src, false), src, &a);
        let b_machine =
            interpreter_with(src, "mill3", Fanuc, |c| c.edit_machine(|m| m.motion.cutter_startup_type_b = true));
        let (b, alarm) = centre_of(b_machine, (0, 1));
        assert_eq!(alarm, None);
        assert_eq!(ends_c(src, true), (b, None));
    }

    #[test]
    fn blocks_that_move_or_are_in_g02_mode_are_not_perpendicular() {
        // The G40 block with X moves in the plane: type A (the block before ends at 20,5, outside).
        let src = "G90 G00 X0. Y-10. Z0\nG41 D1 G01 F500\nY0.\nX20.\nG40 X30.\nM30\n";
        assert_centre(
            ends_c(src, false),
            src,
            &[(1, 0.0, -10.0), (2, -5.0, -10.0), (3, -5.0, 5.0), (4, 20.0, 5.0), (5, 30.0, 0.0)],
        );
        // A G41 block in G02 mode without a move: the next G01 block is an ordinary start-up.
        let src = "G90 G00 X0. Y-10. Z0\nG02 G41 D1 F500\nG01 Y0.\nX20.\nG40 X30.\nM30\n";
        assert_centre(ends_c(src, false), src, &[(1, 0.0, -10.0), (3, 0.0, 5.0), (4, 20.0, 5.0), (5, 30.0, 0.0)]);
    }

    #[test]
    fn d0_inserts_nothing() {
        let src = "G90 G00 X0. Y-10. Z0\nG41 D0 G01 F500\nY0.\nX20.\nG40\nM30\n";
        assert_centre(ends_c(src, false), src, &[(1, 0.0, -10.0), (3, 0.0, 0.0), (4, 20.0, 0.0), (5, 20.0, 0.0)]);
    }
}

mod avoidance {
    //! Interference avoidance (FANUC No.19607#5 CAV = 1, `motion.cutter_interference_avoidance`;
    //! FANUC 30i B-63944EN-1/02 §5): an interfering block gets no vector of its own; the block
    //! before it ends where its offset path crosses that of the block after it. No crossing:
    //! PS0041 at the block before, which does not move.

    use super::*;

    /// Where the offset lines (G41, radius `r`) of the programmed lines `a1`→`b1` and `a2`→`b2`
    /// meet.
    fn meet(r: f64, [a1, b1]: [[f64; 2]; 2], [a2, b2]: [[f64; 2]; 2]) -> [f64; 2] {
        let offset = |a: [f64; 2], b: [f64; 2]| {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy);
            ([a[0] - r * dy / l, a[1] + r * dx / l], [dx / l, dy / l])
        };
        let ((p, d), (q, e)) = (offset(a1, b1), offset(a2, b2));
        let t = ((q[0] - p[0]) * e[1] - (q[1] - p[1]) * e[0]) / (d[0] * e[1] - d[1] * e[0]);
        [p[0] + t * d[0], p[1] + t * d[1]]
    }

    fn ends_avoiding(src: &str) -> Centre {
        let interp = interpreter_with(src, "mill3", Fanuc, |c| {
            c.edit_machine(|m| m.motion.cutter_interference_avoidance = true)
        });
        centre_of(interp, (0, 1))
    }

    /// A dip smaller than the tool: +X to 20,0, down-right to 21,−1, up-right at 45° to 31,9,
    /// +X to 40,9; G41 R5 (the tool above).
    const DIP: &str = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-1.\nX31. Y9.\nX40.\nG40 X50.\nM30\n";

    #[test]
    fn a_dip_smaller_than_the_tool_is_avoided() {
        // Offset paths: block 3 y = 5; block 4 (direction (1,−1)/√2, left normal (1,1)/√2)
        // x + y = 20 + 5√2; block 5 (direction (1,1)/√2, left normal (−1,1)/√2)
        // y − x = −22 + 5√2; block 6 y = 14. Corner 3/4 (outside, obtuse): y = 5 on block 4's
        // path, x = 15 + 5√2 = 22.071; corner 4/5 (inside): x = 21, y = −1 + 5√2 = 6.071, so
        // block 4 would run from 22.071,5 to 21,6.071, against its programmed (1,−1): PS0041.
        // Avoidance: block 3 ends where y = 5 meets block 5's path, x = 27 − 5√2 = 19.929;
        // block 4 stays there; block 5 runs to y = 14 at x = 36 − 5√2 = 28.929; block 6 ends
        // at 40,14 (in line with the cancel), the cancel goes to 50,9.
        let s = 5.0 * 2f64.sqrt();
        let want = [
            (1, -10.0, 0.0),
            (2, 0.0, 5.0),
            (3, 27.0 - s, 5.0),
            (4, 27.0 - s, 5.0),
            (5, 36.0 - s, 14.0),
            (6, 40.0, 14.0),
            (7, 50.0, 9.0),
        ];
        assert_centre(ends_avoiding(DIP), DIP, &want);
        // Without avoidance: PS0041 at block 4, the tool stops at the end of block 3.
        assert_stops_at_block_3_without_avoidance(DIP, 15.0 + s);
    }

    /// Without avoidance: PS0041 at block 4, the last motion block 3's, ending at X `x`.
    #[track_caller]
    fn assert_stops_at_block_3_without_avoidance(src: &str, x: f64) {
        let (ends, alarm) = centre(src, Fanuc);
        assert_eq!(alarm, Some(("PS0041".to_string(), 4)));
        assert_eq!(ends.last().map(|e| e.0), Some(3));
        assert!(approx(ends.last().unwrap().1[0], x));
    }

    #[test]
    fn a_groove_with_parallel_walls_has_no_avoidance_point() {
        // The `crc_interference` groove: 4 wide, 2 deep, tool 10. Block 5 (the bottom) would run
        // backwards; the walls' offset paths x = 25 and x = 19 are parallel: no avoidance point,
        // PS0041 at block 4 (the wall before, FANUC 30i: "an alarm will occur immediately before
        // block 1"), which does not move: the tool stops at the end of block 3, 25,5.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F1000.\nX20.\nY-2.\nX24.\nY0.\nX40.\nG40 X50.\nM30\n";
        let (ends, alarm) = ends_avoiding(src);
        assert_eq!(alarm, Some(("PS0041".to_string(), 4)));
        assert_eq!(ends, vec![(1, [-10.0, 0.0]), (2, [0.0, 5.0]), (3, [25.0, 5.0])]);
        let (ends, alarm) = centre(src, Fanuc);
        assert_eq!(alarm, Some(("PS0041".to_string(), 5)));
        assert_eq!(ends.last(), Some(&(4, [25.0, 3.0])));
    }

    /// A dip of two short blocks (G41 R5): +X to 20,0, down-right to 21,−1, right and up to
    /// 22,−0.5, up at 45° to 32,9.5, +X to 40,9.5.
    const TWO: &str =
        "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-1.\nX22. Y-0.5\nX32. Y9.5\nX40.\nG40 X50.\nM30\n";

    #[test]
    fn two_consecutive_interfering_blocks_share_one_avoidance_vector() {
        // Offset paths: block 3 y = 5; block 4 x + y = 20 + 5√2; block 5 (direction (2,1)/√5,
        // left normal (−1,2)/√5) −x + 2y = −23 + 5√5; block 6 y − x = −22.5 + 5√2; block 7
        // y = 14.5. Corner 3/4 (outside, obtuse): x = 15 + 5√2 = 22.071; corner 4/5 (inside):
        // 3y = −3 + 5√2 + 5√5, y = 5.084, x = 21.987: block 4 runs back (−0.084, 0.084) against
        // (1,−1) — it interferes. The avoidance vector for it, block 3 meeting block 5, is
        // x = 33 − 5√5 = 21.820, y = 5; block 5 would start there and end at corner 5/6
        // (inside): y = −0.5 + 5√5 − 5√2 = 3.609, x = 19.038 — back against (2,1): block 5
        // interferes too. Two consecutive: the avoidance vector is where block 3 meets block 6
        // (CRC-41, "between the last good block and the next good block"): x = 27.5 − 5√2 =
        // 20.429, y = 5. Blocks 4 and 5 stay there; block 6 ends at corner 6/7 (outside):
        // y = 14.5, x = 37 − 5√2 = 29.929; block 7 at 40,14.5 (in line with the cancel).
        let s = 5.0 * 2f64.sqrt();
        assert!(approx(
            meet(5.0, [[0.0, 0.0], [20.0, 0.0]], [[21.0, -1.0], [22.0, -0.5]])[0],
            33.0 - 5.0 * 5f64.sqrt()
        ));
        let want = [
            (1, -10.0, 0.0),
            (2, 0.0, 5.0),
            (3, 27.5 - s, 5.0),
            (4, 27.5 - s, 5.0),
            (5, 27.5 - s, 5.0),
            (6, 37.0 - s, 14.5),
            (7, 40.0, 14.5),
            (8, 50.0, 9.5),
        ];
        assert_centre(ends_avoiding(TWO), TWO, &want);
        // Without avoidance: PS0041 at block 4, block 3 ends at its own corner.
        assert_stops_at_block_3_without_avoidance(TWO, 15.0 + s);
    }

    #[test]
    fn two_interfering_blocks_before_a_parallel_one_have_no_avoidance_point() {
        // `TWO`'s first three blocks, then +X at y = −0.5 to 40: block 4 interferes as there;
        // block 5 from the avoidance point 33 − 5√5 = 21.820, 5 to corner 5/6 (outside, obtuse:
        // −x + 2y = −23 + 5√5 meets y = 4.5 at x = 32 − 5√5 = 20.820) runs back against (2,1):
        // two consecutive. Block 3's offset path y = 5 and block 6's y = 4.5 are parallel: no
        // avoidance vector, PS0041 at block 3, which does not move (FANUC 30i: "an alarm will
        // occur immediately before block 1").
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-1.\nX22. Y-0.5\nX40.\nG40 X50.\nM30\n";
        let (b3, b5, b6) = ([[0.0, 0.0], [20.0, 0.0]], [[21.0, -1.0], [22.0, -0.5]], [[22.0, -0.5], [40.0, -0.5]]);
        let (va, c56) = (meet(5.0, b3, b5), meet(5.0, b5, b6));
        assert!(approx(c56[0], 32.0 - 5.0 * 5f64.sqrt()) && approx(c56[1], 4.5));
        assert!((c56[0] - va[0]) * 2.0 + (c56[1] - va[1]) < 0.0);
        let (ends, alarm) = ends_avoiding(src);
        assert_eq!(alarm, Some(("PS0041".to_string(), 3)));
        assert_eq!(ends, vec![(1, [-10.0, 0.0]), (2, [0.0, 5.0])]);
    }

    #[test]
    fn three_consecutive_interfering_blocks_stop_before_the_first() {
        // `TWO` with a third short block, right to 23,−0.3, before the climb to 33,10. Block 4
        // interferes as there; block 5 from the avoidance point 21.820,5 (block 3 meeting block
        // 5) to corner 5/6 (inside) 20.363,4.272 runs back against (2,1); block 6 (direction
        // (5,1)/√26, offset −x + 5y = −24.5 + 5√26) from the avoidance point 24.005,5 (block 3
        // meeting block 6) to corner 6/7 (inside) 20.495,4.298 runs back against (5,1): three
        // consecutive interfering blocks, no avoidance vector (CRC-42). The control overcuts
        // without an alarm; fivex stops before the first interfering block (rule 9's decision):
        // PS0041 at block 4, block 3 ends at its own corner 15 + 5√2, 5 — as without avoidance.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-1.\nX22. Y-0.5\nX23. Y-0.3\nX33. Y10.\nX40.\nG40 X50.\nM30\n";
        let (b3, b5, b6, b7) = (
            [[0.0, 0.0], [20.0, 0.0]],
            [[21.0, -1.0], [22.0, -0.5]],
            [[22.0, -0.5], [23.0, -0.3]],
            [[23.0, -0.3], [33.0, 10.0]],
        );
        let (va, c56) = (meet(5.0, b3, b5), meet(5.0, b5, b6));
        assert!((c56[0] - va[0]) * 2.0 + (c56[1] - va[1]) < 0.0);
        let (va2, c67) = (meet(5.0, b3, b6), meet(5.0, b6, b7));
        assert!(approx(va2[0], 25.0 - (-24.5 + 5.0 * 26f64.sqrt())));
        assert!((c67[0] - va2[0]) * 5.0 + (c67[1] - va2[1]) < 0.0);
        let (ends, alarm) = ends_avoiding(src);
        assert_eq!(alarm, Some(("PS0041".to_string(), 4)));
        let s = 5.0 * 2f64.sqrt();
        assert_eq!(ends.len(), 3);
        assert!(ends[2].0 == 3 && approx(ends[2].1[0], 15.0 + s) && approx(ends[2].1[1], 5.0), "{ends:?}");
        assert_eq!((ends, alarm), centre(src, Fanuc));
    }

    #[test]
    fn an_avoidance_whose_next_block_would_gouge_is_given_up() {
        // `TWO` with block 6 right-down to 22.5,−0.6, then up to 33,10. Blocks 4 and 5 interfere
        // (as in the three-block case); block 3 meets block 6's offset (direction (5,−1)/√26,
        // x + 5y = 19.5 + 5√26) at 5√26 − 5.5 = 19.995, 5 — and block 6 from there to corner 6/7 (inside)
        // 20.842,4.831 runs forward: the avoidance vector exists. But that corner is 4.904 from
        // the programmed point 20,0 (the start of block 4, which the avoidance replaced): the
        // guard finds a gouge of 0.096 mm; PS0041 at block 3, which does not move.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21. Y-1.\nX22. Y-0.5\nX22.5 Y-0.6\nX33. Y10.\nX40.\nG40 X50.\nM30\n";
        let (b3, b6, b7) = ([[0.0, 0.0], [20.0, 0.0]], [[22.0, -0.5], [22.5, -0.6]], [[22.5, -0.6], [33.0, 10.0]]);
        let (va, c67) = (meet(5.0, b3, b6), meet(5.0, b6, b7));
        assert!(approx(va[0], 5.0 * 26f64.sqrt() - 5.5) && approx(va[1], 5.0));
        assert!((c67[0] - va[0]) * 5.0 - (c67[1] - va[1]) > 0.0);
        let d = (c67[0] - 20.0).hypot(c67[1]);
        assert!(d < 5.0 - 0.09 && d > 5.0 - 0.1, "{d}");
        let (ends, alarm) = ends_avoiding(src);
        assert_eq!(alarm, Some(("PS0041".to_string(), 3)));
        assert_eq!(ends, vec![(1, [-10.0, 0.0]), (2, [0.0, 5.0])]);
    }

    #[test]
    fn the_gouge_found_by_the_property_test_now_alarms() {
        // The dip `X20. / X21.588 Y-2.455 / X22.129 Y-0.871 / X41.372 Y-6.282` with G41 R5
        // (`docs/cutter-compensation.md`, rule 9): block 4 interferes; block 3 meets block 5's
        // offset at 18.851,5, block 4 stays there, block 5 runs to its corner with block 6
        // (inside) 18.927,5.223. Block 6 from there to its corner with block 7 passes 4.83 mm
        // from 20,0, the start of the avoided block 4: the guard stops it — PS0041 at block 6,
        // which does not move (the tool stands at the end of block 5). Before the guard the run
        // completed with that gouge.
        let src = "G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\nX20.\nX21.588 Y-2.455\nX22.129 Y-0.871\nX41.372 Y-6.282\nX60.\nG40 X70.\nM30\n";
        let (b3, b5, b6) =
            ([[0.0, 0.0], [20.0, 0.0]], [[21.588, -2.455], [22.129, -0.871]], [[22.129, -0.871], [41.372, -6.282]]);
        let (va, c56) = (meet(5.0, b3, b5), meet(5.0, b5, b6));
        let (ends, alarm) = ends_avoiding(src);
        assert_eq!(alarm, Some(("PS0041".to_string(), 6)));
        let want = [(1, -10.0, 0.0), (2, 0.0, 5.0), (3, va[0], va[1]), (4, va[0], va[1]), (5, c56[0], c56[1])];
        assert_centre((ends, None), src, &want);
        assert!((va[0] - 18.851).abs() < 1e-3 && (c56[0] - 18.927).abs() < 1e-3 && (c56[1] - 5.223).abs() < 1e-3);
    }

    /// Random contours along +X with a dip (a block shorter than the radius, then one up that
    /// may be short too) in them, compensated with G41 R5: where the plain run stops with
    /// PS0041 and the run with avoidance completes (over one or two interfering blocks), no
    /// point of the tool centre path between the start-up and the cancel comes closer than
    /// R − 1 µm to the programmed contour. At least a fifth of the programs must be such cases
    /// (so that the property is exercised); where the guard finds a gouge the run stops with
    /// PS0041 and is not counted.
    #[test]
    fn an_avoided_path_never_comes_closer_than_the_radius() {
        let mut seed: u64 = 0x5eed_c0de_2020;
        let mut rand = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let dist = |p: [f64; 2], a: [f64; 2], b: [f64; 2]| {
            let (d, w) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
            let t = ((w[0] * d[0] + w[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
            (w[0] - t * d[0]).hypot(w[1] - t * d[1])
        };
        let (mut avoided, mut two, total) = (0, 0, 200);
        for _ in 0..total {
            // 0,0 → 20,0; the dip: down at −20°…−80° for 0.5–4, up at 20°…80° for 0.5–10 (one
            // or two short blocks: avoidance over one or two blocks, or the guard's alarm where
            // the path after it would come too close — the dips the test left out before the
            // guard); then a block of 15–25 at −40°…60°, one of 20 along +X; the cancel beyond.
            let mut pts = vec![[0.0f64, 0.0], [20.0, 0.0]];
            let go = |pts: &mut Vec<[f64; 2]>, deg: f64, len: f64| {
                let l = pts[pts.len() - 1];
                let a = deg.to_radians();
                pts.push([
                    ((l[0] + len * a.cos()) * 1000.0).round() / 1000.0,
                    ((l[1] + len * a.sin()) * 1000.0).round() / 1000.0,
                ]);
            };
            go(&mut pts, -20.0 - 60.0 * rand(), 0.5 + 3.5 * rand());
            go(&mut pts, 20.0 + 60.0 * rand(), 0.5 + 9.5 * rand());
            go(&mut pts, -40.0 + 100.0 * rand(), 15.0 + 10.0 * rand());
            go(&mut pts, 0.0, 20.0);
            let last = pts[pts.len() - 1];
            let mut src = String::from("G90 G00 X-10. Y0 Z0\nG41 D1 G01 X0. F500\n");
            for p in &pts[1..] {
                src += &format!("X{:.3} Y{:.3}\n", p[0], p[1]);
            }
            src += &format!("G40 X{:.3} Y{:.3}\nM30\n", last[0] + 10.0, last[1]);
            let (_, plain) = centre(&src, Fanuc);
            let (ends, alarm) = ends_avoiding(&src);
            if plain.as_ref().map(|a| a.0.as_str()) != Some("PS0041") || alarm.is_some() {
                continue;
            }
            avoided += 1;
            // Two interfering blocks avoided together: blocks 4 and 5 both stay at the point.
            let at = |line: u32| ends.iter().find(|e| e.0 == line).map(|e| e.1);
            if at(4).is_some() && at(4) == at(5) {
                two += 1;
            }
            // Lines 3..=7 are the contour's blocks (and the moves inserted at their corners).
            let mut from = ends[0].1;
            for &(line, to) in &ends[1..] {
                if (3..=7).contains(&line) {
                    for k in 0..=32 {
                        let t = k as f64 / 32.0;
                        let p = [from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])];
                        let d = pts.windows(2).map(|w| dist(p, w[0], w[1])).fold(f64::INFINITY, f64::min);
                        assert!(d >= 5.0 - 1e-3, "line {line}: {p:?} is {d} from the contour\n{src}");
                    }
                }
                from = to;
            }
        }
        assert!(avoided * 5 >= total, "only {avoided} of {total} programs were avoided");
        assert!(two * 20 >= total, "only {two} of {total} programs were avoided over two blocks");
    }

    #[test]
    fn without_interference_avoidance_changes_nothing() {
        // The outside square and the inside pocket: the same points with avoidance on.
        for src in [
            "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n",
            "G90 G00 X20. Y10. Z0\nG41 D1 G01 Y0. F500\nX40.\nY40.\nX0.\nY0.\nX20.\nG04 P1\nG40 Y10.\nM30\n",
        ] {
            assert_eq!(ends_avoiding(src), centre(src, Fanuc), "{src}");
        }
    }
}
