//! Canned cycles (issue 17, item 2): the repeat count K, G91 levels, the dwell of peck cycles,
//! G92 against G52, and hole machining in the tilted working plane (twp §1.3.2: the cycles
//! are allowed there and drill along the feature coordinate system's Z).

use crate::common;

use common::{canon, interpreter, motions};
use fivex_engine::canon::CanonKind;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, Sample};
use fivex_engine::Dialect;

#[test]
fn k_repeats_in_the_syntec_dialect_too() {
    let src = "G90 G00 X0 Y0 Z20.\nG91 G98 G81 X10. R-15. Z-7. K2 F300.\nG80\nG90\nM30\n";
    let r = common::run_with(src, "mill3", Dialect::Syntec);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.workpiece[0], 20.0);
}

#[test]
fn k0_stores_the_cycle_data_without_drilling() {
    let src = "G90 G00 X0 Y0 Z20.\nG99 G81 X10. R5. Z-7. K0 F300.\nX30.\nG80\nM30\n";
    let m = motions(src);
    assert!(m.iter().all(|m| m.target[0] != 10.0), "K0 moved to its hole");
}

fn dwells(src: &str) -> usize {
    canon(src).iter().filter(|c| matches!(c.kind, CanonKind::Dwell { .. })).count()
}

#[test]
fn peck_cycles_do_not_dwell_with_a_p_left_from_g82() {
    for peck in ["G73", "G83"] {
        let src = format!("G90 G00 X0 Y0 Z10.\nG82 X0 Y0 Z-5. R2. P500 F600\n{peck} X5. Q2.\nG80\nM30\n");
        assert_eq!(dwells(&src), 1, "{peck}: only G82's hole dwells");
    }
}

// --- the tilted working plane --------------------------------------------------------------

/// The feature coordinate system of the programs below (Euler Z–X–Z, twp TWP-01).
fn fcs() -> fivex_engine::geom::Rigid {
    fivex_engine::twp::euler(Vec3::new(20.0, 10.0, 0.0), 30.0, 20.0, 10.0)
}

const TILTED: &str = "N1 G90 G54 G00 X0 Y0 Z60.\nN2 G68.2 X20. Y10. Z0 I30. J20. K10.\nN3 G53.1\n\
                      N4 G43 H1\nN5 G00 X5. Y5. Z30.\nN6 G98 G81 X10. Y-5. Z-8. R3. F300.\n\
                      N7 G99 X-10. Y5.\nN8 G83 X0 Y0 Z-6. R2. Q4.\nN9 G80\nN10 G49\nN11 G69\nM30\n";

/// Every sample of the program with its tool tip and tool direction in `frame` (the FCS, or
/// the workpiece system as the identity), by forward kinematics of the machine axes (tool
/// length 100; the presets' table frame is the workpiece system under G54).
fn sampled(preset: &str, dialect: Dialect, src: &str, frame: &fivex_engine::geom::Rigid) -> Vec<(u32, Vec3, Vec3)> {
    let m = MachineConfig::preset(preset).unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let mut interp = interpreter(src, preset, dialect);
    let mut samples: Vec<Sample> = Vec::new();
    let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| samples.push(*s));
    assert!(r.completed(), "{preset}: {:?}", r.alarms);
    let f = frame;
    samples
        .iter()
        .map(|s| {
            let pose = kin.forward(&s.machine, 100.0);
            (s.line, f.from_parent(&pose.tip), f.r.transpose() * pose.tool)
        })
        .collect()
}

/// Checks one hole block: the tip is at the initial level (positioning) or on the hole's axis
/// between the bottom and that level, the bottom and R are reached, it ends at `end_z`.
fn check_hole(got: &[(u32, Vec3, Vec3)], line: u32, hole: (f64, f64), bottom: f64, top: f64, end_z: f64, what: &str) {
    check_hole_with(got, line, hole, (bottom, top, end_z), Vec3::z(), what)
}

