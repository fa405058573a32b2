//! Haas G187 corner rounding (`interp::corner_blend`, `fivex_engine::blend`; `docs/dialects.md`,
//! "Haas cycles"): random polylines of G01 moves under `G187 E` stay within E of the
//! programmed polyline on every sample, end exactly at the last point, pass each corner at
//! min(E, what half the moves allow), and turn through a rounded corner by no more than a chord
//! does; a reset and M30 end the mode; P without E keeps the corners exact; the modes the
//! rounding is not built for are refused.

use crate::common::*;
use fivex_engine::blend::rounding;
use fivex_engine::canon::{CanonKind, MotionKind};
use fivex_engine::chords::TOLERANCE_MM;
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect::Haas;
use proptest::prelude::*;

type P3 = [f64; 3];

fn sub(a: &P3, b: &P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: &P3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The distance from `q` to the segment `a`–`b`.
fn to_segment(q: &P3, a: &P3, b: &P3) -> f64 {
    let (ab, aq) = (sub(b, a), sub(q, a));
    let l2 = ab.iter().map(|x| x * x).sum::<f64>();
    let t = if l2 > 0.0 { (ab.iter().zip(&aq).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0) } else { 0.0 };
    norm(&[aq[0] - t * ab[0], aq[1] - t * ab[1], aq[2] - t * ab[2]])
}

/// The turn between the directions of `a`→`b` and `b`→`c`, radians.
fn turn(a: &P3, b: &P3, c: &P3) -> f64 {
    let (u, v) = (sub(b, a), sub(c, b));
    let cos = u.iter().zip(&v).map(|(x, y)| x * y).sum::<f64>() / (norm(&u) * norm(&v));
    cos.clamp(-1.0, 1.0).acos()
}

/// The linear motions (line, end X/Y/Z) a program emits through the stages, Haas on mill3.
fn linear_ends(src: &str) -> Vec<(u32, P3)> {
    let mut out = Vec::new();
    let alarm = through_stages(interpreter(src, "mill3", Haas), |c| {
        if let CanonKind::Motion(m) = &c.kind {
            if m.kind == MotionKind::Linear {
                out.push((c.line, [m.target[0], m.target[1], m.target[2]]));
            }
        }
    });
    assert_eq!(alarm, None, "{src}");
    out
}

/// A program: rapid to the first point, then G01 through the others under `G187 P2 E<e>`.
fn program(points: &[P3], e: f64) -> String {
    let [x, y, z] = points[0];
    let mut src = format!("G187 P2 E{e:.4}\nG00 X{x:.3} Y{y:.3} Z{z:.3}\nG01 F3000.\n");
    for p in &points[1..] {
        src.push_str(&format!("X{:.3} Y{:.3} Z{:.3}\n", p[0], p[1], p[2]));
    }
    src.push_str("M30\n");
    src
}

fn round3(p: P3) -> P3 {
    p.map(|v| (v * 1e3).round() / 1e3)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(24)))]

    #[test]
    fn g187_rounds_every_corner_within_e_and_ends_at_the_last_point(
        raw in prop::collection::vec((-40.0f64..40.0, -40.0f64..40.0, -20.0f64..0.0), 3..7),
        e in 0.001f64..2.0,
    ) {
        let e = (e * 1e4).round() / 1e4;
        let mut points: Vec<P3> = raw.into_iter().map(|(x, y, z)| round3([x, y, z])).collect();
        points.dedup_by(|a, b| norm(&sub(a, b)) < 0.01);
        prop_assume!(points.len() >= 3);
        let src = program(&points, e);
        // Lines: 1 G187, 2 G00, 3 G01 F, then point k (from 1) on line 3 + k.
        let line_of = |k: usize| 3 + k as u32;

        // Every sample of the run within E of the polyline, and the end exactly the last point.
        let mut interp = interpreter(&src, "mill3", Haas);
        let mut worst: f64 = 0.0;
        let polyline = |q: &P3| {
            points.windows(2).map(|s| to_segment(q, &s[0], &s[1])).fold(f64::INFINITY, f64::min)
        };
        let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
            if s.line >= line_of(1) && s.line <= line_of(points.len() - 1) {
                worst = worst.max(polyline(&[s.tip[0], s.tip[1], s.tip[2]]));
            }
        });
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        prop_assert!(worst <= e + 1e-9, "a sample {worst} from the polyline, E {e}\n{src}");
        let last = points[points.len() - 1];
        for (w, l) in r.workpiece.iter().zip(last) {
            prop_assert!((w - l).abs() < 1e-9, "{:?}\n{src}", r.workpiece);
        }

        // The emitted path: its vertices from the first point on.
        let ends = linear_ends(&src);
        let mut path: Vec<(u32, P3)> = vec![(line_of(0), points[0])];
        path.extend(ends.iter().copied());
        let vertex = |i: usize| path[i].1;
        let corners: Vec<_> = (1..points.len() - 1)
            .map(|k| {
                let (a, c, b) = (points[k - 1], points[k], points[k + 1]);
                rounding(turn(&a, &c, &b), norm(&sub(&c, &a)), norm(&sub(&b, &c)), e)
            })
            .collect();
        for k in 1..points.len() - 1 {
            let c = points[k];
            let want = corners[k - 1];
            // Its deviation: the emitted path of the corner's two blocks nearest the corner.
            let near = (1..path.len())
                .filter(|&i| path[i].0 == line_of(k) || path[i].0 == line_of(k + 1))
                .map(|i| to_segment(&c, &vertex(i - 1), &vertex(i)))
                .fold(f64::INFINITY, f64::min);
            let deviation = want.map_or(0.0, |w| w.deviation);
            prop_assert!((near - deviation).abs() < 1e-6, "corner {k}: {near} vs {deviation}\n{src}");
            prop_assert!(deviation <= e + 1e-12);
        }
        // Tangent continuity: at every vertex but an exact corner the path turns by no more
        // than one chord of the arcs it may lie on (those of the rounded corners it is within
        // the tangent distance of); a vertex on no arc is an exact corner.
        for i in 1..path.len() - 1 {
            let (p, q, s) = (vertex(i - 1), vertex(i), vertex(i + 1));
            if norm(&sub(&q, &p)) < 1e-9 || norm(&sub(&s, &q)) < 1e-9 {
                continue;
            }
            let chord = (1..points.len() - 1)
                .filter_map(|k| corners[k - 1].filter(|w| norm(&sub(&q, &points[k])) <= w.tangent + 1e-9))
                .map(|w| 2.0 * (1.0 - TOLERANCE_MM / w.radius).clamp(-1.0, 1.0).acos())
                .fold(None, |m: Option<f64>, c| Some(m.map_or(c, |m| m.max(c))));
            let Some(chord) = chord else {
                prop_assert!(points.contains(&q), "a vertex {q:?} on no arc and no corner\n{src}");
                continue;
            };
            let t = turn(&p, &q, &s);
            prop_assert!(t <= chord + 1e-9, "a turn of {t} at {q:?}, a chord {chord}\n{src}");
        }
    }
}

