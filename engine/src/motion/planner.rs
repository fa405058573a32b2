//! Look-ahead: the speed at every junction between segments, so that the machine can always
//! stop by the end of what it has read, never exceeds a segment's limits, and slows down at
//! corners only as much as each axis's allowed speed step requires.
//!
//! Segments are queued as the interpreter produces them. A segment is released only when at
//! least [`Planner::lookahead`] segments follow it (or the queue ends in a stop: a non-motion
//! command, an exact stop, the program end): its end speed is then final, because the speeds
//! are planned as if the machine had to stop at the end of the queue. Planning runs once per
//! `lookahead` released segments over the whole queue (a backward pass from the stop, then a
//! forward pass from the current speed), so it costs two passes per segment.

use super::path::Segment;
use super::profile::{reachable, Profile};
use crate::canon::Pos;
use std::collections::VecDeque;

/// A segment with its planned profile, ready to execute.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    pub segment: Segment,
    pub profile: Profile,
}

struct Queued {
    segment: Segment,
    /// Highest speed at the end of this segment (the junction with the next one).
    junction: f64,
    /// Planned speed at the end.
    v_end: f64,
}

pub struct Planner {
    queue: VecDeque<Queued>,
    /// Segments at the head of the queue whose end speed is final.
    settled: usize,
    /// Speed at the end of the last released segment.
    v_now: f64,
    pub lookahead: usize,
    /// Highest speed step each axis may take at a corner, units/s (FANUC No.1783).
    corner_step: Pos,
}

impl Planner {
    pub fn new(lookahead: usize, corner_step: Pos) -> Planner {
        Planner { queue: VecDeque::new(), settled: 0, v_now: 0.0, lookahead: lookahead.max(1), corner_step }
    }

    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// Queue a segment (zero-length segments are dropped: they take no time).
    pub fn push(&mut self, segment: Segment) {
        if segment.len <= 0.0 {
            return;
        }
        if let Some(last) = self.queue.back_mut() {
            last.junction = if last.segment.stop_after || segment.rapid {
                0.0
            } else {
                corner_speed(&last.segment, &segment, &self.corner_step)
            };
        }
        self.queue.push_back(Queued { segment, junction: 0.0, v_end: 0.0 });
    }

    /// The next segment whose speeds are final, if any; with `stop`, every queued segment is
    /// released (the machine stops at the end of the queue).
    pub fn pop(&mut self, stop: bool) -> Option<Planned> {
        if self.settled == 0 {
            let n = self.queue.len();
            // Planning passes over the whole queue, so they run once `lookahead` segments can
            // be released: two passes per segment whatever the look-ahead.
            if n == 0 || (!stop && n < 2 * self.lookahead) {
                return None;
            }
            self.plan();
            self.settled = if stop { n } else { n - self.lookahead };
        }
        let q = self.queue.pop_front()?;
        self.settled -= 1;
        let profile = Profile::plan(self.v_now, q.v_end, q.segment.len, &q.segment.limits);
        self.v_now = q.v_end;
        Some(Planned { segment: q.segment, profile })
    }

    fn plan(&mut self) {
        // Backward: the machine must be able to stop at the end of the queue.
        let mut v_next_start = 0.0;
        for q in self.queue.iter_mut().rev() {
            q.v_end = q.junction.min(v_next_start);
            v_next_start = reachable(q.v_end, q.segment.len, q.segment.limits.v, &q.segment.limits);
        }
        // Forward: from the current speed, no faster than acceleration allows.
        let mut v_start = self.v_now;
        for q in self.queue.iter_mut() {
            q.v_end = q.v_end.min(reachable(v_start, q.segment.len, q.segment.limits.v, &q.segment.limits));
            v_start = q.v_end;
        }
    }
}

/// The highest speed through the junction of `a` into `b`: neither segment's speed, and at
/// most `step[i]` of sudden speed change on any axis (tangent junctions need no slowing).
fn corner_speed(a: &Segment, b: &Segment, step: &Pos) -> f64 {
    let mut v = a.limits.v.min(b.limits.v);
    for ((step, from), to) in step.iter().zip(&a.end_dir).zip(&b.start_dir) {
        let jump = (to - from).abs();
        if jump > 1e-12 {
            v = v.min(step / jump);
        }
    }
    v
}
