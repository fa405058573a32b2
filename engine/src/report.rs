//! The run report: what a program did on one machine, measured on the executed motion
//! (`docs/fleet.md` defines every figure). It watches a run as a [`crate::run::Observer`], so a
//! run without a report pays nothing; with one, the run samples every `period_s` (1 ms by
//! default) and the report reads each sample once.
//!
//! - travel: the sum of the sampled position changes per axis (mm or degrees, unwound);
//! - speeds: the largest sampled speed per axis, and the mean over the time the axis moves
//!   (travel ÷ time with a position change), units per minute;
//! - near singular: the time the tool direction is within the machine's own singular angle of
//!   the singular posture (`near_singular_deg`);
//! - limits: the lowest and highest position reached and the closest approach (margin) to the
//!   stored stroke or the rotary movement range, whichever is tighter;
//! - unwinds: executed motions (a split kinematic path's pieces as one) in which a rotary axis
//!   turns 180° or more against the direction it last moved in;
//! - tip deviation: the distance, in the table frame, from the tool tip the axes put there to the
//!   programmed tip path: a tool centre point or tilted-plane move's own tip line or circle (under
//!   cutting point control the cutting point's path plus the tool's vector); on a
//!   move whose rotary axes turn without one, the straight line between the tip's start and end
//!   (the linearisation error); a move whose rotary axes stand still carries the tip rigidly
//!   along its programmed path and deviates by nothing.

use crate::canon::Pos;
use crate::interp::Interpreter;
use crate::kin::Vec3;
use crate::machine::AxisKind;
use crate::motion::Segment;
use crate::run::{run_observed, Observer, RunOptions, RunResult, Sample};
use serde::Serialize;

/// The words of the report's `&'static str` fields, for the service's document.
#[cfg(feature = "schema")]
mod schema {
    #![allow(dead_code)]

    /// How the run ended.
    #[derive(utoipa::ToSchema)]
    #[serde(rename_all = "lowercase")]
    pub enum ReportStatus {
        Completed,
        Alarm,
    }

    /// Which end of its limits an axis came closest to.
    #[derive(utoipa::ToSchema)]
    #[serde(rename_all = "lowercase")]
    pub enum MarginSide {
        Negative,
        Positive,
    }
}

/// The singular angle used when the machine sets none (degrees).
pub const DEFAULT_NEAR_SINGULAR_DEG: f64 = 1.0;

/// A rotary move of at least this many degrees against the last direction is an unwind.
pub const UNWIND_DEG: f64 = 180.0;

/// The report of one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Report {
    /// `completed` or `alarm`.
    #[cfg_attr(feature = "schema", schema(value_type = schema::ReportStatus))]
    pub status: &'static str,
    /// The first alarm (code, message, line, n) when the run ended in one.
    pub alarm: Option<crate::Alarm>,
    pub cycle_time_s: f64,
    /// Per axis, in the machine's axis order.
    pub axes: Vec<AxisReport>,
    /// The angle to the singular posture taken as near (degrees); `None` on machines without one.
    pub near_singular_deg: Option<f64>,
    /// Seconds spent within that angle.
    pub near_singular_s: f64,
    /// The smallest angle to the singular posture seen, degrees.
    pub min_singular_angle_deg: Option<f64>,
    pub tip_deviation: TipDeviation,
    /// The sampling period the report was measured with, seconds.
    pub period_s: f64,
    /// Each axis's speed over the run, for plots.
    pub speeds: SpeedProfile,
}

/// Axis speeds over time: the mean speed of each axis in consecutive intervals of `period_s`
/// (at most [`SpeedProfile::MAX_POINTS`] of them: the interval doubles as the run grows).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct SpeedProfile {
    /// The interval, seconds.
    pub period_s: f64,
    /// Per axis, in axis order.
    pub axes: Vec<AxisSpeeds>,
}

/// One axis's speed in each interval, mm/min or °/min.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct AxisSpeeds {
    #[cfg_attr(feature = "schema", schema(min_length = 1, max_length = 1))]
    pub axis: char,
    pub speeds: Vec<f64>,
}

impl SpeedProfile {
    pub const MAX_POINTS: usize = 1000;
    /// The first interval (whole sampling periods; it doubles while the run is longer than
    /// `MAX_POINTS` of them).
    pub const FIRST_PERIOD_S: f64 = 0.05;
}

/// Travel per axis per interval, as the run goes. Intervals hold whole sampling periods
/// (counted, so that floating-point times never put a sample in the wrong interval).
struct SpeedAcc {
    sample_s: f64,
    /// Sampling periods per interval.
    per_interval: u64,
    /// Per interval, per axis: the travel in it.
    travel: Vec<Vec<f64>>,
}