fn check_hole_with(
    got: &[(u32, Vec3, Vec3)],
    line: u32,
    hole: (f64, f64),
    (bottom, top, end_z): (f64, f64, f64),
    tool_along: Vec3,
    what: &str,
) {
    // The axes follow the tip through the kinematics to a few 0.1 µm (`docs/motion.md`).
    const TOL: f64 = 1e-4;
    let s: Vec<_> = got.iter().filter(|(l, _, _)| *l == line).collect();
    assert!(s.len() > 10, "{what}: samples of N{line}");
    let mut min_z = f64::INFINITY;
    for (_, tip, tool) in &s {
        assert!((tool - tool_along).norm() < 1e-6, "{what} N{line}: tool {tool:?}, expected {tool_along:?}");
        let on_axis = (tip.x - hole.0).abs() < TOL && (tip.y - hole.1).abs() < TOL;
        let at_top = (tip.z - top).abs() < TOL;
        assert!(on_axis || at_top, "{what} N{line}: tip {tip:?} off the hole axis below the initial level");
        assert!(tip.z > bottom - TOL && tip.z < top + TOL, "{what} N{line}: tip {tip:?} outside the levels");
        min_z = min_z.min(tip.z);
    }
    assert!((min_z - bottom).abs() < TOL, "{what} N{line}: bottom {min_z}, expected {bottom}");
    let last = s.last().unwrap().1;
    assert!((last - Vec3::new(hole.0, hole.1, end_z)).norm() < TOL, "{what} N{line}: ends at {last:?}");
}

#[test]
fn drilling_cycles_in_the_tilted_plane_drill_at_the_fcs_hole_along_fcs_z() {
    for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
        for dialect in [Dialect::Fanuc, Dialect::Syntec] {
            let what = format!("{preset} {dialect:?}");
            let got = sampled(preset, dialect, TILTED, &fcs());
            // Initial level 30 (N5). N6 G98: back to 30. N7 G99: back to R 3. N8 G83 G99: R 2.
            check_hole(&got, 6, (10.0, -5.0), -8.0, 30.0, 30.0, &what);
            check_hole(&got, 7, (-10.0, 5.0), -8.0, 30.0, 3.0, &what);
            // N8 starts at the R level of N7 (3) and positions there.
            let n8: Vec<_> = got.iter().filter(|(l, _, _)| *l == 8).collect();
            for (_, tip, _) in &n8 {
                let on_axis = tip.x.abs() < 1e-4 && tip.y.abs() < 1e-4;
                assert!(on_axis || (tip.z - 3.0).abs() < 1e-4, "{what} N8: {tip:?}");
            }
            let min = n8.iter().map(|(_, t, _)| t.z).fold(f64::INFINITY, f64::min);
            assert!((min + 6.0).abs() < 1e-4, "{what} N8 bottom {min}");
            assert!((n8.last().unwrap().1 - Vec3::new(0.0, 0.0, 2.0)).norm() < 1e-4, "{what} N8 end");
        }
    }
}

#[test]
fn syntec_cycles_under_rtcp_drill_at_the_workpiece_hole_with_the_tool_tilted() {
    // FANUC refuses a cycle under TCP (TV-63, PS5421); Syntec's manual names no such rule, and
    // under RTCP every programmed point is the tool tip in the workpiece: the hole is drilled
    // along the workpiece Z with the tool as the rotary axes hold it.
    let src = "N1 G90 G00 X0 Y0 Z60. B0 C0\nN2 G43.4 H1\nN3 G00 X5. Y5. Z30. B30. C0\n\
               N4 G98 G81 X10. Y-5. Z-8. R3. F300.\nN5 G80\nN6 G49\nM30\n";
    let identity = fivex_engine::twp::euler(Vec3::zeros(), 0.0, 0.0, 0.0);
    let m = MachineConfig::preset("head-bc").unwrap();
    let tool = Kinematics::new(&m).unwrap().forward(&[0.0, 0.0, 0.0, 30.0, 0.0], 100.0).tool;
    let got = sampled("head-bc", Dialect::Syntec, src, &identity);
    check_hole_with(&got, 4, (10.0, -5.0), (-8.0, 30.0, 30.0), tool, "head-bc Syntec RTCP");
}

