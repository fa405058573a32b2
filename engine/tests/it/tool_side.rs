//! Tool side offset of 5-axis cutter compensation, type 1 (G41.2/G42.2, `stage::tool_side`):
//! the manual's vectors worked out by hand, the rule that defines it checked against cutter
//! compensation C (the same corners in the plane perpendicular to the tool, whatever the tool's
//! direction and whatever part of the moves runs along it), the interference check at a change
//! of the compensation plane, and what is still refused. Tool offsets have radius 5, length 100.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::interp::Step;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::stage::Pipeline;
use fivex_engine::Dialect::Fanuc;

const H: f64 = std::f64::consts::FRAC_1_SQRT_2 * 5.0;

#[test]
fn tv09_a_corner_in_the_plane_of_a_tilted_tool() {
    // head-bc at B45 C-90: the tool (0, −0.7071, 0.7071). From (−50,0,0) along X to (100,0,0),
    // then to (100,100,100): in the plane e2 = X, e3 = (0, 0.7071, 0.7071) a 90° left turn.
    // The start-up block ends perpendicular to X in the plane (type A): 5 along e3. G41.2
    // (inside): VD = −5 e2 + 5 e3 = (−5, 3.5355, 3.5355); the last block before G40 ends
    // perpendicular to itself (−5 e2), then the cancel moves to the programmed point.
    // G42.2 (outside at the corner, α = 90°): the offset lines' intersection, VD = (5, −3.5355,
    // −3.5355); the turn into the cancel is an inside corner for it: the intersection again.
    let prog = |g: &str| {
        format!("G90 G00 X-50. Y0 Z0 B45. C-90.\n{g} D1\nG01 X0 F1000.\nX100.\nY100. Z100.\nG40 X150.\nM30\n")
    };
    let moves = |first: [f64; 3], corner: [f64; 3], last: [f64; 3]| {
        vec![(1, [-50.0, 0.0, 0.0]), (3, first), (4, corner), (5, last), (6, [150.0, 100.0, 100.0])]
    };
    assert_ends(&prog("G41.2"), "head-bc", &moves([0.0, H, H], [95.0, H, H], [95.0, 100.0, 100.0]));
    assert_ends(&prog("G42.2"), "head-bc", &moves([0.0, -H, -H], [105.0, -H, -H], [105.0, 100.0 - H, 100.0 - H]));
}

#[test]
fn tv09_the_same_under_tool_centre_point_control() {
    // G43.4 first, G40 before G49 (§3.5.2): the tip goes where the vectors say; the axes put it
    // there (checked for every motion by `ends_of`).
    let src = "G90 G00 X-50. Y0 Z0 B0 C0\nG43.4 H1\nG00 B45. C-90.\nG41.2 D1\nG01 X0 F1000.\nX100.\n\
               Y100. Z100.\nG40 X150.\nG49\nM30\n";
    let got = ends_of(src, "head-bc");
    assert_eq!(got.alarm, None);
    let at = |line: u32| got.ends.iter().find(|(l, _)| *l == line).unwrap().1;
    assert!((at(6) - Vec3::new(95.0, H, H)).norm() < 1e-9, "{:?}", at(6));
    assert!((at(7) - Vec3::new(95.0, 100.0, 100.0)).norm() < 1e-9, "{:?}", at(7));
}

/// The moves `blocks` (axis words, the two rotary angles at the end) of `preset` twice: with the
/// rotary words `letters` (type 1), and with the tool directions they give as I/J/K (type 2).
fn both_types(preset: &str, letters: (char, char), blocks: &[(&str, f64, f64)]) -> (String, String) {
    let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
    let (mut type1, mut type2) = (String::new(), String::new());
    for (k, (xyz, p, q)) in blocks.iter().enumerate() {
        let mut pos = [0.0; 8];
        (pos[3], pos[4]) = (*p, *q);
        let t = kin.forward(&pos, 0.0).tool;
        let feed = if k == 0 { " F1000." } else { "" };
        type1 += &format!("G01 {xyz} {}{p:.3} {}{q:.3}{feed}\n", letters.0, letters.1);
        type2 += &format!("G01 {xyz} I{:.9} J{:.9} K{:.9}{feed}\n", t.x, t.y, t.z);
    }
    (type1, type2)
}

#[test]
fn type_2_under_g43_5_places_the_tip_as_type_1_with_the_same_tool_directions() {
    // G41.6 with the tool given by I/J/K at each block end (G43.5 turns them into angles) and
    // G41.2 with the same directions given by B/C: the same tool tip at every block end.
    let blocks =
        [("X0", 45.0, -90.0), ("X100.", 30.0, -60.0), ("Y100. Z60.", 20.0, -120.0), ("X20. Y80.", 35.0, -90.0)];
    let (type1, type2) = both_types("head-bc", ('B', 'C'), &blocks);
    let start = "G90 G00 X-50. Y0 Z0 B45. C-90.\n";
    let end = "G40 X-50.\nG49\nM30\n";
    let one = ends_of(&format!("{start}G43.4 H1\nG41.2 D1\n{type1}{end}"), "head-bc");
    let two = ends_of(&format!("{start}G43.5 H1\nG41.6 D1\n{type2}{end}"), "head-bc");
    assert_eq!((&one.alarm, &two.alarm), (&None, &None));
    let tips = |e: &Ends| e.ends.iter().filter(|(l, _)| (5..=9).contains(l)).map(|(l, p)| (*l, *p)).collect::<Vec<_>>();
    let (a, b) = (tips(&one), tips(&two));
    assert_eq!(a.len(), 5, "{a:?}");
    assert_eq!(a.len(), b.len());
    for ((l1, p), (l2, q)) in a.iter().zip(&b) {
        assert!(l1 == l2 && (p - q).norm() < 1e-6, "line {l1}: type 1 {p:?}, type 2 {q:?}");
    }
    // Compensated: the tip is not on the programmed X100. line end (100, 0, 0).
    assert!((a[1].1 - Vec3::new(100.0, 0.0, 0.0)).norm() > 4.0, "{a:?}");
}

#[test]
fn type_2_on_a_table_machine_takes_i_j_k_after_its_g41_6_block() {
    // §3.2.1: "In a tool rotation type machine, I, J, and K can be specified in a G41.6/G42.6
    // command block; in a table rotation type machine, however, they cannot" — in that block
    // only: the blocks after it give the tool's direction by I/J/K as on any machine. On table-ac
    // in the table coordinate system (TBP = 1, WKP = 0): the tips of type 1 with A/C words for
    // the same directions.
    let blocks = [("X0 Y0", -20.0, 0.0), ("X60.", -30.0, 45.0), ("Y50. Z10.", -25.0, 90.0), ("X10. Y40.", -20.0, 60.0)];
    let (type1, type2) = both_types("table-ac", ('A', 'C'), &blocks);
    let table = |c: &mut fivex_engine::interp::Config| c.edit_machine(|m| m.five_axis.crc_table_coordinates = true);
    let (start, end) = ("G90 G00 X-50. Y0 Z50. A0 C0\n", "G40 X-50.\nG49\nM30\n");
    let one = ends_with(&format!("{start}G43.4 H1\nG41.2 D1\n{type1}{end}"), "table-ac", table);
    let two = ends_with(&format!("{start}G43.5 H1\nG41.6 D1\n{type2}{end}"), "table-ac", table);
    assert_eq!((&one.alarm, &two.alarm), (&None, &None));
    let tips = |e: &Ends| e.ends.iter().filter(|(l, _)| (4..=8).contains(l)).map(|(l, p)| (*l, *p)).collect::<Vec<_>>();
    let (a, b) = (tips(&one), tips(&two));
    assert!(a.len() >= 5 && a.len() == b.len(), "{a:?}\n{b:?}");
    for ((l1, p), (l2, q)) in a.iter().zip(&b) {
        assert!(l1 == l2 && (p - q).norm() < 1e-6, "line {l1}: type 1 {p:?}, type 2 {q:?}");
    }
    // In the G41.6 block itself I/J/K stay PS5460.
    let in_block = format!("{start}G43.5 H1\nG41.6 D1 I0 J0 K1.\n{type2}{end}");
    assert_eq!(ends_with(&in_block, "table-ac", table).alarm, Some(("PS5460".into(), 3)));
}

/// `contour` from (-10, -10) under G41 on mill3 and under G41.2 on head-bc (the tool vertical).
fn g41_and_g41_2(contour: &str) -> (Ends, Ends) {
    let start = "G90 G00 X-10. Y-10. Z0\n";
    (ends_of(&format!("{start}G41 D1\n{contour}"), "mill3"), ends_of(&format!("{start}G41.2 D1\n{contour}"), "head-bc"))
}

#[test]
fn a_vertical_tool_compensates_as_g41_in_g17() {
    // With the tool along Z the plane is XY: the same tool centre as cutter compensation C.
    let (g41, g41_2) = g41_and_g41_2("G01 X0 Y0 F500.\nX40.\nY40.\nX20. Y25.\nX0 Y40.\nY0\nG40 Y-10.\nM30\n");
    assert_eq!((&g41.alarm, &g41_2.alarm), (&None, &None));
    assert_eq!(g41.ends.len(), g41_2.ends.len());
    assert_eq!(g41.ends.len(), 8, "the start, the start-up, 5 blocks, the cancel");
    for ((l1, a), (l2, b)) in g41.ends.iter().zip(&g41_2.ends) {
        assert_eq!(l1, l2);
        assert!((a - b).norm() < 1e-9, "line {l1}: {a:?} {b:?}");
    }
}

#[test]
fn arcs_seen_along_their_normal_compensate_as_g41_in_their_plane() {
    // CRC-16: with the tool along the circles' normal the projection changes nothing: the tool
    // vertical and G17, or the tool along +X (B90) and G19, give cutter compensation C's tool
    // centre (tangent and non-tangent arcs, inside and outside, both sides).
    let contour = |a: &str, b: &str| {
        format!(
            "G01 {a}0 {b}0 F500.\n{a}40.\nG03 {a}60. {b}20. R20.\nG01 {b}40.\nG02 {a}40. {b}60. R25.\nG01 {a}10.\n\
             G03 {a}0 {b}50. R10.\nG01 {b}0\nG40 {b}-10.\nM30\n"
        )
    };
    for side in ["G41", "G42"] {
        for (plane, a, b, angles, start) in
            [("G17", "X", "Y", "B0 C0", "X-10. Y-10. Z0"), ("G19", "Y", "Z", "B90. C0", "X0 Y-10. Z-10.")]
        {
            let conventional = format!("G90 {plane} G00 {start}\n{side} D1\n{}", contour(a, b));
            let tool_side = format!("G90 {plane} G00 {start} {angles}\n{side}.2 D1\n{}", contour(a, b));
            let (c, t) = (ends_of(&conventional, "mill3"), ends_of(&tool_side, "head-bc"));
            assert_eq!((&c.alarm, &t.alarm), (&None, &None), "{side} {plane}");
            assert!(c.ends.len() >= 10, "{side} {plane}: {:?}", c.ends);
            assert_eq!(c.ends.len(), t.ends.len(), "{side} {plane}");
            for ((l1, p), (l2, q)) in c.ends.iter().zip(&t.ends) {
                assert!(l1 == l2 && (p - q).norm() < 1e-9, "{side} {plane} line {l1}: {p:?} {q:?}");
            }
            // And the run moves through them (the executor takes the reshaped circles).
            let r = run_with(&tool_side, "head-bc", Fanuc);
            assert!(r.completed(), "{side} {plane}: {:?}", r.alarms);
        }
        // A tilted tool sees the circles as ellipses, which the corner rules do not place
        // vectors on: refused at the first circle (not built).
        let tilted = format!("G90 G17 G00 X-10. Y-10. Z0 B30. C20.\n{side}.2 D1\n{}", contour("X", "Y"));
        assert_eq!(ends_of(&tilted, "head-bc").alarm, Some(("PS0010".into(), 5)), "{side}");
    }
}

