//! Jerk-limited speed profiles along a path parameter.
//!
//! A profile takes a segment of length `len` from speed `vs` to speed `ve`, never faster than
//! `limits.v`, with |acceleration| ≤ `limits.a` and |jerk| ≤ `limits.j`, and with zero
//! acceleration at both ends: consecutive segments then join with continuous speed and
//! acceleration. Each speed change is the classic S-curve (jerk up, constant acceleration,
//! jerk down — or only the two jerk phases for a small change); every phase has constant jerk,
//! so time, distance and speed are exact polynomials and the cycle time is analytic.

use arrayvec::ArrayVec;

/// The limits along the path: speed (units/s), acceleration (units/s²), jerk (units/s³).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    pub v: f64,
    pub a: f64,
    pub j: f64,
}

impl Limits {
    /// The lower of each limit: what two stretches of path run at together.
    pub fn min(self, other: Limits) -> Limits {
        Limits { v: self.v.min(other.v), a: self.a.min(other.a), j: self.j.min(other.j) }
    }
}

/// Time and distance to change speed between `v0` and `v1` (either way; the two are
/// symmetric) starting and ending with zero acceleration.
pub fn change(v0: f64, v1: f64, lim: &Limits) -> (f64, f64) {
    let dv = (v1 - v0).abs();
    let t = if dv * lim.j <= lim.a * lim.a { 2.0 * (dv / lim.j).sqrt() } else { dv / lim.a + lim.a / lim.j };
    (t, 0.5 * (v0 + v1) * t)
}

/// The highest speed, at most `cap`, that can be reached from (or brought down to) `v0` within
/// `len`: the distance of a speed change grows with the target speed, so it is found by
/// bisection.
pub fn reachable(v0: f64, len: f64, cap: f64, lim: &Limits) -> f64 {
    if cap <= v0 || change(v0, cap, lim).1 <= len {
        return cap;
    }
    bisect_to(v0, cap, len, lim, |v| change(v0, v, lim).1)
}

/// A time no motion over `len` from rest to rest (zero acceleration at both ends) within `lim`
/// can beat, for less than a bisection's cost: its speed at most `lim.v` (`len / v`), its
/// acceleration at most `lim.a` (half the time up, half down: 2·√(len/a)), its jerk at most
/// `lim.j` (the jerk's four equal phases, ±j: 4·∛(len/2j)). A planned profile takes at least
/// that, less its rounding (some 1e-16 of it), so a profile whose floor is no faster than one
/// already planned cannot be faster by 1e-9 of it (`motion::path`).
pub fn rest_to_rest_floor(len: f64, lim: &Limits) -> f64 {
    (len / lim.v).max(2.0 * (len / lim.a).sqrt()).max(4.0 * (len / (2.0 * lim.j)).cbrt())
}

/// [`bisect`] for `dist(x) <= len`, `dist` a distance of speed changes under `lim` that grows
/// with `x` (it fits at `lo`, not at `hi`): its very steps, bit for bit, with fewer evaluations
/// of `dist` — the bisections were a third of a 5-axis run's time. A few steps of regula falsi
/// find about where `dist` reaches `len`; two points either side of it whose distances clear
/// `len` by far more than their rounding ([`CLEAR`]) then answer for every probe beyond them
/// (`dist` growing, a probe below the lower fits as surely as it does; above the upper, it does
/// not). Only the probes between the two are evaluated.
fn bisect_to(lo: f64, hi: f64, len: f64, lim: &Limits, dist: impl Fn(f64) -> f64) -> f64 {
    let sane = |x: f64| x.is_finite() && x > 0.0;
    let (below, above) = if sane(len) && sane(lim.a) && sane(lim.j) {
        bracket(lo, hi, len, &dist)
    } else {
        (f64::NEG_INFINITY, f64::INFINITY)
    };
    bisect(lo, hi, |x| x <= below || (x < above && dist(x) <= len))
}

/// How far (a share of `len`) the distances at [`bracket`]'s points must clear it: `dist` is a
/// few sums, products, quotients and roots of the speeds and limits, each rounded by at most
/// half of 2.2e-16, so more than a hundred times its rounding (at most ≈ 1e-15 of it).
const CLEAR: f64 = 1e-13;

