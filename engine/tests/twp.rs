//! Tilted working plane in programs (spec `fanuc-twp-wsec-manual-params.md` TWP-01…TWP-13,
//! `syntec.md` SYN-18…SYN-22): where the tip and the tool are after G68.2, G53.1 and moves in the
//! feature coordinate system, on every kind of machine.

mod common;

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