#[test]
fn an_arc_under_tcp_runs_with_its_tip_on_the_offset_circle() {
    // G43.4, the tool vertical: a G02 half circle of radius 20 about (20, 0) over the top, the
    // tool (R5) on the left of the travel, outside it: every sample of the run has its tip
    // (forward kinematics) at 25 from the centre while the block runs.
    let src = "G90 G00 X0 Y-20. Z0 B0 C0\nG43.4 H1\nG41.2 D1\nG01 X0 Y0 F1000.\nG02 X40. Y0 R20.\nG01 Y-20.\nG40 X50.\nG49\nM30\n";
    let got = ends_of(src, "head-bc");
    assert_eq!(got.alarm, None);
    let mut interp = interpreter(src, "head-bc", Fanuc);
    let mut radii = Vec::new();
    let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
        if s.line == 5 {
            radii.push(((s.tip[0] - 20.0).powi(2) + s.tip[1].powi(2)).sqrt());
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(radii.len() > 100, "{}", radii.len());
    assert!(
        radii.iter().all(|d| (d - 25.0).abs() < 1e-3),
        "{:?}",
        radii.iter().cloned().fold((f64::MAX, 0.0f64), |a, d| (a.0.min(d), a.1.max(d)))
    );
}

#[test]
fn an_arc_as_the_start_up_block_is_ps0034() {
    let src = "G90 G00 X-20. Y0 Z0\nG41.2 D1\nG02 X20. Y0 R20. F500.\nG40 X30.\nM30\n";
    assert_eq!(ends_of(src, "head-bc").alarm, Some(("PS0034".into(), 3)));
}

#[test]
fn no_19632_places_the_vectors_at_the_cutting_points() {
    // CRC-30 / M-11 (TV-16's formula QT = Q + LC·(sin b cos c, sin b sin c, cos b), here the
    // tool direction of head-bc at B, C), LC = 100. N3 X100 with the tool vertical, N4 Y100
    // turning B to 20°: the cutting points P_T = (0,0,100), Q_T = (100,0,100) and
    // R_T = (100,100,0) + 100 (sin20, 0, cos20). In the plane of Q (XY) the inside corner of
    // G41.2 is where y = 5 meets the line Q_T→R_T offset by 5 to its left; the vector from Q_T
    // is added to the programmed (pivot) point Q = (100, 0, 0).
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.2 D1\nG01 X100. F500.\nY100. B20.\nG40 X200.\nM30\n";
    let s20 = 20f64.to_radians().sin();
    let d = Vec3::new(100.0 * s20, 100.0, 0.0).normalize(); // Q_T → R_T seen in XY
    let n = Vec3::new(-d.y, d.x, 0.0);
    let t = (5.0 - 5.0 * n.y) / d.y;
    let want = [100.0 + 5.0 * n.x + t * d.x, 5.0, 0.0];
    let mut interp =
        interpreter_with(src, "head-bc", Fanuc, |c| c.edit_machine(|m| m.five_axis.cutting_point_distance = 100.0));
    let mut stages = Pipeline::for_config(interp.config());
    let mut out = Vec::new();
    let mut ends = Vec::new();
    while let Ok(Step::Continue) = interp.step(&mut out) {
        assert!(stages.process(&mut out, false).is_none());
        for c in out.drain(..) {
            if let CanonKind::Motion(m) = c.kind {
                ends.push((c.line, [m.target[0], m.target[1], m.target[2]]));
            }
        }
    }
    let n3 = ends.iter().find(|(l, _)| *l == 3).unwrap().1;
    assert!((Vec3::from(n3) - Vec3::from(want)).norm() < 1e-9, "{n3:?} want {want:?}");
    // At the programmed points instead (No.19632 = 0): the 90° corner, (95, 5, 0).
    let plain = ends_of(src, "head-bc");
    assert!((plain.ends[1].1 - Vec3::new(95.0, 5.0, 0.0)).norm() < 1e-9, "{:?}", plain.ends);
}

/// CRC-11 (§3.1.2 (2)): the moves inserted at an outside corner lie before the single-block stop
/// point of the block that ends there, so they run at that block's feed — here F1000, though
/// the next block gives F500 — and belong to its line (the controller stops after them).
#[test]
fn crc11_the_corner_moves_run_at_the_feed_of_the_block_before_them() {
    // G41.2 with the tool along Z: a right turn of 153° is an outside corner under 90°, two
    // lengthened vectors joined by a straight move (CRC-10).
    let src = "G90 G00 X-10. Y0 Z0 B0 C0\nG41.2 D1 G01 X0 F1000.\nX20.\nX0 Y-10. F500.\nG40 X-10.\nM30\n";
    let mut at_corner = Vec::new();
    let alarm = through_stages(interpreter(src, "head-bc", Fanuc), |c| {
        if let CanonKind::Motion(m) = c.kind {
            if c.line == 3 {
                at_corner.push(m.feed);
            }
        }
    });
    assert_eq!(alarm, None);
    // The block itself (to the first lengthened vector) and the corner's inserted move (to the
    // second), both at F1000.
    assert_eq!(at_corner, vec![1000.0; 2], "line 3's motions: {at_corner:?}");
}

fn spg(c: &mut fivex_engine::interp::Config) {
    c.edit_machine(|m| m.five_axis.crc_codes_by_mechanism = true);
}

/// TV-17 (CRC-31, CRC-32): SPG (No.19607#1) selects the tool side offset's codes by mechanism —
/// G41.4/G42.4 on a table machine, G41.5/G42.5 on a mixed one; the other family there, or a
/// code of another mechanism, is PS5460; without SPG G41.4/G41.5 are PS0010 (fivex: on every
/// machine) and G41.2/G42.2 run everywhere.
#[test]
fn tv17_the_codes_follow_spg_and_the_mechanism() {
    let cases: &[(&str, bool, &str, Option<&str>)] = &[
        ("table-ac", false, "G41.4", Some("PS0010")),
        ("table-ac", false, "G42.4", Some("PS0010")),
        ("table-ac", true, "G41.4", None),
        ("table-ac", true, "G42.4", None),
        ("table-ac", true, "G41.2", Some("PS5460")),
        ("table-ac", false, "G41.2", None),
        ("table-ac", true, "G41.5", Some("PS5460")),
        ("mixed-bc", false, "G41.5", Some("PS0010")),
        ("mixed-bc", true, "G41.5", None),
        ("mixed-bc", true, "G42.5", None),
        ("mixed-bc", true, "G42.2", Some("PS5460")),
        ("mixed-bc", true, "G41.4", Some("PS5460")),
        ("mixed-bc", false, "G41.2", None),
        ("head-bc", true, "G41.2", None),
        ("head-bc", true, "G41.4", Some("PS5460")),
        ("head-bc", true, "G41.5", Some("PS5460")),
        ("head-bc", false, "G41.4", Some("PS0010")),
        ("mill3", false, "G41.5", Some("PS0010")),
    ];
    for &(preset, on, code, want) in cases {
        let src = format!("G90 G00 X-10. Y-10. Z0\n{code} D1\nG01 X0 Y0 F500.\nX40.\nG40 Y-10.\nM30\n");
        let got = if on { first_alarm_with(&src, preset, spg) } else { first_alarm(&src, preset) };
        let want = want.map(|w| (w.to_string(), 2));
        assert_eq!(got, want, "{preset} SPG={on} {code}");
    }
}

/// With SPG, G41.4/G42.4 on a table machine and G41.5/G42.5 on a mixed one compensate exactly as
/// G41.2/G42.2 does there without it.
#[test]
fn with_spg_the_mechanism_codes_compensate_as_g41_2() {
    let contour = "G01 X0 Y0 F500.\nX40.\nY40.\nX20. Y25.\nX0 Y40.\nY0\nG40 Y-10.\nM30\n";
    for (preset, turned, codes) in
        [("table-ac", "A30. C40.", ["G41.4", "G42.4"]), ("mixed-bc", "B20. C40.", ["G41.5", "G42.5"])]
    {
        for (code, plain) in codes.iter().zip(["G41.2", "G42.2"]) {
            let start = format!("G90 G00 X-10. Y-10. Z0 {turned}\n");
            let by_mechanism = ends_with(&format!("{start}{code} D1\n{contour}"), preset, spg);
            let g41_2 = ends_of(&format!("{start}{plain} D1\n{contour}"), preset);
            assert_eq!((&by_mechanism.alarm, &g41_2.alarm), (&None, &None), "{preset} {code}");
            assert_eq!(by_mechanism.ends, g41_2.ends, "{preset} {code}");
            // And the compensation did something: the corner at X40 Y0 is off the contour.
            let corner = g41_2.ends.iter().find(|(l, _)| *l == 4).unwrap().1;
            assert!((corner.xy() - nalgebra::Vector2::new(40.0, 0.0)).norm() > 4.0, "{preset} {code}: {corner:?}");
        }
    }
}

#[test]
fn on_a_table_machine_the_plane_is_perpendicular_to_the_fixed_tool() {
    // table-ac, the table turned (A30 C40): without TCP the program is in the workpiece system,
    // which does not turn with the table (TBP = 0), and the tool stands along Z: the tool side
    // offset is cutter compensation C in XY.
    let contour = "G01 X0 Y0 F500.\nX40.\nY40.\nX20. Y25.\nX0 Y40.\nY0\nG40 Y-10.\nM30\n";
    let g41 = ends_of(&format!("G90 G00 X-10. Y-10. Z0\nG41 D1\n{contour}"), "mill3");
    let g41_2 = ends_of(&format!("G90 G00 X-10. Y-10. Z0 A30. C40.\nG41.2 D1\n{contour}"), "table-ac");
    assert_eq!((&g41.alarm, &g41_2.alarm), (&None, &None));
    assert_eq!(g41.ends.len(), g41_2.ends.len());
    for ((l1, a), (l2, b)) in g41.ends.iter().zip(&g41_2.ends) {
        assert!(l1 == l2 && (a - b).norm() < 1e-9, "line {l1}: {a:?} {b:?}");
    }
    // Under TCP in the workpiece system (WKP = 1) the tip follows the same offset path, the
    // table turning under it (the machine axes carry the tip: forward kinematics); with Π on
    // the table (WKP = 0, the default) TCP and compensation would be in two systems: PS5460
    // (TV-24).
    let tcp = format!("G90 G00 X-10. Y-10. Z0 A0 C0\nG43.4 H1\nG00 A30. C40.\nG41.2 D1\n{contour}")
        .replace("M30", "G49\nM30");
    let workpiece = |c: &mut fivex_engine::interp::Config| {
        c.edit_machine(|m| m.five_axis.tcp_coordinates = fivex_engine::machine::TcpCoordinates::Workpiece)
    };
    let kin = Kinematics::new(&MachineConfig::preset("table-ac").unwrap()).unwrap();
    let mut ends = Vec::new();
    let alarm = through_stages(interpreter_with(&tcp, "table-ac", Fanuc, workpiece), |c| {
        if let CanonKind::Motion(m) = c.kind {
            if let Some(t) = m.tip.as_deref() {
                assert!((kin.forward(&m.machine, 100.0).tip - t.to).norm() < 1e-9, "line {}", c.line);
                // The tip in the workpiece system: machine directions (the frame only turns
                // the table's frame back).
                ends.push((c.line, t.frame.r.transpose() * (t.to - t.frame.o)));
            }
        }
    });
    assert_eq!(alarm, None);
    let ends: Vec<_> = ends.into_iter().filter(|(l, _)| *l >= 5).collect();
    let planar: Vec<_> = g41.ends.iter().filter(|(l, _)| *l >= 3).collect();
    assert_eq!(ends.len(), planar.len(), "{ends:?}");
    for ((l1, p), (l2, q)) in ends.iter().zip(planar) {
        assert!(l1 - 2 == *l2 && (p.xy() - q.xy()).norm() < 1e-6, "line {l1}: {p:?} {q:?}");
    }
    assert_eq!(first_alarm(&tcp, "table-ac"), Some(("PS5460".into(), 4)));
}

#[test]
fn tv07_changing_the_side_retraces_the_block() {
    // (3)-1: G42.2 in the returning block: the tool comes back on the same line (start, end
    // and the cancel's start all 5 to the left of +X).
    let src = "G90 G00 X0 Y0 Z0\nG41.2 D1\nG91 G01 X100. F500.\nG42.2 X-100.\nG90 G40 Y-20.\nM30\n";
    assert_ends(
        src,
        "head-bc",
        // (The change of side joins the two perpendicular vectors by a move, here of length 0.)
        &[
            (1, [0.0, 0.0, 0.0]),
            (3, [100.0, 5.0, 0.0]),
            (3, [100.0, 5.0, 0.0]),
            (4, [0.0, 5.0, 0.0]),
            (5, [0.0, -20.0, 0.0]),
        ],
    );
}

#[test]
fn blocks_without_a_command_count_under_g41_2_as_under_g41() {
    // M08 and G90 between two sides are two blocks without movement: the vector is lost, the
    // side X40. ends perpendicular to itself at (40, 5) under both (`cutter.rs`,
    // `a_block_that_gives_no_command_is_a_block_without_motion`).
    let (g41, g41_2) = g41_and_g41_2("G01 X0 Y0 F500.\nX40.\nM08\nG90\nY40.\nG40 X0.\nM30\n");
    assert_eq!((&g41.alarm, &g41_2.alarm), (&None, &None));
    for got in [&g41, &g41_2] {
        let side = got.ends.iter().find(|(l, _)| *l == 4).map(|(_, p)| *p);
        assert!(side.is_some_and(|p| (p - Vec3::new(40.0, 5.0, 0.0)).norm() < 1e-9), "{:?}", got.ends);
    }
    assert_eq!(g41.ends.len(), g41_2.ends.len());
}

#[test]
fn a_rotary_axis_alone_keeps_the_vector_and_the_corner_takes_the_next_move() {
    // CRC-14: N4 turns B only; the corner at the end of N3 is made with N5, and N4 ends at
    // the same vector. Tool vertical at N3's end: the corner is in XY, (95, 5, 0); B then tilts
    // the tool about Y, which leaves that vector perpendicular to it.
    let src = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X100. F500.\nB20.\nY100.\nG40 Y150.\nM30\n";
    let got = ends_of(src, "head-bc");
    assert_eq!(got.alarm, None);
    let ends: Vec<(u32, [f64; 3])> = got.ends.iter().map(|(l, p)| (*l, [p.x, p.y, p.z])).collect();
    let near = |a: [f64; 3], b: [f64; 3]| (Vec3::from(a) - Vec3::from(b)).norm() < 1e-9;
    assert_eq!(ends.iter().map(|e| e.0).collect::<Vec<_>>(), [1, 3, 4, 5, 6]);
    assert!(near(ends[1].1, [95.0, 5.0, 0.0]) && near(ends[2].1, [95.0, 5.0, 0.0]), "{ends:?}");
    // N5 in the plane of the tilted tool (B20: (sin20, 0, cos20)) ends perpendicular to itself
    // there: Y is in that plane, its left seen from the tool is −(tool × Y)... = −e where
    // e = Y × tool; 5 × (−cos20, 0, sin20).
    let (s, c) = 20f64.to_radians().sin_cos();
    assert!(near(ends[3].1, [100.0 - 5.0 * c, 100.0, 5.0 * s]), "{ends:?}");
}

#[test]
fn tv01_a_change_of_plane_that_reverses_the_path_is_ps0041() {
    // The manual's program turned 90° about Z for head-bc (B tilts about Y): the tool at
    // B46 (0.7193, 0, 0.6947) along N4, B−45 (−0.7071, 0, 0.7071) along N6 after the
    // rotary-only N5; the tool turns 91° ≥ 45° (No.19635 = 0), the vectors N4 and N6 would
    // get point the same way, and N6 runs against N4 seen in N4's plane.
    let tv01 = |n6: &str| {
        format!(
            "G90 G00 X0 Y0 Z0 B46. C0\nG41.2 D1\nG01 Y100. F3000.\nX200. Z-200.\nB-45.\n{n6}\nY0\n\
             X200. Z-200.\nB46.\nX0 Z0\nG40 Y-50.\nM30\n"
        )
    };
    let got = ends_of(&tv01("X400. Z0"), "head-bc");
    assert_eq!(got.alarm, Some(("PS0041".to_string(), 4)), "{:?}", got.ends);
    // TV-02…TV-05: Q in N4, or G41.2 again in N6, answer the check instead of the alarm. In N4's
    // plane its move runs along t = (0.6947, 0, −0.7193) and its perpendicular vector (left seen
    // from the tool) is n = (0, 5, 0); the corner against N6 gives two vectors, n + 5t and the
    // other side's (Q3 keeps both, Q2 the first, Q1 and G41.2 only n).
    let n4_ends = |src: &str| {
        let got = ends_of(src, "head-bc");
        assert_eq!(got.alarm, None, "{src}");
        got.ends.iter().filter(|(l, _)| *l == 4).map(|(_, p)| [p.x, p.y, p.z]).collect::<Vec<_>>()
    };
    let near = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.len() == b.len() && a.iter().zip(b).all(|(p, q)| (Vec3::from(*p) - Vec3::from(*q)).norm() < 1e-5)
    };
    let (n, v1, v2) = ([200.0, 105.0, -200.0], [203.473292, 105.0, -203.596699], [203.473292, 95.0, -203.596699]);
    for (src, want) in [
        (tv01("X400. Z0").replace("X200. Z-200.\nB-45.", "X200. Z-200. Q1\nB-45."), vec![n]),
        (tv01("G41.2 X400. Z0"), vec![n]),
        (tv01("X400. Z0").replace("X200. Z-200.\nB-45.", "X200. Z-200. Q2\nB-45."), vec![v1]),
        (tv01("X400. Z0").replace("X200. Z-200.\nB-45.", "X200. Z-200. Q3\nB-45."), vec![v1, v2]),
    ] {
        let got = n4_ends(&src);
        assert!(near(&got, &want), "got {got:?} want {want:?}\n{src}");
    }
    // Q where the check does not stop the block changes nothing (decision: Q answers the
    // check); a Q other than 1–3 is refused.
    let plain = "G90 G00 X0 Y0 Z0\nG41.2 D1\nG01 X50. F500.\nY50.\nG40 X0\nM30\n";
    assert_eq!(ends_of(plain, "head-bc").ends, ends_of(&plain.replace("X50. F500.", "X50. F500. Q1"), "head-bc").ends);
    assert_eq!(ends_of(&plain.replace("Y50.", "Y50. Q4"), "head-bc").alarm, Some(("PS0010".into(), 4)));
    // TV-06: No.19635 = 95°: the tool's 91° turn is no plane change, no PS0041 from that check.
    let wide = |c: &mut fivex_engine::interp::Config| c.edit_machine(|m| m.five_axis.plane_change_angle = 95.0);
    assert_ne!(first_alarm_with(&tv01("X400. Z0"), "head-bc", wide).map(|a| a.1), Some(4));
    // A tool that turns less (B30 at N5: 16°) is no plane change: no PS0041 from that check.
    let src = tv01("X400. Z0").replace("B-45.", "B30.");
    let got = ends_of(&src, "head-bc");
    assert_ne!(got.alarm.as_ref().map(|a| a.1), Some(4), "{:?}", got.alarm);
}