/// Two points in `[lo, hi]` between which `dist` reaches `len`: `dist` at the lower is at most
/// `len` less [`CLEAR`] of it, at the upper at least `len` and as much more (infinite ones where
/// that was not found).
fn bracket(lo: f64, hi: f64, len: f64, dist: &impl Fn(f64) -> f64) -> (f64, f64) {
    let none = (f64::NEG_INFINITY, f64::INFINITY);
    // Regula falsi, the Illinois way (the end that stays has its value halved).
    let (mut a, mut b) = (lo, hi);
    let (mut fa, mut fb) = (dist(a) - len, dist(b) - len);
    if !(fa <= 0.0 && fb > 0.0) {
        return none;
    }
    let (mut x, mut side) = (f64::NAN, 0);
    for _ in 0..16 {
        let next = b - fb * (b - a) / (fb - fa);
        if !(next > a && next < b) {
            break;
        }
        let step = (next - x).abs();
        x = next;
        let fx = dist(x) - len;
        if fx <= 0.0 {
            (a, fa) = (x, fx);
            if side < 0 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb) = (x, fx);
            if side > 0 {
                fa *= 0.5;
            }
            side = 1;
        }
        if step <= 1e-13 * x {
            break;
        }
    }
    if !x.is_finite() {
        return none;
    }
    // The points a little either side (`dist` grows by a share at least a quarter of x's);
    // the fewer probes lie between them, the fewer are evaluated.
    let (below, above) = (x * (1.0 - 3e-13), x * (1.0 + 3e-13));
    (
        if dist(below) <= len * (1.0 - CLEAR) { below } else { f64::NEG_INFINITY },
        if dist(above) >= len * (1.0 + CLEAR) { above } else { f64::INFINITY },
    )
}

/// The largest `x` in `[lo, hi]` with `fits(x)`, for `fits` true at `lo` and monotone.
fn bisect(mut lo: f64, mut hi: f64, fits: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// One constant-jerk phase with the state it starts from.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Phase {
    duration: f64,
    jerk: f64,
    s: f64,
    v: f64,
    a: f64,
}

/// Position, speed and acceleration along the path at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathState {
    pub s: f64,
    pub v: f64,
    pub a: f64,
}

impl Phase {
    fn at(&self, t: f64) -> PathState {
        let j = self.jerk;
        PathState {
            s: self.s + t * (self.v + t * (0.5 * self.a + t * j / 6.0)),
            v: self.v + t * (self.a + 0.5 * t * j),
            a: self.a + t * j,
        }
    }
}

/// A planned run: at most ten phases (an S-curve down to the limit when it enters too fast, two
/// S-curves and a cruise), or a table of many (a run along a kinematic path, `motion::optimal`).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    phases: ArrayVec<Phase, 10>,
    /// The phases of a tabled profile (then `phases` is empty), with the time each starts.
    table: Option<std::sync::Arc<Table>>,
    len: f64,
    duration: f64,
    /// Speed at the end (also when there is no phase at all).
    end_speed: f64,
}

/// Many constant-jerk phases and their start times (for a search by time).
#[derive(Debug, PartialEq)]
struct Table {
    phases: Vec<Phase>,
    starts: Vec<f64>,
}

impl Profile {
    /// A profile of the given constant-jerk phases, each `(duration, jerk, state at its start)`,
    /// covering `len` and ending at `end_speed` (the caller makes them continuous).
    pub fn tabled(phases: impl IntoIterator<Item = (f64, f64, PathState)>, len: f64, end_speed: f64) -> Profile {
        let (mut list, mut starts, mut t) = (Vec::new(), Vec::new(), 0.0);
        for (duration, jerk, at) in phases {
            if duration > 0.0 {
                starts.push(t);
                list.push(Phase { duration, jerk, s: at.s, v: at.v, a: at.a });
                t += duration;
            }
        }
        let table = Some(std::sync::Arc::new(Table { phases: list, starts }));
        Profile { phases: ArrayVec::new(), table, len, duration: t, end_speed }
    }

