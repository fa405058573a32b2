//! The tool length offset vector and the returns in machine coordinates (FANUC 0i-MB Operator's
//! Manual B-63844EN §14.1.2 "G53, G28, and G30 Commands in Tool Length Offset Mode"): a G28/G30
//! return or a G53 move of the offset axis Z in G43/G44 cancels the offset vector, the mode
//! staying G43/G44; so the `G49` every FANUC post writes after `G28 G91 Z0.` has nothing left to
//! remove. `docs/conventions.md`, "Tool length vector and the returns". Tool lengths are 100
//! (`common::interpreter_with`), G54 is zero unless set.

use crate::common;

use common::{end_of, interpreter_with, motion_ends};
use fivex_engine::canon::Pos;
use fivex_engine::interp::Config;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult};
use fivex_engine::Dialect;

fn ends(src: &str, preset: &str, dialect: Dialect) -> Vec<(u32, Pos)> {
    motion_ends(interpreter_with(src, preset, dialect, |_| {}))
}

fn run_on(src: &str, preset: &str, dialect: Dialect, tweak: impl FnOnce(&mut Config)) -> RunResult {
    let mut interp = interpreter_with(src, preset, dialect, tweak);
    run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
}

/// mill3 with its 2nd reference position at machine Z −20 (G30).
fn g30_at_minus_20(c: &mut Config) {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.axes[2].references[0] = -20.0;
    c.machine = m.into();
}

fn moves_on(ends: &[(u32, Pos)], line: u32) -> bool {
    ends.iter().any(|(l, _)| *l == line)
}

/// Autodesk Fusion's fanuc.cps ends every section and the program with `G28 G91 Z0.` / `G90` /
/// `G49` (its `writeRetract(Z)` then `cancelLengthCompensation()`); the same with G30 and with
/// `G90 G53 G0 Z0.`. By hand: `G43 Z50. H1` puts the nose at machine Z 50 + 100 = 150, the
/// return takes it to the reference position (machine zero; G30's Z −20 here), and the G49
/// moves nothing: before, it dropped the spindle by the tool length (Z 0 → −100).
#[test]
fn the_g49_after_a_return_in_g43_moves_nothing() {
    for (ret, at) in [("G28 G91 Z0.", 0.0), ("G30 G91 Z0.", -20.0), ("G90 G53 G0 Z0.", 0.0)] {
        let src = format!("G90 G54 G17\nT1 M6\nG0 X0 Y0\nG43 Z50. H1\n{ret}\nG90\nG49\nM30\n");
        for dialect in [Dialect::Fanuc, Dialect::Syntec] {
            let e = motion_ends(interpreter_with(&src, "mill3", dialect, g30_at_minus_20));
            assert!((end_of(&e, 4)[2] - 150.0).abs() < 1e-9, "{ret} {dialect:?}: {e:?}");
            assert!((end_of(&e, 5)[2] - at).abs() < 1e-9, "{ret} {dialect:?}: {e:?}");
            assert!(!moves_on(&e, 7), "{ret} {dialect:?}: the G49 block moved: {e:?}");
            let r = run_on(&src, "mill3", dialect, g30_at_minus_20);
            assert!(r.completed(), "{ret} {dialect:?}: {:?}", r.alarms);
            assert!((r.machine[2] - at).abs() < 1e-9, "{ret} {dialect:?}: ends at {:?}", r.machine);
        }
    }
}

/// The audit's 3-axis bridge machine: Z stroke −100…700 and a 150 mm tool. The Fusion ending
/// raised OT0511 at the G49 (the nose sent to −150); on a FANUC nothing moves there.
#[test]
fn the_fusion_ending_on_a_short_z_stroke_does_not_overtravel() {
    let src = "G90 G54 G17\nT1 M6\nG0 X0 Y0\nG43 Z50. H1\nG1 Z-1. F500.\nX50.\nG0 Z50.\n\
               G28 G91 Z0.\nG90\nG49\nG28 G91 X0. Y0.\nG90\nM30\n";
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| {
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.axes[2].stroke = Some([-100.0, 700.0]);
        c.machine = m.into();
    });
    interp.state.offsets.tool_mut(1).unwrap().h_geometry = 150.0;
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!((r.machine[0], r.machine[1], r.machine[2]), (0.0, 0.0, 0.0));
}

