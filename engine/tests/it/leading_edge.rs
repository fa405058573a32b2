//! Leading edge offset of 5-axis cutter compensation (G41.3 … G40, `stage::leading_edge`) on
//! head-bc (B tilts the tool about Y: at C0 the tool is (sin B, 0, cos B)): the manual's
//! vectors worked out by hand, the rules for moves along the tool, blocks without movement and
//! the block before G40, PS5408, what is still refused (among it TCP, which the manual's lists
//! do not allow with G41.3), and a property test of the defining rule. Tool offsets have
//! radius 5, length 100.

use crate::common::*;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;

/// 5·(sin 60°, cos 60°): R times the components of the tool at B30 (sin 30° = 0.5).
const S: f64 = 4.330127018922193;
const C: f64 = 2.5;

#[test]
fn tv10_the_tool_trails_the_programmed_point_across_the_tool() {
    // B30: VT = (0.5, 0, 0.8660), VM = X: θ = 60°. VM's part across the tool is
    // X − 0.5·VT = (0.75, 0, −0.4330), |…| = 0.8660; VC = −5·(0.8660, 0, −0.5) = (−4.3301, 0, 2.5)
    // at every block end. The G41.3 block moves by it when the first block comes (start-up,
    // CRC-22); the block before G40 makes it with its own move (CRC-26); G40 moves back.
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG41.3 D1\nG01 X100. F1000.\nX200.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-S, 0.0, C]),
            (3, [100.0 - S, 0.0, C]),
            (4, [200.0 - S, 0.0, C]),
            (5, [200.0, 0.0, 0.0]),
        ],
    );
    // B−30 (θ = 120°): VC = (−4.3301, 0, −2.5).
    let src = src.replace("B30.", "B-30.");
    assert_ends(
        &src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-S, 0.0, -C]),
            (3, [100.0 - S, 0.0, -C]),
            (4, [200.0 - S, 0.0, -C]),
            (5, [200.0, 0.0, 0.0]),
        ],
    );
}

/// The run's cutting point (`Sample::cutting`) is the leading edge: the end's edge toward the
/// block's move across the tool, R from the tip — at every sample of the blocks of the mode, so
/// on the programmed point where the block starts (its tip at the programmed point + VC).
#[test]
fn tv10_the_cutting_point_is_the_leading_edge() {
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG41.3 D1\nG01 X100. F1000.\nX200.\nG40\nM30\n";
    let mut interp = interpreter(src, "head-bc", fivex_engine::Dialect::Fanuc);
    let (mut seen, mut worst) = (0, 0.0f64);
    let r = fivex_engine::run::run(&mut interp, &Default::default(), |s| {
        if !(3..=4).contains(&s.line) {
            return;
        }
        let cut = s.cutting.expect("a cutting point under G41.3");
        let edge = Vec3::from(cut) - Vec3::from(s.tip);
        worst = worst.max((edge - Vec3::new(S, 0.0, -C)).norm());
        seen += 1;
    });
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(seen > 100, "{seen} samples");
    assert!(worst < 1e-9, "the cutting point {worst} mm off the leading edge");
}

#[test]
fn tv10_a_vertical_tool_and_a_move_down_and_across() {
    // VT = Z, VM = (100, 0, −50): θ = 116.6°, VC = (−5, 0, 0): the part along the tool drops out.
    // At the corner into Y the next move makes the vector: (0, −5, 0) (θ = 90°, the vector before
    // pointed the formula's way: sign +).
    let src = "G90 G00 X0 Y0 Z50. B0 C0\nG41.3 D1\nG01 X100. Z0 F1000.\nY100.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 50.0]),
            (2, [-5.0, 0.0, 50.0]),
            (3, [100.0, -5.0, 0.0]),
            (4, [100.0, 95.0, 0.0]),
            (5, [100.0, 100.0, 0.0]),
        ],
    );
}

