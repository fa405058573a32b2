//! Cutter compensation C (G41/G42/G40 with D), as the FANUC 30i performs it in the G17/G18/G19
//! plane: the tool centre runs at the radius from the programmed contour, corners by the
//! manual's vectors. Rules and sources: `docs/cutter-compensation.md`.
//!
//! The stage holds the last motion in the plane until the next one has come (the corner between
//! them places its end): one motion of look-ahead, and at most [`MAX_BLOCKS_BETWEEN`] blocks
//! without motion in the plane held behind it. The interpreter refuses what the stage does not
//! perform (`interp::unbuilt::cutter`): while G41/G42 is in force, programming and machine
//! coordinates differ by a translation, so a point is compensated by moving both by the same
//! vector in the plane; the other axes move as programmed.

pub(super) mod curve;

use super::{Link, PerpendicularStart, Stage};
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, CanonKind, CutterWord, Motion, MotionKind, Pos, Touch};
use crate::interp::gcode::code;
use crate::interp::Config;
use crate::machine::MachineConfig;
use curve::{add, cross, dot, norm, scale, sub, swept, Curve, P2};

/// Blocks without motion in the plane that may come between two motions in it before the
/// corner vector is lost: FANUC No.19625 (blocks read in offset mode, 3 when 0) less the two
/// moving blocks.
pub const MAX_BLOCKS_BETWEEN: usize = 1;

/// A motion shorter than this in the plane does not move in it (mm).
const NO_MOVE: f64 = 1e-9;

/// An arc whose ends are closer than this (mm) has no chord direction for the interference
/// check (a whole turn, or a compensated arc that shrank to a point): points are rounded to 1 µm.
const CHORD: f64 = 1e-3;

/// Blocks whose directions at a corner differ by less than this (radians) meet tangentially:
/// their offset paths are taken as their tangent lines there. (Where two circles almost touch,
/// their crossing moves by the points' rounding divided by the angle: ill-conditioned.)
const NEAR_TANGENT: f64 = 1e-3;

/// A motion waiting for the next motion in the plane.
#[derive(Clone)]
pub(super) struct Held {
    pub(super) canon: Canon,
    pub(super) curve: Curve,
    /// Signed radius: positive puts the tool on the left (G41 with a positive D).
    pub(super) r: f64,
    /// The compensated start (where the tool is when it begins).
    pub(super) start: P2,
    /// The start-up block (type A: its end vector is perpendicular to the next block).
    pub(super) startup: bool,
}

/// A block released but not handed on yet, under interference avoidance: if the block after it
/// interferes, its end moves to the avoidance vector.
struct Staged {
    held: Held,
    /// What its release gave: the block, the moves inserted after it, the commands behind it.
    out: Vec<Canon>,
    /// The commands behind it as they came (before they were moved by its vector).
    after: Vec<Canon>,
}

/// An avoidance vector placed but not handed on yet: until the block that starts at it has
/// passed the check, that block interfering too moves it (two consecutive interfering blocks),
/// a third gives it up.
struct Pending {
    /// Block 1, the last good block before the interfering ones, as it was staged (its output
    /// with its own vector, the commands behind it as they came).
    before: Staged,
    /// The interfering blocks (one or two), each with the commands behind it as they came.
    interfering: Vec<(Held, Vec<Canon>)>,
    /// Block 1 to the avoidance point, the interfering blocks there, the commands behind them.
    out: Vec<Canon>,
}

/// After an avoidance: the programmed blocks it replaced (with their signed radii), which the
/// new path near the avoidance point must keep the radius from, and how many more blocks
/// released are checked against them.
struct Guard {
    replaced: Vec<(Curve, f64)>,
    left: usize,
}

/// The blocks released after an avoidance point whose paths the guard checks: the one that
/// starts there and the one after it (decision, `docs/cutter-compensation.md` rule 9).
pub(super) const GUARDED_BLOCKS: usize = 2;

/// The guard's tolerance (mm): the new path may come this much closer than the radius.
const GUARD_TOLERANCE: f64 = 1e-3;

/// The cutter compensation C stage.
pub struct Cutter {
    /// Axis indices of X, Y, Z.
    xyz: [Option<usize>; 3],
    link: Link,
    /// G41/G42 in force (as far as the motions that came through say).
    on: bool,
    /// The plane's two axis indices while on.
    plane: (usize, usize),
    /// The programmed end of the last motion while on (programming coordinates).
    programmed: Pos,
    /// The compensated point minus the programmed one, where the tool is.
    vector: P2,
    /// No motion in the plane has come since compensation was turned on.
    startup: bool,
    held: Option<Held>,
    /// The cutter word of the block whose motion comes next.
    word: Option<CutterWord>,
    /// A G39 block without I/J/K: its arc ends perpendicular to the next block in the plane,
    /// so it waits for that block (the block before it has ended at its own vector).
    corner: Option<Canon>,
    /// The commands after `held` or `corner` (no motion in the plane).
    after: Vec<Canon>,
    /// An alarm was raised: nothing more is handed on until a reset.
    stopped: bool,
    /// The alarm found, until the pipeline takes it.
    alarm: Option<(AlarmId, u32, Option<u32>)>,
    /// Start-up and cancel of type B (FANUC No.5003#0 SUP = 1) instead of type A.
    type_b: bool,
    /// G41/G42 came in a G00/G01 block without an axis word of the plane under No.5003#1 SUV:
    /// the next motion in the plane is preceded by a straight move perpendicular to it.
    perpendicular: Option<PerpendicularStart>,
    /// Interference avoidance (FANUC No.19607#5 CAV = 1): an interfering block's vectors give
    /// way to one at the crossing of the blocks around it.
    avoid: bool,
    /// Under `avoid`: the last block released, held back until the block after it is checked.
    staged: Option<Staged>,
    /// Under `avoid`: the avoidance vector placed, not handed on yet (in the place of `staged`).
    pending: Option<Pending>,
    /// Under `avoid`: the programmed blocks the last avoidance replaced, checked against.
    guard: Option<Guard>,
    /// The avoidance point just placed: where the next block starts.
    avoided: Option<P2>,
    /// Where the staged block's output belongs in the current call's output.
    staged_at: usize,
    /// The next motion in the plane while the held block is released at the corner with it.
    next: Option<(Curve, f64)>,
    /// G41/G42 was given again in offset mode: the held motion ends at its perpendicular vector
    /// when the next motion in the plane comes.
    respecified: bool,
    /// `Config::refuse_unbuilt`: off only in the tests of the 5-axis mode interlocks, where a
    /// motion the stage does not compensate passes as it came (as before the stage existed).
    refuse: bool,
}

