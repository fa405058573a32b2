//! Motion: canonical motions become timed axis motion. `executor` is the one place where that
//! happens (queue, plan, execute, sample); `path` gives each motion its geometry and the limits
//! its axes impose, `planner` looks ahead and fixes the speed at every junction, `profile` turns
//! a segment into a jerk-limited speed profile that can be sampled at any time.
//! Everything is in seconds and machine units (mm, deg).

pub mod after;
pub mod contact;
pub mod executor;
mod optimal;
pub mod path;
pub mod planner;
pub mod profile;

pub use executor::{Braking, Endpoint, Executor, Finished, Sample};
pub use path::{AxisLimits, FeedContext, Segment};
pub use planner::{Cursor, Planned, Planner, Point};
pub use profile::{Limits, PathState, Profile};

use crate::alarm::AlarmId;
use crate::canon::Pos;
use crate::machine::{Machine, MachineConfig, MAX_AXES};

/// Segments of look-ahead (the issue asks for at least 200).
pub const LOOKAHEAD: usize = 256;

/// The time over which a junction's sudden changes are allowed (the interpolation period).
pub const JUNCTION_S: f64 = 0.001;

/// What each axis may change at once at a junction (the role of FANUC No.1783, allowable speed
/// difference for corner deceleration): its speed by what its acceleration gives in
/// [`JUNCTION_S`], and its acceleration (a line meeting an arc, arcs of other radii) by what its
/// jerk gives in it.
pub fn junction_steps(m: &MachineConfig) -> (Pos, Pos) {
    let (mut speed, mut accel) = ([0.0; MAX_AXES], [0.0; MAX_AXES]);
    for ((v, a), axis) in speed.iter_mut().zip(accel.iter_mut()).zip(&m.axes) {
        *v = axis.max_accel() * JUNCTION_S;
        *a = axis.max_jerk() * JUNCTION_S;
    }
    (speed, accel)
}

/// The planner for a machine, with [`LOOKAHEAD`] and its [`junction_steps`].
pub fn planner_for(m: &Machine) -> Planner {
    let (speed, accel) = junction_steps(m);
    Planner::new(LOOKAHEAD, speed, accel).with_axes(m.limits().clone())
}

/// The first stored stroke limit the segment would cross (end point, and the quadrant points
/// of an arc, points along a kinematic path; a straight move in axis space stays inside a box
/// when its ends do).
pub fn stroke_check(seg: &Segment, m: &MachineConfig) -> Result<(), AlarmId> {
    stroke_check_shifted(seg, m, &[0.0; MAX_AXES])
}

/// [`stroke_check`] of the segment moved by `shift` (a manual handle interruption's, added to
/// every planned point on the way to the axes).
pub fn stroke_check_shifted(seg: &Segment, m: &MachineConfig, shift: &Pos) -> Result<(), AlarmId> {
    let shifted = |p: Pos| -> Pos { std::array::from_fn(|i| p[i] + shift[i]) };
    let points = std::iter::once(seg.to()).chain(seg.arc_extremes()).chain(follow_peaks(seg, m, shift));
    check_points(points.map(shifted), m)
}

/// Without the stroke limit check before movement (G54.4, S000 III.2 "Stroke limit check
/// before movement": not available in that mode): the stored stroke limit stops the machine
/// where an axis reaches it. `seg` (moved by `shift`) up to there, ending at rest, and the
/// alarm it gives (`precheck: false`); `None` when no axis leaves its stroke on the way, or the
/// crossing is not found on the segment (an axis-independent rapid, whose distance is time,
/// or a bulge between the search's points): the caller keeps the check before movement then.
pub fn stroke_stop(seg: &Segment, m: &MachineConfig, shift: &Pos) -> Option<(Segment, AlarmId)> {
    const STEPS: usize = 512;
    if seg.is_independent() {
        return None;
    }
    let outside = |s: f64| {
        let p = seg.at(s).0;
        check_points(std::iter::once(std::array::from_fn(|i| p[i] + shift[i])), m).err()
    };
    let len = seg.len;
    let k = (0..=STEPS).find(|&k| outside(len * k as f64 / STEPS as f64).is_some())?;
    let (mut inside, mut out) = (len * k.saturating_sub(1) as f64 / STEPS as f64, len * k as f64 / STEPS as f64);
    if k == 0 {
        inside = 0.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (inside + out);
        if outside(mid).is_some() {
            out = mid;
        } else {
            inside = mid;
        }
    }
    let Some(AlarmId::OverTravel { axis, positive, .. }) = outside(out) else { return None };
    let head = seg.head(if k == 0 { 0.0 } else { inside });
    stroke_check_shifted(&head, m, shift).ok()?;
    Some((head, AlarmId::OverTravel { axis, positive, precheck: false }))
}

/// The points of a kinematic path to check: 17 along it, and where an axis comes within reach
/// of a limit, its peak between them found by search (random machines went 0.0014° past a
/// limit between two of the 17). "Within reach": less than the largest second difference of
/// its samples away — an axis cannot bulge by more than an eighth of it between two of them.
fn follow_peaks(seg: &Segment, m: &MachineConfig, shift: &Pos) -> Vec<Pos> {
    let samples = seg.follow_samples();
    let mut points: Vec<Pos> = samples.iter().map(|&(_, p)| p).collect();
    let n = samples.len();
    for (i, axis) in m.axes.iter().enumerate() {
        let Some([lo, hi]) = axis.stroke else { continue };
        if n < 3 {
            break;
        }
        let v = |k: usize| samples[k].1[i] + shift[i];
        let reach = (1..n - 1).map(|k| (v(k + 1) - 2.0 * v(k) + v(k - 1)).abs()).fold(0.0, f64::max);
        for (sign, limit) in [(1.0, hi), (-1.0, lo)] {
            let k = (0..n).max_by(|&a, &b| (sign * v(a)).total_cmp(&(sign * v(b)))).unwrap_or(0);
            if sign * (limit - v(k)) < reach {
                let (from, to) = (samples[k.saturating_sub(1)].0, samples[(k + 1).min(n - 1)].0);
                points.push(seg.peak(i, sign, from, to));
            }
        }
    }
    points
}

fn check_points(points: impl Iterator<Item = Pos>, m: &MachineConfig) -> Result<(), AlarmId> {
    for p in points {
        for (i, axis) in m.axes.iter().enumerate() {
            let Some([lo, hi]) = axis.stroke else { continue };
            // A hair of rounding at the limit itself is not an over-travel.
            let tol = 1e-9 * (1.0 + hi.abs().max(lo.abs()));
            if p[i] > hi + tol {
                return Err(AlarmId::OverTravel { axis: axis.name, positive: true, precheck: true });
            }
            if p[i] < lo - tol {
                return Err(AlarmId::OverTravel { axis: axis.name, positive: false, precheck: true });
            }
        }
    }
    Ok(())
}
