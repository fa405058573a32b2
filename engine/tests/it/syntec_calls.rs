//! Syntec's subprogram and macro calls where they are not FANUC's (audit "Syntec everyday G
//! codes", F1–F4; `docs/dialects.md`, "Syntec's subprogram and macro calls"): M98's P is the whole program
//! name, M02/M30 in an M98 subprogram returns to the caller, G66.1 is not built, and the alarms
//! the Syntec MACRO handbook (`SYNTEC-40101720/syntec-macro`) names carry its codes. FANUC and
//! Haas read the same text as before.

use crate::common::*;

use fivex_engine::check::check;
use fivex_engine::lang::parse_file;
use fivex_engine::run::{run, RunOptions, RunResult};
use fivex_engine::Dialect::{self, Fanuc, Haas, Syntec};

fn syntec(src: &str) -> RunResult {
    run_with(src, "mill3", Syntec)
}

/// The alarms of a run as (code, line).
fn alarms(r: &RunResult) -> Vec<(String, u32)> {
    r.alarms.iter().map(|a| (a.code.clone(), a.line)).collect()
}

/// `fivex check`'s diagnostics as (line, code).
fn checked(src: &str, dialect: Dialect) -> Vec<(u32, String)> {
    check(parse_file(src), dialect).iter().map(|d| (d.line, dialect.describe(&d.id).0)).collect()
}

/// The machine position at the end of the run (mill3, no offsets: the programmed position).
fn end(r: &RunResult) -> [f64; 3] {
    let p = r.machine;
    [p[0], p[1], p[2]]
}

/// F2: `M98 P12345` ran O2345 (FANUC's count 1 in front of a four-digit number); on Syntec P is
/// the subprogram's name and L the count (handbook §5.1, CALL-M98-001), so O12345 runs once:
/// Y 0 → 7, X stays 0. FANUC keeps its reading (O2345: X 0 → 1).
#[test]
fn m98_p_of_five_digits_is_the_program_number() {
    let src = "O1\nG90 G00 X0 Y0 Z10.\nM98 P12345\nM30\n\
               O2345\nG91 G01 X1. F1000\nG90\nM99\n\
               O12345\nG91 G01 Y7. F1000\nG90\nM99\n";
    let r = syntec(src);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [0.0, 7.0, 10.0]);
    assert_eq!(checked(src, Syntec), []);
    let r = run_with(src, "mill3", Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [1.0, 0.0, 10.0]);
    // With L the count is L's: three times O12345, Y 0 → 21.
    let r = syntec(&src.replace("M98 P12345", "M98 P12345 L3"));
    assert_eq!(end(&r), [0.0, 21.0, 10.0]);
}

/// F2: `M98 P30100` with only O100 loaded ran O100 three times; on Syntec it calls O30100,
/// which is not there: COR-030 at the call, before anything of it runs, and `fivex check`
/// says so too. FANUC and Haas as before (FANUC: O100 three times; Haas: 314).
#[test]
fn m98_p30100_calls_o30100_not_o100_three_times() {
    let src = "O1\nG90 G00 X3. Y0 Z10.\nM98 P30100\nM30\nO100\nG91 G01 X1. F1000\nG90\nM99\n";
    let r = syntec(src);
    assert_eq!(alarms(&r), [("COR-030".to_string(), 3)]);
    assert_eq!(end(&r), [3.0, 0.0, 10.0]);
    assert_eq!(checked(src, Syntec), [(3, "COR-030".to_string())]);
    let r = run_with(src, "mill3", Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [6.0, 0.0, 10.0]);
    assert_eq!(checked(src, Fanuc), []);
    assert_eq!(alarm_with(src, Haas), "314");
}

/// F4 (call semantics pack §2.2): M198 without P is COR-052 on Syntec (it was COR-030, "not
/// found"); M98 without P calls the running program itself there, which fivex does not build
/// (COR-100). Both before the block moves, in the run and in `fivex check`.
#[test]
fn m198_without_p_is_cor_052_and_m98_without_p_is_not_built() {
    for (m, code) in [("M198", "COR-052"), ("M98", "COR-100")] {
        let src = format!("O1\nG90 G00 X0 Y0 Z10.\nG00 X5. {m}\nM30\nO100\nM99\n");
        let r = syntec(&src);
        assert_eq!(alarms(&r), [(code.to_string(), 3)], "{m}");
        assert_eq!(end(&r), [0.0, 0.0, 10.0], "{m}: the block did nothing");
        assert_eq!(checked(&src, Syntec), [(3, code.to_string())], "{m}");
        assert_eq!(alarm_with(&src, Fanuc), "PS0078");
    }
}