    /// From `vs` to `ve` over `len`; `vs` and `ve` must be reachable from each other within
    /// `len` (the planner guarantees it; otherwise the profile runs at the nearer speed).
    pub fn plan(vs: f64, ve: f64, len: f64, lim: &Limits) -> Profile {
        let mut p = Profile { phases: ArrayVec::new(), table: None, len: len.max(0.0), duration: 0.0, end_speed: vs };
        if len <= 0.0 {
            return p;
        }
        // The planner's passes keep every speed change within its length; one that is not
        // would run past the segment, where the axes stand while the speed goes on (a 0/0 of
        // unlimited acceleration, a non-linear rapid's time parameter, is not a change).
        debug_assert!(
            change(vs, ve, lim).1.is_nan() || change(vs, ve, lim).1 <= len * (1.0 + 1e-6) + 1e-9 || vs > lim.v.max(ve),
            "a speed change from {vs} to {ve} needs {} in a length of {len} ({lim:?})",
            change(vs, ve, lim).1
        );
        let mut state = PathState { s: 0.0, v: vs, a: 0.0 };
        // Entering faster than the segment allows (the override was just lowered): slow down
        // first, as far as the segment lets.
        let top = lim.v.max(ve);
        if vs > top && change(vs, top, lim).1 <= len {
            p.ramp(&mut state, top, lim);
        }
        let (vs, len) = (state.v, len - state.s);
        if vs <= 0.0 && lim.v <= 0.0 {
            // No speed allowed (a 0% override): the machine waits here until replanned.
            p.phases.push(Phase { duration: f64::INFINITY, jerk: 0.0, s: state.s, v: 0.0, a: 0.0 });
            p.duration = f64::INFINITY;
            return p;
        }
        let floor = vs.max(ve);
        let cap = lim.v.max(floor);
        let total = |vp: f64| change(vs, vp, lim).1 + change(vp, ve, lim).1;
        let peak = if total(cap) <= len { cap } else { bisect_to(floor, cap, len, lim, total) };
        p.ramp(&mut state, peak, lim);
        let cruise = len - total(peak);
        if cruise > 0.0 && peak > 0.0 {
            p.push(&mut state, cruise / peak, 0.0);
        }
        p.ramp(&mut state, ve, lim);
        p.end_speed = ve;
        p
    }

    fn push(&mut self, state: &mut PathState, duration: f64, jerk: f64) {
        if duration <= 0.0 {
            return;
        }
        let phase = Phase { duration, jerk, s: state.s, v: state.v, a: state.a };
        *state = phase.at(duration);
        // A ramp ends with zero acceleration; rounding leaves a trace of it.
        if jerk != 0.0 && state.a.abs() < 1e-9 * (1.0 + state.v) {
            state.a = 0.0;
        }
        self.phases.push(phase);
        self.duration += duration;
    }

    /// An S-curve from the current speed to `v1`.
    fn ramp(&mut self, state: &mut PathState, v1: f64, lim: &Limits) {
        let dv = v1 - state.v;
        let j = lim.j.copysign(dv);
        if dv.abs() * lim.j <= lim.a * lim.a {
            let t = (dv.abs() / lim.j).sqrt();
            self.push(state, t, j);
            self.push(state, t, -j);
        } else {
            let t = lim.a / lim.j;
            self.push(state, t, j);
            self.push(state, dv.abs() / lim.a - t, 0.0);
            self.push(state, t, -j);
        }
        state.v = v1;
    }

    /// From speed `v` and acceleration `a` to a steady speed: the acceleration jerked back to
    /// zero, then, if that is faster than `target`, an S-curve down to it (an override lowered
    /// while moving). Its length is the distance it needs.
    pub fn transition(v: f64, a: f64, target: f64, lim: &Limits) -> Profile {
        let mut p = Profile { phases: ArrayVec::new(), table: None, len: 0.0, duration: 0.0, end_speed: v };
        let mut state = PathState { s: 0.0, v, a };
        p.push(&mut state, a.abs() / lim.j, -lim.j.copysign(a));
        state.a = 0.0;
        if state.v > target {
            p.ramp(&mut state, target, lim);
        }
        p.end_speed = state.v;
        p.len = state.s.max(0.0);
        p
    }

    /// The quickest stop from speed `v` and acceleration `a` (a feed hold): jerk −J down to a
    /// deceleration `ap`, hold it, jerk +J back to zero, ending at rest. The speed lost is
    /// `(a² − 2ap²)/2J − ap·t₂ = −v`, so `ap = √(J·v + a²/2)` when that is within A, else A with
    /// a constant phase. Its length is the stopping distance.
    pub fn stop(v: f64, a: f64, lim: &Limits) -> Profile {
        Profile::stop_turning(v, a, lim, lim.j)
    }

