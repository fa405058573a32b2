//! Work and tool offsets as programs select and set them: the audit of tool data and work
//! offsets (`docs/conventions.md`, "The language", G10 and "G54 P").

use crate::common::*;
use fivex_engine::check::check;
use fivex_engine::lang::parse_file;
use fivex_engine::run::RunOptions;
use fivex_engine::Dialect::{self, Fanuc, Haas, Syntec};

/// The codes `fivex check` reports for `src` in `dialect`, with their line.
fn checked(src: &str, dialect: Dialect) -> Vec<(u32, String)> {
    check(parse_file(src), dialect).iter().map(|d| (d.line, dialect.describe(&d.id).0)).collect()
}

/// Audit F1: `G54 P2` ran in G54, its P dropped. FANUC's format is "G54.1 Pn ; or G54 Pn ;":
/// G54 P2 selects G54.1 P2 (machine X −3 = its offset; −7 was G54's), `#4014` reads 54.1 and
/// `#4130` 2.
#[test]
fn fanuc_g54_p_selects_the_additional_work_system() {
    let src = "G21 G90 G49\nG10 L20 P1 X-1.\nG10 L20 P2 X-3.\nG10 L2 P1 X-7.\nG10 L2 P2 X-9.\n\
               G54 P2 G00 X0\n#100=#4014\n#101=#4130\nM30\n";
    let r = run_src(src);
    assert!(r.completed(), "{:?}", r.alarms);
    assert_eq!(r.machine[0], -3.0);
    let v = |n| r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v);
    assert_eq!((v(100), v(101)), (Some(54.1), Some(2.0)));
    // P out of G54.1's range is G54.1's alarm.
    assert_eq!(alarm("G54 P301\nM30\n"), "PS0030");
}

/// Where the dialect gives P beside G54…G59 no meaning (FANUC's G55–G59, Syntec's and Haas's
/// G54–G59), the P is refused (not built) rather than dropped; the P of another code of the
/// block is that code's (`G54 M98 P100` calls O100), except in FANUC's G54, where both would
/// take it (PS0010). `fivex check` reports them.
#[test]
fn a_p_beside_g54_to_g59_is_not_dropped() {
    for (src, dialect, code) in [
        ("G55 P2 G00 X0\nM30\n", Fanuc, "PS0009"),
        ("G54 P2 G00 X0\nM30\n", Syntec, "COR-100"),
        ("G54 P2 G00 X0\nM30\n", Haas, "311"),
        ("G59 P2\nM30\n", Haas, "311"),
        ("G54 G04 P100\nM30\n", Fanuc, "PS0010"),
        ("G54 M98 P100\nM30\n", Fanuc, "PS0010"),
    ] {
        let r = run_with(src, "mill3", dialect);
        let got: Vec<_> = r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect();
        assert_eq!(got, [(code, 1)], "{dialect:?} {src}");
        assert!(checked(src, dialect).contains(&(1, code.to_string())), "{dialect:?} {src}");
    }
    // The P of a dwell or a call in Syntec: that code's.
    let r = run_with("G55 G04 P100\nM30\n", "mill3", Syntec);
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(checked("G55 G04 P100\nM30\n", Syntec).is_empty());
}

/// Audit F4: `G91 G53 X-10.` moved to machine X−10 (90 mm from −100) without an alarm. G53 is
/// given in absolute terms; controls differ on an incremental one, so it is refused (PS0010,
/// COR-070, Haas 339) under G91 in force or in its block, and nothing moves.
#[test]
fn g53_under_g91_is_refused() {
    let src = "G21 G90 G49\nG10 L2 P1 X-100. Y-50. Z-200.\nG54 G00 X0 Y0 Z100.\nG91 G53 X-10.\nG90\nM30\n";
    for (dialect, code) in [(Fanuc, "PS0010"), (Syntec, "COR-070"), (Haas, "339")] {
        let r = run_with(src, "mill3", dialect);
        let got: Vec<_> = r.alarms.iter().map(|a| (a.code.as_str(), a.line)).collect();
        assert_eq!(got, [(code, 4)], "{dialect:?}");
        assert_eq!(r.machine[0], -100.0, "{dialect:?}");
    }
    assert_eq!(alarm("G91\nG53 Z0\nM30\n"), "PS0010");
    assert_eq!(alarm("G53 G91 Z0\nM30\n"), "PS0010");
    assert!(run_src("G91 G28 Z0\nG90 G53 Z0\nM30\n").completed());
}

