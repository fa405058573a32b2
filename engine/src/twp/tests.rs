//! Every TV-TWP frame example of the extract, and the forms agreeing with each other.

// The expected values are the extract's printed six-decimal numbers, kept as printed.
#![allow(clippy::approx_constant)]

use super::*;
use proptest::prelude::*;

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The frame's axes against the extract's (6 decimals).
fn axes(f: &Rigid, x: [f64; 3], y: [f64; 3], z: [f64; 3]) {
    for (got, want, name) in [(f.x(), x, "Xc"), (f.y(), y, "Yc"), (f.z(), z, "Zc")] {
        assert!((got - v(want[0], want[1], want[2])).norm() < 2e-6, "{name}: {got:?} vs {want:?}");
    }
}

#[test]
fn euler_tv_twp_01_to_04_and_07() {
    // TV-TWP-01: G68.2 X20 Y5 Z0 I0 J90 K0.
    let f = euler(v(20.0, 5.0, 0.0), 0.0, 90.0, 0.0);
    axes(&f, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]);
    // TV-TWP-02: the FCS point (-15, 0, -15) is WCS (5, 20, 0).
    assert!((f.to_parent(&v(-15.0, 0.0, -15.0)) - v(5.0, 20.0, 0.0)).norm() < 1e-12);
    // TV-TWP-03: G68.2 X5 Y20 Z0 I90 J90 K0 (parent WCS).
    let f3 = euler(v(5.0, 20.0, 0.0), 90.0, 90.0, 0.0);
    axes(&f3, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    // TV-TWP-04: G68.4 X-15 Y0 Z-15 I90 J90 K90 inside TV-TWP-01's frame.
    let f4 = f.then(&euler(v(-15.0, 0.0, -15.0), 90.0, 90.0, 90.0));
    assert!((f4.o - v(5.0, 20.0, 0.0)).norm() < 1e-12);
    axes(&f4, [0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]);
    // TV-TWP-07, 07b, 07c.
    axes(
        &euler(Vec3::zeros(), 30.0, 45.0, 60.0),
        [0.126826, 0.780330, 0.612372],
        [-0.926777, -0.126826, 0.353553],
        [0.353553, -0.612372, 0.707107],
    );
    let f7b = euler(v(100.0, 0.0, 0.0), 0.0, 30.0, 0.0);
    for (p, want) in [
        (v(10.0, 0.0, 0.0), v(110.0, 0.0, 0.0)),
        (v(0.0, 10.0, 0.0), v(100.0, 8.660254, 5.0)),
        (v(0.0, 0.0, 10.0), v(100.0, -5.0, 8.660254)),
    ] {
        assert!((f7b.to_parent(&p) - want).norm() < 1e-6, "{p:?}");
        assert!((f7b.from_parent(&want) - p).norm() < 1e-6, "inverse of {p:?}");
    }
    axes(&euler(Vec3::zeros(), 0.0, 0.0, 45.0), [0.707107, 0.707107, 0.0], [-0.707107, 0.707107, 0.0], [0.0, 0.0, 1.0]);
}

#[test]
fn roll_pitch_yaw_tv_twp_08_and_09() {
    let rpy = |q: Option<u32>| roll_pitch_yaw(Vec3::zeros(), q, 30.0, 45.0, 60.0).unwrap();
    let q123 = ([0.353553, 0.612372, -0.707107], [-0.573223, 0.739199, 0.353553], [0.739199, 0.280330, 0.612372]);
    axes(&rpy(Some(123)), q123.0, q123.1, q123.2);
    axes(&rpy(None), q123.0, q123.1, q123.2);
    axes(
        &rpy(Some(321)),
        [0.353553, 0.926777, 0.126826],
        [-0.612372, 0.126826, 0.780330],
        [0.707107, -0.353553, 0.612372],
    );
    axes(
        &rpy(Some(132)),
        [0.353553, 0.866025, -0.353553],
        [-0.176777, 0.433013, 0.883883],
        [0.918559, -0.25, 0.306186],
    );
    axes(&rpy(Some(213)), [0.047367, 0.789149, -0.612372], [-0.75, 0.433013, 0.5], [0.659740, 0.435596, 0.612372]);
    axes(&rpy(Some(231)), [0.353553, 0.883883, -0.306186], [-0.866025, 0.433013, 0.25], [0.353553, 0.176777, 0.918559]);
    axes(&rpy(Some(312)), [0.659740, 0.75, -0.047367], [-0.435596, 0.433013, 0.789149], [0.612372, -0.5, 0.612372]);
    let e = roll_pitch_yaw(Vec3::zeros(), Some(123), 90.0, 90.0, 0.0).unwrap();
    axes(&e, [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]);
    for q in [124, 0, 12, 111] {
        assert_eq!(roll_pitch_yaw(Vec3::zeros(), Some(q), 1.0, 2.0, 3.0), Err(AlarmId::TwpFormat), "Q{q}");
    }
}