impl SpeedAcc {
    fn new(sample_s: f64) -> SpeedAcc {
        let per_interval = (SpeedProfile::FIRST_PERIOD_S / sample_s).round().max(1.0) as u64;
        SpeedAcc { sample_s, per_interval, travel: Vec::new() }
    }

    /// The travel of the sampling period that starts at `t`.
    fn add(&mut self, t: f64, travel: &[f64]) {
        let period = (t / self.sample_s).round().max(0.0) as u64;
        let mut k = (period / self.per_interval) as usize;
        while k >= SpeedProfile::MAX_POINTS {
            // Merge pairs: the interval doubles.
            let merged = self
                .travel
                .chunks(2)
                .map(|pair| {
                    pair.iter().fold(vec![0.0; travel.len()], |acc, b| acc.iter().zip(b).map(|(x, y)| x + y).collect())
                })
                .collect();
            self.travel = merged;
            self.per_interval *= 2;
            k = (period / self.per_interval) as usize;
        }
        if self.travel.len() <= k {
            self.travel.resize(k + 1, vec![0.0; travel.len()]);
        }
        for (acc, d) in self.travel[k].iter_mut().zip(travel) {
            *acc += d;
        }
    }

    fn profile(&self, names: &[char]) -> SpeedProfile {
        let period_s = self.per_interval as f64 * self.sample_s;
        let per_min = 60.0 / period_s;
        let axes = names
            .iter()
            .enumerate()
            .map(|(i, name)| AxisSpeeds { axis: *name, speeds: self.travel.iter().map(|b| b[i] * per_min).collect() })
            .collect();
        SpeedProfile { period_s, axes }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct AxisReport {
    #[cfg_attr(feature = "schema", schema(min_length = 1, max_length = 1))]
    pub name: char,
    pub rotary: bool,
    /// Sum of the position changes, mm or degrees.
    pub travel: f64,
    /// Highest speed, mm/min or deg/min.
    pub max_speed: f64,
    /// Mean speed while the axis moves, mm/min or deg/min (0 when it never moves).
    pub mean_speed: f64,
    /// Lowest and highest position reached (machine coordinates, unwound).
    pub min: f64,
    pub max: f64,
    /// The tighter of the stored stroke and the rotary movement range; `None`: no limit.
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub limits: Option<[f64; 2]>,
    /// Closest approach to the limits (negative: beyond), and on which side.
    pub margin: Option<f64>,
    #[cfg_attr(feature = "schema", schema(value_type = Option<schema::MarginSide>))]
    pub margin_side: Option<&'static str>,
    /// Rotary unwinds (see the module docs).
    pub unwinds: u32,
}

/// The largest tip deviation and where it happened.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct TipDeviation {
    /// mm.
    pub max: f64,
    pub t: Option<f64>,
    pub line: Option<u32>,
    pub n: Option<u32>,
    /// The tool tip there, table frame.
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub tip: Option<[f64; 3]>,
}

/// Run the program to its end and measure it; the `RunResult` is the one `run::run` gives.
pub fn run_with_report(interp: &mut Interpreter, opts: &RunOptions) -> (RunResult, Report) {
    let mut rec = Recorder::new(interp, opts.period_s);
    let result = run_observed(interp, opts, |_| {}, &mut rec);
    let report = rec.finish(&result);
    (result, report)
}

/// The observer that builds a [`Report`].
pub struct Recorder {
    /// The machine, whose mechanism of each segment's chain (Syntec G10 L5000) reads its tip.
    machine: std::sync::Arc<crate::machine::Machine>,
    /// The mechanism chain of the segment last sampled (Syntec G10 L5000).
    chain: crate::machine::Chain,
    /// The line of the axis whose posture is singular (`Kinematics::singularity`) in that
    /// chain, fixed in the table frame: the angle to it comes from each sample's tool direction.
    singular_axis: Option<Vec3>,
    axes: Vec<AxisAcc>,
    /// The angle taken as near the singular posture (while the chain has one).
    near_deg: Option<f64>,
    near: f64,
    near_s: f64,
    min_singular: Option<f64>,
    period_s: f64,
    /// Where the motion being executed started, while its pieces run (a kinematic path the
    /// planner split, `Segment::continued`): an unwind is the whole motion's turn.
    motion_from: Option<Pos>,
    last: Option<(f64, Pos)>,
    /// Where the last executed segment ended: the motion after the last sample counts too.
    last_end: Option<Pos>,
    deviation: TipDeviation,
    /// Chord of the segment being sampled: (segment `from`, `to`) and its tip end points.
    chord: Option<(Pos, Pos, Vec3, Vec3)>,
    speeds: SpeedAcc,
}

struct AxisAcc {
    name: char,
    rotary: bool,
    travel: f64,
    moving_s: f64,
    max_speed: f64,
    min: f64,
    max: f64,
    limits: Option<[f64; 2]>,
    unwinds: u32,
    /// Sign of the last movement (0: none yet).
    direction: f64,
}

impl Recorder {
    /// A recorder for a run of `interp` (its machine and its compiled mechanism).
    pub fn new(interp: &Interpreter, period_s: f64) -> Recorder {
        let machine = &interp.config().machine;
        let kin = interp.kinematics().cloned();
        let axes = machine
            .axes
            .iter()
            .map(|a| {
                let range = machine.rotary.iter().find(|l| l.axis == a.name).and_then(|l| l.range);
                let limits = match (a.stroke, range) {
                    (Some(s), Some(r)) => Some([s[0].max(r[0]), s[1].min(r[1])]),
                    (s, r) => s.or(r),
                };
                AxisAcc {
                    name: a.name,
                    rotary: a.kind == AxisKind::Rotary,
                    travel: 0.0,
                    moving_s: 0.0,
                    max_speed: 0.0,
                    min: f64::INFINITY,
                    max: f64::NEG_INFINITY,
                    limits,
                    unwinds: 0,
                    direction: 0.0,
                }
            })
            .collect();
        let singular_axis = singular_axis(kin.as_deref());
        let f = &machine.five_axis;
        // The machine's own singular angles: No.19738 (type 2 end-point change) first, then
        // No.11204 (G54.4); a machine with neither uses the default.
        let near = [f.singular_angle, f.singular_tolerance_deg].into_iter().find(|a| *a > 0.0);
        let near = near.unwrap_or(DEFAULT_NEAR_SINGULAR_DEG);
        Recorder {
            machine: machine.clone(),
            chain: machine.chain(),
            axes,
            near_deg: singular_axis.map(|_| near),
            near,
            singular_axis,
            near_s: 0.0,
            min_singular: None,
            period_s,
            motion_from: None,
            last: None,
            last_end: None,
            deviation: TipDeviation { max: 0.0, t: None, line: None, n: None, tip: None },
            chord: None,
            speeds: SpeedAcc::new(period_s),
        }
    }

