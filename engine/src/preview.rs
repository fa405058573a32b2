//! The tool path a program asks for, as a display draws it: the tool tip in the table frame
//! (where the tip is relative to the part on its table, `docs/machine-config.md`) through every
//! motion, without timing: the executor's segment geometry, never planned. The interpreter runs
//! ahead on its own; nothing moves.
//!
//! Straight moves are their two ends; arcs, moves that turn a rotary axis and moves along a
//! tool tip path (TCP, tilted planes) are sampled at most every [`STEP`] mm (or degrees) of
//! their path parameter, so a rotary move without TCP shows the curve the tip really makes.

use crate::alarm::Alarm;
use crate::canon::{CanonKind, MotionKind, Pos};
use crate::interp::{Interpreter, Step};
use crate::machine::AxisKind;
use crate::motion::{Endpoint, Executor};

/// Largest path-parameter step between samples of a curved move, mm or degrees.
pub const STEP: f64 = 1.0;
/// Most samples of one move.
const MAX_PER_MOVE: usize = 256;

/// The programmed tool tip path.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ToolPath {
    /// Tip positions in the table frame, in program order; the first is where the run starts.
    pub points: Vec<[f64; 3]>,
    /// Per point: the 1-based line of the block that moves to it (0 for the start).
    pub lines: Vec<u32>,
    /// Per point: the move to it is a rapid.
    pub rapid: Vec<bool>,
    /// The path stopped early: the program's alarm, or `max_points` was reached (`truncated`).
    pub alarm: Option<Alarm>,
    pub truncated: bool,
}

/// Runs `interp` (already loaded, in its start state) to its end and returns the tip path, at
/// most `max_points` points.
pub fn tool_path(interp: &mut Interpreter, max_points: usize) -> ToolPath {
    let machine = interp.config().machine.clone();
    let rotary: Vec<bool> = machine.axes.iter().map(|a| a.kind == AxisKind::Rotary).collect();
    let start = Endpoint {
        machine: interp.state.machine_position(),
        work: interp.state.position(),
        basis: interp.state.tip_basis(),
    };
    let mut exec = Executor::new(machine, start);
    let mut stages = crate::stage::Pipeline::for_config(interp.config());
    let ctx = exec.feed_context(1.0, 1.0, false);
    let tip = |exec: &Executor, pos: &Pos, length: f64| -> [f64; 3] {
        match exec.kinematics() {
            Some(k) => k.forward(pos, length).tip.into(),
            None => [pos[0], pos[1], pos[2] - length],
        }
    };
    let mut path = ToolPath::default();
    let push = |path: &mut ToolPath, p: [f64; 3], line: u32, rapid: bool| -> bool {
        if path.points.len() >= max_points {
            path.truncated = true;
            return false;
        }
        path.points.push(p);
        path.lines.push(line);
        path.rapid.push(rapid);
        true
    };
    push(&mut path, tip(&exec, &start.machine, 0.0), 0, true);
    let mut out = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let stage_alarm = stages.process(&mut out, crate::run::ends(&step));
        for c in out.drain(..) {
            let CanonKind::Motion(m) = &c.kind else { continue };
            let rapid = matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid);
            let from = exec.queued.machine;
            let turns = rotary.iter().enumerate().any(|(i, &r)| r && (m.machine[i] - from[i]).abs() > 1e-9);
            let length = m.context.tool_length;
            let seg = exec.geometry(&c, m, ctx);
            if m.arc.is_some() || m.tip.is_some() || turns {
                let n = ((seg.len / STEP).ceil() as usize).clamp(1, MAX_PER_MOVE);
                for k in 1..=n {
                    let (pos, _) = seg.at(seg.len * k as f64 / n as f64);
                    if !push(&mut path, tip(&exec, &pos, length), c.line, rapid) {
                        return path;
                    }
                }
            } else if !push(&mut path, tip(&exec, &m.machine, length), c.line, rapid) {
                return path;
            }
        }
        if stage_alarm.is_some() {
            path.alarm = stage_alarm;
            return path;
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return path,
            Err(alarm) => {
                path.alarm = Some(alarm);
                return path;
            }
        }
    }
}
