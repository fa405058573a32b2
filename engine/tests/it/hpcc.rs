//! Syntec HPCC, `G05 P10000` (`docs/motion.md`, "Syntec HPCC"): the programmed points become
//! nano smoothing's curve — X, Y, Z within Pr407, with the axis form the rotary axes it names
//! within Pr3052 / Pr3053 — the tip within Pr407 of its block's segment at every 1 ms sample,
//! every axis within its limits, quicker than the polygon; G05 P0 ends it. The format alarms
//! (COR-107) and COR-140 in both orders are data fixtures (`tests/data/modes/hpcc_format_*`,
//! `no_hpcc_in_rtcp_*`); M02/M30 and a reset ending it, unit tests of `interp::smoothing`.

use crate::common;
use crate::smoothing::{program, program_5x, rotary_between, run_in, to_segment, wave, within_segments};

use fivex_engine::check::check;
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::Sample;
use fivex_engine::Dialect::{Fanuc, Syntec};

/// `smoothing::program` with HPCC: `on` (`G05 P10000` …) in place of G05.1 Q3, G05 P0 of Q0.
fn hpcc(points: &[[f64; 3]], feed: f64, on: &str) -> String {
    program(points, feed, true, "").replace("G05.1 Q3 X0 Y0 Z0\n", &format!("{on}\n")).replace("G05.1 Q0\n", "G05 P0\n")
}

