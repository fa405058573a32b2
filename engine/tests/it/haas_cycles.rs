//! The Haas NGC's own cycles (`interp::haas_cycles`, `docs/dialects.md`, "Haas cycles"): G12/G13
//! circular pockets (the tool inside the pocket on every sample, ending at its centre at depth),
//! the bolt patterns G70/G71/G72 (the cycle in force at each hole), G103's block look-ahead
//! limit (a chain of short blocks slows down under P1), G150 general purpose pocket milling (the
//! geometry of `fivex_engine::pocket` on random convex polygons and rounded rectangles: inside
//! the wall less the tool radius and K, the outline pass on it, every point reached, every depth,
//! the end at the hole), the refusals (G47, bad arguments), and the shared canned cycles' Haas
//! rules (the dwell P of G73/G83 and its units, G87, the I/J/K words). G187's corner rounding:
//! `corner_rounding.rs`. The manual's examples are data fixtures, `tests/data/cycles/haas_*.nc`.

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
fn a_tool_length_offset_in_a_bolt_pattern_block_takes_effect_at_the_move_to_r() {
    // As in a cycle block (`cycles.rs`): the positioning over the first hole keeps the old
    // length (machine Z50, no offset), the move to R takes H1's 100 mm (R5 → 105, bottom −10 →
    // 90, the initial level 50 → 150 under G98); the second hole is positioned at 150. Applied
    // from the positioning on, the first rapid ran diagonally 100 mm up.
    let src = "G00 G90 X0 Y0 Z50.\nG81 G98 Z-10. R5. F300. L0\nG70 G43 H1 I10. J0 L2\nG80\nM30\n";
    let ends: Vec<[f64; 3]> = motion_ends(interpreter(src, "mill3", Haas))
        .into_iter()
        .filter(|(line, _)| *line == 3)
        .map(|(_, m)| [m[0], m[1], m[2]])
        .collect();
    let mut want = vec![[10.0, 0.0, 50.0], [10.0, 0.0, 105.0], [10.0, 0.0, 90.0], [10.0, 0.0, 150.0]];
    want.extend([[-10.0, 0.0, 150.0], [-10.0, 0.0, 105.0], [-10.0, 0.0, 90.0], [-10.0, 0.0, 150.0]]);
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (got, want) in ends.iter().zip(&want) {
        assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-9), "{ends:?}");
    }
}

