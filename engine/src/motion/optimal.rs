//! The speed along a run of kinematic segments (TCP, tilted planes, tip rotation) planned
//! against the axes' own limits at every point, not against path limits bounded over a stretch
//! (`path::kinematic_limits`, which the planner's look-ahead keeps using for junction speeds).
//!
//! Along a kinematic path axis i moves at v·q1, accelerates a·q1 + v²·q2 and jerks
//! j·q1 + 3·v·a·q2 + v³·q3 (q1..q3 its derivatives by s at that point, v, a, j the path's).
//! At every 1 ms tick the plan takes the highest path jerk for which every axis stays within its
//! limits, steering toward the highest speed allowed ahead (`drive`): the binding axis is then at
//! its jerk, its acceleration or its speed limit — or the tip at the feed — the rule issue 17
//! asks of every sample. One such drive runs forward from the start, one backward from the end
//! (the same drive on the reversed path: a stop read backwards is a start); the profile follows
//! the forward drive, ramps its acceleration to zero at the latest tick from which the backward
//! drive can be met at the same speed (`join`), cruises the gap and follows the backward drive
//! to the end, so it starts and ends at the planner's speeds with zero acceleration. Where no
//! join is found (both drives still accelerating toward each other where they cross), the
//! run is planned again with its cap a little below the crossing speed around it.
//!
//! The derivatives come from the segments' own grids (`Segment::derivatives`), interpolated
//! between points; the plan keeps to [`MARGIN`] of each axis's acceleration and jerk for what
//! interpolation misses, bounds its speed with what the rate can add between points, and checks
//! every phase against [`WHOLE`], a hair under the whole limits, at the end. A drive caught
//! above a limit (a top speed falling faster than its jerk can build the deceleration, or a
//! landing that overshoots its cap) or with no jerk left at all runs again softer there
//! (`Track::soften`). Anything it cannot do — a
//! path that turns faster than its drive can follow, a ramp that would break a limit, a run too
//! long for a table — leaves the run to the analytic profile (`None`), as does a plan slower
//! than it. `stop` plans a feed hold's stop on such a run the same way (a drive toward rest).

use super::path::{AxisLimits, Segment};
use super::profile::{PathState, Profile};
use crate::canon::Pos;
use crate::machine::MAX_AXES;

/// The tick of the drives (the control's interpolation period), seconds.
const DT: f64 = 0.001;
/// The share of each axis limit the plan keeps to.
const MARGIN: f64 = 0.98;
/// The share of each axis limit the final check ([`verified`]) and a caught drive
/// ([`Track::steer`]) hold the plan to, where the plan's own bounds cannot be kept: a hair
/// under the whole limit, for the axes' rates between points, which the plan takes as
/// linear. (At the whole limit a drive squeezed between an axis's acceleration and another's
/// jerk rode at 99.9997 % of the acceleration in the plan and 100.002 % on the sampled axes.)
const WHOLE: f64 = 0.999 / MARGIN;
/// The share of an axis's speed the drives steer to (what they overshoot by when the
/// path's limits close in is within the rest).
const STEER: f64 = 0.995;
/// The share of an axis's acceleration and jerk a steady speed may take with its own v²·q2 and
/// v³·q3 (the rest lets the speed follow the path's changes). At 94 % a drive that follows a
/// cap a little below it (landing on each point's) left the binding axis under 90 %.
const CRUISE: f64 = 0.97;
/// The share of the jerk at hand that a ramp toward a target speed uses (less near where a
/// drive overshot a landing, [`Track::soften`]).
const RAMP: f64 = 0.95;
/// What [`Track::soften`] multiplies the landings' share of the jerk by where a drive is
/// caught at the same point again.
const RAMP_SOFTER: f64 = 0.95;
/// The shares of the jerk at hand tried for the ramp into the cruise that joins the drives.
const RAMPS: [f64; 4] = [RAMP, 0.8, 0.6, 0.4];
/// The share of the deceleration at hand the look-ahead's braking envelope assumes (the drive
/// needs the rest to turn its acceleration around in time).
const ENVELOPE: f64 = 0.8;
/// A run longer than this many ticks keeps the analytic profile (a table costs memory).
const MAX_TICKS: usize = 60_000;
const TINY: f64 = 1e-12;
/// How far ahead (in time at the speed at hand) a drive makes sure it can brake under a
/// falling top speed.
const GUARD: f64 = 0.06;
/// How many times the drives run again, each time softer around where one was caught, before
/// the run keeps the analytic plan.
const SOFTENINGS: usize = 8;
/// The share of the speed where a drive was stuck with no jerk at hand that the caps around
/// it are lowered to (see [`Track::soften`]).
const STUCK: f64 = 0.9;

/// Derivatives, speed caps and the braking envelope at points along a run (or along it read
/// backwards).
#[derive(Clone)]
struct Track {
    count: usize,
    v: Pos,
    a: Pos,
    j: Pos,
    len: f64,
    s: Vec<f64>,
    d: Vec<[Pos; 3]>,
    /// The highest steady speed at each point: feed, tolerance, junction, and every axis
    /// within its speed and [`CRUISE`] of its acceleration and jerk.
    cap: Vec<f64>,
    /// The feed and junction caps alone (`cap` before the axes' steady speeds lower it).
    fed: Vec<f64>,
    /// `cap` lowered to what the machine can brake to at [`ENVELOPE`] of its deceleration.
    envelope: Vec<f64>,
    /// [`Track::rate_error`] of the cell from each point to the next.
    error: Vec<Pos>,
    /// The highest speed every axis allows at each point, with the rate error of either cell
    /// beside it.
    top: Vec<f64>,
    /// The last point [`Track::index`] found: a drive asks for the same or the next one
    /// tick after tick.
    hint: std::cell::Cell<usize>,
    /// The share of the deceleration at hand the envelope assumes at each point ([`ENVELOPE`],
    /// less where [`Track::soften`] lowered it).
    brake: Vec<f64>,
    /// The share of the jerk at hand a landing uses at each point ([`RAMP`], less where
    /// [`Track::soften`] lowered it).
    ramp: Vec<f64>,
    /// Where the last drive was caught (see [`Track::steer`]).
    trap: std::cell::Cell<Option<Trap>>,
}

/// Where a drive was caught, and how.
#[derive(Debug, Clone, Copy)]
struct Trap {
    s: f64,
    /// The speed there where no path jerk kept every axis within its jerk (3·v·a·q2 and v³·q3
    /// pulling two axes apart); `None` where the tick could not end within an axis's speed or
    /// acceleration.
    stuck: Option<f64>,
}

