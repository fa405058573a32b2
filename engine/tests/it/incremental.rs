//! Streaming a file into the interpreter part by part (`Interpreter::new_incremental`) gives the
//! same canonical commands, alarm and final state as interpreting the whole file at once, for
//! every fixture program cut into parts of any size.

use crate::common;

use fivex_engine::canon::Canon;
use fivex_engine::interp::{Config, Interpreter, Step};
use fivex_engine::lang::{parse_file, parse_part, Source, Stored};
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
    let text: String = (0..100).map(|i| format!("G01 X{i}. F100\n")).chain(["M30\n".to_string()]).collect();
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
    let motions = out.iter().filter(|c| matches!(c.kind, fivex_engine::canon::CanonKind::Motion(_))).count();
    assert_eq!(motions, 100);
    // Part k is asked for only after the 10·(k−1) motions before it ran (the last part: M30).
    assert_eq!(emitted_before_each_push, (0..11).map(|k| k * 10).collect::<Vec<_>>());
}

/// `text`'s first program as the main text and each further program as a stored one, numbered
/// from its own `O` line on (`lang::Source`, what the service gives a cycle start): loaded when a
/// call reaches it.
fn from_memory(text: &str, preset: &str, dialect: Dialect) -> Outcome {
    let starts: Vec<u32> = parse_file(text).programs.iter().skip(1).map(|p| p.line).collect();
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let piece =
        |from: u32, to: Option<&u32>| lines[from as usize - 1..to.map_or(lines.len(), |&t| t as usize - 1)].concat();
    let main = piece(1, starts.first());
    let library = starts
        .iter()
        .enumerate()
        .map(|(k, &first_line)| {
            let text = piece(first_line, starts.get(k + 1));
            let number = parse_file(&text).programs[0].number.expect("an O line");
            std::sync::Arc::new(Stored { number, first_line, text })
        })
        .collect();
    let mut interp = Interpreter::new(parse_file(""), config(preset, dialect));
    interp.load_source(&Source { main, library });
    drive(&mut interp, |_| false)
}

#[test]
fn every_fixture_runs_from_memory_like_a_whole_file() {
    let mut called = 0;
    for (path, text) in common::fixture_programs() {
        if parse_file(&text).programs.len() < 2 {
            continue;
        }
        called += 1;
        for (preset, dialect) in [("mill3", Dialect::Fanuc), ("head-bc", Dialect::Syntec)] {
            let expected = whole(&text, preset, dialect);
            assert!(from_memory(&text, preset, dialect) == expected, "{path} on {preset}/{dialect:?} differs");
        }
    }
    assert!(called >= 5, "only {called} fixtures call another program");
    let text = "(HEADER)\n%\nO0001\n#1=0\nGOTO 10\n#100=99\nN10 WHILE [#1 LT 3] DO 1\nG01 X#1 F100\nM98 P3\n#1=#1+1\nEND 1\nM98 P2\n#102=#5001\nM30\nO0002\n#101=7\nM99\nO0003\n#103=#103+1\nM99\n%\n";
    let expected = whole(text, "mill3", Dialect::Fanuc);
    assert_eq!(from_memory(text, "mill3", Dialect::Fanuc), expected);
    assert!(expected.1.is_none(), "{:?}", expected.1);
    assert_eq!(expected.3, vec![(101, 7.0), (102, 2.0), (103, 3.0)]);
}