#[test]
fn what_the_tool_side_offset_does_not_perform_stays_refused() {
    let cases = [
        ("G41.2 D1 G01 X10. F500\nG93 X20. F10.\n", 2, "head-bc", "PS0010"),
        // Type 2 without G43.5, a Q in type 2 (its inclination); the leading edge offset is
        // `leading_edge.rs`'s.
        ("G41.6 D1 G01 X10. I0 J0 K1. F500\n", 1, "head-bc", "PS0010"),
        ("G43.5 H1\nG41.6 D1 G01 X10. I0 J0 K1. Q2. F500\n", 2, "head-bc", "PS0010"),
        // What the manual forbids in the mode (§3.5.1) keeps its own alarm.
        ("G41.2 D1 G01 X10. F500\nG81 X20. Z-5. R2.\n", 2, "head-bc", "PS5460"),
        ("G41.2 D1 G01 X10. F500\nG28 X0\n", 2, "head-bc", "PS5460"),
    ];
    for (src, line, preset, code) in cases {
        let src = format!("G90 G00 X0 Y0 Z0\n{src}G40 X0\nM30\n");
        assert_eq!(first_alarm(&src, preset), Some((code.to_string(), line + 1)), "{src}");
    }
}

/// No.5003#1 SUV (rule 13, CRC-08) under the tool side offset, in the plane of a tilted tool:
/// head-bc at B45 C−90, the tool t = (0, −s, s), s = √2/2, the plane's axes e2 = X and
/// e3 = (0, s, s) (e2 × e3 = t: G41.2 is G41 seen in (e2, e3)). A point (u, v) there with w
/// along the tool is u e2 + v e3 + w t.
#[test]
fn the_start_up_perpendicular_to_the_next_move_in_the_plane_of_the_tool() {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let lift = |u: f64, v: f64, w: f64| [u, s * (v - w), s * (v + w)];
    let xyz = |p: [f64; 3]| format!("X{:.9} Y{:.9} Z{:.9}", p[0], p[1], p[2]);
    // From (−10, 0) along +u to (20, 0) (1 along the tool), then along +v to (20, 20); the
    // G41.2 block in G01 has no X/Y/Z, nor has the G40 block.
    let src = format!(
        "G90 G00 {} B45. C-90.\nG01 G41.2 D1 F500.\n{}\n{}\nG40\nM30\n",
        xyz(lift(-10.0, 0.0, 0.0)),
        xyz(lift(20.0, 0.0, 1.0)),
        xyz(lift(20.0, 20.0, 0.0))
    );
    let suv = |c: &mut fivex_engine::interp::Config| c.edit_machine(|m| m.motion.cutter_startup_perpendicular = true);
    let got = ends_with(&src, "head-bc", suv);
    assert_eq!(got.alarm, None, "{src}");
    // The G41.2 block (line 2) moves by 5 perpendicular to the first block, to its left in the
    // plane: (−10, 5). The first block is then one of offset mode: the left turn into +v is an
    // inside corner, the offset lines v = 5 and u = 15 meet at (15, 5), at its own w = 1. The
    // last block before the cancel ends perpendicular to itself, (15, 20); the G40 block moves
    // from there to the programmed point (20, 20).
    let want = [
        (1, lift(-10.0, 0.0, 0.0)),
        (2, lift(-10.0, 5.0, 0.0)),
        (3, lift(15.0, 5.0, 1.0)),
        (4, lift(15.0, 20.0, 0.0)),
        (5, lift(20.0, 20.0, 0.0)),
    ];
    assert_eq!(got.ends.len(), want.len(), "{:?}", got.ends);
    for ((l, p), (wl, w)) in got.ends.iter().zip(&want) {
        assert!(l == wl && (p - Vec3::from(*w)).norm() < 1e-6, "line {l}: {p:?} want {wl} {w:?}");
    }
    // Without SUV (type A): the G41.2 and G40 blocks do not move; the start-up block ends at
    // the same inside corner, and M30 leaves the last block perpendicular to itself.
    let plain = ends_of(&src, "head-bc");
    assert_eq!(plain.alarm, None);
    let lines: Vec<u32> = plain.ends.iter().map(|e| e.0).collect();
    assert_eq!(lines, [1, 3, 4]);
    // An arc after the G41.2 block is one of offset mode under SUV (PS0034 without it): the
    // tool vertical, G02 from (0, 0) about (10, 0) — the start-up move goes to the left of its
    // start tangent (0, 1): (−5, 0).
    let arc = "G90 G00 X0 Y0 Z0 B0 C0\nG01 G41.2 D1 F500.\nG02 X20. Y0 I10. J0\nG01 Y-10.\nG40\nM30\n";
    assert_eq!(first_alarm(arc, "head-bc"), Some(("PS0034".into(), 3)));
    let got = ends_with(arc, "head-bc", suv);
    assert_eq!(got.alarm, None);
    assert!((got.ends[1].1 - Vec3::new(-5.0, 0.0, 0.0)).norm() < 1e-9 && got.ends[1].0 == 2, "{:?}", got.ends);
    // Under TCP the tip goes where the vectors say (`ends_with` checks every motion's axes
    // carry it, tool length 100): the same points, two lines later (G43.4 and the turn first).
    let tcp = src.replace("B45. C-90.\n", "B0 C0\nG43.4 H1\nG00 B45. C-90.\n").replace("M30", "G49\nM30");
    let got = ends_with(&tcp, "head-bc", suv);
    assert_eq!(got.alarm, None, "{tcp}");
    assert_eq!(got.ends.len(), want.len() + 3, "{:?}", got.ends);
    for ((l, p), (wl, w)) in got.ends[2..].iter().zip(&want) {
        assert!(*l == wl + 2 && (p - Vec3::from(*w)).norm() < 1e-6, "line {l}: {p:?} want {w:?}");
    }
    // On mixed-bc (B tilts the tool about Y, C turns the table) in the workpiece system
    // (WKP = 1): at B45 the tool is (s, 0, s); the plane's axes e2 = Y, e3 = (−s, 0, s)
    // (e2 × e3 = the tool), so (u, v, w) is (s(w − v), u, s(v + w)). The same contour there
    // gives the same points in (u, v, w), and the run moves through them.
    let workpiece = |c: &mut fivex_engine::interp::Config| {
        c.edit_machine(|m| {
            m.motion.cutter_startup_perpendicular = true;
            m.five_axis.tcp_coordinates = fivex_engine::machine::TcpCoordinates::Workpiece;
        })
    };
    let lift_m = |u: f64, v: f64, w: f64| [s * (w - v), u, s * (v + w)];
    let on_mixed = format!(
        "G90 G00 {} B0 C0\nG43.4 H1\nG00 B45.\nG01 G41.2 D1 F500.\n{}\n{}\nG40\nG49\nM30\n",
        xyz(lift_m(-10.0, 0.0, 0.0)),
        xyz(lift_m(20.0, 0.0, 1.0)),
        xyz(lift_m(20.0, 20.0, 0.0))
    );
    let got = ends_with(&on_mixed, "mixed-bc", workpiece);
    assert_eq!((&got.alarm, got.ends.len()), (&None, 8), "{on_mixed}\n{:?}", got.ends);
    let want_m =
        [(1, -10.0, 0.0, 0.0), (2, -10.0, 5.0, 0.0), (3, 15.0, 5.0, 1.0), (4, 15.0, 20.0, 0.0), (5, 20.0, 20.0, 0.0)];
    for ((l, p), (wl, u, v, w)) in got.ends[2..].iter().zip(want_m) {
        assert!(*l == wl + 2 && (p - Vec3::from(lift_m(u, v, w))).norm() < 1e-6, "mixed line {l}: {p:?}");
    }
    let mut interp = interpreter_with(&on_mixed, "mixed-bc", Fanuc, workpiece);
    let r = fivex_engine::run::run(&mut interp, &Default::default(), |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn m30_ends_the_mode_with_the_last_block_perpendicular() {
    // The start-up block turns right into X50 with the tool on the right: an inside corner,
    // the offset lines' intersection (5, −5); M30 leaves X50 perpendicular to itself.
    let src = "G90 G00 X0 Y-10. Z0\nG42.2 D1 G01 Y0 F500.\nX50.\nM30\n";
    assert_ends(src, "head-bc", &[(1, [0.0, -10.0, 0.0]), (2, [5.0, -5.0, 0.0]), (3, [50.0, -5.0, 0.0])]);
}

/// The G40 block is held to the interference check as cutter compensation C holds it (audit
/// crc2 N3): the cancel after a sharp turn starts at the corner's intersection far beyond its
/// programmed start and would run back against its own move. The random comparison with C found
/// it (b = c = 0: C stopped with PS0041 at the G40 block, the tool side offset ran it, cutting
/// back across the corner); with the check in the plane (NI5 = 1) and in 3-D alike.
#[test]
fn a_cancel_block_that_runs_backwards_is_an_interference_alarm_on_the_tool_side_too() {
    let src = "G90 G00 X48. Y0 Z0 B0 C0\nG42.2 D1\nG01 F800. X30. Y0\nX-22.884811521 Y19.398077267\n\
               X-21.040528013 Y-21.384484584\nX55.602718389 Y-8.522192275\nX30. Y0\nG40 X48. Y0\nM30\n";
    let plane = ends_with(&src.replace("G42.2", "G42").replace(" B0 C0", ""), "mill3", |_| {});
    assert_eq!(plane.alarm, Some(("PS0041".into(), 8)), "cutter compensation C");
    for (check, tweak) in [("in the plane", ni5 as fn(&mut fivex_engine::interp::Config)), ("in 3-D", |_: &mut _| {})] {
        let got = ends_with(src, "head-bc", tweak);
        assert_eq!(got.alarm, plane.alarm, "the check {check}");
        // The tool stops at the end of the block before, where C stops it.
        assert_eq!(got.ends.len(), plane.ends.len(), "the check {check}");
        for ((l1, p), (l2, q)) in got.ends.iter().zip(&plane.ends) {
            assert!(l1 == l2 && (p - q).norm() < 1e-9, "the check {check}: line {l1} at {p:?}, C: line {l2} at {q:?}");
        }
    }
}

/// NI5 = 1 (No.19608#1): the tool side offset's interference check in the compensation plane.
fn ni5(c: &mut fivex_engine::interp::Config) {
    c.edit_machine(|m| m.five_axis.crc_check_in_plane = true)
}

mod random {
    //! The defining rule on random contours: with the tool in any fixed direction, and any part
    //! of each move along the tool, the vector added at every block end is perpendicular to the
    //! tool and is the vector cutter compensation C finds for the contour seen in the plane
    //! perpendicular to the tool (G41 in G17 on the same points in plane coordinates); on a
    //! tool rotation machine and on a mixed one (whose table turns under the program).

    use super::*;
    use proptest::prelude::*;

    /// The tool direction (machine coordinates: without TCP the program's) at B, C on
    /// `preset` (head-bc: both turn the tool; mixed-bc: B the tool, C the table).
    fn tool(preset: &str, b: f64, c: f64) -> Vec3 {
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let mut pos = [0.0; 8];
        (pos[3], pos[4]) = (b, c);
        kin.forward(&pos, 0.0).tool_machine
    }

    fn program(side: &str, points: &[[f64; 3]], start: [f64; 3], first: &str) -> String {
        let xyz = |p: &[f64; 3]| format!("X{:.9} Y{:.9} Z{:.9}", p[0], p[1], p[2]);
        let mut src = format!("G90 G00 {}{first}\n{side} D1\nG01 F800. ", xyz(&start));
        for p in points.iter().chain(std::iter::once(&points[0])) {
            src += &format!("{}\n", xyz(p));
        }
        src + &format!("G40 {}\nM30\n", xyz(&start))
    }

    /// A star-shaped polygon around the origin (inner and outer corners): corners at sorted
    /// angles and radii 30–80, each with a distance along the tool. No two neighbours are half a
    /// turn or more apart (the origin would fall outside, and the polygon could fold back on
    /// itself in a spike: a shrunk case, angles 1.39, 1.40, 1.73 and 3.60 rad, had its tool
    /// centre run on only the ends of every edge).
    pub(super) fn contour() -> impl Strategy<Value = Vec<(f64, f64, f64)>> {
        prop::collection::vec((0.0..std::f64::consts::TAU, 30.0..80.0, -30.0..30.0f64), 4..8)
            .prop_map(|mut v| {
                v.sort_by(|a, b| a.0.total_cmp(&b.0));
                v
            })
            .prop_filter("a star around the origin", |v| {
                let gap = |k: usize| (v[(k + 1) % v.len()].0 - v[k].0).rem_euclid(std::f64::consts::TAU);
                (0..v.len()).all(|k| gap(k) < std::f64::consts::PI)
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(60), max_global_rejects: 10_000, ..ProptestConfig::default() })]
        #[test]
        fn every_vector_is_cutter_compensation_c_in_the_plane_perpendicular_to_the_tool(
            b in -60.0..60.0f64,
            c in -180.0..180.0f64,
            corners in contour(),
            left in any::<bool>(),
            mixed in any::<bool>(),
        ) {
            let preset = if mixed { "mixed-bc" } else { "head-bc" };
            let t = tool(preset, b, c);
            // The test's own plane axes (any pair with e2 × e3 = the tool will do).
            let e2 = t.cross(&Vec3::new(0.3, -0.5, 0.8)).normalize();
            let e3 = t.cross(&e2);
            let flat: Vec<[f64; 2]> = corners.iter().map(|(a, r, _)| [r * a.cos(), r * a.sin()]).collect();
            let lift = |p: [f64; 2], along: f64| e2 * p[0] + e3 * p[1] + t * along;
            let start = [flat[0][0] * 1.6, flat[0][1] * 1.6];
            let side = if left { "G41" } else { "G42" };
            let arr = |v: Vec3| [v.x, v.y, v.z];
            let flat3: Vec<[f64; 3]> = flat.iter().map(|p| [p[0], p[1], 0.0]).collect();
            let plane = ends_of(&program(side, &flat3, [start[0], start[1], 0.0], ""), "mill3");
            let points: Vec<[f64; 3]> = flat.iter().zip(&corners).map(|(p, k)| arr(lift(*p, k.2))).collect();
            let tilted = program(&format!("{side}.2"), &points, arr(lift(start, 0.0)), &format!(" B{b:.9} C{c:.9}"));
            // The check in the plane (NI5 = 1) is cutter compensation C's there; with NI5 = 0
            // it is made in 3-D and misses reversals hidden by the moves along the tool.
            let tilted = ends_with(&tilted, preset, ni5);
            prop_assert_eq!(&plane.alarm, &tilted.alarm);
            // A contour the compensation refuses (a gouge) is refused by both: compare others.
            prop_assume!(plane.alarm.is_none());
            prop_assert_eq!(plane.ends.len(), tilted.ends.len());
            let n = flat.len();
            for ((l1, p), (l2, q)) in plane.ends.iter().zip(&tilted.ends) {
                prop_assert_eq!(l1, l2);
                // Line 3 + k ends at corner k (line 3 + n closes the contour); the start and
                // the cancel are at the start point.
                let (programmed, along) = match *l1 as usize {
                    k if (3..=3 + n).contains(&k) => (flat[(k - 3) % n], corners[(k - 3) % n].2),
                    _ => (start, 0.0),
                };
                let vector = q - lift(programmed, along);
                prop_assert!(vector.dot(&t).abs() < 1e-9, "line {}: {:?} along the tool", l1, vector);
                let want = e2 * (p.x - programmed[0]) + e3 * (p.y - programmed[1]);
                prop_assert!((vector - want).norm() < 1e-7, "line {}: {:?} want {:?}", l1, vector, want);
            }
        }
    }

    /// Where a flat end mill standing on `tip` along `t` touches a line whose point at the
    /// radius seen along the tool is `on`: there, or where the line runs below the tip, on the
    /// tool's bottom edge above it.
    pub(super) fn touching(on: Vec3, tip: Vec3, t: Vec3) -> Vec3 {
        on - t * t.dot(&(on - tip)).min(0.0)
    }

    /// A star polygon lifted into the plane perpendicular to `t` (with the parts along it of
    /// `corners`) as a program: the machine turned to `angles` first, TCP, the contour under
    /// `side` (G41.2 or G42.2), the cancel, G49.
    fn tcp_program(side: &str, t: Vec3, corners: &[(f64, f64, f64)], angles: &str) -> (String, Vec<Vec3>) {
        let e2 = t.cross(&Vec3::new(0.3, -0.5, 0.8)).normalize();
        let e3 = t.cross(&e2);
        let points: Vec<Vec3> =
            corners.iter().map(|(a, r, z)| e2 * (r * a.cos()) + e3 * (r * a.sin()) + t * *z).collect();
        let xyz = |p: &Vec3| format!("X{:.9} Y{:.9} Z{:.9}", p.x, p.y, p.z);
        let start = points[0] * 1.6;
        let mut src = format!("G90 G00 {} {angles}\nG43.4 H1\n{side} D1\nG01 F3000. ", xyz(&start));
        for p in points.iter().chain(std::iter::once(&points[0])) {
            src += &format!("{}\n", xyz(p));
        }
        src += &format!("G40 {}\nG49\nM30\n", xyz(&start));
        (src, points)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(24), max_global_rejects: 10_000, ..ProptestConfig::default() })]
        /// At every sample of the run in the middle of a contour block, the real tool tip (forward
        /// kinematics of the sampled axes) is at the radius from the programmed line, measured
        /// in the plane perpendicular to the tool, on the commanded side: on a tool rotation, a
        /// mixed and a table machine, under TCP in the workpiece system; every axis within its
        /// speed, acceleration and jerk (a corner's step between segments allowed).
        #[test]
        fn every_sample_of_a_straight_block_keeps_the_tip_at_the_radius(
            machine in 0..3usize,
            b in -50.0..50.0f64,
            c in -180.0..180.0f64,
            corners in contour(),
            left in any::<bool>(),
        ) {
            let (preset, angles) = [("head-bc", "B"), ("mixed-bc", "B"), ("table-ac", "A")][machine];
            let angles = format!("{angles}{b:.3} C{c:.3}");
            let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
            let mut pos = [0.0; 8];
            (pos[3], pos[4]) = ((b * 1000.0).round() / 1000.0, (c * 1000.0).round() / 1000.0);
            // The tool in the workpiece system (which does not turn with a table: WKP = 1).
            let t = kin.forward(&pos, 0.0).tool_machine;
            let side = if left { "G41.2" } else { "G42.2" };
            let (src, points) = tcp_program(side, t, &corners, &angles);
            let workpiece = |c: &mut fivex_engine::interp::Config| {
                c.edit_machine(|m| m.five_axis.tcp_coordinates = fivex_engine::machine::TcpCoordinates::Workpiece)
            };
            prop_assume!(first_alarm_with(&src, preset, workpiece).is_none());
            let mut interp = interpreter_with(&src, preset, Fanuc, workpiece);
            let n = points.len();
            let (mut checked, mut cut_checked) = (0, 0);
            let (mut worst, mut worst_cut) = (0.0f64, 0.0f64);
            let mut samples = Vec::new();
            let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
                samples.push(*s);
                // Line 5 + k runs from corner k to corner k + 1 (the start-up block is line 4).
                let k = s.line as usize;
                if !(5..5 + n).contains(&k) {
                    return;
                }
                let (p, q) = (points[(k - 5) % n], points[(k - 4) % n]);
                // The real tip from the sampled axes (tool length 100), in machine coordinates:
                // the programming system here (no work offset; WKP = 1 does not turn with the
                // table, where the trace's `tip` is on the table).
                let tip = kin.forward(&s.machine, 100.0).tip_machine;
                // In the plane perpendicular to the tool: the programmed line and the tip.
                let flat = |v: Vec3| v - t * v.dot(&t);
                let (d, w) = (flat(q - p), flat(tip - p));
                let u = d.dot(&w) / d.norm_squared();
                if !(0.25..=0.75).contains(&u) {
                    return;
                }
                let across = w - d * u;
                let sign = if t.dot(&d.cross(&across)) > 0.0 { 1.0 } else { -1.0 };
                let want = if left { 5.0 } else { -5.0 };
                worst = worst.max((sign * across.norm() - want).abs());
                checked += 1;
                // The cutting point (the trace's, in the table frame like `tip`) turned into
                // machine directions about the tip: the line's point at the radius seen along the
                // tool, or where it runs below the tip, the tool's bottom edge above it.
                if let Some(cut) = s.cutting {
                    let turn = kin.table_frame(&s.machine).r;
                    let at = tip + turn * (Vec3::from(cut) - Vec3::from(s.tip));
                    worst_cut = worst_cut.max((at - touching(p + (q - p) * u, tip, t)).norm());
                    cut_checked += 1;
                }
            });
            prop_assert!(r.completed(), "{:?}", r.alarms);
            prop_assert!(checked > 10 * n, "{} samples checked", checked);
            prop_assert!(worst < 1e-3, "a sample {} mm off the radius", worst);
            prop_assert_eq!(cut_checked, checked, "samples without a cutting point");
            prop_assert!(worst_cut < 1e-3, "a cutting point {} mm off the programmed line", worst_cut);
            check_limits_by_segment(&samples, &MachineConfig::preset(preset).unwrap())
                .map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
        }
    }
}

