//! Look-ahead: the speed at every junction between segments, so that the machine can always
//! stop by the end of what it has read, never exceeds a segment's limits, and slows down at
//! corners only as much as each axis's allowed speed step requires.
//!
//! Segments are queued as the interpreter produces them and grouped into *runs*: consecutive
//! segments with the same speed limit, similar acceleration and jerk limits and no binding
//! corner between them. A run gets one jerk-limited profile over its whole length (zero
//! acceleration only at its ends), so that a program of many short segments accelerates as
//! one smooth move instead of pulsing at every block. Consecutive kinematic segments share a
//! run unless a sharp corner (to under half the speed) parts them; such a run (of at most
//! `OPTIMAL_SEGMENTS`, all its junctions smooth) is planned against each axis's own limits at every
//! point (`motion::optimal`) when that is quicker than its pieces' runs of similar path limits
//! (speed limits within 10 %: `shares_part`), which it is released as otherwise.
//!
//! A run is released only when at least [`Planner::lookahead`] segments follow it (or the
//! queue ends in a stop: a non-motion command, an exact stop, the program end): its speeds are
//! then final, because they are planned as if the machine had to stop at the end of the queue.
//! Planning runs over the whole queue (a backward pass from the stop, then a forward pass from
//! the current speed) once per [`Planner::batch`] segments queued beyond the look-ahead (an
//! eighth of it), so that the queue holds at most the look-ahead and one batch: a controller's
//! memory is mostly this queue (issue 18, `docs/performance.md`). Runs are grouped from the end
//! of the last released one, as they always were, so a run is never cut shorter by planning
//! more often; a run not yet followed by a look-ahead's worth waits for the next batch (the
//! plannings before the batch that can release it are skipped: they would change nothing). A
//! released run's segments stay at the front of the queue until it is popped (its profile is
//! made then), so the planner never holds a segment twice.

use super::path::{AxisLimits, Segment};
use super::profile::{reachable, Limits, Profile};
use crate::canon::Pos;
use std::collections::VecDeque;

/// A run of segments with its planned profile, ready to execute.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    pub segments: Vec<Segment>,
    pub profile: Profile,
}

/// Where the machine is at one instant of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub machine: Pos,
    pub work: Pos,
    /// Tool tip speed, mm/min.
    pub feed: f64,
    pub line: u32,
    pub n: Option<u32>,
    /// Distance along the run.
    pub s: f64,
}

/// The segment a run's samples are in, remembered between samples taken in time order.
#[derive(Debug, Clone, Copy, Default)]
pub struct Cursor {
    k: usize,
    start: f64,
}

impl Cursor {
    /// The index in the run of the segment the last point was on.
    pub fn index(&self) -> usize {
        self.k
    }

    /// The run's distance at that segment's start.
    pub fn start(&self) -> f64 {
        self.start
    }
}

impl Planned {
    /// The point `t` seconds into the run (`cursor` starts at default and only moves forward,
    /// so `t` must not decrease between calls with the same cursor).
    pub fn point(&self, t: f64, cursor: &mut Cursor) -> Point {
        let state = self.profile.at(t);
        let segments = &self.segments;
        while cursor.k + 1 < segments.len() && state.s > cursor.start + segments[cursor.k].len {
            cursor.start += segments[cursor.k].len;
            cursor.k += 1;
        }
        let seg = &segments[cursor.k];
        let (machine, work) = seg.at(state.s - cursor.start);
        let feed = seg.tip_speed(state.s - cursor.start, state.v) * 60.0;
        Point { machine, work, feed, line: seg.line, n: seg.n, s: state.s }
    }

    /// The path not yet covered at distance `s`: the rest of the segment holding it and every
    /// later one.
    pub fn rest(&self, s: f64) -> Vec<Segment> {
        let mut start = 0.0;
        let mut out = Vec::new();
        for seg in &self.segments {
            let end = start + seg.len;
            if end > s + 1e-12 {
                out.push(if s > start { seg.tail(s - start) } else { seg.clone() });
            }
            start = end;
        }
        out
    }
}