#[test]
fn refusals_and_bad_arguments() {
    let first = |src: &str| {
        let r = run_with(&format!("G00 Z10.\n{src}\nM30\n"), "mill3", Haas);
        r.alarms.first().map(|a| (a.code.clone(), a.line))
    };
    // Not built: text engraving; `fivex check` reports it at its G word, with the function's name.
    assert_eq!(first("G47 P0 X0 Y0 I0 J0.5 R0.05 Z-0.005 F15. (FIVEX)"), Some(("310".into(), 2)));
    let diags = fivex_engine::check::check(fivex_engine::lang::parse_file("G00 Z10.\nG47 P0 (FIVEX)\nM30\n"), Haas);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect();
    assert_eq!(found, vec![(2, 1, "310".to_string())], "{diags:?}");
    assert!(diags[0].detail.contains("text engraving"), "{diags:?}");
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
    // The codes are the Haas dialect's only (Syntec's G70/G71 are inch/metric input,
    // `alarms.rs`).
    for dialect in [Fanuc, Syntec] {
        for g in ["G12 I10. D1 Z-1. F100.", "G72 I10. L4", "G103 P1"] {
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

// --- G150 general purpose pocket milling ------------------------------------------------------

use fivex_engine::pocket::{self, Move, Seg, P};

/// A G150 program: `block` at line 2 (after `G00 Z10.`), the outline `sub` as N100 after M30.
fn g150(block: &str, sub: &str) -> String {
    format!("G00 Z10.\n{block}\nM30\nN100 {sub}\nM99\n")
}

/// A U from the start hole X15 Y-8: its base y -15..0, its arms x 0..12 and 20..32 up to y 15.
const U: &str = "G01 Y-15.\nX32.\nY15.\nX20.\nY0\nX12.\nY15.\nX0\nY-15.\nX15.";

/// A 30 x 20 rectangle from the start hole X15 Y10: up to the top edge, round counter-clockwise.
const RECT: &str = "G01 Y20.\nX0\nY0\nX30.\nY20.\nX15.";

fn first_alarm(src: &str) -> Option<(String, u32)> {
    let r = run_with(src, "mill3", Haas);
    r.alarms.first().map(|a| (a.code.clone(), a.line))
}

#[test]
fn g150_cuts_a_rectangle_level_by_level_and_ends_at_the_hole_at_r() {
    // D1: radius 5; K0.5 → the region is x 5.5..24.5, y 5.5..14.5; J4 → strokes along X, 9 / 4
    // → 3 intervals: y = 8.5 and 11.5. Q2 from R1: depths -1, -2 (Z).
    let src = g150("G150 X15. Y10. Z-2. R1. Q2. J4. K0.5 P100 D1 F300.", RECT);
    let r = run_with(&src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(approx(r.workpiece[0], 15.0) && approx(r.workpiece[1], 10.0) && approx(r.workpiece[2], 1.0));
    let mut moves = Vec::new();
    through_stages(interpreter(&src, "mill3", Haas), |c| {
        if let CanonKind::Motion(m) = &c.kind {
            moves.push((m.kind, [m.target[0], m.target[1], m.target[2]]));
        }
    });
    let at = |k: usize| moves[k].1;
    // G00 Z10; the rapid over the hole at the tool's height; to R; the plunge; the entry
    // straight up to the outline pass at y 14.5, along it to the corner x 5.5.
    assert_eq!(moves[1], (MotionKind::Rapid, [15.0, 10.0, 10.0]));
    assert_eq!(moves[2].0, MotionKind::Rapid);
    assert!(approx(at(2)[2], 1.0));
    assert!(moves[3].0 == MotionKind::Linear && approx(at(3)[2], -1.0) && approx(at(3)[0], 15.0));
    assert!(approx(at(4)[0], 15.0) && approx(at(4)[1], 14.5));
    assert!(approx(at(5)[0], 5.5) && approx(at(5)[1], 14.5));
    // Both depths cut, strokes on y 8.5 and 11.5 across the region at each.
    for z in [-1.0, -2.0] {
        for y in [8.5, 11.5] {
            let ends: Vec<f64> =
                moves.iter().filter(|(_, p)| approx(p[2], z) && approx(p[1], y)).map(|(_, p)| p[0]).collect();
            assert!(ends.iter().any(|&x| approx(x, 5.5)) && ends.iter().any(|&x| approx(x, 24.5)), "{z} {y}: {ends:?}");
        }
    }
    // K: the finish pass at the tool radius alone (y 15) at Z only.
    assert!(moves.iter().any(|(_, p)| approx(p[1], 15.0) && approx(p[2], -2.0)));
    assert!(!moves.iter().any(|(_, p)| approx(p[1], 15.0) && approx(p[2], -1.0)));
}

#[test]
fn g150_finds_n_in_the_program_first_then_the_program_o_and_reads_g91() {
    // The outline as program O200, in G91, strokes along Y (I).
    let sub = "O200\nG91 G01 Y10.\nX-15.\nY-20.\nX30.\nY20.\nX-15.\nG90\nM99\n";
    let src = format!("G00 Z10.\nG150 X15. Y10. Z-1. R1. Q2. I4. P200 D1 F300.\nM30\n{sub}");
    let r = run_with(&src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    let same = run_with(&g150("G150 X15. Y10. Z-1. R1. Q2. I4. P100 D1 F300.", RECT), "mill3", Haas);
    assert_eq!(r.workpiece, same.workpiece);
    assert!((r.cycle_time_s - same.cycle_time_s).abs() < 1e-9, "{} {}", r.cycle_time_s, same.cycle_time_s);
    // N200 in the program wins over O200.
    let both = format!("G00 Z10.\nG150 X15. Y10. Z-1. R1. Q2. I4. P200 D1 F300.\nM30\nN200 G01 Y13.\nX10.\nY7.\nX20.\nY13.\nX15.\nM99\n{sub}");
    assert_eq!(first_alarm(&both), Some(("746".into(), 2)), "the 10 x 6 outline is too small for the tool: N200 read");
}

#[test]
fn g150_refusals() {
    let block = |b: &str| g150(b, RECT);
    for src in [
        // I and J both, neither; a step wider than the tool; Q missing, zero; R never given; Z
        // missing, not below R; K negative.
        block("G150 X15. Y10. Z-2. R1. Q2. I4. J4. P100 D1 F300."),
        block("G150 X15. Y10. Z-2. R1. Q2. P100 D1 F300."),
        block("G150 X15. Y10. Z-2. R1. Q2. J10.5 P100 D1 F300."),
        block("G150 X15. Y10. Z-2. R1. J4. P100 D1 F300."),
        block("G150 X15. Y10. Z-2. R1. Q0 J4. P100 D1 F300."),
        block("G150 X15. Y10. Z-2. Q2. J4. P100 D1 F300."),
        block("G150 X15. Y10. R1. Q2. J4. P100 D1 F300."),
        block("G150 X15. Y10. Z1. R1. Q2. J4. P100 D1 F300."),
        block("G150 X15. Y10. Z-2. R1. Q2. J4. K-0.1 P100 D1 F300."),
        // The start hole too near the wall; G42 on a counter-clockwise outline; the tool too big.
        block("G150 X3. Y10. Z-2. R1. Q2. J4. P100 D1 F300."),
        block("G150 G42 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300."),
        g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", "G01 Y14.\nX11.\nY6.\nX19.\nY14.\nX15."),
        // The outline: an F in it, not closed, an arc first, a G00, no M99.
        g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", "G01 Y20. F100.\nX0\nY0\nX30.\nY20.\nX15."),
        g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", "G01 Y20.\nX0\nY0\nX30.\nY20."),
        g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", "G02 Y20. R5.\nX0\nY0\nX30.\nY20.\nX15."),
        g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", "G00 Y20.\nX0\nY0\nX30.\nY20.\nX15."),
        "G00 Z10.\nG150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.\nM30\nN100 G01 Y20.\nX0\n".into(),
    ] {
        assert_eq!(first_alarm(&src), Some(("746".into(), 2)), "{src}");
    }
    // Program / line not found (314), no P (313), no F (320).
    assert_eq!(first_alarm(&block("G150 X15. Y10. Z-2. R1. Q2. J4. P300 D1 F300.")), Some(("314".into(), 2)));
    assert_eq!(first_alarm(&block("G150 X15. Y10. Z-2. R1. Q2. J4. D1 F300.")), Some(("313".into(), 2)));
    assert_eq!(first_alarm(&block("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1")), Some(("320".into(), 2)));
    // Not built (310): L, the block in G91, a stroke line crossing the region twice (a U whose
    // arms the X strokes cut; along Y the same U is cut), and the modes G12/G13 refuse.
    for src in [
        block("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 L2 F300."),
        block("G91 G150 X0 Y0 Z-2. R1. Q2. J4. P100 D1 F300."),
        g150("G150 X15. Y-8. Z-2. R1. Q2. J4. P100 D1 F300.", U),
        block("G68 X0 Y0 R30.\nG150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300."),
    ] {
        let want_line = if src.contains("G68") { 3 } else { 2 };
        assert_eq!(first_alarm(&src), Some(("310".into(), want_line)), "{src}");
    }
    let along_y = g150("G150 X15. Y-8. Z-2. R1. Q2. I4. P100 D1 F300.", U);
    assert!(run_with(&along_y, "mill3", Haas).completed());
    // In a canned cycle: 339 (multiple codes), as G12.
    let cycle = block("G81 Z-1. R1. F100. L0\nG150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.");
    assert_eq!(first_alarm(&cycle), Some(("339".into(), 3)));
    // R given once is kept for the next G150 (the manual).
    let again = "G00 Z10.\nG150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.\nG150 X15. Y10. Z-3. Q2. J4. P100 D1 F300.\nM30\nN100 G01 Y20.\nX0\nY0\nX30.\nY20.\nX15.\nM99\n";
    let r = run_with(again, "mill3", Haas);
    assert!(r.completed() && approx(r.workpiece[2], 1.0), "{:?} {:?}", r.alarms, r.workpiece);
}

/// The points of a path of moves from `from`, `n` samples per move (its ends included).
fn samples(from: P, moves: &[Move], n: usize) -> Vec<P> {
    let mut at = from;
    let mut out = vec![from];
    for m in moves {
        match *m {
            Move::Line { to } => {
                out.extend((1..=n).map(|k| {
                    let t = k as f64 / n as f64;
                    [at[0] + (to[0] - at[0]) * t, at[1] + (to[1] - at[1]) * t]
                }));
            }
            Move::Arc { to, centre, sweep } => {
                let r = pocket::dist(at, centre);
                let a0 = (at[1] - centre[1]).atan2(at[0] - centre[0]);
                out.extend((1..n).map(|k| {
                    let t = a0 + sweep * k as f64 / n as f64;
                    [centre[0] + r * t.cos(), centre[1] + r * t.sin()]
                }));
                out.push(to);
            }
        }
        at = m.to();
    }
    out
}

fn wall_distance(outline: &[Seg], p: P) -> f64 {
    outline.iter().map(|s| pocket::distance_to(s, p)).fold(f64::MAX, f64::min)
}

/// Whether `p` is inside the outline (winding by crossings of a ray along +X, sampled arcs).
fn inside_outline(outline: &[Seg], p: P) -> bool {
    let pts: Vec<P> = outline.iter().flat_map(|s| samples(s.start, &[as_move(s)], 64)).collect();
    let mut inside = false;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
            inside = !inside;
        }
    }
    inside
}

fn as_move(s: &Seg) -> Move {
    match s.arc {
        None => Move::Line { to: s.end },
        Some((centre, sweep)) => Move::Arc { to: s.end, centre, sweep },
    }
}

/// The G150 invariants on one outline: every point of the cut inside the wall less `tool + k`
/// (to 1e-9), the outline pass exactly there, the finish pass at `tool`, every point of the
/// region less the step within step/2 of a pass, and the path back at the hole.
fn check_pocket(outline: &[Seg], hole: P, tool: f64, k: f64, step: f64, along_x: bool) -> Result<(), TestCaseError> {
    let plan =
        pocket::plan(outline, hole, tool, k, step, along_x).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
    let d = tool + k;
    let cut = samples(hole, &plan.level, 8);
    for p in &cut {
        prop_assert!(inside_outline(outline, *p), "{p:?} outside");
        prop_assert!(wall_distance(outline, *p) >= d - 1e-9, "{p:?}: {} < {d}", wall_distance(outline, *p));
    }
    let pass = samples(plan.contour[0].start, &plan.contour.iter().map(as_move).collect::<Vec<_>>(), 8);
    for p in &pass {
        prop_assert!((wall_distance(outline, *p) - d).abs() < 1e-9, "pass {p:?}: {}", wall_distance(outline, *p));
    }
    prop_assert!(pocket::dist(plan.level.last().unwrap().to(), hole) < 1e-12);
    if k > 0.0 {
        for p in &samples(plan.finish[0].to(), &plan.finish[1..plan.finish.len() - 1], 8) {
            prop_assert!((wall_distance(outline, *p) - tool).abs() < 1e-9, "finish {p:?}");
        }
        prop_assert!(pocket::dist(plan.finish.last().unwrap().to(), hole) < 1e-12);
    } else {
        prop_assert!(plan.finish.is_empty());
    }
    // Coverage: grid points of the region at least `step` inside the pass.
    let lines: Vec<(P, P)> = {
        let mut at = hole;
        let mut v = Vec::new();
        for m in &plan.level {
            if let Move::Line { to } = *m {
                v.push((at, to));
            }
            at = m.to();
        }
        v
    };
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in &pass {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let seg_dist = |p: P, (a, b): (P, P)| pocket::distance_to(&Seg::line(a, b), p);
    let mut checked = 0;
    for i in 0..=24 {
        for j in 0..=24 {
            let p = [lo[0] + (hi[0] - lo[0]) * i as f64 / 24.0, lo[1] + (hi[1] - lo[1]) * j as f64 / 24.0];
            if !inside_outline(outline, p) || wall_distance(outline, p) < d + step {
                continue;
            }
            checked += 1;
            let near = lines.iter().map(|&l| seg_dist(p, l)).fold(f64::MAX, f64::min);
            prop_assert!(near <= step / 2.0 + 1e-9, "{p:?} is {near} from every stroke (step {step})");
        }
    }
    let _ = checked;
    Ok(())
}

/// A convex polygon: `n` corners on a circle of radius `r` about `c`, evenly spaced give or
/// take 15 % of the spacing (no gap above 156°, so every edge is at least 0.2 r from the
/// centre), either way round.
fn polygon(c: P, r: f64, jitter: &[f64], ccw: bool) -> Vec<Seg> {
    let n = jitter.len();
    let mut pts: Vec<P> = (0..n)
        .map(|i| {
            let t = (i as f64 + 0.15 * jitter[i]) * std::f64::consts::TAU / n as f64;
            [c[0] + r * t.cos(), c[1] + r * t.sin()]
        })
        .collect();
    if !ccw {
        pts.reverse();
    }
    (0..n).map(|i| Seg::line(pts[i], pts[(i + 1) % n])).collect()
}

/// A rectangle `w` x `h` from (x0, y0) with corners rounded by `rho` (tangent arcs), starting
/// mid-top, counter-clockwise.
fn rounded(x0: f64, y0: f64, w: f64, h: f64, rho: f64) -> Vec<Seg> {
    use std::f64::consts::FRAC_PI_2 as Q;
    let (x1, y1) = (x0 + w, y0 + h);
    let arc = |c: P, a0: f64| {
        let s = [c[0] + rho * a0.cos(), c[1] + rho * a0.sin()];
        let e = [c[0] + rho * (a0 + Q).cos(), c[1] + rho * (a0 + Q).sin()];
        Seg { start: s, end: e, arc: Some((c, Q)) }
    };
    let tl = arc([x0 + rho, y1 - rho], Q);
    let bl = arc([x0 + rho, y0 + rho], 2.0 * Q);
    let br = arc([x1 - rho, y0 + rho], 3.0 * Q);
    let tr = arc([x1 - rho, y1 - rho], 0.0);
    let mid = [x0 + w / 2.0, y1];
    vec![
        Seg::line(mid, tl.start),
        tl,
        Seg::line(tl.end, bl.start),
        bl,
        Seg::line(bl.end, br.start),
        br,
        Seg::line(br.end, tr.start),
        tr,
        Seg::line(tr.end, mid),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(48)))]

    #[test]
    fn g150_on_random_convex_polygons(
        cx in -50.0..50.0f64, cy in -50.0..50.0f64, r in 10.0..80.0f64,
        jitter in prop::collection::vec(-1.0..1.0f64, 3..10),
        ccw in any::<bool>(), along_x in any::<bool>(),
        tool_f in 0.01..0.06f64, k_f in 0.0..0.04f64, step_f in 0.1..1.0f64,
    ) {
        let outline = polygon([cx, cy], r, &jitter, ccw);
        let (tool, k) = (tool_f * r, k_f * r);
        check_pocket(&outline, [cx, cy], tool, k, step_f * 2.0 * tool, along_x)?;
    }

    #[test]
    fn g150_on_random_rounded_rectangles(
        x0 in -50.0..50.0f64, y0 in -50.0..50.0f64, w in 20.0..120.0f64, h in 20.0..120.0f64,
        rho_f in 0.0..0.45f64, along_x in any::<bool>(),
        tool_f in 0.01..0.15f64, k_f in 0.0..0.05f64, step_f in 0.1..1.0f64,
    ) {
        let m = w.min(h);
        // Corners rounded from a hair to almost half the side (some smaller than the tool
        // radius plus K, whose offset arcs vanish into a sharp corner).
        let rho = (rho_f * m).max(0.01);
        let (tool, k) = (tool_f * m, k_f * m);
        let outline = rounded(x0, y0, w, h, rho);
        check_pocket(&outline, [x0 + w / 2.0, y0 + h / 2.0], tool, k, step_f * 2.0 * tool, along_x)?;
    }

    /// Through the interpreter: every depth from R down by Q is cut at the hole, the last at Z,
    /// and the tool ends over the hole at R.
    #[test]
    fn g150_cuts_every_depth_and_ends_at_the_hole_at_r(
        r in -2.0..5.0f64, depth in 0.5..20.0f64, q in 0.3..6.0f64,
    ) {
        let (r, depth, q) = ((r * 1000.0).round() / 1000.0, (depth * 1000.0).round() / 1000.0, (q * 1000.0).round() / 1000.0);
        let z = r - depth;
        let src = g150(&format!("G150 X15. Y10. Z{z:.3} R{r:.3} Q{q:.3} J4. P100 D1 F3000."), RECT);
        let mut plunges = Vec::new();
        let mut last = [0.0; 3];
        let alarm = through_stages(interpreter(&src, "mill3", Haas), |c| {
            if let CanonKind::Motion(m) = &c.kind {
                let p = [m.target[0], m.target[1], m.target[2]];
                if m.kind == MotionKind::Linear && p[2] < last[2] - 1e-9 && approx(p[0], 15.0) && approx(p[1], 10.0) {
                    plunges.push(p[2]);
                }
                last = p;
            }
        });
        prop_assert!(alarm.is_none(), "{alarm:?}");
        let mut want = Vec::new();
        let mut at = r - q;
        while at > z + 1e-6 {
            want.push(at);
            at -= q;
        }
        want.push(z);
        prop_assert_eq!(plunges.len(), want.len());
        for (g, w) in plunges.iter().zip(&want) {
            prop_assert!((g - w).abs() < 1e-9, "{:?} {:?}", plunges, want);
        }
        prop_assert!(approx(last[0], 15.0) && approx(last[1], 10.0) && approx(last[2], r), "{:?}", last);
    }
}

#[test]
fn check_reads_g150_s_subprogram() {
    let found = |src: &str| {
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(src), Haas);
        diags.iter().map(|d| (d.line, Haas.describe(&d.id).0)).collect::<Vec<_>>()
    };
    // N100 in the program, O200 in the file: nothing to report.
    assert_eq!(found(&g150("G150 X15. Y10. Z-2. R1. Q2. J4. P100 D1 F300.", RECT)), vec![]);
    let o200 = "G150 X15. Y10. Z-1. R1. Q2. I4. P200 D1 F300.\nM30\nO200\nG01 Y20.\nX0\nY0\nX30.\nY20.\nX15.\nM99\n";
    assert_eq!(found(o200), vec![]);
    // Neither (314), no P (313).
    assert_eq!(found(&g150("G150 X15. Y10. Z-2. R1. Q2. J4. P300 D1 F300.", RECT)), vec![(2, "314".to_string())]);
    assert_eq!(found(&g150("G150 X15. Y10. Z-2. R1. Q2. J4. D1 F300.", RECT)), vec![(2, "313".to_string())]);
}

/// The drilling-axis (Z) end of every motion of line `line`, with its kind, and the first
/// motion's X/Y (the hole).
fn cycle_z(src: &str, line: u32, dialect: fivex_engine::Dialect) -> ((f64, f64), Vec<(MotionKind, f64)>) {
    let mut moves = Vec::new();
    let mut hole = None;
    for c in canon_in(src, dialect) {
        if let CanonKind::Motion(m) = &c.kind {
            if c.line == line {
                hole.get_or_insert((m.target[0], m.target[1]));
                moves.push((m.kind, (m.target[2] * 1e9).round() / 1e9));
            }
        }
    }
    (hole.expect("a motion on that line"), moves)
}

fn canon_in(src: &str, dialect: fivex_engine::Dialect) -> Vec<fivex_engine::canon::Canon> {
    let mut v = Vec::new();
    interpreter(src, "mill3", dialect).run(|c| v.push(c)).expect("no alarm");
    v
}

/// Haas G51: "scaling does not affect canned cycle Z-axis movements such as clearance planes
/// and incremental values" (96-8000 rev R, G51, programming notes): the hole is scaled, R, Z,
/// the initial level and Q are not. FANUC scales the levels (×2 about Z0 here: R4, Z−10) and
/// not Q. Before, the Haas hole went 5 mm deeper (the audit's F3).
#[test]
fn haas_scaling_leaves_the_cycle_levels_alone() {
    use MotionKind::{Linear as F, Rapid as R};
    let head = "G00 X0 Y0 Z50.\nG51 X0 Y0 Z0 P2.\n";
    // G99 G81 from Z50: the hole at (20, 10); Haas R2, Z−5, back to R2.
    let g81 = format!("{head}G99 G81 X10. Y5. Z-5. R2. F200.\nG80\nG50\nM30\n");
    let (hole, haas) = cycle_z(&g81, 3, Haas);
    assert!(close(hole, (20.0, 10.0)), "{hole:?}");
    assert_eq!(haas, vec![(R, 50.0), (R, 2.0), (F, -5.0), (R, 2.0)]);
    let (_, fanuc) = cycle_z(&g81, 3, Fanuc);
    assert_eq!(fanuc, vec![(R, 50.0), (R, 4.0), (F, -10.0), (R, 4.0)]);
    // G91 G98: R from the initial level Z50 (the tool's, 25 programmed), Z from R; back to 50.
    let inc = format!("{head}G91 G98 G81 X10. Y5. Z-7. R-48. F200.\nG80\nG90 G50\nM30\n");
    let (_, haas) = cycle_z(&inc, 3, Haas);
    assert_eq!(haas, vec![(R, 50.0), (R, 2.0), (F, -5.0), (R, 50.0)]);
    // FANUC: 25 − 48 = −23 and −30 programmed, −46 and −60 after the scaling.
    let (_, fanuc) = cycle_z(&inc, 3, Fanuc);
    assert_eq!(fanuc, vec![(R, 50.0), (R, -46.0), (F, -60.0), (R, 50.0)]);
    // G83 Q3 from R2 to Z−5 (Haas): pecks to −1, −4, −5, each return to R and back to 0.5 mm
    // above the last depth.
    let g83 = format!("{head}G99 G83 X10. Y5. Z-5. R2. Q3. F200.\nG80\nG50\nM30\n");
    let (_, haas) = cycle_z(&g83, 3, Haas);
    let want =
        [(R, 50.0), (R, 2.0), (F, -1.0), (R, 2.0), (R, -0.5), (F, -4.0), (R, 2.0), (R, -3.5), (F, -5.0), (R, 2.0)];
    assert_eq!(haas, want.to_vec());
}

// --- The shared canned cycles in the Haas dialect (`docs/dialects.md`, "Haas cycles") -----------

/// A dwell (seconds), the drilling-axis (Z) end of the motion before it, and the kind and Z of
/// the motion after it (mm, rounded to 1 nm).
type DwellAt = (f64, f64, Option<(MotionKind, f64)>);

/// Line `line`'s dwells.
fn dwells(src: &str, line: u32, dialect: fivex_engine::Dialect) -> Vec<DwellAt> {
    let round = |z: f64| (z * 1e9).round() / 1e9;
    let canon: Vec<_> = canon_in(src, dialect).into_iter().filter(|c| c.line == line).collect();
    let motion = |c: &fivex_engine::canon::Canon| match &c.kind {
        CanonKind::Motion(m) => Some((m.kind, round(m.target[2]))),
        _ => None,
    };
    let mut out = Vec::new();
    for (i, c) in canon.iter().enumerate() {
        if let CanonKind::Dwell { seconds } = c.kind {
            let before = canon[..i].iter().rev().find_map(motion).expect("a motion before").1;
            out.push((seconds, before, canon[i + 1..].iter().find_map(motion)));
        }
    }
    out
}

/// The manual's G83 line (96-8000, G83: "peck several times and dwell for five seconds at the
/// end", `G83 Z-0.62 F15. R0.1 Q0.175 P5.`): 5 s at the bottom (−0.62 in = −15.748 mm) of each
/// hole after the last peck, then the return to R (0.1 in = 2.54 mm, G99); the same P for the next
/// hole. Before, the P was dropped (the audit's F2).
#[test]
fn haas_g83_and_g73_dwell_p_after_the_last_peck() {
    use MotionKind::Rapid;
    let src = "G20\nG00 X0 Y0 Z1.\nG99 G83 X1. Y1. Z-0.62 F15. R0.1 Q0.175 P5.\nX2.\nG80\nM30\n";
    assert_eq!(dwells(src, 3, Haas), vec![(5.0, -15.748, Some((Rapid, 2.54)))]);
    assert_eq!(dwells(src, 4, Haas), vec![(5.0, -15.748, Some((Rapid, 2.54)))]);
    // Without P no dwell; a P without a point counts milliseconds (Autodesk's Haas post writes
    // `P500`); G73 likewise; G98 returns to the initial level (Z1 in = 25.4 mm).
    assert_eq!(dwells(&src.replace(" P5.", ""), 3, Haas), vec![]);
    let ms = "G00 X0 Y0 Z50.\nG98 G83 X10. Y10. Z-10. R2. Q4. P500 F200.\nG73 X20. Q4. P2.\nG80\nM30\n";
    assert_eq!(dwells(ms, 2, Haas), vec![(0.5, -10.0, Some((Rapid, 50.0)))]);
    assert_eq!(dwells(ms, 3, Haas), vec![(2.0, -10.0, Some((Rapid, 50.0)))]);
    // G80 (and a group-01 code) resets it: "the dwell time will be reset to zero".
    let reset = "G00 X0 Y0 Z50.\nG83 X10. Z-10. R2. Q4. P500 F200.\nG80\nG83 X20. Z-10. R2. Q4.\nG80\nM30\n";
    assert_eq!(dwells(reset, 4, Haas), vec![]);
    // FANUC's G83 has no dwell (unchanged).
    assert_eq!(dwells(&ms.replace("P2.", "P2000"), 2, Fanuc), vec![]);
}

/// A cycle's P with a decimal point counts seconds in the Haas dialect, as G04's: the NGC's G82
/// example `G82 Z-0.720 P0.3 R0.1 F15.` dwells 0.3 s. Before, `P1.` dwelt 0.001 s (the audit's F3).
#[test]
fn haas_cycle_p_with_a_point_is_seconds() {
    let head = "G00 X0 Y0 Z50.\n";
    for cycle in ["G82", "G89", "G76 Q0.5", "G88"] {
        for (p, want) in [("P1.", 1.0), ("P1000", 1.0), ("P0.3", 0.3), ("P250", 0.25)] {
            let src = format!("{head}M03 S500\nG98 {cycle} X10. Y10. Z-10. R2. {p} F200.\nG80\nM30\n");
            let got = dwells(&src, 3, Haas);
            assert_eq!(got.iter().map(|d| (d.0, d.1)).collect::<Vec<_>>(), vec![(want, -10.0)], "{cycle} {p}");
        }
    }
    // The manual's example, inch: 0.3 s at −0.72 in.
    let src = "G20\nG00 X2. Y-2. Z0.1\nG82 Z-0.720 P0.3 R0.1 F15.\nG80\nM30\n";
    assert_eq!(dwells(src, 3, Haas).iter().map(|d| (d.0, d.1)).collect::<Vec<_>>(), vec![(0.3, -18.288)]);
    // G04 reads P the same way.
    assert_eq!(
        canon_in("G04 P1.\nG04 P1000\nM30\n", Haas)
            .iter()
            .filter(|c| matches!(c.kind, CanonKind::Dwell { seconds } if seconds == 1.0))
            .count(),
        2
    );
    // FANUC refuses the point at a dwell's P (PS0007), as before.
    let r = run_with(&format!("{head}G82 X10. Z-10. R2. P1. F200.\nM30\n"), "mill3", Fanuc);
    assert_eq!(r.alarms.first().map(|a| a.code.as_str()), Some("PS0007"));
}

/// The NGC's back bore is G77 and its G87 another cycle: G87 no longer runs FANUC's back boring
/// (orient, shift, up from below, automatic return) in the Haas dialect: it is refused as not
/// built, as G77 is, and `fivex check` names it (the audit's F1). FANUC's G87 is unchanged.
#[test]
fn haas_g87_is_not_fanuc_s_back_boring() {
    let block = "G87 G98 X10. Y10. Z-20. R2. Q1. F100.";
    let src = format!("G00 X0 Y0 Z50.\nM03 S500\n{block}\nG80\nM30\n");
    let r = run_with(&src, "mill3", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("310", 3)));
    assert!(r.machine.iter().take(2).all(|&v| v == 0.0), "{:?}", r.machine);
    let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(&src), Haas);
    assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(3, 1)]);
    assert!(diags[0].detail.contains("G87") && diags[0].detail.contains("G77"), "{diags:?}");
    assert!(run_with(&src.replace("R2.", "R-30."), "mill3", Fanuc).completed());
}

