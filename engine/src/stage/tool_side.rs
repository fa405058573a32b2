//! Tool side offset of 5-axis cutter compensation (FANUC G41.2/G42.2 type 1, G41.6/G42.6
//! type 2 under G43.5): at the end Q of each block the compensation plane is the plane
//! perpendicular to the tool there; the block, its start P and the next block's end R are
//! projected on it and cutter compensation C places the corner in it (the 2-D rules of
//! `stage::cutter`); the vectors found are added to the programmed 3-D point Q (FANUC 5-axis
//! manual §3.1.2, "the same as cutter compensation C" in that plane). Rules, decisions and what
//! is still refused: `docs/cutter-compensation.md`, "Tool side offset".
//!
//! What the stage sees as a block's motion in the plane is its move with the part along the
//! tool taken out; a block that does not move in its plane (a move along the tool, a rotary
//! axis alone) is a block without motion and keeps the vector of the block before it. A circle
//! is compensated where the tool is along its normal (seen from a tilted tool it is an
//! ellipse: refused here, at run time). The tool is read, and a motion moved, in its
//! programming coordinates (`stage::tool_shift`): on a table machine the workpiece system,
//! which does not turn with the table, or with TBP = 1 the table coordinate system, which does.

use super::cutter::curve::{Curve, P2};
use super::cutter::{avoidance_point, check_direction, corner, gouges, Held, GUARDED_BLOCKS, MAX_BLOCKS_BETWEEN};
use super::tool_shift::ToolShift;
use super::{CompStart, Link, Stage};
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, CutterWord, Motion, MotionKind, Touch};
use crate::interp::gcode::code;
use crate::interp::Config;
use crate::kin::Vec3;

/// A move shorter than this in its plane does not move in it (mm).
const NO_MOVE: f64 = 1e-9;

/// FANUC No.19635 at 0: the tool directions of two blocks differ "a lot" for the interference
/// check of a compensation plane change from 45° on.
const PLANE_CHANGE_DEG: f64 = 45.0;

/// The cosine of the turn of the tool from which the plane-change check looks at a corner
/// (`five_axis.plane_change_angle`, No.19635).
fn plane_change_cos(m: &crate::machine::MachineConfig) -> f64 {
    let deg = m.five_axis.plane_change_angle;
    if deg == 0.0 { PLANE_CHANGE_DEG } else { deg }.to_radians().cos()
}

/// The compensation plane at a block's end: e1 the tool direction (programming coordinates),
/// (e2, e3) the plane's axes with e2 × e3 = e1, so that the 2-D rules' "left seen from the
/// plane's normal" is the left seen from the tool side (G41.2).
#[derive(Debug, Clone, Copy)]
struct Plane {
    e1: Vec3,
    e2: Vec3,
    e3: Vec3,
}

impl Plane {
    fn of(tool: Vec3) -> Plane {
        // Any completion gives the same vectors (the 2-D rules do not change when the plane
        // turns in itself); X, or Y where X is almost along the tool, keeps it well conditioned.
        let axis = if tool.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let e2 = (axis - tool * tool.dot(&axis)).normalize();
        Plane { e1: tool, e2, e3: tool.cross(&e2) }
    }

    fn project(&self, v: Vec3) -> P2 {
        [v.dot(&self.e2), v.dot(&self.e3)]
    }

    fn lift(&self, p: P2) -> Vec3 {
        self.e2 * p[0] + self.e3 * p[1]
    }
}

/// A circular (or helical) block in programming coordinates: its centre moved along the normal
/// into the plane of the block's end, the unit normal the sweep turns about (right-handed), and
/// the signed sweep (radians).
#[derive(Debug, Clone, Copy)]
struct Arc3 {
    center: Vec3,
    normal: Vec3,
    sweep: f64,
}

impl Arc3 {
    /// The block as a 2-D block in `plane` (coordinates relative to `origin`): its start,
    /// end and centre projected (FANUC §3.1.2 "Others"), turning the way it is seen from the
    /// tool side. `None` where the tool is not along the circle's normal: seen from a tilted
    /// tool a circle is an ellipse, which the 2-D rules (lines and circles) do not place corners
    /// on (not built).
    fn curve(&self, plane: &Plane, origin: Vec3, from: Vec3, to: Vec3) -> Option<Curve> {
        let facing = self.normal.dot(&plane.e1);
        (1.0 - facing.abs() <= ALIGNED).then(|| Curve::Arc {
            from: plane.project(from - origin),
            to: plane.project(to - origin),
            center: plane.project(self.center - origin),
            sweep: self.sweep * facing.signum(),
        })
    }

