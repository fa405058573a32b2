//! Chamfering `,C` and corner rounding `,R` (`interp::chamfer`; `docs/dialects.md`,
//! "Chamfering and corner R"), through the interpreter: random polylines of G01 lines in the
//! XY plane with a random `,C` or `,R` at every corner either end in PS0055 exactly when a line
//! is too short for the chamfers/tangent lengths at its two ends, or give the path the
//! definitions give, computed here independently: each line shortened by `c` (or `r·tan(θ/2)`)
//! at each corner, the chamfer a line between those points, the arc of radius `r` tangent to
//! both lines (its radius at each end perpendicular to the line), turning by the corner's
//! angle; the path continuous and its last point exact. Both dialects that perform them.

use crate::common::*;
use fivex_engine::canon::{CanonKind, Motion, MotionKind};
use fivex_engine::Dialect::{self, Fanuc, Haas};
use proptest::prelude::*;

type P = [f64; 2];

fn dist(a: P, b: P) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn unit(a: P, b: P) -> P {
    let l = dist(a, b);
    [(b[0] - a[0]) / l, (b[1] - a[1]) / l]
}

/// The program's motions, or the first alarm's code.
fn run(src: &str, dialect: Dialect) -> Result<Vec<Motion>, String> {
    let mut interp = interpreter(src, "mill3", dialect);
    let mut v = Vec::new();
    interp.run(|c| v.push(c)).map_err(|a| a.code)?;
    Ok(v.into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Motion(m) => Some(m),
            _ => None,
        })
        .collect())
}

fn xy(m: &Motion) -> P {
    [m.target[0], m.target[1]]
}

