//! The geometry of one motion: where the axes are at each distance along it, and the speed,
//! acceleration and jerk the path may have so that no axis exceeds its own limits.
//!
//! The path parameter `s` is the FANUC feed length: the Euclidean length over every moving
//! axis, millimetres and degrees alike (a simultaneous linear and rotary move is fed at F in
//! that combined length, FANUC "feedrate for simultaneous rotary and linear axis"). Straight
//! moves are straight in axis space; arcs are circles (or spirals, when the end radius differs
//! within the tolerance) in the plane's two axes with every other axis moving in proportion.

use super::profile::{Limits, Profile};
use crate::canon::{Arc, FeedMode, Motion, MotionKind, Pos};
use crate::kin::{Kinematics, Vec3};
use crate::machine::{MachineConfig, MotionOptions, MAX_AXES};

/// Per-axis limits in the units of the axis (mm or deg) per second.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisLimits {
    pub count: usize,
    pub v: Pos,
    pub a: Pos,
    pub j: Pos,
}

impl AxisLimits {
    pub fn of(m: &MachineConfig) -> AxisLimits {
        let mut l = AxisLimits { count: m.axes.len(), v: [0.0; MAX_AXES], a: [0.0; MAX_AXES], j: [0.0; MAX_AXES] };
        for (i, axis) in m.axes.iter().enumerate() {
            l.v[i] = axis.rapid / 60.0;
            l.a[i] = axis.max_accel();
            l.j[i] = axis.max_jerk();
        }
        l
    }

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

/// One motion ready for planning.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub line: u32,
    pub n: Option<u32>,
    pub rapid: bool,
    /// Machine and programming positions at the start and the end.
    pub from: Pos,
    pub to: Pos,
    pub work_from: Pos,
    pub work_to: Pos,
    circle: Option<Circle>,
    /// A non-linear rapid: each axis's own rest-to-rest profile (`None` for axes that stay);
    /// the path parameter is then the time.
    independent: Option<Box<[Option<Profile>; MAX_AXES]>>,
    /// Tool tip centre rotation: the rotary axes move, X/Y/Z keep the tip on one point.
    pivot: Option<Box<Pivot>>,
    /// Length of the path parameter (mm and degrees).
    pub len: f64,
    /// The speed the program asks for (override applied) and what the axes allow, per second.
    pub limits: Limits,
    /// The programmed speed before the override, and the highest the axes allow.
    programmed: f64,
    axis_speed: f64,
    /// Axis rates d(axis)/ds at the start and at the end (the tangents, for corners).
    pub start_dir: Pos,
    pub end_dir: Pos,
    /// d²(axis)/ds² at the start and at the end (zero on a line; toward the centre on an arc).
    pub start_curvature: Pos,
    pub end_curvature: Pos,
    /// Tool tip (X, Y, Z of the programming system) distance per unit of `s`.
    pub tip_rate: f64,
    /// The motion must come to a stop at its end (G09, G61, rapids).
    pub stop_after: bool,
    /// The feed override does not act (G63, tapping cycles).
    fixed_feed: bool,
}

/// The mechanism and the point a tool tip centre rotation keeps the tip on.
#[derive(Debug, Clone, PartialEq)]
struct Pivot {
    kin: std::sync::Arc<Kinematics>,
    /// Tool tip in the table frame, and the tool length.
    tip: Vec3,
    tool_length: f64,
}

impl Pivot {
    /// Every axis at `u` of the way from `from` to `to`, X/Y/Z then put so that the tip stays.
    fn at(&self, from: &Pos, to: &Pos, u: f64) -> Pos {
        let mut q: Pos = std::array::from_fn(|i| from[i] + (to[i] - from[i]) * u);
        let carriage = self.kin.carriage_for(&q, self.tip, self.tool_length);
        for (axis, index) in self.kin.linear.iter().enumerate() {
            if let Some(i) = index {
                q[*i] = carriage[axis];
            }
        }
        q
    }
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
    pub fn new(m: &Motion, from: &Pos, work_from: &Pos, axes: &AxisLimits, ctx: FeedContext) -> Segment {
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
        let mut limits = axes.along(&rate);
        if let Some(c) = &circle {
            arc_limits(&mut limits, c, &rate, axes);
        }
        let axis_speed = limits.v;
        let programmed = if rapid {
            axis_speed
        } else {
            let per_minute = match m.feed_mode {
                FeedMode::PerMinute => m.feed,
                FeedMode::PerRevolution => m.feed * m.spindle,
                FeedMode::InverseTime => m.feed * len,
            };
            per_minute / 60.0 * feed_scale
        };
        let mut seg = Segment {
            line: 0,
            n: None,
            rapid,
            from: *from,
            to: m.machine,
            work_from: *work_from,
            work_to: m.target,
            circle,
            independent: None,
            pivot: None,
            len,
            limits,
            start_dir,
            end_dir,
            start_curvature,
            end_curvature,
            tip_rate,
            stop_after: rapid || ctx.exact_stop,
            fixed_feed: m.context.fixed_feed,
            programmed,
            axis_speed,
        };
        seg.set_override(ctx.feed_override, ctx.rapid_override);
        if rapid && ctx.options.nonlinear_rapid {
            seg.make_independent(axes, ctx.rapid_override);
        }
        seg
    }

