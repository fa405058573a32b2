//! Tilted working plane in programs (spec `fanuc-twp-wsec-manual-params.md` TWP-01…TWP-13,
//! `syntec.md` SYN-18…SYN-22): where the tip and the tool are after G68.2, G53.1 and moves in the
//! feature coordinate system, on every kind of machine.

use crate::common;

use common::{end_of, interpreter_with, motion_ends};
use fivex_engine::canon::Pos;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;

/// The machine position at the end of each motion, by line; tool lengths 100.
fn ends(preset: &str, dialect: Dialect, src: &str) -> Vec<(u32, Pos)> {
    motion_ends(interpreter_with(src, preset, dialect, |_| {}))
}

fn close(a: Vec3, b: Vec3, tol: f64) -> bool {
    (a - b).norm() < tol
}

/// SYN TV-32 / the example: G68.2 X100 Y100 Z50 I30 J15 K20, G53.1, G43 H1, G01 X0 Y0
/// Z0 puts the tool tip at workpiece (100, 100, 50) with the tool along the feature Z.
const TV32: &str = "N1 G90 G54 G01 X0 Y0 Z50. F1000\nN2 G68.2 X100. Y100. Z50. I30. J15. K20.\n\
                    N3 G01 X0 Y0 Z50.\nN4 G53.1\nN5 G43 H1\nN6 G01 X0 Y0 Z0\nN98 G49\nN99 G69\n\
                    N100 G01 X0. Y0. Z50.\nM30\n";

fn zc() -> Vec3 {
    Vec3::new(0.129410, -0.224144, 0.965926)
}

#[test]
fn tv32_tip_at_the_plane_origin_with_the_tool_along_feature_z_on_every_machine() {
    for dialect in [Dialect::Fanuc, Dialect::Syntec] {
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let m = MachineConfig::preset(preset).unwrap();
            let kin = Kinematics::new(&m).unwrap();
            let e = ends(preset, dialect, TV32);
            // N3 without length compensation: the nose at 50 along Zc from the origin.
            let n3 = kin.forward(&end_of(&e, 3), 0.0).tip;
            assert!(close(n3, Vec3::new(106.470476, 88.792807, 98.296291), 1e-5), "{preset}: N3 {n3:?}");
            // N4: the tool along Zc (relative to the workpiece).
            let n4 = kin.forward(&end_of(&e, 4), 100.0);
            assert!(close(n4.tool, zc(), 1e-6), "{preset} {dialect:?}: N4 tool {:?}", n4.tool);
            // N6: the tip at the FCS origin.
            let n6 = kin.forward(&end_of(&e, 6), 100.0);
            assert!(close(n6.tip, Vec3::new(100.0, 100.0, 50.0), 1e-9), "{preset}: N6 tip {:?}", n6.tip);
            assert!(close(n6.tool, zc(), 1e-6));
        }
    }
}

/// Syntec §4.7.2 (TV-09/TV-34): the manual's own program as printed, from its first block
/// `G71` (metric input in the Syntec dialect, decision; it was COR-070 at line 1). Surface 1's
/// frame Xc (0, 0.965926, 0.258819), Yc (−1, 0, 0), Zc (0, −0.258819, 0.965926) at G54
/// (100, 0, −26.7): the tip at FCS (11.4608, 24.1067, 10) after the G01 is G54 (75.893300, 8.482092,
/// −14.074468), after `Z-.15` (75.893300, 11.109106, −23.878616), by hand.
#[test]
fn syntec_manual_example_4_7_2_runs_from_its_g71() {
    let src = "G71\nG17 G40 G49 G90 G80\nG91 G28 Z0.0\nG90 G54 G00 X11.4608 Y24.1067\n\
               G68.2 X100. Y0. Z-26.7 I0. J15. K90.\nG53.1\nG43 G00 Z10. H01\nS20000 M03\n\
               G01 X11.4608 Y24.1067 F1000.\nZ-.15\nG49\nG69\nM30\n";
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let e = ends("head-bc", Dialect::Syntec, src);
    let zc = Vec3::new(0.0, -0.258819, 0.965926);
    for (line, want) in [(9, Vec3::new(75.8933, 8.482092, -14.074468)), (10, Vec3::new(75.8933, 11.109106, -23.878616))]
    {
        let at = kin.forward(&end_of(&e, line), 100.0);
        assert!(close(at.tip, want, 1e-5), "line {line}: tip {:?}", at.tip);
        assert!(close(at.tool, zc, 1e-6), "line {line}: tool {:?}", at.tool);
    }
}