struct Queued {
    segment: Segment,
    /// Highest speed at the end of this segment (the junction with the next one).
    junction: f64,
    /// Whether the path goes on into the next segment without a corner or a change of
    /// curvature (no axis's speed or acceleration steps there).
    smooth: bool,
}

/// Consecutive queued segments planned as one move.
struct Run {
    end: usize,
    len: f64,
    limits: Limits,
    /// Every segment a kinematic path whose speed is planned against the axes' own limits.
    kinematic: bool,
    /// A run that goes on through a junction that is not smooth (`Queued::smooth`):
    /// `motion::optimal` sees the axes' bending inside segments, not the corners between them
    /// (their 3·v·a·q2 jerk: a wave under G43.4 in 0.1 mm blocks ran X at 1.03 times its jerk),
    /// so such a run keeps the analytic plan.
    cornered: bool,
    /// Highest speed at its end, then the planned one.
    cap: f64,
    v_end: f64,
}

/// The highest block look-ahead limit a segment carries (Haas G103 P15).
const MAX_BLOCK_LIMIT: usize = 15;

/// The most segments of a kinematic run planned against the axes at every point
/// (`motion::optimal`): a block's pieces (at most 16) and a few short blocks.
const OPTIMAL_SEGMENTS: usize = 48;

/// A run whose speeds are final, waiting at the front of the queue: its segments stay there
/// until it is popped (a released run is not a second copy of its segments).
struct Released {
    count: usize,
    v_start: f64,
    v_end: f64,
    len: f64,
    limits: Limits,
    /// Its profile when planned at release (a kinematic run, `motion::optimal`).
    profile: Option<Box<Profile>>,
}

pub struct Planner {
    /// Every segment not yet popped: those of the released runs first, in order.
    queue: VecDeque<Queued>,
    ready: VecDeque<Released>,
    /// Segments the last planning left unreleased: the next one waits for a batch more.
    left: usize,
    /// The queue length a planning needs to release anything (0: unknown): the first run's end
    /// and a look-ahead after it, where the last planning released nothing.
    first_release: usize,
    /// Speed at the end of the last released run.
    v_now: f64,
    pub lookahead: usize,
    /// Highest speed step each axis may take at a corner, units/s (FANUC No.1783), and
    /// highest acceleration step where the curvature changes, units/s².
    speed_step: Pos,
    accel_step: Pos,
    /// The machine's axis limits: a run of kinematic segments is planned against them at
    /// every point (`motion::optimal`); without them, with its run's path limits.
    axes: Option<AxisLimits>,
}

impl Planner {
    pub fn new(lookahead: usize, speed_step: Pos, accel_step: Pos) -> Planner {
        let lookahead = lookahead.max(1);
        Planner {
            queue: VecDeque::new(),
            ready: VecDeque::new(),
            left: 0,
            first_release: 0,
            v_now: 0.0,
            lookahead,
            speed_step,
            accel_step,
            axes: None,
        }
    }

    /// An empty planner with the same look-ahead, steps and axis limits.
    pub fn fresh(&self) -> Planner {
        Planner { axes: self.axes.clone(), ..Planner::new(self.lookahead, self.speed_step, self.accel_step) }
    }

    /// The planner, planning runs of kinematic segments against the axes' own limits.
    pub fn with_axes(self, axes: AxisLimits) -> Planner {
        Planner { axes: Some(axes), ..self }
    }

    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// Segments queued beyond the look-ahead before the queue is planned again.
    pub fn batch(&self) -> usize {
        (self.lookahead / 8).max(1)
    }

    /// Queue a segment (zero-length segments are dropped: they take no time); a kinematic
    /// path whose limits change along the way is queued as its pieces (`Segment::split`).
    pub fn push(&mut self, segment: Segment) {
        for piece in segment.split() {
            self.push_one(piece);
        }
    }

