//! The Haas NGC's own cycles (`interp::haas_cycles`, `docs/dialects.md`, "Haas cycles"): G12/G13
//! circular pockets (the tool inside the pocket on every sample, ending at its centre at depth),
//! the bolt patterns G70/G71/G72 (the cycle in force at each hole), G103's block look-ahead
//! limit (a chain of short blocks slows down under P1), and the refusals (G47, G150, bad
//! arguments). G187's corner rounding: `corner_rounding.rs`. The manual's examples are data fixtures, `tests/data/cycles/haas_*.nc`.

use crate::common::*;
use fivex_engine::canon::{CanonKind, MotionKind};
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect::{Fanuc, Haas, Syntec};
use proptest::prelude::*;

/// The holes a program drills: the drilling moves' (G01) X/Y, in order.
fn holes(src: &str) -> Vec<(f64, f64)> {
    let interp = interpreter(src, "mill3", Haas);
    let mut out = Vec::new();
    through_stages(interp, |c| {
        if let CanonKind::Motion(m) = &c.kind {
            if m.kind == MotionKind::Linear {
                out.push((m.target[0], m.target[1]));
            }
        }
    });
    out
}

fn close(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9
}

#[test]
fn g70_drills_l_holes_evenly_around_the_circle_from_j() {
    let src = "G00 X10. Y20. Z10.\nG81 Z-5. R2. F300. L0\nG70 I50. J15. L8\nG80\nM30\n";
    let got = holes(src);
    assert_eq!(got.len(), 8, "{got:?}");
    for (k, h) in got.iter().enumerate() {
        let t = (15.0 + 45.0 * k as f64).to_radians();
        assert!(close(*h, (10.0 + 50.0 * t.cos(), 20.0 + 50.0 * t.sin())), "hole {k}: {h:?}");
    }
    // I negative: the same circle clockwise.
    let cw = holes("G00 Z10.\nG81 Z-5. R2. F300. L0\nG70 I-50. J90. L4\nG80\nM30\n");
    let want = [(0.0, 50.0), (50.0, 0.0), (0.0, -50.0), (-50.0, 0.0)];
    assert!(cw.iter().zip(want).all(|(h, w)| close(*h, w)) && cw.len() == 4, "{cw:?}");
}

#[test]
fn g71_steps_k_degrees_and_g72_steps_i_along_the_line() {
    let arc = holes("G00 Z10.\nG81 Z-5. R2. F300. L0\nG71 I40. J30. K-20. L3\nG80\nM30\n");
    let want: Vec<_> =
        [30.0f64, 10.0, -10.0].iter().map(|a| (40.0 * a.to_radians().cos(), 40.0 * a.to_radians().sin())).collect();
    assert!(arc.len() == 3 && arc.iter().zip(&want).all(|(h, w)| close(*h, *w)), "{arc:?}");
    // G72: the first hole at the block's point, then every I along the angle J.
    let line = holes("G00 X5. Y5. Z10.\nG81 Z-5. R2. F300. L0\nG72 I10. J90. L3\nG80\nM30\n");
    assert!(
        line.len() == 3 && line.iter().zip([(5.0, 5.0), (5.0, 15.0), (5.0, 25.0)]).all(|(h, w)| close(*h, w)),
        "{line:?}"
    );
}

