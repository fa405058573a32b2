//! The tool path a program asks for, as a display draws it: the tool tip in the table frame
//! (where the tip is relative to the part on its table, `docs/machine-config.md`) through every
//! motion, without timing: the executor's segment geometry, never planned. The interpreter runs
//! ahead on its own; nothing moves.
//!
//! Straight moves are their two ends; arcs, moves that turn a rotary axis and moves along a
//! tool tip path (TCP, tilted planes) are sampled at most every [`STEP`] mm (or degrees) of
//! their path parameter, so a rotary move without TCP shows the curve the tip really makes.
//!
//! The path is the one the machine would move: after the path stages, so under cutter
//! compensation (G41/G42, and the 5-axis G41.2…G42.6, G41.3) it is the tool centre's. Once compensation has been in force, the
//! programmed path — the interpreter's commands before the stages, the contour as written — comes
//! beside it ([`ToolPath::programmed`]), so a display can draw both.

use crate::alarm::Alarm;
use crate::canon::{Canon, CanonKind, MotionKind, Pos};
use crate::interp::gcode::{code, group};
use crate::interp::{Interpreter, Step};
use crate::machine::AxisKind;
use crate::motion::{Endpoint, Executor, FeedContext};

/// Largest path-parameter step between samples of a curved move, mm or degrees.
pub const STEP: f64 = 1.0;
/// Most samples of one move.
const MAX_PER_MOVE: usize = 256;

/// Points of a path in program order, as a display draws them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Polyline {
    /// Tip positions in the table frame; the first is where the run starts.
    pub points: Vec<[f64; 3]>,
    /// Per point: the 1-based line of the block that moves to it (0 for the start).
    pub lines: Vec<u32>,
    /// Per point: the move to it is a rapid.
    pub rapid: Vec<bool>,
}

/// The tool tip path a program asks for.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ToolPath {
    /// Tip positions in the table frame, in program order; the first is where the run starts.
    /// After the path stages: where the tool centre goes (compensated under G41/G42 and the
    /// 5-axis compensations).
    pub points: Vec<[f64; 3]>,
    /// Per point: the 1-based line of the block that moves to it (0 for the start).
    pub lines: Vec<u32>,
    /// Per point: the move to it is a rapid.
    pub rapid: Vec<bool>,
    /// The path stopped early: the program's alarm, or `max_points` was reached (`truncated`).
    pub alarm: Option<Alarm>,
    pub truncated: bool,
    /// When cutter compensation was in force somewhere: the programmed path, the interpreter's
    /// commands before the path stages, from the same start (equal to the path above until
    /// compensation starts). It goes as far as the interpreter read — the blocks a stage held
    /// when it stopped with an alarm included — and to at most `max_points` points (`truncated`
    /// is set when it was cut there too). `None` without compensation: the path is the
    /// programmed one.
    pub programmed: Option<Polyline>,
}

/// Where the tip is at `pos` with tool length `length`.
fn tip(exec: &Executor, pos: &Pos, length: f64) -> [f64; 3] {
    match exec.kinematics() {
        Some(k) => k.forward(pos, length).tip.into(),
        None => [pos[0], pos[1], pos[2] - length],
    }
}

/// Adds command `c`'s motion (if it is one) to `line` through `exec`'s geometry; `false` when
/// `max_points` was reached (the point that did not fit is not added).
fn draw(exec: &mut Executor, c: &Canon, rotary: &[bool], ctx: FeedContext, line: &mut Polyline, max: usize) -> bool {
    let CanonKind::Motion(m) = &c.kind else { return true };
    let rapid = matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid);
    let from = exec.queued.machine;
    let turns = rotary.iter().enumerate().any(|(i, &r)| r && (m.machine[i] - from[i]).abs() > 1e-9);
    let length = m.context.tool_length;
    let seg = exec.geometry(c, m, ctx);
    let mut push = |p: [f64; 3]| -> bool {
        if line.points.len() >= max {
            return false;
        }
        line.points.push(p);
        line.lines.push(c.line);
        line.rapid.push(rapid);
        true
    };
    if m.arc.is_some() || m.tip.is_some() || turns {
        let n = ((seg.len / STEP).ceil() as usize).clamp(1, MAX_PER_MOVE);
        for k in 1..=n {
            let (pos, _) = seg.at(seg.len * k as f64 / n as f64);
            if !push(tip(exec, &pos, length)) {
                return false;
            }
        }
        true
    } else {
        push(tip(exec, &m.machine, length))
    }
}

/// Runs `interp` (already loaded, in its start state) to its end and returns the tip path, at
/// most `max_points` points (each of the two paths).
pub fn tool_path(interp: &mut Interpreter, max_points: usize) -> ToolPath {
    let machine = interp.config().machine.clone();
    let rotary: Vec<bool> = machine.axes.iter().map(|a| a.kind == AxisKind::Rotary).collect();
    let start = Endpoint {
        machine: interp.state.machine_position(),
        work: interp.state.position(),
        basis: interp.state.tip_basis(),
    };
    let mut exec = Executor::new(machine.clone(), start);
    let mut stages = crate::stage::Pipeline::for_config(interp.config());
    let ctx = exec.feed_context(1.0, 1.0, false);
    let mut main = Polyline::default();
    let mut path = ToolPath::default();
    // The programmed path's own executor, from where the paths part: made when compensation
    // first comes into force (until then the stages hand on what they take, unchanged).
    let mut programmed: Option<(Executor, Polyline, bool)> = None;
    let finish = |mut path: ToolPath, main: Polyline, programmed: Option<(Executor, Polyline, bool)>| {
        (path.points, path.lines, path.rapid) = (main.points, main.lines, main.rapid);
        if let Some((_, line, full)) = programmed {
            path.truncated |= full;
            path.programmed = Some(line);
        }
        path
    };
    let first = tip(&exec, &start.machine, 0.0);
    if max_points == 0 {
        path.truncated = true;
        return path;
    }
    (main.points, main.lines, main.rapid) = (vec![first], vec![0], vec![true]);
    let mut out = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let mode = interp.state.modal(group::CUTTER_COMP);
        if programmed.is_none() && code::COMPENSATED_BY_STAGES.contains(&mode) {
            let exec = Executor::new(machine.clone(), exec.queued);
            programmed = Some((exec, main.clone(), false));
        }
        if let Some((exec, line, full)) = &mut programmed {
            for c in out.iter() {
                if !*full && !draw(exec, c, &rotary, ctx, line, max_points) {
                    *full = true;
                }
            }
        }
        let stage_alarm = stages.process(&mut out, crate::run::ends(&step));
        for c in out.drain(..) {
            if !draw(&mut exec, &c, &rotary, ctx, &mut main, max_points) {
                path.truncated = true;
                return finish(path, main, programmed);
            }
        }
        if stage_alarm.is_some() {
            path.alarm = stage_alarm;
            return finish(path, main, programmed);
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return finish(path, main, programmed),
            Err(alarm) => {
                path.alarm = Some(alarm);
                return finish(path, main, programmed);
            }
        }
    }
}
