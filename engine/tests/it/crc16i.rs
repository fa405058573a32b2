//! The 16i variant of 3-D cutter compensation (`five_axis.crc_variant = "16i"`, FANUC
//! 16i-MA/MB A-78438E; `docs/cutter-compensation.md`, "16i variant"): what it changes in the
//! tool side offset (the check in the compensation plane, No.19605#5 NIC, No.19630, type C's
//! restrictions, the commands the mode refuses) and that the 30i behaviour, the default, is
//! unchanged. head-bc, tool offsets of radius 5, length 100.

use crate::common::*;
use fivex_engine::interp::Config;
use fivex_engine::machine::{CrcVariant, MachineConfig};

/// The 16i variant, with `edit` on top.
fn sixteen_i(edit: impl FnOnce(&mut MachineConfig)) -> impl FnOnce(&mut Config) {
    move |c: &mut Config| {
        c.edit_machine(|m| {
            m.five_axis.crc_variant = CrcVariant::Fanuc16i;
            edit(m);
        })
    }
}

fn near(got: &Ends, want: &[(u32, [f64; 3])]) -> bool {
    got.ends.len() == want.len()
        && got
            .ends
            .iter()
            .zip(want)
            .all(|((l, p), (wl, w))| l == wl && (p - fivex_engine::kin::Vec3::from(*w)).norm() < 1e-6)
}

#[test]
fn the_30i_is_the_default_and_is_not_written() {
    let m = MachineConfig::preset("head-bc").unwrap();
    assert_eq!(m.five_axis.crc_variant, CrcVariant::Fanuc30i);
    let json = serde_json::to_value(&m).unwrap();
    assert!(json["five_axis"].get("crc_variant").is_none(), "{}", json["five_axis"]);
    let mut m16 = m.clone();
    m16.five_axis.crc_variant = CrcVariant::Fanuc16i;
    let json = serde_json::to_value(&m16).unwrap();
    assert_eq!(json["five_axis"]["crc_variant"], "16i");
    let back: MachineConfig = serde_json::from_value(json).unwrap();
    assert_eq!(back, m16);
}

#[test]
fn the_settings_of_one_variant_are_refused_on_the_other() {
    let base = MachineConfig::preset("head-bc").unwrap();
    let refused = |edit: &dyn Fn(&mut MachineConfig)| {
        let mut m = base.clone();
        edit(&mut m);
        m.validate().is_err()
    };
    // 16i parameters on a 30i.
    assert!(refused(&|m| m.five_axis.plane_change_check_off = true));
    assert!(refused(&|m| m.five_axis.non_movement_limit = 0.01));
    // 30i parameters on a 16i.
    let on_16i = |edit: fn(&mut MachineConfig)| {
        move |m: &mut MachineConfig| {
            m.five_axis.crc_variant = CrcVariant::Fanuc16i;
            edit(m)
        }
    };
    assert!(refused(&on_16i(|m| m.five_axis.crc_check_in_plane = true)));
    assert!(refused(&on_16i(|m| m.five_axis.avoidance_max_tool_angle = 5.0)));
    assert!(refused(&on_16i(|m| m.five_axis.crc_codes_by_mechanism = true)));
    assert!(refused(&on_16i(|m| m.five_axis.non_movement_limit = -0.01)));
    // Its own settings are accepted.
    assert!(!refused(&on_16i(|m| {
        m.five_axis.plane_change_check_off = true;
        m.five_axis.non_movement_limit = 0.01;
    })));
}

/// The DIP of `tool_side.rs` (`ni5_…`) with the tool vertical: N5 (line 5, to 21,−1) moves 3
/// along the tool.
const DIP: &str = "G90 G00 X-10. Y0 Z0 B0 C0\nG41.2 D1\nG01 F500. X0 Y0 Z0\nX20.\nX21. Y-1. Z3.\nX31. Y9.\n\
                   X40. Y9. Z0\nG40 X50.\nM30\n";

