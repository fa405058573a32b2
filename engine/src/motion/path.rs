//! The geometry of one motion: where the axes are at each distance along it, and the speed,
//! acceleration and jerk the path may have so that no axis exceeds its own limits.
//!
//! The path parameter `s` is the FANUC feed length: the Euclidean length over every moving
//! axis, millimetres and degrees alike (a simultaneous linear and rotary move is fed at F in
//! that combined length, FANUC "feedrate for simultaneous rotary and linear axis"). Straight
//! moves are straight in axis space; arcs are circles (or spirals, when the end radius differs
//! within the tolerance) in the plane's two axes with every other axis moving in proportion.

use super::profile::{Limits, Profile};
use crate::canon::{Arc, Compensation, CuttingMove, FeedMode, Motion, MotionKind, Pos, Tapping, TipArc, TipMove};
use crate::geom::Rigid;
use crate::kin::{Kinematics, Vec3};
use crate::machine::{MotionOptions, MAX_AXES};

pub use crate::machine::AxisLimits;

impl AxisLimits {
    /// The path limits of a motion whose axis rates per unit of `s` are at most `rate[i]`:
    /// axis i moves `rate[i]` times as fast, as much accelerated and as much jerked as the path.
    fn along(&self, rate: &Pos) -> Limits {
        let mut lim = Limits { v: f64::INFINITY, a: f64::INFINITY, j: f64::INFINITY };
        for (i, &rate) in rate.iter().enumerate().take(self.count) {
            if rate > 1e-12 {
                lim.v = lim.v.min(self.v[i] / rate);
                lim.a = lim.a.min(self.a[i] / rate);
                lim.j = lim.j.min(self.j[i] / rate);
            }
        }
        lim
    }
}

/// A circle (or spiral) in the plane of axes `a`, `b`, in programming coordinates.
#[derive(Debug, Clone, PartialEq)]
struct Circle {
    a: usize,
    b: usize,
    center: (f64, f64),
    r0: f64,
    r1: f64,
    start: f64,
    /// Signed swept angle, radians.
    sweep: f64,
}

/// A circular segment's centre, the axis it turns about (unit, its sweep right-handed about
/// it) and its sweep, radians (`Segment::turn`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turn {
    pub center: TurnCenter,
    pub axis: Vec3,
    pub sweep: f64,
}

/// Where a circle's centre and axis are given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TurnCenter {
    /// A tip path's circle: the table frame.
    Tip(Vec3),
    /// A circle of the axes: their position at the centre (the other axes where the segment
    /// starts); the axis in the machine's X/Y/Z directions.
    Axes(Pos),
}

/// One motion ready for planning.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub line: u32,
    /// Serial of the block read that made it (the controller's `Executing`; 0 outside it).
    pub block: u64,
    pub n: Option<u32>,
    pub rapid: bool,
    /// Machine and programming positions at the start and the end, and the start's tangent
    /// (`from()`, `to()`, `work_from()`, `work_to()`, `start_dir()`).
    points: Points,
    /// Boxed: most segments are straight, and the queue holds hundreds of them.
    circle: Option<Box<Circle>>,
    /// A non-linear rapid: each axis's own rest-to-rest profile (`None` for axes that stay);
    /// the path parameter is then the time.
    independent: Option<Box<[Option<Profile>; MAX_AXES]>>,
    /// A path the axes follow through the kinematics: tool centre point control, tilted
    /// working planes, tool tip centre rotation.
    follow: Option<Box<Follow>>,
    /// Length of the path parameter (mm and degrees).
    pub len: f64,
    /// The speed the program asks for (override applied) and what the axes allow, per second.
    pub limits: Limits,
    /// The programmed speed before the override, and the highest the axes allow.
    programmed: f64,
    axis_speed: f64,
    /// The end's tangent and the curvatures at both ends, for the planner's corners (`None`:
    /// the end's tangent is the start's and neither end is curved, as on every straight move).
    bent: Option<Box<Bent>>,
    /// Tool tip (X, Y, Z of the programming system) distance per unit of `s`.
    pub tip_rate: f64,
    /// The motion must come to a stop at its end (G09, G61, rapids, a single-block stop).
    pub stop_after: bool,
    traits: Traits,
    /// The tool length offset in force (what a display needs to place the tip from the axes).
    pub tool_length: f64,
    /// How the trace reads the tool tip from the axes on this segment (`crate::tip`); the
    /// maker of the segment sets it (from the canonical command's).
    pub tip_basis: crate::tip::Basis,
    /// The override applied (`set_override`), for the pieces it is split into.
    factor: f64,
    /// Haas G103 P: at the end of the block this segment ends, the machine can stop within the
    /// next `block_limit` blocks (0: no such limit; `motion::planner`).
    pub block_limit: u8,
    /// Under cutter compensation: what places the point where the tool touches the contour
    /// (`Segment::cutting_point`; the executor sets it, knowing the vector the motion starts
    /// with). Boxed: most segments are not compensated.
    pub contact: Option<Box<super::contact::Contact>>,
}

/// Eight yes/no facts of a segment in one byte (the look-ahead holds hundreds of segments:
/// issue 18).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Traits(u8);

impl Traits {
    /// The feed override does not act (G63, tapping cycles).
    const FIXED_FEED: u8 = 1;
    /// A move in machine coordinates (G53, reference returns): a manual intervention's shift
    /// does not move it.
    const MACHINE_COORDINATES: u8 = 2;
    /// The next segment is the rest of this motion (a piece of a split kinematic path).
    const CONTINUED: u8 = 4;
    /// No feed of its own: it runs as fast as the axes allow (a kinematic rapid, a rotary-only
    /// move fed by the axes), so each piece at its own speed.
    const UNFED: u8 = 8;
    /// A chord of a curve whose bending caps its speed (`Motion::speed_cap`: NURBS, nano
    /// smoothing): its corners with the next chord are the curve's, which the cap has seen.
    const CHORD: u8 = 16;
    /// Cutting feed planned without look-ahead (acceleration/deceleration before
    /// interpolation off): its limits let the commanded feed come at once, no corner slows it,
    /// and the axes' interpolated positions pass through the filter after interpolation
    /// (`motion::after`; `docs/motion.md`, "Without look-ahead"). A trait rather than a field,
    /// so that G103's `Segment::block_limit` fits the segment's size.
    const AFTER_INTERPOLATION: u8 = 32;
    /// A tapping cycle's feed into the hole (`canon::Tapping::In`).
    const TAP_IN: u8 = 64;
    /// A tapping cycle's feed back out of the hole (`canon::Tapping::Out`).
    const TAP_OUT: u8 = 128;

    fn of(m: &Motion, unfed: bool) -> Traits {
        let mut t = Traits::default();
        t.set(Traits::FIXED_FEED, m.context.fixed_feed);
        t.set(Traits::MACHINE_COORDINATES, m.kind == MotionKind::MachineRapid);
        t.set(Traits::UNFED, unfed);
        t.set(Traits::CHORD, m.speed_cap.is_finite());
        t.set(Traits::TAP_IN, m.context.tapping == Tapping::In);
        t.set(Traits::TAP_OUT, m.context.tapping == Tapping::Out);
        t
    }

    fn has(self, which: u8) -> bool {
        self.0 & which != 0
    }

    fn set(&mut self, which: u8, on: bool) {
        if on {
            self.0 |= which;
        } else {
            self.0 &= !which;
        }
    }
}

/// A segment's positions and its start tangent, each of every axis: kept for the first
/// [`INLINE_AXES`] axes (a five-axis machine's), the others boxed only where one of them is not
/// +0.0 (a machine of more axes). The planner's look-ahead holds hundreds of segments per
/// controller (issue 18): five positions of eight axes were 320 of a segment's 512 bytes, three
/// eighths of them zeros. Every number reads back bit for bit as it was set.
#[derive(Debug, Clone)]
struct Points {
    head: [[f64; INLINE_AXES]; ROWS],
    rest: Option<Box<[[f64; MAX_AXES - INLINE_AXES]; ROWS]>>,
}

/// The axes a segment keeps inline.
const INLINE_AXES: usize = 5;

/// The rows of [`Points`].
const ROWS: usize = 5;
const FROM: usize = 0;
const TO: usize = 1;
const WORK_FROM: usize = 2;
const WORK_TO: usize = 3;
const START_DIR: usize = 4;

impl Points {
    fn new(rows: [&Pos; ROWS]) -> Points {
        let mut points = Points { head: [[0.0; INLINE_AXES]; ROWS], rest: None };
        for (row, p) in rows.into_iter().enumerate() {
            points.set(row, p);
        }
        points
    }

    fn get(&self, row: usize) -> Pos {
        let mut p = [0.0; MAX_AXES];
        p[..INLINE_AXES].copy_from_slice(&self.head[row]);
        if let Some(rest) = &self.rest {
            p[INLINE_AXES..].copy_from_slice(&rest[row]);
        }
        p
    }

    fn set(&mut self, row: usize, p: &Pos) {
        self.head[row].copy_from_slice(&p[..INLINE_AXES]);
        let tail = &p[INLINE_AXES..];
        match &mut self.rest {
            Some(rest) => rest[row].copy_from_slice(tail),
            // Bit for bit: a -0.0 is kept.
            None if tail.iter().any(|x| x.to_bits() != 0) => {
                let mut rest = Box::new([[0.0; MAX_AXES - INLINE_AXES]; ROWS]);
                rest[row].copy_from_slice(tail);
                self.rest = Some(rest);
            }
            None => {}
        }
    }
}

/// As the positions compare (boxed or not).
impl PartialEq for Points {
    fn eq(&self, other: &Points) -> bool {
        (0..ROWS).all(|row| self.get(row) == other.get(row))
    }
}

/// d(axis)/ds at the end of a segment and d²(axis)/ds² at both ends (zero on a line; toward the
/// centre on an arc), where they are not the start's tangent and zeros: the planner's
/// look-ahead holds hundreds of segments, and 192 bytes of each would otherwise repeat one
/// tangent and zeros. The numbers are the ones given, bit for bit.
#[derive(Debug, Clone, PartialEq)]
struct Bent {
    end_dir: Pos,
    start_curvature: Pos,
    end_curvature: Pos,
}

const NO_CURVATURE: Pos = [0.0; MAX_AXES];

impl Bent {
    /// `None` where the end's tangent is `start_dir` and neither end is curved.
    fn of(start_dir: &Pos, end_dir: Pos, start_curvature: Pos, end_curvature: Pos) -> Option<Box<Bent>> {
        // Bit for bit (a -0.0 is kept as given).
        let same = |a: &Pos, b: &Pos| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        let straight =
            same(start_dir, &end_dir) && same(&start_curvature, &NO_CURVATURE) && same(&end_curvature, &NO_CURVATURE);
        (!straight).then(|| Box::new(Bent { end_dir, start_curvature, end_curvature }))
    }
}

/// A tool tip path in the table frame and how the tool turns along it; the machine axes at each
/// point come from the kinematics (`Kinematics::carriage_for`).
#[derive(Debug, Clone, PartialEq)]
struct Follow {
    kin: std::sync::Arc<Kinematics>,
    tool_length: f64,
    from: Vec3,
    to: Vec3,
    circle: Option<Circle3>,
    posture: Option<Posture>,
    /// Why the rotary axes turn in proportion although the block asked otherwise (`None`: they
    /// do not, or it did not).
    fallback: Option<Fallback>,
    /// G54.4 tool direction compensation along the way (when there is no posture).
    compensation: Option<Compensation>,
    /// Cutting point control: `from`/`to`/`circle` are the cutting point's path, the tip is
    /// away from it by the block's vector (`cutting_point::Along`).
    cutting: Option<Box<Cutting>>,
    /// The programming coordinate system in the table frame; `None`: the programming
    /// coordinates keep their offset from the machine's (a manual tip rotation outside tool
    /// centre point control).
    work_frame: Option<Rigid>,
    /// The display shows the tip in machine directions minus this instead (FANUC DET = 1).
    display_shift: Option<Vec3>,
    /// The highest path speed the program's tolerance allows (FANUC CRS), and the curve a
    /// chord belongs to (`Motion::speed_cap`); infinite without.
    speed_cap: f64,
    /// The axes' speeds are held below the machine's — the rotary axes to a share of theirs
    /// (G54.4, No.11202/11203), every axis of a manual tip rotation to its manual rapid rate
    /// (No.1424, `Segment::tip_rotation`): only the segment's own limits know it, so the
    /// planner plans it with them, not against the machine's axes at every point.
    clamped: bool,
    /// The path's stretches with limits of their own (empty: one for the whole path); the
    /// planner queues each as a segment (`Segment::split`).
    pieces: Box<[Piece]>,
    /// The path is the unturned tip's (`TipMove::head_fixed`: no TCP), not the tool tip's.
    head_fixed: bool,
}

/// Cutting point control along a (part of a) block: `u` of the way is `lo + u·(hi − lo)` of
/// the block's `along`.
#[derive(Debug, Clone, PartialEq)]
struct Cutting {
    along: crate::cutting_point::Along,
    lo: f64,
    hi: f64,
}

/// A circle (or spiral, or helix) in space: at `u` of the way, `center + r(u)·(cos φ·e1 +
/// sin φ·e2) + u·rise` with φ = `u·sweep`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Circle3 {
    center: Vec3,
    e1: Vec3,
    e2: Vec3,
    r0: f64,
    r1: f64,
    sweep: f64,
    rise: Vec3,
}

impl Circle3 {
    fn new(arc: &TipArc, from: &Vec3, to: &Vec3) -> Circle3 {
        let n = arc.normal.normalize();
        let along = |p: &Vec3| n * n.dot(&(p - arc.center));
        let start = from - arc.center - along(from);
        let end = to - arc.center - along(to);
        let e1 = start.try_normalize(1e-12).unwrap_or_else(|| n.cross(&Vec3::x()).normalize());
        Circle3 {
            center: arc.center + along(from),
            e1,
            e2: n.cross(&e1),
            r0: start.norm(),
            r1: end.norm(),
            sweep: arc.sweep_deg.to_radians(),
            rise: along(to) - along(from),
        }
    }

    fn at(&self, u: f64) -> Vec3 {
        let (sin, cos) = (self.sweep * u).sin_cos();
        let r = self.r0 + (self.r1 - self.r0) * u;
        self.center + (self.e1 * cos + self.e2 * sin) * r + self.rise * u
    }

    /// At `u` of the way: the unit direction from the point toward the centre, the unit travel
    /// direction in the plane (perpendicular to it, along the sweep) and the plane's normal.
    fn axes_at(&self, u: f64) -> (Vec3, Vec3, Vec3) {
        let (sin, cos) = (self.sweep * u).sin_cos();
        let radial = self.e1 * cos + self.e2 * sin;
        let travel = (self.e2 * cos - self.e1 * sin) * self.sweep.signum();
        (-radial, travel, self.e1.cross(&self.e2))
    }

    /// Length in the plane (mean radius) and along the normal.
    fn lengths(&self) -> (f64, f64) {
        (0.5 * (self.r0 + self.r1) * self.sweep.abs(), self.rise.norm())
    }
}

/// Tool posture control: how the tool direction turns along the path.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Posture {
    /// The great circle from `v0` to `v1`, `angle` apart (spec M-7).
    Great { v0: Vec3, v1: Vec3, angle: f64 },
    /// FANUC on a circle (M-8): the angles of the tool to the centre direction (`alpha`) and to
    /// the travel direction (`beta`), radians, go linearly from start to end; the tool stays on
    /// the `sigma` side of the plane.
    Arc { alpha: [f64; 2], beta: [f64; 2], sigma: f64 },
}