const F1: &str = "O1\nG21 G90 G17 G54 G40 G49 G80\nG00 X0 Y0 Z10.\nM98 P100\nG00 Z50.\nG00 X50. Y50.\nM30\n\
                  O100\nG01 Z-1. F500\nG01 X20. F1000\nG00 Z10.\nM30\n";

/// F1: an M30 in an M98 subprogram ended the whole run at (20, 0, 10); on Syntec it ends the
/// subprogram and returns to the caller (call semantics pack §2.2), so the main program's
/// `G00 Z50.` and `G00 X50. Y50.` run: the end is (50, 50, 50), and the part is counted once
/// (the main program's M30), not at the subprogram's. FANUC and Haas end at the subprogram's M30.
#[test]
fn m30_in_an_m98_subprogram_returns_to_the_caller() {
    let mut interp = interpreter(F1, "mill3", Syntec);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [50.0, 50.0, 50.0]);
    assert_eq!(interp.state.part_count().0, 1.0);
    // M02 the same; and from a subprogram called by a subprogram, back to that one.
    let r = syntec(&F1.replace("G00 Z10.\nM30", "G00 Z10.\nM02"));
    assert_eq!(end(&r), [50.0, 50.0, 50.0]);
    let nested = "O1\nG90 G00 X0 Y0 Z10.\nM98 P100\nG00 Z50.\nM30\n\
                  O100\nM98 P200\nG00 Y9.\nM30\nO200\nG00 X4.\nM30\n";
    let r = syntec(nested);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [4.0, 9.0, 50.0]);
    for other in [Fanuc, Haas] {
        let r = run_with(F1, "mill3", other);
        assert!(r.completed(), "{other:?}: {:?}", r.alarms);
        assert_eq!(end(&r), [20.0, 0.0, 10.0], "{other:?}");
    }
    // M30 in the main program still ends the run.
    let r = syntec("G90 G00 X0 Y0 Z10.\nM30\nG00 X99.\n");
    assert_eq!(end(&r), [0.0, 0.0, 10.0]);
}

/// F1: where the handbook does not say what M02/M30 does — in a G65 macro (it speaks of
/// subprograms), or in a subprogram whose call has repetitions still to come (`M98 P100 L2`) —
/// the Syntec dialect refuses the M30 block as not built (COR-100) instead of ending the run.
#[test]
fn m30_in_a_macro_or_a_repeated_subprogram_is_refused_on_syntec() {
    let g65 = F1.replace("M98 P100", "G65 P100 A1.");
    let repeated = F1.replace("M98 P100", "M98 P100 L2");
    for src in [&g65, &repeated] {
        let r = syntec(src);
        assert_eq!(alarms(&r), [("COR-100".to_string(), 12)], "{src}");
        assert_eq!(end(&r), [20.0, 0.0, 10.0], "{src}");
        let r = run_with(src, "mill3", Fanuc);
        assert!(r.completed(), "{:?}", r.alarms);
        assert_eq!(end(&r), [20.0, 0.0, 10.0]);
    }
    // The last repetition's M30 returns: L1 is a plain call.
    let r = syntec(&F1.replace("M98 P100", "M98 P100 L1"));
    assert_eq!(end(&r), [50.0, 50.0, 50.0]);
}