#[test]
fn tv33_alignment_takes_the_masters_shortest_way() {
    // Spindle C–B from all zero: (C −60, B 15) or (C 120, B −15); the master C moves least.
    let e = ends("head-bc", Dialect::Syntec, TV32);
    let n4 = end_of(&e, 4);
    assert!((n4[3] - 15.0).abs() < 1e-4 && (n4[4] + 60.0).abs() < 1e-4, "B, C = {}, {}", n4[3], n4[4]);
}

#[test]
fn tv_twp_02_moves_in_the_feature_system_reach_their_workpiece_point() {
    let src = "N1 G55\nN2 G90 G01 X20.0 Y5.0 Z0 F1000\nN3 G68.2 X20.0 Y5.0 Z0 I0 J90.0 K0\nN4 G53.1\n\
               N5 X-15.0 Y0 Z-15.0\nN6 G69\nM30\n";
    for preset in ["head-bc", "table-ac", "mixed-bc"] {
        let m = MachineConfig::preset(preset).unwrap();
        let kin = Kinematics::new(&m).unwrap();
        let n5 = kin.forward(&end_of(&ends(preset, Dialect::Fanuc, src), 5), 0.0);
        assert!(close(n5.tip, Vec3::new(5.0, 20.0, 0.0), 1e-9), "{preset}: {:?}", n5.tip);
        assert!(close(n5.tool, Vec3::new(0.0, -1.0, 0.0), 1e-9), "{preset}: {:?}", n5.tool);
    }
}

#[test]
fn tv32_g53_6_and_g53_3_variants_end_with_the_tip_at_the_origin() {
    // SYN TV-32: `N3 G53.6 H1; N4 G01 X0 Y0 Z0` and `N4 G53.3 X0 Y0 Z0 H1` end where N4–N6 do.
    let g53_6 = "N1 G90 G54 G01 X0 Y0 Z50. F1000\nN2 G68.2 X100. Y100. Z50. I30. J15. K20.\n\
                 N3 G53.6 H1\nN4 G01 X0 Y0 Z0\nN98 G49\nN99 G69\nM30\n";
    let g53_3 = "N1 G90 G54 G01 X0 Y0 Z50. F1000\nN2 G68.2 X100. Y100. Z50. I30. J15. K20.\n\
                 N3 G01 X0 Y0 Z50.\nN4 G53.3 X0 Y0 Z0 H1\nN98 G49\nN99 G69\nM30\n";
    for preset in ["head-bc", "table-ac", "mixed-bc"] {
        let m = MachineConfig::preset(preset).unwrap();
        let kin = Kinematics::new(&m).unwrap();
        for (src, line) in [(g53_6, 4), (g53_3, 4)] {
            let end = kin.forward(&end_of(&ends(preset, Dialect::Syntec, src), line), 100.0);
            assert!(close(end.tip, Vec3::new(100.0, 100.0, 50.0), 1e-9), "{preset}: {:?}\n{src}", end.tip);
            assert!(close(end.tool, zc(), 1e-6), "{preset}: {:?}", end.tool);
        }
        // G53.6 keeps the tip (of the 100 mm tool) in place while the axes turn.
        let mut interp = interpreter_with(g53_6, preset, Dialect::Syntec, |_| {});
        let mut tips = Vec::new();
        fivex_engine::run::run(&mut interp, &fivex_engine::run::RunOptions::default(), |s| {
            if s.line == 3 {
                tips.push(kin.forward(&s.machine, 100.0).tip);
            }
        });
        assert!(tips.len() > 10, "{preset}: G53.6 moved");
        let spread = tips.iter().map(|t| (t - tips[0]).norm()).fold(0.0, f64::max);
        assert!(spread < 1e-6, "{preset}: the tip moved {spread} mm during G53.6");
    }
}

