//! Workpiece setting error compensation, FANUC G54.4 (spec `fanuc-twp-wsec-manual-params.md`
//! WSE-01…WSE-26, §2.13, TV-WSE-01…TV-WSE-28): error data and macro variables, the effective
//! error with the table-position conversion, the start block's recomputation, the program in the
//! displaced system (Example 1), circles in space, reset, machine-coordinate moves and the mode
//! alarms. Decisions: `docs/five-axis.md`, "Workpiece setting error compensation (G54.4)".

#![allow(clippy::approx_constant)]

use crate::common;

use common::{end_of, interpreter_with, motion_ends};
use fivex_engine::canon::{CanonKind, FeedMode, MotionKind, Pos};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::{MachineConfig, PlaneAfterReset};
use fivex_engine::run::{run, RunOptions};
use fivex_engine::wse;
use fivex_engine::Dialect;

fn fanuc(src: &str, preset: &str) -> Interpreter {
    interpreter_with(src, preset, Dialect::Fanuc, |_| {})
}

fn fanuc_with(src: &str, preset: &str, tweak: impl FnOnce(&mut Config)) -> Interpreter {
    interpreter_with(src, preset, Dialect::Fanuc, tweak)
}

/// Run to the end (no alarm expected) and hand back the interpreter.
fn ran(mut interp: Interpreter) -> Interpreter {
    interp.run(|_| {}).expect("no alarm");
    interp
}

/// The alarm code a program ends in.
fn alarm_of(mut interp: Interpreter) -> String {
    interp.run(|_| {}).expect_err("an alarm").code
}

fn close3(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < tol)
}

fn xyz(p: &Pos) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// TV-WSE-01/02: COMMON X 10; No.01 x 0.5 a 1.5; No.02 x 0.8 a 1.8, set by macro variables.
const DATA_01: &str = "#26000=10.\n#26010=0.5\n#26013=1.5\n#26020=0.8\n#26023=1.8\n";

#[test]
fn tv_wse_01_02_effective_error_adds_common_translations_and_takes_the_sets_rotation() {
    for (n, dx, da) in [(1, 10.5, 1.5), (2, 10.8, 1.8)] {
        let interp = ran(fanuc(&format!("{DATA_01}G54.4 P{n}\nM30\n"), "mill3"));
        let (set, e) = interp.state.active_setting_error().expect("G54.4 on");
        assert_eq!(set, n as u8);
        assert!(close3(e.o.into(), [dx, 0.0, 0.0], 1e-12), "P{n}: Δ {:?}", e.o);
        assert!(close3(wse::angles(&e.r), [da, 0.0, 0.0], 1e-9), "P{n}: angles {:?}", wse::angles(&e.r));
    }
}

#[test]
fn tv_wse_03_sets_measured_with_the_table_turned_are_converted_to_table_position_0() {
    // mixed-bc: C on the table (left hand, FANUC No.19689 = 1); G54 X/Y 0 puts the WCS origin
    // on the C axis. No.00: Y 10 at C −90; No.01: x 5, c 2 at C 90.
    let src = "#26001=10.\n#26006=-90.\n#26010=5.\n#26015=2.\n#26016=90.\nG54.4 P1\nM30\n";
    let interp = ran(fanuc(src, "mixed-bc"));
    let (_, e) = interp.state.active_setting_error().unwrap();
    assert!(close3(e.o.into(), [10.0, 5.0, 0.0], 1e-9), "Δ {:?}", e.o);
    assert!(close3(wse::angles(&e.r), [0.0, 0.0, 2.0], 1e-9), "{:?}", wse::angles(&e.r));
    // Each set on its own, as the seed's intermediate values.
    let st = &interp.state;
    let mut common_only = st.clone();
    common_only.setting_errors.sets[1] = Default::default();
    assert!(close3(common_only.effective_setting_error(1).o.into(), [10.0, 0.0, 0.0], 1e-9));
    // Without a table nothing is converted.
    let interp = ran(fanuc(src, "head-bc"));
    let (_, e) = interp.state.active_setting_error().unwrap();
    assert!(close3(e.o.into(), [5.0, 10.0, 0.0], 1e-9), "head-bc Δ {:?}", e.o);
}

#[test]
fn tv_wse_04_macro_variables_read_and_write_the_sets() {
    let src = "#26013=1.25\n#26075=-3.5\n#26076=45.\n#26077=-30.\n#26000=1.\n#26001=2.\n#26002=3.\n\
               #26006=4.\n#26007=5.\n#100=#26013\n#101=#26075\n#102=#26076\n#103=#26077\n\
               #104=#26000+#26001+#26002+#26006+#26007\nM30\n";
    let interp = ran(fanuc(src, "mill3"));
    let s = &interp.state.setting_errors.sets;
    assert_eq!((s[1].rotation[0], s[7].rotation[2], s[7].table), (1.25, -3.5, [45.0, -30.0]));
    assert_eq!((s[0].shift, s[0].table), ([1.0, 2.0, 3.0], [4.0, 5.0]));
    let vars = interp.state.common_variables();
    let v = |n| vars.iter().find(|(k, _)| *k == n).unwrap().1;
    assert_eq!((v(100), v(101), v(102), v(103), v(104)), (1.25, -3.5, 45.0, -30.0, 15.0));
    // A host writes the sets directly.
    let mut interp = fanuc("#100=#26012\nM30\n", "mill3");
    interp.state.setting_errors.sets[1].shift[2] = -7.0;
    let interp = ran(interp);
    assert_eq!(interp.state.common_variables(), vec![(100, -7.0)]);
}

#[test]
fn tv_wse_04d_common_has_no_rotation_variables() {
    for src in
        ["#100=#26003\nM30\n", "#26004=1.\nM30\n", "#100=#26005\nM30\n", "#100=#26008\nM30\n", "#26080=1.\nM30\n"]
    {
        assert_eq!(alarm_of(fanuc(src, "mill3")), "PS0115", "{src}");
    }
}

/// Example 1 (TV-WSE-17): No.01 x 10, y 20, c −20; G55 at machine (100, 50, −400).
fn example_1(preset: &str) -> Interpreter {
    let src = "N10 G55\nN15 G54.4 P1\nN20 G90 G00 X0 Y0 Z300.0 B0 C0\nN30 G01 G43 H01 Z40.0 F500.\n\
               N40 X50.0 Y50.0 Z20.0\nN50 X150.0\nN60 Y150.0\nN70 X50.0\nN80 Y50.0\nN90 X0 Y0 Z40.0\n\
               N100 G49 Z300.0\nN115 G54.4 P0\nN120 G00 X0 Y0\nM30\n";
    let mut interp = fanuc(src, preset);
    let g55 = interp.state.offsets.work_mut(2);
    g55[..3].copy_from_slice(&[100.0, 50.0, -400.0]);
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    interp
}

#[test]
fn tv_wse_17_example_1_cuts_the_displaced_square() {
    // Right-hand Δc (OQ-11): p_w = Rz(−20°)·p_s + (10, 20, 0). Tool tip in G55 = machine −
    // G55 − tool length along Z (B0 C0).
    let expected = [
        (3, [10.0, 20.0, 300.0], 0.0),
        (4, [10.0, 20.0, 40.0], 100.0),
        (5, [74.085638, 49.883624, 20.0], 100.0),
        (6, [168.054900, 15.681610, 20.0], 100.0),
        (7, [202.256915, 109.650872, 20.0], 100.0),
        (8, [108.287653, 143.852886, 20.0], 100.0),
        (9, [74.085638, 49.883624, 20.0], 100.0),
        (10, [10.0, 20.0, 40.0], 100.0),
        (11, [10.0, 20.0, 300.0], 0.0),
        // After G54.4 P0, X0 Y0 is the G55 origin again.
        (13, [0.0, 0.0, 300.0], 0.0),
    ];
    for preset in ["head-bc", "mill3"] {
        let src_preset = preset;
        let mut interp = example_1(src_preset);
        if preset == "mill3" {
            // mill3 has no B/C: the same program without them.
            let text = "N10 G55\nN15 G54.4 P1\nN20 G90 G00 X0 Y0 Z300.0\nN30 G01 G43 H01 Z40.0 F500.\n\
                        N40 X50.0 Y50.0 Z20.0\nN50 X150.0\nN60 Y150.0\nN70 X50.0\nN80 Y50.0\nN90 X0 Y0 Z40.0\n\
                        N100 G49 Z300.0\nN115 G54.4 P0\nN120 G00 X0 Y0\nM30\n";
            let offsets = interp.state.offsets.clone();
            let errors = interp.state.setting_errors;
            interp = fanuc(text, preset);
            interp.state.offsets = offsets;
            interp.state.setting_errors = errors;
        }
        let ends = motion_ends(interp);
        for (line, tip, length) in expected {
            let m = end_of(&ends, line);
            let got = [m[0] - 100.0, m[1] - 50.0, m[2] + 400.0 - length];
            assert!(close3(got, tip, 1e-6), "{preset} line {line}: {got:?} vs {tip:?}");
        }
    }
}

#[test]
fn tv_wse_17_sides_are_straight_lines_in_the_wcs() {
    // Every sample of N50 (a side of the square) lies on the displaced side.
    let mut interp = example_1("head-bc");
    let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
        if s.line == 6 {
            let p = [s.machine[0] - 100.0 - 10.0, s.machine[1] - 50.0 - 20.0];
            // Back into the WSCS (Rz(+20°)): the side is y = 50, x from 50 to 150.
            let (sn, cs) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
            let ps = [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1]];
            assert!((ps[1] - 50.0).abs() < 1e-6, "off the side: WSCS {ps:?}");
            assert!((50.0 - 1e-6..=150.0 + 1e-6).contains(&ps[0]), "{ps:?}");
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
}

#[test]
fn tv_wse_18_the_start_block_recomputes_the_absolute_position_without_moving() {
    let src = "G90 G00 X0 Y0 Z300.\nG54.4 P1\n#100=#5001\n#101=#5002\n#102=#5003\n#103=#5041\n#104=#5042\n\
               G54.4 P0\n#105=#5001\n#106=#5002\nM30\n";
    let mut interp = fanuc(src, "mill3");
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    let mut motions = 0;
    interp
        .run(|c| {
            if matches!(c.kind, CanonKind::Motion(_)) {
                motions += 1
            }
        })
        .unwrap();
    assert_eq!(motions, 1, "G54.4 P1 / P0 do not move");
    let vars = interp.state.common_variables();
    let v = |n| vars.iter().find(|(k, _)| *k == n).unwrap().1;
    assert!(close3([v(100), v(101), v(102)], [-2.556523, -22.214054, 300.0], 1e-6));
    // #5041… are WCS coordinates (WSE-20).
    assert!(close3([v(103), v(104), 0.0], [0.0, 0.0, 0.0], 1e-9));
    // P0 recomputes back.
    assert!(close3([v(105), v(106), 0.0], [0.0, 0.0, 0.0], 1e-9));
}

#[test]
fn tv_wse_18_wcs_points_map_to_their_wscs_coordinates() {
    let e = wse::frame([10.0, 20.0, 0.0], [0.0, 0.0, -20.0]);
    for (w, s) in [([10.0, 20.0, 40.0], [0.0, 0.0, 40.0]), ([74.085638, 49.883624, 20.0], [50.0, 50.0, 20.0])] {
        let got = e.from_parent(&w.into());
        assert!(close3(got.into(), s, 1e-6), "{got:?}");
    }
}