/// A polyline from headings and lengths, rounded to the program's 0.001 mm.
fn polyline(start: P, legs: &[(f64, f64)]) -> Vec<P> {
    let r = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut pts = vec![[r(start[0]), r(start[1])]];
    let mut heading: f64 = 0.0;
    let mut at = start;
    for &(turn, len) in legs {
        heading += turn.to_radians();
        at = [at[0] + len * heading.cos(), at[1] + len * heading.sin()];
        pts.push([r(at[0]), r(at[1])]);
    }
    pts
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(64)))]

    #[test]
    fn random_corners_follow_the_definition(
        start in (-50.0..50.0f64, -50.0..50.0f64),
        legs in prop::collection::vec(
            ((10.0..170.0f64, any::<bool>()).prop_map(|(t, left)| if left { t } else { -t }), 5.0..60.0f64),
            2..6,
        ),
        joins in prop::collection::vec((any::<bool>(), 0.5..12.0f64), 5),
        haas in any::<bool>(),
    ) {
        let pts = polyline([start.0, start.1], &legs);
        let n = pts.len();
        // The corners 1..n-1, with their join and size (rounded as written).
        let joins: Vec<(bool, f64)> =
            (1..n - 1).map(|i| (joins[i - 1].0, (joins[i - 1].1 * 1000.0).round() / 1000.0)).collect();
        let mut src = format!("G90 G21 G54 G00 X{:.3} Y{:.3} Z0\n", pts[0][0], pts[0][1]);
        for (i, p) in pts.iter().enumerate().skip(1) {
            let word = match joins.get(i - 1) {
                Some(&(true, s)) if i < n - 1 => format!(" ,R{s:.3}"),
                Some(&(false, s)) if i < n - 1 => format!(" ,C{s:.3}"),
                _ => String::new(),
            };
            src += &format!("G01 X{:.3} Y{:.3}{word} F1000.\n", p[0], p[1]);
        }
        src += "M30\n";
        // The tangent length at each corner, and the turn there (signed, + left).
        let mut t = vec![0.0; n];
        let mut turn = vec![0.0; n];
        for i in 1..n - 1 {
            let (d1, d2) = (unit(pts[i - 1], pts[i]), unit(pts[i], pts[i + 1]));
            let cross = d1[0] * d2[1] - d1[1] * d2[0];
            let th = cross.abs().atan2(d1[0] * d2[0] + d1[1] * d2[1]);
            turn[i] = th.copysign(cross);
            let (round, s) = joins[i - 1];
            t[i] = if round { s * (th / 2.0).tan() } else { s };
        }
        // Each line must hold the tangent lengths at both its ends.
        let slack: Vec<f64> = (1..n).map(|i| dist(pts[i - 1], pts[i]) - t[i - 1] - t[i]).collect();
        prop_assume!(slack.iter().all(|s| s.abs() > 1e-6));
        let dialect = if haas { Haas } else { Fanuc };
        let got = run(&src, dialect);
        if slack.iter().any(|&s| s < 0.0) {
            let want = if haas { "752" } else { "PS0055" };
            let code = got.err();
            prop_assert_eq!(code.as_deref(), Some(want), "{}", src);
            return Ok(());
        }
        let ms = got.map_err(|e| TestCaseError::fail(format!("{e} in\n{src}")))?;
        // The rapid, then per line: the line to p1, the chamfer or arc to p2; then the last line.
        let mut k = 1;
        let mut here = xy(&ms[0]);
        prop_assert!(dist(here, pts[0]) < 1e-9);
        for i in 1..n - 1 {
            let (d1, d2) = (unit(pts[i - 1], pts[i]), unit(pts[i], pts[i + 1]));
            let p1 = [pts[i][0] - t[i] * d1[0], pts[i][1] - t[i] * d1[1]];
            let p2 = [pts[i][0] + t[i] * d2[0], pts[i][1] + t[i] * d2[1]];
            let line = &ms[k];
            prop_assert_eq!(line.kind, MotionKind::Linear);
            prop_assert!(dist(xy(line), p1) < 1e-9, "corner {i}: p1 {:?} vs {:?}\n{src}", xy(line), p1);
            // p1 lies on the programmed line, between where the line starts and the corner.
            prop_assert!((dist(here, p1) + dist(p1, pts[i]) - dist(here, pts[i])).abs() < 1e-9);
            let join = &ms[k + 1];
            prop_assert!(dist(xy(join), p2) < 1e-9, "corner {i}: p2\n{src}");
            prop_assert!((dist(p2, pts[i]) - t[i]).abs() < 1e-9 && (dist(p1, pts[i]) - t[i]).abs() < 1e-9);
            let (round, r) = joins[i - 1];
            if round {
                let arc = join.arc.as_ref().expect("an arc");
                let c = [arc.center[0], arc.center[1]];
                prop_assert_eq!(join.kind, if turn[i] > 0.0 { MotionKind::ArcCcw } else { MotionKind::ArcCw });
                prop_assert!((arc.radius - r).abs() < 1e-12);
                prop_assert!((dist(c, p1) - r).abs() < 1e-9 && (dist(c, p2) - r).abs() < 1e-9);
                // Tangent to both lines: the radius at each end is perpendicular to its line.
                prop_assert!(((p1[0] - c[0]) * d1[0] + (p1[1] - c[1]) * d1[1]).abs() < 1e-9);
                prop_assert!(((p2[0] - c[0]) * d2[0] + (p2[1] - c[1]) * d2[1]).abs() < 1e-9);
                prop_assert!((arc.sweep_deg - turn[i].to_degrees()).abs() < 1e-9);
                prop_assert_eq!(arc.plane_axes, (0, 1, 2));
            } else {
                prop_assert_eq!(join.kind, MotionKind::Linear);
            }
            here = p2;
            k += 2;
        }
        prop_assert_eq!(ms.len(), k + 1, "{}", src);
        let last = &ms[k];
        prop_assert_eq!(last.kind, MotionKind::Linear);
        prop_assert!(dist(xy(last), pts[n - 1]) < 1e-12);
        prop_assert!(ms.iter().all(|m| m.target[2] == 0.0));
    }
}

/// A `,C` block's pieces carry its line, N and F; the next block's line carries its own.
#[test]
fn pieces_belong_to_the_first_block() {
    let src = "G90 G00 X0 Y0\nN7 G01 X10. ,R2. F300.\nN8 Y10. F600.\nM30\n";
    let mut interp = interpreter(src, "mill3", Fanuc);
    let mut got = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                got.push((c.line, c.n, m.feed, m.kind));
            }
        })
        .expect("runs");
    // The rapid's feed is whatever F was before; the three moves carry their blocks' F.
    let want = [
        (1, None, got[0].2, MotionKind::Rapid),
        (2, Some(7), 300.0, MotionKind::Linear),
        (2, Some(7), 300.0, MotionKind::ArcCcw),
        (3, Some(8), 600.0, MotionKind::Linear),
    ];
    assert_eq!(got, want);
}