    /// The signed sweep (degrees) from `from` to `to` about the centre, the way the block turns
    /// (the ends moved by their vectors: a spiral, a helix where they leave the plane).
    fn sweep_deg(&self, from: Vec3, to: Vec3) -> f64 {
        let u = Plane::of(self.normal);
        let (a, b) = (u.project(from - self.center), u.project(to - self.center));
        crate::stage::cutter::curve::swept(a, b, [0.0, 0.0], self.sweep).to_degrees() * self.sweep.signum()
    }
}

/// No.19636 at 0: the tool must not turn across the avoided blocks; it turns where the angle
/// between its directions exceeds this (degrees: directions computed from the same rotary
/// angles agree far closer).
const AVOID_MIN_DEG: f64 = 1e-6;

/// The tool is along a circle's normal where 1 − |cos| of their angle is at most this (4.5e-5
/// rad: a circle of 1 m seen from there is round to 1 µm).
const ALIGNED: f64 = 1e-9;

/// A block waiting for the next block that moves in its plane.
#[derive(Clone)]
struct Waiting {
    /// The block as a 2-D block in its end plane, coordinates relative to `to`.
    held: Held,
    plane: Plane,
    /// Where its vectors are placed (X, Y, Z, programming coordinates): its programmed start
    /// and end, or with No.19632 the cutting points there (CRC-30).
    from: Vec3,
    to: Vec3,
    /// The vector where it starts (programming coordinates).
    start_vector: Vec3,
    /// Q1/Q2/Q3 of the block: its end where the plane-change check finds it in the way.
    q: Option<u8>,
    arc: Option<Arc3>,
}

/// The block after a waiting one, as its corner sees it: its programmed end, its tool there,
/// its signed radius; `cancel`: it is the G40 block.
#[derive(Debug, Clone, Copy)]
struct Next {
    to: Vec3,
    tool: Vec3,
    rn: f64,
    cancel: bool,
    arc: Option<Arc3>,
}

/// The tool side offset stage.
pub struct ToolSide {
    /// The tool, and the vector where it stands.
    shift: ToolShift,
    /// FANUC No.19632: the vectors are placed at the cutting point this far along the tool
    /// from the programmed (pivot) point (0: at the programmed point).
    cutting_point: f64,
    /// The tool at the end of the last motion (where the next one starts), kept while
    /// `cutting_point` is set.
    tool_last: Vec3,
    link: Link,
    on: bool,
    /// The programmed end of the last motion while on.
    programmed: Vec3,
    startup: bool,
    waiting: Option<Waiting>,
    /// The commands after `waiting` (no motion in the plane).
    after: Vec<Canon>,
    stopped: bool,
    alarm: Option<(AlarmId, u32, Option<u32>)>,
    type_b: bool,
    /// The check at a change of the compensation plane: cos of the least turn of the tool;
    /// `None`: not made (16i No.19605#5 NIC = 1).
    plane_change_cos: Option<f64>,
    /// A move this short or shorter in its plane does not move in it (mm): `NO_MOVE`, or the 16i's
    /// No.19630.
    no_move: f64,
    /// The next motion's Q1/Q2/Q3; and G41.2/G42.2 given again: the waiting block ends
    /// perpendicular to itself where the next block that moves in its plane comes.
    q: Option<u8>,
    perpendicular: bool,
    /// `Config::refuse_unbuilt`: off only in the tests of the 5-axis mode interlocks, which
    /// check alarms and modes with the paths as they were before the stage existed: then the
    /// stage hands everything on as it comes.
    refuse: bool,
    /// The interference check in the plane perpendicular to the tool (FANUC No.19608#1 NI5 = 1);
    /// off: on the programmed 3-D positions and the vectors (§3.5.1).
    check_in_plane: bool,
    /// Interference avoidance (No.19607#5 CAV = 1, with NI5 = 1: §3.4).
    avoid: bool,
    /// The cosine of the largest turn of the tool across the avoided blocks (No.19636).
    avoid_cos: f64,
    /// Under `avoid`: what was released and not handed on yet — the last block (`staged`), or
    /// an avoidance placed (`pending`) — handed on once the block after it has passed the check.
    held_back: Vec<Canon>,
    staged: Option<Staged>,
    pending: Option<Pending>,
    guard: Option<Guard>,
    /// The next block while the waiting one is released at the corner with it (offset mode).
    next: Option<Next>,
    /// G41.2 came in a G00/G01 block without X/Y/Z under No.5003#1 SUV: the next block that
    /// moves in its plane is preceded by a straight move perpendicular to it (rule 13).
    perpendicular_start: Option<CompStart>,
}

/// Under interference avoidance: the block released last, which becomes block 1 if the block
/// after it interferes.
#[derive(Clone)]
struct Staged {
    w: Waiting,
    /// The tool and vector before its output was made (to make it again, ending elsewhere).
    shift: ToolShift,
    /// The commands behind it as they came.
    after: Vec<Canon>,
    /// What its release gave.
    out: Vec<Canon>,
}

