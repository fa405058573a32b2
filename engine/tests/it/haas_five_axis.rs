//! Haas 5-axis (`docs/dialects.md`, "Haas 5-axis"): G234 TCPC and G254/G255 DWO on the Haas
//! machines of the library (`machines/haas-*.json`, read as Haas settings lists), the rules of
//! the manual as alarms, and the Haas list's round trip.
//!
//! Π, G234's programming frame, is the work coordinate system fixed to the table as it is at
//! the rotary zero: the point `p` is at machine `p + G54` with the rotaries at 0. G254's frame
//! has Π's origin, carried by the table, and the machine's axes (`carried`).

use crate::common;

use common::{cases, check_limits_of, check_strokes, end_of, interpreter_with, motion_ends};
use fivex_engine::geom::Rigid;
use fivex_engine::interp::gcode::{code, group};
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::{AxisKind, MachineConfig, MAX_AXES};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::vendor::{self, ParamFile};
use fivex_engine::Dialect;
use proptest::prelude::*;

/// Tool length of every offset in `common::interpreter_with`.
const LENGTH: f64 = 100.0;

/// A Haas machine of the library, as its settings list describes it.
fn haas(name: &str) -> MachineConfig {
    let path = format!("{}/../machines/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let f: ParamFile = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(f.dialect, Dialect::Haas);
    vendor::machine_from(f.dialect, &f.name, &f.parameters)
        .unwrap_or_else(|e| panic!("{name}: {}", e.describe(f.dialect)))
}

/// The Haas machines with rotary axes.
const ROTARY: [&str; 3] = ["haas-umc-750", "haas-vf2-tr160", "haas-vf2-hrt160"];

fn run_on(m: &MachineConfig, src: &str) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions { max_time_s: 120.0, ..RunOptions::default() }, |s| samples.push(*s));
    (r, samples)
}

/// The first alarm's code and line.
fn alarm_on(m: &MachineConfig, src: &str) -> (String, u32) {
    let (r, _) = run_on(m, src);
    assert!(!r.completed(), "expected an alarm from\n{src}");
    (r.alarms[0].code.clone(), r.alarms[0].line)
}

/// Π in the table frame for work offset `g54` (X, Y, Z; rotary offsets 0).
fn pi(kin: &Kinematics, m: &MachineConfig, g54: [f64; 3]) -> Rigid {
    let zero = [0.0; MAX_AXES];
    let table = kin.table_frame(&zero[..m.axes.len()]);
    let r = table.r.transpose();
    Rigid { r, o: r * (Vec3::from(g54) + kin.nose - table.o) }
}

/// The MRZP (Settings 255–257) of a Haas machine: where its table axes' lines meet.
fn mrzp(m: &MachineConfig) -> [f64; 3] {
    m.rotary[0].point
}

fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Rotary words for fractions of each rotary axis's range (a rollover axis: −180…180).
fn rotary_words(m: &MachineConfig, fractions: &[f64]) -> String {
    let mut s = String::new();
    for (k, a) in m.axes.iter().filter(|a| a.kind == AxisKind::Rotary).enumerate() {
        let [lo, hi] = a.stroke.map_or([-180.0, 180.0], |[lo, hi]| [lo + 2.0, hi - 2.0]);
        s += &format!(" {}{:.3}", a.name, mm(lo + (hi - lo) * fractions[k]));
    }
    s
}

fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let u = ((p - a).dot(&d) / d.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (p - (a + d * u)).norm()
}