/// The values are lengths: in G20 inches, without a decimal point least increments (like R).
#[test]
fn values_are_lengths() {
    let ends = |src: &str| run(src, Fanuc).expect("runs").iter().map(xy).collect::<Vec<_>>();
    let inch = ends("G90 G20 G00 X0 Y0\nG01 X1. ,C.1 F10.\nY1.\nM30\n");
    assert!(dist(inch[1], [0.9 * 25.4, 0.0]) < 1e-9 && dist(inch[2], [25.4, 0.1 * 25.4]) < 1e-9, "{inch:?}");
    let increments = ends("G90 G21 G00 X0 Y0\nG01 X10. ,C500 F100.\nY10.\nM30\n");
    assert!(dist(increments[1], [9.5, 0.0]) < 1e-9, "{increments:?}");
}

/// `,C0` leaves the corner sharp; a negative value is refused (PS0009).
#[test]
fn zero_keeps_the_corner_and_a_negative_value_is_refused() {
    let ms = run("G90 G00 X0 Y0\nG01 X10. ,C0 F100.\nY10.\nM30\n", Fanuc).expect("runs");
    assert_eq!(ms.iter().map(xy).collect::<Vec<_>>(), vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]]);
    assert_eq!(run("G90 G00 X0 Y0\nG01 X10. ,C-1. F100.\nY10.\nM30\n", Fanuc).err().as_deref(), Some("PS0009"));
}

/// Under cutter compensation C (offset mode) the chamfered path is offset like any other: with
/// G41 D1 (radius 5) the line along +X runs at Y5, the chamfer from X35 Y0 to X40 Y-5 at 5 on
/// its left, the line down at X45; the two corners are outside corners of 45° (interior 135°),
/// so each is the crossing of the offset lines: X35 + 5·tan 22.5° = X37.0710678 at Y5, and
/// Y-5 + 5·tan 22.5° = Y-2.9289322 at X45. Start-up is type A (the vector perpendicular to the
/// next block: X0 Y5); the cancel block along +X makes an inside corner with the line down, so
/// that line ends where the offset lines cross, X45 Y-25.
#[test]
fn the_chamfered_path_is_offset_under_cutter_compensation() {
    let t = 5.0 * (22.5f64).to_radians().tan();
    let src = "G90 G21 G54 G00 X-20. Y-20. Z0\nG41 D1 G01 X0 Y0 F500.\nX40. ,C5.\nY-30.\nG40 X60.\nM30\n";
    assert_ends(
        src,
        "mill3",
        &[
            (1, [-20.0, -20.0, 0.0]),
            (2, [0.0, 5.0, 0.0]),
            (3, [35.0 + t, 5.0, 0.0]),
            (3, [45.0, -5.0 + t, 0.0]),
            (4, [45.0, -25.0, 0.0]),
            (5, [60.0, -30.0, 0.0]),
        ],
    );
    // A ,C in the start-up block or in the cancel block is not built (PS0010 at that block).
    let start_up = "G90 G00 X-20. Y-20.\nG41 D1 G01 X0 Y0 ,C1. F500.\nX40.\nG40 X60.\nM30\n";
    assert_eq!(first_alarm(start_up, "mill3"), Some(("PS0010".into(), 2)));
    let cancel = "G90 G00 X-20. Y-20.\nG41 D1 G01 X0 Y0 F500.\nG40 X40. ,C1.\nY-30.\nM30\n";
    assert_eq!(first_alarm(cancel, "mill3"), Some(("PS0010".into(), 3)));
}

/// The next block may name an axis off the plane that stays where it is; one that moves is
/// PS0051, and so is a next block that moves only off the plane.
#[test]
fn the_next_block_moves_in_the_plane_only() {
    let ms = run("G90 G00 X0 Y0 Z0\nG01 X10. ,C1. F100.\nY10. Z0\nM30\n", Fanuc).expect("runs");
    assert_eq!(ms.iter().map(xy).collect::<Vec<_>>(), vec![[0.0, 0.0], [9.0, 0.0], [10.0, 1.0], [10.0, 10.0]]);
    for next in ["Y10. Z-1.", "Z-1."] {
        let src = format!("G90 G00 X0 Y0 Z0\nG01 X10. ,C1. F100.\n{next}\nM30\n");
        assert_eq!(run(&src, Fanuc).err().as_deref(), Some("PS0051"), "{next}");
    }
}
