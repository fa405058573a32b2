//! Helpers shared by the engine's integration tests.
#![allow(dead_code)]

use fivex_engine::canon::{Canon, CanonKind};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult};
use fivex_engine::Dialect;

pub fn interpreter(src: &str, preset: &str, dialect: Dialect) -> Interpreter {
    interpreter_with(src, preset, dialect, |_| {})
}

/// An interpreter whose configuration `tweak` adjusts; tool offsets 1–99 have length 100 and
/// radius 5.
pub fn interpreter_with(src: &str, preset: &str, dialect: Dialect, tweak: impl FnOnce(&mut Config)) -> Interpreter {
    let mut cfg = Config::new(MachineConfig::preset(preset).expect("preset"), dialect);
    cfg.max_blocks = 1_000_000;
    tweak(&mut cfg);
    let mut interp = Interpreter::new(parse_file(src), cfg);
    for n in 1..=99 {
        let t = interp.state.offsets.tool_mut(n).unwrap();
        t.h_geometry = 100.0;
        t.d_geometry = 5.0;
    }
    interp
}

/// Run on mill3/FANUC; the full result.
pub fn run_src(src: &str) -> RunResult {
    run_with(src, "mill3", Dialect::Fanuc)
}

pub fn run_with(src: &str, preset: &str, dialect: Dialect) -> RunResult {
    let mut interp = interpreter(src, preset, dialect);
    run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {})
}

/// The value of common variable `n` after running `src` (None = vacant).
pub fn var(src: &str, n: u32) -> Option<f64> {
    let r = run_src(src);
    assert!(r.completed(), "unexpected alarm {:?} in\n{src}", r.alarms);
    r.variables.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
}

/// The alarm code `src` ends in (panics if it completes).
pub fn alarm(src: &str) -> String {
    alarm_with(src, Dialect::Fanuc)
}

pub fn alarm_with(src: &str, dialect: Dialect) -> String {
    let r = run_with(src, "mill3", dialect);
    assert!(!r.completed(), "expected an alarm from\n{src}");
    r.alarms[0].code.clone()
}

/// All canonical commands of a program.
pub fn canon(src: &str) -> Vec<Canon> {
    let mut interp = interpreter(src, "mill3", Dialect::Fanuc);
    let mut v = Vec::new();
    interp.run(|c| v.push(c)).expect("no alarm");
    v
}

pub fn motions(src: &str) -> Vec<fivex_engine::canon::Motion> {
    canon(src)
        .into_iter()
        .filter_map(|c| match c.kind {
            CanonKind::Motion(m) => Some(m),
            _ => None,
        })
        .collect()
}

pub fn approx(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// Every program of `tests/fixtures/*.nc` as (path, text); there are at least 40.
pub fn fixture_programs() -> Vec<(String, String)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/fixtures");
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("tests/fixtures") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "nc") {
            out.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
        }
    }
    assert!(out.len() >= 40, "expected the fixture programs, found {}", out.len());
    out
}