/// What a drive steers to.
#[derive(Debug, Clone, Copy)]
enum Steer {
    /// The highest speed allowed ahead.
    Ahead,
    /// Rest, as soon as it can.
    Halt,
    /// This speed with no acceleration, then stop driving; none if that lies past `until`.
    Settle { v: f64, until: f64 },
}

/// The shares of the speed where the drives cross that a run without a join is capped at
/// around the crossing, tried in turn (each lower one leaves the two landings more room).
const BELOW_CROSSING: [f64; 6] = [0.99, 0.97, 0.93, 0.85, 0.7, 0.5];
/// The most ticks a settling drive may take.
const SETTLE_TICKS: usize = 2000;
/// How much quicker than the two drives' lower speed a join may be (it is not below both
/// everywhere: a settling ramp may run above a braking drive for a few ticks).
const MARGIN_BEAT: f64 = 1.02;
/// How much slower than the analytic plan a run along a bending path may be planned this way
/// (see [`plan`]).
const BENDING_BEAT: f64 = 1.01;

/// A state of a drive and the jerk of its next tick.
#[derive(Debug, Clone, Copy)]
struct Tick {
    s: f64,
    v: f64,
    a: f64,
    j: f64,
    /// The tick's duration: [`DT`], or less for the one that lands on a steady speed.
    dt: f64,
}

impl Track {
    /// The run's track; `junctions[k]` caps the speed where segment k meets k + 1.
    fn new(segments: &[&Segment], junctions: &[f64], axes: &AxisLimits) -> Option<Track> {
        let mut t = Track {
            count: axes.count,
            v: axes.v,
            a: axes.a.map(|x| x * MARGIN),
            j: axes.j.map(|x| x * MARGIN),
            len: 0.0,
            s: Vec::new(),
            d: Vec::new(),
            cap: Vec::new(),
            fed: Vec::new(),
            envelope: Vec::new(),
            error: Vec::new(),
            top: Vec::new(),
            hint: std::cell::Cell::new(0),
            brake: Vec::new(),
            ramp: Vec::new(),
            trap: std::cell::Cell::new(None),
        };
        for (k, seg) in segments.iter().enumerate() {
            let grid = seg.derivatives(axes)?;
            let cells = grid.d.len() - 1;
            let feed = seg.speed_cap();
            for (p, d) in grid.d.iter().enumerate() {
                t.s.push(t.len + seg.len * grid.u[p]);
                t.d.push(*d);
                let mut cap = feed;
                if p == cells {
                    cap = cap.min(junctions.get(k).copied().unwrap_or(f64::INFINITY));
                }
                if p == 0 && k > 0 {
                    cap = cap.min(junctions[k - 1]);
                }
                t.cap.push(cap);
                t.fed.push(cap);
            }
            t.len += seg.len;
        }
        t.error = (0..t.s.len()).map(|k| t.rate_error(k)).collect();
        for k in 0..t.s.len() {
            let error = |cell: Option<usize>| cell.map_or([0.0; MAX_AXES], |c| t.error[c]);
            let (before, after) = (error(k.checked_sub(1)), error(Some(k)));
            let error: Pos = std::array::from_fn(|i| before[i].max(after[i]));
            t.cap[k] = t.cap[k].min(t.steady(&t.d[k], &error));
        }
        // A path too short to difference (or a rate that is not a number) keeps the analytic
        // plan.
        t.brake = vec![ENVELOPE; t.s.len()];
        t.ramp = vec![RAMP; t.s.len()];
        let finite = t.d.iter().all(|d| d.iter().all(|row| row.iter().all(|x| x.is_finite())));
        if !finite || t.cap.iter().any(|&c| c.is_nan() || c <= TINY) {
            return None;
        }
        t.fill_envelope();
        t.fill_top();
        Some(t)
    }

    /// The same track read from its end: s' = len − s, odd derivatives change sign.
    fn reversed(&self) -> Track {
        let flip = |d: &[Pos; 3]| [d[0].map(|x| -x), d[1], d[2].map(|x| -x)];
        let mut t = Track {
            count: self.count,
            v: self.v,
            a: self.a,
            j: self.j,
            len: self.len,
            s: self.s.iter().rev().map(|s| self.len - s).collect(),
            d: self.d.iter().rev().map(flip).collect(),
            cap: self.cap.iter().rev().copied().collect(),
            fed: self.fed.iter().rev().copied().collect(),
            envelope: Vec::new(),
            error: Vec::new(),
            top: Vec::new(),
            hint: std::cell::Cell::new(0),
            brake: self.brake.iter().rev().copied().collect(),
            ramp: self.ramp.iter().rev().copied().collect(),
            trap: std::cell::Cell::new(None),
        };
        t.error = (0..t.s.len()).map(|k| t.rate_error(k)).collect();
        t.fill_envelope();
        t.fill_top();
        t
    }

    /// The same track with its caps at most `v` from `from` to `to`.
    fn capped(&self, from: f64, to: f64, v: f64) -> Track {
        let mut t = self.clone();
        for (cap, s) in t.cap.iter_mut().zip(&self.s) {
            if (from..=to).contains(s) {
                *cap = cap.min(v);
            }
        }
        t.fill_envelope();
        t
    }

    fn fill_top(&mut self) {
        let last = self.s.len() - 1;
        self.top = (0..=last)
            .map(|k| {
                let d = &self.d[k];
                self.top_speed_at(d, k)
                    .min(self.top_speed_at(d, k.saturating_sub(1)))
                    .min(self.top_speed_at(d, (k + 1).min(last)))
            })
            .collect();
    }

    /// The highest jerk for this tick from `x` after which braking at `brake` (a negative
    /// jerk) keeps the speed below every point's top speed within [`GUARD`] ahead: a top speed
    /// that falls faster than the jerk lets the deceleration grow is met in time.
    fn brake_guard(&self, x: &Tick, brake: f64) -> f64 {
        let mut j = f64::INFINITY;
        let v = x.v.max(TINY);
        for k in self.index(x.s) + 1..self.s.len() {
            let t = (self.s[k] - x.s) / v;
            if t > GUARD {
                break;
            }
            if t <= DT {
                continue;
            }
            let tau = t - DT;
            j = j.min((STEER * self.top[k] - x.v - x.a * t - 0.5 * brake * tau * tau) / (0.5 * DT * DT + DT * tau));
        }
        j
    }

    /// How much more than its interpolated value an axis's rate by s can be in the cell from
    /// point `k` to the next: a function's distance from its chord is at most h²/8 times its
    /// second derivative, and the rate at a point, a difference over ±h, is off by up to h²/6
    /// times it (q3, taken 1.5 times the larger at the cell's ends).
    fn rate_error(&self, k: usize) -> Pos {
        let Some(&next) = self.s.get(k + 1) else { return [0.0; MAX_AXES] };
        let h = next - self.s[k];
        let share = 1.5 * (1.0 / 8.0 + 1.0 / 6.0) * h * h;
        std::array::from_fn(|i| share * self.d[k][2][i].abs().max(self.d[k + 1][2][i].abs()))
    }