    /// [`Profile::stop`] whose first phase, turning a positive acceleration `a` down, may use
    /// the higher jerk `first` (where the machine is, its own); the rest keeps `lim.j`. The
    /// speed lost is then v + a²/2J₁ = ap²·(1/2J₁ + 1/2J) + ap·t₂.
    pub fn stop_turning(v: f64, a: f64, lim: &Limits, first: f64) -> Profile {
        let mut p = Profile { phases: ArrayVec::new(), table: None, len: 0.0, duration: 0.0, end_speed: 0.0 };
        let mut j = lim.j;
        if a < 0.0 && v > 0.0 && a * a > 2.0 * j * v {
            // Already braking harder than this jerk can end without reversing (only when the
            // limits are lower than the ones the motion was planned with, or by rounding):
            // end the braking exactly at rest.
            j = a * a / (2.0 * v);
        }
        let j1 = if a > 0.0 { first.max(j) } else { j };
        let need = v + a * a / (2.0 * j);
        let (mut ap, mut hold) = if j1 == j {
            let ideal = (j * v + 0.5 * a * a).max(0.0).sqrt();
            if ideal <= lim.a {
                (ideal, 0.0)
            } else {
                (lim.a, (need - lim.a * lim.a / j) / lim.a)
            }
        } else {
            let (gain, k) = (v + a * a / (2.0 * j1), 0.5 / j1 + 0.5 / j);
            let ideal = (gain / k).max(0.0).sqrt();
            if ideal <= lim.a {
                (ideal, 0.0)
            } else {
                (lim.a, ((gain - lim.a * lim.a * k) / lim.a).max(0.0))
            }
        };
        if -a > ap {
            // Braking already harder than that (a run planned with other limits): hold the
            // deceleration it has, then end it.
            ap = -a;
            hold = ((need - ap * ap / j) / ap).max(0.0);
        }
        let mut state = PathState { s: 0.0, v, a };
        p.push(&mut state, (a + ap) / j1, -j1);
        p.push(&mut state, hold, 0.0);
        p.push(&mut state, ap / j, j);
        // Rounding at a standstill must not give a stop that runs backwards.
        p.len = state.s.max(0.0);
        p
    }

    /// From speed `v` and acceleration `a` to rest exactly `len` further on (single block
    /// switched on under way: the machine stops at a block end, not wherever its quickest stop
    /// ends): down (or up) to a steady speed, a cruise at it, an S-curve to rest. The steady
    /// speed is the highest, at most `lim.v`, from which that fits in `len`. `None` where the
    /// machine cannot stop within `len` ([`Profile::stop`] is longer), or is braking harder
    /// than `lim.j` can end without reversing.
    pub fn stop_at(v: f64, a: f64, len: f64, lim: &Limits) -> Option<Profile> {
        if (a < 0.0 && a * a > 2.0 * lim.j * v) || Profile::stop(v, a, lim).len() > len {
            return None;
        }
        let start = PathState { s: 0.0, v, a };
        let settled = |vc: f64| {
            let mut p = Profile { phases: ArrayVec::new(), table: None, len: 0.0, duration: 0.0, end_speed: vc };
            let mut state = start;
            p.settle(&mut state, vc, lim);
            (p, state)
        };
        let dist = |vc: f64| settled(vc).1.s + change(vc, 0.0, lim).1;
        // Jerking the acceleration to zero at once gives this speed: the top never lies below it.
        let top = lim.v.max(v + a * a.abs() / (2.0 * lim.j));
        let vc = if dist(top) <= len { top } else { bisect(0.0, top, |x| dist(x) <= len) };
        let (mut p, mut state) = settled(vc);
        let cruise = len - dist(vc);
        if cruise > 0.0 && vc > 0.0 {
            p.push(&mut state, cruise / vc, 0.0);
        }
        p.ramp(&mut state, 0.0, lim);
        (p.end_speed, p.len) = (0.0, len);
        Some(p)
    }