    fn push_one(&mut self, segment: Segment) {
        if segment.len <= 0.0 {
            return;
        }
        // Grown by doubling up to what running a program holds (the look-ahead and a batch),
        // exactly to that, then by a split block's pieces only when one comes: doubling past it
        // would reserve room for hundreds of segments never queued.
        let (len, held) = (self.queue.len(), self.lookahead + self.batch());
        if len == self.queue.capacity() && len < held + super::path::MAX_PIECES {
            let to = if len < held { (2 * len).clamp(4, held) } else { held + super::path::MAX_PIECES };
            self.queue.reserve_exact(to - len);
        }
        if let Some(last) = self.queue.back_mut() {
            let corner = if last.segment.stop_after || segment.rapid {
                0.0
            } else {
                corner_speed(&last.segment, &segment, &self.speed_step, &self.accel_step)
            };
            last.junction = last.segment.limits.v.min(segment.limits.v).min(corner);
            last.smooth = corner == f64::INFINITY;
        }
        self.queue.push_back(Queued { segment, junction: 0.0, smooth: false });
        self.limit_to_blocks();
    }

    /// Haas G103 P<n>: the control reads only n blocks ahead, so at the end of a block read
    /// under it the machine must be able to stop within the n blocks that follow, whatever
    /// comes after them. When the newest segment completes a block, each earlier block end
    /// that now has exactly its n blocks queued after it gets that speed as its junction cap
    /// (a stop at the end of the n-th block, from the lowest limits on the way). A block is
    /// its segments up to one that is not `continued` (a split kinematic path's pieces are one
    /// block; a canned cycle's or a pocket's moves are each a block of their own).
    fn limit_to_blocks(&mut self) {
        let Some(newest) = self.queue.back() else { return };
        if newest.segment.continued() {
            return;
        }
        let (mut blocks, mut len) = (0, 0.0);
        let mut lim: Option<Limits> = None;
        for k in (0..self.queue.len() - 1).rev() {
            let after = &self.queue[k + 1].segment;
            len += after.len;
            lim = Some(lim.map_or(after.limits, |l| l.min(after.limits)));
            if !after.continued() {
                blocks += 1;
            }
            if blocks > MAX_BLOCK_LIMIT {
                break;
            }
            let q = &mut self.queue[k];
            let n = q.segment.block_limit as usize;
            if n > 0 && blocks == n && !q.segment.continued() {
                if let Some(l) = lim {
                    q.junction = q.junction.min(reachable(0.0, len, l.v, &l));
                }
            }
        }
    }

    /// Every segment not yet executed, in order (the planner unchanged).
    pub fn segments(&self) -> impl Iterator<Item = &Segment> {
        self.queue.iter().map(|q| &q.segment)
    }

    /// Every segment not yet executed, in order, and the planner emptied (for a replan from
    /// rest after a feed hold).
    pub fn take_all(&mut self) -> Vec<Segment> {
        self.ready.clear();
        self.left = 0;
        self.first_release = 0;
        let out = self.queue.drain(..).map(|q| q.segment).collect();
        self.v_now = 0.0;
        out
    }

    /// The highest speed at which the machine may enter `path` and still keep to every
    /// junction speed and stop at its next exact stop (or its end): the backward pass over
    /// it, with the lowest limits of all its segments.
    pub fn entry_speed(&self, path: &[Segment]) -> f64 {
        let Some(lim) = path.iter().map(|s| s.limits).reduce(Limits::min) else {
            return 0.0;
        };
        let end = path.iter().position(|s| s.stop_after).map_or(path.len(), |k| k + 1);
        let mut v_next_start = 0.0;
        for k in (0..end).rev() {
            let junction = match path.get(k + 1) {
                Some(next) if k + 1 < end => junction_speed(&path[k], next, &self.speed_step, &self.accel_step),
                _ => 0.0,
            };
            let v_end = junction.min(v_next_start);
            v_next_start = reachable(v_end, path[k].len, path[k].limits.v, &lim);
        }
        v_next_start
    }

    /// The speed the next released run starts at.
    pub fn speed(&self) -> f64 {
        self.v_now
    }

