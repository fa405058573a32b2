//! The Haas NGC dialect's core rules that data fixtures cannot show (`tests/data/*/haas_*.nc`
//! hold the rest): the dwell's units, `fivex check` of the NGC's codes, the alarm of a FANUC
//! code the NGC does not have, a main program that reaches an M99 after M97, and `fivex check`
//! of the conditional M99.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::check::check;
use fivex_engine::interp::gcode::{code, group};
use fivex_engine::lang::parse_file;
use fivex_engine::Dialect::{Fanuc, Haas};

fn dwells(src: &str, dialect: fivex_engine::Dialect) -> Vec<f64> {
    let mut interp = interpreter(src, "mill3", dialect);
    let mut v = Vec::new();
    interp.run(|c| v.push(c)).expect("no alarm");
    v.iter().filter_map(|c| if let CanonKind::Dwell { seconds } = c.kind { Some(seconds) } else { None }).collect()
}

/// G04 P: Haas reads a P with a decimal point in seconds and one without in milliseconds;
/// FANUC takes milliseconds without a point and refuses one (PS0007).
#[test]
fn dwell_p_with_a_point_is_seconds_in_haas() {
    let src = "G04 P1.5\nG04 P500\nM30\n";
    assert_eq!(dwells(src, Haas), vec![1.5, 0.5]);
    assert_eq!(dwells("G04 P500\nM30\n", Fanuc), vec![0.5]);
    assert_eq!(alarm(src), "PS0007");
}

/// `fivex check` reports a Haas code fivex does not build at its word, with the Haas alarm, and
/// a FANUC code the NGC does not have as no code of the dialect.
#[test]
fn check_reports_haas_codes() {
    let src = "G00 X1.\nG47 P0 (FIVEX)\nG54.1 P2\nG154 P3\nG110\nM30\n";
    let diags = check(parse_file(src), Haas);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect();
    assert_eq!(found, vec![(2, 1, "310".to_string()), (3, 1, "310".to_string())], "{diags:?}");
    assert!(diags[0].detail.contains("text engraving (G47)"), "{}", diags[0].detail);
    // FANUC's G47 is another function fivex does not build; it has neither G154 nor G110.
    let fanuc: Vec<_> = check(parse_file(src), Fanuc).iter().map(|d| d.line).collect();
    assert_eq!(fanuc, vec![2, 4, 5]);
}

/// M98 P in `fivex check`: Haas reads P as the program number (no count in front of it).
#[test]
fn check_reads_m98_p_as_the_program_number() {
    let src = "M98 P30010\nM30\nO0010\nM99\n";
    let lines = |d| check(parse_file(src), d).iter().map(|d| d.line).collect::<Vec<_>>();
    assert_eq!(lines(Fanuc), Vec::<u32>::new());
    assert_eq!(lines(Haas), vec![1]);
}

/// The skeleton accepted M97 as a plain M code: the program ran on into its local subprogram
/// and looped at its M99 until the block budget. Now the main program ends at its M30.
#[test]
fn m97_program_ends_at_m30() {
    let src = "G00 X1.\nM97 P100 L3\nM30\nN100 G91 X1.\nG90\nM99\n";
    let r = run_with(src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(approx(r.machine[0], 4.0), "{:?}", r.machine);
    assert!(r.blocks < 20, "{} blocks", r.blocks);
}

/// An L0 call does not run the subprogram (and does not disturb the caller).
#[test]
fn m97_l0_calls_nothing() {
    let src = "M98 P20\nM30\nO0020\nM97 P10 L0\n#100=1\nM99\nN10 #101=1\nM99\n";
    let r = run_with(src, "mill3", Haas);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.variables, vec![(100, 1.0)]);
}