/// SYN-21, TV-45: `G53.6 H1 R50.` keeps the point 50 mm up the tool from the tip in place while
/// the axes turn; afterwards the program point is the tip again. (G53.6 is Syntec's; FANUC's
/// tilted plane does not allow it: PS5462.)
#[test]
fn g53_6_r_keeps_the_point_r_up_the_tool() {
    let src = "N1 G90 G54 G01 X0 Y0 Z50. F1000\nN2 G68.2 X100. Y100. Z50. I30. J15. K20.\n\
               N3 G53.6 H1 R50.\nN4 G01 X0 Y0 Z0\nN98 G49\nN99 G69\nM30\n";
    let dialect = Dialect::Syntec;
    for preset in ["head-bc", "table-ac", "mixed-bc"] {
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let mut interp = interpreter_with(src, preset, dialect, |_| {});
        let (mut pivots, mut tips) = (Vec::new(), Vec::new());
        fivex_engine::run::run(&mut interp, &fivex_engine::run::RunOptions::default(), |s| {
            if s.line == 3 {
                pivots.push(kin.forward(&s.machine, 50.0).tip);
                tips.push(kin.forward(&s.machine, 100.0).tip);
            }
        });
        assert!(pivots.len() > 10, "{preset}: G53.6 moved");
        let spread = |v: &[Vec3]| v.iter().map(|t| (t - v[0]).norm()).fold(0.0, f64::max);
        assert!(spread(&pivots) < 1e-6, "{preset}: the pivot moved {} mm", spread(&pivots));
        assert!(spread(&tips) > 1.0, "{preset}: the tip should swing about the pivot");
        let e = ends(preset, dialect, src);
        let n3 = kin.forward(&end_of(&e, 3), 100.0);
        assert!(close(n3.tool, zc(), 1e-6), "{preset}: {:?}", n3.tool);
        let n4 = kin.forward(&end_of(&e, 4), 100.0);
        assert!(close(n4.tip, Vec3::new(100.0, 100.0, 50.0), 1e-9), "{preset}: N4 tip {:?}", n4.tip);
    }
}

/// TV-TWP-03/04 (MTW = No.11221#0 = 1): G68.2 in the plane replaces it (origin in the WCS),
/// G68.4 composes with it; both put the tool along the WCS +X after G53.1, with X/Y turned 180°
/// about Z from each other. With MTW = 0 both are PS5462 (tested in modes.rs).
#[test]
fn tv_twp_03_04_multiple_planes_with_mtw() {
    let base = "N1 G55\nN2 G90 G01 X20.0 Y5.0 Z0 F1000\nN3 G68.2 X20.0 Y5.0 Z0 I0 J90.0 K0\nN4 G53.1\n\
                N5 X-15.0 Y0 Z-15.0\n";
    let tv03 =
        format!("{base}N6 G68.2 X5.0 Y20.0 Z0 I90.0 J90.0 K0\nN7 G53.1\nN8 G01 X0 Y0 Z0\nN9 X10.\nN10 G69\nM30\n");
    let tv04 = format!(
        "{base}N6 G68.4 X-15.0 Y0 Z-15.0 I90.0 J90.0 K90.0\nN7 G53.1\nN8 G01 X0 Y0 Z0\nN9 X10.\nN10 G69\nM30\n"
    );
    for preset in ["head-bc", "table-ac"] {
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let run = |src: &str| {
            motion_ends(interpreter_with(src, preset, Dialect::Fanuc, |c| {
                c.edit_machine(|m| m.five_axis.multiple_planes = true)
            }))
        };
        for (src, n9) in [(&tv03, Vec3::new(5.0, 30.0, 0.0)), (&tv04, Vec3::new(5.0, 10.0, 0.0))] {
            let e = run(src);
            let n8 = kin.forward(&end_of(&e, 8), 0.0);
            assert!(close(n8.tool, Vec3::x(), 1e-9), "{preset}: tool {:?}\n{src}", n8.tool);
            assert!(close(n8.tip, Vec3::new(5.0, 20.0, 0.0), 1e-9), "{preset}: N8 {:?}\n{src}", n8.tip);
            let n9_tip = kin.forward(&end_of(&e, 9), 0.0).tip;
            assert!(close(n9_tip, n9, 1e-9), "{preset}: N9 {n9_tip:?}\n{src}");
        }
        let refused = fivex_engine::run::run(
            &mut interpreter_with(&tv03, preset, Dialect::Fanuc, |_| {}),
            &fivex_engine::run::RunOptions::default(),
            |_| {},
        );
        assert_eq!(refused.alarms.first().map(|a| a.code.as_str()), Some("PS5462"), "{preset}: MTW = 0");
    }
}