#[test]
fn a_bolt_pattern_block_does_not_drill_its_centre_and_takes_the_cycle_data() {
    // The cycle and the pattern in one block: Z/R/F are the cycle's, X/Y the centre (not
    // drilled), every hole gets G83's pecks to the block's Z.
    let src = "G00 Z10.\nG83 G70 X100. Y0 I10. L2 Z-6. R1. Q2. F200.\nG80\nM30\n";
    let r = run_with(src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    let feeds = holes(src);
    // Two holes, four pecks each (to -1, -3, -5, -6).
    assert_eq!(feeds.len(), 2 * 4, "{feeds:?}");
    assert!(feeds[..4].iter().all(|h| close(*h, (110.0, 0.0))) && feeds[4..].iter().all(|h| close(*h, (90.0, 0.0))));
    assert!(approx(r.workpiece[0], 90.0) && approx(r.workpiece[2], 10.0), "{:?}", r.workpiece);
}

#[test]
fn refusals_and_bad_arguments() {
    let first = |src: &str| {
        let r = run_with(&format!("G00 Z10.\n{src}\nM30\n"), "mill3", Haas);
        r.alarms.first().map(|a| (a.code.clone(), a.line))
    };
    // Not built: text engraving, general purpose pocket milling.
    for src in ["G47 P0 X0 Y0 I0 J0.5 R0.05 Z-0.005 F15. (FIVEX)", "G150 P1 Q2 R0.1 Z-1. I0.4 J0.3 K0.01 F10."] {
        assert_eq!(first(src), Some(("310".into(), 2)), "{src}");
    }
    // `fivex check` reports them at their G word, with the function's name.
    for (src, name) in [("G47 P0 (FIVEX)", "text engraving"), ("G150 P1 Q2 Z-1. F10.", "pocket milling")] {
        let diags =
            fivex_engine::check::check(fivex_engine::lang::parse_file(&format!("G00 Z10.\n{src}\nM30\n")), Haas);
        let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect();
        assert_eq!(found, vec![(2, 1, "310".to_string())], "{src}: {diags:?}");
        assert!(diags[0].detail.contains(name), "{src}: {diags:?}");
    }
    // A bolt pattern without a canned cycle, and its arguments.
    assert_eq!(first("G70 I10. L4"), Some(("310".into(), 2)));
    for src in [
        "G81 Z-1. R1. F100. L0\nG70 L4",
        "G81 Z-1. R1. F100. L0\nG70 I10.",
        "G81 Z-1. R1. F100. L0\nG70 I10. L0",
        "G81 Z-1. R1. F100. L0\nG71 I10. L3",
        "G81 Z-1. R1. F100. L0\nG70 I10. L2.5",
    ] {
        assert_eq!(first(src), Some(("746".into(), 3)), "{src}");
    }
    // G12/G13: I not above the tool radius (D1: 5 mm), K without Q, Q without K, K below I, L
    // in G90, G103 P out of range.
    for src in [
        "G12 I5. D1 Z-1. F100.",
        "G13 I10. K20. D1 Z-1. F100.",
        "G12 I10. Q2. D1 Z-1. F100.",
        "G12 I10. K8. Q1. D1 Z-1. F100.",
        "G12 I10. D1 Z-1. L2 F100.",
        "G12 D1 Z-1. F100.",
        "G103 P16",
        "G103 P-1",
    ] {
        assert_eq!(first(src), Some(("746".into(), 2)), "{src}");
    }
    // A rotary axis word in a pocket's block (head-bc: B C), and more arcs than a block may
    // expand into.
    let r = run_with("G00 Z10.\nG12 I10. D1 Z-1. B10. F100.\nM30\n", "head-bc", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("746", 2)));
    // (The interpreter alone: a run carries out what the block read before the alarm, which
    // would take longer than the time budget.)
    let src = "G00 Z10.\nG91 G12 I6. K400. Q0.04 D1 Z-0.001 L12 F100.\nM30\n";
    assert_eq!(through_stages(interpreter(src, "mill3", Haas), |_| {}), Some(("FX0003".into(), 2)));
    // G12 outside G17, in a canned cycle, under G41 or rotation: refused.
    assert_eq!(first("G18\nG12 I10. D1 Z-1. F100."), Some(("310".into(), 3)));
    assert_eq!(first("G68 X0 Y0 R30.\nG12 I10. D1 Z-1. F100."), Some(("310".into(), 3)));
    // No F yet.
    assert_eq!(first("G12 I10. D1 Z-1."), Some(("320".into(), 2)));
    // The codes are the Haas dialect's only.
    for dialect in [Fanuc, Syntec] {
        for g in ["G12 I10. D1 Z-1. F100.", "G70 I10. L4", "G103 P1"] {
            let r = run_with(&format!("{g}\nM30\n"), "mill3", dialect);
            let want = if dialect == Fanuc { "PS0010" } else { "COR-070" };
            assert_eq!(r.alarms.first().map(|a| a.code.as_str()), Some(want), "{dialect:?} {g}");
        }
    }
}

/// The tool tip on every sample of a pocket run's line 2 (the pocket's block).
fn pocket_samples(src: &str) -> (Vec<[f64; 3]>, fivex_engine::run::RunResult) {
    pocket_samples_with(src, 5.0)
}

/// [`pocket_samples`] with tool offset 7's radius `tool`.
fn pocket_samples_with(src: &str, tool: f64) -> (Vec<[f64; 3]>, fivex_engine::run::RunResult) {
    let mut interp = interpreter(src, "mill3", Haas);
    interp.state.offsets.tool_mut(7).unwrap().d_geometry = tool;
    let mut tips = Vec::new();
    let r = run(&mut interp, &RunOptions { period_s: 0.002, ..RunOptions::default() }, |s| {
        if s.line == 2 {
            tips.push(s.tip)
        }
    });
    (tips, r)
}