impl Posture {
    /// `None` when the two are equal or opposite (FANUC: conventional control in that block).
    fn new(v0: Vec3, v1: Vec3) -> Option<Posture> {
        let (v0, v1) = (v0.try_normalize(1e-12)?, v1.try_normalize(1e-12)?);
        let angle = v0.dot(&v1).clamp(-1.0, 1.0).acos();
        (angle > 1e-9 && angle < std::f64::consts::PI - 1e-9).then_some(Posture::Great { v0, v1, angle })
    }

    /// The posture `tip` asks for from direction `v0` to `v1`: on its circle by the arc rule
    /// where the dialect has one, else the great circle.
    fn of(tip: &TipMove, circle: Option<&Circle3>, (v0, v1): (Vec3, Vec3)) -> Option<Posture> {
        match circle {
            Some(c) if tip.posture_on_arc => Posture::on_arc(v0, v1, c),
            _ => Posture::new(v0, v1),
        }
    }

    /// The arc rule on `circle` (also `None` for equal or opposite directions, TCP-27). The
    /// tool stays on the side of the plane it starts on (the interpreter has refused directions
    /// on both sides, P/S0432). *Decision* (Q-7): a start or end direction in the plane has no
    /// side; the formula's out-of-plane part `√(1 − cos²α − cos²β)` would then change at an
    /// infinite rate there (no feed could follow it), so such a block turns on the great
    /// circle as a line does.
    fn on_arc(v0: Vec3, v1: Vec3, circle: &Circle3) -> Option<Posture> {
        let great = Posture::new(v0, v1)?;
        let (v0, v1) = (v0.normalize(), v1.normalize());
        let n = circle.e1.cross(&circle.e2);
        if v0.dot(&n).abs() < 1e-6 || v1.dot(&n).abs() < 1e-6 {
            return Some(great);
        }
        let angles = |v: Vec3, u: f64| {
            let (centre, travel, _) = circle.axes_at(u);
            (v.dot(&centre).clamp(-1.0, 1.0).acos(), v.dot(&travel).clamp(-1.0, 1.0).acos())
        };
        let ((a0, b0), (a1, b1)) = (angles(v0, 0.0), angles(v1, 1.0));
        Some(Posture::Arc { alpha: [a0, a1], beta: [b0, b1], sigma: v0.dot(&n).signum() })
    }

    /// The direction `u` of the way (M-7: `[sin((1−u)Ω)·v0 + sin(uΩ)·v1] / sin Ω`; M-8:
    /// `cos α·c + cos β·τ + σ·√(1 − cos²α − cos²β)·n` on `circle`).
    fn at(&self, u: f64, circle: Option<&Circle3>) -> Vec3 {
        match (self, circle) {
            (Posture::Great { v0, v1, angle }, _) => {
                ((v0 * ((1.0 - u) * angle).sin() + v1 * (u * angle).sin()) / angle.sin()).normalize()
            }
            (Posture::Arc { alpha, beta, sigma }, Some(c)) => {
                let (centre, travel, n) = c.axes_at(u);
                let ca = (alpha[0] + (alpha[1] - alpha[0]) * u).cos();
                let cb = (beta[0] + (beta[1] - beta[0]) * u).cos();
                let up = (1.0 - ca * ca - cb * cb).max(0.0).sqrt();
                (centre * ca + travel * cb + n * (sigma * up)).normalize()
            }
            // An arc rule always comes with its circle.
            (Posture::Arc { .. }, None) => Vec3::z(),
        }
    }

    /// Keep what is left after `u` of the way; `false`: nothing left to turn.
    fn cut(&mut self, u: f64, circle: Option<&Circle3>) -> bool {
        let v = self.at(u, circle);
        match self {
            Posture::Great { v0, angle, .. } => {
                *v0 = v;
                *angle *= 1.0 - u;
                *angle > 1e-12
            }
            Posture::Arc { alpha, beta, .. } => {
                alpha[0] += (alpha[1] - alpha[0]) * u;
                beta[0] += (beta[1] - beta[0]) * u;
                true
            }
        }
    }

    /// Keep what comes before `u` of the way; `false`: nothing left to turn.
    fn keep_to(&mut self, u: f64, circle: Option<&Circle3>) -> bool {
        let v = self.at(u, circle);
        match self {
            Posture::Great { v1, angle, .. } => {
                *v1 = v;
                *angle *= u;
                *angle > 1e-12
            }
            Posture::Arc { alpha, beta, .. } => {
                alpha[1] = alpha[0] + (alpha[1] - alpha[0]) * u;
                beta[1] = beta[0] + (beta[1] - beta[0]) * u;
                true
            }
        }
    }

    /// What keeps the axes from following the posture from `from` to `to` as `Follow::at`
    /// turns them (the inverse solution nearest the proportional angles) without a jump (`None`:
    /// nothing); such a block runs with conventional control, as for equal or opposite
    /// directions (`docs/five-axis.md`).
    fn hindrance(&self, kin: &Kinematics, from: &Pos, to: &Pos, circle: Option<&Circle3>) -> Option<PostureFallback> {
        hindrance(kin, from, to, |u| self.at(u, circle))
    }
}

/// Why a block that asks for tool posture control runs with conventional control (the rotary
/// axes in proportion) although its end directions are neither equal nor opposite. The manuals
/// do not say what the control does there: the fallback is fivex's own rule, so a run tells the
/// user (`crate::notice`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PostureFallback {
    /// The way leaves the directions the rotary axes reach, or comes within `EDGE` of their edge.
    Reach,
    /// The axes would have to jump to the other branch of the inverse.
    Branch,
}

/// Why a block's rotary axes turn in proportion between its end points although it asked for
/// another way, by a rule of fivex's own (`crate::notice`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// Tool posture control, and why it is not followed.
    Posture(PostureFallback),
    /// G54.4's tool direction compensation, which is not followed along the block (an end at
    /// or near the singular posture, an axis the singular-posture rule held, or a step) where
    /// it differs from the axes in proportion by more than 0.001°.
    Compensation,
}

/// Whether the tool can turn on the great circle from its direction at `from` to that at `to`
/// (tool posture control on a line, Syntec's tool-vector interpolation) with the axes following
/// it continuously; `true` also when there is nothing to turn.
pub(crate) fn great_circle_continuous(kin: &Kinematics, from: &Pos, to: &Pos) -> bool {
    let (v0, v1) = (kin.forward(from, 0.0).tool, kin.forward(to, 0.0).tool);
    Posture::new(v0, v1).is_none_or(|p| p.hindrance(kin, from, to, None).is_none())
}

/// What keeps the axes from following the tool direction `direction(u)` from `from` to `to`
/// as `Follow::at` turns them (the inverse solution nearest the proportional angles): leaving
/// the directions the machine reaches, or a jump to another branch of the inverse.
fn hindrance(kin: &Kinematics, from: &Pos, to: &Pos, direction: impl Fn(f64) -> Vec3) -> Option<PostureFallback> {
    /// More than this in 1/64 of the block is a jump to the other branch.
    const JUMP_DEG: f64 = 30.0;
    if !within_reach(kin, &direction) {
        Some(PostureFallback::Reach)
    } else {
        (!no_jump(kin, from, to, &direction, JUMP_DEG)).then_some(PostureFallback::Branch)
    }
}

/// Whether `direction(u)` stays among the directions the rotary axes reach
/// (`Kinematics::reach`) all the way. Looking at every 1/64 of the block is not enough: a
/// random great circle left them for 1.5 % of its way, between two looks, and the axes jumped
/// 3° in a millisecond on each side. A smooth way leaves them around a least distance to
/// their edge, so each sampled dip of that distance is followed down to its bottom.
fn within_reach(kin: &Kinematics, direction: &impl Fn(f64) -> Vec3) -> bool {
    /// Nearer the edge than this (a dot product; about 0.06° there) the axes' derivatives grow
    /// as 1/√ of the distance to it, without bound on the edge: with only rounding kept off
    /// it, a random block ran an axis's jerk 5 % over its limit even on the finest grid
    /// (`Grid::fine`), one ending on the edge 50 % on the usual grid.
    const EDGE: f64 = 1e-3;
    let Some(reach) = kin.reach() else { return true };
    let slack = |u: f64| reach.slack(&direction(u).normalize());
    let at: Vec<f64> = (0..=STEPS).map(|k| slack(k as f64 / STEPS as f64)).collect();
    if at.iter().any(|s| *s < EDGE) {
        return false;
    }
    dips(&at).into_iter().all(|(lo, hi)| crate::golden::least(slack, lo, hi, 48) >= EDGE)
}

/// Where a function sampled at every 1/[`STEPS`] of a block (`at`) may dip below its samples:
/// the span about each sample no higher than its neighbours, to be followed down to its bottom.
/// A dip at an end lies between it and its neighbour (a way passing the singular posture within
/// the last 64th and ending beyond it: a random head-table machine stepped B 180° there).
fn dips(at: &[f64]) -> Vec<(f64, f64)> {
    let step = 1.0 / STEPS as f64;
    let lower = |k: usize, j: Option<usize>| j.and_then(|j| at.get(j)).is_none_or(|&a| at[k] <= a);
    (0..at.len())
        .filter(|&k| lower(k, k.checked_sub(1)) && lower(k, Some(k + 1)))
        .map(|k| (k.saturating_sub(1) as f64 * step, (k + 1).min(STEPS) as f64 * step))
        .collect()
}

/// As `continuous`, and steady enough to plan (G54.4's recomputed direction): no 1/64 of the
/// block turns an axis more than four even shares of the largest rotary travel. Leaving an
/// exactly singular posture the workpiece-side axis has to stand at the new direction's azimuth
/// at once (seed §2.3.11: it "may make a large motion"); a step like that falls between the
/// segment's limit samples, so such a block turns its axes in proportion instead.
fn steady(kin: &Kinematics, from: &Pos, to: &Pos, direction: impl Fn(f64) -> Vec3) -> bool {
    let travel = kin.joints().iter().filter_map(|j| j.index).map(|i| (to[i] - from[i]).abs()).fold(0.0, f64::max);
    within_reach(kin, &direction)
        && steps_within(kin, from, to, &direction, (4.0 * travel / STEPS as f64 + 1e-6).min(30.0))
}

const STEPS: usize = 64;

/// The axes at `u` of the block as `Follow::at` turns them for `direction(u)`.
fn angles_at(kin: &Kinematics, from: &Pos, to: &Pos, direction: &impl Fn(f64) -> Vec3, u: f64) -> Option<Pos> {
    let q: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * u);
    kin.angles_near(direction(u), &q)
}