#[test]
fn three_points_tv_twp_10_and_11() {
    let pts = [Vec3::zeros(), v(10.0, 0.0, 0.0), v(0.0, 10.0, 10.0)];
    let s = 0.707107;
    axes(&three_points(pts, Vec3::zeros(), 0.0, 0.0).unwrap(), [1.0, 0.0, 0.0], [0.0, s, s], [0.0, -s, s]);
    axes(&three_points(pts, Vec3::zeros(), 90.0, 0.0).unwrap(), [0.0, s, s], [-1.0, 0.0, 0.0], [0.0, -s, s]);
    let c =
        three_points([v(10.0, 20.0, 0.0), v(30.0, 20.0, 0.0), v(10.0, 40.0, -20.0)], Vec3::zeros(), 0.0, 0.0).unwrap();
    assert_eq!(c.o, v(10.0, 20.0, 0.0));
    axes(&c, [1.0, 0.0, 0.0], [0.0, s, -s], [0.0, s, s]);
    // TV-TWP-10d: the Q0 shift along the FCS axes.
    assert!((three_points(pts, v(5.0, 0.0, 0.0), 0.0, 0.0).unwrap().o - v(5.0, 0.0, 0.0)).norm() < 1e-12);
    // TV-TWP-11, 11b, 11c: collinear, coincident, an unstable plane under No.11220 = 0.001.
    let refused = |p: [Vec3; 3], min: f64| three_points(p, Vec3::zeros(), 0.0, min) == Err(AlarmId::TwpFormat);
    assert!(refused([Vec3::zeros(), v(10.0, 0.0, 0.0), v(20.0, 0.0, 0.0)], 0.0));
    assert!(refused([Vec3::zeros(), Vec3::zeros(), v(0.0, 10.0, 0.0)], 0.0));
    assert!(refused([Vec3::zeros(), v(100.0, 0.0, 0.0), v(50.0, 0.0005, 0.0)], 0.001));
    assert!(!refused([Vec3::zeros(), v(100.0, 0.0, 0.0), v(50.0, 0.0005, 0.0)], 0.0001));
}

#[test]
fn two_vectors_tv_twp_12() {
    let s = 0.707107;
    let f = two_vectors(Vec3::zeros(), v(1.0, 0.0, 0.0), v(0.0, -1.0, 1.0)).unwrap();
    axes(&f, [1.0, 0.0, 0.0], [0.0, s, s], [0.0, -s, s]);
    // 87.14° is accepted and Z kept exactly; 84.29° and 95.71° are refused; zero vectors too.
    let f = two_vectors(Vec3::zeros(), v(1.0, 0.0, 0.05), v(0.0, 0.0, 1.0)).unwrap();
    axes(&f, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    for x in [v(1.0, 0.0, 0.1), v(1.0, 0.0, -0.1), Vec3::zeros()] {
        assert_eq!(two_vectors(Vec3::zeros(), x, v(0.0, 0.0, 1.0)), Err(AlarmId::TwpFormat), "{x:?}");
    }
    assert_eq!(two_vectors(Vec3::zeros(), v(1.0, 0.0, 0.0), Vec3::zeros()), Err(AlarmId::TwpFormat));
    axes(
        &two_vectors(Vec3::zeros(), v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0)).unwrap(),
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
    );
}