// --- the table coordinate system as PCS (No.19746#4 TBP = 1, CRC-38, TV-20…TV-26) ------------

/// The manual's §3.6 Program 1 (mixed machine: B tilts the tool about Y, C turns the table about
/// Z; TBP = 1, WKP = 0, type 1), as printed but for O101.
const PROGRAM_1: &str = "N10 G55\nN20 G90 X0 Y0 Z300. B0 C0\nN30 G01 G43.4 H01 Z40. F500.\nN40 G41.2 D01\n\
    N50 X50. Y50. Z20. B30. C45.\nN60 X-50. C135.\nN70 X-100. Y-100. C225.\nN80 X100. C315.\n\
    N90 X50. Y50. C405.\nN100 X0 Y0 Z40. B0 C360.\nN110 G40\nN120 G49 Z300.\nN130 M30\n";

/// Program 2: the same in the workpiece system (WKP = 1).
const PROGRAM_2: &str = "N10 G55\nN20 G90 X0 Y0 Z300. B0 C0\nN30 G01 G43.4 H01 Z40. F500.\nN40 G41.2 D01\n\
    N50 X70.711 Y0 Z20. B30. C45.\nN60 C135.\nN70 X141.421 C225.\nN80 C315.\nN90 X70.711 C405.\n\
    N100 X0 Y0 Z40. B0 C360.\nN110 G40\nN120 G49 Z300.\nN130 M30\n";

fn tbp(coordinates: fivex_engine::machine::TcpCoordinates) -> impl FnOnce(&mut fivex_engine::interp::Config) {
    move |c: &mut fivex_engine::interp::Config| {
        c.edit_machine(|m| {
            m.five_axis.crc_table_coordinates = true;
            m.five_axis.tcp_coordinates = coordinates;
        })
    }
}

/// Every motion under TCP of `src` on mixed-bc: line, the tip in Π (the motion's programming
/// frame), the tool (table frame) and the machine axes; every motion's axes carry its tip
/// (forward kinematics, tool length 100). And the alarm.
#[allow(clippy::type_complexity)]
fn tip_ends(
    src: &str,
    tweak: impl FnOnce(&mut fivex_engine::interp::Config),
) -> (Vec<(u32, Vec3, Vec3, [f64; 8])>, Option<(String, u32)>) {
    let kin = Kinematics::new(&MachineConfig::preset("mixed-bc").unwrap()).unwrap();
    let mut ends = Vec::new();
    let alarm = through_stages(interpreter_with(src, "mixed-bc", Fanuc, tweak), |c| {
        if let CanonKind::Motion(m) = c.kind {
            if let Some(t) = m.tip.as_deref() {
                let pose = kin.forward(&m.machine, 100.0);
                assert!((pose.tip - t.to).norm() < 1e-9, "line {}: {:?} {:?}", c.line, pose.tip, t.to);
                let mut machine = [0.0; 8];
                machine[..m.machine.len().min(8)].copy_from_slice(&m.machine[..m.machine.len().min(8)]);
                ends.push((c.line, t.frame.r.transpose() * (t.to - t.frame.o), pose.tool, machine));
            }
        }
    });
    (ends, alarm)
}