#[test]
fn the_manual_s_single_pass_pocket_ends_at_its_centre_at_depth() {
    // G13 I only: down at the centre, out, the circle, back; the tool (D1: radius 5) runs on
    // radius I - 5 and ends at the centre at Z.
    let (tips, r) = pocket_samples("G00 X30. Y40. Z2.\nG13 I20. D7 Z-3. F600.\nM30\n");
    assert!(r.completed(), "{:?}", r.alarms);
    let reach = tips.iter().map(|t| (t[0] - 30.0).hypot(t[1] - 40.0)).fold(0.0, f64::max);
    assert!((reach - 15.0).abs() < 1e-6, "reach {reach}");
    assert!(
        approx(r.workpiece[0], 30.0) && approx(r.workpiece[1], 40.0) && approx(r.workpiece[2], -3.0),
        "{:?}",
        r.workpiece
    );
    // D0: the tool centre on I.
    let (tips, _) = pocket_samples("G00 Z2.\nG12 I20. D0 Z-3. F600.\nM30\n");
    let reach = tips.iter().map(|t| t[0].hypot(t[1])).fold(0.0, f64::max);
    assert!((reach - 20.0).abs() < 1e-6, "reach {reach}");
}

#[test]
fn g91_l_repeats_the_depth_increment() {
    let r = run_with("G00 Z2.\nG91 G12 I10. D1 Z-4. L3 F600.\nG90\nM30\n", "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(approx(r.workpiece[2], -10.0) && approx(r.workpiece[0], 0.0), "{:?}", r.workpiece);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(24)))]

    /// The pocket invariant: on every sample the tool centre stays within K (or I) less the
    /// tool radius of the centre, never below the depth, reaches that radius, and the cycle
    /// ends at the centre at the depth.
    #[test]
    fn a_pocket_stays_inside_its_radius_and_ends_at_the_centre(
        cw in any::<bool>(),
        tool in 0.0f64..6.0,
        i_over in 0.5f64..10.0,
        extra in prop::option::of((0.5f64..30.0, 0.3f64..8.0)),
        depth in 0.5f64..10.0,
        (cx, cy) in (-50.0f64..50.0, -50.0f64..50.0),
    ) {
        let i = tool + i_over;
        let kq = extra.map(|(more, q)| format!(" K{:.3} Q{:.3}", i + more, q)).unwrap_or_default();
        let outer = extra.map_or(i, |(more, _)| i + more);
        let g = if cw { 12 } else { 13 };
        let src = format!(
            "G00 X{cx:.3} Y{cy:.3} Z2.\nG{g} I{i:.3}{kq} D7 Z-{depth:.3} F1200.\nM30\n"
        );
        // As the block reads them (3 decimals); the tool radius is the offset's own.
        let round = |v: f64| (v * 1e3).round() / 1e3;
        let (outer, cx, cy, depth) = (round(outer), round(cx), round(cy), round(depth));
        let (tips, r) = pocket_samples_with(&src, tool);
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        let mut reach: f64 = 0.0;
        for t in &tips {
            let d = (t[0] - cx).hypot(t[1] - cy);
            prop_assert!(d <= outer - tool + 1e-6, "{d} > {}\n{src}", outer - tool);
            prop_assert!(t[2] >= -depth - 1e-6, "{t:?}\n{src}");
            reach = reach.max(d);
        }
        prop_assert!((reach - (outer - tool)).abs() < 1e-6, "reach {reach}\n{src}");
        let w = r.workpiece;
        prop_assert!((w[0] - cx).abs() < 1e-9 && (w[1] - cy).abs() < 1e-9 && (w[2] + depth).abs() < 1e-9, "{w:?}\n{src}");
    }
}

/// A chain of short collinear blocks at a high feed: the time it takes with G103 `p`.
fn chain_time(p: u32) -> f64 {
    let mut src = format!("G103 P{p}\nG01 X0 Y0 F6000.\n");
    for k in 1..=40 {
        src.push_str(&format!("X{}.\n", 2 * k));
    }
    src.push_str("M30\n");
    let r = run_with(&src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    r.cycle_time_s
}

#[test]
fn g103_p1_slows_a_chain_of_short_blocks() {
    let (free, p1, p3, p15) = (chain_time(0), chain_time(1), chain_time(3), chain_time(15));
    // P1: at each block end the machine must be able to stop within the next 2 mm block, which
    // from 100 mm/s takes about 3.5 mm on mill3 (4000 mm/s², 80000 mm/s³): it never reaches
    // the feed. Three blocks (6 mm) are enough to stop from it: no slower than no limit.
    assert!(p1 > 1.2 * free, "P0 {free} P1 {p1}");
    assert!(p1 > p3 && (p3 - free).abs() < 1e-9 && (p15 - free).abs() < 1e-9, "P0 {free} P1 {p1} P3 {p3} P15 {p15}");
    // And a corner sequence: a polygon of 2 mm sides turning 3° at each corner, slower with P1.
    let polygon = |p: u32| {
        let mut src = format!("G103 P{p}\nG01 X0 Y0 F6000.\n");
        let (mut x, mut y) = (0.0f64, 0.0f64);
        for k in 1..=40 {
            let a = (3.0 * k as f64).to_radians();
            (x, y) = (x + 2.0 * a.cos(), y + 2.0 * a.sin());
            src.push_str(&format!("X{x:.3} Y{y:.3}\n"));
        }
        src.push_str("G103\nM30\n");
        run_with(&src, "mill3", Haas).cycle_time_s
    };
    assert!(polygon(1) > 1.1 * polygon(0), "{} {}", polygon(1), polygon(0));
    // G103 alone (no P) ends the limit, as P0 does.
    let src = |tail: &str| format!("G103 P1\n{tail}G01 X0 Y0 F6000.\nX2.\nX4.\nX6.\nX8.\nX10.\nM30\n");
    let ended = run_with(&src("G103\n"), "mill3", Haas).cycle_time_s;
    let zero = run_with(&src("G103 P0\n"), "mill3", Haas).cycle_time_s;
    let limited = run_with(&src(""), "mill3", Haas).cycle_time_s;
    assert!(approx(ended, zero) && limited > zero, "{ended} {zero} {limited}");
}

#[test]
fn haas_canned_cycles_repeat_with_l_and_refuse_k() {
    // L2 in G91: two holes 10 mm apart; L0 stores the data only; K (Haas: a peck argument of
    // G73/G83, not built) is refused, as FANUC's dialect refuses L.
    let two = holes("G00 Z10.\nG91 G81 X10. Z-5. R-8. F300. L2\nG90 G80\nM30\n");
    assert!(two.len() == 2 && close(two[0], (10.0, 0.0)) && close(two[1], (20.0, 0.0)), "{two:?}");
    assert!(holes("G00 Z10.\nG81 X10. Z-5. R2. F300. L0\nG80\nM30\n").is_empty());
    let r = run_with("G00 Z10.\nG81 X10. Z-5. R2. F300. K2\nG80\nM30\n", "mill3", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("311", 2)));
    let r = run_with("G00 Z10.\nG81 X10. Z-5. R2. F300. L2\nG80\nM30\n", "mill3", Fanuc);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("PS0009", 2)));
}