    /// From the state's speed and acceleration to steady speed `vc`, as quickly as `lim`
    /// allows: the acceleration jerked toward the change (to at most A, held there), then back
    /// to zero. The side is the change's from the speed the acceleration's end alone gives
    /// (v + a·|a|/2J); the speed gained that way is (2p² − a²)/2J + p·t, p the peak.
    fn settle(&mut self, state: &mut PathState, vc: f64, lim: &Limits) {
        let j = lim.j;
        let side = if vc >= state.v + state.a * state.a.abs() / (2.0 * j) { 1.0 } else { -1.0 };
        let (gain, a0) = (side * (vc - state.v), side * state.a);
        let mut peak = (j * gain + 0.5 * a0 * a0).max(0.0).sqrt();
        let mut hold = 0.0;
        if peak > lim.a {
            peak = lim.a.max(a0);
            hold = ((gain - (2.0 * peak * peak - a0 * a0) / (2.0 * j)) / peak).max(0.0);
        }
        self.push(state, (peak - a0) / j, side * j);
        self.push(state, hold, 0.0);
        self.push(state, peak / j, -side * j);
        (state.v, state.a) = (vc, 0.0);
    }

    /// The distance the profile covers.
    pub fn len(&self) -> f64 {
        self.len
    }

    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The state `t` seconds into the segment (clamped to the segment).
    pub fn at(&self, t: f64) -> PathState {
        if let Some(table) = &self.table {
            let t = t.max(0.0);
            if t < self.duration {
                let k = table.starts.partition_point(|&start| start <= t).saturating_sub(1);
                let mut state = table.phases[k].at(t - table.starts[k]);
                state.s = state.s.clamp(0.0, self.len);
                return state;
            }
            return PathState { s: self.len, v: self.end_speed, a: 0.0 };
        }
        let mut rest = t.max(0.0);
        for phase in &self.phases {
            if rest <= phase.duration {
                let mut state = phase.at(rest);
                state.s = state.s.clamp(0.0, self.len);
                return state;
            }
            rest -= phase.duration;
        }
        PathState { s: self.len, v: self.end_speed, a: 0.0 }
    }