/// After the return the position is read without the vector, as the control displays it: the
/// workpiece Z and #5043 are the machine Z less G54's Z (before: 100 lower, the vector still
/// applied to the display), #5083 (the offset applied) is 0, and #4008 still reads 43
/// ("the previously specified modal G code remains displayed").
#[test]
fn after_the_return_the_position_is_read_without_the_vector() {
    let src = "G10 L2 P1 Z-300.\nG90 G54 G17\nG0 X0 Y0\nG43 Z50. H1\nG28 G91 Z0.\nG90\n\
               #100=#5043\n#101=#4008\n#102=#5083\nM30\n";
    let r = run_on(src, "mill3", Dialect::Fanuc, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let var = |n| r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v);
    assert_eq!(var(100), Some(300.0));
    assert_eq!(var(101), Some(43.0));
    assert_eq!(var(102), Some(0.0));
    assert!((r.machine[2]).abs() < 1e-9, "{:?}", r.machine);
    assert!((r.workpiece[2] - 300.0).abs() < 1e-9, "{:?}", r.workpiece);
    assert!((r.tip.tip[2] - 300.0).abs() < 1e-9, "{:?}", r.tip);
}

/// The vector comes back with the next move of Z (its end point with the vector, as a G43 H
/// block's) or with a length selection; a move of X/Y alone leaves Z at the reference position.
/// By hand (G54 zero, lengths 100): after `G28 G91 Z0.` the X/Y move stays at machine Z 0,
/// `G0 Z50.` goes to 150. After a second return, `G43 H2` with H2 = 120 moves by the 120 in
/// force (machine Z 0 → 120; its block moves by the length, as before: Syntec, and FANUC with
/// TOS = 0), and a FANUC TOS = 0 G49 after the restored vector moves by it again (120 → 0).
/// FANUC with TOS = 1 (the default): the bare `G43 H2` and `G49` move nothing ("TOS", below),
/// machine Z stays 0. G44 and G91 Z moves alike.
#[test]
fn the_next_z_move_or_a_length_selection_restores_the_vector() {
    let src = "G90 G54 G17\nG0 X0 Y0\nG43 Z50. H1\nG28 G91 Z0.\nG90 G0 X10. Y10.\nG0 Z50.\n\
               G28 G91 Z0.\nG90 G43 H2\nG49\nG44 H1 Z50.\nG91 G28 Z0.\nZ-10.\nM30\n";
    for (dialect, by_motion) in [(Dialect::Fanuc, false), (Dialect::Fanuc, true), (Dialect::Syntec, false)] {
        let mut interp = if by_motion {
            interpreter_with(src, "mill3", dialect, tos0("mill3"))
        } else {
            interpreter_with(src, "mill3", dialect, |_| {})
        };
        interp.state.offsets.tool_mut(2).unwrap().h_geometry = 120.0;
        let e = motion_ends(interp);
        let z = |line| end_of(&e, line)[2];
        assert_eq!(z(4), 0.0, "{dialect:?} {e:?}");
        assert_eq!((end_of(&e, 5)[0], z(5)), (10.0, 0.0), "{dialect:?} {e:?}");
        assert_eq!(z(6), 150.0, "{dialect:?} {e:?}");
        if dialect == Dialect::Fanuc && !by_motion {
            assert!(!moves_on(&e, 8) && !moves_on(&e, 9), "TOS = 1: {e:?}");
        } else {
            assert_eq!(z(8), 120.0, "{dialect:?} {e:?}");
        }
        // (Syntec's G49 without axis words moves nothing: "Syntec G49", below.)
        if by_motion {
            assert_eq!(z(9), 0.0, "{dialect:?} {e:?}");
        } else {
            assert!(!moves_on(&e, 9), "{e:?}");
        }
        assert_eq!(z(10), -50.0, "{dialect:?} {e:?}");
        assert_eq!(z(11), 0.0, "{dialect:?} {e:?}");
        // G91 Z-10. from machine 0, the program point 0 less the vector: 0 − 10 − 100.
        assert_eq!(z(12), -110.0, "{dialect:?} {e:?}");
    }
}