#[test]
fn circles_under_g54_4_stay_circles_when_the_error_tilts_their_plane() {
    // Δa 10°, Δb −5°: the G17 circle is a circle in space; every sample is on it (WSCS).
    let src = "G90 G00 X0 Y0 Z10.\nG54.4 P1\nG00 X20. Y0 Z10.\nG17 G03 X-20. Y0 I-20. J0 F2000.\nG02 X20. Y0 R20.\n\
               G54.4 P0\nM30\n";
    let mut interp = fanuc(src, "mill3");
    let set = wse::ErrorSet { shift: [5.0, -3.0, 2.0], rotation: [10.0, -5.0, 30.0], table: [0.0; 2] };
    interp.state.setting_errors.sets[1] = set;
    let e = wse::frame(set.shift, set.rotation);
    let mut seen = 0;
    let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
        if s.line == 4 || s.line == 5 {
            let p = e.from_parent(&xyz(&s.machine).into());
            assert!((p[0].hypot(p[1]) - 20.0).abs() < 1e-6 && (p[2] - 10.0).abs() < 1e-6, "line {}: {p:?}", s.line);
            // G03 from +X to −X and G02 back both pass over +Y (seen from the WSCS +Z).
            assert!(p[1] >= -1e-6, "line {}: {p:?}", s.line);
            seen += 1;
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(seen > 20);
    // Back at the start after the two half circles, in the WCS.
    let w = e.to_parent(&[20.0, 0.0, 10.0].into());
    assert!(close3(xyz(&r.machine), w.into(), 1e-9), "{:?}", r.machine);
}

#[test]
fn g53_and_g28_bypass_the_error() {
    let src =
        "G90 G00 X0 Y0 Z50.\nG54.4 P1\nG53 X100. Y10. Z-5.\n#100=#5001\n#101=#5002\nG28 X0 Y0 Z0\nG54.4 P0\nM30\n";
    let mut interp = fanuc(src, "mill3");
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    let ends = motion_ends(interp.clone());
    assert_eq!(xyz(&end_of(&ends, 3)), [100.0, 10.0, -5.0], "G53 in machine coordinates");
    // G28's intermediate point is a program point (through the error), the return is machine 0.
    let g28: Vec<_> = ends.iter().filter(|(l, _)| *l == 6).collect();
    assert!(close3(xyz(&g28[0].1), [10.0, 20.0, 0.0], 1e-9), "{:?}", g28[0].1);
    assert_eq!(xyz(&g28[1].1), [0.0, 0.0, 0.0]);
    let interp = ran(interp);
    let vars = interp.state.common_variables();
    let v = |n| vars.iter().find(|(k, _)| *k == n).unwrap().1;
    // The machine point (100, 10) in the WSCS.
    let s = wse::frame([10.0, 20.0, 0.0], [0.0, 0.0, -20.0]).from_parent(&[100.0, 10.0, -5.0].into());
    assert!((v(100) - s[0]).abs() < 1e-9 && (v(101) - s[1]).abs() < 1e-9);
}

#[test]
fn wse_21_reset_cancels_unless_d3r() {
    for keep in [false, true] {
        let mut interp = fanuc_with("G54.4 P1\nM30\n", "mill3", |c| {
            c.edit_machine(|m| {
                m.five_axis.plane_after_reset = if keep { PlaneAfterReset::Kept } else { PlaneAfterReset::Cancelled }
            })
        });
        interp.state.setting_errors.sets[1].shift = [1.0, 2.0, 3.0];
        let mut interp = ran(interp);
        let before = interp.state.machine_position();
        interp.reset();
        assert_eq!(interp.state.active_setting_error().is_some(), keep, "D3R = {keep}");
        assert_eq!(interp.state.machine_position(), before, "a reset does not move");
        // After the reset a new G54.4 P1 is refused only while the old one is still on.
        interp.load(parse_file("G54.4 P2\nM30\n"));
        let r = interp.run(|_| {});
        assert_eq!(r.is_err(), keep, "D3R = {keep}: {r:?}");
    }
}

// --- mode rules ---------------------------------------------------------------------------

fn alarm_on(src: &str, preset: &str) -> String {
    alarm_of(fanuc(src, preset))
}

#[test]
fn tv_wse_10_to_12_block_format() {
    for src in ["G54.4\n", "G54.4 P8\n", "G54.4 P-1\n", "G54.4 P1 G01 X10.\n", "G54.4 P1 G90\n", "G54.4 P1\nG54.4 P2\n"]
    {
        assert_eq!(alarm_on(src, "mill3"), "PS0437", "{src}");
    }
    // TV-WSE-13: P0 cancels.
    let interp = ran(fanuc("G54.4 P1\nG54.4 P0\nG54.4 P2\nM30\n", "mill3"));
    assert_eq!(interp.state.active_setting_error().map(|a| a.0), Some(2));
}

#[test]
fn tv_wse_14_basic_axes_missing() {
    let mut m = MachineConfig::preset("mill3").unwrap();
    m.axes.retain(|a| a.name != 'Y');
    let mut interp = Interpreter::new(parse_file("G54.4 P1\nM30\n"), Config::new(m, Dialect::Fanuc));
    assert_eq!(interp.run(|_| {}).unwrap_err().code, "PS0436");
}

#[test]
fn tv_wse_15_16_mode_lists() {
    for g in ["G61", "G92 X0", "G52 X1.", "G68.3", "G55", "G20"] {
        assert_eq!(alarm_on(&format!("G54.4 P1\n{g}\n"), "head-bc"), "PS0437", "{g}");
    }
    // (G41 is not built: `modes.rs` checks this rule with G41; here another listed state.)
    assert_eq!(alarm_on("G68 X0 Y0 R10.\nG54.4 P1\n", "mill3"), "PS0439");
    // §6.6: the modes opened inside must close before G54.4 P0 [A: PS0437].
    assert_eq!(alarm_on("G54.4 P1\nG43 H1 G01 Z10. F100.\nG54.4 P0\n", "mill3"), "PS0437");
    assert_eq!(alarm_on("G54.4 P1\nG68.2 X0 Y0 Z0 I0 J30. K0\nG54.4 P0\n", "head-bc"), "PS0437");
    let interp = ran(fanuc("G54.4 P1\nG43 H1 G01 Z10. F100.\nG49 G00 Z200.\nG54.4 P0\nM30\n", "mill3"));
    assert!(interp.state.active_setting_error().is_none());
}

#[test]
fn tv_wse_19b_19c_tcp_and_g53_1_need_tool_direction_compensation() {
    assert_eq!(alarm_on("G54.4 P1\nG43.4 H1\n", "head-bc"), "PS5421");
    assert_eq!(alarm_on("G54.4 P1\nG68.2 X0 Y0 Z0 I0 J30. K0\nG53.1\n", "head-bc"), "PS5458");
}

// --- tool direction compensation (RCM = 1) -------------------------------------------------

fn rcm(c: &mut Config) {
    c.edit_machine(|m| m.five_axis.tool_direction_compensation = true);
}

/// Example 2 (TV-WSE-19) on the BC head with RCM = 1, No.01 as Example 1, G55 (100, 50, −400).
const EXAMPLE_2: &str = "N15 G05.1 Q1\nN10 G55\nN16 G54.4 P1\nN20 G90 G00 X0 Y0 Z300.0 B0 C0\n\
    N30 G01 G43.4 H01 Z40.0 F500.\nN40 X50.0 Y50.0 Z20.0 B45.0 C-90.0\nN50 X150.0\nN60 C0.0\nN70 Y150.0\n\
    N80 C90.0\nN90 X50.0\nN100 C180.0\nN110 Y50.0\nN120 X0 Y0 Z40.0 B0.0 C0.0\nN130 G49 Z300.0\nN135 G54.4 P0\n\
    N136 G05.1 Q0\nM30\n";

fn example_2(src: &str, tweak: impl FnOnce(&mut Config)) -> Interpreter {
    let mut interp = fanuc_with(src, "head-bc", tweak);
    interp.state.offsets.work_mut(2)[..3].copy_from_slice(&[100.0, 50.0, -400.0]);
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    interp
}

#[test]
fn tv_wse_19_example_2_keeps_the_tool_direction_relative_to_the_displaced_workpiece() {
    use fivex_engine::kin::Kinematics;
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let ends = motion_ends(example_2(EXAMPLE_2, rcm));
    // (line, B, C, tip in G55, tool length); B index 3, C index 4.
    let expected = [
        (4, 0.0, 0.0, [10.0, 20.0, 300.0], 0.0),
        (5, 0.0, 0.0, [10.0, 20.0, 40.0], 100.0),
        (6, 45.0, -110.0, [74.085638, 49.883624, 20.0], 100.0),
        (7, 45.0, -110.0, [168.054900, 15.681610, 20.0], 100.0),
        (8, 45.0, -20.0, [168.054900, 15.681610, 20.0], 100.0),
        (9, 45.0, -20.0, [202.256915, 109.650872, 20.0], 100.0),
        (10, 45.0, 70.0, [202.256915, 109.650872, 20.0], 100.0),
        (11, 45.0, 70.0, [108.287653, 143.852886, 20.0], 100.0),
        (12, 45.0, 160.0, [108.287653, 143.852886, 20.0], 100.0),
        (13, 45.0, 160.0, [74.085638, 49.883624, 20.0], 100.0),
        // Singular target from a posture that is not: C stays (§2.14 rule 2).
        (14, 0.0, 160.0, [10.0, 20.0, 40.0], 100.0),
        // Singular to singular, the programmed posture singular too: C moves as commanded
        // (rule 1-(2)), and G49 Z300 commands no C motion: it stays at 160.
        (15, 0.0, 160.0, [10.0, 20.0, 300.0], 0.0),
    ];
    let dirs = [
        (6, [-0.241845, -0.664463, 0.707107]),
        (8, [0.664463, -0.241845, 0.707107]),
        (10, [0.241845, 0.664463, 0.707107]),
        (12, [-0.664463, 0.241845, 0.707107]),
    ];
    for (line, b, c, tip, length) in expected {
        let m = end_of(&ends, line);
        assert!((m[3] - b).abs() < 1e-6 && (m[4] - c).abs() < 1e-6, "line {line}: B {} C {}", m[3], m[4]);
        let pose = kin.forward(&m, length);
        let got =
            [pose.tip[0] - 100.0 - kin.nose[0], pose.tip[1] - 50.0 - kin.nose[1], pose.tip[2] + 400.0 - kin.nose[2]];
        assert!(close3(got, tip, 1e-6), "line {line}: tip {got:?} vs {tip:?}");
    }
    for (line, d) in dirs {
        let t = kin.forward(&end_of(&ends, line), 100.0).tool;
        assert!(close3(t.into(), d, 1e-6), "line {line}: tool {t:?}");
    }
}

/// Example 2's closing `G49 Z300.` (N130) commands no C: at the singular posture C does not
/// turn at any sample (it turned 160° → 360° the long way, +200°, on head-bc's shortest-way C).
#[test]
fn tv_wse_19_the_closing_g49_block_does_not_turn_c() {
    let mut interp = example_2(EXAMPLE_2, rcm);
    let mut seen = 0;
    let r = run(&mut interp, &RunOptions { period_s: 0.005, ..RunOptions::default() }, |s| {
        if s.line == 15 {
            seen += 1;
            let c = (s.machine[4] - 160.0).rem_euclid(360.0);
            assert!(
                c.min(360.0 - c) < 1e-6 && s.machine[3].abs() < 1e-6,
                "N130 at B {} C {}",
                s.machine[3],
                s.machine[4]
            );
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(seen > 10, "{seen} samples of N130");
}

#[test]
fn tv_wse_19_without_rcm_tcp_is_refused_and_the_rotary_axes_are_untouched() {
    assert_eq!(alarm_of(example_2(EXAMPLE_2, |_| {})), "PS5421");
    // RCM = 0 and no TCP: the rotary axes go where programmed (OQ-13).
    let src = "G55\nG54.4 P1\nG90 G00 X0 Y0 Z300. B0 C0\nG01 X50. Y50. Z20. B45. C-90. F500.\nG54.4 P0\nM30\n";
    let ends = motion_ends(example_2(src, |_| {}));
    let m = end_of(&ends, 4);
    assert!((m[3] - 45.0).abs() < 1e-9 && (m[4] + 90.0).abs() < 1e-9);
}

#[test]
fn tv_wse_20_table_machines_with_rcm_refuse_machine_coordinates_and_g95() {
    let on = |src: &str| alarm_of(fanuc_with(src, "table-ac", rcm));
    for g in ["G28 X0", "G29 X0", "G30 X0", "G43.1 H1", "G53 X0", "G06.2 P3 X0 R1. K0", "G95"] {
        assert_eq!(on(&format!("G54.4 P1\n{g}\n")), "PS0439", "{g}");
    }
    // TV-WSE-20b: G54.4 in G95.
    assert_eq!(on("G95\nG54.4 P1\n"), "PS0439");
    // Without RCM, or on a head machine, these rows do not apply.
    assert!(fanuc_with("G95\nG54.4 P1\nG54.4 P0\nG94\nM30\n", "head-bc", rcm).run(|_| {}).is_ok());
    assert!(fanuc("G95\nG54.4 P1\nG54.4 P0\nG94\nM30\n", "table-ac").run(|_| {}).is_ok());
}

#[test]
fn tv_wse_20c_tcp_and_g68_2_need_the_table_at_absolute_0() {
    let on = |src: &str| fanuc_with(src, "table-ac", rcm).run(|_| {}).map_err(|a| a.code);
    for start in ["G43.4 H1", "G68.2 X0 Y0 Z0 I0 J0 K0"] {
        let turned = format!("G90 G00 X0 Y0 Z100. A0 C15.\nG54.4 P1\n{start}\n");
        assert_eq!(on(&turned), Err("PS0439".into()), "{start}");
    }
    assert_eq!(on("G90 G00 X0 Y0 Z100. A0 C0\nG54.4 P1\nG43.4 H1\nG01 X10. F500.\nG49\nG54.4 P0\nM30\n"), Ok(()));
}

#[test]
fn tv_wse_20d_axes_outside_5_axis_machining() {
    let mut m = MachineConfig::preset("table-ac").unwrap();
    let mut u = m.axes[0].clone();
    u.name = 'U';
    m.axes.push(u);
    let mut cfg = Config::new(m, Dialect::Fanuc);
    rcm(&mut cfg);
    let run = |cfg: Config, src: &str| Interpreter::new(parse_file(src), cfg).run(|_| {}).map_err(|a| a.code);
    assert_eq!(run(cfg.clone(), "G54.4 P1\nG01 X1. U5. F100.\n"), Err("PS0439".into()));
    assert_eq!(run(cfg, "G01 U5. F100.\nG54.4 P1\nG01 X1. F100.\nG54.4 P0\nM30\n"), Ok(()));
}

/// TV-WSE-22…25: a C–B head (head-bc), error Δb = −2°, tolerance `tol`, start at B `b0`.
fn singular_run(b0: f64, error: bool, tol: f64) -> Pos {
    let src = format!(
        "N10 G05.1 Q1\nN20 G90 G01 B{b0:.1} C0 F1000.\n{}N30 G43.4 H1\nN40 X0 Y0 Z0\nN50 B90.0 C90.0\nM30\n",
        if error { "N25 G54.4 P1\n" } else { "" }
    );
    let mut interp = fanuc_with(&src, "head-bc", |c| {
        rcm(c);
        c.edit_machine(|m| m.five_axis.singular_tolerance_deg = tol);
    });
    interp.state.setting_errors.sets[1].rotation = [0.0, -2.0, 0.0];
    let ends = motion_ends(interp);
    ends.last().unwrap().1
}

#[test]
fn tv_wse_22_to_25_the_side_of_the_singular_angle() {
    let bc = |p: Pos| (p[3], p[4]);
    let near = |(b, c): (f64, f64), (eb, ec): (f64, f64)| (b - eb).abs() < 1e-6 && (c - ec).abs() < 1e-6;
    // TV-WSE-22: no error.
    assert!(near(bc(singular_run(-1.0, false, 0.0)), (90.0, 90.0)));
    // TV-WSE-23: from B −1 the tool never reaches the singular posture: B stays negative and
    // runs past the −45° lower limit of the seed's machine (no clamping, WSE-23).
    assert!(near(bc(singular_run(-1.0, true, 0.0)), (-90.0, -90.0)), "{:?}", bc(singular_run(-1.0, true, 0.0)));
    // TV-WSE-24: from B +1 it stays positive.
    assert!(near(bc(singular_run(1.0, true, 0.0)), (90.0, 90.0)), "{:?}", bc(singular_run(1.0, true, 0.0)));
    // TV-WSE-25: with No.11204 = 0.1 the path passes within 0.1° of the singular posture
    // (0.035° at programmed B ≈ 2.0): treated as singular, B crosses 0.
    let got = bc(singular_run(-1.0, true, 0.1));
    assert!(near(got, (90.0, 90.0)), "{got:?}");
}

/// S000 III.2 (restrictions): "In the mode of Workpiece setting error compensation, Stroke
/// limit check before movement is not available." The seed's O2 (§2.3.12, error Δb −2°, from
/// B −1) on its machine whose B moves in [−45, 100] (§2.3.18: "set the stored stroke limit
/// check to prevent a movement over the range"): N50 runs until B reaches −45, stops there
/// and gives the stored stroke check's alarm OT0501, not the pre-check's OT0511 before
/// anything of N50 moves. The tip (TCP, X0 Y0 Z0) stays at the origin all the while.
#[test]
fn g54_4_has_no_stroke_check_before_movement_the_axis_stops_at_its_limit() {
    use fivex_engine::controller::{Controller, Mode, RunState};
    use fivex_engine::kin::Kinematics;
    let src =
        "N10 G05.1 Q1\nN20 G90 G01 B-1.0 C0 F1000.\nN25 G54.4 P1\nN30 G43.4 H1\nN40 X0 Y0 Z0\nN50 B90.0 C90.0\nM30\n";
    let b45 = |c: &mut Config| {
        rcm(c);
        c.edit_machine(|m| m.axes[3].stroke = Some([-45.0, 100.0]));
    };
    let mut interp = fanuc_with(src, "head-bc", b45);
    interp.state.setting_errors.sets[1].rotation = [0.0, -2.0, 0.0];
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let mut n50 = Vec::new();
    let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
        if s.line == 6 {
            n50.push(s.machine);
        }
    });
    let a = &r.alarms[0];
    assert_eq!(
        (a.code.as_str(), a.message.as_str(), a.line),
        ("OT0501", "- OVERTRAVEL ( SOFT 1 ) B", 6),
        "{:?}",
        r.alarms
    );
    assert!(n50.iter().all(|m| m[3] >= -45.0 - 1e-9), "B stays within its stroke");
    assert!(n50.iter().any(|m| m[3] < -40.0), "N50 moved toward the limit");
    assert!((r.machine[3] + 45.0).abs() < 1e-6, "stopped at the limit: {:?}", r.machine);
    for m in &n50 {
        let tip = kin.forward(m, 100.0).tip - kin.nose;
        assert!(tip.norm() < 1e-6, "the tip stays at the origin: {tip:?}");
    }
    // The same in the controller.
    let mut cfg = Config::new(MachineConfig::preset("head-bc").unwrap(), Dialect::Fanuc);
    b45(&mut cfg);
    let mut c = Controller::new(cfg);
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 100.0;
    c.interpreter_mut().state.setting_errors.sets[1].rotation = [0.0, -2.0, 0.0];
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(0.005);
    }
    assert_eq!(c.run_state(), RunState::Alarm);
    assert_eq!((c.alarms()[0].code.as_str(), c.alarms()[0].line), ("OT0501", 6), "{:?}", c.alarms());
    assert!((c.point().machine[3] + 45.0).abs() < 1e-6, "{:?}", c.point().machine);
}

#[test]
fn tv_wse_18_rcm_start_block_turns_the_absolute_rotary_coordinates() {
    // TV-WSE-23's start: machine B −1 C0, Δb −2°: the tool seen from the WSCS is at B +1 C0.
    let src = "G90 G01 B-1. C0 F1000.\nG54.4 P1\n#100=#5004\n#101=#5005\nM30\n";
    let mut interp = fanuc_with(src, "head-bc", rcm);
    interp.state.setting_errors.sets[1].rotation = [0.0, -2.0, 0.0];
    let interp = ran(interp);
    let vars = interp.state.common_variables();
    assert!((vars[0].1 - 1.0).abs() < 1e-9 && vars[1].1.abs() < 1e-9, "{vars:?}");
}

#[test]
fn tv_wse_27_singular_start_keeps_the_absolute_coordinates() {
    // B 0.05 with Δb −0.03 and No.11204 = 0.1: both postures singular.
    let src = "G90 G00 X1. Y2. Z3. B0.05 C30.\nG54.4 P1\n#100=#5001\n#101=#5004\n#102=#5005\nM30\n";
    let mut interp = fanuc_with(src, "head-bc", |c| {
        rcm(c);
        c.edit_machine(|m| m.five_axis.singular_tolerance_deg = 0.1);
    });
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [5.0, 0.0, 0.0], rotation: [0.0, -0.03, 0.0], table: [0.0; 2] };
    let interp = ran(interp);
    let v: Vec<f64> = interp.state.common_variables().iter().map(|x| x.1).collect();
    assert!((v[0] - 1.0).abs() < 1e-9 && (v[1] - 0.05).abs() < 1e-9 && (v[2] - 30.0).abs() < 1e-9, "{v:?}");
}