/// The corner rounding in force after `blocks` blocks of `src` (Haas, mill3), and after a
/// reset then.
fn rounding_after(src: &str, blocks: usize) -> (Option<f64>, Option<f64>) {
    let mut interp = interpreter(src, "mill3", Haas);
    let mut out = Vec::new();
    for _ in 0..blocks {
        interp.step(&mut out).unwrap();
    }
    let on = interp.state.corner_rounding();
    interp.reset();
    (on, interp.state.corner_rounding())
}

#[test]
fn a_reset_and_m30_end_g187_and_e_is_read_in_the_program_s_unit() {
    assert_eq!(rounding_after("G187 P1 E0.05\nG01 X10. F1000.\n", 2), (Some(0.05), None));
    assert!(rounding_after("G187 E0.05\nG01 X10. F1000.\nM30\n", 3).0.is_none());
    // G20: E in inch (the manual's page example, G187 P3 E0.0125).
    let (inch, _) = rounding_after("G20\nG187 P3 E0.0125\n", 2);
    assert!((inch.unwrap() - 0.3175).abs() < 1e-12, "{inch:?}");
    // A later G187 replaces it; without E (Setting 85: 0 on fivex's machines) corners are exact.
    assert!(rounding_after("G187 E0.05\nG187 P3\n", 2).0.is_none());
    assert!(rounding_after("G187 E0.05\nG187\n", 2).0.is_none());
    assert!(rounding_after("G187 E0.05\nG187 E0\n", 2).0.is_none());
}

#[test]
fn without_e_the_corners_stay_exact_and_a_reset_ends_the_rounding() {
    let square = "G01 X10. F1000.\nY10.\nX0\nY0\n";
    let points = |src: &str| linear_ends(src).into_iter().map(|(_, p)| p).collect::<Vec<_>>();
    let exact = points(&format!("{square}M30\n"));
    assert_eq!(exact.len(), 4);
    // P alone: the level's acceleration is not modelled, its rounding is Setting 85's (0).
    assert_eq!(points(&format!("G187 P1\n{square}M30\n")), exact);
    // Rounded, then a reset (program restart from the top) leaves them exact.
    let rounded = linear_ends(&format!("G187 P1 E0.1\n{square}M30\n"));
    assert!(rounded.len() > exact.len());
    let mut interp = interpreter(&format!("G187 P1 E0.1\n{square}"), "mill3", Haas);
    let mut out = Vec::new();
    for _ in 0..3 {
        interp.step(&mut out).unwrap();
    }
    assert_eq!(interp.state.corner_rounding(), Some(0.1));
    interp.reset();
    assert_eq!(interp.state.corner_rounding(), None);
}