#[test]
fn hpcc_smooths_the_tip_within_pr407() {
    // The wave of 0.1 mm blocks with ±3 µm of noise on mill3: the tip within Pr407 (default
    // 3 µm) of its blocks' segments, and off them (the noise is smoothed).
    let points = wave(0.1, 0.003, 5);
    let (r, samples) = run_in(Syntec, &hpcc(&points, 12000.0, "G05 P10000"), "mill3", |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let worst = within_segments(&samples, &points, 0.003).unwrap();
    assert!(worst > 0.0005, "the noise is not smoothed: {worst}");
    // ±8 µm of noise: Pr407 = 3 µm keeps within 3 µm (the curve follows the noise), Pr407 =
    // 10 µm within 10 µm, using it (beyond 5 µm somewhere).
    let points = wave(0.1, 0.008, 5);
    let src = hpcc(&points, 12000.0, "G05 P10000");
    let (_, narrow) = run_in(Syntec, &src, "mill3", |_| {});
    within_segments(&narrow, &points, 0.003).unwrap();
    let (_, wide) = run_in(Syntec, &src, "mill3", |m| m.five_axis.smooth_path_tolerance = Some(0.010));
    let worst = within_segments(&wide, &points, 0.010).unwrap();
    assert!(worst > 0.005, "Pr407 = 10 µm keeps within {worst} of the blocks");
}

#[test]
fn hpcc_keeps_the_axes_limits_and_is_quicker_than_the_polygon() {
    // The noisy wave at F15000 in blocks of 0.2, 0.1 and 0.05 mm: smoothed and not, every
    // axis within its speed, acceleration and jerk in 10 ms differences; the curve quicker.
    let mill3 = MachineConfig::preset("mill3").unwrap();
    for step in [0.2, 0.1, 0.05] {
        let points = wave(step, 0.003, 11);
        let mut times = Vec::new();
        for src in [program(&points, 15000.0, false, ""), hpcc(&points, 15000.0, "G05 P10000")] {
            let (r, samples) = run_in(Syntec, &src, "mill3", |_| {});
            assert!(r.completed(), "{:?}", r.alarms);
            let every: Vec<Sample> = samples.iter().step_by(10).copied().collect();
            common::check_limits_every(&every, &mill3, true, 0.01).unwrap_or_else(|e| panic!("step {step}: {e}"));
            times.push(r.cycle_time_s);
        }
        eprintln!("HPCC wave, {step} mm blocks: {:.3} s unsmoothed, {:.3} s in G05 P10000", times[0], times[1]);
        assert!(times[1] < times[0], "step {step}: smoothed {} s, polygon {} s", times[1], times[0]);
    }
}

/// `program_5x` on head-bc without TCP (HPCC is not allowed under it): `on` in place of G43.4
/// and G05.1 Q3, G05 P0 of Q0 and G49.
fn program_5x_hpcc(points: &[[f64; 3]], on: &str) -> String {
    program_5x(points, 3000.0, 12.0, 40.0)
        .replace("G43.4 H1 G01", "G01")
        .replace("G05.1 Q3 X0 Y0 Z0 B0 C0\n", &format!("{on}\n"))
        .replace("G05.1 Q0\nG49\n", "G05 P0\n")
}

#[test]
fn the_axis_form_smooths_the_rotary_axes_it_names_within_pr3052_3053() {
    // Head-bc (C the master, B the slave), X Y Z along the wave and B, C turning, without TCP:
    // the machine's X/Y/Z are the programmed points.
    let points = wave(0.2, 0.003, 3);
    let tweak = |m: &mut MachineConfig| m.five_axis.smooth_tolerance = Some([0.02, 0.01]);
    let axis_form = program_5x_hpcc(&points, "G05 P10000 X0 Y0 Z0 B1. C1.");
    let (r, samples) = run_in(Syntec, &axis_form, "head-bc", tweak);
    assert!(r.completed(), "{:?}", r.alarms);
    // The programmed B and C of each point, read back from the program.
    let word = |line: &str, letter: char| -> f64 {
        let w = line.split(' ').find(|w| w.starts_with(letter)).unwrap();
        w[1..].parse().unwrap()
    };
    let lines: Vec<&str> = axis_form.lines().collect();
    let rotary: Vec<[f64; 2]> = (0..points.len())
        .map(|i| if i == 0 { lines[0] } else { lines[2 + i] })
        .map(|l| [word(l, 'B'), word(l, 'C')])
        .collect();
    let m = MachineConfig::preset("head-bc").unwrap();
    let (b, c) = (m.axis_index(b'B').unwrap(), m.axis_index(b'C').unwrap());
    let mut seen = 0;
    for s in samples.iter().filter(|s| (4..3 + points.len() as u32).contains(&s.line)) {
        let i = s.line as usize - 3;
        let d = to_segment([s.machine[0], s.machine[1], s.machine[2]], points[i - 1], points[i]);
        assert!(d < 0.003 + 1e-6, "line {}: X/Y/Z {d} from the segment", s.line);
        // B (slave, Pr3053) and C (master, Pr3052) within their tolerances.
        rotary_between(s, [(0, b, 0.01), (1, c, 0.02)], rotary[i - 1], rotary[i]);
        seen += 1;
    }
    assert!(seen > 100, "{seen}");
    // Smoothed: its blocks move by chords of the curve. Without axis words HPCC smooths X, Y, Z
    // alone: these blocks, which turn B and C, each move straight (one motion, to its point),
    // as without HPCC.
    let motions = |src: &str| common::motion_ends(common::interpreter_with(src, "head-bc", Syntec, |_| {}));
    let plain = motions(&program_5x_hpcc(&points, "G04 X0").replace("G05 P0\n", "G04 X0\n"));
    let linear_only = motions(&program_5x_hpcc(&points, "G05 P10000"));
    assert_eq!(linear_only, plain);
    assert!(motions(&axis_form).len() > plain.len() + points.len(), "the axis form is not smoothed");
}

#[test]
fn g05_p0_moves_what_is_held_and_ends_it() {
    // After G05 P0 the blocks are the programmed moves again, one motion each; the last block
    // of the curve ends at its own point, reached before G05 P0's block.
    let points = wave(0.1, 0.003, 7);
    let n = points.len() as u32;
    let src = hpcc(&points, 6000.0, "G05 P10000").replace("G05 P0\n", "G05 P0\nX1. Y1. Z1.\nX2. Y1.5 Z1.2\n");
    let ends = common::motion_ends(common::interpreter_with(&src, "mill3", Syntec, |_| {}));
    let last = points[points.len() - 1];
    assert_eq!(common::end_of(&ends, 2 + n)[..3], last);
    let after: Vec<_> = ends.iter().filter(|(line, _)| *line > 3 + n).collect();
    assert_eq!(
        after.iter().map(|(l, p)| (*l, p[..3].to_vec())).collect::<Vec<_>>(),
        [(4 + n, vec![1.0, 1.0, 1.0]), (5 + n, vec![2.0, 1.5, 1.2])]
    );
    // The curve's blocks moved by more motions than blocks.
    let curve = ends.iter().filter(|(line, _)| (4..3 + n).contains(line)).count();
    assert!(curve > points.len(), "{curve} motions for {} blocks", points.len() - 1);
}

#[test]
fn cutter_compensation_with_hpcc_is_not_built() {
    // As with nano smoothing: the curve would be built before the compensation, either order.
    let on = "G90 G00 X0 Y0 Z0\nG01 F1000\nG05 P10000\n";
    for (src, line) in [(format!("{on}G41 D1 X10.\nM30\n"), 4), ("G01 F1000\nG41 D1 X10.\nG05 P10000\nM30\n".into(), 3)]
    {
        let r = common::run_with(&src, "mill3", Syntec);
        assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("COR-100", line), "{src}");
    }
}