/// TV-TWP-11c: No.11220 = 0.001 refuses three points whose third is 0.0005 off the line of the
/// other two ("unstable plane"); with No.11220 = 0 only points on one line are refused.
#[test]
fn tv_twp_11c_unstable_plane_distance_is_no_11220() {
    let src = "G68.2 P2 Q1 X0 Y0 Z0\nG68.2 P2 Q2 X100. Y0 Z0\nG68.2 P2 Q3 X50. Y0.0005 Z0\nG69\nM30\n";
    let result = |min: f64| {
        let mut interp = interpreter_with(src, "head-bc", Dialect::Fanuc, |c| {
            c.edit_machine(|m| m.five_axis.plane_min_distance = min)
        });
        fivex_engine::run::run(&mut interp, &fivex_engine::run::RunOptions::default(), |_| {})
    };
    assert_eq!(result(0.001).alarms[0].code, "PS5457");
    assert!(result(0.0).completed(), "{:?}", result(0.0).alarms);
    assert_eq!(result(0.0).alarms.len(), 0);
}

/// Reset and the tilted plane (FANUC No.5400#2 D3R, Syntec Pr3014): cancelled by default, kept
/// when the machine says so; after a cancelling reset X/Y/Z are workpiece coordinates again.
#[test]
fn reset_cancels_or_keeps_the_plane() {
    use fivex_engine::machine::PlaneAfterReset;
    let src = "G90 G01 X0 Y0 Z0 F1000\nG68.2 X10. Y0 Z0 I0 J0 K90.\nM00\n";
    for (rule, kept) in
        [(PlaneAfterReset::Cancelled, false), (PlaneAfterReset::Kept, true), (PlaneAfterReset::KeptOverRestart, true)]
    {
        let mut interp = interpreter_with(src, "head-bc", Dialect::Syntec, |c| {
            c.edit_machine(|m| m.five_axis.plane_after_reset = rule)
        });
        fivex_engine::run::run(&mut interp, &fivex_engine::run::RunOptions::default(), |_| {});
        assert_eq!(interp.state.modal(16), 682, "{rule:?}: the plane is on before the reset");
        interp.reset();
        assert_eq!(interp.state.modal(16), if kept { 682 } else { 690 }, "{rule:?}");
        interp.load(fivex_engine::lang::parse_file("G01 X5.\nM30\n"));
        let e = motion_ends(interp);
        // In the plane (FCS X along the WCS +Y, Y along −X, origin X10) the tip at WCS 0 is FCS
        // (0, 10, 0), so X5 is the WCS point (0, 5, 0).
        let tip = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap().forward(&e[0].1, 0.0).tip;
        let want = if kept { Vec3::new(0.0, 5.0, 0.0) } else { Vec3::new(5.0, 0.0, 0.0) };
        assert!(close(tip, want, 1e-9), "{rule:?}: {tip:?}");
    }
}

