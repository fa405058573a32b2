//! Ideal execution: motion goes straight to each end point (arcs along their circle) at the
//! programmed feed, so cycle time is path length / feed. The motion issues replace this with
//! look-ahead and jerk-limited interpolation; positions and system variables are already exact.

use crate::alarm::{Alarm, AlarmId};
use crate::canon::{Canon, CanonKind, FeedMode, Motion, MotionKind, Pos};
use crate::interp::{Interpreter, Step};
use crate::machine::MAX_AXES;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// Interpolation (sampling) period, seconds.
    pub period_s: f64,
    /// Simulated seconds after which the run stops with an alarm.
    pub max_time_s: f64,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions { period_s: 0.001, max_time_s: 1.0e6 }
    }
}

/// One interpolation period of the trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub line: u32,
    pub n: Option<u32>,
    pub machine: Pos,
    /// Tool tip in the active workpiece system (the programmed point: ideal compensation).
    pub tip: [f64; 3],
    /// Unit tool vector, tip toward holder, in the workpiece system (from the rotary axes).
    pub tool: [f64; 3],
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

/// Run the program to its end, calling `on_sample` for every interpolation period.
pub fn run(interp: &mut Interpreter, opts: &RunOptions, mut on_sample: impl FnMut(&Sample)) -> RunResult {
    let mut rapid = [0.0; MAX_AXES];
    for (r, axis) in rapid.iter_mut().zip(&interp.config().machine.axes) {
        *r = axis.rapid;
    }
    let mut exec = Executor {
        // A mechanism the kinematics refuses still runs (issue-2 ideal motion); its trace shows
        // the tool along +Z.
        kinematics: crate::kin::Kinematics::new(&interp.config().machine).ok(),
        rapid,
        t: 0.0,
        next_sample: 0,
        machine: interp.state.machine_position(),
        workpiece: interp.state.position(),
        opts: *opts,
        messages: Vec::new(),
    };
    let tracing = opts.period_s > 0.0;
    let mut out = Vec::with_capacity(16);
    let mut alarms = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let before = exec.t;
        for c in out.drain(..) {
            exec.apply(&c, tracing, &mut on_sample);
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
        if exec.t > opts.max_time_s {
            let id = AlarmId::TimeBudgetExceeded { budget_s: opts.max_time_s };
            let (code, message) = interp.config().dialect.describe(&id);
            let (line, n) = interp.state.current_block();
            alarms.push(Alarm { code, message, line, n });
            break;
        }
    }
    RunResult {
        alarms,
        blocks: interp.blocks(),
        cycle_time_s: exec.t,
        machine: interp.state.machine_position(),
        workpiece: interp.state.position(),
        variables: interp.state.common_variables(),
        messages: exec.messages,
    }
}

struct Executor {
    kinematics: Option<crate::kin::Kinematics>,
    /// Rapid rate per axis, mm/min or deg/min.
    rapid: Pos,
    t: f64,
    /// Index of the next sample: sample k is at k × period.
    next_sample: u64,
    machine: Pos,
    workpiece: Pos,
    opts: RunOptions,
    messages: Vec<String>,
}

impl Executor {
    fn apply(&mut self, c: &Canon, tracing: bool, on_sample: &mut impl FnMut(&Sample)) {
        match &c.kind {
            CanonKind::Motion(m) => {
                let (duration, length) = duration(m, &self.machine, &self.rapid);
                let feed = if duration > 0.0 { length / duration * 60.0 } else { 0.0 };
                if tracing {
                    let (m0, w0) = (self.machine, self.workpiece);
                    self.sample_until(self.t + duration, c, on_sample, |u| interpolate(m, &m0, &w0, u), feed);
                }
                self.t += duration;
                self.machine = m.machine;
                self.workpiece = m.target;
            }
            CanonKind::Dwell { seconds } => {
                if tracing {
                    let (m0, w0) = (self.machine, self.workpiece);
                    self.sample_until(self.t + seconds, c, on_sample, |_| (m0, w0), 0.0);
                }
                self.t += seconds;
            }
            CanonKind::Print { text } => self.messages.push(text.clone()),
            CanonKind::Stop { message: Some(m), .. } => self.messages.push(m.clone()),
            _ => {}
        }
    }