fn g10(g54: [f64; 3]) -> String {
    format!("G10 L2 P1 X{:.3} Y{:.3} Z{:.3}\n", g54[0], g54[1], g54[2])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(12), ..ProptestConfig::default() })]

    /// G234 on every Haas rotary machine, the part anywhere near the MRZP: lines while the
    /// rotary axes turn to random angles; the tip (length H) stays within 1 µm of the
    /// programmed line in the table-fixed work coordinates at every 1 ms sample, inside the
    /// strokes and every axis within its speed, acceleration and jerk.
    #[test]
    fn g234_tip_on_the_path(
        which in 0..3usize,
        shift in prop::array::uniform3(-30.0..30.0f64),
        blocks in prop::collection::vec((prop::array::uniform3(-40.0..40.0f64), prop::collection::vec(0.0..1.0f64, 2)), 1..5),
        feed in 1000.0..6000.0f64,
    ) {
        let m = haas(ROTARY[which]);
        let kin = Kinematics::new(&m).unwrap();
        let c = mrzp(&m);
        let g54 = [mm(c[0] + shift[0]), mm(c[1] + shift[1]), mm(c[2] + shift[2].abs())];
        let pi = pi(&kin, &m, g54);
        let zero: String = m.axes.iter().filter(|a| a.kind == AxisKind::Rotary).map(|a| format!(" {}0", a.name)).collect();
        let mut src = format!("{}G90 G54 G17 G00{zero}\nG234 H1\nX0 Y0 Z50.\nG01 F{:.3}\n", g10(g54), mm(feed));
        let mut at = Vec3::new(0.0, 0.0, 50.0);
        let mut paths = Vec::new();
        for (k, (p, fractions)) in blocks.iter().enumerate() {
            let end = Vec3::from(p.map(mm));
            src += &format!("X{:.3} Y{:.3} Z{:.3}{}\n", end.x, end.y, end.z, rotary_words(&m, fractions));
            paths.push((6 + k as u32, at, end));
            at = end;
        }
        // M30 ends TCPC where the machine stands (a G49 block would move the nose to the tip
        // point, below the travels with the part turned over).
        src += "M30\n";
        let (r, samples) = run_on(&m, &src);
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        let mut worst = 0.0f64;
        for s in &samples {
            if let Some((_, a, b)) = paths.iter().find(|(line, _, _)| *line == s.line) {
                let tip = pi.from_parent(&kin.forward(&s.machine, LENGTH).tip);
                worst = worst.max(distance_to_segment(tip, *a, *b));
            }
        }
        prop_assert!(worst < 1e-3, "the tip is {worst} mm off the path\n{src}");
        check_strokes(&samples, &m)?;
        check_limits_of(&samples, &m, false).map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
    }
}

/// G254 on the trunnions at several rotary positions: after it the tip reaches the programmed
/// points — from the work origin carried by the table, along the machine's axes — at the end of
/// every move, rapid or cut (expected positions by hand, `carried`).
#[test]
fn g254_reaches_the_workpiece_points() {
    for name in ["haas-umc-750", "haas-vf2-tr160"] {
        let m = haas(name);
        let c = mrzp(&m);
        let g54 = [mm(c[0] + 12.5), mm(c[1] - 20.0), mm(c[2] + 35.0)];
        let (tilt, platter) = (m.rotary[0].axis, m.rotary[1].axis);
        // The UMC's B about Y, the TR160's A about X.
        let about = if tilt == 'B' { 'Y' } else { 'X' };
        for (t, p) in [(0.0, 0.0), (90.0, 0.0), (-30.0, 45.0), (60.0, -120.0), (100.0, 200.0)] {
            if m.rotary[0].range.is_some_and(|[lo, hi]| t < lo || t > hi) {
                continue;
            }
            let src = format!(
                "{}G90 G54 G00 {tilt}{t:.1} {platter}{p:.1}\nG43 H1\nG254\nG00 X10. Y-5.\nZ30.\nG01 Z5. F500.\nX-15. Y12.\nG02 X-5. Y22. R10.\nG255\nM30\n",
                g10(g54)
            );
            let interp = interpreter_with(&src, "mill3", Dialect::Haas, |cfg| cfg.machine = m.clone().into());
            let ends = motion_ends(interp);
            let wants: [(u32, f64, f64, Option<f64>); 5] = [
                (5, 10.0, -5.0, None),
                (6, 10.0, -5.0, Some(30.0)),
                (7, 10.0, -5.0, Some(5.0)),
                (8, -15.0, 12.0, Some(5.0)),
                (9, -5.0, 22.0, Some(5.0)),
            ];
            let o = carried(c, about, t, p, g54);
            for (line, x, y, z) in wants {
                let end = end_of(&ends, line);
                let tip = [end[0] - o[0], end[1] - o[1], end[2] - LENGTH - o[2]];
                assert!((tip[0] - x).abs() < 1e-6, "{name} {tilt}{t} {platter}{p} line {line}: {tip:?}");
                assert!((tip[1] - y).abs() < 1e-6, "{name} {tilt}{t} {platter}{p} line {line}: {tip:?}");
                if let Some(z) = z {
                    assert!((tip[2] - z).abs() < 1e-6, "{name} {tilt}{t} {platter}{p} line {line}: {tip:?}");
                }
                // The rotary axes stay where they were put.
                for l in &m.rotary {
                    let i = m.axes.iter().position(|a| a.name == l.axis).unwrap();
                    let angle = if l.axis == tilt { t } else { p };
                    let d = (end[i] - angle).rem_euclid(360.0);
                    assert!(d.min(360.0 - d) < 1e-9, "{name}: {} moved to {}", l.axis, end[i]);
                }
            }
        }
    }
}