/// An avoidance vector placed: block 1 and the interfering blocks (one or two, each with the
/// commands behind it as they came).
struct Pending {
    before: Staged,
    interfering: Vec<(Waiting, Vec<Canon>)>,
}

/// After an avoidance: the programmed blocks it replaced, as 2-D blocks in block 1's plane
/// (relative to `origin`, block 1's end) with their signed radii, which the new path must keep
/// the radius from (cutter compensation C's guard), and how many more blocks are checked.
struct Guard {
    replaced: Vec<(Curve, f64)>,
    plane: Plane,
    origin: Vec3,
    left: usize,
}

fn is_tool_side(comp: u16) -> bool {
    code::TOOL_SIDE.contains(&comp)
}

/// The signed offset radius: positive puts the tool on the left seen from the tool side.
fn signed_radius(m: &Motion) -> f64 {
    let side = if code::TOOL_SIDE_RIGHT.contains(&m.context.cutter_comp) { -1.0 } else { 1.0 };
    side * m.context.cutter_radius
}

impl ToolSide {
    pub fn new(config: &Config) -> ToolSide {
        let m = &config.machine;
        let sixteen_i = !m.five_axis.crc_variant.is_30i();
        ToolSide {
            shift: ToolShift::new(m, Touch::Side { along: m.five_axis.cutting_point_distance }),
            cutting_point: m.five_axis.cutting_point_distance,
            tool_last: crate::kin::vec3(m.tool_axis).normalize(),
            link: config.stages.share(),
            on: false,
            programmed: Vec3::zeros(),
            startup: false,
            waiting: None,
            after: Vec::new(),
            stopped: false,
            alarm: None,
            type_b: m.motion.cutter_startup_type_b,
            plane_change_cos: (!m.five_axis.plane_change_check_off).then(|| plane_change_cos(m)),
            no_move: m.five_axis.non_movement_limit.max(NO_MOVE),
            q: None,
            perpendicular: false,
            refuse: config.refuse_unbuilt,
            // The 16i checks in the compensation plane, "as in cutter compensation C", and has
            // no avoidance (A-78438E §1.1; `docs/cutter-compensation.md`, "16i variant").
            check_in_plane: m.five_axis.crc_check_in_plane || sixteen_i,
            avoid: m.motion.cutter_interference_avoidance && m.five_axis.crc_check_in_plane,
            avoid_cos: m.five_axis.avoidance_max_tool_angle.max(AVOID_MIN_DEG).to_radians().cos(),
            held_back: Vec::new(),
            staged: None,
            pending: None,
            guard: None,
            next: None,
            perpendicular_start: None,
        }
    }

    /// The circle of a circular block ending at `to` (programming coordinates), if it is one.
    fn arc(&self, m: &Motion, to: Vec3) -> Option<Arc3> {
        let (center, normal, sweep_deg) = match (&m.arc, m.tip.as_deref().and_then(|t| t.arc.map(|a| (t, a)))) {
            (Some(a), _) => {
                let axis = |i: usize| self.shift.linear_of(i);
                let mut normal = Vec3::zeros();
                if let Some(k) = axis(a.plane_axes.2) {
                    normal[k] = 1.0;
                }
                (self.shift.xyz(&a.center), normal, a.sweep_deg)
            }
            (None, Some((t, a))) => {
                // The tip's circle is in the table frame: back into programming coordinates.
                (t.frame.r.transpose() * (a.center - t.frame.o), t.frame.r.transpose() * a.normal, a.sweep_deg)
            }
            (None, None) => return None,
        };
        let normal = normal.try_normalize(1e-12)?;
        // The centre in the plane of the end (a helix rises along the normal).
        let center = center + normal * normal.dot(&(to - center));
        Some(Arc3 { center, normal, sweep: sweep_deg.to_radians() })
    }

    fn alarm(&mut self, id: AlarmId, c: &Canon) {
        self.alarm.get_or_insert((id, c.line, c.n));
        self.stopped = true;
        self.waiting = None;
        self.after.clear();
    }