#[test]
fn a_canned_cycle_must_not_span_the_start_or_end_of_the_plane() {
    // TWP-16: canned cycles nest inside G68.2 … G69. Ending the plane with the cycle on would
    // carry the FCS levels (R, Z, initial level) into the workpiece system.
    let src = "G90 G00 X0 Y0 Z50.\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG81 X0 Y0 Z-1. R1. F100\nG69\nG80\nM30\n";
    let ok = src.replace("G69\nG80\n", "G80\nG69\n");
    // FANUC TWP-11 refuses a cycle on at G68.2; Syntec the same, a decision.
    let before = "G90 G00 X0 Y0 Z50.\nG81 X0 Y0 Z-1. R1. F100\nG68.2 X0 Y0 Z0 I0 J30. K0\nG80\nG69\nM30\n";
    for (dialect, code) in [(Dialect::Fanuc, "PS5462"), (Dialect::Syntec, "COR-100")] {
        let r = common::run_with(src, "head-bc", dialect);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((code, 5)), "{dialect:?}");
        assert!(common::run_with(&ok, "head-bc", dialect).completed(), "{dialect:?}");
        let r = common::run_with(before, "head-bc", dialect);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((code, 3)), "{dialect:?}");
    }
}

/// G76/G87 shift the oriented tool's edge off the wall by Q in a direction of the machine; under
/// a coordinate rotation or a mirror image fivex turned or mirrored it with the program (mirrored,
/// the shift pushed the edge into the bore), which no manual at hand confirms: refused as not
/// built, as is the cycle repeated later in that state; without a shift (Q0) or without the
/// transforms it runs.
#[test]
fn fine_and_back_boring_shift_is_refused_under_rotation_or_mirror() {
    let head = "G90 G00 X0 Y0 Z50.\n";
    for (transform, cycle) in [
        ("G68 X0 Y0 R90.", "G76 X10. Y0 Z-10. R2. Q1. F100."),
        ("G51.1 X0", "G76 X10. Y0 Z-10. R2. Q1. F100."),
        ("G51 X0 Y0 I-1000 J1000", "G87 X10. Y0 Z-2. R-12. Q1. F100."),
    ] {
        // (Syntec's G68 takes another form: its mirror image is enough to show it.)
        let syntec = transform.starts_with("G51.1");
        let dialects: &[Dialect] = if syntec { &[Dialect::Fanuc, Dialect::Syntec] } else { &[Dialect::Fanuc] };
        for &dialect in dialects {
            let src = format!("{head}{transform}\n{cycle}\nG80\nM30\n");
            let r = common::run_with(&src, "mill3", dialect);
            let want = if dialect == Dialect::Fanuc { "PS0010" } else { "COR-100" };
            assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((want, 3)), "{src}");
            // The cycle given before the transform, repeated by a hole position under it.
            let src = format!("{head}{cycle}\n{transform}\nX20.\nG80\nM30\n");
            let r = common::run_with(&src, "mill3", dialect);
            assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((want, 4)), "{src}");
            let no_shift = format!("{head}{transform}\n{}\nG80\nM30\n", cycle.replace("Q1.", "Q0"));
            assert!(common::run_with(&no_shift, "mill3", dialect).completed(), "{no_shift}");
            let plain = format!("{head}{cycle}\nG80\nM30\n");
            assert!(common::run_with(&plain, "mill3", dialect).completed(), "{plain}");
        }
    }
}