    /// The highest steady speed the axes allow where their derivatives are `d` (the rates
    /// possibly `error` higher between points).
    fn steady(&self, d: &[Pos; 3], error: &Pos) -> f64 {
        let mut v = f64::INFINITY;
        for i in 0..self.count {
            let [q1, q2, q3] = [d[0][i].abs() + error[i], d[1][i].abs(), d[2][i].abs()];
            if q1 > TINY {
                v = v.min(STEER * self.v[i] / q1);
            }
            if q2 > TINY {
                v = v.min((CRUISE * self.a[i] / q2).sqrt());
            }
            if q3 > TINY {
                // ∛x only where it can be the lower (as `path::limits_with_share`).
                let x = CRUISE * self.j[i] / q3;
                if x < v * v * v * (1.0 + 1e-12) {
                    v = v.min(x.cbrt());
                }
            }
        }
        v
    }

    /// Backward from the end (with no speed required there: the other drive ends the run),
    /// the speed from which the machine can still brake to every later cap (at each point's
    /// `brake` share of the deceleration at hand).
    fn fill_envelope(&mut self) {
        let n = self.s.len();
        self.envelope = self.cap.clone();
        for k in (0..n - 1).rev() {
            let after = self.envelope[k + 1];
            let (lo, _) = self.accel_bounds(&self.d[k + 1], after, 1.0);
            let brake = (-lo).max(0.0) * self.brake[k + 1];
            let ds = self.s[k + 1] - self.s[k];
            self.envelope[k] = self.cap[k].min((after * after + 2.0 * brake * ds).sqrt());
        }
    }

    /// Halve the deceleration the envelope assumes around `trap`, where a drive (either way
    /// along the track: `backward`) was caught: over the distance the top speed there covers
    /// in the time the jerk needs to build the deceleration at hand, either side (the top
    /// speed may go on falling past it). The drives then start braking earlier for a top
    /// speed, or an acceleration bound, that falls faster than they can follow: the envelope
    /// assumes a deceleration at once, not one the jerk has to build.
    ///
    /// Caught `again` — at the same point, or inside the stretch where a landing was softened
    /// before — the drive was landing on a cap it overshot, and the envelope is not what
    /// failed: its landing's share of the jerk is lowered instead, by
    /// [`RAMP_SOFTER`], over three times the distance the top speed covers while the jerk turns
    /// the larger deceleration at hand (at rest or at the top speed) before it. A landing's
    /// jerk is the mean of the bound over the speeds it passes; where that bound is low when
    /// the landing starts and the drive falls behind its curve, the acceleration it keeps
    /// lowers the bound further on (3·v·a·q2), and the drive ran past the cap. (Without this a
    /// twentieth of random TCP blocks kept the analytic plan, hundreds of short samples each.)
    ///
    /// Where the drive was stuck with no jerk at all, the caps there are lowered to [`STUCK`]
    /// of its speed too, at the points of its cell and the cells beside it.
    ///
    /// Returns the stretch where landings were softened.
    fn soften(&mut self, trap: Trap, backward: bool, again: bool) -> Option<(f64, f64)> {
        let mut softened = None;
        let k = self.index(trap.s);
        let (lo, _) = self.accel_bounds(&self.d[k], self.top[k], 1.0);
        let (jerk, _) = self.jerk_bounds(&self.d[k], self.top[k], 0.0, 1.0);
        let span = self.top[k] * (2.0 * (-lo).max(0.0) / (-jerk).max(TINY)).max(0.1);
        let near = |s: f64| (s - trap.s).abs() <= span;
        if !again {
            for (share, s) in self.brake.iter_mut().zip(&self.s) {
                if near(*s) {
                    *share *= 0.5;
                }
            }
        } else if trap.stuck.is_none() {
            let (rest, _) = self.accel_bounds(&self.d[k], 0.0, 1.0);
            let landing = self.top[k] * rest.abs().max(lo.abs()) / (-jerk).max(TINY);
            let reach = 3.0 * landing.max(span);
            let stretch = if backward { (trap.s - span, trap.s + reach) } else { (trap.s - reach, trap.s + span) };
            for (share, s) in self.ramp.iter_mut().zip(&self.s) {
                if (stretch.0..=stretch.1).contains(s) {
                    *share *= RAMP_SOFTER;
                }
            }
            softened = Some(stretch);
        }
        // Stuck with no jerk at all: not slowly enough there, whatever the braking before —
        // at the points of the cell it was stuck in and of the cells beside it. (Over the
        // envelope's stretch, `near`, a drive stuck at 15 mm/s capped 8 mm of a 12 mm swing,
        // where the axes allowed 18, at 13.6: 570 samples short of issue 17's rule.)
        if let Some(v) = trap.stuck {
            for cap in &mut self.cap[k.saturating_sub(1)..=(k + 2).min(self.s.len() - 1)] {
                *cap = cap.min(STUCK * v);
            }
        }
        self.fill_envelope();
        softened
    }

    /// The point at or before `s` (the later of two at a junction).
    fn index(&self, s: f64) -> usize {
        let fits = |k: usize| self.s[k] <= s && self.s.get(k + 1).is_none_or(|&next| next > s);
        let hint = self.hint.get();
        let k = if hint < self.s.len() && fits(hint) {
            hint
        } else if hint + 1 < self.s.len() && fits(hint + 1) {
            hint + 1
        } else {
            self.s.partition_point(|&x| x <= s).saturating_sub(1)
        };
        self.hint.set(k);
        k
    }

    /// The derivatives at `s`, interpolated.
    fn at(&self, s: f64) -> [Pos; 3] {
        let k = self.index(s);
        let Some(&next) = self.s.get(k + 1) else { return self.d[k] };
        let span = next - self.s[k];
        if span <= TINY {
            return self.d[k];
        }
        let u = ((s - self.s[k]) / span).clamp(0.0, 1.0);
        let (p, q) = (&self.d[k], &self.d[k + 1]);
        let mut out = *p;
        for (o, row) in out.iter_mut().enumerate() {
            for (i, x) in row.iter_mut().enumerate().take(self.count) {
                *x += (q[o][i] - p[o][i]) * u;
            }
        }
        out
    }

    /// The interpolated envelope at `s`, and the lowest cap from `s` to `ahead`.
    fn target(&self, s: f64, ahead: f64) -> f64 {
        let last = self.s.len() - 1;
        let k = self.index(s);
        let far = (self.index(ahead) + 1).clamp(k, last);
        let mut target = self.envelope[far];
        for c in &self.cap[k..=far] {
            target = target.min(*c);
        }
        target
    }

