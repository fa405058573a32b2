//! Programming transforms (`engine/src/interp/frames.rs`, `docs/conventions.md` "Programming
//! transforms"): G68/G69 coordinate system rotation, G51/G50 scaling, G51.1/G50.1 programmable
//! mirror image, G16/G15 polar coordinates, in the FANUC 30i M series' manner. Expected
//! coordinates are worked out by hand in the comments (FANUC manual-style examples); where the
//! manuals leave a choice the test says "decision".

use crate::common;
use common::*;

use fivex_engine::canon::{Motion, MotionKind};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;

const SQRT3_2: f64 = 0.866_025_403_784_438_6;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-6
}

/// Assert a motion's X/Y (workpiece) target.
#[track_caller]
fn at(m: &Motion, x: f64, y: f64) {
    assert!(close(m.target[0], x) && close(m.target[1], y), "expected X{x} Y{y}, got {:?}", &m.target[..3]);
}

/// The arc of a motion: (center X, center Y, radius, sweep in degrees).
#[track_caller]
fn arc_of(m: &Motion) -> (f64, f64, f64, f64) {
    let a = m.arc.as_ref().expect("an arc");
    (a.center[0], a.center[1], a.radius, a.sweep_deg)
}

/// Rotate (x, y) about (cx, cy) by `deg` counter-clockwise.
fn rot(x: f64, y: f64, cx: f64, cy: f64, deg: f64) -> (f64, f64) {
    let (s, c) = deg.to_radians().sin_cos();
    let (dx, dy) = (x - cx, y - cy);
    (cx + dx * c - dy * s, cy + dx * s + dy * c)
}

fn motions_cfg(src: &str, tweak: impl FnOnce(&mut Config)) -> Vec<Motion> {
    let mut cfg = Config::new(MachineConfig::preset("mill3").expect("preset"), Dialect::Fanuc);
    tweak(&mut cfg);
    let mut interp = Interpreter::new(parse_file(src), cfg);
    let mut v = Vec::new();
    interp
        .run(|c| {
            if let fivex_engine::canon::CanonKind::Motion(m) = &c.kind {
                v.push(m.clone());
            }
        })
        .expect("no alarm");
    v
}

// ---------------------------------------------------------------------------------------------
// G68 / G69 coordinate system rotation
// ---------------------------------------------------------------------------------------------

#[test]
fn fanuc_incremental_commands_in_rotation_mode() {
    // The FANUC manual's example of incremental commands in rotation mode.
    let src = "N1 G92 X-500. Y-500. G69 G17\n\
               N2 G68 X700. Y300. R60.\n\
               N3 G90 G01 X0 Y0 F200.\n\
               N4 G91 X1000.\n\
               N5 G02 Y1000. R1000.\n\
               N6 G03 X-1000. I-500. J-500.\n\
               N7 G01 Y-1000.\n\
               N8 G69 G90 X-500. Y-500.\nM30\n";
    let m = motions(src);
    let r = |x, y| rot(x, y, 700.0, 300.0, 60.0);
    let p = r(0.0, 0.0);
    at(&m[0], p.0, p.1);
    let p = r(1000.0, 0.0);
    at(&m[1], p.0, p.1);
    // N5: from (1000, 0) to (1000, 1000), R1000 CW: programmed center (1000 + 866.025, 500).
    let p = r(1000.0, 1000.0);
    at(&m[2], p.0, p.1);
    assert_eq!(m[2].kind, MotionKind::ArcCw);
    let (cx, cy, radius, sweep) = arc_of(&m[2]);
    let c = r(1000.0 + 1000.0 * SQRT3_2, 500.0);
    assert!(close(cx, c.0) && close(cy, c.1) && close(radius, 1000.0) && close(sweep, -60.0), "{:?}", m[2].arc);
    // N6: G91 X-1000 with the center 500 left and down: end (0, 1000), center (500, 500).
    let p = r(0.0, 1000.0);
    at(&m[3], p.0, p.1);
    let (cx, cy, radius, _) = arc_of(&m[3]);
    let c = r(500.0, 500.0);
    assert!(close(cx, c.0) && close(cy, c.1) && close(radius, 500.0 * 2f64.sqrt()));
    let p = r(0.0, 0.0);
    at(&m[4], p.0, p.1);
}

