//! The tool path a program asks for, as a display draws it: the tool tip in the table frame
//! (where the tip is relative to the part on its table, `docs/machine-config.md`) through every
//! motion, without timing. The interpreter runs ahead on its own; nothing moves.
//!
//! Straight moves are their two ends; arcs, moves that turn a rotary axis and moves along a
//! tool tip path (TCP, tilted planes) are sampled at most every [`STEP`] mm (or degrees) of
//! their path parameter, so a rotary move without TCP shows the curve the tip really makes.

use crate::alarm::Alarm;
use crate::canon::{CanonKind, MotionKind, Pos};
use crate::interp::{Interpreter, Step};
use crate::machine::AxisKind;
use crate::motion::{AxisLimits, FeedContext, Segment};

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
    let kin = interp.kinematics().cloned();
    let axes = AxisLimits::of(&machine);
    let rotary: Vec<bool> = machine.axes.iter().map(|a| a.kind == AxisKind::Rotary).collect();
    let ctx = FeedContext { feed_override: 1.0, rapid_override: 1.0, exact_stop: false, options: machine.motion };
    let tip = |pos: &Pos, length: f64| -> [f64; 3] {
        match &kin {
            Some(k) => k.forward(pos, length).tip.into(),
            None => [pos[0], pos[1], pos[2] - length],
        }
    };
    let mut from_machine = interp.state.machine_position();
    let mut from_work = interp.state.position();
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
    push(&mut path, tip(&from_machine, 0.0), 0, true);
    let mut out = Vec::new();
    loop {
        let step = interp.step(&mut out);
        for c in out.drain(..) {
            let CanonKind::Motion(m) = &c.kind else { continue };
            let rapid = matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid);
            let turns = (0..machine.axes.len()).any(|i| rotary[i] && (m.machine[i] - from_machine[i]).abs() > 1e-9);
            let length = m.context.tool_length;
            if m.arc.is_some() || m.tip.is_some() || turns {
                let seg = Segment::new(m, &from_machine, &from_work, &axes, ctx, kin.as_ref());
                let n = ((seg.len / STEP).ceil() as usize).clamp(1, MAX_PER_MOVE);
                for k in 1..=n {
                    let (pos, _) = seg.at(seg.len * k as f64 / n as f64);
                    if !push(&mut path, tip(&pos, length), c.line, rapid) {
                        return path;
                    }
                }
            } else if !push(&mut path, tip(&m.machine, length), c.line, rapid) {
                return path;
            }
            (from_machine, from_work) = (m.machine, m.target);
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
