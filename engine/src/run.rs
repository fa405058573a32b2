//! Running a program to its end: the interpreter's canonical commands go through the motion
//! planner (`crate::motion`: look-ahead, jerk-limited speed profiles, axis limits, stroke
//! check) and are sampled every interpolation period into the trace; the cycle time is the
//! simulated time including every acceleration.

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, Pos};
use crate::interp::{Interpreter, Step};
use crate::motion::{Endpoint, Executor, Segment};
use crate::notice::Notice;
use crate::stage::Pipeline;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// Interpolation (sampling) period, seconds.
    pub period_s: f64,
    /// Simulated seconds after which the run stops with an alarm.
    pub max_time_s: f64,
    /// Feed and rapid override, fractions (1.0 = 100%).
    pub feed_override: f64,
    pub rapid_override: f64,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { period_s: 0.001, max_time_s: 1.0e6, feed_override: 1.0, rapid_override: 1.0 }
    }
}

/// One interpolation period of the trace (the executor's sample).
pub use crate::motion::Sample;

#[derive(Debug, Clone, PartialEq)]
pub struct RunResult {
    pub alarms: Vec<Alarm>,
    pub blocks: u64,
    pub cycle_time_s: f64,
    pub machine: Pos,
    pub workpiece: Pos,
    /// Where the machine ends, read as the trace reads it (`crate::tip`).
    pub tip: crate::tip::Tip,
    /// The last commanded point (X, Y, Z of `workpiece`) and the system it is in.
    pub programmed: [f64; 3],
    pub programmed_in: crate::tip::System,
    /// Non-vacant common variables (#100–#199, #500–#999).
    pub variables: Vec<(u32, f64)>,
    /// DPRNT output and stop messages, in order.
    pub messages: Vec<String>,
    /// Blocks run by a rule of fivex's own (`crate::notice`), in order.
    pub notices: Vec<crate::notice::Notice>,
}

impl RunResult {
    pub fn completed(&self) -> bool {
        self.alarms.is_empty()
    }
}

/// What a run report (`crate::report`) watches besides the samples: the segment each sample is
/// on and each segment's motion. `run` passes [`NoObserver`], whose empty methods compile away,
/// so a plain run pays nothing for it.
pub trait Observer {
    /// A motion was queued for planning as `segment` (in execution order).
    fn queued(&mut self, _motion: &crate::canon::Motion, _segment: &Segment) {}
    /// One interpolation period: the sample, the machine position before rollover display,
    /// and the segment it is on with the distance along it and its number in queue order
    /// (from 0; `None` while standing still).
    fn sample(&mut self, _sample: &Sample, _machine: &Pos, _on: Option<(&Segment, f64, u64)>) {}
    /// A segment was executed to its end.
    fn executed(&mut self, _segment: &Segment) {}
    /// Asked before every block and every sample: `true` ends the run there, as if the program
    /// had ended (a host cancelling the run; the result is then incomplete and only the host
    /// knows why). The engine reads no clock and no flag of its own, so stopping is the host's.
    fn stop(&mut self) -> bool {
        false
    }
}

/// The observer that watches nothing.
pub struct NoObserver;

impl Observer for NoObserver {}

/// Run the program to its end, calling `on_sample` for every interpolation period.
pub fn run(interp: &mut Interpreter, opts: &RunOptions, on_sample: impl FnMut(&Sample)) -> RunResult {
    run_observed(interp, opts, on_sample, &mut NoObserver)
}

