//! Syntec's tilted working plane teach function (§3.3–§3.4, spec `syntec.md` SYN-13…SYN-17 and
//! the teach rows TV-28, TV-29…TV-29d, TV-44): latching the tip from the machine, each teach
//! mode's frame and its failures, the Euler angles back from a frame, and the G68.2 block — run
//! on the controller, it sets the plane that was taught.

use fivex_engine::controller::{Controller, Mode, RunState};
use fivex_engine::geom::Vec3;
use fivex_engine::interp::Config;
use fivex_engine::kin::Kinematics;
use fivex_engine::machine::MachineConfig;
use fivex_engine::teach::{self, euler_angles, LatchRefused, Latched, Method, Points, Slot};
use fivex_engine::twp;
use fivex_engine::Dialect;
use proptest::prelude::*;

const TICK: f64 = 0.002;

fn preset(name: &str) -> MachineConfig {
    MachineConfig::preset(name).unwrap()
}

/// A controller for `preset` with H1 = 50 mm.
fn controller(name: &str, dialect: Dialect) -> Controller {
    let mut c = Controller::new(Config::new(preset(name), dialect));
    c.interpreter_mut().state.offsets.tool_mut(1).unwrap().h_geometry = 50.0;
    c
}

/// Run `text` in MDI to its end (within 60 simulated seconds).
fn mdi(c: &mut Controller, text: &str) {
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi(text).unwrap();
    c.cycle_start().unwrap();
    let start = c.time();
    while c.run_state() == RunState::Running && c.time() - start < 60.0 {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Idle, "{text}: {:?}", c.alarms());
}

fn at(x: f64, y: f64, z: f64) -> Latched {
    Latched { point: Vec3::new(x, y, z), tool: Vec3::z() }
}

fn points(p: &[Latched]) -> Points {
    let mut out = Points::default();
    for (slot, l) in Slot::ALL.into_iter().zip(p) {
        out.set(slot, *l);
    }
    out
}

fn close(a: Vec3, b: Vec3, tol: f64) -> bool {
    (a - b).norm() < tol
}

// --- the teach modes (§3.4) ------------------------------------------------------------------

#[test]
fn tv_44_three_points_p3_on_minus_y_turns_the_plane_over() {
    let taught =
        teach::teach(Method::ThreePoints, &points(&[at(0.0, 0.0, 0.0), at(10.0, 0.0, 0.0), at(0.0, -5.0, 0.0)]))
            .unwrap();
    let f = taught.frame;
    assert!(close(f.x(), Vec3::x(), 1e-12) && close(f.y(), -Vec3::y(), 1e-12) && close(f.z(), -Vec3::z(), 1e-12));
    assert_eq!(taught.block, "G68.2 X0. Y0. Z0. I0. J180. K0.");
}

#[test]
fn three_points_origin_x_direction_and_y_side() {
    // P1 (10, 20, 5), P2 along (1, 1, 0) from it, P3 on the +Z side: the plane XZ-like, tilted.
    let p = points(&[at(10.0, 20.0, 5.0), at(13.0, 23.0, 5.0), at(10.0, 20.0, 9.0)]);
    let f = teach::teach(Method::ThreePoints, &p).unwrap().frame;
    let s = 0.5f64.sqrt();
    assert!(close(f.o, Vec3::new(10.0, 20.0, 5.0), 1e-12));
    assert!(close(f.x(), Vec3::new(s, s, 0.0), 1e-12), "{:?}", f.x());
    assert!(close(f.y(), Vec3::z(), 1e-12), "{:?}", f.y());
    assert!(close(f.z(), Vec3::new(s, -s, 0.0), 1e-12), "{:?}", f.z());
}

#[test]
fn tv_28_collinear_or_coincident_points_fail() {
    for p in [
        [at(0.0, 0.0, 0.0), at(10.0, 0.0, 0.0), at(25.0, 0.0, 0.0)],
        [at(0.0, 0.0, 0.0), at(10.0, 10.0, 10.0), at(-3.0, -3.0, -3.0)],
        [at(1.0, 2.0, 3.0), at(1.0, 2.0, 3.0), at(5.0, 0.0, 0.0)],
        // Off the line by less than one BLU.
        [at(0.0, 0.0, 0.0), at(100.0, 0.0, 0.0), at(50.0, 0.0005, 0.0)],
    ] {
        assert_eq!(teach::teach(Method::ThreePoints, &points(&p)), Err(teach::Failure::Collinear), "{p:?}");
    }
    // One BLU off the line is a plane.
    let p = [at(0.0, 0.0, 0.0), at(100.0, 0.0, 0.0), at(50.0, 0.002, 0.0)];
    assert!(teach::teach(Method::ThreePoints, &points(&p)).is_ok());
}