impl Cutter {
    pub fn new(config: &Config) -> Cutter {
        let m: &MachineConfig = &config.machine;
        Cutter {
            xyz: [m.axis_index(b'X'), m.axis_index(b'Y'), m.axis_index(b'Z')],
            link: config.stages.share(),
            on: false,
            plane: (0, 1),
            programmed: [0.0; crate::machine::MAX_AXES],
            vector: [0.0; 2],
            startup: false,
            held: None,
            word: None,
            corner: None,
            after: Vec::new(),
            stopped: false,
            alarm: None,
            type_b: m.motion.cutter_startup_type_b,
            perpendicular: None,
            avoid: m.motion.cutter_interference_avoidance,
            staged: None,
            pending: None,
            guard: None,
            avoided: None,
            staged_at: 0,
            next: None,
            respecified: false,
            refuse: config.refuse_unbuilt,
        }
    }

    /// The plane's axes (first, second) for a plane code; `None` if the machine lacks one.
    fn plane_axes(&self, plane: u16) -> Option<(usize, usize)> {
        let [x, y, z] = self.xyz;
        match plane {
            code::G18 => Some((z?, x?)),
            code::G19 => Some((y?, z?)),
            _ => Some((x?, y?)),
        }
    }

    fn in_plane(&self, p: &Pos) -> P2 {
        [p[self.plane.0], p[self.plane.1]]
    }

    /// The motion's path in the plane from `from`; `None` when it does not move in the plane.
    fn curve(&self, m: &Motion, from: &Pos) -> Option<Curve> {
        let (a, b) = (self.in_plane(from), self.in_plane(&m.target));
        match m.arc.as_deref() {
            Some(arc) => Some(Curve::Arc {
                from: a,
                to: b,
                center: [arc.center[self.plane.0], arc.center[self.plane.1]],
                sweep: arc.sweep_deg.to_radians(),
            }),
            None if norm(sub(b, a)) > NO_MOVE => Some(Curve::Line { from: a, to: b }),
            None => None,
        }
    }

    fn alarm(&mut self, id: AlarmId, c: &Canon) {
        self.alarm.get_or_insert((id, c.line, c.n));
        self.next = None;
        self.stopped = true;
        self.held = None;
        self.corner = None;
        self.after.clear();
    }

    /// `c` moved so that its end in the plane is at `to` (programming coordinates); the machine
    /// position moves by the same.
    fn placed(&self, mut c: Canon, to: P2) -> Canon {
        if let CanonKind::Motion(m) = &mut c.kind {
            m.record_offset(Touch::Side { along: 0.0 });
            let (a, b) = self.plane;
            let d = sub(to, [m.target[a], m.target[b]]);
            m.target[a] = to[0];
            m.target[b] = to[1];
            m.machine[a] += d[0];
            m.machine[b] += d[1];
        }
        c
    }

    /// Hand on the held motion ending at `points[0]`, then straight moves to the other points,
    /// then the commands held behind it, moved by the vector at the last point.
    fn release(&mut self, points: &[P2], out: &mut Vec<Canon>) {
        let Some(h) = self.held.take() else { return };
        let end = points[0];
        if let Err(id) = check_direction(&h, end) {
            match (self.next.filter(|_| self.avoid), self.pending.take()) {
                // The block that starts at an avoidance point interferes too.
                (Some(next), Some(p)) => self.avoid_again(p, h, next, out),
                (Some(next), None) if self.staged.is_some() => self.avoid_interference(h, next),
                (_, pending) => {
                    // No block after it in offset mode: the alarm as without avoidance (what
                    // was avoided before it moves).
                    self.pending = pending;
                    self.flush_staged(out);
                    let canon = h.canon.clone();
                    self.alarm(id, &canon);
                }
            }
            return;
        }
        if let Some(g) = &mut self.guard {
            let gouges = gouges(&g.replaced, &path_of(&h, points));
            g.left = g.left.saturating_sub(1);
            if g.left == 0 {
                self.guard = None;
            }
            if gouges {
                // The block that starts at the avoidance point: the avoidance is given up, PS0041
                // at the block before the interfering ones (not moved). A later block: PS0041 at
                // it (the tool stops at the end of the block before it).
                let canon = match self.pending.take() {
                    Some(p) => p.before.held.canon,
                    None => h.canon.clone(),
                };
                self.alarm(AlarmId::CutterInterference, &canon);
                return;
            }
        }
        if self.avoid {
            // Hand on the avoidance or the block staged before, stage this one.
            self.flush_staged(out);
            let mut produced = Vec::new();
            let after = self.after.clone();
            let held = h.clone();
            self.produce(h, points, end, &mut produced);
            self.staged_at = out.len();
            self.staged = Some(Staged { held, out: produced, after });
        } else {
            self.produce(h, points, end, out);
        }
    }