/// The largest rotary step between two sets of axes.
fn largest_step(kin: &Kinematics, a: &Pos, b: &Pos) -> f64 {
    kin.joints().iter().filter_map(|j| j.index).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

/// Where the axes are looked at along a block ([`steps_within`], [`no_jump`]): every
/// 1/[`STEPS`] of it, and where `direction(u)` comes nearest the singular posture between two of
/// those. A way passing within a hair of the posture needs the free axis to turn half round
/// within that hair, and the inverse solution nearest the proportional angles changes branch
/// there; between two looks that went unseen, and the axes stepped (a random head-head: A by
/// 180° in a millisecond, with no notice). Each sampled dip of the tool's lean off the
/// posture's line is followed down to its bottom ([`dips`]).
fn checkpoints(kin: &Kinematics, direction: &impl Fn(f64) -> Vec3) -> Vec<f64> {
    let mut out: Vec<f64> = (1..=STEPS).map(|k| k as f64 / STEPS as f64).collect();
    let Some(joint) = kin.singular_joint() else { return out };
    // The sine of the lean: exact near the posture, where its cosine keeps no digits.
    let lean = |u: f64| direction(u).normalize().cross(&joint.direction).norm();
    let at: Vec<f64> = (0..=STEPS).map(|k| lean(k as f64 / STEPS as f64)).collect();
    for (lo, hi) in dips(&at) {
        let (u, _) = crate::golden::bottom(lean, lo, hi, 60);
        // (A way that ends nearest the posture has its bottom at the end, looked at already.)
        if u > 1e-9 && u < 1.0 - 1e-9 {
            out.push(u);
        }
    }
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// Whether the inverse solution nearest the proportional angles for `direction(u)` exists at
/// every [`checkpoints`] of the block and no rotary axis moves more than `limit_deg` between two of
/// them.
fn steps_within(kin: &Kinematics, from: &Pos, to: &Pos, direction: &impl Fn(f64) -> Vec3, limit_deg: f64) -> bool {
    let mut prev = *from;
    for u in checkpoints(kin, direction) {
        let Some(a) = angles_at(kin, from, to, direction, u) else { return false };
        if largest_step(kin, &a, &prev) > limit_deg {
            return false;
        }
        prev = a;
    }
    true
}

/// As [`steps_within`] with `limit_deg`, and no smaller jump either: a step of more than
/// 5° is halved 16 times; a steep but continuous turn shrinks with it, a change of inverse
/// branch keeps its size (random machines found a 28° jump of A inside a block). Nor does the
/// free axis step at the singular posture: no machine turns it in no time (a block from or to
/// the posture turns it first or last, `singular_turns`; one that would step near it runs with
/// conventional control, and says so).
fn no_jump(kin: &Kinematics, from: &Pos, to: &Pos, direction: &impl Fn(f64) -> Vec3, limit_deg: f64) -> bool {
    const STEEP_DEG: f64 = 5.0;
    let at = |u: f64| angles_at(kin, from, to, direction, u);
    let mut prev = (0.0, *from);
    for u in checkpoints(kin, direction) {
        let Some(a) = at(u) else { return false };
        let step = largest_step(kin, &a, &prev.1);
        if step > limit_deg {
            return false;
        }
        if step > STEEP_DEG {
            let (mut lo, mut hi) = (prev, (u, a));
            for _ in 0..16 {
                let mid_u = 0.5 * (lo.0 + hi.0);
                let Some(mid) = at(mid_u) else { return false };
                // Keep the half that holds the larger step.
                if largest_step(kin, &mid, &lo.1) >= largest_step(kin, &hi.1, &mid) {
                    hi = (mid_u, mid);
                } else {
                    lo = (mid_u, mid);
                }
            }
            if largest_step(kin, &hi.1, &lo.1) > 1.0 {
                return false;
            }
        }
        prev = (u, a);
    }
    true
}

/// The tool direction of G54.4's compensation `u` of the way.
fn compensated(kin: &Kinematics, c: &Compensation, u: f64) -> Vec3 {
    let q: Pos = std::array::from_fn(|i| c.from[i] + (c.to[i] - c.from[i]) * u);
    c.turn * kin.forward(&q, 0.0).tool
}

/// How tool posture control turns the tool along a tip path from `from` to `to` (`Ok(None)`:
/// the rotary axes in proportion, as asked or for equal or opposite directions; `Err`: in
/// proportion although posture control was asked for, and why).
fn posture_along(
    kin: &Kinematics,
    tip: &TipMove,
    circle: Option<&Circle3>,
    from: &Pos,
    to: &Pos,
) -> Result<Option<Posture>, PostureFallback> {
    let Some(p) = tip.posture.and_then(|ends| Posture::of(tip, circle, ends)) else { return Ok(None) };
    // Both ends at the singular posture (within `AT_POLE_DEG`, the tool turning by at most twice
    // that): the directions count as equal or opposite. Followed, the way reached the end's
    // free axis only by a step (random machines: A by 3·10⁻⁵° in a millisecond, a linear axis
    // at twice its jerk).
    if at_pole(kin, from).is_some() && at_pole(kin, to).is_some() {
        return Ok(None);
    }
    let hindrance = p
        .hindrance(kin, from, to, circle)
        .or_else(|| free_axis_steps_at_an_end(kin, &p, circle, from, to).then_some(PostureFallback::Branch));
    match hindrance {
        // The rotary axes in proportion may turn the tool on the posture's own way (a
        // nutating head turning a horizontal tool on the edge of its reach): nothing differs.
        Some(_) if off_proportional(kin, from, to, |u| p.at(u, circle), STEPS) < 1e-8 => Ok(None),
        Some(why) => Err(why),
        None => Ok(Some(p)),
    }
}

/// Tool posture control from or to the singular posture (TV-43: B0 C30 → B90 C0 on head-bc).
/// There the free axis (`Kinematics::singularity`) has no angle of its own, yet the tool leaves
/// (or reaches) the posture along its way only with that axis at one angle: the axes following
/// the way stepped to it within one interpolation period (C by 30° in a millisecond, found
/// when the notices made such blocks visible). The machine turns the free axis there instead,
/// the tip standing — at the singular posture that does not turn the tool; within
/// [`AT_POLE_DEG`] of it the turn also takes the tool onto the posture — before (or after) the
/// way. `None` when neither end needs such a turn or the way cannot be followed from there
/// (tool posture control then decides as without this).
pub(crate) fn singular_turns(kin: &Kinematics, tip: &TipMove, from: &Pos, to: &Pos) -> Option<SingularTurns> {
    /// How far the turn's other axes may lie from the end's (degrees): the way followed from
    /// the other end must come back to this end's angles, not to an equivalent pair.
    const SAME_DEG: f64 = 1e-2;
    let (v0, v1) = tip.posture?;
    if tip.cutting.is_some() || tip.compensation.is_some() {
        return None;
    }
    at_pole(kin, from).or_else(|| at_pole(kin, to))?;
    let free_joint = kin.singular_joint()?;
    let free = free_joint.index?;
    let circle = tip.arc.as_ref().map(|a| Circle3::new(a, &tip.from, &tip.to));
    let posture_of = |ends: (Vec3, Vec3)| Posture::of(tip, circle.as_ref(), ends);
    // An end within `AT_POLE_DEG` of the posture counts as on it: the way from (to) the posture
    // itself, whose direction near it sets the free axis's angle.
    let pole = |v: Vec3| free_joint.direction * v.dot(&free_joint.direction).signum();
    let (p0, p1) = (at_pole(kin, from).map_or(v0, |_| pole(v0)), at_pole(kin, to).map_or(v1, |_| pole(v1)));
    let posture = posture_of((p0, p1))?;
    // The axes along the way from `start` (at `u0`) to the other end, each point's inverse
    // solution nearest the last; the last steps shrink geometrically, since near the singular
    // posture the free axis turns fastest. At the posture itself the axes have no inverse of
    // their own: their limit there is extrapolated from the last two points (the angles are
    // smooth in the tool's distance from the posture; where the axes are not square to each
    // other the free axis still turns along the way, and the last point alone left it 10⁻⁶°
    // from the way's own start — a step a linear axis read as 5 % over its jerk).
    let follow = |start: &Pos, u0: f64, u1: f64| -> Option<Pos> {
        let even = (1..256).map(|k| k as f64 / 256.0);
        let near_end = (1..=13).map(|k| 1.0 - 2f64.powi(-k) / 256.0);
        let (mut before, mut q) = (*start, *start);
        for t in even.chain(near_end) {
            (before, q) = (q, kin.angles_near(posture.at(u0 + (u1 - u0) * t, circle.as_ref()), &q)?);
        }
        Some(std::array::from_fn(|i| 2.0 * q[i] - before[i]))
    };
    // `end` turned onto the posture `pole` itself, the free axis where the way followed to it
    // has it (`q`), so that the way leaves (reaches) the posture exactly, its axes' limit there
    // its first (last) point (`None`: already there). At the posture that turns only the free
    // axis; within `AT_POLE_DEG` of it the other axis too, by a hair. (Turning only the free
    // axis until the tool's lean off the posture lay along the way, as fivex did until
    // 2026-11-30, left the way's end 10⁻⁹ rad off the posture, where the inverse keeps fewer
    // digits: its last point stepped 10⁻⁷° from the way's limit, a linear axis 6 % over its
    // jerk.)
    let turned = |end: &Pos, q: Pos, pole: Vec3| -> Option<Option<Pos>> {
        let joints = kin.joints();
        let mut others = joints.iter().filter_map(|j| j.index).filter(|&i| i != free);
        if !others.all(|i| (q[i] - end[i]).abs() < SAME_DEG) {
            return None;
        }
        let on = kin.angles_near(pole, &q)?;
        let mut at = *end;
        for i in joints.iter().filter_map(|j| j.index) {
            at[i] = on[i];
        }
        Some((largest_step(kin, &at, end) > 1e-9).then_some(at))
    };
    let lead = match at_pole(kin, from) {
        Some(_) => turned(from, follow(to, 1.0, 0.0)?, p0)?,
        None => None,
    };
    let start = lead.unwrap_or(*from);
    let trail = match at_pole(kin, to) {
        Some(_) => turned(to, follow(&start, 0.0, 1.0)?, p1)?,
        None => None,
    };
    if lead.is_none() && trail.is_none() {
        return None;
    }
    // The way between the directions the turns leave the tool in.
    let way = (kin.forward(&start, 0.0).tool, kin.forward(&trail.unwrap_or(*to), 0.0).tool);
    let p = posture_of(way)?;
    p.hindrance(kin, &start, &trail.unwrap_or(*to), circle.as_ref()).is_none().then_some(SingularTurns {
        lead,
        trail,
        way,
    })
}

/// The tool's angle (radians) off the posture's line `pole`, either side.
fn lean_off(pole: Vec3, v: Vec3) -> f64 {
    v.normalize().dot(&pole).abs().min(1.0).acos()
}

/// An end (`end`: 0 or 1) of a way within [`LEAN_READ`] of the singular posture, its middle not
/// (`Follow::free_off_pole`): the free axis's index, where the way is [`LEAN_READ`] off the
/// posture (a share of it) and the free axis's angle there. `None` elsewhere.
fn pole_end(
    kin: &Kinematics,
    posture: &Posture,
    circle: Option<&Circle3>,
    from: &Pos,
    to: &Pos,
    end: f64,
) -> Option<(usize, f64, f64)> {
    let joint = kin.singular_joint()?;
    let off = |u: f64| lean_off(joint.direction, posture.at(u, circle));
    if off(end) >= LEAN_READ || off(0.5) < LEAN_READ {
        return None;
    }
    let (mut near, mut far) = (end, 0.5);
    for _ in 0..60 {
        let mid = 0.5 * (near + far);
        if off(mid) < LEAN_READ {
            near = mid;
        } else {
            far = mid;
        }
    }
    let q: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * far);
    let there = kin.angles_near(posture.at(far, circle), &q)?;
    let i = joint.index?;
    Some((i, far, there[i]))
}

/// Whether the free axis has to turn at an end of the way within [`LEAN_READ`] of the singular
/// posture (`pole_end`, where the tool turns by less than 10⁻⁶ rad) far more than over the same
/// share of the way next to it: a step. An end on the posture itself is turned onto with the
/// way's own free axis (`singular_turns`), and where the axes are not square the free axis turns
/// along the way evenly there; one a hair off the posture, on a random machine whose tool axis
/// kept it from the posture by 8·10⁻⁷ rad, needed A 0.0087° there and stepped.
fn free_axis_steps_at_an_end(
    kin: &Kinematics,
    posture: &Posture,
    circle: Option<&Circle3>,
    from: &Pos,
    to: &Pos,
) -> bool {
    /// Below this (degrees) no turn is a step: a rotary axis moves that much from rest in 1 ms
    /// at a jerk of 10 000°/s³.
    const STEP_DEG: f64 = 1e-6;
    [(0.0, from), (1.0, to)].into_iter().any(|(end, at)| {
        let Some((i, far, there)) = pole_end(kin, posture, circle, from, to, end) else { return false };
        let next = end + 2.0 * (far - end);
        let q: Pos = std::array::from_fn(|k| from[k] + (to[k] - from[k]) * next);
        let beyond = kin.angles_near(posture.at(next, circle), &q).map_or(there, |b| b[i]);
        (there - at[i]).abs() > 10.0 * (beyond - there).abs() + STEP_DEG
    })
}

/// How far (radians) off the singular posture the inverse's free axis is read on a way that
/// ends there (`Follow::free_off_pole`): there the lean keeps 10 digits.
const LEAN_READ: f64 = 1e-6;

/// An end this near the singular posture (degrees) is at it: a program's 0.001° angles reach no
/// nearer on a machine whose singular angle is not a round number, and between there and the
/// posture the free axis would turn faster than any grid of the way resolves.
const AT_POLE_DEG: f64 = 1e-3;

/// How the axes `q` stand at the singular posture (within [`AT_POLE_DEG`]); `None`: off it.
fn at_pole(kin: &Kinematics, q: &Pos) -> Option<crate::kin::Singularity> {
    kin.singularity(q).filter(|s| s.angle < AT_POLE_DEG)
}

/// A tool posture control block at the singular posture as the machine runs it
/// (`singular_turns`).
pub(crate) struct SingularTurns {
    /// The axes after the turn at the start, at the posture (`None`: no turn there).
    pub lead: Option<Pos>,
    /// The axes before the turn at the end, at the posture (`None`: no turn there).
    pub trail: Option<Pos>,
    /// The tool directions (table frame) the way turns between.
    pub way: (Vec3, Vec3),
}

/// How far (the largest distance between unit vectors, about the angle in radians) the tool
/// of the rotary axes turning in proportion from `from` to `to` is from `direction(u)` at the
/// inner points of `steps` even steps of the block.
fn off_proportional(kin: &Kinematics, from: &Pos, to: &Pos, direction: impl Fn(f64) -> Vec3, steps: usize) -> f64 {
    (1..steps)
        .map(|k| {
            let u = k as f64 / steps as f64;
            let q: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * u);
            (kin.forward(&q, 0.0).tool - direction(u).normalize()).norm()
        })
        .fold(0.0, f64::max)
}

/// Cutting point control: the vector from the cutting point to the tool tip (table frame) where
/// a block from the axes at `from` to the angles of `to` ends, as its path turns the tool
/// (`tip.cutting` set; the interpreter places the block's end with it); `None` when the tool
/// cannot follow the block (`cutting_point::through_singular`).
pub(crate) fn cutting_end(kin: &std::sync::Arc<Kinematics>, tip: &TipMove, from: &Pos, to: &Pos) -> Option<Vec3> {
    let circle = tip.arc.as_ref().map(|a| Circle3::new(a, &tip.from, &tip.to));
    let posture = posture_along(kin, tip, circle.as_ref(), from, to).unwrap_or(None);
    let follow = Follow { circle, posture, ..Follow::plain(kin.clone(), tip.tool_length, tip.from, tip.to) };
    match &tip.cutting {
        Some(c) => {
            let tool_at = |u: f64| kin.forward(&follow.angles(from, to, u), 0.0).tool;
            if crate::cutting_point::through_singular(c.tool, c.normals, c.singular_deg, tool_at) {
                return None;
            }
            Some(follow.along(c, from, to).vector_for(1.0, tool_at(1.0)))
        }
        None => Some(Vec3::zeros()),
    }
}

impl Follow {
    /// A straight tip path from `from` to `to` with the rotary axes in proportion, nothing else
    /// along it.
    fn plain(kin: std::sync::Arc<Kinematics>, tool_length: f64, from: Vec3, to: Vec3) -> Follow {
        Follow {
            kin,
            tool_length,
            from,
            to,
            circle: None,
            posture: None,
            fallback: None,
            compensation: None,
            cutting: None,
            work_frame: None,
            display_shift: None,
            speed_cap: f64::INFINITY,
            clamped: false,
            pieces: Box::default(),
            head_fixed: false,
        }
    }

    /// Whether the axes' way can bend sharply (`Grid::fine`): the rotary axes follow a
    /// direction by the inverse (tool posture control, G54.4's compensation) rather than
    /// turning in proportion, or the tip moves with the tool's direction (cutting point
    /// control: a flat end's vector turns fast near its singular posture).
    fn bends_sharply(&self) -> bool {
        self.posture.is_some() || self.compensation.is_some() || self.cutting.is_some()
    }

    /// A block's cutting point vector all along it, the axes going from `from` to `to`.
    fn along(&self, c: &CuttingMove, from: &Pos, to: &Pos) -> crate::cutting_point::Along {
        let tool_at = |u: f64| self.kin.forward(&self.angles(from, to, u), 0.0).tool;
        crate::cutting_point::Along::new(c.tool, c.normals, c.singular_deg, c.start, tool_at)
    }

    /// How far the tip travels relative to the table along the way (chords of 32 steps): a
    /// cutting point control block whose cutting point and rotary axes stand moves the tip by
    /// its vector alone.
    fn vector_travel(&self, from: &Pos, to: &Pos) -> f64 {
        const STEPS: usize = 32;
        let tip = |k: usize| {
            let u = k as f64 / STEPS as f64;
            self.aimed_tip(&self.angles(from, to, u), u)
        };
        (1..=STEPS).map(|k| (tip(k) - tip(k - 1)).norm()).sum()
    }

    fn tip(&self, u: f64) -> Vec3 {
        match &self.circle {
            Some(c) => c.at(u),
            None => self.from + (self.to - self.from) * u,
        }
    }

    /// Every axis at `u` of the way from `from` to `to`: the rotary (and other) axes in
    /// proportion, or for the posture's direction the inverse solution nearest that, then X/Y/Z
    /// so that the tip is on the path.
    fn at(&self, from: &Pos, to: &Pos, u: f64) -> Pos {
        let mut q = self.angles(from, to, u);
        let aimed = self.aimed_tip(&q, u);
        let carriage = if self.head_fixed {
            self.kin.carriage_for_unturned(&q, aimed, self.tool_length)
        } else {
            self.kin.carriage_for(&q, aimed, self.tool_length)
        };
        for (axis, index) in self.kin.linear.iter().enumerate() {
            if let Some(i) = index {
                q[*i] = carriage[axis];
            }
        }
        q
    }

