//! Every NC-level alarm path not covered by `macro_b.rs`, in both dialects.

use crate::common;
use common::*;
use fivex_engine::Dialect::{Fanuc, Haas, Syntec};

/// The alarm `src` ends in, in both dialects, with the line it names.
fn both(src: &str, fanuc: &str, syntec: &str, line: u32) {
    for (dialect, code) in [(Fanuc, fanuc), (Syntec, syntec)] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!(r.alarms.len(), 1, "{dialect:?}: expected one alarm from\n{src}");
        assert_eq!(r.alarms[0].code, code, "{dialect:?}\n{src}");
        assert_eq!(r.alarms[0].line, line, "{dialect:?}\n{src}");
    }
}

#[test]
fn plane_change_during_cutter_compensation() {
    both("G17 G41 D1 G01 X10. F100\nG18\n", "PS0037", "COR-013", 2);
    // Re-selecting the same plane is not a change.
    for dialect in [Fanuc, Syntec] {
        assert!(run_with("G17 G41 D1 G01 X10. F100\nG17\nG40 X0\nM30\n", "mill3", dialect).completed());
    }
}

#[test]
fn a_circle_without_radius_or_centre_is_r_or_ijk_not_found() {
    // FANUC PS0022 R OR I,J,K COMMAND NOT FOUND (30i alarm list); it was PS0020, the alarm of a
    // circle whose end is off it, as if the centre were the start.
    both("G90 G17 G01 X10. Y0 F1000.\nG02 X20. Y0\nM30\n", "PS0022", "COR-017", 2);
    // In G18 the plane's centre words are K and I; a J does not give the circle.
    both("G90 G18 G01 X10. Z0 F1000.\nG03 X20. Z0 J5.\nM30\n", "PS0022", "COR-017", 2);
    // A helical block with no motion in the plane and no centre has no circle either.
    both("G90 G17 G01 X10. Y0 F1000.\nG02 Z-5.\nM30\n", "PS0022", "COR-017", 2);
    let r = run_with("G90 G17 G01 X10. Y0 F1000.\nG02 X20. Y0\nM30\n", "mill3", fivex_engine::Dialect::Haas);
    assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("338", 2)));
    // One centre word is enough (the other is 0), R alone too.
    for arc in ["G02 X20. Y0 I5.", "G02 X20. Y0 R5.", "G02 X10. Y0 J5."] {
        let src = format!("G90 G17 G01 X10. Y0 F1000.\n{arc}\nM30\n");
        for dialect in [Fanuc, Syntec] {
            assert!(run_with(&src, "mill3", dialect).completed(), "{dialect:?} {arc}");
        }
    }
}

#[test]
fn g80_forgets_the_cycle_data() {
    // The dwell P of G82 must not survive G80 into a later G81.
    let src = "G00 Z10.\nG82 X0 Y0 Z-1. R1. P500 F600\nG80\nG81 X1. Y0 Z-1. R1.\nM30\n";
    let dwells = canon(src).iter().filter(|c| matches!(c.kind, fivex_engine::canon::CanonKind::Dwell { .. })).count();
    assert_eq!(dwells, 1);
}

#[test]
fn positions_read_in_inch_under_g20() {
    let r = run_src("G20 G00 X1. Y1\n#100=#5001\n#101=#5002\n#102=#5021\nM30\n");
    let v = |n| r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v).unwrap();
    assert!(approx(v(100), 1.0) && approx(v(101), 0.0001) && approx(v(102), 1.0), "{:?}", r.variables);
}

/// Syntec's G70/G71 are inch/metric input, as G20/G21 (decision, inferred from the Syntec
/// 5-axis manual's worked program, §4.7.2, which starts with G71); FANUC's milling G-code list
/// has neither (PS0010), the Haas NGC's are its bolt patterns.
#[test]
fn syntec_g70_and_g71_are_inch_and_metric_input() {
    // The units group: G20, then G21 (read from the state: Syntec's #4001–#5500 are user
    // parameters, refused, `syntec_macro.rs`).
    use fivex_engine::interp::gcode::{code, group};
    for (src, units) in [("G70 G00 X1. Y1.\nM30\n", code::G20), ("G70\nG71\nM30\n", code::G21)] {
        let mut interp = interpreter(src, "mill3", Syntec);
        interp.run(|_| {}).unwrap();
        assert_eq!(interp.state.modal(group::UNITS), units, "{src}");
    }
    let e = motion_ends(interpreter("G70 G00 X1.\nG71 G00 Y1.\nM30\n", "mill3", Syntec));
    assert!(approx(end_of(&e, 1)[0], 25.4) && approx(end_of(&e, 2)[1], 1.0), "{e:?}");
    for g in ["G70", "G71"] {
        let r = run_with(&format!("{g}\nM30\n"), "mill3", Fanuc);
        assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("PS0010", 1), "{g}");
    }
}