    /// The avoidance placed (if any) and the staged block's output, put where they belong in
    /// `out` (at most one of them is there).
    fn flush_staged(&mut self, out: &mut Vec<Canon>) {
        let at = self.staged_at.min(out.len());
        if let Some(p) = self.pending.take() {
            out.splice(at..at, p.out);
        } else if let Some(st) = self.staged.take() {
            out.splice(at..at, st.out);
        }
    }

    /// Interference avoidance (FANUC 30i B-63944EN-1/02 §5, "interference avoidance"; the
    /// 5-axis extract's CRC-41/M-15): the held block `h` interferes. Its vectors and those of
    /// the staged block before it (block 1) give way to one avoidance vector (`place_avoidance`).
    fn avoid_interference(&mut self, h: Held, next: (Curve, f64)) {
        let Some(before) = self.staged.take() else { return };
        self.place_avoidance(Pending { before, interfering: Vec::new(), out: Vec::new() }, h, next);
    }

    /// The block `h` that starts at the avoidance point `p` placed interferes as well: two
    /// consecutive interfering blocks, the avoidance vector moves to the crossing of block 1 with
    /// `next` (CRC-41: "between the last good block (N20) and the next good block (N50)"). A third
    /// one: no avoidance vector can be made (CRC-42); block 1 ends at its own vector and PS0041
    /// stops the tool before the first interfering block (decision: the control's overcut without
    /// alarm is not hidden, `docs/cutter-compensation.md` rule 9).
    fn avoid_again(&mut self, p: Pending, h: Held, next: (Curve, f64), out: &mut Vec<Canon>) {
        if p.interfering.len() >= 2 {
            let first = p.interfering[0].0.canon.clone();
            let at = self.staged_at.min(out.len());
            out.splice(at..at, p.before.out);
            self.alarm(AlarmId::CutterInterference, &first);
            return;
        }
        self.place_avoidance(p, h, next);
    }

    /// One avoidance vector for the interfering blocks of `p` and `h`: the crossing of block 1's
    /// offset path with that of `next` (the block after `h`). Block 1 ends there, the interfering
    /// blocks move nothing in the plane, `next` starts there; all of it waits (`pending`) until
    /// `next` has passed the check. No crossing (parallel or concentric paths, or one farther than
    /// ten radii from the corner), a block 1 that would interfere ending there, or one whose new
    /// path comes closer than the radius to an interfering block (the guard): PS0041 at block 1,
    /// which does not move.
    fn place_avoidance(&mut self, mut p: Pending, h: Held, (next, rn): (Curve, f64)) {
        p.interfering.push((h, std::mem::take(&mut self.after)));
        // (With the blocks an avoidance just before replaced, while its guard still runs.)
        let mut replaced: Vec<(Curve, f64)> = p.interfering.iter().map(|(h, _)| (h.curve, h.r)).collect();
        if let Some(g) = self.guard.take() {
            for old in g.replaced {
                if !replaced.contains(&old) {
                    replaced.push(old);
                }
            }
        }
        let b = &p.before.held;
        let Some(va) = avoidance_point(b, &next, rn, &replaced) else {
            let canon = b.canon.clone();
            self.alarm(AlarmId::CutterInterference, &canon);
            return;
        };
        let mut produced = Vec::new();
        self.after = p.before.after.clone();
        self.produce(p.before.held.clone(), &[va], va, &mut produced);
        for (h, after) in &p.interfering {
            // An interfering block: to the avoidance point, straight (it moves only out of the
            // plane), then the commands behind it.
            let mut c = self.placed(h.canon.clone(), va);
            if let CanonKind::Motion(m) = &mut c.kind {
                m.arc = None;
                if m.kind != MotionKind::Rapid {
                    m.kind = MotionKind::Linear;
                }
            }
            produced.push(c);
            self.vector = sub(va, h.curve.to());
            for c in after {
                produced.push(self.shifted(c.clone()));
            }
        }
        p.out = produced;
        self.pending = Some(p);
        self.guard = Some(Guard { replaced, left: GUARDED_BLOCKS });
        self.avoided = Some(va);
    }

    /// The output of the released block `h` ending at `end`, then straight moves to the other
    /// `points`, then the commands held behind it moved by the vector at the last point.
    fn produce(&mut self, h: Held, points: &[P2], end: P2, out: &mut Vec<Canon>) {
        let mut first = self.placed(h.canon, end);
        if let (CanonKind::Motion(m), Curve::Arc { center, sweep, .. }) = (&mut first.kind, h.curve) {
            if let Some(arc) = m.arc.as_deref_mut() {
                arc.radius = norm(sub(h.start, center));
                arc.sweep_deg = swept(h.start, end, center, sweep).to_degrees() * sweep.signum();
            }
        }
        // The inserted moves: straight, at the block's feed, from its end (the other axes there).
        let template = (points.len() > 1).then(|| first.clone());
        out.push(first);
        if let Some(template) = template {
            for &p in &points[1..] {
                let mut c = self.placed(template.clone(), p);
                if let CanonKind::Motion(m) = &mut c.kind {
                    m.arc = None;
                    if m.kind != MotionKind::Rapid {
                        m.kind = MotionKind::Linear;
                    }
                }
                out.push(c);
            }
        }
        let last = points[points.len() - 1];
        self.vector = sub(last, h.curve.to());
        for c in std::mem::take(&mut self.after) {
            out.push(self.shifted(c));
        }
    }

    /// A command moved by the current vector (a motion out of the plane keeps the offset).
    fn shifted(&self, c: Canon) -> Canon {
        match &c.kind {
            CanonKind::Motion(m) => {
                let p = add(self.in_plane(&m.target), self.vector);
                self.placed(c, p)
            }
            _ => c,
        }
    }