    /// The rotary (and other) axes `u` of the way: in proportion, or for the posture's
    /// direction the inverse solution nearest that (X/Y/Z not yet placed).
    fn angles(&self, from: &Pos, to: &Pos, u: f64) -> Pos {
        let q: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * u);
        let direction = match (&self.posture, &self.compensation) {
            (Some(p), _) => Some(p.at(u, self.circle.as_ref())),
            (None, Some(c)) => Some(compensated(&self.kin, c, u)),
            (None, None) => None,
        };
        let Some(d) = direction else { return q };
        let mut out = self.kin.angles_near(d, &q).unwrap_or(q);
        if let Some((free, angle)) = self.posture.as_ref().and_then(|p| self.free_off_pole(p, from, to, u, d)) {
            out[free] = angle;
        }
        out
    }

    /// Near the singular posture the inverse reads the free axis from the tool's lean off the
    /// posture's line, and where the lean is tiny it keeps few digits: on a way from the posture
    /// of a random machine its angle held still, then stepped 10⁻⁷° where the lean reached
    /// 10⁻⁸ rad — and the linear axes, which keep the tip, 10⁻⁶ mm, a jerk 4 000 % over
    /// in 0.1 ms samples. Within [`LEAN_READ`] of the posture, at an end of the way that lies
    /// there, the free axis instead runs straight from that end to where the way is
    /// [`LEAN_READ`] off (which turns the tool off its way by the lean times the difference,
    /// 10⁻¹⁵ rad). `None`: elsewhere; the index of the free axis and its angle.
    fn free_off_pole(&self, posture: &Posture, from: &Pos, to: &Pos, u: f64, direction: Vec3) -> Option<(usize, f64)> {
        let joint = self.kin.singular_joint()?;
        if lean_off(joint.direction, direction) >= LEAN_READ {
            return None;
        }
        let (end, at_end) = if u < 0.5 { (0.0, from) } else { (1.0, to) };
        let (i, far, there) = pole_end(&self.kin, posture, self.circle.as_ref(), from, to, end)?;
        let share = (u - end) / (far - end);
        Some((i, at_end[i] + (there - at_end[i]) * share))
    }

    /// Where the tip goes `u` of the way with the axes at `q` (only their angles count): on
    /// the path, or under cutting point control the block's vector away from it.
    fn aimed_tip(&self, q: &Pos, u: f64) -> Vec3 {
        let tip = self.tip(u);
        match &self.cutting {
            Some(c) => {
                let along = c.lo + (c.hi - c.lo) * u;
                tip + c.along.vector_for(along, self.kin.forward(q, 0.0).tool)
            }
            None => tip,
        }
    }

    /// Keep what is left after `u` of the way.
    fn cut(&mut self, u: f64) {
        if let Some(c) = &mut self.cutting {
            c.lo += (c.hi - c.lo) * u;
        }
        self.from = self.tip(u);
        if let Some(p) = &mut self.posture {
            if !p.cut(u, self.circle.as_ref()) {
                self.posture = None;
            }
        }
        if let Some(c) = &mut self.compensation {
            c.from = std::array::from_fn(|i| c.from[i] + (c.to[i] - c.from[i]) * u);
        }
        if let Some(c) = &mut self.circle {
            let (sin, cos) = (c.sweep * u).sin_cos();
            (c.e1, c.e2) = (c.e1 * cos + c.e2 * sin, c.e2 * cos - c.e1 * sin);
            c.center += c.rise * u;
            c.r0 += (c.r1 - c.r0) * u;
            c.sweep *= 1.0 - u;
            c.rise *= 1.0 - u;
        }
    }

    /// Keep what comes before `u` of the way.
    fn keep_to(&mut self, u: f64) {
        if let Some(c) = &mut self.cutting {
            c.hi = c.lo + (c.hi - c.lo) * u;
        }
        self.to = self.tip(u);
        if let Some(p) = &mut self.posture {
            if !p.keep_to(u, self.circle.as_ref()) {
                self.posture = None;
            }
        }
        if let Some(c) = &mut self.compensation {
            c.to = std::array::from_fn(|i| c.from[i] + (c.to[i] - c.from[i]) * u);
        }
        if let Some(c) = &mut self.circle {
            c.r1 = c.r0 + (c.r1 - c.r0) * u;
            c.sweep *= u;
            c.rise *= u;
        }
    }

    /// Programming coordinates at `u` for machine position `machine`.
    fn work(&self, machine: &Pos, u: f64, offset: &Pos) -> Pos {
        let mut work: Pos = std::array::from_fn(|i| machine[i] + offset[i]);
        if let Some(f) = &self.work_frame {
            let p = match self.display_shift {
                Some(shift) => self.kin.table_frame(machine).to_parent(&self.tip(u)) - shift,
                None => f.from_parent(&self.tip(u)),
            };
            for (axis, index) in self.kin.linear.iter().enumerate() {
                if let Some(i) = index {
                    work[*i] = p[axis];
                }
            }
        }
        work
    }
}

/// Bounds on a kinematic path's axis derivatives over a stretch of it.
struct Sampled {
    /// The largest |d(axis)/ds|, |d²/ds²|, |d³/ds³| of every axis over the stretch.
    rate: Pos,
    bend: Pos,
    twist: Pos,
    start_dir: Pos,
    end_dir: Pos,
    start_curvature: Pos,
    end_curvature: Pos,
}

/// The first three derivatives by s of every axis at points of a kinematic path (`q` gives the
/// axes at u = s / `len`): evenly spaced, then, where the axes' way bends too sharply for that,
/// closer (`Grid::fine`).
pub(super) struct Grid {
    len: f64,
    /// Where each point lies, as a share of the path: ascending from 0 to 1.
    pub(super) u: Vec<f64>,
    /// `d[k]`: d/ds, d²/ds², d³/ds³ of every axis at `u[k]`.
    pub(super) d: Vec<[Pos; 3]>,
}

/// d/ds, d²/ds², d³/ds³ of every axis at `u` by differences of `q` at u ± h/2 and u ± 3h/2
/// (`h` a share of the path `len` long).
fn differences(q: &impl Fn(f64) -> Pos, u: f64, h: f64, len: f64, axes: &AxisLimits) -> [Pos; 3] {
    let mut out = [[0.0; MAX_AXES]; 3];
    if len <= 0.0 {
        return out;
    }
    let ds = h * len;
    let (a, b, c, d) = (q(u - 1.5 * h), q(u - 0.5 * h), q(u + 0.5 * h), q(u + 1.5 * h));
    for i in 0..axes.count {
        out[0][i] = (c[i] - b[i]) / ds;
        out[1][i] = (d[i] - c[i] - b[i] + a[i]) / (2.0 * ds * ds);
        out[2][i] = (d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i]) / (ds * ds * ds);
    }
    out
}

/// What a scatter of [`ROUNDING`] in the positions makes of each of [`differences`] taken `ds`
/// (mm) apart.
fn rounding(ds: f64) -> [f64; 3] {
    [2.0 * ROUNDING / ds, 2.0 * ROUNDING / (ds * ds), 8.0 * ROUNDING / (ds * ds * ds)]
}

/// How far apart (mm or degrees) two positions of a path's axes may be and still be the same
/// to [`Grid::refine`]: a nanometre is below any machine's resolution, and the positions the
/// kinematics give near a flat end's singular posture scatter by 10⁻¹⁰ mm (its vector there is
/// the difference of nearly equal directions); differences of such positions over steps far
/// finer than the path's own changes would never read as smooth.
const ROUNDING: f64 = 1e-9;

/// The points of `cells` even cells (0 … 1).
fn even(cells: usize) -> Vec<f64> {
    (0..=cells).map(|k| k as f64 / cells as f64).collect()
}

impl Grid {
    fn new(q: impl Fn(f64) -> Pos, len: f64, cells: usize, axes: &AxisLimits) -> Grid {
        let cells = cells.max(1);
        let h = 1.0 / (4.0 * cells as f64);
        let u = even(cells);
        let d = u.iter().map(|&u| differences(&q, u, h, len, axes)).collect();
        Grid { len, u, d }
    }

    /// The same derivatives by differences between the points themselves (one evaluation of
    /// `q` a point, two beyond either end): a quarter of [`Grid::new`]'s cost, with errors of
    /// (len / cells)²/6 times the next derivative (the planner's `optimal` allows for them).
    fn lattice(q: impl Fn(f64) -> Pos, len: f64, cells: usize, axes: &AxisLimits) -> Grid {
        let cells = cells.max(1);
        let du = 1.0 / cells as f64;
        let ds = du * len;
        let x: Vec<Pos> = (0..cells + 5).map(|m| q((m as f64 - 2.0) * du)).collect();
        let d = (2..cells + 3)
            .map(|m| {
                let mut out = [[0.0; MAX_AXES]; 3];
                if len <= 0.0 {
                    return out;
                }
                for i in 0..axes.count {
                    let (a, b, c, d, e) = (x[m - 2][i], x[m - 1][i], x[m][i], x[m + 1][i], x[m + 2][i]);
                    out[0][i] = (d - b) / (2.0 * ds);
                    out[1][i] = (d - 2.0 * c + b) / (ds * ds);
                    out[2][i] = (e - 2.0 * d + 2.0 * b - a) / (2.0 * ds * ds * ds);
                }
                out
            })
            .collect();
        Grid { len, u: even(cells), d }
    }

    fn cells(&self) -> usize {
        self.d.len() - 1
    }

    /// The point at share `u` of the path (one of the grid's: a piece's end).
    fn point(&self, u: f64) -> usize {
        self.u.partition_point(|&x| x < u).min(self.cells())
    }

    /// `make(cells)` — kept as it is where each point reads as its neighbours' mean — else its
    /// cells doubled (at most [`DOUBLINGS`] times) until the finer grid's derivatives read as
    /// the coarser one's between its points, as the planner reads them
    /// (linearly): within [`READ`] of their largest size, or of what would move an axis by 1 % of
    /// its limit at the highest speed the axes allow the path (below that a difference is
    /// nothing to the planner — and finite differences over a short block's tiny steps differ
    /// by rounding alone: cutting-5x's 20,000 blocks ran 9.5 times slower before that floor).
    /// Where the axes' way bends sharply — tool posture control near the edge of the
    /// directions the axes reach, where their derivatives grow as 1/√ of the distance to it;
    /// cutting point control near a flat end's singular posture — the planner missed peaks
    /// between the points of the usual grid: random blocks ran an axis's jerk up to 7 %
    /// (posture) and 10 % (cutting point) over. Where even the finest even grid does not
    /// agree with the one before, its cells are halved further where they disagree
    /// ([`Grid::refine`]).
    fn fine(make: impl Fn(usize) -> Grid, q: impl Fn(f64) -> Pos, cells: usize, axes: &AxisLimits) -> Grid {
        /// At most 16 times the usual number of cells.
        const DOUBLINGS: usize = 4;
        let mut grid = make(cells);
        // A grid whose every point reads as its neighbours' mean is smooth enough as it is
        // (most blocks: one look, no finer grid to make).
        let tolerance = grid.tolerance(axes);
        let smooth = (1..grid.cells())
            .all(|m| reads_as(&grid.d[m], &tolerance, |o, i| 0.5 * (grid.d[m - 1][o][i] + grid.d[m + 1][o][i])));
        if smooth {
            return grid;
        }
        for _ in 0..DOUBLINGS {
            let finer = make(2 * grid.cells());
            let tolerance = finer.tolerance(axes);
            let coarse = &grid.d;
            let agree = (0..finer.d.len()).all(|m| {
                let (k, between) = (m / 2, m % 2 == 1);
                reads_as(&finer.d[m], &tolerance, |o, i| {
                    if between {
                        0.5 * (coarse[k][o][i] + coarse[k + 1][o][i])
                    } else {
                        coarse[k][o][i]
                    }
                })
            });
            grid = finer;
            if agree {
                return grid;
            }
        }
        grid.refine(&q, axes)
    }

    /// This grid with its cells halved, again and again, where the derivatives in a cell's
    /// middle do not read as the mean of its ends' — first by [`Grid::tolerance`], then, inside
    /// a cell being halved, by the cell's own sizes ([`halve`]): a flat end's vector under
    /// cutting point control turns half round within a sliver of the block about twice the
    /// tool's least angle to the normal wide, far narrower than an even grid resolves (an
    /// axis's jerk ran at up to 5 times its limit there). Every point beside a halved cell takes
    /// its derivatives again over its nearer neighbour's spacing.
    fn refine(self, q: &impl Fn(f64) -> Pos, axes: &AxisLimits) -> Grid {
        /// At most 2⁻³⁰ of a cell: far below a sliver 10⁻⁷ rad wide (PS5464 nearer).
        const DEPTH: usize = 30;
        /// At most this many points added to a block.
        const ADDED: usize = 4096;
        let (len, tolerance) = (self.len, self.tolerance(axes));
        let at = |u: f64, h: f64| differences(q, u, h, len, axes);
        let mut u = vec![self.u[0]];
        let mut budget = ADDED;
        for c in 0..self.cells() {
            let (u0, u1) = (self.u[c], self.u[c + 1]);
            let middle = at(0.5 * (u0 + u1), 0.125 * (u1 - u0));
            let (d0, d1) = (&self.d[c], &self.d[c + 1]);
            if !reads_as(&middle, &tolerance, |o, i| 0.5 * (d0[o][i] + d1[o][i])) {
                halve(&at, axes, len, (u0, u1), DEPTH, &mut budget, &mut u);
            }
            u.push(u1);
        }
        // Points whose nearer neighbour moved closer: their derivatives over that spacing (the
        // rest, as on the even grid this one was).
        let even = 1.0 / self.cells() as f64;
        let d = (0..u.len())
            .map(|k| {
                let before = k.checked_sub(1).map_or(f64::INFINITY, |p| u[k] - u[p]);
                let after = u.get(k + 1).map_or(f64::INFINITY, |n| n - u[k]);
                let spacing = before.min(after);
                if spacing > 0.999 * even {
                    self.d[self.point(u[k])]
                } else {
                    at(u[k], 0.25 * spacing)
                }
            })
            .collect();
        Grid { len, u, d }
    }

    /// How far two readings of a derivative may differ (see [`Grid::fine`]): [`READ`] of its
    /// largest size on the grid, plus what moves the axis by 1 % of its limit at the path's
    /// highest speed.
    fn tolerance(&self, axes: &AxisLimits) -> [Pos; 3] {
        tolerance_of(&self.d, axes, READ)
    }

    /// The bounds of cell `c` (from point `c` to `c + 1`): its points' largest |d/ds|,
    /// |d²/ds²|, |d³/ds³| of every axis, the first two raised by the next one's times half the
    /// cell — between two points a derivative can exceed them by at most that, so a peak
    /// between points does not let an axis run past its limits (random machines found 1e-5
    /// overshoots without it).
    fn cell(&self, c: usize) -> [Pos; 3] {
        let mut out = [[0.0; MAX_AXES]; 3];
        widen(&mut out, &self.d[c]);
        widen(&mut out, &self.d[c + 1]);
        let half = 0.5 * self.len * (self.u[c + 1] - self.u[c]);
        let [rate, bend, twist] = out;
        [std::array::from_fn(|i| rate[i] + bend[i] * half), std::array::from_fn(|i| bend[i] + twist[i] * half), twist]
    }

    /// The bounds ([`Grid::cell`]) over the cells from point `k0` to point `k1`.
    fn maxima(&self, k0: usize, k1: usize) -> [Pos; 3] {
        let mut out = [[0.0; MAX_AXES]; 3];
        for c in k0..k1.max(k0 + 1).min(self.cells()) {
            widen(&mut out, &self.cell(c));
        }
        out
    }

    /// The bounds over the cells from point `k0` to point `k1`, whose cells' bounds are
    /// `maxima` ([`Grid::maxima`]).
    fn bounds_of(&self, maxima: [Pos; 3], k0: usize, k1: usize) -> Sampled {
        let [rate, bend, twist] = maxima;
        Sampled {
            rate,
            bend,
            twist,
            start_dir: self.d[k0][0],
            end_dir: self.d[k1][0],
            start_curvature: self.d[k0][1],
            end_curvature: self.d[k1][1],
        }
    }

    fn bounds(&self, k0: usize, k1: usize) -> Sampled {
        self.bounds_of(self.maxima(k0, k1), k0, k1)
    }

    /// The whole path's bounds.
    fn whole(&self) -> Sampled {
        self.bounds(0, self.cells())
    }
}

/// How far a derivative between a grid's points may stray from its linear reading, as a share
/// of its largest size ([`Grid::fine`]): the optimal plan reads the derivatives so and takes
/// every axis to 99.9 % of its limits, so a misreading of a few tenths of a percent shows as an
/// axis past its limit (with 2 %, random flat ends passing near their singular posture ran Z's
/// jerk 0.15 % over).
const READ: f64 = 0.005;