    /// The phases of a tabled profile (none for another): duration, jerk, state at the start.
    pub fn tabled_phases(&self) -> impl Iterator<Item = (f64, f64, PathState)> + '_ {
        let phases = self.table.as_ref().map_or(&[][..], |t| &t.phases[..]);
        phases.iter().map(|p| (p.duration, p.jerk, PathState { s: p.s, v: p.v, a: p.a }))
    }

    /// The phases from `t` seconds in to the end, each `(duration, jerk, state at its start)`,
    /// the first cut at `t`, positions measured from where the profile is at `t`.
    pub fn phases_after(&self, t: f64) -> Vec<(f64, f64, PathState)> {
        let phases: &[Phase] = match &self.table {
            Some(table) => &table.phases,
            None => &self.phases,
        };
        let origin = self.at(t).s;
        let (mut out, mut start) = (Vec::new(), 0.0);
        for p in phases {
            let end = start + p.duration;
            if end > t {
                let from = (t - start).max(0.0);
                let x = p.at(from);
                out.push((p.duration - from, p.jerk, PathState { s: x.s - origin, ..x }));
            }
            start = end;
        }
        out
    }

    /// Whether the profile is a table of phases (planned against the axes at every point).
    pub fn is_tabled(&self) -> bool {
        self.table.is_some()
    }

    /// For a tabled profile: whether each phase starts where the one before ends (position,
    /// speed and acceleration within `tol` relative), and the last at `len` with its end speed.
    pub fn is_continuous(&self, tol: f64) -> bool {
        let Some(table) = &self.table else { return true };
        let close = |x: f64, y: f64| (x - y).abs() <= tol * (1.0 + x.abs().max(y.abs()));
        let ends = table.phases.iter().map(|p| p.at(p.duration));
        let starts = table.phases.iter().skip(1).map(|p| PathState { s: p.s, v: p.v, a: p.a });
        let last = PathState { s: self.len, v: self.end_speed, a: 0.0 };
        ends.zip(starts.chain(std::iter::once(last)))
            .all(|(e, s)| close(e.s, s.s) && close(e.v, s.v) && close(e.a, s.a))
    }

    /// The jerk `t` seconds into the profile (zero outside it).
    pub fn jerk_at(&self, t: f64) -> f64 {
        if t < 0.0 || t >= self.duration {
            return 0.0;
        }
        let (phases, starts): (&[Phase], Option<&[f64]>) = match &self.table {
            Some(table) => (&table.phases, Some(&table.starts)),
            None => (&self.phases, None),
        };
        let k = match starts {
            Some(starts) => starts.partition_point(|&start| start <= t).saturating_sub(1),
            None => {
                let mut rest = t;
                let mut k = 0;
                while k + 1 < phases.len() && rest > phases[k].duration {
                    rest -= phases[k].duration;
                    k += 1;
                }
                k
            }
        };
        phases.get(k).map_or(0.0, |p| p.jerk)
    }

    /// The speed the profile ends at.
    pub fn end_speed(&self) -> f64 {
        self.end_speed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const LIM: Limits = Limits { v: 100.0, a: 1000.0, j: 20000.0 };

    #[test]
    fn a_stop_far_ahead_goes_up_to_the_limit_first() {
        // From 50 to 100 (Δv·J = A²: two jerk phases, 2·√(50/J) = 0.1 s over 7.5), 100 down to
        // rest (v/A + A/J = 0.15 s over 7.5), and 985 at 100 between: 10.1 s.
        let p = Profile::stop_at(50.0, 0.0, 1000.0, &LIM).unwrap();
        assert!((p.duration() - 10.1).abs() < 1e-9, "{}", p.duration());
        assert_eq!((p.len(), p.end_speed()), (1000.0, 0.0));
    }

    #[test]
    fn rest_to_rest_time_is_analytic() {
        // Long enough to cruise: accelerating takes v/a + a/j over (v/2)(v/a + a/j).
        let p = Profile::plan(0.0, 0.0, 500.0, &LIM);
        let ramp = 100.0 / 1000.0 + 1000.0 / 20000.0;
        assert!((p.duration() - (500.0 / 100.0 + ramp)).abs() < 1e-12, "{}", p.duration());
        let end = p.at(p.duration());
        assert_eq!((end.s, end.v), (500.0, 0.0));
        // Short: a pure jerk S-curve (dv·j ≤ a²) to a peak and back; distance 2·vp·√(vp/j).
        let p = Profile::plan(0.0, 0.0, 1.0, &LIM);
        let vp = (0.5f64.powi(2) * 20000.0).powf(1.0 / 3.0);
        assert!((p.duration() - 4.0 * (vp / 20000.0).sqrt()).abs() < 1e-9, "{}", p.duration());
    }

    #[test]
    fn change_matches_the_profile() {
        let (t, d) = change(10.0, 90.0, &LIM);
        let p = Profile::plan(10.0, 90.0, d, &LIM);
        assert!((p.duration() - t).abs() < 1e-9 && (p.at(t).v - 90.0).abs() < 1e-6);
    }

    proptest! {
        #[test]
        fn the_bracketed_bisection_takes_the_plain_ones_steps(
            v in 1.0..100.0f64, a in 0.0..4.0f64, j in 0.0..6.0f64, f0 in 0.0..1.0f64, f1 in 0.0..1.0f64, l in -5.0..3.0f64,
        ) {
            // Limits over decades, speeds from rest to the limit, lengths from 10 nm to 1 m.
            let lim = Limits { v, a: 10f64.powf(a), j: 10f64.powf(j) };
            let (vs, ve, len) = (v * f0 * f0, v * f1, 10f64.powf(l));
            let one = |x: f64| change(vs, x, &lim).1;
            if one(v) > len {
                let plain = bisect(vs, v, |x| one(x) <= len);
                prop_assert_eq!(plain.to_bits(), bisect_to(vs, v, len, &lim, one).to_bits());
            }
            let floor = vs.max(ve);
            let two = |x: f64| change(vs, x, &lim).1 + change(x, ve, &lim).1;
            if two(floor) <= len && two(v) > len {
                let plain = bisect(floor, v, |x| two(x) <= len);
                prop_assert_eq!(plain.to_bits(), bisect_to(floor, v, len, &lim, two).to_bits());
            }
        }

        #[test]
        fn no_rest_to_rest_profile_beats_its_floor(v in -1.0..3.0f64, a in 0.0..4.0f64, j in 0.0..6.0f64, l in -5.0..3.0f64) {
            let lim = Limits { v: 10f64.powf(v), a: 10f64.powf(a), j: 10f64.powf(j) };
            let len = 10f64.powf(l);
            let planned = Profile::plan(0.0, 0.0, len, &lim).duration();
            prop_assert!(rest_to_rest_floor(len, &lim) <= planned * (1.0 + 1e-14), "{planned}");
        }

        #[test]
        fn a_stop_at_a_distance_ends_there_at_rest_within_limits(
            vs in 0.0..100.0f64, ve in 0.0..100.0f64, f in 0.0..1.0f64, more in 0.0..50.0f64,
        ) {
            // Any instant of a planned profile: stop `more` beyond its quickest stop, exactly.
            let p = Profile::plan(vs, ve, change(vs, ve, &LIM).1 + 10.0, &LIM);
            let at = p.at(p.duration() * f);
            let least = Profile::stop(at.v, at.a, &LIM).len();
            prop_assert!(least < 1e-9 || Profile::stop_at(at.v, at.a, least * 0.999, &LIM).is_none());
            let len = least + more;
            let stop = Profile::stop_at(at.v, at.a, len, &LIM).expect("far enough");
            prop_assert!(stop.phases.iter().all(|ph| ph.jerk.abs() <= LIM.j * (1.0 + 1e-12)));
            let mut last = stop.at(0.0);
            prop_assert!((last.v - at.v).abs() < 1e-9 && (last.a - at.a).abs() < 1e-9);
            for i in 1..=500 {
                let s = stop.at(stop.duration() * i as f64 / 500.0);
                prop_assert!(s.v >= -1e-9 && s.v <= LIM.v.max(at.v) + 1e-9 && s.a.abs() <= LIM.a + 1e-6, "{s:?}");
                prop_assert!(s.s >= last.s - 1e-12);
                last = s;
            }
            let end = stop.phases.last().map_or(PathState { s: 0.0, v: at.v, a: at.a }, |ph| ph.at(ph.duration));
            prop_assert!((end.s - len).abs() < 1e-6 * (1.0 + len) && end.v.abs() < 1e-6 && end.a.abs() < 1e-6, "{end:?} for {len}");
        }

        #[test]
        fn a_stop_from_anywhere_ends_at_rest_within_limits(vs in 0.0..100.0f64, ve in 0.0..100.0f64, f in 0.0..1.0f64) {
            // Any instant of a planned profile: stop from its speed and acceleration.
            let len = change(vs, ve, &LIM).1 + 10.0;
            let p = Profile::plan(vs, ve, len, &LIM);
            let at = p.at(p.duration() * f);
            let stop = Profile::stop(at.v, at.a, &LIM);
            let n = 500;
            for i in 0..=n {
                let s = stop.at(stop.duration() * i as f64 / n as f64);
                prop_assert!(s.v >= -1e-9 && s.a.abs() <= LIM.a + 1e-6, "{s:?}");
            }
            let end = stop.at(stop.duration());
            prop_assert!(end.v.abs() < 1e-6 && stop.phases.last().is_none_or(|ph| ph.at(ph.duration).a.abs() < 1e-6));
        }

        #[test]
        fn profiles_respect_limits_and_reach_the_end(
            vs in 0.0..100.0f64, ve in 0.0..100.0f64, len in 0.001..300.0f64,
        ) {
            // Speeds the planner would allow: each reachable from the other within len.
            let ve = ve.min(reachable(vs, len, 100.0, &LIM));
            let vs = vs.min(reachable(ve, len, 100.0, &LIM));
            let p = Profile::plan(vs, ve, len, &LIM);
            let n = 2000;
            let mut last = p.at(0.0);
            prop_assert!((last.v - vs).abs() < 1e-9);
            for i in 1..=n {
                let s = p.at(p.duration() * i as f64 / n as f64);
                prop_assert!(s.v <= LIM.v + 1e-9 && s.v >= -1e-9, "speed {}", s.v);
                prop_assert!(s.a.abs() <= LIM.a + 1e-6, "acceleration {}", s.a);
                prop_assert!(s.s >= last.s - 1e-12, "moves forward");
                last = s;
            }
            prop_assert!((last.s - len).abs() < 1e-6 * (1.0 + len), "ends at {} of {}", last.s, len);
            prop_assert!((last.v - ve).abs() < 1e-6, "end speed {} for {}", last.v, ve);
        }
    }
}