/// The machine's cycle settings (FANUC No.5101#4/#5, No.5114, No.5115): G76's shift goes the
/// way RD1/RD2 set — named as in G17, the plane's first and second axes in G18/G19 — and G73's
/// retract and G83's clearance are the machine's; fivex's defaults (+X, 0.5 mm) without them.
#[test]
fn cycle_settings_set_the_bore_shift_and_the_peck_distances() {
    use fivex_engine::machine::{BoreShift, CycleOptions};
    let ends = |src: &str, cycles: CycleOptions, axis: usize| -> Vec<f64> {
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.cycles = cycles;
        let mut interp = fivex_engine::interp::Interpreter::new(
            fivex_engine::lang::parse_file(src),
            fivex_engine::interp::Config::new(m, Dialect::Fanuc),
        );
        let mut v = Vec::new();
        interp.run(|c| v.push(c)).expect("no alarm");
        v.iter()
            .filter_map(|c| match &c.kind {
                CanonKind::Motion(m) => Some(m.target[axis]),
                _ => None,
            })
            .collect()
    };
    let with = |bore_shift| CycleOptions { bore_shift, ..CycleOptions::default() };
    // G17, the hole at X10 Y20: the shift at the bottom by Q2 and back.
    let g76 = "G90 G17 G00 X0 Y0 Z10.\nG76 X10. Y20. Z-5. R2. Q2. F100.\nG80\nM30\n";
    for (shift, axis, hole, to) in [
        (BoreShift::PlusX, 0, 10.0, 12.0),
        (BoreShift::MinusX, 0, 10.0, 8.0),
        (BoreShift::PlusY, 1, 20.0, 22.0),
        (BoreShift::MinusY, 1, 20.0, 18.0),
    ] {
        let along = ends(g76, with(shift), axis);
        assert!(along.contains(&to), "{shift:?}: {along:?}");
        assert!(along.iter().all(|&x| x == 0.0 || x == hole || x == to), "{shift:?}: {along:?}");
        let other = ends(g76, with(shift), 1 - axis);
        assert!(other.iter().all(|&x| x == 0.0 || x == [20.0, 10.0][axis]), "{shift:?} moved across: {other:?}");
    }
    // G18 (Z–X plane, drilling along Y): -y is −X, the plane's second axis.
    let g18 = "G90 G18 G00 X0 Y10. Z0\nG76 X10. Z20. Y-5. R2. Q2. F100.\nG80\nM30\n";
    assert!(ends(g18, with(BoreShift::MinusY), 0).contains(&8.0));
    assert!(ends(g18, with(BoreShift::PlusX), 2).contains(&22.0), "+x is +Z in G18");
    // G73 retracts by No.5114, G83 comes back to No.5115 above the last peck (Z-4).
    let peck = |code: &str| format!("G90 G00 X0 Y0 Z10.\n{code} Z-6. R2. Q6. F100.\nG80\nM30\n");
    let c = CycleOptions { peck_retract: 1.5, peck_clearance: 0.25, ..CycleOptions::default() };
    assert!(ends(&peck("G73"), c, 2).contains(&-2.5), "G73 back up 1.5 from Z-4");
    assert!(ends(&peck("G83"), c, 2).contains(&-3.75), "G83 down to 0.25 above Z-4");
    let d = CycleOptions::default();
    assert!(ends(&peck("G73"), d, 2).contains(&-3.5) && ends(&peck("G83"), d, 2).contains(&-3.5));
}

#[test]
fn check_reports_l_in_a_cycle_block() {
    use fivex_engine::check::check;
    use fivex_engine::lang::parse_file;
    let src = "G90 G00 X0 Y0 Z20.\nG91 G81 X10. R-15. Z-7. L3 F300.\nG80\nM98 P1 L2\nM30\nO1\nM99\n";
    let d = check(parse_file(src), Dialect::Fanuc);
    let found: Vec<_> = d.iter().map(|d| (d.line, d.col, d.id.clone())).collect();
    assert_eq!(found, vec![(2, 25, fivex_engine::AlarmId::ImproperAddress)]);
}

#[test]
fn syntec_refuses_k_in_a_cycle_block_under_tcp_type_2() {
    // Under G43.5 I/J/K are the tool direction: `K2` there is not a repeat count.
    let src = "G90 G00 X0 Y0 Z60. B0 C0\nG43.5 H1\nG00 X5. Y5. Z30.\nG98 G81 X10. Y-5. Z-8. R3. F300.\nX0 K2\nG80\nG49\nM30\n";
    let r = common::run_with(src, "head-bc", Dialect::Syntec);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("COR-100", 5)));
    assert!(common::run_with(&src.replace(" K2", ""), "head-bc", Dialect::Syntec).completed());
}

/// The cutting feeds of each line of `src` (mill3, FANUC).
fn feeds_per_line(src: &str) -> Vec<(u32, usize)> {
    let mut count: Vec<(u32, usize)> = Vec::new();
    for c in canon(src) {
        if let CanonKind::Motion(m) = &c.kind {
            if m.kind == fivex_engine::canon::MotionKind::Linear {
                match count.last_mut() {
                    Some((l, n)) if *l == c.line => *n += 1,
                    _ => count.push((c.line, 1)),
                }
            }
        }
    }
    count
}