/// Haas keeps #100–#199 and the NGC's own #10000… through power off, as it keeps #500–#999.
#[test]
fn haas_retains_100_to_199() {
    use fivex_engine::run::{run, RunOptions};
    let mut before = interpreter("#100=1\n#10200=2\n#500=3\nM30\n", "mill3", Haas);
    assert!(run(&mut before, &RunOptions::default(), |_| {}).completed());
    let kept = before.state.retained_variables();
    assert_eq!(kept, vec![(100, 1.0), (500, 3.0), (10200, 2.0), (3901, 1.0)]);
    let mut after = interpreter("#101=#100\n#102=#10200\nM30\n", "mill3", Haas);
    let values: Vec<(u32, Option<f64>)> = kept.iter().map(|&(n, v)| (n, Some(v))).collect();
    after.state.load_retained(&values).unwrap();
    let r = run(&mut after, &RunOptions::default(), |_| {});
    let v = |n: u32| r.variables.iter().find(|(k, _)| *k == n).map(|p| p.1);
    assert_eq!((v(101), v(102)), (Some(1.0), Some(2.0)));
}

/// `fivex check` reports the Haas M codes fivex does not build (M96 jumps on an input).
#[test]
fn check_reports_haas_m_codes() {
    let src = "G00 X1.\nM96 P10 Q8\nM109 P501\nM30\nN10 M30\n";
    let found: Vec<_> = check(parse_file(src), Haas).iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect();
    assert_eq!(found, vec![(2, 1, "329".to_string()), (3, 1, "329".to_string())]);
    assert!(check(parse_file(src), Fanuc).is_empty());
}

/// `fivex check` in the Haas dialect: M97 to a line the program does not have (337), and M97,
/// M98, G65 without P (313).
#[test]
fn check_reports_m97_targets_and_missing_p() {
    let src = "M97 P100\nM97 P200\nM97 L2\nM98 L2\nG65 A1.\nM30\nN100 M99\n";
    let found: Vec<_> = check(parse_file(src), Haas).iter().map(|d| (d.line, d.col, Haas.describe(&d.id).0)).collect();
    let want = [(2, 5, "337"), (3, 1, "313"), (4, 1, "313"), (5, 1, "313")];
    assert_eq!(found, want.map(|(l, c, code)| (l, c, code.to_string())), "{found:?}");
}

/// `fivex check` and the conditional M99 `[cond] M99 P<n>`: in the Haas dialect a literal P the
/// program has no N for is 337 and other words after the condition 540; FANUC reports the
/// block as the syntax error it was before the form was read (a block cannot start with '[').
#[test]
fn check_reports_the_conditional_m99() {
    let src = "#100=1\nN10 [#100 LT 3] M99 P10\n[#100 LT 3] M99 P20\n[#100 LT 3] X1.\nM30\n";
    let found = |d: fivex_engine::Dialect| -> Vec<_> {
        check(parse_file(src), d).iter().map(|x| (x.line, d.describe(&x.id).0)).collect()
    };
    assert_eq!(found(Haas), vec![(3, "337".to_string()), (4, "540".to_string())]);
    let fanuc = vec![(2, "PS0004".to_string()), (3, "PS0004".to_string()), (4, "PS0004".to_string())];
    assert_eq!(found(Fanuc), fanuc);
}

/// The machine position of every axis at the end of `src` on `preset`, which must complete.
fn machine_at_end(src: &str, preset: &str, dialect: fivex_engine::Dialect) -> Vec<f64> {
    let r = run_with(src, preset, dialect);
    assert!(r.completed(), "{dialect:?}: {:?}", r.alarms);
    let axes = fivex_engine::machine::MachineConfig::preset(preset).unwrap().axes.len();
    r.machine[..axes].to_vec()
}

fn approx_all(got: &[f64], want: &[f64]) -> bool {
    got.len() == want.len() && got.iter().zip(want).all(|(a, b)| approx(*a, *b))
}

