//! Chamfering `,C` and corner rounding `,R` between two G01/G02/G03 blocks (FANUC M series
//! "optional angle chamfering and corner R", Haas NGC G01 "corner rounding and chamfering";
//! `docs/dialects.md`, "Chamfering and corner R"): `G01 X… Y… ,C c` moves to the virtual
//! corner of this block and the next, cut short by `c` along each line from that corner (on an
//! arc, the chord `c`) and joined by a straight line; `,R r` joins them by an arc of radius `r`
//! tangent to both.
//!
//! The block cannot move until the next block is read: its move is held (the current point is
//! its corner, so that an incremental next block starts there), and the next block must be a
//! G01/G02/G03 move in the selected plane (`CornerNextBlock`, FANUC PS0051; a G00 is
//! `CornerNotG01`, PS0052). An element shorter than the chamfer or the tangent length is
//! `CornerTooShort` (PS0055). Built: line–line (closed form), line–arc, arc–line and arc–arc
//! corners in the plane, in G90/G91, under coordinate rotation and mirror image (the corner is
//! built on the transformed elements: a rigid motion keeps the lengths, and a mirrored corner
//! turns the other way) and in cutter compensation's offset mode (the stage offsets the
//! pieces), with the modes of a plain 3-axis path; every other mode is refused as not built
//! (`refuse_corner_modes`).
//!
//! The held element, the chamfer and the arc are motions of the first block (its line, sequence
//! number and F); the second block's element (from the chamfer's end) is the second block's.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, CanonKind, MotionContext, MotionKind, Pos};

/// What joins the two lines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Join {
    /// `,C`: a straight line between the points at the distance from the corner.
    Chamfer,
    /// `,R`: an arc of the radius tangent to both lines.
    Round,
}

/// Closer than this (mm) counts as the same point, and a piece this short is not emitted.
const EPS: f64 = 1e-9;

/// A G01 block with `,C`/`,R` whose move waits for the next block.
#[derive(Debug, Clone)]
pub(super) struct HeldCorner {
    join: Join,
    /// The chamfer distance or the radius, mm.
    size: f64,
    /// Where the held line starts now (its programmed start, or the end of the chamfer before
    /// it), workpiece coordinates.
    from: Pos,
    /// The block's element: its line's direction (unit), or its arc.
    elem: Elem,
    /// What is left of it before the corner: mm of a line, radians of an arc.
    avail: f64,
    /// The virtual corner: the block's end point.
    corner: Pos,
    /// The block's line, sequence number and F.
    tag: super::BlockTag,
    /// The block's modal context (its G09, cutter compensation …): the pieces are emitted while
    /// the next block runs, and carry their own block's.
    context: MotionContext,
}

/// A corner's pieces in the plane's two coordinates ([`corner`], [`corner_general`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Corner {
    /// Where the first element stops.
    pub p1: [f64; 2],
    /// Where the second element starts.
    pub p2: [f64; 2],
    /// For `,R`: the arc's center and its signed sweep (radians, positive counter-clockwise);
    /// `None` for a chamfer or where the lines go straight on (nothing to round).
    pub arc: Option<([f64; 2], f64)>,
}

/// The corner between a line arriving along `d1` (unit, `avail` mm of it left before the
/// corner) and the line from `corner` to `end`, or the alarm: the second line has no length in the plane
/// (`CornerNextBlock`), the lines turn back on themselves, or either is shorter than the
/// chamfer or the arc's tangent length (`CornerTooShort`).
pub(crate) fn corner(
    d1: [f64; 2],
    avail: f64,
    corner: [f64; 2],
    end: [f64; 2],
    join: Join,
    size: f64,
) -> Result<Corner, AlarmId> {
    let v2 = [end[0] - corner[0], end[1] - corner[1]];
    let len2 = v2[0].hypot(v2[1]);
    if len2 < EPS {
        return Err(AlarmId::CornerNextBlock);
    }
    let d2 = [v2[0] / len2, v2[1] / len2];
    let cross = d1[0] * d2[1] - d1[1] * d2[0];
    let dot = d1[0] * d2[0] + d1[1] * d2[1];
    // The turn from the first direction to the second, 0 (straight on) to π (back).
    let turn = cross.abs().atan2(dot);
    // Lines that turn straight back have no corner to cut (**decision**: the manuals are
    // silent; the chamfer would have no length and the arc no tangent points).
    if size > 0.0 && std::f64::consts::PI - turn < 1e-9 {
        return Err(AlarmId::CornerTooShort);
    }
    let t = match join {
        Join::Chamfer => size,
        Join::Round => size * (turn / 2.0).tan(),
    };
    if t > avail + EPS || t > len2 + EPS {
        return Err(AlarmId::CornerTooShort);
    }
    let p1 = [corner[0] - t * d1[0], corner[1] - t * d1[1]];
    let p2 = [corner[0] + t * d2[0], corner[1] + t * d2[1]];
    let arc = (join == Join::Round && t > EPS).then(|| {
        // The center is on the inside of the turn, `size` from the first line at p1.
        let left = cross > 0.0;
        let n = if left { [-d1[1], d1[0]] } else { [d1[1], -d1[0]] };
        let center = [p1[0] + size * n[0], p1[1] + size * n[1]];
        (center, if left { turn } else { -turn })
    });
    Ok(Corner { p1, p2, arc })
}