/// One block on head-bc with RCM = 1 and error Δc = `dc`, from machine B `b0` C `c0` to
/// programmed B `b` C `c`; the machine's end (B, C).
fn one_block(b0: f64, c0: f64, b: f64, c: f64, dc: f64, tol: f64) -> (f64, f64) {
    let src = format!("G90 G00 B{b0:.3} C{c0:.3}\nG54.4 P1\nG00 B{b:.3} C{c:.3}\nM30\n");
    let mut interp = fanuc_with(&src, "head-bc", |cfg| {
        rcm(cfg);
        cfg.edit_machine(|m| m.five_axis.singular_tolerance_deg = tol);
    });
    interp.state.setting_errors.sets[1].rotation = [0.0, 0.0, dc];
    let end = motion_ends(interp).last().unwrap().1;
    (end[3], end[4])
}

#[test]
fn tv_wse_28_the_four_cases_of_the_singular_rules() {
    // TV-WSE-28, No.11204 = 0.1, Δb −0.45: from machine B0 C10 (singular) to programmed B0.5
    // C0 (not singular), which the error turns to 0.05° off the singular posture.
    let src = "G90 G00 B0 C10.\nG54.4 P1\nG00 B0.5 C0\nM30\n";
    let mut interp = fanuc_with(src, "head-bc", |c| {
        rcm(c);
        c.edit_machine(|m| m.five_axis.singular_tolerance_deg = 0.1);
    });
    interp.state.setting_errors.sets[1].rotation = [0.0, -0.45, 0.0];
    let end = motion_ends(interp).last().unwrap().1;
    // C (workpiece side) does not move, only B.
    assert!((end[4] - 10.0).abs() < 1e-9, "C {}", end[4]);
    // TV-WSE-28b: current B0, programmed target B0 (singular): C moves as commanded.
    let (b, c) = one_block(0.0, 10.0, 0.0, 40.0, 5.0, 0.0);
    assert!(b.abs() < 1e-9 && (c - 40.0).abs() < 1e-9, "{b} {c}");
    // TV-WSE-28c: current B20, compensated target singular: C does not move.
    let (b, c) = one_block(20.0, 10.0, 0.0, 40.0, 5.0, 0.0);
    assert!(b.abs() < 1e-9 && (c - 10.0).abs() < 1e-9, "{b} {c}");
    // TV-WSE-28d: current B0 (singular), target not: the pair with the smaller C motion, judged
    // (as TV-WSE-19 derives) in the first interpolation period that leaves the singular
    // posture, not at the block's end. Programmed B30 C170, Δc 5: the end pairs are (B30,
    // C175) and (B−30, C−5), and C−5 is nearer C0; but the first step (programmed B0.03 C0.17)
    // needs C 5.17 with B > 0 or C −174.83 with B < 0, so B stays positive.
    let (b, c) = one_block(0.0, 0.0, 30.0, 170.0, 5.0, 0.0);
    assert!((b - 30.0).abs() < 1e-6 && (c - 175.0).abs() < 1e-6, "{b} {c}");
    let (b, c) = one_block(0.0, 0.0, -30.0, -10.0, 5.0, 0.0);
    assert!((b + 30.0).abs() < 1e-6 && (c + 5.0).abs() < 1e-6, "{b} {c}");
    // TV-WSE-28e: current B20, target not singular: B stays positive although the other pair
    // (B−30, C−5) would move C far less than (B30, C175).
    let (b, c) = one_block(20.0, 0.0, 30.0, 170.0, 5.0, 0.0);
    assert!((b - 30.0).abs() < 1e-6 && (c - 175.0).abs() < 1e-6, "{b} {c}");
    // And from B −20 it stays negative.
    let (b, c) = one_block(-20.0, 0.0, 30.0, 170.0, 5.0, 0.0);
    assert!((b + 30.0).abs() < 1e-6 && (c + 5.0).abs() < 1e-6, "{b} {c}");
}