#[test]
fn a_box_not_latched_fails_the_teach() {
    let only_p1 = points(&[at(0.0, 0.0, 0.0)]);
    assert_eq!(teach::teach(Method::ThreePoints, &only_p1), Err(teach::Failure::Missing(Slot::P2)));
    let euler = Method::Euler { i: 0.0, j: 0.0, k: 0.0 };
    assert_eq!(teach::teach(euler, &Points::default()), Err(teach::Failure::Missing(Slot::P1)));
    let mut p = points(&[at(0.0, 0.0, 0.0), at(1.0, 0.0, 0.0), at(0.0, 1.0, 0.0)]);
    p.clear();
    assert_eq!(teach::teach(Method::ThreePoints, &p), Err(teach::Failure::Missing(Slot::P1)));
}

#[test]
fn tv_29_two_vectors_not_orthogonal_or_zero_fail_and_29c_is_the_identity_at_p1() {
    let p = points(&[at(12.5, -3.0, 40.0)]);
    let two = |x: [f64; 3], z: [f64; 3]| Method::TwoVectors { x: Vec3::from(x), z: Vec3::from(z) };
    assert_eq!(teach::teach(two([1.0, 0.0, 0.0], [1.0, 0.0, 1.0]), &p), Err(teach::Failure::NotOrthogonal));
    assert_eq!(teach::teach(two([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]), &p), Err(teach::Failure::ZeroVector));
    assert_eq!(teach::teach(two([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), &p), Err(teach::Failure::ZeroVector));
    assert_eq!(teach::teach(two([1.0, 0.0, f64::NAN], [0.0, 0.0, 1.0]), &p), Err(teach::Failure::NotFinite));
    // 1° off is refused (FANUC's G68.2 P3 would take it), 0.3° is within the tolerance.
    let (s1, c1) = 1f64.to_radians().sin_cos();
    assert_eq!(teach::teach(two([c1, 0.0, s1], [0.0, 0.0, 1.0]), &p), Err(teach::Failure::NotOrthogonal));
    let (s, c) = 0.3f64.to_radians().sin_cos();
    let near = teach::teach(two([c, 0.0, s], [0.0, 0.0, 2.0]), &p).unwrap();
    assert!(close(near.frame.z(), Vec3::z(), 1e-12) && close(near.frame.x(), Vec3::x(), 1e-12));
    // TV-29c.
    let id = teach::teach(two([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]), &p).unwrap();
    assert_eq!(id.block, "G68.2 X12.5 Y-3. Z40. I0. J0. K0.");
    assert_eq!(id.frame.o, Vec3::new(12.5, -3.0, 40.0));
    // X (0.6, 0, 0.8), Z (−0.8, 0, 0.6): Y is +Y, the plane turned −90° and tilted atan(4/3).
    let tilted = teach::teach(two([0.6, 0.0, 0.8], [-0.8, 0.0, 0.6]), &p).unwrap();
    assert!(close(tilted.frame.y(), Vec3::y(), 1e-12));
    assert_eq!(tilted.block, "G68.2 X12.5 Y-3. Z40. I-90. J53.13 K90.");
    // Unit vectors typed with three decimals are orthogonal enough.
    assert!(teach::teach(two([0.5, 0.5, 0.707], [-0.5, -0.5, 0.707]), &p).is_ok());
}

#[test]
fn euler_mode_gives_the_angles_back_as_typed() {
    // TV-32's plane taught on the screen: P1 (100, 100, 50), I30 J15 K20.
    let p = points(&[at(100.0, 100.0, 50.0)]);
    let taught = teach::teach(Method::Euler { i: 30.0, j: 15.0, k: 20.0 }, &p).unwrap();
    assert_eq!(taught.block, "G68.2 X100. Y100. Z50. I30. J15. K20.");
    assert!(close(taught.frame.z(), Vec3::new(0.129410, -0.224144, 0.965926), 1e-6));
    // A negative J is the same plane as the other solution (I + 180, −J, K + 180).
    let other = teach::teach(Method::Euler { i: 10.0, j: -40.0, k: -30.0 }, &p).unwrap();
    assert_eq!(other.block, "G68.2 X100. Y100. Z50. I-170. J40. K150.");
}

#[test]
fn tool_direction_z_is_the_tool_x_its_right_hand_turned_by_i() {
    let s = 0.5f64.sqrt();
    let tilted = Latched { point: Vec3::new(5.0, 0.0, 0.0), tool: Vec3::new(s, 0.0, s) };
    let f = teach::teach(Method::ToolDirection { i: 0.0 }, &points(&[tilted])).unwrap().frame;
    // Facing the tip from the holder (looking along −tool) with +Z up, the right hand is +Y.
    assert!(close(f.z(), Vec3::new(s, 0.0, s), 1e-12));
    assert!(close(f.x(), Vec3::y(), 1e-12), "{:?}", f.x());
    assert!(close(f.y(), Vec3::new(-s, 0.0, s), 1e-12), "{:?}", f.y());
    // I turns X and Y about the tool, right hand.
    let turned = teach::teach(Method::ToolDirection { i: 90.0 }, &points(&[tilted])).unwrap().frame;
    assert!(close(turned.x(), f.y(), 1e-12) && close(turned.y(), -f.x(), 1e-12) && close(turned.z(), f.z(), 1e-12));
    // A vertical tool: the workpiece's own axes.
    let vertical = teach::teach(Method::ToolDirection { i: 30.0 }, &points(&[at(1.0, 2.0, 3.0)])).unwrap();
    assert_eq!(vertical.block, "G68.2 X1. Y2. Z3. I30. J0. K0.");
}

// --- Euler angles back from a frame ---------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::common::cases(512)))]

    /// Any rotation comes back from its Euler angles, J in [0, 180], I and K in (−180, 180].
    #[test]
    fn euler_angles_rebuild_the_rotation(i in -720.0..720.0f64, j in -360.0..360.0f64, k in -720.0..720.0f64) {
        let r = twp::euler(Vec3::zeros(), i, j, k).r;
        let [a, b, c] = euler_angles(&r);
        prop_assert!((0.0..=180.0).contains(&b), "J {}", b);
        prop_assert!(a > -180.0 - 1e-9 && a <= 180.0 && c > -180.0 - 1e-9 && c <= 180.0);
        let back = twp::euler(Vec3::zeros(), a, b, c).r;
        prop_assert!((back - r).abs().max() < 1e-9, "{:?} from {:?}", back, r);
    }
}