/// F3: G66.1 ran FANUC's rule (the later blocks' moves not made, their words the arguments:
/// X10. and X20. never moved, the macro ran three times, end (0, 0, 13)); Syntec's runs each
/// block and calls after it (handbook CALL-G661-001), with details the source leaves open, so the
/// Syntec dialect refuses G66.1 as not built at its block (COR-100), in the run and in
/// `fivex check`. FANUC keeps its rule.
#[test]
fn g66_1_is_not_built_in_the_syntec_dialect() {
    let src = "O1\nG90 G01 X0 Y0 Z10. F1000\nG66.1 P100\nX10.\nX20.\nG67\nM30\nO100\nG91 G00 Z1.\nG90\nM99\n";
    let r = syntec(src);
    assert_eq!(alarms(&r), [("COR-100".to_string(), 3)]);
    assert_eq!(end(&r), [0.0, 0.0, 10.0]);
    assert_eq!(checked(src, Syntec), [(3, "COR-100".to_string())]);
    let r = run_with(src, "mill3", Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [0.0, 0.0, 13.0]);
    assert_eq!(checked(src, Fanuc), []);
}

/// F3, G66: Syntec's, as FANUC's, makes the block's move and then calls the macro with the G66
/// block's arguments (the technical reference's GETARG/GETTRAPARG example: `GETARG(X)` is the
/// G66 block's 100 after `G01 X20.`): X 0 → 20, then Y to #24 = 100.
#[test]
fn g66_moves_then_calls_with_its_own_arguments_in_the_syntec_dialect() {
    let src = "O1\nG90 G01 X0 Y0 Z10. F1000\nG66 P100 X100.\nG01 X20.\nG67\nM30\nO100\nG01 Y#24\nM99\n";
    for dialect in [Syntec, Fanuc] {
        let r = run_with(src, "mill3", dialect);
        assert!(r.completed(), "{dialect:?}: {:?}", r.alarms);
        assert_eq!(end(&r), [20.0, 100.0, 10.0], "{dialect:?}");
    }
}

/// The handbook (§2.3, §5.1) gives a G66 macro one set of local variables "从 `G66` 到 `G67`
/// 期间共用" (shared by its calls from G66 to G67, cleared by G67), where a G65 call makes fresh
/// ones. A counter the macro keeps in #10 counts 1, 2, 3 over three moves: Y ends at 3, where
/// fresh locals at each call (FANUC's rule, and fivex's before) end at 1. After G67 a new G66
/// starts from new locals (Y 1 again). The L repetitions of one call share them too (`L2`: 2, 4, 6).
#[test]
fn g66_calls_share_their_local_variables_until_g67_in_the_syntec_dialect() {
    let prog = |calls: &str| format!("O1\nG90 G01 X0 Y0 Z10. F1000\n{calls}\nM30\nO100\n#10=#10+1.\nG01 Y#10\nM99\n");
    let three = prog("G66 P100 A1.\nG01 X1.\nG01 X2.\nG01 X3.\nG67");
    let r = syntec(&three);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [3.0, 3.0, 10.0]);
    let r = run_with(&three, "mill3", Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [3.0, 1.0, 10.0]);
    // G67 ends them: the next G66's first call counts from vacant again.
    let r = syntec(&prog("G66 P100\nG01 X1.\nG01 X2.\nG67\nG66 P100\nG01 X3.\nG67"));
    assert_eq!(end(&r), [3.0, 1.0, 10.0], "{:?}", r.alarms);
    // Repetitions share them: two calls of L2 count to 4.
    let r = syntec(&prog("G66 P100 L2\nG01 X1.\nG01 X2.\nG67"));
    assert_eq!(end(&r), [2.0, 4.0, 10.0], "{:?}", r.alarms);
}

/// What the handbook leaves open: whether each call of a G66 writes the G66 block's arguments
/// into #1–#26 again (it says so of G65, §2.3 "引数写入 #1 ~ #26", and of G66 only that the
/// locals are shared). A variable holding an argument that an earlier call changed reads
/// differently under the two readings (#1 = 1. again, or 2.): reading it in a later call before
/// writing it is refused (COR-100 at that block). Written first, it is the same under both;
/// the first call reads its arguments as any call; a variable no argument set is kept.
#[test]
fn g66_argument_an_earlier_call_changed_is_refused_when_read_in_the_syntec_dialect() {
    let src = "O1\nG90 G01 X0 Y0 Z10. F1000\nG66 P100 A1.\nG01 X1.\nG01 X2.\nG67\nM30\n\
               O100\n#1=#1+1.\nG01 Y#1\nM99\n";
    let r = syntec(src);
    // The first call (after line 4) moves Y to 2; the second's read of #1 (line 9) is refused.
    assert_eq!(alarms(&r), [("COR-100".to_string(), 9)]);
    assert_eq!(end(&r), [2.0, 2.0, 10.0]);
    // Written before it is read: both readings agree.
    let r = syntec(&src.replace("#1=#1+1.", "#1=5.\n#1=#1+1."));
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [2.0, 6.0, 10.0]);
    // Changed back to the argument's value and type: no difference, no refusal.
    let r = syntec(&src.replace("#1=#1+1.\nG01 Y#1", "G01 Y#1\n#1=7.\n#1=1."));
    assert!(r.completed(), "{:?}", r.alarms);
    // FANUC: fresh arguments at each call.
    let r = run_with(src, "mill3", Fanuc);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(end(&r), [2.0, 2.0, 10.0]);
}