#[test]
fn non_motion_blocks_rapids_arcs_and_rotary_moves_keep_their_corner_exact() {
    // Each of these between two G01 moves keeps the corner (10, 0) exact: a vertex there.
    for between in ["#100=1.", "G04 P0.1", "G00 X10.", "G02 X10. Y0 I-1. J0", "M08"] {
        let src = format!("G187 E0.2\nG01 X10. F1000.\n{between}\nG01 Y10.\nM30\n");
        let ends = linear_ends(&src);
        assert!(ends.iter().any(|(_, p)| p == &[10.0, 0.0, 0.0]), "{between}: {ends:?}");
        assert!(ends.iter().all(|(_, p)| p[0] <= 10.0 + 1e-12), "{between}: {ends:?}");
    }
    // A comment alone does not: the corner is rounded.
    let ends = linear_ends("G187 E0.2\nG01 X10. F1000.\n(CORNER)\nY10.\nM30\n");
    assert!(!ends.iter().any(|(_, p)| p == &[10.0, 0.0, 0.0]), "{ends:?}");
}

#[test]
fn the_modes_the_rounding_is_not_built_for_are_refused() {
    let first = |src: &str| {
        let r = run_with(&format!("G00 Z10.\n{src}\nM30\n"), "mill3", Haas);
        r.alarms.first().map(|a| (a.code.clone(), a.line))
    };
    // Cutter compensation: G41 in G187, G187 in G41.
    assert_eq!(first("G187 E0.1\nG41 D1 G01 X10. F100."), Some(("753".into(), 3)));
    assert_eq!(first("G41 D1 G01 X10. F100.\nG187 E0.1"), Some(("753".into(), 3)));
    // Bad arguments: P other than 1–3, a negative E.
    assert_eq!(first("G187 P4"), Some(("746".into(), 2)));
    assert_eq!(first("G187 E-0.1"), Some(("746".into(), 2)));
    // G187 E is G187's argument: `fivex check` reports nothing.
    let diags = fivex_engine::check::check(fivex_engine::lang::parse_file("G187 P3 E0.01\nM30\n"), Haas);
    assert!(diags.is_empty(), "{diags:?}");
}

#[test]
fn tcp_and_dwo_are_refused_in_g187() {
    let r = run_with("G187 E0.1\nG234 H1\nM30\n", "table-ac", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("753", 2)), "{:?}", r.alarms);
    let r = run_with("G187 E0.1\nG254\nM30\n", "table-ac", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("753", 2)), "{:?}", r.alarms);
}

/// Audit A2 F6/F7: the NGC post's `G187 P3 E0.01` then its `G254` lead-in stopped with `310
/// INVALID G CODE`, which calls the valid G254 invalid; the alarm now names the refusal
/// (constructed `753`). `fivex check` reports it without a machine, as it does G28 under G254
/// (730, the post's "Safe retracts = G28" option), reading the blocks in order.
#[test]
fn g187_with_dwo_names_the_refusal_and_check_reports_it() {
    let r = run_with("G187 P3 E0.01\nG00 X0 Y0\nG254\nG255\nM30\n", "table-ac", Haas);
    let alarm = r.alarms.first().expect("refused");
    assert_eq!((alarm.code.as_str(), alarm.line), ("753", 3));
    assert_eq!(alarm.message, "G187 CORNER ROUNDING NOT BUILT IN THIS MODE");
    let found = |src: &str| {
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(src), Haas);
        diags.iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect::<Vec<_>>()
    };
    let at = |line, col, code: &str| vec![(line, col, code.to_string())];
    assert_eq!(found("G187 P3 E0.01\nG00 X0 Y0\nG254\nG255\nM30\n"), at(3, 1, "753"));
    assert_eq!(found("G254\nG00 X0 Y0 Z10.\nG187 P3 E0.01\nG255\nM30\n"), at(3, 1, "753"));
    assert_eq!(found("G187 E0.1\nG00 G234 X0 Y0 Z50. H01\nG49\nM30\n"), at(2, 5, "753"));
    // No rounding (the post's default `G187 P3`: Setting 85 is 0), rounding ended, or M30 between.
    assert_eq!(found("G187 P3\nG254\nG255\nM30\n"), vec![]);
    assert_eq!(found("G187 P2 E0.02\nG187\nG254\nG255\nM30\n"), vec![]);
    assert_eq!(found("G187 E0.02\nM30\nG254\nG255\nM30\n"), vec![]);
    // G28 while G254 is on (not before it, not after G255).
    assert_eq!(found("G28 G91 Z0.\nG90 G254\nG28 G91 Z0.\nG90 G255\nG28 G91 X0. Y0.\nM30\n"), at(3, 1, "730"));
    let r = run_with("G28 G91 Z0.\nG90 G254\nG28 G91 Z0.\nG90 G255\nM30\n", "table-ac", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("730", 3)));
}