    fn sample_until(
        &mut self,
        t1: f64,
        c: &Canon,
        on_sample: &mut impl FnMut(&Sample),
        at: impl Fn(f64) -> (Pos, Pos),
        feed: f64,
    ) {
        let t0 = self.t;
        loop {
            let ts = self.next_sample as f64 * self.opts.period_s;
            if ts > t1 || (ts > t0 && t1 == t0) {
                return;
            }
            let u = if t1 > t0 { ((ts - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
            let (machine, work) = at(u);
            let tool = self.kinematics.as_ref().map_or([0.0, 0.0, 1.0], |k| k.forward(&machine, 0.0).tool.into());
            on_sample(&Sample { t: ts, line: c.line, n: c.n, machine, tip: [work[0], work[1], work[2]], tool, feed });
            self.next_sample += 1;
        }
    }
}

/// Duration (s) and tool path length (mm, degrees counted as mm) of a motion.
fn duration(m: &Motion, from: &Pos, rapid: &Pos) -> (f64, f64) {
    let mut delta = [0.0; MAX_AXES];
    for (i, d) in delta.iter_mut().enumerate() {
        *d = m.machine[i] - from[i];
    }
    let straight = delta.iter().map(|d| d * d).sum::<f64>().sqrt();
    let length = match &m.arc {
        Some(arc) => {
            let arc_len = arc.radius * arc.sweep_deg.abs().to_radians();
            let (a, b, _) = arc.plane_axes;
            let helix: f64 = (0..MAX_AXES).filter(|&i| i != a && i != b).map(|i| delta[i] * delta[i]).sum();
            (arc_len * arc_len + helix).sqrt()
        }
        None => straight,
    };
    let minutes = match m.kind {
        MotionKind::Rapid | MotionKind::MachineRapid => {
            // Every axis at its own rapid rate; the slowest decides.
            rapid.iter().zip(&delta).map(|(r, d)| if *r > 0.0 { d.abs() / r } else { 0.0 }).fold(0.0, f64::max)
        }
        _ => match m.feed_mode {
            FeedMode::InverseTime => {
                if m.feed > 0.0 {
                    1.0 / m.feed
                } else {
                    0.0
                }
            }
            FeedMode::PerMinute => length / m.feed.max(f64::MIN_POSITIVE),
            FeedMode::PerRevolution => length / (m.feed * m.spindle).max(f64::MIN_POSITIVE),
        },
    };
    (minutes * 60.0, length)
}

/// Machine and workpiece position at fraction `u` of a motion.
fn interpolate(m: &Motion, m0: &Pos, w0: &Pos, u: f64) -> (Pos, Pos) {
    let mut machine = [0.0; MAX_AXES];
    let mut work = [0.0; MAX_AXES];
    for i in 0..MAX_AXES {
        machine[i] = m0[i] + (m.machine[i] - m0[i]) * u;
        work[i] = w0[i] + (m.target[i] - w0[i]) * u;
    }
    if let Some(arc) = &m.arc {
        let (a, b, _) = arc.plane_axes;
        let start = (w0[b] - arc.center[b]).atan2(w0[a] - arc.center[a]);
        let angle = start + arc.sweep_deg.to_radians() * u;
        let (x, y) = (arc.center[a] + arc.radius * angle.cos(), arc.center[b] + arc.radius * angle.sin());
        // Offsets are constant along an arc: machine = work + (end offset).
        machine[a] = x + (m.machine[a] - m.target[a]);
        machine[b] = y + (m.machine[b] - m.target[b]);
        work[a] = x;
        work[b] = y;
    }
    (machine, work)
}