/// Haas: a G28 without axis words returns every axis, the rotary ones too, to machine zero
/// (96-8000 rev R, G28); before, it moved nothing, as FANUC's G28 that names no axis, which
/// stays so. G54 = (−400, −200, −400), tool length 100: line 3 leaves the machine at X −500,
/// Y −300, Z −400 + 50 + 100 = −250, A30 C45.
#[test]
fn g28_without_axes_returns_every_axis_in_haas() {
    let src = "G10 L2 P1 X-400. Y-200. Z-400.\nG90 G54 G00 A30. C45.\nG43 H1 X-100. Y-100. Z50.\nG28\nM30\n";
    let haas = machine_at_end(src, "table-ac", Haas);
    assert!(approx_all(&haas, &[0.0; 5]), "{haas:?}");
    let fanuc = machine_at_end(src, "table-ac", Fanuc);
    assert!(approx_all(&fanuc, &[-500.0, -300.0, -250.0, 30.0, 45.0]), "{fanuc:?}");
    // With axis words only those return (Z), in both dialects.
    let z_only = src.replace("G28\n", "G91 G28 Z0\n");
    for dialect in [Haas, Fanuc] {
        let m = machine_at_end(&z_only, "table-ac", dialect);
        assert!(approx_all(&m, &[-500.0, -300.0, 0.0, 30.0, 45.0]), "{dialect:?}: {m:?}");
    }
}

/// Haas: G28 cancels tool length compensation for the blocks after it (96-8000 rev R, G28 and
/// G49); FANUC keeps G43. G54 Z −400, tool length 100: after `G91 G28 Z0` the `G00 Z200.` goes
/// to machine Z −400 + 200 = −200 without the length, −100 with it. The audit's program (the
/// report's F1/F2): after a bare G28, `G01 Z100.` feeds to −300 on a Haas.
#[test]
fn g28_cancels_tool_length_in_haas() {
    let head = "G10 L2 P1 X-400. Y-200. Z-400.\nG90 G54 G00 G17 G40 G49 G80\nG43 H1 Z150.\n";
    let src = format!("{head}G91 G28 Z0.\nG90 G00 X0 Y0\nG00 Z200.\n#100=#4008\nM30\n");
    assert!(approx_all(&machine_at_end(&src, "mill3", Haas), &[-400.0, -200.0, -200.0]));
    assert!(approx_all(&machine_at_end(&src, "mill3", Fanuc), &[-400.0, -200.0, -100.0]));
    let group08 = |d| run_with(&src, "mill3", d).variables.iter().find(|v| v.0 == 100).map(|v| v.1);
    assert_eq!((group08(Haas), group08(Fanuc)), (Some(49.0), Some(43.0)));
    let audit = format!("{head}G00 X-100. Y-100.\nG28\nG00 X0 Y0\nG01 Z100. F500.\nM30\n");
    assert!(approx_all(&machine_at_end(&audit, "mill3", Haas), &[-400.0, -200.0, -300.0]));
}

/// Haas: H0 and M30 cancel tool length compensation too (96-8000 rev R, G49). `G43 H1` then
/// `H0 Z50.` goes to machine Z −400 + 50 = −350 with no length in both dialects (FANUC's H0 is
/// a length of 0 under G43), but a later `H1` alone takes the length again only where G43 is
/// still in force: FANUC −250, Haas −350. After M30 the next program starts in G49 on a Haas.
#[test]
fn h0_and_m30_cancel_tool_length_in_haas() {
    let src = "G10 L2 P1 Z-400.\nG90 G54 G00 G43 H1 Z50.\nH0 Z50.\nH1 Z50.\nM30\n";
    let z = |d| machine_at_end(src, "mill3", d)[2];
    assert!(approx(z(Haas), -350.0) && approx(z(Fanuc), -250.0), "{} {}", z(Haas), z(Fanuc));
    // M30: the group 08 mode after the program end (the interpreter keeps its state).
    for (dialect, want) in [(Haas, code::G49), (Fanuc, code::G43)] {
        let mut interp = interpreter("G10 L2 P1 Z-400.\nG90 G54 G00 G43 H1 Z50.\nM30\n", "mill3", dialect);
        interp.run(|_| {}).expect("no alarm");
        assert_eq!(interp.state.modal(group::LENGTH_COMP), want, "{dialect:?}");
    }
}