#[test]
fn tv_wse_21_on_a_table_machine_the_line_is_straight_seen_from_the_workpiece() {
    // table-ac, G55 X50 Y0 Z0; N30 G01 X−50 Y150 C−90 with Δc 5 (RCM = 1): every sample of the
    // tip in the WSCS is on the programmed line, while the table turns.
    let src = "N10 G55\nN15 G05.1 Q1\nN16 G54.4 P1\nN20 G90 G00 X0 Y0 Z0 A0 C0\nN30 G01 X-50.0 Y150.0 C-90.0 F100.0\n\
               N40 G54.4 P0\nM30\n";
    let mut interp = fanuc_with(src, "table-ac", rcm);
    interp.state.offsets.work_mut(2)[..3].copy_from_slice(&[50.0, 0.0, 0.0]);
    interp.state.setting_errors.sets[1].rotation = [0.0, 0.0, 5.0];
    let c_end = end_of(&motion_ends(interp.clone()), 5)[4];
    let mut seen = 0;
    let r = run(&mut interp, &RunOptions { period_s: 0.01, ..RunOptions::default() }, |s| {
        if s.line == 5 {
            // The programmed point is in the WSCS; the tip (in the WCS, from the axes) carried
            // back into it by the 5° error about Z is on the same line.
            assert_eq!(s.programmed_in, fivex_engine::tip::System::Wscs);
            let (sn, cs) = 5f64.to_radians().sin_cos();
            let back = [cs * s.tip[0] + sn * s.tip[1], -sn * s.tip[0] + cs * s.tip[1], s.tip[2]];
            for [x, y, z] in [s.programmed, back] {
                // On the line from (0, 0, 0) to (−50, 150, 0): 3x + y = 0, z = 0, x in [−50, 0].
                let on = (3.0 * x + y).abs() < 1e-6 && z.abs() < 1e-6 && (-50.0 - 1e-6..=1e-6).contains(&x);
                assert!(on, "{:?} / tip {:?}", [x, y, z], s.tip);
            }
            seen += 1;
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(seen > 100);
    // The tool is along the C axis (singular): C goes where programmed (§2.14 rule 1 (2)).
    assert!((c_end + 90.0).abs() < 1e-6, "C {c_end}");
}

#[test]
fn oq_21_a_tilted_plane_inside_g54_4_is_defined_in_the_wscs() {
    // Example 1's error; G68.2 with Euler angles 0 and origin (50, 50, 20) in the WSCS, then
    // X0 Y0 Z0 (no tool length): the nose at the displaced (50, 50, 20), i.e. WCS (74.09, 49.88).
    let src =
        "G55\nG54.4 P1\nG90 G00 X0 Y0 Z100.\nG68.2 X50. Y50. Z20. I0 J0 K0\nG01 X0 Y0 Z0 F500.\nG69\nG54.4 P0\nM30\n";
    let mut interp = fanuc(src, "head-bc");
    interp.state.offsets.work_mut(2)[..3].copy_from_slice(&[100.0, 50.0, -400.0]);
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    let m = end_of(&motion_ends(interp), 5);
    let got = [m[0] - 100.0, m[1] - 50.0, m[2] + 400.0];
    assert!(close3(got, [74.085638, 49.883624, 20.0], 1e-6), "{got:?}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, ..proptest::prelude::ProptestConfig::default() })]

    /// Any error: G54.4 Pn and P0 do not move; a programmed point lands at `R_e·p + Δ` plus the
    /// work offset; after P0 the current point is that WCS point.
    #[test]
    fn programmed_points_land_on_the_displaced_workpiece(
        shift in proptest::array::uniform3(-100.0f64..100.0),
        rot in proptest::array::uniform3(-30.0f64..30.0),
        p in proptest::array::uniform3(-200.0f64..200.0),
    ) {
        let src = format!(
            "G90 G00 X10. Y20. Z30.\nG54.4 P3\nG01 X{:.4} Y{:.4} Z{:.4} F1000.\nG54.4 P0\n#100=#5001\n#101=#5002\n#102=#5003\nM30\n",
            p[0], p[1], p[2]
        );
        let mut interp = fanuc(&src, "mill3");
        interp.state.offsets.work_mut(1)[..3].copy_from_slice(&[7.0, -8.0, 9.0]);
        interp.state.setting_errors.sets[3] = wse::ErrorSet { shift, rotation: rot, table: [0.0; 2] };
        let mut motions = Vec::new();
        interp.run(|c| if let CanonKind::Motion(m) = c.kind { motions.push(m.machine) }).unwrap();
        proptest::prop_assert_eq!(motions.len(), 2);
        let q = [(p[0] * 1e4).round() / 1e4, (p[1] * 1e4).round() / 1e4, (p[2] * 1e4).round() / 1e4];
        let w = wse::frame(shift, rot).to_parent(&q.into());
        let m = motions[1];
        proptest::prop_assert!(close3([m[0] - 7.0, m[1] + 8.0, m[2] - 9.0], w.into(), 1e-9), "{:?} vs {:?}", m, w);
        let vars = interp.state.common_variables();
        let v: Vec<f64> = vars.iter().map(|x| x.1).collect();
        proptest::prop_assert!(close3([v[0], v[1], v[2]], w.into(), 1e-9));
        // The rotation angles come back from the matrix.
        proptest::prop_assert!(close3(wse::angles(&wse::rotation(rot)), rot, 1e-9));
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 24, ..proptest::prelude::ProptestConfig::default() })]

    /// RCM = 1 on every 5-axis machine kind: at a block's end the tip is at `R_e·p + Δ` and the
    /// tool, relative to the workpiece, is `R_e` times the direction the programmed angles give.
    #[test]
    fn compensation_keeps_tip_and_tool_relative_to_the_displaced_workpiece(
        shift in proptest::array::uniform3(-20.0f64..20.0),
        rot in proptest::array::uniform3(-3.0f64..3.0),
        p in proptest::array::uniform3(-50.0f64..50.0),
        angles in proptest::array::uniform2(15.0f64..75.0),
    ) {
        use fivex_engine::kin::Kinematics;
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let machine = MachineConfig::preset(preset).unwrap();
            let kin = Kinematics::new(&machine).unwrap();
            let names: Vec<char> = kin.joints().iter().map(|j| j.name).collect();
            let src = format!(
                "G90 G00 X0 Y0 Z100.\nG54.4 P1\nG43 H1\nG01 X{:.3} Y{:.3} Z{:.3} {}{:.3} {}{:.3} F1000.\nM30\n",
                p[0], p[1], p[2], names[0], angles[0], names[1], angles[1]
            );
            let mut interp = fanuc_with(&src, preset, rcm);
            interp.state.setting_errors.sets[1] = wse::ErrorSet { shift, rotation: rot, table: [0.0; 2] };
            let end = motion_ends(interp).last().unwrap().1;
            let e = wse::frame(shift, rot);
            let q = [p[0], p[1], p[2]].map(|x| (x * 1e3).round() / 1e3);
            let want_tip = e.to_parent(&q.into()) + kin.nose;
            let pose = kin.forward(&end, 100.0);
            proptest::prop_assert!((pose.tip - want_tip).norm() < 1e-6, "{preset}: tip {:?} vs {:?}", pose.tip, want_tip);
            let mut programmed = [0.0; fivex_engine::machine::MAX_AXES];
            for (j, a) in kin.joints().iter().zip(angles) {
                programmed[j.index.unwrap()] = (a * 1e3).round() / 1e3;
            }
            let want_tool = e.r * kin.forward(&programmed, 0.0).tool;
            proptest::prop_assert!((pose.tool - want_tool).norm() < 1e-9, "{preset}: tool {:?} vs {:?}", pose.tool, want_tool);
        }
    }
}

#[test]
fn ps0438_and_ds0030_when_the_direction_cannot_be_reached() {
    // A head with B only (C removed): a tool tilted in XZ turned by Δc 30° has no B angle.
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.rotary.retain(|l| l.axis == 'B');
    m.axes.retain(|a| a.name != 'C');
    let mut cfg = Config::new(m, Dialect::Fanuc);
    rcm(&mut cfg);
    let run = |src: &str| {
        let mut interp = Interpreter::new(parse_file(src), cfg.clone());
        interp.state.setting_errors.sets[1].rotation = [0.0, 0.0, 30.0];
        interp.run(|_| {}).map_err(|a| a.code)
    };
    // The start block: the tool at B30 seen from the WSCS needs a C.
    assert_eq!(run("G90 G00 B30.\nG54.4 P1\n"), Err("PS0438".into()));
    // Started with the tool along Z (reachable), then B30 in the WSCS cannot be reached.
    assert_eq!(run("G90 G00 B0\nG54.4 P1\nG00 X10.\nG00 B30.\n"), Err("DS0030".into()));
    assert_eq!(run("G90 G00 B0\nG54.4 P1\nG00 X10.\nG54.4 P0\nM30\n"), Ok(()));
}

#[test]
fn canned_cycles_under_rcm_keep_the_machine_position() {
    // head-bc, RCM = 1, tool vertical: a drilling cycle's moves are plain ones; the block after
    // the cycle starts where the cycle ended (no jump).
    let src = "G90 G00 X0 Y0 Z50. B0 C0\nG54.4 P1\nG81 X10. Y5. Z-5. R2. F200.\nG80\nG01 X20. F500.\nG54.4 P0\nM30\n";
    let mut interp = fanuc_with(src, "head-bc", rcm);
    interp.state.setting_errors.sets[1].shift = [3.0, 4.0, 0.0];
    let ends = motion_ends(interp.clone());
    let last_cycle = end_of(&ends, 3);
    assert!(close3(xyz(&last_cycle), [13.0, 9.0, 50.0], 1e-9), "{last_cycle:?}");
    let r = run(&mut interp, &RunOptions { period_s: 0.01, ..RunOptions::default() }, |s| {
        if s.line == 5 {
            assert!((s.machine[1] - 9.0).abs() < 1e-9 && (s.machine[2] - 50.0).abs() < 1e-9, "{:?}", s.machine);
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(close3(xyz(&r.machine), [23.0, 9.0, 50.0], 1e-9), "{:?}", r.machine);
}

#[test]
fn extreme_error_data_end_in_alarms_not_panics() {
    for (preset, rcm_on) in [("mill3", false), ("head-bc", true), ("table-ac", true), ("mixed-bc", false)] {
        for data in [
            "#26010=99999999.\n#26015=99999999.\n",
            "#1=10000000000.\n#26013=#1*#1*#1\n#26014=-#1*#1*#1\n#26016=#1*#1\n",
            "#1=10000000000.\n#26000=-#1*#1*#1\n",
        ] {
            let src = format!("{data}G54.4 P1\nG00 X1. Y1. Z1.\nG02 X2. Y2. R5. F100.\nG54.4 P0\nM30\n");
            let mut interp =
                fanuc_with(&src, preset, |c| c.edit_machine(|m| m.five_axis.tool_direction_compensation = rcm_on));
            let r = run(&mut interp, &RunOptions::default(), |_| {});
            // A shift beyond every stroke is an over travel before the move; angles and table
            // data of 1e20–1e30 make positions that are no numbers: the block alarms (it used
            // to "complete" in the run-time guard's 10⁶ s with every position null).
            let code = r.alarms.first().map(|a| a.code.as_str());
            assert!(!r.completed(), "{preset} {data:?} completed");
            // G54.4 has no check before movement: the stored stroke check stops the move.
            assert!(matches!(code, Some("OT0500" | "OT0501" | "PS0111")), "{preset} {data:?}: {:?}", r.alarms);
            assert!(r.alarms[0].line >= 4, "{preset} {data:?}: the data itself is accepted: {:?}", r.alarms);
        }
    }
}

// --- PS0438: the settings tool direction compensation needs (TV-WSE-19d/e) -----------------

/// head-bc with RCM = 1 read from FANUC parameters after `edit` changed them.
fn machine_from_fanuc(preset: &str, edit: impl FnOnce(&mut fivex_engine::vendor::Params)) -> MachineConfig {
    use fivex_engine::vendor::{machine_from, params_of};
    let mut m = MachineConfig::preset(preset).unwrap();
    m.five_axis.tool_direction_compensation = true;
    let mut p = params_of(Dialect::Fanuc, &m).unwrap();
    edit(&mut p);
    machine_from(Dialect::Fanuc, preset, &p).unwrap()
}

fn run_on(m: &MachineConfig, src: &str) -> Result<(), (String, u32)> {
    let mut interp = Interpreter::new(parse_file(src), Config::new(m.clone(), Dialect::Fanuc));
    for n in 1..=9 {
        interp.state.offsets.tool_mut(n).unwrap().h_geometry = 100.0;
    }
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
    interp.run(|_| {}).map_err(|a| (a.code, a.line))
}

#[test]
fn tv_wse_19d_look_ahead_must_be_on_when_g54_4_starts_with_rcm() {
    let start = "G90 G00 X0 Y0 Z100. B0 C0\nG54.4 P1\nG01 X10. F500.\nG54.4 P0\nM30\n";
    let q1 = "G05.1 Q1\nG90 G00 X0 Y0 Z100. B0 C0\nG54.4 P1\nG01 X10. F500.\nG54.4 P0\nG05.1 Q0\nM30\n";
    // SHP = 1 (fivex's default: absent No.1604): on from power-on.
    let shp1 = machine_from_fanuc("head-bc", |_| {});
    assert!(shp1.motion.look_ahead_set_up() && !shp1.motion.look_ahead_by_command);
    assert_eq!(run_on(&shp1, start), Ok(()));
    // SHP = 0: G54.4 P1 needs G05.1 Q1 first.
    let shp0 = machine_from_fanuc("head-bc", |p| p.set(1604, 0.0));
    assert!(shp0.motion.look_ahead_by_command);
    assert_eq!(run_on(&shp0, start), Err(("PS0438".into(), 2)));
    assert_eq!(run_on(&shp0, q1), Ok(()));
    // Switched off again before G54.4.
    let off_again = "G05.1 Q1\nG05.1 Q0\nG54.4 P1\n";
    assert_eq!(run_on(&shp0, off_again), Err(("PS0438".into(), 3)));
    assert_eq!(run_on(&shp1, "G05.1 Q0\nG54.4 P1\n"), Err(("PS0438".into(), 2)));
    // [A] and not inside: G05.1 Q0 while compensating.
    assert_eq!(run_on(&shp1, "G54.4 P1\nG05.1 Q0\n"), Err(("PS0438".into(), 2)));
    // Without RCM none of this matters.
    let mut plain = shp0.clone();
    plain.five_axis.tool_direction_compensation = false;
    assert_eq!(run_on(&plain, start), Ok(()));
    assert_eq!(run_on(&plain, "G54.4 P1\nG05.1 Q0\nG54.4 P0\nM30\n"), Ok(()));
    // A reset keeps G05.1 Q1 as it keeps the modal G codes (CLR = 0).
    let mut interp = Interpreter::new(parse_file("G05.1 Q1\nM30\n"), Config::new(shp0.clone(), Dialect::Fanuc));
    interp.run(|_| {}).unwrap();
    interp.reset();
    interp.load(parse_file("G54.4 P1\nG54.4 P0\nM30\n"));
    assert!(interp.run(|_| {}).is_ok());
}

#[test]
fn tv_wse_19d_lrp_frp_and_the_acceleration_parameters() {
    let src = "G05.1 Q1\nG54.4 P1\nG54.4 P0\nM30\n";
    type Edit = fn(&mut fivex_engine::vendor::Params);
    let edits: [(&str, Edit); 4] = [
        ("LRP = 0", |p| p.set(1401, 0.0)),
        ("FRP = 0", |p| p.set(19501, 0.0)),
        ("No.1671 all 0", |p| p.set_axes(1671, vec![0.0; 5])),
        ("No.1660 all 0", |p| p.set_axes(1660, vec![0.0; 5])),
    ];
    for (what, edit) in edits {
        let m = machine_from_fanuc("head-bc", edit);
        assert_eq!(run_on(&m, src), Err(("PS0438".into(), 2)), "{what}");
        let mut plain = m.clone();
        plain.five_axis.tool_direction_compensation = false;
        assert_eq!(run_on(&plain, src), Ok(()), "{what} without RCM");
    }
    // Set, they pass: FRP = 1, No.1671 on one axis, No.1660 on one axis.
    let m = machine_from_fanuc("head-bc", |p| {
        p.set(19501, 32.0);
        p.set_axes(1671, vec![0.0, 0.0, 1000.0, 0.0, 0.0]);
        p.set_axes(1660, vec![0.0, 0.0, 0.0, 0.0, 900.0]);
    });
    assert_eq!(run_on(&m, src), Ok(()));
}

#[test]
fn tv_wse_19e_tool_length_offset_in_g54_4_needs_tos_1() {
    let tos0 = machine_from_fanuc("head-bc", |p| p.set(5006, 0.0));
    assert!(tos0.five_axis.length_offset_by_motion);
    for (src, line) in [
        ("G54.4 P1\nG43 H1\n", 2),
        ("G54.4 P1\nG00 X0 Y0 Z100. B0 C0\nG43.4 H1\n", 3),
        ("G54.4 P1\nG01 G44 H1 Z10. F100.\n", 2),
        ("G54.4 P1\nG43.5 H1\n", 2),
    ] {
        assert_eq!(run_on(&tos0, src), Err(("PS0438".into(), line)), "{src}");
    }
    // TOS = 0 outside G54.4, and TOS = 1 (fivex's default) inside: accepted.
    assert_eq!(run_on(&tos0, "G43 H1 G01 Z10. F100.\nG49 G00 Z100.\nM30\n"), Ok(()));
    let tos1 = machine_from_fanuc("head-bc", |p| p.set(5006, 64.0));
    assert!(!tos1.five_axis.length_offset_by_motion);
    let inside = "G54.4 P1\nG00 X0 Y0 Z100. B0 C0\nG43.4 H1\nG01 Z50. F500.\nG49\nG54.4 P0\nM30\n";
    assert_eq!(run_on(&tos1, inside), Ok(()));
    // RCM = 0: G43 with TOS = 0 is refused too (WSE-24 is a general restriction).
    let mut plain = tos0.clone();
    plain.five_axis.tool_direction_compensation = false;
    assert_eq!(run_on(&plain, "G54.4 P1\nG43 H1\n"), Err(("PS0438".into(), 2)));
}

// --- No.11202 / No.11203: the compensating rotary motion's speed (WSE-24) -------------------

/// The highest C speed (deg/s) on `line`, sampled every millisecond.
fn top_c_speed(mut interp: Interpreter, line: u32) -> f64 {
    let mut last: Option<(f64, f64)> = None;
    let mut top: f64 = 0.0;
    let r = run(&mut interp, &RunOptions { period_s: 0.001, ..RunOptions::default() }, |s| {
        if s.line == line {
            if let Some((t, c)) = last {
                if s.t > t {
                    top = top.max((s.machine[4] - c).abs() / (s.t - t));
                }
            }
            last = Some((s.t, s.machine[4]));
        } else {
            last = None;
        }
    });
    assert!(r.completed(), "{:?}", r.alarms);
    top
}

#[test]
fn wse_24_no_11202_11203_clamp_the_compensating_rotary_motion() {
    // head-bc, RCM = 1, Δc 90°: from machine B30 C0 the start block makes the programmed C −90;
    // programmed C0 then needs machine C 90 — a quarter turn of compensation in a 10 mm move.
    let src = |g: &str| format!("G90 G00 X0 Y0 Z100. B30. C0\nG54.4 P1\n{g} X10. C0\nG54.4 P0\nM30\n");
    let interp = |g: &str, feed_pct: f64, rapid_pct: f64| {
        let mut interp = fanuc_with(&src(g), "head-bc", |c| {
            rcm(c);
            c.edit_machine(|m| {
                (m.five_axis.wse_feed_clamp_pct, m.five_axis.wse_rapid_clamp_pct) = (feed_pct, rapid_pct)
            });
        });
        interp.state.setting_errors.sets[1].rotation = [0.0, 0.0, 90.0];
        interp
    };
    let c_rate = 10_800.0 / 60.0;
    let end = end_of(&motion_ends(interp("G00", 0.0, 0.0)), 3);
    assert!((end[4] - 90.0).abs() < 1e-6, "C {}", end[4]);
    // No.11203 = 2 on a rapid, No.11202 = 1 on a cutting move (F far above what the axes
    // allow): C within that share of its rate, and near it (the clamp is what holds C back:
    // without it C turns faster, as fast as the carriage circling the C axis allows).
    for (g, feed_pct, rapid_pct, share) in [("G00", 50.0, 2.0, 0.02), ("G01 F100000.", 1.0, 50.0, 0.01)] {
        let free = top_c_speed(interp(g, 0.0, 0.0), 3);
        let top = top_c_speed(interp(g, feed_pct, rapid_pct), 3);
        assert!(top <= share * c_rate * (1.0 + 1e-6) && top > 0.9 * share * c_rate, "{g}: {top}");
        assert!(free > 1.5 * share * c_rate, "{g}: free {free}");
    }
    // Without G54.4 no clamp applies.
    let src = "G90 G00 X0 Y0 Z100. B30. C0\nG01 X10. C90. F100000.\nM30\n";
    let top = top_c_speed(fanuc_with(src, "head-bc", |c| c.edit_machine(|m| m.five_axis.wse_feed_clamp_pct = 1.0)), 2);
    assert!(top > 1.5 * 0.01 * c_rate, "{top}");
}

// --- WSE-19 / No.5412: canned-cycle rapids in G54.4 -----------------------------------------

/// The (kind, feed, feed mode, machine end) of every motion of line 3.
fn cycle_motions(src: &str, tweak: impl FnOnce(&mut Config)) -> Vec<(MotionKind, f64, FeedMode, [f64; 3])> {
    let mut interp = fanuc_with(src, "mill3", tweak);
    interp.state.setting_errors.sets[1].shift = [3.0, 4.0, 0.0];
    let mut v = Vec::new();
    interp
        .run(|c| {
            if let (3, CanonKind::Motion(m)) = (c.line, c.kind) {
                v.push((m.kind, m.feed, m.feed_mode, xyz(&m.machine)))
            }
        })
        .expect("no alarm");
    v
}

#[test]
fn wse_19_canned_cycle_rapids_run_at_no_5412_in_g54_4() {
    use MotionKind::{Linear, Rapid};
    let g81 = "G90 G00 X0 Y0 Z50.\nG54.4 P1\nG98 G81 X10. Y5. Z-5. R2. F200.\nG80\nG54.4 P0\nM30\n";
    let ends = [[13.0, 9.0, 50.0], [13.0, 9.0, 2.0], [13.0, 9.0, -5.0], [13.0, 9.0, 50.0]];
    let with = |cycle_feed: f64, dry_run: f64| {
        move |c: &mut Config| {
            c.edit_machine(|m| m.five_axis.wse_cycle_feed = cycle_feed);
            c.edit_machine(|m| m.manual.dry_run_feed = dry_run);
        }
    };
    let pm = FeedMode::PerMinute;
    // No.5412 = 3000: positioning, to R and the return run at 3000 mm/min; the hole at F.
    let got = cycle_motions(g81, with(3000.0, 1500.0));
    let kinds: Vec<_> = got.iter().map(|m| (m.0, m.1, m.2)).collect();
    assert_eq!(kinds, [(Linear, 3000.0, pm), (Linear, 3000.0, pm), (Linear, 200.0, pm), (Linear, 3000.0, pm)]);
    for (m, end) in got.iter().zip(ends) {
        assert!(close3(m.3, end, 1e-9), "{:?} vs {end:?}", m.3);
    }
    // No.5412 = 0: the dry run rate No.1410.
    let got = cycle_motions(g81, with(0.0, 1500.0));
    assert!(got.iter().enumerate().all(|(k, m)| m.0 == Linear && m.1 == if k == 2 { 200.0 } else { 1500.0 }));
    // Both 0: rapids stay rapids; and outside G54.4 No.5412 does nothing.
    let got = cycle_motions(g81, with(0.0, 0.0));
    assert_eq!(got.iter().map(|m| m.0).collect::<Vec<_>>(), [Rapid, Rapid, Linear, Rapid]);
    let outside = "G90 G00 X0 Y0 Z50.\nG04 P0\nG98 G81 X10. Y5. Z-5. R2. F200.\nG80\nM30\n";
    let got = cycle_motions(outside, with(3000.0, 1500.0));
    assert_eq!(got.iter().map(|m| m.0).collect::<Vec<_>>(), [Rapid, Rapid, Linear, Rapid]);
    // In G95 the hole is fed per revolution, the former rapids still per minute.
    let g95 = "G95 G90 G00 X0 Y0 Z50. S1000 M03\nG54.4 P1\nG99 G81 X10. Y5. Z-5. R2. F0.1\nG80\nG54.4 P0\nM30\n";
    let got = cycle_motions(g95, with(3000.0, 0.0));
    let kinds: Vec<_> = got.iter().map(|m| (m.0, m.1, m.2)).collect();
    let rev = FeedMode::PerRevolution;
    assert_eq!(kinds, [(Linear, 3000.0, pm), (Linear, 3000.0, pm), (Linear, 0.1, rev), (Linear, 3000.0, pm)]);
}

// --- WSE-25: manual intervention on a table or mixed machine with RCM = 1 --------------------

/// AUTO run of Example-1-like moves on `preset`, held in the first cutting move (line 3).
fn held_in_g54_4(preset: &str, rcm_on: bool) -> fivex_engine::controller::Controller {
    use fivex_engine::controller::{Controller, Mode, RunState};
    let mut cfg = Config::new(MachineConfig::preset(preset).unwrap(), Dialect::Fanuc);
    cfg.edit_machine(|m| m.five_axis.tool_direction_compensation = rcm_on);
    let mut c = Controller::new(cfg);
    c.interpreter_mut().state.setting_errors.sets[1].shift = [3.0, 4.0, 0.0];
    c.set_mode(Mode::Auto).unwrap();
    let names: String = c.interpreter().config().machine.rotary.iter().map(|l| format!(" {}0", l.axis)).collect();
    let src = format!("G90 G00 X0 Y0 Z100.{names}\nG54.4 P1\nG01 X100. F600.\nY50.\nG54.4 P0\nM30\n");
    c.select_program(&src).unwrap();
    c.cycle_start().unwrap();
    while c.point().line != 3 && c.time() < 60.0 {
        c.tick(0.01);
    }
    for _ in 0..100 {
        c.tick(0.01);
    }
    c.feed_hold();
    for _ in 0..300 {
        c.tick(0.01);
    }
    assert_eq!(c.run_state(), RunState::Hold, "{:?}", c.alarms());
    c
}

#[test]
fn wse_25_manual_intervention_with_rcm_on_a_table_machine_raises_ps0439() {
    use fivex_engine::controller::{Mode, RunState};
    use fivex_engine::kin::ManualFeed;
    type Action = fn(&mut fivex_engine::controller::Controller) -> Result<(), fivex_engine::controller::Refusal>;
    let actions: [(Mode, Action); 4] = [
        (Mode::Handle, |c| c.handle('X', 1.0)),
        (Mode::Jog, |c| c.jog_start('C', true)),
        (Mode::Handle, |c| c.handle_direction(ManualFeed::ToolAxis, 1.0)),
        (Mode::Handle, |c| c.handle_tip_rotation('C', 5.0)),
    ];
    for preset in ["table-ac", "mixed-bc"] {
        for (k, (mode, act)) in actions.iter().enumerate() {
            let mut c = held_in_g54_4(preset, true);
            let before = c.point().machine;
            c.set_mode(*mode).unwrap();
            assert_eq!(act(&mut c), Ok(()), "{preset} action {k}");
            assert_eq!(c.run_state(), RunState::Alarm, "{preset} action {k}");
            let a = &c.alarms()[0];
            assert_eq!((a.code.as_str(), a.line), ("PS0439", 3), "{preset} action {k}: {a:?}");
            for _ in 0..50 {
                c.tick(0.01);
            }
            assert_eq!(c.point().machine, before, "{preset} action {k}: nothing moves");
        }
    }
    // A head machine with RCM = 1, or a table machine without it: the intervention moves.
    for (preset, rcm_on) in [("head-bc", true), ("table-ac", false)] {
        let mut c = held_in_g54_4(preset, rcm_on);
        let before = c.point().machine;
        c.set_mode(Mode::Handle).unwrap();
        c.handle('X', 1.0).unwrap();
        for _ in 0..200 {
            c.tick(0.01);
        }
        assert!(c.alarms().is_empty(), "{preset}: {:?}", c.alarms());
        assert!((c.point().machine[0] - before[0] - 1.0).abs() < 1e-9, "{preset}");
    }
}

// --- WSE-18 / DAK (No.3106#6): the absolute position in the WCS or the WSCS -----------------

type ByLine = std::collections::BTreeMap<u32, [f64; 3]>;

/// The last sampled programmed point (what the display shows) and tip (from the axes, in the
/// WCS) of every line, and the run's final workpiece position.
fn shown_tips(mut interp: Interpreter) -> (ByLine, ByLine, Pos) {
    let (mut shown, mut tips) = (ByLine::new(), ByLine::new());
    let r = run(&mut interp, &RunOptions { period_s: 0.005, ..RunOptions::default() }, |s| {
        shown.insert(s.line, s.programmed);
        tips.insert(s.line, s.tip);
    });
    assert!(r.completed(), "{:?}", r.alarms);
    (shown, tips, r.workpiece)
}

#[test]
fn wse_18_dak_shows_the_absolute_position_in_the_wcs() {
    // Example 1 on head-bc, ending inside G54.4 after N60: DAK = 0 shows the WSCS (the
    // programmed points), DAK = 1 the WCS (TV-WSE-17's numbers).
    let src = "N10 G55\nN15 G54.4 P1\nN20 G90 G00 X0 Y0 Z300.0 B0 C0\nN30 G01 G43 H01 Z40.0 F500.\n\
               N40 X50.0 Y50.0 Z20.0\nN50 X150.0\nN60 Y150.0\nM30\n";
    let interp = |dak: bool, rcm_on: bool| {
        let mut i = fanuc_with(src, "head-bc", |c| {
            c.edit_machine(|m| m.five_axis.wse_display_wcs = dak);
            c.edit_machine(|m| m.five_axis.tool_direction_compensation = rcm_on);
        });
        i.state.offsets.work_mut(2)[..3].copy_from_slice(&[100.0, 50.0, -400.0]);
        i.state.setting_errors.sets[1] =
            wse::ErrorSet { shift: [10.0, 20.0, 0.0], rotation: [0.0, 0.0, -20.0], table: [0.0; 2] };
        i
    };
    let wscs = [(5, [50.0, 50.0, 20.0]), (6, [150.0, 50.0, 20.0]), (7, [150.0, 150.0, 20.0])];
    let wcs =
        [(5, [74.085638, 49.883624, 20.0]), (6, [168.054900, 15.681610, 20.0]), (7, [202.256915, 109.650872, 20.0])];
    // Plain moves (RCM = 0) and tip paths (RCM = 1) alike.
    for rcm_on in [false, true] {
        for (dak, want) in [(false, wscs), (true, wcs)] {
            let (shown, tips, end) = shown_tips(interp(dak, rcm_on));
            // The last sample of a line is within a period (0.04 mm at F500) of its end; the
            // tip, read from the axes, is in the WCS whatever the display shows.
            for ((line, p), (_, real)) in want.into_iter().zip(wcs) {
                assert!(close3(shown[&line], p, 0.1), "DAK {dak} RCM {rcm_on} line {line}: {:?}", shown[&line]);
                assert!(close3(tips[&line], real, 0.1), "DAK {dak} RCM {rcm_on} line {line}: tip {:?}", tips[&line]);
            }
            assert!(close3(xyz(&end), want[2].1, 1e-6), "DAK {dak} RCM {rcm_on}: end {end:?}");
        }
    }
    // The controller's position display the same way, at rest after the program.
    for (dak, want) in [(false, wscs[2].1), (true, wcs[2].1)] {
        use fivex_engine::controller::{Controller, Mode, RunState};
        let i = interp(dak, true);
        let mut c = Controller::new(i.config().clone());
        c.interpreter_mut().state.offsets = i.state.offsets.clone();
        c.interpreter_mut().state.setting_errors = i.state.setting_errors;
        c.set_mode(Mode::Auto).unwrap();
        c.select_program(src).unwrap();
        c.cycle_start().unwrap();
        while c.run_state() == RunState::Running && c.time() < 300.0 {
            c.tick(0.05);
        }
        assert!(close3(xyz(&c.point().work), want, 1e-6), "DAK {dak}: {:?}", c.point().work);
    }
    // Every sample of N50 with DAK = 1 lies on the displaced side in the WCS.
    let mut i = interp(true, false);
    let (sn, cs) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
    let r = run(&mut i, &RunOptions { period_s: 0.01, ..RunOptions::default() }, |s| {
        if s.line == 6 {
            let p = [s.tip[0] - 10.0, s.tip[1] - 20.0];
            assert!((sn * p[0] + cs * p[1] - 50.0).abs() < 1e-6, "{:?}", s.tip);
        }
    });
    assert!(r.completed());
    // The FANUC bit.
    let mut m = MachineConfig::preset("head-bc").unwrap();
    m.five_axis.wse_display_wcs = true;
    let p = fivex_engine::vendor::params_of(Dialect::Fanuc, &m).unwrap();
    assert!(p.bit(3106, 6).unwrap());
}

/// TV-65 (fanuc-tcp.md TCP-14): TCP refuses the same look-ahead settings with PS5420.
#[test]
fn tv_65_tcp_refuses_missing_look_ahead_with_ps5420() {
    let tcp = "G43.4 H1\nG49\nM30\n";
    type Edit = fn(&mut fivex_engine::vendor::Params);
    let edits: [Edit; 3] =
        [|p| p.set(19501, 0.0), |p| p.set_axes(1671, vec![0.0; 5]), |p| p.set_axes(1660, vec![0.0; 5])];
    for edit in edits {
        let m = machine_from_fanuc("head-bc", edit);
        assert_eq!(run_on(&m, tcp), Err(("PS5420".into(), 1)));
    }
    // SHP = 0 without G05.1 Q1: TCP-14 names the option, not the mode.
    assert_eq!(run_on(&machine_from_fanuc("head-bc", |p| p.set(1604, 0.0)), tcp), Ok(()));
}

// --- §2.13.5: the compensation recomputed all along a block ---------------------------------

#[test]
fn compensation_holds_the_tool_direction_at_every_sample_of_a_block() {
    use fivex_engine::kin::{Kinematics, Vec3};
    // RCM = 1, Δa 3°, Δb −2° (not about the workpiece-side C axis: proportional rotary motion
    // between exact end points would leave the programmed direction inside the block). The
    // first rotary axis (B of head-bc, A of table-ac) is index 3, C index 4.
    for (preset, first_axis) in [("head-bc", 'B'), ("table-ac", 'A')] {
        let src = format!(
            "G90 G00 X0 Y0 Z100. {first_axis}30. C0\nG54.4 P1\n#100=#5004\n#101=#5005\nG43 H1 Z100.\n\
             G01 X20. {first_axis}45. C60. F1000.\nG49\nG54.4 P0\nM30\n"
        );
        let mut interp = fanuc_with(&src, preset, rcm);
        interp.state.setting_errors.sets[1].rotation = [3.0, -2.0, 0.0];
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let re = wse::rotation([3.0, -2.0, 0.0]);
        let mut samples = Vec::new();
        let mut start = ([0.0; 3], [0.0; fivex_engine::machine::MAX_AXES]);
        let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
            if s.line == 5 {
                start = (s.programmed, s.machine);
            }
            if s.line == 6 {
                samples.push((s.programmed, s.machine));
            }
        });
        assert!(r.completed() && r.notices.is_empty(), "{preset}: {:?} {:?}", r.alarms, r.notices);
        let vars = r.variables.clone();
        let v = |n| vars.iter().find(|(k, _)| *k == n).unwrap().1;
        let (a0, c0) = (v(100), v(101));
        // The block starts where line 5 ended (its first sample may be a period in).
        let (x0, first, last) = (start.0[0], start.1, samples.last().unwrap().1);
        let direction = |a: f64, c: f64| {
            let mut q = [0.0; fivex_engine::machine::MAX_AXES];
            (q[3], q[4]) = (a, c);
            kin.forward(&q, 0.0).tool
        };
        let angle = |a: Vec3, b: Vec3| a.dot(&b).clamp(-1.0, 1.0).acos();
        let (mut worst, mut proportional) = (0.0f64, 0.0f64);
        for (tip, m) in &samples {
            let u = (tip[0] - x0) / (20.0 - x0);
            let want = re * direction(a0 + u * (45.0 - a0), c0 + u * (60.0 - c0));
            worst = worst.max(angle(kin.forward(m, 0.0).tool, want));
            // What turning the axes in proportion between the end points would give.
            let lerp = |k: usize| first[k] + u * (last[k] - first[k]);
            proportional = proportional.max(angle(direction(lerp(3), lerp(4)), want));
        }
        assert!(samples.len() > 50, "{preset}");
        // 1 µrad: the block now runs at its real speed, so the samples are sparser and `u`,
        // read back from the tip's X, carries the start sample's rounding (1.7e-7 rad seen);
        // still 100 times finer than the proportional rule's error asserted below.
        assert!(worst < 1e-6, "{preset}: the tool leaves the compensated direction by {worst} rad");
        assert!(proportional > 1e-4, "{preset}: the block does not tell the two apart: {proportional}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: common::cases(6), ..proptest::prelude::ProptestConfig::default() })]

    /// RCM = 1 on every 5-axis machine kind, any small error: the compensated block (its axes
    /// turned to the compensated direction along the way or in proportion) keeps the tip on the
    /// programmed line relative to the displaced workpiece at every 1 ms sample, and every axis
    /// within its speed, acceleration and jerk.
    #[test]
    fn compensated_blocks_keep_the_tip_on_the_line_within_the_axis_limits(
        rot in proptest::array::uniform3(-4.0f64..4.0),
        p in proptest::array::uniform3(-40.0f64..40.0),
        angles in proptest::array::uniform2(20.0f64..60.0),
        start in proptest::array::uniform2(20.0f64..60.0),
    ) {
        use fivex_engine::kin::Kinematics;
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
            let names: Vec<char> = kin.joints().iter().map(|j| j.name).collect();
            let src = format!(
                "G90 G00 X0 Y0 Z100. {a}{:.3} {b}{:.3}\nG54.4 P1\nG43 H1\nG01 X{:.3} Y{:.3} Z{:.3} {a}{:.3} {b}{:.3} F3000.\nG49\nM30\n",
                start[0], start[1], p[0], p[1], p[2], angles[0], angles[1], a = names[0], b = names[1]
            );
            let mut interp = fanuc_with(&src, preset, rcm);
            interp.state.setting_errors.sets[1] = wse::ErrorSet { shift: [1.0, -2.0, 0.5], rotation: rot, table: [0.0; 2] };
            let mut samples = Vec::new();
            let r = run(&mut interp, &RunOptions { period_s: 0.001, ..RunOptions::default() }, |s| samples.push(*s));
            proptest::prop_assert!(r.completed(), "{preset}: {:?}", r.alarms);
            // The tip where the axes put it (table frame, the work offsets 0), in the WSCS.
            let e = wse::frame([1.0, -2.0, 0.5], rot);
            let tip = |m: &Pos| -> [f64; 3] { e.from_parent(&(kin.forward(m, 100.0).tip - kin.nose)).into() };
            let line: Vec<_> = samples.iter().filter(|s| s.line == 4).map(|s| tip(&s.machine)).collect();
            let target = [p[0], p[1], p[2]].map(|x| (x * 1e3).round() / 1e3);
            let from = line[0];
            let d: [f64; 3] = std::array::from_fn(|k| target[k] - from[k]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            // The last sample is within a period (0.05 mm at F3000) of the end.
            proptest::prop_assert!(close3(*line.last().unwrap(), target, 0.06), "{preset}: ends at {:?}", line.last());
            for t in &line {
                let w: [f64; 3] = std::array::from_fn(|k| t[k] - from[k]);
                let along = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / len;
                let off: f64 = (0..3).map(|k| (w[k] - along * d[k] / len).powi(2)).sum::<f64>().sqrt();
                proptest::prop_assert!(off < 1e-6, "{preset}: tip {t:?} {off} off the line");
            }
            common::check_limits(&samples, preset, false)?;
        }
    }
}

// --- a tilted working plane inside G54.4 with tool direction compensation --------------------

/// The common variables (#100…) a program set, by number.
fn variable(interp: &Interpreter, n: u32) -> f64 {
    interp.state.common_variables().into_iter().find(|(k, _)| *k == n).expect("set").1
}

#[test]
fn g53_1_in_g54_4_with_rcm_aims_the_tool_along_the_displaced_fcs_z() {
    use fivex_engine::kin::Kinematics;
    // Example 2's error (Δc −20°, Δ (10, 20, 0)) on head-bc, G55 (100, 50, −400). The FCS
    // (Euler I0 J45 K0, origin (50, 50, 20) in the WSCS) has its +Z along Rx(45°)·Z =
    // (0, −0.707107, 0.707107) seen from the ideal workpiece: programmed angles B45 C−90 (or
    // B−45 C90). The compensation turns them about the workpiece-side C by Δc: the tool along
    // Rz(−20°)·(0, −0.707107, 0.707107) = (−0.241845, −0.664463, 0.707107), Example 2's N40
    // direction, at B45 C−110 (B−45 C70). #5004/#5005 show the programmed angles.
    let src = "N1 G05.1 Q1\nN2 G55\nN3 G54.4 P1\nN4 G90 G00 X0 Y0 Z300. B0 C-30.\n\
               N5 G68.2 X50. Y50. Z20. I0 J45. K0\nN6 G53.1\nN7 #100=#5004\n#101=#5005\n\
               N9 G43 H1\nN10 G01 X0 Y0 Z0 F500.\nN11 X30.\nN12 X30. C-80.\n#102=#5005\n#103=#5004\n\
               N14 G49\nN15 G69\nN16 G54.4 P0\nM30\n";
    let mut interp = example_2(src, rcm);
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let mut ends = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                ends.push((c.line, m.machine))
            }
        })
        .expect("no alarm");
    let g53_1 = end_of(&ends, 6);
    let (b, c) = (g53_1[3], g53_1[4]);
    let (pb, pc) = (variable(&interp, 100), variable(&interp, 101));
    // From C−30 FANUC's cascade takes B45 C−90 (C moves 60°, not 120°) → machine B45 C−110.
    assert!((b - 45.0).abs() < 1e-9 && (c + 110.0).abs() < 1e-9, "machine B{b} C{c}");
    // (C rolls over: its programmed coordinate is shown within 0…360.)
    let same = |a: f64, b: f64| ((a - b).rem_euclid(360.0) + 1e-9) % 360.0 < 2e-9;
    assert!(same(pb, 45.0) && same(pc, -90.0), "programmed B{pb} C{pc}");
    // X/Y/Z stay in the G53.1 block.
    assert!(close3(xyz(&g53_1), xyz(&end_of(&ends, 4)), 1e-9));
    let tool = kin.forward(&g53_1, 0.0).tool;
    assert!(close3(tool.into(), [-0.241845, -0.664463, 0.707107], 1e-6), "tool {tool:?}");
    // The FCS origin is the WSCS point (50, 50, 20): the tip at Example 1's N40 point.
    let tip_at = |line: u32| {
        let pose = kin.forward(&end_of(&ends, line), 100.0);
        [pose.tip[0] - 100.0 - kin.nose[0], pose.tip[1] - 50.0 - kin.nose[1], pose.tip[2] + 400.0 - kin.nose[2]]
    };
    assert!(close3(tip_at(10), [74.085638, 49.883624, 20.0], 1e-6), "{:?}", tip_at(10));
    // X30 in the FCS: along the FCS X, which is the WSCS X (Euler J about X keeps it), turned
    // by Δc: 30·(cos −20°, sin −20°, 0) = (28.190779, −10.260604, 0) further.
    let along = [102.276417, 39.623020, 20.0];
    assert!(close3(tip_at(11), along, 1e-5), "{:?}", tip_at(11));
    assert!((end_of(&ends, 11)[4] - c).abs() < 1e-9, "X/Y/Z moves keep the rotary axes");
    // A rotary word in the plane is a programmed angle too: C−80 (from C−90) → machine C−100;
    // the tip stays.
    let n12 = end_of(&ends, 12);
    assert!((n12[4] + 100.0).abs() < 1e-9 && (n12[3] - 45.0).abs() < 1e-9, "B {} C {}", n12[3], n12[4]);
    assert!(same(variable(&interp, 102), -80.0) && same(variable(&interp, 103), 45.0));
    assert!(close3(tip_at(12), along, 1e-6), "{:?}", tip_at(12));
}

#[test]
fn g69_in_g54_4_with_rcm_gives_back_the_programmed_angles() {
    // After G69 the current point is the tip in the WSCS and #5005 the programmed C, so a
    // following move is compensated once, not twice.
    let src = "N1 G05.1 Q1\nN2 G55\nN3 G54.4 P1\nN4 G90 G00 X0 Y0 Z300. B0 C0\n\
               N5 G68.2 X0 Y0 Z0 I0 J45. K0\nN6 G53.1\nN7 G69\n#100=#5004\n#101=#5005\n\
               N10 G01 X10. F500.\nN11 G54.4 P0\nM30\n";
    let mut interp = example_2(src, rcm);
    let mut ends = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                ends.push((c.line, m.machine))
            }
        })
        .expect("no alarm");
    let (n6, n10) = (end_of(&ends, 6), end_of(&ends, 10));
    assert!((variable(&interp, 101) - (n6[4] + 20.0)).abs() < 1e-9, "#5005 {}", variable(&interp, 101));
    assert!((n10[3] - n6[3]).abs() < 1e-9 && (n10[4] - n6[4]).abs() < 1e-9, "{n6:?} → {n10:?}");
}