#[test]
fn peck_cycles_cut_depth_over_q_feeds_with_no_empty_last_peck() {
    // Depth (R − Z) over Q, rounded up: the control counts in least input increments, so a
    // depth that is a whole number of pecks ends on its last full peck (4.2 / 0.7 = 6), where a
    // running sum in binary fractions fell short by 1e-16 and added a zero-depth peck.
    let cases = [
        ("G83", "Z-2.2 R2. Q0.7", 6),
        ("G83", "Z-0.9 R0.3 Q0.3", 4),
        ("G73", "Z-0.9 R0.3 Q0.1", 12),
        ("G83", "Z-0.9 R0.1 Q0.1", 10),
        ("G83", "Z-3.3 R0.3 Q0.3", 12),
        ("G83", "Z-4.2 R0.3 Q0.3", 15),
        ("G83", "Z-6.3 R0.3 Q0.3", 22),
        ("G83", "Z-6.3 R1. Q0.1", 73),
        ("G83", "Z-1.3 R0.5 Q0.3", 6),
        ("G83", "Z-3. R3. Q0.2", 30),
        ("G73", "Z-10. R2. Q5.", 3),
        ("G83", "Z-10. R2. Q-5.", 3),
        ("G83", "Z-10. R2. Q20.", 1),
    ];
    for (code, words, want) in cases {
        let src = format!("G90 G00 X0 Y0 Z50.\n{code} X0 Y0 {words} F600.\nG80\nM30\n");
        assert_eq!(feeds_per_line(&src), vec![(2, want)], "{code} {words}");
    }
}

#[test]
fn a_cycle_without_its_hole_bottom_is_refused_not_drilled_to_zero() {
    // *Decision* (docs/conventions.md, "Canned cycles"): no manual at hand says what the control
    // drills to when no bottom was given since the cycle started (the first cycle, or after
    // G80 / a group-01 code cleared the data); fivex refused to invent one (it fed to Z0).
    let head = "G90 G00 X0 Y0 Z50.\n";
    let cases = [
        ("G81 X10. Y10. R5. F600.\nG80\nM30\n", 2),
        ("G81 X10. Y10. Z-10. R5. F600.\nG80\nG81 X20. R5.\nG80\nM30\n", 4),
        ("G81 X10. Y10. Z-10. R5. F600.\nG01 X0\nG81 X20. R5.\nG80\nM30\n", 4),
        ("G81 X10. Y10. Z-10. R5. F600.\nG00 X0\nG83 X20. R5. Q2.\nG80\nM30\n", 4),
        // The drilling axis of G18 is Y, of G19 X: Z (or Y) there is no bottom.
        ("G18 G81 X10. Z10. R5. F600.\nG80\nM30\n", 2),
        ("G19 G81 Y10. Z10. R5. F600.\nG80\nM30\n", 2),
        // K0 stores the data, the next block drills with it: still without a bottom.
        ("G81 X10. Y10. R5. K0 F600.\nX20.\nG80\nM30\n", 3),
    ];
    for (body, line) in cases {
        let src = format!("{head}{body}");
        for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
            let src = if dialect == Dialect::Haas { src.replace(" K0", " L0") } else { src.clone() };
            let r = common::run_with(&src, "mill3", dialect);
            assert_eq!(
                r.alarms.first().map(|a| (a.code.as_str(), a.line)),
                Some(("FX0008", line)),
                "{dialect:?}\n{src}"
            );
        }
    }
    // The bottom given once is kept while the cycle lasts, in every plane.
    for ok in [
        "G81 X10. Y10. Z-10. R5. F600.\nX20.\nR3.\nG80\nM30\n",
        "G18 G81 X10. Z10. Y-5. R5. F600.\nX20.\nG80\nG17\nM30\n",
        "G19 G81 Y10. Z10. X-5. R5. F600.\nY20.\nG80\nG17\nM30\n",
        "G81 X10. Y10. Z-10. R5. K0 F600.\nX20.\nG80\nM30\n",
    ] {
        let r = common::run_with(&format!("{head}{ok}"), "mill3", Dialect::Fanuc);
        assert!(r.completed(), "{ok}: {:?}", r.alarms);
    }
}