/// One element of a corner in the plane: a line (its direction, unit) or an arc (its center,
/// radius and turning sense).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Elem {
    Line { dir: [f64; 2] },
    Arc { center: [f64; 2], radius: f64, ccw: bool },
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

fn unit2(a: [f64; 2]) -> [f64; 2] {
    let l = norm(a);
    [a[0] / l, a[1] / l]
}

/// The angle an arc about `c` turns through from `x` to `y` in its sense, in [0, 2π).
pub(crate) fn travel(c: [f64; 2], ccw: bool, x: [f64; 2], y: [f64; 2]) -> f64 {
    let (ax, ay) = ((x[1] - c[1]).atan2(x[0] - c[0]), (y[1] - c[1]).atan2(y[0] - c[0]));
    let t = if ccw { (ay - ax).rem_euclid(std::f64::consts::TAU) } else { (ax - ay).rem_euclid(std::f64::consts::TAU) };
    // A point a hair behind `x` counts as `x` itself.
    if std::f64::consts::TAU - t < 1e-9 {
        0.0
    } else {
        t
    }
}

impl Elem {
    /// The direction of travel at `at` (a point of the element).
    fn tangent(&self, at: [f64; 2]) -> [f64; 2] {
        match *self {
            Elem::Line { dir } => dir,
            Elem::Arc { center, ccw, .. } => {
                let v = unit2(sub(at, center));
                if ccw {
                    [-v[1], v[0]]
                } else {
                    [v[1], -v[0]]
                }
            }
        }
    }

    /// How far (mm on a line, radians on an arc) the element travels from `x` to `y`; on a line
    /// negative if `y` is behind `x`.
    fn travel(&self, x: [f64; 2], y: [f64; 2]) -> f64 {
        match *self {
            Elem::Line { dir } => dot(sub(y, x), dir),
            Elem::Arc { center, ccw, .. } => travel(center, ccw, x, y),
        }
    }

    /// The point at chord `c` from `p` along the element (`forward`) or back along it.
    fn at_chord(&self, p: [f64; 2], c: f64, forward: bool) -> Result<[f64; 2], AlarmId> {
        match *self {
            Elem::Line { dir } => {
                let s = if forward { c } else { -c };
                Ok([p[0] + s * dir[0], p[1] + s * dir[1]])
            }
            Elem::Arc { center, radius, ccw } => {
                if c > 2.0 * radius + EPS {
                    return Err(AlarmId::CornerTooShort);
                }
                let phi = 2.0 * (c / (2.0 * radius)).min(1.0).asin();
                let a = if ccw == forward { phi } else { -phi };
                let (sn, cs) = a.sin_cos();
                let v = sub(p, center);
                Ok([center[0] + v[0] * cs - v[1] * sn, center[1] + v[0] * sn + v[1] * cs])
            }
        }
    }

    /// The element moved `r` to the side `s` (+1 left of the travel, −1 right): a circle's new
    /// radius (a line keeps its direction; where it passes is the caller's).
    fn offset(&self, s: f64, r: f64) -> Result<Elem, AlarmId> {
        match *self {
            Elem::Line { dir } => Ok(Elem::Line { dir }),
            Elem::Arc { center, radius, ccw } => {
                // Left of a counter-clockwise arc is toward its center.
                let radius = if (s > 0.0) == ccw { radius - r } else { radius + r };
                if radius <= EPS {
                    return Err(AlarmId::CornerTooShort);
                }
                Ok(Elem::Arc { center, radius, ccw })
            }
        }
    }

    /// Where a circle about `f` tangent to the element touches it.
    fn touch(&self, p: [f64; 2], f: [f64; 2]) -> [f64; 2] {
        match *self {
            Elem::Line { dir } => {
                let t = dot(sub(f, p), dir);
                [p[0] + t * dir[0], p[1] + t * dir[1]]
            }
            Elem::Arc { center, radius, .. } => {
                let u = unit2(sub(f, center));
                [center[0] + radius * u[0], center[1] + radius * u[1]]
            }
        }
    }
}