    /// Hand on the waiting block ending at `points[0]` (2-D, relative to its end in its
    /// plane), then straight moves to the other points at its feed, then the commands held
    /// behind it at the last vector. Under interference avoidance it is held back (`staged`)
    /// until the block after it has passed the check, and an interfering block gives way to an
    /// avoidance vector.
    fn release(&mut self, points: &[P2], out: &mut Vec<Canon>) {
        let Some(w) = self.waiting.take() else { return };
        if self.interferes(&w, points[0]) {
            let next = self.next.filter(|_| self.avoid);
            match (next, self.pending.take(), self.staged.take()) {
                // The block that starts at an avoidance point interferes too.
                (Some(next), Some(p), _) => self.avoid_again(p, w, next, out),
                (Some(next), None, Some(before)) => {
                    self.place_avoidance(Pending { before, interfering: Vec::new() }, w, next);
                }
                // No block 1 (the start-up block, a vector lost) or no block after it in
                // offset mode: the alarm as without avoidance (what was avoided before moves).
                _ => {
                    self.flush(out);
                    self.alarm(AlarmId::CutterInterference, &w.held.canon);
                }
            }
            return;
        }
        if let Some(g) = &mut self.guard {
            g.left = g.left.saturating_sub(1);
            let gouges = guard_gouges(g, &w, points);
            if g.left == 0 {
                self.guard = None;
            }
            if gouges {
                // The block that starts at the avoidance point: the avoidance is given up, PS0041
                // at block 1 (not moved). A later block: PS0041 at it.
                let canon = match self.pending.take() {
                    Some(p) => {
                        self.held_back.clear();
                        p.before.w.held.canon
                    }
                    None => w.held.canon.clone(),
                };
                self.flush(out);
                self.alarm(AlarmId::CutterInterference, &canon);
                return;
            }
        }
        if self.avoid {
            self.flush(out);
            let (shift, after) = (self.shift.clone(), self.after.clone());
            let mut produced = Vec::new();
            self.produce(w.clone(), points, &mut produced);
            self.held_back = produced.clone();
            self.staged = Some(Staged { w, shift, after, out: produced });
        } else {
            self.produce(w, points, out);
        }
    }

    /// What was held back goes out: the avoidance or the staged block is final.
    fn flush(&mut self, out: &mut Vec<Canon>) {
        out.append(&mut self.held_back);
        self.staged = None;
        self.pending = None;
    }

    /// The interference check of a block ending at `end` (2-D in its plane): with NI5 = 1 in
    /// the plane perpendicular to the tool (cutter compensation C's check); with NI5 = 0 on the
    /// programmed positions and the vectors in 3-D (§3.5.1): the tool centre's move from start to
    /// end against the programmed move. (A circle, seen along its normal, is checked in the
    /// plane either way: its swept angle is about that normal.)
    fn interferes(&self, w: &Waiting, end: P2) -> bool {
        if self.check_in_plane || w.arc.is_some() {
            return check_direction(&w.held, end).is_err();
        }
        let programmed = w.to - w.from;
        let centre = (w.to + w.plane.lift(end)) - (w.from + w.start_vector);
        centre.dot(&programmed) < 0.0
    }

    /// The interference check of the G40 block, as cutter compensation C holds it to one (audit
    /// crc2 N3, `stage::cutter`): from where the tool stands, the vector the block before left
    /// off its programmed start `from`, to its programmed end `to` it must not run against its
    /// own move — in its plane (`curve`, relative to `to`) with NI5 = 1, in 3-D without.
    fn cancel_interferes(&self, curve: &Curve, plane: &Plane, from: Vec3, to: Vec3) -> bool {
        let vector = self.shift.vector;
        if self.check_in_plane {
            // A straight move: the stage refuses an arc as the G40 block.
            use crate::stage::cutter::curve::{add, dot, sub};
            let start = add(curve.from(), plane.project(vector));
            return dot(sub(curve.to(), start), sub(curve.to(), curve.from())) < 0.0;
        }
        (to - (from + vector)).dot(&(to - from)) < 0.0
    }

    /// The output of the released block `w` ending at `points[0]`, the corner's straight moves,
    /// the commands behind it.
    fn produce(&mut self, w: Waiting, points: &[P2], out: &mut Vec<Canon>) {
        let template = (points.len() > 1).then(|| w.held.canon.clone());
        let start = w.from + self.shift.vector;
        let end = w.plane.lift(points[0]);
        let mut first = self.shift.placed(w.held.canon, end);
        if let (Some(arc), CanonKind::Motion(m)) = (w.arc, &mut first.kind) {
            reshape(m, &arc, start, w.to + end);
        }
        out.push(first);
        if let Some(mut template) = template {
            if let CanonKind::Motion(m) = &mut template.kind {
                // A corner's move: straight, at the block's end, the rotary axes standing.
                straighten(m);
                if let Some(t) = m.tip.as_deref_mut() {
                    t.from = t.to;
                    t.posture = None;
                }
            }
            for &p in &points[1..] {
                let c = self.shift.placed(template.clone(), w.plane.lift(p));
                out.push(c);
            }
        }
        for c in std::mem::take(&mut self.after) {
            let c = self.shift.placed(c, self.shift.vector);
            out.push(c);
        }
    }

    /// The block `w` that starts at the avoidance point of `p` interferes as well: two
    /// consecutive interfering blocks, the avoidance vector moves to the crossing of block 1
    /// with `next` (CRC-41). A third: no avoidance vector (CRC-42); block 1 ends at its own
    /// vector and PS0041 stops the tool before the first interfering block (decision, as cutter
    /// compensation C: `docs/cutter-compensation.md`, rule 9).
    fn avoid_again(&mut self, p: Pending, w: Waiting, next: Next, out: &mut Vec<Canon>) {
        if p.interfering.len() >= 2 {
            self.held_back = p.before.out;
            self.flush(out);
            self.alarm(AlarmId::CutterInterference, &p.interfering[0].0.held.canon);
            return;
        }
        self.place_avoidance(p, w, next);
    }

