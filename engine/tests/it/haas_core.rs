//! The Haas NGC dialect's core rules that data fixtures cannot show (`tests/data/*/haas_*.nc`
//! hold the rest): the dwell's units, `fivex check` of the NGC's codes, the alarm of a FANUC
//! code the NGC does not have, a main program that reaches an M99 after M97, and `fivex check`
//! of the conditional M99.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::check::check;
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