    /// The held motion ends with the vector perpendicular to it (nothing follows it in the
    /// plane: the program's end, a cancel without motion in the plane, a lost vector). A G39
    /// waiting for the next block has no end then: PS0033 at it.
    fn release_perpendicular(&mut self, out: &mut Vec<Canon>) {
        if let Some(c) = self.corner.take() {
            self.alarm(AlarmId::CutterNoSolution, &c);
        } else if let Some(h) = &self.held {
            let end = h.curve.offset_point(true, h.r);
            self.release(&[end], out);
        } else {
            for c in std::mem::take(&mut self.after) {
                out.push(self.shifted(c));
            }
        }
    }

    fn motion(&mut self, c: Canon, out: &mut Vec<Canon>) {
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let comp = offsets(m);
        if !self.on && !comp {
            out.push(c);
            return;
        }
        if m.tip.is_some() || m.kind == MotionKind::MachineRapid && comp {
            // The interpreter refuses these (`unbuilt::cutter`); never shift them blindly.
            if self.refuse {
                self.alarm(AlarmId::GCodeNotBuilt, &c);
            } else {
                self.release_perpendicular(out);
                self.cancelled();
                out.push(c);
            }
            return;
        }
        let toward = match self.word.take() {
            Some(CutterWord::CornerArc(direction)) => return self.corner_arc(c, direction, out),
            Some(CutterWord::CancelDirection(d)) => Some(ijk_in_plane(d, m.context.plane)),
            Some(CutterWord::VectorHold(direction)) if comp => return self.vector_hold(c, direction, out),
            // G41/G42 given again: it acts at the next motion in the plane.
            Some(CutterWord::Perpendicular) if comp && self.on => {
                self.respecified = true;
                None
            }
            // (The tool side offset's words are taken by its stage, before this one.)
            Some(
                CutterWord::VectorHold(_)
                | CutterWord::PlaneChange(_)
                | CutterWord::Perpendicular
                | CutterWord::WithoutMotion,
            )
            | None => None,
        };
        // G41/G42 again after a G40 that moved nothing: that cancel, then a new start-up.
        let restart = if comp { self.link.take_comp_start() } else { None };
        if self.on && restart.is_some() {
            self.release_perpendicular(out);
            self.cancelled();
            if self.stopped {
                return;
            }
        }
        if !self.on {
            let Some(plane) = self.plane_axes(m.context.plane) else {
                self.alarm(AlarmId::GCodeNotBuilt, &c);
                return;
            };
            self.on = true;
            self.plane = plane;
            self.vector = [0.0; 2];
            self.startup = true;
            self.programmed = restart.map_or(m.target, |s| s.pos);
            self.perpendicular = restart.and_then(|s| s.perpendicular);
        }
        let from = std::mem::replace(&mut self.programmed, m.target);
        let curve = self.curve(m, &from);
        let r = signed_radius(m);
        let is_arc = m.arc.is_some();
        if let (Some(curve), true, true) = (&curve, comp, self.startup && self.held.is_none()) {
            if let Some(p) = self.perpendicular.take() {
                // Start-up perpendicular to the next movement (No.5003#1 SUV): a straight move of
                // the offset value perpendicular to this block at its start; this block is then
                // one of offset mode (an arc too).
                let to = curve.offset_point(false, r);
                if norm(sub(to, curve.from())) > NO_MOVE {
                    out.push(self.inserted_before(&c, &from, to, p));
                }
                self.vector = sub(to, curve.from());
                self.startup = false;
            }
        }
        match (curve, comp) {
            (None, true) => {
                if self.corner.is_some() {
                    self.after.push(c);
                } else if self.held.is_some() {
                    self.after.push(c);
                    self.lose_vector_if_too_many(out);
                } else {
                    out.push(self.shifted(c));
                }
            }
            (None, false) => {
                // G40 without motion in the plane: the vector goes in this move.
                match (toward, &self.held) {
                    (Some(d), Some(h)) => {
                        let points = cancel_toward(h, d);
                        self.release(&points, out);
                    }
                    _ => self.release_perpendicular(out),
                }
                self.cancelled();
                out.push(c);
            }
            (Some(_), _) if is_arc && (self.startup || !comp) => {
                self.alarm(AlarmId::ArcInCompStartCancel, &c);
            }
            (Some(curve), true) => {
                self.finish_corner(&curve, out);
                let respecified = std::mem::take(&mut self.respecified);
                let start = match self.held.take() {
                    None => add(curve.from(), self.vector),
                    Some(h) => {
                        // G41/G42 given again in offset mode (FANUC 30i §6.6, "cutter compensation
                        // G code in the offset mode"): the block before ends at its vector
                        // perpendicular to its move, "irrespective of machining inner or outer
                        // side"; this block starts there.
                        let corner = if respecified {
                            Ok(vec![h.curve.offset_point(true, h.r)])
                        } else {
                            corner(&h, &curve, r, false, self.type_b)
                        };
                        let points = match corner {
                            Ok(p) => p,
                            Err(id) => {
                                let canon = h.canon.clone();
                                self.alarm(id, &canon);
                                return;
                            }
                        };
                        self.held = Some(h);
                        self.next = Some((curve, r));
                        self.release(&points, out);
                        self.next = None;
                        if self.stopped {
                            return;
                        }
                        // (Where interference avoidance placed the vector, the block starts there.)
                        self.avoided.take().unwrap_or(points[points.len() - 1])
                    }
                };
                let startup = std::mem::replace(&mut self.startup, false);
                self.held = Some(Held { canon: c, curve, r, start, startup });
            }
            (Some(curve), false) => {
                self.finish_corner(&curve, out);
                if let Some(h) = self.held.take() {
                    let points = match toward {
                        Some(d) => Ok(cancel_toward(&h, d)),
                        None => corner(&h, &curve, h.r, true, self.type_b),
                    };
                    match points {
                        Ok(points) => {
                            self.held = Some(h);
                            self.release(&points, out);
                        }
                        Err(id) => {
                            let canon = h.canon.clone();
                            self.alarm(id, &canon);
                        }
                    }
                    if self.stopped {
                        return;
                    }
                } else {
                    self.release_perpendicular(out);
                }
                // Rule 9 holds for the cancel block too (no FANUC source exempts it): from where
                // the tool stands to its programmed end it must not run against its own move (a
                // cancel shorter than the radius after an inside corner: audit crc2 N3). The tool
                // stops at the end of the block before.
                let start = add(curve.from(), self.vector);
                let cancel = Held { canon: c, curve, r: 0.0, start, startup: false };
                if check_direction(&cancel, curve.to()).is_err() {
                    self.alarm(AlarmId::CutterInterference, &cancel.canon);
                    return;
                }
                self.cancelled();
                out.push(cancel.canon);
            }
        }
    }

