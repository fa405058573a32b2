//! Helpers shared by the engine's integration tests.
#![allow(dead_code)]

use fivex_engine::canon::{Canon, CanonKind};
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use proptest::prelude::{prop_assert, TestCaseError};

pub mod random;

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

/// The machine position at the end of each motion of a program, with its line.
pub fn motion_ends(mut interp: Interpreter) -> Vec<(u32, fivex_engine::canon::Pos)> {
    let mut v = Vec::new();
    interp
        .run(|c| {
            if let CanonKind::Motion(m) = c.kind {
                v.push((c.line, m.machine))
            }
        })
        .expect("no alarm");
    v
}

/// The end of the last motion of `line` among `ends`.
pub fn end_of(ends: &[(u32, fivex_engine::canon::Pos)], line: u32) -> fivex_engine::canon::Pos {
    ends.iter().rev().find(|(l, _)| *l == line).expect("a motion on that line").1
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

/// Per-axis limits of a preset, and whether the axis rolls over (its samples are shown
/// modulo 360).
pub fn limits(preset: &str) -> Vec<(f64, f64, f64, bool)> {
    limits_of(&MachineConfig::preset(preset).unwrap())
}

/// [`limits`] of any machine.
pub fn limits_of(m: &MachineConfig) -> Vec<(f64, f64, f64, bool)> {
    m.axes.iter().map(|a| (a.rapid / 60.0, a.max_accel(), a.max_jerk(), a.rollover)).collect()
}

/// Finite differences of the sampled axis positions stay within the axis limits: speed
/// everywhere; acceleration and jerk inside blocks, and at block junctions too when every
/// block ends at rest, sampled every millisecond (a corner may change an axis's speed by the allowed step at once, as
/// FANUC's No.1783 allows).
pub fn check_limits(samples: &[Sample], preset: &str, junctions_too: bool) -> Result<(), TestCaseError> {
    check_limits_of(samples, &MachineConfig::preset(preset).unwrap(), junctions_too)
}

/// Axis `i` of four consecutive samples, a rollover axis unwound across 0/360 (a sample moves
/// far less than half a turn).
pub fn positions(w: [&Sample; 4], i: usize, rollover: bool) -> [f64; 4] {
    let mut x = w.map(|s| s.machine[i]);
    for k in 1..4 {
        if rollover {
            x[k] = x[k - 1] + ((x[k] - x[k - 1] + 180.0).rem_euclid(360.0) - 180.0);
        }
    }
    x
}

/// Speed, acceleration and jerk by finite differences of four positions 1 ms apart.
pub fn derivatives(x: [f64; 4]) -> (f64, f64, f64) {
    derivatives_every(x, 0.001)
}

/// [`derivatives`] of positions `period` seconds apart.
pub fn derivatives_every(x: [f64; 4], period: f64) -> (f64, f64, f64) {
    let vel = (x[1] - x[0]) / period;
    let acc = (x[2] - 2.0 * x[1] + x[0]) / (period * period);
    let jerk = (x[3] - 3.0 * x[2] + 3.0 * x[1] - x[0]) / period.powi(3);
    (vel, acc, jerk)
}

/// [`check_limits`] on any machine.
pub fn check_limits_of(samples: &[Sample], m: &MachineConfig, junctions_too: bool) -> Result<(), TestCaseError> {
    check_limits_every(samples, m, junctions_too, 0.001)
}

/// [`check_limits_of`] with every junction between two motion segments taken as a corner,
/// also within one line (`Sample::segment`: a compensated corner's connecting moves).
pub fn check_limits_by_segment(samples: &[Sample], m: &MachineConfig) -> Result<(), TestCaseError> {
    check_limits_within(samples, m, false, 0.001, |w| {
        w.iter().all(|s| s.line == w[0].line && s.segment == w[0].segment)
    })
}

/// [`check_limits_of`] on samples `period` seconds apart (a finite difference over a longer
/// period averages the derivative over it, so the same limits hold).
pub fn check_limits_every(
    samples: &[Sample],
    m: &MachineConfig,
    junctions_too: bool,
    period: f64,
) -> Result<(), TestCaseError> {
    check_limits_within(samples, m, junctions_too, period, |w| w.iter().all(|s| s.line == w[0].line))
}

/// The limits check of [`check_limits_every`], `same_block` telling the windows of four samples
/// that lie within one block from those across a junction.
fn check_limits_within(
    samples: &[Sample],
    m: &MachineConfig,
    junctions_too: bool,
    period: f64,
    same_block: impl Fn(&[Sample]) -> bool,
) -> Result<(), TestCaseError> {
    let lim = limits_of(m);
    let slack = 1.0 + 1e-6;
    for w in samples.windows(4) {
        let same_block = same_block(w);
        for (i, &(v, a, j, rollover)) in lim.iter().enumerate() {
            let x = positions([&w[0], &w[1], &w[2], &w[3]], i, rollover);
            let (vel, acc, jerk) = derivatives_every(x, period);
            prop_assert!(vel.abs() <= v * slack + 1e-6, "axis {i} speed {vel} > {v} at t={}", w[0].t);
            if same_block || junctions_too {
                prop_assert!(acc.abs() <= a * slack + 1e-3, "axis {i} acceleration {acc} > {a} at t={}", w[0].t);
                prop_assert!(jerk.abs() <= j * slack + 1.0, "axis {i} jerk {jerk} > {j} at t={}", w[0].t);
            } else {
                // Across a junction: at most the corner step (A × 1 ms) plus what the two
                // periods' acceleration adds.
                let dv = ((x[2] - x[1]) - (x[1] - x[0])) / period;
                prop_assert!(
                    dv.abs() <= (0.001 + 2.0 * period) * a * slack,
                    "axis {i} speed step {dv} at t={} (lines {} to {})",
                    w[0].t,
                    w[0].line,
                    w[3].line
                );
            }
        }
    }
    Ok(())
}

/// Every sampled axis position lies within its stored stroke.
pub fn check_strokes(samples: &[Sample], m: &MachineConfig) -> Result<(), TestCaseError> {
    for s in samples {
        for (i, a) in m.axes.iter().enumerate() {
            if let Some([lo, hi]) = a.stroke {
                let x = s.machine[i];
                prop_assert!(
                    x >= lo - 1e-6 && x <= hi + 1e-6,
                    "axis {} at {x} outside [{lo}, {hi}] at t={}",
                    a.name,
                    s.t
                );
            }
        }
    }
    Ok(())
}

/// A proptest case count: `default`, or PROPTEST_CASES when set (a count written into a
/// `ProptestConfig` would override the variable).
pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(default)
}