#[test]
fn fivex_check_reports_the_g05_forms_literal_words_decide() {
    // At the word that is wrong; the rotary axes of the axis form, and values given by
    // expressions, are left to the run (`fivex check --preset` runs the program).
    let diag = |text: &str, dialect| {
        check(parse_file(&format!("{text}\nM30\n")), dialect)
            .iter()
            .map(|d| (d.col, dialect.describe(&d.id).0))
            .collect::<Vec<_>>()
    };
    let one = |col: u32, code: &str| vec![(col, code.to_string())];
    assert_eq!(diag("G05 P10000", Syntec), vec![]);
    assert_eq!(diag("G05 P0", Syntec), vec![]);
    assert_eq!(diag("G05 P10000 X0 Y0 Z0 B1. C1.", Syntec), vec![]);
    assert_eq!(diag("G05 P10000 X0 Y0 Z0 B0 C1.", Syntec), vec![]);
    assert_eq!(diag("G05 P#1", Syntec), vec![]);
    assert_eq!(diag("G05 P10000 E#1", Syntec), vec![]);
    assert_eq!(diag("G05 P1", Syntec), one(5, "COR-107"));
    assert_eq!(diag("G90 G05", Syntec), one(5, "COR-107"));
    assert_eq!(diag("G05 P10000 E0", Syntec), one(12, "COR-107"));
    assert_eq!(diag("G05 P10000 X0 Y0.5 Z0 B1. C1.", Syntec), one(15, "COR-107"));
    assert_eq!(diag("G05 P0 Z0", Syntec), one(8, "COR-107"));
    // A positive E: not built, at the G word (not the address E of FANUC's thread lead).
    assert_eq!(diag("G05 P10000 E1.", Syntec), one(1, "COR-100"));
    // FANUC keeps refusing G05 but P0, and E as an address.
    assert_eq!(diag("G05 P10000", Fanuc), one(1, "PS0010"));
    assert_eq!(diag("G05 P10000 E1.", Fanuc), vec![(1, "PS0010".to_string()), (12, "PS0009".to_string())]);
    // The run says the same at the same blocks.
    for (text, code) in [("G05 P1", "COR-107"), ("G05 P10000 E0", "COR-107"), ("G05 P10000 E1.", "COR-100")] {
        let r = common::run_with(&format!("{text}\nM30\n"), "head-bc", Syntec);
        assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), (code, 1), "{text}");
    }
}

#[test]
fn in_a_tilted_working_plane_the_curve_is_the_planes() {
    // The manual forbids HPCC only with RTCP: in G68.2 (turned 30° about Z) the points are the
    // plane's, the curve is built in its coordinates and the tip (workpiece system) keeps
    // within Pr407 of the programmed segments carried into it.
    let points = wave(0.1, 0.003, 5);
    let (sin, cos) = 30f64.to_radians().sin_cos();
    let carried: Vec<[f64; 3]> =
        points.iter().map(|p| [cos * p[0] - sin * p[1], sin * p[0] + cos * p[1], p[2]]).collect();
    let src = format!("G68.2 X0 Y0 Z0 I30. J0 K0\n{}", hpcc(&points, 6000.0, "G05 P10000"));
    let (r, samples) = run_in(Syntec, &src, "head-bc", |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    // `within_segments` counts the lines from the program's second one.
    let shifted: Vec<Sample> = samples.iter().map(|s| Sample { line: s.line - 1, ..*s }).collect();
    let worst = within_segments(&shifted, &carried, 0.003).unwrap();
    assert!(worst > 0.0005, "the noise is not smoothed: {worst}");
}
