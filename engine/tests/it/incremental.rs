//! Streaming a file into the interpreter part by part (`Interpreter::new_incremental`) gives the
//! same canonical commands, alarm and final state as interpreting the whole file at once, for
//! every fixture program cut into parts of any size.

use crate::common;

use fivex_engine::canon::Canon;
use fivex_engine::interp::{Config, Interpreter, Step};
use fivex_engine::lang::{parse_file, parse_part};
use fivex_engine::machine::MachineConfig;
use fivex_engine::{Alarm, Dialect};

type Outcome = (Vec<Canon>, Option<Alarm>, u64, Vec<(u32, f64)>);

fn config(preset: &str, dialect: Dialect) -> Config {
    let mut cfg = Config::new(MachineConfig::preset(preset).unwrap(), dialect);
    cfg.max_blocks = 100_000;
    cfg
}

fn drive(interp: &mut Interpreter, mut next_part: impl FnMut(&mut Interpreter) -> bool) -> Outcome {
    let mut out = Vec::new();
    let alarm = loop {
        match interp.step(&mut out) {
            Ok(Step::Continue) => {}
            Ok(Step::Ended) => break None,
            Ok(Step::NeedInput) => {
                if !next_part(interp) {
                    interp.finish();
                }
            }
            Err(a) => break Some(a),
        }
    };
    (out, alarm, interp.blocks(), interp.state.common_variables())
}

fn whole(text: &str, preset: &str, dialect: Dialect) -> Outcome {
    let mut interp = Interpreter::new(parse_file(text), config(preset, dialect));
    drive(&mut interp, |_| false)
}

/// The file cut after every `lines` lines, parts pushed only when the interpreter asks.
fn streamed(text: &str, lines: usize, preset: &str, dialect: Dialect) -> Outcome {
    let all: Vec<&str> = text.split_inclusive('\n').collect();
    let mut parts = all.chunks(lines.max(1)).enumerate().map(|(k, chunk)| {
        let first_line = (k * lines.max(1)) as u32 + 1;
        parse_part(&chunk.concat(), first_line, k > 0)
    });
    let mut interp = Interpreter::new_incremental(config(preset, dialect));
    drive(&mut interp, |i| match parts.next() {
        Some(part) => {
            i.push_part(part);
            true
        }
        None => false,
    })
}

fn check(name: &str, text: &str) {
    for (preset, dialect) in [("mill3", Dialect::Fanuc), ("head-bc", Dialect::Syntec)] {
        let expected = whole(text, preset, dialect);
        for lines in [1, 2, 3, 5, 8, 13, 1000] {
            let got = streamed(text, lines, preset, dialect);
            assert!(got == expected, "{name}: parts of {lines} lines on {preset}/{dialect:?} differ");
        }
    }
}

#[test]
fn every_fixture_streams_like_a_whole_file() {
    for (path, text) in common::fixture_programs() {
        check(&path, &text);
    }
}

#[test]
fn forward_jumps_loops_and_calls_across_parts() {
    let text = "(HEADER)\n%\nO0001\n#1=0\nGOTO 10\n#100=99\nN10 WHILE [#1 LT 3] DO 1\nG01 X#1 F100\n#1=#1+1\nEND 1\nM98 P2\n#102=#5001\nM30\nO0002\n#101=7\nM99\n%\n";
    check("forward", text);
    let (_, alarm, _, vars) = streamed(text, 1, "mill3", Dialect::Fanuc);
    assert!(alarm.is_none());
    assert_eq!(vars, vec![(101, 7.0), (102, 2.0)]);
}

#[test]
fn a_do_whose_end_never_comes() {
    check("open do", "#1=0\nWHILE [#1 LT 3] DO 1\n#1=#1+1\nM30\n");
}

#[test]
fn plain_blocks_run_before_the_rest_arrives() {
    let text: String = (0..100).map(|i| format!("G01 X{i}. F100\n")).collect();
    let parts: Vec<_> = text
        .split_inclusive('\n')
        .collect::<Vec<_>>()
        .chunks(10)
        .enumerate()
        .map(|(k, c)| parse_part(&c.concat(), (k * 10) as u32 + 1, k > 0))
        .collect();
    let mut parts = parts.into_iter();
    let mut interp = Interpreter::new_incremental(config("mill3", Dialect::Fanuc));
    let mut out = Vec::new();
    let mut emitted_before_each_push = Vec::new();
    loop {
        match interp.step(&mut out).unwrap() {
            Step::Continue => {}
            Step::Ended => break,
            Step::NeedInput => match parts.next() {
                Some(p) => {
                    emitted_before_each_push.push(out.len());
                    interp.push_part(p);
                }
                None => interp.finish(),
            },
        }
    }
    assert_eq!(out.len(), 100);
    // Part k is asked for only after the 10·(k−1) motions before it ran.
    assert_eq!(emitted_before_each_push, (0..10).map(|k| k * 10).collect::<Vec<_>>());
}
