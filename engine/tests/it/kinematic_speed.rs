//! Kinematic segments run as fast as the machine allows (issue 17, item 3; `docs/motion.md`,
//! "Kinematic paths"): on random machines, TCP and tilted-plane blocks never drive an axis past
//! its limits, and at every sample the tip moves at the commanded feed or some axis is at 90 %
//! or more of one of its limits (speed, acceleration or jerk) — where that holds. Each sample of
//! a block is counted in one class ([`Tally`]): the feed, an axis at the limit, a jerk switch
//! the differences smear, a block end, or *short*: below both. The property tests assert the
//! limits and, per block, the feed or an axis at 90 % somewhere; `kinematic_samples_survey`
//! measures the classes over a fixed set of random cases and holds them to the figures
//! `docs/motion.md` gives (the short samples are the part of the rule not reached yet: where
//! the planned profile joins its forward and backward drives, a drive braking early for a dip
//! of the path's speed limit, runs whose analytic profile was quicker, and runs the drives
//! cannot plan, which keep the analytic one).
//!
//! The axis speeds, accelerations and jerks are finite differences of the 1 ms samples (as in
//! `common::check_limits_of`): over four samples of one block they are exact for the cubic
//! pieces of the profile and average a jerk switch over 3 ms.
//!
//! Case counts are modest by default; `PROPTEST_CASES=200 cargo test -p fivex-engine --test it kinematic_speed`
//! runs more.

use crate::common;

use common::random::{angles_inside, random_machine_of};
use common::{cases, check_limits_of, derivatives, interpreter_with, limits_of, positions};
use fivex_engine::controller::{Controller, RunState};
use fivex_engine::interp::Config;
use fivex_engine::kin::MachineKind;
use fivex_engine::machine::{AxisKind, MachineConfig};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::Dialect;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{RngAlgorithm, TestRng, TestRunner};

/// Run `src` on `machine`, every 1 ms sample.
fn run_on(machine: &MachineConfig, src: &str) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| c.machine = machine.clone().into());
    let mut samples = Vec::new();
    let options = RunOptions { max_time_s: 120.0, ..RunOptions::default() };
    let r = run(&mut interp, &options, |s| samples.push(*s));
    (r, samples)
}

/// A number as a program writes it.
fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// The rotary words for commanded angles `q` (axis order).
fn rotary_words(m: &MachineConfig, q: &[f64]) -> String {
    let mut s = String::new();
    for (i, a) in m.axes.iter().enumerate() {
        if a.kind == AxisKind::Rotary {
            s += &format!(" {}{:.3}", a.name, mm(q[i]));
        }
    }
    s
}

/// Random machines with two rotary axes (every kind but the 4-axis ones).
fn five_axis_machine() -> impl Strategy<Value = MachineConfig> {
    (0..3usize).prop_flat_map(|k| {
        random_machine_of([MachineKind::HeadHead, MachineKind::TableTable, MachineKind::HeadTable][k])
    })
}

/// The highest share of a limit (speed, acceleration or jerk) any axis reaches over four
/// consecutive samples, by finite differences.
fn window_share(w: &[&Sample], lim: &[(f64, f64, f64, bool)]) -> f64 {
    let mut most: f64 = 0.0;
    for (i, &(v, a, j, rollover)) in lim.iter().enumerate() {
        let (vel, acc, jerk) = derivatives(positions([w[0], w[1], w[2], w[3]], i, rollover));
        most = most.max(vel.abs() / v).max(acc.abs() / a).max(jerk.abs() / j);
    }
    most
}

/// The share of a limit an axis must reach wherever the tip is below the feed (issue 17).
const AT_LIMIT: f64 = 0.9;