/// The motion ends that come out of the path stages for `src` on `preset` (FANUC): line and
/// X/Y/Z in programming coordinates, and the alarm (code, line). Under a 5-axis cutter
/// compensation (G41.2…G42.6, G41.3) every motion's machine axes are checked to put the tool
/// where the stage says: the tip under TCP (tool length 100), else the programmed point.
pub struct Ends {
    pub ends: Vec<(u32, fivex_engine::kin::Vec3)>,
    pub alarm: Option<(String, u32)>,
}

pub fn ends_of(src: &str, preset: &str) -> Ends {
    ends_with(src, preset, |_| {})
}

/// [`ends_of`] with the configuration `tweak` adjusts (the machine's mechanism as the preset's).
pub fn ends_with(src: &str, preset: &str, tweak: impl FnOnce(&mut Config)) -> Ends {
    use fivex_engine::interp::gcode::code;
    use fivex_engine::kin::{Kinematics, Vec3};
    let kin = Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap();
    let mut ends = Vec::new();
    let alarm = through_stages(interpreter_with(src, preset, Dialect::Fanuc, tweak), |c| {
        if let CanonKind::Motion(m) = c.kind {
            let on = code::TOOL_SIDE.contains(&m.context.cutter_comp) || m.context.cutter_comp == code::G41_3;
            let at = Vec3::new(m.target[0], m.target[1], m.target[2]);
            let length = if m.tip.is_some() { 100.0 } else { 0.0 };
            let tip = kin.forward(&m.machine, length).tip;
            let want = if let Some(t) = &m.tip { t.to } else { kin.forward(&m.target, 0.0).tip };
            assert!(!on || (tip - want).norm() < 1e-9, "line {}: machine tip {tip:?}, stage {want:?}", c.line);
            ends.push((c.line, at));
        }
    });
    Ends { ends, alarm }
}

/// Run `interp` to its end through the path stages every driver uses, handing `each` every
/// command that comes out; the alarm (code, line) that stopped it, if any.
pub fn through_stages(mut interp: Interpreter, mut each: impl FnMut(Canon)) -> Option<(String, u32)> {
    use fivex_engine::interp::Step;
    let mut stages = fivex_engine::stage::Pipeline::for_config(interp.config());
    let mut out = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let end = !matches!(step, Ok(Step::Continue | Step::NeedInput));
        let stage_alarm = stages.process(&mut out, end);
        out.drain(..).for_each(&mut each);
        if let Some(a) = stage_alarm {
            return Some((a.code, a.line));
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return None,
            Err(a) => return Some((a.code, a.line)),
        }
    }
}

/// No alarm, and the motion ends of [`ends_of`] are `want` (line, X/Y/Z) to 1e-6, in order.
#[track_caller]
pub fn assert_ends(src: &str, preset: &str, want: &[(u32, [f64; 3])]) {
    let got = ends_of(src, preset);
    assert_eq!(got.alarm, None, "{src}");
    let close = got.ends.len() == want.len()
        && got
            .ends
            .iter()
            .zip(want)
            .all(|((l, p), (wl, w))| l == wl && (p - fivex_engine::kin::Vec3::from(*w)).norm() < 1e-6);
    assert!(close, "got {:?}\nwant {want:?}\n{src}", got.ends);
}

/// The first alarm (code, line) of a run of `src` on `preset` (FANUC), if any.
pub fn first_alarm(src: &str, preset: &str) -> Option<(String, u32)> {
    first_alarm_with(src, preset, |_| {})
}

/// [`first_alarm`] with the configuration `tweak` adjusts.
pub fn first_alarm_with(src: &str, preset: &str, tweak: impl FnOnce(&mut Config)) -> Option<(String, u32)> {
    let mut interp = interpreter_with(src, preset, Dialect::Fanuc, tweak);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    r.alarms.first().map(|a| (a.code.clone(), a.line))
}