/// §3.5.3 in the table coordinate system (TBP = 1, WKP = 0, under TCP): in the mode only the
/// listed G codes (CRC-50, PS5460), a start only in the listed modal states (CRC-51, PS5421),
/// and no axis outside the five (PS5460).
#[test]
fn in_the_table_system_the_mode_takes_the_listed_codes_only() {
    use fivex_engine::machine::TcpCoordinates::TableAtStart;
    let program = |before: &str, inside: &str| {
        format!(
            "G55\nG90 X0 Y0 Z300. B0 C0\nG01 G43.4 H01 Z40. F500.\n{before}G41.2 D01\nX50. Y50. Z20. B30. C45.\n\
             {inside}X-50. C135.\nG40\nG49 Z300.\nM30\n"
        )
    };
    let (_, alarm) = tip_ends(&program("", "G04 P100\nG61\nG64\nG91 X0\nG90\n"), tbp(TableAtStart));
    assert_eq!(alarm, None);
    // G94 is a state it may start in, not a code it takes (every 5-axis compensation takes it
    // in the workpiece system); G63 is taken by TCP, not by it.
    assert_eq!(tip_ends(&program("", "G94\n"), tbp(TableAtStart)).1, Some(("PS5460".into(), 6)));
    assert_eq!(tip_ends(&program("G63\n", ""), tbp(TableAtStart)).1, Some(("PS5421".into(), 5)));
    // In the workpiece system (TBP = 0) neither list applies.
    let (_, alarm) = tip_ends(&program("", "G94\n"), |c| {
        c.edit_machine(|m| m.five_axis.tcp_coordinates = fivex_engine::machine::TcpCoordinates::Workpiece)
    });
    assert_eq!(alarm, None);
    // A sixth axis (U beside X) moved in the mode.
    let with_u = |c: &mut fivex_engine::interp::Config| {
        tbp(TableAtStart)(c);
        c.edit_machine(|m| {
            let mut u = m.axes[0].clone();
            u.name = 'U';
            m.axes.push(u);
        })
    };
    let alarm = through_stages(interpreter_with(&program("", "U10.\n"), "mixed-bc", Fanuc, with_u), |_| {});
    assert_eq!(alarm, Some(("PS5460".into(), 6)));
    // Outside the mode U moves freely.
    let outside = program("", "").replace("G49 Z300.", "G49 Z300.\nU10.");
    assert_eq!(through_stages(interpreter_with(&outside, "mixed-bc", Fanuc, with_u), |_| {}), None);
}

#[test]
fn tv26_program_1_compensates_in_the_table_system() {
    use fivex_engine::machine::TcpCoordinates::{TableAtStart, TableAtZero};
    // TBP = 1, WKP = 0 (INZ = 0 and 1: the table stands at C0 when TCP starts, so Π is the
    // table system either way): TCP and compensation in one system (TV-24 row "1 0").
    for wkp0 in [TableAtStart, TableAtZero] {
        let (ends, alarm) = tip_ends(PROGRAM_1, tbp(wkp0));
        assert_eq!(alarm, None);
        let last = |line: u32| ends.iter().rev().find(|(l, ..)| *l == line).unwrap();
        // The tool in the table system at B30 (C the table's turn): (sin B cos C, sin B sin C,
        // cos B), the manual's VT; at each corner Q (between P and R, lines 6–9 = N60–N90) the
        // plane is ⊥ VT; the moves projected on it give unit u1, u2, their left normals
        // n = VT × u (G41.2: G41 seen from the holder), and every corner turns left (inside):
        // the offset lines meet at Q + r (n1 + n2) / (1 + n1·n2), r = 5. Worked out:
        // N80: Q (100, −100, 20), VT at C315 (0.353553, −0.353553, 0.866025); the move from
        // (−100, −100, 20) along +X projects to u1 = (0.935414, 0.133631, −0.327327), the next
        // one toward (50, 50, 20) to u2 = (−0.176777, 0.883883, 0.433013); n1 = (0, 0.925820,
        // 0.377964), n2 = (−0.918559, −0.306186, 0.25), n1·n2 = −0.188982: the vector
        // (−5.663000, 3.820101, 3.871459), ⊥ VT, 5 from both offset lines.
        let corners = [
            (6, 135.0, [-47.060011, 45.790898, 22.918604]),
            (7, 225.0, [-94.337000, -96.179899, 23.871459]),
            (8, 315.0, [94.337000, -96.179899, 23.871459]),
            (9, 405.0, [48.873122, 41.802054, 23.806844]),
        ];
        for (line, c, want) in corners {
            let (_, tip, tool, machine) = last(line);
            let c = f64::to_radians(c);
            let vt = Vec3::new(0.5 * c.cos(), 0.5 * c.sin(), 30f64.to_radians().cos());
            assert!((tool - vt).norm() < 1e-9, "line {line}: tool {tool:?}, VT {vt:?}");
            assert!((tip - Vec3::from(want)).norm() < 1e-5, "line {line}: {tip:?} {want:?}");
            assert!((machine[3] - 30.0).abs() < 1e-9, "line {line}: B {}", machine[3]);
        }
        // N80 by the definition: the vector is ⊥ VT and 5 from both offset lines.
        let (_, tip, ..) = last(8);
        let v = tip - Vec3::new(100.0, -100.0, 20.0);
        let (vt, n1, n2) = (
            Vec3::new(0.353553, -0.353553, 0.866025),
            Vec3::new(0.0, 0.925820, 0.377964),
            Vec3::new(-0.918559, -0.306186, 0.25),
        );
        assert!(v.dot(&vt).abs() < 1e-5 && (v.dot(&n1) - 5.0).abs() < 1e-5 && (v.dot(&n2) - 5.0).abs() < 1e-5);
    }
}

#[test]
fn tv26_program_2_and_what_the_same_machining_means() {
    use fivex_engine::machine::TcpCoordinates::{TableAtStart, Workpiece};
    // Program 2 (WKP = 1: TCP and compensation in the workpiece system, TV-24 row "1 1") runs.
    let (p1, a1) = tip_ends(PROGRAM_1, tbp(TableAtStart));
    let (p2, a2) = tip_ends(PROGRAM_2, tbp(Workpiece));
    assert_eq!((a1, a2), (None, None));
    // "All perform the same machining" (§3.6): the programmed end points are one point on the
    // table, p_w = Rz(−C)·p_t (TV-26), so without compensation every block end has the same
    // machine axes (to the printed 3 decimals; C modulo 360).
    let last =
        |ends: &[(u32, Vec3, Vec3, [f64; 8])], line: u32| ends.iter().rev().find(|(l, ..)| *l == line).unwrap().3;
    let plain = |src: &str, wkp| tip_ends(&src.replace("G41.2 D01", "G40"), tbp(wkp));
    let ((q1, b1), (q2, b2)) = (plain(PROGRAM_1, TableAtStart), plain(PROGRAM_2, Workpiece));
    assert_eq!((b1, b2), (None, None));
    for line in 5..=10 {
        let (m1, m2) = (last(&q1, line), last(&q2, line));
        for k in 0..5 {
            let d = if k == 4 { ((m1[k] - m2[k]).rem_euclid(360.0) + 180.0) % 360.0 - 180.0 } else { m1[k] - m2[k] };
            assert!(d.abs() < 2e-3, "line {line} axis {k}: {m1:?} {m2:?}");
        }
    }
    // With compensation they cannot agree: in the workpiece system Program 2's contour is a line
    // along X run out and back (N60/N80 turn the table only and keep their vectors), so its
    // vectors are found from that line, not from the quadrilateral on the table Program 1
    // describes. N80's end: Program 1 puts the tip at Q + (−5.663, 3.820, 3.871) in the table
    // system (above); Program 2 at the second of the two lengthened vectors of its turn back at
    // (141.421, 0, 20) (α < 90°, CRC-10): 5 along the line projected ⊥ the tool, (4.330, 0,
    // −2.5), and 5 to its right for the return.
    let (m1, m2) = (last(&p1, 8), last(&p2, 8));
    assert!((m1[0] - m2[0]).abs() > 1.0, "{m1:?} {m2:?}");
    let (_, tip, ..) = p2.iter().rev().find(|(l, ..)| *l == 8).unwrap();
    assert!((tip - Vec3::new(145.751127, -5.0, 17.5)).norm() < 1e-5, "{tip:?}");
}

/// Program 3 (type 2, G41.6 with I/J/K, TBP = 1), as printed under G43.4, and with G43.5.
const PROGRAM_3: &str = "N10 G55\nN20 G90 X0 Y0 Z300. B0 C0\nN30 G01 G43.4 H01 Z40. F500.\nN40 G41.6 D01\n\
    N50 X50. Y50. Z20. I35.355 J35.355 K86.603\nN60 X-50. I-35.355 J35.355 K86.603\n\
    N70 X-100. Y-100. I-35.355 J-35.355 K86.603\nN80 X100. I35.355 J-35.355 K86.603\n\
    N90 X50. Y50. I35.355 J35.355 K86.603\nN100 X0 Y0 Z40. K1.\nN110 G40\nN120 G49 Z300.\nN130 M30\n";

#[test]
fn tv26_program_3() {
    use fivex_engine::machine::TcpCoordinates::TableAtStart;
    // As printed, G41.6 under G43.4: the pairing of §3.5.2 (CRC-48, TV-18: type 2 with G43.5
    // only) refuses it.
    let (_, alarm) = tip_ends(PROGRAM_3, tbp(TableAtStart));
    assert_eq!(alarm, Some(("PS5460".into(), 4)));
    // Under G43.5 (the pairing the manual requires) the same tips as Program 1 in Π.
    let (p3, a3) = tip_ends(&PROGRAM_3.replace("G43.4", "G43.5"), tbp(TableAtStart));
    let (p1, _) = tip_ends(PROGRAM_1, tbp(TableAtStart));
    assert_eq!(a3, None);
    for line in 5..=10 {
        let at = |ends: &[(u32, Vec3, Vec3, [f64; 8])]| ends.iter().rev().find(|(l, ..)| *l == line).unwrap().1;
        assert!((at(&p1) - at(&p3)).norm() < 1e-3, "line {line}: {:?} {:?}", at(&p1), at(&p3));
    }
}

#[test]
fn tbp_interlocks_and_what_stays_refused() {
    use fivex_engine::machine::TcpCoordinates::{TableAtStart, Workpiece};
    let with = |src: &str, edit: fn(&mut MachineConfig)| {
        first_alarm_with(src, "mixed-bc", |c| {
            c.edit_machine(|m| {
                m.five_axis.crc_table_coordinates = true;
                edit(m);
            })
        })
    };
    let contour = "G01 X10. F500.\nY10.\nG40 X20. Y20.\n";
    // TBP = 1 without TCP: compensated in the table system (`table_system` below).
    let alone = format!("G90 G00 X0 Y0 Z0 B0 C30.\nG41.2 D1\n{contour}M30\n");
    assert_eq!(with(&alone, |_| {}), None);
    // … whose look-ahead prerequisites come first (TV-20: PS5483 at G41.2).
    assert_eq!(with(&alone, |m| m.motion.no_feed_look_ahead = true), Some(("PS5483".into(), 2)));
    assert_eq!(with(&alone, |m| m.motion.no_rapid_look_ahead = true), Some(("PS5483".into(), 2)));
    assert_eq!(with(&alone, |m| m.motion.nonlinear_rapid = true), Some(("PS5483".into(), 2)));
    // TBP = 1, WKP = 1: the workpiece system (CRC-39), as TBP = 0: compensated without TCP.
    assert_eq!(with(&alone, |m| m.five_axis.tcp_coordinates = Workpiece), None);
    // TBP = 0, WKP = 0 stays PS5460 (TV-24 row "0 0") at the block that starts the second.
    let nested = format!("G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG41.2 D1\n{contour}G49\nM30\n");
    let tbp0 =
        first_alarm_with(&nested, "mixed-bc", |c| c.edit_machine(|m| m.five_axis.tcp_coordinates = TableAtStart));
    assert_eq!(tbp0, Some(("PS5460".into(), 3)));
    assert_eq!(with(&nested, |_| {}), None);
    // TV-23: TCP first and cancelled last. Ex. 2 (G43.4 inside G41.2) is PS5460 at G43.4 (not
    // a code the mode takes, CRC-49/50); Ex. 3 (G49 before G40) is PS5460 (CRC-48/49).
    let ex2 = "G90 G00 X0 Y0 Z0 B0 C0\nG41.2 D1\nG43.4 H1\nG01 X10. F500.\nG49\nM30\n";
    assert_eq!(with(ex2, |_| {}), Some(("PS5460".into(), 3)));
    let ex3 = "G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG41.2 D1\nG01 X10. F500.\nG49\nG40\nM30\n";
    assert_eq!(with(ex3, |_| {}), Some(("PS5460".into(), 5)));
    // Both in one block: TCP is not first (PS5460).
    let one = "G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1 G41.2 D1\nG01 X10. F500.\nG40 X20.\nG49\nM30\n";
    assert_eq!(with(one, |_| {}), Some(("PS5460".into(), 2)));
    // TV-25: the table stands as when TCP started (its turn modulo 360°), and no table axis
    // word in the G41.2 block.
    let turned = format!("G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG01 Z10. C30. F500.\nG41.2 D1\n{contour}G49\nM30\n");
    assert_eq!(with(&turned, |_| {}), Some(("PS5460".into(), 4)));
    let back = turned.replace("C30.", "C360.");
    assert_eq!(with(&back, |_| {}), None);
    let word = nested.replace("G41.2 D1", "G41.2 D1 C10.");
    assert_eq!(with(&word, |_| {}), Some(("PS5460".into(), 3)));
    // The head axis may move before G41.2 (B is the tool's).
    let head = nested.replace("G41.2 D1", "G01 B20. F500.\nG41.2 D1").replace("G49", "G40\nG49");
    assert_eq!(with(&head, |_| {}), None);
}

