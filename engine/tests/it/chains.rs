//! Syntec's multi-kinematic chain `G10 L5000 P_ [Q_]` (SYN-26, spec syntec.md TV-22…TV-23c) on
//! the library's exchangeable-head machine `head-exchange-bc-ac` (set 1 a B/C fork head, set 2
//! an A/C head 50 mm longer): the alarms, and a switch after which TCP, the tilted plane and the
//! trace's tip go through the second chain (`docs/five-axis.md`, "Multiple mechanism chains").

use crate::common;

use fivex_engine::canon::CanonKind;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::{Chain, MachineConfig, RotaryLink, Side, SubChain};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect::{self, Fanuc, Syntec};
use proptest::prelude::*;

const SET_2: Chain = Chain { set: 2, sub: 1 };

fn exchange_head() -> MachineConfig {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../machines/head-exchange-bc-ac.json");
    fivex_engine::machine_file::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The machine with set 1's sub-chain 2: a right-angle attachment, the tool along +X at zero
/// angles, its nose 120 mm from the carriage reference point toward −X and 80 mm below it.
fn with_attachment() -> MachineConfig {
    let mut m = exchange_head();
    m.sub_chains = vec![SubChain { q: 2, tool_axis: [1.0, 0.0, 0.0], nose: [-120.0, 0.0, -80.0], holder: 0.0 }];
    m
}

/// Tool offsets 1–99 of length 100, as `common::interpreter_with` sets them.
fn interpreter(src: &str, m: MachineConfig, dialect: Dialect) -> Interpreter {
    let mut cfg = Config::new(m, dialect);
    cfg.max_blocks = 100_000;
    let mut interp = Interpreter::new(parse_file(src), cfg);
    for n in 1..=99 {
        interp.state.offsets.tool_mut(n).unwrap().h_geometry = 100.0;
    }
    interp
}

fn trace(src: &str, m: MachineConfig) -> (Vec<Sample>, RunResult) {
    let mut interp = interpreter(src, m, Syntec);
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    (samples, r)
}

fn first_alarm(src: &str, m: MachineConfig, dialect: Dialect) -> Option<(String, u32)> {
    let mut interp = interpreter(src, m, dialect);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    r.alarms.first().map(|a| (a.code.clone(), a.line))
}

fn alarm(src: &str, m: MachineConfig) -> Option<(String, u32)> {
    first_alarm(src, m, Syntec)
}

fn at(code: &str, line: u32) -> Option<(String, u32)> {
    Some((code.to_string(), line))
}

fn chain_kin(m: &MachineConfig, chain: Chain) -> Kinematics {
    Kinematics::new(&m.chain_view(chain).unwrap()).unwrap()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    Vec3::from(a).metric_distance(&Vec3::from(b))
}

#[test]
fn tv_22_q_outside_the_integers_0_to_4_is_cor_163() {
    for q in ["Q5", "Q1.5", "Q-1"] {
        assert_eq!(alarm(&format!("G10 L5000 P1 {q}\n"), exchange_head()), at("COR-163", 1), "{q}");
    }
    // Q0…Q1 are the set as described: accepted on a spindle-type set.
    assert_eq!(alarm("G10 L5000 P1 Q0\nG10 L5000 P2 Q1\nG10 L5000 P1\n", exchange_head()), None);
}

#[test]
fn tv_22b_q_on_a_set_that_is_not_spindle_type_is_cor_164() {
    // Set 2 a table A/C trunnion (Pr3101 = 2): P2 alone switches, any Q (Q0 too) is COR-164.
    let mut m = exchange_head();
    let table = |axis, direction, z| RotaryLink {
        axis,
        side: Side::Table,
        direction,
        hand: fivex_engine::machine::Hand::Left,
        point: [0.0, 0.0, z],
        zero_offset: 0.0,
        fixed: None,
        range: None,
    };
    m.chains[0].rotary = vec![table('A', [1.0, 0.0, 0.0], -120.0), table('C', [0.0, 0.0, 1.0], 0.0)];
    (m.chains[0].nose, m.chains[0].holder) = ([0.0; 3], 0.0);
    assert_eq!(alarm("G10 L5000 P2 Q1\n", m.clone()), at("COR-164", 1));
    assert_eq!(alarm("G10 L5000 P2 Q0\n", m.clone()), at("COR-164", 1));
    assert_eq!(alarm("G10 L5000 P2\nG10 L5000 P1 Q1\n", m), None);
}

#[test]
fn tv_22c_with_sub_chain_2_only_rtcp_and_the_listed_plane_commands_run() {
    // COR-165: under Q2 the alignment G53.3 is not in the list (§6.2's: G68.2 + G53.1/G53.6).
    let src = "G10 L5000 P1 Q2\nG68.2 X0. Y0. Z0. I0. J30. K0.\nG53.3\n";
    assert_eq!(alarm(src, with_attachment()), at("COR-165", 3));
    // The same block under Q1 (the set itself) is not refused by the chain rule.
    let q1 = "G10 L5000 P1 Q1\nG68.2 X0. Y0. Z0. I0. J30. K0.\nG53.3\n";
    assert_ne!(alarm(q1, with_attachment()).map(|a| a.0), Some("COR-165".to_string()));
    // What Q2 supports runs: G43.4, G68.2 + G53.1, G68.3 is checked like any other.
    let allowed = "G90 G00 X0. Y0. Z200. A0. B0. C0.\nG10 L5000 P1 Q2\nG43.4 H1\nG01 X10. F1000.\nG49\n\
                   G68.2 X0. Y0. Z0. I0. J30. K0.\nG53.1\nG69\nG10 L5000 P1\nM30\n";
    assert_eq!(alarm(allowed, with_attachment()), None);
}

#[test]
fn tv_23_switching_under_rtcp_is_cor_160() {
    assert_eq!(alarm("G43.4 H1\nG10 L5000 P2\n", exchange_head()), at("COR-160", 2));
    // After G49 it switches.
    assert_eq!(alarm("G43.4 H1\nG49\nG10 L5000 P2\n", exchange_head()), None);
}

/// The switch block holds G10's own words only (`docs/five-axis.md`, "Multiple mechanism
/// chains"): `G10 L5000 P2 G43.4 H1` had started RTCP on set 1 without its H while the executor
/// followed set 2 (a 58 mm axis step in 1 ms), and the move of `G10 L5000 P2 G01 X10.` was
/// dropped. A 5-axis function turned on in the switch block is COR-160 (its solution: "make
/// sure 5-axis function is disabled for the alarmed block"), any other G code COR-070, an
/// address L5000 does not take COR-002, an address given twice the G10 format alarm COR-014.
#[test]
fn the_chain_switch_block_holds_nothing_but_the_switch() {
    let head = "G90 G00 X0. Y0. Z50. A0. B0. C0.\n";
    for (block, code) in [
        ("G10 L5000 P2 G43.4 H1", "COR-160"),
        ("G10 L5000 P1 G43.4 H1", "COR-160"),
        ("G10 L5000 P2 G43.5 H1 I0 J0 K1.", "COR-160"),
        ("G10 L5000 P2 G68.2 X0 Y0 Z0 I0 J0 K0", "COR-160"),
        ("G10 L5000 P2 G53.1", "COR-160"),
        ("G10 L5000 P2 G01 X10. F100.", "COR-070"),
        ("G10 L5000 P2 G43 H1", "COR-070"),
        ("G10 L5000 P2 X10.", "COR-002"),
        ("G10 L5000 P2 H1", "COR-002"),
        ("G10 L5000 P2 M03", "COR-002"),
        ("G10 L5000 P2 P3", "COR-014"),
        ("G10 L5000.5 P2", "COR-014"),
    ] {
        let src = format!("{head}{block}\nG01 X20. B10. F500.\nM30\n");
        assert_eq!(alarm(&src, exchange_head()), at(code, 2), "{block}");
    }
    // What the block may hold besides G10's words: N and G90/G91.
    let ok = format!("{head}N2 G90 G10 L5000 P2\nG91 G10 L5000 P1 Q1\nM30\n");
    assert_eq!(alarm(&ok, exchange_head()), None);
    // `fivex check` finds them without running.
    let diags = fivex_engine::check::check(parse_file("G10 L5000 P2 G43.4 H1\nG10 L5000 P2 G01 X10.\n"), Syntec);
    let found: Vec<_> = diags.iter().map(|d| (d.line, d.col, Syntec.describe(&d.id).0)).collect();
    assert_eq!(found, vec![(1, 14, "COR-160".to_string()), (2, 14, "COR-070".to_string())]);
}

#[test]
fn tv_23b_a_set_or_sub_chain_that_is_not_configured_is_cor_161() {
    // Set 3 absent (Pr5501 = 0); sets outside 1–4; set 2 on a one-chain machine; set 1 on a
    // 3-axis machine (Pr3001 = 0); sub-chain 3 not described.
    for (src, m) in [
        ("G10 L5000 P3\n", exchange_head()),
        ("G10 L5000 P0\n", exchange_head()),
        ("G10 L5000 P5\n", exchange_head()),
        ("G10 L5000 P2\n", MachineConfig::preset("head-bc").unwrap()),
        ("G10 L5000 P1\n", MachineConfig::preset("mill3").unwrap()),
        ("G10 L5000 P1 Q3\n", with_attachment()),
        ("G10 L5000 P2 Q2\n", with_attachment()),
    ] {
        assert_eq!(alarm(src, m.clone()), at("COR-161", 1), "{src} on {}", m.name);
    }
    // P is required, as in every G10 (the G10 format alarm); P1.5 is not a set number.
    assert_eq!(alarm("G10 L5000\n", exchange_head()).map(|a| a.1), Some(1));
    assert_eq!(alarm("G10 L5000 P1.5\n", exchange_head()).map(|a| a.1), Some(1));
}

#[test]
fn tv_23c_the_options_are_not_modelled_so_no_type_raises_cor_162() {
    // COR-162 (option-29 on, option-12 off, a set of type 1–3): fivex models no software
    // options — RTCP (option-12) is always there — so a table-type set (Pr3001 = 2) switches.
    assert_eq!(alarm("G10 L5000 P1\nG43.4 H1\nG49\n", MachineConfig::preset("table-ac").unwrap()), None);
}

#[test]
fn fanuc_has_no_g10_l5000() {
    assert_eq!(first_alarm("G10 L5000 P2\n", exchange_head(), Fanuc), at("PS1144", 1));
}

/// P1 → P2, then a TCP line: the sampled axes put the tip (forward kinematics through set 2,
/// computed here) on the programmed line within 1 µm at every sample; before the switch the
/// tip is set 1's. The trace's `tip` is that FK, not set 1's, which differs by metres here.
#[test]
fn after_p2_tcp_keeps_the_tip_on_the_line_through_the_second_chain() {
    let src = "G90 G54 G00 X0. Y0. Z100. A0. B0. C0.\nG43 H1 G01 B20. F3000.\nG49 Z100.\nG10 L5000 P2\n\
               G43.4 H1\nG01 X20. Y-10. Z50. A30. C60. F1500.\nG01 X-20. Y10. Z40. A-20. C-30.\nG49\nM30\n";
    let m = exchange_head();
    let (samples, r) = trace(src, m.clone());
    assert!(r.completed(), "{:?}", r.alarms);
    let (set1, set2) = (chain_kin(&m, Chain::MAIN), chain_kin(&m, SET_2));
    // Programmed TCP lines in the table frame (no table axes: machine coordinates) — the
    // G43.4 block starts at (0, 0, 100) less the tool: tip (0, 0, 100 + 0 − 50 − 100)… read
    // instead from the first sample of line 6, which is where line 5 left the tip.
    let start = samples.iter().find(|s| s.line == 6).expect("line 6").tip;
    let lines = [(6, start, [20.0, -10.0, 50.0]), (7, [20.0, -10.0, 50.0], [-20.0, 10.0, 40.0])];
    let mut checked = 0;
    for s in &samples {
        let kin = if s.line >= 5 { &set2 } else { &set1 };
        let length = if matches!(s.line, 2 | 5..=7) { 100.0 } else { 0.0 };
        let tip = kin.forward(&s.machine, length).tip;
        // No work offset; the nose is in the origin (set 2: −50 mm in Z).
        let origin = kin.nose;
        let expected = [tip.x - origin.x, tip.y - origin.y, tip.z - origin.z];
        assert!(dist(s.tip, expected) < 1e-9, "line {} t {}: tip {:?} ≠ FK {expected:?}", s.line, s.t, s.tip);
        if let Some((_, a, b)) = lines.iter().find(|(l, ..)| *l == s.line) {
            let (a, b, p) = (Vec3::from(*a), Vec3::from(*b), Vec3::from(expected));
            let u = (b - a).normalize();
            let off = (p - a) - u * (p - a).dot(&u);
            assert!(off.norm() < 1e-3, "line {} t {}: {} µm off the line", s.line, s.t, off.norm() * 1e3);
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} samples on the TCP lines");
    // Set 1's FK of an A-tilted pose is elsewhere: the check above could fail.
    let last = samples.iter().rev().find(|s| s.line == 7).unwrap();
    assert!(dist(set1.forward(&last.machine, 100.0).tip.into(), set2.forward(&last.machine, 100.0).tip.into()) > 10.0);
}

/// By hand, set 2 at X0 Y0 Z0 A90 C0, tool 100: the pivot is 150 mm above the carriage point,
/// the nose 50 mm below it; A turns +90° about +X, which takes (0, 0, −300) from the pivot to
/// (0, 300, 0): tip (0, 300, 150), tool (0, −1, 0). Set 1 at B90: tip (−250, 0, 150).
#[test]
fn the_second_chain_by_hand() {
    let m = exchange_head();
    let pos = |a: f64, b: f64| [0.0, 0.0, 0.0, a, b, 0.0, 0.0, 0.0];
    let p2 = chain_kin(&m, SET_2).forward(&pos(90.0, 0.0), 100.0);
    assert!(dist(p2.tip.into(), [0.0, 300.0, 150.0]) < 1e-9, "{:?}", p2.tip);
    assert!(dist(p2.tool.into(), [0.0, -1.0, 0.0]) < 1e-12);
    let p1 = chain_kin(&m, Chain::MAIN).forward(&pos(0.0, 90.0), 100.0);
    assert!(dist(p1.tip.into(), [-250.0, 0.0, 150.0]) < 1e-9, "{:?}", p1.tip);
}

/// G68.2 tilting the plane 30° about X, then G53.1: in set 2 the A/C head turns A (B stays 0)
/// and the tool, by set 2's FK, is the plane's Z: (0, −sin 30°, cos 30°) = (0, −0.5, 0.866).
#[test]
fn the_tool_alignment_turns_the_second_chain() {
    let src = "G90 G00 X0. Y0. Z200. A0. B0. C0.\nG10 L5000 P2\nG68.2 X0. Y0. Z0. I0. J30. K0.\nG53.1\nM30\n";
    let m = exchange_head();
    let mut interp = interpreter(src, m.clone(), Syntec);
    let mut ends = Vec::new();
    interp.run(|c| ends.extend(matches!(c.kind, CanonKind::Motion(_)).then_some(c))).unwrap();
    let CanonKind::Motion(last) = &ends.last().unwrap().kind else { unreachable!() };
    assert_eq!(last.machine[4], 0.0, "B stays");
    assert!(last.machine[3].abs() > 29.0, "A turns: {:?}", last.machine);
    let tool = chain_kin(&m, SET_2).forward(&last.machine, 0.0).tool;
    let want = [0.0, -0.5, 3f64.sqrt() / 2.0];
    assert!(dist(tool.into(), want) < 1e-9, "{tool:?}");
}

/// With sub-chain 2 (the attachment, tool along +X) TCP's tip is the attachment's.
#[test]
fn a_sub_chain_is_the_set_with_its_attachment() {
    let src =
        "G90 G00 X0. Y0. Z200. A0. B0. C0.\nG10 L5000 P1 Q2\nG43.4 H1\nG01 X10. Y5. Z-20. B10. C15. F1000.\nG49\nM30\n";
    let m = with_attachment();
    let (samples, r) = trace(src, m.clone());
    assert!(r.completed(), "{:?}", r.alarms);
    let kin = chain_kin(&m, Chain { set: 1, sub: 2 });
    assert_eq!(kin.tool_axis, Vec3::x());
    let last = samples.iter().rev().find(|s| s.line == 4).unwrap();
    let tip = kin.forward(&last.machine, 100.0).tip - kin.nose;
    assert!(dist(tip.into(), last.tip) < 1e-9 && dist(last.tip, [10.0, 5.0, -20.0]) < 1e-3, "{:?}", last.tip);
}

/// The chain stays through M30 and a reset (the head on the machine does not change); a new
/// interpreter — power-on — starts in set 1 (spec §1.1: path 1 uses set 1 by default).
#[test]
fn the_chain_survives_m30_and_reset_not_power_on() {
    let mut interp = interpreter("G10 L5000 P2\nM30\n", exchange_head(), Syntec);
    interp.run(|_| {}).unwrap();
    assert_eq!(interp.config().machine.chain(), SET_2);
    interp.reset();
    assert_eq!(interp.config().machine.chain(), SET_2);
    assert_eq!(interp.state.tip_basis().chain, SET_2);
    interp.load(parse_file("G10 L5000 P1\n"));
    interp.run(|_| {}).unwrap();
    assert_eq!(interp.config().machine.chain(), Chain::MAIN);
    assert_eq!(interpreter("", exchange_head(), Syntec).config().machine.chain(), Chain::MAIN);
}

fn block() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..6u8, prop::option::of(-1..6i8)).prop_map(|(p, q)| match q {
            Some(q) => format!("G10 L5000 P{p} Q{q}"),
            None => format!("G10 L5000 P{p}"),
        }),
        (-50..50i32, -40..40i32, -40..40i32).prop_map(|(x, a, b)| format!("G01 X{x}. A{a}. B{b}. F2000.")),
        Just("G43.4 H1".to_string()),
        Just("G49".to_string()),
        Just("G68.2 X0. Y0. Z0. I0. J20. K0.".to_string()),
        Just("G53.1".to_string()),
        Just("G69".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(48)))]

    /// Random switches among moves and 5-axis modes never panic; no alarm is fivex's own guard
    /// (FX…: the chain's, the modes', the kinematics' and the strokes' are expected), and a run
    /// that completes ends in a chain the machine has.
    #[test]
    fn random_chain_switches_never_panic(blocks in prop::collection::vec(block(), 1..12)) {
        let src = format!("G90 G00 X0. Y0. Z150. A0. B0. C0.\n{}\nM30\n", blocks.join("\n"));
        let m = with_attachment();
        let mut interp = interpreter(&src, m.clone(), Syntec);
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        match r.alarms.first() {
            Some(a) => prop_assert!(!a.code.starts_with("FX"), "{} in\n{src}", a.code),
            None => prop_assert!(m.chain_list().contains(&interp.config().machine.chain())),
        }
    }
}