/// A resource bound, not data: kept here rather than in `tests/data/alarms` (its run takes the
/// interpreter through 200,000 pecks, four times over in the data harness).
#[test]
fn a_block_that_would_expand_without_bound_alarms() {
    // One million pecks: stopped at the expansion limit, not after exhausting memory.
    both("G00 Z1.\nG83 X0 Y0 Z-1000. R0 Q0.001 F1000.\n", "FX0003", "FX0003", 2);
}

#[test]
fn runaway_expressions_are_refused_not_crashing() {
    let long_sum = format!("#100=1{}\nM30\n", "+1".repeat(100_000));
    both(&long_sum, "PS0125", "COR-020", 1);
    let minus = format!("#100={}1\nM30\n", "-".repeat(100_000));
    both(&minus, "PS0125", "COR-020", 1);
    // Within the bound, fine.
    assert_eq!(var(&format!("#100=1{}\nM30\n", "+1".repeat(400)), 100), Some(401.0));
}

#[test]
fn a_time_budget_alarm_names_the_block() {
    let mut interp = interpreter("N10 G00 X0\nN20 G01 X500. F100.\nM30\n", "mill3", Fanuc);
    let r = fivex_engine::run::run(
        &mut interp,
        &fivex_engine::run::RunOptions { period_s: 0.0, max_time_s: 10.0, ..Default::default() },
        |_| {},
    );
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line, r.alarms[0].n), ("FX0002", 2, Some(20)));
    // The run stops where the budget runs out, inside the block: 10 s at 100 mm/min is about
    // 16.6 mm (less the speed-up).
    assert_eq!(r.cycle_time_s, 10.0);
    assert!(r.machine[0] > 16.0 && r.machine[0] < 16.7, "{}", r.machine[0]);
}

/// A G10 block holds G10's data, N and G90/G91, nothing else (`docs/conventions.md`, G10):
/// `G10 L2 P1 X5. G43 H1` had set G43 and dropped its H (the next move ran without the
/// length), `G10 L2 P1 X5. G01 Y10.` dropped the move. Another G code is the dialect's alarm
/// for codes that cannot share a block, an address the form does not take the improper
/// address, an address given twice or an L with a fraction the G10 format alarm; FANUC's L
/// written with a decimal point is PS0007 as at its other addresses that take none.
#[test]
fn a_g10_block_refuses_the_commands_it_would_drop() {
    let cases = [
        ("G10 L2 P1 X5. G43 H1", ("PS0010", "COR-070", "339")),
        ("G10 L2 P1 X5. G01 Y10. F100.", ("PS0010", "COR-070", "339")),
        ("G10 L2 P1 X5. G54", ("PS0010", "COR-070", "339")),
        ("G10 L2 P1 X5. H1", ("PS0009", "COR-002", "311")),
        ("G10 L12 P1 R5. D1", ("PS0009", "COR-002", "311")),
        ("G10 L10 P1 R5. Z1.", ("PS0009", "COR-002", "311")),
        ("G10 L2 P1 X5. M03", ("PS0009", "COR-002", "311")),
        ("G10 L2 P1 X5. F100.", ("PS0009", "COR-002", "311")),
        ("G10 L2 P1 X5. X6.", ("PS1144", "COR-014", "703")),
        ("G10 L2 P1 P2 X5.", ("PS1144", "COR-014", "703")),
        ("G10 L2.4 P1 X5.", ("PS0007", "COR-014", "703")),
        ("G10 L2. P1 X5.", ("PS0007", "", "")),
    ];
    for (block, (fanuc, syntec, haas)) in cases {
        let src = format!("G00 Z50.\n{block}\nG00 X10.\nM30\n");
        for (dialect, code) in [(Fanuc, fanuc), (Syntec, syntec), (Haas, haas)] {
            let r = run_with(&src, "mill3", dialect);
            if code.is_empty() {
                assert!(r.completed(), "{dialect:?} {block}: {:?}", r.alarms);
                continue;
            }
            let got = r.alarms.first().map(|a| (a.code.as_str(), a.line));
            assert_eq!(got, Some((code, 2)), "{dialect:?} {block}");
        }
    }
    // G10's own blocks still run, with G90/G91 and N: X1 added to X5 in G54.
    let src = "N1 G90 G10 L2 P1 X5.\nN2 G91 G10 L2 P1 X1.\nG90 G10 L12 P1 R5.\nM30\n";
    for dialect in [Fanuc, Syntec, Haas] {
        let mut interp = interpreter(src, "mill3", dialect);
        interp.run(|_| {}).unwrap_or_else(|a| panic!("{dialect:?}: {a:?}"));
        assert_eq!(interp.state.offsets.work(1)[0], 6.0, "{dialect:?}");
    }
    // `fivex check` reports them at the word.
    let diags =
        fivex_engine::check::check(fivex_engine::lang::parse_file("G10 L2 P1 X5. G43 H1\nG10 L12 P1 R5. D1\n"), Fanuc);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Fanuc.describe(&d.id).0)).collect();
    assert_eq!(found, vec![(1, 15, "PS0010".to_string()), (2, 16, "PS0009".to_string())]);
}