#[test]
fn check_reads_the_haas_repeat_count() {
    let diag = |src: &str, dialect| {
        fivex_engine::check::check(fivex_engine::lang::parse_file(src), dialect)
            .iter()
            .map(|d| (d.line, d.col, dialect.describe(&d.id).0))
            .collect::<Vec<_>>()
    };
    assert_eq!(diag("G81 Z-1. R1. F100. L0\nM30\n", Haas), vec![]);
    assert_eq!(diag("G81 Z-1. R1. F100. K2\nM30\n", Haas), vec![(1, 20, "311".to_string())]);
    assert_eq!(diag("G81 Z-1. R1. F100. L2\nM30\n", Fanuc), vec![(1, 20, "PS0009".to_string())]);
    // A bolt pattern in the cycle's block: its K and L are the pattern's.
    assert_eq!(diag("G81 G71 I10. J0 K30. L3 Z-1. R1. F100.\nM30\n", Haas), vec![]);
    assert!(run_with("G00 Z10.\nG81 G71 I10. J0 K30. L3 Z-1. R1. F100.\nG80\nM30\n", "mill3", Haas).completed());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(32)))]

    /// G70: L holes, each on the circle of radius |I| about the block's point, J the first's
    /// angle, consecutive ones 360/L degrees apart in I's sense.
    #[test]
    fn g70_holes_lie_evenly_on_the_circle(
        i in prop_oneof![-80.0f64..-1.0, 1.0f64..80.0],
        j in -360.0f64..360.0,
        l in 1u32..13,
        (cx, cy) in (-100.0f64..100.0, -100.0f64..100.0),
    ) {
        let src = format!("G00 Z10.\nG81 Z-1. R1. F300. L0\nG70 X{cx:.3} Y{cy:.3} I{i:.3} J{j:.3} L{l}\nG80\nM30\n");
        let round = |v: f64| (v * 1e3).round() / 1e3;
        let (i, j, cx, cy) = (round(i), round(j), round(cx), round(cy));
        let got = holes(&src);
        prop_assert_eq!(got.len(), l as usize, "{}", src);
        for (k, h) in got.iter().enumerate() {
            let t = (j + i.signum() * 360.0 / l as f64 * k as f64).to_radians();
            let want = (cx + i.abs() * t.cos(), cy + i.abs() * t.sin());
            prop_assert!((h.0 - want.0).abs() < 1e-9 && (h.1 - want.1).abs() < 1e-9, "hole {} {:?} {:?}\n{}", k, h, want, src);
        }
    }
}