/// The share of a limit some axis reaches somewhere in a block whose tip stays below the feed,
/// at least. The goal is [`AT_LIMIT`], which blocks planned against the axes at every point
/// (`motion/optimal.rs`) reach; a run that plan cannot do keeps the path limits, whose floor this
/// is (random runs found 74 % and 85 %; before that planning the lowest of 500 was 55 %; on
/// 2026-11-29 one at 42.2 %, kept in the regressions file: F14915 X16.474 Y5.597 Z67.581 A33.2
/// B−35.816 on a random head-head, whose forward drive ran into a state where no path jerk keeps
/// every axis within its jerk — 3·v·a·q2 and v³·q3 pull two axes apart. Its drives now run again
/// slower there, and it reaches 98 %; the lowest of 8000 random blocks since was 56 %. In
/// session 25 the shrinker found a head-head block at 35.8 %, present since before it, whose
/// two drives cross still accelerating and no cap down to 85 % of the crossing speed let them
/// join: the caps now go down to 50 %, and it passes).
const BLOCK_REACHED: f64 = 0.5;

/// Samples at either end of a block where its junction speed or the stop binds.
const ENDS: usize = 3;

/// How the samples of blocks meet the rule, each sample in the first class that holds.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
struct Tally {
    samples: usize,
    /// The tip at the feed (after override).
    feed: usize,
    /// Some axis at [`AT_LIMIT`] or more of a limit over the four samples around it (the one
    /// before, it and the two after: speed, acceleration and jerk centred on it).
    axis: usize,
    /// Only a window holding the sample that is not centred on it reaches [`AT_LIMIT`]: a jerk
    /// switch the differences smear over 3 ms.
    smeared: usize,
    /// Within [`ENDS`] samples of the block's first or last, where a junction or the stop binds.
    ends: usize,
    /// None of these: the rule is not met at this sample.
    short: usize,
    /// The highest share any window of the block reaches.
    peak: f64,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.samples += o.samples;
        self.feed += o.feed;
        self.axis += o.axis;
        self.smeared += o.smeared;
        self.ends += o.ends;
        self.short += o.short;
        self.peak = self.peak.max(o.peak);
    }

    fn share(&self, n: usize) -> f64 {
        n as f64 / self.samples.max(1) as f64
    }
}

/// The rule at every sample of `line`, fed at `feed` mm/min.
fn tally(samples: &[Sample], m: &MachineConfig, line: u32, feed: f64) -> Tally {
    let lim = limits_of(m);
    let block: Vec<&Sample> = samples.iter().filter(|s| s.line == line).collect();
    let n = block.len();
    let windows: Vec<f64> = (0..n.saturating_sub(3)).map(|w| window_share(&block[w..w + 4], &lim)).collect();
    let window = |w: usize| windows.get(w).copied().unwrap_or(0.0);
    let mut t = Tally { samples: n, peak: windows.iter().copied().fold(0.0, f64::max), ..Tally::default() };
    for (k, sample) in block.iter().enumerate() {
        if sample.feed >= 0.99 * feed {
            t.feed += 1;
        } else if k >= 1 && window(k - 1) >= AT_LIMIT {
            t.axis += 1;
        } else if (k.saturating_sub(3)..=k).any(|w| window(w) >= AT_LIMIT) {
            t.smeared += 1;
        } else if k < ENDS || k + ENDS >= n {
            t.ends += 1;
        } else {
            t.short += 1;
        }
    }
    t
}

/// The limits, and the block rule: the tip at the feed or an axis at [`AT_LIMIT`] somewhere in
/// `line` (of a completed run fed at `feed` mm/min); the block's tally.
fn check_block(samples: &[Sample], m: &MachineConfig, line: u32, feed: f64, src: &str) -> Result<Tally, TestCaseError> {
    check_limits_of(samples, m, false)?;
    let t = tally(samples, m, line, feed);
    prop_assert!(
        t.feed > 0 || t.peak >= BLOCK_REACHED,
        "line {line}: the tip never reaches F{feed} mm/min and no axis more than {:.1} % of a limit\n{src}\n{m:?}",
        t.peak * 100.0
    );
    Ok(t)
}

/// A G43.4 line from X0 Y0 Z50 (rotary axes at 0) to `target` scaled to `travel` mm while the
/// rotary axes turn to `fractions` of their range, at `feed` mm/min; the block is line 4.
fn tcp_program(m: &MachineConfig, target: [f64; 3], travel: f64, fractions: &[f64], feed: f64) -> Option<String> {
    let norm = target.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm <= 0.1 {
        return None;
    }
    let p = target.map(|x| mm(x / norm * travel));
    let zero: String = m.rotary.iter().map(|l| format!(" {}0", l.axis)).collect();
    Some(format!(
        "G90 G17 G00{zero}\nG43.4 H1\nX0 Y0 Z50.\nG09 G01 X{:.3} Y{:.3} Z{:.3}{} F{:.0}\nG49\nM30\n",
        p[0],
        p[1],
        50.0 + p[2],
        rotary_words(m, &angles_inside(m, fractions, 3.0)),
        feed
    ))
}

