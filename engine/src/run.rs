//! Running a program to its end: the interpreter's canonical commands go through the motion
//! planner (`crate::motion`: look-ahead, jerk-limited speed profiles, axis limits, stroke
//! check) and are sampled every interpolation period into the trace; the cycle time is the
//! simulated time including every acceleration.

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, Pos};
use crate::interp::{Interpreter, Step};
use crate::machine::MachineConfig;
use crate::motion::{self, AxisLimits, FeedContext, Planned, Planner, Segment};

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

/// One interpolation period of the trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub line: u32,
    pub n: Option<u32>,
    pub machine: Pos,
    /// Tool tip in the active workpiece system, from the machine axes and the tool length in
    /// effect by forward kinematics (`crate::tip`): where the machine puts it.
    pub tip: [f64; 3],
    /// Unit tool vector, tip toward holder, in the workpiece system (from the rotary axes).
    pub tool: [f64; 3],
    /// The commanded point (X, Y, Z) in the system `programmed_in` names.
    pub programmed: [f64; 3],
    pub programmed_in: crate::tip::System,
    /// Tool tip speed relative to the workpiece, mm/min.
    pub feed: f64,
}

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
    let machine = interp.config().machine.clone();
    let mut exec = Executor {
        // A mechanism the kinematics refuses still runs; its trace shows the tool along +Z.
        kinematics: interp.kinematics().cloned(),
        axes: AxisLimits::of(&machine),
        planner: motion::planner_for(&machine),
        machine_config: machine,
        t: 0.0,
        next_sample: 0,
        machine: interp.state.machine_position(),
        workpiece: interp.state.shown_position(),
        queued_machine: interp.state.machine_position(),
        queued_work: interp.state.shown_position(),
        basis: interp.state.tip_basis(),
        queued_basis: interp.state.tip_basis(),
        opts: *opts,
        messages: Vec::new(),
        over_budget: None,
        executed: 0,
        observer,
    };
    let tracing = opts.period_s > 0.0;
    let mut out = Vec::with_capacity(16);
    let mut alarms = Vec::new();
    let mut motion_alarm = false;
    loop {
        if exec.observer.stop() {
            break;
        }
        let step = interp.step(&mut out);
        let before = exec.t;
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
        interp.state.advance_time(exec.t - before);
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
    exec.drain(true, tracing, &mut on_sample);
    if let Some((line, n)) = exec.over_budget {
        // The run stopped there: a program error read ahead in a later block was never reached.
        let id = AlarmId::TimeBudgetExceeded { budget_s: opts.max_time_s };
        let (code, message) = interp.config().dialect.describe(&id);
        alarms = vec![Alarm { code, message, line, n }];
        motion_alarm = true;
    }
    let (machine, workpiece, basis) = if motion_alarm {
        (exec.machine, exec.workpiece, exec.basis)
    } else {
        (interp.state.machine_position(), interp.state.shown_position(), interp.state.tip_basis())
    };
    let tip = crate::tip::locate(exec.kinematics.as_deref(), &machine, &basis);
    let shown = &exec.machine_config;
    let (machine, workpiece) = (shown.shown(&machine), shown.shown(&workpiece));
    RunResult {
        alarms,
        blocks: interp.blocks(),
        cycle_time_s: exec.t,
        machine,
        workpiece,
        tip,
        programmed: [workpiece[0], workpiece[1], workpiece[2]],
        programmed_in: basis.programmed_in,
        variables: interp.state.common_variables(),
        messages: exec.messages,
    }
}

struct Executor<'o, O: Observer> {
    observer: &'o mut O,
    /// Segments executed to their end so far.
    executed: u64,
    kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
    machine_config: MachineConfig,
    axes: AxisLimits,
    planner: Planner,
    t: f64,
    /// Index of the next sample: sample k is at k × period.
    next_sample: u64,
    /// Where the machine is (the end of the last executed segment).
    machine: Pos,
    workpiece: Pos,
    /// Where the last queued segment ends.
    queued_machine: Pos,
    queued_work: Pos,
    /// How the tip is read while the machine stands (after the last executed segment or a
    /// command that waits).
    basis: crate::tip::Basis,
    /// The basis of the last queued motion.
    queued_basis: crate::tip::Basis,
    opts: RunOptions,
    messages: Vec<String>,
    /// The block during which simulated time ran past `max_time_s`; nothing runs after it.
    over_budget: Option<(u32, Option<u32>)>,
}