    /// The machine moves on at speed `v` (with zero acceleration) into what is pushed next.
    pub fn continue_at(&mut self, v: f64) {
        self.v_now = v;
    }

    /// The next run whose speeds are final, if any; with `stop`, every queued segment is
    /// released (the machine stops at the end of the queue).
    pub fn pop(&mut self, stop: bool) -> Option<Planned> {
        if self.ready.is_empty() {
            let n = self.queue.len();
            // Planning passes over the whole queue, so they run once a batch more than the
            // look-ahead (and than the last planning left) is queued.
            if n == 0 || (!stop && n < self.lookahead.max(self.left) + self.batch()) {
                return None;
            }
            // A planning that would release nothing is skipped, as if it had run: a long run
            // (a CAM program's hundreds of short blocks) waits for its look-ahead over several
            // batches, and each planning passes over the whole queue.
            if !stop && n < self.first_release {
                self.left = n;
                return None;
            }
            self.plan(if stop { n } else { n - self.lookahead });
            self.left = n - self.ready.iter().map(|r| r.count).sum::<usize>();
        }
        let r = self.ready.pop_front()?;
        // Exactly as many as the run has (collected, a one-segment run would reserve four).
        let mut segments = Vec::with_capacity(r.count);
        segments.extend(self.queue.drain(..r.count).map(|q| q.segment));
        let profile = match r.profile {
            Some(p) => *p,
            None => Profile::plan(r.v_start, r.v_end, r.len, &r.limits),
        };
        Some(Planned { segments, profile })
    }

    /// Plan the queue and release the runs that end within its first `release` segments.
    fn plan(&mut self, release: usize) {
        let mut runs = self.runs(0..self.queue.len(), true);
        // Where nothing is released, the first run is the same at the next planning (its
        // segments, their junctions and the limits of the one after it are as queued) unless
        // the queue's end cut it: it is released once a look-ahead follows it.
        self.first_release = match runs.first() {
            Some(r) if r.end > release && r.end < self.queue.len() => r.end + self.lookahead,
            _ => 0,
        };
        // Backward: the machine must be able to stop at the end of the queue.
        pass(&mut runs, self.v_now, 0.0);
        let mut taken = 0;
        for r in runs.iter().take_while(|r| r.end <= release) {
            if !r.kinematic {
                self.release(r, taken, None);
                taken = r.end;
                continue;
            }
            // A kinematic run: planned against the axes' own limits, or as runs of similar path
            // limits between the same speeds — the first where it can be planned and is quick
            // enough against the second (`optimal::plan`: it can lose where its joins are
            // conservative).
            let mut parts = self.runs(taken..r.end, false);
            pass(&mut parts, self.v_now, r.v_end);
            // Each part's speed change starts and ends at zero acceleration, so a chain of short
            // parts brakes less in the same length than the run as one S-curve, which the
            // backward pass counted on: where the parts cannot slow down from the speed the run
            // starts at, the run goes as one profile within the lowest limits of its segments.
            // (Not where one profile would only be quicker: its acceleration across the small
            // corners between short blocks adds to the axes' jerk, which the parts' ends at zero
            // acceleration keep within the limits.)
            let whole = !feasible(&parts, self.v_now);
            let analytic = if whole {
                Profile::plan(self.v_now, r.v_end, r.len, &r.limits).duration()
            } else {
                chain_duration(&parts, self.v_now)
            };
            // A run of many segments (a long chain of short blocks, the look-ahead's queue)
            // keeps the analytic plan: planning it tick by tick costs more than it saves.
            let optimal = match &self.axes {
                Some(axes) if !r.cornered && r.end - taken <= OPTIMAL_SEGMENTS => {
                    self.optimal(taken, r, axes, analytic)
                }
                _ => None,
            };
            match optimal {
                Some(profile) => {
                    self.release(r, taken, Some(Box::new(profile)));
                }
                None if whole => self.release(r, taken, None),
                None => {
                    let mut from = taken;
                    for part in &parts {
                        self.release(part, from, None);
                        from = part.end;
                    }
                }
            }
            taken = r.end;
        }
    }