/// A move in a tilted working plane (G68.2 with Euler angles `angles`, G53.1, G43 H1) to
/// `target` at `feed` mm/min; the block is line 7.
fn twp_program(m: &MachineConfig, angles: (f64, f64, f64), target: [f64; 3], feed: f64) -> String {
    let zero: String = m.rotary.iter().map(|l| format!(" {}0", l.axis)).collect();
    let (i, j, k) = angles;
    let [tx, ty, tz] = target.map(mm);
    format!(
        "G90 G54 G00{zero}\nG01 X0 Y0 Z50. F2000.\nG68.2 X0 Y0 Z0 I{i:.3} J{j:.3} K{k:.3}\nG01 X0 Y0 Z50.\nG53.1\nG43 H1\n\
         G01 X{tx:.3} Y{ty:.3} Z{tz:.3} F{feed:.0}\nG49\nG69\nM30\n"
    )
}

/// F from 500 to 20000 mm/min, tip travel from 0.5 to 60 mm (a short move with a large swing
/// is the case that crawled).
fn tcp_cases() -> impl Strategy<Value = (MachineConfig, [f64; 3], f64, Vec<f64>, f64)> {
    (
        five_axis_machine(),
        prop::array::uniform3(-1.0..1.0f64),
        0.5..60.0f64,
        prop::collection::vec(0.0..1.0f64, 8),
        500.0..20000.0f64,
    )
}

/// Whether G53.1 finds the tool direction of the G68.2 plane `angles` (as `twp_program` writes
/// them): an inverse solution within the movement ranges (FANUC's choice from the program zero).
fn reaches_the_plane(m: &MachineConfig, (i, j, k): (f64, f64, f64)) -> bool {
    use fivex_engine::kin::{Kinematics, Selection, Vec3};
    let kin = Kinematics::new(m).unwrap();
    let zeros = vec![0.0; m.axes.len()];
    let z = fivex_engine::twp::euler(Vec3::zeros(), mm(i), mm(j), mm(k)).z();
    let tool = kin.table_frame(&zeros).r.transpose() * z;
    let candidates = kin.inverse(Vec3::zeros(), tool, 0.0, &zeros);
    kin.select(&candidates, &zeros, Selection { dialect: Dialect::Fanuc, pri: false, p: 0 }).is_ok()
}

