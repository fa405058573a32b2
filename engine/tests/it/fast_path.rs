//! The interpreter's fast path for plain motion blocks (`interp/plain.rs`) gives the same
//! canonical commands, alarm and final state as the general path, on every fixture program and
//! on random programs that mix plain blocks with everything that changes their meaning.

use crate::common;

use fivex_engine::canon::Canon;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::{Alarm, Dialect};
use proptest::prelude::*;

/// Commands, alarm, executed blocks and the whole final state (as its debug text).
type Outcome = (Vec<Canon>, Option<Alarm>, u64, String);

fn run(text: &str, preset: &str, dialect: Dialect, fast_paths: bool) -> Outcome {
    let mut cfg = Config::new(MachineConfig::preset(preset).unwrap(), dialect);
    cfg.max_blocks = 100_000;
    cfg.fast_paths = fast_paths;
    let mut interp = Interpreter::new(parse_file(text), cfg);
    let mut out = Vec::new();
    let alarm = interp.run(|c| out.push(c)).err();
    // The state holds its configuration: compare it without the switch itself.
    let state = format!("{:?}", interp.state).replace("fast_paths: true", "fast_paths: false");
    (out, alarm, interp.blocks(), state)
}

fn both_paths_agree(name: &str, text: &str) -> Result<(), TestCaseError> {
    for (preset, dialect) in [("mill3", Dialect::Fanuc), ("head-bc", Dialect::Syntec), ("table-ac", Dialect::Fanuc)] {
        let fast = run(text, preset, dialect, true);
        let general = run(text, preset, dialect, false);
        prop_assert!(fast == general, "{}: the fast path differs on {}/{:?}", name, preset, dialect);
    }
    Ok(())
}

#[test]
fn every_fixture_runs_alike_on_both_paths() {
    for (path, text) in common::fixture_programs() {
        both_paths_agree(&path, &text).unwrap();
    }
}

/// A block: mostly plain motion, and the modes, transforms, cycles and calls around it.
fn block() -> impl Strategy<Value = String> {
    let num = prop_oneof![
        (-500i32..500).prop_map(|v| v.to_string()),
        (-5000i32..5000).prop_map(|v| format!("{:.3}", v as f64 / 100.0)),
        Just("#1".to_string()),
        Just("[#1+2]".to_string()),
    ];
    let plain = (
        prop::sample::select(vec!["", "G00 ", "G01 ", "G0", "G1 "]),
        prop::collection::vec((prop::sample::select(vec!['X', 'Y', 'Z', 'A', 'B', 'C']), num.clone()), 0..4),
        prop::option::of(prop::sample::select(vec!["F100", "F0", "F-5", "F2.5", "F#1"])),
    )
        .prop_map(|(g, axes, f)| {
            let words: String = axes.iter().map(|(l, v)| format!("{l}{v} ")).collect();
            format!("{g}{words}{}", f.unwrap_or(""))
        });
    let other = prop::sample::select(vec![
        "G90",
        "G91",
        "G17",
        "G18",
        "G19",
        "G20",
        "G21",
        "G93",
        "G94",
        "G95",
        "G02 X10 Y0 R5 F100",
        "G03 X0 Y10 I-5 J5",
        "G02",
        "G68 X0 Y0 R30",
        "G69",
        "G51 X0 Y0 P2000",
        "G50",
        "G51.1 X0",
        "G50.1 X0",
        "G16",
        "G15",
        "G81 Z-1 R1 F100",
        "X5 Y5",
        "G80",
        "G43 H1",
        "G49",
        "G41 D1",
        "G40",
        "G54",
        "G55",
        "G54.1 P2",
        "G92 X0 Y0",
        "G52 X1",
        "M03 S1000",
        "M05",
        "G28 X0",
        "G53 X0",
        "G04 P100",
        "G66 P9 A1",
        "G67",
        "G65 P9",
        "#1=#1+1",
        "#1=#0",
        "T1 M06",
        "G43.4 H1",
        "G49",
        "G68.2 X0 Y0 Z0 I0 J30 K0",
        "G53.1",
        "G69",
        "G41.2 D1",
        "M98 P9",
        "G10 L2 P1 X1",
    ])
    .prop_map(str::to_string);
    prop_oneof![3 => plain, 2 => other]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_programs_run_alike_on_both_paths(blocks in prop::collection::vec(block(), 0..40)) {
        let text = format!("#1=1\n{}\nM30\nO0009\n#100=#100+1\nM99\n", blocks.join("\n"));
        both_paths_agree(&text, &text)?;
    }
}