// --- §3.4: the interference check in the compensation plane (NI5) and avoidance (CAV) --------

mod interference {
    //! FANUC 5-axis manual §3.4 (CRC-40…CRC-43, M-15, TV-33): with No.19608#1 NI5 = 1 the
    //! interference check is made in the plane perpendicular to the tool, with NI5 = 0 on the
    //! programmed 3-D positions and the vectors (§3.5.1); with No.19607#5 CAV = 1 (and NI5 = 1)
    //! an interfering block's vectors give way to one avoidance vector Va, made in the plane of
    //! the block before them (`docs/cutter-compensation.md`, "Tool side offset", rule 12).
    //! The contours are cutter compensation C's hand-worked dips (`cutter.rs`, `avoidance`)
    //! lifted into the plane of a tilted tool on head-bc, B45 C−90: the tool t = (0, −s, s),
    //! s = √2/2, the plane's axes e2 = X, e3 = (0, s, s) (e2 × e3 = t, so G41.2 is G41 seen
    //! there), and each point moved along the tool by its own w: (u, v, w) → u e2 + v e3 + w t.

    use super::*;

    const S: f64 = std::f64::consts::FRAC_1_SQRT_2;

    fn lift(u: f64, v: f64, w: f64) -> Vec3 {
        Vec3::new(u, S * (v - w), S * (v + w))
    }

    /// `G41.2` on head-bc at B45 C−90 from (−10, 0, 0) through `points` (u, v, w), the cancel to
    /// `cancel` (u, v; w = 0). `angles[k]`: B/C words of the k-th point, if any.
    fn program(points: &[(f64, f64, f64)], cancel: (f64, f64), angles: &[(usize, &str)]) -> String {
        let xyz = |p: Vec3| format!("X{:.9} Y{:.9} Z{:.9}", p.x, p.y, p.z);
        let mut src = format!("G90 G00 {} B45. C-90.\nG41.2 D1\nG01 F500. ", xyz(lift(-10.0, 0.0, 0.0)));
        for (k, &(u, v, w)) in points.iter().enumerate() {
            let extra = angles.iter().find(|a| a.0 == k).map_or("", |a| a.1);
            src += &format!("{}{extra}\n", xyz(lift(u, v, w)));
        }
        src + &format!("G40 {}\nM30\n", xyz(lift(cancel.0, cancel.1, 0.0)))
    }

    fn with(ni5: bool, cav: bool, max_turn: f64) -> impl FnOnce(&mut fivex_engine::interp::Config) {
        move |c: &mut fivex_engine::interp::Config| {
            c.edit_machine(|m| {
                m.five_axis.crc_check_in_plane = ni5;
                m.motion.cutter_interference_avoidance = cav;
                m.five_axis.avoidance_max_tool_angle = max_turn;
            })
        }
    }

    /// `ends` are `want` (line, u, v, w lifted) to 1e-6, in order.
    #[track_caller]
    fn assert_lifted(got: &Ends, want: &[(u32, f64, f64, f64)]) {
        let close = got.ends.len() == want.len()
            && got.ends.iter().zip(want).all(|((l, p), &(wl, u, v, w))| *l == wl && (p - lift(u, v, w)).norm() < 1e-6);
        assert!(
            close,
            "got {:?}\nwant {:?}",
            got.ends,
            want.iter().map(|&(l, u, v, w)| (l, lift(u, v, w))).collect::<Vec<_>>()
        );
    }

    /// `cutter.rs`'s `TWO` (a dip of two short blocks), each point moved along the tool.
    const TWO: [(f64, f64, f64); 6] =
        [(0.0, 0.0, 0.0), (20.0, 0.0, 2.0), (21.0, -1.0, -3.0), (22.0, -0.5, 5.0), (32.0, 9.5, 1.0), (40.0, 9.5, 0.0)];

    #[test]
    fn tv33_two_interfering_blocks_share_one_avoidance_vector_in_the_plane_of_the_tool() {
        // In the plane (u, v) this is `cutter.rs`'s TWO, worked there by hand: N3 (to 20,0)
        // ends at 15 + 5√2 = 22.071 on v = 5; N4 (to 21,−1) would run from there to its inside
        // corner with N5 at 21.987, 5.084, back against (1, −1); avoided with N5's offset line
        // −u + 2v = −23 + 5√5 at 33 − 5√5 = 21.820, 5, N5 would run from there to its inside
        // corner with N6 at 19.038, 3.609, back against (2, 1): N4 and N5 interfere (TV-33's N30
        // and N40: V20, V30, V40 removed). Va is where N3's offset line v = 5 crosses N6's,
        // v − u = −22.5 + 5√2: u = 27.5 − 5√2 = 20.429 (N3 "N20", N6 "N50", both in N3's plane —
        // the tool does not turn). N3 ends at Va at its own w (2), N4 and N5 stand there (each
        // at its own w: they move only along the tool), N6 ends at its corner with N7 (outside,
        // obtuse: v = 14.5, u = 37 − 5√2), N7 at 40, 14.5 (in line with the cancel).
        let r2 = 5.0 * 2f64.sqrt();
        let src = program(&TWO, (50.0, 9.5), &[]);
        let got = ends_with(&src, "head-bc", with(true, true, 0.0));
        assert_eq!(got.alarm, None, "{src}");
        assert_lifted(
            &got,
            &[
                (1, -10.0, 0.0, 0.0),
                (3, 0.0, 5.0, 0.0),
                (4, 27.5 - r2, 5.0, 2.0),
                (5, 27.5 - r2, 5.0, -3.0),
                (6, 27.5 - r2, 5.0, 5.0),
                (7, 37.0 - r2, 14.5, 1.0),
                (8, 40.0, 14.5, 0.0),
                (9, 50.0, 9.5, 0.0),
            ],
        );
        // And the run moves through them (the executor takes every move).
        let mut interp = interpreter_with(&src, "head-bc", Fanuc, with(true, true, 0.0));
        let r = fivex_engine::run::run(&mut interp, &Default::default(), |_| {});
        assert!(r.completed(), "{:?}", r.alarms);
        // `fivex check` runs the same stages: nothing to report with avoidance, PS0041 without.
        let check = |cav: bool| {
            let mut interp = interpreter_with(&src, "head-bc", Fanuc, with(true, cav, 0.0));
            fivex_engine::check::run_without_motion(&mut interp, true).map(|s| (s.alarm.code, s.alarm.line))
        };
        assert_eq!((check(true), check(false)), (None, Some(("PS0041".into(), 5))));
        // Without avoidance: PS0041 at N4, N3 ends at its own corner 15 + 5√2, 5.
        let plain = ends_with(&src, "head-bc", with(true, false, 0.0));
        assert_eq!(plain.alarm, Some(("PS0041".into(), 5)));
        assert_eq!(plain.ends.last().map(|e| e.0), Some(4));
        assert!((plain.ends.last().unwrap().1 - lift(15.0 + r2, 5.0, 2.0)).norm() < 1e-6, "{:?}", plain.ends);
    }

    #[test]
    fn no_19636_a_tool_turning_across_the_avoided_block_keeps_the_plain_vectors() {
        // `cutter.rs`'s DIP (one interfering block, N4), N4 turning the tool to B48 (3°): the
        // tool at the end of N3 ("N20") and at the start of N5 ("N50", the end of N4) differ by
        // 3°. No.19636 = 0 (the tool must not turn): no avoidance, N4's check raises PS0041 and
        // N3 ends at its own corner 15 + 5√2, 5 (CRC-41: "the compensation vector is determined
        // but interference avoidance is not performed").
        let dip = [(0.0, 0.0, 0.0), (20.0, 0.0, 0.0), (21.0, -1.0, 0.0), (31.0, 9.0, 0.0), (40.0, 9.0, 0.0)];
        let r2 = 5.0 * 2f64.sqrt();
        let src = program(&dip, (50.0, 9.0), &[(2, " B48.")]);
        let got = ends_with(&src, "head-bc", with(true, true, 0.0));
        assert_eq!(got.alarm, Some(("PS0041".into(), 5)), "{src}");
        assert_eq!(got.ends.last().map(|e| e.0), Some(4));
        assert!((got.ends.last().unwrap().1 - lift(15.0 + r2, 5.0, 0.0)).norm() < 1e-6, "{:?}", got.ends);
        // No.19636 = 2°: still too much. 5°: the avoidance is made — Va in N3's plane (the
        // tool there is B45's), where v = 5 crosses N5's offset line v − u = −22 + 5√2:
        // u = 27 − 5√2 (`cutter.rs`, `a_dip_smaller_than_the_tool_is_avoided`). N4 ends at Va
        // in that plane too (§3.4.1: N3's plane "is regarded as a compensation plane"): its
        // vector is perpendicular to N3's tool, not to its own turned one, and N5 starts there.
        assert_eq!(ends_with(&src, "head-bc", with(true, true, 2.0)).alarm, Some(("PS0041".into(), 5)));
        let got = ends_with(&src, "head-bc", with(true, true, 5.0));
        assert_eq!(got.alarm, None, "{src}");
        let at = |line: u32| got.ends.iter().find(|e| e.0 == line).unwrap().1;
        assert!((at(4) - lift(27.0 - r2, 5.0, 0.0)).norm() < 1e-6, "{:?}", got.ends);
        assert!((at(5) - lift(27.0 - r2, 5.0, 0.0)).norm() < 1e-6, "{:?}", got.ends);
    }

    #[test]
    fn three_consecutive_interfering_blocks_stop_before_the_first() {
        // `cutter.rs`'s three short blocks (to 21,−1; 22,−0.5; 23,−0.3) before the climb: N4, N5
        // and N6 interfere one after the other (worked there by hand). No avoidance vector
        // (CRC-42); the control overcuts, fivex stops before the first interfering block
        // (decision, as under G41): PS0041 at N4, N3 at its own corner 15 + 5√2, 5.
        let three = [
            (0.0, 0.0, 0.0),
            (20.0, 0.0, 1.0),
            (21.0, -1.0, 0.0),
            (22.0, -0.5, -1.0),
            (23.0, -0.3, 0.0),
            (33.0, 10.0, 2.0),
            (40.0, 10.0, 0.0),
        ];
        let src = program(&three, (50.0, 10.0), &[]);
        let got = ends_with(&src, "head-bc", with(true, true, 0.0));
        assert_eq!(got.alarm, Some(("PS0041".into(), 5)), "{src}");
        assert_eq!(got.ends.last().map(|e| e.0), Some(4));
        assert!((got.ends.last().unwrap().1 - lift(15.0 + 5.0 * 2f64.sqrt(), 5.0, 1.0)).norm() < 1e-6);
    }

    #[test]
    fn ni5_the_check_in_the_plane_sees_a_reversal_that_the_moves_along_the_tool_hide_in_3d() {
        // The DIP with N4 (to 21,−1) moving 3 along the tool. In the plane N4 runs from its
        // corner with N3 (22.071, 5) to its corner with N5 (21, 6.071): (−1.071, 1.071) against
        // the programmed (1, −1), dot −2.142 < 0 — NI5 = 1: PS0041 at N4. In 3-D (NI5 = 0,
        // §3.5.1) both moves also run 3 along the tool: the dot is −2.142 + 9 > 0, no alarm — the
        // legacy check lets the compensated block run back over the dip.
        let dip = [(0.0, 0.0, 0.0), (20.0, 0.0, 0.0), (21.0, -1.0, 3.0), (31.0, 9.0, 3.0), (40.0, 9.0, 0.0)];
        let src = program(&dip, (50.0, 9.0), &[]);
        assert_eq!(ends_with(&src, "head-bc", with(true, false, 0.0)).alarm, Some(("PS0041".into(), 5)));
        let legacy = ends_with(&src, "head-bc", with(false, false, 0.0));
        assert_eq!(legacy.alarm, None);
        let r2 = 5.0 * 2f64.sqrt();
        let at = |line: u32| legacy.ends.iter().find(|e| e.0 == line).unwrap().1;
        assert!((at(5) - lift(21.0, r2 - 1.0, 3.0)).norm() < 1e-6, "{:?}", legacy.ends);
        // The same dip without the move along the tool: the 3-D check sees it as well.
        let flat = [(0.0, 0.0, 0.0), (20.0, 0.0, 0.0), (21.0, -1.0, 0.0), (31.0, 9.0, 0.0), (40.0, 9.0, 0.0)];
        let src = program(&flat, (50.0, 9.0), &[]);
        assert_eq!(ends_with(&src, "head-bc", with(false, false, 0.0)).alarm, Some(("PS0041".into(), 5)));
        // NI5 = 0 with CAV = 1: no avoidance under the tool side offset (§3.5.1: "the
        // interference check avoidance function cannot be used").
        assert_eq!(ends_with(&src, "head-bc", with(false, true, 0.0)).alarm, Some(("PS0041".into(), 5)));
        assert_eq!(ends_with(&src, "head-bc", with(true, true, 0.0)).alarm, None);
    }
}