fn twp_cases() -> impl Strategy<Value = (MachineConfig, (f64, f64, f64), [f64; 3], f64)> {
    (
        five_axis_machine(),
        (-180.0..180.0f64, 0.0..60.0f64, -180.0..180.0f64),
        prop::array::uniform3(-50.0..50.0f64),
        500.0..40000.0f64,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(64), ..ProptestConfig::default() })]

    /// G43.4 lines on random machines while the rotary axes turn to random angles.
    #[test]
    fn tcp_blocks_run_at_the_feed_or_an_axis_limit((m, target, travel, fractions, feed) in tcp_cases()) {
        let src = tcp_program(&m, target, travel, &fractions, feed);
        prop_assume!(src.is_some());
        let src = src.unwrap_or_default();
        let (r, samples) = run_on(&m, &src);
        // No OT refusal is left out: the rotary axes turn in proportion between angles within
        // their ranges, and the linear strokes are far (none in 1 000 cases).
        prop_assert!(r.completed(), "{:?}\n{src}", r.alarms);
        check_block(&samples, &m, 4, feed.round(), &src)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(16), ..ProptestConfig::default() })]

    /// A move in a tilted working plane on random machines: the rotary axes stand, X/Y/Z follow
    /// the feature system's line.
    #[test]
    fn tilted_plane_blocks_run_at_the_feed_or_an_axis_limit((m, angles, target, feed) in twp_cases()) {
        let src = twp_program(&m, angles, target, feed);
        let (r, samples) = run_on(&m, &src);
        // A plane the machine cannot tilt to is refused (PS5459), and only such a one: not
        // this test's subject.
        if !r.completed() {
            let unreachable = r.alarms[0].code == "PS5459" && !reaches_the_plane(&m, angles);
            prop_assert!(unreachable, "{:?} for a plane the machine reaches\n{src}", r.alarms);
        }
        prop_assume!(r.completed());
        check_block(&samples, &m, 7, feed.round(), &src)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(24), ..ProptestConfig::default() })]

    /// A feed hold at a random moment of a G43.4 block on a random machine, then cycle start:
    /// the stop brakes from wherever the profile is (also one planned against the axes at every
    /// point, faster than the path limits the stop uses), never past the block's G09 point, and
    /// every axis stays within its limits (a stop that ran on into the next block showed as a
    /// speed step at the junction).
    #[test]
    fn a_feed_hold_in_a_tcp_block_keeps_every_axis_within_its_limits(
        (m, target, travel, fractions, feed) in tcp_cases(),
        at in 0.05..0.95f64,
    ) {
        let src = tcp_program(&m, target, travel, &fractions, feed);
        prop_assume!(src.is_some());
        let src = format!("G10 L10 P1 R100.\n{}", src.unwrap_or_default());
        let (r, samples) = run_on(&m, &src);
        prop_assume!(r.completed());
        let block: Vec<f64> = samples.iter().filter(|s| s.line == 5).map(|s| s.t).collect();
        prop_assume!(block.len() > 20);
        let hold_at = block[0] + at * (block[block.len() - 1] - block[0]);
        let mut c = Controller::new(Config::new(m.clone(), Dialect::Fanuc));
        c.select_program(&src).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        c.cycle_start().map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        let mut seen = vec![c.sample()];
        let tick = |c: &mut Controller, seen: &mut Vec<Sample>| {
            c.tick(0.001);
            seen.push(c.sample());
        };
        while c.time() < hold_at && c.run_state() == RunState::Running {
            tick(&mut c, &mut seen);
        }
        prop_assert_eq!(c.run_state(), RunState::Running, "the program ended before the hold");
        c.feed_hold();
        for _ in 0..3000 {
            tick(&mut c, &mut seen);
        }
        prop_assert_eq!(c.run_state(), RunState::Hold);
        c.cycle_start().map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        while c.run_state() == RunState::Running && c.time() < 200.0 {
            tick(&mut c, &mut seen);
        }
        prop_assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
        check_limits_of(&seen, &m, false)?;
    }
}

/// The cases of the survey: the same random blocks every run. (120 and 30 until 2026-11-29:
/// too few to hold a block that falls back to the analytic plan, one in twenty then, so the
/// figure they gave was 40 times better than on larger sets.)
const SURVEY_TCP: usize = 600;
const SURVEY_TWP: usize = 100;

/// The share of all samples below the feed where no axis is at [`AT_LIMIT`] (short samples),
/// at most, over the survey; `docs/motion.md` gives the measured figure.
const SURVEY_SHORT: f64 = 0.0015;