    /// Release run `r` (starting at queue index `from`) at the current speed.
    fn release(&mut self, r: &Run, from: usize, profile: Option<Box<Profile>>) {
        let (v_start, v_end, len, limits) = (self.v_now, r.v_end, r.len, r.limits);
        self.ready.push_back(Released { count: r.end - from, v_start, v_end, len, limits, profile });
        self.v_now = r.v_end;
    }

    /// The profile of kinematic run `r` (from queue index `from`) against the axes' limits,
    /// if it is quick enough against the analytic plan's `to_beat` (`optimal::plan`).
    fn optimal(&self, from: usize, r: &Run, axes: &AxisLimits, to_beat: f64) -> Option<Profile> {
        let segments: Vec<&Segment> = self.queue.range(from..r.end).map(|q| &q.segment).collect();
        let queued = self.queue.range(from..r.end - 1);
        let plan = |junctions: &[f64]| super::optimal::plan(&segments, junctions, (self.v_now, r.v_end), axes, to_beat);
        // Between a block's pieces nothing but the axes' own limits at every point: the queued
        // junction speed there is the lower of the two pieces' path limits, each bounded over
        // its whole stretch (it cost TCP swings up to a tenth of their time). Where the drives
        // cannot plan the run that way (a top speed or acceleration bound that falls faster
        // than they can follow), with the queued speeds, which keep them slower there.
        let open: Vec<f64> =
            queued.clone().map(|q| if q.segment.continued() { f64::INFINITY } else { q.junction }).collect();
        let junctions: Vec<f64> = queued.map(|q| q.junction).collect();
        plan(&open).or_else(|| if open == junctions { None } else { plan(&junctions) })
    }

    /// The corner speed at each junction of `path` (one fewer than its segments).
    pub fn corners(&self, path: &[&Segment]) -> Vec<f64> {
        path.windows(2).map(|w| corner_speed(w[0], w[1], &self.speed_step, &self.accel_step)).collect()
    }

    /// The queued segments `range` grouped into runs (at most `lookahead` segments each, so
    /// that a run is released while its look-ahead still follows it); with `merge_kinematic`,
    /// consecutive kinematic segments share a run unless a corner parts them.
    fn runs(&self, range: std::ops::Range<usize>, merge_kinematic: bool) -> Vec<Run> {
        // At most a run per segment: reserved at once, as growing it by doubling copies it
        // (a planning every batch makes this the planner's most frequent allocation).
        let mut runs: Vec<Run> = Vec::with_capacity(range.len());
        let mut open: Option<Run> = None;
        let last = range.end - 1;
        let first = range.start;
        for (k, q) in self.queue.range(range).enumerate().map(|(k, q)| (k + first, q)) {
            let lim = q.segment.limits;
            let run = match open.take() {
                Some(mut r) => {
                    r.len += q.segment.len;
                    r.limits = r.limits.min(lim);
                    r.kinematic &= q.segment.is_kinematic();
                    r
                }
                None => Run {
                    end: 0,
                    len: q.segment.len,
                    limits: lim,
                    kinematic: merge_kinematic && self.axes.is_some() && q.segment.is_kinematic(),
                    cornered: false,
                    cap: 0.0,
                    v_end: 0.0,
                },
            };
            let run = Run { end: k + 1, cap: q.junction, ..run };
            let next = self.queue.get(k + 1).filter(|_| k < last).map(|n| n.segment.limits);
            let count = runs.last().map_or(k + 1 - first, |last| k + 1 - last.end);
            let ends = match next {
                None => true,
                // Kinematic segments are planned at every point against the axes' limits: only a
                // sharp corner (to under half the speed) or a full run ends their run. Short
                // blocks under TCP meet at small corners everywhere (the rotary axes turn
                // linearly in each): ended there, every block was a run of its own, its speed
                // changes starting and ending at zero acceleration, and a program took longer
                // the shorter its blocks (`docs/motion.md`).
                Some(next) if run.kinematic && kinematic_pair(&q.segment, self.queue.get(k + 1)) => {
                    q.junction < 0.5 * run.limits.v.min(next.v) || count >= self.lookahead
                }
                Some(next) => {
                    // A corner that may have to slow the machine, limits too different to
                    // share (the run takes the lowest: `shares_part`), or a full run.
                    let kinematic = !merge_kinematic && kinematic_pair(&q.segment, self.queue.get(k + 1));
                    q.junction < run.limits.v.min(next.v)
                        || !shares_part(next, run.limits, kinematic)
                        || count >= self.lookahead
                }
            };
            if ends {
                runs.push(run);
            } else {
                // A kinematic run going on through a corner of its own runs no faster than it
                // anywhere, as far as its passes and its whole-run profile know.
                let mut run = run;
                run.cornered |= !q.smooth;
                run.limits.v = run.limits.v.min(q.junction);
                open = Some(run);
            }
        }
        runs
    }
}