/// Random dips under G41.2 with CAV and NI5 (`docs/cutter-compensation.md`, "Tool side offset",
/// rule 12), in the plane of a tool fixed at random B/C, on head-bc and mixed-bc under TCP (the
/// workpiece system): the contours of `cutter.rs`'s `an_avoided_path_never_comes_closer_than_
/// the_radius` — along +X, a dip of one or two short blocks, a long block, one along +X — lifted
/// into the plane perpendicular to the tool, each point moved along the tool at random. Every
/// run either ends in PS0041 or completes with every sample of the contour's blocks having its
/// real tip (forward kinematics of the sampled axes, tool length 100) at R − 1 µm or more from
/// every programmed block, measured in the plane. At least a fifth of the programs must be
/// avoided (PS0041 without CAV, complete with it), so that the property is exercised.
#[test]
fn an_avoided_path_keeps_the_radius_in_the_plane() {
    let mut seed: u64 = 0x5eed_c0de_0334;
    let mut rand = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let dist = |p: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        let (d, w) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
        let t = ((w[0] * d[0] + w[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
        (w[0] - t * d[0]).hypot(w[1] - t * d[1])
    };
    let settings = |cav: bool| {
        move |c: &mut fivex_engine::interp::Config| {
            c.edit_machine(|m| {
                m.five_axis.tcp_coordinates = fivex_engine::machine::TcpCoordinates::Workpiece;
                m.five_axis.crc_check_in_plane = true;
                m.motion.cutter_interference_avoidance = cav;
            })
        }
    };
    let (mut avoided, mut alarms, total) = (0, 0, cases(40));
    for case in 0..total {
        let preset = if case % 2 == 0 { "head-bc" } else { "mixed-bc" };
        let (b, c) = (
            ((-50.0 + 100.0 * rand()) * 1000.0f64).round() / 1000.0,
            ((-180.0 + 360.0 * rand()) * 1000.0f64).round() / 1000.0,
        );
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let mut pos = [0.0; 8];
        (pos[3], pos[4]) = (b, c);
        let t = kin.forward(&pos, 0.0).tool_machine;
        let e2 = t.cross(&Vec3::new(0.3, -0.5, 0.8)).normalize();
        let e3 = t.cross(&e2);
        // The contour in the plane (u, v), as `cutter.rs` makes it.
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
        let lift = |p: [f64; 2], w: f64| e2 * p[0] + e3 * p[1] + t * w;
        let xyz = |p: Vec3| format!("X{:.9} Y{:.9} Z{:.9}", p.x, p.y, p.z);
        let last = pts[pts.len() - 1];
        let mut src =
            format!("G90 G00 {} B{b:.3} C{c:.3}\nG43.4 H1\nG41.2 D1\nG01 F3000. ", xyz(lift([-10.0, 0.0], 0.0)));
        for p in &pts {
            src += &format!("{}\n", xyz(lift(*p, -3.0 + 6.0 * rand())));
        }
        src += &format!("G40 {}\nG49\nM30\n", xyz(lift([last[0] + 10.0, last[1]], 0.0)));
        let plain = first_alarm_with(&src, preset, settings(false));
        let mut interp = interpreter_with(&src, preset, Fanuc, settings(true));
        // Line 5 + k runs the contour's block k + 1 (from pts[k] to pts[k + 1]).
        let contour = 5..5 + pts.len() as u32 - 1;
        let mut worst = f64::INFINITY;
        let mut samples = 0;
        let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
            if contour.contains(&s.line) {
                let tip = kin.forward(&s.machine, 100.0).tip_machine;
                let p = [tip.dot(&e2), tip.dot(&e3)];
                let d = pts.windows(2).map(|w| dist(p, w[0], w[1])).fold(f64::INFINITY, f64::min);
                worst = worst.min(d);
                samples += 1;
            }
        });
        if let Some(a) = r.alarms.first() {
            assert_eq!(a.code, "PS0041", "{src}");
            alarms += 1;
            continue;
        }
        assert!(samples > 20, "{samples} samples\n{src}");
        assert!(worst >= 5.0 - 1e-3, "{preset}: a tip {worst} from the contour in the plane\n{src}");
        if plain.is_some_and(|a| a.0 == "PS0041") {
            avoided += 1;
        }
    }
    assert!(avoided * 5 >= total, "only {avoided} of {total} programs were avoided ({alarms} alarms)");
}

// --- the table coordinate system without TCP (TBP = 1, WKP = 0; CRC-38, M-14) ----------------

mod table_system {
    //! FANUC 5-axis manual §3.2.2/§3.3.2 (CRC-38, M-14): with TBP = 1 and WKP = 0 the tool side
    //! offset without TCP reads X/Y/Z in the table coordinate system — the workpiece system frozen
    //! to the table at the end of the G41.2 block (INZ = 0) or with the table axes at 0 (INZ = 1)
    //! — and compensates there; the machine's linear axes carry the programmed point through the
    //! table's turn (`interp::table_crc`). The presets' table axes turn left-handed, so a point
    //! at p in the table system (frozen at C = c0) is at p_w = Rz(−(C − c0))·p in the workpiece
    //! system when the table stands at C (M-14's p_w = Rz(−C)·p_t, with c0 = 0). Work offsets 0,
    //! radius 5, no tool length (G49: §3.5.3's list of states the mode starts in has no G43, so
    //! the programmed point, and the tip read with length 0, is the spindle nose); at A0/B0 the
    //! tool is along Z.

    use super::*;
    use fivex_engine::machine::TcpCoordinates::{self, TableAtStart, TableAtZero};
    use fivex_engine::run::{run, RunOptions, Sample};

    /// A 40 mm square run counter-clockwise in the table system with G41.2 (the tool inside),
    /// entered along its first side; N6 turns the table by 30° while it runs.
    fn square(a: &str, c0: f64) -> String {
        format!(
            "N1 G90 G00 X-20. Y0 Z10. {a}0 C{c0:.1}\nN2 G49 Z10.\nN3 G41.2 D1\nN4 G01 X0 Y0 F500.\nN5 X40.\n\
             N6 Y40. C{:.1}\nN7 X0\nN8 Y0\nN9 G40 X-20.\nN10 M30\n",
            c0 + 30.0
        )
    }

    fn with(coordinates: TcpCoordinates, det: bool) -> impl FnOnce(&mut fivex_engine::interp::Config) {
        move |c: &mut fivex_engine::interp::Config| {
            tbp(coordinates)(c);
            c.edit_machine(|m| m.five_axis.display_workpiece = det);
        }
    }

    /// The samples of a run (every 2 ms), and where each line's last motion ends (after the
    /// stages): the machine axes, and the tip there by forward kinematics (table frame, tool
    /// length 0).
    struct Run {
        samples: Vec<Sample>,
        ends: Vec<(u32, [f64; 8], Vec3)>,
    }