fn umc() -> MachineConfig {
    haas("haas-umc-750")
}

#[test]
fn g254_alarms_of_the_manual_s_rules() {
    let m = umc();
    let head = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\n";
    // Rotary motion under G254, and in its block.
    assert_eq!(alarm_on(&m, &format!("{head}G254\nG00 X0 Y0\nZ50.\nC90.\nM30\n")), ("742".into(), 7));
    assert_eq!(alarm_on(&m, &format!("{head}G254 C90.\nM30\n")), ("742".into(), 4));
    // A cut before X, Y and Z were all given after G254 (a rapid may give them one by one).
    assert_eq!(alarm_on(&m, &format!("{head}G254\nG00 X0 Y0\nG01 X10. F500.\nM30\n")), ("743".into(), 6));
    assert_eq!(alarm_on(&m, &format!("{head}G254\nG01 X0 Y0 F500.\nM30\n")), ("743".into(), 5));
    // The work offset's B value must be zero.
    let tilted = "G10 L2 P1 X-381. Y-254. Z-400. B5.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\n";
    assert_eq!(alarm_on(&m, &format!("{tilted}G254\nM30\n")), ("744".into(), 4));
    // Not with G234.
    assert_eq!(alarm_on(&m, &format!("{head}G254\nG234 H1\nM30\n")), ("745".into(), 5));
    assert_eq!(alarm_on(&m, "G90 G54 G00 B0 C0\nG234 H1\nG254\nM30\n"), ("745".into(), 3));
    // G234 needs a tool length (H).
    assert_eq!(alarm_on(&m, "G90 G54 G00 B0 C0\nG234\nM30\n"), ("741".into(), 2));
    // A refused block changes nothing: the machine has not moved at the alarm.
    let (r, _) = run_on(&m, &format!("{head}G254 C90.\nM30\n"));
    let c = m.axes.iter().position(|a| a.name == 'C').unwrap();
    assert!((r.machine[c] - 45.0).abs() < 1e-9);
}

/// The reference returns in the Haas 5-axis modes. Under G254 the manual says G28/G29 do not
/// apply DWO's rotation and strongly recommends against them; fivex cannot tell from which
/// point an incremental intermediate point or G29's end is then taken, so it refuses them (730,
/// decision; before, `G91 G28 Z0` moved Y by 41 mm on its way up). G234 refuses them as FANUC's
/// TCP does (731). After G255 / G49 they run within the axes' limits.
#[test]
fn reference_returns_in_dwo_and_tcpc() {
    let m = umc();
    let dwo = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\nG254\nG00 X0 Y0\nZ50.\n";
    let tcpc = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\nG234 H1\nG00 X0 Y0\nZ50.\n";
    for block in ["G91 G28 Z0", "G28 X0 Y0 Z50.", "G29 X0 Y0 Z50."] {
        assert_eq!(alarm_on(&m, &format!("{dwo}{block}\nG255\nM30\n")), ("730".into(), 7), "G254 {block}");
        assert_eq!(alarm_on(&m, &format!("{tcpc}{block}\nG49\nM30\n")), ("731".into(), 7), "G234 {block}");
    }
    for src in [format!("{dwo}G255\nG91 G28 Z0\nM30\n"), format!("{tcpc}G49\nG91 G28 Z0\nM30\n")] {
        let (r, samples) = run_on(&m, &src);
        assert!(r.completed(), "{src}: {:?}", r.alarms);
        // The speed bound holds across block ends too: no block starts where the machine is not.
        if let Err(e) = check_limits_of(&samples, &m, false) {
            panic!("{src}: {e}");
        }
    }
}