    /// One avoidance vector Va for the interfering blocks of `p` and `w` (CRC-41, M-15): the
    /// block after them (`next`) projected on block 1's plane — perpendicular to the tool at its
    /// end — and crossed with block 1 there (`cutter::avoidance_point`). Block 1 ends at Va, each
    /// interfering block at Va in that plane (it moves only along block 1's tool), `next` starts
    /// there; all of it is held back until `next` has passed the check. The tool
    /// turning more than No.19636 between block 1's end and `next`'s start, no crossing, or the
    /// guard failing: PS0041 — at the first interfering block (block 1 keeps its own vector)
    /// when the tool turned, else at block 1, which does not move.
    fn place_avoidance(&mut self, mut p: Pending, w: Waiting, next: Next) {
        p.interfering.push((w, std::mem::take(&mut self.after)));
        let b = p.before.w.clone();
        let last = &p.interfering[p.interfering.len() - 1].0;
        if b.plane.e1.dot(&last.plane.e1) < self.avoid_cos {
            // (The check has raised it: "the compensation vector is determined but interference
            // avoidance is not performed".)
            let first = p.interfering[0].0.held.canon.clone();
            self.held_back = p.before.out;
            self.staged = None;
            self.alarm(AlarmId::CutterInterference, &first);
            return;
        }
        let in_b = |v: Vec3| b.plane.project(v - b.to);
        let line = Curve::Line { from: in_b(last.to), to: in_b(next.to) };
        let next_curve = next.arc.and_then(|a| a.curve(&b.plane, b.to, last.to, next.to)).unwrap_or(line);
        let mut replaced: Vec<(Curve, f64)> = p.interfering.iter().map(|(h, _)| (seen_from(&b, h), h.held.r)).collect();
        if let Some(g) = self.guard.take() {
            // (The blocks an avoidance just before replaced, while its guard still runs.)
            for (curve, r) in g.replaced {
                let moved = moved(curve, (&g.plane, g.origin), (&b.plane, b.to));
                if !replaced.contains(&(moved, r)) {
                    replaced.push((moved, r));
                }
            }
        }
        let Some(va) = avoidance_point(&b.held, &next_curve, next.rn, &replaced) else {
            self.held_back.clear();
            self.staged = None;
            self.alarm(AlarmId::CutterInterference, &b.held.canon);
            return;
        };
        self.shift = p.before.shift.clone();
        self.after = p.before.after.clone();
        let mut produced = Vec::new();
        self.produce(b.clone(), &[va], &mut produced);
        let at = b.to + b.plane.lift(va);
        let e1 = b.plane.e1;
        for (h, after) in &p.interfering {
            // An interfering block: straight to Va in block 1's plane, which the avoidance takes
            // as the compensation plane (§3.4.1) — it moves only along block 1's tool — then the
            // commands behind it.
            let mut c = h.held.canon.clone();
            if let CanonKind::Motion(m) = &mut c.kind {
                straighten(m);
            }
            let across = at - h.to;
            let c = self.shift.placed(c, across - e1 * across.dot(&e1));
            produced.push(c);
            for c in after {
                let c = self.shift.placed(c.clone(), self.shift.vector);
                produced.push(c);
            }
        }
        self.held_back = produced;
        self.pending = Some(p);
        self.guard = Some(Guard { replaced, plane: b.plane, origin: b.to, left: GUARDED_BLOCKS });
    }

    /// The waiting block ends with the vector perpendicular to it (nothing follows it in its
    /// plane); without one, the commands held are handed on at the current vector.
    fn release_perpendicular(&mut self, out: &mut Vec<Canon>) {
        if let Some(w) = &self.waiting {
            let end = w.held.curve.offset_point(true, w.held.r);
            self.release(&[end], out);
            // No corner joins it to the next block: it is no block 1 of an avoidance.
            self.staged = None;
        } else {
            self.flush(out);
            for c in std::mem::take(&mut self.after) {
                let c = self.shift.placed(c, self.shift.vector);
                out.push(c);
            }
        }
    }

    fn cancelled(&mut self) {
        self.perpendicular_start = None;
        // (What is held back goes out with the next command; no block after the cancel joins it.)
        self.staged = None;
        self.pending = None;
        self.guard = None;
        self.on = false;
        self.startup = false;
        self.shift.vector = Vec3::zeros();
        self.shift.table = None;
    }

