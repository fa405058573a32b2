//! Leading edge offset of 5-axis cutter compensation (FANUC G41.3 … G40) on a machine whose
//! rotary axes turn the tool: at the end of each block n the tool centre is moved by
//! VC_n = R·n((VM_{n+1} × VT_n) × VT_n), perpendicular to the tool VT_n there, in the plane of
//! the tool and the next block's move VM_{n+1} — against that move's part across the tool, so
//! that the tool's edge, not its centre, is on the programmed point (FANUC 5-axis manual §3.1.3–
//! §3.1.4). Rules, decisions and what is still refused: `docs/cutter-compensation.md`,
//! "Leading edge offset".
//!
//! The stage holds each block that moves until the next block that moves has come (one block
//! without movement between them is looked over, two or more keep the vector before), then
//! hands it on ending at its vector; the blocks without movement behind it keep that vector.
//! The G41.3 block moves by the first vector (made with the tool at G41.3 and the first block's
//! move) when that block comes; the G40 block moves back by the last one, made with the last
//! block's own move. Only straight moves are compensated (the mode allows G00/G01 only, the
//! interlocks of `interp::modes`), on machines without a rotary table, so programming, table
//! and machine coordinates differ by a rotation and a translation that the block carries
//! (`TipMove::frame` under TCP): `stage::tool_shift`, shared with `stage::tool_side`.

use super::tool_shift::ToolShift;
use super::{Link, PerpendicularStart, Stage};
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, MotionKind, Pos, Touch};
use crate::interp::gcode::code;
use crate::interp::Config;
use crate::kin::Vec3;

/// A move shorter than this (X/Y/Z) does not move (mm): a block without movement.
const NO_MOVE: f64 = 1e-9;

/// Directions computed from rotary angles are not exact: an angle this close (degrees) to 0°,
/// 90° or 180° is that angle whatever Δθ is.
const ANGLE_EPS_DEG: f64 = 1e-7;

/// How the angle θ between the tool and the next move counts (FANUC 5-axis manual §3.1.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Theta {
    /// 0° or 180°: the move runs along the tool; no plane (PS5408 at start-up, else the vector
    /// before is kept).
    Along,
    /// 90°: the vector's sign follows the vector before.
    Across,
    /// Any other angle: the vector of the formula.
    Normal,
}

/// θ (degrees, 0…180) classed with the fluctuation `delta` (No.19631): 0 ≤ θ ≤ Δθ is 0°,
/// 180 − Δθ ≤ θ ≤ 180 is 180°, 90 − Δθ ≤ θ ≤ 90 + Δθ is 90°, in the manual's order.
pub fn classify(theta: f64, delta: f64) -> Theta {
    let d = delta.max(0.0) + ANGLE_EPS_DEG;
    if theta <= d || theta >= 180.0 - d {
        Theta::Along
    } else if (theta - 90.0).abs() <= d {
        Theta::Across
    } else {
        Theta::Normal
    }
}

/// The angle between the tool and a move, degrees (0 for no move).
fn theta(tool: Vec3, mv: Vec3) -> f64 {
    tool.cross(&mv).norm().atan2(tool.dot(&mv)).to_degrees()
}

/// The manual's vector at a block end, before the sign: (VM × VT) × VT.
fn direction(tool: Vec3, mv: Vec3) -> Vec3 {
    mv.cross(&tool).cross(&tool)
}

/// The vector made last, and the tool at the end of its block (for the 90° rule).
#[derive(Debug, Clone, Copy)]
pub struct Previous {
    pub vc: Vec3,
    pub tool: Vec3,
}