/// F4: the handbook's §9.14 names COR-004 for an operation's domain error (`ATAN2(0,0)`), and
/// COR-016, COR-023, COR-027 and COR-034 are its codes of other alarms: fivex's constructed
/// codes for a zero divisor, DO without END, G28 in a canned cycle and scaling P0 move off them.
#[test]
fn syntec_alarm_codes_do_not_collide_with_the_handbooks() {
    let cases = [
        ("#1=ATAN[0]/[0]\nM30\n", "COR-004", "PS0119"),
        ("#1=SQRT[-1]\nM30\n", "COR-004", "PS0119"),
        ("#1=0\n#2=1/#1\nM30\n", "COR-004", "PS0112"),
        ("WHILE[1 LT 2] DO1\nG00 X1.\nM30\n", "COR-044", "PS0124"),
        ("G90 G00 X0 Y0 Z10.\nG81 X1. Y1. Z-1. R2. F100\nG28 Z10.\nM30\n", "COR-043", "PS0044"),
        ("G51 X0 Y0 Z0 P0\nM30\n", "COR-045", "PS0142"),
        ("G00 X1234567890123456\nM30\n", "COR-042", "PS0003"),
    ];
    for (src, syntec_code, fanuc_code) in cases {
        assert_eq!(alarm_with(src, Syntec), syntec_code, "{src}");
        assert_eq!(alarm_with(src, Fanuc), fanuc_code, "{src}");
    }
    // POW's base may not be negative on Syntec (handbook §9.2, COR-122); FANUC takes a whole
    // exponent: POW[-2,3] = -8.
    assert_eq!(alarm_with("#1=POW[-2,3]\nM30\n", Syntec), "COR-122");
    assert_eq!(alarm_with("#1=POW[-2.5,2]\nM30\n", Syntec), "COR-122");
    assert_eq!(var("#100=POW[-2,3]\nM30\n", 100), Some(-8.0));
    assert!(syntec("#1=POW[2,3]\n#2=POW[0,2]\nM30\n").completed());
    let message = |id| Syntec.describe(&id);
    use fivex_engine::alarm::AlarmId;
    assert_eq!(message(AlarmId::MissingP).0, "COR-052");
    assert_eq!(message(AlarmId::ArgumentOutOfRange), ("COR-004".into(), "Operation domain error".into()));
}

/// A variable number the Syntec dialect does not keep is the handbook's `COR-016` "不合法的变数
/// 存取" (illegal variable access: §2.8's "存取超出开放范围或当前应用不允许的变量", a variable outside
/// the open ranges or not allowed here, and §9.14), read or written, in the run and in `fivex
/// check`; it was the constructed COR-021. FANUC keeps PS0115.
#[test]
fn a_variable_out_of_the_kept_ranges_is_the_handbooks_cor_016() {
    for src in ["#34=1.\nM30\n", "#1=#3901\nM30\n", "G00 X#1100\nM30\n"] {
        assert_eq!(alarm_with(src, Syntec), "COR-016", "{src}");
        assert_eq!(checked(src, Syntec), [(1, "COR-016".to_string())], "{src}");
    }
    assert_eq!(alarm_with("#34=1.\nM30\n", Fanuc), "PS0115");
    let message = Syntec.describe(&fivex_engine::alarm::AlarmId::VariableOutOfRange);
    assert_eq!(message, ("COR-016".into(), "Illegal variable access".into()));
}