/// The speeds at the ends of `runs`: backward from `v_end` (each within its junction cap and
/// able to brake to the next), then forward from `v_start`, no faster than acceleration allows.
fn pass(runs: &mut [Run], v_start: f64, v_end: f64) {
    let mut v_next_start = v_end;
    let n = runs.len();
    for (k, r) in runs.iter_mut().enumerate().rev() {
        r.v_end = if k + 1 == n { v_end } else { r.cap.min(v_next_start) };
        v_next_start = reachable(r.v_end, r.len, r.limits.v, &r.limits);
    }
    let mut v = v_start;
    for r in runs.iter_mut() {
        r.v_end = settle(v, r.v_end.min(reachable(v, r.len, r.limits.v, &r.limits)), r.len, &r.limits);
        v = r.v_end;
    }
}

/// An end speed at most `v_end` that a run of `len` can slow down to from `v_start`. Slowing
/// down is not monotonic in the target under a jerk limit: a change's time grows as the root
/// of its size, so braking from 16.7 mm/s to 4.3 takes 0.261 mm and to rest 0.241. So where the
/// backward pass let the machine enter a run faster than it can slow to the end speed the next
/// run asks for (it checked only that the queue could stop: 1 µm blocks at F1000 on mill3),
/// the run slows down further, to the highest speed below that it reaches in its length — at
/// worst to rest, which it can (the backward pass made sure of it).
fn settle(v_start: f64, v_end: f64, len: f64, lim: &Limits) -> f64 {
    let fits = |v: f64| super::profile::change(v_start, v, lim).1 <= len * (1.0 + 1e-9) + 1e-12;
    if v_end >= v_start || fits(v_end) || !fits(0.0) {
        return v_end;
    }
    let (mut lo, mut hi) = (0.0, v_end);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Whether each of `runs` can go from the speed the one before ends at (the first from
/// `v_start`) to its own end speed within its length.
fn feasible(runs: &[Run], v_start: f64) -> bool {
    let mut v = v_start;
    runs.iter().all(|r| {
        let fits = super::profile::change(v, r.v_end, &r.limits).1 <= r.len * (1.0 + 1e-9) + 1e-12;
        v = r.v_end;
        fits
    })
}

/// The time `runs` take from speed `v_start`, each on its own profile.
fn chain_duration(runs: &[Run], v_start: f64) -> f64 {
    let mut v = v_start;
    runs.iter()
        .map(|r| {
            let t = Profile::plan(v, r.v_end, r.len, &r.limits).duration();
            v = r.v_end;
            t
        })
        .sum()
}

/// The time a chain of smoothly joined stretches (`(length, limits)`, junction speeds only
/// their own limits) takes from rest to rest, planned as [`Planner`] plans them: runs of
/// pieces whose limits `shares_part`, a backward and a
/// forward pass. (`path` uses it to choose how to cut a kinematic path.)
pub(crate) fn chain_time(chain: &[(f64, Limits)]) -> f64 {
    let mut runs: Vec<(f64, Limits)> = Vec::new();
    for &(len, lim) in chain {
        match runs.last_mut() {
            Some((l, r)) if shares_part(lim, *r, true) => {
                *l += len;
                *r = r.min(lim);
            }
            _ => runs.push((len, lim)),
        }
    }
    if runs.iter().any(|(_, r)| !(r.v > 0.0 && r.a > 0.0 && r.j > 0.0)) {
        return f64::INFINITY;
    }
    // Backward from the stop, then forward from rest; a junction takes the lower limit. The
    // bisections of `reachable` are most of the cost, so they are skipped where their result
    // cannot matter: the first run's backward one (nothing comes before it), and a forward one
    // whose end speed is already no higher than where it starts and its limit (what `reachable`
    // returns is never below either).
    let mut ends = vec![0.0; runs.len()];
    let mut v_next_start = 0.0;
    for (k, (len, r)) in runs.iter().enumerate().rev() {
        let cap = runs.get(k + 1).map_or(0.0, |(_, next)| r.v.min(next.v));
        ends[k] = cap.min(v_next_start);
        if k > 0 {
            v_next_start = reachable(ends[k], *len, r.v, r);
        }
    }
    let (mut v_start, mut time) = (0.0f64, 0.0);
    for ((len, r), end) in runs.iter().zip(ends.iter_mut()) {
        if *end > v_start.min(r.v) {
            *end = end.min(reachable(v_start, *len, r.v, r));
        }
        time += Profile::plan(v_start, *end, *len, r).duration();
        v_start = *end;
    }
    time
}

fn kinematic_pair(a: &Segment, b: Option<&Queued>) -> bool {
    a.is_kinematic() && b.is_some_and(|b| b.segment.is_kinematic())
}

/// Whether a segment of limits `next` can join a run of limits `run` (taking the lower of
/// each): the same speed (a feed), acceleration and jerk within a factor of two. Kinematic
/// pieces' speed limits differ a little from block to block (the rotary axes turn at another
/// rate in each of a CAM program's short blocks): theirs may be within 10 %, else every block
/// was a part of its own, whose speed changes start and end at zero acceleration, and a wave
/// under G43.4 took 4.9 s in 0.025 mm blocks against 3.1 s in 0.2 mm ones.
fn shares_part(next: Limits, run: Limits, kinematic: bool) -> bool {
    let v_share = if kinematic { KINEMATIC_SPEED_SHARE } else { 1e-9 };
    (next.v - run.v).abs() <= v_share * run.v && within_twice(next.a, run.a) && within_twice(next.j, run.j)
}

/// How far kinematic pieces' speed limits may differ and share a part (`shares_part`).
const KINEMATIC_SPEED_SHARE: f64 = 0.1;

fn within_twice(x: f64, of: f64) -> bool {
    x >= 0.5 * of && x <= 2.0 * of
}

/// The highest speed through the junction of `a` into `b`: neither segment's speed, at most
/// `speed_step[i]` of sudden speed change on any axis (a corner; tangent junctions need no
/// slowing), and at most `accel_step[i]` of sudden acceleration change (where the curvature
/// changes: the acceleration toward an arc's centre is v² times its curvature vector).
fn junction_speed(a: &Segment, b: &Segment, speed_step: &Pos, accel_step: &Pos) -> f64 {
    a.limits.v.min(b.limits.v).min(corner_speed(a, b, speed_step, accel_step))
}

/// The highest speed through the junction of `a` into `b` that its corner and its change of
/// curvature allow (infinite where the path goes on smoothly, as between a block's pieces).
fn corner_speed(a: &Segment, b: &Segment, speed_step: &Pos, accel_step: &Pos) -> f64 {
    match (a.after_interpolation(), b.after_interpolation()) {
        // Without look-ahead the interpolation runs through corners at the feed: the filter
        // after interpolation rounds them.
        (true, true) => return f64::INFINITY,
        // Look-ahead switched on or off: the machine stops there, so the filter is at rest when
        // it starts or ends.
        (true, false) | (false, true) => return 0.0,
        (false, false) => {}
    }
    let mut v = f64::INFINITY;
    let (start_dir, end_dir) = (b.start_dir(), a.end_dir());
    // A polygon of short blocks: corners that turn an axis by `turn` every `shorter` of path
    // turn it as a circle of radius r = shorter/turn does, and junctions closer than the
    // period add their speed steps up. So the axis's acceleration toward that circle's centre,
    // v²/r, stays within its limit, and the jerk of that acceleration turning, v³/r², within
    // half of its limit (the other half for speed changes along the blocks) — FANUC's AI
    // contour control likewise slows down by the acceleration across small blocks. A curve's
    // chords are capped by the curve's own bending instead (`Segment::is_chord`) — but that
    // is the bending of the programmed axes, in acceleration only: under TCP the machine's
    // axes bend more than the tip does, so kinematic chords keep the jerk rule (a wave in
    // G05.1 Q3 on head-bc ran with X at 1.3 times its jerk without it).
    let chords = a.is_chord() && b.is_chord();
    let polygon = !chords;
    let kinematic = a.is_kinematic() && b.is_kinematic();
    let shorter = a.len.min(b.len);
    for i in 0..speed_step.len() {
        let turn = (start_dir[i] - end_dir[i]).abs();
        if turn > 1e-12 {
            v = v.min(speed_step[i] / turn);
            let (accel, jerk) = (speed_step[i] / super::JUNCTION_S, accel_step[i] / super::JUNCTION_S);
            let r = shorter / turn;
            if polygon {
                v = v.min((accel * r).sqrt());
            }
            if polygon || kinematic {
                v = v.min((0.5 * jerk * r * r).cbrt());
            }
        }
        let bend = (b.start_curvature()[i] - a.end_curvature()[i]).abs();
        if bend > 1e-12 {
            v = v.min((accel_step[i] / bend).sqrt());
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canon::Motion;
    use crate::machine::MotionOptions;
    use crate::motion::path::FeedContext;

    /// Legs of 300 steps of 0.1 mm, turning 90° between legs: runs of a full look-ahead, whose
    /// release waits for several batches.
    fn legs(count: usize, axes: &AxisLimits) -> Vec<Segment> {
        let ctx = FeedContext {
            feed_override: 1.0,
            rapid_override: 1.0,
            exact_stop: false,
            options: MotionOptions::default(),
        };
        let mut here: Pos = [0.0; 8];
        (0..count)
            .map(|k| {
                let mut to = here;
                to[(k / 300) % 2] += 0.1;
                let m = Motion::straight(false, to, to, 3000.0);
                let seg = Segment::new(&m, &here, &here, axes, ctx, None);
                here = to;
                seg
            })
            .collect()
    }

    /// Skipping the plannings that cannot release the first run releases the same runs, with
    /// the same profiles, at the same calls as planning once per batch.
    #[test]
    fn skipped_plannings_change_nothing() {
        let axes = AxisLimits { count: 5, v: [100.0; 8], a: [1000.0; 8], j: [20000.0; 8] };
        let new = || Planner::new(256, [5.0; 8], [500.0; 8]);
        let (mut skipping, mut planning) = (new(), new());
        let mut skipped = 0;
        for seg in legs(2000, &axes) {
            skipping.push(seg.clone());
            planning.push(seg);
            loop {
                // Planning at every batch, as before skipping.
                planning.first_release = 0;
                let (a, b) = (skipping.pop(false), planning.pop(false));
                assert_eq!(a, b);
                if skipping.queue.len() < skipping.first_release {
                    skipped += 1;
                }
                if a.is_none() {
                    break;
                }
            }
        }
        while let Some(a) = skipping.pop(true) {
            assert_eq!(Some(a), planning.pop(true));
        }
        assert_eq!(planning.pop(true), None);
        assert!(skipped > 0, "no planning skipped");
    }
}