/// G28 of X/Y alone and G53 of X alone in G43 leave the Z vector ("other than tool length offset
/// axis: not canceled"): with TOS = 0 the G49 after them still moves by the length (machine Z
/// 150 → 50); with TOS = 1 it moves nothing, and `G0 Z60.` then goes to 60 without it.
#[test]
fn a_return_of_other_axes_keeps_the_vector() {
    for ret in ["G28 G91 X0. Y0.", "G90 G53 X100."] {
        let src = format!("G90 G54 G17\nG0 X0 Y0\nG43 Z50. H1\n{ret}\nG90\nG49\nG0 Z60.\nM30\n");
        let e = motion_ends(interpreter_with(&src, "mill3", Dialect::Fanuc, tos0("mill3")));
        assert_eq!(end_of(&e, 4)[2], 150.0, "{ret}: {e:?}");
        assert_eq!(end_of(&e, 6)[2], 50.0, "{ret}: {e:?}");
        let e = ends(&src, "mill3", Dialect::Fanuc);
        assert_eq!(end_of(&e, 4)[2], 150.0, "{ret}: {e:?}");
        assert!(!moves_on(&e, 6), "{ret}: {e:?}");
        assert_eq!(end_of(&e, 7)[2], 60.0, "{ret}: {e:?}");
    }
}

/// Fusion's 3+2 ending on head-bc (the audit's p3): `G68.2 X0. Y0. Z0. I90. J30. K-90.` is a
/// turn of 30° about Y (Euler ZXZ: Rz(90)·Rx(30)·Rz(−90)), so G53.1 gives B30 and the feature Z
/// is (sin 30°, 0, cos 30°). `G28 G91 Z0.` takes machine Z to 0; the G49 and the G69 after it
/// move nothing (before: the head went 100 mm down the tilted tool, X −50, Z −86.6). Then, by
/// the restoration rule, `G0 Z15.` in the plane again (before the G69 here) puts the tip 15
/// along the feature Z with the 100 mm tool, beside the nose's feature X/Y after the return.
#[test]
fn the_3_plus_2_ending_on_a_head_moves_nothing_at_g49() {
    let head = "G90 G17 G94 G49 G40 G80\nG54\nG0 B30. C0.\nG68.2 X0. Y0. Z0. I90. J30. K-90.\nG53.1\n\
                G90 G17 G43 G0 X-20. Y-10. Z15. H1\nG0 Z5.\nG28 G91 Z0.\nG90\n";
    let zc = Vec3::new(0.5, 0.0, 3f64.sqrt() / 2.0);
    let xc = Vec3::new(3f64.sqrt() / 2.0, 0.0, -0.5);
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    for dialect in [Dialect::Fanuc, Dialect::Syntec] {
        let src = format!("{head}G49\nG69\nG0 B0. C0.\nM30\n");
        let e = ends(&src, "head-bc", dialect);
        let returned = end_of(&e, 8);
        assert!(returned[2].abs() < 1e-9 && (returned[3] - 30.0).abs() < 1e-9, "{dialect:?} {returned:?}");
        let tip = kin.forward(&end_of(&e, 7), 100.0).tip;
        assert!((tip.dot(&zc) - 5.0).abs() < 1e-9, "{dialect:?}: the cut level {tip:?}");
        assert!(!moves_on(&e, 10) && !moves_on(&e, 11), "{dialect:?}: G49/G69 moved: {e:?}");
        let swung = end_of(&e, 12);
        assert!((swung[0] - returned[0]).abs() < 1e-9 && swung[2].abs() < 1e-9, "{dialect:?} {swung:?}");

        let src = format!("{head}G0 Z15.\nG49\nG69\nM30\n");
        let e = ends(&src, "head-bc", dialect);
        let nose = kin.forward(&end_of(&e, 8), 0.0).tip;
        let tip = kin.forward(&end_of(&e, 10), 100.0).tip;
        assert!((tip.dot(&zc) - 15.0).abs() < 1e-9, "{dialect:?}: {tip:?}");
        assert!((tip.dot(&xc) - nose.dot(&xc)).abs() < 1e-9 && (tip.y - nose.y).abs() < 1e-9, "{dialect:?}");
    }
}

/// TCP's G49 still moves by the offset (seed 000 §2.3.10: the G49 block is an ordinary move
/// that removes the tool length at its end): on head-bc at B0 C0, `G43.4 H1` lifts the nose by
/// the 100 mm length over the tip at Z 0 (machine Z 100), and the G49 takes it back to 0.
#[test]
fn the_g49_ending_tcp_still_moves_by_the_offset() {
    let src = "G90 G0 X0 Y0 Z0 B0 C0\nG43.4 H1\nG0 X0 Y0 Z0\nG49\nM30\n";
    let e = ends(src, "head-bc", Dialect::Fanuc);
    assert!((end_of(&e, 2)[2] - 100.0).abs() < 1e-9, "{e:?}");
    assert!(end_of(&e, 4)[2].abs() < 1e-9, "{e:?}");
}