#[test]
fn g91_r_adds_to_the_active_rotation() {
    // RIN = 1 (this project's setting): 30 + G91 60 = 90.
    // The FANUC manual's repetition: each call of the subprogram adds 45°.
    let src = "O1\nG90 G00 X0 Y0\nM98 P2 L4\nM30\nO2\nG68 X0 Y0 G91 R45.\nG90 G01 X10. Y0 F100.\nM99\n";
    let m = motions(src);
    at(&m[1], 10.0 * 0.5f64.sqrt(), 10.0 * 0.5f64.sqrt());
    at(&m[3], -10.0 * 0.5f64.sqrt(), 10.0 * 0.5f64.sqrt());
}

#[test]
fn with_rin_0_r_is_always_absolute() {
    let m = motions_cfg("G68 X0 Y0 R30.\nG91 G68 X0 Y0 R60.\nG90 G01 X10. Y0 F100.\nM30\n", |c| {
        c.rotation_angle_incremental = false
    });
    at(&m[0], 5.0, 10.0 * SQRT3_2);
}

/// An R beyond ±360° is refused with fivex's FX0010 in every dialect (FANUC's range of the
/// angle; its alarm is not known): fivex turned `R400.` into a 40° rotation without a word.
/// ±360 itself and a sum of G91 R's beyond 360 (ten calls of 45°) run.
#[test]
fn a_rotation_angle_beyond_360_degrees_is_fx0010() {
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        // (Without a decimal point 0.001° in FANUC; Syntec refuses such an angle, COR-048.)
        let no_point = if dialect == Dialect::Fanuc { &["R360001"][..] } else { &[] };
        for r in ["R400.", "R-360.5"].iter().chain(no_point) {
            let src = format!("G90 G00 X0 Y0\nG68 X0 Y0 {r}\nG01 X10. F100.\nM30\n");
            let result = run_with(&src, "mill3", dialect);
            let alarm = result.alarms.first().unwrap_or_else(|| panic!("{dialect:?} {r}: no alarm"));
            assert_eq!((alarm.code.as_str(), alarm.line), ("FX0010", 2), "{dialect:?} {r}");
            assert_eq!(result.workpiece[0], 0.0, "{dialect:?} {r}: the G01 after it must not run");
        }
    }
    let m = motions("G90 G00 X0 Y0\nG68 X0 Y0 R-360.\nG01 X10. F100.\nG68 X0 Y0 R360000\nX20.\nM30\n");
    at(&m[m.len() - 2], 10.0, 0.0);
    at(&m[m.len() - 1], 20.0, 0.0);
    let src = "O1\nG90 G00 X0 Y0\nM98 P2 L10\nM30\nO2\nG68 X0 Y0 G91 R45.\nG90 G01 X10. Y0 F100.\nM99\n";
    let m = motions(src);
    assert_eq!(m.len(), 11, "the G00 and ten calls");
    at(&m[10], 0.0, 10.0);
    // `fivex check` says it at the R word (no decimal point: 0.001°).
    let diags =
        fivex_engine::check::check(parse_file("G68 X0 Y0 R400.\nG68 X0 Y0 R400000\nG68 R400\nM30\n"), Dialect::Fanuc);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Dialect::Fanuc.describe(&d.id).0)).collect();
    assert_eq!(found, [(1, 11, "FX0010".to_string()), (2, 11, "FX0010".to_string())]);
}

/// Two of G51.1, G51, G68 in one block are FANUC's PS0010 (each takes the block's axis words as
/// its data, and the manual commands them one block each): fivex gave the block's X Y to all of
/// them, the mirror axis, the scaling centre and the rotation centre at once. One a block, and
/// G69/G50/G50.1 beside another code, run as before.
#[test]
fn two_transforms_started_in_one_block_are_ps0010() {
    for block in ["G51.1 X5. G68 R90.", "G51 X0 Y0 P2000 G68 R30.", "G68 R30. G51.1 Y0", "G51.1 X0 G51 P2."] {
        let src = format!("G90 G00 X0 Y0\n{block}\nG01 X10. F100.\nM30\n");
        let result = run_src(&src);
        let alarm = result.alarms.first().unwrap_or_else(|| panic!("{block}: no alarm"));
        assert_eq!((alarm.code.as_str(), alarm.line), ("PS0010", 2), "{block}");
        assert_eq!(result.workpiece[0], 0.0, "{block}: nothing after the refused block runs");
    }
    // Haas: G101 is its G51.1.
    let result = run_with("G90 G00 X0 Y0\nG101 X0 G68 R30.\nM30\n", "mill3", Dialect::Haas);
    assert_eq!(result.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("339", 2)), "{:?}", result.alarms);
    // One a block, in the manual's order: X mirrored about 0, then turned 90° the other way
    // (the mirror turns the rotation over): X10 Y0 → X-10 Y0 → X0 Y10.
    let m = motions("G90 G00 X0 Y0\nG51.1 X0\nG68 X0 Y0 R90.\nG01 X10. Y0 F100.\nG69 G50.1 X0\nM30\n");
    at(m.last().expect("a motion"), 0.0, 10.0);
    let diags = fivex_engine::check::check(parse_file("G51.1 X5. G68 R90.\nG51.1 X5.\nG68 R90.\n"), Dialect::Fanuc);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Dialect::Fanuc.describe(&d.id).0)).collect();
    assert_eq!(found, [(1, 11, "PS0010".to_string())]);
}