/// The controller follows the program's chain in program order: before the `G10 L5000 P2`
/// block is reached, its manual feeds and tip use set 1; after it, set 2 — the status's chain,
/// the mechanism of the 5-axis manual feeds and the tip it shows (set 2's nose: the carriage
/// point at 0, 0, 200 with no tool puts the tip 50 lower, at machine Z 150 — in the workpiece
/// system, whose origin is the nose, it stays 200).
#[test]
fn the_controller_takes_the_chain_in_program_order() {
    use fivex_engine::controller::{Controller, RunState};
    let mut c = Controller::new(Config::new(exchange_head(), Syntec));
    assert_eq!((c.chain(), c.kinematics().unwrap().head[1].name), (Chain::MAIN, 'B'));
    // A manual feed setting changed on the panel survives the switch.
    c.manual_options_mut().tool_length = 42.0;
    c.select_program("G90 G00 X0. Y0. Z200.\nG10 L5000 P2\nM30\n").unwrap();
    c.cycle_start().unwrap();
    while c.run_state() == RunState::Running && c.time() < 10.0 {
        c.tick(0.001);
        if c.point().line == 1 {
            assert_eq!(c.chain(), Chain::MAIN, "not before its block");
        }
    }
    assert_eq!((c.chain(), c.kinematics().unwrap().head[1].name), (SET_2, 'A'));
    assert_eq!(c.manual_options().tool_length, 42.0);
    assert!(dist(c.tip().table, [0.0, 0.0, 150.0]) < 1e-9, "{:?}", c.tip());
    assert!(dist(c.tip().tip, [0.0, 0.0, 200.0]) < 1e-9, "{:?}", c.tip());
    c.reset();
    assert_eq!(c.chain(), SET_2, "a reset keeps the chain");
}