    fn samples(src: &str, preset: &str, coordinates: TcpCoordinates, det: bool) -> Run {
        let mut interp = interpreter_with(src, preset, Fanuc, with(coordinates, det));
        let mut samples = Vec::new();
        let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| samples.push(*s));
        assert!(r.alarms.is_empty(), "{:?}", r.alarms);
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let mut ends: Vec<(u32, [f64; 8], Vec3)> = Vec::new();
        let alarm = through_stages(interpreter_with(src, preset, Fanuc, with(coordinates, det)), |c| {
            if let CanonKind::Motion(m) = c.kind {
                let mut machine = [0.0; 8];
                machine[..m.machine.len().min(8)].copy_from_slice(&m.machine[..m.machine.len().min(8)]);
                ends.retain(|(l, ..)| *l != c.line);
                ends.push((c.line, machine, kin.forward(&m.machine, 0.0).tip));
            }
        });
        assert_eq!(alarm, None);
        Run { samples, ends }
    }

    /// Rz(θ) of the x-y part, degrees.
    fn rz(deg: f64, p: [f64; 3]) -> Vec3 {
        let (s, c) = deg.to_radians().sin_cos();
        Vec3::new(c * p[0] - s * p[1], s * p[0] + c * p[1], p[2])
    }

    /// The compensated tool-tip path by hand, in the table system: the start-up block N4 ends
    /// perpendicular to N5 at its start, on its left (0, 5) (type A, the two collinear); the
    /// square's corners turn left, inside for G41.2: the offset sides meet 5 in from each
    /// corner; N8 ends perpendicular to itself (the cancel, type A): moving −Y its left is +X,
    /// (5, 0); N9 moves to the programmed point. Z stays 10 (the tool along Z: no vector along
    /// it).
    const ENDS: [(u32, [f64; 3]); 6] = [
        (4, [0.0, 5.0, 10.0]),
        (5, [35.0, 5.0, 10.0]),
        (6, [35.0, 35.0, 10.0]),
        (7, [5.0, 35.0, 10.0]),
        (8, [5.0, 0.0, 10.0]),
        (9, [-20.0, 0.0, 10.0]),
    ];

    /// Every sample of lines 4–9 (the tip by forward kinematics of the sampled axes, table
    /// frame, turned into the table system by `to_system`) is on its block's straight line of
    /// the hand-worked path within 1 µm, and each block ends at its hand-worked point.
    #[track_caller]
    fn assert_on_path(run: &Run, start: [f64; 3], to_system: impl Fn([f64; 3]) -> Vec3) {
        let mut from = Vec3::from(start);
        for (line, end) in ENDS {
            let end = Vec3::from(end);
            let on: Vec<&Sample> = run.samples.iter().filter(|s| s.line == line).collect();
            assert!(!on.is_empty(), "line {line}");
            let d = (end - from).normalize();
            for s in &on {
                let p = to_system(s.tip_table) - from;
                let off = (p - d * p.dot(&d)).norm();
                assert!(off < 1e-6, "line {line}: {:?} off the line by {off}", to_system(s.tip_table));
            }
            let (.., tip) = run.ends.iter().find(|(l, ..)| *l == line).unwrap();
            let last = to_system((*tip).into());
            assert!((last - end).norm() < 1e-6, "line {line}: ends at {last:?}, by hand {end:?}");
            from = end;
        }
    }

    #[test]
    fn crc38_the_square_is_cut_on_the_table_while_it_turns() {
        // Frozen at C30 (INZ = 0): the table system is the workpiece system with the table at
        // C30, so a point p of it is in the table frame at Rz(30)·p (left-handed C) and the tip
        // (table frame) is read back in it by Rz(−30).
        for preset in ["table-ac", "table-bc", "mixed-bc"] {
            let a = if preset == "table-ac" { "A" } else { "B" };
            let got = samples(&square(a, 30.0), preset, TableAtStart, false);
            assert_on_path(&got, [-20.0, 0.0, 10.0], |t| rz(-30.0, t));
            // N6's end by hand in machine terms: the tip (35, 35, 10) of the table system with the
            // table at C60, 30° past the freeze: Rz(−30)·(35, 35) = (35 cos30 + 35 sin30,
            // −35 sin30 + 35 cos30) = (47.810889, 12.810889) in the workpiece system — the
            // machine's X/Y (offsets 0, the nose over X/Y, the tool along Z).
            let (_, n6, _) = got.ends.iter().find(|(l, ..)| *l == 6).unwrap();
            assert!((n6[0] - 47.810889).abs() < 1e-6 && (n6[1] - 12.810889).abs() < 1e-6, "{preset}: {n6:?}");
            assert!((n6[4] - 60.0).abs() < 1e-9);
        }
    }

    #[test]
    fn on_a_mixed_machine_the_tool_is_read_in_the_table_system_as_the_table_turns_under_it() {
        // mixed-bc, the head at B30 (the tool (sin30, 0, cos30) = (0.5, 0, 0.866025) in the
        // machine), frozen at C0. N3 enters along +Y and N4 goes on along +Y while C turns to
        // 90: at N4's end the table has turned under the head, so in the table system the tool
        // is Rz(90)·(0.5, 0, 0.866025) = (0, 0.5, 0.866025) (a point p of it is at Rz(−C)·p).
        // N4 is the block before G40: its vector is perpendicular to itself in the plane ⊥ that
        // tool — the move (0, 40, 0) projected there, (0, 40, 0) − 20·t = (0, 30, −17.320508),
        // unit u = (0, 0.866025, −0.5); G41.2's left n = t × u = (−0.25 − 0.75, 0, 0) = (−1, 0, 0):
        // N4 ends at (0, 40, 50) + 5·n = (−5, 40, 50) in the table system. Machine X/Y there,
        // C90: Rz(−90)·(−5, 40) = (40, 5).
        let src = "N1 G90 G00 X0 Y-20. Z50. B30. C0\nN2 G41.2 D1\nN3 G01 Y0 F500.\nN4 Y40. C90.\n\
                   N5 G40 Y60.\nN6 M30\n";
        let got = samples(src, "mixed-bc", TableAtStart, false);
        let (_, m, _) = got.ends.iter().find(|(l, ..)| *l == 4).unwrap();
        assert!((m[0] - 40.0).abs() < 1e-6 && (m[1] - 5.0).abs() < 1e-6, "{m:?}");
        assert!((m[3] - 30.0).abs() < 1e-9 && (m[4] - 90.0).abs() < 1e-9);
        // The point the machine carries (the unturned tip: G49, the nose) in the table system.
        let kin = Kinematics::new(&MachineConfig::preset("mixed-bc").unwrap()).unwrap();
        let point = kin.unturned_tip(m, 0.0);
        assert!((point - Vec3::new(-5.0, 40.0, 50.0)).norm() < 1e-6, "{point:?}");
        // N3 (the start-up) ends perpendicular to N4 at its start, where the table still stands
        // at C0: the tool (0.5, 0, 0.866025), +Y projected is +Y itself, n = t × Y =
        // (−0.866025, 0, 0.5): (0, 0, 50) + 5·n = (−4.330127, 0, 52.5).
        let (_, m3, _) = got.ends.iter().find(|(l, ..)| *l == 3).unwrap();
        let p3 = kin.unturned_tip(m3, 0.0);
        assert!((p3 - Vec3::new(-4.330127, 0.0, 52.5)).norm() < 1e-6, "{p3:?}");
    }

    #[test]
    fn m14_the_same_part_with_the_table_turned_is_the_same_tip_path_on_it() {
        // The same program frozen at C0 and at C90: every sample's tip in its table system
        // (Rz(−c0) of the table frame) is on the same hand-worked path. The machine's X/Y/Z are
        // the same at every block end (the part turned with the table: at N6's end the table has
        // turned 30° past the freeze either way, Rz(−30)·(35, 35)), C is 90° apart.
        let at0 = samples(&square("A", 0.0), "table-ac", TableAtStart, false);
        let at90 = samples(&square("A", 90.0), "table-ac", TableAtStart, false);
        assert_on_path(&at0, [-20.0, 0.0, 10.0], Vec3::from);
        assert_on_path(&at90, [-20.0, 0.0, 10.0], |t| rz(-90.0, t));
        for ((l0, m0, _), (l90, m90, _)) in at0.ends.iter().zip(&at90.ends) {
            assert_eq!(l0, l90);
            assert!((0..3).all(|k| (m0[k] - m90[k]).abs() < 1e-9), "line {l0}: {m0:?} {m90:?}");
            assert!((m90[4] - m0[4] - 90.0).abs() < 1e-9, "line {l0}: {m0:?} {m90:?}");
        }
    }

    #[test]
    fn inz_fixes_the_table_system_with_the_table_axes_at_0() {
        // INZ = 1, the G41.2 block at C30: the table system is the workpiece system at C0, the
        // table frame itself here (offsets 0, nose on the table's axis). The start-up block
        // starts where the tool stands, (−20, 0) of the workpiece system at C30: Rz(30)·(−20, 0)
        // = (−17.320508, −10) in the table system; the rest of the path is the same square.
        let got = samples(&square("A", 30.0), "table-ac", TableAtZero, false);
        assert_on_path(&got, [-10.0 * 3f64.sqrt(), -10.0, 10.0], Vec3::from);
    }

    #[test]
    fn crc38_det_shows_the_table_system_or_the_workpiece_system() {
        // DET = 0: the position display (the commanded point) in the table system, named
        // `programming`; DET = 1: in the workpiece system with the machine's axes. At N6's end the
        // commanded point is the compensated one (35, 35, 10) in the table system, and
        // Rz(−30)·(35, 35) = (47.810889, 12.810889) in the workpiece system (the table at C60).
        // (A dwell after N6 shows where it ended.)
        let src = square("A", 30.0).replace("N7 X0", "N7 G04 P500\nN7 X0");
        let shown = |det: bool| {
            let s = samples(&src, "table-ac", TableAtStart, det);
            let dwell = *s.samples.iter().rfind(|s| s.line == 7).unwrap();
            (dwell.programmed, dwell.programmed_in.name())
        };
        let (p, name) = shown(false);
        assert!((Vec3::from(p) - Vec3::new(35.0, 35.0, 10.0)).norm() < 1e-6, "{p:?}");
        assert_eq!(name, "programming");
        let (p, name) = shown(true);
        assert!((Vec3::from(p) - Vec3::new(47.810889, 12.810889, 10.0)).norm() < 1e-6, "{p:?}");
        assert_eq!(name, "workpiece_machine_axes");
    }

    #[test]
    fn crc38_the_g40_block_suppresses_buffering_the_machine_stops_before_it() {
        // After the stages: N8's move, then the stop (a dwell of no time, line 9), then the G40
        // block's move; the machine comes to rest at N8's end, (5, 0) of the table system.
        let mut order = Vec::new();
        let interp = interpreter_with(&square("A", 30.0), "table-ac", Fanuc, with(TableAtStart, false));
        let alarm = through_stages(interp, |c| match c.kind {
            CanonKind::Motion(_) => order.push((c.line, "move")),
            CanonKind::Dwell { seconds } => order.push((c.line, if seconds == 0.0 { "stop" } else { "dwell" })),
            _ => {}
        });
        assert_eq!(alarm, None);
        let at = order.iter().position(|&(l, k)| (l, k) == (9, "stop")).expect("a stop at the G40 block");
        assert_eq!((order[at - 1], order[at + 1]), ((8, "move"), (9, "move")));
        // The run stands there: with the G40 block going on along N8 (X5. Y-20.: straight on
        // from (5, 0)), the slowest sample of N8's second half and G40's first half is at rest
        // (0 within the 2 ms sampling: the S-curve's last period, j·t²/2 = 80000 · 0.002² / 2
        // mm/s = 9.6 mm/min at most); read ahead (the same path in the workpiece system, WKP =
        // 1, the table standing) it is passed at the feed.
        let straight_on = square("A", 30.0).replace("C60.0", "C30.0").replace("G40 X-20.", "G40 X5. Y-20.");
        let slowest = |coordinates| {
            samples(&straight_on, "table-ac", coordinates, false)
                .samples
                .iter()
                .filter(|s| {
                    let y = rz(-30.0, s.tip_table).y;
                    s.line == 8 && y < 17.0 || s.line == 9 && y > -10.0
                })
                .map(|s| s.feed)
                .fold(f64::INFINITY, f64::min)
        };
        assert!(slowest(TableAtStart) < 10.0);
        let read_ahead = slowest(TcpCoordinates::Workpiece);
        assert!(read_ahead > 499.0, "{read_ahead}");
    }

    #[test]
    fn after_g40_the_program_is_read_in_the_workpiece_system_again() {
        // The table stands at C60 after the square: X-30. Y0 of a block after G40 is the workpiece
        // point itself (machine X/Y with offsets 0), not the table system's (which would be at
        // Rz(−30)·(−30, 0)).
        let src = square("A", 30.0).replace("N10 M30", "N10 G00 X-30. Y0\nN11 M30");
        let got = samples(&src, "table-ac", TableAtStart, false);
        let (_, m, _) = got.ends.iter().find(|(l, ..)| *l == 10).unwrap();
        assert!((m[0] + 30.0).abs() < 1e-9 && m[1].abs() < 1e-9 && (m[4] - 60.0).abs() < 1e-9, "{m:?}");
        assert_eq!(got.samples.last().unwrap().programmed_in.name(), "workpiece");
    }

    #[test]
    fn crc38_alarms_in_the_table_system_without_tcp() {
        let alarm = |src: &str, edit: fn(&mut MachineConfig)| {
            first_alarm_with(src, "table-ac", |c| {
                tbp(TableAtStart)(c);
                c.edit_machine(edit);
            })
        };
        let src = square("A", 30.0);
        assert_eq!(alarm(&src, |_| {}), None);
        // `fivex check` runs the interpreter and the stages: no longer "not built" (PS0010).
        let mut interp = interpreter_with(&src, "table-ac", Fanuc, tbp(TableAtStart));
        assert_eq!(fivex_engine::check::run_without_motion(&mut interp, true).map(|s| s.alarm.code), None);
        // PS5483: the look-ahead prerequisites, at the G41.2 block (TV-20).
        assert_eq!(alarm(&src, |m| m.motion.nonlinear_rapid = true), Some(("PS5483".into(), 3)));
        assert_eq!(alarm(&src, |m| m.motion.no_feed_look_ahead = true), Some(("PS5483".into(), 3)));
        // PS5460: a workpiece system selected in the mode (CRC-38 note 3).
        let g55 = src.replace("N7 X0", "N7 G55 X0");
        assert_eq!(alarm(&g55, |_| {}), Some(("PS5460".into(), 7)));
        // The table turned in the G41.2 block: its move ends first, then the system is frozen
        // (there at C30: the same path as the square started at C30).
        let turning = square("A", 0.0).replace("N3 G41.2 D1", "N3 G41.2 D1 C30.").replace("C30.0\nN7", "C60.\nN7");
        let got = samples(&turning, "table-ac", TableAtStart, false);
        assert_on_path(&got, [-20.0, 0.0, 10.0], |t| rz(-30.0, t));
        // With SPG (No.19607#1) the mechanism's codes, G41.4 on table-ac and G41.5 on mixed-bc,
        // compensate in the table system as G41.2 does: the same block ends.
        for (preset, tilt, code) in [("table-ac", "A", "G41.4"), ("mixed-bc", "B", "G41.5")] {
            let src = square(tilt, 30.0);
            let by_mechanism = src.replace("G41.2", code);
            let spg_tbp = |c: &mut fivex_engine::interp::Config| {
                with(TableAtStart, false)(c);
                spg(c);
            };
            let ends = |src: &str, tweak: &dyn Fn(&mut fivex_engine::interp::Config)| {
                let mut ends = Vec::new();
                let interp = interpreter_with(src, preset, Fanuc, tweak);
                let alarm = through_stages(interp, |c| {
                    if let CanonKind::Motion(m) = c.kind {
                        ends.push((c.line, m.machine));
                    }
                });
                assert_eq!(alarm, None, "{preset} {src}");
                ends
            };
            assert_eq!(ends(&by_mechanism, &spg_tbp), ends(&src, &|c| with(TableAtStart, false)(c)), "{preset}");
        }
    }
}

mod table_system_random {
    //! The tool side offset in the table coordinate system without TCP on random contours: a star
    //! polygon lifted into the plane perpendicular to the tool as the table system sees it, the
    //! table turned before G41.2 and the system fixed with the table axes at 0 (INZ = 1), so that
    //! the table system is neither the workpiece system nor the machine's directions.

    use super::*;
    use proptest::prelude::*;

    use super::random::{contour, touching};

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(24), max_global_rejects: 10_000, ..ProptestConfig::default() })]
        /// At every sample in the middle of a contour block, the point the machine carries (the
        /// unturned tip, forward kinematics of the sampled axes; G49, so the spindle nose), read
        /// in the table system, is at the radius from the programmed line in the plane
        /// perpendicular to the tool, on the commanded side: on table-ac, table-bc and mixed-bc.
        #[test]
        fn every_sample_keeps_the_radius_in_the_table_system(
            machine in 0..3usize,
            b in -40.0..40.0f64,
            c in -180.0..180.0f64,
            corners in contour(),
            left in any::<bool>(),
        ) {
            let (preset, tilt) = [("table-ac", "A"), ("table-bc", "B"), ("mixed-bc", "B")][machine];
            // table-bc's B turns within −30…110.
            let b = if preset == "table-bc" { b.abs() } else { b };
            let (b, c) = ((b * 1000.0).round() / 1000.0, (c * 1000.0).round() / 1000.0);
            let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
            let mut pos = [0.0; 8];
            (pos[3], pos[4]) = (b, c);
            // With INZ = 1 and no offsets the table system is the table frame: the tool there.
            let t = kin.forward(&pos, 0.0).tool;
            let e2 = t.cross(&Vec3::new(0.3, -0.5, 0.8)).normalize();
            let e3 = t.cross(&e2);
            let points: Vec<Vec3> =
                corners.iter().map(|(a, r, z)| e2 * (r * a.cos()) + e3 * (r * a.sin()) + t * *z).collect();
            let xyz = |p: &Vec3| format!("X{:.9} Y{:.9} Z{:.9}", p.x, p.y, p.z);
            // The G00 block is in the workpiece system: the start placed on the turned table.
            let start = points[0] * 1.6;
            let start_w = kin.table_frame(&pos).to_parent(&start);
            let side = if left { "G41.2" } else { "G42.2" };
            let mut src = format!("G90 G00 {} {tilt}{b:.3} C{c:.3}\n{side} D1\nG01 F3000. ", xyz(&start_w));
            for p in points.iter().chain(std::iter::once(&points[0])) {
                src += &format!("{}\n", xyz(p));
            }
            src += &format!("G40 {}\nM30\n", xyz(&start));
            let inz = tbp(fivex_engine::machine::TcpCoordinates::TableAtZero);
            prop_assume!(first_alarm_with(&src, preset, inz).is_none());
            let mut interp =
                interpreter_with(&src, preset, Fanuc, tbp(fivex_engine::machine::TcpCoordinates::TableAtZero));
            let n = points.len();
            let (mut checked, mut cut_checked) = (0, 0);
            let (mut worst, mut worst_cut) = (0.0f64, 0.0f64);
            let mut samples = Vec::new();
            let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
                samples.push(*s);
                // Line 4 + k runs from corner k to corner k + 1 (the start-up block is line 3).
                let k = s.line as usize;
                if !(4..4 + n).contains(&k) {
                    return;
                }
                let (p, q) = (points[(k - 4) % n], points[(k - 3) % n]);
                let point = kin.unturned_tip(&s.machine, 0.0);
                let flat = |v: Vec3| v - t * v.dot(&t);
                let (d, w) = (flat(q - p), flat(point - p));
                let u = d.dot(&w) / d.norm_squared();
                if !(0.25..=0.75).contains(&u) {
                    return;
                }
                let across = w - d * u;
                let sign = if t.dot(&d.cross(&across)) > 0.0 { 1.0 } else { -1.0 };
                let want = if left { 5.0 } else { -5.0 };
                worst = worst.max((sign * across.norm() - want).abs());
                checked += 1;
                // The cutting point (the trace's, in the table frame like `tip`) moved with the
                // tip onto the unturned tip: as in the test above.
                if let Some(cut) = s.cutting {
                    let at = point + (Vec3::from(cut) - Vec3::from(s.tip));
                    worst_cut = worst_cut.max((at - touching(p + (q - p) * u, point, t)).norm());
                    cut_checked += 1;
                }
            });
            prop_assert!(r.completed(), "{:?}", r.alarms);
            prop_assert!(checked > 10 * n, "{} samples checked", checked);
            prop_assert!(worst < 1e-3, "a sample {} mm off the radius", worst);
            prop_assert_eq!(cut_checked, checked, "samples without a cutting point");
            prop_assert!(worst_cut < 1e-3, "a cutting point {} mm off the programmed line", worst_cut);
            check_limits_by_segment(&samples, &MachineConfig::preset(preset).unwrap())
                .map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
        }
    }
}