#[test]
fn plane_moves_in_g54_4_hold_the_compensated_direction_at_every_sample() {
    use fivex_engine::kin::{Kinematics, Vec3};
    // As `compensation_holds_the_tool_direction_at_every_sample_of_a_block`, the block inside a
    // tilted plane (identity FCS shifted by (5, 0, 0), so programmed angles read alike).
    for (preset, first_axis) in [("head-bc", 'B'), ("table-ac", 'A')] {
        let src = format!(
            "G90 G00 X0 Y0 Z100. {first_axis}0 C0\nG54.4 P1\nG00 {first_axis}0 C0\nG68.2 X5. Y0 Z0 I0 J0 K0\n\
             G00 {first_axis}30. C0\n#100=#5004\n#101=#5005\nG43 H1\n\
             G01 X15. Y0 Z50. {first_axis}45. C60. F1000.\nG49\nG69\nG54.4 P0\nM30\n"
        );
        let mut interp = fanuc_with(&src, preset, rcm);
        interp.state.setting_errors.sets[1].rotation = [3.0, -2.0, 0.0];
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let e = wse::frame([0.0; 3], [3.0, -2.0, 0.0]);
        let mut samples = Vec::new();
        let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
            if s.line == 9 {
                samples.push(s.machine);
            }
        });
        assert!(r.completed(), "{preset}: {:?}", r.alarms);
        let v = |n| r.variables.iter().find(|(k, _)| *k == n).unwrap().1;
        let (a0, c0) = (v(100), v(101));
        assert!((a0 - 30.0).abs() < 1e-9 && c0.abs() < 1e-9, "{preset}: programmed {a0} {c0}");
        let direction = |a: f64, c: f64| {
            let mut q = [0.0; fivex_engine::machine::MAX_AXES];
            (q[3], q[4]) = (a, c);
            kin.forward(&q, 0.0).tool
        };
        let angle = |a: Vec3, b: Vec3| a.dot(&b).clamp(-1.0, 1.0).acos();
        // The tip in the FCS (work offsets 0; the FCS is the WSCS shifted by X5).
        let tip = |m: &Pos| e.from_parent(&(kin.forward(m, 100.0).tip - kin.nose)) - Vec3::new(5.0, 0.0, 0.0);
        let (start, end) = (tip(&samples[0]), Vec3::new(15.0, 0.0, 50.0));
        let mut worst = 0.0f64;
        for m in &samples {
            let t = tip(m);
            let u = ((t - start).dot(&(end - start)) / (end - start).norm_squared()).clamp(0.0, 1.0);
            let off_line = (t - start - u * (end - start)).norm();
            assert!(off_line < 1e-6, "{preset}: tip {t:?} {off_line} off the FCS line");
            let want = e.r * direction(a0 + u * (45.0 - a0), c0 + u * (60.0 - c0));
            worst = worst.max(angle(kin.forward(m, 0.0).tool, want));
        }
        assert!(samples.len() > 50, "{preset}");
        // 1 µrad: the block now runs at its real speed, so the samples are sparser and `u`,
        // read back from the tip's X, carries the start sample's rounding (1.7e-7 rad seen);
        // still 100 times finer than the proportional rule's error asserted below.
        assert!(worst < 1e-6, "{preset}: the tool leaves the compensated direction by {worst} rad");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: common::cases(12), ..proptest::prelude::ProptestConfig::default() })]

    /// RCM = 1 on every 5-axis machine kind, any small error and any plane: after G53.1 and a
    /// move in the FCS the tip is at `E(F(p))` and the tool, relative to the workpiece, along
    /// `R_e·F·Z` (the FCS +Z of the displaced workpiece) at the block ends and at every 1 ms
    /// sample of the move, every axis within its limits.
    #[test]
    fn g53_1_and_plane_moves_follow_the_displaced_fcs(
        rot in proptest::array::uniform3(-3.0f64..3.0),
        shift in proptest::array::uniform3(-10.0f64..10.0),
        euler in proptest::array::uniform3(-40.0f64..40.0),
        p in proptest::array::uniform3(-30.0f64..30.0),
    ) {
        use fivex_engine::kin::{Kinematics, Vec3};
        let euler = euler.map(|x| (x * 1e3).round() / 1e3);
        let p = p.map(|x| (x * 1e3).round() / 1e3);
        // Tilt J at least 10° away from the singular posture (the tool along Z).
        let j = if euler[1].abs() < 10.0 { euler[1].signum() * 10.0 + euler[1] } else { euler[1] };
        let mut checked = Vec::new();
        for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
            let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
            let names: Vec<char> = kin.joints().iter().map(|j| j.name).collect();
            let src = format!(
                "G90 G00 X0 Y0 Z100. {a}0 {b}0\nG54.4 P1\nG00 {a}0 {b}0\nG68.2 X1. Y2. Z3. I{:.3} J{:.3} K{:.3}\nG53.1\nG43 H1\n\
                 G01 X{:.3} Y{:.3} Z{:.3} F3000.\nG49\nG69\nG54.4 P0\nM30\n",
                euler[0], j, euler[2], p[0], p[1], p[2], a = names[0], b = names[1]
            );
            let mut interp = fanuc_with(&src, preset, rcm);
            interp.state.setting_errors.sets[1] = wse::ErrorSet { shift, rotation: rot, table: [0.0; 2] };
            let mut samples = Vec::new();
            let r = run(&mut interp, &RunOptions { period_s: 0.001, ..RunOptions::default() }, |s| samples.push(*s));
            // A plane the rotary strokes cannot reach stops at the stroke (G54.4: OT0500/OT0501).
            if r.alarms.iter().any(|a| a.code == "OT0500" || a.code == "OT0501") {
                continue;
            }
            proptest::prop_assert!(r.completed(), "{preset}: {:?}", r.alarms);
            let e = wse::frame(shift, rot);
            let f = fivex_engine::twp::euler(Vec3::new(1.0, 2.0, 3.0), euler[0], j, euler[2]);
            let want_tool = e.r * f.r * Vec3::z();
            let on_table = |m: &Pos| kin.forward(m, 100.0);
            let moves: Vec<_> = samples.iter().filter(|s| s.line == 7).collect();
            proptest::prop_assert!(!moves.is_empty());
            let want_end = e.to_parent(&f.to_parent(&p.into())) + kin.nose;
            let last = on_table(&moves.last().unwrap().machine);
            proptest::prop_assert!((last.tip - want_end).norm() < 0.06, "{preset}: ends at {:?} vs {:?}", last.tip, want_end);
            let from = on_table(&moves[0].machine).tip;
            let d = want_end - from;
            for s in &moves {
                let pose = on_table(&s.machine);
                proptest::prop_assert!((pose.tool - want_tool).norm() < 1e-9, "{preset}: tool {:?} vs {:?}", pose.tool, want_tool);
                let w = pose.tip - from;
                let off = (w - d * (w.dot(&d) / d.norm_squared())).norm();
                proptest::prop_assert!(off < 1e-6, "{preset}: tip {off} off the line");
            }
            common::check_limits(&samples, preset, false)?;
            checked.push(preset);
        }
        // The head machine's B (±110°) reaches every plane tilted by at most 50°: never skipped.
        proptest::prop_assert!(checked.contains(&"head-bc"), "only {checked:?} reached the plane");
    }
}