    /// G39 (corner circular interpolation, FANUC 15i §14.4.9): the block before ends at its
    /// perpendicular vector (the old vector); an arc of the offset radius about the corner turns
    /// from there to the new vector — perpendicular to `direction` (I/J/K) on the side of the
    /// compensation, or, without one, perpendicular to the next block at its start (then the arc
    /// waits for that block). The next block starts at the new vector.
    fn corner_arc(&mut self, c: Canon, direction: Option<[f64; 3]>, out: &mut Vec<Canon>) {
        // A corner needs a block before it in offset mode: none since G41/G42 (or since a
        // restart after a G40 that moved nothing), or another G39 still waiting, is PS0010.
        let restarted = self.link.take_comp_start().is_some();
        if !self.on || restarted || self.startup && self.held.is_none() || self.corner.is_some() {
            self.alarm(AlarmId::ImproperGCode, &c);
            return;
        }
        self.release_perpendicular(out);
        if self.stopped {
            return;
        }
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let Some(d) = direction else {
            self.corner = Some(c);
            return;
        };
        let new = scale(curve::left(curve::unit(ijk_in_plane(d, m.context.plane))), signed_radius(m));
        self.emit_corner(c, new, out);
    }

    /// G38 vector hold (NCT 99M/2000M §14.5.5, Mitsubishi M700V §12.4): the block before ends
    /// at its corner with this block as usual; this block (a straight move) ends at its
    /// programmed point plus the vector where it starts — no corner with the block after it,
    /// which starts there — or, with `direction` (I/J/K), plus the offset value along it. A G38
    /// block that does not move in the plane keeps the corner (a block without motion in the
    /// plane); with I/J/K the block before ends at its perpendicular vector and the block moves
    /// to the new vector at its point.
    fn vector_hold(&mut self, c: Canon, direction: Option<[f64; 3]>, out: &mut Vec<Canon>) {
        // The vector held is one of offset mode: none before the first block that moved in it.
        let restarted = self.link.take_comp_start().is_some();
        if !self.on || restarted || self.startup && self.held.is_none() && self.corner.is_none() {
            self.alarm(AlarmId::ImproperGCode, &c);
            return;
        }
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let from = std::mem::replace(&mut self.programmed, m.target);
        let new = direction.map(|d| scale(curve::unit(ijk_in_plane(d, m.context.plane)), m.context.cutter_radius));
        let r = signed_radius(m);
        let Some(curve) = self.curve(m, &from) else {
            // No motion in the plane: with I/J/K the vector changes here, else a plain block.
            if let Some(new) = new {
                self.release_perpendicular(out);
                if self.stopped {
                    return;
                }
                self.vector = new;
                out.push(self.shifted(c));
            } else if self.corner.is_some() || self.held.is_some() {
                self.after.push(c);
                self.lose_vector_if_too_many(out);
            } else {
                out.push(self.shifted(c));
            }
            return;
        };
        self.finish_corner(&curve, out);
        let start = match self.held.take() {
            None => add(curve.from(), self.vector),
            Some(h) => match corner(&h, &curve, r, false, self.type_b) {
                Ok(points) => {
                    self.held = Some(h);
                    self.release(&points, out);
                    if self.stopped {
                        return;
                    }
                    points[points.len() - 1]
                }
                Err(id) => {
                    let canon = h.canon.clone();
                    self.alarm(id, &canon);
                    return;
                }
            },
        };
        self.startup = false;
        let vector = new.unwrap_or_else(|| sub(start, curve.from()));
        self.held = Some(Held { canon: c, curve, r, start, startup: false });
        self.release(&[add(curve.to(), vector)], out);
    }

    /// A waiting G39 ends perpendicular to `next` at its start.
    fn finish_corner(&mut self, next: &Curve, out: &mut Vec<Canon>) {
        let Some(c) = self.corner.take() else { return };
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let r = signed_radius(m);
        self.emit_corner(c, sub(next.offset_point(false, r), next.from()), out);
    }