#[test]
fn tv12_the_block_after_g41_3_along_the_tool_is_ps5408() {
    for first in ["G01 Z-10. F500.", "G01 Z10. F500.", "G01 B10. F500."] {
        let src = format!("G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\n{first}\nG40\nM30\n");
        assert_eq!(ends_of(&src, "head-bc").alarm, Some(("PS5408".to_string(), 3)), "{src}");
    }
    // Tilted: along the tool at B30 is (0.5, 0, 0.8660).
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG41.3 D1\nG01 X-50. Z-86.602540378 F500.\nG40\nM30\n";
    assert_eq!(ends_of(src, "head-bc").alarm, Some(("PS5408".to_string(), 3)));
}

#[test]
fn tv13_a_move_along_the_tool_keeps_the_vector_before() {
    // N3's vector is made with N4 (−Z, θ = 180°): VC of N2 (−5, 0, 0) is kept, and by N4 (N5 −Z)
    // again. N5's vector is made with N6 (X, 90°): the vector before, (−5, 0, 0), points the
    // formula's way for N5's own move (along the tool: no direction, sign +): (−5, 0, 0).
    let src = "G90 G00 X0 Y0 Z50. B0 C0\nG41.3 D1\nG01 X100. F500.\nZ40.\nZ30.\nX200.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 50.0]),
            (2, [-5.0, 0.0, 50.0]),
            (3, [95.0, 0.0, 50.0]),
            (4, [95.0, 0.0, 40.0]),
            (5, [95.0, 0.0, 30.0]),
            (6, [195.0, 0.0, 30.0]),
            (7, [200.0, 0.0, 30.0]),
        ],
    );
}

#[test]
fn tv14_one_block_without_movement_is_looked_over() {
    // N4 turns B only: N3's vector is made with N5's move (Y) and N3's tool (vertical):
    // (0, −5, 0); N4 keeps it (it stays perpendicular to the tilted tool). N5 (the block before
    // G40) with the tool at B30: Y is across it, (0, −5, 0) again.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X100. F500.\nB30.\nY100.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-5.0, 0.0, 0.0]),
            (3, [100.0, -5.0, 0.0]),
            (4, [100.0, -5.0, 0.0]),
            (5, [100.0, 95.0, 0.0]),
            (6, [100.0, 100.0, 0.0]),
        ],
    );
}

#[test]
fn tv14_two_blocks_without_movement_keep_the_vector_before() {
    // N4 and N5 do not move: N3 keeps the vector of the G41.3 block, (−5, 0, 0), and so do they.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X100. F500.\nB0\nC0\nY100.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-5.0, 0.0, 0.0]),
            (3, [95.0, 0.0, 0.0]),
            (4, [95.0, 0.0, 0.0]),
            (5, [95.0, 0.0, 0.0]),
            (6, [100.0, 95.0, 0.0]),
            (7, [100.0, 100.0, 0.0]),
        ],
    );
}

#[test]
fn tv10_at_90_degrees_the_sign_follows_the_vector_before() {
    // N3 keeps (−5, 0, 0) over two blocks without movement; N6 goes back along −X and its
    // vector is made with N7 (Y, θ = 90°): the vector before (−5, 0, 0) points against
    // (VM6 × VT) × VT = (1, 0, 0), so N6's vector is the formula's negated: −(0, −5, 0) = (0, 5, 0);
    // N7 likewise against its own move's (0, −1, 0): (0, 5, 0) (M-10 rule 2, TV-10's last row).
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X100. F500.\nB0\nC0\nX0\nY100.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-5.0, 0.0, 0.0]),
            (3, [95.0, 0.0, 0.0]),
            (4, [95.0, 0.0, 0.0]),
            (5, [95.0, 0.0, 0.0]),
            (6, [0.0, 5.0, 0.0]),
            (7, [0.0, 105.0, 0.0]),
            (8, [0.0, 100.0, 0.0]),
        ],
    );
}