/// The words of a G68.2 block by letter.
fn words(block: &str) -> std::collections::HashMap<char, f64> {
    block.split(' ').skip(1).map(|w| (w.chars().next().unwrap(), w[1..].parse().unwrap())).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::common::cases(256)))]

    /// Three points anywhere: X along P1→P2, P3 on the +Y side in the plane, a right-handed
    /// orthonormal frame, and the block's values (to one BLU) give that frame back as G68.2 reads
    /// them (`twp::euler`).
    #[test]
    fn three_points_teach_and_block_round_trip(
        p in proptest::array::uniform3(proptest::array::uniform3(-500.0..500.0f64)),
    ) {
        let v = p.map(Vec3::from);
        let off_line = (v[1] - v[0]).cross(&(v[2] - v[0])).norm() / (v[1] - v[0]).norm().max(1e-12);
        prop_assume!((v[1] - v[0]).norm() > 1.0 && off_line > 1.0);
        let taught = teach::teach(Method::ThreePoints, &points(&v.map(|q| at(q.x, q.y, q.z)))).unwrap();
        let f = taught.frame;
        prop_assert!(close(f.x(), (v[1] - v[0]).normalize(), 1e-9));
        prop_assert!(f.from_parent(&v[2]).y > 0.0 && f.from_parent(&v[2]).z.abs() < 1e-6);
        prop_assert!((f.r.transpose() * f.r - nalgebra::Matrix3::identity()).abs().max() < 1e-9 && f.r.determinant() > 0.0);
        let w = words(&taught.block);
        let back = twp::euler(Vec3::new(w[&'X'], w[&'Y'], w[&'Z']), w[&'I'], w[&'J'], w[&'K']);
        prop_assert!((back.r - f.r).abs().max() < 5e-5, "{} for {:?}", taught.block, f.r);
        prop_assert!((back.o - f.o).abs().max() <= 0.0005 + 1e-9);
    }
}

#[test]
fn euler_angles_at_j_0_and_180_put_the_turn_in_i() {
    for (i, j, k) in [(10.0, 0.0, 25.0), (-70.0, 180.0, 30.0), (0.0, 0.0, 0.0)] {
        let r = twp::euler(Vec3::zeros(), i, j, k).r;
        let [a, b, c] = euler_angles(&r);
        assert_eq!(c, 0.0);
        assert!((b - j).abs() < 1e-9);
        assert!((twp::euler(Vec3::zeros(), a, b, c).r - r).abs().max() < 1e-12);
    }
}