/// The head-bc preset with its C axis turning left-handed (Syntec Pr3007 = 2).
fn head_bc_c_left() -> MachineConfig {
    let mut m = MachineConfig::preset("head-bc").unwrap();
    for l in m.rotary.iter_mut().filter(|l| l.axis == 'C') {
        l.hand = fivex_engine::machine::Hand::Left;
    }
    m
}

/// A spindle C–A head: the head-bc preset with its B axis turning about X as A.
fn head_ca() -> MachineConfig {
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.axes.iter_mut().filter(|a| a.name == 'B').for_each(|a| a.name = 'A');
    for l in m.rotary.iter_mut().filter(|l| l.axis == 'B') {
        (l.axis, l.direction) = ('A', [1.0, 0.0, 0.0]);
    }
    m
}

/// Syntec TV-08 (G68.3 P1, SYN-24): the FCS is turned as the rotary axes turn the tool. After
/// C45 and B90 the FCS point Y10 is G54 (7.071, 7.071, 0) — the printed value, which this
/// convention gives on a head whose C turns left-handed (Q-15: the figure is missing; with a
/// right-handed C the same rule gives (−7.071, 7.071, 0), also pinned here). R is ignored.
#[test]
fn syntec_tv08_g68_3_p1_takes_the_frame_from_the_rotary_axes() {
    let src = "N1 G54 G90 G00 B0. C0.\nN2 C45.\nN3 B90.\nN4 G68.3 P1 X0. Y0. Z0. R30.\nN5 G01 X0 Y10. Z0 F1000\n\
               N6 G69\nN7 G00 X0. Y0. Z0. B0. C0.\nN8 M30\n";
    let h = std::f64::consts::FRAC_1_SQRT_2 * 10.0;
    for (m, want) in
        [(head_bc_c_left(), Vec3::new(h, h, 0.0)), (MachineConfig::preset("head-bc").unwrap(), Vec3::new(-h, h, 0.0))]
    {
        let kin = Kinematics::new(&m).unwrap();
        let e = motion_ends(interpreter_with(src, "head-bc", Dialect::Syntec, |c| c.machine = m.clone().into()));
        let n5 = kin.forward(&end_of(&e, 5), 0.0);
        assert!(close(n5.tip, want, 1e-9), "{:?}: {:?}", m.rotary[0].hand, n5.tip);
    }
}

/// Syntec TV-37 (G68.3 type 1): the origin is the current point, Zc the tool as it stands;
/// after G43 H1 and X0 Y0 Z0 the tip (100 mm tool) is at that point. The current point is the
/// programmed one, the nose at zero angles (Syntec's 1.7 normalisation, Q-16), so the carriage
/// moves by ΔM = (h + L)·t − h·ẑ with the head-bc pivot h = 150 above the nose.
#[test]
fn syntec_tv37_g68_3_origin_at_the_current_point() {
    let src = "N1 G90 G01 X0. Y0. Z0. F1000.\nN2 B-45.\nN3 G68.3\nN4 G43 H1\nN5 X0. Y0. Z0.\nN6 G69 G49\nM30\n";
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let e = ends("head-bc", Dialect::Syntec, src);
    let (n2, n5) = (end_of(&e, 2), end_of(&e, 5));
    let t = Vec3::new(-1.0, 0.0, 1.0).normalize();
    assert!(close(kin.forward(&n2, 0.0).tool, t, 1e-12));
    assert!(close(kin.forward(&n5, 100.0).tip, Vec3::zeros(), 1e-9));
    let shift = Vec3::new(n5[0] - n2[0], n5[1] - n2[1], n5[2] - n2[2]);
    assert!(close(shift, 250.0 * t - 150.0 * Vec3::z(), 1e-9), "{shift:?}");
}

