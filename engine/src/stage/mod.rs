//! Path stages: where the program's path is rewritten between the interpreter and the motion
//! executor (cutter compensation, cutting point control, splines and smoothing, as they are
//! built). Every driver of the interpreter (`crate::run`, `crate::controller`,
//! `crate::preview`) passes the canonical commands of each step through its [`Pipeline`]
//! before the executor sees them, so a stage is written once and acts on every run, every
//! controller and every preview.
//!
//! Adding a stage: write a module under `stage/` with a type that implements [`Stage`], and
//! register it in [`Pipeline::for_config`], the one place that says which stages a program
//! goes through and in which order. Until a function's stage exists, the interpreter refuses
//! the function with the dialect's alarm (`interp::unbuilt`), never passes it on silently.
//!
//! A stage may hold commands back to look ahead (cutter compensation C holds a motion until the
//! next motion in its plane has come, to place the corner between them). It releases them, in
//! order, when it has seen enough, and all of them at the end of the program. A command keeps
//! the line, sequence number and tip basis of the block it came from; the controller counts a
//! released command to the block being read when it comes out (what its modal display shows
//! while it moves).
//!
//! A stage out of its mode may say so ([`Stage::passes`]): the pipeline then does not move the
//! commands through it (three stages moving every command cost a long program of short moves
//! about 9 % of its run time).
//!
//! A stage that finds a program error (a gouge, a corner without a solution) holds back the
//! offending command and everything after it and gives the alarm to the pipeline
//! ([`Stage::take_alarm`]); [`Pipeline::process`] returns it to its driver with what was
//! released before it, and the driver stops there as on an interpreter alarm. The interpreter
//! tells the stages one thing the commands do not carry, through the [`Link`] of its `Config`:
//! where the path stood when cutter compensation was turned on.

pub mod cutter;
pub mod leading_edge;
mod tool_shift;
pub mod tool_side;

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, CutterWord, Pos};
use crate::interp::Config;
use crate::Dialect;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// How many blocks without movement `after` holds (the commands a stage holds behind the motion
/// of line `held` that waits for its corner): one per block, and one more for each
/// [`CutterWord::WithoutMotion`] (a block that gave nothing else, or a zero move's second).
fn blocks_without_motion(after: &[Canon], held: u32) -> usize {
    let marked = |c: &&Canon| matches!(c.kind, CanonKind::Cutter(CutterWord::WithoutMotion));
    let mut lines: Vec<u32> = after.iter().filter(|c| !marked(c)).map(|c| c.line).filter(|&l| l != held).collect();
    lines.dedup();
    lines.len() + after.iter().filter(marked).count()
}

/// What the path stages tell the interpreter that feeds them (one per interpreter: a cloned
/// `Config` gets a new one, [`Link::share`] hands the same one to the stages).
#[derive(Default)]
pub struct Link(Arc<Shared>);

/// The link's state. The flag lets the stage ask "anything there?" once per command without
/// taking the lock.
#[derive(Default)]
struct Shared {
    /// A start of compensation is waiting in `data`.
    posted: AtomicBool,
    data: Mutex<Data>,
}

#[derive(Default)]
struct Data {
    comp_start: Option<CompStart>,
}

/// Cutter compensation was turned on (G41/G42, G41.2/G42.2 or G41.3 after G40).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompStart {
    /// Where the program's path stood (programming coordinates): the start of the start-up
    /// block.
    pub pos: Pos,
    /// Where the machine axes stood then (the tool direction at G41.3, `stage::leading_edge`).
    pub machine: Pos,
    /// The block that turned compensation on inserts a move of its own when the next block
    /// comes: a start-up "perpendicular to the next movement" (FANUC No.5003#1 SUV = 1: the
    /// G41/G42 block is in G00/G01 and has no axis word of the plane), or the leading edge
    /// offset's G41.3 block (its move by the first vector). Its line and sequence number, and
    /// whether it is in G00, for the block the stage inserts.
    pub perpendicular: Option<PerpendicularStart>,
    /// 5-axis cutter compensation in the table coordinate system without tool centre point
    /// control (FANUC TBP = 1, WKP = 0): that system in the table frame, frozen at the end of the
    /// start block (`pos` is then in it). The start block is an ordinary move whose end the
    /// interpreter gives there; the moves of the mode carry it as their tip frame.
    pub table: Option<crate::geom::Rigid>,
}

/// The G41/G42 block of a start-up "perpendicular to the next movement", or a G41.3 block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PerpendicularStart {
    pub line: u32,
    pub n: Option<u32>,
    pub rapid: bool,
}

impl Clone for Link {
    fn clone(&self) -> Link {
        Link::default()
    }
}