/// Every sample of a fixed set of random TCP and tilted-plane blocks, classified: the figures
/// `docs/motion.md` quotes. Run with `--nocapture` to see them.
#[test]
fn kinematic_samples_survey() {
    let mut runner =
        TestRunner::new_with_rng(ProptestConfig::default(), TestRng::from_seed(RngAlgorithm::ChaCha, &[17; 32]));
    let mut total = Tally::default();
    let (mut blocks, mut whole_short) = (0, 0);
    let record = |src: &str, m: &MachineConfig, line: u32, feed: f64, total: &mut Tally| {
        let (r, samples) = run_on(m, src);
        if !r.completed() {
            return false;
        }
        let t = check_block(&samples, m, line, feed, src).unwrap_or_else(|e| panic!("{e}"));
        total.add(&t);
        true
    };
    let tcp = tcp_cases();
    for _ in 0..SURVEY_TCP {
        let (m, target, travel, fractions, feed) = tcp.new_tree(&mut runner).expect("a case").current();
        let Some(src) = tcp_program(&m, target, travel, &fractions, feed) else { continue };
        let before = total.short;
        if record(&src, &m, 4, feed.round(), &mut total) {
            blocks += 1;
            whole_short += usize::from(total.short > before);
        }
    }
    let twp = twp_cases();
    for _ in 0..SURVEY_TWP {
        let (m, angles, target, feed) = twp.new_tree(&mut runner).expect("a case").current();
        let before = total.short;
        if record(&twp_program(&m, angles, target, feed), &m, 7, feed.round(), &mut total) {
            blocks += 1;
            whole_short += usize::from(total.short > before);
        }
    }
    let below_feed = total.samples - total.feed;
    let short = total.short as f64 / below_feed.max(1) as f64;
    eprintln!(
        "kinematic survey: {blocks} blocks, {} samples: feed {:.1} %, axis at 90 % {:.1} %, smeared {:.2} %, \
         ends {:.2} %, short {:.2} % ({:.2} % of the samples below the feed; in {whole_short} blocks)",
        total.samples,
        100.0 * total.share(total.feed),
        100.0 * total.share(total.axis),
        100.0 * total.share(total.smeared),
        100.0 * total.share(total.ends),
        100.0 * total.share(total.short),
        100.0 * short,
    );
    assert!(blocks >= SURVEY_TCP / 2, "only {blocks} of the survey's blocks completed");
    assert!(short <= SURVEY_SHORT, "{:.1} % of the samples below the feed are short of the rule", 100.0 * short);
}

/// A wave under G43.4 on head-bc in short blocks (the tip along z = 2·sin(x/5), B and C turning
/// with it), as CAM output is: the axes never stand still while the tip is fed, and keep their
/// limits in 10 ms differences. Before, a run of short blocks that the planner cut into parts
/// (each part's speed change starts and ends at zero acceleration) could not brake from the
/// speed the run was entered at: the part's profile ran past its length, and the axes stood
/// for up to 32 ms at its end while the reported feed went on, then jumped (X's jerk 4–13 times
/// its limit in 10 ms differences). And the same wave takes about the same time in blocks of
/// any length: a run of short blocks used to end at every small corner between them, each
/// block's speed change starting and ending at zero acceleration, and the wave took 3.10 s in
/// 0.2 mm blocks but 4.94 s in 0.025 mm ones.
#[test]
fn short_tcp_blocks_never_stand_still_while_fed() {
    let head_bc = MachineConfig::preset("head-bc").unwrap();
    let mut times = Vec::new();
    for step in [0.2, 0.1, 0.05, 0.025] {
        let n = (30.0 / step) as usize;
        let angles = |i: usize| {
            let u = i as f64 / n as f64;
            [10.0 + 10.0 * (3.0 * u).sin().abs(), 60.0 * u]
        };
        let mut src = String::from("G90 G00 X0 Y0 Z0 B10. C0\nG43.4 H1 G01 F6000\n");
        for i in 1..=n {
            let x = i as f64 * step;
            let [b, c] = angles(i);
            src += &format!("X{x:.7} Y{:.7} Z{:.7} B{b:.7} C{c:.7}\n", 0.3 * x, 2.0 * (x / 5.0).sin());
        }
        src += "G49\nM30\n";
        let (r, samples) = run_on(&head_bc, &src);
        assert!(r.completed(), "{:?}", r.alarms);
        let stalls =
            samples.windows(2).filter(|w| w[1].line > 2 && w[1].feed > 1.0 && w[0].machine == w[1].machine).count();
        assert_eq!(stalls, 0, "step {step}: samples where the axes stand while the feed is not 0");
        let every: Vec<Sample> = samples.iter().step_by(10).copied().collect();
        common::check_limits_every(&every, &head_bc, true, 0.01).unwrap_or_else(|e| panic!("step {step}: {e}"));
        times.push(r.cycle_time_s);
    }
    eprintln!("G43.4 wave by block length 0.2, 0.1, 0.05, 0.025 mm: {times:.3?} s");
    let (fast, slow) = times.iter().fold((f64::MAX, 0.0_f64), |(lo, hi), &t| (lo.min(t), hi.max(t)));
    assert!(slow <= 1.05 * fast, "cycle times by block length (0.2 .. 0.025 mm): {times:?}");
}