/// The words a Haas cycle does not perform are refused, not ignored (the audit's F4, F6): the
/// I, J, K peck forms of G83/G73 (96-8000, the G83 and G73 pages) and G76's shift by I/J (the
/// NGC's G77 page: "if Q is not specified") as functions not built (310, named by `fivex check`;
/// before, G83 I/J said `305 INVALID Q`), also in a later block that runs the cycle without
/// naming it; I or J in the other cycles (G81 I5., G84 J2 ran as if absent) as unknown (311).
/// A bolt pattern's own I/J/K still go (`check_reads_the_haas_repeat_count`).
#[test]
fn haas_cycle_words_not_performed_are_refused() {
    let first = |body: &str| {
        let src = format!("G00 X0 Y0 Z50.\nM03 S500\n{body}\nG80\nM30\n");
        let r = run_with(&src, "mill3", Haas);
        r.alarms.first().map(|a| (a.code.clone(), a.line))
    };
    let refused = |code: &str, line| Some((code.to_string(), line));
    for body in [
        "G83 G99 X10. Y10. Z-20. R2. I5. J1. F200.",
        "G83 G99 X10. Y10. Z-20. R2. I5. J1. K1. Q2. F200.",
        "G73 X10. Y10. Z-20. R2. I5. J1. K1. F200.",
        "G73 X10. Y10. Z-20. R2. K4. Q1. F200.",
        "G98 G76 X10. Y10. Z-10. R2. I0.5 J0.3 P500 F200.",
    ] {
        assert_eq!(first(body), refused("310", 3), "{body}");
    }
    // The cycle in force, a later block: its I is refused the same way.
    assert_eq!(first("G83 X10. Z-20. R2. Q5. F200.\nX20. I5."), refused("310", 4));
    assert_eq!(first("G76 X10. Z-20. R2. Q0.5 F200.\nX20. J0.3"), refused("310", 4));
    for body in [
        "G81 X10. Y10. Z-10. R2. I5. J5. F200.",
        "G84 X10. Y10. Z-10. R2. F750. J2",
        "G81 X10. Z-10. R2. F200.\nX20. I5.",
    ] {
        let line = 2 + body.lines().count() as u32;
        assert_eq!(first(body), refused("311", line), "{body}");
    }
    // `fivex check` names the peck form at its G word.
    let diags = fivex_engine::check::check(
        fivex_engine::lang::parse_file("G83 G99 X10. Y10. Z-20. R2. I5. J1. F200.\nG80\nM30\n"),
        Haas,
    );
    assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(1, 1)], "{diags:?}");
    assert!(diags[0].detail.contains("I, J, K peck form of G83"), "{diags:?}");
    // G47's E (its plunge feed) is G47's: the run refuses G47 (310), not the E as FANUC's thread
    // lead (311), and `fivex check` reports G47 alone.
    let g47 = "G00 X0 Y0 Z0\nG47 P0 X0 Y0 I0 J.5 R.05 Z-.005 F15. E10. (TEXT)\nM30\n";
    let r = run_with(g47, "mill3", Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("310", 2)));
    let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(g47), Haas);
    assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(2, 1)], "{diags:?}");
    // FANUC is unchanged: G81 with I runs (the I is ignored, as before).
    assert!(run_with("G00 X0 Y0 Z50.\nG81 X10. Z-10. R2. I5. F200.\nG80\nM30\n", "mill3", Fanuc).completed());
}