/// What cancels G254 and G234: G255, M30 and reset do; M00/M01 do not (the manual's lists).
#[test]
fn what_cancels_dwo_and_tcpc() {
    let m = umc();
    let head = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\nG254\nG00 X0 Y0\nZ50.\n";
    // M00 and M01 leave G254 on: the next block is still in the turned workpiece system (the cut
    // after them needs no X/Y/Z again).
    let (r, _) = run_on(&m, &format!("{head}M00\nM01\nG01 Z40. F500.\nM30\n"));
    assert!(r.completed(), "{:?}", r.alarms);
    // After G255 rotary motion is allowed again.
    let (r, _) = run_on(&m, &format!("{head}G255\nG00 B0 C0\nM30\n"));
    assert!(r.completed(), "{:?}", r.alarms);
    // M30 ends both: the modes are G255 and G49 at the end.
    for tail in ["M30\n", "M02\n"] {
        let src = format!("{head}{tail}");
        let mut interp = interpreter_with(&src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        assert!(r.completed(), "{:?}", r.alarms);
        assert_eq!(interp.state.modal(group::DYNAMIC_FIXTURE), code::G255, "{tail}");
    }
    let src = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B0 C0\nG234 H1\nG00 X0 Y0 Z50.\nM30\n";
    let mut interp = interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(interp.state.modal(group::LENGTH_COMP), code::G49);
    // Reset ends G254 too.
    let src = format!("{head}G01 Z45. F500.\n");
    let mut interp = interpreter_with(&src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
    let _ = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert_eq!(interp.state.modal(group::DYNAMIC_FIXTURE), code::G254);
    interp.reset();
    assert_eq!(interp.state.modal(group::DYNAMIC_FIXTURE), code::G255);
}

/// G53 moves in machine terms under G254 (the manual: it ignores it); the current point follows,
/// so the next block needs no new rule.
#[test]
fn g53_under_dwo_moves_in_machine_coordinates() {
    let m = umc();
    let src = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C45.\nG43 H1 Z100.\nG254\nG00 X0 Y0\nZ50.\nG53 Z0\nG255\nM30\n";
    let interp = interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
    let ends = motion_ends(interp);
    let z = m.axes.iter().position(|a| a.name == 'Z').unwrap();
    assert!(end_of(&ends, 7)[z].abs() < 1e-9);
}

/// G234 and G254 are the NGC's: the FANUC and Syntec dialects do not have them.
#[test]
fn g234_and_g254_are_haas_codes() {
    let m = umc();
    for d in [Dialect::Fanuc, Dialect::Syntec] {
        for src in ["G234 H1\nM30\n", "G254\nM30\n", "G255\nM30\n"] {
            let mut interp = interpreter_with(src, "mill3", d, |c| c.machine = m.clone().into());
            let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
            assert!(!r.completed(), "{d:?} {src}");
            assert!(["PS0010", "COR-070"].contains(&r.alarms[0].code.as_str()), "{d:?}: {:?}", r.alarms);
        }
    }
}

/// The G234 block does not move by itself, even with the table tilted: the current point
/// becomes the tip where it stands.
#[test]
fn g234_block_does_not_move() {
    let m = umc();
    let src = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B40. C30. Z150.\nG234 H1\nG01 X0 Y0 Z60. F1000.\nG49\nM30\n";
    let interp = interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into());
    let ends = motion_ends(interp);
    let before = end_of(&ends, 2);
    if let Some((_, at)) = ends.iter().find(|(l, _)| *l == 3) {
        for (a, b) in at.iter().zip(before.iter()) {
            assert!((a - b).abs() < 1e-9, "the G234 block moved: {at:?} from {before:?}");
        }
    }
    // And the next block puts the tip on X0 Y0 Z60 of the table-fixed work coordinates.
    let kin = Kinematics::new(&m).unwrap();
    let pi = pi(&kin, &m, [-381.0, -254.0, -400.0]);
    let tip = pi.from_parent(&kin.forward(&end_of(&ends, 4), LENGTH).tip);
    assert!((tip - Vec3::new(0.0, 0.0, 60.0)).norm() < 1e-6, "{tip:?}");
}

/// The Haas settings list: model → list → model is the identity on the library's machines, and
/// a list whose settings describe no Haas unit is refused.
#[test]
fn haas_list_round_trips() {
    for name in ["haas-umc-750", "haas-vf2-tr160", "haas-vf2-hrt160"] {
        let m = haas(name);
        let p = vendor::params_of(Dialect::Haas, &m).unwrap();
        assert_eq!(vendor::machine_from(Dialect::Haas, name, &p).unwrap(), m, "{name}");
        // MRZP as the settings give it.
        assert_eq!(m.rotary[0].point, [p.get(255).unwrap(), p.get(256).unwrap(), p.get(257).unwrap()]);
        assert!(vendor::unmodelled::of_params(Dialect::Haas, &p).is_empty(), "{name}");
    }
    // A head-head machine is not a Haas unit.
    let head = MachineConfig::preset("head-bc").unwrap();
    assert!(vendor::params_of(Dialect::Haas, &head).is_err());
    // A unit code out of range, a missing travel.
    let mut p = vendor::params_of(Dialect::Haas, &umc()).unwrap();
    p.set(9000, 7.0);
    assert!(vendor::machine_from(Dialect::Haas, "x", &p).is_err());
    let mut p = vendor::params_of(Dialect::Haas, &umc()).unwrap();
    p.0.remove(&9001);
    assert!(vendor::machine_from(Dialect::Haas, "x", &p).is_err());
    // MRZP on a 3-axis list changes nothing: reported as not modelled.
    let mut p = vendor::params_of(Dialect::Haas, &umc()).unwrap();
    p.set(9000, 0.0);
    let report = vendor::unmodelled::of_params(Dialect::Haas, &p);
    assert!(report.iter().any(|u| u.parameter == "Setting 255"), "{report:?}");
    // A rotary unit without its MRZP settings loads with the centre at machine zero: said.
    let mut p = vendor::params_of(Dialect::Haas, &umc()).unwrap();
    p.0.remove(&255);
    p.0.remove(&257);
    let report: Vec<String> =
        vendor::unmodelled::of_params(Dialect::Haas, &p).into_iter().map(|u| u.parameter).collect();
    assert_eq!(report, ["Setting 255", "Setting 257"]);
}

/// G234 runs on a head machine too (head-bc: the tip machinery is the same); G254 is refused
/// there at its block (730, decision: the pages describe DWO on table units, and whether the
/// NGC's X/Y/Z would turn with a tilted head is not said; `docs/dialects.md`).
#[test]
fn haas_codes_on_a_head_machine() {
    let body = "G234 H1\nG01 X10. Y5. Z20. B20. C30. F1000.\nG49\nM30\n";
    let r = common::run_with(body, "head-bc", Dialect::Haas);
    assert!(r.completed(), "{body}: {:?}", r.alarms);
    let r = common::run_with("G00 B20. C30.\nG254\nG00 X1. Y1.\nZ1.\nG255\nM30\n", "head-bc", Dialect::Haas);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("730", 2), "{:?}", r.alarms);
}