    /// More blocks without motion in the plane than the read-ahead holds: the vector is lost.
    fn lose_vector_if_too_many(&mut self, out: &mut Vec<Canon>) {
        let Some(w) = &self.waiting else { return };
        if super::blocks_without_motion(&self.after, w.held.canon.line) > MAX_BLOCKS_BETWEEN {
            self.release_perpendicular(out);
        }
    }

    /// The corner at the waiting block's end with the next block: the points of the corner in
    /// the waiting block's plane.
    /// `respecified`: the next block gave G41.2/G42.2 again.
    fn corner_with(&self, w: &Waiting, next: Next, respecified: bool) -> Result<Vec<P2>, AlarmId> {
        let Next { to, tool, rn, cancel, arc } = next;
        let perpendicular = || vec![w.held.curve.offset_point(true, w.held.r)];
        let line = Curve::Line { from: [0.0, 0.0], to: w.plane.project(to - w.to) };
        let next = match arc {
            Some(a) => a.curve(&w.plane, w.to, w.to, to).unwrap_or(line),
            None => line,
        };
        let along_tool = arc.is_none() && crate::stage::cutter::curve::norm(next.to()) <= self.no_move;
        if along_tool || respecified {
            // The next block runs along this block's tool (no corner in this plane), or gave
            // G41.2/G42.2 again (§3.1.2: "a perpendicular vector is generated").
            return Ok(perpendicular());
        }
        let points = corner(&w.held, &next, rn, cancel, self.type_b)?;
        let checked = self.plane_change_cos.is_some_and(|cos| plane_change_interferes(w, to, tool, cos));
        if cancel || !checked {
            return Ok(points);
        }
        // The block that the check stops may say what its end does instead (§3.1.2).
        match w.q {
            Some(1) => Ok(perpendicular()),
            Some(2) => Ok(points[..1].to_vec()),
            Some(_) => Ok(points),
            None => Err(AlarmId::CutterInterference),
        }
    }

    fn motion(&mut self, c: Canon, out: &mut Vec<Canon>) {
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        // Q belongs to this block's end (nothing to do where it does not move in its plane).
        let q = self.q.take();
        let comp = is_tool_side(m.context.cutter_comp);
        if !self.on && !comp {
            if self.cutting_point != 0.0 {
                self.tool_last = self.shift.tool(m, &m.machine);
            }
            self.flush(out);
            out.push(c);
            return;
        }
        if m.kind == MotionKind::MachineRapid {
            // The interpreter refuses these (`unbuilt::cutter`); never shift them blindly.
            self.alarm(AlarmId::GCodeNotBuilt, &c);
            return;
        }
        let restart = if comp { self.link.take_comp_start() } else { None };
        if self.on && restart.is_some() {
            self.release_perpendicular(out);
            self.cancelled();
        }
        if !self.on {
            self.on = true;
            self.shift.vector = Vec3::zeros();
            self.startup = true;
            self.programmed = restart.map_or_else(|| self.shift.xyz(&m.target), |s| self.shift.xyz(&s.pos));
            self.perpendicular_start = restart.filter(|s| s.perpendicular.is_some());
            self.shift.table = restart.and_then(|s| s.table);
        }
        let (from, to) = (self.programmed, self.shift.xyz(&m.target));
        self.programmed = to;
        let tool = self.shift.tool(m, &m.machine);
        let tool_from = std::mem::replace(&mut self.tool_last, tool);
        let plane = Plane::of(tool);
        // Where the vectors are placed: the programmed points, or the cutting points (CRC-30,
        // each with its own tool; a block that moves no linear axis gets no vector).
        let (from_at, to_at) = (from + tool_from * self.cutting_point, to + tool * self.cutting_point);
        let arc = self.arc(m, to);
        let curve = match arc {
            Some(a) if self.cutting_point == 0.0 => a.curve(&plane, to, from, to),
            // (A circle's cutting points with No.19632: not built.)
            Some(_) => None,
            None => Some(Curve::Line { from: plane.project(from_at - to_at), to: [0.0, 0.0] }),
        };
        let Some(curve) = curve else {
            self.alarm(AlarmId::GCodeNotBuilt, &c);
            return;
        };
        let no_move = self.no_move;
        let in_plane = |v: Vec3| crate::stage::cutter::curve::norm(plane.project(v)) > no_move;
        let moves = arc.is_some() || in_plane(to - from) && in_plane(to_at - from_at);
        if comp && moves && self.startup && self.waiting.is_none() {
            if let Some(s) = self.perpendicular_start.take() {
                // Start-up perpendicular to the next movement (No.5003#1 SUV, rule 13): the
                // G41.2 block moves straight by the offset value perpendicular to this block at
                // its start, in this block's plane (the plane is taken at block ends, rule 11);
                // this block is then one of offset mode (an arc too).
                let v0 = plane
                    .lift(crate::stage::cutter::curve::sub(curve.offset_point(false, signed_radius(m)), curve.from()));
                if v0.norm() > NO_MOVE {
                    self.flush(out);
                    let inserted = self.shift.startup_move(&c, s.pos, s.machine, s.perpendicular, v0);
                    out.push(inserted);
                }
                self.shift.vector = v0;
                self.startup = false;
            }
        }
        if arc.is_some() && (self.startup || !comp) {
            self.alarm(AlarmId::ArcInCompStartCancel, &c);
            return;
        }
        let r = signed_radius(m);
        if !comp {
            // G40: the waiting block ends perpendicular (type A) or at its corner with this
            // block (type B); this block moves to its programmed end.
            let next = Next { to: to_at, tool, rn: 0.0, cancel: true, arc };
            match (&self.waiting, moves) {
                (Some(w), true) => match self.corner_with(w, Next { rn: w.held.r, ..next }, false) {
                    // (No block after the cancel in offset mode: no avoidance.)
                    Ok(points) => self.release(&points, out),
                    Err(id) => {
                        let canon = w.held.canon.clone();
                        self.alarm(id, &canon);
                    }
                },
                _ => self.release_perpendicular(out),
            }
            if !self.stopped && moves && self.cancel_interferes(&curve, &plane, from_at, to_at) {
                // The tool stops at the end of the block before (released above).
                self.flush(out);
                self.alarm(AlarmId::CutterInterference, &c);
                return;
            }
            if !self.stopped {
                self.cancelled();
                self.flush(out);
                let c = self.shift.placed(c, Vec3::zeros());
                out.push(c);
            }
            return;
        }
        if !moves {
            if self.waiting.is_some() {
                self.after.push(c);
                self.lose_vector_if_too_many(out);
            } else {
                self.flush(out);
                let c = self.shift.placed(c, self.shift.vector);
                out.push(c);
            }
            return;
        }
        // The vector where this block starts.
        let vector = match &self.waiting {
            None => self.shift.vector,
            Some(w) => {
                let respecified = std::mem::take(&mut self.perpendicular);
                let next = Next { to: to_at, tool, rn: r, cancel: false, arc };
                let points = match self.corner_with(w, next, respecified) {
                    Ok(points) => points,
                    Err(id) => {
                        let canon = w.held.canon.clone();
                        self.alarm(id, &canon);
                        return;
                    }
                };
                self.next = Some(next);
                self.release(&points, out);
                self.next = None;
                if self.stopped {
                    return;
                }
                // The last vector placed (with an avoidance, Va seen in the last interfering
                // block's plane).
                self.shift.vector
            }
        };
        let startup = std::mem::replace(&mut self.startup, false);
        let held = Held { canon: c, curve, r, start: plane.project(from_at + vector - to_at), startup };
        self.waiting = Some(Waiting { held, plane, from: from_at, to: to_at, start_vector: vector, q, arc });
    }
}