/// [`run`] with an observer; the result is the same bit for bit whatever the observer does,
/// unless its [`Observer::stop`] ends the run early.
pub fn run_observed(
    interp: &mut Interpreter,
    opts: &RunOptions,
    mut on_sample: impl FnMut(&Sample),
    observer: &mut impl Observer,
) -> RunResult {
    let start = Endpoint {
        machine: interp.state.machine_position(),
        work: interp.state.shown_position(),
        basis: interp.state.tip_basis(),
    };
    let mut exec = Driver {
        // A mechanism the kinematics refuses still runs; its trace shows the tool along +Z.
        exec: Executor::new(interp.config().machine.clone(), start),
        next_sample: 0,
        opts: *opts,
        messages: Vec::new(),
        notices: Vec::new(),
        over_budget: None,
        parts: 0,
        cutting_s: 0.0,
        optional_stop: interp.config().optional_stop,
        observer,
    };
    let mut stages = Pipeline::for_config(interp.config());
    let tracing = opts.period_s > 0.0;
    let mut out = Vec::with_capacity(16);
    let mut alarms = Vec::new();
    let mut motion_alarm = false;
    loop {
        if exec.observer.stop() {
            break;
        }
        let step = interp.step(&mut out);
        let stage_alarm = stages.process(&mut out, ends(&step));
        let (before, cut_before) = (exec.exec.time(), exec.cutting_s);
        for c in out.drain(..) {
            if let Err(id) = exec.apply(&c, tracing, &mut on_sample) {
                let (code, message) = interp.config().dialect.describe(&id);
                alarms.push(Alarm { code, message, line: c.line, n: c.n });
                motion_alarm = true;
                break;
            }
        }
        if motion_alarm || exec.over_budget.is_some() {
            break;
        }
        if let Some(alarm) = stage_alarm {
            // A path stage's program error: what it released before it has run.
            alarms.push(alarm);
            break;
        }
        interp.state.advance_time(exec.exec.time() - before);
        // The whole run is automatic operation (Haas #3021…, the controller's operating time).
        interp.state.count_operation(exec.exec.time() - before, exec.cutting_s - cut_before);
        match step {
            Ok(Step::Continue) => {}
            // A caller that streams parts handles this itself; here every part has arrived.
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => break,
            Err(alarm) => {
                alarms.push(alarm);
                break;
            }
        }
    }
    // Whatever was read before the end or the alarm is carried out, and the machine stops.
    let (before, cut_before) = (exec.exec.time(), exec.cutting_s);
    exec.drain(true, tracing, &mut on_sample);
    let (last_s, last_cut_s) = (exec.exec.time() - before, exec.cutting_s - cut_before);
    if let Some((line, n)) = exec.over_budget {
        // The run stopped there: a program error read ahead in a later block was never reached.
        let id = AlarmId::TimeBudgetExceeded { budget_s: opts.max_time_s };
        let (code, message) = interp.config().dialect.describe(&id);
        alarms = vec![Alarm { code, message, line, n }];
        motion_alarm = true;
    }
    let Driver { exec, messages, notices, parts, .. } = exec;
    for _ in 0..parts {
        interp.state.count_part();
    }
    // The last stretch of operation, which closes the parts' times too (Haas #3024).
    interp.state.count_operation(last_s, last_cut_s);
    // The machine is where the executor left it: a path stage may have moved it off the
    // interpreter's point (cutter compensation) or held back what an alarm then dropped.
    let machine = exec.here.machine;
    let (workpiece, basis) = if motion_alarm {
        (exec.here.work, exec.basis())
    } else {
        // As the controller shows it at rest: the one rule of `State::shown_at_rest`.
        (interp.state.shown_at_rest(&exec.here.work), interp.state.tip_basis())
    };
    let tip = crate::tip::locate(exec.machine().kinematics_of(basis.chain).map(|k| &**k), &machine, &basis);
    let shown = exec.machine();
    let (machine, workpiece) = (shown.shown(&machine), shown.shown(&workpiece));
    RunResult {
        alarms,
        blocks: interp.blocks(),
        cycle_time_s: exec.time(),
        machine,
        workpiece,
        tip,
        programmed: [workpiece[0], workpiece[1], workpiece[2]],
        programmed_in: basis.programmed_in,
        variables: interp.state.common_variables(),
        messages,
        notices,
    }
}

/// The run's driver of the executor: the interpolation periods, the time budget, the messages.
struct Driver<'o, O: Observer> {
    exec: Executor,
    observer: &'o mut O,
    /// Index of the next sample: sample k is at k × period.
    next_sample: u64,
    opts: RunOptions,
    messages: Vec<String>,
    notices: Vec<crate::notice::Notice>,
    /// The block during which simulated time ran past `max_time_s`; nothing runs after it.
    over_budget: Option<(u32, Option<u32>)>,
    /// Program ends (M02/M30) the machine reached: parts machined (#3901).
    parts: u32,
    /// Seconds the machine moved along cutting feeds (not rapids): Haas #3022.
    cutting_s: f64,
    /// The optional stop switch: off, an M01 is an M code like any other (no message).
    optional_stop: bool,
}