#[test]
fn tv15_the_block_before_g40_uses_its_own_move() {
    // B30: VT = (0.5, 0, 0.8660); N4 moves (0, 100, −50): VM·VT = −43.3013, its part across the
    // tool (21.6506, 100, −12.5), length 103.0776; VC = −5·that/length = (−1.0502, −4.8507,
    // 0.6063) at the ends of N3 (made with N4) and of N4 (its own move, before G40).
    let v = [-1.050210063, -4.850712501, 0.606339063];
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG41.3 D1\nG01 X100. F500.\nY100. Z-50.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-S, 0.0, C]),
            (3, [100.0 + v[0], v[1], v[2]]),
            (4, [100.0 + v[0], 100.0 + v[1], -50.0 + v[2]]),
            (5, [100.0, 100.0, -50.0]),
        ],
    );
}

#[test]
fn m30_ends_the_mode_at_the_last_vector_and_d_changes_act_from_their_block() {
    // M30 in the mode: the last block ends at its own vector (as before G40); no move back.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X100. F500.\nM30\n";
    assert_ends(src, "head-bc", &[(1, [0.0, 0.0, 0.0]), (2, [-5.0, 0.0, 0.0]), (3, [95.0, 0.0, 0.0])]);
    // D0 in the mode: the value of the block whose end the vector is at.
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X100. F500.\nD0\nX200.\nG40\nM30\n";
    assert_ends(
        src,
        "head-bc",
        &[
            (1, [0.0, 0.0, 0.0]),
            (2, [-5.0, 0.0, 0.0]),
            (3, [95.0, 0.0, 0.0]),
            (5, [200.0, 0.0, 0.0]),
            (6, [200.0, 0.0, 0.0]),
        ],
    );
}

#[test]
fn tv31_what_the_leading_edge_offset_does_not_perform_stays_refused() {
    let cases = [
        // The mode's own rules (interlocks): other addresses in the G41.3 block, a block
        // without a move after it, circles in the mode, table and mixed machines.
        ("G41.3 D1 X10.\n", 2, "head-bc", "PS5460"),
        ("G41.3 D1\nM08\n", 3, "head-bc", "PS5460"),
        ("G41.3 D1\nG01 X10. F500.\nG02 X20. R5.\n", 4, "head-bc", "PS5460"),
        ("G41.3 D1\n", 2, "table-ac", "PS5460"),
        ("G41.3 D1\n", 2, "mixed-bc", "PS5460"),
        // Not built: Q in the mode, G93; no tool rotation mechanism.
        ("G41.3 D1\nG01 X10. F500. Q1\n", 3, "head-bc", "PS0010"),
        ("G41.3 D1\nG01 X10. F500.\nG93 X20. F10.\n", 4, "head-bc", "PS0010"),
        ("G41.3 D1\n", 2, "mill3", "PS0010"),
        // Not with TCP: G41.3 is not among the G codes allowed in TCP (§2.3.1, TCP-16), nor
        // among the modal states TCP may start in (§2.3.2, TCP-15).
        ("G43.4 H1\nG41.3 D1\n", 3, "head-bc", "PS5421"),
        ("G41.3 D1\nG01 X10. F500.\nG43.4 H1\n", 4, "head-bc", "PS5421"),
    ];
    for (src, line, preset, code) in cases {
        let src = format!("G90 G00 X0 Y0 Z0\n{src}G40\nM30\n");
        assert_eq!(first_alarm(&src, preset), Some((code.to_string(), line)), "{preset}\n{src}");
    }
}

mod random {
    //! The defining rule on random paths: with the tool turning from block to block, every
    //! vector added at a block end is perpendicular to the tool there, of length R, in the
    //! plane of that tool and the next block's move, and against that move's part across the
    //! tool (M-10).

    use super::*;
    use proptest::prelude::*;