impl std::fmt::Debug for Link {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Link")
    }
}

impl Link {
    /// The same link, for the stages of the interpreter whose `Config` holds it.
    pub fn share(&self) -> Link {
        Link(self.0.clone())
    }

    fn lock(&self) -> MutexGuard<'_, Data> {
        // A panic elsewhere cannot leave the two plain fields half-written.
        self.0.data.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn post(&self, f: impl FnOnce(&mut Data)) {
        let mut data = self.lock();
        f(&mut data);
        self.0.posted.store(data.comp_start.is_some(), Ordering::Release);
    }

    fn take<T>(&self, f: impl FnOnce(&mut Data) -> Option<T>) -> Option<T> {
        if !self.0.posted.load(Ordering::Acquire) {
            return None;
        }
        let mut value = None;
        self.post(|data| value = f(data));
        value
    }

    /// The interpreter turned cutter compensation on.
    pub fn comp_started(&self, start: CompStart) {
        self.post(|data| data.comp_start = Some(start));
    }

    pub fn take_comp_start(&self) -> Option<CompStart> {
        self.take(|data| data.comp_start.take())
    }

    /// A reset: nothing is due.
    pub fn clear(&self) {
        self.post(|data| *data = Data::default());
    }
}

/// One stage of the path.
pub trait Stage: Send {
    /// Take the next command; hand on, in order, whatever is ready.
    fn push(&mut self, command: Canon, out: &mut Vec<Canon>);
    /// The program has ended (or stopped with an alarm): hand on everything held.
    fn finish(&mut self, out: &mut Vec<Canon>);
    /// The program was abandoned (reset): drop everything held.
    fn reset(&mut self);
    /// The program error this stage found (its id, and the line and sequence number of the
    /// block), once; the stage hands nothing on after it until a reset.
    fn take_alarm(&mut self) -> Option<(AlarmId, u32, Option<u32>)> {
        None
    }
    /// Whether the stage, as it stands, would hand `command` on unchanged at once (holding
    /// nothing, taking nothing from it): then the pipeline does not pass it through the stage.
    /// `false` (the default) is always right; `true` only saves moving commands.
    fn passes(&self, _command: &Canon) -> bool {
        false
    }
}

/// The stages a machine's programs go through, in order.
#[derive(Default)]
pub struct Pipeline {
    stages: Vec<Box<dyn Stage>>,
    /// Whose alarm codes and messages a stage's error gets.
    dialect: Dialect,
    /// What one stage handed on, for the next.
    between: Vec<Canon>,
}

impl Pipeline {
    /// The stages for programs run with `config`: the tool side offset and the leading edge
    /// offset of 5-axis cutter compensation, and cutter compensation C (the three are modes of
    /// one modal group: a motion is changed by one of them at most; the first two hand the last
    /// the words of G38/G39/G40). Cutting point control and splines are refused by the
    /// interpreter until their stages are built.
    pub fn for_config(config: &Config) -> Pipeline {
        let stages: Vec<Box<dyn Stage>> = vec![
            Box::new(tool_side::ToolSide::new(config)),
            Box::new(leading_edge::LeadingEdge::new(config)),
            Box::new(cutter::Cutter::new(config)),
        ];
        Pipeline { stages, dialect: config.dialect, between: Vec::new() }
    }

    /// Pass one interpreter step's commands through every stage: `commands` becomes what comes
    /// out of the last one. `end`: the program has ended, everything held comes out. A stage's
    /// program error comes back after what was released before it: the driver carries those
    /// out and stops with the alarm, as on an interpreter alarm.
    #[must_use = "a stage's program error must stop the driver"]
    pub fn process(&mut self, commands: &mut Vec<Canon>, end: bool) -> Option<Alarm> {
        let mut found = None;
        for stage in &mut self.stages {
            // A stage out of its mode hands every command on as it is (most programs, most of
            // the time): no need to move them through it.
            if !end && commands.iter().all(|c| stage.passes(c)) {
                continue;
            }
            for c in commands.drain(..) {
                stage.push(c, &mut self.between);
            }
            if end {
                stage.finish(&mut self.between);
            }
            std::mem::swap(commands, &mut self.between);
            found = found.or_else(|| stage.take_alarm());
        }
        // The blocks without movement have been counted; the executor has nothing to do for them.
        commands.retain(|c| !matches!(c.kind, CanonKind::Cutter(CutterWord::WithoutMotion)));
        let (id, line, n) = found?;
        let (code, message) = self.dialect.describe(&id);
        Some(Alarm { code, message, line, n })
    }