/// The vector VC_n at the end of block n: `tool` VT_n, `next` the move it is made with
/// (VM_{n+1}, or the block's own before G40), `own` the block's own move VM_n (the 90° rule
/// compares the vector before with (VM_n × VT_{n−1}) × VT_{n−1}), `r` the offset value.
/// `None`: θ counts as 0° or 180° (or there is no move): no vector of its own.
/// `delta`: Δθ of [`classify`] (`five_axis.leading_edge_tolerance`, No.19631; the manual gives
/// no default, a cleared parameter is 0: only the exact angles count).
pub fn vector(r: f64, tool: Vec3, next: Vec3, own: Vec3, previous: Option<Previous>, delta: f64) -> Option<Vec3> {
    if next.norm() <= NO_MOVE {
        return None;
    }
    let class = classify(theta(tool, next), delta);
    if class == Theta::Along {
        return None;
    }
    let vc = direction(tool, next).normalize() * r;
    // 90°: the vector points the way the vector before pointed, measured against the formula
    // the vector before would have had with this block's move (times R: a negative offset
    // value flips both, not the sign). Without a vector before, or without that direction: +.
    let flipped = class == Theta::Across
        && previous.is_some_and(|p| {
            let d = direction(p.tool, own) * r;
            d.norm() > NO_MOVE && p.vc.dot(&d.normalize()) < -NO_MOVE
        });
    Some(if flipped { -vc } else { vc })
}

/// A block that moves, waiting for the next block that moves.
struct Waiting {
    canon: Canon,
    /// Its move VM (programming coordinates), the tool at its end, its offset value.
    mv: Vec3,
    tool: Vec3,
    r: f64,
}

/// The G41.3 block: where the path and the machine stood, its line.
struct Startup {
    pos: Pos,
    machine: Pos,
    block: Option<PerpendicularStart>,
}

/// The leading edge offset stage.
pub struct LeadingEdge {
    /// The tool, and the vector where it stands.
    shift: ToolShift,
    link: Link,
    on: bool,
    /// The programmed end of the last motion while on.
    programmed: Vec3,
    previous: Option<Previous>,
    startup: Option<Startup>,
    waiting: Option<Waiting>,
    /// The commands after `waiting` (blocks without movement).
    after: Vec<Canon>,
    stopped: bool,
    alarm: Option<(AlarmId, u32, Option<u32>)>,
    /// Δθ of the θ classes (`five_axis.leading_edge_tolerance`, No.19631), degrees.
    delta_theta: f64,
    /// `Config::refuse_unbuilt` (off: the stage hands everything on as it comes, for the tests
    /// of the mode interlocks).
    refuse: bool,
}

impl LeadingEdge {
    pub fn new(config: &Config) -> LeadingEdge {
        let m = &config.machine;
        LeadingEdge {
            shift: ToolShift::new(m, Touch::LeadingEdge),
            link: config.stages.share(),
            on: false,
            programmed: Vec3::zeros(),
            previous: None,
            startup: None,
            waiting: None,
            after: Vec::new(),
            stopped: false,
            alarm: None,
            delta_theta: m.five_axis.leading_edge_tolerance,
            refuse: config.refuse_unbuilt,
        }
    }

    fn alarm(&mut self, id: AlarmId, c: &Canon) {
        self.alarm.get_or_insert((id, c.line, c.n));
        self.stopped = true;
        self.waiting = None;
        self.after.clear();
    }

    /// The vector kept where a block makes none of its own.
    fn kept(&self) -> Vec3 {
        self.previous.map_or(self.shift.vector, |p| p.vc)
    }

    /// Hand on the waiting block ending at `vc`, then the commands held behind it at `vc`.
    fn release(&mut self, vc: Vec3, out: &mut Vec<Canon>) {
        let Some(w) = self.waiting.take() else { return };
        let c = self.shift.placed(w.canon, vc);
        out.push(c);
        for c in std::mem::take(&mut self.after) {
            let c = self.shift.placed(c, vc);
            out.push(c);
        }
        self.previous = Some(Previous { vc, tool: w.tool });
    }

    /// The mode ends (G40, M02/M30, another compensation, the end of the program): the block
    /// waiting is the block before G40, its vector is made with its own move (CRC-26).
    fn end_mode(&mut self, out: &mut Vec<Canon>) {
        if let Some(w) = &self.waiting {
            let vc = vector(w.r, w.tool, w.mv, w.mv, self.previous, self.delta_theta).unwrap_or_else(|| self.kept());
            self.release(vc, out);
        }
        for c in std::mem::take(&mut self.after) {
            let c = self.shift.placed(c, self.shift.vector);
            out.push(c);
        }
        self.startup = None;
    }

    fn cancelled(&mut self) {
        self.on = false;
        self.shift.vector = Vec3::zeros();
        self.previous = None;
        self.startup = None;
    }