#[test]
fn a_plane_change_while_a_cycle_is_in_force_is_refused() {
    // FANUC: the cycle is cancelled before the drilling axis changes (decision: PS0010 at the
    // plane's block). fivex drilled along Y with the Z levels (R5 → Y5, Z-10 → Y-10, the
    // initial level Z50 → Y50).
    let head = "G90 G17 G00 X0 Y10. Z50.\nG81 G98 X10. Y10. Z-10. R5. F600.\n";
    for (body, code) in [
        ("G18\nX20. Z5.\nG80\nM30\n", "G18"),
        ("G19\nG80\nM30\n", "G19"),
        ("G18 X20. Z5.\nG80\nM30\n", "G18 with a hole"),
        ("G18 G83 X20. Z5. Y-5. R5. Q2.\nG80\nM30\n", "G18 with a new cycle"),
    ] {
        let src = format!("{head}{body}");
        for (dialect, want) in [(Dialect::Fanuc, "PS0010"), (Dialect::Syntec, "COR-070"), (Dialect::Haas, "310")] {
            let r = common::run_with(&src, "mill3", dialect);
            assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((want, 3)), "{code} {dialect:?}");
        }
        // `fivex check` on a machine runs the program without motion and finds it there.
        let mut interp = interpreter(&src, "mill3", Dialect::Fanuc);
        let stop = fivex_engine::check::run_without_motion(&mut interp, true).map(|s| (s.alarm.code, s.alarm.line));
        assert_eq!(stop, Some(("PS0010".to_string(), 3)), "{code}: check");
    }
    // Cancelling first, in the block or before it, or naming the plane in force, is allowed.
    for ok in [
        "G80\nG18\nG17\nM30\n",
        "G80 G18\nG17\nM30\n",
        "G18 G80\nG17\nM30\n",
        "G00 G18 X0\nG17\nM30\n",
        "G17 X20.\nG80\nM30\n",
    ] {
        let r = common::run_with(&format!("{head}{ok}"), "mill3", Dialect::Fanuc);
        assert!(r.completed(), "{ok}: {:?}", r.alarms);
    }
}

/// The machine X/Y/Z at the end of each motion of `line` (mill3, FANUC; H1–H99 are 100 long).
fn machine_ends(src: &str, line: u32) -> Vec<[f64; 3]> {
    common::motion_ends(interpreter(src, "mill3", Dialect::Fanuc))
        .into_iter()
        .filter(|(l, _)| *l == line)
        .map(|(_, m)| [m[0], m[1], m[2]])
        .collect()
}

#[test]
fn a_tool_length_offset_in_a_cycle_block_takes_effect_at_the_move_to_r() {
    // FANUC 15i-MA operator's manual (G76, "Tool length compensation"): "the offset is applied
    // at the time of positioning to point R". The positioning over the hole keeps the old
    // length (machine Z50 with no offset), the move to R takes the new one: R5 + 100 = 105,
    // the bottom −10 + 100 = 90, the initial level 50 + 100 = 150 (G98).
    let src = "G90 G00 X0 Y0 Z50.\nG81 G43 H1 X10. Y10. Z-10. R5. F600.\nG80\nM30\n";
    assert_eq!(machine_ends(src, 1), vec![[0.0, 0.0, 50.0]]);
    let want = vec![[10.0, 10.0, 50.0], [10.0, 10.0, 105.0], [10.0, 10.0, 90.0], [10.0, 10.0, 150.0]];
    assert_eq!(machine_ends(src, 2), want);
    // G99: the tool waits at R (machine 5) after the first hole; the next block's G43 still
    // moves it to R with the new length (105) before the feed, which would otherwise start
    // 85 mm under the bottom and cut upward.
    let src = "G90 G00 X0 Y0 Z50.\nG81 G99 X10. Y10. Z-10. R5. F600.\nG43 H1 X20.\nG80\nM30\n";
    let want = vec![[20.0, 10.0, 5.0], [20.0, 10.0, 105.0], [20.0, 10.0, 90.0], [20.0, 10.0, 105.0]];
    assert_eq!(machine_ends(src, 3), want);
    // G49 in the block: positioned with the length in force (150), then R without it (5).
    let src = "G90 G00 X0 Y0 Z50.\nG43 H1 Z50.\nG81 G49 G98 X10. Y10. Z-10. R5. F600.\nG80\nM30\n";
    let want = vec![[10.0, 10.0, 150.0], [10.0, 10.0, 5.0], [10.0, 10.0, -10.0], [10.0, 10.0, 50.0]];
    assert_eq!(machine_ends(src, 3), want);
    // K0 stores the data and has no move to R: the length takes effect in its block, as in a
    // block of its own (machine Z 150), not along the next hole's positioning.
    let src = "G00 G90 X0 Y0 Z50.\nG81 G43 H1 X10. Y10. Z-10. R5. K0 F600.\nX20.\nG80\nM30\n";
    assert_eq!(machine_ends(src, 2), vec![[0.0, 0.0, 150.0]]);
    let want = vec![[20.0, 0.0, 150.0], [20.0, 0.0, 105.0], [20.0, 0.0, 90.0], [20.0, 0.0, 150.0]];
    assert_eq!(machine_ends(src, 3), want);
}