/// The run report measures the singular posture of each block's chain: set 1's C master is
/// along the tool at zero angles (singular the whole time), set 2 here an A master about X with
/// set 1's B as its slave, 90° from the tool. A move in set 2 with the tool along Z spends no
/// time near the singular posture; the same move in set 1 spends all of it there.
#[test]
fn the_report_reads_the_singular_posture_of_the_chain_in_use() {
    let mut m = exchange_head();
    let b = m.rotary[1];
    m.chains[0].rotary = vec![m.chains[0].rotary[1], b]; // A master, B slave
    let report = |src: &str| {
        let mut interp = interpreter(src, m.clone(), Syntec);
        let opts = RunOptions { period_s: 0.01, ..RunOptions::default() };
        let (r, report) = fivex_engine::report::run_with_report(&mut interp, &opts);
        assert!(r.completed(), "{:?}", r.alarms);
        (r.cycle_time_s, report)
    };
    let (time, set1) = report("G90 G01 X100. F3000.\nM30\n");
    assert!(time > 1.9 && set1.near_singular_s > time - 0.05, "{time} {}", set1.near_singular_s);
    let (time, set2) = report("G10 L5000 P2\nG90 G01 X100. F3000.\nM30\n");
    assert!(time > 1.9 && set2.near_singular_s < 0.05, "{time} {}", set2.near_singular_s);
}