/// The alarm code and line of `src` in `dialect` on mill3 (None: it completed).
fn first(src: &str, dialect: Dialect) -> Option<(String, u32)> {
    run_with(src, "mill3", dialect).alarms.first().map(|a| (a.code.clone(), a.line))
}

/// Audit F5: a G10 whose P is missing, negative, fractional or out of its form's range, or
/// whose R is missing, is FANUC's PS0031 ILLEGAL P COMMAND IN G10 ("No data setting address
/// such as P or R was specified … The sign or decimal point of the specified address is in
/// error, or the specified address is out of range", 30i alarm list); it was PS0030 (the H/D
/// number alarm) or PS1144. Syntec's constructed COR-046, Haas's 331 RANGE ERROR.
#[test]
fn a_wrong_or_missing_p_of_g10_is_ps0031() {
    for block in [
        "G10 L2 P7 X1.",
        "G10 L2 P-1 X1.",
        "G10 L2 X1.",
        "G10 L20 P0 X1.",
        "G10 L20 P301 X1.",
        "G10 L10 P1000 R1.",
        "G10 L10 P0 R1.",
        "G10 L11 R1.",
        "G10 L12 P2.5 R1.",
        "G10 L10 P1",
        "G10 L13 P1 R#0",
    ] {
        let src = format!("G21 G90\n{block}\nM30\n");
        for (dialect, code) in [(Fanuc, "PS0031"), (Syntec, "COR-046"), (Haas, "331")] {
            assert_eq!(first(&src, dialect), Some((code.to_string(), 2)), "{dialect:?} {block}");
        }
    }
    // The ranges themselves: L2 P0–P6, L20 P1–P300 (Haas P1–P99), L10–L13 P1–P999 (Haas 200).
    let src = "G10 L2 P0 X1.\nG10 L2 P6 X1.\nG10 L20 P1 X1.\nG10 L20 P300 X1.\nG10 L10 P999 R1.\nM30\n";
    assert_eq!(first(src, Fanuc), None);
    assert_eq!(first("G10 L20 P100 X1.\nM30\n", Haas), Some(("331".into(), 1)));
    assert_eq!(first("G10 L10 P201 R1.\nM30\n", Haas), Some(("331".into(), 1)));
    // A P or L with a decimal point: PS0031 / PS0007 in FANUC; Syntec and Haas read the whole
    // value (P2 takes 7 mm), as their L.
    let src = "G21 G90\nG10 L10 P2. R7.\n#100=#11002\nM30\n";
    assert_eq!(first(src, Fanuc), Some(("PS0031".into(), 2)));
    // (Haas's length geometry of offset 2 is #2002; Syntec's tool offset variables are refused,
    // so there the length shows in the machine Z of G43 H2 Z0, next to that of H0.)
    let r = run_with(&src.replace("#11002", "#2002"), "mill3", Haas);
    assert!(r.completed(), "Haas {:?}", r.alarms);
    assert_eq!(r.variables.iter().find(|(k, _)| *k == 100).map(|(_, v)| *v), Some(7.0), "Haas");
    let z = |h: u32| {
        let r = run_with(&format!("G21 G90\nG10 L10 P2. R7.\nG43 H{h} Z0\nM30\n"), "mill3", Syntec);
        assert!(r.completed(), "Syntec {:?}", r.alarms);
        r.machine[2]
    };
    assert!((z(2) - z(0) - 7.0).abs() < 1e-9, "Syntec: H2 is 7 mm ({} vs {})", z(2), z(0));
}