    /// Drop everything the stages hold (and the alarm they found).
    pub fn reset(&mut self) {
        for stage in &mut self.stages {
            stage.reset();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canon::CanonKind;

    /// A stage that holds each command until the next one comes (one command of look-ahead).
    #[derive(Default)]
    struct HoldOne(Option<Canon>);

    impl Stage for HoldOne {
        fn push(&mut self, command: Canon, out: &mut Vec<Canon>) {
            out.extend(self.0.replace(command));
        }
        fn finish(&mut self, out: &mut Vec<Canon>) {
            out.extend(self.0.take());
        }
        fn reset(&mut self) {
            self.0 = None;
        }
    }

    fn dwell(line: u32) -> Canon {
        Canon { line, n: None, kind: CanonKind::Dwell { seconds: 1.0 }, tip_basis: Default::default() }
    }

    fn lines(c: &[Canon]) -> Vec<u32> {
        c.iter().map(|c| c.line).collect()
    }

    #[test]
    fn stages_look_ahead_and_release_everything_at_the_end_in_order() {
        let mut p =
            Pipeline { stages: vec![Box::new(HoldOne::default()), Box::new(HoldOne::default())], ..Default::default() };
        let mut step = vec![dwell(1), dwell(2)];
        assert_eq!(p.process(&mut step, false), None);
        assert!(step.is_empty(), "two stages of one command each hold both: {:?}", lines(&step));
        let mut step = vec![dwell(3)];
        assert_eq!(p.process(&mut step, false), None);
        assert_eq!(lines(&step), [1]);
        let mut step = vec![dwell(4)];
        assert_eq!(p.process(&mut step, true), None);
        assert_eq!(lines(&step), [2, 3, 4]);
    }

    #[test]
    fn reset_drops_what_is_held() {
        let mut p = Pipeline { stages: vec![Box::new(HoldOne::default())], ..Default::default() };
        let mut step = vec![dwell(1)];
        assert_eq!(p.process(&mut step, false), None);
        p.reset();
        let mut step = vec![dwell(2)];
        assert_eq!(p.process(&mut step, true), None);
        assert_eq!(lines(&step), [2]);
    }

    /// A stage that finds an interference at line 2 and hands on nothing from there.
    #[derive(Default)]
    struct Gouge(Option<(AlarmId, u32, Option<u32>)>, bool);

    impl Stage for Gouge {
        fn push(&mut self, command: Canon, out: &mut Vec<Canon>) {
            if command.line == 2 {
                (self.0, self.1) = (Some((AlarmId::CutterInterference, 2, None)), true);
            }
            if !self.1 {
                out.push(command);
            }
        }
        fn finish(&mut self, _: &mut Vec<Canon>) {}
        fn reset(&mut self) {
            *self = Gouge::default();
        }
        fn take_alarm(&mut self) -> Option<(AlarmId, u32, Option<u32>)> {
            self.0.take()
        }
    }

    #[test]
    fn a_stage_error_comes_back_after_what_was_released_before_it() {
        let mut p = Pipeline {
            stages: vec![Box::new(Gouge::default())],
            dialect: crate::Dialect::Syntec,
            ..Default::default()
        };
        let mut step = vec![dwell(1), dwell(2), dwell(3)];
        let alarm = p.process(&mut step, false).expect("the stage's alarm");
        assert_eq!(lines(&step), [1]);
        assert_eq!(
            (alarm.code.as_str(), alarm.line),
            (crate::Dialect::Syntec.describe(&AlarmId::CutterInterference).0.as_str(), 2)
        );
        let mut step = vec![dwell(4)];
        assert_eq!(p.process(&mut step, true), None, "raised once");
    }

    #[test]
    fn a_cloned_config_gets_its_own_link() {
        let config = Config::new(crate::machine::MachineConfig::preset("mill3").unwrap(), crate::Dialect::Fanuc);
        let shared = config.stages.share();
        let cloned = config.clone();
        let start = CompStart {
            pos: [1.0; crate::machine::MAX_AXES],
            machine: [2.0; crate::machine::MAX_AXES],
            perpendicular: None,
            table: None,
        };
        config.stages.comp_started(start);
        assert_eq!(cloned.stages.take_comp_start(), None);
        assert_eq!(shared.take_comp_start(), Some(start));
        assert_eq!(shared.take_comp_start(), None, "once");
    }

    #[test]
    fn without_compensation_the_stages_hand_on_as_it_came() {
        let config = Config::new(crate::machine::MachineConfig::preset("mill3").unwrap(), crate::Dialect::Fanuc);
        let mut p = Pipeline::for_config(&config);
        let mut step = vec![dwell(1), dwell(2)];
        assert_eq!(p.process(&mut step, false), None);
        assert_eq!(lines(&step), [1, 2]);
    }
}