    /// The G39 block `c` as the arc from the current vector to `new` about its point (the
    /// corner): clockwise for the tool on the left (G41 with a positive value), counter-clockwise
    /// on the right. Then the commands held behind it, moved by the new vector.
    fn emit_corner(&mut self, c: Canon, new: P2, out: &mut Vec<Canon>) {
        let CanonKind::Motion(m) = &c.kind else { unreachable!("motions only") };
        let corner = self.in_plane(&m.target);
        let old = self.vector;
        let clockwise = signed_radius(m) > 0.0;
        let turn = cross(old, new).atan2(dot(old, new));
        // The whole way round in the compensation's sense (at an inside corner that is more
        // than half a turn: FANUC 15i, "overcutting results").
        let sweep =
            if clockwise { -(-turn).rem_euclid(std::f64::consts::TAU) } else { turn.rem_euclid(std::f64::consts::TAU) };
        let normal = match m.context.plane {
            code::G18 => self.xyz[1],
            code::G19 => self.xyz[0],
            _ => self.xyz[2],
        };
        let (a, b) = self.plane;
        let mut c = self.placed(c, add(corner, new));
        if let CanonKind::Motion(m) = &mut c.kind {
            if sweep.abs() > 1e-12 {
                let mut center = m.target;
                center[a] = corner[0];
                center[b] = corner[1];
                m.kind = if clockwise { MotionKind::ArcCw } else { MotionKind::ArcCcw };
                m.arc = Some(Box::new(Arc {
                    center,
                    plane_axes: (a, b, normal.unwrap_or(a)),
                    radius: norm(old),
                    sweep_deg: sweep.to_degrees(),
                }));
            }
        }
        out.push(c);
        self.vector = new;
        for c in std::mem::take(&mut self.after) {
            out.push(self.shifted(c));
        }
    }

    fn cancelled(&mut self) {
        self.guard = None;
        self.on = false;
        self.startup = false;
        self.perpendicular = None;
        self.respecified = false;
        self.vector = [0.0; 2];
    }

    /// The block inserted by a start-up perpendicular to the next movement: a straight move,
    /// of the G41/G42 block `p` (its line, G00 or G01), from where the motion `c` starts
    /// (programmed at `from`) to `to` in the plane; the other axes stay where they are.
    fn inserted_before(&self, c: &Canon, from: &Pos, to: P2, p: PerpendicularStart) -> Canon {
        let mut s = c.clone();
        s.line = p.line;
        s.n = p.n;
        if let CanonKind::Motion(m) = &mut s.kind {
            for ((t, machine), f) in m.target.iter_mut().zip(m.machine.iter_mut()).zip(from) {
                *machine -= *t - f;
                *t = *f;
            }
            m.arc = None;
            m.kind = if p.rapid { MotionKind::Rapid } else { MotionKind::Linear };
        }
        self.placed(s, to)
    }

    /// More blocks without motion in the plane than the read-ahead holds: the held motion ends
    /// perpendicular, the next one starts from there (FANUC: the vector is lost).
    fn lose_vector_if_too_many(&mut self, out: &mut Vec<Canon>) {
        let Some(h) = &self.held else { return };
        if super::blocks_without_motion(&self.after, h.canon.line) > MAX_BLOCKS_BETWEEN {
            self.release_perpendicular(out);
        }
    }
}

/// I/J/K (X/Y/Z components) as the plane's two, in its order.
fn ijk_in_plane(d: [f64; 3], plane: u16) -> P2 {
    match plane {
        code::G18 => [d[2], d[0]],
        code::G19 => [d[1], d[2]],
        _ => [d[0], d[1]],
    }
}

/// G40 with I/J/K: the block before ends where its offset path meets the line along `d` from its
/// programmed end, offset to the same side — whether the corner is inside or outside. Where they
/// do not meet, or meet farther than ten radii from the corner (lines almost parallel), it ends
/// at its perpendicular vector (a decision, as for the change of side).
fn cancel_toward(h: &Held, d: P2) -> Vec<P2> {
    let e = h.curve.to();
    let line = Curve::Line { from: e, to: add(e, curve::unit(d)) };
    let near = |p: &P2| norm(sub(*p, e)) <= 10.0 * h.r.abs();
    match curve::intersection(&h.curve, h.r, &line, h.r, e).filter(near) {
        Some(p) => vec![p],
        None => vec![h.curve.offset_point(true, h.r)],
    }
}

/// Whether a motion is in offset mode: G41/G42 with an offset number other than 0. D0 is no
/// offset: in offset mode its block is an offset cancel, as a G40 block is (an arc there is
/// PS0034), and the start-up waits for a block with a D other than 0 (FANUC 15i-MA §14.3,
/// "Offset mode cancel": "0 has been commanded as the offset number"; its start-up needs
/// "0 < offset number"). It compensated by 0: the corners around it were placed as corners.
fn offsets(m: &Motion) -> bool {
    matches!(m.context.cutter_comp, code::G41 | code::G42) && m.context.d != 0
}

/// The signed offset radius of a motion: positive puts the tool on the left.
fn signed_radius(m: &Motion) -> f64 {
    let side = if m.context.cutter_comp == code::G42 { -1.0 } else { 1.0 };
    side * m.context.cutter_radius
}