/// The G234 page's conceptual example, in inches: the edge from X0 Y0 Z0 to X0 Y-1. Z0 of the
/// part (G54) is cut with the table turned (the page's B and C values are not in the text read:
/// B30 C45 here); under TCPC the tip runs along the part's Y only, 25.4 mm, while the machine's
/// X, Y and Z all move.
#[test]
fn g234_manual_example_edge_in_inches() {
    let m = umc();
    let kin = Kinematics::new(&m).unwrap();
    let g54 = [-381.0, -254.0, -432.0];
    let src = "G20\nG10 L2 P1 X-15. Y-10. Z-17.007874\nG90 G54 G00 B0 C0\nG234 H1\nG00 X0 Y0 Z1. B30. C45.\nG01 Z0 F10.\nY-1.\nG00 Z1.\nG49\nM30\n";
    let (r, samples) = run_on(&m, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let pi = pi(&kin, &m, g54);
    let on = |s: &Sample| pi.from_parent(&kin.forward(&s.machine, LENGTH).tip);
    let edge: Vec<&Sample> = samples.iter().filter(|s| s.line == 7).collect();
    assert!(edge.len() > 10);
    let mut moved = [0.0f64; 3];
    for s in &edge {
        let tip = on(s);
        assert!(tip.x.abs() < 1e-6 && tip.z.abs() < 1e-6 && tip.y <= 1e-6 && tip.y >= -25.4 - 1e-6, "{tip:?}");
        for (k, d) in moved.iter_mut().enumerate() {
            *d = d.max((s.machine[k] - edge[0].machine[k]).abs());
        }
    }
    // The edge ends at Y-1. (the last sample of line 7 may fall within the last millisecond
    // before it: the first of line 8, which moves Z only, shows where it ended).
    let next = samples.iter().find(|s| s.line == 8).expect("line 8 runs");
    let end = on(next);
    assert!((end.y + 25.4).abs() < 1e-6 && end.x.abs() < 1e-6, "{end:?}");
    // The machine moves in X, Y and Z to draw a line along the part's Y.
    assert!(moved.iter().all(|d| *d > 1.0), "{moved:?}");
}

/// `v` turned by `deg` about the machine axis `axis` ('X', 'Y' or 'Z'), right-hand; written out
/// here so that the expected positions do not come from fivex's kinematics.
fn turned(axis: char, deg: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = deg.to_radians().sin_cos();
    let [x, y, z] = v;
    match axis {
        'X' => [x, y * c - z * s, y * s + z * c],
        'Y' => [x * c + z * s, y, -x * s + z * c],
        _ => [x * c - y * s, x * s + y * c, z],
    }
}

/// Where the table carries the point `q` (machine coordinates at the rotary zero) when the tilt
/// axis (line `tilt` through the MRZP `p`) stands at `t` and the platter (about Z) at `c`: table
/// axes turn left-hand, the platter rides on the tilt.
fn carried(p: [f64; 3], tilt: char, t: f64, c: f64, q: [f64; 3]) -> [f64; 3] {
    let r = turned(tilt, -t, turned('Z', -c, [q[0] - p[0], q[1] - p[1], q[2] - p[2]]));
    [p[0] + r[0], p[1] + r[1], p[2] + r[2]]
}

/// G254 on a UMC as Autodesk's Haas NGC post writes a 3+2 drilling (`docs/dialects.md`, "Haas
/// 5-axis"): the hole whose bottom is the part's (20, 10, −5), G54 (−400, −230, −450), the table
/// at B30 C45. By hand (`carried`, B about Y through the MRZP (−381, −254, −432)): the work
/// origin goes to (−368.9381, −223.5944, −445.8207) and the hole's bottom to (−348.0670,
/// −230.6655, −439.5442), so the program gives the bottom as (20.8712, −7.0711, 6.2765) from the
/// origin along machine X, Y, Z. The X/Y block moves machine X/Y only, the plunge machine Z only
/// (along the spindle), and the nose ends 100 (the tool length) above the bottom.
#[test]
fn g254_axes_are_the_machine_s_and_the_origin_turns_with_the_table() {
    let m = umc();
    let src = "G10 L2 P1 X-400. Y-230. Z-450.\nG90 G54 G17 G00 B0 C0\nG43 H1 Z150.\nB30. C45.\nG254\nX20.8712 Y-7.0711\nZ56.2765\nG01 Z6.2765 F300.\nG00 Z56.2765\nG255\nM30\n";
    let (r, samples) = run_on(&m, src);
    assert!(r.completed(), "{:?}", r.alarms);
    // Independent of the numbers above: the hole's bottom carried by hand.
    let bottom = carried([-381.0, -254.0, -432.0], 'Y', 30.0, 45.0, [-380.0, -220.0, -455.0]);
    let want = [bottom[0], bottom[1], bottom[2] + LENGTH];
    assert!((want[0] + 348.0670).abs() < 1e-4 && (want[2] - 100.0 + 439.5442).abs() < 1e-4, "{want:?}");
    let ends = motion_ends(interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into()));
    let end = end_of(&ends, 8);
    for k in 0..3 {
        assert!((end[k] - want[k]).abs() < 1e-3, "plunge ends at {end:?}, want {want:?}");
    }
    let moved = |line: u32, k: usize| {
        let on: Vec<f64> = samples.iter().filter(|s| s.line == line).map(|s| s.machine[k]).collect();
        assert!(on.len() > 3, "line {line} runs");
        on.iter().fold(0.0f64, |d, v| d.max((v - on[0]).abs()))
    };
    // The X/Y block: machine Z stays; the plunge and the retract: machine X and Y stay.
    assert!(moved(6, 2) < 1e-9 && moved(6, 0) > 1.0, "the X/Y block moved Z");
    for line in [8, 9] {
        assert!(moved(line, 0) < 1e-9 && moved(line, 1) < 1e-9 && moved(line, 2) > 10.0, "line {line}");
    }
}