#[test]
fn a_tool_length_change_in_a_cycle_block_that_follows_the_tip_is_not_built() {
    // In the tilted plane (and under Syntec RTCP) the moves follow the tip with the new
    // length from the positioning on: refused (decision), not run with the diagonal.
    let tilted = "G90 G00 X0 Y0 Z60.\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\nG43 H1\nG00 X0 Y0 Z30.\n\
                  G81 X10. Y0 Z-5. R3. F300.\nX20. H2\nG80\nG49\nG69\nM30\n";
    for (dialect, code) in [(Dialect::Fanuc, "PS0010"), (Dialect::Syntec, "COR-100")] {
        let r = common::run_with(tilted, "head-bc", dialect);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some((code, 7)), "{dialect:?}");
        assert!(common::run_with(&tilted.replace(" H2", ""), "head-bc", dialect).completed(), "{dialect:?}");
    }
    let rtcp = "G90 G00 X0 Y0 Z60. B0 C0\nG43.4 H1\nG00 X5. Y5. Z30.\nG98 G81 X10. Y-5. Z-8. R3. F300.\n\
                X20. H2\nG80\nG49\nM30\n";
    let r = common::run_with(rtcp, "head-bc", Dialect::Syntec);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("COR-100", 5)));
}

/// The notices of a run of `src` on mill3 (FANUC) as (code, line); the run must complete.
fn notices(src: &str) -> Vec<(String, u32)> {
    let r = common::run_with(src, "mill3", Dialect::Fanuc);
    assert!(r.completed(), "{:?}\n{src}", r.alarms);
    r.notices.iter().map(|n| (n.code.clone(), n.line)).collect()
}

#[test]
fn a_cycle_whose_r_lies_beyond_its_bottom_runs_with_a_notice() {
    // R below the bottom: the tool rapids past Z to R and cuts back up toward Z. FANUC's text
    // at hand names no alarm; the run says where (FX1004), once per block.
    let head = "G90 G00 X0 Y0 Z50.\n";
    let beyond = |s: &str| notices(&format!("{head}{s}")) == vec![("FX1004".to_string(), 2)];
    for cycle in
        ["G73 Q2.", "G74", "G76 Q1.", "G81", "G82 P100", "G83 Q2.", "G84", "G85", "G86", "G88 P100", "G89 P100"]
    {
        assert!(beyond(&format!("{cycle} X10. Y10. Z-10. R-20. F600.\nG80\nM30\n")), "{cycle}");
        // R above Z: no notice.
        assert_eq!(notices(&format!("{head}{cycle} X10. Y10. Z-10. R5. F600.\nG80\nM30\n")), vec![], "{cycle}");
    }
    // Z above R, in G91 (R from the initial level, Z from R), in G18 (along Y), K2: one notice
    // for the block.
    assert!(beyond("G81 X10. Y10. Z10. R5. F600.\nG80\nM30\n"));
    assert!(beyond("G91 G81 X10. Y10. Z10. R-45. F600.\nG80\nG90\nM30\n"));
    assert!(beyond("G18 G81 X10. Z10. Y-10. R-20. F600.\nG80\nG17\nM30\n"));
    assert!(beyond("G91 G81 X10. Z10. R-45. K2 F600.\nG80\nG90\nM30\n"));
    // Every hole block of the cycle is told (the audit's e_mix: G90 R2. keeps the bottom 15).
    let mix = "G81 G99 X10. Y10. Z-10. R5. F600.\nG91 X10.\nR-20.\nG90 X40. R2.\nG80\nM30\n";
    assert_eq!(notices(&format!("{head}{mix}")), vec![("FX1004".to_string(), 5)]);
    // G87 back boring: R lies below Z by design; R above Z is told.
    assert_eq!(notices(&format!("{head}G87 X10. Y10. Z-10. R-20. Q1. F600.\nG80\nM30\n")), vec![]);
    assert_eq!(
        notices(&format!("{head}G87 X10. Y10. Z-10. R5. Q1. F600.\nG80\nM30\n")),
        vec![("FX1004".to_string(), 2)]
    );
}