/// The points of the corner between the held block `h` and the next block `next` (radius `rn`
/// for the next one): the held block's end, then the ends of the straight moves inserted, the
/// last of which is where `next` starts. `cancel`: `next` is the G40 block; `type_b`: start-up
/// and cancel of type B.
pub(super) fn corner(h: &Held, next: &Curve, rn: f64, cancel: bool, type_b: bool) -> Result<Vec<P2>, AlarmId> {
    let (a, r) = (&h.curve, h.r);
    let e = a.to();
    let (t1, t2) = (a.tangent(true), next.tangent(false));
    if r == 0.0 && rn == 0.0 {
        return Ok(vec![e]);
    }
    let turn = cross(t1, t2);
    let straight = turn.abs() < NEAR_TANGENT && dot(t1, t2) > 0.0;
    if !cancel && r.signum() != rn.signum() {
        // Change of side: where the old side's offset meets the new side's; without one, the
        // perpendicular vectors of both joined by a straight move.
        // (Blocks almost in line would put the crossing metres away: fivex takes it only within
        // ten radii of the corner, a decision, `docs/cutter-compensation.md`.)
        let near = |p: &P2| norm(sub(*p, e)) <= 10.0 * r.abs().max(rn.abs());
        return Ok(match curve::intersection(a, r, next, rn, e).filter(|p| !straight && near(p)) {
            Some(p) => vec![p],
            None => vec![a.offset_point(true, r), next.offset_point(false, rn)],
        });
    }
    if straight {
        // (Nearly) tangent continuation: where the offset tangent lines meet.
        let (n1, n2) = (curve::left(t1), curve::left(t2));
        return Ok(vec![add(e, scale(add(n1, n2), r / (1.0 + dot(n1, n2))))]);
    }
    let inner = turn * r > 0.0;
    if inner {
        // Inside a corner the offset curves meet; the next block starts there.
        return curve::intersection(a, r, next, r, e).map(|p| vec![p]).ok_or(AlarmId::CutterNoSolution);
    }
    if !type_b && cancel {
        // Cancel type A: perpendicular to the block before, then straight to the programmed end.
        return Ok(vec![a.offset_point(true, r)]);
    }
    if !type_b && h.startup {
        // Start-up type A: the vector at the end is perpendicular to the next block.
        return Ok(vec![next.offset_point(false, r)]);
    }
    let mut points = Vec::with_capacity(6);
    if h.startup {
        // Start-up type B: the start-up block ends perpendicular to itself, then the corner.
        points.push(a.offset_point(true, r));
    }
    if dot(t1, t2) >= 0.0 {
        // Outside an obtuse corner (90° ≤ α < 180°): the offset curves' intersection.
        points.push(curve::intersection(a, r, next, r, e).ok_or(AlarmId::CutterNoSolution)?);
    } else {
        // Outside an acute corner: each vector perpendicular to its block, lengthened by the
        // radius along it (forward along the first, backward along the second), joined by a
        // straight move; an arc ends (starts) at its own perpendicular vector first.
        let ra = r.abs();
        if matches!(a, Curve::Arc { .. }) {
            points.push(a.offset_point(true, r));
        }
        points.push(add(a.offset_point(true, r), scale(t1, ra)));
        points.push(sub(next.offset_point(false, r), scale(t2, ra)));
        if matches!(next, Curve::Arc { .. }) {
            points.push(next.offset_point(false, r));
        }
    }
    if cancel {
        // Cancel type B: the cancel block starts perpendicular to itself.
        points.push(next.offset_point(false, r));
    }
    points.dedup();
    Ok(points)
}

/// The avoidance vector of interference avoidance (`docs/cutter-compensation.md`, rule 9, and
/// the tool side offset's rule 12): where the offset path of `before` (block 1, the last good
/// block) crosses that of `next` (the next good block, signed radius `rn`), the crossing nearest
/// block 1's programmed end. `None` — no avoidance — where they do not cross within ten radii of
/// that end (decision, as rules 5 and 11), where block 1 ending there would itself interfere,
/// or where its path there comes within the radius of one of the `replaced` blocks (the guard).
pub(super) fn avoidance_point(before: &Held, next: &Curve, rn: f64, replaced: &[(Curve, f64)]) -> Option<P2> {
    let corner = before.curve.to();
    let near = |q: &P2| norm(sub(*q, corner)) <= 10.0 * before.r.abs().max(rn.abs());
    curve::intersection(&before.curve, before.r, next, rn, corner)
        .filter(near)
        .filter(|va| check_direction(before, *va).is_ok())
        .filter(|va| !gouges(replaced, &path_of(before, &[*va])))
}

/// The tool centre path of the released block `h` ending at `points[0]`, then straight to the
/// other points: its pieces (an arc keeps its centre; its radius may change along it).
pub(super) fn path_of(h: &Held, points: &[P2]) -> Vec<Curve> {
    let mut pieces = Vec::with_capacity(points.len());
    pieces.push(match h.curve {
        Curve::Line { .. } => Curve::Line { from: h.start, to: points[0] },
        Curve::Arc { center, sweep, .. } => Curve::Arc {
            from: h.start,
            to: points[0],
            center,
            sweep: swept(h.start, points[0], center, sweep) * sweep.signum(),
        },
    });
    for w in points.windows(2) {
        pieces.push(Curve::Line { from: w[0], to: w[1] });
    }
    pieces
}

/// The guard after an interference avoidance (`docs/cutter-compensation.md`, rule 9): some point
/// of the path `pieces` comes closer than the radius (less [`GUARD_TOLERANCE`]) to one of the
/// programmed blocks `replaced`, or lies beside one of them on the side away from the tool.
/// The path is sampled at most a hundredth of the radius apart (the sampled distance errs by
/// less than 0.1 µm near the radius).
pub(super) fn gouges(replaced: &[(Curve, f64)], pieces: &[Curve]) -> bool {
    replaced.iter().any(|(g, r)| {
        let want = r.abs() - GUARD_TOLERANCE;
        if want <= 0.0 {
            return false;
        }
        pieces.iter().any(|piece| {
            let n = ((curve::length(piece) / (r.abs() / 100.0)).ceil() as usize).clamp(8, 100_000);
            (0..=n).any(|k| curve::clearance(g, *r, curve::point_at(piece, k as f64 / n as f64)) < want)
        })
    })
}

/// The interference check (`docs/cutter-compensation.md`, rule 9): the compensated block must
/// not run against the programmed one. The direction check: from its start to its end (a line,
/// or an arc's chord) it runs more than 90° away from the programmed start to end. The arc check:
/// the compensated arc's swept angle differs from the programmed one by more than 180° (it runs
/// the other way round), or the tool does not fit inside it.
pub(super) fn check_direction(h: &Held, end: P2) -> Result<(), AlarmId> {
    let (from, to) = (h.curve.from(), h.curve.to());
    let (programmed, compensated) = (sub(to, from), sub(end, h.start));
    match h.curve {
        Curve::Line { .. } => {
            if dot(compensated, programmed) < 0.0 {
                return Err(AlarmId::CutterInterference);
            }
        }
        Curve::Arc { sweep, center, .. } => {
            if h.curve.offset_radius(h.r).is_some_and(|radius| radius <= 0.0) {
                return Err(AlarmId::CutterInterference);
            }
            let turned = swept(h.start, end, center, sweep);
            if (turned - sweep.abs()).abs() > std::f64::consts::PI {
                return Err(AlarmId::CutterInterference);
            }
            // The chord has a direction only when the arc's ends are apart (not a whole turn).
            let apart = norm(programmed) > CHORD && norm(compensated) > CHORD;
            if apart && dot(compensated, programmed) < 0.0 {
                return Err(AlarmId::CutterInterference);
            }
        }
    }
    Ok(())
}