/// The same share within a cell being halved ([`halve`]), of the cell's own sizes: with
/// [`READ`] there, such a block ran Y's jerk 2 % over (the floor of 1 % of a limit, and the
/// rounding, add to it); none in 3 000 random blocks with this.
const READ_HALVED: f64 = 0.001;

/// [`Grid::tolerance`] of the derivatives `d`, straying by `share` of their largest size.
fn tolerance_of<'a>(d: impl IntoIterator<Item = &'a [Pos; 3]>, axes: &AxisLimits, share: f64) -> [Pos; 3] {
    let mut largest = [[0.0; MAX_AXES]; 3];
    for d in d {
        widen(&mut largest, d);
    }
    // The path is never faster than its fastest axis allows.
    let top = (0..axes.count).map(|i| axes.v[i] / largest[0][i]).fold(f64::INFINITY, f64::min);
    let limits = [&axes.v, &axes.a, &axes.j];
    std::array::from_fn(|o| {
        std::array::from_fn(|i| share * largest[o][i] + 0.01 * limits[o][i] / top.powi(o as i32 + 1))
    })
}

/// Whether derivatives `d` are within `tolerance` of `read(order, axis)`.
fn reads_as(d: &[Pos; 3], tolerance: &[Pos; 3], read: impl Fn(usize, usize) -> f64) -> bool {
    (0..3).all(|o| (0..MAX_AXES).all(|i| (d[o][i] - read(o, i)).abs() <= tolerance[o][i]))
}

/// Push onto `points` the points that halve the cell `u0 … u1` of a path `len` long (neither
/// end) until each part's middle reads as its ends' mean by the part's own sizes
/// ([`tolerance_of`] its three points with [`READ_HALVED`], plus what [`ROUNDING`] makes of
/// their differences), at most `depth` times, while `budget` lasts. `at(u, h)` the derivatives
/// at `u` by differences `h` apart.
fn halve(
    at: &impl Fn(f64, f64) -> [Pos; 3],
    axes: &AxisLimits,
    len: f64,
    (u0, u1): (f64, f64),
    depth: usize,
    budget: &mut usize,
    points: &mut Vec<f64>,
) {
    if depth == 0 || *budget == 0 {
        return;
    }
    let (um, h) = (0.5 * (u0 + u1), 0.125 * (u1 - u0));
    let (d0, dm, d1) = (at(u0, h), at(um, h), at(u1, h));
    let mut tolerance = tolerance_of([&d0, &dm, &d1], axes, READ_HALVED);
    for (row, r) in tolerance.iter_mut().zip(rounding(h * len)) {
        for t in row {
            *t += r;
        }
    }
    if reads_as(&dm, &tolerance, |o, i| 0.5 * (d0[o][i] + d1[o][i])) {
        return;
    }
    *budget -= 1;
    halve(at, axes, len, (u0, um), depth - 1, budget, points);
    points.push(um);
    halve(at, axes, len, (um, u1), depth - 1, budget, points);
}

/// Raise `maxima` to the magnitudes of the derivatives `d` where they are larger.
fn widen(maxima: &mut [Pos; 3], d: &[Pos; 3]) {
    for (bound, d) in maxima.iter_mut().zip(d) {
        for (b, x) in bound.iter_mut().zip(d) {
            *b = b.max(x.abs());
        }
    }
}

/// The shares of each axis's acceleration and jerk that a kinematic path's cruise may take
/// (`kinematic_limits`), tried in turn; the rest is left to the path's speed changes.
const CRUISE_SHARES: [f64; 2] = [0.9, 0.5];

/// The path limits of a kinematic path (its derivative grid `grid`) fed at `feed` (per second;
/// infinite for a rapid), never faster than `cap`, and the pieces it is cut into (none: it
/// runs whole).
///
/// Axis i moves at v·q1, accelerates a·q1 + v²·q2 and jerks j·q1 + 3·v·a·q2 + v³·q3 (q1..q3
/// its derivatives by s, bounded over a stretch by the grid; v, a, j the path's speed,
/// acceleration and jerk). A stretch's top speed v comes first: at most the axis's speed, and
/// its own terms v²·q2 and v³·q3 within a share σ of the axis's acceleration and jerk. What is
/// left goes to speed changes: a ≤ (A − v²·q2)/q1, the cross term 3·v·a·q2 within half of the
/// jerk left, j with the rest. The path is cut where these limits change by more than a few %
/// ([`pieces`]), so that each piece cruises at what its own stretch allows. The share, and
/// whether to cut at all, is the choice of [`CRUISE_SHARES`] × {cut, whole} whose rest-to-rest
/// time at min(v, feed) is the shortest as the planner would plan it (`chain_time`): a high
/// share cruises fast but accelerates slowly, and a chain of short pieces changes speed more
/// slowly than one profile (its acceleration returns to zero at every junction); a third
/// option merges the pieces at either end where the path changes speed from or to rest. The
/// pieces of the chosen cut then take each the share that shortens that time. Without
/// `may_cut` the path runs whole.
fn kinematic_limits(grid: &Grid, axes: &AxisLimits, feed: f64, cap: f64, may_cut: bool) -> (Limits, Vec<Piece>) {
    let fed = |lim: Limits| Limits { v: lim.v.min(feed), ..lim };
    // The bounds do not depend on the share: found once for both.
    let whole_bounds = grid.whole();
    let cell_bounds: Vec<Sampled> =
        if may_cut { (0..grid.cells()).map(|c| grid.bounds(c, c + 1)).collect() } else { Vec::new() };
    let mut best: Option<(f64, Limits, Vec<Piece>)> = None;
    // An option is planned (`chain_time`, most of the cost) only where its floor does not
    // already lose to the best so far (it mostly does: a lower cruise share rarely wins).
    let consider = |best: &mut Option<(f64, Limits, Vec<Piece>)>, whole: Limits, cut: Vec<Piece>| {
        if best.as_ref().is_some_and(|(t, _, _)| floor_time(&cut, whole, grid.len, fed) >= *t) {
            return;
        }
        let time = if cut.is_empty() {
            super::planner::chain_time(&[(grid.len, fed(whole))])
        } else {
            chain_time(&cut, grid.len, fed)
        };
        if best.as_ref().is_none_or(|(t, _, _)| time < *t * (1.0 - 1e-9)) {
            *best = Some((time, whole, cut));
        }
    };
    for share in CRUISE_SHARES {
        let whole = limits_with_share(&whole_bounds, axes, share, cap);
        let cut = if may_cut { pieces(grid, &cell_bounds, axes, share, cap) } else { Vec::new() };
        consider(&mut best, whole, Vec::new());
        if !cut.is_empty() {
            let reach = super::profile::change(0.0, fed(whole).v, &fed(whole)).1 / grid.len;
            let ends_whole = merge_ends(grid, axes, share, cap, &cut, reach);
            consider(&mut best, whole, cut);
            if !ends_whole.is_empty() {
                consider(&mut best, whole, ends_whole);
            }
        }
    }
    let Some((time, whole, mut cut)) = best else { return (Limits { v: 0.0, a: 0.0, j: 0.0 }, Vec::new()) };
    // Each piece its own share, where that is faster: a piece that only changes speed does
    // better with a low one (a lower top speed, more acceleration left), one that cruises with
    // a high one.
    let mut time = time;
    for k in 0..cut.len() {
        let k0 = if k == 0 { 0 } else { grid.point(cut[k - 1].end) };
        let k1 = grid.point(cut[k].end);
        let bounds = grid.bounds(k0, k1);
        for share in CRUISE_SHARES {
            let kept = cut[k].limits;
            cut[k].limits = limits_with_share(&bounds, axes, share, cap);
            // The same limits take the same time; a floor no faster cannot win either.
            if cut[k].limits == kept || floor_time(&cut, whole, grid.len, fed) >= time {
                cut[k].limits = kept;
                continue;
            }
            let t = chain_time(&cut, grid.len, fed);
            if t < time * (1.0 - 1e-9) {
                time = t;
            } else {
                cut[k].limits = kept;
            }
        }
    }
    (whole, cut)
}

/// A time the path `len` long, cut into `pieces` (or whole, with the limits `whole`), cannot
/// beat from rest to rest: the chain's profiles are a motion within the highest of their
/// limits ([`super::profile::rest_to_rest_floor`]).
fn floor_time(pieces: &[Piece], whole: Limits, len: f64, fed: impl Fn(Limits) -> Limits) -> f64 {
    let lim = match pieces.split_first() {
        None => whole,
        Some((first, rest)) => rest.iter().fold(first.limits, |m, p| Limits {
            v: m.v.max(p.limits.v),
            a: m.a.max(p.limits.a),
            j: m.j.max(p.limits.j),
        }),
    };
    super::profile::rest_to_rest_floor(len, &fed(lim))
}

/// The rest-to-rest time of a path `len` long cut into `pieces`, with `fed` applied to their
/// limits.
fn chain_time(pieces: &[Piece], len: f64, fed: impl Fn(Limits) -> Limits) -> f64 {
    let mut start = 0.0;
    let chain: Vec<(f64, Limits)> = pieces
        .iter()
        .map(|p| {
            let piece = ((p.end - start) * len, fed(p.limits));
            start = p.end;
            piece
        })
        .collect();
    super::planner::chain_time(&chain)
}

/// `cut` with its pieces within `reach` (a share of the path) of either end merged into one at
/// each end: where the machine changes speed from or to rest, one profile over the stretch
/// beats a chain of short ones, each returning to zero acceleration. Empty when the two ends
/// meet.
fn merge_ends(grid: &Grid, axes: &AxisLimits, share: f64, cap: f64, cut: &[Piece], reach: f64) -> Vec<Piece> {
    let starts: Vec<f64> = std::iter::once(0.0).chain(cut.iter().map(|p| p.end)).collect();
    let first = cut.iter().position(|p| p.end >= reach).unwrap_or(cut.len() - 1);
    let last = (0..cut.len()).rev().find(|&k| starts[k] <= 1.0 - reach).unwrap_or(0);
    if first >= last {
        return Vec::new();
    }
    let merged = |k0: usize, k1: usize| Piece {
        limits: limits_with_share(&grid.bounds(grid.point(starts[k0]), grid.point(cut[k1].end)), axes, share, cap),
        ..cut[k1].clone()
    };
    let mut out = vec![merged(0, first)];
    out.extend_from_slice(&cut[first + 1..last]);
    out.push(merged(last, cut.len() - 1));
    out
}

/// A stretch of a kinematic path planned with limits of its own (`Segment::split`).
#[derive(Debug, Clone, PartialEq)]
struct Piece {
    /// Where it ends, as a share of the path.
    end: f64,
    /// Its speed (what the axes allow, before the feed), acceleration and jerk limits.
    limits: Limits,
    /// d(axis)/ds and d²(axis)/ds² where it ends (the next piece starts with the same: the
    /// planner sees a smooth junction).
    end_dir: Pos,
    end_curvature: Pos,
}

/// At most this many pieces to a kinematic block: each is a segment in the planner's queue.
pub(super) const MAX_PIECES: usize = 16;

/// Cells of a kinematic path share a piece while the piece's limits stay within this share of
/// each cell's own; with more than [`MAX_PIECES`] pieces the share doubles.
const PIECE_TOLERANCE: f64 = 0.03;

/// A kinematic path cut where its limits change: the cells of `grid` (their bounds
/// `cell_bounds`) grouped into stretches whose own limits (the cruise taking `share`, at most
/// `cap`) are each within a few % of every cell's in them. Empty when one stretch is the whole
/// path.
fn pieces(grid: &Grid, cell_bounds: &[Sampled], axes: &AxisLimits, share: f64, cap: f64) -> Vec<Piece> {
    let own = |k0: usize, k1: usize| limits_with_share(&grid.bounds(k0, k1), axes, share, cap);
    let cells: Vec<Limits> = cell_bounds.iter().map(|b| limits_with_share(b, axes, share, cap)).collect();
    let mut tolerance = PIECE_TOLERANCE;
    let ends = loop {
        let ends = cuts(
            grid,
            &cells,
            |maxima, k0, k1| limits_with_share(&grid.bounds_of(maxima, k0, k1), axes, share, cap),
            tolerance,
        );
        if ends.len() <= MAX_PIECES || tolerance >= 1.0 {
            break ends;
        }
        tolerance *= 2.0;
    };
    if ends.len() <= 1 {
        return Vec::new();
    }
    let mut k0 = 0;
    ends.iter()
        .map(|&k1| {
            let piece =
                Piece { end: grid.u[k1], limits: own(k0, k1), end_dir: grid.d[k1][0], end_curvature: grid.d[k1][1] };
            k0 = k1;
            piece
        })
        .collect()
}

/// The end points (grid indices) of the stretches: a stretch grows cell by cell while its
/// limits (`own` of its points' largest derivatives, its first and its last point) stay
/// within `tolerance` of the highest of its cells' own.
fn cuts(grid: &Grid, cells: &[Limits], own: impl Fn([Pos; 3], usize, usize) -> Limits, tolerance: f64) -> Vec<usize> {
    let close = |x: f64, top: f64| x == top || x >= (1.0 - tolerance) * top;
    let mut ends = Vec::new();
    let (mut k0, mut top, mut maxima) = (0, cells[0], grid.maxima(0, 1));
    for (c, cell) in cells.iter().enumerate().skip(1) {
        let up = Limits { v: top.v.max(cell.v), a: top.a.max(cell.a), j: top.j.max(cell.j) };
        let mut wider = maxima;
        widen(&mut wider, &grid.cell(c));
        let merged = own(wider, k0, c + 1);
        if close(merged.v, up.v) && close(merged.a, up.a) && close(merged.j, up.j) {
            (top, maxima) = (up, wider);
        } else {
            ends.push(c);
            (k0, top, maxima) = (c, *cell, grid.maxima(c, c + 1));
        }
    }
    ends.push(cells.len());
    ends
}

/// [`kinematic_limits`] with the cruise taking `share` of each axis's acceleration and jerk.
fn limits_with_share(d: &Sampled, axes: &AxisLimits, share: f64, cap: f64) -> Limits {
    let tiny = 1e-12;
    let mut v = cap;
    for i in 0..axes.count {
        if d.rate[i] > tiny {
            v = lower(v, axes.v[i], d.rate[i]);
        }
        // The roots (the cube root was a tenth of a TCP run's time) only where they can be the
        // lower: with x above v² (v³) by more than its rounding, √x (∛x) is above v. The
        // quotient too where its numerator clears v² (v³) times its denominator: x then does.
        if d.bend[i] > tiny && share * axes.a[i] <= v * v * d.bend[i] * (1.0 + 2e-12) {
            let x = share * axes.a[i] / d.bend[i];
            if x < v * v * (1.0 + 1e-12) {
                v = v.min(x.sqrt());
            }
        }
        if d.twist[i] > tiny && share * axes.j[i] <= v * v * v * d.twist[i] * (1.0 + 2e-12) {
            let x = share * axes.j[i] / d.twist[i];
            if x < v * v * v * (1.0 + 1e-12) {
                v = v.min(x.cbrt());
            }
        }
    }
    // The jerk each axis has left beside the cruise's own v³·q3.
    let jerk_left = |i: usize| axes.j[i] - v.powi(3) * d.twist[i];
    let mut a = f64::INFINITY;
    for i in 0..axes.count {
        if d.rate[i] > tiny {
            a = lower(a, axes.a[i] - v * v * d.bend[i], d.rate[i]);
        }
        if d.bend[i] > tiny && v > 0.0 {
            a = lower(a, 0.5 * jerk_left(i), 3.0 * v * d.bend[i]);
        }
    }
    let mut j = f64::INFINITY;
    for i in 0..axes.count {
        if d.rate[i] > tiny {
            j = lower(j, jerk_left(i) - 3.0 * v * a * d.bend[i], d.rate[i]);
        }
    }
    Limits { v, a: a.max(0.0), j: j.max(0.0) }
}