#[test]
fn projection_angles_tv_twp_13() {
    let p = |i, j, k| projection(Vec3::zeros(), i, j, k);
    axes(&p(30.0, 0.0, 0.0).unwrap(), [0.866025, 0.0, -0.5], [0.0, 1.0, 0.0], [0.5, 0.0, 0.866025]);
    axes(&p(0.0, 30.0, 0.0).unwrap(), [1.0, 0.0, 0.0], [0.0, 0.866025, 0.5], [0.0, -0.5, 0.866025]);
    axes(
        &p(30.0, 20.0, 0.0).unwrap(),
        [0.866025, 0.0, -0.5],
        [0.150313, 0.953742, 0.260350],
        [0.476871, -0.300627, 0.825965],
    );
    axes(
        &p(30.0, 20.0, 90.0).unwrap(),
        [0.150313, 0.953742, 0.260350],
        [-0.866025, 0.0, 0.5],
        [0.476871, -0.300627, 0.825965],
    );
    for (i, j) in [(90.0, -90.0), (89.5, -89.5), (90.0, 90.0)] {
        assert_eq!(p(i, j, 0.0), Err(AlarmId::TwpFormat), "I{i} J{j}");
    }
}

#[test]
fn tool_axis_tv_twp_14() {
    // BC head at B30 C0: tool (0.5, 0, 0.866025); No.12321 = 3 (Z vertical).
    let tool = v(0.5, 0.0, 3f64.sqrt() / 2.0);
    let f = tool_axis(Vec3::zeros(), tool, Vec3::z(), 0.0, 1.0).unwrap();
    axes(&f, [0.0, 1.0, 0.0], [-0.866025, 0.0, 0.5], [0.5, 0.0, 0.866025]);
    let f = tool_axis(Vec3::zeros(), tool, Vec3::z(), 90.0, 1.0).unwrap();
    axes(&f, [-0.866025, 0.0, 0.5], [0.0, -1.0, 0.0], [0.5, 0.0, 0.866025]);
    // The tool along the vertical axis: the fallback X (+X for a vertical Z).
    axes(
        &tool_axis(Vec3::zeros(), Vec3::z(), Vec3::z(), 0.0, 1.0).unwrap(),
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    );
}

/// The frame part of the issue's example: G68.2 X100 Y100 Z50 I30 J15 K20 puts the FCS point
/// (0, 0, 0) at WCS (100, 100, 50) (the motion part waits for TWP in the interpreter).
#[test]
fn issue_example_origin() {
    let f = euler(v(100.0, 100.0, 50.0), 30.0, 15.0, 20.0);
    assert_eq!(f.to_parent(&Vec3::zeros()), v(100.0, 100.0, 50.0));
    assert!((f.z().norm() - 1.0).abs() < 1e-12 && (f.r.transpose() * f.r - Matrix3::identity()).norm() < 1e-12);
}

proptest! {
    /// The same plane through every form: three points taken on the Euler frame's axes, its X
    /// and Z as two vectors, give the Euler frame back; every frame is a rotation.
    #[test]
    fn three_points_and_two_vectors_agree_with_euler(
        o in prop::array::uniform3(-500.0..500.0f64),
        i in -180.0..180.0f64, j in -180.0..180.0f64, k in -180.0..180.0f64,
        dx in 1.0..200.0f64, dy in 1.0..200.0f64, along in -100.0..100.0f64,
    ) {
        let e = euler(v(o[0], o[1], o[2]), i, j, k);
        prop_assert!((e.r.transpose() * e.r - Matrix3::identity()).norm() < 1e-12);
        prop_assert!((e.r.determinant() - 1.0).abs() < 1e-12);
        let p = [e.o, e.to_parent(&v(dx, 0.0, 0.0)), e.to_parent(&v(along, dy, 0.0))];
        let t = three_points(p, Vec3::zeros(), 0.0, 0.0).unwrap();
        prop_assert!((t.r - e.r).norm() < 1e-9 && (t.o - e.o).norm() < 1e-9);
        let w = two_vectors(e.o, e.x() * dx, e.z() * dy).unwrap();
        prop_assert!((w.r - e.r).norm() < 1e-9);
        // Projection-angle frames are rotations too.
        let pr = projection(e.o, i, j.clamp(-80.0, 80.0), 0.0);
        if let Ok(pr) = pr {
            prop_assert!((pr.r.transpose() * pr.r - Matrix3::identity()).norm() < 1e-9);
            prop_assert!((pr.r.determinant() - 1.0).abs() < 1e-9);
        }
    }
}