/// A circular block moved to start at `start` and end at `end` (programming coordinates): the
/// same centre, its radius where it starts, its sweep between the moved ends.
fn reshape(m: &mut Motion, arc: &Arc3, start: Vec3, end: Vec3) {
    let sweep = arc.sweep_deg(start, end);
    if let Some(a) = m.arc.as_deref_mut() {
        let radial = start - arc.center;
        a.radius = (radial - arc.normal * radial.dot(&arc.normal)).norm();
        a.sweep_deg = sweep;
    }
    if let Some(a) = m.tip.as_deref_mut().and_then(|t| t.arc.as_mut()) {
        a.sweep_deg = sweep;
    }
}

/// A block's move made straight in its plane (an interfering block under avoidance, a
/// corner's move): no circle, G01 unless it is G00.
fn straighten(m: &mut Motion) {
    m.arc = None;
    if m.kind != MotionKind::Rapid {
        m.kind = MotionKind::Linear;
    }
    if let Some(t) = m.tip.as_deref_mut() {
        t.arc = None;
    }
}

/// The programmed block `h` as a 2-D block in the plane of `b` (relative to `b`'s end): its
/// ends projected, a circle seen along its normal as a circle, else by its chord (decision:
/// only a tool turned within No.19636 gets here, and a circle is compensated only where the
/// tool is along its normal).
fn seen_from(b: &Waiting, h: &Waiting) -> Curve {
    let line = Curve::Line { from: b.plane.project(h.from - b.to), to: b.plane.project(h.to - b.to) };
    h.arc.and_then(|a| a.curve(&b.plane, b.to, h.from, h.to)).unwrap_or(line)
}

/// A 2-D block of the plane `from` (coordinates relative to its origin) as seen in the plane
/// `to`: its points lifted into 3-D and projected there; a circle by its chord where the two
/// planes are not parallel (as `seen_from`).
fn moved(curve: Curve, from: (&Plane, Vec3), to: (&Plane, Vec3)) -> Curve {
    let at = |p: P2| to.0.project(from.1 + from.0.lift(p) - to.1);
    let facing = from.0.e1.dot(&to.0.e1);
    match curve {
        Curve::Arc { from: a, to: b, center, sweep } if 1.0 - facing.abs() <= ALIGNED => {
            Curve::Arc { from: at(a), to: at(b), center: at(center), sweep: sweep * facing.signum() }
        }
        c => Curve::Line { from: at(c.from()), to: at(c.to()) },
    }
}