    /// Two or more blocks without movement after the waiting block: it keeps the vector before
    /// it (CRC-25), and so do they.
    fn keep_vector_if_too_many(&mut self, out: &mut Vec<Canon>) {
        let Some(w) = &self.waiting else { return };
        if super::blocks_without_motion(&self.after, w.canon.line) >= 2 {
            let vc = self.kept();
            self.release(vc, out);
        }
    }

    fn motion(&mut self, c: Canon, out: &mut Vec<Canon>) {
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let lead = m.context.cutter_comp == code::G41_3;
        if !self.on && !lead {
            out.push(c);
            return;
        }
        if m.arc.is_some() || m.kind == MotionKind::MachineRapid || m.tip.as_ref().is_some_and(|t| t.arc.is_some()) {
            // The mode interlocks refuse these (G00/G01 only); never shift them blindly.
            self.alarm(AlarmId::GCodeNotBuilt, &c);
            return;
        }
        if !lead {
            // G40 (or another mode): the block before ends at its own vector, this block
            // moves back to the programmed path.
            self.end_mode(out);
            let c = self.shift.placed(c, Vec3::zeros());
            out.push(c);
            self.cancelled();
            return;
        }
        if !self.on {
            let Some(s) = self.link.take_comp_start() else {
                // G41.3 not started from G40 (the interlocks forbid it): nothing to start from.
                self.alarm(AlarmId::GCodeNotBuilt, &c);
                return;
            };
            self.on = true;
            self.shift.vector = Vec3::zeros();
            self.previous = None;
            self.programmed = self.shift.xyz(&s.pos);
            self.startup = Some(Startup { pos: s.pos, machine: s.machine, block: s.perpendicular });
        }
        let from = self.programmed;
        let to = self.shift.xyz(&m.target);
        let mv = to - from;
        if mv.norm() <= NO_MOVE {
            if self.startup.is_some() {
                // The block after G41.3 must move, not along the tool (a rotary axis alone
                // does not): no plane for the first vector.
                self.alarm(AlarmId::LeadingEdgeAlongTool, &c);
            } else if self.waiting.is_some() {
                self.after.push(c);
                self.keep_vector_if_too_many(out);
            } else {
                let c = self.shift.placed(c, self.shift.vector);
                out.push(c);
            }
            return;
        }
        self.programmed = to;
        let (tool, r) = (self.shift.tool(m, &m.machine), m.context.cutter_radius);
        if let Some(s) = self.startup.take() {
            // Start-up (CRC-22): the tool at G41.3 and this block's move.
            let tool0 = self.shift.tool(m, &s.machine);
            let Some(vc) = vector(r, tool0, mv, mv, None, self.delta_theta) else {
                self.alarm(AlarmId::LeadingEdgeAlongTool, &c);
                return;
            };
            // The move of the G41.3 block (`ToolShift::startup_move`).
            let inserted = self.shift.startup_move(&c, s.pos, s.machine, s.block, vc);
            out.push(inserted);
            for c in std::mem::take(&mut self.after) {
                let c = self.shift.placed(c, vc);
                out.push(c);
            }
            self.previous = Some(Previous { vc, tool: tool0 });
        } else if let Some(w) = &self.waiting {
            // The block before ends at its vector with this block's move (CRC-23; one block
            // without movement between them is looked over, CRC-25).
            let vc = vector(w.r, w.tool, mv, w.mv, self.previous, self.delta_theta).unwrap_or_else(|| self.kept());
            self.release(vc, out);
        }
        self.waiting = Some(Waiting { canon: c, mv, tool, r });
    }
}

impl Stage for LeadingEdge {
    fn push(&mut self, command: Canon, out: &mut Vec<Canon>) {
        if self.stopped {
            return;
        }
        match &command.kind {
            _ if !self.refuse => out.push(command),
            CanonKind::Motion(_) => self.motion(command, out),
            CanonKind::ProgramEnd { .. } if self.on => {
                // M02/M30 end the mode: the last block ends at its own vector, which stays.
                self.end_mode(out);
                self.cancelled();
                out.push(command);
            }
            _ if self.waiting.is_some() => {
                self.after.push(command);
                self.keep_vector_if_too_many(out);
            }
            _ if self.on => {
                let c = self.shift.placed(command, self.shift.vector);
                out.push(c);
            }
            _ => out.push(command),
        }
    }