/// A pocket whose outline starts on a concave corner (the audit's F5): a 40 x 40 square with a
/// half-disc tab (radius 10) on its right edge, started where the tab leaves the edge, (20, 0).
/// Before, 746 (the straight entry to the end of the corner's arc cut the corner); the same
/// outline started on an edge ran. Now it runs: every point inside the wall by the tool radius +
/// K, the passes exactly there, the region covered (`check_pocket`); the run's tip never nearer
/// the wall than the tool radius (5), reaching X 25 (the tab's edge 30 − 5) on the finish pass.
#[test]
fn g150_starts_on_a_concave_corner() {
    let tab = Seg { start: [20.0, 0.0], end: [20.0, 20.0], arc: Some(([20.0, 10.0], std::f64::consts::PI)) };
    let corners = [[20.0, 20.0], [-20.0, 20.0], [-20.0, -20.0], [20.0, -20.0], [20.0, 0.0]];
    let mut outline = vec![tab];
    outline.extend(corners.windows(2).map(|w| Seg::line(w[0], w[1])));
    for (k, step, along_x) in [(0.5, 8.0, false), (0.0, 4.0, true), (0.5, 8.0, true)] {
        check_pocket(&outline, [0.0, 0.0], 5.0, k, step, along_x).unwrap();
    }
    let sub = "G01 X20. Y0\nG03 X20. Y20. R10.\nG01 X-20. Y20.\nG01 Y-20.\nG01 X20.\nG01 Y0.";
    let (tips, r) = pocket_samples(&g150("G150 X0 Y0 Z-6. R2. Q3. I8. K0.5 P100 D7 F3000.", sub));
    assert!(r.completed(), "{:?}", r.alarms);
    let near = tips.iter().map(|t| wall_distance(&outline, [t[0], t[1]])).fold(f64::MAX, f64::min);
    let reach = tips.iter().map(|t| t[0]).fold(f64::MIN, f64::max);
    assert!(tips.iter().all(|t| inside_outline(&outline, [t[0], t[1]])));
    // (The samples are 0.1 mm apart at F3000: the arc's top lies within 3e-4 mm of one.)
    assert!((near - 5.0).abs() < 1e-6 && (reach - 25.0).abs() < 1e-3, "{near} {reach}");
}