/// Audit A2 F4: `M98 H2` (Autodesk's SYIL/Syntec post calls its subprograms so) changed the tool
/// length to H2's in G43 and moved Z by the difference, then raised the call's alarm. A block
/// refused with an alarm does nothing: the machine stays where the block before left it
/// (tool 1 length 100 at Z15: machine Z 115), and the state it reports is the one before.
#[test]
fn a_call_refused_at_its_block_moves_nothing() {
    let src = "G10 L10 P2 R120.\nG90 G21 G54\nG00 X0 Y0\nG43 Z15. H01\nM98 H2\nM30\n";
    // FANUC: H is the tool length offset; an M98 without P has no program to call (PS0078).
    // Syntec: H of an M98 is the form of the call fivex does not build (COR-100).
    for (dialect, code) in [(Fanuc, "PS0078"), (Syntec, "COR-100")] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!(r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect::<Vec<_>>(), [(code, 5)], "{dialect:?}");
        assert_eq!(r.machine[2], 115.0, "{dialect:?}: the refused block moved Z");
        assert_eq!(r.workpiece[2], 15.0, "{dialect:?}");
    }
    // A call of a program the file does not have, in a block that moves: neither the move nor
    // the tool length change is made.
    let r = run_with("G90 G00 X0 Y0 Z15.\nG43 H1 G00 X10. Z20. M98 P1234\nM30\n", "mill3", Fanuc);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("PS0078", 2));
    assert_eq!(&r.machine[..3], &[0.0, 0.0, 15.0]);
    // Haas M97 to a line the program does not have: 337, nothing moved.
    let r = run_with("G90 G00 X0 Y0 Z15.\nG00 X10. M97 P500\nM30\n", "mill3", Haas);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("337", 2));
    assert_eq!(&r.machine[..3], &[0.0, 0.0, 15.0]);
}

/// Syntec audit: `M98 P100.5` with O0100 in the file: the run finds no program of a number with
/// a fraction, `fivex check` truncated it to 100 and said nothing. Both refuse it now.
#[test]
fn check_refuses_a_called_program_number_with_a_fraction_as_the_run_does() {
    let src = "M98 P100.5\nM30\nO0100\nG01 X1. F100.\nM99\n";
    for (dialect, code) in [(Fanuc, "PS0078"), (Syntec, "COR-030")] {
        let r = run_with(src, "mill3", dialect);
        assert_eq!(r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect::<Vec<_>>(), [(code, 1)], "{dialect:?}");
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(src), dialect);
        let found: Vec<_> = diags.iter().map(|d| (d.line, dialect.describe(&d.id).0)).collect();
        assert_eq!(found, [(1, code.to_string())], "{dialect:?}");
    }
    let src = "M98 P100\nM30\nO0100\nG01 X1. F100.\nM99\n";
    assert!(run_with(src, "mill3", Fanuc).completed());
    assert_eq!(fivex_engine::check::check(fivex_engine::lang::parse_file(src), Fanuc), []);
}

/// The Haas M78/M79 alarms are about the block's own G31 move: that move is made, then the
/// alarm (the one kind of alarm that follows its block's motion).
#[test]
fn m79_alarms_after_its_skip_move() {
    let r = run_with("G90 G00 X0 Y0 Z15.\nG31 X20. F500. M79\nM30\n", "mill3", Haas);
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("749", 2), "{:?}", r.alarms);
    assert_eq!(r.machine[0], 20.0);
}

/// Audit A F3: a number with more digits than an address takes is PS0003 TOO MANY DIGITS (it
/// was PS0005 for a nine-digit N, OT0510 for `X1234567890.`). FANUC's words have nine digits of
/// the least input increment (IS-B: ±999999.999), a sequence number eight (N1–N99999999).
#[test]
fn too_many_digits() {
    for block in ["N123456789 G00 X1.", "G00 X1234567890.", "G00 X1234567.", "G00 X1234567890", "G01 X1. F1234567."] {
        let src = format!("G90 G54 G17 G94\n{block}\nM30\n");
        both(&src, "PS0003", "COR-042", 2);
        let r = run_with(&src, "mill3", Haas);
        assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("331", 2), "{block}");
        let diags = fivex_engine::check::check(fivex_engine::lang::parse_file(&src), Fanuc);
        assert_eq!(diags.iter().map(|d| (d.line, Fanuc.describe(&d.id).0)).collect::<Vec<_>>(), [(2, "PS0003".into())]);
    }
    // At the limit, and decimals beyond the increment (rounded to it, not counted).
    for block in [
        "N12345678 G00 X1.",
        "G00 X123.456",
        "G00 X123456789",
        "G00 X-999.999",
        "G00 X12.3456789012",
        "G00 X0.000000001",
    ] {
        let src = format!("G90 G54 G17 G94\n{block}\nM30\n");
        let r = run_with(&src, "mill3", Fanuc);
        assert!(!r.alarms.iter().any(|a| a.code == "PS0003"), "{block}: {:?}", r.alarms);
    }
}