    fn finish(&mut self, out: &mut Vec<Canon>) {
        if !self.stopped {
            self.end_mode(out);
        }
    }

    fn take_alarm(&mut self) -> Option<(AlarmId, u32, Option<u32>)> {
        self.alarm.take()
    }

    fn passes(&self, command: &Canon) -> bool {
        let idle = !self.on && self.waiting.is_none() && self.startup.is_none() && !self.stopped;
        idle && !matches!(&command.kind, CanonKind::Motion(m) if m.context.cutter_comp == code::G41_3)
    }

    fn reset(&mut self) {
        self.cancelled();
        self.shift.reset();
        self.waiting = None;
        self.after.clear();
        self.stopped = false;
        self.alarm = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Vec3, b: [f64; 3]) -> bool {
        (a - Vec3::from(b)).norm() < 1e-6
    }

    #[test]
    fn tv10_the_vector_of_the_formula() {
        let (s, c) = (0.5, 0.75f64.sqrt());
        let x = Vec3::new(1.0, 0.0, 0.0);
        let cases = [
            (Vec3::new(s, 0.0, c), x, 10.0, [-8.660254, 0.0, 5.0]),
            (Vec3::new(-s, 0.0, c), x, 10.0, [-8.660254, 0.0, -5.0]),
            (Vec3::z(), Vec3::new(100.0, 0.0, -50.0), 10.0, [-10.0, 0.0, 0.0]),
            (Vec3::z(), x, 5.0, [-5.0, 0.0, 0.0]),
        ];
        for (tool, mv, r, want) in cases {
            let got = vector(r, tool, mv, mv, None, 0.0).unwrap();
            assert!(near(got, want), "{tool:?} {mv:?}: {got:?}");
        }
        // 90° after a vector that pointed the other way (+(VM_n × VT_{n−1}) × VT_{n−1} negated):
        // the sign follows it.
        let before = Previous { vc: Vec3::new(5.0, 0.0, 0.0), tool: Vec3::z() };
        assert!(near(vector(5.0, Vec3::z(), x, x, Some(before), 0.0).unwrap(), [5.0, 0.0, 0.0]));
        let before = Previous { vc: Vec3::new(-5.0, 0.0, 0.0), tool: Vec3::z() };
        assert!(near(vector(5.0, Vec3::z(), x, x, Some(before), 0.0).unwrap(), [-5.0, 0.0, 0.0]));
        // Not 90°: the formula whatever the vector before.
        let before = Previous { vc: Vec3::new(10.0, 0.0, 0.0), tool: Vec3::z() };
        let mv = Vec3::new(100.0, 0.0, -50.0);
        assert!(near(vector(10.0, Vec3::z(), mv, mv, Some(before), 0.0).unwrap(), [-10.0, 0.0, 0.0]));
    }

    #[test]
    fn tv11_theta_classes_with_19631_at_5() {
        let cases = [
            (3.0, Theta::Along),
            (5.0, Theta::Along),
            (5.001, Theta::Normal),
            (177.0, Theta::Along),
            (84.9, Theta::Normal),
            (85.0, Theta::Across),
            (95.0, Theta::Across),
            (120.0, Theta::Normal),
        ];
        for (theta, want) in cases {
            assert_eq!(classify(theta, 5.0), want, "θ = {theta}");
        }
        // With No.19631 = 0 (fivex's): only the exact angles.
        assert_eq!(classify(0.001, 0.0), Theta::Normal);
        assert_eq!(classify(90.0, 0.0), Theta::Across);
        assert_eq!(classify(180.0, 0.0), Theta::Along);
    }

    #[test]
    fn tv12_a_move_along_the_tool_has_no_vector() {
        for mv in [Vec3::new(0.0, 0.0, -10.0), Vec3::new(0.0, 0.0, 10.0), Vec3::zeros()] {
            assert_eq!(vector(5.0, Vec3::z(), mv, mv, None, 0.0), None);
        }
    }
}