/// Audit F6: in FANUC a decimal point at H, D, T or the P of G54.1/G54 is PS0007 ILLEGAL USE OF
/// DECIMAL POINT at its block (`H1.` ran as H1); a variable there is rounded as before, and a
/// macro call's argument keeps its point. Syntec and Haas read the whole value.
#[test]
fn fanuc_refuses_a_decimal_point_at_h_d_t_and_the_work_system_p() {
    for block in ["G43 H1. Z0", "G41 D1. X10. F100.", "D2.", "T1. M06", "T1.5 M06", "G54.1 P1. X0", "G54 P2. X0"] {
        let src = format!("G21 G90 G00 Z50.\n{block}\nG40 G49\nM30\n");
        assert_eq!(first(&src, Fanuc), Some(("PS0007".to_string(), 2)), "{block}");
    }
    // Syntec and Haas: `H1.` is H1 (length 100 from the tools of the test helper: Z 0 + 100).
    for dialect in [Syntec, Haas] {
        let r = run_with("G21 G90 G00 Z50.\nG43 H1. Z0\nM30\n", "mill3", dialect);
        assert!(r.completed(), "{dialect:?} {:?}", r.alarms);
        assert!(approx(r.machine[2], 100.0), "{dialect:?} {}", r.machine[2]);
    }
    // A variable at H is rounded (#1 = 1.: H1), a macro call's H keeps its point (#11 = 1.5).
    let r = run_src("#1=1.\nG21 G90 G00 Z50.\nG43 H#1 Z0\nG65 P9001 H1.5\nM30\nO9001\n#100=#11\nM99\n");
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(approx(r.machine[2], 100.0), "{}", r.machine[2]);
    assert_eq!(r.variables.iter().find(|(k, _)| *k == 100).map(|(_, v)| *v), Some(1.5));
}