/// Haas: reset cancels tool length compensation (96-8000 rev R, G49); the machine stays.
#[test]
fn reset_cancels_tool_length_in_haas() {
    for (dialect, want) in [(Haas, code::G49), (Fanuc, code::G43)] {
        let mut interp = interpreter("G10 L2 P1 Z-400.\nG90 G54 G00 G43 H1 Z50.\nM00\nM30\n", "mill3", dialect);
        let mut out = Vec::new();
        while !out.iter().any(|c: &fivex_engine::canon::Canon| matches!(c.kind, CanonKind::Stop { .. })) {
            interp.step(&mut out).expect("no alarm");
        }
        interp.reset();
        assert_eq!(interp.state.modal(group::LENGTH_COMP), want, "{dialect:?}");
    }
}

/// Haas has 200 tool offsets: H or D beyond them, and G10 L10–L13 P beyond them, are `331
/// RANGE ERROR` (before, `G43 H999` ran with a length of 0); FANUC's 999 are unchanged.
#[test]
fn tool_offsets_beyond_200_are_a_range_error_in_haas() {
    for block in ["G43 H201 Z10.", "G43 H999 Z10.", "G41 D201 X1.", "G10 L10 P201 R50.", "D250"] {
        let src = format!("G00 Z100.\n{block}\nG40 G49\nM30\n");
        let r = run_with(&src, "mill3", Haas);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("331", 2)), "{block}");
        assert!(run_with(&src, "mill3", Fanuc).completed(), "FANUC {block}");
    }
    assert!(run_with("G43 H200 Z10.\nD200\nG49\nM30\n", "mill3", Haas).completed());
    // G234 (TCPC) took its length from H999 as 0 too.
    let tcpc = run_with("G90 G00 A0 C0\nG234 H999\nG49\nM30\n", "table-ac", Haas);
    assert_eq!(tcpc.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("331", 2)));
    assert_eq!(alarm_with("G43 H1000 Z10.\nM30\n", Fanuc), "PS0030");
}

/// Haas: a block that selects G43/G44 with no H given or in force (none since power-on, or H0)
/// is `754` at its block, and `fivex check` reports it in the main program (constructed code,
/// *decision*: no Haas source says what the NGC does; before, `G43 Z50.` ran with a length of
/// 0, the spindle nose at machine Z −400 + 50 = −350 and the 100 mm tool's tip at −450, where
/// Z50. was programmed). With an H in force it runs with that length: −400 + 50 + 100 = −250.
/// FANUC keeps H0's length of 0 (−350).
#[test]
fn g43_without_h_is_refused_in_haas() {
    let head = "G10 L2 P1 Z-400.\nG90 G54 G00 G17 G40 G49 G80\n";
    for block in ["G43 Z50.", "G44 Z50.", "G43 H1 Z50.\nH0 Z60.\nG43 Z50."] {
        let src = format!("{head}{block}\nM30\n");
        let line = 2 + block.lines().count() as u32;
        let r = run_with(&src, "mill3", Haas);
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("754", line)), "{block}");
        let diags = check(parse_file(&src), Haas);
        assert_eq!(diags.iter().map(|d| (d.line, d.col)).collect::<Vec<_>>(), vec![(line, 1)], "{block}");
        assert!(run_with(&src, "mill3", Fanuc).completed(), "FANUC {block}");
    }
    assert!(approx(machine_at_end(&format!("{head}G43 Z50.\nM30\n"), "mill3", Fanuc)[2], -350.0));
    // An H in force: given alone before, or kept through G49 (as FANUC's H is; no source either
    // way for the NGC). H0 in the G43 block cancels it (the G49 page): no length, no alarm.
    for (block, z) in [("H1\nG43 Z50.", -250.0), ("G43 H1 Z80.\nG49 Z80.\nG43 Z50.", -250.0), ("G43 H0 Z50.", -350.0)] {
        let src = format!("{head}{block}\nM30\n");
        assert!(approx(machine_at_end(&src, "mill3", Haas)[2], z), "{block}");
        assert_eq!(check(parse_file(&src), Haas), vec![], "{block}");
    }
    // Check reads no further than the text tells the H: after a call, a subprogram's G43 alone.
    let called = format!("{head}M98 P100\nG43 Z50.\nM30\nO100\nH1\nG43 Z50.\nM99\n");
    assert_eq!(check(parse_file(&called), Haas), vec![]);
    assert!(run_with(&called, "mill3", Haas).completed());
}