/// `m.min(num / den)` for `den` > 0, without the division (most of `limits_with_share`'s time)
/// where the numerator clears `m` times the denominator by more than their rounding: the
/// quotient is then above `m`.
fn lower(m: f64, num: f64, den: f64) -> f64 {
    let bound = m * den;
    if num > bound + bound.abs() * 1e-12 {
        m
    } else {
        m.min(num / den)
    }
}

/// The interpolation period of the FANUC CRS clamp (the control's 1 ms), seconds.
const INTERPOLATION_PERIOD: f64 = 0.001;

/// FANUC CRS (M-12; the metric is open, Q-31, *decision* in `docs/five-axis.md`): the control
/// moves the axes in straight lines between interpolation points, so between two points a
/// period apart the tip leaves the path by about the sagitta of the axis-space chord, which
/// grows with the square of the step. Measured for a 1 mm (or 1°) step at `n + 1` places along
/// the path, it gives the highest speed (path units per second) whose step keeps the deviation
/// within `tolerance` mm.
fn deviation_speed(follow: &Follow, from: &Pos, to: &Pos, len: f64, n: usize, tolerance: f64) -> f64 {
    if len <= 0.0 {
        return f64::INFINITY;
    }
    let step = len.min(1.0);
    let du = step / len;
    let mut worst: f64 = 0.0;
    for k in 0..=n {
        let u0 = k as f64 / n as f64 * (1.0 - du);
        let (a, b) = (follow.at(from, to, u0), follow.at(from, to, u0 + du));
        let middle: Pos = std::array::from_fn(|i| 0.5 * (a[i] + b[i]));
        let tip = if follow.head_fixed {
            follow.kin.unturned_tip(&middle, follow.tool_length)
        } else {
            follow.kin.forward(&middle, follow.tool_length).tip
        };
        worst = worst.max((tip - follow.tip(u0 + 0.5 * du)).norm());
    }
    if worst <= 1e-12 {
        return f64::INFINITY;
    }
    step * (tolerance / worst).sqrt() / INTERPOLATION_PERIOD
}

/// Cells of a kinematic path's derivative grid per sample point of [`sample_count`]: the
/// finer grid the pieces are cut from.
const CELLS_PER_SAMPLE: usize = 2;

/// Sample points for a kinematic path: more where the rotary axes turn more.
fn sample_count(turn_deg: f64, sweep_deg: f64) -> usize {
    (4 + (turn_deg / 3.0) as usize + (sweep_deg.abs() / 10.0) as usize).min(32)
}

/// What the planner needs beyond the motion itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedContext {
    /// Feed and rapid override, fractions (1.0 = 100%).
    pub feed_override: f64,
    pub rapid_override: f64,
    /// G09 on this block, or G61 modal.
    pub exact_stop: bool,
    /// The machine's interpolation choices (helical feed, rapid type).
    pub options: MotionOptions,
}