    /// Tool tip centre rotation (FANUC MAN-11/12): the rotary axes go from `from` to the
    /// rotary values of `to` in proportion (the path parameter is their angle, fed at
    /// `feed_deg_min`), X/Y/Z keep the tool tip (`tool_length` long) where it is relative to
    /// the table. The axes' rates along the way are sampled to bound the path's speed,
    /// acceleration and jerk.
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
        let pivot = Pivot { kin, tip, tool_length };
        let rotary: Vec<usize> = (0..axes.count).filter(|i| !pivot.kin.linear.contains(&Some(*i))).collect();
        let len = rotary.iter().map(|&i| (to[i] - from[i]).powi(2)).sum::<f64>().sqrt();
        let end = pivot.at(from, to, 1.0);
        let offset: Pos = std::array::from_fn(|i| work_from[i] - from[i]);
        // The first three derivatives of every axis by s, by differences at 33 points.
        const N: usize = 32;
        let h = 1.0 / (4.0 * N as f64);
        let q = |u: f64| pivot.at(from, to, u);
        let (mut rate, mut bend, mut twist) = ([0.0f64; MAX_AXES], [0.0f64; MAX_AXES], [0.0f64; MAX_AXES]);
        let (mut start_dir, mut end_dir) = ([0.0; MAX_AXES], [0.0; MAX_AXES]);
        let (mut start_curvature, mut end_curvature) = ([0.0; MAX_AXES], [0.0; MAX_AXES]);
        if len > 0.0 {
            for k in 0..=N {
                let u = k as f64 / N as f64;
                let (a, b, c, d) = (q(u - 1.5 * h), q(u - 0.5 * h), q(u + 0.5 * h), q(u + 1.5 * h));
                let ds = h * len;
                for i in 0..axes.count {
                    let d1 = (c[i] - b[i]) / ds;
                    let d2 = (d[i] - c[i] - b[i] + a[i]) / (2.0 * ds * ds);
                    let d3 = (d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i]) / (ds * ds * ds);
                    rate[i] = rate[i].max(d1.abs());
                    bend[i] = bend[i].max(d2.abs());
                    twist[i] = twist[i].max(d3.abs());
                    if k == 0 {
                        (start_dir[i], start_curvature[i]) = (d1, d2);
                    }
                    if k == N {
                        (end_dir[i], end_curvature[i]) = (d1, d2);
                    }
                }
            }
        }
        // Axis i moves at v*q1, accelerates a*q1 + v^2*q2 and jerks j*q1 + 3*v*a*q2 + v^3*q3
        // (q1..q3 its derivatives by s): half the acceleration and a third of the jerk for each
        // of the terms.
        let mut limits = axes.along(&rate.map(|r| 2.0 * r));
        limits.j = limits.j.min(axes.along(&rate.map(|r| 3.0 * r)).j);
        for i in 0..axes.count {
            if bend[i] > 1e-12 {
                limits.v = limits.v.min((0.5 * axes.a[i] / bend[i]).sqrt());
                limits.v = limits.v.min(axes.j[i] / (9.0 * axes.a[i] * bend[i]).max(1e-12));
            }
            if twist[i] > 1e-12 {
                limits.v = limits.v.min((axes.j[i] / (3.0 * twist[i])).cbrt());
            }
        }
        let mut seg = Segment {
            line: 0,
            n: None,
            rapid: false,
            from: *from,
            to: end,
            work_from: *work_from,
            work_to: std::array::from_fn(|i| end[i] + offset[i]),
            circle: None,
            independent: None,
            pivot: Some(Box::new(pivot)),
            len,
            limits,
            programmed: feed_deg_min / 60.0,
            axis_speed: limits.v,
            start_dir,
            end_dir,
            start_curvature,
            end_curvature,
            tip_rate: 0.0,
            stop_after: true,
            fixed_feed: false,
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
        for (i, profile) in profiles.iter_mut().enumerate().take(axes.count) {
            let travel = (self.to[i] - self.from[i]).abs();
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
        let k = match (self.rapid, self.fixed_feed) {
            (true, _) => rapid,
            (false, true) => 1.0,
            (false, false) => feed,
        };
        self.limits.v = self.axis_speed.min(self.programmed * k.max(0.0));
    }

    /// Machine and programming positions at distance `s` along the segment.
    pub fn at(&self, s: f64) -> (Pos, Pos) {
        if s >= self.len {
            return (self.to, self.work_to);
        }
        if let Some(p) = &self.pivot {
            let u = if self.len > 0.0 { s / self.len } else { 1.0 };
            let machine = p.at(&self.from, &self.to, u);
            let work = std::array::from_fn(|i| machine[i] + (self.work_to[i] - self.to[i]));
            return (machine, work);
        }
        if let Some(profiles) = &self.independent {
            // Each axis on its own profile, `s` seconds in; the offsets are constant.
            let machine: Pos = std::array::from_fn(|i| match &profiles[i] {
                Some(p) => self.from[i] + p.at(s).s.copysign(self.to[i] - self.from[i]),
                None => self.from[i],
            });
            let work = std::array::from_fn(|i| machine[i] + (self.work_to[i] - self.to[i]));
            return (machine, work);
        }
        let u = if self.len > 0.0 { s / self.len } else { 1.0 };
        let mut machine: Pos = std::array::from_fn(|i| self.from[i] + (self.to[i] - self.from[i]) * u);
        let mut work: Pos = std::array::from_fn(|i| self.work_from[i] + (self.work_to[i] - self.work_from[i]) * u);
        if let Some(c) = &self.circle {
            let angle = c.start + c.sweep * u;
            let r = c.r0 + (c.r1 - c.r0) * u;
            let (sin, cos) = angle.sin_cos();
            let (x, y) = (c.center.0 + r * cos, c.center.1 + r * sin);
            // The offsets are constant along an arc: machine = programming + (end offset).
            machine[c.a] = x + (self.to[c.a] - self.work_to[c.a]);
            machine[c.b] = y + (self.to[c.b] - self.work_to[c.b]);
            work[c.a] = x;
            work[c.b] = y;
        }
        (machine, work)
    }

    /// What is left of the segment from distance `s` on (a feed hold resumes from there).
    pub fn tail(&self, s: f64) -> Segment {
        let s = s.clamp(0.0, self.len);
        let u = if self.len > 0.0 { s / self.len } else { 1.0 };
        let (from, work_from) = self.at(s);
        let mut tail = Segment { from, work_from, len: self.len - s, ..self.clone() };
        if let Some(c) = &mut tail.circle {
            c.start += c.sweep * u;
            c.r0 += (c.r1 - c.r0) * u;
            c.sweep *= 1.0 - u;
            let share = self.start_dir[c.a].hypot(self.start_dir[c.b]);
            c.set_tangent(&mut tail.start_dir, c.start, share);
            c.set_curvature(&mut tail.start_curvature, c.start, c.r0, share);
        }
        tail
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

/// On an arc the plane's axes also accelerate toward the centre (v²/r) and that acceleration
/// turns (v³/r² of jerk): half of each axis's acceleration and a third of its jerk go to the
/// turning, the rest to speed changes along the path.
fn arc_limits(lim: &mut Limits, c: &Circle, rate: &Pos, axes: &AxisLimits) {
    let r = c.r0.min(c.r1).max(1e-9);
    let k = rate[c.a].max(1e-12);
    let (amax, jmax) = (axes.a[c.a].min(axes.a[c.b]), axes.j[c.a].min(axes.j[c.b]));
    // Plane speed w = k·v: w²/r ≤ amax/2, w³/r² ≤ jmax/3, and the cross term 3·w·a_t·k/r ≤ jmax/3
    // with a_t ≤ amax/(2k).
    let w = (0.5 * amax * r).sqrt().min((jmax / 3.0 * r * r).cbrt()).min(jmax * r / (4.5 * amax));
    lim.v = lim.v.min(w / k);
    lim.a = lim.a.min(0.5 * amax / k);
    lim.j = lim.j.min(jmax / 3.0 / k);
}