    /// The path accelerations at which every axis stays within `share` of its (planning)
    /// acceleration at speed `v`.
    fn accel_bounds(&self, d: &[Pos; 3], v: f64, share: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for ((q1, q2), limit) in d[0].iter().zip(&d[1]).zip(&self.a).take(self.count) {
            tighten(&mut lo, &mut hi, *q1, q2 * v * v, limit * share);
        }
        (lo, hi)
    }

    /// The path jerks at which every axis stays within `share` of its (planning) jerk at speed
    /// `v`, acceleration `a`.
    fn jerk_bounds(&self, d: &[Pos; 3], v: f64, a: f64, share: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (((q1, q2), q3), limit) in d[0].iter().zip(&d[1]).zip(&d[2]).zip(&self.j).take(self.count) {
            tighten(&mut lo, &mut hi, *q1, 3.0 * q2 * v * a + q3 * v * v * v, limit * share);
        }
        (lo, hi)
    }

    /// The jerk a landing from `x` turns its acceleration to zero with, coming `up` to its
    /// speed (the acceleration falls) or down to it (it rises); `now` the jerk bounds at `x`:
    /// [`RAMP`] of the mean, over the speeds the landing passes, of the bound where it passes
    /// them (Simpson's rule on its start, middle speed and end, each at the point of the path
    /// it is at then). A drive that follows the landing curve of that jerk tick by tick turns
    /// at the share of the bound at every point (v' = a and a' = −J(v) give a² = 2∫J dv).
    /// (The mean of the start and end bounds, no more than the start's, left the binding axis
    /// at 84–89 % of its jerk in landings whose bound rises: the drive then follows a curve
    /// that rises too, and turns by less than it.)
    fn landing_jerk(&self, x: &Tick, (lo, hi): (f64, f64), up: bool, room: f64) -> f64 {
        let bound = |(lo, hi): (f64, f64)| if up { -lo } else { hi };
        let j0 = bound((lo, hi));
        let a0 = if up { x.a.max(0.0) } else { x.a.min(0.0) };
        let share = self.ramp[self.index(x.s)];
        if a0 == 0.0 || j0 <= TINY {
            return (share * j0).max(TINY);
        }
        // Where the landing passes its speeds: as a constant-jerk ramp at the bound now, up to
        // the target `room` away at most. (Past it, the bound at speeds the drive never
        // reaches raised the mean: landings that began at a bound lower than the mean ran
        // past the cap.)
        let t = (a0.abs() / j0).min(2.0 * room.max(0.0) / a0.abs()).max(TINY);
        let along = |u: f64| x.s + x.v * u + 0.5 * a0 * u * u - a0 * u * u * u / (6.0 * t);
        let dv = 0.5 * a0 * t;
        // The middle speed is passed where a² is half a0² (a² falls linearly in v).
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let mid = bound(self.jerk_bounds(&self.at(along(t * (1.0 - half))), x.v + 0.5 * dv, a0 * half, 1.0));
        let end = bound(self.jerk_bounds(&self.at(along(t)), x.v + dv, 0.0, 1.0));
        (share * (j0 + 4.0 * mid + end) / 6.0).max(TINY)
    }

    /// The highest speed at which every axis is within its speed where the derivatives are
    /// `d`, in the cell from point `k`.
    fn top_speed_at(&self, d: &[Pos; 3], k: usize) -> f64 {
        let error = &self.error[k];
        (0..self.count).map(|i| self.v[i] / (d[0][i].abs() + error[i]).max(TINY)).fold(f64::INFINITY, f64::min)
    }

    /// Every axis within its speed, and within `share` of the acceleration and jerk the plan
    /// keeps to, at state `x` with path jerk `j` ([`WHOLE`]: the final check's).
    fn within(&self, x: &PathState, j: f64, share: f64) -> bool {
        let d = self.at(x.s);
        let speed_ok = x.v.abs() <= self.top_speed_at(&d, self.index(x.s)) + 1e-9;
        let inside = |(lo, hi): (f64, f64), x: f64| x >= lo - 1e-9 && x <= hi + 1e-9;
        speed_ok && inside(self.accel_bounds(&d, x.v, share), x.a) && inside(self.jerk_bounds(&d, x.v, x.a, share), j)
    }

    /// From `start` at each tick the jerk that steers toward the highest speed allowed ahead
    /// (with `halt`, toward rest: the ticks then end where the machine stands), within every
    /// axis's limits; until the end of the track.
    fn drive(&self, start: Tick, halt: bool) -> Option<Vec<Tick>> {
        self.steer(start, if halt { Steer::Halt } else { Steer::Ahead })
    }

    /// From `start` (accelerating toward `v`) the ticks that bring the acceleration to zero at
    /// speed `v` with the jerk at hand, at `until` at the latest; the last is the settled state.
    fn settle(&self, start: Tick, v: f64, until: f64) -> Option<Vec<Tick>> {
        self.steer(start, Steer::Settle { v, until })
    }