/// A mirror image changed while scaling or rotation is on, or scaling while rotation is on, is
/// fivex's FX0011 in every dialect: FANUC processes mirror image → scaling → rotation and asks
/// for the commands in that order, cancelled in reverse ("Do not specify G50.1 or G51.1 during
/// scaling or coordinate rotation mode"). fivex kept the rotation's sense and centre from the
/// G68 block: `G51.1 X0`, `G68 R30.`, `G50.1 X0` went on turning −30° (X10 → X8.66 Y-5.), and
/// `G51 P2.`, `G68 X10. Y0 R90.`, `G50` turned about X20. Cancels in one block count first, and
/// a cancel of what is not on changes nothing.
#[test]
fn transforms_out_of_nesting_order_are_fx0011() {
    let wrong = [
        "G51.1 X0\nG68 X0 Y0 R30.\nG50.1 X0",
        "G68 X0 Y0 R30.\nG51.1 X0",
        "G51 X0 Y0 P2.\nG51.1 X0",
        "G51.1 X0\nG51 X0 Y0 P2.\nG50.1",
        "G51 X0 Y0 P2.\nG68 X10. Y0 R90.\nG50",
        "G68 X0 Y0 R30.\nG51 X0 Y0 P2.",
    ];
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        for blocks in wrong {
            let blocks = if dialect == Dialect::Haas {
                blocks.replace("G51.1", "G101").replace("G50.1", "G100")
            } else {
                blocks.to_string()
            };
            let src = format!("G90 G00 X0 Y0\n{blocks}\nG01 X10. F100.\nM30\n");
            let result = run_with(&src, "mill3", dialect);
            let alarm = result.alarms.first().unwrap_or_else(|| panic!("{dialect:?} {blocks}: no alarm"));
            let last = 1 + blocks.lines().count() as u32;
            assert_eq!((alarm.code.as_str(), alarm.line), ("FX0011", last), "{dialect:?} {blocks}");
            assert_eq!(result.workpiece[0], 0.0, "{dialect:?} {blocks}: the G01 after it must not run");
        }
    }
    // The manual's order, a block cancelling all three, and cancels of what is not on.
    let src = "G90 G00 X0 Y0\nG50 G50.1 G69\nG51.1 X0\nG51 X0 Y0 P2.\nG68 X0 Y0 R30.\n\
               G01 X10. F100.\nG69\nG50\nG50.1 X0\nG51.1 X0\nG51 X0 Y0 P2.\nG68 X0 Y0 R30.\n\
               G69 G50 G50.1\nG01 X10.\nM30\n";
    let m = motions(src);
    // X10 mirrored, doubled, turned 30° the other way: (−20·cos30°, 20·sin30°).
    at(&m[1], -20.0 * SQRT3_2, 10.0);
    // Everything cancelled: X10 as written, Y where the tool stands.
    at(&m[2], 10.0, 10.0);
}