impl Cutter {
    fn push_command(&mut self, command: Canon, out: &mut Vec<Canon>) {
        match &command.kind {
            CanonKind::Motion(_) => self.motion(command, out),
            // A block without movement: counted while a motion waits for its corner (the
            // pipeline drops it).
            CanonKind::Cutter(CutterWord::WithoutMotion) if self.held.is_some() => {
                self.after.push(command);
                self.lose_vector_if_too_many(out);
            }
            CanonKind::Cutter(CutterWord::WithoutMotion) => {}
            CanonKind::Cutter(word) => self.word = Some(*word),
            CanonKind::ProgramEnd { .. } if self.on => {
                // M02/M30 cancel: the last motion ends perpendicular, the vector stays there.
                self.release_perpendicular(out);
                self.cancelled();
                if !self.stopped {
                    out.push(command);
                }
            }
            _ if self.corner.is_some() => self.after.push(command),
            _ if self.held.is_some() => {
                self.after.push(command);
                self.lose_vector_if_too_many(out);
            }
            _ => out.push(command),
        }
    }

    /// Under interference avoidance: what one call gave (`local`) goes to `out`, the staged
    /// block in its place unless it is the last thing given and more may come.
    fn settle(&mut self, mut local: Vec<Canon>, end: bool, out: &mut Vec<Canon>) {
        let waiting = self.staged.is_some() || self.pending.is_some();
        if waiting && (end || self.stopped || local.len() > self.staged_at) {
            self.flush_staged(&mut local);
        }
        out.append(&mut local);
    }
}

impl Stage for Cutter {
    fn push(&mut self, command: Canon, out: &mut Vec<Canon>) {
        if self.stopped {
            return;
        }
        if !self.avoid {
            return self.push_command(command, out);
        }
        // (The staged block, if any, came before everything of this call.)
        self.staged_at = 0;
        let mut local = Vec::new();
        self.push_command(command, &mut local);
        self.settle(local, false, out);
    }

    fn finish(&mut self, out: &mut Vec<Canon>) {
        self.staged_at = 0;
        let mut local = Vec::new();
        if !self.stopped {
            self.release_perpendicular(&mut local);
        }
        self.settle(local, true, out);
    }

    fn take_alarm(&mut self) -> Option<(AlarmId, u32, Option<u32>)> {
        self.alarm.take()
    }

    fn passes(&self, command: &Canon) -> bool {
        // (Under interference avoidance every call goes through `settle`: not skipped.)
        let idle = !self.avoid
            && !self.on
            && !self.stopped
            && self.held.is_none()
            && self.corner.is_none()
            && self.word.is_none()
            && self.after.is_empty();
        idle && match &command.kind {
            CanonKind::Motion(m) => !offsets(m),
            CanonKind::Cutter(_) => false,
            _ => true,
        }
    }

    fn reset(&mut self) {
        self.staged = None;
        self.pending = None;
        self.guard = None;
        self.avoided = None;
        self.next = None;
        self.on = false;
        self.startup = false;
        self.perpendicular = None;
        self.respecified = false;
        self.vector = [0.0; 2];
        self.held = None;
        self.word = None;
        self.corner = None;
        self.after.clear();
        self.stopped = false;
        self.alarm = None;
        self.link.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, TAU};

    fn held(curve: Curve, r: f64, start: P2) -> Held {
        let canon = Canon { line: 1, n: None, kind: CanonKind::ProgramEnd { m: 30 }, tip_basis: Default::default() };
        Held { canon, curve, r, start, startup: false }
    }

    #[test]
    fn the_arc_check_sees_an_arc_whose_chord_turns_back() {
        // A counter-clockwise quarter circle R10 about the origin, (10,0) → (0,10), the tool (5)
        // inside: offset radius 5. Compensated from 150° to 200° on it: (−4.330, 2.5) →
        // (−4.698, −1.710). It turns 50° the right way (within 180° of the programmed 90°: the
        // swept-angle check passes), but its chord (−0.368, −4.210) against the programmed
        // (−10, 10) gives 3.68 − 42.10 < 0: more than 90° away, an interference.
        let arc = Curve::Arc { from: [10.0, 0.0], to: [0.0, 10.0], center: [0.0, 0.0], sweep: FRAC_PI_2 };
        let at = |deg: f64| [5.0 * deg.to_radians().cos(), 5.0 * deg.to_radians().sin()];
        assert_eq!(check_direction(&held(arc, 5.0, at(150.0)), at(200.0)), Err(AlarmId::CutterInterference));
        // From 30° to 100°: the chord (−5.198, 2.424) is within 90° of (−10, 10): no alarm.
        assert_eq!(check_direction(&held(arc, 5.0, at(30.0)), at(100.0)), Ok(()));
        // A whole turn has no chord: not checked by it.
        let full = Curve::Arc { from: [10.0, 0.0], to: [10.0, 0.0], center: [0.0, 0.0], sweep: TAU };
        assert_eq!(check_direction(&held(full, 5.0, at(0.0)), at(0.0)), Ok(()));
    }
}