/// Syntec G49 (*decision*, `docs/dialects.md`, "Syntec G49"): a G49 block without axis words
/// moves nothing, whether it ends G43 in the tilted plane or RTCP; the current point is then
/// the nose where it stands. Autodesk's SYIL post (the audit's s1b and s2) writes `G49` at
/// clearance height before `G69` and `G28 G91 Z0.`. By hand on head-bc, plane `G68.2 X0 Y0 Z0
/// I0 J30. K0` (a turn of 30° about X; Syntec's G53.1 P0 from B0 C0: B−30 C90 or B30 C−90,
/// whichever), `G43 H1` / `G0 X0 Y0 Z15.`: the tip 15 up the feature Z with the 100 mm tool;
/// the G49 leaves the machine there (before: 100 mm down the tilted tool, to 85 below the
/// tip's level), and the next `G0 Z115.` in the plane puts the nose — now the controlled point
/// — at feature Z 115, where the G43 tip at Z15 had it: no motion either. FANUC with TOS = 1
/// (the default) the same, its bare G43 in the plane moving nothing too (the tilted-plane
/// interplay of "TOS"); with TOS = 0 the G49 moves by the length down the tilted tool.
#[test]
fn a_syntec_g49_without_axis_words_moves_nothing() {
    let plane = "G90 G17 G49\nG0 X0 Y0 Z200. B0 C0\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG43 H1\nG0 X0 Y0 Z15.\nG49\nG0 Z115.\nG69\nM30\n";
    let e = ends(plane, "head-bc", Dialect::Syntec);
    assert!(!moves_on(&e, 7), "{e:?}");
    let at = end_of(&e, 6);
    let same = end_of(&e, 8);
    assert!(at.iter().zip(&same).all(|(a, b)| (a - b).abs() < 1e-9), "{at:?} → {same:?}");
    let e = ends(plane, "head-bc", Dialect::Fanuc);
    assert!(!moves_on(&e, 5) && !moves_on(&e, 7), "FANUC, TOS = 1: {e:?}");
    let (fanuc_at, fanuc_same) = (end_of(&e, 6), end_of(&e, 8));
    assert!(at.iter().zip(&fanuc_at).all(|(a, b)| (a - b).abs() < 1e-9), "{at:?} / {fanuc_at:?}");
    assert!(at.iter().zip(&fanuc_same).all(|(a, b)| (a - b).abs() < 1e-9), "{at:?} → {fanuc_same:?}");
    let e = motion_ends(interpreter_with(plane, "head-bc", Dialect::Fanuc, tos0("head-bc")));
    assert!(moves_on(&e, 5) && moves_on(&e, 7), "FANUC TOS = 0 moves by the length: {e:?}");

    let rtcp = "G90 G0 X0 Y0 Z0 B0 C0\nG43.4 H1\nG0 X10. Y0 Z20. B30.\nG49\nM30\n";
    let e = ends(rtcp, "head-bc", Dialect::Syntec);
    assert!(!moves_on(&e, 4), "{e:?}");
    assert!(moves_on(&ends(rtcp, "head-bc", Dialect::Fanuc), 4));
}

/// `preset` with FANUC No.5006#6 TOS = 0 (`five_axis.length_offset_by_motion`): tool length
/// offset by moving the axes.
fn tos0(preset: &str) -> impl FnOnce(&mut Config) + '_ {
    move |c: &mut Config| {
        let mut m = MachineConfig::preset(preset).unwrap();
        m.five_axis.length_offset_by_motion = true;
        c.machine = m.into();
    }
}