// --- WSE-25: a hypothetical table axis is at 0° in the compensation --------------------------

#[test]
fn wse_25_a_hypothetical_table_axis_counts_0_in_the_compensation() {
    use fivex_engine::kin::{Kinematics, Vec3};
    // table-ac with A hypothetical at 20°: a C table tilted 20° about X (FANUC No.19685 = 20,
    // IA1 = 1). Taken at 0° the C line is along Z and so is the tool: the tool is always in the
    // singular posture, so a Δc error leaves C where the program puts it (§2.14 rule 1-(2)) and
    // only X/Y/Z take the error. At its 20° the tool would be 20° off the C line, and the
    // error's turn (about the WCS Z, not the C line) could not be met by C: the G01 would find
    // no angles (DS0030).
    let mut m = MachineConfig::preset("table-ac").unwrap();
    m.axes.retain(|a| a.name != 'A');
    m.rotary.iter_mut().find(|l| l.axis == 'A').unwrap().fixed = Some(20.0);
    let kin = Kinematics::new(&m).unwrap();
    let c = m.axis_index(b'C').unwrap();
    let src = "G90 G00 X0 Y0 Z100. C0\nG54.4 P1\nG43 H1\nG01 X10. Y5. Z20. C30. F1000.\nG49\nG54.4 P0\nM30\n";
    let mut interp = fanuc_with(src, "table-ac", |c| {
        c.machine = m.clone().into();
        rcm(c);
    });
    interp.state.setting_errors.sets[1] =
        wse::ErrorSet { shift: [1.0, 2.0, 0.0], rotation: [0.0, 0.0, 5.0], table: [0.0; 2] };
    let ends = motion_ends(interp);
    let end = end_of(&ends, 4);
    assert!((end[c] - 30.0).abs() < 1e-9, "C {}", end[c]);
    // The tip on the table (placed as every move places it: the table at its 20°).
    let want = wse::frame([1.0, 2.0, 0.0], [0.0, 0.0, 5.0]).to_parent(&Vec3::new(10.0, 5.0, 20.0));
    let mut zero = [0.0; fivex_engine::machine::MAX_AXES];
    zero[c] = 0.0;
    let tf = kin.table_frame(&zero);
    let want = tf.r.transpose() * (want + kin.nose - tf.o);
    let got = kin.forward(&end, 100.0).tip;
    assert!((got - want).norm() < 1e-6, "tip {got:?} vs {want:?}");
    // With the fixed angle at 0 in the machine itself the same block ends alike on C.
    let mut flat = m.clone();
    flat.rotary.iter_mut().find(|l| l.axis == 'A').unwrap().fixed = Some(0.0);
    let mut interp = fanuc_with(src, "table-ac", |c| {
        c.machine = flat.into();
        rcm(c);
    });
    interp.state.setting_errors.sets[1].rotation = [0.0, 0.0, 5.0];
    assert!((end_of(&motion_ends(interp), 4)[c] - 30.0).abs() < 1e-9);
}