#[test]
fn the_16i_checks_in_the_compensation_plane() {
    // In the XY plane line 5 runs from its corner with line 4, (15 + 5√2, 5) = (22.071, 5), to
    // its corner with line 6, (21, 6 + 5(√2 − 1)... ) = (21, 6.071): (−1.071, 1.071) against the
    // programmed (1, −1), dot −2.142 < 0. The 16i checks there ("as in cutter compensation C",
    // A-78438E §1.1): PS0041 at line 5. The 30i's default (NI5 = 0) checks in 3-D, where both
    // moves also rise 3 along the tool: −2.142 + 9 > 0, no alarm.
    assert_eq!(ends_of(DIP, "head-bc").alarm, None);
    assert_eq!(ends_with(DIP, "head-bc", sixteen_i(|_| {})).alarm, Some(("PS0041".into(), 5)));
    // The same with the 30i's NI5 = 1.
    let ni5 = |c: &mut Config| c.edit_machine(|m| m.five_axis.crc_check_in_plane = true);
    assert_eq!(ends_with(DIP, "head-bc", ni5).alarm, Some(("PS0041".into(), 5)));
    // CAV (No.19607#5, shared with G41/G42) does not avoid under the 16i's tool side offset.
    let cav = sixteen_i(|m| m.motion.cutter_interference_avoidance = true);
    assert_eq!(ends_with(DIP, "head-bc", cav).alarm, Some(("PS0041".into(), 5)));
}

/// A-78438E Fig. 1.1 (n)–(u) (TV-01), turned 90° about Z for head-bc as `tool_side.rs`'s
/// `tv01_…`: the tool turns 91° between N4 (line 4) and N6 (line 6).
fn tv01(n4_extra: &str) -> String {
    format!(
        "G90 G00 X0 Y0 Z0 B46. C0\nG41.2 D1\nG01 Y100. F3000.\nX200. Z-200.{n4_extra}\nB-45.\nX400. Z0\nY0\n\
         X200. Z-200.\nB46.\nX0 Z0\nG40 Y-50.\nM30\n"
    )
}

#[test]
fn nic_skips_the_check_at_a_change_of_the_compensation_plane() {
    // NIC = 0 (No.19605#5, the default): the check raises PS0041 at N4 as on the 30i.
    let plain = ends_with(&tv01(""), "head-bc", sixteen_i(|_| {}));
    assert_eq!(plain.alarm, Some(("PS0041".into(), 4)));
    // NIC = 1 (A-78438E p.36: "1: Not perform"): no check, so N4 ends at both of its corner
    // vectors as with Q3 ("the two vectors (V1 and V2) are not deleted"). In N4's plane its
    // move runs along t = (0.6947, 0, −0.7193) (the tool at B46 is (0.7193, 0, 0.6947)) and its
    // perpendicular vector is n = (0, 5, 0); V1 = n + 5t from (200, 100, −200):
    // (203.473292, 105, −203.596699), V2 its mirror across N4, (203.473292, 95, −203.596699).
    let nic = ends_with(&tv01(""), "head-bc", sixteen_i(|m| m.five_axis.plane_change_check_off = true));
    let n4: Vec<[f64; 3]> = nic.ends.iter().filter(|e| e.0 == 4).map(|e| [e.1.x, e.1.y, e.1.z]).collect();
    let want = [[203.473292, 105.0, -203.596699], [203.473292, 95.0, -203.596699]];
    assert_eq!(n4.len(), 2, "{:?}", nic.ends);
    for (p, w) in n4.iter().zip(want) {
        assert!(p.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-5), "{n4:?}");
    }
    assert_ne!(nic.alarm.as_ref().map(|a| a.1), Some(4), "{:?}", nic.alarm);
    // The same ends as the 16i with Q3 in N4, and as the 30i with Q3.
    let q3 = ends_with(&tv01(" Q3"), "head-bc", sixteen_i(|_| {}));
    let q3_30i = ends_of(&tv01(" Q3"), "head-bc");
    let n4_of = |e: &Ends| e.ends.iter().filter(|e| e.0 == 4).map(|e| e.1).collect::<Vec<_>>();
    for other in [&q3, &q3_30i] {
        assert!(n4_of(other).iter().zip(n4_of(&nic)).all(|(a, b)| (a - b).norm() < 1e-9) && n4_of(other).len() == 2);
    }
}

/// Lines 3–6: X to 50, a 5 µm jog in +Y, Y to 50, the cancel along −X; the tool vertical.
const JOG: &str = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\nY0.005\nY50.\nG40 X-50.\nM30\n";