/// Audit F2: a tool offset value beyond the valid input range (IS-B: geometry ±999.999 mm /
/// ±99.9999 in, wear ±99.999 mm / ±9.9999 in), set by G10 (under G91 the sum) or by a system
/// variable, is FANUC's PS0032 ILLEGAL OFFSET VALUE IN G10 at its block and the offset keeps its
/// value; fivex stored 999999 mm. Syntec COR-047, Haas 331.
#[test]
fn a_tool_offset_value_out_of_range_is_ps0032() {
    let bad = [
        ("G10 L10 P1 R999999.", 1),
        ("G10 L10 P1 R1000.", 1),
        ("G10 L12 P1 R-1000.", 1),
        ("G10 L11 P1 R100.", 1),
        ("G10 L1 P1 R-100.", 1),
        ("G10 L13 P1 R100.", 1),
        ("G91 G10 L10 P1 R900.", 1),
        ("G20\nG10 L10 P1 R100.", 1),
        ("G20\nG10 L11 P1 R10.", 1),
        ("#11001=1000.", 1),
        ("#10002=5000.", 2),
        ("#2001=100.", 1),
        ("#13001=-1000.", 1),
        ("#12001=100.", 1),
        ("G20\n#11001=100.", 1),
    ];
    for (block, number) in bad {
        let src = format!("G21 G90\n{block}\nM30\n");
        let line = 2 + block.matches('\n').count() as u32;
        let mut interp = interpreter(&src, "mill3", Fanuc);
        let r = fivex_engine::run::run(&mut interp, &RunOptions { period_s: 0.0, ..Default::default() }, |_| {});
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("PS0032", line)), "{block}");
        // The helper's tools: length 100, radius 5, no wear; the refused value is not stored.
        let t = interp.state.offsets.tool(number).unwrap();
        assert_eq!((t.h_geometry, t.h_wear, t.d_geometry, t.d_wear), (100.0, 0.0, 5.0, 0.0), "{block}");
    }
    // The limits themselves are values, in mm and in inch (stored in mm: 99.9999 in = 2539.99746).
    let src = "G21 G90\nG10 L10 P1 R999.999\nG10 L11 P1 R-99.999\nG10 L12 P2 R-999.999\n#12002=99.999\n\
               G91 G10 L10 P3 R899.999\nG90\nG20\nG10 L10 P4 R99.9999\n#10004=-9.9999\nG21\nM30\n";
    let mut interp = interpreter(src, "mill3", Fanuc);
    let r = fivex_engine::run::run(&mut interp, &RunOptions { period_s: 0.0, ..Default::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let o = &interp.state.offsets;
    let t = |n| *o.tool(n).unwrap();
    assert_eq!((t(1).h_geometry, t(1).h_wear), (999.999, -99.999));
    assert_eq!((t(2).d_geometry, t(2).d_wear), (-999.999, 99.999));
    assert!(approx(t(3).h_geometry, 999.999), "{}", t(3).h_geometry);
    assert!(approx(t(4).h_geometry, 2539.99746) && approx(t(4).h_wear, -253.99746), "{:?}", t(4));
    // Syntec and Haas (Haas #2001 is the length geometry).
    assert_eq!(first("G10 L10 P1 R1000.\nM30\n", Syntec), Some(("COR-047".into(), 1)));
    assert_eq!(first("G10 L10 P1 R1000.\nM30\n", Haas), Some(("331".into(), 1)));
    assert_eq!(first("#2001=1000.\nM30\n", Haas), Some(("331".into(), 1)));
    assert_eq!(first("#2001=999.\nM30\n", Haas), None);
}

/// Work offsets have the range of nine digits of IS-B, ±999999.999 mm / ±99999.9999 inch
/// (a written number cannot pass it, PS0003; a variable, a G91 sum or a system variable could):
/// beyond it is PS0032 at the block and the offset keeps its value. A macro's bad reading set a
/// workpiece zero a kilometre away, which a machine without stroke limits ran to. A rotary axis
/// counts degrees, under G20 too.
#[test]
fn a_work_offset_value_out_of_range_is_ps0032() {
    let bad = [
        "#1=1000000.\nG10 L2 P1 X#1",
        "G10 L2 P1 X900000.\nG91 G10 L2 P1 X100000.",
        "#1=-1000000.\nG10 L20 P5 Y#1",
        "#5221=1000000.",
        "#1=1000000.\n#7001=#1",
        "G20\n#1=100000.\nG10 L2 P1 X#1",
        "G20\n#5222=100000.",
    ];
    for block in bad {
        let src = format!("G21 G90\n{block}\nM30\n");
        let line = 2 + block.matches('\n').count() as u32;
        let mut interp = interpreter(&src, "mill3", Fanuc);
        let r = fivex_engine::run::run(&mut interp, &RunOptions { period_s: 0.0, ..Default::default() }, |_| {});
        assert_eq!(r.alarms.first().map(|a| (a.code.as_str(), a.line)), Some(("PS0032", line)), "{block}");
        let o = &interp.state.offsets;
        assert!(o.work(1)[..3].iter().chain(&o.work(7)[..3]).all(|&v| v == 0.0 || v == 900000.0), "{block}");
    }
    // The limits themselves are values (stored in mm: 99999.9999 in = 2539999.99746 mm), and a
    // rotary axis's offset counts degrees under G20.
    let src = "G21 G90\n#1=999999.999\nG10 L2 P1 X#1\n#5222=-999999.999\nG20\n#1=99999.9999\n\
               G10 L2 P2 X#1\n#1=500000.\nG10 L2 P3 C#1\nG21\nM30\n";
    let mut interp = interpreter(src, "head-bc", Fanuc);
    let r = fivex_engine::run::run(&mut interp, &RunOptions { period_s: 0.0, ..Default::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    let o = &interp.state.offsets;
    assert_eq!((o.work(1)[0], o.work(1)[1]), (999999.999, -999999.999));
    assert!(approx(o.work(2)[0], 2539999.99746), "{}", o.work(2)[0]);
    assert_eq!(o.work(3)[4], 500000.0);
}

/// A work offset written through its macro variable (#5201…, #5221…, #7001…, #14001…) shifts
/// the coordinate system at once without moving an axis, exactly as G10 L2/L20 of the same
/// offset does: an axis the next block does not command stays where it is in machine
/// coordinates, and its absolute position reads the shift (audit of offsets: after
/// `#5223=5.` the next `G01 Y10.` ramped machine Z from 0 to 5, and under G91 `X1.` after
/// `#5221=5.` went to X6 with #5001 reading 0).
#[test]
fn a_work_offset_variable_shifts_the_system_as_g10_does() {
    // (dialect, work system selected, the variable write, the G10 of the same offset)
    let cases = [
        (Fanuc, "G54", "#5223=5.", "G10 L2 P1 Z5."),
        (Fanuc, "G54", "#5221=5.", "G10 L2 P1 X5."),
        (Fanuc, "G54", "#5203=5.", "G10 L2 P0 Z5."),
        (Fanuc, "G54", "#5201=5.", "G10 L2 P0 X5."),
        (Fanuc, "G54.1 P1", "#7003=5.", "G10 L20 P1 Z5."),
        (Fanuc, "G54.1 P1", "#14001=5.", "G10 L20 P1 X5."),
        (Haas, "G54", "#5223=5.", "G10 L2 P1 Z5."),
        (Haas, "G54", "#5221=5.", "G10 L2 P1 X5."),
        (Haas, "G154 P1", "#7003=5.", "G10 L20 P1 Z5."),
        (Haas, "G154 P1", "#14001=5.", "G10 L20 P1 X5."),
        // G20: the variable and G10 both take inch.
        (Fanuc, "G54", "G20\n#5223=0.2\nG21", "G20\nG10 L2 P1 Z0.2\nG21"),
    ];
    for (dialect, select, write, g10) in cases {
        let program = |set: &str| {
            format!(
                "G21 G90 G17 G40 G49 G80\n{select} G00 X0 Y0 Z0\n{set}\n#100=#5001\n#101=#5003\n#102=#5021\n\
                 #103=#5023\nG01 Y10. F1000\nG91 G01 X1.\nG90\n#104=#5001\n#105=#5003\nM30\n"
            )
        };
        let by_variable = run_with(&program(write), "mill3", dialect);
        let by_g10 = run_with(&program(g10), "mill3", dialect);
        assert!(by_variable.completed() && by_g10.completed(), "{write}: {:?} {:?}", by_variable.alarms, by_g10.alarms);
        let what = format!("{dialect:?} {select} {write}");
        assert_eq!(by_variable.machine, by_g10.machine, "{what}: machine");
        assert_eq!(by_variable.workpiece, by_g10.workpiece, "{what}: workpiece");
        assert_eq!(by_variable.tip, by_g10.tip, "{what}: tip");
        assert_eq!(by_variable.programmed, by_g10.programmed, "{what}: programmed");
        assert_eq!(by_variable.variables, by_g10.variables, "{what}: variables");
        // And what the G10 does: no axis moved for the shift, the uncommanded one stays put.
        let m = by_variable.machine;
        let z_shifted = write.contains("#5223") || write.contains("#5203") || write.contains("#7003");
        if z_shifted {
            assert_eq!((m[0], m[1]), (1.0, 10.0), "{what}");
            assert!(m[2].abs() < 1e-9, "{what}: machine Z {}", m[2]);
            let shift = if write.contains("G20") { 5.08 } else { 5.0 };
            assert!((by_variable.workpiece[2] + shift).abs() < 1e-9, "{what}: {:?}", by_variable.workpiece);
            // The summary's workpiece is the tip's (tool length 0 under G49).
            assert!((by_variable.tip.tip[2] - by_variable.workpiece[2]).abs() < 1e-9, "{what}");
        } else {
            assert_eq!((m[0], m[1], m[2]), (1.0, 10.0, 0.0), "{what}");
            let v = |n: u32| by_variable.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v);
            assert_eq!((v(100), v(104)), (Some(-5.0), Some(-4.0)), "{what}");
            assert!((by_variable.tip.tip[0] - by_variable.workpiece[0]).abs() < 1e-9, "{what}");
        }
    }
}

/// The Haas dialect has no external work offset (its G10 L2 P0 and #5201… are G52): a value in
/// the external offset's storage (set before through the service, or kept from another
/// dialect's machine) does not shift a Haas program's work systems, which could neither read
/// nor cancel it. FANUC applies it.
#[test]
fn the_external_offset_storage_does_not_shift_a_haas_program() {
    for (dialect, want) in [(Fanuc, 7.5), (Haas, 5.0)] {
        let src = "G21 G90 G54 G00 X5. Y0 Z0\n#100=#5001\nM30\n";
        let mut interp = interpreter(src, "mill3", dialect);
        interp.state.offsets.work_mut(0)[0] = 2.5;
        let r = fivex_engine::run::run(&mut interp, &RunOptions { period_s: 0.0, ..Default::default() }, |_| {});
        assert!(r.completed(), "{:?}", r.alarms);
        assert_eq!(r.machine[0], want, "{dialect:?}");
        assert_eq!(r.workpiece[0], 5.0, "{dialect:?}");
    }
}