/// FANUC TOS = 1 (fivex's default; `docs/five-axis.md`, "TOS"): a bare `G43 H1` shifts the
/// coordinate system and moves nothing; the X move after it stays at the height the machine
/// stands at, and the next Z move goes to its target with the length. By hand (G54 zero,
/// length 100): `G0 Z50.` without length puts the nose at machine Z 50; `G43 H1` nothing;
/// `G0 X50.` ends at (50, 0, 50); `Z20.` at 20 + 100 = 120. With TOS = 0 the G43 block lifts the
/// nose by the length (Z 50 → 150) and the X move runs at 150.
#[test]
fn a_bare_g43_moves_nothing_with_tos_1() {
    let src = "G90 G54 G17 G49\nG0 X0 Y0 Z50.\nG43 H1\nG0 X50.\nZ20.\nM30\n";
    let e = ends(src, "mill3", Dialect::Fanuc);
    assert!(!moves_on(&e, 3), "{e:?}");
    assert_eq!(&end_of(&e, 4)[..3], &[50.0, 0.0, 50.0], "{e:?}");
    assert_eq!(end_of(&e, 5)[2], 120.0, "{e:?}");
    let e = motion_ends(interpreter_with(src, "mill3", Dialect::Fanuc, tos0("mill3")));
    assert_eq!(end_of(&e, 3)[2], 150.0, "TOS = 0: {e:?}");
    assert_eq!(&end_of(&e, 4)[..3], &[50.0, 0.0, 150.0], "TOS = 0: {e:?}");
    assert_eq!(end_of(&e, 5)[2], 120.0, "TOS = 0: {e:?}");
}

/// FANUC TOS = 1: a bare `G49` at clearance height does not plunge. By hand: `G43 Z50. H1`
/// puts the nose at machine Z 150; `G49` moves nothing (TOS = 0: down by the length to 50);
/// `G0 X10.` stays at 150; `Z60.` goes to 60 without length. The workpiece Z (#5043) reads the
/// nose's 150 after the G49 (TOS = 0: 50).
#[test]
fn a_bare_g49_at_clearance_does_not_plunge_with_tos_1() {
    let src = "G90 G54 G17\nG0 X0 Y0\nG43 Z50. H1\nG49\n#100=#5043\nG0 X10.\nZ60.\nM30\n";
    let e = ends(src, "mill3", Dialect::Fanuc);
    assert_eq!(end_of(&e, 3)[2], 150.0, "{e:?}");
    assert!(!moves_on(&e, 4), "{e:?}");
    assert_eq!(&end_of(&e, 6)[..3], &[10.0, 0.0, 150.0], "{e:?}");
    assert_eq!(end_of(&e, 7)[2], 60.0, "{e:?}");
    let e = motion_ends(interpreter_with(src, "mill3", Dialect::Fanuc, tos0("mill3")));
    assert_eq!(end_of(&e, 4)[2], 50.0, "TOS = 0: {e:?}");
    assert_eq!(&end_of(&e, 6)[..3], &[10.0, 0.0, 50.0], "TOS = 0: {e:?}");
    assert_eq!(end_of(&e, 7)[2], 60.0, "TOS = 0: {e:?}");

    let r = run_on(src, "mill3", Dialect::Fanuc, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.machine[2], 60.0);
    assert!(r.variables.iter().any(|&(k, v)| k == 100 && v == 150.0), "#5043 after the G49: {:?}", r.variables);
    // Ending right after the G49: the summary's tip is the nose where it stands (length 0).
    let r = run_on("G90 G54 G17\nG0 X0 Y0\nG43 Z50. H1\nG49\nM30\n", "mill3", Dialect::Fanuc, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!((r.machine[2], r.tip.tip[2]), (150.0, 150.0));
}

/// FANUC TOS = 1, a G43 block with axis words: a G90 Z move ends where it would with TOS = 0
/// (Z 20 + 100 = 120), an H change with only X leaves Z where it stands, and a G91 Z move moves
/// by its increment only (from 50: `G91 G43 H1 Z-10.` → 40; TOS = 0: 50 − 10 + 100 = 140).
#[test]
fn a_g43_block_with_axis_words_under_tos_1() {
    for (block, z1, z0) in
        [("G43 H1 Z20.", 120.0, 120.0), ("G43 H1 X10.", 50.0, 150.0), ("G91 G43 H1 Z-10.", 40.0, 140.0)]
    {
        let src = format!("G90 G54 G17 G49\nG0 X0 Y0 Z50.\n{block}\nM30\n");
        let e = ends(&src, "mill3", Dialect::Fanuc);
        assert_eq!(end_of(&e, 3)[2], z1, "{block}: {e:?}");
        let e = motion_ends(interpreter_with(&src, "mill3", Dialect::Fanuc, tos0("mill3")));
        assert_eq!(end_of(&e, 3)[2], z0, "TOS = 0 {block}: {e:?}");
    }
}