#[test]
fn no_19630_takes_a_short_move_as_a_block_without_movement() {
    // Without No.19630 (the 30i, and the 16i with it 0) the jog is a block of its own: the
    // start-up block ends at the intersection of y = 5 with the jog's offset line x = 45 (an
    // inside corner under G41.2, type A), (45, 5); the jog continues straight into line 5, so
    // it ends at its perpendicular vector (45, 0.005) — it runs back 4.995 against its
    // programmed +0.005: PS0041 at line 4.
    assert_eq!(ends_of(JOG, "head-bc").alarm, Some(("PS0041".into(), 4)));
    assert_eq!(ends_with(JOG, "head-bc", sixteen_i(|_| {})).alarm, Some(("PS0041".into(), 4)));
    // A limit below the jog changes nothing.
    let short = sixteen_i(|m| m.five_axis.non_movement_limit = 0.004);
    assert_eq!(ends_with(JOG, "head-bc", short).alarm, Some(("PS0041".into(), 4)));
    // No.19630 = 0.01 mm: the jog (5 µm in the plane) is a block without movement. The corner
    // at the end of line 3 is made with line 5 (+Y at x = 50): (45, 5); the jog keeps that
    // vector (−5, 5, 0): it ends at (50, 0.005) + (−5, 5) = (45, 5.005); line 5 ends where its
    // offset line x = 45 meets the cancel block's, y = 45 (inside, type A): (45, 45); the
    // cancel goes to (−50, 50).
    let limit = sixteen_i(|m| m.five_axis.non_movement_limit = 0.01);
    let got = ends_with(JOG, "head-bc", limit);
    assert_eq!(got.alarm, None);
    let want = [
        (1, [-50.0, 0.0, 0.0]),
        (3, [45.0, 5.0, 0.0]),
        (4, [45.0, 5.005, 0.0]),
        (5, [45.0, 45.0, 0.0]),
        (6, [-50.0, 50.0, 0.0]),
    ];
    assert!(near(&got, &want), "{:?}", got.ends);
}

#[test]
fn type_c_takes_no_move_in_its_g41_2_or_g40_block_and_a_move_after_g41_2() {
    // No.5003#1 SUV (type C), TV-32. The 30i's NOTE (5-axis manual §3.1.1) and the 16i's
    // (A-78438E p.7): the G40/G41.2/G42.2 block is in G00/G01 and has no move command, and the
    // block after G41.2/G42.2 moves by G00, G01, G02 or G03 — conditions that "must always be
    // satisfied". PS5460, fivex's number: neither names one.
    let suv = |m: &mut MachineConfig| m.motion.cutter_startup_perpendicular = true;
    let moving_start = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1 X-40.\nG01 X50. F500.\nY50.\nG40\nM30\n";
    let moving_cancel = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\nY50.\nG40 X0\nM30\n";
    let arc_mode = "G90 G00 X-50. Y0 Z0 B0 C0\nG02 X-30. Y0 R10. F500.\nG41.2 D1\nG01 X50. F500.\nY50.\nG40\nM30\n";
    let no_move_after = "G90 G00 X-50. Y0 Z0 B0 C0\nG01 G41.2 D1 F500.\nM08\nX50.\nY50.\nG40\nM30\n";
    let dwell_after = "G90 G00 X-50. Y0 Z0 B0 C0\nG01 G41.2 D1 F500.\nG04 P100\nX50.\nY50.\nG40\nM30\n";
    let on_30i = |c: &mut Config| c.edit_machine(suv);
    for (src, line) in [(moving_start, 2), (moving_cancel, 5), (arc_mode, 3), (no_move_after, 3), (dwell_after, 3)] {
        assert_eq!(first_alarm_with(src, "head-bc", sixteen_i(suv)), Some(("PS5460".into(), line)), "{src}");
        assert_eq!(first_alarm_with(src, "head-bc", on_30i), Some(("PS5460".into(), line)), "{src}");
        // Without SUV (type A/B) the same programs start up and cancel with the moves.
        assert_eq!(first_alarm_with(src, "head-bc", |_| {}), None, "{src}");
    }
    // The block after G41.2 may move the rotary axes only, or by an arc (rule 13).
    let rotary_after = "G90 G00 X-50. Y0 Z0 B0 C0\nG01 G41.2 D1 F500.\nB0.\nX50.\nY50.\nG40\nM30\n";
    assert_eq!(first_alarm_with(rotary_after, "head-bc", on_30i), None);
    // Without a move, type C is the 30i's: a straight move of the G41.2 block by 5 perpendicular
    // to the first block, (−50, 5); the corner at (50, 0) inside, (45, 5); the block before the
    // G40 ends perpendicular to itself, (45, 50), and the G40 block moves to (50, 50).
    let ok = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\nY50.\nG40\nM30\n";
    let (a, b) = (ends_with(ok, "head-bc", sixteen_i(suv)), ends_with(ok, "head-bc", on_30i));
    assert_eq!((&a.alarm, &b.alarm), (&None, &None));
    let want = [
        (1, [-50.0, 0.0, 0.0]),
        (2, [-50.0, 5.0, 0.0]),
        (3, [45.0, 5.0, 0.0]),
        (4, [45.0, 50.0, 0.0]),
        (5, [50.0, 50.0, 0.0]),
    ];
    assert!(near(&a, &want), "{:?}", a.ends);
    assert_eq!(a.ends, b.ends);
}