impl Segment {
    /// The segment of `m` starting at machine `from` / programming `work_from`.
    /// `kin` is needed by motions along a tool tip path (`Motion::tip`).
    pub fn new(
        m: &Motion,
        from: &Pos,
        work_from: &Pos,
        axes: &AxisLimits,
        ctx: FeedContext,
        kin: Option<&std::sync::Arc<Kinematics>>,
    ) -> Segment {
        if let (Some(tip), Some(kin)) = (m.tip.as_deref(), kin) {
            return Segment::along_tip(m, tip, kin.clone(), from, work_from, axes, ctx);
        }
        let delta: Pos = std::array::from_fn(|i| m.machine[i] - from[i]);
        let circle = m.arc.as_deref().map(|arc| circle(arc, work_from, &m.target));
        // Path length per unit of F's length: 1, or for a helix fed along its arc (HTG = 0)
        // the path's length over the arc's.
        let mut feed_scale = 1.0;
        let (len, start_dir, end_dir, tip_rate) = match &circle {
            None => {
                let len = norm(&delta);
                let dir: Pos = std::array::from_fn(|i| if len > 0.0 { delta[i] / len } else { 0.0 });
                let tip = (delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2]).sqrt();
                (len, dir, dir, if len > 0.0 { tip / len } else { 0.0 })
            }
            Some(c) => {
                // Arc length of the plane part (the spiral's mean radius), the rest straight.
                let planar = 0.5 * (c.r0 + c.r1) * c.sweep.abs();
                let other: f64 = (0..MAX_AXES).filter(|&i| i != c.a && i != c.b).map(|i| delta[i] * delta[i]).sum();
                let len = (planar * planar + other).sqrt();
                let share = if len > 0.0 { planar / len } else { 0.0 };
                let dir_at = |angle: f64| -> Pos {
                    let mut dir = std::array::from_fn(|i| if len > 0.0 { delta[i] / len } else { 0.0 });
                    c.set_tangent(&mut dir, angle, share);
                    dir
                };
                if !ctx.options.helical_feed_on_path && planar > 0.0 {
                    feed_scale = len / planar;
                }
                let tip = (planar * planar
                    + (0..3).filter(|&i| i != c.a && i != c.b).map(|i| delta[i] * delta[i]).sum::<f64>())
                .sqrt();
                (len, dir_at(c.start), dir_at(c.start + c.sweep), if len > 0.0 { tip / len } else { 0.0 })
            }
        };
        let (mut start_curvature, mut end_curvature) = ([0.0; MAX_AXES], [0.0; MAX_AXES]);
        if let Some(c) = &circle {
            let share = if len > 0.0 { 0.5 * (c.r0 + c.r1) * c.sweep.abs() / len } else { 0.0 };
            c.set_curvature(&mut start_curvature, c.start, c.r0, share);
            c.set_curvature(&mut end_curvature, c.start + c.sweep, c.r1, share);
        }
        let rapid = matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid);
        // Per-axis rate bound over the whole segment (an arc axis reaches its full share).
        let rate: Pos = match &circle {
            None => start_dir.map(f64::abs),
            Some(c) => std::array::from_fn(|i| {
                if i == c.a || i == c.b {
                    start_dir[c.a].hypot(start_dir[c.b])
                } else {
                    start_dir[i].abs()
                }
            }),
        };
        let fed = programmed_speed(m, len) * feed_scale;
        let mut limits = axes.along(&rate);
        if let Some(c) = &circle {
            limits = arc_limits(limits, c, &rate, axes, len, fed * ctx.feed_override);
        }
        // A chord of a curve: what the curve's bending leaves the axes (`Motion::speed_cap`).
        limits.v = limits.v.min(m.speed_cap as f64);
        let axis_speed = limits.v;
        let programmed = if rapid { axis_speed } else { fed };
        let mut seg = Segment {
            line: 0,
            block: 0,
            n: None,
            rapid,
            points: Points::new([from, &m.machine, work_from, &m.target, &start_dir]),
            circle: circle.map(Box::new),
            independent: None,
            follow: None,
            len,
            limits,
            bent: Bent::of(&start_dir, end_dir, start_curvature, end_curvature),
            tip_rate,
            stop_after: rapid || ctx.exact_stop,
            traits: Traits::of(m, false),
            tool_length: m.context.tool_length,
            tip_basis: crate::tip::Basis::default(),
            programmed,
            axis_speed,
            factor: 1.0,
            block_limit: 0,
            contact: None,
        };
        seg.set_override(ctx.feed_override, ctx.rapid_override);
        if rapid && ctx.options.nonlinear_rapid {
            seg.make_independent(axes, ctx.rapid_override);
        }
        seg
    }

    /// A motion along a tool tip path (tool centre point control, tilted working plane): the
    /// path parameter is the tip's travel relative to the table (F is the tip's speed, FANUC
    /// TCP-18), or the rotary axes' combined angle when the tip stays (TCP-20: fed at F with
    /// RFC = 1, else as fast as the axes go). The axes' rates along the way are sampled to bound
    /// the path's speed, acceleration and jerk.
    fn along_tip(
        m: &Motion,
        tip: &TipMove,
        kin: std::sync::Arc<Kinematics>,
        from: &Pos,
        work_from: &Pos,
        axes: &AxisLimits,
        ctx: FeedContext,
    ) -> Segment {
        let circle = tip.arc.as_ref().map(|a| Circle3::new(a, &tip.from, &tip.to));
        let mut feed_scale = 1.0;
        let (tip_len, sweep_deg) = match &circle {
            Some(c) => {
                let (planar, rise) = c.lengths();
                let len = planar.hypot(rise);
                if !ctx.options.helical_feed_on_path && planar > 0.0 {
                    feed_scale = len / planar;
                }
                (len, c.sweep.to_degrees())
            }
            None => ((tip.to - tip.from).norm(), 0.0),
        };
        let turn = rotary_travel(&kin, from, &m.machine);
        let (posture, posture_fallback) = match posture_along(&kin, tip, circle.as_ref(), from, &m.machine) {
            Ok(posture) => (posture, None),
            Err(why) => (None, Some(why)),
        };
        // G54.4's compensation all along the way, where it starts and ends on the block's end
        // points (not so when a singular-posture rule held an axis within No.11204), differs
        // from turning the axes in proportion (it does not for an error about the
        // workpiece-side axis, or rotary axes that stay: then the cheaper way) and the axes can
        // follow it without a jump; otherwise in proportion between the end points.
        let on = |c: &Compensation, u: f64| {
            let q: Pos = std::array::from_fn(|i| from[i] + (m.machine[i] - from[i]) * u);
            kin.angles_near(compensated(&kin, c, u), &q)
                .is_some_and(|a| kin.joints().iter().filter_map(|j| j.index).all(|i| (a[i] - q[i]).abs() < 1e-9))
        };
        // At (within 1° of) the singular posture the free axis has no angle of its own: the
        // compensated direction's azimuth would swing it at once at that end (a seed of the
        // displaced-FCS property stepped C by 0.12° in 1 ms starting from B0): in proportion.
        let near_singular = |q: &Pos| kin.singularity(q).is_some_and(|s| s.angle < 1.0);
        let compensation = tip
            .compensation
            .filter(|_| !near_singular(from) && !near_singular(&m.machine))
            .filter(|c| posture.is_none() && on(c, 0.0) && on(c, 1.0))
            .filter(|c| ![0.25, 0.5, 0.75].iter().all(|&u| on(c, u)))
            .filter(|c| steady(&kin, from, &m.machine, |u| compensated(&kin, c, u)));
        // Dropped where it would have turned the tool otherwise (beyond what a display shows):
        // the run tells it.
        let deviates = |c: &Compensation| {
            off_proportional(&kin, from, &m.machine, |u| compensated(&kin, c, u), 4) > 1e-3f64.to_radians()
        };
        let dropped = compensation.is_none() && posture.is_none() && tip.compensation.as_ref().is_some_and(deviates);
        let fallback = posture_fallback.map(Fallback::Posture).or(dropped.then_some(Fallback::Compensation));
        let mut follow = Follow {
            circle,
            posture,
            fallback,
            compensation,
            work_frame: Some(tip.frame),
            display_shift: tip.display_shift,
            clamped: tip.rotary_clamp.is_some(),
            head_fixed: tip.head_fixed,
            ..Follow::plain(kin.clone(), tip.tool_length, tip.from, tip.to)
        };
        follow.cutting = tip
            .cutting
            .as_ref()
            .map(|c| Box::new(Cutting { along: follow.along(c, from, &m.machine), lo: 0.0, hi: 1.0 }));
        // FANUC No.11202/11203: the rotary axes of a G54.4-compensated move within a share of
        // their rate.
        let clamped;
        let axes = match tip.rotary_clamp {
            Some(share) => {
                let mut a = axes.clone();
                for i in kin.joints().iter().filter_map(|j| j.index) {
                    a.v[i] *= share;
                }
                clamped = a;
                &clamped
            }
            None => axes,
        };
        // Cutting point control: the cutting point and the rotary axes may stand while the tip
        // moves, by a new surface normal (`,L2`) alone; the block's path is then the tip's,
        // fed at F like any move (without this its length was 0 and the planner dropped it: the
        // next block's first sample stepped by the tip's travel).
        let normal_only = match &follow.cutting {
            Some(_) if tip_len < 1e-9 && turn < 1e-9 => follow.vector_travel(from, &m.machine),
            _ => 0.0,
        };
        let rotary_only = tip_len < 1e-9 && normal_only < 1e-9;
        let len = if rotary_only { turn } else { tip_len.max(normal_only) };
        let rapid = matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid);
        let to = m.machine;
        let n = sample_count(turn, sweep_deg);
        let q = |u| follow.at(from, &to, u);
        let grid = |cells| Grid::new(q, len, cells, axes);
        let grid = if follow.bends_sharply() {
            Grid::fine(grid, q, CELLS_PER_SAMPLE * n, axes)
        } else {
            grid(CELLS_PER_SAMPLE * n)
        };
        let found = grid.whole();
        let cap = tip
            .deviation
            .map_or(f64::INFINITY, |tolerance| deviation_speed(&follow, from, &to, len, n, tolerance))
            .min(m.speed_cap as f64);
        follow.speed_cap = cap;
        // Inverse time prescribes the block's time also for rotary-only moves (TCP-19).
        let fixed_time = m.feed_mode == FeedMode::InverseTime;
        let as_fast_as_axes = rapid || (rotary_only && !tip.rotary_feed && !fixed_time);
        let feed = if as_fast_as_axes { f64::INFINITY } else { programmed_speed(m, len) * feed_scale };
        let scale = if rapid { ctx.rapid_override } else { ctx.feed_override };
        let (limits, pieces) = kinematic_limits(&grid, axes, feed * scale.max(0.0), cap, true);
        let axis_speed = limits.v;
        let programmed = if as_fast_as_axes { axis_speed } else { feed };
        let work_to = follow.work(&to, 1.0, &std::array::from_fn(|i| m.target[i] - to[i]));
        let mut seg = Segment {
            line: 0,
            block: 0,
            n: None,
            rapid,
            points: Points::new([from, &to, work_from, &work_to, &found.start_dir]),
            circle: None,
            independent: None,
            follow: Some(Box::new(Follow { pieces: pieces.into_boxed_slice(), ..follow })),
            len,
            limits,
            programmed,
            axis_speed,
            bent: Bent::of(&found.start_dir, found.end_dir, found.start_curvature, found.end_curvature),
            tip_rate: if rotary_only { 0.0 } else { 1.0 },
            stop_after: rapid || ctx.exact_stop,
            traits: Traits::of(m, as_fast_as_axes),
            tool_length: m.context.tool_length,
            tip_basis: crate::tip::Basis::default(),
            factor: 1.0,
            block_limit: 0,
            contact: None,
        };
        seg.set_override(ctx.feed_override, ctx.rapid_override);
        seg
    }

    /// A [`Segment::tip_rotation`] under tool centre point control: the tip stands still on
    /// the table, so its program coordinates (X/Y/Z in Π) stay what they were while the rotary
    /// axes turn (Syntec R519, TV-27b); the other axes still follow the machine.
    pub fn keeping_program_xyz(mut self) -> Segment {
        if let Some(f) = self.follow.as_mut() {
            let mut held = Vec3::zeros();
            let (work_from, mut work_to) = (self.points.get(WORK_FROM), self.points.get(WORK_TO));
            for (axis, index) in f.kin.linear.iter().enumerate() {
                if let Some(i) = index {
                    held[axis] = work_from[*i];
                    work_to[*i] = work_from[*i];
                }
            }
            self.points.set(WORK_TO, &work_to);
            // The frame that puts the (fixed) tip at those coordinates.
            f.work_frame = Some(Rigid { r: nalgebra::Matrix3::identity(), o: f.from - held });
        }
        self
    }

    /// Tool tip centre rotation (FANUC MAN-11/12): the rotary axes go from `from` to the
    /// rotary values of `to` in proportion (the path parameter is their angle, fed at
    /// `feed_deg_min`), X/Y/Z keep the tool tip (`tool_length` long) where it is relative to
    /// the table.
    ///
    /// `axes` are the manual move's limits (FANUC No.1424, TV-MAN-09), below the machine's:
    /// the segment is planned with its own path limits, never against the machine's axes at
    /// every point (`Follow::clamped`), so no axis passes its `axes.v` and the path speed is
    /// the slowest axis's all along (the tip stays, the axes keep their proportions). The linear
    /// axes' resultant (the carriage's tangential speed) is held to the lowest `axes.v` of the
    /// linear axes that move (MAN-11/12: "the synthetic speed of the linear axes … does not
    /// exceed the manual rapid traverse rate (No.1424) of any moving linear axis").
    pub fn tip_rotation(
        kin: std::sync::Arc<Kinematics>,
        from: &Pos,
        work_from: &Pos,
        to: &Pos,
        tool_length: f64,
        feed_deg_min: f64,
        axes: &AxisLimits,
    ) -> Segment {
        let tip = kin.forward(from, tool_length).tip;
        let len = rotary_travel(&kin, from, to);
        let linear: Vec<usize> = kin.linear.iter().flatten().copied().collect();
        let follow = Follow { clamped: true, ..Follow::plain(kin, tool_length, tip, tip) };
        let end = follow.at(from, to, 1.0);
        let offset: Pos = std::array::from_fn(|i| work_from[i] - from[i]);
        // Cells of at most half a degree: the bounds over a cell exceed the rates at its points
        // by the bend over half of it (with 64 cells a JOG's full turn ran 5 % under its clamp).
        let cells = (CELLS_PER_SAMPLE * 32).max((2.0 * len).ceil().min(4096.0) as usize);
        let grid = Grid::new(|u| follow.at(from, to, u), len, cells, axes);
        let found = grid.whole();
        let cap = linear_resultant_cap(&grid, &linear, axes, &found);
        // Whole: a handle interruption runs its tip rotation as the one run its planner
        // releases first (`controller/interrupt.rs`), so a manual rotation is never cut.
        let (limits, _) = kinematic_limits(&grid, axes, feed_deg_min / 60.0, cap, false);
        let mut seg = Segment {
            line: 0,
            block: 0,
            n: None,
            rapid: false,
            points: Points::new([
                from,
                &end,
                work_from,
                &std::array::from_fn(|i| end[i] + offset[i]),
                &found.start_dir,
            ]),
            circle: None,
            independent: None,
            follow: Some(Box::new(follow)),
            len,
            limits,
            programmed: feed_deg_min / 60.0,
            axis_speed: limits.v,
            bent: Bent::of(&found.start_dir, found.end_dir, found.start_curvature, found.end_curvature),
            tip_rate: 0.0,
            stop_after: true,
            traits: Traits::default(),
            tool_length,
            // The caller places it in the workpiece system it runs in.
            tip_basis: crate::tip::Basis { tool_length, ..Default::default() },
            factor: 1.0,
            block_limit: 0,
            contact: None,
        };
        seg.set_override(1.0, 1.0);
        seg
    }

    /// Turn a rapid into the non-linear type: every axis its own S-curve at its own rapid rate
    /// (× override), all starting together; the block lasts as long as the slowest axis. The
    /// path parameter becomes the time, run at speed 1 with no limit on its acceleration.
    fn make_independent(&mut self, axes: &AxisLimits, rapid_override: f64) {
        let mut profiles: [Option<Profile>; MAX_AXES] = Default::default();
        let mut duration: f64 = 0.0;
        let (from, to) = (self.from(), self.to());
        for (i, profile) in profiles.iter_mut().enumerate().take(axes.count) {
            let travel = (to[i] - from[i]).abs();
            if travel > 0.0 {
                let lim = Limits { v: axes.v[i] * rapid_override.max(0.0), a: axes.a[i], j: axes.j[i] };
                let p = Profile::plan(0.0, 0.0, travel, &lim);
                duration = duration.max(p.duration());
                *profile = Some(p);
            }
        }
        if !duration.is_finite() || duration <= 0.0 {
            return;
        }
        self.len = duration;
        self.limits = Limits { v: 1.0, a: f64::INFINITY, j: f64::INFINITY };
        self.axis_speed = 1.0;
        self.programmed = 1.0;
        self.tip_rate = 0.0;
        self.independent = Some(Box::new(profiles));
    }

    /// The programmed feed before the override, per minute of the path parameter.
    pub fn programmed_feed(&self) -> f64 {
        self.programmed * 60.0
    }

    /// The same motion moved by a manual intervention with manual absolute off (FANUC MAN-02,
    /// MAN-03): every axis by `machine`; a path the axes follow through the kinematics instead
    /// has its tool tip moved by `tip` in the table frame (so the shift turns with the table); a
    /// move in machine coordinates stays.
    pub fn shifted(&self, machine: &Pos, tip: Vec3) -> Segment {
        // The pieces were cut for the path before the shift: the shifted one runs whole.
        let mut seg = self.whole();
        if self.traits.has(Traits::MACHINE_COORDINATES) {
            return seg;
        }
        let (mut from, mut to) = (self.from(), self.to());
        match &mut seg.follow {
            Some(f) => {
                (f.from, f.to) = (f.from + tip, f.to + tip);
                if let Some(c) = &mut f.circle {
                    c.center += tip;
                }
                (from, to) = (f.at(&from, &to, 0.0), f.at(&from, &to, 1.0));
            }
            None => {
                for ((from, to), d) in from.iter_mut().zip(to.iter_mut()).zip(machine) {
                    (*from, *to) = (*from + d, *to + d);
                }
            }
        }
        seg.points.set(FROM, &from);
        seg.points.set(TO, &to);
        seg
    }

    /// The first three derivatives by s of every axis at evenly spaced points of a kinematic
    /// path, its ends included (as many as its limits were found from), for planning its speed
    /// against the axes' own limits (`motion::optimal`); `None` for other segments, and for
    /// one whose limits are not the machine's (G54.4's rotary clamp).
    pub(super) fn derivatives(&self, axes: &AxisLimits) -> Option<Grid> {
        let f = self.follow.as_ref().filter(|f| !f.clamped && self.len > 1e-9)?;
        let sweep = f.circle.as_ref().map_or(0.0, |c| c.sweep.to_degrees());
        let (from, to) = (self.from(), self.to());
        let n = sample_count(rotary_travel(&f.kin, &from, &to), sweep);
        let q = |u| f.at(&from, &to, u);
        let lattice = |cells| Grid::lattice(q, self.len, cells, axes);
        Some(if f.bends_sharply() {
            Grid::fine(lattice, q, CELLS_PER_SAMPLE * n, axes)
        } else {
            lattice(CELLS_PER_SAMPLE * n)
        })
    }

    /// The highest path speed that is not the axes' own: the programmed feed after the
    /// override and the program's tolerance (none for a move that runs as fast as the axes
    /// allow, unless an override lowers it).
    pub(super) fn speed_cap(&self) -> f64 {
        let tolerance = self.follow.as_ref().map_or(f64::INFINITY, |f| f.speed_cap);
        if self.traits.has(Traits::UNFED) && self.factor >= 1.0 {
            return tolerance;
        }
        (self.programmed * self.factor).min(tolerance)
    }

    /// A tool tip path (tool centre point control, the tilted working plane): the axes follow
    /// a programmed tip through the kinematics, not in machine coordinates.
    pub fn is_tip_path(&self) -> bool {
        self.follow.is_some() && !self.traits.has(Traits::MACHINE_COORDINATES)
    }

    /// A path the axes follow through the kinematics, limited by the machine's own axis
    /// limits (its speed can be planned against them at every point, `Segment::derivatives`).
    pub fn is_kinematic(&self) -> bool {
        self.follow.as_ref().is_some_and(|f| !f.clamped) && self.len > 0.0
    }

    /// Whether this is a non-linear rapid (its path parameter is the time).
    pub fn is_independent(&self) -> bool {
        self.independent.is_some()
    }

    /// Tool tip speed (mm/s) at distance `s` when the path parameter moves at `v`.
    pub fn tip_speed(&self, s: f64, v: f64) -> f64 {
        match &self.independent {
            None => v * self.tip_rate,
            Some(profiles) => {
                let speed = |i: usize| profiles[i].as_ref().map_or(0.0, |p| p.at(s).v);
                (speed(0).powi(2) + speed(1).powi(2) + speed(2).powi(2)).sqrt()
            }
        }
    }

    /// Apply the feed or rapid override (fractions) to the programmed speed.
    pub fn set_override(&mut self, feed: f64, rapid: f64) {
        if self.independent.is_some() {
            // Its axes' profiles were planned with the override of the time.
            return;
        }
        let k = match (self.rapid, self.traits.has(Traits::FIXED_FEED)) {
            (true, _) => rapid,
            (false, true) => 1.0,
            (false, false) => feed,
        };
        self.factor = k.max(0.0);
        self.limits.v = self.axis_speed.min(self.programmed * self.factor);
    }

    /// Machine positions at the start and the end.
    pub fn from(&self) -> Pos {
        self.points.get(FROM)
    }

    pub fn to(&self) -> Pos {
        self.points.get(TO)
    }

    /// Programming positions at the start and the end.
    pub fn work_from(&self) -> Pos {
        self.points.get(WORK_FROM)
    }

    pub fn work_to(&self) -> Pos {
        self.points.get(WORK_TO)
    }

    /// d(axis)/ds at the start and at the end (the tangents, for corners).
    pub fn start_dir(&self) -> Pos {
        self.points.get(START_DIR)
    }

    pub fn end_dir(&self) -> Pos {
        self.bent.as_ref().map_or_else(|| self.start_dir(), |b| b.end_dir)
    }

    /// d²(axis)/ds² at the start and at the end (zero on a line; toward the centre on an arc).
    pub fn start_curvature(&self) -> &Pos {
        self.bent.as_ref().map_or(&NO_CURVATURE, |b| &b.start_curvature)
    }

    pub fn end_curvature(&self) -> &Pos {
        self.bent.as_ref().map_or(&NO_CURVATURE, |b| &b.end_curvature)
    }

    /// Another start tangent and curvature, the same end.
    fn with_start(&mut self, start_dir: Pos, start_curvature: Pos) {
        self.bent = Bent::of(&start_dir, self.end_dir(), start_curvature, *self.end_curvature());
        self.points.set(START_DIR, &start_dir);
    }

    /// The same start, another end tangent and curvature.
    fn with_end(&mut self, end_dir: Pos, end_curvature: Pos) {
        self.bent = Bent::of(&self.start_dir(), end_dir, *self.start_curvature(), end_curvature);
    }

    /// Whether the next segment is the rest of this motion (a piece of a split kinematic path,
    /// `split`).
    /// A chord of a curve whose bending caps its speed (NURBS, nano smoothing).
    pub fn is_chord(&self) -> bool {
        self.traits.has(Traits::CHORD)
    }

    pub fn continued(&self) -> bool {
        self.traits.has(Traits::CONTINUED)
    }

    /// Where the segment stands in a tapping cycle (`canon::MotionContext::tapping`).
    pub fn tapping(&self) -> Tapping {
        if self.traits.has(Traits::TAP_IN) {
            Tapping::In
        } else if self.traits.has(Traits::TAP_OUT) {
            Tapping::Out
        } else {
            Tapping::No
        }
    }

    /// Cutting feed planned without look-ahead (`Traits::AFTER_INTERPOLATION`).
    pub fn after_interpolation(&self) -> bool {
        self.traits.has(Traits::AFTER_INTERPOLATION)
    }

    pub fn set_after_interpolation(&mut self, on: bool) {
        self.traits.set(Traits::AFTER_INTERPOLATION, on);
    }

    /// The segment as the planner queues it: a kinematic path whose limits change along the
    /// way becomes its pieces, each with the limits of its own stretch, joined smoothly (equal
    /// tangents and curvatures) and ending where the next begins; others stay whole.
    pub fn split(mut self) -> Vec<Segment> {
        let pieces = self.follow.as_mut().map(|f| std::mem::take(&mut f.pieces)).unwrap_or_default();
        if pieces.is_empty() {
            return vec![self];
        }
        let mut out = Vec::with_capacity(pieces.len());
        let (mut start, mut dir, mut curvature) = (0.0, self.start_dir(), *self.start_curvature());
        for (k, piece) in pieces.iter().enumerate() {
            let last = k + 1 == pieces.len();
            let end = if last { self.len } else { piece.end * self.len };
            let mut seg = self.part(start, end);
            seg.with_start(dir, curvature);
            if !last {
                seg.with_end(piece.end_dir, piece.end_curvature);
            }
            seg.axis_speed = piece.limits.v;
            seg.limits = piece.limits;
            if seg.traits.has(Traits::UNFED) {
                seg.programmed = piece.limits.v;
            }
            seg.limits.v = seg.axis_speed.min(seg.programmed * seg.factor);
            seg.stop_after = last && self.stop_after;
            seg.traits.set(Traits::CONTINUED, !last);
            (start, dir, curvature) = (end, piece.end_dir, piece.end_curvature);
            out.push(seg);
        }
        out
    }

    /// The segment, its pieces forgotten: it runs whole.
    fn whole(&self) -> Segment {
        let mut seg = self.clone();
        if let Some(f) = &mut seg.follow {
            f.pieces = Box::default();
        }
        seg
    }

    /// The stretch from distance `s0` to `s1` (a kinematic path's piece).
    fn part(&self, s0: f64, s1: f64) -> Segment {
        let mut p = if s0 > 0.0 { self.tail(s0) } else { self.clone() };
        if s1 < self.len {
            let (to, work_to) = self.at(s1);
            p.points.set(TO, &to);
            p.points.set(WORK_TO, &work_to);
            if let Some(f) = &mut p.follow {
                f.keep_to((s1 - s0) / (self.len - s0));
            }
            p.len = s1 - s0;
        }
        p
    }

    /// Machine and programming positions at distance `s` along the segment.
    pub fn at(&self, s: f64) -> (Pos, Pos) {
        let (to, work_to) = (self.to(), self.work_to());
        if s >= self.len {
            return (to, work_to);
        }
        let from = self.from();
        if let Some(f) = &self.follow {
            let u = if self.len > 0.0 { s / self.len } else { 1.0 };
            let machine = f.at(&from, &to, u);
            let work = f.work(&machine, u, &std::array::from_fn(|i| work_to[i] - to[i]));
            return (machine, work);
        }
        if let Some(profiles) = &self.independent {
            // Each axis on its own profile, `s` seconds in; the offsets are constant.
            let machine: Pos = std::array::from_fn(|i| match &profiles[i] {
                Some(p) => from[i] + p.at(s).s.copysign(to[i] - from[i]),
                None => from[i],
            });
            let work = std::array::from_fn(|i| machine[i] + (work_to[i] - to[i]));
            return (machine, work);
        }
        let u = if self.len > 0.0 { s / self.len } else { 1.0 };
        let work_from = self.work_from();
        let mut machine: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * u);
        let mut work: Pos = std::array::from_fn(|i| work_from[i] + (work_to[i] - work_from[i]) * u);
        if let Some(c) = &self.circle {
            let angle = c.start + c.sweep * u;
            let r = c.r0 + (c.r1 - c.r0) * u;
            let (sin, cos) = angle.sin_cos();
            let (x, y) = (c.center.0 + r * cos, c.center.1 + r * sin);
            // The offsets are constant along an arc: machine = programming + (end offset).
            machine[c.a] = x + (to[c.a] - work_to[c.a]);
            machine[c.b] = y + (to[c.b] - work_to[c.b]);
            work[c.a] = x;
            work[c.b] = y;
        }
        (machine, work)
    }

    /// The programmed tool tip (table frame) at distance `s` along a path the axes follow
    /// through the kinematics, with the tool length it is for; `None` on other segments.
    /// Under cutting point control the tip the cutting point asks for there.
    pub fn programmed_tip(&self, s: f64) -> Option<(crate::kin::Vec3, f64)> {
        // Without TCP the path is not the tip's (`TipMove::head_fixed`): nothing to compare.
        let f = self.follow.as_ref().filter(|f| !f.head_fixed)?;
        let u = if self.len > 0.0 { (s / self.len).clamp(0.0, 1.0) } else { 1.0 };
        let tip = match f.cutting {
            Some(_) => f.aimed_tip(&self.at(s).0, u),
            None => f.tip(u),
        };
        Some((tip, f.tool_length))
    }

    /// Where the tool with the axes at `machine` (its tip at `tip` pointing along `tool`, table
    /// frame) touches the part at distance `s` along the segment: under cutter compensation the
    /// contour (`motion::contact`), under cutting point control the surface (table frame);
    /// `None` on other segments.
    pub fn cutting_point(&self, s: f64, machine: &Pos, tip: Vec3, tool: Vec3) -> Option<Vec3> {
        let u = if self.len > 0.0 { (s / self.len).clamp(0.0, 1.0) } else { 1.0 };
        if let Some(c) = &self.contact {
            return Some(c.point(tip, tool));
        }
        let f = self.follow.as_ref()?;
        let c = f.cutting.as_ref()?;
        let pose = f.kin.forward(machine, f.tool_length);
        Some(c.along.contact(c.lo + (c.hi - c.lo) * u, pose.tip, pose.tool))
    }

    /// Why this block's rotary axes turn in proportion although it asked for another way
    /// (`None`: they do not, or it did not).
    pub fn fallback(&self) -> Option<Fallback> {
        self.follow.as_ref()?.fallback
    }

    /// A circular segment's centre, axis and sweep.
    pub fn turn(&self) -> Option<Turn> {
        if let Some(c) = self.follow.as_ref().and_then(|f| f.circle.as_ref()) {
            return Some(Turn { center: TurnCenter::Tip(c.center), axis: c.e1.cross(&c.e2), sweep: c.sweep });
        }
        let c = self.circle.as_ref()?;
        let unit = |i: usize| (i < 3).then(|| Vec3::ith(i, 1.0));
        // The circle is the programmed one; the machine's axes move by the same less the
        // offsets between them.
        let (from, work_from) = (self.from(), self.work_from());
        let mut center = from;
        center[c.a] = c.center.0 + from[c.a] - work_from[c.a];
        center[c.b] = c.center.1 + from[c.b] - work_from[c.b];
        Some(Turn { center: TurnCenter::Axes(center), axis: unit(c.a)?.cross(&unit(c.b)?), sweep: c.sweep })
    }

    /// The segment up to distance `s`, ending there at rest (where a stored stroke limit stops
    /// the machine in a block nothing checked before it moved: `motion::stroke_stop`).
    pub fn head(&self, s: f64) -> Segment {
        let s = s.clamp(0.0, self.len);
        let u = if self.len > 0.0 { s / self.len } else { 1.0 };
        let mut seg = self.whole().part(0.0, s);
        if let Some(c) = seg.circle.as_mut().filter(|_| u < 1.0) {
            c.r1 = c.r0 + (c.r1 - c.r0) * u;
            c.sweep *= u;
        }
        seg.stop_after = true;
        seg
    }

    /// What is left of the segment from distance `s` on (a feed hold resumes from there).
    pub fn tail(&self, s: f64) -> Segment {
        let s = s.clamp(0.0, self.len);
        let u = if self.len > 0.0 { s / self.len } else { 1.0 };
        let (from, work_from) = self.at(s);
        // Pieces are shares of the whole path: a tail (of a segment not yet split) runs whole,
        // within the whole path's limits.
        let mut tail = Segment { len: self.len - s, ..self.whole() };
        tail.points.set(FROM, &from);
        tail.points.set(WORK_FROM, &work_from);
        if let Some(c) = &mut tail.circle {
            c.start += c.sweep * u;
            c.r0 += (c.r1 - c.r0) * u;
            c.sweep *= 1.0 - u;
            let (mut dir, mut curvature) = (self.start_dir(), *self.start_curvature());
            let share = dir[c.a].hypot(dir[c.b]);
            c.set_tangent(&mut dir, c.start, share);
            c.set_curvature(&mut curvature, c.start, c.r0, share);
            tail.with_start(dir, curvature);
        }
        if let Some(f) = &mut tail.follow {
            f.cut(u);
        }
        tail
    }

    /// Points along a path the axes follow through the kinematics, the ends included, with
    /// their path distances (for the stroke check: the axes may bulge out between the ends);
    /// 17 to a segment, none for other segments.
    pub fn follow_samples(&self) -> Vec<(f64, Pos)> {
        const N: usize = 16;
        if self.follow.is_none() || self.len <= 0.0 {
            return Vec::new();
        }
        // The machine positions of `Segment::at` (its programming ones, unused here, cost a
        // frame change each).
        let (f, from, to) = (self.follow.as_ref().expect("a kinematic path"), self.from(), self.to());
        let machine = |s: f64| if s >= self.len { to } else { f.at(&from, &to, s / self.len) };
        (0..=N).map(|k| self.len * k as f64 / N as f64).map(|s| (s, machine(s))).collect()
    }

    /// The point in `[lo, hi]` where axis `i` is largest (`sign` 1) or smallest (-1), for a
    /// single peak there, by golden-section search. The best point evaluated is the answer, not
    /// the last bracket's middle: where the axis jumps (the inverse kinematics changing branch
    /// mid-block) the search closes in on the jump and its middle can fall on the low side.
    pub fn peak(&self, i: usize, sign: f64, mut lo: f64, mut hi: f64) -> Pos {
        const INV_PHI: f64 = 0.618_033_988_749_894_9;
        let mut best = (f64::MIN, self.at(lo).0);
        let mut f = |s: f64| {
            let p = self.at(s).0;
            if sign * p[i] > best.0 {
                best = (sign * p[i], p);
            }
            sign * p[i]
        };
        let (mut a, mut b) = (hi - INV_PHI * (hi - lo), lo + INV_PHI * (hi - lo));
        let (mut fa, mut fb) = (f(a), f(b));
        for _ in 0..30 {
            if fa < fb {
                lo = a;
                (a, fa) = (b, fb);
                b = lo + INV_PHI * (hi - lo);
                fb = f(b);
            } else {
                hi = b;
                (b, fb) = (a, fa);
                a = hi - INV_PHI * (hi - lo);
                fa = f(a);
            }
        }
        f(0.5 * (lo + hi));
        best.1
    }

    /// The axis-space extremes an arc reaches between its end points (for the stroke check):
    /// the quadrant points it sweeps over.
    pub fn arc_extremes(&self) -> impl Iterator<Item = Pos> + '_ {
        let quarter = std::f64::consts::FRAC_PI_2;
        self.circle.iter().flat_map(move |c| {
            let (lo, hi) = if c.sweep < 0.0 { (c.start + c.sweep, c.start) } else { (c.start, c.start + c.sweep) };
            let first = (lo / quarter).ceil() as i64;
            let last = (hi / quarter).floor() as i64;
            (first..=last.min(first + 4)).map(move |k| self.at(self.len * ((k as f64 * quarter - c.start) / c.sweep)).0)
        })
    }
}