    /// The ticks of a drive from `start` steering by `steer` (see [`Steer`]); `None` where it
    /// cannot keep to the limits, with [`Track::trap`] set where it was caught.
    fn steer(&self, start: Tick, steer: Steer) -> Option<Vec<Tick>> {
        let halt = matches!(steer, Steer::Halt);
        self.trap.set(None);
        let mut x = start;
        let mut out = Vec::new();
        while x.s < self.len {
            if out.len() >= MAX_TICKS {
                return None;
            }
            let d = self.at(x.s);
            let (j_lo, j_hi) = self.jerk_bounds(&d, x.v, x.a, 1.0);
            if j_lo.is_nan() || j_hi.is_nan() || j_lo > j_hi {
                if j_lo > j_hi {
                    self.trap.set(Some(Trap { s: x.s, stuck: Some(x.v) }));
                }
                return None;
            }
            // The jerk a ramp down can count on: what it has now and where it ends (at zero
            // acceleration, a little faster), the lower; how far ahead the drive looks for its
            // target takes it. (The lower of either direction's made the window far longer than
            // the landing where rising had the tighter bound: the drive aimed at caps beyond
            // where it lands, and as its acceleration changed, the window's end crossed points
            // and the target flipped between their caps.)
            let (end_lo, _) = self.jerk_bounds(&d, x.v + x.a.max(0.0).powi(2) / (2.0 * (-j_lo).max(TINY)), 0.0, 1.0);
            let turn = self.ramp[self.index(x.s)] * (-j_lo).min(-end_lo).max(TINY);
            let target = match steer {
                Steer::Halt => 0.0,
                Steer::Settle { v, .. } => v,
                Steer::Ahead => self.goal(&x, j_hi, turn),
            };
            // The acceleration after this tick from which a ramp at jerk `law` lands on the
            // target: below it, the highest such acceleration, x²/2law + x·DT/2 ≤ room; above
            // it, the lowest from which a ramp up ends at it, x²/2law − x·DT/2 ≤ −room.
            // (A drive may stand a hair above a cap that falls: the continuous curve there;
            // a halt lands on rest by the discrete one, which does not overshoot it.)
            let room = target - x.v - 0.5 * x.a * DT;
            // `law` is the jerk that landing turns the acceleration with: negative coming up
            // to the target, positive coming down to it (`landing_jerk`). (Both directions'
            // lower bound, as `turn`, held ramps down to 73 % of the jerk at hand where the
            // other direction's was the tighter.)
            let up = self.landing_jerk(&x, (j_lo, j_hi), true, if room >= 0.0 { room } else { f64::INFINITY });
            let law = if room >= 0.0 { up } else { self.landing_jerk(&x, (j_lo, j_hi), false, -room) };
            let disc = 0.25 * DT * DT + 2.0 * room / law;
            let wanted = if room < 0.0 && halt {
                law * (0.5 * DT - (0.25 * DT * DT - 2.0 * room / law).sqrt())
            } else if disc >= 0.0 {
                law * (disc.sqrt() - 0.5 * DT)
            } else {
                -(2.0 * law * (x.v - target).max(0.0)).sqrt()
            };
            // The acceleration the next tick may reach, where it will be.
            let ahead = x.s + x.v * DT;
            let next = self.at(ahead);
            let (a_lo, a_hi) = self.accel_bounds(&next, x.v + x.a * DT, 1.0);
            if a_lo.is_nan() || a_hi.is_nan() || a_lo > a_hi {
                // No acceleration keeps every axis within its limits there at this speed.
                return None;
            }
            let mut j = ((wanted - x.a) / DT).clamp((a_lo - x.a) / DT, (a_hi - x.a) / DT);
            // Never past an axis's speed at the next tick (the law above keeps to it but for
            // a path whose rates grow faster than it looked ahead).
            // (Its cell's rate error too, or the next one's: where the tick ends is known to
            // within a·DT²/2, and the bound steps at a cell's end.)
            let cell = self.index(ahead);
            let fastest =
                self.top_speed_at(&next, cell).min(self.top_speed_at(&next, (cell + 1).min(self.s.len() - 1)));
            // (It brakes with the jerk a landing on the target would: at 80 % of the jerk at
            // hand, as it was, it landed every drive coming up to an axis's top speed early.)
            let guard = self.brake_guard(&x, -up);
            j = j.min(2.0 * (fastest - x.v - x.a * DT) / (DT * DT)).min(guard);
            j = j.clamp(j_lo, j_hi);
            // The jerk's bounds move with the speed and acceleration over the tick: within them
            // where it ends too.
            // (The derivatives where the tick ends: those `ahead`, a·DT²/2 from it.)
            let (v_end, a_end) = (x.v + DT * (x.a + 0.5 * DT * j), x.a + DT * j);
            let (end_lo, end_hi) = self.jerk_bounds(&next, v_end, a_end, 1.0);
            if end_lo <= end_hi {
                j = j.clamp(end_lo.max(j_lo).min(j_hi), end_hi.min(j_hi).max(j_lo));
            }
            // Caught: no jerk at hand keeps the tick's end within an axis's speed or its whole
            // acceleration (the top speed or the bound falls faster than the drive can follow).
            // The run cannot pass the final check this way: stop here and say where.
            let (v_end, a_end) = (x.v + DT * (x.a + 0.5 * DT * j), x.a + DT * j);
            let (whole_lo, whole_hi) = self.accel_bounds(&next, v_end, WHOLE);
            if v_end > fastest * (1.0 + 1e-9) + 1e-9 || a_end > whole_hi + 1e-9 || a_end < whole_lo - 1e-9 {
                self.trap.set(Some(Trap { s: x.s, stuck: None }));
                return None;
            }
            let mut t = DT;
            // Landing on the steady speed within this tick: one ramp that ends exactly there
            // (the law above only nears it), and then holding it — unless a falling top speed
            // ahead needs the brakes now.
            let gap = target - x.v;
            if x.a.abs() <= 1e-9 * (1.0 + x.v) && gap.abs() <= 1e-9 * (1.0 + x.v) {
                if guard >= 0.0 {
                    (x.a, j) = (0.0, 0.0);
                }
            } else if x.a * gap > 0.0 && 2.0 * gap / x.a <= DT {
                // Toward the speed with the acceleration still pointing to it: the jerk that
                // ends both together (within the jerk at hand).
                let landing = -x.a * x.a / (2.0 * gap);
                if landing >= j_lo && landing <= j_hi {
                    (j, t) = (landing, 2.0 * gap / x.a);
                }
            }
            (x.j, x.dt) = (j, t);
            out.push(x);
            let landed = t < DT;
            x = Tick {
                s: x.s + t * (x.v + t * (0.5 * x.a + t * j / 6.0)),
                v: if landed { target } else { x.v + t * (x.a + 0.5 * t * j) },
                a: if landed { 0.0 } else { x.a + t * j },
                j: 0.0,
                dt: DT,
            };
            if x.v < -1e-9 {
                return None;
            }
            if let Steer::Settle { v, until } = steer {
                if x.s > until {
                    return None;
                }
                if landed || (x.a == 0.0 && (x.v - v).abs() <= 1e-9 * (1.0 + v)) {
                    out.push(x);
                    return Some(out);
                }
                if out.len() >= SETTLE_TICKS {
                    return None;
                }
            }
            x.v = x.v.max(0.0);
            if x.v <= TINY && x.a.abs() <= TINY && target <= TINY {
                // At rest: where a halt ends; a drive stalled on a cap of zero.
                if halt {
                    out.push(x);
                    return Some(out);
                }
                return None;
            }
        }
        if halt {
            return None;
        }
        out.push(x);
        Some(out)
    }

    /// The speed the drive steers to from `x` (with `j_hi` the highest jerk at hand and `turn`
    /// the jerk its ramps use): the lowest cap, and envelope, a ramp from the acceleration
    /// the next tick may reach would pass. Its length is taken as the distance covered keeping
    /// that acceleration for the ramp's time τ, v·τ + a·τ²/2 (the ramp covers v·τ + a·τ²/3).
    /// (Taken as at the ramp's end speed all along, v·τ + a·τ², the excess shrank with the
    /// acceleration while the drive landed, pulling the window's end back to a higher
    /// envelope: the target rose in steps and the jerk chattered between ticks.)
    fn goal(&self, x: &Tick, j_hi: f64, turn: f64) -> f64 {
        let most = (x.a + j_hi * DT).max(0.0);
        let tau = most / turn + 2.0 * DT;
        self.target(x.s, x.s + (x.v + 0.5 * most * tau) * tau)
    }