/// A canned drilling cycle under G254 feeds along the spindle (machine Z) on every Haas rotary
/// unit tilted (the auditor's G81 at A90 on the HRT160 fed along machine Y, across the drill):
/// G54 the MRZP + (5, −8, 40); the hole at X10 Y5 from the carried origin, its bottom Z40,
/// R50; by hand the bottom of the nose is the carried origin + (10, 5, 40 + 100).
#[test]
fn g254_drills_along_the_spindle() {
    for (name, rotary, tilt, t, c) in [
        ("haas-umc-750", "B30. C45.", 'Y', 30.0, 45.0),
        ("haas-vf2-tr160", "A-30. B45.", 'X', -30.0, 45.0),
        ("haas-vf2-hrt160", "A90.", 'X', 90.0, 0.0),
    ] {
        let m = haas(name);
        let p = mrzp(&m);
        let g54 = [p[0] + 5.0, p[1] - 8.0, p[2] + 40.0];
        let src = format!(
            "{}G90 G54 G17 G00 G43 H1 Z200.\nG00 {rotary}\nG254\nG00 X10. Y5.\nZ60.\nG98 G81 Z40. R50. F300.\nG80\nG255\nM30\n",
            g10(g54)
        );
        let (r, samples) = run_on(&m, &src);
        assert!(r.completed(), "{name}: {:?}", r.alarms);
        let o = carried(p, tilt, t, c, g54);
        let hole = [o[0] + 10.0, o[1] + 5.0];
        let cycle: Vec<&Sample> = samples.iter().filter(|s| s.line == 7).collect();
        assert!(cycle.len() > 10, "{name}: the cycle runs");
        for s in &cycle {
            assert!(
                (s.machine[0] - hole[0]).abs() < 1e-6 && (s.machine[1] - hole[1]).abs() < 1e-6,
                "{name}: the drill left the hole's line: {:?}, hole {hole:?}",
                s.machine
            );
        }
        let deepest = cycle.iter().map(|s| s.machine[2]).fold(f64::INFINITY, f64::min);
        assert!((deepest - (o[2] + 40.0 + LENGTH)).abs() < 1e-3, "{name}: bottom {deepest}, origin {o:?}");
        // The X/Y block moved machine X/Y only.
        let xy: Vec<&Sample> = samples.iter().filter(|s| s.line == 5).collect();
        assert!(xy.iter().all(|s| (s.machine[2] - xy[0].machine[2]).abs() < 1e-9), "{name}: the X/Y block moved Z");
    }
}