/// Syntec TV-38 (G68.3 repeated, each relative to the work system, X from P × Zc with P = +Z):
/// on a C–A head, frame 1 after A90 (t = −Y) has Xc = +X, Yc = +Z; frame 2 after C90 (t = +X)
/// has Xc = +Y, Yc = +Z and origin G55 (10, 0, 0); N4 and N7 both reach G55 (10, 0, 0).
#[test]
fn syntec_tv38_g68_3_twice_relative_to_the_work_system() {
    let src = "N1 G55\nN2 G01 A90. F1000.\nN3 G68.3 X0 Y0 Z0 R0\nN4 X10. Y0. Z0.\nN5 C90.\n\
               N6 G68.3 X10. Y0. Z0. R0\nN7 X0. Y0. Z0.\nN8 G69\nM30\n";
    let m = head_ca();
    let kin = Kinematics::new(&m).unwrap();
    let e = motion_ends(interpreter_with(src, "head-bc", Dialect::Syntec, |c| c.machine = m.clone().into()));
    assert!(close(kin.forward(&end_of(&e, 2), 0.0).tool, -Vec3::y(), 1e-12));
    assert!(close(kin.forward(&end_of(&e, 5), 0.0).tool, Vec3::x(), 1e-12));
    for line in [4, 7] {
        let tip = kin.forward(&end_of(&e, line), 0.0).tip;
        assert!(close(tip, Vec3::new(10.0, 0.0, 0.0), 1e-9), "N{line}: {tip:?}");
    }
}

/// G68.3's X axis is P × Zc with P the vertical axis of No.12321 (`manual.vertical`; 0: the
/// reference tool direction's axis, Z on head-bc): with the tool along (0, −0.707, 0.707) feature X
/// is +X for P = Z and (0, −0.707, −0.707) for P = X.
#[test]
fn g68_3_x_axis_from_no_12321() {
    use fivex_engine::machine::ManualVertical;
    let src = "N1 G90 G01 X0 Y0 Z0 F1000\nN2 B-45. C90.\nN3 G68.3 X0 Y0 Z0\nN4 G01 X10. Y0 Z0\nN5 G69\nM30\n";
    let h = 10.0 * std::f64::consts::FRAC_1_SQRT_2;
    for (vertical, want) in [
        (ManualVertical::Tool, Vec3::new(10.0, 0.0, 0.0)),
        (ManualVertical::Z, Vec3::new(10.0, 0.0, 0.0)),
        (ManualVertical::X, Vec3::new(0.0, -h, -h)),
    ] {
        let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
        let e = motion_ends(interpreter_with(src, "head-bc", Dialect::Syntec, |c| {
            c.edit_machine(|m| m.manual.vertical = vertical)
        }));
        // The origin is the programmed point (the nose at zero angles); N4 is 10 along X_c from it.
        let (n3_origin, n4) = (Vec3::zeros(), kin.forward(&end_of(&e, 4), 0.0).tip);
        assert!(close(n4 - n3_origin, want, 1e-9), "{vertical:?}: {n4:?}");
    }
}

/// The reference returns in the plane (FANUC, and Syntec's G68.2): twp §1.3.2 lists G28, G29
/// and G30 among the plane's commands and TWP-13 puts the return itself in machine
/// coordinates; the intermediate point is an FCS point (OQ-16), as is G29's end point. The
/// plane `G68.2 X10 Y20 Z5 I0 J30 K0` by hand: Xc (1, 0, 0), Yc (0, cos 30°, sin 30°),
/// Zc (0, −sin 30°, cos 30°), origin (10, 20, 5); G54 is zero, so WCS points are table points.
const RETURNS_IN_PLANE: &str = "G90 G17 G49 G40 G80\nG00 X0 Y0 Z100.\nG68.2 X10. Y20. Z5. I0 J30. K0\nG53.1\n\
                                G43 H1\nG00 X5. Y5. Z50.\nG91 G28 Z0\nG90 G00 X5. Y5. Z50.\nG91 G30 Z0\n\
                                G90 G00 X5. Y5. Z50.\nG28 X5. Y5. Z50.\nG29 X10. Y10. Z40.\nG49\nG69\nM30\n";