/// The points where a line through `a` along `d` (unit) meets a circle.
fn line_circle(a: [f64; 2], d: [f64; 2], c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    let v = sub(a, c);
    let b = dot(v, d);
    let disc = b * b - (dot(v, v) - r * r);
    if disc < 0.0 {
        return Vec::new();
    }
    let q = disc.sqrt();
    [-b - q, -b + q].iter().map(|t| [a[0] + t * d[0], a[1] + t * d[1]]).collect()
}

/// The points where two circles meet.
fn circle_circle(c1: [f64; 2], r1: f64, c2: [f64; 2], r2: f64) -> Vec<[f64; 2]> {
    let d = norm(sub(c2, c1));
    if d < EPS || d > r1 + r2 || d < (r1 - r2).abs() {
        return Vec::new();
    }
    let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let u = unit2(sub(c2, c1));
    let m = [c1[0] + a * u[0], c1[1] + a * u[1]];
    vec![[m[0] - h * u[1], m[1] + h * u[0]], [m[0] + h * u[1], m[1] - h * u[0]]]
}

/// The corner at `p` between element `e1` (with `avail` of it left before `p`: mm or radians)
/// and element `e2` (`extent` of it after `p`), where either may be an arc. A chamfer joins the
/// points at chord `size` from `p` on each (the NCT manual's rule for arcs, the distance along a
/// line); a corner R is the circle of radius `size` tangent to both on the inside of the turn
/// whose center is nearest the corner. The alarms as [`corner`].
pub(crate) fn corner_general(
    e1: Elem,
    avail: f64,
    p: [f64; 2],
    e2: Elem,
    extent: f64,
    join: Join,
    size: f64,
) -> Result<Corner, AlarmId> {
    let (t1, t2) = (e1.tangent(p), e2.tangent(p));
    let cross = t1[0] * t2[1] - t1[1] * t2[0];
    let straight = cross.abs() < 1e-9;
    if size > 0.0 && straight && dot(t1, t2) < 0.0 {
        return Err(AlarmId::CornerTooShort);
    }
    if size == 0.0 || (straight && join == Join::Round) {
        return Ok(Corner { p1: p, p2: p, arc: None });
    }
    let (q1, q2, arc) = match join {
        Join::Chamfer => (e1.at_chord(p, size, false)?, e2.at_chord(p, size, true)?, None),
        Join::Round => {
            let s = if cross > 0.0 { 1.0 } else { -1.0 };
            let (o1, o2) = (e1.offset(s, size)?, e2.offset(s, size)?);
            let shift = |e: &Elem| match *e {
                Elem::Line { dir } => [p[0] - s * size * dir[1], p[1] + s * size * dir[0]],
                Elem::Arc { .. } => p,
            };
            let (a1, a2) = (shift(&e1), shift(&e2));
            let candidates = match (o1, o2) {
                (Elem::Line { dir: d1 }, Elem::Line { dir: d2 }) => {
                    // Both lines: the crossing of the offset lines.
                    let den = d1[0] * d2[1] - d1[1] * d2[0];
                    let t = ((a2[0] - a1[0]) * d2[1] - (a2[1] - a1[1]) * d2[0]) / den;
                    vec![[a1[0] + t * d1[0], a1[1] + t * d1[1]]]
                }
                (Elem::Line { dir }, Elem::Arc { center, radius, .. }) => line_circle(a1, dir, center, radius),
                (Elem::Arc { center, radius, .. }, Elem::Line { dir }) => line_circle(a2, dir, center, radius),
                (Elem::Arc { center: c1, radius: r1, .. }, Elem::Arc { center: c2, radius: r2, .. }) => {
                    circle_circle(c1, r1, c2, r2)
                }
            };
            // Of the circles tangent to both, the one touching each element on its part next
            // to the corner, nearest the corner.
            let valid = |q1: [f64; 2], q2: [f64; 2]| {
                (-EPS..=avail + EPS).contains(&e1.travel(q1, p)) && (-EPS..=extent + EPS).contains(&e2.travel(p, q2))
            };
            let (f, q1, q2) = candidates
                .into_iter()
                .filter(|f| f[0].is_finite() && f[1].is_finite())
                .map(|f| (f, e1.touch(p, f), e2.touch(p, f)))
                .filter(|&(_, q1, q2)| valid(q1, q2))
                .min_by(|x, y| {
                    (norm(sub(x.1, p)) + norm(sub(x.2, p))).total_cmp(&(norm(sub(y.1, p)) + norm(sub(y.2, p))))
                })
                .ok_or(AlarmId::CornerTooShort)?;
            let sweep = if s > 0.0 { travel(f, true, q1, q2) } else { -travel(f, false, q1, q2) };
            (q1, q2, Some((f, sweep)))
        }
    };
    // Each point on its element's part next to the corner.
    let back = e1.travel(q1, p);
    let ahead = e2.travel(p, q2);
    if !(-EPS..=avail + EPS).contains(&back) || !(-EPS..=extent + EPS).contains(&ahead) {
        return Err(AlarmId::CornerTooShort);
    }
    Ok(Corner { p1: q1, p2: q2, arc })
}