    /// A position reached, as the machine shows it: a rollover axis modulo 360 (its unwound
    /// angle, −10 or 620, is no position the machine shows; `travel` stays unwound).
    fn position(&mut self, pos: &Pos) {
        for (a, p) in self.axes.iter_mut().zip(&self.machine.shown(pos)) {
            a.min = a.min.min(*p);
            a.max = a.max.max(*p);
        }
    }

    /// The report, with the run's status and cycle time.
    pub fn finish(mut self, result: &RunResult) -> Report {
        // The way from the last sample to where the machine stopped.
        if let (Some((t0, p0)), Some(end)) = (self.last, self.last_end) {
            let dt = (result.cycle_time_s - t0).max(0.0);
            for (i, a) in self.axes.iter_mut().enumerate() {
                let d = (end[i] - p0[i]).abs();
                if d > 0.0 {
                    a.travel += d;
                    a.moving_s += dt;
                }
            }
        }
        let axes = self
            .axes
            .iter()
            .map(|a| {
                let seen = a.min <= a.max;
                let (min, max) = if seen { (a.min, a.max) } else { (0.0, 0.0) };
                let (margin, side) = match a.limits {
                    Some([lo, hi]) if seen => {
                        if min - lo <= hi - max {
                            (Some(min - lo), Some("negative"))
                        } else {
                            (Some(hi - max), Some("positive"))
                        }
                    }
                    _ => (None, None),
                };
                AxisReport {
                    name: a.name,
                    rotary: a.rotary,
                    travel: a.travel,
                    max_speed: a.max_speed,
                    mean_speed: if a.moving_s > 0.0 { a.travel / a.moving_s * 60.0 } else { 0.0 },
                    min,
                    max,
                    limits: a.limits,
                    margin,
                    margin_side: side,
                    unwinds: a.unwinds,
                }
            })
            .collect();
        Report {
            status: if result.completed() { "completed" } else { "alarm" },
            alarm: result.alarms.first().cloned(),
            cycle_time_s: result.cycle_time_s,
            axes,
            near_singular_deg: self.near_deg,
            near_singular_s: self.near_s,
            min_singular_angle_deg: self.min_singular,
            tip_deviation: self.deviation,
            period_s: self.period_s,
            speeds: self.speeds.profile(&self.axes.iter().map(|a| a.name).collect::<Vec<_>>()),
        }
    }