    /// [`Track::goal`] with the jerk at `x` (a ramp down's, as in the drive).
    fn goal_at(&self, x: &Tick) -> f64 {
        let (lo, hi) = self.jerk_bounds(&self.at(x.s), x.v, x.a, 1.0);
        self.goal(x, hi, self.ramp[self.index(x.s)] * (-lo).max(TINY))
    }

    /// The constant-jerk ramp from `x` that brings its acceleration to zero at speed `v`
    /// (`None` when none can within the limits): its jerk, duration and the state it ends in.
    fn ramp_to(&self, x: &Tick, v: f64) -> Option<(f64, f64, PathState)> {
        let start = PathState { s: x.s, v: x.v, a: x.a };
        if x.a.abs() <= TINY {
            return ((v - x.v).abs() <= 1e-9 * (1.0 + v)).then_some((0.0, 0.0, start));
        }
        let dv = v - x.v;
        if dv * x.a <= 0.0 {
            return None;
        }
        let j = -x.a * x.a / (2.0 * dv);
        let tau = -x.a / j;
        let end = PathState { s: x.s + tau * (x.v + tau * (0.5 * x.a + tau * j / 6.0)), v, a: 0.0 };
        let fits = (0..=4).all(|k| {
            let t = tau * k as f64 / 4.0;
            let p = PathState {
                s: x.s + t * (x.v + t * (0.5 * x.a + t * j / 6.0)),
                v: x.v + t * (x.a + 0.5 * t * j),
                a: x.a + t * j,
            };
            self.within(&p, j, 1.0)
        });
        fits.then_some((j, tau, end))
    }

    /// The ticks from `x` to a steady speed `v` (the last one steady, at `until` at the
    /// latest): a settling drive, or else one constant-jerk ramp.
    fn join_ramp(&self, x: &Tick, v: f64, until: f64) -> Option<Vec<Tick>> {
        if let Some(ticks) = self.settle(*x, v, until) {
            return Some(ticks);
        }
        let (j, dt, end) = self.ramp_to(x, v)?;
        Some(vec![Tick { j, dt, ..*x }, Tick { s: end.s, v: end.v, a: end.a, j: 0.0, dt: DT }])
    }

    /// The speed a ramp from `x` ends at with `share` of the jerk at hand.
    fn plateau(&self, x: &Tick, share: f64) -> f64 {
        let (lo, hi) = self.jerk_bounds(&self.at(x.s), x.v, x.a, 1.0);
        let turn = share * if x.a > 0.0 { -lo } else { hi };
        if turn <= TINY {
            return f64::INFINITY;
        }
        x.v + x.a * x.a.abs() / (2.0 * turn)
    }

    /// Every axis within its limits at speed `v` and no acceleration from `s0` to `s1`.
    fn cruise_fits(&self, s0: f64, s1: f64, v: f64) -> bool {
        let steady = |s: f64| self.within(&PathState { s, v, a: 0.0 }, 0.0, 1.0);
        let (k0, k1) = (self.index(s0), self.index(s1));
        steady(s0)
            && steady(s1)
            && self.s[k0 + 1..=k1.max(k0)].iter().all(|&s| steady(s))
            && v <= self.cap_between(k0, k1)
    }

    /// Whether some axis's rate by s changes along the track (a TCP swing; not a straight move
    /// in a tilted plane, whose analytic plan keeps to the axes' limits exactly).
    fn bends(&self) -> bool {
        self.d.iter().any(|d| d[1].iter().chain(&d[2]).any(|x| x.abs() > 1e-9))
    }