#[test]
fn the_controller_sends_the_cycle_notice_too() {
    use fivex_engine::controller::{Controller, Event, RunState};
    let src = "G90 G00 X0 Y0 Z50.\nG81 X10. Y10. Z-10. R-20. F600.\nG80\nM30\n";
    let mut c =
        Controller::new(fivex_engine::interp::Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc));
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    let mut found = Vec::new();
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(0.001);
        for e in c.take_events() {
            if let Event::Notice(n) = e {
                found.push((n.code, n.line));
            }
        }
    }
    assert_eq!(found, vec![("FX1004".to_string(), 2)]);
}

#[test]
fn fanuc_refuses_a_decimal_point_at_the_dwell_s_p() {
    // P is a whole number of milliseconds; `P1.5` meant as 1.5 s would dwell 1.5 ms. FANUC:
    // PS0007 ILLEGAL USE OF DECIMAL POINT at the block. A variable or an expression is rounded
    // as at any address that takes whole numbers.
    let head = "G90 G00 X0 Y0 Z50.\n";
    for body in [
        "G04 P1.5\nM30\n",
        "G82 X10. Y10. Z-10. R5. P1.5 F600.\nG80\nM30\n",
        "G89 X10. Y10. Z-10. R5. P2. F600.\nG80\nM30\n",
    ] {
        let r = common::run_with(&format!("{head}{body}"), "mill3", Dialect::Fanuc);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("PS0007", 2)), "{body}");
    }
    let seconds = |src: &str| -> Vec<f64> {
        canon(src)
            .iter()
            .filter_map(|c| match c.kind {
                CanonKind::Dwell { seconds } => Some(seconds),
                _ => None,
            })
            .collect()
    };
    assert_eq!(seconds(&format!("{head}G04 P1500\n#1=1499.6\nG04 P#1\nG04 P[1.5*1000]\nM30\n")), vec![1.5, 1.5, 1.5]);
    assert_eq!(seconds(&format!("{head}G82 X10. Y10. Z-10. R5. P1500 F600.\nG80\nM30\n")), vec![1.5]);
    // `fivex check` finds it in a block that names G04 or the cycle; a later hole block is
    // left to the run.
    use fivex_engine::check::check;
    use fivex_engine::lang::parse_file;
    let src = "G04 P1.5\nG82 X10. Y10. Z-10. R5. P2. F600.\nX20. P1.5\nG80\nG04 P#1\nM30\n";
    let found: Vec<_> = check(parse_file(src), Dialect::Fanuc).iter().map(|d| (d.line, d.col, d.id.clone())).collect();
    let id = fivex_engine::AlarmId::IllegalDecimalPoint;
    assert_eq!(found, vec![(1, 5, id.clone()), (2, 25, id)]);
    assert!(check(parse_file(src), Dialect::Haas).is_empty());
    // Haas reads P with a point as seconds (its own rule); Syntec keeps milliseconds (no
    // source at hand says otherwise).
    let haas = common::run_with("G04 P1.5\nM30\n", "mill3", Dialect::Haas);
    assert!(haas.completed(), "{:?}", haas.alarms);
    let syntec = common::run_with("G04 P1.5\nM30\n", "mill3", Dialect::Syntec);
    assert!(syntec.completed(), "{:?}", syntec.alarms);
}