impl State {
    /// The block's `,C`/`,R` (FANUC and Haas; Syntec refuses them as addresses not built), as
    /// (join, size in mm). A block with both is `ImproperAddress` (**decision**: FANUC's
    /// PS0009 family; one of them at a time, the sources say), a negative size too.
    fn corner_words(&self, w: &Words) -> Result<Option<(Join, f64)>, AlarmId> {
        let (c, r) = (self.value(w, b'c'), self.value(w, b'r'));
        let (join, size) = match (c, r) {
            (None, None) => return Ok(None),
            (Some(_), Some(_)) => return Err(AlarmId::ImproperAddress),
            (Some(c), None) => (Join::Chamfer, c),
            (None, Some(r)) => (Join::Round, r),
        };
        if !(size.is_finite() && size >= 0.0) {
            return Err(AlarmId::ImproperAddress);
        }
        Ok(Some((join, size)))
    }

    /// Before anything of the block is done: while a corner is held the block must be a G01
    /// move in the plane; a block with `,C`/`,R` must be a G01 block in a mode the corner is
    /// built for (`refuse`).
    pub(super) fn corner_block(&mut self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect == crate::Dialect::Syntec {
            return Ok(());
        }
        let words = self.corner_words(w)?;
        let motion = self.after_block(w, group::MOTION);
        if self.corner.is_some() {
            let g_ok = w
                .gcodes()
                .iter()
                .all(|&g| matches!(g, code::G00 | code::G01 | code::G02 | code::G03 | code::G90 | code::G91));
            // Axis words of any axis: one that moves off the plane is refused where the move is
            // known (`corner_motion`), one that stays where it is (Z0 at Z0) does not count.
            let letters_ok = w.mcodes().is_empty()
                && w.letters().all(|l| {
                    matches!(l, b'G' | b'F' | b'N' | b'I' | b'J' | b'K' | b'R' | b'c' | b'r')
                        || self.axis_of(l).is_some()
                });
            let moves = w.letters().any(|l| self.axis_of(l).is_some());
            if motion == code::G00 && moves {
                return Err(AlarmId::CornerNotG01);
            }
            if !(g_ok && letters_ok && moves && matches!(motion, code::G01 | code::G02 | code::G03)) {
                return Err(AlarmId::CornerNextBlock);
            }
        }
        if words.is_some() {
            if !matches!(motion, code::G01 | code::G02 | code::G03) {
                // On G00 nothing to chamfer (**decision**: not built).
                return Err(AlarmId::AddressNotBuilt);
            }
            self.refuse_corner_modes(w)?;
            if !w.letters().any(|l| self.axis_of(l).is_some()) {
                // A `,C`/`,R` without a move: nothing to chamfer (**decision**: PS0055).
                return Err(AlarmId::CornerTooShort);
            }
        }
        Ok(())
    }