    fn cap_between(&self, k0: usize, k1: usize) -> f64 {
        self.cap[k0..=k1.min(self.cap.len() - 1)].iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// Narrow `[lo, hi]` to the x with |q1·x + rest| ≤ limit.
fn tighten(lo: &mut f64, hi: &mut f64, q1: f64, rest: f64, limit: f64) {
    if q1.abs() > TINY {
        let (a, b) = ((-limit - rest) / q1, (limit - rest) / q1);
        *lo = lo.max(a.min(b));
        *hi = hi.min(a.max(b));
    } else if rest.abs() > limit {
        *lo = f64::INFINITY;
        *hi = f64::NEG_INFINITY;
    }
}

/// The profile of a run of kinematic segments from speed `v_start` to `v_end` (both with zero
/// acceleration), `junctions[k]` the highest speed where segment k meets k + 1; `None` when a
/// segment is not kinematic, the plan cannot keep to the limits (see the module), or it takes
/// longer than `to_beat`, the analytic plan's time (along a bending path, 1 % longer).
pub fn plan(
    segments: &[&Segment],
    junctions: &[f64],
    (v_start, v_end): (f64, f64),
    axes: &AxisLimits,
    to_beat: f64,
) -> Option<Profile> {
    let forward = Track::new(segments, junctions, axes)?;
    // Along a bending path the analytic plan's limits are bounded over stretches, and where it
    // wins by a hair it leaves every axis below 90 % of its limits for a while (issue 17's
    // rule): the plan that keeps them at their limits is taken within 1 % of it.
    let to_beat = if forward.bends() { BENDING_BEAT * to_beat } else { to_beat };
    let drives = Drives::new(forward, (v_start, v_end))?;
    let profile = match drives.join(to_beat) {
        Joined::Profile(profile) => Some(*profile),
        Joined::Skipped => None,
        // Both drives still accelerating toward each other where they cross (each landing on
        // the same cap ahead, which neither reaches): no ramp lands below the crossing in
        // time. Capped a little below the speed there, they land on that cap and cruise, and
        // join on the cruise.
        Joined::None(crossing) => BELOW_CROSSING.iter().find_map(|&share| {
            let (from, to, v) = drives.below_crossing(crossing, share)?;
            match Drives::new(drives.forward.capped(from, to, v), (v_start, v_end))?.join(to_beat) {
                Joined::Profile(profile) => Some(*profile),
                _ => None,
            }
        }),
    };
    profile.filter(|p| p.duration() <= to_beat)
}

/// How a join of the two drives came out.
enum Joined {
    Profile(Box<Profile>),
    /// Not looked for: no join could beat the plan to beat.
    Skipped,
    /// None found back from the forward tick where the drives cross.
    None(usize),
}

/// A run's track, its reverse, and the drive along each from the run's end speeds.
struct Drives {
    forward: Track,
    backward: Track,
    f: Vec<Tick>,
    b: Vec<Tick>,
    v_end: f64,
}

impl Drives {
    /// The drives from the run's end speeds; where one is caught, both run again softer there
    /// (up to [`SOFTENINGS`] times; see [`Track::soften`]).
    fn new(mut forward: Track, (v_start, v_end): (f64, f64)) -> Option<Drives> {
        let rest = |v: f64| Tick { s: 0.0, v, a: 0.0, j: 0.0, dt: DT };
        // Where the last drive was caught (forward distance) and which way it ran, and where
        // landings were last softened and for which way.
        let mut last = None;
        let mut landed: Option<(bool, (f64, f64))> = None;
        for _ in 0..SOFTENINGS {
            let backward = forward.reversed();
            let caught = match backward.drive(rest(v_end), false) {
                None => backward.trap.get().map(|trap| (Trap { s: forward.len - trap.s, ..trap }, true)),
                Some(b) => match forward.drive(rest(v_start), false) {
                    Some(f) => return Some(Drives { forward, backward, f, b, v_end }),
                    None => forward.trap.get().map(|trap| (trap, false)),
                },
            };
            let (trap, backward) = caught?;
            // Caught again where the landings were softened: they were not softened enough.
            let inside = landed.is_some_and(|(way, (from, to))| way == backward && (from..=to).contains(&trap.s));
            if let Some(stretch) = forward.soften(trap, backward, inside || last == Some((trap.s, backward))) {
                landed = Some((backward, stretch));
            }
            last = Some((trap.s, backward));
        }
        None
    }

    /// The backward drive's speed at forward distance s.
    fn speed_back(&self, s: f64) -> f64 {
        let sigma = self.forward.len - s;
        let k = self.b.partition_point(|x| x.s <= sigma).saturating_sub(1);
        self.b[k].v
    }

    /// `share` of the speed at the forward tick `crossing`, and the stretch around it from the
    /// last tick of each drive from which a ramp at the jerk at hand still lands below that.
    fn below_crossing(&self, crossing: usize, share: f64) -> Option<(f64, f64, f64)> {
        let v = share * self.f[crossing].v;
        let len = self.forward.len;
        let first = self.f[..=crossing].iter().rposition(|x| self.forward.plateau(x, RAMP) < v)?;
        let sigma = len - self.f[crossing].s;
        let back = self.b.partition_point(|x| x.s <= sigma).min(self.b.len() - 1);
        let last = self.b[..=back].iter().rposition(|x| self.backward.plateau(x, RAMP) < v)?;
        let (from, to) = (self.f[first].s, len - self.b[last].s);
        (v > TINY && from < to).then_some((from, to, v))
    }

    /// The profile joining the drives (see the module).
    fn join(&self, to_beat: f64) -> Joined {
        let Drives { forward, backward, f, b, .. } = self;
        let speed_back = |s: f64| self.speed_back(s);
        let len = forward.len;
        let crossing = f.iter().position(|x| x.v > speed_back(x.s) * (1.0 + 1e-9) + 1e-12).unwrap_or(f.len() - 1);
        // No join is quicker than the two drives' lower speed all along: where that is no quicker
        // than the plan to beat, the joins are not looked for (they cost several drives each).
        // Over each forward tick the lower speed takes at least as long as either drive does
        // there (the backward drive's time read off its ticks by distance): a lower bound, so a
        // join that could win is never skipped. (Dividing each tick's length by the backward
        // speed at its start overestimated it where the backward drive nears rest: a long forward
        // tick over the last few slow backward ones — by 4–17 % on whole blocks.)
        let mut clock = 0.0;
        let b_time: Vec<f64> = b
            .iter()
            .map(|t| {
                let now = clock;
                clock += t.dt;
                now
            })
            .collect();
        let time_back = |sigma: f64| {
            let k = b.partition_point(|x| x.s <= sigma).saturating_sub(1);
            match b.get(k + 1) {
                Some(next) if next.s > b[k].s => {
                    b_time[k] + (b_time[k + 1] - b_time[k]) * ((sigma - b[k].s) / (next.s - b[k].s)).clamp(0.0, 1.0)
                }
                _ => b_time[k],
            }
        };
        let fastest: f64 = f.windows(2).map(|w| w[0].dt.max(time_back(len - w[0].s) - time_back(len - w[1].s))).sum();
        if fastest >= MARGIN_BEAT * to_beat {
            return Joined::Skipped;
        }
        // A join from forward tick k: its speed, the forward ramp, the backward tick and ramp, and
        // where the backward ramp starts (read forwards).
        let join_at = |k: usize| {
            let x = f[k];
            // Into a cruise at the speed the drive steers to, or at the end of a ramp at the jerk
            // at hand (or gentler where the limits tighten along it).
            let speeds =
                std::iter::once(forward.goal_at(&x)).chain(RAMPS.iter().map(|&share| forward.plateau(&x, share)));
            speeds.filter(|v| *v > TINY && v.is_finite()).find_map(|v| {
                let rf = forward.join_ramp(&x, v, len)?;
                let ef = *rf.last()?;
                // The backward tick nearest the crossing whose ramp can end at the same speed,
                // short of the forward ramp's end.
                let top = b.partition_point(|t| t.s < len - ef.s);
                // (A ramp ending at v at most the jerk at hand is needed first: a cheaper test.)
                let reaches = |m: &usize| {
                    let t = &b[*m];
                    let end = backward.plateau(t, 1.0);
                    if t.a > 0.0 {
                        t.v <= v && end <= v + 1e-9
                    } else {
                        t.a == 0.0 || end >= v - 1e-9
                    }
                };
                let (m, (rb, s_back)) = (0..top)
                    .rev()
                    .take(4000)
                    .filter(reaches)
                    .take(8)
                    .find_map(|m| Some((m, self.back_ramp(m, v, ef.s)?)))?;
                forward.cruise_fits(ef.s, s_back.max(ef.s), v).then_some((v, rf, m, rb, s_back))
            })
        };
        // The latest tick at or before the crossing with a join: back from the crossing in
        // doubling steps to one that has one, then halving the gap (each try runs drives).
        let (mut k, mut step, mut failed) = (crossing, 1, crossing + 1);
        let mut joined = loop {
            if let Some(join) = join_at(k) {
                break Some((k, join));
            }
            if k == 0 {
                break None;
            }
            failed = k;
            k = k.saturating_sub(step);
            step *= 2;
        };
        while let Some((found, _)) = joined {
            if failed - found <= 1 {
                break;
            }
            let mid = found + (failed - found) / 2;
            match join_at(mid) {
                Some(join) => joined = Some((mid, join)),
                None => failed = mid,
            }
        }
        let Some((k, join)) = joined else { return Joined::None(crossing) };
        // The join with its cruise closed, or as found where that one breaks a limit.
        let closed = self.closed(k, join.clone());
        match self.profile(k, closed).or_else(|| self.profile(k, join)) {
            Some(profile) => Joined::Profile(Box::new(profile)),
            None => Joined::None(crossing),
        }
    }

    /// The profile of the drives joined from forward tick `k` by `join`, if it keeps every
    /// axis within its limits.
    fn profile(&self, k: usize, (v, rf, m, rb, s_back): Join) -> Option<Profile> {
        let Drives { forward, f, b, v_end, .. } = self;
        let len = forward.len;
        let ef = rf[rf.len() - 1];
        let state = |t: &Tick| PathState { s: t.s, v: t.v, a: t.a };
        let mut phases: Vec<(f64, f64, PathState)> = Vec::with_capacity(k + m + rf.len() + rb.len() + 1);
        phases.extend(f[..k].iter().chain(&rf[..rf.len() - 1]).map(|t| (t.dt, t.j, state(t))));
        phases.push(((s_back - ef.s).max(0.0) / v, 0.0, PathState { s: ef.s, v, a: 0.0 }));
        // The backward drive read forwards: a state at σ is one at len − σ with its
        // acceleration's sign changed; the jerk keeps its sign.
        let fwd = |t: &Tick| PathState { s: len - t.s, v: t.v, a: -t.a };
        phases.extend((0..rb.len() - 1).rev().map(|i| (rb[i].dt, rb[i].j, fwd(&rb[i + 1]))));
        phases.extend((0..m).rev().map(|i| (b[i].dt, b[i].j, fwd(&b[i + 1]))));
        verified(forward, Profile::tabled(phases, len, *v_end))
    }
}

/// A join: its speed, the forward ramp, the backward tick it starts from, the backward ramp,
/// and where that ramp starts (read forwards).
type Join = (f64, Vec<Tick>, usize, Vec<Tick>, f64);

impl Drives {
    /// The ramp from backward tick `m` to a steady `v` that ends (read forwards) at or after
    /// `from`, where the forward ramp ends; and where it starts, read forwards.
    fn back_ramp(&self, m: usize, v: f64, from: f64) -> Option<(Vec<Tick>, f64)> {
        let len = self.forward.len;
        let rb = self.backward.join_ramp(&self.b[m], v, len - from + 1e-12)?;
        let s_back = len - rb.last()?.s;
        (s_back >= from - 1e-12).then_some((rb, s_back))
    }

    /// `join` from forward tick `k` with the cruise between its ramps closed: the highest
    /// speed (within 5 % above the join's) whose ramps from the same two ticks still meet,
    /// found by halving. The ramps land at zero acceleration on the join's speed and the
    /// cruise between them runs with no axis near a limit: the quickest profile turns
    /// through the join's speed instead. (Cruises of 1–24 ms were a third of the samples
    /// short of issue 17's rule.)
    fn closed(&self, k: usize, join: Join) -> Join {
        let Drives { forward, f, b, .. } = self;
        let len = forward.len;
        let m = join.2;
        let meet = |v: f64| -> Option<Join> {
            let rf = forward.join_ramp(&f[k], v, len)?;
            let ef = rf.last()?.s;
            let (rb, s_back) = self.back_ramp(m, v, ef)?;
            forward.cruise_fits(ef, s_back.max(ef), v).then_some((v, rf, m, rb, s_back))
        };
        let gap = |j: &Join| j.4 - j.1[j.1.len() - 1].s;
        if gap(&join) <= 1e-9 {
            return join;
        }
        // No faster than the feed or a junction's speed anywhere the ramps cover — but for a
        // junction the join already passes faster: a junction between two pieces of one block
        // (its speed the look-ahead's path limit, `path::kinematic_limits`), which the drives
        // and joins cross by the axes' own limits (`verified`).
        let (k0, k1) = (forward.index(f[k].s), forward.index(len - b[m].s));
        let span = forward.fed[(k0 + 1).min(k1)..=k1.max(k0)]
            .iter()
            .copied()
            .filter(|&cap| cap >= join.0)
            .fold(f64::INFINITY, f64::min);
        let (mut lo, mut hi) = (join.0, (join.0 * 1.05).min(span));
        let mut best = join;
        for _ in 0..12 {
            let mid = 0.5 * (lo + hi);
            match meet(mid) {
                Some(j) => {
                    lo = mid;
                    best = j;
                }
                None => hi = mid,
            }
        }
        best
    }
}

/// The quickest stop along `path` (its corner speeds `corners`) from speed `v` and acceleration
/// `a` within every axis's own limits (a feed hold during a run planned by [`plan`], which may
/// go faster than the path limits `Profile::stop` would use); its length is the stopping
/// distance. `None` when it cannot stop within `path`.
pub fn stop(path: &[&Segment], corners: &[f64], v: f64, a: f64, axes: &AxisLimits) -> Option<Profile> {
    let track = Track::new(path, corners, axes)?;
    let ticks = track.drive(Tick { s: 0.0, v, a, j: 0.0, dt: DT }, true)?;
    let (last, moving) = ticks.split_last()?;
    let phases = moving.iter().map(|t| (t.dt, t.j, PathState { s: t.s, v: t.v, a: t.a }));
    verified(&track, Profile::tabled(phases, last.s, 0.0))
}

/// The profile, if every one of its phases keeps every axis within [`WHOLE`] of its limits.
fn verified(track: &Track, profile: Profile) -> Option<Profile> {
    if !profile.is_continuous(1e-9) {
        return None;
    }
    // Each phase at its start and end; a steady one also at every point of the track inside
    // it (between points its axis rates are linear: the limits hold if they hold there);
    // another long one every tick.
    let ok = profile.tabled_phases().all(|(duration, j, x)| {
        let at = |t: f64| {
            let p = PathState {
                s: x.s + t * (x.v + t * (0.5 * x.a + t * j / 6.0)),
                v: x.v + t * (x.a + 0.5 * t * j),
                a: x.a + t * j,
            };
            track.within(&p, j, WHOLE)
        };
        if !(at(0.0) && at(duration)) {
            return false;
        }
        if j == 0.0 && x.a == 0.0 && x.v > 0.0 {
            let (k0, k1) = (track.index(x.s), track.index(x.s + x.v * duration));
            return track.s[k0 + 1..=k1.max(k0)].iter().all(|&s| at((s - x.s) / x.v));
        }
        (1..(duration / DT).ceil() as usize).all(|k| at(k as f64 * DT))
    });
    ok.then_some(profile)
}