/// Another plane selected while G68 stays on is PS0144 (Haas 707, Syntec COR-035): FANUC says
/// G17/G18/G19 "must not be designated in the mode of coordinate system rotation". fivex went on
/// rotating X/Y while a G18 block's moves and cycles took the ZX plane. The same plane again, a
/// plane with G69 and a G68 that sets the rotation anew in its block's plane run.
#[test]
fn a_plane_change_under_g68_is_ps0144() {
    for (dialect, code) in [(Dialect::Fanuc, "PS0144"), (Dialect::Syntec, "COR-035"), (Dialect::Haas, "707")] {
        let src = "G90 G17 G00 X0 Y0 Z0\nG68 X0 Y0 R90.\nG18\nG01 X10. F100.\nM30\n";
        let result = run_with(src, "mill3", dialect);
        let alarm = result.alarms.first().unwrap_or_else(|| panic!("{dialect:?}: no alarm"));
        assert_eq!((alarm.code.as_str(), alarm.line), (code, 3), "{dialect:?}");
        assert_eq!(result.workpiece[..2], [0.0, 0.0], "{dialect:?}: the G01 after it must not run");
    }
    // G17 again keeps the rotation (X10 → Y10); G69 G18 ends it; G18 G68 rotates Z/X anew:
    // X10 in the ZX plane turned 90° from Z toward X is Z-10.
    let src = "G90 G17 G00 X0 Y0 Z0\nG68 X0 Y0 R90.\nG17 G01 X10. F100.\nG69 G18\nG00 X0 Z0\n\
               G18 G68 X0 Z0 R90.\nG01 X10.\nG69\nM30\n";
    let m = motions(src);
    at(&m[1], 0.0, 10.0);
    let end = m.last().expect("a motion").target;
    assert!(close(end[0], 0.0) && close(end[2], -10.0), "expected X0 Z-10, got {:?}", &end[..3]);
}

#[test]
fn g68_moves_the_machine_through_the_work_offset() {
    // G54 X100: workpiece (0, 10) is machine (100, 10).
    let m = motions("G10 L2 P1 X100.\nG54 G68 X0 Y0 R90.\nG01 X10. Y0 F100.\nM30\n");
    assert!(close(m[0].machine[0], 100.0) && close(m[0].machine[1], 10.0));
}

// ---------------------------------------------------------------------------------------------
// G51 / G50 scaling
// ---------------------------------------------------------------------------------------------

#[test]
fn g51_scales_a_circle_about_its_center() {
    // P2000 = ×2 about X0 Y0: X10 → X20; G02 X-10 R10 → X-20 with R20; I-10 → I-20.
    let m = motions(
        "G00 X0 Y0\nG51 X0 Y0 P2000\nG00 X10. Y0\nG02 X-10. Y0 R10. F100.\nG02 X10. Y0 I10. J0\nG50\nG00 X0 Y0\nM30\n",
    );
    assert_eq!(m.len(), 5);
    at(&m[1], 20.0, 0.0);
    at(&m[2], -20.0, 0.0);
    let (cx, cy, r, sweep) = arc_of(&m[2]);
    assert!(close(cx, 0.0) && close(cy, 0.0) && close(r, 20.0) && close(sweep, -180.0));
    at(&m[3], 20.0, 0.0);
    let (cx, cy, r, _) = arc_of(&m[3]);
    assert!(close(cx, 0.0) && close(cy, 0.0) && close(r, 20.0));
    // After G50 the scaling is off: X0 Y0 is X0 Y0.
    at(&m[4], 0.0, 0.0);
}

#[test]
fn g51_per_axis_radius_uses_the_larger_magnification() {
    // FANUC's example: X×2 (I2000), Y×1 (J1000); G02 X100 Y0 R100 from X0 Y100 is the same as
    // G02 X200 Y0 R200.
    let scaled = motions("G90 G00 X0 Y100. Z0\nG51 X0 Y0 Z0 I2000 J1000\nG02 X100. Y0 R100. F500.\nM30\n");
    let plain = motions("G90 G00 X0 Y100. Z0\nG02 X200. Y0 R200. F500.\nM30\n");
    let (a, b) = (arc_of(&scaled[1]), arc_of(&plain[1]));
    assert!(close(a.0, b.0) && close(a.1, b.1) && close(a.2, b.2) && close(a.3, b.3), "{a:?} vs {b:?}");
}

#[test]
fn a_negative_magnification_mirrors_and_swaps_g02_g03() {
    // I-1000: X mirrored about X0. X10 Y5 → (-10, 5); G02 to X20 Y5 (R5, center (15, 5))
    // becomes a CCW arc to (-20, 5) about (-15, 5).
    let m = motions("G51 X0 Y0 I-1000 J1000\nG01 X10. Y5. F100.\nG02 X20. Y5. R5.\nM30\n");
    assert_eq!(m[1].kind, MotionKind::ArcCcw);
    let (cx, cy, r, sweep) = arc_of(&m[1]);
    assert!(close(cx, -15.0) && close(cy, 5.0) && close(r, 5.0) && close(sweep, 180.0));
}