#[test]
fn wse_25_a_hypothetical_table_slave_at_an_angle_compensates_as_at_0() {
    use fivex_engine::kin::Kinematics;
    // mixed-bc with its table C hypothetical at 30°: the only table axis, so the frames at 0°
    // and at 30° differ by one fixed turn and the compensated tool direction is the same
    // either way: relative to the workpiece, R_e times the programmed direction (machine
    // directions, as the table does not move).
    let mut m = MachineConfig::preset("mixed-bc").unwrap();
    m.axes.retain(|a| a.name != 'C');
    m.rotary.iter_mut().find(|l| l.axis == 'C').unwrap().fixed = Some(30.0);
    let kin = Kinematics::new(&m).unwrap();
    let b = m.axis_index(b'B').unwrap();
    let src = "G90 G00 X0 Y0 Z100. B10.\nG54.4 P1\nG43 H1\nG01 X10. B40. F1000.\nG49\nG54.4 P0\nM30\n";
    let mut interp = fanuc_with(src, "mixed-bc", |c| {
        c.machine = m.into();
        rcm(c);
    });
    let rot = [0.0, 3.0, 0.0];
    interp.state.setting_errors.sets[1].rotation = rot;
    let end = end_of(&motion_ends(interp), 4);
    let mut programmed = [0.0; fivex_engine::machine::MAX_AXES];
    programmed[b] = 40.0;
    let machine_dir = |p: &Pos| {
        let pose = kin.forward(p, 0.0);
        kin.table_frame(p).r * pose.tool
    };
    let want = wse::rotation(rot) * machine_dir(&programmed);
    assert!((machine_dir(&end) - want).norm() < 1e-9, "{:?} vs {want:?}", machine_dir(&end));
    assert!((end[b] - 43.0).abs() < 1e-9, "B {}", end[b]);
}