    /// From a segment of another mechanism chain on, the singular axis is that chain's.
    fn follow_chain(&mut self, chain: crate::machine::Chain) {
        if chain != self.chain {
            self.chain = chain;
            self.singular_axis = singular_axis(self.machine.kinematics_of(chain).map(|k| &**k));
            self.near_deg = self.near_deg.or(self.singular_axis.map(|_| self.near));
        }
    }

    /// The angle between the sample's tool direction and the singular axis, degrees (as
    /// `Kinematics::singularity` computes it).
    fn singular_angle(&self, sample: &Sample) -> Option<f64> {
        let axis = self.singular_axis?;
        let tool = Vec3::new(sample.tool[0], sample.tool[1], sample.tool[2]);
        Some(tool.dot(&axis).abs().min(1.0).acos().to_degrees())
    }

    /// The tip deviation at a sample on `seg`, `s` along it, with the axes at `machine`.
    fn deviation(&mut self, machine: &Pos, seg: &Segment, s: f64) -> Option<(f64, Vec3)> {
        let kin = self.machine.kinematics_of(seg.tip_basis.chain)?.clone();
        if let Some((programmed, length)) = seg.programmed_tip(s) {
            let tip = kin.forward(machine, length).tip;
            return Some(((tip - programmed).norm(), tip));
        }
        let (from, to) = (seg.from(), seg.to());
        let rotary_moves = self.axes.iter().enumerate().any(|(i, a)| a.rotary && from[i] != to[i]);
        if !rotary_moves {
            return None;
        }
        let length = seg.tool_length;
        let chord = match self.chord {
            Some((f, t, a, b)) if f == from && t == to => (a, b),
            _ => {
                let (a, b) = (kin.forward(&from, length).tip, kin.forward(&to, length).tip);
                self.chord = Some((from, to, a, b));
                (a, b)
            }
        };
        let tip = kin.forward(machine, length).tip;
        Some((distance_to_segment(tip, chord.0, chord.1), tip))
    }
}

/// The line of the axis whose posture is singular, at all angles zero.
fn singular_axis(kin: Option<&crate::kin::Kinematics>) -> Option<Vec3> {
    let k = kin?;
    let axis = k.singularity(&[0.0; crate::machine::MAX_AXES])?.axis;
    k.joints().iter().find(|j| j.name == axis).map(|j| j.direction)
}

/// Distance from `p` to the line segment from `a` to `b`.
fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let u = if len2 > 0.0 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + ab * u)).norm()
}

impl Observer for Recorder {
    fn sample(&mut self, sample: &Sample, machine: &Pos, on: Option<(&Segment, f64, u64)>) {
        if let Some((seg, ..)) = on {
            self.follow_chain(seg.tip_basis.chain);
        }
        if let Some((t0, p0)) = self.last {
            let dt = sample.t - t0;
            if dt > 0.0 {
                let mut moved = [0.0; crate::machine::MAX_AXES];
                for (i, a) in self.axes.iter_mut().enumerate() {
                    let d = (machine[i] - p0[i]).abs();
                    if d > 0.0 {
                        a.travel += d;
                        a.moving_s += dt;
                        a.max_speed = a.max_speed.max(d / dt * 60.0);
                        moved[i] = d;
                    }
                }
                self.speeds.add(t0, &moved[..self.axes.len()]);
            }
            if let (Some(angle), Some(near)) = (self.singular_angle(sample), self.near_deg) {
                self.min_singular = Some(self.min_singular.map_or(angle, |m: f64| m.min(angle)));
                if angle <= near {
                    self.near_s += dt;
                }
            }
        } else {
            self.min_singular = self.singular_angle(sample);
        }
        self.last = Some((sample.t, *machine));
        self.position(machine);
        if let Some((seg, s, _)) = on {
            if let Some((d, tip)) = self.deviation(machine, seg, s) {
                if d > self.deviation.max {
                    self.deviation = TipDeviation {
                        max: d,
                        t: Some(sample.t),
                        line: Some(sample.line),
                        n: sample.n,
                        tip: Some(tip.into()),
                    };
                }
            }
        }
    }

    fn executed(&mut self, segment: &Segment) {
        let (start, end) = (segment.from(), segment.to());
        self.position(&start);
        self.position(&end);
        self.last_end = Some(end);
        let from = *self.motion_from.get_or_insert(start);
        if segment.continued() {
            return;
        }
        self.motion_from = None;
        for (i, a) in self.axes.iter_mut().enumerate() {
            let d = end[i] - from[i];
            if a.rotary && d != 0.0 {
                if a.direction != 0.0 && d.abs() >= UNWIND_DEG && d.signum() != a.direction {
                    a.unwinds += 1;
                }
                a.direction = d.signum();
            }
        }
    }
}