    fn tool(b: f64, c: f64) -> Vec3 {
        let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
        let mut pos = [0.0; 8];
        (pos[3], pos[4]) = (b, c);
        kin.forward(&pos, 0.0).tool
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(60), ..ProptestConfig::default() })]
        #[test]
        fn every_vector_is_perpendicular_to_the_tool_of_length_r_in_the_plane_of_the_next_move(
            blocks in prop::collection::vec(((-80.0..80.0f64, -80.0..80.0f64, -40.0..40.0f64), (-50.0..50.0f64, -90.0..90.0f64)), 3..7),
        ) {
            // The values as the program gives them (6 decimals).
            let r6 = |v: f64| (v * 1e6).round() / 1e6;
            let blocks: Vec<_> =
                blocks.iter().map(|&((x, y, z), (b, c))| ((r6(x), r6(y), r6(z)), (r6(b), r6(c)))).collect();
            let point = |p: &(f64, f64, f64)| Vec3::new(p.0, p.1, p.2);
            // The first move not along the tool at B0 C0 (that is PS5408).
            prop_assume!(blocks[0].0 .0.hypot(blocks[0].0 .1) > 1.0);
            let mut at = Vec3::zeros();
            for (p, _) in &blocks {
                prop_assume!((point(p) - at).norm() > 1.0);
                at = point(p);
            }
            let xyz = |p: &(f64, f64, f64)| format!("X{:.6} Y{:.6} Z{:.6}", p.0, p.1, p.2);
            let mut src = String::from("G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\n");
            let mut lines = Vec::new();
            for (k, (p, (b, c))) in blocks.iter().enumerate() {
                src += &format!("G01 {} B{b:.6} C{c:.6}{}\n", xyz(p), if k == 0 { " F800." } else { "" });
                lines.push(src.lines().count() as u32);
            }
            src += "G40\nM30\n";
            let got = ends_of(&src, "head-bc");
            // Moves along the tool or exactly across it (90°) do not come up here.
            prop_assert_eq!(&got.alarm, &None);
            for (k, (p, (b, c))) in blocks.iter().enumerate() {
                let line = lines[k];
                let end = got.ends.iter().find(|(l, _)| *l == line).map(|e| e.1);
                prop_assert!(end.is_some(), "line {} missing: {:?}", line, got.ends);
                let vc = end.unwrap() - point(p);
                let t = tool(*b, *c);
                // The move the vector is made with: the next block's, the last block's own.
                let next = match blocks.get(k + 1) {
                    Some((q, _)) => point(q) - point(p),
                    None => point(p) - if k == 0 { Vec3::zeros() } else { point(&blocks[k - 1].0) },
                };
                prop_assert!(vc.dot(&t).abs() < 1e-7, "line {}: {:?} not across the tool {:?}", line, vc, t);
                prop_assert!((vc.norm() - 5.0).abs() < 1e-7, "line {}: |{:?}| ≠ 5", line, vc);
                prop_assert!(vc.dot(&t.cross(&next)).abs() < 1e-6 * next.norm(), "line {}: {:?} out of the plane", line, vc);
                prop_assert!(vc.dot(&next) <= 1e-9, "line {}: {:?} ahead of the move {:?}", line, vc, next);
            }
        }
    }
}

#[test]
fn tv11_no_19631_counts_a_move_near_the_tool_as_along_it() {
    // The first move 3° off the vertical tool: with Δθ = 5° it counts as 0° (PS5408 at
    // start-up); with the default 0 it has a vector of its own.
    let (s3, c3) = 3f64.to_radians().sin_cos();
    let src = format!("G90 G00 X0 Y0 Z0 B0 C0\nG41.3 D1\nG01 X{:.6} Z{:.6} F500.\nG40\nM30\n", 50.0 * s3, 50.0 * c3);
    let tolerance = |c: &mut fivex_engine::interp::Config| c.edit_machine(|m| m.five_axis.leading_edge_tolerance = 5.0);
    assert_eq!(first_alarm_with(&src, "head-bc", tolerance), Some(("PS5408".into(), 3)));
    assert_eq!(first_alarm(&src, "head-bc"), None);
}