#[test]
fn block_values_are_blu_with_a_decimal_point() {
    let b = teach::g68_2(&Vec3::new(-0.0004, 1234.56789, -7.0), [0.0006, -0.0006, 179.9996]);
    assert_eq!(b, "G68.2 X0. Y1234.568 Z-7. I0.001 J-0.001 K180.");
}

// --- F1 from the machine (§3.3) -------------------------------------------------------------

#[test]
fn tv_29d_latch_needs_length_compensation_and_the_g69_state() {
    let mut c = controller("head-bc", Dialect::Syntec);
    assert_eq!(teach::latch(&c), Err(LatchRefused::LengthCompensationOff));
    mdi(&mut c, "G90 G43 H1 G00 X10. Y0 Z0");
    assert!(teach::latch(&c).is_ok());
    mdi(&mut c, "G49\nG68.2 X0 Y0 Z0 I0 J0 K0\nG43 H1");
    assert_eq!(teach::latch(&c), Err(LatchRefused::PlaneActive));
    mdi(&mut c, "G69\nG44 H1");
    assert!(teach::latch(&c).is_ok());
    mdi(&mut c, "G49");
    assert_eq!(teach::latch(&c), Err(LatchRefused::LengthCompensationOff));
    let mut f = controller("head-bc", Dialect::Fanuc);
    mdi(&mut f, "G90 G43 H1 G00 X10. Y0 Z0");
    assert_eq!(teach::latch(&f), Err(LatchRefused::NotSyntec));
}

#[test]
fn latch_reads_the_tip_through_the_kinematics() {
    // A BC head tilted B30 under G43: the tip is 50 mm down the turned tool from the nose.
    let kin = Kinematics::new(&preset("head-bc")).unwrap();
    let mut c = controller("head-bc", Dialect::Syntec);
    mdi(&mut c, "G90 G54 G43 H1 G01 X10. Y20. Z30. B30. C0 F3000");
    let latched = teach::latch(&c).unwrap();
    let pose = kin.forward(&c.point().machine, 50.0);
    let tip = c.tip();
    assert!(close(latched.tool, pose.tool, 1e-12) && (latched.tool.z - 3f64.sqrt() / 2.0).abs() < 1e-9);
    assert_eq!(latched.point, Vec3::from(tip.tip));
    // Under RTCP X/Y/Z are the tip: the latch gives them back.
    mdi(&mut c, "G49\nG43.4 H1\nG01 X-15. Y5. Z12. B-20. C45.");
    let rtcp = teach::latch(&c).unwrap();
    assert!(close(rtcp.point, Vec3::new(-15.0, 5.0, 12.0), 1e-6), "{:?}", rtcp.point);
    assert!(close(rtcp.tool, kin.forward(&c.point().machine, 50.0).tool, 1e-12));
}

/// Three points latched with the tool, taught, and the G68.2 block run in MDI: a move to
/// feature X10 puts the tip 10 mm along P1→P2, and G53.1 turns the tool to the feature Z.
#[test]
fn the_taught_block_sets_the_plane_that_was_taught() {
    for name in ["head-bc", "table-ac", "mixed-bc"] {
        let mut c = controller(name, Dialect::Syntec);
        let mut p = Points::default();
        mdi(&mut c, "G90 G54 G43.4 H1");
        for (slot, xyz) in [(Slot::P1, "X20. Y10. Z5."), (Slot::P2, "X60. Y40. Z5."), (Slot::P3, "X0 Y30. Z35.")] {
            mdi(&mut c, &format!("G01 {xyz} F3000"));
            p.set(slot, teach::latch(&c).unwrap());
        }
        let taught = teach::teach(Method::ThreePoints, &p).unwrap();
        let x = Vec3::new(0.8, 0.6, 0.0);
        assert!(close(taught.frame.x(), x, 1e-6), "{name}: {:?}", taught.frame.x());
        mdi(&mut c, &format!("G49\n{}\nG53.1\nG43 H1\nG01 X10. Y0 Z0", taught.block));
        let tip = c.tip();
        let want = Vec3::new(20.0, 10.0, 5.0) + x * 10.0;
        assert!(close(Vec3::from(tip.tip), want, 1e-3), "{name}: {:?} for {want:?}", tip.tip);
        assert!(close(Vec3::from(tip.tool), taught.frame.z(), 1e-4), "{name}: {:?}", tip.tool);
    }
}