/// G254 on a machine without rotary axes is refused at its block (`IllegalCommandInMode`, 730;
/// decision, `docs/dialects.md`): a 3-axis preset has kinematics too, and G254 ran there
/// silently before.
#[test]
fn g254_is_refused_without_rotary_axes() {
    let r = common::run_with("G00 G43 H1 Z50.\nG254\nG00 X0 Y0\nM30\n", "mill3", Dialect::Haas);
    assert!(!r.completed(), "G254 ran on a 3-axis machine");
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("730", 2), "{:?}", r.alarms);
}

/// The UMC-750's B tilts about Y, −35…120 (Autodesk's Haas NGC post, `docs/dialects.md`,
/// "Haas 5-axis"). By hand: G54 (−381, −254, −400), MRZP (−381, −254, −432); at B30 C0 the
/// part's origin, 32 above the MRZP, turns with the table by −30° about Y (left-hand) to
/// MRZP + (32·sin −30°, 0, 32·cos 30°) = (−397, −254, −404.2872), and the nose stands 100 above
/// it; the tool leans toward the part's +X, (sin 30°, 0, cos 30°). B118 is inside the range.
#[test]
fn umc_b_tilts_about_y() {
    let m = umc();
    let src = "G10 L2 P1 X-381. Y-254. Z-400.\nG90 G54 G00 B30. C0 Z150.\nG234 H1\nG01 X0 Y0 Z0 F1000.\nM30\n";
    let (r, samples) = run_on(&m, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let want = [-397.0, -254.0, -404.287_187_078_897_9 + LENGTH];
    for (k, w) in want.iter().enumerate() {
        assert!((r.machine[k] - w).abs() < 1e-6, "machine {:?}, want {want:?}", r.machine);
    }
    let tool = samples.last().unwrap().tool;
    assert!((tool[0] - 0.5).abs() < 1e-9 && tool[1].abs() < 1e-9, "tool {tool:?}");
    let (r, _) = run_on(&m, "G90 G54 G00 B118. C0\nB-34.\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
}

/// Haas: a G49 block without axis words moves nothing, whether it ends G234 or G43; the length
/// is gone from the next move on (`docs/dialects.md`, "Haas 5-axis": Autodesk's Haas NGC post
/// writes `G49 (TCPC OFF)` at the last cutting point and then `G53 G0 Z…`; a G49 that dropped
/// the spindle by the tool length would crash every such program). By hand: after G49 with G54
/// Z −450 the nose goes to work Z200 at machine Z −250; with G54 Z −400 and G43 H1 (100) at Z50
/// the nose stands at −250, stays there through G49 and X10., and Z50. then puts it at −350.
/// FANUC with TOS = 1 (its default, `docs/five-axis.md`, "TOS") the same; with TOS = 0 the
/// G49 block moves by the length (−350 at once).
#[test]
fn g49_without_axis_words_moves_nothing() {
    let m = umc();
    let src = "G10 L2 P1 X-400. Y-230. Z-450.\nG90 G54 G00 B20. C30. Z100.\nG234 H1\nG01 X10. Y5. Z60. F1000.\nG49\nG00 Z200.\nG53 Z0\nM30\n";
    let (r, _) = run_on(&m, src);
    assert!(r.completed(), "{:?}", r.alarms);
    let ends = motion_ends(interpreter_with(src, "mill3", Dialect::Haas, |c| c.machine = m.clone().into()));
    assert!(ends.iter().all(|(l, _)| *l != 5), "the G49 block moved: {ends:?}");
    let (cut, up) = (end_of(&ends, 4), end_of(&ends, 6));
    assert!((up[0] - cut[0]).abs() < 1e-9 && (up[1] - cut[1]).abs() < 1e-9, "{cut:?} → {up:?}");
    assert!((up[2] + 250.0).abs() < 1e-9, "after G49 the nose goes to work Z200: {up:?}");

    let src = "G10 L2 P1 X-400. Y-230. Z-400.\nG90 G54 G00 G43 H1 Z50.\nG49\nX10.\nZ50.\nM30\n";
    for (dialect, at_g49) in [(Dialect::Haas, None), (Dialect::Fanuc, None), (Dialect::Fanuc, Some(-350.0))] {
        let ends = motion_ends(interpreter_with(src, "mill3", dialect, |c| {
            let mut m = MachineConfig::preset("mill3").unwrap();
            m.five_axis.length_offset_by_motion = at_g49.is_some();
            c.machine = m.into();
        }));
        let z = |line| end_of(&ends, line)[2];
        assert!((z(2) + 250.0).abs() < 1e-9, "{dialect:?}: {ends:?}");
        match at_g49 {
            None => {
                assert!(ends.iter().all(|(l, _)| *l != 3), "{dialect:?}: the G49 block moved: {ends:?}");
                assert!((z(4) + 250.0).abs() < 1e-9 && (end_of(&ends, 4)[0] + 390.0).abs() < 1e-9, "{ends:?}");
            }
            Some(want) => assert!((z(3) - want).abs() < 1e-9, "{dialect:?}: {ends:?}"),
        }
        assert!((z(5) + 350.0).abs() < 1e-9, "{dialect:?}: {ends:?}");
    }
}