/// The guard after an avoidance: the tool centre path of the released block `w` (ending at
/// `points[0]`, then its corner's moves), in 3-D projected on block 1's plane, comes within the
/// radius of a replaced block (`cutter::gouges`). A circle not seen along its normal from there
/// (the tool turned) is checked by its chord.
fn guard_gouges(g: &Guard, w: &Waiting, points: &[P2]) -> bool {
    let at = |v: Vec3| g.plane.project(v - g.origin);
    let (start, end) = (w.from + w.start_vector, w.to + w.plane.lift(points[0]));
    let first = match w.arc.and_then(|a| a.curve(&g.plane, g.origin, start, end)) {
        Some(Curve::Arc { from, to, center, sweep }) => Curve::Arc {
            from,
            to,
            center,
            sweep: crate::stage::cutter::curve::swept(from, to, center, sweep) * sweep.signum(),
        },
        _ => Curve::Line { from: at(start), to: at(end) },
    };
    let mut pieces = vec![first];
    for pair in points.windows(2) {
        pieces.push(Curve::Line { from: at(w.to + w.plane.lift(pair[0])), to: at(w.to + w.plane.lift(pair[1])) });
    }
    gouges(&g.replaced, &pieces)
}

/// The interference check at a change of the compensation plane (FANUC 5-axis manual §3.1.2):
/// the tool turns between the two blocks by the angle whose cosine is `cos` or more, the
/// vectors they would each get point the same way, and their paths run against each other
/// seen in the first block's plane.
fn plane_change_interferes(w: &Waiting, to: Vec3, vb: Vec3, cos: f64) -> bool {
    let va = w.plane.e1;
    let (ua, ub) = (w.to - w.from, to - w.to);
    let turned = va.dot(&vb) <= cos;
    let same_side = va.cross(&ua).dot(&vb.cross(&ub)) >= 0.0;
    let ra = ua - va * ua.dot(&va);
    let rb = ub - va * ub.dot(&va);
    turned && same_side && ra.dot(&rb) < 0.0
}

impl Stage for ToolSide {
    fn push(&mut self, command: Canon, out: &mut Vec<Canon>) {
        if self.stopped {
            return;
        }
        self.push_command(command, out);
        if self.stopped {
            // The blocks before the one the alarm stops move (what an avoidance gave up is gone).
            self.flush(out);
        }
    }

    fn finish(&mut self, out: &mut Vec<Canon>) {
        if !self.stopped {
            self.release_perpendicular(out);
        }
        self.flush(out);
    }

    fn take_alarm(&mut self) -> Option<(AlarmId, u32, Option<u32>)> {
        self.alarm.take()
    }

    fn passes(&self, command: &Canon) -> bool {
        let idle = !self.on
            && self.waiting.is_none()
            && self.held_back.is_empty()
            && self.q.is_none()
            && !self.perpendicular
            && !self.stopped;
        idle && self.cutting_point == 0.0
            && match &command.kind {
                CanonKind::Motion(m) => !is_tool_side(m.context.cutter_comp),
                CanonKind::Cutter(CutterWord::PlaneChange(_) | CutterWord::Perpendicular) => false,
                _ => true,
            }
    }

    fn reset(&mut self) {
        self.cancelled();
        self.q = None;
        self.perpendicular = false;
        self.shift.reset();
        self.waiting = None;
        self.after.clear();
        self.held_back.clear();
        self.next = None;
        self.stopped = false;
        self.alarm = None;
    }
}

impl ToolSide {
    fn push_command(&mut self, command: Canon, out: &mut Vec<Canon>) {
        match &command.kind {
            // The words of the tool side offset are this stage's; G38/G39/G40's go on.
            CanonKind::Cutter(CutterWord::PlaneChange(q)) => self.q = Some(*q),
            // (G41/G42 given again is cutter compensation C's.)
            CanonKind::Cutter(CutterWord::Perpendicular) if self.on => self.perpendicular = true,
            _ if !self.refuse => out.push(command),
            CanonKind::Motion(_) => self.motion(command, out),
            CanonKind::ProgramEnd { .. } if self.on => {
                self.release_perpendicular(out);
                self.cancelled();
                if !self.stopped {
                    self.flush(out);
                    out.push(command);
                }
            }
            _ if self.waiting.is_some() => {
                self.after.push(command);
                self.lose_vector_if_too_many(out);
            }
            _ => {
                self.flush(out);
                out.push(command);
            }
        }
    }
}