impl<O: Observer> Executor<'_, O> {
    fn apply(&mut self, c: &Canon, tracing: bool, on_sample: &mut impl FnMut(&Sample)) -> Result<(), AlarmId> {
        match &c.kind {
            CanonKind::Motion(m) => {
                self.express_start_in(&c.tip_basis);
                let ctx = FeedContext {
                    feed_override: self.opts.feed_override,
                    rapid_override: self.opts.rapid_override,
                    exact_stop: m.context.exact_stop,
                    options: self.machine_config.motion,
                };
                let mut seg =
                    Segment::new(m, &self.queued_machine, &self.queued_work, &self.axes, ctx, self.kinematics.as_ref());
                (seg.line, seg.n, seg.tip_basis) = (c.line, c.n, c.tip_basis);
                if let Err(id) = motion::stroke_check(&seg, &self.machine_config) {
                    // The machine stops at the end of the block before; the offending one never moves.
                    self.drain(true, tracing, on_sample);
                    return Err(id);
                }
                (self.queued_machine, self.queued_work) = (m.machine, m.target);
                self.observer.queued(m, &seg);
                self.planner.push(seg);
                self.drain(false, tracing, on_sample);
            }
            other => {
                // Every other command waits for the motion before it to end; the machine then
                // stands in the block's workpiece system with its tool length.
                self.drain(true, tracing, on_sample);
                self.basis = c.tip_basis;
                match other {
                    _ if self.over_budget.is_some() => {}
                    CanonKind::Dwell { seconds } => self.wait(*seconds, c, tracing, on_sample),
                    CanonKind::ToolChange { .. } => {
                        self.wait(self.machine_config.motion.tool_change_s, c, tracing, on_sample)
                    }
                    CanonKind::Print { text } => self.messages.push(text.clone()),
                    CanonKind::Stop { message: Some(m), .. } => self.messages.push(m.clone()),
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// A motion in another workpiece system (G54…, G10, G52, G92 changed since the last one,
    /// in its block or before) starts where the machine stands, expressed in the new system, as
    /// the interpreter's current point is: its programmed start moves by the origin's change.
    fn express_start_in(&mut self, basis: &crate::tip::Basis) {
        let before = std::mem::replace(&mut self.queued_basis, *basis);
        crate::tip::restate_start(&mut self.queued_work, &before, basis);
    }

    /// Stand still for `seconds` (a dwell, a tool change), sampling the trace.
    fn wait(&mut self, seconds: f64, c: &Canon, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        let end = (self.t + seconds).min(self.opts.max_time_s.max(self.t));
        if tracing {
            let (m0, w0) = (self.machine, self.workpiece);
            let (line, n) = (c.line, c.n);
            self.sample_until(end, &mut |_| (m0, w0, 0.0, line, n, None), on_sample);
        }
        if end < self.t + seconds {
            self.t = end;
            self.over_budget = Some((c.line, c.n));
            return;
        }
        self.t = end;
        self.check_budget(c.line, c.n);
    }

    /// Execute the segments whose speeds are final (`stop`: all, ending at rest).
    fn drain(&mut self, stop: bool, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        while let Some(p) = self.planner.pop(stop) {
            if self.over_budget.is_none() {
                self.execute(&p, tracing, on_sample);
            }
        }
    }

    fn execute(&mut self, p: &Planned, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        let Some(last) = p.segments.last() else { return };
        let t0 = self.t;
        // The run stops where the time budget runs out, even inside a segment.
        let t1 = (t0 + p.profile.duration()).min(self.opts.max_time_s.max(t0));
        let mut cursor = motion::Cursor::default();
        let done = self.executed;
        if tracing {
            self.sample_until(
                t1,
                &mut |dt| {
                    let at = p.point(dt, &mut cursor);
                    let on = &p.segments[cursor.index()];
                    let number = done + cursor.index() as u64;
                    (at.machine, at.work, at.feed, at.line, at.n, Some((on, at.s - cursor.start(), number)))
                },
                on_sample,
            );
        }
        if t1 < t0 + p.profile.duration() {
            let mut cursor = motion::Cursor::default();
            let at = p.point(t1 - t0, &mut cursor);
            (self.t, self.machine, self.workpiece) = (t1, at.machine, at.work);
            self.basis = p.segments[cursor.index()].tip_basis;
            self.over_budget = Some((at.line, at.n));
            return;
        }
        for seg in &p.segments {
            self.observer.executed(seg);
        }
        self.executed += p.segments.len() as u64;
        self.t = t1;
        self.machine = last.to;
        self.workpiece = last.work_to;
        self.basis = last.tip_basis;
        self.check_budget(last.line, last.n);
    }

    fn check_budget(&mut self, line: u32, n: Option<u32>) {
        if self.t > self.opts.max_time_s && self.over_budget.is_none() {
            self.over_budget = Some((line, n));
        }
    }

    /// Samples from the current time to `t1`; `at(dt)` gives machine and programming position,
    /// tip feed (mm/min), line and sequence number `dt` seconds after the current time, and the
    /// segment there with the distance along it.
    fn sample_until<'s>(
        &mut self,
        t1: f64,
        at: &mut impl FnMut(f64) -> (Pos, Pos, f64, u32, Option<u32>, Option<(&'s Segment, f64, u64)>),
        on_sample: &mut impl FnMut(&Sample),
    ) {
        let t0 = self.t;
        loop {
            let ts = self.next_sample as f64 * self.opts.period_s;
            if ts > t1 || (ts > t0 && t1 == t0) || self.observer.stop() {
                return;
            }
            let (raw, work, feed, line, n, on) = at((ts - t0).max(0.0));
            // The segment's tool length and workpiece system; standing still, the last ones.
            let basis = on.map_or(&self.basis, |(seg, _, _)| &seg.tip_basis);
            let placed = crate::tip::locate(self.kinematics.as_deref(), &raw, basis);
            let machine = self.machine_config.shown(&raw);
            let sample = Sample {
                t: ts,
                line,
                n,
                machine,
                tip: placed.tip,
                tool: placed.tool,
                programmed: [work[0], work[1], work[2]],
                programmed_in: basis.programmed_in,
                feed,
            };
            on_sample(&sample);
            self.observer.sample(&sample, &raw, on);
            self.next_sample += 1;
        }
    }
}