#[test]
fn leaving_the_exact_singular_posture_keeps_the_axis_limits() {
    // B0 C0 is the singular posture; Δa/Δb tilt the direction the compensation needs, so at
    // the first bit of the move the workpiece-side C would have to stand at the new direction's
    // azimuth at once (2.54° here). The block turns its axes in proportion between the exact
    // end points instead, within every axis limit; the end points keep the rules (rule 3: C
    // moves the shorter way, −2.54°).
    use fivex_engine::kin::Kinematics;
    let rotation = [0.0, -1.5865938540159266, -2.5368967295580447];
    for preset in ["head-bc", "table-bc", "mixed-bc"] {
        let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
        let names: Vec<char> = kin.joints().iter().map(|j| j.name).collect();
        let src = format!("G90 G00 X0 Y0 Z100. {a}0 {b}0\nG54.4 P1\nG00 {a}0 {b}0\nM30\n", a = names[0], b = names[1]);
        let mut interp = fanuc_with(&src, preset, rcm);
        interp.state.setting_errors.sets[1] = wse::ErrorSet { shift: [0.0; 3], rotation, table: [0.0; 2] };
        let mut samples = Vec::new();
        let r = run(&mut interp, &RunOptions { period_s: 0.001, ..RunOptions::default() }, |s| samples.push(*s));
        assert!(r.completed(), "{preset}: {:?}", r.alarms);
        // fivex's own rule, so the run tells it.
        let noticed: Vec<(&str, u32)> = r.notices.iter().map(|n| (n.code.as_str(), n.line)).collect();
        assert_eq!(noticed, [("FX1003", 3)], "{preset}");
        // Where the block ended (the run's end: M30 does not move), not the block's last
        // sample, which may come up to a period before its end.
        let c = r.machine[4];
        assert!((c.rem_euclid(360.0) - (360.0 + rotation[2])).abs() < 1e-6, "{preset}: C {c}");
        if let Err(e) = common::check_limits(&samples, preset, false) {
            panic!("{preset}: {e}");
        }
    }
}

#[test]
fn g49_in_g54_4_with_rcm_compensates_the_programmed_angles_once() {
    use fivex_engine::kin::Kinematics;
    // Example 2's N30/N40 (TCP type 1 to B45 C−90: machine B45 C−110), then G49 Z300 under
    // G54.4: the rotary coordinates after G49 are still the programmed B45 C−90, so the G49
    // block leaves the machine at B45 C−110 (it turned C to −130 when the current point took
    // the machine angles as programmed ones); the nose at WSCS (50, 50, 300) = G55 (74.085638,
    // 49.883624, 300).
    let src = "N1 G05.1 Q1\nN2 G55\nN3 G54.4 P1\nN4 G90 G00 X0 Y0 Z300. B0 C0\nN5 G01 G43.4 H01 Z40. F500.\n\
               N6 X50. Y50. Z20. B45. C-90.\nN7 G49 Z300.\n#100=#5005\nN9 G54.4 P0\nM30\n";
    let mut interp = example_2(src, rcm);
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let mut ends = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                ends.push((c.line, m.machine))
            }
        })
        .expect("no alarm");
    let (n6, n7) = (end_of(&ends, 6), end_of(&ends, 7));
    assert!((n6[3] - 45.0).abs() < 1e-9 && (n6[4] + 110.0).abs() < 1e-9, "N6 {n6:?}");
    assert!((n7[3] - 45.0).abs() < 1e-9 && (n7[4] + 110.0).abs() < 1e-9, "N7 {n7:?}");
    assert!((variable(&interp, 100) + 90.0).rem_euclid(360.0) < 1e-9, "#5005 {}", variable(&interp, 100));
    let nose = kin.forward(&n7, 0.0).tip - kin.nose;
    let got = [nose[0] - 100.0, nose[1] - 50.0, nose[2] + 400.0];
    assert!(close3(got, [74.085638, 49.883624, 300.0], 1e-6), "{got:?}");
}

#[test]
fn g49_after_tcp_type_2_in_g54_4_keeps_the_rotary_axes() {
    // TCP type 2 inside G54.4 (RCM = 1): I/J/K are directions in Π, which holds the error, so
    // N6 stands at the machine angles for (0, −0.707107, 0.707107) in the WSCS; G49 Z300 then
    // moves only X/Y/Z (the current point's rotary coordinates are the angles whose error-free
    // direction is the actual one, compensated back to where the axes stand).
    let src = "N1 G05.1 Q1\nN2 G55\nN3 G54.4 P1\nN4 G90 G00 X0 Y0 Z300. B0 C-30.\nN5 G01 G43.5 H01 Z40. F500.\n\
               N6 X50. Y50. Z20. I0 J-0.707107 K0.707107\nN7 G49 Z300.\nN8 G54.4 P0\nM30\n";
    let interp = example_2(src, rcm);
    let ends = motion_ends(interp);
    let (n6, n7) = (end_of(&ends, 6), end_of(&ends, 7));
    assert!((n6[3] - 45.0).abs() < 1e-6 && (n6[4] + 110.0).abs() < 1e-6, "N6 {n6:?}");
    assert!((n7[3] - n6[3]).abs() < 1e-9 && (n7[4] - n6[4]).abs() < 1e-9, "N7 {n7:?}");
}

#[test]
fn g68_2_and_g69_in_g54_4_with_rcm_keep_the_programmed_angles() {
    // table-ac, Δa 2° Δb −1.5°: after G54.4 P1 the program puts A0 C0 (machine angles turned by
    // the error, the tool along the ideal workpiece's Z, singular: C free). G68.2 and G69 move
    // nothing, so #5004/#5005 stay 0 (recomputing them from the machine would make C whatever
    // the machine C is, and a following G68.2 would then raise PS0439).
    let src = "G90 G00 X0 Y0 Z100. A0 C0\nG54.4 P1\nG00 A0 C0\nG68.2 X0 Y0 Z0 I0 J20. K0\n\
               #100=#5004\n#101=#5005\nG69\n#102=#5004\n#103=#5005\nG68.2 X0 Y0 Z0 I0 J10. K0\nG69\nG54.4 P0\nM30\n";
    let mut interp = fanuc_with(src, "table-ac", rcm);
    interp.state.setting_errors.sets[1].rotation = [2.0, -1.5, 0.0];
    let interp = ran(interp);
    for n in 100..=103 {
        assert!(variable(&interp, n).abs() < 1e-9, "#{n} = {}", variable(&interp, n));
    }
}