#[test]
fn reference_returns_in_the_plane_go_through_fcs_points() {
    let (s, c) = (0.5, 3f64.sqrt() / 2.0);
    let fcs = |p: [f64; 3]| {
        Vec3::new(10.0, 20.0, 5.0) + p[0] * Vec3::x() + p[1] * Vec3::new(0.0, c, s) + p[2] * Vec3::new(0.0, -s, c)
    };
    let same = |a: &Pos, b: &Pos| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
    for dialect in [Dialect::Fanuc, Dialect::Syntec] {
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let m = MachineConfig::preset(preset).unwrap();
            let kin = Kinematics::new(&m).unwrap();
            let e = ends(preset, dialect, RETURNS_IN_PLANE);
            let of = |line: u32| e.iter().filter(|(l, _)| *l == line).map(|(_, p)| *p).collect::<Vec<_>>();
            // `G91 G28 Z0` / `G91 G30 Z0` after the tip went to FCS (5, 5, 50): the intermediate
            // point is where the tip stands, then machine Z alone goes to the reference position (0).
            for (line, before) in [(7, 6), (9, 8)] {
                let here = end_of(&e, before);
                let legs = of(line);
                assert_eq!(legs.len(), 2, "{preset} {dialect:?} line {line}: {legs:?}");
                assert!(
                    same(&legs[0], &here),
                    "{preset} {dialect:?} line {line}: intermediate {:?} from {here:?}",
                    legs[0]
                );
                let mut back = here;
                back[2] = 0.0;
                assert!(same(&legs[1], &back), "{preset} {dialect:?} line {line}: return {:?}", legs[1]);
            }
            // `G28 X5. Y5. Z50.`: the intermediate point is the current FCS point again.
            let legs = of(11);
            assert!(same(&legs[0], &end_of(&e, 10)), "{preset} {dialect:?}: G28 X5 Y5 Z50 {:?}", legs[0]);
            // G29: through the intermediate point to FCS (10, 10, 40), the tool along Zc.
            let legs = of(12);
            let mid = kin.forward(&legs[0], 100.0).tip;
            assert!(close(mid, fcs([5.0, 5.0, 50.0]), 1e-6), "{preset} {dialect:?}: G29 via {mid:?}");
            let end = kin.forward(legs.last().unwrap(), 100.0);
            assert!(close(end.tip, fcs([10.0, 10.0, 40.0]), 1e-6), "{preset} {dialect:?}: G29 to {:?}", end.tip);
            assert!(close(end.tool, Vec3::new(0.0, -s, c), 1e-9), "{preset} {dialect:?}: tool {:?}", end.tool);
        }
    }
}

/// The same program run: it completes, and the axes keep their limits — the speed bound holds
/// across block ends too, so no block starts from a point the machine is not at (before, the
/// block after G29 was planned from where the machine had been before it).
#[test]
fn reference_returns_in_the_plane_run_continuously() {
    use fivex_engine::run::{run, RunOptions};
    for dialect in [Dialect::Fanuc, Dialect::Syntec] {
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let mut interp = interpreter_with(RETURNS_IN_PLANE, preset, dialect, |_| {});
            let mut samples = Vec::new();
            let r = run(&mut interp, &RunOptions { period_s: 0.001, ..RunOptions::default() }, |s| samples.push(*s));
            assert!(r.completed(), "{preset} {dialect:?}: {:?}", r.alarms);
            let m = MachineConfig::preset(preset).unwrap();
            if let Err(e) = common::check_limits_of(&samples, &m, false) {
                panic!("{preset} {dialect:?}: {e}");
            }
        }
    }
}