impl<O: Observer> Driver<'_, O> {
    fn apply(&mut self, c: &Canon, tracing: bool, on_sample: &mut impl FnMut(&Sample)) -> Result<(), AlarmId> {
        match &c.kind {
            CanonKind::Motion(m) => {
                let ctx =
                    self.exec.feed_context(self.opts.feed_override, self.opts.rapid_override, m.context.exact_stop);
                if let Some(notice) = Notice::of_command(c) {
                    Notice::add(&mut self.notices, notice);
                }
                let (observer, notices) = (&mut *self.observer, &mut self.notices);
                let queued = |seg: &Segment| {
                    observer.queued(m, seg);
                    if let Some(notice) = Notice::of(seg) {
                        Notice::add(notices, notice);
                    }
                };
                // The machine stops at the end of the block before, the offending one never
                // moving; or (G54.4) where a stroke limit stops the block on its way.
                if let Err(id) | Ok(Some(id)) = self.exec.queue(c, m, ctx, 0, None, queued) {
                    self.drain(true, tracing, on_sample);
                    return Err(id);
                }
                self.drain(false, tracing, on_sample);
            }
            other => {
                // Every other command waits for the motion before it to end; the machine then
                // stands in the block's workpiece system with its tool length.
                self.drain(true, tracing, on_sample);
                self.exec.stand_in(c.tip_basis);
                match other {
                    _ if self.over_budget.is_some() => {}
                    CanonKind::Dwell { seconds } => self.wait(*seconds, c, tracing, on_sample),
                    CanonKind::ToolChange { .. } => {
                        self.wait(self.exec.machine().motion.tool_change_s, c, tracing, on_sample)
                    }
                    CanonKind::Print { text } => self.messages.push(text.clone()),
                    CanonKind::Chain(chain) => self.exec.follow_chain(*chain),
                    CanonKind::Stop { optional: true, .. } if !self.optional_stop => {}
                    CanonKind::Stop { message: Some(m), .. } => self.messages.push(m.clone()),
                    CanonKind::ProgramEnd { .. } => self.parts += 1,
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// Stand still for `seconds` (a dwell, a tool change), sampling the trace.
    fn wait(&mut self, seconds: f64, c: &Canon, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        let t = self.exec.time();
        let end = (t + seconds).min(self.opts.max_time_s.max(t));
        if tracing {
            self.sample_until(end, Some((c.line, c.n)), on_sample);
        }
        self.exec.idle_until(end);
        if end < t + seconds {
            self.over_budget = Some((c.line, c.n));
            return;
        }
        self.check_budget(c.line, c.n);
    }

    /// Execute the runs whose speeds are final (`stop`: all, ending at rest).
    fn drain(&mut self, stop: bool, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        while self.over_budget.is_none() && self.exec.release(stop) {
            self.execute(tracing, on_sample);
        }
    }

    /// Execute the run released, to its end or to the time budget.
    fn execute(&mut self, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        let Some(end) = self.exec.run_end() else { return };
        // The run stops where the time budget runs out, even inside a segment.
        let t1 = end.min(self.opts.max_time_s.max(self.exec.time()));
        if tracing {
            self.sample_until(t1, None, on_sample);
        }
        self.exec.advance_to(t1);
        let Some(finished) = self.exec.finish() else {
            self.over_budget = Some((self.exec.here.line, self.exec.here.n));
            return;
        };
        for seg in &finished.planned.segments {
            self.observer.executed(seg);
        }
        self.cutting_s += cutting_seconds(&finished.planned);
        self.exec.arrive(&finished);
        if let Some(last) = finished.planned.segments.last() {
            self.check_budget(last.line, last.n);
        }
        if finished.planned.profile.end_speed().abs() < 1e-9 {
            self.settle(tracing, on_sample);
        }
    }

    /// At a stop, wait while the filter after interpolation still moves the axes (cutting feed
    /// without look-ahead: `docs/motion.md`), tick by tick of the interpolation period.
    fn settle(&mut self, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        while self.exec.lagging() && self.over_budget.is_none() {
            let t1 = self.exec.next_tick();
            if tracing {
                self.sample_until(t1, None, on_sample);
            }
            self.exec.idle_until(t1);
            self.check_budget(self.exec.here.line, self.exec.here.n);
        }
    }

    fn check_budget(&mut self, line: u32, n: Option<u32>) {
        if self.exec.time() > self.opts.max_time_s && self.over_budget.is_none() {
            self.over_budget = Some((line, n));
        }
    }

    /// Samples from the current time to `t1`: along the run under way, or standing still in
    /// block (`line`, `n`) of `standing`.
    fn sample_until(&mut self, t1: f64, standing: Option<(u32, Option<u32>)>, on_sample: &mut impl FnMut(&Sample)) {
        let t0 = self.exec.time();
        let standing_at = self.exec.here.machine;
        loop {
            let ts = self.next_sample as f64 * self.opts.period_s;
            if ts > t1 || (ts > t0 && t1 == t0) || self.observer.stop() {
                return;
            }
            let sample = match standing {
                None => {
                    self.exec.advance_to(ts);
                    let axes = self.exec.axes_now();
                    self.exec.sample(ts, &axes, &self.exec.basis())
                }
                Some((line, n)) => {
                    let basis = self.exec.basis();
                    Sample { line, n, feed: 0.0, ..self.exec.sample(ts, &standing_at, &basis) }
                }
            };
            on_sample(&sample);
            let raw = self.exec.axes_now();
            self.observer.sample(&sample, &raw, self.exec.on());
            self.next_sample += 1;
        }
    }
}

/// The seconds of a run spent along its cutting feeds: the profile's time between the ends of
/// each segment that is not a rapid (the time the profile reaches a distance, by bisection).
fn cutting_seconds(planned: &crate::motion::Planned) -> f64 {
    let profile = &planned.profile;
    let segments = &planned.segments;
    if segments.iter().all(|s| !s.rapid) {
        return profile.duration();
    }
    if segments.iter().all(|s| s.rapid) {
        return 0.0;
    }
    let time_at = |s: f64| {
        let (mut lo, mut hi) = (0.0, profile.duration());
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if profile.at(mid).s < s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    let (mut s0, mut total) = (0.0, 0.0);
    for (k, seg) in segments.iter().enumerate() {
        let s1 = if k + 1 == segments.len() { profile.len() } else { s0 + seg.len };
        if !seg.rapid {
            let t0 = if k == 0 { 0.0 } else { time_at(s0) };
            let t1 = if k + 1 == segments.len() { profile.duration() } else { time_at(s1) };
            total += t1 - t0;
        }
        s0 = s1;
    }
    total
}

/// The program ends after this step (its end or an alarm): the path stages release everything.
pub(crate) fn ends(step: &Result<Step, Alarm>) -> bool {
    !matches!(step, Ok(Step::Continue | Step::NeedInput))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canon::Motion;
    use crate::machine::MotionOptions;
    use crate::motion::{AxisLimits, FeedContext, Limits, Planned, Profile};

    /// A 10 mm move along X from `from`, a rapid or a feed.
    fn segment(from: f64, rapid: bool) -> Segment {
        let axes = AxisLimits { count: 3, v: [100.0; 8], a: [1000.0; 8], j: [20000.0; 8] };
        let ctx = FeedContext {
            feed_override: 1.0,
            rapid_override: 1.0,
            exact_stop: false,
            options: MotionOptions::default(),
        };
        let (mut a, mut b): (Pos, Pos) = ([0.0; 8], [0.0; 8]);
        (a[0], b[0]) = (from, from + 10.0);
        let m = Motion::straight(rapid, b, b, 3000.0);
        Segment::new(&m, &a, &a, &axes, ctx, None)
    }

    /// A run of two 10 mm segments from rest to rest is symmetric in time: the first half of
    /// its distance takes half its duration. Whichever of the two is the feed, the feed timer
    /// gets half; both feeds, all of it; both rapids, none.
    #[test]
    fn cutting_seconds_split_a_run_at_its_rapids() {
        let profile = Profile::plan(0.0, 0.0, 20.0, &Limits { v: 50.0, a: 1000.0, j: 20000.0 });
        let run = |first: bool, second: bool| {
            let planned =
                Planned { segments: vec![segment(0.0, first), segment(10.0, second)], profile: profile.clone() };
            cutting_seconds(&planned)
        };
        let whole = profile.duration();
        assert!(whole > 0.4, "{whole}");
        assert!((run(false, true) - whole / 2.0).abs() < 1e-9, "{} of {whole}", run(false, true));
        assert!((run(true, false) - whole / 2.0).abs() < 1e-9, "{} of {whole}", run(true, false));
        assert_eq!(run(false, false), whole);
        assert_eq!(run(true, true), 0.0);
    }
}