#[test]
fn the_16i_refuses_dwell_nurbs_in_feed_and_mst_with_a_move_in_the_mode() {
    // A-78438E p.27–28, "Commands that cannot be specified": dwell G04, G05, G06.2, G160/G161,
    // and M, S, T with a motion command. The 30i takes G04 and M with a move there.
    let src =
        |block: &str| format!("G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\n{block}\nY50.\nG40 X-50.\nM30\n");
    for block in ["G04 P100", "X60. M08", "X60. S1000", "G06.2 P3 K0 X0 Y0 R1.", "G05 P10000"] {
        assert_eq!(first_alarm_with(&src(block), "head-bc", sixteen_i(|_| {})), Some(("PS5460".into(), 4)), "{block}");
    }
    for block in ["G04 P100", "X60. M08"] {
        assert_eq!(first_alarm_with(&src(block), "head-bc", |_| {}), None, "{block}");
    }
    // M alone (no move) and M in the G40 block are allowed.
    assert_eq!(first_alarm_with(&src("M08"), "head-bc", sixteen_i(|_| {})), None);
    let cancel_m = "G90 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\nY50.\nG40 X-50. M09\nM30\n";
    assert_eq!(first_alarm_with(cancel_m, "head-bc", sixteen_i(|_| {})), None);
}

#[test]
fn the_16i_has_g41_2_g42_2_and_g41_3_only() {
    let src = |g: &str| {
        format!("G90 G00 X-50. Y0 Z0 B0 C0\nG43.5 H1\n{g} D1\nG01 X50. I0 J0 K1. F500.\nG40 X-50.\nG49\nM30\n")
    };
    assert_eq!(first_alarm_with(&src("G41.6"), "head-bc", sixteen_i(|_| {})), Some(("PS0010".into(), 3)));
    assert_eq!(first_alarm_with(&src("G41.6"), "head-bc", |_| {}), None);
}

#[test]
fn the_leading_edge_offset_is_the_same_on_both() {
    // A-78438E §1.2 (Fig. 1.2 (d)–(f), p.21–23) is the 30i's §3.1.3–§3.1.4 (`leading_edge.rs`):
    // the variant changes nothing there.
    let src = "G90 G00 X0 Y0 Z0 B30. C0\nG41.3 D1\nG01 X50. F500.\nY50.\nX0 Z10.\nG40\nM30\n";
    let (a, b) = (ends_of(src, "head-bc"), ends_with(src, "head-bc", sixteen_i(|_| {})));
    assert_eq!((&a.alarm, &b.alarm), (&None, &None));
    assert!(a.ends.len() >= 5);
    assert_eq!(a.ends, b.ends);
}

mod random {
    //! Invariants on random contours (head-bc, the tool tilted anywhere, each point moved along
    //! the tool by its own amount): the 16i variant is the 30i with NI5 = 1 (the check in the
    //! compensation plane) and without avoidance — the same ends and the same alarm; and a
    //! No.19630 below every block's move in its plane changes nothing.