#[test]
fn g83_peck_depth_and_clearance_are_not_scaled() {
    // ×2 about the origin: hole X10 → X20, R2 → R4, Z-10 → Z-20; Q3 stays 3 mm a peck, the
    // 0.5 mm clearance stays 0.5 mm.
    let m = motions("G51 X0 Y0 Z0 P2000\nG00 Z10.\nG83 X10. Y0 Z-10. R2. Q3. F100.\nG80\nM30\n");
    let z: Vec<f64> = m.iter().skip(1).map(|m| m.target[2]).collect();
    let expected = [
        20.0, 4.0, 1.0, // position (Z stays at the scaled 20), R point, first peck
        4.0, 1.5, -2.0, // back to R, down to 0.5 above, second peck
        4.0, -1.5, -5.0, 4.0, -4.5, -8.0, 4.0, -7.5, -11.0, 4.0, -10.5, -14.0, 4.0, -13.5, -17.0, 4.0, -16.5, -20.0,
        20.0, // G98: the initial level
    ];
    assert_eq!(z.len(), expected.len(), "{z:?}");
    for (a, b) in z.iter().zip(expected) {
        assert!(close(*a, b), "{z:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// G51.1 / G50.1 programmable mirror image
// ---------------------------------------------------------------------------------------------

#[test]
fn g51_1_mirrors_one_axis_and_swaps_g02_g03() {
    // Mirror about X0: (10, 10) → (-10, 10); the CW arc to (20, 0) about (10, 0) becomes CCW to
    // (-20, 0) about (-10, 0).
    let m = motions("G00 X0 Y0\nG51.1 X0\nG01 X10. Y10. F100.\nG02 X20. Y0 R10.\nG50.1 X0\nG00 X0 Y0\nM30\n");
    assert_eq!(m[2].kind, MotionKind::ArcCcw);
    let (cx, cy, r, sweep) = arc_of(&m[2]);
    assert!(close(cx, -10.0) && close(cy, 0.0) && close(r, 10.0) && close(sweep, 90.0));
}

#[test]
fn g51_1_about_a_line_off_the_origin() {
    // Mirror about X5: X10 → X0; I/J arcs have their center mirrored too.
    let m = motions("G51.1 X5.\nG01 X10. Y0 F100.\nG03 X10. Y0 I-2. J0\nM30\n");
    assert_eq!(m[1].kind, MotionKind::ArcCw);
    let (cx, cy, r, sweep) = arc_of(&m[1]);
    assert!(close(cx, 2.0) && close(cy, 0.0) && close(r, 2.0) && close(sweep, -360.0));
}

#[test]
fn mirroring_both_plane_axes_keeps_the_direction() {
    let m = motions("G51.1 X0 Y0\nG01 X10. Y0 F100.\nG02 X0 Y-10. R10.\nM30\n");
    assert_eq!(m[1].kind, MotionKind::ArcCw);
}

// ---------------------------------------------------------------------------------------------
// G16 / G15 polar coordinates
// ---------------------------------------------------------------------------------------------

#[test]
fn g16_bolt_hole_circle_with_g81() {
    // The FANUC manual's bolt hole circle: radius 100 at 30°, 150°, 270°.
    let src = "G17 G90 G16\nG81 X100. Y30. Z-20. R-5. F200.\nY150.\nY270.\nG15 G80\nM30\n";
    let m = motions(src);
    // Each hole: position, R (-5), bottom (-20), back to the initial level (0).
    let z: Vec<f64> = m[..4].iter().map(|m| m.target[2]).collect();
    assert_eq!(z, vec![0.0, -5.0, -20.0, 0.0]);
    // The same with incremental angles.
    let inc = motions("G17 G90 G16\nG81 X100. Y30. Z-20. R-5. F200.\nG91 Y120.\nY120.\nG15 G80\nM30\n");
    assert_eq!(inc.len(), m.len());
    for (a, b) in inc.iter().zip(&m) {
        at(a, b.target[0], b.target[1]);
    }
}

#[test]
fn g16_with_only_the_radius_keeps_the_angle() {
    let m = motions("G16\nG01 X10. Y45. F100.\nX20.\nM30\n");
    let h = 0.5f64.sqrt();
    at(&m[1], 20.0 * h, 20.0 * h);
}

#[test]
fn decision_g16_incremental_radius_starts_at_the_current_point() {
    // G91 with a radius: the origin is the current point (10, 10); the incremental angle counts
    // from the current point's angle about the zero (45°): 45 + 90 = 135°, radius 5.
    let m = motions("G00 X10. Y10.\nG16\nG91 G01 X5. Y90. F100.\nM30\n");
    let h = 0.5f64.sqrt();
    at(&m[1], 10.0 - 5.0 * h, 10.0 + 5.0 * h);
}

// ---------------------------------------------------------------------------------------------
// canned cycles and reference returns under the transforms
// ---------------------------------------------------------------------------------------------

#[test]
fn g76_shift_is_not_scaled() {
    // ×2 about the origin: the hole X5 → X10; the shift Q1 stays 1 mm.
    let m = motions("G51 X0 Y0 Z0 P2000\nG00 Z5.\nG76 X5. Y0 Z-5. R1. Q1. F100.\nG80 G50\nM30\n");
    let xs: Vec<f64> = m.iter().skip(1).map(|m| m.target[0]).collect();
    assert!(xs.iter().any(|&x| close(x, 11.0)), "{xs:?}");
    assert!(xs.iter().all(|&x| close(x, 10.0) || close(x, 11.0)), "{xs:?}");
}

/// G27–G30 and the coordinate system changes (G52–G59, G92) while mirror image, scaling or
/// rotation stays on are FX0012 in every dialect: FANUC's restrictions of each of the three
/// forbid them ("specify it only after cancelling") and name no alarm. fivex ran G28's
/// intermediate point through the rotation and kept the rotation centre's workpiece
/// coordinates over a work system change, which no manual confirms. A cancel in the block
/// counts first; the work system in force named again changes nothing. (G27 is not built:
/// PS0010 comes first.)
#[test]
fn returns_and_coordinate_changes_under_the_transforms_are_fx0012() {
    let starts = ["G68 X0 Y0 R90.", "G51 X0 Y0 P2.", "G51.1 X0", "G51.1 X0 Y0\nG50.1 X0"];
    let forbidden =
        ["G28 X10. Y0", "G91 G28 Z0", "G30 Z0", "G29 X0 Y0", "G52 X5. Y5.", "G53 Z0", "G92 X0 Y0", "G55", "G54.1 P2"];
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        for start in starts {
            for block in forbidden {
                // Not in these dialects (refused on their own: `docs/dialects.md`).
                let absent = match dialect {
                    Dialect::Syntec => block.starts_with("G54.1"),
                    Dialect::Haas => block.starts_with("G30"),
                    Dialect::Fanuc => false,
                };
                if absent {
                    continue;
                }
                let (start, block) = if dialect == Dialect::Haas {
                    let haas = |s: &str| s.replace("G51.1", "G101").replace("G50.1", "G100").replace("G54.1", "G154");
                    (haas(start), haas(block))
                } else {
                    (start.to_string(), block.to_string())
                };
                let src = format!("G90 G00 X0 Y0 Z0\n{start}\n{block}\nG90 G01 X10. F100.\nM30\n");
                let result = run_with(&src, "mill3", dialect);
                let what = format!("{dialect:?} {start} / {block}");
                let alarm = result.alarms.first().unwrap_or_else(|| panic!("{what}: no alarm"));
                let line = 2 + start.lines().count() as u32;
                assert_eq!((alarm.code.as_str(), alarm.line), ("FX0012", line), "{what}");
                assert_eq!(result.workpiece[..3], [0.0; 3], "{what}: nothing after it may run");
            }
        }
    }
    // Cancelled in the block or before, or the work system in force named again: they run.
    // G69 G28 returns X and Y through X10 Y0 as written (machine X0 Y0 on mill3); G54 again
    // keeps the rotation (X10 → Y10).
    let src = "G90 G54 G00 X0 Y0 Z0\nG68 X0 Y0 R90.\nG54 G01 X10. F100.\nG69 G28 X10. Y0\n\
               G51.1 X0 Y0\nG50.1 X0\nG50.1\nG53 Z0\nM30\n";
    let m = motions(src);
    at(&m[1], 0.0, 10.0);
    assert!(m.iter().any(|m| m.kind == MotionKind::MachineRapid), "G28 and G53 run");
    // G54.1 without P is P1: the same system again runs, from P2 it is another one.
    let p1 = "G90 G54.1 P1 G00 X0 Y0\nG68 X0 Y0 R90.\nG54.1\nG69\nM30\n";
    assert!(run_with(p1, "mill3", Dialect::Fanuc).completed());
    let p2 = "G90 G54.1 P2 G00 X0 Y0\nG68 X0 Y0 R90.\nG54.1\nG69\nM30\n";
    assert_eq!(run_with(p2, "mill3", Dialect::Fanuc).alarms.first().map(|a| a.code.as_str()), Some("FX0012"));
}