    /// The modes the corner is not built for, refused like a function not built: cutter
    /// compensation other than in G41/G42's offset mode, TCP or a tilted plane (the tip path), G54.4, nano smoothing, G187,
    /// scaling, inverse time feed, a modal macro call.
    fn refuse_corner_modes(&self, w: &Words) -> Result<(), AlarmId> {
        let after = |group: usize| self.after_block(w, group);
        // Under cutter compensation C the corner is built on the programmed path and its pieces
        // go to the compensation stage as any other motions (FANUC offsets the chamfered path):
        // only in offset mode, G41/G42 in force before the block and no group-07 code in it
        // (the start-up and cancel blocks, G41.x/G42.x, are not built).
        let before = self.modes[group::CUTTER_COMP];
        let comp_not_built = (before != code::G40 || after(group::CUTTER_COMP) != code::G40)
            && (self.block_code(w, group::CUTTER_COMP).is_some() || !matches!(before, code::G41 | code::G42));
        let refused = self.follows_tip()
            || code::TILTED_PLANES.contains(&after(group::ROTATION))
            || code::TCP.contains(&after(group::LENGTH_COMP))
            || after(group::DYNAMIC_FIXTURE) == code::G254
            || self.wse.is_some()
            || comp_not_built
            || self.smoothing.is_some()
            || self.blend.is_some()
            // Rotation and mirror image move the lines rigidly: the corner is built on the
            // transformed lines, lengths kept. Whether scaling scales `c`/`r` no source says.
            || self.xf.scaling()
            || after(group::FEED_MODE) == code::G93
            || !self.modal_calls.is_empty()
            || self.rotary_word(w);
        if refused {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// Whether the G01 block being executed takes part in a corner (holds one or ends one).
    pub(super) fn corner_motion_block(&self, w: &Words) -> bool {
        self.cfg.dialect != crate::Dialect::Syntec && (self.corner.is_some() || w.has(b'c') || w.has(b'r'))
    }

    /// The G01/G02/G03 move of a block that ends a held corner, holds one, or both.
    pub(super) fn corner_motion(&mut self, w: &Words, programmed: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        self.check_feed()?;
        let target = self.xf.forward(&programmed);
        let (a, b, c) = self.plane_axes()?;
        let off_plane = |p: &Pos, q: &Pos| (0..p.len()).any(|i| i != a && i != b && (p[i] - q[i]).abs() > EPS);
        let xy = |p: &Pos| [p[a], p[b]];
        // The block's programmed element starts at the current point: the corner held before
        // it, if any (the corner's pieces below move the tool on to `start`).
        let line_start = self.pos;
        // This block's element (`self.arc` reads the arc from the current point).
        let elem = match self.modes[group::MOTION] {
            code::G02 | code::G03 => match self.arc(w, &target)? {
                // A full circle's corner is not built (where it starts and ends is one point).
                (_, Some(arc)) if arc.sweep_deg.abs() >= 360.0 - 1e-9 => return Err(AlarmId::GCodeNotBuilt),
                (_, Some(arc)) if !off_plane(&line_start, &target) => {
                    let sweep = arc.sweep_deg.to_radians();
                    let center = [arc.center[a], arc.center[b]];
                    (Elem::Arc { center, radius: arc.radius, ccw: sweep > 0.0 }, sweep.abs())
                }
                // A helix, or an R arc that does not move in the plane: not built / no move.
                (_, Some(_)) => return Err(AlarmId::GCodeNotBuilt),
                (_, None) => return Err(AlarmId::CornerNextBlock),
            },
            _ => {
                let len = norm(sub(xy(&target), xy(&line_start)));
                let dir = if len < EPS { [0.0, 0.0] } else { unit2(sub(xy(&target), xy(&line_start))) };
                (Elem::Line { dir }, len)
            }
        };
        let mut start = self.pos;
        if let Some(held) = self.corner.take() {
            if off_plane(&held.corner, &target) {
                return Err(AlarmId::CornerNextBlock);
            }
            if elem.1 < EPS {
                return Err(AlarmId::CornerNextBlock);
            }
            let p = xy(&held.corner);
            let k = match (held.elem, elem.0) {
                // Line–line: the closed form (its property test).
                (Elem::Line { dir }, Elem::Line { .. }) => {
                    corner(dir, held.avail, p, xy(&target), held.join, held.size)?
                }
                (e1, e2) => corner_general(e1, held.avail, p, e2, elem.1, held.join, held.size)?,
            };
            let at = |q: [f64; 2]| {
                let mut p = held.corner;
                (p[a], p[b]) = (q[0], q[1]);
                p
            };
            let (p1, p2) = (at(k.p1), at(k.p2));
            let first = out.len();
            self.as_block(held.tag, |s| {
                s.pos = held.from;
                s.emit_piece(held.elem, held.from, p1, (a, b, c), out);
                match k.arc {
                    Some((center, sweep)) => {
                        let kind = if sweep > 0.0 { MotionKind::ArcCcw } else { MotionKind::ArcCw };
                        let arc = Arc {
                            center: at(center),
                            plane_axes: (a, b, c),
                            radius: held.size,
                            sweep_deg: sweep.to_degrees(),
                        };
                        s.push_motion(kind, p2, Some(Box::new(arc)), out);
                    }
                    None if norm(sub(xy(&p2), xy(&p1))) > EPS => s.push_motion(MotionKind::Linear, p2, None, out),
                    None => {}
                }
            });
            for c in &mut out[first..] {
                if let CanonKind::Motion(m) = &mut c.kind {
                    m.context = held.context;
                }
            }
            self.pos = p2;
            start = p2;
        }
        match self.corner_words(w)? {
            Some((join, size)) => {
                if off_plane(&line_start, &target) {
                    return Err(AlarmId::GCodeNotBuilt);
                }
                if elem.1 < EPS {
                    return Err(AlarmId::CornerTooShort);
                }
                // What is left of the element after the corner before it.
                let avail = if start == line_start { elem.1 } else { elem.0.travel(xy(&start), xy(&target)) };
                self.corner = Some(Box::new(HeldCorner {
                    join,
                    size,
                    from: start,
                    elem: elem.0,
                    avail,
                    corner: target,
                    tag: self.block_tag(),
                    context: self.context(),
                }));
                // The next block starts at the corner (incremental words count from it).
                self.pos = target;
            }
            None => {
                self.emit_piece(elem.0, start, target, (a, b, c), out);
                self.pos = target;
            }
        }
        self.xf.programmed = programmed;
        Ok(())
    }

    /// A piece of an element from `from` to `to` (the current point is `from`): a line, or an
    /// arc about the element's center turning its way. Nothing if it has no length in the plane
    /// (a line off the plane still moves).
    fn emit_piece(&mut self, elem: Elem, from: Pos, to: Pos, (a, b, c): (usize, usize, usize), out: &mut Vec<Canon>) {
        let (f, t) = ([from[a], from[b]], [to[a], to[b]]);
        let moves_off = (0..from.len()).any(|i| i != a && i != b && (from[i] - to[i]).abs() > EPS);
        if norm(sub(t, f)) <= EPS && !moves_off {
            return;
        }
        match elem {
            Elem::Line { .. } => self.push_motion(MotionKind::Linear, to, None, out),
            Elem::Arc { center, radius, ccw } => {
                let turn = travel(center, ccw, f, t);
                let mut cp = from;
                (cp[a], cp[b]) = (center[0], center[1]);
                let sweep = if ccw { turn } else { -turn };
                let arc = Arc { center: cp, plane_axes: (a, b, c), radius, sweep_deg: sweep.to_degrees() };
                let kind = if ccw { MotionKind::ArcCcw } else { MotionKind::ArcCw };
                self.push_motion(kind, to, Some(Box::new(arc)), out);
            }
        }
    }

    /// The end of the text, M02/M30 or a reset with a corner held: the next move never comes.
    pub(super) fn corner_end(&mut self) -> Result<(), AlarmId> {
        if self.corner.take().is_some() {
            return Err(AlarmId::CornerNextBlock);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
        (p[0] - q[0]).hypot(p[1] - q[1])
    }

    #[test]
    fn mitsubishi_example() {
        // G91 G01 X100. ,C10. ; X100. Y100. (from X0 Y0): the chamfer from (90, 0) to
        // (100 + 10/√2, 10/√2).
        let k = corner([1.0, 0.0], 100.0, [100.0, 0.0], [200.0, 100.0], Join::Chamfer, 10.0).unwrap();
        let h = 10.0 / 2f64.sqrt();
        assert!(dist(k.p1, [90.0, 0.0]) < 1e-12);
        assert!(dist(k.p2, [100.0 + h, h]) < 1e-12);
        assert_eq!(k.arc, None);
    }

    #[test]
    fn right_angle_round() {
        // X0 Y0 → X20 Y0 ,R5 → X20 Y20: tangent points (15, 0) and (20, 5), center (15, 5), +90°.
        let k = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 20.0], Join::Round, 5.0).unwrap();
        assert!(dist(k.p1, [15.0, 0.0]) < 1e-12 && dist(k.p2, [20.0, 5.0]) < 1e-12);
        let (c, sweep) = k.arc.unwrap();
        assert!(dist(c, [15.0, 5.0]) < 1e-12);
        assert!((sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Turning right: clockwise, the center below.
        let k = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, -20.0], Join::Round, 5.0).unwrap();
        let (c, sweep) = k.arc.unwrap();
        assert!(dist(c, [15.0, -5.0]) < 1e-12 && sweep < 0.0);
    }

    #[test]
    fn alarms() {
        let too_short = corner([1.0, 0.0], 2.0, [2.0, 0.0], [2.0, 20.0], Join::Chamfer, 3.0);
        assert_eq!(too_short, Err(AlarmId::CornerTooShort));
        let second_short = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 2.0], Join::Round, 3.0);
        assert_eq!(second_short, Err(AlarmId::CornerTooShort));
        let back = corner([1.0, 0.0], 20.0, [20.0, 0.0], [10.0, 0.0], Join::Chamfer, 1.0);
        assert_eq!(back, Err(AlarmId::CornerTooShort));
        let no_move = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 0.0], Join::Chamfer, 1.0);
        assert_eq!(no_move, Err(AlarmId::CornerNextBlock));
        // Exactly the length of the line: allowed (the line is used up).
        assert!(corner([1.0, 0.0], 3.0, [3.0, 0.0], [3.0, 3.0], Join::Chamfer, 3.0).is_ok());
    }

    proptest! {
        /// Random line–line corners: the chamfer's ends lie on the lines at `c` from the
        /// corner; the arc has radius `r`, is tangent to both lines at its ends, and turns by
        /// the angle between them; the pieces join (p1 on the first line, p2 on the second).
        #[test]
        fn corners_are_exact(
            sx in -100.0..100.0f64, sy in -100.0..100.0f64,
            cx in -100.0..100.0f64, cy in -100.0..100.0f64,
            ex in -100.0..100.0f64, ey in -100.0..100.0f64,
            size in 0.0..30.0f64, round in any::<bool>(),
        ) {
            let len1 = (cx - sx).hypot(cy - sy);
            let len2 = (ex - cx).hypot(ey - cy);
            prop_assume!(len1 > 1e-3 && len2 > 1e-3);
            let d1 = [(cx - sx) / len1, (cy - sy) / len1];
            let d2 = [(ex - cx) / len2, (ey - cy) / len2];
            let join = if round { Join::Round } else { Join::Chamfer };
            let turn = (d1[0] * d2[1] - d1[1] * d2[0]).abs().atan2(d1[0] * d2[0] + d1[1] * d2[1]);
            prop_assume!(std::f64::consts::PI - turn > 1e-6);
            let t = if round { size * (turn / 2.0).tan() } else { size };
            let got = corner(d1, len1, [cx, cy], [ex, ey], join, size);
            if t > len1 + 1e-6 || t > len2 + 1e-6 {
                prop_assert_eq!(got, Err(AlarmId::CornerTooShort));
                return Ok(());
            }
            prop_assume!(t < len1 - 1e-6 && t < len2 - 1e-6);
            let k = got.unwrap();
            let tol = 1e-9 * (1.0 + t);
            // p1 on the first line, t before the corner; p2 on the second, t after it.
            prop_assert!(dist(k.p1, [cx, cy]) - t < tol && t - dist(k.p1, [cx, cy]) < tol);
            prop_assert!((dist([sx, sy], k.p1) + dist(k.p1, [cx, cy]) - len1).abs() < tol);
            prop_assert!((dist([cx, cy], k.p2) + dist(k.p2, [ex, ey]) - len2).abs() < tol);
            prop_assert!((dist(k.p2, [cx, cy]) - t).abs() < tol);
            if round && t > 1e-9 {
                let (c, sweep) = k.arc.expect("a turn is rounded");
                prop_assert!((dist(c, k.p1) - size).abs() < tol * 10.0);
                prop_assert!((dist(c, k.p2) - size).abs() < tol * 10.0);
                // Tangent: the radius at each end is perpendicular to its line.
                let r1 = [k.p1[0] - c[0], k.p1[1] - c[1]];
                let r2 = [k.p2[0] - c[0], k.p2[1] - c[1]];
                prop_assert!((r1[0] * d1[0] + r1[1] * d1[1]).abs() < 1e-7 * (1.0 + size));
                prop_assert!((r2[0] * d2[0] + r2[1] * d2[1]).abs() < 1e-7 * (1.0 + size));
                // Sweeping p1 about c by `sweep` lands on p2, and the arc leaves along d1.
                let (s, co) = sweep.sin_cos();
                let rot = [c[0] + r1[0] * co - r1[1] * s, c[1] + r1[0] * s + r1[1] * co];
                prop_assert!(dist(rot, k.p2) < 1e-7 * (1.0 + size));
                prop_assert!((sweep.abs() - turn).abs() < 1e-9);
                let tangent = if sweep > 0.0 { [-r1[1], r1[0]] } else { [r1[1], -r1[0]] };
                prop_assert!(tangent[0] * d1[0] + tangent[1] * d1[1] > 0.0);
            } else {
                prop_assert!(k.arc.is_none());
            }
        }

        /// Random corners with arcs (line–arc, arc–line, arc–arc): a chamfer's ends are on
        /// their elements at chord `c` from the corner; a corner R's ends are on their elements,
        /// `r` from its center, and the path turns smoothly there (the fillet leaves the first
        /// element along its direction and meets the second along its direction); or the
        /// corner is refused as too short.
        #[test]
        fn corners_with_arcs_are_exact(
            p in (-50.0..50.0f64, -50.0..50.0f64),
            kinds in (0..3u8),
            a1 in 0.0..std::f64::consts::TAU, a2 in 0.0..std::f64::consts::TAU,
            r1 in 5.0..80.0f64, r2 in 5.0..80.0f64,
            ccw1 in any::<bool>(), ccw2 in any::<bool>(),
            size in 0.1..8.0f64, round in any::<bool>(),
        ) {
            let p = [p.0, p.1];
            let line = |a: f64| Elem::Line { dir: [a.cos(), a.sin()] };
            // An arc through p: its center r away from p in direction a.
            let arc = |a: f64, r: f64, ccw: bool| Elem::Arc { center: [p[0] + r * a.cos(), p[1] + r * a.sin()], radius: r, ccw };
            let (e1, e2) = match kinds {
                0 => (line(a1), arc(a2, r2, ccw2)),
                1 => (arc(a1, r1, ccw1), line(a2)),
                _ => (arc(a1, r1, ccw1), arc(a2, r2, ccw2)),
            };
            let extent = |e: &Elem| if matches!(e, Elem::Line { .. }) { 1000.0 } else { 3.0 };
            let join = if round { Join::Round } else { Join::Chamfer };
            let (t1, t2) = (e1.tangent(p), e2.tangent(p));
            let cross = t1[0] * t2[1] - t1[1] * t2[0];
            prop_assume!(cross.abs() > 1e-3);
            let got = corner_general(e1, extent(&e1), p, e2, extent(&e2), join, size);
            // Where the chamfer or fillet must exist: a corner turning by 0.2–2.4 rad, a chamfer
            // under a quarter of every radius; a fillet between a line and an arc under a
            // quarter of the radius, and where it lies inside the arc's circle, under a fifth of
            // the circular segment the line cuts off (its depth R·(1 − cos φ), φ the angle
            // between the line and the arc's tangent).
            let turn = cross.abs().atan2(t1[0] * t2[0] + t1[1] * t2[1]);
            let left = cross > 0.0;
            let room = |e: &Elem| match *e {
                Elem::Line { .. } => f64::INFINITY,
                Elem::Arc { radius, ccw, .. } if ccw == left => {
                    0.2 * radius * (1.0 - turn.min(std::f64::consts::PI - turn).cos())
                }
                Elem::Arc { radius, .. } => 0.25 * radius,
            };
            let radius = |e: &Elem| if let Elem::Arc { radius, .. } = *e { radius } else { f64::INFINITY };
            let easy = (0.2..2.4).contains(&turn)
                && if round { kinds < 2 && size < room(&e1).min(room(&e2)) } else { size < 0.25 * radius(&e1).min(radius(&e2)) };
            prop_assert!(!easy || got.is_ok(), "{:?}", got);
            let Ok(k) = got else {
                prop_assert_eq!(got, Err(AlarmId::CornerTooShort));
                return Ok(());
            };
            let on = |e: &Elem, q: [f64; 2]| match *e {
                Elem::Line { dir } => (dir[0] * (q[1] - p[1]) - dir[1] * (q[0] - p[0])).abs(),
                Elem::Arc { center, radius, .. } => (dist(q, center) - radius).abs(),
            };
            prop_assert!(on(&e1, k.p1) < 1e-7 && on(&e2, k.p2) < 1e-7, "{:?}", k);
            // On the part next to the corner: before it on the first, after it on the second.
            prop_assert!(e1.travel(k.p1, p) >= -1e-9 && e1.travel(k.p1, p) <= extent(&e1) + 1e-9);
            prop_assert!(e2.travel(p, k.p2) >= -1e-9 && e2.travel(p, k.p2) <= extent(&e2) + 1e-9);
            match k.arc {
                None => {
                    prop_assert!(!round);
                    prop_assert!((dist(k.p1, p) - size).abs() < 1e-7 && (dist(k.p2, p) - size).abs() < 1e-7);
                }
                Some((f, sweep)) => {
                    prop_assert!(round);
                    prop_assert!((dist(f, k.p1) - size).abs() < 1e-7 && (dist(f, k.p2) - size).abs() < 1e-7);
                    // The fillet's direction at each end is the element's there (G1).
                    let dir_at = |q: [f64; 2]| {
                        let v = [(q[0] - f[0]) / size, (q[1] - f[1]) / size];
                        if sweep > 0.0 { [-v[1], v[0]] } else { [v[1], -v[0]] }
                    };
                    let (u1, u2) = (dir_at(k.p1), dir_at(k.p2));
                    let (w1, w2) = (e1.tangent(k.p1), e2.tangent(k.p2));
                    prop_assert!(dist(u1, w1) < 1e-6, "leaves along {:?}, element {:?}", u1, w1);
                    prop_assert!(dist(u2, w2) < 1e-6, "meets along {:?}, element {:?}", u2, w2);
                    // Turning p1 about f by the sweep gives p2.
                    let (sn, cs) = sweep.sin_cos();
                    let v = [k.p1[0] - f[0], k.p1[1] - f[1]];
                    prop_assert!(dist([f[0] + v[0] * cs - v[1] * sn, f[1] + v[0] * sn + v[1] * cs], k.p2) < 1e-7);
                    prop_assert!((cross > 0.0) == (sweep > 0.0));
                }
            }
        }
    }
}