    use super::*;
    use proptest::prelude::*;

    fn program(b: f64, c: f64, points: &[(f64, f64, f64)]) -> String {
        let mut src = format!("G90 G00 X-120. Y0 Z0 B{b:.3} C{c:.3}\nG41.2 D1\nG01 F800. ");
        for (x, y, z) in points.iter().chain(std::iter::once(&points[0])) {
            src += &format!("X{x:.6} Y{y:.6} Z{z:.6}\n");
        }
        src + "G40 X-120. Y0 Z0\nM30\n"
    }

    /// A star-shaped polygon around the origin (inner and outer corners) with Z moves.
    fn contour() -> impl Strategy<Value = Vec<(f64, f64, f64)>> {
        prop::collection::vec((0.0..std::f64::consts::TAU, 20.0..80.0, -20.0..20.0f64), 4..9).prop_map(|mut v| {
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.into_iter().map(|(a, r, z)| (r * a.cos(), r * a.sin(), z)).collect()
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(40), ..ProptestConfig::default() })]
        #[test]
        fn the_16i_is_the_30i_checking_in_the_plane(b in -60.0..60.0f64, c in -180.0..180.0f64, points in contour()) {
            let src = program(b, c, &points);
            let ni5 = |cfg: &mut Config| cfg.edit_machine(|m| m.five_axis.crc_check_in_plane = true);
            let (a, s) = (ends_with(&src, "head-bc", ni5), ends_with(&src, "head-bc", sixteen_i(|_| {})));
            prop_assert_eq!(&a.alarm, &s.alarm, "{}", src);
            prop_assert_eq!(&a.ends, &s.ends, "{}", src);
            // With CAV the 30i (NI5 = 1) may avoid; the 16i does not: where the 30i without
            // CAV stops, so does the 16i with it.
            let cav = sixteen_i(|m| m.motion.cutter_interference_avoidance = true);
            prop_assert_eq!(&ends_with(&src, "head-bc", cav).alarm, &a.alarm, "{}", src);
        }

        #[test]
        fn a_limit_below_every_move_changes_nothing(b in -60.0..60.0f64, c in -180.0..180.0f64, points in contour()) {
            // Corners at least a few mm apart in any plane the tilt gives (the polygon's sides are
            // ≥ 0 long, so keep the limit far below: 1 µm, and skip contours with a shorter side).
            let tool = {
                let (sb, cb) = b.to_radians().sin_cos();
                let (sc, cc) = c.to_radians().sin_cos();
                fivex_engine::kin::Vec3::new(sb * cc, sb * sc, cb)
            };
            let ring: Vec<_> = points.iter().chain(std::iter::once(&points[0])).collect();
            let shortest = ring.windows(2).map(|w| {
                let d = fivex_engine::kin::Vec3::new(w[1].0 - w[0].0, w[1].1 - w[0].1, w[1].2 - w[0].2);
                (d - tool * d.dot(&tool)).norm()
            }).fold(f64::INFINITY, f64::min);
            prop_assume!(shortest > 0.01);
            let src = program(b, c, &points);
            let plain = ends_with(&src, "head-bc", sixteen_i(|_| {}));
            let limited = ends_with(&src, "head-bc", sixteen_i(|m| m.five_axis.non_movement_limit = 0.001));
            prop_assert_eq!(&plain.alarm, &limited.alarm, "{}", src);
            prop_assert_eq!(&plain.ends, &limited.ends, "{}", src);
        }
    }
}

#[test]
fn a_plane_change_in_the_mode_is_ps0037() {
    // A-78438E p.38: P/S0037 "CRC:PLANE CHANGE — an attempt was made to change the plane in the
    // cutter compensation mode" — as on the 30i (the interpreter's rule 1).
    let src = "G90 G17 G00 X-50. Y0 Z0 B0 C0\nG41.2 D1\nG01 X50. F500.\nG18\nY50.\nG40 X-50.\nM30\n";
    assert_eq!(first_alarm_with(src, "head-bc", sixteen_i(|_| {})), Some(("PS0037".into(), 4)));
    assert_eq!(first_alarm_with(src, "head-bc", |_| {}), Some(("PS0037".into(), 4)));
}