/// The speed F asks for along a path `len` long, per second (G93: the block takes 1/F min).
fn programmed_speed(m: &Motion, len: f64) -> f64 {
    let per_minute = match m.feed_mode {
        FeedMode::PerMinute => m.feed,
        FeedMode::PerRevolution => m.feed * m.spindle,
        FeedMode::InverseTime => m.feed * len,
    };
    per_minute / 60.0
}

/// The highest path speed at which the resultant of the `linear` axes' speeds stays within
/// the lowest `axes.v` of those that move (`found` the grid's bounds): the resultant's rate by
/// s bounded over each cell as [`Grid::cell`] bounds an axis's (its points' largest, raised by
/// the next derivative's times half the cell). Infinite when no linear axis moves.
fn linear_resultant_cap(grid: &Grid, linear: &[usize], axes: &AxisLimits, found: &Sampled) -> f64 {
    let tiny = 1e-12;
    let clamp = linear.iter().filter(|&&i| found.rate[i] > tiny).map(|&i| axes.v[i]).fold(f64::INFINITY, f64::min);
    let size = |k: usize, order: usize| linear.iter().map(|&i| grid.d[k][order][i].powi(2)).sum::<f64>().sqrt();
    let rate = (0..grid.cells())
        .map(|c| {
            let half = 0.5 * grid.len * (grid.u[c + 1] - grid.u[c]);
            size(c, 0).max(size(c + 1, 0)) + size(c, 1).max(size(c + 1, 1)) * half
        })
        .fold(0.0, f64::max);
    if clamp.is_finite() && rate > tiny {
        clamp / rate
    } else {
        f64::INFINITY
    }
}

/// The rotary axes' combined travel (degrees) from `from` to `to`.
fn rotary_travel(kin: &Kinematics, from: &Pos, to: &Pos) -> f64 {
    (0..kin.axes).filter(|i| !kin.linear.contains(&Some(*i))).map(|i| (to[i] - from[i]).powi(2)).sum::<f64>().sqrt()
}

fn norm(v: &Pos) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

impl Circle {
    /// The plane axes' d/ds at `angle`, the plane part being `share` of the path.
    fn set_tangent(&self, dir: &mut Pos, angle: f64, share: f64) {
        let (sin, cos) = angle.sin_cos();
        let turn = self.sweep.signum();
        dir[self.a] = -sin * turn * share;
        dir[self.b] = cos * turn * share;
    }

    /// The plane axes' d²/ds² at `angle`, radius `r`: share² / r toward the centre.
    fn set_curvature(&self, k: &mut Pos, angle: f64, r: f64, share: f64) {
        let (sin, cos) = angle.sin_cos();
        let scale = share * share / r.max(1e-12);
        k[self.a] = -cos * scale;
        k[self.b] = -sin * scale;
    }
}

fn circle(arc: &Arc, start: &Pos, end: &Pos) -> Circle {
    let (a, b, _) = arc.plane_axes;
    let (cx, cy) = (arc.center[a], arc.center[b]);
    Circle {
        a,
        b,
        center: (cx, cy),
        r0: arc.radius,
        r1: (end[a] - cx).hypot(end[b] - cy),
        start: (start[b] - cy).atan2(start[a] - cx),
        sweep: arc.sweep_deg.to_radians(),
    }
}

/// The limits `along` of an arc's path, fed at `feed` (per second), bounded for its turning.
///
/// The plane's axes also accelerate toward the centre (w²/r at a plane speed w) and that
/// acceleration turns: at angle φ an axis accelerates −(sin φ·a + cos φ·w²/r) and jerks
/// sin φ·(w³/r² − j) − cos φ·3·w·a/r (a, j the plane's acceleration and jerk along the path),
/// the two parts in quadrature. As on a kinematic path (`kinematic_limits`) the top speed comes
/// first: w²/r and w³/r² within a share σ of the plane axes' acceleration and jerk. Speed
/// changes get what is left at that top speed (an override raised mid-block may take the arc
/// there): a ≤ √(A² − (w²/r)²), the cross term 3·w·a/r within half of √(J² − (w³/r²)²), and
/// j ≤ √(J² − (3·w·a/r)²) − w³/r². σ is the one of [`CRUISE_SHARES`] whose rest-to-rest time
/// over the arc is the shorter: a high share cruises fast but leaves little for speed changes
/// (a small circle entered slowly from a line spends most of its time changing speed), a low
/// one the other way round.
fn arc_limits(along: Limits, c: &Circle, rate: &Pos, axes: &AxisLimits, len: f64, feed: f64) -> Limits {
    let mut best: Option<(f64, Limits)> = None;
    for share in CRUISE_SHARES {
        let lim = arc_limits_with_share(along, c, rate, axes, share);
        let time = super::planner::chain_time(&[(len, Limits { v: lim.v.min(feed), ..lim })]);
        if best.is_none_or(|(t, _)| time < t * (1.0 - 1e-9)) {
            best = Some((time, lim));
        }
    }
    best.map_or(along, |(_, lim)| lim)
}

/// [`arc_limits`] with the turning at the top speed taking `share` of the plane axes' limits.
fn arc_limits_with_share(along: Limits, c: &Circle, rate: &Pos, axes: &AxisLimits, share: f64) -> Limits {
    let r = c.r0.min(c.r1).max(1e-9);
    // Plane speed w = k·v for a path speed v.
    let k = rate[c.a].max(1e-12);
    let (amax, jmax) = (axes.a[c.a].min(axes.a[c.b]), axes.j[c.a].min(axes.j[c.b]));
    let w = (share * amax * r).sqrt().min((share * jmax * r * r).cbrt()).min(along.v * k).max(1e-12);
    let (pull, turn) = (w * w / r, w * w * w / (r * r));
    let a = (amax * amax - pull * pull).sqrt().min(0.5 * (jmax * jmax - turn * turn).sqrt() * r / (3.0 * w));
    let cross = 3.0 * w * a / r;
    let j = (jmax * jmax - cross * cross).sqrt() - turn;
    Limits { v: along.v.min(w / k), a: along.a.min(a / k), j: along.j.min(j / k) }
}

#[cfg(test)]
mod tests {
    /// The look-ahead holds hundreds of segments per controller (issue 18: a running one under
    /// 200 kB): a field added to every segment shows here first.
    #[test]
    fn a_segment_stays_small() {
        let size = std::mem::size_of::<super::Segment>();
        println!("size_of::<Segment>() = {size}");
        assert!(size <= 384, "a segment takes {size} bytes");
    }

    /// A segment's positions read back bit for bit, those of axes beyond the inline ones (and
    /// a -0.0 there) included.
    #[test]
    fn points_read_back_bit_for_bit() {
        use super::{Points, FROM, TO};
        let bits = |p: crate::canon::Pos| p.map(f64::to_bits);
        let five = [1.5, -2.0, -0.0, 3.0, 4.0, 0.0, 0.0, 0.0];
        let eight = [0.1, 0.0, 0.0, 0.0, 0.0, -0.0, 7.25, 1e-300];
        let mut points = Points::new([&five; 5]);
        assert!(points.rest.is_none(), "five axes are kept inline");
        points.set(TO, &eight);
        assert_eq!(bits(points.get(TO)), bits(eight));
        assert_eq!(bits(points.get(FROM)), bits(five));
        points.set(TO, &five);
        assert_eq!(bits(points.get(TO)), bits(five));
    }
}
